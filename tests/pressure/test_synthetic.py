"""The synthetic indicator diagrams (multicrank.pressure.synthetic), on a cylinder of this
library's geometry written out here in closed form.

Checked: the ideal compressor has p_s and p_d on its suction and discharge branches, exact
polytropes between, its valve events at the volumes the polytropes give and the closed-form
indicated work; the engine cycle is an exact polytrope without heat release, agrees with the
first law integrated by an ODE solver with it, is continuous, and holds the gas-exchange
pressure where it should; every bad input is a MechanismError naming the parameter.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import multicrank as mc
from multicrank.pressure import INTERPOLATIONS, STANDARD_ATMOSPHERE, IndicatorDiagram

TAU = 2 * math.pi
REF = STANDARD_ATMOSPHERE

# A cylinder of this library: θ = 0 at outer dead centre, where the volume is smallest.
R, LAM, BORE, CLEARANCE = 0.05, 0.25, 0.08, 2.5e-5
AREA = math.pi * BORE**2 / 4


def volume(theta):
    theta = np.asarray(theta, dtype=float)
    return CLEARANCE + AREA * R * (1 - np.cos(theta) + (1 - np.sqrt(1 - LAM**2 * np.sin(theta) ** 2)) / LAM)


def volume_rate(theta):
    """dV/dθ [m³/rad] of `volume`, in closed form."""
    s, c = np.sin(theta), np.cos(theta)
    return AREA * R * (s + LAM * s * c / np.sqrt(1 - LAM**2 * s**2))


V_MIN, V_MAX = CLEARANCE, CLEARANCE + 2 * AREA * R


def crossing(target, lo, hi):
    """θ in [lo, hi] with volume(θ) = target (volume monotone there), by bisection."""
    f_lo = volume(lo) - target
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if (volume(mid) - target) * f_lo > 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


# -- the ideal compressor -----------------------------------------------------------------------

P_S, P_D, N = 1.0e5, 6.0e5, 1.3


def compressor(**keywords):
    options = {"suction_pressure": P_S, "discharge_pressure": P_D, "polytropic_exponent": N}
    return IndicatorDiagram.compressor(volume, **{**options, **keywords})


def test_compressor_branches_in_closed_form():
    diagram = compressor()
    theta, p = diagram.angle, diagram.pressure + REF  # absolute
    v = volume(theta)
    v4 = V_MIN * (P_D / P_S) ** (1 / N)  # suction opens
    v2 = V_MAX * (P_S / P_D) ** (1 / N)  # discharge opens
    theta4, theta2 = crossing(v4, 0.0, math.pi), crossing(v2, math.pi, TAU)
    # The valve events are nodes of the table (kinks of the diagram).
    assert np.min(np.abs(theta - theta4)) < 1e-9 and np.min(np.abs(theta - theta2)) < 1e-9
    # θ = 0 is outer dead centre, the smallest volume: the end of discharge.
    assert diagram(0.0) == P_D - REF and diagram(math.pi) == P_S - REF and diagram(TAU) == P_D - REF
    reexpansion = theta < theta4 - 1e-9
    suction = (theta >= theta4 - 1e-9) & (theta <= math.pi)
    compression = (theta >= math.pi) & (theta <= theta2 + 1e-9)
    discharge = theta >= theta2 - 1e-9
    assert reexpansion.sum() > 50 and suction.sum() > 100 and compression.sum() > 100 and discharge.sum() > 20
    np.testing.assert_allclose(p[suction], P_S, rtol=1e-15)
    np.testing.assert_allclose(p[discharge], P_D, rtol=1e-15)
    np.testing.assert_allclose(p[compression] * v[compression] ** N, P_S * V_MAX**N, rtol=1e-9)
    np.testing.assert_allclose(p[reexpansion] * v[reexpansion] ** N, P_D * V_MIN**N, rtol=1e-9)


@pytest.mark.parametrize("kind", INTERPOLATIONS)
def test_compressor_indicated_work_is_the_ideal_work(kind):
    """W = n/(n−1)·p_s·(V_1 − V_4)·[(p_d/p_s)^((n−1)/n) − 1] in absolute pressures, taken by the
    gas (∮p dV < 0); gauge pressures give the same loop integral."""
    v4 = V_MIN * (P_D / P_S) ** (1 / N)
    ideal = N / (N - 1) * P_S * (V_MAX - v4) * ((P_D / P_S) ** ((N - 1) / N) - 1)
    # The table is exact at its nodes; what is left is the interpolation between them, O(h²).
    coarse = compressor(kind=kind)
    assert coarse.indicated_work(volume) == pytest.approx(-ideal, rel=5e-5)
    fine = compressor(kind=kind, points=2881)
    assert fine.indicated_work(volume) == pytest.approx(-ideal, rel=5e-6)


def test_compressor_gauge_input_is_the_same_cycle():
    absolute = compressor()
    gauge = compressor(suction_pressure=P_S - REF, discharge_pressure=P_D - REF, absolute=False)
    np.testing.assert_allclose(gauge.pressure, absolute.pressure, rtol=0, atol=1e-9)
    other = compressor(reference_pressure=0.0)  # a crankcase in vacuum: gauge = absolute
    np.testing.assert_allclose(other.pressure, absolute.pressure + REF, rtol=1e-15)


def test_compressor_events_follow_the_volume_not_the_angle():
    """With V smallest at θ = π instead of 0, the whole cycle moves by π."""
    shifted = IndicatorDiagram.compressor(
        lambda t: volume(np.asarray(t) + math.pi), suction_pressure=P_S, discharge_pressure=P_D, polytropic_exponent=N
    )
    plain = compressor()
    assert shifted(math.pi) == P_D - REF and shifted(0.0) == P_S - REF
    theta4 = crossing(V_MIN * (P_D / P_S) ** (1 / N), 0.0, math.pi)
    assert np.min(np.abs(shifted.breakpoints - (theta4 + math.pi))) < 1e-9
    assert shifted.indicated_work(lambda t: volume(np.asarray(t) + math.pi)) == pytest.approx(
        plain.indicated_work(volume), rel=1e-6
    )


def test_compressor_four_stroke_cycle_repeats_each_revolution():
    diagram = compressor(cycle=2 * TAU, points=1441)
    theta = np.linspace(0, TAU, 200)
    np.testing.assert_allclose(diagram(theta + TAU), diagram(theta), rtol=0, atol=1e-6 * P_D)
    assert diagram.indicated_work(volume) == pytest.approx(2 * compressor().indicated_work(volume), rel=1e-5)


def test_compressor_bad_input():
    with pytest.raises(mc.MechanismError, match="clearance is too large"):
        compressor(discharge_pressure=P_S * 400)
    with pytest.raises(mc.MechanismError, match=r"discharge_pressure = .* must exceed suction_pressure"):
        compressor(discharge_pressure=P_S)
    with pytest.raises(mc.MechanismError, match=r"suction_pressure .* above vacuum"):
        compressor(suction_pressure=-2e5, absolute=False)
    with pytest.raises(mc.MechanismError, match="polytropic_exponent"):
        compressor(polytropic_exponent=0.0)
    with pytest.raises(mc.MechanismError, match="points"):
        compressor(points=3)
    with pytest.raises(mc.MechanismError, match="volume must be a callable"):
        IndicatorDiagram.compressor(2e-4, suction_pressure=P_S, discharge_pressure=P_D)
    with pytest.raises(mc.MechanismError, match=r"volume\(θ\) must be finite and positive"):
        IndicatorDiagram.compressor(lambda t: volume(t) - 1e-4, suction_pressure=P_S, discharge_pressure=P_D)
    with pytest.raises(mc.MechanismError, match="constant"):
        IndicatorDiagram.compressor(lambda t: np.full(np.shape(t), 1e-4), suction_pressure=P_S, discharge_pressure=P_D)
    with pytest.raises(mc.MechanismError, match=r"volume\(θ\) must return an array of θ's shape"):
        IndicatorDiagram.compressor(lambda t: np.ones(3), suction_pressure=P_S, discharge_pressure=P_D)


# -- the engine ---------------------------------------------------------------------------------

P_IN = 1.0e5


def engine(**keywords):
    return IndicatorDiagram.engine(volume, **{"intake_pressure": P_IN, "heat_release": 800.0, **keywords})


def relative_to_firing(theta, cycle):
    """θ as an angle relative to the firing dead centre, in [−Φ/2, Φ/2)."""
    return np.remainder(np.asarray(theta) + cycle / 2, cycle) - cycle / 2


@pytest.mark.parametrize("cycle", [TAU, 2 * TAU])
def test_motored_engine_is_a_pure_polytrope(cycle):
    kappa = 1.32
    diagram = engine(cycle=cycle, heat_release=0.0, compression_exponent=kappa, expansion_exponent=kappa, kind="linear")
    theta, p = diagram.angle, diagram.pressure + REF
    t = relative_to_firing(theta, cycle)
    closed = (t >= -math.pi) & (t <= math.pi - math.radians(40.0))  # intake closing … exhaust opening
    invariant = p[closed] * volume(theta[closed]) ** kappa
    np.testing.assert_allclose(invariant, P_IN * V_MAX**kappa, rtol=1e-9)
    # Back to the start on expansion: the same pressure at the same volume either side of the firing dead centre.
    assert diagram(math.radians(100.0)) == pytest.approx(diagram(cycle - math.radians(100.0)), rel=1e-9)
    assert diagram(0.0) == pytest.approx(P_IN * (V_MAX / V_MIN) ** kappa - REF, rel=1e-12)


def test_motored_engine_with_two_exponents():
    diagram = engine(heat_release=0.0, compression_exponent=1.36, expansion_exponent=1.28)
    theta, p = diagram.angle, diagram.pressure + REF
    t = relative_to_firing(theta, 2 * TAU)
    peak = P_IN * (V_MAX / V_MIN) ** 1.36
    compression = (t >= -math.pi) & (t <= 0)
    expansion = (t >= 0) & (t <= math.pi - math.radians(40.0))
    np.testing.assert_allclose(p[compression] * volume(theta[compression]) ** 1.36, P_IN * V_MAX**1.36, rtol=1e-9)
    np.testing.assert_allclose(p[expansion] * volume(theta[expansion]) ** 1.28, peak * V_MIN**1.28, rtol=1e-9)


def wiebe_rate(t, heat, start, duration, a=5.0, m=2.0):
    u = (t - start) / duration
    if u < 0 or u > 1:
        return 0.0
    return heat * a * (m + 1) / duration * u**m * math.exp(-a * u ** (m + 1))


@pytest.mark.parametrize("cycle", [TAU, 2 * TAU])
def test_engine_follows_the_first_law(cycle):
    """dp/dθ = (κ−1)/V·dQ/dθ − κ p/V·dV/dθ, integrated by an ODE solver from intake closing."""
    from scipy.integrate import solve_ivp

    start, duration, heat, closing = math.radians(-12.0), math.radians(55.0), 900.0, math.radians(30.0)
    diagram = engine(
        cycle=cycle, heat_release=heat, start_of_combustion=start, combustion_duration=duration, intake_closing=closing
    )

    def first_law(kappa):
        def rate(t, p):
            v = volume(t)
            return (kappa - 1) / v * wiebe_rate(t, heat, start, duration) - kappa * p / v * volume_rate(t)

        return rate

    t = relative_to_firing(diagram.angle, cycle)
    t_close, t_open = -math.pi + closing, math.pi - math.radians(40.0)
    p, lo = P_IN, t_close
    for hi, kappa in ((start, 1.35), (0.0, 1.35), (start + duration, 1.3), (t_open, 1.3)):
        node = np.argmin(np.abs(t - hi))
        # The events are nodes (the dead centres, found numerically, to ~1e-10 rad).
        assert abs(t[node] - hi) < 1e-9
        p = solve_ivp(first_law(kappa), (lo, t[node]), [p], method="DOP853", rtol=1e-12, atol=1e-6).y[0, -1]
        assert diagram.pressure[node] + REF == pytest.approx(p, rel=1e-8)
        lo = t[node]


@pytest.mark.parametrize("cycle", [TAU, 2 * TAU])
def test_fired_engine_peaks_after_ignition_and_does_work(cycle):
    start, heat = math.radians(-8.0), 4000.0
    fired = engine(cycle=cycle, start_of_combustion=start, heat_release=heat)
    motored = engine(cycle=cycle, heat_release=0.0)
    peak_at = relative_to_firing(fired.angle[np.argmax(fired.pressure)], cycle)
    assert start < peak_at < start + math.radians(60.0)
    assert np.max(fired.pressure) > 2 * np.max(motored.pressure)
    # The heat only adds pressure, and only from the start of combustion on.
    t = relative_to_firing(fired.angle, cycle)
    before, burning = t <= start, (t > start) & (t < math.pi - math.radians(40.0))
    np.testing.assert_array_equal(fired.pressure[before], motored.pressure[before])
    assert np.all(fired.pressure[burning] >= motored.pressure[burning])
    assert np.all(fired.pressure[burning & (t > start + 0.05)] > motored.pressure[burning & (t > start + 0.05)])
    work = fired.indicated_work(volume)
    # Positive, less than the heat released (the exhaust takes the rest), and not negligible.
    assert 0.2 * heat < work < heat * (1 - math.exp(-5.0))
    # Motored with equal exponents, the blowdown loses a little of the compression work.
    assert engine(cycle=cycle, heat_release=0.0, expansion_exponent=1.35).indicated_work(volume) < 0


@pytest.mark.parametrize("cycle", [TAU, 2 * TAU])
@pytest.mark.parametrize("synthetic", ["engine", "compressor"])
def test_synthetic_cycles_are_continuous(cycle, synthetic):
    """The largest step between neighbouring table points halves with the step: no jump anywhere."""

    def largest_step(points):
        if synthetic == "engine":
            diagram = engine(cycle=cycle, points=points, intake_closing=math.radians(35.0))
        else:
            diagram = compressor(cycle=cycle, points=points)
        return np.max(np.abs(np.diff(diagram.pressure))), np.max(np.abs(diagram.pressure))

    coarse, scale = largest_step(721)
    fine, _ = largest_step(1441)
    assert fine < 0.6 * coarse and coarse < 0.05 * scale


def test_four_stroke_gas_exchange_is_at_constant_pressure():
    closing = math.radians(30.0)
    diagram = engine(intake_closing=closing, intake_pressure=1.4e5)
    theta = diagram.angle
    exchange = (theta >= math.pi) & (theta <= 3 * math.pi + closing)
    assert exchange.sum() > 700
    assert np.all(diagram.pressure[exchange] == 1.4e5 - REF)
    between = np.linspace(math.pi, 3 * math.pi + closing, 1001)
    np.testing.assert_allclose(diagram(between), 1.4e5 - REF, rtol=1e-12)
    # Outside, the cylinder is closed: the pressure moves.
    assert diagram(3 * math.pi + closing + 0.2) > 1.4e5 - REF
    assert diagram(math.pi - 0.1) > 1.4e5 - REF


def test_two_stroke_scavenging_is_at_constant_pressure():
    closing = math.radians(45.0)
    diagram = engine(cycle=TAU, intake_closing=closing, points=721)
    theta = diagram.angle
    exchange = (theta >= math.pi) & (theta <= math.pi + closing)
    assert exchange.sum() > 80
    assert np.all(diagram.pressure[exchange] == P_IN - REF)


def test_engine_gauge_input_and_reference():
    absolute = engine()
    gauge = engine(intake_pressure=P_IN - REF, absolute=False)
    np.testing.assert_allclose(gauge.pressure, absolute.pressure, rtol=0, atol=1e-6)


@pytest.mark.parametrize(
    ("keywords", "match"),
    [
        ({"start_of_combustion": -math.radians(200.0)}, "start_of_combustion = .* out of range"),
        ({"combustion_duration": math.radians(150.0)}, "combustion_duration = .* out of range"),
        ({"combustion_duration": 0.0}, "combustion_duration"),
        ({"compression_exponent": 1.0}, "compression_exponent"),
        ({"expansion_exponent": np.nan}, "expansion_exponent"),
        ({"heat_release": -1.0}, "heat_release"),
        ({"wiebe_a": 0.0}, "wiebe_a"),
        ({"wiebe_m": -1.0}, "wiebe_m"),
        ({"exhaust_opening": 0.0}, "exhaust_opening"),
        ({"exhaust_opening": 4.0}, "exhaust_opening"),
        ({"intake_closing": -0.1}, "intake_closing"),
        ({"intake_closing": math.pi}, "intake_closing"),
        ({"intake_pressure": 0.0}, "intake_pressure"),
        ({"cycle": 2}, "cycle = 2.0"),
        ({"absolute": 1}, "absolute must be True or False"),
    ],
)
def test_engine_bad_input(keywords, match):
    with pytest.raises(mc.MechanismError, match=match):
        engine(**keywords)


def test_engine_needs_the_smallest_volume_at_zero():
    with pytest.raises(mc.MechanismError, match="smallest at θ = 0"):
        IndicatorDiagram.engine(lambda t: volume(np.asarray(t) + 0.5), intake_pressure=P_IN, heat_release=0.0)
    with pytest.raises(mc.MechanismError, match="one minimum and one maximum per revolution"):
        IndicatorDiagram.engine(lambda t: volume(2 * np.asarray(t)), intake_pressure=P_IN, heat_release=0.0)
