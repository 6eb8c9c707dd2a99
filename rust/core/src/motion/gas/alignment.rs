//! Where the units of a group fall on one another's indicator panels: what lets their G be
//! summed panel on panel (the gas work's `Summed`). It depends on the panels' edges and the
//! units' phases alone, so designs that differ in r or l share it.

use multiversion::multiversion;

use super::super::quadrature::{MonomialRunning, Panels};

/// How near a panel shifted by a unit's phase must fall on a panel, as a part of Φ, for
/// the units' G to be summed there (the gas work's `Summed`): a few roundings of the angles
/// (the ulp of Φ = 4π is 1.8·10⁻¹⁵ rad), where the look-up of each unit at φ + α itself
/// rounds by one.
pub(super) const ALIGNED: f64 = 4.0 * f64::EPSILON;

/// Where each unit of a group falls on its rule's panels: for panel p shifted by each phase
/// α_j, the panel q it falls on (to [`ALIGNED`]) — it depends on the panels' edges and the
/// phases alone, not on r or l — or, where it falls on none, the unit as a stray of p.
#[derive(Debug, PartialEq)]
pub(super) struct Alignment {
    /// Every unit's panels that fall on panels, in runs (p, q, how many, whole cycles of
    /// α_j + edge p over edge q): unit by unit, p increasing.
    pub(super) runs: Vec<Run>,
    /// The units that do not, panel p's from `first_stray[p]` to `first_stray[p + 1]` (a
    /// few, next to a kink off the steps): each unit's phase and the panel its look-up there
    /// starts from.
    pub(super) first_stray: Vec<usize>,
    pub(super) strays: Vec<(f64, usize)>,
}

/// Panels p… p + count − 1 shifted by a unit's phase: panels q… q + count − 1, `turns`
/// cycles on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Run {
    pub(super) p: usize,
    pub(super) q: usize,
    pub(super) count: usize,
    pub(super) turns: f64,
}

impl Alignment {
    /// `None` where most units fall on no panel (a table or phases off the steps), so that
    /// a sum would save no look-up.
    pub(super) fn new(panels: &Panels, cycle: f64, phases: &[f64]) -> Option<Self> {
        Self::walked(panels, cycle, phases, true)
    }

    /// [`Alignment::new`], each unit's panels walked one by one unless `stretches`: then a
    /// panel that falls on one is followed by all those after it that do ([`aligned_after`]),
    /// the same runs and strays in fewer steps.
    fn walked(panels: &Panels, cycle: f64, phases: &[f64], stretches: bool) -> Option<Self> {
        let edges = &panels.edges;
        let count = panels.count();
        let tolerance = ALIGNED * cycle;
        let mut runs: Vec<Run> = Vec::new();
        // (panel, (phase, where its look-up starts)) of every unit that does not fall on a
        // panel there.
        let mut strays: Vec<(usize, (f64, usize))> = Vec::new();
        for &phase in phases {
            let turns = (phase / cycle).floor();
            let shift = phase - turns * cycle;
            // The panel q that panel p shifted falls on, walked along with p (the one after
            // the last one's), looked for again where it is not.
            let mut next = None;
            let mut hint = 0;
            let mut p = 0;
            while p < count {
                let width = edges[p + 1] - edges[p];
                let (turn, start) = match edges[p] + shift {
                    start if start >= cycle - tolerance => (1.0, start - cycle),
                    start => (0.0, start),
                };
                let fits = |q: usize| {
                    (edges[q] - start).abs() <= tolerance
                        && (edges[q + 1] - (start + width)).abs() <= tolerance
                };
                let q = match next {
                    Some(q) if fits(q) => q,
                    _ => {
                        let middle = (start + 0.5 * width).clamp(0.0, cycle);
                        MonomialRunning::locate(panels, middle, &mut hint).0
                    }
                };
                if fits(q) {
                    let turns = turns + turn;
                    match runs.last_mut() {
                        Some(run)
                            if run.p + run.count == p
                                && run.q + run.count == q
                                && run.turns == turns =>
                        {
                            run.count += 1;
                        }
                        _ => runs.push(Run {
                            p,
                            q,
                            count: 1,
                            turns,
                        }),
                    }
                    // The panels after p that fall on those after q, in the same turn,
                    // all at once: what the steps above find for each of them, one by one.
                    let stretch = if stretches {
                        aligned_after(edges, p, q, shift, turn, cycle, tolerance)
                    } else {
                        0
                    };
                    if let Some(run) = runs.last_mut() {
                        run.count += stretch;
                    }
                    let (p_last, q_last) = (p + stretch, q + stretch);
                    next = Some(if q_last + 1 == count { 0 } else { q_last + 1 });
                    p = p_last;
                } else {
                    // The panel before q: the shifted panel may start just before q's edge.
                    strays.push((p, (phase, q.saturating_sub(1))));
                    next = None;
                    if 2 * strays.len() > count * phases.len() {
                        // Most units fall on no panel: no sum (below), whatever the rest.
                        return None;
                    }
                }
                p += 1;
            }
        }
        if 2 * strays.len() > count * phases.len() {
            return None;
        }
        strays.sort_by_key(|&(p, _)| p);
        let mut first_stray = vec![0; count + 1];
        for &(p, _) in &strays {
            first_stray[p + 1] += 1;
        }
        for p in 0..count {
            first_stray[p + 1] += first_stray[p];
        }
        Some(Self {
            runs,
            first_stray,
            strays: strays.into_iter().map(|(_, stray)| stray).collect(),
        })
    }
}

