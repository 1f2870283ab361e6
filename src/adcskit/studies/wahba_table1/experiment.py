"""The measurements of ``wahba-table1``: S0 Table 1 replicas and the noise-bound sweep.

The printed single-epoch vectors (S0 eq. 9, from Ahmed & Kerrigan 2011) are perturbed by
uniform bounded noise of ±``noise_bound`` of each component's value, on both the reference
and the body vectors, then renormalised. Each trial is solved by the q-method (S0's
baseline), the paper's min-max goal attainment — exactly (``minmax``, closed form + KKT on the
box) and iteratively as the paper does (``minmax-slsqp``: SLSQP on the full epigraph problem
from TRIAD, the kind of solver MATLAB's ``fminimax`` is) — NSGA-II with a truth-free knee pick
and with the paper's pick by the true attitude (not deployable), the worst-case robust solver
(Ahmed & Kerrigan), and QUEST/SVD as sanity rows. A noise-bound sweep gives the slope reading
of the "200× less dependence on input accuracy" claim.

Run times of the rows the speed claim compares (:data:`~.timing.TIMED`) come from a separate
timing phase (:mod:`~.timing`): on the first ``timing_epochs`` epochs of each replica, each
method solves the same epoch ``timing_repeats`` times, interleaved with the others, single-
threaded, and its time on an epoch is the median of those repeats (CPU time of the solving
thread, ``time.thread_time``); a row's time per replica is the median over its timed epochs.
The big-budget NSGA-II runs only there, on the first ``n_big_epochs`` epochs. Other rows'
times are single solves (informative only).

Interval given to the robust solvers: midpoint = the measured (noisy, normalised) vector,
radius = ``noise_bound`` × |measured component| (S0 §4-1: "bounds ±b^r, ±r^r ... 20 % of
the input value").

:func:`measure` runs every trial of every replica and of the sweep in one executor map, in one
fixed order of the random stream, and returns frozen records (:class:`Measurements` and the
records it holds). Claims, figures and report read these records only; nothing after
:func:`measure` draws a random number or solves.

References
----------
S0, eq. 9, §4-1, Table 1.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from adcskit._results import Result
from adcskit.determination import robust_wahba, solve_wahba
from adcskit.studies.wahba_table1.config import Config
from adcskit.studies.wahba_table1.draws import angle_deg, epoch_inputs, perturb, perturb_raw
from adcskit.studies.wahba_table1.paper import B_EXACT, PAPER_TABLE1, R_EXACT, q_exact
from adcskit.studies.wahba_table1.timing import TIMED, TimedEpoch, time_epochs

__all__ = ["CHEAP_ROWS", "ITER_ROWS", "ROWS", "SWEEP_ROWS", "ExactVectors", "Measurements", "Replica", "RowStats",
           "Solve", "Trial", "angle_deg", "epoch_inputs", "measure", "perturb", "perturb_raw", "qmethod_in_box", "trial"]

#: Rows run on every trial (cheap). The two "box-at" rows are diagnostics, NOT deployable:
#: the min-max search box centred on the noise-free answer.
CHEAP_ROWS = (
    "q-method", "minmax", "worst-case", "quest", "svd",
    "minmax-box-at-exact-triad", "minmax-box-at-truth",
)
#: Iterative rows, run on the first ``n_iterative`` trials of each replica; ``nsga2-big-knee``
#: (NSGA-II at ``pop_size x nsga2_big_n_gen`` evaluations, knee pick) only on the first
#: ``n_big_epochs`` of them: it is timed for the big-budget readings of ``speed-600x``.
ITER_ROWS = ("minmax-slsqp", "nsga2-knee", "nsga2-truth-pick", "nsga2-big-knee")
ROWS = CHEAP_ROWS[:3] + ITER_ROWS + CHEAP_ROWS[3:]
#: Rows of the noise-bound sweep.
SWEEP_ROWS = ("q-method", "minmax", "worst-case", "minmax-box-at-exact-triad", "minmax-box-at-truth")

_TINY = 1e-12


def qmethod_in_box(b: np.ndarray, r: np.ndarray, search_range: float) -> bool:
    """Whether the unconstrained q-method attitude lies in the ±search_range TRIAD box (S0 §4-1).

    Examples
    --------
    S0 eq. 9's noise-free vectors are inconsistent (~4 deg residual): TRIAD and the q-method
    differ by more than a ±10 % box.

    >>> qmethod_in_box(*perturb(np.random.default_rng(0), 0.0), 0.1)
    False
    """
    qt = solve_wahba(b, r, method="triad").q
    qo = solve_wahba(b, r, method="q-method").q
    if qo @ qt < 0:
        qo = -qo
    return bool(np.all(np.abs(qo - qt) <= search_range * np.abs(qt) + 1e-15))


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class Solve(Result):
    """One row's solve of one trial: attitude error vs ``q_exact`` [deg], CPU time [s] and the
    number of objective evaluations (NSGA-II rows; 0 otherwise)."""

    error_deg: float
    runtime_s: float
    nfev: int = 0


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class Trial(Result):
    """One perturbed epoch solved by every requested row.

    ``in_box``: the q-method attitude lies in the search box; ``cf_vs_slsqp_deg``: angle
    between the closed-form and the SLSQP min-max attitudes (None unless both ran).
    """

    solves: Mapping[str, Solve]
    in_box: bool
    cf_vs_slsqp_deg: float | None = None

    def __contains__(self, row: str) -> bool:
        return row in self.solves


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class RowStats(Result):
    """Statistics of one row over a set of trials (a Table 1 row); ``runtime_s`` is the median
    CPU time per epoch, ``nfev`` the median objective evaluations per epoch (NSGA-II rows)."""

    mean_deg: float
    var_deg2: float
    max_deg: float
    runtime_s: float
    n_trials: int
    nfev: float = 0.0


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class Replica(Result):
    """The deciding quantities of one replica (one seed of the whole pipeline)."""

    stats: Mapping[str, RowStats]
    stats_iterative: Mapping[str, RowStats]
    sweep_mean_deg: Mapping[str, list[float]]
    slopes: Mapping[str, float]
    err_ratio: float
    err_ratio_slsqp: float
    nsga_truth_ratio: float
    nsga_knee_ratio: float
    worst_case_ratio: float
    var_ratio: float
    slope_ratio: float
    speed_ratio: float
    speed_ratio_closed_form: float
    speed_ratio_big: float
    speed_ratio_closed_form_big: float
    minmax_over_nsga_truth: float
    minmax_over_nsga_knee: float
    var_minmax_over_nsga_truth: float
    var_minmax_over_nsga_knee: float
    frac_in_box: float
    cf_vs_slsqp_max_deg: float
    box_truth_mean_deg: float
    box_truth_closer: bool
    box_truth_var_deg2: float
    timing_spread: float = 0.0  # largest (max - min) / median over the timing repeats of one solve
    timing_identical: bool = True  # every timing repeat returned the same attitude as its first solve


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class ExactVectors(Result):
    """S0 eq. 9's noise-free vectors: q-method vs the printed ``q_exact``, and the vector angles [deg]."""

    qmethod_vs_qexact_deg: float
    angle_r1_r2_deg: float
    angle_b1_b2_deg: float


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class Measurements(Result):
    """Everything the study reports: per-replica trials and sweep, replicas, pooled statistics."""

    bounds: np.ndarray
    table: tuple[tuple[Trial, ...], ...]
    sweep: tuple[tuple[tuple[Trial, ...], ...], ...]
    replicas: tuple[Replica, ...]
    stats: Mapping[str, RowStats]
    sweep_mean_deg: Mapping[str, list[float]]
    slopes: Mapping[str, float]
    frac_in_box: float
    cf_vs_slsqp_max_deg: float
    exact: ExactVectors
    timed: tuple[TimedEpoch, ...] = ()  # the timing phase of speed-600x

    @property
    def pooled(self) -> list[Trial]:
        """Every replica's Table 1 trials, replica by replica."""
        return [res for rep in self.table for res in rep]


