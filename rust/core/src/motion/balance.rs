//! The energy method for the "balance" load (docs/theory.md, "Steady running", "Three ways
//! to the periodic solution"): with every torque a function of φ alone,
//!
//!   ω²(φ) = 2[E₀ + K(φ)]/J(φ),  K(φ) = ∫₀^φ (M_gas − M_load) dφ − [U(φ) − U(0)],
//!
//! written E = s + K̃ with K̃ = K − min K ≥ 0 and s > 0 the kinetic energy left at the worst
//! angle; s is the root of (Φ/(t_Φ(s)·ω_m))² − 1, increasing and nearly linear in s.

use std::cell::Cell;
use std::sync::Arc;

use multiversion::multiversion;

use crate::error::Result;

use super::cycle::Cycle;
use super::extrema::{brent, brent_from, grading, local_minima, refine_extrema, Dip, GRADE_REACH};
use super::margin::{Graded, Mesh};
use super::solution::{message, Curves, Periodic, PeriodicSolver, Solution};

/// Refinements of the time mesh before the answer is taken, at most: each grades for the s
/// found on the last, until the mesh no longer grows.
const MESH_ROUNDS: usize = 16;

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
    curvature: Arc<[f64]>,
    /// max |K''| over the nodes (N·m/rad), times (1.5 widest half-widths)²: E's nearest
    /// complex zero is far enough from every base panel where 2s is at least this (J).
    grade_below: f64,
    /// min and max of J − I_w over the samples (kg·m²).
    rest_bounds: (f64, f64),
    /// min K (J): over the samples, then (`dips`) between them.
    k_min: f64,
    /// Where (rad).
    lowest: f64,
    /// The local minima of K̃ located between the samples (once, where first needed; they
    /// do not depend on s): E = s + K̃ dips there.
    dips: Option<Vec<Dip>>,
    /// K̃ = K − min K at the base nodes, then the edges (J). Shared by the copies each solve
    /// works on ([`Balance::with_inertia`]) until one locates a dip below it.
    lifted: Arc<Vec<f64>>,
}

