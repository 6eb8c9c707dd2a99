"""The physical machine in SI units: `Cylinder`s (`cylinder`) on one shaft (`Machine`, `machine`),
built in code, from a layout (`layout` places the cylinders, `phases` chooses their phases) or
from a TOML machine file (`files` reads it, `loading` builds the machine); where things are along
the shaft (`throws`: the throws and the main bearings) and the shaft as a torsional chain
(`Shaft`, `shaft`), whose torsional questions (its modes, `ShaftModes`, among them) are the
torsion room's. The Machine's other methods live by job: `description` (repr, the gravity
engine, the in-line design), `dynamics` (J, U and the torques of mass) and `gas` (the piston
forces and the gas torque)."""

from .cylinder import Cylinder
from .machine import Machine
from .shaft import Shaft

__all__ = ["Cylinder", "Machine", "Shaft"]
