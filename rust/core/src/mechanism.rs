//! Validated descriptions of a multi-crank mechanism (docs/theory.md, "Crank phases", "Dimensionless moments"):
//! the dimensionless design (λ, γ, U1, U2), crank phase sets, and the conversion
//! from physical masses and lengths to the dimensionless gravity moments U1, U2.

use std::f64::consts::{PI, TAU};
use std::sync::LazyLock;

use crate::error::{check, check_finite, check_length, try_with_capacity, MechanismError, Result};

/// The speeds a machine may run at, ω [rad/s]: (π/30)·10⁻⁶ ≤ ω ≤ (π/30)·10⁸, i.e. 10⁻⁶ to
/// 10⁸ revolutions per minute (2π rad a revolution, 60 s a minute). The one rule for a speed:
/// every entry of the core checks a speed with [`check_speed`], and Python's
/// `multicrank._validation` reads these limits through the binding (`SPEED_LIMITS`).
pub const SPEED_LIMITS: (f64, f64) = (1e-6 * PI / 30.0, 1e8 * PI / 30.0);

/// The allowed range of a speed in words, from [`SPEED_LIMITS`].
static SPEED_ALLOWED: LazyLock<String> = LazyLock::new(|| {
    format!(
        "{:e} <= omega <= {:e} [rad/s]",
        SPEED_LIMITS.0, SPEED_LIMITS.1
    )
});

/// A speed ω [rad/s] named `name`: finite and within [`SPEED_LIMITS`], the one rule for a
/// speed.
pub fn check_speed(name: &'static str, omega: f64) -> Result<f64> {
    let allowed: &'static str = SPEED_ALLOWED.as_str();
    check(name, omega, allowed, |w| {
        (SPEED_LIMITS.0..=SPEED_LIMITS.1).contains(&w)
    })
}

/// A shaft's moment of inertia I_w [kg·m²]: > 0, as every use of one requires.
pub(crate) fn check_shaft_inertia(value: f64) -> Result<f64> {
    check("shaft_inertia", value, "shaft_inertia > 0", |i| i > 0.0)
}

/// Two- or four-stroke working cycle: one cycle spans T = 2π or 4π of crank angle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strokes {
    Two,
    Four,
}

impl Strokes {
    pub fn from_count(strokes: i64) -> Result<Self> {
        match strokes {
            2 => Ok(Self::Two),
            4 => Ok(Self::Four),
            other => Err(MechanismError::InvalidChoice {
                parameter: "strokes",
                value: other.to_string(),
                allowed: "2 or 4",
            }),
        }
    }

    /// The crank angle of one working cycle, T.
    pub fn cycle_angle(self) -> f64 {
        match self {
            Self::Two => TAU,
            Self::Four => 2.0 * TAU,
        }
    }
}

/// Single- or double-acting cylinders (a double-acting cylinder works on both piston faces).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Acting {
    Single,
    Double,
}

impl Acting {
    pub fn from_name(acting: &str) -> Result<Self> {
        match acting {
            "single" => Ok(Self::Single),
            "double" => Ok(Self::Double),
            other => Err(MechanismError::InvalidChoice {
                parameter: "acting",
                value: format!("{other:?}"),
                allowed: "\"single\" or \"double\"",
            }),
        }
    }
}

/// The crank phases α_j = j·α, j = 0 … k−1, of a regular in-line machine (eq. 8–12):
/// α = T/k for single-acting and T/(2k) for double-acting machines.
pub fn crank_phases(cranks: i64, strokes: Strokes, acting: Acting) -> Result<Vec<f64>> {
    if cranks < 1 {
        return Err(MechanismError::InvalidChoice {
            parameter: "cranks",
            value: cranks.to_string(),
            allowed: "an integer >= 1",
        });
    }
    let per_cycle = match acting {
        Acting::Single => cranks as f64,
        Acting::Double => 2.0 * cranks as f64,
    };
    let alpha = strokes.cycle_angle() / per_cycle;
    let mut phases = try_with_capacity("cranks", cranks, cranks as u128)?;
    phases.extend((0..cranks).map(|j| j as f64 * alpha));
    Ok(phases)
}

