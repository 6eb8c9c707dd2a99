use super::*;
use crate::mechanism::{crank_phases, Acting, Strokes};
use crate::series::{build_series, SeriesKind};
use std::cell::Cell;

/// A curve that counts its evaluations.
struct Counting<'a, C: Curve> {
    curve: &'a C,
    evaluations: Cell<usize>,
}

impl<C: Curve> Curve for Counting<'_, C> {
    fn scale(&self) -> f64 {
        self.curve.scale()
    }
    fn at(&self, y: f64) -> (f64, f64, f64) {
        self.evaluations.set(self.evaluations.get() + 1);
        self.curve.at(y)
    }
    fn bounds(&self, a: f64, b: f64) -> Bounds {
        self.curve.bounds(a, b)
    }
    fn cells(&self) -> usize {
        self.curve.cells()
    }
}

/// (extrema, evaluations of Q) for one design, on the curve the search would take.
fn counted(design: Design, alphas: &[f64]) -> (EnergyExtrema, usize) {
    let phases = Phases::new(alphas).unwrap();
    let series = build_series(SeriesKind::Exact, &[design], alphas, Parallelism::SERIAL)
        .pop()
        .unwrap();
    let units = [Coefficients::new(&design)];
    let closed = ClosedCurve {
        units: &units,
        phases: &phases,
        cells: 0,
    };
    let zero = closed.at(0.0).2;
    let curve = SeriesCurve::new(&series);
    if series.complete {
        let counting = Counting {
            curve: &curve,
            evaluations: Cell::new(0),
        };
        (search(&counting, zero), counting.evaluations.get())
    } else {
        let closed = ClosedCurve {
            cells: 64,
            ..closed
        };
        let counting = Counting {
            curve: &closed,
            evaluations: Cell::new(0),
        };
        (search(&counting, zero), counting.evaluations.get())
    }
}

/// Sweep-like designs: k = 1 … 12, two- and four-stroke, λ 0.2 … 0.43, any tilt.
fn sweep_like() -> Vec<(Design, Vec<f64>)> {
    let mut cases = Vec::new();
    for k in 1..=12 {
        for strokes in [Strokes::Two, Strokes::Four] {
            let alphas = crank_phases(k, strokes, Acting::Single).unwrap();
            for i in 0..20 {
                let x = i as f64;
                let design =
                    Design::new(0.2 + 0.012 * x, 0.15 * x, 0.05, 0.04 - 0.004 * x).unwrap();
                cases.push((design, alphas.clone()));
            }
        }
    }
    cases
}

#[test]
fn a_design_takes_a_few_evaluations() {
    // The work of a sweep's extrema: ~12 evaluations of the series per design (a grid
    // of 8+ cells, a split or two, two Newton steps per root), never many.
    let cases = sweep_like();
    let counts: Vec<usize> = cases.iter().map(|(d, a)| counted(*d, a).1).collect();
    let mean = counts.iter().sum::<usize>() as f64 / counts.len() as f64;
    assert!(mean <= 20.0, "{mean} evaluations per design");
    assert!(*counts.iter().max().unwrap() <= 200, "{counts:?}");
}

#[test]
fn near_one_the_work_is_bounded() {
    // Issue 13, item 4: λ up to the last double below 1, where the search runs on the
    // closed form and halves the cells across the ~√(1 − λ²)-wide features near π/2.
    let v8 = [0.0, 0.5, 1.0, 1.5].map(|x| x * std::f64::consts::PI);
    for lambda in [
        0.9999,
        1.0 - 1e-8,
        1.0 - 1e-12,
        1.0 - 2f64.powi(-52),
        1.0 - 2f64.powi(-53),
    ] {
        for alphas in [
            vec![0.0],
            v8.to_vec(),
            crank_phases(3, Strokes::Two, Acting::Single).unwrap(),
        ] {
            let design = Design::new(lambda, 1.1, 1.3, 0.4).unwrap();
            let (extrema, evaluations) = counted(design, &alphas);
            assert!(evaluations <= 2_000, "λ = {lambda}: {evaluations}");
            assert!(extrema.range.is_finite() && extrema.range > 0.0);
        }
    }
}

#[test]
fn crowded_roots_are_separated() {
    // Three roots of Q within ~1e-2 of bottom dead centre (u2 ≈ −(1 − λ)·u1, tilt
    // ~1e-7): the grid scan found one of them and missed the deepest minimum by ~1e-8
    // relative. Against dense sampling of the closed form around the cluster.
    let (lambda, delta, tilt, alpha) = (
        0.1677057617477402,
        6.257907076319158e-05,
        9.379743138017965e-08,
        2.7899826191419748,
    );
    let design = Design::new(
        lambda,
        std::f64::consts::FRAC_PI_2 + tilt,
        1.0,
        -(1.0 - lambda) * (1.0 + delta),
    )
    .unwrap();
    let phases = Phases::new(&[alpha]).unwrap();
    let centre = std::f64::consts::PI - alpha;
    let phi: Vec<f64> = (0..=400_000)
        .map(|i| centre - 0.05 + 0.1 * i as f64 / 400_000.0)
        .chain((0..=20_000).map(|i| TAU * i as f64 / 20_000.0))
        .collect();
    let u = crate::exact::evaluate_one(crate::Quantity::PotentialEnergy, &design, &phases, &phi);
    let (lo, hi) = u
        .iter()
        .fold((f64::MAX, f64::MIN), |(lo, hi), &x| (lo.min(x), hi.max(x)));
    let (extrema, _) = counted(design, &[alpha]);
    assert!(extrema.min <= lo + 1e-15, "{} vs sampled {lo}", extrema.min);
    assert!(extrema.max >= hi - 1e-15, "{} vs sampled {hi}", extrema.max);
}
