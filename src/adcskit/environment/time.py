"""Time handling: UTC instants, Julian dates and Greenwich mean sidereal time.

Instants are ``numpy.datetime64[ns]`` arrays on the UTC time scale. Leap seconds are not
modelled (numpy's ``datetime64`` has none), UT1 is taken equal to UTC (``|UT1 - UTC| < 0.9 s``,
i.e. an Earth-rotation error below 14 arcsec), and TT/TDB is taken equal to UT1 where the
low-precision algorithms below ask for it (Vallado 2013, sec. 5.1.1 does the same).

Hand-written because the kept libraries offer no vectorised IAU-82 GMST: ``sgp4`` has a scalar
``gstime`` only, and an astropy-class dependency would be out of scale for one formula.

References
----------
.. [1] D. A. Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed., Microcosm
   Press, 2013: eq. 3-43 (Julian date), eq. 3-47 (GMST, IAU-82), Example 3-5.
"""

from __future__ import annotations

import datetime as _dt
from typing import Any

import numpy as np

from adcskit._validation import as_array, short_repr
from adcskit.errors import InputError, InputTypeError

__all__ = [
    "J2000",
    "as_utc",
    "utc_times",
    "julian_date",
    "julian_centuries",
    "gmst",
    "decimal_year",
]

#: J2000.0 epoch, 2000-01-01 12:00:00 (taken on the UTC scale, see the module docstring).
J2000 = np.datetime64("2000-01-01T12:00:00", "ns")
_UNIX_EPOCH_JD = 2440587.5
_NS_PER_DAY = 86_400 * 10**9


def _strip_z(text: str) -> str:
    # numpy parses a trailing "Z" (UTC designator) with a DeprecationWarning; it is UTC anyway.
    return text[:-1] if text.endswith(("Z", "z")) else text


def as_utc(times: Any, name: str = "times") -> np.ndarray:
    """Convert UTC instants to a ``datetime64[ns]`` array.

    Parameters
    ----------
    times : datetime64, datetime, ISO-8601 str, or array_like of these
        UTC instants. Timezone-aware ``datetime`` objects are converted to UTC; naive ones
        and strings are read as UTC (a trailing ``Z`` is accepted; other UTC offsets are
        not). Numbers are refused (seconds or Julian days would be
        ambiguous): use :func:`utc_times` for an epoch plus offsets in seconds.
    name : str
        Parameter name for error messages.

    Returns
    -------
    numpy.ndarray of datetime64[ns]
        Same shape as the input (0-d for a single instant).

    Examples
    --------
    >>> from adcskit.environment import as_utc
    >>> as_utc("2024-03-20T03:06:00Z")
    array('2024-03-20T03:06:00.000000000', dtype='datetime64[ns]')
    >>> as_utc(["2024-01-01", "2024-01-02T12:00"]).shape
    (2,)
    """
    value = times
    if isinstance(value, _dt.datetime) and value.tzinfo is not None:
        value = value.astimezone(_dt.UTC).replace(tzinfo=None)
    elif isinstance(value, list | tuple):
        value = [
            v.astimezone(_dt.UTC).replace(tzinfo=None)
            if isinstance(v, _dt.datetime) and v.tzinfo is not None
            else v
            for v in value
        ]
    if isinstance(value, str):
        value = _strip_z(value)
    elif isinstance(value, list | tuple):
        value = [_strip_z(v) if isinstance(v, str) else v for v in value]
    arr = np.asarray(value)
    if arr.dtype.kind in "iufcb":
        raise InputTypeError(
            f"{name} must be UTC instants (numpy datetime64, datetime or ISO-8601 strings); "
            f"got numbers {short_repr(times)} — use utc_times(epoch, t_seconds) for offsets"
        )
    try:
        out = arr.astype("datetime64[ns]")
        coarse = arr.astype("datetime64[s]")  # wide range: detects silent ns wrap-around
    except (TypeError, ValueError, OverflowError) as exc:
        raise InputTypeError(
            f"{name} must be UTC instants (numpy datetime64, datetime or ISO-8601 strings); "
            f"got {short_repr(times)} ({exc})"
        ) from None
    if out.size == 0:
        raise InputError(f"{name} must not be empty; got shape {out.shape}")
    if np.any(np.isnat(out)) or np.any(np.isnat(coarse)):
        raise InputError(f"{name} must not contain NaT (not-a-time); got {short_repr(times)}")
    _check_ns_range(name, out, coarse, times)
    return out


#: Instants representable as datetime64[ns]: 1678-01-01 .. 2262-04-11 (numpy's int64 range).
_NS_MIN = np.datetime64("1678-01-01T00:00:00", "s")
_NS_MAX = np.datetime64("2262-04-11T00:00:00", "s")


def _check_ns_range(name: str, out: np.ndarray, coarse: np.ndarray, original: Any) -> None:
    bad = (coarse < _NS_MIN) | (coarse > _NS_MAX) | (out.astype("datetime64[s]") != coarse)
    if np.any(bad):
        raise InputError(
            f"{name} must be between 1678-01-01 and 2262-04-11 UTC (the range of datetime64[ns]); "
            f"got {short_repr(original)}"
        )


