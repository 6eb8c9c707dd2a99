"""One exception type, naming the parameter: the worked examples (issues 13 and 26).

Where tests/test_errors.py calls every public callable with random bad values, this file
holds the cases found by hand or by a hypothesis run, each refused with a
:class:`mc.MechanismError` that names the parameter (or the column, the row, the field, the
callable) and its allowed range: counts beyond 64 bits, engines' columns, ``crank_ratio``'s
own range, copies of grids and engines, flags, work that could not finish, unknown fields of
``replace``, pressure, load and drive callables that return the wrong thing, tampered torque
order tables, bad rows of sweep tables, quantities beyond the documented limit, a machine
file with a huge bore. The machine, cylinder, engine and design come from tests/test_errors.py.
"""

from __future__ import annotations

import copy
import math
import pickle
import re
from collections.abc import Callable

import numpy as np
import pandas as pd
import pytest

import multicrank as mc
from tests.test_errors import CYLINDER, DESIGN, ENGINE, GRID_RESULT, MACHINE


# --------------------------------------------------------------------------- the examples
@pytest.mark.parametrize(
    "call, parameter",
    [
        (lambda: mc.crank_phases(10**30), "cranks"),
        (lambda: mc.crank_phases(2**63), "cranks"),
        (lambda: mc.surviving_harmonics(3, n_max=2**64), "n_max"),
        (lambda: mc.surviving_harmonics(2**64), "cranks"),
        (lambda: mc.paper_coefficient(2**40, 1), "i"),
        (lambda: mc.paper_coefficient(1, 2**40), "j"),
        (lambda: mc.lambda_coefficients(0.3, 10**30), "n_max"),
        (lambda: mc.fourier_coefficients(**DESIGN, n_max=-1), "n_max"),
        (lambda: mc.Engine.from_throws(5, [[0.0]], crank_ratio=0.3, u1=1, u2=0), "throws"),
        (lambda: mc.Engine.from_throws([0.0], 5, crank_ratio=0.3, u1=1, u2=0), "banks"),
        (lambda: mc.Engine.from_throws([0.0], [["a"]], crank_ratio=0.3, u1=1, u2=0), "banks[0]"),
        (lambda: mc.Engine.from_throws([0.0], [[]], crank_ratio=0.3, u1=1, u2=0), "banks"),
        (lambda: ENGINE.perturbed("seed"), "rng"),
        (lambda: ENGINE.perturbed(np.random.default_rng(0), u1_rel="x"), "u1_rel"),
        (lambda: ENGINE.harmonic_sensitivity(u1_rel=math.nan), "u1_rel"),
        (lambda: ENGINE.harmonic_sensitivity(phase=-0.1), "phase"),
        (lambda: mc.sweep(GRID_RESULT, outputs=None), "outputs"),
        (lambda: mc.sweep(GRID_RESULT, outputs=["force_rms", "force_rms"]), "outputs"),
        (lambda: mc.sweep(GRID_RESULT, phi=[[0.1], [0.2, 0.3]]), "phi"),
        (lambda: mc.sweep(GRID_RESULT, phi=10**30), "phi"),
        (lambda: mc.to_xarray(GRID_RESULT, axes=["crank_ratio"]), "axes"),
        (lambda: mc.to_xarray(GRID_RESULT, axes={"crank_ratio": 0.2}), "axes"),
        (lambda: mc.to_xarray(None), "result"),
        (lambda: mc.DesignGrid(crank_ratio=[[0.1], [0.2, 0.3]], inclination=0, u1=1, u2=0), "crank_ratio"),
        (lambda: mc.DesignGrid(crank_ratio=0.3, inclination="up", u1=1, u2=0), "inclination"),
        (lambda: mc.DesignGrid(crank_ratio=0.3, inclination=0, u1=1, u2=0, strokes=[2, 3]), "strokes"),
        (lambda: mc.UniformGrid("ten", 0.0, 0.1), "count"),
        # no angles: empty loads whose summary and polar diagram failed in numpy
        (lambda: mc.bearing_loads(MACHINE, phi=[]), "phi"),
        # True is an int to Python, not a bearing's number (it drew bearing 1)
        (lambda: mc.bearing_loads(MACHINE, phi=[0.0, 1.0]).polar(True), "bearing"),
        (lambda: mc.bearing_loads(MACHINE, phi=[0.0, 1.0]).polar(np.False_), "bearing"),
    ],
)
def test_issue_examples(call, parameter):
    with pytest.raises(mc.MechanismError, match=parameter.replace("[", r"\[").replace("]", r"\]")):
        call()


