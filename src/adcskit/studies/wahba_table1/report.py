"""The ``wahba-table1`` study's tables and text: pure functions of the :class:`~.experiment.Measurements`.

Examples
--------
>>> from adcskit.studies.wahba_table1 import report
>>> len(report.differences())
11
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import fields
from typing import Any

import numpy as np

from adcskit.studies._base import Comparison
from adcskit.studies._verdict import Claim
from adcskit.studies.wahba_table1.config import Config
from adcskit.studies.wahba_table1.experiment import ROWS, SWEEP_ROWS, Measurements
from adcskit.studies.wahba_table1.paper import PAPER_TABLE1, paper_ratio

__all__ = ["REPLICA_KEYS", "comparison", "differences", "measured", "summary", "tables", "title"]

#: The per-replica ratios and fractions of ``replicas.csv`` (and ``measured["replicas"]``).
REPLICA_KEYS = ("err_ratio", "err_ratio_slsqp", "nsga_truth_ratio", "nsga_knee_ratio", "worst_case_ratio",
                "var_ratio", "slope_ratio", "speed_ratio", "speed_ratio_closed_form", "speed_ratio_big",
                "speed_ratio_closed_form_big", "minmax_over_nsga_truth", "minmax_over_nsga_knee",
                "var_minmax_over_nsga_truth", "var_minmax_over_nsga_knee", "frac_in_box", "box_truth_mean_deg",
                "timing_spread")


def _row(rec: Any) -> dict[str, Any]:
    """A record's fields as a flat ``{name: value}`` mapping (values as measured, NaN kept)."""
    return {f.name: getattr(rec, f.name) for f in fields(rec)}


def title(cfg: Config) -> str:
    """The result's title, with the configured noise bound."""
    return f"Robust Wahba, one epoch with ±{cfg.noise_bound:.0%} interval noise (S0 Table 1)"


def _replica_rows(m: Measurements) -> list[dict[str, Any]]:
    return [{"replica": j, **{k: getattr(rep, k) for k in REPLICA_KEYS}} for j, rep in enumerate(m.replicas)]


def tables(cfg: Config, m: Measurements) -> dict[str, list[dict[str, Any]]]:
    """The CSV tables: Table 1 rows (pooled), the noise sweep, the per-replica ratios."""
    table_rows = [{"method": row, **_row(m.stats[row]),
                   **({"sweep_slope_deg_per_unit": m.slopes[row]} if row in m.slopes else {})} for row in ROWS]
    sweep_rows = [{"noise_bound": float(bd), **{row: m.sweep_mean_deg[row][i] for row in SWEEP_ROWS}}
                  for i, bd in enumerate(m.bounds)]
    return {"table1": table_rows, "sweep": sweep_rows, "replicas": _replica_rows(m)}


def measured(cfg: Config, m: Measurements) -> dict[str, Any]:
    """The ``measured`` block of ``result.json``."""
    return {
        "methods": {row: _row(st) for row, st in m.stats.items()},
        "sweep": {"noise_bound": m.bounds.tolist(), "mean_deg": m.sweep_mean_deg, "slope_deg_per_unit": m.slopes},
        "replicas": _replica_rows(m),
        "fraction_qmethod_in_box": m.frac_in_box,
        "closed_form_vs_slsqp_max_deg": m.cf_vs_slsqp_max_deg,
        "exact_vectors": _row(m.exact),
        # per-reading means over the replicas, quoted by the doc page
        "ratio_means": {k: float(_mean(m, k)) for k in REPLICA_KEYS if k.startswith(("speed", "minmax_", "var_"))},
        "nsga2_nfev": {row: m.stats[row].nfev for row in ("nsga2-knee", "nsga2-big-knee")},
        # speed-600x's timing phase: per timed epoch, each method's CPU times of its repeats [s]
        "timing": [{"replica": t.replica, "epoch": t.epoch, "times_s": {k: list(v) for k, v in t.times.items()},
                    "identical": t.identical} for t in m.timed],
    }


def comparison(cfg: Config, m: Measurements) -> list[Comparison]:
    """Paper vs measured, per Table 1 row and quantity (rows the paper lacks say so)."""
    out = []
    for row in ROWS:
        p = PAPER_TABLE1.get(row, {})
        st = m.stats[row]
        for key, unit in (("mean_deg", "deg"), ("var_deg2", "deg²"), ("runtime_s", "s")):
            out.append(Comparison(quantity=f"{row}: {key}", paper=p.get(key), measured=getattr(st, key), unit=unit,
                                  note=("" if p else "not in the paper") + f" ({st.n_trials} trials pooled)"))
    return out


def _mean(m: Measurements, key: str) -> float:
    return np.mean([getattr(rep, key) for rep in m.replicas])


