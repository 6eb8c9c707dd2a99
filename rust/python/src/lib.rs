//! The `multicrank._native` extension: converts numpy arrays to slices, releases the GIL
//! around the core kernels and converts the results back. Broadcasting, coercion and the
//! user-facing conveniences live in the Python package (`python/multicrank/_api.py`).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use multicrank_core as core;
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

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

/// Work (points × cranks) from which kernels run on rayon's pool.
static PARALLEL_THRESHOLD: AtomicUsize = AtomicUsize::new(core::Parallelism::DEFAULT_THRESHOLD);
/// Set in a forked child: rayon's pool threads do not survive fork, so stay serial there.
static FORKED_CHILD: AtomicBool = AtomicBool::new(false);

fn parallelism() -> core::Parallelism {
    if FORKED_CHILD.load(Ordering::Relaxed) {
        core::Parallelism::SERIAL
    } else {
        core::Parallelism {
            threshold: PARALLEL_THRESHOLD.load(Ordering::Relaxed),
        }
    }
}

fn slice<'a>(array: &'a PyReadonlyArray1<'_, f64>) -> PyResult<&'a [f64]> {
    Ok(array.as_slice()?)
}

/// The crank angles: the points given, or a uniform grid (start, step, len) when the
/// Python side passes one (then `points` is empty and ignored).
fn phi_from(points: &[f64], uniform: Option<(f64, f64, usize)>) -> core::Result<core::Phi<'_>> {
    Ok(match uniform {
        Some((start, step, len)) => core::UniformGrid::new(start, step, len)?.into(),
        None => points.into(),
    })
}

/// A new float64 array of `len`, filled by `fill` with the GIL released. It is not zeroed
/// first: that would be a serial pass over the whole output before the (parallel) kernels,
/// which write every element anyway.
fn filled<'py>(
    py: Python<'py>,
    len: usize,
    fill: impl FnOnce(&mut [f64]) -> core::Result<()> + Send,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    // SAFETY: a fresh C-contiguous array that nothing else can see until it is returned;
    // `fill` writes all of it or fails, and then the array is dropped unseen.
    let array = unsafe { PyArray1::<f64>::new(py, len, false) };
    let buffer = unsafe { array.as_slice_mut() }?;
    py.detach(|| fill(buffer)).map_err(to_py_err)?;
    Ok(array)
}

/// Two arrays returned together, e.g. (u1, u2) or (a, b).
type ArrayPair<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

/// The number of crank angles: the grid's, or the points'.
fn phi_len(points: &[f64], uniform: Option<(f64, f64, usize)>) -> usize {
    uniform.map_or(points.len(), |(_, _, len)| len)
}

/// The slices of several arrays at once (design or unit columns).
fn slices<'a, const N: usize>(
    arrays: [&'a PyReadonlyArray1<'_, f64>; N],
) -> PyResult<[&'a [f64]; N]> {
    let mut out: [&[f64]; N] = [&[]; N];
    for (slot, array) in out.iter_mut().zip(arrays) {
        *slot = slice(array)?;
    }
    Ok(out)
}

/// The four broadcast design columns as validated designs.
fn designs_from(columns: [&[f64]; 4]) -> core::Result<Vec<core::Design>> {
    let n = columns[0].len();
    if let Some(bad) = columns.iter().find(|c| c.len() != n) {
        return Err(core::MechanismError::LengthMismatch {
            parameter: "design arrays",
            expected: n,
            found: bad.len(),
        });
    }
    (0..n)
        .map(|i| core::Design::new(columns[0][i], columns[1][i], columns[2][i], columns[3][i]))
        .collect()
}

/// The closed-form quantity named `name`, if it names one.
fn closed_form(name: &str) -> Option<core::Quantity> {
    match name {
        "potential_energy" => Some(core::Quantity::PotentialEnergy),
        "generalized_force" => Some(core::Quantity::GeneralizedForce),
        "force_derivative" => Some(core::Quantity::ForceDerivative),
        _ => None,
    }
}

const CLOSED_FORM_NAMES: &str = "\"potential_energy\", \"generalized_force\", \"force_derivative\"";

fn series_kind(method: &str) -> PyResult<core::SeriesKind> {
    match method {
        "exact" | "series" => Ok(core::SeriesKind::Exact),
        "paper" => Ok(core::SeriesKind::Paper),
        other => Err(MechanismError::new_err(format!(
            "method = {other:?} is not allowed; allowed: \"exact\", \"series\", \"paper\""
        ))),
    }
}

