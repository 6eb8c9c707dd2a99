"""How a sweep runs its chunks, whatever they compute: in memory, into the Parquet parts of a
:class:`~multicrank.sweeps.store.PartStore` (resumable), with a progress bar; and how a
dask DataFrame of designs is recognised. Shared by :func:`~multicrank.sweep` (gravity) and
:func:`~multicrank.motion_sweep` (motion): each gives a function ``compute(start, stop)``
that returns the result rows of designs ``start … stop − 1``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pandas as pd

from .store import PartStore

__all__ = ["in_memory", "is_dask", "progress_bar", "to_parquet"]

#: The result rows of designs start … stop − 1 (stop may pass the last design).
Compute = Callable[[int, int], pd.DataFrame]


def progress_bar(total: int, enabled: bool, initial: int = 0, desc: str = "sweep") -> Any:
    """A tqdm bar over ``total`` designs, or None when not ``enabled``."""
    if not enabled:
        return None
    from tqdm.auto import tqdm

    # Whole designs: unit_scale would print "0.00/2.00" for a sweep of two.
    return tqdm(total=int(total), initial=int(initial), unit="designs", desc=desc, smoothing=0.1)


def is_dask(designs: Any) -> bool:
    """Whether ``designs`` is a dask DataFrame (without importing dask)."""
    module = type(designs).__module__
    return module.startswith("dask") and hasattr(designs, "map_partitions")


def in_memory(total: int, chunk_size: int, compute: Compute, progress: bool, desc: str = "sweep") -> pd.DataFrame:
    """Every chunk computed in order and concatenated (with no designs: ``compute(0, 0)``)."""
    bar = progress_bar(total, progress, desc=desc)
    pieces = []
    try:
        for start in range(0, total, chunk_size):
            pieces.append(compute(start, start + chunk_size))
            if bar is not None:
                bar.update(len(pieces[-1]))
    finally:
        if bar is not None:
            bar.close()
    if not pieces:
        pieces.append(compute(0, 0))
    return pd.concat(pieces) if len(pieces) > 1 else pieces[0]


def to_parquet(
    out: Path,
    manifest: dict,
    total: int,
    chunk_size: int,
    compute: Compute,
    resume: bool,
    progress: bool,
    desc: str = "sweep",
) -> Path:
    """Every chunk not yet finished computed into a part of the store at ``out`` (fingerprinted
    by ``manifest``), then the parts merged into ``out``."""
    store = PartStore(out, manifest, resume=resume)
    n_chunks = math.ceil(total / chunk_size)
    done = store.finished()
    bar = progress_bar(total, progress, initial=sum(min(chunk_size, total - i * chunk_size) for i in done), desc=desc)
    try:
        for index in range(n_chunks):
            if index in done:
                continue
            start = index * chunk_size
            written = store.write(index, compute(start, start + chunk_size))
            if bar is not None:
                bar.update(written)
    finally:
        if bar is not None:
            bar.close()
    return store.merge(n_chunks, lambda: compute(0, 0))
