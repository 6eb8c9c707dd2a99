//! Arguments in, arrays out — the one place where Python objects become slices and
//! core values, and results become numpy arrays and dicts: φ as points or a uniform grid,
//! the design, engine, physical and machine bundles, output sizes checked before
//! allocation, arrays filled with the GIL released; a motion machine's gas tables and a
//! motion sweep's design columns.

use multicrank_core as core;
use numpy::{
    IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyMemoryError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error::{refused, to_py_err};

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

/// The gravity API's dimensionless designs (crank ratio λ, inclination, u1, u2: the fields
/// of a `core::Design`) as four broadcast columns of one length; a motion sweep's per-design
/// overrides of a physical machine are `MotionDesigns` (`core::MachineDesigns`).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct DimensionlessDesigns<'py> {
    crank_ratio: PyReadonlyArray1<'py, f64>,
    inclination: PyReadonlyArray1<'py, f64>,
    u1: PyReadonlyArray1<'py, f64>,
    u2: PyReadonlyArray1<'py, f64>,
}

impl DimensionlessDesigns<'_> {
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

/// The physical parameters of units, one column per field of `core::PhysicalColumns`.
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
    omega: PyReadonlyArray1<'py, f64>,
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
            omega: self.omega.as_slice()?,
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
    /// The units, one per row of the columns (their lengths checked; values are the core's
    /// to check).
    pub(crate) fn units(&self) -> PyResult<Vec<core::PhysicalCylinder>> {
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
        Ok((0..n)
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
            .collect())
    }

    /// The validated units under gravity `g` (O(units): built with the GIL held).
    pub(crate) fn dynamics(&self, g: f64) -> PyResult<core::Dynamics> {
        core::Dynamics::new(&self.units()?, g).map_err(to_py_err)
    }
}

/// One cylinder end's pressure: SciPy's `PPoly` arrays, the breakpoints x (m + 1) and the
/// coefficients c (K × m); None where that end has no gas.
pub(crate) type DiagramArg<'py> = Option<(PyReadonlyArray1<'py, f64>, PyReadonlyArray2<'py, f64>)>;

/// Where a diagram's two arrays lie in memory and how: data pointers, shapes and strides.
type ArraysKey = (
    *const f64,
    Vec<usize>,
    Vec<isize>,
    *const f64,
    Vec<usize>,
    Vec<isize>,
);

fn arrays_key(x: &PyReadonlyArray1<'_, f64>, c: &PyReadonlyArray2<'_, f64>) -> ArraysKey {
    let (x, c) = (x.as_array(), c.as_array());
    (
        x.as_ptr(),
        x.shape().to_vec(),
        x.strides().to_vec(),
        c.as_ptr(),
        c.shape().to_vec(),
        c.strides().to_vec(),
    )
}

/// A `PPoly`'s arrays (x, c) over one working cycle (`cycle`, rad) as the core's
/// piecewise polynomial, checked.
fn polynomial(
    x: &PyReadonlyArray1<'_, f64>,
    c: &PyReadonlyArray2<'_, f64>,
    cycle: f64,
) -> Result<core::PiecewisePolynomial, core::MechanismError> {
    let (x, c) = (x.as_array(), c.as_array());
    let pieces = x.len().saturating_sub(1);
    if c.ncols() != pieces {
        return Err(core::MechanismError::LengthMismatch {
            parameter: "coefficients (columns: one per piece)",
            expected: pieces,
            found: c.ncols(),
        });
    }
    // c_ki at k·m + i: the rows of c one after another, whatever its strides.
    core::PiecewisePolynomial::new(flat(x), flat(c), cycle)
}

/// An array's values in logical order: one copy of its memory where they already lie so
/// (ndarray's element walk took a V12's new machine a fifth of its time), else the walk.
fn flat<D: numpy::ndarray::Dimension>(array: numpy::ndarray::ArrayView<'_, f64, D>) -> Vec<f64> {
    array
        .as_slice()
        .map_or_else(|| array.iter().copied().collect(), <[f64]>::to_vec)
}

/// A driving torque's `PPoly` arrays (x, c) (N·m over one working cycle of `cycle` rad) as
/// the core's piecewise polynomial; None stays None. A bad table is a MechanismError
/// naming `drive`.
pub(crate) fn drive_table(
    table: &DiagramArg<'_>,
    cycle: f64,
) -> PyResult<Option<core::PiecewisePolynomial>> {
    table
        .as_ref()
        .map(|(x, c)| {
            polynomial(x, c, cycle).map_err(|error| refused("drive", format!("drive: {error}")))
        })
        .transpose()
}

