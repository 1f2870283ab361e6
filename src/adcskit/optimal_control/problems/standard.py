"""Standard optimal-control test problems with published or closed-form optima.

Each function returns the problem; the reference optimum is returned by
:func:`reference_objective` with its source, so tests and benchmarks compare against it.

* :func:`hypersensitive` — Rao & Mease (2000): ``min ½∫(x² + u²)``, ``ẋ = −x³ + u``,
  ``x(0) = 1``, ``x(tf) = 1.5``; boundary layers at both ends.
* :func:`bryson_denham` — Bryson & Ho (1975, §3.11): double integrator, ``min ½∫u²`` with
  the state inequality ``x <= l``; ``J* = 4 / (9 l)`` for ``l <= 1/6``.
* :func:`brachistochrone` — minimum-time slide under gravity; the optimum is a cycloid
  (closed form, :func:`brachistochrone_time`).
* :func:`rigid_body_reorientation` — minimum-time rest-to-rest reorientation of a rigid body
  with ``|u_i| <= 1`` (Bilimoria & Wie 1993); for a spherical body (unit inertia) turned
  180° about a principal axis the optimum (3.243) beats the eigenaxis slew ``2√π``.
* :func:`goddard_rocket` — the Goddard maximum-altitude rocket as a three-phase problem
  (full thrust, singular arc, coast) with the singular-arc condition as a path constraint
  (Bryson 1999, §9.3; GPOPS-II example).
* :func:`free_flying_robot` — Sakawa's planar free-flying robot with two thrusters, minimum
  fuel ``∫ Σ u_i`` in fixed time (Sakawa 1999; Betts 2010, ex. 6.13; GPOPS-II
  ``J* = 7.9101471``); bang-bang thrusts with several switches.
* :func:`oscillator_min_time` — minimum time to bring a controlled harmonic oscillator
  ``ẍ = −x + u``, ``|u| <= 1`` to rest at the origin (Pontryagin et al. 1962, §I.5):
  bang-bang with a switch every π s; the default start needs four switches.
* :func:`orbit_raising` — Bryson & Ho (1975, §2.5): maximum final radius of a low-thrust
  transfer in fixed time, the thrust direction a unit vector ``(w1, w2)``,
  ``w1² + w2² = 1`` (a path constraint); ``r(tf) = 1.525 r0``.
* :func:`robot_arm` — COPS 3.0 problem "robot" (Dolan, Moré & Munson 2004): minimum time to
  swing a robot arm (three coupled rotations/extension, ``|u_i| <= 1``); ``tf* = 9.1409118``.

References
----------
Rao & Mease, Automatica 36(12), 2000. Bryson & Ho, Applied Optimal Control, 1975, §3.11.
Bilimoria & Wie, J. Guid. Control Dyn. 16(3), 1993. Bryson, Dynamic Optimization, 1999,
§9.3. Patterson & Rao, ACM TOMS 41(1), 2014 (GPOPS-II). Sakawa, Optim. Control Appl. Meth.
20(5), 1999. Betts, Practical Methods for Optimal Control, 2nd ed., SIAM 2010, ex. 6.13.
Pontryagin, Boltyanskii, Gamkrelidze & Mishchenko, The Mathematical Theory of Optimal
Processes, 1962, §I.5. Dolan, Moré & Munson, Benchmarking optimization software with COPS
3.0, Argonne tech. rep. ANL/MCS-TM-273, 2004, §8 (robot arm).
"""

from __future__ import annotations

import casadi as ca
import numpy as np
from scipy.optimize import brentq

from adcskit._validation import check_finite, check_positive, check_range
from adcskit.errors import InputError, SolverError
from adcskit.optimal_control.multiphase import MultiPhaseProblem, Phase
from adcskit.optimal_control.problem import OptimalControlProblem

__all__ = [
    "brachistochrone",
    "brachistochrone_time",
    "bryson_denham",
    "free_flying_robot",
    "goddard_rocket",
    "hypersensitive",
    "oscillator_min_time",
    "oscillator_min_time_reference",
    "orbit_raising",
    "reference_objective",
    "rigid_body_reorientation",
    "robot_arm",
]


# ------------------------------------------------------------------------- hypersensitive
def _hs_f(x, u, t):
    return [-x[0] ** 3 + u[0]]


def _hs_g(x, u, t):
    return 0.5 * (x[0] * x[0] + u[0] * u[0])


