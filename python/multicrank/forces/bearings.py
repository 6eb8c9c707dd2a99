"""The loads on a machine's main bearings (docs/theory.md, "Main-bearing loads").

Each unit's piston and rod are rigid bodies (the rod with its real mass, centre of gravity
and moment of inertia ``rod_inertia`` — unlike the free forces, the bearing loads depend on
it), the gas force is carried through the rod to the crank pin, the crank web and
counterweight turn with their throw, and every part has its weight. The shaft is taken as
statically determinate, cut at every main bearing: each throw's load is shared by the two
bearings on either side of it by the lever rule. The Rust core computes it all; here the
arguments are checked and the result is laid out.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validation import (
    as_flag,
    as_instance,
    as_real_array,
    check_size,
    contiguous,
    refused,
    rpm_from_omega,
    running_omega,
)
from ..machine.machine import Machine, load_factor, rated_omega
from ..machine.native import motion_machine

if TYPE_CHECKING:
    from ..motion.steady_result import SteadyState
    from .shaking import ShakingForces

__all__ = ["BearingLoads", "bearing_loads"]

#: Angles per working cycle when none are given at a constant speed (every half degree of a
#: two-stroke cycle), and of the steady state's grid (``steady=True``).
DEFAULT_POINTS = 720


@dataclass(frozen=True, eq=False)
class BearingLoads:
    """The forces a machine's main bearings receive from its shaft.

    Attributes
    ----------
    machine : Machine
        The machine.
    rpm : float
        The speed n [1/min]: constant, or the steady state's mean (``steady``).
    omega : float
        ω = πn/30 [rad/s].
    steady : bool
        Whether the loads are those of the steady state's ω(φ) and ε(φ).
    gravity : bool
        Whether the weights (and, in steady running, gravity's part of the speed fluctuation)
        are included.
    phi : ndarray
        The crank angles φ [rad], shape (angles,).
    positions : ndarray
        The bearings' axial positions z [m] (``Machine.bearings``), shape (bearings,).
    vertical, horizontal : ndarray
        The force each bearing receives from the shaft [N], vertical (positive upward) and
        horizontal (positive toward a cylinder at γ = 0), shape (bearings, angles).
    """

    machine: Machine
    rpm: float
    omega: float
    steady: bool
    gravity: bool
    phi: np.ndarray
    positions: np.ndarray
    vertical: np.ndarray
    horizontal: np.ndarray
    #: The loads of the same machine with g = 0 (horizontal, vertical), made when first read.
    _without_gravity: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list, repr=False)

    def without_gravity(self) -> tuple[np.ndarray, np.ndarray]:
        """The loads of the same machine at the same angles with g = 0.

        No weights and, in steady running, no gravity in the speed fluctuation: computed on
        first use (the summary's "what gravity adds") and kept.

        Returns
        -------
        tuple of ndarray
            (horizontal, vertical) [N], each of shape (bearings, angles).
        """
        if not self._without_gravity:
            if self.gravity:
                # the default angles (and any equal to them) by the same path as the loads
                phi = None if self.steady or _are_default(self.phi, self.machine) else self.phi
                _, horizontal, vertical = _loads(self.machine, self.omega, self.steady, phi, False)
            else:
                horizontal, vertical = self.horizontal, self.vertical
            self._without_gravity.append((horizontal, vertical))
        return self._without_gravity[0]

    @property
    def magnitude(self) -> np.ndarray:
        """The magnitude √(F_h² + F_v²) [N] of each bearing's load at each angle, shape
        (bearings, angles)."""
        return np.hypot(self.horizontal, self.vertical)

    @property
    def summary(self) -> Any:
        """Per bearing: its ``position`` [m], the largest load ``max`` [N] and the angle
        ``phi_max`` [rad] where it acts, the ``mean`` of the load's magnitude over the angles
        [N], ``max_without_gravity`` [N] (the same machine with g = 0: no weights and, in
        steady running, no gravity in the speed fluctuation) and ``gravity_adds`` [N], the
        largest magnitude over the angles of what gravity adds to the load vector. A pandas
        DataFrame indexed by ``bearing`` (0 … from the front, z increasing)."""
        import pandas as pd

        magnitude = self.magnitude
        at = np.argmax(magnitude, axis=1)
        horizontal, vertical = self.without_gravity()
        added = np.hypot(self.horizontal - horizontal, self.vertical - vertical)
        frame = pd.DataFrame(
            {
                "position": self.positions,
                "max": magnitude.max(axis=1),
                "phi_max": self.phi[at],
                "mean": magnitude.mean(axis=1),
                "max_without_gravity": np.hypot(horizontal, vertical).max(axis=1),
                "gravity_adds": added.max(axis=1),
            },
            index=pd.Index(np.arange(len(self.positions)), name="bearing"),
        )
        frame.attrs.update(
            {
                "rpm": self.rpm,
                "steady": self.steady,
                "gravity": self.gravity,
                "units": {
                    "position": "m",
                    "max": "N",
                    "phi_max": "rad",
                    "mean": "N",
                    "max_without_gravity": "N",
                    "gravity_adds": "N",
                },
            }
        )
        return frame

    def polar(self, bearing: int = 0, ax: Any = None) -> Any:
        """The polar diagram of one bearing's load.

        The tip of the load vector over the cycle, horizontal against vertical [N], the shaft
        centre at the origin, the largest load marked (its value and angle φ).

        Parameters
        ----------
        bearing : int, default 0
            Which bearing, from the front (0 … bearings − 1).
        ax : matplotlib Axes, optional
            Where to draw; default a new figure's.

        Returns
        -------
        matplotlib.axes.Axes
            The axes drawn on.
        """
        import matplotlib.pyplot as plt

        count = len(self.positions)
        if isinstance(bearing, bool | np.bool_) or not isinstance(bearing, int | np.integer):
            # True is an int to Python, not a bearing's number.
            raise refused("bearing", f"bearing must be an integer 0 <= bearing < {count}, got {bearing!r}")
        if not 0 <= bearing < count:
            raise refused("bearing", f"bearing = {bearing!r} is out of range; allowed: 0 <= bearing < {count}")
        if ax is None:
            _, ax = plt.subplots(figsize=(4.5, 4.5), layout="constrained")
        h, v = self.horizontal[bearing], self.vertical[bearing]
        magnitude = np.hypot(h, v)
        largest = int(np.argmax(magnitude))
        reach = 1.15 * float(magnitude[largest]) or 1.0
        ax.plot(h, v, lw=1.2, color="C0")
        ax.plot([0, h[largest]], [0, v[largest]], color="C3", lw=1)
        ax.annotate(
            f"max {magnitude[largest]:.4g} N at φ = {np.degrees(self.phi[largest]):.0f}°",
            (h[largest], v[largest]),
            xytext=(0.03, 0.03),
            textcoords="axes fraction",
            fontsize="small",
            color="C3",
        )
        ax.plot([0], [0], marker="+", color="k")
        ax.set(
            aspect="equal",
            xlim=(-reach, reach),
            ylim=(-reach, reach),
            xlabel="horizontal [N]",
            ylabel="vertical [N]",
            title=f"bearing {bearing} (z = {self.positions[bearing]:.3g} m), {self.rpm:.4g} rpm",
        )
        ax.grid(alpha=0.3)
        return ax


def bearing_loads(
    machine: Machine, rpm: Any = None, *, phi: Any = None, steady: Any = False, gravity: Any = True
) -> BearingLoads:
    """The force each main bearing receives from the shaft, over the crank angle.

    Parameters
    ----------
    machine : Machine
        The machine: its cylinders (masses, geometry, ``rod_inertia``, gas pressures, phases,
        inclinations and ``axial_position``) and its main bearings (``Machine.bearings``:
        ``main_bearings``, or n + 1 interleaving the n throws).
    rpm : float, optional
        The speed n [1/min] (constant, or the steady state's mean); default the machine's own
        ``rpm``.
    phi : array_like, optional
        Crank angles φ [rad], 1-D, at a constant speed; default 720 uniform angles over one
        working cycle. In steady running the loads are on the steady state's 720 angles
        (give None).
    steady : bool, default False
        True: in the machine's steady running at that mean speed ("balance" load), with its
        ω(φ) and ε(φ), rather than at a constant speed.
    gravity : bool, default True
        False leaves the weights out (g = 0).

    Returns
    -------
    BearingLoads
        ``phi``, ``positions``, ``vertical``, ``horizontal`` (bearings × angles) [N],
        ``summary`` and ``polar(bearing)``.

    Raises
    ------
    MechanismError
        For a bad argument, naming it; for a machine without ``rpm`` when none is given.
    StallError
        ``steady=True`` where the machine stalls at that speed.

    Notes
    -----
    Each unit: the piston (mass m_t) is pushed by the gas force F, the wall's normal force and
    the rod; the rod (m_k, centre of gravity z_k from the piston pin, I_k about it) by the
    piston and the crank pin; Newton–Euler for both gives the pin's force on the rod, whose
    reaction, with the web's and counterweight's inertia and the weights, loads the throw. A
    throw at z_t between bearings at z_a < z_t < z_b puts (z_b − z_t)/(z_b − z_a) of its load on
    a and the rest on b (docs/theory.md, "Main-bearing loads"). Under the machine's
    ``load_law`` the gas forces are those of the law's pressures at this (mean) speed.

    Examples
    --------
    >>> import multicrank as mc
    >>> compressor = mc.presets.MACHINES["boxer-compressor"]
    >>> loads = mc.bearing_loads(compressor)
    >>> loads.vertical.shape
    (3, 720)
    """
    machine = as_instance(machine, Machine, "machine")
    omega = running_omega(machine, rpm)
    steady, gravity = as_flag(steady, "steady"), as_flag(gravity, "gravity")
    if steady and phi is not None:
        raise refused("phi", "phi: in steady running the loads are on the steady state's own angles; give None")
    return _bearing_loads(machine, omega, steady, phi, gravity)


def bearing_loads_beside(forces: ShakingForces) -> BearingLoads:
    """:func:`bearing_loads` of the machine of ``forces`` (a :class:`~multicrank.ShakingForces`)
    at its speed, steady or constant, gravity included: the same ω [rad/s] and, in steady
    running, the same steady state — on every ``2·turns``-th of its angles, the 720 of one
    working cycle that :func:`bearing_loads` takes —, so that the two of one call chain (the
    command line's ``forces``) solve one steady state and convert no speed again."""
    return _bearing_loads(forces.machine, forces.omega, forces.steady, None, True, state=forces._state)


def _bearing_loads(
    machine: Machine, omega: float, steady: bool, phi: Any, gravity: bool, state: SteadyState | None = None
) -> BearingLoads:
    """The loads of checked input, ω [rad/s] (in steady running: of ``state`` where given, the
    machine's steady state at that mean speed with gravity, else one solved here)."""
    positions = np.asarray(machine.bearings, dtype=float)
    angles, horizontal, vertical = _loads(machine, omega, steady, phi, gravity, state)
    return BearingLoads(machine, rpm_from_omega(omega), omega, steady, gravity, angles, positions, vertical, horizontal)


def _loads(
    machine: Machine,
    omega: float,
    steady: bool,
    phi: Any,
    gravity: bool,
    state: SteadyState | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(φ, horizontal, vertical) of one pass of the core: at the constant speed ω [rad/s] at
    the angles ``phi`` (None: the default ones), or in steady running at that mean speed (of
    ``state`` where given: :data:`DEFAULT_POINTS` of its uniform angles); every bearing of
    the machine's (``machine.bearings``), bearing-major."""
    if not steady and phi is None:
        # the parts the core keeps per machine, at the load law's factor at this speed
        factor = float(load_factor(omega, rated_omega(machine)))
        horizontal, vertical = motion_machine(machine).bearing_loads_at_speed(omega, factor, gravity)
        angles = _default_angles(machine)
        shape = (len(machine.bearings), DEFAULT_POINTS)
        return angles, horizontal.reshape(shape), vertical.reshape(shape)
    if steady:
        if state is None:
            from ..motion.steady import balanced_state

            state = balanced_state(machine, omega, gravity=gravity, points=DEFAULT_POINTS + 1)
        step, left = divmod(state.phi.size - 1, DEFAULT_POINTS)
        assert step >= 1 and left == 0, "a steady state of DEFAULT_POINTS·k + 1 points"
        angles, speeds, accelerations = (a[:-1:step] for a in (state.phi, state.omega, state.acceleration))
    else:
        angles = _default_angles(machine) if phi is None else _as_phi(phi, machine)
        speeds, accelerations = np.full(angles.shape, omega), np.zeros(angles.shape)
    angles, speeds, accelerations = (contiguous(np.asarray(a, dtype=float)) for a in (angles, speeds, accelerations))
    from ..motion._periodic import at_load

    # the load law's gas forces at this speed
    horizontal, vertical = motion_machine(at_load(machine, omega)).bearing_loads(angles, speeds, accelerations, gravity)
    shape = (len(machine.bearings), angles.size)
    return angles, horizontal.reshape(shape), vertical.reshape(shape)


#: The default angles of each working cycle Φ [rad] met, read-only (a copy goes out).
_DEFAULT_ANGLES: dict[float, np.ndarray] = {}


def _default_angles(machine: Machine) -> np.ndarray:
    """The :data:`DEFAULT_POINTS` uniform angles over the working cycle [rad] (the core's own),
    a fresh copy of those made once per cycle length."""
    cycle = float(machine.cycle)
    angles = _DEFAULT_ANGLES.get(cycle)
    if angles is None:
        angles = cycle * np.arange(DEFAULT_POINTS) / DEFAULT_POINTS
        angles.flags.writeable = False
        angles = _DEFAULT_ANGLES.setdefault(cycle, angles)
    return angles.copy()


def _are_default(phi: np.ndarray, machine: Machine) -> bool:
    """Whether ``phi`` are the default angles, to the bit."""
    return phi.shape == (DEFAULT_POINTS,) and bool(np.array_equal(phi, _default_angles(machine)))


def _as_phi(phi: Any, machine: Machine) -> np.ndarray:
    """The angles a user gave, checked before anything of their size is made: 1-D, at least
    one, and no more than memory holds of what the loads at them take — the speeds and
    accelerations, each cylinder's gas force (the core's) and the two loads of every bearing
    (:func:`~multicrank._validation.check_size`)."""
    angles = as_real_array(phi, "phi")
    if angles.ndim != 1:
        raise refused("phi", f"phi must be 1-D, got shape {angles.shape}")
    if angles.size == 0:
        raise refused("phi", "phi must not be empty: give at least one crank angle [rad] (or None for the default)")
    per_angle = 2 + len(machine.cylinders) + 2 * len(machine.bearings)
    check_size("phi", f"{angles.size} angles for {len(machine.bearings)} bearings", angles.size * per_angle)
    return angles
