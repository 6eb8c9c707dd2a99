//! The chain's modes against closed forms (two discs, three equal discs, the uniform chain,
//! the symmetric four-disc chain split into its symmetric and antisymmetric halves), and
//! against the eigenproblem itself (K a = ω² J a, J-orthogonal shapes) for random chains —
//! none of them the recurrence that the code bisects.

use super::*;
use crate::test_support::Lcg;

fn modes(inertia: &[f64], stiffness: &[f64], count: usize) -> Modes {
    Chain::new(inertia, stiffness)
        .and_then(|chain| chain.modes(count))
        .expect("a valid chain")
}

fn shape(modes: &Modes, mode: usize) -> Vec<f64> {
    (0..modes.nodes())
        .map(|node| modes.amplitude(node, mode))
        .collect()
}

fn assert_close(found: f64, expected: f64, rel: f64) {
    assert!(
        (found - expected).abs() <= rel * expected.abs(),
        "{found} against {expected} (rel {rel})"
    );
}

#[test]
fn two_discs_swing_at_the_closed_form_frequency_in_inverse_ratio_to_their_inertias() {
    let (j1, j2, k) = (2.0, 0.5, 8.0e4);
    let found = modes(&[j1, j2], &[k], 1);
    assert_eq!((found.count(), found.nodes()), (1, 2));
    assert_close(found.omega()[0], (k * (1.0 / j1 + 1.0 / j2)).sqrt(), 1e-15);
    // zero momentum: J1 a1 + J2 a2 = 0, the larger amplitude +1
    assert_close(found.amplitude(0, 0), -0.25, 1e-15);
    assert_eq!(found.amplitude(1, 0), 1.0);
}

#[test]
fn three_equal_discs_have_omega_squared_k_over_j_and_three_k_over_j() {
    let (j, k) = (1.5, 3.0e5);
    let found = modes(&[j; 3], &[k; 2], 2);
    assert_close(found.omega()[0], (k / j).sqrt(), 1e-15);
    assert_close(found.omega()[1], (3.0 * k / j).sqrt(), 1e-15);
    // the ends against each other, the middle still: (1, 0, −1)
    let first = shape(&found, 0);
    assert_close(first[0], 1.0, 1e-15);
    assert_close(first[2], -1.0, 1e-15);
    assert!(first[1].abs() < 1e-15);
    // the middle against both ends: (1, −2, 1), the largest +1
    let second = shape(&found, 1);
    assert_eq!(second[1], 1.0);
    assert_close(second[0], -0.5, 1e-15);
    assert_close(second[2], -0.5, 1e-15);
}

#[test]
fn a_symmetric_four_disc_chain_keeps_the_digits_of_its_soft_mode() {
    // Two heavy discs through two light ones, a soft section between stiff ones: the
    // antisymmetric half is the two-disc problem J0 J1 λ² − (J0 (k1 + 2k2) + J1 k1) λ +
    // 2 k1 k2 = 0 (the middle section, twisted by 2θ1, holds node 1 to the ground by 2k2),
    // the symmetric half the free pair, λ = k1 (1/J0 + 1/J1).
    let (j0, j1, k1, k2) = (1e4, 1e-4, 1e9, 1e3);
    let found = modes(&[j0, j1, j1, j0], &[k1, k2, k1], 3);
    let (a, b, c) = (j0 * j1, j0 * (k1 + 2.0 * k2) + j1 * k1, 2.0 * k1 * k2);
    let root = (b * b - 4.0 * a * c).sqrt();
    let antisymmetric = [2.0 * c / (b + root), (b + root) / (2.0 * a)];
    let symmetric = k1 * (1.0 / j0 + 1.0 / j1);
    let mut expected = [antisymmetric[0], antisymmetric[1], symmetric];
    expected.sort_by(f64::total_cmp);
    for (found, expected) in found.omega().iter().zip(expected) {
        assert_close(*found, expected.sqrt(), 2e-15);
    }
    // 0.0711761828096906… Hz (mpmath, 40 digits)
    assert_close(
        found.omega()[0] / (2.0 * std::f64::consts::PI),
        0.071_176_182_809_690_6,
        1e-14,
    );
    // the first mode: the heavy discs against each other, each light one following its
    // neighbour to 2e-6, a_1/a_0 = k1/(k1 + 2k2 − λ J1) from node 1's equation
    let first = shape(&found, 0);
    assert_close(first[0], 1.0, 1e-15);
    let ratio = k1 / (k1 + 2.0 * k2 - antisymmetric[0] * j1);
    assert_close(first[1], ratio, 1e-15);
    assert_close(first[2], -ratio, 1e-15);
    assert_close(first[3], -1.0, 1e-15);
}

#[test]
fn a_long_uniform_chain_has_the_closed_form_modes() {
    // n equal discs on n − 1 equal sections: ω_m = 2 √(k/J) sin(mπ/2n), a_j ∝ cos(mπ(j + ½)/n).
    let (n, j, k) = (300, 0.02, 3e5);
    let found = modes(&vec![j; n], &vec![k; n - 1], n - 1);
    let pi = std::f64::consts::PI;
    for (index, &omega) in found.omega().iter().enumerate() {
        let m = (index + 1) as f64;
        assert_close(
            omega,
            2.0 * (k / j).sqrt() * (m * pi / (2.0 * n as f64)).sin(),
            1e-13,
        );
    }
    for mode in [0, 1, 2, 150, n - 2] {
        let m = (mode + 1) as f64;
        let exact: Vec<f64> = (0..n)
            .map(|node| (m * pi * (node as f64 + 0.5) / n as f64).cos())
            .collect();
        let size = exact.iter().fold(0.0f64, |s, a| s.max(a.abs()));
        let first = exact
            .iter()
            .position(|a| a.abs() >= size * (1.0 - 1e-9))
            .expect("a largest node");
        let scale = size * exact[first].signum();
        for (found, exact) in shape(&found, mode).iter().zip(&exact) {
            assert!((found - exact / scale).abs() < 1e-10, "mode {mode}");
        }
    }
}

