//! The gas work W(φ) = ∫₀^φ M_gas dφ of a machine, exact at every φ: each cylinder's
//! indicator work G at phase 0 integrated on panels cut at every breakpoint of its tables
//! (the room's doc, `gas`), and W the sum of the units' G at their phases.

use std::f64::consts::PI;
use std::sync::{Arc, OnceLock};

use crate::dynamics::Dynamics;
use crate::error::Result;
use crate::mechanism::PhysicalCylinder;
use crate::parallel::Parallelism;
use crate::trig::sincos_table;

use super::super::quadrature::{breaks, MonomialRunning, PanelShift, Panels};
use super::alignment::Alignment;
use super::{periodic, GasCylinder, PiecewisePolynomial};

/// F of one cylinder at phase 0 at every θ (rad) of `theta`, in increasing order, θ taken
/// modulo the cycle, in runs of `run` angles each within one piece of every table (a rule's
/// panels: each table's values in one walk, [`PiecewisePolynomial::values_in_runs`]).
fn one_cylinder_forces(
    cylinder: GasCylinder,
    diagrams: &[PiecewisePolynomial],
    cycle: f64,
    theta: &[f64],
    run: usize,
) -> Vec<f64> {
    let mut forces = vec![0.0; theta.len()];
    if !cylinder.has_gas() {
        return forces;
    }
    // The head's pressures are laid where its forces go, and turned into them there (one
    // table of 10⁴ doubles, not three, for a rule's nodes).
    let folded: Vec<f64>;
    let angles = if theta.iter().all(|t| (0.0..cycle).contains(t)) {
        theta // periodic leaves them as they are
    } else {
        folded = theta.iter().map(|&t| periodic(t, cycle)).collect();
        &folded
    };
    let crank_end = cylinder.crank_end.map(|d| {
        let mut p = vec![0.0; angles.len()];
        diagrams[d].values_in_runs(angles, run, &mut p);
        p
    });
    if let Some(d) = cylinder.head {
        diagrams[d].values_in_runs(angles, run, &mut forces);
    }
    let head = cylinder.head.is_some();
    for (k, force) in forces.iter_mut().enumerate() {
        let crank_end = crank_end.as_ref().map(|p| p[k]);
        *force = cylinder.net_force(head.then_some(*force), crank_end);
    }
    forces
}

/// Gauss points per panel of an indicator's interpolant of F·s′, F one polynomial of K
/// coefficients (`pressure_order`) on every panel, the widest `widest` (rad) wide: m = K + d
/// nodes take F times s′ to degree d exactly, d the least (at most 4) whose Taylor rest of
/// s′, (h/2)^(d+1)/(d+1)!, is at most that of degree 4 on a panel of the widest width π/64,
/// (π/128)⁵/5! — the resolution of s′ the Gauss rule of K + 3 degrees integrated before.
/// Tables of half a degree or less take d = 3. Integrated exactly from the panel's edge, the
/// interpolant gives G at every x.
fn indicator_order(pressure_order: usize, widest: f64) -> usize {
    let rest = |d: usize, h: f64| (1..=d + 1).fold(1.0, |r, k| r * 0.5 * h / k as f64);
    let bound = rest(4, INDICATOR_WIDTH);
    let d = (1..4).find(|&d| rest(d, widest) <= bound).unwrap_or(4);
    pressure_order + d
}

/// The widest panel of an indicator rule (rad) (a table interval wider than this is split).
const INDICATOR_WIDTH: f64 = PI / 64.0;

/// Angles W is looked up at side by side ([`MonomialRunning::at_lanes`]).
const LANES: usize = 8;

/// What of one cylinder's indicator rule its crank radius and rod length do not change:
/// the panels, cut at every breakpoint of its tables and at its dead centres (kπ), at most
/// π/64 wide, and F at their Gauss nodes. Shared by designs that differ in r or l alone.
#[derive(Debug)]
struct Rule {
    cycle: f64,
    panels: Panels,
    /// F (N) at every node of `panels`.
    forces: Vec<f64>,
    /// What F depends on besides the tables: the cylinder's tables, bore and piston rod.
    key: RuleKey,
    /// (sin φ, cos φ) at the nodes, made when a second machine takes the rule (a machine
    /// alone has its kernel make them, without keeping 2 × 10⁴ doubles).
    trig: OnceLock<(Vec<f64>, Vec<f64>)>,
}

/// A cylinder's tables (head, crank end) and its areas' bits (bore, piston rod diameter).
type RuleKey = (Option<usize>, Option<usize>, [u64; 2]);

