//! The energy method for the "balance" load (docs/theory.md, "Steady running", "Three ways
//! to the periodic solution"): with every torque a function of φ alone,
//!
//!   ω²(φ) = 2[E₀ + K(φ)]/J(φ),  K(φ) = ∫₀^φ (M_gas − M_load) dφ − [U(φ) − U(0)],
//!
//! written E = s + K̃ with K̃ = K − min K ≥ 0 and s > 0 the kinetic energy left at the worst
//! angle; s is the root of (Φ/(t_Φ(s)·ω_m))² − 1, increasing and nearly linear in s.

use std::sync::Arc;

use crate::error::Result;

use super::cycle::Cycle;
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

/// A solution's speed and time at requested angles.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Curves {
    /// ω(φ_i) (rad/s).
    pub omega: Vec<f64>,
    /// t(φ_i) (s), from φ = 0.
    pub time: Vec<f64>,
}

/// A solution, or the stall that refused it.
pub(crate) type Solved = std::result::Result<Periodic, Stall>;

/// How close to the real axis E's nearest complex zero may come to a panel, in its half-
/// widths: a zero at distance d leaves a 12-point Gauss rule a Bernstein ellipse of ρ ≥ 3
/// (1/ω = √(J/2E) to ~1e-12) when d ≥ 1.5 half-widths (the Python implementation's
/// `_GRADE_REACH`).
const GRADE_REACH: f64 = 1.5;

/// Geometric grading towards a near-zero of E: each panel this many times wider than the
/// last (`_GRADE_RATIO`).
const GRADE_RATIO: f64 = 4.0;

/// Refinements of the time mesh before the answer is taken (the Python implementation's
/// 16): each grades for the s found on the last.
const MESH_ROUNDS: usize = 16;

/// The rule on which t_Φ = ∫₀^Φ √(J/2E) dφ is taken: the base panels graded towards E's
/// near-zeros, and there K̃ (J) and J − I_w (kg·m²), nodes then edges.
#[derive(Debug, Clone)]
struct Graded {
    panels: Panels,
    lifted: Vec<f64>,
    rest: Vec<f64>,
}

/// A time mesh: the base panels and tables or a graded one.
#[derive(Clone, Copy)]
struct Mesh<'m> {
    panels: &'m Panels,
    lifted: &'m [f64],
    rest: &'m [f64],
}

impl Mesh<'_> {
    fn nodes(&self) -> usize {
        self.panels.phi.len()
    }
}

/// K̃ on the cycle's tables, and the root in s (docs/theory.md, "Steady running").
#[derive(Debug, Clone)]
pub(crate) struct Balance {
    cycle: Arc<Cycle>,
    gas: bool,
    /// The constant load (N·m).
    pub load: f64,
    /// I_w (kg·m²): the cycle's own, or another (`with_inertia`; K does not depend on it).
    inertia: f64,
    /// K'' = (M_gas − U′)′ at the base nodes (N·m/rad), by central differences of the exact
    /// torque: how sharply E = s + K̃ may dip.
    curvature: Vec<f64>,
    /// max |K''| over the nodes (N·m/rad).
    sharpest: f64,
    /// min K (J): over the samples, then (`locate_minimum`) between them.
    k_min: f64,
    /// Where (rad), and J − I_w there (kg·m²).
    lowest: f64,
    rest_low: f64,
    /// Whether min K was located between the samples.
    exact: bool,
    /// K̃ = K − min K at the base nodes, then the edges (J).
    lifted: Vec<f64>,
}

impl Balance {
    /// The energy method on `cycle` with the constant `load` (N·m); `gas`: whether the gas
    /// work is taken (false: gravity and the variation of J alone).
    pub fn new(cycle: &Arc<Cycle>, load: f64, gas: bool) -> Result<Self> {
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
        let curvature = cycle.curvature(gas);
        Ok(Self {
            cycle: Arc::clone(cycle),
            gas,
            load,
            inertia: cycle.inertia,
            sharpest: curvature.iter().fold(0.0, |m, c| f64::max(m, c.abs())),
            curvature,
            k_min,
            lowest: at(lowest),
            rest_low: cycle.rest[lowest],
            exact: false,
            lifted: k.iter().map(|k| k - k_min).collect(),
        })
    }

    /// The same torques on a shaft of inertia I_w = `inertia` (kg·m²): no table is made
    /// again (the Python implementation's `Balance.with_inertia`).
    pub fn with_inertia(&self, inertia: f64) -> Self {
        Self {
            inertia,
            ..self.clone()
        }
    }

