"""What the thin bindings promise: the parallel threshold per call, exact paper
coefficients over their whole documented range, and errors that name the parameter."""

from fractions import Fraction
from math import comb

import numpy as np
import pytest

import multicrank as mc

HUGE = 2**62

DESIGNS = dict(
    crank_ratio=np.linspace(0.0, 0.9, 7)[:, None],
    inclination=np.array([0.0, 0.4, np.pi / 2]),
    u1=0.8,
    u2=-0.3,
    phases=mc.crank_phases(5, 4),
)


@pytest.mark.parametrize(
    "evaluate",
    [
        mc.potential_energy,
        mc.generalized_force,
        lambda phi, **k: mc.generalized_force(phi, method="series", **k),
        mc.force_derivative,
    ],
)
@pytest.mark.parametrize("phi", [np.linspace(-7, 7, 4001), mc.uniform_grid(4001, -7, 7)])
def test_threshold_per_call_changes_no_bit(evaluate, phi):
    serial = evaluate(phi, parallel_threshold=HUGE, **DESIGNS)
    parallel = evaluate(phi, parallel_threshold=0, **DESIGNS)
    default = evaluate(phi, **DESIGNS)
    assert serial.shape == (7, 3, 4001)
    assert serial.tobytes() == parallel.tobytes() == default.tobytes()


def test_threshold_per_call_for_extrema():
    serial = mc.energy_extrema(parallel_threshold=HUGE, **DESIGNS)
    parallel = mc.energy_extrema(parallel_threshold=0, **DESIGNS)
    for a, b in zip(serial, parallel, strict=True):
        assert a.tobytes() == b.tobytes()
    delta = mc.speed_fluctuation(parallel_threshold=0, **DESIGNS)
    assert delta.tobytes() == serial.range.tobytes()


@pytest.mark.parametrize("bad", [-1, 1.5, "0", True])
def test_bad_threshold_is_named(bad):
    with pytest.raises(mc.MechanismError, match="parallel_threshold"):
        mc.generalized_force(0.3, parallel_threshold=bad, **DESIGNS)


def test_paper_coefficients_exact_through_j_20():
    # The general coefficient of eq. (15) in Python's unbounded integers.
    for i in range(1, 23):
        for j in range(21):
            expected = (
                Fraction(0)
                if j < i - 1
                else (-1) ** (i + 1)
                * Fraction(2 * i * comb(2 * j, j) * comb(2 * j + 2, j + 1 - i), (j + 1) * 4 ** (2 * j + 1))
            )
            assert mc.paper_coefficient(i, j) == expected, (i, j)
    with pytest.raises(mc.MechanismError, match="j = 21"):
        mc.paper_coefficient(1, 21)


@pytest.mark.parametrize(
    "errors, name",
    [
        ({"u1_rel": np.nan}, "u1_rel"),
        ({"u2_rel": -0.1}, "u2_rel"),
        ({"phase": np.inf}, "phase"),
        ({"u1_rel": "a lot"}, "u1_rel"),
        ({"phase": [0.1, 0.2]}, "phase"),
    ],
)
def test_sensitivity_errors_name_the_parameter(errors, name):
    engine = mc.layout_engine("v8-cross", crank_ratio=0.3, u1=1e-3, u2=2e-4)
    with pytest.raises(mc.MechanismError, match=name):
        engine.harmonic_sensitivity(**errors)


def test_standard_gravity_is_the_conventional_value():
    assert mc.STANDARD_GRAVITY == 9.80665  # CGPM 1901, exact by definition
    u1, _ = mc.dimensionless_moments(
        crank_radius=0.1, rod_length=0.4, rod_cg=0.3, piston_mass=1.0, rod_mass=0.0, shaft_inertia=1.0, rpm=30 / np.pi
    )
    assert u1 == pytest.approx(0.1 * 9.80665, rel=1e-15)
