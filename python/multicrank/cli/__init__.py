"""The `multicrank` command line (click): one module per command group."""

from .commands import main

__all__ = ["main"]
