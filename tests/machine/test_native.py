"""The native machine of the steady state (multicrank._native.NativeMachine, made by
multicrank.machine.native.native_machine) and mc.steady_state / mc.flywheel_inertia through it:
against an independent oracle (rust/core/tests/data/oracle.py: planar geometry, complex-step
derivatives, SciPy interpolants and quadratures, brentq; it shares no code with multicrank),
through the fixtures it wrote (rust/core/tests/data/motion_fixtures.json) and live; its sweep
against its own steady state of each design's machine (motion.variants.machine_variant), bit
for bit, on any thread count."""

import importlib.util
import json
import math
import pathlib
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pandas as pd
import pytest

import multicrank as mc
from multicrank._native import MOTION_SWEEP_OUTPUTS, FlywheelResult, NativeMachine, SteadyResult
from multicrank.machine.cylinder import unit_columns
from multicrank.machine.native import native_machine
from multicrank.motion.variants import machine_variant

STEADY = (
    "delta",
    "delta_midrange",
    "delta_without_gravity",
    "delta_coasting",
    "omega_mean",
    "omega_max",
    "omega_min",
    "period",
    "mean_load_torque",
)

ORACLE_DIR = pathlib.Path(__file__).resolve().parents[2] / "rust" / "core" / "tests" / "data"
#: What the oracle found (make_motion_fixtures.py): the machines' parameters and their motion.
FIXTURES = json.loads((ORACLE_DIR / "motion_fixtures.json").read_text())["machines"]
#: Relative tolerances against the oracle (good to ~1e-13 here, ~1e-9 near stall: its two
#: runs' agreement is in the fixtures). The core's time quadrature puts its energy offset,
#: and with it every ω, up to 3e-9 off at the machines' speeds (δ 3.5e-9, δ about the
#: midrange 6e-9, the flywheel 7e-9), its lowest running speed 3e-8; the cycle integrals (ω_m
#: asked for, the balancing load) are exact to rounding. A real error is far larger: a gas
#: torque 1e-6 off moves δ by ~1e-6.
TOLERANCE = {"integrals": 1e-12, "speeds": 1e-8, "deltas": 2e-8, "flywheel": 2e-8, "swing": 1e-12, "min_rpm": 2e-7}


def machine(name):
    return mc.presets.MACHINES[name]


def oracle():
    """rust/core/tests/data/oracle.py, imported from its file (once)."""
    name = "multicrank_motion_oracle"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, ORACLE_DIR / "oracle.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module  # its dataclasses look their module up
        spec.loader.exec_module(module)
    return sys.modules[name]


def fixture_machine(record):
    """The fixture's machine built from its parameters (its tables by their own kind)."""
    cycle = math.pi * record["strokes"]
    diagrams = [
        mc.IndicatorDiagram(np.array(d["x"]), np.array(d["pressure"]), cycle=cycle, kind=d["kind"])
        for d in record["diagrams"]
    ]
    fields = ("crank_radius", "rod_length", "piston_mass", "rod_mass", "rod_cg", "rod_inertia", "crank_mass")
    fields += ("crank_cg_radius", "counterweight_mass", "counterweight_radius", "phase", "inclination", "bore")
    cylinders = [
        mc.Cylinder(
            **{key: c[key] for key in fields},
            piston_rod_diameter=c["piston_rod_diameter"],
            pressure=None if c["head"] is None else diagrams[c["head"]],
            pressure_crank_end=None if c["crank_end"] is None else diagrams[c["crank_end"]],
        )
        for c in record["cylinders"]
    ]
    return mc.Machine(cylinders, shaft_inertia=record["shaft_inertia"], strokes=record["strokes"], g=record["g"])


def close(found, expected, kind, what):
    assert found == pytest.approx(expected, rel=TOLERANCE[kind], abs=1e-15), (what, found, expected)


def omega(rpm):
    """ω = πn/30 [rad/s] of n [1/min]: the core takes and gives speeds in rad/s."""
    return math.pi * rpm / 30


