use super::*;

fn units() -> Vec<PhysicalCylinder> {
    let unit = |r: f64, l: f64, z: f64, inertia_factor: f64, phase: f64| PhysicalCylinder {
        crank_radius: r,
        rod_length: l,
        piston_mass: 3.0,
        rod_mass: 2.0,
        rod_cg: z,
        rod_inertia: inertia_factor * two_mass_rod_inertia(2.0, l, z),
        crank_mass: 1.5,
        crank_cg_radius: 0.05,
        counterweight_mass: 1.0,
        counterweight_radius: 0.08,
        phase,
        inclination: 1.2 - phase,
    };
    vec![
        unit(0.1, 0.35, 0.25, 1.0, 0.0),
        unit(0.1, 0.35, 0.25, 0.6, 2.1),
        unit(0.12, 0.3, 0.1, 1.4, -0.7),
    ]
}

/// Planar positions of one unit's piston pin and rod CG (cylinder axis along x; the
/// inclination turns everything rigidly and changes no speed), and the rod angle.
fn positions(u: &PhysicalCylinder, phi: f64) -> ([f64; 2], [f64; 2], f64) {
    let psi = phi + u.phase;
    let crank_pin = [u.crank_radius * psi.cos(), u.crank_radius * psi.sin()];
    let piston_pin = [
        crank_pin[0] + (u.rod_length.powi(2) - crank_pin[1].powi(2)).sqrt(),
        0.0,
    ];
    let t = u.rod_cg / u.rod_length;
    let cg = [
        piston_pin[0] + t * (crank_pin[0] - piston_pin[0]),
        t * crank_pin[1],
    ];
    (piston_pin, cg, (crank_pin[1] / u.rod_length).asin())
}

/// d/dφ by a fourth-order central difference.
fn slope(f: impl Fn(f64) -> f64, x: f64) -> f64 {
    let h = 1e-3;
    (8.0 * (f(x + h) - f(x - h)) - (f(x + 2.0 * h) - f(x - 2.0 * h))) / (12.0 * h)
}

/// 2T/φ̇² from Σ ½ m v² + ½ I β̇² with velocities from differentiated positions.
fn kinetic_inertia(units: &[PhysicalCylinder], shaft: f64, phi: f64) -> f64 {
    let mut j = shaft;
    for u in units {
        let piston = slope(|p| positions(u, p).0[0], phi);
        let cg_x = slope(|p| positions(u, p).1[0], phi);
        let cg_y = slope(|p| positions(u, p).1[1], phi);
        let rod = slope(|p| positions(u, p).2, phi);
        j += u.piston_mass * piston * piston
            + u.rod_mass * (cg_x * cg_x + cg_y * cg_y)
            + u.rod_inertia * rod * rod;
    }
    j
}

#[test]
fn inertia_is_twice_the_kinetic_energy_and_its_slope_the_derivative() {
    let units = units();
    let machine = Dynamics::new(&units, 9.81).unwrap();
    let phi: Vec<f64> = (0..97).map(|i| -3.0 + 0.0625 * i as f64).collect();
    let (mut j, mut dj) = (vec![0.0; phi.len()], vec![0.0; phi.len()]);
    machine
        .reduced_inertia(0.7, &phi, &mut j, &mut dj, Parallelism::SERIAL)
        .unwrap();
    for (i, &p) in phi.iter().enumerate() {
        let expected = kinetic_inertia(&units, 0.7, p);
        assert!(
            (j[i] - expected).abs() <= 1e-9 * expected,
            "J at {p}: {} vs {expected}",
            j[i]
        );
        let numerical = slope(
            |x| {
                let (mut a, mut b) = ([0.0], [0.0]);
                machine
                    .reduced_inertia(0.7, &[x], &mut a, &mut b, Parallelism::SERIAL)
                    .unwrap();
                a[0]
            },
            p,
        );
        assert!(
            (dj[i] - numerical).abs() <= 1e-9 * j[i],
            "J' at {p}: {} vs {numerical}",
            dj[i]
        );
    }
}

#[test]
fn travel_velocity_and_gas_torque_by_virtual_work() {
    let units = units();
    let machine = Dynamics::new(&units, 9.81).unwrap();
    let phi: Vec<f64> = (0..61).map(|i| 0.1 * i as f64).collect();
    let n = phi.len();
    let (mut s, mut v) = (vec![0.0; 3 * n], vec![0.0; 3 * n]);
    machine
        .kinematics(Kinematics::Travel, &phi, &mut s, Parallelism::SERIAL)
        .unwrap();
    machine
        .kinematics(Kinematics::Velocity, &phi, &mut v, Parallelism::SERIAL)
        .unwrap();
    let forces: Vec<f64> = (0..3 * n)
        .map(|i| 1e4 * (1.0 + (0.37 * i as f64).sin()))
        .collect();
    let mut torque = vec![0.0; n];
    machine
        .gas_torque(&phi, &forces, &mut torque, Parallelism::SERIAL)
        .unwrap();
    for (j, u) in units.iter().enumerate() {
        // s = r + l − x: the travel from outer dead centre, from the position.
        let travel = |p: f64| u.crank_radius + u.rod_length - positions(u, p).0[0];
        for (i, &p) in phi.iter().enumerate() {
            assert!((s[j * n + i] - travel(p)).abs() <= 1e-15);
            assert!((v[j * n + i] - slope(travel, p)).abs() <= 1e-10);
        }
    }
    for i in 0..n {
        let work: f64 = (0..3).map(|j| forces[j * n + i] * v[j * n + i]).sum();
        assert!((torque[i] - work).abs() <= 1e-12 * work.abs().max(1.0));
    }
}

