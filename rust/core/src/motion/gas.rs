//! The gas: pressures as periodic piecewise polynomials, and the gas work
//! W(φ) = ∫₀^φ M_gas dφ integrated exactly against the piston velocity (docs/theory.md,
//! "Steady running", "How the integrals are taken").
//!
//! The gas torque of unit j is F(θ_j)·s'(ψ_j), ψ_j = φ + α_j, θ_j = ψ_j mod Φ, so its work from
//! φ = 0 is G(φ + α_j) − G(α_j) with G(x) = ∫₀^x F(θ) s'(θ) dθ the indicator work of that
//! unit's cylinder alone at phase 0 (continued beyond a cycle by G(x + Φ) = G(x) + G(Φ)).
//! Units that differ only in phase, inclination and masses share one G. G is integrated on
//! panels cut at every breakpoint of the cylinder's tables (`work`): there the pressure is
//! one polynomial and F·s' analytic, so the polynomial through F·s′ at a few Gauss nodes is
//! it to rounding, and integrated exactly from the panel's edge it gives G at every x, not
//! only at the nodes — made once per cylinder, a G at any x is then a sum of a dozen terms.

use std::f64::consts::PI;
use std::sync::Arc;

use crate::error::{check, check_finite, MechanismError, Result};
use crate::mechanism::PhysicalCylinder;

mod alignment;
mod rule;
mod work;

pub(crate) use work::GasWork;

/// A periodic piecewise polynomial in SciPy's `PPoly` convention: on [x_i, x_{i+1})
/// p(θ) = Σ_k c_ki (θ − x_i)^(K−1−k), taken modulo the cycle Φ = x_m − x_0 (θ is first
/// brought into [x_0, x_0 + Φ)). What an `IndicatorDiagram` interpolates (a periodic cubic
/// spline, PCHIP or linear), passed as its arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewisePolynomial {
    breakpoints: Vec<f64>,
    /// c_ki at i·K + k: each piece's coefficients side by side (one cache line for a
    /// cubic's), from the highest power.
    coefficients: Vec<f64>,
    order: usize,
    /// m/(x_m − x_0): the piece of θ guessed as if the breakpoints were uniform (tables
    /// usually are), then corrected by a step or two.
    per_radian: f64,
}

/// Breakpoints whose span differs from the cycle by more than this (relative) are refused:
/// a table that does not close over Φ (the tolerance of IndicatorDiagram's own check).
const SPAN_TOLERANCE: f64 = 1e-9;

impl PiecewisePolynomial {
    /// From breakpoints x[0..=m] (strictly increasing, spanning exactly `cycle`) and
    /// coefficients c, K rows of m (`coefficients[k * m + i]` = c_ki).
    pub fn new(breakpoints: Vec<f64>, coefficients: Vec<f64>, cycle: f64) -> Result<Self> {
        let m = breakpoints.len().saturating_sub(1);
        if m == 0 {
            return Err(MechanismError::Empty {
                parameter: "breakpoints",
            });
        }
        if coefficients.is_empty() || coefficients.len() % m != 0 {
            return Err(MechanismError::LengthMismatch {
                parameter: "coefficients",
                expected: m * (coefficients.len() / m).max(1),
                found: coefficients.len(),
            });
        }
        check_finite("breakpoints", &breakpoints, "finite, strictly increasing")?;
        if let Some(pair) = breakpoints.windows(2).find(|p| p[1] <= p[0]) {
            return Err(MechanismError::OutOfRange {
                parameter: "breakpoints",
                value: pair[1],
                allowed: "strictly increasing",
            });
        }
        check_finite("coefficients", &coefficients, "finite")?;
        let span = breakpoints[m] - breakpoints[0];
        check(
            "breakpoints",
            span,
            "a span of exactly one cycle (2π or 4π)",
            |s| (s - cycle).abs() <= SPAN_TOLERANCE * cycle,
        )?;
        let order = coefficients.len() / m;
        // Row k of the table (power K − 1 − k) to place k of every piece.
        let mut by_piece = vec![0.0; m * order];
        for (k, row) in coefficients.chunks_exact(m).enumerate() {
            for (piece, &c) in by_piece.chunks_exact_mut(order).zip(row) {
                piece[k] = c;
            }
        }
        Ok(Self {
            order,
            per_radian: m as f64 / span,
            breakpoints,
            coefficients: by_piece,
        })
    }