@pytest.mark.parametrize("record", FIXTURES, ids=[r["name"] for r in FIXTURES])
def test_the_steady_state_agrees_with_the_oracle(record):
    m = fixture_machine(record)
    expected = record["steady_state"]
    state = mc.steady_state(m, rpm=record["rpm"])
    native = native_machine(m)
    assert isinstance(native, NativeMachine)
    found = native.steady_state(omega(record["rpm"]))
    assert isinstance(found, SteadyResult) and found.omega is None and found.gas_torque is None
    for key, kind in [("omega_mean", "integrals"), ("period", "integrals"), ("mean_load_torque", "integrals")]:
        close(getattr(state, key), expected[key], kind, key)
        close(getattr(found, key), expected[key], kind, key)
    for key in ("omega_max", "omega_min"):
        close(getattr(state, key), expected[key], "speeds", key)
        close(getattr(found, key), expected[key], "speeds", key)
    for key in ("delta", "delta_midrange", "delta_without_gravity", "delta_gravity_only"):
        # The oracle's fixture says "delta_gravity_only" for δ of the machine coasting.
        name = "delta_coasting" if key == "delta_gravity_only" else key
        close(getattr(state, name), expected[key], "deltas", key)
        close(getattr(found, name), expected[key], "deltas", key)
    np.testing.assert_allclose(
        mc.steady_state(m, rpm=record["rpm"], points=361).omega, record["curves"]["omega"], rtol=TOLERANCE["speeds"]
    )


@pytest.mark.parametrize("record", FIXTURES, ids=[r["name"] for r in FIXTURES])
def test_the_flywheel_agrees_with_the_oracle(record):
    m = fixture_machine(record)
    native = native_machine(m)
    for case in record["flywheels"]:
        delta = case["delta"]
        sized = mc.flywheel_inertia(m, delta=delta, rpm=record["rpm"])
        found = native.flywheel_inertia(delta, omega(record["rpm"]))
        assert isinstance(found, FlywheelResult) and (found.delta, found.omega_mean) == (delta, omega(record["rpm"]))
        for key, kind in [
            ("shaft_inertia", "flywheel"),
            ("shaft_inertia_without_gravity", "flywheel"),
            ("textbook", "swing"),
            ("energy_swing", "swing"),
        ]:
            close(float(getattr(sized, key)), case[key], kind, (delta, key))
            close(getattr(found, key), case[key], kind, (delta, key))


def test_a_stall_carries_the_angle_and_the_lowest_speed_the_oracle_finds():
    (record,) = [r for r in FIXTURES if r["stalls"]]
    (case,) = record["stalls"]
    m = fixture_machine(record)
    with pytest.raises(mc.StallError) as python:
        mc.steady_state(m, rpm=case["rpm"])
    with pytest.raises(mc.MechanismError, match=r"stalls at omega_mean = .*min_omega") as native:
        native_machine(m).steady_state(omega(case["rpm"]))
    assert native.value.omega_mean == omega(case["rpm"])
    for raised in (python.value, native.value):
        assert raised.angle == pytest.approx(case["angle"], abs=1e-3)
    close(python.value.min_rpm, case["min_rpm"], "min_rpm", "min_rpm")
    close(native.value.min_omega, omega(case["min_rpm"]), "min_rpm", "min_omega")


def test_a_machine_the_fixtures_lack_agrees_with_the_oracle_run_here():
    # Six cylinders, four-stroke, at their own speed: the oracle from the preset's parameters
    # alone (nothing computed by multicrank), with and without gravity (~3 s).
    found = oracle()
    m = machine("inline-6")
    model = found.machine_of(m)
    phi = np.linspace(0.0, m.cycle, 1001)
    J, _ = m.reduced_inertia(phi)
    np.testing.assert_allclose(J, model.shaft_inertia + model.engine_inertia(phi), rtol=1e-14)
    gas = m.gas_torque(phi)
    np.testing.assert_allclose(gas, model.gas_torque(phi), rtol=0, atol=1e-13 * np.abs(gas).max())
    weight = m.gravity_torque(phi)
    # (a balanced six: each crank's gravity torque is ~10 N·m, their sum ~1e-4)
    np.testing.assert_allclose(weight, model.gravity_torque(phi), rtol=0, atol=1e-12)
    cycle = found.Cycle(model)
    omega_mean = math.pi * m.rpm / 30
    expected = found.Balance(cycle).solve(omega_mean)
    without = found.Balance(cycle, gravity=False).solve(omega_mean)
    state = mc.steady_state(m, rpm=m.rpm)
    close(state.mean_load_torque, expected.mean_load_torque, "integrals", "mean_load_torque")
    for key in ("omega_max", "omega_min"):
        close(getattr(state, key), getattr(expected, key), "speeds", key)
    close(state.delta, expected.delta, "deltas", "delta")
    close(state.delta_without_gravity, without.delta, "deltas", "delta_without_gravity")


