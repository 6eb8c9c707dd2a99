"""Compare the criterion benches of two builds, run alternately on the same host.

    python benches/compare_builds.py [--base REF] [--head REF|.] [--bench NAME ...]
                                     [--filter REGEX] [--rounds N] [--threshold PCT]
                                     [--fail-above PCT] [--keep]

Each side is checked out into its own git worktree under a temporary directory and built
there with its own CARGO_TARGET_DIR (`cargo bench -p multicrank-benches --no-run`), so
neither build touches the repository's target/ and both can be compared in one session.
The bench executables then run alternately — base, head, base, head, … (--rounds pairs) —
so that a noisy, shared host disturbs both sides alike; every run writes criterion's
results under its own CRITERION_HOME, and for each benchmark the best (lowest) median of
a side's rounds is kept. RAYON_NUM_THREADS=1 for every run: the serial groups are what
is compared (the parallel ones then measure the pool's overhead on one thread).

Prints, for every benchmark both sides have, the base and head times, head/base, and a
flag where head is slower by more than --threshold percent (default 5). It reports; it
never fails a build: the exit status is 0 unless --fail-above PCT is given and a
benchmark regressed by more than PCT percent (then 1).

--base defaults to the merge-base of HEAD and main, --head to HEAD; "." as --head means
the working tree as it is (uncommitted changes included), built in place but into the
temporary target directory. --bench picks criterion bench targets (default: every one in
benches/Cargo.toml); --filter is passed to criterion as its benchmark filter, e.g.
'exact/force/(points|uniform)/serial'. Fat-LTO release builds take minutes each.

Example (the closed form, serial, against the merge-base):

    python benches/compare_builds.py --bench kernels --filter 'exact/.*/serial' --rounds 3

Standard library only.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def git(*args: str, cwd: Path = ROOT) -> str:
    return subprocess.run(["git", *args], cwd=cwd, capture_output=True, text=True, check=True).stdout.strip()


def bench_names(tree: Path = ROOT) -> list[str]:
    """The [[bench]] targets of `tree`'s benches/Cargo.toml."""
    text = (tree / "benches" / "Cargo.toml").read_text()
    return re.findall(r'\[\[bench\]\]\s*\nname\s*=\s*"([^"]+)"', text)


def checkout(ref: str, where: Path) -> Path:
    """A detached worktree of `ref` at `where` ("." : the repository's own working tree)."""
    if ref == ".":
        return ROOT
    git("worktree", "add", "--detach", str(where), ref)
    return where


def build(tree: Path, target: Path, benches: list[str]) -> dict[str, Path]:
    """Build the bench executables of `tree` into `target`; their paths by bench name."""
    command = ["cargo", "bench", "-p", "multicrank-benches", "--no-run", "--message-format=json"]
    for name in benches:
        command += ["--bench", name]
    env = dict(os.environ, CARGO_TARGET_DIR=str(target))
    print(f"building {tree} (target {target}) ...", file=sys.stderr, flush=True)
    out = subprocess.run(command, cwd=tree, env=env, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"build failed in {tree}:\n{out.stderr[-4000:]}")
    executables = {}
    for line in out.stdout.splitlines():
        try:
            message = json.loads(line)
        except json.JSONDecodeError:
            continue
        target_info = message.get("target", {})
        if message.get("executable") and "bench" in target_info.get("kind", []):
            executables[target_info["name"]] = Path(message["executable"])
    return executables


