//! Roots and extrema on the cycle's panels, and where the time mesh is graded: Brent's
//! method, the exact extremes of a function known at the panels' samples, and the local
//! minima of the kinetic energy E towards which t = ∫√(J/2E) dφ needs finer panels
//! (docs/theory.md, "How the integrals are taken").

use crate::error::Result;

use super::interpolant::polish;
use super::quadrature::Panels;

/// Brent's method: a root of `f` in [a, b] where f(a) and f(b) differ in sign (or one is 0),
/// to |error| ≤ xtol + rtol·|x| (rtol ≥ 4ε, else the bracket could stop shrinking). Inverse
/// quadratic interpolation or the secant where they stay well inside the bracket, bisection
/// otherwise: never slower than bisection by more than a small factor. `None` when the ends
/// have the same sign or f is not finite.
pub(crate) fn brent(
    mut f: impl FnMut(f64) -> Result<f64>,
    a: f64,
    b: f64,
    xtol: f64,
    rtol: f64,
) -> Result<Option<f64>> {
    let (fa, fb) = (f(a)?, f(b)?);
    brent_from(f, (a, fa), (b, fb), xtol, rtol)
}

/// [`brent`] from ends whose values are known, `(a, f(a))` and `(b, f(b))`.
pub(crate) fn brent_from(
    mut f: impl FnMut(f64) -> Result<f64>,
    (a, fa): (f64, f64),
    (b, fb): (f64, f64),
    xtol: f64,
    rtol: f64,
) -> Result<Option<f64>> {
    let rtol = rtol.max(4.0 * f64::EPSILON);
    let (mut a, mut b) = (a, b);
    let (mut fa, mut fb) = (fa, fb);
    if !(fa.is_finite() && fb.is_finite()) || fa * fb > 0.0 {
        return Ok(None);
    }
    if fa == 0.0 {
        return Ok(Some(a));
    }
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    // Each step at least halves the bracket every few steps: 200 covers the doubles' range.
    for _ in 0..200 {
        if fb * fc > 0.0 {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 0.5 * (xtol + rtol * b.abs());
        let m = 0.5 * (c - b);
        if m.abs() <= tol || fb == 0.0 {
            return Ok(Some(b));
        }
        if e.abs() >= tol && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q) = if a == c {
                (2.0 * m * s, 1.0 - s)
            } else {
                let q = fa / fc;
                let r = fb / fc;
                (
                    s * (2.0 * m * q * (q - r) - (b - a) * (r - 1.0)),
                    (q - 1.0) * (r - 1.0) * (s - 1.0),
                )
            };
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol { d } else { tol.copysign(m) };
        fb = f(b)?;
        if !fb.is_finite() {
            return Ok(None);
        }
    }
    Ok(Some(b))
}

/// How close to the real axis E's nearest complex zero may come to a panel, in its half-
/// widths: a zero at distance d leaves a 12-point Gauss rule a Bernstein ellipse of ρ ≥ 3
/// (1/ω = √(J/2E) to ~1e-12) when d ≥ 1.5 half-widths (docs/theory.md, "How the integrals
/// are taken").
pub(crate) const GRADE_REACH: f64 = 1.5;

/// Geometric grading towards a near-zero of E: each panel this many times wider than the
/// last.
const GRADE_RATIO: f64 = 4.0;

/// A local minimum of E located exactly: where E = s + K̃ dips between the samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Dip {
    /// φ (rad).
    pub angle: f64,
    /// E there (J).
    pub value: f64,
    /// |E''| there (J/rad²), the larger of the samples' beside it.
    pub bend: f64,
}