DESIGNS = {
    "slow-compressor": {
        "shaft_inertia": [350.0, 250.0, 500.0, 300.0],
        "rpm": [120.0, 90.0, 150.0, 110.0],
        # Powers of two: Python rebuilds a scaled diagram's interpolant from the scaled table,
        # the core scales its coefficients, and only these scale both exactly.
        "pressure_scale": [1.0, 0.5, 2.0, 1.0],
        "rod_mass": [40.0, 45.0, 50.0, 38.0],
        # Rows 0 and 3 differ in r alone of their gas: the second takes the first's rules.
        "crank_radius": [0.15, 0.14, 0.16, 0.155],
    },
    "inline-4": {
        "shaft_inertia": [0.18, 0.1, 0.3],
        "rpm": [3000.0, 2000.0, 4500.0],
        "bore": [0.086, 0.08, 0.09],
        "crank_mass": [1.0, 1.5, 0.8],
        "g": [9.80665, 0.0, 20.0],
    },
    "boxer-compressor": {
        "rod_length": [0.25, 0.28, 0.3],
        "counterweight_mass": [0.0, 2.0, 4.0],
        "rpm": [600.0, 900.0, 1200.0],
    },
}


@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_sweep_rows_are_the_steady_states_of_their_machines(name):
    m = machine(name)
    columns = {k: np.array(v) for k, v in DESIGNS[name].items()}
    core = {"omega" if k == "rpm" else k: omega(v) if k == "rpm" else v for k, v in columns.items()}
    native = native_machine(m)
    found = native.sweep(core, list(MOTION_SWEEP_OUTPUTS), omega=omega(m.rpm), target_delta=1 / 100)
    assert set(found) == set(MOTION_SWEEP_OUTPUTS)
    assert found["stalled"].dtype == np.bool_ and not found["stalled"].any()
    for row in range(len(columns["rpm"])):
        design = {k: float(v[row]) for k, v in columns.items()}
        own = native_machine(machine_variant(m, design))
        state = own.steady_state(omega(design["rpm"]))
        flywheel = own.flywheel_inertia(1 / 100, omega(design["rpm"]))
        expected = {
            "delta": state.delta,
            "delta_without_gravity": state.delta_without_gravity,
            "delta_coasting": state.delta_coasting,
            "gravity_effect": state.delta / state.delta_without_gravity - 1,
            "omega_min": state.omega_min,
            "omega_max": state.omega_max,
            "flywheel_inertia": flywheel.shaft_inertia,
            "flywheel_inertia_without_gravity": flywheel.shaft_inertia_without_gravity,
        }
        # To 1e-12, not bit for bit: a design that differs from an earlier one of the sweep only
        # in pressure_scale, bore or counterweights takes that one's gas scaled or its U
        # reweighted (equal to rounding); δ/δ₀ − 1 compared as δ/δ₀, which it cancels.
        for output, value in expected.items():
            got = found[output][row]
            if output == "gravity_effect":
                got, value = 1 + got, 1 + value
            assert math.isclose(got, value, rel_tol=1e-12, abs_tol=1e-15) or (math.isnan(value) and math.isnan(got)), (
                row,
                output,
            )


def test_a_pressure_scale_agrees_to_rounding():
    m = machine("marine-2t-twin")
    found = native_machine(m).sweep({"pressure_scale": np.array([1.1, 0.7])}, ["delta"], omega=omega(m.rpm))
    for row, scale in enumerate((1.1, 0.7)):
        expected = native_machine(machine_variant(m, {"pressure_scale": scale})).steady_state(omega(m.rpm)).delta
        assert found["delta"][row] == pytest.approx(expected, rel=1e-12)


def test_a_stalled_row_is_a_row():
    m = machine("slow-compressor")
    found = native_machine(m).sweep({"omega": omega(np.array([5.0, 120.0]))}, ["delta", "omega_min"])
    assert found["stalled"].tolist() == [True, False]
    assert np.isnan(found["delta"][0]) and np.isnan(found["omega_min"][0])
    assert found["delta"][1] == native_machine(m).steady_state(omega(120.0)).delta


