"""The measurements of the ``thruster-layout`` study (S3), as typed frozen records.

:func:`measure` runs everything the study decides and draws from: the GA / DE layout designs
(every (n, algorithm, seed), the DE-settings sensitivity at n = 6 and the paired-couple
reading of Table 8), the reference-vs-optimal on-times, the paper's printed layouts scored on
our manoeuvre, the out-of-sample fuel comparison per seed and the pseudo-inverse's torque
miss on random layouts. Claims, figures and tables are pure functions of its
:class:`Measurements` (``claims.py``, ``figures.py``, ``report.py``).

The random stream is one :class:`numpy.random.SeedSequence` drawn from ``rng``; its spawn
order (designs, miss, fuel directions, paired designs, fuel redraws) fixes every number, so it
must not change.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from adcskit._results import Result
from adcskit.studies.thruster_layout.config import Config, parse_de
from adcskit.studies.thruster_layout.paper import A_REF, PAPER, manoeuvre_demands

__all__ = [
    "ALLOCATIONS",
    "AllocComparison",
    "AllocStats",
    "AlgSummary",
    "BestLayout",
    "DesignRun",
    "DesignTask",
    "EminSeed",
    "FUEL_DEFAULT",
    "FuelRun",
    "OUT_OF_SAMPLE",
    "Measurements",
    "MissQuantiles",
    "MissStats",
    "PaperLayoutScore",
    "ReferenceVsOptimal",
    "SettingRun",
    "measure",
    "torque_tolerance_nm",
]

#: Allocations compared on the reference and the optimal layout (S3's, and the exact LP).
ALLOCATIONS = ("pinv-redistribute", "lp-min-fuel")
#: The default reading of the fuel claim.
FUEL_DEFAULT = "out of sample, pinv-redistribute, best design"
_FUEL_READINGS = {
    "default": FUEL_DEFAULT,
    "lp": "out of sample, lp-min-fuel, best design",
    "design": "design demands, pinv-redistribute, best design",
    "de": "out of sample, pinv-redistribute, DE design",
    "lp-de": "out of sample, lp-min-fuel, DE design",
}
#: Readings whose demands are random directions (their ratios carry a sampling error).
OUT_OF_SAMPLE = ("default", "lp", "de", "lp-de")
_MISS_METHODS = ("pinv-redistribute", "nnls", "lp-min-fuel")


@dataclass(frozen=True, slots=True, kw_only=True)
class DesignTask:
    """One optimisation to run (picklable, for any executor); ``setting`` names a DE-sensitivity run."""

    n: int
    alg: str
    seed_index: int
    seed: np.random.SeedSequence
    demands: np.ndarray
    half: tuple[float, ...]
    faces: tuple[str, ...]
    max_cant_deg: float
    weights: tuple[float, ...]
    f_max: float
    t_min: float
    mdot: float
    t_s: float
    gain: float
    pop_size: int
    n_gen: int
    de_strategy: str
    de_F: float
    de_CR: float
    setting: str | None = None
    paired: bool = False
    repeat: int = 0  # > 0: a timing repeat of the main task (same seed, same result)


@dataclass(frozen=True, slots=True, kw_only=True)
class DesignRun:
    """The result of one :class:`DesignTask`: S3 eq. 18's terms, cost and the layout found.

    ``cpu_s`` is the process CPU time (``time.process_time``) of this run; on a main design,
    ``cpu_s_repeats`` holds it and that of each timing repeat (``Config.timing_repeats``), and
    :attr:`cpu_s_median` their median, which the ``de-faster`` claim reads.
    """

    n: int
    alg: str
    seed_index: int
    f_best: float
    torque_error: float
    e_min: float
    sum_tp_s: float
    runtime_s: float
    cpu_s: float
    evaluations: int
    history: Any
    torque_matrix: Any
    positions: Any
    directions: Any
    faces: list[str]
    setting: str | None = None
    paired: bool = False
    repeat: int = 0
    cpu_s_repeats: tuple[float, ...] = ()

    @property
    def cpu_s_median(self) -> float:
        """Median process CPU time over this run and its timing repeats (s)."""
        return float(np.median(self.cpu_s_repeats)) if self.cpu_s_repeats else float(self.cpu_s)


@dataclass(frozen=True, slots=True, kw_only=True)
class AllocStats:
    """One allocation method on one layout over a set of demands."""

    sum_tp_s: float  # mean over demands of the summed on-times
    error_nm: float  # mean torque miss
    max_error_nm: float  # largest torque miss over the demands
    n_missed: int  # demands missed by more than :func:`torque_tolerance_nm`
    all_met: bool
    fuel_kg: float
    on_times_s: np.ndarray  # per thruster, summed over demands


@dataclass(frozen=True, slots=True, repr=False)
class BestLayout(Result):
    """The best layout of one (n, algorithm) over seeds, with the exact LP's allocation on it."""

    torque_matrix: Any
    positions: Any
    directions: Any
    faces: list[str]
    controllable: bool
    lp_sum_tp_s: float
    lp_error_nm: float
    lp_all_met: bool


