"""Monte-Carlo envelope figures of recorded simulation traces.

For a recorded channel of a :class:`~adcskit.simulation.SimulationResult` (``record=True``)
an *envelope* is, at each recorded time, the median and the 5–95 % and 1–99 % bands of the
samples (:func:`numpy.nanpercentile`, linear interpolation), with the worst few samples drawn
on top so that a tail can be traced back to its sample (and its seed and parameters). With
fewer than 100 samples the 1–99 % band is interpolated between the most extreme samples and
says little; the figure's title states ``n``.

* :func:`envelope` — the numbers (:class:`Envelope`): median and bands of any array
  ``(N, R)``;
* :func:`envelope_figure` — the generic figure: one panel per channel (an indexed group such
  as ``thrust`` gives one panel per index), for any channel, including those the wheel and
  magnetorquer models add (wheel speeds, momentum, dipole): pass their scale and unit;
* :func:`attitude_error_figure` — pointing error (deg, log scale) and, optionally, the
  error about each body axis;
* :func:`body_rate_figure` — body rates about x, y, z (deg/s).

Worst samples are ranked by a stated per-sample metric (``worst_by``, default for the
attitude figure ``pointing_max_deg``, for the rate figure ``max_rate_deg_s``) or, with
``worst_by="peak"``, by the largest ``|value|`` of the plotted channel over the trace; a
NaN metric ranks as the worst. The legend names the ranking.

Figures are :class:`matplotlib.figure.Figure` objects without pyplot (no global state; save
with ``fig.savefig``), like the studies' ``new_figure``. Hand-written here: only the layout;
the percentiles are NumPy's.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from adcskit._results import Result
from adcskit._validation import check_choice, check_finite, check_flag, check_int, short_repr
from adcskit.constants import DEG_PER_RAD
from adcskit.errors import InputError, InputTypeError
from adcskit.simulation.core import SimulationResult
from adcskit.simulation.export import CHANNEL_INFO, _group_channels
from adcskit.simulation.wheels import WheelSimulationResult

#: Result types whose traces the envelope functions read (same ``t``, ``trace``, ``channels``,
#: ``metrics``, ``n_samples`` fields).
_RESULTS = (SimulationResult, WheelSimulationResult)

__all__ = [
    "Envelope",
    "envelope",
    "worst_samples",
    "envelope_figure",
    "attitude_error_figure",
    "body_rate_figure",
]

#: Percentiles of an envelope, %.
BANDS = (1.0, 5.0, 50.0, 95.0, 99.0)
#: Colours of the worst samples, worst first (red, orange, purple, brown, pink).
_WORST_COLOURS = ("C3", "C1", "C4", "C5", "C6")
_UNIT_SCALES = {"rad": ("deg", DEG_PER_RAD), "rad/s": ("deg/s", DEG_PER_RAD)}


@dataclass(frozen=True, slots=True, kw_only=True)
class Envelope(Result):
    """Median and percentile bands of Monte-Carlo traces over time (:func:`envelope`).

    Attributes
    ----------
    t : ndarray (R,), s
    median, p1, p5, p95, p99 : ndarray (R,)
        Percentiles over the samples at each time (NaN samples ignored; all-NaN times are NaN).
    n : int
        Number of samples.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.simulation.envelopes import envelope
    >>> e = envelope(np.arange(101.0)[:, None] * np.ones((1, 3)), t=[0.0, 1.0, 2.0])
    >>> e.median.tolist(), e.p5.tolist(), float(e.p99[0]), e.n
    ([50.0, 50.0, 50.0], [5.0, 5.0, 5.0], 99.0, 101)
    """

    t: np.ndarray
    median: np.ndarray
    p1: np.ndarray
    p5: np.ndarray
    p95: np.ndarray
    p99: np.ndarray
    n: int


def envelope(values: Any, t: Any) -> Envelope:
    """Median, 5–95 % and 1–99 % bands over samples of traces ``values`` (N, R).

    Parameters
    ----------
    values : array_like (N, R)
        One row per sample, one column per recorded time (any unit; NaN allowed and ignored).
    t : array_like (R,), s
        Recorded times.

    Returns
    -------
    Envelope

    Raises
    ------
    InputError
        ``values`` not 2-D, no sample, or ``t`` of another length.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.simulation.envelopes import envelope
    >>> x = np.random.default_rng(0).normal(size=(1000, 2))
    >>> e = envelope(x, [0.0, 1.0])
    >>> bool(np.all(np.abs(e.p95 - 1.645) < 0.15))     # N(0, 1): p95 = 1.645
    True
    """
    v = np.asarray(values, dtype=float) if not isinstance(values, str) else None
    if v is None or v.ndim != 2 or v.shape[0] < 1:
        raise InputError(f"values must be a 2-D array (samples, times) with at least one sample; got "
                         f"{short_repr(values) if v is None else 'shape ' + str(v.shape)}")
    tt = np.asarray(t, dtype=float).reshape(-1)
    if tt.shape != (v.shape[1],):
        raise InputError(f"t must have one time per column of values ({v.shape[1]}); got {tt.size}")
    if v.size == 0 or np.all(np.isnan(v)):
        q = np.full((len(BANDS), v.shape[1]), np.nan)
    else:
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN columns give NaN
            q = np.nanpercentile(v, BANDS, axis=0)
    return Envelope(t=tt, p1=q[0], p5=q[1], median=q[2], p95=q[3], p99=q[4], n=int(v.shape[0]))


def _check_result(result: Any) -> SimulationResult:
    if not isinstance(result, _RESULTS):
        raise InputTypeError(f"result must be a SimulationResult or WheelSimulationResult (from "
                             f"adcskit.simulation.simulate or simulate_wheels); "
                             f"got {type(result).__name__}")
    if result.trace is None or result.t is None:
        raise InputError("result must hold traces for an envelope figure: run simulate(..., record=True); "
                         "got a result without traces")
    return result


def _channel_values(result: SimulationResult, channel: str) -> tuple[np.ndarray, list[str]]:
    """(N, R, K) values of a channel or an indexed group, and the K panel labels."""
    chans = tuple(result.channels)
    for var, idx, dim in _group_channels(chans):
        if var == channel:
            labels = [chans[c] for c in idx] if dim is not None else [channel]
            return np.asarray(result.trace, dtype=float)[:, :, idx], labels
    if channel in chans:
        c = chans.index(channel)
        return np.asarray(result.trace, dtype=float)[:, :, [c]], [channel]
    groups = [g[0] for g in _group_channels(chans)]
    check_choice("channel", channel, sorted(set(groups) | set(chans)))
    raise AssertionError("unreachable")  # pragma: no cover


def worst_samples(result: SimulationResult, n: int = 3, *, by: str = "pointing_max_deg",
                  channel: str | None = None, largest: bool = True) -> np.ndarray:
    """Indices of the ``n`` worst samples by a per-sample metric (worst first).

    Parameters
    ----------
    result : SimulationResult
    n : int
        How many (at most ``result.n_samples``), >= 0.
    by : str
        A metric of ``result.metrics`` (e.g. ``"pointing_max_deg"``), or ``"peak"``: the
        largest ``|value|`` of ``channel`` over the trace. A NaN value ranks as the worst.
    channel : str, optional
        The channel (or indexed group) for ``by="peak"``.
    largest : bool
        Worst = largest value (default) or smallest.

    Returns
    -------
    ndarray of int

    Examples
    --------
    >>> from adcskit.simulation import Scenario, SimSpec, simulate
    >>> from adcskit.simulation.envelopes import worst_samples
    >>> res = simulate(Scenario(sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0)), n_samples=5, rng=1)
    >>> idx = worst_samples(res, 2, by="pointing_max_deg")
    >>> bool(res.metrics["pointing_max_deg"][idx[0]] == res.metrics["pointing_max_deg"].max())
    True
    """
    if not isinstance(result, _RESULTS):
        raise InputTypeError(f"result must be a SimulationResult or WheelSimulationResult; got {type(result).__name__}")
    n = check_int("n", n, minimum=0)
    return _worst(result, n, by, channel, largest, "by")


def _worst(result: SimulationResult, n: int, by: Any, channel: str | None, largest: bool, name: str) -> np.ndarray:
    n = min(n, int(result.n_samples))
    if by == "peak":
        if channel is None:
            raise InputError(f"{name}='peak' needs channel (the channel whose largest |value| ranks the samples); got None")
        _check_result(result)
        vals, _ = _channel_values(result, channel)
        with np.errstate(invalid="ignore"):
            score = np.nanmax(np.abs(vals).reshape(vals.shape[0], -1), axis=1) if vals.size else np.zeros(0)
    else:
        check_choice(name, by, sorted(result.metrics) + ["peak"])
        score = np.asarray(result.metrics[by], dtype=float)
    key = np.where(np.isnan(score), np.inf, score if largest else -score)
    return np.argsort(-key, kind="stable")[:n]


def envelope_figure(
    result: SimulationResult,
    channel: str,
    *,
    scale: Any = None,
    units: str | None = None,
    label: str | None = None,
    worst: int = 3,
    worst_by: str = "peak",
    yscale: str = "linear",
    t_from: Any = 0.0,
    figsize: tuple[float, float] | None = None,
) -> Any:
    """Envelope figure of one recorded channel (or indexed group): one panel per component.

    Parameters
    ----------
    result : SimulationResult or WheelSimulationResult
        With traces (``simulate(..., record=True)`` or ``simulate_wheels(..., record=True)``:
        e.g. ``"speed"`` for the wheel speeds ``speed_0`` ... one panel each).
    channel : str
        A channel of ``result.channels`` (``"pointing_error"``, ``"omega_x"``) or the base of
        an indexed group (``"thrust"`` for ``thrust_0`` ... ``thrust_5``: one panel each);
        future channels such as wheel speeds work the same way.
    scale : float, optional
        Factor from the trace's SI value to the plotted unit. Default: rad -> deg and
        rad/s -> deg/s for the known channels (:data:`adcskit.simulation.export.CHANNEL_INFO`),
        else 1.
    units : str, optional
        Unit shown on the y axis (default: the one ``scale`` leads to).
    label : str, optional
        Quantity shown on the y axis (default: the channel's name).
    worst : int
        Worst samples to draw, >= 0 (by ``worst_by``; see :func:`worst_samples`).
    worst_by : str
        A metric name or ``"peak"`` (largest ``|value|`` of this channel).
    yscale : {"linear", "log", "symlog"}
    t_from : float, s
        Plot from this time on (e.g. the metrics window).
    figsize : (float, float), optional
        Inches; default 7 wide and 2.6 per panel.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from adcskit.simulation import Scenario, SimSpec, simulate
    >>> from adcskit.simulation.envelopes import envelope_figure
    >>> res = simulate(Scenario(sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0)), n_samples=5,
    ...                rng=1, record=True)
    >>> fig = envelope_figure(res, "thrust", units="fraction of f_max", worst=1)
    >>> len(fig.axes), fig.axes[-1].get_xlabel()
    (6, 'time [s]')
    """
    res = _check_result(result)
    if not isinstance(channel, str):
        raise InputTypeError(f"channel must be a str; got {short_repr(channel)}")
    vals, labels = _channel_values(res, channel)
    base = channel
    si = CHANNEL_INFO.get(base, ("", base))[0]
    if scale is None:
        units_default, s = _UNIT_SCALES.get(si, (si, 1.0))
    else:
        s = check_finite("scale", scale)
        units_default = si if s == 1.0 else ""
    units = units_default if units is None else units
    if not isinstance(units, str):
        raise InputTypeError(f"units must be a str; got {short_repr(units)}")
    check_choice("yscale", yscale, ("linear", "log", "symlog"))
    worst = check_int("worst", worst, minimum=0)
    t_from = check_finite("t_from", t_from)
    t = np.asarray(res.t, dtype=float)
    keep = t >= t_from
    if not np.any(keep):
        raise InputError(f"t_from must be at most the last recorded time {t[-1]:g} s; got {t_from:g} s")
    idx = _worst(res, worst, worst_by, channel, True, "worst_by")
    k = vals.shape[2]
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize or (7.0, 1.0 + 2.4 * k), layout="constrained")
    axes = fig.subplots(k, 1, sharex=True, squeeze=False)[:, 0]
    ulab = f" [{units}]" if units else ""
    for j, ax in enumerate(axes):
        v = vals[:, keep, j] * s
        e = envelope(v, t[keep])
        _draw(ax, e, v, idx, worst_by, yscale)
        name = label if (label is not None and k == 1) else (f"{label} {j}" if label is not None else labels[j])
        ax.set_ylabel(f"{name}{ulab}")
    axes[-1].set_xlabel("time [s]")
    _legend(fig, axes[0])
    fig.suptitle(f"{label or channel}: median, 5-95 % and 1-99 % of n = {res.n_samples} samples",
                 fontsize="medium")
    return fig


def _legend(fig: Any, ax: Any) -> None:
    """One legend for the figure, below the panels (never over the data)."""
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=min(len(labels), 4), fontsize="small",
               frameon=False)


def _draw(ax: Any, e: Envelope, v: np.ndarray, worst: np.ndarray, worst_by: str, yscale: str) -> None:
    ax.fill_between(e.t, e.p1, e.p99, color="C0", alpha=0.18, lw=0, label="1-99 %")
    ax.fill_between(e.t, e.p5, e.p95, color="C0", alpha=0.38, lw=0, label="5-95 %")
    ax.plot(e.t, e.median, color="C0", lw=1.8, label="median", zorder=4)
    by = "peak |value|" if worst_by == "peak" else worst_by
    for r, i in enumerate(worst):
        ax.plot(e.t, v[i], color=_WORST_COLOURS[r % len(_WORST_COLOURS)], lw=0.9, alpha=0.85, zorder=3,
                label=f"worst by {by}: sample {int(i)}" if r == 0 else f"sample {int(i)}")
    ax.set_yscale(yscale)
    if yscale == "log":
        _log_floor(ax, [e.p1, e.p5, e.median, e.p95, e.p99] + [v[i] for i in worst])
    ax.grid(True, which="major", alpha=0.3)


#: A log-scale panel spans at most this many decades below its largest value: errors at
#: rounding level (true knowledge before a step: 2e-15 deg) would otherwise stretch the axis
#: over a dozen empty decades.
LOG_DECADES = 4


def _log_floor(ax: Any, series: list[np.ndarray]) -> None:
    """Bottom of a log axis: the smallest positive value shown, but at most ``LOG_DECADES``
    decades below the largest (values below it are clipped at the axis)."""
    v = np.concatenate([np.asarray(x, dtype=float).ravel() for x in series])
    v = v[np.isfinite(v) & (v > 0)]
    if v.size:
        top = float(np.max(v))
        ax.set_ylim(bottom=max(float(np.min(v)), top * 10.0**-LOG_DECADES) / 1.25, top=top * 1.25)


def attitude_error_figure(result: SimulationResult, *, worst: int = 3, worst_by: str = "pointing_max_deg",
                          axes: bool = False, yscale: str = "log", t_from: Any = 0.0) -> Any:
    """Envelope of the pointing error (deg) and, with ``axes=True``, of its body-axis components.

    Parameters
    ----------
    result : SimulationResult
        With traces.
    worst : int
        Worst samples to draw.
    worst_by : str
        Metric ranking them (default ``pointing_max_deg``: largest error over the metrics
        window) or ``"peak"``.
    axes : bool
        Add one panel per body axis (error rotation vector components, deg, linear scale).
    yscale : {"log", "linear", "symlog"}
        Of the pointing-error panel.
    t_from : float, s

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from adcskit.simulation import GuidanceSpec, Scenario, SimSpec, simulate
    >>> from adcskit.simulation.envelopes import attitude_error_figure
    >>> sc = Scenario(guidance=GuidanceSpec(kind="step", target_rotvec_deg=(1.0, 0.0, 0.0)),
    ...               sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0))
    >>> fig = attitude_error_figure(simulate(sc, n_samples=5, rng=1, record=True), axes=True)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['pointing error [deg]', 'error about x [deg]', 'error about y [deg]', 'error about z [deg]']
    """
    res = _check_result(result)
    axes = check_flag("axes", axes)
    if not axes:
        return envelope_figure(res, "pointing_error", label="pointing error", worst=worst, worst_by=worst_by,
                               yscale=yscale, t_from=t_from)
    worst = check_int("worst", worst, minimum=0)
    t_from = check_finite("t_from", t_from)
    check_choice("yscale", yscale, ("linear", "log", "symlog"))
    return _panels(res, [("pointing_error", "pointing error", yscale), ("err_x", "error about x", "linear"),
                         ("err_y", "error about y", "linear"), ("err_z", "error about z", "linear")],
                   "deg", DEG_PER_RAD, worst, worst_by, t_from, "attitude error")


def body_rate_figure(result: SimulationResult, *, worst: int = 3, worst_by: str = "max_rate_deg_s",
                     t_from: Any = 0.0) -> Any:
    """Envelopes of the body rates about x, y and z (deg/s), one panel each.

    Parameters
    ----------
    result : SimulationResult
        With traces.
    worst : int
        Worst samples to draw.
    worst_by : str
        Metric ranking them (default ``max_rate_deg_s``: largest rate magnitude over the run)
        or ``"peak"`` (largest ``|omega_x|`` ...: ranked on the x panel's channel for all).
    t_from : float, s

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from adcskit.simulation import Scenario, SimSpec, simulate
    >>> from adcskit.simulation.envelopes import body_rate_figure
    >>> fig = body_rate_figure(simulate(Scenario(sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0)),
    ...                                 n_samples=5, rng=1, record=True))
    >>> fig.axes[0].get_ylabel()
    'rate about x [deg/s]'
    """
    res = _check_result(result)
    worst = check_int("worst", worst, minimum=0)
    t_from = check_finite("t_from", t_from)
    return _panels(res, [("omega_x", "rate about x", "linear"), ("omega_y", "rate about y", "linear"),
                         ("omega_z", "rate about z", "linear")], "deg/s", DEG_PER_RAD, worst, worst_by, t_from,
                   "body rates")


def _panels(res: SimulationResult, panels: list[tuple[str, str, str]], units: str, s: float, worst: int,
            worst_by: str, t_from: float, title: str) -> Any:
    from matplotlib.figure import Figure

    t = np.asarray(res.t, dtype=float)
    keep = t >= t_from
    if not np.any(keep):
        raise InputError(f"t_from must be at most the last recorded time {t[-1]:g} s; got {t_from:g} s")
    idx = _worst(res, worst, worst_by, panels[0][0], True, "worst_by")
    fig = Figure(figsize=(7.0, 1.0 + 2.4 * len(panels)), layout="constrained")
    axs = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    for ax, (ch, lab, ysc) in zip(axs, panels):
        vals, _ = _channel_values(res, ch)
        v = vals[:, keep, 0] * s
        _draw(ax, envelope(v, t[keep]), v, idx, worst_by, ysc)
        ax.set_ylabel(f"{lab} [{units}]")
    axs[-1].set_xlabel("time [s]")
    _legend(fig, axs[0])
    fig.suptitle(f"{title}: median, 5-95 % and 1-99 % of n = {res.n_samples} samples", fontsize="medium")
    return fig