def _timed(fn):
    """``fn()`` and the CPU time the calling thread spent in it [s] (``time.thread_time``)."""
    t0 = time.thread_time()
    out = fn()
    return out, time.thread_time() - t0


def trial(task: tuple[np.random.SeedSequence, float, dict[str, Any], tuple[str, ...]]) -> Trial:
    """One perturbed epoch solved by every requested row.

    ``task`` is ``(seed, noise bound, {"search_range", "pop_size", "n_gen", "big_n_gen"}, rows)``;
    run times are CPU times of this thread (``time.thread_time``).

    Examples
    --------
    >>> t = trial((np.random.SeedSequence(0), 0.2, {"search_range": 0.1, "pop_size": 8, "n_gen": 4,
    ...            "big_n_gen": 8}, ("q-method", "quest")))
    >>> sorted(t.solves), abs(t.solves["quest"].error_deg - t.solves["q-method"].error_deg) < 1e-6
    (['q-method', 'quest'], True)
    """
    seed, bound, cfg, rows = task
    b, r, seed_ns = epoch_inputs(seed, bound)
    qt = q_exact()
    br, rr = bound * np.abs(b), bound * np.abs(r)
    sr = cfg["search_range"]
    in_box = qmethod_in_box(b, r, sr)
    out: dict[str, Solve] = {}

    def put(row: str, q: np.ndarray, dt: float, nfev: int = 0) -> None:
        out[row] = Solve(error_deg=angle_deg(q, qt), runtime_s=dt, nfev=int(nfev))

    for m in ("q-method", "quest", "svd"):
        if m in rows:
            res, dt = _timed(lambda m=m: solve_wahba(b, r, method=m))
            put(m, res.q, dt)
    qs = {}
    for row, solver in (("minmax", "closed-form"), ("minmax-slsqp", "slsqp")):
        if row in rows:
            res, dt = _timed(lambda s=solver: robust_wahba(b, br, r, rr, method="minmax", search_range=sr, solver=s))
            put(row, res.q, dt)
            qs[row] = res.q
    cf_vs_slsqp = angle_deg(qs["minmax"], qs["minmax-slsqp"]) if len(qs) == 2 else None
    # diagnostics: S0's search box centred on TRIAD of the *noise-free* vectors / on q_exact
    for row, centre in (("minmax-box-at-exact-triad", "triad"), ("minmax-box-at-truth", "truth")):
        if row in rows:
            q0 = qt if centre == "truth" else solve_wahba(B_EXACT, R_EXACT, method="triad").q
            res, dt = _timed(lambda q0=q0: robust_wahba(b, br, r, rr, method="minmax", search_range=sr, q0=q0))
            put(row, res.q, dt)
    if "worst-case" in rows:
        res, dt = _timed(lambda: robust_wahba(b, br, r, rr, method="worst-case"))
        put("worst-case", res.q, dt)
    if "nsga2-knee" in rows or "nsga2-truth-pick" in rows:
        res, dt = _timed(
            lambda: robust_wahba(b, br, r, rr, method="nsga2", search_range=sr,
                                 pop_size=cfg["pop_size"], n_gen=cfg["n_gen"], rng=seed_ns)
        )
        put("nsga2-knee", res.q, dt, res.nfev)
        # the paper's selection: the Pareto point closest to the TRUE attitude (needs truth)
        out["nsga2-truth-pick"] = Solve(error_deg=float(min(angle_deg(q, qt) for q in res.pareto_q)), runtime_s=dt,
                                        nfev=int(res.nfev))
    if "nsga2-big-knee" in rows:  # the big-budget reading of speed-600x: same population, more generations
        res, dt = _timed(
            lambda: robust_wahba(b, br, r, rr, method="nsga2", search_range=sr,
                                 pop_size=cfg["pop_size"], n_gen=cfg["big_n_gen"], rng=seed_ns)
        )
        put("nsga2-big-knee", res.q, dt, res.nfev)
    return Trial(solves=out, in_box=in_box, cf_vs_slsqp_deg=cf_vs_slsqp)


