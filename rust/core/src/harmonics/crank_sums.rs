//! The crank phase sums S_n = Σ_j e^{i n α_j}, and which harmonics survive them for
//! a regular crank set (§5's rule, in exact integers).

use super::{gcd, MAX_HARMONIC};
use crate::error::{try_filled, try_with_capacity, MechanismError, Result};
use crate::mechanism::{Acting, Strokes};

/// The crank-set constants of §5's rule: α = 2π·p/q with p = 1 (two-stroke) or 2
/// (four-stroke) and q = a·k, a = 1 (single acting) or 2 (double acting). In u128, so that
/// no product of user integers below can overflow.
fn crank_set(cranks: u64, strokes: Strokes, acting: Acting) -> (u128, u128, u128) {
    let p = match strokes {
        Strokes::Two => 1,
        Strokes::Four => 2,
    };
    let a = match acting {
        Acting::Single => 1,
        Acting::Double => 2,
    };
    (p, a, a * cranks as u128)
}

/// Whether harmonic n of Q_u* survives the sum over the regular crank set of §2 (false for
/// zero cranks).
///
/// With α = 2π·p/q (p = 1 two-stroke, 2 four-stroke; q = a·k, a = 1 single-, 2
/// double-acting), the phase sum S_n = Σ_{j<k} e^{2πi·n·j·p/q} is k when q | n·p, and
/// otherwise the geometric sum (1 − e^{2πi·n·k·p/q})/(1 − e^{2πi·n·p/q}), zero exactly when
/// q | n·p·k — that is, since n·p·k mod a·k = k·(n·p mod a), when a | n·p. Only n = 1 (the
/// N and W1 terms) and even n (the W_n terms) carry coefficients at all. Exact for every
/// n and k: n·p < 2^65 and q < 2^65 are formed in u128.
pub fn harmonic_survives(n: u64, cranks: u64, strokes: Strokes, acting: Acting) -> bool {
    if cranks == 0 || n == 0 || (n > 1 && n % 2 == 1) {
        return false;
    }
    let (p, a, q) = crank_set(cranks, strokes, acting);
    let np = n as u128 * p;
    np % q == 0 || np % a != 0
}

/// The n ≤ n_max that survive the crank sum of a regular machine, ascending; an error
/// naming `cranks` for zero cranks, and one naming `n_max` when the list would not fit
/// in memory.
///
/// Every even survivor is a multiple of lcm(2, q/gcd(q, p)) (for even n the rule is
/// q | n·p, as a | n·p always holds), so the list is made in O(its length), whatever
/// n_max and k.
pub fn surviving_harmonics(
    cranks: u64,
    strokes: Strokes,
    acting: Acting,
    n_max: u64,
) -> Result<Vec<u64>> {
    if cranks == 0 {
        return Err(MechanismError::InvalidChoice {
            parameter: "cranks",
            value: cranks.to_string(),
            allowed: "an integer >= 1",
        });
    }
    let (p, _, q) = crank_set(cranks, strokes, acting);
    let period = q / gcd(q, p);
    let step = if period % 2 == 0 { period } else { 2 * period };
    let first = n_max >= 1 && harmonic_survives(1, cranks, strokes, acting);
    let evens = n_max as u128 / step;
    let mut out = try_with_capacity("n_max", n_max, evens + first as u128)?;
    if first {
        out.push(1);
    }
    // n = ν·step ≤ n_max < 2^64 for every ν ≤ evens.
    out.extend((1..=evens).map(|nu| (nu * step) as u64));
    Ok(out)
}

/// The phase sums C_n = Σ_j cos nα_j and S_n = Σ_j sin nα_j for n = 0 … n_max.
///
/// A sum whose modulus is below its own rounding noise (8ε·k·(1 + n·max|α_j|)) is set to
/// exactly zero: for a regular crank set it is zero, and the harmonic has cancelled. One
/// unit's sum is e^{inα_j} itself, the building block of an engine of any layout.
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseSums {
    pub cos: Vec<f64>,
    pub sin: Vec<f64>,
    pub cranks: usize,
    /// max |α_j|: the rounding of n·α_j grows with it.
    reach: f64,
}

impl PhaseSums {
    /// The sums for n = 0 … n_max; an error naming n_max when they would not fit in memory.
    pub fn new(phases: &[f64], n_max: usize) -> Result<Self> {
        let len = n_max as u128 + 1;
        let cos = try_filled("n_max", n_max, len, 0.0)?;
        let sin = try_filled("n_max", n_max, len, 0.0)?;
        Ok(Self::filled(phases, cos, sin))
    }

    /// The sums through a series' harmonic reach (at most MAX_HARMONIC: a few kilobytes,
    /// never a size a user chose).
    pub(crate) fn within_reach(phases: &[f64], reach: usize) -> Self {
        let len = reach.min(MAX_HARMONIC) + 1;
        Self::filled(phases, vec![0.0; len], vec![0.0; len])
    }

    fn filled(phases: &[f64], mut cos: Vec<f64>, mut sin: Vec<f64>) -> Self {
        let reach = phases.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
        for n in 0..cos.len() {
            let (mut c, mut s) = (0.0, 0.0);
            for &alpha in phases {
                let (sa, ca) = (n as f64 * alpha).sin_cos();
                c += ca;
                s += sa;
            }
            if c.hypot(s) > 8.0 * f64::EPSILON * noise(phases.len(), reach, n) {
                cos[n] = c;
                sin[n] = s;
            }
        }
        Self {
            cos,
            sin,
            cranks: phases.len(),
            reach,
        }
    }

