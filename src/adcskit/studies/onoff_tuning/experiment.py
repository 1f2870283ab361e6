"""The measurements of ``onoff-tuning``: NSGA-II front, robust GAs, Monte-Carlo evaluations, sweeps.

:func:`measure` runs everything the study reports, in one fixed order of the random stream
(seed-0 NSGA-II, gain-order simulations, the per-seed pipelines, the all-four ratio sweep, the
input-std sweep, the command-rate sweep, the per-uncertainty ratio sweep, the LHS draw of
Fig. 11), and returns frozen records: :class:`Measurements` and the rows it holds. Claims,
figures and report read these records only; nothing after :func:`measure` draws a random
number or simulates.

References
----------
S4, eqs. (9)-(10), Tables 3-6, Figs. 9-21.
"""

from __future__ import annotations

import copy
import os
from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from adcskit._progress import status, track
from adcskit._results import Result
from adcskit.control.onoff import simulate_batch, simulate_trace
from adcskit.control.tuning import (
    RobustTuningScale,
    estimate_tuning_time,
    evaluate_gains,
    monte_carlo,
    tune_deterministic,
    tune_robust,
)
from adcskit.studies.onoff_tuning.config import Config
from adcskit.studies.onoff_tuning.ga_store import resolve_store
from adcskit.studies.onoff_tuning.paper import CASES, PAPER_TABLE4, PAPER_TABLE6, _reorder
from adcskit.uncertainty.sampling import Gaussian, latin_hypercube

__all__ = ["Measurements", "SeedRun", "CaseRun", "CaseReading", "GainEval", "GARun", "RateContrast",
           "RobustCase", "OrderRow", "SweepRow", "StdRow", "RateRow", "StepTrace", "ga_jobs", "measure", "stored_ga",
           "stored_sweep"]


def row(rec: Any) -> dict[str, Any]:
    """A record's fields as a flat ``{name: value}`` row (values as measured, for a CSV).

    Examples
    --------
    >>> row(RateRow(rate_hz=50.0, factor=1.0, det_mean_deg=0.1, det_std_deg=0.02, robust_mean_deg=0.12,
    ...             robust_std_deg=0.01))["robust_std_deg"]
    0.01
    """
    return {f.name: getattr(rec, f.name) for f in fields(rec)}


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class OrderRow(Result):
    """One printed gain set (Table 4 or 6) simulated nominally under one gain-order reading."""

    order: str
    entry: str
    kp: float
    ki: float
    kd: float
    overshoot_pct: float
    error_deg: float
    fuel: float
    feasible: bool


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class SweepRow(Result):
    """One robust GA of a weight-ratio sweep and its Monte-Carlo evaluation (Figs 12-14)."""

    case: str
    ratio: float
    kp: float
    ki: float
    kd: float
    mean_abs_err_deg: float
    std_abs_err_deg: float
    generations: int
    #: where a stored sweep GA came from (as :attr:`GARun.stored`); "" = run here (or seed 0's claim GA)
    stored: str = ""


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class StdRow(Result):
    """Deterministic and robust gains at one multiple of the Table 5 spread (Figs 15-19)."""

    case: str
    factor: float
    input_std: float
    det_mean_deg: float
    det_std_deg: float
    robust_mean_deg: float
    robust_std_deg: float


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class RateRow(Result):
    """Deterministic and robust gains at one command rate and spread (Figs 20-21)."""

    rate_hz: float
    factor: float
    det_mean_deg: float
    det_std_deg: float
    robust_mean_deg: float
    robust_std_deg: float


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class GainEval(Result):
    """One gain set on one seed's fresh evaluation samples of one case: |error| [deg] mean and
    std, overshoot-violation rate, mean fuel [N m s], eq. 10 incl. penalty and its penalty."""

    mean: float
    std: float
    viol: float
    fuel: float
    eq10: float
    eq10_penalty: float


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class GARun(Result):
    """The robust GA of one case and penalty reading: gains (K_p, K_i, K_d), eq. 10 on the
    training samples (incl. penalty), its core and penalty, generations and stopping rule."""

    gains: np.ndarray
    objective: float
    core: float
    penalty: float
    generations: int
    converged: bool
    #: where a stored GA came from (``ga_store``: "backend run of DATE on MACHINE, commit C"); "" = run here
    stored: str = ""


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class CaseReading(Result):
    """One penalty reading of one case: ``key`` is ``"robust"`` (the default reading) or
    ``"robust_<reading>"``; ``evals`` maps a gain label (robust key, ``det``, ``table4``,
    ``table6``) to its evaluation."""

    key: str
    evals: Mapping[str, GainEval]
    ga: GARun


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class CaseRun(Result):
    """One case of one seed: its weight ratio and its readings (default first)."""

    ratio: float
    readings: tuple[CaseReading, ...]

    def flat(self) -> dict[str, Any]:
        """The per-seed row of this case (``mean_det``, ``gains_robust``, ...; issue-16 names).

        Examples
        --------
        >>> ev = GainEval(mean=0.1, std=0.02, viol=0.0, fuel=20.0, eq10=0.03, eq10_penalty=0.0)
        >>> ga = GARun(gains=np.array([30.0, 0.02, 45.0]), objective=0.03, core=0.03, penalty=0.0, generations=3,
        ...            converged=False)
        >>> flat = CaseRun(ratio=180.0, readings=(CaseReading(key="robust", evals={"robust": ev, "det": ev}, ga=ga),)).flat()
        >>> list(flat)[:3], flat["std_det"], flat["ga_generations_robust"]
        (['ratio', 'mean_robust', 'std_robust'], 0.02, 3)
        """
        out: dict[str, Any] = {"ratio": self.ratio}
        for rd in self.readings:
            for key, ev in rd.evals.items():
                out.update({f"{name}_{key}": v for name, v in row(ev).items()})
            rk = rd.key
            out.update({f"gains_{rk}": rd.ga.gains, f"ga_objective_{rk}": rd.ga.objective,
                        f"ga_core_{rk}": rd.ga.core, f"ga_penalty_{rk}": rd.ga.penalty,
                        f"ga_generations_{rk}": rd.ga.generations, f"ga_converged_{rk}": rd.ga.converged})
        return out


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class RateContrast(Result):
    """Lowest vs highest command rate on one seed: the smallest low/high ratio over (mean,
    std) x (det, robust) and the values behind it."""

    low_hz: float
    high_hz: float
    ratio_min: float
    values: Mapping[str, float]


