"""Tables and text of ``onoff-schmitt``: paper-vs-ours rows, ``measured``, the sweep CSV,
the summary and the differences from S4; pure functions of the measurement records.

References
----------
S4, Figs. 2-7, Tables 2-4.
"""

from __future__ import annotations

from typing import Any

from adcskit.studies._base import Comparison
from adcskit.studies.onoff_schmitt.config import Config
from adcskit.studies.onoff_schmitt.experiment import Measurements

__all__ = ["comparison", "differences", "measured", "summary", "tables"]


def measured(m: Measurements) -> dict[str, Any]:
    """``result.json`` → ``measured`` (keys and order of the study's JSON schema)."""
    sw = m.sweep
    return {
        "nominal": m.nominal.to_dict(),
        "region_medians": {"inside": m.region_inside.to_dict(), "outside": m.region_outside.to_dict()},
        "table2_rows_medians": {k: v.to_dict() for k, v in m.rows.items()},
        "trend_corr_u_on": {"firings": m.firings_trend, "error": m.err_trend},
        "sweep": {"u_on": sw.u_on, "off_ratio": sw.off_ratio, "fuel": sw.fuel, "firings": sw.firings,
                  "mean_abs_err_last10_deg": sw.err_deg},
    }


def comparison(config: Config, m: Measurements) -> list[Comparison]:
    """Paper-vs-ours rows: the 0.25° accuracy, Table 2's recommended region, the overshoot."""
    ins, out = m.region_inside, m.region_outside
    return [
        Comparison(quantity="pointing accuracy (max |e|, last 10 s)", paper=config.accuracy_claim_deg,
                   measured=round(m.nominal.max_abs_err_last10_deg, 4), unit="deg",
                   note="S4 text under Fig. 7"),
        Comparison(quantity="recommended U_on range (all criteria)", paper="0.1 < U_on < 0.6",
                   measured=f"median firings inside {ins.firings:.0f} / outside {out.firings:.0f}",
                   note="S4 Table 2 (decoded)"),
        Comparison(quantity="recommended U_off/U_on range (all criteria)", paper="0.1 < U_off/U_on < 0.85",
                   measured=f"median fuel inside {ins.fuel:.2f} / outside {out.fuel:.2f} N m s",
                   unit="", note="S4 Table 2 (decoded)"),
        Comparison(quantity="nominal overshoot", paper=None, measured=round(m.nominal.overshoot_pct, 3), unit="%",
                   note="S4 shows the response (Fig. 5) but prints no number"),
    ]


def tables(m: Measurements) -> dict[str, list[dict[str, Any]]]:
    """One CSV per table: the threshold sweep, one row per grid point."""
    sw = m.sweep
    n_ratio, n_u_on = sw.UU.shape
    return {"schmitt_sweep": [
        {"u_on": float(sw.UU[i, j]), "off_ratio": float(sw.RR[i, j]), "fuel": float(sw.fuel[i, j]),
         "firings": int(sw.firings[i, j]), "mean_abs_err_last10_deg": float(sw.err_deg[i, j]),
         "overshoot_pct": float(sw.overshoot_pct[i, j])}
        for i in range(n_ratio) for j in range(n_u_on)
    ]}


def summary(config: Config, m: Measurements, claims) -> str:
    """The result's summary paragraph."""
    nominal = m.nominal
    return (
        f"Nominal loop (S4 Table 3): overshoot {nominal.overshoot_pct:.2f} %, mean |e| over the last 10 s "
        f"{nominal.mean_abs_err_last10_deg:.4f}°, max {nominal.max_abs_err_last10_deg:.4f}° "
        f"(S4 claims {config.accuracy_claim_deg:g}°), fuel {nominal.fuel:.2f} N m s, {nominal.firings} firings. "
        f"Swept {m.sweep.u_on.size}×{m.sweep.off_ratio.size} Schmitt thresholds. Verdicts: "
        + "; ".join(f"{c.id}: {c.outcome}" for c in claims) + "."
    )


def differences(config: Config) -> list[str]:
    """What we do differently from S4, and why."""
    return [
        "S4's model equations did not survive in the source text; we model the derivative as "
        "K_d s/(τ_d s+1) with τ_d = 0.01 s (not printed), the thruster as two equal first-order lags "
        "(τ_t = 0.01 s, S4 Table 3) after a pure delay, and the Schmitt trigger as evaluated at the 50 Hz "
        "command rate.",
        "S4 prints no gains for this study; we use Table 4's minimum-error point in the (K_p, K_d, K_i) "
        "reading (see onoff-tuning for why).",
        "Fuel is the delivered angular impulse ∫|T_c| dt [N m s]; S4 calls its fuel measure ΔV without a "
        "formula.",
        f"Simulated {config.t_final_s:g} s with a {config.dt_s * 1e3:g} ms fixed step (S4 prints neither).",
    ]
