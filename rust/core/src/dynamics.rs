//! The machine in motion: the reduced moment of inertia J(φ), its slope J'(φ), the piston's
//! travel s(ψ) and velocity ratio s'(ψ), and the gas torque Σ_j F_j·s'(ψ_j) of physical
//! slider-crank units in SI units.
//!
//! The rod (mass m_k, centre of gravity z_k from the piston pin, moment of inertia I_k about
//! it) is replaced exactly by m_k1 = m_k (l − z_k)/l at the piston pin, m_k3 = m_k z_k/l at the
//! crank pin and ΔI = I_k − m_k z_k (l − z_k) turning with the rod angle β (sin β = λ sin ψ):
//! the same mass, first moment and moment of inertia as the rigid rod. So, with the
//! reciprocating mass m = m_t + m_k1,
//!
//!   J(φ)  = I_w + Σ_j [m_k3 r² + m s'(ψ_j)² + ΔI β'(ψ_j)²],
//!   J'(φ) = Σ_j [2 m s' s'' + 2 ΔI β' β''],
//!
//! with s' = r[sin ψ + λ sin ψ cos ψ / w], s'' = r[cos ψ + λ (cos 2ψ + λ² sin⁴ψ)/w³],
//! β' = λ cos ψ / w, β'' = −λ(1 − λ²) sin ψ / w³, w = √(1 − λ² sin²ψ). Each is a crank term
//! of `exact`'s block kernels, so it runs on the same vectorised sincos, rotations, angle
//! sources and threads as the gravity kernels.

use crate::angles::{Phi, PreparedPhi, Run, TableAngles};
use crate::engine::{Engine, EngineUnit};
use crate::error::{check, check_length, check_rows_length, MechanismError, Result};
use crate::exact::{crank_run, weighted_crank_run, CrankTerm, Quantity, RowWeights};
use crate::mechanism::{
    check_shaft_inertia, check_speed, two_mass_rod_inertia, Phases, PhysicalCylinder,
};
use crate::parallel::{for_each_row_segment, Parallelism};
use crate::trig::MulAdd;

/// What the kernels need of a unit: r, λ, λ², the reciprocating mass and ΔI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Slider {
    r: f64,
    lambda: f64,
    l2: f64,
    reciprocating: f64,
    delta_inertia: f64,
}

impl PhysicalCylinder {
    /// The gravity moments U1, U2 (J) of this unit (eq. 5–7 times I_w ω²: g times the
    /// moment arms), as the unit of an SI engine whose U* is U in joules.
    pub(crate) fn gravity_unit(&self, g: f64) -> EngineUnit {
        let (reciprocating, rotating) = self.moment_arms();
        EngineUnit {
            phase: self.phase,
            inclination: self.inclination,
            crank_ratio: self.crank_radius / self.rod_length,
            u1: g * reciprocating,
            u2: g * rotating,
        }
    }

    /// m_k3 = m_k z_k / l, the rod's share that turns with the crank pin.
    fn rod_share_pin(&self) -> f64 {
        self.rod_mass * self.rod_cg / self.rod_length
    }

    fn slider(&self) -> Slider {
        let lambda = self.crank_radius / self.rod_length;
        let rod_share_piston = self.rod_mass * (self.rod_length - self.rod_cg) / self.rod_length;
        Slider {
            r: self.crank_radius,
            lambda,
            l2: lambda * lambda,
            reciprocating: self.piston_mass + rod_share_piston,
            delta_inertia: self.rod_inertia
                - two_mass_rod_inertia(self.rod_mass, self.rod_length, self.rod_cg),
        }
    }
}

/// w = √(1 − λ² sin²ψ) at sin ψ.
#[inline(always)]
fn root<M: MulAdd>(k: &Slider, s: f64) -> f64 {
    M::mul_add(-k.l2, s * s, 1.0).sqrt()
}

