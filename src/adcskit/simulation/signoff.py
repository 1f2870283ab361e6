"""A requirement table checked on a simulation result: met, not met or inconclusive.

:func:`check_simulation` applies :func:`adcskit.uncertainty.check_requirements` (one line per
requirement, e.g. ``pointing_max_deg p99 <= 0.1 after 300 s``; grammar in
:func:`adcskit.uncertainty.parse_requirement`) to the per-sample metrics of a
:class:`~adcskit.simulation.SimulationResult` and adds, per row, where the values came from
and the fewest samples that could demonstrate the requirement at all.

Time windows (``after T s``). The simulator computes its pointing metrics
(``pointing_mean_deg``, ``pointing_rms_deg``, ``pointing_max_deg``, ``pointing_rms_x_deg``
...) and ``knowledge_rms_deg`` at every step over ``[SimSpec.metrics_from_s, t_final]``. A
requirement's ``after T s`` is answered

* from the metric itself when ``T`` equals the scenario's ``metrics_from_s`` (exact);
* otherwise from the recorded traces (``simulate(..., record=True)``) for the pointing
  metrics and ``max_rate_deg_s`` (largest body-rate magnitude), over the recorded times
  ``t >= T``. With ``SimSpec.record_every = 1`` the trace holds every step and the values
  equal the kernel's definitions (tested); with ``record_every > 1`` they are computed from
  one point every ``record_every`` steps — a mean or RMS is then a sampled estimate and a
  maximum can miss a peak between two points (optimistic for a ``<=`` requirement), so the
  row's source says "decimated" and the table's ``exact`` is False;
* never for the other metrics (settling time, propellant, NEES, ``knowledge_rms_deg`` whose
  trace is recorded at other instants than the kernel's window): an
  :class:`~adcskit.errors.InputError` says to re-run with ``metrics_from_s = T``.

A requirement without ``after`` uses the metric as the simulator computed it (pointing
metrics over the scenario's window). NaN values (``settling_time_s`` of a sample that never
settled) count as violating by default (``nan_policy="fail"``), which is what a sign-off
needs.

"Samples for a bound" (``n_for_bound``): the fewest samples for which the row's confidence
bound can meet its threshold at all, i.e. with no violating sample — Wilks' number
(:func:`adcskit.uncertainty.samples_needed`): 59 for a p95 at 95 %, 299 for a p99 at 95 %,
459 for a p99 at 99 %; for ``P(event) <= q`` at confidence ``c`` the same number with
coverage ``1 - q``. ``None`` for ``max``/``min`` (judged on every sample, any ``n``) and
``mean`` (depends on the spread). An inconclusive row also carries ``n_needed``, the samples
that would decide it if the observed rate held.

References
----------
Wilks 1941; Guba, Makai & Pál 2003, Table 1; Conover 1999, §3.2 (see
:mod:`adcskit.uncertainty.requirements`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from adcskit._results import Result
from adcskit._validation import check_choice
from adcskit.constants import DEG_PER_RAD
from adcskit.errors import InputError, InputTypeError
from adcskit.simulation.core import SimulationResult
from adcskit.simulation.scenario import Scenario
from adcskit.uncertainty.requirements import (
    Requirement,
    RequirementTable,
    RequirementVerdict,
    check_requirements,
    read_requirements,
    samples_needed,
)

__all__ = ["WINDOWED_METRICS", "TRACE_METRICS", "SignOffTable", "check_simulation"]

#: Metrics the simulator computes over ``[metrics_from_s, t_final]``.
WINDOWED_METRICS = ("pointing_mean_deg", "pointing_rms_deg", "pointing_max_deg", "pointing_rms_x_deg",
                    "pointing_rms_y_deg", "pointing_rms_z_deg", "knowledge_rms_deg")
#: Metrics that :func:`check_simulation` can re-window from the recorded traces.
TRACE_METRICS = ("pointing_mean_deg", "pointing_rms_deg", "pointing_max_deg", "pointing_rms_x_deg",
                 "pointing_rms_y_deg", "pointing_rms_z_deg", "max_rate_deg_s")


@dataclass(frozen=True, slots=True, kw_only=True)
class SignOffTable(Result):
    """A requirement table checked on a simulation result (:func:`check_simulation`).

    Attributes
    ----------
    table : RequirementTable
        The verdicts (:func:`adcskit.uncertainty.check_requirements`), one row per requirement.
    sources : tuple of str
        Per row: where the values came from (the simulator's metric and its window, or the
        traces, decimated or not).
    n_for_bound : tuple of (int or None)
        Per row: fewest samples that could demonstrate the requirement (no violating sample;
        Wilks), ``None`` for ``max``/``min``/``mean`` rows.
    exact : bool
        Every row's values follow the simulator's per-step definitions (no decimated trace).
    success : bool
        Every requirement met, on exact values (``exact``): a table with rows from decimated
        traces is never signed off, whatever its verdicts.
    message : str

    Examples
    --------
    >>> from adcskit.simulation import Scenario, SimSpec, simulate
    >>> from adcskit.simulation.signoff import check_simulation
    >>> sc = Scenario(sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0))
    >>> t = check_simulation(["pointing_max_deg p95 <= 1 after 1 s"], simulate(sc, n_samples=8, rng=1), sc)
    >>> t.table.rows[0].verdict, t.n_for_bound
    ('inconclusive (need ~59 samples)', (59,))
    """

    table: RequirementTable
    sources: tuple[str, ...]
    n_for_bound: tuple[int | None, ...]
    exact: bool
    success: bool
    message: str

    @property
    def rows(self) -> tuple[RequirementVerdict, ...]:
        """The verdicts (``table.rows``)."""
        return self.table.rows

    def table_rows(self) -> list[dict[str, Any]]:
        """One flat mapping per requirement (for a report table or a CSV file)."""
        out = []
        for row, src, nb in zip(self.table.rows, self.sources, self.n_for_bound):
            d = row.table_row()
            conf = row.requirement.confidence
            d.update({"confidence": conf, "n_needed": row.n_needed, "n_for_bound": nb, "source": src})
            out.append(d)
        return out

    def to_markdown(self) -> str:
        """The table as Markdown (one row per requirement, then the summary line).

        Examples
        --------
        >>> from adcskit.simulation import Scenario, SimSpec, simulate
        >>> from adcskit.simulation.signoff import check_simulation
        >>> sc = Scenario(sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0))
        >>> md = check_simulation(["R1: final_error_deg max <= 1"], simulate(sc, n_samples=4, rng=1), sc).to_markdown()
        >>> print(md.splitlines()[0])
        | id | requirement | n | estimate | bound | verdict | samples for a bound | values from |
        """
        head = "| id | requirement | n | estimate | bound | verdict | samples for a bound | values from |"
        lines = [head, "|" + "---|" * 8]
        for d in self.table_rows():
            lines.append("| " + " | ".join(_cells(d)) + " |")
        lines.append("")
        lines.append(self.message)
        return "\n".join(lines)

    def to_text(self) -> str:
        """The table as aligned plain text (for a terminal or a log).

        Examples
        --------
        >>> from adcskit.simulation import Scenario, SimSpec, simulate
        >>> from adcskit.simulation.signoff import check_simulation
        >>> sc = Scenario(sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0))
        >>> txt = check_simulation(["final_error_deg max <= 1"], simulate(sc, n_samples=4, rng=1), sc).to_text()
        >>> txt.splitlines()[0].split()[:3]
        ['id', 'requirement', 'n']
        """
        hdr = ["id", "requirement", "n", "estimate", "bound", "verdict", "samples for a bound", "values from"]
        body = [_cells(d) for d in self.table_rows()]
        width = [max(len(r[j]) for r in [hdr, *body]) for j in range(len(hdr))]
        fmt = "  ".join(f"{{:{w}}}" for w in width)
        lines = [fmt.format(*hdr), fmt.format(*("-" * w for w in width))]
        lines += [fmt.format(*r).rstrip() for r in body]
        return "\n".join(lines + ["", self.message])


def _num(x: Any) -> str:
    if x is None:
        return "-"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    return "inf" if x == math.inf else ("-inf" if x == -math.inf else ("nan" if x != x else f"{x:.4g}"))


def _cells(d: dict[str, Any]) -> list[str]:
    return [d["name"] or "-", d["requirement"], _num(d["n"]), _num(d["estimate"]), _num(d["bound"]), d["verdict"],
            _num(d["n_for_bound"]), d["source"]]


def _n_for_bound(req: Requirement) -> int | None:
    """Fewest samples for which the requirement's bound can meet its threshold (no violation)."""
    c = req.confidence
    if req.statistic == "percentile":
        cov = req.percentile / 100.0 if req.comparison in ("<=", "<") else 1.0 - req.percentile / 100.0
        return samples_needed(cov, c)
    if req.statistic == "probability":
        q = req.threshold
        cov = 1.0 - q if req.comparison in ("<=", "<") else q
        if not 0.0 < cov < 1.0:
            return None
        return samples_needed(cov, c)
    return None


