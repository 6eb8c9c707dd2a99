//! A periodic solution as every steady-state solver gives it (the energy method of
//! `balance`, the closed form of `square_law`): its numbers (`Periodic`), its speed and time at
//! requested angles (`Curves`), or the stall that refused it (`Stall`).

/// Why a solution was refused: the machine does not run at the state asked for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Stall {
    /// φ (rad) of the speed minimum (or of the worst angle).
    pub angle: f64,
}

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

/// A solution, or the stall that refused it.
pub(crate) type Solved = std::result::Result<Periodic, Stall>;