    /// Φ (rad).
    pub fn cycle(&self) -> f64 {
        self.cycle.cycle()
    }

    /// (1/Φ)∫(J − I_w) dφ (kg·m²).
    pub fn mean_rest(&self) -> f64 {
        self.cycle.mean_rest()
    }

    /// max K̃ over the samples (J): about max K − min K.
    pub fn swing(&self) -> f64 {
        self.lifted.iter().fold(f64::NEG_INFINITY, |m, &k| m.max(k))
    }

    fn base(&self) -> Mesh<'_> {
        Mesh {
            panels: &self.cycle.panels,
            lifted: &self.lifted,
            rest: &self.cycle.rest,
        }
    }

    fn view<'m>(&'m self, graded: &'m Option<Graded>) -> Mesh<'m> {
        graded.as_ref().map_or_else(
            || self.base(),
            |g| Mesh {
                panels: &g.panels,
                lifted: &g.lifted,
                rest: &g.rest,
            },
        )
    }

    /// K̃(φ) (J) at any angles in [0, Φ].
    fn lifted_at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        let u = self.cycle.potential_at(phi)?;
        let w = if self.gas {
            self.cycle.gas.work.at(phi)?
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

    /// K′ = M_gas − U′ − M_load (N·m) at one angle.
    fn slope_at(&self, phi: f64) -> Result<f64> {
        let folded = [phi.rem_euclid(self.cycle.cycle())];
        Ok(self.cycle.torque_at(&folded, self.gas)?[0] - self.load)
    }

    /// min K between the samples: K̃ ≥ 0 also on graded nodes near it (the Python
    /// implementation's `_locate_minimum`). Once.
    fn locate_minimum(&mut self) -> Result<()> {
        if self.exact {
            return Ok(());
        }
        self.exact = true;
        let (lowest, dip) = refine_extremum(
            &self.cycle.panels,
            &self.lifted,
            false,
            |phi| self.slope_at(phi),
            |phi| Ok(self.lifted_at(&[phi.rem_euclid(self.cycle.cycle())])?[0]),
        )?;
        if dip < 0.0 {
            let lowest = lowest.rem_euclid(self.cycle.cycle());
            self.k_min += dip;
            self.lifted.iter_mut().for_each(|k| *k -= dip);
            self.lowest = lowest;
            self.rest_low = self.cycle.rest_at(&[lowest])?[0];
        }
        Ok(())
    }

    /// The grading edges for E = s + K̃ (see [`grading`]).
    fn grading(&self, s: f64) -> Vec<f64> {
        let energy: Vec<f64> = self.lifted.iter().map(|k| s + k).collect();
        grading(&self.cycle.panels, &energy, &self.curvature)
    }

    /// The time mesh fit for E = s + K̃: `None` for the base panels, where E's nearest
    /// complex zero, at least √(2s/max|K''|) from the real axis, is far enough from all of
    /// them; else the base panels graded (min K first located exactly).
    fn mesh(&mut self, s: f64) -> Result<Option<Graded>> {
        let half = self.cycle.panels.widest_half();
        if 2.0 * s >= self.sharpest * (GRADE_REACH * half).powi(2) || self.grading(s).is_empty() {
            return Ok(None);
        }
        self.locate_minimum()?;
        let extra = self.grading(s);
        if extra.is_empty() {
            return Ok(None);
        }
        let panels = self.cycle.panels.refined(&extra);
        let everywhere: Vec<f64> = panels.phi.iter().chain(&panels.edges).copied().collect();
        Ok(Some(Graded {
            lifted: self.lifted_at(&everywhere)?,
            rest: self.cycle.rest_at(&everywhere)?,
            panels,
        }))
    }

    /// t_Φ(s) = ∫₀^Φ √(J/2(s + K̃)) dφ on a mesh.
    fn period(&self, mesh: Mesh<'_>, s: f64) -> f64 {
        let term = |w: f64, rest: f64, k: f64| w * (0.5 * (self.inertia + rest) / (s + k)).sqrt();
        let n = mesh.nodes();
        let (w, rest, k) = (
            &mesh.panels.weights[..n],
            &mesh.rest[..n],
            &mesh.lifted[..n],
        );
        // LANES running sums added at the end: the same sum in the same order every time,
        // and one the compiler keeps in vector registers (a single running sum of doubles
        // it may not reorder); the period is taken a dozen times per solve.
        let mut lanes = [0.0; LANES];
        let whole = n / LANES * LANES;
        for ((w, rest), k) in w[..whole]
            .chunks_exact(LANES)
            .zip(rest[..whole].chunks_exact(LANES))
            .zip(k[..whole].chunks_exact(LANES))
        {
            for lane in 0..LANES {
                lanes[lane] += term(w[lane], rest[lane], k[lane]);
            }
        }
        let tail: f64 = (whole..n).map(|i| term(w[i], rest[i], k[i])).sum();
        lanes.iter().sum::<f64>() + tail
    }

    /// The periodic solution of mean speed `omega_mean` (rad/s); `Err(Stall)` inside `Ok`
    /// when it needs ω_min < `ratio`·ω_m. s by Brent's method on (ω_m(s)/ω_m)² − 1, nearly
    /// linear in s, on a mesh graded for that s (again until the mesh no longer grows).
    pub fn solve(&mut self, omega_mean: f64, ratio: f64) -> Result<Solved> {
        Ok(self.solve_on_mesh(omega_mean, ratio)?.0)
    }

    /// As [`Balance::solve`], with ω(φ) (rad/s) and t(φ) (s, from φ = 0) of the solution at
    /// `phi` (rad, each in [0, Φ]) as the Python implementation's `Periodic.omega_at` and
    /// `time_at` give them (see [`Balance::curves`]).
    pub fn solve_with_curves(
        &mut self,
        omega_mean: f64,
        ratio: f64,
        phi: &[f64],
    ) -> Result<std::result::Result<(Periodic, Curves), Stall>> {
        let (solved, graded) = self.solve_on_mesh(omega_mean, ratio)?;
        match solved {
            Ok(solution) => {
                let curves = if phi.is_empty() {
                    Curves {
                        omega: Vec::new(),
                        time: Vec::new(),
                    }
                } else {
                    self.curves(self.view(&graded), solution.margin, phi)?
                };
                Ok(Ok((solution, curves)))
            }
            Err(stall) => Ok(Err(stall)),
        }
    }

    /// ω(φ) = √(2E/J) with E = s + K̃(φ) evaluated exactly (the Python implementation's
    /// `omega_at`), and t(φ) = ∫₀^φ dφ/ω with each panel's interpolant of 1/ω through the
    /// mesh's nodes integrated exactly (its `time_at`: `antiderivative(1/ω)`), at `phi`
    /// (rad, in [0, Φ]; an angle on an edge is taken on the panel that starts there).
    fn curves(&self, mesh: Mesh<'_>, s: f64, phi: &[f64]) -> Result<Curves> {
        let lifted = self.lifted_at(phi)?;
        let rest = self.cycle.rest_at(phi)?;
        let omega = lifted
            .iter()
            .zip(&rest)
            .map(|(k, rest)| (2.0 * (s + k).max(0.0) / (self.inertia + rest)).sqrt())
            .collect();
        let inverse: Vec<f64> = mesh.rest[..mesh.nodes()]
            .iter()
            .zip(mesh.lifted)
            .map(|(rest, k)| 1.0 / (2.0 * (s + k).max(0.0) / (self.inertia + rest)).sqrt())
            .collect();
        let time = mesh.panels.running_at(&inverse, phi);
        Ok(Curves { omega, time })
    }

    /// `solve`, and the graded mesh the answer was taken on (`None`: the base panels).
    fn solve_on_mesh(&mut self, omega_mean: f64, ratio: f64) -> Result<(Solved, Option<Graded>)> {
        let cycle = Arc::clone(&self.cycle);
        let target = cycle.cycle() / omega_mean;
        // At s_low the speed at the worst angle is ratio·ω_m: if the mean speed there is
        // already above the one asked for, the solution has a smaller s, and stalls.
        let s_low = 0.5 * (self.inertia + self.rest_low) * (ratio * omega_mean).powi(2);
        // At s_high, ω² = 2(s + K̃)/J ≥ ω_m² everywhere: the mean speed is at least ω_m.
        let j_max = cycle.rest.iter().fold(f64::NEG_INFINITY, |a, &r| a.max(r)) + self.inertia;
        let s_high = 0.5 * j_max * omega_mean * omega_mean * 1.01;
        let mut graded = self.mesh(s_high)?;
        let mut s = s_high;
        let period =
            |this: &Self, graded: &Option<Graded>, s: f64| this.period(this.view(graded), s);
        for _ in 0..MESH_ROUNDS {
            let size = self.view(&graded).nodes();
            let excess =
                |s: f64| -> Result<f64> { Ok((target / period(self, &graded, s)).powi(2) - 1.0) };
            let at_low = excess(s_low)?;
            if at_low > 0.0 {
                let finer = self.mesh(s_low)?;
                if self.view(&finer).nodes() > size {
                    // Decide on a mesh that resolves the peak at s_low.
                    graded = finer;
                    continue;
                }
                return Ok((Err(Stall { angle: self.lowest }), graded));
            }
            let mut high = s_high;
            let mut at_high = excess(high)?;
            // Never more than a step or two (s_high bounds the root); the bound only ends
            // the loop on a NaN.
            for _ in 0..64 {
                if at_high >= 0.0 {
                    break;
                }
                high *= 2.0;
                at_high = excess(high)?;
            }
            // rtol 1e-15: s to rounding (the excess is nearly linear in s).
            let found = brent_from(excess, (s_low, at_low), (high, at_high), 0.0, 1e-15)?;
            let Some(root) = found else {
                return Ok((Err(Stall { angle: self.lowest }), graded));
            };
            s = root;
            let finer = self.mesh(s)?;
            if self.view(&finer).nodes() <= size {
                break;
            }
            graded = finer;
        }
        let solved = self.finish(self.view(&graded), s, ratio)?;
        Ok((solved, graded))
    }

    /// The periodic solution with E = s + K̃ (its mean speed follows), no stall check (the
    /// Python implementation's `at_margin`).
    fn at_margin(&mut self, s: f64) -> Result<Solved> {
        let graded = self.mesh(s)?;
        self.finish(self.view(&graded), s, 0.0)
    }

    /// The lowest mean speed (rad/s) whose solution keeps ω_min ≥ `ratio`·ω_m (the stall
    /// error's min_rpm): the root in log s of ω_min/ω_m − ratio, which grows with s
    /// (Brent's method, to 1e-12 in log s as the Python implementation's
    /// `lowest_running_speed`). `above`: an s (J) known to stall.
    pub fn lowest_running_speed(&mut self, ratio: f64, above: f64) -> Result<f64> {
        let swing = self.swing();
        let mut shortfall = |log_s: f64| -> Result<f64> {
            Ok(match self.at_margin(log_s.exp())? {
                Ok(p) => p.omega_min / p.omega_mean - ratio,
                Err(_) => -ratio,
            })
        };
        let mut low = above.max(1e-300).ln();
        let mut high = swing.max(above).max(1e-300).ln() + 1.0;
        // The ratio rises from 0 (s → 0) to 1 (s → ∞): a few steps of e² each.
        for _ in 0..400 {
            if shortfall(high)? >= 0.0 {
                break;
            }
            high += 2.0;
        }
        for _ in 0..400 {
            if shortfall(low)? <= 0.0 {
                break;
            }
            low -= 2.0;
        }
        let found = brent(&mut shortfall, low, high, 1e-12, 4.0 * f64::EPSILON)?;
        let Some(log_s) = found else {
            return Ok(f64::NAN);
        };
        Ok(self
            .at_margin(log_s.exp())?
            .map_or(f64::NAN, |p| p.omega_mean))
    }

    /// max K − min K (J), both located between the samples and evaluated exactly: the ΔE of
    /// the textbook flywheel estimate (the Python implementation's `energy_swing`).
    pub fn energy_swing(&self) -> Result<f64> {
        let value = |phi: f64| Ok(self.lifted_at(&[phi.rem_euclid(self.cycle.cycle())])?[0]);
        let slope = |phi: f64| self.slope_at(phi);
        let panels = &self.cycle.panels;
        let (_, top) = refine_extremum(panels, &self.lifted, true, slope, value)?;
        let (_, bottom) = refine_extremum(panels, &self.lifted, false, slope, value)?;
        Ok(top.max(self.swing()) - bottom.min(0.0))
    }

    /// t_Φ, ω_m and the extremes of ω for E = s + K̃ on a mesh.
    fn finish(&self, mesh: Mesh<'_>, s: f64, ratio: f64) -> Result<Solved> {
        let cycle = &self.cycle;
        let panels = mesh.panels;
        let n = mesh.nodes();
        let omega: Vec<f64> = mesh
            .rest
            .iter()
            .zip(mesh.lifted)
            .map(|(rest, k)| (2.0 * (s + k).max(0.0) / (self.inertia + rest)).sqrt())
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
        let speed = |phi: f64| Ok(self.speed_and_torque(s, phi)?.0);
        let (phi_max, omega_max) = refine_extremum(
            panels,
            &omega,
            true,
            |phi| self.speed_and_torque(s, phi).map(|x| x.1),
            speed,
        )?;
        let (phi_min, omega_min) = refine_extremum(
            panels,
            &omega,
            false,
            |phi| self.speed_and_torque(s, phi).map(|x| x.1),
            speed,
        )?;
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

    /// ω(φ) exactly and the net torque J φ̈ = M_gas − U′ − M_load − ½J′ω², whose sign is
    /// that of dω/dφ and whose roots are the extremes of ω.
    fn speed_and_torque(&self, s: f64, phi: f64) -> Result<(f64, f64)> {
        let folded = [phi.rem_euclid(self.cycle.cycle())];
        let energy = s + self.lifted_at(&folded)?[0];
        let (rest, slope) = self.cycle.inertia_at(&folded)?;
        let j = self.inertia + rest[0];
        let torque = self.cycle.torque_at(&folded, self.gas)?[0] - self.load;
        Ok((
            (2.0 * energy.max(0.0) / j).sqrt(),
            torque - slope[0] * energy / j,
        ))
    }
}

/// The running sums of the period's quadrature.
const LANES: usize = 8;

/// Edges to add to the base panels so that ∫√(J/2E) dφ stays spectrally accurate where
/// E (`energy`, nodes then edges; E'' = `curvature` at the nodes) nearly vanishes:
/// geometric panels (ratio 4) towards every local minimum of E whose complex zeros, at d = √(2E/|E''|) from the real axis, come closer than 1.5
/// half-widths of the widest panel; the innermost panel [φ_i − d/3, φ_i + d/3] (the
/// Python implementation's `grading` and `_near_zeros`). Empty where none does.
pub(crate) fn grading(panels: &Panels, energy: &[f64], curvature: &[f64]) -> Vec<f64> {
    let cycle = panels.cycle();
    let half = panels.widest_half();
    let samples = panels.in_angle_order(energy);
    // The curvature of an edge is that of its panel's first node.
    let mut bend = Vec::with_capacity(samples.len());
    for panel in curvature.chunks_exact(panels.order) {
        bend.push(panel[0]);
        bend.extend_from_slice(panel);
    }
    let count = samples.len();
    let mut extra = Vec::new();
    for i in 0..count {
        let (before, after) = ((i + count - 1) % count, (i + 1) % count);
        let (angle, value) = samples[i];
        if !(value < samples[before].1 && value <= samples[after].1) {
            continue;
        }
        // E'' from the neighbours too: a minimum on an edge has both panels' curvature.
        let bend_here = bend[i].abs().max(bend[before].abs()).max(bend[after].abs());
        let reach = if bend_here > 0.0 {
            (2.0 * value.max(0.0) / bend_here).sqrt()
        } else {
            f64::INFINITY
        };
        // reach is never NaN: value ≥ 0, bend_here > 0 (else ∞).
        if reach >= GRADE_REACH * half {
            continue;
        }
        let width = (reach / (2.0 * GRADE_REACH)).max(1e-12 * cycle);
        let steps = ((2.0 * half / width).ln() / GRADE_RATIO.ln()).ceil() as i32;
        for k in 0..=steps {
            let step = width * GRADE_RATIO.powi(k);
            extra.push((angle - step).rem_euclid(cycle));
            extra.push((angle + step).rem_euclid(cycle));
        }
    }
    extra
}

/// The angle and value of the largest (`largest`) or smallest of a function known at the
/// nodes then edges of `panels` (`values`): the best sample, then the root of its slope
/// (`slope`, any angle) between it and a neighbour sample (Brent's method, to rounding),
/// where the function is evaluated exactly (`value`). Kept only where better than the
/// sample (an extremum at a kink of the slope has no root there).
pub(crate) fn refine_extremum(
    panels: &Panels,
    values: &[f64],
    largest: bool,
    mut slope: impl FnMut(f64) -> Result<f64>,
    mut value: impl FnMut(f64) -> Result<f64>,
) -> Result<(f64, f64)> {
    let cycle = panels.cycle();
    let samples = panels.in_angle_order(values);
    let sign = if largest { 1.0 } else { -1.0 };
    let mut best = 0;
    for (i, sample) in samples.iter().enumerate() {
        if sign * sample.1 > sign * samples[best].1 {
            best = i;
        }
    }
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
    let mut rate = |phi: f64| -> Result<f64> { Ok(sign * slope(phi)?) };
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
        let found = value(root)?;
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
