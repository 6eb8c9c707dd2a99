//! Throughput of the machine's kernels, serial (one thread; the shared 2-core host):
//! the dynamics of a four-cylinder in-line machine on 10⁵ points of φ (reduced inertia
//! J and J′ together, gas torque, piston travel, gravity torque), in points per second;
//! the energy extrema and the sweep outputs of 1000 designs (k = 4), in designs per second.
//! The motion sweep (δ with and without gravity) of 128 variants of a gassed four-cylinder
//! four-stroke machine, serial and parallel, and one steady state of it, in designs per
//! second.
//! Run: `cargo bench -p multicrank-benches --bench machine` (release profile); the motion
//! groups alone: `… --bench machine -- motion`.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use multicrank_core::{
    all_energy_extrema, build_series, crank_phases, motion_sweep, steady_state, sweep, Acting,
    Design, Dynamics, GasCylinder, Kinematics, MachineDesigns, MachineView, MotionOutputs,
    Parallelism, PhaseSetTable, Phases, PhysicalCylinder, PiecewisePolynomial, SeriesKind, Strokes,
    SweepOutputs,
};

const POINTS: usize = 100_000;
const DESIGNS: usize = 1000;
const SERIAL: Parallelism = Parallelism::SERIAL;

fn machine() -> Dynamics {
    Dynamics::new(&units(), 9.81).expect("a valid machine")
}

fn units() -> Vec<PhysicalCylinder> {
    let phases = crank_phases(4, Strokes::Four, Acting::Single).expect("k >= 1");
    phases
        .iter()
        .map(|&phase| PhysicalCylinder {
            crank_radius: 0.05,
            rod_length: 0.16,
            piston_mass: 0.5,
            rod_mass: 0.6,
            rod_cg: 0.11,
            rod_inertia: 0.003,
            crank_mass: 1.0,
            crank_cg_radius: 0.02,
            counterweight_mass: 0.8,
            counterweight_radius: 0.04,
            phase,
            inclination: FRAC_PI_2,
        })
        .collect()
}

/// λ spread over [0.2, 0.4], γ over a half turn: designs as a sweep sees them.
fn designs() -> Vec<Design> {
    (0..DESIGNS)
        .map(|i| {
            let t = i as f64 / DESIGNS as f64;
            Design::new(0.2 + 0.2 * t, -1.5 + 3.0 * t, 0.8, 0.3).expect("valid design")
        })
        .collect()
}

fn dynamics(c: &mut Criterion) {
    let machine = machine();
    let phi: Vec<f64> = (0..POINTS)
        .map(|i| TAU * i as f64 / POINTS as f64)
        .collect();
    let forces = vec![1.0e4; machine.len() * POINTS];
    let (mut out, mut slope) = (vec![0.0; POINTS], vec![0.0; POINTS]);
    let mut travel = vec![0.0; machine.len() * POINTS];
    let mut group = c.benchmark_group("dynamics");
    group.throughput(Throughput::Elements(POINTS as u64));
    group.sample_size(10);
    group.bench_function("reduced_inertia", |b| {
        b.iter(|| machine.reduced_inertia(0.5, &phi, &mut out, &mut slope, SERIAL))
    });
    group.bench_function("gas_torque", |b| {
        b.iter(|| machine.gas_torque(&phi, &forces, &mut out, SERIAL))
    });
    group.bench_function("travel", |b| {
        b.iter(|| machine.kinematics(Kinematics::Travel, &phi, &mut travel, SERIAL))
    });
    group.bench_function("gravity_torque", |b| {
        b.iter(|| machine.gravity_torque(&phi, &mut out, SERIAL))
    });
    group.finish();
}

