"""The physical machine in SI units: `Cylinder`s on one shaft (`Machine`), built in code, from
a layout or from a TOML machine file (`files`)."""

from .machine import Cylinder, Machine

__all__ = ["Cylinder", "Machine"]
