"""The Parquet store of a sweep: finished chunks as parts on disk, merged atomically.

A sweep to ``out`` writes each finished chunk as ``<out>.parts/part-NNNNNNNN.parquet``
(written to a temporary name and renamed, so a part exists whole or not at all), next to a
``manifest.json`` that fingerprints the sweep. When every part is there they are merged in
order, one row group each, into a temporary file that is renamed to ``out``; the parts are
then removed. A sweep interrupted in between (Ctrl-C, a kill) resumes from its parts if the
fingerprint matches. Nothing here knows what the chunks contain.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ._native import MechanismError
from ._optional import require

__all__ = ["PartStore", "fingerprint"]


def fingerprint(total: int, phi: np.ndarray, outputs: tuple[str, ...], chunk_size: int, first: pd.DataFrame) -> dict:
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


class PartStore:
    """The parts directory of one sweep to ``out``, with the manifest ``manifest``.

    Opening it starts afresh (removing old parts) unless ``resume``; with ``resume`` the
    existing parts must belong to a sweep with the same manifest.
    """

    def __init__(self, out: Path, manifest: dict, *, resume: bool) -> None:
        self._pa = require("pyarrow", "parquet")
        self._pq = require("pyarrow.parquet", "parquet")
        self.out = out
        self.parts = out.with_name(out.name + ".parts")
        manifest_file = self.parts / "manifest.json"
        if self.parts.exists():
            if not resume:
                shutil.rmtree(self.parts)
            elif not manifest_file.exists() or json.loads(manifest_file.read_text()) != manifest:
                raise MechanismError(
                    f"cannot resume: {self.parts} belongs to a different sweep (designs, phi, outputs or chunk_size"
                    " differ)"
                )
        self.parts.mkdir(parents=True, exist_ok=True)
        manifest_file.write_text(json.dumps(manifest))

    def _part(self, index: int) -> Path:
        return self.parts / f"part-{index:08d}.parquet"

    def finished(self) -> set[int]:
        """The indices of the chunks whose parts are on disk."""
        return {int(p.stem.split("-")[1]) for p in self.parts.glob("part-*.parquet")}

    def write(self, index: int, frame: pd.DataFrame) -> int:
        """Store chunk ``index``; returns its number of rows."""
        table = self._pa.Table.from_pandas(frame, preserve_index=False)
        final = self._part(index)
        temporary = final.with_suffix(".tmp")
        self._pq.write_table(table, temporary)
        os.replace(temporary, final)  # a part exists whole or not at all
        return int(table.num_rows)

    def merge(self, chunks: int, empty: Callable[[], pd.DataFrame]) -> Path:
        """Merge parts 0 … chunks−1, in order, one row group each, into ``out`` (renamed
        atomically) and remove the parts. With no chunks, ``out`` gets ``empty()``'s columns."""
        temporary = self.out.with_name(self.out.name + ".tmp")
        writer: Any = None
        try:
            for index in range(chunks):
                table = self._pq.read_table(self._part(index))
                if writer is None:
                    writer = self._pq.ParquetWriter(temporary, table.schema)
                writer.write_table(table, row_group_size=max(table.num_rows, 1))
            if writer is None:  # no designs: an empty file with the right columns
                self._pq.write_table(self._pa.Table.from_pandas(empty(), preserve_index=False), temporary)
        finally:
            if writer is not None:
                writer.close()
        os.replace(temporary, self.out)
        shutil.rmtree(self.parts)
        return self.out
