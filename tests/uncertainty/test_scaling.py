"""Campaigns that scale (tasks carry index ranges, the samples travel once) and the
building blocks of S4's paper-scale robust tuning (time estimate, progress, backend)."""

from __future__ import annotations

import os
import pickle
import sys
from pathlib import Path

import numpy as np
import pytest

from adcskit._progress import progress_session
from adcskit.control import LoopSettings
from adcskit.control.tuning import (
    PAPER_SCALE,
    RobustTuningScale,
    estimate_tuning_time,
    evaluate_gains,
    monte_carlo,
    tune_robust,
)
from adcskit.errors import InputError
from adcskit.uncertainty import Gaussian, SerialExecutor, TruncatedGaussian, run_campaign

SRC = Path(__file__).resolve().parents[2] / "src"
TESTS = Path(__file__).resolve().parents[1]
TABLE5 = {  # S4 Table 5, delay and inertia kept positive by truncation
    "inertia": TruncatedGaussian(mean=10.0, std=2.0, low=0.5),
    "torque": TruncatedGaussian(mean=1.0, std=0.2, low=0.05),
    "disturbance": Gaussian(mean=0.05, std=0.05),
    "delay": TruncatedGaussian(mean=0.02, std=0.01, low=0.0),
}
TINY = LoopSettings(t_final=0.2, t_window=0.1)
GAINS = [56.24, 0.02, 49.99]


class _SpyExecutor(SerialExecutor):
    """Serial executor that records the pickled size of every task and of the shared data."""

    def __init__(self) -> None:
        self.task_bytes: list[int] = []
        self.shared_bytes = 0

    def map(self, fn, tasks, *, description="tasks", **kw):
        self.task_bytes += [len(pickle.dumps(t)) for t in tasks]
        if "shared" in kw:
            self.shared_bytes = len(pickle.dumps(kw["shared"]))
        return super().map(fn, tasks, description=description, **kw)


def test_monte_carlo_tasks_do_not_carry_the_samples():
    # 20 000 samples x 4 parameters = 640 kB of float64; each task must stay a few hundred
    # bytes (its index range), the samples travel once as shared data
    spy = _SpyExecutor()
    r = monte_carlo(GAINS, TABLE5, 20_000, settings=TINY, task_size=5000, executor=spy, rng=1)
    assert r.metrics.n_samples == 20_000 and len(spy.task_bytes) == 4
    assert max(spy.task_bytes) < 4096
    assert spy.shared_bytes > 20_000 * 4 * 8


@pytest.fixture(scope="module")
def pools(dask_local2):
    """One process pool and the session's local Dask cluster (2 workers each)."""
    from adcskit.uncertainty import make_executor

    old = os.environ.get("PYTHONPATH")
    # spawned workers import adcskit and this test module by name
    os.environ["PYTHONPATH"] = os.pathsep.join([str(SRC), str(TESTS), *sys.path])
    try:
        with make_executor("processes:2") as proc:
            yield {"processes:2": proc, "dask-local:2": dask_local2}
    finally:
        if old is None:
            os.environ.pop("PYTHONPATH", None)
        else:
            os.environ["PYTHONPATH"] = old


def _scaled_sum(task, shared):
    lo, hi = task
    return float(shared["x"][lo:hi].sum() * shared["scale"])


def test_shared_data_reaches_every_executor(pools):
    import test_scaling as mod  # workers import the task function by this name

    shared = {"x": np.arange(1000.0), "scale": 0.5}
    tasks = [(i, i + 100) for i in range(0, 1000, 100)]
    expected = [0.5 * sum(range(lo, hi)) for lo, hi in tasks]
    for spec, ex in {"serial": "serial", **pools}.items():
        res = run_campaign(mod._scaled_sum, tasks, executor=ex, chunk_size=3, shared=shared)
        assert res.values == expected, spec


