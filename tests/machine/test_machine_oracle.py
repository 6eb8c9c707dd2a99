"""An independent, first-principles oracle for the physical machine model `mc.Cylinder` / `mc.Machine`.

Nothing here reuses the closed forms of motion.md or docs/theory.md (s', s'', β', the two-mass rod, J = …).
For every slider-crank unit the oracle places each mass point in the plane, in mpmath (30 digits):

    shaft axis              at the origin
    cylinder axis           e = (cos γ, sin γ)
    crank pin               C = r·(cos(ψ+γ), sin(ψ+γ)),  ψ = φ + α  (ψ from the unit's outer dead centre)
    piston pin              P = x·e with |P − C| = l, the root on the piston's side (x = r + l at ψ = 0)
    rod centre of gravity   R = P + (z_k/l)·(C − P)    (z_k measured from the piston pin)
    rod angle               β = angle of C − P from −e  (the rod turns with β̇; the axis is fixed)
    crank-web CG            S = r_s·(cos(ψ+γ), sin(ψ+γ))
    counterweight           W = −r_p·(cos(ψ+γ), sin(ψ+γ))

and from those positions alone:

    U        = g·Σ m·y, each unit minus its own value at ψ = 0, summed over the units
    J(φ)     = I_w + Σ_units [m_t |dP/dφ|² + m_k |dR/dφ|² + I_k (dβ/dφ)²]   (T = ½ J φ̇²; rigid rod, any I_k)
    J'(φ)    = mpmath.diff of J;  gravity torque = −mpmath.diff of U
    M_gas    = Σ_units F(θ)·ds/dφ (virtual work), s = r + l − x, θ = (φ + α) mod Φ,
               F = p(θ)·A − p_c(θ)·(A − π d²/4), A = π D²/4
    M_inertia(φ, ω) = −½ J'(φ) ω²

Position derivatives are mpmath.diff of the positions (mpmath raises its working precision itself).

The library tests compare `mc.Machine` (motion.md §7) against the oracle; the
`self_check` tests below validate the oracle on its own against rigid-body facts that need no formula of
the spec (dead centres, the crank at 90°, λ → 0, finite differences).

Tolerances: J relative to J itself; J', U, gravity torque and gas torque relative to their largest
magnitude over the test angles, but never less than 1 % of the size of their parts (the largest over the
angles of Σ_units |J'_j| + (J − I_w) for J', Σ_units |M_gas,j| for M_gas, g·Σ m·|displacement| for U and
g·Σ m·|velocity| for the gravity torque), so that a machine whose parts cancel (a balanced boxer, U ≡ 0)
is still measured against something. 1e-12 for the fixed machines, 1e-11 for the property test.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace
from functools import cache

import numpy as np
import pytest
from hypothesis import Phase, given, settings
from hypothesis import strategies as st
from mpmath import mp, mpf

import multicrank as mc

DPS = 30
PI = math.pi
G0 = 9.80665
CANCEL_FLOOR = 1e-2  # see the module doc: scales never fall below 1 % of the size of the parts


# mc.Machine exists now: the library tests run unconditionally (a skip here would hide a
# missing machine); the marker stays as a label of the tests that need it.
def needs_machine(test):
    return test


# --------------------------------------------------------------------------------------
# Machine description (plain floats, the values handed to the library) and pressures
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Pressure:
    """p(θ) = scale·[c0 + Σ_k (a_k sin(ν_k θ) + b_k cos(ν_k θ)) + ramp·θ/cycle]  [Pa].

    Callable with numpy arrays (what the library gets) and, through `exact`, with an mpf (the oracle).
    A nonzero `ramp` makes p non-periodic, so a library that does not reduce θ modulo the cycle fails.
    """

    scale: float
    c0: float
    terms: tuple[tuple[float, float, float], ...] = ()  # (ν, a, b)
    ramp: float = 0.0
    cycle: float = 2 * PI

    def __call__(self, theta):
        theta = np.asarray(theta, dtype=float)
        out = np.full(theta.shape, self.c0) + self.ramp * theta / self.cycle
        for nu, a, b in self.terms:
            out = out + a * np.sin(nu * theta) + b * np.cos(nu * theta)
        return self.scale * out

    def exact(self, theta, cycle):
        out = mpf(self.c0) + mpf(self.ramp) * theta / cycle
        for nu, a, b in self.terms:
            out += mpf(a) * mp.sin(mpf(nu) * theta) + mpf(b) * mp.cos(mpf(nu) * theta)
        return mpf(self.scale) * out


@dataclass(frozen=True)
class Unit:
    """One slider-crank unit in SI units, field for field the arguments of `mc.Cylinder`."""

    r: float  # crank_radius
    l: float  # rod_length
    mt: float = 0.0  # piston_mass
    mk: float = 0.0  # rod_mass
    zk: float = 0.0  # rod_cg, from the piston-pin axis
    ik: float | None = None  # rod_inertia about the rod's CG; None → the library's default
    ms: float = 0.0  # crank_mass
    rs: float = 0.0  # crank_cg_radius
    mp: float = 0.0  # counterweight_mass
    rp: float = 0.0  # counterweight_radius
    bore: float = 0.0
    alpha: float = 0.0  # phase
    gamma: float = PI / 2  # inclination
    p: Pressure | None = None  # pressure on the crown
    pc: Pressure | None = None  # pressure_crank_end
    d: float = 0.0  # piston_rod_diameter

    def cylinder(self):
        return mc.Cylinder(
            crank_radius=self.r,
            rod_length=self.l,
            piston_mass=self.mt,
            rod_mass=self.mk,
            rod_cg=self.zk,
            rod_inertia=self.ik,
            crank_mass=self.ms,
            crank_cg_radius=self.rs,
            counterweight_mass=self.mp,
            counterweight_radius=self.rp,
            bore=self.bore,
            phase=self.alpha,
            inclination=self.gamma,
            pressure=self.p,
            pressure_crank_end=self.pc,
            piston_rod_diameter=self.d,
        )


@dataclass(frozen=True)
class Spec:
    """A machine: units, shaft inertia I_w, strokes (2 or 4) and g."""

    units: tuple[Unit, ...]
    iw: float
    strokes: int = 2
    g: float = G0

    def machine(self):
        return mc.Machine([u.cylinder() for u in self.units], shaft_inertia=self.iw, strokes=self.strokes, g=self.g)


# --------------------------------------------------------------------------------------
# The oracle (mpmath). Every function expects to be called inside mp.workdps(DPS).
# --------------------------------------------------------------------------------------


def _x(v):
    """The exact binary value of a float as an mpf (never a decimal re-reading)."""
    return mpf(float(v))


def rod_inertia(u: Unit):
    """I_k as the oracle uses it: the given value, or the documented default m_k·z_k·(l − z_k) (the
    rigid rod whose mass is concentrated at its two pins)."""
    if u.ik is not None:
        return _x(u.ik)
    return _x(u.mk) * _x(u.zk) * (_x(u.l) - _x(u.zk))


def positions(u: Unit, psi):
    """Planar positions of unit u's mass points at crank angle ψ from its outer dead centre.

    Returns a dict: C (crank pin), x (piston pin's distance from the shaft along e), P (piston pin),
    R (rod CG), beta (rod angle from −e, i.e. from the direction piston pin → shaft), S (web CG),
    W (counterweight), s (piston travel r + l − x, toward the shaft). Points are (x, y) pairs.
    """
    r, l, zk = _x(u.r), _x(u.l), _x(u.zk)
    gamma = _x(u.gamma)
    ex, ey = mp.cos(gamma), mp.sin(gamma)
    cx, cy = mp.cos(psi + gamma), mp.sin(psi + gamma)
    crank = (r * cx, r * cy)
    # |x·e − C|² = l²  ⇔  x² − 2x(e·C) + |C|² − l² = 0; the larger root is on the piston's side.
    ec = ex * crank[0] + ey * crank[1]
    x = ec + mp.sqrt(ec**2 - (crank[0] ** 2 + crank[1] ** 2) + l**2)
    pin = (x * ex, x * ey)
    t = zk / l
    rod = (pin[0] + t * (crank[0] - pin[0]), pin[1] + t * (crank[1] - pin[1]))
    dx, dy = crank[0] - pin[0], crank[1] - pin[1]
    # angle of d = C − P measured from −e: atan2(cross(−e, d), dot(−e, d)); dot(−e, d) > 0, no branch cut
    beta = mp.atan2(-(ex * dy - ey * dx), -(ex * dx + ey * dy))
    web = (_x(u.rs) * cx, _x(u.rs) * cy)
    cw = (-_x(u.rp) * cx, -_x(u.rp) * cy)
    return {"C": crank, "x": x, "P": pin, "R": rod, "beta": beta, "S": web, "W": cw, "s": r + l - x}


def _masses(u: Unit):
    return (("P", _x(u.mt)), ("R", _x(u.mk)), ("S", _x(u.ms)), ("W", _x(u.mp)))


def unit_potential(u: Unit, psi, g):
    """g·Σ m·y of unit u at crank angle ψ minus the same at ψ = 0 [J]."""
    now, ref = positions(u, psi), positions(u, mpf(0))
    return g * mp.fsum(m * (now[k][1] - ref[k][1]) for k, m in _masses(u))


def unit_potential_bound(u: Unit, psi, g):
    """g·Σ m·|displacement from ψ = 0| ≥ |unit_potential|: the size of the unit's parts of U."""
    now, ref = positions(u, psi), positions(u, mpf(0))
    return g * mp.fsum(m * mp.hypot(now[k][0] - ref[k][0], now[k][1] - ref[k][1]) for k, m in _masses(u))


def _d(fn, psi):
    return mp.diff(fn, psi)


def unit_velocities(u: Unit, psi):
    """d/dφ (= d/dψ) of the piston pin's position along e, of the rod CG (x, y) and of the rod angle."""
    vx = _d(lambda q: positions(u, q)["x"], psi)
    vr = (_d(lambda q: positions(u, q)["R"][0], psi), _d(lambda q: positions(u, q)["R"][1], psi))
    wb = _d(lambda q: positions(u, q)["beta"], psi)
    return vx, vr, wb


def unit_kinetic(u: Unit, psi):
    """2T/φ̇² of the unit's piston and rigid rod: m_t|Ṗ|² + m_k|Ṙ|² + I_k β̇² (dots: d/dφ) [kg·m²]."""
    vx, vr, wb = unit_velocities(u, psi)
    return _x(u.mt) * vx**2 + _x(u.mk) * (vr[0] ** 2 + vr[1] ** 2) + rod_inertia(u) * wb**2


def unit_gravity_bound(u: Unit, psi, g):
    """g·Σ m·|d position/dφ| ≥ |d(unit_potential)/dφ|: the size of the unit's parts of the gravity torque."""
    vx, vr, _ = unit_velocities(u, psi)
    return g * (_x(u.mt) * abs(vx) + _x(u.mk) * mp.hypot(*vr) + _x(u.ms) * abs(_x(u.rs)) + _x(u.mp) * abs(_x(u.rp)))


def unit_gas(u: Unit, psi, cycle):
    """Gas torque of one unit by virtual work: F(θ)·ds/dφ, θ = ψ mod cycle [N·m]."""
    theta = psi - cycle * mp.floor(psi / cycle)
    area = mp.pi * _x(u.bore) ** 2 / 4
    force = mpf(0)
    if u.p is not None:
        force += u.p.exact(theta, cycle) * area
    if u.pc is not None:
        force -= u.pc.exact(theta, cycle) * (area - mp.pi * _x(u.d) ** 2 / 4)
    return force * _d(lambda q: positions(u, q)["s"], psi)


@cache
def oracle(spec: Spec, phis: tuple[float, ...]):
    """Oracle values at the float angles `phis`, as float arrays, and their scales (see the module doc):
    J, dJ, U, Mg (= −dU/dφ), Mgas; scale_dJ, scale_U, scale_Mg, scale_gas."""
    out = {k: [] for k in ("J", "dJ", "U", "Mg", "Mgas", "bU", "bMg", "bdJ", "bgas")}
    with mp.workdps(DPS):
        g = _x(spec.g)
        cycle = mp.pi * spec.strokes
        for phi in phis:
            f = _x(phi)
            psis = [(u, f + _x(u.alpha)) for u in spec.units]
            kin = [unit_kinetic(u, q) for u, q in psis]
            dkin = [_d(lambda q, u=u: unit_kinetic(u, q), p) for u, p in psis]
            pot = [unit_potential(u, q, g) for u, q in psis]
            grav = [-_d(lambda q, u=u: unit_potential(u, q, g), p) for u, p in psis]
            gas = [unit_gas(u, q, cycle) for u, q in psis]
            out["J"].append(_x(spec.iw) + mp.fsum(kin))
            out["dJ"].append(mp.fsum(dkin))
            out["U"].append(mp.fsum(pot))
            out["Mg"].append(mp.fsum(grav))
            out["Mgas"].append(mp.fsum(gas))
            # J' is also measured against J − I_w: a unit can have J' ≡ 0 (rod CG on the crank pin, no piston)
            out["bdJ"].append(mp.fsum(abs(v) for v in dkin) + mp.fsum(kin))
            out["bgas"].append(mp.fsum(abs(v) for v in gas))
            out["bU"].append(mp.fsum(unit_potential_bound(u, q, g) for u, q in psis))
            out["bMg"].append(mp.fsum(unit_gravity_bound(u, q, g) for u, q in psis))
    res = {k: np.array([float(v) for v in vals]) for k, vals in out.items()}
    for key, value, bound in (("dJ", "dJ", "bdJ"), ("U", "U", "bU"), ("Mg", "Mg", "bMg"), ("gas", "Mgas", "bgas")):
        res[f"scale_{key}"] = max(float(np.max(np.abs(res[value]))), CANCEL_FLOOR * float(np.max(res.pop(bound))))
    return res


# --------------------------------------------------------------------------------------
# Comparison helpers and angle sets
# --------------------------------------------------------------------------------------


def assert_close(lib, ref, tol, label, phis):
    """max |lib − ref| ≤ tol (an absolute bound, or an array of them)."""
    lib = np.asarray(lib, dtype=float)
    assert lib.shape == ref.shape, f"{label}: shape {lib.shape} != {ref.shape}"
    assert np.all(np.isfinite(lib)), f"{label}: non-finite values"
    err = np.abs(lib - ref)
    excess = err - tol
    i = int(np.argmax(excess))
    assert excess[i] <= 0, (
        f"{label}: |lib − oracle| = {err[i]:.3e} > tol {np.broadcast_to(tol, err.shape)[i]:.3e} at φ = {phis[i]!r}: "
        f"lib {lib[i]!r}, oracle {ref[i]!r} (max |error| over all angles {err.max():.3e})"
    )


def check_mechanics(spec: Spec, phis, rtol):
    """J, J', U and the gravity torque of the library against the oracle."""
    phis = tuple(float(p) for p in phis)
    ref = oracle(spec, phis)
    m = spec.machine()
    arr = np.array(phis)
    J, dJ = m.reduced_inertia(arr)
    assert_close(J, ref["J"], rtol * ref["J"], "J", phis)
    assert_close(dJ, ref["dJ"], rtol * ref["scale_dJ"], "dJ/dφ", phis)
    assert_close(m.potential_energy(arr), ref["U"], rtol * ref["scale_U"], "U", phis)
    assert_close(m.gravity_torque(arr), ref["Mg"], rtol * ref["scale_Mg"], "gravity torque", phis)


def angles(units, n=36, cycle=2 * PI):
    """n evenly spaced angles over [0, cycle) plus every unit's dead centres (ψ = 0 and ψ = π) in [0, 2π)."""
    grid = [cycle * k / n for k in range(n)]
    dead = sorted({float(np.mod(-u.alpha + k * PI, 2 * PI)) for u in units for k in (0, 1)})
    return tuple(grid + dead)


# --------------------------------------------------------------------------------------
# Machines
# --------------------------------------------------------------------------------------

BASE = Unit(r=0.06, l=0.21, mt=1.3, mk=0.85, zk=0.145)
TWO_MASS = BASE.mk * BASE.zk * (BASE.l - BASE.zk)

SINGLES = {
    "default-rod-inertia": Spec((BASE,), iw=0.35),
    "inertia-below-two-mass": Spec((replace(BASE, ik=0.55 * TWO_MASS),), iw=0.35),
    "inertia-above-two-mass": Spec((replace(BASE, ik=1.4 * TWO_MASS),), iw=0.35),
}


def _on_pin(gamma, pin_angle, **kw):
    """A unit with inclination γ whose crank pin is at absolute angle φ + pin_angle: α = pin_angle − γ."""
    return Unit(gamma=gamma, alpha=pin_angle - gamma, **kw)


LAYOUTS = {
    # two cylinders at 90° ± 45° sharing one crank pin, the pin at 90° when φ = 0
    "v-twin": Spec(
        (
            _on_pin(PI / 2 - PI / 4, PI / 2, r=0.05, l=0.17, mt=0.9, mk=0.6, zk=0.12, ik=0.004),
            _on_pin(PI / 2 + PI / 4, PI / 2, r=0.05, l=0.17, mt=1.1, mk=0.45, zk=0.11, ms=2.0, rs=0.02),
        ),
        iw=0.2,
    ),
    # opposed horizontal cylinders (γ = 0 and π) on throws 180° apart: α = 0 for both; unequal rods so U ≠ 0
    "boxer": Spec(
        (
            _on_pin(0.0, 0.0, r=0.04, l=0.15, mt=0.7, mk=0.5, zk=0.1, ik=0.0011),
            _on_pin(PI, PI, r=0.04, l=0.15, mt=0.7, mk=0.62, zk=0.09, ik=0.0012),
        ),
        iw=0.12,
    ),
    "inclined-single-web-counterweight": Spec(
        (Unit(r=0.08, l=0.26, mt=2.2, mk=1.6, zk=0.18, ik=0.009, ms=3.1, rs=0.035, mp=2.4, rp=0.07, gamma=PI / 6),),
        iw=0.8,
    ),
}

P_SMOOTH = Pressure(1e5, 2.0, ((1.0, 1.0, 0.0), (2.0, 0.0, 0.3)))
P_CRANK = Pressure(1e5, 1.5, ((1.0, 0.0, -0.8), (3.0, 0.2, 0.0)))
# four-stroke: not 2π-periodic, and with a ramp that breaks periodicity over 4π as well
P_FOUR = Pressure(1e5, 3.0, ((0.5, 1.0, 0.4), (1.5, 0.2, -0.3)), ramp=0.5, cycle=4 * PI)
P_FOUR_CRANK = Pressure(8e4, 1.0, ((0.5, -0.5, 0.0), (1.0, 0.0, 0.25)), ramp=-0.3, cycle=4 * PI)
P_TWO_RAMP = Pressure(1e5, 2.5, ((1.0, 0.6, 0.2),), ramp=0.7, cycle=2 * PI)

GAS = {
    "two-stroke-single-acting": Spec((replace(BASE, bore=0.09, p=P_SMOOTH, alpha=0.4),), iw=0.3),
    "two-stroke-double-acting": Spec(
        (
            replace(BASE, bore=0.1, p=P_SMOOTH, pc=P_CRANK, d=0.03, alpha=-0.7),
            replace(BASE, bore=0.1, p=P_TWO_RAMP, pc=P_CRANK, d=0.025, alpha=PI / 2 + 2 * PI, gamma=PI / 3),
        ),
        iw=0.3,
    ),
    "four-stroke-single-acting-twin": Spec(
        (
            replace(BASE, bore=0.085, p=P_FOUR, alpha=0.0),
            replace(BASE, bore=0.085, p=P_FOUR, alpha=2 * PI),
            replace(BASE, bore=0.085, p=P_FOUR, alpha=-1.3, gamma=-PI / 2),
        ),
        iw=0.3,
        strokes=4,
    ),
    "four-stroke-double-acting": Spec(
        (replace(BASE, bore=0.12, p=P_FOUR, pc=P_FOUR_CRANK, d=0.035, alpha=9.0, gamma=0.3),),
        iw=0.3,
        strokes=4,
    ),
}


# --------------------------------------------------------------------------------------
# Self-checks of the oracle (no library needed)
# --------------------------------------------------------------------------------------

CHECK_UNITS = [
    Unit(r=0.06, l=0.21, mt=1.3, mk=0.85, zk=0.145, ik=0.004, ms=2.0, rs=0.03, mp=1.1, rp=0.05, gamma=PI / 2),
    Unit(r=0.3, l=0.55, mt=7.0, mk=5.0, zk=0.4, ik=0.02, ms=1.0, rs=0.1, mp=3.0, rp=0.2, gamma=0.7, alpha=1.1),
    Unit(r=0.1, l=0.4, mt=0.0, mk=2.0, zk=0.0, ik=0.01, gamma=-2.5, alpha=-3.0),
]


@pytest.mark.parametrize("u", CHECK_UNITS, ids=["upright", "inclined", "rod-only"])
def test_self_check_rigid_body_facts(u):
    """Facts of the rigid slider-crank that need no kinematic formula:
    - the rod has length l and the piston pin lies on the axis at r + l (ψ = 0) and l − r (ψ = π);
    - at ψ = 0 and π the piston is momentarily at rest and the rod turns about the piston pin with
      |β̇| = r/l, so J = m_k (z_k r/l)² + I_k (r/l)²;
    - at ψ = ±π/2 crank pin and piston pin move parallel to the axis, so the rod translates: J = (m_t + m_k) r²;
    - at ψ = π every point has gone 2r (2r_s, −2r_p) down the axis: U = −2g sin γ [r(m_t + m_k) + m_s r_s − m_p r_p];
    - J does not depend on γ and is even in ψ."""
    with mp.workdps(DPS):
        r, l, zk, ik = _x(u.r), _x(u.l), _x(u.zk), rod_inertia(u)
        g = _x(G0)
        tiny = mpf(10) ** (-DPS + 4)
        for psi in (mpf(0), mp.pi / 3, mp.pi, mpf(4)):
            pos = positions(u, psi)
            assert abs(mp.hypot(pos["P"][0] - pos["C"][0], pos["P"][1] - pos["C"][1]) - l) < tiny * l
        assert abs(positions(u, mpf(0))["x"] - (r + l)) < tiny * l
        assert abs(positions(u, mp.pi)["x"] - (l - r)) < tiny * l
        dead = _x(u.mk) * (zk * r / l) ** 2 + ik * (r / l) ** 2
        side = (_x(u.mt) + _x(u.mk)) * r**2
        for psi, want in ((mpf(0), dead), (mp.pi, dead), (mp.pi / 2, side), (-mp.pi / 2, side)):
            assert abs(unit_kinetic(u, psi) - want) < tiny * (side + dead)
        drop = -2 * g * mp.sin(_x(u.gamma)) * (r * (_x(u.mt) + _x(u.mk)) + _x(u.ms) * _x(u.rs) - _x(u.mp) * _x(u.rp))
        scale = g * (r * (_x(u.mt) + _x(u.mk)) + _x(u.ms) * _x(u.rs) + _x(u.mp) * _x(u.rp))
        assert abs(unit_potential(u, mp.pi, g) - drop) < tiny * scale
        for psi in (mpf("0.3"), mpf("2.2")):
            k = unit_kinetic(u, psi)
            assert abs(unit_kinetic(u, -psi) - k) < tiny * side
            assert abs(unit_kinetic(replace(u, gamma=u.gamma + 1.234), psi) - k) < tiny * side
            assert abs(unit_potential(u, psi, g)) <= unit_potential_bound(u, psi, g) * (1 + tiny)


def test_self_check_long_rod_limit():
    """λ → 0 (l = 10⁹ r), piston only, upright: J → I_w + m_t r² sin²ψ, U → −m_t g r (1 − cos ψ)."""
    r, mt, iw = 0.07, 3.0, 0.4
    spec = Spec((Unit(r=r, l=r * 1e9, mt=mt),), iw=iw)
    phis = (0.0, 0.4, 1.3, PI / 2, 2.0, PI, 4.0, 5.9)
    ref = oracle(spec, phis)
    p = np.array(phis)
    np.testing.assert_allclose(ref["J"], iw + mt * r**2 * np.sin(p) ** 2, rtol=1e-8, atol=0)
    np.testing.assert_allclose(ref["U"], -mt * G0 * r * (1 - np.cos(p)), rtol=0, atol=1e-8 * mt * G0 * r)
    np.testing.assert_allclose(ref["Mg"], mt * G0 * r * np.sin(p), rtol=0, atol=1e-8 * mt * G0 * r)


def test_self_check_derivatives_match_finite_differences():
    """The oracle's J' and gravity torque agree with 4th-order central differences of its J and U (h = 1e-6),
    and its gas torque at ψ = π/2 (where ds/dφ = r: the rod translates) is F·r."""
    spec = LAYOUTS["v-twin"]
    phis = (0.3, 1.7, 4.4)
    h = 1e-6
    with mp.workdps(DPS):
        g = _x(spec.g)

        def J(f):
            return mp.fsum(unit_kinetic(u, f + _x(u.alpha)) for u in spec.units)

        def U(f):
            return mp.fsum(unit_potential(u, f + _x(u.alpha), g) for u in spec.units)

        def cd(fn, f):
            hh = mpf(h)
            return (-fn(f + 2 * hh) + 8 * fn(f + hh) - 8 * fn(f - hh) + fn(f - 2 * hh)) / (12 * hh)

        fd_J = np.array([float(cd(J, _x(p))) for p in phis])
        fd_U = np.array([float(cd(U, _x(p))) for p in phis])
    ref = oracle(spec, phis)
    # truncation ~h⁴ and rounding ~10⁻³⁰/h are both far below the float64 conversion of the results
    np.testing.assert_allclose(ref["dJ"], fd_J, rtol=0, atol=1e-15 * ref["scale_dJ"])
    np.testing.assert_allclose(ref["Mg"], -fd_U, rtol=0, atol=1e-15 * ref["scale_Mg"])

    u = replace(BASE, bore=0.09, p=P_SMOOTH, pc=P_CRANK, d=0.02, gamma=1.0)
    with mp.workdps(DPS):
        for psi in (mp.pi / 2, 5 * mp.pi / 2):
            theta = psi - 2 * mp.pi * mp.floor(psi / (2 * mp.pi))
            area = mp.pi * _x(u.bore) ** 2 / 4
            force = P_SMOOTH.exact(theta, 2 * mp.pi) * area - P_CRANK.exact(theta, 2 * mp.pi) * (
                area - mp.pi * _x(u.d) ** 2 / 4
            )
            assert abs(unit_gas(u, psi, 2 * mp.pi) - force * _x(u.r)) < mpf(10) ** (-DPS + 5) * abs(force)


def test_self_check_layouts():
    """The V-twin's two units share one crank pin; the boxer's throws are opposite and its pistons move in and
    out together (both at outer dead centre at φ = 0). Up to 1e-15 m: α and γ are the floats the library gets."""
    with mp.workdps(DPS):
        for f in (mpf(0), mpf("1.1"), mpf("4.0")):
            a, b = LAYOUTS["v-twin"].units
            ca = positions(a, f + _x(a.alpha))["C"]
            cb = positions(b, f + _x(b.alpha))["C"]
            assert abs(ca[0] - cb[0]) + abs(ca[1] - cb[1]) < 1e-15
            a, b = LAYOUTS["boxer"].units
            ca = positions(a, f + _x(a.alpha))["C"]
            cb = positions(b, f + _x(b.alpha))["C"]
            assert abs(ca[0] + cb[0]) + abs(ca[1] + cb[1]) < 1e-15
            assert abs(positions(a, f + _x(a.alpha))["s"] - positions(b, f + _x(b.alpha))["s"]) < 1e-15


def test_self_check_pressure_callables():
    """The numpy and mpmath faces of each pressure agree, and the ramped ones are not periodic."""
    theta = np.linspace(0.0, 4 * PI, 9)[:-1]
    for p in (P_SMOOTH, P_CRANK, P_FOUR, P_FOUR_CRANK, P_TWO_RAMP):
        with mp.workdps(DPS):
            exact = np.array([float(p.exact(_x(t), mpf(p.cycle))) for t in theta])
        np.testing.assert_allclose(p(theta), exact, rtol=1e-14)
    assert abs(P_FOUR(1.0) - P_FOUR(1.0 + 4 * PI)) > 1e4
    assert abs(P_FOUR(1.0) - P_FOUR(1.0 + 2 * PI)) > 1e4
    assert abs(P_TWO_RAMP(1.0) - P_TWO_RAMP(1.0 + 2 * PI)) > 1e4


# --------------------------------------------------------------------------------------
# 1–2. J, J', U and the gravity torque of fixed machines
# --------------------------------------------------------------------------------------


@needs_machine
@pytest.mark.parametrize("name", SINGLES)
def test_single_upright_unit(name):
    spec = SINGLES[name]
    check_mechanics(spec, angles(spec.units), 1e-12)


@needs_machine
@pytest.mark.parametrize("name", LAYOUTS)
def test_layouts(name):
    spec = LAYOUTS[name]
    check_mechanics(spec, angles(spec.units, n=30), 1e-12)


@needs_machine
def test_results_have_the_shape_of_phi():
    m = SINGLES["default-rod-inertia"].machine()
    grid = np.linspace(0.0, 2 * PI, 6).reshape(2, 3)
    J, dJ = m.reduced_inertia(grid)
    assert np.shape(J) == np.shape(dJ) == grid.shape
    for fn in (m.potential_energy, m.gravity_torque, m.gas_torque):
        assert np.shape(fn(grid)) == grid.shape
        assert np.shape(fn(0.7)) == ()
    assert np.shape(m.inertia_torque(grid, 100.0)) == grid.shape
    J1, dJ1 = m.reduced_inertia(0.7)
    assert np.shape(J1) == np.shape(dJ1) == ()


# --------------------------------------------------------------------------------------
# 3. gas torque (virtual work)
# --------------------------------------------------------------------------------------


@needs_machine
@pytest.mark.parametrize("name", GAS)
def test_gas_torque(name):
    spec = GAS[name]
    cycle = PI * spec.strokes
    phis = angles(spec.units, n=32, cycle=cycle)
    ref = oracle(spec, phis)
    lib = spec.machine().gas_torque(np.array(phis))
    assert_close(lib, ref["Mgas"], 1e-12 * ref["scale_gas"], "gas torque", phis)


# --------------------------------------------------------------------------------------
# 4. the Eksergian inertia torque
# --------------------------------------------------------------------------------------


@needs_machine
@pytest.mark.parametrize("name", ["inertia-below-two-mass", "v-twin", "inclined-single-web-counterweight"])
@pytest.mark.parametrize("omega", [0.0, 37.5, 314.159])
def test_inertia_torque(name, omega):
    spec = {**SINGLES, **LAYOUTS}[name]
    phis = angles(spec.units, n=24)
    ref = oracle(spec, phis)
    lib = spec.machine().inertia_torque(np.array(phis), omega)
    want = -0.5 * ref["dJ"] * omega**2
    assert_close(lib, want, 1e-12 * ref["scale_dJ"] * omega**2, f"inertia torque at ω = {omega}", phis)


# --------------------------------------------------------------------------------------
# 5. property test: random geometry
# --------------------------------------------------------------------------------------

_mass = st.floats(0.0, 100.0)


@st.composite
def units(draw):
    r = draw(st.floats(0.05, 1.0))
    lam = draw(st.floats(1e-3, 0.6))
    l = r / lam
    mk = draw(_mass)
    zk = draw(st.floats(0.0, 1.0)) * l
    two_mass = mk * zk * (l - zk)
    ik = draw(st.one_of(st.none(), st.floats(0.3, 1.5).map(lambda f: f * two_mass)))
    if mk == 0.0 and ik is not None:
        ik = 0.0
    return Unit(
        r=r,
        l=l,
        mt=draw(_mass),
        mk=mk,
        zk=zk,
        ik=ik,
        ms=draw(_mass),
        rs=draw(st.floats(0.0, 1.0)),
        mp=draw(_mass),
        rp=draw(st.floats(0.0, 1.0)),
        alpha=draw(st.floats(-20.0, 20.0)),
        gamma=draw(st.floats(-2 * PI, 2 * PI)),
    )


@needs_machine
# no shrinking: every shrink step runs the mpmath oracle, and hypothesis would spend minutes on it
@settings(max_examples=30, deadline=None, phases=(Phase.explicit, Phase.reuse, Phase.generate))
@given(
    us=st.lists(units(), min_size=1, max_size=3),
    iw=st.floats(0.01, 100.0),
    strokes=st.sampled_from([2, 4]),
    phi0=st.floats(-10.0, 10.0),
)
def test_property_random_geometry(us, iw, strokes, phi0):
    spec = Spec(tuple(us), iw=iw, strokes=strokes)
    check_mechanics(spec, [phi0 + 2 * PI * k / 8 for k in range(8)], 1e-11)


# --------------------------------------------------------------------------------------
# 6. switched off: g = 0, bore = 0
# --------------------------------------------------------------------------------------


@needs_machine
def test_no_gravity_and_no_bore():
    phis = np.linspace(-3.0, 9.0, 25)
    layout = LAYOUTS["inclined-single-web-counterweight"]
    m = replace(layout, g=0.0).machine()
    assert np.all(m.potential_energy(phis) == 0.0)
    assert np.all(m.gravity_torque(phis) == 0.0)
    J, _ = m.reduced_inertia(phis)
    J_g, _ = layout.machine().reduced_inertia(phis)
    np.testing.assert_array_equal(J, J_g)  # gravity has nothing to do with inertia
    # a pressure but no bore: no gas torque (single and double acting)
    no_bore = Spec((replace(BASE, p=P_SMOOTH), replace(BASE, p=P_SMOOTH, pc=P_CRANK, alpha=1.0)), iw=0.3)
    assert np.all(no_bore.machine().gas_torque(phis) == 0.0)
    # a bore but no pressure
    assert np.all(Spec((replace(BASE, bore=0.1),), iw=0.3).machine().gas_torque(phis) == 0.0)


# --------------------------------------------------------------------------------------
# 7. bad input → MechanismError naming the parameter
# --------------------------------------------------------------------------------------

NAN = float("nan")
GOOD = Unit(r=0.06, l=0.21, mt=1.3, mk=0.85, zk=0.145, ik=0.004, ms=1.0, rs=0.02, mp=0.5, rp=0.05, bore=0.09)
FIELD = {
    "crank_radius": "r",
    "rod_length": "l",
    "piston_mass": "mt",
    "rod_mass": "mk",
    "rod_cg": "zk",
    "rod_inertia": "ik",
    "crank_mass": "ms",
    "crank_cg_radius": "rs",
    "counterweight_mass": "mp",
    "counterweight_radius": "rp",
    "bore": "bore",
    "phase": "alpha",
    "inclination": "gamma",
    "piston_rod_diameter": "d",
}

BAD_CYLINDERS = [
    ("bore", -0.01, "bore"),
    ("rod_length", 0.06, "rod_length|crank_radius"),  # l = r
    ("rod_length", 0.03, "rod_length|crank_radius"),  # l < r
    ("rod_cg", -0.001, "rod_cg"),
    ("rod_cg", 0.2101, "rod_cg"),
    ("piston_mass", -1.0, "piston_mass"),
    ("rod_mass", -0.5, "rod_mass"),
    ("crank_mass", -1.0, "crank_mass"),
    ("counterweight_mass", -1.0, "counterweight_mass"),
    ("rod_inertia", -1e-3, "rod_inertia"),
    *((name, NAN, name) for name in FIELD),
]


def _build(units, **machine):
    kw = {"shaft_inertia": 0.3, "strokes": 2, "g": G0, **machine}
    return mc.Machine([u.cylinder() for u in units], **kw)


@needs_machine
@pytest.mark.parametrize(("param", "value", "pattern"), BAD_CYLINDERS, ids=lambda v: repr(v))
def test_bad_cylinder(param, value, pattern):
    unit = replace(GOOD, **{FIELD[param]: value})
    with pytest.raises(mc.MechanismError, match=pattern):
        _build([unit])  # the error may come from Cylinder(...) or from Machine(...)


@needs_machine
@pytest.mark.parametrize(
    ("kwargs", "pattern"),
    [
        ({"shaft_inertia": 0.0}, "shaft_inertia"),
        ({"shaft_inertia": -1.0}, "shaft_inertia"),
        ({"shaft_inertia": NAN}, "shaft_inertia"),
        ({"strokes": 3}, "strokes"),
        ({"g": NAN}, r"\bg\b"),
    ],
    ids=repr,
)
def test_bad_machine(kwargs, pattern):
    with pytest.raises(mc.MechanismError, match=pattern):
        _build([GOOD], **kwargs)


@needs_machine
def test_empty_machine():
    with pytest.raises(mc.MechanismError, match=re.escape("cylinders")):
        mc.Machine([], shaft_inertia=0.3)
