//! The square-law load in closed form (docs/theory.md, "Steady running"): under a load
//! c·ω² with M(φ) the gas torque plus a constant drive, dE/dφ = M − U′ − (2c/J)E is linear
//! in E, so
//!
//!   E(φ) = e^{−A(φ)} [E₀ + ∫₀^φ e^{A}(M − U′) dφ],  A(φ) = ∫₀^φ 2c/J dφ,
//!   E₀ = ∫₀^Φ e^{A}(M − U′) dφ / (e^{A(Φ)} − 1)
//!
//! (docs/theory.md, "Three ways to the periodic solution"). Both running integrals are
//! taken on the cycle's panels, each panel's interpolant integrated exactly, so E is known
//! everywhere; the mean speed is a result.

use crate::error::{MechanismError, Result};

use super::cycle::Cycle;
use super::extrema::{grading, local_minima, refine_extrema};
use super::quadrature::{Antiderivative, Panels};
use super::solution::{message, Curves, Periodic, PeriodicSolver, Solution};

/// The closed form fails (e^{A(Φ)} overflows) beyond this many e-folds per cycle.
const MOST_E_FOLDS: f64 = 700.0;

/// The square-law load c·ω² beside a constant drive on a machine's cycle: a
/// [`PeriodicSolver`], the closed form set up for each shaft inertia asked for.
pub(crate) struct SquareLaw<'c> {
    cycle: &'c Cycle,
    coefficient: f64,
    drive: f64,
}

impl<'c> SquareLaw<'c> {
    /// The load c = `coefficient` (N·m·s²/rad²) and the constant `drive` (N·m) on `cycle`.
    pub fn new(cycle: &'c Cycle, coefficient: f64, drive: f64) -> Self {
        Self {
            cycle,
            coefficient,
            drive,
        }
    }
}

impl PeriodicSolver for SquareLaw<'_> {
    /// The closed form with I_w = `shaft_inertia` (the cycle's tables kept: J − I_w does
    /// not depend on it). Errors: more than 700 e-folds of E damped per cycle, naming `load`.
    fn solve(&self, shaft_inertia: f64, ratio: f64, phi: Option<&[f64]>) -> Result<Solution> {
        if shaft_inertia == self.cycle.inertia {
            return ClosedForm::new(self.cycle, self.coefficient, self.drive)?.solve(ratio, phi);
        }
        let mut trial = self.cycle.clone();
        trial.inertia = shaft_inertia;
        ClosedForm::new(&trial, self.coefficient, self.drive)?.solve(ratio, phi)
    }

    /// As the trait's, and a shaft so light that more than 700 e-folds of E are damped per
    /// cycle stops at once: `None`, a stall.
    fn delta_at(&self, shaft_inertia: f64, ratio: f64) -> Result<Option<f64>> {
        match self.solve(shaft_inertia, ratio, None) {
            Ok(found) => Ok(found.delta()),
            Err(MechanismError::OutOfRange { .. }) => Ok(None),
            Err(error) => Err(error),
        }
    }
}

/// E(φ) of the periodic solution under a load c·ω² and a constant drive, for one shaft
/// inertia.
struct ClosedForm<'c> {
    cycle: &'c Cycle,
    coefficient: f64,
    drive: f64,
    rate: Antiderivative<'c>,
    forcing: Antiderivative<'c>,
    /// E(0) (J).
    pub energy_at_zero: f64,
    /// E at the base nodes, then the edges (J).
    energy: Vec<f64>,
    /// E'' at the base nodes (J/rad²).
    curvature: Vec<f64>,
}

