"""Vector sensor models: sun sensor and three-axis magnetometer.

A sensor turns reference-frame vectors ``r`` and the true attitude matrix ``A``
(reference -> body, ``b = A r``, design.md convention) into body-frame measurements. The
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

from adcskit._validation import as_array, as_batch, as_rng, check_flag, check_positive, check_range
from adcskit.attitude._checks import dcms
from adcskit.errors import InputError
from adcskit.sensors.intervals import midpoint_radius

__all__ = ["VectorSensor", "SunSensor", "Magnetometer"]


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
        Rotation vector of the sensor frame relative to the body frame (|θ| < π).
    normalize : bool
        Re-normalise the output to unit length.

    Notes
    -----
    Instances compare and hash by value (arrays compared elementwise) and pickle, so they can
    be sent to process or dask workers.
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
