"""What a sweep puts out: the names of the outputs (:data:`SWEEP_OUTPUTS`), the outputs a
sweep is asked for (:func:`as_outputs`) and a grid sweep's result as an ``xarray.Dataset``
(:func:`to_xarray`). :mod:`multicrank.sweeps.designs` re-exports ``SWEEP_OUTPUTS`` and
``to_xarray``, where they have always been found.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np
import pandas as pd

from .._native import SWEEP_OUTPUTS as _NATIVE_SWEEP_OUTPUTS
from .._optional import require
from .._validation import as_array as _as_array
from .._validation import refused

__all__ = ["SWEEP_OUTPUTS", "as_outputs", "to_xarray"]

#: Every output a sweep can compute, in column order (the core's names).
SWEEP_OUTPUTS: tuple[str, ...] = tuple(_NATIVE_SWEEP_OUTPUTS)


def as_outputs(outputs: Any, allowed: tuple[str, ...] = SWEEP_OUTPUTS) -> tuple[str, ...]:
    """The outputs a sweep is asked for: one name or a sequence of them, from ``allowed``, each once."""
    if isinstance(outputs, str):
        outputs = (outputs,)
    elif isinstance(outputs, (bytes, Mapping)) or not isinstance(outputs, Iterable):
        raise refused(
            "outputs",
            f"outputs must be an output name or a list of them, got {type(outputs).__name__}; "
            f"allowed: {', '.join(allowed)}",
        )
    outputs = tuple(outputs)
    unknown = [o for o in outputs if not isinstance(o, str) or o not in allowed]
    if unknown:
        raise refused("outputs", f"outputs {unknown!r} are unknown; allowed: {', '.join(allowed)}")
    if not outputs:
        raise refused("outputs", f"outputs must name at least one output; allowed: {', '.join(allowed)}")
    repeated = sorted({o for o in outputs if outputs.count(o) > 1})
    if repeated:
        raise refused("outputs", f"outputs names {', '.join(repeated)} more than once")
    return outputs


def to_xarray(result: pd.DataFrame, axes: Mapping[str, Any] | None = None) -> Any:
    """A grid sweep's result as an ``xarray.Dataset``: one dimension per grid axis, one
    variable per output. Needs the ``xarray`` extra.

    The result's rows must be the grid's, in its order (C order, the first axis slowest):
    each axis's column is checked against it, so a filtered or re-sorted result is refused
    rather than reshaped into the wrong cells.

    Parameters
    ----------
    result : pandas.DataFrame
        What :func:`sweep` returned for a :func:`design_grid` (or a :class:`DesignGrid`), or
        :func:`motion_sweep` for a :class:`MachineGrid`.
    axes : mapping of str to sequence, optional
        The grid's axes, ``{name: values}`` in grid order; default the ``grid_axes`` the
        grid left in ``result.attrs``.

    Returns
    -------
    xarray.Dataset
        One variable per output column of ``result``, on one dimension per axis, with the
        axes' values as coordinates.

    Examples
    --------
    >>> import numpy as np
    >>> import multicrank as mc
    >>> grid = mc.design_grid(crank_ratio=[0.2, 0.3], inclination=np.radians([0, 90]),
    ...                       u1=1e-3, u2=0.0, cranks=[1, 2])
    >>> data = mc.to_xarray(mc.sweep(grid, phi=360))
    >>> dict(data["energy_range"].sizes)
    {'crank_ratio': 2, 'inclination': 2, 'cranks': 2}
    >>> data["energy_range"].sel(cranks=2).values.round(7)
    array([[0.       , 0.000202 ],
           [0.       , 0.0003071]])
    """
    xr = require("xarray", "xarray")

    if not isinstance(result, pd.DataFrame):
        raise refused("result", f"result must be the pandas DataFrame of a grid sweep, got {type(result).__name__}")
    if axes is None:
        axes = result.attrs.get("grid_axes")
        if not axes:
            raise refused("result", "result does not come from a design grid: pass axes={name: values, ...}")
    if not isinstance(axes, Mapping) or not axes:
        raise refused("axes", f"axes must be a non-empty mapping {{name: values, ...}}, got {type(axes).__name__}")
    arrays: dict[str, np.ndarray] = {}
    for name, values in axes.items():
        if not isinstance(name, str):
            raise refused("axes", f"axes must be keyed by column names (strings), got {name!r}")
        array = _as_array(values, f"axes[{name!r}]")
        if array.ndim != 1 or array.size == 0:
            raise refused("axes", f"axes[{name!r}] must be a non-empty 1-D sequence, got shape {array.shape}")
        arrays[name] = array
    shape = tuple(len(v) for v in arrays.values())
    if math.prod(shape) != len(result):
        raise refused("result", f"result has {len(result)} rows, the axes make {math.prod(shape)}")
    for i, (name, array) in enumerate(arrays.items()):
        if name not in result.columns:
            raise refused("axes", f"axes[{name!r}]: result has no column {name!r}")
        along = [1] * len(shape)
        along[i] = shape[i]
        expected = np.broadcast_to(array.reshape(along), shape).reshape(-1)
        if not np.array_equal(result[name].to_numpy(), expected):
            raise refused(
                "axes",
                f"axes[{name!r}]: result's column {name!r} does not run over this axis in grid order (C order, "
                "the first axis slowest); pass the rows of the whole grid, in its order",
            )
    # A motion sweep names its outputs in attrs; a gravity sweep's are SWEEP_OUTPUTS.
    named = result.attrs.get("sweep_outputs", SWEEP_OUTPUTS)
    outputs = [c for c in result.columns if c in named]
    dims = list(arrays)
    return xr.Dataset(
        {name: (dims, result[name].to_numpy().reshape(shape)) for name in outputs},
        coords=arrays,
    )