/// A validated engine from its per-unit columns.
fn engine_from(columns: [&[f64]; 5]) -> core::Result<core::Engine> {
    let n = columns[0].len();
    if let Some(bad) = columns.iter().find(|c| c.len() != n) {
        return Err(core::MechanismError::LengthMismatch {
            parameter: "cylinder arrays",
            expected: n,
            found: bad.len(),
        });
    }
    core::Engine::new(
        (0..n)
            .map(|i| core::Cylinder {
                phase: columns[0][i],
                inclination: columns[1][i],
                crank_ratio: columns[2][i],
                u1: columns[3][i],
                u2: columns[4][i],
            })
            .collect(),
    )
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

    /// evaluate(quantity, phi, crank_ratio, inclination, u1, u2, phases, uniform=None) ->
    /// flat array of length len(crank_ratio) * len(phi), design-major. The four design
    /// arrays are already broadcast to one length; `quantity` is "potential_energy",
    /// "generalized_force" or "force_derivative"; `uniform` = (start, step, len) evaluates
    /// on that uniform grid instead of `phi`.
    #[pyfunction]
    #[pyo3(signature = (quantity, phi, crank_ratio, inclination, u1, u2, phases, uniform=None))]
    #[allow(clippy::too_many_arguments)]
    fn evaluate<'py>(
        py: Python<'py>,
        quantity: &str,
        phi: PyReadonlyArray1<'py, f64>,
        crank_ratio: PyReadonlyArray1<'py, f64>,
        inclination: PyReadonlyArray1<'py, f64>,
        u1: PyReadonlyArray1<'py, f64>,
        u2: PyReadonlyArray1<'py, f64>,
        phases: PyReadonlyArray1<'py, f64>,
        uniform: Option<(f64, f64, usize)>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let quantity = closed_form(quantity).ok_or_else(|| {
            MechanismError::new_err(format!(
                "quantity = {quantity:?} is not allowed; allowed: {CLOSED_FORM_NAMES}"
            ))
        })?;
        let (phi, phases) = (slice(&phi)?, slice(&phases)?);
        let columns = slices([&crank_ratio, &inclination, &u1, &u2])?;
        let parallelism = parallelism();
        let len = columns[0].len() * phi_len(phi, uniform);
        filled(py, len, |out| {
            let phi = phi_from(phi, uniform)?;
            let phases = core::Phases::new(phases)?;
            let designs = designs_from(columns)?;
            core::evaluate(quantity, &designs, &phases, phi, out, parallelism)
        })
    }

    /// dimensionless_moments(...) over equal-length 1-D arrays -> (u1, u2); see
    /// `multicrank_core::PhysicalUnit::dimensionless_moments`.
    #[pyfunction]
    #[allow(clippy::too_many_arguments)]
    fn dimensionless_moments<'py>(
        py: Python<'py>,
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
    ) -> PyResult<ArrayPair<'py>> {
        let c = [
            slice(&crank_radius)?,
            slice(&rod_length)?,
            slice(&rod_cg)?,
            slice(&piston_mass)?,
            slice(&rod_mass)?,
            slice(&crank_mass)?,
            slice(&crank_cg_radius)?,
            slice(&counterweight_mass)?,
            slice(&counterweight_radius)?,
            slice(&shaft_inertia)?,
            slice(&rpm)?,
            slice(&g)?,
        ];
        let n = c[0].len();
        if let Some(bad) = c.iter().find(|col| col.len() != n) {
            return Err(to_py_err(core::MechanismError::LengthMismatch {
                parameter: "physical parameter arrays",
                expected: n,
                found: bad.len(),
            }));
        }
        let (u1, u2): (Vec<f64>, Vec<f64>) = (0..n)
            .map(|i| {
                core::PhysicalUnit {
                    crank_radius: c[0][i],
                    rod_length: c[1][i],
                    rod_cg: c[2][i],
                    piston_mass: c[3][i],
                    rod_mass: c[4][i],
                    crank_mass: c[5][i],
                    crank_cg_radius: c[6][i],
                    counterweight_mass: c[7][i],
                    counterweight_radius: c[8][i],
                    shaft_inertia: c[9][i],
                    rpm: c[10][i],
                    g: c[11][i],
                }
                .dimensionless_moments()
            })
            .collect::<core::Result<Vec<_>>>()
            .map_err(to_py_err)?
            .into_iter()
            .unzip();
        Ok((u1.into_pyarray(py), u2.into_pyarray(py)))
    }

    /// evaluate_series(method, phi, crank_ratio, inclination, u1, u2, phases, uniform=None)
    /// -> flat Q_u* from the Fourier form ("series": exact Λ_n to machine precision;
    /// "paper": eq. 16); `uniform` as in `evaluate`.
    #[pyfunction]
    #[pyo3(signature = (method, phi, crank_ratio, inclination, u1, u2, phases, uniform=None))]
    #[allow(clippy::too_many_arguments)]
    fn evaluate_series<'py>(
        py: Python<'py>,
        method: &str,
        phi: PyReadonlyArray1<'py, f64>,
        crank_ratio: PyReadonlyArray1<'py, f64>,
        inclination: PyReadonlyArray1<'py, f64>,
        u1: PyReadonlyArray1<'py, f64>,
        u2: PyReadonlyArray1<'py, f64>,
        phases: PyReadonlyArray1<'py, f64>,
        uniform: Option<(f64, f64, usize)>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let kind = series_kind(method)?;
        let (phi, phases) = (slice(&phi)?, slice(&phases)?);
        let columns = slices([&crank_ratio, &inclination, &u1, &u2])?;
        let parallelism = parallelism();
        let len = columns[0].len() * phi_len(phi, uniform);
        filled(py, len, |out| {
            let phi = phi_from(phi, uniform)?;
            let alphas = phases;
            let phases = core::Phases::new(alphas)?;
            let designs = designs_from(columns)?;
            let series = core::build_series(kind, &designs, alphas, parallelism);
            core::evaluate_series_or_exact(&series, &designs, &phases, phi, out, parallelism)
        })
    }

    /// lambda_coefficients(crank_ratio, n_max, method) -> flat (len(crank_ratio) * (n_max+1)),
    /// method "exact" or "paper". crank_ratio already validated.
    #[pyfunction]
    fn lambda_coefficients<'py>(
        py: Python<'py>,
        crank_ratio: PyReadonlyArray1<'py, f64>,
        n_max: usize,
        method: &str,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let kind = match method {
            "exact" => core::SeriesKind::Exact,
            "paper" => core::SeriesKind::Paper,
            other => {
                return Err(MechanismError::new_err(format!(
                    "method = {other:?} is not allowed; allowed: \"exact\", \"paper\""
                )))
            }
        };
        let lambdas = slice(&crank_ratio)?;
        let out = py.detach(|| {
            let mut out = vec![0.0; lambdas.len() * (n_max + 1)];
            for (row, &lambda) in out.chunks_mut(n_max + 1).zip(lambdas) {
                match kind {
                    core::SeriesKind::Exact => core::lambda_exact(lambda, row),
                    core::SeriesKind::Paper => core::lambda_paper(lambda, row),
                }
            }
            out
        });
        Ok(out.into_pyarray(py))
    }

    /// paper_coefficient(i, j) -> (numerator, denominator) of [λ^(2j+1)] Λ_(2i), exact.
    #[pyfunction]
    fn paper_coefficient(i: u32, j: u32) -> PyResult<(i64, u64)> {
        if j > 20 {
            return Err(MechanismError::new_err(format!(
                "j = {j} is out of range; allowed: 0 <= j <= 20"
            )));
        }
        Ok(core::paper_coefficient(i, j))
    }

    /// surviving_harmonics(cranks, strokes, acting, n_max) -> the n <= n_max that survive.
    #[pyfunction]
    fn surviving_harmonics(
        cranks: u64,
        strokes: i64,
        acting: &str,
        n_max: u64,
    ) -> PyResult<Vec<u64>> {
        let strokes = core::Strokes::from_count(strokes).map_err(to_py_err)?;
        let acting = core::Acting::from_name(acting).map_err(to_py_err)?;
        Ok(core::surviving_harmonics(cranks, strokes, acting, n_max))
    }

    /// fourier_coefficients(crank_ratio, inclination, u1, u2, phases, n_max) -> (a, b),
    /// each flat of length len(crank_ratio) * (n_max + 1).
    #[pyfunction]
    #[allow(clippy::too_many_arguments)]
    fn fourier_coefficients<'py>(
        py: Python<'py>,
        crank_ratio: PyReadonlyArray1<'py, f64>,
        inclination: PyReadonlyArray1<'py, f64>,
        u1: PyReadonlyArray1<'py, f64>,
        u2: PyReadonlyArray1<'py, f64>,
        phases: PyReadonlyArray1<'py, f64>,
        n_max: usize,
    ) -> PyResult<ArrayPair<'py>> {
        let phases = slice(&phases)?;
        let columns = slices([&crank_ratio, &inclination, &u1, &u2])?;
        let (a, b) = py
            .detach(|| -> core::Result<(Vec<f64>, Vec<f64>)> {
                core::Phases::new(phases)?;
                let designs = designs_from(columns)?;
                let sums = core::PhaseSums::new(phases, n_max.max(1));
                let width = n_max + 1;
                let mut a = vec![0.0; designs.len() * width];
                let mut b = vec![0.0; designs.len() * width];
                for ((design, a), b) in designs
                    .iter()
                    .zip(a.chunks_mut(width))
                    .zip(b.chunks_mut(width))
                {
                    core::fourier_coefficients(design, &sums, a, b);
                }
                Ok((a, b))
            })
            .map_err(to_py_err)?;
        Ok((a.into_pyarray(py), b.into_pyarray(py)))
    }

    /// energy_extrema(crank_ratio, inclination, u1, u2, phases) -> (min, min_at, max, max_at, range)
    /// of U_w* over one revolution, exact (roots of Q_u* polished by Newton).
    #[pyfunction]
    #[allow(clippy::type_complexity)]
    fn energy_extrema<'py>(
        py: Python<'py>,
        crank_ratio: PyReadonlyArray1<'py, f64>,
        inclination: PyReadonlyArray1<'py, f64>,
        u1: PyReadonlyArray1<'py, f64>,
        u2: PyReadonlyArray1<'py, f64>,
        phases: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<(
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
    )> {
        let alphas = slice(&phases)?;
        let columns = slices([&crank_ratio, &inclination, &u1, &u2])?;
        let parallelism = parallelism();
        let extrema = py
            .detach(|| -> core::Result<Vec<core::EnergyExtrema>> {
                let phases = core::Phases::new(alphas)?;
                let designs = designs_from(columns)?;
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
        let column = |f: fn(&core::EnergyExtrema) -> f64| {
            extrema.iter().map(f).collect::<Vec<_>>().into_pyarray(py)
        };
        Ok((
            column(|e| e.min),
            column(|e| e.min_at),
            column(|e| e.max),
            column(|e| e.max_at),
            column(|e| e.range),
        ))
    }

    /// sweep(crank_ratio, inclination, u1, u2, phase_set, set_phases, set_offsets, phi,
    /// force, energy, harmonic) -> (force_max_abs, force_rms, energy_min, energy_max,
    /// energy_range, leading_harmonic, leading_amplitude), one value per design (NaN where
    /// not asked).
    /// Phase set i is set_phases[set_offsets[i]..set_offsets[i+1]].
    #[pyfunction]
    #[allow(clippy::too_many_arguments, clippy::type_complexity)]
    fn sweep<'py>(
        py: Python<'py>,
        crank_ratio: PyReadonlyArray1<'py, f64>,
        inclination: PyReadonlyArray1<'py, f64>,
        u1: PyReadonlyArray1<'py, f64>,
        u2: PyReadonlyArray1<'py, f64>,
        phase_set: PyReadonlyArray1<'py, u32>,
        set_phases: PyReadonlyArray1<'py, f64>,
        set_offsets: PyReadonlyArray1<'py, u64>,
        phi: PyReadonlyArray1<'py, f64>,
        force: bool,
        energy: bool,
        harmonic: bool,
    ) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
        let columns = slices([&crank_ratio, &inclination, &u1, &u2])?;
        let phase_set = phase_set.as_slice()?;
        let (set_phases, set_offsets, phi) =
            (slice(&set_phases)?, set_offsets.as_slice()?, slice(&phi)?);
        let outputs = core::SweepOutputs {
            force,
            energy,
            harmonic,
        };
        let parallelism = parallelism();
        let rows = py
            .detach(|| -> core::Result<Vec<core::SweepRow>> {
                let designs = designs_from(columns)?;
                let sets = set_offsets
                    .windows(2)
                    .map(|w| {
                        set_phases
                            .get(w[0] as usize..w[1] as usize)
                            .map(<[f64]>::to_vec)
                    })
                    .collect::<Option<Vec<_>>>()
                    .ok_or(core::MechanismError::InvalidChoice {
                        parameter: "set_offsets",
                        value: format!("{set_offsets:?}"),
                        allowed: "ascending offsets into set_phases",
                    })?;
                let max_ratio = designs.iter().map(|d| d.crank_ratio).fold(0.0, f64::max);
                let table = core::PhaseSetTable::new(&sets, max_ratio)?;
                core::sweep(&designs, phase_set, &table, phi, outputs, parallelism)
            })
            .map_err(to_py_err)?;
        let fields: [fn(&core::SweepRow) -> f64; 7] = [
            |r| r.force_max_abs,
            |r| r.force_rms,
            |r| r.energy_min,
            |r| r.energy_max,
            |r| r.energy_range,
            |r| r.leading_harmonic,
            |r| r.leading_amplitude,
        ];
        Ok(fields
            .iter()
            .map(|f| rows.iter().map(f).collect::<Vec<_>>().into_pyarray(py))
            .collect())
    }

    /// engine_evaluate(quantity, phi, phase, inclination, crank_ratio, u1, u2, uniform=None)
    /// -> array like phi: "potential_energy", "generalized_force", "force_derivative"
    /// (closed form) or "series" (the machine-precision Fourier form) of a cylinder-level
    /// engine; `uniform` as in `evaluate`.
    #[pyfunction]
    #[pyo3(signature = (quantity, phi, phase, inclination, crank_ratio, u1, u2, uniform=None))]
    #[allow(clippy::too_many_arguments)]
    fn engine_evaluate<'py>(
        py: Python<'py>,
        quantity: &str,
        phi: PyReadonlyArray1<'py, f64>,
        phase: PyReadonlyArray1<'py, f64>,
        inclination: PyReadonlyArray1<'py, f64>,
        crank_ratio: PyReadonlyArray1<'py, f64>,
        u1: PyReadonlyArray1<'py, f64>,
        u2: PyReadonlyArray1<'py, f64>,
        uniform: Option<(f64, f64, usize)>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        // None: the series
        let quantity = match (quantity, closed_form(quantity)) {
            ("series", _) => None,
            (_, Some(q)) => Some(q),
            (other, None) => {
                return Err(MechanismError::new_err(format!(
                    "quantity = {other:?} is not allowed; allowed: {CLOSED_FORM_NAMES}, \"series\""
                )))
            }
        };
        let phi = slice(&phi)?;
        let columns = slices([&phase, &inclination, &crank_ratio, &u1, &u2])?;
        let parallelism = parallelism();
        filled(py, phi_len(phi, uniform), |out| {
            let phi = phi_from(phi, uniform)?;
            let engine = engine_from(columns)?;
            match quantity {
                Some(q) => engine.evaluate(q, phi, out, parallelism),
                None => engine.evaluate_series(phi, out, parallelism),
            }
        })
    }

    /// engine_fourier(phase, inclination, crank_ratio, u1, u2, n_max) -> (a, b).
    #[pyfunction]
    #[allow(clippy::too_many_arguments)]
    fn engine_fourier<'py>(
        py: Python<'py>,
        phase: PyReadonlyArray1<'py, f64>,
        inclination: PyReadonlyArray1<'py, f64>,
        crank_ratio: PyReadonlyArray1<'py, f64>,
        u1: PyReadonlyArray1<'py, f64>,
        u2: PyReadonlyArray1<'py, f64>,
        n_max: usize,
    ) -> PyResult<ArrayPair<'py>> {
        let columns = slices([&phase, &inclination, &crank_ratio, &u1, &u2])?;
        let (a, b) = py
            .detach(|| -> core::Result<(Vec<f64>, Vec<f64>)> {
                let engine = engine_from(columns)?;
                let (mut a, mut b) = (vec![0.0; n_max + 1], vec![0.0; n_max + 1]);
                engine.fourier_coefficients(&mut a, &mut b);
                Ok((a, b))
            })
            .map_err(to_py_err)?;
        Ok((a.into_pyarray(py), b.into_pyarray(py)))
    }

    /// engine_extrema(phase, inclination, crank_ratio, u1, u2) -> (min, min_at, max, max_at, range).
    #[pyfunction]
    fn engine_extrema<'py>(
        py: Python<'py>,
        phase: PyReadonlyArray1<'py, f64>,
        inclination: PyReadonlyArray1<'py, f64>,
        crank_ratio: PyReadonlyArray1<'py, f64>,
        u1: PyReadonlyArray1<'py, f64>,
        u2: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<(f64, f64, f64, f64, f64)> {
        let columns = slices([&phase, &inclination, &crank_ratio, &u1, &u2])?;
        let e = py
            .detach(|| engine_from(columns).map(|engine| engine.energy_extrema()))
            .map_err(to_py_err)?;
        Ok((e.min, e.min_at, e.max, e.max_at, e.range))
    }

    /// The work size (points × cranks) from which kernels run in parallel.
    #[pyfunction]
    fn get_parallel_threshold() -> usize {
        PARALLEL_THRESHOLD.load(Ordering::Relaxed)
    }

    /// Set the work size (points × cranks) from which kernels run in parallel;
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
