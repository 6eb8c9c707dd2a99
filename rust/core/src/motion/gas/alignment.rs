//! Where the units of a group fall on one another's indicator panels: what lets their G be
//! summed panel on panel (the gas work's `Summed`). It depends on the panels' edges and the
//! units' phases alone, so designs that differ in r or l share it.

use super::super::quadrature::{MonomialRunning, Panels};

/// How near a panel shifted by a unit's phase must fall on a panel, as a part of Φ, for
/// the units' G to be summed there (the gas work's `Summed`): a few roundings of the angles
/// (the ulp of Φ = 4π is 1.8·10⁻¹⁵ rad), where the look-up of each unit at φ + α itself
/// rounds by one.
pub(super) const ALIGNED: f64 = 4.0 * f64::EPSILON;

/// Where each unit of a group falls on its rule's panels: for panel p shifted by each phase
/// α_j, the panel q it falls on (to [`ALIGNED`]) — it depends on the panels' edges and the
/// phases alone, not on r or l — or, where it falls on none, the unit as a stray of p.
#[derive(Debug)]
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
#[derive(Debug, Clone, Copy)]
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
            for p in 0..count {
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
                    next = Some(if q + 1 == count { 0 } else { q + 1 });
                } else {
                    // The panel before q: the shifted panel may start just before q's edge.
                    strays.push((p, (phase, q.saturating_sub(1))));
                    next = None;
                }
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
