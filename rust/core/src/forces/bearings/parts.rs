//! The parts of the bearing loads at a constant speed, kept per machine: each load linear
//! in ω², g and the gas forces (`unit_forces`, the one Newton–Euler, at unit inputs).

use super::{unit_forces, BearingLayout};
use crate::error::{check, check_finite, check_length, Result};
use crate::mechanism::PhysicalCylinder;

/// The parts of every main bearing's load at fixed crank angles at a constant speed, each
/// load being linear in ω², g and the gas forces (a pressure scale s multiplying them all):
/// L(φ) = ω²·W(φ) + g·G(φ) + s·F(φ), W, G and F each `unit_forces` at unit inputs (ω = 1,
/// g = 1, the gas forces alone; ε = 0) shared into the bearings by the lever rule. Made once
/// per machine for its default angles; a constant speed's loads are then three multiply-adds
/// per bearing, angle and direction — equal to [`bearing_loads`](super::bearing_loads)' to
/// rounding (not to the bit: the sums are ordered otherwise).
#[derive(Debug, Clone)]
pub struct BearingParts {
    points: usize,
    /// Per bearing and angle (bearing-major): W, G, F, each (horizontal, vertical).
    parts: Vec<[[f64; 2]; 3]>,
}

impl BearingParts {
    /// The parts at the angles `phi` (rad, finite) with the gas forces `gas` (N, unit-major,
    /// units × phi, finite) of the units `units` (valid) on `layout`.
    pub fn new(
        units: &[PhysicalCylinder],
        layout: &BearingLayout,
        phi: &[f64],
        gas: &[f64],
    ) -> Result<Self> {
        let points = phi.len();
        check_length("throw_of_unit", units.len(), layout.throw_of_unit.len())?;
        check_length("gas", units.len() * points, gas.len())?;
        for unit in units {
            unit.validate()?;
        }
        for (name, values) in [("phi", phi), ("gas", gas)] {
            check_finite(name, values, "finite")?;
        }
        let mut parts = vec![[[0.0; 2]; 3]; layout.bearings() * points];
        for (j, unit) in units.iter().enumerate() {
            let (a, share_a, b, share_b) = layout.shares[layout.throw_of_unit[j]];
            for (i, &p) in phi.iter().enumerate() {
                let loads = [
                    unit_forces(unit, p, 1.0, 0.0, 0.0, 0.0).throw_load,
                    unit_forces(unit, p, 0.0, 0.0, 0.0, 1.0).throw_load,
                    unit_forces(unit, p, 0.0, 0.0, gas[j * points + i], 0.0).throw_load,
                ];
                for (k, load) in loads.iter().enumerate() {
                    for d in 0..2 {
                        parts[a * points + i][k][d] += share_a * load[d];
                        parts[b * points + i][k][d] += share_b * load[d];
                    }
                }
            }
        }
        Ok(Self { points, parts })
    }

    /// The number of angles.
    pub fn points(&self) -> usize {
        self.points
    }

    /// The loads (N, bearing-major, bearings × angles) at the constant speed `omega` (rad/s),
    /// the gas forces times `pressure_scale` and g (m/s²), into `horizontal` and `vertical`.
    pub fn at_speed(
        &self,
        omega: f64,
        pressure_scale: f64,
        g: f64,
        horizontal: &mut [f64],
        vertical: &mut [f64],
    ) -> Result<()> {
        check_length("horizontal", self.parts.len(), horizontal.len())?;
        check_length("vertical", self.parts.len(), vertical.len())?;
        check("omega", omega, "finite", |_| true)?;
        check("pressure_scale", pressure_scale, "finite", |_| true)?;
        check("g", g, "any finite real", |_| true)?;
        let omega2 = omega * omega;
        for ((part, h), v) in self.parts.iter().zip(horizontal).zip(vertical) {
            let [w, gravity, gas] = part;
            *h = omega2 * w[0] + g * gravity[0] + pressure_scale * gas[0];
            *v = omega2 * w[1] + g * gravity[1] + pressure_scale * gas[1];
        }
        Ok(())
    }
}
