//! The orders of the shaft torques (docs/theory.md, "Orders"): the Fourier coefficients per
//! revolution of the gas torque, the inertia torque −½ J′(φ) ω² at a mean speed and the
//! gravity torque −U′(φ), by Gauss–Legendre panels.
//!
//! For the order ν (harmonics per revolution: 0, 1, 2, … for a two-stroke machine, 0, ½, 1,
//! … for a four-stroke one, whose working cycle spans two revolutions)
//! a_ν + i b_ν = (2/T) ∫₀^T M(φ) e^{iνφ} dφ (half of it for ν = 0, the mean), so that
//! M(φ) = Σ_ν a_ν cos νφ + b_ν sin νφ.
//!
//! - Inertia and gravity: J and U are analytic and 2π-periodic; one revolution's panels give
//!   their coefficients to rounding. Their half orders are exactly 0, and so is gravity's
//!   mean (U is periodic).
//! - Gas: the panels of the working cycle, cut at every gassed unit's dead centres and at
//!   its pressure tables' breakpoints (mapped to φ = θ − α), between which the pressure is
//!   one polynomial and the torque analytic: the coefficients of the tabulated pressure's
//!   torque are exact to rounding.
//!
//! Every piece between cuts is cut into equal panels no wider than min(π/16, ¼·2π/ν_max)
//! with 12 nodes each, so that a panel integrates cos νφ to rounding up to the highest order.

use std::f64::consts::{PI, TAU};

use rayon::prelude::*;

use crate::dynamics::Dynamics;
use crate::error::{try_with_capacity, MechanismError, Result};
use crate::mechanism::check_speed;
use crate::parallel::Parallelism;

use super::cycle::dead_centres;
use super::gas::Forces;
use super::quadrature::{breaks, Panels};
use super::MachineView;

/// Gauss–Legendre nodes per panel.
const NODES: usize = 12;
/// The widest panel (rad), …
const MAX_WIDTH: f64 = PI / 16.0;
/// … and at most this fraction of the shortest period 2π/ν_max: with 12 nodes a panel then
/// integrates cos νφ to rounding.
const PERIOD_FRACTION: f64 = 0.25;
/// Orders between exact restarts of the rotation e^{iνφ} → e^{i(ν + Δν)φ} (each step adds a
/// rounding of ~1e-16; 32 of them stay far below what the coefficients need).
const RESTART: usize = 32;
/// Nodes summed apart before their sum joins the total: the rounding of a sum over ~10⁵
/// nodes grows with √(chunks) + √(chunk), not with √(nodes).
const CHUNK: usize = 128;
/// Nodes whose recurrences run side by side (a multiple of every SIMD width; divides CHUNK).
const LANES: usize = 16;

/// The orders of a machine's shaft torques at a mean speed.
#[derive(Debug, Clone, PartialEq)]
pub struct TorqueOrders {
    /// ν per revolution: 0, 1/s, 2/s, … up to the highest order, s = 1 (two-stroke) or 2
    /// (four-stroke).
    pub order: Vec<f64>,
    /// a_ν and b_ν (N·m) of the gas torque.
    pub gas_cos: Vec<f64>,
    pub gas_sin: Vec<f64>,
    /// a_ν and b_ν (N·m) of the inertia torque −½ J′ ω² (0 at half orders).
    pub inertia_cos: Vec<f64>,
    pub inertia_sin: Vec<f64>,
    /// a_ν and b_ν (N·m) of the gravity torque −U′ (0 at half orders and for the mean; all
    /// 0 without gravity).
    pub gravity_cos: Vec<f64>,
    pub gravity_sin: Vec<f64>,
    /// Σ_j max_φ |M_j(φ)| (N·m) of each unit's inertia torque alone: the size of what the
    /// sum over the units cancels, and so the scale of its rounding.
    pub inertia_scale: f64,
    /// The same of the units' gravity torques (0 without gravity).
    pub gravity_scale: f64,
}

