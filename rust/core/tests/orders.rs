//! The torque orders against an independent oracle: the gas, inertia and gravity torques of
//! upright slider-cranks written here from their planar geometry (heights, velocities,
//! the rod's swing), sampled densely over the cycle and transformed by a plain discrete
//! Fourier sum, which is exact to rounding for these smooth periodic torques.

use std::f64::consts::{FRAC_PI_2, PI};

use multicrank_core::{
    torque_orders, GasCylinder, MachineView, MechanismError, PhysicalCylinder, PiecewisePolynomial,
    Strokes,
};

const G: f64 = 9.81;
const OMEGA: f64 = 120.0;
const CYCLE: f64 = 4.0 * PI;
const BORE: f64 = 0.09;

fn unit(phase: f64, piston_mass: f64, crank_radius: f64) -> PhysicalCylinder {
    PhysicalCylinder {
        crank_radius,
        rod_length: 0.21,
        piston_mass,
        rod_mass: 0.85,
        rod_cg: 0.145,
        rod_inertia: 0.003,
        crank_mass: 3.0,
        crank_cg_radius: 0.04,
        counterweight_mass: 1.0,
        counterweight_radius: 0.05,
        phase,
        inclination: FRAC_PI_2,
    }
}

/// p(θ) (Pa): 10⁵·(1 + q⁴), q = θ(Φ − θ)/(Φ/2)² on θ mod Φ — smooth across the cycle's end to
/// its fourth derivative, with half orders.
fn pressure(theta: f64) -> f64 {
    let t = theta.rem_euclid(CYCLE);
    let q = t * (CYCLE - t) / (CYCLE * CYCLE / 4.0);
    1e5 * (1.0 + q.powi(4))
}

/// The same pressure as a `PiecewisePolynomial` of one piece: the monomials of θ⁴(Φ − θ)⁴.
fn pressure_table() -> PiecewisePolynomial {
    let scale = 1e5 / (CYCLE * CYCLE / 4.0).powi(4);
    let binomial = [1.0, 4.0, 6.0, 4.0, 1.0];
    // c[k] multiplies θ^(8 − k).
    let mut c = [0.0; 9];
    for (k, b) in binomial.iter().enumerate() {
        // θ⁴ · C(4, k) Φ^(4−k) (−θ)^k
        c[8 - (4 + k)] = scale * b * CYCLE.powi(4 - k as i32) * (-1.0_f64).powi(k as i32);
    }
    c[8] += 1e5;
    PiecewisePolynomial::new(vec![0.0, CYCLE], c.to_vec(), CYCLE).expect("a valid table")
}

/// Per unit at its crank angle ψ: (U (J), J's varying part (kg·m²), s' (m/rad)) from the
/// planar geometry of an upright slider-crank: pin at (r sin ψ, r cos ψ), piston pin at
/// (0, r cos ψ + w), w = √(l² − r² sin² ψ), the rod's angle β with l sin β = r sin ψ.
fn planar(u: &PhysicalCylinder, psi: f64) -> (f64, f64, f64) {
    let (r, l, z) = (u.crank_radius, u.rod_length, u.rod_cg);
    let (s, c) = psi.sin_cos();
    let w = (l * l - r * r * s * s).sqrt();
    let pin = (r * s, r * c);
    let piston = (0.0, r * c + w);
    let rod = (
        piston.0 + z / l * (pin.0 - piston.0),
        piston.1 + z / l * (pin.1 - piston.1),
    );
    let height = u.piston_mass * piston.1
        + u.rod_mass * rod.1
        + (u.crank_mass * u.crank_cg_radius - u.counterweight_mass * u.counterweight_radius) * c;
    // Velocities per unit crank speed.
    let pin_v = (r * c, -r * s);
    let piston_v = (0.0, -r * s - r * r * s * c / w);
    let rod_v = (
        piston_v.0 + z / l * (pin_v.0 - piston_v.0),
        piston_v.1 + z / l * (pin_v.1 - piston_v.1),
    );
    let swing = r * c / w;
    let inertia = u.piston_mass * piston_v.1 * piston_v.1
        + u.rod_mass * (rod_v.0 * rod_v.0 + rod_v.1 * rod_v.1)
        + u.rod_inertia * swing * swing;
    (G * height, inertia, -piston_v.1)
}

