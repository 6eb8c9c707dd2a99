"""Hypothesis profiles: "ci" (reproducible, no deadline, failures print a blob to replay
with @reproduce_failure) where the environment variable CI is set, as CI sets it; "dev"
(hypothesis' defaults, new random examples each run) otherwise."""

from __future__ import annotations

import os

from hypothesis import settings

settings.register_profile("ci", deadline=None, derandomize=True, print_blob=True)
settings.register_profile("dev")
settings.load_profile("ci" if os.environ.get("CI") else "dev")
