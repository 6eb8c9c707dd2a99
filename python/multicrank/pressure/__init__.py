"""Indicator diagrams: gas pressure over the working cycle, from tables, CSV files or the
synthetic compressor and engine cycles (`IndicatorDiagram`), and the units they are given in."""

from .diagram import (
    ANGLE_UNITS,
    EXAMPLE_COMPRESSOR_CSV,
    INTERPOLATIONS,
    PRESSURE_UNITS,
    STANDARD_ATMOSPHERE,
    IndicatorDiagram,
)

__all__ = [
    "ANGLE_UNITS",
    "EXAMPLE_COMPRESSOR_CSV",
    "INTERPOLATIONS",
    "PRESSURE_UNITS",
    "STANDARD_ATMOSPHERE",
    "IndicatorDiagram",
]
