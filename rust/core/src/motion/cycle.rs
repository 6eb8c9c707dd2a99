//! The machine over one working cycle (docs/theory.md, "Steady running", "How the integrals
//! are taken"): J − I_w, J′, U − U(0) and the gas work W tabulated at the nodes and edges of
//! Gauss–Legendre panels cut at the gassed units' dead centres, and the same quantities at
//! any angle. Every value comes from `Dynamics` (J, J′, U, the torques) and `gas`
//! (the forces and their work): here are only the tables.

use std::f64::consts::PI;
use std::sync::{Arc, Mutex, PoisonError};

use crate::dynamics::Dynamics;
use crate::error::Result;
use crate::parallel::Parallelism;

use super::drive::Drive;
use super::gas::{Forces, GasWork, PiecewisePolynomial};
use super::quadrature::{breaks, Panels};
use super::MachineView;

/// Gauss–Legendre points per panel: 12 (exact to degree 23); on π/8 panels δ of smooth
/// torques comes out to 1e-11 against independent oracles (docs/theory.md, "How the
/// integrals are taken").
const ORDER: usize = 12;
/// The widest panel (rad) to start from: one eighth of a turn resolves J and U of usual
/// machines (crank ratios to ~0.35, a few cylinders) to rounding with 12 points.
const START_WIDTH: f64 = PI / 8.0;
/// The panels are not halved below this width (rad): by then J and U have harmonics beyond
/// any real machine's (three degrees).
const NARROWEST: f64 = PI / 60.0;
/// The panels resolve a function when the last two Legendre coefficients of every panel's
/// interpolant stay below this fraction of its range (then the 12-point rule integrates it
/// to ~1e-14), …
const RESOLVED: f64 = 1e-7;
/// … or below rounding of its size.
const ROUNDING: f64 = 1e-14;

/// What of a machine's tables its gas alone decides: the forces, the indicator work G of
/// each cylinder, the panels' cuts (the gassed units' dead centres), and W and M_gas′ on the
/// panels of each width tried. Kept apart so that designs that differ only in masses, g, I_w
/// or speed share it (a motion sweep's); W on the panels of a width is made by whichever
/// design asks first — the same doubles whoever does. A gas `scaled` shares all of it: the
/// forces and W are linear in the pressures and proportional to the areas, so a design that
/// differs only in `pressure_scale` (or the bore, where every crank end's area is the
/// bore's) takes them times its `scale`, to rounding.
#[derive(Debug)]
pub(crate) struct Gas {
    forces: Arc<Forces>,
    work: Arc<GasWork>,
    cuts: Vec<f64>,
    on_panels: Arc<Mutex<ByWidth>>,
    /// What the forces, W and M_gas′ shared are multiplied by (1 for a gas of its own).
    scale: f64,
}

/// W on the panels of each width made, by the width's bits.
type ByWidth = Vec<(u64, Arc<OnPanels>)>;

/// W (J) at the nodes then edges of the panels of one width, and M_gas′ (N·m/rad) at their
/// nodes, from one look-up of the indicator rules ([`GasWork::with_slope_at`]).
#[derive(Debug)]
struct OnPanels {
    work: Vec<f64>,
    slope: Vec<f64>,
}

impl Gas {
    /// The gas of `machine` with `diagrams` in place of its own (the same pressures, or
    /// scaled ones, shared); checks it. With `like`, another machine's gas whose indicator
    /// rules are taken where they fit ([`GasWork::new`]): a sweep along r or l.
    pub fn new(
        machine: &MachineView<'_>,
        diagrams: Arc<[PiecewisePolynomial]>,
        like: Option<&Gas>,
    ) -> Result<Self> {
        let cycle = machine.strokes.cycle_angle();
        let forces = Forces::new(machine.units, machine.gas, diagrams.clone(), cycle)?;
        let like = like.map(|g| &*g.work);
        let work = GasWork::new(machine.units, machine.gas, diagrams, cycle, like)?;
        // The tables' own breakpoints enter through W, exactly.
        Ok(Self {
            forces: Arc::new(forces),
            work: Arc::new(work),
            cuts: breaks(dead_centres(machine), cycle),
            on_panels: Arc::new(Mutex::new(Vec::new())),
            scale: 1.0,
        })
    }

    /// The same gas with its pressures times `factor` (all it holds shared, nothing made
    /// again).
    pub fn scaled(&self, factor: f64) -> Self {
        Self {
            forces: Arc::clone(&self.forces),
            work: Arc::clone(&self.work),
            cuts: self.cuts.clone(),
            on_panels: Arc::clone(&self.on_panels),
            scale: self.scale * factor,
        }
    }