/// Every local minimum of the samples of E (`energy`, nodes then edges; E'' = `curvature`
/// at the nodes) located exactly, as [`refine_extrema`] locates an extremum: the root of
/// the slope E′ between the samples beside it and E there (`exact`: E and E′ at any angle);
/// the sample itself where that is no lower (a minimum at a kink of E′).
///
/// The grading must be centred on the minimum itself, with its own d: graded towards a
/// sample 6e-3 rad off a minimum of d = 3e-4 rad, the time of a cycle near a stall was
/// 0.5 % off.
pub(crate) fn local_minima(
    panels: &Panels,
    energy: &[f64],
    curvature: &[f64],
    mut exact: impl FnMut(f64) -> Result<(f64, f64)>,
) -> Result<Vec<Dip>> {
    let samples = panels.in_angle_order(energy);
    let scale = samples.iter().fold(0.0_f64, |m, s| m.max(s.1.abs()));
    // The curvature of an edge is that of its panel's first node.
    let mut bend = Vec::with_capacity(samples.len());
    for panel in curvature.chunks_exact(panels.order) {
        bend.push(panel[0]);
        bend.extend_from_slice(panel);
    }
    let count = samples.len();
    let mut dips = Vec::new();
    for i in 0..count {
        let (before, after) = ((i + count - 1) % count, (i + 1) % count);
        if !(samples[i].1 < samples[before].1 && samples[i].1 <= samples[after].1) {
            continue;
        }
        let (angle, value) =
            refine_at(panels, energy, Some(&samples), i, false, scale, &mut exact)?;
        dips.push(Dip {
            angle: angle.rem_euclid(panels.cycle()),
            value,
            // E'' from the neighbours too: a minimum on an edge has both panels' curvature.
            bend: bend[i].abs().max(bend[before].abs()).max(bend[after].abs()),
        });
    }
    Ok(dips)
}

/// Edges to add to the base panels so that ∫√(J/2E) dφ stays spectrally accurate where E
/// nearly vanishes: geometric panels (ratio 4) centred on every local minimum of E (`dips`,
/// located exactly) whose complex zeros, at d = √(2E/|E''|) from the real axis, come closer
/// than 1.5 half-widths of the widest panel; the innermost panel [φ_i − d/3, φ_i + d/3]
/// (docs/theory.md, "How the integrals are taken"). Empty where none does.
pub(crate) fn grading(panels: &Panels, dips: impl IntoIterator<Item = Dip>) -> Vec<f64> {
    let cycle = panels.cycle();
    let half = panels.widest_half();
    let mut extra = Vec::new();
    for dip in dips {
        let reach = if dip.bend > 0.0 {
            (2.0 * dip.value.max(0.0) / dip.bend).sqrt()
        } else {
            f64::INFINITY
        };
        // reach is never NaN: value ≥ 0, bend > 0 (else ∞).
        if reach >= GRADE_REACH * half {
            continue;
        }
        let width = (reach / (2.0 * GRADE_REACH)).max(1e-12 * cycle);
        let steps = ((2.0 * half / width).ln() / GRADE_RATIO.ln()).ceil() as i32;
        for k in 0..=steps {
            let step = width * GRADE_RATIO.powi(k);
            extra.push((dip.angle - step).rem_euclid(cycle));
            extra.push((dip.angle + step).rem_euclid(cycle));
        }
    }
    extra
}

/// The angles and values of the largest and the smallest of a function known at the nodes
/// then edges of `panels` (`values`), each located as the best sample (the first in angle
/// order of those within [`TIE_ULPS`] of it), then the root of the function's slope between it and a neighbour
/// sample, where the function is evaluated exactly (`exact`: its value and slope at any
/// angle). Kept only where better than the sample (an extremum at a kink of the slope has
/// no root there).
///
/// The root is found on the panel's interpolant of the samples and polished by Newton's
/// steps on the exact slope ([`polish`]): an exact evaluation or two. Where that does not
/// settle (a kink, an extremum the interpolant does not resolve), Brent's method on the
/// exact slope ([`refine_sample`]).
pub(crate) fn refine_extrema(
    panels: &Panels,
    values: &[f64],
    mut exact: impl FnMut(f64) -> Result<(f64, f64)>,
) -> Result<[(f64, f64); 2]> {
    let (most, least) = bounds(&values[..panels.phi.len() + panels.count()]);
    let scale = most.abs().max(least.abs());
    // Extremes equal to rounding (a machine whose cycle repeats within itself: a twin's
    // halves, a V12's twelfths) are told apart by rounding alone: the first of them in
    // angle order is taken.
    let tie = TIE_ULPS * f64::EPSILON * scale;
    let top = first_at(panels, values, |v| v >= most - tie);
    let bottom = first_at(panels, values, |v| v <= least + tie);
    Ok([
        refine_at(panels, values, None, top, true, scale, &mut exact)?,
        refine_at(panels, values, None, bottom, false, scale, &mut exact)?,
    ])
}

