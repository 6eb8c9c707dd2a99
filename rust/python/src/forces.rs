//! The forces on the frame of a `NativeMachine`: its shaking forces (the core makes them on
//! first use and keeps them), with the orders last computed kept for the next call (the same
//! machine asked again at another speed scales them by ω² in the core without a new series),
//! its bearing loads and the frame's outputs of a sweep.

use std::sync::Arc;

use multicrank_core as core;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::conversion::{empty_array, filled, MotionDesigns, OutputSize};
use crate::error::motion_err;
use crate::error::to_py_err;
use crate::machine::NativeMachine;
use crate::parallel::parallelism;

impl NativeMachine {
    /// The orders through `max_order`: those kept where they reach it, else computed (and
    /// kept). A poisoned lock only loses the cache.
    fn orders_through(&self, max_order: usize) -> core::Result<Arc<core::ShakingOrders>> {
        let kept = self.orders.lock().ok().and_then(|held| held.clone());
        if let Some(orders) = kept.filter(|o| o.max_order() >= max_order) {
            return Ok(orders);
        }
        let made = Arc::new(self.core.shaking_forces()?.orders(max_order)?);
        if let Ok(mut held) = self.orders.lock() {
            *held = Some(Arc::clone(&made));
        }
        Ok(made)
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

#[pymethods]
impl NativeMachine {
    /// shaking_reference() -> float: the engine centre z_ref (m) the shaking moments are taken
    /// about, `core::engine_centre` of the units' axial positions.
    fn shaking_reference(&self) -> f64 {
        core::engine_centre(self.core.axial_position())
    }

    /// shaking_orders(omega, max_order) -> {column: array}: the shaking forces and moments by
    /// order 1 … max_order at the constant speed `omega` (rad/s), the columns
    /// `core::ORDER_COLUMNS` (N, N·m, rad).
    fn shaking_orders<'py>(
        &self,
        py: Python<'py>,
        omega: f64,
        max_order: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        let columns = py
            .detach(|| self.orders_through(max_order)?.at(omega, max_order))
            .map_err(to_py_err)?;
        order_columns(py, columns)
    }

    /// shaking_orders_in_motion(omega, acceleration, max_harmonic) -> {column: array}: the
    /// harmonics 1 … max_harmonic of the working cycle of the shaking forces and moments
    /// while the machine runs at ω(φ) (rad/s) with ε(φ) (rad/s²), both sampled at N uniform
    /// angles jΦ/N of the cycle (N > 2·max_harmonic); the columns `core::ORDER_COLUMNS`.
    fn shaking_orders_in_motion<'py>(
        &self,
        py: Python<'py>,
        omega: PyReadonlyArray1<'py, f64>,
        acceleration: PyReadonlyArray1<'py, f64>,
        max_harmonic: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (omega, acceleration) = (omega.as_slice()?, acceleration.as_slice()?);
        let (parallelism, cycle) = (parallelism(None), self.core.strokes().cycle_angle());
        let columns = py
            .detach(|| {
                self.core
                    .shaking_forces()?
                    .orders_in_motion(cycle, omega, acceleration, max_harmonic, parallelism)?
                    .table(1.0, max_harmonic)
            })
            .map_err(to_py_err)?;
        order_columns(py, columns)
    }

