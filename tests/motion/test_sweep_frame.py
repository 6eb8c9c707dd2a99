"""The frame's outputs of mc.motion_sweep (free_force_1/2, free_moment_1/2, max_bearing_load):
every row is what mc.shaking_forces and mc.bearing_loads give for that design's machine (built
by machine_variant: a separate route through Python objects, itself tested against independent
oracles in tests/forces), for any columns, any load, any thread count."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import multicrank as mc
from multicrank.motion.variants import machine_variant
from multicrank.presets import MACHINES

FRAME = ["free_force_1", "free_force_2", "free_moment_1", "free_moment_2", "max_bearing_load"]


def expected_row(machine, design):
    variant = machine_variant(machine, design)
    rpm = design.get("rpm", machine.rpm)
    orders = mc.shaking_forces(variant, rpm, max_order=2).orders
    largest = orders["force_forward"] + orders["force_backward"]
    moment = orders["moment_forward"] + orders["moment_backward"]
    bearings = mc.bearing_loads(variant, rpm)
    return [largest[1], largest[2], moment[1], moment[2], bearings.summary["max"].max()]


@pytest.mark.parametrize(
    ("name", "axes"),
    [
        ("inline-4", {"rpm": [1500.0, 4500.0], "counterweight_mass": [0.0, 1.3, 3.0]}),
        ("boxer-compressor", {"pressure_scale": [0.5, 1.0], "rod_length": [0.3, 0.4]}),
        ("genset-v12", {"g": [0.0, 9.81], "phase[3]": [0.0, 1.0]}),
        # Phases alone (a firing order's candidates: each unit's throw loads made once per
        # phase it takes), at the machine's speed and at one speed given as a column.
        ("genset-v12", {"phase[3]": [0.0, 1.0, 2.5], "phase[7]": [0.0, 0.7]}),
        ("inline-6", {"rpm": [1200.0], "phase[1]": [0.0, 2.0], "phase[4]": [0.3, 4.0]}),
    ],
)
def test_every_row_is_its_machines_forces_and_bearing_loads(name, axes):
    machine = MACHINES[name]
    grid = mc.MachineGrid(machine, **axes)
    found = mc.motion_sweep(machine, grid, outputs=FRAME)
    assert list(found.columns[-len(FRAME) :]) == FRAME
    for _, row in found.iterrows():
        design = {key: row[key] for key in axes}
        np.testing.assert_allclose(
            row[FRAME].to_numpy(dtype=float), expected_row(machine, design), rtol=1e-12, atol=1e-9
        )


def test_the_frame_beside_the_steady_state_and_with_any_load():
    machine = MACHINES["inline-4"]
    grid = mc.MachineGrid(machine, counterweight_mass=[0.5, 2.0])
    both = mc.motion_sweep(machine, grid, outputs=["delta", "free_force_1", "max_bearing_load"])
    assert list(both.columns) == [
        "counterweight_mass",
        "delta",
        "stalled",
        "near_stall",
        "free_force_1",
        "max_bearing_load",
    ]
    alone = mc.motion_sweep(machine, grid, outputs=["delta"])
    np.testing.assert_array_equal(both["delta"], alone["delta"])
    fan = mc.PowerLawLoad(torque=40.0, rpm=3000.0)
    loaded = mc.motion_sweep(machine, grid, outputs=["free_force_1", "max_bearing_load"], load=fan)
    np.testing.assert_array_equal(loaded["max_bearing_load"], both["max_bearing_load"])


def test_the_columns_do_not_depend_on_the_thread_count():
    machine = MACHINES["genset-v12"]
    grid = mc.MachineGrid(machine, rpm=np.linspace(600.0, 1800.0, 40), counterweight_mass=[1.0, 3.0])
    before = mc.get_parallel_threshold()
    try:
        mc.set_parallel_threshold(2**62)
        serial = mc.motion_sweep(machine, grid, outputs=FRAME)
        mc.set_parallel_threshold(1)
        parallel = mc.motion_sweep(machine, grid, outputs=FRAME)
    finally:
        mc.set_parallel_threshold(before)
    pd.testing.assert_frame_equal(serial, parallel)


def test_the_frame_needs_a_speed_and_names_a_bad_row():
    no_speed = MACHINES["inline-4"].replace(rpm=None, rpm_range=None, delta_target=None)
    with pytest.raises(mc.MechanismError, match="rpm"):
        mc.motion_sweep(no_speed, mc.MachineGrid(no_speed, counterweight_mass=[1.0]), outputs=["free_force_1"])
    machine = MACHINES["inline-4"]
    with pytest.raises(mc.MechanismError, match="rod_length"):
        mc.motion_sweep(machine, pd.DataFrame({"rod_length": [0.14, 0.01]}), outputs=["max_bearing_load"])


def test_the_outputs_are_listed():
    assert mc.MOTION_SWEEP_OUTPUTS[-len(FRAME) :] == tuple(FRAME)
    default = mc.motion_sweep(MACHINES["inline-4"], mc.MachineGrid(MACHINES["inline-4"], rpm=[3000.0]))
    assert not set(FRAME) & set(default.columns)  # asked for by name only
