"""Write motion_fixtures.json: built-in machines' parameters and what an independent oracle
(oracle.py, beside this file) says of their steady running — at each machine's own speed
(load "balance"), with g = 0 and gravity alone, near stall and below it (the lowest speed
that runs), under a square-law load beside a constant drive, the flywheels for
δ = 1/40, 1/100 and the machine's class value, and the steady state and flywheel (δ = 1/40)
beside a driving torque that depends on φ (:func:`drive_of`, given to both as the same
``PPoly``).

The Rust core (rust/core/src/motion/) is checked against these numbers by
rust/core/tests/motion*.rs, and the Python package by tests/machine/test_native.py.

Why they test something: the oracle shares no code and no formula with multicrank. From the
library only the machines' *parameters* are read here (masses, lengths, inertias, phases,
inclinations, bores, g, I_w, each indicator diagram's table of angles and pressures and its
interpolation kind); the oracle places every unit in the plane, differentiates by the complex
step, interpolates the tables with SciPy itself, and finds the periodic solution with its own
quadratures and ``scipy.optimize.brentq`` (its docstring says how). The diagrams are written
as the oracle's own piecewise polynomials (SciPy ``PPoly`` coefficients ``c`` over the
table's angles ``x``), which is what the core is given by the tests.

Regenerate from the repository root (about two minutes):

    .venv/bin/python rust/core/tests/data/make_motion_fixtures.py

Everything is computed twice, with Gauss–Legendre rules of ``oracle.GL_POINTS`` and
``oracle.GL_CHECK`` points; the worst relative difference of the two runs, per kind of
quantity, is written as ``oracle.agreement`` (a measure of the oracle's own accuracy, which
the tests' tolerances must exceed). Floats are written by ``repr`` (shortest round-trip), so
the Rust side reads the very same doubles; the diagrams are listed once each (the cylinders
refer to them by index).
"""

from __future__ import annotations

import json
import math
import pathlib
import sys

import numpy as np
from scipy import interpolate

sys.path.insert(0, str(pathlib.Path(__file__).parent))
import oracle

MACHINES = ("slow-compressor", "marine-2t-twin", "inline-4", "boxer-compressor")
#: Speeds [1/min] near stall (the dip of ω a few 1e-4 rad wide) and below the lowest that
#: runs, per machine.
NEAR_STALL = {"slow-compressor": (9.0, 12.0)}
STALLS = {"slow-compressor": (5.0,)}
#: ω(φ) and t(φ) are written at φ = linspace(0, Φ, POINTS).
POINTS = 361
#: ω_min/ω_m below which the machine is taken to stall (the library's default).
RATIO = 1e-3
#: The kinds of quantity whose two runs' agreement is recorded.
KINDS = {
    "speeds": ("omega_mean", "omega_max", "omega_min", "period", "mean_load_torque"),
    "deltas": ("delta", "delta_midrange", "delta_without_gravity", "delta_gravity_only"),
    "near_stall_speeds": ("omega_min",),
    "flywheels": ("shaft_inertia", "shaft_inertia_without_gravity", "textbook", "energy_swing"),
    "min_rpm": ("min_rpm",),
}


def parameters(name: str):
    """The preset's parameters (read from multicrank: nothing computed by it)."""
    import multicrank as mc
    from multicrank.presets import MACHINE_CLASSES, SPEED_FLUCTUATION

    machine = mc.presets.MACHINES[name]
    return machine, SPEED_FLUCTUATION[MACHINE_CLASSES[name]][1], mc.__version__


def steady_record(state: oracle.Steady, without: oracle.Steady | None, alone: oracle.Steady) -> dict:
    return {
        "delta": state.delta,
        "delta_midrange": state.delta_midrange,
        "delta_without_gravity": without.delta if without is not None else math.nan,
        "delta_gravity_only": alone.delta,
        "omega_mean": state.omega_mean,
        "omega_max": state.omega_max,
        "omega_min": state.omega_min,
        "phi_max": state.phi_max,
        "phi_min": state.phi_min,
        "period": state.period,
        "mean_load_torque": state.mean_load_torque,
    }


def curves(phi: np.ndarray, state: oracle.Steady) -> dict:
    return {"phi": phi.tolist(), "omega": state.omega.tolist(), "time": state.time.tolist()}


def balance_at(cycle: oracle.Cycle, phi: np.ndarray, rpm: float) -> tuple[dict, dict]:
    omega_mean = math.pi * rpm / 30
    state = oracle.Balance(cycle, angles=phi).solve(omega_mean, ratio=RATIO)
    without = oracle.Balance(cycle, gravity=False).solve(omega_mean, ratio=RATIO)
    alone = oracle.Balance(cycle, gas=False).solve(omega_mean, ratio=RATIO)
    return steady_record(state, without, alone), curves(phi, state)


