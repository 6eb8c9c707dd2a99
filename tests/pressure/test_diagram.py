"""Indicator diagrams (multicrank.pressure): tables and CSV files (the synthetic cycles are
test_synthetic's).

Checked: the interpolants pass through the table and are periodic (value, and slope where
they are C¹), θ wraps and keeps its shape; every bad input is a MechanismError naming the
parameter (or the file, line and column); CSV files round-trip in every unit, absolute
pressures become gauge exactly; pressures below vacuum are refused and pressures absurd for
their unit warn; a machine scaled down by 10⁻¹⁰⁰ runs as it does.
"""

from __future__ import annotations

import math
import pickle
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import multicrank as mc
from multicrank.pressure import (
    EXAMPLE_COMPRESSOR_CSV,
    INTERPOLATIONS,
    PRESSURE_UNITS,
    STANDARD_ATMOSPHERE,
    IndicatorDiagram,
)

TAU = 2 * math.pi
REF = STANDARD_ATMOSPHERE


def smooth_table(points=73, cycle=TAU, start=0.0):
    angle = np.linspace(start, start + cycle, points)
    pressure = 1e5 + 3e5 * np.cos(TAU / cycle * angle) + 1e5 * np.sin(2 * TAU / cycle * angle)
    pressure[-1] = pressure[0]
    return angle, pressure


# -- interpolation ------------------------------------------------------------------------------


@pytest.mark.parametrize("kind", INTERPOLATIONS)
@pytest.mark.parametrize("cycle", [TAU, 2 * TAU])
def test_interpolant_passes_through_the_nodes_and_wraps(kind, cycle):
    angle, pressure = smooth_table(points=37, cycle=cycle)
    diagram = IndicatorDiagram(angle, pressure, cycle=cycle, kind=kind)
    assert diagram.kind == kind and diagram.cycle == cycle and diagram.strokes == (2 if cycle == TAU else 4)
    np.testing.assert_allclose(diagram(angle), pressure, rtol=0, atol=1e-9 * 4e5)
    # θ outside [0, Φ) wraps: a whole number of cycles away gives the same pressure.
    theta = np.linspace(-0.3, cycle + 0.3, 101)
    for turns in (-3, -1, 1, 2, 7):
        np.testing.assert_allclose(diagram(theta + turns * cycle), diagram(theta), rtol=0, atol=1e-6)
    # Between the nodes it is an interpolant of the smooth function the table samples.
    exact = 1e5 + 3e5 * np.cos(TAU / cycle * theta) + 1e5 * np.sin(2 * TAU / cycle * theta)
    tolerance = {"periodic-cubic": 1e-3, "pchip": 2e-2, "linear": 4e-2}[kind]
    np.testing.assert_allclose(diagram(theta), exact, rtol=0, atol=tolerance * 4e5)


@pytest.mark.parametrize("kind", ["periodic-cubic", "pchip"])
def test_slope_is_periodic_for_the_smooth_kinds(kind):
    angle, pressure = smooth_table(points=25)
    diagram = IndicatorDiagram(angle, pressure, cycle=TAU, kind=kind)
    h = 1e-6
    left = (diagram(TAU - h) - diagram(TAU - 2 * h)) / h  # one-sided, inside the last interval
    right = (diagram(2 * h) - diagram(h)) / h  # inside the first
    assert math.isclose(left, right, rel_tol=1e-4, abs_tol=1.0)
    assert math.isclose(diagram.derivative(0.0), diagram.derivative(TAU - 1e-12), rel_tol=1e-6, abs_tol=1e-3)
    np.testing.assert_allclose(diagram.derivative(0.0), right, rtol=1e-4)


def test_linear_is_piecewise_linear_and_not_smoothed():
    angle = np.array([0.0, 1.0, 2.0, 4.0, TAU])
    pressure = np.array([0.0, 10.0, -5.0, 3.0, 0.0])
    diagram = IndicatorDiagram(angle, pressure, cycle=TAU, kind="linear")
    assert diagram(0.5) == pytest.approx(5.0) and diagram(3.0) == pytest.approx(-1.0)
    assert diagram(TAU + 0.5) == pytest.approx(5.0)
    assert diagram.derivative(1.5) == pytest.approx(-15.0)


