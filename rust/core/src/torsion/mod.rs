//! The shaft as a torsional chain (docs/theory.md, "Torsional merit of a firing order"): node
//! inertias J_i (kg·m²) joined by section stiffnesses k_i (N·m/rad), section i between nodes
//! i and i + 1, free at both ends. Undamped, its small twists obey J θ̈ + K θ = 0 with
//! J = diag(J_0 … J_{n−1}) and the tridiagonal K (K_ii = k_{i−1} + k_i, K_{i,i+1} = −k_i).
//!
//! What this room holds: the validated [`Chain`] and its natural modes ([`Chain::modes`],
//! in `modes`: every ω² to a few units in its last digit by Holzer's recurrence and a count
//! of its negative pivots, each shape by the same recurrence from both ends).
//!
//! What it will hold (the next issue, "A torsional vibration calculation"): the damped chain
//! (section, node and modal damping, viscous dampers as extra free rings) and its forced
//! response, order by order — (K − ν²Ω²J + iνΩC) Θ_ν = T_ν at each speed, the cylinders'
//! torque orders at their nodes — synthesised in time with the orders' phases into each
//! section's vibratory torque; and the exact periodic response of the chain, each cylinder's
//! own J(θ), ½J′(θ)θ̇², gas and gravity torque at its node, through the core's periodic
//! solver pattern (status, message, nfev) as `motion` has it.

mod modes;

#[cfg(test)]
mod tests;

pub use modes::Modes;

use crate::error::{check, check_length, MechanismError, Result};

/// A free–free torsional chain: n ≥ 2 node inertias J_i > 0 (kg·m²) and the n − 1 section
/// stiffnesses k_i > 0 (N·m/rad) between them, checked on construction.
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    inertia: Vec<f64>,
    stiffness: Vec<f64>,
}

impl Chain {
    /// The chain of `inertia` (J_i, kg·m², at least two nodes) and `stiffness` (k_i,
    /// N·m/rad, one fewer: section i joins nodes i and i + 1).
    ///
    /// Errors: fewer than two nodes or a J_i that is not finite and > 0 (naming
    /// `inertia`); a `stiffness` of another length, or a k_i that is not finite and > 0
    /// (naming `stiffness`).
    pub fn new(inertia: &[f64], stiffness: &[f64]) -> Result<Self> {
        if inertia.len() < 2 {
            return Err(MechanismError::InvalidChoice {
                parameter: "inertia",
                value: format!("{} nodes", inertia.len()),
                allowed: "at least 2 nodes",
            });
        }
        for &value in inertia {
            check("inertia", value, "inertia > 0 (kg·m², finite)", |j| {
                j > 0.0
            })?;
        }
        check_length("stiffness", inertia.len() - 1, stiffness.len())?;
        for &value in stiffness {
            check(
                "stiffness",
                value,
                "stiffness > 0 (N·m/rad, finite)",
                |k| k > 0.0,
            )?;
        }
        Ok(Self {
            inertia: inertia.to_vec(),
            stiffness: stiffness.to_vec(),
        })
    }

    /// The node inertias J_i (kg·m²).
    pub fn inertia(&self) -> &[f64] {
        &self.inertia
    }

    /// The section stiffnesses k_i (N·m/rad).
    pub fn stiffness(&self) -> &[f64] {
        &self.stiffness
    }

    /// The number of nodes n (the chain has n − 1 elastic modes).
    pub fn nodes(&self) -> usize {
        self.inertia.len()
    }
}
