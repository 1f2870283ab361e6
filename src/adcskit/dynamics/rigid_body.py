"""Rigid-body rotational dynamics: Euler's equations and attitude propagation.

``J ω̇ = τ − ω × (J ω)`` with ``ω`` the body rate (rad/s, body components) relative to an
inertial reference, ``J`` the inertia tensor about the centre of mass (kg m²) and ``τ`` the
external torque (N m, body). Attitude propagation integrates the quaternion kinematics of
:mod:`adcskit.attitude.kinematics` together with Euler's equations by
``scipy.integrate.solve_ivp`` (adaptive; DOP853 by default) and renormalises the quaternion.

References
----------
Markley & Crassidis (2014), eq. 3.81 (Euler's equations), eq. 3.20 (kinematics).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from adcskit._validation import as_array, as_batch, check_positive
from adcskit.attitude import _kernels as _k
from adcskit.attitude._checks import broadcast, out, quats
from adcskit.errors import InputError

__all__ = ["AttitudeTrajectory", "as_inertia", "euler_equations", "propagate_attitude"]


def as_inertia(inertia: Any, name: str = "inertia") -> np.ndarray:
    """Inertia tensor from a ``(3,)`` diagonal or a ``(3, 3)`` matrix; checked symmetric
    positive definite (the triangle inequalities follow from a physical body but are not
    enforced, so that models of idealised bodies remain usable)."""
    arr = as_array(name, inertia)
    if arr.shape == (3,):
        arr = np.diag(arr)
    if arr.shape != (3, 3):
        raise InputError(f"{name} must have shape (3,) (principal moments) or (3, 3); got shape {arr.shape}")
    if not np.allclose(arr, arr.T, rtol=1e-12, atol=1e-12 * np.abs(arr).max()):
        raise InputError(f"{name} must be symmetric; got {arr.tolist()}")
    ev = np.linalg.eigvalsh(arr)
    if ev.min() <= 0:
        raise InputError(f"{name} must be positive definite (kg m²); got eigenvalues {ev.tolist()}")
    return arr


def _euler_rhs(w: np.ndarray, J: np.ndarray, tau: np.ndarray) -> np.ndarray:
    Jw = w @ J.T
    return np.linalg.solve(J, (tau - np.cross(w, Jw)).T).T


def euler_equations(omega: Any, inertia: Any, torque: Any = None) -> np.ndarray:
    """Angular acceleration ``ω̇ = J⁻¹ (τ − ω × J ω)``.

    Parameters
    ----------
    omega : array_like, shape (3,) or (N, 3), rad/s
    inertia : array_like, shape (3,) or (3, 3), kg m²
    torque : array_like, shape (3,) or (N, 3), N m, optional (default zero)

    Returns
    -------
    numpy.ndarray, shape like ``omega``, rad/s²
    """
    w, wb = as_batch("omega", omega, (3,))
    J = as_inertia(inertia)
    if torque is None:
        t, tb = np.zeros((1, 3)), False
    else:
        t, tb = as_batch("torque", torque, (3,))
    w, t = broadcast("omega", w, "torque", t)
    return out(_euler_rhs(w, J, t), wb or tb)


@dataclass(frozen=True, slots=True, kw_only=True)
class AttitudeTrajectory:
    """Result of :func:`propagate_attitude`.

    Attributes
    ----------
    t : ndarray (M,), s
    q : ndarray (M, 4), canonical scalar-last quaternions
    omega : ndarray (M, 3), rad/s
    success, status, message, nfev : as in ``scipy.integrate.solve_ivp``
    """

    t: np.ndarray
    q: np.ndarray
    omega: np.ndarray
    success: bool
    status: int
    message: str
    nfev: int

    def to_dict(self) -> dict[str, Any]:
        return {
            "t": self.t.tolist(),
            "q": self.q.tolist(),
            "omega": self.omega.tolist(),
            "success": self.success,
            "status": self.status,
            "message": self.message,
            "nfev": self.nfev,
        }


def propagate_attitude(
    q0: Any,
    omega0: Any,
    inertia: Any,
    t_eval: Any,
    torque: Callable[[float, np.ndarray, np.ndarray], Any] | None = None,
    *,
    method: str = "DOP853",
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> AttitudeTrajectory:
    """Integrate quaternion kinematics and Euler's equations.

    Parameters
    ----------
    q0 : array_like (4,)
        Initial attitude (reference → body, scalar last).
    omega0 : array_like (3,), rad/s
        Initial body rate.
    inertia : array_like (3,) or (3, 3), kg m²
    t_eval : array_like (M,), s
        Increasing output times; integration runs from ``t_eval[0]`` to ``t_eval[-1]``.
    torque : callable ``torque(t, q, omega) -> (3,)`` N m, optional
        External torque in body components (e.g. gravity gradient).
    method, rtol, atol :
        Passed to ``scipy.integrate.solve_ivp``.

    Returns
    -------
    AttitudeTrajectory
        ``success=False`` with the integrator's message if it fails.
    """
    q, _ = quats("q0", q0)
    if q.shape[0] != 1:
        raise InputError(f"q0 must be one quaternion of shape (4,); got {q.shape[0]} quaternions")
    w = as_array("omega0", omega0, shape=(3,))
    J = as_inertia(inertia)
    t = as_array("t_eval", t_eval, ndim=1)
    if t.size < 2 or np.any(np.diff(t) <= 0):
        raise InputError(f"t_eval must hold >= 2 strictly increasing times (s); got {t.size} values")
    check_positive("rtol", rtol)
    check_positive("atol", atol)

    def rhs(tt: float, x: np.ndarray) -> np.ndarray:
        qq = x[:4] / np.linalg.norm(x[:4])
        ww = x[4:]
        tau = np.zeros(3) if torque is None else np.asarray(torque(tt, qq, ww), dtype=float)
        v, s = qq[:3], qq[3]
        dq = np.concatenate([0.5 * (s * ww + np.cross(v, ww)), [-0.5 * v @ ww]])
        dw = np.linalg.solve(J, tau - np.cross(ww, J @ ww))
        return np.concatenate([dq, dw])

    sol = solve_ivp(rhs, (t[0], t[-1]), np.concatenate([q[0], w]), method=method, t_eval=t, rtol=rtol, atol=atol)
    y = sol.y.T if sol.y.size else np.empty((0, 7))
    qs = _k.canonical(y[:, :4]) if len(y) else y[:, :4]
    return AttitudeTrajectory(
        t=np.asarray(sol.t),
        q=qs,
        omega=y[:, 4:],
        success=bool(sol.success),
        status=int(sol.status),
        message=str(sol.message),
        nfev=int(sol.nfev),
    )
