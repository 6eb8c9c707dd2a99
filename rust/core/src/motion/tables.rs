//! The tables of a machine's working cycle for the "balance" load (`SteadyTables`), made once
//! and shared by every steady state and flywheel of that machine whatever its shaft inertia and
//! mean speed, and their solves: the steady state with its curves, the two comparison δ, the
//! lowest mean speed that runs (a stall's `min_omega`) and the flywheel for a δ.

use std::sync::{Arc, OnceLock};

use crate::dynamics::Dynamics;
use crate::error::{check, MechanismError, Result};
use crate::mechanism::{check_shaft_inertia, check_speed};

use super::balance::{Balance, SolvedBalance};
use super::cycle::{Cycle, Gas};
use super::drive::Drive;
use super::gas::PiecewisePolynomial;
use super::solution::{Periodic, PeriodicSolver, Solution};
use super::{check_speed_ratio, flywheel, FlywheelInertia, MachineView, SteadyCurves, SteadyState};

/// Every angle of `phi` in [0, Φ] (Φ = `cycle`, rad), else an error naming `phi`.
fn check_angles(phi: &[f64], cycle: f64) -> Result<()> {
    for &angle in phi {
        check("phi", angle, "0 <= phi <= cycle angle", |a| {
            (0.0..=cycle).contains(&a)
        })?;
    }
    Ok(())
}

/// A steady state under the "balance" load as its solve left it
/// ([`SteadyTables::solved_steady_state`]): ω and t at any angles, later, from the mesh and
/// margin it was solved on — the doubles [`SteadyTables::steady_state`] gives with those
/// angles.
#[derive(Debug, Clone)]
pub struct SolvedSteadyState {
    kept: SolvedBalance,
}

impl SolvedSteadyState {
    /// (ω(φ_i) (rad/s), t(φ_i) (s, from φ = 0)) at `phi` (rad, each in [0, Φ]), as
    /// [`SteadyCurves`] holds them.
    ///
    /// Errors: an angle outside [0, Φ] (or not finite), naming `phi`.
    pub fn curves(&self, phi: &[f64]) -> Result<(Vec<f64>, Vec<f64>)> {
        check_angles(phi, self.kept.cycle())?;
        self.kept_curves(phi)
    }

    /// `curves` of angles already checked.
    fn kept_curves(&self, phi: &[f64]) -> Result<(Vec<f64>, Vec<f64>)> {
        let curves = self.kept.curves(phi)?;
        Ok((curves.omega, curves.time))
    }
}

/// The constant "balance" load (N·m): the cycle mean of the gas torque, W(Φ)/Φ.
fn balance_load(cycle: &Cycle) -> f64 {
    cycle.work_per_cycle() / cycle.cycle()
}

/// A machine's working cycle tabulated once for every steady state of it under the
/// "balance" load, whatever the shaft inertia I_w and the mean speed: J − I_w, U, the gas
/// work W and the torques' slopes on the cycle's panels, and the energy method's set-up with
/// gravity, with g = 0 and coasting (gas and load removed): none of them depends on I_w or
/// the speed.
/// What the Python API's `MotionMachine` keeps, and what a motion sweep shares between designs
/// that differ only in I_w and speed. Immutable; every solve works on its own copy.
#[derive(Debug, Clone)]
pub struct SteadyTables {
    pub(super) cycle: Arc<Cycle>,
    /// The "balance" load (N·m).
    pub(super) load: f64,
    /// The machine as it is; with g = 0 (`None` when g = 0 already); coasting (gravity and
    /// J(φ)'s variation alone).
    machine: Balance,
    /// Both made on first use (a steady state without its comparisons needs neither).
    without_gravity: OnceLock<Option<Balance>>,
    coasting: OnceLock<Balance>,
    /// (ω_m, ΔE) of the textbook estimate at the first mean speed asked for (ΔE does not
    /// depend on I_w; a sweep sizes many flywheels at one speed).
    swing: OnceLock<(f64, f64)>,
}

