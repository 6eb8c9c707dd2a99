//! A periodic solution as every steady-state solver gives it (the energy method of
//! `balance`, the closed form of `square_law`), in one pattern (as SciPy's `solve_ivp` and
//! its `OdeSolver`s): every solver is a [`PeriodicSolver`] with one `solve`, and every
//! answer one [`Solution`] — its [`Status`] and `message`, its evaluation counts, its numbers
//! (`Periodic`) where it converged, the stall angle where it stalled, and its speed and time
//! at requested angles (`Curves`) where asked.

use crate::error::Result;

/// A periodic solution's numbers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Periodic {
    pub omega_mean: f64,
    pub period: f64,
    pub omega_max: f64,
    pub omega_min: f64,
    pub phi_max: f64,
    pub phi_min: f64,
    /// s: E at the worst angle (J); E(φ) = s + K̃(φ).
    pub margin: f64,
    /// E(0) (J).
    pub energy_at_zero: f64,
}

impl Periodic {
    /// ω_min ≤ ω_m ≤ ω_max to the last ulp. The time mean Φ/∫dφ/ω lies between the extreme
    /// speeds, but where ω hardly varies (δ at rounding level: a pure flywheel) the three are
    /// computed by different sums and the mean may round an ulp outside: the nearer extreme
    /// then takes the mean's value (never the other way), and where ω is the same everywhere
    /// (ω_max = ω_min) both do, so that δ stays 0.
    pub fn mean_inside(self) -> Self {
        if self.omega_max == self.omega_min {
            return Self {
                omega_max: self.omega_mean,
                omega_min: self.omega_mean,
                ..self
            };
        }
        Self {
            omega_max: self.omega_max.max(self.omega_mean),
            omega_min: self.omega_min.min(self.omega_mean),
            ..self
        }
    }

    pub fn delta(&self) -> f64 {
        (self.omega_max - self.omega_min) / self.omega_mean
    }
}

/// A solution's speed and time at requested angles.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Curves {
    /// ω(φ_i) (rad/s).
    pub omega: Vec<f64>,
    /// t(φ_i) (s), from φ = 0.
    pub time: Vec<f64>,
}

/// How a solve ended (SciPy's `status`: 0 is success).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Status {
    /// The periodic solution was found and runs (ω_min ≥ ratio·ω_m).
    Converged,
    /// The machine does not run at the state asked for: its speed would reach zero, or
    /// fall below ratio·ω_m.
    Stalled,
}

impl Status {
    /// SciPy's convention: 0 success (converged), 1 the machine stalled.
    pub fn code(self) -> i32 {
        match self {
            Self::Converged => 0,
            Self::Stalled => 1,
        }
    }
}

/// One solve's answer, whatever the solver.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Solution {
    /// Converged or stalled.
    pub status: Status,
    /// What happened, in words.
    pub message: &'static str,
    /// Evaluations of the function whose root is found (the energy method: the mean speed
    /// as a function of the margin s, each a quadrature of the period over the cycle);
    /// 0 for the closed form, which finds no root.
    pub nfev: usize,
    /// Of those, the root finder's own (Newton's steps after the first evaluation, or
    /// Brent's method's iterations where the bracket is searched; the rest bracket the
    /// root).
    pub nit: usize,
    /// The numbers where it converged.
    pub periodic: Option<Periodic>,
    /// φ (rad) of the speed minimum (or of the worst angle) where it stalled.
    pub stall_angle: Option<f64>,
    /// ω and t at the angles asked for (where it converged and angles were given).
    pub curves: Option<Curves>,
    /// The load's cycle mean (N·m): the constant "balance" load, or (1/Φ)∫cω² dφ of the
    /// square law (NaN where it stalled).
    pub mean_load: f64,
}

impl Solution {
    /// A converged solution, no counts yet.
    pub fn converged(periodic: Periodic, message: &'static str) -> Self {
        Self {
            status: Status::Converged,
            message,
            nfev: 0,
            nit: 0,
            periodic: Some(periodic),
            stall_angle: None,
            curves: None,
            mean_load: f64::NAN,
        }
    }

    /// A stall at `angle` (rad), no counts yet.
    pub fn stalled(angle: f64, message: &'static str) -> Self {
        Self {
            status: Status::Stalled,
            message,
            nfev: 0,
            nit: 0,
            periodic: None,
            stall_angle: Some(angle),
            curves: None,
            mean_load: f64::NAN,
        }
    }

    /// The same answer with its evaluation counts.
    pub fn counted(self, nfev: usize, nit: usize) -> Self {
        Self { nfev, nit, ..self }
    }

    /// δ where it converged.
    pub fn delta(&self) -> Option<f64> {
        self.periodic.map(|p| p.delta())
    }

    /// δ, NaN where it stalled.
    pub fn delta_or_nan(&self) -> f64 {
        self.delta().unwrap_or(f64::NAN)
    }
}

/// The messages of the solvers' answers.
pub(crate) mod message {
    /// The energy method's root in s found, and the machine runs.
    pub const ROOT_FOUND: &str =
        "the margin s giving the mean speed asked for was found; the machine runs";
    /// The closed form, and the machine runs.
    pub const CLOSED_FORM: &str = "the periodic solution in closed form; the machine runs";
    /// ω_min < ratio·ω_m.
    pub const CRAWLS: &str =
        "the machine stalls: its speed minimum falls below min_speed_ratio times the mean speed";
    /// E reaches zero.
    pub const STOPS: &str = "the machine stalls: its kinetic energy reaches zero within the cycle";
    /// No s gives the mean speed with ω_min ≥ ratio·ω_m.
    pub const NO_ROOT: &str =
        "the machine stalls: no margin s gives the mean speed asked for with min_speed_ratio kept";
}

/// A steady-state solver: one question (a load rule on a machine's tables, at a mean speed
/// where the load needs one), answered for any shaft inertia.
pub(crate) trait PeriodicSolver {
    /// The periodic solution with I_w = `shaft_inertia` (kg·m²) that stalls where ω_min <
    /// `ratio`·ω_m, with ω and t at `phi` (rad, each in [0, Φ]) where given.
    ///
    /// Errors: those of the tables' evaluations (and of the solver's set-up), not a stall.
    fn solve(&self, shaft_inertia: f64, ratio: f64, phi: Option<&[f64]>) -> Result<Solution>;

    /// δ with I_w = `shaft_inertia` (kg·m²), `None` where the machine stalls: what the
    /// flywheel search asks ([`inertia_for`]).
    ///
    /// [`inertia_for`]: super::flywheel::inertia_for
    fn delta_at(&self, shaft_inertia: f64, ratio: f64) -> Result<Option<f64>> {
        Ok(self.solve(shaft_inertia, ratio, None)?.delta())
    }
}

#[cfg(test)]
mod tests;