/// s'(ψ) = ds/dψ = r[sin ψ + λ sin ψ cos ψ / w].
struct Velocity;
/// s(ψ) = r[(1 − cos ψ) + λ sin²ψ/(1 + w)], the travel from outer dead centre (the stable
/// form of (1 − w)/λ: exact to the last bits as λ → 0).
struct Travel;
/// J_j − m_k3 r² = m s'² + ΔI β'².
struct Inertia;
/// J'_j = 2 m s' s'' + 2 ΔI β' β''.
struct InertiaSlope;

impl CrankTerm for Velocity {
    type Unit = Slider;
    #[inline(always)]
    fn term<M: MulAdd>(k: &Slider, s: f64, c: f64) -> f64 {
        k.r * M::mul_add(k.lambda * s, c / root::<M>(k, s), s)
    }
}

impl CrankTerm for Travel {
    type Unit = Slider;
    #[inline(always)]
    fn term<M: MulAdd>(k: &Slider, s: f64, c: f64) -> f64 {
        k.r * M::mul_add(k.lambda * s, s / (1.0 + root::<M>(k, s)), 1.0 - c)
    }
}

impl CrankTerm for Inertia {
    type Unit = Slider;
    #[inline(always)]
    fn term<M: MulAdd>(k: &Slider, s: f64, c: f64) -> f64 {
        let w = root::<M>(k, s);
        let velocity = k.r * M::mul_add(k.lambda * s, c / w, s);
        let rod_rate = k.lambda * c / w;
        M::mul_add(
            k.reciprocating * velocity,
            velocity,
            k.delta_inertia * rod_rate * rod_rate,
        )
    }
}

impl CrankTerm for InertiaSlope {
    type Unit = Slider;
    #[inline(always)]
    fn term<M: MulAdd>(k: &Slider, s: f64, c: f64) -> f64 {
        let s2 = s * s;
        let w2 = M::mul_add(-k.l2, s2, 1.0);
        let w = w2.sqrt();
        let w3 = w2 * w;
        let velocity = k.r * M::mul_add(k.lambda * s, c / w, s);
        let curvature = M::mul_add(k.l2, s2 * s2, M::mul_add(c, c, -s2));
        let acceleration = k.r * M::mul_add(k.lambda, curvature / w3, c);
        let rod_rate = k.lambda * c / w;
        let rod_acceleration = -k.lambda * (1.0 - k.l2) * s / w3;
        2.0 * M::mul_add(
            k.reciprocating * velocity,
            acceleration,
            k.delta_inertia * rod_rate * rod_acceleration,
        )
    }
}

/// The moving units of a machine, validated, ready for the kernels.
#[derive(Debug, Clone, PartialEq)]
pub struct Dynamics {
    sliders: Vec<Slider>,
    phases: Phases,
    /// Σ_j m_k3 r²: the rods' big-end shares, turning with the crank pins.
    rotating: f64,
    /// The units' gravity as an engine whose U1, U2 are in joules: its U* is U (J), its Q*
    /// is dU/dφ (N·m).
    gravity: Engine,
}

/// Which per-unit kinematic quantity `Dynamics::kinematics` evaluates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kinematics {
    /// s(ψ_j) (m), the piston travel from outer dead centre.
    Travel,
    /// s'(ψ_j) = ds/dφ (m/rad).
    Velocity,
}

impl Dynamics {
    /// The units of a machine under gravity `g` (m/s²) (0: none).
    pub fn new(units: &[PhysicalCylinder], g: f64) -> Result<Self> {
        if units.is_empty() {
            return Err(MechanismError::Empty {
                parameter: "cylinders",
            });
        }
        for unit in units {
            unit.validate()?;
        }
        check("g", g, "any finite real", |_| true)?;
        let phases: Vec<f64> = units.iter().map(|u| u.phase).collect();
        Ok(Self {
            sliders: units.iter().map(PhysicalCylinder::slider).collect(),
            phases: Phases::new(&phases)?,
            rotating: units
                .iter()
                .map(|u| u.rod_share_pin() * u.crank_radius * u.crank_radius)
                .sum(),
            gravity: Engine::new(units.iter().map(|u| u.gravity_unit(g)).collect())?,
        })
    }

