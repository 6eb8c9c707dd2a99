use super::*;

#[test]
fn a_piecewise_polynomial_wraps_and_takes_its_pieces() {
    // p = 1 + θ on [0, 1), 2 − (θ − 1)·2 on [1, 2π): linear, PPoly order 2.
    let x = vec![0.0, 1.0, 2.0 * PI];
    let slope2 = -2.0 / (2.0 * PI - 1.0);
    let p = PiecewisePolynomial::new(x, vec![1.0, slope2, 1.0, 2.0], 2.0 * PI).unwrap();
    assert_eq!(p.value(0.5), 1.5);
    assert_eq!(p.value(1.0), 2.0);
    assert!((p.value(0.5 + 2.0 * PI) - 1.5).abs() < 1e-15);
    assert!((p.value(-0.5) - (2.0 + slope2 * (2.0 * PI - 1.5))).abs() < 1e-14);
    assert!(PiecewisePolynomial::new(vec![0.0, 1.0], vec![1.0], 2.0 * PI).is_err());
    assert!(PiecewisePolynomial::new(vec![0.0, 7.0, 2.0 * PI], vec![1.0; 2], 2.0 * PI).is_err());
    assert!(PiecewisePolynomial::new(vec![0.0, 2.0 * PI], vec![1.0; 3], 2.0 * PI).is_ok());
    assert!(PiecewisePolynomial::new(vec![0.0, 2.0 * PI], vec![f64::NAN], 2.0 * PI).is_err());
    // One value not finite among many, anywhere: refused, naming the coefficients.
    for bad in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
        for at in [0, 17, 39] {
            let mut many = vec![1.0; 40];
            many[at] = bad;
            let refused = PiecewisePolynomial::new(vec![0.0, 2.0 * PI], many, 2.0 * PI);
            assert_eq!(refused.unwrap_err().parameter(), Some("coefficients"));
        }
    }
}

#[test]
fn the_fold_is_rem_euclid_to_the_last_bit() {
    for period in [2.0 * PI, 4.0 * PI, 1.0, 3.0e-3] {
        let mut angles = vec![0.0, -0.0, period, -period, 2.0 * period, -2.0 * period];
        angles.extend([1e-300, -1e-300, -1e-17, f64::EPSILON, -f64::EPSILON]);
        // A fine sweep over several periods either side, and just around the ends.
        angles.extend((-4000..4000).map(|i| i as f64 * period / 997.0));
        for k in -3..=3 {
            let end = k as f64 * period;
            let mut x = end;
            for _ in 0..8 {
                x = x.next_up();
                angles.push(x);
            }
            let mut x = end;
            for _ in 0..8 {
                x = x.next_down();
                angles.push(x);
            }
        }
        for angle in angles {
            let (found, expected) = (periodic(angle, period), angle.rem_euclid(period));
            assert_eq!(
                found.to_bits(),
                expected.to_bits(),
                "{angle:e} mod {period}"
            );
        }
    }
}

#[test]
fn the_guessed_piece_is_the_searched_one() {
    // Uniform, nearly uniform and very uneven breakpoints over 4π.
    let cycle = 4.0 * PI;
    let uniform: Vec<f64> = (0..=720).map(|i| cycle * i as f64 / 720.0).collect();
    let bunched: Vec<f64> = (0..=50)
        .map(|i| cycle * (i as f64 / 50.0).powi(3))
        .collect();
    let shifted: Vec<f64> = (0..=90).map(|i| -1.0 + cycle * i as f64 / 90.0).collect();
    for x in [uniform, bunched, shifted] {
        let m = x.len() - 1;
        let p = PiecewisePolynomial::new(x.clone(), vec![1.0; 2 * m], cycle).unwrap();
        let mut probes: Vec<f64> = x.clone();
        probes.extend(x.iter().map(|b| b.next_up()));
        probes.extend(x.iter().map(|b| b.next_down()));
        probes.extend((0..5000).map(|i| x[0] + cycle * i as f64 / 4999.0));
        for t in probes.into_iter().filter(|t| (x[0]..=x[m]).contains(t)) {
            let searched = x.partition_point(|&b| b <= t).saturating_sub(1).min(m - 1);
            assert_eq!(p.piece(t), searched, "{t}");
        }
    }
}