def test_only_what_is_asked_comes_back():
    m = machine("inline-4")
    native = native_machine(m)
    assert set(native.sweep({"omega": omega(np.array([3000.0]))}, ["delta"])) == {"delta", "stalled"}
    fly = native.sweep({"omega": omega(np.array([3000.0]))}, ["flywheel_inertia"], target_delta=1 / 100)
    assert set(fly) == {"flywheel_inertia"}
    assert set(native.sweep({}, ["omega_max"], omega=omega(3000.0))) == {"omega_max", "stalled"}


def test_the_native_results_are_typed_and_frozen():
    m = machine("marine-2t-twin")
    native = native_machine(m)
    phi = np.linspace(0.0, m.cycle, 5)
    state = native.steady_state(omega(m.rpm), phi=phi)
    sized = native.flywheel_inertia(1 / 50, omega(m.rpm))
    assert isinstance(state, SteadyResult) and isinstance(sized, FlywheelResult)
    assert state.omega.shape == state.gravity_torque.shape == (5,)
    for result, name in [(state, "delta"), (state, "omega"), (sized, "shaft_inertia")]:
        with pytest.raises(AttributeError):
            setattr(result, name, 0.0)
    assert state == native.steady_state(omega(m.rpm), phi=phi) != native.steady_state(omega(m.rpm))
    assert sized == native.flywheel_inertia(1 / 50, omega(m.rpm)) != native.flywheel_inertia(1 / 40, omega(m.rpm))


def test_the_object_is_reused_and_thread_count_independent():
    m = machine("marine-2t-twin")
    native = native_machine(m)
    first = native.steady_state(omega(m.rpm))
    assert [native.steady_state(omega(m.rpm)) for _ in range(3)] == [first] * 3
    with ThreadPoolExecutor(4) as pool:
        assert list(pool.map(lambda _: native.steady_state(omega(m.rpm)), range(8))) == [first] * 8
    designs = {"shaft_inertia": np.linspace(100.0, 400.0, 12), "omega": omega(np.linspace(60.0, 140.0, 12))}
    outputs = ["delta", "delta_without_gravity", "delta_coasting", "omega_max", "flywheel_inertia"]
    parallel = native.sweep(designs, outputs, target_delta=1 / 50, parallel_threshold=0)
    serial = native.sweep(designs, outputs, target_delta=1 / 50, parallel_threshold=2**62)
    assert parallel.keys() == serial.keys()
    for name in parallel:
        assert parallel[name].tobytes() == serial[name].tobytes(), name
    assert native.steady_state(omega(m.rpm)) == first


def columns_of(m):
    cylinders = m.cylinders
    tables = [native_table(c.pressure) for c in cylinders]
    return {
        "units": unit_columns(cylinders),
        "bore": np.array([c.bore for c in cylinders]),
        "piston_rod_diameter": np.array([c.piston_rod_diameter for c in cylinders]),
        "pressure": tables,
        "pressure_crank_end": [None] * len(cylinders),
        "shaft_inertia": m.shaft_inertia,
        "strokes": m.strokes,
        "g": m.g,
    }


def native_table(pressure):
    return None if pressure is None else (np.array(pressure._poly.x), np.array(pressure._poly.c))


@pytest.mark.parametrize(
    ("change", "named"),
    [
        ({"shaft_inertia": 0.0}, "shaft_inertia"),
        ({"strokes": 3}, "strokes"),
        ({"g": math.nan}, "g"),
        ({"bore": np.array([0.1, 0.2, 0.3])}, "bore"),
        ({"piston_rod_diameter": np.array([0.5, 0.5])}, "piston_rod_diameter"),
        ({"strokes": 4}, "pressure of cylinder 0: breakpoints"),
    ],
)
def test_a_bad_machine_names_the_parameter(change, named):
    arguments = columns_of(machine("marine-2t-twin")) | change
    with pytest.raises(mc.MechanismError, match=named):
        NativeMachine(**arguments)


