"""Design sweeps: per-design agreement with the reference, streaming to Parquet with resume,
interruption, grids and xarray, a real Dask cluster, and the CLI."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest

import multicrank as mc
import multicrank.reference as ref

SCRIPT = Path(sys.executable).with_name("multicrank")


def random_designs(n: int, seed: int = 0) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    return pd.DataFrame(
        {
            "crank_ratio": rng.uniform(0, 0.9, n),
            "inclination": rng.uniform(-np.pi, np.pi, n),
            "u1": rng.uniform(0, 1, n),
            "u2": rng.uniform(-0.5, 0.5, n),
            "cranks": rng.integers(1, 13, n),
            "strokes": rng.choice([2, 4], n),
            "acting": rng.choice(["single", "double"], n),
            "label": [f"m{i}" for i in range(n)],  # carried through with passthrough="label"
        }
    )


def per_design(row, phi):
    phases = mc.crank_phases(int(row.cranks), int(row.strokes), row.acting)
    design = dict(crank_ratio=row.crank_ratio, inclination=row.inclination, u1=row.u1, u2=row.u2, phases=phases)
    return design, ref.generalized_force(phi, **design), ref.potential_energy(phi, **design)


def test_outputs_match_per_design_reference():
    designs = random_designs(60)
    result = mc.sweep(designs, passthrough="label", phi=360)
    assert list(result.columns) == list(designs.columns) + list(mc.SWEEP_OUTPUTS)
    assert (result["label"] == designs["label"]).all() and (result.index == designs.index).all()
    phi = np.arange(360) * (2 * np.pi / 360)
    dense = np.linspace(0, 2 * np.pi, 20001)
    for row in result.itertuples():
        design, q, _ = per_design(row, phi)
        scale = row.cranks * (abs(row.u1) + abs(row.u2)) / (1 - row.crank_ratio**2) ** 1.5
        assert abs(row.force_max_abs - np.max(np.abs(q))) <= 1e-13 * scale
        assert abs(row.force_rms - np.sqrt(np.mean(q**2))) <= 1e-13 * scale
        u = ref.potential_energy(dense, **design)
        assert row.energy_min <= u.min() + 1e-13 * scale and row.energy_max >= u.max() - 1e-13 * scale
        # δ_g is taken before the level is added, so it agrees with max − min to the level's ulp.
        level = max(abs(row.energy_min), abs(row.energy_max))
        assert row.energy_range == pytest.approx(row.energy_max - row.energy_min, abs=4 * np.finfo(float).eps * level)
        assert row.energy_range - (u.max() - u.min()) <= 1e-6 * scale  # the dense grid is close
        # The leading harmonic against an FFT of the exact force.
        grid = np.arange(4096) * (2 * np.pi / 4096)
        spectrum = np.abs(np.fft.rfft(ref.generalized_force(grid, **design))) * 2 / grid.size
        if spectrum.max() > 1e-12 * scale:
            assert row.leading_harmonic == int(np.argmax(spectrum))
            assert row.leading_amplitude == pytest.approx(spectrum.max(), rel=1e-9, abs=1e-13 * scale)


def test_mapping_defaults_and_phi_array():
    designs = {"crank_ratio": [0.3, 0.25], "inclination": [np.pi / 2, 0.0], "u1": [0.5, 0.5], "u2": [0.1, 0.1]}
    phi = np.linspace(0, 2 * np.pi, 101)
    result = mc.sweep(designs, phi=phi, outputs=["force_max_abs"])
    assert list(result.columns) == [*list(designs), "force_max_abs"]
    q = ref.generalized_force(phi, crank_ratio=0.3, inclination=np.pi / 2, u1=0.5, u2=0.1)
    assert result["force_max_abs"].iloc[0] == pytest.approx(np.abs(q).max(), rel=1e-14)


def test_thread_count_and_chunking_do_not_change_a_bit():
    designs = random_designs(3000, seed=3)
    base = mc.sweep(designs, passthrough="label", phi=200, chunk_size=3000)
    other = mc.sweep(designs, passthrough="label", phi=200, chunk_size=7)
    pd.testing.assert_frame_equal(base, other, check_exact=True)
    code = textwrap.dedent(
        """
        import sys, numpy as np, pandas as pd, multicrank as mc
        designs = pd.read_pickle(sys.argv[1])
        mc.set_parallel_threshold(0)
        mc.sweep(designs, passthrough="label", phi=200, chunk_size=512).to_pickle(sys.argv[2])
        """
    )
    for threads in ("1", "2", "3"):
        with_threads = _run_child(code, designs, dict(os.environ, RAYON_NUM_THREADS=threads))
        pd.testing.assert_frame_equal(base, with_threads, check_exact=True)


def _run_child(code: str, designs: pd.DataFrame, env) -> pd.DataFrame:
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        src, dst = Path(tmp) / "in.pkl", Path(tmp) / "out.pkl"
        designs.to_pickle(src)
        subprocess.run([sys.executable, "-c", code, str(src), str(dst)], check=True, env=env, timeout=300)
        return pd.read_pickle(dst)


@pytest.mark.parametrize(
    "designs, message",
    [
        ({"crank_ratio": [0.3], "inclination": [0.0], "u1": [1.0]}, "u2"),
        ({"crank_ratio": [1.3], "inclination": [0.0], "u1": [1.0], "u2": [0.0]}, "crank_ratio"),
        ({"crank_ratio": [0.3], "inclination": [np.nan], "u1": [1.0], "u2": [0.0]}, "inclination"),
        ({"crank_ratio": [0.3], "inclination": [0.0], "u1": [1.0], "u2": [0.0], "cranks": [0]}, "cranks"),
        ({"crank_ratio": [0.3], "inclination": [0.0], "u1": [1.0], "u2": [0.0], "cranks": [1.5]}, "cranks"),
        ({"crank_ratio": [0.3], "inclination": [0.0], "u1": [1.0], "u2": [0.0], "strokes": [3]}, "strokes"),
        ({"crank_ratio": [0.3], "inclination": [0.0], "u1": [1.0], "u2": [0.0], "acting": ["both"]}, "acting"),
        ({"crank_ratio": [0.3, 0.2], "inclination": [0.0], "u1": [1.0], "u2": [0.0]}, "equal lengths"),
        ({"crank_ratio": ["a"], "inclination": [0.0], "u1": [1.0], "u2": [0.0]}, "crank_ratio"),
        ([1, 2, 3], "designs must be"),
    ],
)
def test_bad_designs(designs, message):
    with pytest.raises(mc.MechanismError, match=message):
        mc.sweep(designs)


def test_bad_options():
    designs = {"crank_ratio": [0.3], "inclination": [0.0], "u1": [1.0], "u2": [0.0]}
    with pytest.raises(mc.MechanismError, match="force_peak"):
        mc.sweep(designs, outputs=["force_peak"])
    with pytest.raises(mc.MechanismError, match="phi"):
        mc.sweep(designs, phi=0)
    with pytest.raises(mc.MechanismError, match="method"):
        mc.sweep(designs, method="paper")


def test_curves_option_matches_evaluation():
    designs = random_designs(25, seed=5)
    table, curves = mc.sweep(designs, passthrough="label", phi=90, outputs=["force_max_abs"], curves=True)
    assert curves.shape == (25, 90)
    phi = np.arange(90) * (2 * np.pi / 90)
    for i, row in enumerate(table.itertuples()):
        _, q, _ = per_design(row, phi)
        np.testing.assert_allclose(curves[i], q, rtol=0, atol=1e-13 * 12 * 2 / (1 - 0.81) ** 1.5)
    np.testing.assert_array_equal(np.abs(curves).max(axis=1), table["force_max_abs"])


def test_grid_to_xarray():
    axes = dict(crank_ratio=[0.2, 0.3, 0.4], inclination=np.radians([0, 45, 90, 135]), u1=0.01, cranks=[1, 2])
    grid = mc.design_grid(**axes, u2=0.002)
    assert len(grid) == 24 and (grid["u1"] == 0.01).all()
    assert grid.iloc[1].to_dict()["cranks"] == 2  # C order: the last axis varies fastest
    result = mc.sweep(grid, phi=120)
    data = mc.to_xarray(result)
    assert dict(data.sizes) == {"crank_ratio": 3, "inclination": 4, "cranks": 2}
    one = data["energy_range"].sel(crank_ratio=0.3, cranks=2).isel(inclination=2).item()
    row = result[
        (result.crank_ratio == 0.3) & (result.cranks == 2) & (result.inclination == grid.inclination.unique()[2])
    ]
    assert one == row["energy_range"].item()
    # A lazy DesignGrid sweeps to the same numbers.
    lazy = mc.sweep(mc.DesignGrid(**axes, u2=0.002), phi=120, chunk_size=5)
    np.testing.assert_array_equal(lazy["energy_range"].to_numpy(), result["energy_range"].to_numpy())


def test_parquet_streaming_matches_in_memory(tmp_path):
    designs = random_designs(1000, seed=7)
    expected = mc.sweep(designs, passthrough="label", phi=64)
    path = mc.sweep(designs, passthrough="label", phi=64, out=tmp_path / "r.parquet", chunk_size=128)
    assert path == tmp_path / "r.parquet" and not (tmp_path / "r.parquet.parts").exists()
    assert pq.ParquetFile(path).num_row_groups == 8
    pd.testing.assert_frame_equal(pq.read_table(path).to_pandas(), expected.reset_index(drop=True))


# The signal tests send their signal only once the work has visibly started (a part on disk, a
# line from the child), into work that cannot finish in between: a child that blocks once it has
# written its parts, or a sweep of 10⁸ designs (about an hour) that the test always ends. No
# test depends on how fast the machine is; the 300 s bounds only turn a hang into a failure.

# A sweep whose PartStore stops after `parts` parts: it prints a line and waits to be killed.
_STOPS_AFTER = """
import sys, time
import numpy as np
import multicrank as mc
from multicrank.sweeps.store import PartStore

