"""What a report is about (:class:`ReportSettings`), and the machine's speeds every part of it
needs: its running speed and its speed range."""

from __future__ import annotations

from dataclasses import dataclass, field

from .._native import MechanismError
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
    ``machines``, the machines of the speed-range figure (by default every preset)."""

    machine: Machine = field(default_factory=lambda: MACHINES[DEFAULT_MACHINE_NAME])
    k_max: int = 12
    n_max: int = 24
    points: int = 721
    threshold: float = DEFAULT_THRESHOLD
    lambdas: int = 60
    machines: dict[str, Machine] = field(default_factory=lambda: dict(MACHINES))
    #: The δ to size the flywheel for (default: the machine's ``delta_target``, else a built-in
    #: machine's class limit, else the machine's own δ without gravity).
    delta: float | None = None
    #: Points per axis of the "where gravity matters" map (speed × shaft inertia): the map
    #: solves this many squared steady states, a few ms each.
    gravity_map_points: int = 15


def running_speed(machine: Machine) -> float:
    """The machine's running speed [rpm], which the report's gravity analysis needs."""
    if machine.rpm is None:
        raise MechanismError(
            f"machine {machine.name!r} has no running speed: the report judges gravity at the machine's rpm; "
            "give rpm (in a machine file: rpm = ...)"
        )
    return machine.rpm


def speed_range(machine: Machine) -> tuple[float, float]:
    """The machine's speed range [rpm]; its running speed ±50 % where it gives none."""
    if machine.rpm_range is not None:
        return machine.rpm_range
    rpm = running_speed(machine)
    return 0.5 * rpm, 1.5 * rpm