@dataclass(frozen=True, kw_only=True, repr=False)
class SeedRun(Result):
    """One independent repetition of the pipeline (``flat`` views: :meth:`CaseRun.flat`)."""

    seed_index: int
    det_gains: np.ndarray
    cases: Mapping[str, CaseRun]
    runs: Mapping[str, Any]
    mc_results: Mapping[str, tuple[Any, Any]]
    rate: RateContrast
    pareto: Any

    def flat(self, case: str) -> dict[str, Any]:
        return self.cases[case].flat()


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class RobustCase(Result):
    """Seed 0's deterministic-vs-robust evaluation of one case (``measured.robust``)."""

    gains: np.ndarray
    ratio: float
    mean_abs_err_deg: float
    std_abs_err_deg: float
    det_mean_abs_err_deg: float
    det_std_abs_err_deg: float
    robust_fuel_mean: float
    det_fuel_mean: float
    robust_max_overshoot_pct: float
    det_max_overshoot_pct: float
    robust_violation_rate: float
    det_violation_rate: float
    ga_generations: int
    ga_converged: bool
    ga_objective: float
    ga_penalty: float
    n_mc: int
    mean_diff_ci95_deg: list
    std_diff_ci95_deg: list


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class StepTrace(Result):
    """A nominal step response of a Pareto point (Fig. 10): time [s] and attitude [rad]."""

    label: str
    gains: np.ndarray
    t: np.ndarray
    theta: np.ndarray


@dataclass(frozen=True, kw_only=True, repr=False)
class Measurements(Result):
    """Everything :func:`measure` ran, in records.

    ``pareto`` is seed 0's NSGA-II front (:class:`~adcskit.control.tuning.ParetoResult`);
    ``ga`` the GA settings in force (:func:`_ga_settings`); ``mc_all`` seed 0's per-sample
    mean |error| [deg] of the deterministic and robust gains, all four uncertainties;
    ``lhs_inertia`` the 1000-sample LHS draw of Fig. 11.
    """

    ga: Mapping[str, Any]
    pareto: Any
    det_gains: np.ndarray
    minfuel_gains: np.ndarray
    minfuel_settled: np.ndarray
    order_rows: tuple[OrderRow, ...]
    feasible: Mapping[str, int]
    consistent_order: str
    seeds: tuple[SeedRun, ...]
    robust: Mapping[str, RobustCase]
    sweep_rows: tuple[SweepRow, ...]
    std_rows: tuple[StdRow, ...]
    rate_rows: tuple[RateRow, ...]
    traces: tuple[StepTrace, ...]
    mc_all: tuple[np.ndarray, np.ndarray]
    lhs_inertia: np.ndarray

    @property
    def robust_runs(self) -> Mapping[str, Any]:
        """Seed 0's robust GA result per case (default penalty reading)."""
        return self.seeds[0].runs

    def case_flats(self, case: str) -> list[dict[str, Any]]:
        """Every seed's per-seed row of ``case``."""
        return [s.flat(case) for s in self.seeds]


def stored_ga(m: Measurements) -> dict[str, Any]:
    """How many claim GAs were replayed from a GA store (``ga_store``) and from which runs.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> rd = lambda src: NS(ga=NS(stored=src))
    >>> seed = NS(cases={"all": NS(readings=(rd("CPU run of D on M"), rd("")))})
    >>> stored_ga(NS(seeds=(seed,)))
    {'n_stored': 1, 'n_runs': 2, 'sources': ['CPU run of D on M']}
    """
    srcs = [rd.ga.stored for so in m.seeds for case in so.cases.values() for rd in case.readings]
    return {"n_stored": sum(bool(s) for s in srcs), "n_runs": len(srcs), "sources": sorted({s for s in srcs if s})}


