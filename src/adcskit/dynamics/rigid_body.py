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

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from adcskit._results import Result
from adcskit._validation import (
    as_array,
    as_batch,
    check_callable,
    check_int,
    check_positive,
    short_repr,
)
from adcskit.attitude import _kernels as _k
from adcskit.attitude._checks import broadcast, out, quats
from adcskit.errors import InputError

__all__ = ["AttitudeTrajectory", "as_inertia", "euler_equations", "propagate_attitude"]

#: Largest ``| |q0| - 1 |`` that :func:`propagate_attitude` accepts (rounding of a unit quaternion).
_Q0_NORM_TOL = 1e-9


def as_inertia(inertia: Any, name: str = "inertia") -> np.ndarray:
    """Inertia tensor from a ``(3,)`` diagonal or a ``(3, 3)`` matrix; checked symmetric
    positive definite (the triangle inequalities follow from a physical body but are not
    enforced, so that models of idealised bodies remain usable).

    Examples
    --------
    >>> as_inertia([10.0, 12.0, 8.0])
    array([[10.,  0.,  0.],
           [ 0., 12.,  0.],
           [ 0.,  0.,  8.]])
    """
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

    Examples
    --------
    >>> euler_equations([0.0, 0.0, 0.0], [10.0, 12.0, 8.0], torque=[1.0, 0.0, 0.0])   # rad/s^2
    array([0.1, 0. , 0. ])
    """
    w, wb = as_batch("omega", omega, (3,))
    J = as_inertia(inertia)
    if torque is None:
        t, tb = np.zeros((1, 3)), False
    else:
        t, tb = as_batch("torque", torque, (3,))
    w, t = broadcast("omega", w, "torque", t)
    return out(_euler_rhs(w, J, t), wb or tb)


@dataclass(frozen=True, slots=True, repr=False, kw_only=True)
class AttitudeTrajectory(Result):
    """Result of :func:`propagate_attitude`.

    Attributes
    ----------
    t : ndarray (M,), s
    q : ndarray (M, 4), canonical scalar-last quaternions
    omega : ndarray (M, 3), rad/s
    success, status, message, nfev : as in ``scipy.integrate.solve_ivp``

    Examples
    --------
    >>> import numpy as np
    >>> traj = propagate_attitude([0, 0, 0, 1], [0.0, 0.0, 0.1], [10.0, 12.0, 8.0], np.linspace(0, 10, 11))
    >>> traj.success, traj.q.shape
    (True, (11, 4))
    """

    t: np.ndarray
    q: np.ndarray
    omega: np.ndarray
    success: bool
    status: int
    message: str
    nfev: int


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
    max_nfev: int = 1_000_000,
    max_wall_s: float | None = None,
) -> AttitudeTrajectory:
    """Integrate quaternion kinematics and Euler's equations.

    Parameters
    ----------
    q0 : array_like (4,)
        Initial attitude (reference → body, scalar last), a unit quaternion: ``| |q0| − 1 |``
        must be ≤ 1e-9 (rounding), else :class:`~adcskit.errors.InputError`.
    omega0 : array_like (3,), rad/s
        Initial body rate.
    inertia : array_like (3,) or (3, 3), kg m²
    t_eval : array_like (M,), s
        Increasing output times; integration runs from ``t_eval[0]`` to ``t_eval[-1]``.
    torque : callable ``torque(t, q, omega) -> (3,)`` N m, optional
        External torque in body components (e.g. gravity gradient).
    method, rtol, atol :
        Passed to ``scipy.integrate.solve_ivp``.
    max_nfev : int
        Guard against runaway integrations: stop with ``success=False`` after this many
        right-hand-side evaluations, or at once when the initial rate alone needs more
        (``|omega0| (t_end - t_start)`` radians at one evaluation per radian at least).
    max_wall_s : float, optional
        Wall-clock guard in seconds (off by default, since it makes results depend on the
        machine's speed).

    Returns
    -------
    AttitudeTrajectory
        ``success=False`` with a message if the integrator fails, a guard stops it, or the
        torque function returns a non-finite or wrongly shaped value.

    Examples
    --------
    >>> from adcskit.attitude import error_angle
    >>> import numpy as np
    >>> t = np.linspace(0.0, 60.0, 7)
    >>> traj = propagate_attitude([0, 0, 0, 1], [0.0, 0.0, 0.1], [10.0, 12.0, 8.0], t)
    >>> round(float(np.degrees(error_angle(traj.q[-1], [0, 0, 0, 1]))), 3)   # 6 rad about z
    16.225
    """
    q, _ = quats("q0", q0)
    if q.shape[0] != 1:
        raise InputError(f"q0 must be one quaternion of shape (4,); got {q.shape[0]} quaternions")
    nq = float(np.linalg.norm(as_array("q0", q0)))
    if abs(nq - 1.0) > _Q0_NORM_TOL:
        raise InputError(f"q0 must be a unit quaternion (|q0| within {_Q0_NORM_TOL:g} of 1: rounding only, an "
                         f"initial state is not normalised silently); got |q0| = {nq:.12g}")
    w = as_array("omega0", omega0, shape=(3,))
    J = as_inertia(inertia)
    t = as_array("t_eval", t_eval, ndim=1)
    if t.size < 2 or np.any(np.diff(t) <= 0):
        raise InputError(f"t_eval must hold >= 2 strictly increasing times (s); got {t.size} values")
    check_positive("rtol", rtol)
    check_positive("atol", atol)
    check_callable("torque", torque, allow_none=True)
    max_nfev = check_int("max_nfev", max_nfev, minimum=1)
    if max_wall_s is not None:
        max_wall_s = check_positive("max_wall_s", max_wall_s, unit="s")
    guard = _Guard(max_nfev, max_wall_s)
    if float(np.linalg.norm(w)) * (t[-1] - t[0]) > max_nfev:
        return _failed(t, q[0], w, f"the initial rate |omega0| = {np.linalg.norm(w):.3g} rad/s over "
                       f"{t[-1] - t[0]:.3g} s needs more than max_nfev = {max_nfev} evaluations")

    def rhs(tt: float, x: np.ndarray) -> np.ndarray:
        guard.tick()
        if not np.all(np.isfinite(x)):
            raise _Abort(f"the state became non-finite at t = {tt:.6g} s")
        qq = x[:4] / np.linalg.norm(x[:4])
        ww = x[4:]
        if torque is None:
            tau = np.zeros(3)
        else:
            try:
                tau = np.asarray(torque(tt, qq, ww), dtype=float)
            except (TypeError, ValueError) as exc:
                raise _Abort(f"torque(t, q, omega) did not return 3 real numbers at t = {tt:.6g} s: {exc}") from None
            if tau.shape != (3,) or not np.all(np.isfinite(tau)) or np.abs(tau).max() > 1e150:
                raise _Abort(f"torque(t, q, omega) must return 3 finite numbers (N m); got "
                             f"{short_repr(tau)} at t = {tt:.6g} s")
        v, s = qq[:3], qq[3]
        dq = np.concatenate([0.5 * (s * ww + np.cross(v, ww)), [-0.5 * v @ ww]])
        dw = np.linalg.solve(J, tau - np.cross(ww, J @ ww))
        return np.concatenate([dq, dw])

    try:
        sol = solve_ivp(rhs, (t[0], t[-1]), np.concatenate([q[0], w]), method=method, t_eval=t, rtol=rtol,
                        atol=atol)
    except _Abort as exc:
        return _failed(t, q[0], w, str(exc), guard.nfev)
    # a step-size failure before the first t_eval point leaves sol.y a plain empty list
    y = np.asarray(sol.y, dtype=float).reshape(7, -1).T
    if not np.all(np.isfinite(y)):
        return _failed(t, q[0], w, "the integration produced non-finite values", int(sol.nfev))
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


class _Abort(Exception):
    """Internal: stops :func:`propagate_attitude`'s integration; becomes ``success=False``."""


class _Guard:
    """Counts right-hand-side evaluations and wall time of one integration."""

    def __init__(self, max_nfev: int, max_wall_s: float | None) -> None:
        self.nfev = 0
        self.max_nfev = max_nfev
        self.max_wall_s = max_wall_s
        self.t0 = time.perf_counter()

    def tick(self) -> None:
        self.nfev += 1
        if self.nfev > self.max_nfev:
            raise _Abort(f"stopped after max_nfev = {self.max_nfev} evaluations (runaway integration; "
                         "raise max_nfev to continue)")
        if self.max_wall_s is not None and self.nfev % 64 == 0:
            if time.perf_counter() - self.t0 > self.max_wall_s:
                raise _Abort(f"stopped after max_wall_s = {self.max_wall_s:g} s of wall-clock time")


def _failed(t: np.ndarray, q0: np.ndarray, w0: np.ndarray, message: str, nfev: int = 0) -> AttitudeTrajectory:
    """A ``success=False`` trajectory holding only the initial state."""
    return AttitudeTrajectory(t=t[:1].copy(), q=q0[None].copy(), omega=w0[None].copy(), success=False,
                              status=-1, message=message, nfev=int(nfev))
