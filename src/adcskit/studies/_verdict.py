"""The verdict model: the paper's claims, decided over seeds and readings.

A study reports three kinds of statement (``docs/architecture.md``, "The verdict rule"):

* **claims** — the paper's own statements, in the paper's words, with where they are
  (section / table / figure) and the quantity that decides them;
* **checks** — our consistency tests (:class:`adcskit.studies.Check`, pass / fail);
* **findings** — our own questions (baselines the paper omits, closed-loop answers), decided
  like claims but counted apart.

A claim or finding has exactly one of four outcomes (:data:`OUTCOMES`):

``"holds"``
    every independent seed supports it and, where a deciding quantity has a threshold, the
    confidence interval of its mean lies entirely on the supporting side;
``"does not hold"``
    the mirror image: no seed supports it and the interval lies on the other side;
``"inconclusive"``
    the evidence does not separate the two: seeds disagree, the interval straddles the
    threshold, a seed failed (non-finite value), a deterministic value lies within its
    declared equivalence margin of the threshold (a tie), a stochastic claim was run on a
    single seed ("a single-seed pass is not holds"), or one reading is decided while the
    others are inconclusive;
``"depends on reading"``
    at least one documented reading of an ambiguity of the paper holds and at least one does
    not hold; every reading is listed with its own outcome.

The rule is symmetric: nothing rescues a claim that nothing could also sink. A stochastic
outcome on fewer than :data:`MIN_SEEDS` seeds is *indicative* (``Claim.indicative``) and never
"comparable" with the paper; the runner also marks a claim whose protocol keys differ from the
paper's printed values as ``"reduced protocol"`` (``Claim.protocol``).

A study module declares its claims as :class:`ClaimSpec` objects (statement, location,
deciding quantity, threshold) and hands per-seed measurements, keyed by reading, to
:meth:`ClaimSpec.evaluate`; the verdict strings are never written by hand.

Example
-------
>>> spec = ClaimSpec(id="faster", statement="A is faster than B", where="Table 1",
...                  quantity="time ratio B/A", value=lambda m: m["ratio"], threshold=1.0)
>>> runs = {"default": [{"ratio": r} for r in (3.1, 2.9, 3.4, 3.0, 3.2)]}
>>> spec.evaluate(runs).outcome
'holds'
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from adcskit._results import to_jsonable
from adcskit._validation import (
    as_array,
    check_callable,
    check_choice,
    check_finite,
    check_flag,
    check_mapping,
    check_range,
)
from adcskit.errors import InputError

__all__ = [
    "OUTCOMES",
    "HOLDS",
    "DOES_NOT_HOLD",
    "INCONCLUSIVE",
    "DEPENDS_ON_READING",
    "MIN_SEEDS",
    "PAPER_PROTOCOL",
    "REDUCED_PROTOCOL",
    "CUSTOM_SETTINGS",
    "PROTOCOLS",
    "Reading",
    "Claim",
    "Finding",
    "ClaimSpec",
    "FindingSpec",
    "decide",
    "combine_readings",
    "mean_interval",
    "wilson_interval",
    "tally",
]

HOLDS = "holds"
DOES_NOT_HOLD = "does not hold"
INCONCLUSIVE = "inconclusive"
DEPENDS_ON_READING = "depends on reading"
OUTCOMES = (HOLDS, DOES_NOT_HOLD, INCONCLUSIVE, DEPENDS_ON_READING)

#: Seeds a stochastic verdict needs at full settings (issue: "at least 5 independent seeds").
MIN_SEEDS = 5

#: ``Claim.protocol`` values: decided at the paper's protocol, below it (our defaults or the
#: quick overrides differ from a value the paper prints), or under a user's custom settings.
PAPER_PROTOCOL = "paper protocol"
REDUCED_PROTOCOL = "reduced protocol"
CUSTOM_SETTINGS = "custom settings"
PROTOCOLS = (PAPER_PROTOCOL, REDUCED_PROTOCOL, CUSTOM_SETTINGS)


def _finite_or_none(x: float) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def wilson_interval(k: int, n: int, confidence: float = 0.95) -> tuple[float, float]:
    """Wilson score interval of a binomial fraction ``k / n``.

    >>> tuple(round(v, 3) for v in wilson_interval(5, 5))
    (0.566, 1.0)
    """
    from scipy.stats import norm

    if n <= 0:
        return (0.0, 1.0)
    z = float(norm.ppf(0.5 + confidence / 2))
    p = k / n
    den = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return (max(0.0, centre - half), min(1.0, centre + half))


def mean_interval(values: Sequence[float], confidence: float = 0.95) -> tuple[float, float]:
    """Student-t confidence interval of the mean of ``values`` (independent seeds).

    With one value the interval is that value (a width cannot be estimated); non-finite
    values are dropped.

    >>> lo, hi = mean_interval([1.0, 2.0, 3.0])
    >>> round(lo, 3), round(hi, 3)
    (-0.484, 4.484)
    """
    from scipy.stats import t as student_t

    v = np.asarray([x for x in values if x is not None and math.isfinite(float(x))], dtype=float)
    if v.size == 0:
        return (math.nan, math.nan)
    scale = float(np.max(np.abs(v))) or 1.0  # in units of the largest value: no overflow
    v = v / scale
    m = float(v.mean())
    if v.size == 1:
        return (m * scale, m * scale)
    se = float(v.std(ddof=1)) / math.sqrt(v.size)
    h = float(student_t.ppf(0.5 + confidence / 2, v.size - 1)) * se
    return ((m - h) * scale, (m + h) * scale)


@dataclass(frozen=True, slots=True, kw_only=True)
class Reading:
    """The outcome of a claim under one reading of the paper (or the only reading).

    Attributes
    ----------
    reading : str
        Name of the reading (e.g. ``"variance ratio"``); ``"default"`` when unambiguous.
    outcome : str
        One of :data:`OUTCOMES` (never ``"depends on reading"``).
    n_seeds : int
        Independent repetitions behind the outcome.
    fraction_held : float
        Fraction of seeds that supported the claim.
    interval : (float, float)
        95 % interval: of the deciding quantity's mean when the claim has one, else the
        Wilson interval of ``fraction_held``.
    values : tuple of float
        The deciding quantity per seed (empty for a yes/no claim).
    detail : str
        How the outcome was reached.

    Examples
    --------
    >>> r = decide([True, True, True], reading="variance ratio")
    >>> r.reading, r.outcome, r.n_seeds
    ('variance ratio', 'holds', 3)
    """

    reading: str
    outcome: str
    n_seeds: int
    fraction_held: float
    interval: tuple[float, float]
    values: tuple[float, ...] = ()
    detail: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {
            "reading": self.reading,
            "outcome": self.outcome,
            "n_seeds": int(self.n_seeds),
            "fraction_held": _finite_or_none(self.fraction_held),
            "interval": [_finite_or_none(self.interval[0]), _finite_or_none(self.interval[1])],
            "values": [_finite_or_none(v) for v in self.values],
            "detail": self.detail,
        }


@dataclass(frozen=True, slots=True, kw_only=True)
class Claim:
    """A verdict on one of the paper's claims (``result.json`` → ``claims``).

    Attributes
    ----------
    id : str
        Short stable identifier.
    statement : str
        The paper's words (translated where needed).
    where : str
        Section / table / figure of the paper.
    quantity : str
        What decides the claim, with its threshold.
    outcome : str
        One of :data:`OUTCOMES`.
    n_seeds, fraction_held, interval
        Of the default reading (see :class:`Reading`).
    readings : tuple of Reading
        One entry per documented reading; empty when the claim has no ambiguity.
    detail : str
        The evidence in words and numbers.
    paper, measured
        The paper's value of the deciding quantity and ours (mean over seeds, default
        reading), where they exist.
    unit : str
    comparable : bool
        True only when the claim was decided at the paper's protocol (:attr:`protocol` is
        ``"paper protocol"``) on enough seeds (not :attr:`indicative`): only then is the
        outcome a verdict on the paper. Set by the runner.
    protocol_keys : tuple of str or None
        Config keys that define the paper's protocol for this claim (None: any key).
    indicative : bool
        A stochastic claim decided on fewer than :data:`MIN_SEEDS` seeds (a quick run).
    protocol : str
        ``"paper protocol"``, ``"reduced protocol"`` (a protocol key differs from the paper's
        printed value: our defaults or the quick overrides) or ``"custom settings"`` (the
        user changed a protocol key). Set by the runner.
    protocol_differences : tuple of str
        What differs from the paper's protocol, one ``"key: ours X, paper Y"`` per key.
    margin, margin_reason
        The equivalence margin of a deterministic comparison and why (empty when none).
    timing : bool
        The deciding quantity is a measured time (compared with a snapshot by outcome only).

    Examples
    --------
    >>> c = Claim(id="c1", statement="A is faster than B", where="Table 1", outcome="holds", n_seeds=5, fraction_held=1.0)
    >>> c.to_dict()["outcome"], c.display_outcome
    ('holds', 'holds')
    """

    id: str
    statement: str
    where: str = ""
    quantity: str = ""
    outcome: str
    n_seeds: int = 1
    fraction_held: float = math.nan
    interval: tuple[float, float] = (math.nan, math.nan)
    readings: tuple[Reading, ...] = ()
    detail: str = ""
    paper: Any = None
    measured: Any = None
    unit: str = ""
    comparable: bool = True
    protocol_keys: tuple[str, ...] | None = None
    indicative: bool = False
    protocol: str = PAPER_PROTOCOL
    protocol_differences: tuple[str, ...] = ()
    margin: float = 0.0
    margin_reason: str = ""
    timing: bool = False

    def __post_init__(self) -> None:
        check_choice("outcome", self.outcome, OUTCOMES)
        check_choice("protocol", self.protocol, PROTOCOLS)
        object.__setattr__(self, "readings", tuple(self.readings))
        object.__setattr__(self, "protocol_differences", tuple(self.protocol_differences))
        object.__setattr__(self, "interval", (float(self.interval[0]), float(self.interval[1])))

    @property
    def display_outcome(self) -> str:
        """The outcome as the report shows it.

        ``"indicative (2 seeds)"`` below :data:`MIN_SEEDS` seeds, ``"not comparable"`` under
        custom settings, the outcome followed by ``" (reduced protocol)"`` below the paper's
        protocol, else the outcome.
        """
        if self.indicative:
            return f"indicative ({self.n_seeds} seed{'s' if self.n_seeds != 1 else ''})"
        if self.protocol == CUSTOM_SETTINGS:
            return "not comparable"
        if self.protocol == REDUCED_PROTOCOL:
            return f"{self.outcome} (reduced protocol)"
        return self.outcome

    def to_dict(self) -> dict[str, Any]:
        return {
            "id": self.id,
            "statement": self.statement,
            "where": self.where,
            "quantity": self.quantity,
            "outcome": self.outcome,
            "n_seeds": int(self.n_seeds),
            "fraction_held": _finite_or_none(self.fraction_held),
            "interval": [_finite_or_none(self.interval[0]), _finite_or_none(self.interval[1])],
            "readings": [r.to_dict() for r in self.readings],
            "detail": self.detail,
            "paper": to_jsonable(self.paper),
            "measured": to_jsonable(self.measured),
            "unit": self.unit,
            "comparable": bool(self.comparable),
            "protocol_keys": None if self.protocol_keys is None else list(self.protocol_keys),
            "indicative": bool(self.indicative),
            "protocol": self.protocol,
            "protocol_differences": list(self.protocol_differences),
            "display_outcome": self.display_outcome,
            "margin": _finite_or_none(self.margin) if self.margin else None,
            "margin_reason": self.margin_reason,
            "timing": bool(self.timing),
        }


@dataclass(frozen=True, slots=True, kw_only=True)
class Finding(Claim):
    """A verdict on one of *our* questions (``result.json`` → ``findings``).

    Same fields as :class:`Claim`; ``statement`` is our question or hypothesis, ``where``
    is usually empty and ``paper`` None. Findings are never counted as the paper's claims.

    Examples
    --------
    >>> Finding(id="f1", statement="our baseline beats the paper's", outcome="inconclusive").to_dict()["where"]
    ''
    """


def decide(
    held: Sequence[bool] | None = None,
    *,
    values: Sequence[float] | None = None,
    threshold: float | None = None,
    better: str = "above",
    stochastic: bool = True,
    reading: str = "default",
    confidence: float = 0.95,
    margin: float = 0.0,
) -> Reading:
    """Outcome of one reading from per-seed results.

    Either give ``held`` (one bool per seed) or ``values`` with ``threshold`` (a seed holds
    when its value is above, or below for ``better="below"``, the threshold by more than
    ``margin``), never both: an extra pass/fail condition must not contradict the interval, so
    it is its own reading or check.

    Rules, symmetric for "holds" and "does not hold":

    * no seeds, or a stochastic claim on a single seed: ``inconclusive``;
    * any non-finite value (a failed seed): ``inconclusive``, with the count;
    * a value within ``margin`` of the threshold is a tie (``inconclusive``): the declared
      equivalence margin of a deterministic comparison (a grid's resolution, a solver's
      repeatability);
    * seeds that disagree: ``inconclusive``;
    * unanimous seeds: ``holds`` / ``does not hold``, unless with a threshold and two or more
      seeds the ``confidence`` interval of the mean reaches into ``threshold ± margin``
      (then ``inconclusive``).

    >>> decide([True, True, False, True, True]).outcome
    'inconclusive'
    >>> decide(values=[0.9, 1.2, 1.1], threshold=1.0).outcome
    'inconclusive'
    >>> decide(values=[0.2, 0.3, 0.25], threshold=1.0).outcome
    'does not hold'
    >>> decide(values=[4.56], threshold=4.54, stochastic=False, margin=0.05).outcome
    'inconclusive'
    """
    check_choice("better", better, ("above", "below"))
    stochastic = check_flag("stochastic", stochastic)
    confidence = check_range("confidence", confidence, 0.0, 1.0, lo_open=True, hi_open=True)
    margin = check_range("margin", margin, 0.0, math.inf)
    vals: tuple[float, ...] = ()
    n_failed = n_tied = 0
    if values is not None:
        if held is not None:
            raise InputError("decide: give held or values, not both (an extra condition is its own reading or check)")
        if threshold is None:
            raise InputError("decide: values need a threshold")
        threshold = check_finite("threshold", threshold, max_abs=None)
        # NaN / inf values are allowed: a failed seed, which makes the reading inconclusive
        vals = tuple(as_array("values", values, ndim=1, finite=False, nonempty=False, max_abs=None).tolist())
        sign = 1.0 if better == "above" else -1.0
        ok = []
        for v in vals:  # a seed supports, is against, ties (within the margin) or failed
            if not math.isfinite(v):
                n_failed += 1
                ok.append(False)
                continue
            d = sign * (v - threshold)
            ok.append(d > margin)
            n_tied += int(-margin <= d <= margin)
    elif held is not None:
        ok = [bool(h) for h in held]
    else:
        raise InputError("decide: give held or values")
    n = len(ok)
    k = sum(ok)
    frac = k / n if n else math.nan
    if vals:
        interval = mean_interval(vals, confidence)
    elif not stochastic:
        interval = (frac, frac)  # a deterministic computation: no sampling interval
    else:
        interval = wilson_interval(k, n, confidence)
    why = f"{k}/{n} seeds support it"
    if n == 0:
        outcome, why = INCONCLUSIVE, "no seeds"
    elif n_failed:
        outcome = INCONCLUSIVE
        why += f"; {n_failed}/{n} seeds failed (non-finite value): a failed seed decides nothing"
    elif stochastic and n < 2:
        outcome = INCONCLUSIVE
        why += "; a single seed cannot decide a stochastic claim"
    elif n_tied:
        outcome = INCONCLUSIVE
        why += (f"; {n_tied}/{n} within the equivalence margin ±{margin:.4g} of {threshold:.4g}: a tie")
    elif 0 < k < n:  # failed and tied seeds are handled above: every other seed is for or against
        outcome = INCONCLUSIVE
        why += "; seeds disagree"
    else:
        outcome = HOLDS if k == n else DOES_NOT_HOLD
        if vals and n >= 2 and threshold is not None and all(math.isfinite(x) for x in interval):
            lo, hi = interval
            if lo <= threshold + margin and hi >= threshold - margin:
                outcome = INCONCLUSIVE
                band = f"{threshold:.4g}" if margin == 0 else f"{threshold:.4g} ± {margin:.4g}"
                why += f"; the {confidence:.0%} interval of the mean [{lo:.4g}, {hi:.4g}] reaches {band}"
    if stochastic and 0 < n < MIN_SEEDS:
        why += f" (indicative: {n} < {MIN_SEEDS} seeds)"
    return Reading(reading=reading, outcome=outcome, n_seeds=n, fraction_held=frac, interval=interval, values=vals, detail=why)


def combine_readings(readings: Iterable[Reading]) -> str:
    """The claim's outcome over its readings, by a symmetric rule.

    * every reading agrees: that outcome;
    * at least one reading holds and at least one does not hold: ``depends on reading``;
    * otherwise (a decided outcome beside inconclusive readings, or none decided):
      ``inconclusive``; the per-reading outcomes are listed beside it.

    >>> r = lambda o: Reading(reading="x", outcome=o, n_seeds=5, fraction_held=1.0, interval=(0, 1))
    >>> combine_readings([r("holds"), r("holds")])
    'holds'
    >>> combine_readings([r("holds"), r("does not hold")])
    'depends on reading'
    >>> combine_readings([r("does not hold"), r("inconclusive")])
    'inconclusive'
    """
    outcomes = {r.outcome for r in readings}
    if not outcomes:
        return INCONCLUSIVE
    if len(outcomes) == 1:
        return outcomes.pop()
    if HOLDS in outcomes and DOES_NOT_HOLD in outcomes:
        return DEPENDS_ON_READING
    return INCONCLUSIVE


@dataclass(frozen=True, slots=True, kw_only=True)
class ClaimSpec:
    """Declarative definition of a claim; :meth:`evaluate` turns measurements into a :class:`Claim`.

    Parameters
    ----------
    id, statement, where, quantity, unit
        See :class:`Claim`.
    value : callable, optional
        ``value(measurement) -> float``: the deciding quantity of one seed's measurement
        (a mapping the study builds). With ``threshold`` and ``better`` it decides the seed.
    threshold : float, optional
    better : {"above", "below"}
        Which side of ``threshold`` supports the claim.
    held : callable, optional
        ``held(measurement) -> bool`` for a yes/no claim; never together with ``value`` (an
        extra condition would contradict the interval: make it its own reading or check).
    paper : any
        The paper's value of the deciding quantity.
    stochastic : bool
        False for a deterministic computation (one run decides it).
    readings : tuple of str
        The readings of an ambiguity that can move this claim; empty: only the default
        reading is used and ``Claim.readings`` is empty.
    protocol_keys : tuple of str or None
        Config keys that define the paper's protocol for this claim (None: every key).
    margin : float
        Equivalence margin around ``threshold`` (same unit as ``value``): a value within it is
        a tie (``inconclusive``). A deterministic comparison (``stochastic=False`` with a
        ``value``) must declare one with ``margin_reason`` (e.g. the grid's resolution), even
        when it is 0 (an exact count).
    margin_reason : str
        Why the margin has that size.
    timing : bool
        The deciding quantity is a measured time (CPU or wall): a re-run is compared with the
        page's snapshot by outcome only.

    Examples
    --------
    >>> spec = ClaimSpec(id="lower-rms", statement="min-max has a lower RMS error", where="Fig. 4",
    ...                  quantity="RMS ratio min-max / q-method", value=lambda m: m["ratio"],
    ...                  threshold=1.0, better="below")
    >>> spec.evaluate({"default": [{"ratio": r} for r in (0.8, 0.7, 0.75, 0.82, 0.78)]}).outcome
    'holds'
    """

    id: str
    statement: str
    where: str
    quantity: str
    value: Callable[[Mapping[str, Any]], float] | None = None
    threshold: float | None = None
    better: str = "above"
    held: Callable[[Mapping[str, Any]], bool] | None = None
    paper: Any = None
    unit: str = ""
    stochastic: bool = True
    readings: tuple[str, ...] = ()
    protocol_keys: tuple[str, ...] | None = None
    margin: float = 0.0
    margin_reason: str = ""
    timing: bool = False
    describe: Callable[[Reading], str] | None = field(default=None, repr=False)

    _cls = Claim

    def __post_init__(self) -> None:
        check_callable("value", self.value, allow_none=True)
        check_callable("held", self.held, allow_none=True)
        check_choice("better", self.better, ("above", "below"))
        check_flag("stochastic", self.stochastic)
        object.__setattr__(self, "timing", check_flag("timing", self.timing))
        object.__setattr__(self, "margin", check_range("margin", self.margin, 0.0, math.inf))
        if self.threshold is not None:
            object.__setattr__(self, "threshold", check_finite("threshold", self.threshold, max_abs=None))
        if self.value is not None and self.threshold is None:
            raise InputError(f"claim {self.id!r}: value needs a threshold")
        if self.value is not None and self.held is not None:
            raise InputError(f"claim {self.id!r}: give value or held, not both; an extra condition "
                             "must not contradict the interval: make it its own reading or check")
        if self.value is None and self.held is None:
            raise InputError(f"claim {self.id!r}: give value (with threshold) or held")
        if self.value is not None and not self.stochastic and not self.margin_reason.strip():
            raise InputError(f"claim {self.id!r}: a deterministic comparison declares its equivalence margin "
                             "(margin=..., margin_reason='why this size'; margin=0 needs a reason too)")

    def _reading(self, name: str, runs: Sequence[Mapping[str, Any]]) -> Reading:
        vals = [float(self.value(m)) for m in runs] if self.value is not None else None
        held = [bool(self.held(m)) for m in runs] if self.held is not None else None
        if vals is not None and self.threshold is None:
            raise ValueError(f"claim {self.id!r}: value needs a threshold")
        r = decide(held, values=vals, threshold=self.threshold, better=self.better, stochastic=self.stochastic,
                   reading=name, margin=self.margin)
        if self.describe is not None:
            from dataclasses import replace

            r = replace(r, detail=f"{self.describe(r)}; {r.detail}")
        return r

    def evaluate(self, runs: Mapping[str, Sequence[Mapping[str, Any]]], *, default: str = "default", detail: str = "") -> Claim:
        """Decide the claim from ``runs[reading] = [measurement of seed 0, seed 1, ...]``.

        ``runs`` must hold ``default`` and every name in :attr:`readings`.
        """
        check_mapping("runs", runs)
        names = list(dict.fromkeys([default, *self.readings])) if self.readings else [default]
        missing = [n for n in names if n not in runs]
        if missing:
            raise ValueError(f"claim {self.id!r}: no runs for readings {missing}; have {sorted(runs)}")
        unknown = [n for n in runs if n not in names]
        if unknown:  # a run under a reading the claim does not declare would be dropped silently
            raise InputError(f"runs has readings {unknown} that claim {self.id!r} does not declare; "
                             f"declared: {names}")
        per = [self._reading(n, runs[n]) for n in names]
        main = per[0]
        outcome = combine_readings(per)
        measured = float(np.mean(main.values)) if main.values else main.fraction_held
        text = detail or main.detail
        if len(per) > 1:
            text += " | readings: " + "; ".join(f"{r.reading}: {r.outcome}" for r in per)
        return self._cls(
            id=self.id,
            statement=self.statement,
            where=self.where,
            quantity=self.quantity,
            outcome=outcome,
            n_seeds=main.n_seeds,
            fraction_held=main.fraction_held,
            interval=main.interval,
            readings=tuple(per) if len(per) > 1 else (),
            detail=text,
            paper=self.paper,
            measured=measured,
            unit=self.unit,
            protocol_keys=self.protocol_keys,
            indicative=bool(self.stochastic and any(0 < r.n_seeds < MIN_SEEDS for r in per)),
            margin=self.margin,
            margin_reason=self.margin_reason,
            timing=self.timing,
        )


@dataclass(frozen=True, slots=True, kw_only=True)
class FindingSpec(ClaimSpec):
    """Declarative definition of a finding (our question); evaluates to a :class:`Finding`.

    Examples
    --------
    >>> spec = FindingSpec(id="f", statement="ours uses less fuel", quantity="fuel ratio",
    ...                    value=lambda m: m["r"], threshold=1.0, better="below")
    >>> type(spec.evaluate({"default": [{"r": 0.9}, {"r": 1.1}]})).__name__
    'Finding'
    """

    where: str = ""
    _cls = Finding


@dataclass(frozen=True, slots=True)
class Declared:
    """A claim or finding spec with its per-seed measurements keyed by reading: what a study's
    claim factory in ``claims.py`` returns, decided by :func:`decide_declared`."""

    spec: ClaimSpec
    runs: Mapping[str, Sequence[Any]]
    default: str = "default"


def decide_declared(factories: Sequence[Callable[[Any, Any], Any]], config: Any, measurements: Any) -> list:
    """Build each declared statement of a study and decide it.

    Each factory takes ``(config, measurements)`` and returns ``None`` (the configuration leaves
    the statement out), a :class:`Declared` (a claim or finding, decided by
    :meth:`ClaimSpec.evaluate` over its readings), an already computed check, or a list of
    these. The order of the result is the order of the factories.

    Examples
    --------
    >>> spec = FindingSpec(id="f", statement="s", quantity="q", value=lambda r: r, threshold=1.0,
    ...                    better="below")
    >>> [f.outcome for f in decide_declared([lambda c, m: Declared(spec, {"default": m}),
    ...                                      lambda c, m: None], None, [0.5] * 5)]
    ['holds']
    """
    out = []
    for make in factories:
        made = make(config, measurements)
        for d in made if isinstance(made, list | tuple) else (made,):
            if isinstance(d, Declared):
                out.append(d.spec.evaluate(d.runs, default=d.default))
            elif d is not None:
                out.append(d)
    return out


def tally(outcomes: Iterable[str]) -> dict[str, int]:
    """Count outcomes in :data:`OUTCOMES` order (plus ``"not comparable"`` when present).

    >>> tally(["holds", "inconclusive", "holds"])
    {'holds': 2, 'does not hold': 0, 'inconclusive': 1, 'depends on reading': 0}
    """
    counts = {o: 0 for o in OUTCOMES}
    for o in outcomes:
        counts[o] = counts.get(o, 0) + 1
    return counts
