//! The gas work W(φ) = ∫₀^φ M_gas dφ of a machine, exact at every φ: each cylinder's
//! indicator work G at phase 0 integrated on panels cut at every breakpoint of its tables
//! (the room's doc, `gas`), and W the sum of the units' G at their phases.

use std::sync::Arc;

use crate::dynamics::Dynamics;
use crate::error::Result;
use crate::mechanism::PhysicalCylinder;
use crate::parallel::Parallelism;

use super::super::quadrature::{MonomialRunning, PanelShift};
use super::alignment::Alignment;
use super::rule::{Rule, RuleKey};
use super::{GasCylinder, PiecewisePolynomial};

/// Angles W is looked up at side by side ([`MonomialRunning::at_lanes`]).
const LANES: usize = 8;

/// G(x) = ∫₀^x F(θ) s'(θ) dθ of one cylinder at phase 0 (J), for any real x: F·s′ on the
/// panels of its [`Rule`], its interpolant through each panel's Gauss nodes integrated
/// exactly ([`MonomialRunning`]).
#[derive(Debug, Clone)]
struct Indicator {
    rule: Arc<Rule>,
    /// G and (F·s′)′ on every panel, in monomials for the many look-ups of W.
    running: MonomialRunning,
}

impl Indicator {
    /// On `rule` (made for this cylinder's tables and areas), with the unit's r and l.
    fn new(unit: &PhysicalCylinder, rule: Arc<Rule>) -> Result<Self> {
        let alone = PhysicalCylinder {
            phase: 0.0,
            ..*unit
        };
        let dynamics = Dynamics::new(&[alone], 0.0)?;
        let phi = &rule.panels.phi;
        let mut torque = vec![0.0; phi.len()];
        match rule.trig.get() {
            Some((sin, cos)) => {
                dynamics.gas_torque_on_table(sin, cos, &rule.forces, &mut torque)?
            }
            None => dynamics.gas_torque(phi, &rule.forces, &mut torque, Parallelism::SERIAL)?,
        }
        let running = MonomialRunning::through(&rule.panels, &torque);
        Ok(Self { rule, running })
    }

    fn per_cycle(&self) -> f64 {
        self.running.at_edges[self.running.at_edges.len() - 1]
    }

    /// [`Rule::turns_and_angle`].
    #[inline]
    fn turns_and_angle(&self, angle: f64, phase: f64) -> (f64, f64) {
        self.rule.turns_and_angle(angle, phase)
    }

    /// G(φ + `phase`) added to `work` for each φ of `phi`; with `slope`, G″ = (F·s′)′
    /// (N·m/rad) there, the slope of the interpolant G integrates, added to it (one panel
    /// look-up for both). φ + phase in increasing order walks the panels.
    fn add(&self, phi: &[f64], phase: f64, work: &mut [f64], slope: Option<&mut [f64]>) {
        let per_cycle = self.per_cycle();
        let mut hint = 0;
        let (panels, running) = (&self.rule.panels, &self.running);
        match slope {
            None => {
                // LANES angles at a time: their Horner chains side by side (the same doubles).
                let mut whole = work.chunks_exact_mut(LANES);
                let mut angles = phi.chunks_exact(LANES);
                for (w, p) in (&mut whole).zip(&mut angles) {
                    let (mut turns, mut y) = ([0.0; LANES], [0.0; LANES]);
                    for l in 0..LANES {
                        (turns[l], y[l]) = self.turns_and_angle(p[l], phase);
                    }
                    let g = running.at_lanes(panels, &y, &mut hint);
                    for l in 0..LANES {
                        w[l] += turns[l] * per_cycle + g[l];
                    }
                }
                for (w, &p) in whole.into_remainder().iter_mut().zip(angles.remainder()) {
                    *w += self.at_one(p, phase, &mut hint, None);
                }
            }
            Some(slope) => {
                for ((w, s), &p) in work.iter_mut().zip(slope.iter_mut()).zip(phi) {
                    *w += self.at_one(p, phase, &mut hint, Some(s));
                }
            }
        }
    }

