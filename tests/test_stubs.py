"""The hand-written `_native.pyi` must match the compiled module (mypy.stubtest)."""

import subprocess
import sys


def test_native_stub_matches_module():
    result = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "multicrank._native"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stdout + result.stderr