/// The stall at `omega_mean` (rad/s) at φ = `angle` (rad) as [`MechanismError::Stall`],
/// with the lowest mean speed that runs (`min_omega`), searched from an s known to stall
/// (docs/theory.md, "Stall").
fn stall_error(
    balance: &Balance,
    angle: f64,
    omega_mean: f64,
    ratio: f64,
) -> Result<MechanismError> {
    let above = 1e-6 * balance.swing();
    let lowest = balance.clone().lowest_running_speed(ratio, above)?;
    let min_omega = if lowest.is_finite() {
        Some(running_speed(balance, lowest, ratio)?)
    } else {
        None
    };
    Ok(MechanismError::Stall {
        angle: angle.rem_euclid(balance.cycle()),
        omega_mean,
        min_omega,
    })
}

/// `omega` (rad/s), nudged up until the steady state asked for at it runs: min_omega is a
/// speed that runs (the threshold's root and the solve's own root in s each round by
/// ~1e-15; a caller's round trip through 1/min by as much again), within a few ulps of the
/// threshold. Each trial solves on a fresh copy of `balance`, as
/// [`SteadyTables::steady_state`] does (a copy that has located its minima already rounds
/// differently).
fn running_speed(balance: &Balance, omega: f64, ratio: f64) -> Result<f64> {
    let mut found = omega;
    let mut step = 4.0 * f64::EPSILON;
    for _ in 0..64 {
        let solved = balance
            .at_speed(found)
            .solve(balance.inertia(), ratio, None)?;
        if solved.periodic.is_some() {
            return Ok(found);
        }
        found = omega * (1.0 + step);
        step *= 2.0;
    }
    Ok(found)
}

impl SteadyTables {
    /// The tables of `machine` (its units, gas and g checked, naming the parameter).
    pub fn new(machine: &MachineView<'_>) -> Result<Self> {
        Self::from_cycle(Cycle::new(
            machine,
            Dynamics::new(machine.units, machine.g)?,
        )?)
    }

    /// The tables of `machine` whose gas is `gas` (a sweep's, shared by its designs that
    /// differ only in masses, g, I_w or speed).
    pub(crate) fn with_gas(machine: &MachineView<'_>, gas: &Arc<Gas>) -> Result<Self> {
        let dynamics = Dynamics::new(machine.units, machine.g)?;
        Self::from_cycle(Cycle::with_gas(machine, dynamics, gas)?)
    }

    /// The same machine with its gas's pressures times `factor` (a sweep's designs that
    /// differ only in `pressure_scale` or bore): J, U and the panels kept, W and M_gas scaled.
    pub(crate) fn gas_scaled(&self, factor: f64) -> Result<Self> {
        Self::from_cycle(self.cycle.gas_scaled(factor))
    }

    pub(super) fn from_cycle(cycle: Cycle) -> Result<Self> {
        let cycle = Arc::new(cycle);
        let load = balance_load(&cycle);
        Ok(Self {
            machine: Balance::new(&cycle, load, true)?,
            coasting: OnceLock::new(),
            without_gravity: OnceLock::new(),
            load,
            cycle,
            swing: OnceLock::new(),
        })
    }

    /// The energy method's set-up with g = 0 (`None` where g = 0 already), made on first
    /// use from these tables (nothing is tabulated again).
    fn without_gravity_balance(&self) -> Result<Option<&Balance>> {
        if let Some(made) = self.without_gravity.get() {
            return Ok(made.as_ref());
        }
        let made = if self.cycle.gravity_on {
            let cycle = Arc::new(self.cycle.without_gravity());
            Some(Balance::new(&cycle, self.load, true)?)
        } else {
            None
        };
        Ok(self.without_gravity.get_or_init(|| made).as_ref())
    }