@dataclass(frozen=True, slots=True, repr=False)
class AlgSummary(Result):
    """One (n, algorithm) over seeds: the best seed's terms, medians and per-seed lists."""

    f_best: float
    torque_error: float
    e_min: float
    sum_tp_s: float
    runtime_s: float
    cpu_s: float
    cpu_s_seeds: list[float]
    evaluations: int
    f_best_median: float
    f_best_seeds: list[float]
    runtime_s_seeds: list[float]
    torque_error_seeds: list[float]
    e_min_seeds: list[float]
    sum_tp_s_seeds: list[float]
    best_layout: BestLayout


@dataclass(frozen=True, slots=True, repr=False)
class AllocComparison(Result):
    """Reference vs the best 6-thruster layout under one allocation, on the design demands."""

    sum_tp_ref_s: float
    sum_tp_opt_s: float
    error_ref_nm: float
    error_opt_nm: float
    all_met_ref: bool
    all_met_opt: bool
    fuel_ref_kg: float
    fuel_opt_kg: float
    on_times_ref_s: np.ndarray
    on_times_opt_s: np.ndarray
    sum_tp_opt_s_per_seed: dict[str, list[float]]


@dataclass(frozen=True, slots=True, repr=False)
class ReferenceVsOptimal(Result):
    """S3 Fig. 5's comparison on the design demands (both allocations)."""

    sum_tp_ref_s: float
    sum_tp_opt_s: float
    allocation: str
    optimal_layout: str
    sum_tp_definition: str
    by_allocation: dict[str, AllocComparison]


@dataclass(frozen=True, slots=True, repr=False)
class PaperLayoutScore(Result):
    """One of S3's printed layout matrices scored on our manoeuvre (eq. 18)."""

    max_column_norm_m: float
    realisable_in_box: bool
    controllable: bool
    f_best_our_manoeuvre: float
    error_nm: float
    e_min_rad: float
    sum_tp_s: float


@dataclass(frozen=True, slots=True)
class MissQuantiles:
    """Relative torque miss of one allocator over the random layouts."""

    median_rel_error: float
    p90_rel_error: float
    max_rel_error: float
    fraction_exact: float  # met to 1e-9 relative

    def to_dict(self) -> dict[str, Any]:
        return {"median_rel_error": self.median_rel_error, "p90_rel_error": self.p90_rel_error,
                "max_rel_error": self.max_rel_error, "fraction_exact_1e-9": self.fraction_exact}


@dataclass(frozen=True, slots=True)
class MissStats:
    """Each allocator's torque miss on random 8-thruster layouts with feasible demands."""

    n_layouts: int
    n_thrusters: int
    by_method: dict[str, MissQuantiles]

    def to_dict(self) -> dict[str, Any]:
        return {"n_layouts": self.n_layouts, "n_thrusters": self.n_thrusters,
                **{m: q.to_dict() for m, q in self.by_method.items()}}


