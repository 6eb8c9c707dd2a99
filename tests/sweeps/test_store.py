"""Sweep files and designs that cannot be trusted (issue 13, item 6).

- A resume must match the interrupted sweep's whole definition: a grid or a table that
  differs anywhere (not only in its first rows) is refused, never mixed in.
- Parts carry checksums: a damaged part is computed again on resume and never merged.
- ``out=`` is checked before any work: an existing directory, a parts path taken by a
  file, a place that cannot be written.
- A failed or interrupted merge (a full disk, Ctrl-C) leaves no half-written file.
- Unknown design columns are refused (in DesignGrid, design_grid and the frames passed to
  sweep) unless passed through explicitly.
"""

from __future__ import annotations

import contextlib
import errno
import math
import os
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path
from typing import Any
from unittest import mock

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import multicrank as mc
from multicrank.sweeps import driver as sweeps
from multicrank.sweeps.store import PartStore

GRID_CODE = (
    "mc.DesignGrid(crank_ratio=np.linspace(0.1, 0.9, 40), inclination=np.linspace(0, 3, 25), u1=[0.2, 0.7],"
    " u2=[-0.1, 0.1], cranks=[1, 5])"
)  # 8000 designs: 16 chunks of 500


def base_grid(**changes: Any) -> mc.DesignGrid:
    axes = dict(
        crank_ratio=np.linspace(0.1, 0.9, 40),
        inclination=np.linspace(0, 3, 25),
        u1=[0.2, 0.7],
        u2=[-0.1, 0.1],
        cranks=[1, 5],
    )
    return mc.DesignGrid(**{**axes, **changes})


def table(n: int = 3000, seed: int = 0) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    return pd.DataFrame(
        {
            "crank_ratio": rng.uniform(0, 0.9, n),
            "inclination": rng.uniform(-3, 3, n),
            "u1": rng.uniform(0, 1, n),
            "u2": rng.uniform(-0.5, 0.5, n),
            "cranks": rng.integers(1, 7, n),
            "label": [f"m{i}" for i in range(n)],
        }
    )


SWEEP = dict(phi=64, chunk_size=500)


class Interrupted(Exception):
    """Stands for Ctrl-C or a kill between two parts (KeyboardInterrupt would stop hypothesis)."""


@contextlib.contextmanager
def interrupted_after(parts: int):
    """The sweep stops (raising Interrupted) once ``parts`` parts are on disk."""
    original = PartStore.write
    written = [0]

    def write(self, index, frame):
        if written[0] >= parts:
            raise Interrupted
        written[0] += 1
        return original(self, index, frame)

    with mock.patch.object(PartStore, "write", write), pytest.raises(Interrupted):
        yield


@contextlib.contextmanager
def no_merge():
    """The sweep stops (raising Interrupted) with every part on disk, before the merge."""
    with mock.patch.object(PartStore, "merge", side_effect=Interrupted), pytest.raises(Interrupted):
        yield


@contextlib.contextmanager
def native_calls():
    """Counts the calls into the Rust sweep."""
    with mock.patch.object(sweeps, "_native_sweep", wraps=sweeps._native_sweep) as spy:
        yield spy


def part_files(out: Path) -> list[Path]:
    return sorted(out.with_name(out.name + ".parts").glob("part-*.parquet"))


def leftovers(directory: Path) -> list[Path]:
    """Temporary files anywhere under ``directory``."""
    return [p for p in directory.rglob("*") if p.name.endswith(".tmp")]


@pytest.fixture(scope="module")
def whole(tmp_path_factory) -> bytes:
    """The bytes of the uninterrupted sweep of base_grid()."""
    out = tmp_path_factory.mktemp("whole") / "whole.parquet"
    mc.sweep(base_grid(), out=out, **SWEEP)
    return out.read_bytes()