def hypersensitive(tf: float = 10.0) -> OptimalControlProblem:
    """Rao & Mease's hyper-sensitive problem on ``[0, tf]`` (s).

    Examples
    --------
    >>> from adcskit.optimal_control.problems.standard import hypersensitive
    >>> hypersensitive(10.0).tf_bounds
    (10.0, 10.0)
    """
    tf = check_positive("tf", tf, unit="s")
    return OptimalControlProblem(
        name="hypersensitive",
        dynamics=_hs_f,
        n_states=1,
        n_controls=1,
        initial_state=[1.0],
        final_state=[1.5],
        tf_bounds=(tf, tf),
        lagrange=_hs_g,
        state_scale=[1.0],
        control_scale=[1.0],
    )


# ------------------------------------------------------------------------- Bryson-Denham
def _bd_f(x, u, t):
    return [x[1], u[0]]


def _bd_g(x, u, t):
    return 0.5 * u[0] * u[0]


def bryson_denham(l: float = 1.0 / 9.0) -> OptimalControlProblem:  # noqa: E741 - Bryson & Ho's symbol
    """Bryson–Denham problem: ``x(0) = 0, v(0) = 1, x(1) = 0, v(1) = −1``, ``x <= l``.

    Examples
    --------
    >>> from adcskit.optimal_control.problems.standard import bryson_denham
    >>> float(bryson_denham(1 / 9).state_upper[0]) == 1 / 9
    True
    """
    l = check_positive("l", l, unit="m", min_value=1e-6)  # noqa: E741 (control scale ~ 1/l)
    return OptimalControlProblem(
        name="bryson-denham",
        dynamics=_bd_f,
        n_states=2,
        n_controls=1,
        state_names=("x", "v"),
        control_names=("u",),
        state_upper=[l, np.inf],
        initial_state=[0.0, 1.0],
        final_state=[0.0, -1.0],
        tf_bounds=(1.0, 1.0),
        lagrange=_bd_g,
        state_scale=[l, 1.0],
        control_scale=[1.0 / l],
    )


# ------------------------------------------------------------------------- brachistochrone
_G0 = 9.80665


def _br_f(x, u, t):
    v = x[2]
    return [v * ca.sin(u[0]), -v * ca.cos(u[0]), _G0 * ca.cos(u[0])]


def _br_mayer(x0, t0, xf, tf):
    return tf


def brachistochrone(x_final: float = 10.0, drop: float = 5.0) -> OptimalControlProblem:
    """Minimum-time slide from rest at ``(0, 10)`` m to ``(x_final, 10 − drop)`` m, ``g = 9.80665``.

    States ``(x, y, v)`` (m, m, m/s), control the angle θ from the downward vertical (rad);
    the dymos example uses ``x_final = 10``, ``drop = 5``.

    Examples
    --------
    >>> from adcskit.optimal_control.problems.standard import brachistochrone, brachistochrone_time
    >>> round(brachistochrone_time(10.0, 5.0), 4)
    1.8016
    """
    xf = check_positive("x_final", x_final, unit="m")
    dy = check_positive("drop", drop, unit="m")
    _check_ratio(xf, dy)
    t_ref = brachistochrone_time(xf, dy)
    return OptimalControlProblem(
        name="brachistochrone",
        dynamics=_br_f,
        n_states=3,
        n_controls=1,
        state_names=("x", "y", "v"),
        control_names=("theta",),
        state_lower=[0.0, -np.inf, 0.0],
        control_lower=[0.0],
        control_upper=[np.pi],
        initial_state=[0.0, 10.0, 0.0],
        final_state=[xf, 10.0 - dy, np.nan],
        tf_bounds=(0.2 * t_ref, 5.0 * t_ref),
        tf_guess=2.0 * t_ref,
        mayer=_br_mayer,
        state_scale=[xf, 10.0, np.sqrt(2 * _G0 * dy)],
        control_scale=[1.0],
    )


def _check_ratio(xf: float, dy: float) -> None:
    # the cycloid's angle is bracketed in [1e-3, 2 pi): x_final / drop must lie in its range
    if not 1e-3 <= xf / dy <= 1e12:
        raise InputError(f"x_final / drop must be in [1e-3, 1e12] (a cycloid through the end point); "
                         f"got x_final = {xf:g} m, drop = {dy:g} m")


