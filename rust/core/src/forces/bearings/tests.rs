//! The layout's rules: the lever rule, throws within rounding, the default and refused bearings.

use super::*;

#[test]
fn the_lever_rule_shares_a_throw_between_its_neighbours() {
    // Throws at 0.1 and 0.5 between bearings at 0, 0.4 and 1.0: 3/4 and 1/4, then 5/6
    // and 1/6.
    let given = [0.0, 0.4, 1.0];
    let layout = BearingLayout::new(&[0.1, 0.5, 0.5], Some(&given), 0.05).unwrap();
    assert_eq!(layout.bearings(), 3);
    assert_eq!(layout.throws(), [0.1, 0.5]);
    assert_eq!(layout.throw_of_unit(), [0, 1, 1]);
    let close = |a: f64, b: f64| (a - b).abs() < 1e-15;
    let (a, share_a, b, share_b) = layout.shares[0];
    assert!((a, b) == (0, 1) && close(share_a, 0.75) && close(share_b, 0.25));
    let (a, share_a, b, share_b) = layout.shares[1];
    assert!((a, b) == (1, 2) && close(share_a, 5.0 / 6.0) && close(share_b, 1.0 / 6.0));
}

#[test]
fn units_within_rounding_are_one_throw_and_default_bearings_interleave_them() {
    let layout = BearingLayout::new(&[0.3, 0.1, 0.3 + 1e-15, 0.2], None, 0.05).unwrap();
    assert_eq!(layout.throws(), [0.1, 0.2, 0.3]);
    assert_eq!(layout.throw_of_unit(), [2, 0, 2, 1]);
    let expected = [0.05, 0.15, 0.25, 0.35];
    for (found, want) in layout.bearing_position().iter().zip(expected) {
        assert!((found - want).abs() < 1e-15, "{found} {want}");
    }
    let lone = BearingLayout::new(&[2.0, 2.0], None, 0.1).unwrap();
    assert_eq!(lone.bearing_position(), [1.9, 2.1]);
}

#[test]
fn an_overhung_throw_or_one_at_a_bearing_is_refused_naming_it() {
    let given = [0.0, 0.4, 1.0];
    for (z, words) in [
        (
            -0.1,
            "the throw at z = -0.1 m (cylinders[0]) is overhung, before the first",
        ),
        (
            0.0,
            "main_bearings[0] = 0 m is at the throw at z = 0 m (cylinders[0])",
        ),
        (0.4, "main_bearings[1] = 0.4 m is at the throw"),
        (1.2, "is overhung, beyond the last bearing at 1 m"),
    ] {
        let error = BearingLayout::new(&[z], Some(&given), 0.1).unwrap_err();
        assert_eq!(error.parameter(), Some("main_bearings"));
        assert!(error.to_string().contains(words), "{error}");
    }
    for (given, words) in [
        (&[0.0][..], "at least two"),
        (
            &[1.0, 0.0],
            "main_bearings[1] = 0 m is not beyond main_bearings[0] = 1 m",
        ),
        (&[0.0, f64::NAN], "main_bearings[1] = nan is out of range"),
    ] {
        let error = BearingLayout::new(&[0.5], Some(given), 0.1).unwrap_err();
        assert!(error.to_string().contains(words), "{error}");
    }
    assert!(BearingLayout::new(&[f64::INFINITY], None, 0.1).is_err());
    assert!(BearingLayout::new(&[], None, 0.1).is_err());
}