/// The orders of `machine`'s gas, inertia and gravity torques up to `max_order` (≥ 1) at the
/// mean speed `omega` ω (rad/s); `gravity` false gives zero gravity orders (as if g were 0).
pub fn torque_orders(
    machine: &MachineView<'_>,
    omega: f64,
    max_order: usize,
    gravity: bool,
) -> Result<TorqueOrders> {
    check_speed("omega", omega)?;
    if max_order == 0 {
        return Err(MechanismError::OutOfRange {
            parameter: "max_order",
            value: 0.0,
            allowed: "max_order >= 1",
        });
    }
    let cycle = machine.strokes.cycle_angle();
    let per_cycle = (cycle / TAU).round() as usize; // harmonics of the cycle per order
                                                    // What the gas panels' node arrays will hold (≈ 12 per quarter of the shortest period
                                                    // over the cycle, each in about ten arrays), refused up front rather than aborted on.
    let nodes = NODES as u128 * (max_order as u128 * 4 * per_cycle as u128 + 64);
    try_with_capacity::<f64>("max_order", max_order, 10 * nodes)?;
    let count = max_order * per_cycle + 1;
    let order: Vec<f64> = (0..count).map(|k| k as f64 / per_cycle as f64).collect();
    let width = MAX_WIDTH.min(PERIOD_FRACTION * TAU / max_order as f64);
    let dynamics = Dynamics::new(machine.units, machine.g)?;
    let parallelism = Parallelism::default();

    let forces = Forces::new(machine.units, machine.gas, machine.diagrams.into(), cycle)?;
    let panels = Panels::new(&breaks(gas_cuts(machine, cycle), cycle), NODES, width);
    let mut torque = vec![0.0; panels.phi.len()];
    dynamics.gas_torque(
        panels.phi.as_slice(),
        &forces.at(&panels.phi),
        &mut torque,
        parallelism,
    )?;
    let (gas_cos, gas_sin) = coefficients(&panels, &torque, count, per_cycle);

    // One revolution, integer orders only, spread over the cycle's orders (half orders 0).
    let revolution = Panels::new(&[0.0, TAU], NODES, width);
    let spread = |(cos, sin): (Vec<f64>, Vec<f64>)| {
        let (mut a, mut b) = (vec![0.0; count], vec![0.0; count]);
        for (k, (c, s)) in cos.into_iter().zip(sin).enumerate() {
            a[k * per_cycle] = c;
            b[k * per_cycle] = s;
        }
        (a, b)
    };
    let inertia = |units: &Dynamics| -> Result<Vec<f64>> {
        let n = revolution.phi.len();
        let (mut rest, mut slope) = (vec![0.0; n], vec![0.0; n]);
        units.inertia_beside_shaft(
            revolution.phi.as_slice(),
            &mut rest,
            &mut slope,
            parallelism,
        )?;
        Ok(slope.iter().map(|s| -0.5 * s * omega * omega).collect())
    };
    let weight = |units: &Dynamics| -> Result<Vec<f64>> {
        let mut out = vec![0.0; revolution.phi.len()];
        units.gravity_torque(revolution.phi.as_slice(), &mut out, parallelism)?;
        Ok(out)
    };
    let integer = max_order + 1;
    let (inertia_cos, inertia_sin) =
        spread(coefficients(&revolution, &inertia(&dynamics)?, integer, 1));
    let (mut gravity_cos, mut gravity_sin) = (vec![0.0; count], vec![0.0; count]);
    if gravity && machine.g != 0.0 {
        (gravity_cos, gravity_sin) =
            spread(coefficients(&revolution, &weight(&dynamics)?, integer, 1));
        gravity_cos[0] = 0.0; // −U′ of a periodic U has no mean: exactly, not to rounding
    }

    // Σ_j max|M_j| of the units alone.
    let largest = |values: Vec<f64>| values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let (mut inertia_scale, mut gravity_scale) = (0.0, 0.0);
    for unit in machine.units {
        let alone = Dynamics::new(std::slice::from_ref(unit), machine.g)?;
        inertia_scale += largest(inertia(&alone)?);
        if gravity {
            gravity_scale += largest(weight(&alone)?);
        }
    }
    Ok(TorqueOrders {
        order,
        gas_cos,
        gas_sin,
        inertia_cos,
        inertia_sin,
        gravity_cos,
        gravity_sin,
        inertia_scale,
        gravity_scale,
    })
}

