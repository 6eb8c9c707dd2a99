//! The physical machine in SI units: potential energy, gravity torque and piston travel,
//! reduced inertia J(φ) and J′(φ), gas torque, and its dimensionless engine.

use multicrank_core as core;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::conversion::{empty_array, filled, named, MachineColumns, OutputSize, PhiArg};
use crate::error::to_py_err;
use crate::parallel::parallelism;

/// machine_evaluate(quantity, units, g, phi, parallel_threshold=None) -> flat array:
/// "potential_energy" U (J) or "gravity_torque" −dU/dφ (N·m) (like phi), or the piston
/// "travel" s (m) or "velocity" ds/dφ (m/rad) of every unit (unit-major, units × phi).
#[pyfunction]
#[pyo3(signature = (quantity, units, g, phi, parallel_threshold=None))]
pub(crate) fn machine_evaluate<'py>(
    py: Python<'py>,
    quantity: &str,
    units: MachineColumns<'py>,
    g: f64,
    phi: PhiArg<'py>,
    parallel_threshold: Option<usize>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (machine, phi) = (units.dynamics(g)?, phi.slice()?);
    let parallelism = parallelism(parallel_threshold);
    let points = OutputSize::of("phi", phi.len());
    let per_unit = |kinematics| (points.times(machine.len()), Some(kinematics));
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
        Some(k) => machine.kinematics(k, phi.phi()?, out, parallelism),
        None if gravity_torque => machine.gravity_torque(phi.phi()?, out, parallelism),
        None => machine.potential_energy(phi.phi()?, out, parallelism),
    })
}

/// machine_inertia(units, shaft_inertia, phi, parallel_threshold=None) ->
/// {"J", "dJ_dphi"}: the reduced moment of inertia (kg·m²) and its slope (kg·m²/rad).
#[pyfunction]
#[pyo3(signature = (units, shaft_inertia, phi, parallel_threshold=None))]
pub(crate) fn machine_inertia<'py>(
    py: Python<'py>,
    units: MachineColumns<'py>,
    shaft_inertia: f64,
    phi: PhiArg<'py>,
    parallel_threshold: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (machine, phi) = (units.dynamics(0.0)?, phi.slice()?);
    let parallelism = parallelism(parallel_threshold);
    let size = OutputSize::of("phi", phi.len());
    let (inertia, slope) = (empty_array(py, size)?, empty_array(py, size)?);
    {
        let (mut j, mut dj) = (inertia.readwrite(), slope.readwrite());
        let (j, dj) = (j.as_slice_mut()?, dj.as_slice_mut()?);
        py.detach(|| machine.reduced_inertia(shaft_inertia, phi.phi()?, j, dj, parallelism))
            .map_err(to_py_err)?;
    }
    let dict = PyDict::new(py);
    dict.set_item("J", inertia)?;
    dict.set_item("dJ_dphi", slope)?;
    Ok(dict)
}

/// machine_gas_torque(units, phi, forces, parallel_threshold=None) -> Σ_j F_j s'_j (N·m);
/// `forces` (N) are unit-major (units × phi), positive toward the shaft.
#[pyfunction]
#[pyo3(signature = (units, phi, forces, parallel_threshold=None))]
pub(crate) fn machine_gas_torque<'py>(
    py: Python<'py>,
    units: MachineColumns<'py>,
    phi: PhiArg<'py>,
    forces: PyReadonlyArray1<'py, f64>,
    parallel_threshold: Option<usize>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (machine, phi, forces) = (units.dynamics(0.0)?, phi.slice()?, forces.as_slice()?);
    let parallelism = parallelism(parallel_threshold);
    filled(py, OutputSize::of("phi", phi.len()), |out| {
        machine.gas_torque(phi.phi()?, forces, out, parallelism)
    })
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

/// machine_engine(units, g, shaft_inertia, omega) -> the dimensionless engine's columns
/// {"phase", "inclination", "crank_ratio", "u1", "u2"} at the speed `omega` (rad/s).
#[pyfunction]
pub(crate) fn machine_engine<'py>(
    py: Python<'py>,
    units: MachineColumns<'py>,
    g: f64,
    shaft_inertia: f64,
    omega: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let engine = units
        .dynamics(g)?
        .dimensionless(shaft_inertia, omega)
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

/// two_mass_rod_inertia(rod_mass, rod_length, rod_cg) -> I_k (kg·m²) of the two-mass rod,
/// m_k z_k (l − z_k): the default of a cylinder whose rod inertia is not given.
#[pyfunction]
pub(crate) fn two_mass_rod_inertia(rod_mass: f64, rod_length: f64, rod_cg: f64) -> f64 {
    core::two_mass_rod_inertia(rod_mass, rod_length, rod_cg)
}