# --------------------------------------------------------------------------- resume fingerprint
def test_resume_refuses_a_grid_that_differs_after_its_first_1000_rows(tmp_path, whole):
    out = tmp_path / "s.parquet"
    with interrupted_after(3):
        mc.sweep(base_grid(), out=out, **SWEEP)
    kept = [p.read_bytes() for p in part_files(out)]
    # Only rows 7800 … 7999 differ (the last value of the slowest axis).
    other = base_grid(crank_ratio=np.r_[np.linspace(0.1, 0.9, 40)[:-1], 0.95])
    assert other.frame(0, 7800).equals(base_grid().frame(0, 7800))
    with native_calls() as spy, pytest.raises(mc.MechanismError, match="cannot resume"):
        mc.sweep(other, out=out, resume=True, **SWEEP)
    assert spy.call_count == 0 and [p.read_bytes() for p in part_files(out)] == kept
    mc.sweep(base_grid(), out=out, resume=True, **SWEEP)
    assert out.read_bytes() == whole and not leftovers(tmp_path)


@pytest.mark.parametrize(
    "change",
    [
        "last value",
        "one ulp",
        "label",
        "column order",
        "dtype",
        "extra row",
    ],
)
def test_resume_refuses_a_table_that_differs_anywhere(tmp_path, change):
    designs = table()
    out = tmp_path / "t.parquet"
    with interrupted_after(2):
        mc.sweep(designs, out=out, passthrough="label", **SWEEP)
    other = designs.copy()
    if change == "last value":
        other.loc[2999, "u2"] = 0.25
    elif change == "one ulp":
        other.loc[2500, "inclination"] = np.nextafter(other.loc[2500, "inclination"], 9.0)
    elif change == "label":
        other.loc[2999, "label"] = "renamed"
    elif change == "column order":
        other = other[["u1", "crank_ratio", "inclination", "u2", "cranks", "label"]]
    elif change == "dtype":
        other["cranks"] = other["cranks"].astype(np.int32)
    else:
        other = pd.concat([other, other.iloc[:1]], ignore_index=True)
    with pytest.raises(mc.MechanismError, match="cannot resume"):
        mc.sweep(other, out=out, resume=True, passthrough="label", **SWEEP)
    mc.sweep(designs, out=out, resume=True, passthrough="label", **SWEEP)  # the same table resumes
    expected = mc.sweep(designs, passthrough="label", phi=64)
    pd.testing.assert_frame_equal(pq.read_table(out).to_pandas(), expected)


def _axis(elements: st.SearchStrategy) -> st.SearchStrategy:
    return st.one_of(elements, st.lists(elements, min_size=1, max_size=5))


@st.composite
def grids(draw) -> dict[str, Any]:
    ratio = st.floats(0, 0.95).map(lambda x: round(x, 3))
    real = st.floats(-3, 3).map(lambda x: round(x, 3))
    axes: dict[str, Any] = {
        # the slowest axis: up to 40 values, so that grids reach a few thousand rows
        "crank_ratio": draw(st.one_of(ratio, st.lists(ratio, min_size=1, max_size=40))),
        "inclination": draw(_axis(real)),
        "u1": draw(_axis(real)),
        "u2": draw(_axis(real)),
    }
    if draw(st.booleans()):
        axes["cranks"] = draw(_axis(st.integers(1, 8)))
    if draw(st.booleans()):
        axes["strokes"] = draw(_axis(st.sampled_from([2, 4])))
    if draw(st.booleans()):
        axes["acting"] = draw(_axis(st.sampled_from(["single", "double"])))
    return axes


REPLACEMENTS = {
    "crank_ratio": st.floats(0, 0.95),
    "inclination": st.floats(-3, 3),
    "u1": st.floats(-3, 3),
    "u2": st.floats(-3, 3),
    "cranks": st.integers(1, 8),
    "strokes": st.sampled_from([2, 4]),
    "acting": st.sampled_from(["single", "double"]),
}


