"""Sampling, robust objective (S4 eq. 10), resumable campaigns and tuning for the S4 loop."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from adcskit.control import (
    LoopSettings,
    mean_change_converged,
    robust_objective,
    weights_from_ratio,
)
from adcskit.control.tuning import monte_carlo, tune_deterministic, tune_robust
from adcskit.errors import InputError
from adcskit.uncertainty import (
    Gaussian,
    TruncatedGaussian,
    latin_hypercube,
    run_campaign,
    sample_stats,
)

SRC = Path(__file__).resolve().parents[2] / "src"
TESTS = Path(__file__).resolve().parents[1]

# S4 Table 5 (digest-decoded), delay and inertia kept positive by truncation
TABLE5 = {
    "inertia": TruncatedGaussian(mean=10.0, std=2.0, low=0.5),
    "torque": TruncatedGaussian(mean=1.0, std=0.2, low=0.05),
    "disturbance": Gaussian(mean=0.05, std=0.05),
    "delay": TruncatedGaussian(mean=0.02, std=0.01, low=0.0),
}
SHORT = LoopSettings(t_final=4.0, t_window=2.0)


def test_lhs_is_stratified_and_seeded():
    n = 200
    s = latin_hypercube(TABLE5, n, rng=7)
    # every marginal has exactly one sample in each 1/n quantile bin (LHS definition)
    u = stats.norm.cdf(s["disturbance"], 0.05, 0.05)
    assert sorted(np.floor(u * n).astype(int)) == list(range(n))
    assert np.all(s["delay"] >= 0) and np.all(s["inertia"] > 0)
    s2 = latin_hypercube(TABLE5, n, rng=7)
    for k in s:
        np.testing.assert_array_equal(s[k], s2[k])
    # mean within 4 sigma/sqrt(n) (LHS is much tighter; seeded statistical bound)
    assert abs(s["inertia"].mean() - 10.0) < 4 * 2.0 / np.sqrt(n)


def test_truncated_gaussian_keeps_sign():
    s = latin_hypercube({"delay": TruncatedGaussian(mean=0.02, std=0.01, low=0.0)}, 5000, rng=1)
    assert s["delay"].min() >= 0.0
    with pytest.raises(InputError, match="low"):
        TruncatedGaussian(mean=0.0, std=1.0, low=1.0, high=0.0)


def test_sample_stats():
    st = sample_stats([1.0, 2.0, 3.0, np.nan])
    assert st.n == 3 and st.mean == 2.0 and st.std == 1.0 and st.p50 == 2.0


def test_robust_objective_eq10():
    e = np.array([[0.1, 0.3], [0.2, 0.2]])
    os = np.array([[5.0, 14.0], [0.0, 0.0]])
    w1, w2 = weights_from_ratio(3.0)
    assert (w1, w2) == (0.25, 0.75)
    f = robust_objective(e, os, w1=w1, w2=w2, penalty_weight=2.0)
    # row 0: 0.25*0.2 + 0.75*0.1 + 2*mean(0, 4) = 0.05 + 0.075 + 4
    np.testing.assert_allclose(f, [0.05 + 0.075 + 4.0, 0.25 * 0.2], rtol=1e-12)
    assert robust_objective([np.nan, 1.0], nonfinite="infeasible") == np.inf  # a diverged sample
    with pytest.raises(InputError, match="errors must be finite"):  # issue 44: not silent by default
        robust_objective([np.nan, 1.0])


def test_robust_objective_penalty_on_mean_overshoot():
    # penalty readings (S4 prints none): per sample, mean(max(os - 10, 0)); on E[os], max(mean(os) - 10, 0)
    e = np.array([[0.1, 0.3], [0.2, 0.2]])
    os = np.array([[5.0, 14.0], [12.0, 12.0]])
    w1, w2 = weights_from_ratio(3.0)
    per = robust_objective(e, os, w1=w1, w2=w2, penalty_weight=2.0, penalty_on="sample")
    mean = robust_objective(e, os, w1=w1, w2=w2, penalty_weight=2.0, penalty_on="mean")
    core = np.array([0.05 + 0.075, 0.25 * 0.2])
    # row 0: per sample 2 * mean(0, 4) = 4; E[os] = 9.5 < 10 -> 0
    # row 1: both samples exceed by 2 -> 4 in both readings
    np.testing.assert_allclose(per, core + [4.0, 4.0], rtol=1e-12)
    np.testing.assert_allclose(mean, core + [0.0, 4.0], rtol=1e-12)
    with pytest.raises(InputError, match="penalty_on"):
        robust_objective(e, os, penalty_on="max")


def test_stopping_rule():
    assert not mean_change_converged([1.0] * 10)  # needs 11 values for 10 changes
    assert mean_change_converged([1.0] * 11)
    assert not mean_change_converged([1.0] * 10 + [0.9])
    assert mean_change_converged([2.0, 1.0] + [1.0] * 10)


def _square(x):
    return x * x


_FAIL_AT = {"value": None}


def _square_or_fail(x):
    if x == _FAIL_AT["value"]:
        raise RuntimeError("interrupted")
    return x * x


def test_campaign_resume_after_interruption(tmp_path):
    tasks = list(range(10))
    _FAIL_AT["value"] = 7
    with pytest.raises(RuntimeError, match="interrupted"):
        run_campaign(_square_or_fail, tasks, directory=tmp_path, chunk_size=2)
    # chunks 0-2 (tasks 0..5) finished before the failure and are on disk
    assert len(list(tmp_path.glob("chunk_*.pkl"))) == 3
    _FAIL_AT["value"] = None
    res = run_campaign(_square_or_fail, tasks, directory=tmp_path, chunk_size=2)
    assert res.values == [t * t for t in tasks]
    assert res.n_resumed == 3 and res.n_chunks == 5
    # a third run computes nothing
    assert run_campaign(_square_or_fail, tasks, directory=tmp_path, chunk_size=2).n_resumed == 5
    # different tasks do not reuse the old chunks
    assert run_campaign(_square, [11, 12], directory=tmp_path, chunk_size=2).n_resumed == 0


def test_monte_carlo_resume(tmp_path):
    a = monte_carlo([56.24, 0.02, 49.99], TABLE5, 40, settings=SHORT, task_size=10,
                    directory=tmp_path, rng=3)
    b = monte_carlo([56.24, 0.02, 49.99], TABLE5, 40, settings=SHORT, task_size=10,
                    directory=tmp_path, rng=3)
    assert a.n_resumed == 0 and b.n_resumed == 4
    np.testing.assert_array_equal(a.metrics.as_array(), b.metrics.as_array())


@pytest.fixture
def worker_path(monkeypatch):
    # spawned workers import adcskit and this test module by name
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(SRC), str(TESTS), *sys.path]))


def test_campaign_serial_vs_dask_local_identical(dask_local2):
    serial = monte_carlo([56.24, 0.02, 49.99], TABLE5, 60, settings=SHORT, task_size=15, rng=11)
    dask = monte_carlo([56.24, 0.02, 49.99], TABLE5, 60, settings=SHORT, task_size=15, rng=11,
                       executor=dask_local2)
    assert dask.executor == "dask-local:2"
    np.testing.assert_array_equal(serial.metrics.as_array(), dask.metrics.as_array())


def test_tune_deterministic_front_is_feasible_and_nondominated():
    r = tune_deterministic(settings=SHORT, pop_size=12, n_gen=4, rng=0)
    assert r.success and r.x.shape[1] == 3
    assert np.all(r.overshoot_pct <= 10.0 + 1e-9)  # S4 eq. (9) constraint
    assert np.all((r.x > 0) & (r.x <= 100))
    F = r.F
    for i in range(len(F)):
        dominated = np.all(F <= F[i], axis=1) & np.any(F < F[i], axis=1)
        assert not dominated.any()
    assert np.all(np.diff(F[:, 0]) >= 0)  # sorted by error


def test_tune_robust_runs_and_is_seeded():
    kw = dict(ratio=10.0, n_samples=4, settings=SHORT, pop_size=8, max_gen=3, rng=5)
    a = tune_robust(TABLE5, **kw)
    b = tune_robust(TABLE5, **kw)
    np.testing.assert_array_equal(a.x, b.x)
    assert a.nit == 3 and a.status == 1 and not a.success
    assert np.all(np.diff(a.history) <= 0)  # elitist GA: best never gets worse
    assert a.fun == pytest.approx(a.history[-1])
    with pytest.raises(InputError, match="dists keys"):
        tune_robust({"kp": Gaussian(mean=1, std=1)}, ratio=1.0)


def test_campaign_resume_after_interruption_on_processes(tmp_path, worker_path):
    # workers write their own chunk files, so chunks finished before the failure survive
    import test_onoff_uncertainty as mod  # the workers import the task function by this name

    from adcskit.uncertainty import make_executor

    tasks = [0, 1, 2, 3, 4, 5, 6, 70]
    with make_executor("processes:2") as ex, pytest.raises(ValueError, match="boom"):
        run_campaign(mod._boom_at_70, tasks, executor=ex, directory=tmp_path, chunk_size=2)
    kept = len(list(tmp_path.glob("chunk_*.pkl")))
    assert 2 <= kept <= 3  # chunks 0-1 finished before the failing chunk 3 could start
    res = run_campaign(mod._square, tasks[:-1] + [7], directory=tmp_path / "other", chunk_size=2)
    assert res.n_resumed == 0
    ok = run_campaign(mod._boom_at_70, tasks[:6], directory=tmp_path, chunk_size=2)
    # tasks[:6] form the same first three chunks as before: those finished are reused
    assert ok.values == [t * t for t in tasks[:6]] and ok.n_resumed == kept


def _boom_at_70(x):
    if x == 70:
        raise ValueError("boom")
    return x * x