def test_bad_calls_name_the_parameter():
    m = machine("marine-2t-twin")
    native = native_machine(m)
    with pytest.raises(mc.MechanismError, match="omega_mean"):
        native.steady_state(-1.0)
    with pytest.raises(mc.MechanismError, match="min_speed_ratio"):
        native.steady_state(omega(m.rpm), min_speed_ratio=1.5)
    with pytest.raises(mc.MechanismError, match="delta"):
        native.flywheel_inertia(0.0, omega(m.rpm))
    with pytest.raises(mc.MechanismError, match='designs = "speed" is not allowed'):
        native.sweep({"speed": np.ones(2)}, ["delta"])
    with pytest.raises(mc.MechanismError, match="outputs"):
        native.sweep({"omega": np.ones(2)}, ["speed"])
    with pytest.raises(mc.MechanismError, match="shaft_inertia"):
        native.sweep({"omega": np.ones(2), "shaft_inertia": np.ones(3)}, ["delta"])
    with pytest.raises(mc.MechanismError, match="design 1: shaft_inertia"):
        native.sweep({"shaft_inertia": np.array([1.0, -1.0])}, ["delta"], omega=omega(m.rpm))
    with pytest.raises(mc.MechanismError, match="delta"):
        native.sweep({"omega": np.ones(2)}, ["flywheel_inertia"])
    with pytest.raises(TypeError, match=r'designs\["omega"\] must be a 1-D float64 array'):
        native.sweep({"omega": [1.0, 2.0]}, ["delta"])


def test_a_callable_pressure_crosses_to_rust_sampled_once():
    # A pressure callable is evaluated once, for every cylinder that shares it, on the grid of
    # multicrank.machine.native.sampled, and the core takes the polynomials through those
    # values: its gas torque is the callable's (evaluated by Python at any angle) to rounding.
    m = machine("marine-2t-twin")
    calls = []

    def pressure(theta):
        calls.append(np.size(theta))
        return 8e6 * np.exp(4 * (np.cos(theta - 0.35) - 1)) - 2e5

    smooth = m.replace(cylinders=[c.replace(pressure=pressure) for c in m.cylinders])
    native = native_machine(smooth)
    assert len(calls) == 1
    phi = np.linspace(0.0, smooth.cycle, 1001)
    core = native.steady_state(smooth.rpm, phi=phi).gas_torque
    python = smooth.gas_torque(phi)
    np.testing.assert_allclose(core, python, rtol=0, atol=1e-12 * np.abs(python).max())


# -- the core's stalls, and the sweep's two routes ------------------------------------------------


def test_a_stall_from_the_core_is_the_stall_error_with_the_lowest_speed():
    compressor = mc.presets.MACHINES["slow-compressor"]
    with pytest.raises(mc.StallError) as raised:
        mc.steady_state(compressor, rpm=0.5)
    assert "min_rpm" in str(raised.value) and raised.value.min_rpm > 0.5
    # The lowest speed that runs does run, and a little below it does not.
    assert mc.steady_state(compressor, rpm=1.01 * raised.value.min_rpm).omega_min > 0
    with pytest.raises(mc.StallError):
        mc.steady_state(compressor, rpm=0.99 * raised.value.min_rpm)


# -- a machine built once, and a result that computes what is read ------------------------------


def test_a_steady_state_computes_its_arrays_and_comparisons_only_when_read():
    machine = mc.presets.MACHINES["inline-4"]
    state = mc.steady_state(machine)
    assert "_arrays" not in state.__dict__ and "_comparisons" not in state.__dict__
    delta = state.delta
    assert "_arrays" not in state.__dict__ and "_comparisons" not in state.__dict__
    # Read later, they are those of a result that computed everything (the Python route's
    # arrays are eager: the same numbers from the other implementation, to its accuracy).
    assert state.omega.shape == (361,) and "_comparisons" not in state.__dict__
    assert state.delta_without_gravity == pytest.approx(0.007514092, rel=1e-6)
    assert state.delta == delta and not state.omega.flags.writeable
    again = mc.steady_state(machine)
    np.testing.assert_array_equal(again.acceleration, state.acceleration)


def test_a_pickled_steady_state_carries_everything():
    import pickle

    state = mc.steady_state(mc.presets.MACHINES["slow-compressor"], rpm=120)
    loaded = pickle.loads(pickle.dumps(state))
    assert loaded.delta_coasting == state.delta_coasting
    np.testing.assert_array_equal(loaded.time, state.time)
    assert loaded._later is None and loaded.summary() == state.summary()