def test_shapes_are_kept():
    diagram = IndicatorDiagram(*smooth_table(), cycle=TAU)
    scalar = diagram(0.3)
    assert isinstance(scalar, np.float64)
    assert diagram(np.zeros((3, 4))).shape == (3, 4)
    assert diagram(np.zeros((2, 0, 5))).shape == (2, 0, 5)
    assert diagram([0.1, 0.2]).shape == (2,)
    assert isinstance(diagram.derivative(0.3), np.float64)
    assert np.isnan(diagram(np.nan)) and np.isnan(diagram(np.inf))


def test_table_may_start_anywhere():
    """A four-stroke table over [−360°, 360°] is the same diagram as over [0°, 720°]."""
    shifted = IndicatorDiagram(*smooth_table(points=145, cycle=2 * TAU, start=-TAU), cycle=2 * TAU)
    plain = IndicatorDiagram(*smooth_table(points=145, cycle=2 * TAU), cycle=2 * TAU)
    theta = np.linspace(0, 2 * TAU, 333)
    np.testing.assert_allclose(shifted(theta), plain(theta), rtol=0, atol=1e-6)
    assert shifted.breakpoints[0] == -TAU and shifted.breakpoints[-1] == TAU


def test_attributes_are_the_table_read_only():
    angle, pressure = smooth_table()
    diagram = IndicatorDiagram(angle, pressure, cycle=TAU)
    np.testing.assert_array_equal(diagram.angle, angle)
    np.testing.assert_array_equal(diagram.pressure, pressure)
    np.testing.assert_array_equal(diagram.breakpoints, angle)
    with pytest.raises(ValueError, match="read-only"):
        diagram.pressure[0] = 1.0
    angle[3] = 99.0  # the diagram holds its own copy
    assert diagram.angle[3] != 99.0
    assert "73 points" in repr(diagram) and "two-stroke" in repr(diagram) and "gauge" in repr(diagram)


def test_closure_within_tolerance_is_made_exact():
    angle, pressure = smooth_table()
    pressure[-1] *= 1 + 1e-8
    diagram = IndicatorDiagram(angle, pressure, cycle=TAU)
    assert diagram.pressure[-1] == diagram.pressure[0]
    angle[-1] += 1e-7  # within the span tolerance
    assert IndicatorDiagram(angle, pressure, cycle=TAU).angle[-1] == TAU


@pytest.mark.parametrize("kind", INTERPOLATIONS)
def test_subnormal_pressures_are_kept_without_overflow(kind):
    # The table hypothesis found: zeros and one subnormal value. PCHIP's slopes divide by the
    # differences (1/2.2e-309 overflows); warnings are errors here. Such a pressure is not 0
    # (1e-30 Pa and below once were, which dropped the gas of a machine scaled by 1e-100): it
    # is interpolated as the same table in bar is, to a subnormal double's rounding.
    angle = np.array([0.0, 1.0, 2.5, 4.0, TAU])
    diagram = IndicatorDiagram(angle, [0.0, 2.2e-309, 0.0, 0.0, 0.0], cycle=TAU, kind=kind)
    in_bar = IndicatorDiagram(angle, [0.0, 2.2, 0.0, 0.0, 0.0], cycle=TAU, kind=kind)
    theta = np.linspace(-TAU, 2 * TAU, 1001)
    assert diagram.pressure[1] == 2.2e-309 and diagram(angle[1]) == 2.2e-309
    np.testing.assert_allclose(diagram(theta), in_bar(theta) * 1e-309, rtol=0, atol=1e-322)
    np.testing.assert_allclose(diagram.derivative(theta), in_bar.derivative(theta) * 1e-309, rtol=0, atol=1e-321)
    assert diagram.mean_pressure() == pytest.approx(in_bar.mean_pressure() * 1e-309, rel=1e-12)
    # Beside a real pressure, a subnormal value stays (to its rounding beside 1e7); PCHIP's
    # interpolant stays within the neighbouring nodes (no overshoot).
    pressure = np.array([1e7, 2.2e-309, -5e-324, 3e5, 1e7])
    diagram = IndicatorDiagram(angle, pressure, cycle=TAU, kind=kind)
    np.testing.assert_allclose(diagram(angle), pressure, rtol=1e-15, atol=1e-316)
    assert diagram(angle[1]) > 0
    if kind != "periodic-cubic":
        between = np.linspace(angle[1], angle[2], 101)
        assert np.all(np.abs(diagram(between)) <= 2.2e-309 + 1e-316)


