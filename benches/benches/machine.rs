//! Throughput of the machine's kernels, serial (one thread; the shared 2-core host):
//! the dynamics of a four-cylinder in-line machine on 10⁵ points of φ (reduced inertia
//! J and J′ together, gas torque, piston travel, gravity torque), in points per second;
//! the energy extrema and the sweep outputs of 1000 designs (k = 4), in designs per second.
//! Run: `cargo bench -p multicrank-benches --bench machine` (release profile).

use std::f64::consts::{FRAC_PI_2, TAU};

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use multicrank_core::{
    all_energy_extrema, build_series, crank_phases, sweep, Acting, Design, Dynamics, Kinematics,
    Parallelism, PhaseSetTable, Phases, PhysicalCylinder, SeriesKind, Strokes, SweepOutputs,
};

const POINTS: usize = 100_000;
const DESIGNS: usize = 1000;
const SERIAL: Parallelism = Parallelism::SERIAL;

fn machine() -> Dynamics {
    let phases = crank_phases(4, Strokes::Four, Acting::Single).expect("k >= 1");
    let units: Vec<PhysicalCylinder> = phases
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
        .collect();
    Dynamics::new(&units, 9.81).expect("a valid machine")
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

criterion_group!(benches, dynamics, designs_per_second);
criterion_main!(benches);
