"""The routes of one steady state against the plain one, same process, one core.

    python benches/python/bench_routes.py [--repeat 7] [--markdown]

``mc.steady_state(slow-compressor, rpm=120).delta`` (the plain "balance" route: one solve on
the machine's cycle tables) is the baseline; beside it, on the same machine and speed, the
questions that used to leave the Rust core for a Python implementation and now stay in it:

- a constant drive (``drive=500``: the load grows by it, the motion is the plain one's);
- a drive that varies over the cycle (``drive=lambda phi, omega: 500 + 50 sin phi``: sampled once
  at the mean speed, its work integrated exactly by the core, its tables made for the call);
- a new machine whose pressure is a Python callable (its first steady state: the callable
  sampled, the native machine and its cycle tables made), and the same machine asked again.

Each figure is the best of --repeat runs (benches/python/timing.py); the ratio is against the
plain route measured in the same run. Runs in a child process with RAYON_NUM_THREADS=1.
Refuses a debug build of the extension.
"""

from __future__ import annotations

import argparse
import json

from timing import best_time, child_rows


def measure(repeat: int) -> list[dict]:
    import numpy as np

    import multicrank as mc

    if mc.build_profile != "release":
        raise SystemExit(f"bench_routes: refusing a {mc.build_profile} build; install the release wheel")
    compressor = mc.presets.MACHINES["slow-compressor"]
    rpm = 120.0

    def smooth_pressure(theta):
        return 8e5 * np.exp(4 * (np.cos(theta - 0.35) - 1)) - 0.2e5

    callable_gas = [c.replace(pressure=smooth_pressure, pressure_crank_end=None) for c in compressor.cylinders]
    asked_again = compressor.replace(cylinders=callable_gas)
    cases = {
        "plain (balance)": lambda: mc.steady_state(compressor, rpm=rpm).delta,
        "drive=500": lambda: mc.steady_state(compressor, rpm=rpm, drive=500.0).delta,
        "drive=500+50 sin φ": lambda: (
            mc.steady_state(compressor, rpm=rpm, drive=lambda phi, omega: 500.0 + 50.0 * np.sin(phi)).delta
        ),
        # replace() makes a new Machine: its native machine (and the sampling) made afresh.
        "callable pressure, new machine": lambda: (
            mc.steady_state(compressor.replace(cylinders=callable_gas), rpm=rpm).delta
        ),
        "callable pressure, asked again": lambda: mc.steady_state(asked_again, rpm=rpm).delta,
    }
    rows = [{"route": name, "seconds": best_time(function, repeat)} for name, function in cases.items()]
    plain = rows[0]["seconds"]
    for row in rows:
        row["ratio"] = row["seconds"] / plain
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(measure(args.repeat)))
        return
    rows = child_rows(__file__, "--repeat", str(args.repeat))
    print("| steady_state of the slow compressor at 120 rpm | time | against the plain route |")
    print("|---|---|---|")
    for row in rows:
        print(f"| {row['route']} | {row['seconds'] * 1e6:.1f} µs | {row['ratio']:.2f}× |")
    if not args.markdown:
        print("\none core (RAYON_NUM_THREADS=1); best of --repeat, each run long enough to time")


if __name__ == "__main__":
    main()