/// (sin γ, cos γ) of a cylinder's inclination, each exactly 0 where it is below the
/// rounding of γ itself.
///
/// γ reaches the library rounded to a double (π, π/2 and their multiples are not doubles),
/// so sin γ and cos γ are known only to about ε·|γ|: a horizontal cylinder typed as 180°
/// has sin γ = 1.2e-16 and would give a boxer gravity harmonics of 1e-17 that are rounding,
/// not physics. The rounding of γ (ε/2·|γ|) moves sin γ by up to ε/2·|γ|·|cos γ| and cos γ
/// by ε/2·|γ|·|sin γ|; a value within twice that of 0 cannot be told from 0 and is 0
/// (issue 13, item 9). A genuinely small γ keeps its sine (ε·|γ| < |sin γ| there).
pub(crate) fn inclination_sin_cos(gamma: f64) -> (f64, f64) {
    let (sin, cos) = gamma.sin_cos();
    let reach = f64::EPSILON * gamma.abs();
    let sin = if sin.abs() <= reach * cos.abs() {
        0.0
    } else {
        sin
    };
    let cos = if cos.abs() <= reach * sin.abs().max(f64::MIN_POSITIVE) {
        0.0
    } else {
        cos
    };
    (sin, cos)
}

/// One machine in dimensionless form: crank ratio λ = r/l, cylinder inclination γ to the
/// horizontal (rad, +π/2 upright), and the gravity moments U1 (reciprocating) and
/// U2 (rotating unbalance), both divided by I_w·ω².
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Design {
    pub crank_ratio: f64,
    pub inclination: f64,
    pub u1: f64,
    pub u2: f64,
}

impl Design {
    pub fn new(crank_ratio: f64, inclination: f64, u1: f64, u2: f64) -> Result<Self> {
        Ok(Self {
            crank_ratio: check("crank_ratio", crank_ratio, "0 <= crank_ratio < 1", |x| {
                (0.0..1.0).contains(&x)
            })?,
            inclination: check("inclination", inclination, "any finite real", |_| true)?,
            u1: check("u1", u1, "any finite real", |_| true)?,
            u2: check("u2", u2, "any finite real", |_| true)?,
        })
    }

    /// (sin γ, cos γ), rounding-level values exactly 0 (see [`inclination_sin_cos`]).
    pub(crate) fn inclination_sin_cos(&self) -> (f64, f64) {
        inclination_sin_cos(self.inclination)
    }
}

impl Design {
    /// Validated designs from four columns of equal length (the broadcast design arrays).
    pub fn from_columns(
        crank_ratio: &[f64],
        inclination: &[f64],
        u1: &[f64],
        u2: &[f64],
    ) -> Result<Vec<Self>> {
        for column in [inclination, u1, u2] {
            check_length("design arrays", crank_ratio.len(), column.len())?;
        }
        (0..crank_ratio.len())
            .map(|i| Self::new(crank_ratio[i], inclination[i], u1[i], u2[i]))
            .collect()
    }
}

/// A set of crank phases α_j kept as (cos α_j, sin α_j), so that every crank angle
/// ψ_j = φ + α_j follows from one sincos of φ by a rotation.
#[derive(Debug, Clone, PartialEq)]
pub struct Phases {
    pub(crate) cos: Vec<f64>,
    pub(crate) sin: Vec<f64>,
}

impl Phases {
    pub fn new(phases: &[f64]) -> Result<Self> {
        if phases.is_empty() {
            return Err(MechanismError::Empty {
                parameter: "phases",
            });
        }
        check_finite("phases", phases, "finite angles in radians")?;
        Ok(Self {
            cos: phases.iter().map(|a| a.cos()).collect(),
            sin: phases.iter().map(|a| a.sin()).collect(),
        })
    }

