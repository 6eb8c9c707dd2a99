//! The machine, converted once: `NativeMachine` owns a `core::Machine` (everything a machine
//! is, checked by the core) and answers every question the Python package asks of it — its
//! gravity, kinematics, reduced inertia and gas torque here; its motion in `motion.rs`, the
//! forces on its frame in `forces.rs`, its torque orders in `orders.rs` (one class, its
//! methods by domain). Free functions for what is not a machine's: the net piston force of
//! pressures, a unit's travel, the two-mass rod and the layout rules of a machine being built.

use std::sync::{Arc, Mutex};

use multicrank_core as core;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::conversion::{empty_array, filled, gas_tables, named, DiagramArg, MachineColumns};
use crate::conversion::{OutputSize, PhiArg};
use crate::error::to_py_err;
use crate::parallel::parallelism;

/// A machine as the core holds it, converted and checked once and reused by every call:
/// its units, their gas (the indicator diagrams as SciPy `PPoly` arrays), I_w, the strokes,
/// g, the units' axial positions and the main bearings; the cycle's tables and the shaking
/// forces the core makes on first use and keeps. Immutable; safe to share between threads.
///
/// NativeMachine(units, bore, piston_rod_diameter, pressure, pressure_crank_end,
/// shaft_inertia, strokes, g, axial_position=None, main_bearings=None): `units` the unit
/// columns, `bore` and `piston_rod_diameter` (m) one per unit, `pressure` and
/// `pressure_crank_end` one per unit, each None or the pair (x, c) of the gauge pressure's
/// (Pa) `PPoly` (breakpoints x spanning one working cycle, coefficients c of shape
/// (K, len(x) − 1)), `shaft_inertia` I_w (kg·m²) > 0, `strokes` 2 or 4, `g` (m/s²),
/// `axial_position` (m) one per unit (default all 0), `main_bearings` (m) or None for
/// bearings interleaving the throws.
#[pyclass(frozen, name = "NativeMachine", module = "multicrank._native")]
pub(crate) struct NativeMachine {
    pub(crate) core: core::Machine,
    /// The shaking orders last asked for (the same machine asked again at another speed
    /// scales them by ω² without a new series).
    pub(crate) orders: Mutex<Option<Arc<core::ShakingOrders>>>,
}

#[pymethods]
impl NativeMachine {
    #[new]
    #[pyo3(signature = (
        units, bore, piston_rod_diameter, pressure, pressure_crank_end, shaft_inertia, strokes, g,
        axial_position=None, main_bearings=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        units: MachineColumns<'_>,
        bore: PyReadonlyArray1<'_, f64>,
        piston_rod_diameter: PyReadonlyArray1<'_, f64>,
        pressure: Vec<DiagramArg<'_>>,
        pressure_crank_end: Vec<DiagramArg<'_>>,
        shaft_inertia: f64,
        strokes: i64,
        g: f64,
        axial_position: Option<PyReadonlyArray1<'_, f64>>,
        main_bearings: Option<PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<Self> {
        let strokes = core::Strokes::from_count(strokes).map_err(to_py_err)?;
        let units = units.units()?;
        let (gas, diagrams) = gas_tables(
            units.len(),
            bore.as_slice()?,
            piston_rod_diameter.as_slice()?,
            &pressure,
            &pressure_crank_end,
            strokes.cycle_angle(),
        )?;
        let axial_position = match axial_position {
            Some(z) => z.as_slice()?.to_vec(),
            None => vec![0.0; units.len()],
        };
        let main_bearings = main_bearings.map(|b| b.as_slice().map(<[f64]>::to_vec));
        let core = core::Machine::new(core::MachineParts {
            units,
            gas,
            diagrams,
            shaft_inertia,
            strokes,
            g,
            axial_position,
            main_bearings: main_bearings.transpose()?,
        })
        .map_err(to_py_err)?;
        Ok(Self {
            core,
            orders: Mutex::new(None),
        })
    }