#[test]
fn net_piston_forces_are_the_pressures_on_the_two_circles() {
    // D = 0.2 m, d = 0.05 m: A = 0.01π, A_c = (0.04 − 0.0025)π/4 = 0.009375π (m²).
    let gas = [
        GasCylinder {
            bore: 0.2,
            piston_rod_diameter: 0.05,
            ..GasCylinder::NONE
        },
        GasCylinder::NONE,
    ];
    let head = [1e5, 0.0, 7.0, 7.0];
    let crank_end = [0.0, 2e5, 0.0, 0.0];
    let mut out = [f64::NAN; 4];
    net_piston_forces(&gas, &head, &crank_end, &mut out).unwrap();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
    assert!(close(out[0], 1e5 * 0.01 * PI), "{}", out[0]);
    assert!(close(out[1], -2e5 * 0.009375 * PI), "{}", out[1]);
    assert_eq!(&out[2..], &[0.0, 0.0], "no bore, no force");
    let mut short = [0.0; 3];
    assert!(net_piston_forces(&gas, &head[..3], &crank_end[..3], &mut short).is_err());
    let mut five = [0.0; 5];
    assert!(net_piston_forces(&gas, &[0.0; 5], &[0.0; 5], &mut five).is_err());
    let wide_rod = [GasCylinder {
        bore: 0.1,
        piston_rod_diameter: 0.2,
        ..GasCylinder::NONE
    }];
    assert!(net_piston_forces(&wide_rod, &[1.0], &[1.0], &mut [0.0]).is_err());
}

#[test]
fn a_look_up_from_a_hint_is_the_searched_one_in_any_order() {
    // A cubic spline-like table of 360 uneven pieces over 4π, probed in increasing order
    // (the walk), decreasing, and scattered: value_near gives value's doubles every time,
    // and so does values_in_runs, in runs of 1, 7 and 13 (3001 probes: a last run short).
    let cycle = 4.0 * PI;
    let x: Vec<f64> = (0..=360)
        .map(|i| {
            let u = i as f64 / 360.0;
            cycle * (u + 0.02 * (6.0 * PI * u).sin())
        })
        .collect();
    let m = x.len() - 1;
    let coefficients: Vec<f64> = (0..4 * m)
        .map(|n| ((n * 7919) % 113) as f64 - 56.0)
        .collect();
    let p = PiecewisePolynomial::new(x, coefficients, cycle).unwrap();
    let increasing: Vec<f64> = (0..3001)
        .map(|i| -1.0 + 3.0 * cycle * i as f64 / 3000.0)
        .collect();
    let decreasing: Vec<f64> = increasing.iter().rev().copied().collect();
    let scattered: Vec<f64> = (0..3001)
        .map(|i| cycle * (((i * 104_729) % 3001) as f64 / 1500.0 - 0.5))
        .collect();
    for probes in [increasing, decreasing, scattered] {
        let mut hint = 0;
        for &t in &probes {
            let (near, searched) = (p.value_near(t, &mut hint), p.value(t));
            assert_eq!(near.to_bits(), searched.to_bits(), "{t}");
        }
        // In runs of any length: most runs here cross a breakpoint (those angles looked up
        // alone), a run of one never does.
        for run in [1, 7, 13] {
            let mut together = vec![f64::NAN; probes.len()];
            p.values_in_runs(&probes, run, &mut together);
            for (&t, value) in probes.iter().zip(together) {
                assert_eq!(value.to_bits(), p.value(t).to_bits(), "{t} {run}");
            }
        }
    }
}

