//! The vocabulary of a motion sweep: the design columns a sweep may set on its base machine
//! (`MachineDesigns`, with `UnitColumn` and `UnitField` for a single unit's fields), the outputs
//! it may ask for (`MotionOutputs`) and the columns it fills (`MotionColumns`).

use crate::error::{MechanismError, Result};
use crate::mechanism::PhysicalCylinder;

/// Per-design overrides of a base machine: each column optional (`None`: the base
/// machine's value), one value per design when given. The cylinder fields are set on every
/// cylinder (SI units).
///
/// `rod_inertia`: NaN is the two-mass rod of the design's own rod, m_k z_k (l − z_k)
/// ([`two_mass_rod_inertia`]). Without a `rod_inertia` column, a unit whose base rod is the
/// two-mass rod stays one when `rod_mass`, `rod_length` or `rod_cg` change (as the Python
/// API's `Cylinder.replace`); any other unit keeps its rod inertia.
///
/// `units`: a field set on one unit alone ([`UnitColumn`]), after the columns set on every
/// unit: what a firing order (the phases) or a counterweight per throw changes.
///
/// [`two_mass_rod_inertia`]: crate::mechanism::two_mass_rod_inertia
#[derive(Debug, Clone, Default)]
pub struct MachineDesigns<'a> {
    /// The number of designs (every column given has this length).
    pub designs: usize,
    /// I_w (kg·m²).
    pub shaft_inertia: Option<&'a [f64]>,
    /// The mean speed ω_m (rad/s); without it every design runs at the sweep's base
    /// `omega`.
    pub omega: Option<&'a [f64]>,
    /// g (m/s²).
    pub g: Option<&'a [f64]>,
    /// Multiplies every diagram's pressure.
    pub pressure_scale: Option<&'a [f64]>,
    pub crank_radius: Option<&'a [f64]>,
    pub rod_length: Option<&'a [f64]>,
    pub piston_mass: Option<&'a [f64]>,
    pub rod_mass: Option<&'a [f64]>,
    pub rod_cg: Option<&'a [f64]>,
    pub rod_inertia: Option<&'a [f64]>,
    pub crank_mass: Option<&'a [f64]>,
    pub crank_cg_radius: Option<&'a [f64]>,
    pub counterweight_mass: Option<&'a [f64]>,
    pub counterweight_radius: Option<&'a [f64]>,
    /// The gas cylinders' D (m).
    pub bore: Option<&'a [f64]>,
    /// Fields of single units, one value per design each.
    pub units: Vec<UnitColumn<'a>>,
}

/// A field a design may set on one unit alone (the Python API's `"phase[j]"` columns).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnitField {
    /// α_j (rad): where the unit sits on the crank and in its working cycle.
    Phase,
    /// m_p (kg) of the unit's counterweight.
    CounterweightMass,
    /// r_p (m) of the unit's counterweight.
    CounterweightRadius,
}

impl UnitField {
    /// Every field by its public name.
    pub const NAMES: [(&'static str, Self); 3] = [
        ("phase", Self::Phase),
        ("counterweight_mass", Self::CounterweightMass),
        ("counterweight_radius", Self::CounterweightRadius),
    ];

    /// The field of a public name, if there is one.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::NAMES
            .iter()
            .find(|(known, _)| *known == name)
            .map(|(_, field)| *field)
    }

    /// Its public name.
    pub fn name(self) -> &'static str {
        Self::NAMES
            .iter()
            .find(|(_, field)| *field == self)
            .map_or("", |(name, _)| name)
    }

    /// Whether it changes the machine's gas: the phase moves the unit in its working cycle;
    /// a counterweight enters gravity alone.
    pub(super) fn changes_gas(self) -> bool {
        self == Self::Phase
    }

    /// Sets this field of `unit` to `value`.
    pub(super) fn set(self, unit: &mut PhysicalCylinder, value: f64) {
        match self {
            Self::Phase => unit.phase = value,
            Self::CounterweightMass => unit.counterweight_mass = value,
            Self::CounterweightRadius => unit.counterweight_radius = value,
        }
    }
}

/// One unit's own values of a field, one per design; set after the columns set on every
/// unit, and after an earlier column of the same unit and field.
#[derive(Debug, Clone, Copy)]
pub struct UnitColumn<'a> {
    pub field: UnitField,
    /// The unit's index in the machine.
    pub unit: usize,
    pub values: &'a [f64],
}