def stored_sweep(m: Measurements) -> dict[str, Any]:
    """How many of the all-four ratio sweep's own GAs (Figs 12-14) were replayed from a GA store, and
    from which runs (its Table 6 ratio is seed 0's claim GA, counted by :func:`stored_ga`).

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> rows = (NS(case="all", ratio=10.0, stored="CPU run of D on M"), NS(case="all", ratio=180.0, stored=""),
    ...         NS(case="delay", ratio=10.0, stored=""))
    >>> stored_sweep(NS(sweep_rows=rows, robust={"all": NS(ratio=180.0)}))
    {'n_stored': 1, 'n_runs': 1, 'sources': ['CPU run of D on M']}
    """
    srcs = [r.stored for r in m.sweep_rows if r.case == "all" and r.ratio != m.robust["all"].ratio]
    return {"n_stored": sum(bool(s) for s in srcs), "n_runs": len(srcs), "sources": sorted({s for s in srcs if s})}


def _seeds(rng: np.random.Generator, n: int) -> list[int]:
    return [int(s) for s in rng.integers(0, 2**31 - 1, size=n)]


def _paired_bootstrap(det: np.ndarray, rob: np.ndarray, rng: np.random.Generator, n_boot: int = 400) -> dict:
    """95 % bootstrap intervals of robust − deterministic mean and std (same samples for both)."""
    n = det.size
    idx = rng.integers(0, n, size=(n_boot, n))
    d, r = det[idx], rob[idx]
    dm = r.mean(axis=1) - d.mean(axis=1)
    ds = r.std(axis=1) - d.std(axis=1)
    return {"mean": np.percentile(dm, [2.5, 97.5]).tolist(), "std": np.percentile(ds, [2.5, 97.5]).tolist()}


def _campaign_dir(config: Config, name: str) -> str | None:
    return os.path.join(config.campaign_dir, name) if config.campaign_dir else None


def _deterministic(config: Config, base, settings, bounds, seed):
    """NSGA-II Pareto front (eq. 9) and its minimum-error / minimum-fuel points."""
    pareto = tune_deterministic(base=base, settings=settings, pop_size=config.nsga_pop, n_gen=config.nsga_gen,
                                bounds=bounds, overshoot_max_pct=config.overshoot_max_pct, rng=seed)
    if pareto.success:
        det_gains = pareto.x[0]  # minimum-error point (front sorted by error)
        minfuel_gains = pareto.x[int(np.argmin(pareto.F[:, 1]))]
        # eq. (9) admits points that never finish the slew; also report the cheapest point that
        # settles (2 % band) within the horizon
        settle = evaluate_gains(pareto.x, base=base, settings=settings).settling_time
        settled = np.flatnonzero(np.isfinite(settle))
        minfuel_settled = pareto.x[settled[np.argmin(pareto.F[settled, 1])]] if settled.size else minfuel_gains
    else:  # pragma: no cover - NSGA-II always finds feasible gains for the S4 loop
        det_gains = np.array(_reorder(PAPER_TABLE4["min_error"], "kp_kd_ki"))
        minfuel_gains = np.array(_reorder(PAPER_TABLE4["min_fuel"], "kp_kd_ki"))
        minfuel_settled = minfuel_gains
    return pareto, det_gains, minfuel_gains, minfuel_settled


def _ga_settings(config: Config) -> dict[str, Any]:
    """GA population, generation cap, LHS training samples and evaluation runs of the claims.

    ``paper_scale=True`` has already set these keys to S4's protocol (:class:`Config`).
    """
    return {"pop": config.ga_pop, "max_gen": config.ga_max_gen, "n_lhs": config.n_lhs, "n_mc": config.n_mc}


def _eq10(config: Config, case: str, err_deg: np.ndarray, os_pct: np.ndarray, penalty_on: str) -> dict[str, float]:
    """S4 eq. (10) as the GA optimised it (weights, penalty) on a set of per-sample metrics."""
    from adcskit.control.robust import robust_objective, weights_from_ratio

    w1, w2 = weights_from_ratio(config.ratio(case))
    a = np.abs(err_deg)
    core = float(w1 * a.mean() + w2 * a.std())
    total = float(robust_objective(err_deg[None], os_pct[None], w1=w1, w2=w2,
                                   overshoot_max_pct=config.overshoot_max_pct,
                                   penalty_weight=config.penalty_weight_deg_per_pct, penalty_on=penalty_on,
                                   nonfinite="infeasible")[0])
    return {"eq10": total, "eq10_core": core, "eq10_penalty": total - core}


def _mc_stats(r) -> dict[str, float]:
    err = np.degrees(r.metrics.mean_abs_err_last)
    return {"mean": float(np.mean(err)), "std": float(np.std(err))}


