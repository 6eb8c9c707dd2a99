"""Motion at sweep scale: the steady state (and the flywheel) of many variants of one machine,
one row each (:func:`motion_sweep`).

Designs are rows of :mod:`~multicrank.motion.variants`' columns — a :class:`MachineGrid`, a
pandas DataFrame or a dask DataFrame — processed chunk by chunk as :func:`~multicrank.sweep`
does (in memory, streamed to resumable Parquet parts, or one chunk per dask partition). This
module checks the sweep asked for (its outputs, load, designs and options, before any work)
and runs its chunks; `_sweep_rows` solves each chunk, by the Rust core's batched solver where
it solves the machine, else by a loop over :func:`~multicrank.steady_state` and
:func:`~multicrank.flywheel_inertia`; the rows are the same either way.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import uuid
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .._validation import as_count, as_flag, as_instance, one_of, refused, warn_renamed
from ..machine.machine import Machine
from ..sweeps.chunks import in_memory, is_dask, to_parquet
from ..sweeps.designs import (
    as_frame,
    as_passthrough,
    check_columns,
    design_rows,
    grid_axes_of,
)
from ..sweeps.outputs import as_outputs
from ..sweeps.store import as_out, designs_digest, fingerprint
from ._periodic import resolve_rules
from ._sweep_rows import _FLYWHEEL, _STEADY, MOTION_SWEEP_OUTPUTS, _solve_chunk, _solve_partition
from .flywheel import _as_delta
from .loads import BALANCE
from .variants import MachineGrid, check_values, machine_columns, row_variant

__all__ = ["MOTION_SWEEP_OUTPUTS", "MachineGrid", "motion_sweep"]

#: Outputs of 0.1 under their new names: the old name is still accepted, with a
#: DeprecationWarning, and gives the column under its new name.
RENAMED_OUTPUTS = {"delta_gravity_only": "delta_coasting"}
# Designs per chunk: about a second of work — Ctrl-C keeps all but that, and a part of Parquet
# is not too small to be worth a file. The core solves a design in ~0.05–0.2 ms; the Python
# loop (callable pressures, other loads) in a few ms.
DEFAULT_CHUNK_SIZE = 8192
DEFAULT_PYTHON_CHUNK_SIZE = 256


# ----------------------------------------------------------------------------- options
def _as_outputs(outputs: Any, delta: float | None) -> tuple[str, ...]:
    """The outputs asked for, in column order; default the steady state's, and the flywheel's
    with ``delta_target=``. ``stalled`` comes with any output of the steady state, ``near_stall``
    with ``delta`` (and ``delta`` with ``near_stall``); a name of 0.1 gives its new one."""
    if outputs is None:
        asked: tuple[str, ...] = _STEADY + (_FLYWHEEL if delta is not None else ())
    else:
        if isinstance(outputs, str):
            outputs = (outputs,)
        if isinstance(outputs, Iterable) and not isinstance(outputs, bytes | Mapping):
            outputs = list(outputs)
            for i, name in enumerate(outputs):
                if isinstance(name, str) and name in RENAMED_OUTPUTS:
                    outputs[i] = RENAMED_OUTPUTS[name]
                    warn_renamed(f"the output {name!r}", repr(outputs[i]), stacklevel=4)
        asked = as_outputs(outputs, MOTION_SWEEP_OUTPUTS)
    flywheel = [o for o in asked if o in _FLYWHEEL]
    if flywheel and delta is None:
        raise refused(
            "outputs", f"outputs {flywheel!r} need delta_target=, the coefficient of speed fluctuation to size for"
        )
    if delta is not None and not flywheel:
        raise refused(
            "delta_target",
            "delta_target= is given but outputs name no flywheel_inertia: ask for it, or leave delta_target out",
        )
    if any(o in _STEADY for o in asked):
        asked = (*asked, "stalled")
    if "delta" in asked or "near_stall" in asked:
        asked = (*asked, "delta", "near_stall")
    return tuple(o for o in MOTION_SWEEP_OUTPUTS if o in asked)


def _digest(value: Any, what: str, resume: bool) -> str:
    """A SHA-256 of a pickle of ``value`` (a machine, a load), for a sweep's fingerprint; for
    one that cannot be pickled, a random one (its sweep is never resumed) unless ``resume``."""
    try:
        return hashlib.sha256(pickle.dumps(value, protocol=4)).hexdigest()
    except Exception as error:  # a lambda pressure or load: no fingerprint, so no resume
        if not resume:
            return f"unpicklable-{uuid.uuid4().hex}"
        raise refused(
            what,
            f"{what} cannot be pickled ({error}), so a resume could not tell its sweep from another: give "
            f"{what} as picklable objects (IndicatorDiagram, PowerLawLoad, module-level functions), or sweep "
            "without resume=True",
        ) from None


# ----------------------------------------------------------------------------- the sweep
def _as_target(delta_target: Any, delta: Any) -> tuple[str, float | None]:
    """(the name given, the δ to size the flywheel for) from ``delta_target`` or its deprecated
    name ``delta`` (at most one); None: no flywheel."""
    if delta_target is None and delta is None:
        return "delta_target", None
    name, value = one_of(("delta_target", delta_target), ("delta", delta))
    return name, _as_delta(value, name)


def _check_speed(names: Iterable[str], machine: Machine, route: str) -> None:
    """The speed of every design: an ``rpm`` column or the machine's own, with "balance";
    none with a load that fixes the speed."""
    names = list(names)
    if route == BALANCE and "rpm" not in names and machine.rpm is None:
        raise refused(
            "rpm",
            f"rpm is required with load='balance': give the designs an rpm column [1/min], or the machine "
            f"{machine.name!r} an rpm of its own",
        )
    if route != BALANCE and "rpm" in names:
        raise refused(
            "rpm", f"the designs' rpm column is not allowed with this load: a {route} load fixes the mean speed itself"
        )


def _check_table(machine: Machine, frame: pd.DataFrame) -> None:
    """Every value of a table of designs a finite number (rpm a speed), and the machines of
    its first and last rows built (a row the machine refuses later stops the sweep, named)."""
    known = machine_columns(machine)
    names = [c for c in frame.columns if c in known]
    for name in names:
        check_values(name, frame[name].to_numpy(), rows=frame.index)
    for position in {0, len(frame) - 1} if len(frame) else ():
        row = frame.iloc[position]
        row_variant(machine, {name: row[name] for name in names}, frame.index[position])


def _check_names(machine: Machine, names: Any, passthrough: tuple[str, ...], outputs: tuple[str, ...]) -> None:
    """The columns of a motion sweep's designs: machine columns, and those passed through."""
    check_columns(names, passthrough, outputs, known=machine_columns(machine), required=(), what="machine")


