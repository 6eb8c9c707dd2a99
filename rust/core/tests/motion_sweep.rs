//! The motion sweep: every row is `steady_state` / `flywheel_inertia` of its own machine,
//! built by hand from the fixtures' arrays (tests/common), to 1e-12 relative (bit for bit
//! where nothing is scaled: see `close`).

mod common;

use common::{diagram, fixture_named, fixtures, machine_json, machine_of, number, omega, Fixture};
use multicrank_core::{
    flywheel_inertia, motion_sweep, steady_state, steady_state_curves, two_mass_rod_inertia,
    GasCylinder, MachineDesigns, MachineView, MechanismError, MotionColumns, MotionOutputs,
    Parallelism, PhysicalCylinder, PiecewisePolynomial, SteadyTables, UnitColumn, UnitField,
};
use std::f64::consts::PI;

/// One design's overrides, as the test applies them by hand (`rpm` in 1/min, the core's
/// column `omega` in rad/s).
#[derive(Clone, Copy, Default)]
struct Design {
    shaft_inertia: Option<f64>,
    rpm: Option<f64>,
    g: Option<f64>,
    pressure_scale: Option<f64>,
    crank_radius: Option<f64>,
    rod_length: Option<f64>,
    rod_mass: Option<f64>,
    rod_inertia: Option<f64>,
    piston_mass: Option<f64>,
    counterweight_mass: Option<f64>,
    bore: Option<f64>,
}

/// The machine of `design`, built by hand from the fixture's own arrays: (units, gas,
/// diagrams, I_w, g, rpm). A two-mass rod (all the fixtures' are) stays one where the rod
/// changes and no rod_inertia is given; NaN asks for it.
struct HandBuilt {
    units: Vec<PhysicalCylinder>,
    gas: Vec<GasCylinder>,
    diagrams: Vec<PiecewisePolynomial>,
    shaft_inertia: f64,
    g: f64,
    rpm: f64,
}

fn hand_built(f: &Fixture, d: &Design) -> HandBuilt {
    let m = machine_json(&f.name);
    let cycle = f.strokes.cycle_angle();
    let scale = d.pressure_scale.unwrap_or(1.0);
    let diagrams = m["diagrams"]
        .as_array()
        .expect("diagrams")
        .iter()
        .map(|d| diagram(d, cycle, scale))
        .collect();
    let units = f
        .units
        .iter()
        .map(|u| {
            let mut new = PhysicalCylinder {
                crank_radius: d.crank_radius.unwrap_or(u.crank_radius),
                rod_length: d.rod_length.unwrap_or(u.rod_length),
                rod_mass: d.rod_mass.unwrap_or(u.rod_mass),
                piston_mass: d.piston_mass.unwrap_or(u.piston_mass),
                counterweight_mass: d.counterweight_mass.unwrap_or(u.counterweight_mass),
                ..*u
            };
            let two_mass = new.rod_mass * new.rod_cg * (new.rod_length - new.rod_cg);
            new.rod_inertia = match d.rod_inertia {
                Some(i) if i.is_nan() => two_mass,
                Some(i) => i,
                None if d.rod_mass.is_some() || d.rod_length.is_some() => two_mass,
                None => u.rod_inertia,
            };
            new
        })
        .collect();
    let gas = f
        .gas
        .iter()
        .map(|g| GasCylinder {
            bore: d.bore.unwrap_or(g.bore),
            ..*g
        })
        .collect();
    HandBuilt {
        units,
        gas,
        diagrams,
        shaft_inertia: d.shaft_inertia.unwrap_or(f.shaft_inertia),
        g: d.g.unwrap_or(f.g),
        rpm: d.rpm.unwrap_or(f.rpm),
    }
}

