"""Executors give the same results, in task order, whatever runs them (design.md: same seed ->
bit-identical results)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

from adcskit.errors import AdcskitError, InputError
from adcskit.uncertainty import SerialExecutor, make_executor

TESTS = Path(__file__).resolve().parents[1]


def _tasks(n: int = 12):
    return np.random.SeedSequence(2024).spawn(n)


def _expected():
    import fake_study

    return [fake_study.draw(s) for s in _tasks()]


def test_serial_executor_order_and_values():
    import fake_study

    with make_executor("serial") as ex:
        assert isinstance(ex, SerialExecutor) and ex.n_workers == 1
        assert ex.map(fake_study.draw, _tasks()) == _expected()


@pytest.fixture
def tests_on_path(monkeypatch):
    # worker processes import the task function's module by name
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(TESTS), *sys.path]))


def test_process_pool_is_bit_identical(tests_on_path):
    import fake_study

    with make_executor("processes:2") as ex:
        assert ex.n_workers == 2
        assert ex.map(fake_study.draw, _tasks()) == _expected()


def test_dask_local_is_bit_identical(dask_local2):
    import fake_study

    ex = dask_local2  # the session's DaskExecutor(n_workers=2): a cluster start costs seconds
    assert ex.spec == "dask-local:2" and ex.n_workers == 2
    assert ex.dashboard_link.startswith("http://127.0.0.1:")
    assert ex.map(fake_study.draw, _tasks()) == _expected()


@pytest.mark.parametrize(
    ("spec", "args"),
    [("dask-local:2", (None, 2)), ("dask-local", (None, None)), ("dask://10.0.0.7:8786", ("tcp://10.0.0.7:8786",))],
)
def test_dask_specs_build_a_dask_executor(monkeypatch, spec, args):
    import adcskit.uncertainty.executor as executor

    calls = []
    monkeypatch.setattr(executor, "DaskExecutor", lambda *a: calls.append(a) or "built")
    assert executor.make_executor(spec) == "built" and calls == [args]


def test_dask_executor_arguments_are_checked():
    from adcskit.uncertainty import DaskExecutor

    with pytest.raises(InputError, match="n_workers must be"):
        DaskExecutor(n_workers=0)
    with pytest.raises(InputError, match="timeout must be > 0 s"):
        DaskExecutor(n_workers=1, timeout=-1.0)


@pytest.mark.parametrize(
    ("spec", "fragment"),
    [
        ("threads", "executor spec must be one of serial, processes[:N], dask-local[:N], dask://HOST:PORT; got 'threads'"),
        ("processes:0", "must end with a worker count in [1, 1024] after ':'; got '0'"),
        ("processes:x", "must end with a worker count in [1, 1024]"),
        ("processes:100000", "must end with a worker count in [1, 1024]"),
        ("dask://nohost", "needs a host and a numeric port in [1, 65535]"),
        ("dask://host:70000", "needs a host and a numeric port in [1, 65535]; got 'dask://host:70000'"),
        (3, "executor spec must be an Executor or a string"),
    ],
)
def test_bad_specs(spec, fragment):
    # issue 44: each message names the spec, the value and what is allowed
    with pytest.raises(AdcskitError) as err:
        make_executor(spec)
    assert fragment in str(err.value)


def test_array_bytes_counts_the_arrays_inside_tasks():
    # what decides whether DaskExecutor scatters the tasks (SCATTER_TASKS_BYTES): the arrays'
    # nbytes inside tuples, lists and dict values (a simulate task: (shared dict, per-sample
    # dict, seeds, flag)), counted only until the limit is reached
    from adcskit.uncertainty.executor import _array_bytes

    task = ({"C": np.zeros(54)}, {"P": np.zeros((10, 44)), "DIRS": np.zeros((10, 6, 3))}, np.zeros(10, np.uint64), False)
    assert _array_bytes([task, task], limit=10**9) == 2 * 8 * (54 + 440 + 180 + 10)
    assert _array_bytes([task, task], limit=100) < 2 * 8 * (54 + 440 + 180 + 10)  # stopped early
    assert _array_bytes([(1, "text", None), b"abcd"], limit=10**9) == 4
