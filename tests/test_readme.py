"""The README's Python examples run as written, in order, in one namespace (as a reader
pasting them one after the other would), and its shell commands name real options."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"
SCRIPT = Path(sys.executable).with_name("multicrank")


def blocks(language: str) -> list[str]:
    return re.findall(rf"^```{language}\n(.*?)^```", README.read_text(encoding="utf-8"), flags=re.M | re.S)


def test_python_examples_run(tmp_path, monkeypatch):
    examples = blocks("python")
    assert len(examples) >= 6
    monkeypatch.chdir(tmp_path)  # the examples write results/ and the like
    namespace: dict = {}
    for number, code in enumerate(examples, start=1):
        try:
            exec(compile(code, f"README.md python block {number}", "exec"), namespace)
        except Exception as error:  # pragma: no cover - the message is the point
            pytest.fail(f"README python block {number} fails: {error!r}\n{code}")


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