def _stats(results: list[Trial], rows) -> dict[str, RowStats]:
    stats = {}
    for m in rows:
        e = np.array([res.solves[m].error_deg for res in results if m in res])
        t = np.array([res.solves[m].runtime_s for res in results if m in res])
        nf = np.array([res.solves[m].nfev for res in results if m in res])
        stats[m] = RowStats(
            mean_deg=float(e.mean()),
            var_deg2=float(e.var(ddof=1)) if e.size > 1 else float("nan"),
            max_deg=float(e.max()),
            runtime_s=float(np.median(t)),
            n_trials=int(e.size),
            nfev=float(np.median(nf)),
        )
    return stats


def _sweep_mean(points: list[list[Trial]], m: str) -> float:
    return float(np.mean([res.solves[m].error_deg for pt in points for res in pt]))


def _timed_stats(timed: list[TimedEpoch], method: str) -> RowStats:
    """A row's statistics over timed epochs: errors of the answers, median of per-epoch medians."""
    rows = [t for t in timed if method in t.times]
    e = np.array([t.error_deg[method] for t in rows])
    return RowStats(mean_deg=float(e.mean()), var_deg2=float(e.var(ddof=1)) if e.size > 1 else float("nan"),
                    max_deg=float(e.max()), runtime_s=float(np.median([t.median(method) for t in rows])),
                    n_trials=int(e.size), nfev=float(np.median([t.nfev[method] for t in rows])))


def _with_timed_runtimes(stats: dict[str, RowStats], timed: list[TimedEpoch]) -> dict[str, RowStats]:
    """``stats`` with the timed rows' run times replaced by the timing phase's medians."""
    out = dict(stats)
    for m in TIMED:
        if m in out and any(m in t.times for t in timed):
            out[m] = replace(out[m], runtime_s=_timed_stats(timed, m).runtime_s)
    return out