@st.composite
def mutations(draw, axes: dict[str, Any]) -> dict[str, Any]:
    """``axes`` with one change: a value replaced, an axis extended, reversed or made
    constant; or the last value of the slowest axis replaced, which changes the last rows only."""
    spans = [name for name, values in axes.items() if isinstance(values, list) and len(values) > 1]
    if spans and draw(st.booleans()):
        slowest = spans[0]
        tail = list(axes[slowest])
        tail[-1] = draw(REPLACEMENTS[slowest])
        return {**axes, slowest: tail}
    name = draw(st.sampled_from(sorted(axes)))
    values = axes[name]
    replacement = REPLACEMENTS[name]
    how = draw(st.sampled_from(["replace", "extend", "reverse", "collapse"]))
    if not isinstance(values, list):
        new: Any = draw(replacement)
    elif how == "replace":
        new = list(values)
        new[draw(st.integers(0, len(values) - 1))] = draw(replacement)
    elif how == "extend":
        new = [*values, draw(replacement)]
    elif how == "reverse":
        new = values[::-1]
    else:
        new = values[0]
    return {**axes, name: new}


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_random_grids_resume_only_with_the_same_definition(data):
    axes = data.draw(grids(), label="axes")
    grid = mc.DesignGrid(**axes)
    assume(2 <= len(grid) <= 4000)
    changed = data.draw(mutations(axes), label="changed")
    assume(not mc.DesignGrid(**changed).to_frame().equals(grid.to_frame()))
    chunks = data.draw(st.integers(2, 12), label="chunks")
    chunk_size = math.ceil(len(grid) / chunks)
    chunks = math.ceil(len(grid) / chunk_size)
    assume(chunks >= 2)
    stop_after = data.draw(st.integers(1, chunks - 1), label="stop_after")
    options = dict(phi=16, chunk_size=chunk_size)
    with tempfile.TemporaryDirectory() as tmp:
        whole, out = Path(tmp) / "whole.parquet", Path(tmp) / "out.parquet"
        mc.sweep(grid, out=whole, **options)
        with interrupted_after(stop_after):
            mc.sweep(grid, out=out, **options)
        with pytest.raises(mc.MechanismError, match="cannot resume"):
            mc.sweep(mc.DesignGrid(**changed), out=out, resume=True, **options)
        assert len(part_files(out)) == stop_after
        mc.sweep(grid, out=out, resume=True, **options)
        assert out.read_bytes() == whole.read_bytes()


@settings(max_examples=10, deadline=None)
@given(
    ratios=st.lists(st.floats(0, 0.95), min_size=25, max_size=40, unique=True),
    inclinations=st.lists(st.floats(-3, 3), min_size=40, max_size=60),
    u1=_axis(st.floats(-1, 1)),
    last=st.floats(0, 0.95),
    chunk_size=st.integers(100, 400),
)
def test_random_changes_far_into_a_grid_are_refused(ratios, inclinations, u1, last, chunk_size):
    """Only the last rows differ (the slowest axis's last value), far beyond the first 1000."""
    assume(last != ratios[-1])
    grid = mc.DesignGrid(crank_ratio=ratios, inclination=inclinations, u1=u1, u2=0.1)
    changed = mc.DesignGrid(crank_ratio=[*ratios[:-1], last], inclination=inclinations, u1=u1, u2=0.1)
    options = dict(phi=16, chunk_size=chunk_size, outputs=["force_rms"])
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out.parquet"
        with interrupted_after(2):
            mc.sweep(grid, out=out, **options)
        with pytest.raises(mc.MechanismError, match="cannot resume"):
            mc.sweep(changed, out=out, resume=True, **options)
        mc.sweep(grid, out=out, resume=True, **options)
        pd.testing.assert_frame_equal(pq.read_table(out).to_pandas(), mc.sweep(grid, **options).reset_index(drop=True))


def test_a_torn_or_foreign_manifest_is_not_resumed(tmp_path):
    out = tmp_path / "m.parquet"
    with interrupted_after(2):
        mc.sweep(base_grid(), out=out, **SWEEP)
    manifest = out.with_name(out.name + ".parts") / "manifest.json"
    for text in ("{", "", '{"designs": 8000}', "\udcff"):
        manifest.write_bytes(text.encode("utf-8", "surrogateescape"))
        with pytest.raises(mc.MechanismError, match="cannot resume"):
            mc.sweep(base_grid(), out=out, resume=True, **SWEEP)


def test_an_empty_parts_directory_without_manifest_starts_afresh(tmp_path, whole):
    out = tmp_path / "e.parquet"
    out.with_name(out.name + ".parts").mkdir()  # killed between mkdir and the manifest
    mc.sweep(base_grid(), out=out, resume=True, **SWEEP)
    assert out.read_bytes() == whole