    /// G(y + `phase`) and, with `slope`, G″ there added to it: one unit at one angle, its
    /// panel looked for from `hint`.
    #[inline]
    fn at_one(&self, y: f64, phase: f64, hint: &mut usize, slope: Option<&mut f64>) -> f64 {
        let (t, x) = self.turns_and_angle(y, phase);
        let at_turn = t * self.per_cycle();
        match slope {
            None => at_turn + self.running.at_near(&self.rule.panels, x, hint),
            Some(slope) => {
                let (g, g2) = self.running.at_and_slope_near(&self.rule.panels, x, hint);
                *slope += g2;
                at_turn + g
            }
        }
    }

    /// G(x) for each x.
    fn at(&self, x: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; x.len()];
        self.add(x, 0.0, &mut out, None);
        out
    }
}

/// Σ_j G(x + α_j) of a group's units on their indicator's panels, wherever panel p shifted
/// by every α_j is a panel (to `ALIGNED`) — the usual case: a table of equal steps, and
/// firing intervals and bank angles whole multiples of the step. There the units'
/// polynomials, in the same x across the panel, add coefficient by coefficient: W is one
/// look-up for the group where it was one per unit. Elsewhere (a kink of the table off the
/// steps, a phase between edges) the units are looked up one by one.
#[derive(Debug, Clone)]
struct Summed {
    /// The sum over the units that fall on panels, on each panel.
    running: MonomialRunning,
    /// Where they fall, and the units that do not.
    alignment: Arc<Alignment>,
    /// The group's indicated work of one cycle (J).
    per_cycle: f64,
}

impl Summed {
    /// The `units` of `alignment` summed on `indicator` (made on the rule it was found on).
    fn new(indicator: &Indicator, alignment: Arc<Alignment>, units: usize) -> Self {
        let per_cycle = indicator.per_cycle();
        let shifts: Vec<PanelShift> = alignment
            .runs
            .iter()
            .map(|run| PanelShift {
                p: run.p,
                q: run.q,
                count: run.count,
                at_edge: run.turns * per_cycle,
            })
            .collect();
        let mut running = indicator.running.sum_of_shifts(&shifts);
        let count = indicator.rule.panels.count();
        let units = units as f64;
        running.at_edges[count] = running.at_edges[0] + units * per_cycle;
        Self {
            running,
            alignment,
            per_cycle: units * per_cycle,
        }
    }

    /// Σ_j G(φ + α_j) at one angle given as (t, y) and its panel (p, x), and with `slope`
    /// Σ_j G″ added to it.
    #[inline]
    fn at(
        &self,
        indicator: &Indicator,
        (t, y): (f64, f64),
        (p, x): (usize, f64),
        mut slope: Option<&mut f64>,
    ) -> f64 {
        let mut value = t * self.per_cycle + self.running.at_panel(p, x);
        if let Some(slope) = slope.as_deref_mut() {
            *slope += self.running.slope_at_panel(&indicator.rule.panels, p, x);
        }
        self.add_strays(indicator, y, p, &mut value, slope);
        value
    }

    /// The units that stray on panel `p` (each looked up alone at `y` + its phase) added
    /// to `value`, and with `slope` their G″ to it.
    #[inline]
    fn add_strays(
        &self,
        indicator: &Indicator,
        y: f64,
        p: usize,
        value: &mut f64,
        mut slope: Option<&mut f64>,
    ) {
        let Alignment {
            first_stray,
            strays,
            ..
        } = &*self.alignment;
        for &(phase, mut hint) in &strays[first_stray[p]..first_stray[p + 1]] {
            *value += indicator.at_one(y, phase, &mut hint, slope.as_deref_mut());
        }
    }

    fn has_strays(&self, p: usize) -> bool {
        let first_stray = &self.alignment.first_stray;
        first_stray[p] != first_stray[p + 1]
    }
}

/// Units alike in all that G depends on: their indicator rule, their phases (rad) and, for
/// more than one, their sum.
#[derive(Debug, Clone)]
struct Group {
    indicator: Indicator,
    phases: Vec<f64>,
    summed: Option<Summed>,
}