@dataclass(frozen=True, slots=True, repr=False)
class FuelRun(Result):
    """One seed of one reading of the fuel claim: optimal / reference summed on-time."""

    reading: str
    seed_index: int
    layout: str
    sum_tp_ref_s: float
    sum_tp_opt_s: float
    ratio: float
    opt_error_nm: float
    ref_error_nm: float
    opt_max_error_nm: float  # largest torque miss of the optimal layout over the demands
    ref_max_error_nm: float
    opt_n_missed: int  # demands the optimal layout misses by more than :func:`torque_tolerance_nm`
    ref_n_missed: int
    n_demands: int
    ratio_redraws: tuple[float, ...] = ()  # the same ratio on independent redraws of the directions

    @property
    def equal_torque(self) -> bool:
        """Both layouts meet every demand within :func:`torque_tolerance_nm` (the premise of the ratio)."""
        return self.opt_n_missed == 0 and self.ref_n_missed == 0

    @property
    def log_ratio_sd(self) -> float:
        """Sampling error of ``log(ratio)``: its standard deviation over this draw and the redraws
        of the directions (0 without redraws: design demands are not sampled)."""
        draws = (self.ratio, *self.ratio_redraws)
        return float(np.std(np.log(draws), ddof=1)) if len(draws) > 1 else 0.0


@dataclass(frozen=True, slots=True, repr=False)
class EminSeed(Result):
    """One seed of one reading of Table 8: the DE layouts' e_min per n and the worst deviation."""

    rel_dev: float
    e_min: dict[str, float]


@dataclass(frozen=True, slots=True, kw_only=True)
class SettingRun:
    """F_best per seed of one optimiser setting at n = 6 (DE sensitivity)."""

    setting: str
    f_best_seeds: list[float]
    f_best_median: float
    ratio_seeds: tuple[float, ...] = ()  # on the GA entry: per seed, min over DE settings / GA


@dataclass(frozen=True, slots=True, kw_only=True)
class Measurements:
    """Everything :func:`measure` ran, for claims, figures and tables."""

    demands: np.ndarray
    half: np.ndarray
    runs: tuple[DesignRun, ...]  # the (n, algorithm, seed) designs, in task order
    timing_runs: tuple[DesignRun, ...]  # timing repeats of ``runs`` (same seeds), for the CPU-time medians
    setting_runs: tuple[DesignRun, ...]  # DE-sensitivity designs at n = 6
    paired_runs: tuple[DesignRun, ...]  # paired-couple DE designs (Table 8 reading)
    summaries: Mapping[tuple[int, str], AlgSummary]  # in config order of n, then algorithm
    best_per_n: Mapping[int, DesignRun]
    reference_vs_optimal: ReferenceVsOptimal | None
    paper_layouts: Mapping[str, PaperLayoutScore]
    miss: MissStats
    fuel: tuple[FuelRun, ...]  # seed-major, readings in :data:`_FUEL_READINGS` order
    fuel_readings: tuple[str, ...]
    e_min: Mapping[str, tuple[EminSeed, ...]]  # per Table 8 reading, per seed
    e_min_ns: tuple[int, ...]
    sensitivity: tuple[SettingRun, ...]
    total_time_s: float
    total_cpu_s: float

    def run(self, n: int, alg: str, seed_index: int) -> DesignRun:
        """The main design of ``(n, alg)`` on seed ``seed_index``."""
        return next(r for r in self.runs if r.n == n and r.alg == alg and r.seed_index == seed_index)

    def fuel_by_reading(self) -> dict[str, list[FuelRun]]:
        """The fuel runs per reading, seeds in order."""
        return {k: [r for r in self.fuel if r.reading == k] for k in self.fuel_readings}


# ----------------------------------------------------------------------------- tasks