# --------------------------------------------------------------------------- checksummed parts
def _flip(path: Path) -> None:
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0x01
    path.write_bytes(bytes(data))


DAMAGE = {
    "a flipped bit": _flip,
    "truncated": lambda p: p.write_bytes(p.read_bytes()[:-100]),
    "emptied": lambda p: p.write_bytes(b""),
    "another part's bytes": lambda p: p.write_bytes(sorted(p.parent.glob("part-*"))[0].read_bytes()),
}


@pytest.mark.parametrize("damage", DAMAGE)
def test_a_damaged_part_is_computed_again_on_resume(tmp_path, whole, damage):
    out = tmp_path / "d.parquet"
    with interrupted_after(4):
        mc.sweep(base_grid(), out=out, **SWEEP)
    target = part_files(out)[2]
    DAMAGE[damage](target)
    with native_calls() as spy, pytest.warns(RuntimeWarning, match="damaged"):
        mc.sweep(base_grid(), out=out, resume=True, **SWEEP)
    assert spy.call_count == 16 - 3  # the damaged chunk again, and those never done
    assert out.read_bytes() == whole and not leftovers(tmp_path)


def test_a_part_damaged_before_the_merge_is_never_merged(tmp_path, whole):
    out = tmp_path / "b.parquet"
    original = PartStore.merge

    def damage_then_merge(self, chunks, empty):
        _flip(part_files(out)[5])
        return original(self, chunks, empty)

    with mock.patch.object(PartStore, "merge", damage_then_merge), pytest.raises(mc.MechanismError, match="damaged"):
        mc.sweep(base_grid(), out=out, **SWEEP)
    assert not out.exists() and not leftovers(tmp_path)
    assert len(part_files(out)) == 15  # the damaged part is gone, the others kept
    with native_calls() as spy:
        mc.sweep(base_grid(), out=out, resume=True, **SWEEP)
    assert spy.call_count == 1 and out.read_bytes() == whole


# --------------------------------------------------------------------------- out= up front
def test_out_an_existing_directory_is_refused_before_any_work(tmp_path):
    with native_calls() as spy, pytest.raises(mc.MechanismError, match=r"out = .* is an existing directory"):
        mc.sweep(base_grid(), out=tmp_path, **SWEEP)
    assert spy.call_count == 0 and list(tmp_path.iterdir()) == []


def test_out_whose_parts_path_is_a_file_is_refused_before_any_work(tmp_path):
    (tmp_path / "x.parquet.parts").write_text("not a directory")
    with native_calls() as spy, pytest.raises(mc.MechanismError, match=r"out = .*x.parquet.parts"):
        mc.sweep(base_grid(), out=tmp_path / "x.parquet", **SWEEP)
    assert spy.call_count == 0


def test_out_that_cannot_be_written_is_refused_before_any_work(tmp_path):
    (tmp_path / "file").write_text("a file, not a directory")
    with native_calls() as spy, pytest.raises(mc.MechanismError, match=r"out = .*cannot write"):
        mc.sweep(base_grid(), out=tmp_path / "file" / "x.parquet", **SWEEP)
    assert spy.call_count == 0


def test_invalid_designs_are_refused_before_anything_is_written(tmp_path):
    designs = table()
    designs.loc[2999, "crank_ratio"] = 1.5  # in the last chunk
    with native_calls() as spy, pytest.raises(mc.MechanismError, match=r"crank_ratio = 1.5"):
        mc.sweep(designs, out=tmp_path / "v.parquet", passthrough="label", **SWEEP)
    assert spy.call_count == 0 and list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------- failed merges
def _failing_write_table(after: int, error: BaseException):
    """The merge's writes (to a temporary file ``….tmp``, given as a path or an open file,
    not the parts' in-memory buffers) fail after ``after``."""
    original = pq.ParquetWriter.write_table
    calls = [0]

    def write_table(self, *args, **kwargs):
        if str(getattr(self.where, "name", self.where)).endswith(".tmp"):
            calls[0] += 1
            if calls[0] > after:
                raise error
        return original(self, *args, **kwargs)

    return mock.patch.object(pq.ParquetWriter, "write_table", write_table)


