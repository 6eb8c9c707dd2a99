//! Steady running at a mean speed (docs/theory.md, "Steady running"): the periodic motion of
//! a machine under the "balance" load by the energy method, its coefficient of speed
//! fluctuation δ, and what gravity does to it.
//!
//! The rooms: `quadrature` (Gauss–Legendre panels over the cycle), `gas` (pressures as
//! periodic piecewise polynomials and the exact gas work), `cycle` (the machine's J, U and W
//! tabulated on the panels, and at any angle), `balance` (the energy method and Brent's
//! method), `flywheel` (the shaft inertia for a δ) and `sweep` (many variants of one machine,
//! one row each). J, J′, U and the torques are `Dynamics`'s.

mod balance;
mod columns;
mod cycle;
mod extrema;
mod flywheel;
mod gas;
mod quadrature;
mod square_law;
mod sweep;
mod variant;

use std::f64::consts::PI;
use std::sync::{Arc, OnceLock};

use crate::dynamics::{Dynamics, PhysicalCylinder};
use crate::error::{check, MechanismError, Result};
use crate::mechanism::{check_rpm, check_shaft_inertia, omega_from_rpm, Strokes};

use balance::{Balance, Periodic, Solved, Stall};
use cycle::{Cycle, Gas};
use square_law::SquareLaw;

pub use columns::{DesignColumns, MotionColumns, MotionOutputs, UnitColumn, UnitField};
pub use gas::{GasCylinder, PiecewisePolynomial};
pub use sweep::motion_sweep;

/// A machine as the steady state takes it (SI units).
#[derive(Debug, Clone, Copy)]
pub struct Machine<'a> {
    /// The slider-crank units.
    pub units: &'a [PhysicalCylinder],
    /// Their gas, one per unit ([`GasCylinder::NONE`] where there is none).
    pub gas: &'a [GasCylinder],
    /// The pressures (Pa) the units' `head` and `crank_end` refer to, each periodic over the
    /// working cycle.
    pub diagrams: &'a [PiecewisePolynomial],
    /// I_w (kg·m²): everything that turns rigidly with the shaft.
    pub shaft_inertia: f64,
    pub strokes: Strokes,
    /// g (m/s²) (0: none).
    pub g: f64,
}

/// A machine's periodic steady running under the "balance" load (a constant load equal to
/// the cycle mean of the gas torque) at a given time-mean speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyState {
    /// ω_m = Φ/t_Φ (rad/s), as found (the one asked for, to rounding).
    pub omega_mean: f64,
    /// t_Φ (s), the time of one working cycle.
    pub period: f64,
    /// The extreme speeds (rad/s), located exactly (roots of the net torque).
    pub omega_max: f64,
    pub omega_min: f64,
    /// Where they occur, φ in [0, Φ) (rad).
    pub phi_max: f64,
    pub phi_min: f64,
    /// E(0) = ½J(0)ω(0)² (J): with K(φ), ω(φ)² = 2[E(0) + K(φ)]/J(φ) everywhere.
    pub energy_at_zero: f64,
    /// The constant load (N·m): (1/Φ)∫M_gas dφ (gravity's mean is zero).
    pub mean_load_torque: f64,
    /// δ = (ω_max − ω_min)/ω_m.
    pub delta: f64,
    /// (ω_max − ω_min)/((ω_max + ω_min)/2), the textbook convention.
    pub delta_midrange: f64,
    /// δ of the same machine and load rule with g = 0, at the same mean speed; NaN where
    /// that machine would stall.
    pub delta_without_gravity: f64,
    /// δ with gas and load removed, gravity (and the variation of J) alone, at the same mean
    /// speed; NaN where it would stall.
    pub delta_gravity_only: f64,
}

/// The constant "balance" load (N·m): the cycle mean of the gas torque, W(Φ)/Φ.
fn balance_load(cycle: &Cycle) -> f64 {
    cycle.gas.work.per_cycle / cycle.cycle()
}

/// δ of a solution, NaN where it stalls.
fn delta_or_nan(found: Solved) -> f64 {
    found.map_or(f64::NAN, |p| p.delta())
}

/// The lowest ratio ω_min/ω_m accepted for `min_speed_ratio`: below it the crawl over a dead
/// centre takes longer than any run (and 1/ratio² leaves the range of a double on the way).
const SMALLEST_SPEED_RATIO: f64 = 1e-9;

