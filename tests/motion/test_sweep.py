"""mc.motion_sweep and mc.MachineGrid: every row is the steady state (and the flywheel) of the
same machine built by hand, stalls are rows, bad input is refused by name, and the sweep
streams to Parquet, resumes only itself, runs on dask and converts to xarray."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import multicrank as mc
from multicrank.motion import sweep as motion_sweep_module
from multicrank.motion.variants import ScaledPressure, machine_columns, machine_variant

COMPRESSOR = mc.presets.MACHINES["slow-compressor"]  # two-stroke, one double-acting cylinder
INLINE_4 = mc.presets.MACHINES["inline-4"]  # four-stroke
V12 = mc.presets.MACHINES["genset-v12"]  # a V (v12-60), four-stroke
RTOL = 1e-12  # the contract: every row equals steady_state to 1e-12 relative
DELTA_ATOL = 1e-15  # and a few ε absolute for a δ (see assert_rows_match)


def expected_row(machine: mc.Machine, design: dict, load="balance", delta=None) -> dict:
    """The outputs of one design, by steady_state and flywheel_inertia of its machine."""
    variant = machine_variant(machine, design)
    rpm = design.get("rpm")
    row: dict = {}
    try:
        state = mc.steady_state(variant, rpm=rpm, load=load)
    except mc.StallError:
        row.update(
            dict.fromkeys(("delta", "delta_without_gravity", "rpm_min", "rpm_max"), math.nan),
            stalled=True,
            near_stall=False,
        )
    else:
        row.update(
            delta=state.delta,
            delta_without_gravity=state.delta_without_gravity,
            delta_coasting=state.delta_coasting,
            gravity_effect=state.delta / state.delta_without_gravity - 1,
            rpm_min=state.omega_min * 30 / math.pi,
            rpm_max=state.omega_max * 30 / math.pi,
            stalled=False,
            near_stall=state.delta > 0.5,
        )
    if delta is not None:
        sized = mc.flywheel_inertia(variant, delta=delta, rpm=rpm, load=load)
        row.update(
            flywheel_inertia=sized.shaft_inertia, flywheel_inertia_without_gravity=sized.shaft_inertia_without_gravity
        )
    return row


def assert_rows_match(machine: mc.Machine, result: pd.DataFrame, load="balance", delta=None) -> None:
    known = machine_columns(machine)
    names = [c for c in result.columns if c in known]
    for _, row in result.iterrows():
        expected = expected_row(machine, {n: row[n] for n in names}, load, delta)
        for name, value in expected.items():
            if name not in result.columns:
                continue
            if name in ("stalled", "near_stall"):
                assert bool(row[name]) is value, name
            elif name == "gravity_effect":
                # δ/δ₀ − 1 cancels where gravity changes little: δ/δ₀ itself to RTOL (a
                # pressure_scale row's diagrams are the base's coefficients scaled, the
                # variant's re-interpolated from scaled pressures: equal to rounding).
                np.testing.assert_allclose(1 + row[name], 1 + value, rtol=RTOL, atol=0, err_msg=name)
            elif name.startswith("delta"):
                # δ = (ω_max − ω_min)/ω_m is a difference of speeds: its rounding is absolute,
                # a few ε (a δ of 1e-5 is known to ~1e-11 relative, no better).
                np.testing.assert_allclose(row[name], value, rtol=RTOL, atol=DELTA_ATOL, err_msg=name)
            else:
                np.testing.assert_allclose(row[name], value, rtol=RTOL, atol=0, err_msg=name)


# -- the rows are steady states ------------------------------------------------------------------


@st.composite
def designs(draw):
    """A base machine and a small table of random variants of it."""
    machine = draw(st.sampled_from([COMPRESSOR, INLINE_4, V12]))
    cylinder = machine.cylinders[0]
    factor = st.floats(0.6, 1.6)
    columns = draw(
        st.sets(
            st.sampled_from(
                ["shaft_inertia", "rpm", "g", "pressure_scale", "piston_mass", "rod_mass", "counterweight_mass"]
            ),
            min_size=1,
            max_size=4,
        )
    )
    # A cylinder's own phase (a firing order) and counterweight, on a cylinder drawn.
    unit = draw(st.integers(0, len(machine) - 1))
    own = draw(st.sets(st.sampled_from([f"phase[{unit}]", f"counterweight_mass[{unit}]"]), max_size=2))
    rows = draw(st.integers(1, 2))
    base = {
        "shaft_inertia": machine.shaft_inertia,
        "rpm": machine.rpm,
        "g": mc.STANDARD_GRAVITY,
        "pressure_scale": 1.0,
        "piston_mass": cylinder.piston_mass,
        "rod_mass": cylinder.rod_mass,
        "counterweight_mass": max(cylinder.counterweight_mass, 1.0),
    }
    table = {name: [base[name] * draw(factor) for _ in range(rows)] for name in sorted(columns)}
    for name in sorted(own):
        if name.startswith("phase"):
            # Moved by a turn (another firing order of a four-stroke) or anywhere.
            moves = st.sampled_from([0.0, 2 * math.pi]) | st.floats(-7.0, 7.0)
            table[name] = [machine.cylinders[unit].phase + draw(moves) for _ in range(rows)]
        else:
            table[name] = [draw(st.floats(0.0, 2.0)) * max(machine.cylinders[unit].counterweight_mass, 1.0)
                           for _ in range(rows)]  # fmt: skip
    return machine, pd.DataFrame(table)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(designs())
def test_every_row_is_the_steady_state_of_its_machine(case):
    machine, table = case
    result = mc.motion_sweep(machine, table, chunk_size=1)
    assert list(result.columns) == [*table.columns, *mc.MOTION_SWEEP_OUTPUTS[:8]]
    pd.testing.assert_frame_equal(result[table.columns], table)
    assert_rows_match(machine, result)


@pytest.mark.parametrize("machine", [INLINE_4, COMPRESSOR, V12], ids=["inline-4", "compressor", "v12"])
def test_designs_that_differ_in_pressure_or_bore_are_each_their_own_machine(machine):
    # In one chunk the core shares one gas (and J, U) among designs that differ only in
    # pressure_scale (and bore, where no crank end has a piston rod: the compressor keys its
    # bore), scaled: each row is still the steady state and flywheel of its own machine.
    bore = machine.cylinders[0].bore
    grid = mc.MachineGrid(
        machine,
        pressure_scale=[0.6, 1.0, 1.4],
        bore=bore * np.array([0.95, 1.0, 1.08]),
        rpm=[machine.rpm, 1.3 * machine.rpm],
    )
    outputs = [*mc.MOTION_SWEEP_OUTPUTS[:8], "flywheel_inertia", "flywheel_inertia_without_gravity"]
    assert_rows_match(machine, mc.motion_sweep(machine, grid, delta_target=0.005, outputs=outputs), delta=0.005)


@pytest.mark.parametrize("machine", [INLINE_4, COMPRESSOR, V12], ids=["inline-4", "compressor", "v12"])
def test_designs_that_differ_in_webs_and_counterweights_are_each_their_own_machine(machine):
    # In one chunk the core gives designs that differ only in crank webs and counterweights
    # one machine's J, panels and gas, with their own U (the first moments enter it alone):
    # each row is still the steady state and flywheel of its own machine.
    cylinder = machine.cylinders[0]
    grid = mc.MachineGrid(
        machine,
        counterweight_mass=[0.0, 1.0, 4.0],
        counterweight_radius=[0.5 * cylinder.crank_radius, cylinder.crank_radius],
        **{"counterweight_mass[0]": [0.0, 2.5]},
        crank_mass=[cylinder.crank_mass, cylinder.crank_mass + 1.0],
        rpm=[machine.rpm, 1.3 * machine.rpm],
    )
    outputs = [*mc.MOTION_SWEEP_OUTPUTS[:8], "flywheel_inertia", "flywheel_inertia_without_gravity"]
    assert_rows_match(machine, mc.motion_sweep(machine, grid, delta_target=0.005, outputs=outputs), delta=0.005)


def test_machine_variant_is_the_machine_built_by_hand():
    design = {"shaft_inertia": 300.0, "g": 5.0, "piston_mass": 90.0, "bore": 0.25, "pressure_scale": 1.3, "rpm": 100.0}
    cylinders = [
        c.replace(
            piston_mass=90.0,
            bore=0.25,
            pressure=c.pressure.scaled(1.3),
            pressure_crank_end=c.pressure_crank_end.scaled(1.3),
        )
        for c in COMPRESSOR.cylinders
    ]
    assert machine_variant(COMPRESSOR, design) == COMPRESSOR.replace(cylinders=cylinders, shaft_inertia=300.0, g=5.0)
    assert machine_variant(COMPRESSOR, {"rpm": 100.0}) is COMPRESSOR


def test_a_column_of_one_cylinder_sets_that_cylinder_alone():
    design = {
        "counterweight_mass": 3.0,
        "counterweight_mass[2]": 1.5,
        "phase[3]": 0.25,
        "counterweight_radius[0]": 0.05,
    }
    cylinders = list(INLINE_4.cylinders)
    cylinders = [c.replace(counterweight_mass=3.0) for c in cylinders]
    cylinders[2] = cylinders[2].replace(counterweight_mass=1.5)
    cylinders[3] = cylinders[3].replace(phase=0.25)
    cylinders[0] = cylinders[0].replace(counterweight_radius=0.05)
    assert machine_variant(INLINE_4, design) == INLINE_4.replace(cylinders=cylinders)
    with pytest.raises(mc.MechanismError, match=r"phase\[4\]"):
        machine_variant(INLINE_4, {"phase[4]": 0.0})
    with pytest.raises(mc.MechanismError, match=r"phase\[4\]"):
        mc.motion_sweep(INLINE_4, pd.DataFrame({"phase[4]": [0.0]}))
    with pytest.raises(mc.MechanismError, match=r"crank_mass\[0\]"):
        mc.MachineGrid(INLINE_4, **{"crank_mass[0]": [1.0, 2.0]})
    grid = mc.MachineGrid(INLINE_4, **{"counterweight_mass[1]": [0.0, 2.0], "phase[2]": 0.5})
    assert_rows_match(INLINE_4, mc.motion_sweep(INLINE_4, grid, outputs="delta"))


def test_a_grid_with_the_flywheel_matches_flywheel_inertia():
    grid = mc.MachineGrid(COMPRESSOR, rpm=[100.0, 140.0], counterweight_mass=[10.0, 50.0])
    result = mc.motion_sweep(COMPRESSOR, grid, delta_target=1 / 40)
    # every output but the frame's, which are asked for by name only
    frame = ("free_force_1", "free_force_2", "free_moment_1", "free_moment_2", "max_bearing_load")
    expected = [o for o in mc.MOTION_SWEEP_OUTPUTS if o not in frame]
    assert list(result.columns) == ["rpm", "counterweight_mass", *expected]
    assert_rows_match(COMPRESSOR, result, delta=1 / 40)
    only = mc.motion_sweep(COMPRESSOR, grid, delta_target=1 / 40, outputs="flywheel_inertia")
    assert list(only.columns) == ["rpm", "counterweight_mass", "flywheel_inertia"]  # no steady state asked
    np.testing.assert_array_equal(only["flywheel_inertia"], result["flywheel_inertia"])


def test_the_target_delta_given_as_delta_is_deprecated_and_the_same_sweep():
    """``delta=`` names the result column δ; the target is ``delta_target=`` (issue 27, item 7)."""
    grid = mc.MachineGrid(COMPRESSOR, rpm=[100.0, 140.0])
    new = mc.motion_sweep(COMPRESSOR, grid, delta_target=1 / 40, outputs="flywheel_inertia")
    with pytest.warns(DeprecationWarning, match=r"motion_sweep\(delta=\) is deprecated.* use delta_target="):
        old = mc.motion_sweep(COMPRESSOR, grid, delta=1 / 40, outputs="flywheel_inertia")
    pd.testing.assert_frame_equal(old, new)
    with pytest.raises(mc.MechanismError, match="give exactly one of delta_target and delta"):
        mc.motion_sweep(COMPRESSOR, grid, delta_target=1 / 40, delta=1 / 40)


def test_a_square_law_load_fixes_the_speed():
    engine = mc.presets.MACHINES["marine-2t-twin"]
    propeller = mc.PowerLawLoad(torque=2600.0, rpm=300)
    table = pd.DataFrame({"pressure_scale": [0.8, 1.0]})
    result = mc.motion_sweep(engine, table, load=propeller, outputs=["delta", "rpm_min", "rpm_max"])
    assert_rows_match(engine, result, load=propeller)
    assert result["rpm_max"].iloc[0] < result["rpm_max"].iloc[1]  # less gas, less speed
    with pytest.raises(mc.MechanismError, match="rpm column is not allowed"):
        mc.motion_sweep(engine, pd.DataFrame({"rpm": [100.0]}), load=propeller)


def test_a_design_that_stalls_is_a_row_and_the_sweep_goes_on():
    grid = mc.MachineGrid(COMPRESSOR, rpm=[5.0, 120.0], shaft_inertia=[20.0, 350.0])
    result = mc.motion_sweep(COMPRESSOR, grid, chunk_size=3)
    assert result["stalled"].tolist() == [True, True, False, False]
    for name in ("delta", "delta_without_gravity", "delta_coasting", "gravity_effect", "rpm_min", "rpm_max"):
        assert result[name].iloc[:2].isna().all(), name
        assert result[name].iloc[2:].notna().all(), name
    assert result["stalled"].dtype == bool
    assert_rows_match(COMPRESSOR, result.iloc[2:])


# -- the grid --------------------------------------------------------------------------------------


def test_machine_grid_is_a_lazy_product_equal_by_value():
    grid = mc.MachineGrid(COMPRESSOR, shaft_inertia=[250.0, 350.0], rpm=range(100, 160, 20), g=0.0)
    assert len(grid) == 6 and grid.shape == (2, 3)
    assert grid.frame(4).to_dict("list") == {"shaft_inertia": [350.0, 350.0], "rpm": [120, 140], "g": [0.0, 0.0]}
    assert grid == mc.MachineGrid(COMPRESSOR, shaft_inertia=[250.0, 350.0], rpm=range(100, 160, 20), g=0.0)
    assert grid != mc.MachineGrid(COMPRESSOR, shaft_inertia=[250.0, 350.0], rpm=range(100, 160, 20), g=1.0)
    assert grid != mc.MachineGrid(
        COMPRESSOR.replace(name="other"), shaft_inertia=[250.0, 350.0], rpm=range(100, 160, 20), g=0.0
    )
    assert grid != mc.DesignGrid(crank_ratio=[0.2, 0.3], inclination=0.0, u1=0.0, u2=0.0)
    assert pickle.loads(pickle.dumps(grid)) == grid


def test_unknown_columns_are_refused_by_name():
    with pytest.raises(mc.MechanismError, match=r"'piston_mas' is not a machine column \(did you mean 'piston_mass'"):
        mc.MachineGrid(COMPRESSOR, piston_mas=[80.0, 90.0])
    with pytest.raises(mc.MechanismError, match=r"unknown column\(s\) 'rpms' \(did you mean 'rpm'"):
        mc.motion_sweep(COMPRESSOR, pd.DataFrame({"rpms": [100.0]}))
    labelled = mc.motion_sweep(
        COMPRESSOR, pd.DataFrame({"rpm": [100.0], "label": ["a"]}), passthrough="label", outputs="delta"
    )
    assert labelled["label"].tolist() == ["a"]


@pytest.mark.parametrize(
    ("axes", "match"),
    [
        ({"rod_length": [0.6, 0.1]}, r"design 1 \(.*rod_length = 0.1\): rod_length .*crank_radius"),
        ({"shaft_inertia": [350.0, -1.0]}, "shaft_inertia"),
        ({"rpm": [120.0, 0.0]}, "rpm"),
        ({"piston_mass": [80.0, math.nan]}, "piston_mass"),
        ({"pressure_scale": [1.0, math.inf]}, "pressure_scale"),
    ],
)
def test_a_bad_value_anywhere_on_an_axis_is_refused_up_front(axes, match):
    with pytest.raises(mc.MechanismError, match=match):
        mc.MachineGrid(COMPRESSOR, counterweight_mass=[20.0, 30.0, 40.0], **axes)


def test_bad_input_names_the_parameter():
    grid = mc.MachineGrid(COMPRESSOR, rpm=[100.0, 120.0])
    cases = [
        (dict(machine="slow-compressor"), "machine"),
        (dict(outputs=["delta", "speed"]), "outputs"),
        (dict(outputs="flywheel_inertia"), "need delta_target="),
        (dict(delta_target=1 / 40, outputs="delta"), "delta_target= is given"),
        (dict(delta_target=-1.0), "delta_target = -1.0 is out of range"),
        (dict(chunk_size=0), "chunk_size"),
        (dict(load=100.0), "load"),
        (dict(resume=True), "resume=True needs out="),
        (dict(designs=[1, 2]), "designs"),
        (dict(designs=mc.MachineGrid(INLINE_4, rpm=[3000.0])), "another machine"),
    ]
    for change, match in cases:
        arguments = dict(machine=COMPRESSOR, designs=grid) | change
        machine, designs = arguments.pop("machine"), arguments.pop("designs")
        with pytest.raises(mc.MechanismError, match=match):
            mc.motion_sweep(machine, designs, **arguments)
    without_rpm = COMPRESSOR.replace(rpm=None, rpm_range=None)
    with pytest.raises(mc.MechanismError, match="rpm is required"):
        mc.motion_sweep(without_rpm, pd.DataFrame({"shaft_inertia": [300.0]}))


def test_pressure_scale_scales_diagrams_and_callables():
    diagram = COMPRESSOR.cylinders[0].pressure
    doubled = diagram.scaled(2.0)
    np.testing.assert_array_equal(doubled.pressure, 2.0 * diagram.pressure)
    assert doubled.kind == diagram.kind and doubled.cycle == diagram.cycle
    assert diagram.scaled(1.0) is diagram
    with pytest.raises(mc.MechanismError, match="factor"):
        diagram.scaled(math.nan)
    wrapped = ScaledPressure(np.cos, 3.0)
    assert pickle.loads(pickle.dumps(wrapped)) == wrapped
    np.testing.assert_array_equal(wrapped(np.array([0.0, 1.0])), 3.0 * np.cos([0.0, 1.0]))


# -- Parquet, dask, xarray -------------------------------------------------------------------------


def test_parquet_streams_resumes_and_refuses_another_sweep(tmp_path, monkeypatch):
    pytest.importorskip("pyarrow")
    grid = mc.MachineGrid(COMPRESSOR, shaft_inertia=[250.0, 350.0], rpm=[90.0, 120.0, 150.0])
    whole = mc.motion_sweep(COMPRESSOR, grid, out=tmp_path / "whole.parquet", chunk_size=2)
    expected = mc.motion_sweep(COMPRESSOR, grid, chunk_size=2)
    pd.testing.assert_frame_equal(pd.read_parquet(whole), expected.reset_index(drop=True))

    target = tmp_path / "run.parquet"
    solve = motion_sweep_module._solve_chunk
    calls = []

    def interrupted(machine, frame, *args):
        calls.append(frame.index[0])
        if len(calls) == 2:
            raise KeyboardInterrupt
        return solve(machine, frame, *args)

    monkeypatch.setattr(motion_sweep_module, "_solve_chunk", interrupted)
    with pytest.raises(KeyboardInterrupt):
        mc.motion_sweep(COMPRESSOR, grid, out=target, chunk_size=2)
    monkeypatch.setattr(motion_sweep_module, "_solve_chunk", solve)
    assert not target.exists() and len(list((tmp_path / "run.parquet.parts").glob("part-*"))) == 1

    changed_axis = mc.MachineGrid(COMPRESSOR, shaft_inertia=[250.0, 351.0], rpm=[90.0, 120.0, 150.0])
    heavier = COMPRESSOR.replace(g=9.9)
    for machine, designs in ((COMPRESSOR, changed_axis), (heavier, mc.MachineGrid(heavier, **grid.axes))):
        with pytest.raises(mc.MechanismError, match=r"cannot resume.*differ"):
            mc.motion_sweep(machine, designs, out=target, chunk_size=2, resume=True)
    with pytest.raises(mc.MechanismError, match="cannot resume"):
        mc.motion_sweep(COMPRESSOR, grid, out=target, chunk_size=2, resume=True, delta_target=1 / 40)

    mc.motion_sweep(COMPRESSOR, grid, out=target, chunk_size=2, resume=True)
    assert target.read_bytes() == whole.read_bytes()


def test_dask_on_a_local_cluster_matches_in_process():
    dd = pytest.importorskip("dask.dataframe")
    distributed = pytest.importorskip("distributed")
    table = mc.MachineGrid(COMPRESSOR, rpm=[5.0, 90.0, 120.0], piston_mass=[60.0, 85.0]).to_frame()
    table["label"] = [f"design {i}" for i in range(len(table))]
    expected = mc.motion_sweep(COMPRESSOR, table, passthrough="label")
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None)
    with cluster, distributed.Client(cluster):
        lazy = mc.motion_sweep(COMPRESSOR, dd.from_pandas(table, npartitions=3), passthrough="label")
        assert isinstance(lazy, dd.DataFrame)
        result = lazy.compute()
    pd.testing.assert_frame_equal(result.sort_index(), expected, check_exact=True, check_dtype=False)
    assert result["stalled"].sum() == 2


def test_to_xarray_labels_the_axes_of_a_grid():
    pytest.importorskip("xarray")
    grid = mc.MachineGrid(COMPRESSOR, shaft_inertia=[250.0, 350.0], rpm=[5.0, 90.0, 120.0], g=0.0)
    data = mc.to_xarray(mc.motion_sweep(COMPRESSOR, grid, outputs=["delta", "rpm_min"]))
    assert dict(data.sizes) == {"shaft_inertia": 2, "rpm": 3}
    assert sorted(data.data_vars) == ["delta", "near_stall", "rpm_min", "stalled"]
    assert data["stalled"].sel(rpm=5.0).all() and not data["stalled"].sel(rpm=120.0).any()


def test_a_machine_grid_checks_each_axis_at_its_extremes_not_every_value(monkeypatch):
    """A long axis is checked by building machines at its extremes only (building one per value
    took 13 s for 20 000 speeds), and a value that breaks a rule between fields (λ = r/l < 1)
    is still found where it stands in the middle of its axis."""
    from multicrank.motion import variants

    built = []
    real = variants.row_variant
    monkeypatch.setattr(variants, "row_variant", lambda *args: built.append(args[-1]) or real(*args))
    engine = mc.presets.MACHINES["inline-4"]
    grid = mc.MachineGrid(engine, rpm=np.linspace(1000, 6000, 20_000), shaft_inertia=[0.2, 0.3, 0.25])
    assert len(grid) == 60_000
    assert len(built) <= 2 * 2 + 2
    with pytest.raises(mc.MechanismError, match=r"rod_length = 0\.03 is out of range"):
        mc.MachineGrid(engine, rpm=[1000, 2000], rod_length=[0.2, 0.18, 0.03, 0.15])