    /// shaking_curves(phi, omega, acceleration) -> array (5 × phi, component-major): the
    /// vertical and horizontal forces (N), the pitch and yaw moments (N·m) and the torque the
    /// frame receives about the shaft axis (N·m) at each φ (rad) at the speed ω (rad/s) and
    /// acceleration ε (rad/s²) given there.
    fn shaking_curves<'py>(
        &self,
        py: Python<'py>,
        phi: PyReadonlyArray1<'py, f64>,
        omega: PyReadonlyArray1<'py, f64>,
        acceleration: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (phi, omega, acceleration) =
            (phi.as_slice()?, omega.as_slice()?, acceleration.as_slice()?);
        let parallelism = parallelism(None);
        let points = phi.len();
        filled(py, OutputSize::of("phi", points).times(5), |out| {
            let (components, torque) = out.split_at_mut(4 * points);
            self.core.shaking_forces()?.curves(
                phi,
                omega,
                acceleration,
                components,
                parallelism,
            )?;
            self.core.frame_torque(phi, omega, acceleration, torque)
        })
    }

    /// bearing_loads(phi, omega, acceleration, gravity=True) -> (horizontal, vertical): the
    /// force every main bearing receives from the shaft (N), bearing-major (bearings × phi),
    /// at the crank angles `phi` (rad) with the speed `omega` (rad/s) and acceleration
    /// `acceleration` (rad/s²) there, one value per angle; the machine's gas forces and (with
    /// `gravity`) its weights.
    #[pyo3(signature = (phi, omega, acceleration, gravity=true))]
    fn bearing_loads<'py>(
        &self,
        py: Python<'py>,
        phi: PyReadonlyArray1<'py, f64>,
        omega: PyReadonlyArray1<'py, f64>,
        acceleration: PyReadonlyArray1<'py, f64>,
        gravity: bool,
    ) -> PyResult<ArrayPair<'py>> {
        let (phi, omega, acceleration) =
            (phi.as_slice()?, omega.as_slice()?, acceleration.as_slice()?);
        let parallelism = parallelism(None);
        let size = OutputSize::of("phi", phi.len()).times(self.core.layout().bearings());
        let (horizontal, vertical) = (empty_array(py, size)?, empty_array(py, size)?);
        {
            let (mut h, mut v) = (horizontal.readwrite(), vertical.readwrite());
            let (h, v) = (h.as_slice_mut()?, v.as_slice_mut()?);
            py.detach(|| {
                self.core
                    .bearing_loads(phi, omega, acceleration, gravity, h, v, parallelism)
            })
            .map_err(to_py_err)?;
        }
        Ok((horizontal, vertical))
    }

    /// bearing_loads_at_speed(omega, pressure_scale, gravity) -> (horizontal, vertical): the
    /// loads (N, bearing-major) at the default angles (`core::BEARING_ANGLES` over the cycle)
    /// at the constant speed omega (rad/s), the gas forces times pressure_scale, from the
    /// parts the core keeps per machine (`core::Machine::bearing_loads_at_speed`).
    fn bearing_loads_at_speed<'py>(
        &self,
        py: Python<'py>,
        omega: f64,
        pressure_scale: f64,
        gravity: bool,
    ) -> PyResult<ArrayPair<'py>> {
        let size = OutputSize::of("phi", core::BEARING_ANGLES).times(self.core.layout().bearings());
        let (horizontal, vertical) = (empty_array(py, size)?, empty_array(py, size)?);
        {
            let (mut h, mut v) = (horizontal.readwrite(), vertical.readwrite());
            let (h, v) = (h.as_slice_mut()?, v.as_slice_mut()?);
            py.detach(|| {
                self.core
                    .bearing_loads_at_speed(omega, pressure_scale, gravity, h, v)
            })
            .map_err(to_py_err)?;
        }
        Ok((horizontal, vertical))
    }

    /// frame_sweep(designs, outputs, omega, parallel_threshold=None) -> {output: array}: the
    /// frame's outputs (`core::FRAME_OUTPUTS`, those named in `outputs`) of every design (the
    /// motion sweep's design columns, `designs`) at its speed (an `omega` column, else
    /// `omega`, rad/s) held constant: free_force_1/2 (N) and free_moment_1/2 (N·m), the
    /// largest magnitude over a cycle of the first- and second-order shaking force and
    /// moment, and max_bearing_load (N) over the working cycle.
    #[pyo3(signature = (designs, outputs, omega, parallel_threshold=None))]
    fn frame_sweep<'py>(
        &self,
        py: Python<'py>,
        designs: &Bound<'py, PyDict>,
        outputs: Vec<String>,
        omega: Option<f64>,
        parallel_threshold: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let asked = core::FrameOutputs::from_names(&outputs).map_err(to_py_err)?;
        let designs = MotionDesigns::extract(designs)?;
        let columns = designs.columns()?;
        let parallelism = parallelism(parallel_threshold);
        let found = py
            .detach(|| self.core.frame_sweep(omega, &columns, asked, parallelism))
            .map_err(|error| motion_err(py, error))?;
        let dict = PyDict::new(py);
        for (name, column) in core::FRAME_OUTPUTS.iter().zip(found) {
            if outputs.iter().any(|o| o == name) {
                dict.set_item(*name, PyArray1::from_vec(py, column))?;
            }
        }
        Ok(dict)
    }
}