def _estimate(config: Config, ga: dict[str, Any], settings) -> tuple[int, float, str]:
    """(GA runs, worst-case seconds, message) of the claim runs, from issue 14's timed probe."""
    n_pen = len(config.penalty_readings) - 1
    n_ga = config.n_seeds * (len(CASES) + n_pen)
    n_eval = config.n_seeds * (len(CASES) * 3 + 1 + n_pen) * ga["n_mc"]
    est = estimate_tuning_time(
        RobustTuningScale(pop_size=ga["pop"], max_gen=ga["max_gen"], n_samples=ga["n_lhs"], n_eval=n_eval,
                          tol=config.ga_tol_deg, window=config.ga_window),
        settings=settings, backend=config.backend,
    )
    total = n_ga * est.max_tuning_s + est.evaluation_s
    return n_ga, total, (f"{n_ga} robust GA runs and {n_eval} evaluation runs; per GA run: {est.message}; "
                         f"claim runs in all at most {total / 3600:.1f} h on {est.backend}")


def _gain_eval(config: Config, case: str, r, pen: str) -> GainEval:
    """A Monte-Carlo result of one gain set as the claims read it (S4 eq. 10 with ``pen``)."""
    err = np.degrees(r.metrics.mean_abs_err_last)
    os_pct = np.nan_to_num(r.metrics.overshoot_pct, nan=0.0)
    e10 = _eq10(config, case, err, os_pct, pen)
    return GainEval(mean=float(np.mean(err)), std=float(np.std(err)),
                    viol=float(np.mean(os_pct > config.overshoot_max_pct)), fuel=float(np.mean(r.metrics.fuel)),
                    eq10=e10["eq10"], eq10_penalty=e10["eq10_penalty"])


def _readings(config: Config) -> list[tuple[str, str]]:
    """(penalty reading, case) of every robust GA of one seed, in run order."""
    readings = [("sample", case) for case in CASES]
    if "mean" in config.penalty_readings:
        readings.append(("mean", "all"))
    if config.penalty_readings[0] == "mean":
        readings = [("mean", c) for c in CASES] + ([("sample", "all")] if "sample" in config.penalty_readings else [])
    return readings


def claim_gas(config: Config, s_index: int, kids: list[int], ga: Mapping[str, Any], settings, base,
              bounds) -> list[tuple[str, str, str, dict[str, Any]]]:
    """``(label, penalty reading, case, tune_robust keywords)`` of every claim GA of one seed, in run order
    (``kids``: the seed's 16 child seeds; the GA of the default reading uses child ``1 + case index``, the
    other reading child 11)."""
    pen0 = config.penalty_readings[0]
    out = []
    for pen, case in _readings(config):
        ci = CASES.index(case)
        kw = dict(ratio=config.ratio(case), n_samples=ga["n_lhs"], base=base, settings=settings,
                  pop_size=ga["pop"], max_gen=ga["max_gen"], tol=config.ga_tol_deg, window=config.ga_window,
                  bounds=bounds, overshoot_max_pct=config.overshoot_max_pct,
                  penalty_weight=config.penalty_weight_deg_per_pct,
                  rng=kids[1 + ci] if pen == pen0 else kids[11], penalty_on=pen, backend=config.backend)
        out.append((f"s{s_index}_{case}_{pen}", pen, case, kw))
    return out


def _seed_seqs(config: Config, rng: np.random.Generator) -> list[np.random.SeedSequence]:
    """The pipelines' independent seed sequences (the first draw of the study's random stream)."""
    return np.random.SeedSequence(int(rng.integers(2**63))).spawn(config.n_seeds)


def _seed0_nsga(seed_seqs: list[np.random.SeedSequence]) -> int:
    """Seed 0's NSGA-II seed, run before the pipelines: it spawns 16 children of ``seed_seqs[0]``, so
    that pipeline's own children (:func:`_kids`) are the next 16."""
    return int(seed_seqs[0].spawn(16)[0].generate_state(1)[0])


def _kids(ss: np.random.SeedSequence) -> list[int]:
    return [int(k.generate_state(1)[0]) for k in ss.spawn(16)]


def stored_claim_gas(config: Config, seed: int, store) -> tuple[int, int]:
    """(stored, all) claim GAs of a run of ``config`` with root seed ``seed`` that ``store`` holds."""
    return _count_stored(config, _seed_seqs(config, np.random.default_rng(seed)), store)


def _claim_jobs(config: Config, seed_seqs: list[np.random.SeedSequence]) -> list[tuple[str, str, str, dict]]:
    """:func:`claim_gas` of every seed of a run (``seed_seqs`` as :func:`measure` draws them; not advanced)."""
    seed_seqs = copy.deepcopy(seed_seqs)  # spawning advances them
    settings, base, ga = config.settings(), config.base(), _ga_settings(config)
    bounds = (1e-3, config.gain_max)
    _seed0_nsga(seed_seqs)  # as in measure(): before the pipelines
    return [job for i, ss in enumerate(seed_seqs) for job in claim_gas(config, i, _kids(ss), ga, settings, base, bounds)]


def _count_stored(config: Config, seed_seqs: list[np.random.SeedSequence], store) -> tuple[int, int]:
    jobs = _claim_jobs(config, seed_seqs)
    return sum(store.has(config.dists(case), **kw) for _, _, case, kw in jobs), len(jobs)


