//! The energy method for the "balance" load (docs/theory.md, "Steady running", "Three ways
//! to the periodic solution"): with every torque a function of φ alone,
//!
//!   ω²(φ) = 2[E₀ + K(φ)]/J(φ),  K(φ) = ∫₀^φ (M_gas − M_load) dφ − [U(φ) − U(0)],
//!
//! written E = s + K̃ with K̃ = K − min K ≥ 0 and s > 0 the kinetic energy left at the worst
//! angle; s is the root of (Φ/(t_Φ(s)·ω_m))² − 1, increasing and nearly linear in s.

use crate::error::{MechanismError, Result};

use super::cycle::Cycle;

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
    let rtol = rtol.max(4.0 * f64::EPSILON);
    let (mut a, mut b) = (a, b);
    let (mut fa, mut fb) = (f(a)?, f(b)?);
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

/// Why a solution was refused: the machine does not run at the state asked for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Stall {
    /// φ (rad) of the speed minimum (or of the worst angle).
    pub angle: f64,
}

/// A periodic solution's numbers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Periodic {
    pub omega_mean: f64,
    pub period: f64,
    pub omega_max: f64,
    pub omega_min: f64,
    pub phi_max: f64,
    pub phi_min: f64,
    /// s: E at the worst angle (J); E(φ) = s + K̃(φ).
    pub margin: f64,
    /// E(0) (J).
    pub energy_at_zero: f64,
}

impl Periodic {
    pub fn delta(&self) -> f64 {
        (self.omega_max - self.omega_min) / self.omega_mean
    }
}

/// K̃ on the cycle's tables, and the root in s.
pub(crate) struct Balance<'c, 'a> {
    cycle: &'c Cycle<'a>,
    gas: bool,
    /// The constant load (N·m).
    pub load: f64,
    /// max |K''| over the nodes (N·m/rad) (0 until `with_curvature`).
    sharpest: f64,
    /// min K over the samples (J).
    k_min: f64,
    /// Where (rad), and J − I_w there.
    lowest: f64,
    rest_low: f64,
    /// K̃ = K − min K at the nodes, then the edges (J).
    lifted: Vec<f64>,
}

/// How close to the real axis E's nearest complex zero may come before the base panels no
/// longer integrate 1/ω = √(J/2E) to ~1e-12, in half-widths of the widest panel: a zero at
/// distance d leaves a 12-point Gauss rule a Bernstein ellipse of ρ ≥ 3 when d ≥ 1.5 half-
/// widths (the Python implementation's `_GRADE_REACH`).
const GRADE_REACH: f64 = 1.5;

/// The step (rad) of the central differences that estimate K'' = M′ for that bound: small
/// beside a panel (≥ π/60 wide), large enough that rounding of M (~1e-16·|M|) stays below
/// 1e-10 of the slope.
const SLOPE_STEP: f64 = 1e-5;

impl<'c, 'a> Balance<'c, 'a> {
    /// The energy method on `cycle` with the constant `load` (N·m); `gas`: whether the gas
    /// work is taken (false: gravity and the variation of J alone).
    pub fn new(cycle: &'c Cycle<'a>, load: f64, gas: bool) -> Self {
        let n = cycle.nodes();
        let angles = cycle.panels.phi.iter().chain(&cycle.panels.edges);
        let k: Vec<f64> = angles
            .zip(&cycle.potential)
            .zip(&cycle.gas_work)
            .map(|((phi, u), w)| {
                let k = -u - load * phi;
                if gas {
                    k + w
                } else {
                    k
                }
            })
            .collect();
        // The lowest node, then an edge only where strictly lower.
        let mut lowest = 0;
        for i in 1..n {
            if k[i] < k[lowest] {
                lowest = i;
            }
        }
        for i in n..k.len() {
            if k[i] < k[lowest] {
                lowest = i;
            }
        }
        let at = |i: usize| {
            if i < n {
                cycle.panels.phi[i]
            } else {
                cycle.panels.edges[i - n]
            }
        };
        let k_min = k[lowest];
        Self {
            cycle,
            gas,
            load,
            sharpest: 0.0,
            k_min,
            lowest: at(lowest),
            rest_low: cycle.rest[lowest],
            lifted: k.iter().map(|k| k - k_min).collect(),
        }
    }

