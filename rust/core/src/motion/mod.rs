//! Steady running at a mean speed (docs/theory.md, "Steady running"): the periodic motion of
//! a machine under the "balance" load by the energy method, its coefficient of speed
//! fluctuation δ, and what gravity does to it.
//!
//! The rooms: `quadrature` (Gauss–Legendre panels over the cycle), `gas` (pressures as
//! periodic piecewise polynomials and the exact gas work), `drive` (a driving torque of φ
//! and its exact work), `cycle` (the machine's J, U and W
//! tabulated on the panels, and at any angle), `solution` (the one solver pattern: the
//! `PeriodicSolver` trait, which `balance` at a mean speed and `square_law` implement, and
//! the `Solution` every solve answers with — its status, message and evaluation counts), `extrema` (Brent's method, the extremes between samples and the graded
//! mesh), `balance` (the energy method), `square_law` (the square-law load in closed form),
//! `tables` (a machine's tables, shared by every steady state of it), `flywheel` (the shaft
//! inertia for a δ), and the motion sweep: `columns` (its vocabulary), `variant` (a design's
//! machine) and `sweep` (the driver, many variants of one machine, one row each). This file
//! holds the five entries (`steady_state`, `steady_state_curves`, `square_law_steady_state`,
//! `flywheel_inertia`, `square_law_flywheel_inertia`) and their results. J, J′, U and the torques are `Dynamics`'s.

mod balance;
mod columns;
mod cycle;
mod drive;
mod extrema;
mod flywheel;
mod frame_sweep;
mod gas;
mod interpolant;
mod margin;
mod orders;
mod quadrature;
mod solution;
mod square_law;
mod sweep;
mod tables;
mod variant;
mod webs;

use crate::error::{check, MechanismError, Result};
use crate::mechanism::PhysicalCylinder;
use crate::mechanism::{check_shaft_inertia, check_speed, Strokes};

use cycle::Cycle;
use solution::PeriodicSolver;
use square_law::SquareLaw;
use tables::state_of;

pub use columns::{MachineDesigns, MotionColumns, MotionOutputs, UnitColumn, UnitField};
pub use flywheel::size_shaft_inertia;
pub(crate) use frame_sweep::frame_sweep;
pub use frame_sweep::{default_angles, FrameOutputs, BEARING_ANGLES, FRAME_OUTPUTS};
pub(crate) use gas::Forces as GasForces;
pub use gas::{net_piston_forces, GasCylinder, PiecewisePolynomial};
pub use orders::{torque_orders, TorqueOrders};
pub use sweep::motion_sweep;
pub use tables::{CycleArrays, SolvedSteadyState, SteadyTables};

/// A machine as its motion takes it (SI units): a [`Machine`](crate::Machine)'s own
/// ([`Machine::view`](crate::Machine::view)), or a design's machine in a sweep.
#[derive(Debug, Clone, Copy)]
pub struct MachineView<'a> {
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

impl MachineView<'_> {
    /// The rules of its gas (`gas::check_gas`).
    pub(crate) fn check_gas(&self) -> Result<()> {
        gas::check_gas(
            self.units,
            self.gas,
            self.diagrams,
            self.strokes.cycle_angle(),
        )
    }

    /// Every unit's gas force F = p·A − p_c·A_c (N, toward the shaft) at every φ (rad),
    /// unit-major (units × phi), from the machine's own diagrams.
    pub fn piston_forces(&self, phi: &[f64]) -> Result<Vec<f64>> {
        Ok(self.gas_forces()?.at(phi))
    }

    /// The rule of its gas forces (its diagrams copied into it).
    pub(crate) fn gas_forces(&self) -> Result<gas::Forces> {
        gas::Forces::new(
            self.units,
            self.gas,
            self.diagrams.into(),
            self.strokes.cycle_angle(),
        )
    }
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
    /// δ of the machine coasting: gas, drive and load removed, gravity and the variation of J
    /// alone, at the same mean speed; NaN where it would stall.
    pub delta_coasting: f64,
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

/// Where a machine with no mean driving torque comes to rest: the sample (node or edge)
/// where the work of gas, drive and gravity from φ = 0, W + M_drive·φ − (U − U(0)), is
/// largest — the bottom of the well of their potential (for a machine without gas or
/// drive, the lowest potential energy): the angle a square-law stall reports.
fn rest_angle(cycle: &Cycle, drive: f64) -> f64 {
    let angles = cycle.panels.phi.iter().chain(&cycle.panels.edges);
    let mut best = (0.0, f64::NEG_INFINITY);
    for ((phi, w), u) in angles.zip(&cycle.work).zip(&cycle.potential) {
        let work = w + drive * phi - u;
        if work > best.1 {
            best = (*phi, work);
        }
    }
    best.0.rem_euclid(cycle.cycle())
}