@pytest.mark.parametrize(
    "columns, named",
    [
        (dict(phase=[[0.0, 1.0]]), "phase"),
        (dict(inclination=np.zeros((2, 2))), "inclination"),
        (dict(u1=[]), "u1"),
        (dict(u2=[1.0, 2.0, 3.0]), "u2"),
        (dict(crank_ratio=[0.1, 0.2, 0.3]), "crank_ratio"),
        (dict(phase=[], u1=[]), "phase, u1"),
    ],
)
def test_engine_column_errors_name_the_column(columns, named):
    base = dict(phase=[0.0, 1.0], inclination=1.0, crank_ratio=0.3, u1=0.5, u2=0.1)
    with pytest.raises(mc.MechanismError) as error:
        mc.Engine(**{**base, **columns})
    for name in named.split(", "):
        assert name in str(error.value)


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, -0.1, 1.0])
def test_crank_ratio_errors_give_its_own_range(value):
    for call in (
        lambda: mc.generalized_force(0.1, crank_ratio=value, inclination=1.0, u1=0.5, u2=0.1),
        lambda: mc.lambda_coefficients(value, 4),
        lambda: mc.Engine(phase=0.0, inclination=1.0, crank_ratio=value, u1=0.5, u2=0.1),
        lambda: mc.DesignGrid(crank_ratio=value, inclination=1.0, u1=0.5, u2=0.1),
    ):
        with pytest.raises(mc.MechanismError, match=r"allowed: 0\.0 <= crank_ratio < 1\.0"):
            call()


@pytest.mark.parametrize(
    "grid", [mc.uniform_grid(10), mc.uniform_grid(7, -1.0, 2.0, endpoint=True), mc.UniformGrid(3, 1e6, 0.5)]
)
def test_copies_of_a_uniform_grid_are_uniform_grids(grid):
    for copied in (copy.copy(grid), copy.deepcopy(grid), pickle.loads(pickle.dumps(grid)), copy.deepcopy([grid])[0]):
        assert type(copied) is mc.UniformGrid
        assert (copied.count, copied.start, copied.step) == (grid.count, grid.start, grid.step)
        np.testing.assert_array_equal(copied, grid)
    # private names are not asked of the points (no recursion while half-built)
    with pytest.raises(AttributeError):
        grid._no_such_thing  # noqa: B018


def test_engines_copy_and_pickle():
    for copied in (copy.copy(ENGINE), copy.deepcopy(ENGINE), pickle.loads(pickle.dumps(ENGINE))):
        assert type(copied) is mc.Engine and copied.name == ENGINE.name
        pd.testing.assert_frame_equal(copied.to_frame(), ENGINE.to_frame())


def test_counts_beyond_64_bits_name_the_limit():
    with pytest.raises(mc.MechanismError, match=r"n_max = \d+ is out of range; allowed: an integer >= 0 \(at most"):
        mc.surviving_harmonics(4, n_max=2**64)
    assert mc.surviving_harmonics(4, n_max=np.uint8(8)) == mc.surviving_harmonics(4, n_max=8)


