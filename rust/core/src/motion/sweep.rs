//! Motion at sweep scale: the steady state (and the flywheel) of many variants of one
//! machine, one row each (the Python API's `motion_sweep`, its `_solve_chunk`).
//!
//! A design is the base machine with some numbers replaced (`DesignColumns`); each row is
//! exactly what `steady_state` and `flywheel_inertia` give for that design's machine — the
//! same tables, the same solves, in the same order — less what was not asked for. Every row
//! is solved on its own, so the columns are bit-identical for any thread count.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::sync::Arc;

use crate::dynamics::{two_mass_rod_inertia, Dynamics, PhysicalCylinder};
use crate::error::{check, check_length, MechanismError, Result};
use crate::mechanism::{check_rpm, check_shaft_inertia, omega_from_rpm};
use crate::parallel::{map_indices, Parallelism};

use super::cycle::Gas;
use super::gas::{GasCylinder, PiecewisePolynomial};
use super::{check_speed_ratio, flywheel, Machine, SteadyTables};

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
#[derive(Debug, Clone, Default)]
pub struct DesignColumns<'a> {
    /// The number of designs (every column given has this length).
    pub designs: usize,
    /// I_w (kg·m²).
    pub shaft_inertia: Option<&'a [f64]>,
    /// The mean speed (1/min); without it every design runs at the sweep's base `rpm`.
    pub rpm: Option<&'a [f64]>,
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
    fn changes_gas(self) -> bool {
        self == Self::Phase
    }

    /// Sets this field of `unit` to `value`.
    fn set(self, unit: &mut PhysicalCylinder, value: f64) {
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

impl<'a> DesignColumns<'a> {
    /// `designs` designs, none of them changing anything yet.
    pub fn new(designs: usize) -> Self {
        Self {
            designs,
            ..Self::default()
        }
    }

    /// Every column by its public name, given or not.
    fn named(&self) -> [(&'static str, Option<&'a [f64]>); 15] {
        [
            ("shaft_inertia", self.shaft_inertia),
            ("rpm", self.rpm),
            ("g", self.g),
            ("pressure_scale", self.pressure_scale),
            ("crank_radius", self.crank_radius),
            ("rod_length", self.rod_length),
            ("piston_mass", self.piston_mass),
            ("rod_mass", self.rod_mass),
            ("rod_cg", self.rod_cg),
            ("rod_inertia", self.rod_inertia),
            ("crank_mass", self.crank_mass),
            ("crank_cg_radius", self.crank_cg_radius),
            ("counterweight_mass", self.counterweight_mass),
            ("counterweight_radius", self.counterweight_radius),
            ("bore", self.bore),
        ]
    }
}

/// Which columns a motion sweep fills (the Python API's `MOTION_SWEEP_OUTPUTS`); only
/// what is asked is computed. `stalled` comes with any output of the steady state.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MotionOutputs {
    /// δ of the steady state (with gravity).
    pub delta: bool,
    /// δ of the machine with g = 0 at the same mean speed.
    pub delta_without_gravity: bool,
    /// δ of gravity (and the variation of J) alone.
    pub delta_gravity_only: bool,
    /// δ/δ₀ − 1, δ₀ = `delta_without_gravity`.
    pub gravity_effect: bool,
    /// The speed extremes (1/min).
    pub rpm_min: bool,
    pub rpm_max: bool,
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
        "delta_gravity_only",
        "gravity_effect",
        "rpm_min",
        "rpm_max",
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
                "delta_gravity_only" => outputs.delta_gravity_only = true,
                "gravity_effect" => outputs.gravity_effect = true,
                "rpm_min" => outputs.rpm_min = true,
                "rpm_max" => outputs.rpm_max = true,
                "flywheel_inertia" => outputs.flywheel_inertia = true,
                "flywheel_inertia_without_gravity" => {
                    outputs.flywheel_inertia_without_gravity = true
                }
                other => {
                    return Err(MechanismError::InvalidChoice {
                        parameter: "outputs",
                        value: format!("{other:?}"),
                        allowed: "delta, delta_without_gravity, delta_gravity_only, \
                                  gravity_effect, rpm_min, rpm_max, stalled, flywheel_inertia, \
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
            || self.delta_gravity_only
            || self.gravity_effect
            || self.rpm_min
            || self.rpm_max
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
    /// δ of gravity alone (NaN where stalled, or where it stalls).
    pub delta_gravity_only: Vec<f64>,
    /// δ/δ₀ − 1: NaN where δ₀ is; +∞ where δ₀ = 0 < δ; NaN where both are 0.
    pub gravity_effect: Vec<f64>,
    /// 30 ω_min/π, 30 ω_max/π (1/min) (NaN where stalled).
    pub rpm_min: Vec<f64>,
    pub rpm_max: Vec<f64>,
    /// Whether the design cannot keep its mean speed (ω_min < min_speed_ratio·ω_m):
    /// filled with any output of the steady state.
    pub stalled: Vec<bool>,
    /// I_w (kg·m²) for the target δ; NaN where it is unreachable.
    pub flywheel_inertia: Vec<f64>,
    /// The same with g = 0; NaN where unreachable.
    pub flywheel_inertia_without_gravity: Vec<f64>,
}

/// One design's numbers (NaN where not asked).
#[derive(Debug, Clone, Copy)]
struct Row {
    delta: f64,
    delta_without_gravity: f64,
    delta_gravity_only: f64,
    gravity_effect: f64,
    rpm_min: f64,
    rpm_max: f64,
    stalled: bool,
    flywheel_inertia: f64,
    flywheel_inertia_without_gravity: f64,
}

impl Row {
    const NONE: Self = Self {
        delta: f64::NAN,
        delta_without_gravity: f64::NAN,
        delta_gravity_only: f64::NAN,
        gravity_effect: f64::NAN,
        rpm_min: f64::NAN,
        rpm_max: f64::NAN,
        stalled: false,
        flywheel_inertia: f64::NAN,
        flywheel_inertia_without_gravity: f64::NAN,
    };
}

/// δ/δ₀ − 1 (the Python API's `SteadyState.gravity_effect`).
fn gravity_effect(delta: f64, without: f64) -> f64 {
    if without == 0.0 {
        if delta == 0.0 {
            f64::NAN
        } else {
            f64::INFINITY
        }
    } else {
        delta / without - 1.0
    }
}

/// A design's machine, apart from the diagrams (scaled only when it is solved).
#[derive(Debug, Clone)]
struct Variant {
    units: Vec<PhysicalCylinder>,
    gas: Vec<GasCylinder>,
    shaft_inertia: f64,
    rpm: f64,
    g: f64,
    pressure_scale: Option<f64>,
}

/// A steady state costs a few thousand kernel evaluations per unit: the `work` per design
/// and unit given to `Parallelism` (whose threshold counts points × cranks).
const WORK_PER_DESIGN_AND_UNIT: usize = 4096;

/// Design `row` of `designs` applied to `base` (speed `rpm` where there is no rpm column),
/// checked: every value, every unit and its gas.
fn variant(
    base: &Machine<'_>,
    rpm: Option<f64>,
    designs: &DesignColumns<'_>,
    row: usize,
) -> Result<Variant> {
    let value = |column: Option<&[f64]>| column.map(|c| c[row]);
    let shaft_inertia =
        check_shaft_inertia(value(designs.shaft_inertia).unwrap_or(base.shaft_inertia))?;
    let rpm = match value(designs.rpm).or(rpm) {
        Some(rpm) => check_rpm(rpm)?,
        None => {
            return Err(MechanismError::OutOfRange {
                parameter: "rpm",
                value: f64::NAN,
                allowed: "rpm > 0: an rpm column, or the sweep's base rpm",
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
        rpm,
        g,
        pressure_scale,
    })
}

/// A design's machine (its diagrams: `shared`, the base ones, scaled where the design says
/// so), and the gas of it.
fn gas(base: &Machine<'_>, shared: &Arc<[PiecewisePolynomial]>, variant: &Variant) -> Result<Gas> {
    let diagrams = match variant.pressure_scale {
        Some(factor) => shared.iter().map(|d| d.scaled(factor)).collect(),
        None => Arc::clone(shared),
    };
    Gas::new(&variant.machine(base), diagrams)
}

impl Variant {
    /// The machine of the design, its diagrams apart (a `Gas` holds them).
    fn machine<'v>(&'v self, base: &Machine<'_>) -> Machine<'v> {
        Machine {
            units: &self.units,
            gas: &self.gas,
            diagrams: &[],
            shaft_inertia: self.shaft_inertia,
            strokes: base.strokes,
            g: self.g,
        }
    }
}

/// One design solved on its machine's tables: `steady_state` and `flywheel_inertia` of
/// that machine, less what is not asked for; a stall is a row, not an error.
fn solve(
    tables: &SteadyTables,
    variant: &Variant,
    outputs: MotionOutputs,
    target: Option<f64>,
    ratio: f64,
) -> Result<Row> {
    let inertia = variant.shaft_inertia;
    let omega_mean = omega_from_rpm(variant.rpm);
    let mut row = Row::NONE;
    if outputs.steady() {
        match tables.solve(inertia, omega_mean, ratio)? {
            Ok(solution) if solution.delta().is_finite() => {
                let delta = solution.delta();
                row.delta = delta;
                // The row's mean speed is the rpm asked for, which the solution's ω_m
                // meets to rounding: the extremes keep it between them to the last ulp.
                row.rpm_min = (solution.omega_min * 30.0 / PI).min(variant.rpm);
                row.rpm_max = (solution.omega_max * 30.0 / PI).max(variant.rpm);
                if outputs.delta_without_gravity || outputs.gravity_effect {
                    let without = tables
                        .delta_without_gravity(inertia, omega_mean, ratio)?
                        .unwrap_or(delta);
                    row.delta_without_gravity = without;
                    row.gravity_effect = gravity_effect(delta, without);
                }
                if outputs.delta_gravity_only {
                    row.delta_gravity_only =
                        tables.delta_gravity_only(inertia, solution.omega_mean, ratio)?;
                }
            }
            _ => row.stalled = true,
        }
    }
    if let (true, Some(delta)) = (outputs.flywheel(), target) {
        let without = outputs.flywheel_inertia_without_gravity;
        match tables.flywheel_inertia(delta, variant.rpm, ratio, inertia, without) {
            Ok(found) => {
                row.flywheel_inertia = found.shaft_inertia;
                row.flywheel_inertia_without_gravity = found.shaft_inertia_without_gravity;
            }
            // The target unreachable: NaN in the flywheel's columns only.
            Err(MechanismError::Unreachable { .. }) => {}
            Err(error) => return Err(error),
        }
    }
    Ok(row)
}

/// Designs solved together: within a block, designs that differ only in I_w and speed
/// share their machine's tables (made once per distinct machine); a block bounds the tables
/// held at once (~100 kB each).
const BLOCK: usize = 512;

/// The columns that change a machine's gas (its W and M_gas): the pressures and the
/// kinematics of the gassed cylinders.
const GAS_COLUMNS: [&str; 4] = ["pressure_scale", "crank_radius", "rod_length", "bore"];

/// What of design `row` changes its machine's tables (every column but `shaft_inertia` and
/// `rpm`; `gas`: only the gas's columns, and the units' phases), bit for bit.
fn row_key(designs: &DesignColumns<'_>, row: usize, gas: bool) -> Vec<u64> {
    let shared = designs
        .named()
        .into_iter()
        .filter(|(name, _)| {
            if gas {
                GAS_COLUMNS.contains(name)
            } else {
                !matches!(*name, "shaft_inertia" | "rpm")
            }
        })
        .filter_map(|(_, column)| column.map(|c| c[row].to_bits()));
    let units = designs
        .units
        .iter()
        .filter(|c| !gas || c.field.changes_gas())
        .map(|c| c.values[row].to_bits());
    shared.chain(units).collect()
}

/// The distinct keys of `rows`, in order of their first row: (each row's index among them,
/// the first row of each).
fn distinct(
    rows: impl Iterator<Item = usize>,
    key: impl Fn(usize) -> Vec<u64>,
) -> (Vec<usize>, Vec<usize>) {
    let mut first_of: HashMap<Vec<u64>, usize> = HashMap::new();
    let mut firsts = Vec::new();
    let index = rows
        .map(|row| {
            *first_of.entry(key(row)).or_insert_with(|| {
                firsts.push(row);
                firsts.len() - 1
            })
        })
        .collect();
    (index, firsts)
}

/// The steady state under the "balance" load (and, with `target_delta`, the flywheel for
/// that δ) of every design: `base` with the design's columns applied, at the design's `rpm`
/// (1/min), or at `rpm` where there is no rpm column. Each row equals [`steady_state`] and
/// [`flywheel_inertia`] of that design's machine (same `min_speed_ratio`); only `outputs`
/// are computed (δ alone solves one steady state per design). In parallel over designs
/// when `parallelism` says so, the columns bit-identical for any thread count.
///
/// A design that stalls is a row with `stalled` true and NaN in its δ and speed columns; a
/// flywheel target a design cannot reach is NaN in its flywheel columns.
///
/// Errors, before any work: a bad base machine, `min_speed_ratio` or `target_delta` (≥ 1e-9,
/// needed by the flywheel outputs), a column of the wrong length, naming the parameter; a
/// bad value of design `row` as [`MechanismError::InRow`], naming the parameter.
///
/// [`steady_state`]: super::steady_state
/// [`flywheel_inertia`]: super::flywheel_inertia
pub fn motion_sweep(
    base: &Machine<'_>,
    rpm: Option<f64>,
    designs: &DesignColumns<'_>,
    outputs: MotionOutputs,
    target_delta: Option<f64>,
    min_speed_ratio: f64,
    parallelism: Parallelism,
) -> Result<MotionColumns> {
    check_speed_ratio(min_speed_ratio)?;
    if outputs.flywheel() {
        check(
            "delta",
            target_delta.unwrap_or(f64::NAN),
            "delta >= 1e-9 (the target of the flywheel outputs)",
            |d| d >= flywheel::SMALLEST_DELTA,
        )?;
    }
    // The base machine's own faults are not a row's.
    Dynamics::new(base.units, base.g)?;
    check_length("gas", base.units.len(), base.gas.len())?;
    for gas in base.gas {
        gas.validate(base.diagrams.len())?;
    }
    for (name, column) in designs.named() {
        if let Some(column) = column {
            check_length(name, designs.designs, column.len())?;
        }
    }
    for column in &designs.units {
        if column.unit >= base.units.len() {
            return Err(MechanismError::InvalidChoice {
                parameter: "designs",
                value: format!("{}[{}]", column.field.name(), column.unit),
                allowed: "a unit's field with the unit's index below the machine's number of units",
            });
        }
        check_length(column.field.name(), designs.designs, column.values.len())?;
    }
    let n = designs.designs;
    for row in 0..n {
        variant(base, rpm, designs, row).map_err(|error| MechanismError::InRow {
            row,
            error: Box::new(error),
        })?;
    }
    let shared: Arc<[PiecewisePolynomial]> = base.diagrams.into();
    let in_row = |row: usize| {
        move |error| MechanismError::InRow {
            row,
            error: Box::new(error),
        }
    };
    let mut rows = Vec::with_capacity(n);
    for start in (0..n).step_by(BLOCK) {
        let block = start..(start + BLOCK).min(n);
        // The distinct gases and machines of the block, in order of their first design.
        let (gas_of, gas_firsts) = distinct(block.clone(), |row| row_key(designs, row, true));
        let (machine_of, firsts) = distinct(block.clone(), |row| row_key(designs, row, false));
        let work = |count: usize| {
            count
                .saturating_mul(base.units.len())
                .saturating_mul(WORK_PER_DESIGN_AND_UNIT)
        };
        let gases = map_indices(gas_firsts.len(), work(gas_firsts.len()), parallelism, |g| {
            let row = gas_firsts[g];
            variant(base, rpm, designs, row)
                .and_then(|v| gas(base, &shared, &v))
                .map(Arc::new)
                .map_err(in_row(row))
        });
        let gases = gases.into_iter().collect::<Result<Vec<_>>>()?;
        let made = map_indices(firsts.len(), work(firsts.len()), parallelism, |m| {
            let row = firsts[m];
            variant(base, rpm, designs, row)
                .and_then(|v| {
                    SteadyTables::with_gas(&v.machine(base), &gases[gas_of[row - block.start]])
                })
                .map_err(in_row(row))
        });
        let made = made.into_iter().collect::<Result<Vec<_>>>()?;
        let solved = map_indices(block.len(), work(block.len()), parallelism, |i| {
            let row = block.start + i;
            variant(base, rpm, designs, row)
                .and_then(|v| {
                    solve(
                        &made[machine_of[i]],
                        &v,
                        outputs,
                        target_delta,
                        min_speed_ratio,
                    )
                })
                .map_err(in_row(row))
        });
        for row in solved {
            rows.push(row?);
        }
    }
    let column = |asked: bool, get: fn(&Row) -> f64| -> Vec<f64> {
        if asked {
            rows.iter().map(get).collect()
        } else {
            Vec::new()
        }
    };
    Ok(MotionColumns {
        delta: column(outputs.delta, |r| r.delta),
        delta_without_gravity: column(outputs.delta_without_gravity, |r| r.delta_without_gravity),
        delta_gravity_only: column(outputs.delta_gravity_only, |r| r.delta_gravity_only),
        gravity_effect: column(outputs.gravity_effect, |r| r.gravity_effect),
        rpm_min: column(outputs.rpm_min, |r| r.rpm_min),
        rpm_max: column(outputs.rpm_max, |r| r.rpm_max),
        stalled: if outputs.steady() {
            rows.iter().map(|r| r.stalled).collect()
        } else {
            Vec::new()
        },
        flywheel_inertia: column(outputs.flywheel_inertia, |r| r.flywheel_inertia),
        flywheel_inertia_without_gravity: column(outputs.flywheel_inertia_without_gravity, |r| {
            r.flywheel_inertia_without_gravity
        }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gravity_effect_follows_the_python_rules() {
        assert_eq!(gravity_effect(0.03, 0.02), 0.03 / 0.02 - 1.0);
        assert!(gravity_effect(0.03, f64::NAN).is_nan());
        assert_eq!(gravity_effect(0.03, 0.0), f64::INFINITY);
        assert!(gravity_effect(0.0, 0.0).is_nan());
    }

    #[test]
    fn outputs_are_named_as_in_python() {
        let all = MotionOutputs::from_names(&MotionOutputs::NAMES).expect("known");
        assert!(all.steady() && all.flywheel());
        let stalled = MotionOutputs::from_names(&["stalled"]).expect("known");
        assert!(stalled.steady() && !stalled.delta && !stalled.flywheel());
        assert!(MotionOutputs::from_names(&["speed"]).is_err());
    }
}