    /// The same pressure times `factor` (every coefficient scaled; a motion sweep's
    /// `pressure_scale`).
    pub(crate) fn scaled(&self, factor: f64) -> Self {
        Self {
            breakpoints: self.breakpoints.clone(),
            coefficients: self.coefficients.iter().map(|c| c * factor).collect(),
            order: self.order,
            per_radian: self.per_radian,
        }
    }

    pub fn breakpoints(&self) -> &[f64] {
        &self.breakpoints
    }

    /// K: the number of coefficients per piece (degree + 1).
    pub fn order(&self) -> usize {
        self.order
    }

    pub(crate) fn pieces(&self) -> usize {
        self.breakpoints.len() - 1
    }

    pub(crate) fn cycle(&self) -> f64 {
        self.breakpoints[self.pieces()] - self.breakpoints[0]
    }

    /// p(θ), θ taken modulo the cycle as `IndicatorDiagram` takes it: x_0 + (θ − x_0) mod Φ,
    /// in the piece [x_i, x_{i+1}) that holds it (the last piece at x_m).
    pub fn value(&self, theta: f64) -> f64 {
        self.value_near(theta, &mut 0)
    }

    /// [`PiecewisePolynomial::value`] (the same doubles), its piece looked for first at
    /// `hint` and the one after it, and left there: angles taken in increasing order walk
    /// the pieces without a search.
    #[inline]
    pub(crate) fn value_near(&self, theta: f64, hint: &mut usize) -> f64 {
        let x0 = self.breakpoints[0];
        let t = x0 + periodic(theta - x0, self.cycle());
        let i = self.piece_near(t, *hint);
        *hint = i;
        let dx = t - self.breakpoints[i];
        let mut p = 0.0;
        for &c in &self.coefficients[i * self.order..(i + 1) * self.order] {
            p = p * dx + c;
        }
        p
    }

    /// [`PiecewisePolynomial::value_near`] at every θ of `theta`, in order, into `out` (the
    /// same doubles), the angles in runs of `run` that each lie in one piece, as an
    /// indicator rule's panels do (they are cut at every breakpoint): a run's piece found
    /// once and its coefficients read once for all its angles, each angle only checked to
    /// lie in it (one that does not, looked up alone).
    pub(crate) fn values_in_runs(&self, theta: &[f64], run: usize, out: &mut [f64]) {
        let (x0, cycle, order) = (self.breakpoints[0], self.cycle(), self.order);
        let (x, last) = (&self.breakpoints, self.pieces() - 1);
        let run = run.max(1);
        let mut hint = 0;
        for (angles, values) in theta.chunks(run).zip(out.chunks_mut(run)) {
            let i = self.piece_near(x0 + periodic(angles[0] - x0, cycle), hint);
            hint = i;
            let (low, high) = (x[i], if i == last { f64::INFINITY } else { x[i + 1] });
            let coefficients = &self.coefficients[i * order..(i + 1) * order];
            for (&angle, value) in angles.iter().zip(values.iter_mut()) {
                let t = x0 + periodic(angle - x0, cycle);
                *value = if low <= t && t < high {
                    let dx = t - low;
                    coefficients.iter().fold(0.0, |p, &c| p * dx + c)
                } else {
                    self.value_near(angle, &mut hint)
                };
            }
        }
    }

    /// θ taken modulo the cycle as [`PiecewisePolynomial::value`] takes it: the piece i that
    /// holds it, and θ − x_i there.
    pub(crate) fn locate(&self, theta: f64) -> (usize, f64) {
        let x0 = self.breakpoints[0];
        let t = x0 + periodic(theta - x0, self.cycle());
        let i = self.piece(t);
        (i, t - self.breakpoints[i])
    }

    /// c_ki (k from the highest power, K − 1 − k the power of θ − x_i).
    pub(crate) fn coefficient(&self, k: usize, i: usize) -> f64 {
        self.coefficients[i * self.order + k]
    }

    /// [`PiecewisePolynomial::piece`] of t, `hint` and the three pieces after it tried first
    /// (angles in order a little coarser than the table skip one or two).
    #[inline]
    fn piece_near(&self, t: f64, hint: usize) -> usize {
        let x = &self.breakpoints;
        let last = self.pieces() - 1;
        // The piece i holds t where x_i ≤ t < x_{i+1}, or where i is the last and x_i ≤ t.
        let holds = |i: usize| x[i] <= t && (i == last || t < x[i + 1]);
        (hint..=(hint + 3).min(last))
            .find(|&i| holds(i))
            .unwrap_or_else(|| self.piece(t))
    }