/// `min_speed_ratio`, as every solve takes it: 1e-9 ≤ ratio < 1.
fn check_speed_ratio(value: f64) -> Result<f64> {
    check(
        "min_speed_ratio",
        value,
        "1e-9 <= min_speed_ratio < 1",
        |r| (SMALLEST_SPEED_RATIO..1.0).contains(&r),
    )
}

/// A machine's working cycle tabulated once for every steady state of it under the
/// "balance" load, whatever the shaft inertia I_w and the mean speed: J − I_w, U, the gas
/// work W and the torques' slopes on the cycle's panels, and the energy method's set-up with
/// gravity, with g = 0 and of gravity alone (none of them depends on I_w or the speed).
/// What `MotionMachine` keeps in Python, and what a motion sweep shares between designs
/// that differ only in I_w and speed. Immutable; every solve works on its own copy.
#[derive(Debug, Clone)]
pub struct SteadyTables {
    cycle: Arc<Cycle>,
    /// The "balance" load (N·m).
    load: f64,
    /// The machine as it is; with g = 0 (`None` when g = 0 already); gravity alone.
    machine: Balance,
    without_gravity: Option<Balance>,
    gravity_only: Balance,
    /// (ω_m, ΔE) of the textbook estimate at the first mean speed asked for (ΔE does not
    /// depend on I_w; a sweep sizes many flywheels at one speed).
    swing: OnceLock<(f64, f64)>,
}

/// The lowest mean speed that runs, searched from an s known to stall (the Python
/// implementation's `_stall_error`).
fn stall_error(balance: &Balance, stall: Stall, rpm: f64, ratio: f64) -> Result<MechanismError> {
    let above = 1e-6 * balance.swing();
    let lowest = balance.clone().lowest_running_speed(ratio, above)?;
    let min_rpm = if lowest.is_finite() {
        Some(running_rpm(balance, 30.0 * lowest / PI, ratio)?)
    } else {
        None
    };
    Ok(MechanismError::Stall {
        angle: stall.angle.rem_euclid(balance.cycle()),
        rpm,
        min_rpm,
    })
}

/// `rpm` (1/min), nudged up until the steady state asked for at it runs: min_rpm is a
/// speed that runs (the threshold's root, the round trip through rpm and the solve's own
/// root in s each round by ~1e-15), within a few ulps of the threshold. Each trial solves
/// on a fresh copy of `balance`, as [`SteadyTables::steady_state`] does (a copy that has
/// located its minima already rounds differently).
fn running_rpm(balance: &Balance, rpm: f64, ratio: f64) -> Result<f64> {
    let mut found = rpm;
    let mut step = 4.0 * f64::EPSILON;
    for _ in 0..64 {
        if balance.clone().solve(omega_from_rpm(found), ratio)?.is_ok() {
            return Ok(found);
        }
        found = rpm * (1.0 + step);
        step *= 2.0;
    }
    Ok(found)
}

impl SteadyTables {
    /// The tables of `machine` (its units, gas and g checked, naming the parameter).
    pub fn new(machine: &Machine<'_>) -> Result<Self> {
        Self::from_cycle(Cycle::new(
            machine,
            Dynamics::new(machine.units, machine.g)?,
        )?)
    }

    /// The tables of `machine` whose gas is `gas` (a sweep's, shared by its designs that
    /// differ only in masses, g, I_w or speed).
    pub(crate) fn with_gas(machine: &Machine<'_>, gas: &Arc<Gas>) -> Result<Self> {
        let dynamics = Dynamics::new(machine.units, machine.g)?;
        Self::from_cycle(Cycle::with_gas(machine, dynamics, gas)?)
    }

    fn from_cycle(cycle: Cycle) -> Result<Self> {
        let cycle = Arc::new(cycle);
        let load = balance_load(&cycle);
        let without_gravity = if cycle.gravity_on {
            Some(Balance::new(
                &Arc::new(cycle.without_gravity()),
                load,
                true,
            )?)
        } else {
            None
        };
        Ok(Self {
            machine: Balance::new(&cycle, load, true)?,
            gravity_only: Balance::new(&cycle, 0.0, false)?,
            without_gravity,
            load,
            cycle,
            swing: OnceLock::new(),
        })
    }

    /// ΔE (J) of the textbook flywheel estimate at the mean speed `omega_mean` (rad/s): the
    /// swing of ∫(M_gas − U′ − M_load − ½J′ω_m²) dφ, the load balancing the gas
    /// ([`Balance::energy_swing`]).
    fn energy_swing(&self, omega_mean: f64) -> Result<f64> {
        if let Some(&(omega, swing)) = self.swing.get() {
            if omega == omega_mean {
                return Ok(swing);
            }
        }
        let swing = self.machine.energy_swing(omega_mean)?;
        let _ = self.swing.set((omega_mean, swing));
        Ok(swing)
    }

