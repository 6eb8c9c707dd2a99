//! Engines of any layout (V, boxer, W, odd-fire, unequal cylinders): a list of slider-crank
//! units, each with its own crank phase, cylinder inclination, crank ratio and gravity
//! moments.
//!
//! A unit's crank pin sits at the absolute angle ψ_j + γ_j (mathematics.md §1). Cylinders that
//! share a crank pin of absolute angle φ + β (V, W, the 180° V) therefore have the phases
//! α_j = β − γ_j; opposed cylinders of a boxer sit on throws π apart. Each unit contributes
//! the in-line formulas with its own γ_j, so the kernels are those of `exact.rs`, with one set
//! of coefficients per unit, at the same speed.

use crate::error::{check, check_length, MechanismError, Result};
use crate::exact::{evaluate_units, Coefficients, Quantity};
use crate::extrema::{extrema_of_units, EnergyExtrema};
use crate::grid::{Phi, PreparedPhi};
use crate::harmonics::{harmonic_reach, ExactLambdas};
use crate::mechanism::{Design, Phases};
use crate::parallel::{for_each_row_segment, Parallelism};
use crate::series::{series_or_closed, FourierSeries, SeriesPhi};

/// One slider-crank unit of an engine (dimensionless, like `Design`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    /// α_j: the unit's crank angle is ψ_j = φ + α_j, from its own outer dead centre.
    pub phase: f64,
    /// γ_j: its cylinder axis to the horizontal.
    pub inclination: f64,
    pub crank_ratio: f64,
    pub u1: f64,
    pub u2: f64,
}

/// A validated engine: its units and their kernel coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct Engine {
    cylinders: Vec<Cylinder>,
    phases: Phases,
    coefficients: Vec<Coefficients>,
}

impl Engine {
    pub fn new(cylinders: Vec<Cylinder>) -> Result<Self> {
        if cylinders.is_empty() {
            return Err(MechanismError::Empty {
                parameter: "cylinders",
            });
        }
        let mut alphas = Vec::with_capacity(cylinders.len());
        let mut coefficients = Vec::with_capacity(cylinders.len());
        for c in &cylinders {
            alphas.push(check("phase", c.phase, "finite angles in radians", |_| {
                true
            })?);
            let design = Design::new(c.crank_ratio, c.inclination, c.u1, c.u2)?;
            coefficients.push(Coefficients::new(&design));
        }
        Ok(Self {
            phases: Phases::new(&alphas)?,
            cylinders,
            coefficients,
        })
    }

    pub fn cylinders(&self) -> &[Cylinder] {
        &self.cylinders
    }

