//! Engines of any layout (V, boxer, W, odd-fire, unequal cylinders): a list of slider-crank
//! units, each with its own crank phase, cylinder inclination, crank ratio and gravity
//! moments. A regular in-line machine is the special case whose units share one design
//! (`Engine::inline`): one set of kernel coefficients and one group of phase sums.
//!
//! A unit's crank pin sits at the absolute angle ψ_j + γ_j (docs/theory.md, "Conventions"). Cylinders that
//! share a crank pin of absolute angle φ + β (V, W, the 180° V) therefore have the phases
//! α_j = β − γ_j; opposed cylinders of a boxer sit on throws π apart. Each unit contributes
//! the in-line formulas with its own γ_j, so the kernels are those of `exact.rs`, with one set
//! of coefficients per unit, at the same speed.

use crate::angles::{Phi, PreparedPhi};
use crate::error::{check, check_length, try_filled, MechanismError, Result};
use crate::exact::{evaluate_units, Coefficients, Quantity};
use crate::extrema::{extrema_of_units, EnergyExtrema};
use crate::harmonics::{harmonic_reach, harmonic_width, PhaseSums};
use crate::mechanism::{Design, Phases};
use crate::parallel::{for_each_row_segment, Parallelism};
use crate::series::{self, FourierSeries, SeriesKind, UnitGroup};
use crate::series_kernels::{series_or_closed, SeriesPhi};

/// One slider-crank unit of an engine in the dimensionless terms of the gravity moments: its
/// crank phase α_j, cylinder inclination γ_j (rad) and `Design` (crank ratio λ, gravity
/// moments u1, u2). Not a physical cylinder: the unit in SI units (masses, lengths, bore) is
/// `PhysicalCylinder`, whose gravity is one of these in joules (`Dynamics`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EngineUnit {
    /// α_j: the unit's crank angle is ψ_j = φ + α_j, from its own outer dead centre.
    pub phase: f64,
    /// γ_j: its cylinder axis to the horizontal.
    pub inclination: f64,
    pub crank_ratio: f64,
    pub u1: f64,
    pub u2: f64,
}

/// A validated engine: its units, their kernel coefficients (one set shared by every unit,
/// or one per unit) and the groups of units that share one design.
#[derive(Debug, Clone, PartialEq)]
pub struct Engine {
    cylinders: Vec<EngineUnit>,
    phases: Phases,
    coefficients: Vec<Coefficients>,
    /// Each group's design and the phases of its units.
    groups: Vec<(Design, Vec<f64>)>,
}

impl Engine {
    /// An engine of independent units (one group each).
    pub fn new(cylinders: Vec<EngineUnit>) -> Result<Self> {
        if cylinders.is_empty() {
            return Err(MechanismError::Empty {
                parameter: "cylinders",
            });
        }
        let mut groups = Vec::with_capacity(cylinders.len());
        for c in &cylinders {
            let phase = check("phase", c.phase, "finite angles in radians", |_| true)?;
            groups.push((
                Design::new(c.crank_ratio, c.inclination, c.u1, c.u2)?,
                vec![phase],
            ));
        }
        let alphas: Vec<f64> = cylinders.iter().map(|c| c.phase).collect();
        Ok(Self {
            phases: Phases::new(&alphas)?,
            coefficients: groups.iter().map(|(d, _)| Coefficients::new(d)).collect(),
            cylinders,
            groups,
        })
    }

    /// A regular in-line machine: identical units of `design` at the crank phases `phases`.
    pub fn inline(design: Design, phases: &[f64]) -> Result<Self> {
        let phase_set = Phases::new(phases)?;
        Ok(Self {
            cylinders: phases
                .iter()
                .map(|&phase| EngineUnit {
                    phase,
                    inclination: design.inclination,
                    crank_ratio: design.crank_ratio,
                    u1: design.u1,
                    u2: design.u2,
                })
                .collect(),
            phases: phase_set,
            coefficients: vec![Coefficients::new(&design)],
            groups: vec![(design, phases.to_vec())],
        })
    }

    /// An engine from per-unit columns of equal length.
    pub fn from_columns(
        phase: &[f64],
        inclination: &[f64],
        crank_ratio: &[f64],
        u1: &[f64],
        u2: &[f64],
    ) -> Result<Self> {
        for column in [inclination, crank_ratio, u1, u2] {
            check_length("cylinder arrays", phase.len(), column.len())?;
        }
        Self::new(
            (0..phase.len())
                .map(|i| EngineUnit {
                    phase: phase[i],
                    inclination: inclination[i],
                    crank_ratio: crank_ratio[i],
                    u1: u1[i],
                    u2: u2[i],
                })
                .collect(),
        )
    }

    pub fn cylinders(&self) -> &[EngineUnit] {
        &self.cylinders
    }

    pub(crate) fn coefficients(&self) -> &[Coefficients] {
        &self.coefficients
    }

    pub(crate) fn phases(&self) -> &Phases {
        &self.phases
    }

    /// The harmonic reach the series of this engine can need.
    pub(crate) fn reach(&self) -> usize {
        self.groups
            .iter()
            .map(|(d, _)| harmonic_reach(d.crank_ratio))
            .max()
            .unwrap_or(24)
    }