    /// Φ (rad).
    pub fn cycle(&self) -> f64 {
        self.cycle.cycle()
    }

    /// The "balance" load (N·m): the cycle mean of the gas torque.
    pub fn load(&self) -> f64 {
        self.load
    }

    /// The periodic steady state with I_w = `shaft_inertia` (kg·m²) at the mean speed `rpm`
    /// (1/min), as [`steady_state_curves`] gives it, with ω and t at `phi` (rad, each in
    /// [0, Φ]; none: no curves). `compare`: whether δ without gravity and of gravity alone
    /// are solved too (else NaN, and two solves saved).
    ///
    /// Errors: bad input, naming the parameter; [`MechanismError::Stall`] with the lowest
    /// mean speed that runs.
    pub fn steady_state(
        &self,
        shaft_inertia: f64,
        rpm: f64,
        min_speed_ratio: f64,
        phi: &[f64],
        compare: bool,
    ) -> Result<SteadyCurves> {
        check_shaft_inertia(shaft_inertia)?;
        check_rpm(rpm)?;
        check_speed_ratio(min_speed_ratio)?;
        let cycle = self.cycle();
        for &angle in phi {
            check("phi", angle, "0 <= phi <= cycle angle", |a| {
                (0.0..=cycle).contains(&a)
            })?;
        }
        let omega_mean = omega_from_rpm(rpm);
        let balance = self.machine.with_inertia(shaft_inertia);
        let (solution, curves) =
            match balance
                .clone()
                .solve_with_curves(omega_mean, min_speed_ratio, phi)?
            {
                Ok(found) => found,
                Err(stall) => return Err(stall_error(&balance, stall, rpm, min_speed_ratio)?),
            };
        let mut state = state_of(&solution, self.load, f64::NAN, f64::NAN);
        if compare {
            (state.delta_without_gravity, state.delta_gravity_only) = self.comparisons(
                shaft_inertia,
                rpm,
                state.delta,
                state.omega_mean,
                min_speed_ratio,
            )?;
        }
        Ok(SteadyCurves {
            state,
            omega: curves.omega,
            time: curves.time,
        })
    }

    /// (δ without gravity, δ of gravity alone) of a steady state found by
    /// [`SteadyTables::steady_state`] with I_w = `shaft_inertia` at `rpm` (its `delta` and
    /// `omega_mean`, rad/s): the two comparison solves it skips without `compare` — δ₀ at the
    /// speed asked for (δ itself without gravity), δ of gravity alone at the mean speed
    /// found; each NaN where it stalls.
    pub fn comparisons(
        &self,
        shaft_inertia: f64,
        rpm: f64,
        delta: f64,
        omega_mean: f64,
        min_speed_ratio: f64,
    ) -> Result<(f64, f64)> {
        check_shaft_inertia(shaft_inertia)?;
        check_rpm(rpm)?;
        check_speed_ratio(min_speed_ratio)?;
        let without = self
            .delta_without_gravity(shaft_inertia, omega_from_rpm(rpm), min_speed_ratio)?
            .unwrap_or(delta);
        let alone = self.delta_gravity_only(shaft_inertia, omega_mean, min_speed_ratio)?;
        Ok((without, alone))
    }

    /// The machine's own arrays at `phi` (rad, any angles) with I_w = `shaft_inertia`
    /// (kg·m²): J (kg·m²), J′ (kg·m²/rad), M_gas and the gravity torque −U′ (N·m), as the
    /// tables take them.
    pub fn arrays_at(&self, shaft_inertia: f64, phi: &[f64]) -> Result<CycleArrays> {
        check_shaft_inertia(shaft_inertia)?;
        let (mut reduced_inertia, slope) = self.cycle.inertia_at(phi)?;
        reduced_inertia
            .iter_mut()
            .for_each(|rest| *rest += shaft_inertia);
        Ok(CycleArrays {
            reduced_inertia,
            reduced_inertia_slope: slope,
            gas_torque: self.cycle.gas_torque_at(phi)?,
            gravity_torque: self.cycle.gravity_torque_at(phi)?,
        })
    }

