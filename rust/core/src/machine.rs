//! What a machine is, whole and checked once: its slider-crank units, their gas (the
//! indicator diagrams as periodic piecewise polynomials), I_w, the strokes, g, where each
//! unit sits along the shaft and the main bearings there ([`BearingLayout`], the rules of
//! throws and bearings in one place). Everything the core answers about a machine borrows
//! it: its gravity and kinematics ([`Dynamics`]), its motion (a [`MachineView`] for the
//! steady state, the flywheel, the torque orders and the sweeps, and the cycle's tables made
//! on first use and kept), its shaking forces (made on first use and kept) and its bearing
//! loads. The Python package's `Machine` (python/multicrank/machine/machine.py) becomes one
//! of these once, in python/multicrank/machine/native.py.

use std::sync::OnceLock;

use crate::dynamics::Dynamics;
use crate::error::Result;
use crate::forces::{bearing_loads, frame_torque, BearingLayout, BearingParts, ShakingForces};
use crate::mechanism::{check_shaft_inertia, PhysicalCylinder, Strokes};
use crate::motion::{default_angles, GasForces, PiecewisePolynomial, SteadyTables};
use crate::motion::{frame_sweep, FrameOutputs, GasCylinder, MachineDesigns, MachineView};
use crate::parallel::Parallelism;

/// A machine as it is given, before its checks: the input of [`Machine::new`].
#[derive(Debug, Clone)]
pub struct MachineParts {
    /// The slider-crank units, at least one.
    pub units: Vec<PhysicalCylinder>,
    /// Their gas, one per unit ([`GasCylinder::NONE`] where there is none).
    pub gas: Vec<GasCylinder>,
    /// The pressures (Pa) the units' `head` and `crank_end` refer to, each periodic over the
    /// working cycle.
    pub diagrams: Vec<PiecewisePolynomial>,
    /// I_w (kg·m²) > 0: everything that turns rigidly with the shaft.
    pub shaft_inertia: f64,
    pub strokes: Strokes,
    /// g (m/s²), finite (0: none).
    pub g: f64,
    /// Each unit's position z (m) along the shaft.
    pub axial_position: Vec<f64>,
    /// The main bearings' positions (m), or None for bearings interleaving the throws.
    pub main_bearings: Option<Vec<f64>>,
}

/// A machine, checked once ([`Machine::new`]) and immutable; safe to share between threads.
/// What is made from it on first use (the cycle's tables, with and without gravity, and the
/// shaking forces) is kept: two threads may both make one, one is kept, and both are the
/// same doubles.
#[derive(Debug)]
pub struct Machine {
    parts: MachineParts,
    layout: BearingLayout,
    dynamics: Dynamics,
    tables: OnceLock<SteadyTables>,
    tables_without_gravity: OnceLock<SteadyTables>,
    shaking: OnceLock<ShakingForces>,
    /// Its gas forces' rule (the diagrams shared), made on first use.
    gas_forces: OnceLock<GasForces>,
    /// The gas forces at the default angles ([`default_angles`]), made on first use.
    default_gas: OnceLock<Vec<f64>>,
    /// The parts of its bearing loads at the default angles, with and without gravity's
    /// being asked for (g's part is kept either way), made on first use.
    bearing_parts: OnceLock<BearingParts>,
}

impl Machine {
    /// `parts` checked, every refusal naming its parameter: the units (each unit's rules),
    /// their gas (one per unit, each diagram spanning the working cycle), I_w > 0, g finite,
    /// one finite axial position per unit and the main bearings' rules
    /// ([`BearingLayout::new`], the default bearings set at the largest crank radius).
    pub fn new(parts: MachineParts) -> Result<Self> {
        let dynamics = Dynamics::new(&parts.units, parts.g)?;
        check_shaft_inertia(parts.shaft_inertia)?;
        crate::error::check_length(
            "axial_position",
            parts.units.len(),
            parts.axial_position.len(),
        )?;
        let crank_radius = parts
            .units
            .iter()
            .fold(0.0_f64, |r, u| r.max(u.crank_radius));
        let layout = BearingLayout::new(
            &parts.axial_position,
            parts.main_bearings.as_deref(),
            crank_radius,
        )?;
        let machine = Self {
            parts,
            layout,
            dynamics,
            tables: OnceLock::new(),
            tables_without_gravity: OnceLock::new(),
            shaking: OnceLock::new(),
            gas_forces: OnceLock::new(),
            default_gas: OnceLock::new(),
            bearing_parts: OnceLock::new(),
        };
        machine.view().check_gas()?;
        Ok(machine)
    }