def test_flags_take_booleans_only():
    designs = {"crank_ratio": [0.3], "inclination": [1.0], "u1": [0.5], "u2": [0.1]}
    for flag in ("resume", "progress", "curves"):
        with pytest.raises(mc.MechanismError, match=flag):
            mc.sweep(designs, phi=8, **{flag: "no"})
    assert len(mc.sweep(designs, phi=8, progress=np.bool_(False))) == 1
    with pytest.raises(mc.MechanismError, match="resume=True needs out="):
        mc.sweep(designs, phi=8, resume=True)


@pytest.mark.parametrize(
    "call, parameter",
    [
        (lambda: mc.simulate(MACHINE, [0.0, 1.0], rpm0=600.0, max_step=5e-324), "max_step"),
        (lambda: mc.simulate(MACHINE, [0.0, 1.0], rpm0=600.0, max_step=1e-9), "max_step"),
        (lambda: mc.simulate(MACHINE, [0.0, 1e3], rpm0=1e6), "rpm0"),
        (lambda: mc.simulate(MACHINE, [0.0, 1e3], rpm0=1e7), "rpm0"),
        (lambda: mc.simulate(MACHINE, [0.0, 1.0], rpm0=600.0, atol=3.7096188882506045e-181), "atol"),
        (lambda: mc.flywheel_inertia(MACHINE, delta=4e-26, rpm=600.0), "delta"),
        (lambda: mc.steady_state(MACHINE, rpm=1e-197), "rpm"),
        (lambda: mc.steady_state(MACHINE, rpm=600.0, min_speed_ratio=4e-230), "min_speed_ratio"),
        (lambda: mc.Layout("x", "", (0.0,), b"\x00"), "banks"),
    ],
)
def test_work_that_could_not_finish_is_refused_up_front(call, parameter):
    """Issue 13: the motion API's hypothesis run found a hang (max_step = 5e-324) and
    overflows at extreme speeds, ratios and targets; each is now refused by name, at once."""
    with pytest.raises(mc.MechanismError, match=parameter):
        call()


@pytest.mark.parametrize(
    "replace, keyword, named",
    [
        (
            CYLINDER.replace,
            "bore_mm",
            r"unknown cylinder field\(s\) bore_mm \(did you mean 'bore'\?\); known: crank_radius",
        ),
        (
            CYLINDER.replace,
            "shaft_inertia",
            r"unknown cylinder field\(s\) shaft_inertia.*known: crank_radius, rod_length",
        ),
        (MACHINE.replace, "shaft_inertai", r"unknown machine field\(s\) shaft_inertai \(did you mean 'shaft_inertia'"),
        (
            MACHINE.replace,
            "bore",
            r"unknown machine field\(s\) bore \(bore: a field of each cylinder.*known: cylinders",
        ),
    ],
)
def test_replace_refuses_an_unknown_field_by_name(replace, keyword, named):
    """Issue 26, item 6: Cylinder.replace(bore_mm=...) raised TypeError where Machine.replace
    gave a MechanismError; both name the field and list the fields there are."""
    with pytest.raises(mc.MechanismError, match=named):
        replace(**{keyword: 1.0})


GASSED = CYLINDER.replace(bore=0.1)
PRESSURE_RETURNS = {
    "wrong shape": (lambda theta: np.zeros(3), r"returned shape \(3,\)"),
    "a scalar": (lambda theta: 1e5, r"returned shape \(\)"),
    "a transposed array": (lambda theta: np.zeros((*theta.shape[::-1], 1)), "returned shape"),
    "complex": (lambda theta: (1e5 + 1e3j) * np.ones_like(theta), "real pressure.*complex128"),
    "text": (lambda theta: np.full(theta.shape, "1e5"), "real pressure"),
    "objects": (lambda theta: np.full(theta.shape, None), "real pressure"),
    "ragged": (lambda theta: [[1.0], [1.0, 2.0]], "real pressure"),
    "inf": (lambda theta: np.full(theta.shape, np.inf), r"non-finite pressure \(inf\) \[Pa\]"),
}


