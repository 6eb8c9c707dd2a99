//! The coefficients Λ_n of f(ψ) = (λ/2) sin 2ψ / √(1 − λ² sin² ψ) = Σ_{n even} Λ_n sin nψ:
//! exact (₂F₁ in double-double, bounded work for every λ < 1) and as the paper's
//! λ-series (`paper_coefficient`, `lambda_paper`); how far a series must reach.

use super::MAX_HARMONIC;
use crate::doubledouble::DoubleDouble;
use crate::error::{check, try_filled, MechanismError, Result};
use crate::parallel::{for_each_row, Parallelism};

/// t = λ / (1 + √(1 − λ²)) in double-double.
fn t_of(crank_ratio: f64) -> DoubleDouble {
    let one_minus = DoubleDouble::new(1.0).sub(DoubleDouble::product(crank_ratio, crank_ratio));
    let denominator = one_minus.sqrt().add(DoubleDouble::new(1.0));
    DoubleDouble::new(crank_ratio).div(denominator)
}

/// Λ_2, Λ_4, Λ_6, … of the exact closed form, one per `next()`:
///
/// Λ_{2m} = 2m·C(½, m)·t^{2m−1}·Σ_{b≥0} [C(½, b)·C(½, b+m)/C(½, m)]·t^{4b}
///        = 2m·C(½, m)·t^{2m−1}·F_m,   F_m = ₂F₁(−½, m − ½; m + 1; z),  z = t⁴.
///
/// t^{2m−1} and 2m·C(½, m) are carried in double-double, so the relative error stays at a
/// few ulps for every m. F_m lies in [√(1 − z), 1] and is found with bounded work for
/// every z ∈ [0, 1) — λ → 1 (z → 1) included, where its power series needs ~40/(1 − z)
/// terms (10⁹ at λ = 1 − 2⁻⁵³, which once took 40 s for a series):
///
/// - z ≤ ½: the power series in z (its term ratios are below z: ≤ 56 terms);
/// - z > ½ and m·w ≤ 2 (w = 1 − z): the expansion about z = 1 for c − a − b = 2
///   (Abramowitz & Stegun 15.3.11), a series in w with logarithmic terms whose ratios
///   are ≤ ~m·w/2 (≤ ~46 terms);
/// - z > ½ and m·w > 2: Miller's backward recurrence on the three-term recurrence
///   z(m + 3/2)(m − ½)·F_{m+1} = m(m + 1)·[(1 + z)·F_m − F_{m−1}] (F_m, tending to √w, is
///   its minimal solution going up, the other grows like z^{−m}), in double-double,
///   normalised by the F_{m−1} before the block: about 40/w + (block length) steps per
///   block of up to thousands of harmonics, O(1) per harmonic.
///
/// `work()` counts the terms and recurrence steps, so that tests can bound it.
#[derive(Debug, Clone)]
pub struct ExactLambdas {
    t: DoubleDouble,
    t2: DoubleDouble,
    /// z = t⁴ and w = 1 − z, both from t in double-double.
    z: DoubleDouble,
    w: f64,
    m: u64,
    /// t^{2m−1}
    power: DoubleDouble,
    /// C(½, m)
    binomial: DoubleDouble,
    /// m!/Γ(m + 3/2) and ψ(m + 3/2) − ψ(3/2) = Σ_{k≤m} 2/(2k + 1): the expansion about z = 1.
    gamma_ratio: DoubleDouble,
    digamma: DoubleDouble,
    /// F_{m−1}: where a Miller block is normalised.
    previous: f64,
    /// F_m for m = block_start … block_start + block.len() − 1 (Miller).
    block: Vec<f64>,
    block_start: u64,
    /// The harmonic index up to which a Miller block is made at once (more when asked).
    reach: u64,
    /// Tabulated power-series terms that reach 2^-58 at this z (0: z too large for them).
    tabulated: usize,
    work: u64,
}

