"""Figures of ``onoff-schmitt`` (S4 Figs. 2-7): pure functions of the measurement records.

References
----------
S4, Figs. 2-7.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from adcskit.studies._base import new_figure
from adcskit.studies.onoff_schmitt.config import Config
from adcskit.studies.onoff_schmitt.experiment import Measurements
from adcskit.studies.onoff_schmitt.paper import RECOMMENDED

__all__ = ["figures"]


def _contour(ax, x, y, z, title, label, fig, log=False):
    zz = np.log10(np.maximum(z, 1e-12)) if log else z
    cs = ax.contourf(x, y, zz, levels=20, cmap="viridis")
    cb = fig.colorbar(cs, ax=ax)
    cb.set_label(("log10 " if log else "") + label)
    ax.set_xlabel("U_on")
    ax.set_ylabel("U_off / U_on")
    ax.set_title(title, fontsize=9)
    (a, b), (c, d) = RECOMMENDED["u_on"], RECOMMENDED["off_ratio"]
    ax.plot([a, b, b, a, a], [c, c, d, d, c], "w--", lw=1.2, label="S4 Table 2 region")
    ax.legend(loc="upper right", fontsize=7)


def _sweep_figures(m: Measurements) -> dict[str, Any]:
    """S4 Figs. 2-4: fuel, firings and mean |error| over the threshold grid."""
    sw, out = m.sweep, {}
    for name, z, title, label, log in (
        ("fig2_fuel", sw.fuel, "Fuel ∫|T_c|dt vs Schmitt thresholds (S4 Fig. 2)", "fuel [N m s]", False),
        ("fig3_firings", sw.firings, "Number of firings (S4 Fig. 3)", "firings", True),
        ("fig4_error", sw.err_deg, "Mean |error| over the last 10 s (S4 Fig. 4)", "error [deg]", True),
    ):
        fig, ax = new_figure(figsize=(6.0, 4.4))
        _contour(ax, sw.UU, sw.RR, z, title, label, fig, log=log)
        out[name] = fig
    return out


def _step_response(config: Config, m: Measurements):
    """S4 Fig. 5: step response and pointing error of the nominal run."""
    trace, step = m.trace, math.radians(config.step_deg)
    fig, axes = new_figure(2, 1, figsize=(6.4, 5.6), sharex=True)
    axes[0].plot(trace.t, np.degrees(trace.theta), lw=1)
    axes[0].axhline(config.step_deg, color="k", ls=":", lw=0.8)
    axes[0].set_ylabel("θ [deg]")
    axes[0].set_title(f"Step response to {config.step_deg:g}° with T_d = {config.disturbance_nm} N m (S4 Fig. 5)",
                      fontsize=9)
    axes[1].plot(trace.t, np.degrees(step - trace.theta), lw=0.8)
    ylim = max(1.3 * config.accuracy_claim_deg, 4 * m.nominal.max_abs_err_last10_deg)
    axes[1].set_ylim(-ylim, ylim)
    axes[1].axhline(config.accuracy_claim_deg, color="r", ls="--", lw=0.8,
                    label=f"±{config.accuracy_claim_deg:g}° (S4 claim: 0.25°)")
    axes[1].axhline(-config.accuracy_claim_deg, color="r", ls="--", lw=0.8)
    axes[1].set_ylabel("error [deg]")
    axes[1].set_xlabel("t [s]")
    axes[1].legend(fontsize=7)
    return fig


def _thruster_history(m: Measurements):
    """S4 Fig. 6: Schmitt-trigger command and delivered torque of the nominal run."""
    trace = m.trace
    fig, axes = new_figure(2, 1, figsize=(6.4, 4.8), sharex=True)
    axes[0].step(trace.t, trace.command, where="post", lw=0.8)
    axes[0].set_ylabel("command")
    axes[0].set_title("Thruster on/off command and delivered torque (S4 Fig. 6)", fontsize=9)
    axes[1].plot(trace.t, trace.thrust_torque, lw=0.8)
    axes[1].set_ylabel("T_c [N m]")
    axes[1].set_xlabel("t [s]")
    return fig


def _limit_cycle(config: Config, m: Measurements):
    """S4 Fig. 7: phase portrait of the nominal run over the last ``t_window_s``."""
    trace, step = m.trace, math.radians(config.step_deg)
    fig, ax = new_figure(figsize=(5.6, 4.4))
    tail = trace.t >= config.t_final_s - config.t_window_s
    ax.plot(np.degrees(step - trace.theta[tail]), np.degrees(trace.omega[tail]), lw=0.6)
    ax.set_xlabel("error θ_ref − θ [deg]")
    ax.set_ylabel("ω [deg/s]")
    ax.set_title("Limit cycle over the last 10 s (S4 Fig. 7)", fontsize=9)
    return fig


def figures(config: Config, m: Measurements) -> dict[str, Any]:
    """S4 Figs. 2-7 from the records, keyed by file stem, in the study's order."""
    return {**_sweep_figures(m), "fig5_step_response": _step_response(config, m),
            "fig6_thruster_history": _thruster_history(m), "fig7_limit_cycle": _limit_cycle(config, m)}
