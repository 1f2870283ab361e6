"""Orbits: analytic circular and Keplerian two-body propagation, and SGP4 from a TLE.

All states are ECI (see :mod:`adcskit.environment.frames`: adcskit's ECI is the TEME frame of
SGP4), metres and metres per second, for a 1-D array of times ``t`` in seconds from an
optional UTC ``epoch``.

The two-body propagators are closed forms (hand-written: poliastro-class libraries are not a
kept dependency, and the whole propagator is a vectorised Kepler solve plus a perifocal
rotation). SGP4 is the ``sgp4`` package (Vallado et al. 2006) used as is: its TEME output *is*
adcskit's ECI, so no frame conversion is applied (TEME -> GCRF would add precession-nutation,
~0.36 deg in 2026, which no other part of adcskit uses).

References
----------
.. [1] D. A. Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed., 2013:
   Alg. 2 (KepEqtnE), Alg. 9 (RV2COE), Alg. 10 (COE2RV).
.. [2] D. A. Vallado, P. Crawford, R. Hujsak, T. S. Kelso, "Revisiting Spacetrack Report #3",
   AIAA 2006-6753.
.. [3] J. M. A. Danby, *Fundamentals of Celestial Mechanics*, 2nd ed., 1988, sec. 6.6
   (starter ``E0 = M + 0.85 e sign(sin M)``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from adcskit._results import compact_repr
from adcskit._validation import as_array, as_batch, check_finite, check_positive, check_range
from adcskit.environment.frames import WGS84_A
from adcskit.environment.time import J2000, as_utc, utc_times
from adcskit.errors import InputError

__all__ = [
    "MU_EARTH",
    "R_EARTH",
    "OrbitState",
    "KeplerOrbit",
    "circular_orbit",
    "kepler_orbit",
    "solve_kepler",
    "elements_to_rv",
    "rv_to_elements",
    "sgp4_orbit",
]

from adcskit.constants import MU_EARTH  # noqa: E402  (EGM-96 / WGS-84, m^3/s^2)

R_EARTH = WGS84_A  #: Earth's equatorial radius used for altitudes, m


@compact_repr
@dataclass(frozen=True, slots=True)
class OrbitState:
    """Positions and velocities along an orbit.

    Attributes
    ----------
    t : numpy.ndarray, s, shape (N,)
        Times from ``epoch``.
    r : numpy.ndarray, m, shape (N, 3)
        ECI positions.
    v : numpy.ndarray, m/s, shape (N, 3)
        ECI velocities.
    epoch : numpy.datetime64 or None
        UTC instant of ``t = 0`` (None for a purely relative time axis).
    status : numpy.ndarray of int, shape (N,)
        0 where the state is valid; SGP4's error code otherwise (the row is NaN).

    Notes
    -----
    Iterating yields ``r, v``, so ``r, v = circular_orbit(...)`` works.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import OrbitState
    >>> st = OrbitState(t=np.array([0.0, 10.0]), r=np.array([[7e6, 0.0, 0.0], [7e6, 75e3, 0.0]]),
    ...                 v=np.array([[0.0, 7.5e3, 0.0], [-80.0, 7.5e3, 0.0]]))
    >>> st.success
    True
    >>> r, v = st                                    # unpacks as (r, v)
    >>> r.shape
    (2, 3)
    """

    t: np.ndarray
    r: np.ndarray
    v: np.ndarray
    epoch: np.datetime64 | None = None
    status: np.ndarray = field(default=None)  # type: ignore[assignment]

    def __post_init__(self) -> None:
        if self.status is None:
            object.__setattr__(self, "status", np.zeros(len(self.t), dtype=int))

    def __iter__(self):
        return iter((self.r, self.v))

    @property
    def times(self) -> np.ndarray:
        """UTC instants ``epoch + t`` (datetime64[ns]); needs an ``epoch``."""
        if self.epoch is None:
            raise InputError(
                "this OrbitState has no epoch; pass epoch=... to the orbit function to get "
                "absolute UTC times"
            )
        return utc_times(self.epoch, self.t)

    @property
    def success(self) -> bool:
        """True when every state is valid (``status == 0``)."""
        return bool(np.all(self.status == 0))

    def to_dict(self) -> dict[str, Any]:
        """Plain-Python view (lists) for JSON output."""
        return {
            "t": self.t.tolist(),
            "r": self.r.tolist(),
            "v": self.v.tolist(),
            "epoch": None if self.epoch is None else str(self.epoch),
            "status": self.status.tolist(),
        }


def _times_1d(t: Any) -> np.ndarray:
    arr = as_array("t", t, ndim=(0, 1))
    return np.atleast_1d(arr)


def _epoch(epoch: Any) -> np.datetime64 | None:
    if epoch is None:
        return None
    ep = as_utc(epoch, "epoch")
    if ep.ndim != 0:
        raise InputError(f"epoch must be one UTC instant; got shape {ep.shape}")
    return ep[()]


def _perifocal_to_eci(raan: float, inc: float, argp: float) -> np.ndarray:
    """Columns P, Q, W of the perifocal frame in ECI: R3(-raan) R1(-inc) R3(-argp)."""
    cO, sO, ci, si, cw, sw = (np.cos(raan), np.sin(raan), np.cos(inc), np.sin(inc),
                              np.cos(argp), np.sin(argp))
    return np.array([
        [cO * cw - sO * sw * ci, -cO * sw - sO * cw * ci, sO * si],
        [sO * cw + cO * sw * ci, -sO * sw + cO * cw * ci, -cO * si],
        [sw * si, cw * si, ci],
    ])


def circular_orbit(
    altitude: float,
    inclination: float,
    raan: float,
    arg_lat0: float,
    t: Any,
    *,
    epoch: Any = None,
    mu: float = MU_EARTH,
    radius: float = R_EARTH,
) -> OrbitState:
    """Circular two-body orbit in closed form.

    Parameters
    ----------
    altitude : float, m
        Height above ``radius`` (> 0).
    inclination : float, rad
        In [0, π].
    raan : float, rad
        Right ascension of the ascending node.
    arg_lat0 : float, rad
        Argument of latitude (angle from the ascending node) at ``t = 0``.
    t : float or array_like, s, shape (N,)
        Times from ``epoch``.
    epoch : datetime-like, optional
        UTC instant of ``t = 0``; stored in the result so that ``state.times`` gives the
        absolute times that :func:`sun_direction` and :func:`magnetic_field` need.
    mu : float, m^3/s^2
        Gravitational parameter.
    radius : float, m
        Reference radius of the central body (WGS-84 equatorial by default).

    Returns
    -------
    OrbitState
        ``r`` (m) and ``v`` (m/s) in ECI, shape (N, 3). Mean motion ``n = sqrt(mu / a^3)``,
        ``a = radius + altitude``, argument of latitude ``u = arg_lat0 + n t``.

    Examples
    --------
    S0's scenario (800 km, 75 deg, RAAN 0), one sample a second for 20 minutes:

    >>> import numpy as np
    >>> st = circular_orbit(800e3, np.radians(75), 0.0, 0.0, np.arange(1200.0),
    ...                     epoch="2024-01-01T00:00:00")
    >>> st.r.shape
    (1200, 3)

    References
    ----------
    Vallado (2013), Alg. 10 with e = 0 (argument of latitude in place of true anomaly).
    """
    h = check_positive("altitude", altitude, unit="m")
    inc = check_range("inclination", inclination, 0.0, np.pi, unit="rad")
    Om = check_finite("raan", raan)
    u0 = check_finite("arg_lat0", arg_lat0)
    mu_ = check_positive("mu", mu, unit="m^3/s^2")
    R = check_positive("radius", radius, unit="m")
    tt = _times_1d(t)
    a = R + h
    n = np.sqrt(mu_ / a) / a  # = sqrt(mu / a^3) without overflowing a^3
    u = u0 + n * tt
    cu, su = np.cos(u), np.sin(u)
    P = _perifocal_to_eci(Om, inc, 0.0)
    r = a * (np.outer(cu, P[:, 0]) + np.outer(su, P[:, 1]))
    v = a * n * (np.outer(-su, P[:, 0]) + np.outer(cu, P[:, 1]))
    return OrbitState(t=tt, r=r, v=v, epoch=_epoch(epoch))


def _solve_kepler(M: np.ndarray, e: float, tol: float = 1e-14, maxiter: int = 50) -> np.ndarray:
    Mw = np.mod(M + np.pi, 2.0 * np.pi) - np.pi  # wrap to [-pi, pi)
    E = Mw + 0.85 * e * np.sign(np.sin(Mw))
    for _ in range(maxiter):
        f = E - e * np.sin(E) - Mw
        dE = f / (1.0 - e * np.cos(E))
        E = E - dE
        if np.all(np.abs(dE) <= tol * (1.0 + np.abs(E))):
            break
    return E + (M - Mw)  # restore the whole turns


def solve_kepler(mean_anomaly: Any, e: float) -> np.ndarray:
    """Eccentric anomaly from Kepler's equation ``M = E - e sin E`` (elliptic orbits).

    Parameters
    ----------
    mean_anomaly : float or array_like, rad
        Any real values (whole turns are kept: ``E`` increases with ``M``).
    e : float
        Eccentricity in [0, 1).

    Returns
    -------
    numpy.ndarray, rad
        Same shape as ``mean_anomaly``; residual below 1e-14 rad.

    Notes
    -----
    Vectorised Newton iteration from Danby's starter, which converges for every
    ``0 <= e < 1`` (Danby 1988, sec. 6.6); hand-written because ``scipy.optimize.newton``
    on arrays offers no better starter and returns per-element failure flags we do not need.

    References
    ----------
    Vallado (2013), Alg. 2 (KepEqtnE).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import solve_kepler
    >>> E = solve_kepler(np.array([0.0, 1.0, np.pi]), 0.1)
    >>> E.round(9)
    array([0.        , 1.08859775, 3.14159265])
    >>> np.allclose(E - 0.1 * np.sin(E), [0.0, 1.0, np.pi])
    True
    """
    M = as_array("mean_anomaly", mean_anomaly)
    ecc = check_range("e", e, 0.0, 1.0, hi_open=True)
    return _solve_kepler(M, ecc)


def elements_to_rv(
    a: float, e: float, inclination: float, raan: float, argp: float, true_anomaly: Any,
    *, mu: float = MU_EARTH,
) -> tuple[np.ndarray, np.ndarray]:
    """Classical orbital elements to ECI position (m) and velocity (m/s).

    ``true_anomaly`` (rad) is a scalar or a 1-D array of N values; the results then have
    shape (3,) or (N, 3).

    References
    ----------
    Vallado (2013), Alg. 10 (COE2RV).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import elements_to_rv
    >>> r, v = elements_to_rv(7000e3, 0.0, 0.0, 0.0, 0.0, 0.0)   # circular equatorial, at the node
    >>> r.round(3), v.round(3)
    (array([7000000.,       0.,       0.]), array([   0.   , 7546.053,    0.   ]))
    >>> elements_to_rv(7000e3, 0.01, 0.9, 0.1, 0.2, np.linspace(0.0, np.pi, 5))[0].shape
    (5, 3)
    """
    a_ = check_positive("a", a, unit="m", min_value=1.0)
    ecc = check_range("e", e, 0.0, 1.0, hi_open=True)
    inc = check_range("inclination", inclination, 0.0, np.pi, unit="rad")
    P = _perifocal_to_eci(check_finite("raan", raan), inc, check_finite("argp", argp))
    mu_ = check_positive("mu", mu, unit="m^3/s^2")
    nu = as_array("true_anomaly", true_anomaly, ndim=(0, 1))
    return _elements_to_rv(a_, ecc, P, nu, mu_)


def _elements_to_rv(a, e, P, nu, mu):
    p = a * (1.0 - e**2)
    rad = p / (1.0 + e * np.cos(nu))
    r_pf = np.stack([rad * np.cos(nu), rad * np.sin(nu), np.zeros_like(nu)], axis=-1)
    v_pf = np.sqrt(mu / p) * np.stack([-np.sin(nu), e + np.cos(nu), np.zeros_like(nu)], axis=-1)
    return r_pf @ P.T, v_pf @ P.T


def rv_to_elements(r: Any, v: Any, *, mu: float = MU_EARTH) -> dict[str, np.ndarray]:
    """ECI position/velocity to classical elements (elliptic, non-equatorial orbits).

    Parameters
    ----------
    r : array_like, m, shape (3,) or (N, 3)
    v : array_like, m/s, same shape as ``r``
    mu : float, m^3/s^2

    Returns
    -------
    dict
        ``a`` (m), ``e``, ``inclination``, ``raan``, ``argp``, ``true_anomaly``,
        ``mean_anomaly`` (rad), each of shape () or (N,). Angles of circular or equatorial
        orbits are undefined (NaN-free but arbitrary); use them with care.

    References
    ----------
    Vallado (2013), Alg. 9 (RV2COE).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import elements_to_rv, rv_to_elements
    >>> r, v = elements_to_rv(7000e3, 0.01, 0.9, 0.1, 0.2, 0.3)
    >>> el = rv_to_elements(r, v)
    >>> round(float(el["a"]), 3), round(float(el["e"]), 9), round(float(el["inclination"]), 9)
    (7000000.0, 0.01, 0.9)
    >>> round(float(el["true_anomaly"]), 9)
    0.3
    """
    rr, batched = as_batch("r", r, (3,))
    vv, _ = as_batch("v", v, (3,))
    if rr.shape != vv.shape:
        raise InputError(f"v must have the same shape as r {rr.shape}; got {vv.shape}")
    mu_ = check_positive("mu", mu, unit="m^3/s^2")
    rn = np.linalg.norm(rr, axis=1)
    h = np.cross(rr, vv)
    hn = np.linalg.norm(h, axis=1)
    if np.any(rn < 1e-100) or np.any(hn < 1e-100 * np.maximum(rn, 1.0)):
        raise InputError("r and v must describe an orbit with non-zero position and angular momentum "
                         "(r x v != 0); got a zero or rectilinear r, v")
    nvec = np.cross(np.array([0.0, 0.0, 1.0]), h)
    nn = np.linalg.norm(nvec, axis=1)
    evec = np.cross(vv, h) / mu_ - rr / rn[:, None]
    e = np.linalg.norm(evec, axis=1)
    energy = 0.5 * np.einsum("ij,ij->i", vv, vv) - mu_ / rn
    if np.any(energy >= 0):
        raise InputError(f"r, v must describe an elliptic orbit (negative specific energy) for "
                         f"mu = {mu_:g} m^3/s^2; got energy {float(energy.max()):g} m^2/s^2")
    a = -mu_ / (2.0 * energy)
    inc = np.arccos(np.clip(h[:, 2] / hn, -1.0, 1.0))
    raan = np.mod(np.arctan2(nvec[:, 1], nvec[:, 0]), 2 * np.pi)
    safe_n = np.where(nn > 0, nn, 1.0)[:, None]
    safe_e = np.where(e > 0, e, 1.0)[:, None]
    nhat = nvec / safe_n
    ehat = evec / safe_e
    # Angles measured in the orbit plane with atan2 (robust near 0 and pi).
    hhat = h / hn[:, None]
    argp = np.mod(np.arctan2(np.einsum("ij,ij->i", np.cross(nhat, ehat), hhat),
                             np.einsum("ij,ij->i", nhat, ehat)), 2 * np.pi)
    rhat = rr / rn[:, None]
    nu = np.mod(np.arctan2(np.einsum("ij,ij->i", np.cross(ehat, rhat), hhat),
                           np.einsum("ij,ij->i", ehat, rhat)), 2 * np.pi)
    E = 2.0 * np.arctan2(np.sqrt(1.0 - e) * np.sin(nu / 2), np.sqrt(1.0 + e) * np.cos(nu / 2))
    M = np.mod(E - e * np.sin(E), 2 * np.pi)
    out = {"a": a, "e": e, "inclination": inc, "raan": raan, "argp": argp,
           "true_anomaly": nu, "mean_anomaly": M}
    return out if batched else {k: val[0] for k, val in out.items()}


@dataclass(frozen=True, slots=True, kw_only=True)
class KeplerOrbit:
    """An elliptic two-body orbit given by classical elements at ``t = 0``.

    Attributes
    ----------
    a : float, m
        Semi-major axis (> 0).
    e : float
        Eccentricity in [0, 1).
    inclination, raan, argp, mean_anomaly0 : float, rad
        Inclination in [0, π], right ascension of the ascending node, argument of perigee,
        mean anomaly at ``t = 0``.
    epoch : datetime-like, optional
        UTC instant of ``t = 0``.
    mu : float, m^3/s^2

    Examples
    --------
    >>> from adcskit.environment import KeplerOrbit
    >>> orb = KeplerOrbit(a=7000e3, e=0.01, inclination=0.9)
    >>> round(orb.period, 3)                        # s
    5828.517
    >>> st = orb.propagate([0.0, 600.0, 1200.0])
    >>> st.r.shape, st.v.shape
    ((3, 3), (3, 3))
    >>> round(float(st.r[0, 0]), 3)                 # perigee radius a (1 - e), m
    6930000.0
    """

    a: float
    e: float = 0.0
    inclination: float = 0.0
    raan: float = 0.0
    argp: float = 0.0
    mean_anomaly0: float = 0.0
    epoch: Any = None
    mu: float = MU_EARTH

    def __post_init__(self) -> None:
        object.__setattr__(self, "a", check_positive("a", self.a, unit="m", min_value=1.0))
        object.__setattr__(self, "e", check_range("e", self.e, 0.0, 1.0, hi_open=True))
        object.__setattr__(
            self, "inclination", check_range("inclination", self.inclination, 0.0, np.pi, unit="rad")
        )
        for name in ("raan", "argp", "mean_anomaly0"):
            object.__setattr__(self, name, check_finite(name, getattr(self, name)))
        object.__setattr__(self, "mu", check_positive("mu", self.mu, unit="m^3/s^2"))
        object.__setattr__(self, "epoch", _epoch(self.epoch))

    @property
    def mean_motion(self) -> float:
        """Mean motion ``sqrt(mu / a^3)``, rad/s."""
        return float(np.sqrt(self.mu / self.a) / self.a)  # no overflow of a^3

    @property
    def period(self) -> float:
        """Orbital period ``2π sqrt(a^3 / mu)``, s."""
        return float(2.0 * np.pi / self.mean_motion)

    def propagate(self, t: Any) -> OrbitState:
        """States at times ``t`` (s from the epoch), shape (N, 3) each."""
        tt = _times_1d(t)
        M = self.mean_anomaly0 + self.mean_motion * tt
        E = _solve_kepler(M, self.e)
        nu = 2.0 * np.arctan2(np.sqrt(1.0 + self.e) * np.sin(E / 2),
                              np.sqrt(1.0 - self.e) * np.cos(E / 2))
        P = _perifocal_to_eci(self.raan, self.inclination, self.argp)
        r, v = _elements_to_rv(self.a, self.e, P, nu, self.mu)
        return OrbitState(t=tt, r=r, v=v, epoch=self.epoch)


def kepler_orbit(
    a: float, e: float, inclination: float, raan: float, argp: float, mean_anomaly0: float,
    t: Any, *, epoch: Any = None, mu: float = MU_EARTH,
) -> OrbitState:
    """Elliptic two-body orbit in closed form (see :class:`KeplerOrbit`).

    Parameters
    ----------
    a : float, m
    e : float
        In [0, 1).
    inclination, raan, argp, mean_anomaly0 : float, rad
    t : float or array_like, s, shape (N,)
    epoch : datetime-like, optional
    mu : float, m^3/s^2

    Returns
    -------
    OrbitState

    References
    ----------
    Vallado (2013), Alg. 2 (Kepler's equation) and Alg. 10 (COE2RV).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import kepler_orbit
    >>> t = np.linspace(0.0, 3000.0, 4)                   # s
    >>> st = kepler_orbit(7000e3, 0.05, np.radians(98.0), 0.0, 0.0, 0.0, t,
    ...                   epoch="2024-03-20T12:00:00")
    >>> st.r.shape, st.success
    ((4, 3), True)
    >>> round(float(np.linalg.norm(st.r[0])), 3)     # starts at perigee a (1 - e), m
    6650000.0
    """
    return KeplerOrbit(a=a, e=e, inclination=inclination, raan=raan, argp=argp,
                       mean_anomaly0=mean_anomaly0, epoch=epoch, mu=mu).propagate(t)


def sgp4_orbit(tle_line1: str, tle_line2: str, times: Any) -> OrbitState:
    """SGP4 propagation of a two-line element set (``sgp4`` package, WGS-72 constants).

    Parameters
    ----------
    tle_line1, tle_line2 : str
        The two TLE lines.
    times : datetime-like or array_like, shape () or (N,)
        UTC instants.

    Returns
    -------
    OrbitState
        ``r`` (m) and ``v`` (m/s) in TEME, which is adcskit's ECI (no conversion is applied;
        see the module docstring); ``epoch`` is the TLE epoch and ``t`` the seconds from it.
        Rows where SGP4 reports an error (e.g. decay) are NaN with the error code in
        ``status`` (``success`` is then False).

    References
    ----------
    Vallado et al. (2006), "Revisiting Spacetrack Report #3".

    Examples
    --------
    >>> from adcskit.environment import sgp4_orbit
    >>> l1 = "1 25544U 98067A   08264.51782528 -.00002182  00000-0 -11606-4 0  2927"
    >>> l2 = "2 25544  51.6416 247.4627 0006703 130.5360 325.0288 15.72125391563537"
    >>> st = sgp4_orbit(l1, l2, ["2008-09-20T12:00:00", "2008-09-20T12:10:00"])
    >>> st.r.shape, st.success, st.status
    ((2, 3), True, array([0, 0]))
    >>> import numpy as np
    >>> bool(6.6e6 < np.linalg.norm(st.r[0]) < 6.8e6)   # ISS altitude, m
    True
    """
    from sgp4.api import Satrec

    for name, line, first in (("tle_line1", tle_line1, "1"), ("tle_line2", tle_line2, "2")):
        if not isinstance(line, str) or not line.startswith(first) or len(line.rstrip()) != 69:
            raise InputError(
                f"{name} must be a TLE line of 69 characters starting with {first!r}; "
                f"got {line!r}"
            )
    try:
        sat = Satrec.twoline2rv(tle_line1, tle_line2)
    except ValueError as exc:
        raise InputError(f"tle_line1/tle_line2 could not be parsed as a TLE: {exc}") from None
    tt = np.atleast_1d(as_utc(times))
    if tt.ndim != 1:
        raise InputError(f"times must be one instant or a 1-D array; got shape {tt.shape}")
    d = (tt - J2000).astype(np.int64) / 86_400e9
    whole = np.floor(d)
    err, r, v = sat.sgp4_array(2451545.0 + whole, d - whole)
    r = np.asarray(r) * 1e3
    v = np.asarray(v) * 1e3
    err = np.asarray(err, dtype=int)
    r[err != 0] = np.nan
    v[err != 0] = np.nan
    ep_days = (sat.jdsatepoch - 2451545.0) + sat.jdsatepochF
    epoch = J2000 + np.timedelta64(int(round(ep_days * 86_400e9)), "ns")
    t_rel = (tt - epoch).astype(np.int64) / 1e9
    return OrbitState(t=t_rel, r=r, v=v, epoch=epoch, status=err)
