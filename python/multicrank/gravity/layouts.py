"""The crank and cylinder layouts: in-line, V, boxer, W, odd-fire.

A :class:`Layout` is an arrangement without masses: the crank throws' angles and the
cylinders' bank inclinations on each throw. It gives the dimensionless :class:`~multicrank.Engine`
for per-cylinder λ, u1, u2 (:meth:`Layout.engine`), and, through
:meth:`multicrank.Machine.from_layout`, a physical machine with one cylinder on every bank.
``LAYOUTS`` holds the presets; :mod:`multicrank.presets` names them beside the built-in machines.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import refused
from .engines import Engine, as_throws
from .mechanism import crank_phases

__all__ = ["LAYOUTS", "Layout", "layout_engine"]


@dataclass(frozen=True)
class Layout:
    """A crank and cylinder arrangement, without masses: where the throws are and which
    cylinders sit on each.

    Angles are in **degrees** here, as the layouts are written. A cylinder on a throw at β
    with bank inclination γ gets phase α = β − γ (see :meth:`Engine.from_throws`).

    Parameters
    ----------
    name : str
        The layout's name (its key in ``LAYOUTS`` for the built-in ones).
    note : str
        What it is, in a few words.
    throws : tuple of float
        β_t [deg]: each throw's crank-pin angle at φ = 0 (absolute, from the horizontal),
        in their order along the shaft from the front: ``Machine.from_layout``'s
        ``cylinder_spacing`` places them so. The in-line layouts other than the four-stroke
        4, 5, 6 and 8 (which are the textbook cranks, numbered from the front) give cylinder
        j the phase j·T/k of the regular phase set; as cylinder j fires at φ = −α_j, they
        fire in the reverse of that order after cylinder 1, 1-k-…-2, as
        :func:`~multicrank.firing_orders` names them (``inline-3-4t`` 1-3-2, ``inline-6-2t``
        1-6-5-4-3-2).
    banks : tuple of tuple of float
        Per throw, the inclinations γ [deg] of the cylinders on it (90 = upright).
    strokes : {2, 4} or None, default None
        The working cycle the layout was made for, where it was made for one (the in-line
        presets: their throws are the regular phase set of that cycle, written unreduced,
        e.g. 0°, 180°, 360°, 540° for a four-stroke four); None where it serves either.

    Examples
    --------
    >>> import multicrank as mc
    >>> layout = mc.LAYOUTS["v8-cross"]
    >>> layout.note
    '90° V8, cross-plane crank (pins 0°, 90°, 270°, 180°)'
    >>> layout.cylinders, layout.throws, layout.banks[0]
    (8, (90.0, 180.0, 360.0, 270.0), (45.0, 135.0))
    """

    name: str
    note: str
    throws: tuple[float, ...]
    banks: tuple[tuple[float, ...], ...]
    strokes: int | None = None

    def __post_init__(self) -> None:
        for label in ("name", "note"):
            if not isinstance(getattr(self, label), str):
                raise refused(label, f"{label} must be a string, got {type(getattr(self, label)).__name__}")
        if self.strokes is not None and not (type(self.strokes) is int and self.strokes in (2, 4)):
            raise refused("strokes", f"strokes = {self.strokes!r} is not allowed; allowed: 2, 4 or None")
        # The checks of Engine.from_throws (by the same names), without building an engine;
        # what they accept is kept as plain floats, so that a layout is hashable and prints
        # as written.
        throws, banks = as_throws(self.throws, self.banks)
        object.__setattr__(self, "throws", tuple(float(t) for t in throws))
        object.__setattr__(self, "banks", tuple(tuple(float(b) for b in bank) for bank in banks))

    def engine(self, *, crank_ratio: Any, u1: Any, u2: Any) -> Engine:
        """The dimensionless :class:`Engine` of this layout.

        Parameters
        ----------
        crank_ratio : float or array_like
            λ [dimensionless] per cylinder: a scalar, or one value per cylinder in the
            layout's order (throw by throw, bank by bank).
        u1, u2 : float or array_like
            The dimensionless gravity moments [dimensionless] per cylinder, likewise.

        Returns
        -------
        Engine
            One unit per cylinder, named after the layout.
        """
        return Engine.from_throws(
            np.radians(self.throws),
            [np.radians(b) for b in self.banks],
            crank_ratio=crank_ratio,
            u1=u1,
            u2=u2,
            name=self.name,
        )

    @property
    def cylinders(self) -> int:
        """The number of cylinders on all throws (an int)."""
        return sum(len(b) for b in self.banks)


#: The firing orders of the textbook four-stroke in-line cranks, cylinders numbered from the
#: front along the shaft: the in-line layouts of these sizes are these cranks, so that
#: :func:`~multicrank.firing_orders` names them as engine people do (1-3-4-2, not the
#: 1-4-3-2 of the phases 0°, 180°, 360°, 540° in cylinder order, whose crank pairs 1 with 3).
TEXTBOOK_FIRING: dict[int, tuple[int, ...]] = {
    4: (1, 3, 4, 2),
    5: (1, 2, 4, 5, 3),
    6: (1, 5, 3, 6, 2, 4),
    8: (1, 6, 2, 5, 8, 3, 7, 4),
}


def _inline(cranks: int, strokes: int) -> Layout:
    # Upright in-line: the pin of crank j is at φ + α_j + 90°.
    phases = np.degrees(crank_phases(cranks, strokes, "single"))
    if strokes == 4 and cranks in TEXTBOOK_FIRING:
        # The same phases (evenly over 720°), cylinder j the one that fires at t = −α_j.
        order = TEXTBOOK_FIRING[cranks]
        phases = np.array([(-720.0 * order.index(j + 1) / cranks) % 720.0 for j in range(cranks)])
    return Layout(
        f"inline-{cranks}-{strokes}t",
        f"in-line {cranks}, {strokes}-stroke, upright",
        tuple(float(p) + 90.0 for p in phases),
        tuple((90.0,) for _ in range(cranks)),
        strokes,
    )


def _vee(name: str, note: str, bank_angle: float, throws: Sequence[float]) -> Layout:
    """Two banks symmetric about the vertical, one cylinder of each on every throw."""
    banks = (90.0 - bank_angle / 2, 90.0 + bank_angle / 2)
    return Layout(name, note, tuple(t + 90.0 for t in throws), tuple(banks for _ in throws))


def _boxer(name: str, note: str, throws: Sequence[float]) -> Layout:
    """Opposed cylinders: each throw β carries a right-hand cylinder (γ = 0); its opposed
    partner on the left (γ = 180°) sits on its own throw β + 180°."""
    pins, banks = [], []
    for t in throws:
        pins += [t, t + 180.0]
        banks += [(0.0,), (180.0,)]
    return Layout(name, note, tuple(pins), tuple(banks))


LAYOUTS: dict[str, Layout] = {}
for _k in range(1, 13):
    for _s in (2, 4):
        _layout = _inline(_k, _s)
        LAYOUTS[_layout.name] = _layout
for _layout in (
    _vee("v-twin-45", "45° V-twin, one shared pin (the classic American V-twin)", 45.0, [0.0]),
    _vee("v-twin-90", "90° V-twin, one shared pin", 90.0, [0.0]),
    Layout(
        "twin-270", "parallel twin with a 270° crank (odd fire 270°/450°), upright", (90.0, 0.0), ((90.0,), (90.0,))
    ),
    _vee("v6-60", "60° V6, three shared pins at 120°", 60.0, [0.0, 120.0, 240.0]),
    _vee("v6-90", "90° V6, three shared pins at 120°", 90.0, [0.0, 120.0, 240.0]),
    _vee("v8-flat", "90° V8, flat-plane crank (pins 0°, 180°, 180°, 0°)", 90.0, [0.0, 180.0, 180.0, 0.0]),
    _vee("v8-cross", "90° V8, cross-plane crank (pins 0°, 90°, 270°, 180°)", 90.0, [0.0, 90.0, 270.0, 180.0]),
    _vee("v12-60", "60° V12, six shared pins as an in-line six", 60.0, [0.0, 120.0, 240.0, 240.0, 120.0, 0.0]),
    _boxer("boxer-2", "flat twin, opposed cylinders on throws 180° apart", [0.0]),
    _boxer("boxer-4", "flat four, opposed cylinders on throws 180° apart", [0.0, 180.0]),
    _boxer("boxer-6", "flat six, opposed cylinders on throws 180° apart", [0.0, 120.0, 240.0]),
    _vee("v-180-2", "180° V twin: opposed cylinders sharing one pin (not a boxer)", 180.0, [0.0]),
    _vee("v-180-4", "180° V four: opposed cylinders sharing two pins at 180°", 180.0, [0.0, 180.0]),
    Layout(
        "w12",
        "broad-arrow W12: three banks 60° apart (30°, 90°, 150°) on a flat-plane four-throw crank",
        (90.0, 270.0, 270.0, 90.0),
        tuple((30.0, 90.0, 150.0) for _ in range(4)),
    ),
):
    LAYOUTS[_layout.name] = _layout


def as_layout(layout: Layout | str, name: str = "layout") -> Layout:
    """A :class:`Layout`, or the preset of that name in ``LAYOUTS`` (``name``: the parameter)."""
    if isinstance(layout, Layout):
        return layout
    if isinstance(layout, str) and layout in LAYOUTS:
        return LAYOUTS[layout]
    raise refused(
        name, f"{name} = {layout!r} is not a known layout; known: {', '.join(LAYOUTS)} (or a multicrank.Layout)"
    )


def layout_engine(name: str, *, crank_ratio: Any, u1: Any, u2: Any) -> Engine:
    """A built-in layout as a dimensionless :class:`Engine`.

    Parameters
    ----------
    name : str
        A key of ``LAYOUTS``, e.g. ``"v8-cross"``, ``"boxer-4"`` or ``"inline-6-4t"``.
    crank_ratio : float or array_like
        λ [dimensionless] per cylinder: a scalar, or one value per cylinder in the layout's
        order.
    u1, u2 : float or array_like
        The dimensionless gravity moments [dimensionless] per cylinder, likewise.

    Returns
    -------
    Engine
        ``LAYOUTS[name].engine(crank_ratio=..., u1=..., u2=...)``.

    Examples
    --------
    >>> import multicrank as mc
    >>> vee = mc.layout_engine("v6-60", crank_ratio=0.3, u1=1e-3, u2=2e-4)
    >>> len(vee), vee.surviving_harmonics(8)
    (6, [6])
    """
    return as_layout(name, "name").engine(crank_ratio=crank_ratio, u1=u1, u2=u2)
