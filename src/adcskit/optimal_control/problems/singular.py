"""Test problems with singular arcs and mixed state-control path constraints, closed-form optima.

* :func:`bang_singular_bang` — ``min ∫ x² dt``, ``ẋ = u``, ``|u| <= 1``, ``x(0) = x(tf) = 1``.
  For ``tf >= 2`` the minimum principle gives ``u = −1`` on ``[0, 1]``, the singular arc
  ``x = 0, u = 0`` (``H = x² + λu``, ``∂H/∂u = λ ≡ 0`` there, hence ``λ̇ = −2x = 0``) on
  ``[1, tf − 1]`` and ``u = +1`` on ``[tf − 1, tf]``: ``J* = 2 ∫_0^1 (1 − t)² dt = 2/3``
  whatever the singular arc's length ``tf − 2`` (a lower bound too: ``|ẋ| <= 1`` gives
  ``x(t) >= max(1 − t, 1 − (tf − t), 0)`` pointwise, and this trajectory attains it). A short
  arc (``tf = 2.04``) is what a bang-bang answer (one switch at ``tf/2``, ``J = 2(1 − (1 −
  tf/2)³)/3``) misses by ``O((tf − 2)³)``.
* :func:`rest_to_rest_mixed_path` — minimum time to move ``ẍ = u`` over ``d`` from rest to
  rest with ``u >= −1`` and the mixed path constraint ``u + v <= 1``. Every admissible speed
  obeys ``v(t) <= 1 − e^{−t}`` (from ``v̇ <= 1 − v``, ``v(0) = 0``) and ``v(t) <= T − t``
  (from ``v̇ >= −1``, ``v(T) = 0``); the profile ``min(1 − e^{−t}, T − t)`` is admissible,
  so ``T*`` is the smallest ``T`` with ``∫_0^T min(1 − e^{−t}, T − t) dt = d``
  (:func:`rest_to_rest_mixed_path_time`): the constraint is active on the whole first arc.

Both optima are derived in these docstrings (comparison arguments), not taken from a paper.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from adcskit._validation import check_range
from adcskit.optimal_control.problem import OptimalControlProblem

__all__ = [
    "bang_singular_bang",
    "bang_singular_bang_objective",
    "rest_to_rest_mixed_path",
    "rest_to_rest_mixed_path_time",
]


def _bsb_f(x, u, t):
    return [u[0]]


def _bsb_g(x, u, t):
    return x[0] * x[0]


def bang_singular_bang(tf: float = 3.0) -> OptimalControlProblem:
    """``min ∫_0^tf x² dt``, ``ẋ = u``, ``|u| <= 1``, ``x(0) = x(tf) = 1`` (fixed ``tf``).

    Parameters
    ----------
    tf : float
        Horizon (s), in ``[2, 100]``: the singular arc lasts ``tf − 2``.

    Examples
    --------
    >>> from adcskit.optimal_control.problems import bang_singular_bang, bang_singular_bang_objective
    >>> bang_singular_bang(2.04).tf_bounds, round(bang_singular_bang_objective(2.04), 9)
    ((2.04, 2.04), 0.666666667)
    """
    tf = check_range("tf", tf, 2.0, 100.0)
    return OptimalControlProblem(
        name="bang-singular-bang",
        dynamics=_bsb_f,
        n_states=1,
        n_controls=1,
        state_names=("x",),
        control_names=("u",),
        control_lower=[-1.0],
        control_upper=[1.0],
        initial_state=[1.0],
        final_state=[1.0],
        tf_bounds=(tf, tf),
        lagrange=_bsb_g,
        state_scale=[1.0],
        control_scale=[1.0],
    )


def bang_singular_bang_objective(tf: float = 3.0) -> float:
    """``J* = 2/3`` of :func:`bang_singular_bang` for every ``tf >= 2`` (module docstring).

    Examples
    --------
    >>> from adcskit.optimal_control.problems import bang_singular_bang_objective
    >>> bang_singular_bang_objective(3.0) == 2.0 / 3.0
    True
    """
    check_range("tf", tf, 2.0, 100.0)
    return 2.0 / 3.0


def _rr_f(x, u, t):
    return [x[1], u[0]]


def _rr_path(x, u, t):
    return [u[0] + x[1]]


def _rr_mayer(x0, t0, xf, tf):
    return tf


def _rr_distance(T: float) -> float:
    """``∫_0^T min(1 − e^{−t}, T − t) dt``: the crossing ``t1`` solves ``1 − e^{−t1} = T − t1``."""
    t1 = brentq(lambda t: 1.0 - np.exp(-t) - (T - t), 0.0, T)
    v1 = T - t1
    return float(t1 - (1.0 - np.exp(-t1)) + 0.5 * v1 * v1)


def rest_to_rest_mixed_path_time(distance: float = 1.0) -> float:
    """Minimum time ``T*`` (s) of :func:`rest_to_rest_mixed_path` (module docstring).

    Examples
    --------
    >>> from adcskit.optimal_control.problems import rest_to_rest_mixed_path_time
    >>> round(rest_to_rest_mixed_path_time(1.0), 6)
    2.244704
    """
    d = check_range("distance", distance, 1e-3, 100.0)
    return float(brentq(lambda T: _rr_distance(T) - d, 1e-9, 2.0 * d + 10.0, xtol=1e-14, rtol=1e-15))


def rest_to_rest_mixed_path(distance: float = 1.0) -> OptimalControlProblem:
    """Minimum time ``ẍ = u``, ``(0, 0) → (distance, 0)``, ``u >= −1``, ``u + v <= 1``.

    ``u`` has the upper bound 2 (inactive at the optimum, where ``u = 1 − v <= 1``) so that
    every channel is bounded.

    Parameters
    ----------
    distance : float
        Distance (m), in ``[1e-3, 100]``.

    Examples
    --------
    >>> from adcskit.optimal_control.problems import rest_to_rest_mixed_path
    >>> rest_to_rest_mixed_path().path_upper.tolist()
    [1.0]
    """
    d = check_range("distance", distance, 1e-3, 100.0)
    t_guess = 2.0 * np.sqrt(d) + 1.0
    return OptimalControlProblem(
        name="rest-to-rest-mixed-path",
        dynamics=_rr_f,
        n_states=2,
        n_controls=1,
        state_names=("x", "v"),
        control_names=("u",),
        control_lower=[-1.0],
        control_upper=[2.0],
        initial_state=[0.0, 0.0],
        final_state=[d, 0.0],
        path=_rr_path,
        path_upper=[1.0],
        tf_bounds=(0.1, 10.0 * t_guess),
        tf_guess=t_guess,
        mayer=_rr_mayer,
        state_scale=[max(d, 1.0), 1.0],
        control_scale=[1.0],
    )
