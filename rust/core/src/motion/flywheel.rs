//! The flywheel for a coefficient of speed fluctuation (docs/theory.md, "Flywheel"): the
//! shaft inertia I_w whose steady state under the "balance" load has the δ asked for, by
//! Brent's method on log I_w over exact steady states, with the textbook estimate
//! ΔE/(δω_m²) − mean(J − I_w) as the start. Trial inertias reuse the cycle's tables
//! (`Balance::with_inertia`): J − I_w, U and W do not depend on I_w. The root search
//! ([`size_shaft_inertia`]) is every flywheel's, the Python API's over its shot steady
//! states included.

use crate::error::{check, MechanismError, Reach, Result};
use crate::mechanism::check_shaft_inertia;

use super::cycle::Cycle;
use super::extrema::{brent, brent_from};
use super::solution::PeriodicSolver;
use super::square_law::SquareLaw;
use super::{check_speed_ratio, FlywheelInertia};

/// The shaft inertia that gives a machine the coefficient of speed fluctuation `delta`
/// under a square-law load c·ω² (c = `coefficient`, N·m·s²/rad²) beside a constant `drive`
/// (N·m), on the machine's `cycle` (its tables', with their "balance" load `balance`, N·m,
/// and `textbook`, ΔE and the textbook I_w at a mean speed as
/// [`SteadyTables::textbook_flywheel`](super::SteadyTables::textbook_flywheel) gives them; its
/// own I_w `fallback`): the mean speed is a result,
/// so each trial I_w's δ comes from its own closed-form steady state; [`inertia_for`] finds
/// the root (docs/theory.md, "The flywheel"). The textbook estimate is taken at the mean
/// speed reached (its `omega_mean`), where the constant drive and the load at that speed leave the
/// turning-moment diagram of "balance".
///
/// Errors: bad input, naming the parameter; `delta` unreachable (the machine stalls at any
/// shaft inertia, or before its fluctuation grows that large, or the rods' own inertia
/// keeps δ below it).
#[allow(clippy::too_many_arguments)]
pub(crate) fn square_law_inertia(
    cycle: &Cycle,
    balance: f64,
    textbook: impl Fn(f64) -> Result<(f64, f64)>,
    coefficient: f64,
    drive: f64,
    delta: f64,
    ratio: f64,
    fallback: f64,
) -> Result<FlywheelInertia> {
    check_delta(delta)?;
    check("load", coefficient, "a square-law coefficient > 0", |c| {
        c > 0.0
    })?;
    check("drive", drive, "a finite constant drive", |_| true)?;
    check_speed_ratio(ratio)?;
    check_shaft_inertia(fallback)?;
    let mean = balance + drive;
    if mean.is_nan() || mean <= 0.0 {
        // Nothing drives the machine on the cycle's mean: it stalls at any shaft inertia.
        return Err(MechanismError::Unreachable {
            delta,
            reach: Reach::Stalls,
            closest: f64::NAN,
        });
    }
    let law = SquareLaw::new(cycle, coefficient, drive);
    // The mean speed with a shaft (`None`: it stalls, or so light that more than 700 e-folds
    // of E are damped per cycle and it stops at once).
    let speed = |inertia: f64| -> Result<Option<f64>> {
        Ok(match law.solve(inertia, ratio, None) {
            Err(MechanismError::OutOfRange { .. }) => None,
            Err(error) => return Err(error),
            Ok(found) => found.periodic.map(|p| p.omega_mean),
        })
    };
    // The mean speed with the machine's own shaft, or where the mean torques balance.
    let first = speed(fallback)?.unwrap_or((mean / coefficient).sqrt());
    let (swing, estimate) = textbook(first)?;
    let start = self::start(swing, estimate, cycle, delta, first, fallback);
    let rest = cycle.mean_rest();
    let inertia = inertia_for(&law, ratio, rest, delta, start)?;
    let reached = speed(inertia)?.unwrap_or(first);
    let (swing, estimate) = textbook(reached)?;
    let without = if cycle.gravity_on {
        let without = cycle.without_gravity();
        let law = SquareLaw::new(&without, coefficient, drive);
        inertia_for(&law, ratio, rest, delta, inertia).unwrap_or(f64::NAN)
    } else {
        inertia
    };
    Ok(FlywheelInertia::sized(
        inertia,
        without,
        (swing, estimate),
        delta,
        reached,
    ))
}

