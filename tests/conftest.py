"""Hypothesis profiles.

"gate" (loaded by default, with or without the environment variable CI; "ci" is the same
profile under the name CI tools expect): the test command's profile, one that only the code
can fail.

- ``deadline=None``: a per-example deadline measures the machine, not the code; on a busy
  two-core machine a correct test exceeds it (DeadlineExceeded), so no profile here has one.
- ``derandomize=True``: every run draws the same examples (seeded by a hash of the test), so a
  run that passes passes again on the same checkout, and a failure reproduces anywhere.
- ``database=None``: no example is saved to or replayed from ``.hypothesis/``. A saved
  failing example is replayed before anything else, on every later run, so one flaky failure
  (a deadline on a busy machine) or one fixed long ago on another branch would fail the
  checkout forever; what the gate runs depends only on the checkout.
- ``print_blob=True``: a failure prints the ``@reproduce_failure`` line that replays it.

"explore" (``pytest --hypothesis-profile=explore``): new random examples each run, and failures
saved in ``.hypothesis/`` to replay; for looking for new counterexamples by hand, never the
gate. No deadline either.
"""

from __future__ import annotations

from hypothesis import settings

settings.register_profile("gate", deadline=None, derandomize=True, database=None, print_blob=True)
settings.register_profile("ci", parent=settings.get_profile("gate"))
settings.register_profile("explore", deadline=None, print_blob=True)
settings.load_profile("gate")