    /// W(φ) (J) at any angles: exact.
    fn work_at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        Ok(self.scaled_values(self.work.at(phi)?))
    }

    /// `values` (of the unscaled gas) times the scale.
    fn scaled_values(&self, mut values: Vec<f64>) -> Vec<f64> {
        if self.scale != 1.0 {
            values.iter_mut().for_each(|v| *v *= self.scale);
        }
        values
    }

    /// W on `panels` (cut to `width`), made once per width.
    fn on(&self, panels: &Panels, width: f64) -> Result<Arc<OnPanels>> {
        let key = width.to_bits();
        let find = |made: &Vec<(u64, Arc<OnPanels>)>| {
            made.iter()
                .find(|(k, _)| *k == key)
                .map(|(_, on)| Arc::clone(on))
        };
        // A poisoned lock holds nothing half-made: every entry was pushed whole.
        if let Some(on) = find(
            &self
                .on_panels
                .lock()
                .unwrap_or_else(PoisonError::into_inner),
        ) {
            return Ok(on);
        }
        let everywhere: Vec<f64> = panels.phi.iter().chain(&panels.edges).copied().collect();
        let (work, slope) = self.work.with_slope_at(&everywhere, panels.phi.len());
        let made = Arc::new(OnPanels { work, slope });
        let mut all = self
            .on_panels
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        if let Some(on) = find(&all) {
            return Ok(on);
        }
        all.push((key, Arc::clone(&made)));
        Ok(made)
    }
}

/// The dead centres ψ = φ + α ≡ 0 mod π of every gassed unit, φ in [0, Φ]: where a pressure
/// given by branches (expansion, compression) may switch.
pub(super) fn dead_centres(machine: &MachineView<'_>) -> Vec<f64> {
    let cycle = machine.strokes.cycle_angle();
    let centres = (cycle / PI).round() as usize;
    let mut angles = Vec::new();
    for (unit, gas) in machine.units.iter().zip(machine.gas) {
        if gas.has_gas() {
            angles.extend((0..=centres).map(|k| (k as f64 * PI - unit.phase).rem_euclid(cycle)));
        }
    }
    angles
}

/// The machine's quantities over its cycle. Nothing in them depends on I_w or on the
/// speed: one `Cycle` serves every shaft inertia and every mean speed.
#[derive(Debug, Clone)]
pub(crate) struct Cycle {
    /// Shared by the machine's copies (`without_gravity`, `gas_scaled`), as are the panels.
    pub dynamics: Arc<Dynamics>,
    pub gas: Arc<Gas>,
    /// I_w (kg·m²) of the machine tabulated, the default of a solve (`Balance::with_inertia`
    /// takes another): the tables hold J − I_w, which does not depend on it.
    pub inertia: f64,
    pub panels: Arc<Panels>,
    /// Whether U is kept (g ≠ 0 and not removed by `without_gravity`).
    pub gravity_on: bool,
    /// U(0) (J).
    pub(super) u0: f64,
    /// Whether J − I_w alone chose the panels (every wider width tried failed on it, not on
    /// U): then a machine with the same J and another U has these panels where they
    /// resolve its U (`webs`).
    pub(super) rest_decides: bool,
    /// A driving torque M_d(φ) beside the gas (`with_drive`), `None` for none: it enters
    /// W, the torque and the curvature wherever the gas does.
    drive: Option<Arc<Drive>>,
    /// Nodes, then edges: J − I_w (kg·m²), U − U(0) (J), W = W_gas + W_d (J), the work of
    /// gas and drive from φ = 0.
    pub rest: Vec<f64>,
    pub potential: Vec<f64>,
    pub work: Vec<f64>,
    /// (M_gas + M_d)′ and the gravity torque's slope −U″ (N·m/rad) at the nodes (the gas's
    /// by central differences of the exact torque, the drive's exact): how sharply the
    /// kinetic energy may dip.
    pub work_curvature: Vec<f64>,
    pub gravity_curvature: Vec<f64>,
}

impl Cycle {
    /// The tables of `machine` (its units checked as `dynamics`), its diagrams copied.
    pub fn new(machine: &MachineView<'_>, dynamics: Dynamics) -> Result<Self> {
        let gas = Gas::new(machine, machine.diagrams.into(), None)?;
        Self::with_gas(machine, dynamics, &Arc::new(gas))
    }