/// Hermite cubics through p and p′ at the breakpoints `x` over `cycle`, in PPoly rows
/// (highest power first): a PCHIP-like diagram, C¹ at every breakpoint.
fn hermite_diagram(
    x: Vec<f64>,
    cycle: f64,
    p: impl Fn(f64) -> f64,
    dp: impl Fn(f64) -> f64,
) -> PiecewisePolynomial {
    let pieces = x.len() - 1;
    let mut rows = vec![vec![0.0; pieces]; 4];
    for i in 0..pieces {
        let (a, b) = (x[i], x[i + 1]);
        let h = b - a;
        let (pa, pb, da, db) = (p(a), p(b), dp(a), dp(b));
        let c2 = (3.0 * (pb - pa) / h - 2.0 * da - db) / h;
        let c3 = (da + db - 2.0 * (pb - pa) / h) / (h * h);
        (rows[0][i], rows[1][i], rows[2][i], rows[3][i]) = (c3, c2, da, pa);
    }
    PiecewisePolynomial::new(x, rows.concat(), cycle).unwrap()
}

/// A smooth four-stroke-like pressure, p = 30 bar·(0.6 + 0.4 cos(θ/2))³, as Hermite cubics
/// on `pieces` equal pieces over `cycle`.
fn smooth_diagram(pieces: usize, cycle: f64) -> PiecewisePolynomial {
    let x: Vec<f64> = (0..=pieces)
        .map(|i| cycle * i as f64 / pieces as f64)
        .collect();
    let p = |t: f64| 30e5 * (0.6 + 0.4 * (t / 2.0).cos()).powi(3);
    let dp = |t: f64| -30e5 * 3.0 * (0.6 + 0.4 * (t / 2.0).cos()).powi(2) * 0.2 * (t / 2.0).sin();
    hermite_diagram(x, cycle, p, dp)
}

/// A small slider-crank unit at `phase`, its cylinder inclined by `inclination` (rad).
fn small_unit(phase: f64, inclination: f64) -> PhysicalCylinder {
    PhysicalCylinder {
        crank_radius: 0.06,
        rod_length: 0.2,
        piston_mass: 1.0,
        rod_mass: 1.0,
        rod_cg: 0.05,
        rod_inertia: 0.003,
        crank_mass: 0.0,
        crank_cg_radius: 0.0,
        counterweight_mass: 0.0,
        counterweight_radius: 0.0,
        phase,
        inclination,
    }
}

#[test]
fn the_slope_of_the_gas_work_is_the_derivative_of_the_gas_torque() {
    // Two units of one PCHIP-like diagram (cubic pieces), one double-acting: W″ = M_gas′
    // from the indicator rules' interpolants against central differences of M_gas = Σ F s′
    // from the kernels (Dynamics::gas_torque of the forces looked up at φ ± h).
    let cycle = 4.0 * PI;
    let diagram = smooth_diagram(96, cycle);
    let units = [small_unit(0.0, 0.3), small_unit(2.5, 0.3)];
    let gas = [
        GasCylinder {
            bore: 0.1,
            piston_rod_diameter: 0.0,
            head: Some(0),
            crank_end: None,
        },
        GasCylinder {
            bore: 0.1,
            piston_rod_diameter: 0.03,
            head: Some(0),
            crank_end: Some(0),
        },
    ];
    let diagrams: Arc<[PiecewisePolynomial]> = vec![diagram].into();
    let work = GasWork::new(&units, &gas, diagrams.clone(), cycle, None).unwrap();
    let forces = Forces::new(&units, &gas, diagrams, cycle).unwrap();
    let dynamics = crate::dynamics::Dynamics::new(&units, 0.0).unwrap();
    // Angles inside pieces (central differences across a breakpoint see its kink).
    let phi: Vec<f64> = (0..40).map(|i| 0.3 + 0.31 * i as f64).collect();
    let (_, slope) = work.with_slope_at(&phi, phi.len());
    let h = 1e-5;
    let torque = |shift: f64| {
        let at: Vec<f64> = phi.iter().map(|p| p + shift).collect();
        let mut out = vec![0.0; at.len()];
        dynamics
            .gas_torque(
                &at,
                &forces.at(&at),
                &mut out,
                crate::parallel::Parallelism::SERIAL,
            )
            .unwrap();
        out
    };
    let (ahead, behind) = (torque(h), torque(-h));
    let scale = ahead.iter().fold(0.0_f64, |m, t| m.max(t.abs()));
    for i in 0..phi.len() {
        let numeric = (ahead[i] - behind[i]) / (2.0 * h);
        assert!(
            (slope[i] - numeric).abs() <= 1e-6 * scale,
            "φ = {}: {} against {numeric}",
            phi[i],
            slope[i]
        );
    }
}

