"""Guidance tables from optimal-control solutions.

:func:`optimal_slew_table` solves the time-optimal rest-to-rest eigenaxis slew
(``theta'' = u``, ``|u| <= alpha_max``: a double integrator, whose minimum-time solution is
bang-bang, S2 §3) with :mod:`adcskit.optimal_control` (Gauss pseudospectral + IPOPT) and
turns the attitude part of the solution into a :class:`GuidanceSpec` time table: the angle
``theta(t)`` about the unit axis ``e`` gives ``q(t) = [sin(theta/2) e, cos(theta/2)]`` and
the rate ``omega(t) = theta'(t) e``. For a slew about a principal axis with torque bound
``T``, ``alpha_max = T / J_axis`` makes the table dynamically feasible.

References
----------
S2 (Gauss pseudospectral method, time-optimal manoeuvres); Markley & Crassidis (2014)
§7.6 (eigenaxis slews).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from adcskit._validation import as_array, check_int, check_positive
from adcskit.errors import InputError, SolverError
from adcskit.simulation.scenario import GuidanceSpec

__all__ = ["optimal_slew_table", "table_from_angle"]


def table_from_angle(t: Any, theta: Any, omega: Any, axis: Any, *, t0: float = 0.0) -> GuidanceSpec:
    """A ``table`` guidance from an eigenaxis angle history.

    Parameters
    ----------
    t : array_like (M,), s
        Increasing times of the profile (shifted by ``t0``).
    theta : array_like (M,), rad
        Slew angle about ``axis``.
    omega : array_like (M,), rad/s
        Its rate.
    axis : array_like (3,)
        Slew axis (normalised here), body = reference frame at the start.
    t0 : float, s
        Start time of the slew in the simulation.

    Returns
    -------
    GuidanceSpec

    Examples
    --------
    >>> g = table_from_angle([0.0, 1.0], [0.0, 0.1], [0.0, 0.0], [0, 0, 1])
    >>> g.kind, len(g.table_q)
    ('table', 2)
    """
    tt = as_array("t", t, ndim=1)
    th = as_array("theta", theta, ndim=1)
    om = as_array("omega", omega, ndim=1)
    e = as_array("axis", axis, shape=(3,))
    if th.shape != tt.shape or om.shape != tt.shape:
        raise InputError(f"t, theta and omega must have the same length; got {tt.shape}, {th.shape}, {om.shape}")
    ne = np.linalg.norm(e)
    if ne < 1e-12:
        raise InputError("axis must be non-zero")
    e = e / ne
    keep = np.r_[True, np.diff(tt) > 1e-9]  # collapse duplicate times (interval joints)
    tt, th, om = tt[keep], th[keep], om[keep]
    q = np.concatenate([np.sin(th / 2)[:, None] * e, np.cos(th / 2)[:, None]], axis=1)
    w = om[:, None] * e
    return GuidanceSpec(kind="table", table_t=tuple(float(x) for x in tt + t0),
                        table_q=tuple(tuple(map(float, r)) for r in q),
                        table_w=tuple(tuple(map(float, r)) for r in w))


def optimal_slew_table(
    angle: float,
    accel_max: float,
    axis: Any = (1.0, 0.0, 0.0),
    *,
    t0: float = 0.0,
    mesh: tuple[int, int] = (20, 3),
    n_table: int = 201,
) -> tuple[GuidanceSpec, Any]:
    """Time-optimal rest-to-rest eigenaxis slew from :mod:`adcskit.optimal_control`.

    Parameters
    ----------
    angle : float, rad
        Slew angle (> 0).
    accel_max : float, rad/s^2
        Angular-acceleration bound (``T / J`` about the axis).
    axis : array_like (3,)
        Slew axis.
    t0 : float, s
        When the slew starts in the simulation.
    mesh : (int, int)
        Pseudospectral mesh (intervals, nodes per interval).
    n_table : int
        Table entries (the solution's interpolant is sampled uniformly in time).

    Returns
    -------
    (GuidanceSpec, OptimalControlSolution)

    Raises
    ------
    SolverError
        If IPOPT does not converge.

    References
    ----------
    S2 §3 (Gauss pseudospectral transcription); the exact optimum is bang-bang with
    ``t_f = 2 sqrt(angle / accel_max)``.
    """
    from adcskit.optimal_control import solve
    from adcskit.optimal_control.problems.double_integrator import double_integrator_min_time

    angle = check_positive("angle", angle, unit="rad")
    accel_max = check_positive("accel_max", accel_max, unit="rad/s^2")
    n_table = check_int("n_table", n_table, minimum=2)
    sol = solve(double_integrator_min_time(distance=angle, accel_max=accel_max), mesh=mesh)
    if not sol.success:
        raise SolverError(f"optimal slew did not converge: {sol.message}")
    t = np.linspace(sol.t0, sol.tf, n_table)
    # the state samples are piecewise-polynomial; between them a cubic Hermite with the
    # sampled rate is exact for this problem's piecewise-quadratic angle
    ts, xs = np.asarray(sol.t), np.asarray(sol.x)
    keep = np.r_[True, np.diff(ts) > 1e-12]
    ts, xs = ts[keep], xs[keep]
    from scipy.interpolate import CubicHermiteSpline

    th = CubicHermiteSpline(ts, xs[:, 0], xs[:, 1])(t)
    om = np.interp(t, ts, xs[:, 1])
    th[-1], om[-1] = angle, 0.0
    if not math.isfinite(float(sol.tf)):
        raise SolverError("optimal slew returned a non-finite final time")
    return table_from_angle(t - sol.t0, th, om, axis, t0=t0), sol