    /// The set-up of the machine coasting (gas, drive and load removed), made on first use.
    fn coasting_balance(&self) -> Result<&Balance> {
        if let Some(made) = self.coasting.get() {
            return Ok(made);
        }
        let made = Balance::new(&self.cycle, 0.0, false)?;
        Ok(self.coasting.get_or_init(|| made))
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

    /// The same machine with g = 0, from these tables: the energy method's set-up with
    /// g = 0 that they hold already becomes the machine's (nothing is tabulated again; only
    /// the set-up of the variation of J alone at g = 0 is made). A clone where g = 0 already.
    pub fn without_gravity(&self) -> Result<Self> {
        let Some(balance) = self.without_gravity_balance()? else {
            return Ok(self.clone());
        };
        let cycle = Arc::clone(balance.shared_cycle());
        Ok(Self {
            machine: balance.clone(),
            without_gravity: OnceLock::from(None),
            coasting: OnceLock::new(),
            load: self.load,
            cycle,
            swing: OnceLock::new(),
        })
    }

    /// The same machine with a driving torque M_d(φ) = `drive` (N·m, periodic over the
    /// working cycle, its breakpoints spanning it) beside the gas, from these tables (J, U
    /// and the gas work kept; the drive's work, exact piece by piece, and its slope added):
    /// the "balance" load becomes the cycle mean of gas and drive, and every solve, K₀
    /// ([`SteadyTables::work_at`]) and the textbook flywheel take the drive with the gas.
    ///
    /// Errors: a drive whose breakpoints do not span one cycle, naming `drive`; tables that
    /// have a drive already.
    pub fn with_drive(&self, drive: &PiecewisePolynomial) -> Result<Self> {
        if self.cycle.has_drive() {
            return Err(MechanismError::OutOfRange {
                parameter: "drive",
                value: f64::NAN,
                allowed: "one drive (these tables have one already)",
            });
        }
        let drive = Drive::new(drive.clone(), self.cycle())?;
        Self::from_cycle(self.cycle.with_drive(drive))
    }

    /// Φ (rad).
    pub fn cycle(&self) -> f64 {
        self.cycle.cycle()
    }

    /// The "balance" load (N·m): the cycle mean of the gas torque.
    pub fn load(&self) -> f64 {
        self.load
    }

    /// The periodic steady state with I_w = `shaft_inertia` (kg·m²) at the mean speed
    /// `omega_mean` (rad/s), as [`steady_state_curves`] gives it, with ω and t at `phi` (rad, each in
    /// [0, Φ]; none: no curves). `compare`: whether δ without gravity and coasting
    /// are solved too (else NaN, and two solves saved).
    ///
    /// Errors: bad input, naming the parameter; [`MechanismError::Stall`] with the lowest
    /// mean speed that runs.
    ///
    /// [`steady_state_curves`]: super::steady_state_curves
    pub fn steady_state(
        &self,
        shaft_inertia: f64,
        omega_mean: f64,
        min_speed_ratio: f64,
        phi: &[f64],
        compare: bool,
    ) -> Result<SteadyCurves> {
        let (found, _) =
            self.solved_steady_state(shaft_inertia, omega_mean, min_speed_ratio, phi, compare)?;
        Ok(found)
    }

    /// [`SteadyTables::steady_state`], and the solve kept: ω and t at other angles later
    /// ([`SolvedSteadyState::curves`]) without solving again.
    ///
    /// Errors: as [`SteadyTables::steady_state`].
    pub fn solved_steady_state(
        &self,
        shaft_inertia: f64,
        omega_mean: f64,
        min_speed_ratio: f64,
        phi: &[f64],
        compare: bool,
    ) -> Result<(SteadyCurves, SolvedSteadyState)> {
        check_shaft_inertia(shaft_inertia)?;
        check_speed("omega_mean", omega_mean)?;
        check_speed_ratio(min_speed_ratio)?;
        check_angles(phi, self.cycle())?;
        let (found, kept) = self
            .machine
            .with_inertia(shaft_inertia)
            .solve_kept(omega_mean, min_speed_ratio)?;
        let (Some(solution), Some(kept)) = (found.periodic, kept) else {
            let balance = self.machine.with_inertia(shaft_inertia);
            let angle = found.stall_angle.unwrap_or(f64::NAN);
            return Err(stall_error(&balance, angle, omega_mean, min_speed_ratio)?);
        };
        let mut state = state_of(&solution, self.load, f64::NAN, f64::NAN);
        if compare {
            (state.delta_without_gravity, state.delta_coasting) = self.comparisons(
                shaft_inertia,
                omega_mean,
                state.delta,
                state.omega_mean,
                min_speed_ratio,
            )?;
        }
        let solved = SolvedSteadyState { kept };
        let (omega, time) = solved.kept_curves(phi)?;
        let found = SteadyCurves {
            state,
            omega,
            time,
            status: found.status.code(),
            message: found.message,
            nfev: found.nfev,
            nit: found.nit,
        };
        Ok((found, solved))
    }

    /// (δ without gravity, δ coasting) of a steady state found by
    /// [`SteadyTables::steady_state`] with I_w = `shaft_inertia` at the mean speed `omega`
    /// asked for (rad/s) (its `delta` and `omega_mean`, the mean speed found, rad/s): the two
    /// comparison solves it skips without `compare` — δ₀ at the speed asked for (δ itself
    /// without gravity), δ coasting at the mean speed found; each NaN where it stalls.
    pub fn comparisons(
        &self,
        shaft_inertia: f64,
        omega: f64,
        delta: f64,
        omega_mean: f64,
        min_speed_ratio: f64,
    ) -> Result<(f64, f64)> {
        check_shaft_inertia(shaft_inertia)?;
        check_speed("omega", omega)?;
        check_speed("omega_mean", omega_mean)?;
        check_speed_ratio(min_speed_ratio)?;
        let without = self
            .delta_without_gravity(shaft_inertia, omega, min_speed_ratio)?
            .unwrap_or(delta);
        let alone = self.delta_coasting(shaft_inertia, omega_mean, min_speed_ratio)?;
        Ok((without, alone))
    }

    /// K₀(φ) = W(φ) − (U(φ) − U(0)) (J) at `phi` (rad, each in [0, Φ]): the work of the
    /// gas (and of the drive, where the tables have one) from φ = 0, exact as the tables
    /// take it, less the rise of gravity's potential
    /// (0 without gravity) — the part of the kinetic energy that depends on φ alone.
    ///
    /// Errors: an angle outside [0, Φ] (or not finite), naming `phi`.
    pub fn work_at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        let cycle = self.cycle();
        for &angle in phi {
            check("phi", angle, "0 <= phi <= cycle angle", |a| {
                (0.0..=cycle).contains(&a)
            })?;
        }
        let work = self.cycle.work_at(phi)?;
        let potential = self.cycle.potential_at(phi)?;
        Ok(work.iter().zip(&potential).map(|(w, u)| w - u).collect())
    }

