//! The shaking forces and moments of a machine: its four first-moment engines (vertical,
//! horizontal, and both weighted by the axial position) and what they give, by order at a
//! constant speed ([`ShakingOrders`]) and over φ at any speed and acceleration
//! ([`ShakingForces::curves`]).

use std::f64::consts::FRAC_PI_2;

use crate::angles::Phi;
use crate::engine::{Engine, EngineUnit};
use crate::error::{check, check_finite, check_length, MechanismError, Result};
use crate::exact::Quantity;
use crate::harmonics::MAX_HARMONIC;
use crate::mechanism::check_speed;
use crate::mechanism::PhysicalCylinder;
use crate::parallel::Parallelism;

/// The components, in the order every array here holds them: the vertical force (positive
/// upward), the horizontal force (positive toward a cylinder at γ = 0), the moment of the
/// vertical force about the horizontal axis through the engine centre z_ref
/// (Σ (z − z_ref) F_v: "pitch") and that of the horizontal force about the vertical axis
/// through it (Σ (z − z_ref) F_h: "yaw"); forces in N, moments in N·m. z_ref =
/// (z_min + z_max)/2 is the midpoint of the outermost units ([`engine_centre`]), so that
/// moving every unit along the shaft by the same distance changes no moment.
const COMPONENTS: [&str; 4] = [
    "force_vertical",
    "force_horizontal",
    "moment_pitch",
    "moment_yaw",
];

/// The columns of a table of orders ([`ShakingOrders::at`]), in order: each component's
/// amplitude √(a_n² + b_n²) and phase θ_n (the component is amplitude·cos(nφ − θ_n), θ_n in
/// (−π, π]), then the magnitudes of the parts of F_h + i F_v (and of M_yaw + i M_pitch) that
/// turn with the crank (e^{+inφ}: forward) and against it (e^{−inφ}: backward). A lone
/// rotating unbalance m·e gives a forward first order m·e·ω² and no backward one; the largest
/// magnitude of an order's force over the cycle is forward + backward.
pub const ORDER_COLUMNS: [&str; 12] = [
    "force_vertical",
    "force_vertical_phase",
    "force_horizontal",
    "force_horizontal_phase",
    "moment_pitch",
    "moment_pitch_phase",
    "moment_yaw",
    "moment_yaw_phase",
    "force_forward",
    "force_backward",
    "moment_forward",
    "moment_backward",
];

/// Where [`ORDER_COLUMNS`] holds the forward parts of the force and of the moment (the
/// backward part follows each).
pub(crate) const FORCE_FORWARD: usize = 8;
pub(crate) const MOMENT_FORWARD: usize = 10;

/// A machine's four first-moment engines: S_v, S_h, Σ z S_v, Σ z S_h (kg·m, kg·m²), each
/// unit's U1 = r·[m_t + (l − z_k)/l · m_k] and U2 = r_s m_s − r_p m_p + r (z_k/l) m_k.
#[derive(Debug, Clone, PartialEq)]
pub struct ShakingForces {
    engines: [Engine; 4],
    /// Per component, Σ_j (|U1_j| + |U2_j|) of its engine: no unit's S′ has a harmonic
    /// larger than a small multiple of its share, so what the sum leaves below
    /// `RESOLUTION` of it is rounding.
    scales: [f64; 4],
}

/// The engine centre z_ref = (z_min + z_max)/2 (m) of units at `axial_position`: the point
/// on the shaft the shaking moments are taken about (the textbooks' and the marine guides'
/// reference). A moment of an order that leaves no net force is the same about every point;
/// one whose order also leaves a net force depends on the point, and this one does not move
/// with the origin of z. 0 for no units.
pub fn engine_centre(axial_position: &[f64]) -> f64 {
    let (low, high) = axial_position
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &z| {
            (lo.min(z), hi.max(z))
        });
    if low <= high {
        0.5 * (low + high)
    } else {
        0.0
    }
}

/// An order whose amplitude is below this fraction of n ω² times its component's scale is
/// exactly 0: what cancels between units (an in-line six's first and second orders, a
/// boxer's forces) comes out of the exact series at ~1e-16 of that scale; 1e-13 is far above
/// that rounding and far below any order a machine has.
pub const RESOLUTION: f64 = 1e-13;

