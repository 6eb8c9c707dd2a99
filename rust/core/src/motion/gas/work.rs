//! The gas work W(φ) = ∫₀^φ M_gas dφ of a machine, exact at every φ: each cylinder's
//! indicator work G at phase 0 integrated on panels cut at every breakpoint of its tables
//! (the room's doc, `gas`), and W the sum of the units' G at their phases.

use std::f64::consts::PI;
use std::sync::Arc;

use crate::dynamics::Dynamics;
use crate::error::Result;
use crate::mechanism::PhysicalCylinder;
use crate::parallel::Parallelism;

use super::super::quadrature::{breaks, MonomialRunning, Panels};
use super::{cylinder_force_near, periodic, GasCylinder, PiecewisePolynomial};

/// F of one cylinder at phase 0 at every θ (rad), θ taken modulo the cycle.
fn one_cylinder_forces(
    cylinder: GasCylinder,
    diagrams: &[PiecewisePolynomial],
    cycle: f64,
    theta: &[f64],
) -> Vec<f64> {
    let mut hints = [0, 0];
    theta
        .iter()
        .map(|&t| cylinder_force_near(&cylinder, diagrams, periodic(t, cycle), &mut hints))
        .collect()
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

/// G(x) = ∫₀^x F(θ) s'(θ) dθ of one cylinder at phase 0 (J), for any real x: F·s′ on
/// panels cut at every breakpoint of the cylinder's tables (and its dead centres), at most
/// π/64 wide, its interpolant through each panel's Gauss nodes integrated exactly
/// ([`MonomialRunning`]).
#[derive(Debug, Clone)]
struct Indicator {
    cycle: f64,
    panels: Panels,
    /// G and (F·s′)′ on every panel, in monomials for the many look-ups of W.
    running: MonomialRunning,
}

impl Indicator {
    fn new(
        unit: &PhysicalCylinder,
        gas: GasCylinder,
        diagrams: &[PiecewisePolynomial],
        cycle: f64,
    ) -> Result<Self> {
        let alone = PhysicalCylinder {
            phase: 0.0,
            ..*unit
        };
        let dynamics = Dynamics::new(&[alone], 0.0)?;
        let tables: Vec<&PiecewisePolynomial> = [gas.head, gas.crank_end]
            .into_iter()
            .flatten()
            .map(|d| &diagrams[d])
            .collect();
        let mut angles: Vec<f64> = (0..=(cycle / PI).round() as usize)
            .map(|k| k as f64 * PI)
            .collect();
        for table in &tables {
            angles.extend(table.breakpoints().iter().map(|x| x.rem_euclid(cycle)));
        }
        let order = tables.iter().map(|t| t.order()).max().unwrap_or(1);
        let cuts = breaks(angles, cycle);
        // The widest panel: a piece between cuts in equal panels no wider than the width.
        let widest = cuts.windows(2).fold(0.0, |m: f64, pair| {
            let width = pair[1] - pair[0];
            m.max(width / (width / INDICATOR_WIDTH).ceil().max(1.0))
        });
        let panels = Panels::new(&cuts, indicator_order(order, widest), INDICATOR_WIDTH);
        let forces = one_cylinder_forces(gas, diagrams, cycle, &panels.phi);
        let mut torque = vec![0.0; panels.phi.len()];
        dynamics.gas_torque(&panels.phi, &forces, &mut torque, Parallelism::SERIAL)?;
        let (at_edges, coefficients) = panels.antiderivative(&torque).into_tables();
        let running = MonomialRunning::new(&panels, at_edges, &coefficients);
        Ok(Self {
            cycle,
            panels,
            running,
        })
    }

    fn per_cycle(&self) -> f64 {
        self.running.at_edges[self.running.at_edges.len() - 1]
    }

    /// G(φ + `phase`) added to `work` for each φ of `phi`; with `slope`, G″ = (F·s′)′
    /// (N·m/rad) there, the slope of the interpolant G integrates, added to it (one panel
    /// look-up for both). φ + phase in increasing order walks the panels.
    fn add(&self, phi: &[f64], phase: f64, work: &mut [f64], slope: Option<&mut [f64]>) {
        let per_cycle = self.per_cycle();
        let mut hint = 0;
        let (panels, running) = (&self.panels, &self.running);
        let cycle = self.cycle;
        // x = t·Φ + y, y in [0, Φ): t by floor(x/Φ), where the two usual cases need no
        // call of floor (not inlined on baseline x86-64) and give the same doubles.
        let turns_and_angle = |p: f64| {
            let x = p + phase;
            if (0.0..cycle).contains(&x) && x / cycle < 1.0 {
                (0.0, x)
            } else if (cycle..2.0 * cycle).contains(&x) && (1.0..2.0).contains(&(x / cycle)) {
                (1.0, x - cycle)
            } else {
                let t = (x / cycle).floor();
                (t, x - t * cycle)
            }
        };
        match slope {
            None => {
                // LANES angles at a time: their Horner chains side by side (the same doubles).
                const LANES: usize = 8;
                let mut whole = work.chunks_exact_mut(LANES);
                let mut angles = phi.chunks_exact(LANES);
                for (w, p) in (&mut whole).zip(&mut angles) {
                    let (mut turns, mut y) = ([0.0; LANES], [0.0; LANES]);
                    for l in 0..LANES {
                        (turns[l], y[l]) = turns_and_angle(p[l]);
                    }
                    let g = running.at_lanes(panels, &y, &mut hint);
                    for l in 0..LANES {
                        w[l] += turns[l] * per_cycle + g[l];
                    }
                }
                for (w, &p) in whole.into_remainder().iter_mut().zip(angles.remainder()) {
                    let (t, y) = turns_and_angle(p);
                    *w += t * per_cycle + running.at_near(panels, y, &mut hint);
                }
            }
            Some(slope) => {
                for ((w, s), &p) in work.iter_mut().zip(slope.iter_mut()).zip(phi) {
                    let (t, y) = turns_and_angle(p);
                    let (g, g2) = running.at_and_slope_near(panels, y, &mut hint);
                    *w += t * per_cycle + g;
                    *s += g2;
                }
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

/// W(φ) = ∫₀^φ M_gas dφ of a machine (J).
#[derive(Debug, Clone)]
pub(crate) struct GasWork {
    /// One G per distinct cylinder, with the phases of the units that share it.
    groups: Vec<(Indicator, Vec<f64>)>,
    origin: f64,
    /// W(Φ), the indicated work of one cycle (J).
    pub per_cycle: f64,
}

impl GasWork {
    pub fn new(
        units: &[PhysicalCylinder],
        gas: &[GasCylinder],
        diagrams: Arc<[PiecewisePolynomial]>,
        cycle: f64,
    ) -> Result<Self> {
        // Units alike in all that G depends on: the same diagrams, areas, r and l.
        type Key = (Option<usize>, Option<usize>, [u64; 4]);
        let mut keys: Vec<Key> = Vec::new();
        let mut members: Vec<(usize, Vec<f64>)> = Vec::new();
        for (j, (unit, cylinder)) in units.iter().zip(gas).enumerate() {
            if !cylinder.has_gas() {
                continue;
            }
            let key = (
                cylinder.head,
                cylinder.crank_end,
                [
                    cylinder.bore.to_bits(),
                    cylinder.piston_rod_diameter.to_bits(),
                    unit.crank_radius.to_bits(),
                    unit.rod_length.to_bits(),
                ],
            );
            match keys.iter().position(|k| *k == key) {
                Some(g) => members[g].1.push(unit.phase),
                None => {
                    keys.push(key);
                    members.push((j, vec![unit.phase]));
                }
            }
        }
        let mut groups = Vec::with_capacity(members.len());
        for (j, phases) in members {
            groups.push((Indicator::new(&units[j], gas[j], &diagrams, cycle)?, phases));
        }
        let mut work = Self {
            groups,
            origin: 0.0,
            per_cycle: 0.0,
        };
        work.per_cycle = work
            .groups
            .iter()
            .map(|(g, phases)| g.per_cycle() * phases.len() as f64)
            .sum();
        let mut origin = 0.0;
        for (g, phases) in &work.groups {
            origin += g.at(phases).iter().sum::<f64>();
        }
        work.origin = origin;
        Ok(work)
    }

    /// W at each φ.
    pub fn at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        let mut total = vec![-self.origin; phi.len()];
        for (g, phases) in &self.groups {
            for &phase in phases {
                g.add(phi, phase, &mut total, None);
            }
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
        for (g, phases) in &self.groups {
            for &phase in phases {
                g.add(&phi[..sloped], phase, head, Some(&mut slope));
                g.add(&phi[sloped..], phase, tail, None);
            }
        }
        (total, slope)
    }
}