@pytest.mark.parametrize("kind", INTERPOLATIONS)
@settings(max_examples=25, deadline=None)
@given(power=st.integers(-900, 75))
def test_a_table_times_a_power_of_two_is_the_diagram_times_it(kind, power):
    """Interpolation is homogeneous in p: the table times 2^k gives the diagram times 2^k,
    bit for bit, from 2^75 (~4e22, the table's peak near 1e30 Pa) down to 2^-900 (~1e-271),
    where every value is still a normal double. With pressures below 1e-30 Pa taken as 0, a
    table scaled down that far was the zero diagram."""
    angle, pressure = smooth_table()
    factor = 2.0**power
    diagram = IndicatorDiagram(angle, pressure, cycle=TAU, kind=kind)
    scaled = IndicatorDiagram(angle, pressure * factor, cycle=TAU, kind=kind)
    theta = np.linspace(-1.0, TAU + 1.0, 997)
    np.testing.assert_array_equal(scaled.pressure, pressure * factor)
    np.testing.assert_array_equal(scaled(theta), diagram(theta) * factor)
    np.testing.assert_array_equal(scaled.derivative(theta), diagram.derivative(theta) * factor)
    assert scaled.mean_pressure() == diagram.mean_pressure() * factor


def test_mean_pressure_and_indicated_work_in_closed_form():
    theta = np.linspace(0, TAU, 721)
    # p = 2e5 + 1e5 sin θ: the mean is 2e5; with V = V0 + A(1 − cos θ), ∮p dV = ∫ 1e5 sin θ · A sin θ dθ = 1e5·A·π.
    diagram = IndicatorDiagram(theta, 2e5 + 1e5 * np.sin(theta), cycle=TAU)
    assert diagram.mean_pressure() == pytest.approx(2e5, rel=1e-12)
    work = diagram.indicated_work(lambda t: 1e-4 + 2e-3 * (1 - np.cos(t)))
    assert work == pytest.approx(1e5 * 2e-3 * math.pi, rel=1e-9)
    # Clockwise in the p-V plane (pressure high while expanding): positive, an engine.
    linear = IndicatorDiagram(theta, 2e5 + 1e5 * np.sin(theta), cycle=TAU, kind="linear")
    assert linear.mean_pressure() == pytest.approx(2e5, rel=1e-12)
    assert linear.indicated_work(lambda t: 1e-4 + 2e-3 * (1 - np.cos(t))) == pytest.approx(
        1e5 * 2e-3 * math.pi, rel=1e-4
    )


def test_pickles():
    diagram = IndicatorDiagram(*smooth_table(), cycle=TAU, kind="pchip")
    again = pickle.loads(pickle.dumps(diagram))
    theta = np.linspace(0, TAU, 50)
    np.testing.assert_array_equal(again(theta), diagram(theta))


def test_scipy_is_imported_only_when_used():
    code = "import sys, multicrank.pressure; assert 'scipy' not in sys.modules, 'scipy imported eagerly'"
    subprocess.run([sys.executable, "-c", code], check=True)


# -- bad tables --------------------------------------------------------------------------------