impl FlywheelInertia {
    /// The flywheel found: I_w = `shaft_inertia` (kg·m²) for `delta` at ω_m = `omega_mean`
    /// (rad/s), the g = 0 machine's `shaft_inertia_without_gravity`, and the textbook
    /// estimate's ΔE (J) and I_w (kg·m²) as
    /// [`SteadyTables::textbook_flywheel`](super::SteadyTables::textbook_flywheel) gives them,
    /// with its relative error (textbook − I_w)/I_w.
    pub(crate) fn sized(
        shaft_inertia: f64,
        shaft_inertia_without_gravity: f64,
        (energy_swing, textbook): (f64, f64),
        delta: f64,
        omega_mean: f64,
    ) -> Self {
        Self {
            shaft_inertia,
            shaft_inertia_without_gravity,
            textbook,
            textbook_error: (textbook - shaft_inertia) / shaft_inertia,
            energy_swing,
            delta,
            omega_mean,
        }
    }
}

/// The smallest δ a flywheel is sized for: below it δ is within the rounding of the speeds
/// it is found from.
pub(crate) const SMALLEST_DELTA: f64 = 1e-9;

/// A target δ, as every flywheel takes it: ≥ 1e-9.
pub(crate) fn check_delta(value: f64) -> Result<f64> {
    check("delta", value, "delta >= 1e-9", |d| d >= SMALLEST_DELTA)
}

/// The steps (in log I_w) that widen the bracket from the estimate outwards: the estimate
/// is near for a machine of small δ and ~10 % off for a compressor at δ ≈ 1/30; the first
/// steps cover both, then ×4 each.
fn bracket_steps() -> impl Iterator<Item = f64> {
    [0.05, 0.2, 0.7]
        .into_iter()
        .chain(std::iter::repeat_n(4f64.ln(), 100))
}

/// The shaft inertia I_w (kg·m²) with δ(I_w) = `delta`: the flywheel's one root search,
/// for any steady-state solver, the core's own (its flywheels under "balance" and the
/// square law) or one outside it (the Python API's shooting, for loads given as callables).
/// `delta_at(I_w)` is δ of the steady state with that shaft inertia, `None` where the
/// machine stalls (counted as δ = ∞); δ must fall as I_w grows. `rest`: mean(J − I_w) (kg·m², the rods' and pistons' share of J; a
/// negative one counts as 0), which shapes the first steps; `start` (kg·m², > 0): the
/// estimate to bracket from, e.g. the textbook ΔE/(δω_m²) − `rest`.
///
/// The search (docs/theory.md, "The flywheel"): a Newton step from `start` with the slope
/// that δ ∝ 1/(I_w + `rest`) gives and two secant steps bracket the root where δ behaves
/// as usual; else a shaft a billionth of `rest` is tried (δ of a massless shaft), then the
/// bracket widens from `start` in growing steps, a stall on its light side is bisected to
/// the lightest shaft that runs, and Brent's method on log(δ/`delta`) in log I_w ends it
/// (to 1e-12 absolute and 1e-15 relative in log I_w). Each I_w is asked once.
///
/// Errors: bad input, naming the parameter; `delta` unreachable
/// ([`MechanismError::Unreachable`]: the machine stalls before its fluctuation grows that
/// large, or even a massless shaft keeps δ below it, or δ never falls that low); an error
/// of `delta_at`, unchanged (it ends the search at once).
pub fn size_shaft_inertia(
    delta_at: impl FnMut(f64) -> Result<Option<f64>>,
    rest: f64,
    delta: f64,
    start: f64,
) -> Result<f64> {
    check_delta(delta)?;
    check("rest", rest, "a finite mean(J - I_w)", |_| true)?;
    check("start", start, "a shaft inertia > 0 to start from", |s| {
        s > 0.0
    })?;
    search(delta_at, rest, delta, start)
}

/// [`size_shaft_inertia`] over `solver`'s steady states with the stall ratio `ratio`
/// ([`PeriodicSolver::delta_at`]; the same search for every load), its input the core's
/// own (unchecked: a `start` ≤ 0 is taken as 1e-300).
///
/// Errors: as [`size_shaft_inertia`]'s; those of the solver.
pub(crate) fn inertia_for(
    solver: &impl PeriodicSolver,
    ratio: f64,
    rest: f64,
    delta: f64,
    start: f64,
) -> Result<f64> {
    search(
        |inertia| solver.delta_at(inertia, ratio),
        rest,
        delta,
        start,
    )
}