def _replica(results: list[Trial], sweep: list[list[Trial]], bounds: np.ndarray, n_iter: int,
             timed: list[TimedEpoch]) -> Replica:
    """The deciding quantities of one replica (one seed of the whole pipeline).

    Speed ratios are ratios of CPU times per epoch on the same epochs (each the median of
    interleaved repeats of the same solve, :mod:`~.timing`): all timed epochs for the budget
    readings, the big-budget epochs for the big-budget readings.
    """
    st = _stats(results, CHEAP_ROWS)
    sub = results[:n_iter]
    si = _with_timed_runtimes(_stats(sub, ("q-method", "minmax", *ITER_ROWS[:3])), timed)
    big_epochs = [t for t in timed if "nsga2-big-knee" in t.times]
    si["nsga2-big-knee"] = _timed_stats(big_epochs, "nsga2-big-knee")
    sb = {m: _timed_stats(big_epochs, m) for m in ("minmax", "minmax-slsqp")}
    big = si["nsga2-big-knee"].runtime_s
    sw = {m: [_sweep_mean([pt], m) for pt in sweep] for m in SWEEP_ROWS}
    slopes = {m: float(np.polyfit(bounds, np.array(sw[m]), 1)[0]) for m in SWEEP_ROWS}
    q, mm, paper_mm = st["q-method"], st["minmax"], PAPER_TABLE1["minmax"]["mean_deg"]
    return Replica(
        stats=st,
        stats_iterative=si,
        sweep_mean_deg=sw,
        slopes=slopes,
        err_ratio=q.mean_deg / max(mm.mean_deg, _TINY),
        err_ratio_slsqp=si["q-method"].mean_deg / max(si["minmax-slsqp"].mean_deg, _TINY),
        nsga_truth_ratio=si["q-method"].mean_deg / max(si["nsga2-truth-pick"].mean_deg, _TINY),
        nsga_knee_ratio=si["q-method"].mean_deg / max(si["nsga2-knee"].mean_deg, _TINY),
        worst_case_ratio=q.mean_deg / max(st["worst-case"].mean_deg, _TINY),
        var_ratio=q.var_deg2 / max(mm.var_deg2, _TINY),
        slope_ratio=slopes["q-method"] / max(slopes["minmax"], _TINY),
        speed_ratio=si["nsga2-knee"].runtime_s / max(si["minmax-slsqp"].runtime_s, _TINY),
        speed_ratio_closed_form=si["nsga2-knee"].runtime_s / max(si["minmax"].runtime_s, _TINY),
        speed_ratio_big=big / max(sb["minmax-slsqp"].runtime_s, _TINY),
        speed_ratio_closed_form_big=big / max(sb["minmax"].runtime_s, _TINY),
        minmax_over_nsga_truth=si["minmax"].mean_deg / max(si["nsga2-truth-pick"].mean_deg, _TINY),
        minmax_over_nsga_knee=si["minmax"].mean_deg / max(si["nsga2-knee"].mean_deg, _TINY),
        var_minmax_over_nsga_truth=si["minmax"].var_deg2 / max(si["nsga2-truth-pick"].var_deg2, _TINY),
        var_minmax_over_nsga_knee=si["minmax"].var_deg2 / max(si["nsga2-knee"].var_deg2, _TINY),
        frac_in_box=float(np.mean([res.in_box for res in results])),
        cf_vs_slsqp_max_deg=float(max(res.cf_vs_slsqp_deg for res in sub)),
        box_truth_mean_deg=st["minmax-box-at-truth"].mean_deg,
        box_truth_closer=abs(st["minmax-box-at-truth"].mean_deg - paper_mm) < abs(mm.mean_deg - paper_mm),
        box_truth_var_deg2=st["minmax-box-at-truth"].var_deg2,
        timing_spread=max(t.spread(m) for t in timed for m in t.times),
        timing_identical=all(t.identical for t in timed),
    )


def _exact_vectors() -> ExactVectors:
    """The q-method on S0 eq. 9's noise-free vectors, and the angles between them."""
    ex_err = angle_deg(solve_wahba(B_EXACT, R_EXACT).q, q_exact())
    ang_r = np.degrees(np.arccos(np.dot(R_EXACT[0], R_EXACT[1]) / np.prod(np.linalg.norm(R_EXACT, axis=1))))
    ang_b = np.degrees(np.arccos(np.dot(B_EXACT[0], B_EXACT[1]) / np.prod(np.linalg.norm(B_EXACT, axis=1))))
    return ExactVectors(qmethod_vs_qexact_deg=ex_err, angle_r1_r2_deg=float(ang_r), angle_b1_b2_deg=float(ang_b))


