//! Harmonics of Q_u* (docs/theory.md, "Fourier form and Λ_n", "Which harmonics survive"),
//! in two rooms: the coefficients Λ_n of
//! f(ψ) = (λ/2) sin 2ψ / √(1 − λ² sin² ψ) = Σ_{n even} Λ_n sin nψ — exact and as the paper's
//! λ-series — (`coefficients`), and the crank phase sums S_n = Σ_j e^{i n α_j} with the
//! rule of which harmonics survive them (`crank_sums`).

mod coefficients;
mod crank_sums;

pub(crate) use coefficients::{gcd, harmonic_width, ExactLambdas};
pub use coefficients::{
    harmonic_reach, lambda_exact, lambda_paper, lambda_table, paper_coefficient,
    PAPER_MAX_HARMONIC, PAPER_MAX_J,
};
pub use crank_sums::{harmonic_survives, surviving_harmonics, PhaseSums};

/// The highest harmonic any series here carries (λ → 1 would need ever more).
pub const MAX_HARMONIC: usize = 2048;
