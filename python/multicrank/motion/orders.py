"""Orders of the shaft torques: their Fourier coefficients per revolution (docs/theory.md, "Orders").

:func:`torque_orders` gives, for the order ν (the harmonic number per revolution: 0, 1, 2,
… for a two-stroke machine, and 0, ½, 1, 1½, … for a four-stroke one, whose working cycle
spans two revolutions), the coefficients of

    M(φ) = Σ_ν [a_ν cos νφ + b_ν sin νφ] = Σ_ν A_ν cos(νφ − θ_ν)

for the gas torque, the inertia torque −½ J'(φ) ω² at the mean speed, the gravity torque
−U'(φ) and their sum, in N·m, as a table for torsional-vibration tools.

- **Inertia and gravity**: J(φ) and U(φ) are analytic and 2π-periodic, so the
  Gauss–Legendre panels of one revolution give the coefficients of the machine's own
  −½ J′(φ) ω² and −U′(φ) (:meth:`~multicrank.Machine.inertia_torque`,
  :meth:`~multicrank.Machine.gravity_torque`) to rounding (spectral convergence); their half
  orders are exactly 0, and so is gravity's mean (U is periodic).
- **Gas**: the same panels over the working cycle, cut at every gassed unit's dead centres and
  at the breakpoints of its pressure tables, on each of which the integrand is smooth: for an
  :class:`~multicrank.IndicatorDiagram` the coefficients of the interpolated diagram's
  torque are exact to rounding as well. The torque itself has kinks there, so its series
  converges only algebraically ("spectral for tabulated gas": the coefficients are right,
  a truncated sum is not the torque). A pressure callable crosses to the core as its
  interpolant on a fine grid (degree 7 on panels at most π/256 wide, cut at the dead
  centres, as ``machine.native.sampled`` makes it), whose coefficients are found the
  same way: for a smooth pressure they are its own to rounding; a kink inside one of those
  panels is smoothed there.
- **Load law**: under a machine's :attr:`~multicrank.Machine.load_law` the gauge pressures at
  the speed n are those given times (n/n_r)² (the propeller law); the gas torque is linear in
  them, so its coefficients are those of the diagrams as given times that factor, exactly.

The Rust core computes the coefficients (``NativeMachine.torque_orders`` of the machine's
native machine); here they are checked, rounded
(:data:`RESOLUTION`) and laid out. Each cylinder's own orders, which drive the shaft's
torsional modes, and the hand-off of the orders to openTorsion (:func:`~multicrank.to_opentorsion`)
are the torsion room's (``torsion.excitation``, ``torsion.handoff``), which imports this one.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validation import as_count, as_flag, as_instance, as_omega, rpm_from_omega
from ..machine.machine import Machine, load_factor, rated_omega
from ..machine.native import motion_machine

__all__ = ["ORDER_PARTS", "torque_orders"]

#: The torques of :func:`torque_orders`, in column order.
ORDER_PARTS = ("gas", "inertia", "gravity", "total")

#: A coefficient pair whose amplitude is below this fraction of its part's scale is exactly 0.
#: The scale is the size of what the part's sum cancels: for inertia and gravity Σ_j max|M_j|
#: over the units alone, for gas the part's largest amplitude, for the total the largest of
#: the three. What cancels (an in-line four's odd orders, a single cylinder's odd gravity
#: orders above the first, inertia's mean) comes out of the quadrature at ≈ 1e-16 … 2e-15 of
#: that scale (the presets up to order 100); 1e-13 is fifty times above that rounding.
RESOLUTION = 1e-13


def torque_orders(machine: Machine, rpm: float, *, max_order: int = 12, gravity: bool = True) -> Any:
    """The orders of the gas, inertia and gravity torques on the shaft [N·m].

    Parameters
    ----------
    machine : Machine
        The machine.
    rpm : float
        The mean speed n [1/min], > 0: the inertia torque is −½ J'(φ) ω² at ω = π n/30; the
        gravity torque does not depend on it, and the gas torque only under the machine's
        ``load_law`` (the propeller law: its gauge pressures, and so its gas torque, times
        (n/n_r)², n_r the machine's ``rpm``).
    max_order : int
        The highest order ν, ≥ 1. Every order from 0 in steps of 1 (two-stroke) or ½
        (four-stroke) up to it is listed.
    gravity : bool
        False gives zero gravity columns (as if g were 0).

    Returns
    -------
    pandas.DataFrame
        Indexed by ``order`` (float: ν per revolution), with the columns ``{part}_cos``,
        ``{part}_sin`` (a_ν, b_ν [N·m]), ``{part}_amplitude`` (A_ν = √(a_ν² + b_ν²) [N·m])
        and ``{part}_phase`` (θ_ν = atan2(b_ν, a_ν) [rad]) for each part in
        :data:`ORDER_PARTS`: "gas", "inertia", "gravity" and their sum "total". Order 0 holds
        the mean (a_0, b_0 = 0). φ is the crank angle of the machine (from the outer dead
        centre of a unit with phase 0), so M(φ) = Σ_ν a_ν cos νφ + b_ν sin νφ. ``attrs``
        holds ``rpm``, ``omega`` [rad/s], ``strokes`` and the ``units``.

    Notes
    -----
    Inertia and gravity are 2π-periodic: their half orders are exactly 0, and only a
    four-stroke gas cycle has half orders. Accuracy: gravity and inertia to rounding; gas
    torques to rounding for smooth or tabulated pressures (docs/theory.md, "Orders"). A
    coefficient pair whose amplitude is below 1e-13 times the size of what its part cancels
    (for inertia and gravity Σ_j max|M_j| of the units alone; for gas, its largest amplitude)
    is exactly 0: what cancels (an in-line four's odd orders, inertia's mean) prints as 0,
    not as 1e-15 N·m of rounding. "total" is the sum of the parts before that, zeroed by the
    same rule at the largest of their scales.

    Examples
    --------
    >>> import multicrank as mc
    >>> compressor = mc.presets.MACHINES["slow-compressor"]
    >>> orders = mc.torque_orders(compressor, 120, max_order=3)
    >>> orders[["gas_amplitude", "gravity_amplitude", "total_amplitude"]].round(1)
           gas_amplitude  gravity_amplitude  total_amplitude
    order
    0.0            916.0                0.0            916.0
    1.0            182.7              209.4            260.4
    2.0           1403.1               19.6           1265.4
    3.0            268.7                0.0            205.7
    """
    import pandas as pd

    machine = as_instance(machine, Machine, "machine")
    omega = as_omega(rpm, "rpm")
    highest = as_count(max_order, "max_order", minimum=1)
    gravity = as_flag(gravity, "gravity")
    found = motion_machine(machine).torque_orders(omega, highest, gravity)
    orders = np.asarray(found["order"])
    parts = {name: (np.asarray(found[f"{name}_cos"]), np.asarray(found[f"{name}_sin"])) for name in ORDER_PARTS[:3]}
    # The load law's gas: the torque is linear in the pressures, so its orders scale as they do.
    factor = load_factor(omega, rated_omega(machine))
    parts["gas"] = (parts["gas"][0] * factor, parts["gas"][1] * factor)
    parts["total"] = (
        parts["gas"][0] + parts["inertia"][0] + parts["gravity"][0],
        parts["gas"][1] + parts["inertia"][1] + parts["gravity"][1],
    )

    # What cancelled to below the quadrature's rounding is 0, not 1e-15 N·m of noise.
    scale = {name: float(np.max(np.hypot(*parts[name]))) for name in ORDER_PARTS}
    scale["inertia"] = max(scale["inertia"], float(found["inertia_scale"]))
    scale["gravity"] = max(scale["gravity"], float(found["gravity_scale"]))
    scale["total"] = max(scale.values())
    columns: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    for name in ORDER_PARTS:
        cos, sin = parts[name]
        resolved = np.hypot(cos, sin) >= RESOLUTION * scale[name]
        cos, sin = np.where(resolved, cos, 0.0), np.where(resolved, sin, 0.0)
        columns[f"{name}_cos"], columns[f"{name}_sin"] = cos, sin
        columns[f"{name}_amplitude"] = np.hypot(cos, sin)
        columns[f"{name}_phase"] = np.arctan2(sin, cos)
        units.update({f"{name}_cos": "N·m", f"{name}_sin": "N·m", f"{name}_amplitude": "N·m", f"{name}_phase": "rad"})
    frame = pd.DataFrame(columns, index=pd.Index(orders, name="order"))
    frame.attrs.update({"rpm": rpm_from_omega(omega), "omega": omega, "strokes": machine.strokes, "units": units})
    return frame