    /// The tables of `machine` whose gas is `gas` (made for it, or for a machine that differs
    /// from it only in masses, g or I_w).
    pub fn with_gas(machine: &MachineView<'_>, dynamics: Dynamics, gas: &Arc<Gas>) -> Result<Self> {
        let mut width = START_WIDTH;
        let mut rest_decides = true;
        loop {
            let panels = Panels::new(&gas.cuts, ORDER, width);
            let mut tables = Self::tabulate(machine, dynamics.clone(), gas, panels)?;
            if width < NARROWEST || tables.resolved() {
                tables.rest_decides = rest_decides;
                // W only on the panels kept (J and U decide them).
                let on = gas.on(&tables.panels, width)?;
                tables.work = gas.scaled_values(on.work.clone());
                tables.curvatures(&on)?;
                return Ok(tables);
            }
            rest_decides &= !tables.resolves(&tables.rest[..tables.nodes()]);
            width /= 2.0;
        }
    }

    /// `work_curvature` (once per gas and width) and `gravity_curvature` on the panels found.
    fn curvatures(&mut self, on: &OnPanels) -> Result<()> {
        let phi = &self.panels.phi;
        // M_gas′ from the indicator rules' own interpolants, found with W (no force looked up
        // again), kept unscaled (a scaled gas shares it); the gravity torque's slope −U″
        // exact (one pass of the kernel, where central differences took two).
        self.work_curvature = self.gas.scaled_values(on.slope.clone());
        let mut gravity = vec![0.0; phi.len()];
        if self.gravity_on {
            self.dynamics
                .gravity_torque_slope(phi, &mut gravity, Parallelism::SERIAL)?;
        }
        self.gravity_curvature = gravity;
        Ok(())
    }

    fn tabulate(
        machine: &MachineView<'_>,
        dynamics: Dynamics,
        gas: &Arc<Gas>,
        panels: Panels,
    ) -> Result<Self> {
        let everywhere: Vec<f64> = panels.phi.iter().chain(&panels.edges).copied().collect();
        let mut tables = Self {
            dynamics: Arc::new(dynamics),
            gas: Arc::clone(gas),
            inertia: machine.shaft_inertia,
            panels: Arc::new(panels),
            gravity_on: machine.g != 0.0,
            u0: 0.0,
            rest_decides: true,
            rest: Vec::new(),
            potential: Vec::new(),
            drive: None,
            work: Vec::new(),
            work_curvature: Vec::new(),
            gravity_curvature: Vec::new(),
        };
        tables.rest = tables.rest_at(&everywhere)?;
        if tables.gravity_on {
            let mut u0 = [0.0];
            tables
                .dynamics
                .potential_energy(&[0.0], &mut u0, Parallelism::SERIAL)?;
            tables.u0 = u0[0];
        }
        tables.potential = tables.potential_at(&everywhere)?;
        Ok(tables)
    }

    /// Nodes in the tables (before the edges).
    pub fn nodes(&self) -> usize {
        self.panels.phi.len()
    }

    /// Φ (rad).
    pub fn cycle(&self) -> f64 {
        self.panels.cycle()
    }

    /// The same machine with the driving torque `drive` beside its gas (which has none yet):
    /// its work and slope added to the tables (the panels, J and U kept).
    pub fn with_drive(&self, drive: Drive) -> Self {
        debug_assert!(self.drive.is_none());
        let mut other = self.clone();
        let everywhere: Vec<f64> = self
            .panels
            .phi
            .iter()
            .chain(&self.panels.edges)
            .copied()
            .collect();
        other
            .work
            .iter_mut()
            .zip(drive.work_at(&everywhere))
            .for_each(|(w, d)| *w += d);
        other
            .work_curvature
            .iter_mut()
            .zip(drive.slope_at(&self.panels.phi))
            .for_each(|(c, d)| *c += d);
        other.drive = Some(Arc::new(drive));
        other
    }

    /// The same machine with its gas's pressures times `factor` (`Gas::scaled`): J, U and the
    /// panels kept, W and M_gas′ scaled.
    pub fn gas_scaled(&self, factor: f64) -> Self {
        debug_assert!(self.drive.is_none());
        let mut other = self.clone();
        other.gas = Arc::new(self.gas.scaled(factor));
        other.work.iter_mut().for_each(|w| *w *= factor);
        other.work_curvature.iter_mut().for_each(|c| *c *= factor);
        other
    }

