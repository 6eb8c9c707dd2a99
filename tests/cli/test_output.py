"""How the commands write a result (multicrank/cli/_output.py): ``--format csv`` gives every
number to 12 significant digits and ``--format json`` to 15, whatever its magnitude. The
oracle is exact decimal arithmetic (Python's ``decimal``) on the text written: at most that
many significant digits, within half a unit of the last of them of the value."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import math
import sys
from decimal import ROUND_HALF_EVEN, Decimal

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner
from hypothesis import given
from hypothesis import strategies as st

import multicrank as mc
from multicrank import cli
from multicrank.cli._output import CSV_DIGITS, JSON_DIGITS, write_result

# Finite doubles of every magnitude, subnormal ones included, and the non-finite ones.
numbers = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False, max_value=1e308, min_value=-1e308),
    st.builds(lambda m, e: m * 10.0**e, st.floats(1.0, 10.0, exclude_max=True), st.integers(-300, 300)),
    st.sampled_from([math.nan, math.inf, -math.inf, 0.0, -0.0, 1.2345678901234567e-12]),
)


def significant_digits(text: str) -> int:
    """The significant digits of a number as written (1e-05 has one, 0.00123 three)."""
    mantissa = text.lower().split("e")[0].lstrip("+-").replace(".", "").lstrip("0")
    return len(mantissa.rstrip("0")) or 1


def rounded_to(exact: Decimal, digits: int) -> Decimal:
    """``exact`` rounded to ``digits`` significant digits (half to even, as C's printf)."""
    return exact if exact == 0 else exact.quantize(Decimal(1).scaleb(exact.adjusted() - digits + 1), ROUND_HALF_EVEN)


def check_written(text: str, value: float, digits: int) -> None:
    """``text`` is ``value`` to ``digits`` significant digits: no more digits, and the double
    it reads as is the one nearest to the exact decimal rounding of ``value`` (CSV: the text
    is that rounding itself). Exact decimals: Decimal(value) is the double's own value."""
    assert significant_digits(text) <= digits, (text, value)
    exact = Decimal(value)
    rounded = rounded_to(exact, digits)
    assert float(text) == float(rounded), (text, value, rounded)
    if abs(value) >= sys.float_info.min:  # a normal double: within half a unit of the last digit
        assert abs(Decimal(text) - exact) <= Decimal(5).scaleb(exact.adjusted() - digits), (text, value)


def written(frame: pd.DataFrame, fmt: str) -> str:
    """What write_result writes to stdout."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        write_result(frame, fmt, None, summary=[], json_meta={"machine": "test"})
    return out.getvalue()


@given(values=st.lists(numbers, min_size=1, max_size=20))
def test_json_writes_15_significant_digits_of_every_magnitude(values):
    """pandas' to_json(double_precision=15) kept 15 decimal places: 1.2345678901234567e-12 was
    written 0.000000000001235, four digits."""
    frame = pd.DataFrame({"value": values, "pair": [[v, v / 3] for v in values]})
    data = json.loads(written(frame, "json"), parse_float=str)
    assert data["machine"] == "test" and [row["index"] for row in data["rows"]] == list(range(len(values)))
    for row, value in zip(data["rows"], values, strict=True):
        for text, number in ((row["value"], value), *zip(row["pair"], (value, value / 3), strict=True)):
            if math.isfinite(number):
                check_written(text, number, JSON_DIGITS)
            else:
                assert text is None  # NaN and ±inf are null, as JSON has no such numbers


@given(values=st.lists(numbers.filter(math.isfinite), min_size=1, max_size=20))
def test_csv_writes_12_significant_digits_of_every_magnitude(values):
    rows = list(csv.reader(io.StringIO(written(pd.DataFrame({"value": values}), "csv"))))
    assert rows[0] == ["", "value"]
    for (_, text), value in zip(rows[1:], values, strict=True):
        check_written(text, value, CSV_DIGITS)
        assert Decimal(text) == rounded_to(Decimal(value), CSV_DIGITS)  # the text is the rounding itself


def test_the_other_columns_are_written_as_they_are():
    frame = pd.DataFrame(
        {"name": ["a", "b"], "count": [1, 2], "stalled": [True, False], "speed": pd.array([1 / 3, None], "Float64")},
        index=pd.Index([1e-12 / 7, 2.0], name="rpm"),
    )
    rows = json.loads(written(frame, "json"))["rows"]
    assert rows == [
        {"rpm": 1.42857142857143e-13, "name": "a", "count": 1, "stalled": True, "speed": 0.333333333333333},
        {"rpm": 2.0, "name": "b", "count": 2, "stalled": False, "speed": None},
    ]
    # The largest doubles, whose rounding to 15 digits overflows, are written whole.
    (row,) = json.loads(written(pd.DataFrame({"x": [sys.float_info.max]}), "json"))["rows"]
    assert row["x"] == sys.float_info.max


@pytest.mark.parametrize(("fmt", "digits"), [("json", JSON_DIGITS), ("csv", CSV_DIGITS)])
def test_forces_at_a_tiny_speed_keep_their_digits(fmt, digits):
    """The issue's case: at --rpm 1e-5 the shaking forces are ~1e-12 N and their JSON lost up
    to 19 % (four digits or fewer were left). Each number is the library's to 15 (JSON) or
    12 (CSV) significant digits."""
    machine = mc.presets.MACHINES["inline-4"]
    expected = mc.shaking_forces(machine, rpm=1e-5).orders
    result = CliRunner().invoke(cli.main, ["forces", "--machine", "inline-4", "--rpm", "1e-5", "--format", fmt])
    assert result.exit_code == 0, result.output
    if fmt == "json":
        rows = json.loads(result.stdout, parse_float=str)["rows"]
        table = {name: [row[name] for row in rows] for name in rows[0]}
    else:
        lines = list(csv.reader(io.StringIO(result.stdout)))
        table = {name: [line[j] for line in lines[1:]] for j, name in enumerate(lines[0])}
    small = 0
    for name in ("force_vertical", "force_horizontal", "force_forward", "force_backward"):
        assert len(table[name]) == len(expected)
        for text, value in zip(table[name], expected[name], strict=True):
            check_written(text, float(value), digits)
            small += 0 < abs(value) < 1e-9
    assert small >= 4  # the forces at this speed are tiny: the case is the one of the issue
    np.testing.assert_allclose([float(t) for t in table["force_vertical"]], expected["force_vertical"], rtol=1e-11)