    /// max |K''| = max |M′| over the nodes, by central differences of the exact torque: how
    /// sharply E = s + K̃ may dip, for the bound on the complex zeros of E.
    pub fn with_curvature(mut self) -> Result<Self> {
        let phi = &self.cycle.panels.phi;
        let shifted = |h: f64| phi.iter().map(|p| p + h).collect::<Vec<f64>>();
        let ahead = self.cycle.torque_at(&shifted(SLOPE_STEP), self.gas)?;
        let behind = self.cycle.torque_at(&shifted(-SLOPE_STEP), self.gas)?;
        self.sharpest = ahead.iter().zip(&behind).fold(0.0, |m, (a, b)| {
            f64::max(m, ((a - b) / (2.0 * SLOPE_STEP)).abs())
        });
        Ok(self)
    }

    /// Whether the base panels resolve 1/ω for E = s + K̃: E's complex zeros are at least
    /// √(2s/max|K''|) from the real axis, to be kept `GRADE_REACH` half-widths away.
    fn resolves(&self, s: f64) -> bool {
        let half = self
            .cycle
            .panels
            .edges
            .windows(2)
            .fold(0.0, |m, e| f64::max(m, 0.5 * (e[1] - e[0])));
        2.0 * s >= self.sharpest * (GRADE_REACH * half).powi(2)
    }

    /// t_Φ(s) = ∫₀^Φ √(J/2(s + K̃)) dφ on the panels.
    fn period(&self, s: f64) -> f64 {
        let cycle = self.cycle;
        cycle
            .panels
            .weights
            .iter()
            .zip(&cycle.rest)
            .zip(&self.lifted)
            .map(|((w, rest), k)| w * (0.5 * (cycle.inertia + rest) / (s + k)).sqrt())
            .sum()
    }

