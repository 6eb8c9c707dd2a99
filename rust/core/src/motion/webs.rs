//! Designs of a motion sweep that differ only in their crank webs and counterweights: those
//! enter U alone, through each unit's first moment r_s·m_s − r_p·m_p + r·(z_k/l)·m_k, as
//! U₂[sin(ψ + γ) − sin γ] (`exact`'s energy term, U₂ = g times that moment). Such a design
//! takes another's tables (J − I_w, the panels, the gas) with its U and gravity torque that
//! other's plus the sinusoids of the difference.

use std::sync::{Arc, OnceLock};

use crate::dynamics::Dynamics;
use crate::error::Result;
use crate::mechanism::PhysicalCylinder;
use crate::parallel::Parallelism;

use super::cycle::Cycle;
use super::{MachineView, SteadyTables};

/// A machine's tables and (sin φ, cos φ) at their samples (nodes, then edges), made on
/// first use: what designs that differ from it only in their webs take.
#[derive(Debug)]
pub(super) struct Kinematics {
    pub(super) tables: Arc<SteadyTables>,
    angles: OnceLock<Vec<(f64, f64)>>,
}

impl Kinematics {
    pub(super) fn new(tables: Arc<SteadyTables>) -> Self {
        Self {
            tables,
            angles: OnceLock::new(),
        }
    }

    /// The tables of `machine`, whose units differ from those of these tables' machine
    /// (`from`) only in their crank webs and counterweights; `None` where those panels need
    /// not be `machine`'s own (U chose them, or they do not resolve its U): tabulate it then.
    pub(super) fn reweighted(
        &self,
        from: &[PhysicalCylinder],
        machine: &MachineView<'_>,
    ) -> Result<Option<SteadyTables>> {
        let cycle = &self.tables.cycle;
        let angles = self.angles.get_or_init(|| {
            let samples = cycle.panels.phi.iter().chain(&cycle.panels.edges);
            samples.map(|phi| phi.sin_cos()).collect()
        });
        reweighted(cycle, angles, from, machine)?
            .map(SteadyTables::from_cycle)
            .transpose()
    }
}

/// The tables of `machine` from `tables` of a machine whose units `from` differ from its own
/// only in their crank webs and counterweights (`angles`: (sin φ, cos φ) at its samples).
fn reweighted(
    tables: &Cycle,
    angles: &[(f64, f64)],
    from: &[PhysicalCylinder],
    machine: &MachineView<'_>,
) -> Result<Option<Cycle>> {
    if !tables.rest_decides {
        return Ok(None);
    }
    let g = machine.g;
    // ΔU = Σ ΔU₂[sin(φ + α + γ) − sin(α + γ)] = A sin φ + B (cos φ − 1), with
    // A = Σ ΔU₂ cos(α + γ), B = Σ ΔU₂ sin(α + γ).
    let (mut a, mut b) = (0.0, 0.0);
    for (new, old) in machine.units.iter().zip(from) {
        let change = new.gravity_unit(g).u2 - old.gravity_unit(g).u2;
        if change != 0.0 {
            let (sin, cos) = (new.phase + new.inclination).sin_cos();
            a += change * cos;
            b += change * sin;
        }
    }
    let mut cycle = tables.clone();
    cycle.dynamics = Arc::new(Dynamics::new(machine.units, g)?);
    cycle.inertia = machine.shaft_inertia;
    if !cycle.gravity_on || (a == 0.0 && b == 0.0) {
        return Ok(Some(cycle));
    }
    for (u, (sin, cos)) in cycle.potential.iter_mut().zip(angles) {
        *u += a * sin + b * (cos - 1.0);
    }
    let n = cycle.nodes();
    if !cycle.resolves(&cycle.potential[..n]) {
        return Ok(None);
    }
    // −ΔU′ = B sin φ − A cos φ, whose slope is A sin φ + B cos φ.
    for (slope, (sin, cos)) in cycle.gravity_curvature.iter_mut().zip(angles) {
        *slope += a * sin + b * cos;
    }
    let mut u0 = [0.0];
    cycle
        .dynamics
        .potential_energy(&[0.0], &mut u0, Parallelism::SERIAL)?;
    cycle.u0 = u0[0];
    Ok(Some(cycle))
}
