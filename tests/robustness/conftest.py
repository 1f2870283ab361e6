"""Prints the robustness suite's counts at the end of the run (issue 12) and removes its scratch files."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from cases import remove_scratch  # noqa: E402
from harness import STATS  # noqa: E402


def pytest_sessionfinish(session, exitstatus):  # noqa: ARG001
    """Remove the directories and files the valid calls created (``cases.scratch_path``)."""
    remove_scratch()


def pytest_terminal_summary(terminalreporter, exitstatus, config):  # noqa: ARG001
    if STATS["calls"]:
        terminalreporter.write_line(
            f"robustness: {STATS['calls']} calls, {STATS['rejected']} clean rejections, "
            f"{STATS['accepted']} accepted (finite, correctly shaped or success=False)"
            + "; failures: " + ", ".join(f"{k} {STATS[k]}" for k in ("FOREIGN", "SILENT", "VAGUE", "HANG"))
        )