impl<'a> MachineDesigns<'a> {
    /// `designs` designs, none of them changing anything yet.
    pub fn new(designs: usize) -> Self {
        Self {
            designs,
            ..Self::default()
        }
    }

    /// Every column by its public name, given or not, with what it changes.
    pub(super) fn named(&self) -> [(&'static str, Changes, Option<&'a [f64]>); COLUMNS.len()] {
        COLUMNS.map(|c| (c.name, c.changes, (c.get)(self)))
    }

    /// Sets the column `name` (a name of [`MachineDesigns::NAMES`], or `"field[j]"`: a
    /// [`UnitField`] of unit j alone) to `values`, one per design (their number is checked
    /// by the sweep). An unknown name is an error naming `designs`.
    pub fn set(&mut self, name: &str, values: &'a [f64]) -> Result<()> {
        if let Some(column) = COLUMNS.iter().find(|c| c.name == name) {
            *(column.field)(self) = Some(values);
        } else if let Some((field, unit)) = unit_column(name) {
            self.units.push(UnitColumn {
                field,
                unit,
                values,
            });
        } else {
            return Err(MechanismError::InvalidChoice {
                parameter: "designs",
                value: format!("{name:?}"),
                allowed: Self::NAMES,
            });
        }
        Ok(())
    }

    /// The names [`MachineDesigns::set`] knows, as its error lists them.
    pub const NAMES: &'static str = "shaft_inertia, omega, g, pressure_scale, crank_radius, \
        rod_length, piston_mass, rod_mass, rod_cg, rod_inertia, crank_mass, crank_cg_radius, \
        counterweight_mass, counterweight_radius, bore, and phase[j], counterweight_mass[j], \
        counterweight_radius[j] of unit j";
}

/// What a column set on the whole machine changes of its tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Changes {
    /// Nothing: the tables do not depend on I_w or the mean speed.
    Nothing,
    /// The machine's inertia and gravity, not its gas.
    Machine,
    /// Its gas too (W and M_gas): the pressures and the gassed cylinders' kinematics.
    Gas,
}

/// One column of [`MachineDesigns`] set on the whole machine: its public name, what it
/// changes, and its field.
struct Column {
    name: &'static str,
    changes: Changes,
    get: for<'a> fn(&MachineDesigns<'a>) -> Option<&'a [f64]>,
    field: for<'a, 'b> fn(&'b mut MachineDesigns<'a>) -> &'b mut Option<&'a [f64]>,
}

macro_rules! columns {
    ($($name:ident: $changes:ident),* $(,)?) => {
        [$(Column {
            name: stringify!($name),
            changes: Changes::$changes,
            get: |d| d.$name,
            field: |d| &mut d.$name,
        }),*]
    };
}

/// Every column set on the whole machine: the one list of their names.
const COLUMNS: [Column; 15] = columns![
    shaft_inertia: Nothing,
    omega: Nothing,
    g: Machine,
    pressure_scale: Gas,
    crank_radius: Gas,
    rod_length: Gas,
    piston_mass: Machine,
    rod_mass: Machine,
    rod_cg: Machine,
    rod_inertia: Machine,
    crank_mass: Machine,
    crank_cg_radius: Machine,
    counterweight_mass: Machine,
    counterweight_radius: Machine,
    bore: Gas,
];

/// A one-unit column's field and unit, from its name `"field[j]"` (j a decimal index).
fn unit_column(name: &str) -> Option<(UnitField, usize)> {
    let (field, rest) = name.split_once('[')?;
    let unit = rest.strip_suffix(']')?;
    if unit.is_empty() || !unit.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    Some((UnitField::from_name(field)?, unit.parse().ok()?))
}

/// Which columns a motion sweep fills (the Python API's `MOTION_SWEEP_OUTPUTS`); only
/// what is asked is computed. `stalled` comes with any output of the steady state.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MotionOutputs {
    /// δ of the steady state (with gravity).
    pub delta: bool,
    /// δ of the machine with g = 0 at the same mean speed.
    pub delta_without_gravity: bool,
    /// δ of the machine coasting: gas, drive and load removed (gravity and J(φ)'s variation).
    pub delta_coasting: bool,
    /// δ/δ₀ − 1, δ₀ = `delta_without_gravity`.
    pub gravity_effect: bool,
    /// The speed extremes (rad/s).
    pub omega_min: bool,
    pub omega_max: bool,
    /// I_w (kg·m²) for the target δ (`flywheel_inertia`), and the same with g = 0.
    pub flywheel_inertia: bool,
    pub flywheel_inertia_without_gravity: bool,
    /// Whether the design stalls: implied by any other output of the steady state.
    pub stalled: bool,
}

