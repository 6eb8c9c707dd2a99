"""The evaluation functions of two or more installed builds, timed alternately in one run.

    python benches/python/bench_builds.py /tmp/venv-old/bin/python .venv/bin/python [--rounds 5]

Each interpreter is a virtual environment with a release build of multicrank installed (for
an old commit: ``git worktree add /tmp/old REV && pip wheel --no-deps /tmp/old`` into its own
venv). Each round runs every build once, one after the other, in a child process with one
rayon thread; each child times ``generalized_force`` (closed form and series) on 10⁶ points,
as a plain array and as a uniform grid, k = 1, 6, 12, λ = 0.3, best of ``--repeat`` calls.
The table gives each build's best over the rounds [ms] and the ratio to the first build.
Alternating the builds, rather than running one after the other, is what makes the ratio
fair on a shared host whose load changes from minute to minute. A report, never a test.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

CHILD = r"""
import json, sys, time
import numpy as np
import multicrank as mc

if mc.build_profile != "release":
    sys.exit(f"refusing to time a {mc.build_profile} build")
repeat = int(sys.argv[1])
grid = mc.uniform_grid(1_000_000)
points = np.array(grid)
best = {}
for k in (1, 6, 12):
    design = dict(crank_ratio=0.3, inclination=1.0, u1=0.8, u2=0.3, phases=mc.crank_phases(k))
    for method in ("exact", "series"):
        for kind, phi in (("points", points), ("grid", grid)):
            times = []
            for _ in range(repeat):
                start = time.perf_counter()
                mc.generalized_force(phi, **design, method=method)
                times.append(time.perf_counter() - start)
            best[f"{method} {kind} k={k}"] = 1e3 * min(times)
print(json.dumps(best))
"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("pythons", nargs="+", help="the interpreters of the builds, the first the reference")
    parser.add_argument("--rounds", type=int, default=5, help="rounds of all builds, alternately")
    parser.add_argument("--repeat", type=int, default=10, help="calls per case in one child, best kept")
    args = parser.parse_args()
    env = dict(os.environ, RAYON_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    # Absolute, not resolved: a venv's python is a link, and the venv is where it points from.
    args.pythons = [os.path.abspath(python) for python in args.pythons]
    best: list[dict[str, float]] = [{} for _ in args.pythons]
    for _ in range(args.rounds):
        for i, python in enumerate(args.pythons):
            # From a neutral directory, so that the build installed there is the one imported.
            output = subprocess.run(
                [python, "-c", CHILD, str(args.repeat)], env=env, cwd="/", capture_output=True, text=True, check=True
            ).stdout
            for case, ms in json.loads(output).items():
                best[i][case] = min(ms, best[i].get(case, float("inf")))
    names = [f"build {i}" for i in range(len(args.pythons))]
    print(f"best of {args.rounds} rounds × {args.repeat} calls, one thread, 10⁶ points, λ = 0.3 [ms]")
    for i, python in enumerate(args.pythons):
        print(f"  {names[i]}: {python}")
    header = (
        f"{'case':<22}"
        + "".join(f"{name:>12}" for name in names)
        + "".join(f"{'ratio ' + str(i):>10}" for i in range(1, len(names)))
    )
    print(header)
    for case in best[0]:
        times = [b[case] for b in best]
        print(
            f"{case:<22}" + "".join(f"{t:>12.3f}" for t in times) + "".join(f"{t / times[0]:>10.3f}" for t in times[1:])
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