def _design_task(task: DesignTask) -> DesignRun:
    """One optimisation run (picklable, for any executor)."""
    from adcskit.thrusters import box_faces, design_layout

    faces = box_faces(task.half, task.faces, max_cant=math.radians(task.max_cant_deg))
    res = design_layout(
        task.n, task.demands, mounting=faces, algorithm=task.alg,
        weights=task.weights, f_max=task.f_max, t_min=task.t_min, mdot=task.mdot,
        t_s=task.t_s, gain=task.gain, pop_size=task.pop_size, n_gen=task.n_gen,
        de_strategy=task.de_strategy, de_F=task.de_F, de_CR=task.de_CR,
        rng=np.random.default_rng(task.seed), paired=task.paired,
    )
    return DesignRun(
        n=task.n, alg=task.alg, seed_index=task.seed_index,
        f_best=res.fun, torque_error=res.error, e_min=res.e_min, sum_tp_s=res.sum_tp,
        runtime_s=res.runtime_s, cpu_s=res.cpu_s, evaluations=res.nfev, history=res.history,
        torque_matrix=res.torque_matrix, positions=res.thrusters.positions,
        directions=res.thrusters.directions, faces=list(res.thrusters.names),
        setting=task.setting, paired=task.paired, repeat=task.repeat,
    )


def _tasks(cfg: Config, demands: np.ndarray, root: np.random.SeedSequence) -> list[DesignTask]:
    """Every design task, in the order (and with the seeds) of the study's random stream."""
    half = tuple(np.asarray(cfg.box_half_size_m, float))
    children = iter(root.spawn(len(cfg.n_thrusters) * len(cfg.algorithms) * cfg.n_seeds))
    tasks = [
        DesignTask(
            n=int(n), alg=alg, seed_index=s, seed=next(children), demands=demands, half=half,
            faces=tuple(cfg.faces), max_cant_deg=cfg.max_cant_deg, weights=tuple(cfg.weights),
            f_max=cfg.f_max_n, t_min=cfg.t_min_s, mdot=cfg.mdot_kg_s, t_s=cfg.t_s_s,
            gain=cfg.gain_nm_per_rad, pop_size=cfg.pop_size, n_gen=cfg.n_gen,
            de_strategy=cfg.de_strategy, de_F=cfg.de_F, de_CR=cfg.de_CR,
        )
        for s in range(cfg.n_seeds)
        for n in cfg.n_thrusters
        for alg in cfg.algorithms  # interleaved so background load hits GA and DE alike
    ]
    main = {(t.n, t.alg, t.seed_index): t for t in tasks}
    for spec in _setting_specs(cfg):
        strat, F, CR = parse_de(spec)
        for s in range(cfg.n_seeds):
            tasks.append(replace(main[(6, "de", s)], de_strategy=strat, de_F=F, de_CR=CR, setting=spec))
    return tasks


def _paired_tasks(cfg: Config, tasks: list[DesignTask], root: np.random.SeedSequence) -> list[DesignTask]:
    """Paired reading of Table 8 (S3 §4-1): DE designs with one gene per couple, own seeds."""
    if not ("paired couple" in cfg.e_min_readings and "de" in cfg.algorithms):
        return []
    main = {(t.n, t.alg, t.seed_index): t for t in tasks if t.setting is None}
    pchildren = iter(root.spawn(len(cfg.n_thrusters) * cfg.n_seeds))
    return [replace(main[(int(n), "de", s)], paired=True, seed=next(pchildren))
            for s in range(cfg.n_seeds) for n in cfg.n_thrusters]


def _timing_tasks(cfg: Config, tasks: list[DesignTask]) -> list[DesignTask]:
    """Timing repeats of every main design (``Config.timing_repeats`` - 1 each, same seeds), in
    rounds over the whole interleaved task list so that a load spike hits GA and DE alike."""
    main = [t for t in tasks if t.setting is None and not t.paired]
    return [replace(t, repeat=r) for r in range(1, cfg.timing_repeats) for t in main]


def _with_repeats(runs: tuple[DesignRun, ...], repeats: tuple[DesignRun, ...]) -> tuple[DesignRun, ...]:
    """The main runs with the CPU times of their timing repeats attached."""
    by_key: dict[tuple[int, str, int], list[float]] = {}
    for r in sorted(repeats, key=lambda r: r.repeat):
        by_key.setdefault((r.n, r.alg, r.seed_index), []).append(r.cpu_s)
    return tuple(replace(r, cpu_s_repeats=(r.cpu_s, *by_key.get((r.n, r.alg, r.seed_index), ()))) for r in runs)


