"""The physical machine's kernels against a plain-numpy baseline, same process.

    python benches/python/bench_machine.py [--points 1000000] [--repeat 5] [--markdown]

For k = 1, 4, 6, 12 cylinders (λ = 0.3, rods with ΔI ≠ 0, webs and counterweights, phases
spread over the revolution, inclinations alternating like a V) on 10⁶ points φ it times
`Machine.reduced_inertia` (J and J' together) and `Machine.potential_energy` against a
baseline that is one vectorised numpy expression per cylinder — one sin and one cos of ψ,
one square root — written here from planar geometry (the baseline for U places every mass
point in the plane and sums m·g·height; the one for J differentiates the slider-crank's
travel and rod angle). Best of --repeat, once on one rayon thread and once on all cores
(each in its own child process: rayon fixes its pool at first use). Refuses a debug build.
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import sys

from timing import best_time, per_thread_count

LAMBDA = 0.3


def cylinders(count: int) -> list[dict]:
    r, rod = 0.05, 0.05 / LAMBDA
    return [
        dict(
            crank_radius=r,
            rod_length=rod,
            piston_mass=0.4,
            rod_mass=0.5,
            rod_cg=0.7 * rod,
            rod_inertia=0.8 * 0.5 * 0.7 * rod * 0.3 * rod,  # ΔI < 0, as in a real rod
            crank_mass=0.6,
            crank_cg_radius=0.5 * r,
            counterweight_mass=0.5,
            counterweight_radius=0.6 * r,
            phase=2 * math.pi * j / count,
            inclination=math.radians(90 + (45 if j % 2 else -45)),
        )
        for j in range(count)
    ]


def baseline_inertia(np, phi, units, shaft_inertia):
    """J and J' from s'(ψ), s''(ψ), β'(ψ), β''(ψ), one cylinder at a time."""
    inertia = np.full_like(phi, shaft_inertia)
    slope = np.zeros_like(phi)
    for u in units:
        r, rod, m_k, z = u["crank_radius"], u["rod_length"], u["rod_mass"], u["rod_cg"]
        lam = r / rod
        m_pin = u["piston_mass"] + m_k * (rod - z) / rod
        delta_i = u["rod_inertia"] - m_k * z * (rod - z)
        psi = phi + u["phase"]
        s, c = np.sin(psi), np.cos(psi)
        root = np.sqrt(1 - (lam * s) ** 2)
        ds = r * (s + lam * s * c / root)
        dds = r * (c + lam * (c * c - s * s + lam**2 * s**4) / root**3)
        db = lam * c / root
        ddb = -lam * (1 - lam**2) * s / root**3
        inertia += m_k * z / rod * r**2 + m_pin * ds**2 + delta_i * db**2
        slope += 2 * m_pin * ds * dds + 2 * delta_i * db * ddb
    return inertia, slope


def baseline_energy(np, phi, units, g):
    """Σ m·g·height of piston, rod, web and counterweight, each cylinder from its ψ = 0."""
    total = np.zeros_like(phi)
    for u in units:
        r, rod, gamma = u["crank_radius"], u["rod_length"], u["inclination"]
        # The web's and the counterweight's first moment, as a mass at the crank pin.
        web = (u["crank_mass"] * u["crank_cg_radius"] - u["counterweight_mass"] * u["counterweight_radius"]) / r

        def height_moment(psi, r=r, rod=rod, gamma=gamma, u=u, web=web):
            s, c = np.sin(psi), np.cos(psi)
            along = r * c + rod * np.sqrt(1 - (r / rod * s) ** 2)  # piston pin from the shaft, on the axis
            pin_y = r * (c * math.sin(gamma) + s * math.cos(gamma))  # the crank pin's height
            piston_y = along * math.sin(gamma)
            rod_y = piston_y + u["rod_cg"] / rod * (pin_y - piston_y)
            return u["piston_mass"] * piston_y + u["rod_mass"] * rod_y + web * pin_y

        total += g * (height_moment(phi + u["phase"]) - height_moment(np.zeros(1)))
    return total


def measure(points: int, repeat: int) -> list[dict]:
    import numpy as np

    import multicrank as mc

    if mc.build_profile != "release":
        sys.exit(f"refusing to benchmark a {mc.build_profile} build: pip install . (release) first")
    phi = np.linspace(0, 2 * np.pi, points, endpoint=False)
    rows = []
    for count in (1, 4, 6, 12):
        units = cylinders(count)
        machine = mc.Machine([mc.Cylinder(**u) for u in units], shaft_inertia=2.0)
        # The baselines are the oracle of this benchmark as well: they must agree.
        j_fast, dj_fast = machine.reduced_inertia(phi[:1000])
        j_base, dj_base = baseline_inertia(np, phi[:1000], units, 2.0)
        np.testing.assert_allclose(j_fast, j_base, rtol=1e-12)
        # Evenly spaced cylinders cancel most of J': compare against each cylinder's own scale.
        np.testing.assert_allclose(dj_fast, dj_base, rtol=1e-9, atol=1e-12 * 2e-3)
        np.testing.assert_allclose(
            machine.potential_energy(phi[:1000]),
            baseline_energy(np, phi[:1000], units, machine.g),
            rtol=1e-9,
            atol=1e-12 * count,
        )
        for name, fast, base in (
            (
                "reduced_inertia (J, J')",
                functools.partial(machine.reduced_inertia, phi),
                functools.partial(baseline_inertia, np, phi, units, 2.0),
            ),
            (
                "potential_energy",
                functools.partial(machine.potential_energy, phi),
                functools.partial(baseline_energy, np, phi, units, machine.g),
            ),
        ):
            rows.append(
                dict(
                    function=name,
                    cylinders=count,
                    fast_ns=best_time(fast, repeat) / points * 1e9,
                    base_ns=best_time(base, max(3, repeat // 2)) / points * 1e9,
                )
            )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(measure(args.points, args.repeat)))
        return
    results = per_thread_count(__file__, args.points, args.repeat)
    print("| function | cylinders | threads | baseline ns/pt | multicrank ns/pt | ratio |")
    print("|---|---|---|---|---|---|")
    for threads, rows in results.items():
        for r in rows:
            print(
                f"| {r['function']} | {r['cylinders']} | {threads} | {r['base_ns']:.1f} | {r['fast_ns']:.2f} | "
                f"{r['base_ns'] / r['fast_ns']:.1f}× |"
            )


if __name__ == "__main__":
    main()
