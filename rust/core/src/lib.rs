//! multicrank-core: gravitational potential energy U* and the generalised Lagrange force
//! Q_u* = dU*/dφ of multi-crank piston mechanisms, after M. Stańczak, with the corrections
//! listed in the project's `docs/theory.md`. Pure Rust; the Python bindings live in
//! `rust/python`.
//!
//! Conventions: angles in radians; γ = +π/2 is an upright cylinder; φ is measured from
//! outer dead centre; every crank unit's energy is measured from its own ψ = 0 position;
//! energies are dimensionless, U* = U/(I_w ω²).
//!
//! The rooms: `machine` (what a machine is, whole, checked once by `Machine::new`; everything
//! else borrows it), `mechanism` (validated parameters, a unit's `PhysicalCylinder`, phase sets,
//! physical → dimensionless),
//! `trig` and `doubledouble` (vectorisable sincos, double-double arithmetic), `angles`
//! (where the kernels get sin/cos: points, a shared table, a uniform grid), `exact` (the
//! closed-form kernels), `harmonics` (Λ_n, phase sums, surviving harmonics), `series` (the
//! one series model) and `series_kernels` (its SIMD evaluation), `engine` (units of any
//! layout; an in-line machine is an engine whose units share one design), `dynamics`
//! (reduced inertia, piston kinematics and gas torque in SI units), `extrema`
//! (δ_g), `tolerances` (scatter of harmonics), `sweep` (machines reduced on the fly),
//! `torsion` (the shaft's torsional chain and its modes), `parallel` and `error`.

#![forbid(unsafe_code)]

mod angles;
mod doubledouble;
mod dynamics;
mod engine;
mod error;
mod exact;
mod extrema;
mod forces;
mod harmonics;
mod machine;
mod mechanism;
mod motion;
mod parallel;
mod series;
mod series_kernels;
mod sweep;
#[cfg(test)]
mod test_support;
mod tolerances;
mod torsion;
mod trig;

pub use angles::{Phi, UniformGrid};
pub use dynamics::{Dynamics, Kinematics};
pub use engine::{Engine, EngineUnit};
pub use error::{MechanismError, Reach, Result};
pub use exact::{evaluate, evaluate_one, Quantity};
pub use extrema::{all_energy_extrema, energy_extrema, EnergyExtrema};
pub use forces::{
    bearing_loads, engine_centre, frame_torque, BearingLayout, BearingParts, ShakingForces,
    ShakingOrders, ORDER_COLUMNS, SAME_POSITION,
};
pub use harmonics::{
    harmonic_survives, lambda_exact, lambda_paper, lambda_table, paper_coefficient,
    surviving_harmonics, PhaseSums, PAPER_MAX_J,
};
pub use machine::{Machine, MachineParts};
pub use mechanism::{
    check_speed, crank_phases, dimensionless_moments, two_mass_rod_inertia, Acting, Design, Phases,
    PhysicalColumns, PhysicalCylinder, PhysicalUnit, Strokes, SPEED_LIMITS, STANDARD_GRAVITY,
};
pub use motion::size_shaft_inertia;
pub use motion::{
    flywheel_inertia, motion_sweep, net_piston_forces, square_law_flywheel_inertia,
    square_law_steady_state, steady_state, steady_state_curves, CycleArrays, FlywheelInertia,
    GasCylinder, MachineDesigns, MachineView, MotionColumns, MotionOutputs, PiecewisePolynomial,
    SolvedSteadyState, SteadyCurves, SteadyState, SteadyTables, UnitColumn, UnitField,
};
pub use motion::{torque_orders, TorqueOrders};
pub use motion::{FrameOutputs, BEARING_ANGLES, FRAME_OUTPUTS};
pub use parallel::Parallelism;
pub use series::{build_series, fourier_table, FourierSeries, SeriesKind};
pub use series_kernels::{evaluate_series, evaluate_series_or_exact};
pub use sweep::{sweep, sweep_engines, PhaseSetTable, SweepOutputs, SweepRow};
pub use tolerances::{HarmonicScatter, UnitErrors};
pub use torsion::{Chain, Modes};