impl Group {
    /// Σ_j G(φ + α_j) added to `work` for each φ of `phi`, and with `slope` Σ_j G″ added to
    /// it ([`Indicator::add`]); with `keep`, where `phi` falls on a shared rule's panels is
    /// kept for (or taken from) the machines that share it ([`Rule::located`]).
    fn add(&self, phi: &[f64], work: &mut [f64], mut slope: Option<&mut [f64]>, keep: bool) {
        let Some(summed) = &self.summed else {
            for &phase in &self.phases {
                self.indicator.add(phi, phase, work, slope.as_deref_mut());
            }
            return;
        };
        let indicator = &self.indicator;
        let panels = &indicator.rule.panels;
        let located = keep.then(|| indicator.rule.located(phi)).flatten();
        let mut hint = 0;
        // LANES angles at a time, their Horner chains side by side (at_panel's and
        // slope_at_panel's doubles), each lane's strays, if any, added to it alone.
        let whole = phi.len() / LANES * LANES;
        for first in (0..whole).step_by(LANES) {
            let (turns, y, p, x) = match &located {
                Some(l) => {
                    let lanes = first..first + LANES;
                    let take = |v: &[f64]| -> [f64; LANES] {
                        v[lanes.clone()].try_into().expect("LANES angles")
                    };
                    let p = l.p[lanes.clone()].try_into().expect("LANES angles");
                    (take(&l.turns), take(&l.y), p, take(&l.x))
                }
                None => {
                    let (mut turns, mut y) = ([0.0; LANES], [0.0; LANES]);
                    for l in 0..LANES {
                        (turns[l], y[l]) = indicator.turns_and_angle(phi[first + l], 0.0);
                    }
                    let (p, x) = MonomialRunning::locate_lanes(panels, &y, &mut hint);
                    (turns, y, p, x)
                }
            };
            let g = summed.running.at_panels(&p, &x);
            let mut slopes = slope.as_deref_mut().map(|slope| {
                let lanes = summed.running.slope_at_panels(panels, &p, &x);
                let slope = &mut slope[first..first + LANES];
                slope.iter_mut().zip(lanes).for_each(|(s, lane)| *s += lane);
                slope
            });
            for l in 0..LANES {
                let mut value = turns[l] * summed.per_cycle + g[l];
                if summed.has_strays(p[l]) {
                    let lane = slopes.as_deref_mut().map(|s| &mut s[l]);
                    summed.add_strays(indicator, y[l], p[l], &mut value, lane);
                }
                work[first + l] += value;
            }
        }
        for k in whole..phi.len() {
            let (angle, at) = match &located {
                Some(l) => ((l.turns[k], l.y[k]), (l.p[k], l.x[k])),
                None => {
                    let angle = indicator.turns_and_angle(phi[k], 0.0);
                    (angle, MonomialRunning::locate(panels, angle.1, &mut hint))
                }
            };
            let lane = slope.as_deref_mut().map(|s| &mut s[k]);
            work[k] += summed.at(indicator, angle, at, lane);
        }
    }
}

/// W(φ) = ∫₀^φ M_gas dφ of a machine (J).
#[derive(Debug, Clone)]
pub(crate) struct GasWork {
    /// One G per distinct cylinder, with the phases of the units that share it.
    groups: Vec<Group>,
    /// The tables the rules' forces are of.
    diagrams: Arc<[PiecewisePolynomial]>,
    origin: f64,
    /// W(Φ), the indicated work of one cycle (J).
    pub per_cycle: f64,
}

