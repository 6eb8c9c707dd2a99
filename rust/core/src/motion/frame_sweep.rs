//! The frame's outputs of a motion sweep (docs/theory.md, "Forces on the frame", "Main-bearing
//! loads"): for every design at its speed, held constant, the largest magnitude over a cycle
//! of the first- and second-order shaking force and moment (forward + backward: the
//! ellipse's largest radius) and the largest main-bearing load over the working cycle. Each
//! row is the design's machine as the motion sweep's variant rule makes it, alone, so the
//! columns are bit-identical for any thread count.

use std::collections::HashMap;

use crate::error::{MechanismError, Result};
use crate::forces::{crank_trig, max_bearing_load, BearingLayout, LoadScratch, ShakingForces};
use crate::forces::{largest_bearing_load, throw_loads, FORCE_FORWARD, MOMENT_FORWARD};
use crate::parallel::{map_indices_with, Parallelism};

use super::columns::{MachineDesigns, UnitField};
use super::gas::PiecewisePolynomial;
use super::sweep::check_designs;
use super::variant::variant;
use super::MachineView;

/// The frame's outputs, in column order.
pub const FRAME_OUTPUTS: [&str; 5] = [
    "free_force_1",
    "free_force_2",
    "free_moment_1",
    "free_moment_2",
    "max_bearing_load",
];

/// Angles per working cycle at which a design's bearing loads are taken (every half degree
/// of a two-stroke cycle, every degree of a four-stroke one's).
pub const BEARING_ANGLES: usize = 720;

/// The default angles of the bearing loads: [`BEARING_ANGLES`] uniform ones over the working
/// cycle `cycle` (rad), iΦ/N.
pub fn default_angles(cycle: f64) -> Vec<f64> {
    (0..BEARING_ANGLES)
        .map(|i| cycle * i as f64 / BEARING_ANGLES as f64)
        .collect()
}

/// Kernel evaluations per design and unit, for `Parallelism`'s threshold: the free forces
/// alone are a few series terms; the bearing loads BEARING_ANGLES Newton–Euler solutions.
const FREE_WORK: usize = 256;

/// Which of [`FRAME_OUTPUTS`] to compute.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FrameOutputs([bool; 5]);

impl FrameOutputs {
    /// The outputs named (each from [`FRAME_OUTPUTS`]).
    pub fn from_names<S: AsRef<str>>(names: &[S]) -> Result<Self> {
        let mut asked = [false; 5];
        for name in names {
            let Some(i) = FRAME_OUTPUTS.iter().position(|o| *o == name.as_ref()) else {
                return Err(MechanismError::InvalidChoice {
                    parameter: "outputs",
                    value: name.as_ref().to_string(),
                    allowed:
                        "free_force_1, free_force_2, free_moment_1, free_moment_2, max_bearing_load",
                });
            };
            asked[i] = true;
        }
        Ok(Self(asked))
    }

    fn free(self) -> bool {
        self.0[..4].iter().any(|&a| a)
    }

    fn bearings(self) -> bool {
        self.0[4]
    }
}

/// The frame's outputs of every design of `designs` applied to `base` (mean speed `omega`,
/// rad/s, where there is no omega column), each unit at `axial_position` (m) and its throw
/// shared between the bearings of `bearings` (the base machine's, as
/// [`Machine::frame_sweep`](crate::Machine::frame_sweep) gives them, with its gas forces at
/// the [`default_angles`], `base_gas`, N, unit-major): one column per
/// [`FRAME_OUTPUTS`] name (N, N·m), empty where not asked. A bad value of design `row` is a
/// [`MechanismError::InRow`].
#[allow(clippy::too_many_arguments)]
pub(crate) fn frame_sweep(
    base: &MachineView<'_>,
    omega: Option<f64>,
    designs: &MachineDesigns<'_>,
    axial_position: &[f64],
    bearings: &BearingLayout,
    base_gas: &[f64],
    outputs: FrameOutputs,
    parallelism: Parallelism,
) -> Result<[Vec<f64>; 5]> {
    check_designs(base, designs)?;
    let n = designs.designs;
    let work = n
        .saturating_mul(base.units.len())
        .saturating_mul(if outputs.bearings() {
            BEARING_ANGLES * 8
        } else {
            FREE_WORK
        });
    let cycle = base.strokes.cycle_angle();
    let phi = default_angles(cycle);
    // The base units' (sin ψ, cos ψ): every design's that keeps their phases.
    let mut base_trig = Vec::new();
    if outputs.bearings() {
        crank_trig(base.units, &phi, &mut base_trig);
    }
    let base_gas = (base_gas, &base_trig[..]);
    let by_phase = if outputs.bearings() {
        PhaseLoads::new(base, omega, designs, &phi)?
    } else {
        None
    };
    let rows = map_indices_with(
        n,
        work,
        parallelism,
        LoadScratch::default,
        |scratch, row| {
            design_row(
                base,
                omega,
                designs,
                row,
                axial_position,
                bearings,
                base_gas,
                by_phase.as_ref(),
                outputs,
                &phi,
                scratch,
            )
            .map_err(|error| MechanismError::InRow {
                row,
                error: Box::new(error),
            })
        },
    );
    let mut columns: [Vec<f64>; 5] = Default::default();
    for (k, column) in columns.iter_mut().enumerate() {
        if outputs.0[k] {
            column.reserve(n);
        }
    }
    for row in rows {
        let row = row?;
        for (k, column) in columns.iter_mut().enumerate() {
            if outputs.0[k] {
                column.push(row[k]);
            }
        }
    }
    Ok(columns)
}

