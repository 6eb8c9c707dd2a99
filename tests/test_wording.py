"""What the package prints reads as English and as whole numbers: "1 cylinder", not
"1 cylinders"; progress bars that count "0/2", not "0.00/2.00" (issue 26, item 7)."""

from __future__ import annotations

import io
import re
import subprocess
import sys
from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest
import tqdm.auto
import tqdm.std

import multicrank as mc
from multicrank._text import counted
from multicrank.presets import MACHINES

SCRIPT = Path(sys.executable).with_name("multicrank")


@pytest.mark.parametrize(
    ("number", "expected"), [(0, "0 cylinders"), (1, "1 cylinder"), (2, "2 cylinders"), (1200, "1,200 cylinders")]
)
def test_counted(number, expected):
    assert counted(number, "cylinder") == expected


def test_one_cylinder_is_singular_wherever_a_machine_is_described():
    one = MACHINES["slow-compressor"]
    assert len(one) == 1
    assert "1 cylinder," in repr(one) and "1 cylinders" not in repr(one)
    summary = str(mc.steady_state(one, rpm=120))
    assert "1 cylinder)" in summary and "1 cylinders" not in summary
    assert "1 unit)" in repr(one.engine())
    assert "12 cylinders" in repr(MACHINES["slow-diesel-12"])
    result = subprocess.run([str(SCRIPT), "motion", "--rpm", "120"], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "1 cylinder," in result.stdout and "1 cylinders" not in result.stdout


class Recording(tqdm.std.tqdm):
    """tqdm writing into a buffer that the test reads, keeping every bar it made."""

    made: ClassVar[list[Recording]] = []
    text = io.StringIO()

    def __init__(self, *args, **kwargs):
        kwargs.update(file=Recording.text, disable=False, mininterval=0, miniters=1)
        super().__init__(*args, **kwargs)
        Recording.made.append(self)


@pytest.fixture
def bars(monkeypatch):
    Recording.made, Recording.text = [], io.StringIO()
    monkeypatch.setattr(tqdm.auto, "tqdm", Recording)
    return Recording


def fractional_counts(text: str) -> list[str]:
    """Counts printed with decimals ("0.00/2.00")."""
    return re.findall(r"\d+\.\d+/\d+\.\d+", text)


def test_simulate_counts_whole_output_times(bars):
    times = np.linspace(0.0, 0.5, 11)
    mc.simulate(MACHINES["slow-compressor"], times, rpm0=120, progress=True)
    (bar,) = bars.made
    assert isinstance(bar.total, int) and bar.total == 10 and bar.n == 10
    text = bars.text.getvalue()
    assert "10/10" in text and not fractional_counts(text)


def test_sweep_counts_whole_designs(bars):
    designs = mc.design_grid(crank_ratio=[0.2, 0.3], u1=1e-3, u2=0.0, inclination=np.pi / 2, cranks=1)
    mc.sweep(designs, phi=16, progress=True)
    (bar,) = bars.made
    assert isinstance(bar.total, int) and bar.total == 2
    text = bars.text.getvalue()
    assert "2/2" in text and not fractional_counts(text)