def brachistochrone_time(x_final: float, drop: float, g: float = _G0) -> float:
    """Closed-form minimum time (s) of the brachistochrone: the cycloid
    ``x = R(φ − sin φ)``, ``y = R(1 − cos φ)`` through the end point, ``T = φ_f √(R/g)``.

    Examples
    --------
    End at the cycloid's lowest point (x = πR, y = 2R): φ_f = π, T = π √(R/g) = π for R = g = 1.

    >>> import numpy as np
    >>> round(brachistochrone_time(np.pi, 2.0, g=1.0), 9)
    3.141592654
    """
    xf = check_positive("x_final", x_final, unit="m")
    dy = check_positive("drop", drop, unit="m")
    _check_ratio(xf, dy)
    g = check_positive("g", g, unit="m/s^2")
    ratio = xf / dy
    phi = brentq(lambda p: (p - np.sin(p)) - ratio * (1.0 - np.cos(p)), 1e-3, 2 * np.pi - 1e-9, xtol=1e-15)
    R = dy / (1.0 - np.cos(phi))
    with np.errstate(over="ignore"):
        T = float(phi * np.sqrt(R / g))
    if not np.isfinite(T):
        raise InputError(f"g = {g:g} m/s^2 makes the descent time overflow for R = {R:g} m; "
                         "allowed: g with a finite time phi*sqrt(R/g)")
    return T


# ------------------------------------------------------------------------- rigid body
def _rb_f(x, u, t):
    q1, q2, q3, q4, w1, w2, w3 = (x[i] for i in range(7))
    return [
        0.5 * (w1 * q4 - w2 * q3 + w3 * q2),
        0.5 * (w1 * q3 + w2 * q4 - w3 * q1),
        0.5 * (-w1 * q2 + w2 * q1 + w3 * q4),
        0.5 * (-w1 * q1 - w2 * q2 - w3 * q3),
        u[0],
        u[1],
        u[2],
    ]