/// Harmonics m ≤ TABLE_M take 2m·C(½, m) and the power-series coefficients of F_m from
/// tables made once per process (a sweep builds millions of series: the recurrences'
/// divisions were most of their cost).
const TABLE_M: usize = 256;
/// Power-series terms tabulated per m: enough for z ≤ 0.28 (λ ≤ 0.93).
const TABLE_B: usize = 32;

struct Tables {
    /// 2m·C(½, m), m = 0 … TABLE_M, from the same double-double recurrence as beyond.
    binomial: Vec<DoubleDouble>,
    /// C(½, TABLE_M), where the recurrence goes on.
    last_binomial: DoubleDouble,
    /// c_b(m) = Π_{i≤b} ((3/2 − i)(3/2 − i − m))/(i(i + m)), b < TABLE_B, m = 0 … TABLE_M:
    /// F_m = Σ_b c_b(m)·z^b, |c_b| ≤ 1.
    series: Vec<[f64; TABLE_B]>,
}

fn tables() -> &'static Tables {
    static TABLES: std::sync::OnceLock<Tables> = std::sync::OnceLock::new();
    TABLES.get_or_init(|| {
        let mut binomial = vec![DoubleDouble::new(0.0); TABLE_M + 1];
        let mut c = DoubleDouble::new(1.0);
        for (m, entry) in binomial.iter_mut().enumerate().skip(1) {
            c = next_binomial(c, m as f64);
            *entry = c.mul_f64(2.0 * m as f64);
        }
        let series = (0..=TABLE_M)
            .map(|m| {
                let mut row = [0.0; TABLE_B];
                row[0] = 1.0;
                for b in 1..TABLE_B {
                    let (bf, mf) = (b as f64, m as f64);
                    row[b] = row[b - 1] * ((1.5 - bf) * (1.5 - bf - mf)) / (bf * (bf + mf));
                }
                row
            })
            .collect();
        Tables {
            binomial,
            last_binomial: c,
            series,
        }
    })
}

/// C(½, m) from C(½, m − 1): ·(½ − (m − 1))/m = ·(3 − 2m)/(2m) (C(½, 1) = ½ from 1).
fn next_binomial(previous: DoubleDouble, m: f64) -> DoubleDouble {
    if m == 1.0 {
        DoubleDouble::new(0.5)
    } else {
        previous.mul_f64(3.0 - 2.0 * m).div_f64(2.0 * m)
    }
}

/// 2/√π as a double-double: 1/Γ(3/2).
const TWO_OVER_ROOT_PI: DoubleDouble = DoubleDouble {
    hi: std::f64::consts::FRAC_2_SQRT_PI,
    lo: 1.533_545_961_316_588e-17,
};

impl ExactLambdas {
    pub fn new(crank_ratio: f64) -> Self {
        Self::with_reach(crank_ratio, MAX_HARMONIC)
    }

    /// Λ_2 … as `new`, for a consumer that will ask for harmonics up to n = `reach`
    /// (the length of a Miller block; asking for more still works).
    pub fn with_reach(crank_ratio: f64, reach: usize) -> Self {
        let t = t_of(crank_ratio);
        let t2 = t.mul(t);
        let z = t2.mul(t2);
        // w = 1 − t⁴ = (1 − t²)(1 + t²), with 1 − t² from the double-double t².
        let w = DoubleDouble::new(1.0)
            .sub(t2)
            .mul(DoubleDouble::new(1.0).add(t2))
            .hi;
        Self {
            t,
            t2,
            z,
            w,
            m: 0,
            power: DoubleDouble::new(1.0),
            binomial: DoubleDouble::new(1.0),
            gamma_ratio: TWO_OVER_ROOT_PI,
            digamma: DoubleDouble::new(0.0),
            previous: 1.0,
            block: Vec::new(),
            block_start: 0,
            reach: (reach / 2).max(1) as u64,
            tabulated: Self::tabulated_terms(z.hi),
            work: 0,
        }
    }