def bad(match, *args, **kwargs):
    with pytest.raises(mc.MechanismError, match=match) as info:
        IndicatorDiagram(*args, **kwargs)
    assert isinstance(info.value, ValueError)
    return str(info.value)


def test_closure_failure_explains_the_mismatch():
    angle, pressure = smooth_table()
    pressure[-1] += 1e3
    message = bad("does not close", angle, pressure, cycle=TAU)
    assert "closure_tolerance" in message and "1000 Pa" in message
    IndicatorDiagram(angle, pressure, cycle=TAU, closure_tolerance=1e-2)  # accepted when asked


def test_tables_that_do_not_cover_the_cycle():
    angle, pressure = smooth_table()
    message = bad("cover exactly one cycle", angle[:-1], pressure[:-1], cycle=TAU)  # 0 … 355°, no closing point
    assert "355°" in message and "repeated at the end" in message
    bad("cover exactly one cycle", angle, pressure, cycle=2 * TAU)  # a two-stroke table as four-stroke
    bad("cover exactly one cycle", angle * 1.01, pressure, cycle=TAU)


@pytest.mark.parametrize("name", ["angle", "pressure"])
@pytest.mark.parametrize("value", [np.nan, np.inf])
def test_non_finite_values_name_the_array(name, value):
    angle, pressure = smooth_table()
    table = {"angle": angle, "pressure": pressure}
    table[name][5] = value
    bad(rf"{name}\[5\] = {value} is not finite", table["angle"], table["pressure"], cycle=TAU)


def test_non_increasing_angles():
    angle, pressure = smooth_table()
    angle[10] = angle[9]
    bad(r"angle must increase strictly: angle\[10\]", angle, pressure, cycle=TAU)
    bad("angle must increase strictly", angle[::-1], pressure, cycle=TAU)


@pytest.mark.parametrize(
    ("keywords", "match"),
    [
        ({"cycle": 4}, r"cycle = 4.0 is not allowed.*4\*math.pi"),
        ({"cycle": 3.0}, "cycle = 3.0 is not allowed"),
        ({"cycle": "2pi"}, "cycle must be a real number"),
        ({"cycle": TAU, "kind": "cubic"}, "kind = 'cubic' is not allowed"),
        ({"cycle": TAU, "closure_tolerance": -1}, "closure_tolerance"),
    ],
)
def test_bad_options(keywords, match):
    bad(match, *smooth_table(), **keywords)


def test_bad_shapes_and_lengths():
    angle, pressure = smooth_table()
    bad("angle must be a 1-D array", angle[None, :], pressure, cycle=TAU)
    bad("pressure must be a 1-D array", angle, pressure[None, :], cycle=TAU)
    bad("same length", angle, pressure[:-1], cycle=TAU)
    bad("at least 4 points", [0.0, 1.0, TAU], [1.0, 2.0, 1.0], cycle=TAU)
    bad("pressure must be a real number", angle, ["x"] * angle.size, cycle=TAU)
    with pytest.raises(mc.MechanismError, match="theta"):
        IndicatorDiagram(angle, pressure, cycle=TAU)("zero")


def test_bad_volume_for_the_work():
    diagram = IndicatorDiagram(*smooth_table(), cycle=TAU)
    with pytest.raises(mc.MechanismError, match="volume must be a callable"):
        diagram.indicated_work(1e-3)
    with pytest.raises(mc.MechanismError, match="finite and positive"):
        diagram.indicated_work(lambda t: np.cos(t))
    with pytest.raises(mc.MechanismError, match="periodic"):
        diagram.indicated_work(lambda t: 1.0 + t)


# -- CSV files ---------------------------------------------------------------------------------