def _setting_specs(cfg: Config) -> list[str]:
    return list(cfg.de_sensitivity) if 6 in cfg.n_thrusters and "de" in cfg.algorithms else []


def torque_tolerance_nm(cfg: Config) -> float:
    """The torque miss below which a demand counts as met in the fuel comparison (N m).

    S3's own accuracy scale: the reference layout's minimum torque impulse over one sample,
    ``K e_min = F_max Delta t_min / t_s`` (S3 eq. 9-10) with the reference's largest lever
    ``Delta`` (the layout ``e_min`` of this study: its coarsest thruster, sqrt(2) m). A miss
    below it changes the attitude by less than the reference's own minimum reachable error
    (miss / K < e_min): it is below the thrust quantisation of the pulse-width modulated
    thrusters. It follows from S3's printed thruster data, not from any verdict.

    >>> round(torque_tolerance_nm(Config()), 4)  # 10 N * sqrt(2) m * 3 ms / 0.2 s
    0.2121
    """
    lever = float(np.linalg.norm(np.asarray(A_REF, float), axis=0).max())
    return cfg.f_max_n * lever * cfg.t_min_s / cfg.t_s_s


def _alloc_stats(A: np.ndarray, demands: np.ndarray, method: str, cfg: Config) -> AllocStats:
    from adcskit.thrusters import allocate, fuel_mass, pulse_width

    res = allocate(A, demands, method=method, f_max=cfg.f_max_n)
    tp = pulse_width(res.x, f_max=cfg.f_max_n, t_s=cfg.t_s_s)
    return AllocStats(
        sum_tp_s=float(tp.sum(axis=1).mean()),
        error_nm=float(res.error.mean()),
        max_error_nm=float(res.error.max()),
        n_missed=int(np.sum(res.error > torque_tolerance_nm(cfg))),
        all_met=bool(res.feasible.all()),
        fuel_kg=float(fuel_mass(tp, mdot=cfg.mdot_kg_s).sum()),
        on_times_s=tp.sum(axis=0),
    )


def _pinv_miss(cfg: Config, rng: np.random.Generator) -> MissStats:
    """Relative torque miss of each allocator on random 8-thruster layouts, feasible demands."""
    from adcskit.thrusters import allocate, box_faces, decode_layout

    faces = box_faces(cfg.box_half_size_m)
    n = 8
    lo = np.tile([0, -1, -1, 0, 0], n)
    hi = np.tile([len(faces) - 1e-9, 1, 1, 1, 2 * np.pi], n)
    rel: dict[str, list[float]] = {m: [] for m in _MISS_METHODS}
    for _ in range(cfg.n_random_layouts):
        A = decode_layout(rng.uniform(lo, hi), faces).torque_matrix()
        F_true = rng.uniform(0, cfg.f_max_n, size=n)
        M = A @ F_true  # feasible by construction
        for method in rel:
            r = allocate(A, M, method=method, f_max=cfg.f_max_n)
            rel[method].append(float(r.error / np.linalg.norm(M)))
    by_method = {}
    for method, v in rel.items():
        a = np.asarray(v)
        by_method[method] = MissQuantiles(
            median_rel_error=float(np.median(a)), p90_rel_error=float(np.quantile(a, 0.9)),
            max_rel_error=float(a.max()), fraction_exact=float(np.mean(a <= 1e-9)),
        )
    return MissStats(n_layouts=cfg.n_random_layouts, n_thrusters=n, by_method=by_method)


# ----------------------------------------------------------------------------- aggregation


def _seed_runs(runs: tuple[DesignRun, ...], n: int, alg: str) -> list[DesignRun]:
    return sorted((r for r in runs if r.n == n and r.alg == alg), key=lambda r: r.seed_index)


