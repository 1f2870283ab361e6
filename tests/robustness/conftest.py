"""Prints the robustness suite's counts at the end of the run (issue 12)."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from harness import STATS  # noqa: E402


def pytest_terminal_summary(terminalreporter, exitstatus, config):  # noqa: ARG001
    if STATS["calls"]:
        terminalreporter.write_line(
            f"robustness: {STATS['calls']} calls, {STATS['rejected']} clean rejections, "
            f"{STATS['accepted']} accepted (finite, correctly shaped or success=False)"
            + (f", {STATS['hangs']} hangs" if STATS["hangs"] else "")
        )
