"""The Rust kernels against the plain-numpy reference, under hypothesis."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import multicrank as mc
import multicrank.reference as ref

QUANTITIES = ("potential_energy", "generalized_force", "force_derivative")

finite = st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False)
angles = st.floats(-50.0, 50.0, allow_nan=False, allow_infinity=False)


@st.composite
def machines(draw):
    k = draw(st.integers(1, 12))
    if draw(st.booleans()):
        phases = mc.crank_phases(k, draw(st.sampled_from([2, 4])), draw(st.sampled_from(["single", "double"])))
    else:
        phases = np.array(draw(st.lists(angles, min_size=1, max_size=12)))
    return dict(
        crank_ratio=draw(st.floats(0.0, 0.95)),
        inclination=draw(st.floats(-10.0, 10.0)),
        u1=draw(finite),
        u2=draw(finite),
        phases=phases,
    )


def natural_scale(design) -> float:
    """|U1| + |U2| per crank, times the rod-angle amplification 1/(1 − λ²)^{3/2}."""
    k = len(design["phases"])
    lam = design["crank_ratio"]
    return k * (abs(design["u1"]) + abs(design["u2"]) + 1e-300) / (1 - lam * lam) ** 1.5


@settings(max_examples=300, deadline=None)
@given(machine=machines(), phi=hnp.arrays(np.float64, st.integers(0, 300), elements=angles))
def test_kernels_match_reference(machine, phi):
    scale = natural_scale(machine)
    for quantity in QUANTITIES:
        fast = getattr(mc, quantity)(phi, **machine)
        slow = getattr(ref, quantity)(phi, **machine)
        assert fast.shape == slow.shape == phi.shape
        # The reference rounds ψ = φ + α before its sin/cos; the kernel rotates instead.
        # That argument rounding (|ψ| ε) times the slope bounds the difference.
        tol = 1e-14 * scale * (1 + np.max(np.abs(phi), initial=0.0) + np.max(np.abs(machine["phases"])))
        np.testing.assert_allclose(fast, slow, rtol=0, atol=tol)


@settings(max_examples=60, deadline=None)
@given(
    lam=hnp.arrays(np.float64, st.tuples(st.integers(1, 3), st.just(1)), elements=st.floats(0, 0.95)),
    gamma=hnp.arrays(np.float64, st.integers(1, 4), elements=st.floats(-4, 4)),
    u1=finite,
    u2=finite,
)
def test_broadcast_designs_match_reference(lam, gamma, u1, u2):
    phi = np.linspace(-2 * np.pi, 2 * np.pi, 37).reshape(37, 1)
    phases = mc.crank_phases(5, 4)
    kw = dict(crank_ratio=lam, inclination=gamma, u1=u1, u2=u2, phases=phases)
    fast = mc.generalized_force(phi, **kw)
    slow = ref.generalized_force(phi, **kw)
    assert fast.shape == np.broadcast_shapes(lam.shape, gamma.shape) + phi.shape
    scale = 5 * (abs(u1) + abs(u2) + 1e-300) / (1 - 0.95**2) ** 1.5
    np.testing.assert_allclose(fast, slow, rtol=0, atol=1e-13 * scale)
