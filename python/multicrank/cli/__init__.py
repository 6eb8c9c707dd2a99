"""The ``multicrank`` command line (click): the group ``main`` and one module per command group.

``_group`` holds the group itself (errors as one line, exit status 2) and the shared
``--machine``; ``_output`` the ``--format``/``--out`` of a result; ``gravity`` the commands
``eval`` and ``tables``; ``motion`` ``motion`` and ``simulate``; ``forces`` ``forces``
(the shaking forces and moments by order); ``sweep`` the group ``sweep`` (the gravity sweep),
``motion_sweep`` its command ``sweep motion``; ``optimize`` the group ``optimize`` (the design
aid: ``optimize firing`` and ``optimize counterweights``); ``report`` ``report``. Each command
imports what it computes with when it runs, so that ``multicrank --help`` stays quick.
"""

from ._group import main
from .forces import forces_command
from .gravity import eval_command, tables_command
from .motion import motion_command, simulate_command
from .motion_sweep import motion_sweep_command
from .optimize import optimize_command
from .report import report_command
from .sweep import sweep_command

for _command in (
    report_command,
    motion_command,
    simulate_command,
    forces_command,
    eval_command,
    tables_command,
    sweep_command,
    optimize_command,
):
    main.add_command(_command)
sweep_command.add_command(motion_sweep_command)

__all__ = ["main"]