original, written = PartStore.write, [0]

def write(self, index, frame):
    if written[0] == {parts}:
        print("parts written", flush=True)
        while True:
            time.sleep(60)
    written[0] += 1
    return original(self, index, frame)

PartStore.write = write
mc.sweep({grid}, phi=360, out={out!r}, chunk_size=500)
"""


def test_resume_after_a_kill_gives_the_same_file(tmp_path):
    grid_code = (
        "mc.DesignGrid(crank_ratio=np.linspace(0.1, 0.9, 60), inclination=np.linspace(0, 3, 50), u1=[0.2, 0.7],"
        " u2=[-0.1, 0.1], cranks=[1, 5, 12])"
    )
    uninterrupted = tmp_path / "whole.parquet"
    grid = eval(grid_code, {"mc": mc, "np": np})
    mc.sweep(grid, phi=360, out=uninterrupted, chunk_size=500)

    target = tmp_path / "killed.parquet"
    code = _STOPS_AFTER.format(parts=3, grid=grid_code, out=str(target))
    child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = child.stdout.readline()  # the child has written 3 parts and waits
        assert line == "parts written\n", f"the sweep stopped early: {child.communicate()[1]}"
        child.send_signal(signal.SIGKILL)
        child.communicate(timeout=300)
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()
    assert child.returncode == -signal.SIGKILL
    parts = target.with_name(target.name + ".parts")
    assert len(list(parts.glob("part-*.parquet"))) == 3, "the sweep was killed mid-way"
    assert not target.exists()

    with pytest.raises(mc.MechanismError, match="cannot resume"):
        mc.sweep(grid, phi=180, out=target, chunk_size=500, resume=True)  # another sweep's parts
    mc.sweep(grid, phi=360, out=target, chunk_size=500, resume=True)
    assert pq.read_table(target).equals(pq.read_table(uninterrupted))
    assert pq.ParquetFile(target).num_row_groups == pq.ParquetFile(uninterrupted).num_row_groups
    assert target.read_bytes() == uninterrupted.read_bytes()


def _sigint_as_ctrl_c() -> None:
    """In the child before it starts: SIGINT back to its default, so that Python makes it a
    KeyboardInterrupt. A test run started in the background of a script (CI, nohup, `&`)
    inherits SIGINT ignored, and Python then leaves it ignored: the child would never see the
    test's Ctrl-C."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _interrupt_when_a_part_appears(command: list[str], parts: Path, known: set[str]) -> tuple[int, str]:
    """Runs `command`, sends SIGINT once a part file not in `known` is on disk, and returns the
    exit status and stderr. The sweep is far too long to finish first: the signal always lands."""
    child = subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, preexec_fn=_sigint_as_ctrl_c
    )
    try:
        guard = time.monotonic() + 300  # a hang fails the test; the speed of the machine does not
        while child.poll() is None and time.monotonic() < guard:
            if {path.name for path in parts.glob("part-*.parquet")} - known:
                break
            time.sleep(0.01)
        assert child.poll() is None, f"the sweep ended before a new part was written: {child.communicate()[1]}"
        child.send_signal(signal.SIGINT)
        _, err = child.communicate(timeout=300)
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()
    return child.returncode, err


