//! Throughput of the closed-form kernels on 10⁶ points, k = 1, 6, 12, λ = 0.3,
//! serial (one thread) and parallel (all threads). Run: `cargo bench -p multicrank-benches`.

use std::f64::consts::TAU;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use multicrank_core::{
    crank_phases, evaluate, Acting, Design, Parallelism, Phases, Quantity, Strokes,
};

const POINTS: usize = 1_000_000;

fn kernels(c: &mut Criterion) {
    let phi: Vec<f64> = (0..POINTS)
        .map(|i| TAU * i as f64 / POINTS as f64)
        .collect();
    let design = [Design::new(0.3, 1.0, 0.8, 0.3).expect("valid design")];
    let mut out = vec![0.0; POINTS];
    let mut group = c.benchmark_group("exact");
    group.throughput(Throughput::Elements(POINTS as u64));
    group.sample_size(20);
    for cranks in [1, 6, 12] {
        let phases =
            Phases::new(&crank_phases(cranks, Strokes::Two, Acting::Single).expect("k >= 1"))
                .expect("finite phases");
        for (mode, parallelism) in [
            ("serial", Parallelism::SERIAL),
            ("parallel", Parallelism::default()),
        ] {
            for (name, quantity) in [
                ("force", Quantity::GeneralizedForce),
                ("energy", Quantity::PotentialEnergy),
            ] {
                let id = BenchmarkId::new(format!("{name}/{mode}"), cranks);
                group.bench_with_input(id, &phases, |b, phases| {
                    b.iter(|| evaluate(quantity, &design, phases, &phi, &mut out, parallelism))
                });
            }
        }
    }
    group.finish();
}

criterion_group!(benches, kernels);
criterion_main!(benches);
