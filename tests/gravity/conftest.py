"""Fixtures shared by the gravity room's tests."""

from __future__ import annotations

import pytest

import multicrank as mc


@pytest.fixture
def restore_threshold():
    """The parallel threshold as it was before the test, restored after it."""
    old = mc.get_parallel_threshold()
    try:
        yield old
    finally:
        mc.set_parallel_threshold(old)