/// (max, min) of `values`, NaNs left out: in lanes, without a chain through every sample.
fn bounds(values: &[f64]) -> (f64, f64) {
    const WIDE: usize = 8;
    let (mut most, mut least) = ([f64::NEG_INFINITY; WIDE], [f64::INFINITY; WIDE]);
    let chunks = values.chunks_exact(WIDE);
    let tail = chunks.remainder();
    for chunk in chunks {
        for lane in 0..WIDE {
            most[lane] = most[lane].max(chunk[lane]);
            least[lane] = least[lane].min(chunk[lane]);
        }
    }
    let most = tail
        .iter()
        .chain(&most)
        .fold(f64::NEG_INFINITY, |a, &v| a.max(v));
    let least = tail
        .iter()
        .chain(&least)
        .fold(f64::INFINITY, |a, &v| a.min(v));
    (most, least)
}

/// Samples within this many ulps of the largest |sample| of the best are as good as it.
const TIE_ULPS: f64 = 16.0;

/// The index in angle order ([`Panels::in_angle_order`]) of the first sample that is
/// `best` (0 where none is, or where the first sample is NaN: nothing compares better than
/// it).
fn first_at(panels: &Panels, values: &[f64], best: impl Fn(f64) -> bool) -> usize {
    let (n, order) = (panels.phi.len(), panels.order);
    if values[n].is_nan() {
        return 0;
    }
    for p in 0..panels.count() {
        let first = p * (order + 1);
        if best(values[n + p]) {
            return first;
        }
        if let Some(r) = values[p * order..(p + 1) * order]
            .iter()
            .position(|&v| best(v))
        {
            return first + 1 + r;
        }
    }
    0
}

/// The extremum next to sample `index` (angle order) of `values` (nodes then edges):
/// [`polish`], else [`refine_sample`] on `samples` (`values` in angle order, made here
/// where not given); the sample itself where the root found is no better.
fn refine_at(
    panels: &Panels,
    values: &[f64],
    samples: Option<&[(f64, f64)]>,
    index: usize,
    largest: bool,
    scale: f64,
    exact: &mut impl FnMut(f64) -> Result<(f64, f64)>,
) -> Result<(f64, f64)> {
    let sign = if largest { 1.0 } else { -1.0 };
    let (angle, at_best) = sample(panels, values, index);
    if let Some((root, found)) = polish(panels, values, index, largest, scale, exact)? {
        return Ok(if sign * found > sign * at_best {
            (root, found)
        } else {
            (angle, at_best)
        });
    }
    let made;
    let samples = match samples {
        Some(samples) => samples,
        None => {
            made = panels.in_angle_order(values);
            &made
        }
    };
    refine_sample(panels.cycle(), samples, index, largest, exact)
}

/// Sample `index` in angle order ([`Panels::in_angle_order`]): (angle, value).
fn sample(panels: &Panels, values: &[f64], index: usize) -> (f64, f64) {
    let (n, order) = (panels.phi.len(), panels.order);
    let (p, r) = (index / (order + 1), index % (order + 1));
    if r == 0 {
        (panels.edges[p], values[n + p])
    } else {
        let i = p * order + r - 1;
        (panels.phi[i], values[i])
    }
}