impl GasWork {
    /// W of the machine of `units` and `gas`, its pressures `diagrams`; with `like`,
    /// another machine's W whose rules (panels and F at their nodes) and alignments are
    /// taken where a group's tables, areas and phases are the same as one of its own —
    /// designs that differ only in r or l share all but F·s′ and its interpolants.
    pub fn new(
        units: &[PhysicalCylinder],
        gas: &[GasCylinder],
        diagrams: Arc<[PiecewisePolynomial]>,
        cycle: f64,
        like: Option<&GasWork>,
    ) -> Result<Self> {
        // Units alike in all that G depends on: the same diagrams, areas, r and l.
        let mut keys: Vec<(RuleKey, [u64; 2])> = Vec::new();
        let mut members: Vec<(usize, Vec<f64>)> = Vec::new();
        for (j, (unit, cylinder)) in units.iter().zip(gas).enumerate() {
            if !cylinder.has_gas() {
                continue;
            }
            let key = (
                Rule::key(cylinder),
                [unit.crank_radius.to_bits(), unit.rod_length.to_bits()],
            );
            match keys.iter().position(|k| *k == key) {
                Some(g) => members[g].1.push(unit.phase),
                None => {
                    keys.push(key);
                    members.push((j, vec![unit.phase]));
                }
            }
        }
        // The groups of `like` on the same tables and areas.
        let alike = |key: &RuleKey| -> Vec<&Group> {
            let Some(like) = like else {
                return Vec::new();
            };
            let (head, crank_end, _) = *key;
            let equal = |d: Option<usize>| d.is_none_or(|d| like.diagrams[d] == diagrams[d]);
            let same = Arc::ptr_eq(&like.diagrams, &diagrams) || (equal(head) && equal(crank_end));
            if !same {
                return Vec::new();
            }
            like.groups
                .iter()
                .filter(|g| g.indicator.rule.key == *key)
                .collect()
        };
        let mut groups = Vec::with_capacity(members.len());
        for (j, phases) in members {
            let found = alike(&Rule::key(&gas[j]));
            // A rule taken from another machine: its nodes' sines and cosines made once, for
            // this machine and every later one (a sweep's designs along r or l).
            let rule = found.first().map(|g| {
                g.indicator.rule.trig();
                Arc::clone(&g.indicator.rule)
            });
            // Its phases' alignment, where a group alike has the same phases.
            let alignment = found
                .iter()
                .find(|g| g.phases == phases)
                .map(|g| g.summed.as_ref().map(|s| Arc::clone(&s.alignment)));
            let rule = rule.unwrap_or_else(|| Arc::new(Rule::new(gas[j], &diagrams, cycle)));
            let alignment = match alignment {
                Some(found) => found,
                None => (phases.len() > 1)
                    .then(|| Alignment::new(&rule.panels, rule.cycle, &phases).map(Arc::new))
                    .flatten(),
            };
            let indicator = Indicator::new(&units[j], rule)?;
            let summed = alignment.map(|a| Summed::new(&indicator, a, phases.len()));
            groups.push(Group {
                indicator,
                phases,
                summed,
            });
        }
        let per_cycle = groups
            .iter()
            .map(|g| g.indicator.per_cycle() * g.phases.len() as f64)
            .sum();
        let mut origin = 0.0;
        for g in &groups {
            origin += g.indicator.at(&g.phases).iter().sum::<f64>();
        }
        Ok(Self {
            groups,
            diagrams,
            origin,
            per_cycle,
        })
    }

    /// How many units are looked up one by one, over all panels, in each group that sums
    /// its units (`None` for a group that does not).
    #[cfg(test)]
    pub(super) fn strays(&self) -> Vec<Option<usize>> {
        self.groups
            .iter()
            .map(|g| g.summed.as_ref().map(|s| s.alignment.strays.len()))
            .collect()
    }

    /// How many of its groups hold a rule, and how many an alignment, of `other`'s.
    #[cfg(test)]
    pub(super) fn shared_with(&self, other: &GasWork) -> (usize, usize) {
        let theirs = |mine: &Group| {
            other.groups.iter().fold((false, false), |(r, a), g| {
                let alignments = mine.summed.as_ref().zip(g.summed.as_ref());
                (
                    r || Arc::ptr_eq(&mine.indicator.rule, &g.indicator.rule),
                    a || alignments.is_some_and(|(m, t)| Arc::ptr_eq(&m.alignment, &t.alignment)),
                )
            })
        };
        self.groups
            .iter()
            .map(theirs)
            .fold((0, 0), |(r, a), (mr, ma)| {
                (r + usize::from(mr), a + usize::from(ma))
            })
    }

    /// W at each φ.
    pub fn at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        let mut total = vec![-self.origin; phi.len()];
        for group in &self.groups {
            group.add(phi, &mut total, None, false);
        }
        Ok(total)
    }

    /// W at each φ of `phi`, and W″ = M_gas′ (N·m/rad) at its first `sloped` angles: the sum
    /// of the units' G″ at their phases, the slopes of their indicator rules' interpolants of
    /// F·s′ (exact where the rule is), found in the same look-up as W.
    pub fn with_slope_at(&self, phi: &[f64], sloped: usize) -> (Vec<f64>, Vec<f64>) {
        let mut total = vec![-self.origin; phi.len()];
        let mut slope = vec![0.0; sloped];
        let (head, tail) = total.split_at_mut(sloped);
        for group in &self.groups {
            group.add(&phi[..sloped], head, Some(&mut slope), true);
            group.add(&phi[sloped..], tail, None, true);
        }
        (total, slope)
    }
}
