"""Figures of ``model-estimation``: pure functions of the :class:`~.experiment.Measurements`.

No random numbers, no solving, no simulation: every curve is read from the records.
"""

from __future__ import annotations

import numpy as np

from adcskit.studies._base import new_figure
from adcskit.studies.model_estimation.config import Config
from adcskit.studies.model_estimation.experiment import Measurements

__all__ = ["figures"]

_STYLE = {
    "gmres": ("C0", "-"), "bicg": ("C1", "--"), "bicgstab": ("C2", ":"), "cgs": ("C3", "-."), "qr": ("k", "-"),
    "lsqr": ("0.5", "--"), "adaptive-gmres-offline": ("C4", "-"), "adaptive-gmres-online": ("C5", "-"),
    "ridge-prior": ("C6", "-"), "rls": ("C7", "--"), "augmented-ekf": ("C8", "-"),
    "ridge-prior-discrepancy": ("C6", ":"), "rls-prior": ("C7", "-."),
}



def figures(cfg: Config, m: Measurements) -> dict:
    """The study's figures by file stem: error vs time (default and low-noise readings), the two
    norms of the adaptive variants, and the seed-0 angle estimates."""
    figs = dict(_error_vs_time(cfg, m))
    figs["norm-convergence"] = _norm_convergence(cfg, m)
    figs["angle-estimate"] = _angle_estimate(cfg, m)
    return figs


def _error_vs_time(cfg: Config, m: Measurements):
    for reading in (r for r in ("default", "low noise") if r in m.readings):
        sigma = cfg.noise_std_low if reading == "low noise" else cfg.noise_std
        tag = "" if reading == "default" else "-low-noise"
        fig, axes = new_figure(2, 2, figsize=(11, 7.5), squeeze=False)
        for ax, c in zip(axes.ravel(), cfg.cases):
            runs = m.by[(reading, c)]
            for meth in cfg.methods:
                e = np.median(np.stack([r.methods[meth].e2 for r in runs]), axis=0)
                col, ls = _STYLE[meth]
                ax.semilogy(np.arange(e.size) * cfg.dt_s, e, color=col, ls=ls, label=meth, lw=1.2)
            ax.axhline(runs[0].prior_error, color="k", lw=0.6, ls=":", label="prior A0")
            ax.set_title(f"{c} (median of {len(runs)} seeds)")
            ax.set_xlabel("time [s]")
            ax.set_ylabel("100 ||Â − A||₂ / ||A||₂ [%]")
        axes[0, 0].legend(fontsize=6, ncol=2)
        fig.suptitle(f"Model-error norm vs time, {reading} reading, noise std {sigma:g} (cf. S1 Figs 2, 6, 10)")
        yield f"model-error-vs-time{tag}", fig


def _norm_convergence(cfg: Config, m: Measurements):
    fig, axes = new_figure(2, 2, figsize=(11, 7.5), squeeze=False)
    for ax, c in zip(axes.ravel(), cfg.cases):
        runs = m.by[("default", c)]
        for meth in ("adaptive-gmres-online", "adaptive-gmres-offline"):
            if meth not in cfg.methods:
                continue
            col = _STYLE[meth][0]
            for key, ls in (("e2", "-"), ("efro", "--")):
                e = np.median(np.stack([getattr(r.methods[meth], key) for r in runs]), axis=0)
                ax.plot(np.arange(e.size) * cfg.dt_s, e, color=col, ls=ls,
                        label=f"{meth} {'2-norm' if key == 'e2' else 'Frobenius'}")
        ax.set_title(c)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("relative error [%]")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle("Frobenius and 2-norm convergence of the adaptive GMRES estimates (cf. S1 Figs 4, 8, 12)")
    return fig


def _angle_estimate(cfg: Config, m: Measurements):
    fig, axes = new_figure(2, 2, figsize=(11, 7.5), squeeze=False)
    for ax, c in zip(axes.ravel(), cfg.cases):
        r0 = next(r for r in m.by[("default", c)] if r.seed_index == 0)
        t = np.arange(r0.angle_true.size) * cfg.dt_s
        ax.plot(t, r0.angle_meas, ".", color="0.75", ms=2, label="measurement")
        ax.plot(t, r0.angle_true, "k-", lw=2.0, label="truth")
        for meth, col in (("adaptive-gmres-online", "C5"), ("qr", "C0"), ("augmented-ekf", "C8")):
            if meth in cfg.methods:
                ax.plot(t, r0.methods[meth].angle, color=col, lw=1, label=f"estimate ({meth})")
        lim = 2 * max(np.abs(r0.angle_true).max(), 1e-3)
        ax.set_ylim(-lim, lim)
        ax.set_title(f"{c}: {'pitch θ' if c.startswith('3dof') else 'angle'} (seed 0)")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("rad")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle(f"Angle estimate vs truth, noise std {cfg.noise_std:g} (cf. S1 Figs 1, 5, 9, 13)")
    return fig
