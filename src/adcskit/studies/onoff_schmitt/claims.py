"""The ``onoff-schmitt`` study's claims (S4's) and checks (ours), as declarations.

:data:`CLAIMS`, :data:`FINDINGS` and :data:`CHECKS` list one small factory per statement, in
report order (the thruster-layout convention). Each takes the config and the
:class:`~.experiment.Measurements` and returns

* for a claim: a :class:`Declared` — the framework's :class:`ClaimSpec` and its runs keyed by
  reading — that :func:`evaluate` hands to :meth:`ClaimSpec.evaluate` (the framework decides);
* for a check: a :class:`~adcskit.studies.Check`.

They are factories rather than constants because the framework's specs hold finished strings
and numbers, and S4's statements quote the configured window, threshold and sweep row. The
simulations are deterministic: one run decides each reading.

References
----------
S4, §3, Table 2, Figs. 3-7.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from adcskit.studies._base import Check
from adcskit.studies._verdict import ClaimSpec, Declared, decide_declared
from adcskit.studies.onoff_schmitt.config import Config
from adcskit.studies.onoff_schmitt.experiment import Measurements

__all__ = ["CHECKS", "CLAIMS", "FINDINGS", "Declared", "evaluate"]


@dataclass(frozen=True, slots=True)
class _Error:
    """The nominal run's pointing error in one reading [deg]."""

    e: float


@dataclass(frozen=True, slots=True)
class _Held:
    """One run's yes / no answer."""

    ok: bool


@dataclass(frozen=True, slots=True)
class _Trends:
    """Correlations of ``U_on`` with the firings and with the mean |error|."""

    f: float
    e: float


# ----------------------------------------------------------------------------- claims (S4's)


def _pointing_accuracy(cfg: Config, m: Measurements) -> Declared:
    return Declared(ClaimSpec(
        id="pointing-accuracy-0.25deg",
        statement="the attitude control system reaches a pointing accuracy of 0.25° under the constant "
                  "0.05 N m disturbance",
        where="§3, text with Figs. 5-7",
        quantity=f"|error| over the last {cfg.t_window_s:g} s of the nominal run (Table 3, Table 4 gains); holds "
                 f"below {cfg.accuracy_claim_deg:g}°",
        value=lambda r: r.e, threshold=cfg.accuracy_claim_deg, better="below", unit="deg",
        paper=cfg.accuracy_claim_deg, stochastic=False, readings=("mean |error|",),
        describe=lambda r: f"{r.values[0]:.4f}°",
    ), {"max |error|": [_Error(m.nominal.max_abs_err_last10_deg)],
        "mean |error|": [_Error(m.nominal.mean_abs_err_last10_deg)]}, "max |error|")


def _table2_region(cfg: Config, m: Measurements) -> Declared:
    ins, out = m.region_inside, m.region_outside
    return Declared(ClaimSpec(
        id="table2-recommended-region",
        statement="Table 2: thresholds in the recommended region (all three criteria: 0.1 < U_on < 0.6, "
                  "0.1 < U_off/U_on < 0.85) give low fuel, low thruster activity and low pointing error",
        where="§3, Table 2, Figs. 2-4",
        quantity="median over the swept grid inside vs outside the recommended box; holds if inside is lower "
                 "(all-criteria box: fuel and firings; per-criterion rows: each row's box on its own criterion)",
        held=lambda r: r.ok, stochastic=False, readings=("per-criterion rows",),
        describe=lambda r: "medians inside/outside: fuel "
        f"{ins.fuel:.2f}/{out.fuel:.2f} N m s, firings {ins.firings:.0f}/{out.firings:.0f} (all-criteria box); rows: "
        + ", ".join(f"{k} {v.inside:.3g}/{v.outside:.3g}" for k, v in m.rows.items()),
    ), {"all-criteria box": [_Held(ins.fuel < out.fuel and ins.firings < out.firings)],
        "per-criterion rows": [_Held(all(v.inside < v.outside for v in m.rows.values()))]}, "all-criteria box")


def _u_on_trends(cfg: Config, m: Measurements) -> Declared:
    return Declared(ClaimSpec(
        id="u-on-trends",
        statement="a larger on threshold U_on gives fewer thruster firings and a larger pointing error",
        where="§3, Figs. 3-4",
        quantity=f"correlation of U_on with firings (< 0) and with mean |error| (> 0) along U_off/U_on = "
                 f"{m.trend_ratio:.2f}",
        held=lambda r: r.f < 0 and r.e > 0, stochastic=False,
        describe=lambda r: f"corr(U_on, firings) {m.firings_trend:+.2f}, corr(U_on, error) {m.err_trend:+.2f}",
    ), {"default": [_Trends(m.firings_trend, m.err_trend)]})


# ----------------------------------------------------------------------------- checks (ours)


def _reference_path_agrees(cfg: Config, m: Measurements) -> Check:
    same = m.reference_agrees
    return Check(name="numba kernel and NumPy reference path agree bit for bit on the nominal run", passed=same,
                 detail="all 7 metrics identical" if same else "metrics differ", kind="check")


def _fuel_covers_disturbance(cfg: Config, m: Measurements) -> Check:
    impulse = abs(cfg.disturbance_nm) * cfg.t_window_s
    return Check(name="fuel covers at least the disturbance impulse", passed=m.nominal.fuel >= impulse,
                 detail=f"fuel {m.nominal.fuel:.3f} N m s vs |T_d|·t_window = {impulse:.3f}", kind="check")


def _grid_covers_boxes(cfg: Config, m: Measurements) -> Check:
    inside = m.inside
    return Check(
        name="the swept grid has points inside and outside every Table 2 box",
        passed=bool(inside.any() and (~inside).any()
                    and all(np.isfinite(v.inside) and np.isfinite(v.outside) for v in m.rows.values())),
        detail=f"{int(inside.sum())} of {inside.size} grid points inside the all-criteria box",
        kind="check",
    )


#: S4's claims, in report order.
CLAIMS = (_pointing_accuracy, _table2_region, _u_on_trends)
#: Our findings (none: the study reproduces S4's figures and claims only).
FINDINGS: tuple[Callable[[Config, Measurements], Any], ...] = ()
#: Our consistency checks, in report order.
CHECKS = (_reference_path_agrees, _fuel_covers_disturbance, _grid_covers_boxes)


#: Decide the declared statements (the framework's :func:`~adcskit.studies._verdict.decide_declared`).
evaluate = decide_declared
