"""Figures of the ``thruster-layout`` study: pure functions of the measurement records.

No random numbers, no optimisation, no allocation here: everything drawn is in
:class:`~adcskit.studies.thruster_layout.experiment.Measurements`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from adcskit.studies._base import new_figure
from adcskit.studies.thruster_layout.config import Config
from adcskit.studies.thruster_layout.experiment import ALLOCATIONS, Measurements
from adcskit.studies.thruster_layout.paper import PAPER

__all__ = ["figures"]


def figures(cfg: Config, m: Measurements) -> dict[str, Any]:
    """The study's figures by file stem, in report order (cf. S3 Figs 3-5).

    Examples
    --------
    >>> from adcskit.studies.thruster_layout.figures import figures
    >>> callable(figures)
    True
    """
    out = {
        "runtime_vs_n": _fig_runtime(cfg, m),
        "fitness_vs_n": _fig_fitness(cfg, m),
        "convergence": _fig_convergence(cfg, m),
        "layouts_3d": _fig_layouts(cfg, m),
    }
    if m.reference_vs_optimal is not None:
        out["on_times_ref_vs_opt"] = _fig_on_times(m)
    return out


def _fig_runtime(cfg: Config, m: Measurements):
    fig, ax = new_figure()
    for alg, mk in (("ga", "s-"), ("de", "o-")):
        if alg not in cfg.algorithms:
            continue
        ns = list(cfg.n_thrusters)
        med = [m.summaries[(n, alg)].cpu_s for n in ns]
        lo = [min(m.summaries[(n, alg)].cpu_s_seeds) for n in ns]
        hi = [max(m.summaries[(n, alg)].cpu_s_seeds) for n in ns]
        color = "C0" if alg == "ga" else "C1"
        ax.errorbar(ns, med, yerr=[np.subtract(med, lo), np.subtract(hi, med)], fmt=mk, color=color,
                    capsize=3, label=f"{alg.upper()} CPU time (median, min-max over seeds)")
        ax.plot(ns, [m.summaries[(n, alg)].runtime_s for n in ns], mk[0] + ":", color=color, alpha=0.5,
                label=f"{alg.upper()} wall time (median; shared machine)")
    ax.set_xlabel("number of thrusters")
    ax.set_ylabel("time per optimisation (s)")
    ax.set_title(f"Run time vs n ({cfg.n_gen} generations x {cfg.pop_size}; cf. S3 Fig 3)")
    ax.set_xticks(list(cfg.n_thrusters))
    ax.legend()
    return fig


def _fig_fitness(cfg: Config, m: Measurements):
    fig, ax = new_figure()
    off = {"ga": -0.12, "de": 0.12}
    for alg, mk in (("ga", "s"), ("de", "o")):
        if alg not in cfg.algorithms:
            continue
        ns = list(cfg.n_thrusters)
        for n in ns:
            v = m.summaries[(n, alg)].f_best_seeds
            ax.plot(np.full(len(v), n + off[alg]), v, mk, alpha=0.35, color="C0" if alg == "ga" else "C1")
        ax.plot(np.add(ns, off[alg]), [m.summaries[(n, alg)].f_best_median for n in ns], mk + "-",
                color="C0" if alg == "ga" else "C1", label=f"{alg.upper()} median (dots: seeds)")
    for n, d in PAPER["f_best"].items():
        for _alg, v in d.items():
            ax.plot(int(n), v, "x", color="k", ms=8)
    ax.plot([], [], "x", color="k", label="S3 printed F_best (own manoeuvre)")
    ax.set_xlabel("number of thrusters")
    ax.set_ylabel("F_best (S3 eq. 18)")
    ax.set_yscale("log")
    ax.set_title("Fitness vs n (cf. S3 Fig 4)")
    ax.set_xticks(list(cfg.n_thrusters))
    ax.legend(fontsize=8)
    return fig


def _fig_on_times(m: Measurements):
    fig, axes = new_figure(1, 2, figsize=(9.0, 3.8))
    for ax, method in zip(axes, ALLOCATIONS):
        d = m.reference_vs_optimal.by_allocation[method]
        ref, opt = np.asarray(d.on_times_ref_s), np.asarray(d.on_times_opt_s)
        i = np.arange(1, len(ref) + 1)
        ax.bar(i - 0.2, ref, 0.4, label=f"reference (sum {ref.sum():.3f} s)")
        ax.bar(i + 0.2, opt, 0.4, label=f"optimal (sum {opt.sum():.3f} s)")
        ax.set_xlabel("thruster")
        ax.set_ylabel("total on-time over the manoeuvre (s)")
        ax.set_title(method, fontsize=10)
        ax.set_xticks(i)
        ax.legend(fontsize=8)
    fig.suptitle("On-times on the 14 design demands: reference vs best 6-thruster layout (cf. S3 Fig 5)")
    return fig


def _fig_convergence(cfg: Config, m: Measurements):
    ns = list(cfg.n_thrusters)
    ncols = min(len(ns), 2)
    nrows = math.ceil(len(ns) / ncols)
    fig, axes = new_figure(nrows, ncols, figsize=(9.0, 3.2 * nrows), squeeze=False)
    for ax, n in zip(axes.flat, ns):
        for alg, color in (("ga", "C0"), ("de", "C1")):
            H = np.array([r.history for r in m.runs if r.n == n and r.alg == alg])
            if H.size == 0:
                continue
            g = np.arange(1, H.shape[1] + 1)
            ax.fill_between(g, H.min(0), H.max(0), color=color, alpha=0.2)
            ax.plot(g, np.median(H, 0), color=color, label=f"{alg.upper()} median, min-max band")
        ax.set_yscale("log")
        ax.set_title(f"n = {n}", fontsize=10)
        ax.set_xlabel("generation")
        ax.set_ylabel("best F_best")
        ax.legend(fontsize=8)
    for ax in list(axes.flat)[len(ns):]:
        ax.set_visible(False)
    fig.suptitle("Convergence (best so far) over seeds")
    return fig


def _draw_box(ax, h):
    corners = np.array([[x, y, z] for x in (-h[0], h[0]) for y in (-h[1], h[1]) for z in (-h[2], h[2])])
    for i in range(8):
        for j in range(i + 1, 8):
            if np.sum(corners[i] != corners[j]) == 1:
                ax.plot(*zip(corners[i], corners[j]), color="0.6", lw=0.8)


def _fig_layouts(cfg: Config, m: Measurements):
    from matplotlib.figure import Figure

    ns = list(cfg.n_thrusters)
    ncols = min(len(ns), 2)
    nrows = math.ceil(len(ns) / ncols)
    fig = Figure(figsize=(9.0, 4.2 * nrows), layout="constrained")
    h = np.asarray(cfg.box_half_size_m)
    for k, n in enumerate(ns):
        ax = fig.add_subplot(nrows, ncols, k + 1, projection="3d")
        _draw_box(ax, h)
        row = m.best_per_n[n]
        P, D = np.asarray(row.positions), np.asarray(row.directions)
        ax.scatter(*P.T, color="C3", s=18)
        ax.quiver(*P.T, *(-0.5 * D).T, color="C1", lw=1.2, label="exhaust (-d)")
        ax.quiver(*P.T, *(0.5 * D).T, color="C0", lw=1.2, label="force d")
        ax.set_title(f"n = {n} ({row.alg.upper()}), F_best {row.f_best:.3f}", fontsize=9)
        ax.set_xlabel("X (m)")
        ax.set_ylabel("Y (m)")
        ax.set_zlabel("Z (m)")
        lim = 1.5 * h.max()
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
        ax.set_zlim(-lim, lim)
        if k == 0:
            ax.legend(fontsize=7, loc="upper left")
    fig.suptitle("Best layouts on the 2 x 2 x 2 m box")
    return fig
