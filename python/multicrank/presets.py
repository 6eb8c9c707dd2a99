"""Every preset in one place: the built-in machines (:class:`~multicrank.Machine`) and the crank
and cylinder layouts (``LAYOUTS``, from :mod:`multicrank.layouts`).

The machines' numbers are illustrative: plausible for the class of machine named, not taken
from any one manufacturer's data sheet. Each machine has bores, a synthetic pressure cycle
built from its own cylinder volume V(θ) = V_c + A·s(θ), a running speed and a shaft inertia
(flywheel included) that gives the usual coefficient of speed fluctuation δ of its class
(``SPEED_FLUCTUATION``; the class of each machine in ``MACHINE_CLASSES`` and in its note).
δ is judged at the machine's ``rpm`` with its full-load pressure cycle; the flywheels were
sized with the textbook estimate I_w ≈ ΔE/(δ ω²) − mean(J − I_w), ΔE the largest swing of
∫(M − mean M) dφ over a cycle of the gas, gravity and inertia torques (tests/test_presets.py
checks that each δ lies in its class). The geometry and masses are those of the first
presets, so that the report's gravity analysis is about the same machines.

The machines are built on first use (``ENGINES`` is a lazy mapping): their indicator diagrams
need SciPy, which ``import multicrank`` does not load.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterator, Mapping
from typing import Any

from ._native import MechanismError
from .gravity.layouts import LAYOUTS, Layout, layout_engine
from .machine.cylinder import Cylinder
from .machine.machine import Machine

# DEFAULT_ENGINE (ENGINES[DEFAULT_ENGINE_NAME]) is a module attribute too, built on first use.
__all__ = [
    "DEFAULT_ENGINE_NAME",
    "ENGINES",
    "LAYOUTS",
    "MACHINE_CLASSES",
    "SPEED_FLUCTUATION",
    "Layout",
    "engine_by_name_or_file",
    "layout_engine",
    "load_engine",
]

#: The usual coefficient of speed fluctuation δ = (ω_max − ω_min)/ω_mean of each class of
#: machine, (lowest, highest). Compressors (and pumps) 1/20–1/50, vehicle engines 1/100–1/300
#: and AC generator sets ≤ 1/300 are the classic handbook values (the same as the report's
#: threshold note). Ship propulsion: a direct-driven propeller is a smooth, heavily damped
#: load, like a pump's; we take the pump and compressor limit, δ ≤ 1/20, as its bound
#: (reasoning, not a handbook figure). A lower bound of 0: the class asks no more than the
#: upper one (a smoother machine is as good).
SPEED_FLUCTUATION: dict[str, tuple[float, float]] = {
    "compressor": (1 / 50, 1 / 20),
    "vehicle engine": (1 / 300, 1 / 100),
    "generator set": (0.0, 1 / 300),
    "ship propulsion": (0.0, 1 / 20),
}

#: The class (a key of ``SPEED_FLUCTUATION``) of every built-in machine.
MACHINE_CLASSES: dict[str, str] = {
    "slow-compressor": "compressor",
    "boxer-compressor": "compressor",
    "marine-2t-twin": "ship propulsion",
    "slow-diesel-12": "ship propulsion",
    "inline-4": "vehicle engine",
    "inline-6": "vehicle engine",
    "genset-v12": "generator set",
}

#: The built-in machine that the command line and the report take when none is named.
DEFAULT_ENGINE_NAME = "slow-compressor"

_TWO_STROKE = 2 * math.pi


def _slow_compressor() -> Machine:
    # The paper's kind of machine: heavy, slow, upright, where gravity is not negligible.
    # Bore 300 mm with a 60 mm piston rod (a rod a fifth of the bore, usual for crosshead
    # compressors); 8 % clearance on both ends (large slow machines: 5–10 %); air from
    # 1.0 to 4.0 bar absolute in one stage, n = 1.3 (water-jacketed): 2.94 + 2.82 kJ per
    # revolution, 11.5 kW at 120 rpm. The flywheel: ΔE ≈ 1.64 kJ per revolution at 120 rpm
    # asks I_w ≈ 360 kg·m² for δ = 1/35 (mid-class); 350 kg·m² (a 0.56 t rim at 0.8 m)
    # gives δ ≈ 1/34.
    cylinder = Cylinder(
        crank_radius=0.150,
        rod_length=0.600,
        rod_cg=0.400,
        piston_mass=85.0,
        rod_mass=60.0,
        crank_mass=40.0,
        crank_cg_radius=0.080,
        counterweight_mass=30.0,
        counterweight_radius=0.120,
        bore=0.300,
        piston_rod_diameter=0.060,
    )
    air: dict[str, Any] = dict(
        suction_pressure=1.0e5, discharge_pressure=4.0e5, polytropic_exponent=1.3, clearance_ratio=0.08
    )
    cylinder = cylinder.replace(
        pressure=cylinder.compressor_diagram(**air),
        pressure_crank_end=cylinder.compressor_diagram(end="crank", **air),
    )
    return Machine(
        [cylinder],
        shaft_inertia=350.0,
        name="slow-compressor",
        rpm=120.0,
        rpm_range=(60.0, 300.0),
        note=(
            "Illustrative heavy, slow single-cylinder upright double-acting air compressor (class: compressor, "
            "δ 1/20–1/50): 300 mm bore and stroke, 60 mm piston rod, 85 kg piston with rod and crosshead, "
            "air from 1 to 4 bar absolute, 11.5 kW at 120 rpm; a 350 kg·m² flywheel gives δ ≈ 1/34 — the kind "
            "of machine the paper had in mind, where gravity is not negligible."
        ),
    )


def _boxer_compressor() -> Machine:
    # A balanced-opposed ("boxer") air compressor: two horizontal double-acting cylinders
    # on throws 180° apart, so the reciprocating forces cancel; no counterweights. Bore
    # 250 mm, stroke 140 mm, rod 45 mm, 10 % clearance, 1.0 → 3.5 bar absolute: 40.6 kW at
    # 740 rpm (a six-pole 50 Hz motor). ΔE ≈ 1.14 kJ asks 6.2 kg·m² for δ = 1/35; 6.5 kg·m²
    # (motor rotor ≈ 1.5 and a flywheel ≈ 5) gives δ ≈ 1/36.
    cylinder = Cylinder(
        crank_radius=0.070,
        rod_length=0.350,
        rod_cg=0.230,
        piston_mass=45.0,
        rod_mass=22.0,
        crank_mass=30.0,
        crank_cg_radius=0.050,
        bore=0.250,
        piston_rod_diameter=0.045,
    )
    air: dict[str, Any] = dict(
        suction_pressure=1.0e5, discharge_pressure=3.5e5, polytropic_exponent=1.3, clearance_ratio=0.10
    )
    cylinder = cylinder.replace(
        pressure=cylinder.compressor_diagram(**air),
        pressure_crank_end=cylinder.compressor_diagram(end="crank", **air),
    )
    return Machine.from_layout(
        "boxer-2",
        cylinder,
        shaft_inertia=6.5,
        name="boxer-compressor",
        rpm=740.0,
        rpm_range=(500.0, 1000.0),
        note=(
            "Illustrative balanced-opposed air compressor (class: compressor, δ 1/20–1/50): two horizontal "
            "double-acting cylinders, 250 mm bore, 140 mm stroke, on throws 180° apart; 1 to 3.5 bar absolute, "
            "40.6 kW at 740 rpm; motor rotor and flywheel 6.5 kg·m² give δ ≈ 1/36."
        ),
    )


def _marine_twin() -> Machine:
    # A small fishing-vessel two-stroke twin: bore 240 mm, 300 mm stroke, cranks at 180°;
    # scavenged at 1.3 bar absolute, ε = 14, ports open 70° before and close 50° after the
    # inner dead centre, 17 kJ released per cycle: IMEP ≈ 6.1 bar, peak 38 bar, 83 kW at
    # 300 rpm (an old low-pressure engine). ΔE ≈ 6.0 kJ at 300 rpm asks 238 kg·m² for
    # δ = 1/40; 240 kg·m² (a 0.67 t flywheel at 0.6 m, with shaft and propeller) gives 1/40.
    cylinder = Cylinder(
        crank_radius=0.150,
        rod_length=0.650,
        rod_cg=0.430,
        piston_mass=60.0,
        rod_mass=55.0,
        crank_mass=45.0,
        crank_cg_radius=0.090,
        counterweight_mass=40.0,
        counterweight_radius=0.130,
        bore=0.240,
    )
    cylinder = cylinder.replace(
        pressure=cylinder.engine_diagram(
            intake_pressure=1.3e5,
            heat_release=17.0e3,
            compression_ratio=14.0,
            cycle=_TWO_STROKE,
            start_of_combustion=math.radians(-5.0),
            combustion_duration=math.radians(50.0),
            exhaust_opening=math.radians(70.0),
            intake_closing=math.radians(50.0),
        )
    )
    return Machine.from_layout(
        "inline-2-2t",
        cylinder,
        shaft_inertia=240.0,
        name="marine-2t-twin",
        rpm=300.0,
        rpm_range=(150.0, 400.0),
        note=(
            "Illustrative two-cylinder two-stroke marine engine, small fishing-vessel class (class: ship "
            "propulsion, δ ≤ 1/20): 240 mm bore, 300 mm stroke, λ ≈ 0.23, cranks at 180°, IMEP ≈ 6 bar, "
            "83 kW at 300 rpm rated; flywheel, shaft and propeller 240 kg·m² give δ ≈ 1/40."
        ),
    )


def _inline_four() -> Machine:
    # A 2.0-litre car petrol engine: bore 86 mm, stroke 85 mm, ε = 10.5, full throttle
    # (1.0 bar absolute), combustion from 15° before the firing dead centre over 60°,
    # 1.3 kJ per cylinder and cycle: IMEP ≈ 12.4 bar, peak 49 bar, 122 kW at 6000 rpm. δ is
    # judged at full load and rated speed, 6000 rpm, where ΔE ≈ 0.55 kJ (the inertia torque's
    # second order dominates): the old preset's 0.18 kg·m² (flywheel, clutch and crank, a
    # usual car value) gives δ ≈ 1/133.
    cylinder = Cylinder(
        crank_radius=0.0425,
        rod_length=0.140,
        rod_cg=0.100,
        piston_mass=0.45,
        rod_mass=0.55,
        crank_mass=1.2,
        crank_cg_radius=0.030,
        counterweight_mass=1.3,
        counterweight_radius=0.035,
        bore=0.086,
    )
    cylinder = cylinder.replace(
        pressure=cylinder.engine_diagram(
            intake_pressure=1.0e5,
            heat_release=1300.0,
            compression_ratio=10.5,
            start_of_combustion=math.radians(-15.0),
            combustion_duration=math.radians(60.0),
        )
    )
    return Machine.from_layout(
        "inline-4-4t",
        cylinder,
        shaft_inertia=0.18,
        name="inline-4",
        rpm=6000.0,
        rpm_range=(600.0, 6500.0),
        note=(
            "Illustrative in-line four four-stroke car petrol engine (class: vehicle engine, δ 1/100–1/300): "
            "86 mm bore, 85 mm stroke, 140 mm rods, IMEP ≈ 12.4 bar at full load, 122 kW at 6000 rpm rated; "
            "flywheel, clutch and crank 0.18 kg·m² give δ ≈ 1/133 there; idles from 600 rpm."
        ),
    )


def _inline_six() -> Machine:
    # An 11-litre truck diesel: bore 130 mm, stroke 140 mm, ε = 17, boost 2.5 bar absolute
    # at full load, 8 kJ per cylinder and cycle: IMEP ≈ 20.6 bar, peak 116 bar, 363 kW at
    # 1900 rpm rated. ΔE ≈ 1.38 kJ there; 4.0 kg·m² (flywheel ≈ 2.5, clutch, crank and
    # damper; heavy trucks carry 3–4) gives δ ≈ 1/118.
    cylinder = Cylinder(
        crank_radius=0.070,
        rod_length=0.230,
        rod_cg=0.160,
        piston_mass=2.5,
        rod_mass=3.0,
        crank_mass=4.0,
        crank_cg_radius=0.045,
        counterweight_mass=4.2,
        counterweight_radius=0.060,
        bore=0.130,
    )
    cylinder = cylinder.replace(
        pressure=cylinder.engine_diagram(
            intake_pressure=2.5e5,
            heat_release=8000.0,
            compression_ratio=17.0,
            start_of_combustion=math.radians(-5.0),
            combustion_duration=math.radians(60.0),
        )
    )
    return Machine.from_layout(
        "inline-6-4t",
        cylinder,
        shaft_inertia=4.0,
        name="inline-6",
        rpm=1900.0,
        rpm_range=(500.0, 2200.0),
        note=(
            "Illustrative in-line six four-stroke truck diesel (class: vehicle engine, δ 1/100–1/300): 130 mm "
            "bore, 140 mm stroke, 230 mm rods, IMEP ≈ 20.6 bar, 363 kW at 1900 rpm rated; flywheel, clutch and "
            "crank 4.0 kg·m² give δ ≈ 1/118 there; idles from 500 rpm."
        ),
    )


def _slow_diesel_twelve() -> Machine:
    # A large-ship slow-speed two-stroke crosshead diesel: bore 960 mm, stroke 2.5 m,
    # scavenged at 3.5 bar absolute, ε = 20, exhaust 70° before and scavenge ports closed 40°
    # after the inner dead centre, 7.5 MJ per cylinder and cycle: IMEP ≈ 19.3 bar, peak
    # 181 bar, 63 MW at 90 rpm. No flywheel is needed: twelve cylinders fire every 30°, and
    # the shaft with propeller and entrained water, ≈ 1.5·10⁶ kg·m², gives δ ≈ 1/1600.
    cylinder = Cylinder(
        crank_radius=1.25,
        rod_length=3.0,
        rod_cg=2.0,
        piston_mass=15000.0,
        rod_mass=12000.0,
        crank_mass=18000.0,
        crank_cg_radius=0.8,
        counterweight_mass=12000.0,
        counterweight_radius=1.2,
        bore=0.96,
    )
    cylinder = cylinder.replace(
        pressure=cylinder.engine_diagram(
            intake_pressure=3.5e5,
            heat_release=7.5e6,
            compression_ratio=20.0,
            cycle=_TWO_STROKE,
            start_of_combustion=math.radians(-2.0),
            combustion_duration=math.radians(60.0),
            exhaust_opening=math.radians(70.0),
            intake_closing=math.radians(40.0),
        )
    )
    return Machine.from_layout(
        "inline-12-2t",
        cylinder,
        shaft_inertia=1.5e6,
        name="slow-diesel-12",
        rpm=90.0,
        rpm_range=(25.0, 100.0),
        note=(
            "Illustrative in-line twelve-cylinder slow-speed two-stroke crosshead diesel, large ship propulsion "
            "(class: ship propulsion, δ ≤ 1/20): 960 mm bore, 2.5 m stroke, piston + piston rod + crosshead "
            "≈ 15 t per cylinder, IMEP ≈ 19 bar, 63 MW at 90 rpm rated; shaft with propeller ≈ 1.5·10⁶ kg·m² "
            "and no flywheel give δ ≈ 1/1600."
        ),
    )


def _genset_v_twelve() -> Machine:
    # A 60° V12 four-stroke diesel driving a 50 Hz alternator at 1500 rpm: bore 170 mm, stroke
    # 210 mm (57 litres), boost 3.5 bar absolute, ε = 15, 23 kJ per cylinder and cycle:
    # IMEP ≈ 22.8 bar, peak 136 bar, 1.63 MW. Firing every 60°, ΔE ≈ 0.92 kJ; the engine's
    # flywheel (≈ 12 kg·m²) and the alternator's rotor (≈ 38 kg·m², usual for 2 MVA at four
    # poles), 50 kg·m² in all, give δ ≈ 1/1400, inside the class with a wide margin.
    cylinder = Cylinder(
        crank_radius=0.105,
        rod_length=0.400,
        rod_cg=0.280,
        piston_mass=9.0,
        rod_mass=10.0,
        crank_mass=18.0,
        crank_cg_radius=0.065,
        counterweight_mass=20.0,
        counterweight_radius=0.085,
        bore=0.170,
    )
    cylinder = cylinder.replace(
        pressure=cylinder.engine_diagram(
            intake_pressure=3.5e5,
            heat_release=23.0e3,
            compression_ratio=15.0,
            start_of_combustion=math.radians(-5.0),
            combustion_duration=math.radians(60.0),
        )
    )
    return Machine.from_layout(
        "v12-60",
        cylinder,
        shaft_inertia=50.0,
        strokes=4,
        name="genset-v12",
        rpm=1500.0,
        rpm_range=(1500.0, 1800.0),
        note=(
            "Illustrative 60° V12 four-stroke diesel generator set (class: generator set, δ ≤ 1/300): 170 mm "
            "bore, 210 mm stroke, IMEP ≈ 23 bar, 1.63 MW at 1500 rpm (50 Hz; 1800 rpm for 60 Hz); engine "
            "flywheel and alternator rotor 50 kg·m² give δ ≈ 1/1400."
        ),
    )


class _Machines(Mapping[str, Machine]):
    """The built-in machines by name, each built on first use and kept."""

    def __init__(self, builders: dict[str, Callable[[], Machine]]) -> None:
        self._builders = builders
        self._built: dict[str, Machine] = {}

    def __getitem__(self, name: str) -> Machine:
        if name not in self._built:
            self._built[name] = self._builders[name]()
        return self._built[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._builders)

    def __len__(self) -> int:
        return len(self._builders)

    def __repr__(self) -> str:
        return f"<the built-in machines: {', '.join(self._builders)}>"


#: The built-in machines by name (a mapping; each is built when first looked up).
ENGINES: Mapping[str, Machine] = _Machines(
    {
        "slow-compressor": _slow_compressor,
        "marine-2t-twin": _marine_twin,
        "inline-4": _inline_four,
        "inline-6": _inline_six,
        "slow-diesel-12": _slow_diesel_twelve,
        "boxer-compressor": _boxer_compressor,
        "genset-v12": _genset_v_twelve,
    }
)


def __getattr__(name: str) -> Any:
    # DEFAULT_ENGINE (the slow compressor) is built on first use, as every preset is.
    if name == "DEFAULT_ENGINE":
        return ENGINES[DEFAULT_ENGINE_NAME]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def load_engine(path: str | os.PathLike[str]) -> Machine:
    """A machine from a TOML machine file: :meth:`multicrank.Machine.from_toml`.

    Parameters
    ----------
    path : str or os.PathLike
        The TOML file (docs/machine-files.md).

    Returns
    -------
    Machine
        The machine the file describes.
    """
    return Machine.from_toml(path)


def engine_by_name_or_file(spec: str | os.PathLike[str]) -> Machine:
    """A built-in machine by name (``ENGINES``), or one loaded from a TOML machine file.

    What the command line's ``--engine`` takes.

    Parameters
    ----------
    spec : str or os.PathLike
        A key of ``ENGINES``, or the path of a TOML machine file.

    Returns
    -------
    Machine
        The built-in machine, or the one the file describes.

    Raises
    ------
    MechanismError
        When ``spec`` is neither a built-in machine nor an existing file (naming both
        possibilities), or the file is not a valid machine file.

    Examples
    --------
    >>> from multicrank.presets import engine_by_name_or_file
    >>> machine = engine_by_name_or_file("inline-4")
    >>> machine.name, len(machine), machine.strokes, machine.rpm
    ('inline-4', 4, 4, 6000.0)
    """
    if isinstance(spec, str) and spec in ENGINES:
        return ENGINES[spec]
    if not isinstance(spec, str | os.PathLike):
        raise MechanismError(f"engine = {spec!r}: give a built-in machine's name or a machine file's path")
    if os.path.exists(spec):
        return load_engine(spec)
    raise MechanismError(
        f"engine = {str(spec)!r} is neither a built-in machine ({', '.join(ENGINES)}) nor a machine file (TOML)"
    )
