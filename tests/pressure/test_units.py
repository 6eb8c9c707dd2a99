"""The plausibility warning of a pressure table (``pressure.units.check_pressure_unit``): its
message writes the peak once in the table's unit and, in another unit than bar, in bar beside
it, the two in one notation — never the same number twice ("100000 bar = 1e+05 bar")."""

from __future__ import annotations

import re

import pytest

from multicrank.pressure import PressureUnitWarning
from multicrank.pressure.units import check_pressure_unit

NUMBER = r"-?\d+(?:\.\d+)?(?:e[+-]\d+)?"


def message(pressures_pa: list[float], unit: str) -> str:
    with pytest.warns(PressureUnitWarning) as caught:
        check_pressure_unit(pressures_pa, unit, "table.csv")
    return str(caught[0].message)


def peak_text(text: str) -> str:
    (found,) = re.findall(r"the largest pressure is (.*?), (?:above|below)", text)
    return found


@pytest.mark.parametrize("peak_pa", [1e10, 8e10, 3.2e15])
def test_a_peak_in_bar_is_written_once(peak_pa):
    written = peak_text(message([peak_pa], "bar"))
    assert re.fullmatch(rf"{NUMBER} bar", written), written
    assert float(written.split()[0]) == pytest.approx(peak_pa / 1e5, rel=1e-3)


@pytest.mark.parametrize(
    ("peak_pa", "unit"),
    [(8.0, "Pa"), (8e11, "MPa"), (8e12, "kPa"), (50.0, "Pa"), (9e9, "psi")],
)
def test_a_peak_in_another_unit_is_written_in_it_and_in_bar_in_one_notation(peak_pa, unit):
    written = peak_text(message([peak_pa], unit))
    match = re.fullmatch(rf"({NUMBER}) {re.escape(unit)} = ({NUMBER}) bar", written)
    assert match, written
    first, second = match[1], match[2]
    assert ("e" in first) == ("e" in second), written  # one notation, fixed or with exponents
    assert float(second) == pytest.approx(peak_pa / 1e5, rel=1e-3)
