"""What a report is about (:class:`ReportSettings`), and the machine's speeds every part of it
needs: its running speed and its speed range."""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass, field
from typing import Any, ClassVar

from .._validation import refused, renamed, running_rpm, warn_renamed
from ..machine.machine import Machine
from ..presets import DEFAULT_MACHINE_NAME, MACHINES

__all__ = ["DEFAULT_THRESHOLD", "ReportSettings", "running_speed", "speed_range"]

#: δ_g below which gravity may be neglected in the speed fluctuation: a tenth of 1/300,
#: the tightest coefficient of speed fluctuation usually asked of machines (AC generators;
#: pumps and compressors allow 1/20–1/50, vehicle engines 1/100–1/200).
DEFAULT_THRESHOLD = 1.0 / 3000.0


@dataclass
class ReportSettings:
    """What the report is about: ``machine`` (it needs a running speed, ``rpm``), and
    ``machines``, the machines of the speed-range figure (by default every preset).

    ``delta`` (keyword and attribute) is the name of 0.1 for :attr:`delta_target`: it still
    works, with a DeprecationWarning, and goes in 0.3."""

    machine: Machine = field(default_factory=lambda: MACHINES[DEFAULT_MACHINE_NAME])
    k_max: int = 12
    n_max: int = 24
    points: int = 721
    threshold: float = DEFAULT_THRESHOLD
    lambdas: int = 60
    machines: dict[str, Machine] = field(default_factory=lambda: dict(MACHINES))
    #: The δ to size the flywheel for, a target (default: the machine's ``delta_target``, else
    #: a built-in machine's class limit, else the machine's own δ without gravity).
    delta_target: float | None = None
    #: Points per axis of the "where gravity matters" map (speed × shaft inertia): the map
    #: solves this many squared steady states, a few ms each.
    gravity_map_points: int = 15

    #: The name of 0.1 for :attr:`delta_target`.
    delta: ClassVar[renamed] = renamed("delta_target")

    def __setstate__(self, state: dict[str, Any]) -> None:
        # A pickle of 0.1 holds the target as ``delta``.
        if "delta" in state:
            state = dict(state)
            state["delta_target"] = state.pop("delta")
        self.__dict__.update(state)


_FIELDS_INIT = ReportSettings.__init__
_UNSET: Any = object()


@functools.wraps(_FIELDS_INIT)
def _init(self: ReportSettings, *args: Any, delta: Any = _UNSET, **kwargs: Any) -> None:
    """The dataclass's ``__init__``, which also takes ``delta=``, the name of 0.1 for
    ``delta_target=``, with a DeprecationWarning."""
    if delta is not _UNSET:
        position = [f.name for f in dataclasses.fields(ReportSettings)].index("delta_target")
        given = kwargs.get("delta_target", args[position] if len(args) > position else None)
        if delta is not None and given is not None:
            raise refused("delta_target", "give delta_target or delta (its name of 0.1), not both")
        warn_renamed("ReportSettings(delta=)", "delta_target=")
        if delta is not None:
            kwargs["delta_target"] = delta
    _FIELDS_INIT(self, *args, **kwargs)


ReportSettings.__init__ = _init  # type: ignore[method-assign]


def running_speed(machine: Machine) -> float:
    """The machine's running speed [rpm], at which the report judges gravity (refused by name
    where it has none: :func:`~multicrank._validation.running_rpm`)."""
    return running_rpm(machine, None)


def speed_range(machine: Machine) -> tuple[float, float]:
    """The machine's speed range [rpm]; its running speed ±50 % where it gives none."""
    if machine.rpm_range is not None:
        return machine.rpm_range
    rpm = running_speed(machine)
    return 0.5 * rpm, 1.5 * rpm
