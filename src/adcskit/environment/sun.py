"""Sun position: Vallado's low-precision analytical algorithm (Alg. 29, "SUN").

Accuracy 0.01 deg for 1950-2050 (Vallado's statement, from the Astronomical Almanac series it
is taken from). The result is in the mean-of-date equatorial frame, which differs from
adcskit's ECI (TEME, see :mod:`adcskit.environment.frames`) by nutation only (< 0.006 deg) —
inside the algorithm's own error, so no rotation is applied. The Sun is treated as seen from
the Earth's centre; from a LEO spacecraft the parallax is at most 7000 km / 1 AU = 0.0027 deg.

Hand-written because no kept library has it (``sgp4`` has no ephemerides; a JPL-ephemeris
dependency would be out of scale for a 0.01 deg reference direction).

References
----------
.. [1] D. A. Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed., 2013,
   Algorithm 29 (SUN), sec. 5.1.1, Example 5-1.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from adcskit.environment.time import _days_since_j2000, as_utc

__all__ = ["AU", "sun_position", "sun_direction", "in_shadow"]

AU = 149_597_870_700.0  #: astronomical unit, m (IAU 2012)


def _sun_mod_au(days: np.ndarray) -> np.ndarray:
    """Vallado Alg. 29 on days since J2000 (T_UT1 = T_TDB), returns (..., 3) in AU."""
    T = days / 36525.0
    deg = np.pi / 180.0
    lam_m = (280.460 + 36000.771 * T) * deg  # mean longitude
    M = (357.5291092 + 35999.05034 * T) * deg  # mean anomaly
    lam = lam_m + (1.914666471 * np.sin(M) + 0.019994643 * np.sin(2.0 * M)) * deg  # ecliptic lon
    dist = 1.000140612 - 0.016708617 * np.cos(M) - 0.000139589 * np.cos(2.0 * M)  # AU
    eps = (23.439291 - 0.0130042 * T) * deg  # mean obliquity
    return np.stack(
        [dist * np.cos(lam), dist * np.cos(eps) * np.sin(lam), dist * np.sin(eps) * np.sin(lam)],
        axis=-1,
    )


def sun_position(times: Any) -> np.ndarray:
    """Earth-to-Sun vector in ECI, m.

    Parameters
    ----------
    times : datetime-like or array_like, shape () or (N,)
        UTC instants (numpy datetime64, datetime, ISO strings; see
        :func:`adcskit.environment.time.as_utc`).

    Returns
    -------
    numpy.ndarray, m, shape (3,) or (N, 3)

    References
    ----------
    Vallado (2013), Algorithm 29 and Example 5-1 (2006-04-02 00:00 UTC:
    r = [0.9771945, 0.1924424, 0.0834308] AU).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import sun_position
    >>> au = 149597870700.0
    >>> (sun_position("2006-04-02T00:00:00") / au).round(4)   # Vallado (2013), Example 5-1
    array([0.9772, 0.1924, 0.0834])
    >>> sun_position(["2024-01-01", "2024-07-01"]).shape
    (2, 3)
    """
    return _sun_mod_au(_days_since_j2000(as_utc(times))) * AU


def sun_direction(times: Any) -> np.ndarray:
    """Unit vector from the Earth's centre to the Sun in ECI.

    Parameters
    ----------
    times : datetime-like or array_like, shape () or (N,)
        UTC instants.

    Returns
    -------
    numpy.ndarray, shape (3,) or (N, 3)
        Unit vectors; accuracy 0.01 deg (Vallado 2013, Alg. 29).

    Examples
    --------
    >>> s = sun_direction(["2024-03-20T03:06", "2024-06-20T20:51"])  # equinox, solstice
    >>> bool(abs(s[0, 2]) < 1e-3), bool(s[1, 2] > 0.39)
    (True, True)

    References
    ----------
    Vallado (2013), Algorithm 29 (SUN).
    """
    r = _sun_mod_au(_days_since_j2000(as_utc(times)))
    return r / np.linalg.norm(r, axis=-1, keepdims=True)


def in_shadow(r_eci: Any, times: Any, *, radius: float = 6378137.0) -> np.ndarray:
    """Whether positions are in the Earth's shadow (cylindrical model, no penumbra).

    A point is in shadow when it is behind the Earth (``r . s < 0``) and within ``radius`` of
    the Earth-Sun line (``|r - (r . s) s| < radius``), ``s`` = :func:`sun_direction`.

    Parameters
    ----------
    r_eci : array_like, m, shape (3,) or (N, 3)
        ECI positions.
    times : datetime-like or array_like, shape () or (N,)
        UTC instants, one or one per position.
    radius : float, m
        Shadow cylinder radius (WGS-84 equatorial radius by default).

    Returns
    -------
    numpy.ndarray of bool, shape () or (N,)

    References
    ----------
    Vallado (2013), sec. 5.3 and Algorithm 34 (SHADOW), cylindrical variant.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import in_shadow, sun_position
    >>> t = "2024-03-20T12:00:00"
    >>> s = sun_position(t) / np.linalg.norm(sun_position(t))
    >>> in_shadow(np.array([7000e3 * s, -7000e3 * s]), [t, t])   # sunward side lit, far side dark
    array([False,  True])
    """
    from adcskit._validation import as_batch, check_positive
    from adcskit.errors import InputError

    R = check_positive("radius", radius, unit="m")
    r, batched = as_batch("r_eci", r_eci, (3,))
    t = as_utc(times)
    if t.ndim > 1:
        raise InputError(f"times must be one instant or a 1-D array; got shape {t.shape}")
    s = np.atleast_2d(sun_direction(t))
    if len(s) not in (1, len(r)) and len(r) != 1:
        raise InputError(
            f"times must have one instant or as many as r_eci has rows ({len(r)}); got {len(s)}"
        )
    along = np.sum(r * s, axis=1)
    perp = np.linalg.norm(r - along[:, None] * s, axis=1)
    out = (along < 0) & (perp < R)
    return out if (batched or t.ndim == 1) else out[0]