    /// The piece holding t: the last i with x_i ≤ t, kept in 0..m (NumPy's
    /// `searchsorted(x, t, side="right") − 1`, clipped). Guessed from the mean breakpoint
    /// spacing, then walked a few steps; a binary search where the breakpoints are far from
    /// uniform. The same piece either way.
    fn piece(&self, t: f64) -> usize {
        let x = &self.breakpoints;
        let last = self.pieces() - 1;
        let guess = ((t - x[0]) * self.per_radian).clamp(0.0, last as f64) as usize;
        let mut i = guess;
        for _ in 0..4 {
            if x[i] > t {
                if i == 0 {
                    return 0;
                }
                i -= 1;
            } else if i < last && x[i + 1] <= t {
                i += 1;
            } else {
                return i;
            }
        }
        x.partition_point(|&b| b <= t).saturating_sub(1).min(last)
    }
}

/// `angle.rem_euclid(period)`, to the last bit, without a division where the angle is less
/// than a period outside [0, period): there the one subtraction or addition is exact
/// (Sterbenz) or the very one `rem_euclid` makes.
#[inline]
pub(crate) fn periodic(angle: f64, period: f64) -> f64 {
    if (0.0..period).contains(&angle) {
        angle
    } else if (period..2.0 * period).contains(&angle) {
        angle - period
    } else if -period < angle && angle < 0.0 {
        // rem_euclid: fmod leaves the angle, then adds the period (which may round to it).
        // (−Φ itself folds to −0.)
        angle + period
    } else {
        angle.rem_euclid(period)
    }
}

/// Which pressures act on a unit's piston, and on what areas.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GasCylinder {
    /// D (m): the head end's area is πD²/4; 0: no gas force.
    pub bore: f64,
    /// d (m): the crank end's area is π(D² − d²)/4.
    pub piston_rod_diameter: f64,
    /// The index of the head end's gauge pressure (Pa) among the machine's diagrams.
    pub head: Option<usize>,
    /// The crank end's (double-acting), pushing the piston away from the shaft.
    pub crank_end: Option<usize>,
}

impl GasCylinder {
    /// No gas on this unit.
    pub const NONE: Self = Self {
        bore: 0.0,
        piston_rod_diameter: 0.0,
        head: None,
        crank_end: None,
    };

    pub(crate) fn has_gas(&self) -> bool {
        self.bore > 0.0 && (self.head.is_some() || self.crank_end.is_some())
    }

    pub(crate) fn validate(&self, diagrams: usize) -> Result<()> {
        check("bore", self.bore, "bore >= 0", |d| d >= 0.0)?;
        check(
            "piston_rod_diameter",
            self.piston_rod_diameter,
            "0 <= piston_rod_diameter < bore",
            |d| d >= 0.0 && (d < self.bore || (self.bore == 0.0 && d == 0.0)),
        )?;
        for index in [self.head, self.crank_end].into_iter().flatten() {
            if index >= diagrams {
                return Err(MechanismError::InvalidChoice {
                    parameter: "pressure",
                    value: index.to_string(),
                    allowed: "the index of one of the machine's diagrams",
                });
            }
        }
        Ok(())
    }

    /// πD²/4 (m²): the head end's area.
    #[inline]
    pub fn head_area(&self) -> f64 {
        PI * (self.bore * self.bore) / 4.0
    }

    /// π(D² − d²)/4 (m²): the crank end's area, around the piston rod.
    #[inline]
    pub fn crank_end_area(&self) -> f64 {
        PI * (self.bore * self.bore - self.piston_rod_diameter * self.piston_rod_diameter) / 4.0
    }

    /// F = p·A − p_c·A_c (N), positive toward the shaft, from the gauge pressures (Pa) on
    /// the head end (p) and on the crank end (p_c), each None where that end has none (its
    /// area is then not computed: this sits in the gas work's quadrature loops): the one
    /// place of this rule.
    #[inline]
    pub fn net_force(&self, head: Option<f64>, crank_end: Option<f64>) -> f64 {
        let mut force = 0.0;
        if let Some(p) = head {
            force += p * self.head_area();
        }
        if let Some(p) = crank_end {
            force -= p * self.crank_end_area();
        }
        force
    }
}