def summary(cfg: Config, m: Measurements, claims: Sequence[Claim]) -> str:
    """The one-paragraph summary: the Table 1 means, the in-box fraction and each claim's outcome."""
    by_id = {c.id: c for c in claims}
    qm = m.stats["q-method"]
    sr = f"±{cfg.search_range:.0%}"
    return (
        f"{cfg.n_seeds} replicas x {cfg.n_trials} trials (±{cfg.noise_bound:.0%} noise): q-method "
        f"{qm.mean_deg:.2f} deg vs min-max {m.stats['minmax'].mean_deg:.2f} deg (paper 15.14 vs 2.20). "
        f"The printed min-max problem is the q-method optimum restricted to the {sr} TRIAD box; the "
        f"unconstrained q-method attitude lies inside that box in only {100 * m.frac_in_box:.0f} % of trials. "
        f"7x lower error: {by_id['error-7x'].outcome}; 200x less sensitive: {by_id['sensitivity-200x'].outcome} "
        f"(variance ratio {_mean(m, 'var_ratio'):.2f}, slope ratio "
        f"{_mean(m, 'slope_ratio'):.2f}); ~600x faster than NSGA-II "
        f"(CPU time; NSGA-II {cfg.pop_size}x{cfg.n_gen} or {cfg.pop_size}x{cfg.nsga2_big_n_gen}, iterative "
        f"SLSQP or closed-form min-max): {by_id['speed-600x'].outcome} (ratios {_mean(m, 'speed_ratio'):.0f}, "
        f"{_mean(m, 'speed_ratio_big'):.0f}, {_mean(m, 'speed_ratio_closed_form'):.0f}, "
        f"{_mean(m, 'speed_ratio_closed_form_big'):.0f}; the paper's own table gives "
        f"{paper_ratio('nsga2-truth-pick', 'minmax', 'runtime_s'):.0f}x). NSGA-II more accurate than min-max: "
        f"{by_id['nsga2-beats-minmax'].outcome}. NSGA-II with the paper's truth pick: "
        f"{m.stats['nsga2-truth-pick'].mean_deg:.2f} deg (paper 0.57). A box centred on the true attitude gives "
        f"{m.stats['minmax-box-at-truth'].mean_deg:.2f} deg, consistent with the paper's min-max row."
    )


def differences() -> list[str]:
    """What this study does differently from S0, and why."""
    return [
        "q_exact is printed scalar-first with Shuster's A(q); we convert to scalar-last.",
        "Noise: each component multiplied by (1 + u), u ~ U(−bound, bound), then renormalised; the "
        "interval given to the robust solvers is midpoint = measured vector, radius = bound·|measured "
        "component|.",
        "Min-max: the goal-attainment problem as printed (z* = 0, λ = 1, |ΔL|) is solved exactly "
        "(closed form + KKT on the TRIAD box: row 'minmax') and iteratively as the paper does "
        "(SLSQP on (q, α, β, γ) from TRIAD, finite-difference gradients like MATLAB fminimax: row "
        "'minmax-slsqp'). Both give the same attitude; the speed claim is decided with the iterative one.",
        "NSGA-II: pymoo, population/generations ours (not printed); eq. 5 enforced by renormalising "
        "the box points; ΔL minimised signed (with |ΔL| the front collapses to the q-method point). "
        "The NSGA-II run time scales with population x generations; the paper's 124.58 s suggests a "
        "larger budget than ours, so speed-600x is also decided at 15x our budget (1.5e5 evaluations per "
        "epoch), run on the first n_big_epochs timed epochs of each replica only (not on the whole table).",
        "The paper's NSGA-II row picks the Pareto point nearest the true attitude; we report it as "
        "'nsga2-truth-pick' (not deployable) beside a truth-free knee pick.",
        "Every claim is decided over independent replicas of the whole table (noise draws and "
        "NSGA-II seeds); the iterative rows run on the first n_iterative trials of each replica.",
        "'200 times less dependence': two readings, the variance ratio at ±20 % (the paper's table "
        "gives 95.16/0.4409 = 216) and the ratio of slopes of mean error vs noise bound.",
        "The paper's run-time table gives 124.58/0.287 = 434x, not the abstract's 600x.",
        "Worst-case row (Ahmed & Kerrigan) added; QUEST/SVD rows are sanity checks.",
        "Diagnostic rows minmax-box-at-exact-triad / minmax-box-at-truth centre the search box on "
        "the noise-free answer (not deployable) to test how the paper's min-max figures could arise.",
        "Run times of the compared solvers: CPU time of the solving thread (time.thread_time) with numba "
        "and BLAS pinned to one thread, each timed epoch solved timing_repeats times by every method, "
        "interleaved, the epoch's time the median of the repeats (a shared machine's load moves it "
        "little); Python + numba, not comparable to the paper's MATLAB wall times in absolute terms, "
        "only as ratios of two solvers on the same epochs, with a declared margin around the bar.",
    ]