#[test]
fn units_summed_on_one_rule_are_the_units_looked_up_one_by_one() {
    // A diagram of equal steps over 4π with one kink moved off the steps (a synthetic
    // diagram's combustion start), four units on the steps (one a cycle out, one negative)
    // and, in a second machine, one between them: W of each machine, and its slope, against
    // the sum of the units' own W, each a machine alone (whose rule is never summed).
    let cycle = 4.0 * PI;
    let pieces = 720;
    let step = cycle / pieces as f64;
    let mut x: Vec<f64> = (0..=pieces).map(|i| i as f64 * step).collect();
    x[100] += 3e-9;
    // Hermite cubics through a smooth p and p′ (PPoly rows, highest power first): W″ is
    // continuous, so a look-up on either side of an edge gives it to rounding.
    let p = |t: f64| 30e5 * (0.6 + 0.4 * (t / 2.0).cos()).powi(3) + 1e5 * (7.0 * t).sin();
    let dp = |t: f64| {
        -30e5 * 3.0 * (0.6 + 0.4 * (t / 2.0).cos()).powi(2) * 0.2 * (t / 2.0).sin()
            + 7e5 * (7.0 * t).cos()
    };
    let diagrams: Arc<[PiecewisePolynomial]> = vec![hermite_diagram(x, cycle, p, dp)].into();
    let unit = |phase: f64| small_unit(phase, 0.0);
    let gas = GasCylinder {
        bore: 0.1,
        piston_rod_diameter: 0.0,
        head: Some(0),
        crank_end: None,
    };
    let on_steps = [0.0, 180.0 * step, cycle + 360.0 * step, -90.0 * step];
    // Angles off the edges (where W″, a slope of interpolants, may differ on either side
    // by their error), then the edges themselves (W alone).
    let mut phi: Vec<f64> = (0..3000)
        .map(|i| -cycle + 0.1234567 + 3.0 * cycle * i as f64 / 3001.0)
        .collect();
    let off_edges = phi.len();
    phi.extend((0..=pieces).map(|i| i as f64 * step));
    // Most units off the steps: no sum (it would save no look-up), the units one by one.
    let off: Vec<PhysicalCylinder> = [0.0, step / 3.0, step / 5.0, 2.5 * step]
        .iter()
        .map(|&a| unit(a))
        .collect();
    let apart = GasWork::new(&off, &[gas; 4], diagrams.clone(), cycle, None).unwrap();
    assert_eq!(apart.strays(), [None]);
    for phases in [on_steps.to_vec(), [&on_steps[..], &[step / 3.0]].concat()] {
        let units: Vec<PhysicalCylinder> = phases.iter().map(|&a| unit(a)).collect();
        let work = GasWork::new(
            &units,
            &vec![gas; units.len()],
            diagrams.clone(),
            cycle,
            None,
        )
        .unwrap();
        // The kink's two panels, at each unit's shift, hold the strays (and every panel the
        // unit between steps): every other panel is one look-up.
        let strays = work.strays()[0].expect("a sum of the units");
        if phases.len() == 4 {
            assert!((1..=2 * 4 * 3).contains(&strays), "{strays}");
        } else {
            assert!(strays >= pieces, "{strays}");
        }
        let (found, slope) = work.with_slope_at(&phi, off_edges);
        let mut expected = vec![0.0; phi.len()];
        let mut expected_slope = vec![0.0; off_edges];
        for u in &units {
            let alone = GasWork::new(&[*u], &[gas], diagrams.clone(), cycle, None).unwrap();
            assert_eq!(alone.strays(), [None]);
            let (w, s) = alone.with_slope_at(&phi, off_edges);
            expected.iter_mut().zip(&w).for_each(|(e, w)| *e += w);
            expected_slope.iter_mut().zip(&s).for_each(|(e, s)| *e += s);
        }
        let scale = expected.iter().fold(0.0_f64, |m, w| m.max(w.abs()));
        let slope_scale = expected_slope.iter().fold(0.0_f64, |m, s| m.max(s.abs()));
        for i in 0..phi.len() {
            assert!(
                (found[i] - expected[i]).abs() <= 1e-13 * scale,
                "φ = {}: W {} against {}",
                phi[i],
                found[i],
                expected[i]
            );
        }
        for i in 0..off_edges {
            assert!(
                (slope[i] - expected_slope[i]).abs() <= 1e-12 * slope_scale,
                "φ = {}: W″ {} against {} (scale {slope_scale})",
                phi[i],
                slope[i],
                expected_slope[i]
            );
        }
        assert_eq!(work.at(&phi).unwrap(), found);
    }
}