    /// δ alone (NaN where the machine stalls) with I_w = `shaft_inertia` at ω_m =
    /// `omega_mean` (rad/s), and the solution: one solve, no curves.
    pub(crate) fn solve(&self, shaft_inertia: f64, omega_mean: f64, ratio: f64) -> Result<Solved> {
        self.machine
            .with_inertia(shaft_inertia)
            .solve(omega_mean, ratio)
    }

    /// δ of the machine with g = 0, the same load, at ω_m = `omega_mean` (rad/s), NaN where
    /// it stalls; `None` where the machine has no gravity (δ₀ is then δ).
    pub(crate) fn delta_without_gravity(
        &self,
        shaft_inertia: f64,
        omega_mean: f64,
        ratio: f64,
    ) -> Result<Option<f64>> {
        self.without_gravity
            .as_ref()
            .map(|balance| {
                Ok(delta_or_nan(
                    balance
                        .with_inertia(shaft_inertia)
                        .solve(omega_mean, ratio)?,
                ))
            })
            .transpose()
    }

    /// δ of gravity (and the variation of J) alone, gas and load removed, at ω_m =
    /// `omega_mean` (rad/s); NaN where it stalls.
    pub(crate) fn delta_gravity_only(
        &self,
        shaft_inertia: f64,
        omega_mean: f64,
        ratio: f64,
    ) -> Result<f64> {
        Ok(delta_or_nan(
            self.gravity_only
                .with_inertia(shaft_inertia)
                .solve(omega_mean, ratio)?,
        ))
    }

    /// The shaft inertia for the coefficient of speed fluctuation `delta` at `rpm`, as
    /// [`flywheel_inertia`] gives it; `fallback` (kg·m²): where the search starts when the
    /// textbook estimate is not positive. `without`: whether the g = 0 machine's is sized
    /// too (else NaN).
    pub fn flywheel_inertia(
        &self,
        delta: f64,
        rpm: f64,
        min_speed_ratio: f64,
        fallback: f64,
        without: bool,
    ) -> Result<FlywheelInertia> {
        flywheel::check_delta(delta)?;
        check_rpm(rpm)?;
        check_speed_ratio(min_speed_ratio)?;
        let omega_mean = omega_from_rpm(rpm);
        let balance = &self.machine;
        let swing = self.energy_swing(omega_mean)?;
        let textbook = flywheel::textbook(swing, &self.cycle, delta, omega_mean);
        let start = flywheel::start(swing, textbook, &self.cycle, delta, omega_mean, fallback);
        let inertia = flywheel::inertia_for(balance, omega_mean, min_speed_ratio, delta, start)?;
        let without = match (&self.without_gravity, without) {
            (_, false) => f64::NAN,
            (None, true) => inertia,
            (Some(balance), true) => {
                flywheel::inertia_for(balance, omega_mean, min_speed_ratio, delta, inertia)
                    .unwrap_or(f64::NAN)
            }
        };
        Ok(FlywheelInertia {
            shaft_inertia: inertia,
            shaft_inertia_without_gravity: without,
            textbook,
            textbook_error: (textbook - inertia) / inertia,
            energy_swing: swing,
            delta,
            rpm,
        })
    }
}

/// Where a machine with no mean driving torque comes to rest: the sample (node or edge)
/// where the work of gas, drive and gravity from φ = 0, W + M_drive·φ − (U − U(0)), is
/// largest — the bottom of the well of their potential (for a machine without gas or
/// drive, the lowest potential energy). The Python implementation's `rest_angle`.
fn rest_angle(cycle: &Cycle, drive: f64) -> f64 {
    let angles = cycle.panels.phi.iter().chain(&cycle.panels.edges);
    let mut best = (0.0, f64::NEG_INFINITY);
    for ((phi, w), u) in angles.zip(&cycle.gas_work).zip(&cycle.potential) {
        let work = w + drive * phi - u;
        if work > best.1 {
            best = (*phi, work);
        }
    }
    best.0.rem_euclid(cycle.cycle())
}

/// A machine's arrays over its cycle ([`SteadyTables::arrays_at`]).
#[derive(Debug, Clone, PartialEq)]
pub struct CycleArrays {
    /// J (kg·m²).
    pub reduced_inertia: Vec<f64>,
    /// J′ (kg·m²/rad).
    pub reduced_inertia_slope: Vec<f64>,
    /// M_gas (N·m).
    pub gas_torque: Vec<f64>,
    /// −U′ (N·m), 0 without gravity.
    pub gravity_torque: Vec<f64>,
}

