"""An independent, first-principles oracle for `potential_energy` and `generalized_force`.

Nothing here reuses the closed forms of docs/theory.md (or the paper's). For each
slider-crank unit the oracle places every body in the plane (mpmath, 40 digits):

    shaft centre            at the origin
    cylinder axis           e = (cos γ, sin γ)
    crank pin               C = r·(cos(ψ+γ), sin(ψ+γ))           (ψ from outer dead centre)
    piston pin              P = x_p·e,  x_p = r cos ψ + √(l² − r² sin² ψ)
    rod centre of gravity   R = P + (z_k/l)·(C − P)               (on the rod, z_k from P)
    crank centre of gravity S = r_s·(cos(ψ+γ), sin(ψ+γ))
    counterweight           W = −r_p·(cos(ψ+γ), sin(ψ+γ))         (opposite the crank pin)

and sums U = g·Σ m·h (h = the vertical coordinate). Each unit's energy is measured from its
own ψ = 0 configuration, divided by I_w ω² (ω = π·rpm/30), and the units are summed at
ψ_j = φ + α_j with the phases α_j written out from docs/theory.md, "Crank phases", in exact
arithmetic (not taken from the library). Q* is mpmath.diff of that energy. The library is fed the SI engine through
`mc.dimensionless_moments`, so these tests check the moments, the energy and the force
together against physics.

Tolerance: max|lib − oracle| ≤ 1e-13·max|oracle|. Where the k unit terms cancel (regular
crank sets cancel all but a few high harmonics of Q, which can leave max|Q| ~ 1e-10 of the
individual terms) no double-precision sum can meet that; there the bound is instead
1e-14·max_φ Σ_j |term_j| — still ~10x above the rounding of an honest float64 sum and orders
of magnitude below any formula error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from mpmath import mp, mpf

import multicrank as mc

DPS = 40
PI = math.pi


# --------------------------------------------------------------------------------------
# The oracle
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Engine:
    """A slider-crank unit in SI units."""

    r: float  # crank radius [m]
    l: float  # rod length [m]
    zk: float  # rod CG from the piston-pin axis [m]
    mt: float  # piston mass [kg]
    mk: float  # rod mass [kg]
    ms: float  # crank mass [kg]
    rs: float  # crank CG radius [m]
    mcw: float  # counterweight mass [kg]
    rcw: float  # counterweight radius [m]
    inertia: float  # I_w [kg m^2]
    rpm: float
    g: float = 9.80665

    def moments(self):
        return mc.dimensionless_moments(
            crank_radius=self.r,
            rod_length=self.l,
            rod_cg=self.zk,
            piston_mass=self.mt,
            rod_mass=self.mk,
            crank_mass=self.ms,
            crank_cg_radius=self.rs,
            counterweight_mass=self.mcw,
            counterweight_radius=self.rcw,
            shaft_inertia=self.inertia,
            rpm=self.rpm,
            g=self.g,
        )


def exact_phases(k, strokes, acting):
    """docs/theory.md, "Crank phases", written out: α_j = j·α, α = T/k (single) or T/(2k) (double), T = 2π or 4π."""
    with mp.workdps(DPS):
        period = 2 * mp.pi if strokes == 2 else 4 * mp.pi
        alpha = period / k if acting == "single" else period / (2 * k)
        return [j * alpha for j in range(k)]


class Oracle:
    """Planar positions and Σ m g h for k identical units at phases α_j (mpmath)."""

    def __init__(self, engine: Engine, gamma: float, phases):
        with mp.workdps(DPS):
            e = engine
            self.r, self.l, self.zk = mpf(e.r), mpf(e.l), mpf(e.zk)
            self.mt, self.mk = mpf(e.mt), mpf(e.mk)
            self.ms, self.rs = mpf(e.ms), mpf(e.rs)
            self.mcw, self.rcw = mpf(e.mcw), mpf(e.rcw)
            self.g = mpf(e.g)
            self.gamma = mpf(gamma)
            self.ex, self.ey = mpmath.cos(self.gamma), mpmath.sin(self.gamma)
            omega = mp.pi * mpf(e.rpm) / 30
            self.inv_iw2 = 1 / (mpf(e.inertia) * omega**2)
            self.phases = [a if isinstance(a, mpmath.mpf) else mpf(a) for a in phases]
            self.u_zero = self._raw(mpf(0))

    def positions(self, psi):
        """(piston pin, crank pin, rod CG, crank CG, counterweight), each an (x, y) pair."""
        r, l = self.r, self.l
        xp = r * mpmath.cos(psi) + mpmath.sqrt(l**2 - (r * mpmath.sin(psi)) ** 2)
        piston = (xp * self.ex, xp * self.ey)
        ca, sa = mpmath.cos(psi + self.gamma), mpmath.sin(psi + self.gamma)
        pin = (r * ca, r * sa)
        t = self.zk / l
        rod = (piston[0] + t * (pin[0] - piston[0]), piston[1] + t * (pin[1] - piston[1]))
        crank = (self.rs * ca, self.rs * sa)
        counterweight = (-self.rcw * ca, -self.rcw * sa)
        return piston, pin, rod, crank, counterweight

    def _raw(self, psi):
        piston, _pin, rod, crank, cw = self.positions(psi)
        return self.g * (self.mt * piston[1] + self.mk * rod[1] + self.ms * crank[1] + self.mcw * cw[1])

    def unit_energy(self, psi):
        # No precision change in here: mpmath.diff raises the working precision itself.
        return (self._raw(psi) - self.u_zero) * self.inv_iw2

    def energy_terms(self, phi):
        with mp.workdps(DPS):
            return [self.unit_energy(mpf(phi) + a) for a in self.phases]

    def force_terms(self, phi):
        with mp.workdps(DPS):
            return [mpmath.diff(self.unit_energy, mpf(phi) + a) for a in self.phases]

    def energy(self, phis):
        """(U* at each φ, max_φ Σ_j |unit term|)."""
        return _sum_terms([self.energy_terms(p) for p in phis])

    def force(self, phis):
        """(Q* at each φ, max_φ Σ_j |unit term|)."""
        return _sum_terms([self.force_terms(p) for p in phis])


def _sum_terms(rows):
    with mp.workdps(DPS):
        totals = np.array([float(mpmath.fsum(row)) for row in rows])
        cond = max(float(mpmath.fsum(abs(t) for t in row)) for row in rows)
    return totals, cond


def assert_matches(lib, ref, cond, label):
    lib = np.asarray(lib, dtype=float)
    assert lib.shape == ref.shape, f"{label}: shape {lib.shape} != {ref.shape}"
    assert np.all(np.isfinite(lib)), f"{label}: non-finite values"
    scale = float(np.max(np.abs(ref)))
    tol = max(1e-13 * scale, 1e-14 * cond)
    err = np.abs(lib - ref)
    i = int(np.argmax(err))
    assert err[i] <= tol, (
        f"{label}: max |lib - oracle| = {err[i]:.3e} > tol {tol:.3e} "
        f"(max|oracle| = {scale:.3e}, sum of |terms| = {cond:.3e}); "
        f"worst at index {i}: lib {lib[i]!r}, oracle {ref[i]!r}"
    )


def phi_grid(n, seed=0):
    """n float angles spanning several revolutions (negative ones too), including 0."""
    base = np.linspace(-3.0 * PI, 5.0 * PI, n - 1)
    jitter = np.random.default_rng(seed).uniform(-0.05, 0.05, n - 1)
    return np.concatenate([[0.0], base + jitter])


# --------------------------------------------------------------------------------------
# Engines: one per crank ratio λ = r/l; `heavy_cw` swaps in a counterweight making u2 < 0.
# --------------------------------------------------------------------------------------

ENGINES = {
    # λ = 1e-6: an (unphysically) long rod; lengths are only ratios here.
    1e-6: Engine(
        r=0.05, l=5.0e4, zk=2.0e4, mt=1.4, mk=0.8, ms=1.5, rs=0.03, mcw=0.5, rcw=0.04, inertia=0.35, rpm=900.0
    ),
    0.05: Engine(r=0.01, l=0.2, zk=0.13, mt=0.6, mk=0.4, ms=0.7, rs=0.008, mcw=0.2, rcw=0.01, inertia=0.02, rpm=3000.0),
    0.3: Engine(r=0.06, l=0.2, zk=0.13, mt=1.2, mk=0.9, ms=2.0, rs=0.03, mcw=1.0, rcw=0.05, inertia=0.5, rpm=1500.0),
    0.45: Engine(
        r=0.09, l=0.2, zk=0.05, mt=2.5, mk=1.7, ms=3.0, rs=0.05, mcw=1.5, rcw=0.06, inertia=1.2, rpm=600.0, g=9.81
    ),
    0.8: Engine(r=0.16, l=0.2, zk=0.1, mt=0.9, mk=0.5, ms=1.0, rs=0.1, mcw=0.4, rcw=0.12, inertia=0.3, rpm=250.0),
    0.95: Engine(
        r=0.19, l=0.2, zk=0.2, mt=3.0, mk=2.0, ms=0.0, rs=0.0, mcw=0.0, rcw=0.0, inertia=2.0, rpm=120.0, g=1.62
    ),
}


def engine_for(lam, heavy_cw):
    e = ENGINES[lam]
    if heavy_cw:
        # outweighs crank + rod's rotating share: u2 < 0
        e = replace(e, mcw=4.0 * (e.ms + e.mk + e.mt), rcw=max(e.r, e.rs) * 1.1)
    return e


# (k, strokes, acting, γ, λ, heavy counterweight)
CASES = [
    (1, 2, "single", PI / 2, 0.3, False),
    (1, 4, "single", 0.0, 0.45, True),
    (1, 2, "double", -PI / 2, 0.95, True),
    (1, 4, "double", 2.5, 1e-6, False),
    (2, 4, "single", PI, 0.8, False),
    (2, 2, "double", 0.3, 0.05, True),
    (2, 2, "single", -1.1, 0.95, False),
    (3, 2, "single", 2.5, 0.3, True),
    (3, 4, "double", -1.1, 1e-6, False),
    (3, 4, "single", PI / 2, 0.8, True),
    (4, 4, "single", PI / 2, 0.3, True),
    (4, 2, "double", 0.0, 0.95, False),
    (5, 2, "single", -PI / 2, 0.45, False),
    (5, 4, "single", 0.3, 0.8, True),
    (6, 4, "single", PI / 2, 0.95, True),
    (6, 2, "double", PI, 0.3, False),
    (7, 2, "single", 2.5, 0.45, True),
    (7, 4, "double", PI / 2, 0.05, False),
    (8, 4, "single", -1.1, 0.8, True),
    (8, 2, "double", -PI / 2, 0.3, True),
    (9, 2, "single", 0.3, 0.95, False),
    (9, 4, "double", 0.0, 0.3, True),
    (10, 4, "single", 0.0, 1e-6, True),
    (10, 2, "double", 2.5, 0.45, True),
    (11, 4, "double", PI, 0.8, False),
    (11, 2, "single", PI / 2, 0.3, True),
    (12, 2, "single", PI / 2, 0.95, True),
    (12, 4, "double", -1.1, 0.45, False),
    (12, 4, "single", -PI / 2, 0.05, False),
    (12, 2, "double", PI / 2, 0.8, True),
]


def _case_id(c):
    k, s, a, g, lam, heavy = c
    return f"k{k}-{s}st-{a}-g{g:.3f}-lam{lam:g}-{'u2neg' if heavy else 'u2pos'}"


@pytest.mark.parametrize("case", CASES, ids=[_case_id(c) for c in CASES])
def test_energy_and_force_match_first_principles(case):
    k, strokes, acting, gamma, lam, heavy = case
    engine = engine_for(lam, heavy)
    u1, u2 = engine.moments()
    assert (float(u2) < 0) == heavy
    phases = mc.crank_phases(k, strokes, acting)
    oracle = Oracle(engine, gamma, exact_phases(k, strokes, acting))
    phis = phi_grid(64 if k <= 4 else 40, seed=k)
    kw = dict(crank_ratio=engine.r / engine.l, inclination=gamma, u1=u1, u2=u2, phases=phases)

    u_ref, u_cond = oracle.energy(phis)
    assert_matches(mc.potential_energy(phis, **kw), u_ref, u_cond, "potential_energy")

    q_ref, q_cond = oracle.force(phis)
    assert_matches(mc.generalized_force(phis, method="exact", **kw), q_ref, q_cond, "generalized_force(exact)")
    # the default method is "exact"
    assert_matches(mc.generalized_force(phis, **kw), q_ref, q_cond, "generalized_force()")


@pytest.mark.parametrize(
    "phases",
    [
        [0.0, PI / 2, 3 * PI / 2, PI],  # cross-plane V8 throw set
        [0.1, 2.0, -1.3, 7.5, 2.0],  # irregular, with a repeated throw
        [-4.0],  # a single, shifted crank
    ],
)
@pytest.mark.parametrize("gamma", [PI / 2, -1.1])
def test_arbitrary_phase_sets(phases, gamma):
    engine = engine_for(0.3, heavy_cw=True)
    u1, u2 = engine.moments()
    oracle = Oracle(engine, gamma, phases)
    phis = phi_grid(40, seed=3)
    kw = dict(crank_ratio=engine.r / engine.l, inclination=gamma, u1=u1, u2=u2, phases=np.array(phases))
    u_ref, u_cond = oracle.energy(phis)
    assert_matches(mc.potential_energy(phis, **kw), u_ref, u_cond, "potential_energy")
    q_ref, q_cond = oracle.force(phis)
    assert_matches(mc.generalized_force(phis, method="exact", **kw), q_ref, q_cond, "generalized_force")


@pytest.mark.parametrize("gamma", [PI / 2, 0.3, PI])
def test_infinite_rod_limit_lambda_zero(gamma):
    """λ = 0 exactly (allowed by the API) is the l → ∞ limit: the oracle uses l = 1e18·r
    (its λ effect, ~r²/l, is 1e-18; 40 digits of l leave 1e-22 absolute)."""
    engine = Engine(r=1.0, l=1e18, zk=0.35e18, mt=1.1, mk=0.7, ms=0.9, rs=0.6, mcw=2.5, rcw=0.8, inertia=1.0, rpm=60.0)
    u1, u2 = engine.moments()
    oracle = Oracle(engine, gamma, exact_phases(3, 4, "single"))
    phis = phi_grid(40, seed=5)
    kw = dict(crank_ratio=0.0, inclination=gamma, u1=u1, u2=u2, phases=mc.crank_phases(3, 4, "single"))
    u_ref, u_cond = oracle.energy(phis)
    assert_matches(mc.potential_energy(phis, **kw), u_ref, u_cond, "potential_energy")
    q_ref, q_cond = oracle.force(phis)
    assert_matches(mc.generalized_force(phis, **kw), q_ref, q_cond, "generalized_force")


def test_design_arrays_broadcast_against_oracle():
    """Design shape D = (3, 2) from inclination (3, 1) and u2 (2,); result D + phi.shape."""
    gammas = np.array([[PI / 2], [0.3], [-2.0]])
    base = engine_for(0.45, heavy_cw=False)
    engines = [base, replace(base, mcw=25.0, rcw=0.1)]
    u1s, u2s = zip(*(e.moments() for e in engines), strict=True)
    assert float(u1s[0]) == float(u1s[1])
    # the counterweight array through dimensionless_moments gives the same u2 pair
    u1_arr, u2_arr = mc.dimensionless_moments(
        crank_radius=base.r,
        rod_length=base.l,
        rod_cg=base.zk,
        piston_mass=base.mt,
        rod_mass=base.mk,
        crank_mass=base.ms,
        crank_cg_radius=base.rs,
        counterweight_mass=np.array([base.mcw, 25.0]),
        counterweight_radius=np.array([base.rcw, 0.1]),
        shaft_inertia=base.inertia,
        rpm=base.rpm,
        g=base.g,
    )
    np.testing.assert_array_equal(np.asarray(u2_arr), np.array([float(u) for u in u2s]))
    np.testing.assert_array_equal(np.asarray(u1_arr), np.full(2, float(u1s[0])))

    phases = mc.crank_phases(2, 4, "single")
    phis = phi_grid(6, seed=9).reshape(2, 3)
    kw = dict(crank_ratio=base.r / base.l, inclination=gammas, u1=u1s[0], u2=np.asarray(u2_arr), phases=phases)
    energy = np.asarray(mc.potential_energy(phis, **kw))
    force = np.asarray(mc.generalized_force(phis, **kw))
    assert energy.shape == force.shape == (3, 2, 2, 3)
    for i in range(3):
        for j in range(2):
            oracle = Oracle(engines[j], float(gammas[i, 0]), exact_phases(2, 4, "single"))
            u_ref, u_cond = oracle.energy(phis.ravel())
            assert_matches(energy[i, j].ravel(), u_ref, u_cond, f"energy[{i},{j}]")
            q_ref, q_cond = oracle.force(phis.ravel())
            assert_matches(force[i, j].ravel(), q_ref, q_cond, f"force[{i},{j}]")


# masses and radii on a coarse grid (no denormal/underflow noise), zeros included
finite_pos = st.integers(0, 50).map(lambda i: i / 10)
ratio = st.integers(0, 20).map(lambda i: i / 10)


@settings(max_examples=15, deadline=None, derandomize=True)
@given(
    k=st.integers(1, 12),
    strokes=st.sampled_from([2, 4]),
    acting=st.sampled_from(["single", "double"]),
    gamma=st.floats(-7.0, 7.0),
    lam=st.floats(1e-6, 0.95),
    zk_frac=st.floats(0.0, 1.0),
    masses=st.tuples(finite_pos, finite_pos, finite_pos, finite_pos),
    radii=st.tuples(ratio, ratio),
    rpm=st.floats(10.0, 1e4),
)
def test_random_engines_match_first_principles(k, strokes, acting, gamma, lam, zk_frac, masses, radii, rpm):
    l = 1.0
    r = lam * l
    engine = Engine(
        r=r,
        l=l,
        zk=zk_frac * l,
        mt=masses[0],
        mk=masses[1],
        ms=masses[2],
        rs=radii[0] * r,
        mcw=masses[3],
        rcw=radii[1] * r,
        inertia=0.7,
        rpm=rpm,
    )
    u1, u2 = engine.moments()
    oracle = Oracle(engine, gamma, exact_phases(k, strokes, acting))
    phis = phi_grid(16, seed=k)
    kw = dict(crank_ratio=lam, inclination=gamma, u1=u1, u2=u2, phases=mc.crank_phases(k, strokes, acting))
    u_ref, u_cond = oracle.energy(phis)
    q_ref, q_cond = oracle.force(phis)
    if u_cond == 0.0:  # all masses zero: everything vanishes
        np.testing.assert_array_equal(mc.potential_energy(phis, **kw), 0.0)
        return
    assert_matches(mc.potential_energy(phis, **kw), u_ref, u_cond, "potential_energy")
    assert_matches(mc.generalized_force(phis, **kw), q_ref, q_cond, "generalized_force")


# --------------------------------------------------------------------------------------
# The oracle checked against itself (so that a failure above is the library's)
# --------------------------------------------------------------------------------------


def test_oracle_geometry_and_derivative_self_consistent():
    engine = engine_for(0.8, heavy_cw=True)
    oracle = Oracle(engine, 0.3, [mpf(0), mpf(2)])
    with mp.workdps(DPS):
        for psi in [mpf("-2.3"), mpf("0.7"), mpf("4.1")]:
            piston, pin, rod, _c, _w = oracle.positions(psi)
            # the rod keeps its length, the piston pin stays on the cylinder axis
            assert abs(mpmath.hypot(pin[0] - piston[0], pin[1] - piston[1]) - oracle.l) < mpf(10) ** -35
            assert abs(piston[0] * oracle.ey - piston[1] * oracle.ex) < mpf(10) ** -35
            # rod CG at distance z_k from the piston pin
            assert abs(mpmath.hypot(rod[0] - piston[0], rod[1] - piston[1]) - oracle.zk) < mpf(10) ** -35
        # the derivative against a central difference
        h = mpf(10) ** -12
        for phi in [-1.9, 0.0, 0.4, 8.8]:
            fd = (mpmath.fsum(oracle.energy_terms(mpf(phi) + h)) - mpmath.fsum(oracle.energy_terms(mpf(phi) - h))) / (
                2 * h
            )
            assert abs(fd - mpmath.fsum(oracle.force_terms(phi))) < mpf(10) ** -20
        # ψ = 0: each unit measured from its own zero
        assert oracle.unit_energy(mpf(0)) == 0


# --------------------------------------------------------------------------------------
# The crank phase sets of docs/theory.md, "Crank phases", written out by hand
# --------------------------------------------------------------------------------------

HAND_PHASES = [
    (1, 2, "single", [0.0]),
    (1, 4, "double", [0.0]),
    (2, 2, "single", [0.0, PI]),
    (2, 4, "single", [0.0, 2 * PI]),
    (2, 2, "double", [0.0, PI / 2]),
    (3, 2, "single", [0.0, 2 * PI / 3, 4 * PI / 3]),
    (4, 4, "single", [0.0, PI, 2 * PI, 3 * PI]),
    (4, 2, "double", [0.0, PI / 4, PI / 2, 3 * PI / 4]),
    (5, 4, "single", [0.0, 4 * PI / 5, 8 * PI / 5, 12 * PI / 5, 16 * PI / 5]),
    (6, 4, "double", [0.0, PI / 3, 2 * PI / 3, PI, 4 * PI / 3, 5 * PI / 3]),
    (12, 2, "double", [j * PI / 12 for j in range(12)]),
    (12, 4, "single", [j * PI / 3 for j in range(12)]),
]


@pytest.mark.parametrize("k,strokes,acting,expected", HAND_PHASES)
def test_crank_phases_by_hand(k, strokes, acting, expected):
    got = np.asarray(mc.crank_phases(k, strokes, acting))
    assert got.shape == (k,)
    assert got.dtype == np.float64
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-14)


def test_crank_phases_defaults():
    np.testing.assert_allclose(mc.crank_phases(3), [0.0, 2 * PI / 3, 4 * PI / 3], rtol=0, atol=1e-14)
    np.testing.assert_allclose(mc.crank_phases(4, strokes=4), [0.0, PI, 2 * PI, 3 * PI], rtol=0, atol=1e-14)


# --------------------------------------------------------------------------------------
# Conventions
# --------------------------------------------------------------------------------------

CONVENTION_DESIGNS = [
    (0.3, PI / 2, 2.0e-4, -1.3e-4),
    (0.95, -1.1, 1.0, 0.5),
    (1e-6, 2.5, 3.0, -7.0),
    (0.0, 0.0, 1.0, 1.0),
]


@pytest.mark.parametrize("lam,gamma,u1,u2", CONVENTION_DESIGNS)
def test_single_crank_energy_zero_at_odc(lam, gamma, u1, u2):
    eps = np.finfo(float).eps
    for phases in (None, [0.0]):
        val = mc.potential_energy(0.0, crank_ratio=lam, inclination=gamma, u1=u1, u2=u2, phases=phases)
        assert np.ndim(val) == 0
        assert abs(float(val)) <= 4 * eps * (abs(u1) + abs(u2))


@pytest.mark.parametrize("lam,gamma,u1,u2", CONVENTION_DESIGNS)
@pytest.mark.parametrize("k,strokes,acting", [(1, 2, "single"), (3, 4, "single"), (5, 2, "double")])
def test_energy_and_force_are_2pi_periodic(lam, gamma, u1, u2, k, strokes, acting):
    phis = np.linspace(-2.0, 4.5, 37)
    kw = dict(crank_ratio=lam, inclination=gamma, u1=u1, u2=u2, phases=mc.crank_phases(k, strokes, acting))
    scale = k * (abs(u1) + abs(u2)) * 4
    for f in (mc.potential_energy, mc.generalized_force):
        base = np.asarray(f(phis, **kw))
        for shift in (2 * PI, -2 * PI, 6 * PI):
            np.testing.assert_allclose(np.asarray(f(phis + shift, **kw)), base, rtol=0, atol=5e-14 * scale)


@pytest.mark.parametrize("lam", [0.0, 1e-6, 0.3, 0.95])
def test_upright_piston_only_energy_is_nonpositive(lam):
    """γ = π/2 (piston above the shaft), u2 = 0: the piston only goes down from ODC."""
    phis = np.linspace(-7.0, 13.0, 2001)
    energy = np.asarray(mc.potential_energy(phis, crank_ratio=lam, inclination=PI / 2, u1=0.8, u2=0.0))
    assert np.all(energy <= 0.0)
    # bottom dead centre: the piston is 2r lower, U* = −2·u1
    bdc = float(mc.potential_energy(PI, crank_ratio=lam, inclination=PI / 2, u1=0.8, u2=0.0))
    assert bdc == pytest.approx(-1.6, rel=1e-14)
    # hanging engine: the piston goes up from ODC
    hanging = np.asarray(mc.potential_energy(phis, crank_ratio=lam, inclination=-PI / 2, u1=0.8, u2=0.0))
    assert np.all(hanging >= 0.0)


def test_upright_crank_pin_convention():
    """u1 = 0, γ = π/2: only a rotating mass at the pin, which is at the top at φ = 0."""
    phis = np.linspace(-3.0, 3.0, 61)
    energy = np.asarray(mc.potential_energy(phis, crank_ratio=0.3, inclination=PI / 2, u1=0.0, u2=1.0))
    np.testing.assert_allclose(energy, np.cos(phis) - 1.0, rtol=0, atol=2e-15)
    # γ = 0: the pin rises as φ grows (φ turns the way γ is measured)
    force = np.asarray(mc.generalized_force(phis, crank_ratio=0.3, inclination=0.0, u1=5.0, u2=1.0))
    np.testing.assert_allclose(force, np.cos(phis), rtol=0, atol=1e-15)
