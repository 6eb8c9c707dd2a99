"""`multicrank report`: the machine's motion with and without gravity, and the paper's
analysis reproduced, corrected and extended, as one HTML page with its figures and tables."""

from .gravity import DEFAULT_THRESHOLD, PAPER_TABLE_1, ReportSettings, write_report

__all__ = ["DEFAULT_THRESHOLD", "PAPER_TABLE_1", "ReportSettings", "write_report"]
