use super::*;

#[test]
fn twelve_points_match_the_tables() {
    // Abramowitz & Stegun, table 25.4 (n = 12), 15 digits.
    let nodes = [
        0.125233408511469,
        0.367831498998180,
        0.587317954286617,
        0.769902674194305,
        0.904117256370475,
        0.981560634246719,
    ];
    let weights = [
        0.249147045813403,
        0.233492536538355,
        0.203167426723066,
        0.160078328543346,
        0.106939325995318,
        0.047175336386512,
    ];
    let (x, w) = gauss_legendre(12);
    for i in 0..6 {
        assert!(
            (x[6 + i] - nodes[i]).abs() < 1e-15,
            "{} vs {}",
            x[6 + i],
            nodes[i]
        );
        assert_eq!(x[5 - i], -x[6 + i]);
        assert!(
            (w[6 + i] - weights[i]).abs() < 1e-15,
            "{} vs {}",
            w[6 + i],
            weights[i]
        );
    }
    // Exact for degree 2n − 1 = 23: ∫x^22 = 2/23, to rounding.
    let moment: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(22)).sum();
    assert!((moment - 2.0 / 23.0).abs() < 4e-16, "{moment}");
    let total: f64 = w.iter().sum();
    // Twelve terms summed: a few ulps of 2.
    assert!((total - 2.0).abs() < 2e-15, "{total}");
    // numpy.polynomial.legendre.leggauss(12), to the last bit or one ulp.
    let numpy = [0.1252334085114689, 0.9815606342467192];
    assert!((x[6] - numpy[0]).abs() <= 2.0 * f64::EPSILON * numpy[0]);
    assert!((x[11] - numpy[1]).abs() <= 2.0 * f64::EPSILON);
}

#[test]
fn every_order_integrates_its_degree() {
    for n in 1..=20 {
        let (x, w) = gauss_legendre(n);
        for degree in 0..2 * n {
            let exact = if degree % 2 == 1 {
                0.0
            } else {
                2.0 / (degree as f64 + 1.0)
            };
            let sum: f64 = x
                .iter()
                .zip(&w)
                .map(|(x, w)| w * x.powi(degree as i32))
                .sum();
            assert!((sum - exact).abs() < 1e-14, "n {n} degree {degree}: {sum}");
        }
    }
}

#[test]
fn the_running_integral_is_exact_for_polynomials_and_spectral_otherwise() {
    let cycle = 2.0 * PI;
    let panels = Panels::new(&breaks(vec![1.0], cycle), 12, PI / 8.0);
    // Degree 11 on every panel: the interpolant is the function.
    let cubic: Vec<f64> = panels.phi.iter().map(|p| p.powi(11) - 3.0 * p).collect();
    let phi = [0.0, 0.3, 1.0, 2.5, cycle];
    for (found, p) in panels.running_at(&cubic, &phi).iter().zip(phi) {
        let exact = p.powi(12) / 12.0 - 1.5 * p * p;
        assert!(
            (found - exact).abs() <= 1e-13 * (1.0 + exact.abs()),
            "{p}: {found} {exact}"
        );
    }
    let slope = panels.slope(&cubic);
    for (found, p) in slope.iter().zip(&panels.phi) {
        let exact = 11.0 * p.powi(10) - 3.0;
        assert!((found - exact).abs() <= 1e-11 * (1.0 + exact.abs()), "{p}");
    }
    let smooth: Vec<f64> = panels.phi.iter().map(|p| p.sin().exp()).collect();
    let found = panels.running_at(&smooth, &[cycle])[0];
    let exact = 2.0 * PI * 1.266_065_877_752_008_4;
    assert!((found - exact).abs() < 1e-14 * exact);
}