/// A chain whose inertias span `decades` decades and stiffnesses as many more.
fn random_chain(random: &mut Lcg, nodes: usize, decades: f64) -> (Vec<f64>, Vec<f64>) {
    let inertia = (0..nodes)
        .map(|_| 10f64.powf(decades * (random.next() - 0.5)))
        .collect();
    let stiffness = (0..nodes - 1)
        .map(|_| 10f64.powf(4.0 + decades * random.next()))
        .collect();
    (inertia, stiffness)
}

#[test]
fn random_chains_solve_their_eigenproblem_with_j_orthogonal_shapes() {
    let mut random = Lcg(37);
    for trial in 0..200 {
        let nodes = 2 + trial % 19;
        let (inertia, stiffness) = random_chain(&mut random, nodes, 1.0);
        let found = modes(&inertia, &stiffness, nodes - 1);
        let omega = found.omega();
        assert!(omega.windows(2).all(|w| w[0] <= w[1]), "increasing");
        let shapes: Vec<Vec<f64>> = (0..nodes - 1).map(|m| shape(&found, m)).collect();
        for (m, a) in shapes.iter().enumerate() {
            // largest magnitude 1, positive at the first node within 1e-9 of it
            let size = a.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            assert_eq!(size, 1.0);
            let first = a.iter().position(|v| v.abs() >= 1.0 - 1e-9);
            assert!(a[first.expect("a largest node")] > 0.0);
            // K a = ω² J a, node by node, to ε of the node's largest term
            let lambda = omega[m] * omega[m];
            for i in 0..nodes {
                let mut force = 0.0;
                let mut size = lambda * inertia[i] * a[i].abs();
                if i > 0 {
                    force += stiffness[i - 1] * (a[i] - a[i - 1]);
                    size += stiffness[i - 1] * (a[i].abs() + a[i - 1].abs());
                }
                if i + 1 < nodes {
                    force += stiffness[i] * (a[i] - a[i + 1]);
                    size += stiffness[i] * (a[i].abs() + a[i + 1].abs());
                }
                let residual = force - lambda * inertia[i] * a[i];
                assert!(
                    residual.abs() <= 1e-12 * size,
                    "trial {trial} mode {m} node {i}"
                );
            }
            // J-orthogonal to the rigid mode (no net momentum) and to every other mode
            let total: f64 = inertia.iter().sum();
            let momentum: f64 = inertia.iter().zip(a).map(|(j, a)| j * a).sum();
            assert!(momentum.abs() < 1e-10 * total, "trial {trial} mode {m}");
            for b in &shapes[..m] {
                let product: f64 = (0..nodes).map(|i| inertia[i] * a[i] * b[i]).sum();
                let size: f64 = (0..nodes).map(|i| inertia[i] * (a[i] * b[i]).abs()).sum();
                assert!(product.abs() < 1e-8 * size.max(1e-300), "trial {trial}");
            }
        }
    }
}

#[test]
fn a_mode_does_not_depend_on_how_many_are_asked() {
    let mut random = Lcg(5);
    for nodes in [3, 9, 17, 40] {
        let (inertia, stiffness) = random_chain(&mut random, nodes, 8.0);
        let all = modes(&inertia, &stiffness, nodes - 1);
        for count in [1, 2, nodes / 2, nodes - 1] {
            let some = modes(&inertia, &stiffness, count.max(1));
            assert_eq!(some.omega(), &all.omega()[..some.count()]);
            for m in 0..some.count() {
                assert_eq!(shape(&some, m), shape(&all, m));
            }
        }
    }
}

#[test]
fn bad_chains_and_counts_are_refused_by_name() {
    let refused = |inertia: &[f64], stiffness: &[f64]| {
        Chain::new(inertia, stiffness)
            .expect_err("refused")
            .parameter()
    };
    assert_eq!(refused(&[1.0], &[]), Some("inertia"));
    assert_eq!(refused(&[], &[]), Some("inertia"));
    assert_eq!(refused(&[1.0, 0.0], &[1.0]), Some("inertia"));
    assert_eq!(refused(&[1.0, f64::NAN], &[1.0]), Some("inertia"));
    assert_eq!(refused(&[1.0, f64::INFINITY], &[1.0]), Some("inertia"));
    assert_eq!(refused(&[1.0, 1.0], &[1.0, 2.0]), Some("stiffness"));
    assert_eq!(refused(&[1.0, 1.0], &[]), Some("stiffness"));
    assert_eq!(refused(&[1.0, 1.0], &[-1.0]), Some("stiffness"));
    assert_eq!(refused(&[1.0, 1.0], &[f64::NAN]), Some("stiffness"));
    let chain = Chain::new(&[1.0, 2.0, 3.0], &[1e4, 2e4]).expect("a valid chain");
    assert_eq!(chain.nodes(), 3);
    assert_eq!(chain.inertia(), &[1.0, 2.0, 3.0]);
    assert_eq!(chain.stiffness(), &[1e4, 2e4]);
    for count in [0, 3, usize::MAX] {
        let error = chain.modes(count).expect_err("refused");
        assert_eq!(error.parameter(), Some("count"));
    }
    assert_eq!(chain.modes(2).expect("in range").count(), 2);
}