def measure(config: Config, *, rng: Any = None, executor: Any = None) -> Measurements:
    """Run every replica's Table 1 trials and noise sweep (all tasks in one executor map).

    Every claim is decided over ``n_seeds`` independent replicas of the whole Table 1
    (``n_trials`` noise draws each, own NSGA-II seeds); the iterative rows (``minmax-slsqp``
    and NSGA-II) run on the first ``n_iterative`` trials of each replica, where the cheap rows
    are compared on the same trials.

    Examples
    --------
    >>> cfg = Config(n_seeds=1, n_trials=3, n_iterative=3, pop_size=4, n_gen=4, nsga2_big_n_gen=6,
    ...              timing_epochs=2, n_big_epochs=1, timing_repeats=2, sweep_bounds=(0.1, 0.2), sweep_trials=2)
    >>> m = measure(cfg, rng=0)
    >>> len(m.replicas), m.stats["nsga2-knee"].n_trials, m.stats["nsga2-big-knee"].nfev, len(m.timed)
    (1, 3, 24.0, 2)
    """
    from adcskit.uncertainty.executor import make_executor

    rng = np.random.default_rng(0) if rng is None else np.random.default_rng(rng)
    ex = executor if executor is not None else make_executor("serial")
    cfg = {"search_range": config.search_range, "pop_size": config.pop_size, "n_gen": config.n_gen,
           "big_n_gen": config.nsga2_big_n_gen}
    root = np.random.SeedSequence(int(rng.integers(2**63 - 1)))
    bounds = np.array(config.sweep_bounds, float)
    nb, n_iter = len(bounds), config.n_iterative
    tasks, where, to_time = [], [], []
    for j, rep in enumerate(root.spawn(config.n_seeds)):
        main_ss, sweep_ss = rep.spawn(2)
        for i, s in enumerate(main_ss.spawn(config.n_trials)):
            rows = CHEAP_ROWS + ITER_ROWS[:3] if i < n_iter else CHEAP_ROWS
            tasks.append((s, config.noise_bound, cfg, rows))
            where.append((j, "table", 0))
            if i < config.timing_epochs:
                to_time.append((j, i, s, config.noise_bound))
        for k, ss in enumerate(sweep_ss.spawn(nb)):
            for s in ss.spawn(config.sweep_trials):
                tasks.append((s, float(bounds[k]), cfg, SWEEP_ROWS))
                where.append((j, "sweep", k))
    out = ex.map(trial, tasks, description="Table 1 replicas and sweep")
    table: list[list[Trial]] = [[] for _ in range(config.n_seeds)]
    sweep: list[list[list[Trial]]] = [[[] for _ in range(nb)] for _ in range(config.n_seeds)]
    for (j, kind, k), res in zip(where, out):
        (table[j] if kind == "table" else sweep[j][k]).append(res)
    # speed-600x: repeats of the same solves, interleaved, single-threaded, after the map (serial)
    timed = time_epochs(to_time, cfg, repeats=config.timing_repeats, n_big=config.n_big_epochs)
    reps = tuple(_replica(table[j], sweep[j], bounds, n_iter, [t for t in timed if t.replica == j])
                 for j in range(config.n_seeds))
    # pooled statistics (all replicas' trials)
    stats = _stats([res for rep in table for res in rep], CHEAP_ROWS)
    stats.update(_stats([r for rep in table for r in rep[:n_iter]], ITER_ROWS[:3]))
    stats = _with_timed_runtimes(stats, list(timed))
    stats["nsga2-big-knee"] = _timed_stats(list(timed), "nsga2-big-knee")
    sweep_mean = {m: [_sweep_mean([sweep[j][k] for j in range(config.n_seeds)], m) for k in range(nb)]
                  for m in SWEEP_ROWS}
    return Measurements(
        bounds=bounds,
        table=tuple(tuple(rep) for rep in table),
        sweep=tuple(tuple(tuple(pt) for pt in rep) for rep in sweep),
        replicas=reps,
        stats=stats,
        sweep_mean_deg=sweep_mean,
        slopes={m: float(np.polyfit(bounds, np.array(sweep_mean[m]), 1)[0]) for m in SWEEP_ROWS},
        frac_in_box=float(np.mean([res.in_box for rep in table for res in rep])),
        cf_vs_slsqp_max_deg=max(m.cf_vs_slsqp_max_deg for m in reps),
        exact=_exact_vectors(),
        timed=timed,
    )