def rigid_body_reorientation(angle_deg: float = 180.0, tf_guess: float | None = None) -> OptimalControlProblem:
    """Minimum-time rest-to-rest reorientation of a spherical rigid body (unit inertia,
    ``|u_i| <= 1``) by ``angle_deg`` about the body z axis (Bilimoria & Wie 1993).

    States: quaternion ``(q1, q2, q3, q4)`` (scalar last) and body rates ``ω`` (rad/s, with
    the inertia and torque normalised to 1); controls: torques ``u`` (normalised).

    Examples
    --------
    >>> from adcskit.optimal_control.problems.standard import rigid_body_reorientation
    >>> rigid_body_reorientation(180.0).final_state[:4].round(12).tolist()
    [0.0, 0.0, 1.0, 0.0]
    """
    ang = np.deg2rad(check_range("angle_deg", angle_deg, 1e-3, 180.0))
    t_eig = 2.0 * np.sqrt(ang)  # eigenaxis bang-bang with |u| <= 1
    return OptimalControlProblem(
        name="rigid-body-reorientation",
        dynamics=_rb_f,
        n_states=7,
        n_controls=3,
        state_names=("q1", "q2", "q3", "q4", "w1", "w2", "w3"),
        control_names=("u1", "u2", "u3"),
        state_lower=[-1.0] * 4 + [-np.inf] * 3,
        state_upper=[1.0] * 4 + [np.inf] * 3,
        control_lower=[-1.0] * 3,
        control_upper=[1.0] * 3,
        initial_state=[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
        final_state=[0.0, 0.0, np.sin(ang / 2), np.cos(ang / 2), 0.0, 0.0, 0.0],
        tf_bounds=(0.3 * t_eig, 3.0 * t_eig),
        tf_guess=t_eig if tf_guess is None else tf_guess,
        mayer=_br_mayer,
        state_scale=[1.0] * 4 + [1.0] * 3,
        control_scale=[1.0] * 3,
    )


# ------------------------------------------------------------------------- Goddard rocket
# Bryson (1999) §9.3 / GPOPS-II example, English units: ft, s, slug, lbf.
_GD = {
    "T_max": 193.044,  # lbf
    "g": 32.174,  # ft/s^2
    "sigma": 5.4915e-5,  # slug/ft (drag coefficient D = sigma v^2 exp(-h/h0))
    "c": 1580.9425,  # ft/s (exhaust velocity)
    "h0": 23800.0,  # ft (density scale height)
    "m0": 3.0,  # slug
    "mf": 1.0,  # slug
}


def _gd_drag(h, v):
    return _GD["sigma"] * v * v * ca.exp(-h / _GD["h0"])


def _gd_f(x, u, t, p):
    h, v, m = x[0], x[1], x[2]
    T = u[0]
    return [v, (T - _gd_drag(h, v)) / m - _GD["g"], -T / _GD["c"]]


def _gd_singular(x, u, t, p):
    """Singular-arc feedback thrust minus the thrust (zero on the singular arc; Bryson 1999,
    eq. 9.3.15 with a quadratic drag ``D = σ v² e^{−h/h0}``)."""
    h, v, m = x[0], x[1], x[2]
    g, c, h0 = _GD["g"], _GD["c"], _GD["h0"]
    D = _gd_drag(h, v)
    term = m * g / (1.0 + 4.0 * c / v + 2.0 * c * c / (v * v)) * (
        c * c / (h0 * g) * (1.0 + v / c) - 1.0 - 2.0 * c / v
    )
    return [u[0] - (D + m * g + term)]


def _gd_events(ends, p):
    # on entry to the singular arc the switching function vanishes: m g = (1 + v/c) D
    x = ends[1].x0
    h, v, m = x[0], x[1], x[2]
    return [m * _GD["g"] - (1.0 + v / _GD["c"]) * _gd_drag(h, v)]


def _gd_objective(ends, p):
    return -ends[2].xf[0]


def goddard_rocket() -> MultiPhaseProblem:
    """The Goddard rocket's maximum final altitude as three phases: full thrust, singular
    arc (thrust from the singular feedback law, a path constraint; its entry fixed by the
    event ``m g = (1 + v/c) D``), coast with zero thrust to ``v = 0``.

    Examples
    --------
    >>> from adcskit.optimal_control.problems.standard import goddard_rocket
    >>> [ph.name for ph in goddard_rocket().phases]
    ['full-thrust', 'singular', 'coast']
    """
    T = _GD["T_max"]
    common = dict(
        dynamics=_gd_f,
        n_states=3,
        n_controls=1,
        state_names=("h", "v", "m"),
        control_names=("T",),
        state_lower=[0.0, 0.0, _GD["mf"]],
        state_upper=[30000.0, 2000.0, _GD["m0"]],
        state_scale=[10000.0, 1000.0, 3.0],
        control_scale=[T],
    )
    p1 = Phase(
        name="full-thrust",
        control_lower=[T],
        control_upper=[T],
        initial_state=[0.0, 0.0, _GD["m0"]],
        t0_bounds=(0.0, 0.0),
        tf_bounds=(0.0, 100.0),
        tf_guess=10.0,
        **common,
    )
    p2 = Phase(
        name="singular",
        control_lower=[0.0],
        control_upper=[T],
        t0_bounds=(0.0, 100.0),
        tf_bounds=(0.0, 100.0),
        t0_guess=10.0,
        tf_guess=30.0,
        path=_gd_singular,
        path_lower=[0.0],
        path_upper=[0.0],
        **common,
    )
    p3 = Phase(
        name="coast",
        control_lower=[0.0],
        control_upper=[0.0],
        final_state=[np.nan, 0.0, np.nan],
        t0_bounds=(0.0, 100.0),
        tf_bounds=(0.0, 100.0),
        t0_guess=30.0,
        tf_guess=45.0,
        **common,
    )
    return MultiPhaseProblem(
        name="goddard-rocket",
        phases=[p1, p2, p3],
        objective=_gd_objective,
        events=_gd_events,
        event_lower=[0.0],
        event_upper=[0.0],
    )


# ------------------------------------------------------------------------- free-flying robot
_FFR = {"alpha": 0.2, "beta": 0.2}


def _ffr_f(x, u, t):
    T1 = u[0] - u[1]
    T2 = u[2] - u[3]
    return [
        x[3],
        x[4],
        x[5],
        (T1 + T2) * ca.cos(x[2]),
        (T1 + T2) * ca.sin(x[2]),
        _FFR["alpha"] * T1 - _FFR["beta"] * T2,
    ]


def _ffr_g(x, u, t):
    return u[0] + u[1] + u[2] + u[3]


def _ffr_path(x, u, t):
    return [u[0] + u[1], u[2] + u[3]]


def free_flying_robot() -> OptimalControlProblem:
    """Sakawa's free-flying robot: minimum fuel ``∫ (u1 + u2 + u3 + u4) dt`` over ``tf = 12`` s.

    States ``(x, y, θ, vx, vy, ω)`` from ``(−10, −10, π/2, 0, 0, 0)`` to rest at the origin;
    thrusts ``T1 = u1 − u2``, ``T2 = u3 − u4`` with ``u_i >= 0`` and ``u1 + u2 <= 1``,
    ``u3 + u4 <= 1`` (path constraints); ``v̇ = (T1 + T2)(cos θ, sin θ)``,
    ``ω̇ = α T1 − β T2``, ``α = β = 0.2`` (normalised units). The optimal thrusts are
    bang-bang (GPOPS-II: ``J* = 7.9101471``).

    References
    ----------
    Sakawa, Optim. Control Appl. Meth. 20(5), 1999. Betts 2010, ex. 6.13. Patterson & Rao,
    ACM TOMS 41(1), 2014, §7.4.

    Examples
    --------
    >>> from adcskit.optimal_control.problems.standard import free_flying_robot
    >>> p = free_flying_robot()
    >>> p.n_states, p.n_controls, p.n_path, p.tf_bounds
    (6, 4, 2, (12.0, 12.0))
    """
    return OptimalControlProblem(
        name="free-flying-robot",
        dynamics=_ffr_f,
        n_states=6,
        n_controls=4,
        state_names=("x", "y", "theta", "vx", "vy", "omega"),
        control_names=("u1", "u2", "u3", "u4"),
        state_lower=[-10.0, -10.0, -np.pi, -2.0, -2.0, -1.0],
        state_upper=[10.0, 10.0, np.pi, 2.0, 2.0, 1.0],
        control_lower=[0.0] * 4,
        control_upper=[1.0] * 4,
        initial_state=[-10.0, -10.0, np.pi / 2, 0.0, 0.0, 0.0],
        final_state=[0.0] * 6,
        tf_bounds=(12.0, 12.0),
        lagrange=_ffr_g,
        path=_ffr_path,
        path_lower=[-np.inf, -np.inf],
        path_upper=[1.0, 1.0],
        state_scale=[10.0, 10.0, 1.0, 1.0, 1.0, 1.0],
        control_scale=[1.0] * 4,
    )


# ------------------------------------------------------------------------- oscillator
def _osc_f(x, u, t):
    return [x[1], -x[0] + u[0]]


def oscillator_min_time(x0: float = 7.0, v0: float = 0.5) -> OptimalControlProblem:
    """Minimum time to bring ``ẍ = −x + u``, ``|u| <= 1`` from ``(x0, v0)`` to rest at 0.

    The optimal control is ``u = −sign(λ_v)`` with ``λ_v = A sin(t + φ)``: bang-bang with
    switches exactly π s apart (Pontryagin et al. 1962, §I.5). From the default start
    ``(7, 0.5)`` it switches four times (:func:`oscillator_min_time_reference`).

    Examples
    --------
    >>> from adcskit.optimal_control.problems.standard import oscillator_min_time
    >>> oscillator_min_time().initial_state.tolist()
    [7.0, 0.5]
    """
    x0 = check_finite("x0", x0)
    v0 = check_finite("v0", v0)
    r = float(np.hypot(x0, v0))
    if r == 0.0:
        raise InputError("the start (x0, v0) must differ from the origin; got (0, 0)")
    if r > 200.0:
        raise InputError(f"hypot(x0, v0) must be <= 200 (about 100 switches); got {r:g}")
    t_guess = np.pi * (r / 2.0 + 1.0)
    return OptimalControlProblem(
        name="oscillator-min-time",
        dynamics=_osc_f,
        n_states=2,
        n_controls=1,
        state_names=("x", "v"),
        control_names=("u",),
        control_lower=[-1.0],
        control_upper=[1.0],
        initial_state=[x0, v0],
        final_state=[0.0, 0.0],
        tf_bounds=(0.1, 4.0 * t_guess),
        tf_guess=t_guess,
        mayer=_br_mayer,
        state_scale=[max(r, 1.0), max(r, 1.0)],
        control_scale=[1.0],
    )


#: Largest start radius |(x0, v0)| the shooting oracle takes (about 50 switches, ~1 s).
_OSC_MAX_RADIUS = 100.0
_OSC_GRID = 200


def oscillator_min_time_reference(x0: float = 7.0, v0: float = 0.5) -> tuple[float, np.ndarray]:
    """Optimal ``tf`` (s) and switch times (s) of :func:`oscillator_min_time`, by shooting
    on the minimum principle's structure.

    On a bang arc with ``u = s = ±1`` the state turns clockwise about ``(s, 0)`` at unit rate;
    switches are π s apart. The unknowns are the first switch time ``t1 ∈ (0, π]`` and the
    final arc's length ``τ ∈ (0, π]`` with the number of full arcs ``k`` and the first sign;
    the candidate reaching the origin (``brentq`` on the final-arc condition) with the least
    time is returned. Independent of the collocation code: an oracle for the tests.

    Examples
    --------
    >>> from adcskit.optimal_control.problems.standard import oscillator_min_time_reference
    >>> tf, sw = oscillator_min_time_reference(7.0, 0.5)
    >>> sw.size, round(tf, 6)
    (4, 11.136045)
    """
    x0 = check_finite("x0", x0)
    v0 = check_finite("v0", v0)
    z0 = complex(x0, v0)
    if abs(z0) > _OSC_MAX_RADIUS:
        # the optimum has about |z0|/2 switches and the search is quadratic in their number
        raise InputError(
            f"x0, v0 = {x0!r}, {v0!r}: the start must lie within {_OSC_MAX_RADIUS:g} of the origin "
            f"(|(x0, v0)| = {abs(z0):.6g}); the optimum would need about {abs(z0) / 2:.3g} switches"
        )

    def flow(z: complex, s: float, dt: float) -> complex:
        # rotation of (x - s, v) by -dt (clockwise) about (s, 0)
        return s + (z - s) * np.exp(-1j * dt)

    best = (np.inf, np.array([]))
    # each π-long arc moves the state's distance from the origin by at most 2
    k_max = int(np.ceil(abs(z0) / 2.0)) + 3
    # ... so k + 2 arcs must cover the distance |z0|: k >= |z0|/2 - 2
    k_min = max(0, int(np.floor(abs(z0) / 2.0)) - 3)
    # the end point sweeps about |z0| * dt as t1 moves by dt: resolve the crossings on a grid
    # that grows with |z0| (200 points missed them beyond |z0| ~ 20 and returned inf)
    n_grid = max(_OSC_GRID, int(40 * abs(z0)))
    for s0 in (1.0, -1.0):
        for k in range(k_min, k_max):

            def end(t1: float, s0: float = s0, k: int = k) -> complex:
                z, s = flow(z0, s0, t1), s0
                for _ in range(k):
                    s = -s
                    z = flow(z, s, np.pi)
                return z, -s

            def miss(t1: float) -> float:
                z, s = end(t1)
                # the last arc (sign s) must pass through the origin: |z − s| = |0 − s| = 1
                return abs(z - s) - 1.0

            grid = np.linspace(1e-9, np.pi, n_grid)
            vals = np.array([miss(t) for t in grid])
            for a, b, fa, fb in zip(grid[:-1], grid[1:], vals[:-1], vals[1:], strict=True):
                if fa == 0.0 or fa * fb < 0.0:
                    t1 = a if fa == 0.0 else brentq(miss, a, b, xtol=1e-15)
                    z, s = end(t1)
                    # clockwise angle from (z − s) to (0 − s) about (s, 0)
                    ang = (np.angle(z - s) - np.angle(-s + 0j)) % (2 * np.pi)
                    if ang > np.pi + 1e-9:
                        continue
                    tf = t1 + k * np.pi + ang
                    if tf < best[0]:
                        best = (float(tf), t1 + np.pi * np.arange(k + 1))
            if best[0] < k * np.pi:
                break
    if not np.isfinite(best[0]):
        raise SolverError(f"oscillator_min_time_reference({x0!r}, {v0!r}): the shooting search found no "
                               "bang-bang path to the origin")
    return best


# ------------------------------------------------------------------------- orbit raising
# Bryson & Ho (1975) §2.5, normalised units: μ = 1, r0 = 1, m0 = 1, thrust T = 0.1405,
# propellant rate |ṁ| = 0.0749, tf = 3.32 (about half an initial orbit period).
_OR = {"mu": 1.0, "T": 0.1405, "mdot": 0.0749, "tf": 3.32}


def _or_f(x, u, t, p):
    r, vr, vt = x[0], x[2], x[3]
    a = _OR["T"] / (1.0 - _OR["mdot"] * t)  # m(t) = m0 − |ṁ| t, m0 = 1
    return [
        vr,
        vt / r,
        vt * vt / r - _OR["mu"] / (r * r) + a * u[0],
        -vr * vt / r + a * u[1],
    ]


def _or_path(x, u, t, p):
    return [u[0] * u[0] + u[1] * u[1]]


def _or_objective(ends, p):
    return -ends[0].xf[0]


def _or_events(ends, p):
    # circular final orbit: v_t(tf)² r(tf) = μ (v_r(tf) = 0 is a fixed final state)
    xf = ends[0].xf
    return [xf[3] * xf[3] * xf[0] - _OR["mu"]]


def orbit_raising() -> MultiPhaseProblem:
    """Bryson & Ho's orbit raising: the largest circular orbit reachable in fixed time.

    One phase with states ``(r, θ, v_r, v_t)`` (radius, polar angle (rad), radial and
    tangential velocity) in normalised units (``μ = 1``, ``r0 = 1``, ``m0 = 1``); controls the
    thrust direction ``(w1, w2)`` (radial, tangential components) as a unit vector,
    ``w1² + w2² = 1`` enforced as a path constraint (the form issue 22 asks for, rather than
    a thrust angle). Constant thrust ``T = 0.1405``, mass ``m(t) = 1 − 0.0749 t``,
    ``tf = 3.32``; start on the circular orbit ``(1, 0, 0, 1)``; end on a circular orbit:
    ``v_r(tf) = 0`` (a final state) and ``v_t(tf)² r(tf) = μ`` (an event, as it is not a
    box bound). Maximising ``r(tf)`` is ``min −r(tf)``; Bryson & Ho print
    ``r(tf) = 1.525 r0`` (:func:`reference_objective`).

    A :class:`~adcskit.optimal_control.MultiPhaseProblem` (one phase) because the terminal
    circularity condition is nonlinear; solve it with
    :func:`~adcskit.optimal_control.solve_adaptive` or
    :func:`~adcskit.optimal_control.solve_multiphase`.

    References
    ----------
    Bryson & Ho, Applied Optimal Control, 1975, §2.5, Fig. 2.5.1.

    Examples
    --------
    >>> from adcskit.optimal_control.problems.standard import orbit_raising
    >>> p = orbit_raising()
    >>> ph = p.phases[0]
    >>> ph.n_states, ph.n_controls, ph.n_path, ph.tf_bounds, p.n_events
    (4, 2, 1, (3.32, 3.32), 1)
    """
    tf = _OR["tf"]
    phase = Phase(
        name="orbit-raising",
        dynamics=_or_f,
        n_states=4,
        n_controls=2,
        state_names=("r", "theta", "vr", "vt"),
        control_names=("w1", "w2"),
        state_lower=[0.5, 0.0, -1.0, 0.1],
        state_upper=[5.0, 4.0 * np.pi, 1.0, 2.0],
        control_lower=[-1.0, -1.0],
        control_upper=[1.0, 1.0],
        initial_state=[1.0, 0.0, 0.0, 1.0],
        final_state=[np.nan, np.nan, 0.0, np.nan],
        t0_bounds=(0.0, 0.0),
        tf_bounds=(tf, tf),
        path=_or_path,
        path_lower=[1.0],
        path_upper=[1.0],
        state_scale=[1.0, 1.0, 1.0, 1.0],
        control_scale=[1.0, 1.0],
    )
    return MultiPhaseProblem(
        name="orbit-raising",
        phases=[phase],
        objective=_or_objective,
        events=_or_events,
        event_lower=[0.0],
        event_upper=[0.0],
    )


# ------------------------------------------------------------------------- COPS robot arm
_ARM_L = 5.0  # arm length (COPS 3.0 §8)


def _arm_f(x, u, t):
    rho, phi = x[0], x[2]
    inertia_phi = ((_ARM_L - rho) ** 3 + rho**3) / 3.0
    inertia_theta = inertia_phi * ca.sin(phi) ** 2
    return [x[3], x[4], x[5], u[0] / _ARM_L, u[1] / inertia_theta, u[2] / inertia_phi]


def robot_arm() -> OptimalControlProblem:
    """COPS robot arm: minimum time to swing an arm of length ``L = 5`` between two rests.

    States ``(ρ, θ, φ, ρ̇, θ̇, φ̇)``: the arm's extension ρ (``0 <= ρ <= L``), azimuth θ
    (``|θ| <= π``) and elevation φ (``0 <= φ <= π``) with their rates; controls
    ``|u_i| <= 1``. Dynamics ``L ρ̈ = u_ρ``, ``I_θ θ̈ = u_θ``, ``I_φ φ̈ = u_φ`` with
    ``I_φ = ((L − ρ)³ + ρ³) / 3`` and ``I_θ = I_φ sin² φ``. From ``(4.5, 0, π/4)`` at rest to
    ``(4.5, 2π/3, π/4)`` at rest; minimise ``tf`` (COPS: ``tf* = 9.1409118``, bang-bang in
    every channel).

    References
    ----------
    Dolan, Moré & Munson, Benchmarking optimization software with COPS 3.0, ANL/MCS-TM-273,
    2004, §8 (robot arm; the model from Monta 1994).

    Examples
    --------
    >>> from adcskit.optimal_control.problems.standard import robot_arm
    >>> p = robot_arm()
    >>> p.n_states, p.n_controls, p.free_final_time
    (6, 3, True)
    """
    return OptimalControlProblem(
        name="robot-arm",
        dynamics=_arm_f,
        n_states=6,
        n_controls=3,
        state_names=("rho", "theta", "phi", "rho_dot", "theta_dot", "phi_dot"),
        control_names=("u_rho", "u_theta", "u_phi"),
        state_lower=[0.0, -np.pi, 0.0, -np.inf, -np.inf, -np.inf],
        state_upper=[_ARM_L, np.pi, np.pi, np.inf, np.inf, np.inf],
        control_lower=[-1.0] * 3,
        control_upper=[1.0] * 3,
        initial_state=[4.5, 0.0, np.pi / 4, 0.0, 0.0, 0.0],
        final_state=[4.5, 2.0 * np.pi / 3, np.pi / 4, 0.0, 0.0, 0.0],
        tf_bounds=(1.0, 30.0),
        tf_guess=10.0,
        mayer=_br_mayer,
        state_scale=[_ARM_L, 1.0, 1.0, 1.0, 1.0, 1.0],
        control_scale=[1.0] * 3,
    )


# ------------------------------------------------------------------------- references
def reference_objective(name: str) -> tuple[float, str]:
    """Published / closed-form optimum of a standard problem at its default settings.

    Returns
    -------
    value : float
    source : str

    Examples
    --------
    >>> reference_objective("bryson-denham")[0]
    4.0
    """
    refs = {
        # Tomlab PROPT example 51 (Rao & Mease's problem, tf = 10, J = ∫(x²+u²) = 6.723925391),
        # halved for the ½ of Rao & Mease's cost.
        "hypersensitive": (6.723925391388357 / 2.0, "Rao & Mease 2000 problem, tf = 10; Tomlab PROPT ex. 51: ∫(x²+u²) = 6.7239254, halved"),
        "bryson-denham": (4.0, "Bryson & Ho 1975 §3.11: J = 4/(9l), l = 1/9"),
        "brachistochrone": (brachistochrone_time(10.0, 5.0), "closed-form cycloid, (0,10) → (10,5) m"),
        "rigid-body-reorientation": (3.243, "Bilimoria & Wie 1993: 180° rest-to-rest, unit inertia and torque, tf = 3.243 (eigenaxis 2√π = 3.545)"),
        "goddard-rocket": (-18550.872, "GPOPS-II example / Bryson 1999 §9.3: h(tf) = 18550.872 ft"),
        "free-flying-robot": (7.9101471, "Patterson & Rao 2014 (GPOPS-II) §7.4 / Betts 2010 ex. 6.13: J* = 7.9101471"),
        "oscillator-min-time": (None, "minimum principle by shooting (oscillator_min_time_reference), start (7, 0.5)"),
        "orbit-raising": (-1.525, "Bryson & Ho 1975 §2.5, Fig. 2.5.1: r(tf) = 1.525 r0 (4 digits printed); objective −r(tf)"),
        "robot-arm": (9.1409118, "COPS 3.0 (Dolan, Moré & Munson 2004) §8 robot arm: tf* = 9.1409118"),
        "launch-ascent": (-7529.712680, "Patterson & Rao 2014 (GPOPS-II) §7.5: final mass 7529.712680 kg"),
    }
    if name not in refs:
        raise InputError(f"name must be one of {sorted(refs)}; got {name!r}")
    value, source = refs[name]
    if value is None:  # computed on demand (a shooting solve)
        value = oscillator_min_time_reference(7.0, 0.5)[0]
    return value, source
