"""The gravity terms and the reduced inertia as SymPy expressions, for a given crank: a
hand-off to users who derive their own Lagrange equations (the paper's use of them).

:func:`gravity` gives the dimensionless potential energy U_w*(φ) = Σ_j U*(φ + α_j) of k
identical slider-crank units (eq. 12) and the generalised force Q_u* = dU_w*/dφ (eq. 13);
:func:`reduced_inertia` the reduced moment of inertia J(φ) = I_w + Σ_j [m_rot r² +
m_rec s′(ψ_j)² + ΔI β′(ψ_j)²] and J′(φ). The crank is a set of phases α_j [rad] — given, the
regular set of ``cranks`` for a cycle, or a layout's cylinders — kept exact where they are
rational multiples of π. Each result's ``lambdify()`` gives numpy functions with the
library's numbers (its tests compare them with the kernels to 1e-13).

A crank of at most :data:`MAX_UNITS` (64) units is taken: SymPy's expressions grow with
every unit (64 take seconds to build and to lambdify), and more would not finish.

Needs the ``symbolic`` extra (SymPy), imported when a function is called.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._optional import require
from ._validation import as_count, as_scalar, refused

__all__ = ["MAX_UNITS", "SymbolicGravity", "SymbolicInertia", "gravity", "reduced_inertia"]

#: The most units (phases, ``cranks``, a layout's cylinders) a crank may have here: the
#: expressions hold a term per unit, and SymPy's work grows faster than their number.
MAX_UNITS = 64


def _sympy() -> Any:
    return require("sympy", "symbolic")


def _exact(angle: Any, sp: Any) -> Any:
    """An angle [rad] as SymPy takes it: a SymPy expression as given, a number as a rational
    multiple of π where it is one (to 1e-12), else as the float."""
    if isinstance(angle, sp.Basic):
        return angle
    value = float(angle)
    turns = sp.nsimplify(value / float(sp.pi), rational=True, tolerance=1e-12)
    if turns.q <= 10**6 and abs(float(turns) * float(sp.pi) - value) <= 1e-12 * max(1.0, abs(value)):
        return turns * sp.pi
    return sp.Float(value)


def _crank(
    phases: Sequence[Any] | None, cranks: int | None, strokes: int, acting: str, layout: Any, sp: Any
) -> tuple[list[Any], list[Any] | None]:
    """(phases α_j, inclinations γ_j or None) from exactly one of the three ways to give a crank."""
    given = [name for name, value in (("phases", phases), ("cranks", cranks), ("layout", layout)) if value is not None]
    if len(given) != 1:
        raise refused(
            given[0] if given else "phases",
            f"give exactly one of phases, cranks and layout, got {', '.join(given) if given else 'none'}",
        )
    if layout is not None:
        from .gravity.layouts import as_layout

        chosen = as_layout(layout)
        units = sum(len(bank) for bank in chosen.banks)
        if units > MAX_UNITS:
            raise refused(
                "layout", f"layout {chosen.name!r} has {units} cylinders; allowed: at most {MAX_UNITS} (MAX_UNITS)"
            )
        alphas, gammas = [], []
        for beta, bank in zip(chosen.throws, chosen.banks, strict=True):
            for gamma in bank:
                # A cylinder on a throw at β inclined at γ has phase β − γ (degrees, exact).
                alphas.append(sp.nsimplify(beta - gamma, rational=True) * sp.pi / 180)
                gammas.append(sp.nsimplify(gamma, rational=True) * sp.pi / 180)
        return alphas, gammas
    if cranks is not None:
        from .gravity.mechanism import crank_phases

        count = as_count(cranks, "cranks", minimum=1, maximum=MAX_UNITS)
        # The library's own phases (its checks and names), each a rational multiple of π.
        return [_exact(alpha, sp) for alpha in crank_phases(count, strokes, acting)], None
    assert phases is not None
    return [_exact(angle, sp) for angle in _phases(phases, sp)], None


def _phases(phases: Any, sp: Any) -> list[Any]:
    """The phases as given, checked: a 1-D sequence of 1 … :data:`MAX_UNITS` angles [rad],
    each a finite real number or a real SymPy expression (one with symbols is taken as it is)."""
    allowed = f"a 1-D sequence of 1 to {MAX_UNITS} finite real angles [rad] (numbers or SymPy expressions)"
    if isinstance(phases, np.ndarray) and phases.ndim != 1:
        raise refused("phases", f"phases must be {allowed}, got an array of shape {phases.shape}")
    if isinstance(phases, (str, bytes, Mapping, sp.Basic)) or not isinstance(phases, (Sequence, np.ndarray)):
        raise refused("phases", f"phases must be {allowed}, got {type(phases).__name__}")
    items = list(phases)
    if not items:
        raise refused("phases", "phases must hold at least one phase [rad]")
    if len(items) > MAX_UNITS:
        raise refused("phases", f"phases holds {len(items)} angles; allowed: {allowed}")
    for j, angle in enumerate(items):
        name = f"phases[{j}]"
        if isinstance(angle, sp.Basic):
            if angle.is_number and not (angle.is_real and angle.is_finite):
                raise refused(name, f"{name} = {angle} is out of range; allowed: {allowed}")
            if not angle.is_number and angle.is_real is False:
                raise refused(name, f"{name} = {angle} is not real; allowed: {allowed}")
            continue
        value = as_scalar(angle, name)
        if not math.isfinite(value):
            raise refused(name, f"{name} = {value} is out of range; allowed: {allowed}")
    return items


def _travel(psi: Any, lam: Any, sp: Any) -> Any:
    """s(ψ)/r = (1 − cos ψ) + λ sin²ψ/(1 + √(1 − λ² sin²ψ)): the stable form (no 0/0 at λ = 0)."""
    root = sp.sqrt(1 - lam**2 * sp.sin(psi) ** 2)
    return (1 - sp.cos(psi)) + lam * sp.sin(psi) ** 2 / (1 + root)


@dataclass(frozen=True)
class SymbolicGravity:
    """U_w*(φ) and Q_u*(φ) of a crank as SymPy expressions (:func:`gravity`).

    Attributes
    ----------
    phi, crank_ratio, u1, u2 : sympy.Symbol
        φ [rad], λ, U1 and U2 [dimensionless] (one λ, U1, U2 for every unit).
    inclination : sympy.Symbol or None
        γ [rad], one for every unit; None where the layout gives each cylinder its own.
    phases, inclinations : tuple of sympy.Expr
        α_j and γ_j of the units.
    potential_energy : sympy.Expr
        U_w*(φ) = Σ_j {U2[sin(ψ_j + γ_j) − sin γ_j] − U1 (s(ψ_j)/r) sin γ_j}, ψ_j = φ + α_j.
    generalized_force : sympy.Expr
        Q_u*(φ) = Σ_j {U2 cos(ψ_j + γ_j) − U1 [sin ψ_j + λ sin 2ψ_j/(2√(1 − λ² sin²ψ_j))] sin γ_j}.
    """

    phi: Any
    crank_ratio: Any
    u1: Any
    u2: Any
    inclination: Any
    phases: tuple[Any, ...]
    inclinations: tuple[Any, ...]
    potential_energy: Any
    generalized_force: Any

    def lambdify(self) -> tuple[Callable[..., Any], Callable[..., Any]]:
        """The expressions as numpy functions.

        Returns
        -------
        tuple of callable
            (U_w*, Q_u*), each of (phi, crank_ratio, u1, u2[, inclination]) — inclination
            only where it is a symbol — its arguments broadcast as numpy does.
        """
        sp = _sympy()
        args = [self.phi, self.crank_ratio, self.u1, self.u2]
        if self.inclination is not None:
            args.append(self.inclination)
        return (
            sp.lambdify(args, self.potential_energy, modules="numpy"),
            sp.lambdify(args, self.generalized_force, modules="numpy"),
        )


def gravity(
    phases: Sequence[Any] | None = None,
    *,
    cranks: int | None = None,
    strokes: int = 2,
    acting: str = "single",
    layout: Any = None,
) -> SymbolicGravity:
    """The potential energy U_w*(φ) (eq. 12) and the generalised force Q_u* = dU_w*/dφ (eq. 13)
    of a crank of identical units, as SymPy expressions.

    Parameters
    ----------
    phases : sequence of float or sympy.Expr, optional
        α_j [rad], one per unit; numbers that are rational multiples of π are kept exact.
    cranks : int, optional
        Instead: the regular phase set of this many cranks, 1 ≤ k ≤ :data:`MAX_UNITS`,
        α_j = j·T/k (single acting) or j·T/(2k) (double acting), T = 2π or 4π as
        ``strokes``; exact.
    strokes : {2, 4}, default 2
        The working cycle of ``cranks`` (2π or 4π).
    acting : {"single", "double"}, default "single"
        How the cylinders of ``cranks`` act.
    layout : Layout or str, optional
        Instead: a layout's cylinders, each with its phase β − γ and its own inclination γ.

    Returns
    -------
    SymbolicGravity
        The symbols and the two expressions; ``lambdify()`` turns them into numpy functions.

    Raises
    ------
    MechanismError
        Unless exactly one of ``phases``, ``cranks`` and ``layout`` is given; for phases that
        are not a 1-D sequence of finite real angles (numbers or real SymPy expressions); for
        more than :data:`MAX_UNITS` (64) units; or for a bad ``cranks``, ``strokes`` or
        ``acting`` (named as :func:`~multicrank.crank_phases` names them).
    OptionalDependencyError
        Without SymPy (the ``symbolic`` extra).

    Examples
    --------
    >>> from multicrank import symbolic
    >>> two = symbolic.gravity(cranks=2)
    >>> two.phases
    (0, pi)
    >>> import sympy
    >>> sympy.simplify(two.generalized_force - sympy.diff(two.potential_energy, two.phi))
    0
    """
    sp = _sympy()
    alphas, gammas = _crank(phases, cranks, strokes, acting, layout, sp)
    phi, lam, u1, u2 = sp.symbols("phi lambda U_1 U_2", real=True)
    gamma = sp.Symbol("gamma", real=True) if gammas is None else None
    inclinations = [gamma] * len(alphas) if gammas is None else gammas
    potential = sp.Integer(0)
    force = sp.Integer(0)
    for alpha, incline in zip(alphas, inclinations, strict=True):
        psi = phi + alpha
        potential += u2 * (sp.sin(psi + incline) - sp.sin(incline)) - u1 * _travel(psi, lam, sp) * sp.sin(incline)
        slope = sp.sin(psi) + lam * sp.sin(2 * psi) / (2 * sp.sqrt(1 - lam**2 * sp.sin(psi) ** 2))
        force += u2 * sp.cos(psi + incline) - u1 * slope * sp.sin(incline)
    return SymbolicGravity(
        phi=phi,
        crank_ratio=lam,
        u1=u1,
        u2=u2,
        inclination=gamma,
        phases=tuple(alphas),
        inclinations=tuple(inclinations),
        potential_energy=potential,
        generalized_force=force,
    )


@dataclass(frozen=True)
class SymbolicInertia:
    """J(φ) and J′(φ) of a crank as SymPy expressions (:func:`reduced_inertia`).

    Attributes
    ----------
    phi, crank_radius, crank_ratio : sympy.Symbol
        φ [rad], r [m], λ = r/l.
    shaft_inertia, reciprocating_mass, rotating_mass, rod_inertia_excess : sympy.Symbol
        I_w [kg·m²]; m_rec = m_t + m_k (l − z_k)/l [kg], moving with the piston pin;
        m_rot = m_k z_k/l [kg], turning with the crank pin; ΔI = I_k − m_k z_k (l − z_k)
        [kg·m²], turning with the rod angle (one of each for every unit).
    phases : tuple of sympy.Expr
        α_j of the units.
    reduced_inertia : sympy.Expr
        J(φ) = I_w + Σ_j [m_rot r² + m_rec s′(ψ_j)² + ΔI β′(ψ_j)²] [kg·m²].
    reduced_inertia_slope : sympy.Expr
        J′(φ) = dJ/dφ [kg·m²/rad].
    """

    phi: Any
    crank_radius: Any
    crank_ratio: Any
    shaft_inertia: Any
    reciprocating_mass: Any
    rotating_mass: Any
    rod_inertia_excess: Any
    phases: tuple[Any, ...]
    reduced_inertia: Any
    reduced_inertia_slope: Any

    def lambdify(self) -> tuple[Callable[..., Any], Callable[..., Any]]:
        """The expressions as numpy functions.

        Returns
        -------
        tuple of callable
            (J, J′), each of (phi, crank_radius, crank_ratio, shaft_inertia,
            reciprocating_mass, rotating_mass, rod_inertia_excess), its arguments broadcast
            as numpy does.
        """
        sp = _sympy()
        args = [
            self.phi,
            self.crank_radius,
            self.crank_ratio,
            self.shaft_inertia,
            self.reciprocating_mass,
            self.rotating_mass,
            self.rod_inertia_excess,
        ]
        return (
            sp.lambdify(args, self.reduced_inertia, modules="numpy"),
            sp.lambdify(args, self.reduced_inertia_slope, modules="numpy"),
        )


def reduced_inertia(
    phases: Sequence[Any] | None = None,
    *,
    cranks: int | None = None,
    strokes: int = 2,
    acting: str = "single",
    layout: Any = None,
) -> SymbolicInertia:
    """The reduced moment of inertia J(φ) of a crank of identical units and its slope J′(φ),
    as SymPy expressions (the kinetic energy T = ½ J φ̇²).

    With ψ = φ + α_j: the piston velocity s′ = r [sin ψ + λ sin 2ψ/(2√(1 − λ² sin²ψ))] and the
    rod's angular velocity β′ = λ cos ψ/√(1 − λ² sin²ψ) (per unit crank speed).

    Parameters
    ----------
    phases : sequence of float or sympy.Expr, optional
        α_j [rad], one per unit, as for :func:`gravity`.
    cranks : int, optional
        Instead: the regular phase set of this many cranks, as for :func:`gravity`.
    strokes : {2, 4}, default 2
        The working cycle of ``cranks`` (2π or 4π).
    acting : {"single", "double"}, default "single"
        How the cylinders of ``cranks`` act.
    layout : Layout or str, optional
        Instead: a layout's cylinders (their inclinations do not enter J).

    Returns
    -------
    SymbolicInertia
        The symbols and the two expressions; ``lambdify()`` turns them into numpy functions.

    Raises
    ------
    MechanismError
        As :func:`gravity`.
    OptionalDependencyError
        Without SymPy (the ``symbolic`` extra).

    Examples
    --------
    >>> from multicrank import symbolic
    >>> one = symbolic.reduced_inertia([0.0])
    >>> J, slope = one.lambdify()
    >>> float(J(0.0, 0.05, 0.25, 1.0, 2.0, 1.0, 0.0))  # at dead centre: I_w + m_rot r²
    1.0025
    """
    sp = _sympy()
    alphas, _ = _crank(phases, cranks, strokes, acting, layout, sp)
    phi, r, lam = sp.symbols("phi r lambda", real=True)
    shaft, reciprocating, rotating, excess = sp.symbols("I_w m_rec m_rot Delta_I", real=True)
    inertia = shaft
    for alpha in alphas:
        psi = phi + alpha
        root = sp.sqrt(1 - lam**2 * sp.sin(psi) ** 2)
        velocity = r * (sp.sin(psi) + lam * sp.sin(2 * psi) / (2 * root))
        turning = lam * sp.cos(psi) / root
        inertia += rotating * r**2 + reciprocating * velocity**2 + excess * turning**2
    return SymbolicInertia(
        phi=phi,
        crank_radius=r,
        crank_ratio=lam,
        shaft_inertia=shaft,
        reciprocating_mass=reciprocating,
        rotating_mass=rotating,
        rod_inertia_excess=excess,
        phases=tuple(alphas),
        reduced_inertia=inertia,
        reduced_inertia_slope=sp.diff(inertia, phi),
    )