/// Owned design columns: a column is given where any design sets it (the others take the
/// base value there; NaN rod_inertia stays NaN).
struct Columns {
    designs: usize,
    values: Vec<(&'static str, Vec<f64>)>,
}

/// A design's override of one column.
type Field = fn(&Design) -> Option<f64>;

fn columns(f: &Fixture, designs: &[Design]) -> Columns {
    let base = f.units[0];
    let fields: [(&'static str, Field, f64); 11] = [
        ("shaft_inertia", |d| d.shaft_inertia, f.shaft_inertia),
        ("omega", |d| d.rpm.map(omega), omega(f.rpm)),
        ("g", |d| d.g, f.g),
        ("pressure_scale", |d| d.pressure_scale, 1.0),
        ("crank_radius", |d| d.crank_radius, base.crank_radius),
        ("rod_length", |d| d.rod_length, base.rod_length),
        ("rod_mass", |d| d.rod_mass, base.rod_mass),
        ("rod_inertia", |d| d.rod_inertia, f64::NAN),
        ("piston_mass", |d| d.piston_mass, base.piston_mass),
        (
            "counterweight_mass",
            |d| d.counterweight_mass,
            base.counterweight_mass,
        ),
        ("bore", |d| d.bore, f.gas[0].bore),
    ];
    let values = fields
        .iter()
        .filter(|(_, get, _)| designs.iter().any(|d| get(d).is_some()))
        .map(|(name, get, own)| {
            (
                *name,
                designs.iter().map(|d| get(d).unwrap_or(*own)).collect(),
            )
        })
        .collect();
    Columns {
        designs: designs.len(),
        values,
    }
}

impl Columns {
    fn view(&self) -> MachineDesigns<'_> {
        let mut view = MachineDesigns::new(self.designs);
        for (name, values) in &self.values {
            let column = Some(&values[..]);
            match *name {
                "shaft_inertia" => view.shaft_inertia = column,
                "omega" => view.omega = column,
                "g" => view.g = column,
                "pressure_scale" => view.pressure_scale = column,
                "crank_radius" => view.crank_radius = column,
                "rod_length" => view.rod_length = column,
                "rod_mass" => view.rod_mass = column,
                "rod_inertia" => view.rod_inertia = column,
                "piston_mass" => view.piston_mass = column,
                "counterweight_mass" => view.counterweight_mass = column,
                "bore" => view.bore = column,
                other => panic!("{other}"),
            }
        }
        view
    }
}

fn all_outputs() -> MotionOutputs {
    MotionOutputs::from_names(&MotionOutputs::NAMES).expect("known outputs")
}

/// Equal to 1e-12 relative (and 1e-15 absolute: δ is a difference of speeds), NaN equal to
/// NaN. Not bit for bit: a design that differs from an earlier one of its block only in
/// `pressure_scale` (or in bore, where no crank end has a piston rod) takes that one's gas
/// work and forces times the ratio of p·D², while its own machine integrates its own scaled
/// pressures and areas: the same numbers to rounding, not the same doubles.
fn close(found: f64, expected: f64, what: &str) {
    assert!(
        (found - expected).abs() <= 1e-12 * expected.abs() + 1e-15
            || (found.is_nan() && expected.is_nan()),
        "{what}: {found:e} vs {expected:e}"
    );
}

/// Every row against steady_state and flywheel_inertia of its machine built by hand.
fn check_rows(f: &Fixture, designs: &[Design], found: &MotionColumns, target: Option<f64>) {
    for (i, design) in designs.iter().enumerate() {
        let h = hand_built(f, design);
        let machine = MachineView {
            units: &h.units,
            gas: &h.gas,
            diagrams: &h.diagrams,
            shaft_inertia: h.shaft_inertia,
            strokes: f.strokes,
            g: h.g,
        };
        check_row(&f.name, i, &machine, h.rpm, found, target);
    }
}

/// Row `i` of a sweep against steady_state and flywheel_inertia of `machine` at `rpm`
/// (1/min).
fn check_row(
    name: &str,
    i: usize,
    machine: &MachineView<'_>,
    rpm: f64,
    found: &MotionColumns,
    target: Option<f64>,
) {
    {
        let what = |key: &str| format!("{name} row {i} {key}");
        match steady_state(machine, omega(rpm), 1e-3) {
            Ok(state) => {
                assert!(!found.stalled[i], "{}", what("stalled"));
                close(found.delta[i], state.delta, &what("delta"));
                close(
                    found.delta_without_gravity[i],
                    state.delta_without_gravity,
                    &what("delta_without_gravity"),
                );
                close(
                    found.delta_coasting[i],
                    state.delta_coasting,
                    &what("delta_coasting"),
                );
                // δ/δ₀ − 1 cancels where gravity changes little: δ/δ₀ itself to 1e-12.
                close(
                    1.0 + found.gravity_effect[i],
                    state.delta / state.delta_without_gravity,
                    &what("gravity_effect"),
                );
                close(found.omega_min[i], state.omega_min, &what("omega_min"));
                close(found.omega_max[i], state.omega_max, &what("omega_max"));
            }
            Err(MechanismError::Stall { .. }) => {
                assert!(found.stalled[i], "{}", what("stalled"));
                for column in [
                    &found.delta,
                    &found.delta_without_gravity,
                    &found.delta_coasting,
                    &found.gravity_effect,
                    &found.omega_min,
                    &found.omega_max,
                ] {
                    assert!(column[i].is_nan(), "{}", what("NaN where stalled"));
                }
            }
            Err(other) => panic!("{}: {other}", what("steady_state")),
        }
        if let Some(delta) = target {
            match flywheel_inertia(machine, delta, omega(rpm), 1e-3) {
                Ok(sized) => {
                    close(
                        found.flywheel_inertia[i],
                        sized.shaft_inertia,
                        &what("flywheel_inertia"),
                    );
                    close(
                        found.flywheel_inertia_without_gravity[i],
                        sized.shaft_inertia_without_gravity,
                        &what("flywheel_inertia_without_gravity"),
                    );
                }
                Err(_) => {
                    assert!(found.flywheel_inertia[i].is_nan());
                    assert!(found.flywheel_inertia_without_gravity[i].is_nan());
                }
            }
        }
    }
}

/// Designs that change every kind of number, on every fixture machine: each row equal to
/// the machine built by hand (the same code path; `close`), flywheel included.
#[test]
fn every_sweep_row_is_the_steady_state_of_its_machine() {
    for f in fixtures() {
        let u = f.units[0];
        let designs = [
            Design::default(),
            Design {
                shaft_inertia: Some(1.3 * f.shaft_inertia),
                g: Some(0.0),
                pressure_scale: Some(1.2),
                ..Design::default()
            },
            Design {
                rpm: Some(1.1 * f.rpm),
                crank_radius: Some(1.02 * u.crank_radius),
                rod_mass: Some(1.1 * u.rod_mass),
                bore: Some(1.01 * f.gas[0].bore),
                ..Design::default()
            },
            Design {
                shaft_inertia: Some(0.9 * f.shaft_inertia),
                g: Some(3.7),
                piston_mass: Some(0.8 * u.piston_mass),
                counterweight_mass: Some(u.counterweight_mass + 1.0),
                rod_inertia: Some(0.9 * u.rod_inertia),
                ..Design::default()
            },
        ];
        let owned = columns(&f, &designs);
        let target = 1.0 / 60.0;
        let found = motion_sweep(
            &machine_of(&f),
            Some(omega(f.rpm)),
            &owned.view(),
            all_outputs(),
            Some(target),
            1e-3,
            Parallelism::default(),
        )
        .expect("a sweep");
        assert_eq!(found.stalled.len(), designs.len());
        check_rows(&f, &designs, &found, Some(target));
    }
}

/// A unit's own phase and counterweight (the design aid's firing orders and counterweights
/// per throw), set after the columns of every unit: each row equal to the machine with (`close`)
/// those values set by hand, on every fixture machine, flywheel included.
#[test]
fn a_unit_column_sets_that_unit_alone() {
    for f in fixtures() {
        let last = f.units.len() - 1;
        let (first, moved) = (f.units[0], f.units[last]);
        let phases = [
            moved.phase,
            moved.phase + 2.0 * PI,
            moved.phase - 0.3,
            moved.phase,
        ];
        let masses = [
            first.counterweight_mass,
            first.counterweight_mass + 2.0,
            first.counterweight_mass,
            0.5,
        ];
        let radii = [first.counterweight_radius, 0.05, 0.05, 0.11];
        // Every unit's counterweight first, then unit 0's own: the own value wins.
        let everywhere = [7.0; 4];
        let view = MachineDesigns {
            counterweight_mass: Some(&everywhere),
            units: vec![
                UnitColumn {
                    field: UnitField::Phase,
                    unit: last,
                    values: &phases,
                },
                UnitColumn {
                    field: UnitField::CounterweightMass,
                    unit: 0,
                    values: &masses,
                },
                UnitColumn {
                    field: UnitField::CounterweightRadius,
                    unit: 0,
                    values: &radii,
                },
            ],
            ..MachineDesigns::new(4)
        };
        let target = 1.0 / 60.0;
        let found = motion_sweep(
            &machine_of(&f),
            Some(omega(f.rpm)),
            &view,
            all_outputs(),
            Some(target),
            1e-3,
            Parallelism::default(),
        )
        .expect("a sweep");
        for row in 0..4 {
            let mut units: Vec<PhysicalCylinder> = f
                .units
                .iter()
                .map(|u| PhysicalCylinder {
                    counterweight_mass: 7.0,
                    ..*u
                })
                .collect();
            units[last].phase = phases[row];
            units[0].counterweight_mass = masses[row];
            units[0].counterweight_radius = radii[row];
            let machine = MachineView {
                units: &units,
                ..machine_of(&f)
            };
            check_row(&f.name, row, &machine, f.rpm, &found, Some(target));
        }
        // A unit the machine does not have names the column.
        let view = MachineDesigns {
            units: vec![UnitColumn {
                field: UnitField::Phase,
                unit: f.units.len(),
                values: &phases,
            }],
            ..MachineDesigns::new(4)
        };
        let error = motion_sweep(
            &machine_of(&f),
            Some(omega(f.rpm)),
            &view,
            all_outputs(),
            Some(target),
            1e-3,
            Parallelism::SERIAL,
        )
        .unwrap_err();
        let expected = format!("phase[{}]", f.units.len());
        assert!(error.to_string().contains(&expected), "{error}");
    }
}

/// Designs that differ only in pressure_scale and bore share one gas and one machine's J and
/// U, scaled (a double-acting cylinder with a piston rod keys its bore instead): each row the
/// steady state and flywheel of its own machine, a zero scale and a zero bore included.
#[test]
fn designs_that_differ_in_pressure_or_bore_share_one_gas_scaled() {
    for f in fixtures() {
        let bore = f.gas[0].bore;
        let scales = [1.0, 0.7, 1.3, 0.0, 1.0, 0.7, 1.1];
        let bores = [1.0, 1.0, 1.05, 1.0, 0.97, 0.0, 1.0].map(|b| b * bore);
        let designs: Vec<Design> = scales
            .iter()
            .zip(bores)
            .enumerate()
            .map(|(i, (&scale, bore))| Design {
                pressure_scale: Some(scale),
                bore: Some(bore),
                rpm: (i == 6).then_some(1.2 * f.rpm),
                ..Design::default()
            })
            .filter(|d| d.bore != Some(0.0) || f.gas.iter().all(|g| g.piston_rod_diameter == 0.0))
            .collect();
        let owned = columns(&f, &designs);
        let target = 1.0 / 60.0;
        let found = motion_sweep(
            &machine_of(&f),
            Some(omega(f.rpm)),
            &owned.view(),
            all_outputs(),
            Some(target),
            1e-3,
            Parallelism::default(),
        )
        .expect("a sweep");
        check_rows(&f, &designs, &found, Some(target));
    }
}

fn slow_compressor() -> Fixture {
    fixture_named("slow-compressor")
}

/// A design below its lowest running speed is a stalled row (NaN δ and speeds) among
/// running ones, not an error; its flywheel is still sized.
#[test]
fn a_stalled_design_is_a_row_not_an_error() {
    let f = slow_compressor();
    let stall = number(&f.stalls[0], "rpm");
    let designs = [f.rpm, stall, 0.75 * f.rpm].map(|rpm| Design {
        rpm: Some(rpm),
        ..Design::default()
    });
    let owned = columns(&f, &designs);
    let found = motion_sweep(
        &machine_of(&f),
        None,
        &owned.view(),
        all_outputs(),
        Some(0.05),
        1e-3,
        Parallelism::SERIAL,
    )
    .expect("a sweep");
    assert_eq!(found.stalled, [false, true, false]);
    assert!(found.delta[1].is_nan() && found.omega_min[1].is_nan());
    check_rows(&f, &designs, &found, Some(0.05));
}

/// rod_inertia NaN is the two-mass rod of the design's own rod; a number is taken as given;
/// without the column a two-mass rod stays one when the rod changes, another rod keeps its
/// inertia.
#[test]
fn a_nan_rod_inertia_is_the_two_mass_rod_of_the_design() {
    let f = slow_compressor();
    let u = f.units[0];
    let designs = [
        Design {
            rod_length: Some(1.1 * u.rod_length),
            rod_inertia: Some(f64::NAN),
            ..Design::default()
        },
        Design {
            rod_length: Some(1.1 * u.rod_length),
            rod_inertia: Some(7.0),
            ..Design::default()
        },
    ];
    let owned = columns(&f, &designs);
    let steady = MotionOutputs {
        flywheel_inertia: false,
        flywheel_inertia_without_gravity: false,
        ..all_outputs()
    };
    let run = |base: &MachineView<'_>, view: &MachineDesigns<'_>| {
        motion_sweep(
            base,
            Some(omega(f.rpm)),
            view,
            steady,
            None,
            1e-3,
            Parallelism::SERIAL,
        )
        .expect("a sweep")
    };
    let found = run(&machine_of(&f), &owned.view());
    check_rows(&f, &designs, &found, None);
    let found = found.delta;
    let two_mass = two_mass_rod_inertia(u.rod_mass, 1.1 * u.rod_length, u.rod_cg);
    assert_ne!(two_mass, u.rod_inertia);
    // The same rows by rod_inertia given as numbers.
    let rod_length = [1.1 * u.rod_length; 2];
    let given = [two_mass, 7.0];
    let view = MachineDesigns {
        rod_length: Some(&rod_length),
        rod_inertia: Some(&given),
        omega: owned.view().omega,
        ..MachineDesigns::new(2)
    };
    assert_eq!(run(&machine_of(&f), &view).delta, found);
    // No rod_inertia column: the two-mass rod follows its rod (row 0) …
    let lengths = [1.1 * u.rod_length];
    let view = MachineDesigns {
        rod_length: Some(&lengths),
        ..MachineDesigns::new(1)
    };
    let base = machine_of(&f);
    assert_eq!(run(&base, &view).delta[0].to_bits(), found[0].to_bits());
    // … and another rod keeps its own inertia.
    let units: Vec<PhysicalCylinder> = f
        .units
        .iter()
        .map(|u| PhysicalCylinder {
            rod_inertia: 7.0,
            ..*u
        })
        .collect();
    let kept = MachineView {
        units: &units,
        ..base
    };
    assert_eq!(run(&kept, &view).delta[0].to_bits(), found[1].to_bits());
}

/// A bad value is an error naming its row and parameter, found before any design is
/// solved (a later bad row stops the sweep even where an earlier design would be slow).
#[test]
fn a_bad_design_is_an_error_naming_its_row_and_parameter() {
    let f = slow_compressor();
    let u = f.units[0];
    let radii = [u.crank_radius, u.crank_radius, 2.0 * u.rod_length];
    let view = MachineDesigns {
        crank_radius: Some(&radii),
        ..MachineDesigns::new(3)
    };
    let error = motion_sweep(
        &machine_of(&f),
        Some(omega(f.rpm)),
        &view,
        all_outputs(),
        Some(0.02),
        1e-3,
        Parallelism::SERIAL,
    )
    .unwrap_err();
    match &error {
        MechanismError::InRow { row: 2, error } => match **error {
            MechanismError::OutOfRange { parameter, .. } => assert_eq!(parameter, "rod_length"),
            ref other => panic!("{other:?}"),
        },
        other => panic!("{other:?}"),
    }
    assert!(
        error.to_string().starts_with("design 2: rod_length"),
        "{error}"
    );
    let inertia = [1.0, -1.0];
    let view = MachineDesigns {
        shaft_inertia: Some(&inertia),
        ..MachineDesigns::new(2)
    };
    let error = motion_sweep(
        &machine_of(&f),
        Some(omega(f.rpm)),
        &view,
        all_outputs(),
        Some(0.02),
        1e-3,
        Parallelism::SERIAL,
    )
    .unwrap_err();
    assert!(
        matches!(&error, MechanismError::InRow { row: 1, error } if matches!(**error, MechanismError::OutOfRange { parameter: "shaft_inertia", .. })),
        "{error:?}"
    );
    // A column of the wrong length, and a flywheel without its target: the sweep's own.
    let short = [1.0];
    let view = MachineDesigns {
        g: Some(&short),
        ..MachineDesigns::new(2)
    };
    let delta = MotionOutputs {
        delta: true,
        ..MotionOutputs::default()
    };
    assert!(matches!(
        motion_sweep(
            &machine_of(&f),
            Some(omega(f.rpm)),
            &view,
            delta,
            None,
            1e-3,
            Parallelism::SERIAL
        ),
        Err(MechanismError::LengthMismatch { parameter: "g", .. })
    ));
    let flywheel = MotionOutputs {
        flywheel_inertia: true,
        ..MotionOutputs::default()
    };
    assert!(matches!(
        motion_sweep(
            &machine_of(&f),
            Some(omega(f.rpm)),
            &MachineDesigns::new(1),
            flywheel,
            None,
            1e-3,
            Parallelism::SERIAL
        ),
        Err(MechanismError::OutOfRange {
            parameter: "delta",
            ..
        })
    ));
}

/// Serial and parallel (one task per design on three threads) give the same bits.
#[test]
fn a_parallel_sweep_is_bit_identical_to_a_serial_one() {
    let f = fixtures()
        .into_iter()
        .find(|f| f.name == "inline-4")
        .expect("inline-4");
    let designs: Vec<Design> = (0..12)
        .map(|i| Design {
            shaft_inertia: Some(f.shaft_inertia * (0.6 + 0.1 * i as f64)),
            rpm: Some(f.rpm * (0.5 + 0.08 * i as f64)),
            pressure_scale: Some(0.8 + 0.03 * i as f64),
            ..Design::default()
        })
        .collect();
    let owned = columns(&f, &designs);
    let run = |parallelism| {
        motion_sweep(
            &machine_of(&f),
            None,
            &owned.view(),
            all_outputs(),
            Some(0.01),
            1e-3,
            parallelism,
        )
        .expect("a sweep")
    };
    let serial = run(Parallelism::SERIAL);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .expect("a pool");
    let parallel = pool.install(|| run(Parallelism { threshold: 0 }));
    let bits = |c: &MotionColumns| {
        [
            &c.delta,
            &c.delta_without_gravity,
            &c.delta_coasting,
            &c.gravity_effect,
            &c.omega_min,
            &c.omega_max,
            &c.flywheel_inertia,
            &c.flywheel_inertia_without_gravity,
        ]
        .iter()
        .map(|v| v.iter().map(|x| x.to_bits()).collect::<Vec<u64>>())
        .collect::<Vec<_>>()
    };
    assert_eq!(bits(&serial), bits(&parallel));
    assert_eq!(serial.stalled, parallel.stalled);
    check_rows(&f, &designs[..3], &serial, Some(0.01));
}

/// Only what is asked is computed: δ alone leaves the other columns empty and does not
/// size a flywheel even when given a target no shaft reaches (which, asked for, costs a
/// long search and gives NaN).
#[test]
fn only_the_outputs_asked_are_computed() {
    let f = slow_compressor();
    let designs = [0.8, 1.0, 1.2].map(|s| Design {
        shaft_inertia: Some(s * f.shaft_inertia),
        ..Design::default()
    });
    let owned = columns(&f, &designs);
    let delta = MotionOutputs {
        delta: true,
        ..MotionOutputs::default()
    };
    let run = |outputs, target| {
        let start = std::time::Instant::now();
        let found = motion_sweep(
            &machine_of(&f),
            Some(omega(f.rpm)),
            &owned.view(),
            outputs,
            target,
            1e-3,
            Parallelism::SERIAL,
        )
        .expect("a sweep");
        (found, start.elapsed())
    };
    let (plain, _) = run(delta, None);
    let (ignored, quick) = run(delta, Some(1e6));
    let asked = MotionOutputs {
        flywheel_inertia: true,
        ..delta
    };
    let (sized, slow) = run(asked, Some(1e6));
    assert_eq!(plain, ignored);
    assert_eq!(plain.delta.len(), 3);
    assert!(plain.delta_without_gravity.is_empty() && plain.flywheel_inertia.is_empty());
    assert_eq!(sized.delta, plain.delta);
    assert!(sized.flywheel_inertia.iter().all(|i| i.is_nan()));
    println!("delta alone {quick:?}; with the unreachable flywheel {slow:?}");
    assert!(quick < slow, "{quick:?} vs {slow:?}");
}

/// Tables made once serve every shaft inertia and speed: each steady state and flywheel from
/// them is bit-equal to the one of the machine built with that I_w; without the comparisons
/// δ is the same and they are NaN.
#[test]
fn tables_made_once_give_every_inertia_and_speed_exactly() {
    for f in fixtures() {
        let base = machine_of(&f);
        let tables = SteadyTables::new(&base).expect("tables");
        let phi = [0.0, 0.5, tables.cycle()];
        for (factor, speed) in [(1.0, 1.0), (0.7, 1.2), (2.5, 0.9)] {
            let inertia = factor * f.shaft_inertia;
            let rpm = omega(speed * f.rpm);
            let machine = MachineView {
                shaft_inertia: inertia,
                ..base
            };
            let fresh = steady_state_curves(&machine, rpm, 1e-3, &phi);
            let reused = tables.steady_state(inertia, rpm, 1e-3, &phi, true);
            match (fresh, reused) {
                (Ok(fresh), Ok(reused)) => {
                    assert_eq!(
                        format!("{fresh:?}"),
                        format!("{reused:?}"),
                        "{} {factor} {speed}",
                        f.name
                    );
                    let alone = tables
                        .steady_state(inertia, rpm, 1e-3, &[], false)
                        .expect("runs");
                    assert_eq!(alone.state.delta, fresh.state.delta);
                    assert!(alone.state.delta_without_gravity.is_nan());
                    assert!(alone.state.delta_coasting.is_nan());
                    assert!(alone.omega.is_empty() && alone.time.is_empty());
                }
                (Err(fresh), Err(reused)) => assert_eq!(fresh, reused, "{}", f.name),
                (fresh, reused) => panic!("{}: {fresh:?} vs {reused:?}", f.name),
            }
            let sized = flywheel_inertia(&machine, 0.02, rpm, 1e-3);
            let from_tables = tables.flywheel_inertia(0.02, rpm, 1e-3, inertia, true);
            assert_eq!(
                format!("{sized:?}"),
                format!("{from_tables:?}"),
                "{} flywheel",
                f.name
            );
        }
    }
}
