"""Design-space sweeps: millions of machines, each reduced on the fly in the Rust core.

A sweep never materialises a designs × φ matrix (unless ``curves=True`` asks for it): each
design's Q_u* is evaluated on the φ grid and reduced to a few numbers in the same pass.
Designs (see :mod:`multicrank.designs`) are processed chunk by chunk, so a sweep streams to
Parquet with bounded memory (see :mod:`multicrank.store`), reports progress, stops cleanly
on Ctrl-C, resumes where it stopped, and runs unchanged on a Dask cluster (one Rust call
per partition).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .._native import sweep as _native_sweep
from .._native import sweep_engines as _native_sweep_engines
from .._validation import as_count, as_flag, as_option, as_real_array, check_size, contiguous, refused
from ..gravity.engines import Engine
from ..gravity.evaluation import generalized_force
from .chunks import in_memory, is_dask, progress_bar, to_parquet
from .designs import (
    DESIGN_COLUMNS,
    DesignGrid,
    as_frame,
    as_passthrough,
    check_columns,
    design_grid,
    design_rows,
    grid_axes_of,
    machine_columns,
    phase_table,
    validate_designs,
)
from .outputs import SWEEP_OUTPUTS, as_outputs, to_xarray
from .store import as_out, designs_digest, fingerprint

# DesignGrid and design_grid live in designs, SWEEP_OUTPUTS and to_xarray in outputs; they are
# re-exported here, where multicrank's lazy attributes and earlier code have always found them.
__all__ = ["SWEEP_OUTPUTS", "DesignGrid", "design_grid", "sweep", "to_xarray"]

_GROUPS = {
    "force": ("force_max_abs", "force_rms"),
    "energy": ("energy_min", "energy_max", "energy_range"),
    "harmonic": ("leading_harmonic", "leading_amplitude"),
}
# Designs per call into Rust: short enough that Ctrl-C is answered within about a second
# (the energy extrema cost ~15 µs per design, the grid outputs ~2 µs), long enough that the
# per-call synchronisation of the thread pool does not show.
_CALL_SIZE = {"energy": 8192, "grid": 65536}
# Engines per call: a few thousand units at most, for the same reasons.
_ENGINE_CALL_SIZE = 1024


# ----------------------------------------------------------------------------- options
def _as_phi(phi: Any) -> np.ndarray:
    if isinstance(phi, (int, np.integer)) and not isinstance(phi, (bool, np.bool_)):
        count = check_size("phi", phi, as_count(phi, "phi", minimum=1))
        try:
            return np.arange(count) * (2 * np.pi / count)
        except (ValueError, MemoryError):
            raise refused(
                "phi", f"phi = {count} points cannot be allocated; allowed: a grid that fits in memory"
            ) from None
    array = as_real_array(phi, "phi")
    if array.ndim != 1 or array.size == 0:
        raise refused(
            "phi",
            f"phi must be a positive int (a uniform grid over one revolution) or a non-empty 1-D array, got shape "
            f"{array.shape}",
        )
    return contiguous(array)


# ----------------------------------------------------------------------------- the sweep
def _reduce(columns: dict[str, np.ndarray], phi: np.ndarray, outputs: tuple[str, ...]) -> dict[str, np.ndarray]:
    """One call into Rust per _CALL_SIZE designs; returns the requested output columns."""
    set_index, phase_sets = phase_table(columns)
    phi = contiguous(phi)  # arrays unpickled on a Dask worker may be misaligned
    parts: list[dict[str, np.ndarray]] = []
    n = len(set_index)
    call_size = _CALL_SIZE["energy" if any(o in outputs for o in _GROUPS["energy"]) else "grid"]
    for start in range(0, n, call_size):
        part = slice(start, min(start + call_size, n))
        design = {c: contiguous(columns[c][part]) for c in DESIGN_COLUMNS}
        parts.append(_native_sweep(design, np.ascontiguousarray(set_index[part]), phase_sets, phi, list(outputs)))
    return _joined(parts, outputs)


def _joined(parts: list[dict[str, np.ndarray]], outputs: tuple[str, ...]) -> dict[str, np.ndarray]:
    """The output columns of consecutive Rust calls, joined; leading_harmonic as integers."""
    joined = {name: np.concatenate([p[name] for p in parts]) if parts else np.zeros(0) for name in outputs}
    if "leading_harmonic" in joined:
        joined["leading_harmonic"] = joined["leading_harmonic"].astype(np.int64)
    return joined


def _sweep_frame(frame: pd.DataFrame, phi: np.ndarray, outputs: tuple[str, ...]) -> pd.DataFrame:
    """The designs of `frame` with one column per output (the per-chunk and per-partition work)."""
    reduced = _reduce(machine_columns(frame), phi, outputs)
    result = frame.copy()
    for name, values in reduced.items():
        result[name] = values
    return result


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
    passthrough: Any = None,
) -> Any:
    """Reduce every design of a sweep to the requested outputs, in parallel, in Rust.

    Parameters
    ----------
    designs : DataFrame, mapping, DesignGrid, dask DataFrame or list of Engine
        The designs: a pandas DataFrame, a mapping of equal-length 1-D columns, a
        :class:`DesignGrid`, a ``dask.dataframe.DataFrame``, or a list of
        :class:`Engine` (any layout; the result then has one row per engine with its name
        and number of units). Columns ``crank_ratio`` λ [dimensionless], ``inclination`` γ
        [rad], ``u1``, ``u2`` [dimensionless]; optional ``cranks`` (default 1), ``strokes``
        (2) and ``acting`` ("single"). Any other column is refused unless named in
        ``passthrough``. Every design is validated before the sweep starts.
    phi : int or array_like, default 720
        An int n is the uniform grid φ_i = 2πi/n [rad], i < n (one revolution, endpoint
        excluded); a 1-D array [rad] is used as given. Used by ``force_max_abs`` and
        ``force_rms``.
    outputs : str or sequence of str, default SWEEP_OUTPUTS
        Names from :data:`SWEEP_OUTPUTS`, all dimensionless: ``force_max_abs``,
        ``force_rms``: max|Q_u*| and √mean(Q_u*²) over the φ grid; ``energy_min``,
        ``energy_max``, ``energy_range``: the exact extrema of U_w* over a revolution and
        their difference δ_g (= :func:`speed_fluctuation`); ``leading_harmonic``,
        ``leading_amplitude``: the harmonic n of Q_u* with the largest amplitude
        √(a_n² + b_n²) and that amplitude (0, 0 when Q_u* ≡ 0).
    method : {"exact", "series"}, default "exact"
        Synonyms: the outputs are exact to machine precision. They are computed on the
        Fourier form with exact Λ_n (which equals the closed form to ~1e-15·max|Q|),
        because it is the faster path: few harmonics per design and no sqrt per crank.
    out : str or os.PathLike, optional
        Stream the result to this Parquet file, chunk by chunk (one row group per chunk),
        with bounded memory; the file appears atomically when complete, and the path is
        returned instead of a DataFrame. Finished chunks are kept in ``<out>.parts/``, each
        with a checksum. An existing directory, or a place that cannot be written, is refused
        before any work; a failed or interrupted merge (a full disk) leaves no partial file.
        Needs the ``parquet`` extra.
    resume : bool, default False
        With ``out``: continue an interrupted sweep of the same designs from its finished
        chunks (no row lost or duplicated). The whole definition of the designs (every
        value of a table, or a grid's axes), φ, the outputs and the chunking must match the
        interrupted sweep's, or the resume is refused; a part damaged on disk is computed
        again.
    progress : bool, default False
        Show a progress bar (designs/s, ETA).
    chunk_size : int, default 65536
        Designs per chunk (and per Parquet row group). Results do not depend on it.
    curves : bool, default False
        Also return Q_u* of every design on the φ grid, an array (designs, len(phi)) — for
        small sweeps only.
    passthrough : str or sequence of str, optional
        Columns of a table of designs that are not design columns (labels, ids, …) and are
        carried through to the result unchanged. Design columns and outputs cannot be named.

    Returns
    -------
    pandas.DataFrame or tuple or pathlib.Path or dask.dataframe.DataFrame
        The designs and one column per output, same rows and order; ``(DataFrame, curves)``
        with ``curves=True``; the Parquet file's path with ``out``; a lazy dask DataFrame
        for dask input.

    Raises
    ------
    MechanismError
        For an unknown or misspelt column or output, a bad value in any design (before any
        work starts), or options that do not go together.

    Notes
    -----
    Threads: rayon's pool (``RAYON_NUM_THREADS``); results are bit-identical for any thread
    count and chunk size. Ctrl-C raises KeyboardInterrupt within about a second; with
    ``out`` the finished chunks stay on disk for ``resume=True``.

    Examples
    --------
    >>> import numpy as np
    >>> import multicrank as mc
    >>> grid = mc.design_grid(crank_ratio=np.linspace(0.2, 0.45, 26),
    ...                       inclination=np.radians([0, 45, 90]),
    ...                       u1=np.geomspace(1e-4, 1e-1, 31), u2=0.0,
    ...                       cranks=range(1, 13), strokes=[2, 4])
    >>> result = mc.sweep(grid, phi=360)
    >>> len(result)
    58032
    >>> row = result.query("cranks == 6 and strokes == 4").iloc[-1]
    >>> print(f"λ = {row.crank_ratio}, γ = {np.degrees(row.inclination):.0f}°, "
    ...       f"u1 = {row.u1:g}: δ_g = {row.energy_range:.4e}, "
    ...       f"leading harmonic {row.leading_harmonic:.0f}")
    λ = 0.45, γ = 90°, u1 = 0.1: δ_g = 5.6873e-05, leading harmonic 6
    """
    as_option(method, "method", ("exact", "series"))
    outputs = as_outputs(outputs)
    phi = _as_phi(phi)
    chunk_size = as_count(chunk_size, "chunk_size", minimum=1)
    resume = as_flag(resume, "resume")
    progress = as_flag(progress, "progress")
    curves = as_flag(curves, "curves")
    passthrough = as_passthrough(passthrough)
    path = None if out is None else as_out(out)
    if resume and path is None:
        raise refused("resume", "resume=True needs out= (the Parquet file of the interrupted sweep)")

    if _is_engine_list(designs):
        if path is not None or curves or passthrough:
            raise refused("out", "out=, curves= and passthrough= take tabular designs, not a list of engines")
        return _sweep_engines(list(designs), phi, outputs, progress)

    if is_dask(designs):
        if path is not None or curves:
            raise refused("out", "out= and curves= are not available for dask input: write with dask's to_parquet")
        check_columns(list(designs.columns), passthrough, outputs)
        meta = designs._meta.copy()
        for name in outputs:
            meta[name] = np.zeros(0, dtype=np.int64 if name == "leading_harmonic" else np.float64)
        return designs.map_partitions(_sweep_frame, phi, outputs, meta=meta)

    if not isinstance(designs, DesignGrid):
        designs = as_frame(designs)  # once, for the checks, the fingerprint and the chunks
    # Every design is checked before any work (and before anything is written).
    validate_designs(designs, passthrough, outputs)
    if path is not None:
        if curves:
            raise refused("curves", "curves= cannot be combined with out=")
        return _sweep_to_parquet(designs, path, phi, outputs, chunk_size, resume, progress)

    total, rows = design_rows(designs)
    if curves:  # the designs × φ matrix, checked before the sweep rather than after it
        check_size("curves", f"True for {total} designs × {len(phi)} points", total * len(phi))
    result = in_memory(total, chunk_size, lambda start, stop: _sweep_frame(rows(start, stop), phi, outputs), progress)
    grid_axes = grid_axes_of(designs)
    if grid_axes:
        result.attrs["grid_axes"] = grid_axes
    if curves:
        return result, _curves(result, phi)
    return result


def _curves(frame: pd.DataFrame, phi: np.ndarray) -> np.ndarray:
    """Q_u* of every design on the grid (designs × φ), one Rust call per machine kind."""
    columns = machine_columns(frame)
    set_index, phase_sets = phase_table(columns)
    curves = np.empty((len(frame), len(phi)))
    for code in np.unique(set_index):
        rows = np.flatnonzero(set_index == code)
        curves[rows] = generalized_force(
            phi,
            crank_ratio=columns["crank_ratio"][rows],
            inclination=columns["inclination"][rows],
            u1=columns["u1"][rows],
            u2=columns["u2"][rows],
            phases=phase_sets[code],
        )
    return curves


def _is_engine_list(designs: Any) -> bool:
    return isinstance(designs, (list, tuple)) and len(designs) > 0 and all(isinstance(e, Engine) for e in designs)


def _sweep_engines(engines: list[Engine], phi: np.ndarray, outputs: tuple[str, ...], progress: bool) -> pd.DataFrame:
    """The outputs of each cylinder-level engine, reduced in Rust like designs: for layouts,
    unequal cylinders and Monte-Carlo samples of manufacturing tolerances."""
    bar = progress_bar(len(engines), progress)
    parts: list[dict[str, np.ndarray]] = []
    try:
        for start in range(0, len(engines), _ENGINE_CALL_SIZE):
            batch = engines[start : start + _ENGINE_CALL_SIZE]
            parts.append(_native_sweep_engines([e.columns() for e in batch], contiguous(phi), list(outputs)))
            if bar is not None:
                bar.update(len(batch))
    finally:
        if bar is not None:
            bar.close()
    frame = pd.DataFrame({"engine": [e.name for e in engines], "cylinders": [len(e) for e in engines]})
    for name, values in _joined(parts, outputs).items():
        frame[name] = values
    return frame


def _sweep_to_parquet(
    designs: Any, out: Path, phi: np.ndarray, outputs: tuple[str, ...], chunk_size: int, resume: bool, progress: bool
) -> Path:
    """Sweep chunk by chunk into the parts of a :class:`~multicrank.store.PartStore`, then merge."""
    total, rows = design_rows(designs)
    manifest = fingerprint(total, phi, outputs, chunk_size, designs_digest(designs))
    return to_parquet(
        out,
        manifest,
        total,
        chunk_size,
        lambda start, stop: _sweep_frame(rows(start, stop), phi, outputs),
        resume,
        progress,
    )