/// A `LengthMismatch` naming `parameter` unless `found == expected`.
fn check_length(parameter: &'static str, expected: usize, found: usize) -> PyResult<()> {
    if found == expected {
        Ok(())
    } else {
        Err(to_py_err(core::MechanismError::LengthMismatch {
            parameter,
            expected,
            found,
        }))
    }
}

/// The gas of a machine's `units` units: per unit its bore D and piston-rod diameter d (m)
/// and the tables of its two ends (`head`: the `pressure`, `crank_end`: the
/// `pressure_crank_end`), as the core's cylinders and the distinct diagrams they index
/// (tables equal to the last bit are one diagram, so that units alike share their indicator
/// work). Each table is checked by the core against the working cycle `cycle` (rad); an
/// error names the end and the unit.
pub(crate) fn gas_tables(
    units: usize,
    bore: &[f64],
    piston_rod_diameter: &[f64],
    head: &[DiagramArg<'_>],
    crank_end: &[DiagramArg<'_>],
    cycle: f64,
) -> PyResult<(Vec<core::GasCylinder>, Vec<core::PiecewisePolynomial>)> {
    check_length("bore", units, bore.len())?;
    check_length("piston_rod_diameter", units, piston_rod_diameter.len())?;
    check_length("pressure", units, head.len())?;
    check_length("pressure_crank_end", units, crank_end.len())?;
    let mut diagrams: Vec<core::PiecewisePolynomial> = Vec::new();
    // The arrays converted so far, by where their data lie and how (pointers, shapes,
    // strides), with their diagram's index: the same arrays passed for several cylinders (the
    // packer passes one pair per distinct diagram: a V12 of one diagram passes one) are
    // converted and checked once.
    let mut seen: Vec<(ArraysKey, usize)> = Vec::new();
    let mut index =
        |end: &'static str, j: usize, table: &DiagramArg<'_>| -> PyResult<Option<usize>> {
            let Some((x, c)) = table else {
                return Ok(None);
            };
            let key = arrays_key(x, c);
            if let Some((_, i)) = seen.iter().find(|(k, _)| *k == key) {
                return Ok(Some(*i));
            }
            let named = |error: core::MechanismError| {
                refused(end, format!("{end} of cylinder {j}: {error}"))
            };
            let diagram = polynomial(x, c, cycle).map_err(named)?;
            let i = match diagrams.iter().position(|d| *d == diagram) {
                Some(i) => i,
                None => {
                    diagrams.push(diagram);
                    diagrams.len() - 1
                }
            };
            seen.push((key, i));
            Ok(Some(i))
        };
    let mut gas = Vec::with_capacity(units);
    for j in 0..units {
        gas.push(core::GasCylinder {
            bore: bore[j],
            piston_rod_diameter: piston_rod_diameter[j],
            head: index("pressure", j, &head[j])?,
            crank_end: index("pressure_crank_end", j, &crank_end[j])?,
        });
    }
    Ok((gas, diagrams))
}

/// A motion sweep's design columns by name (`core::MachineDesigns`'s fields, and
/// `"field[j]"` for a field of unit j alone), each a 1-D float64 array.
pub(crate) struct MotionDesigns<'py>(Vec<(String, PyReadonlyArray1<'py, f64>)>);

impl<'py> MotionDesigns<'py> {
    /// From a dict of column name → array (a value that is no float64 array is a
    /// `TypeError` naming its column).
    pub(crate) fn extract(designs: &Bound<'py, PyDict>) -> PyResult<Self> {
        let mut columns = Vec::with_capacity(designs.len());
        for (name, values) in designs.iter() {
            let name: String = name.extract()?;
            let values = values
                .extract::<PyReadonlyArray1<'py, f64>>()
                .map_err(|_| {
                    PyTypeError::new_err(format!(
                        "designs[{name:?}] must be a 1-D float64 array, not {}",
                        values
                            .get_type()
                            .name()
                            .map_or_else(|_| "?".to_owned(), |n| n.to_string())
                    ))
                })?;
            columns.push((name, values));
        }
        Ok(Self(columns))
    }

    /// The core's columns: as many designs as the first column is long (one, the base
    /// machine, without columns); a name the core does not know names `designs`.
    pub(crate) fn columns(&self) -> PyResult<core::MachineDesigns<'_>> {
        let count = match self.0.first() {
            Some((_, values)) => values.len(),
            None => 1,
        };
        let mut designs = core::MachineDesigns::new(count);
        for (name, values) in &self.0 {
            designs.set(name, values.as_slice()?).map_err(to_py_err)?;
        }
        Ok(designs)
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
