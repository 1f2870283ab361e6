"""Requirement statistics: percentile bounds, exceedance probabilities, sample sizes, verdicts.

A Monte-Carlo campaign answers "what is my 99th-percentile pointing error, and with what
confidence"; this module turns the per-sample values of a campaign into statements an engineer
can sign off:

* :func:`percentile_bound` — distribution-free confidence bounds on a percentile from order
  statistics (one- or two-sided): the upper bound on the p-th percentile at confidence
  ``gamma`` is the order statistic ``X_(k)`` with the smallest ``k`` such that
  ``P(Binom(n, p) <= k - 1) >= gamma`` (Conover 1999, §3.2; Hahn & Meeker 1991, §5.2). Too
  few samples for a bound give an infinite bound and ``success=False``, never a guess.
* :func:`proportion_interval` / :func:`exceedance_probability` — the probability of an event
  (a requirement exceeded) with a Clopper–Pearson (exact) or Wilson interval, from
  :func:`scipy.stats.binomtest` (``proportion_ci``).
* :func:`samples_needed` — the smallest number of samples for a stated coverage and confidence
  (Wilks 1941): 59 for 95 %/95 % one-sided with no failure, 93 two-sided.
* :class:`Requirement`, :func:`parse_requirement`, :func:`read_requirements` and
  :func:`check_requirements` — a requirement table (``pointing_max_deg p99 <= 0.1 after 300
  s``) checked against per-sample metrics. A requirement is **met** only if the confidence
  bound meets it, **not met** only if the bound on the other side fails it, and otherwise
  **inconclusive**, with the number of samples that would decide it at the observed rate.

The binomial quantities come from :mod:`scipy.stats` (``binom``, ``beta``, ``binomtest``,
``t``); only the order-statistic ranks and the sample-size search are written here, because no
kept library exposes them.

References
----------
S. S. Wilks, "Determination of sample sizes for setting tolerance limits", *Ann. Math.
Statist.* 12(1), 91–96, 1941. — A. Guba, M. Makai, L. Pál, "Statistical aspects of best
estimate method — I", *Reliab. Eng. Syst. Safety* 80, 217–232, 2003 (Table 1: 59, 93, 124,
153 samples for 95/95 one-sided with 0–3 failures). — W. J. Conover, *Practical
Nonparametric Statistics*, 3rd ed., Wiley 1999, §3.2 (quantile confidence intervals). —
C. J. Clopper, E. S. Pearson, *Biometrika* 26(4), 404–413, 1934. — E. B. Wilson, *J. Amer.
Statist. Assoc.* 22, 209–212, 1927.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats

from adcskit._results import Result
from adcskit._validation import (
    as_array,
    check_choice,
    check_finite,
    check_int,
    check_mapping,
    check_path,
    check_range,
    short_repr,
)
from adcskit.errors import ConfigError, InputError, InputTypeError

__all__ = [
    "PercentileBound",
    "percentile_bound",
    "ProportionInterval",
    "proportion_interval",
    "exceedance_probability",
    "samples_needed",
    "Requirement",
    "parse_requirement",
    "read_requirements",
    "RequirementVerdict",
    "RequirementTable",
    "check_requirements",
]

#: Which bounds of a percentile or a proportion are asked for.
SIDES = ("upper", "lower", "two-sided")
#: Interval methods of :func:`proportion_interval` -> ``scipy.stats.binomtest`` method name.
PROPORTION_METHODS = {"clopper-pearson": "exact", "wilson": "wilson"}
#: Statistics a :class:`Requirement` can constrain.
STATISTICS = ("percentile", "mean", "max", "min", "probability")
#: Comparisons of a requirement (and of the event of a ``probability`` requirement).
COMPARISONS = ("<=", "<", ">=", ">")
#: Largest sample size :func:`samples_needed` and the verdicts' planning search look at.
MAX_SAMPLES = 10**12

_OPS = {"<=": np.less_equal, "<": np.less, ">=": np.greater_equal, ">": np.greater}
_NEGATE = {"<=": ">", "<": ">=", ">=": "<", ">": "<="}


def _confidence(value: Any, name: str = "confidence") -> float:
    return check_range(name, value, 0.0, 1.0, lo_open=True, hi_open=True)


def _sample(name: str, x: Any) -> np.ndarray:
    """A 1-D float sample; ±inf are orderable and allowed, NaN is refused (say what it means)."""
    arr = as_array(name, x, finite=False, max_abs=None)
    if arr.ndim != 1:
        raise InputError(f"{name} must be a 1-D array of per-sample values; got shape {arr.shape}")
    n_nan = int(np.isnan(arr).sum())
    if n_nan:
        raise InputError(
            f"{name} must not contain NaN (a sample without a value: drop it or decide what it "
            f"means first); got {n_nan} NaN of {arr.size}"
        )
    return arr


# ---------------------------------------------------------------------------------------------
# percentiles from order statistics
# ---------------------------------------------------------------------------------------------


def _upper_rank(n: int, q: float, alpha: float) -> int | None:
    """Smallest 1-based k with P(Binom(n, q) <= k - 1) >= 1 - alpha, or None if k > n."""
    cdf = stats.binom.cdf(np.arange(n), n, q)  # cdf[j] = P(B <= j), j = 0..n-1
    ok = np.nonzero(cdf >= 1.0 - alpha)[0]
    return int(ok[0]) + 1 if ok.size else None


def _lower_rank(n: int, q: float, alpha: float) -> int | None:
    """Largest 1-based k with P(Binom(n, q) >= k) >= 1 - alpha, or None if k < 1."""
    cdf = stats.binom.cdf(np.arange(n), n, q)  # P(B >= k) = 1 - cdf[k-1]
    ok = np.nonzero(cdf <= alpha)[0]
    return int(ok[-1]) + 1 if ok.size else None


def _bound_samples(tail: float, alpha: float) -> int:
    """Fewest samples n with (1 - tail)**n <= alpha: X_(n) then bounds the (1 - tail)-quantile
    from above (closed form; ``log1p`` keeps a tiny ``tail`` exact)."""
    if tail >= 1.0:
        return 1
    if tail <= 0.0:
        raise InputError("percentile must be far enough from 0 and 100 % for a bound in float64 "
                         f"(tail probability {tail:g}); got a percentile whose tail rounds to 0")
    step = math.log1p(-tail)
    n = max(1, math.ceil(math.log(alpha) / step))
    while n > 1 and (n - 1) * step <= math.log(alpha):
        n -= 1
    while n * step > math.log(alpha):
        n += 1
    return n


def _first_n(pred: Any, lo: int) -> int:
    """Smallest integer n >= lo with pred(n) true, for pred monotone in n (bisection)."""
    hi = max(lo, 1)
    while not pred(hi):
        lo, hi = hi + 1, hi * 2
        if hi > MAX_SAMPLES:
            raise InputError(f"more than {MAX_SAMPLES:.0e} samples would be needed")
    while lo < hi:
        mid = (lo + hi) // 2
        if pred(mid):
            hi = mid
        else:
            lo = mid + 1
    return hi


@dataclass(frozen=True, slots=True, kw_only=True)
class PercentileBound(Result):
    """Distribution-free confidence bound(s) on a percentile (:func:`percentile_bound`).

    Attributes
    ----------
    percentile : float, %
    confidence : float
        Requested confidence level.
    achieved_confidence : float
        Exact confidence of the order statistics used (>= ``confidence`` when ``success``;
        NaN when no bound exists): the binomial probability that they bracket the percentile.
    side : str
        ``"upper"``, ``"lower"`` or ``"two-sided"``.
    n : int
    estimate : float
        Point estimate (``numpy.quantile``, linear interpolation). Not a bound.
    lower, upper : float
        The bounds; ``-inf`` / ``inf`` for a side that is not asked for or that ``n`` samples
        cannot give.
    rank_lower, rank_upper : int or None
        1-based ranks of the order statistics used (``None``: no bound on that side).
    n_needed : int
        Fewest samples for which the requested bound(s) exist at all.
    success : bool
        Every requested bound exists.
    message : str

    Examples
    --------
    >>> from adcskit.uncertainty import percentile_bound
    >>> b = percentile_bound(range(1, 60), 95.0, confidence=0.95)
    >>> b.upper, b.rank_upper, b.success          # 59 samples: the largest bounds the p95
    (59.0, 59, True)
    """

    percentile: float
    confidence: float
    achieved_confidence: float
    side: str
    n: int
    estimate: float
    lower: float
    upper: float
    rank_lower: int | None
    rank_upper: int | None
    n_needed: int
    success: bool
    message: str


def percentile_bound(x: Any, percentile: Any, *, confidence: Any = 0.95, side: str = "upper") -> PercentileBound:
    """Distribution-free confidence bound(s) on a percentile of the population behind ``x``.

    The bound is an order statistic of ``x``: for any continuous distribution, the upper
    bound ``X_(k)`` satisfies ``P(X_(k) >= x_p) = P(Binom(n, p) <= k - 1) >= confidence``,
    with ``k`` the smallest rank that does (and mirror-wise for the lower bound). Two-sided
    bounds split ``1 - confidence`` equally between the sides.

    Parameters
    ----------
    x : array_like (n,)
        Per-sample values (any unit). ±inf are allowed (an order statistic may be infinite);
        NaN is refused.
    percentile : float, %
        In (0, 100); ``99`` is the 99th percentile.
    confidence : float
        In (0, 1).
    side : {"upper", "lower", "two-sided"}

    Returns
    -------
    PercentileBound
        With ``n`` too small for a requested bound, that bound is ``inf`` (``-inf``),
        ``success`` is False and ``message`` and ``n_needed`` say how many samples it takes.

    Raises
    ------
    InputError
        ``percentile`` or ``confidence`` out of range, NaN in ``x``, an unknown ``side``.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.uncertainty import percentile_bound
    >>> err = np.random.default_rng(0).rayleigh(0.02, 1000)        # pointing error, deg
    >>> b = percentile_bound(err, 99.0, confidence=0.95)
    >>> round(b.estimate, 4), round(b.upper, 4), b.rank_upper      # p99 <= upper at 95 %
    (0.0597, 0.0692, 996)
    >>> percentile_bound(err[:100], 99.0).message                  # too few for an upper bound
    'no upper bound on the p99 at 95 % confidence from 100 samples: at least 299 needed'
    """
    arr = np.sort(_sample("x", x))
    p = check_range("percentile", percentile, 0.0, 100.0, lo_open=True, hi_open=True, unit="%")
    conf = _confidence(confidence)
    check_choice("side", side, SIDES)
    n, q = int(arr.size), p / 100.0
    alpha = (1.0 - conf) / 2.0 if side == "two-sided" else 1.0 - conf
    k_up = _upper_rank(n, q, alpha) if side != "lower" else None
    k_lo = _lower_rank(n, q, alpha) if side != "upper" else None
    need = max(_bound_samples(1.0 - q, alpha) if side != "lower" else 1,
               _bound_samples(q, alpha) if side != "upper" else 1)
    ok = (side == "lower" or k_up is not None) and (side == "upper" or k_lo is not None)
    cdf = stats.binom.cdf
    if not ok:
        achieved = math.nan
    elif side == "upper":
        achieved = float(cdf(k_up - 1, n, q))
    elif side == "lower":
        achieved = float(1.0 - cdf(k_lo - 1, n, q))
    else:
        achieved = float(cdf(k_up - 1, n, q) - cdf(k_lo - 1, n, q))
    what = "bound" if side != "two-sided" else "two-sided bounds"
    label = f"{side + ' ' if side != 'two-sided' else ''}{what} on the p{p:g} at {conf * 100:g} % confidence"
    msg = (f"{label} from {n} samples (order statistics, achieved confidence {achieved:.4f})" if ok
           else f"no {label} from {n} samples: at least {need} needed")
    return PercentileBound(
        percentile=p, confidence=conf, achieved_confidence=achieved, side=side, n=n,
        estimate=float(np.quantile(arr, q)) if np.all(np.isfinite(arr)) else float(np.quantile(arr, q, method="inverted_cdf")),
        lower=float(arr[k_lo - 1]) if k_lo is not None else -math.inf,
        upper=float(arr[k_up - 1]) if k_up is not None else math.inf,
        rank_lower=k_lo, rank_upper=k_up, n_needed=need, success=ok, message=msg,
    )


# ---------------------------------------------------------------------------------------------
# proportions
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True, kw_only=True)
class ProportionInterval(Result):
    """Confidence interval on a probability from ``k`` events in ``n`` trials.

    Attributes
    ----------
    k, n : int
    estimate : float
        ``k / n``.
    lower, upper : float
        Interval ends (``0`` / ``1`` on a side that is not asked for).
    confidence : float
    method : str
        ``"clopper-pearson"`` (exact: coverage >= confidence for every true probability) or
        ``"wilson"`` (score interval: coverage close to, not always above, confidence).
    side : str
    event : str
        What was counted (e.g. ``"x > 0.1"``); empty for :func:`proportion_interval`.

    Examples
    --------
    >>> from adcskit.uncertainty import proportion_interval
    >>> ci = proportion_interval(0, 59, side="upper")
    >>> ci.estimate, round(ci.upper, 4)           # 0 of 59: P < 0.0495 at 95 %
    (0.0, 0.0495)
    """

    k: int
    n: int
    estimate: float
    lower: float
    upper: float
    confidence: float
    method: str
    side: str
    event: str = ""


_ALTERNATIVE = {"two-sided": "two-sided", "upper": "less", "lower": "greater"}


def proportion_interval(
    k: Any, n: Any, *, confidence: Any = 0.95, method: str = "clopper-pearson", side: str = "two-sided"
) -> ProportionInterval:
    """Confidence interval on a probability from ``k`` events in ``n`` independent trials.

    A thin, validated front of :meth:`scipy.stats.binomtest(k, n).proportion_ci
    <scipy.stats._result_classes.BinomTestResult.proportion_ci>`; ``side="upper"`` gives the
    one-sided interval ``[0, upper]`` (scipy's ``alternative="less"``), ``"lower"`` gives
    ``[lower, 1]``.

    Parameters
    ----------
    k : int
        Number of events, in [0, n].
    n : int
        Number of trials, >= 1.
    confidence : float
        In (0, 1).
    method : {"clopper-pearson", "wilson"}
    side : {"two-sided", "upper", "lower"}

    Returns
    -------
    ProportionInterval

    References
    ----------
    Clopper & Pearson 1934; Wilson 1927 (module references).

    Examples
    --------
    >>> from adcskit.uncertainty import proportion_interval
    >>> ci = proportion_interval(3, 100)                       # 3 failures in 100 runs
    >>> round(ci.lower, 4), round(ci.upper, 4)
    (0.0062, 0.0852)
    >>> w = proportion_interval(3, 100, method="wilson")
    >>> round(w.lower, 4), round(w.upper, 4)
    (0.0103, 0.0845)
    """
    n = check_int("n", n, minimum=1)
    k = check_int("k", k, minimum=0, maximum=n)
    conf = _confidence(confidence)
    check_choice("method", method, PROPORTION_METHODS)
    check_choice("side", side, SIDES)
    ci = stats.binomtest(k, n, alternative=_ALTERNATIVE[side]).proportion_ci(
        confidence_level=conf, method=PROPORTION_METHODS[method])
    return ProportionInterval(k=k, n=n, estimate=k / n, lower=float(ci.low), upper=float(ci.high),
                              confidence=conf, method=method, side=side)


def exceedance_probability(
    x: Any, threshold: Any, *, comparison: str = ">", confidence: Any = 0.95, method: str = "clopper-pearson",
    side: str = "two-sided",
) -> ProportionInterval:
    """Probability that a sample exceeds ``threshold``, with a confidence interval.

    Counts the samples with ``x <comparison> threshold`` (``x > threshold`` by default) and
    passes the count to :func:`proportion_interval`.

    Parameters
    ----------
    x : array_like (n,)
        Per-sample values (±inf allowed, NaN refused).
    threshold : float
        Same unit as ``x``.
    comparison : {">", ">=", "<", "<="}
        The event counted.
    confidence : float
        In (0, 1).
    method : {"clopper-pearson", "wilson"}
    side : {"two-sided", "upper", "lower"}

    Returns
    -------
    ProportionInterval

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.uncertainty import exceedance_probability
    >>> err = np.random.default_rng(0).rayleigh(0.02, 1000)        # deg
    >>> pe = exceedance_probability(err, 0.06, side="upper")      # P(err > 0.06 deg)
    >>> pe.k, pe.estimate, round(pe.upper, 4), pe.event
    (10, 0.01, 0.0169, 'x > 0.06')
    """
    arr = _sample("x", x)
    thr = check_finite("threshold", threshold, max_abs=None)
    check_choice("comparison", comparison, COMPARISONS)
    k = int(np.count_nonzero(_OPS[comparison](arr, thr)))
    ci = proportion_interval(k, arr.size, confidence=confidence, method=method, side=side)
    return ProportionInterval(k=ci.k, n=ci.n, estimate=ci.estimate, lower=ci.lower, upper=ci.upper,
                              confidence=ci.confidence, method=ci.method, side=ci.side,
                              event=f"x {comparison} {thr:g}")


def samples_needed(coverage: Any, confidence: Any = 0.95, *, failures: Any = 0, side: str = "one-sided") -> int:
    """Fewest samples for a distribution-free tolerance bound (Wilks 1941).

    One-sided: with ``n`` samples, the ``(failures + 1)``-th largest bounds the
    ``coverage``-quantile from above with the stated confidence:
    ``P(Binom(n, 1 - coverage) <= failures) <= 1 - confidence``. Equivalently: if
    ``failures`` or fewer of ``n`` runs violate a requirement, the probability of violating
    it is below ``1 - coverage`` with that confidence. Two-sided: the interval
    ``[X_(1+r), X_(n-r)]`` (``r = failures`` samples outside it on each side) covers
    ``coverage`` of the population with that confidence; its coverage follows
    ``Beta(n - 2r - 1, 2r + 2)``, the one-sided law with ``2r + 1`` failures.

    Parameters
    ----------
    coverage : float
        Population fraction to cover, in (0, 1) (0.95 for "95 %").
    confidence : float
        In (0, 1).
    failures : int
        Samples allowed beyond the bound (per side for ``two-sided``), >= 0.
    side : {"one-sided", "two-sided"}

    Returns
    -------
    int

    References
    ----------
    Wilks 1941, eq. (8)-(9); Guba, Makai & Pál 2003, Table 1 (59, 93, 124, 153 for 95/95
    one-sided with 0-3 failures; 93 two-sided).

    Examples
    --------
    >>> from adcskit.uncertainty import samples_needed
    >>> samples_needed(0.95, 0.95), samples_needed(0.95, 0.95, failures=1)
    (59, 93)
    >>> samples_needed(0.95, 0.95, side="two-sided"), samples_needed(0.99, 0.95)
    (93, 299)
    """
    beta = _confidence(coverage, "coverage")
    gamma = _confidence(confidence)
    r = check_int("failures", failures, minimum=0, maximum=10**6)
    check_choice("side", side, ("one-sided", "two-sided"))
    m = r if side == "one-sided" else 2 * r + 1
    # P(Binom(n, 1 - beta) <= m) decreases with n: the first n where it is <= 1 - gamma
    return _first_n(lambda n: stats.binom.cdf(m, n, 1.0 - beta) <= 1.0 - gamma, m + 1)


# ---------------------------------------------------------------------------------------------
# requirements
# ---------------------------------------------------------------------------------------------

_NAME_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_.]*\Z")


@dataclass(frozen=True, slots=True, kw_only=True)
class Requirement(Result):
    """One line of a requirement table, e.g. ``pointing_max_deg p99 <= 0.1 after 300 s``.

    Parameters
    ----------
    metric : str
        Name of a per-sample metric (a key of the metrics mapping, unit in the name).
    statistic : {"percentile", "mean", "max", "min", "probability"}
        ``percentile``: the ``percentile``-th percentile of the population (order-statistic
        bounds, distribution-free); ``mean``: the population mean (Student-t bound, which
        assumes a near-normal sample mean); ``max`` / ``min``: every sample (no population
        statement beyond the Wilks coverage it implies); ``probability``: the probability of
        the event ``metric <event> event_threshold`` (Clopper–Pearson bound by default).
    comparison : {"<=", "<", ">=", ">"}
        How the statistic compares with ``threshold``. ``max`` takes ``<=``/``<`` only and
        ``min`` takes ``>=``/``>`` only.
    threshold : float
        Metric unit, or a probability in [0, 1] for ``probability``.
    percentile : float, %, optional
        In (0, 100); required with ``statistic="percentile"`` only.
    event : {">", ">=", "<", "<="}, optional
        Required with ``statistic="probability"`` only.
    event_threshold : float, optional
        Metric unit; required with ``statistic="probability"`` only.
    confidence : float
        In [0.5, 1): the confidence of the bounds that decide the verdict.
    after_s : float, s, optional
        The requirement holds from this time on: the metric must have been computed over
        ``[after_s, end]`` (see :func:`check_requirements`).
    name : str
        Optional label (e.g. a requirement id ``"ADCS-012"``).

    Examples
    --------
    >>> from adcskit.uncertainty import Requirement
    >>> r = Requirement(metric="pointing_max_deg", statistic="percentile", percentile=99.0,
    ...                 comparison="<=", threshold=0.1, after_s=300.0)
    >>> r.text
    'pointing_max_deg p99 <= 0.1 after 300 s at 95 % confidence'
    """

    metric: str
    statistic: str
    comparison: str
    threshold: float
    percentile: float | None = None
    event: str | None = None
    event_threshold: float | None = None
    confidence: float = 0.95
    after_s: float | None = None
    name: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.metric, str) or not _NAME_RE.match(self.metric):
            raise InputError(f"metric must be a metric name (letters, digits, '_', '.'); got {short_repr(self.metric)}")
        check_choice("statistic", self.statistic, STATISTICS)
        check_choice("comparison", self.comparison, COMPARISONS)
        object.__setattr__(self, "threshold", check_finite("threshold", self.threshold))
        if self.statistic == "percentile":
            if self.percentile is None:
                raise InputError("percentile must be given (in (0, 100) %) for statistic 'percentile'; got None")
            object.__setattr__(self, "percentile", check_range("percentile", self.percentile, 0.0, 100.0,
                                                               lo_open=True, hi_open=True, unit="%"))
        elif self.percentile is not None:
            raise InputError(f"percentile must be None for statistic {self.statistic!r}; got {short_repr(self.percentile)}")
        if self.statistic == "probability":
            if self.event is None or self.event_threshold is None:
                raise InputError("event and event_threshold must be given for statistic 'probability' "
                                 f"(e.g. event='>', event_threshold=0.1); got {self.event!r}, {self.event_threshold!r}")
            check_choice("event", self.event, COMPARISONS)
            object.__setattr__(self, "event_threshold", check_finite("event_threshold", self.event_threshold))
            check_range("threshold", self.threshold, 0.0, 1.0)
        elif self.event is not None or self.event_threshold is not None:
            raise InputError(f"event and event_threshold must be None for statistic {self.statistic!r}; "
                             f"got {self.event!r}, {self.event_threshold!r}")
        if self.statistic == "max" and self.comparison not in ("<=", "<"):
            raise InputError(f"comparison must be '<=' or '<' for statistic 'max' (every sample below); got {self.comparison!r}")
        if self.statistic == "min" and self.comparison not in (">=", ">"):
            raise InputError(f"comparison must be '>=' or '>' for statistic 'min' (every sample above); got {self.comparison!r}")
        object.__setattr__(self, "confidence", check_range("confidence", self.confidence, 0.5, 1.0, hi_open=True))
        if self.after_s is not None:
            object.__setattr__(self, "after_s", check_range("after_s", self.after_s, 0.0, 1e12, unit="s"))
        if not isinstance(self.name, str):
            raise InputTypeError(f"name must be a str; got {short_repr(self.name)}")

    @property
    def text(self) -> str:
        """The one-line form :func:`parse_requirement` reads back."""
        if self.statistic == "probability":
            head = f"P({self.metric} {self.event} {_fmt(self.event_threshold)}) {self.comparison} {_fmt(self.threshold)}"
        else:
            stat = f"p{_fmt(self.percentile)}" if self.statistic == "percentile" else self.statistic
            head = f"{self.metric} {stat} {self.comparison} {_fmt(self.threshold)}"
        tail = f" after {_fmt(self.after_s)} s" if self.after_s is not None else ""
        label = f"{self.name}: " if self.name else ""
        return f"{label}{head}{tail} at {_fmt(self.confidence * 100)} % confidence"

    _dict_extra = ("text",)  # the requirement as one sentence, after the fields


def _fmt(x: float) -> str:
    """Shortest text of a number that reads back to it (up to 12 significant digits)."""
    return format(x, ".12g")


_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_TAIL = (rf"(?:\s+after\s+(?P<after>{_NUM})\s*s)?"
         rf"(?:\s+(?:at|@)\s+(?P<conf>{_NUM})\s*%(?:\s*(?:confidence|conf))?)?\s*\Z")
_STAT_RE = re.compile(
    rf"\s*(?:(?P<name>[^:]+?)\s*:\s*)?(?P<metric>[A-Za-z_][A-Za-z0-9_.]*)\s+(?P<stat>p{_NUM}|mean|max|min)\s*"
    rf"(?P<cmp><=|>=|<|>)\s*(?P<thr>{_NUM})" + _TAIL, re.I)
_PROB_RE = re.compile(
    rf"\s*(?:(?P<name>[^:]+?)\s*:\s*)?P\(\s*(?P<metric>[A-Za-z_][A-Za-z0-9_.]*)\s*(?P<ev><=|>=|<|>)\s*(?P<evthr>{_NUM})\s*\)"
    rf"\s*(?P<cmp><=|>=|<|>)\s*(?P<thr>{_NUM})\s*(?P<pct>%)?" + _TAIL, re.I)


def parse_requirement(text: str, *, confidence: Any = 0.95) -> Requirement:
    """Read one requirement from its one-line text form.

    Grammar (keywords case-insensitive, ``[...]`` optional)::

        [label:] METRIC STAT OP VALUE [after T s] [at C % [confidence]]
        [label:] P(METRIC OP VALUE) OP PROB[%] [after T s] [at C % [confidence]]

    ``STAT`` is ``pNN`` (a percentile in %, e.g. ``p99``, ``p99.9``), ``mean``, ``max`` or
    ``min``; ``OP`` is ``<=``, ``<``, ``>=`` or ``>``. Without ``at C %`` the
    ``confidence`` argument applies.

    Parameters
    ----------
    text : str
    confidence : float
        Default confidence, in [0.5, 1).

    Returns
    -------
    Requirement

    Raises
    ------
    InputError
        Text that does not follow the grammar (the message shows it) or out-of-range values.

    Examples
    --------
    >>> from adcskit.uncertainty import parse_requirement
    >>> r = parse_requirement("pointing_max_deg p99 <= 0.1 after 300 s")
    >>> r.statistic, r.percentile, r.threshold, r.after_s, r.confidence
    ('percentile', 99.0, 0.1, 300.0, 0.95)
    >>> parse_requirement("R2: P(settling_time_s > 60) <= 1 % at 90 % confidence").text
    'R2: P(settling_time_s > 60) <= 0.01 at 90 % confidence'
    """
    if not isinstance(text, str):
        raise InputTypeError(f"text must be a str; got {short_repr(text)}")
    conf = check_range("confidence", confidence, 0.5, 1.0, hi_open=True)
    m = _PROB_RE.match(text) or _STAT_RE.match(text)
    if m is None:
        raise InputError(
            "text must read 'METRIC pNN|mean|max|min OP VALUE [after T s] [at C %]' or "
            f"'P(METRIC OP VALUE) OP PROB [after T s] [at C %]'; got {short_repr(text)}")
    g = m.groupdict()
    common = dict(metric=g["metric"], comparison=g["cmp"], name=(g["name"] or "").strip(),
                  confidence=round(float(g["conf"]) / 100.0, 12) if g["conf"] else conf,
                  after_s=float(g["after"]) if g["after"] else None)
    if "ev" in g:
        thr = round(float(g["thr"]) / 100.0, 14) if g["pct"] else float(g["thr"])
        return Requirement(statistic="probability", threshold=thr, event=g["ev"],
                           event_threshold=float(g["evthr"]), **common)
    stat = g["stat"].lower()
    if stat.startswith("p"):
        return Requirement(statistic="percentile", percentile=float(stat[1:]), threshold=float(g["thr"]), **common)
    return Requirement(statistic=stat, threshold=float(g["thr"]), **common)


_FIELDS = ("metric", "statistic", "comparison", "threshold", "percentile", "event", "event_threshold",
           "confidence", "after_s", "name")


def read_requirements(source: Any, *, confidence: Any = 0.95) -> tuple[Requirement, ...]:
    """Read a requirement table: a TOML file, a mapping, or an iterable of lines/requirements.

    A TOML table is an array ``[[requirement]]`` whose entries are either ``text = "..."``
    (the one-line form of :func:`parse_requirement`, optionally with ``name``) or the fields
    of :class:`Requirement`. Unknown keys are a :class:`~adcskit.errors.ConfigError`.

    Parameters
    ----------
    source : str, os.PathLike, mapping or iterable
        Path of a ``.toml`` file; a mapping with key ``"requirement"`` (a parsed TOML file);
        or an iterable of one-line strings, mappings and :class:`Requirement` objects.
    confidence : float
        Confidence of the entries that do not state theirs, in [0.5, 1).

    Returns
    -------
    tuple of Requirement

    Examples
    --------
    >>> import tomllib
    >>> from adcskit.uncertainty import read_requirements
    >>> doc = tomllib.loads('''
    ... [[requirement]]
    ... name = "ADCS-1"
    ... text = "pointing_rms_deg p95 <= 0.05"
    ... [[requirement]]
    ... metric = "settling_time_s"
    ... statistic = "max"
    ... comparison = "<="
    ... threshold = 60.0
    ... ''')
    >>> [r.text for r in read_requirements(doc)]
    ['ADCS-1: pointing_rms_deg p95 <= 0.05 at 95 % confidence', 'settling_time_s max <= 60 at 95 % confidence']
    """
    conf = check_range("confidence", confidence, 0.5, 1.0, hi_open=True)
    if isinstance(source, (str, Path)):
        from adcskit.config import read_toml

        path = check_path("source", source)
        if not path.is_file():
            raise InputError(f"source must be an existing TOML file or a list of requirements; got "
                             f"{short_repr(str(source))} (not a file; to pass one line of text, wrap it in a list)")
        source = read_toml(path)
    if isinstance(source, Mapping):
        unknown = set(source) - {"requirement"}
        if unknown or "requirement" not in source:
            raise ConfigError(f"a requirement table must have exactly the key 'requirement' (an array of tables); "
                              f"got keys {sorted(map(str, source))}")
        source = source["requirement"]
    if isinstance(source, (str, bytes)) or not isinstance(source, Iterable):
        raise InputTypeError(f"source must be a TOML path, a mapping or an iterable of requirements; got {short_repr(source)}")
    out: list[Requirement] = []
    for i, item in enumerate(source):
        where = f"source[{i}]"
        if isinstance(item, Requirement):
            out.append(item)
        elif isinstance(item, str):
            try:
                out.append(parse_requirement(item, confidence=conf))
            except InputError as exc:
                raise InputError(f"{where}: {exc}") from None
        elif isinstance(item, Mapping):
            keys = set(item)
            allowed = {"text", "name"} if "text" in keys else set(_FIELDS)
            bad = sorted(map(str, keys - allowed))
            if bad:
                raise ConfigError(f"{where} has unknown key(s) {bad}; allowed: {sorted(allowed)}")
            try:
                if "text" in keys:
                    r = parse_requirement(item["text"], confidence=conf)
                    if "name" in keys:
                        r = Requirement(**({k: getattr(r, k) for k in _FIELDS} | {"name": item["name"]}))
                else:
                    r = Requirement(**({"confidence": conf} | dict(item)))
            except (InputError, InputTypeError, TypeError) as exc:
                raise ConfigError(f"{where}: {exc}") from None
            out.append(r)
        else:
            raise InputTypeError(f"{where} must be a str, a mapping or a Requirement; got {short_repr(item)}")
    if not out:
        raise InputError("a requirement table must hold at least one requirement; got none")
    return tuple(out)


@dataclass(frozen=True, slots=True, kw_only=True)
class RequirementVerdict:
    """One row of a checked requirement table (:func:`check_requirements`).

    Attributes
    ----------
    requirement : Requirement
    outcome : str
        ``"met"`` (the confidence bound meets the threshold), ``"not met"`` (the bound on the
        other side fails it) or ``"inconclusive"``.
    verdict : str
        The outcome as printed: ``"inconclusive (need ~N samples)"`` when a sample size can
        decide it at the observed rate.
    n : int
        Samples used.
    n_nan : int
        Samples without a value (NaN), counted as violating under ``nan_policy="fail"``.
    n_violating : int
        Samples beyond the threshold (``percentile``/``max``/``min``) or with the event
        (``probability``); -1 for ``mean``.
    estimate : float
        Point estimate of the statistic (metric unit; a probability for ``probability``).
    bound : float
        The confidence bound on the met side (upper for ``<=``/``<``): met iff it satisfies the
        comparison. ±inf when ``n`` is too small for one.
    opposite_bound : float
        The bound on the other side: not met iff it fails the comparison.
    n_needed : int or None
        For an inconclusive row, about how many samples would decide it if the observed rate
        (or mean and spread) held; ``None`` when decided, or when no number can (an observed
        rate exactly at the threshold).
    method : str
        How the bounds were computed.
    detail : str

    Examples
    --------
    >>> from adcskit.uncertainty import check_requirements
    >>> row = check_requirements(["x max <= 1"], {"x": [0.1, 0.5]}).rows[0]
    >>> row.outcome, row.n_violating
    ('met', 0)
    """

    requirement: Requirement
    outcome: str
    verdict: str
    n: int
    n_nan: int
    n_violating: int
    estimate: float
    bound: float
    opposite_bound: float
    n_needed: int | None
    method: str
    detail: str

    def to_dict(self) -> dict[str, Any]:
        d = {k: getattr(self, k) for k in self.__slots__ if k != "requirement"}
        return {"requirement": self.requirement.text, **d, "spec": self.requirement.to_dict()}

    def table_row(self) -> dict[str, Any]:
        """Flat row for a report table or a CSV file (strings and numbers only)."""
        r = self.requirement
        return {"name": r.name, "requirement": r.text.split(": ", 1)[-1] if r.name else r.text, "n": self.n,
                "estimate": self.estimate, "bound": self.bound, "verdict": self.verdict}


@dataclass(frozen=True, slots=True, kw_only=True)
class RequirementTable(Result):
    """A requirement table checked against per-sample metrics (:func:`check_requirements`).

    Attributes
    ----------
    rows : tuple of RequirementVerdict
    n_met, n_not_met, n_inconclusive : int
    success : bool
        Every requirement met.
    message : str

    Examples
    --------
    >>> from adcskit.uncertainty import check_requirements
    >>> t = check_requirements(["x max <= 1", "x min >= 0.2"], {"x": [0.1, 0.5]})
    >>> t.success, t.n_met, t.n_not_met, t.message
    (False, 1, 1, '1 met, 1 not met, 0 inconclusive of 2 requirements')
    """

    rows: tuple[RequirementVerdict, ...]
    n_met: int
    n_not_met: int
    n_inconclusive: int
    success: bool
    message: str
    columns: tuple[str, ...] = field(default=("name", "requirement", "n", "estimate", "bound", "verdict"))

    def table_rows(self) -> list[dict[str, Any]]:
        """One flat mapping per requirement (:attr:`columns`), for report tables and CSV files."""
        return [row.table_row() for row in self.rows]

    _dict_exclude = ("columns",)  # the per-row metric columns stay out


def _cp_bounds(k: int, n: int, gamma: float) -> tuple[float, float]:
    """One-sided Clopper–Pearson lower and upper bounds at confidence gamma (beta quantiles)."""
    lo = 0.0 if k == 0 else float(stats.beta.ppf(1.0 - gamma, k, n - k + 1))
    hi = 1.0 if k == n else float(stats.beta.ppf(gamma, k + 1, n - k))
    return lo, hi


def _proportion_bounds(k: int, n: int, gamma: float, method: str) -> tuple[float, float]:
    if method == "clopper-pearson":
        return _cp_bounds(k, n, gamma)
    lo = proportion_interval(k, n, confidence=gamma, method=method, side="lower").lower
    hi = proportion_interval(k, n, confidence=gamma, method=method, side="upper").upper
    return lo, hi


def _rate_n_needed(k: int, n: int, q0: float, bad_is_high: bool, strict: bool, gamma: float, method: str) -> int | None:
    """About how many samples decide ``P(event) vs q0`` if the observed rate k/n held."""
    rate = k / n
    if rate == q0:
        return None
    if (rate < q0) == bad_is_high:  # heading for "met": the far bound must cross q0
        def decided(m: int) -> bool:
            # conservative count: more events when they are bad, fewer when they are good
            kk = math.ceil(rate * m - 1e-12) if bad_is_high else math.floor(rate * m + 1e-12)
            lo, hi = _proportion_bounds(kk, m, gamma, method)
            return (hi < q0 if strict else hi <= q0) if bad_is_high else (lo > q0 if strict else lo >= q0)
    else:  # heading for "not met"
        def decided(m: int) -> bool:
            kk = math.floor(rate * m + 1e-12) if rate > q0 else math.ceil(rate * m - 1e-12)
            lo, hi = _proportion_bounds(kk, m, gamma, method)
            return (lo >= q0 if strict else lo > q0) if bad_is_high else (hi <= q0 if strict else hi < q0)
    try:
        return _first_n(decided, n + 1)
    except InputError:
        return None


def _evaluate(req: Requirement, v: np.ndarray, n_nan: int, method: str) -> RequirementVerdict:
    n, gamma, op, thr = int(v.size), req.confidence, req.comparison, req.threshold
    upper_req = op in ("<=", "<")          # the statistic must stay below the threshold
    meets = _OPS[op]
    need: int | None = None
    if req.statistic in ("max", "min"):
        violating = int(np.count_nonzero(~meets(v, thr)))
        est = float(v.max() if req.statistic == "max" else v.min())
        outcome = "met" if violating == 0 else "not met"
        cov = (1.0 - gamma) ** (1.0 / n)
        how = "every sample (sample extreme; no population bound)"
        detail = (f"{violating} of {n} samples violate it" if violating else
                  f"all {n} samples meet it: at {gamma * 100:g} % confidence at least {cov * 100:.2f} % of the "
                  f"population does (Wilks)")
        bound = opposite = est
    elif req.statistic == "percentile":
        p = req.percentile
        violating = int(np.count_nonzero(~meets(v, thr)))
        up = percentile_bound(v, p, confidence=gamma, side="upper")
        lo = percentile_bound(v, p, confidence=gamma, side="lower")
        est = up.estimate
        bound, opposite = (up.upper, lo.lower) if upper_req else (lo.lower, up.upper)
        if meets(bound, thr):
            outcome = "met"
        elif not meets(opposite, thr):
            outcome = "not met"
        else:
            outcome = "inconclusive"
            # dual: p-th percentile <= T  <=>  P(X > T) <= 1 - p (exact binomial test)
            q0 = 1.0 - p / 100.0 if upper_req else p / 100.0
            need = _rate_n_needed(violating, n, q0, True, False, gamma, "clopper-pearson")
        how = "order statistics (distribution-free)"
        detail = (f"p{p:g} estimate {est:.6g}; {'upper' if upper_req else 'lower'} {gamma * 100:g} % bound "
                  f"{bound:.6g}, {'lower' if upper_req else 'upper'} {opposite:.6g}; {violating} of {n} samples "
                  f"violate the threshold")
    elif req.statistic == "probability":
        event_op, event_thr = req.event, req.event_threshold
        violating = int(np.count_nonzero(_OPS[event_op](v, event_thr)))
        lo_b, hi_b = _proportion_bounds(violating, n, gamma, method)
        est = violating / n
        bound, opposite = (hi_b, lo_b) if upper_req else (lo_b, hi_b)
        if meets(bound, thr):
            outcome = "met"
        elif not meets(opposite, thr):
            outcome = "not met"
        else:
            outcome = "inconclusive"
            need = _rate_n_needed(violating, n, thr, upper_req, op in ("<", ">"), gamma, method)
        how = f"{method} interval"
        detail = (f"{violating} of {n} samples with {req.metric} {event_op} {event_thr:g}; one-sided {gamma * 100:g} % "
                  f"bounds [{lo_b:.4g}, {hi_b:.4g}]")
    else:  # mean
        if not np.all(np.isfinite(v)):
            raise InputError(f"metric {req.metric!r} must be finite for a 'mean' requirement; got an infinite value")
        violating = -1
        est = float(v.mean())
        if n < 2:
            bound, opposite = (math.inf, -math.inf) if upper_req else (-math.inf, math.inf)
        else:
            half = float(stats.t.ppf(gamma, n - 1)) * float(v.std(ddof=1)) / math.sqrt(n)
            bound, opposite = (est + half, est - half) if upper_req else (est - half, est + half)
        if meets(bound, thr):
            outcome = "met"
        elif not meets(opposite, thr):
            outcome = "not met"
        else:
            outcome = "inconclusive"
            s, gap = (float(v.std(ddof=1)) if n > 1 else 0.0), abs(est - thr)
            if gap > 0 and s > 0:
                try:
                    need = _first_n(lambda m: float(stats.t.ppf(gamma, m - 1)) * s / math.sqrt(m) < gap, max(n + 1, 2))
                except InputError:
                    need = None
        how = "Student t (assumes a near-normal sample mean; not distribution-free)"
        detail = f"mean {est:.6g}; one-sided {gamma * 100:g} % bounds {min(bound, opposite):.6g} .. {max(bound, opposite):.6g}"
    if n_nan:
        detail += f"; {n_nan} NaN sample(s) counted as violating"
    verdict = outcome if outcome != "inconclusive" else (
        f"inconclusive (need ~{need} samples)" if need is not None else "inconclusive")
    return RequirementVerdict(requirement=req, outcome=outcome, verdict=verdict, n=n, n_nan=n_nan,
                              n_violating=violating, estimate=est, bound=float(bound), opposite_bound=float(opposite),
                              n_needed=need, method=how, detail=detail)


def check_requirements(
    requirements: Any,
    metrics: Any,
    *,
    metrics_from_s: Any = None,
    method: str = "clopper-pearson",
    nan_policy: str = "raise",
) -> RequirementTable:
    """Check a requirement table against per-sample metrics: met, not met or inconclusive.

    Each requirement is decided by its confidence bounds, symmetrically: **met** if the
    bound on the favourable side satisfies the comparison (e.g. the upper 95 % bound on the
    p99 is ``<= 0.1``), **not met** if the bound on the other side violates it (the lower
    95 % bound is ``> 0.1``), else **inconclusive**, with about how many samples would decide
    it if the observed rate held. A point estimate alone never decides. ``max``/``min``
    requirements are judged on every sample (one violating sample is "not met").

    Parameters
    ----------
    requirements : str, os.PathLike, mapping or iterable
        Anything :func:`read_requirements` reads (a list of one-line strings, a TOML path, ...).
    metrics : mapping of str to array_like (n,)
        Per-sample values by metric name, e.g. ``SimulationResult.metrics`` of
        :func:`adcskit.simulation.simulate`.
    metrics_from_s : float or mapping of str to float, s, optional
        Start of the time window over which the metrics were computed (the simulator's
        ``SimSpec.metrics_from_s``; a mapping names the windowed metrics only, e.g. the
        ``pointing_*`` and ``knowledge_rms_deg`` metrics of the simulator, whose
        ``settling_time_s`` or ``propellant_kg`` cover the whole run). A requirement with
        ``after_s`` is checked only on a metric whose window starts exactly there: per-sample
        summaries over another window cannot be re-windowed (an RMS over ``[50, end]`` s says
        nothing exact about ``[300, end]`` s), so any other case raises
        :class:`~adcskit.errors.InputError` (re-run with ``metrics_from_s = after_s``).
    method : {"clopper-pearson", "wilson"}
        Interval of ``probability`` requirements. Clopper–Pearson (default) has at least the
        stated coverage; Wilson is shorter but only approximately covers.
    nan_policy : {"raise", "fail"}
        A NaN value (e.g. ``settling_time_s`` of a sample that never settled) raises, or
        counts as a sample that violates the requirement (not allowed for ``mean``).

    Returns
    -------
    RequirementTable

    Raises
    ------
    InputError
        An unknown metric (the message lists the available ones), a window that does not
        match ``after_s``, NaN values under ``nan_policy="raise"``.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.uncertainty import check_requirements
    >>> rng = np.random.default_rng(1)
    >>> metrics = {"pointing_max_deg": rng.rayleigh(0.02, 500),      # deg, over [300, end] s
    ...            "settling_time_s": rng.normal(40.0, 5.0, 500)}
    >>> table = check_requirements(
    ...     ["pointing_max_deg p99 <= 0.1 after 300 s",
    ...      "pointing_max_deg p99 <= 0.05 after 300 s",
    ...      "pointing_max_deg p99 <= 0.06 after 300 s",
    ...      "P(settling_time_s > 60) <= 1 %"],
    ...     metrics, metrics_from_s={"pointing_max_deg": 300.0})
    >>> [row.verdict for row in table.rows]
    ['met', 'not met', 'inconclusive (need ~7653 samples)', 'met']
    >>> table.table_rows()[0]["requirement"]
    'pointing_max_deg p99 <= 0.1 after 300 s at 95 % confidence'
    """
    reqs = read_requirements(requirements)
    check_mapping("metrics", metrics)
    check_choice("method", method, PROPORTION_METHODS)
    check_choice("nan_policy", nan_policy, ("raise", "fail"))
    if metrics_from_s is not None and not isinstance(metrics_from_s, Mapping):
        metrics_from_s = check_range("metrics_from_s", metrics_from_s, 0.0, 1e12, unit="s")
    elif isinstance(metrics_from_s, Mapping):
        metrics_from_s = {str(k): check_range(f"metrics_from_s[{k!r}]", w, 0.0, 1e12, unit="s")
                          for k, w in metrics_from_s.items()}
    rows = []
    for req in reqs:
        check_choice(f"metric of requirement {req.text!r}", req.metric, [str(k) for k in metrics])
        if req.after_s is not None:
            window = metrics_from_s.get(req.metric) if isinstance(metrics_from_s, dict) else metrics_from_s
            if window is None:
                raise InputError(
                    f"requirement {req.text!r} holds after {req.after_s:g} s but the time window of metric "
                    f"{req.metric!r} is unknown: pass metrics_from_s (the simulator's SimSpec.metrics_from_s) "
                    "for a metric computed over [after_s, end] s")
            if not math.isclose(window, req.after_s, rel_tol=1e-9, abs_tol=1e-9):
                raise InputError(
                    f"requirement {req.text!r} needs metric {req.metric!r} over [{req.after_s:g}, end] s; got it over "
                    f"[{window:g}, end] s (a per-sample summary cannot be re-windowed: re-run with "
                    f"metrics_from_s = {req.after_s:g} s, or compute it from the traces)")
        v = as_array(f"metrics[{req.metric!r}]", metrics[req.metric], finite=False, max_abs=None)
        if v.ndim != 1:
            raise InputError(f"metrics[{req.metric!r}] must be 1-D (one value per sample); got shape {v.shape}")
        nan = np.isnan(v)
        n_nan = int(nan.sum())
        if n_nan:
            if nan_policy == "raise":
                raise InputError(
                    f"metrics[{req.metric!r}] must not contain NaN under nan_policy='raise'; got {n_nan} NaN of "
                    f"{v.size} (pass nan_policy='fail' to count them as violating the requirement)")
            if req.statistic == "mean":
                raise InputError(f"nan_policy='fail' cannot be applied to a 'mean' requirement ({req.text!r}); "
                                 f"metrics[{req.metric!r}] has {n_nan} NaN")
            v = v.copy()
            if req.statistic == "probability":  # NaN counts as the bad outcome of the event
                event_is_bad = req.comparison in ("<=", "<")
                event_up = req.event in (">", ">=")
                v[nan] = math.inf if event_is_bad == event_up else -math.inf
            else:
                v[nan] = math.inf if req.comparison in ("<=", "<") else -math.inf
        rows.append(_evaluate(req, v, n_nan, method))
    n_met = sum(r.outcome == "met" for r in rows)
    n_not = sum(r.outcome == "not met" for r in rows)
    n_inc = len(rows) - n_met - n_not
    return RequirementTable(rows=tuple(rows), n_met=n_met, n_not_met=n_not, n_inconclusive=n_inc,
                            success=n_met == len(rows),
                            message=f"{n_met} met, {n_not} not met, {n_inc} inconclusive of {len(rows)} requirements")