def _from_trace(res: SimulationResult, scenario: Scenario, metric: str, after_s: float) -> tuple[np.ndarray, str, bool]:
    sim = scenario.sim
    if res.trace is None or res.t is None:
        raise InputError(
            f"metric {metric!r} after {after_s:g} s needs the traces (the simulator's window starts at "
            f"{sim.metrics_from_s:g} s): run simulate(..., record=True), or re-run with metrics_from_s = {after_s:g}")
    rec = int(sim.record_every)
    n_rec = res.trace.shape[1]
    kk = np.arange(n_rec) * rec                       # step index of each recorded point
    k_win = int(math.ceil(after_s / sim.dt - 1e-9))   # the kernel's first step of a window (core: K_WIN)
    keep = (kk >= max(k_win, 1))
    if not np.any(keep):
        raise InputError(f"after_s must be at most t_final = {sim.t_final:g} s for metric {metric!r}; got {after_s:g} s")
    ch = {c: i for i, c in enumerate(res.channels)}
    tr = np.asarray(res.trace, dtype=float)[:, keep, :]
    if metric == "max_rate_deg_s":
        w = np.sqrt(sum(tr[:, :, ch[c]] ** 2 for c in ("omega_x", "omega_y", "omega_z")))
        v = np.max(w, axis=1) * DEG_PER_RAD
    else:
        comp = {"pointing_rms_x_deg": "err_x", "pointing_rms_y_deg": "err_y", "pointing_rms_z_deg": "err_z"}
        e = tr[:, :, ch[comp.get(metric, "pointing_error")]]
        if metric == "pointing_mean_deg":
            v = np.mean(e, axis=1)
        elif metric == "pointing_max_deg":
            v = np.max(e, axis=1)
        else:
            v = np.sqrt(np.mean(e * e, axis=1))
        v = v * DEG_PER_RAD
    t_first = kk[keep][0] * sim.dt
    if rec == 1:
        src = f"trace, every step over [{t_first:g}, {sim.t_final:g}] s"
    else:
        src = (f"trace decimated: 1 point every {rec * sim.dt:g} s over [{t_first:g}, {sim.t_final:g}] s "
               "(sampled; a maximum can miss peaks)")
    return v, src, rec == 1