/// The periodic steady state of `machine` under the "balance" load at the mean speed
/// `omega_mean` ω_m (rad/s, a time mean; within [`SPEED_LIMITS`]), by the energy method (docs/theory.md, "Steady
/// running"). `min_speed_ratio`: the machine stalls when ω_min < min_speed_ratio·ω_m
/// (1e-3 in the Python API).
///
/// Near stall the time quadrature is graded geometrically towards the speed minimum
/// (docs/theory.md, "How the integrals are taken"), so that the answer holds down to the
/// lowest speed that runs.
///
/// Errors: bad input, naming the parameter; [`MechanismError::Stall`] when the machine
/// cannot keep that mean speed, with the lowest mean speed that runs (`min_omega`).
///
/// [`SPEED_LIMITS`]: crate::mechanism::SPEED_LIMITS
pub fn steady_state(
    machine: &MachineView<'_>,
    omega_mean: f64,
    min_speed_ratio: f64,
) -> Result<SteadyState> {
    Ok(steady_state_curves(machine, omega_mean, min_speed_ratio, &[])?.state)
}

/// A steady state with its speed and time at requested angles.
#[derive(Debug, Clone, PartialEq)]
pub struct SteadyCurves {
    /// The numbers, as [`steady_state`] gives them.
    pub state: SteadyState,
    /// ω(φ_i) (rad/s): √(2E/J) with E(φ) = E(0) + K(φ) evaluated exactly at φ_i.
    pub omega: Vec<f64>,
    /// t(φ_i) (s), the time from φ = 0: ∫₀^φ dφ/ω with each panel's interpolant of 1/ω
    /// through the time mesh's nodes integrated exactly. t(0) = 0 and t(Φ) = `period` to
    /// rounding (the Python API's `SteadyState` sets both exactly).
    pub time: Vec<f64>,
    /// How the solve ended, SciPy's convention: 0 converged (a stall is an error, never a
    /// result).
    pub status: i32,
    /// What happened, in words.
    pub message: &'static str,
    /// Evaluations of the function whose root is found (the energy method: the mean speed
    /// as a function of the margin s, each a quadrature of the period); 0 for the closed
    /// form of the square law, which finds no root.
    pub nfev: usize,
    /// Of those, the root finder's (Brent's method's) own.
    pub nit: usize,
}

/// [`steady_state`], with ω (rad/s) and t (s, from φ = 0) of the solution at the angles
/// `phi` (rad, each in [0, Φ]): the arrays of the Python API's `SteadyState` (its `points`
/// angles are `linspace(0, Φ, points)`).
///
/// Errors: as [`steady_state`]; an angle outside [0, Φ] (or not finite), naming `phi`.
pub fn steady_state_curves(
    machine: &MachineView<'_>,
    omega_mean: f64,
    min_speed_ratio: f64,
    phi: &[f64],
) -> Result<SteadyCurves> {
    check_shaft_inertia(machine.shaft_inertia)?;
    check_speed("omega_mean", omega_mean)?;
    SteadyTables::new(machine)?.steady_state(
        machine.shaft_inertia,
        omega_mean,
        min_speed_ratio,
        phi,
        true,
    )
}

