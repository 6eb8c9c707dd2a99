"""Files the package reads and writes: one home for the rules they follow.

:func:`atomic_write` puts a file in place whole or not at all (a sweep's parts and manifest,
the command line's ``--out`` files, the report's pages, figures and tables): a reader never
sees half of it, and a failure or Ctrl-C leaves nothing new behind. :func:`atomic_directory`
does the same for a folder (the report's): filled under a temporary name beside it, it
replaces the old folder only once it is whole. :func:`read_toml` reads
a TOML file (a machine file, a sweep's ``--config``) with one message per way it can fail,
naming the file.
"""

from __future__ import annotations

import os
import shutil
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any

from ._validation import refused

__all__ = ["TEMPORARY_SUFFIX", "atomic_directory", "atomic_write", "read_toml", "write_atomically"]

#: How a temporary file of :func:`atomic_write` ends: a file left by a killed process is
#: recognisable (the sweep store removes such files on resume).
TEMPORARY_SUFFIX = ".tmp"


@contextmanager
def atomic_write(path: str | os.PathLike[str]) -> Iterator[IO[bytes]]:
    """A binary file to write that appears at ``path`` only once it is whole.

    What is written goes to a temporary file beside ``path`` (in the same directory, so that
    the rename cannot cross file systems), which is flushed and fsynced — the bytes are on
    the disk before the name points to them, so a crash cannot leave a file of the right
    name and the wrong content — and then renamed over ``path`` (``os.replace``, atomic).
    On any error or interruption inside the block, or in the flush, fsync or rename, the
    temporary file is removed and ``path`` is left as it was.

    The file is created with the permissions of a plain ``open`` (0o666 less the umask).

    Parameters
    ----------
    path : str or os.PathLike
        The file to write; its directory must exist.

    Yields
    ------
    IO[bytes]
        The temporary file, open for writing bytes.
    """
    target = Path(path)
    # Unique (two writers of one path do not share a temporary), hidden, and ending in
    # TEMPORARY_SUFFIX so that one left by a kill is recognised as such.
    temporary = target.with_name(f".{target.name}.{uuid.uuid4().hex[:12]}{TEMPORARY_SUFFIX}")
    handle = open(temporary, "xb")  # "x": a temporary of this name is ours alone
    try:
        with handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(temporary, target)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


@contextmanager
def atomic_directory(path: str | os.PathLike[str]) -> Iterator[Path]:
    """A folder to fill that appears at ``path`` only once it is whole, replacing the one there.

    The block fills a new, hidden folder beside ``path`` (same parent, so that the renames
    cannot cross file systems; its name ends in :data:`TEMPORARY_SUFFIX`). When the block
    ends without an error, a folder already at ``path`` is renamed aside, the new one renamed
    to ``path`` and the old one removed: the old folder stays as it was, whole, until the new
    one is complete, and a reader sees one or the other, apart from the instant between the
    two renames, when there is none. On any error or interruption (Ctrl-C) the new folder is
    removed and ``path`` is left as it was. The parent folders are created if needed.

    The whole folder is replaced: files in the old one that the block does not write are
    gone afterwards. Deciding whether a folder may be replaced is the caller's.

    Parameters
    ----------
    path : str or os.PathLike
        The folder to write (a symbolic link to a folder: the folder it points to).

    Yields
    ------
    pathlib.Path
        The temporary folder, empty, to fill.
    """
    target = Path(path).resolve()
    target.parent.mkdir(parents=True, exist_ok=True)
    temporary = target.with_name(f".{target.name}.{uuid.uuid4().hex[:12]}{TEMPORARY_SUFFIX}")
    temporary.mkdir()
    try:
        yield temporary
        if not os.path.lexists(target):
            os.replace(temporary, target)
            return
        aside = target.with_name(f".{target.name}.{uuid.uuid4().hex[:12]}.old{TEMPORARY_SUFFIX}")
        os.replace(target, aside)
        try:
            os.replace(temporary, target)
        except BaseException:
            if not os.path.lexists(target):
                os.replace(aside, target)  # the old folder back where it was
            raise
        shutil.rmtree(aside, ignore_errors=True)
    except BaseException:
        shutil.rmtree(temporary, ignore_errors=True)
        raise


def write_atomically(path: str | os.PathLike[str], data: bytes | str) -> None:
    """``data`` at ``path``, whole or not at all (see :func:`atomic_write`); text as UTF-8.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write; its directory must exist.
    data : bytes or str
        Its content; a str is written as UTF-8, its newlines as they are.
    """
    with atomic_write(path) as handle:
        handle.write(data.encode("utf-8") if isinstance(data, str) else data)


def read_toml(path: str | os.PathLike[str], what: str, *, label: str | None = None) -> dict[str, Any]:
    """The TOML file at ``path``, as a dict; any way it cannot be read is one MechanismError.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    what : str
        What the file should be, for the message about a directory, e.g. "a machine file".
    label : str, optional
        How the messages name the file, e.g. "--config sweep.toml" (default: the path).

    Returns
    -------
    dict
        The file's top-level table.

    Raises
    ------
    MechanismError
        Naming the file: not a path, no such file, a directory, unreadable, not UTF-8 text,
        not valid TOML.
    """
    import tomllib

    try:
        name = Path(os.fspath(path))
    except TypeError:
        raise refused("path", f"path must be a file path (str or os.PathLike), got {type(path).__name__}") from None
    where = str(name) if label is None else label
    try:
        with open(name, "rb") as handle:
            return tomllib.load(handle)
    except FileNotFoundError:
        raise refused("path", f"{where}: no such file") from None
    except IsADirectoryError:
        raise refused("path", f"{where}: is a directory, not {what}") from None
    except tomllib.TOMLDecodeError as error:
        raise refused("path", f"{where}: not a valid TOML file: {error}") from None
    except UnicodeDecodeError as error:
        raise refused("path", f"{where}: not a UTF-8 text file: {error.reason}") from None
    except OSError as error:
        raise refused("path", f"{where}: cannot be read: {error.strerror or error}") from None
