//! The `multicrank._native` extension: borrows numpy arrays as slices, releases the GIL
//! around the core and returns fresh numpy arrays — with names where there are several.
//! Validation of values and all the mathematics live in the core (`multicrank-core`);
//! broadcasting, coercion and the user-facing conveniences in the Python package.
//!
//! Bundles: a design is a dict of four equal-length float64 arrays (`crank_ratio`,
//! `inclination`, `u1`, `u2`), an engine a dict of five (`phase`, `inclination`,
//! `crank_ratio`, `u1`, `u2`), φ either an array of points or a uniform grid
//! `(start, step, count)`. Every call that can run in parallel takes `parallel_threshold`
//! (work size from which it goes parallel; None = the global default).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use multicrank_core as core;
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::create_exception;
use pyo3::exceptions::{PyMemoryError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

create_exception!(
    multicrank,
    MechanismError,
    PyValueError,
    "Invalid mechanism description or evaluation request; the message names the parameter \
     and its allowed range."
);

fn to_py_err(error: core::MechanismError) -> PyErr {
    MechanismError::new_err(error.to_string())
}

/// Work (points × cranks) from which kernels run on rayon's pool, unless a call says.
static PARALLEL_THRESHOLD: AtomicUsize = AtomicUsize::new(core::Parallelism::DEFAULT_THRESHOLD);
/// Set in a forked child: rayon's pool threads do not survive fork, so stay serial there.
static FORKED_CHILD: AtomicBool = AtomicBool::new(false);

fn parallelism(threshold: Option<usize>) -> core::Parallelism {
    if FORKED_CHILD.load(Ordering::Relaxed) {
        core::Parallelism::SERIAL
    } else {
        core::Parallelism {
            threshold: threshold.unwrap_or_else(|| PARALLEL_THRESHOLD.load(Ordering::Relaxed)),
        }
    }
}

/// The crank angles of an evaluation: points, or a uniform grid (start, step, count).
#[derive(FromPyObject)]
enum PhiArg<'py> {
    Grid((f64, f64, usize)),
    Points(PyReadonlyArray1<'py, f64>),
}

/// `PhiArg` borrowed, ready to cross into a detached closure.
#[derive(Clone, Copy)]
enum PhiSlice<'a> {
    Grid(f64, f64, usize),
    Points(&'a [f64]),
}

impl PhiArg<'_> {
    fn slice(&self) -> PyResult<PhiSlice<'_>> {
        Ok(match self {
            Self::Grid((start, step, count)) => PhiSlice::Grid(*start, *step, *count),
            Self::Points(points) => PhiSlice::Points(points.as_slice()?),
        })
    }
}

impl<'a> PhiSlice<'a> {
    fn len(self) -> usize {
        match self {
            Self::Grid(_, _, count) => count,
            Self::Points(points) => points.len(),
        }
    }

    fn phi(self) -> core::Result<core::Phi<'a>> {
        Ok(match self {
            Self::Grid(start, step, count) => core::UniformGrid::new(start, step, count)?.into(),
            Self::Points(points) => points.into(),
        })
    }
}

/// Designs as four broadcast columns of one length.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
struct DesignColumns<'py> {
    crank_ratio: PyReadonlyArray1<'py, f64>,
    inclination: PyReadonlyArray1<'py, f64>,
    u1: PyReadonlyArray1<'py, f64>,
    u2: PyReadonlyArray1<'py, f64>,
}

impl DesignColumns<'_> {
    fn slices(&self) -> PyResult<[&[f64]; 4]> {
        Ok([
            self.crank_ratio.as_slice()?,
            self.inclination.as_slice()?,
            self.u1.as_slice()?,
            self.u2.as_slice()?,
        ])
    }
}

fn designs([crank_ratio, inclination, u1, u2]: [&[f64]; 4]) -> core::Result<Vec<core::Design>> {
    core::Design::from_columns(crank_ratio, inclination, u1, u2)
}