def test_ctrl_c_exits_130_keeps_whole_parts_and_resume_continues_from_them(tmp_path):
    """SIGINT to `multicrank sweep` while it runs: exit status 130 with a one-line hint, the
    finished parts kept whole, no output file; --resume continues after them and leaves them as
    they are (interrupted again). The sweep is 1.28·10⁸ designs (about an hour); the test ends it."""
    chunk = 4000
    grid = ["--crank-ratio", "0.1:0.9:4000", "--inclination", "0:90:2000", "--u1", "0.2,0.7", "--u2=-0.1,0.1",
            "--cranks", "1,12", "--chunk-size", str(chunk), "--no-progress"]  # fmt: skip
    target = tmp_path / "x.parquet"
    parts = tmp_path / "x.parquet.parts"
    command = [str(SCRIPT), "sweep", *grid, "--out", str(target)]

    status, err = _interrupt_when_a_part_appears(command, parts, set())
    assert status == 130, f"exit status {status}; stderr: {err}"
    assert "interrupted" in err and "--resume" in err and "Traceback" not in err
    assert not target.exists()
    kept = {path.name: path.stat() for path in parts.glob("part-*.parquet")}
    assert kept
    for name in kept:
        assert pq.read_table(parts / name).num_rows == chunk  # whole parts only

    status, err = _interrupt_when_a_part_appears([*command, "--resume"], parts, set(kept))
    assert status == 130, f"exit status {status}; stderr: {err}"
    now = sorted(parts.glob("part-*.parquet"))
    assert len(now) > len(kept) and not target.exists()
    # Chunks 0, 1, … in order: the resumed sweep went on from the first chunk it did not have,
    # and did not write the kept parts again (the same files, not rewritten).
    assert [int(path.name.split("-")[1]) for path in now] == list(range(len(now)))
    for name, stat in kept.items():
        again = (parts / name).stat()
        assert (again.st_ino, again.st_mtime_ns) == (stat.st_ino, stat.st_mtime_ns)
    for path in now:
        assert pq.read_table(path).num_rows == chunk