def _counting_builds(monkeypatch: pytest.MonkeyPatch) -> list[object]:
    """The machines native.native_machine is asked to convert, from now on."""
    from multicrank.machine import native

    built: list[object] = []
    convert = native.native_machine

    def counted(machine: mc.Machine) -> NativeMachine:
        built.append(machine)
        return convert(machine)

    monkeypatch.setattr(native, "native_machine", counted)
    return built


def test_the_machine_owns_one_native_machine_for_every_question(monkeypatch):
    from multicrank.machine import native

    built = _counting_builds(monkeypatch)
    machine = mc.presets.MACHINES["inline-4"].replace(shaft_inertia=0.31)
    first = native.motion_machine(machine)
    assert native.motion_machine(machine) is first
    # g = 0 is answered by the same native machine (its tables hold the g = 0 solver): the
    # steady state, its comparisons and arrays, and the flywheel, with and without gravity.
    with_g = mc.steady_state(machine, rpm=3000)
    without = mc.steady_state(machine, rpm=3000, gravity=False)
    assert without.omega.size and math.isfinite(without.delta_coasting)  # the lazy parts too
    mc.flywheel_inertia(machine, delta=0.02, rpm=3000, gravity=False)
    assert built == [machine]
    # ... and they are the g = 0 machine's, which its own native machine gives.
    flat = mc.steady_state(machine.replace(g=0.0), rpm=3000)
    assert without.delta == pytest.approx(flat.delta, rel=1e-9)
    assert without.delta_coasting == pytest.approx(flat.delta_coasting, rel=1e-9)
    assert without.delta_without_gravity == without.delta != with_g.delta
    np.testing.assert_allclose(without.omega, flat.omega, rtol=1e-12)
    sized = mc.flywheel_inertia(machine, delta=0.02, rpm=3000, gravity=False).shaft_inertia
    flat_sized = mc.flywheel_inertia(machine.replace(g=0.0), delta=0.02, rpm=3000).shaft_inertia
    assert sized == pytest.approx(flat_sized, rel=1e-9)


def test_a_copy_of_a_machine_makes_its_own_native_machine_and_none_outlives_it():
    import copy
    import gc
    import pickle
    import weakref

    from multicrank.machine import native

    machine = mc.presets.MACHINES["inline-4"].replace(shaft_inertia=0.31)
    first = native.motion_machine(machine)
    # An equal machine is another object: its own native machine, the same numbers.
    for twin in (machine.replace(), pickle.loads(pickle.dumps(machine)), copy.deepcopy(machine)):
        assert twin == machine and "_native" not in twin.__dict__
        assert native.motion_machine(twin) is not first
        assert mc.steady_state(twin).delta == mc.steady_state(machine).delta
    assert native.motion_machine(machine) is first
    alive = weakref.ref(machine)
    del machine, first, twin
    gc.collect()
    assert alive() is None


def test_threads_share_one_native_machine_and_agree(monkeypatch):
    from threading import Barrier, Event

    from multicrank.machine import native

    built = _counting_builds(monkeypatch)
    convert = native.native_machine
    second, entered = Event(), []

    def slow(machine: mc.Machine) -> NativeMachine:
        # The first build waits (GIL released) until another thread builds too, as one
        # without the machine's lock would; with it, none does and the wait runs out.
        entered.append(machine)
        if len(entered) > 1:
            second.set()
        else:
            second.wait(1.0)
        return convert(machine)

    monkeypatch.setattr(native, "native_machine", slow)
    machine = mc.presets.MACHINES["genset-v12"].replace(shaft_inertia=41.0)
    together = Barrier(8)

    def ask(_: int) -> NativeMachine:
        together.wait()  # all eight ask at once
        return native.motion_machine(machine)

    with ThreadPoolExecutor(8) as pool:
        made = list(pool.map(ask, range(8)))
    assert built == [machine] and all(m is made[0] for m in made)
    speeds = np.linspace(900.0, 1800.0, 16)
    with ThreadPoolExecutor(4) as pool:
        found = list(pool.map(lambda rpm: mc.steady_state(machine, rpm=rpm).delta, speeds))
    assert found == [mc.steady_state(machine, rpm=rpm).delta for rpm in speeds]


# -- the core answers, and its errors are worded from what it returns ----------------------------


