"""The physical machine in SI units: `Cylinder`s (`cylinder`) on one shaft (`Machine`, `machine`),
built in code, from a layout (`layout` places the cylinders, `phases` chooses their phases) or
from a TOML machine file (`files` reads it, `loading` builds the machine). The Machine's other
methods live by job: `description` (repr, the gravity engine, the in-line design), `dynamics`
(J, U and the torques of mass) and `gas` (the piston forces and the gas torque)."""

from .cylinder import Cylinder
from .machine import Machine

__all__ = ["Cylinder", "Machine"]