impl<'c> ClosedForm<'c> {
    /// The closed form for the load c = `coefficient` (N·m·s²/rad²) and the constant
    /// `drive` (N·m). Errors: more than 700 e-folds of E damped per cycle (the load
    /// names the parameter).
    pub fn new(cycle: &'c Cycle, coefficient: f64, drive: f64) -> Result<Self> {
        let panels = &cycle.panels;
        let n = cycle.nodes();
        let j: Vec<f64> = cycle.rest[..n].iter().map(|r| cycle.inertia + r).collect();
        let damping: Vec<f64> = j.iter().map(|j| 2.0 * coefficient / j).collect();
        let rate = panels.antiderivative(&damping);
        let total = rate.at_edges[panels.count()];
        if total.is_nan() || total >= MOST_E_FOLDS {
            return Err(MechanismError::OutOfRange {
                parameter: "load",
                value: total,
                allowed: "a square-law load damping < 700 e-folds of kinetic energy per cycle",
            });
        }
        let rate_nodes = rate.at_nodes();
        // ∫₀^φ e^{A} M_gas dφ by parts, = e^{A}W − ∫₀^φ A′ e^{A} W dφ: W, the gas work, is
        // exact and smooth (the kinks of tabulated pressures are in M_gas, not in W).
        let gravity = cycle.torque_at(&panels.phi, false)?;
        let work = &cycle.work;
        let forcing_nodes: Vec<f64> = (0..n)
            .map(|i| rate_nodes[i].exp() * (drive + gravity[i] - damping[i] * work[i]))
            .collect();
        let forcing = panels.antiderivative(&forcing_nodes);
        let forcing_at = forcing.at_nodes();
        let b_cycle = total.exp() * work[work.len() - 1] + forcing.at_edges[panels.count()];
        let e0 = b_cycle / total.exp_m1();
        // E = e^{−A}(E₀ + e^{A}W + ∫…) = W + e^{−A}(E₀ + ∫…)
        let mut energy: Vec<f64> = (0..n)
            .map(|i| work[i] + (-rate_nodes[i]).exp() * (e0 + forcing_at[i]))
            .collect();
        energy.extend(
            rate.at_edges
                .iter()
                .zip(&forcing.at_edges)
                .zip(&work[n..])
                .map(|((a, f), w)| w + (-a).exp() * (e0 + f)),
        );
        // E′ = M − U′ − (2c/J)E at the nodes (M_gas the slope of W's interpolant: an
        // estimate, only for where the time mesh is graded); E'' its slope.
        let gas = panels.slope(&work[..n]);
        let torque: Vec<f64> = (0..n)
            .map(|i| gas[i] + drive + gravity[i] - damping[i] * energy[i])
            .collect();
        let curvature = panels.slope(&torque);
        Ok(Self {
            cycle,
            coefficient,
            drive,
            rate,
            forcing,
            energy_at_zero: e0,
            energy,
            curvature,
        })
    }