    /// The one phase α_j, as a set of its own.
    pub(crate) fn one(&self, j: usize) -> Self {
        Self {
            cos: vec![self.cos[j]],
            sin: vec![self.sin[j]],
        }
    }

    /// One crank at phase 0.
    pub fn single() -> Self {
        Self {
            cos: vec![1.0],
            sin: vec![0.0],
        }
    }

    pub fn len(&self) -> usize {
        self.cos.len()
    }

    pub fn is_empty(&self) -> bool {
        self.cos.is_empty()
    }
}

/// Standard gravity, m/s².
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// One slider-crank unit in SI units with its shaft's I_w (kg·m²), speed ω (rad/s) and g
/// (m/s²): the input of the dimensionless moments U1, U2 (eq. 1–7). The unit's phase,
/// inclination and `rod_inertia` do not enter them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhysicalUnit {
    /// The unit's geometry and moving masses.
    pub cylinder: PhysicalCylinder,
    pub shaft_inertia: f64,
    /// The shaft's speed ω [rad/s].
    pub omega: f64,
    pub g: f64,
}

/// One slider-crank unit's geometry and moving masses (SI: m, kg, kg·m², rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhysicalCylinder {
    pub crank_radius: f64,
    pub rod_length: f64,
    /// m_t: piston with rings and pin (and crosshead and piston rod where there are).
    pub piston_mass: f64,
    pub rod_mass: f64,
    /// z_k: the rod's centre of gravity, measured from the piston-pin axis.
    pub rod_cg: f64,
    /// I_k: the rod's moment of inertia about its own centre of gravity.
    pub rod_inertia: f64,
    /// This unit's crank web and counterweight: only their first moments enter (gravity);
    /// their inertia is part of the shaft's.
    pub crank_mass: f64,
    pub crank_cg_radius: f64,
    pub counterweight_mass: f64,
    pub counterweight_radius: f64,
    /// α_j: the unit's crank angle is ψ_j = φ + α_j.
    pub phase: f64,
    /// γ_j: its cylinder axis to the horizontal (+π/2 upright).
    pub inclination: f64,
}

/// I_k of the two-mass rod, m_k z_k (l − z_k) [kg·m²]: the rod whose mass, split between the
/// two pin axes in inverse proportion to their distances from its centre of gravity, has its
/// moment of inertia too (ΔI = 0). The default where a rod's own inertia is not known; never
/// negative for 0 ≤ z_k ≤ l.
pub fn two_mass_rod_inertia(rod_mass: f64, rod_length: f64, rod_cg: f64) -> f64 {
    rod_mass * rod_cg * (rod_length - rod_cg)
}

impl PhysicalCylinder {
    /// Every rule of a unit: its geometry and masses, I_k >= 0 and finite angles.
    pub(crate) fn validate(&self) -> Result<()> {
        // The geometry and mass rules are those of the dimensionless moments.
        self.validate_masses()?;
        check("rod_inertia", self.rod_inertia, "rod_inertia >= 0", |x| {
            x >= 0.0
        })?;
        check("phase", self.phase, "a finite angle in radians", |_| true)?;
        check(
            "inclination",
            self.inclination,
            "a finite angle in radians",
            |_| true,
        )?;
        Ok(())
    }

    /// The rules of the geometry and the masses (everything but I_w, the speed and g).
    pub(crate) fn validate_masses(&self) -> Result<()> {
        let positive = |x: f64| x > 0.0;
        let non_negative = |x: f64| x >= 0.0;
        check(
            "crank_radius",
            self.crank_radius,
            "crank_radius > 0",
            positive,
        )?;
        check(
            "rod_length",
            self.rod_length,
            "rod_length > crank_radius",
            |l| l > self.crank_radius,
        )?;
        check("rod_cg", self.rod_cg, "0 <= rod_cg <= rod_length", |z| {
            (0.0..=self.rod_length).contains(&z)
        })?;
        check(
            "piston_mass",
            self.piston_mass,
            "piston_mass >= 0",
            non_negative,
        )?;
        check("rod_mass", self.rod_mass, "rod_mass >= 0", non_negative)?;
        check(
            "crank_mass",
            self.crank_mass,
            "crank_mass >= 0",
            non_negative,
        )?;
        check(
            "crank_cg_radius",
            self.crank_cg_radius,
            "crank_cg_radius >= 0",
            non_negative,
        )?;
        check(
            "counterweight_mass",
            self.counterweight_mass,
            "counterweight_mass >= 0",
            non_negative,
        )?;
        check(
            "counterweight_radius",
            self.counterweight_radius,
            "counterweight_radius >= 0",
            non_negative,
        )?;
        Ok(())
    }

