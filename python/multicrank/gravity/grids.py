"""Uniform crank-angle grids that the kernels evaluate by rotation instead of a sincos per point.

On a uniform grid the kernels take e^{iφ} at the exact progression start + i·step as one
complex multiplication of two exact values — a seed every 1024 points and a table of
offsets e^{i·r·step} — and then rotate it by the rounding of the point the grid exposes,
x_i = start + i·step rounded to double as numpy rounds it (found exactly per point). So
sin/cos cost almost nothing, the rounding does not accumulate along the grid, and the
values are those at the grid's own points, wherever it starts: a few ulps at every point,
however long the grid and however far out (10¹⁵ rad included). They agree with
evaluation at the same points given as a plain array to ~1e-15 relative to the terms, but
not bit for bit: with a plain array each point's value depends on that point alone, which
is the default.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import numpy as np

from .._broadcasting import as_angles
from .._validation import as_count, as_real_array, check_size, contiguous, refused

__all__ = ["UniformGrid", "as_phi", "grid_of", "uniform_grid"]


class UniformGrid(np.lib.mixins.NDArrayOperatorsMixin):
    """Crank angles φ_i = start + i·step [rad], i = 0 … count − 1: a 1-D float64 array-like.

    The points are rounded to double as numpy rounds ``start + arange(count) * step``, and
    values are computed at exactly these points. Pass a grid as ``phi`` to
    :func:`potential_energy`, :func:`generalized_force`, :func:`force_derivative`, an
    :class:`Engine`'s methods or :meth:`Machine.reduced_inertia` and the like, and they use
    the rotation kernels. Everywhere else it behaves as the read-only array of its points
    (``np.asarray(grid)``, arithmetic, ufuncs, indexing, ``.max()``, plotting), and anything
    derived from it is a plain ndarray, since that need not be uniform. Make one with
    :func:`uniform_grid`.

    Parameters
    ----------
    count : int
        The number of points, ≥ 1.
    start : float
        φ_0 [rad], finite.
    step : float
        The spacing [rad], finite (0 and negative steps are allowed).

    Attributes
    ----------
    count : int
        The number of points.
    start, step : float
        φ_0 and the spacing [rad].
    """

    __slots__ = ("_cache", "count", "start", "step")

    def __init__(self, count: int, start: float, step: float) -> None:
        self.count = as_count(count, "count", minimum=1)
        self.start = _finite_angle(start, "start")
        self.step = _finite_angle(step, "step")
        self._cache: np.ndarray | None = None

    @property
    def _points(self) -> np.ndarray:
        # Formed on first use only: evaluation on the grid never needs them.
        if self._cache is None:
            check_size("count", self.count, self.count)
            points = self.start + np.arange(self.count) * self.step  # as the kernels index them
            points.flags.writeable = False
            self._cache = points
        return self._cache

    def __array__(self, dtype: Any = None, copy: bool | None = None) -> np.ndarray:
        if copy:
            return np.array(self._points, dtype=dtype)
        return self._points if dtype is None else self._points.astype(dtype, copy=False)

    def __array_ufunc__(self, ufunc: np.ufunc, method: str, *inputs: Any, **kwargs: Any) -> Any:
        inputs = tuple(x._points if isinstance(x, UniformGrid) else x for x in inputs)
        return getattr(ufunc, method)(*inputs, **kwargs)

    def __getattr__(self, name: str) -> Any:
        # shape, dtype, size, ndim, min, max, reshape, tolist, …: those of the points. Not
        # private names: before __init__ (while unpickling or copying) `_cache` is unset,
        # and asking the points for it would recurse.
        if name.startswith("_") and not name.startswith("__array"):
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        return getattr(self._points, name)

    # copy.deepcopy asks the instance for __deepcopy__, which would otherwise be the
    # points' and return a plain ndarray: a copy of a grid is a grid.
    def __copy__(self) -> UniformGrid:
        return UniformGrid(self.count, self.start, self.step)

    def __deepcopy__(self, memo: dict) -> UniformGrid:
        return UniformGrid(self.count, self.start, self.step)

    def __len__(self) -> int:
        return self.count

    def __getitem__(self, key: Any) -> Any:
        return self._points[key]

    def __iter__(self) -> Iterator[np.float64]:
        return iter(self._points)

    def __reduce__(self) -> tuple:
        return (UniformGrid, (self.count, self.start, self.step))

    def __repr__(self) -> str:
        return f"UniformGrid(count={self.count}, start={self.start!r}, step={self.step!r})"


def uniform_grid(count: int, start: float = 0.0, stop: float = 2 * math.pi, *, endpoint: bool = False) -> UniformGrid:
    """``count`` crank angles from ``start`` to ``stop`` [rad], evenly spaced, for fast evaluation.

    Like ``np.linspace(start, stop, count, endpoint=endpoint)`` — by default one revolution
    without its repeated end point — but the evaluation functions recognise it and generate
    sin/cos by rotation (see :mod:`multicrank.grids`): for ≥ 10⁴ points about 1.5× faster
    for the closed form at small k, and the series path's e^{ipφ} comes free as well.

    Parameters
    ----------
    count : int
        The number of points, ≥ 1.
    start : float, default 0
        The first angle [rad], finite.
    stop : float, default 2π
        The end of the interval [rad], finite; included only with ``endpoint=True``.
    endpoint : bool, default False
        Whether ``stop`` is the last point (as in ``np.linspace``).

    Returns
    -------
    UniformGrid
        The points ``start + i * step`` with ``step = (stop − start) / (count − endpoint)``,
        as numpy computes them (with ``endpoint=True`` the last may differ from ``stop`` by
        an ulp).

    Examples
    --------
    >>> import numpy as np
    >>> import multicrank as mc
    >>> grid = mc.uniform_grid(4, start=np.pi / 4, stop=2 * np.pi + np.pi / 4)
    >>> np.degrees(grid)
    array([ 45., 135., 225., 315.])
    >>> Q = mc.generalized_force(grid, crank_ratio=0.25, inclination=np.pi / 2, u1=1e-3, u2=0.0)
    >>> Q.round(7)
    array([-0.0008341, -0.0005801,  0.0005801,  0.0008341])
    """
    count = as_count(count, "count", minimum=1)
    bounds = [_finite_angle(start, "start"), _finite_angle(stop, "stop")]
    if not isinstance(endpoint, (bool, np.bool_)):
        raise refused("endpoint", f"endpoint must be True or False, got {endpoint!r}")
    intervals = count - 1 if endpoint else count
    step = (bounds[1] - bounds[0]) / intervals if intervals else 0.0
    if not math.isfinite(step):
        raise refused("stop", f"stop - start = {bounds[1] - bounds[0]} is out of range; allowed: a finite span")
    return UniformGrid(count, bounds[0], step)


def _finite_angle(value: Any, name: str) -> float:
    array = as_real_array(value, name)
    if array.ndim != 0:
        raise refused(name, f"{name} must be a single angle [rad], got shape {array.shape}")
    if not math.isfinite(array):
        raise refused(name, f"{name} = {float(array)} is out of range; allowed: a finite angle [rad]")
    return float(array)


def grid_of(phi: Any) -> tuple[float, float, int] | None:
    """(start, step, count) when ``phi`` is an intact :class:`UniformGrid`, else None."""
    if isinstance(phi, UniformGrid):
        return (phi.start, phi.step, phi.count)
    return None


def as_phi(phi: Any) -> tuple[tuple[int, ...], np.ndarray | tuple[float, float, int]]:
    """φ for the kernels: (its shape, the flat contiguous points or the uniform grid).

    For a :class:`~multicrank.UniformGrid` the kernels rotate: they get (start, step, count)
    and no points, which are then never formed.
    """
    uniform = grid_of(phi)
    if uniform:
        check_size("phi", f"a uniform grid of {uniform[2]} points", uniform[2])
        return (uniform[2],), uniform
    angles = as_angles(phi)
    return angles.shape, contiguous(angles).reshape(-1)
