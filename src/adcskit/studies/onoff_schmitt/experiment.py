"""The measurements of ``onoff-schmitt``: the nominal run and the Schmitt threshold sweep.

:func:`measure` runs, in the study's order, the nominal step response (S4 Figs. 5-7) with its
NumPy reference re-run, then the ``U_on`` x ``U_off/U_on`` sweep (S4 Figs. 2-4, Table 2), and
returns :class:`Measurements`, a frozen record of everything the claims, tables and figures
read. The simulations are deterministic: no random numbers are drawn.

References
----------
S4, Figs. 2-7, Tables 2-3.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from adcskit._progress import status
from adcskit._results import Result
from adcskit.control.onoff import OnOffTrace, simulate_batch, simulate_trace
from adcskit.studies.onoff_schmitt.config import Config
from adcskit.studies.onoff_schmitt.paper import RECOMMENDED, TABLE2_ROWS

__all__ = ["Nominal", "Medians", "InsideOutside", "Sweep", "Measurements", "measure"]


@dataclass(frozen=True, slots=True, repr=False)
class Nominal(Result):
    """Metrics of the nominal run (S4 Table 3 loop, Table 4 gains); fields = ``measured.nominal``."""

    overshoot_pct: float
    mean_abs_err_last10_deg: float
    fuel: float
    firings: int
    max_abs_err_last10_deg: float
    settling_time_s: float


@dataclass(frozen=True, slots=True, repr=False)
class Medians(Result):
    """Medians over a set of grid points of the three Table 2 criteria."""

    fuel: float
    firings: float
    err_deg: float


@dataclass(frozen=True, slots=True, repr=False)
class InsideOutside(Result):
    """Median of one criterion inside and outside one Table 2 box."""

    inside: float
    outside: float


@dataclass(frozen=True, slots=True, repr=False)
class Sweep(Result):
    """The threshold sweep: axes, grids ``(n_ratio, n_u_on)`` and the metrics on them."""

    u_on: np.ndarray
    off_ratio: np.ndarray
    UU: np.ndarray
    RR: np.ndarray
    fuel: np.ndarray
    firings: np.ndarray
    err_deg: np.ndarray
    overshoot_pct: np.ndarray

    def criterion(self, name: str) -> np.ndarray:
        """The grid of one Table 2 criterion (``fuel``, ``firings`` or ``err_deg``)."""
        return {"fuel": self.fuel, "firings": self.firings, "err_deg": self.err_deg}[name]


@dataclass(frozen=True, slots=True, repr=False)
class Measurements(Result):
    """Everything the claims, tables and figures of the study read."""

    nominal: Nominal
    trace: OnOffTrace
    reference_agrees: bool
    sweep: Sweep
    inside: np.ndarray
    region_inside: Medians
    region_outside: Medians
    rows: dict[str, InsideOutside]
    trend_ratio: float
    firings_trend: float
    err_trend: float


def _med(z: np.ndarray, mask: np.ndarray) -> float:
    return float(np.median(z[mask])) if mask.any() else float("nan")


def _in_box(sweep: Sweep, box: dict[str, Any]) -> np.ndarray:
    m = np.ones(sweep.UU.shape, bool)
    for (lo, hi), G in ((box["u_on"], sweep.UU), (box["off_ratio"], sweep.RR)):
        if lo is not None:
            m &= G > lo
        if hi is not None:
            m &= G < hi
    return m


def _sweep(config: Config, settings) -> Sweep:
    u_on = np.linspace(*config.sweep_u_on, config.n_u_on)
    ratio = np.linspace(*config.sweep_ratio, config.n_ratio)
    UU, RR = np.meshgrid(u_on, ratio)  # (n_ratio, n_u_on)
    sweep = simulate_batch(config.params(u_on=UU.ravel(), off_ratio=RR.ravel()), settings)
    shape = UU.shape
    return Sweep(u_on=u_on, off_ratio=ratio, UU=UU, RR=RR, fuel=sweep.fuel.reshape(shape),
                 firings=sweep.firings.reshape(shape),
                 err_deg=np.degrees(sweep.mean_abs_err_last).reshape(shape),
                 overshoot_pct=sweep.overshoot_pct.reshape(shape))


def measure(config: Config) -> Measurements:
    """Run the nominal loop and the threshold sweep (deterministic) and collect the records.

    Examples
    --------
    >>> from adcskit.studies.onoff_schmitt import Config
    >>> m = measure(Config(n_u_on=3, n_ratio=2, t_final_s=4.0, t_window_s=2.0))
    >>> m.sweep.fuel.shape, m.reference_agrees, m.nominal.firings > 0
    ((2, 3), True, True)
    """
    settings = config.settings()
    # nominal run (S4 Figs 5-7)
    status("onoff-schmitt: nominal step response")
    trace = simulate_trace(config.params(), settings)
    mt = trace.metrics
    nominal = Nominal(
        overshoot_pct=float(mt.overshoot_pct[0]),
        mean_abs_err_last10_deg=float(np.degrees(mt.mean_abs_err_last[0])),
        fuel=float(mt.fuel[0]),
        firings=int(mt.firings[0]),
        max_abs_err_last10_deg=float(np.degrees(mt.max_abs_err_last[0])),
        settling_time_s=float(mt.settling_time[0]),
    )
    ref = simulate_batch(config.params(), settings, backend="numpy")
    same = np.array_equal(ref.as_array(), mt.as_array(), equal_nan=True)

    # threshold sweep (S4 Figs 2-4)
    status("onoff-schmitt: threshold sweep")
    sw = _sweep(config, settings)
    (a, b), (c, d) = RECOMMENDED["u_on"], RECOMMENDED["off_ratio"]
    inside = (sw.UU > a) & (sw.UU < b) & (sw.RR > c) & (sw.RR < d)
    region = [Medians(fuel=_med(sw.fuel, msk), firings=_med(sw.firings, msk), err_deg=_med(sw.err_deg, msk))
              for msk in (inside, ~inside)]
    rows = {}
    for crit, box in TABLE2_ROWS.items():
        msk = _in_box(sw, box)
        rows[crit] = InsideOutside(inside=_med(sw.criterion(crit), msk), outside=_med(sw.criterion(crit), ~msk))
    # trends along U_on at the nominal ratio (closest grid row)
    row = int(np.argmin(np.abs(sw.off_ratio - config.off_ratio)))
    return Measurements(
        nominal=nominal, trace=trace, reference_agrees=bool(same), sweep=sw, inside=inside,
        region_inside=region[0], region_outside=region[1], rows=rows, trend_ratio=float(sw.off_ratio[row]),
        firings_trend=float(np.corrcoef(sw.u_on, sw.firings[row])[0, 1]),
        err_trend=float(np.corrcoef(sw.u_on, sw.err_deg[row])[0, 1]),
    )