/// How many of the panels p + 1, p + 2, … (while p + k + 1 ≤ count and q + k + 1 ≤ count − 1)
/// shifted by `shift` (rad) fall on panels q + 1, q + 2, … to `tolerance` (rad) in the same
/// `turn` (0 or 1 cycles back) as panel p on q: each tested as [`Alignment::new`] tests a
/// panel on the one after its last one's, the start e_p + shift (less Φ = `cycle` in the
/// second turn) and its end start + width within the tolerance of q's edges. The walk's
/// common case (every panel of a unit on the steps falls on one), in blocks that compile to
/// vector comparisons (in the widest vectors the machine has: comparisons, one addition and
/// one subtraction a panel, the same at any width).
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq", "x86_64+avx2"))]
fn aligned_after(
    edges: &[f64],
    p: usize,
    q: usize,
    shift: f64,
    turn: f64,
    cycle: f64,
    tolerance: f64,
) -> usize {
    let count = edges.len() - 1;
    // Panels p + k with k ≥ 1 whose q + k is a panel (q + k ≤ count − 1).
    let last = (count - 1 - q).min(count - 1 - p);
    // Whether panel p + k (edges a[0], a[1]) falls on q + k (edges b[0], b[1]).
    let fits = |a: [f64; 2], b: [f64; 2]| {
        let shifted = a[0] + shift;
        let second = shifted >= cycle - tolerance;
        let start = if second { shifted - cycle } else { shifted };
        let width = a[1] - a[0];
        ((if second { 1.0 } else { 0.0 }) == turn)
            & ((b[0] - start).abs() <= tolerance)
            & ((b[1] - (start + width)).abs() <= tolerance)
    };
    const BLOCK: usize = 8;
    let mut k = 1;
    // Blocks of edges as arrays of their length: no bounds check inside, so the block's
    // tests are vector comparisons.
    while k + BLOCK <= last + 1 {
        let a: &[f64; BLOCK + 1] = edges[p + k..p + k + BLOCK + 1].try_into().expect("a block");
        let b: &[f64; BLOCK + 1] = edges[q + k..q + k + BLOCK + 1].try_into().expect("a block");
        let mut all = true;
        for i in 0..BLOCK {
            all &= fits([a[i], a[i + 1]], [b[i], b[i + 1]]);
        }
        if !all {
            break;
        }
        k += BLOCK;
    }
    while k <= last
        && fits(
            [edges[p + k], edges[p + k + 1]],
            [edges[q + k], edges[q + k + 1]],
        )
    {
        k += 1;
    }
    k - 1
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::test_support::Lcg;

    #[test]
    fn stretches_find_the_runs_and_strays_of_the_walk_panel_by_panel() {
        let mut random = Lcg(7);
        let (mut with_runs, mut with_strays) = (0, 0);
        for case in 0..60 {
            let cycle = if case % 2 == 0 { 4.0 * PI } else { 2.0 * PI };
            // A table's steps, the dead centres among them, and in some cases a few cuts
            // off the steps (a kink of a diagram between its breakpoints).
            let steps = [90, 720, 1440][case % 3];
            let step = cycle / steps as f64;
            let mut breaks: Vec<f64> = (0..=steps).map(|i| i as f64 * step).collect();
            for _ in 0..(case % 4) {
                breaks.push(random.next() * cycle);
            }
            breaks.sort_by(f64::total_cmp);
            breaks.dedup();
            let panels = Panels::new(&breaks, 3, if case % 5 == 0 { step / 3.0 } else { 1.0 });
            // Phases on the steps, one cycle on, just off them (within and beyond the
            // tolerance), and anywhere.
            let phases: Vec<f64> = (0..2 + case % 7)
                .map(|j| {
                    let on = (random.next() * steps as f64).floor() * step;
                    match (case + j) % 5 {
                        0 => on + cycle,
                        1 => on + 0.5 * ALIGNED * cycle,
                        2 => on + 3.0 * ALIGNED * cycle,
                        3 => random.next() * cycle,
                        _ => on,
                    }
                })
                .collect();
            let walked = Alignment::walked(&panels, cycle, &phases, false);
            assert_eq!(
                Alignment::walked(&panels, cycle, &phases, true),
                walked,
                "case {case}: phases {phases:?}"
            );
            if let Some(found) = walked {
                with_runs += usize::from(found.runs.iter().any(|run| run.count > 8));
                with_strays += usize::from(!found.strays.is_empty());
            }
        }
        // Both ways through a walk were taken: long runs, and strays among them.
        assert!(
            with_runs > 20 && with_strays > 10,
            "{with_runs} {with_strays}"
        );
    }
}