    /// W(φ) = W_gas + W_d (J), the work of gas and drive from φ = 0, at any angles: exact.
    pub fn work_at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        let mut work = self.gas.work_at(phi)?;
        if let Some(drive) = &self.drive {
            work.iter_mut()
                .zip(drive.work_at(phi))
                .for_each(|(w, d)| *w += d);
        }
        Ok(work)
    }

    /// Whether a drive is taken beside the gas.
    pub fn has_drive(&self) -> bool {
        self.drive.is_some()
    }

    /// W(Φ) (J): the work of gas and drive over one cycle.
    pub fn work_per_cycle(&self) -> f64 {
        self.gas.work.per_cycle * self.gas.scale + self.drive.as_ref().map_or(0.0, |d| d.per_cycle)
    }

    /// The same machine with g = 0 (the panels, J and W kept).
    pub fn without_gravity(&self) -> Self {
        let mut other = self.clone();
        other.gravity_on = false;
        other.u0 = 0.0;
        other.potential.iter_mut().for_each(|u| *u = 0.0);
        other.gravity_curvature.iter_mut().for_each(|c| *c = 0.0);
        other
    }

    /// Whether the panels resolve J − I_w and U (their interpolants' last two Legendre
    /// coefficients below `RESOLVED` of the range, or of rounding).
    fn resolved(&self) -> bool {
        let n = self.nodes();
        self.resolves(&self.rest[..n]) && self.resolves(&self.potential[..n])
    }

    /// Whether the panels resolve `values` at their nodes (as `resolved`), or are as narrow
    /// as they are cut.
    pub(super) fn resolves(&self, values: &[f64]) -> bool {
        if self.panels.max_width < NARROWEST {
            return true;
        }
        let (low, high) = values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let spread = high - low;
        if spread == 0.0 {
            return true;
        }
        let size = values.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        self.panels.tail(values) <= (RESOLVED * spread).max(ROUNDING * size)
    }

    /// (J − I_w (kg·m²), J′ (kg·m²/rad)) at any angles: the rods' and pistons' share of J
    /// and its slope, for any I_w.
    pub fn inertia_at(&self, phi: &[f64]) -> Result<(Vec<f64>, Vec<f64>)> {
        let (mut inertia, mut slope) = (vec![0.0; phi.len()], vec![0.0; phi.len()]);
        self.dynamics
            .inertia_beside_shaft(phi, &mut inertia, &mut slope, Parallelism::SERIAL)?;
        Ok((inertia, slope))
    }

    /// J − I_w (kg·m²) at any angles.
    pub fn rest_at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        let mut inertia = vec![0.0; phi.len()];
        self.dynamics
            .inertia_alone_beside_shaft(phi, &mut inertia)?;
        Ok(inertia)
    }

    /// (1/Φ)∫(J − I_w) dφ (kg·m²): the rods' and pistons' mean share of J.
    pub fn mean_rest(&self) -> f64 {
        self.panels.integral(&self.rest[..self.nodes()]) / self.cycle()
    }

    /// U(φ) − U(0) (J) at any angles (0 without gravity).
    pub fn potential_at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        let mut u = vec![0.0; phi.len()];
        if self.gravity_on {
            self.dynamics
                .potential_energy(phi, &mut u, Parallelism::SERIAL)?;
            u.iter_mut().for_each(|u| *u -= self.u0);
        }
        Ok(u)
    }

    /// M_gas (N·m) at any angles.
    pub fn gas_torque_at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        let mut torque = vec![0.0; phi.len()];
        let forces = self.gas.scaled_values(self.gas.forces.at(phi));
        self.dynamics
            .gas_torque(phi, &forces, &mut torque, Parallelism::SERIAL)?;
        Ok(torque)
    }

    /// The gravity torque −U′ (N·m) at any angles (0 without gravity).
    pub fn gravity_torque_at(&self, phi: &[f64]) -> Result<Vec<f64>> {
        let mut weight = vec![0.0; phi.len()];
        if self.gravity_on {
            self.dynamics
                .gravity_torque(phi, &mut weight, Parallelism::SERIAL)?;
        }
        Ok(weight)
    }

    /// M_gas + M_d + the gravity torque −U′ (N·m) at any angles (`gas`: whether M_gas and
    /// the drive are taken).
    pub fn torque_at(&self, phi: &[f64], gas: bool) -> Result<Vec<f64>> {
        let mut torque = self.gravity_torque_at(phi)?;
        if gas {
            torque
                .iter_mut()
                .zip(self.gas_torque_at(phi)?)
                .for_each(|(m, g)| *m += g);
            if let Some(drive) = &self.drive {
                torque
                    .iter_mut()
                    .zip(drive.torque_at(phi))
                    .for_each(|(m, d)| *m += d);
            }
        }
        Ok(torque)
    }

    /// K'' = (M_gas + M_d − U′)′ at the base nodes (N·m/rad) (`gas`: whether M_gas and the
    /// drive are taken).
    pub fn curvature(&self, gas: bool) -> Vec<f64> {
        if gas {
            self.work_curvature
                .iter()
                .zip(&self.gravity_curvature)
                .map(|(g, w)| g + w)
                .collect()
        } else {
            self.gravity_curvature.clone()
        }
    }
}