def test_cli_resume_after_ctrl_c_writes_the_same_file(tmp_path, monkeypatch):
    """Ctrl-C (a KeyboardInterrupt after the third part, in-process, so it always lands) gives
    exit status 130 and the hint; --resume then writes the file byte for byte as an
    uninterrupted sweep does."""
    from click.testing import CliRunner

    from multicrank import cli
    from multicrank.sweeps.store import PartStore

    chunk, chunks = 500, 12
    grid = ["--crank-ratio", "0.1:0.9:30", "--inclination", "0:90:25", "--u1", "0.2,0.7", "--u2=-0.1,0.1",
            "--cranks", "1,12", "--chunk-size", str(chunk), "--no-progress"]  # fmt: skip
    target = tmp_path / "x.parquet"
    parts = tmp_path / "x.parquet.parts"
    original, written = PartStore.write, [0]

    def ctrl_c_after_three(self, index, frame):
        if written[0] == 3:
            raise KeyboardInterrupt
        written[0] += 1
        return original(self, index, frame)

    with monkeypatch.context() as patch:
        patch.setattr(PartStore, "write", ctrl_c_after_three)
        result = CliRunner().invoke(cli.main, ["sweep", *grid, "--out", str(target)])
    assert result.exit_code == 130, result.output
    assert "interrupted" in result.output and "--resume" in result.output
    assert not target.exists() and len(list(parts.glob("part-*.parquet"))) == 3

    def run(*args: str) -> None:
        result = CliRunner().invoke(cli.main, ["sweep", *grid, *args])
        assert result.exit_code == 0, result.output

    run("--out", str(target), "--resume")
    run("--out", str(tmp_path / "whole.parquet"))
    assert not parts.exists()
    assert pq.ParquetFile(target).num_row_groups == chunks
    assert target.read_bytes() == (tmp_path / "whole.parquet").read_bytes()


