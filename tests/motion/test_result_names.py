"""Numbers named for what they are: δ of the machine coasting is ``delta_coasting`` (formerly
``delta_gravity_only``, which it never was: with g = 0 it is J(φ)'s alone), gravity's effect
on δ is the fraction ``gravity_effect`` in every output, and a δ above
``mc.NEAR_STALL_DELTA`` is said to be near a stall wherever δ is shown. The machines: the slow
compressor at the two mean speeds where δ = 0.55 and 0.45 (found by brentq), either side of
the threshold."""

from __future__ import annotations

import io
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.optimize import brentq

import multicrank as mc
from multicrank.machine.native import motion_machine
from multicrank.motion.steady import NEAR_STALL_NOTE
from multicrank.presets import MACHINES

SCRIPT = Path(sys.executable).with_name("multicrank")
COMPRESSOR = MACHINES["slow-compressor"]
NOTE = "near a stall"  # what every note of a δ above the threshold says


def run(*args: str) -> subprocess.CompletedProcess:
    result = subprocess.run([str(SCRIPT), *args], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    return result


@pytest.fixture(scope="module")
def speeds() -> tuple[float, float]:
    """The slow compressor's mean speeds [rpm] of δ = 0.55 (near a stall) and δ = 0.45 (not)."""

    def at(delta: float) -> float:
        return round(brentq(lambda n: mc.steady_state(COMPRESSOR, rpm=n).delta - delta, 15.0, 120.0), 3)

    return at(0.55), at(0.45)


def test_the_threshold_is_one_documented_constant():
    assert mc.NEAR_STALL_DELTA == 0.5 and "NEAR_STALL_DELTA" in mc.__all__
    assert NEAR_STALL_NOTE.startswith(f"δ > {mc.NEAR_STALL_DELTA:g}: {NOTE}")


def test_the_steady_state_says_near_a_stall_above_the_threshold_only(speeds):
    near, clear = (mc.steady_state(COMPRESSOR, rpm=n) for n in speeds)
    assert near.delta > 0.5 > clear.delta
    assert near.near_stall and not clear.near_stall
    assert NOTE in near.summary() and NOTE in repr(near)
    assert NOTE not in clear.summary()
    assert near.to_pandas().attrs["near_stall"] == 1 and clear.to_pandas().attrs["near_stall"] == 0


def test_motion_sweep_marks_near_stall_designs_by_either_route(speeds):
    grid = mc.MachineGrid(COMPRESSOR, rpm=[*speeds, 5.0])  # 5 rpm stalls
    native = mc.motion_sweep(COMPRESSOR, grid)
    assert list(native.columns) == ["rpm", *mc.MOTION_SWEEP_OUTPUTS[:8]]
    assert native["near_stall"].tolist() == [True, False, False] and native["stalled"].tolist() == [False] * 2 + [True]
    # A callable pressure (the table behind a lambda): it crosses to the core sampled, and the
    # rows ask only for near_stall.
    table = COMPRESSOR.cylinders[0].pressure
    by_callable = COMPRESSOR.replace(cylinders=[COMPRESSOR.cylinders[0].replace(pressure=lambda t: table(t))])
    assert motion_machine(by_callable) is not None
    rows = mc.motion_sweep(by_callable, pd.DataFrame({"rpm": [*speeds, 5.0]}), outputs=["near_stall"])
    assert list(rows.columns) == ["rpm", "delta", "stalled", "near_stall"]  # near_stall brings δ
    assert rows["near_stall"].tolist() == [True, False, False]
    np.testing.assert_allclose(rows["delta"][:2], native["delta"][:2], rtol=1e-6)


def test_the_old_output_name_warns_and_gives_delta_coasting():
    grid = mc.MachineGrid(COMPRESSOR, rpm=[90.0, 120.0])
    assert "delta_gravity_only" not in mc.MOTION_SWEEP_OUTPUTS
    with pytest.warns(DeprecationWarning, match="'delta_gravity_only' is deprecated .* use 'delta_coasting'") as caught:
        result = mc.motion_sweep(COMPRESSOR, grid, outputs=["delta_gravity_only"])
    assert caught[0].filename == __file__  # it points at the caller's line
    assert list(result.columns) == ["rpm", "delta_coasting", "stalled"]
    for rpm, value in zip(result["rpm"], result["delta_coasting"], strict=True):
        assert value == mc.steady_state(COMPRESSOR, rpm=rpm).delta_coasting


def test_delta_coasting_is_delta_without_gas_in_a_sweep():
    # pressure_scale 0 takes the gas away, and with it the balance load: δ of that design is
    # δ_coasting of the machine as built, at the same speed — with g = 0 too (J(φ) alone).
    for g in (mc.STANDARD_GRAVITY, 0.0):
        grid = mc.MachineGrid(COMPRESSOR, pressure_scale=[0.0, 1.0], rpm=[60.0, 120.0], g=g)
        result = mc.motion_sweep(COMPRESSOR, grid, outputs=["delta", "delta_coasting"])
        without_gas, as_built = result.iloc[:2], result.iloc[2:]
        np.testing.assert_allclose(without_gas["delta"], as_built["delta_coasting"], rtol=1e-9)
        assert (as_built["delta_coasting"] > 1e-3).all()


def test_the_square_law_route_names_delta_coasting():
    # The core returns the comparisons with the square law's solution (its own key): the
    # coasting machine is the one without gas and load, at the speed the load settles to.
    fan = mc.PowerLawLoad(torque=90.0, rpm=120)
    state = mc.steady_state(COMPRESSOR, load=fan, drive=1000.0)
    assert state.method == "closed form"
    no_gas = COMPRESSOR.replace(
        cylinders=[c.replace(pressure=None, pressure_crank_end=None) for c in COMPRESSOR.cylinders]
    )
    assert state.delta_coasting == pytest.approx(mc.steady_state(no_gas, rpm=state.rpm).delta, rel=1e-9)


def test_motion_command_names_and_notes(speeds):
    near, clear = speeds
    csv = run("motion", "--rpm", str(near), "--rpm", str(clear), "--format", "csv", "--no-progress")
    frame = pd.read_csv(io.StringIO(csv.stdout), index_col="rpm")
    assert {"gravity_effect", "delta_coasting", "near_stall"} <= set(frame.columns)
    assert not {"gravity_change_percent", "delta_gravity_only"} & set(frame.columns)
    for rpm in speeds:
        state = mc.steady_state(COMPRESSOR, rpm=rpm)
        row = frame.loc[rpm]
        assert row["gravity_effect"] == pytest.approx(state.delta / state.delta_without_gravity - 1, rel=1e-9)
        assert row["delta_coasting"] == pytest.approx(state.delta_coasting, rel=1e-10)
        assert bool(row["near_stall"]) == (state.delta > 0.5)
    assert NOTE in csv.stderr and f"{near:g}" in csv.stderr
    table = run("motion", "--rpm", str(near), "--rpm", str(clear), "--no-progress").stdout
    assert NOTE in table and "gravity_effect" in table and "delta_coasting" in table
    data = json.loads(run("motion", "--rpm", str(clear), "--format", "json", "--no-progress").stdout)
    assert data["near_stall_delta"] == 0.5 and data["rows"][0]["near_stall"] is False
    assert {"gravity_effect", "delta_coasting"} <= set(data["rows"][0])
    assert NOTE not in run("motion", "--rpm", str(clear), "--no-progress").stdout


def test_sweep_motion_command_names_and_notes(speeds):
    near, clear = speeds
    axis = f"{near},{clear}"
    csv = run("sweep", "motion", "--rpm", axis, "--outputs", "delta_gravity_only,delta", "--format", "csv",
              "--no-progress")  # fmt: skip
    frame = pd.read_csv(io.StringIO(csv.stdout), index_col=0)
    assert list(frame.columns) == ["rpm", "delta", "delta_coasting", "stalled", "near_stall"]
    assert frame["near_stall"].tolist() == [True, False]
    assert "delta_gravity_only is now delta_coasting" in csv.stderr and NOTE in csv.stderr
    expected = mc.motion_sweep(COMPRESSOR, mc.MachineGrid(COMPRESSOR, rpm=[near, clear]), outputs=["delta_coasting"])
    np.testing.assert_allclose(frame["delta_coasting"], expected["delta_coasting"], rtol=1e-10)
    table = run("sweep", "motion", "--rpm", axis, "--no-progress").stdout
    assert "1 of 2 designs near_stall" in table and NOTE in table and "delta_coasting" in table
    data = json.loads(run("sweep", "motion", "--rpm", str(clear), "--format", "json", "--no-progress").stdout)
    assert {"delta_coasting", "gravity_effect", "near_stall"} <= set(data["rows"][0])


def test_the_design_aid_marks_near_stall(speeds):
    from multicrank.report.design import DesignResults, _firing_html

    near, clear = speeds
    for rpm, flagged in ((near, True), (clear, False)):
        firing = mc.firing_orders(COMPRESSOR, rpm=rpm)
        assert firing["near_stall"].tolist() == [flagged]
        page = _firing_html(DesignResults(machine=COMPRESSOR, rpm=rpm, firing=firing, own=0, optimum=None))
        assert (NOTE in page) == flagged and ("†" in page) == flagged
        printed = run("optimize", "firing", "--machine", "slow-compressor", "--rpm", str(rpm), "--no-progress")
        assert (NOTE in printed.stdout) == flagged and "near_stall" in printed.stdout


def test_the_report_says_near_a_stall():
    from multicrank.report.motion import motion_html, motion_results
    from multicrank.report.settings import ReportSettings

    figures = dict.fromkeys(
        ("motion_speed", "motion_torques", "motion_speed_range", "motion_gravity_map", "motion_orders"), "x.png"
    )
    # A light flywheel (δ ≈ 0.9 at 120 rpm), and the compressor as built (δ ≈ 0.03).
    light = COMPRESSOR.replace(shaft_inertia=10.0, rpm_range=(100.0, 200.0))
    for machine, flagged in ((light, True), (COMPRESSOR.replace(rpm_range=(100.0, 200.0)), False)):
        results = motion_results(ReportSettings(machine=machine, gravity_map_points=2), speeds=3)
        assert results.state.near_stall == flagged
        assert results.speeds["near_stall"].any() == flagged and "delta_coasting" in results.speeds
        page = motion_html(results, machine, figures, 1e-3)
        assert (NOTE in page) == flagged
        assert "gravity alone" not in page and "δ coasting" in page
