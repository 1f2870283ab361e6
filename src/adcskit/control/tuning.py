"""Deterministic (NSGA-II) and robust (GA) tuning of the on-off loop's PID gains.

* :func:`tune_deterministic` — S4 eq. (9): find ``(K_p, K_i, K_d) ∈ (0, 100]³`` minimising
  [mean ``|e|`` over the last 10 s, fuel] subject to overshoot ≤ 10 %, with pymoo's NSGA-II
  (the constraint handled by pymoo's constraint domination) → Pareto front.
* :func:`tune_robust` — S4 eq. (10): minimise ``w₁ E|Error| + w₂ σ(Error) + penalty`` over
  Latin-hypercube samples of the uncertain parameters with pymoo's single-objective GA
  (population 70 as printed), stopped by S4's rule (mean change of the best objective over
  the last 10 generations < 1e-7) or a generation cap.
* :func:`robust_objective_at` — eq. (10) of given gains on the training samples of a
  :func:`tune_robust` call, computed as that call computes its result (bit for bit): the check
  a stored GA result passes before it is replayed.

The same LHS samples are used for every candidate and generation (common random numbers),
so the robust objective is a deterministic function of the gains and the GA can converge.
Each generation is evaluated as one batch of ``pop × n_samples`` loops by the batch kernel,
on the CPU or an NVIDIA GPU (``backend="cpu" | "cuda" | "auto"``, see
:mod:`adcskit._targets`).

S4's own protocol at full size (:data:`PAPER_SCALE`: population 70, the S4 stopping rule
with the 1000-generation cap, 1000 LHS samples per candidate, a 10 000-run evaluation) is
``tune_robust(dists, ratio=r, **PAPER_SCALE.tune_kwargs(), backend=...)``;
:func:`estimate_tuning_time` predicts its duration from a short calibration run first.

Gains are always in the order ``(K_p, K_i, K_d)`` here; the objective's error is in degrees.

References
----------
S4, eqs. (9)-(10), Tables 4-6, Fig. 8.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from adcskit._progress import bar, status
from adcskit._results import Result, compact_repr
from adcskit._targets import TARGET_BACKENDS, resolve_backend
from adcskit._validation import as_rng, check_choice, check_int, check_positive
from adcskit.control.onoff import LoopParams, LoopSettings, OnOffMetrics, simulate_batch
from adcskit.control.robust import mean_change_converged, robust_objective
from adcskit.errors import InputError
from adcskit.uncertainty.sampling import Fixed, Gaussian, TruncatedGaussian, latin_hypercube

__all__ = [
    "GAIN_NAMES",
    "PAPER_SCALE",
    "MonteCarloResult",
    "ParetoResult",
    "RobustTuningResult",
    "RobustTuningScale",
    "TuningTimeEstimate",
    "estimate_tuning_time",
    "evaluate_gains",
    "monte_carlo",
    "robust_objective_at",
    "tune_deterministic",
    "tune_robust",
]

GAIN_NAMES = ("kp", "ki", "kd")
_UNCERTAIN = ("inertia", "torque", "disturbance", "delay")


def evaluate_gains(
    gains: Any,
    samples: Mapping[str, np.ndarray] | None = None,
    *,
    base: LoopParams | None = None,
    settings: LoopSettings | None = None,
    parallel: bool = True,
    backend: str = "cpu",
) -> OnOffMetrics:
    """Simulate every gain triple on every parameter sample (one batch).

    Parameters
    ----------
    gains : array_like (m, 3) or (3,)
        ``(K_p, K_i, K_d)`` rows.
    samples : mapping of LoopParams field -> ndarray (n,), optional
        Uncertain parameters; fields not given keep ``base``'s values.
    base : LoopParams, optional
        Nominal parameters (S4 Table 3).
    settings : LoopSettings, optional
        Simulation settings.
    parallel : bool
        Use numba's threads (CPU kernel).
    backend : {"cpu", "cuda", "auto"}
        Where the batch runs (``auto``: the GPU when one is usable).

    Returns
    -------
    OnOffMetrics
        Metrics for the ``m × n`` runs, gain-major (reshape to ``(m, n)``).
    """
    g = np.atleast_2d(np.asarray(gains, dtype=float))
    if g.ndim != 2 or g.shape[1] != 3:
        raise InputError(f"gains must have shape (3,) or (m, 3); got {np.shape(gains)}")
    base = LoopParams() if base is None else base
    samples = {} if samples is None else dict(samples)
    n = 1
    for name, v in samples.items():
        v = np.atleast_1d(np.asarray(v, dtype=float))
        samples[name] = v
        n = max(n, v.shape[0])
    m = g.shape[0]
    changes: dict[str, Any] = {name: np.repeat(g[:, j], n) for j, name in enumerate(GAIN_NAMES)}
    for name, v in samples.items():
        changes[name] = np.tile(np.broadcast_to(v, (n,)), m)
    if backend not in TARGET_BACKENDS:
        raise InputError(f"backend must be one of {', '.join(map(repr, TARGET_BACKENDS))}; got {backend!r}")
    return simulate_batch(base.replace(**changes), settings, parallel=parallel, backend=backend)


@dataclass(frozen=True, slots=True, repr=False, kw_only=True)
class ParetoResult(Result):
    """Pareto front of the deterministic two-objective tuning (S4 eq. 9).

    Attributes
    ----------
    x : ndarray (k, 3)
        Non-dominated gains ``(K_p, K_i, K_d)``, sorted by increasing error.
    F : ndarray (k, 2)
        ``[mean |e| over the last window (deg), fuel (N m s)]``.
    overshoot_pct : ndarray (k,)
        Overshoot of each point [%] (all ≤ the limit when ``success``).
    success : bool
    message : str
    nit : int
        Generations run.
    nfev : int
        Loop simulations run.
    """

    x: np.ndarray
    F: np.ndarray
    overshoot_pct: np.ndarray
    success: bool
    message: str
    nit: int
    nfev: int


@dataclass(frozen=True, slots=True, repr=False, kw_only=True)
class RobustTuningResult(Result):
    """Outcome of the robust GA tuning (S4 eq. 10).

    Attributes
    ----------
    x : ndarray (3,)
        Best gains ``(K_p, K_i, K_d)``.
    fun : float
        Robust objective at ``x`` [deg].
    mean_abs_err_deg, std_abs_err_deg : float
        Mean and standard deviation of the per-sample error over the LHS samples [deg].
    max_overshoot_pct : float
        Largest overshoot over the samples [%].
    success : bool
        The S4 stopping rule was met (False: stopped by the generation cap).
    status : int
        0 converged by the S4 rule, 1 generation cap reached.
    message : str
    nit : int
        Generations.
    nfev : int
        Loop simulations (candidates × samples).
    history : ndarray (nit,)
        Best objective after each generation.
    w1, w2 : float
        Weights used.
    backend : str
        Where the loops ran (``cpu`` or ``cuda``).
    """

    x: np.ndarray
    fun: float
    mean_abs_err_deg: float
    std_abs_err_deg: float
    max_overshoot_pct: float
    success: bool
    status: int
    message: str
    nit: int
    nfev: int
    history: np.ndarray = field(repr=False)
    w1: float = 1.0
    w2: float = 1.0
    backend: str = "cpu"


def _bounds(bounds: tuple[float, float]) -> tuple[float, float]:
    lo, hi = float(bounds[0]), float(bounds[1])
    if not (0.0 <= lo < hi) or not math.isfinite(hi):
        raise InputError(f"bounds must be (lo, hi) with 0 <= lo < hi < inf; got {bounds!r}")
    return lo, hi


def _seed(rng: Any) -> int:
    return int(as_rng(rng).integers(0, 2**31 - 1))


def tune_deterministic(
    *,
    base: LoopParams | None = None,
    settings: LoopSettings | None = None,
    pop_size: int = 60,
    n_gen: int = 60,
    bounds: tuple[float, float] = (1e-3, 100.0),
    overshoot_max_pct: float = 10.0,
    rng: Any = None,
    backend: str = "cpu",
) -> ParetoResult:
    """Two-objective deterministic tuning with NSGA-II (S4 eq. 9).

    Parameters
    ----------
    base : LoopParams, optional
        Nominal parameters (S4 Table 3); its gains are ignored.
    settings : LoopSettings, optional
        Simulation settings.
    pop_size, n_gen : int
        NSGA-II population and generations (S4 does not print them).
    bounds : (float, float)
        Box for every gain (S4: ``0 < K ≤ 100``; the lower end is a small positive number).
    overshoot_max_pct : float
        Overshoot constraint [%] (S4: 10).
    rng : Generator or int, optional
        Seeds pymoo.
    backend : {"cpu", "cuda", "auto"}
        Where each generation's batch runs.

    Returns
    -------
    ParetoResult
        Feasible non-dominated points; ``success=False`` if none is feasible.

    References
    ----------
    S4, eq. (9), Table 4, Fig. 9.
    """
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    pop_size = check_int("pop_size", pop_size, minimum=4)
    n_gen = check_int("n_gen", n_gen, minimum=1)
    lo, hi = _bounds(bounds)
    osmax = check_positive("overshoot_max_pct", overshoot_max_pct)
    base = LoopParams() if base is None else base
    target = resolve_backend(backend)
    counter = {"nfev": 0}

    class _Problem(Problem):
        def __init__(self) -> None:
            super().__init__(n_var=3, n_obj=2, n_ieq_constr=1, xl=lo, xu=hi)

        def _evaluate(self, x, out, *args, **kwargs):
            m = evaluate_gains(x, base=base, settings=settings, backend=target)
            counter["nfev"] += x.shape[0]
            err = np.degrees(m.mean_abs_err_last)
            fuel = m.fuel
            bad = ~np.isfinite(err) | ~np.isfinite(fuel)
            out["F"] = np.column_stack([np.where(bad, 1e6, err), np.where(bad, 1e6, fuel)])
            out["G"] = (np.nan_to_num(m.overshoot_pct, nan=1e6) - osmax)[:, None]

    res = minimize(
        _Problem(), NSGA2(pop_size=pop_size), ("n_gen", n_gen), seed=_seed(rng), verbose=False
    )
    if res.X is None or res.F is None:
        return ParetoResult(
            x=np.empty((0, 3)),
            F=np.empty((0, 2)),
            overshoot_pct=np.empty(0),
            success=False,
            message="no feasible gains (overshoot constraint never met)",
            nit=n_gen,
            nfev=counter["nfev"],
        )
    X = np.atleast_2d(res.X)
    F = np.atleast_2d(res.F)
    order = np.argsort(F[:, 0], kind="stable")
    X, F = X[order], F[order]
    m = evaluate_gains(X, base=base, settings=settings, backend=target)
    return ParetoResult(
        x=X,
        F=F,
        overshoot_pct=m.overshoot_pct,
        success=True,
        message=f"{X.shape[0]} non-dominated feasible points after {n_gen} generations",
        nit=n_gen,
        nfev=counter["nfev"],
    )


def tune_robust(
    dists: Mapping[str, Gaussian | TruncatedGaussian | Fixed],
    *,
    ratio: float,
    n_samples: int = 50,
    base: LoopParams | None = None,
    settings: LoopSettings | None = None,
    pop_size: int = 70,
    max_gen: int = 1000,
    tol: float = 1e-7,
    window: int = 10,
    bounds: tuple[float, float] = (1e-3, 100.0),
    overshoot_max_pct: float = 10.0,
    penalty_weight: float = 1.0,
    rng: Any = None,
    backend: str = "cpu",
    time_estimate: bool = False,
    penalty_on: str = "sample",
) -> RobustTuningResult:
    """Robust GA tuning on LHS samples (S4 eq. 10, Fig. 8).

    Parameters
    ----------
    dists : mapping of LoopParams field -> distribution
        Uncertain parameters (S4 Table 5: ``inertia``, ``torque``, ``disturbance``,
        ``delay``).
    ratio : float
        Weight ratio ``w₂/w₁`` (weights normalised to sum 1).
    n_samples : int
        LHS samples per objective evaluation (S4 does not print it).
    base, settings
        Nominal parameters and simulation settings.
    pop_size : int
        GA population (S4: 70).
    max_gen : int
        Generation cap (S4: 1000 iterations).
    tol, window
        S4 stopping rule: mean change of the best objective over the last ``window``
        generations < ``tol`` (S4: 1e-7, 10).
    bounds : (float, float)
        Box for every gain (S4: ``0 < K ≤ 100``).
    overshoot_max_pct, penalty_weight : float
        Overshoot constraint [%] and its penalty [deg per % of mean excess].
    rng : Generator or int, optional
        Draws the LHS samples and seeds pymoo.
    backend : {"cpu", "cuda", "auto"}
        Where each generation's ``pop × n_samples`` batch runs.
    time_estimate : bool
        Before starting, time a short calibration run (:func:`estimate_tuning_time`) and
        print the predicted duration above the progress bars (shown when a progress session
        is active, e.g. under the CLI). A progress bar over the generations is always
        offered to the active session.
    penalty_on : {"sample", "mean"}
        Penalise each sample's overshoot excess (averaged) or the excess of the mean
        overshoot (:func:`adcskit.control.robust.robust_objective`).

    Returns
    -------
    RobustTuningResult

    References
    ----------
    S4, eq. (10), Table 5, Table 6, Fig. 8.
    """
    from pymoo.algorithms.soo.nonconvex.ga import GA
    from pymoo.core.problem import Problem
    from pymoo.core.termination import Termination
    from pymoo.optimize import minimize

    pop_size = check_int("pop_size", pop_size, minimum=4)
    max_gen = check_int("max_gen", max_gen, minimum=1)
    window = check_int("window", window, minimum=1)
    tol = check_positive("tol", tol)
    lo, hi = _bounds(bounds)
    prob = _robust_problem(dists, ratio=ratio, n_samples=n_samples, base=base, settings=settings,
                           overshoot_max_pct=overshoot_max_pct, penalty_weight=penalty_weight, rng=rng,
                           backend=backend, penalty_on=penalty_on)
    objective, target, counter = prob.objective, prob.target, prob.counter
    if time_estimate:
        est = estimate_tuning_time(
            RobustTuningScale(pop_size=pop_size, max_gen=max_gen, n_samples=prob.n_samples, n_eval=0,
                              tol=tol, window=window),
            settings=settings, backend=target,
        )
        status(est.message)

    class _Problem(Problem):
        def __init__(self) -> None:
            super().__init__(n_var=3, n_obj=1, xl=lo, xu=hi)

        def _evaluate(self, x, out, *args, **kwargs):
            f, _ = objective(x)
            out["F"] = np.where(np.isfinite(f), f, 1e6)[:, None]

    class _S4Termination(Termination):
        def __init__(self) -> None:
            super().__init__()
            self.history: list[float] = []
            self.converged = False

        def _update(self, algorithm) -> float:
            self.history.append(float(algorithm.opt[0].F[0]))
            advance(1)
            if mean_change_converged(self.history, tol=tol, window=window):
                self.converged = True
                return 1.0
            return min(1.0, len(self.history) / max_gen)

    term = _S4Termination()
    with bar(f"robust GA ({target})", max_gen) as advance:
        res = minimize(
            _Problem(), GA(pop_size=pop_size, eliminate_duplicates=True), term, seed=prob.seed, verbose=False
        )
    term = res.algorithm.termination  # pymoo works on its own copy of the termination
    x = np.asarray(res.X, dtype=float).ravel()
    at = prob.at(x)
    converged = term.converged
    return RobustTuningResult(
        x=x,
        **at,
        success=converged,
        status=0 if converged else 1,
        message=(
            f"S4 stopping rule met after {len(term.history)} generations"
            if converged
            else f"generation cap {max_gen} reached before the S4 stopping rule"
        ),
        nit=len(term.history),
        nfev=counter["nfev"],
        history=np.asarray(term.history),
        w1=prob.w1,
        w2=prob.w2,
        backend=target,
    )


@dataclass(frozen=True, slots=True)
class _RobustProblem:
    """The robust objective of one :func:`tune_robust` call: its LHS training samples, pymoo seed
    (drawn from ``rng`` right after the samples), weights and backend, and ``objective(x)`` ->
    (eq. 10 per row of ``x``, the metrics)."""

    objective: Any
    seed: int
    n_samples: int
    w1: float
    w2: float
    target: str
    counter: dict

    def at(self, x: np.ndarray) -> dict[str, float]:
        """Eq. 10 and its statistics at one gain triple, as :class:`RobustTuningResult` holds them."""
        f, m = self.objective(np.asarray(x, dtype=float).reshape(1, 3))
        err = np.degrees(m.mean_abs_err_last)
        return {"fun": float(f[0]), "mean_abs_err_deg": float(np.mean(err)), "std_abs_err_deg": float(np.std(err)),
                "max_overshoot_pct": float(np.nanmax(m.overshoot_pct))}


def _robust_problem(dists, *, ratio, n_samples, base, settings, overshoot_max_pct, penalty_weight, rng, backend,
                    penalty_on) -> _RobustProblem:
    """Validate the objective's inputs, draw the training samples and the pymoo seed (one source for
    :func:`tune_robust` and :func:`robust_objective_at`)."""
    from adcskit.control.robust import weights_from_ratio

    for name in dists:
        if name not in LoopParams.__slots__ or name in GAIN_NAMES:  # type: ignore[attr-defined]
            raise InputError(f"dists keys must be LoopParams fields other than the gains; got {name!r}")
    w1, w2 = weights_from_ratio(ratio)
    n_samples = check_int("n_samples", n_samples, minimum=2)
    osmax = check_positive("overshoot_max_pct", overshoot_max_pct)
    check_choice("penalty_on", penalty_on, ("sample", "mean"))
    base = LoopParams() if base is None else base
    target = resolve_backend(backend)
    gen = as_rng(rng)
    samples = latin_hypercube(dists, n_samples, gen)
    seed = _seed(gen)
    counter = {"nfev": 0}

    def objective(x: np.ndarray) -> tuple[np.ndarray, OnOffMetrics]:
        m = evaluate_gains(x, samples, base=base, settings=settings, backend=target)
        counter["nfev"] += x.shape[0] * n_samples
        err = np.degrees(m.mean_abs_err_last).reshape(x.shape[0], n_samples)
        os = m.overshoot_pct.reshape(x.shape[0], n_samples)
        f = robust_objective(
            err, os, w1=w1, w2=w2, overshoot_max_pct=osmax, penalty_weight=penalty_weight,
            penalty_on=penalty_on, nonfinite="infeasible",
        )
        return f, m

    return _RobustProblem(objective=objective, seed=seed, n_samples=n_samples, w1=w1, w2=w2, target=target,
                          counter=counter)


def robust_objective_at(
    x: Any,
    dists: Mapping[str, Gaussian | TruncatedGaussian | Fixed],
    *,
    ratio: float,
    n_samples: int = 50,
    base: LoopParams | None = None,
    settings: LoopSettings | None = None,
    overshoot_max_pct: float = 10.0,
    penalty_weight: float = 1.0,
    rng: Any = None,
    backend: str = "cpu",
    penalty_on: str = "sample",
    **ga_keywords: Any,
) -> dict[str, float]:
    """S4 eq. (10) of the gains ``x`` on the training samples a :func:`tune_robust` call with the
    same arguments optimised on (same LHS draw from ``rng``), computed as that call computes its
    result's ``fun``: for the same ``x`` on the same machine and backend the value is the same
    float, bit for bit. Used to verify a stored GA result before it is replayed.

    ``ga_keywords`` takes the GA-only arguments of :func:`tune_robust` (``pop_size``,
    ``max_gen``, ``tol``, ``window``, ``bounds``, ``time_estimate``), which do not enter the
    objective; any other keyword is an error.

    Returns
    -------
    dict
        ``fun``, ``mean_abs_err_deg``, ``std_abs_err_deg``, ``max_overshoot_pct`` (the fields of
        :class:`RobustTuningResult`).

    Examples
    --------
    >>> from adcskit.uncertainty import Gaussian
    >>> kw = dict(ratio=10.0, n_samples=3, settings=LoopSettings(t_final=2.0, t_window=1.0), rng=7)
    >>> r = tune_robust({"disturbance": Gaussian(mean=0.05, std=0.05)}, pop_size=4, max_gen=1, **kw)
    >>> robust_objective_at(r.x, {"disturbance": Gaussian(mean=0.05, std=0.05)}, **kw)["fun"] == r.fun
    True
    """
    unknown = set(ga_keywords) - {"pop_size", "max_gen", "tol", "window", "bounds", "time_estimate"}
    if unknown:
        raise InputError(f"robust_objective_at got unexpected keywords {sorted(unknown)}; allowed: the arguments "
                         "of tune_robust")
    g = np.asarray(x, dtype=float)
    if g.shape != (3,) or not np.all(np.isfinite(g)):
        raise InputError(f"x must be 3 finite gains (K_p, K_i, K_d); got {x!r}")
    prob = _robust_problem(dists, ratio=ratio, n_samples=n_samples, base=base, settings=settings,
                           overshoot_max_pct=overshoot_max_pct, penalty_weight=penalty_weight, rng=rng,
                           backend=backend, penalty_on=penalty_on)
    return prob.at(g)


@compact_repr
@dataclass(frozen=True, slots=True, kw_only=True)
class MonteCarloResult:
    """Monte-Carlo evaluation of one gain triple.

    Attributes
    ----------
    gains : ndarray (3,)
        ``(K_p, K_i, K_d)``.
    samples : dict of str -> ndarray (n,)
        The LHS parameter samples.
    metrics : OnOffMetrics
        Per-sample metrics (n entries).
    mean_abs_err_deg, std_abs_err_deg : float
        Mean and standard deviation (``ddof=0``, as in eq. 10) of the per-sample error [deg].
    n_resumed : int
        Campaign chunks loaded from disk instead of computed.
    executor : str
        Executor spec.
    """

    gains: np.ndarray
    samples: dict
    metrics: OnOffMetrics = field(repr=False)
    mean_abs_err_deg: float
    std_abs_err_deg: float
    n_resumed: int = 0
    executor: str = "serial"

    def to_dict(self) -> dict[str, Any]:
        return {
            "gains": self.gains,
            "mean_abs_err_deg": self.mean_abs_err_deg,
            "std_abs_err_deg": self.std_abs_err_deg,
            "n": self.metrics.n_samples,
            "n_resumed": self.n_resumed,
            "executor": self.executor,
        }


def _mc_task(task: tuple, samples: Mapping[str, np.ndarray]) -> np.ndarray:
    """One campaign task: simulate ``gains`` on rows ``start:stop`` of the shared samples.

    The task carries only the index range; the sample arrays reach the workers once, as the
    campaign's shared data (scattered on Dask), not inside every task.
    """
    gains, (start, stop), base, settings, parallel, backend = task
    chunk = {k: v[start:stop] for k, v in samples.items()}
    return evaluate_gains(
        gains, chunk, base=base, settings=settings, parallel=parallel, backend=backend
    ).as_array()


def monte_carlo(
    gains: Any,
    dists: Mapping[str, Gaussian | TruncatedGaussian | Fixed],
    n: int,
    *,
    base: LoopParams | None = None,
    settings: LoopSettings | None = None,
    executor: Any = None,
    directory: Any = None,
    task_size: int | None = None,
    rng: Any = None,
    backend: str = "cpu",
) -> MonteCarloResult:
    """Evaluate one gain triple on ``n`` LHS samples, as a resumable campaign.

    The samples are drawn here (once, from ``rng``), sent to the executor's workers once
    (the campaign's shared data) and processed in tasks of ``task_size`` samples that carry
    only their index range, so the result is identical on every executor and the task
    graph stays small whatever ``n``; with ``directory`` an interrupted campaign resumes
    (see :func:`adcskit.uncertainty.campaign.run_campaign`).

    Parameters
    ----------
    gains : array_like (3,)
        ``(K_p, K_i, K_d)``.
    dists : mapping
        Uncertain parameters (S4 Table 5).
    n : int
        Monte-Carlo runs (S4: 10 000).
    base, settings
        Nominal parameters and simulation settings.
    executor : spec or Executor, optional
        Where tasks run.
    directory : path, optional
        Campaign directory (resume).
    task_size : int, optional
        Samples per task (default 1000 on the CPU, 2**21 on the GPU, which needs large
        batches to fill its threads).
    rng : Generator or int, optional
        Draws the samples.
    backend : {"cpu", "cuda", "auto"}
        Where each task's batch runs; on ``cuda`` every worker needs a GPU.

    Returns
    -------
    MonteCarloResult

    References
    ----------
    S4, Figs. 15-21 (10 000 runs per point).
    """
    from adcskit.control._onoff_kernels import METRIC_NAMES
    from adcskit.uncertainty.campaign import run_campaign
    from adcskit.uncertainty.executor import make_executor

    g = np.asarray(gains, dtype=float).ravel()
    if g.shape != (3,):
        raise InputError(f"gains must have shape (3,); got {np.shape(gains)}")
    n = check_int("n", n, minimum=1)
    target = resolve_backend(backend)
    if task_size is None:
        task_size = 1 << 21 if target == "cuda" else 1000
    task_size = check_int("task_size", task_size, minimum=1)
    samples = latin_hypercube(dists, n, rng)
    owns = executor is None or isinstance(executor, str)
    ex = make_executor(executor)
    try:
        parallel = ex.n_workers == 1
        tasks = [
            (g, (i, min(n, i + task_size)), base, settings, parallel, target)
            for i in range(0, n, task_size)
        ]
        camp = run_campaign(_mc_task, tasks, executor=ex, directory=directory, chunk_size=1,
                            description="Monte-Carlo", shared=samples)
    finally:
        if owns:
            ex.close()
    arr = np.concatenate(camp.values, axis=0)
    s = settings or LoopSettings()
    metrics = OnOffMetrics(
        **{name: np.ascontiguousarray(arr[:, j]) for j, name in enumerate(METRIC_NAMES)},
        n_steps=s.n_steps,
        backend="cuda" if target == "cuda" else "numba",
    )
    err = np.degrees(metrics.mean_abs_err_last)
    return MonteCarloResult(
        gains=g,
        samples=samples,
        metrics=metrics,
        mean_abs_err_deg=float(np.mean(err)),
        std_abs_err_deg=float(np.std(err)),
        n_resumed=camp.n_resumed,
        executor=camp.executor,
    )


@dataclass(frozen=True, slots=True, kw_only=True)
class RobustTuningScale(Result):
    """Size of a robust tuning run: GA population, stopping rule, LHS and evaluation sizes.

    Attributes
    ----------
    pop_size : int
        GA population (S4: 70).
    max_gen : int
        Generation cap (S4: 1000 iterations).
    n_samples : int
        LHS samples per candidate evaluation.
    n_eval : int
        Monte-Carlo runs of the final evaluation (S4: 10 000).
    tol, window : float, int
        S4 stopping rule: mean change of the best objective over the last ``window``
        generations < ``tol`` (S4: 1e-7, 10).

    References
    ----------
    S4, Fig. 8 (population 70, 1000 iterations, stopping rule) and Figs. 15-21 (10 000 runs).

    Examples
    --------
    >>> PAPER_SCALE.pop_size, PAPER_SCALE.max_gen, PAPER_SCALE.n_eval
    (70, 1000, 10000)
    >>> RobustTuningScale(max_gen=60, n_samples=40).tune_kwargs()["n_samples"]
    40
    """

    pop_size: int = 70
    max_gen: int = 1000
    n_samples: int = 1000
    n_eval: int = 10_000
    tol: float = 1e-7
    window: int = 10

    def __post_init__(self) -> None:
        check_int("pop_size", self.pop_size, minimum=4)
        check_int("max_gen", self.max_gen, minimum=1)
        check_int("n_samples", self.n_samples, minimum=2)
        check_int("n_eval", self.n_eval, minimum=0)
        check_positive("tol", self.tol)
        check_int("window", self.window, minimum=1)

    def tune_kwargs(self) -> dict[str, Any]:
        """Keyword arguments of :func:`tune_robust` for this scale."""
        return {"pop_size": self.pop_size, "max_gen": self.max_gen, "n_samples": self.n_samples,
                "tol": self.tol, "window": self.window}


PAPER_SCALE = RobustTuningScale()
"""S4's protocol at full size: population 70, S4 stopping rule (1e-7 over 10 generations)
with the 1000-generation cap, 1000 LHS samples per candidate, 10 000-run evaluation."""


@dataclass(frozen=True, slots=True, repr=False, kw_only=True)
class TuningTimeEstimate(Result):
    """Predicted duration of a robust tuning run, from a timed calibration batch.

    Attributes
    ----------
    backend : str
        ``cpu`` or ``cuda``.
    rate : float
        Measured throughput [sample-steps/s] (compilation excluded).
    calibration_s : float
        Wall time of the timed calibration batch [s].
    generation_s : float
        Predicted time of one GA generation (``pop_size × n_samples`` loops) [s].
    max_tuning_s : float
        Predicted time if the GA runs to the generation cap (initial population included) [s].
    evaluation_s : float
        Predicted time of the ``n_eval``-run evaluation [s].
    total_max_s : float
        ``max_tuning_s + evaluation_s`` [s]: an upper bound, the S4 rule usually stops earlier.
    message : str
        One human-readable line.
    """

    backend: str
    rate: float
    calibration_s: float
    generation_s: float
    max_tuning_s: float
    evaluation_s: float
    total_max_s: float
    message: str


def _fmt_duration(s: float) -> str:
    if s < 120:
        return f"{s:.1f} s"
    if s < 7200:
        return f"{s / 60:.1f} min"
    if s < 2 * 86400:
        return f"{s / 3600:.1f} h"
    return f"{s / 86400:.1f} days"


#: Shortest timed calibration of :func:`estimate_tuning_time` (s), and its most batches.
_MIN_CALIBRATION_S = 0.5
_MAX_CALIBRATION_BATCHES = 64


def estimate_tuning_time(
    scale: RobustTuningScale = PAPER_SCALE,
    *,
    settings: LoopSettings | None = None,
    backend: str = "cpu",
    calibration_samples: int | None = None,
    rng: Any = 0,
) -> TuningTimeEstimate:
    """Predict how long a robust tuning run of ``scale`` takes here, from a short timed batch.

    The calibration simulates ``calibration_samples`` loops (random gains in S4's box,
    nominal parameters) for ``min(t_final, 5 s)`` after one untimed warm-up batch
    (compilation), repeated until at least 0.5 s have passed, measures sample-steps per
    second (wall clock: the prediction is of wall time), and scales: one GA generation is
    ``pop_size × n_samples`` loops of ``settings.n_steps`` steps (pymoo's GA evaluates
    ``pop_size`` offspring per generation), the cap adds ``max_gen + 1`` of them (the
    initial population), and the evaluation is ``n_eval`` loops.

    Parameters
    ----------
    scale : RobustTuningScale
        Run size (default :data:`PAPER_SCALE`).
    settings : LoopSettings, optional
        Simulation settings of the run (S4: 1 ms step, 30 s).
    backend : {"cpu", "cuda", "auto"}
        Where the run will execute.
    calibration_samples : int, optional
        Loops in the timed batch (default 1024 on the CPU, 2**20 on the GPU).
    rng : Generator or int
        Draws the calibration gains.

    Returns
    -------
    TuningTimeEstimate
        Rate, per-generation and worst-case times, and a printable message.

    References
    ----------
    S4, Fig. 8 (robust loop, 1000 iterations, stopping rule) and Figs. 15-21 (10 000 runs).

    Examples
    --------
    >>> est = estimate_tuning_time(RobustTuningScale(pop_size=4, max_gen=2, n_samples=2,
    ...     n_eval=10), settings=LoopSettings(t_final=1.0, t_window=0.5), calibration_samples=8)
    >>> est.rate > 0 and est.total_max_s >= est.generation_s
    True
    """
    if not isinstance(scale, RobustTuningScale):
        raise InputError(f"scale must be a RobustTuningScale; got {type(scale).__name__}")
    settings = LoopSettings() if settings is None else settings
    if not isinstance(settings, LoopSettings):
        raise InputError(f"settings must be a LoopSettings; got {type(settings).__name__}")
    target = resolve_backend(backend)
    if calibration_samples is None:
        calibration_samples = 1 << 20 if target == "cuda" else 1024
    n_cal = check_int("calibration_samples", calibration_samples, minimum=1)
    t_cal = min(settings.t_final, 5.0)
    cal = LoopSettings(
        dt=settings.dt, t_final=t_cal, t_window=min(settings.t_window, t_cal),
        tau_thruster=settings.tau_thruster, tau_deriv=settings.tau_deriv,
        command_rate_hz=settings.command_rate_hz, settle_band=settings.settle_band,
    )
    gains = as_rng(rng).uniform(1.0, 100.0, size=(n_cal, 3))
    evaluate_gains(gains[: min(n_cal, 64)], settings=cal, backend=target)  # compile / load cache
    # time whole batches until at least _MIN_CALIBRATION_S have passed (one 1024-loop batch is
    # ~0.05 s on two cores: a single one read 2x apart between runs)
    t0 = time.perf_counter()
    batches = 0
    while True:
        evaluate_gains(gains, settings=cal, backend=target)
        batches += 1
        elapsed = time.perf_counter() - t0
        if elapsed >= _MIN_CALIBRATION_S or batches >= _MAX_CALIBRATION_BATCHES:
            break
    rate = batches * n_cal * cal.n_steps / max(elapsed, 1e-9)
    steps = settings.n_steps
    gen_s = scale.pop_size * scale.n_samples * steps / rate
    tune_s = (scale.max_gen + 1) * gen_s
    eval_s = scale.n_eval * steps / rate
    total = tune_s + eval_s
    msg = (
        f"robust tuning on {target}: measured {rate:.3g} sample-steps/s; one generation = "
        f"{scale.pop_size} x {scale.n_samples} loops x {steps} steps = "
        f"{scale.pop_size * scale.n_samples * steps:.3g} sample-steps ~ {_fmt_duration(gen_s)}; "
        f"at most {scale.max_gen} generations ~ {_fmt_duration(tune_s)} (the S4 rule usually "
        f"stops earlier); {scale.n_eval}-run evaluation ~ {_fmt_duration(eval_s)}; "
        f"worst case ~ {_fmt_duration(total)}"
    )
    return TuningTimeEstimate(
        backend=target, rate=rate, calibration_s=elapsed, generation_s=gen_s,
        max_tuning_s=tune_s, evaluation_s=eval_s, total_max_s=total, message=msg,
    )
