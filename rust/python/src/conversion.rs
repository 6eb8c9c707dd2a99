//! Arguments in, arrays out — the one place where Python objects become slices and
//! core values, and results become numpy arrays and dicts: φ as points or a uniform grid,
//! the design, engine, physical and machine bundles, output sizes checked before
//! allocation, arrays filled with the GIL released.

use multicrank_core as core;
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::PyMemoryError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error::to_py_err;

/// The crank angles of an evaluation: points, or a uniform grid (start, step, count).
#[derive(FromPyObject)]
pub(crate) enum PhiArg<'py> {
    Grid((f64, f64, usize)),
    Points(PyReadonlyArray1<'py, f64>),
}

/// `PhiArg` borrowed, ready to cross into a detached closure.
#[derive(Clone, Copy)]
pub(crate) enum PhiSlice<'a> {
    Grid(f64, f64, usize),
    Points(&'a [f64]),
}

impl PhiArg<'_> {
    pub(crate) fn slice(&self) -> PyResult<PhiSlice<'_>> {
        Ok(match self {
            Self::Grid((start, step, count)) => PhiSlice::Grid(*start, *step, *count),
            Self::Points(points) => PhiSlice::Points(points.as_slice()?),
        })
    }
}

impl<'a> PhiSlice<'a> {
    pub(crate) fn len(self) -> usize {
        match self {
            Self::Grid(_, _, count) => count,
            Self::Points(points) => points.len(),
        }
    }

    pub(crate) fn phi(self) -> core::Result<core::Phi<'a>> {
        Ok(match self {
            Self::Grid(start, step, count) => core::UniformGrid::new(start, step, count)?.into(),
            Self::Points(points) => points.into(),
        })
    }
}

/// Designs as four broadcast columns of one length.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct DesignColumns<'py> {
    crank_ratio: PyReadonlyArray1<'py, f64>,
    inclination: PyReadonlyArray1<'py, f64>,
    u1: PyReadonlyArray1<'py, f64>,
    u2: PyReadonlyArray1<'py, f64>,
}

impl DesignColumns<'_> {
    pub(crate) fn slices(&self) -> PyResult<[&[f64]; 4]> {
        Ok([
            self.crank_ratio.as_slice()?,
            self.inclination.as_slice()?,
            self.u1.as_slice()?,
            self.u2.as_slice()?,
        ])
    }
}

pub(crate) fn designs(
    [crank_ratio, inclination, u1, u2]: [&[f64]; 4],
) -> core::Result<Vec<core::Design>> {
    core::Design::from_columns(crank_ratio, inclination, u1, u2)
}

/// An engine as five per-unit columns of one length.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct EngineColumns<'py> {
    phase: PyReadonlyArray1<'py, f64>,
    inclination: PyReadonlyArray1<'py, f64>,
    crank_ratio: PyReadonlyArray1<'py, f64>,
    u1: PyReadonlyArray1<'py, f64>,
    u2: PyReadonlyArray1<'py, f64>,
}

impl EngineColumns<'_> {
    /// The validated engine (O(units): built with the GIL held).
    pub(crate) fn engine(&self) -> PyResult<core::Engine> {
        core::Engine::from_columns(
            self.phase.as_slice()?,
            self.inclination.as_slice()?,
            self.crank_ratio.as_slice()?,
            self.u1.as_slice()?,
            self.u2.as_slice()?,
        )
        .map_err(to_py_err)
    }
}

/// The physical parameters of units, one column per field of `core::PhysicalUnit`.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct PhysicalArrays<'py> {
    crank_radius: PyReadonlyArray1<'py, f64>,
    rod_length: PyReadonlyArray1<'py, f64>,
    rod_cg: PyReadonlyArray1<'py, f64>,
    piston_mass: PyReadonlyArray1<'py, f64>,
    rod_mass: PyReadonlyArray1<'py, f64>,
    crank_mass: PyReadonlyArray1<'py, f64>,
    crank_cg_radius: PyReadonlyArray1<'py, f64>,
    counterweight_mass: PyReadonlyArray1<'py, f64>,
    counterweight_radius: PyReadonlyArray1<'py, f64>,
    shaft_inertia: PyReadonlyArray1<'py, f64>,
    rpm: PyReadonlyArray1<'py, f64>,
    g: PyReadonlyArray1<'py, f64>,
}

impl PhysicalArrays<'_> {
    pub(crate) fn columns(&self) -> PyResult<core::PhysicalColumns<'_>> {
        Ok(core::PhysicalColumns {
            crank_radius: self.crank_radius.as_slice()?,
            rod_length: self.rod_length.as_slice()?,
            rod_cg: self.rod_cg.as_slice()?,
            piston_mass: self.piston_mass.as_slice()?,
            rod_mass: self.rod_mass.as_slice()?,
            crank_mass: self.crank_mass.as_slice()?,
            crank_cg_radius: self.crank_cg_radius.as_slice()?,
            counterweight_mass: self.counterweight_mass.as_slice()?,
            counterweight_radius: self.counterweight_radius.as_slice()?,
            shaft_inertia: self.shaft_inertia.as_slice()?,
            rpm: self.rpm.as_slice()?,
            g: self.g.as_slice()?,
        })
    }
}

