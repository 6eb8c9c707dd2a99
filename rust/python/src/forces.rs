//! The forces on the frame of a `MotionMachine`: its shaking forces, made on first use, with
//! the orders last computed kept for the next call (the same machine asked again at another
//! speed scales them by ω² in the core without a new series).

use std::sync::{Arc, Mutex, OnceLock};

use multicrank_core as core;
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::conversion::{filled, OutputSize};
use crate::error::to_py_err;
use crate::parallel::parallelism;

/// A machine's units at their axial positions, their shaking forces (made on first use: a
/// machine asked only for its motion never pays for them) and the orders last computed.
pub(crate) struct ShakingCache {
    units: Vec<core::PhysicalCylinder>,
    axial_position: Vec<f64>,
    forces: OnceLock<core::ShakingForces>,
    orders: Mutex<Option<Arc<core::ShakingOrders>>>,
}

impl ShakingCache {
    pub(crate) fn new(units: Vec<core::PhysicalCylinder>, axial_position: Vec<f64>) -> Self {
        Self {
            units,
            axial_position,
            forces: OnceLock::new(),
            orders: Mutex::new(None),
        }
    }

    fn forces(&self) -> core::Result<&core::ShakingForces> {
        if let Some(forces) = self.forces.get() {
            return Ok(forces);
        }
        let made = core::ShakingForces::new(&self.units, &self.axial_position)?;
        Ok(self.forces.get_or_init(|| made))
    }

    /// The orders through `max_order`: those kept where they reach it, else computed (and
    /// kept). A poisoned lock only loses the cache.
    fn orders_through(&self, max_order: usize) -> core::Result<Arc<core::ShakingOrders>> {
        let kept = self.orders.lock().ok().and_then(|held| held.clone());
        if let Some(orders) = kept.filter(|o| o.max_order() >= max_order) {
            return Ok(orders);
        }
        let made = Arc::new(self.forces()?.orders(max_order)?);
        if let Ok(mut held) = self.orders.lock() {
            *held = Some(Arc::clone(&made));
        }
        Ok(made)
    }

    pub(crate) fn orders<'py>(
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

    pub(crate) fn orders_in_motion<'py>(
        &self,
        py: Python<'py>,
        cycle: f64,
        omega: &PyReadonlyArray1<'py, f64>,
        acceleration: &PyReadonlyArray1<'py, f64>,
        max_harmonic: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (omega, acceleration) = (omega.as_slice()?, acceleration.as_slice()?);
        let parallelism = parallelism(None);
        let columns = py
            .detach(|| {
                self.forces()?
                    .orders_in_motion(cycle, omega, acceleration, max_harmonic, parallelism)?
                    .table(1.0, max_harmonic)
            })
            .map_err(to_py_err)?;
        order_columns(py, columns)
    }

    pub(crate) fn curves<'py>(
        &self,
        py: Python<'py>,
        phi: &PyReadonlyArray1<'py, f64>,
        omega: &PyReadonlyArray1<'py, f64>,
        acceleration: &PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (phi, omega, acceleration) =
            (phi.as_slice()?, omega.as_slice()?, acceleration.as_slice()?);
        let parallelism = parallelism(None);
        filled(py, OutputSize::of("phi", phi.len()).times(4), |out| {
            self.forces()?
                .curves(phi, omega, acceleration, out, parallelism)
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