def _summaries(cfg: Config, runs, demands) -> tuple[dict[tuple[int, str], AlgSummary], dict[int, DesignRun]]:
    """Per (n, algorithm): best seed, medians and per-seed lists; and the best design per n."""
    from adcskit.thrusters import check_controllability

    agg: dict[tuple[int, str], AlgSummary] = {}
    best_per_n: dict[int, DesignRun] = {}
    for n in cfg.n_thrusters:
        for alg in cfg.algorithms:
            rs = _seed_runs(runs, n, alg)
            b = min(rs, key=lambda r: r.f_best)
            # the same layout with the exact least-fuel allocation instead of S3's
            lp = _alloc_stats(np.asarray(b.torque_matrix), demands, "lp-min-fuel", cfg)
            agg[(int(n), alg)] = AlgSummary(
                f_best=b.f_best, torque_error=b.torque_error, e_min=b.e_min, sum_tp_s=b.sum_tp_s,
                runtime_s=float(np.median([r.runtime_s for r in rs])),
                cpu_s=float(np.median([r.cpu_s_median for r in rs])), cpu_s_seeds=[r.cpu_s_median for r in rs],
                evaluations=int(b.evaluations),
                f_best_median=float(np.median([r.f_best for r in rs])), f_best_seeds=[r.f_best for r in rs],
                runtime_s_seeds=[r.runtime_s for r in rs], torque_error_seeds=[r.torque_error for r in rs],
                e_min_seeds=[r.e_min for r in rs], sum_tp_s_seeds=[r.sum_tp_s for r in rs],
                best_layout=BestLayout(
                    torque_matrix=b.torque_matrix, positions=b.positions, directions=b.directions,
                    faces=b.faces, controllable=check_controllability(b.torque_matrix).success,
                    lp_sum_tp_s=lp.sum_tp_s, lp_error_nm=lp.error_nm, lp_all_met=lp.all_met,
                ),
            )
            if n not in best_per_n or b.f_best < best_per_n[n].f_best:
                best_per_n[n] = b
    return agg, best_per_n


def _reference_vs_optimal(cfg: Config, runs, best_per_n, demands) -> ReferenceVsOptimal | None:
    """Reference vs the best 6-thruster layout on the design demands (S3 Fig. 5)."""
    if 6 not in cfg.n_thrusters:
        return None
    opt6 = best_per_n[6]
    by_alloc = {}
    for method in ALLOCATIONS:
        ref = _alloc_stats(A_REF, demands, method, cfg)
        opt = _alloc_stats(np.asarray(opt6.torque_matrix), demands, method, cfg)
        per_seed = {
            alg: [_alloc_stats(np.asarray(r.torque_matrix), demands, method, cfg).sum_tp_s
                  for r in _seed_runs(runs, 6, alg)]
            for alg in cfg.algorithms
        }
        by_alloc[method] = AllocComparison(
            sum_tp_ref_s=ref.sum_tp_s, sum_tp_opt_s=opt.sum_tp_s, error_ref_nm=ref.error_nm,
            error_opt_nm=opt.error_nm, all_met_ref=ref.all_met, all_met_opt=opt.all_met,
            fuel_ref_kg=ref.fuel_kg, fuel_opt_kg=opt.fuel_kg, on_times_ref_s=ref.on_times_s,
            on_times_opt_s=opt.on_times_s, sum_tp_opt_s_per_seed=per_seed,
        )
    return ReferenceVsOptimal(
        sum_tp_ref_s=by_alloc["pinv-redistribute"].sum_tp_ref_s,
        sum_tp_opt_s=by_alloc["pinv-redistribute"].sum_tp_opt_s,
        allocation="pinv-redistribute",
        optimal_layout=f"best 6-thruster layout ({opt6.alg.upper()}, seed {opt6.seed_index})",
        sum_tp_definition="mean over the 14 demands of the summed on-times (s)",
        by_allocation=by_alloc,
    )


def _paper_layouts(cfg: Config, demands, half) -> dict[str, PaperLayoutScore]:
    """S3's printed layout matrices evaluated on our manoeuvre."""
    from adcskit.thrusters import check_controllability, score_layout

    out = {}
    for name, A in PAPER["layouts"].items():
        A = np.asarray(A, float)
        sc = score_layout(A, demands, weights=cfg.weights, f_max=cfg.f_max_n, t_min=cfg.t_min_s,
                          t_s=cfg.t_s_s, gain=cfg.gain_nm_per_rad)
        col = np.linalg.norm(A, axis=0)
        out[name] = PaperLayoutScore(
            max_column_norm_m=float(col.max()),
            realisable_in_box=bool(col.max() <= np.linalg.norm(half) + 1e-9),
            controllable=check_controllability(A).success,
            f_best_our_manoeuvre=sc.fun, error_nm=sc.error, e_min_rad=sc.e_min, sum_tp_s=sc.sum_tp,
        )
    return out