    /// evaluate(quantity, phi, parallel_threshold=None) -> flat array: "potential_energy" U
    /// (J) or "gravity_torque" −dU/dφ (N·m) (like phi), or the piston "travel" s (m) or
    /// "velocity" ds/dφ (m/rad) of every unit (unit-major, units × phi).
    #[pyo3(signature = (quantity, phi, parallel_threshold=None))]
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        quantity: &str,
        phi: PhiArg<'py>,
        parallel_threshold: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        evaluate_quantity(py, self.core.dynamics(), quantity, phi, parallel_threshold)
    }

    /// reduced_inertia(phi, shaft_inertia=None, parallel_threshold=None) -> {"J",
    /// "dJ_dphi"}: the reduced moment of inertia (kg·m²) and its slope (kg·m²/rad) with I_w =
    /// `shaft_inertia` (kg·m², default the machine's).
    #[pyo3(signature = (phi, shaft_inertia=None, parallel_threshold=None))]
    fn reduced_inertia<'py>(
        &self,
        py: Python<'py>,
        phi: PhiArg<'py>,
        shaft_inertia: Option<f64>,
        parallel_threshold: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let phi = phi.slice()?;
        let inertia = shaft_inertia.unwrap_or(self.core.shaft_inertia());
        let parallelism = parallelism(parallel_threshold);
        let size = OutputSize::of("phi", phi.len());
        let (j_array, dj_array) = (empty_array(py, size)?, empty_array(py, size)?);
        {
            let (mut j, mut dj) = (j_array.readwrite(), dj_array.readwrite());
            let (j, dj) = (j.as_slice_mut()?, dj.as_slice_mut()?);
            let dynamics = self.core.dynamics();
            py.detach(|| dynamics.reduced_inertia(inertia, phi.phi()?, j, dj, parallelism))
                .map_err(to_py_err)?;
        }
        let dict = PyDict::new(py);
        dict.set_item("J", j_array)?;
        dict.set_item("dJ_dphi", dj_array)?;
        Ok(dict)
    }

    /// gas_torque(phi, forces, parallel_threshold=None) -> Σ_j F_j s'_j (N·m) at `phi`
    /// (rad), `forces` (N) unit-major (units × phi), positive toward the shaft.
    #[pyo3(signature = (phi, forces, parallel_threshold=None))]
    fn gas_torque<'py>(
        &self,
        py: Python<'py>,
        phi: PhiArg<'py>,
        forces: PyReadonlyArray1<'py, f64>,
        parallel_threshold: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (phi, forces) = (phi.slice()?, forces.as_slice()?);
        let (dynamics, parallelism) = (self.core.dynamics(), parallelism(parallel_threshold));
        filled(py, OutputSize::of("phi", phi.len()), |out| {
            dynamics.gas_torque(phi.phi()?, forces, out, parallelism)
        })
    }

    /// engine(omega, shaft_inertia=None) -> the dimensionless engine's columns {"phase",
    /// "inclination", "crank_ratio", "u1", "u2"} at the speed `omega` (rad/s) with I_w =
    /// `shaft_inertia` (kg·m², default the machine's).
    #[pyo3(signature = (omega, shaft_inertia=None))]
    fn engine<'py>(
        &self,
        py: Python<'py>,
        omega: f64,
        shaft_inertia: Option<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let inertia = shaft_inertia.unwrap_or(self.core.shaft_inertia());
        let engine = self
            .core
            .dynamics()
            .dimensionless(inertia, omega)
            .map_err(to_py_err)?;
        let column = |f: fn(&core::EngineUnit) -> f64| engine.cylinders().iter().map(f).collect();
        named(
            py,
            [
                ("phase", column(|c| c.phase)),
                ("inclination", column(|c| c.inclination)),
                ("crank_ratio", column(|c| c.crank_ratio)),
                ("u1", column(|c| c.u1)),
                ("u2", column(|c| c.u2)),
            ],
        )
    }

    /// layout() -> (throws, throw_of_unit, bearings): the throws' axial positions (m,
    /// increasing), each unit's throw (its index among them) and the main bearings' positions
    /// (m), as `bearing_layout` gives them.
    fn layout(&self) -> (Vec<f64>, Vec<usize>, Vec<f64>) {
        layout_tuple(self.core.layout())
    }

    fn __repr__(&self) -> String {
        let strokes = match self.core.strokes() {
            core::Strokes::Two => 2,
            core::Strokes::Four => 4,
        };
        format!(
            "NativeMachine({} units, {} diagrams, {strokes}-stroke, shaft_inertia={}, g={})",
            self.core.len(),
            self.core.diagrams().len(),
            self.core.shaft_inertia(),
            self.core.g()
        )
    }
}

fn layout_tuple(layout: &core::BearingLayout) -> (Vec<f64>, Vec<usize>, Vec<f64>) {
    (
        layout.throws().to_vec(),
        layout.throw_of_unit().to_vec(),
        layout.bearing_position().to_vec(),
    )
}