def _seed_pipeline(config: Config, s_index: int, ss, ga: dict[str, Any], settings, base, bounds, mc_kw,
                   order: str, pareto=None) -> SeedRun:
    """One independent repetition of the whole pipeline: NSGA-II, robust GA per case (own LHS
    training draw and pymoo seed), evaluation of deterministic, robust and S4's gains on the
    same fresh samples, the E[overshoot]-penalty reading and the command-rate contrast."""
    kids = _kids(ss)
    if pareto is None:
        pareto, det_gains, _, _ = _deterministic(config, base, settings, bounds, kids[0])
    else:
        det_gains = pareto.x[0] if pareto.success else np.array(_reorder(PAPER_TABLE4["min_error"], "kp_kd_ki"))
    t4 = np.array(_reorder(PAPER_TABLE4["min_error"], order))
    t6 = np.array(_reorder(PAPER_TABLE6["all"]["printed"], order))
    pen0 = config.penalty_readings[0]
    cases: dict[str, list[CaseReading]] = {}
    runs: dict[str, Any] = {}
    mc_results: dict[str, dict[str, Any]] = {}
    store = resolve_store(config.ga_store, config.paper_scale)
    jobs = claim_gas(config, s_index, kids, ga, settings, base, bounds)
    for label, pen, case, kw in track(jobs, f"robust GA, seed {s_index}", total=len(jobs)):
        status(f"onoff-tuning: seed {s_index}, robust GA {case} (w2/w1 = {config.ratio(case):g}, penalty on {pen})")
        ci = CASES.index(case)
        res, src = _tune(store, label, config.dists(case), **kw)
        mc_seed = kids[6 + ci]  # the same evaluation samples for every gain set of this seed and case
        gains = {"robust": res.x}
        if case not in cases:  # the deterministic and S4's gains: once per case
            gains.update({"det": det_gains, "table4": t4})
            if case == "all":
                gains["table6"] = t6
        rk = "robust" if pen == pen0 else f"robust_{pen}"
        evals: dict[str, GainEval] = {}
        for label, g in gains.items():
            key = rk if label == "robust" else label
            r = monte_carlo(g, config.dists(case), ga["n_mc"], settings=settings, rng=mc_seed,
                            directory=_campaign_dir(config, f"s{s_index}_{case}_{key}"), **mc_kw)
            evals[key] = _gain_eval(config, case, r, pen)
            if s_index == 0 and pen == pen0 and label in ("det", "robust"):
                mc_results.setdefault(case, {})[label] = r
        core = float(res.w1 * res.mean_abs_err_deg + res.w2 * res.std_abs_err_deg)
        cases.setdefault(case, []).append(CaseReading(key=rk, evals=evals, ga=GARun(
            gains=res.x, objective=res.fun, core=core, penalty=res.fun - core, generations=res.nit,
            converged=bool(res.success), stored=_provenance(src))))
        if rk == "robust":
            runs[case] = res
    return SeedRun(seed_index=s_index, det_gains=det_gains,
                   cases={c: CaseRun(ratio=config.ratio(c), readings=tuple(rd)) for c, rd in cases.items()},
                   runs=runs, mc_results={c: (v["det"], v["robust"]) for c, v in mc_results.items()},
                   rate=_rate_contrast(config, s_index, kids[12], det_gains, runs["all"].x, mc_kw), pareto=pareto)


def _tune(store, label: str, dists, **kw):
    """``tune_robust(dists, **kw)`` and None, or through ``store`` (a stored run and its provenance)."""
    if store is None:
        return tune_robust(dists, **kw), None
    return store.tune(label, dists, **kw)


def _provenance(src: Mapping[str, Any] | None) -> str:
    """A stored GA's provenance in words ("" when the GA ran here)."""
    if not src:
        return ""
    commit = f", adcskit {src['commit']}" if src.get("commit") else ""
    day = str(src.get("date", "?"))[:10]  # one line per run of many GAs, not per GA
    return f"{str(src.get('backend', '?')).upper()} run of {day} on {src.get('machine', '?')}{commit}"


def _rate_contrast(config: Config, s_index: int, seed: int, det_gains, robust_gains, mc_kw) -> RateContrast:
    """Command rate (Figs 20-21): lowest vs highest rate, Table 5 spread, same samples."""
    rates = sorted(config.command_rates_hz)
    rate = {}
    for hz in (rates[0], rates[-1]):
        for label, g in (("det", det_gains), ("robust", robust_gains)):
            r = monte_carlo(g, config.dists("all"), config.n_mc_rate, settings=config.settings(hz), rng=seed,
                            directory=_campaign_dir(config, f"s{s_index}_rate_{hz:g}_{label}"), **mc_kw)
            rate[(hz, label)] = _mc_stats(r)
    return RateContrast(
        low_hz=rates[0], high_hz=rates[-1],
        ratio_min=min(rate[(rates[0], lab)][w] / rate[(rates[-1], lab)][w] for lab in ("det", "robust")
                      for w in ("mean", "std")),
        values={f"{lab}_{w}_{hz:g}Hz": rate[(hz, lab)][w] for (hz, lab) in rate for w in ("mean", "std")})


