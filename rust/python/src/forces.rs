//! The forces on the frame of a `MotionMachine`: its shaking forces, made on first use, with
//! the orders last computed kept for the next call (the same machine asked again at another
//! speed scales them by ω² in the core without a new series).

use std::sync::{Arc, Mutex, OnceLock};

use multicrank_core as core;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::conversion::{empty_array, filled, MotionDesigns, OutputSize};
use crate::error::to_py_err;
use crate::motion::{motion_err, MotionMachine};
use crate::parallel::parallelism;

/// A machine's axial positions, its shaking forces (made on first use from the machine's
/// units: a machine asked only for its motion never pays for them) and the orders last
/// computed.
pub(crate) struct ShakingCache {
    axial_position: Vec<f64>,
    forces: OnceLock<core::ShakingForces>,
    orders: Mutex<Option<Arc<core::ShakingOrders>>>,
}

impl ShakingCache {
    pub(crate) fn new(axial_position: Vec<f64>) -> Self {
        Self {
            axial_position,
            forces: OnceLock::new(),
            orders: Mutex::new(None),
        }
    }

    /// The engine centre the moments are taken about (m).
    pub(crate) fn reference(&self) -> f64 {
        core::engine_centre(&self.axial_position)
    }

    /// The shaking forces of `units` (the owning machine's, the same at every call).
    fn forces(&self, units: &[core::PhysicalCylinder]) -> core::Result<&core::ShakingForces> {
        if let Some(forces) = self.forces.get() {
            return Ok(forces);
        }
        let made = core::ShakingForces::new(units, &self.axial_position)?;
        Ok(self.forces.get_or_init(|| made))
    }

    /// The orders through `max_order`: those kept where they reach it, else computed (and
    /// kept). A poisoned lock only loses the cache.
    fn orders_through(
        &self,
        units: &[core::PhysicalCylinder],
        max_order: usize,
    ) -> core::Result<Arc<core::ShakingOrders>> {
        let kept = self.orders.lock().ok().and_then(|held| held.clone());
        if let Some(orders) = kept.filter(|o| o.max_order() >= max_order) {
            return Ok(orders);
        }
        let made = Arc::new(self.forces(units)?.orders(max_order)?);
        if let Ok(mut held) = self.orders.lock() {
            *held = Some(Arc::clone(&made));
        }
        Ok(made)
    }

    pub(crate) fn orders<'py>(
        &self,
        py: Python<'py>,
        machine: &core::Machine<'_>,
        omega: f64,
        max_order: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        let columns = py
            .detach(|| {
                self.orders_through(machine.units, max_order)?
                    .at(omega, max_order)
            })
            .map_err(to_py_err)?;
        order_columns(py, columns)
    }

    pub(crate) fn orders_in_motion<'py>(
        &self,
        py: Python<'py>,
        machine: &core::Machine<'_>,
        omega: &PyReadonlyArray1<'py, f64>,
        acceleration: &PyReadonlyArray1<'py, f64>,
        max_harmonic: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (omega, acceleration) = (omega.as_slice()?, acceleration.as_slice()?);
        let (parallelism, cycle) = (parallelism(None), machine.strokes.cycle_angle());
        let columns = py
            .detach(|| {
                self.forces(machine.units)?
                    .orders_in_motion(cycle, omega, acceleration, max_harmonic, parallelism)?
                    .table(1.0, max_harmonic)
            })
            .map_err(to_py_err)?;
        order_columns(py, columns)
    }

    /// The four components (component-major) and, fifth, the torque the frame receives
    /// about the shaft axis (`core::frame_torque`, with `machine`'s gas forces and g).
    pub(crate) fn curves<'py>(
        &self,
        py: Python<'py>,
        machine: &core::Machine<'_>,
        phi: &PyReadonlyArray1<'py, f64>,
        omega: &PyReadonlyArray1<'py, f64>,
        acceleration: &PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (phi, omega, acceleration) =
            (phi.as_slice()?, omega.as_slice()?, acceleration.as_slice()?);
        let parallelism = parallelism(None);
        let points = phi.len();
        filled(py, OutputSize::of("phi", points).times(5), |out| {
            let (components, torque) = out.split_at_mut(4 * points);
            self.forces(machine.units)?.curves(
                phi,
                omega,
                acceleration,
                components,
                parallelism,
            )?;
            let gas = machine.piston_forces(phi)?;
            core::frame_torque(
                machine.units,
                phi,
                omega,
                acceleration,
                &gas,
                machine.g,
                torque,
            )
        })
    }
}