/// (a_ν, b_ν) of f over [0, Φ) for ν = k/2, k < count, by the plain discrete Fourier sum of
/// `samples` equally spaced values.
fn dft(f: impl Fn(f64) -> f64, samples: usize, count: usize) -> Vec<(f64, f64)> {
    let values: Vec<f64> = (0..samples)
        .map(|i| f(i as f64 * CYCLE / samples as f64))
        .collect();
    (0..count)
        .map(|k| {
            let nu = k as f64 / 2.0;
            let (mut a, mut b) = (0.0, 0.0);
            for (i, v) in values.iter().enumerate() {
                let angle = nu * (i as f64 * CYCLE / samples as f64);
                a += v * angle.cos();
                b += v * angle.sin();
            }
            let factor = if k == 0 { 1.0 } else { 2.0 } / samples as f64;
            (factor * a, factor * b)
        })
        .collect()
}

/// The coefficients of −g′ from those of g (`a`, `b`): −g′ = Σ ν(a sin νφ − b cos νφ).
fn negative_slope(coefficients: &[(f64, f64)]) -> Vec<(f64, f64)> {
    coefficients
        .iter()
        .enumerate()
        .map(|(k, &(a, b))| {
            let nu = k as f64 / 2.0;
            (-nu * b, nu * a)
        })
        .collect()
}

fn assert_close(name: &str, found: (&[f64], &[f64]), expected: &[(f64, f64)], tolerance: f64) {
    let largest = expected
        .iter()
        .fold(0.0_f64, |m, (a, b)| m.max(a.hypot(*b)));
    assert!(largest > 1.0, "{name}: {largest} N·m, trivially small");
    for (k, ((a, b), (ea, eb))) in found.0.iter().zip(found.1).zip(expected).enumerate() {
        assert!(
            (a - ea).abs() <= tolerance * largest && (b - eb).abs() <= tolerance * largest,
            "{name} order {}: ({a}, {b}) against ({ea}, {eb})",
            k as f64 / 2.0
        );
    }
}