def write(path, text):
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize("unit", sorted(PRESSURE_UNITS))
@pytest.mark.parametrize("angle_unit", ["deg", "rad"])
def test_csv_round_trip_in_every_unit(tmp_path, unit, angle_unit):
    angle, pressure = smooth_table()
    factor = {"Pa": 1.0, "kPa": 1e3, "bar": 1e5, "MPa": 1e6, "psi": 4.4482216152605 / 0.0254**2}[unit]
    angles = np.degrees(angle) if angle_unit == "deg" else angle
    rows = "".join(f"{float(a)!r},{float(p / factor)!r}\n" for a, p in zip(angles, pressure, strict=True))
    path = write(tmp_path / "table.csv", f"angle,pressure\n{rows}")
    diagram = IndicatorDiagram.from_csv(path, angle_unit=angle_unit, pressure_unit=unit)
    assert diagram.cycle == TAU  # inferred
    np.testing.assert_allclose(diagram.angle, angle, rtol=1e-15, atol=1e-15)
    np.testing.assert_allclose(diagram.pressure, pressure, rtol=1e-14, atol=1e-9)


def test_psi_is_the_exact_pound_force_per_square_inch():
    assert PRESSURE_UNITS["psi"] == pytest.approx(0.45359237 * 9.80665 / 0.0254**2, rel=1e-15)
    assert PRESSURE_UNITS["psi"] == pytest.approx(6894.757293168361, rel=1e-15)


@pytest.mark.parametrize("reference", [STANDARD_ATMOSPHERE, 98_000.0, 0.0])
def test_absolute_pressures_become_gauge_exactly(tmp_path, reference):
    # Absolute kPa values; gauge = 1000·value − reference exactly (all values are exact in binary).
    absolute_kpa = [300.0, 150.5, 100.0, 96.25, 300.0]
    degrees = [0.0, 90.0, 180.0, 270.0, 360.0]
    path = write(tmp_path / "abs.csv", "".join(f"{d},{p}\n" for d, p in zip(degrees, absolute_kpa, strict=True)))
    keywords = {} if reference == STANDARD_ATMOSPHERE else {"reference_pressure": reference}
    diagram = IndicatorDiagram.from_csv(path, pressure_unit="kPa", absolute=True, kind="linear", **keywords)
    assert diagram.pressure.tolist() == [1000.0 * p - reference for p in absolute_kpa]
    gauge = IndicatorDiagram.from_csv(path, pressure_unit="kPa", kind="linear")
    assert gauge.pressure.tolist() == [1000.0 * p for p in absolute_kpa]


def test_csv_layouts(tmp_path):
    """Comments, a named header, other columns, semicolons, tabs, white space, four-stroke."""
    degrees = np.linspace(0, 720, 9)
    bar = [1.0, 2.0, 3.0, 2.0, 1.5, 1.0, 1.2, 1.1, 1.0]
    lines = [f"{i};{d};{p}" for i, (d, p) in enumerate(zip(degrees, bar, strict=True))]
    text = "# measured nowhere\n\n# another comment\nindex;theta;p_bar\n" + "\n".join(lines) + "\n"
    path = write(tmp_path / "semicolon.csv", text)
    expected = (np.radians(degrees), np.array(bar) * 1e5)
    for diagram in (
        IndicatorDiagram.from_csv(path, pressure_unit="bar", angle_column="theta", pressure_column="p_bar"),
        IndicatorDiagram.from_csv(path, pressure_unit="bar", angle_column=1, pressure_column=2),
    ):
        assert diagram.cycle == 2 * TAU
        np.testing.assert_allclose(diagram.angle, expected[0], rtol=1e-15)
        np.testing.assert_allclose(diagram.pressure, expected[1], rtol=1e-15)
    tabs = write(tmp_path / "tabs.tsv", text.replace(";", "\t"))
    spaces = write(tmp_path / "spaces.txt", text.replace(";", "   "))
    explicit = write(tmp_path / "pipes.txt", text.replace(";", "|"))
    for p, delimiter in ((tabs, None), (spaces, None), (explicit, "|")):
        diagram = IndicatorDiagram.from_csv(
            p, pressure_unit="bar", angle_column=1, pressure_column=2, delimiter=delimiter
        )
        np.testing.assert_allclose(diagram.pressure, expected[1], rtol=1e-15)
    # The cycle may be given; a 720° table is no two-stroke one.
    IndicatorDiagram.from_csv(path, pressure_unit="bar", angle_column=1, pressure_column=2, cycle=4 * math.pi)
    with pytest.raises(mc.MechanismError, match=r"semicolon.csv: angle must cover exactly one cycle"):
        IndicatorDiagram.from_csv(path, angle_column=1, pressure_column=2, cycle=TAU)


