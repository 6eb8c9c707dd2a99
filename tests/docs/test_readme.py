"""The README's Python examples run as written, each on its own in a fresh interpreter (as a
reader pasting one of them would; the Dask example saved as a script and run as one, as it
says), and its shell commands name real options."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[2] / "README.md"
SCRIPT = Path(sys.executable).with_name("multicrank")


def blocks(language: str) -> list[str]:
    return re.findall(rf"^```{language}\n(.*?)^```", README.read_text(encoding="utf-8"), flags=re.M | re.S)


EXAMPLES = blocks("python")


def test_the_readme_has_its_examples():
    assert len(EXAMPLES) >= 10
    assert sum("from distributed import Client" in code for code in EXAMPLES) == 1


@pytest.mark.parametrize("code", EXAMPLES, ids=[f"block {n}" for n in range(1, len(EXAMPLES) + 1)])
def test_python_example_runs_on_its_own(code, tmp_path):
    """Each block in a fresh interpreter, in an empty folder (they write results/ and the
    like), run as a script file: with its own imports, and the Dask one under its
    ``if __name__ == "__main__":`` guard (a local cluster's workers import the script)."""
    script = tmp_path / "example.py"
    script.write_text(code, encoding="utf-8")
    result = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, f"README example fails:\n{code}\n{result.stderr[-3000:]}"
    if "from distributed import Client" in code:
        assert any((tmp_path / "results").glob("*.parquet"))


def test_main_job_installs_the_report_extra():
    assert 'pip install ".[report]" && multicrank report' in blocks("bash")[0]


def test_shell_sweep_example_runs(tmp_path):
    (command,) = [b for b in blocks("bash") if "multicrank sweep" in b]
    args = command.split("#")[0].replace("\\\n", " ").split()[2:]
    # The README's grid, written into tmp_path.
    args[args.index("--out") + 1] = str(tmp_path / "sweep.parquet")
    result = subprocess.run([str(SCRIPT), "sweep", *args, "--no-progress"], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert "designs" in result.stdout and (tmp_path / "sweep.parquet").exists()
