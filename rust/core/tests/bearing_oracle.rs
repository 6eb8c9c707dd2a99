//! The main-bearing loads against an oracle written here from scratch: the positions of the
//! crank pin, piston pin and rod of every unit as functions of time, their accelerations by
//! central differences (fourth order), and Newton–Euler per body (piston, rod: five unknowns — the rod's
//! force on the piston, the wall's normal force, the pin's force on the rod — solved as a
//! linear system), the throw's own inertia and weight, and the lever rule.

use multicrank_core::{bearing_loads, BearingLayout, BearingParts, Parallelism, PhysicalCylinder};

fn units() -> Vec<PhysicalCylinder> {
    let unit = |k: f64| PhysicalCylinder {
        crank_radius: 0.043 + 0.004 * k,
        rod_length: 0.151 + 0.013 * k,
        piston_mass: 0.61 + 0.17 * k,
        rod_mass: 0.53 + 0.11 * k,
        rod_cg: 0.102 + 0.007 * k,
        rod_inertia: 0.0029 + 0.0007 * k,
        crank_mass: 1.3 + 0.2 * k,
        crank_cg_radius: 0.021 + 0.002 * k,
        counterweight_mass: 0.9 + 0.3 * k,
        counterweight_radius: 0.037 + 0.003 * k,
        phase: 0.7 + 2.1 * k,
        inclination: 1.1 + 0.6 * k,
    };
    (0..3).map(|k| unit(k as f64)).collect()
}

const AXIAL: [f64; 3] = [0.05, 0.18, 0.18];
const BEARINGS: [f64; 3] = [0.0, 0.12, 0.3];

fn solve(mut a: [[f64; 6]; 5]) -> [f64; 5] {
    for col in 0..5 {
        let pivot = (col..5)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .expect("a column");
        a.swap(col, pivot);
        let pivot_row = a[col];
        for (row, values) in a.iter_mut().enumerate() {
            if row != col {
                let f = values[col] / pivot_row[col];
                for (value, p) in values.iter_mut().zip(pivot_row).skip(col) {
                    *value -= f * p;
                }
            }
        }
    }
    std::array::from_fn(|i| a[i][5] / a[i][i])
}

/// (P, B, G, rod angle, crank point at unit radius) of a unit, in the global frame.
type Positions = ([f64; 2], [f64; 2], [f64; 2], f64, [f64; 2]);

/// The [`Positions`] of a unit at crank angle φ.
fn positions(u: &PhysicalCylinder, phi: f64) -> Positions {
    let e = [u.inclination.cos(), u.inclination.sin()];
    let n = [-e[1], e[0]];
    let psi = phi + u.phase;
    let d = [
        psi.cos() * e[0] + psi.sin() * n[0],
        psi.cos() * e[1] + psi.sin() * n[1],
    ];
    let p = [u.crank_radius * d[0], u.crank_radius * d[1]];
    // B on the axis, |B − P| = l: x² − 2x(P·e) + |P|² − l² = 0, the far root.
    let pe = p[0] * e[0] + p[1] * e[1];
    let pn = p[0] * n[0] + p[1] * n[1];
    let x = pe + (u.rod_length * u.rod_length - pn * pn).sqrt();
    let b = [x * e[0], x * e[1]];
    let w = [(b[0] - p[0]) / u.rod_length, (b[1] - p[1]) / u.rod_length];
    let g = [b[0] - u.rod_cg * w[0], b[1] - u.rod_cg * w[1]];
    (p, b, g, w[1].atan2(w[0]), d)
}