    /// The first moments [kg·m] whose weight makes U1 and U2 (eq. 5–7 without g/(I_w ω²)):
    /// r·[m_t + (l − z_k)/l · m_k] and r_s·m_s − r_p·m_p + r·(z_k/l)·m_k.
    pub(crate) fn moment_arms(&self) -> (f64, f64) {
        let rod_share_pin = self.rod_cg / self.rod_length;
        let rod_share_piston = (self.rod_length - self.rod_cg) / self.rod_length;
        (
            self.crank_radius * (self.piston_mass + rod_share_piston * self.rod_mass),
            self.crank_cg_radius * self.crank_mass
                - self.counterweight_radius * self.counterweight_mass
                + self.crank_radius * rod_share_pin * self.rod_mass,
        )
    }
}

impl PhysicalUnit {
    fn validate(&self) -> Result<()> {
        let positive = |x: f64| x > 0.0;
        self.cylinder.validate_masses()?;
        check(
            "shaft_inertia",
            self.shaft_inertia,
            "shaft_inertia > 0",
            positive,
        )?;
        check_speed("omega", self.omega)?;
        check("g", self.g, "any finite real", |_| true)?;
        Ok(())
    }

    /// The dimensionless gravity moments (U1, U2) of the corrected eq. 5–7:
    ///
    /// U1 = r·g·[m_t + (l − z_k)/l · m_k] / (I_w ω²),
    /// U2 = g·[r_s·m_s − r_p·m_p + r·(z_k/l)·m_k] / (I_w ω²).
    ///
    /// The rod's share that translates with the piston is (l − z_k)/l; the paper's
    /// printed eq. 5–6 swap the two shares (erratum 3).
    pub fn dimensionless_moments(&self) -> Result<(f64, f64)> {
        self.validate()?;
        let scale = self.g / (self.shaft_inertia * self.omega * self.omega);
        let (reciprocating, rotating) = self.cylinder.moment_arms();
        Ok((scale * reciprocating, scale * rotating))
    }
}

/// Columns of the `PhysicalUnit` fields that enter U1, U2 (its cylinder's and the shaft's),
/// one entry per unit, all of one length.
#[derive(Debug, Clone, Copy)]
pub struct PhysicalColumns<'a> {
    pub crank_radius: &'a [f64],
    pub rod_length: &'a [f64],
    pub rod_cg: &'a [f64],
    pub piston_mass: &'a [f64],
    pub rod_mass: &'a [f64],
    pub crank_mass: &'a [f64],
    pub crank_cg_radius: &'a [f64],
    pub counterweight_mass: &'a [f64],
    pub counterweight_radius: &'a [f64],
    pub shaft_inertia: &'a [f64],
    pub omega: &'a [f64],
    pub g: &'a [f64],
}