@pytest.mark.parametrize("drive", [500.0, mc.PowerLawLoad(torque=300.0, rpm=60.0)])
def test_a_drive_that_does_not_depend_on_phi_leaves_the_balanced_motion_as_without_it(drive):
    # Under "balance" a drive M_d(ω_m) that does not depend on φ adds M_d·φ to the work and as
    # much to the balancing load: K(φ), and with it every speed, is that of no drive (the same
    # doubles), and the load grows by M_d exactly.
    compressor = mc.presets.MACHINES["slow-compressor"]
    plain = mc.steady_state(compressor, rpm=120)
    driven = mc.steady_state(compressor, rpm=120, drive=drive)
    taken = drive if isinstance(drive, float) else float(drive(0.0, 4 * math.pi))
    assert driven.method == "energy"
    same = ("omega_mean", "omega_max", "omega_min", "phi_min", "period", "delta_without_gravity", "delta_coasting")
    for name in same:
        assert getattr(driven, name) == getattr(plain, name), name
    assert driven.mean_load_torque == pytest.approx(plain.mean_load_torque + taken, rel=1e-15, abs=1e-12)
    np.testing.assert_allclose(driven.drive_torque, taken, rtol=1e-14)  # held at ω_m (as found, to rounding)
    flywheel = mc.flywheel_inertia(compressor, delta=1 / 40, rpm=120, drive=drive)
    assert flywheel.shaft_inertia == mc.flywheel_inertia(compressor, delta=1 / 40, rpm=120).shaft_inertia


def test_an_unreachable_flywheel_target_is_worded_from_the_cores_answer():
    # The core says why (reach) and how close the machine comes (closest): there is no
    # Python solve to fall back on.
    heavy = mc.presets.MACHINES["slow-compressor"]
    with pytest.raises(mc.MechanismError, match=r"delta = 50.0 is unreachable at this speed: .* about \d") as raised:
        mc.flywheel_inertia(heavy, delta=50.0, rpm=120)
    assert "solved again" not in str(raised.value)


def test_a_design_the_core_refuses_is_named_without_solving_rows(monkeypatch):
    from multicrank.motion import _sweep_rows

    def solved_again(*args, **kwargs):
        raise AssertionError("solved again in Python")

    monkeypatch.setattr(_sweep_rows, "_solve_rows", solved_again)
    compressor = mc.presets.MACHINES["slow-compressor"]
    frame = pd.DataFrame({"rod_length": [0.6, 0.01]}, index=["good", "bad"])
    with pytest.raises(mc.MechanismError, match=r"design bad \(rod_length = 0.01\): rod_length"):
        mc.motion_sweep(compressor, frame)


class _KinkedCallable:
    """A pressure callable that names the angles of its kinks (as a wrapped diagram does)."""

    def __init__(self, diagram):
        self.diagram = diagram

    def __call__(self, theta):
        return self.diagram(theta)

    @property
    def breakpoints(self):
        return self.diagram.breakpoints

    @property
    def cycle(self):
        return self.diagram.cycle


def test_a_callable_that_names_its_kinks_is_sampled_piece_by_piece():
    """A pressure callable with ``breakpoints`` is sampled on panels cut there: each panel holds
    one cubic piece of the compressor's periodic-cubic diagrams, which the degree-7 interpolant
    reproduces, so the steady state is the diagram's own (the table route, checked against the
    independent oracle above) to rounding; cut only at the dead centres, the kinks inside the
    panels cost ~1e-7 of δ."""
    compressor = mc.presets.MACHINES["slow-compressor"]

    def wrapped(pressure):
        return None if pressure is None else _KinkedCallable(pressure)

    cylinders = [
        c.replace(pressure=wrapped(c.pressure), pressure_crank_end=wrapped(c.pressure_crank_end))
        for c in compressor.cylinders
    ]
    reference = mc.steady_state(compressor, rpm=120)
    found = mc.steady_state(compressor.replace(cylinders=cylinders), rpm=120)
    assert found.delta == pytest.approx(reference.delta, rel=1e-12)
    assert found.mean_load_torque == pytest.approx(reference.mean_load_torque, rel=1e-12)
    orders = mc.torque_orders(compressor.replace(cylinders=cylinders), 120, max_order=6)
    expected = mc.torque_orders(compressor, 120, max_order=6)
    np.testing.assert_allclose(orders["gas_amplitude"], expected["gas_amplitude"], rtol=1e-11, atol=1e-9)