def test_the_example_file_is_the_synthetic_compressor():
    assert EXAMPLE_COMPRESSOR_CSV.is_file()
    text = EXAMPLE_COMPRESSOR_CSV.read_text(encoding="utf-8")
    assert "SYNTHETIC" in text and "NOT measured" in text
    diagram = IndicatorDiagram.from_csv(EXAMPLE_COMPRESSOR_CSV, pressure_unit="bar", absolute=True)
    r, lam = 0.03, 0.25
    area = math.pi * 0.08**2 / 4

    def example_volume(theta):
        return 1.5e-5 + area * r * (1 - np.cos(theta) + (1 - np.sqrt(1 - lam**2 * np.sin(theta) ** 2)) / lam)

    made = IndicatorDiagram.compressor(
        example_volume, suction_pressure=1.0e5, discharge_pressure=8.0e5, polytropic_exponent=1.3, points=73
    )
    np.testing.assert_allclose(diagram.angle, made.angle, rtol=0, atol=1e-11)
    np.testing.assert_allclose(diagram.pressure, made.pressure, rtol=0, atol=1e-5)


def csv_error(tmp_path, text, match, **keywords):
    path = write(tmp_path / "bad.csv", text)
    with pytest.raises(mc.MechanismError, match=match) as info:
        IndicatorDiagram.from_csv(path, **keywords)
    assert "bad.csv" in str(info.value)


def test_csv_errors_name_file_line_and_column(tmp_path):
    good = "angle,p\n0,1\n90,2\n180,3\n270,2\n360,1\n"
    csv_error(tmp_path, good.replace("180,3", "180,three"), r"line 4, column 1 \(pressure_column\): 'three'")
    csv_error(tmp_path, good.replace("180,3", "1.8e2x,3"), r"line 4, column 0 \(angle_column\)")
    csv_error(tmp_path, good.replace("180,3", "180,nan"), r"line 4, column 1 .*not a finite number")
    csv_error(tmp_path, good.replace("180,3", "180"), r"line 4: 1 column\(s\), but pressure_column = 1")
    csv_error(tmp_path, good.replace("270,2", "170,2"), r"line 5, column 0 .*does not increase on line 4")
    csv_error(tmp_path, good, r"pressure_column = 'bar' is not in the header", pressure_column="bar")
    csv_error(tmp_path, "angle,p\n0,1\n90,2\n", "2 data row")
    csv_error(tmp_path, good.replace("360,1", "350,1"), r"cannot infer the cycle.*350°")
    csv_error(tmp_path, good.replace("360,1", "360,1.5"), "does not close")


@pytest.mark.parametrize(
    ("keywords", "match"),
    [
        ({"pressure_unit": "atm"}, "pressure_unit = 'atm' is not allowed"),
        ({"pressure_unit": "pa"}, "pressure_unit = 'pa' is not allowed"),
        ({"angle_unit": "grad"}, "angle_unit = 'grad' is not allowed"),
        ({"absolute": "yes"}, "absolute must be True or False"),
        ({"reference_pressure": np.nan}, "reference_pressure"),
        ({"angle_column": -1}, "angle_column"),
        ({"pressure_column": 0}, "angle_column and pressure_column must differ"),
        ({"delimiter": ",,"}, "delimiter"),
        ({"cycle": 5.0}, "cycle = 5.0"),
    ],
)
def test_csv_bad_options(tmp_path, keywords, match):
    path = write(tmp_path / "t.csv", "0,1\n90,2\n180,3\n270,2\n360,1\n")
    with pytest.raises(mc.MechanismError, match=match):
        IndicatorDiagram.from_csv(path, **keywords)


