"""The ``wahba-table1`` study's figures: pure functions of the :class:`~.experiment.Measurements`.

Examples
--------
>>> from adcskit.studies.wahba_table1 import figures
>>> figures.__all__
['figures', 'replica_ratios', 'sweep_mean_error', 'table1_errors']
"""

from __future__ import annotations

from typing import Any

import numpy as np

from adcskit.studies._base import new_figure
from adcskit.studies.wahba_table1.config import Config
from adcskit.studies.wahba_table1.experiment import ROWS, SWEEP_ROWS, Measurements
from adcskit.studies.wahba_table1.paper import paper_ratio

__all__ = ["figures", "replica_ratios", "sweep_mean_error", "table1_errors"]

_STYLES = {"q-method": ("k", "o-"), "minmax": ("C0", "s-"), "worst-case": ("C2", "^-"),
           "minmax-box-at-exact-triad": ("C3", "v--"), "minmax-box-at-truth": ("C1", "d--")}
#: Per-replica ratios shown against the paper's factor: (Replica field, label).
_RATIO_KEYS = (("err_ratio", "error q/min-max"), ("nsga_truth_ratio", "error q/NSGA-II truth pick"),
               ("var_ratio", "variance q/min-max"), ("slope_ratio", "slope q/min-max"),
               ("speed_ratio", "time NSGA-II/SLSQP min-max"),
               ("speed_ratio_big", "time NSGA-II 15x/SLSQP min-max"),
               ("speed_ratio_closed_form", "time NSGA-II/closed form"),
               ("minmax_over_nsga_truth", "error min-max/NSGA-II truth pick"))


def sweep_mean_error(cfg: Config, m: Measurements) -> Any:
    """Mean attitude error vs noise bound, per sweep row (pooled over the replicas)."""
    fig, ax = new_figure(figsize=(7.0, 4.2))
    for row in SWEEP_ROWS:
        col, style = _STYLES[row]
        ax.plot(m.bounds * 100, m.sweep_mean_deg[row], style, color=col, label=row)
    ax.set_xlabel("noise bound [% of component]")
    ax.set_ylabel("mean attitude error δθ [deg]")
    ax.set_title(f"S0 sensitivity sweep ({cfg.n_seeds} x {cfg.sweep_trials} trials per point)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return fig


def table1_errors(cfg: Config, m: Measurements) -> Any:
    """Box plot of every row's attitude errors over the pooled Table 1 trials."""
    fig, ax = new_figure(figsize=(7.6, 4.4))
    names = list(ROWS)
    pooled = m.pooled
    data = [[res.solves[row].error_deg for res in pooled if row in res] for row in names]
    ax.boxplot(data, tick_labels=names)
    ax.set_ylabel("δθ [deg]")
    ax.set_title(f"Table 1 trials (±{cfg.noise_bound:.0%}, {cfg.n_seeds} x {cfg.n_trials} trials; "
                 f"iterative rows {cfg.n_seeds} x {cfg.n_iterative})")
    ax.tick_params(axis="x", labelrotation=30)
    return fig


def replica_ratios(cfg: Config, m: Measurements) -> Any:
    """The deciding ratios of every replica against the paper's factors (log scale)."""
    fig, ax = new_figure(figsize=(7.0, 4.2))
    for i, (key, _lab) in enumerate(_RATIO_KEYS):
        v = [getattr(rep, key) for rep in m.replicas]
        ax.plot(np.full(len(v), i), v, "o", color=f"C{i}", alpha=0.7)
    paper_marks = (paper_ratio("q-method", "minmax", "mean_deg"), paper_ratio("q-method", "nsga2-truth-pick", "mean_deg"),
                   paper_ratio("q-method", "minmax", "var_deg2"), 200.0, 600.0, 600.0, 600.0,
                   paper_ratio("minmax", "nsga2-truth-pick", "mean_deg"))
    ax.plot(range(len(_RATIO_KEYS)), paper_marks, "k_", ms=20, mew=2, label="paper's factor")
    ax.set_yscale("log")
    ax.set_xticks(range(len(_RATIO_KEYS)), [lab for _, lab in _RATIO_KEYS], rotation=25, fontsize=7)
    ax.set_ylabel("ratio [-]")
    ax.set_title(f"Deciding ratios per replica ({cfg.n_seeds} seeds) vs the paper")
    ax.axhline(1.0, color="0.6", lw=0.8)
    ax.legend(fontsize=8)
    return fig


def figures(cfg: Config, m: Measurements) -> dict[str, Any]:
    """Every figure of the study, keyed by file stem."""
    return {"sweep-mean-error": sweep_mean_error(cfg, m), "table1-errors": table1_errors(cfg, m),
            "replica-ratios": replica_ratios(cfg, m)}
