"""Huge requests fail fast (issue 13, item 1).

Every size a user asks for — a count, an n_max, a grid, the designs × φ of a result — is
checked against what can be allocated before anything is allocated or computed, and
refused with a MechanismError naming the parameter and the size: never a crash ("PyObject
pointer is null"), an abort ("memory allocation failed"), an integer overflow or a hang.
Sizes are drawn at random from both sides of the limit; "huge" ones exceed any machine's
address space (2·10¹⁴ doubles is 1.6 PB), so the tests do not depend on this machine.
"""

from __future__ import annotations

import sys
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import multicrank as mc
import multicrank._validation as validation

DESIGN = dict(crank_ratio=0.3, inclination=1.0, u1=1.0, u2=0.2)
ENGINE = mc.Engine(phase=[0.0, 2.0], inclination=[0.5, 1.5], crank_ratio=0.3, u1=1.0, u2=0.1)

# A size that fits (and is quick) or one beyond any machine, up to what a u64 holds.
small = st.integers(0, 2000)
huge = st.one_of(st.integers(2 * 10**14, 2**63 - 1), st.sampled_from([2**62, 2**63 - 1, 2**63, 2**64 - 2, 2**64 - 1]))

# Each request of size n: (the parameter it is asked through, the call, the result's length).
REQUESTS = {
    "lambda_coefficients": ("n_max", lambda n: mc.lambda_coefficients([0.1, 0.4], n), lambda n: 2 * (n + 1)),
    "lambda_coefficients_paper": (
        "n_max",
        lambda n: mc.lambda_coefficients(0.3, n, method="paper"),
        lambda n: n + 1,
    ),
    "crank_phases": ("cranks", lambda n: mc.crank_phases(n + 1), lambda n: n + 1),
    "fourier_coefficients": (
        "n_max",
        lambda n: np.concatenate(mc.fourier_coefficients(**DESIGN, phases=[0.0, 1.0], n_max=n)),
        lambda n: 2 * (n + 1),
    ),
    "engine_fourier": ("n_max", lambda n: np.concatenate(ENGINE.fourier_coefficients(n)), lambda n: 2 * (n + 1)),
    "engine_sensitivity": (
        "n_max",
        lambda n: ENGINE.harmonic_sensitivity(u1_rel=0.01, n_max=n + 1)["amplitude"].to_numpy(),
        lambda n: 1 + (n + 1) // 2,
    ),
    "surviving_harmonics": (
        "n_max",
        lambda n: np.array(mc.surviving_harmonics(1, n_max=n)),
        lambda n: (n >= 1) + n // 2,
    ),
    "harmonic_table": ("k_max", lambda n: mc.harmonic_table(k_max=n + 1).to_numpy(), lambda n: 7 * (n + 1)),
    "uniform_grid": ("phi", lambda n: mc.generalized_force(mc.uniform_grid(n + 1), **DESIGN), lambda n: n + 1),
    "uniform_grid_points": ("count", lambda n: np.asarray(mc.uniform_grid(n + 1)), lambda n: n + 1),
    "engine_grid": ("phi", lambda n: ENGINE.potential_energy(mc.uniform_grid(n + 1)), lambda n: n + 1),
    "sweep_phi": (
        "phi",
        lambda n: mc.sweep({"crank_ratio": [0.3], "inclination": [1.0], "u1": [1.0], "u2": [0.0]}, phi=n + 1)[
            "force_rms"
        ].to_numpy(),
        lambda n: 1,
    ),
}


def check_request(name: str, n: int) -> None:
    parameter, call, length = REQUESTS[name]
    if n <= 2000:
        assert np.size(call(n)) == length(n), name
        return
    start = time.perf_counter()
    with pytest.raises(mc.MechanismError) as error:
        call(n)
    message = str(error.value)
    # A grid of 2**64 points is refused when it is made, by its own parameter, count.
    past_native = n + 1 > 2**64 - 1 and message.startswith("count = ")
    assert message.startswith(f"{parameter} = ") or past_native, message
    # Beyond what memory allows, or (n + 1 past 2**64 − 1) beyond the native layer's counts.
    assert "more than can be allocated" in message or f"(at most {2**64 - 1})" in message, message
    # fails fast: nothing was computed (a generous bound; the refusal itself takes microseconds)
    assert time.perf_counter() - start < 5.0, (name, n)


@pytest.mark.parametrize("name", sorted(REQUESTS))
@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(n=st.one_of(small, huge))
def test_every_size_is_checked_up_front(name, n):
    check_request(name, n)


@pytest.mark.parametrize("name", sorted(REQUESTS))
def test_the_issue_sizes(name):
    """10¹² (the issue's examples: they aborted with "memory allocation failed") and the
    sizes whose +1 or product overflows 64 bits."""
    for n in (10**12, 2**64 - 2, 2**64 - 1):
        check_request(name, n)