/// A solution's numbers as a [`SteadyState`].
fn state_of(solution: &Periodic, load: f64, without: f64, alone: f64) -> SteadyState {
    SteadyState {
        omega_mean: solution.omega_mean,
        period: solution.period,
        omega_max: solution.omega_max,
        omega_min: solution.omega_min,
        phi_max: solution.phi_max,
        phi_min: solution.phi_min,
        energy_at_zero: solution.energy_at_zero,
        mean_load_torque: load,
        delta: solution.delta(),
        delta_midrange: 2.0 * (solution.omega_max - solution.omega_min)
            / (solution.omega_max + solution.omega_min),
        delta_without_gravity: without,
        delta_gravity_only: alone,
    }
}

/// The periodic steady state of `machine` under the "balance" load at the mean speed `rpm`
/// (1/min) (time mean, ω_m = π·rpm/30), by the energy method (docs/theory.md, "Steady
/// running"). `min_speed_ratio`: the machine stalls when ω_min < min_speed_ratio·ω_m
/// (1e-3 in the Python API).
///
/// Near stall the time quadrature is graded geometrically towards the speed minimum (the
/// Python implementation's `graded_mesh`), so that the answer holds down to the lowest speed
/// that runs.
///
/// Errors: bad input, naming the parameter; [`MechanismError::Stall`] when the machine
/// cannot keep that mean speed, with the lowest mean speed that runs (`min_rpm`).
pub fn steady_state(machine: &Machine<'_>, rpm: f64, min_speed_ratio: f64) -> Result<SteadyState> {
    Ok(steady_state_curves(machine, rpm, min_speed_ratio, &[])?.state)
}

/// A steady state with its speed and time at requested angles.
#[derive(Debug, Clone, PartialEq)]
pub struct SteadyCurves {
    /// The numbers, as [`steady_state`] gives them.
    pub state: SteadyState,
    /// ω(φ_i) (rad/s): √(2E/J) with E(φ) = E(0) + K(φ) evaluated exactly at φ_i (the
    /// Python implementation's `Periodic.omega_at`).
    pub omega: Vec<f64>,
    /// t(φ_i) (s), the time from φ = 0: ∫₀^φ dφ/ω with each panel's interpolant of 1/ω
    /// through the time mesh's nodes integrated exactly (its `Periodic.time_at`). t(0) = 0
    /// and t(Φ) = `period` to rounding (`SteadyState` in Python sets both exactly).
    pub time: Vec<f64>,
}

/// [`steady_state`], with ω (rad/s) and t (s, from φ = 0) of the solution at the angles
/// `phi` (rad, each in [0, Φ]): the arrays of the Python implementation's `SteadyState`
/// (its `points` angles are `linspace(0, Φ, points)`).
///
/// Errors: as [`steady_state`]; an angle outside [0, Φ] (or not finite), naming `phi`.
pub fn steady_state_curves(
    machine: &Machine<'_>,
    rpm: f64,
    min_speed_ratio: f64,
    phi: &[f64],
) -> Result<SteadyCurves> {
    check_shaft_inertia(machine.shaft_inertia)?;
    SteadyTables::new(machine)?.steady_state(machine.shaft_inertia, rpm, min_speed_ratio, phi, true)
}

