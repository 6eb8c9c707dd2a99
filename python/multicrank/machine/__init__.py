"""The physical machine in SI units: `Cylinder`s (`cylinder`) on one shaft (`Machine`, `machine`),
built in code, from a layout (its firing: `firing`) or from a TOML machine file (`files`)."""

from .cylinder import Cylinder
from .machine import Machine

__all__ = ["Cylinder", "Machine"]