def _gain_order(config: Config, base, settings) -> tuple[list[OrderRow], dict[str, int], str]:
    """Simulate both readings of Tables 4 and 6 nominally; the consistent reading is the one
    with the most entries inside the overshoot constraint."""
    order_rows = []
    for order in ("kp_kd_ki", "kp_ki_kd"):
        printed = {f"table4_{k}": v for k, v in PAPER_TABLE4.items()}
        printed.update({f"table6_{k}": v["printed"] for k, v in PAPER_TABLE6.items()})
        names = list(printed)
        gains = np.array([_reorder(printed[k], order) for k in names])
        nom = simulate_batch(base.replace(kp=gains[:, 0], ki=gains[:, 1], kd=gains[:, 2]), settings)
        for j, k in enumerate(names):
            order_rows.append(OrderRow(
                order=order, entry=k, kp=gains[j, 0], ki=gains[j, 1], kd=gains[j, 2],
                overshoot_pct=float(nom.overshoot_pct[j]),
                error_deg=float(np.degrees(nom.mean_abs_err_last[j])), fuel=float(nom.fuel[j]),
                feasible=bool(nom.overshoot_pct[j] <= config.overshoot_max_pct),
            ))
    feasible = {o: sum(r.feasible for r in order_rows if r.order == o) for o in ("kp_kd_ki", "kp_ki_kd")}
    return order_rows, feasible, max(feasible, key=feasible.get)


def _robust_summary(config: Config, seed0: SeedRun, ga: Mapping[str, Any]) -> dict[str, RobustCase]:
    """Seed 0's deterministic-vs-robust evaluation per case, with paired bootstrap intervals."""
    robust = {}
    for case in CASES:
        det, rob = seed0.mc_results[case]
        ci = _paired_bootstrap(np.degrees(det.metrics.mean_abs_err_last), np.degrees(rob.metrics.mean_abs_err_last),
                               np.random.default_rng(0))
        c0 = seed0.flat(case)
        run = seed0.runs[case]
        robust[case] = RobustCase(
            gains=run.x, ratio=config.ratio(case),
            mean_abs_err_deg=rob.mean_abs_err_deg, std_abs_err_deg=rob.std_abs_err_deg,
            det_mean_abs_err_deg=det.mean_abs_err_deg, det_std_abs_err_deg=det.std_abs_err_deg,
            robust_fuel_mean=float(np.mean(rob.metrics.fuel)), det_fuel_mean=float(np.mean(det.metrics.fuel)),
            robust_max_overshoot_pct=float(np.nanmax(rob.metrics.overshoot_pct)),
            det_max_overshoot_pct=float(np.nanmax(det.metrics.overshoot_pct)),
            robust_violation_rate=c0["viol_robust"], det_violation_rate=c0["viol_det"],
            ga_generations=run.nit, ga_converged=run.success,
            ga_objective=run.fun, ga_penalty=c0["ga_penalty_robust"],
            n_mc=ga["n_mc"], mean_diff_ci95_deg=ci["mean"], std_diff_ci95_deg=ci["std"],
        )
    return robust


def _sweep_row(case: str, r: float, res, ev, stored: str = "") -> SweepRow:
    return SweepRow(case=case, ratio=r, kp=res.x[0], ki=res.x[1], kd=res.x[2], mean_abs_err_deg=ev.mean_abs_err_deg,
                    std_abs_err_deg=ev.std_abs_err_deg, generations=res.nit, stored=stored)


def _sweep_seeds(config: Config, rng) -> list[tuple[float, int | None, int]]:
    """``(ratio, GA seed or None, evaluation seed)`` of the all-four ratio sweep, drawn from ``rng`` in the
    sweep's order (the Table 6 ratio reuses seed 0's GA: no GA seed)."""
    out = []
    for r in sorted(set(config.sweep_ratios) | {config.ratio_all}):
        ga_seed = None if r == config.ratio_all else _seeds(rng, 1)[0]
        out.append((r, ga_seed, _seeds(rng, 1)[0]))
    return out


def _sweep_ga(config: Config, r: float, seed: int, base, settings, bounds) -> tuple[str, dict[str, Any]]:
    """``(label, tune_robust keywords)`` of the sweep GA at ratio ``r``."""
    return f"sweep_all_{r:g}", dict(
        ratio=r, n_samples=config.n_lhs, base=base, settings=settings, pop_size=config.ga_pop,
        max_gen=config.sweep_max_gen, tol=config.ga_tol_deg, window=config.ga_window, bounds=bounds,
        overshoot_max_pct=config.overshoot_max_pct, penalty_weight=config.penalty_weight_deg_per_pct,
        rng=seed, backend=config.backend)