def run_once(executable: Path, home: Path, args: argparse.Namespace) -> None:
    command = [str(executable), "--bench", "--noplot"]
    command += ["--warm-up-time", str(args.warm_up_time), "--measurement-time", str(args.measurement_time)]
    if args.filter:
        command.append(args.filter)
    env = dict(os.environ, CRITERION_HOME=str(home), RAYON_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    subprocess.run(command, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)


def medians(home: Path) -> dict[str, float]:
    """Median time (ns) of every benchmark criterion wrote under `home`."""
    found = {}
    for estimates in home.glob("**/new/estimates.json"):
        meta = json.loads((estimates.parent / "benchmark.json").read_text())
        found[meta["full_id"]] = json.loads(estimates.read_text())["median"]["point_estimate"]
    return found


def show(ns: float) -> str:
    for unit, scale in (("s", 1e9), ("ms", 1e6), ("µs", 1e3)):
        if ns >= scale:
            return f"{ns / scale:.3f} {unit}"
    return f"{ns:.1f} ns"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", help="git ref of the baseline (default: merge-base of HEAD and main)")
    parser.add_argument("--head", default="HEAD", help='git ref to compare, or "." for the working tree')
    parser.add_argument("--bench", action="append", help="criterion bench target (repeatable; default all)")
    parser.add_argument("--filter", help="criterion benchmark filter (a regex)")
    parser.add_argument("--rounds", type=int, default=2, help="alternating pairs of runs (default 2)")
    parser.add_argument("--threshold", type=float, default=5.0, help="flag slower by more than PCT")
    parser.add_argument("--fail-above", type=float, help="exit 1 if a benchmark regressed by more than PCT")
    parser.add_argument("--warm-up-time", type=float, default=1.0)
    parser.add_argument("--measurement-time", type=float, default=3.0)
    parser.add_argument("--keep", action="store_true", help="keep the temporary worktrees and builds")
    args = parser.parse_args()

    base = args.base or git("merge-base", "HEAD", "main")
    benches = args.bench or bench_names()
    scratch = Path(tempfile.mkdtemp(prefix="multicrank-compare-"))
    sides = {"base": base, "head": args.head}
    trees = {}
    try:
        executables = {}
        for side, ref in sides.items():
            trees[side] = checkout(ref, scratch / f"tree-{side}")
            here = [name for name in benches if name in bench_names(trees[side])]
            executables[side] = build(trees[side], scratch / f"target-{side}", here)
        best: dict[str, dict[str, float]] = {side: {} for side in sides}
        for round_ in range(args.rounds):
            for side in sides:  # base, head, base, head, ...
                for name in benches:
                    if name not in executables[side]:
                        continue  # a bench target the other side does not have yet
                    home = scratch / f"criterion-{side}-{name}-{round_}"
                    print(f"round {round_ + 1}/{args.rounds}: {side} {name}", file=sys.stderr, flush=True)
                    run_once(executables[side][name], home, args)
                    for bench_id, ns in medians(home).items():
                        best[side][bench_id] = min(ns, best[side].get(bench_id, float("inf")))

        # natural order: .../serial/6 before .../serial/12
        def natural(bench_id: str) -> list:
            return [int(part) if part.isdigit() else part for part in re.split(r"(\d+)", bench_id)]

        common = sorted(set(best["base"]) & set(best["head"]), key=natural)
        print(f"base {base[:12]}  head {args.head}  (best median of {args.rounds} alternating runs, one thread)")
        width = max([len(b) for b in common] + [9])
        print(f"{'benchmark':<{width}} {'base':>12} {'head':>12} {'head/base':>10}")
        worst = 0.0
        for bench_id in common:
            before, after = best["base"][bench_id], best["head"][bench_id]
            ratio = after / before
            change = (ratio - 1.0) * 100.0
            worst = max(worst, change)
            flag = f"  slower by {change:.1f}%" if change > args.threshold else ""
            print(f"{bench_id:<{width}} {show(before):>12} {show(after):>12} {ratio:>10.3f}{flag}")
        only = sorted(set(best["base"]) ^ set(best["head"]))
        if only:
            print(f"\non one side only: {', '.join(only)}")
        if args.fail_above is not None and worst > args.fail_above:
            return 1
        return 0
    finally:
        for tree in trees.values():
            if tree != ROOT and not args.keep:
                subprocess.run(["git", "worktree", "remove", "--force", str(tree)], cwd=ROOT, capture_output=True)
        if args.keep:
            print(f"kept {scratch}", file=sys.stderr)
        else:
            shutil.rmtree(scratch, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