    /// K̃(φ) (J) at any angles in [0, Φ].
    fn lifted_at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        let u = self.cycle.potential_at(phi)?;
        let w = if self.gas {
            self.cycle.work.at(phi)?
        } else {
            vec![0.0; phi.len()]
        };
        Ok(phi
            .iter()
            .zip(&u)
            .zip(&w)
            .map(|((phi, u), w)| w + (-u - self.load * phi) - self.k_min)
            .collect())
    }

    /// The periodic solution of mean speed `omega_mean` (rad/s); `Err(Stall)` inside `Ok`
    /// when it needs ω_min < `ratio`·ω_m.
    pub fn solve(
        &self,
        omega_mean: f64,
        ratio: f64,
    ) -> Result<std::result::Result<Periodic, Stall>> {
        let cycle = self.cycle;
        let target = cycle.cycle() / omega_mean;
        let excess = |s: f64| -> Result<f64> { Ok((target / self.period(s)).powi(2) - 1.0) };
        // At s_low the speed at the worst angle is ratio·ω_m: if the mean speed there is
        // already above the one asked for, the solution has a smaller s, and stalls.
        let s_low = 0.5 * (cycle.inertia + self.rest_low) * (ratio * omega_mean).powi(2);
        // Near stall 1/ω peaks sharper than the base panels resolve, and their t_Φ could err
        // either way: the Python implementation then grades the panels geometrically towards
        // the peak. Not ported yet: where it would be needed, say so rather than guess.
        let unresolved = || MechanismError::Unresolved {
            parameter: "rpm",
            value: 30.0 * omega_mean / std::f64::consts::PI,
        };
        if excess(s_low)? > 0.0 {
            if !self.resolves(s_low) {
                return Err(unresolved());
            }
            return Ok(Err(Stall { angle: self.lowest }));
        }
        // At s_high, ω² = 2(s + K̃)/J ≥ ω_m² everywhere: the mean speed is at least ω_m.
        let j_max = cycle.rest.iter().fold(f64::NEG_INFINITY, |a, &r| a.max(r)) + cycle.inertia;
        let mut high = 0.5 * j_max * omega_mean * omega_mean * 1.01;
        // Never more than a step or two (s_high bounds the root); the bound only ends the
        // loop on a NaN.
        for _ in 0..64 {
            if excess(high)? >= 0.0 {
                break;
            }
            high *= 2.0;
        }
        // rtol 1e-15: s to rounding (the excess is nearly linear in s).
        let Some(s) = brent(excess, s_low, high, 0.0, 1e-15)? else {
            return Ok(Err(Stall { angle: self.lowest }));
        };
        if !self.resolves(s) {
            return Err(unresolved());
        }
        self.finish(s, ratio)
    }

    /// t_Φ, ω_m and the extremes of ω for E = s + K̃.
    fn finish(&self, s: f64, ratio: f64) -> Result<std::result::Result<Periodic, Stall>> {
        let cycle = self.cycle;
        let panels = &cycle.panels;
        let n = cycle.nodes();
        let omega: Vec<f64> = cycle
            .rest
            .iter()
            .zip(&self.lifted)
            .map(|(rest, k)| (2.0 * (s + k).max(0.0) / (cycle.inertia + rest)).sqrt())
            .collect();
        if let Some(i) = omega.iter().position(|&w| w <= 0.0) {
            let angle = if i < n {
                panels.phi[i]
            } else {
                panels.edges[i - n]
            };
            return Ok(Err(Stall { angle }));
        }
        let period = panels.integral(&omega[..n].iter().map(|w| 1.0 / w).collect::<Vec<_>>());
        let omega_mean = cycle.cycle() / period;
        let (phi_max, omega_max) = self.extremum(s, &omega, true)?;
        let (phi_min, omega_min) = self.extremum(s, &omega, false)?;
        let solution = Periodic {
            omega_mean,
            period,
            omega_max,
            omega_min,
            phi_max: phi_max.rem_euclid(cycle.cycle()),
            phi_min: phi_min.rem_euclid(cycle.cycle()),
            margin: s,
            energy_at_zero: s - self.k_min,
        };
        if omega_min < ratio * omega_mean {
            return Ok(Err(Stall {
                angle: solution.phi_min,
            }));
        }
        Ok(Ok(solution))
    }

    /// ω(φ) exactly and the sign of dω/dφ: J φ̈ = M_gas − U′ − M_load − ½J′ω², the net torque
    /// with the inertia torque, whose roots are the extremes of ω.
    fn speed_and_torque(&self, s: f64, phi: f64) -> Result<(f64, f64)> {
        let folded = [phi.rem_euclid(self.cycle.cycle())];
        let energy = s + self.lifted_at(&folded)?[0];
        let (j, slope) = self.cycle.inertia_at(&folded)?;
        let torque = self.cycle.torque_at(&folded, self.gas)?[0] - self.load;
        Ok((
            (2.0 * energy.max(0.0) / j[0]).sqrt(),
            torque - slope[0] * energy / j[0],
        ))
    }

    /// The angle and value of the largest (`largest`) or smallest ω: the best sample of
    /// nodes and edges, then the root of the net torque between it and a neighbour sample
    /// (Brent's method, to rounding), where ω is evaluated exactly. Kept only where better
    /// than the sample (an extremum at a kink of the torque has no root there).
    fn extremum(&self, s: f64, omega: &[f64], largest: bool) -> Result<(f64, f64)> {
        let panels = &self.cycle.panels;
        let (n, order) = (self.cycle.nodes(), panels.order);
        // The samples in angle order: edge p, the nodes of panel p, …; the last edge is edge 0.
        let mut samples: Vec<(f64, f64)> = Vec::with_capacity(n + panels.count());
        for p in 0..panels.count() {
            samples.push((panels.edges[p], omega[n + p]));
            let nodes = p * order..(p + 1) * order;
            samples.extend(
                panels.phi[nodes.clone()]
                    .iter()
                    .copied()
                    .zip(omega[nodes].iter().copied()),
            );
        }
        let sign = if largest { 1.0 } else { -1.0 };
        let mut best = 0;
        for (i, sample) in samples.iter().enumerate() {
            if sign * sample.1 > sign * samples[best].1 {
                best = i;
            }
        }
        let count = samples.len();
        let (angle, value) = samples[best];
        let before = samples[(best + count - 1) % count].0;
        let before = if before > angle {
            before - self.cycle.cycle()
        } else {
            before
        };
        let after = samples[(best + 1) % count].0;
        let after = if after < angle {
            after + self.cycle.cycle()
        } else {
            after
        };
        // ω rises (for a maximum) up to the root: the net torque, times sign, goes from
        // positive to negative.
        let rate = |phi: f64| -> Result<f64> { Ok(sign * self.speed_and_torque(s, phi)?.1) };
        let here = rate(angle)?;
        let (a, b) = if here > 0.0 {
            (angle, after)
        } else {
            (before, angle)
        };
        if let Some(root) = brent(rate, a, b, 0.0, 4.0 * f64::EPSILON)? {
            let (found, _) = self.speed_and_torque(s, root)?;
            if sign * found > sign * value {
                return Ok((root, found));
            }
        }
        Ok((angle, value))
    }
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