#[test]
fn a_rule_taken_from_another_machine_gives_the_machines_own_doubles() {
    // Machines that differ from a first one in r and l take its indicator rules (and, with
    // its phases, its alignments): W and W″ must be the doubles of the machine made alone.
    // Where the pressures, the bore or the phases differ, what does not fit is not taken.
    let cycle = 4.0 * PI;
    let pieces = 360;
    let diagram = smooth_diagram(pieces, cycle);
    let diagrams: Arc<[PiecewisePolynomial]> = vec![diagram.clone()].into();
    let step = cycle / pieces as f64;
    let machine = |phases: &[f64], r: f64, l: f64| -> Vec<PhysicalCylinder> {
        phases
            .iter()
            .map(|&a| PhysicalCylinder {
                crank_radius: r,
                rod_length: l,
                ..small_unit(a, 0.2)
            })
            .collect()
    };
    let gas = |bore: f64| GasCylinder {
        bore,
        piston_rod_diameter: 0.0,
        head: Some(0),
        crank_end: None,
    };
    let phases = [0.0, 120.0 * step, 240.0 * step];
    let make = |units: &[PhysicalCylinder], bore: f64, d: &Arc<[PiecewisePolynomial]>, like| {
        GasWork::new(units, &vec![gas(bore); units.len()], d.clone(), cycle, like).unwrap()
    };
    let first = make(&machine(&phases, 0.06, 0.2), 0.1, &diagrams, None);
    let phi: Vec<f64> = (0..997)
        .map(|i| -1.0 + 2.5 * cycle * i as f64 / 996.0)
        .collect();
    let scaled: Arc<[PiecewisePolynomial]> = vec![diagram.scaled(1.1)].into();
    let copied: Arc<[PiecewisePolynomial]> = vec![diagram.clone()].into();
    let other_phases = [0.0, 60.0 * step, 240.0 * step];
    // (units, bore, diagrams, the rules and alignments it takes from the first)
    let cases = [
        (machine(&phases, 0.055, 0.23), 0.1, &diagrams, (1, 1)),
        (machine(&phases, 0.06, 0.25), 0.1, &copied, (1, 1)),
        (machine(&other_phases, 0.055, 0.2), 0.1, &diagrams, (1, 0)),
        (machine(&phases, 0.055, 0.23), 0.1, &scaled, (0, 0)),
        (machine(&phases, 0.055, 0.23), 0.11, &diagrams, (0, 0)),
    ];
    for (units, bore, d, taken) in cases {
        let alone = make(&units, bore, d, None);
        let like = make(&units, bore, d, Some(&first));
        assert_eq!(like.shared_with(&first), taken);
        assert_eq!(alone.shared_with(&first), (0, 0));
        assert_eq!(like.per_cycle.to_bits(), alone.per_cycle.to_bits());
        // Asked again (where the angles fall, kept by a shared rule, taken), and at angles
        // of the same length but one (looked for afresh): the doubles of the machine alone.
        let mut moved = phi.clone();
        moved[321] += 0.125;
        for angles in [&phi, &phi, &moved] {
            let (w, s) = like.with_slope_at(angles, 500);
            let (w0, s0) = alone.with_slope_at(angles, 500);
            for (a, b) in w.iter().chain(&s).zip(w0.iter().chain(&s0)) {
                assert_eq!(a.to_bits(), b.to_bits());
            }
        }
    }
}