impl Balance {
    /// The energy method on `cycle` with the constant `load` (N·m); `gas`: whether the gas
    /// work is taken (false: gravity and the variation of J alone).
    pub fn new(cycle: &Arc<Cycle>, load: f64, gas: bool) -> Result<Self> {
        let n = cycle.nodes();
        // The nodes' angles, then the edges': a loop over each (one over their chain did
        // not vectorise).
        let mut k: Vec<f64> = Vec::with_capacity(cycle.potential.len());
        for (angles, first) in [(&cycle.panels.phi, 0), (&cycle.panels.edges, n)] {
            let last = first + angles.len();
            let (u, w) = (&cycle.potential[first..last], &cycle.work[first..last]);
            if gas {
                k.extend(
                    angles
                        .iter()
                        .zip(u)
                        .zip(w)
                        .map(|((phi, u), w)| (-u - load * phi) + w),
                );
            } else {
                k.extend(angles.iter().zip(u).map(|(phi, u)| -u - load * phi));
            }
        }
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
            grade_below: curvature.iter().fold(0.0, |m, c| f64::max(m, c.abs()))
                * (GRADE_REACH * cycle.panels.widest_half()).powi(2),
            rest_bounds: cycle
                .rest
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(low, high), &r| {
                    (low.min(r), high.max(r))
                }),
            curvature: curvature.into(),
            k_min,
            lowest: at(lowest),
            dips: None,
            lifted: Arc::new(k.iter().map(|k| k - k_min).collect()),
        })
    }

    /// The same torques on a shaft of inertia I_w = `inertia` (kg·m²): no table is made
    /// again (K and K̃ do not depend on I_w).
    pub fn with_inertia(&self, inertia: f64) -> Self {
        Self {
            inertia,
            ..self.clone()
        }
    }

    /// I_w (kg·m²).
    pub fn inertia(&self) -> f64 {
        self.inertia
    }

    /// Φ (rad).
    pub fn cycle(&self) -> f64 {
        self.cycle.cycle()
    }

    /// The tabulated cycle these torques are set up on.
    pub(super) fn shared_cycle(&self) -> &Arc<Cycle> {
        &self.cycle
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
        graded.as_ref().map_or_else(|| self.base(), Graded::view)
    }

    /// K̃(φ) (J) at any angles in [0, Φ].
    fn lifted_at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        let u = self.cycle.potential_at(phi)?;
        let w = if self.gas {
            self.cycle.work_at(phi)?
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

    /// The local minima of K̃ located exactly, and min K with them: K̃ ≥ 0 also on graded
    /// nodes near it. Once: they do not depend on s.
    fn dips(&mut self) -> Result<&[Dip]> {
        if self.dips.is_none() {
            let cycle = self.cycle.cycle();
            let mut dips =
                local_minima(&self.cycle.panels, &self.lifted, &self.curvature, |phi| {
                    let value = self.lifted_at(&[phi.rem_euclid(cycle)])?[0];
                    Ok((value, self.slope_at(phi)?))
                })?;
            let deepest = dips
                .iter()
                .copied()
                .fold(None, |a: Option<Dip>, d| match a {
                    Some(a) if a.value <= d.value => Some(a),
                    _ => Some(d),
                });
            if let Some(deepest) = deepest.filter(|d| d.value < 0.0) {
                let dip = deepest.value;
                self.k_min += dip;
                Arc::make_mut(&mut self.lifted)
                    .iter_mut()
                    .for_each(|k| *k -= dip);
                dips.iter_mut().for_each(|d| d.value -= dip);
                self.lowest = deepest.angle;
            }
            self.dips = Some(dips);
        }
        Ok(self.dips.as_deref().unwrap_or_default())
    }

    /// The time mesh fit for E = s + K̃: `None` for the base panels, where E's nearest
    /// complex zero, at least √(2s/max|K''|) from the real axis, is far enough from all of
    /// them; else the base panels graded towards E's minima, located exactly.
    fn mesh(&mut self, s: f64) -> Result<Option<Graded>> {
        if 2.0 * s >= self.grade_below {
            return Ok(None);
        }
        let lifted: Vec<Dip> = self
            .dips()?
            .iter()
            .map(|d| Dip {
                value: s + d.value,
                ..*d
            })
            .collect();
        let extra = grading(&self.cycle.panels, lifted);
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

    /// The energy method at the mean speed `omega_mean` (rad/s): a [`PeriodicSolver`].
    pub fn at_speed(&self, omega_mean: f64) -> AtSpeed<'_> {
        AtSpeed {
            balance: self,
            omega_mean,
        }
    }

    /// The periodic solution of mean speed `omega_mean` (rad/s), stalled where it needs
    /// ω_min < `ratio`·ω_m, and where it converged what its curves need
    /// ([`SolvedBalance`]). s by Brent's method on (ω_m(s)/ω_m)² − 1, nearly linear in s,
    /// on a mesh graded for that s (again until the mesh no longer grows).
    pub fn solve_kept(
        mut self,
        omega_mean: f64,
        ratio: f64,
    ) -> Result<(Solution, Option<SolvedBalance>)> {
        let (solution, graded) = self.solve_on_mesh(omega_mean, ratio)?;
        let kept = solution.periodic.map(|periodic| SolvedBalance {
            margin: periodic.margin,
            graded,
            balance: self,
        });
        Ok((solution, kept))
    }

    /// ω(φ) = √(2E/J) with E = s + K̃(φ) evaluated exactly, and t(φ) = ∫₀^φ dφ/ω with each
    /// panel's interpolant of 1/ω through the mesh's nodes integrated exactly
    /// ([`Panels::running_at`](super::quadrature::Panels::running_at)), at `phi` (rad, in [0, Φ]; an angle on an edge is taken on
    /// the panel that starts there).
    fn curves(&self, mesh: Mesh<'_>, s: f64, phi: &[f64]) -> Result<Curves> {
        let lifted = self.lifted_at(phi)?;
        let rest = self.cycle.rest_at(phi)?;
        let omega = speeds(s, self.inertia, &lifted, &rest, false);
        let nodes = mesh.nodes();
        let inverse = speeds(
            s,
            self.inertia,
            &mesh.lifted[..nodes],
            &mesh.rest[..nodes],
            true,
        );
        let time = mesh.panels.running_at(&inverse, phi);
        Ok(Curves { omega, time })
    }

    /// The solution without curves, and the graded mesh the answer was taken on (`None`: the
    /// base panels); the counts are those of the excess (ω_m(s)/ω_m)² − 1 over every round.
    fn solve_on_mesh(&mut self, omega_mean: f64, ratio: f64) -> Result<(Solution, Option<Graded>)> {
        let cycle = Arc::clone(&self.cycle);
        let target = cycle.cycle() / omega_mean;
        // At s_low the speed at the worst angle is at most ratio·ω_m (J there is at least the
        // least J): if the mean speed there is already above the one asked for, the solution
        // has a smaller s, and stalls. Only that: a solution above s_low is judged by its own
        // ω_min (`finish`), so that a speed just above the lowest that runs does run.
        let (rest_min, rest_max) = self.rest_bounds;
        let s_low = 0.5 * (self.inertia + rest_min) * (ratio * omega_mean).powi(2);
        // At s_high, ω² = 2(s + K̃)/J ≥ ω_m² everywhere: the mean speed is at least ω_m.
        let j_max = rest_max + self.inertia;
        let s_high = 0.5 * j_max * omega_mean * omega_mean * 1.01;
        let mut graded = self.mesh(s_high)?;
        let mut s = s_high;
        // t_Φ at the root, where Newton's method took it there.
        let mut period_at_root = None;
        let period = |this: &Self, graded: &Option<Graded>, s: f64| {
            this.view(graded).period(this.inertia, s)
        };
        // Evaluations of the excess, and of them the root finder's.
        let (nfev, nit) = (Cell::new(0), Cell::new(0));
        for _ in 0..MESH_ROUNDS {
            let size = self.view(&graded).nodes();
            let newton = self.view(&graded).newton(self.inertia, target, s_low);
            nfev.set(nfev.get() + newton.evaluations);
            nit.set(nit.get() + newton.evaluations.saturating_sub(1));
            if let Some((root, at_root)) = newton.root {
                s = root;
                period_at_root = Some(at_root);
                let k_min = self.k_min;
                let finer = self.mesh(s)?;
                if self.view(&finer).nodes() <= size && self.k_min == k_min {
                    break;
                }
                graded = finer;
                continue;
            }
            period_at_root = None;
            let excess = |s: f64| -> Result<f64> {
                nfev.set(nfev.get() + 1);
                Ok((target / period(self, &graded, s)).powi(2) - 1.0)
            };
            let at_low = excess(s_low)?;
            if at_low > 0.0 {
                let finer = self.mesh(s_low)?;
                if self.view(&finer).nodes() > size {
                    // Decide on a mesh that resolves the peak at s_low.
                    graded = finer;
                    continue;
                }
                let stall = Solution::stalled(self.lowest, message::CRAWLS);
                return Ok((stall.counted(nfev.get(), nit.get()), graded));
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
            let counted = |s: f64| {
                nit.set(nit.get() + 1);
                excess(s)
            };
            let found = brent_from(counted, (s_low, at_low), (high, at_high), 0.0, 1e-15)?;
            let Some(root) = found else {
                let stall = Solution::stalled(self.lowest, message::NO_ROOT);
                return Ok((stall.counted(nfev.get(), nit.get()), graded));
            };
            s = root;
            let k_min = self.k_min;
            let finer = self.mesh(s)?;
            // Where the mesh located min K between the samples just now, K̃ moved under the
            // s found: solve again on the mesh as it is now.
            if self.view(&finer).nodes() <= size && self.k_min == k_min {
                break;
            }
            graded = finer;
        }
        let solved = self.finish(self.view(&graded), s, ratio, period_at_root)?;
        Ok((solved.counted(nfev.get(), nit.get()), graded))
    }

    /// The periodic solution with E = s + K̃ (its mean speed follows), no stall check: the
    /// search for the lowest running speed goes through stalls.
    fn at_margin(&mut self, s: f64) -> Result<Solution> {
        let graded = self.mesh(s)?;
        self.finish(self.view(&graded), s, 0.0, None)
    }

    /// The lowest mean speed (rad/s) whose solution keeps ω_min ≥ `ratio`·ω_m (the stall
    /// error's min_omega): the root in log s of ω_min/ω_m − ratio, which grows with s
    /// (Brent's method, to 1e-12 in log s; docs/theory.md, "Stall"), rounded up: the mean
    /// speed of the nearest s above the root whose ratio is not short (steps of 1e-12 in
    /// log s, doubling), a speed that runs and within ~1e-11 of the threshold. `above`: an
    /// s (J) known to stall.
    pub fn lowest_running_speed(&mut self, ratio: f64, above: f64) -> Result<f64> {
        // min K located first: K̃, and with it the function whose root is taken, is then the
        // same at every s.
        self.dips()?;
        let swing = self.swing();
        let mut shortfall = |log_s: f64| -> Result<f64> {
            Ok(match self.at_margin(log_s.exp())?.periodic {
                Some(p) => p.omega_min / p.omega_mean - ratio,
                None => -ratio,
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
        let Some(mut log_s) = found else {
            return Ok(f64::NAN);
        };
        // Brent's answer may lie either side of the root: step up to the running side (at
        // most `high`, which runs).
        let mut step = 1e-12;
        while log_s < high && shortfall(log_s)? < 0.0 {
            log_s = (log_s + step).min(high);
            step *= 2.0;
        }
        Ok(self
            .at_margin(log_s.exp())?
            .periodic
            .map_or(f64::NAN, |p| p.omega_mean))
    }

    /// max − min (J) of the textbook turning-moment diagram's energy at the constant speed
    /// ω_m = `omega_mean` (rad/s): ∫(M_gas − U′ − M_load − ½J′ω_m²) dφ = K − ½ω_m²(J − J(0)),
    /// both extremes located between the samples and evaluated exactly — the ΔE of the
    /// textbook flywheel estimate (docs/theory.md, "The flywheel"). The inertia
    /// torque is part of it: without it the estimate does not tend to the exact flywheel as
    /// δ → 0.
    pub fn energy_swing(&self, omega_mean: f64) -> Result<f64> {
        let half_square = 0.5 * omega_mean * omega_mean;
        let cycle = &self.cycle;
        let diagram: Vec<f64> = self
            .lifted
            .iter()
            .zip(&cycle.rest)
            .map(|(k, rest)| k - half_square * rest)
            .collect();
        let exact = |phi: f64| -> Result<(f64, f64)> {
            let folded = [phi.rem_euclid(cycle.cycle())];
            let (rest, slope) = cycle.inertia_at(&folded)?;
            Ok((
                self.lifted_at(&folded)?[0] - half_square * rest[0],
                self.slope_at(phi)? - half_square * slope[0],
            ))
        };
        let [(_, top), (_, bottom)] = refine_extrema(&cycle.panels, &diagram, exact)?;
        let (most, least) = diagram
            .iter()
            .fold((f64::NEG_INFINITY, f64::INFINITY), |(a, b), &d| {
                (a.max(d), b.min(d))
            });
        Ok(top.max(most) - bottom.min(least))
    }

    /// t_Φ, ω_m and the extremes of ω for E = s + K̃ on a mesh (t_Φ = `period` where it
    /// was taken at this s already).
    fn finish(&self, mesh: Mesh<'_>, s: f64, ratio: f64, period: Option<f64>) -> Result<Solution> {
        let cycle = &self.cycle;
        let panels = mesh.panels;
        let n = mesh.nodes();
        // ω² at the samples: its extremes are ω's, and the square root is taken only of them.
        let square: Vec<f64> = mesh
            .rest
            .iter()
            .zip(mesh.lifted)
            .map(|(rest, k)| 2.0 * (s + k).max(0.0) / (self.inertia + rest))
            .collect();
        if let Some(i) = square.iter().position(|&w| w <= 0.0) {
            let angle = if i < n {
                panels.phi[i]
            } else {
                panels.edges[i - n]
            };
            return Ok(Solution::stalled(angle, message::STOPS));
        }
        let period = period.unwrap_or_else(|| {
            let inverse = square[..n].iter().map(|w| 1.0 / w.sqrt());
            panels.weights.iter().zip(inverse).map(|(w, f)| w * f).sum()
        });
        let omega_mean = cycle.cycle() / period;
        let [(phi_max, top), (phi_min, bottom)] =
            refine_extrema(panels, &square, |phi| self.speed_squared(s, phi))?;
        let (omega_max, omega_min) = (top.sqrt(), bottom.sqrt());
        let solution = Periodic {
            omega_mean,
            period,
            omega_max,
            omega_min,
            phi_max: phi_max.rem_euclid(cycle.cycle()),
            phi_min: phi_min.rem_euclid(cycle.cycle()),
            margin: s,
            energy_at_zero: s - self.k_min,
        }
        .mean_inside();
        if omega_min < ratio * omega_mean {
            return Ok(Solution::stalled(solution.phi_min, message::CRAWLS));
        }
        Ok(Solution {
            mean_load: self.load,
            ..Solution::converged(solution, message::ROOT_FOUND)
        })
    }

    /// ω(φ)² = 2E/J and its slope 2Jφ̈/J exactly, with the net torque J φ̈ = M_gas − U′ −
    /// M_load − ½J′ω², whose roots are the extremes of ω.
    fn speed_squared(&self, s: f64, phi: f64) -> Result<(f64, f64)> {
        let folded = [phi.rem_euclid(self.cycle.cycle())];
        let energy = s + self.lifted_at(&folded)?[0];
        let (rest, slope) = self.cycle.inertia_at(&folded)?;
        let j = self.inertia + rest[0];
        let torque = self.cycle.torque_at(&folded, self.gas)?[0] - self.load;
        let square = 2.0 * energy.max(0.0) / j;
        Ok((square, 2.0 * (torque - slope[0] * energy / j) / j))
    }
}

/// The energy method of a [`Balance`] at a mean speed ω_m (rad/s): the steady state of any
/// shaft inertia there ([`Balance::at_speed`]). Each solve works on a fresh copy of the
/// set-up with that inertia ([`Balance::with_inertia`]): a copy that has located its minima
/// already rounds differently.
pub(crate) struct AtSpeed<'b> {
    balance: &'b Balance,
    omega_mean: f64,
}

impl PeriodicSolver for AtSpeed<'_> {
    fn solve(&self, shaft_inertia: f64, ratio: f64, phi: Option<&[f64]>) -> Result<Solution> {
        let (mut solution, kept) = self
            .balance
            .with_inertia(shaft_inertia)
            .solve_kept(self.omega_mean, ratio)?;
        if let (Some(phi), Some(kept)) = (phi, kept) {
            solution.curves = Some(kept.curves(phi)?);
        }
        Ok(solution)
    }
}

/// A converged solve of the energy method, kept for its curves: the copy of the set-up it
/// was solved on (with the minima it located), the mesh it was graded to and its margin s.
/// ω and t at any angles later cost no second solve, and are the doubles the solve would
/// have given with those angles.
#[derive(Debug, Clone)]
pub(crate) struct SolvedBalance {
    balance: Balance,
    graded: Option<Graded>,
    margin: f64,
}

impl SolvedBalance {
    /// Φ (rad).
    pub fn cycle(&self) -> f64 {
        self.balance.cycle()
    }

    /// ω(φ) (rad/s) and t(φ) (s, from φ = 0) at `phi` (rad, each in [0, Φ]), as
    /// [`Balance::curves`] gives them.
    pub fn curves(&self, phi: &[f64]) -> Result<Curves> {
        if phi.is_empty() {
            return Ok(Curves {
                omega: Vec::new(),
                time: Vec::new(),
            });
        }
        let balance = &self.balance;
        balance.curves(balance.view(&self.graded), self.margin, phi)
    }
}

/// ω = √(2·max(s + K̃, 0)/(I_w + J − I_w)) (rad/s) at each point of `lifted` (K̃) and `rest`
/// (J − I_w), or 1/ω where `inverse`; in the widest vectors the machine has (a square root
/// and a division round correctly at any width: the same doubles).
#[multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn speeds(s: f64, inertia: f64, lifted: &[f64], rest: &[f64], inverse: bool) -> Vec<f64> {
    let mut out = vec![0.0; lifted.len().min(rest.len())];
    for ((out, k), rest) in out.iter_mut().zip(lifted).zip(rest) {
        let omega = (2.0 * (s + k).max(0.0) / (inertia + rest)).sqrt();
        *out = if inverse { 1.0 / omega } else { omega };
    }
    out
}