/// F = p·A − p_c·A_c (N) of every unit at every point, from the gauge pressures (Pa) on each
/// unit's two ends (`head`, `crank_end`: unit-major, units × points, 0 where an end has no
/// pressure), into `out` (the same shape). For pressures the core does not hold (a callable
/// evaluated by the caller); each cylinder's `head` and `crank_end` indices are not read.
pub fn net_piston_forces(
    gas: &[GasCylinder],
    head: &[f64],
    crank_end: &[f64],
    out: &mut [f64],
) -> Result<()> {
    for (parameter, found) in [("head", head.len()), ("crank_end", crank_end.len())] {
        if found != out.len() {
            return Err(MechanismError::LengthMismatch {
                parameter,
                expected: out.len(),
                found,
            });
        }
    }
    if gas.is_empty() {
        return Ok(());
    }
    if out.len() % gas.len() != 0 {
        return Err(MechanismError::LengthMismatch {
            parameter: "head",
            expected: gas.len() * (out.len() / gas.len() + 1),
            found: out.len(),
        });
    }
    let points = out.len() / gas.len();
    for cylinder in gas {
        let ends_unread = GasCylinder {
            head: None,
            crank_end: None,
            ..*cylinder
        };
        ends_unread.validate(0)?;
    }
    for (j, cylinder) in gas.iter().enumerate() {
        let span = j * points..(j + 1) * points;
        let unit = out[span.clone()].iter_mut();
        for ((f, &p), &p_c) in unit.zip(&head[span.clone()]).zip(&crank_end[span]) {
            *f = cylinder.net_force(Some(p), Some(p_c));
        }
    }
    Ok(())
}

/// The rules of a machine's gas: one per unit, each naming a diagram the machine has, each
/// diagram spanning its working cycle `cycle` (rad).
pub(crate) fn check_gas(
    units: &[PhysicalCylinder],
    gas: &[GasCylinder],
    diagrams: &[PiecewisePolynomial],
    cycle: f64,
) -> Result<()> {
    if gas.len() != units.len() {
        return Err(MechanismError::LengthMismatch {
            parameter: "gas",
            expected: units.len(),
            found: gas.len(),
        });
    }
    for cylinder in gas {
        cylinder.validate(diagrams.len())?;
    }
    for diagram in diagrams {
        check(
            "breakpoints",
            diagram.cycle(),
            "a span of the machine's cycle",
            |s| (s - cycle).abs() <= SPAN_TOLERANCE * cycle,
        )?;
    }
    Ok(())
}

/// The net piston forces F = p(θ)·A − p_c(θ)·A_c of a machine's units.
#[derive(Debug, Clone)]
pub(crate) struct Forces {
    gas: Vec<GasCylinder>,
    diagrams: Arc<[PiecewisePolynomial]>,
    phases: Vec<f64>,
    cycle: f64,
}

impl Forces {
    pub fn new(
        units: &[PhysicalCylinder],
        gas: &[GasCylinder],
        diagrams: Arc<[PiecewisePolynomial]>,
        cycle: f64,
    ) -> Result<Self> {
        check_gas(units, gas, &diagrams, cycle)?;
        Ok(Self {
            gas: gas.to_vec(),
            diagrams,
            phases: units.iter().map(|u| u.phase).collect(),
            cycle,
        })
    }

    /// F of unit j at its cycle angle θ, each end's piece looked for first where `hints`
    /// say (see [`PiecewisePolynomial::value_near`]).
    fn force(&self, j: usize, theta: f64, hints: &mut [usize; 2]) -> f64 {
        cylinder_force_near(&self.gas[j], &self.diagrams, theta, hints)
    }

    /// Every unit's force at every φ, unit-major (as `Dynamics::gas_torque` takes them):
    /// θ_j = (φ + α_j) mod Φ.
    pub fn at(&self, phi: &[f64]) -> Vec<f64> {
        let mut out = Vec::with_capacity(phi.len() * self.gas.len());
        for (j, phase) in self.phases.iter().enumerate() {
            let mut hints = [0, 0];
            out.extend(
                phi.iter()
                    .map(|p| self.force(j, periodic(p + phase, self.cycle), &mut hints)),
            );
        }
        out
    }
}

/// F = p(θ)·A − p_c(θ)·A_c (N) of one cylinder at its cycle angle θ, the pieces of its two
/// ends looked for first at `hints` (head, crank end) and left there: angles in increasing
/// order walk the pieces without a search, and any order gives the same doubles.
#[inline]
fn cylinder_force_near(
    cylinder: &GasCylinder,
    diagrams: &[PiecewisePolynomial],
    theta: f64,
    hints: &mut [usize; 2],
) -> f64 {
    if !cylinder.has_gas() {
        return 0.0;
    }
    let [head, crank_end] = hints;
    let head = cylinder.head.map(|d| diagrams[d].value_near(theta, head));
    let crank_end = cylinder
        .crank_end
        .map(|d| diagrams[d].value_near(theta, crank_end));
    cylinder.net_force(head, crank_end)
}

#[cfg(test)]
mod tests;
