"""Write motion_fixtures.json: built-in machines, their indicator diagrams as SciPy PPoly arrays,
and what the Python implementation's ``mc.steady_state`` (load "balance") says of them: at the
machine's own speed, near stall (graded panels) and below it (``StallError.min_rpm``), and the
flywheels ``mc.flywheel_inertia`` sizes for δ = 1/40, 1/100 and the machine's class value.

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
from multicrank.presets import MACHINE_CLASSES, SPEED_FLUCTUATION

MACHINES = ("slow-compressor", "marine-2t-twin", "inline-4", "boxer-compressor")
#: Speeds [1/min] near stall, where the time quadrature is graded towards the dead point, and
#: below it (a StallError with min_rpm), per machine.
NEAR_STALL = {"slow-compressor": (9.0, 12.0)}
STALLS = {"slow-compressor": (5.0,)}
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
#: SteadyState's arrays: φ = linspace(0, Φ, POINTS).
POINTS = 361
#: The square-law load's results (closed form) kept beside its arrays.
SQUARE_LAW = (
    "delta",
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
FLYWHEEL = ("shaft_inertia", "shaft_inertia_without_gravity", "textbook", "energy_swing")


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
    state = mc.steady_state(machine, rpm=machine.rpm, points=POINTS)
    extremes = refined_extremes(machine, machine.rpm)
    near = [
        {
            "rpm": rpm,
            "steady_state": {key: float(getattr(slow, key)) for key in RESULTS},
            "refined": refined_extremes(machine, rpm),
            "curves": curves(slow),
        }
        for rpm in NEAR_STALL.get(name, ())
        for slow in [mc.steady_state(machine, rpm=rpm, points=POINTS)]
    ]
    stalls = []
    for rpm in STALLS.get(name, ()):
        try:
            mc.steady_state(machine, rpm=rpm)
        except mc.StallError as error:
            stalls.append(
                {
                    "rpm": rpm,
                    "angle": error.angle,
                    "min_rpm": error.min_rpm,
                    "refined_min_rpm": refined_min_rpm(machine, rpm),
                }
            )
        else:
            raise AssertionError(f"{name} runs at {rpm} rpm")
    targets = (1 / 40, 1 / 100, SPEED_FLUCTUATION[MACHINE_CLASSES[name]][1])
    flywheels = []
    for delta in targets:
        found = mc.flywheel_inertia(machine, delta=delta, rpm=machine.rpm)
        # δ at Python's I_w with its extremes searched again exactly: where Python's own δ
        # (extremes on interpolants) is off, so is its I_w, by about as much (relative).
        sized = machine.replace(shaft_inertia=found.shaft_inertia)
        exact = refined_extremes(sized, machine.rpm)["delta"]
        flywheels.append(
            {"delta": delta, "refined_delta": exact} | {key: float(getattr(found, key)) for key in FLYWHEEL}
        )
    return {
        "name": name,
        "strokes": machine.strokes,
        "g": machine.g,
        "shaft_inertia": machine.shaft_inertia,
        "rpm": machine.rpm,
        "cylinders": cylinders,
        "diagrams": diagrams,
        "steady_state": {key: float(getattr(state, key)) for key in RESULTS},
        "curves": curves(state),
        "refined": extremes,
        "square_law": square_laws(machine, state.mean_load_torque),
        "near_stall": near,
        "stalls": stalls,
        "flywheels": flywheels,
    }


def curves(state) -> dict:
    """SteadyState's phi, omega [rad/s] and time [s] (t(0) = 0 and t(Φ) = period are set)."""
    return {key: getattr(state, key).tolist() for key in ("phi", "omega", "time")}