impl ShakingForces {
    /// The shaking forces of `units` at the axial positions `axial_position` (m, one per
    /// unit, any finite real: the moments are about the engine centre, [`engine_centre`]).
    pub fn new(units: &[PhysicalCylinder], axial_position: &[f64]) -> Result<Self> {
        if units.is_empty() {
            return Err(MechanismError::Empty {
                parameter: "cylinders",
            });
        }
        check_length("axial_position", units.len(), axial_position.len())?;
        for unit in units {
            unit.validate()?;
        }
        for &z in axial_position {
            check("axial_position", z, "a finite position in metres", |_| true)?;
        }
        let first_moments: Vec<EngineUnit> = units.iter().map(|u| u.gravity_unit(1.0)).collect();
        let turned = |unit: &EngineUnit| EngineUnit {
            inclination: unit.inclination + FRAC_PI_2,
            ..*unit
        };
        let weighted = |unit: EngineUnit, z: f64| EngineUnit {
            u1: unit.u1 * z,
            u2: unit.u2 * z,
            ..unit
        };
        let horizontal: Vec<EngineUnit> = first_moments.iter().map(turned).collect();
        let centre = engine_centre(axial_position);
        let by_position = |units: &[EngineUnit]| -> Vec<EngineUnit> {
            units
                .iter()
                .zip(axial_position)
                .map(|(u, &z)| weighted(*u, z - centre))
                .collect()
        };
        let (pitch, yaw) = (by_position(&first_moments), by_position(&horizontal));
        let scale = |units: &[EngineUnit]| units.iter().map(|u| u.u1.abs() + u.u2.abs()).sum();
        let scales = [
            scale(&first_moments),
            scale(&horizontal),
            scale(&pitch),
            scale(&yaw),
        ];
        Ok(Self {
            scales,
            engines: [
                Engine::new(first_moments)?,
                Engine::new(horizontal)?,
                Engine::new(pitch)?,
                Engine::new(yaw)?,
            ],
        })
    }

    /// The Fourier coefficients per ω² of the four components through order `max_order`
    /// (1 … 2048), from the engines' exact series: F = −ω² S″, so an order n of S′ =
    /// a_n cos nφ + b_n sin nφ gives F's cos and sin coefficients −n b_n and n a_n (times ω²).
    pub fn orders(&self, max_order: usize) -> Result<ShakingOrders> {
        if !(1..=MAX_HARMONIC).contains(&max_order) {
            return Err(MechanismError::InvalidChoice {
                parameter: "max_order",
                value: max_order.to_string(),
                allowed: "1 <= max_order <= 2048",
            });
        }
        let mut cos: [Vec<f64>; 4] = Default::default();
        let mut sin: [Vec<f64>; 4] = Default::default();
        for (k, engine) in self.engines.iter().enumerate() {
            let (a, b) = engine.fourier_coefficients(max_order)?;
            cos[k] = (0..=max_order).map(|n| -(n as f64) * b[n]).collect();
            sin[k] = (0..=max_order).map(|n| n as f64 * a[n]).collect();
        }
        let floors = self.scales.map(|scale| {
            (0..=max_order)
                .map(|n| RESOLUTION * n as f64 * scale)
                .collect()
        });
        Ok(ShakingOrders {
            max_order,
            cos,
            sin,
            floors,
        })
    }