#[allow(clippy::too_many_arguments)]
fn design_row(
    base: &MachineView<'_>,
    omega: Option<f64>,
    designs: &MachineDesigns<'_>,
    row: usize,
    axial_position: &[f64],
    bearings: &BearingLayout,
    (base_gas, base_trig): (&[f64], &[(f64, f64)]),
    by_phase: Option<&PhaseLoads>,
    outputs: FrameOutputs,
    phi: &[f64],
    scratch: &mut LoadScratch,
) -> Result<[f64; 5]> {
    let v = variant(base, omega, designs, row)?;
    let mut found = [f64::NAN; 5];
    if outputs.free() {
        let table = ShakingForces::new(&v.units, axial_position)?
            .orders(2)?
            .at(v.omega, 2)?;
        // The largest magnitude over a cycle of orders 1 and 2: forward + backward.
        for (slot, forward) in [(0, FORCE_FORWARD), (2, MOMENT_FORWARD)] {
            for order in 0..2 {
                found[slot + order] = table[forward][order] + table[forward + 1][order];
            }
        }
    }
    if let (true, Some(by_phase)) = (outputs.bearings(), by_phase) {
        found[4] = by_phase.largest(&v.units, bearings, phi.len(), scratch);
    } else if outputs.bearings() {
        let machine = v.machine(base);
        // The base machine's gas forces serve where the design keeps its gas and phases
        // (times its pressure scale: the diagrams' coefficients scaled, to rounding).
        let same_phases = v
            .units
            .iter()
            .zip(base.units)
            .all(|(a, b)| a.phase == b.phase);
        let same_gas = same_phases && machine.gas == base.gas;
        let (gas, scale) = if same_gas {
            (None, v.pressure_scale.unwrap_or(1.0))
        } else {
            let scaled: Vec<PiecewisePolynomial>;
            let diagrams = match v.pressure_scale {
                Some(factor) => {
                    scaled = base.diagrams.iter().map(|d| d.scaled(factor)).collect();
                    &scaled[..]
                }
                None => base.diagrams,
            };
            let machine = MachineView {
                diagrams,
                ..machine
            };
            (Some(machine.piston_forces(phi)?), 1.0)
        };
        found[4] = max_bearing_load(
            &v.units,
            bearings,
            phi,
            v.omega,
            gas.as_deref().unwrap_or(base_gas),
            scale,
            v.g,
            same_phases.then_some(base_trig),
            scratch,
        );
    }
    Ok(found)
}

/// The throw loads of every unit at every phase it takes, where the designs change nothing but
/// the units' phases (a firing order's candidates): a unit's loads on its throw depend on its
/// own phase alone, so they are made once per distinct (unit, phase) — a crank's cylinders
/// take few — and a design's largest bearing load sums its units' ([`largest_bearing_load`]):
/// the same doubles as its own machine's, a few multiply-adds per unit and angle.
struct PhaseLoads {
    /// (unit, phase's bits) → its loads' index in `loads`.
    index: HashMap<(usize, u64), usize>,
    loads: Vec<Vec<[f64; 2]>>,
}

impl PhaseLoads {
    /// The loads of every (unit, phase) of `designs` at the angles `phi` (rad); `None` where a
    /// design changes anything else than phases (I_w aside: it changes no frame output), or
    /// the designs' speed or g differ (a column of one value is the base's).
    fn new(
        base: &MachineView<'_>,
        omega: Option<f64>,
        designs: &MachineDesigns<'_>,
        phi: &[f64],
    ) -> Result<Option<Self>> {
        let one_value = |column: &[f64]| column.iter().all(|v| v.to_bits() == column[0].to_bits());
        let only_phases = designs
            .named()
            .iter()
            .all(|(name, _, column)| match column {
                None => true,
                Some(_) if *name == "shaft_inertia" => true,
                Some(column) => (*name == "omega" || *name == "g") && one_value(column),
            })
            && designs.units.iter().all(|c| c.field == UnitField::Phase);
        if !only_phases || designs.designs == 0 {
            return Ok(None);
        }
        // Every design's speed and g: the first's.
        let first = variant(base, omega, designs, 0)?;
        let (omega, g) = (first.omega, first.g);
        let mut found = Self {
            index: HashMap::new(),
            loads: Vec::new(),
        };
        for row in 0..designs.designs {
            for (j, unit) in variant(base, Some(omega), designs, row)?
                .units
                .iter()
                .enumerate()
            {
                let key = (j, unit.phase.to_bits());
                if found.index.contains_key(&key) {
                    continue;
                }
                let alone = MachineView {
                    units: std::slice::from_ref(unit),
                    gas: &base.gas[j..=j],
                    ..*base
                };
                let mut loads = Vec::with_capacity(phi.len());
                throw_loads(unit, phi, omega, &alone.piston_forces(phi)?, g, &mut loads);
                found.index.insert(key, found.loads.len());
                found.loads.push(loads);
            }
        }
        Ok(Some(found))
    }

    /// The largest bearing load of the design whose units are `units`.
    fn largest(
        &self,
        units: &[crate::mechanism::PhysicalCylinder],
        layout: &BearingLayout,
        points: usize,
        scratch: &mut LoadScratch,
    ) -> f64 {
        let per_unit: Vec<&[[f64; 2]]> = units
            .iter()
            .enumerate()
            .map(|(j, unit)| &self.loads[self.index[&(j, unit.phase.to_bits())]][..])
            .collect();
        largest_bearing_load(layout, &per_unit, points, scratch.bearings())
    }
}
