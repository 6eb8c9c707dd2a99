"""The size rule (issue 37, item 5): no Python module over 500 lines, no Rust source over
600, no test file — Python or Rust — over 800.

Read from the checkout beside this file (the tests run against an installed wheel, but
the sources they hold to the rule are the repository's). A file over its limit is split
along a seam of its own, never trimmed by squeezing lines.
"""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PYTHON_LIMIT, RUST_LIMIT, TEST_LIMIT = 500, 600, 800


def is_rust_test(path: Path) -> bool:
    """A Rust file of tests: an integration test (under a ``tests/`` folder) or a unit-test
    module kept beside its source (``src/<module>/tests.rs``)."""
    return "tests" in path.parts or path.stem == "tests"


def limited_files(root: Path) -> dict[Path, int]:
    """Every source and test file the rule covers → its limit in lines."""
    files: dict[Path, int] = {}
    for path in (root / "python" / "multicrank").rglob("*.py"):
        files[path] = PYTHON_LIMIT
    for path in (root / "tests").rglob("*.py"):
        files[path] = TEST_LIMIT
    for crate in sorted(path for path in (root / "rust").iterdir() if path.is_dir()):
        for folder in ("src", "tests"):
            for path in (crate / folder).rglob("*.rs"):
                files[path] = TEST_LIMIT if is_rust_test(path.relative_to(crate)) else RUST_LIMIT
    return files


def line_count(path: Path) -> int:
    """The file's lines, as ``wc -l`` and an editor count them."""
    return len(path.read_text(encoding="utf-8").splitlines())


def over_limit(root: Path) -> list[str]:
    """'path: N lines (limit L)' for every covered file over its limit, by path."""
    return [
        f"{path.relative_to(root)}: {lines} lines (limit {limit})"
        for path, limit in sorted(limited_files(root).items())
        if (lines := line_count(path)) > limit
    ]


def test_the_walk_finds_every_kind_of_file() -> None:
    # A walk that found nothing would pass the rule vacuously: each kind is there, with its limit.
    files = limited_files(ROOT)
    assert files[ROOT / "python" / "multicrank" / "__init__.py"] == PYTHON_LIMIT
    assert files[Path(__file__).resolve()] == TEST_LIMIT
    assert files[ROOT / "rust" / "core" / "src" / "lib.rs"] == RUST_LIMIT
    assert files[ROOT / "rust" / "python" / "src" / "lib.rs"] == RUST_LIMIT
    rust = [path.relative_to(ROOT / "rust").parts for path in files if path.suffix == ".rs"]
    integration = [parts for parts in rust if parts[1] == "tests"]
    unit = [parts for parts in rust if parts[1] == "src" and parts[-1] == "tests.rs"]
    assert integration and unit, "no Rust test files found: the walk or the layout changed"
    assert all(files[ROOT / "rust" / Path(*parts)] == TEST_LIMIT for parts in integration + unit)
    assert len(files) > 200


@pytest.mark.parametrize(
    ("name", "limit", "lines", "over"),
    [
        ("python/multicrank/big.py", PYTHON_LIMIT, 500, False),
        ("python/multicrank/big.py", PYTHON_LIMIT, 501, True),
        ("rust/core/src/big.rs", RUST_LIMIT, 600, False),
        ("rust/core/src/big.rs", RUST_LIMIT, 601, True),
        ("rust/core/src/big/tests.rs", TEST_LIMIT, 801, True),
        ("rust/core/tests/big.rs", TEST_LIMIT, 800, False),
        ("tests/test_big.py", TEST_LIMIT, 801, True),
    ],
)
def test_a_file_over_its_limit_is_named(tmp_path: Path, name: str, limit: int, lines: int, over: bool) -> None:
    # The check itself, on a made-up checkout: a file at its limit passes, one line more is named.
    for crate in ("core", "python"):
        (tmp_path / "rust" / crate / "src").mkdir(parents=True)
    (tmp_path / "python" / "multicrank").mkdir(parents=True)
    (tmp_path / "tests").mkdir()
    path = tmp_path / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("x = 1\n" * lines, encoding="utf-8")
    expected = [f"{name}: {lines} lines (limit {limit})"] if over else []
    assert over_limit(tmp_path) == expected


def test_every_file_is_within_its_limit() -> None:
    over = over_limit(ROOT)
    assert not over, "over the size rule (split along a seam):\n" + "\n".join(over)