@pytest.mark.parametrize("end", ["pressure", "pressure_crank_end"])
@pytest.mark.parametrize("returns", sorted(PRESSURE_RETURNS))
def test_a_pressure_callable_must_return_one_real_pressure_per_angle(end, returns):
    """Issue 26, item 6: a pressure of the wrong shape gave numpy's broadcast error, a complex
    one lost its imaginary part; the callable is named, with what it must return."""
    function, message = PRESSURE_RETURNS[returns]
    machine = mc.Machine([GASSED.replace(**{end: function})], shaft_inertia=0.5, rpm=600.0)
    for call in (lambda: machine.gas_torque(np.linspace(0.0, 1.0, 5)), lambda: mc.steady_state(machine)):
        with pytest.raises(mc.MechanismError, match=rf"^{end} .*{message}"):
            call()


TORQUE_RETURNS = {
    "complex": (lambda phi, omega: (1.0 + 1.0j) * np.ones_like(phi), "real torque.*complex128"),
    "a complex scalar": (lambda phi, omega: 1.0 + 0.5j, "real torque.*complex"),
    "text": (lambda phi, omega: np.full(np.shape(phi), "1"), "real torque"),
    "wrong shape": (lambda phi, omega: np.zeros(7), r"returned shape \(7,\)"),
    "nan": (lambda phi, omega: np.full(np.shape(phi), np.nan), r"non-finite torque \(nan\)"),
}


@pytest.mark.parametrize("parameter", ["load", "drive"])
@pytest.mark.parametrize("returns", sorted(TORQUE_RETURNS))
def test_a_load_or_drive_callable_must_return_real_torques(parameter, returns):
    """Issue 26, item 6: a drive returning complex numbers was accepted, its imaginary part dropped."""
    function, message = TORQUE_RETURNS[returns]
    given = {"load": 1.0, "drive": None, parameter: function}
    for call in (
        lambda: mc.steady_state(MACHINE, **given),
        lambda: mc.simulate(MACHINE, [0.0, 0.01], rpm0=600.0, **given),
    ):
        with pytest.raises(mc.MechanismError, match=rf"^{parameter} .*{message}"):
            call()


def test_a_torque_callable_may_return_what_broadcasts():
    """The documented contract of loads stays: a result that broadcasts to (phi, omega) is taken."""
    machine = mc.Machine([CYLINDER], shaft_inertia=0.5, rpm=600.0)
    constant = mc.simulate(machine, [0.0, 0.01], rpm0=600.0, load=0.5)
    scalar = mc.simulate(machine, [0.0, 0.01], rpm0=600.0, load=lambda phi, omega: 0.5)
    np.testing.assert_array_equal(scalar.omega, constant.omega)


def _tampered(change: Callable[[pd.DataFrame], None]) -> pd.DataFrame:
    orders = mc.torque_orders(MACHINE, 600.0, max_order=3)
    change(orders)
    return orders


@pytest.mark.parametrize(
    "orders, named",
    [
        (_tampered(lambda t: t.__setitem__("total_amplitude", np.nan)), r"total_amplitude = nan at order 0\.0"),
        (_tampered(lambda t: t.loc.__setitem__((2.0, "total_amplitude"), -1.0)), r"total_amplitude = -1\.0 at order 2"),
        (_tampered(lambda t: t.loc.__setitem__((3.0, "total_phase"), np.inf)), "total_phase = inf at order 3"),
        (_tampered(lambda t: t.__setitem__("total_amplitude", "1")), "total_amplitude must hold real numbers"),
        (_tampered(lambda t: t.attrs.__setitem__("omega", -62.8)), r"attrs\['omega'\] = -62\.8 is out of range"),
        (_tampered(lambda t: t.attrs.__setitem__("omega", np.nan)), r"attrs\['omega'\] = nan is out of range"),
        (_tampered(lambda t: t.attrs.__setitem__("omega", "fast")), r"attrs\['omega'\] = 'fast' is not a speed"),
        (_tampered(lambda t: t.pop("total_phase")), "lacks the column"),
        (_tampered(lambda t: setattr(t, "index", pd.Index([0.0, -1.0, 2.0, 3.0], name="order"))), "order = -1.0"),
    ],
)
def test_to_opentorsion_refuses_a_tampered_table(orders, named):
    """Issue 26, item 6: a table of torque_orders changed since (NaN amplitudes, a negative ω
    in its attrs) was handed to openTorsion as it was."""
    with pytest.raises(mc.MechanismError, match=rf"^orders .*{named}"):
        mc.to_opentorsion(orders, dofs=2, node=0, mean=True)