/// An engine as five per-unit columns of one length.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
struct EngineColumns<'py> {
    phase: PyReadonlyArray1<'py, f64>,
    inclination: PyReadonlyArray1<'py, f64>,
    crank_ratio: PyReadonlyArray1<'py, f64>,
    u1: PyReadonlyArray1<'py, f64>,
    u2: PyReadonlyArray1<'py, f64>,
}

impl EngineColumns<'_> {
    /// The validated engine (O(units): built with the GIL held).
    fn engine(&self) -> PyResult<core::Engine> {
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
struct PhysicalArrays<'py> {
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
    fn columns(&self) -> PyResult<core::PhysicalColumns<'_>> {
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
struct MachineColumns<'py> {
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
    fn dynamics(&self, g: f64) -> PyResult<core::Dynamics> {
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
struct OutputSize {
    /// The parameter the size comes from (as the user named it).
    parameter: &'static str,
    /// Its value.
    value: usize,
    /// Values per unit of it (designs, units, ...).
    per_value: usize,
}

impl OutputSize {
    fn of(parameter: &'static str, value: usize) -> Self {
        Self {
            parameter,
            value,
            per_value: 1,
        }
    }

    fn times(self, per_value: usize) -> Self {
        Self { per_value, ..self }
    }

    fn too_large(self) -> PyErr {
        to_py_err(core::MechanismError::TooLarge {
            parameter: self.parameter,
            value: self.value.to_string(),
            elements: self.value as u128 * self.per_value as u128,
            item_bytes: std::mem::size_of::<f64>(),
        })
    }

    /// The number of values, or the error naming the parameter when it overflows.
    fn len(self) -> PyResult<usize> {
        self.value
            .checked_mul(self.per_value)
            .ok_or_else(|| self.too_large())
    }
}

/// A new, uninitialised float64 array of `size` values from numpy (whose allocation,
/// unlike an infallible Rust one, reports failure): a `MechanismError` naming the
/// parameter and the size when the memory cannot be had.
fn empty_array(py: Python<'_>, size: OutputSize) -> PyResult<Bound<'_, PyArray1<f64>>> {
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
fn filled<'py>(
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
fn named<'py>(
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
fn record_columns<'py, T>(
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

/// The output names a sweep was asked for, as the core knows them.
fn sweep_names(outputs: &[String]) -> PyResult<(core::SweepOutputs, Vec<&'static str>)> {
    let groups = core::SweepOutputs::from_names(outputs).map_err(to_py_err)?;
    let names = core::SweepRow::NAMES
        .into_iter()
        .filter(|name| outputs.iter().any(|o| o == name))
        .collect();
    Ok((groups, names))
}

fn series_kind(method: &str) -> PyResult<core::SeriesKind> {
    match method {
        "exact" | "series" => Ok(core::SeriesKind::Exact),
        "paper" => Ok(core::SeriesKind::Paper),
        other => Err(MechanismError::new_err(format!(
            "method = {other:?} is not allowed; allowed: \"exact\", \"series\", \"paper\""
        ))),
    }
}

/// What `evaluate` and `engine_evaluate` compute: a closed-form quantity, or Q_u* from a
/// Fourier form.
enum Evaluation {
    Closed(core::Quantity),
    Series(core::SeriesKind),
}

fn evaluation(quantity: &str) -> PyResult<Evaluation> {
    Ok(match quantity {
        "potential_energy" => Evaluation::Closed(core::Quantity::PotentialEnergy),
        "generalized_force" => Evaluation::Closed(core::Quantity::GeneralizedForce),
        "force_derivative" => Evaluation::Closed(core::Quantity::ForceDerivative),
        "series" | "paper" => Evaluation::Series(series_kind(quantity)?),
        other => {
            return Err(MechanismError::new_err(format!(
                "quantity = {other:?} is not allowed; allowed: \"potential_energy\", \
                 \"generalized_force\", \"force_derivative\", \"series\", \"paper\""
            )))
        }
    })
}

#[pymodule]
mod _native {
    use super::*;

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        m.add("MechanismError", m.py().get_type::<MechanismError>())?;
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        m.add(
            "build_profile",
            if cfg!(debug_assertions) {
                "debug"
            } else {
                "release"
            },
        )?;
        m.add("STANDARD_GRAVITY", core::STANDARD_GRAVITY)?;
        m.add("SWEEP_OUTPUTS", core::SweepRow::NAMES.to_vec())?;
        m.add("EXTREMA_FIELDS", core::EnergyExtrema::NAMES.to_vec())?;
        Ok(())
    }

    /// crank_phases(cranks, strokes, acting) -> the phases α_j (rad) of a regular machine.
    #[pyfunction]
    fn crank_phases<'py>(
        py: Python<'py>,
        cranks: i64,
        strokes: i64,
        acting: &str,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let strokes = core::Strokes::from_count(strokes).map_err(to_py_err)?;
        let acting = core::Acting::from_name(acting).map_err(to_py_err)?;
        let phases = core::crank_phases(cranks, strokes, acting).map_err(to_py_err)?;
        Ok(phases.into_pyarray(py))
    }

    /// evaluate(quantity, phi, design, phases, parallel_threshold=None) -> flat array of
    /// len(design) * len(phi), design-major: "potential_energy", "generalized_force",
    /// "force_derivative" (closed form), "series" (the machine-precision Fourier form) or
    /// "paper" (eq. 16).
    #[pyfunction]
    #[pyo3(signature = (quantity, phi, design, phases, parallel_threshold=None))]
    fn evaluate<'py>(
        py: Python<'py>,
        quantity: &str,
        phi: PhiArg<'py>,
        design: DesignColumns<'py>,
        phases: PyReadonlyArray1<'py, f64>,
        parallel_threshold: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let evaluation = evaluation(quantity)?;
        let (phi, columns, alphas) = (phi.slice()?, design.slices()?, phases.as_slice()?);
        let parallelism = parallelism(parallel_threshold);
        let size = OutputSize::of("phi", phi.len()).times(columns[0].len());
        filled(py, size, |out| {
            let (phi, phases, designs) =
                (phi.phi()?, core::Phases::new(alphas)?, designs(columns)?);
            match evaluation {
                Evaluation::Closed(q) => {
                    core::evaluate(q, &designs, &phases, phi, out, parallelism)
                }
                Evaluation::Series(kind) => {
                    let series = core::build_series(kind, &designs, alphas, parallelism);
                    core::evaluate_series_or_exact(
                        &series,
                        &designs,
                        &phases,
                        phi,
                        out,
                        parallelism,
                    )
                }
            }
        })
    }

    /// dimensionless_moments(units) -> {"u1", "u2"}: `units` holds equal-length arrays of
    /// every `PhysicalUnit` field (see `multicrank_core::PhysicalUnit::dimensionless_moments`).
    #[pyfunction]
    fn dimensionless_moments<'py>(
        py: Python<'py>,
        units: PhysicalArrays<'py>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let columns = units.columns()?;
        let (u1, u2) = py
            .detach(|| core::dimensionless_moments(&columns))
            .map_err(to_py_err)?;
        named(py, [("u1", u1), ("u2", u2)])
    }

    /// lambda_coefficients(crank_ratio, n_max, method, parallel_threshold=None) -> flat
    /// (len(crank_ratio) * (n_max + 1)), method "exact" or "paper".
    #[pyfunction]
    #[pyo3(signature = (crank_ratio, n_max, method, parallel_threshold=None))]
    fn lambda_coefficients<'py>(
        py: Python<'py>,
        crank_ratio: PyReadonlyArray1<'py, f64>,
        n_max: usize,
        method: &str,
        parallel_threshold: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let paper = match method {
            "exact" => false,
            "paper" => true,
            other => {
                return Err(MechanismError::new_err(format!(
                    "method = {other:?} is not allowed; allowed: \"exact\", \"paper\""
                )))
            }
        };
        let lambdas = crank_ratio.as_slice()?;
        let parallelism = parallelism(parallel_threshold);
        let table = py
            .detach(|| core::lambda_table(paper, lambdas, n_max, parallelism))
            .map_err(to_py_err)?;
        Ok(table.into_pyarray(py))
    }

    /// paper_coefficient(i, j) -> (numerator, denominator) of [λ^(2j+1)] Λ_(2i), exact.
    #[pyfunction]
    fn paper_coefficient(i: u32, j: u32) -> PyResult<(i128, u128)> {
        core::paper_coefficient(i, j).map_err(to_py_err)
    }

    /// surviving_harmonics(cranks, strokes, acting, n_max) -> the n <= n_max that survive,
    /// as a uint64 array (its size checked in the core before it is made).
    #[pyfunction]
    fn surviving_harmonics<'py>(
        py: Python<'py>,
        cranks: u64,
        strokes: i64,
        acting: &str,
        n_max: u64,
    ) -> PyResult<Bound<'py, PyArray1<u64>>> {
        let strokes = core::Strokes::from_count(strokes).map_err(to_py_err)?;
        let acting = core::Acting::from_name(acting).map_err(to_py_err)?;
        let harmonics = py
            .detach(|| core::surviving_harmonics(cranks, strokes, acting, n_max))
            .map_err(to_py_err)?;
        Ok(harmonics.into_pyarray(py))
    }

    /// fourier_coefficients(design, phases, n_max, parallel_threshold=None) -> {"a", "b"},
    /// each flat of len(design) * (n_max + 1).
    #[pyfunction]
    #[pyo3(signature = (design, phases, n_max, parallel_threshold=None))]
    fn fourier_coefficients<'py>(
        py: Python<'py>,
        design: DesignColumns<'py>,
        phases: PyReadonlyArray1<'py, f64>,
        n_max: usize,
        parallel_threshold: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (columns, alphas) = (design.slices()?, phases.as_slice()?);
        let parallelism = parallelism(parallel_threshold);
        let (a, b) = py
            .detach(|| core::fourier_table(&designs(columns)?, alphas, n_max, parallelism))
            .map_err(to_py_err)?;
        named(py, [("a", a), ("b", b)])
    }

    /// energy_extrema(design, phases, parallel_threshold=None) -> {"min", "min_at", "max",
    /// "max_at", "range"}: the exact extrema of U_w* over one revolution, per design.
    #[pyfunction]
    #[pyo3(signature = (design, phases, parallel_threshold=None))]
    fn energy_extrema<'py>(
        py: Python<'py>,
        design: DesignColumns<'py>,
        phases: PyReadonlyArray1<'py, f64>,
        parallel_threshold: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (columns, alphas) = (design.slices()?, phases.as_slice()?);
        let parallelism = parallelism(parallel_threshold);
        let extrema = py
            .detach(|| -> core::Result<Vec<core::EnergyExtrema>> {
                let (phases, designs) = (core::Phases::new(alphas)?, designs(columns)?);
                let series =
                    core::build_series(core::SeriesKind::Exact, &designs, alphas, parallelism);
                Ok(core::all_energy_extrema(
                    &designs,
                    &phases,
                    &series,
                    parallelism,
                ))
            })
            .map_err(to_py_err)?;
        record_columns(
            py,
            &extrema,
            &core::EnergyExtrema::NAMES,
            core::EnergyExtrema::get,
        )
    }

    /// sweep(design, phase_set, phase_sets, phi, outputs, parallel_threshold=None) ->
    /// {output: array}, one value per design: design i has the crank phases
    /// phase_sets[phase_set[i]]; `outputs` are names from SWEEP_OUTPUTS.
    #[pyfunction]
    #[pyo3(signature = (design, phase_set, phase_sets, phi, outputs, parallel_threshold=None))]
    fn sweep<'py>(
        py: Python<'py>,
        design: DesignColumns<'py>,
        phase_set: PyReadonlyArray1<'py, u32>,
        phase_sets: Vec<PyReadonlyArray1<'py, f64>>,
        phi: PyReadonlyArray1<'py, f64>,
        outputs: Vec<String>,
        parallel_threshold: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (groups, names) = sweep_names(&outputs)?;
        let (columns, phase_set, phi) = (design.slices()?, phase_set.as_slice()?, phi.as_slice()?);
        let sets = phase_sets
            .iter()
            .map(|set| Ok(set.as_slice()?.to_vec()))
            .collect::<PyResult<Vec<_>>>()?;
        let parallelism = parallelism(parallel_threshold);
        let rows = py
            .detach(|| -> core::Result<Vec<core::SweepRow>> {
                let designs = designs(columns)?;
                let max_ratio = designs.iter().map(|d| d.crank_ratio).fold(0.0, f64::max);
                let table = core::PhaseSetTable::new(&sets, max_ratio)?;
                core::sweep(&designs, phase_set, &table, phi, groups, parallelism)
            })
            .map_err(to_py_err)?;
        record_columns(py, &rows, &names, core::SweepRow::get)
    }

    /// sweep_engines(engines, phi, outputs, parallel_threshold=None) -> {output: array},
    /// one value per engine (a list of engine dicts).
    #[pyfunction]
    #[pyo3(signature = (engines, phi, outputs, parallel_threshold=None))]
    fn sweep_engines<'py>(
        py: Python<'py>,
        engines: Vec<EngineColumns<'py>>,
        phi: PyReadonlyArray1<'py, f64>,
        outputs: Vec<String>,
        parallel_threshold: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (groups, names) = sweep_names(&outputs)?;
        let engines = engines
            .iter()
            .map(EngineColumns::engine)
            .collect::<PyResult<Vec<_>>>()?;
        let phi = phi.as_slice()?;
        let parallelism = parallelism(parallel_threshold);
        let rows = py
            .detach(|| core::sweep_engines(&engines, phi, groups, parallelism))
            .map_err(to_py_err)?;
        record_columns(py, &rows, &names, core::SweepRow::get)
    }

    /// engine_evaluate(quantity, phi, engine, parallel_threshold=None) -> array like phi:
    /// "potential_energy", "generalized_force", "force_derivative" (closed form) or
    /// "series" (the machine-precision Fourier form) of an engine.
    #[pyfunction]
    #[pyo3(signature = (quantity, phi, engine, parallel_threshold=None))]
    fn engine_evaluate<'py>(
        py: Python<'py>,
        quantity: &str,
        phi: PhiArg<'py>,
        engine: EngineColumns<'py>,
        parallel_threshold: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let evaluation = match evaluation(quantity)? {
            Evaluation::Series(core::SeriesKind::Paper) => {
                return Err(MechanismError::new_err(
                    "quantity = \"paper\" is not allowed for an engine; allowed: \
                     \"potential_energy\", \"generalized_force\", \"force_derivative\", \"series\"",
                ))
            }
            other => other,
        };
        let (phi, engine) = (phi.slice()?, engine.engine()?);
        let parallelism = parallelism(parallel_threshold);
        filled(
            py,
            OutputSize::of("phi", phi.len()),
            |out| match evaluation {
                Evaluation::Closed(q) => engine.evaluate(q, phi.phi()?, out, parallelism),
                Evaluation::Series(_) => engine.evaluate_series(phi.phi()?, out, parallelism),
            },
        )
    }

    /// engine_fourier(engine, n_max) -> {"a", "b"}, each of length n_max + 1.
    #[pyfunction]
    fn engine_fourier<'py>(
        py: Python<'py>,
        engine: EngineColumns<'py>,
        n_max: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        let engine = engine.engine()?;
        let (a, b) = py
            .detach(|| engine.fourier_coefficients(n_max))
            .map_err(to_py_err)?;
        named(py, [("a", a), ("b", b)])
    }

    /// engine_extrema(engine) -> {"min", "min_at", "max", "max_at", "range"} (floats).
    #[pyfunction]
    fn engine_extrema<'py>(
        py: Python<'py>,
        engine: EngineColumns<'py>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let engine = engine.engine()?;
        let extrema = py.detach(|| engine.energy_extrema());
        let dict = PyDict::new(py);
        for name in core::EnergyExtrema::NAMES {
            dict.set_item(name, extrema.get(name))?;
        }
        Ok(dict)
    }

    /// engine_leading_harmonic(engine) -> {"n", "amplitude"}: the largest harmonic of
    /// Q_u* (n = 0, amplitude 0 when Q ≡ 0).
    #[pyfunction]
    fn engine_leading_harmonic<'py>(
        py: Python<'py>,
        engine: EngineColumns<'py>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let engine = engine.engine()?;
        let (n, amplitude) = py.detach(|| engine.leading_harmonic());
        let dict = PyDict::new(py);
        dict.set_item("n", n)?;
        dict.set_item("amplitude", amplitude)?;
        Ok(dict)
    }

    /// engine_sensitivity(engine, u1_rel, u2_rel, phase, n_max) -> {"n", "amplitude",
    /// "scatter_rms"}: harmonics n = 1 and even n <= n_max, nominal amplitude and the rms
    /// of their first-order scatter under independent unit errors.
    #[pyfunction]
    fn engine_sensitivity<'py>(
        py: Python<'py>,
        engine: EngineColumns<'py>,
        u1_rel: f64,
        u2_rel: f64,
        phase: f64,
        n_max: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        let engine = engine.engine()?;
        let errors = core::UnitErrors {
            u1_rel,
            u2_rel,
            phase,
        };
        let rows = py
            .detach(|| engine.harmonic_sensitivity(errors, n_max))
            .map_err(to_py_err)?;
        named(
            py,
            [
                ("n", rows.iter().map(|r| r.n as f64).collect()),
                ("amplitude", rows.iter().map(|r| r.amplitude).collect()),
                ("scatter_rms", rows.iter().map(|r| r.scatter_rms).collect()),
            ],
        )
    }

    /// machine_evaluate(quantity, units, g, phi, parallel_threshold=None) -> flat array:
    /// "potential_energy" U (J) or "gravity_torque" −dU/dφ (N·m) (like phi), or the piston
    /// "travel" s (m) or "velocity" ds/dφ (m/rad) of every unit (unit-major, units × phi).
    #[pyfunction]
    #[pyo3(signature = (quantity, units, g, phi, parallel_threshold=None))]
    fn machine_evaluate<'py>(
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
                return Err(MechanismError::new_err(format!(
                    "quantity = {other:?} is not allowed; allowed: \"potential_energy\", \
                     \"gravity_torque\", \"travel\", \"velocity\""
                )))
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
    fn machine_inertia<'py>(
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
    fn machine_gas_torque<'py>(
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

    /// machine_engine(units, g, shaft_inertia, rpm) -> the dimensionless engine's columns
    /// {"phase", "inclination", "crank_ratio", "u1", "u2"} at that speed.
    #[pyfunction]
    fn machine_engine<'py>(
        py: Python<'py>,
        units: MachineColumns<'py>,
        g: f64,
        shaft_inertia: f64,
        rpm: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let engine = units
            .dynamics(g)?
            .dimensionless(shaft_inertia, rpm)
            .map_err(to_py_err)?;
        let column = |f: fn(&core::Cylinder) -> f64| engine.cylinders().iter().map(f).collect();
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

    /// The work size (points × cranks) from which kernels run in parallel by default.
    #[pyfunction]
    fn get_parallel_threshold() -> usize {
        PARALLEL_THRESHOLD.load(Ordering::Relaxed)
    }

    /// Set the default work size (points × cranks) from which kernels run in parallel;
    /// 0 = always parallel, a huge value = always serial. Results do not depend on it.
    #[pyfunction]
    fn set_parallel_threshold(threshold: usize) {
        PARALLEL_THRESHOLD.store(threshold, Ordering::Relaxed);
    }

    /// Called in a forked child (os.register_at_fork): rayon's threads did not survive
    /// the fork, so every later call in this process runs serially.
    #[pyfunction]
    fn _after_fork_in_child() {
        FORKED_CHILD.store(true, Ordering::Relaxed);
    }
}