impl Rule {
    fn key(gas: &GasCylinder) -> RuleKey {
        (
            gas.head,
            gas.crank_end,
            [gas.bore.to_bits(), gas.piston_rod_diameter.to_bits()],
        )
    }

    fn new(gas: GasCylinder, diagrams: &[PiecewisePolynomial], cycle: f64) -> Self {
        let tables: Vec<&PiecewisePolynomial> = [gas.head, gas.crank_end]
            .into_iter()
            .flatten()
            .map(|d| &diagrams[d])
            .collect();
        // The tables' breakpoints folded into the cycle (`periodic`: rem_euclid's doubles,
        // without its division), each table's a sorted run turned at its fold, then the
        // dead centres put in their places: sorted as made, so `breaks` need not sort them.
        let mut angles: Vec<f64> = Vec::new();
        for table in &tables {
            let folded = table.breakpoints().iter().map(|&x| periodic(x, cycle));
            if angles.is_empty() {
                angles.extend(folded);
                let turn = angles
                    .windows(2)
                    .position(|p| p[1] < p[0])
                    .map_or(0, |i| i + 1);
                angles.rotate_left(turn);
            } else {
                angles.extend(folded);
            }
        }
        for k in 0..=(cycle / PI).round() as usize {
            let centre = k as f64 * PI;
            let at = angles.partition_point(|&a| a.total_cmp(&centre).is_le());
            angles.insert(at, centre);
        }
        let order = tables.iter().map(|t| t.order()).max().unwrap_or(1);
        let cuts = breaks(angles, cycle);
        // The widest panel: a piece between cuts in equal panels no wider than the width.
        let widest = cuts.windows(2).fold(0.0, |m: f64, pair| {
            let width = pair[1] - pair[0];
            m.max(width / (width / INDICATOR_WIDTH).ceil().max(1.0))
        });
        let panels = Panels::new(&cuts, indicator_order(order, widest), INDICATOR_WIDTH);
        let forces = one_cylinder_forces(gas, diagrams, cycle, &panels.phi, panels.order);
        Self {
            cycle,
            panels,
            forces,
            key: Self::key(&gas),
            trig: OnceLock::new(),
        }
    }

    /// (sin φ, cos φ) at the nodes, made on first use.
    fn trig(&self) -> &(Vec<f64>, Vec<f64>) {
        self.trig.get_or_init(|| sincos_table(&self.panels.phi))
    }
}

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

    /// (t, y) with x = φ + `phase` = t·Φ + y, y ∈ [0, Φ): t by floor(x/Φ), where the two
    /// usual cases need no call of floor (not inlined on baseline x86-64) and give the same
    /// doubles.
    #[inline]
    fn turns_and_angle(&self, angle: f64, phase: f64) -> (f64, f64) {
        let (x, cycle) = (angle + phase, self.rule.cycle);
        if (0.0..cycle).contains(&x) && x / cycle < 1.0 {
            (0.0, x)
        } else if (cycle..2.0 * cycle).contains(&x) && (1.0..2.0).contains(&(x / cycle)) {
            (1.0, x - cycle)
        } else {
            let t = (x / cycle).floor();
            (t, x - t * cycle)
        }
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
    /// it ([`Indicator::add`]).
    fn add(&self, phi: &[f64], work: &mut [f64], mut slope: Option<&mut [f64]>) {
        let Some(summed) = &self.summed else {
            for &phase in &self.phases {
                self.indicator.add(phi, phase, work, slope.as_deref_mut());
            }
            return;
        };
        let indicator = &self.indicator;
        let panels = &indicator.rule.panels;
        let mut hint = 0;
        // LANES angles at a time, their Horner chains side by side (at_panel's and
        // slope_at_panel's doubles), each lane's strays, if any, added to it alone.
        let whole = phi.len() / LANES * LANES;
        for first in (0..whole).step_by(LANES) {
            let (mut turns, mut y) = ([0.0; LANES], [0.0; LANES]);
            for l in 0..LANES {
                (turns[l], y[l]) = indicator.turns_and_angle(phi[first + l], 0.0);
            }
            let (p, x) = MonomialRunning::locate_lanes(panels, &y, &mut hint);
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
            let angle = indicator.turns_and_angle(phi[k], 0.0);
            let at = MonomialRunning::locate(panels, angle.1, &mut hint);
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
            group.add(phi, &mut total, None);
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
            group.add(&phi[..sloped], head, Some(&mut slope));
            group.add(&phi[sloped..], tail, None);
        }
        (total, slope)
    }
}