    /// U(φ) (J): Σ m·g·height, each unit from its own ψ = 0 configuration.
    pub fn potential_energy<'a>(
        &self,
        phi: impl Into<Phi<'a>>,
        out: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        self.gravity
            .evaluate(Quantity::PotentialEnergy, phi, out, parallelism)
    }

    /// The gravity torque on the shaft, −dU/dφ (N·m).
    pub fn gravity_torque<'a>(
        &self,
        phi: impl Into<Phi<'a>>,
        out: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        self.negated_gravity(Quantity::GeneralizedForce, phi, out, parallelism)
    }

    /// The gravity torque's slope −U″ (N·m/rad), exact.
    pub fn gravity_torque_slope<'a>(
        &self,
        phi: impl Into<Phi<'a>>,
        out: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        self.negated_gravity(Quantity::ForceDerivative, phi, out, parallelism)
    }

    /// −`quantity` of the gravity engine: a torque on the shaft from U's derivatives.
    fn negated_gravity<'a>(
        &self,
        quantity: Quantity,
        phi: impl Into<Phi<'a>>,
        out: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        self.gravity.evaluate(quantity, phi, out, parallelism)?;
        out.iter_mut().for_each(|m| *m = -*m);
        Ok(())
    }

    /// The dimensionless engine of these units at the speed `omega` ω [rad/s] with shaft
    /// inertia I_w: U1, U2 divided by I_w ω².
    pub fn dimensionless(&self, shaft_inertia: f64, omega: f64) -> Result<Engine> {
        check_shaft_inertia(shaft_inertia)?;
        check_speed("omega", omega)?;
        let scale = shaft_inertia * omega * omega;
        Engine::new(
            self.gravity
                .cylinders()
                .iter()
                .map(|c| EngineUnit {
                    u1: c.u1 / scale,
                    u2: c.u2 / scale,
                    ..*c
                })
                .collect(),
        )
    }

    pub fn len(&self) -> usize {
        self.sliders.len()
    }

    pub fn is_empty(&self) -> bool {
        self.sliders.is_empty()
    }

    /// J(φ) (kg·m²) into `inertia` and J'(φ) (kg·m²/rad) into `slope`, with `shaft_inertia`
    /// I_w (everything that turns rigidly with the shaft) added to J.
    pub fn reduced_inertia<'a>(
        &self,
        shaft_inertia: f64,
        phi: impl Into<Phi<'a>>,
        inertia: &mut [f64],
        slope: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        check_shaft_inertia(shaft_inertia)?;
        self.inertia_with(
            shaft_inertia + self.rotating,
            phi,
            inertia,
            Some(slope),
            parallelism,
        )
    }

    /// J − I_w (kg·m²) and J′ (kg·m²/rad): the rods', pistons' and cranks' share of the
    /// reduced inertia, the same doubles whatever shaft it is later added to (the steady
    /// state's tables, made once for every I_w).
    pub(crate) fn inertia_beside_shaft<'a>(
        &self,
        phi: impl Into<Phi<'a>>,
        inertia: &mut [f64],
        slope: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        self.inertia_with(self.rotating, phi, inertia, Some(slope), parallelism)
    }

    /// J − I_w (kg·m²) alone, as [`Dynamics::inertia_beside_shaft`] gives it (the same
    /// doubles), without the slope: what ω(φ) = √(2E/J) needs.
    pub(crate) fn inertia_alone_beside_shaft(
        &self,
        phi: &[f64],
        inertia: &mut [f64],
    ) -> Result<()> {
        self.inertia_with(self.rotating, phi, inertia, None, Parallelism::SERIAL)
    }

    /// The sliders' varying inertia plus `constant` (kg·m²), and its slope (kg·m²/rad) where
    /// `slope` is given.
    fn inertia_with<'a>(
        &self,
        constant: f64,
        phi: impl Into<Phi<'a>>,
        inertia: &mut [f64],
        slope: Option<&mut [f64]>,
        parallelism: Parallelism,
    ) -> Result<()> {
        let phi = phi.into();
        check_length("inertia", phi.len(), inertia.len())?;
        if let Some(slope) = &slope {
            check_length("slope", phi.len(), slope.len())?;
        }
        let phi = PreparedPhi::new(phi, parallelism);
        let work = phi.len().saturating_mul(self.len());
        for_each_row_segment(inertia, phi.len(), work, parallelism, |_, col, segment| {
            let run = phi.run(col, segment.len());
            crank_run::<Inertia>(&self.sliders, &self.phases, run, segment);
            segment.iter_mut().for_each(|j| *j += constant);
        });
        if let Some(slope) = slope {
            for_each_row_segment(slope, phi.len(), work, parallelism, |_, col, segment| {
                let run = phi.run(col, segment.len());
                crank_run::<InertiaSlope>(&self.sliders, &self.phases, run, segment)
            });
        }
        Ok(())
    }

    /// s or s' of every unit at every φ, unit-major (`out[j * phi.len() + i]`).
    pub fn kinematics<'a>(
        &self,
        quantity: Kinematics,
        phi: impl Into<Phi<'a>>,
        out: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        let phi = phi.into();
        check_rows_length("out", self.len(), phi.len(), out.len())?;
        let phi = PreparedPhi::new(phi, parallelism);
        let work = out.len();
        for_each_row_segment(out, phi.len(), work, parallelism, |row, col, segment| {
            let unit = std::slice::from_ref(&self.sliders[row]);
            let phase = self.phases.one(row);
            let run = phi.run(col, segment.len());
            match quantity {
                Kinematics::Travel => crank_run::<Travel>(unit, &phase, run, segment),
                Kinematics::Velocity => crank_run::<Velocity>(unit, &phase, run, segment),
            }
        });
        Ok(())
    }

    /// The gas torque Σ_j F_j(φ_i)·s'(ψ_j) (N·m), given the net piston force of every unit at
    /// every φ (`forces`, unit-major like `kinematics`; positive pushes the piston toward
    /// the shaft, along increasing s).
    pub fn gas_torque<'a>(
        &self,
        phi: impl Into<Phi<'a>>,
        forces: &[f64],
        out: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        let phi = phi.into();
        let n = phi.len();
        check_rows_length("forces", self.len(), n, forces.len())?;
        check_length("out", n, out.len())?;
        let phi = PreparedPhi::new(phi, parallelism);
        let work = n.saturating_mul(self.len());
        for_each_row_segment(out, n, work, parallelism, |_, col, segment| {
            let run = phi.run(col, segment.len());
            let weights = RowWeights {
                values: forces,
                stride: n,
                first: col,
            };
            weighted_crank_run::<Velocity, _>(&self.sliders, &self.phases, run, weights, segment);
        });
        Ok(())
    }

    /// [`Dynamics::gas_torque`] at angles whose sines and cosines are given (`sin`, `cos`:
    /// [`sincos_table`](crate::trig::sincos_table) of them, the values the kernel would make
    /// of each point, so the same doubles), serially: the indicator rule a geometry sweep's
    /// designs share makes them once.
    pub(crate) fn gas_torque_on_table(
        &self,
        sin: &[f64],
        cos: &[f64],
        forces: &[f64],
        out: &mut [f64],
    ) -> Result<()> {
        let n = sin.len();
        check_length("cos", n, cos.len())?;
        check_rows_length("forces", self.len(), n, forces.len())?;
        check_length("out", n, out.len())?;
        let weights = RowWeights {
            values: forces,
            stride: n,
            first: 0,
        };
        let run = Run::Table(TableAngles { sin, cos });
        weighted_crank_run::<Velocity, _>(&self.sliders, &self.phases, run, weights, out);
        Ok(())
    }
}

#[cfg(test)]
mod tests;