    /// N with z^N ≤ 2^-58 (the rest of the series, ≤ z^N/(1 − z) with |c_b| ≤ 1, is then
    /// below half an ulp of F ≥ √(1 − z)), if N ≤ TABLE_B; else 0.
    fn tabulated_terms(z: f64) -> usize {
        if z == 0.0 {
            return 1;
        }
        let terms = (-58.0 * std::f64::consts::LN_2 / z.ln()).ceil();
        if terms.is_finite() && terms >= 1.0 && terms <= TABLE_B as f64 {
            terms as usize
        } else {
            0
        }
    }

    /// Moves to the next harmonic without computing it (its Λ is not needed: the crank sum
    /// cancels it); only where F_m comes from the power series, which needs no F_{m−1}.
    pub(crate) fn skip(&mut self) {
        if self.z.hi > 0.5 {
            self.next();
        } else {
            self.advance();
        }
    }

    /// m, t^{2m−1} and C(½, m) (and the expansion about z = 1's running values) to the
    /// next harmonic.
    fn advance(&mut self) {
        self.m += 1;
        let m = self.m as f64;
        self.power = if self.m == 1 {
            self.t
        } else {
            self.power.mul(self.t2)
        };
        if self.m as usize == TABLE_M + 1 {
            self.binomial = next_binomial(tables().last_binomial, m);
        } else if self.m as usize > TABLE_M {
            self.binomial = next_binomial(self.binomial, m);
        }
        if self.z.hi > 0.5 && m * self.w <= 2.0 {
            // R_m = R_{m−1}·m/(m + ½); Σ_{k≤m} 2/(2k + 1): only for the expansion about
            // z = 1, which is not used again once m·w > 2.
            self.gamma_ratio = self.gamma_ratio.mul_f64(m).div_f64(m + 0.5);
            self.digamma = self
                .digamma
                .add(DoubleDouble::new(2.0).div_f64(2.0 * m + 1.0));
        }
    }

    /// t = λ/(1 + √(1 − λ²)) rounded to double: |Λ_{2m}| ≤ t^{2m−1}/(1 − t⁴).
    pub fn t(&self) -> f64 {
        self.t.hi
    }

    /// The terms and recurrence steps spent so far (a bound on the work, for tests).
    #[cfg(test)]
    pub(crate) fn work(&self) -> u64 {
        self.work
    }

    /// F_m for the current m by the power series in z (z ≤ ½, or m = 1).
    fn power_series(&mut self) -> f64 {
        if self.tabulated > 0 && self.m as usize <= TABLE_M {
            self.work += self.tabulated as u64;
            let row = &tables().series[self.m as usize][..self.tabulated];
            return row.iter().rev().fold(0.0, |sum, &c| sum * self.z.hi + c);
        }
        self.summed_power_series()
    }

    /// F_m by summing the power series term by term (z too large, or m, for the tables).
    fn summed_power_series(&mut self) -> f64 {
        // Term ratios c_b/c_{b−1} = ((3/2 − b)/b)·((3/2 − b − m)/(b + m))·z, below z in size.
        // Summed with Neumaier's compensation; once the geometric estimate of the rest,
        // term·r/(1 − r) with r the last ratio, is below 1e-17 of the sum, it is added and
        // the loop ends.
        let (m, z) = (self.m as f64, self.z.hi);
        let (mut term, mut sum, mut compensation) = (1.0_f64, 1.0_f64, 0.0_f64);
        let mut b = 1.0;
        while b < 10_000.0 {
            self.work += 1;
            let ratio = ((1.5 - b) * (1.5 - b - m)) / (b * (b + m)) * z;
            term *= ratio;
            let next = sum + term;
            compensation += if sum.abs() >= term.abs() {
                (sum - next) + term
            } else {
                (term - next) + sum
            };
            sum = next;
            let rest = term * ratio / (1.0 - ratio);
            if rest.abs() <= 1e-17 * sum.abs() {
                compensation += rest;
                break;
            }
            b += 1.0;
        }
        sum + compensation
    }