/// The periodic steady state of `machine` under a square-law load M = c·ω² (c =
/// `coefficient`, N·m·s²/rad²: a PowerLawLoad of exponent 2, c = M_n/ω_n²) beside a constant
/// `drive` (N·m), in closed form (docs/theory.md, "Steady running"; the Python
/// implementation's `SquareLaw`): the mean speed is a result. With ω (rad/s) and t (s) at
/// `phi` (rad, in [0, Φ]) as [`steady_state_curves`] gives them.
///
/// In the [`SteadyState`]: `mean_load_torque` is the load's cycle mean (1/Φ)∫cω² dφ;
/// `energy_at_zero` E₀; `delta_without_gravity` the same load and drive with g = 0 and
/// `delta_gravity_only` gravity alone ("balance", gas and load removed) at the mean speed
/// found, each NaN where it stalls.
///
/// Errors: bad input, naming the parameter; a drive whose cycle mean with the gas torque is
/// not positive (`drive`: nothing to balance); a load damping more than 700 e-folds of E per
/// cycle (`load`); [`MechanismError::Stall`] (its `rpm` NaN: none was asked for, `min_rpm`
/// none) where E would reach zero or ω_min < `min_speed_ratio`·ω_m.
pub fn square_law_steady_state(
    machine: &Machine<'_>,
    coefficient: f64,
    drive: f64,
    min_speed_ratio: f64,
    phi: &[f64],
) -> Result<SteadyCurves> {
    check_shaft_inertia(machine.shaft_inertia)?;
    check("load", coefficient, "a square-law coefficient > 0", |c| {
        c > 0.0
    })?;
    check("drive", drive, "a finite constant drive", |_| true)?;
    check_speed_ratio(min_speed_ratio)?;
    let cycle_angle = machine.strokes.cycle_angle();
    for &angle in phi {
        check("phi", angle, "0 <= phi <= cycle angle", |a| {
            (0.0..=cycle_angle).contains(&a)
        })?;
    }
    let tables = SteadyTables::new(machine)?;
    let cycle = &tables.cycle;
    let mean = tables.load + drive;
    if mean.is_nan() || mean <= 0.0 {
        // Nothing drives the machine on the cycle's mean (a design without gas, or a drive
        // that takes what the gas gives): a square-law load brings it to rest, a stall like
        // any other (a sweep's row, not an error in the input).
        return Err(MechanismError::Stall {
            angle: rest_angle(cycle, drive),
            rpm: f64::NAN,
            min_rpm: None,
        });
    }
    let (solution, curves, mean_load) =
        match SquareLaw::new(cycle, coefficient, drive)?.solve(min_speed_ratio, phi)? {
            Ok(found) => found,
            Err(stall) => {
                return Err(MechanismError::Stall {
                    angle: stall.angle.rem_euclid(cycle.cycle()),
                    rpm: f64::NAN,
                    min_rpm: None,
                })
            }
        };
    let delta_without_gravity = if cycle.gravity_on {
        let without = cycle.without_gravity();
        SquareLaw::new(&without, coefficient, drive)?
            .solve(min_speed_ratio, &[])?
            .map_or(f64::NAN, |found| found.0.delta())
    } else {
        solution.delta()
    };
    let delta_gravity_only =
        tables.delta_gravity_only(machine.shaft_inertia, solution.omega_mean, min_speed_ratio)?;
    Ok(SteadyCurves {
        state: state_of(
            &solution,
            mean_load,
            delta_without_gravity,
            delta_gravity_only,
        ),
        omega: curves.omega,
        time: curves.time,
    })
}

/// The shaft inertia that gives a machine a coefficient of speed fluctuation δ under the
/// "balance" load (docs/theory.md, "Flywheel").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlywheelInertia {
    /// I_w (kg·m²) giving the time-mean δ asked for, to the steady state's accuracy (the
    /// root to 1e-12 in log I_w).
    pub shaft_inertia: f64,
    /// The same for the machine with g = 0 (equal to `shaft_inertia` without gravity); NaN
    /// where only gravity makes the machine fluctuate that much.
    pub shaft_inertia_without_gravity: f64,
    /// The textbook estimate ΔE/(δω_m²) − mean(J − I_w) (kg·m²).
    pub textbook: f64,
    /// (textbook − shaft_inertia)/shaft_inertia.
    pub textbook_error: f64,
    /// ΔE (J) of the textbook estimate: max − min of ∫(M_gas − U′ − M_load − ½J′ω_m²) dφ,
    /// every torque at the mean speed, the load balancing the gas.
    pub energy_swing: f64,
    /// The δ asked for.
    pub delta: f64,
    /// The mean speed (1/min).
    pub rpm: f64,
}

/// The shaft inertia I_w (kg·m²) that gives `machine` (its own `shaft_inertia` replaced)
/// the coefficient of speed fluctuation `delta` (≥ 1e-9) at the mean speed `rpm` (1/min),
/// the "balance" load: Brent's method on log I_w over exact steady states, δ falling as I_w
/// grows (the Python implementation's `flywheel_inertia`). `min_speed_ratio` as for
/// [`steady_state`]. The cycle's tables are made once: a trial I_w only changes J = I_w +
/// (J − I_w).
///
/// Errors: bad input, naming the parameter; `delta` unreachable (the machine stalls before
/// its fluctuation grows that large, or the rods' own inertia keeps it below).
pub fn flywheel_inertia(
    machine: &Machine<'_>,
    delta: f64,
    rpm: f64,
    min_speed_ratio: f64,
) -> Result<FlywheelInertia> {
    flywheel::check_delta(delta)?;
    check_shaft_inertia(machine.shaft_inertia)?;
    check_rpm(rpm)?;
    check_speed_ratio(min_speed_ratio)?;
    SteadyTables::new(machine)?.flywheel_inertia(
        delta,
        rpm,
        min_speed_ratio,
        machine.shaft_inertia,
        true,
    )
}
