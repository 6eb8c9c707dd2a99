//! A driving torque that depends on the crank angle alone (docs/theory.md, "Steady
//! running"): M_d(φ) (N·m), periodic over the working cycle, given as a piecewise polynomial
//! (SciPy's `PPoly` layout over [0, Φ], as the pressures cross), and its work
//! W_d(φ) = ∫₀^φ M_d dφ, exact: each piece's antiderivative in closed form.

use crate::error::{MechanismError, Result};

use super::gas::PiecewisePolynomial;

/// M_d (N·m) as a periodic piecewise polynomial, and its work at the breakpoints.
#[derive(Debug, Clone)]
pub(crate) struct Drive {
    torque: PiecewisePolynomial,
    /// ∫_{x_0}^{x_i} M_d dθ (J) for i = 0..=m.
    at_breakpoints: Vec<f64>,
    /// ∫ M_d dφ over one cycle (J).
    pub per_cycle: f64,
    /// The integral from x_0 to φ = 0 folded into the first cycle, I(0) (J).
    at_zero: f64,
}

impl Drive {
    /// The drive of torque `torque` (N·m) over a cycle of Φ = `cycle` rad.
    ///
    /// Errors: breakpoints that do not span exactly one cycle, naming `drive`.
    pub fn new(torque: PiecewisePolynomial, cycle: f64) -> Result<Self> {
        let span = torque.cycle();
        if (span - cycle).abs() > 1e-9 * cycle {
            return Err(MechanismError::OutOfRange {
                parameter: "drive",
                value: span,
                allowed: "breakpoints spanning exactly one cycle (2π or 4π)",
            });
        }
        let x = torque.breakpoints();
        let mut at_breakpoints = Vec::with_capacity(x.len());
        let mut sum = 0.0;
        at_breakpoints.push(0.0);
        for i in 0..torque.pieces() {
            sum += piece_integral(&torque, i, x[i + 1] - x[i]);
            at_breakpoints.push(sum);
        }
        let mut drive = Self {
            torque,
            per_cycle: sum,
            at_breakpoints,
            at_zero: 0.0,
        };
        drive.at_zero = drive.integral(0.0);
        Ok(drive)
    }

    /// ∫_{x_0}^θ M_d dθ (J) for any θ: the folded angle's integral, plus a cycle's work per
    /// cycle crossed.
    fn integral(&self, theta: f64) -> f64 {
        let (i, dx) = self.torque.locate(theta);
        let folded = self.torque.breakpoints()[i] + dx;
        let turns = ((theta - folded) / self.torque.cycle()).round();
        self.at_breakpoints[i] + piece_integral(&self.torque, i, dx) + turns * self.per_cycle
    }

    /// W_d(φ) = ∫₀^φ M_d dφ (J) at `phi` (rad, any angles).
    pub fn work_at(&self, phi: &[f64]) -> Vec<f64> {
        phi.iter()
            .map(|&p| self.integral(p) - self.at_zero)
            .collect()
    }

    /// M_d (N·m) at `phi` (rad, any angles).
    pub fn torque_at(&self, phi: &[f64]) -> Vec<f64> {
        phi.iter().map(|&p| self.torque.value(p)).collect()
    }

    /// M_d′ (N·m/rad) at `phi` (rad, any angles): each piece's derivative in closed form.
    pub fn slope_at(&self, phi: &[f64]) -> Vec<f64> {
        let order = self.torque.order();
        phi.iter()
            .map(|&p| {
                let (i, dx) = self.torque.locate(p);
                // Σ (K − 1 − k) c_ki dx^(K − 2 − k), by Horner's rule.
                let mut slope = 0.0;
                for k in 0..order.saturating_sub(1) {
                    let power = (order - 1 - k) as f64;
                    slope = slope * dx + power * self.torque.coefficient(k, i);
                }
                slope
            })
            .collect()
    }
}

/// ∫_{x_i}^{x_i + dx} of piece i (J): Σ c_ki dx^(K − k)/(K − k), by Horner's rule.
fn piece_integral(torque: &PiecewisePolynomial, i: usize, dx: f64) -> f64 {
    let order = torque.order();
    let mut sum = 0.0;
    for k in 0..order {
        sum = sum * dx + torque.coefficient(k, i) / (order - k) as f64;
    }
    sum * dx
}