    /// F_m by the expansion about z = 1 (A&S 15.3.11 with a = −½, b = m − ½, c − a − b = 2):
    ///
    /// F_m = (R/√π)·[2 + (m − ½)·w + (w²/2)(m + ½)(m − ½)·Σ_n T_n·L_n],
    /// R = m!/Γ(m + 3/2), T_n = (3/2)_n (m + 3/2)_n w^n/(n! (n + 2)!),
    /// L_n = ln w − ψ(n + 1) − ψ(n + 3) + ψ(n + 3/2) + ψ(m + n + 3/2),
    ///
    /// where L_0 = ln w + 5/2 − 4 ln 2 + Σ_{k≤m} 2/(2k + 1) and each L_{n+1} follows by
    /// ψ(x + 1) = ψ(x) + 1/x. For m·w ≤ 2 the terms fall from the start: ≤ ~46 of them.
    fn about_one(&mut self) -> f64 {
        let (m, w) = (self.m as f64, self.w);
        let mut log = w.ln() + 2.5 - 4.0 * std::f64::consts::LN_2 + self.digamma.hi;
        let (mut term, mut sum) = (0.5, 0.0_f64);
        let mut n = 0.0;
        while n < 400.0 {
            self.work += 1;
            sum += term * log;
            n += 1.0;
            term *= (0.5 + n) * (m + 0.5 + n) / (n * (n + 2.0)) * w;
            log += -1.0 / n - 1.0 / (n + 2.0) + 1.0 / (n + 0.5) + 1.0 / (m + n + 0.5);
            if n > 2.0 && (term * log).abs() <= 1e-18 * sum.abs() {
                break;
            }
        }
        let bracket = 2.0 + (m - 0.5) * w + 0.5 * w * w * (m + 0.5) * (m - 0.5) * sum;
        // R/√π·bracket = R·(2/√π)·(bracket/2)
        self.gamma_ratio
            .mul(TWO_OVER_ROOT_PI)
            .mul_f64(0.5 * bracket)
            .hi
    }

    /// F_m from a Miller block, made when m leaves the last one.
    fn miller(&mut self) -> f64 {
        let index = self.m - self.block_start;
        if self.block_start == 0 || index >= self.block.len() as u64 {
            self.make_block();
        }
        self.block[(self.m - self.block_start) as usize]
    }

    /// F_m … F_{m+B−1} by the backward recurrence, started K steps above the block with
    /// F̃ = 1, 1 (the unwanted solution falls by z per step going down: K = ln(2^-60)/ln z),
    /// in double-double, and scaled so that the value at m − 1 is the F_{m−1} found before.
    /// B covers the harmonics the consumer said it would ask for, at least K (so a block
    /// costs at most twice its length) and at most 2^20 (8 MB).
    fn make_block(&mut self) {
        let z = self.z;
        let steps = ((-60.0 * std::f64::consts::LN_2) / z.hi.ln()).ceil() as u64 + 8;
        let wanted = self.reach.saturating_sub(self.m) + 1;
        let length = wanted.max(steps).clamp(64, 1 << 20);
        let top = self.m + length - 1 + steps;
        let one_plus_z = DoubleDouble::new(1.0).add(z);
        let (mut above, mut here) = (DoubleDouble::new(1.0), DoubleDouble::new(1.0));
        self.block.clear();
        self.block.resize(length as usize, 0.0);
        // here = F̃_k, above = F̃_{k+1}; F̃_{k−1} = (1 + z)F̃_k − z(k + 3/2)(k − ½)/(k(k + 1))·F̃_{k+1}.
        let mut k = top;
        while k >= self.m {
            self.work += 1;
            if k < self.m + length {
                self.block[(k - self.m) as usize] = here.hi;
            }
            // (k + 3/2)(k − ½)/(k(k + 1)) = 1 − ¾/(k(k + 1)): the small part in double
            // (its rounding, ε·¾/k², sums to ~ε/m over the whole recurrence).
            let kf = k as f64;
            let coefficient =
                DoubleDouble::new(1.0).sub(DoubleDouble::new(0.75 / (kf * (kf + 1.0))));
            let below = one_plus_z.mul(here).sub(z.mul(coefficient).mul(above));
            (above, here) = (here, below);
            // Keep the values near 1 (the wanted solution tends to a constant, but a start
            // far from it could drift in scale over many steps).
            if here.hi.abs() > 1e100 || here.hi.abs() < 1e-100 {
                let rescale = 1.0 / here.hi;
                (above, here) = (above.mul_f64(rescale), here.mul_f64(rescale));
                for f in &mut self.block {
                    *f *= rescale;
                }
            }
            k -= 1;
        }
        // here = F̃_{m−1}
        let scale = self.previous / here.hi;
        for f in &mut self.block {
            *f *= scale;
        }
        self.block_start = self.m;
    }
}

