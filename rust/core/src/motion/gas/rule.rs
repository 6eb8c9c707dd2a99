//! An indicator rule: the panels of one cylinder's indicator work cut at every breakpoint
//! of its pressure tables, with the piston forces at their nodes — all that its crank
//! radius and rod length do not change, so that designs differing in r or l share it.

use std::f64::consts::PI;
use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use crate::trig::sincos_table;

use super::super::quadrature::{breaks, MonomialRunning, Panels};
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

/// What of one cylinder's indicator rule its crank radius and rod length do not change:
/// the panels, cut at every breakpoint of its tables and at its dead centres (kπ), at most
/// π/64 wide, and F at their Gauss nodes. Shared by designs that differ in r or l alone.
#[derive(Debug)]
pub(super) struct Rule {
    pub(super) cycle: f64,
    pub(super) panels: Panels,
    /// F (N) at every node of `panels`.
    pub(super) forces: Vec<f64>,
    /// What F depends on besides the tables: the cylinder's tables, bore and piston rod.
    pub(super) key: RuleKey,
    /// (sin φ, cos φ) at the nodes, made when a second machine takes the rule (a machine
    /// alone has its kernel make them, without keeping 2 × 10⁴ doubles).
    pub(super) trig: OnceLock<(Vec<f64>, Vec<f64>)>,
    /// Where the angles of the last few tables of W asked of a rule that machines share
    /// fall on its panels: a sweep's designs along r or l ask W at the same cycle nodes,
    /// each design found them again (half of looking W up there).
    located: Mutex<Vec<Arc<Located>>>,
}

/// How many tables' angles a shared rule keeps located (a cycle's nodes and its edges, of
/// a width or two).
const KEPT_LOCATED: usize = 4;

/// Where angles φ fall on a rule: each one's whole cycles t and y = φ − tΦ
/// ([`Rule::turns_and_angle`]), its panel p and x ∈ [−1, 1] across it
/// ([`MonomialRunning::locate`]).
#[derive(Debug)]
pub(super) struct Located {
    angles: Vec<f64>,
    pub(super) turns: Vec<f64>,
    pub(super) y: Vec<f64>,
    pub(super) p: Vec<usize>,
    pub(super) x: Vec<f64>,
}

impl Located {
    fn new(rule: &Rule, phi: &[f64]) -> Self {
        let n = phi.len();
        let mut located = Self {
            angles: phi.to_vec(),
            turns: Vec::with_capacity(n),
            y: Vec::with_capacity(n),
            p: Vec::with_capacity(n),
            x: Vec::with_capacity(n),
        };
        let mut hint = 0;
        for &angle in phi {
            let (t, y) = rule.turns_and_angle(angle, 0.0);
            let (p, x) = MonomialRunning::locate(&rule.panels, y, &mut hint);
            located.turns.push(t);
            located.y.push(y);
            located.p.push(p);
            located.x.push(x);
        }
        located
    }

    /// Whether these are `phi`'s, bit for bit.
    fn of(&self, phi: &[f64]) -> bool {
        self.angles.len() == phi.len()
            && self
                .angles
                .iter()
                .zip(phi)
                .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

/// A cylinder's tables (head, crank end) and its areas' bits (bore, piston rod diameter).
pub(super) type RuleKey = (Option<usize>, Option<usize>, [u64; 2]);

impl Rule {
    pub(super) fn key(gas: &GasCylinder) -> RuleKey {
        (
            gas.head,
            gas.crank_end,
            [gas.bore.to_bits(), gas.piston_rod_diameter.to_bits()],
        )
    }

    pub(super) fn new(gas: GasCylinder, diagrams: &[PiecewisePolynomial], cycle: f64) -> Self {
        let tables: Vec<&PiecewisePolynomial> = [gas.head, gas.crank_end]
            .into_iter()
            .flatten()
            .map(|d| &diagrams[d])
            .collect();
        // The tables' breakpoints folded into the cycle (`periodic`: rem_euclid's doubles,
        // without its division), each table's a sorted run turned at its fold, then the
        // dead centres put in their places: one table's are sorted as made, so `breaks`
        // need not sort them (two tables' runs it sorts).
        let mut angles: Vec<f64> = Vec::new();
        for table in &tables {
            let start = angles.len();
            angles.extend(table.breakpoints().iter().map(|&x| periodic(x, cycle)));
            let run = &mut angles[start..];
            let turn = run
                .windows(2)
                .position(|p| p[1] < p[0])
                .map_or(0, |i| i + 1);
            run.rotate_left(turn);
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
            located: Mutex::new(Vec::new()),
        }
    }

    /// Where `phi` falls on the panels, kept for the machines that share this rule (`None`
    /// for a rule no second machine has taken: each of its tables is asked once).
    pub(super) fn located(&self, phi: &[f64]) -> Option<Arc<Located>> {
        // A second machine that takes the rule makes its trig: the mark of a shared rule.
        self.trig.get()?;
        // A poisoned lock holds nothing half-made: every entry was pushed whole.
        let kept = || self.located.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(found) = kept().iter().find(|l| l.of(phi)) {
            return Some(Arc::clone(found));
        }
        let made = Arc::new(Located::new(self, phi));
        let mut all = kept();
        if all.len() == KEPT_LOCATED {
            all.remove(0);
        }
        all.push(Arc::clone(&made));
        Some(made)
    }

    /// (sin φ, cos φ) at the nodes, made on first use.
    pub(super) fn trig(&self) -> &(Vec<f64>, Vec<f64>) {
        self.trig.get_or_init(|| sincos_table(&self.panels.phi))
    }

    /// (t, y) with x = φ + `phase` = t·Φ + y, y ∈ [0, Φ): t by floor(x/Φ), where the two
    /// usual cases need no call of floor (not inlined on baseline x86-64) and give the same
    /// doubles.
    #[inline]
    pub(super) fn turns_and_angle(&self, angle: f64, phase: f64) -> (f64, f64) {
        let (x, cycle) = (angle + phase, self.cycle);
        if (0.0..cycle).contains(&x) && x / cycle < 1.0 {
            (0.0, x)
        } else if (cycle..2.0 * cycle).contains(&x) && (1.0..2.0).contains(&(x / cycle)) {
            (1.0, x - cycle)
        } else {
            let t = (x / cycle).floor();
            (t, x - t * cycle)
        }
    }
}
