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
//!
//! One file per domain, like the core: `conversion` (arguments and arrays, in one place),
//! `evaluation`, `harmonics`, `extrema`, `sweep`, `engine`, `machine` (the `NativeMachine`
//! class, owning a `core::Machine`: built once, its methods by domain in `machine`, `motion`,
//! `forces` and `orders`), `flywheel` (the core's flywheel search over a Python steady
//! state), `torsion` (the shaft's chain), `parallel` (thresholds and fork), `error`; this
//! file only assembles the module.

mod conversion;
mod engine;
mod error;
mod evaluation;
mod extrema;
mod flywheel;
mod forces;
mod harmonics;
mod machine;
mod motion;
mod motion_results;
mod orders;
mod parallel;
mod sweep;
mod torsion;

use pyo3::prelude::*;

#[pymodule]
mod _native {
    use multicrank_core as core;
    use pyo3::prelude::*;

    use crate::error::MechanismError;

    #[pymodule_export]
    use crate::engine::{
        engine_evaluate, engine_extrema, engine_fourier, engine_leading_harmonic,
        engine_sensitivity,
    };
    #[pymodule_export]
    use crate::evaluation::{crank_phases, dimensionless_moments, evaluate};
    #[pymodule_export]
    use crate::extrema::energy_extrema;
    #[pymodule_export]
    use crate::flywheel::size_shaft_inertia;
    #[pymodule_export]
    use crate::harmonics::{
        fourier_coefficients, lambda_coefficients, paper_coefficient, surviving_harmonics,
    };
    #[pymodule_export]
    use crate::machine::{
        bearing_layout, piston_forces, two_mass_rod_inertia, unit_travel, NativeMachine,
    };
    #[pymodule_export]
    use crate::motion_results::{FlywheelResult, SolvedSteady, SteadyResult};
    #[pymodule_export]
    use crate::parallel::{_after_fork_in_child, get_parallel_threshold, set_parallel_threshold};
    #[pymodule_export]
    use crate::sweep::{sweep, sweep_engines};
    #[pymodule_export]
    use crate::torsion::chain_modes;

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        crate::error::add_default_parameter(m.py())?;
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
        // (low, high) [rad/s]: the one rule for a speed, which the Python API checks with.
        m.add("SPEED_LIMITS", core::SPEED_LIMITS)?;
        m.add("SWEEP_OUTPUTS", core::SweepRow::NAMES.to_vec())?;
        m.add("EXTREMA_FIELDS", core::EnergyExtrema::NAMES.to_vec())?;
        m.add("MOTION_SWEEP_OUTPUTS", core::MotionOutputs::NAMES.to_vec())?;
        m.add("FRAME_OUTPUTS", core::FRAME_OUTPUTS.to_vec())?;
        m.add("SHAKING_ORDER_COLUMNS", core::ORDER_COLUMNS.to_vec())?;
        Ok(())
    }
}