impl Iterator for ExactLambdas {
    type Item = f64;

    fn next(&mut self) -> Option<f64> {
        self.advance();
        let m = self.m as f64;
        let near_one = self.z.hi > 0.5;
        if self.power.hi == 0.0 {
            // t^{2m−1} underflowed: so has every later Λ (the F_m are ≤ 1).
            self.previous = 0.0;
            return Some(0.0);
        }
        let hypergeometric = if !near_one {
            self.power_series()
        } else if m * self.w <= 2.0 {
            self.about_one()
        } else {
            self.miller()
        };
        self.previous = hypergeometric;
        // Each regime is bounded (see the type's docs): ≤ 400 terms per harmonic, and a
        // Miller block (≤ 2^20 long) costs its length plus a warm-up of ~41.6/w < 21·m
        // steps (m·w > 2 there).
        debug_assert!(
            self.work <= 400 * self.m + (self.m / (1 << 20) + 1) * ((1 << 20) + 21 * self.m + 8)
        );
        let coefficient = if self.m as usize <= TABLE_M {
            tables().binomial[self.m as usize]
        } else {
            self.binomial.mul_f64(2.0 * m)
        };
        let value = coefficient.mul(self.power);
        Some(value.hi * hypergeometric + value.lo * hypergeometric)
    }
}

/// Λ_0 … Λ_{n_max} of the exact form into `out` (length n_max + 1; odd entries and Λ_0 are 0).
pub fn lambda_exact(crank_ratio: f64, out: &mut [f64]) {
    out.fill(0.0);
    let mut lambdas = ExactLambdas::with_reach(crank_ratio, out.len().saturating_sub(1));
    for n in (2..out.len()).step_by(2) {
        let value = lambdas.next().unwrap_or(0.0);
        if value == 0.0 && lambdas.power.hi == 0.0 {
            break; // t^{2m−1} underflowed: every later Λ is 0, as `out` already holds
        }
        out[n] = value;
    }
}

/// n_max + 1 entries (Λ_0 … Λ_{n_max}, a_0 … a_{n_max}), or `TooLarge` naming n_max
/// (n_max + 1 itself overflows only where no such table could be allocated anyway).
pub(crate) fn harmonic_width(n_max: usize) -> Result<usize> {
    n_max.checked_add(1).ok_or(MechanismError::TooLarge {
        parameter: "n_max",
        value: n_max.to_string(),
        elements: n_max as u128 + 1,
        item_bytes: std::mem::size_of::<f64>(),
    })
}

/// Λ_0 … Λ_{n_max} for every crank ratio, row by row (`crank_ratios.len()` rows of
/// n_max + 1), exact or as the paper's λ-series; in parallel for many rows. The table is
/// allocated up front (an error naming n_max if it cannot be), and each row is computed
/// once, whole, by one task: Λ_n comes from a recurrence in n, so a row cut into parallel
/// chunks would be recomputed from its start for every chunk.
pub fn lambda_table(
    paper: bool,
    crank_ratios: &[f64],
    n_max: usize,
    parallelism: Parallelism,
) -> Result<Vec<f64>> {
    for &lambda in crank_ratios {
        check("crank_ratio", lambda, "0 <= crank_ratio < 1", |x| {
            (0.0..1.0).contains(&x)
        })?;
    }
    let width = harmonic_width(n_max)?;
    let len = crank_ratios.len() as u128 * width as u128;
    let mut out = try_filled("n_max", n_max, len, 0.0)?;
    // Λ_n costs far more than one output point: weigh each entry like 64 points.
    let work = out.len().saturating_mul(64);
    for_each_row(&mut out, width, work, parallelism, |row, values| {
        if paper {
            lambda_paper(crank_ratios[row], values)
        } else {
            lambda_exact(crank_ratios[row], values)
        }
    });
    Ok(out)
}