def test_csv_unreadable_paths(tmp_path):
    with pytest.raises(mc.MechanismError, match="is a directory"):
        IndicatorDiagram.from_csv(tmp_path)
    with pytest.raises(mc.MechanismError, match="no such file"):
        IndicatorDiagram.from_csv(tmp_path / "missing.csv")
    binary = tmp_path / "binary.csv"
    binary.write_bytes(b"\x89PNG\r\n\x1a\n\xff\xfe\x00")
    with pytest.raises(mc.MechanismError, match=r"binary\.csv' is not a UTF-8 text file"):
        IndicatorDiagram.from_csv(binary)
    with pytest.raises(mc.MechanismError, match="path must be a file path"):
        IndicatorDiagram.from_csv(3)  # type: ignore[arg-type]


# -- property -----------------------------------------------------------------------------------


@settings(max_examples=30, deadline=None)
@given(
    steps=st.lists(st.floats(0.2, 1.0), min_size=3, max_size=30),
    values=st.lists(st.floats(-1e6, 1e7), min_size=31, max_size=31),
    start=st.floats(-10.0, 10.0),
    cycle=st.sampled_from([TAU, 2 * TAU]),
    kind=st.sampled_from(INTERPOLATIONS),
)
def test_random_tables_interpolate_through_the_nodes_periodically(steps, values, start, cycle, kind):
    spacing = np.asarray(steps) / np.sum(steps) * cycle
    angle = start + np.concatenate(([0.0], np.cumsum(spacing)))
    angle[-1] = start + cycle
    pressure = np.asarray(values[: angle.size])
    pressure[-1] = pressure[0]
    diagram = IndicatorDiagram(angle, pressure, cycle=cycle, kind=kind)
    scale = 1.0 + np.max(np.abs(pressure))
    np.testing.assert_allclose(diagram(angle), pressure, rtol=0, atol=1e-9 * scale)
    for turns in (-2, 1, 3):
        np.testing.assert_allclose(diagram(angle + turns * cycle), pressure, rtol=0, atol=1e-9 * scale)
    between = 0.5 * (angle[:-1] + angle[1:])
    np.testing.assert_allclose(diagram(between + cycle), diagram(between), rtol=0, atol=1e-9 * scale)
    assert diagram(start) == pytest.approx(diagram(start + cycle), abs=1e-9 * scale)


# -- absolute pressures below vacuum, and pressures in the wrong unit (issue 26, item 6) -----------


def test_a_negative_absolute_pressure_in_a_csv_is_refused_by_line_and_column(tmp_path):
    """A table of gauge pressures read with absolute=True (or a sign error) is refused, as
    the synthetic cycles refuse a suction or intake pressure below vacuum."""
    text = "angle,p\n0,3\n90,1.5\n180,-0.2\n270,-0.4\n360,3\n"
    csv_error(
        tmp_path,
        text,
        r"bad\.csv, line 4, column 1 \(pressure_column\): '-0\.2' is a negative absolute pressure",
        pressure_unit="bar",
        absolute=True,
    )
    # as gauge pressures the same table is fine, and an absolute 0 (vacuum) is a pressure
    path = write(tmp_path / "gauge.csv", text)
    assert IndicatorDiagram.from_csv(path, pressure_unit="bar").pressure[3] == -0.4e5
    vacuum = write(tmp_path / "vacuum.csv", text.replace("-0.2", "0").replace("-0.4", "0.5"))
    diagram = IndicatorDiagram.from_csv(vacuum, pressure_unit="bar", absolute=True, kind="linear")
    assert diagram.pressure[2] == -STANDARD_ATMOSPHERE


def _table_in(tmp_path, pressures_pa, factor):
    """The smooth two-stroke table of pressures [Pa] written as numbers in a unit of ``factor`` Pa."""
    angle = np.degrees(np.linspace(0.0, TAU, 37))
    rows = "".join(f"{float(a)!r},{float(p / factor)!r}\n" for a, p in zip(angle, pressures_pa, strict=True))
    return write(tmp_path / "table.csv", "angle,p\n" + rows)


