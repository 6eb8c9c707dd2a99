//! multicrank-core: gravitational potential energy U* and the generalised Lagrange force
//! Q_u* = dU*/dφ of multi-crank piston mechanisms, after M. Stańczak, with the corrections
//! of `shared/spec/mathematics.md`. Pure Rust; the Python bindings live in `rust/python`.
//!
//! Conventions: angles in radians; γ = +π/2 is an upright cylinder; φ is measured from
//! outer dead centre; every crank unit's energy is measured from its own ψ = 0 position;
//! energies are dimensionless, U* = U/(I_w ω²).

mod doubledouble;
pub mod engine;
pub mod error;
pub mod exact;
pub mod extrema;
pub mod grid;
pub mod harmonics;
pub mod mechanism;
pub mod parallel;
pub mod series;
pub mod sweep;
pub mod trig;

pub use engine::{Cylinder, Engine};
pub use error::{MechanismError, Result};
pub use exact::{evaluate, evaluate_one, Quantity};
pub use extrema::{all_energy_extrema, energy_extrema, EnergyExtrema};
pub use grid::{Phi, UniformGrid};
pub use harmonics::{
    fourier_coefficients, harmonic_survives, lambda_exact, lambda_paper, paper_coefficient,
    surviving_harmonics, PhaseSums,
};
pub use mechanism::{
    crank_phases, Acting, Design, Phases, PhysicalUnit, Strokes, STANDARD_GRAVITY,
};
pub use parallel::Parallelism;
pub use series::{
    build_series, evaluate_series, evaluate_series_or_exact, FourierSeries, SeriesKind,
};
pub use sweep::{sweep, PhaseSetTable, SweepOutputs, SweepRow};
