"""Design-space sweeps: millions of machines, each reduced on the fly in the Rust core.

A sweep never materialises a designs × φ matrix (unless ``curves=True`` asks for it): each
design's Q_u* is evaluated on the φ grid and reduced to a few numbers in the same pass.
Designs are processed chunk by chunk, so a sweep streams to Parquet with bounded memory,
reports progress, stops cleanly on Ctrl-C, resumes where it stopped, and runs unchanged
on a Dask cluster (one Rust call per partition).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import shutil
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Iterator

import numpy as np
import pandas as pd

from ._native import MechanismError
from ._native import sweep as _native_sweep
from ._validation import as_count, as_design, as_option, contiguous
from .mechanism import crank_phases

__all__ = ["SWEEP_OUTPUTS", "DesignGrid", "design_grid", "sweep", "to_xarray"]

#: Every output a sweep can compute, in column order.
SWEEP_OUTPUTS = (
    "force_max_abs",
    "force_rms",
    "energy_min",
    "energy_max",
    "energy_range",
    "leading_harmonic",
    "leading_amplitude",
)
DESIGN_COLUMNS = ("crank_ratio", "inclination", "u1", "u2")
OPTIONAL_COLUMNS = {"cranks": 1, "strokes": 2, "acting": "single"}
_GROUPS = {
    "force": ("force_max_abs", "force_rms"),
    "energy": ("energy_min", "energy_max", "energy_range"),
    "harmonic": ("leading_harmonic", "leading_amplitude"),
}
# Designs per call into Rust: short enough that Ctrl-C is answered within about a second
# (the energy extrema cost ~15 µs per design, the grid outputs ~2 µs), long enough that the
# per-call synchronisation of the thread pool does not show.
_CALL_SIZE = {"energy": 8192, "grid": 65536}


# ----------------------------------------------------------------------------- designs
def _as_frame(designs: Any) -> pd.DataFrame:
    if isinstance(designs, pd.DataFrame):
        return designs
    if isinstance(designs, Mapping):
        columns = {}
        for name, values in designs.items():
            array = np.asarray(values)
            if array.ndim != 1:
                raise MechanismError(f"designs column {name!r} must be 1-D, got shape {array.shape}")
            columns[name] = array
        lengths = {len(v) for v in columns.values()}
        if len(lengths) > 1:
            sizes = ", ".join(f"{k} {len(v)}" for k, v in columns.items())
            raise MechanismError(f"designs columns must have equal lengths, got {sizes}")
        return pd.DataFrame(columns)
    raise MechanismError(
        "designs must be a pandas DataFrame, a mapping of equal-length 1-D columns, a "
        f"DesignGrid or a dask DataFrame, got {type(designs).__name__}"
    )


def _check_columns(columns: Any) -> None:
    missing = [c for c in DESIGN_COLUMNS if c not in columns]
    if missing:
        raise MechanismError(
            f"designs lack the column(s) {', '.join(missing)}; required: {', '.join(DESIGN_COLUMNS)} "
            f"(optional: {', '.join(OPTIONAL_COLUMNS)})"
        )


def _integer_column(values: Any, name: str, allowed: tuple[int, ...] | None, minimum: int) -> np.ndarray:
    array = np.asarray(values)
    if array.dtype.kind == "f" and np.all(np.isfinite(array)) and np.all(array == np.round(array)):
        array = array.astype(np.int64)
    if array.dtype.kind not in "iu":
        raise MechanismError(f"designs column {name!r} must hold integers, got dtype {array.dtype}")
    if array.size and array.min() < minimum:
        raise MechanismError(f"{name} = {array.min()} is out of range; allowed: an integer >= {minimum}")
    if allowed is not None and array.size and not np.isin(array, allowed).all():
        bad = array[~np.isin(array, allowed)][0]
        raise MechanismError(f"strokes = {bad} is not allowed; allowed: 2 or 4")
    return array.astype(np.int64)


def _machine_columns(frame: pd.DataFrame) -> dict[str, np.ndarray]:
    """The validated design columns of a frame (optional columns filled with defaults)."""
    _check_columns(frame.columns)
    n = len(frame)
    out = {
        "crank_ratio": as_design(frame["crank_ratio"].to_numpy(), "crank_ratio", low=0.0, high=1.0),
        "inclination": as_design(frame["inclination"].to_numpy(), "inclination"),
        "u1": as_design(frame["u1"].to_numpy(), "u1"),
        "u2": as_design(frame["u2"].to_numpy(), "u2"),
    }
    cranks = frame["cranks"].to_numpy() if "cranks" in frame else np.full(n, 1)
    strokes = frame["strokes"].to_numpy() if "strokes" in frame else np.full(n, 2)
    out["cranks"] = _integer_column(cranks, "cranks", None, 1)
    out["strokes"] = _integer_column(strokes, "strokes", (2, 4), 1)
    # Kept as "is double-acting", not as strings: cheaper to key machine kinds by.
    if "acting" in frame:
        acting = np.asarray(frame["acting"].to_numpy(), dtype=object)
        bad = ~np.isin(acting, ["single", "double"])
        if bad.any():
            raise MechanismError(f"acting = {acting[bad][0]!r} is not allowed; allowed: 'single', 'double'")
        out["double"] = acting == "double"
    else:
        out["double"] = np.zeros(n, dtype=bool)
    return out


def _phase_table(columns: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(per-design set index, flat phases of the distinct sets, offsets into them)."""
    double = columns["double"]
    # One integer per machine kind: cheaper to make unique than tuples of objects.
    kinds = columns["cranks"] * 4 + (columns["strokes"] == 4) * 2 + double
    unique, codes = np.unique(kinds, return_inverse=True)
    sets = [crank_phases(int(key // 4), 4 if key % 4 >= 2 else 2, "double" if key % 2 else "single") for key in unique]
    offsets = np.zeros(len(sets) + 1, dtype=np.uint64)
    offsets[1:] = np.cumsum([len(p) for p in sets])
    flat = np.concatenate(sets) if sets else np.zeros(0)
    return codes.astype(np.uint32), contiguous(flat), offsets


def _as_phi(phi: Any) -> np.ndarray:
    if isinstance(phi, (int, np.integer)) and not isinstance(phi, bool):
        count = as_count(phi, "phi", minimum=1)
        return np.arange(count) * (2 * np.pi / count)
    array = np.asarray(phi)
    if array.ndim != 1 or array.size == 0 or array.dtype.kind not in "iuf":
        raise MechanismError("phi must be a positive int (a uniform grid over one revolution) or a non-empty 1-D array")
    return contiguous(array)


def _as_outputs(outputs: Any) -> tuple[str, ...]:
    if isinstance(outputs, str):
        outputs = (outputs,)
    outputs = tuple(outputs)
    unknown = [o for o in outputs if o not in SWEEP_OUTPUTS]
    if unknown or not outputs:
        raise MechanismError(f"unknown outputs {unknown}; allowed: {', '.join(SWEEP_OUTPUTS)}")
    return outputs


# ----------------------------------------------------------------------------- grids
class DesignGrid:
    """The Cartesian product of design axes, generated lazily chunk by chunk.

    ``DesignGrid(crank_ratio=np.linspace(0.2, 0.45, 26), inclination=..., u1=..., u2=0.0,
    cranks=range(1, 13))``: 1-D axes span the grid (C order, first axis slowest); scalars are
    constant columns. ``len(grid)`` is the number of designs; ``grid.frame(start, stop)``
    builds only those rows, so a sweep of 10⁷ designs never holds them all.
    """

    def __init__(self, **axes: Any) -> None:
        if not axes:
            raise MechanismError("a design grid needs at least one axis")
        self.axes: dict[str, np.ndarray] = {}
        self.constants: dict[str, Any] = {}
        for name, values in axes.items():
            if isinstance(values, str) or np.ndim(values) == 0:
                self.constants[name] = values
            else:
                array = np.asarray(list(values) if isinstance(values, range) else values)
                if array.ndim != 1 or array.size == 0:
                    raise MechanismError(f"grid axis {name!r} must be a scalar or a non-empty 1-D sequence")
                self.axes[name] = array
        self.shape = tuple(len(v) for v in self.axes.values())

    def __len__(self) -> int:
        return math.prod(self.shape)

    def frame(self, start: int = 0, stop: int | None = None) -> pd.DataFrame:
        """Rows start … stop−1 of the product as a DataFrame (index = row number)."""
        stop = len(self) if stop is None else min(stop, len(self))
        rows = np.arange(start, stop)
        index = np.unravel_index(rows, self.shape) if self.shape else ()
        data = {name: values[i] for (name, values), i in zip(self.axes.items(), index)}
        for name, value in self.constants.items():
            data[name] = np.full(len(rows), value, dtype=object if isinstance(value, str) else None)
        return pd.DataFrame(data, index=pd.RangeIndex(start, stop))

    def to_frame(self) -> pd.DataFrame:
        return self.frame()


def design_grid(**axes: Any) -> pd.DataFrame:
    """The Cartesian product of the given axes as a DataFrame (one row per design).

    1-D axes span the grid in C order (the first axis varies slowest); scalars become
    constant columns. The frame remembers its axes (``frame.attrs["grid_axes"]``) so that a
    sweep of it converts to an ``xarray.Dataset`` with one dimension per axis
    (:func:`to_xarray`).
    """
    grid = DesignGrid(**axes)
    frame = grid.to_frame()
    frame.attrs["grid_axes"] = {k: v.tolist() for k, v in grid.axes.items()}
    return frame


def to_xarray(result: pd.DataFrame, axes: Mapping[str, Any] | None = None):
    """A grid sweep's result as an ``xarray.Dataset``: one dimension per grid axis, one
    variable per output. ``axes`` defaults to the ``grid_axes`` the grid left in ``attrs``."""
    import xarray as xr

    axes = axes if axes is not None else result.attrs.get("grid_axes")
    if not axes:
        raise MechanismError("result does not come from a design grid: pass axes={name: values, ...}")
    shape = tuple(len(v) for v in axes.values())
    if math.prod(shape) != len(result):
        raise MechanismError(f"result has {len(result)} rows, the axes make {math.prod(shape)}")
    outputs = [c for c in result.columns if c in SWEEP_OUTPUTS]
    dims = list(axes)
    return xr.Dataset(
        {name: (dims, result[name].to_numpy().reshape(shape)) for name in outputs},
        coords={name: np.asarray(values) for name, values in axes.items()},
    )


# ----------------------------------------------------------------------------- the sweep
def _reduce(columns: dict[str, np.ndarray], phi: np.ndarray, outputs: tuple[str, ...]) -> dict[str, np.ndarray]:
    """One call into Rust per _CALL_SIZE designs; returns the requested output columns."""
    wanted = {group: any(o in outputs for o in names) for group, names in _GROUPS.items()}
    set_index, set_phases, offsets = _phase_table(columns)
    phi = contiguous(phi)  # arrays unpickled on a Dask worker may be misaligned
    parts: list[list[np.ndarray]] = []
    n = len(set_index)
    call_size = _CALL_SIZE["energy" if wanted["energy"] else "grid"]
    for start in range(0, n, call_size):
        part = slice(start, min(start + call_size, n))
        parts.append(
            _native_sweep(
                *(contiguous(columns[c][part]) for c in DESIGN_COLUMNS),
                np.ascontiguousarray(set_index[part]),
                set_phases,
                offsets,
                phi,
                wanted["force"],
                wanted["energy"],
                wanted["harmonic"],
            )
        )
    names = ("force_max_abs", "force_rms", "energy_min", "energy_max", "energy_range", "leading_harmonic",
             "leading_amplitude")
    raw = {name: np.concatenate([p[i] for p in parts]) if parts else np.zeros(0) for i, name in enumerate(names)}
    if wanted["harmonic"]:
        raw["leading_harmonic"] = raw["leading_harmonic"].astype(np.int64)
    return {name: raw[name] for name in outputs}


def _sweep_frame(frame: pd.DataFrame, phi: np.ndarray, outputs: tuple[str, ...]) -> pd.DataFrame:
    """The designs of `frame` with one column per output (the per-chunk and per-partition work)."""
    reduced = _reduce(_machine_columns(frame), phi, outputs)
    result = frame.copy()
    for name, values in reduced.items():
        result[name] = values
    return result


def _chunks(designs: Any, chunk_size: int) -> tuple[int, Any]:
    """(number of designs, function start, stop -> DataFrame)."""
    if isinstance(designs, DesignGrid):
        return len(designs), designs.frame
    frame = _as_frame(designs)
    return len(frame), lambda start, stop: frame.iloc[start:stop]


def _progress_bar(total: int, enabled: bool, initial: int = 0):
    if not enabled:
        return None
    from tqdm.auto import tqdm

    return tqdm(total=total, initial=initial, unit="designs", unit_scale=True, desc="sweep", smoothing=0.1)


def sweep(
    designs: Any,
    *,
    phi: Any = 720,
    outputs: Any = SWEEP_OUTPUTS,
    method: str = "exact",
    out: str | os.PathLike | None = None,
    resume: bool = False,
    progress: bool = False,
    chunk_size: int = 65536,
    curves: bool = False,
):
    """Reduce every design of a sweep to the requested outputs, in parallel, in Rust.

    Parameters
    ----------
    designs : pandas.DataFrame, mapping of equal-length 1-D columns, DesignGrid,
        dask.dataframe.DataFrame, or a list of :class:`multicrank.Engine` (any layout; the
        result then has one row per engine with its name and number of units). Columns ``crank_ratio``, ``inclination`` [rad], ``u1``,
        ``u2``; optional ``cranks`` (default 1), ``strokes`` (2) and ``acting`` ("single").
        Other columns are carried through.
    phi : int or 1-D array
        An int n is the uniform grid φ_i = 2πi/n, i < n (one revolution, endpoint excluded);
        an array is used as given. Used by ``force_max_abs`` and ``force_rms``.
    outputs : names from SWEEP_OUTPUTS
        ``force_max_abs``, ``force_rms``: max|Q_u*| and √mean(Q_u*²) over the φ grid;
        ``energy_min``, ``energy_max``, ``energy_range``: the exact extrema of U_w* over a
        revolution and their difference δ_g (= :func:`speed_fluctuation`);
        ``leading_harmonic``, ``leading_amplitude``: the harmonic n of Q_u* with the largest
        amplitude √(a_n² + b_n²) and that amplitude (0, 0 when Q_u* ≡ 0).
    method : "exact" (or its synonym "series")
        Outputs are exact to machine precision. They are computed on the Fourier form with
        exact Λ_n (which equals the closed form to ~1e-15·max|Q|), because it is the faster
        path: few harmonics per design and no sqrt per crank.
    out : path, optional
        Stream the result to this Parquet file, chunk by chunk (one row group per chunk),
        with bounded memory; the file appears atomically when complete, and the path is
        returned instead of a DataFrame. Finished chunks are kept in ``<out>.parts/``.
    resume : bool
        With ``out``: continue an interrupted sweep of the same designs from its finished
        chunks (no row lost or duplicated).
    progress : bool
        Show a progress bar (designs/s, ETA).
    chunk_size : int
        Designs per chunk (and per Parquet row group). Results do not depend on it.
    curves : bool
        Also return Q_u* of every design on the φ grid, an array (designs, len(phi)) — for
        small sweeps only.

    Returns
    -------
    DataFrame (designs + outputs, same rows and order), or ``(DataFrame, curves)``, or the
    Parquet path with ``out``, or a lazy dask DataFrame for dask input.

    Threads: rayon's pool (``RAYON_NUM_THREADS``); results are bit-identical for any thread
    count and chunk size. Ctrl-C raises KeyboardInterrupt within about a second; with
    ``out`` the finished chunks stay on disk for ``resume=True``.
    """
    as_option(method, "method", ("exact", "series"))
    outputs = _as_outputs(outputs)
    phi = _as_phi(phi)
    chunk_size = as_count(chunk_size, "chunk_size", minimum=1)

    if _is_engine_list(designs):
        if out is not None or curves:
            raise MechanismError("out= and curves= take tabular designs, not a list of engines")
        return _sweep_engines(list(designs), phi, outputs, progress)

    if _is_dask(designs):
        if out is not None or curves:
            raise MechanismError("out= and curves= are not available for dask input: write with dask's to_parquet")
        _check_columns(designs.columns)
        meta = designs._meta.copy()
        for name in outputs:
            meta[name] = np.zeros(0, dtype=np.int64 if name == "leading_harmonic" else np.float64)
        return designs.map_partitions(_sweep_frame, phi, outputs, meta=meta)

    if out is not None:
        if curves:
            raise MechanismError("curves= cannot be combined with out=")
        return _sweep_to_parquet(designs, Path(out), phi, outputs, chunk_size, resume, progress)

    total, rows = _chunks(designs, chunk_size)
    bar = _progress_bar(total, progress)
    pieces = []
    try:
        for start in range(0, total, chunk_size):
            pieces.append(_sweep_frame(rows(start, start + chunk_size), phi, outputs))
            if bar is not None:
                bar.update(len(pieces[-1]))
    finally:
        if bar is not None:
            bar.close()
    if not pieces:
        pieces.append(_sweep_frame(rows(0, 0), phi, outputs))
    result = pd.concat(pieces) if len(pieces) > 1 else pieces[0]
    grid_axes = getattr(designs, "attrs", {}).get("grid_axes") if not isinstance(designs, DesignGrid) else {
        k: v.tolist() for k, v in designs.axes.items()
    }
    if grid_axes:
        result.attrs["grid_axes"] = grid_axes
    if curves:
        return result, _curves(result, phi)
    return result


def _curves(frame: pd.DataFrame, phi: np.ndarray) -> np.ndarray:
    """Q_u* of every design on the grid (designs × φ), one Rust call per machine kind."""
    from .evaluation import generalized_force

    columns = _machine_columns(frame)
    set_index, set_phases, offsets = _phase_table(columns)
    curves = np.empty((len(frame), len(phi)))
    for code in np.unique(set_index):
        rows = np.flatnonzero(set_index == code)
        curves[rows] = generalized_force(
            phi,
            crank_ratio=columns["crank_ratio"][rows],
            inclination=columns["inclination"][rows],
            u1=columns["u1"][rows],
            u2=columns["u2"][rows],
            phases=set_phases[int(offsets[code]) : int(offsets[code + 1])],
        )
    return curves


def _is_engine_list(designs: Any) -> bool:
    from .engines import Engine

    return isinstance(designs, (list, tuple)) and len(designs) > 0 and all(isinstance(e, Engine) for e in designs)


def _sweep_engines(engines: list, phi: np.ndarray, outputs: tuple[str, ...], progress: bool) -> pd.DataFrame:
    """The outputs of each cylinder-level engine (one Rust call per engine and output group):
    for layouts, unequal cylinders and Monte-Carlo samples of manufacturing tolerances."""
    rows = []
    bar = _progress_bar(len(engines), progress)
    for engine in engines:
        row: dict[str, Any] = {"engine": engine.name, "cylinders": len(engine)}
        if any(o in outputs for o in _GROUPS["force"]):
            q = engine.generalized_force(phi)
            row["force_max_abs"], row["force_rms"] = float(np.max(np.abs(q))), float(np.sqrt(np.mean(q * q)))
        if any(o in outputs for o in _GROUPS["energy"]):
            extrema = engine.energy_extrema()
            row["energy_min"], row["energy_max"], row["energy_range"] = extrema.min, extrema.max, extrema.range
        if any(o in outputs for o in _GROUPS["harmonic"]):
            row["leading_harmonic"], row["leading_amplitude"] = engine.leading_harmonic()
        rows.append(row)
        if bar is not None:
            bar.update(1)
    if bar is not None:
        bar.close()
    frame = pd.DataFrame(rows)
    return frame[["engine", "cylinders", *outputs]]


def _is_dask(designs: Any) -> bool:
    module = type(designs).__module__
    return module.startswith("dask") and hasattr(designs, "map_partitions")


# ----------------------------------------------------------------------------- Parquet
def _fingerprint(total: int, phi: np.ndarray, outputs: tuple[str, ...], chunk_size: int, first: pd.DataFrame) -> dict:
    """What must match for a resume: the chunking, the grid, the outputs and the designs' start."""
    digest = hashlib.sha256()
    digest.update(np.ascontiguousarray(phi).tobytes())
    digest.update(pd.util.hash_pandas_object(first, index=True).to_numpy().tobytes())
    return {
        "designs": total,
        "chunk_size": chunk_size,
        "outputs": list(outputs),
        "digest": digest.hexdigest(),
    }


def _part_files(parts: Path) -> Iterator[Path]:
    return iter(sorted(parts.glob("part-*.parquet")))


def _sweep_to_parquet(
    designs: Any, out: Path, phi: np.ndarray, outputs: tuple[str, ...], chunk_size: int, resume: bool, progress: bool
) -> Path:
    import pyarrow as pa
    import pyarrow.parquet as pq

    total, rows = _chunks(designs, chunk_size)
    parts = out.with_name(out.name + ".parts")
    manifest = _fingerprint(total, phi, outputs, chunk_size, rows(0, min(total, 1000)))
    manifest_file = parts / "manifest.json"
    if parts.exists():
        if not resume:
            shutil.rmtree(parts)
        elif not manifest_file.exists() or json.loads(manifest_file.read_text()) != manifest:
            raise MechanismError(
                f"cannot resume: {parts} belongs to a different sweep (designs, phi, outputs or chunk_size differ)"
            )
    parts.mkdir(parents=True, exist_ok=True)
    manifest_file.write_text(json.dumps(manifest))

    n_chunks = math.ceil(total / chunk_size)
    done = {int(p.stem.split("-")[1]) for p in _part_files(parts)}
    bar = _progress_bar(total, progress, initial=sum(min(chunk_size, total - i * chunk_size) for i in done))
    try:
        for index in range(n_chunks):
            if index in done:
                continue
            start = index * chunk_size
            table = pa.Table.from_pandas(_sweep_frame(rows(start, start + chunk_size), phi, outputs), preserve_index=False)
            final = parts / f"part-{index:08d}.parquet"
            temporary = final.with_suffix(".tmp")
            pq.write_table(table, temporary)
            os.replace(temporary, final)  # a part exists whole or not at all
            if bar is not None:
                bar.update(table.num_rows)
    finally:
        if bar is not None:
            bar.close()

    # Merge the parts, in order, one row group each, into a temporary file; rename atomically.
    temporary = out.with_name(out.name + ".tmp")
    writer = None
    try:
        for index in range(n_chunks):
            table = pq.read_table(parts / f"part-{index:08d}.parquet")
            if writer is None:
                writer = pq.ParquetWriter(temporary, table.schema)
            writer.write_table(table, row_group_size=max(table.num_rows, 1))
        if writer is None:  # no designs: an empty file with the right columns
            empty = _sweep_frame(rows(0, 0), phi, outputs)
            pq.write_table(pa.Table.from_pandas(empty, preserve_index=False), temporary)
    finally:
        if writer is not None:
            writer.close()
    os.replace(temporary, out)
    shutil.rmtree(parts)
    return out
