"""Figures of ``onoff-tuning`` (S4 Figs 9-21): pure functions of the measurement records.

No random draw, no simulation, no optimisation: the step responses and the LHS sample they
show were taken by :func:`~adcskit.studies.onoff_tuning.experiment.measure`.

References
----------
S4, Figs. 9-21.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from adcskit.studies._base import new_figure
from adcskit.studies.onoff_tuning.config import CASE_PARAMS, Config
from adcskit.studies.onoff_tuning.experiment import Measurements
from adcskit.studies.onoff_tuning.paper import CASES

__all__ = ["figures"]

_INPUT_UNITS = {"inertia": "kg m²", "torque": "N m", "disturbance": "N m", "delay": "s"}


def _pareto(m: Measurements):
    """S4 Fig. 9: the Pareto front, our min-error point and the feasible Table 4 points."""
    pareto = m.pareto
    fig, ax = new_figure(figsize=(6.0, 4.4))
    ax.plot(pareto.F[:, 0], pareto.F[:, 1], "o", ms=3, label="NSGA-II Pareto front")
    if pareto.success:
        ax.plot(pareto.F[0, 0], pareto.F[0, 1], "s", color="k", ms=7, mfc="none",
                label="min-error (deterministic gains)")
    for r in m.order_rows:
        if r.entry.startswith("table4") and r.feasible:
            ax.plot(r.error_deg, r.fuel, "^", ms=7, label=f"S4 {r.entry} ({r.order})")
    ax.set_xscale("log")
    ax.set_xlabel("mean |error| over the last 10 s [deg]")
    ax.set_ylabel("fuel ∫|T_c|dt [N m s]")
    ax.set_title("Deterministic two-objective tuning (S4 Fig. 9)", fontsize=9)
    ax.legend(fontsize=7)
    return fig


def _steps(config: Config, m: Measurements):
    """S4 Fig. 10: step responses of the Pareto points."""
    fig, ax = new_figure(figsize=(6.4, 4.0))
    for tr in m.traces:
        ax.plot(tr.t, np.degrees(tr.theta), lw=1, label=f"{tr.label} {np.round(tr.gains, 2).tolist()}")
    ax.axhline(config.step_deg, color="k", ls=":", lw=0.8)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("θ [deg]")
    ax.set_title("Step responses of Pareto points (S4 Fig. 10)", fontsize=9)
    ax.legend(fontsize=7)
    return fig


def _lhs(config: Config, m: Measurements):
    """S4 Fig. 11: the LHS draw of the inertia against its Gaussian."""
    from scipy import stats

    fig, axes = new_figure(1, 2, figsize=(8.0, 3.4))
    s = m.lhs_inertia
    axes[0].hist(s, bins=30, density=True, alpha=0.7, label="LHS, 1000 samples")
    xs = np.linspace(s.min(), s.max(), 200)
    axes[0].plot(xs, stats.norm.pdf(xs, config.inertia_kgm2, config.std_inertia_kgm2), "k", lw=1, label="N(10, 2²)")
    axes[0].set_xlabel("J [kg m²]")
    axes[0].legend(fontsize=7)
    axes[1].plot(np.sort(s), np.arange(1, s.size + 1) / s.size, lw=1, label="empirical CDF")
    axes[1].plot(xs, stats.norm.cdf(xs, config.inertia_kgm2, config.std_inertia_kgm2), "k--", lw=1, label="Gaussian CDF")
    axes[1].legend(fontsize=7)
    axes[1].set_xlabel("J [kg m²]")
    fig.suptitle("Latin-hypercube sampling of the inertia (S4 Fig. 11)", fontsize=9)
    return fig


def _ratio_sweep(m: Measurements):
    """S4 Figs 12-14: std and mean of |error| vs the weight ratio."""
    fig, axes = new_figure(1, 2, figsize=(10.0, 4.0))
    for case in CASES:
        rows = sorted((r for r in m.sweep_rows if r.case == case), key=lambda r: r.ratio)
        if not rows:
            continue
        x = [r.ratio for r in rows]
        style = "k-o" if case == "all" else "-o"
        label = case + (" (stored GAs replayed)" if any(r.stored for r in rows) else "")
        axes[0].plot(x, [r.std_abs_err_deg for r in rows], style, ms=4, label=label)
        axes[1].plot(x, [r.mean_abs_err_deg for r in rows], style, ms=4, label=label)
    for ax, what in zip(axes, ("std", "mean")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("w2 / w1")
        ax.set_ylabel(f"{what} |error| [deg]")
    axes[0].legend(fontsize=7)
    fig.suptitle("Robust tuning vs weight ratio (S4 Figs 12-13: each uncertainty; Fig. 14: all four)", fontsize=10)
    return fig


def _std_sweep(m: Measurements):
    """S4 Figs 15-19: deterministic vs robust gains vs the input standard deviation."""
    fig, axes = new_figure(2, 5, figsize=(14.0, 5.2))
    for j, case in enumerate(CASES):
        rows = [r for r in m.std_rows if r.case == case]
        x = [r.input_std for r in rows]
        for i, what in enumerate(("mean", "std")):
            ax = axes[i, j]
            ax.plot(x, [getattr(r, f"det_{what}_deg") for r in rows], "s-", label="deterministic")
            ax.plot(x, [getattr(r, f"robust_{what}_deg") for r in rows], "o-", label="robust")
            ax.set_title(f"{case}: {what} |error|", fontsize=8)
            ax.set_yscale("log")
            unit = _INPUT_UNITS.get(CASE_PARAMS[case][0], "") if case != "all" else "× Table 5"
            ax.set_xlabel(f"input std [{unit}]", fontsize=8)
            ax.tick_params(labelsize=7)
            if j == 0:
                ax.set_ylabel("[deg]")
                ax.legend(fontsize=7)
    fig.suptitle("Deterministic vs robust gains vs input standard deviation (S4 Figs 15-19)", fontsize=10)
    return fig


def _command_rate(config: Config, m: Measurements):
    """S4 Figs 20-21: command rate 50/200/1000 Hz, all four uncertainties."""
    fig, axes = new_figure(1, 2, figsize=(10.0, 4.0))
    for i, what in enumerate(("std", "mean")):
        for hz in config.command_rates_hz:
            rows = [r for r in m.rate_rows if r.rate_hz == hz]
            x = [r.factor for r in rows]
            axes[i].plot(x, [getattr(r, f"det_{what}_deg") for r in rows], "s--", label=f"det {hz:g} Hz")
            axes[i].plot(x, [getattr(r, f"robust_{what}_deg") for r in rows], "o-", label=f"robust {hz:g} Hz")
        axes[i].set_xlabel("input std (× Table 5)")
        axes[i].set_ylabel(f"{what} |error| [deg]")
        axes[i].set_yscale("log")
    axes[0].legend(fontsize=7)
    fig.suptitle("Command rate 50/200/1000 Hz, all four uncertainties (S4 Figs 20-21)", fontsize=10)
    return fig


def _convergence(m: Measurements):
    """Robust GA convergence and the all-four Monte-Carlo histograms (seed 0)."""
    fig, axes = new_figure(1, 2, figsize=(10.0, 3.8))
    for case in CASES:
        h = m.robust_runs[case].history
        axes[0].plot(np.arange(1, h.size + 1), h, label=case)
    axes[0].set_yscale("log")
    axes[0].set_xlabel("generation")
    axes[0].set_ylabel("best robust objective [deg]")
    axes[0].set_title("robust GA convergence (seed 0)", fontsize=9)
    axes[0].legend(fontsize=7)
    det, rob = m.mc_all
    bins = np.linspace(0, np.percentile(np.r_[det, rob], 99), 50)
    axes[1].hist(det, bins=bins, alpha=0.6, label="deterministic")
    axes[1].hist(rob, bins=bins, alpha=0.6, label="robust")
    axes[1].set_xlabel("mean |error| over the last 10 s [deg]")
    axes[1].set_title("all four uncertainties, Monte Carlo (seed 0)", fontsize=9)
    axes[1].legend(fontsize=7)
    return fig


def figures(config: Config, m: Measurements) -> dict[str, Any]:
    """Every figure of the study, by file stem."""
    return {
        "fig9_pareto": _pareto(m),
        "fig10_step_responses": _steps(config, m),
        "fig11_lhs_inertia": _lhs(config, m),
        "fig12_14_ratio_sweep": _ratio_sweep(m),
        "fig15_19_std_sweep": _std_sweep(m),
        "fig20_21_command_rate": _command_rate(config, m),
        "ga_convergence_and_mc": _convergence(m),
    }