/// The physical units of a machine, one column per field of `core::PhysicalCylinder`.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct MachineColumns<'py> {
    crank_radius: PyReadonlyArray1<'py, f64>,
    rod_length: PyReadonlyArray1<'py, f64>,
    piston_mass: PyReadonlyArray1<'py, f64>,
    rod_mass: PyReadonlyArray1<'py, f64>,
    rod_cg: PyReadonlyArray1<'py, f64>,
    rod_inertia: PyReadonlyArray1<'py, f64>,
    crank_mass: PyReadonlyArray1<'py, f64>,
    crank_cg_radius: PyReadonlyArray1<'py, f64>,
    counterweight_mass: PyReadonlyArray1<'py, f64>,
    counterweight_radius: PyReadonlyArray1<'py, f64>,
    phase: PyReadonlyArray1<'py, f64>,
    inclination: PyReadonlyArray1<'py, f64>,
}

impl MachineColumns<'_> {
    /// The validated units under gravity `g` (O(units): built with the GIL held).
    pub(crate) fn dynamics(&self, g: f64) -> PyResult<core::Dynamics> {
        let columns = [
            self.crank_radius.as_slice()?,
            self.rod_length.as_slice()?,
            self.piston_mass.as_slice()?,
            self.rod_mass.as_slice()?,
            self.rod_cg.as_slice()?,
            self.rod_inertia.as_slice()?,
            self.crank_mass.as_slice()?,
            self.crank_cg_radius.as_slice()?,
            self.counterweight_mass.as_slice()?,
            self.counterweight_radius.as_slice()?,
            self.phase.as_slice()?,
            self.inclination.as_slice()?,
        ];
        let n = columns[0].len();
        if let Some(bad) = columns.iter().find(|c| c.len() != n) {
            return Err(to_py_err(core::MechanismError::LengthMismatch {
                parameter: "cylinder arrays",
                expected: n,
                found: bad.len(),
            }));
        }
        let units: Vec<core::PhysicalCylinder> = (0..n)
            .map(|i| core::PhysicalCylinder {
                crank_radius: columns[0][i],
                rod_length: columns[1][i],
                piston_mass: columns[2][i],
                rod_mass: columns[3][i],
                rod_cg: columns[4][i],
                rod_inertia: columns[5][i],
                crank_mass: columns[6][i],
                crank_cg_radius: columns[7][i],
                counterweight_mass: columns[8][i],
                counterweight_radius: columns[9][i],
                phase: columns[10][i],
                inclination: columns[11][i],
            })
            .collect();
        core::Dynamics::new(&units, g).map_err(to_py_err)
    }
}

/// How many values an output holds, and which request asked for them: the size is checked
/// before anything is allocated or computed.
#[derive(Clone, Copy)]
pub(crate) struct OutputSize {
    /// The parameter the size comes from (as the user named it).
    parameter: &'static str,
    /// Its value.
    value: usize,
    /// Values per unit of it (designs, units, ...).
    per_value: usize,
}

impl OutputSize {
    pub(crate) fn of(parameter: &'static str, value: usize) -> Self {
        Self {
            parameter,
            value,
            per_value: 1,
        }
    }

    pub(crate) fn times(self, per_value: usize) -> Self {
        Self { per_value, ..self }
    }

    pub(crate) fn too_large(self) -> PyErr {
        to_py_err(core::MechanismError::TooLarge {
            parameter: self.parameter,
            value: self.value.to_string(),
            elements: self.value as u128 * self.per_value as u128,
            item_bytes: std::mem::size_of::<f64>(),
        })
    }

    /// The number of values, or the error naming the parameter when it overflows.
    pub(crate) fn len(self) -> PyResult<usize> {
        self.value
            .checked_mul(self.per_value)
            .ok_or_else(|| self.too_large())
    }
}

/// A new, uninitialised float64 array of `size` values from numpy (whose allocation,
/// unlike an infallible Rust one, reports failure): a `MechanismError` naming the
/// parameter and the size when the memory cannot be had.
pub(crate) fn empty_array(py: Python<'_>, size: OutputSize) -> PyResult<Bound<'_, PyArray1<f64>>> {
    let len = size.len()?;
    // numpy refuses more than isize::MAX bytes with a ValueError, and a failed allocation
    // with a MemoryError: both mean "too large" here.
    if len > isize::MAX as usize / std::mem::size_of::<f64>() {
        return Err(size.too_large());
    }
    match py.import("numpy")?.getattr("empty")?.call1((len,)) {
        Ok(array) => Ok(array.cast_into::<PyArray1<f64>>()?),
        Err(error) if error.is_instance_of::<PyMemoryError>(py) => Err(size.too_large()),
        Err(error) => Err(error),
    }
}

/// A new float64 array of `size` values, filled by `fill` with the GIL released. It is not
/// zeroed first: that would be a serial pass over the whole output before the (parallel)
/// kernels, which write every element anyway.
pub(crate) fn filled<'py>(
    py: Python<'py>,
    size: OutputSize,
    fill: impl FnOnce(&mut [f64]) -> core::Result<()> + Send,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let array = empty_array(py, size)?;
    {
        let mut writable = array.readwrite();
        let buffer = writable.as_slice_mut()?;
        py.detach(|| fill(buffer)).map_err(to_py_err)?;
    }
    Ok(array)
}

/// A dict of named float64 arrays.
pub(crate) fn named<'py>(
    py: Python<'py>,
    columns: impl IntoIterator<Item = (&'static str, Vec<f64>)>,
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (name, values) in columns {
        dict.set_item(name, values.into_pyarray(py))?;
    }
    Ok(dict)
}

/// The columns `names` of records that answer `get(name)`.
pub(crate) fn record_columns<'py, T>(
    py: Python<'py>,
    records: &[T],
    names: &[&'static str],
    get: impl Fn(&T, &str) -> Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    named(
        py,
        names.iter().map(|&name| {
            let column = records.iter().map(|r| get(r, name).unwrap_or(f64::NAN));
            (name, column.collect())
        }),
    )
}