    /// The four components at every φ (into `out`, component-major: 4 × phi), at the speed
    /// ω(φ) `omega` (rad/s) and acceleration ε(φ) `acceleration` (rad/s²), each one value
    /// per angle: F = −(S″ω² + S′ε), S′ and S″ from the closed-form kernels.
    pub fn curves<'a>(
        &self,
        phi: impl Into<Phi<'a>>,
        omega: &[f64],
        acceleration: &[f64],
        out: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        let phi = phi.into();
        let points = phi.len();
        check_length("omega", points, omega.len())?;
        check_length("acceleration", points, acceleration.len())?;
        check_length("out", 4 * points, out.len())?;
        check_finite("omega", omega, "a finite speed in rad/s")?;
        check_finite(
            "acceleration",
            acceleration,
            "a finite acceleration in rad/s²",
        )?;
        let mut slope = vec![0.0; points];
        for (engine, component) in self.engines.iter().zip(out.chunks_mut(points.max(1))) {
            engine.evaluate(Quantity::ForceDerivative, phi, component, parallelism)?;
            engine.evaluate(Quantity::GeneralizedForce, phi, &mut slope, parallelism)?;
            for (i, value) in component.iter_mut().enumerate() {
                *value = -(*value * omega[i] * omega[i] + slope[i] * acceleration[i]);
            }
        }
        Ok(())
    }

    /// The harmonics 1 … `max_harmonic` of the working cycle (`cycle` Φ, rad; harmonic k is
    /// order k·2π/Φ per revolution) of the four components while the machine runs at the
    /// speed ω(φ) `omega` (rad/s) and acceleration ε(φ) `acceleration` (rad/s²) sampled at
    /// N uniform angles jΦ/N, j = 0 … N − 1: the components there from the closed-form
    /// kernels ([`ShakingForces::curves`]), then their discrete Fourier transform (N >
    /// 2·`max_harmonic`). The coefficients are in N and N·m ([`ShakingOrders::table`] with
    /// scale 1); an amplitude below `RESOLUTION`·N times the larger of the component's
    /// largest value and its units' own forces (scale·max(ω² + |ε|)) is rounding, exactly 0.
    pub fn orders_in_motion(
        &self,
        cycle: f64,
        omega: &[f64],
        acceleration: &[f64],
        max_harmonic: usize,
        parallelism: Parallelism,
    ) -> Result<ShakingOrders> {
        check("cycle", cycle, "cycle > 0", |c| c > 0.0)?;
        let points = omega.len();
        if max_harmonic == 0 || points <= 2 * max_harmonic {
            return Err(MechanismError::InvalidChoice {
                parameter: "max_order",
                value: max_harmonic.to_string(),
                allowed: "1 <= harmonics of the cycle < half the samples of the steady state",
            });
        }
        let phi: Vec<f64> = (0..points)
            .map(|j| cycle * j as f64 / points as f64)
            .collect();
        let mut values = vec![0.0; 4 * points];
        self.curves(
            phi.as_slice(),
            omega,
            acceleration,
            &mut values,
            parallelism,
        )?;
        let swing = omega
            .iter()
            .zip(acceleration)
            .fold(0.0_f64, |m, (w, e)| m.max(w * w + e.abs()));
        let turn: Vec<(f64, f64)> = (0..points)
            .map(|m| (std::f64::consts::TAU * m as f64 / points as f64).sin_cos())
            .collect();
        let mut cos: [Vec<f64>; 4] = Default::default();
        let mut sin: [Vec<f64>; 4] = Default::default();
        let mut floors: [Vec<f64>; 4] = Default::default();
        for (k, component) in values.chunks(points).enumerate() {
            let largest = component.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let (mut a, mut b) = (vec![0.0; max_harmonic + 1], vec![0.0; max_harmonic + 1]);
            for n in 1..=max_harmonic {
                let (mut sum_cos, mut sum_sin) = (0.0, 0.0);
                for (j, &x) in component.iter().enumerate() {
                    let (s, c) = turn[(j * n) % points];
                    sum_cos += x * c;
                    sum_sin += x * s;
                }
                a[n] = 2.0 * sum_cos / points as f64;
                b[n] = 2.0 * sum_sin / points as f64;
            }
            cos[k] = a;
            sin[k] = b;
            // The transform's rounding is relative to the largest value; what the units'
            // sum cancels, to the units' own forces at the fastest swing.
            let floor = RESOLUTION * points as f64 * largest.max(self.scales[k] * swing);
            floors[k] = vec![floor; max_harmonic + 1];
        }
        Ok(ShakingOrders {
            max_order: max_harmonic,
            cos,
            sin,
            floors,
        })
    }
}

