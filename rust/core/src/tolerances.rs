//! Manufacturing tolerances: how far harmonics that cancel for identical cylinders come
//! back when the units' masses and phases scatter.
//!
//! For harmonic n, c_n = a_n + i b_n is linear in u1_j and u2_j and depends on α_j through
//! e^{±inα_j}, so for small independent errors, to first order,
//! E|δc_n|² = Σ_j |∂c_n/∂u1_j|²·(σ_u1·u1_j)² + |∂c_n/∂u2_j|²·(σ_u2·u2_j)² + |∂c_n/∂α_j|²·σ_α².

use crate::engine::Engine;
use crate::error::{check, try_filled, try_with_capacity, Result};
use crate::harmonics::lambda_exact;
use crate::mechanism::inclination_sin_cos;

/// Standard deviations of independent per-unit errors.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct UnitErrors {
    /// Relative standard deviation of each u1_j (unequal reciprocating masses).
    pub u1_rel: f64,
    /// Relative standard deviation of each u2_j (unequal rotating unbalance).
    pub u2_rel: f64,
    /// Standard deviation of each phase α_j, in radians.
    pub phase: f64,
}

impl UnitErrors {
    fn validate(&self) -> Result<()> {
        let non_negative = |x: f64| x >= 0.0;
        check("u1_rel", self.u1_rel, "a finite u1_rel >= 0", non_negative)?;
        check("u2_rel", self.u2_rel, "a finite u2_rel >= 0", non_negative)?;
        check(
            "phase",
            self.phase,
            "a finite phase >= 0 (radians)",
            non_negative,
        )?;
        Ok(())
    }
}

/// One harmonic's nominal amplitude √(a_n² + b_n²) and the rms of its first-order scatter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HarmonicScatter {
    pub n: usize,
    pub amplitude: f64,
    pub scatter_rms: f64,
}

impl Engine {
    /// The nominal amplitude and first-order scatter of harmonics n = 1 and the even
    /// n ≤ n_max of Q_u* under the errors `errors` (see the module docs).
    pub fn harmonic_sensitivity(
        &self,
        errors: UnitErrors,
        n_max: usize,
    ) -> Result<Vec<HarmonicScatter>> {
        errors.validate()?;
        let (a, b) = self.fourier_coefficients(n_max)?;
        let width = a.len();
        let mut lambdas = try_filled("n_max", n_max, width as u128, 0.0)?;
        let mut variance = try_filled("n_max", n_max, width as u128, 0.0)?;
        for c in self.cylinders() {
            let (sin_g, cos_g) = inclination_sin_cos(c.inclination);
            let (sin_a, cos_a) = c.phase.sin_cos();
            let (sd_u1, sd_u2) = (errors.u1_rel * c.u1, errors.u2_rel * c.u2);
            let phase_var = errors.phase * errors.phase;
            if n_max >= 1 {
                // a_1 = N cos α + W1 sin α, b_1 = W1 cos α − N sin α;
                // N = u2 cos γ, W1 = −(u1 + u2) sin γ.
                let (big_n, w1) = (c.u2 * cos_g, -(c.u1 + c.u2) * sin_g);
                let d_u1 = (-sin_g * sin_a, -sin_g * cos_a);
                let d_u2 = (
                    cos_g * cos_a - sin_g * sin_a,
                    -sin_g * cos_a - cos_g * sin_a,
                );
                let d_alpha = (-big_n * sin_a + w1 * cos_a, -w1 * sin_a - big_n * cos_a);
                variance[1] += squared(d_u1) * sd_u1 * sd_u1
                    + squared(d_u2) * sd_u2 * sd_u2
                    + squared(d_alpha) * phase_var;
            }
            // a_n = W_n sin nα, b_n = W_n cos nα with W_n = −u1 sin γ Λ_n (n even).
            lambda_exact(c.crank_ratio, &mut lambdas);
            for n in (2..width).step_by(2) {
                let (s, co) = (n as f64 * c.phase).sin_cos();
                let w = -c.u1 * sin_g * lambdas[n];
                let d_u1 = (-sin_g * lambdas[n] * s, -sin_g * lambdas[n] * co);
                let d_alpha = (w * n as f64 * co, -w * n as f64 * s);
                variance[n] += squared(d_u1) * sd_u1 * sd_u1 + squared(d_alpha) * phase_var;
            }
        }
        let mut rows = try_with_capacity("n_max", n_max, width as u128 / 2 + 1)?;
        rows.extend(
            (1..width)
                .filter(|&n| n == 1 || n % 2 == 0)
                .map(|n| HarmonicScatter {
                    n,
                    amplitude: a[n].hypot(b[n]),
                    scatter_rms: variance[n].sqrt(),
                }),
        );
        Ok(rows)
    }
}

