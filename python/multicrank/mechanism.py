"""Machine description: crank phase sets and the dimensionless gravity moments
(docs/theory.md, "Crank phases" and "Dimensionless moments")."""

from __future__ import annotations

from typing import Any

import numpy as np

from ._native import STANDARD_GRAVITY as _NATIVE_STANDARD_GRAVITY
from ._native import crank_phases as _native_crank_phases
from ._native import dimensionless_moments as _native_dimensionless_moments
from ._validation import as_count, as_option, as_real_array, as_strokes, broadcast_designs, check_size, finish

__all__ = ["STANDARD_GRAVITY", "crank_phases", "dimensionless_moments"]

#: Standard gravity [m/s²], the core's constant.
STANDARD_GRAVITY: float = _NATIVE_STANDARD_GRAVITY


def crank_phases(cranks: int, strokes: int = 2, acting: str = "single") -> np.ndarray:
    """Crank phases α_j = j·α (rad), j = 0 … k−1, of a regular in-line machine (eq. 8–12).

    α = T/k for single-acting and T/(2k) for double-acting machines, with T = 2π for a
    two-stroke and 4π for a four-stroke cycle. Only the set of α_j mod 2π matters, so the
    firing order is irrelevant; the values are returned unreduced (α_j may exceed 2π).

    Parameters
    ----------
    cranks : int ≥ 1
    strokes : 2 or 4
    acting : "single" or "double"

    Returns
    -------
    ndarray of shape (cranks,)
    """
    cranks = as_count(cranks, "cranks", minimum=1)
    check_size("cranks", cranks, cranks)
    return _native_crank_phases(
        cranks,
        as_strokes(strokes),
        as_option(acting, "acting", ("single", "double")),
    )


_PHYSICAL = (
    "crank_radius",
    "rod_length",
    "rod_cg",
    "piston_mass",
    "rod_mass",
    "crank_mass",
    "crank_cg_radius",
    "counterweight_mass",
    "counterweight_radius",
    "shaft_inertia",
    "rpm",
    "g",
)


def dimensionless_moments(
    *,
    crank_radius: Any,
    rod_length: Any,
    rod_cg: Any,
    piston_mass: Any,
    rod_mass: Any,
    crank_mass: Any = 0.0,
    crank_cg_radius: Any = 0.0,
    counterweight_mass: Any = 0.0,
    counterweight_radius: Any = 0.0,
    shaft_inertia: Any,
    rpm: Any,
    g: Any = STANDARD_GRAVITY,
) -> tuple[np.ndarray | np.float64, np.ndarray | np.float64]:
    """The dimensionless gravity moments (u1, u2) of one crank unit (corrected eq. 5–7).

    .. math::

        U_1 = \\frac{r g\\,[m_t + (l - z_k)/l \\cdot m_k]}{I_w \\omega^2}, \\qquad
        U_2 = \\frac{g\\,[r_s m_s - r_p m_p + r (z_k/l) m_k]}{I_w \\omega^2}, \\qquad
        \\omega = \\pi n / 30.

    The rod's mass is split exactly for potential energy: (l − z_k)/l of it translates with
    the piston, z_k/l rotates with the crank pin. (The paper's printed eq. 5–6 swap the two
    shares; see docs/theory.md, "Errata of the paper".) u2 is negative when the counterweight
    outweighs the rotating parts.

    Parameters (SI units; arrays broadcast together)
    ----------
    crank_radius : r [m], > 0
    rod_length : l [m], > crank_radius
    rod_cg : z_k [m], the rod's centre of gravity measured from the piston-pin axis, 0 ≤ z_k ≤ l
    piston_mass : m_t [kg], complete piston (with pin and rings), ≥ 0
    rod_mass : m_k [kg], ≥ 0
    crank_mass : m_s [kg], crank web and pin, with its centre of gravity at ``crank_cg_radius`` r_s [m]
    counterweight_mass : m_p [kg], opposite the crank pin at ``counterweight_radius`` r_p [m]
    shaft_inertia : I_w [kg·m²], the shaft and everything turning with it, > 0
    rpm : n [1/min], mean speed, > 0
    g : [m/s²], default standard gravity

    Returns
    -------
    (u1, u2), each of the broadcast shape (numpy float64 scalars for scalar input).
    """
    values = dict(
        zip(
            _PHYSICAL,
            (
                crank_radius,
                rod_length,
                rod_cg,
                piston_mass,
                rod_mass,
                crank_mass,
                crank_cg_radius,
                counterweight_mass,
                counterweight_radius,
                shaft_inertia,
                rpm,
                g,
            ),
            strict=True,
        )
    )
    arrays = {name: as_real_array(value, name) for name, value in values.items()}
    shape, flat = broadcast_designs("physical parameters", **arrays)
    moments = _native_dimensionless_moments(flat)
    return finish(moments["u1"], shape), finish(moments["u2"], shape)