impl MotionOutputs {
    /// Every output a motion sweep can compute, in column order.
    pub const NAMES: [&'static str; 9] = [
        "delta",
        "delta_without_gravity",
        "delta_coasting",
        "gravity_effect",
        "omega_min",
        "omega_max",
        "stalled",
        "flywheel_inertia",
        "flywheel_inertia_without_gravity",
    ];

    /// The outputs named (from `NAMES`; `stalled` alone asks for the steady state).
    pub fn from_names<S: AsRef<str>>(names: &[S]) -> Result<Self> {
        let mut outputs = Self::default();
        for name in names {
            match name.as_ref() {
                "delta" => outputs.delta = true,
                "stalled" => outputs.stalled = true,
                "delta_without_gravity" => outputs.delta_without_gravity = true,
                "delta_coasting" => outputs.delta_coasting = true,
                "gravity_effect" => outputs.gravity_effect = true,
                "omega_min" => outputs.omega_min = true,
                "omega_max" => outputs.omega_max = true,
                "flywheel_inertia" => outputs.flywheel_inertia = true,
                "flywheel_inertia_without_gravity" => {
                    outputs.flywheel_inertia_without_gravity = true
                }
                other => {
                    return Err(MechanismError::InvalidChoice {
                        parameter: "outputs",
                        value: format!("{other:?}"),
                        allowed: "delta, delta_without_gravity, delta_coasting, \
                                  gravity_effect, omega_min, omega_max, stalled, flywheel_inertia, \
                                  flywheel_inertia_without_gravity",
                    })
                }
            }
        }
        Ok(outputs)
    }

    /// Whether the steady state (with gravity) is solved.
    pub fn steady(self) -> bool {
        self.stalled
            || self.delta
            || self.delta_without_gravity
            || self.delta_coasting
            || self.gravity_effect
            || self.omega_min
            || self.omega_max
    }

    /// Whether the flywheel is sized.
    pub fn flywheel(self) -> bool {
        self.flywheel_inertia || self.flywheel_inertia_without_gravity
    }
}

/// A motion sweep's columns, one row per design; a column not asked for is empty.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MotionColumns {
    /// δ (NaN where stalled).
    pub delta: Vec<f64>,
    /// δ₀: g = 0 (NaN where stalled, or where that machine stalls).
    pub delta_without_gravity: Vec<f64>,
    /// δ of the machine coasting (NaN where stalled, or where it stalls).
    pub delta_coasting: Vec<f64>,
    /// δ/δ₀ − 1: NaN where δ₀ is; +∞ where δ₀ = 0 < δ; NaN where both are 0.
    pub gravity_effect: Vec<f64>,
    /// ω_min, ω_max (rad/s), each widened to hold the mean speed asked for (NaN where
    /// stalled).
    pub omega_min: Vec<f64>,
    pub omega_max: Vec<f64>,
    /// Whether the design cannot keep its mean speed (ω_min < min_speed_ratio·ω_m):
    /// filled with any output of the steady state.
    pub stalled: Vec<bool>,
    /// I_w (kg·m²) for the target δ; NaN where it is unreachable.
    pub flywheel_inertia: Vec<f64>,
    /// The same with g = 0; NaN where unreachable.
    pub flywheel_inertia_without_gravity: Vec<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each column's name sets its own field alone, and the error lists every name.
    #[test]
    fn each_name_sets_its_own_column() {
        let values = [1.0, 2.0];
        for (i, column) in COLUMNS.iter().enumerate() {
            let mut designs = MachineDesigns::new(2);
            designs.set(column.name, &values).unwrap();
            for (j, (name, _, given)) in designs.named().into_iter().enumerate() {
                assert_eq!(
                    given.is_some(),
                    i == j,
                    "{name} after setting {}",
                    column.name
                );
            }
            assert!(MachineDesigns::NAMES.contains(column.name));
        }
        let mut designs = MachineDesigns::new(2);
        designs.set("phase[3]", &values).unwrap();
        assert_eq!(
            (designs.units[0].field, designs.units[0].unit),
            (UnitField::Phase, 3)
        );
        for bad in ["crank", "phase[]", "phase[x]", "bore[1]"] {
            assert!(matches!(
                designs.set(bad, &values),
                Err(MechanismError::InvalidChoice {
                    parameter: "designs",
                    ..
                })
            ));
        }
    }
}
