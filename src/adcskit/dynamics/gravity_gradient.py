"""Gravity-gradient torque and circular-orbit rate.

``τ_gg = 3 μ / |r|⁵ · r_b × (J r_b)`` with ``r_b`` the spacecraft position (from the Earth's
centre) in body components (Markley & Crassidis 2014, eq. 3.155; Wie 2008, §6.4).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from adcskit._validation import as_batch, check_positive
from adcskit.attitude._checks import out
from adcskit.constants import MU_EARTH, R_EARTH
from adcskit.dynamics.rigid_body import as_inertia
from adcskit.errors import InputError

__all__ = ["gravity_gradient_torque", "orbit_rate"]


def gravity_gradient_torque(r_body: Any, inertia: Any, mu: float = MU_EARTH) -> np.ndarray:
    """Gravity-gradient torque (N m, body components).

    Parameters
    ----------
    r_body : array_like, shape (3,) or (N, 3), m
        Position of the spacecraft relative to the Earth's centre, in body components
        (``A r_eci`` with ``A`` the attitude matrix).
    inertia : array_like, shape (3,) or (3, 3), kg m²
    mu : float, m³/s²

    Examples
    --------
    >>> import numpy as np
    >>> r = 7.0e6 * np.array([0.0, np.sin(0.1), np.cos(0.1)])   # m, body frame, tilted off the z axis
    >>> tau = gravity_gradient_torque(r, [100.0, 120.0, 80.0])
    >>> tau.shape, bool(abs(tau[0]) > 0)
    ((3,), True)
    """
    r, batched = as_batch("r_body", r_body, (3,))
    J = as_inertia(inertia)
    mu = check_positive("mu", mu, unit="m³/s²")
    rn = np.linalg.norm(r, axis=1)
    if np.any(rn <= 0):
        raise InputError("r_body must be non-zero (position from the Earth's centre, m); got a zero vector")
    return out(3 * mu / rn[:, None] ** 5 * np.cross(r, r @ J.T), batched)


def orbit_rate(altitude: float, *, mu: float = MU_EARTH, radius: float = R_EARTH) -> float:
    """Mean motion ``n = sqrt(μ / a³)`` (rad/s) of a circular orbit at ``altitude`` (m).

    Examples
    --------
    >>> round(orbit_rate(800e3), 7)                 # rad/s
    0.0010381
    >>> round(2 * 3.141592653589793 / orbit_rate(800e3) / 60, 2)   # period, min
    100.87
    """
    h = check_positive("altitude", altitude, allow_zero=True, unit="m")
    mu = check_positive("mu", mu)
    radius = check_positive("radius", radius)
    r = radius + h
    return float(np.sqrt(mu / r) / r)  # = sqrt(mu / r**3) without overflowing r**3
