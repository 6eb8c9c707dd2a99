"""The `multicrank` command line (click): one module per command group."""

from .motion import main

__all__ = ["main"]