/// The search of [`size_shaft_inertia`], on input already checked.
fn search(
    mut delta_at: impl FnMut(f64) -> Result<Option<f64>>,
    rest: f64,
    delta: f64,
    start: f64,
) -> Result<f64> {
    // `excess` is log(δ/delta): the δ it was found for is delta·e^excess.
    let unreachable = |reach: Reach, excess: f64| MechanismError::Unreachable {
        delta,
        reach,
        closest: delta * excess.exp(),
    };
    let mut known: Vec<(f64, f64)> = Vec::new();
    // log(δ(I_w)/delta), +∞ where the machine stalls; each I_w solved once.
    let mut excess = |log_inertia: f64| -> Result<f64> {
        if let Some(&(_, value)) = known.iter().find(|(x, _)| *x == log_inertia) {
            return Ok(value);
        }
        let value = match delta_at(log_inertia.exp())? {
            Some(found) if found > 0.0 => (found / delta).ln(),
            // A flywheel so heavy that δ rounds to 0 is beyond the target.
            Some(_) => f64::NEG_INFINITY,
            None => f64::INFINITY,
        };
        known.push((log_inertia, value));
        Ok(value)
    };
    let origin = start.max(1e-300).ln();
    if let Some(root) = newton_bracket(&mut excess, origin, rest)? {
        return Ok(root.exp());
    }
    // δ rises as I_w falls, towards δ of a massless shaft: where a shaft a billionth of the
    // rods' and pistons' inertia still runs below the target, no shaft reaches it (one
    // solve, where stepping down until δ levels off takes a dozen).
    let massless = (1e-9 * rest).max(1e-300).ln();
    if excess(origin)? <= 0.0 && massless < origin {
        let at_floor = excess(massless)?;
        if at_floor.is_finite() && at_floor < 0.0 {
            return Err(unreachable(Reach::Massless, at_floor));
        }
    }
    let (mut low, mut high) = (origin, origin);
    if excess(origin)? > 0.0 {
        let mut found = false;
        for step in bracket_steps() {
            (low, high) = (high, high + step);
            if excess(high)? <= 0.0 {
                found = true;
                break;
            }
        }
        if !found {
            return Err(unreachable(Reach::NeverFalls, f64::NAN));
        }
    } else {
        let mut found = false;
        for step in bracket_steps() {
            (high, low) = (low, low - step);
            if excess(low)? > 0.0 {
                found = true;
                break;
            }
            // δ(I_w) levels off as I_w → 0 (the rods' and pistons' inertia remains).
            if low < origin - 60.0 || (excess(low)? - excess(high)?).abs() < 1e-9 {
                break;
            }
        }
        if !found {
            return Err(unreachable(Reach::Massless, excess(low)?));
        }
    }
    // A stall on the low side is +∞: the low end moves to the lightest shaft that still
    // runs (bisection); a target beyond it is unreachable.
    if excess(low)?.is_infinite() {
        let mut running = high;
        for _ in 0..40 {
            let middle = 0.5 * (low + running);
            if excess(middle)?.is_infinite() {
                low = middle;
            } else {
                running = middle;
            }
        }
        let at_running = excess(running)?;
        if at_running < 0.0 {
            return Err(unreachable(Reach::Stalls, at_running));
        }
        low = running;
    }
    match brent(&mut excess, low, high, 1e-12, 1e-15)? {
        Some(log_inertia) => Ok(log_inertia.exp()),
        None => Err(unreachable(Reach::NeverFalls, f64::NAN)),
    }
}