/// The periodic steady state of `machine` under a square-law load M = c·ω² (c =
/// `coefficient`, N·m·s²/rad²: a PowerLawLoad of exponent 2, c = M_n/ω_n²) beside a constant
/// `drive` (N·m), in closed form (docs/theory.md, "Three ways to the periodic solution"):
/// the mean speed is a result. With ω (rad/s) and t (s) at
/// `phi` (rad, in [0, Φ]) as [`steady_state_curves`] gives them.
///
/// In the [`SteadyState`]: `mean_load_torque` is the load's cycle mean (1/Φ)∫cω² dφ;
/// `energy_at_zero` E₀; `delta_without_gravity` the same load and drive with g = 0 and
/// `delta_coasting` that of the machine coasting (gas, drive and load removed: gravity and
/// J(φ)'s variation alone) at the mean speed found, each NaN where it stalls.
///
/// Errors: bad input, naming the parameter; a drive whose cycle mean with the gas torque is
/// not positive (`drive`: nothing to balance); a load damping more than 700 e-folds of E per
/// cycle (`load`); [`MechanismError::Stall`] (its `omega_mean` NaN: none was asked for,
/// `min_omega` none) where E would reach zero or ω_min < `min_speed_ratio`·ω_m.
pub fn square_law_steady_state(
    machine: &MachineView<'_>,
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
            omega_mean: f64::NAN,
            min_omega: None,
        });
    }
    let inertia = machine.shaft_inertia;
    let found =
        SquareLaw::new(cycle, coefficient, drive).solve(inertia, min_speed_ratio, Some(phi))?;
    let (Some(solution), Some(curves)) = (found.periodic, found.curves) else {
        return Err(MechanismError::Stall {
            angle: found
                .stall_angle
                .unwrap_or(f64::NAN)
                .rem_euclid(cycle.cycle()),
            omega_mean: f64::NAN,
            min_omega: None,
        });
    };
    let delta_without_gravity = if cycle.gravity_on {
        let without = cycle.without_gravity();
        SquareLaw::new(&without, coefficient, drive)
            .solve(inertia, min_speed_ratio, None)?
            .delta_or_nan()
    } else {
        solution.delta()
    };
    let delta_coasting =
        tables.delta_coasting(machine.shaft_inertia, solution.omega_mean, min_speed_ratio)?;
    Ok(SteadyCurves {
        state: state_of(
            &solution,
            found.mean_load,
            delta_without_gravity,
            delta_coasting,
        ),
        omega: curves.omega,
        time: curves.time,
        status: found.status.code(),
        message: found.message,
        nfev: found.nfev,
        nit: found.nit,
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
    /// The mean speed ω_m (rad/s).
    pub omega_mean: f64,
}

/// The shaft inertia I_w (kg·m²) that gives `machine` (its own `shaft_inertia` replaced)
/// the coefficient of speed fluctuation `delta` (≥ 1e-9) at the mean speed `omega_mean` (rad/s),
/// the "balance" load: Brent's method on log I_w over exact steady states, δ falling as I_w
/// grows (docs/theory.md, "The flywheel"). `min_speed_ratio` as for
/// [`steady_state`]. The cycle's tables are made once: a trial I_w only changes J = I_w +
/// (J − I_w).
///
/// Errors: bad input, naming the parameter; `delta` unreachable (the machine stalls before
/// its fluctuation grows that large, or the rods' own inertia keeps it below).
pub fn flywheel_inertia(
    machine: &MachineView<'_>,
    delta: f64,
    omega_mean: f64,
    min_speed_ratio: f64,
) -> Result<FlywheelInertia> {
    flywheel::check_delta(delta)?;
    check_shaft_inertia(machine.shaft_inertia)?;
    check_speed("omega_mean", omega_mean)?;
    check_speed_ratio(min_speed_ratio)?;
    SteadyTables::new(machine)?.flywheel_inertia(
        delta,
        omega_mean,
        min_speed_ratio,
        machine.shaft_inertia,
        true,
    )
}

/// The shaft inertia I_w (kg·m²) that gives `machine` (its own `shaft_inertia` replaced)
/// the coefficient of speed fluctuation `delta` (≥ 1e-9) under a square-law load M = c·ω²
/// (c = `coefficient`, N·m·s²/rad²) beside a constant `drive` (N·m): the mean speed is a
/// result of each trial shaft (the closed form of [`square_law_steady_state`]), and the
/// one search of [`flywheel_inertia`] finds the root. `omega_mean` is the mean speed (rad/s) reached with
/// the shaft found, the textbook estimate taken there. `min_speed_ratio` as for
/// [`steady_state`].
///
/// Errors: bad input, naming the parameter; `delta` unreachable (the machine stalls at any
/// shaft, or before its fluctuation grows that large, or the rods' own inertia keeps it
/// below).
pub fn square_law_flywheel_inertia(
    machine: &MachineView<'_>,
    coefficient: f64,
    drive: f64,
    delta: f64,
    min_speed_ratio: f64,
) -> Result<FlywheelInertia> {
    check_shaft_inertia(machine.shaft_inertia)?;
    SteadyTables::new(machine)?.square_law_flywheel_inertia(
        coefficient,
        drive,
        delta,
        min_speed_ratio,
        machine.shaft_inertia,
    )
}
