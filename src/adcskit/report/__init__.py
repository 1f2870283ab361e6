"""HTML report built from the ``result.json`` files of a results directory."""

from adcskit.report.html import build_report, load_results

__all__ = ["build_report", "load_results"]
