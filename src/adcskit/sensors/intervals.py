"""Interval (bounded-error) boxes for vector measurements, in midpoint-radius form.

S0 writes every uncertain vector as ``b = b^m + diag(α) b^r`` with ``α ∈ [-1, 1]^3``
(S0 eq. 4-5): ``b^m`` is the box midpoint and ``b^r >= 0`` its componentwise radius. The
helpers here build those boxes so that they *enclose every true vector consistent with a
measurement* under the bounded error models of :mod:`adcskit.sensors.models`:

``angle_bound`` θ
    The true vector lies within angle θ of the measured one (same norm). The box is exact:
    with ``φ_i`` the angle between the measured direction and axis ``i``, the true component
    ranges over ``|b| [cos(min(π, φ_i + θ)), cos(max(0, φ_i - θ))]``.
``fraction`` f
    Each component was multiplied by ``1 + f u_i``, ``u_i ∈ [-1, 1]`` (S0 Table 1 uses
    ``f = 0.2``). The true component is then ``m_i / (1 + f u_i)``, i.e. between
    ``m_i / (1 + f)`` and ``m_i / (1 - f)``: exact, and *not* symmetric about ``m_i``. The
    naive box ``m_i ± f |m_i|`` would miss true values by up to ``f² / (1 - f)`` relative.
    If the measurement was re-normalised to unit length afterwards (``normalized=True``, as
    :class:`~adcskit.sensors.SunSensor` does), the lost scale widens the box to
    ``m_i [(1 - f)/(1 + f), (1 + f)/(1 - f)]``, clipped to [-1, 1] (valid, not tight).

When both are given, the fraction box is widened on each side by the chord
``2 |c|max sin(θ/2)`` of the angular error (valid, not tight). Gaussian noise and biases
have no bound and are not part of the box.

Hand-written: a few closed forms; no interval library is a kept dependency.

References
----------
.. [S0] Robust optimal attitude determination with interval uncertainty (seed paper S0),
   eq. 4-5 (midpoint-radius vectors) and Table 1 (±20 % component errors).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from adcskit._validation import as_array, as_batch, check_flag, check_range
from adcskit.errors import InputError

__all__ = ["interval_from_bounds", "midpoint_radius", "vector_bounds"]


def interval_from_bounds(lower: Any, upper: Any) -> tuple[np.ndarray, np.ndarray]:
    """Midpoint and radius of the box ``[lower, upper]``.

    Parameters
    ----------
    lower, upper : array_like
        Same shape, ``lower <= upper`` elementwise.

    Returns
    -------
    mid, radius : numpy.ndarray
        ``(upper + lower) / 2`` and ``(upper - lower) / 2 >= 0``, so that every
        ``x ∈ [lower, upper]`` is ``mid + α radius`` with ``α ∈ [-1, 1]`` (S0 eq. 4).

    Examples
    --------
    >>> from adcskit.sensors import interval_from_bounds
    >>> mid, radius = interval_from_bounds([0.9, -0.1, 0.0], [1.1, 0.1, 0.2])
    >>> mid.round(6), radius.round(6)
    (array([1. , 0. , 0.1]), array([0.1, 0.1, 0.1]))
    """
    lo = as_array("lower", lower)
    hi = as_array("upper", upper)
    if lo.shape != hi.shape:
        raise InputError(f"upper must have the shape of lower {lo.shape}; got {hi.shape}")
    if np.any(lo > hi):
        idx = tuple(int(i) for i in np.argwhere(lo > hi)[0])
        raise InputError(
            f"lower must be <= upper elementwise; got lower={lo[idx]:g} > upper={hi[idx]:g} "
            f"at index {idx}"
        )
    return 0.5 * (hi + lo), 0.5 * (hi - lo)


def _angle_bounds(v: np.ndarray, theta: float) -> tuple[np.ndarray, np.ndarray]:
    n = np.linalg.norm(v, axis=1, keepdims=True)
    u = v / np.where(n > 0, n, 1.0)
    phi = np.arccos(np.clip(u, -1.0, 1.0))
    lo = n * np.cos(np.minimum(np.pi, phi + theta))
    hi = n * np.cos(np.maximum(0.0, phi - theta))
    return lo, hi


def _fraction_bounds(v: np.ndarray, f: float, normalized: bool) -> tuple[np.ndarray, np.ndarray]:
    if normalized:
        a, b = v * (1.0 - f) / (1.0 + f), v * (1.0 + f) / (1.0 - f)
    else:
        a, b = v / (1.0 + f), v / (1.0 - f)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    if normalized:
        lo, hi = np.clip(lo, -1.0, 1.0), np.clip(hi, -1.0, 1.0)
    return lo, hi


def vector_bounds(
    measured: Any, *, angle_bound: float = 0.0, fraction: float = 0.0, normalized: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """Componentwise lower/upper bounds of the true vector given a measured one.

    Parameters
    ----------
    measured : array_like, shape (3,) or (N, 3)
        Measured vectors (any unit).
    angle_bound : float, rad
        Bound on the angular error, in [0, π).
    fraction : float
        Bound on the relative error of each component, in [0, 1).
    normalized : bool
        The measurement was re-normalised to unit length after the fraction error.

    Returns
    -------
    lower, upper : numpy.ndarray, shape of ``measured``

    See the module docstring for the formulas.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.sensors import vector_bounds
    >>> lower, upper = vector_bounds([1.0, 0.0, 0.0], angle_bound=np.radians(2.0))
    >>> bool(np.all(lower <= [1.0, 0.0, 0.0])), bool(np.all(upper >= [1.0, 0.0, 0.0]))
    (True, True)
    >>> lower.round(6), upper.round(6)
    (array([ 0.999391, -0.034899, -0.034899]), array([1.      , 0.034899, 0.034899]))
    >>> vector_bounds(np.ones((5, 3)), fraction=0.05)[0].shape
    (5, 3)
    """
    v, batched = as_batch("measured", measured, (3,))
    th = check_range("angle_bound", angle_bound, 0.0, np.pi, unit="rad", hi_open=True)
    f = check_range("fraction", fraction, 0.0, 1.0, hi_open=True)
    normalized = check_flag("normalized", normalized)
    if f > 0:
        lo, hi = _fraction_bounds(v, f, normalized)
        if th > 0:
            cmax = np.linalg.norm(np.maximum(np.abs(lo), np.abs(hi)), axis=1, keepdims=True)
            d = 2.0 * cmax * np.sin(th / 2.0)
            lo, hi = lo - d, hi + d
    elif th > 0:
        lo, hi = _angle_bounds(v, th)
    else:
        lo, hi = v.copy(), v.copy()
    return (lo, hi) if batched else (lo[0], hi[0])


def midpoint_radius(
    measured: Any, *, angle_bound: float = 0.0, fraction: float = 0.0, normalized: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """Midpoint-radius box ``(b^m, b^r)`` enclosing the true vector (S0 eq. 4-5).

    Parameters are those of :func:`vector_bounds`.

    Returns
    -------
    mid, radius : numpy.ndarray, shape of ``measured``
        Every true vector consistent with the measurement is ``mid + diag(α) radius`` for
        some ``α ∈ [-1, 1]^3``.

    Examples
    --------
    >>> mid, rad = midpoint_radius([1.0, 0.0, 0.0], fraction=0.2)
    >>> [round(float(x), 4) for x in (mid[0], rad[0])]
    [1.0417, 0.2083]

    References
    ----------
    S0, eq. 4-5 and Table 1.
    """
    lo, hi = vector_bounds(measured, angle_bound=angle_bound, fraction=fraction,
                           normalized=normalized)
    return 0.5 * (hi + lo), 0.5 * (hi - lo)