/// A table of orders as a dict of its `core::ORDER_COLUMNS`.
fn order_columns(py: Python<'_>, columns: Vec<Vec<f64>>) -> PyResult<Bound<'_, PyDict>> {
    let dict = PyDict::new(py);
    for (name, values) in core::ORDER_COLUMNS.iter().zip(columns) {
        dict.set_item(*name, PyArray1::from_vec(py, values))?;
    }
    Ok(dict)
}

/// Two arrays: a bearing load's horizontal and vertical components.
type ArrayPair<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

/// machine_bearing_loads(machine, phi, omega, acceleration, throw_of_unit, throw_position,
/// bearing_position, gravity=True) -> (horizontal, vertical): the force every main bearing
/// (at `bearing_position`, m, increasing) receives from the shaft (N), bearing-major
/// (bearings × phi), at the crank angles `phi` (rad) with the speed `omega` (rad/s) and
/// acceleration `acceleration` (rad/s²) there, one value per angle; unit j on throw
/// `throw_of_unit[j]` at `throw_position` (m); the machine's gas forces and (with `gravity`)
/// its weights.
#[pyfunction]
#[pyo3(signature = (
    machine, phi, omega, acceleration, throw_of_unit, throw_position, bearing_position,
    gravity=true
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn machine_bearing_loads<'py>(
    py: Python<'py>,
    machine: &Bound<'py, MotionMachine>,
    phi: PyReadonlyArray1<'py, f64>,
    omega: PyReadonlyArray1<'py, f64>,
    acceleration: PyReadonlyArray1<'py, f64>,
    throw_of_unit: Vec<usize>,
    throw_position: PyReadonlyArray1<'py, f64>,
    bearing_position: PyReadonlyArray1<'py, f64>,
    gravity: bool,
) -> PyResult<ArrayPair<'py>> {
    let machine = machine.get().machine_with(gravity);
    let (phi, omega, acceleration) = (phi.as_slice()?, omega.as_slice()?, acceleration.as_slice()?);
    let layout = core::BearingLayout::new(
        &throw_of_unit,
        throw_position.as_slice()?,
        bearing_position.as_slice()?,
    )
    .map_err(to_py_err)?;
    let parallelism = parallelism(None);
    let size = OutputSize::of("phi", phi.len()).times(layout.bearings());
    let (horizontal, vertical) = (empty_array(py, size)?, empty_array(py, size)?);
    {
        let (mut h, mut v) = (horizontal.readwrite(), vertical.readwrite());
        let (h, v) = (h.as_slice_mut()?, v.as_slice_mut()?);
        py.detach(|| {
            let gas = machine.piston_forces(phi)?;
            core::bearing_loads(
                machine.units,
                &layout,
                phi,
                omega,
                acceleration,
                &gas,
                machine.g,
                h,
                v,
                parallelism,
            )
        })
        .map_err(to_py_err)?;
    }
    Ok((horizontal, vertical))
}

/// machine_frame_sweep(machine, designs, outputs, omega, axial_position, throw_of_unit,
/// throw_position, bearing_position, parallel_threshold=None) -> {output: array}: the frame's
/// outputs (`core::FRAME_OUTPUTS`, those named in `outputs`) of every design (the motion
/// sweep's design columns, `designs`) at its speed (an `omega` column, else `omega`, rad/s)
/// held constant: free_force_1/2 (N) and free_moment_1/2 (N·m), the largest magnitude over a
/// cycle of the first- and second-order shaking force and moment, and max_bearing_load (N)
/// over the working cycle; units at `axial_position` (m), on the throws `throw_of_unit` at
/// `throw_position` between the bearings at `bearing_position` (m).
#[pyfunction]
#[pyo3(signature = (
    machine, designs, outputs, omega, axial_position, throw_of_unit, throw_position,
    bearing_position, parallel_threshold=None
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn machine_frame_sweep<'py>(
    py: Python<'py>,
    machine: &Bound<'py, MotionMachine>,
    designs: &Bound<'py, PyDict>,
    outputs: Vec<String>,
    omega: Option<f64>,
    axial_position: PyReadonlyArray1<'py, f64>,
    throw_of_unit: Vec<usize>,
    throw_position: PyReadonlyArray1<'py, f64>,
    bearing_position: PyReadonlyArray1<'py, f64>,
    parallel_threshold: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let machine = machine.get().machine();
    let asked = core::FrameOutputs::from_names(&outputs).map_err(to_py_err)?;
    let designs = MotionDesigns::extract(designs)?;
    let columns = designs.columns()?;
    let layout = core::BearingLayout::new(
        &throw_of_unit,
        throw_position.as_slice()?,
        bearing_position.as_slice()?,
    )
    .map_err(to_py_err)?;
    let axial_position = axial_position.as_slice()?;
    let parallelism = parallelism(parallel_threshold);
    let found = py
        .detach(|| {
            core::frame_sweep(
                &machine,
                omega,
                &columns,
                axial_position,
                &layout,
                asked,
                parallelism,
            )
        })
        .map_err(|error| motion_err(py, error))?;
    let dict = PyDict::new(py);
    for (name, column) in core::FRAME_OUTPUTS.iter().zip(found) {
        if outputs.iter().any(|o| o == name) {
            dict.set_item(*name, PyArray1::from_vec(py, column))?;
        }
    }
    Ok(dict)
}