@pytest.mark.parametrize(
    "error", [OSError(errno.ENOSPC, "No space left on device"), KeyboardInterrupt()], ids=["full disk", "Ctrl-C"]
)
def test_a_failed_merge_leaves_no_temporary_file_and_resumes(tmp_path, whole, error):
    out = tmp_path / "f.parquet"
    with _failing_write_table(5, error), pytest.raises(type(error)):
        mc.sweep(base_grid(), out=out, **SWEEP)
    assert not out.exists() and not leftovers(tmp_path)
    assert len(part_files(out)) == 16  # every part kept: the resume only merges
    with native_calls() as spy:
        mc.sweep(base_grid(), out=out, resume=True, **SWEEP)
    assert spy.call_count == 0 and out.read_bytes() == whole


def test_a_failed_part_write_leaves_no_temporary_file(tmp_path, whole):
    out = tmp_path / "p.parquet"
    original = os.fsync
    calls = [0]

    def fsync(fd):
        calls[0] += 1
        if calls[0] == 4:  # the manifest, then parts 0, 1, and part 2 fails
            raise OSError(errno.ENOSPC, "No space left on device")
        return original(fd)

    with mock.patch("multicrank._files.os.fsync", fsync), pytest.raises(OSError):
        mc.sweep(base_grid(), out=out, **SWEEP)
    assert len(part_files(out)) == 2 and not leftovers(tmp_path)
    mc.sweep(base_grid(), out=out, resume=True, **SWEEP)
    assert out.read_bytes() == whole


@pytest.mark.skipif(sys.platform != "linux", reason="needs RLIMIT_FSIZE and SIGXFSZ")
def test_a_real_write_limit_during_the_merge(tmp_path, whole):
    """The file-size limit (RLIMIT_FSIZE) stands in for a full disk: every part fits, the
    merged file does not, and the kernel fails the write (EFBIG) as it would with ENOSPC."""
    out = tmp_path / "r.parquet"
    with no_merge():
        mc.sweep(base_grid(), out=out, **SWEEP)
    limit = max(p.stat().st_size for p in part_files(out)) + 4096
    assert sum(p.stat().st_size for p in part_files(out)) > 2 * limit
    code = textwrap.dedent(
        f"""
        import resource, signal, numpy as np, multicrank as mc
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, ({limit}, {limit}))
        try:
            mc.sweep({GRID_CODE}, phi=64, chunk_size=500, out={str(out)!r}, resume=True)
        except OSError as error:
            print("OSError", error.errno)
        """
    )
    child = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert child.returncode == 0 and child.stdout.split() == ["OSError", str(errno.EFBIG)], child.stderr
    assert not out.exists() and not leftovers(tmp_path) and len(part_files(out)) == 16
    mc.sweep(base_grid(), out=out, resume=True, **SWEEP)
    assert out.read_bytes() == whole


# --------------------------------------------------------------------------- unknown columns
GRID_AXES = dict(crank_ratio=[0.2, 0.3], inclination=1.0, u1=0.5, u2=0.1)


def test_a_misspelt_column_is_refused_everywhere():
    for make in (mc.DesignGrid, mc.design_grid):
        with pytest.raises(mc.MechanismError, match="'cylinders' is not a design column"):
            make(**GRID_AXES, cylinders=[1, 2])
        with pytest.raises(mc.MechanismError, match="did you mean 'inclination'"):
            make(crank_ratio=0.3, inclinaton=1.0, u1=0.5, u2=0.1)
    frame = mc.design_grid(**GRID_AXES).assign(cylinders=4)
    with native_calls() as spy, pytest.raises(mc.MechanismError, match=r"unknown column.*'cylinders'.*passthrough"):
        mc.sweep(frame, phi=16)
    assert spy.call_count == 0
    with pytest.raises(mc.MechanismError, match="cylinders"):
        mc.sweep(dict(frame), phi=16)