def _meta(designs: Any, outputs: tuple[str, ...]) -> pd.DataFrame:
    meta = designs._meta.copy()
    for name in outputs:
        meta[name] = np.zeros(0, dtype=bool if name in ("stalled", "near_stall") else np.float64)
    return meta


def motion_sweep(
    machine: Machine,
    designs: Any,
    *,
    outputs: Any = None,
    load: Any = BALANCE,
    delta_target: Any = None,
    out: str | os.PathLike | None = None,
    resume: bool = False,
    chunk_size: int | None = None,
    progress: bool = False,
    passthrough: Any = (),
    delta: Any = None,
) -> Any:
    """The steady running of many variants of one machine: δ with and without gravity, the
    speed extremes and (with ``delta_target=``) the flywheel, one row per design.

    Every row is what :func:`steady_state` (with gravity) and :func:`flywheel_inertia` give
    for that design's machine (:class:`MachineGrid` says how a design changes the machine):
    under the machine's ``load_law`` their outputs run, with "balance", the law's gauge
    pressures at each design's speed (times its ``pressure_scale``), and so do the frame's
    outputs (the bearing loads' gas forces).

    Parameters
    ----------
    machine : Machine
        The base machine.
    designs : MachineGrid, DataFrame or dask DataFrame
        The designs: a :class:`MachineGrid` (of ``machine``: its own base machine is used), or
        a table whose columns name what changes: ``shaft_inertia`` [kg·m²], ``rpm`` [1/min],
        ``g`` [m/s²], ``pressure_scale`` [dimensionless] and any :class:`Cylinder` field set on
        every cylinder (``crank_radius``, ``rod_length``, ``piston_mass``, ``rod_mass``,
        ``rod_cg``, ``rod_inertia``, ``crank_mass``, ``crank_cg_radius``,
        ``counterweight_mass``, ``counterweight_radius``, ``bore``; SI units), and a field of
        cylinder j alone (from 0), set after those: ``"phase[j]"`` α_j [rad] (a firing
        order), ``"counterweight_mass[j]"`` [kg], ``"counterweight_radius[j]"`` [m]. Any other
        column is refused unless named in ``passthrough``.
    outputs : str or sequence of str, optional
        Names from :data:`MOTION_SWEEP_OUTPUTS`: ``delta``, ``delta_without_gravity``,
        ``delta_coasting`` (δ of the steady state, of the machine with g = 0, and of the
        machine coasting with gas and load removed — J(φ)'s variation and gravity together:
        :class:`SteadyState`), ``gravity_effect`` = δ/δ_without_gravity − 1 (the relative
        change gravity makes, :attr:`SteadyState.gravity_effect`), ``rpm_min``, ``rpm_max``
        [1/min] (the speed extremes), ``stalled`` (added with any of these), ``near_stall``
        (δ > :data:`~multicrank.NEAR_STALL_DELTA` = 0.5, a machine that nearly stops each
        cycle; added with ``delta``, and adds it), ``flywheel_inertia`` and
        ``flywheel_inertia_without_gravity`` [kg·m²] (:class:`FlywheelInertia`'s
        ``shaft_inertia`` and ``shaft_inertia_without_gravity``; need ``delta_target``);
        the frame's, at each design's speed (its ``rpm``, else the machine's) held constant,
        whatever the load: ``free_force_1``, ``free_force_2`` [N] and ``free_moment_1``,
        ``free_moment_2`` [N·m] (the largest magnitude over a cycle of the first- and
        second-order shaking force and moment, the moment about the engine centre: forward +
        backward of :func:`~multicrank.shaking_forces`) and ``max_bearing_load`` [N] (the largest load on
        any main bearing over the working cycle, :func:`~multicrank.bearing_loads` at 720
        angles). Default: all of the steady state's, and the flywheel's with ``delta_target``
        (the frame's only when named). Only what is asked is
        computed. The name of 0.1 ``delta_gravity_only`` is still accepted, with a
        DeprecationWarning, and gives the column ``delta_coasting``.
    load : "balance", PowerLawLoad or callable, default "balance"
        The load, as for :func:`steady_state`; checked once, before any work. With
        "balance" each design runs at its ``rpm`` (default the machine's own ``rpm``; a
        sweep with neither is refused); other loads fix the speed, and an ``rpm`` column is
        refused.
    delta_target : float, optional
        δ_target, the coefficient of speed fluctuation to size the flywheel for
        [dimensionless], ≥ 1e-9 (as :attr:`Machine.delta_target`; the ``delta`` column is
        the δ each design runs at).
    out : str or os.PathLike, optional
        Stream the result to this Parquet file, chunk by chunk, as :func:`sweep` does
        (atomic, checksummed parts in ``<out>.parts/``); returns the path.
    resume : bool, default False
        With ``out``: continue an interrupted sweep from its finished chunks. The machine,
        the designs, the outputs, the load, ``delta_target`` and ``chunk_size`` must be the
        interrupted sweep's, or the resume is refused.
    chunk_size : int, optional
        Designs per chunk (and per Parquet row group), default 8192 where the Rust core solves
        the machine and 256 where Python does (a callable pressure, a load other than
        "balance"): about a second of work each. Results do not depend on it.
    progress : bool, default False
        Show a progress bar (designs/s, ETA).
    passthrough : str or sequence of str, default ()
        Columns of a table that are carried through unchanged (labels, ids, …).
    delta : float, optional
        Deprecated since 0.2 (goes in 0.3): ``delta_target``, under the name of the result
        column δ.

    Returns
    -------
    pandas.DataFrame or pathlib.Path or dask.dataframe.DataFrame
        The designs and one column per output, same rows and order (a grid's result
        remembers its axes for :func:`to_xarray`); the Parquet file's path with ``out``; a
        lazy dask DataFrame for dask input (one chunk per partition).

    Raises
    ------
    MechanismError
        For an unknown or misspelt column or output, a bad value, a load or option that is
        refused — before any work; for a design whose machine cannot be built, naming it.
        A design that stalls is never an error: it is a row with ``stalled`` True and NaN δ.

    Examples
    --------
    The slow compressor with three flywheels at three speeds:

    >>> import multicrank as mc
    >>> compressor = mc.presets.MACHINES["slow-compressor"]
    >>> grid = mc.MachineGrid(compressor, shaft_inertia=[250.0, 350.0, 450.0], rpm=[90.0, 120.0, 150.0])
    >>> result = mc.motion_sweep(compressor, grid, outputs=["delta", "gravity_effect"])
    >>> result.round(4)
       shaft_inertia    rpm   delta  gravity_effect  stalled  near_stall
    0          250.0   90.0  0.0762          0.1706    False       False
    1          250.0  120.0  0.0413          0.1814    False       False
    2          250.0  150.0  0.0252          0.2004    False       False
    3          350.0   90.0  0.0545          0.1690    False       False
    4          350.0  120.0  0.0295          0.1804    False       False
    5          350.0  150.0  0.0181          0.1996    False       False
    6          450.0   90.0  0.0425          0.1681    False       False
    7          450.0  120.0  0.0230          0.1798    False       False
    8          450.0  150.0  0.0141          0.1992    False       False
    >>> dict(mc.to_xarray(result)["delta"].sizes)
    {'shaft_inertia': 3, 'rpm': 3}
    """
    machine = as_instance(machine, Machine, "machine")
    given, target = _as_target(delta_target, delta)
    outputs = _as_outputs(outputs, target)
    if given == "delta":
        warn_renamed("motion_sweep(delta=)", "delta_target=")
    rules = resolve_rules(load, None)  # the load, checked once
    if chunk_size is None:
        native = isinstance(load, str) and load == BALANCE
        size = DEFAULT_CHUNK_SIZE if native else DEFAULT_PYTHON_CHUNK_SIZE
    else:
        size = as_count(chunk_size, "chunk_size", minimum=1)
    resume = as_flag(resume, "resume")
    progress = as_flag(progress, "progress")
    passthrough = as_passthrough(passthrough)
    path = None if out is None else as_out(out)
    if resume and path is None:
        raise refused("resume", "resume=True needs out= (the Parquet file of the interrupted sweep)")

    if isinstance(designs, MachineGrid):
        if designs.machine != machine:
            raise refused(
                "designs",
                "designs is a MachineGrid of another machine than machine: make the grid of the machine you sweep",
            )
        _check_names(machine, [*designs.axes, *designs.constants], passthrough, outputs)
        names: list[str] = [*designs.axes, *designs.constants]
    elif is_dask(designs):
        if path is not None:
            raise refused("out", "out= is not available for dask input: write with dask's to_parquet")
        _check_names(machine, list(designs.columns), passthrough, outputs)
        _check_speed(designs.columns, machine, rules.route)
        return designs.map_partitions(_solve_partition, machine, outputs, load, target, meta=_meta(designs, outputs))
    else:
        if not isinstance(designs, pd.DataFrame):
            raise refused(
                "designs",
                f"designs must be a MachineGrid, a pandas DataFrame or a dask DataFrame, got {type(designs).__name__}",
            )
        designs = as_frame(designs)
        _check_names(machine, designs.columns, passthrough, outputs)
        names = list(designs.columns)
    _check_speed(names, machine, rules.route)
    if not isinstance(designs, MachineGrid):
        _check_table(machine, designs)

    total, rows = design_rows(designs)

    def compute(start: int, stop: int) -> pd.DataFrame:
        return _solve_chunk(machine, rows(start, stop), outputs, load, target)

    if path is not None:
        settings = {
            "sweep": "motion",
            "machine_sha256": _digest(machine, "machine", resume),
            "load_sha256": _digest(load, "load", resume),
            "delta": target,
        }
        manifest = fingerprint(total, None, outputs, size, designs_digest(designs), settings=settings)
        return Path(to_parquet(path, manifest, total, size, compute, resume, progress, desc="motion sweep"))
    result = in_memory(total, size, compute, progress, desc="motion sweep")
    grid_axes = grid_axes_of(designs)
    if grid_axes:
        result.attrs["grid_axes"] = grid_axes
    result.attrs["sweep_outputs"] = list(outputs)
    return result
