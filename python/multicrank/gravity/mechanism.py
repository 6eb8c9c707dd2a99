"""Machine description: crank phase sets and the dimensionless gravity moments
(docs/theory.md, "Crank phases" and "Dimensionless moments")."""

from __future__ import annotations

from typing import Any

import numpy as np

from .._broadcasting import broadcast_designs, finish
from .._native import STANDARD_GRAVITY as _NATIVE_STANDARD_GRAVITY
from .._native import crank_phases as _native_crank_phases
from .._native import dimensionless_moments as _native_dimensionless_moments
from .._validation import as_count, as_omega_array, as_option, as_real_array, as_strokes, check_size

__all__ = ["STANDARD_GRAVITY", "crank_phases", "dimensionless_moments"]

#: Standard gravity [m/s²], the core's constant.
STANDARD_GRAVITY: float = _NATIVE_STANDARD_GRAVITY


def crank_phases(cranks: int, strokes: int = 2, acting: str = "single") -> np.ndarray:
    """Crank phases α_j = j·α [rad], j = 0 … k−1, of a regular in-line machine.

    The paper's eq. (8)–(12): α = T/k for single-acting and T/(2k) for double-acting
    machines, with T = 2π for a two-stroke and 4π for a four-stroke cycle. Only the set of
    α_j mod 2π matters, so the firing order is irrelevant; the values are returned
    unreduced (α_j may exceed 2π).

    Parameters
    ----------
    cranks : int
        The number of cranks k, ≥ 1.
    strokes : {2, 4}, default 2
        The working cycle: two-stroke (T = 2π) or four-stroke (T = 4π).
    acting : {"single", "double"}, default "single"
        Single-acting cylinders, or double-acting ones (both faces of the piston work:
        twice the impulses per cycle).

    Returns
    -------
    ndarray
        α_j [rad], shape (cranks,).

    Examples
    --------
    >>> import numpy as np
    >>> import multicrank as mc
    >>> np.degrees(mc.crank_phases(4, strokes=4))
    array([  0., 180., 360., 540.])
    >>> np.degrees(mc.crank_phases(3))
    array([  0., 120., 240.])
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
    r"""The dimensionless gravity moments (u1, u2) of one crank unit.

    The paper's eq. (5)–(7), corrected:

    .. math::

        U_1 = \frac{r g\,[m_t + (l - z_k)/l \cdot m_k]}{I_w \omega^2}, \qquad
        U_2 = \frac{g\,[r_s m_s - r_p m_p + r (z_k/l) m_k]}{I_w \omega^2}, \qquad
        \omega = \pi n / 30.

    The rod's mass is split exactly for potential energy: (l − z_k)/l of it translates with
    the piston, z_k/l rotates with the crank pin. (The paper's printed eq. 5–6 swap the two
    shares; see docs/theory.md, "Errata of the paper".) u2 is negative when the counterweight
    outweighs the rotating parts. All parameters are keywords and broadcast together.

    Parameters
    ----------
    crank_radius : array_like
        r [m], > 0.
    rod_length : array_like
        l [m], > crank_radius.
    rod_cg : array_like
        z_k [m], the rod's centre of gravity measured from the piston-pin axis,
        0 ≤ z_k ≤ l.
    piston_mass : array_like
        m_t [kg], ≥ 0: the complete piston (with pin and rings; crosshead and piston rod
        where there are).
    rod_mass : array_like
        m_k [kg], ≥ 0.
    crank_mass : array_like, default 0
        m_s [kg]: the crank web and pin, with its centre of gravity at ``crank_cg_radius``.
    crank_cg_radius : array_like, default 0
        r_s [m], the radius of the crank's centre of gravity.
    counterweight_mass : array_like, default 0
        m_p [kg], opposite the crank pin at ``counterweight_radius``.
    counterweight_radius : array_like, default 0
        r_p [m], the radius of the counterweight's centre of gravity.
    shaft_inertia : array_like
        I_w [kg·m²], > 0: the shaft and everything turning rigidly with it.
    rpm : array_like
        n [1/min], > 0: the mean speed.
    g : array_like, default STANDARD_GRAVITY
        The acceleration of gravity [m/s²], 9.80665 by default.

    Returns
    -------
    u1, u2 : ndarray or numpy.float64
        U1 and U2 [dimensionless], each of the broadcast shape of the parameters (numpy
        float64 scalars for scalar input).

    Examples
    --------
    The paper's kind of machine: a heavy, slow crank unit at 120 rpm.

    >>> import multicrank as mc
    >>> u1, u2 = mc.dimensionless_moments(
    ...     crank_radius=0.15, rod_length=0.6, rod_cg=0.4, piston_mass=85, rod_mass=60,
    ...     crank_mass=40, crank_cg_radius=0.08,
    ...     counterweight_mass=30, counterweight_radius=0.12,
    ...     shaft_inertia=45, rpm=120)
    >>> print(f"u1 = {u1:.6f}, u2 = {u2:.6f}")
    u1 = 0.021735, u2 = 0.007728
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
    flat["omega"] = as_omega_array(flat.pop("rpm"), "rpm")  # the core's speed is ω [rad/s]
    moments = _native_dimensionless_moments(flat)
    return finish(moments["u1"], shape), finish(moments["u2"], shape)