def fixture(name: str) -> dict:
    machine, class_delta, _ = parameters(name)
    model = oracle.machine_of(machine)
    phi = np.linspace(0.0, model.cycle, POINTS)
    cycle = oracle.Cycle(model, angles=phi)
    diagrams: list = []
    index: dict[int, int] = {}

    def diagram(table: oracle.Table | None, source) -> int | None:
        if table is None:
            return None
        if id(source) not in index:
            index[id(source)] = len(diagrams)
            diagrams.append(
                {
                    "kind": table.kind,
                    "x": table.poly.x.tolist(),
                    "pressure": table.pressure.tolist(),
                    "c": table.poly.c.tolist(),
                }
            )
        return index[id(source)]

    cylinders = []
    for unit, source in zip(model.units, machine.cylinders, strict=True):
        record = {key: float(getattr(unit, key)) for key in oracle.UNIT_FIELDS}
        # One table per diagram object (the cylinders sharing a diagram share its index).
        record["head"] = diagram(unit.head, source.pressure)
        record["crank_end"] = diagram(unit.crank_end, source.pressure_crank_end)
        cylinders.append(record)
    steady, steady_curves = balance_at(cycle, phi, machine.rpm)
    near = []
    for rpm in NEAR_STALL.get(name, ()):
        record, near_curves = balance_at(cycle, phi, rpm)
        near.append({"rpm": rpm, "steady_state": record, "curves": near_curves})
    stalls = []
    balance = oracle.Balance(cycle)
    for rpm in STALLS.get(name, ()):
        try:
            balance.solve(math.pi * rpm / 30, ratio=RATIO)
        except oracle.Stall as stall:
            stalls.append({"rpm": rpm, "angle": stall.angle, "min_rpm": balance.min_rpm(ratio=RATIO)})
        else:
            raise AssertionError(f"{name} runs at {rpm} rpm")
    omega_mean = math.pi * machine.rpm / 30
    without = oracle.Balance(cycle, gravity=False)
    flywheels = []
    for delta in (1 / 40, 1 / 100, class_delta):
        swing = balance.energy_swing(omega_mean)
        flywheels.append(
            {
                "delta": delta,
                "shaft_inertia": balance.flywheel(delta, omega_mean),
                "shaft_inertia_without_gravity": without.flywheel(delta, omega_mean),
                "textbook": swing / (delta * omega_mean**2) - balance.mean_engine_inertia(),
                "energy_swing": swing,
            }
        )
    return {
        "name": name,
        "strokes": round(model.cycle / math.pi),
        "g": model.g,
        "shaft_inertia": model.shaft_inertia,
        "rpm": machine.rpm,
        "cylinders": cylinders,
        "diagrams": diagrams,
        "steady_state": steady,
        "curves": steady_curves,
        "square_law": square_laws(cycle, phi, machine.rpm, steady["mean_load_torque"]),
        "near_stall": near,
        "stalls": stalls,
        "flywheels": flywheels,
        "drive": driven(model, machine.rpm, steady["mean_load_torque"]),
    }


def drive_of(cycle: float, size: float):
    """A driving torque of φ alone: M_d = T·(0.5 + 0.3 sin(2πφ/Φ) + 0.2 cos(6πφ/Φ)) with T =
    ``size`` [N·m], as the periodic cubic spline (SciPy) through 49 points over [0, Φ]: a
    ``PPoly`` the oracle integrates by its own rules and the core by its antiderivative."""
    x = np.linspace(0.0, cycle, 49)
    turn = 2 * np.pi * x / cycle
    y = size * (0.5 + 0.3 * np.sin(turn) + 0.2 * np.cos(3 * turn))
    y[-1] = y[0]
    return interpolate.CubicSpline(x, y, bc_type="periodic")


def driven(model: oracle.Machine, rpm: float, balance_load: float) -> dict:
    """The "balance" load beside :func:`drive_of` (T = the balance load without it): the
    steady state at the machine's speed (with g = 0 and gravity alone beside) and the
    flywheel for δ = 1/40."""
    drive = drive_of(model.cycle, abs(balance_load))
    cycle = oracle.Cycle(model, drive=drive)
    omega_mean = math.pi * rpm / 30
    balance = oracle.Balance(cycle)
    state = balance.solve(omega_mean, ratio=RATIO)
    without = oracle.Balance(cycle, gravity=False).solve(omega_mean, ratio=RATIO)
    alone = oracle.Balance(cycle, gas=False).solve(omega_mean, ratio=RATIO)
    delta = 1 / 40
    swing = balance.energy_swing(omega_mean)
    return {
        "x": drive.x.tolist(),
        "c": drive.c.tolist(),
        "steady_state": steady_record(state, without, alone),
        "flywheel": {
            "delta": delta,
            "shaft_inertia": balance.flywheel(delta, omega_mean),
            "textbook": swing / (delta * omega_mean**2) - balance.mean_engine_inertia(),
            "energy_swing": swing,
        },
    }