    /// (ΔE (J), the textbook I_w (kg·m²)) for the coefficient of speed fluctuation `delta`
    /// at the constant speed ω_m = `omega_mean` (rad/s), the load balancing the gas: the
    /// `energy_swing` and `textbook` of [`SteadyTables::flywheel_inertia`], without its
    /// search.
    ///
    /// Errors: `delta` < 1e-9 or `omega_mean` outside [`SPEED_LIMITS`], naming the parameter.
    ///
    /// [`SPEED_LIMITS`]: crate::mechanism::SPEED_LIMITS
    pub fn textbook_flywheel(&self, delta: f64, omega_mean: f64) -> Result<(f64, f64)> {
        flywheel::check_delta(delta)?;
        check_speed("omega_mean", omega_mean)?;
        let swing = self.energy_swing(omega_mean)?;
        Ok((
            swing,
            flywheel::textbook(swing, &self.cycle, delta, omega_mean),
        ))
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

    /// The solution with I_w = `shaft_inertia` at ω_m = `omega_mean` (rad/s): one solve,
    /// no curves.
    pub(crate) fn solve(
        &self,
        shaft_inertia: f64,
        omega_mean: f64,
        ratio: f64,
    ) -> Result<Solution> {
        self.machine
            .at_speed(omega_mean)
            .solve(shaft_inertia, ratio, None)
    }

    /// δ of the machine with g = 0, the same load, at ω_m = `omega_mean` (rad/s), NaN where
    /// it stalls; `None` where the machine has no gravity (δ₀ is then δ).
    pub(crate) fn delta_without_gravity(
        &self,
        shaft_inertia: f64,
        omega_mean: f64,
        ratio: f64,
    ) -> Result<Option<f64>> {
        self.without_gravity_balance()?
            .map(|balance| {
                Ok(balance
                    .at_speed(omega_mean)
                    .solve(shaft_inertia, ratio, None)?
                    .delta_or_nan())
            })
            .transpose()
    }

    /// δ of the machine coasting: gravity and the variation of J alone (gas, drive and load
    /// removed), at ω_m = `omega_mean` (rad/s); NaN where it stalls.
    pub(crate) fn delta_coasting(
        &self,
        shaft_inertia: f64,
        omega_mean: f64,
        ratio: f64,
    ) -> Result<f64> {
        Ok(self
            .coasting_balance()?
            .at_speed(omega_mean)
            .solve(shaft_inertia, ratio, None)?
            .delta_or_nan())
    }

    /// The shaft inertia for the coefficient of speed fluctuation `delta` at the mean speed
    /// `omega_mean` (rad/s), as
    /// [`flywheel_inertia`] gives it; `fallback` (kg·m²): where the search starts when the
    /// textbook estimate is not positive. `without`: whether the g = 0 machine's is sized
    /// too (else NaN).
    ///
    /// [`flywheel_inertia`]: super::flywheel_inertia
    pub fn flywheel_inertia(
        &self,
        delta: f64,
        omega_mean: f64,
        min_speed_ratio: f64,
        fallback: f64,
        without: bool,
    ) -> Result<FlywheelInertia> {
        flywheel::check_delta(delta)?;
        check_speed("omega_mean", omega_mean)?;
        check_speed_ratio(min_speed_ratio)?;
        let balance = &self.machine;
        let swing = self.energy_swing(omega_mean)?;
        let textbook = flywheel::textbook(swing, &self.cycle, delta, omega_mean);
        let start = flywheel::start(swing, textbook, &self.cycle, delta, omega_mean, fallback);
        let rest = self.cycle.mean_rest();
        let inertia = flywheel::inertia_for(
            &balance.at_speed(omega_mean),
            min_speed_ratio,
            rest,
            delta,
            start,
        )?;
        let without = if without {
            match self.without_gravity_balance()? {
                None => inertia,
                Some(balance) => flywheel::inertia_for(
                    &balance.at_speed(omega_mean),
                    min_speed_ratio,
                    rest,
                    delta,
                    inertia,
                )
                .unwrap_or(f64::NAN),
            }
        } else {
            f64::NAN
        };
        Ok(FlywheelInertia::sized(
            inertia,
            without,
            (swing, textbook),
            delta,
            omega_mean,
        ))
    }
}

impl SteadyTables {
    /// The shaft inertia for the coefficient of speed fluctuation `delta` under a square-law
    /// load, as [`square_law_flywheel_inertia`] gives it; `fallback` (kg·m²): the shaft the
    /// first mean speed is found with (the machine's own).
    ///
    /// [`square_law_flywheel_inertia`]: super::square_law_flywheel_inertia
    pub fn square_law_flywheel_inertia(
        &self,
        coefficient: f64,
        drive: f64,
        delta: f64,
        min_speed_ratio: f64,
        fallback: f64,
    ) -> Result<FlywheelInertia> {
        flywheel::square_law_inertia(
            &self.cycle,
            self.load,
            |omega| self.textbook_flywheel(delta, omega),
            coefficient,
            drive,
            delta,
            min_speed_ratio,
            fallback,
        )
    }
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
pub(super) fn state_of(solution: &Periodic, load: f64, without: f64, alone: f64) -> SteadyState {
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
        delta_coasting: alone,
    }
}