#[test]
fn the_orders_are_the_fourier_sums_of_the_planar_torques() {
    let units = [unit(0.3, 1.3, 0.06), unit(2.0, 1.7, 0.05)];
    let gas = [
        GasCylinder {
            bore: BORE,
            piston_rod_diameter: 0.0,
            head: Some(0),
            crank_end: None,
        },
        GasCylinder::NONE,
    ];
    let diagrams = [pressure_table()];
    let machine = MachineView {
        units: &units,
        gas: &gas,
        diagrams: &diagrams,
        shaft_inertia: 0.25,
        strokes: Strokes::Four,
        g: G,
    };
    let max_order = 40;
    let found = torque_orders(&machine, OMEGA, max_order, true).expect("the orders");
    let count = 2 * max_order + 1;
    assert_eq!(found.order.len(), count);
    assert_eq!(found.order[1], 0.5);
    assert_eq!(found.order[count - 1], max_order as f64);

    let samples = 1 << 14;
    let sum = |part: fn(&(f64, f64, f64)) -> f64, phi: f64| -> f64 {
        units.iter().map(|u| part(&planar(u, phi + u.phase))).sum()
    };
    let potential = dft(|phi| sum(|p| p.0, phi), samples, count);
    let inertia = dft(|phi| sum(|p| p.1, phi), samples, count);
    // −U′, and −½J′ω² = ½ω² · (−J′).
    let gravity = negative_slope(&potential);
    let inertia: Vec<(f64, f64)> = negative_slope(&inertia)
        .iter()
        .map(|(a, b)| (0.5 * OMEGA * OMEGA * a, 0.5 * OMEGA * OMEGA * b))
        .collect();
    let area = PI * BORE * BORE / 4.0;
    let first = units[0];
    let gas_torque = dft(
        |phi| pressure(phi + first.phase) * area * planar(&first, phi + first.phase).2,
        samples,
        count,
    );
    assert_close("gas", (&found.gas_cos, &found.gas_sin), &gas_torque, 1e-12);
    assert_close(
        "inertia",
        (&found.inertia_cos, &found.inertia_sin),
        &inertia,
        1e-12,
    );
    assert_close(
        "gravity",
        (&found.gravity_cos, &found.gravity_sin),
        &gravity,
        1e-12,
    );
    // Half orders of a 2π-periodic torque, and gravity's mean, exactly 0.
    for k in (1..count).step_by(2) {
        assert_eq!(found.inertia_cos[k], 0.0);
        assert_eq!(found.gravity_sin[k], 0.0);
    }
    assert_eq!(found.gravity_cos[0], 0.0);
    assert!(found.gas_cos[1].hypot(found.gas_sin[1]) > 1.0);

    // The scales: Σ_j max|M_j| of each unit alone, from the planar torques on a dense grid.
    let mut scales = (0.0, 0.0);
    for u in &units {
        let (mut inertia, mut gravity) = (0.0_f64, 0.0_f64);
        let h = 1e-5;
        for i in 0..4096 {
            let psi = i as f64 * 2.0 * PI / 4096.0 + u.phase;
            let (ahead, behind) = (planar(u, psi + h), planar(u, psi - h));
            gravity = gravity.max(((ahead.0 - behind.0) / (2.0 * h)).abs());
            inertia = inertia.max((0.5 * OMEGA * OMEGA * (ahead.1 - behind.1) / (2.0 * h)).abs());
        }
        scales.0 += inertia;
        scales.1 += gravity;
    }
    // The core's maxima are over its quadrature nodes (≤ π/192 apart): at most the true ones,
    // and within ~(π/384)²·max|M″/M|/2 of them; a scale only decides what rounds to 0.
    for (found, dense) in [
        (found.inertia_scale, scales.0),
        (found.gravity_scale, scales.1),
    ] {
        assert!(
            found <= dense * (1.0 + 1e-8) && found >= dense * (1.0 - 1e-3),
            "{found} {dense}"
        );
    }

    let without = torque_orders(&machine, OMEGA, max_order, false).expect("the orders");
    assert!(without
        .gravity_cos
        .iter()
        .chain(&without.gravity_sin)
        .all(|&m| m == 0.0));
    assert_eq!(without.gravity_scale, 0.0);
    assert_eq!(without.gas_cos, found.gas_cos);
}

#[test]
fn bad_speed_and_order_are_refused_by_name() {
    let units = [unit(0.0, 1.0, 0.05)];
    let gas = [GasCylinder::NONE];
    let machine = MachineView {
        units: &units,
        gas: &gas,
        diagrams: &[],
        shaft_inertia: 0.1,
        strokes: Strokes::Two,
        g: G,
    };
    for (omega, order, parameter) in [
        (0.0, 4, "omega"),
        (f64::NAN, 4, "omega"),
        (OMEGA, 0, "max_order"),
    ] {
        match torque_orders(&machine, omega, order, true) {
            Err(MechanismError::OutOfRange { parameter: p, .. }) => assert_eq!(p, parameter),
            other => panic!("{omega} {order}: {other:?}"),
        }
    }
    // More orders than memory holds: refused by name, not aborted on.
    for order in [usize::MAX, 1 << 60] {
        match torque_orders(&machine, OMEGA, order, true) {
            Err(MechanismError::TooLarge { parameter, .. }) => assert_eq!(parameter, "max_order"),
            other => panic!("{order}: {other:?}"),
        }
    }
}
