"""`multicrank report`: the machine's motion with and without gravity, and the paper's
analysis reproduced, corrected and extended, as one HTML page with its figures and tables.

``settings`` holds what a report is about, ``motion`` its first part (the steady running;
``gravity_map`` its map of where gravity matters), ``forces`` the forces on the frame and the
main bearings, ``design`` what to change (firing orders, counterweights), ``gravity`` the
paper's analysis, ``html`` the page and the directory written."""

from .gravity import PAPER_TABLE_1
from .html import write_report
from .settings import DEFAULT_THRESHOLD, ReportSettings

__all__ = ["DEFAULT_THRESHOLD", "PAPER_TABLE_1", "ReportSettings", "write_report"]
