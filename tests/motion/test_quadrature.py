"""The Gauss–Legendre panels of the torque orders (motion/_quadrature.py): cut at the torques' kinks."""

from __future__ import annotations

import math

import numpy as np
import pytest

import multicrank as mc
from multicrank.motion._quadrature import CycleQuadrature, cycle_breaks


def test_a_kink_on_a_panel_edge_is_integrated_exactly():
    # |φ − c| has a kink at c: split there, the panel rule is exact; not split, it is not.
    kink = 2.0
    exact = (kink**2 + (2 * math.pi - kink) ** 2) / 2
    split = CycleQuadrature(np.array([0.0, kink, 2 * math.pi]))
    whole = CycleQuadrature(np.array([0.0, 2 * math.pi]), max_width=2 * math.pi)
    assert split.integral(np.abs(split.phi - kink)) == pytest.approx(exact, rel=1e-14)
    assert abs(whole.integral(np.abs(whole.phi - kink)) - exact) > 1e-6


def _cylinder(**changes):
    base = dict(crank_radius=0.1, rod_length=0.35, piston_mass=2.0, rod_mass=1.0, rod_cg=0.25, bore=0.09)
    return mc.Cylinder(**{**base, **changes})


def test_breaks_are_the_gassed_units_dead_centres_and_table_angles():
    table = mc.IndicatorDiagram([0.0, 1.0, 3.0, 2 * math.pi], [1e5, 3e5, 2e5, 1e5], cycle=2 * math.pi, kind="linear")
    machine = mc.Machine(
        [_cylinder(phase=0.5, pressure=table), _cylinder(phase=1.0, bore=0.0), _cylinder(phase=2.5)],
        shaft_inertia=1.0,
    )
    # Dead centres at φ = kπ − α; table angles at φ = θ − α (mod Φ); the second unit has no
    # bore and the third no pressure, so neither adds a break.
    dead_centres = [math.pi - 0.5, 2 * math.pi - 0.5]
    table_angles = [1.0 - 0.5, 3.0 - 0.5]
    expected = np.sort([0.0, *dead_centres, *table_angles, 2 * math.pi])
    np.testing.assert_allclose(cycle_breaks(machine), expected, atol=1e-15)