def test_dask_local_cluster_matches_in_process():
    import dask.dataframe as dd
    from distributed import Client, LocalCluster

    designs = random_designs(2000, seed=11)
    expected = mc.sweep(designs, passthrough="label", phi=90)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            lazy = mc.sweep(dd.from_pandas(designs, npartitions=5), passthrough="label", phi=90)
            assert isinstance(lazy, dd.DataFrame)
            result = lazy.compute()
            assert len(client.scheduler_info()["workers"]) == 2
    pd.testing.assert_frame_equal(result.sort_index(), expected, check_exact=True, check_dtype=False)


def test_cli_sweep_writes_parquet_and_summary(tmp_path):
    out = tmp_path / "cli.parquet"
    result = subprocess.run(
        [
            str(SCRIPT),
            "sweep",
            "--crank-ratio",
            "0.2:0.4:3",
            "--inclination",
            "0,90",
            "--u1",
            "0.05",
            "--u2=-0.01",
            "--cranks",
            "1:3",
            "--strokes",
            "2,4",
            "--phi",
            "180",
            "--out",
            str(out),
            "--no-progress",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    assert "36 designs" in result.stdout and "energy_range" in result.stdout
    table = pq.read_table(out).to_pandas()
    expected = mc.sweep(
        mc.DesignGrid(
            crank_ratio=[0.2, 0.3, 0.4],
            inclination=np.radians([0.0, 90.0]),
            u1=0.05,
            u2=-0.01,
            cranks=[1, 2, 3],
            strokes=[2, 4],
        ),
        phi=180,
    )
    np.testing.assert_allclose(table["energy_range"], expected["energy_range"], rtol=1e-12, atol=1e-15)


def test_cli_sweep_from_toml(tmp_path):
    config = tmp_path / "sweep.toml"
    config.write_text(
        'phi = 90\noutputs = ["force_max_abs", "energy_range"]\n[axes]\ncrank_ratio = "0.2:0.3:2"\n'
        'inclination = [90.0]\nu1 = "0.1"\ncranks = "4,6"\n'
    )
    out = tmp_path / "toml.parquet"
    result = subprocess.run(
        [str(SCRIPT), "sweep", "--config", str(config), "--out", str(out), "--no-progress"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    table = pq.read_table(out).to_pandas()
    assert len(table) == 4 and list(table.columns)[-2:] == ["force_max_abs", "energy_range"]
    assert np.allclose(table["inclination"], np.pi / 2)


def test_cli_sweep_errors_are_usage_errors(tmp_path):
    result = subprocess.run(
        [str(SCRIPT), "sweep", "--crank-ratio", "0.2", "--out", str(tmp_path / "x.parquet")],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 2 and "inclination" in result.stderr


def test_progress_bar_reports_designs(capsys):
    designs = random_designs(300, seed=13)
    quiet = mc.sweep(designs, passthrough="label", phi=32, outputs=["force_rms"], chunk_size=100)
    shown = mc.sweep(designs, passthrough="label", phi=32, outputs=["force_rms"], chunk_size=100, progress=True)
    pd.testing.assert_frame_equal(quiet, shown)
    err = capsys.readouterr().err
    assert "300/300" in err and "designs/s" in err