    /// E(φ) (J) at any angles in [0, Φ]: W + e^{−A}(E₀ + ∫₀^φ e^{A}(…) dφ).
    fn energy_at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        let work = self.cycle.work_at(phi)?;
        Ok(phi
            .iter()
            .zip(&work)
            .map(|(&p, w)| {
                w + (-self.rate.at(p)).exp() * (self.energy_at_zero + self.forcing.at(p))
            })
            .collect())
    }

    /// ω(φ) = √(2E/J) (rad/s) at any angles in [0, Φ], E exact there.
    fn omega_at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        let energy = self.energy_at(phi)?;
        let rest = self.cycle.rest_at(phi)?;
        Ok(energy
            .iter()
            .zip(&rest)
            .map(|(e, r)| (2.0 * e.max(0.0) / (self.cycle.inertia + r)).sqrt())
            .collect())
    }

    /// ω(φ) and dω/dφ at one angle, from J ω dω/dφ = M_gas + M_drive − U′ − cω² − ½J′ω²
    /// (N·m), whose roots are the extremes of ω.
    fn speed_and_slope(&self, phi: f64) -> Result<(f64, f64)> {
        let folded = [phi.rem_euclid(self.cycle.cycle())];
        let energy = self.energy_at(&folded)?[0];
        let (rest, slope) = self.cycle.inertia_at(&folded)?;
        let j = self.cycle.inertia + rest[0];
        let torque = self.cycle.torque_at(&folded, true)?[0] + self.drive;
        let omega = (2.0 * energy.max(0.0) / j).sqrt();
        let torque = torque - (2.0 * self.coefficient + slope[0]) * energy / j;
        Ok((omega, torque / (j * omega)))
    }

    /// The periodic solution (stalled where E reaches zero or ω_min < `ratio`·ω_m), with ω
    /// and t at `phi` (rad, in [0, Φ]) where given, as the energy method gives them, and
    /// the load's cycle mean (1/Φ)∫cω² dφ (N·m): the cycle quadrature of cω² with ω exact
    /// at the base nodes.
    fn solve(&self, ratio: f64, phi: Option<&[f64]>) -> Result<Solution> {
        let cycle = self.cycle;
        let base = &cycle.panels;
        if self.energy.iter().any(|&e| e.is_nan() || e <= 0.0) {
            // Where E is lowest: the worst sample (not located between the samples).
            let samples = base.in_angle_order(&self.energy);
            let worst = samples
                .iter()
                .fold(samples[0], |a, &b| if b.1 < a.1 { b } else { a });
            return Ok(Solution::stalled(worst.0, message::STOPS));
        }
        // E′ = M − U′ − (2c/J)E exactly at any angle: the minima of E located between the
        // samples, and the time mesh graded towards them.
        let energy_slope = |p: f64| -> Result<f64> {
            let folded = [p.rem_euclid(cycle.cycle())];
            let energy = self.energy_at(&folded)?[0];
            let j = cycle.inertia + cycle.rest_at(&folded)?[0];
            let torque = cycle.torque_at(&folded, true)?[0] + self.drive;
            Ok(torque - 2.0 * self.coefficient * energy / j)
        };
        let dips = local_minima(base, &self.energy, &self.curvature, |p| {
            let value = self.energy_at(&[p.rem_euclid(cycle.cycle())])?[0];
            Ok((value, energy_slope(p)?))
        })?;
        let extra = grading(base, dips);
        let graded;
        let (panels, energy, rest): (&Panels, Vec<f64>, Vec<f64>) = if extra.is_empty() {
            (base, self.energy.clone(), cycle.rest.clone())
        } else {
            graded = base.refined(&extra);
            let everywhere: Vec<f64> = graded.phi.iter().chain(&graded.edges).copied().collect();
            (
                &graded,
                self.energy_at(&everywhere)?,
                cycle.rest_at(&everywhere)?,
            )
        };
        let n = panels.phi.len();
        if let Some(i) = energy.iter().position(|&e| e.is_nan() || e <= 0.0) {
            let angle = if i < n {
                panels.phi[i]
            } else {
                panels.edges[i - n]
            };
            return Ok(Solution::stalled(angle, message::STOPS));
        }
        let omega: Vec<f64> = energy
            .iter()
            .zip(&rest)
            .map(|(e, r)| (2.0 * e / (cycle.inertia + r)).sqrt())
            .collect();
        let inverse: Vec<f64> = omega[..n].iter().map(|w| 1.0 / w).collect();
        let period = panels.integral(&inverse);
        let omega_mean = cycle.cycle() / period;
        let [(phi_max, omega_max), (phi_min, omega_min)] =
            refine_extrema(panels, &omega, |p| self.speed_and_slope(p))?;
        let solution = Periodic {
            omega_mean,
            period,
            omega_max,
            omega_min,
            phi_max: phi_max.rem_euclid(cycle.cycle()),
            phi_min: phi_min.rem_euclid(cycle.cycle()),
            margin: f64::NAN,
            energy_at_zero: self.energy_at_zero,
        }
        .mean_inside();
        if omega_min < ratio * omega_mean {
            return Ok(Solution::stalled(solution.phi_min, message::CRAWLS));
        }
        let at_nodes = self.omega_at(&base.phi)?;
        let load: Vec<f64> = at_nodes.iter().map(|w| self.coefficient * w * w).collect();
        let mean_load = base.integral(&load) / cycle.cycle();
        let curves = phi
            .map(|phi| -> Result<Curves> {
                Ok(Curves {
                    omega: self.omega_at(phi)?,
                    time: panels.running_at(&inverse, phi),
                })
            })
            .transpose()?;
        Ok(Solution {
            curves,
            mean_load,
            ..Solution::converged(solution, message::CLOSED_FORM)
        })
    }
}