    /// `quantity` at every φ into `out` (same length as `phi`).
    pub fn evaluate<'a>(
        &self,
        quantity: Quantity,
        phi: impl Into<Phi<'a>>,
        out: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        let phi = PreparedPhi::new(phi.into(), parallelism);
        check_length("out", phi.len(), out.len())?;
        let work = phi.len().saturating_mul(self.cylinders.len());
        for_each_row_segment(out, phi.len(), work, parallelism, |_, col, segment| {
            evaluate_units(
                quantity,
                &self.coefficients,
                &self.phases,
                phi.run(col, segment.len()),
                segment,
            )
        });
        Ok(())
    }

    /// Fourier coefficients a_n, b_n (n = 0 … len − 1) of Q_u*, exact Λ_n, every harmonic.
    pub fn fourier_coefficients(&self, a: &mut [f64], b: &mut [f64]) {
        let n_max = a.len().saturating_sub(1);
        let (terms, _) = self.harmonics(n_max, false);
        a.fill(0.0);
        b.fill(0.0);
        for (n, an, bn) in terms {
            a[n] = an;
            b[n] = bn;
        }
    }

    /// (n, a_n, b_n) of Q_u* for n = 1 and even n ≤ n_max. Per unit
    /// Q = N cos ψ + W1 sin ψ + Σ_{n even} N1 Λ_n(λ_j) sin nψ, ψ = φ + α_j, so
    /// a_1 = Σ N_j cos α_j + W1_j sin α_j, b_1 = Σ W1_j cos α_j − N_j sin α_j,
    /// a_n = Σ W_nj sin nα_j, b_n = Σ W_nj cos nα_j. A sum below its own rounding noise
    /// is zero (the harmonic cancelled). With `cut`, stop where a bound on the rest is
    /// below ε·rms(Q)/2 (as `FourierSeries::exact`).
    /// Also returns whether the rest is provably negligible (always true without `cut`).
    fn harmonics(&self, n_max: usize, cut: bool) -> (Vec<(usize, f64, f64)>, bool) {
        let units: Vec<(f64, f64, f64)> = self
            .cylinders
            .iter()
            .map(|c| {
                let (sin_g, cos_g) = c.inclination.sin_cos();
                let n1 = -c.u1 * sin_g;
                (c.u2 * cos_g, n1 - c.u2 * sin_g, n1)
            })
            .collect();
        let mut out = Vec::new();
        let (mut a1, mut b1, mut noise1) = (0.0, 0.0, 0.0);
        for (c, &(n, w1, _)) in self.cylinders.iter().zip(&units) {
            let (sa, ca) = c.phase.sin_cos();
            a1 += n * ca + w1 * sa;
            b1 += w1 * ca - n * sa;
            noise1 += (n.abs() + w1.abs()) * (1.0 + c.phase.abs());
        }
        let keep = |a: f64, b: f64, noise: f64| a.hypot(b) > 8.0 * f64::EPSILON * noise;
        if n_max >= 1 && keep(a1, b1, noise1) {
            out.push((1, a1, b1));
        }
        let mut mean_square = 0.5 * (a1 * a1 + b1 * b1);
        let mut lambdas: Vec<ExactLambdas> = self
            .cylinders
            .iter()
            .map(|c| ExactLambdas::new(c.crank_ratio))
            .collect();
        // Tail bound: Σ_j |N1_j| t_j^{2M+1}/((1 − t_j²)(1 − t_j⁴)) with t_j^{2M+1} tracked per unit.
        let t: Vec<f64> = lambdas.iter().map(ExactLambdas::t).collect();
        let mut t_power = t.clone();
        let mut complete = !cut || units.iter().all(|&(_, _, n1)| n1 == 0.0);
        for n in (2..=n_max).step_by(2) {
            if cut && complete {
                break;
            }
            let (mut a, mut b, mut noise) = (0.0, 0.0, 0.0);
            for ((c, &(_, _, n1)), lambda) in
                self.cylinders.iter().zip(&units).zip(lambdas.iter_mut())
            {
                let w = n1 * lambda.next().unwrap_or(0.0);
                let (s, co) = (n as f64 * c.phase).sin_cos();
                a += w * s;
                b += w * co;
                noise += w.abs() * (1.0 + n as f64 * c.phase.abs());
            }
            if keep(a, b, noise) {
                out.push((n, a, b));
                mean_square += 0.5 * (a * a + b * b);
            }
            if cut {
                let mut tail = 0.0;
                for ((tp, &tj), &(_, _, n1)) in t_power.iter_mut().zip(&t).zip(&units) {
                    *tp *= tj * tj;
                    tail += n1.abs() * *tp / ((1.0 - tj * tj) * (1.0 - tj.powi(4)));
                }
                let negligible = t_power.iter().all(|&tp| tp <= 1e-30);
                complete = tail <= 0.5 * f64::EPSILON * mean_square.sqrt() || negligible;
            }
        }
        (out, complete)
    }

    /// Q_u* at every φ from its series where that is complete, else the closed form.
    pub fn evaluate_series<'a>(
        &self,
        phi: impl Into<Phi<'a>>,
        out: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        let series = self.series();
        let phi = SeriesPhi::new(phi.into(), std::slice::from_ref(&series), parallelism);
        check_length("out", phi.len(), out.len())?;
        let work = phi.len().saturating_mul(4);
        for_each_row_segment(out, phi.len(), work, parallelism, |_, col, segment| {
            series_or_closed(
                &series,
                &self.coefficients,
                &self.phases,
                phi.run(col, segment.len()),
                phi.harmonic(series.step),
                segment,
            )
        });
        Ok(())
    }

    /// Q_u* as a machine-precision series (every surviving harmonic, cut by a rigorous bound).
    pub fn series(&self) -> FourierSeries {
        let reach = self
            .cylinders
            .iter()
            .map(|c| harmonic_reach(c.crank_ratio))
            .max()
            .unwrap_or(24);
        let (harmonics, complete) = self.harmonics(reach, true);
        let (a1, b1) = match harmonics.first() {
            Some(&(1, a, b)) => (a, b),
            _ => (0.0, 0.0),
        };
        let even: Vec<_> = harmonics.into_iter().filter(|&(n, _, _)| n > 1).collect();
        FourierSeries {
            complete,
            ..FourierSeries::from_terms(a1, b1, &even)
        }
    }

    /// The exact extrema of U_w* over a revolution (δ_g = range).
    pub fn energy_extrema(&self) -> EnergyExtrema {
        extrema_of_units(&self.coefficients, &self.phases, &self.series())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanism::{crank_phases, Acting, Strokes};
    use crate::{evaluate, harmonics::PhaseSums};

    #[test]
    fn identical_cylinders_are_the_inline_engine() {
        let alphas = crank_phases(6, Strokes::Four, Acting::Single).unwrap();
        let design = Design::new(0.3, 1.2, 0.7, -0.2).unwrap();
        let engine = Engine::new(
            alphas
                .iter()
                .map(|&phase| Cylinder {
                    phase,
                    inclination: 1.2,
                    crank_ratio: 0.3,
                    u1: 0.7,
                    u2: -0.2,
                })
                .collect(),
        )
        .unwrap();
        let phi: Vec<f64> = (0..1000).map(|i| i as f64 * 0.0123 - 3.0).collect();
        let (mut a, mut b) = (vec![0.0; phi.len()], vec![0.0; phi.len()]);
        engine
            .evaluate(
                Quantity::GeneralizedForce,
                &phi,
                &mut a,
                Parallelism::SERIAL,
            )
            .unwrap();
        let phases = Phases::new(&alphas).unwrap();
        evaluate(
            Quantity::GeneralizedForce,
            &[design],
            &phases,
            &phi,
            &mut b,
            Parallelism::SERIAL,
        )
        .unwrap();
        assert_eq!(a, b);
        let inline = FourierSeries::exact(&design, &PhaseSums::new(&alphas, 60));
        let general = engine.series();
        assert_eq!(inline.step, general.step);
        for (x, y) in inline
            .cos
            .iter()
            .zip(&general.cos)
            .chain(inline.sin.iter().zip(&general.sin))
        {
            assert!((x - y).abs() <= 1e-15 * x.abs().max(1e-300) + 1e-300);
        }
    }

    #[test]
    fn rejects_bad_cylinders() {
        assert!(Engine::new(vec![]).is_err());
        let bad = Cylinder {
            phase: 0.0,
            inclination: 0.0,
            crank_ratio: 1.0,
            u1: 0.0,
            u2: 0.0,
        };
        assert!(Engine::new(vec![bad])
            .unwrap_err()
            .to_string()
            .contains("crank_ratio"));
    }
}
