//! Throughput of the kernels on 10⁶ points, k = 1, 4, 6, 12, λ = 0.3: the closed form and
//! the Fourier series, on any points and on a uniform grid (rotations), serial (one thread)
//! and parallel (all threads); Λ_0…Λ_24 per λ; and the machine's floor for the closed form
//! (the output write alone, on one thread and on all, and one sqrt and one division per
//! point, vectorised).
//! Run: `cargo bench -p multicrank-benches` (release profile).

use std::f64::consts::TAU;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use multicrank_core::{
    build_series, crank_phases, evaluate, evaluate_series, lambda_exact, Acting, Design,
    Parallelism, Phases, Phi, Quantity, SeriesKind, Strokes, UniformGrid,
};
use multiversion::multiversion;
use rayon::prelude::*;

const POINTS: usize = 1_000_000;

fn kernels(c: &mut Criterion) {
    let phi: Vec<f64> = (0..POINTS)
        .map(|i| TAU * i as f64 / POINTS as f64)
        .collect();
    let uniform = UniformGrid::revolution(POINTS);
    let grids: [(&str, Phi); 2] = [("points", Phi::Points(&phi)), ("uniform", uniform.into())];
    let design = [Design::new(0.3, 1.0, 0.8, 0.3).expect("valid design")];
    let mut out = vec![0.0; POINTS];
    let modes = [
        ("serial", Parallelism::SERIAL),
        ("parallel", Parallelism::default()),
    ];
    let mut group = c.benchmark_group("exact");
    group.throughput(Throughput::Elements(POINTS as u64));
    group.sample_size(20);
    for cranks in [1, 4, 6, 12] {
        let phases =
            Phases::new(&crank_phases(cranks, Strokes::Two, Acting::Single).expect("k >= 1"))
                .expect("finite phases");
        for (grid, angles) in grids {
            for (mode, parallelism) in modes {
                for (name, quantity) in [
                    ("force", Quantity::GeneralizedForce),
                    ("energy", Quantity::PotentialEnergy),
                ] {
                    let id = BenchmarkId::new(format!("{name}/{grid}/{mode}"), cranks);
                    group.bench_with_input(id, &phases, |b, phases| {
                        b.iter(|| {
                            evaluate(quantity, &design, phases, angles, &mut out, parallelism)
                        })
                    });
                }
            }
        }
    }
    group.finish();

    let mut group = c.benchmark_group("series");
    group.throughput(Throughput::Elements(POINTS as u64));
    group.sample_size(20);
    for cranks in [1, 4, 6, 12] {
        let alphas = crank_phases(cranks, Strokes::Two, Acting::Single).expect("k >= 1");
        let series = build_series(SeriesKind::Exact, &design, &alphas, Parallelism::SERIAL);
        for (grid, angles) in grids {
            for (mode, parallelism) in modes {
                group.bench_with_input(
                    BenchmarkId::new(format!("force/{grid}/{mode}"), cranks),
                    &series,
                    |b, series| b.iter(|| evaluate_series(series, angles, &mut out, parallelism)),
                );
            }
        }
    }
    group.finish();

    // The floor under the closed form at k = 1: what no kernel can beat on this machine.
    let mut group = c.benchmark_group("floor");
    group.throughput(Throughput::Elements(POINTS as u64));
    group.sample_size(20);
    group.bench_function("write", |b| b.iter(|| write_only(&mut out)));
    group.bench_function("write_parallel", |b| {
        b.iter(|| out.par_chunks_mut(8 * 1024).for_each(write_only))
    });
    group.bench_function("sqrt_div", |b| b.iter(|| sqrt_and_division(&phi, &mut out)));
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

/// Writing 10⁶ float64 values and nothing else (memory bandwidth).
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2+fma", "x86_64+avx2+fma"))]
fn write_only(out: &mut [f64]) {
    for (i, o) in out.iter_mut().enumerate() {
        *o = i as f64;
    }
    std::hint::black_box(out);
}

/// One sqrt and one division per point — the irreducible part of the crank term
/// λ sin ψ cos ψ / √(1 − λ² sin²ψ) — with a load and a store, vectorised.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2+fma", "x86_64+avx2+fma"))]
fn sqrt_and_division(x: &[f64], out: &mut [f64]) {
    for (o, &v) in out.iter_mut().zip(x) {
        let s = 0.1 * v; // within the sqrt's domain, as sin ψ is
        *o = s / (1.0 - 0.09 * (s * s)).sqrt();
    }
    std::hint::black_box(out);
}

criterion_group!(benches, kernels);
criterion_main!(benches);