def _fuel(cfg: Config, runs, demands, fuel_seeds, redraw_seeds=None) -> tuple[tuple[FuelRun, ...], tuple[str, ...]]:
    """Optimal vs reference per seed, out of sample and on the design demands, both allocations.

    Each out-of-sample ratio is recomputed on ``cfg.fuel_redraws`` independent draws of the
    directions (``redraw_seeds[s]``): its sampling error (:attr:`FuelRun.log_ratio_sd`).
    """
    if 6 not in cfg.n_thrusters:
        return (), ()
    mag = float(np.linalg.norm(demands[0]))
    names = dict(_FUEL_READINGS)
    if "de" not in cfg.algorithms or len(cfg.algorithms) == 1:
        names.pop("de")
        names.pop("lp-de")

    def directions(seed) -> np.ndarray:
        dirs = np.random.default_rng(seed).standard_normal((cfg.n_fuel_demands, 3))
        return mag * dirs / np.linalg.norm(dirs, axis=1, keepdims=True)

    rows = []
    for s in range(cfg.n_seeds):
        rand = directions(fuel_seeds[s])
        redraws = [directions(ss) for ss in redraw_seeds[s].spawn(cfg.fuel_redraws)] if redraw_seeds else []
        six = {a: next(r for r in runs if r.n == 6 and r.alg == a and r.seed_index == s) for a in cfg.algorithms}
        best = min(six.values(), key=lambda r: r.f_best)
        cases = {"default": (best, "pinv-redistribute"), "lp": (best, "lp-min-fuel"),
                 "design": (best, "pinv-redistribute"), "de": (six.get("de"), "pinv-redistribute"),
                 "lp-de": (six.get("de"), "lp-min-fuel")}
        for key in names:
            lay, method = cases[key]
            A = np.asarray(lay.torque_matrix)
            D = demands if key == "design" else rand
            ref = _alloc_stats(A_REF, D, method, cfg)
            opt = _alloc_stats(A, D, method, cfg)
            again = () if key == "design" else tuple(
                _alloc_stats(A, R, method, cfg).sum_tp_s / _alloc_stats(A_REF, R, method, cfg).sum_tp_s
                for R in redraws)
            rows.append(FuelRun(
                reading=names[key], seed_index=s, layout=f"{lay.alg.upper()} seed {s}",
                sum_tp_ref_s=ref.sum_tp_s, sum_tp_opt_s=opt.sum_tp_s, ratio=opt.sum_tp_s / ref.sum_tp_s,
                opt_error_nm=opt.error_nm, ref_error_nm=ref.error_nm,
                opt_max_error_nm=opt.max_error_nm, ref_max_error_nm=ref.max_error_nm,
                opt_n_missed=opt.n_missed, ref_n_missed=ref.n_missed, n_demands=len(D), ratio_redraws=again,
            ))
    return tuple(rows), tuple(names.values())


def _e_min(cfg: Config, runs, paired_runs) -> tuple[dict[str, tuple[EminSeed, ...]], tuple[int, ...]]:
    """Table 8: the DE layouts' e_min per seed under each impulse-bit reading."""
    table8 = PAPER["table8_e_min_rad"]
    ns = tuple(n for n in cfg.n_thrusters if str(n) in table8)
    if "de" not in cfg.algorithms or not ns:
        return {}, ns
    src = {"single thruster": [r for r in runs if r.alg == "de"], "paired couple": list(paired_runs)}
    out = {}
    for reading in cfg.e_min_readings:
        rr = src[reading]
        seeds = []
        for s in range(cfg.n_seeds):
            e = {str(n): next(r.e_min for r in rr if r.n == n and r.seed_index == s) for n in ns}
            seeds.append(EminSeed(rel_dev=max(abs(e[str(n)] - table8[str(n)]) / table8[str(n)] for n in ns), e_min=e))
        out[reading] = tuple(seeds)
    return out, ns


