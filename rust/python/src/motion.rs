//! Steady running at sweep scale: a `NativeMachine`'s steady state, its flywheel and sweeps
//! of its variants, each call with the GIL released around the core.

use multicrank_core as core;
use std::borrow::Cow;

use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::conversion::{drive_table, DiagramArg, MotionDesigns};
use crate::error::{motion_err, to_py_err};
use crate::machine::NativeMachine;
use crate::motion_results::{steady_result, FlywheelResult, SteadyResult};
use crate::parallel::parallelism;

impl NativeMachine {
    /// The tables of [`core::Machine::tables`], with the driving torque `drive` beside the
    /// gas where one is given (that call's own tables, made from the kept ones).
    fn tables_with(
        &self,
        gravity: bool,
        drive: Option<&core::PiecewisePolynomial>,
    ) -> core::Result<Cow<'_, core::SteadyTables>> {
        let tables = self.core.tables(gravity)?;
        Ok(match drive {
            None => Cow::Borrowed(tables),
            Some(drive) => Cow::Owned(tables.with_drive(drive)?),
        })
    }

    fn cycle(&self) -> f64 {
        self.core.strokes().cycle_angle()
    }
}

#[pymethods]
impl NativeMachine {
    /// steady_state(omega_mean, min_speed_ratio=1e-3, phi=None, compare=True,
    /// shaft_inertia=None, gravity=True) -> SteadyResult: the periodic steady state under the
    /// "balance" load at the mean speed `omega_mean` (rad/s, within SPEED_LIMITS) with I_w = `shaft_inertia` (kg·m², default the machine's): omega_mean, period,
    /// omega_max, omega_min, phi_max, phi_min, energy_at_zero, mean_load_torque, delta,
    /// delta_midrange, delta_without_gravity, delta_coasting (SI units; the last two
    /// NaN unless `compare`), and with `phi` (rad, in [0, Φ]) the arrays omega (rad/s),
    /// time (s from φ = 0), reduced_inertia, reduced_inertia_slope, gas_torque and
    /// gravity_torque there. A stall is a MechanismError with attributes angle, omega_mean
    /// and min_omega (rad/s). `gravity=False`: the same machine with g = 0 (on this machine's tables).
    /// `drive`: None, or the PPoly arrays (x, c) of a driving torque M_d(φ) (N·m, x spanning
    /// one working cycle) beside the gas, the load balancing both (its cycle mean).
    /// `arrays=False`: with `phi`, ω and t alone (the rest: `cycle_arrays`). The result's
    /// `solved` gives ω and t at other angles later without a second solve.
    #[pyo3(signature = (
        omega_mean, min_speed_ratio=1e-3, phi=None, compare=true, shaft_inertia=None,
        gravity=true, drive=None, arrays=true
    ))]
    #[allow(clippy::too_many_arguments)]
    fn steady_state<'py>(
        &self,
        py: Python<'py>,
        omega_mean: f64,
        min_speed_ratio: f64,
        phi: Option<PyReadonlyArray1<'py, f64>>,
        compare: bool,
        shaft_inertia: Option<f64>,
        gravity: bool,
        drive: DiagramArg<'py>,
        arrays: bool,
    ) -> PyResult<SteadyResult> {
        let angles = phi.as_ref().map(|a| a.as_slice()).transpose()?;
        let inertia = shaft_inertia.unwrap_or(self.core.shaft_inertia());
        let drive = drive_table(&drive, self.cycle())?;
        let (found, arrays, solved) = py
            .detach(|| {
                let tables = self.tables_with(gravity, drive.as_ref())?;
                let (found, solved) = tables.solved_steady_state(
                    inertia,
                    omega_mean,
                    min_speed_ratio,
                    angles.unwrap_or(&[]),
                    compare,
                )?;
                let arrays = angles
                    .filter(|_| arrays)
                    .map(|phi| tables.arrays_at(inertia, phi))
                    .transpose()?;
                Ok((found, arrays, solved))
            })
            .map_err(|error| motion_err(py, error))?;
        steady_result(py, found, angles.is_some(), arrays, Some(solved))
    }

    /// cycle_arrays(phi, shaft_inertia=None, gravity=True, drive=None) -> (reduced_inertia,
    /// reduced_inertia_slope, gas_torque, gravity_torque): J (kg·m², with I_w =
    /// `shaft_inertia`, default the machine's), J′ (kg·m²/rad), M_gas (N·m, the gas alone)
    /// and −U′ (N·m; 0 with `gravity=False`) at `phi` (rad, in [0, Φ]), as the cycle's tables
    /// (with `drive`, as steady_state takes it) give them: what steady_state gives with its
    /// arrays.
    #[pyo3(signature = (phi, shaft_inertia=None, gravity=true, drive=None))]
    fn cycle_arrays<'py>(
        &self,
        py: Python<'py>,
        phi: PyReadonlyArray1<'py, f64>,
        shaft_inertia: Option<f64>,
        gravity: bool,
        drive: DiagramArg<'py>,
    ) -> PyResult<[Bound<'py, PyArray1<f64>>; 4]> {
        let angles = phi.as_slice()?;
        let inertia = shaft_inertia.unwrap_or(self.core.shaft_inertia());
        let drive = drive_table(&drive, self.cycle())?;
        let found = py
            .detach(|| {
                self.tables_with(gravity, drive.as_ref())?
                    .arrays_at(inertia, angles)
            })
            .map_err(|error| motion_err(py, error))?;
        Ok([
            found.reduced_inertia.into_pyarray(py),
            found.reduced_inertia_slope.into_pyarray(py),
            found.gas_torque.into_pyarray(py),
            found.gravity_torque.into_pyarray(py),
        ])
    }

    /// comparisons(omega, delta, omega_mean, min_speed_ratio=1e-3, shaft_inertia=None,
    /// gravity=True) ->
    /// (delta_without_gravity, delta_coasting): the two comparison solves of the steady
    /// state at the mean speed `omega` asked for (rad/s) that steady_state(compare=False)
    /// found (its `delta` and `omega_mean`, the mean speed found, rad/s), each NaN where it
    /// stalls; `drive` as steady_state takes it.
    #[pyo3(signature = (
        omega, delta, omega_mean, min_speed_ratio=1e-3, shaft_inertia=None, gravity=true,
        drive=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn comparisons(
        &self,
        py: Python<'_>,
        omega: f64,
        delta: f64,
        omega_mean: f64,
        min_speed_ratio: f64,
        shaft_inertia: Option<f64>,
        gravity: bool,
        drive: DiagramArg<'_>,
    ) -> PyResult<(f64, f64)> {
        let inertia = shaft_inertia.unwrap_or(self.core.shaft_inertia());
        let drive = drive_table(&drive, self.cycle())?;
        py.detach(|| {
            self.tables_with(gravity, drive.as_ref())?.comparisons(
                inertia,
                omega,
                delta,
                omega_mean,
                min_speed_ratio,
            )
        })
        .map_err(|error| motion_err(py, error))
    }

    /// mean_gas_torque() -> float: the cycle mean of the gas torque (N·m), W(Φ)/Φ — the
    /// "balance" load beside no drive, and what a square-law load needs positive (with the
    /// drive) to run at all.
    fn mean_gas_torque(&self, py: Python<'_>) -> PyResult<f64> {
        py.detach(|| self.core.tables(true).map(core::SteadyTables::load))
            .map_err(|error| motion_err(py, error))
    }

    /// gas_and_gravity_work(phi, gravity=True) -> array: K₀(φ) = W(φ) − (U(φ) − U(0)) (J)
    /// at `phi` (rad, each in [0, Φ]): the gas work from φ = 0, exact as the tables take it,
    /// less the rise of gravity's potential (none with `gravity=False`) — the part of the
    /// kinetic energy that depends on φ alone.
    #[pyo3(signature = (phi, gravity=true))]
    fn gas_and_gravity_work<'py>(
        &self,
        py: Python<'py>,
        phi: PyReadonlyArray1<'py, f64>,
        gravity: bool,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let angles = phi.as_slice()?;
        let work = py
            .detach(|| self.core.tables(gravity)?.work_at(angles))
            .map_err(|error| motion_err(py, error))?;
        Ok(work.into_pyarray(py))
    }

    /// textbook_flywheel(delta, omega_mean, drive=None, gravity=True) -> (energy_swing,
    /// textbook): ΔE (J) and the textbook I_w = ΔE/(δω_m²) − mean(J − I_w) (kg·m²) for the
    /// coefficient of speed fluctuation `delta` at the constant speed `omega_mean` (rad/s),
    /// the load balancing the gas (and `drive`): what flywheel_inertia reports as
    /// energy_swing and textbook, without its search.
    #[pyo3(signature = (delta, omega_mean, drive=None, gravity=true))]
    fn textbook_flywheel(
        &self,
        py: Python<'_>,
        delta: f64,
        omega_mean: f64,
        drive: DiagramArg<'_>,
        gravity: bool,
    ) -> PyResult<(f64, f64)> {
        let drive = drive_table(&drive, self.cycle())?;
        py.detach(|| {
            self.tables_with(gravity, drive.as_ref())?
                .textbook_flywheel(delta, omega_mean)
        })
        .map_err(|error| motion_err(py, error))
    }

    /// square_law(coefficient, drive=0.0, min_speed_ratio=1e-3, phi=None, gravity=True)
    /// -> SteadyResult: the
    /// periodic steady state under the load c·ω² (c = `coefficient`, N·m·s²/rad²) beside a
    /// constant `drive` (N·m), in closed form: the numbers of steady_state (the mean speed a
    /// result, mean_load_torque the load's cycle mean), with `phi` omega and time there;
    /// `gravity=False`: with g = 0.
    #[pyo3(signature = (coefficient, drive=0.0, min_speed_ratio=1e-3, phi=None, gravity=true))]
    fn square_law<'py>(
        &self,
        py: Python<'py>,
        coefficient: f64,
        drive: f64,
        min_speed_ratio: f64,
        phi: Option<PyReadonlyArray1<'py, f64>>,
        gravity: bool,
    ) -> PyResult<SteadyResult> {
        let angles = phi.as_ref().map(|a| a.as_slice()).transpose()?;
        let found = py
            .detach(|| {
                core::square_law_steady_state(
                    &self.core.view_with(gravity),
                    coefficient,
                    drive,
                    min_speed_ratio,
                    angles.unwrap_or(&[]),
                )
            })
            .map_err(|error| motion_err(py, error))?;
        steady_result(py, found, angles.is_some(), None, None)
    }

    /// flywheel_inertia(delta, omega_mean, min_speed_ratio=1e-3, without_gravity=True,
    /// gravity=True) -> FlywheelResult: the shaft inertia giving the coefficient of speed
    /// fluctuation `delta` at the mean speed `omega_mean` (rad/s) under the "balance" load:
    /// shaft_inertia, shaft_inertia_without_gravity (NaN unless `without_gravity`), textbook,
    /// textbook_error, energy_swing, delta, omega_mean. A
    /// target no shaft inertia gives is a MechanismError with attributes delta, reach
    /// ("never_falls", "massless" or "stalls") and closest (the δ nearest to it that the
    /// machine reaches; NaN where none is known). `gravity=False`: the machine with g = 0;
    /// `drive` as steady_state takes it.
    #[pyo3(signature = (
        delta, omega_mean, min_speed_ratio=1e-3, without_gravity=true, gravity=true,
        drive=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn flywheel_inertia<'py>(
        &self,
        py: Python<'py>,
        delta: f64,
        omega_mean: f64,
        min_speed_ratio: f64,
        without_gravity: bool,
        gravity: bool,
        drive: DiagramArg<'py>,
    ) -> PyResult<FlywheelResult> {
        let drive = drive_table(&drive, self.cycle())?;
        let f = py
            .detach(|| {
                self.tables_with(gravity, drive.as_ref())?.flywheel_inertia(
                    delta,
                    omega_mean,
                    min_speed_ratio,
                    self.core.shaft_inertia(),
                    without_gravity,
                )
            })
            .map_err(|error| motion_err(py, error))?;
        Ok(FlywheelResult::from(f))
    }

    /// square_law_flywheel_inertia(coefficient, delta, drive=0.0, min_speed_ratio=1e-3,
    /// gravity=True) -> FlywheelResult: the shaft inertia giving the coefficient of speed
    /// fluctuation `delta` under the load c·ω² (c = `coefficient`, N·m·s²/rad²) beside a
    /// constant `drive` (N·m), the mean speed a result (`omega_mean`, rad/s: the one reached with the
    /// shaft found, the textbook estimate taken there); the rest as flywheel_inertia gives it
    /// (shaft_inertia_without_gravity always sized).
    #[pyo3(signature = (coefficient, delta, drive=0.0, min_speed_ratio=1e-3, gravity=true))]
    fn square_law_flywheel_inertia(
        &self,
        py: Python<'_>,
        coefficient: f64,
        delta: f64,
        drive: f64,
        min_speed_ratio: f64,
        gravity: bool,
    ) -> PyResult<FlywheelResult> {
        let f = py
            .detach(|| {
                self.core.tables(gravity)?.square_law_flywheel_inertia(
                    coefficient,
                    drive,
                    delta,
                    min_speed_ratio,
                    self.core.shaft_inertia(),
                )
            })
            .map_err(|error| motion_err(py, error))?;
        Ok(FlywheelResult::from(f))
    }

    /// sweep(designs, outputs, omega=None, target_delta=None, min_speed_ratio=1e-3,
    /// parallel_threshold=None) -> {output: array}: the steady state (and the flywheel for
    /// `target_delta`) of every design, this machine with the design's columns applied
    /// (`designs`: column name → float64 array, one value per design; no columns: one
    /// design, this machine), at its `omega` column or at `omega` (the mean speed, rad/s).
    /// The outputs asked (names from
    /// MOTION_SWEEP_OUTPUTS), and `stalled` (bool) with any output of the steady state; a
    /// stalled design is NaN in its δ and speed columns, an unreachable target NaN in the
    /// flywheel columns. A bad value of a design is a MechanismError naming the design and
    /// the parameter, with the design's index (from 0) as its attribute `row`. Bit-identical for any thread count.
    #[pyo3(signature = (
        designs, outputs, omega=None, target_delta=None, min_speed_ratio=1e-3,
        parallel_threshold=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn sweep<'py>(
        &self,
        py: Python<'py>,
        designs: &Bound<'py, PyDict>,
        outputs: Vec<String>,
        omega: Option<f64>,
        target_delta: Option<f64>,
        min_speed_ratio: f64,
        parallel_threshold: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let asked = core::MotionOutputs::from_names(&outputs).map_err(to_py_err)?;
        let designs = MotionDesigns::extract(designs)?;
        let columns = designs.columns()?;
        let parallelism = parallelism(parallel_threshold);
        let mut found = py
            .detach(|| {
                core::motion_sweep(
                    &self.core.view(),
                    omega,
                    &columns,
                    asked,
                    target_delta,
                    min_speed_ratio,
                    parallelism,
                )
            })
            .map_err(|error| motion_err(py, error))?;
        let dict = PyDict::new(py);
        for name in core::MotionOutputs::NAMES {
            let column = match name {
                "stalled" => {
                    if asked.steady() {
                        dict.set_item(name, std::mem::take(&mut found.stalled).into_pyarray(py))?;
                    }
                    continue;
                }
                "delta" => &mut found.delta,
                "delta_without_gravity" => &mut found.delta_without_gravity,
                "delta_coasting" => &mut found.delta_coasting,
                "gravity_effect" => &mut found.gravity_effect,
                "omega_min" => &mut found.omega_min,
                "omega_max" => &mut found.omega_max,
                "flywheel_inertia" => &mut found.flywheel_inertia,
                "flywheel_inertia_without_gravity" => &mut found.flywheel_inertia_without_gravity,
                _ => continue,
            };
            if outputs.iter().any(|o| o == name) {
                dict.set_item(name, std::mem::take(column).into_pyarray(py))?;
            }
        }
        Ok(dict)
    }
}