/// The Fourier coefficients per ω² (N/(rad/s)², N·m/(rad/s)²) of the shaking forces and
/// moments at a constant speed, orders 0 … `max_order` (order 0 is 0).
#[derive(Debug, Clone, PartialEq)]
pub struct ShakingOrders {
    max_order: usize,
    cos: [Vec<f64>; 4],
    sin: [Vec<f64>; 4],
    /// Per component and harmonic, the amplitude below which it is rounding (exactly 0).
    floors: [Vec<f64>; 4],
}

impl ShakingOrders {
    /// The highest order held.
    pub fn max_order(&self) -> usize {
        self.max_order
    }

    /// The table of orders 1 … `max_order` (at most [`ShakingOrders::max_order`]) at the
    /// constant speed `omega` (rad/s): one column per [`ORDER_COLUMNS`] name, each a value
    /// per order.
    pub fn at(&self, omega: f64, max_order: usize) -> Result<Vec<Vec<f64>>> {
        check_speed("omega", omega)?;
        self.table(omega * omega, max_order)
    }

    /// The table of harmonics 1 … `max_order` with every coefficient times `scale`.
    pub fn table(&self, scale: f64, max_order: usize) -> Result<Vec<Vec<f64>>> {
        if !(1..=self.max_order).contains(&max_order) {
            return Err(MechanismError::InvalidChoice {
                parameter: "max_order",
                value: max_order.to_string(),
                allowed: "1 <= max_order <= the orders computed",
            });
        }
        let mut columns = vec![Vec::with_capacity(max_order); ORDER_COLUMNS.len()];
        for n in 1..=max_order {
            let resolved = |k: usize| self.cos[k][n].hypot(self.sin[k][n]) >= self.floors[k][n];
            let a: [f64; 4] = std::array::from_fn(|k| {
                if resolved(k) {
                    scale * self.cos[k][n]
                } else {
                    0.0
                }
            });
            let b: [f64; 4] = std::array::from_fn(|k| {
                if resolved(k) {
                    scale * self.sin[k][n]
                } else {
                    0.0
                }
            });
            for k in 0..COMPONENTS.len() {
                let amplitude = a[k].hypot(b[k]);
                columns[2 * k].push(amplitude);
                // An order that is exactly 0 has no phase: 0, not atan2's π of a −0.
                columns[2 * k + 1].push(if amplitude == 0.0 {
                    0.0
                } else {
                    b[k].atan2(a[k])
                });
            }
            // (h, v) = (1, 0) for the forces, (3, 2) for the moments: A = a_h + i a_v,
            // B = b_h + i b_v; forward |A − iB|/2, backward |A + iB|/2.
            // What cancels between the two components is rounding as well, by the larger
            // of their floors.
            for (slot, (h, v)) in [(FORCE_FORWARD, (1, 0)), (MOMENT_FORWARD, (3, 2))] {
                let floor = scale * self.floors[h][n].max(self.floors[v][n]);
                let resolved = |x: f64| if x >= floor { x } else { 0.0 };
                columns[slot].push(resolved(0.5 * (a[h] + b[v]).hypot(a[v] - b[h])));
                columns[slot + 1].push(resolved(0.5 * (a[h] - b[v]).hypot(a[v] + b[h])));
            }
        }
        Ok(columns)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(phase: f64, inclination: f64) -> PhysicalCylinder {
        PhysicalCylinder {
            crank_radius: 0.05,
            rod_length: 0.2,
            piston_mass: 0.0,
            rod_mass: 0.0,
            rod_cg: 0.1,
            rod_inertia: 0.0,
            crank_mass: 0.0,
            crank_cg_radius: 0.0,
            counterweight_mass: 0.0,
            counterweight_radius: 0.0,
            phase,
            inclination,
        }
    }

    #[test]
    fn a_rotating_unbalance_turns_forward_at_first_order() {
        // m·e = 2 kg · 0.04 m at the crank pin's angle: F = m e ω² (cos, sin)(φ + γ + α).
        let cylinder = PhysicalCylinder {
            crank_mass: 2.0,
            crank_cg_radius: 0.04,
            ..unit(0.3, 1.1)
        };
        let forces = ShakingForces::new(&[cylinder], &[0.5]).unwrap();
        let omega = 100.0;
        let table = forces.orders(4).unwrap().at(omega, 4).unwrap();
        let column = |name: &str| &table[ORDER_COLUMNS.iter().position(|c| *c == name).unwrap()];
        let me_w2 = 2.0 * 0.04 * omega * omega;
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * me_w2;
        assert!(close(column("force_forward")[0], me_w2));
        assert!(close(column("force_backward")[0], 0.0));
        assert!(close(column("force_vertical")[0], me_w2));
        assert!(close(column("force_horizontal")[0], me_w2));
        // Alone, the unit is the engine centre: its force has no lever about it.
        assert!(close(column("moment_forward")[0], 0.0));
        // F_v = m e ω² sin(φ + 1.4) = m e ω² cos(φ − (π/2 − 1.4)).
        let phase = column("force_vertical_phase")[0];
        assert!((phase - (FRAC_PI_2 - 1.4)).abs() < 1e-12, "{phase}");
        for n in 1..4 {
            assert!(close(column("force_vertical")[n], 0.0), "order {}", n + 1);
        }
    }

    #[test]
    fn the_moments_are_about_the_midpoint_of_the_outermost_units() {
        assert_eq!(engine_centre(&[0.3, -0.1, 0.9, 0.2]), 0.4);
        assert_eq!(engine_centre(&[]), 0.0);
        // Two alike unbalances 0.4 m apart with their pins together: no couple about the
        // centre wherever the pair sits; pins opposed: the couple m e ω² · 0.4 m.
        let unbalance = |phase: f64| PhysicalCylinder {
            crank_mass: 2.0,
            crank_cg_radius: 0.04,
            ..unit(phase, FRAC_PI_2)
        };
        let omega = 100.0;
        let me_w2 = 2.0 * 0.04 * omega * omega;
        for origin in [0.0, 3.0, -11.0] {
            let at = [origin, origin + 0.4];
            for (phase, couple) in [(0.0, 0.0), (std::f64::consts::PI, 0.4 * me_w2)] {
                let forces = ShakingForces::new(&[unbalance(0.0), unbalance(phase)], &at).unwrap();
                let table = forces.orders(2).unwrap().at(omega, 2).unwrap();
                let moment = table[MOMENT_FORWARD][0] + table[MOMENT_FORWARD + 1][0];
                assert!(
                    (moment - couple).abs() <= 1e-12 * me_w2,
                    "{origin} {phase}: {moment}"
                );
            }
        }
    }

    #[test]
    fn the_curves_are_the_orders_summed_at_constant_speed() {
        let cylinders = [
            PhysicalCylinder {
                piston_mass: 1.5,
                rod_mass: 1.0,
                ..unit(0.0, 1.2)
            },
            PhysicalCylinder {
                piston_mass: 1.5,
                rod_mass: 1.0,
                counterweight_mass: 3.0,
                counterweight_radius: 0.05,
                ..unit(2.0, -0.4)
            },
        ];
        let forces = ShakingForces::new(&cylinders, &[-0.1, 0.2]).unwrap();
        let orders = forces.orders(60).unwrap();
        let phi: Vec<f64> = (0..7).map(|i| 0.9 * i as f64).collect();
        let omega = vec![50.0; phi.len()];
        let mut out = vec![0.0; 4 * phi.len()];
        forces
            .curves(
                phi.as_slice(),
                &omega,
                &vec![0.0; phi.len()],
                &mut out,
                Parallelism::SERIAL,
            )
            .unwrap();
        for k in 0..4 {
            let scale = out[k * phi.len()..(k + 1) * phi.len()]
                .iter()
                .fold(0.0_f64, |m, v| m.max(v.abs()));
            for (i, &p) in phi.iter().enumerate() {
                let summed: f64 = (1..=60)
                    .map(|n| {
                        let (s, c) = (n as f64 * p).sin_cos();
                        2500.0 * (orders.cos[k][n] * c + orders.sin[k][n] * s)
                    })
                    .sum();
                let curve = out[k * phi.len() + i];
                assert!(
                    (summed - curve).abs() < 1e-12 * scale,
                    "{k} {p}: {summed} {curve}"
                );
            }
        }
    }
}