def utc_times(epoch: Any, t: Any) -> np.ndarray:
    """UTC instants ``epoch + t``.

    Parameters
    ----------
    epoch : datetime64, datetime or ISO-8601 str
        One UTC instant.
    t : float or array_like of float, s
        Offsets from ``epoch`` in seconds (rounded to the nanosecond).

    Returns
    -------
    numpy.ndarray of datetime64[ns]
        Shape of ``t``.

    Examples
    --------
    >>> utc_times("2024-03-20T00:00:00", [0.0, 60.0])[1]
    np.datetime64('2024-03-20T00:01:00.000000000')
    """
    ep = as_utc(epoch, "epoch")
    if ep.ndim != 0:
        raise InputError(f"epoch must be one instant; got shape {ep.shape}")
    tt = as_array("t", t, nonempty=False)
    # offsets must keep epoch + t inside datetime64[ns] (int64 nanoseconds, about ±292 years)
    if tt.size and np.abs(tt).max() > 9e9:
        raise InputError(f"t must be offsets of magnitude <= 9e9 s (datetime64[ns] range); "
                         f"got max |t| = {np.abs(tt).max():g}")
    dt = np.round(tt * 1e9).astype("timedelta64[ns]")
    when = ep.astype("datetime64[s]").astype(np.int64) + tt  # seconds since 1970, as floats
    if tt.size and (np.any(when < _NS_MIN.astype(np.int64)) or np.any(when > _NS_MAX.astype(np.int64))):
        raise InputError(f"t must keep epoch + t between 1678-01-01 and 2262-04-11 UTC; got t in "
                         f"[{tt.min():g}, {tt.max():g}] s from epoch {ep}")
    return ep + dt


def _days_since_j2000(times: np.ndarray) -> np.ndarray:
    # Integer nanosecond difference first: no float64 rounding of the ~2.45e6 Julian date.
    return (times - J2000).astype(np.int64) / _NS_PER_DAY


def julian_date(times: Any) -> np.ndarray:
    """Julian date of UTC instants (UT1 = UTC).

    Parameters
    ----------
    times : datetime-like or array_like
        UTC instants (see :func:`as_utc`).

    Returns
    -------
    numpy.ndarray of float, days
        Julian date, same shape as ``times``. Float64 resolves ~40 microseconds at current
        dates; internal computations use days from J2000 instead to keep full precision.

    References
    ----------
    Vallado (2013), eq. 3-43; the J2000 epoch is JD 2451545.0.

    Examples
    --------
    >>> from adcskit.environment import julian_date
    >>> float(julian_date("2000-01-01T12:00:00"))               # J2000.0
    2451545.0
    >>> julian_date(["2024-01-01", "2024-01-02"])
    array([2460310.5, 2460311.5])
    """
    return 2451545.0 + _days_since_j2000(as_utc(times))


def julian_centuries(times: Any) -> np.ndarray:
    """Julian centuries since J2000.0, ``T = (JD - 2451545.0) / 36525`` (Vallado eq. 3-42).

    Examples
    --------
    >>> from adcskit.environment import julian_centuries
    >>> float(julian_centuries("2000-01-01T12:00:00"))          # J2000.0
    0.0
    >>> round(float(julian_centuries("2050-01-01T12:00:00")), 6)
    0.500014
    """
    return _days_since_j2000(as_utc(times)) / 36525.0


def _gmst_from_days(d: np.ndarray) -> np.ndarray:
    T = d / 36525.0
    # Vallado eq. 3-47 in seconds; the 876600 h * 3600 s term is written as whole turns
    # (36525 days of 86400 s) plus the fractional day to keep precision.
    frac_day = np.mod(d, 1.0)
    sec = (
        67310.54841
        + 8640184.812866 * T
        + 0.093104 * T**2
        - 6.2e-6 * T**3
        + frac_day * 86400.0  # 876600 h * 3600 * T = 86400 * d; whole days drop out mod 86400
    )
    return np.mod(sec, 86400.0) * (2.0 * np.pi / 86400.0)


def gmst(times: Any) -> np.ndarray:
    """Greenwich mean sidereal time (IAU-82), radians in [0, 2π).

    Parameters
    ----------
    times : datetime-like or array_like
        UTC instants (UT1 = UTC assumed).

    Returns
    -------
    numpy.ndarray of float, rad
        Same shape as ``times``.

    References
    ----------
    Vallado (2013), eq. 3-47 (IAU-82 GMST); Example 3-5 (1992-08-20 12:14 UT1 ->
    152.578787810 deg) is a test oracle.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import gmst
    >>> round(float(np.degrees(gmst("1992-08-20T12:14:00"))), 6)   # Vallado (2013), Example 3-5
    152.578788
    >>> gmst(["2024-01-01", "2024-01-02"]).shape
    (2,)
    """
    return _gmst_from_days(_days_since_j2000(as_utc(times)))


def decimal_year(times: Any) -> np.ndarray:
    """Decimal year of UTC instants (``2025.0`` is 2025-01-01 00:00 UTC).

    Examples
    --------
    >>> from adcskit.environment import decimal_year
    >>> float(decimal_year("2025-01-01T00:00:00"))
    2025.0
    >>> round(float(decimal_year("2024-07-02T00:00:00")), 4)
    2024.5
    """
    t = as_utc(times)
    year = t.astype("datetime64[Y]")
    start = year.astype("datetime64[ns]")
    end = (year + np.timedelta64(1, "Y")).astype("datetime64[ns]")
    return (year.astype(np.int64) + 1970) + (t - start).astype(np.int64) / (end - start).astype(
        np.int64
    )