def _sensitivity(cfg: Config, setting_runs, agg) -> tuple[SettingRun, ...]:
    """F_best per seed of each DE setting at n = 6, then the default DE and the GA."""
    out = []
    for spec in dict.fromkeys(_setting_specs(cfg)):
        f = [r.f_best for r in sorted((r for r in setting_runs if r.setting == spec), key=lambda r: r.seed_index)]
        out.append(SettingRun(setting=spec, f_best_seeds=f, f_best_median=float(np.median(f))))
    if out and "ga" in cfg.algorithms:
        de, ga = agg[(6, "de")], agg[(6, "ga")]
        out.append(SettingRun(setting=f"{cfg.de_strategy}:{cfg.de_F}:{cfg.de_CR} (default)",
                              f_best_seeds=de.f_best_seeds, f_best_median=de.f_best_median))
        ratios = tuple(min(k.f_best_seeds[s] for k in out) / ga.f_best_seeds[s] for s in range(cfg.n_seeds))
        out.append(SettingRun(setting="ga (pymoo defaults)", f_best_seeds=ga.f_best_seeds,
                              f_best_median=ga.f_best_median, ratio_seeds=ratios))
    return tuple(out)


# ----------------------------------------------------------------------------- measure


def measure(cfg: Config, *, rng: Any = None, executor: Any = None) -> Measurements:
    """Run every measurement of the study (see the module docstring)."""
    from adcskit._validation import as_rng
    from adcskit.uncertainty.executor import SerialExecutor

    rng = as_rng(rng)
    ex = executor if executor is not None else SerialExecutor()
    demands = manoeuvre_demands(cfg.correction_deg, cfg.gain_nm_per_rad)
    half = np.asarray(cfg.box_half_size_m, float)
    root = np.random.SeedSequence(int(rng.integers(2**63)))
    tasks = _tasks(cfg, demands, root)
    miss_seed = root.spawn(1)[0]  # spawned second, as before the paired reading existed
    fuel_seeds = root.spawn(cfg.n_seeds)  # random demand directions, one set per seed
    tasks += _paired_tasks(cfg, tasks, root)
    redraw_seeds = root.spawn(cfg.n_seeds)  # spawned last: every number before it is unchanged
    tasks += _timing_tasks(cfg, tasks)  # no new seeds: the stream above is unchanged
    all_runs = tuple(ex.map(_design_task, tasks, description="thruster layouts"))
    timing_runs = tuple(r for r in all_runs if r.repeat > 0)
    all_runs = tuple(r for r in all_runs if r.repeat == 0)
    runs = _with_repeats(tuple(r for r in all_runs if r.setting is None and not r.paired), timing_runs)
    setting_runs = tuple(r for r in all_runs if r.setting is not None)
    paired_runs = tuple(r for r in all_runs if r.paired)
    agg, best_per_n = _summaries(cfg, runs, demands)
    fuel, fuel_readings = _fuel(cfg, runs, demands, fuel_seeds, redraw_seeds)
    e_min, e_min_ns = _e_min(cfg, runs, paired_runs)
    return Measurements(
        demands=demands, half=half, runs=runs, timing_runs=timing_runs, setting_runs=setting_runs,
        paired_runs=paired_runs,
        summaries=agg, best_per_n=best_per_n,
        reference_vs_optimal=_reference_vs_optimal(cfg, runs, best_per_n, demands),
        paper_layouts=_paper_layouts(cfg, demands, half),
        miss=_pinv_miss(cfg, np.random.default_rng(miss_seed)),
        fuel=fuel, fuel_readings=fuel_readings, e_min=e_min, e_min_ns=e_min_ns,
        sensitivity=_sensitivity(cfg, setting_runs, agg),
        total_time_s=float(sum(r.runtime_s for r in all_runs + timing_runs)),
        total_cpu_s=float(sum(r.cpu_s for r in all_runs + timing_runs)),
    )
