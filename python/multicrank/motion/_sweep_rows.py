"""The rows of a motion sweep (:func:`~multicrank.motion_sweep`): what each output is and
how one chunk of designs is solved, by one function, :func:`_solve_chunk` — the work of every
chunk and of every dask partition. By the Rust core's batched solver
(:meth:`multicrank._native.NativeMachine.sweep`, designs in parallel, the GIL released) where
the machine's pressures are tables and the load is "balance", else by a loop over
:func:`~multicrank.steady_state` and :func:`~multicrank.flywheel_inertia`; the frame's outputs
by the core's frame sweep at each design's speed. The rows are the same either way.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pandas as pd

from .._native import FRAME_OUTPUTS as _CORE_FRAME_OUTPUTS
from .._native import MOTION_SWEEP_OUTPUTS as _CORE_OUTPUTS
from .._native import MechanismError
from .._validation import contiguous, omega_from_rpm, refused, reworded, rpm_from_omega
from ..machine.machine import Machine, load_factor, rated_omega
from ..machine.native import motion_machine
from .flywheel import flywheel_inertia
from .loads import BALANCE
from .steady import NEAR_STALL_DELTA, StallError, steady_state
from .variants import machine_columns, row_variant

__all__ = ["MOTION_SWEEP_OUTPUTS"]

# The native extension's names of our outputs, where they differ (it gives the speed
# extremes in rad/s).
_SPEED_OUTPUTS = {"rpm_min": "omega_min", "rpm_max": "omega_max"}
_FROM_NATIVE = {native: name for name, native in _SPEED_OUTPUTS.items()}
# The flywheel's outputs (which need delta=), and the steady state's: the core's, and
# near_stall (δ > NEAR_STALL_DELTA, from δ) after stalled.
_FLYWHEEL = ("flywheel_inertia", "flywheel_inertia_without_gravity")
_STEADY = (*(_FROM_NATIVE.get(o, o) for o in _CORE_OUTPUTS if o not in _FLYWHEEL), "near_stall")
# The frame's outputs (at each design's speed held constant; any load): the first- and
# second-order free force and moment, the largest main-bearing load.
_FRAME = tuple(_CORE_FRAME_OUTPUTS)
#: Every output a motion sweep can compute, in column order.
MOTION_SWEEP_OUTPUTS: tuple[str, ...] = (*_STEADY, *_FLYWHEEL, *_FRAME)


def _near_stall(result: pd.DataFrame, outputs: tuple[str, ...]) -> pd.DataFrame:
    """``result`` with its ``near_stall`` column (δ > NEAR_STALL_DELTA; False where stalled)."""
    if "near_stall" in outputs:
        result["near_stall"] = (result["delta"] > NEAR_STALL_DELTA).to_numpy(dtype=bool)
    return result


def _solve_chunk(
    machine: Machine, frame: pd.DataFrame, outputs: tuple[str, ...], load: Any, delta: float | None
) -> pd.DataFrame:
    """The designs of ``frame`` with one column per output: the work of every chunk and of
    every dask partition, and the one place where a design is solved.

    By the Rust core's batched steady state where it solves the machine (tables for
    pressures, the "balance" load): every row equal to :func:`steady_state` and
    :func:`flywheel_inertia` of its machine, which take the same core path, to 1e-12 (bit for
    bit unless the core gave the design another design's gas scaled, for its pressure_scale
    or bore, or that design's U reweighted, for its crank webs and counterweights). Else a loop over
    rows: each row's machine (:func:`~multicrank.motion.variants.machine_variant`) solved by
    :func:`steady_state` (with gravity) and, where the flywheel is asked for,
    :func:`flywheel_inertia`.

    A design that stalls (a :class:`StallError`, or a δ that is not finite) is a row with
    ``stalled`` True and NaN in the δ and speed columns; a flywheel that no shaft inertia
    gives (the target unreachable) is NaN. A design the machine refuses (a rod shorter than
    its crank) raises :class:`MechanismError` naming the row.
    """
    framed = [o for o in outputs if o in _FRAME]
    if framed:
        rest = tuple(o for o in outputs if o not in _FRAME)
        result = _solve_chunk(machine, frame, rest, load, delta) if rest else frame.copy()
        for name, column in _frame_columns(machine, frame, framed).items():
            result[name] = column
        return result
    if isinstance(load, str) and load == BALANCE:
        native = motion_machine(machine)
        known = machine_columns(machine)
        names = [c for c in frame.columns if c in known]
        # The core's speeds are ω [rad/s]: the rpm column [1/min] (checked by check_values) and
        # the machine's rpm converted here, once; the speed extremes back to 1/min below.
        designs = {name: contiguous(frame[name].to_numpy(dtype=np.float64)) for name in names}
        _at_speed(machine, designs)
        computed = [o for o in outputs if o != "near_stall"]
        omega = None if machine.rpm is None else omega_from_rpm(machine.rpm)
        try:
            found = native.sweep(designs, [_SPEED_OUTPUTS.get(o, o) for o in computed], omega=omega, target_delta=delta)
        except MechanismError as error:
            raise _refused_design(machine, frame, names, error) from None
        result = frame.copy()
        for name in outputs:  # near_stall in its place, from delta by _near_stall
            if name in _SPEED_OUTPUTS:
                # The row's rpm is the one asked, and ω and back is not always it to the last
                # ulp: the extremes stay on either side of it in 1/min as the core keeps them
                # about ω_m in rad/s.
                speed = rpm_from_omega(found[_SPEED_OUTPUTS[name]])
                asked = frame["rpm"].to_numpy(dtype=float) if "rpm" in frame else np.full(len(frame), machine.rpm)
                result[name] = np.minimum(speed, asked) if name == "rpm_min" else np.maximum(speed, asked)
            else:
                result[name] = False if name == "near_stall" else found[name]
        return _near_stall(result, outputs)
    return _near_stall(_solve_rows(machine, frame, outputs, load, delta), outputs)


def _at_speed(machine: Machine, designs: dict[str, np.ndarray]) -> None:
    """The designs' speeds as the core takes them, in place: the rpm column [1/min] (checked
    by check_values) converted to ω [rad/s] once; under the machine's load law its diagrams
    at each design's speed, as steady_state and bearing_loads run them (a pressure_scale)."""
    if "rpm" not in designs:
        return  # the machine's own speed: its rated one, the diagrams as given
    designs["omega"] = contiguous(omega_from_rpm(designs.pop("rpm")))
    if machine.load_law is not None:
        factor = load_factor(designs["omega"], rated_omega(machine))
        designs["pressure_scale"] = contiguous(designs.get("pressure_scale", 1.0) * factor)