def test_passthrough_carries_named_columns_only():
    frame = mc.design_grid(**GRID_AXES).assign(cylinders=4, batch="a")
    result = mc.sweep(frame, phi=16, passthrough=["cylinders", "batch"], outputs="force_rms")
    assert list(result.columns) == [*frame.columns, "force_rms"]
    expected = mc.sweep(frame.drop(columns=["cylinders", "batch"]), phi=16, outputs="force_rms")
    np.testing.assert_array_equal(result["force_rms"], expected["force_rms"])  # cranks = 1: not 4
    with pytest.raises(mc.MechanismError, match="batch"):
        mc.sweep(frame, phi=16, passthrough="cylinders")
    with pytest.raises(mc.MechanismError, match=r"'missing'.*do not have"):
        mc.sweep(frame, phi=16, passthrough=["cylinders", "batch", "missing"])
    with pytest.raises(mc.MechanismError, match=r"'u1'.*not passed through"):
        mc.sweep(frame, phi=16, passthrough=["cylinders", "batch", "u1"])
    with pytest.raises(mc.MechanismError, match=r"'force_rms'.*not passed through"):
        mc.sweep(frame.assign(force_rms=0.0), phi=16, passthrough=["cylinders", "batch", "force_rms"])
    with pytest.raises(mc.MechanismError, match="passthrough"):
        mc.sweep(frame, phi=16, passthrough=[3])
    with pytest.raises(mc.MechanismError, match="more than once"):
        mc.sweep(pd.concat([frame, frame[["u1"]]], axis=1), phi=16, passthrough=["cylinders", "batch"])


def test_dask_frames_are_checked_when_the_graph_is_built():
    import dask.dataframe as dd

    frame = dd.from_pandas(mc.design_grid(**GRID_AXES).assign(cylinders=4), npartitions=1)
    with pytest.raises(mc.MechanismError, match="cylinders"):
        mc.sweep(frame, phi=16)
    lazy = mc.sweep(frame, phi=16, passthrough="cylinders", outputs=["force_rms"])
    assert list(lazy.compute()["cylinders"]) == [4, 4]


@settings(max_examples=50, deadline=None)
@given(name=st.from_regex(r"[A-Za-z_][A-Za-z0-9_]{0,14}", fullmatch=True))
def test_random_unknown_names_are_refused_by_name(name):
    assume(name not in ("crank_ratio", "inclination", "u1", "u2", "cranks", "strokes", "acting"))
    with pytest.raises(mc.MechanismError, match=repr(name).replace("\\", "\\\\")):
        mc.DesignGrid(**GRID_AXES, **{name: 1.0})
    frame = mc.design_grid(**GRID_AXES)
    frame[name] = 1.0
    with pytest.raises(mc.MechanismError, match=repr(name)):
        mc.sweep(frame, phi=8)
    assert list(mc.sweep(frame, phi=8, passthrough=name)[name]) == [1.0, 1.0]


# --------------------------------------------------------------------------- to_xarray
def test_to_xarray_refuses_rows_out_of_grid_order():
    result = mc.sweep(mc.design_grid(crank_ratio=[0.2, 0.3, 0.4], inclination=[0.0, 1.0], u1=0.5, u2=0.1), phi=16)
    assert mc.to_xarray(result).sizes == {"crank_ratio": 3, "inclination": 2}
    shuffled = result.sort_values("inclination", kind="stable")  # attrs survive; the order does not
    with pytest.raises(mc.MechanismError, match="grid order"):
        mc.to_xarray(shuffled)
    with pytest.raises(mc.MechanismError, match="grid order"):
        mc.to_xarray(result, axes={"inclination": [0.0, 1.0], "crank_ratio": [0.2, 0.3, 0.4]})
    with pytest.raises(mc.MechanismError, match="no column 'rpm'"):
        mc.to_xarray(result, axes={"rpm": [50, 60, 70], "inclination": [0.0, 1.0]})
    with pytest.raises(mc.MechanismError, match="grid order"):  # a constant column is no axis
        mc.to_xarray(result, axes={"u1": [0.5, 0.6, 0.7], "inclination": [0.0, 1.0]})
    with pytest.raises(mc.MechanismError, match="rows"):
        mc.to_xarray(result.iloc[:4])
