"""Shared test fixtures, and the test lanes (issue 20, item 5).

Markers (registered in ``pyproject.toml``) sort the suite into lanes without changing what
the default run selects (everything but ``slow``):

* ``study`` — quick runs of whole studies (``tests/studies/``), minutes each;
* ``docs`` — the Sphinx build, the docstring examples of every module and the docs pages;
* ``compile`` — tests whose first run compiles a large numba kernel (the closed-loop
  simulator, about 75 CPU-seconds; cached in ``__pycache__`` afterwards).

The fast lane for day-to-day work is ``pytest -m "not slow and not study and not docs"``
(a ``-m`` on the command line replaces the ``-m 'not slow'`` of ``addopts``, so keep
``not slow`` in it). CI runs the default ``pytest``, which selects every lane.

The default run is spread over the cores by pytest-xdist (``-n auto --maxprocesses=4 --dist
worksteal`` in ``addopts``), so a test may not rely on another test having run in its process,
and writes only under ``tmp_path`` (or the robustness suite's scratch root): each worker has
its own session fixtures (``dask_local2`` starts one cluster per worker). ``-n 0`` runs the
suite in one process.
"""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")

TESTS = Path(__file__).resolve().parent
SRC = TESTS.parent / "src"

#: Longest time (s) one Dask map may take in the tests before it is cancelled with a
#: TimeoutError, so that a lost task fails the test instead of hanging CI (issue 23: a map
#: once hung 20 min in Client.scatter). Generous: the tests' maps take a few seconds.
DASK_TIMEOUT_S = 120.0


@pytest.fixture(scope="session")
def dask_local2():
    """One local Dask cluster (2 single-threaded worker processes on 127.0.0.1), started at
    most once per test session and shared by every test that asks for it (a start costs a
    few seconds). Its workers import adcskit from this checkout and test modules by name."""
    pytest.importorskip("dask.distributed")
    from adcskit.uncertainty import DaskExecutor

    old = os.environ.get("PYTHONPATH")
    os.environ["PYTHONPATH"] = os.pathsep.join([str(SRC), str(TESTS), *sys.path])
    try:
        ex = DaskExecutor(n_workers=2, timeout=DASK_TIMEOUT_S)
    finally:
        if old is None:
            os.environ.pop("PYTHONPATH", None)
        else:
            os.environ["PYTHONPATH"] = old
    with ex:
        yield ex


@pytest.fixture(scope="session")
def benchmark_script():
    """``benchmark_script("bench_x")`` -> the module ``benchmarks/bench_x.py``, loaded once per
    session by path (benchmarks are scripts, not a package) and registered under its name; the
    ``sys.path`` entries a script puts first (``benchmarks/``, ``src``) are taken back."""
    loaded = {}

    def load(name: str):
        if name not in loaded:
            spec = importlib.util.spec_from_file_location(name, TESTS.parent / "benchmarks" / f"{name}.py")
            mod = importlib.util.module_from_spec(spec)
            sys.modules.setdefault(name, mod)
            saved = list(sys.path)
            try:
                spec.loader.exec_module(mod)
            finally:
                sys.path[:] = saved
            loaded[name] = mod
        return loaded[name]

    return load


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
