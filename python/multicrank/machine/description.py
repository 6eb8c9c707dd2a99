"""A :class:`~multicrank.Machine` described: its one-line ``repr``, its dimensionless gravity
:class:`~multicrank.Engine` at a speed (:meth:`~multicrank.Machine.engine`) and the keywords of
the in-line functions for it (:meth:`~multicrank.Machine.design`). :class:`MachineDescription`
holds these methods; :class:`~multicrank.Machine` inherits them and holds the data.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._native import NativeMachine
from .._text import counted
from .._validation import refused, rpm_from_omega, running_omega
from ..gravity.engines import Engine

__all__ = ["MachineDescription"]


class MachineDescription:
    """The methods of :class:`~multicrank.Machine` that describe it; a part of that class,
    without data of its own."""

    if TYPE_CHECKING:  # the fields Machine sets
        name: str
        shaft_inertia: float
        strokes: int
        g: float
        rpm: float | None

        @property
        def _core(self) -> NativeMachine: ...  # made on first use

        def __len__(self) -> int: ...

    def __repr__(self) -> str:
        speed = "" if self.rpm is None else f", {self.rpm:g} rpm"
        return (
            f"Machine({self.name!r}, {counted(len(self), 'cylinder')}, shaft_inertia={self.shaft_inertia:g} kg·m², "
            f"{self.strokes}-stroke{speed}, g={self.g:g})"
        )

    def engine(self, rpm: float | None = None) -> Engine:
        """The dimensionless gravity engine at a speed.

        One unit per cylinder, with u1, u2 = U1, U2 ÷ I_w ω², ω = π·rpm/30; a cylinder's crank
        web and counterweight are in its u2. U* × I_w ω² is :meth:`potential_energy` up to a
        constant, and Q_u* × I_w ω² is −:meth:`gravity_torque`.

        Parameters
        ----------
        rpm : float, optional
            The speed n [1/min], > 0; default the machine's own ``rpm``.

        Returns
        -------
        Engine
            Named "<machine name> at <rpm> rpm".

        Raises
        ------
        MechanismError
            When no ``rpm`` is given and the machine has none.
        """
        omega = running_omega(self, rpm)
        columns = self._core.engine(omega)
        return Engine(**columns, name=f"{self.name} at {rpm_from_omega(omega):g} rpm")

    def design(self, rpm: float | None = None) -> dict[str, Any]:
        """The keywords of the in-line functions for this machine at a speed.

        The keywords of :func:`~multicrank.potential_energy`,
        :func:`~multicrank.generalized_force`, :func:`~multicrank.speed_fluctuation`, …:
        ``crank_ratio``, ``inclination`` [rad], ``u1``, ``u2`` and ``phases`` [rad]. Only for
        a machine of identical units that differ in phase alone (an in-line machine with a
        web on every crank, the paper's machine); any other has no single (λ, γ, u1, u2): use
        :meth:`engine`.

        Parameters
        ----------
        rpm : float, optional
            The speed n [1/min], > 0; default the machine's own ``rpm``.

        Returns
        -------
        dict
            ``crank_ratio``, ``inclination``, ``u1``, ``u2`` (floats) and ``phases`` (an
            array), to pass as ``**design``.

        Raises
        ------
        MechanismError
            When the cylinders differ in anything but their phase.

        Examples
        --------
        >>> import numpy as np
        >>> import multicrank as mc
        >>> design = mc.presets.MACHINES["slow-compressor"].design()
        >>> sorted(design)
        ['crank_ratio', 'inclination', 'phases', 'u1', 'u2']
        >>> print(f"δ_g = {mc.speed_fluctuation(**design):.6f}")
        δ_g = 0.007576
        """
        engine = self.engine(rpm)
        shared = {}
        for field in ("crank_ratio", "inclination", "u1", "u2"):
            column = getattr(engine, field)
            if not np.all(column == column[0]):
                raise refused(
                    field,
                    f"machine {self.name!r} has cylinders that differ in {field}: the in-line design (one "
                    f"crank_ratio, inclination, u1, u2 for all) is for machines of identical cylinders; use engine()",
                )
            shared[field] = float(column[0])
        return {**shared, "phases": engine.phase.copy()}
