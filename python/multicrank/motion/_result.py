"""What every result of :mod:`multicrank.motion` shares: what was solved, and its conversion
to a pandas table and an xarray dataset (each written once, here).

A result names its arrays and their units in ``COLUMNS`` (the first is the dimension they
are sampled on: ``phi`` or ``time``), and the numbers that describe it as a whole in
``NUMBERS``; a result of numbers only (no ``COLUMNS``) converts to one row.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np

from .._optional import require

__all__ = ["MotionResult"]


class MotionResult:
    """The base of :class:`~multicrank.SteadyState`, :class:`~multicrank.FlywheelInertia` and
    :class:`~multicrank.Transient`.

    Attributes
    ----------
    method : str
        How it was solved, in a word or two (each result says which).
    solved : str
        What was solved and how, in words: "balance load (energy method)", "square-law load
        (closed form)", "periodic motion (shooting)", "flywheel (Brent's method over steady
        states by …)" or "time integration (DOP853)".
    """

    method: str

    #: The arrays, name → unit, in column order; the first is the dimension (the index).
    COLUMNS: ClassVar[dict[str, str]] = {}
    #: The numbers that describe the whole result, name → unit ("" for a number without one).
    NUMBERS: ClassVar[dict[str, str]] = {}

    @property
    def solved(self) -> str:
        raise NotImplementedError  # each result says it

    def _column(self, name: str) -> Any:
        """An array (or a number) of the result by its column name (its attribute, by default)."""
        return getattr(self, name)

    def _numbers(self) -> dict[str, Any]:
        """``NUMBERS`` as table and dataset attributes: netCDF takes neither None nor bool, so a
        missing number is NaN and a flag is 0 or 1."""
        numbers: dict[str, Any] = {}
        for name in self.NUMBERS:
            value = self._column(name)
            numbers[name] = math.nan if value is None else int(value) if isinstance(value, bool) else value
        return numbers

    def to_pandas(self) -> Any:
        """The result as a table.

        Returns
        -------
        pandas.DataFrame
            A result with arrays: indexed by their dimension (``phi`` [rad] or ``time`` [s]),
            one column per array; ``attrs`` holds ``units`` (of the index and of every column),
            ``solved`` and the numbers that describe the result. A result of numbers only: one
            row of them, their ``units`` and ``solved`` in ``attrs``.
        """
        import pandas as pd

        if not self.COLUMNS:
            frame = pd.DataFrame({name: [value] for name, value in self._numbers().items()})
            frame.attrs.update(solved=self.solved, units=dict(self.NUMBERS))
            return frame
        dimension, *names = self.COLUMNS
        frame = pd.DataFrame(
            {name: self._column(name) for name in names}, index=pd.Index(self._column(dimension), name=dimension)
        )
        frame.attrs.update(self._numbers())
        frame.attrs.update(solved=self.solved, units=dict(self.COLUMNS))
        return frame

    def to_xarray(self) -> Any:
        """The result as an ``xarray.Dataset``; needs the ``xarray`` extra.

        Returns
        -------
        xarray.Dataset
            One variable per array on the result's dimension (``phi`` or ``time``), each with
            its ``units`` attribute; ``solved`` and the numbers that describe the result as
            attributes of the dataset. A result of numbers only: one 0-d variable per number.
        """
        xr = require("xarray", "xarray")
        variables: dict[str, tuple[Any, ...]]
        if not self.COLUMNS:
            variables = {name: ((), value, {"units": self.NUMBERS[name]}) for name, value in self._numbers().items()}
            return xr.Dataset(variables, attrs={"solved": self.solved})
        dimension, *names = self.COLUMNS
        variables = {name: (dimension, np.asarray(self._column(name)), {"units": self.COLUMNS[name]}) for name in names}
        return xr.Dataset(
            variables,
            coords={dimension: (dimension, np.asarray(self._column(dimension)), {"units": self.COLUMNS[dimension]})},
            attrs={**self._numbers(), "solved": self.solved},
        )
