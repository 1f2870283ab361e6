"""Sensor models: sun sensor (with eclipse), three-axis magnetometer, rate gyro.

A sensor turns reference-frame vectors ``r`` and the true attitude matrix ``A``
(reference -> body, ``b = A r``, docs/architecture.md convention) into body-frame measurements. The
error chain, applied in this order to ``b = A r``:

1. **misalignment** θ (rotation vector of the sensor frame relative to the body frame, rad):
   ``b <- exp(-[θ×]) b`` (``≈ (I - [θ×]) b``), a fixed small rotation;
2. **bounded angular error** (``angle_bound``): ``b`` is turned by a random rotation whose
   angle never exceeds the bound — the new direction is uniform over the spherical cap of
   half-angle ``angle_bound`` around ``b`` (S0's "±0.5 deg" magnetometer, "±0.005 deg" sun
   sensor);
3. **bounded component error** (``component_fraction`` f): ``b_i <- b_i (1 + f u_i)``,
   ``u_i ~ U[-1, 1]`` independently (S0 Table 1's ±20 %);
4. **Gaussian noise** (``noise_std``): ``b <- b + σ n``, ``n ~ N(0, I3)`` — for the sun sensor
   σ is an angle (rad, applied to the unit vector), for the magnetometer a field (T);
5. **bias** (constant, body frame, same unit as the output);
6. the sun sensor re-normalises to a unit vector (``normalize``).

:meth:`VectorSensor.interval` returns the S0 midpoint-radius box (eq. 4-5) that encloses the
true vector given the bounded errors 2-3 (see :mod:`adcskit.sensors.intervals`); known
misalignment and bias are for the user to correct and Gaussian noise is unbounded, so
neither is in the box.

:class:`RateGyro` is Farrenkopf's gyro model (angle random walk + bias random walk), sampled
at its own rate with the exact discrete form (see :mod:`adcskit.sensors._gyro_kernels`).

Hand-written: the models are a few lines of array algebra; no kept library has them.

References
----------
.. [S0] Seed paper S0: bounded sensor errors (magnetometer ±0.5 deg, sun sensor ±0.005 deg)
   and Table 1 (±20 % of each component), interval vectors eq. 4-5.
.. [2] F. L. Markley, J. L. Crassidis, *Fundamentals of Spacecraft Attitude Determination and
   Control*, Springer, 2014, ch. 4 (sensor models, misalignment as a small rotation).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from adcskit._results import Result
from adcskit._validation import (
    as_array,
    as_batch,
    as_rng,
    check_finite,
    check_flag,
    check_positive,
    check_range,
)
from adcskit.attitude._checks import dcms
from adcskit.errors import InputError, InputTypeError
from adcskit.sensors.intervals import midpoint_radius

__all__ = ["VectorSensor", "SunSensor", "Magnetometer", "RateGyro", "GyroMeasurement"]


def _rotvec_matrix(rv: np.ndarray) -> np.ndarray:
    """Active rotation matrix exp([rv×]) (Rodrigues)."""
    ang = float(np.linalg.norm(rv))
    if ang == 0.0:
        return np.eye(3)
    k = rv / ang
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(ang) * K + (1.0 - np.cos(ang)) * (K @ K)


def _perturb_in_cap(b: np.ndarray, bound: float, rng: np.random.Generator) -> np.ndarray:
    """Rotate each row of b by a random direction uniform in the cap of half-angle bound."""
    n = len(b)
    cos_a = 1.0 - rng.random(n) * (1.0 - np.cos(bound))  # uniform in [cos bound, 1]
    psi = rng.random(n) * 2.0 * np.pi
    sin_a = np.sqrt(np.clip(1.0 - cos_a**2, 0.0, None))
    norm = np.linalg.norm(b, axis=1, keepdims=True)
    u = b / np.where(norm > 0, norm, 1.0)
    # Perpendicular basis: cross with the coordinate axis least aligned with u.
    axis = np.eye(3)[np.argmin(np.abs(u), axis=1)]
    e1 = np.cross(u, axis)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(u, e1)
    d = cos_a[:, None] * u + sin_a[:, None] * (np.cos(psi)[:, None] * e1 + np.sin(psi)[:, None] * e2)
    return norm * d


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class VectorSensor:
    """Generic vector sensor (base of :class:`SunSensor` and :class:`Magnetometer`).

    Attributes
    ----------
    noise_std : float
        Gaussian noise standard deviation per component (output unit; rad for the sun
        sensor, T for the magnetometer), >= 0.
    angle_bound : float, rad
        Bound of the uniform-in-cap angular error, in [0, π).
    component_fraction : float
        Bound f of the relative error of each component, in [0, 1).
    bias : array_like, shape (3,)
        Constant body-frame bias (output unit).
    misalignment : array_like, rad, shape (3,)
        Rotation vector of the sensor frame relative to the body frame (``|θ| < π``).
    normalize : bool
        Re-normalise the output to unit length.

    Notes
    -----
    Instances compare and hash by value (arrays compared elementwise) and pickle, so they can
    be sent to process or dask workers.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.sensors import VectorSensor
    >>> sensor = VectorSensor(angle_bound=np.radians(1.0), normalize=True)
    >>> b = sensor.measure(np.eye(3), [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], rng=0)
    >>> b.shape, np.allclose(np.linalg.norm(b, axis=1), 1.0)
    ((2, 3), True)
    >>> bool(np.degrees(np.arccos(b[0, 0])) <= 1.0)   # error inside the 1 deg cap
    True
    >>> mid, radius = sensor.interval(b[0])              # S0 box that encloses the true vector
    >>> bool(np.all(np.abs(mid - [1.0, 0.0, 0.0]) <= radius + 1e-12))
    True
    """

    noise_std: float = 0.0
    angle_bound: float = 0.0
    component_fraction: float = 0.0
    bias: Any = field(default_factory=lambda: np.zeros(3))
    misalignment: Any = field(default_factory=lambda: np.zeros(3))
    normalize: bool = False

    unit: ClassVar[str] = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "noise_std", check_positive("noise_std", self.noise_std, allow_zero=True))
        object.__setattr__(
            self, "angle_bound",
            check_range("angle_bound", self.angle_bound, 0.0, np.pi, unit="rad", hi_open=True),
        )
        object.__setattr__(
            self, "component_fraction",
            check_range("component_fraction", self.component_fraction, 0.0, 1.0, hi_open=True),
        )
        bias = as_array("bias", self.bias, shape=(3,))
        mis = as_array("misalignment", self.misalignment, shape=(3,))
        if np.linalg.norm(mis) >= np.pi:
            raise InputError(f"misalignment must have norm < pi rad; got {np.linalg.norm(mis):g}")
        bias.setflags(write=False)
        mis.setflags(write=False)
        object.__setattr__(self, "bias", bias)
        object.__setattr__(self, "misalignment", mis)
        object.__setattr__(self, "normalize", check_flag("normalize", self.normalize))

    def _key(self) -> tuple:
        return (type(self), self.noise_std, self.angle_bound, self.component_fraction,
                self.bias.tobytes(), self.misalignment.tobytes(), self.normalize)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, VectorSensor):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    @property
    def misalignment_matrix(self) -> np.ndarray:
        """``exp(-[θ×])``: maps true body components to misaligned sensor components."""
        return _rotvec_matrix(self.misalignment).T

    def _prepare(self, r: np.ndarray) -> np.ndarray:
        return r

    def true_body(self, A: Any, r: Any) -> np.ndarray:
        """Error-free body vectors ``A r`` (after the sensor's own reference preparation)."""
        b, batched = self._true(A, r)
        return b if batched else b[0]

    def _true(self, A: Any, r: Any) -> tuple[np.ndarray, bool]:
        AA, a_batched = dcms("A", A)  # a rotation matrix: zero or skewed matrices are rejected
        rr, r_batched = as_batch("r", r, (3,))
        scale = np.abs(rr).max(axis=1) if rr.size else np.ones(0)
        if np.any(scale < 1e-150):
            raise InputError(f"r must contain non-zero reference vectors; got a zero vector at index "
                             f"{int(np.flatnonzero(scale < 1e-150)[0])}")
        if a_batched and r_batched and len(AA) != len(rr):
            raise InputError(f"A and r must have the same batch length; got {len(AA)} and {len(rr)}")
        rr = self._prepare(rr)
        n = max(len(AA), len(rr))
        b = np.einsum("nij,nj->ni", np.broadcast_to(AA, (n, 3, 3)), np.broadcast_to(rr, (n, 3)))
        return b, a_batched or r_batched

    def measure(self, A: Any, r: Any, rng: Any = None) -> np.ndarray:
        """Simulated body-frame measurements.

        Parameters
        ----------
        A : array_like, shape (3, 3) or (N, 3, 3)
            True attitude matrices, reference -> body (``b = A r``).
        r : array_like, shape (3,) or (N, 3)
            Reference vectors (ECI), e.g. :func:`adcskit.environment.sun_direction` or
            :func:`adcskit.environment.magnetic_field` output.
        rng : numpy.random.Generator or int, optional
            Random source (``None`` -> seed 0). Draws, in order: cap error, component error,
            Gaussian noise — each only when enabled.

        Returns
        -------
        numpy.ndarray, shape (3,) or (N, 3)
            Measurements in the output unit (batched if ``A`` or ``r`` is).
        """
        gen = as_rng(rng)
        b, batched = self._true(A, r)
        b = b @ self.misalignment_matrix.T
        if self.angle_bound > 0:
            b = _perturb_in_cap(b, self.angle_bound, gen)
        if self.component_fraction > 0:
            b = b * (1.0 + self.component_fraction * gen.uniform(-1.0, 1.0, size=b.shape))
        if self.noise_std > 0:
            b = b + self.noise_std * gen.standard_normal(b.shape)
        b = b + self.bias
        if self.normalize:
            b = b / np.linalg.norm(b, axis=1, keepdims=True)
        return b if batched else b[0]

    def interval(self, measured: Any) -> tuple[np.ndarray, np.ndarray]:
        """S0 midpoint-radius box (eq. 4-5) enclosing the true (aligned, bias-free) vector.

        Parameters
        ----------
        measured : array_like, shape (3,) or (N, 3)
            Output of :meth:`measure` (with bias removed by the caller if there is one).

        Returns
        -------
        mid, radius : numpy.ndarray
            See :func:`adcskit.sensors.midpoint_radius`. Gaussian noise is not covered.
        """
        if self.normalize:
            vec, _ = as_batch("measured", measured, (3,))
            norm = np.linalg.norm(vec, axis=1)
            if np.any(norm == 0.0):
                raise InputError(
                    f"measured must be non-zero direction vectors (this sensor outputs unit vectors); "
                    f"got [0, 0, 0] at index {int(np.argmin(norm))}"
                )
        return midpoint_radius(measured, angle_bound=self.angle_bound,
                               fraction=self.component_fraction, normalized=self.normalize)


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class SunSensor(VectorSensor):
    """Sun sensor: unit sun vector in the body frame.

    The reference ``r`` may have any positive length (e.g. :func:`sun_position` in metres); it
    is normalised first, and the output is re-normalised (``normalize=True``). ``noise_std`` is
    an angle (rad) per axis.

    Examples
    --------
    S0's sun sensor, ±0.005 deg bounded error:

    >>> import numpy as np
    >>> ss = SunSensor(angle_bound=np.radians(0.005))
    >>> s_b = ss.measure(np.eye(3), [1.0, 0.0, 0.0], rng=1)
    >>> bool(np.degrees(np.arccos(s_b[0])) <= 0.005)
    True
    """

    normalize: bool = True
    unit: ClassVar[str] = "1"

    def _prepare(self, r: np.ndarray) -> np.ndarray:
        n = np.linalg.norm(r, axis=1, keepdims=True)
        if np.any(n == 0):
            raise InputError("r must be non-zero sun vectors; got a zero vector")
        return r / n

    def measure(self, A: Any, r: Any, rng: Any = None, *, eclipse: Any = None) -> np.ndarray:
        """Simulated sun directions; NaN rows where the spacecraft is in eclipse.

        Parameters
        ----------
        A, r, rng
            As :meth:`VectorSensor.measure`.
        eclipse : array_like of bool, shape () or (N,), optional
            True where the Sun is hidden (e.g. :func:`adcskit.environment.in_shadow` of the
            orbit positions). Those rows are all-NaN, the "no measurement" marker that
            :func:`adcskit.estimation.mekf_filter` skips. The random draws are the same with
            or without eclipses (eclipsed rows are drawn, then blanked), so a seed gives the
            same lit measurements either way.

        Returns
        -------
        numpy.ndarray, shape (3,) or (N, 3)
        """
        out = VectorSensor.measure(self, A, r, rng)
        if eclipse is None:
            return out
        ecl = np.asarray(eclipse)
        if ecl.dtype != bool:
            raise InputTypeError(f"eclipse must be booleans; got dtype {ecl.dtype}")
        rows = np.atleast_2d(out)
        if ecl.ndim > 1 or (ecl.ndim == 1 and ecl.shape[0] != rows.shape[0]):
            raise InputError(f"eclipse must have shape () or ({rows.shape[0]},); got {ecl.shape}")
        rows = rows.copy()
        rows[np.broadcast_to(ecl, rows.shape[:1])] = np.nan
        return rows if out.ndim == 2 else rows[0]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Magnetometer(VectorSensor):
    """Three-axis magnetometer: magnetic field in the body frame, tesla.

    ``noise_std`` and ``bias`` are in tesla; the output keeps the field's magnitude
    (``normalize=False``).

    Examples
    --------
    S0's magnetometer, ±0.5 deg bounded error:

    >>> import numpy as np
    >>> mag = Magnetometer(angle_bound=np.radians(0.5))
    >>> b = mag.measure(np.eye(3), [2e-5, 0.0, -3e-5], rng=1)
    >>> b.shape
    (3,)
    """

    normalize: bool = False
    unit: ClassVar[str] = "T"


@dataclass(frozen=True, slots=True, repr=False)
class GyroMeasurement(Result):
    """Output of :meth:`RateGyro.measure` (leading ``N`` axis only for a batch).

    Attributes
    ----------
    t : ndarray, s, shape (T,)
        Sample epochs ``t_k = t0 + k / rate_hz``; reading ``k`` is the mean rate over
        ``[t_k, t_k+1)``.
    omega : ndarray, rad/s, shape ([N,] T, 3)
        Measured rates (true rate + bias + noise).
    bias : ndarray, rad/s, shape ([N,] T, 3)
        True bias at each epoch ``t_k`` (for NEES and plots).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.sensors import RateGyro
    >>> m = RateGyro(sigma_v=1e-5, sigma_u=1e-7, rate_hz=10.0).measure(np.zeros((50, 3)), rng=0)
    >>> m.omega.shape, m.bias.shape
    ((50, 3), (50, 3))
    """

    t: np.ndarray
    omega: np.ndarray
    bias: np.ndarray


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class RateGyro:
    """Three-axis rate gyro: Farrenkopf's angle random walk + bias random walk.

    ``ω̃ = ω + b + η_v``, ``ḃ = η_u`` with white ``η_v`` (spectral density ``σv²``) and
    ``η_u`` (``σu²``), sampled at ``rate_hz``. Each reading is the mean measured rate over its
    sample interval, simulated with the exact discrete form (Crassidis & Junkins 2012 §7.2)::

        b_{k+1} = b_k + σu √Δt n_u,k
        ω̃_k     = ω_k + (b_k + b_{k+1}) / 2 + sqrt(σv²/Δt + σu² Δt/12) n_v,k

    — the same model the MEKF (:mod:`adcskit.estimation.mekf`) assumes, so a filter given
    these readings is consistent.

    Attributes
    ----------
    sigma_v : float, rad/s^0.5
        Angle random walk, >= 0.
    sigma_u : float, rad/s^1.5
        Bias random walk, >= 0.
    rate_hz : float, Hz
        Sample rate, > 0.
    bias0 : array_like, rad/s, shape (3,)
        Bias at the first sample (draw it from its prior yourself for Monte-Carlo runs).

    References
    ----------
    Farrenkopf 1978; Crassidis & Junkins 2012 §7.2; Markley & Crassidis 2014 §6.2.1.

    Examples
    --------
    >>> import numpy as np
    >>> gyro = RateGyro(sigma_v=1e-5, sigma_u=1e-7, rate_hz=10.0, bias0=[1e-4, 0.0, 0.0])
    >>> m = gyro.measure(np.zeros((100, 3)), rng=0)
    >>> m.omega.shape, float(m.t[1])
    ((100, 3), 0.1)
    """

    sigma_v: float = 0.0
    sigma_u: float = 0.0
    rate_hz: float = 10.0
    bias0: Any = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        object.__setattr__(self, "sigma_v", check_positive("sigma_v", self.sigma_v, allow_zero=True,
                                                           unit="rad/s^0.5"))
        object.__setattr__(self, "sigma_u", check_positive("sigma_u", self.sigma_u, allow_zero=True,
                                                           unit="rad/s^1.5"))
        object.__setattr__(self, "rate_hz", check_positive("rate_hz", self.rate_hz, unit="Hz"))
        b0 = as_array("bias0", self.bias0, shape=(3,))
        b0.setflags(write=False)
        object.__setattr__(self, "bias0", b0)

    def _key(self) -> tuple:
        return (self.sigma_v, self.sigma_u, self.rate_hz, self.bias0.tobytes())

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, RateGyro):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    @property
    def dt(self) -> float:
        """Sample interval ``1 / rate_hz`` [s]."""
        return 1.0 / self.rate_hz

    def measure(self, omega: Any, rng: Any = None, *, t0: float = 0.0) -> GyroMeasurement:
        """Simulated readings for true rates at the gyro's sample epochs.

        Parameters
        ----------
        omega : array_like, rad/s, shape (T, 3) or (N, T, 3)
            True body rate at (more precisely: averaged over) each sample interval.
        rng : numpy.random.Generator or int, optional
            Random source (``None`` -> seed 0). Draws bias increments ``(N, T, 3)`` first,
            then rate noise ``(N, T, 3)`` (``N = 1`` for a single run).
        t0 : float, s
            Epoch of the first sample.

        Returns
        -------
        GyroMeasurement
        """
        w = as_array("omega", omega)
        if w.ndim not in (2, 3) or w.shape[-1] != 3:
            raise InputError(f"omega must have shape (T, 3) or (N, T, 3); got shape {w.shape}")
        start = check_finite("t0", t0)
        gen = as_rng(rng)
        batched = w.ndim == 3
        W = w if batched else w[None]
        N, T = W.shape[0], W.shape[1]
        dt = self.dt
        n_u = gen.standard_normal((N, T, 3))
        n_v = gen.standard_normal((N, T, 3))
        # b_0 .. b_T: cumulative bias random walk (b_T only enters the last reading)
        b = np.empty((N, T + 1, 3))
        b[:, 0] = self.bias0
        np.cumsum(self.sigma_u * np.sqrt(dt) * n_u, axis=1, out=b[:, 1:])
        b[:, 1:] += self.bias0
        sn = np.sqrt(self.sigma_v**2 / dt + self.sigma_u**2 * dt / 12.0)
        meas = W + 0.5 * (b[:, :-1] + b[:, 1:]) + sn * n_v
        t = start + dt * np.arange(T)
        bias = b[:, :-1]
        if not batched:
            meas, bias = meas[0], bias[0]
        return GyroMeasurement(t=t, omega=meas, bias=np.ascontiguousarray(bias))