/// The oracle's load of each bearing (horizontal, vertical) at time 0 with φ(t) = φ₀ + ωt + ½εt².
fn oracle(
    units: &[PhysicalCylinder],
    phi0: f64,
    omega: f64,
    eps: f64,
    gas: &[f64],
    g: f64,
) -> Vec<[f64; 2]> {
    let h = 2e-3 / omega.abs().max(1.0);
    let phi_at = |t: f64| phi0 + omega * t + 0.5 * eps * t * t;
    let second = |f: &dyn Fn(f64) -> f64| {
        (-f(2.0 * h) + 16.0 * f(h) - 30.0 * f(0.0) + 16.0 * f(-h) - f(-2.0 * h)) / (12.0 * h * h)
    };
    let gv = [0.0, -g];
    let mut loads = vec![[0.0; 2]; BEARINGS.len()];
    for (j, u) in units.iter().enumerate() {
        let at = |t: f64| positions(u, phi_at(t));
        let (p, b, gc, _, _) = at(0.0);
        let acc = |pick: &dyn Fn(Positions) -> f64| second(&|t| pick(at(t)));
        let a_b = [acc(&|s| s.1[0]), acc(&|s| s.1[1])];
        let a_g = [acc(&|s| s.2[0]), acc(&|s| s.2[1])];
        let alpha = acc(&|s| s.3);
        let a_d = [acc(&|s| s.4[0]), acc(&|s| s.4[1])];
        let e = [u.inclination.cos(), u.inclination.sin()];
        let n = [-e[1], e[0]];
        let f = gas[j];
        // Unknowns R = (x0, x1), N = x2, Q = (x3, x4).
        let (bg, pg) = ([b[0] - gc[0], b[1] - gc[1]], [p[0] - gc[0], p[1] - gc[1]]);
        let (mt, mk) = (u.piston_mass, u.rod_mass);
        let x = solve([
            [
                1.0,
                0.0,
                n[0],
                0.0,
                0.0,
                mt * a_b[0] + f * e[0] - mt * gv[0],
            ],
            [
                0.0,
                1.0,
                n[1],
                0.0,
                0.0,
                mt * a_b[1] + f * e[1] - mt * gv[1],
            ],
            [-1.0, 0.0, 0.0, 1.0, 0.0, mk * a_g[0] - mk * gv[0]],
            [0.0, -1.0, 0.0, 0.0, 1.0, mk * a_g[1] - mk * gv[1]],
            // I α = (B − G) × (−R) + (P − G) × Q
            [bg[1], -bg[0], 0.0, -pg[1], pg[0], u.rod_inertia * alpha],
        ]);
        let (ms, mp) = (u.crank_mass, u.counterweight_mass);
        let first = ms * u.crank_cg_radius - mp * u.counterweight_radius;
        let load = [
            -x[3] + (ms + mp) * gv[0] - first * a_d[0],
            -x[4] + (ms + mp) * gv[1] - first * a_d[1],
        ];
        let z = AXIAL[j];
        let after = BEARINGS
            .iter()
            .position(|&bz| bz > z)
            .expect("a bearing beyond");
        let (za, zb) = (BEARINGS[after - 1], BEARINGS[after]);
        for (bearing, share) in [
            (after - 1, (zb - z) / (zb - za)),
            (after, (z - za) / (zb - za)),
        ] {
            loads[bearing][0] += share * load[0];
            loads[bearing][1] += share * load[1];
        }
    }
    loads
}

#[test]
fn bearing_loads_agree_with_a_newton_euler_oracle() {
    let units = units();
    let layout = BearingLayout::new(&AXIAL, Some(&BEARINGS), 0.05).unwrap();
    let points = 37;
    let phi: Vec<f64> = (0..points).map(|i| 0.3 + 0.17 * i as f64).collect();
    let gas: Vec<f64> = (0..3 * points)
        .map(|k| 4000.0 * (1.0 + (0.37 * k as f64).sin()))
        .collect();
    let g = 9.81;
    for (omega, eps) in [(314.0, 0.0), (157.0, 2.5e4), (30.0, -900.0)] {
        let (speed, accel) = (vec![omega; points], vec![eps; points]);
        let size = layout.bearings() * points;
        let (mut hz, mut vt) = (vec![0.0; size], vec![0.0; size]);
        bearing_loads(
            &units,
            &layout,
            &phi,
            &speed,
            &accel,
            &gas,
            g,
            &mut hz,
            &mut vt,
            Parallelism::SERIAL,
        )
        .unwrap();
        let (mut hp, mut vp) = (vec![0.0; size], vec![0.0; size]);
        let parts = BearingParts::new(&units, &layout, &phi, &gas).unwrap();
        parts.at_speed(omega, 1.0, g, &mut hp, &mut vp).unwrap();
        for i in 0..points {
            let unit_gas: Vec<f64> = (0..3).map(|j| gas[j * points + i]).collect();
            let want = oracle(&units, phi[i], omega, eps, &unit_gas, g);
            let scale = want.iter().fold(0.0_f64, |m, l| m.max(l[0].hypot(l[1])));
            for (b, w) in want.iter().enumerate() {
                let found = [hz[b * points + i], vt[b * points + i]];
                for d in 0..2 {
                    assert!(
                        (found[d] - w[d]).abs() <= 1e-8 * scale,
                        "{omega} {eps} {i} {b}: {found:?} {w:?}"
                    );
                }
                if eps == 0.0 {
                    // the parts kept: the same loads to rounding
                    let parted = [hp[b * points + i], vp[b * points + i]];
                    for d in 0..2 {
                        assert!(
                            (parted[d] - found[d]).abs() <= 1e-12 * scale,
                            "{parted:?} {found:?}"
                        );
                    }
                }
            }
        }
    }
}
