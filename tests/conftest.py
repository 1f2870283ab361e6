"""Shared test fixtures."""

from __future__ import annotations

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
