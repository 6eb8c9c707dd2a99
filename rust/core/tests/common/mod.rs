//! The motion fixtures (tests/data/motion_fixtures.json, written by
//! tests/data/make_motion_fixtures.py): built-in machines' parameters and what an independent
//! oracle (tests/data/oracle.py: planar geometry, complex-step derivatives, SciPy) says of
//! their steady running. Shared by the motion test files; each uses part of it.
#![allow(dead_code)]

use multicrank_core::{
    steady_state, GasCylinder, MachineView, PhysicalCylinder, PiecewisePolynomial, SteadyState,
    Strokes,
};
use serde_json::Value;

pub const FIXTURES: &str = include_str!("../data/motion_fixtures.json");

/// The fixtures' key for δ of the machine coasting (gas, drive and load removed; gravity and
/// J(φ)'s variation alone), the core's `SteadyState::delta_coasting`: the oracle's own
/// vocabulary (tests/data/make_motion_fixtures.py), kept so the fixture file stays as written.
pub const COASTING_KEY: &str = "delta_gravity_only";

pub fn number(value: &Value, key: &str) -> f64 {
    value[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is not a number"))
}

pub fn array(value: &Value, key: &str) -> Vec<f64> {
    value[key]
        .as_array()
        .unwrap_or_else(|| panic!("{key} is not an array"))
        .iter()
        .map(|v| v.as_f64().expect("a number"))
        .collect()
}

/// ω = πn/30 (rad/s) of a speed n (1/min): the fixtures' speeds are in 1/min, the core's
/// in rad/s (2π rad a revolution, 60 s a minute).
pub fn omega(rpm: f64) -> f64 {
    rpm * std::f64::consts::PI / 30.0
}

/// n = 30ω/π (1/min) of a speed ω (rad/s): the inverse of [`omega`].
pub fn rpm(omega: f64) -> f64 {
    omega * 30.0 / std::f64::consts::PI
}

pub fn relative(found: f64, expected: f64) -> f64 {
    (found - expected).abs() / expected.abs()
}

pub struct Fixture {
    pub name: String,
    pub units: Vec<PhysicalCylinder>,
    pub gas: Vec<GasCylinder>,
    pub diagrams: Vec<PiecewisePolynomial>,
    pub shaft_inertia: f64,
    pub strokes: Strokes,
    pub g: f64,
    pub rpm: f64,
    /// The oracle's steady state at the machine's speed (load "balance").
    pub expected: Value,
    /// Near stall, each {rpm, steady_state, curves}.
    pub near_stall: Vec<Value>,
    /// Below the lowest running speed, each {rpm, angle, min_rpm}.
    pub stalls: Vec<Value>,
    /// Flywheels, each {delta, shaft_inertia, shaft_inertia_without_gravity, textbook,
    /// energy_swing}.
    pub flywheels: Vec<Value>,
    /// ω(φ) and t(φ) at the machine's speed: {phi, omega, time}.
    pub curves: Value,
    /// Square-law loads, each {torque, rpm, drive, coefficient, …, curves}.
    pub square_law: Vec<Value>,
}

/// The fixtures' JSON.
pub fn data() -> Value {
    serde_json::from_str(FIXTURES).expect("the fixtures parse")
}

/// A fixture's diagram (the oracle's `PPoly` arrays x and c), every coefficient times `scale`
/// (a design's pressure_scale, as the sweep applies it; ×1 leaves each one as it is).
pub fn diagram(d: &Value, cycle: f64, scale: f64) -> PiecewisePolynomial {
    let x = array(d, "x");
    let c: Vec<f64> = d["c"]
        .as_array()
        .expect("c")
        .iter()
        .flat_map(|row| row.as_array().expect("c row").iter())
        .map(|v| v.as_f64().expect("c") * scale)
        .collect();
    PiecewisePolynomial::new(x, c, cycle).expect("a valid diagram")
}

/// The JSON of the machine named `name`.
pub fn machine_json(name: &str) -> Value {
    data()["machines"]
        .as_array()
        .expect("machines")
        .iter()
        .find(|m| m["name"] == name)
        .expect("the fixture")
        .clone()
}

pub fn fixtures() -> Vec<Fixture> {
    let data = data();
    let machines = data["machines"].as_array().expect("machines");
    machines.iter().map(fixture).collect()
}

pub fn fixture_named(name: &str) -> Fixture {
    fixture(&machine_json(name))
}

fn fixture(m: &Value) -> Fixture {
    let strokes =
        Strokes::from_count(m["strokes"].as_i64().expect("strokes")).expect("2 or 4 strokes");
    let cycle = strokes.cycle_angle();
    let diagrams = m["diagrams"]
        .as_array()
        .expect("diagrams")
        .iter()
        .map(|d| diagram(d, cycle, 1.0))
        .collect();
    let cylinders = m["cylinders"].as_array().expect("cylinders");
    let units = cylinders
        .iter()
        .map(|c| PhysicalCylinder {
            crank_radius: number(c, "crank_radius"),
            rod_length: number(c, "rod_length"),
            piston_mass: number(c, "piston_mass"),
            rod_mass: number(c, "rod_mass"),
            rod_cg: number(c, "rod_cg"),
            rod_inertia: number(c, "rod_inertia"),
            crank_mass: number(c, "crank_mass"),
            crank_cg_radius: number(c, "crank_cg_radius"),
            counterweight_mass: number(c, "counterweight_mass"),
            counterweight_radius: number(c, "counterweight_radius"),
            phase: number(c, "phase"),
            inclination: number(c, "inclination"),
        })
        .collect();
    let gas = cylinders
        .iter()
        .map(|c| GasCylinder {
            bore: number(c, "bore"),
            piston_rod_diameter: number(c, "piston_rod_diameter"),
            head: c["head"].as_u64().map(|i| i as usize),
            crank_end: c["crank_end"].as_u64().map(|i| i as usize),
        })
        .collect();
    let list = |key: &str| m[key].as_array().expect(key).clone();
    Fixture {
        name: m["name"].as_str().expect("name").to_string(),
        units,
        gas,
        diagrams,
        shaft_inertia: number(m, "shaft_inertia"),
        strokes,
        g: number(m, "g"),
        rpm: number(m, "rpm"),
        expected: m["steady_state"].clone(),
        near_stall: list("near_stall"),
        stalls: list("stalls"),
        flywheels: list("flywheels"),
        curves: m["curves"].clone(),
        square_law: list("square_law"),
    }
}

pub fn machine_of(f: &Fixture) -> MachineView<'_> {
    MachineView {
        units: &f.units,
        gas: &f.gas,
        diagrams: &f.diagrams,
        shaft_inertia: f.shaft_inertia,
        strokes: f.strokes,
        g: f.g,
    }
}

/// The steady state of fixture `f` at `rpm` (1/min).
pub fn solve(f: &Fixture, rpm: f64) -> SteadyState {
    steady_state(&machine_of(f), omega(rpm), 1e-3).expect("runs")
}