fn designs_per_second(c: &mut Criterion) {
    let designs = designs();
    let alphas = crank_phases(4, Strokes::Four, Acting::Single).expect("k >= 1");
    let phases = Phases::new(&alphas).expect("finite phases");
    let series = build_series(SeriesKind::Exact, &designs, &alphas, SERIAL);

    let mut group = c.benchmark_group("extrema");
    group.throughput(Throughput::Elements(DESIGNS as u64));
    group.sample_size(10);
    group.bench_function("energy_extrema", |b| {
        b.iter(|| all_energy_extrema(&designs, &phases, &series, SERIAL))
    });
    group.finish();

    let table = PhaseSetTable::new(&[alphas], 0.4).expect("a valid phase set");
    let phase_set = vec![0_u32; DESIGNS];
    let grid: Vec<f64> = (0..360).map(|i| TAU * i as f64 / 360.0).collect();
    let mut group = c.benchmark_group("sweep");
    group.throughput(Throughput::Elements(DESIGNS as u64));
    group.sample_size(10);
    for (name, outputs) in [
        ("force", &["force_max_abs", "force_rms"][..]),
        ("energy_range", &["energy_range"][..]),
    ] {
        let outputs = SweepOutputs::from_names(outputs).expect("known outputs");
        group.bench_with_input(BenchmarkId::new(name, 360), &outputs, |b, &outputs| {
            b.iter(|| sweep(&designs, &phase_set, &table, &grid, outputs, SERIAL))
        });
    }
    group.finish();
}

/// Motion designs: I_w × ω_m, 16 × 8.
const MOTION_DESIGNS: usize = 128;

/// A four-stroke cylinder pressure (Pa), piecewise linear over 4π from outer dead centre of
/// the firing stroke: expansion, exhaust, intake, compression.
fn pressure() -> PiecewisePolynomial {
    let x = [0.0, 0.1, 0.5, 1.0, 2.0, 3.0, 3.6, 3.9, 4.0].map(|t| t * PI);
    let p = [60e5, 55e5, 15e5, 3e5, 0.1e5, 0.0, 3e5, 30e5, 60e5];
    let pieces = x.len() - 1;
    let slopes = (0..pieces).map(|i| (p[i + 1] - p[i]) / (x[i + 1] - x[i]));
    let coefficients = slopes.chain(p[..pieces].iter().copied()).collect();
    PiecewisePolynomial::new(x.to_vec(), coefficients, 4.0 * PI).expect("a valid diagram")
}

fn motion(c: &mut Criterion) {
    let units = units();
    let gas = vec![
        GasCylinder {
            bore: 0.08,
            piston_rod_diameter: 0.0,
            head: Some(0),
            crank_end: None,
        };
        units.len()
    ];
    let diagrams = [pressure()];
    let machine = MachineView {
        units: &units,
        gas: &gas,
        diagrams: &diagrams,
        shaft_inertia: 0.2,
        strokes: Strokes::Four,
        g: 9.81,
    };
    // ω_m from 50π rad/s (1500 rpm) in steps of 50π/3 rad/s (500 rpm).
    let (inertia, omega): (Vec<f64>, Vec<f64>) = (0..MOTION_DESIGNS)
        .map(|i| {
            let step = (i % 8) as f64;
            (0.1 + 0.02 * (i / 8) as f64, 50.0 * PI * (1.0 + step / 3.0))
        })
        .unzip();
    let designs = MachineDesigns {
        shaft_inertia: Some(&inertia),
        omega: Some(&omega),
        ..MachineDesigns::new(MOTION_DESIGNS)
    };
    let outputs = MotionOutputs {
        delta: true,
        delta_without_gravity: true,
        ..MotionOutputs::default()
    };
    let run = |parallelism| {
        let found = motion_sweep(&machine, None, &designs, outputs, None, 1e-3, parallelism)
            .expect("a sweep");
        assert!(found.stalled.iter().all(|s| !s), "a design stalls");
        found
    };
    let mut group = c.benchmark_group("motion_sweep");
    group.throughput(Throughput::Elements(MOTION_DESIGNS as u64));
    group.sample_size(10);
    group.bench_function("delta_with_without_gravity/serial", |b| {
        b.iter(|| run(SERIAL))
    });
    group.bench_function("delta_with_without_gravity/parallel", |b| {
        b.iter(|| run(Parallelism { threshold: 0 }))
    });
    group.finish();
    let mut group = c.benchmark_group("motion_steady_state");
    group.throughput(Throughput::Elements(1));
    group.sample_size(10);
    group.bench_function("steady_state", |b| {
        b.iter(|| steady_state(&machine, 100.0 * PI, 1e-3).expect("runs"))
    });
    group.finish();
}

criterion_group!(benches, dynamics, designs_per_second, motion);
criterion_main!(benches);
