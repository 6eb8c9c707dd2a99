"""Sweep throughput and streaming memory, against a straightforward loop over the reference.

    python benches/python/bench_sweep.py [--designs 200000] [--stream 10000000]

1. Grid outputs (force_max_abs, force_rms) at phi = 360 on designs with mixed k = 1…12,
   two- and four-stroke: design-points per second with one rayon thread and with all, and
   the ratio to a plain Python loop calling multicrank.reference per design (timed on a
   subset, same process).
2. The exact extrema alone (energy_range, = δ_g: a rigorous root search per design, no φ
   grid) and all outputs (adds the grid outputs and the leading harmonic): designs/s.
3. --stream N designs of a lazy DesignGrid streamed to Parquet (force outputs): time and
   the child process's peak resident memory.
Each measurement runs in its own child process (rayon fixes its pool at first use).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import sys
import tempfile
import time

from timing import child_rows


def designs(n: int):
    import numpy as np
    import pandas as pd

    rng = np.random.default_rng(0)
    return pd.DataFrame(
        {
            "crank_ratio": rng.uniform(0.2, 0.45, n),
            "inclination": rng.uniform(0, np.pi, n),
            "u1": rng.uniform(0, 0.1, n),
            "u2": rng.uniform(-0.05, 0.05, n),
            "cranks": rng.integers(1, 13, n),
            "strokes": rng.choice([2, 4], n),
        }
    )


def child_rates(n: int) -> dict:
    import numpy as np

    import multicrank as mc
    import multicrank.reference as ref

    if mc.build_profile != "release":
        sys.exit("refusing to benchmark a debug build")
    frame = designs(n)
    grid_outputs = ("force_max_abs", "force_rms")
    mc.sweep(frame.iloc[:1000], phi=360, outputs=grid_outputs)  # warm up
    best = min(_timed(lambda: mc.sweep(frame, phi=360, outputs=grid_outputs)) for _ in range(3))
    extrema = min(_timed(lambda: mc.sweep(frame, phi=360, outputs=("energy_range",))) for _ in range(3))
    everything = _timed(lambda: mc.sweep(frame.iloc[: n // 4], phi=360))
    phi = np.arange(360) * (2 * np.pi / 360)
    subset = frame.iloc[:2000]

    def loop():
        for row in subset.itertuples():
            q = ref.generalized_force(
                phi,
                crank_ratio=row.crank_ratio,
                inclination=row.inclination,
                u1=row.u1,
                u2=row.u2,
                phases=mc.crank_phases(int(row.cranks), int(row.strokes)),
            )
            np.abs(q).max(), np.sqrt(np.mean(q**2))

    baseline = _timed(loop) / len(subset) * n
    return {
        "grid_rate": n * 360 / best,
        "baseline_rate": n * 360 / baseline,
        "extrema_rate": n / extrema,
        "all_rate": (n // 4) / everything,
    }


def child_stream(n: int) -> dict:
    import numpy as np

    import multicrank as mc

    side = round(n**0.25)
    grid = mc.DesignGrid(
        crank_ratio=np.linspace(0.2, 0.45, side),
        inclination=np.linspace(0, np.pi, side),
        u1=np.linspace(0.001, 0.1, side),
        u2=np.linspace(-0.05, 0.05, -(-n // side**3)),
    )
    with tempfile.TemporaryDirectory() as tmp:
        elapsed = _timed(
            lambda: mc.sweep(grid, phi=360, outputs=("force_max_abs", "force_rms"), out=os.path.join(tmp, "s.parquet"))
        )
    return {
        "designs": len(grid),
        "seconds": elapsed,
        "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    }


def _timed(function) -> float:
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--designs", type=int, default=200_000)
    parser.add_argument("--stream", type=int, default=10_000_000, help="designs to stream (0: skip)")
    parser.add_argument("--markdown", action="store_true", help="print Markdown")
    parser.add_argument("--child", choices=["rates", "stream"], help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child == "rates":
        print(json.dumps(child_rates(args.designs)))
        return
    if args.child == "stream":
        print(json.dumps(child_stream(args.stream)))
        return

    def run(kind: str, threads: str) -> dict:
        arguments = ("--designs", str(args.designs), "--stream", str(args.stream))
        return child_rows(__file__, kind, *arguments, threads=threads)

    if args.markdown:
        print(
            "| threads | multicrank design-points/s | reference loop | ratio | energy_range, designs/s "
            "| all outputs, designs/s |"
        )
        print("|---|---|---|---|---|---|")
        for threads in ("1", str(os.cpu_count())):
            r = run("rates", threads)
            print(
                f"| {threads} | {r['grid_rate']:.3e} | {r['baseline_rate']:.3e} | "
                f"{r['grid_rate'] / r['baseline_rate']:.0f}× | {r['extrema_rate']:,.0f} | {r['all_rate']:,.0f} |"
            )
        if args.stream:
            s = run("stream", str(os.cpu_count()))
            print(
                f"\nStreamed {s['designs']:,} designs to Parquet in {s['seconds']:.1f} s "
                f"({s['designs'] / s['seconds']:,.0f} designs/s); peak resident memory {s['peak_mb']:.0f} MB."
            )
        return
    print(f"{args.designs:,} designs, mixed k = 1…12, phi = 360; design-points/s (grid outputs)\n")
    print(f"{'threads':>7} {'multicrank':>14} {'reference loop':>15} {'ratio':>8} {'all outputs, designs/s':>24}")
    for threads in ("1", str(os.cpu_count())):
        r = run("rates", threads)
        ratio = r["grid_rate"] / r["baseline_rate"]
        print(
            f"{threads:>7} {r['grid_rate']:>14.3e} {r['baseline_rate']:>15.3e} {ratio:>7.0f}x {r['all_rate']:>24,.0f}"
        )
    if args.stream:
        s = run("stream", str(os.cpu_count()))
        print(
            f"\nstreamed {s['designs']:,} designs to Parquet in {s['seconds']:.1f} s "
            f"({s['designs'] / s['seconds']:,.0f} designs/s), peak memory {s['peak_mb']:.0f} MB"
        )


if __name__ == "__main__":
    main()
