"""multicrank.symbolic: the SymPy expressions of U_w*, Q_u* and J, against the library's kernels
(which share no code with them: the kernels are Rust, the expressions are SymPy's)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import multicrank as mc

sympy = pytest.importorskip("sympy")
from multicrank import symbolic  # noqa: E402  (after the skip: it needs SymPy to be of use)

PHI = np.linspace(-2.0, 13.0, 301)


@pytest.mark.parametrize(
    ("cranks", "strokes", "acting"),
    [(1, 2, "single"), (2, 2, "single"), (3, 4, "single"), (4, 4, "single"), (6, 2, "double"), (5, 4, "double")],
)
def test_the_expressions_give_the_kernels_numbers(cranks, strokes, acting):
    found = symbolic.gravity(cranks=cranks, strokes=strokes, acting=acting)
    U, Q = found.lambdify()
    phases = mc.crank_phases(cranks, strokes, acting)
    assert [float(alpha) for alpha in found.phases] == pytest.approx(list(phases), rel=4e-16, abs=1e-15)
    for lam, gamma, u1, u2 in [(0.3, 1.2, 0.01, 0.02), (0.05, -0.4, 0.2, -0.05), (0.9, math.pi / 2, 1.0, 0.0)]:
        args = dict(crank_ratio=lam, inclination=gamma, u1=u1, u2=u2, phases=phases)
        potential = mc.potential_energy(PHI, **args)
        force = mc.generalized_force(PHI, **args)
        scale = cranks * (abs(u1) + abs(u2))
        np.testing.assert_allclose(U(PHI, lam, u1, u2, gamma), potential, rtol=0, atol=1e-13 * scale)
        np.testing.assert_allclose(Q(PHI, lam, u1, u2, gamma), force, rtol=0, atol=1e-13 * scale)


def test_a_layout_gives_each_cylinder_its_own_inclination():
    found = symbolic.gravity(layout="v8-cross")
    assert found.inclination is None and len(found.phases) == 8
    assert set(found.inclinations) == {sympy.pi / 4, 3 * sympy.pi / 4}
    U, Q = found.lambdify()
    engine = mc.LAYOUTS["v8-cross"].engine(crank_ratio=0.28, u1=0.03, u2=-0.01)
    np.testing.assert_allclose(U(PHI, 0.28, 0.03, -0.01), engine.potential_energy(PHI), rtol=0, atol=1e-14)
    np.testing.assert_allclose(Q(PHI, 0.28, 0.03, -0.01), engine.generalized_force(PHI), rtol=0, atol=1e-14)


def test_the_force_is_the_derivative_of_the_potential():
    # Exactly for two cranks (SymPy simplifies the difference to 0); numerically for others.
    two = symbolic.gravity(cranks=2)
    assert sympy.simplify(two.generalized_force - sympy.diff(two.potential_energy, two.phi)) == 0
    three = symbolic.gravity([0.0, 2.0, 4.5])
    assert three.phases[0] == 0 and isinstance(three.phases[1], sympy.Float)
    derivative = sympy.lambdify(
        [three.phi, three.crank_ratio, three.u1, three.u2, three.inclination],
        sympy.diff(three.potential_energy, three.phi),
    )
    _, Q = three.lambdify()
    np.testing.assert_allclose(derivative(PHI, 0.4, 0.1, 0.3, 0.7), Q(PHI, 0.4, 0.1, 0.3, 0.7), rtol=0, atol=1e-14)


def test_the_reduced_inertia_is_the_machines():
    cylinder = mc.Cylinder(
        crank_radius=0.06, rod_length=0.2, piston_mass=1.2, rod_mass=1.0, rod_cg=0.13, rod_inertia=0.004,
        crank_mass=1.5, crank_cg_radius=0.03,
    )  # fmt: skip
    phases = mc.crank_phases(3, 4)
    machine = mc.Machine([cylinder.replace(phase=float(a)) for a in phases], shaft_inertia=0.7, strokes=4)
    found = symbolic.reduced_inertia(cranks=3, strokes=4)
    J, slope = found.lambdify()
    l, z, m = cylinder.rod_length, cylinder.rod_cg, cylinder.rod_mass
    args = (
        cylinder.crank_radius,
        cylinder.crank_radius / l,
        0.7,
        cylinder.piston_mass + m * (l - z) / l,
        m * z / l,
        cylinder.rod_inertia - m * z * (l - z),
    )
    expected, expected_slope = machine.reduced_inertia(PHI)
    np.testing.assert_allclose(J(PHI, *args), expected, rtol=1e-13)
    np.testing.assert_allclose(slope(PHI, *args), expected_slope, rtol=0, atol=1e-13 * np.abs(expected_slope).max())


def test_one_way_to_give_the_crank_and_the_librarys_checks():
    with pytest.raises(mc.MechanismError, match="exactly one of phases, cranks and layout"):
        symbolic.gravity([0.0], cranks=2)
    with pytest.raises(mc.MechanismError, match="exactly one"):
        symbolic.reduced_inertia()
    with pytest.raises(mc.MechanismError, match="strokes"):
        symbolic.gravity(cranks=2, strokes=3)
    with pytest.raises(mc.MechanismError, match="at least one"):
        symbolic.gravity([])


@pytest.mark.parametrize(
    ("phases", "named"),
    [
        ([math.nan], r"phases\[0\] = nan"),
        ([0.0, math.inf], r"phases\[1\] = inf"),
        ([0.0, -math.inf], r"phases\[1\] = -inf"),
        (["a"], r"phases\[0\]"),
        ("abc", "phases"),
        ([[0.0, 1.0]], r"phases\[0\]"),
        (np.zeros((2, 2)), "phases"),
        (np.float64(0.5), "phases"),
        ({0.0: 1.0}, "phases"),
        ([1 + 2j], r"phases\[0\]"),
        ([True], r"phases\[0\]"),
        ([sympy.nan], r"phases\[0\]"),
        ([sympy.zoo], r"phases\[0\]"),
        ([sympy.I], r"phases\[0\]"),
        ([0.0] * (symbolic.MAX_UNITS + 1), "phases"),
    ],
)
def test_bad_phases_are_refused_by_name(phases, named):
    """Issue 26, item 6: NaN, inf, strings and 2-D phases gave a raw AttributeError or TypeError."""
    for function in (symbolic.gravity, symbolic.reduced_inertia):
        with pytest.raises(mc.MechanismError, match=named):
            function(phases)


def test_phases_may_be_real_sympy_expressions_with_symbols():
    alpha = sympy.Symbol("alpha", real=True)
    found = symbolic.gravity([0.0, alpha, sympy.pi / 3])
    assert found.phases == (0, alpha, sympy.pi / 3)


@pytest.mark.parametrize("cranks", [symbolic.MAX_UNITS + 1, 10**7, 10**30])
def test_more_cranks_than_the_documented_limit_are_refused(cranks):
    """Issue 26, item 6: cranks=10**7 did not finish; beyond MAX_UNITS (64) it is refused at once."""
    assert symbolic.MAX_UNITS == 64
    refused = r"cranks = \d+ is out of range; allowed: an integer 1 <= cranks <= 64"
    for function in (symbolic.gravity, symbolic.reduced_inertia):
        with pytest.raises(mc.MechanismError, match=refused):
            function(cranks=cranks)


def test_a_layout_of_more_cylinders_than_the_limit_is_refused():
    many = mc.Layout("many", "", tuple(range(0, 360, 5)), tuple((90.0,) for _ in range(0, 360, 5)))
    with pytest.raises(mc.MechanismError, match="at most 64"):
        symbolic.gravity(layout=many)
