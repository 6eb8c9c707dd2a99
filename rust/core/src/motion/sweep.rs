//! Motion at sweep scale: the steady state (and the flywheel) of many variants of one
//! machine, one row each (the Python API's `motion_sweep`, its `_solve_chunk`).
//!
//! A design is the base machine with some numbers replaced (`MachineDesigns`); each row is
//! what `steady_state` and `flywheel_inertia` give for that design's machine — the same
//! solves on the same tables, less what was not asked for: bit for bit where the design's
//! tables are made as its machine's own, to rounding (1e-12) where they are another design's
//! with the gas scaled (`Scaling`: pressure_scale, bore) or U reweighted (`webs`: crank webs
//! and counterweights). Designs whose gases differ in r or l alone take the first one's
//! indicator rules (`Level::Pressures`), which changes no double. Every row is solved on
//! its own, its tables made from the same first designs whatever the threads, so the
//! columns are bit-identical for any thread count.

use std::collections::HashMap;
use std::sync::Arc;

use crate::dynamics::Dynamics;
use crate::error::{check, check_length, MechanismError, Result};
use crate::parallel::{map_indices, Parallelism};

use super::columns::{Changes, MachineDesigns, MotionColumns, MotionOutputs};
use super::cycle::Gas;
use super::gas::{GasCylinder, PiecewisePolynomial};
use super::variant::{gas, variant, Variant};
use super::webs::Kinematics;
use super::{check_speed_ratio, flywheel, MachineView, SteadyTables};

/// One design's numbers (NaN where not asked).
#[derive(Debug, Clone, Copy)]
struct Row {
    delta: f64,
    delta_without_gravity: f64,
    delta_coasting: f64,
    gravity_effect: f64,
    omega_min: f64,
    omega_max: f64,
    stalled: bool,
    flywheel_inertia: f64,
    flywheel_inertia_without_gravity: f64,
}