def check_simulation(
    requirements: Any,
    result: SimulationResult,
    scenario: Scenario,
    *,
    confidence: Any = 0.95,
    method: str = "clopper-pearson",
    nan_policy: str = "fail",
) -> SignOffTable:
    """Check a requirement table on the per-sample metrics of a simulation.

    Parameters
    ----------
    requirements : str, os.PathLike, mapping or iterable
        Anything :func:`adcskit.uncertainty.read_requirements` reads: one-line strings such
        as ``"ADCS-1: pointing_max_deg p99 <= 0.1 after 300 s"``, a TOML file of
        ``[[requirement]]`` entries, :class:`~adcskit.uncertainty.Requirement` objects.
    result : SimulationResult
        From :func:`adcskit.simulation.simulate` (``record=True`` when a requirement's window
        differs from the scenario's ``metrics_from_s``).
    scenario : Scenario
        The scenario that produced ``result`` (its metrics window, step and trace decimation).
    confidence : float
        Confidence of the rows that do not state theirs (``at C %``), in [0.5, 1).
    method : {"clopper-pearson", "wilson"}
        Interval of ``P(...)`` rows.
    nan_policy : {"fail", "raise"}
        A NaN metric (a sample that never settled) counts as violating (default) or raises.

    Returns
    -------
    SignOffTable
        Verdicts with their confidence bounds, sources, samples for a bound; ``to_markdown()``
        and ``to_text()`` render it.

    Raises
    ------
    InputError
        An unknown metric (the message lists the available ones); an ``after`` window that
        neither the metric nor the traces can answer (see the module notes).

    Examples
    --------
    >>> from adcskit.simulation import GuidanceSpec, Scenario, SimSpec, simulate
    >>> from adcskit.simulation.signoff import check_simulation
    >>> sc = Scenario(guidance=GuidanceSpec(kind="step", target_rotvec_deg=(0.5, 0.0, 0.0)),
    ...               sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0, record_every=1))
    >>> res = simulate(sc, n_samples=60, rng=2, record=True)
    >>> t = check_simulation(["A: pointing_max_deg p95 <= 1 after 1.5 s", "B: P(final_error_deg > 2) <= 5 %",
    ...                       "C: settling_time_s max <= 0.1"], res, sc)
    >>> [r.outcome for r in t.rows], t.n_for_bound, t.exact
    (['met', 'met', 'not met'], (59, 59, None), True)
    >>> t.sources[0]
    'trace, every step over [1.5, 2] s'
    """
    if not isinstance(result, SimulationResult):
        raise InputTypeError(f"result must be a SimulationResult (from adcskit.simulation.simulate); "
                             f"got {type(result).__name__}")
    if not isinstance(scenario, Scenario):
        raise InputTypeError(f"scenario must be the Scenario that produced result; got {type(scenario).__name__}")
    reqs = read_requirements(requirements, confidence=confidence)
    check_choice("method", method, ("clopper-pearson", "wilson"))
    check_choice("nan_policy", nan_policy, ("fail", "raise"))
    sim = scenario.sim
    rows: list[RequirementVerdict] = []
    sources: list[str] = []
    exact = True
    for req in reqs:
        check_choice(f"metric of requirement {req.text!r}", req.metric, sorted(result.metrics))
        window = sim.metrics_from_s
        if req.metric in WINDOWED_METRICS:
            src = f"metric, every step over [{window:g}, {sim.t_final:g}] s"
        else:
            src = "metric (whole run)" if req.metric != "final_error_deg" else f"metric at t_final = {sim.t_final:g} s"
        values = np.asarray(result.metrics[req.metric], dtype=float)
        if req.after_s is not None and not (req.metric in WINDOWED_METRICS
                                            and math.isclose(req.after_s, window, rel_tol=1e-9, abs_tol=1e-9)):
            if req.metric not in TRACE_METRICS:
                raise InputError(
                    f"requirement {req.text!r}: metric {req.metric!r} cannot be re-windowed to [{req.after_s:g}, end] s "
                    f"(from the traces: {', '.join(TRACE_METRICS)}); re-run with SimSpec(metrics_from_s="
                    f"{req.after_s:g}) or drop 'after'")
            try:
                values, src, ok = _from_trace(result, scenario, req.metric, req.after_s)
            except InputError as exc:
                raise InputError(f"requirement {req.text!r}: {exc}") from None
            exact = exact and ok
        window_arg = req.after_s if req.after_s is not None else None
        one = check_requirements([req], {req.metric: values}, metrics_from_s=window_arg, method=method,
                                 nan_policy=nan_policy)
        rows.append(one.rows[0])
        sources.append(src)
    n_met = sum(r.outcome == "met" for r in rows)
    n_not = sum(r.outcome == "not met" for r in rows)
    n_inc = len(rows) - n_met - n_not
    msg = f"{n_met} met, {n_not} not met, {n_inc} inconclusive of {len(rows)} requirements ({result.n_samples} samples)"
    if not exact:
        msg += ("; some rows from decimated traces (record_every > 1) are approximate: not signed off "
                "(re-run with record_every = 1 or metrics_from_s = after)")
    table = RequirementTable(rows=tuple(rows), n_met=n_met, n_not_met=n_not, n_inconclusive=n_inc,
                             success=n_met == len(rows), message=msg)
    return SignOffTable(table=table, sources=tuple(sources), n_for_bound=tuple(_n_for_bound(r) for r in reqs),
                        exact=exact, success=table.success and exact, message=msg)