/// Where the gas torque may have kinks, φ in [0, Φ): every gassed unit's dead centres and
/// its pressure tables' breakpoints θ, at φ = (θ − α) mod Φ.
fn gas_cuts(machine: &MachineView<'_>, cycle: f64) -> Vec<f64> {
    let mut angles = dead_centres(machine);
    for (unit, gas) in machine.units.iter().zip(machine.gas) {
        if !gas.has_gas() {
            continue;
        }
        for table in [gas.head, gas.crank_end].into_iter().flatten() {
            angles.extend(
                machine.diagrams[table]
                    .breakpoints()
                    .iter()
                    .map(|x| (x - unit.phase).rem_euclid(cycle)),
            );
        }
    }
    angles
}

/// (a_k, b_k), k = 0 … count − 1, of f (`values` at the nodes of `panels`) for the orders
/// ν_k = k/`per_cycle` over the panels' period T: a_k + i b_k = (2/T) Σ w f e^{iν_k φ} over
/// the nodes (1/T for k = 0).
///
/// Blocks of [`RESTART`] orders, each from an exact e^{iνφ} stepped by the rotation
/// e^{iΔνφ}, node by node: the memory is that of the nodes, not of an orders × nodes matrix
/// (the nodes grow with the highest order, so that matrix would grow as its square). Blocks
/// run in parallel, each summing its nodes in the same order whatever the threads: the same
/// doubles on any machine.
fn coefficients(
    panels: &Panels,
    values: &[f64],
    count: usize,
    per_cycle: usize,
) -> (Vec<f64>, Vec<f64>) {
    let step = 1.0 / per_cycle as f64;
    let n = panels.phi.len();
    let weighted: Vec<f64> = panels
        .weights
        .iter()
        .zip(values)
        .map(|(w, f)| w * f)
        .collect();
    let (rotation_sin, rotation_cos): (Vec<f64>, Vec<f64>) =
        panels.phi.iter().map(|p| (step * p).sin_cos()).unzip();
    let period = panels.cycle();
    let mut found = vec![(0.0, 0.0); count];
    let block = |(index, out): (usize, &mut [(f64, f64)])| {
        let first = (index * RESTART) as f64 / per_cycle as f64;
        let span = out.len();
        let mut total = [(0.0, 0.0); RESTART];
        // Per order and lane: LANES nodes side by side, each its own recurrence (so that the
        // rotations of neighbouring nodes run together), summed apart per chunk.
        let mut cos_sums = [[0.0; LANES]; RESTART];
        let mut sin_sums = [[0.0; LANES]; RESTART];
        for start in (0..n).step_by(CHUNK) {
            let end = (start + CHUNK).min(n);
            cos_sums[..span].iter_mut().for_each(|s| *s = [0.0; LANES]);
            sin_sums[..span].iter_mut().for_each(|s| *s = [0.0; LANES]);
            for lanes in (start..end).step_by(LANES) {
                let (mut c, mut s, mut rc, mut rs, mut wf) = (
                    [0.0; LANES],
                    [0.0; LANES],
                    [0.0; LANES],
                    [0.0; LANES],
                    [0.0; LANES],
                );
                for (l, i) in (lanes..(lanes + LANES).min(end)).enumerate() {
                    (s[l], c[l]) = (first * panels.phi[i]).sin_cos();
                    (rs[l], rc[l], wf[l]) = (rotation_sin[i], rotation_cos[i], weighted[i]);
                }
                for (cos_sum, sin_sum) in cos_sums[..span].iter_mut().zip(&mut sin_sums[..span]) {
                    for l in 0..LANES {
                        cos_sum[l] += wf[l] * c[l];
                        sin_sum[l] += wf[l] * s[l];
                        (c[l], s[l]) = (c[l] * rc[l] - s[l] * rs[l], s[l] * rc[l] + c[l] * rs[l]);
                    }
                }
            }
            for ((t, c), s) in total[..span].iter_mut().zip(&cos_sums).zip(&sin_sums) {
                t.0 += c.iter().sum::<f64>();
                t.1 += s.iter().sum::<f64>();
            }
        }
        out.copy_from_slice(&total[..span]);
    };
    found.par_chunks_mut(RESTART).enumerate().for_each(block);
    found
        .iter()
        .enumerate()
        .map(|(k, &(a, b))| {
            let factor = if k == 0 { 1.0 } else { 2.0 } / period;
            (factor * a, factor * b)
        })
        .unzip()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanism::PhysicalCylinder;
    use crate::mechanism::Strokes;
    use crate::motion::{GasCylinder, PiecewisePolynomial};
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn the_recurrence_gives_the_coefficients_of_a_trigonometric_polynomial() {
        // f = 3 + 2 cos 5φ − sin 40φ over one revolution: exact on panels resolving order 40.
        let panels = Panels::new(&[0.0, TAU], NODES, PERIOD_FRACTION * TAU / 64.0);
        let f: Vec<f64> = panels
            .phi
            .iter()
            .map(|p| 3.0 + 2.0 * (5.0 * p).cos() - (40.0 * p).sin())
            .collect();
        let (a, b) = coefficients(&panels, &f, 65, 1);
        for k in 0..65 {
            let (ea, eb) = match k {
                0 => (3.0, 0.0),
                5 => (2.0, 0.0),
                40 => (0.0, -1.0),
                _ => (0.0, 0.0),
            };
            assert!(
                (a[k] - ea).abs() < 1e-14 && (b[k] - eb).abs() < 1e-14,
                "{k}"
            );
        }
    }

    fn unit(phase: f64) -> PhysicalCylinder {
        PhysicalCylinder {
            crank_radius: 0.1,
            rod_length: 0.35,
            piston_mass: 2.0,
            rod_mass: 1.0,
            rod_cg: 0.25,
            rod_inertia: 0.0,
            crank_mass: 0.0,
            crank_cg_radius: 0.0,
            counterweight_mass: 0.0,
            counterweight_radius: 0.0,
            phase,
            inclination: FRAC_PI_2,
        }
    }

    #[test]
    fn cuts_are_the_gassed_units_dead_centres_and_table_angles() {
        // A linear table at θ = 0, 1, 3, 2π on the first unit (α = 0.5); the second has no
        // bore and the third no pressure, so neither adds a cut.
        let table = PiecewisePolynomial::new(
            vec![0.0, 1.0, 3.0, TAU],
            vec![2e5, -0.5e5, -1e5 / (TAU - 3.0), 1e5, 3e5, 2e5],
            TAU,
        )
        .expect("a valid table");
        let diagrams = [table];
        let units = [unit(0.5), unit(1.0), unit(2.5)];
        let gas = [
            GasCylinder {
                bore: 0.09,
                piston_rod_diameter: 0.0,
                head: Some(0),
                crank_end: None,
            },
            GasCylinder {
                head: Some(0),
                ..GasCylinder::NONE
            },
            GasCylinder {
                bore: 0.09,
                ..GasCylinder::NONE
            },
        ];
        let machine = MachineView {
            units: &units,
            gas: &gas,
            diagrams: &diagrams,
            shaft_inertia: 1.0,
            strokes: Strokes::Two,
            g: 9.81,
        };
        let found = breaks(gas_cuts(&machine, TAU), TAU);
        // Dead centres at φ = kπ − α, table angles at θ − α (mod 2π).
        let mut expected = vec![0.0, PI - 0.5, TAU - 0.5, 1.0 - 0.5, 3.0 - 0.5, TAU];
        expected.sort_by(f64::total_cmp);
        assert_eq!(found.len(), expected.len(), "{found:?}");
        for (f, e) in found.iter().zip(&expected) {
            assert!((f - e).abs() < 1e-15, "{found:?}");
        }
    }

    #[test]
    fn a_kink_on_a_panel_edge_is_integrated_exactly() {
        // |φ − c| has a kink at c: cut there, the panel rule is exact; not cut, it is not.
        let kink = 2.0;
        let exact = (kink * kink + (TAU - kink).powi(2)) / 2.0;
        let integral = |panels: Panels| {
            let f: Vec<f64> = panels.phi.iter().map(|p| (p - kink).abs()).collect();
            panels.integral(&f)
        };
        let cut = integral(Panels::new(&breaks(vec![kink], TAU), NODES, PI / 8.0));
        assert!((cut - exact).abs() <= 1e-14 * exact, "{cut} {exact}");
        let whole = integral(Panels::new(&[0.0, TAU], NODES, TAU));
        assert!((whole - exact).abs() > 1e-6, "{whole} {exact}");
    }
}