def square_laws(cycle: oracle.Cycle, phi: np.ndarray, rpm: float, balance_load: float) -> list:
    """A square-law load c·ω² with M_n = T (the "balance" load at the machine's own speed) at
    n_n = that speed: an engine (T > 0) alone and with a constant drive of T/2 beside a load
    of 1.5 T; a compressor (T < 0) with a drive of 1.5|T| beside a load of |T|/2, and of
    3|T| beside 2|T| (all run near the machine's speed)."""
    found = []
    size = abs(balance_load)
    cases = (
        ((0.0, size), (0.5 * size, 1.5 * size))
        if balance_load > 0
        else ((1.5 * size, 0.5 * size), (3 * size, 2 * size))
    )
    for drive, torque in cases:
        coefficient = torque / (math.pi * rpm / 30) ** 2
        state = oracle.SquareLaw(cycle, coefficient, drive, angles=phi).solve(RATIO)
        without = oracle.SquareLaw(cycle, coefficient, drive, gravity=False).solve(RATIO)
        alone = oracle.Balance(cycle, gas=False).solve(state.omega_mean, ratio=RATIO)
        record = steady_record(state, without, alone)
        del record["delta_midrange"]
        found.append(
            {"torque": torque, "rpm": rpm, "drive": drive, "coefficient": coefficient}
            | record
            | {"curves": curves(phi, state)}
        )
    return found


def agreement(first: list, second: list) -> dict:
    """The worst relative difference between two runs, per kind of quantity."""
    worst = dict.fromkeys(KINDS, 0.0)

    def difference(a: float, b: float) -> float:
        return abs(a - b) / abs(b) if b != 0 else abs(a)

    for a, b in zip(first, second, strict=True):
        for kind, keys in KINDS.items():
            pairs = []
            if kind in ("speeds", "deltas"):
                pairs += [(a["steady_state"], b["steady_state"])]
                pairs += [(a["drive"]["steady_state"], b["drive"]["steady_state"])]
                pairs += list(zip(a["square_law"], b["square_law"], strict=True))
            elif kind == "near_stall_speeds":
                pairs += [
                    (x["steady_state"], y["steady_state"])
                    for x, y in zip(a["near_stall"], b["near_stall"], strict=True)
                ]
            elif kind == "flywheels":
                pairs += list(zip(a["flywheels"], b["flywheels"], strict=True))
                pairs += [(a["drive"]["flywheel"], b["drive"]["flywheel"])]
            else:
                pairs += list(zip(a["stalls"], b["stalls"], strict=True))
            for x, y in pairs:
                for key in keys:
                    if key in x:
                        worst[kind] = max(worst[kind], difference(x[key], y[key]))
    return worst


def main() -> None:
    out = pathlib.Path(__file__).with_name("motion_fixtures.json")
    machines = [fixture(name) for name in MACHINES]
    oracle.GL_POINTS, points = oracle.GL_CHECK, oracle.GL_POINTS
    check = [fixture(name) for name in MACHINES]
    measured = agreement(machines, check)
    print("agreement of the oracle's two runs:", measured)
    data = {
        "multicrank": parameters(MACHINES[0])[2],
        "oracle": {
            "script": "rust/core/tests/data/oracle.py (make_motion_fixtures.py writes this file)",
            "method": (
                "planar geometry with complex-step derivatives; SciPy interpolants of the tables; "
                "Gauss-Legendre panels between table breakpoints, the time integral adaptive; "
                "brentq on the energy offset, the flywheel and the lowest running speed; "
                "bounded Brent for the extremes"
            ),
            "gauss_legendre_points": [points, oracle.GL_POINTS],
            "adaptive_rtol": oracle.ADAPTIVE_RTOL,
            "min_speed_ratio": RATIO,
            "agreement": measured,
        },
        "machines": machines,
    }
    out.write_text(json.dumps(data, separators=(",", ":")) + "\n")
    print(f"{out}: {out.stat().st_size} bytes")


if __name__ == "__main__":
    main()