/// The root of `excess` (log(δ/target) in x = log I_w) from `origin`, bracketed in four
/// evaluations where δ behaves as it does on a usual flywheel: δ ∝ 1/(I_w + mean(J − I_w))
/// gives the slope d log δ/d x ≈ −I_w/(I_w + `rest`) for a Newton step from the origin, a
/// secant step follows, and twice the next secant step beyond it brackets the root; then
/// Brent's method (as [`size_shaft_inertia`]'s) on that narrow bracket. `None` where the
/// bracket does not hold (a stall, a flat δ): the caller's wider search then takes over
/// (the values found are kept by `excess`).
fn newton_bracket(
    excess: &mut impl FnMut(f64) -> Result<f64>,
    origin: f64,
    rest: f64,
) -> Result<Option<f64>> {
    let slope = |x: f64| {
        let inertia = x.exp();
        -inertia / (inertia + rest.max(0.0))
    };
    let (x0, e0) = (origin, excess(origin)?);
    if !e0.is_finite() {
        return Ok(None);
    }
    let x1 = x0 - e0 / slope(x0);
    let e1 = excess(x1)?;
    if e1 == 0.0 {
        return Ok(Some(x1));
    }
    // The secant through (x0, e0) and (x1, e1), then the next: where they cannot be taken
    // (equal values, not finite) the bracket is given up.
    let secant = |(xa, ea): (f64, f64), (xb, eb): (f64, f64)| -(eb * (xb - xa)) / (eb - ea);
    let step = secant((x0, e0), (x1, e1));
    if !step.is_finite() {
        return Ok(None);
    }
    let x2 = x1 + step;
    let e2 = excess(x2)?;
    if e2 == 0.0 {
        return Ok(Some(x2));
    }
    let next = secant((x1, e1), (x2, e2));
    if !(e2.is_finite() && next.is_finite()) {
        return Ok(None);
    }
    let x3 = x2 + 2.0 * next + next.signum() * 1e-13;
    let e3 = excess(x3)?;
    if !(e3.is_finite() && e2 * e3 < 0.0) {
        return Ok(None);
    }
    // A step inside the bracket lands next to the root; δ falls as I_w grows, so the
    // root lies on the side the sign of the excess there says: one step of CERTIFY there
    // brackets it to within the tolerance (Brent's method would step blindly and may need
    // another solve).
    let (low, high) = (x2.min(x3), x2.max(x3));
    let quadratic = x1 * e2 * e3 / ((e1 - e2) * (e1 - e3))
        + x2 * e1 * e3 / ((e2 - e1) * (e2 - e3))
        + x3 * e1 * e2 / ((e3 - e1) * (e3 - e2));
    // Inverse quadratic interpolation through the last three (the secant where it leaves
    // the bracket).
    let x4 = if (low..=high).contains(&quadratic) {
        quadratic
    } else {
        x3 - e3 * (x3 - x2) / (e3 - e2)
    };
    let e4 = excess(x4)?;
    // The excess is a smooth function with the bracket's slope there: |e4/slope| is x4's
    // distance to the root, accepted well within the tolerance (δ's own rounding, ~1e-14
    // in the excess, cannot bring a worse x4 below that bar).
    let slope = (e3 - e2) / (x3 - x2);
    if e4.abs() <= 0.1 * CERTIFY * slope.abs() {
        return Ok(Some(x4));
    }
    if e4.is_finite() && (low..=high).contains(&x4) {
        let x5 = x4 + CERTIFY.copysign(e4);
        let e5 = excess(x5)?;
        if e4 * e5 <= 0.0 {
            return Ok(Some(x4));
        }
    }
    let (low, high) = if x2 < x3 {
        ((x2, e2), (x3, e3))
    } else {
        ((x3, e3), (x2, e2))
    };
    brent_from(excess, low, high, 1e-12, 1e-15)
}

/// A step (in log I_w) within the flywheel's tolerance of 1e-12: a sign change across it
/// puts the root within 1e-12 of its start.
const CERTIFY: f64 = 0.9e-12;

/// The textbook I_w (kg·m²) for `delta` at ω_m = `omega_mean` (rad/s) from ΔE = `swing` (J,
/// the swing of the turning-moment diagram's energy at ω_m, inertia torque included:
/// [`Balance::energy_swing`]): ΔE/(δω_m²) − mean(J − I_w), exact to first order in δ.
pub(crate) fn textbook(swing: f64, cycle: &Cycle, delta: f64, omega_mean: f64) -> f64 {
    swing / (delta * omega_mean * omega_mean) - cycle.mean_rest()
}

/// The start of the search: the textbook I_w where positive, else ΔE/(δω_m²), else the
/// larger of mean(J − I_w) and `fallback` (kg·m²).
pub(crate) fn start(
    swing: f64,
    textbook: f64,
    cycle: &Cycle,
    delta: f64,
    omega_mean: f64,
    fallback: f64,
) -> f64 {
    let start = if textbook > 0.0 {
        textbook
    } else {
        swing / (delta * omega_mean * omega_mean)
    };
    if start > 0.0 {
        start
    } else {
        cycle.mean_rest().max(fallback)
    }
}

#[cfg(test)]
mod tests;