    /// The machine as its motion takes it.
    pub fn view(&self) -> MachineView<'_> {
        self.view_with(true)
    }

    /// The machine as its motion takes it, with g = 0 unless `gravity`.
    pub fn view_with(&self, gravity: bool) -> MachineView<'_> {
        let parts = &self.parts;
        MachineView {
            units: &parts.units,
            gas: &parts.gas,
            diagrams: &parts.diagrams,
            shaft_inertia: parts.shaft_inertia,
            strokes: parts.strokes,
            g: if gravity { parts.g } else { 0.0 },
        }
    }

    pub fn units(&self) -> &[PhysicalCylinder] {
        &self.parts.units
    }

    /// The number of units.
    pub fn len(&self) -> usize {
        self.parts.units.len()
    }

    /// Never true: a machine has a unit at least.
    pub fn is_empty(&self) -> bool {
        self.parts.units.is_empty()
    }

    pub fn gas(&self) -> &[GasCylinder] {
        &self.parts.gas
    }

    pub fn diagrams(&self) -> &[PiecewisePolynomial] {
        &self.parts.diagrams
    }

    /// I_w (kg·m²).
    pub fn shaft_inertia(&self) -> f64 {
        self.parts.shaft_inertia
    }

    pub fn strokes(&self) -> Strokes {
        self.parts.strokes
    }

    /// g (m/s²).
    pub fn g(&self) -> f64 {
        self.parts.g
    }

    /// Each unit's axial position z (m).
    pub fn axial_position(&self) -> &[f64] {
        &self.parts.axial_position
    }

    /// Its throws and main bearings.
    pub fn layout(&self) -> &BearingLayout {
        &self.layout
    }

    /// Its gravity and kinematics (J, J′, U, the torques), with the machine's g.
    pub fn dynamics(&self) -> &Dynamics {
        &self.dynamics
    }

    /// The cycle's tables of the machine as it is (`gravity`), or with g = 0: made on first
    /// use, the g = 0 ones from the first (no second tabulation).
    pub fn tables(&self, gravity: bool) -> Result<&SteadyTables> {
        let tables = match self.tables.get() {
            Some(tables) => tables,
            None => {
                let made = SteadyTables::new(&self.view())?;
                self.tables.get_or_init(|| made)
            }
        };
        if gravity || self.parts.g == 0.0 {
            return Ok(tables);
        }
        if let Some(without) = self.tables_without_gravity.get() {
            return Ok(without);
        }
        let made = tables.without_gravity()?;
        Ok(self.tables_without_gravity.get_or_init(|| made))
    }

    /// Its shaking forces (the units at their axial positions, moments about the engine
    /// centre), made on first use.
    pub fn shaking_forces(&self) -> Result<&ShakingForces> {
        if let Some(forces) = self.shaking.get() {
            return Ok(forces);
        }
        let made = ShakingForces::new(&self.parts.units, &self.parts.axial_position)?;
        Ok(self.shaking.get_or_init(|| made))
    }

    /// Every unit's gas force F = p·A − p_c·A_c (N, toward the shaft) at every φ (rad),
    /// unit-major (units × phi), from the machine's own diagrams (their rule made once).
    pub fn piston_forces(&self, phi: &[f64]) -> Result<Vec<f64>> {
        Ok(self.gas_forces()?.at(phi))
    }

    fn gas_forces(&self) -> Result<&GasForces> {
        if let Some(forces) = self.gas_forces.get() {
            return Ok(forces);
        }
        let made = self.view().gas_forces()?;
        Ok(self.gas_forces.get_or_init(|| made))
    }

    /// The gas forces (N, unit-major) at the default angles (the
    /// [`BEARING_ANGLES`](crate::BEARING_ANGLES) uniform angles iΦ/N over the working cycle),
    /// made on first use.
    pub fn default_piston_forces(&self) -> Result<&[f64]> {
        if let Some(gas) = self.default_gas.get() {
            return Ok(gas);
        }
        let made = self.piston_forces(&default_angles(self.parts.strokes.cycle_angle()))?;
        Ok(self.default_gas.get_or_init(|| made))
    }

    /// The parts of its bearing loads at the default angles ([`BearingParts`]), made on
    /// first use.
    pub fn bearing_parts(&self) -> Result<&BearingParts> {
        if let Some(parts) = self.bearing_parts.get() {
            return Ok(parts);
        }
        let phi = default_angles(self.parts.strokes.cycle_angle());
        let made = BearingParts::new(
            &self.parts.units,
            &self.layout,
            &phi,
            self.default_piston_forces()?,
        )?;
        Ok(self.bearing_parts.get_or_init(|| made))
    }

    /// The force every main bearing receives from the shaft (N; horizontal and vertical,
    /// bearing-major, bearings × angles) at the default angles (the
    /// [`BEARING_ANGLES`](crate::BEARING_ANGLES) uniform ones over the working cycle) at the
    /// constant speed `omega` (rad/s), the gas forces times `pressure_scale` (a load law's
    /// factor; 1: as given) and, with `gravity`, the weights: [`Machine::bearing_loads`] at
    /// those angles to rounding, from the parts kept ([`Machine::bearing_parts`]).
    pub fn bearing_loads_at_speed(
        &self,
        omega: f64,
        pressure_scale: f64,
        gravity: bool,
        horizontal: &mut [f64],
        vertical: &mut [f64],
    ) -> Result<()> {
        let g = if gravity { self.parts.g } else { 0.0 };
        self.bearing_parts()?
            .at_speed(omega, pressure_scale, g, horizontal, vertical)
    }

    /// The force every main bearing receives from the shaft (N; horizontal and vertical,
    /// bearing-major, bearings × phi) at the crank angles `phi` (rad) with the speed `omega`
    /// (rad/s) and acceleration `acceleration` (rad/s²) there: the machine's gas forces and,
    /// with `gravity`, its weights ([`bearing_loads`]).
    #[allow(clippy::too_many_arguments)]
    pub fn bearing_loads(
        &self,
        phi: &[f64],
        omega: &[f64],
        acceleration: &[f64],
        gravity: bool,
        horizontal: &mut [f64],
        vertical: &mut [f64],
        parallelism: Parallelism,
    ) -> Result<()> {
        let gas = self.piston_forces(phi)?;
        let g = if gravity { self.parts.g } else { 0.0 };
        bearing_loads(
            &self.parts.units,
            &self.layout,
            phi,
            omega,
            acceleration,
            &gas,
            g,
            horizontal,
            vertical,
            parallelism,
        )
    }

    /// The torque the frame receives about the shaft axis (N·m) at the crank angles `phi`
    /// (rad) with the speed `omega` and acceleration `acceleration` there ([`frame_torque`]).
    pub fn frame_torque(
        &self,
        phi: &[f64],
        omega: &[f64],
        acceleration: &[f64],
        out: &mut [f64],
    ) -> Result<()> {
        let gas = self.piston_forces(phi)?;
        frame_torque(
            &self.parts.units,
            phi,
            omega,
            acceleration,
            &gas,
            self.parts.g,
            out,
        )
    }

    /// The frame's outputs of every design of `designs` applied to this machine (mean speed
    /// `omega`, rad/s, where there is no omega column), held at its speed: the largest
    /// magnitude over a cycle of the first- and second-order shaking force and moment and the
    /// largest main-bearing load, one column per [`FRAME_OUTPUTS`](crate::FRAME_OUTPUTS)
    /// name (N, N·m), empty where not asked. A bad value of design `row` is a
    /// [`MechanismError::InRow`](crate::MechanismError::InRow).
    pub fn frame_sweep(
        &self,
        omega: Option<f64>,
        designs: &MachineDesigns<'_>,
        outputs: FrameOutputs,
        parallelism: Parallelism,
    ) -> Result<[Vec<f64>; 5]> {
        frame_sweep(
            &self.view(),
            omega,
            designs,
            &self.parts.axial_position,
            &self.layout,
            self.default_piston_forces()?,
            outputs,
            parallelism,
        )
    }
}