def _ratio_sweep(config: Config, rng, base, settings, bounds, mc_kw, robust_all) -> list[SweepRow]:
    """Weight-ratio sweep, all four uncertainties (Figs 12-14); the Table 6 ratio reuses seed 0's GA."""
    rows = []
    plan = _sweep_seeds(config, rng)
    store = resolve_store(config.ga_store, config.paper_scale)  # at paper scale 1000 LHS samples per candidate
    for r, ga_seed, mc_seed in track(plan, "ratio sweep", total=len(plan)):
        src = None
        if ga_seed is None:
            res = robust_all
        else:
            status(f"onoff-tuning: ratio sweep w2/w1 = {r:g}")
            label, kw = _sweep_ga(config, r, ga_seed, base, settings, bounds)
            res, src = _tune(store, label, config.dists("all"), **kw)  # stored like the claim GAs
        ev = monte_carlo(res.x, config.dists("all"), config.n_mc_sweep, settings=settings, rng=mc_seed,
                         directory=_campaign_dir(config, f"sweep_{r:g}"), **mc_kw)
        rows.append(_sweep_row("all", r, res, ev, _provenance(src)))
    return rows


def ga_jobs(config: Config, seed: int) -> list[tuple[str, Any, dict[str, Any]]]:
    """``(label, dists, tune_robust keywords)`` of every GA a run of ``config`` with root seed ``seed``
    may keep in a GA store: the claim GAs of every seed, then the all-four ratio sweep's GAs (the
    same inputs :func:`measure` passes, from the same random stream)."""
    rng = np.random.default_rng(seed)
    seed_seqs = _seed_seqs(config, rng)
    jobs = [(label, config.dists(case), kw) for label, _, case, kw in _claim_jobs(config, seed_seqs)]
    settings, base, bounds = config.settings(), config.base(), (1e-3, config.gain_max)
    for r, ga_seed, _ in _sweep_seeds(config, rng):
        if ga_seed is not None:
            label, kw = _sweep_ga(config, r, ga_seed, base, settings, bounds)
            jobs.append((label, config.dists("all"), kw))
    return jobs


def _case_sweep(config: Config, rng, base, settings, bounds, mc_kw) -> list[SweepRow]:
    """Weight-ratio sweep of each single uncertainty (Figs 12-13), a lighter GA."""
    rows = []
    for case in track(CASES[:-1], "ratio sweep per uncertainty", total=len(CASES) - 1):
        for r in sorted(set(config.sweep_cases_ratios) | {config.ratio(case)}):
            status(f"onoff-tuning: ratio sweep, {case}, w2/w1 = {r:g}")
            res = tune_robust(
                config.dists(case), ratio=r, n_samples=config.sweep_cases_n_lhs, base=base, settings=settings,
                pop_size=config.ga_pop, max_gen=config.sweep_cases_max_gen, tol=config.ga_tol_deg,
                window=config.ga_window, bounds=bounds, overshoot_max_pct=config.overshoot_max_pct,
                penalty_weight=config.penalty_weight_deg_per_pct, rng=_seeds(rng, 1)[0], backend=config.backend,
            )
            ev = monte_carlo(res.x, config.dists(case), config.n_mc_ratio_cases, settings=settings,
                             rng=_seeds(rng, 1)[0], directory=_campaign_dir(config, f"sweep_{case}_{r:g}"), **mc_kw)
            rows.append(_sweep_row(case, r, res, ev))
    return rows


def _std_sweep(config: Config, rng, settings, mc_kw, det_gains, robust_runs) -> list[StdRow]:
    """Mean/std of |error| vs the input standard deviation (Figs 15-19)."""
    rows = []
    for case in track(CASES, "input-std sweep", total=len(CASES)):
        status(f"onoff-tuning: input-std sweep, {case}")
        for f in config.std_factors:
            seed = _seeds(rng, 1)[0]
            vals = {}
            for label, g in (("det", det_gains), ("robust", robust_runs[case].x)):
                ev = monte_carlo(g, config.dists(case, f), config.n_mc_sweep, settings=settings, rng=seed,
                                 directory=_campaign_dir(config, f"std_{case}_{f:g}_{label}"), **mc_kw)
                vals[f"{label}_mean_deg"] = ev.mean_abs_err_deg
                vals[f"{label}_std_deg"] = ev.std_abs_err_deg
            rows.append(StdRow(case=case, factor=f, input_std=f * config.input_std(case), **vals))
    return rows


def _rate_sweep(config: Config, rng, mc_kw, det_gains, robust_all) -> list[RateRow]:
    """Command rate (Figs 20-21), all four uncertainties, per spread factor."""
    rows = []
    for hz in track(config.command_rates_hz, "command rates", total=len(config.command_rates_hz)):
        status(f"onoff-tuning: command rate {hz:g} Hz")
        s_hz = config.settings(hz)
        for f in config.std_factors:
            seed = _seeds(rng, 1)[0]
            vals = {}
            for label, g in (("det", det_gains), ("robust", robust_all)):
                ev = monte_carlo(g, config.dists("all", f), config.n_mc_rate, settings=s_hz, rng=seed,
                                 directory=_campaign_dir(config, f"rate_{hz:g}_{f:g}_{label}"), **mc_kw)
                vals[f"{label}_mean_deg"] = ev.mean_abs_err_deg
                vals[f"{label}_std_deg"] = ev.std_abs_err_deg
            rows.append(RateRow(rate_hz=hz, factor=f, **vals))
    return rows


