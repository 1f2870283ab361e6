"""Shared test fixtures, and the test lanes (issue 20, item 5).

Markers (registered in ``pyproject.toml``) sort the suite into lanes without changing what
the default run selects (everything but ``slow``):

* ``study`` — quick runs of whole studies (``tests/studies/``), minutes each;
* ``docs`` — the Sphinx build, the docstring examples of every module and the docs pages;
* ``compile`` — tests whose first run compiles a large numba kernel (the closed-loop
  simulator, about 3 minutes on 2 cores; cached in ``__pycache__`` afterwards).

The fast lane for day-to-day work is ``pytest -m "not slow and not study and not docs"``
(a ``-m`` on the command line replaces the ``-m 'not slow'`` of ``addopts``, so keep
``not slow`` in it). CI runs the default ``pytest``, which selects every lane.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")

_TESTS = Path(__file__).resolve().parent

#: marker -> test files (relative to tests/) or directories (ending in "/") it applies to
LANES: dict[str, tuple[str, ...]] = {
    "study": ("studies/",),
    "docs": ("test_sphinx.py", "test_doctests.py", "test_docs.py"),
    "compile": ("simulation/",),
}


def pytest_collection_modifyitems(config, items):
    for item in items:
        try:
            rel = Path(str(item.path)).resolve().relative_to(_TESTS).as_posix()
        except ValueError:
            continue
        for marker, paths in LANES.items():
            if any(rel.startswith(p) if p.endswith("/") else rel == p for p in paths):
                item.add_marker(getattr(pytest.mark, marker))