def _frame_columns(machine: Machine, frame: pd.DataFrame, outputs: list[str]) -> dict[str, np.ndarray]:
    """The frame's outputs of the designs of ``frame`` by the Rust core, each at the design's
    speed (its ``rpm`` column, else the machine's ``rpm``) held constant, whatever the load."""
    known = machine_columns(machine)
    names = [c for c in frame.columns if c in known]
    if "rpm" not in names and machine.rpm is None:
        raise refused(
            "outputs",
            f"outputs {outputs!r} are taken at each design's speed: give an rpm column, or a machine with rpm",
        )
    designs = {name: contiguous(frame[name].to_numpy(dtype=np.float64)) for name in names}
    _at_speed(machine, designs)
    omega = None if machine.rpm is None else omega_from_rpm(machine.rpm)
    try:
        return motion_machine(machine).frame_sweep(designs, outputs, omega)
    except MechanismError as error:
        raise _refused_design(machine, frame, names, error) from None


def _refused_design(machine: Machine, frame: pd.DataFrame, names: list[str], error: MechanismError) -> MechanismError:
    """The core's refusal of a design (its index in the chunk as the error's ``row``) worded
    as the row loop words it: the design's label and values, and what its machine refuses
    (:func:`~multicrank.motion.variants.row_variant`, which builds that one machine and solves
    nothing). An error of no row is the core's own."""
    row = getattr(error, "row", None)
    if row is None:
        return error
    label = frame.index[row]
    design = {name: frame[name].iloc[row] for name in names}
    try:
        row_variant(machine, design, label)
    except MechanismError as own:
        return own
    values = ", ".join(f"{k} = {v:g}" for k, v in design.items())
    return reworded(error, f"design {label} ({values}): {getattr(error, 'reason', error)}")


def _solve_rows(
    machine: Machine, frame: pd.DataFrame, outputs: tuple[str, ...], load: Any, delta: float | None
) -> pd.DataFrame:
    """:func:`_solve_chunk` by the Python implementation, row by row."""
    rows = len(frame)
    columns = {name: np.full(rows, math.nan) for name in outputs if name not in ("stalled", "near_stall")}
    stalled = np.zeros(rows, dtype=bool)
    known = machine_columns(machine)
    names = [c for c in frame.columns if c in known]
    steady = any(o in _STEADY for o in outputs)
    flywheel = any(o in _FLYWHEEL for o in outputs)
    for i, (label, values) in enumerate(zip(frame.index, frame[names].itertuples(index=False, name=None), strict=True)):
        design = dict(zip(names, values, strict=True))
        variant = row_variant(machine, design, label)
        rpm = design.get("rpm")
        if steady:
            try:
                state = steady_state(variant, rpm=rpm, load=load)
            except StallError:
                stalled[i] = True
            else:
                if not math.isfinite(state.delta):
                    stalled[i] = True
                else:
                    found = {
                        "delta": state.delta,
                        "delta_without_gravity": state.delta_without_gravity,
                        "delta_coasting": state.delta_coasting,
                        "gravity_effect": state.gravity_effect,
                        # The row's mean speed is the rpm asked for (the solution's meets it to
                        # rounding): the extremes keep it between them to the last ulp.
                        "rpm_min": min(rpm_from_omega(state.omega_min), state.rpm if rpm is None else rpm),
                        "rpm_max": max(rpm_from_omega(state.omega_max), state.rpm if rpm is None else rpm),
                    }
                    for name, value in found.items():
                        if name in columns:
                            columns[name][i] = value
        if flywheel:
            assert delta is not None
            try:
                sized = flywheel_inertia(variant, delta=delta, rpm=rpm, load=load)
            except MechanismError:  # the target is unreachable (a StallError is one too)
                continue
            for name, value in (
                ("flywheel_inertia", sized.shaft_inertia),
                ("flywheel_inertia_without_gravity", sized.shaft_inertia_without_gravity),
            ):
                if name in columns:
                    columns[name][i] = value
    result = frame.copy()
    for name in outputs:  # near_stall in its place, from delta by _near_stall
        result[name] = stalled if name == "stalled" else False if name == "near_stall" else columns[name]
    return result


def _solve_partition(
    frame: pd.DataFrame, machine: Machine, outputs: tuple[str, ...], load: Any, delta: float | None
) -> pd.DataFrame:
    """:func:`_solve_chunk` of a dask partition (which dask passes first)."""
    return _solve_chunk(machine, frame, outputs, load, delta)