/// The paper's truncation: powers of λ through λ¹¹, harmonics through n = 12.
pub const PAPER_MAX_POWER: u32 = 11;
pub const PAPER_MAX_HARMONIC: usize = 12;

/// The largest j for which `paper_coefficient` is exact in 128-bit integers.
pub const PAPER_MAX_J: u32 = 20;

fn binomial(n: u128, k: u128) -> u128 {
    if k > n {
        return 0;
    }
    (0..k).fold(1, |acc, i| acc * (n - i) / (i + 1))
}

/// The greatest common divisor (Euclid).
pub(crate) fn gcd(a: u128, b: u128) -> u128 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// [λ^{2j+1}] Λ_{2i} as a reduced fraction, for j ≤ PAPER_MAX_J (no overflow in u128).
fn paper_fraction(i: u32, j: u32) -> (i128, u128) {
    if i == 0 || j + 1 < i {
        return (0, 1);
    }
    let (i, j) = (i as u128, j as u128);
    let numerator = 2 * i * binomial(2 * j, j) * binomial(2 * j + 2, j + 1 - i);
    let denominator = (j + 1) * 4u128.pow(2 * j as u32 + 1);
    let common = gcd(numerator, denominator);
    let sign = if i % 2 == 1 { 1 } else { -1 };
    (sign * (numerator / common) as i128, denominator / common)
}

/// The exact rational [λ^{2j+1}] Λ_{2i} = (−1)^{i+1}·(2i/(j+1))·C(2j, j)·C(2j+2, j+1−i)/4^{2j+1}
/// (eq. 15's general coefficient), as a reduced (numerator, denominator); 0/1 for j < i − 1.
/// Valid for j ≤ PAPER_MAX_J = 20, where the integers fit 128 bits.
pub fn paper_coefficient(i: u32, j: u32) -> Result<(i128, u128)> {
    if j > PAPER_MAX_J {
        return Err(MechanismError::InvalidChoice {
            parameter: "j",
            value: j.to_string(),
            allowed: "an integer 0 <= j <= 20",
        });
    }
    Ok(paper_fraction(i, j))
}

/// Λ_0 … Λ_{n_max} as the paper computes them: the λ-series through λ¹¹, zero above n = 12.
pub fn lambda_paper(crank_ratio: f64, out: &mut [f64]) {
    out.fill(0.0);
    for n in (2..out.len().min(PAPER_MAX_HARMONIC + 1)).step_by(2) {
        let i = (n / 2) as u32;
        out[n] = (i - 1..=(PAPER_MAX_POWER - 1) / 2)
            .map(|j| {
                let (p, q) = paper_fraction(i, j);
                (p as f64 / q as f64) * crank_ratio.powi(2 * j as i32 + 1)
            })
            .sum();
    }
}

/// The harmonic reach a series at crank ratio λ can need: the smallest even n with
/// t^{n−1} ≤ 1e-40 (far below any tail that matters), at least 24, at most MAX_HARMONIC.
pub fn harmonic_reach(crank_ratio: f64) -> usize {
    let t = t_of(crank_ratio).hi;
    if t <= 0.0 {
        return 24;
    }
    let n = 1.0 + (-40.0 * std::f64::consts::LN_10) / t.ln();
    let n = (n.ceil() as usize).clamp(24, MAX_HARMONIC);
    n + n % 2
}

#[cfg(test)]
mod tests;