def square_laws(machine, balance_load: float) -> list:
    """``mc.steady_state`` under a square-law load (the closed form) at M_n = T, the "balance"
    load at the machine's own speed, and n_n that speed: an engine (T > 0) alone and with a
    constant drive of T/2 beside a load of 1.5 T; a compressor (T < 0) with a drive of 1.5|T|
    beside a load of |T|/2, and of 3|T| beside 2|T| (all run near the machine's speed)."""
    found = []
    size = abs(balance_load)
    cases = (
        ((None, size), (0.5 * size, 1.5 * size))
        if balance_load > 0
        else ((1.5 * size, 0.5 * size), (3 * size, 2 * size))
    )
    for drive, torque in cases:
        load = mc.PowerLawLoad(torque, rpm=machine.rpm)
        state = mc.steady_state(machine, load=load, drive=drive, points=POINTS)
        assert state.method == "closed form", state.method
        found.append(
            {
                "torque": torque,
                "rpm": machine.rpm,
                "drive": 0.0 if drive is None else drive,
                "coefficient": load.coefficient,
            }
            | {key: float(getattr(state, key)) for key in SQUARE_LAW}
            | {"curves": curves(state)}
        )
    return found


def refined_extremes(machine, rpm: float) -> dict:
    """ω_max and ω_min searched again, by SciPy's bounded Brent minimiser on the Python
    solutions' own exact ω(φ) around the angles they located (± a tenth of a radian, several
    Gauss nodes), for the machine, the machine with g = 0 and gravity alone: an independent
    check of the extremes, since steady_state locates them on the panels' interpolants (to
    ~1e-7 rad where ω is smooth, worse where a pressure table's kinks sit close by), and
    the δ they give."""
    tables = _periodic.cycle_tables(machine, True)
    rules = _periodic.resolve_rules("balance", None)
    omega_mean = math.pi * rpm / 30
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


def refined_min_rpm(machine, rpm: float, ratio: float = 1e-3) -> float:
    """StallError.min_rpm searched again with ω_min taken as in refined_extremes: the root in
    log s of ω_min/ω_m − ratio with ω_min found by SciPy's bounded Brent minimiser on the exact
    ω(φ) of each trial (steady_state locates ω_min on the panels' interpolants, which near
    stall, where the dip of ω is a few 1e-4 rad wide, leaves it ~1e-6 high)."""
    tables = _periodic.cycle_tables(machine, True)
    rules = _periodic.resolve_rules("balance", None)
    balance = _periodic.balance_at(tables, rules, math.pi * rpm / 30)

    def shortfall(log_s: float) -> float:
        periodic = balance.at_margin(math.exp(log_s))
        centre = periodic.extremes.phi_min

        def omega(phi: float) -> float:
            return float(periodic.omega_at(np.array([phi % machine.cycle]))[0])

        best = scipy.optimize.minimize_scalar(
            omega, bounds=(centre - 0.1, centre + 0.1), method="bounded", options={"xatol": 1e-12}
        )
        return min(omega(best.x), periodic.extremes.omega_min) / periodic.omega_mean - ratio

    low, high = math.log(1e-6 * balance.swing), math.log(balance.swing) + 1.0
    while shortfall(high) < 0:
        high += 2.0
    while shortfall(low) > 0:
        low -= 2.0
    log_s = scipy.optimize.brentq(shortfall, low, high, xtol=1e-12)
    return balance.at_margin(math.exp(log_s)).omega_mean * 30 / math.pi


def python_only() -> None:
    """mc.steady_state and mc.flywheel_inertia by the Python implementation: the core's
    MotionMachine is not offered to them (else the fixtures would be the core's own numbers)."""
    from multicrank.motion import flywheel, steady

    steady.motion_machine = flywheel.motion_machine = lambda machine, **options: None


def main() -> None:
    python_only()
    out = pathlib.Path(__file__).with_name("motion_fixtures.json")
    data = {"multicrank": mc.__version__, "machines": [fixture(name) for name in MACHINES]}
    out.write_text(json.dumps(data, separators=(",", ":")) + "\n")
    print(f"{out}: {out.stat().st_size} bytes")


if __name__ == "__main__":
    main()