def test_monte_carlo_identical_on_every_executor(pools):
    # same seed -> bit-identical metrics, whatever runs the tasks
    kw = dict(settings=LoopSettings(t_final=3.0, t_window=1.0), task_size=25, rng=7)
    ref = monte_carlo(GAINS, TABLE5, 100, **kw).metrics.as_array()
    for spec, ex in pools.items():
        got = monte_carlo(GAINS, TABLE5, 100, executor=ex, **kw)
        assert got.executor == spec
        np.testing.assert_array_equal(got.metrics.as_array(), ref)


def test_resume_does_not_mix_campaigns_with_other_samples(tmp_path):
    a = monte_carlo(GAINS, TABLE5, 30, settings=TINY, task_size=10, directory=tmp_path, rng=3)
    b = monte_carlo(GAINS, TABLE5, 30, settings=TINY, task_size=10, directory=tmp_path, rng=4)
    c = monte_carlo(GAINS, TABLE5, 30, settings=TINY, task_size=10, directory=tmp_path, rng=3)
    assert b.n_resumed == 0 and c.n_resumed == 3  # same index ranges, other samples: recomputed
    np.testing.assert_array_equal(a.metrics.as_array(), c.metrics.as_array())


def test_paper_scale_is_s4s_protocol():
    # S4 Fig. 8 / Sec. 5: population 70, 1000 iterations, stop at mean change < 1e-7 over 10,
    # 10 000 Monte-Carlo runs; >= 1000 LHS samples per candidate (issue 14)
    assert PAPER_SCALE.to_dict() == {"pop_size": 70, "max_gen": 1000, "n_samples": 1000,
                                     "n_eval": 10_000, "tol": 1e-7, "window": 10}
    assert set(PAPER_SCALE.tune_kwargs()) == {"pop_size", "max_gen", "n_samples", "tol", "window"}
    with pytest.raises(InputError, match="pop_size"):
        RobustTuningScale(pop_size=2)


def test_time_estimate_scales_with_the_run_size():
    s = LoopSettings(t_final=2.0, t_window=1.0)
    small = RobustTuningScale(pop_size=10, max_gen=5, n_samples=4, n_eval=100)
    est = estimate_tuning_time(small, settings=s, calibration_samples=64)
    assert est.backend == "cpu" and est.rate > 0
    # generation = pop x samples x steps / rate; the cap adds the initial population
    assert est.generation_s == pytest.approx(10 * 4 * s.n_steps / est.rate)
    assert est.max_tuning_s == pytest.approx(6 * est.generation_s)
    assert est.evaluation_s == pytest.approx(100 * s.n_steps / est.rate)
    assert "sample-steps/s" in est.message and "worst case" in est.message
    with pytest.raises(InputError, match="backend"):
        estimate_tuning_time(small, settings=s, backend="tpu")


def test_tune_robust_prints_estimate_and_reports_backend(capsys):
    kw = dict(ratio=10.0, n_samples=3, settings=LoopSettings(t_final=1.0, t_window=0.5),
              pop_size=6, max_gen=2, rng=5)
    with progress_session():
        r = tune_robust(TABLE5, time_estimate=True, backend="auto", **kw)
    assert "robust tuning on" in capsys.readouterr().out
    plain = tune_robust(TABLE5, backend="cpu", **kw)
    if r.backend == "cpu":  # no GPU here: auto fell back, same numbers as the CPU run
        np.testing.assert_array_equal(r.x, plain.x)
        assert r.fun == plain.fun
    assert r.to_dict()["backend"] in ("cpu", "cuda")


def test_evaluate_gains_backend_is_validated():
    with pytest.raises(InputError, match="backend"):
        evaluate_gains([1.0, 0.0, 1.0], settings=TINY, backend="numpy")


def test_task_size_leaves_the_campaign_unchanged():
    # onoff-tuning lists task_size as a neutral (execution-only) config key: the samples are
    # drawn once and tasks carry index ranges, so the split must not change any number
    kw = dict(settings=LoopSettings(t_final=3.0, t_window=1.0), rng=5)
    a = monte_carlo(GAINS, TABLE5, 60, task_size=7, **kw).metrics.as_array()
    b = monte_carlo(GAINS, TABLE5, 60, task_size=60, **kw).metrics.as_array()
    np.testing.assert_array_equal(a, b)
