"""What a report is about (python/multicrank/report/settings.py): ``ReportSettings``.

One name per idea (issue 27, item 7): the δ the report sizes a flywheel for is a target, named
``delta_target`` as in ``motion_sweep(delta_target=)`` and the machine file; ``delta``, its name
of 0.1, still works for one release with a DeprecationWarning, and means the same.
"""

from __future__ import annotations

import dataclasses
import pickle

import pytest

import multicrank as mc
from multicrank.presets import MACHINES
from multicrank.report import ReportSettings
from multicrank.report.motion import flywheel_target

MACHINE = MACHINES["slow-compressor"]
DEPRECATED = r"ReportSettings\(delta=\) is deprecated since multicrank 0\.2: use delta_target="


def test_the_target_is_delta_target():
    settings = ReportSettings(machine=MACHINE, delta_target=0.04)
    assert settings.delta_target == 0.04
    assert "delta_target" in {f.name for f in dataclasses.fields(ReportSettings)}
    assert "delta" not in {f.name for f in dataclasses.fields(ReportSettings)}
    assert ReportSettings().delta_target is None
    # the report sizes the flywheel for the δ asked for, before the machine's own class limit
    assert flywheel_target(settings, own=0.5) == (0.04, "asked for (--delta-target)")
    assert dataclasses.replace(settings, delta_target=0.02).delta_target == 0.02


def test_the_keyword_delta_warns_and_gives_the_same_settings():
    with pytest.warns(DeprecationWarning, match=DEPRECATED):
        old = ReportSettings(machine=MACHINE, delta=0.04)
    assert old == ReportSettings(machine=MACHINE, delta_target=0.04)
    assert old.delta_target == 0.04
    assert flywheel_target(old, own=0.5) == (0.04, "asked for (--delta-target)")
    with pytest.warns(DeprecationWarning, match=DEPRECATED):
        assert ReportSettings(delta=None).delta_target is None


def test_the_attribute_delta_warns_and_reads_and_writes_delta_target():
    settings = ReportSettings(machine=MACHINE, delta_target=0.04)
    with pytest.warns(DeprecationWarning, match=r"ReportSettings\.delta is deprecated.*ReportSettings\.delta_target"):
        assert settings.delta == 0.04
    with pytest.warns(DeprecationWarning, match=r"ReportSettings\.delta is deprecated"):
        settings.delta = 0.02
    assert settings.delta_target == 0.02
    assert "delta" not in vars(settings)


def test_both_names_at_once_are_refused_by_name():
    with pytest.raises(mc.MechanismError, match="give delta_target or delta"):
        ReportSettings(delta=0.04, delta_target=0.03)
    positional = [f.name for f in dataclasses.fields(ReportSettings)].index("delta_target")
    values = [getattr(ReportSettings(), f.name) for f in dataclasses.fields(ReportSettings)][:positional]
    with pytest.raises(mc.MechanismError, match="give delta_target or delta"):
        ReportSettings(*values, 0.03, delta=0.04)
    assert ReportSettings(*values, 0.03).delta_target == 0.03


def test_a_pickle_that_holds_delta_loads_as_delta_target():
    settings = ReportSettings(machine=MACHINE, delta_target=0.04)
    assert pickle.loads(pickle.dumps(settings)) == settings
    # 0.1's instance held its target as ``delta``
    state = {f.name: getattr(settings, f.name) for f in dataclasses.fields(ReportSettings) if f.name != "delta_target"}
    old = ReportSettings.__new__(ReportSettings)
    old.__setstate__({**state, "delta": 0.04})
    assert old == settings and "delta" not in vars(old)
