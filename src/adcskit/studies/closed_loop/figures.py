"""The ``closed-loop`` study's figures: pure functions of the :class:`~.experiment.Measurements`.

Every trace drawn here was recorded by :func:`~.experiment.measure`; nothing here draws random
numbers or simulates.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from adcskit.simulation.envelopes import envelope
from adcskit.studies._base import new_figure
from adcskit.studies.closed_loop.claims import chi2_mean_band
from adcskit.studies.closed_loop.experiment import Measurements, ModeSequence, Trace

__all__ = ["figures"]


def figures(m: Measurements) -> dict[str, Any]:
    """The study's seven figures, by file stem, in report order.

    Examples
    --------
    >>> from adcskit.studies.closed_loop import figures
    >>> callable(figures.figures)
    True
    """
    return {
        "attitude-error": _fig_error(m.slews.step_trace, m.slews.optimal_trace),
        "thruster-activity": _fig_thrusters(m.slews.step_trace, m.slews.optimal_trace),
        "nees": _fig_nees(m.estimators.nees_trace),
        "propellant": _fig_propellant(m.layouts.propellant_samples),
        "q5-attitude-error": _fig_q5_error(m.wheels.wheel_trace, m.wheels.thruster_trace),
        "q5-wheel-speed": _fig_q5_speed(m.wheels.wheel_trace),
        "q6-mode-sequence-envelopes": _fig_q6(m.modes),
    }


def _envelope(ax, t, err, style, label):
    p05, p50, p95 = np.nanpercentile(err, [5, 50, 95], axis=0)
    ax.plot(t, p50, style, label=f"{label} median")
    ax.fill_between(t, p05, p95, alpha=0.25, label=f"{label} 5-95 %")


def _fig_error(rec_s: Trace, rec_o: Trace):
    fig, ax = new_figure(figsize=(6.4, 4.0))
    i = rec_s.channels.index("pointing_error")
    _envelope(ax, rec_s.t, np.degrees(rec_s.trace[:, :, i]), "-", "step command")
    _envelope(ax, rec_o.t, np.degrees(rec_o.trace[:, :, i]), "--", "optimal profile")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("pointing error to the reference [deg]")
    ax.set_yscale("log")
    ax.set_title(f"GEO slew, {rec_s.n_samples} Monte-Carlo samples")
    ax.legend(fontsize=7)
    return fig


def _fig_thrusters(rec_s: Trace, rec_o: Trace):
    fig, axes = new_figure(2, 1, figsize=(6.4, 5.0), sharex=True)
    for ax, rec, name in zip(axes, (rec_s, rec_o), ("step command", "optimal profile")):
        n = len(rec.channels) - 10
        for j in range(n):
            ax.plot(rec.t, rec.trace[0, :, 10 + j] + 1.2 * j, lw=0.8, label=f"thruster {j}")
        ax.set_ylabel("thrust / F_max (offset)")
        ax.set_title(f"{name}: sample 0", fontsize=9)
    axes[-1].set_xlabel("time [s]")
    axes[0].legend(fontsize=6, ncol=3)
    return fig


def _fig_nees(rec: Trace):
    t, nees = rec.t, rec.trace[:, :, rec.channels.index("nees")]
    fig, ax = new_figure(figsize=(6.4, 3.8))
    n = nees.shape[0]
    keep = np.any(np.isfinite(nees), axis=0)
    t, nees = t[keep], nees[:, keep]
    mean = np.nanmean(nees, axis=0)
    ax.plot(t, mean, "-", lw=0.8, label=f"mean NEES over {n} samples")
    lo, hi = chi2_mean_band(6, n)
    ax.axhspan(lo, hi, color="0.8", label="chi2(6) 95 % band of the mean")
    ax.axhline(6.0, ls="--", color="k", lw=0.8, label="expected 6")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("NEES (attitude + bias)")
    ax.set_yscale("log")
    ax.set_title("MEKF consistency in the LEO closed loop (Gaussian errors)")
    ax.legend(fontsize=7)
    return fig


def _fig_propellant(prop: Any):
    fig, ax = new_figure(figsize=(6.4, 3.8))
    for (name, v), style in zip(prop.items(), ("step", "stepfilled")):
        ax.hist(v * 1e3, bins=40, histtype=style, alpha=0.6 if style == "stepfilled" else 1.0, label=name)
    ax.set_xlabel("propellant per sample [g]")
    ax.set_ylabel("samples")
    ax.set_title("GEO slew + hold, S4 loop, pinv-redistribute: propellant distribution")
    ax.legend(fontsize=8)
    return fig


def _bands(ax, t, values, colour, label, rank_from=None):
    """Median, p5-p95 and p1-p99 bands over samples and the worst sample (largest peak ``|value|``,
    over ``t >= rank_from`` when given)."""
    e = envelope(values, t)
    ax.fill_between(t, e.p1, e.p99, color=colour, alpha=0.15, lw=0, label=f"{label} p1-p99")
    ax.fill_between(t, e.p5, e.p95, color=colour, alpha=0.35, lw=0, label=f"{label} p5-p95")
    ax.plot(t, e.median, color=colour, lw=1.2, label=f"{label} median")
    keep = np.ones(len(t), bool) if rank_from is None else np.asarray(t) >= rank_from
    peak = np.max(np.where(np.isfinite(values[:, keep]), np.abs(values[:, keep]), -np.inf), axis=1)
    w = int(np.argmax(peak))
    where = "" if rank_from is None else f", largest after {rank_from:g} s"
    ax.plot(t, values[w], color=colour, lw=0.6, ls=":", label=f"{label} worst (sample {w}{where})")


def _fig_q5_error(rec_w: Trace, rec_t: Trace):
    fig, axes = new_figure(2, 1, figsize=(6.4, 5.6), sharex=True)
    err_t = np.degrees(rec_t.trace[:, :, rec_t.channels.index("pointing_error")])
    err_w = np.degrees(rec_w.trace[:, :, rec_w.channels.index("error")])
    both = np.concatenate([err_t.ravel(), err_w.ravel()])
    both = both[np.isfinite(both) & (both > 0)]
    ylim = (0.5 * float(np.min(both)), 2.0 * float(np.max(both))) if both.size else (1e-3, 1e2)
    for ax, t, v, colour, name in ((axes[0], rec_t.t, err_t, "C1", "S4 thrusters (PID + Schmitt)"),
                                   (axes[1], rec_w.t, err_w, "C0", "wheels (quaternion PD)")):
        _bands(ax, t, v, colour, name.split(" (")[0], rank_from=t[-1] - 10.0)
        ax.set_yscale("log")
        ax.set_ylim(*ylim)
        ax.set_ylabel("pointing error [deg]")
        ax.set_title(f"{name}, {v.shape[0]} samples", fontsize=9)
        ax.axvspan(t[-1] - 10.0, t[-1], color="0.9", zorder=0)
        ax.legend(fontsize=6, loc="upper right")
    axes[-1].set_xlabel("time [s] (grey: S4's 10 s statistics window)")
    fig.suptitle("Q5: S4's spacecraft, 15 deg step, Monte-Carlo envelopes", fontsize=10)
    return fig


def _fig_q5_speed(rec_w: Trace):
    idx = [i for i, c in enumerate(rec_w.channels) if c.startswith("speed_")]
    fig, axes = new_figure(len(idx), 1, figsize=(6.4, 1.6 * len(idx) + 0.8), sharex=True)
    for ax, i in zip(np.atleast_1d(axes), idx):
        _bands(ax, rec_w.t, rec_w.trace[:, :, i] * 30.0 / np.pi, "C0", "")
        ax.set_ylabel(f"wheel {rec_w.channels[i][6:]} [rpm]", fontsize=8)
    np.atleast_1d(axes)[0].legend(fontsize=6, loc="upper left", ncol=2)
    np.atleast_1d(axes)[-1].set_xlabel("time [s]")
    fig.suptitle(f"Q5: wheel speeds relative to the body, {rec_w.n_samples} samples (median, p5-p95, p1-p99, worst)",
                 fontsize=9)
    return fig


#: Q6 panels: label, log scale, and the per-sample trace (N, R) in display units from the record.
_Q6_PANELS = (
    ("sun angle / pointing error [deg]", True,
     lambda tr, ch: np.degrees(tr[:, :, ch.index("error")])),
    ("body rate [deg/s]", True, lambda tr, ch: np.degrees(tr[:, :, ch.index("rate")])),
    ("largest wheel speed [rpm]", False,
     lambda tr, ch: np.max(np.abs(tr[:, :, [i for i, c in enumerate(ch) if c.startswith("speed_")]]), axis=2)
     * 30.0 / np.pi),
    ("wheel momentum |A h| [N m s]", False, lambda tr, ch: tr[:, :, ch.index("h_wheels")]),
    ("dipole |m| [A m^2]", False,
     lambda tr, ch: np.linalg.norm(tr[:, :, [i for i, c in enumerate(ch) if c.startswith("dipole_")]], axis=2)),
)


def _fig_q6(q6: ModeSequence):
    """Envelopes of the first seed's whole campaign (median, p5-p95, p1-p99), the worst sample by
    the requirement's ``pointing_max_deg`` (NaN: never pointing, ranks worst), and the share of the
    samples in each mode."""
    rec = q6.trace
    t, tr, ch = rec.t, rec.trace, rec.channels
    worst = int(np.argmax(np.where(np.isnan(q6.pointing_max_deg), np.inf, q6.pointing_max_deg)))
    fig, axes = new_figure(len(_Q6_PANELS) + 1, 1, figsize=(7.0, 12.5), sharex=True)
    for ax, (label, log, get) in zip(axes, _Q6_PANELS):
        v = get(tr, ch)
        e = envelope(v, t)
        ax.fill_between(t, e.p1, e.p99, color="C0", alpha=0.18, lw=0, label="p1-p99")
        ax.fill_between(t, e.p5, e.p95, color="C0", alpha=0.38, lw=0, label="p5-p95")
        ax.plot(t, e.median, color="C0", lw=1.4, label="median")
        ax.plot(t, v[worst], color="C3", lw=0.8, label=f"worst by pointing_max_deg (sample {worst})")
        ax.axvspan(q6.metrics_from_s, t[-1], facecolor="0.9", edgecolor="none", zorder=0.5)
        if log:
            ax.set_yscale("log")
        ax.set_ylabel(label, fontsize=8)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=7, loc="upper right", ncol=2)
    mode = tr[:, :, ch.index("mode")]
    shares = [np.mean(mode == k, axis=0) for k in range(3)]
    axes[-1].stackplot(t, *shares, labels=("detumble", "sun acquisition", "nadir pointing"),
                       colors=("C1", "C2", "C0"), alpha=0.7)
    axes[-1].set_ylabel("share of samples per mode", fontsize=8)
    axes[-1].set_ylim(0.0, 1.0)
    axes[-1].legend(fontsize=7, loc="center right")
    axes[-1].set_xlabel("time [s] (grey: the requirement window, the third orbit)")
    fig.suptitle(f"Q6: 12U reference mode sequence, detumble -> sun -> nadir, first seed's {rec.n_samples} samples",
                 fontsize=10)
    return fig
