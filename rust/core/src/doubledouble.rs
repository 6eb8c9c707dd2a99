//! Just enough double-double arithmetic (an unevaluated sum hi + lo, ~106 bits) for Λ_n.
//!
//! Λ_{2m} ∝ t^{2m−1} multiplies the relative error of t by 2m − 1, so t and its powers
//! are carried in double-double; error-free transformations after Dekker and Knuth,
//! without fused multiply-add so the result is the same on every CPU.

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DoubleDouble {
    pub hi: f64,
    pub lo: f64,
}

/// s + e = a + b exactly.
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// s + e = a + b exactly, given |a| ≥ |b|.
fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// Dekker's split: a = hi + lo with both halves of ≤ 26 significant bits.
fn split(a: f64) -> (f64, f64) {
    let t = 134_217_729.0 * a; // 2^27 + 1
    let hi = t - (t - a);
    (hi, a - hi)
}

/// p + e = a·b exactly.
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
}

impl DoubleDouble {
    pub fn new(x: f64) -> Self {
        Self { hi: x, lo: 0.0 }
    }

    fn normalised(hi: f64, lo: f64) -> Self {
        let (hi, lo) = quick_two_sum(hi, lo);
        Self { hi, lo }
    }

    pub fn product(a: f64, b: f64) -> Self {
        let (hi, lo) = two_prod(a, b);
        Self { hi, lo }
    }

    pub fn add(self, other: Self) -> Self {
        let (s, e) = two_sum(self.hi, other.hi);
        Self::normalised(s, e + self.lo + other.lo)
    }

    pub fn neg(self) -> Self {
        Self {
            hi: -self.hi,
            lo: -self.lo,
        }
    }

    pub fn sub(self, other: Self) -> Self {
        self.add(other.neg())
    }

    pub fn mul(self, other: Self) -> Self {
        let (p, e) = two_prod(self.hi, other.hi);
        Self::normalised(p, e + (self.hi * other.lo + self.lo * other.hi))
    }

    pub fn mul_f64(self, b: f64) -> Self {
        let (p, e) = two_prod(self.hi, b);
        Self::normalised(p, e + self.lo * b)
    }

    pub fn div(self, other: Self) -> Self {
        let q1 = self.hi / other.hi;
        let remainder = self.sub(other.mul_f64(q1));
        let q2 = remainder.hi / other.hi;
        let remainder = remainder.sub(other.mul_f64(q2));
        Self::normalised(q1, q2).add(Self::new(remainder.hi / other.hi))
    }

    pub fn div_f64(self, b: f64) -> Self {
        self.div(Self::new(b))
    }

    /// √x for x ≥ 0: one Newton step from the double square root.
    pub fn sqrt(self) -> Self {
        if self.hi <= 0.0 {
            return Self::new(0.0);
        }
        let s = self.hi.sqrt();
        let residual = self.sub(Self::product(s, s));
        Self::normalised(s, residual.hi / (2.0 * s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn carries_the_low_word() {
        // (1 + 2^-60)·3 keeps the 2^-60 part that a double would lose.
        let x = DoubleDouble::new(1.0).add(DoubleDouble::new(2f64.powi(-60)));
        let y = x.mul_f64(3.0);
        assert_eq!((y.hi, y.lo), (3.0, 3.0 * 2f64.powi(-60)));
        let third = DoubleDouble::new(1.0).div_f64(3.0);
        let back = third.mul_f64(3.0).sub(DoubleDouble::new(1.0));
        assert!(back.hi.abs() < 1e-31);
        let root = DoubleDouble::new(2.0).sqrt();
        let square = root.mul(root).sub(DoubleDouble::new(2.0));
        assert!(square.hi.abs() < 1e-31);
    }
}
