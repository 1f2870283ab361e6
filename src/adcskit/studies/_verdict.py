"""The verdict model: the paper's claims, decided over seeds and readings.

A study reports three kinds of statement (``docs/architecture.md``, "The verdict rule"):

* **claims** — the paper's own statements, in the paper's words, with where they are
  (section / table / figure) and the quantity that decides them;
* **checks** — our consistency tests (:class:`adcskit.studies.Check`, pass / fail);
* **findings** — our own questions (baselines the paper omits, closed-loop answers), decided
  like claims but counted apart.

A claim or finding has exactly one of four outcomes (:data:`OUTCOMES`):

``"holds"``
    the seeds support it beyond chance: every seed supports it, or (on :data:`MIN_SEEDS` or
    more seeds) the exact one-sided sign test rejects "the claim is as likely false as true" at
    ``1 - confidence`` (5 of 5 seeds, 9 of 10); where a deciding quantity has a threshold, a
    seed supports it when its value lies on the supporting side beyond the declared margin;
``"does not hold"``
    the mirror image, with the seeds against the claim;
``"inconclusive"``
    the evidence does not separate the two: too few seeds agree for the sign test, a seed
    failed (non-finite value), a declared *premise* of the reading failed on a seed (its value
    is not evidence for that reading, e.g. a fuel ratio at unequal torque), a value lies
    within its declared equivalence margin of the threshold (a tie), a stochastic claim was
    run on a single seed ("a single-seed pass is not holds"), or one reading is decided while
    the others are inconclusive;
``"depends on reading"``
    at least one documented reading of an ambiguity of the paper holds and at least one does
    not hold; every reading is listed with its own outcome.

The rule is **monotone**: moving any seed's value further to the supporting side never weakens
the outcome (the sign test counts seeds; a t-interval of the mean cannot be monotone, since
moving one supporting seed further out widens it: it is shown, on log ratios for ratios, where
its assumptions hold, and never decides). Ratios (``scale="log"``) are compared on log ratios,
so their margin is relative. The interval of a value claim is the sign test's own exact
interval of the median (one-sided bounds at ``confidence``): a claim holds exactly when that
interval lies beyond the threshold and its margin.

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
    "Premise",
    "Reading",
    "Claim",
    "Finding",
    "ClaimSpec",
    "FindingSpec",
    "decide",
    "combine_readings",
    "mean_interval",
    "median_interval",
    "sign_test_p",
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
        The deciding interval: the sign test's exact bounds of the deciding quantity's median
        (:func:`median_interval`, one-sided at 95 % each) when the claim has one, else the
        exact (Clopper-Pearson) bounds of ``fraction_held``.
    values : tuple of float
        The deciding quantity per seed (empty for a yes/no claim).
    detail : str
        How the outcome was reached.
    premise_failures : tuple of str
        One reason per seed whose declared premise failed (:class:`Premise`): such a reading
        is inconclusive.

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
    premise_failures: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return {
            "reading": self.reading,
            "outcome": self.outcome,
            "n_seeds": int(self.n_seeds),
            "fraction_held": _finite_or_none(self.fraction_held),
            "interval": [_finite_or_none(self.interval[0]), _finite_or_none(self.interval[1])],
            "values": [_finite_or_none(v) for v in self.values],
            "detail": self.detail,
            "premise_failures": list(self.premise_failures),
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


def sign_test_p(k: int, n: int) -> float:
    """Exact one-sided sign-test p-value: ``P(X >= k)`` for ``X ~ Binomial(n, 1/2)``.

    The chance that ``k`` or more of ``n`` independent seeds support a claim that is as likely
    false as true.

    >>> sign_test_p(5, 5), round(sign_test_p(9, 10), 4), sign_test_p(0, 3)
    (0.03125, 0.0107, 1.0)
    """
    if n <= 0 or k <= 0:
        return 1.0
    return float(sum(math.comb(n, j) for j in range(k, n + 1)) / 2.0**n)


def median_interval(values: Sequence[float], confidence: float = 0.95) -> tuple[float, float]:
    """Exact distribution-free bounds of the median: the sign test's interval.

    Order statistics ``(x_(r), x_(n+1-r))`` with the largest ``r`` such that each bound is a
    one-sided ``confidence`` bound (``P(Binomial(n, 1/2) <= r - 1) <= 1 - confidence``). A
    threshold lies below the lower bound exactly when the sign test says the values lie above
    it. Below 5 values no such ``r`` exists: the range (less coverage; such a result is
    indicative). Non-finite values are dropped.

    >>> median_interval([3.0, 1.0, 2.0, 5.0, 4.0])
    (1.0, 5.0)
    >>> median_interval(list(range(10)))
    (1.0, 8.0)
    """
    v = sorted(float(x) for x in values if x is not None and math.isfinite(float(x)))
    n = len(v)
    if n == 0:
        return (math.nan, math.nan)
    alpha = 1.0 - confidence
    r = 1
    while r < (n + 1) // 2 and 1.0 - sign_test_p(r + 1, n) <= alpha:  # P(X <= r) <= alpha
        r += 1
    return (v[r - 1], v[n - r])


def _t_note(vals: Sequence[float], threshold: float | None, confidence: float) -> str:
    """The t-interval of the mean, on log values when every value is positive, where its
    assumptions hold (>= 3 finite values, not all equal, Shapiro-Wilk does not reject
    normality at ``1 - confidence``); otherwise why it is not shown. Never decides."""
    v = np.asarray([x for x in vals if math.isfinite(x)], dtype=float)
    if v.size < 3 or np.ptp(v) <= 1e-9 * float(np.max(np.abs(v))):
        return ""
    log = bool(np.all(v > 0) and (threshold is None or threshold > 0))
    w = np.log(v) if log else v
    from scipy.stats import shapiro

    p = float(shapiro(w).pvalue)
    what = "geometric mean" if log else "mean"
    if p < 1.0 - confidence:
        return f"; no t-interval of the {what}: Shapiro-Wilk rejects normality (p = {p:.2g})"
    lo, hi = mean_interval(w.tolist(), confidence)
    if log:
        lo, hi = math.exp(lo), math.exp(hi)
    return f"; {confidence:.0%} t-interval of the {what} [{lo:.4g}, {hi:.4g}] (shown, not deciding)"


def _tally(values: Any, threshold: float | None, better: str, scale: str,
           margin: float) -> tuple[tuple[float, ...], list[bool], int, int, int]:
    """Per seed: supports, against, tie (within the margin) or failed. NaN / inf values are
    allowed (a failed seed, which makes the reading inconclusive)."""
    if threshold is None:
        raise InputError("decide: values need a threshold")
    threshold = check_finite("threshold", threshold, max_abs=None)
    if scale == "log" and threshold <= 0:
        raise InputError(f"decide: scale='log' needs a positive threshold (a ratio's); got {threshold}")
    vals = tuple(as_array("values", values, ndim=1, finite=False, nonempty=False, max_abs=None).tolist())
    sign = 1.0 if better == "above" else -1.0
    ok: list[bool] = []
    n_failed = n_tied = n_against = 0
    for v in vals:
        if not math.isfinite(v) or (scale == "log" and v <= 0):
            n_failed += 1
            ok.append(False)
            continue
        d = sign * (math.log(v / threshold) if scale == "log" else v - threshold)
        ok.append(d > margin)
        n_tied += int(-margin <= d <= margin)
        n_against += int(d < -margin)
    return vals, ok, n_failed, n_tied, n_against


def _interval(vals: tuple[float, ...], k: int, n: int, stochastic: bool, confidence: float) -> tuple[float, float]:
    """The sign test's interval of the median, or the exact Clopper-Pearson bounds of a fraction."""
    if vals:
        return median_interval(vals, confidence)
    if n == 0:
        return (0.0, 1.0)  # no seeds: nothing is known of the fraction
    frac = k / n
    if not stochastic:
        return (frac, frac)  # a deterministic computation: no sampling interval
    from scipy.stats import beta

    alpha = 1.0 - confidence
    return (float(beta.ppf(alpha, k, n - k + 1)) if k > 0 else 0.0,
            float(beta.ppf(confidence, k + 1, n - k)) if k < n else 1.0)


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
    scale: str = "linear",
    premise_failures: Sequence[str] = (),
) -> Reading:
    """Outcome of one reading from per-seed results.

    Either give ``held`` (one bool per seed) or ``values`` with ``threshold`` (a seed supports
    the claim when its value is above, or below for ``better="below"``, the threshold by more
    than ``margin``; with ``scale="log"`` the comparison is of ``log(value)`` with
    ``log(threshold)`` and ``margin`` is in log units: a relative margin), never both: an extra
    pass/fail condition is its own reading or check.

    Rules, symmetric for "holds" and "does not hold" and monotone (a seed moved further to the
    supporting side never weakens the outcome):

    * no seeds, or a stochastic claim on a single seed: ``inconclusive``;
    * any non-finite value (a failed seed; with ``scale="log"`` also a value <= 0):
      ``inconclusive``, with the count;
    * ``premise_failures`` (one reason per seed whose declared premise failed, see
      :class:`Premise`): ``inconclusive``, with the reasons: that seed's value is no evidence;
    * otherwise, with ``k`` seeds for and ``m`` against (a value within ``margin`` of the
      threshold is a tie, neither): ``holds`` when all ``n`` seeds support it or, on
      :data:`MIN_SEEDS` or more seeds of a stochastic claim, when the exact sign test rejects
      chance at ``1 - confidence`` (:func:`sign_test_p`); ``does not hold`` in the mirror
      case; else ``inconclusive``.

    The interval is :func:`median_interval` of the values (or the exact Clopper-Pearson
    bounds of the fraction for ``held``); the t-interval of the mean is described where its
    assumptions hold, never deciding.

    >>> decide([True, True, False, True, True]).outcome
    'inconclusive'
    >>> decide(values=[0.9, 1.2, 1.1], threshold=1.0).outcome
    'inconclusive'
    >>> decide(values=[0.2, 0.3, 0.25], threshold=1.0).outcome
    'does not hold'
    >>> decide(values=[4.56], threshold=4.54, stochastic=False, margin=0.05).outcome
    'inconclusive'
    >>> decide(values=[380.0, 520.0, 610.0, 450.0, 700.0], threshold=300.0, scale="log", margin=0.5).outcome
    'inconclusive'
    """
    check_choice("better", better, ("above", "below"))
    check_choice("scale", scale, ("linear", "log"))
    stochastic = check_flag("stochastic", stochastic)
    confidence = check_range("confidence", confidence, 0.0, 1.0, lo_open=True, hi_open=True)
    margin = check_range("margin", margin, 0.0, math.inf)
    premise_failures = tuple(str(x) for x in premise_failures)
    if values is not None:
        if held is not None:
            raise InputError("decide: give held or values, not both (an extra condition is its own reading or check)")
        vals, ok, n_failed, n_tied, n_against = _tally(values, threshold, better, scale, margin)
    elif held is not None:
        vals, n_failed, n_tied = (), 0, 0
        ok = [bool(h) for h in held]
        n_against = len(ok) - sum(ok)
    else:
        raise InputError("decide: give held or values")
    n = len(ok)
    k = sum(ok)
    frac = k / n if n else math.nan
    alpha = 1.0 - confidence
    interval = _interval(vals, k, n, stochastic, confidence)
    why = f"{k}/{n} seeds support it"
    if n_against and n_against < n:
        why += f", {n_against} against"
    if n_tied:
        unit = f"±{margin:.4g} in log ratio" if scale == "log" else f"±{margin:.4g}"
        why += f", {n_tied} within the equivalence margin {unit} of {threshold:.4g} (a tie)"

    def decided(count: int) -> bool:  # all seeds, or an exact sign test on enough seeds
        if count == n:
            return not stochastic or n >= 2
        return stochastic and n >= MIN_SEEDS and sign_test_p(count, n) <= alpha

    if n == 0:
        outcome, why = INCONCLUSIVE, "no seeds"
    elif n_failed:
        outcome = INCONCLUSIVE
        why += f"; {n_failed}/{n} seeds failed (non-finite value): a failed seed decides nothing"
    elif premise_failures:
        outcome = INCONCLUSIVE
        why += (f"; premise failed on {len(premise_failures)}/{n} seeds, whose values are no evidence for this "
                "reading: " + "; ".join(premise_failures))
    elif stochastic and n < 2:
        outcome = INCONCLUSIVE
        why += "; a single seed cannot decide a stochastic claim"
    elif decided(k):
        outcome = HOLDS
    elif decided(n_against):
        outcome = DOES_NOT_HOLD
    else:
        outcome = INCONCLUSIVE
        if stochastic and n >= MIN_SEEDS:
            why += f"; sign test p = {sign_test_p(max(k, n_against), n):.3g} > {alpha:.2g}: not decided"
        elif n_tied:
            why += ": not decided"
        else:
            why += "; seeds disagree"
    if outcome in (HOLDS, DOES_NOT_HOLD) and stochastic and n >= MIN_SEEDS and max(k, n_against) < n:
        why += f" (exact sign test p = {sign_test_p(max(k, n_against), n):.3g} <= {alpha:.2g})"
    if vals and stochastic and n >= 3:
        why += _t_note(vals, threshold, confidence)
    if stochastic and 0 < n < MIN_SEEDS:
        why += f" (indicative: {n} < {MIN_SEEDS} seeds)"
    return Reading(reading=reading, outcome=outcome, n_seeds=n, fraction_held=frac, interval=interval, values=vals,
                   detail=why, premise_failures=premise_failures)


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
class Premise:
    """A check that is the premise of a claim's readings, evaluated per seed.

    When ``holds(measurement)`` is False on a seed, that seed's value is not evidence for the
    reading (a fuel ratio at unequal torque, a time of a solve that did not converge, a sample
    that is not controllable): the reading is ``inconclusive``, with ``why(measurement)`` as
    the reason, in ``result.json`` (``readings[].premise_failures``) and the claim's detail.

    Parameters
    ----------
    name : str
        The premise in words (``"equal torque"``).
    holds : callable
        ``holds(measurement) -> bool`` for one seed's measurement.
    why : callable, optional
        ``why(measurement) -> str``: the evidence when it fails.
    readings : tuple of str or None
        The readings it is a premise of (None: every reading).

    Examples
    --------
    >>> p = Premise(name="converged", holds=lambda m: m["ok"], why=lambda m: "solver stopped at max_iter")
    >>> spec = ClaimSpec(id="c", statement="s", where="w", quantity="q", value=lambda m: m["r"], threshold=1.0,
    ...                  premises=(p,))
    >>> runs = [{"r": 2.0, "ok": True}] * 4 + [{"r": 2.0, "ok": False}]
    >>> c = spec.evaluate({"default": runs})
    >>> c.outcome, "converged" in c.detail
    ('inconclusive', True)
    """

    name: str
    holds: Callable[[Any], bool]
    why: Callable[[Any], str] | None = field(default=None, repr=False)
    readings: tuple[str, ...] | None = None

    def __post_init__(self) -> None:
        check_callable("holds", self.holds)
        check_callable("why", self.why, allow_none=True)
        if not str(self.name).strip():
            raise InputError("Premise: name must be a non-empty description (e.g. 'equal torque')")
        if self.readings is not None:
            object.__setattr__(self, "readings", tuple(self.readings))

    def failures(self, reading: str, runs: Sequence[Any]) -> list[str]:
        """One reason per seed of ``runs`` on which this premise of ``reading`` fails."""
        if self.readings is not None and reading not in self.readings:
            return []
        return [f"seed {i}: {self.name} fails" + (f" ({self.why(m)})" if self.why is not None else "")
                for i, m in enumerate(runs) if not bool(self.holds(m))]


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
        page's snapshot by its outcome and its readings' outcomes, not by value.
    scale : {"linear", "log"}
        ``"log"`` for a ratio: seeds are compared with the threshold on log ratios and
        ``margin`` is in log units (a relative margin: ``log(1.5)`` is a factor 1.5).
    premises : tuple of Premise
        Checks that are the premises of (some of) the readings, per seed (:class:`Premise`).
    reading_margins : mapping of str to float
        A reading's own equivalence margin where it differs from ``margin`` (e.g. a reading on
        fixed demands has no sampling error of random ones); the reason goes in
        ``margin_reason``.

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
    scale: str = "linear"
    premises: tuple[Premise, ...] = ()
    reading_margins: Mapping[str, float] = field(default_factory=dict)
    describe: Callable[[Reading], str] | None = field(default=None, repr=False)

    _cls = Claim

    def __post_init__(self) -> None:
        check_callable("value", self.value, allow_none=True)
        check_callable("held", self.held, allow_none=True)
        check_choice("better", self.better, ("above", "below"))
        check_choice("scale", self.scale, ("linear", "log"))
        check_flag("stochastic", self.stochastic)
        object.__setattr__(self, "premises", tuple(self.premises))
        check_mapping("reading_margins", self.reading_margins)
        object.__setattr__(self, "reading_margins", {
            str(k): check_range(f"reading_margins[{k!r}]", v, 0.0, math.inf) for k, v in self.reading_margins.items()})
        for p in self.premises:
            if not isinstance(p, Premise):
                raise InputError(f"claim {self.id!r}: premises must be Premise objects; got {type(p).__name__}")
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
        failed = [f for p in self.premises for f in p.failures(name, runs)]
        r = decide(held, values=vals, threshold=self.threshold, better=self.better, stochastic=self.stochastic,
                   reading=name, margin=self.reading_margins.get(name, self.margin), scale=self.scale,
                   premise_failures=failed)
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
            text += " | readings: " + "; ".join(
                f"{r.reading}: {r.outcome}"
                + (f" (premise failed on {len(r.premise_failures)} seeds: no evidence)" if r.premise_failures else "")
                for r in per)
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