/// U, −U′, s or s′ of `dynamics` at `phi`.
fn evaluate_quantity<'py>(
    py: Python<'py>,
    dynamics: &core::Dynamics,
    quantity: &str,
    phi: PhiArg<'py>,
    parallel_threshold: Option<usize>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let phi = phi.slice()?;
    let parallelism = parallelism(parallel_threshold);
    let points = OutputSize::of("phi", phi.len());
    let per_unit = |kinematics| (points.times(dynamics.len()), Some(kinematics));
    let (size, kinematics) = match quantity {
        "potential_energy" | "gravity_torque" => (points, None),
        "travel" => per_unit(core::Kinematics::Travel),
        "velocity" => per_unit(core::Kinematics::Velocity),
        other => {
            return Err(to_py_err(core::MechanismError::InvalidChoice {
                parameter: "quantity",
                value: format!("{other:?}"),
                allowed: "\"potential_energy\", \"gravity_torque\", \"travel\", \"velocity\"",
            }))
        }
    };
    let gravity_torque = quantity == "gravity_torque";
    filled(py, size, |out| match kinematics {
        Some(k) => dynamics.kinematics(k, phi.phi()?, out, parallelism),
        None if gravity_torque => dynamics.gravity_torque(phi.phi()?, out, parallelism),
        None => dynamics.potential_energy(phi.phi()?, out, parallelism),
    })
}

/// bearing_layout(axial_position, main_bearings, crank_radius) -> (throws, throw_of_unit,
/// bearings): the rules of a machine's throws and main bearings (`core::BearingLayout`), for
/// a machine being built: units at `axial_position` (m), the bearings `main_bearings` (m) or
/// None for bearings interleaving the throws (a lone throw's at ± `crank_radius`, m).
#[pyfunction]
pub(crate) fn bearing_layout(
    axial_position: Vec<f64>,
    main_bearings: Option<Vec<f64>>,
    crank_radius: f64,
) -> PyResult<(Vec<f64>, Vec<usize>, Vec<f64>)> {
    let layout = core::BearingLayout::new(&axial_position, main_bearings.as_deref(), crank_radius)
        .map_err(to_py_err)?;
    Ok(layout_tuple(&layout))
}

/// unit_travel(units, phi) -> s (m) of every unit at every φ (rad), unit-major (units ×
/// phi), each unit checked: what a cylinder alone knows of its motion (g plays no part).
#[pyfunction]
pub(crate) fn unit_travel<'py>(
    py: Python<'py>,
    units: MachineColumns<'py>,
    phi: PhiArg<'py>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let dynamics = units.dynamics(0.0)?;
    evaluate_quantity(py, &dynamics, "travel", phi, None)
}

/// piston_forces(bore, piston_rod_diameter, head, crank_end) -> F = p·A − p_c·A_c (N) of
/// every unit (bore D and piston-rod diameter d in m, one per unit) at every point, from the
/// gauge pressures (Pa) on its two ends: `head`, `crank_end` and the result are unit-major
/// (units × points), 0 where an end has no pressure.
#[pyfunction]
pub(crate) fn piston_forces<'py>(
    py: Python<'py>,
    bore: PyReadonlyArray1<'py, f64>,
    piston_rod_diameter: PyReadonlyArray1<'py, f64>,
    head: PyReadonlyArray1<'py, f64>,
    crank_end: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (bore, rod) = (bore.as_slice()?, piston_rod_diameter.as_slice()?);
    if rod.len() != bore.len() {
        return Err(to_py_err(core::MechanismError::LengthMismatch {
            parameter: "piston_rod_diameter",
            expected: bore.len(),
            found: rod.len(),
        }));
    }
    let gas: Vec<core::GasCylinder> = bore
        .iter()
        .zip(rod)
        .map(|(&bore, &piston_rod_diameter)| core::GasCylinder {
            bore,
            piston_rod_diameter,
            ..core::GasCylinder::NONE
        })
        .collect();
    let (head, crank_end) = (head.as_slice()?, crank_end.as_slice()?);
    filled(py, OutputSize::of("head", head.len()), |out| {
        core::net_piston_forces(&gas, head, crank_end, out)
    })
}

/// two_mass_rod_inertia(rod_mass, rod_length, rod_cg) -> I_k (kg·m²) of the two-mass rod,
/// m_k z_k (l − z_k): the default of a cylinder whose rod inertia is not given.
#[pyfunction]
pub(crate) fn two_mass_rod_inertia(rod_mass: f64, rod_length: f64, rod_cg: f64) -> f64 {
    core::two_mass_rod_inertia(rod_mass, rod_length, rod_cg)
}
