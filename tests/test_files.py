"""The package's file rules (multicrank._files): a file written appears whole or not at all,
and a TOML file that cannot be read is one MechanismError naming it."""

from __future__ import annotations

import os
import re
import stat

import pytest

import multicrank as mc
from multicrank._files import atomic_write, read_toml, write_atomically


def test_a_write_replaces_the_file_whole(tmp_path):
    path = tmp_path / "out.csv"
    path.write_text("old\n")
    write_atomically(path, "a,b\n1,2\n")
    assert path.read_bytes() == b"a,b\n1,2\n"
    write_atomically(path, b"\x89PNG")
    assert path.read_bytes() == b"\x89PNG"
    assert [p.name for p in tmp_path.iterdir()] == ["out.csv"]  # no temporary left


@pytest.mark.parametrize("error", [OSError("disk full"), KeyboardInterrupt()], ids=["error", "Ctrl-C"])
def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path, error):
    path = tmp_path / "out.csv"
    path.write_text("old\n")
    with pytest.raises(type(error)), atomic_write(path) as handle:
        handle.write(b"half")
        raise error
    assert path.read_text() == "old\n" and [p.name for p in tmp_path.iterdir()] == ["out.csv"]


def test_a_failed_fsync_leaves_no_file(tmp_path, monkeypatch):
    def failing(fd):
        raise OSError("fsync failed")

    monkeypatch.setattr(os, "fsync", failing)
    with pytest.raises(OSError, match="fsync failed"):
        write_atomically(tmp_path / "new.csv", "x")
    assert list(tmp_path.iterdir()) == []


def test_a_file_gets_the_permissions_of_a_plain_open(tmp_path):
    plain = tmp_path / "plain"
    plain.write_text("x")
    write_atomically(tmp_path / "atomic", "x")
    assert stat.S_IMODE((tmp_path / "atomic").stat().st_mode) == stat.S_IMODE(plain.stat().st_mode)


@pytest.mark.parametrize(
    ("content", "named"),
    [
        (None, "is a directory, not a sweep configuration"),
        (b"\xff\xfe\x00x = 1\n", "not a UTF-8 text file"),
        (b"x = = 1\n", "not a valid TOML file"),
    ],
)
def test_a_toml_file_that_cannot_be_read_is_one_error_naming_it(tmp_path, content, named):
    path = tmp_path / "config.toml"
    if content is None:
        path.mkdir()
    else:
        path.write_bytes(content)
    with pytest.raises(mc.MechanismError, match=f"^--config {re.escape(str(path))}: {named}"):
        read_toml(path, "a sweep configuration", label=f"--config {path}")
    with pytest.raises(mc.MechanismError, match=f"^{re.escape(str(path))}: {named}"):
        read_toml(path, "a sweep configuration")


def test_read_toml(tmp_path):
    path = tmp_path / "config.toml"
    path.write_text('phi = 360\n[axes]\nu1 = "0.1,0.2"\n')
    assert read_toml(path, "a sweep configuration") == {"phi": 360, "axes": {"u1": "0.1,0.2"}}
    with pytest.raises(mc.MechanismError, match=f"^{re.escape(str(tmp_path / 'none.toml'))}: no such file$"):
        read_toml(tmp_path / "none.toml", "a machine file")
    with pytest.raises(mc.MechanismError, match="path must be a file path"):
        read_toml(3, "a machine file")
