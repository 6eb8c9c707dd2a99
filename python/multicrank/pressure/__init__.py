"""Indicator diagrams: gas pressure over the working cycle (`IndicatorDiagram`, `diagram`), from
tables, CSV files (`tables`) or the synthetic compressor and engine cycles (`synthetic`), and
the units they are given in."""

from .diagram import (
    ANGLE_UNITS,
    EXAMPLE_COMPRESSOR_CSV,
    INTERPOLATIONS,
    PLAUSIBLE_PRESSURES,
    PRESSURE_UNITS,
    STANDARD_ATMOSPHERE,
    IndicatorDiagram,
    PressureUnitWarning,
)

__all__ = [
    "ANGLE_UNITS",
    "EXAMPLE_COMPRESSOR_CSV",
    "INTERPOLATIONS",
    "PLAUSIBLE_PRESSURES",
    "PRESSURE_UNITS",
    "STANDARD_ATMOSPHERE",
    "IndicatorDiagram",
    "PressureUnitWarning",
]