impl Row {
    const NONE: Self = Self {
        delta: f64::NAN,
        delta_without_gravity: f64::NAN,
        delta_coasting: f64::NAN,
        gravity_effect: f64::NAN,
        omega_min: f64::NAN,
        omega_max: f64::NAN,
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

/// A steady state costs a few thousand kernel evaluations per unit: the `work` per design
/// and unit given to `Parallelism` (whose threshold counts points × cranks).
const WORK_PER_DESIGN_AND_UNIT: usize = 4096;

/// The base machine's own faults (not a row's) and the designs' columns: each as long as
/// the designs, each unit column of a unit the machine has.
pub(super) fn check_designs(base: &MachineView<'_>, designs: &MachineDesigns<'_>) -> Result<()> {
    Dynamics::new(base.units, base.g)?;
    check_length("gas", base.units.len(), base.gas.len())?;
    for gas in base.gas {
        gas.validate(base.diagrams.len())?;
    }
    for (name, _, column) in designs.named() {
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
    Ok(())
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
    let omega_mean = variant.omega;
    let mut row = Row::NONE;
    if outputs.steady() {
        match tables.solve(inertia, omega_mean, ratio)?.periodic {
            Some(solution) if solution.delta().is_finite() => {
                let delta = solution.delta();
                row.delta = delta;
                // The row's mean speed is the ω_m asked for, which the solution's ω_m
                // meets to rounding: the extremes keep it between them to the last ulp.
                row.omega_min = solution.omega_min.min(omega_mean);
                row.omega_max = solution.omega_max.max(omega_mean);
                if outputs.delta_without_gravity || outputs.gravity_effect {
                    let without = tables
                        .delta_without_gravity(inertia, omega_mean, ratio)?
                        .unwrap_or(delta);
                    row.delta_without_gravity = without;
                    row.gravity_effect = gravity_effect(delta, without);
                }
                if outputs.delta_coasting {
                    row.delta_coasting =
                        tables.delta_coasting(inertia, solution.omega_mean, ratio)?;
                }
            }
            _ => row.stalled = true,
        }
    }
    if let (true, Some(delta)) = (outputs.flywheel(), target) {
        let without = outputs.flywheel_inertia_without_gravity;
        match tables.flywheel_inertia(delta, omega_mean, ratio, inertia, without) {
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
/// share their machine's tables (made once per distinct machine), and machines that differ
/// only in the gas's scale or the webs share what of them does not change; a block bounds
/// the tables held at once (~100 kB each).
const BLOCK: usize = 512;

/// How the designs' gas forces scale: W and M_gas are linear in the pressures and, where
/// every crank end's area is the bore's (no piston rod), proportional to the bore's area,
/// so designs that differ only in `pressure_scale` (or bore) share one gas, scaled.
#[derive(Debug, Clone, Copy)]
struct Scaling {
    bore: bool,
}

impl Scaling {
    fn of(base: &MachineView<'_>, designs: &MachineDesigns<'_>) -> Self {
        let no_rod = |gas: &GasCylinder| gas.crank_end.is_none() || gas.piston_rod_diameter == 0.0;
        Self {
            bore: designs.bore.is_some() && base.gas.iter().all(no_rod),
        }
    }

    /// Whether the column `name` is scaled rather than keyed.
    fn scales(self, name: &str) -> bool {
        name == "pressure_scale" || (self.bore && name == "bore")
    }

    /// What multiplies design `row`'s pressures times areas: pressure_scale·D² (1 for a
    /// column not scaled).
    fn factor(self, designs: &MachineDesigns<'_>, row: usize) -> f64 {
        let scale = designs.pressure_scale.map_or(1.0, |c| c[row]);
        let bore = match (self.bore, designs.bore) {
            (true, Some(c)) => c[row],
            _ => 1.0,
        };
        scale * (bore * bore)
    }

    /// Design `row`'s gas times `factor` of `other`'s (`None`: the same).
    fn ratio(self, designs: &MachineDesigns<'_>, row: usize, other: usize) -> Option<f64> {
        let (own, theirs) = (self.factor(designs, row), self.factor(designs, other));
        (own != theirs).then(|| own / theirs)
    }
}

/// How much of a design's machine a key tells apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Level {
    /// Its pressures: the gas's columns but those of `KINEMATIC` (their bits, scaled or
    /// not), and the units' phases — what its indicator rules' panels and forces depend on.
    Pressures,
    /// Its gas up to `Scaling` (the gas's columns, the units' phases).
    Gas,
    /// Its machine up to `Scaling` and its crank webs and counterweights (`webs`).
    Kinematics,
    /// Its machine up to `Scaling`.
    Shape,
    /// Its machine's tables, bit for bit (every column but `shaft_inertia` and `omega`).
    Machine,
}

/// The columns of the crank webs and counterweights: they enter U alone (`webs`).
const WEBS: [&str; 4] = [
    "crank_mass",
    "crank_cg_radius",
    "counterweight_mass",
    "counterweight_radius",
];

/// The gas's columns that move its pistons, not its pressures on them: designs that differ
/// in these alone share their indicator rules ([`Gas::new`]'s `like`).
///
/// [`Gas::new`]: super::cycle::Gas::new
const KINEMATIC: [&str; 2] = ["crank_radius", "rod_length"];

/// What of design `row` tells its machine apart at `level`: below `Machine`, the columns
/// `scaling` scales only by whether they are 0 (where the gas, or its cuts, is no scaled
/// one).
fn row_key(designs: &MachineDesigns<'_>, row: usize, level: Level, scaling: Scaling) -> Vec<u64> {
    let shared = designs
        .named()
        .into_iter()
        .filter(|(name, changes, _)| match level {
            Level::Pressures => *changes == Changes::Gas && !KINEMATIC.contains(name),
            Level::Gas => *changes == Changes::Gas,
            Level::Kinematics => *changes != Changes::Nothing && !WEBS.contains(name),
            Level::Shape | Level::Machine => *changes != Changes::Nothing,
        })
        .filter_map(|(name, _, column)| {
            let value = column?[row];
            let scaled = !matches!(level, Level::Pressures | Level::Machine);
            Some(if scaled && scaling.scales(name) {
                u64::from(value == 0.0)
            } else {
                value.to_bits()
            })
        });
    // A unit's own column is its phase or its counterweight (a web).
    let units = designs
        .units
        .iter()
        .filter(|c| matches!(level, Level::Shape | Level::Machine) || c.field.changes_gas())
        .map(|c| c.values[row].to_bits());
    shared.chain(units).collect()
}

/// `make(k)` for every k `shared` (in parallel when `parallelism` says so for `work`),
/// `None` for the rest.
fn made_first<T: Send>(
    shared: &[bool],
    work: usize,
    parallelism: Parallelism,
    make: &(dyn Fn(usize) -> Result<T> + Sync),
) -> Result<Vec<Option<T>>> {
    map_indices(shared.len(), work, parallelism, |k| {
        shared[k].then(|| make(k)).transpose()
    })
    .into_iter()
    .collect()
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
/// that δ) of every design: `base` with the design's columns applied, at the design's mean
/// speed `omega` (rad/s), or at `omega` where there is no omega column. Each row equals [`steady_state`] and
/// [`flywheel_inertia`] of that design's machine (same `min_speed_ratio`) to 1e-12 (bit for
/// bit where nothing of its tables is shared scaled or reweighted); only `outputs`
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
    base: &MachineView<'_>,
    omega: Option<f64>,
    designs: &MachineDesigns<'_>,
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
    check_designs(base, designs)?;
    let n = designs.designs;
    for row in 0..n {
        variant(base, omega, designs, row).map_err(|error| MechanismError::InRow {
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
    let scaling = Scaling::of(base, designs);
    let mut rows = Vec::with_capacity(n);
    for start in (0..n).step_by(BLOCK) {
        let block = start..(start + BLOCK).min(n);
        // The distinct gases and machines of the block, in order of their first design: at
        // each level of `Level`.
        let of =
            |level: Level| distinct(block.clone(), |row| row_key(designs, row, level, scaling));
        let (gas_of, gas_firsts) = of(Level::Gas);
        let (kin_of, kin_firsts) = of(Level::Kinematics);
        let (shape_of, shape_firsts) = of(Level::Shape);
        let (machine_of, firsts) = of(Level::Machine);
        let work = |count: usize| {
            count
                .saturating_mul(base.units.len())
                .saturating_mul(WORK_PER_DESIGN_AND_UNIT)
        };
        // What more than one design of the block takes is made first and shared; what one
        // design alone takes is made where it is solved and dropped there (a block of
        // distinct designs never holds all their tables at once).
        let shared_by = |of: &[usize], count: usize| {
            let mut designs = vec![0_usize; count];
            of.iter().for_each(|&k| designs[k] += 1);
            designs.into_iter().map(|d| d > 1).collect::<Vec<bool>>()
        };
        let (gas_shared, kin_shared, shape_shared, machine_shared) = (
            shared_by(&gas_of, gas_firsts.len()),
            shared_by(&kin_of, kin_firsts.len()),
            shared_by(&shape_of, shape_firsts.len()),
            shared_by(&machine_of, firsts.len()),
        );
        // Gases on the same pressures (differing in r or l) take their indicator rules from
        // the first of them, which is made first where it has followers.
        let (pressure_of, pressure_firsts) = distinct(gas_firsts.iter().copied(), |row| {
            row_key(designs, row, Level::Pressures, scaling)
        });
        let leader_of: Vec<usize> = pressure_of
            .iter()
            .map(|&p| gas_of[pressure_firsts[p] - block.start])
            .collect();
        let leads = shared_by(&leader_of, gas_firsts.len());
        let make = |g: usize, like: Option<&Gas>| {
            let row = gas_firsts[g];
            variant(base, omega, designs, row)
                .and_then(|v| gas(base, &shared, &v, like))
                .map(Arc::new)
                .map_err(in_row(row))
        };
        let leaders = made_first(&leads, work(leads.len()), parallelism, &|g| make(g, None))?;
        let make_gas = |g: usize| make(g, leaders[leader_of[g]].as_deref());
        let followers_shared: Vec<bool> = (0..gas_firsts.len())
            .map(|g| gas_shared[g] && !leads[g])
            .collect();
        let followers = made_first(
            &followers_shared,
            work(gas_shared.len()),
            parallelism,
            &make_gas,
        )?;
        let gas_for = |g: usize| match (&leaders[g], &followers[g]) {
            (Some(made), _) | (_, Some(made)) => Ok(Arc::clone(made)),
            _ => make_gas(g),
        };
        // The tables of design `row`, its gas that of its gas's first design scaled where
        // it differs.
        let tabulate = |row: usize| {
            let g = gas_of[row - block.start];
            let own = gas_for(g)?;
            let gas = match scaling.ratio(designs, row, gas_firsts[g]) {
                Some(factor) => Arc::new(own.scaled(factor)),
                None => own,
            };
            variant(base, omega, designs, row)
                .and_then(|v| SteadyTables::with_gas(&v.machine(base), &gas))
                .map(Arc::new)
                .map_err(in_row(row))
        };
        let make_kin = |k: usize| tabulate(kin_firsts[k]).map(|t| Arc::new(Kinematics::new(t)));
        let kins = made_first(&kin_shared, work(kin_shared.len()), parallelism, &make_kin)?;
        let kin_for = |k: usize| kins[k].clone().map_or_else(|| make_kin(k), Ok);
        // A shape: its kinematics' tables with its own webs (their gas scaled as for the
        // kinematics' first design, the row returned), else tabulated.
        let make_shape = |s: usize| {
            let row = shape_firsts[s];
            let k = kin_of[row - block.start];
            let first = kin_firsts[k];
            if first == row {
                return Ok((Arc::clone(&kin_for(k)?.tables), row));
            }
            let from = variant(base, omega, designs, first).map_err(in_row(first))?;
            let reweighted = variant(base, omega, designs, row)
                .and_then(|v| kin_for(k)?.reweighted(&from.units, &v.machine(base)))
                .map(|found| found.map(Arc::new))
                .map_err(in_row(row))?;
            match reweighted {
                Some(tables) => Ok((tables, first)),
                None => Ok((tabulate(row)?, row)),
            }
        };
        let shapes = made_first(
            &shape_shared,
            work(shape_shared.len()),
            parallelism,
            &make_shape,
        )?;
        let shape_for = |s: usize| shapes[s].clone().map_or_else(|| make_shape(s), Ok);
        // A machine: its shape's tables, their gas scaled where it differs.
        let make_machine = |m: usize| {
            let row = firsts[m];
            let (tables, scaled_as) = shape_for(shape_of[row - block.start])?;
            match scaling.ratio(designs, row, scaled_as) {
                Some(factor) => tables.gas_scaled(factor).map(Arc::new).map_err(in_row(row)),
                None => Ok(tables),
            }
        };
        let made = made_first(
            &machine_shared,
            work(machine_shared.len()),
            parallelism,
            &make_machine,
        )?;
        let solved = map_indices(block.len(), work(block.len()), parallelism, |i| {
            let row = block.start + i;
            let m = machine_of[i];
            let tables = made[m].clone().map_or_else(|| make_machine(m), Ok)?;
            variant(base, omega, designs, row)
                .and_then(|v| solve(&tables, &v, outputs, target_delta, min_speed_ratio))
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
        delta_coasting: column(outputs.delta_coasting, |r| r.delta_coasting),
        gravity_effect: column(outputs.gravity_effect, |r| r.gravity_effect),
        omega_min: column(outputs.omega_min, |r| r.omega_min),
        omega_max: column(outputs.omega_max, |r| r.omega_max),
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