@pytest.mark.parametrize(
    ("written_in", "read_as", "likely"),
    [
        ("Pa", "bar", "Pa"),  # the case: 8·10⁵ "bar", a machine that silently stalls
        ("Pa", "MPa", "Pa"),
        ("bar", "Pa", "bar"),  # 8 "Pa": no gas at all
        ("MPa", "Pa", "MPa"),  # 0.8 "Pa"
    ],
)
def test_pressures_absurd_for_their_unit_warn_naming_the_likely_unit(tmp_path, written_in, read_as, likely):
    from multicrank.pressure import PressureUnitWarning

    assert issubclass(PressureUnitWarning, UserWarning)
    absolute = 1e5 + 3.5e5 * (1 + np.cos(np.linspace(0.0, TAU, 37)))  # 1 … 8 bar absolute
    path = _table_in(tmp_path, absolute, PRESSURE_UNITS[written_in])
    with pytest.warns(PressureUnitWarning, match=rf"did you give {likely} where {read_as} is expected\?") as caught:
        IndicatorDiagram.from_csv(path, pressure_unit=read_as, absolute=True)
    assert "table.csv" in str(caught[0].message)
    assert caught[0].filename == __file__  # it points at the caller's line
    # read in the unit it was written in, it is a plausible table and says nothing
    IndicatorDiagram.from_csv(path, pressure_unit=written_in, absolute=True)


def test_the_packages_tables_and_machines_do_not_warn():
    import warnings

    from multicrank.pressure import PressureUnitWarning

    with warnings.catch_warnings():
        warnings.simplefilter("error", PressureUnitWarning)
        IndicatorDiagram.from_csv(EXAMPLE_COMPRESSOR_CSV, pressure_unit="bar", absolute=True)
        for path in mc.presets.MACHINE_FILES.values():
            mc.Machine.from_toml(path)


# -- a machine scaled down: the motion is homogeneous in masses, inertias and pressures ------------

MASSES = ("piston_mass", "rod_mass", "rod_inertia", "crank_mass", "counterweight_mass")


def _scaled_machine(machine: mc.Machine, factor: float) -> mc.Machine:
    """Every mass, inertia and pressure of ``machine`` times ``factor`` (lengths, g and the
    speed as they are)."""

    def cylinder(c: mc.Cylinder) -> mc.Cylinder:
        changes = {name: getattr(c, name) * factor for name in MASSES}
        for end in ("pressure", "pressure_crank_end"):
            if getattr(c, end) is not None:
                changes[end] = getattr(c, end).scaled(factor)
        return c.replace(**changes)

    return machine.replace(
        cylinders=[cylinder(c) for c in machine.cylinders], shaft_inertia=machine.shaft_inertia * factor
    )


def test_a_machine_scaled_by_1e_minus_100_runs_as_it_does():
    """J(φ)φ̈ + ½J′φ̇² = M_gas − dU/dφ − M_load is homogeneous in the masses, inertias and
    pressures: the slow compressor with all of them 10⁻¹⁰⁰ times smaller has the same δ. Its
    pressures, ~10⁻⁹⁵ Pa, were taken as 0 (below the former 1e-30 Pa floor): δ was 71 % off."""
    machine = mc.presets.MACHINES["slow-compressor"]
    small = _scaled_machine(machine, 1e-100)
    assert small.cylinders[0].pressure.pressure.max() == pytest.approx(
        machine.cylinders[0].pressure.pressure.max() * 1e-100
    )
    state, scaled = mc.steady_state(machine), mc.steady_state(small)
    assert scaled.delta == pytest.approx(state.delta, rel=1e-9)
    assert scaled.delta_without_gravity == pytest.approx(state.delta_without_gravity, rel=1e-9)
    assert scaled.mean_load_torque == pytest.approx(state.mean_load_torque * 1e-100, rel=1e-9)