    /// `f` of the unit groups with phase sums through harmonic `n_max` (an error naming
    /// n_max when those would not fit in memory).
    pub(crate) fn with_groups<R>(
        &self,
        n_max: usize,
        f: impl FnOnce(&[UnitGroup]) -> R,
    ) -> Result<R> {
        let sums = self
            .groups
            .iter()
            .map(|(_, phases)| PhaseSums::new(phases, n_max.max(1)))
            .collect::<Result<Vec<_>>>()?;
        Ok(self.groups_of(&sums, f))
    }

    /// `f` of the unit groups with phase sums through the harmonic reach of the series.
    pub(crate) fn with_reach_groups<R>(&self, f: impl FnOnce(&[UnitGroup]) -> R) -> R {
        let reach = self.reach();
        let sums: Vec<PhaseSums> = self
            .groups
            .iter()
            .map(|(_, phases)| PhaseSums::within_reach(phases, reach))
            .collect();
        self.groups_of(&sums, f)
    }

    fn groups_of<R>(&self, sums: &[PhaseSums], f: impl FnOnce(&[UnitGroup]) -> R) -> R {
        let groups: Vec<UnitGroup> = self
            .groups
            .iter()
            .zip(sums)
            .map(|((design, _), sums)| UnitGroup { design, sums })
            .collect();
        f(&groups)
    }

    /// `quantity` at every φ into `out` (same length as `phi`).
    pub fn evaluate<'a>(
        &self,
        quantity: Quantity,
        phi: impl Into<Phi<'a>>,
        out: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        let phi = phi.into();
        check_length("out", phi.len(), out.len())?;
        let phi = PreparedPhi::new(phi, parallelism);
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

    /// Fourier coefficients (a_n, b_n), n = 0 … n_max, of Q_u*, exact Λ_n, every harmonic;
    /// a cancelled harmonic is exactly 0.
    pub fn fourier_coefficients(&self, n_max: usize) -> Result<(Vec<f64>, Vec<f64>)> {
        let width = harmonic_width(n_max)?;
        let mut a = try_filled("n_max", n_max, width as u128, 0.0)?;
        let mut b = try_filled("n_max", n_max, width as u128, 0.0)?;
        self.with_groups(n_max, |groups| {
            series::fourier_coefficients(groups, &mut a, &mut b)
        })?;
        Ok((a, b))
    }

    /// Q_u* as a machine-precision series (every surviving harmonic, cut by a rigorous bound).
    pub fn series(&self) -> FourierSeries {
        self.with_reach_groups(|groups| FourierSeries::new(SeriesKind::Exact, groups))
    }

    /// Q_u* at every φ from its series where that is complete, else the closed form.
    pub fn evaluate_series<'a>(
        &self,
        phi: impl Into<Phi<'a>>,
        out: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        let phi = phi.into();
        check_length("out", phi.len(), out.len())?;
        let series = self.series();
        let phi = SeriesPhi::new(phi, std::slice::from_ref(&series), parallelism);
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

    /// The exact extrema of U_w* over a revolution (δ_g = range).
    pub fn energy_extrema(&self) -> EnergyExtrema {
        extrema_of_units(&self.coefficients, &self.phases, &self.series())
    }

    /// (n, amplitude) of the largest harmonic of Q_u*; (0, 0) when Q ≡ 0.
    pub fn leading_harmonic(&self) -> (usize, f64) {
        self.series().leading_harmonic()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluate;
    use crate::mechanism::{crank_phases, Acting, Strokes};

    #[test]
    fn identical_cylinders_are_the_inline_engine() {
        let alphas = crank_phases(6, Strokes::Four, Acting::Single).unwrap();
        let design = Design::new(0.3, 1.2, 0.7, -0.2).unwrap();
        let inline = Engine::inline(design, &alphas).unwrap();
        let engine = Engine::new(inline.cylinders().to_vec()).unwrap();
        let phi: Vec<f64> = (0..1000).map(|i| i as f64 * 0.0123 - 3.0).collect();
        let (mut a, mut b, mut c) = (
            vec![0.0; phi.len()],
            vec![0.0; phi.len()],
            vec![0.0; phi.len()],
        );
        let force = Quantity::GeneralizedForce;
        engine
            .evaluate(force, &phi, &mut a, Parallelism::SERIAL)
            .unwrap();
        inline
            .evaluate(force, &phi, &mut b, Parallelism::SERIAL)
            .unwrap();
        let phases = Phases::new(&alphas).unwrap();
        evaluate(force, &[design], &phases, &phi, &mut c, Parallelism::SERIAL).unwrap();
        assert_eq!(a, b);
        assert_eq!(b, c);
        let (shared, general) = (inline.series(), engine.series());
        assert_eq!(shared.step, general.step);
        for (x, y) in shared
            .cos
            .iter()
            .zip(&general.cos)
            .chain(shared.sin.iter().zip(&general.sin))
        {
            assert!((x - y).abs() <= 1e-15 * x.abs().max(1e-300) + 1e-300);
        }
    }

    #[test]
    fn rejects_bad_cylinders() {
        assert!(Engine::new(vec![]).is_err());
        let bad = EngineUnit {
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
        let short =
            Engine::from_columns(&[0.0, 1.0], &[0.0], &[0.1, 0.1], &[0.0, 0.0], &[0.0, 0.0]);
        assert!(short.unwrap_err().to_string().contains("cylinder arrays"));
    }
}
