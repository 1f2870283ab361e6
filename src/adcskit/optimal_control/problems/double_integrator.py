"""Double integrator test problems with analytic solutions.

* Rest-to-rest minimum time with ``|u| <= a``: bang-bang, ``tf = 2 sqrt(d / a)``, switch at
  ``tf / 2``, costates ``λ_x = −2 / (a tf)``, ``λ_v(t) = −1/a + 2 t / (a tf)``, ``H ≡ −1``.
* Rest-to-rest minimum energy ``∫ u² dt`` with fixed ``T``: ``u(t) = 6d/T² − 12 d t / T³``,
  ``J = 12 d² / T³``.

References
----------
Bryson & Ho, Applied Optimal Control, 1975, §7.3 (minimum time) and §2.7 (minimum energy).
"""

from __future__ import annotations

import numpy as np

from adcskit._validation import check_positive
from adcskit.optimal_control.problem import OptimalControlProblem

__all__ = ["double_integrator_min_time", "double_integrator_min_energy"]


def _f(x, u, t):
    return [x[1], u[0]]


def _tf(x0, t0, xf, tf):
    return tf


def _energy(x, u, t):
    return u[0] * u[0]


def double_integrator_min_time(distance: float = 1.0, accel_max: float = 1.0) -> OptimalControlProblem:
    """Minimum-time rest-to-rest move of ``distance`` (m) with ``|u| <= accel_max`` (m/s²)."""
    d = check_positive("distance", distance, unit="m", min_value=1e-50, max_value=1e50)
    a = check_positive("accel_max", accel_max, unit="m/s^2", min_value=1e-50, max_value=1e50)
    tf = 2.0 * np.sqrt(d / a)
    return OptimalControlProblem(
        name="double-integrator-min-time",
        dynamics=_f,
        n_states=2,
        n_controls=1,
        state_names=("x", "v"),
        control_names=("u",),
        control_lower=[-a],
        control_upper=[a],
        initial_state=[0.0, 0.0],
        final_state=[d, 0.0],
        tf_bounds=(1e-3 * tf, 100.0 * tf),
        tf_guess=1.3 * tf,
        mayer=_tf,
        state_scale=[d, a * tf / 2],
    )


def double_integrator_min_energy(distance: float = 1.0, duration: float = 1.0) -> OptimalControlProblem:
    """Minimum-energy rest-to-rest move of ``distance`` (m) in fixed ``duration`` (s)."""
    d = check_positive("distance", distance, unit="m", min_value=1e-50, max_value=1e50)
    T = check_positive("duration", duration, unit="s", min_value=1e-50, max_value=1e50)
    return OptimalControlProblem(
        name="double-integrator-min-energy",
        dynamics=_f,
        n_states=2,
        n_controls=1,
        state_names=("x", "v"),
        control_names=("u",),
        initial_state=[0.0, 0.0],
        final_state=[d, 0.0],
        tf_bounds=(T, T),
        lagrange=_energy,
        state_scale=[d, d / T],
        control_scale=[d / T**2],
    )
