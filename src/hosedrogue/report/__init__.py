"""The reproduction report: every result of Wu et al. (2018) Sec. 2.3 and 3 regenerated from this
project's model, written as one self-contained HTML page with its figures (PNG), the data behind
every figure and table (CSV), the headline numbers (``report.json``) and an animation (GIF).

This package and the CLI are the only code that writes files.
"""

from .build import FAST, FULL, ReportSettings, build_report

__all__ = ["build_report", "ReportSettings", "FULL", "FAST"]