def _seed_task(task, shared) -> SeedRun:
    """Executor task: one seed pipeline (``task = (index, SeedSequence, pareto or None)``)."""
    i, ss, pareto = task
    config, ga, settings, base, bounds, mc_kw, order = shared
    return _seed_pipeline(config, i, ss, ga, settings, base, bounds, mc_kw, order, pareto=pareto)


def measure(config: Config, rng: np.random.Generator, executor=None) -> Measurements:
    """Run every measurement of the study, in the fixed order of the random stream."""
    settings = config.settings()
    base = config.base()
    bounds = (1e-3, config.gain_max)
    mc_kw = dict(base=base, executor=executor, task_size=config.task_size, backend=config.backend)
    ga = _ga_settings(config)
    seed_seqs = _seed_seqs(config, rng)
    if config.paper_scale:
        store = resolve_store(config.ga_store, True)
        n_stored, n_all = _count_stored(config, seed_seqs, store) if store is not None else (0, 0)
        if n_all and n_stored == n_all:
            est = f"all {n_all} claim GAs replayed from {store.directory}, evaluations run here"
        else:
            est = _estimate(config, ga, settings)[2] + (f" ({n_stored} of them stored in {store.directory})"
                                                        if store is not None else "")
        msg = (f"onoff-tuning paper-scale: population {ga['pop']}, cap {ga['max_gen']} generations, {ga['n_lhs']} "
               f"LHS samples per candidate, {ga['n_mc']}-run evaluations, {config.n_seeds} seeds: {est}")
        status(msg)
        import sys

        print(msg, file=sys.stderr, flush=True)

    status("onoff-tuning: NSGA-II Pareto front")  # 1. deterministic front (eq. 9), seed 0 of the pipeline
    seed0_nsga = _seed0_nsga(seed_seqs)
    pareto, det_gains, minfuel_gains, minfuel_settled = _deterministic(config, base, settings, bounds, seed0_nsga)
    status("onoff-tuning: printed gain order")  # 2. both readings of Tables 4 and 6
    order_rows, feasible, consistent_order = _gain_order(config, base, settings)
    seeds = []  # 3-4. robust GA per case and seed; evaluations on fresh samples
    if executor is not None and executor.n_workers > 1 and config.n_seeds > 1:
        # the seed pipelines are independent (one SeedSequence child each): one task per seed,
        # its campaigns run in that task (serially); same numbers as the loop below
        status(f"onoff-tuning: {config.n_seeds} pipeline seeds on {executor.spec}")
        tasks = [(i, ss, pareto if i == 0 else None) for i, ss in enumerate(seed_seqs)]
        shared = (config, ga, settings, base, bounds, dict(mc_kw, executor=None), consistent_order)
        seeds = list(executor.map(_seed_task, tasks, description="pipeline seeds", shared=shared))
    else:
        for i, ss in enumerate(seed_seqs):
            status(f"onoff-tuning: pipeline seed {i + 1}/{config.n_seeds}")
            seeds.append(_seed_pipeline(config, i, ss, ga, settings, base, bounds, mc_kw, consistent_order,
                                        pareto=pareto if i == 0 else None))
    robust_runs = seeds[0].runs
    sweep_rows = _ratio_sweep(config, rng, base, settings, bounds, mc_kw, robust_runs["all"])  # 5. Figs 12-14
    std_rows = _std_sweep(config, rng, settings, mc_kw, det_gains, robust_runs)  # 6. Figs 15-19
    rate_rows = _rate_sweep(config, rng, mc_kw, det_gains, robust_runs["all"].x)  # 7. Figs 20-21
    sweep_rows += _case_sweep(config, rng, base, settings, bounds, mc_kw)  # 8. Figs 12-13
    # Fig. 10's step responses and Fig. 11's LHS draw (the last use of the random stream)
    traces = []
    for label, g in (("min error", det_gains), ("min fuel", minfuel_gains), ("min fuel, settled", minfuel_settled)):
        tr = simulate_trace(base.replace(kp=g[0], ki=g[1], kd=g[2]), settings)
        traces.append(StepTrace(label=label, gains=g, t=tr.t, theta=tr.theta))
    lhs = latin_hypercube({"inertia": Gaussian(mean=config.inertia_kgm2, std=config.std_inertia_kgm2)}, 1000,
                          rng)["inertia"]
    det_all, rob_all = seeds[0].mc_results["all"]
    return Measurements(
        ga=ga, pareto=pareto, det_gains=det_gains, minfuel_gains=minfuel_gains, minfuel_settled=minfuel_settled,
        order_rows=tuple(order_rows), feasible=feasible, consistent_order=consistent_order, seeds=tuple(seeds),
        robust=_robust_summary(config, seeds[0], ga), sweep_rows=tuple(sweep_rows), std_rows=tuple(std_rows),
        rate_rows=tuple(rate_rows), traces=tuple(traces),
        mc_all=(np.degrees(det_all.metrics.mean_abs_err_last), np.degrees(rob_all.metrics.mean_abs_err_last)),
        lhs_inertia=lhs,
    )