/// The extremum next to sample `best` of `samples` ((angle, value) in angle order over the
/// cycle `cycle`, the last followed by the first), located as [`refine_extrema`] does.
fn refine_sample(
    cycle: f64,
    samples: &[(f64, f64)],
    best: usize,
    largest: bool,
    exact: &mut impl FnMut(f64) -> Result<(f64, f64)>,
) -> Result<(f64, f64)> {
    let sign = if largest { 1.0 } else { -1.0 };
    let count = samples.len();
    let (angle, at_best) = samples[best];
    let before = samples[(best + count - 1) % count].0;
    let before = if before > angle {
        before - cycle
    } else {
        before
    };
    let after = samples[(best + 1) % count].0;
    let after = if after < angle { after + cycle } else { after };
    // The function rises (for a maximum) up to the root: its slope, times sign, goes from
    // positive to negative.
    let mut rate = |phi: f64| -> Result<f64> { Ok(sign * exact(phi)?.1) };
    // Start at the vertex of the parabola through the best sample and its neighbours (a
    // smooth extremum is there to a small fraction of the spacing) and bracket the root
    // with a step of NARROW_BRACKET of the span the way the slope points: a root to rounding
    // in a few steps. Where the step does not reach it (a kink, a sharp peak), the bracket
    // runs on to the neighbour sample.
    let (f_before, f_after) = (
        samples[(best + count - 1) % count].1,
        samples[(best + 1) % count].1,
    );
    let start =
        parabola_vertex((before, f_before), (angle, at_best), (after, f_after)).unwrap_or(angle);
    let at_start = rate(start)?;
    let found = if at_start == 0.0 {
        Some(start)
    } else {
        // The rate falls through the root: it lies ahead of a positive rate, behind a
        // negative one.
        let (ahead, end) = if at_start > 0.0 {
            (1.0, after)
        } else {
            (-1.0, before)
        };
        let near = start + ahead * NARROW_BRACKET * (after - before);
        let near = if ahead > 0.0 {
            near.min(end)
        } else {
            near.max(end)
        };
        let at_near = rate(near)?;
        let (from, to) = if at_near * at_start <= 0.0 {
            ((start, at_start), (near, at_near))
        } else {
            ((near, at_near), (end, rate(end)?))
        };
        // Brent's method from the ends in ascending order.
        let (low, high) = if from.0 < to.0 {
            (from, to)
        } else {
            (to, from)
        };
        brent_from(&mut rate, low, high, 0.0, 4.0 * f64::EPSILON)?
    };
    if let Some(root) = found {
        let found = exact(root)?.0;
        if sign * found > sign * at_best {
            return Ok((root, found));
        }
    }
    Ok((angle, at_best))
}

/// The half-width of the narrow bracket about a parabola's vertex, as a fraction of the
/// span of the three samples.
const NARROW_BRACKET: f64 = 1e-3;

/// The abscissa of the vertex of the parabola through three points (x ascending); `None`
/// where they are collinear or the vertex falls outside [x₀, x₂].
fn parabola_vertex(
    (x0, y0): (f64, f64),
    (x1, y1): (f64, f64),
    (x2, y2): (f64, f64),
) -> Option<f64> {
    let (d0, d2) = (x0 - x1, x2 - x1);
    let (s0, s2) = ((y0 - y1) / d0, (y2 - y1) / d2);
    let curvature = (s2 - s0) / (x2 - x0);
    if !(curvature.is_finite() && curvature != 0.0) {
        return None;
    }
    // Newton's form p = y1 + s0(x − x1) + c(x − x1)(x − x0): p′ = 0 at
    // x1 − (s0 − c·d0)/(2c).
    let b = s0 - curvature * d0;
    let vertex = x1 - b / (2.0 * curvature);
    (x0 < vertex && vertex < x2).then_some(vertex)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_roots_to_rounding_and_refuses_no_bracket() {
        let root = brent(|x| Ok(x * x - 2.0), 0.0, 2.0, 0.0, 1e-15)
            .unwrap()
            .unwrap();
        assert!((root - 2f64.sqrt()).abs() <= 4e-16 * 2f64.sqrt());
        let root = brent(|x| Ok(x.cos() - x), 0.0, 1.0, 0.0, 4.0 * f64::EPSILON)
            .unwrap()
            .unwrap();
        assert!((root - 0.739_085_133_215_160_6).abs() < 3e-16);
        // A flat then steep function, and a root at an end.
        let root = brent(|x| Ok((x - 1e-3).powi(9)), -1.0, 2.0, 0.0, 1e-15)
            .unwrap()
            .unwrap();
        assert!((root - 1e-3).abs() < 1e-3);
        assert_eq!(brent(Ok, 0.0, 1.0, 0.0, 1e-15).unwrap(), Some(0.0));
        assert_eq!(
            brent(|x| Ok(x * x + 1.0), -1.0, 1.0, 0.0, 1e-15).unwrap(),
            None
        );
        let mut calls = 0;
        brent(
            |x| {
                calls += 1;
                Ok(x.powi(3) - x - 1.0)
            },
            1.0,
            2.0,
            0.0,
            1e-15,
        )
        .unwrap();
        assert!(calls < 15, "{calls} calls");
    }
}