SWEEP_TABLE = pd.DataFrame(
    {"crank_ratio": [0.3, 0.3, 0.3], "inclination": [1.0, 1.0, 1.0], "u1": [0.5, 0.5, 0.5], "u2": [0.1, 0.1, 0.1]},
    index=[10, 20, 30],
)


@pytest.mark.parametrize(
    "column, value, named",
    [
        ("crank_ratio", math.nan, r"design 20 \(crank_ratio = nan\): crank_ratio = nan is out of range"),
        ("u1", math.inf, r"design 20 \(u1 = inf\): u1 = inf is out of range"),
        ("crank_ratio", 1.5, r"design 20 \(crank_ratio = 1\.5\): crank_ratio = 1\.5 is out of range"),
        ("cranks", math.nan, r"design 20 \(cranks = nan\): designs column 'cranks' must hold integers"),
        ("strokes", 3, r"design 20 \(strokes = 3\.?0?\): strokes = 3 is not allowed"),
        ("acting", "both", r"design 20 \(acting = 'both'\): acting = 'both' is not allowed"),
    ],
)
def test_a_bad_value_in_a_sweeps_table_is_named_with_its_row(column, value, named):
    """Issue 26, item 6: a NaN in a design table is refused naming its row and column, as a
    motion sweep names a row the machine refuses."""
    designs = SWEEP_TABLE.copy()
    if column not in designs:
        designs[column] = {"cranks": 2, "strokes": 2, "acting": "single"}[column]
    designs[column] = designs[column].astype(object if isinstance(value, str) else float)
    designs.loc[20, column] = value
    with pytest.raises(mc.MechanismError, match=f"^{named}"):
        mc.sweep(designs, phi=8)


@pytest.mark.parametrize(
    "column, value, named",
    [
        ("shaft_inertia", math.nan, r"design 20 \(shaft_inertia = nan\): shaft_inertia = nan is out of range"),
        ("piston_mass", -math.inf, r"design 20 \(piston_mass = -inf\): piston_mass = -inf is out of range"),
        ("rpm", math.nan, r"design 20 \(rpm = nan\): rpm = nan is out of range; allowed: 1e-06 <= rpm"),
        ("rpm", 0.0, r"design 20 \(rpm = 0\): rpm = 0\.0 is out of range; allowed: 1e-06 <= rpm"),
        ("shaft_inertia", -1.0, r"design 20 \(shaft_inertia = -1\): shaft_inertia = -1\.0 is out of range"),
    ],
)
def test_a_bad_value_in_a_motion_sweeps_table_is_named_with_its_row(column, value, named):
    designs = pd.DataFrame({column: [600.0 if column == "rpm" else 0.6] * 3}, index=[10, 20, 30])
    designs.loc[20, column] = value
    with pytest.raises(mc.MechanismError, match=f"^{named}"):
        mc.motion_sweep(MACHINE, designs, outputs=["delta"])


QUANTITIES = {
    "crank_radius": "m",
    "rod_length": "m",
    "rod_cg": "m",
    "crank_cg_radius": "m",
    "counterweight_radius": "m",
    "bore": "m",
    "piston_rod_diameter": "m",
    "piston_mass": "kg",
    "rod_mass": "kg",
    "crank_mass": "kg",
    "counterweight_mass": "kg",
    "rod_inertia": "kg·m²",
}


