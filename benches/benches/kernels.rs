//! Throughput of the kernels on 10⁶ points, k = 1, 6, 12, λ = 0.3: the closed form and the
//! Fourier series, serial (one thread) and parallel (all threads); and Λ_0…Λ_24 per λ.
//! Run: `cargo bench -p multicrank-benches` (release profile).

use std::f64::consts::TAU;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use multicrank_core::{
    build_series, crank_phases, evaluate, evaluate_series, lambda_exact, Acting, Design,
    Parallelism, Phases, Quantity, SeriesKind, Strokes,
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

    let mut group = c.benchmark_group("series");
    group.throughput(Throughput::Elements(POINTS as u64));
    group.sample_size(20);
    for cranks in [1, 6, 12] {
        let alphas = crank_phases(cranks, Strokes::Two, Acting::Single).expect("k >= 1");
        let series = build_series(SeriesKind::Exact, &design, &alphas, Parallelism::SERIAL);
        for (mode, parallelism) in [
            ("serial", Parallelism::SERIAL),
            ("parallel", Parallelism::default()),
        ] {
            group.bench_with_input(
                BenchmarkId::new(format!("force/{mode}"), cranks),
                &series,
                |b, series| b.iter(|| evaluate_series(series, &phi, &mut out, parallelism)),
            );
        }
    }
    group.finish();

    let mut group = c.benchmark_group("lambda");
    group.throughput(Throughput::Elements(1));
    let mut lambdas = [0.0; 25];
    for crank_ratio in [0.3, 0.95] {
        group.bench_with_input(
            BenchmarkId::new("exact_n24", crank_ratio),
            &crank_ratio,
            |b, &l| b.iter(|| lambda_exact(l, &mut lambdas)),
        );
    }
    group.finish();
}

criterion_group!(benches, kernels);
criterion_main!(benches);
