"""A :class:`~multicrank.Machine` of a layout: :func:`from_layout`, which
:class:`~multicrank.Machine` binds as its class method ``Machine.from_layout``, puts one
cylinder template on every bank of a :class:`~multicrank.Layout` — each cylinder its bank's
inclination and the phase its throw allows (chosen by `phases`), its throw's place along the
shaft, the crank web and counterweight on the throw's first cylinder only.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validation import as_scalar, as_strokes, check_magnitude, refused
from ..gravity.layouts import Layout, as_layout
from ..gravity.mechanism import STANDARD_GRAVITY
from .cylinder import Cylinder, diagram_strokes
from .phases import chosen_firing, even_firing

if TYPE_CHECKING:
    # The Shaft as machine.py imports it, so that this module follows wherever its own module goes.
    from .machine import Machine, Shaft

__all__ = ["from_layout"]


def from_layout(
    cls: type[Machine],
    layout: Layout | str,
    cylinder: Cylinder,
    *,
    shaft_inertia: float,
    strokes: int | None = None,
    firing: Any = None,
    g: float = STANDARD_GRAVITY,
    name: str | None = None,
    rpm: float | None = None,
    rpm_range: tuple[float, float] | None = None,
    note: str | None = None,
    delta_target: float | None = None,
    cylinder_spacing: float | None = None,
    main_bearings: Sequence[float] | None = None,
    shaft: Shaft | None = None,
    load_law: str | None = None,
) -> Machine:
    """A machine of a layout with one cylinder template on every bank.

    Parameters
    ----------
    layout : Layout or str
        A :class:`~multicrank.Layout`, or the name of one in ``LAYOUTS``.
    cylinder : Cylinder
        The template: every cylinder is this one, with its ``phase`` and ``inclination``
        replaced by the layout's. Crank webs and counterweights belong to the **throw**:
        the first cylinder on each throw keeps the template's ``crank_mass`` and
        ``counterweight_mass``, the others on that throw get 0 (a V's shared pin carries
        one web, not two).
    shaft_inertia : float
        I_w [kg·m²], as for :class:`Machine`.
    strokes : 2 or 4, optional
        The working cycle; default the layout's own (``Layout.strokes``: the in-line
        presets are made for one), else that of the template's indicator diagrams (a
        four-stroke engine cycle makes a four-stroke machine), else 2. A cycle that
        contradicts the layout's is refused.
    firing : array_like, optional
        The cylinders' phases α_j [rad] in the layout's order (throw by throw, bank by
        bank), to choose the firing order of a four-stroke machine by hand. Each must be
        β − γ of its cylinder plus a whole number of turns (2π); it is taken modulo the cycle.
    g : float, default STANDARD_GRAVITY
        Gravity [m/s²], as for :class:`Machine`.
    name : str, optional
        A label; default the layout's name.
    rpm : float, optional
        The running speed [1/min], as for :class:`Machine`.
    rpm_range : (float, float), optional
        The speeds (low, high) [1/min] the machine runs at, as for :class:`Machine`.
    note : str, optional
        A description; default the layout's note.
    delta_target : float, optional
        The δ the machine is meant to run at, as for :class:`Machine`.
    cylinder_spacing : float, optional
        s [m], > 0: the distance between neighbouring throws along the shaft. Throw t of
        the layout (``Layout.throws``, from 0) is placed at z_t = z₀ + t·s, z₀ the
        template's ``axial_position``, and every cylinder on it (a V's banks on its shared
        pin) there. Default: every cylinder at z₀, one throw.
    main_bearings : sequence of float, optional
        The main bearings' axial positions [m], as for :class:`Machine`; default
        :attr:`bearings` interleaves the throws.
    shaft : Shaft, optional
        The shaft as a torsional chain, its ``cylinder_nodes`` in the layout's cylinder
        order, as for :class:`Machine`.
    load_law : {None, "propeller"}, optional
        How the indicator diagrams follow the speed, as for :class:`Machine`.

    Returns
    -------
    Machine
        One cylinder per bank and throw, in the layout's order.

    Notes
    -----
    A cylinder on a throw at absolute angle β (the crank pin at φ + β) with bank
    inclination γ gets inclination γ and phase α = β − γ, as
    :meth:`~multicrank.Engine.from_throws` does. On a two-stroke machine that is all:
    α is reduced to [0, 2π). On a four-stroke machine the phase also places the
    cylinder in its 4π cycle (θ = (φ + α) mod 4π; it fires at θ = 0), and β − γ fixes it
    only modulo 2π: each cylinder gets α = β − γ or β − γ + 2π (reduced to [0, 4π)),
    chosen so that the firing is as even as the crank allows. Of the 2ⁿ choices the
    rule takes the one whose largest firing interval (gap between neighbouring phases
    around 4π) is smallest; among equals, the one whose intervals' sum of squares is
    smallest (closest to equal intervals); then the one that moves fewest cylinders
    from β − γ as the layout writes its throws (unreduced angles count: the in-line
    presets write the regular phase set j·4π/k of :func:`~multicrank.crank_phases`,
    whose firing is perfectly even, so they keep it exactly); then the one that keeps
    the earlier cylinders as written. Up to 16 cylinders; beyond, give ``firing``.

    **Along the shaft** the layout's throws are taken in their order from the front:
    ``cylinder_spacing`` puts throw t at z₀ + t·s. The four-stroke in-line layouts of
    4, 5, 6 and 8 cylinders (``inline-4-4t``, …) are the textbook cranks numbered from
    the front, their phases from the textbook firing order (1-3-4-2, 1-2-4-5-3,
    1-5-3-6-2-4, 1-6-2-5-8-3-7-4): the in-line four's pins lie at 0°, 180°, 180°, 0°
    along the shaft and the six's at 0°, 120°, 240°, 240°, 120°, 0° (mirror symmetric,
    so without first- and second-order couples), as in real engines. The other in-line
    layouts give cylinder j the phase j·T/k of the regular phase set; as cylinder j
    fires at φ = −α_j, they fire in the reverse of that order after cylinder 1, 1-k-…-2,
    as :func:`~multicrank.firing_orders` names them (``inline-3-4t`` 1-3-2,
    ``inline-6-2t`` 1-6-5-4-3-2): spaced, after cylinder 1 their firing runs from the
    back of the shaft forwards — for three cylinders every order is the same crank up
    to a mirror, but for the others it need not be the crank a real engine of that
    size has, whose couples differ.
    The V, boxer and W layouts write their throws along the shaft (``v8-cross``:
    0°, 90°, 270°, 180°). For another crank, give the cylinders one by one to
    :class:`Machine`, or a :class:`~multicrank.Layout` of one's own.

    Raises
    ------
    MechanismError
        For an unknown layout, a cylinder that is not a :class:`Cylinder`, a bad or
        contradicting ``strokes``, ``firing`` of the wrong length or at a phase the crank
        cannot have, and the fields :class:`Machine` checks.

    Examples
    --------
    A flat four, four-stroke: each opposed pair shares a phase modulo 2π, and the rule
    spreads the firings evenly over the 720° cycle.

    >>> import numpy as np
    >>> import multicrank as mc
    >>> cylinder = mc.Cylinder(crank_radius=0.04, rod_length=0.13, piston_mass=0.4,
    ...                        rod_mass=0.5, rod_cg=0.09, bore=0.09)
    >>> flat_four = mc.Machine.from_layout("boxer-4", cylinder, shaft_inertia=0.15,
    ...                                    strokes=4, rpm=5000)
    >>> len(flat_four), flat_four.strokes, flat_four.cycle
    (4, 4, 12.566370614359172)
    >>> [round(float(np.degrees(c.phase))) for c in flat_four.cylinders]
    [0, 360, 180, 540]
    >>> [round(float(np.degrees(c.inclination))) for c in flat_four.cylinders]
    [0, 180, 0, 180]
    """
    layout = as_layout(layout)
    if not isinstance(cylinder, Cylinder):
        raise refused(
            "cylinder", f"cylinder must be a multicrank.Cylinder (the template), got {type(cylinder).__name__}"
        )
    if len(layout.throws) != len(layout.banks):
        raise refused(
            "layout",
            f"layout {layout.name!r} has {len(layout.throws)} throws but {len(layout.banks)} banks entries",
        )
    if strokes is None:
        strokes = layout.strokes or diagram_strokes(cylinder) or 2
    cycle_strokes = as_strokes(strokes)
    if layout.strokes is not None and cycle_strokes != layout.strokes:
        raise refused(
            "strokes",
            f"strokes = {cycle_strokes} contradicts layout {layout.name!r}, whose throws are the "
            f"{layout.strokes}-stroke phase set",
        )
    written: list[float] = []  # β − γ [deg], as the layout writes it
    inclinations: list[float] = []
    first: list[bool] = []
    for beta, gammas in zip(layout.throws, layout.banks, strict=True):
        if not len(gammas):
            raise refused("layout", f"layout {layout.name!r} has a throw at {beta:g}° without a cylinder")
        for index, gamma in enumerate(gammas):
            written.append(float(beta) - float(gamma))
            inclinations.append(float(gamma))
            first.append(index == 0)
    crank = np.asarray(written)
    if not np.all(np.isfinite(crank)) or not np.all(np.isfinite(inclinations)):
        raise refused("layout", f"layout {layout.name!r} has a throw or bank angle that is not finite")
    if firing is None:
        phases = even_firing(crank, cycle_strokes)
    else:
        phases = chosen_firing(firing, crank, cycle_strokes)
    origin = cylinder.axial_position
    if cylinder_spacing is None:
        positions = [origin] * len(first)
    else:
        spacing = check_magnitude(as_scalar(cylinder_spacing, "cylinder_spacing"), "cylinder_spacing", "m")
        if not (math.isfinite(spacing) and spacing > 0):
            raise refused(
                "cylinder_spacing",
                f"cylinder_spacing = {spacing} is out of range; allowed: cylinder_spacing > 0 [m] (the distance "
                "between neighbouring throws along the shaft)",
            )
        # Throw t of the layout: the count of first cylinders up to and including this one, less one.
        throw_of = np.cumsum(first) - 1
        positions = [origin + float(t) * spacing for t in throw_of]
    bare = {"crank_mass": 0.0, "counterweight_mass": 0.0}
    cylinders = [
        cylinder.replace(
            phase=phase,
            inclination=math.radians(gamma),
            axial_position=position,
            **({} if keeps_web else bare),
        )
        for phase, gamma, keeps_web, position in zip(phases, inclinations, first, positions, strict=True)
    ]
    return cls(
        cylinders,
        shaft_inertia=shaft_inertia,
        strokes=cycle_strokes,
        g=g,
        name=layout.name if name is None else name,
        rpm=rpm,
        rpm_range=rpm_range,
        note=layout.note if note is None else note,
        delta_target=delta_target,
        main_bearings=main_bearings,
        shaft=shaft,
        load_law=load_law,
    )