@pytest.mark.parametrize("value", [1e160, 1.5e30, -1e200])
@pytest.mark.parametrize("field", sorted(QUANTITIES))
def test_a_cylinder_quantity_beyond_the_documented_limit_is_refused_by_name(field, value):
    """Issue 26, item 6: bore = 1e160 made the piston area overflow (OverflowError); every
    length, mass and inertia of a cylinder is at most MAGNITUDE_LIMIT = 1e30 (SI units)."""
    from multicrank._validation import MAGNITUDE_LIMIT

    assert MAGNITUDE_LIMIT == 1e30
    allowed = f"{field} = {value:g} is out of range; allowed: |{field}| <= 1e+30 [{QUANTITIES[field]}]"
    with pytest.raises(mc.MechanismError, match=re.escape(allowed)):
        CYLINDER.replace(**{field: value})


def test_the_limit_itself_is_a_quantity():
    heavy = CYLINDER.replace(piston_mass=1e30, rod_mass=1e30, crank_mass=1e30, bore=1e30)
    assert heavy.piston_mass == 1e30 and math.isfinite(heavy.piston_area)


@pytest.mark.parametrize(
    "call, named",
    [
        (lambda: mc.Machine([CYLINDER], shaft_inertia=1e300), r"shaft_inertia = 1e\+300 is out of range"),
        (lambda: mc.Machine([CYLINDER], shaft_inertia=1.0, g=1e100), r"g = 1e\+100 is out of range"),
        (lambda: mc.PowerLawLoad(torque=1.0, rpm=1e200), r"rpm = 1e\+200 is out of range; allowed: 1e-06"),
        (lambda: mc.PowerLawLoad(torque=1e31, rpm=600.0), r"torque = 1e\+31 is out of range"),
        (lambda: mc.steady_state(MACHINE, load=1e300), r"load = 1e\+300 is out of range"),
        (
            lambda: mc.IndicatorDiagram([0.0, 2.0, 4.0, 2 * math.pi], [0.0, 1e300, 0.0, 0.0], cycle=2 * math.pi),
            r"pressure\[1\] = 1e\+300 is out of range; allowed: \|pressure\| <= 1e\+30 \[Pa\]",
        ),
        (
            lambda: mc.steady_state(
                mc.Machine([GASSED.replace(pressure=lambda theta: np.full(theta.shape, 1e300))], shaft_inertia=1.0),
                rpm=600.0,
            ),
            r"pressure returned a pressure of 1e\+300 \[Pa\], out of range",
        ),
        (
            lambda: GASSED.compressor_diagram(
                suction_pressure=1e5, discharge_pressure=1e7, polytropic_exponent=1e-3, clearance_ratio=0.1
            ),
            "the clearance is too large for this pressure ratio",
        ),
    ],
)
def test_huge_values_are_refused_by_name_not_overflowed(call, named):
    """Issue 26, item 6: what overflowed (an OverflowError, or a solver that did not converge
    on g = 1e100) is refused by name with its allowed range."""
    with pytest.raises(mc.MechanismError, match=named):
        call()


def test_a_machine_file_with_a_huge_bore_names_the_key(tmp_path):
    """Issue 26, item 6: a machine file with bore = 1e200 raised OverflowError."""
    path = tmp_path / "huge.toml"
    path.write_text(
        "shaft_inertia = 1.0\n[cylinder]\ncrank_radius = 0.05\nrod_length = 0.2\npiston_mass = 1.0\n"
        'rod_mass = 1.0\nrod_cg = 0.05\nbore = 1e200\n[cylinder.pressure]\ntype = "compressor"\n'
        "suction_pressure = 1e5\ndischarge_pressure = 4e5\nclearance_ratio = 0.1\n",
        encoding="utf-8",
    )
    with pytest.raises(mc.MechanismError, match=r"huge\.toml: cylinder: bore = 1e\+200 is out of range"):
        mc.Machine.from_toml(path)