#[test]
fn a_look_up_from_a_hint_is_the_search_and_the_monomial_form_its_integral_and_slope() {
    // Degree 11 on uneven panels: at angles in increasing, decreasing and scattered
    // order, the hinted look-up gives running_at's doubles; the monomial form the same
    // integral to rounding, and the slope f′.
    let cycle = 2.0 * PI;
    let panels = Panels::new(&breaks(vec![0.4, 0.45, 2.0, 5.9], cycle), 12, PI / 8.0);
    let f: Vec<f64> = panels.phi.iter().map(|p| p.powi(11) - 3.0 * p).collect();
    let running = panels.antiderivative(&f);
    let increasing: Vec<f64> = (0..=997).map(|i| cycle * i as f64 / 997.0).collect();
    let decreasing: Vec<f64> = increasing.iter().rev().copied().collect();
    let scattered: Vec<f64> = (0..=997)
        .map(|i| cycle * ((i * 7919) % 998) as f64 / 997.0)
        .collect();
    let mut orders = vec![increasing, decreasing, scattered];
    orders[0].extend(panels.edges.iter().copied());
    let monomial = MonomialRunning::through(&panels, &f);
    let scale = running.at_edges.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
    for angles in &orders {
        // Eight at a time (their Horner chains side by side): at_near's doubles, edges too.
        let (mut hint, mut lanes_hint) = (0, 0);
        for chunk in angles.chunks_exact(8) {
            let lanes: &[f64; 8] = chunk.try_into().unwrap();
            let found = monomial.at_lanes(&panels, lanes, &mut lanes_hint);
            for (angle, value) in chunk.iter().zip(found) {
                let one = monomial.at_near(&panels, *angle, &mut hint);
                assert_eq!(value.to_bits(), one.to_bits(), "{angle}");
            }
        }
    }
    for angles in orders {
        let (mut hint, mut other, mut third) = (0, 0, 0);
        for &angle in &angles {
            let (at, coefficients) = (&running.at_edges, &running.coefficients);
            let near = running_at_near(&panels, at, coefficients, angle, &mut hint);
            let searched = running_at(&panels, at, coefficients, angle);
            assert_eq!(near.to_bits(), searched.to_bits(), "{angle}");
            // The monomial form: the same integral to rounding, and the slope f′ of the
            // degree-11 interpolant (f itself).
            let powers = monomial.at_near(&panels, angle, &mut other);
            assert!((powers - searched).abs() <= 1e-14 * scale, "{angle}");
            let (with, slope) = monomial.at_and_slope_near(&panels, angle, &mut third);
            assert_eq!(with.to_bits(), powers.to_bits(), "{angle}");
            let exact = 11.0 * angle.powi(10) - 3.0;
            assert!(
                (slope - exact).abs() <= 1e-11 * (1.0 + exact.abs()),
                "{angle}: {slope} {exact}"
            );
        }
    }
}

#[test]
fn panels_integrate_a_periodic_function_and_resolve_it() {
    let cycle = 2.0 * PI;
    let panels = Panels::new(&breaks(vec![1.0, 1.0 + 1e-14, 3.0], cycle), 12, PI / 8.0);
    assert!(panels.edges.contains(&1.0) && panels.edges.contains(&3.0));
    assert!(!panels.edges.contains(&(1.0 + 1e-14)));
    assert!(panels
        .edges
        .windows(2)
        .all(|e| e[1] - e[0] <= PI / 8.0 + 1e-15));
    let f: Vec<f64> = panels.phi.iter().map(|p| (p.sin()).exp()).collect();
    // ∫₀^{2π} e^{sin φ} dφ = 2π I₀(1).
    let exact = 2.0 * PI * 1.266_065_877_752_008_4;
    assert!((panels.integral(&f) - exact).abs() < 1e-14 * exact);
    assert!(panels.tail(&f) < 1e-12);
    let sharp: Vec<f64> = panels.phi.iter().map(|p| (40.0 * p.sin()).cos()).collect();
    assert!(panels.tail(&sharp) > 1e-4);
}

#[test]
fn breaks_of_angles_in_order_are_those_of_the_angles_shuffled() {
    // Angles already sorted within [0, Φ] skip the sort: the cuts must be the doubles of the
    // same angles in any order, with near duplicates, −0.0, 0 and Φ themselves among them.
    let cycle = 4.0 * PI;
    let mut random = crate::test_support::Lcg(11);
    let mut sorted: Vec<f64> = (0..500).map(|_| random.next() * cycle).collect();
    sorted.extend([0.0, -0.0, cycle, 1.0, 1.0 + 1e-13, 2.0, 2.0 + 1e-9]);
    sorted.sort_by(f64::total_cmp);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for take in [0, 1, 7, sorted.len()] {
        let part = &sorted[sorted.len() - take..];
        let mut shuffled = part.to_vec();
        shuffled.reverse();
        shuffled.rotate_left(take / 3);
        assert_eq!(
            bits(&breaks(part.to_vec(), cycle)),
            bits(&breaks(shuffled, cycle)),
            "{take}"
        );
    }
    // Sorted but starting below 0 or ending beyond Φ: sorted with 0 and Φ all the same.
    let wide = vec![-0.5, 0.3, cycle + 0.1];
    assert_eq!(
        bits(&breaks(wide.clone(), cycle)),
        bits(&breaks(wide.into_iter().rev().collect(), cycle))
    );
}