/// (U1, U2) of every unit of `columns` (see `PhysicalUnit::dimensionless_moments`).
pub fn dimensionless_moments(columns: &PhysicalColumns) -> Result<(Vec<f64>, Vec<f64>)> {
    let c = columns;
    let n = c.crank_radius.len();
    for column in [
        c.rod_length,
        c.rod_cg,
        c.piston_mass,
        c.rod_mass,
        c.crank_mass,
        c.crank_cg_radius,
        c.counterweight_mass,
        c.counterweight_radius,
        c.shaft_inertia,
        c.omega,
        c.g,
    ] {
        check_length("physical parameter arrays", n, column.len())?;
    }
    (0..n)
        .map(|i| {
            PhysicalUnit {
                cylinder: PhysicalCylinder {
                    crank_radius: c.crank_radius[i],
                    rod_length: c.rod_length[i],
                    rod_cg: c.rod_cg[i],
                    piston_mass: c.piston_mass[i],
                    rod_mass: c.rod_mass[i],
                    crank_mass: c.crank_mass[i],
                    crank_cg_radius: c.crank_cg_radius[i],
                    counterweight_mass: c.counterweight_mass[i],
                    counterweight_radius: c.counterweight_radius[i],
                    // Not in U1, U2.
                    rod_inertia: 0.0,
                    phase: 0.0,
                    inclination: 0.0,
                },
                shaft_inertia: c.shaft_inertia[i],
                omega: c.omega[i],
                g: c.g[i],
            }
            .dimensionless_moments()
        })
        .collect::<Result<Vec<_>>>()
        .map(|moments| moments.into_iter().unzip())
}

#[cfg(test)]
mod tests {
    use super::inclination_sin_cos;
    use std::f64::consts::{FRAC_PI_2, PI};

    #[test]
    fn inclinations_on_the_axes_have_an_exact_zero_and_small_ones_keep_their_sine() {
        for k in [-7.0, -2.0, -1.0, 1.0, 2.0, 3.0, 100.0, 1000.0] {
            let (s, c) = inclination_sin_cos(k * PI);
            assert_eq!(s, 0.0, "sin({k}π)");
            assert_eq!(c.abs(), 1.0);
            let (s, c) = inclination_sin_cos(k * PI + FRAC_PI_2);
            assert_eq!(c, 0.0, "cos({k}π + π/2)");
            assert_eq!(s.abs(), 1.0);
        }
        assert_eq!(inclination_sin_cos(0.0), (0.0, 1.0));
        for gamma in [1e-300, 1e-17, 1e-9, 2.0 * f64::EPSILON] {
            assert_eq!(inclination_sin_cos(gamma), gamma.sin_cos(), "{gamma}");
        }
        // A cylinder a nanoradian off upright is still off upright.
        let off = FRAC_PI_2 - 1e-9;
        assert_eq!(inclination_sin_cos(off), off.sin_cos());
    }

    use super::*;

    #[test]
    fn regular_phase_sets() {
        let two = crank_phases(4, Strokes::Two, Acting::Single).unwrap();
        assert_eq!(two, vec![0.0, PI / 2.0, PI, 1.5 * PI]);
        let four = crank_phases(4, Strokes::Four, Acting::Single).unwrap();
        assert_eq!(four, vec![0.0, PI, TAU, 3.0 * PI]);
        let double = crank_phases(2, Strokes::Two, Acting::Double).unwrap();
        assert_eq!(double, vec![0.0, PI / 2.0]);
        assert!(crank_phases(0, Strokes::Two, Acting::Single).is_err());
        // More phases than memory can hold: refused by name, not an abort.
        let error = crank_phases(i64::MAX, Strokes::Two, Acting::Single).unwrap_err();
        assert!(
            matches!(
                error,
                MechanismError::TooLarge {
                    parameter: "cranks",
                    ..
                }
            ),
            "{error}"
        );
        assert!(error.to_string().contains("9223372036854775807"));
    }

    #[test]
    fn design_ranges() {
        assert!(Design::new(0.0, 0.0, 0.0, 0.0).is_ok());
        assert!(Design::new(1.0, 0.0, 0.0, 0.0).is_err());
        assert!(Design::new(-0.1, 0.0, 0.0, 0.0).is_err());
        let err = Design::new(0.3, f64::NAN, 0.0, 0.0).unwrap_err();
        assert!(err.to_string().contains("inclination"));
        assert!(Design::new(0.3, 0.0, f64::INFINITY, 0.0).is_err());
    }
}
