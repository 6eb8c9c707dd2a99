"""Write motion_fixtures.json: built-in machines, their indicator diagrams as SciPy PPoly arrays,
and what the Python implementation's ``mc.steady_state`` (load "balance") says of them.

The Rust core's energy method (rust/core/src/motion/) is checked against these numbers by
rust/core/tests/motion.rs. Run from the repository root, with the compiled extension in place:

    cp /work/main/python/multicrank/_native*.so python/multicrank/
    PYTHONPATH=python python rust/core/tests/data/make_motion_fixtures.py

Floats are written by ``repr`` (shortest round-trip), so the Rust side reads the very same
doubles, and the diagrams are listed once each (the cylinders refer to them by index).
"""

from __future__ import annotations

import json
import math
import pathlib

import numpy as np
import scipy.optimize

import multicrank as mc
from multicrank.machine.cylinder import unit_columns
from multicrank.motion import _periodic
from multicrank.motion._solvers import Balance

MACHINES = ("slow-compressor", "marine-2t-twin", "inline-4", "boxer-compressor")
RESULTS = (
    "delta",
    "delta_midrange",
    "delta_without_gravity",
    "delta_gravity_only",
    "omega_mean",
    "omega_max",
    "omega_min",
    "phi_max",
    "phi_min",
    "period",
    "mean_load_torque",
)


def fixture(name: str) -> dict:
    machine = mc.presets.MACHINES[name]
    diagrams: list = []
    index: dict[int, int] = {}

    def diagram(pressure) -> int | None:
        if pressure is None:
            return None
        if id(pressure) not in index:
            poly = pressure._poly  # the SciPy PPoly the diagram evaluates (pressure/diagram.py)
            index[id(pressure)] = len(diagrams)
            diagrams.append({"kind": pressure.kind, "x": poly.x.tolist(), "c": poly.c.tolist()})
        return index[id(pressure)]

    columns = unit_columns(machine.cylinders)
    cylinders = []
    for j, cylinder in enumerate(machine.cylinders):
        unit = {field: float(values[j]) for field, values in columns.items()}
        unit.update(
            bore=cylinder.bore,
            piston_rod_diameter=cylinder.piston_rod_diameter,
            head=diagram(cylinder.pressure),
            crank_end=diagram(cylinder.pressure_crank_end),
        )
        cylinders.append(unit)
    state = mc.steady_state(machine, rpm=machine.rpm)
    extremes = refined_extremes(machine, state)
    return {
        "name": name,
        "strokes": machine.strokes,
        "g": machine.g,
        "shaft_inertia": machine.shaft_inertia,
        "rpm": machine.rpm,
        "cylinders": cylinders,
        "diagrams": diagrams,
        "steady_state": {key: float(getattr(state, key)) for key in RESULTS},
        "refined": extremes,
    }


def refined_extremes(machine, state) -> dict:
    """ω_max and ω_min searched again, by SciPy's bounded Brent minimiser on the Python
    solutions' own exact ω(φ) around the angles they located (± a tenth of a radian, several
    Gauss nodes), for the machine, the machine with g = 0 and gravity alone: an independent
    check of the extremes, since steady_state locates them on the panels' interpolants (to
    ~1e-7 rad where ω is smooth, worse where a pressure table's kinks sit close by), and
    the δ they give."""
    tables = _periodic.cycle_tables(machine, True)
    rules = _periodic.resolve_rules("balance", None)
    omega_mean = math.pi * machine.rpm / 30
    solution = _periodic.balance_at(tables, rules, omega_mean).solve(omega_mean, 1e-3)
    variants = {
        "": solution,
        "without_gravity_": _periodic.balance_at(tables.without_gravity(), rules, omega_mean).solve(omega_mean, 1e-3),
        "gravity_only_": Balance(tables, None, 0.0, gas=False).solve(solution.omega_mean, 1e-3),
    }
    found = {}
    for prefix, periodic in variants.items():

        def omega(phi: float, periodic=periodic) -> float:
            return float(periodic.omega_at(np.array([phi % machine.cycle]))[0])

        extremes = periodic.extremes
        for name, centre, sign in (("max", extremes.phi_max, -1.0), ("min", extremes.phi_min, 1.0)):
            best = scipy.optimize.minimize_scalar(
                lambda phi, sign=sign, omega=omega: sign * omega(phi),
                bounds=(centre - 0.1, centre + 0.1),
                method="bounded",
                options={"xatol": 1e-12},
            )
            found[f"{prefix}omega_{name}"] = omega(best.x)
            found[f"{prefix}phi_{name}"] = float(best.x % machine.cycle)
        found[f"{prefix}delta"] = (found[f"{prefix}omega_max"] - found[f"{prefix}omega_min"]) / periodic.omega_mean
    return found


def main() -> None:
    out = pathlib.Path(__file__).with_name("motion_fixtures.json")
    data = {"multicrank": mc.__version__, "machines": [fixture(name) for name in MACHINES]}
    out.write_text(json.dumps(data, separators=(",", ":")) + "\n")
    print(f"{out}: {out.stat().st_size} bytes")


if __name__ == "__main__":
    main()