    pub fn n_max(&self) -> usize {
        self.cos.len() - 1
    }

    /// The size of the rounding of S_n in units of 8ε: a sum below it has cancelled.
    pub(crate) fn noise(&self, n: usize) -> f64 {
        noise(self.cranks, self.reach, n)
    }
}

/// k·(1 + n·max|α_j|): the rounding of Σ_j e^{inα_j} in units of 8ε.
fn noise(cranks: usize, reach: f64, n: usize) -> f64 {
    cranks as f64 * (1.0 + n as f64 * reach)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule of §5 evaluated the slow, obvious way in exact integers: q | n·p, or the
    /// geometric sum's numerator is non-zero (q ∤ n·p·k), with n·p·k formed in u128 — valid
    /// while that product fits, which the values below keep.
    fn survives_by_definition(n: u64, k: u64, strokes: Strokes, acting: Acting) -> bool {
        let p: u128 = if strokes == Strokes::Two { 1 } else { 2 };
        let q: u128 = if acting == Acting::Single { 1 } else { 2 } * k as u128;
        let carried = n == 1 || n % 2 == 0;
        let np = n as u128 * p;
        carried && (np % q == 0 || (np * k as u128) % q != 0)
    }

    #[test]
    fn survival_is_exact_for_huge_counts() {
        // Products n·p·k far beyond u64 (the old rule wrapped and answered at random).
        let big = [
            1u64,
            2,
            3,
            7,
            1 << 31,
            (1 << 32) + 1,
            10u64.pow(12),
            10u64.pow(18),
            u64::MAX / 3,
            u64::MAX,
        ];
        for strokes in [Strokes::Two, Strokes::Four] {
            for acting in [Acting::Single, Acting::Double] {
                for &k in &big {
                    for &n in big
                        .iter()
                        .chain(&[4, 6, 24, 2 * (1 << 31), 2 * 10u64.pow(18)])
                    {
                        if (n as u128) * (k as u128) < (1u128 << 126) {
                            assert_eq!(
                                harmonic_survives(n, k, strokes, acting),
                                survives_by_definition(n, k, strokes, acting),
                                "n={n} k={k} {strokes:?} {acting:?}"
                            );
                        }
                    }
                }
            }
        }
        // The example: k = 10^18 has no harmonic ≤ 24 (it returned [20, 22, 24]).
        let none = surviving_harmonics(10u64.pow(18), Strokes::Two, Acting::Single, 24);
        assert_eq!(none, Ok(vec![]));
        assert!(!harmonic_survives(5, 0, Strokes::Two, Acting::Single));
        assert!(surviving_harmonics(0, Strokes::Two, Acting::Single, 24).is_err());
    }

    #[test]
    fn surviving_list_is_the_rule_and_costs_its_length() {
        for k in 1..=30u64 {
            for strokes in [Strokes::Two, Strokes::Four] {
                for acting in [Acting::Single, Acting::Double] {
                    for n_max in [0u64, 1, 2, 23, 24, 25, 200] {
                        let slow: Vec<u64> = (1..=n_max)
                            .filter(|&n| harmonic_survives(n, k, strokes, acting))
                            .collect();
                        assert_eq!(
                            surviving_harmonics(k, strokes, acting, n_max),
                            Ok(slow),
                            "k={k} n_max={n_max}"
                        );
                    }
                }
            }
        }
        // n_max = u64::MAX with a huge k answers at once (a loop over n would never end).
        let few = surviving_harmonics(u64::MAX / 2, Strokes::Two, Acting::Single, u64::MAX);
        assert_eq!(few, Ok(vec![u64::MAX - 1]));
        let double = surviving_harmonics(u64::MAX, Strokes::Two, Acting::Double, u64::MAX);
        assert_eq!(double, Ok(vec![1]));
        // ... and a list that cannot be held is refused, naming n_max.
        let error = surviving_harmonics(1, Strokes::Two, Acting::Single, u64::MAX).unwrap_err();
        assert!(
            matches!(
                error,
                MechanismError::TooLarge {
                    parameter: "n_max",
                    ..
                }
            ),
            "{error}"
        );
    }

    #[test]
    fn paper_table_1() {
        // W_1: k=1; W_2: 1,2; W_4: 1,2,4; W_6: 1,2,3,6; W_8: 1,2,4,8; W_10: 1,2,5,10;
        // W_12: 1,2,3,4,6,12 (two-stroke, single acting).
        let printed: [(u64, &[u64]); 7] = [
            (1, &[1]),
            (2, &[1, 2]),
            (4, &[1, 2, 4]),
            (6, &[1, 2, 3, 6]),
            (8, &[1, 2, 4, 8]),
            (10, &[1, 2, 5, 10]),
            (12, &[1, 2, 3, 4, 6, 12]),
        ];
        for (n, ks) in printed {
            let found: Vec<u64> = (1..=12)
                .filter(|&k| harmonic_survives(n, k, Strokes::Two, Acting::Single))
                .collect();
            assert_eq!(found, ks, "W_{n}");
        }
    }
}