/// Σ m·g·height of one unit's masses (rod and piston turned by γ from the cylinder
/// frame; web and counterweight on the crank), minus its value at ψ = 0.
fn weight_energy(u: &PhysicalCylinder, g: f64, phi: f64) -> f64 {
    let height = |p: f64| {
        let (piston, cg, _) = positions(u, p);
        let up = |v: [f64; 2]| v[0] * u.inclination.sin() + v[1] * u.inclination.cos();
        let crank = (p + u.phase + u.inclination).sin();
        u.piston_mass * up(piston)
            + u.rod_mass * up(cg)
            + (u.crank_mass * u.crank_cg_radius - u.counterweight_mass * u.counterweight_radius)
                * crank
    };
    g * (height(phi) - height(-u.phase))
}

#[test]
fn potential_energy_is_the_weight_and_its_torque_the_slope() {
    let units = units();
    let machine = Dynamics::new(&units, 9.81).unwrap();
    let phi: Vec<f64> = (0..73).map(|i| -2.0 + 0.1 * i as f64).collect();
    let (mut u, mut torque) = (vec![0.0; phi.len()], vec![0.0; phi.len()]);
    machine
        .potential_energy(&phi, &mut u, Parallelism::SERIAL)
        .unwrap();
    machine
        .gravity_torque(&phi, &mut torque, Parallelism::SERIAL)
        .unwrap();
    let energy = |p: f64| {
        units
            .iter()
            .map(|unit| weight_energy(unit, 9.81, p))
            .sum::<f64>()
    };
    for (i, &p) in phi.iter().enumerate() {
        assert!(
            (u[i] - energy(p)).abs() <= 1e-13 * 10.0,
            "U at {p}: {} vs {}",
            u[i],
            energy(p)
        );
        assert!(
            (torque[i] + slope(energy, p)).abs() <= 1e-9,
            "torque at {p}"
        );
    }
    // The dimensionless engine at a speed is the same energy over I_w ω².
    let omega = 10.0 * std::f64::consts::PI; // 300 rpm
    let engine = machine.dimensionless(2.0, omega).unwrap();
    let mut star = vec![0.0; phi.len()];
    engine
        .evaluate(
            Quantity::PotentialEnergy,
            &phi,
            &mut star,
            Parallelism::SERIAL,
        )
        .unwrap();
    for (a, b) in star.iter().zip(&u) {
        assert!((a * 2.0 * omega * omega - b).abs() <= 1e-13 * 10.0);
    }
    let without = Dynamics::new(&units, 0.0).unwrap();
    without
        .potential_energy(&phi, &mut u, Parallelism::SERIAL)
        .unwrap();
    assert!(u.iter().all(|&x| x == 0.0));
}

#[test]
fn serial_equals_parallel_and_bad_units_are_named() {
    let machine = Dynamics::new(&units(), 9.81).unwrap();
    let phi: Vec<f64> = (0..50_000).map(|i| 1e-4 * i as f64).collect();
    let run = |parallelism| {
        let (mut j, mut dj) = (vec![0.0; phi.len()], vec![0.0; phi.len()]);
        machine
            .reduced_inertia(1.0, &phi, &mut j, &mut dj, parallelism)
            .unwrap();
        let forces = vec![1.0; 3 * phi.len()];
        let mut gas = vec![0.0; phi.len()];
        machine
            .gas_torque(&phi, &forces, &mut gas, parallelism)
            .unwrap();
        (j, dj, gas)
    };
    assert_eq!(run(Parallelism::SERIAL), run(Parallelism { threshold: 0 }));
    let mut bad = units()[0];
    bad.rod_cg = 0.5;
    let message = Dynamics::new(&[bad], 9.81).unwrap_err().to_string();
    assert!(message.contains("rod_cg"), "{message}");
    assert!(Dynamics::new(&[], 9.81).is_err());
    let (mut a, mut b) = ([0.0], [0.0]);
    let error = machine.reduced_inertia(0.0, &[0.0], &mut a, &mut b, Parallelism::SERIAL);
    assert!(error.unwrap_err().to_string().contains("shaft_inertia"));
}
