//! The variant rule of a motion sweep: a design's machine is the base machine with the
//! design's columns applied (`MachineDesigns`), every value, unit and gas checked; its gas is
//! made with the base diagrams, scaled where the design says so.

use std::sync::Arc;

use crate::error::{check, MechanismError, Result};
use crate::mechanism::{check_shaft_inertia, check_speed};
use crate::mechanism::{two_mass_rod_inertia, PhysicalCylinder};

use super::columns::MachineDesigns;
use super::cycle::Gas;
use super::gas::{GasCylinder, PiecewisePolynomial};
use super::MachineView;

/// A design's machine, apart from the diagrams (scaled only when it is solved).
#[derive(Debug, Clone)]
pub(super) struct Variant {
    pub(super) units: Vec<PhysicalCylinder>,
    gas: Vec<GasCylinder>,
    pub(super) shaft_inertia: f64,
    /// The mean speed ω_m (rad/s).
    pub(super) omega: f64,
    pub(super) g: f64,
    pub(super) pressure_scale: Option<f64>,
}

/// Design `row` of `designs` applied to `base` (mean speed `omega`, rad/s, where there is
/// no omega column),
/// checked: every value, every unit and its gas.
pub(super) fn variant(
    base: &MachineView<'_>,
    omega: Option<f64>,
    designs: &MachineDesigns<'_>,
    row: usize,
) -> Result<Variant> {
    let value = |column: Option<&[f64]>| column.map(|c| c[row]);
    let shaft_inertia =
        check_shaft_inertia(value(designs.shaft_inertia).unwrap_or(base.shaft_inertia))?;
    let omega = match value(designs.omega).or(omega) {
        Some(omega) => check_speed("omega", omega)?,
        None => {
            return Err(MechanismError::OutOfRange {
                parameter: "omega",
                value: f64::NAN,
                allowed: "a mean speed (rad/s): an omega column, or the sweep's base omega",
            })
        }
    };
    let g = check(
        "g",
        value(designs.g).unwrap_or(base.g),
        "any finite real",
        |_| true,
    )?;
    let pressure_scale = value(designs.pressure_scale)
        .map(|s| check("pressure_scale", s, "any finite real", |_| true))
        .transpose()?;
    let rod_changes =
        designs.rod_mass.is_some() || designs.rod_length.is_some() || designs.rod_cg.is_some();
    let units = base
        .units
        .iter()
        .enumerate()
        .map(|(index, unit)| {
            let set = |column: Option<&[f64]>, own: f64| value(column).unwrap_or(own);
            let mut new = PhysicalCylinder {
                crank_radius: set(designs.crank_radius, unit.crank_radius),
                rod_length: set(designs.rod_length, unit.rod_length),
                piston_mass: set(designs.piston_mass, unit.piston_mass),
                rod_mass: set(designs.rod_mass, unit.rod_mass),
                rod_cg: set(designs.rod_cg, unit.rod_cg),
                rod_inertia: unit.rod_inertia,
                crank_mass: set(designs.crank_mass, unit.crank_mass),
                crank_cg_radius: set(designs.crank_cg_radius, unit.crank_cg_radius),
                counterweight_mass: set(designs.counterweight_mass, unit.counterweight_mass),
                counterweight_radius: set(designs.counterweight_radius, unit.counterweight_radius),
                ..*unit
            };
            let two_mass = || two_mass_rod_inertia(new.rod_mass, new.rod_length, new.rod_cg);
            new.rod_inertia = match value(designs.rod_inertia) {
                Some(i) if i.is_nan() => two_mass(),
                Some(i) => i,
                None if rod_changes
                    && unit.rod_inertia
                        == two_mass_rod_inertia(unit.rod_mass, unit.rod_length, unit.rod_cg) =>
                {
                    two_mass()
                }
                None => unit.rod_inertia,
            };
            for column in designs.units.iter().filter(|c| c.unit == index) {
                column.field.set(&mut new, column.values[row]);
            }
            new.validate()?;
            Ok(new)
        })
        .collect::<Result<Vec<_>>>()?;
    let gas = base
        .gas
        .iter()
        .map(|gas| {
            let new = GasCylinder {
                bore: value(designs.bore).unwrap_or(gas.bore),
                ..*gas
            };
            new.validate(base.diagrams.len())?;
            Ok(new)
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Variant {
        units,
        gas,
        shaft_inertia,
        omega,
        g,
        pressure_scale,
    })
}

/// A design's machine (its diagrams: `shared`, the base ones, scaled where the design says
/// so), and the gas of it, its indicator rules taken from `like` where they fit.
pub(super) fn gas(
    base: &MachineView<'_>,
    shared: &Arc<[PiecewisePolynomial]>,
    variant: &Variant,
    like: Option<&Gas>,
) -> Result<Gas> {
    let diagrams = match variant.pressure_scale {
        Some(factor) => shared.iter().map(|d| d.scaled(factor)).collect(),
        None => Arc::clone(shared),
    };
    Gas::new(&variant.machine(base), diagrams, like)
}

impl Variant {
    /// The machine of the design, its diagrams apart (a `Gas` holds them).
    pub(super) fn machine<'v>(&'v self, base: &MachineView<'_>) -> MachineView<'v> {
        MachineView {
            units: &self.units,
            gas: &self.gas,
            diagrams: &[],
            shaft_inertia: self.shaft_inertia,
            strokes: base.strokes,
            g: self.g,
        }
    }
}
