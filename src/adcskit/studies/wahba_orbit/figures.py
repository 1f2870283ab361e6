"""Figures of the ``wahba-orbit`` study (cf. S0 Figs. 1-4): pure functions of the records.

No random numbers, no solving, no simulation here: the series drawn are seed 0 of the paper's
case (:attr:`~.experiment.Measurements.first`) and the per-seed RMS of every pass.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from adcskit.attitude import dcm_to_euler, quat_to_dcm
from adcskit.studies._base import new_figure
from adcskit.studies.wahba_orbit.config import Config
from adcskit.studies.wahba_orbit.experiment import METHODS, Measurements

__all__ = ["figures"]


def figures(cfg: Config, m: Measurements) -> dict[str, Any]:
    """The study's figures by file stem, in report order.

    Examples
    --------
    >>> from adcskit.studies.wahba_orbit.figures import figures
    >>> callable(figures)
    True
    """
    figs = {f"euler-{nm}": _fig_euler(m, j, nm) for j, nm in enumerate(("roll", "pitch", "yaw"))}
    figs["attitude-error"] = _fig_error(m)
    figs["rms"] = _fig_rms(cfg, m)
    return figs


def _fig_euler(m: Measurements, j: int, nm: str) -> Any:
    """Euler angle ``nm`` estimated vs truth (S0 Figs. 1-3)."""
    tm = m.t / 60.0
    series = m.first.series
    fig, ax = new_figure(figsize=(7.0, 3.6))
    ax.plot(tm, m.euler_true_deg[:, [2, 1, 0][j]], "k-", lw=2, label="truth")
    for meth, ls in (("q-method", "-"), ("minmax", "--"), ("worst-case", ":")):
        e = np.degrees(dcm_to_euler(quat_to_dcm(series.est[meth]), "ZYX"))[:, [2, 1, 0][j]]
        ax.plot(tm, e, lw=0.8, ls=ls, label=meth)
    ax.set_xlabel("time [min]")
    ax.set_ylabel(f"{nm} [deg]")
    ax.set_title(f"{nm} estimate vs truth ({m.paper_case}, seed 0; S0 Fig. {j + 1})")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    return fig


def _fig_error(m: Measurements) -> Any:
    """Attitude error of every estimator along the pass (seed 0, paper's case)."""
    tm = m.t / 60.0
    series = m.first.series
    fig, ax = new_figure(figsize=(7.0, 3.6))
    for meth, ls in (("worst-case", ":"), ("minmax", "--"), ("q-method", "-")):
        ax.plot(tm, series.err[meth], lw=0.8, ls=ls, label=meth)
    idx = series.nsga_idx
    ax.plot(tm[idx], series.err["nsga2-knee"][idx], "o", ms=3, label="nsga2-knee")
    ax.set_xlabel("time [min]")
    ax.set_ylabel("δθ [deg]")
    ax.set_title(f"attitude error ({m.paper_case}, seed 0)")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    return fig


def _fig_rms(cfg: Config, m: Measurements) -> Any:
    """RMS error by method for every (case, weighting), mean ± std over seeds (S0 Fig. 4)."""
    fig, ax = new_figure(figsize=(7.6, 3.8))
    groups = list(m.by)
    width = 0.8 / len(groups)
    for i, (case, w) in enumerate(groups):
        vals = [m.mean_rms(case, w, meth) for meth in METHODS]
        err = [np.std([o.rms[meth] for o in m.by[(case, w)]]) for meth in METHODS]
        ax.bar(np.arange(len(METHODS)) + i * width, vals, width, yerr=err, label=f"{case}, {w}",
               hatch=["", "//", "..", "xx"][i % 4])
    ax.set_xticks(np.arange(len(METHODS)) + 0.4 - width / 2, METHODS)
    ax.set_yscale("log")
    ax.set_ylabel("RMS δθ [deg] (mean ± std over seeds)")
    ax.set_title(f"RMS attitude error, {cfg.n_seeds} seeds (S0 Fig. 4)")
    ax.legend(fontsize=7)
    return fig
