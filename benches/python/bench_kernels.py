"""multicrank against the plain-numpy baseline (multicrank.reference), same process.

    python benches/python/bench_kernels.py [--points 1000000] [--repeat 7]

For k = 1, 4, 6, 12 on a grid of φ over one revolution (λ = 0.3, two-stroke phases) it
times `generalized_force` (methods "exact" and "series") and `potential_energy` against the
baseline `multicrank.reference.generalized_force` / `potential_energy` (method "exact"),
with φ given as a plain array ("points") and as `mc.uniform_grid` ("grid": rotations),
and `lambda_coefficients(λ, 24)` per λ; best of --repeat, once with one
rayon thread (RAYON_NUM_THREADS=1, each setting in its own child process because rayon
fixes its pool at first use) and once with all cores, and prints ns per point and the
speed-up over the baseline. Refuses a debug build of the extension.
"""

from __future__ import annotations

import argparse
import functools
import json
import sys

from timing import best_time, per_thread_count


def measure(points: int, repeat: int) -> list[dict]:
    import numpy as np

    import multicrank as mc
    import multicrank.reference as ref

    if mc.build_profile != "release":
        sys.exit(f"refusing to benchmark a {mc.build_profile} build: pip install . (release) first")
    grid = mc.uniform_grid(points)
    phi = np.array(grid)  # the same points as a plain array
    rows = []
    for cranks in (1, 4, 6, 12):
        design = dict(crank_ratio=0.3, inclination=1.0, u1=0.8, u2=0.3, phases=mc.crank_phases(cranks))
        cases = [
            ("generalized_force", "exact", "points", {}),
            ("generalized_force", "exact", "grid", {}),
            ("generalized_force", "series", "points", {"method": "series"}),
            ("generalized_force", "series", "grid", {"method": "series"}),
            ("potential_energy", "exact", "points", {}),
        ]
        baselines = {}
        for name, method, angles, options in cases:
            where = grid if angles == "grid" else phi
            # partial binds this iteration's values (a lambda would see the loop's last ones).
            fast = best_time(functools.partial(getattr(mc, name), where, **design, **options), repeat)
            if name not in baselines:
                baselines[name] = best_time(functools.partial(getattr(ref, name), phi, **design), max(3, repeat // 2))
            rows.append(
                dict(
                    function=f"{name}[{method}]",
                    phi=angles,
                    cranks=cranks,
                    fast_ns=fast / points * 1e9,
                    base_ns=baselines[name] / points * 1e9,
                )
            )
    lam = np.linspace(0.0, 0.95, 10_000)
    fast = best_time(lambda: mc.lambda_coefficients(lam, 24), repeat)
    base = best_time(lambda: ref.lambda_coefficients(lam, 24), 1)
    rows.append(
        dict(
            function="lambda_coefficients",
            phi="-",
            cranks="-",
            fast_ns=fast / lam.size * 1e9,
            base_ns=base / lam.size * 1e9,
        )
    )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(measure(args.points, args.repeat)))
        return
    results = per_thread_count(__file__, args.points, args.repeat)
    if args.markdown:
        print("| function | φ | k | threads | baseline ns/pt | multicrank ns/pt | ns per (pt, crank) | ratio |")
        print("|---|---|---|---|---|---|---|---|")
        for threads, rows in results.items():
            for r in rows:
                ratio = r["base_ns"] / r["fast_ns"]
                per_crank = f"{r['fast_ns'] / r['cranks']:.2f}" if "exact" in r["function"] else ""
                print(
                    f"| {r['function']} | {r['phi']} | {r['cranks']} | {threads} | {r['base_ns']:.1f} | "
                    f"{r['fast_ns']:.2f} | {per_crank} | {ratio:.1f}× |"
                )
        return
    print(
        f"{args.points:,} points, λ = 0.3, two-stroke phases; ns per point (best of {args.repeat}); "
        "ratio = baseline time / multicrank time\n"
    )
    print("lambda_coefficients: ns per λ for Λ_0…Λ_24, λ spread over [0, 0.95]\n")
    print(f"{'function':<28} {'phi':>6} {'k':>3} {'threads':>7} {'baseline':>9} {'multicrank':>10} {'ratio':>7}")
    for threads, rows in results.items():
        for r in rows:
            print(
                f"{r['function']:<28} {r['phi']:>6} {r['cranks']:>3} {threads:>7} {r['base_ns']:>9.1f}"
                f" {r['fast_ns']:>10.2f} {r['base_ns'] / r['fast_ns']:>6.1f}x"
            )


if __name__ == "__main__":
    main()
