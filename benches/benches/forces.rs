//! The forces on the frame and the bearings of a twelve-cylinder V (60°, six throws), serial:
//! its shaking forces by order through order 12 — made afresh (the series of its four
//! first-moment engines) and asked again at another speed (a scaling of the orders kept) —
//! and its main-bearing loads at 720 angles (Newton–Euler of every piston and rod, the lever
//! rule over seven bearings). The figures: one `shaking_forces` ≤ 20 µs after the
//! first call, `bearing_loads` at 720 angles ≤ 1 ms for k ≤ 12 (the Python calls add their
//! own overhead: benches/python/bench_forces.py).
//! Run: `cargo bench -p multicrank-benches --bench forces` (release profile).

use std::f64::consts::{FRAC_PI_2, PI};

use criterion::{criterion_group, criterion_main, Criterion};
use multicrank_core::{
    bearing_loads, BearingLayout, BearingParts, Parallelism, PhysicalCylinder, ShakingForces,
};

const ANGLES: usize = 720;

/// Six throws 0-120-240-240-120-0 (as an in-line six), two banks 60° apart on each.
fn vee_twelve() -> (Vec<PhysicalCylinder>, Vec<usize>, Vec<f64>) {
    let pins = [0.0, 120.0, 240.0, 240.0, 120.0, 0.0_f64];
    let mut units = Vec::new();
    let mut throw_of_unit = Vec::new();
    for (t, pin) in pins.iter().enumerate() {
        for bank in [FRAC_PI_2 - PI / 6.0, FRAC_PI_2 + PI / 6.0] {
            units.push(PhysicalCylinder {
                crank_radius: 0.085,
                rod_length: 0.3,
                piston_mass: 2.5,
                rod_mass: 3.0,
                rod_cg: 0.2,
                rod_inertia: 0.03,
                crank_mass: 4.0,
                crank_cg_radius: 0.03,
                counterweight_mass: 3.0,
                counterweight_radius: 0.07,
                phase: pin.to_radians() - bank,
                inclination: bank,
            });
            throw_of_unit.push(t);
        }
    }
    let throws = (0..pins.len()).map(|t| 0.2 * t as f64).collect();
    (units, throw_of_unit, throws)
}

fn forces(c: &mut Criterion) {
    let (units, throw_of_unit, throws) = vee_twelve();
    let axial: Vec<f64> = throw_of_unit.iter().map(|&t| throws[t]).collect();
    let mut group = c.benchmark_group("forces");
    group.bench_function("shaking_orders/first", |b| {
        b.iter(|| {
            let forces = ShakingForces::new(&units, &axial).expect("valid units");
            forces
                .orders(12)
                .expect("order 12")
                .at(157.0, 12)
                .expect("a speed")
        })
    });
    let orders = ShakingForces::new(&units, &axial)
        .and_then(|f| f.orders(12))
        .expect("valid");
    group.bench_function("shaking_orders/again", |b| {
        b.iter(|| orders.at(157.0, 12).expect("a speed"))
    });
    let bearings: Vec<f64> = (0..=throws.len()).map(|b| 0.2 * b as f64 - 0.1).collect();
    let layout = BearingLayout::new(&axial, Some(&bearings), 0.05).expect("valid layout");
    let phi: Vec<f64> = (0..ANGLES)
        .map(|i| 4.0 * PI * i as f64 / ANGLES as f64)
        .collect();
    let omega = vec![157.0; ANGLES];
    let epsilon = vec![0.0; ANGLES];
    let gas: Vec<f64> = (0..units.len() * ANGLES)
        .map(|i| 5e4 * (1.0 + (i as f64 * 0.01).sin()))
        .collect();
    let (mut horizontal, mut vertical) = (
        vec![0.0; bearings.len() * ANGLES],
        vec![0.0; bearings.len() * ANGLES],
    );
    group.bench_function("bearing_loads/720", |b| {
        b.iter(|| {
            bearing_loads(
                &units,
                &layout,
                &phi,
                &omega,
                &epsilon,
                &gas,
                9.81,
                &mut horizontal,
                &mut vertical,
                Parallelism::SERIAL,
            )
            .expect("valid input")
        })
    });
    // The constant speed's loads from the parts a machine keeps (made once).
    let parts = BearingParts::new(&units, &layout, &phi, &gas).expect("valid input");
    group.bench_function("bearing_loads/720/at_speed", |b| {
        b.iter(|| {
            parts
                .at_speed(157.0, 1.0, 9.81, &mut horizontal, &mut vertical)
                .expect("valid input")
        })
    });
    group.finish();
}

criterion_group!(benches, forces);
criterion_main!(benches);
