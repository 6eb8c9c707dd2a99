//! The orders of a machine's shaft torques, a `NativeMachine`'s method, answered by the core
//! with the GIL released.

use multicrank_core as core;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::conversion::named;
use crate::error::to_py_err;
use crate::machine::NativeMachine;

#[pymethods]
impl NativeMachine {
    /// torque_orders(omega, max_order, gravity=True) -> dict: the Fourier
    /// coefficients per revolution (N·m) of the machine's gas torque, inertia torque −½ J′ω² at
    /// the mean speed `omega` (rad/s) and gravity torque −U′, for the orders `order` = 0, 1/s,
    /// 2/s, … up to `max_order` (≥ 1; s = 1 two-stroke, 2 four-stroke): the arrays `order`,
    /// `gas_cos`, `gas_sin`, `inertia_cos`, `inertia_sin`, `gravity_cos`, `gravity_sin`, and
    /// the floats `inertia_scale`, `gravity_scale` (N·m), Σ_j max|M_j| of each unit's inertia
    /// and gravity torque alone. `gravity=False`: zero gravity orders and scale.
    #[pyo3(signature = (omega, max_order, gravity=true))]
    fn torque_orders<'py>(
        &self,
        py: Python<'py>,
        omega: f64,
        max_order: usize,
        gravity: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let found = py
            .detach(|| core::torque_orders(&self.core.view(), omega, max_order, gravity))
            .map_err(to_py_err)?;
        let dict = named(
            py,
            [
                ("order", found.order),
                ("gas_cos", found.gas_cos),
                ("gas_sin", found.gas_sin),
                ("inertia_cos", found.inertia_cos),
                ("inertia_sin", found.inertia_sin),
                ("gravity_cos", found.gravity_cos),
                ("gravity_sin", found.gravity_sin),
            ],
        )?;
        dict.set_item("inertia_scale", found.inertia_scale)?;
        dict.set_item("gravity_scale", found.gravity_scale)?;
        Ok(dict)
    }
}
