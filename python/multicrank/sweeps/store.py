"""The Parquet store of a sweep: finished chunks as checksummed parts on disk, merged atomically.

A sweep to ``out`` writes each finished chunk as ``<out>.parts/part-NNNNNNNN-<sha256>.parquet``:
written under a temporary name and renamed, so a part exists whole or not at all, and named
by the SHA-256 of its bytes, so a part damaged afterwards (a disk error, a stray edit) is
recognised — recomputed on resume, never merged. Next to the parts, ``manifest.json``
fingerprints the sweep: the whole definition of its designs (see
:func:`designs_digest`), φ (of a gravity sweep), the machine, load and
flywheel target (of a motion sweep), the outputs, the chunking and the library's version; a
resume proceeds only if it matches, and a refusal names what differs. When every part is there they are merged in
order, one row group each, into a temporary file that is renamed to ``out``; the parts are
then removed. Whatever fails or is interrupted on the way (a full disk, Ctrl-C, a kill)
leaves no half-written file at ``out`` or beside it, only whole, checksummed parts for a
resume. Nothing here knows what the chunks contain.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import warnings
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .._files import TEMPORARY_SUFFIX, atomic_write, write_atomically
from .._native import __version__
from .._optional import require
from .._validation import refused
from .designs import ProductGrid, as_frame

__all__ = ["PartStore", "as_out", "designs_digest", "fingerprint"]

# The layout of parts and manifest; a store of another layout is never resumed.
_FORMAT = 2
_PART = re.compile(r"part-(\d{8,})-([0-9a-f]{64})\.parquet")


def designs_digest(designs: Any) -> str:
    """A SHA-256 of everything that makes the designs' rows: a grid's definition (axes and
    constants, their names, order, dtypes and values), or a table's every column.

    Values enter through pandas' per-element hash, which for numbers is a bijection of
    their bits, so any changed value anywhere changes the digest. A table's index does not
    enter: it is not written to Parquet.
    """
    digest = hashlib.sha256()

    def update(kind: str, name: Any, values: pd.Series) -> None:
        digest.update(json.dumps([kind, str(name), str(values.dtype), len(values)]).encode())
        digest.update(pd.util.hash_pandas_object(values, index=False).to_numpy().tobytes())

    if isinstance(designs, ProductGrid):
        for name, array in designs.axes.items():
            update("axis", name, pd.Series(array))
        for name, value in designs.constants.items():
            update("constant", name, pd.Series([value]))
    else:
        frame = as_frame(designs)
        for name in frame.columns:
            update("column", name, frame[name])
    return digest.hexdigest()


def fingerprint(
    total: int,
    phi: np.ndarray | None,
    outputs: tuple[str, ...],
    chunk_size: int,
    designs: str,
    *,
    settings: Mapping[str, Any] | None = None,
) -> dict:
    """What must match for a resume: the designs (``designs``, a digest of their whole
    definition), their number and chunking, the φ grid (None: a sweep without one), the
    outputs, the library version and whatever else decides the rows (``settings``: names to
    JSON-able values, e.g. digests of a motion sweep's machine and load)."""
    manifest: dict[str, Any] = {
        "format": _FORMAT,
        "multicrank": __version__,
        "designs": total,
        "designs_sha256": designs,
        "chunk_size": chunk_size,
        "outputs": list(outputs),
    }
    if phi is not None:
        manifest["phi_sha256"] = hashlib.sha256(np.ascontiguousarray(phi, dtype=np.float64).tobytes()).hexdigest()
    if settings is not None:
        manifest["settings"] = dict(settings)
    return manifest


def as_out(out: Any) -> Path:
    """The ``out=`` of a sweep, checked before any work: a path (str or os.PathLike) that is
    not an existing directory, and whose parts directory is not taken by a file."""
    if isinstance(out, (bytes, bytearray)) or not isinstance(out, (str, os.PathLike)):
        raise refused("out", f"out must be the path of a Parquet file (str or os.PathLike), got {type(out).__name__}")
    try:
        path = Path(out)
    except TypeError as exc:  # an os.PathLike whose __fspath__ gives bytes
        raise refused("out", f"out must be the path of a Parquet file: {exc}") from None
    if path.is_dir():
        raise refused("out", f"out = {str(out)!r} is an existing directory; allowed: the path of a Parquet file")
    parts = _parts_of(path)
    if parts.exists() and not parts.is_dir():
        raise refused("out", f"out = {str(out)!r}: {parts} exists and is not a directory of a sweep's parts")
    return path


def _differences(found: Any, manifest: dict) -> str:
    """The keys in which a store's manifest differs from a sweep's, in words."""
    if not isinstance(found, dict):
        return "its manifest is missing or unreadable: designs, settings, outputs or chunk_size may"
    keys = sorted(k for k in {*found, *manifest} if found.get(k) != manifest.get(k))
    return ", ".join(keys)


def _parts_of(out: Path) -> Path:
    return out.with_name(out.name + ".parts")


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


class PartStore:
    """The parts directory of one sweep to ``out``, with the manifest ``manifest``.

    Opening it starts afresh (removing old parts) unless ``resume``; with ``resume`` the
    existing parts must belong to a sweep with the same manifest. A directory that cannot be
    made or written is a :class:`MechanismError` naming ``out``, raised before any work.
    """

    def __init__(self, out: Path, manifest: dict, *, resume: bool) -> None:
        self._pa = require("pyarrow", "parquet")
        self._pq = require("pyarrow.parquet", "parquet")
        self.out = out
        self.parts = _parts_of(out)
        self._done: dict[int, tuple[Path, str]] = {}
        manifest_file = self.parts / "manifest.json"
        try:
            if self.parts.exists():
                if not resume:
                    shutil.rmtree(self.parts)
                elif (found := self._read_manifest(manifest_file)) != manifest and (
                    manifest_file.exists() or any(self.parts.glob("part-*"))
                ):
                    raise refused(
                        "resume",
                        f"cannot resume: {self.parts} belongs to a different sweep ({_differences(found, manifest)} "
                        "differ); run without resume to start afresh",
                    )
            self.parts.mkdir(parents=True, exist_ok=True)
            write_atomically(manifest_file, json.dumps(manifest, sort_keys=True).encode())
        except OSError as exc:
            raise refused("out", f"out = {str(out)!r}: cannot write its parts to {self.parts}: {exc}") from None

    @staticmethod
    def _read_manifest(path: Path) -> Any:
        try:
            return json.loads(path.read_bytes())
        except (OSError, ValueError):  # missing, unreadable, not JSON (a torn write)
            return None

    def finished(self) -> set[int]:
        """The indices of the chunks whose parts are on disk and intact.

        Every part is checked against its checksum; a damaged one is removed (with a
        warning), so that its chunk is computed again. Temporary files of an interrupted
        write are removed.
        """
        for stale in self.parts.glob(f"*{TEMPORARY_SUFFIX}"):
            stale.unlink(missing_ok=True)
        self._done = {}
        for path in sorted(self.parts.glob("part-*")):
            match = _PART.fullmatch(path.name)
            if match is None:
                continue
            index, checksum = int(match[1]), match[2]
            if index in self._done or _sha256(path.read_bytes()) != checksum:
                warnings.warn(
                    f"sweep part {path.name} is damaged (its bytes do not match its checksum): computing it again",
                    RuntimeWarning,
                    stacklevel=3,
                )
                path.unlink()
                continue
            self._done[index] = (path, checksum)
        return set(self._done)

    def write(self, index: int, frame: pd.DataFrame) -> int:
        """Store chunk ``index``; returns its number of rows."""
        table = self._pa.Table.from_pandas(frame, preserve_index=False)
        sink = self._pa.BufferOutputStream()
        self._pq.write_table(table, sink)
        data = sink.getvalue().to_pybytes()
        checksum = _sha256(data)
        final = self.parts / f"part-{index:08d}-{checksum}.parquet"
        write_atomically(final, data)  # a part exists whole or not at all
        self._done[index] = (final, checksum)
        return int(table.num_rows)

    def merge(self, chunks: int, empty: Callable[[], pd.DataFrame]) -> Path:
        """Merge parts 0 … chunks−1, in order, one row group each, into ``out`` (renamed
        atomically) and remove the parts. With no chunks, ``out`` gets ``empty()``'s columns.

        Each part is checked against its checksum as it is read. On any failure (a damaged
        part, a full disk, an interruption) the temporary file is removed and the intact
        parts are kept for a resume.
        """
        with atomic_write(self.out) as handle:
            writer: Any = None
            try:
                for index in range(chunks):
                    path, checksum = self._done[index]
                    data = path.read_bytes()
                    if _sha256(data) != checksum:
                        path.unlink()
                        raise refused(
                            "out",
                            f"sweep part {path.name} of {self.out} was damaged on disk (its bytes do not match its "
                            "checksum); it has been removed: run the same sweep with resume=True to compute it again",
                        )
                    table = self._pq.read_table(self._pa.BufferReader(data))
                    if writer is None:
                        writer = self._pq.ParquetWriter(handle, table.schema)
                    writer.write_table(table, row_group_size=max(table.num_rows, 1))
                if writer is None:  # no designs: an empty file with the right columns
                    self._pq.write_table(self._pa.Table.from_pandas(empty(), preserve_index=False), handle)
                else:
                    closing, writer = writer, None
                    closing.close()
            except BaseException:
                if writer is not None:
                    try:
                        writer.close()
                    except Exception:  # the disk that failed the write may fail the close too
                        pass
                raise
        shutil.rmtree(self.parts)
        return self.out