@settings(max_examples=20, deadline=None)
@given(rows=st.integers(1, 10**7), columns=st.integers(1, 10**7), points=st.integers(1, 100))
def test_designs_times_points(rows, columns, points):
    """The result D + φ.shape is checked before the design arrays are broadcast (a design
    array of 10⁶ × 10⁶ once came back as a PyO3 panic, "PyObject pointer is null")."""
    lam = np.broadcast_to(0.3, (rows, 1))  # views: no memory for the rows themselves
    u1 = np.broadcast_to(1.0, (columns,))
    phi = np.linspace(0.0, 1.0, points)
    limit = validation.allocatable_bytes()
    if rows * columns * points * 8 > limit or rows * columns * 4 * 8 > limit:
        with pytest.raises(mc.MechanismError, match="more than can be allocated"):
            mc.generalized_force(phi, crank_ratio=lam, inclination=1.0, u1=u1, u2=0.0)
    elif rows * columns * points <= 10**5:
        q = mc.generalized_force(phi, crank_ratio=lam, inclination=1.0, u1=u1, u2=0.0)
        assert q.shape == (rows, columns, points)


def test_the_issue_design_array():
    """10⁶ designs × 10⁶ points: a clean error naming phi and both sizes."""
    with pytest.raises(mc.MechanismError, match=r"phi = 1000000 points for 1000000 designs"):
        mc.generalized_force(np.zeros(10**6), **{**DESIGN, "crank_ratio": np.full(10**6, 0.3)})


def test_design_grid_of_huge_size_with_curves_fails_before_sweeping():
    """A DesignGrid of 10¹⁵ designs with curves=True hung (the sweep ran first)."""
    axis = np.linspace(0.1, 0.4, 10**5)
    grid = mc.DesignGrid(crank_ratio=axis, inclination=np.ones(10**5), u1=np.ones(10**5), u2=0.0)
    start = time.perf_counter()
    with pytest.raises(mc.MechanismError, match=r"^curves = True for 1000000000000000 designs"):
        mc.sweep(grid, curves=True)
    assert time.perf_counter() - start < 5.0
    with pytest.raises(mc.MechanismError, match=r"^designs = 1000000000000000 rows"):
        grid.to_frame()
    with pytest.raises(mc.MechanismError, match=r"^designs = "):
        mc.design_grid(crank_ratio=axis, inclination=np.ones(10**5), u1=np.ones(10**5), u2=0.0)


def test_the_native_layer_refuses_what_it_cannot_allocate(monkeypatch):
    """With the Python checks out of the way, the extension itself refuses an output it
    cannot allocate (numpy's allocation reports failure; Rust's would abort) and every
    core table it cannot allocate, naming the parameter."""
    monkeypatch.setattr(validation, "allocatable_bytes", lambda: sys.maxsize)
    design = {k: np.full(1, v) for k, v in DESIGN.items()}
    for count in (2 * 10**14, 2**61, 2**63 - 1, 2**64 - 1):
        with pytest.raises(mc.MechanismError, match=r"^phi = "):
            mc._native.evaluate("generalized_force", (0.0, 1e-3, count), design, np.zeros(1))
        with pytest.raises(mc.MechanismError, match=r"^phi = "):
            mc.generalized_force(mc.uniform_grid(count), **DESIGN)
    designs = {k: np.full(10**6, v) for k, v in DESIGN.items()}
    with pytest.raises(mc.MechanismError, match=r"^phi = "):
        mc._native.evaluate("series", (0.0, 1e-3, 10**9), designs, np.zeros(1))
    for n_max in (10**15, 2**63, 2**64 - 1):
        with pytest.raises(mc.MechanismError, match=r"^n_max = "):
            mc.lambda_coefficients(0.3, n_max)
        with pytest.raises(mc.MechanismError, match=r"^n_max = "):
            mc.fourier_coefficients(**DESIGN, n_max=n_max)
    with pytest.raises(mc.MechanismError, match=r"^cranks = "):
        mc.crank_phases(2**62)


def test_a_small_limit_is_enforced_before_any_work(monkeypatch):
    """The check uses the machine's memory: with a (pretend) 1 kB machine, anything above
    it is refused up front, and smaller requests still run."""
    monkeypatch.setattr(validation, "allocatable_bytes", lambda: 1000)
    assert mc.crank_phases(100).shape == (100,)
    with pytest.raises(mc.MechanismError, match=r"^cranks = 126 asks for 126 values \(1008 bytes\)"):
        mc.crank_phases(126)
    with pytest.raises(mc.MechanismError, match=r"^phi = "):
        mc.generalized_force(np.zeros(200), **DESIGN)
    designs = {"crank_ratio": [0.3] * 9, "inclination": [1.0] * 9, "u1": [1.0] * 9, "u2": [0.0] * 9}
    assert len(mc.sweep(designs, phi=100, outputs=["force_rms"])) == 9
    with pytest.raises(mc.MechanismError, match=r"^curves = True for 9 designs × 100 points"):
        mc.sweep(designs, phi=100, outputs=["force_rms"], curves=True)
