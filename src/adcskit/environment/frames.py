"""Reference frames: ECI <-> ECEF, geodetic/geocentric coordinates, NED/ENU -> ECEF.

Frames
------
ECEF
    Earth-fixed, Greenwich meridian / equator; polar motion is neglected (it is the
    pseudo-Earth-fixed frame PEF of Vallado 2013, sec. 3.7).
ECI
    adcskit's inertial frame is defined by ``r_ECEF = R3(GMST) r_ECI`` with the IAU-82
    GMST of :func:`adcskit.environment.time.gmst`. That is exactly the TEME frame of SGP4
    (Vallado et al. 2006, "Revisiting Spacetrack Report #3", sec. on TEME), so SGP4 states are
    used without conversion. It differs from the mean-of-date frame of the sun algorithm by
    nutation (< 0.006 deg) and from GCRF/J2000 by precession (~0.014 deg per year since 2000,
    ~0.36 deg in 2026): irrelevant for attitude determination as long as every reference vector
    comes from this module, but not negligible against external J2000 data.

Hand-written (a handful of closed forms) because scipy has no geodesy; the geodetic inverse is
Bowring's iteration (converges to < 1e-9 m in three steps for |h| < 1e6 m).

References
----------
.. [1] D. A. Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed., 2013,
   sec. 3.2-3.7 (geodetic coordinates, eq. 3-14; Earth rotation).
.. [2] NIMA TR8350.2, *Department of Defense World Geodetic System 1984*, 3rd ed., 2000
   (a = 6378137 m, 1/f = 298.257223563, omega = 7.292115e-5 rad/s).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from adcskit._validation import as_array, as_batch
from adcskit.constants import OMEGA_EARTH, R_EARTH
from adcskit.environment.time import as_utc, gmst
from adcskit.errors import InputError

__all__ = [
    "WGS84_A",
    "WGS84_F",
    "WGS84_E2",
    "EARTH_ROTATION_RATE",
    "eci_to_ecef_matrix",
    "eci_to_ecef",
    "ecef_to_eci",
    "eci_to_ecef_state",
    "ecef_to_eci_state",
    "geodetic_to_ecef",
    "ecef_to_geodetic",
    "ecef_to_geocentric",
    "geocentric_to_ecef",
    "ned_to_ecef_matrix",
    "enu_to_ecef_matrix",
]

WGS84_A = R_EARTH  #: WGS-84 equatorial radius, m (adcskit.constants)
WGS84_F = 1.0 / 298.257223563  #: WGS-84 flattening
WGS84_E2 = WGS84_F * (2.0 - WGS84_F)  #: WGS-84 first eccentricity squared
EARTH_ROTATION_RATE = OMEGA_EARTH  #: Earth rotation rate (WGS-84), rad/s (adcskit.constants)


def _rot3(angle: np.ndarray) -> np.ndarray:
    """Frame rotation R3(angle) (Vallado eq. 3-15), batched: (N,) -> (N, 3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    out = np.zeros((*np.shape(angle), 3, 3))
    out[..., 0, 0], out[..., 0, 1] = c, s
    out[..., 1, 0], out[..., 1, 1] = -s, c
    out[..., 2, 2] = 1.0
    return out


def eci_to_ecef_matrix(times: Any) -> np.ndarray:
    """Rotation matrix ``R`` with ``r_ECEF = R @ r_ECI``: ``R3(GMST)``.

    Parameters
    ----------
    times : datetime-like or array_like
        UTC instants.

    Returns
    -------
    numpy.ndarray, shape (3, 3) or (N, 3, 3)

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import eci_to_ecef_matrix
    >>> R = eci_to_ecef_matrix("2024-03-20T12:00:00")
    >>> R.shape, np.allclose(R @ R.T, np.eye(3)), float(R[2, 2])
    ((3, 3), True, 1.0)
    >>> eci_to_ecef_matrix(["2024-03-20", "2024-03-21"]).shape
    (2, 3, 3)
    """
    return _rot3(gmst(times))


def _vectors_and_times(r: Any, times: Any, name: str) -> tuple[np.ndarray, np.ndarray, bool]:
    vec, batched = as_batch(name, r, (3,))
    t = as_utc(times)
    if t.ndim > 1:
        raise InputError(f"times must be one instant or a 1-D array; got shape {t.shape}")
    n_t = 1 if t.ndim == 0 else t.shape[0]
    if n_t != 1 and vec.shape[0] != 1 and n_t != vec.shape[0]:
        raise InputError(
            f"times must have one instant or as many as {name} has rows ({vec.shape[0]}); "
            f"got {n_t}"
        )
    return vec, np.atleast_1d(t), batched or t.ndim == 1


def _transform(R: np.ndarray, vec: np.ndarray, batched: bool) -> np.ndarray:
    out = np.einsum("nij,nj->ni", np.broadcast_to(R, (max(len(R), len(vec)), 3, 3)),
                    np.broadcast_to(vec, (max(len(R), len(vec)), 3)))
    return out if batched else out[0]


def eci_to_ecef(r_eci: Any, times: Any) -> np.ndarray:
    """Rotate position vectors from ECI to ECEF.

    Parameters
    ----------
    r_eci : array_like, shape (3,) or (N, 3)
        Vectors in ECI (any unit; returned in the same unit).
    times : datetime-like or array_like, shape () or (N,)
        UTC instants, one or one per row.

    Returns
    -------
    numpy.ndarray, shape (3,) or (N, 3)
        ``R3(GMST) r``. Velocities need the extra ``-omega x r`` term, which this function
        does not add.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import eci_to_ecef, gmst
    >>> t = "2024-03-20T12:00:00"
    >>> r = eci_to_ecef([7000e3, 0.0, 0.0], t)
    >>> np.allclose(r, 7000e3 * np.array([np.cos(gmst(t)), -np.sin(gmst(t)), 0.0]))
    True
    >>> eci_to_ecef(np.ones((4, 3)), ["2024-03-20T12:00:00"] * 4).shape
    (4, 3)
    """
    vec, t, batched = _vectors_and_times(r_eci, times, "r_eci")
    return _transform(_rot3(gmst(t)), vec, batched)


def ecef_to_eci(r_ecef: Any, times: Any) -> np.ndarray:
    """Rotate position vectors from ECEF to ECI (inverse of :func:`eci_to_ecef`).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import ecef_to_eci, eci_to_ecef
    >>> t = "2024-03-20T12:00:00"
    >>> r_ecef = np.array([6778e3, 0.0, 0.0])
    >>> r_eci = ecef_to_eci(r_ecef, t)
    >>> np.allclose(eci_to_ecef(r_eci, t), r_ecef)
    True
    >>> round(float(np.linalg.norm(r_eci)), 3)       # a rotation keeps the length, m
    6778000.0
    """
    vec, t, batched = _vectors_and_times(r_ecef, times, "r_ecef")
    return _transform(np.swapaxes(_rot3(gmst(t)), -1, -2), vec, batched)


def eci_to_ecef_state(r_eci: Any, v_eci: Any, times: Any) -> tuple[np.ndarray, np.ndarray]:
    """Position and velocity from ECI to ECEF: ``r' = R r``, ``v' = R v - ω × r'``.

    Parameters
    ----------
    r_eci : array_like, m, shape (3,) or (N, 3)
    v_eci : array_like, m/s, same shape as ``r_eci``
    times : datetime-like or array_like, shape () or (N,)
        UTC instants.

    Returns
    -------
    r_ecef, v_ecef : numpy.ndarray
        ``ω = [0, 0, EARTH_ROTATION_RATE]`` (transport theorem; Vallado 2013, sec. 3.7).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import eci_to_ecef_state
    >>> r, v = eci_to_ecef_state([7000e3, 0.0, 0.0], [0.0, 7546.0, 0.0], "2024-03-20T12:00:00")
    >>> round(float(np.linalg.norm(v)), 3)           # 7546 m/s minus omega_E * 7000 km, m/s
    7035.552
    """
    r = eci_to_ecef(r_eci, times)
    v = eci_to_ecef(as_array("v_eci", v_eci, shape=as_array("r_eci", r_eci).shape), times)
    return r, v - np.cross(np.array([0.0, 0.0, EARTH_ROTATION_RATE]), r)


def ecef_to_eci_state(r_ecef: Any, v_ecef: Any, times: Any) -> tuple[np.ndarray, np.ndarray]:
    """Position and velocity from ECEF to ECI (inverse of :func:`eci_to_ecef_state`).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import ecef_to_eci_state
    >>> r, v = ecef_to_eci_state([6778e3, 0.0, 0.0], [0.0, 0.0, 0.0], "2024-03-20T12:00:00")
    >>> round(float(np.linalg.norm(v)), 3)   # an Earth-fixed point moves at omega r in ECI, m/s
    494.26
    """
    as_batch("r_ecef", r_ecef, (3,))  # r_ecef's own shape first, so a bad one is blamed on it
    rr = as_array("r_ecef", r_ecef)
    vv = as_array("v_ecef", v_ecef, shape=rr.shape)
    v_inertial_ecef = vv + np.cross(np.array([0.0, 0.0, EARTH_ROTATION_RATE]), rr)
    return ecef_to_eci(rr, times), ecef_to_eci(v_inertial_ecef, times)


def geodetic_to_ecef(lat: Any, lon: Any, h: Any = 0.0) -> np.ndarray:
    """WGS-84 geodetic coordinates to ECEF position.

    Parameters
    ----------
    lat, lon : float or array_like, rad
        Geodetic latitude in [-π/2, π/2] and longitude (east positive).
    h : float or array_like, m
        Height above the ellipsoid.

    Returns
    -------
    numpy.ndarray, m, shape ``(*broadcast_shape, 3)``

    References
    ----------
    Vallado (2013), eq. 3-14.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import geodetic_to_ecef
    >>> geodetic_to_ecef(0.0, 0.0, 0.0).round(3)                 # WGS-84 equatorial radius, m
    array([6378137.,       0.,       0.])
    >>> geodetic_to_ecef(np.radians([0.0, 90.0]), 0.0).round(3)   # pole at the polar radius
    array([[6378137.   ,       0.   ,       0.   ],
           [      0.   ,       0.   , 6356752.314]])
    """
    lat_, lon_, h_ = np.broadcast_arrays(as_array("lat", lat), as_array("lon", lon), as_array("h", h))
    if np.any(np.abs(lat_) > np.pi / 2 + 1e-12):
        raise InputError(f"lat must be in [-pi/2, pi/2] rad; got max |lat| = {np.max(np.abs(lat_)):g}")
    sl, cl = np.sin(lat_), np.cos(lat_)
    N = WGS84_A / np.sqrt(1.0 - WGS84_E2 * sl**2)
    return np.stack(
        [(N + h_) * cl * np.cos(lon_), (N + h_) * cl * np.sin(lon_), (N * (1.0 - WGS84_E2) + h_) * sl],
        axis=-1,
    )


def ecef_to_geodetic(r_ecef: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """ECEF position to WGS-84 geodetic latitude, longitude (rad) and height (m).

    Bowring's iteration from the geocentric guess (five fixed steps, vectorised).

    Parameters
    ----------
    r_ecef : array_like, m, shape (3,) or (N, 3)

    Returns
    -------
    lat, lon, h : numpy.ndarray
        Shapes () or (N,).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import ecef_to_geodetic, geodetic_to_ecef
    >>> r = geodetic_to_ecef(np.radians(45.0), np.radians(10.0), 500e3)
    >>> lat, lon, h = ecef_to_geodetic(r)
    >>> round(float(np.degrees(lat)), 9), round(float(np.degrees(lon)), 9), round(float(h), 3)
    (45.0, 10.0, 500000.0)
    """
    vec, batched = as_batch("r_ecef", r_ecef, (3,))
    if vec.shape[0] == 0:
        raise InputError("r_ecef must hold at least one position; got shape (0, 3)")
    # inside the evolute of the meridian ellipse (|r| < a e^2 / (1 - f), about 42.8 km from the
    # centre) the geodetic latitude is not unique; at the centre it is undefined
    rad = np.linalg.norm(vec, axis=1)
    r_min = WGS84_A * WGS84_E2 / (1.0 - WGS84_F)
    if np.any(rad < r_min):
        raise InputError(
            f"r_ecef must be at least {r_min / 1e3:.1f} km from the Earth's centre (geodetic "
            f"latitude is undefined or not unique closer in); got |r_ecef| = {rad.min():g} m"
        )
    x, y, z = vec.T
    p = np.hypot(x, y)
    lon = np.arctan2(y, x)
    b = WGS84_A * (1.0 - WGS84_F)
    ep2 = WGS84_E2 / (1.0 - WGS84_E2)
    beta = np.arctan2(z, (1.0 - WGS84_F) * p)  # parametric latitude, initial guess
    for _ in range(5):
        lat = np.arctan2(z + ep2 * b * np.sin(beta) ** 3, p - WGS84_E2 * WGS84_A * np.cos(beta) ** 3)
        beta = np.arctan2((1.0 - WGS84_F) * np.sin(lat), np.cos(lat))
    sl = np.sin(lat)
    N = WGS84_A / np.sqrt(1.0 - WGS84_E2 * sl**2)
    # Height formula stable at all latitudes (Vallado alg. 12 style).
    h = p * np.cos(lat) + z * sl - WGS84_A**2 / N
    if not batched:
        return lat[0], lon[0], h[0]
    return lat, lon, h


def ecef_to_geocentric(r_ecef: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """ECEF position to geocentric radius (m), colatitude (rad, [0, π]) and longitude (rad).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import ecef_to_geocentric
    >>> radius, colat, lon = ecef_to_geocentric([0.0, 7000e3, 0.0])
    >>> float(radius), round(float(np.degrees(colat)), 6), round(float(np.degrees(lon)), 6)
    (7000000.0, 90.0, 90.0)
    """
    vec, batched = as_batch("r_ecef", r_ecef, (3,))
    rad = np.linalg.norm(vec, axis=1)
    if np.any(rad == 0):
        raise InputError("r_ecef must be non-zero vectors (the geocentre has no direction)")
    colat = np.arccos(np.clip(vec[:, 2] / rad, -1.0, 1.0))
    lon = np.arctan2(vec[:, 1], vec[:, 0])
    if not batched:
        return rad[0], colat[0], lon[0]
    return rad, colat, lon


def geocentric_to_ecef(radius: Any, colat: Any, lon: Any) -> np.ndarray:
    """Geocentric spherical coordinates (m, rad, rad) to ECEF position, shape (..., 3).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import geocentric_to_ecef
    >>> geocentric_to_ecef(7000e3, np.pi / 2, np.pi / 2).round(3)   # on the equator, 90 deg east
    array([      0., 7000000.,       0.])
    """
    r_, th, ph = np.broadcast_arrays(
        as_array("radius", radius), as_array("colat", colat), as_array("lon", lon)
    )
    if np.any(r_ <= 0):
        raise InputError(f"radius must be > 0 m (the geocentre has no direction); got {r_.min():g}")
    return np.stack(
        [r_ * np.sin(th) * np.cos(ph), r_ * np.sin(th) * np.sin(ph), r_ * np.cos(th)], axis=-1
    )


def enu_to_ecef_matrix(lat: Any, lon: Any) -> np.ndarray:
    """Matrix whose columns are the East, North, Up unit vectors in ECEF.

    ``v_ECEF = M @ [v_E, v_N, v_U]``. ``lat`` is geodetic (or geocentric, for a spherical
    local frame), ``lon`` east-positive, both rad; shape (..., 3, 3).

    Examples
    --------
    >>> from adcskit.environment import enu_to_ecef_matrix
    >>> enu_to_ecef_matrix(0.0, 0.0).round(12) + 0.0   # equator at Greenwich: E=y, N=z, U=x
    array([[0., 0., 1.],
           [1., 0., 0.],
           [0., 1., 0.]])
    """
    la, lo = np.broadcast_arrays(as_array("lat", lat), as_array("lon", lon))
    sla, cla, slo, clo = np.sin(la), np.cos(la), np.sin(lo), np.cos(lo)
    east = np.stack([-slo, clo, np.zeros_like(lo)], axis=-1)
    north = np.stack([-sla * clo, -sla * slo, cla], axis=-1)
    up = np.stack([cla * clo, cla * slo, sla], axis=-1)
    return np.stack([east, north, up], axis=-1)


def ned_to_ecef_matrix(lat: Any, lon: Any) -> np.ndarray:
    """Matrix whose columns are the North, East, Down unit vectors in ECEF (see ENU).

    Examples
    --------
    >>> from adcskit.environment import ned_to_ecef_matrix
    >>> ned_to_ecef_matrix(0.0, 0.0).round(12) + 0.0   # equator at Greenwich: N=z, E=y, D=-x
    array([[ 0.,  0., -1.],
           [ 0.,  1.,  0.],
           [ 1.,  0.,  0.]])
    """
    M = enu_to_ecef_matrix(lat, lon)
    return np.stack([M[..., 1], M[..., 0], -M[..., 2]], axis=-1)