fn squared((x, y): (f64, f64)) -> f64 {
    x * x + y * y
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::EngineUnit;

    fn v_twin() -> Engine {
        let cylinder = |phase, inclination, u1, u2| EngineUnit {
            phase,
            inclination,
            crank_ratio: 0.28,
            u1,
            u2,
        };
        Engine::new(vec![
            cylinder(0.3, 1.2, 0.8, -0.2),
            cylinder(-0.9, 1.9, 0.7, 0.1),
            cylinder(2.0, 0.4, 0.9, 0.3),
        ])
        .unwrap()
    }

    type Perturbation = fn(&mut EngineUnit, f64);

    /// |∂c_n/∂x|² by central differences of the Fourier coefficients of perturbed engines.
    fn squared_slope(
        engine: &Engine,
        n_max: usize,
        perturb: impl Fn(&mut EngineUnit, f64),
    ) -> Vec<f64> {
        let h = 1e-6;
        let shifted = |sign: f64| {
            let mut cylinders = engine.cylinders().to_vec();
            perturb(&mut cylinders[0], sign * h);
            Engine::new(cylinders)
                .unwrap()
                .fourier_coefficients(n_max)
                .unwrap()
        };
        let ((ap, bp), (am, bm)) = (shifted(1.0), shifted(-1.0));
        (0..=n_max)
            .map(|n| ((ap[n] - am[n]) / (2.0 * h)).powi(2) + ((bp[n] - bm[n]) / (2.0 * h)).powi(2))
            .collect()
    }

    #[test]
    fn scatter_matches_numerical_derivatives() {
        // One error at a time, on the first unit only: the variance is |∂c_n/∂x_0|²·σ².
        let n_max = 8;
        let first = v_twin().cylinders()[0];
        let others: Vec<EngineUnit> = v_twin().cylinders()[1..]
            .iter()
            .map(|c| EngineUnit {
                u1: 0.0,
                u2: 0.0,
                ..*c
            })
            .collect();
        let engine = Engine::new([vec![first], others].concat()).unwrap();
        let cases: [(UnitErrors, Perturbation, f64); 3] = [
            (
                UnitErrors {
                    u1_rel: 0.1,
                    ..Default::default()
                },
                |c, d| c.u1 += d,
                0.1 * first.u1,
            ),
            (
                UnitErrors {
                    u2_rel: 0.1,
                    ..Default::default()
                },
                |c, d| c.u2 += d,
                0.1 * first.u2,
            ),
            (
                UnitErrors {
                    phase: 0.01,
                    ..Default::default()
                },
                |c, d| c.phase += d,
                0.01,
            ),
        ];
        for (errors, perturb, sigma) in cases {
            let slopes = squared_slope(&engine, n_max, perturb);
            for row in engine.harmonic_sensitivity(errors, n_max).unwrap() {
                let expected = slopes[row.n].sqrt() * sigma.abs();
                assert!(
                    (row.scatter_rms - expected).abs() <= 1e-7 * (1.0 + expected),
                    "{errors:?} n={}: {} vs {expected}",
                    row.n,
                    row.scatter_rms
                );
            }
        }
    }

    #[test]
    fn rows_and_validation() {
        let rows = v_twin()
            .harmonic_sensitivity(UnitErrors::default(), 7)
            .unwrap();
        let ns: Vec<usize> = rows.iter().map(|r| r.n).collect();
        assert_eq!(ns, vec![1, 2, 4, 6]);
        assert!(rows.iter().all(|r| r.scatter_rms == 0.0));
        let bad = UnitErrors {
            u1_rel: f64::NAN,
            ..Default::default()
        };
        let message = v_twin()
            .harmonic_sensitivity(bad, 4)
            .unwrap_err()
            .to_string();
        assert!(message.contains("u1_rel"), "{message}");
        let negative = UnitErrors {
            phase: -0.1,
            ..Default::default()
        };
        assert!(v_twin().harmonic_sensitivity(negative, 4).is_err());
    }
}
