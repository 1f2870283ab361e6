"""Distributions of uncertain parameters and Latin-hypercube sampling of them.

The Latin hypercube comes from :class:`scipy.stats.qmc.LatinHypercube`; each column of the
unit hypercube is mapped through the inverse CDF of its distribution (``scipy.stats.norm``
or ``scipy.stats.truncnorm``). Only the small distribution records are written here.

References
----------
S4, Table 5 (Gaussian uncertainties) and Fig. 11 (LHS of the inertia, 1000 samples).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from scipy import stats
from scipy.stats import qmc

from adcskit._results import Result
from adcskit._validation import (
    as_array,
    as_rng,
    check_finite,
    check_int,
    check_positive,
    check_real,
    short_repr,
)
from adcskit.errors import InputError, InputTypeError

__all__ = ["Gaussian", "TruncatedGaussian", "Fixed", "latin_hypercube", "SampleStats", "sample_stats"]


class _Distribution(Result):
    """Base of the distribution records: ``to_dict`` is ``{"kind": ..., **fields}``."""

    __slots__ = ()

    #: The ``kind`` tag that leads the dictionary.
    _kind: ClassVar[str] = ""

    def to_dict(self) -> dict[str, Any]:
        """``{"kind": tag}`` followed by every field (converted by ``to_jsonable``)."""
        return {"kind": self._kind, **Result.to_dict(self)}


@dataclass(frozen=True, slots=True, kw_only=True)
class Gaussian(_Distribution):
    """Normal distribution ``N(mean, std²)``.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.uncertainty import Gaussian
    >>> g = Gaussian(mean=10.0, std=1.0)                  # inertia, kg m^2
    >>> g.ppf(np.array([0.5, 0.975])).round(4)           # quantile function
    array([10.  , 11.96])
    """

    mean: float
    std: float

    def __post_init__(self) -> None:
        check_finite("mean", self.mean)
        check_positive("std", self.std, allow_zero=True)

    def ppf(self, u: np.ndarray) -> np.ndarray:
        """Inverse CDF at ``u`` in (0, 1)."""
        u = _probabilities(u)
        if self.std == 0.0:
            return np.full(np.shape(u), float(self.mean))
        return stats.norm.ppf(u, loc=self.mean, scale=self.std)

    _kind = "gaussian"


@dataclass(frozen=True, slots=True, kw_only=True)
class TruncatedGaussian(_Distribution):
    """Normal distribution ``N(mean, std²)`` restricted to ``[low, high]`` (renormalised).

    Used for parameters that must keep their sign (delay and inertia stay positive). Note
    that ``mean`` and ``std`` are those of the parent normal, not of the truncated law.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.uncertainty import TruncatedGaussian
    >>> delay = TruncatedGaussian(mean=0.02, std=0.02, low=0.0)   # s, kept positive
    >>> x = delay.ppf(np.array([0.001, 0.5, 0.9]))           # quantiles
    >>> bool(np.all(x >= 0.0)), (1e3 * x).round(2)                 # ms
    (True, array([ 0.07, 24.  , 47.56]))
    """

    mean: float
    std: float
    low: float = -math.inf
    high: float = math.inf

    def __post_init__(self) -> None:
        check_finite("mean", self.mean)
        check_positive("std", self.std, allow_zero=True)
        check_real("low", self.low)
        check_real("high", self.high)
        if not (self.low < self.high):
            raise InputError(f"low must be < high; got low={self.low!r}, high={self.high!r}")
        if self.std == 0.0 and not (self.low <= self.mean <= self.high):
            raise InputError(f"mean must be in [low, high] when std = 0; got {self.mean!r}")

    def ppf(self, u: np.ndarray) -> np.ndarray:
        """Inverse CDF at ``u`` in (0, 1)."""
        u = _probabilities(u)
        if self.std == 0.0:
            return np.full(np.shape(u), float(self.mean))
        a = (self.low - self.mean) / self.std
        b = (self.high - self.mean) / self.std
        x = stats.truncnorm.ppf(u, a, b, loc=self.mean, scale=self.std)
        if not np.all(np.isfinite(x)):
            # [low, high] is narrower than float64 resolves in units of std, or holds no
            # probability mass that float64 can represent
            raise InputError(
                f"low and high must span a representable part of N(mean, std^2); got "
                f"low={self.low!r}, high={self.high!r} (mean={self.mean!r}, std={self.std!r}: "
                f"standardised bounds {a:.6g}, {b:.6g}), which give non-finite quantiles"
            )
        return x

    _kind = "truncated_gaussian"


@dataclass(frozen=True, slots=True, kw_only=True)
class Fixed(_Distribution):
    """A parameter without uncertainty (a point mass).

    Examples
    --------
    >>> from adcskit.uncertainty import Fixed, latin_hypercube
    >>> latin_hypercube({"torque": Fixed(value=1.0)}, 3, rng=0)["torque"]
    array([1., 1., 1.])
    """

    value: float

    def __post_init__(self) -> None:
        check_finite("value", self.value)

    def ppf(self, u: np.ndarray) -> np.ndarray:
        """Inverse CDF at ``u`` in (0, 1): ``value`` everywhere."""
        return np.full(np.shape(_probabilities(u)), float(self.value))

    _kind = "fixed"


_DISTS = (Gaussian, TruncatedGaussian, Fixed)


def _probabilities(u: Any) -> np.ndarray:
    """``u`` as a float array of probabilities in the open interval (0, 1)."""
    arr = as_array("u", u, nonempty=False)
    if np.any((arr <= 0) | (arr >= 1)):
        raise InputError(f"u must hold probabilities in (0, 1) (the quantiles at 0 and 1 are infinite); "
                         f"got range [{arr.min():g}, {arr.max():g}]")
    return arr


def latin_hypercube(
    dists: Mapping[str, Gaussian | TruncatedGaussian | Fixed], n: int, rng: Any = None
) -> dict[str, np.ndarray]:
    """Draw ``n`` Latin-hypercube samples of independent parameters.

    Parameters
    ----------
    dists : mapping of str to Gaussian, TruncatedGaussian or Fixed
        One distribution per parameter name.
    n : int
        Number of samples (every marginal gets exactly one sample per ``1/n`` quantile bin).
    rng : Generator or int, optional
        Randomness (``None`` → seed 0).

    Returns
    -------
    dict of str to ndarray (n,)
        The samples, in the order of ``dists``.

    References
    ----------
    S4, Fig. 11 (LHS of the Gaussian inertia, 1000 samples); McKay, Beckman & Conover (1979).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.uncertainty import Fixed, Gaussian, latin_hypercube
    >>> dists = {"inertia": Gaussian(mean=10.0, std=1.0), "torque": Fixed(value=1.0)}
    >>> s = latin_hypercube(dists, 4, rng=0)
    >>> list(s), s["inertia"].shape
    (['inertia', 'torque'], (4,))
    >>> from scipy.stats import norm
    >>> np.sort(np.floor(4 * norm.cdf(s["inertia"], 10.0, 1.0)))   # one sample per quartile bin
    array([0., 1., 2., 3.])
    """
    if not isinstance(dists, Mapping) or not dists:
        raise InputTypeError(f"dists must be a non-empty mapping of name -> distribution; got {dists!r}")
    for name, d in dists.items():
        if not isinstance(d, _DISTS):
            raise InputTypeError(
                f"dists[{name!r}] must be a Gaussian, TruncatedGaussian or Fixed; got {type(d).__name__}"
            )
    n = check_int("n", n, minimum=1, maximum=10**8)
    gen = as_rng(rng)
    unit = qmc.LatinHypercube(d=len(dists), rng=gen).random(n)
    return {name: np.asarray(d.ppf(unit[:, j]), dtype=float) for j, (name, d) in enumerate(dists.items())}


@dataclass(frozen=True, slots=True, kw_only=True)
class SampleStats(Result):
    """Summary statistics of a sample (``std`` with ``ddof=1``).

    Examples
    --------
    >>> from adcskit.uncertainty import sample_stats
    >>> s = sample_stats([1.0, 2.0, 3.0, 4.0])
    >>> type(s).__name__, s.n, s.mean, round(s.std, 6), s.p50
    ('SampleStats', 4, 2.5, 1.290994, 2.5)
    """

    n: int
    mean: float
    std: float
    min: float
    max: float
    p05: float
    p50: float
    p95: float


def sample_stats(x: Any) -> SampleStats:
    """Mean, standard deviation (``ddof=1``), extremes and 5/50/95 % quantiles of ``x``.

    NaN and infinite entries are ignored; ``n`` counts the finite ones. An input without any
    finite value raises :class:`~adcskit.errors.InputError` (there is nothing to summarise).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.uncertainty import sample_stats
    >>> x = np.random.default_rng(0).normal(10.0, 1.0, 1000)
    >>> s = sample_stats(np.append(x, np.nan))            # NaN is ignored
    >>> s.n, round(s.mean, 1), round(s.std, 1)
    (1000, 10.0, 1.0)
    >>> sorted(s.to_dict())
    ['max', 'mean', 'min', 'n', 'p05', 'p50', 'p95', 'std']
    """
    arr = as_array("x", x, finite=False, nonempty=False).ravel()
    arr = arr[np.isfinite(arr)]
    if arr.size == 0:
        raise InputError(f"x must contain at least one finite value; got {short_repr(x)}")
    q = np.quantile(arr, [0.05, 0.5, 0.95])
    return SampleStats(
        n=int(arr.size),
        mean=float(arr.mean()),
        std=float(arr.std(ddof=1)) if arr.size > 1 else 0.0,
        min=float(arr.min()),
        max=float(arr.max()),
        p05=float(q[0]),
        p50=float(q[1]),
        p95=float(q[2]),
    )
