"""Post-processing of an optimal-control solution: bang-bang structure and re-simulation.

* :func:`bang_bang` — fraction of collocation points at which each control sits on a bound,
  and switch times from the zero crossings of the switching function ``∂H/∂u`` (the
  costate-based switching function of the minimum principle; for a control-affine problem
  ``u_i = −u_max sign(∂H/∂u_i)`` on a bang arc).
* :func:`resimulate` — integrate the dynamics with the optimal open-loop controls by
  :func:`scipy.integrate.solve_ivp` (adaptive, interval by interval so that no step straddles
  a control discontinuity at a mesh point) and report the terminal-state miss.

References
----------
S2, §6 (bang-bang controls, Figs 3–4), eq. 35–36. Bilimoria & Wie, J. Guid. Control Dyn.
16(3), 1993 (time-optimal slews are bang-bang).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from adcskit._results import compact_repr
from adcskit._validation import check_choice, check_int, check_positive, check_range
from adcskit.errors import InputTypeError
from adcskit.optimal_control.solve import OptimalControlSolution

__all__ = ["BangBangResult", "ResimulationResult", "bang_bang", "resimulate"]


@compact_repr
@dataclass(frozen=True, slots=True, kw_only=True)
class BangBangResult:
    """Bang-bang structure of each control channel.

    Attributes
    ----------
    at_bound_fraction : (n_controls,) ndarray
        Fraction of collocation points within ``tol × (upper − lower)`` of a bound.
    is_bang_bang : (n_controls,) ndarray of bool
        ``at_bound_fraction >= min_fraction``.
    switch_times : tuple of ndarray
        Per channel, times (s) where the switching function changes sign (linear
        interpolation between collocation points) and the control flips between bounds.
    n_switches : (n_controls,) ndarray of int
    all_bang_bang : bool

    Examples
    --------
    >>> from adcskit.optimal_control import solve
    >>> from adcskit.optimal_control.problems import double_integrator_min_time
    >>> sol = solve(double_integrator_min_time(distance=1.0, accel_max=1.0), mesh=(4, 3))
    >>> from adcskit.optimal_control import bang_bang
    >>> bb = bang_bang(sol)
    >>> type(bb).__name__, bb.all_bang_bang, bb.n_switches
    ('BangBangResult', True, array([1]))
    """

    at_bound_fraction: np.ndarray
    is_bang_bang: np.ndarray
    switch_times: tuple[np.ndarray, ...]
    n_switches: np.ndarray
    all_bang_bang: bool

    def to_dict(self) -> dict[str, Any]:
        return {
            "at_bound_fraction": self.at_bound_fraction,
            "is_bang_bang": self.is_bang_bang,
            "switch_times": [list(s) for s in self.switch_times],
            "n_switches": self.n_switches,
            "all_bang_bang": self.all_bang_bang,
        }


def bang_bang(solution: OptimalControlSolution, *, tol: float = 0.02, min_fraction: float = 0.9) -> BangBangResult:
    """Detect bang-bang controls and their switch times.

    Parameters
    ----------
    solution : OptimalControlSolution
    tol : float
        A control is "on a bound" within ``tol`` of its bound range (default 2 %).
    min_fraction : float
        Fraction of collocation points that must be on a bound for a bang-bang channel.

    Examples
    --------
    >>> from adcskit.optimal_control import solve
    >>> from adcskit.optimal_control.problems import double_integrator_min_time
    >>> sol = solve(double_integrator_min_time(distance=1.0, accel_max=1.0), mesh=(4, 3))
    >>> from adcskit.optimal_control import bang_bang
    >>> round(sol.tf, 6)                                  # analytic 2 sqrt(d / a) = 2 s
    2.0
    >>> bb = bang_bang(sol)
    >>> bb.is_bang_bang, bb.n_switches, bb.switch_times[0].round(3)   # switch at tf / 2
    (array([ True]), array([1]), array([1.]))
    """
    if not isinstance(solution, OptimalControlSolution):
        raise InputTypeError(f"solution must be an OptimalControlSolution; got {type(solution).__name__}")
    tol = check_range("tol", tol, 0.0, 0.5)
    min_fraction = check_range("min_fraction", min_fraction, 0.0, 1.0)
    prob = solution.problem
    lo, hi = prob.control_lower, prob.control_upper
    span = np.where(np.isfinite(hi - lo), hi - lo, np.nan)
    u = solution.u
    on_lo = np.abs(u - lo) <= tol * span
    on_hi = np.abs(u - hi) <= tol * span
    frac = np.mean(on_lo | on_hi, axis=0)
    frac = np.where(np.isfinite(span), frac, 0.0)
    tc = solution.t_control
    sw = solution.switching
    switches = []
    for j in range(u.shape[1]):
        s = sw[:, j]
        side = np.where(on_hi[:, j], 1, np.where(on_lo[:, j], -1, 0))
        k_on = np.flatnonzero(side != 0)
        times = []
        for k1, k2 in zip(k_on[:-1], k_on[1:], strict=False):
            if side[k1] == side[k2]:
                continue
            t_sw = 0.5 * (tc[k1] + tc[k2])
            for k in range(k1, k2):  # zero of the switching function between the two bang nodes
                if s[k] * s[k + 1] < 0:
                    t_sw = tc[k] - s[k] * (tc[k + 1] - tc[k]) / (s[k + 1] - s[k])
                    break
            times.append(t_sw)
        switches.append(np.array(times))
    is_bb = frac >= min_fraction
    return BangBangResult(
        at_bound_fraction=frac,
        is_bang_bang=is_bb,
        switch_times=tuple(switches),
        n_switches=np.array([len(s) for s in switches], dtype=int),
        all_bang_bang=bool(np.all(is_bb)),
    )


@compact_repr
@dataclass(frozen=True, slots=True, kw_only=True)
class ResimulationResult:
    """Open-loop re-simulation of an optimal control history.

    Attributes
    ----------
    success : bool
    message : str
    t : (M,) ndarray
        Output times (s).
    x : (M, n_states) ndarray
        Integrated states.
    terminal_miss : (n_states,) ndarray
        Integrated final state minus the NLP's final state.
    terminal_miss_scaled : float
        ``max_i |miss_i| / scale_i`` with the problem's state scales.
    nfev : int

    Examples
    --------
    >>> from adcskit.optimal_control import solve
    >>> from adcskit.optimal_control.problems import double_integrator_min_energy
    >>> sol = solve(double_integrator_min_energy(distance=1.0, duration=1.0), mesh=(4, 3))
    >>> from adcskit.optimal_control import resimulate
    >>> rs = resimulate(sol)
    >>> type(rs).__name__, rs.success, bool(rs.terminal_miss_scaled < 1e-6)
    ('ResimulationResult', True, True)
    """

    success: bool
    message: str
    t: np.ndarray
    x: np.ndarray
    terminal_miss: np.ndarray
    terminal_miss_scaled: float
    nfev: int

    def to_dict(self) -> dict[str, Any]:
        return {
            "success": self.success,
            "message": self.message,
            "terminal_miss": self.terminal_miss,
            "terminal_miss_scaled": self.terminal_miss_scaled,
            "nfev": self.nfev,
        }


def resimulate(
    solution: OptimalControlSolution,
    *,
    control: str = "lagrange",
    method: str = "DOP853",
    rtol: float = 1e-10,
    atol: float = 1e-12,
    points_per_interval: int = 10,
) -> ResimulationResult:
    """Integrate ``ẋ = f(x, u(t), t)`` from the NLP's initial state with its controls.

    Parameters
    ----------
    control : {"lagrange", "nearest", "switching"}
        Control reconstruction inside each mesh interval: ``"lagrange"``/``"nearest"`` (see
        :meth:`OptimalControlSolution.control_at`), or ``"switching"`` — on the channels that
        :func:`bang_bang` finds bang-bang, the minimum-principle law ``u = lower if ∂H/∂u > 0
        else upper`` with ``∂H/∂u`` linearly interpolated between collocation points (switch
        times between nodes are then resolved), elsewhere Lagrange. Measured on the S2
        rendezvous (40×4): the law agrees with the NLP controls at 99 % of the nodes, but its
        terminal miss is ~8× that of ``"lagrange"`` (0.115 vs 0.014 state scales) because
        the interpolated costates place the switches less accurately than the NLP's own
        control polynomials; ``"lagrange"`` is the default.
    method : str
        :func:`scipy.integrate.solve_ivp` method.
    rtol, atol : float
        Integrator tolerances.

    Examples
    --------
    >>> from adcskit.optimal_control import solve
    >>> from adcskit.optimal_control.problems import double_integrator_min_time
    >>> sol = solve(double_integrator_min_time(distance=1.0, accel_max=1.0), mesh=(4, 3))
    >>> from adcskit.optimal_control import resimulate
    >>> rs = resimulate(sol)                    # integrate the NLP's controls (DOP853)
    >>> rs.success, rs.x.shape[1], rs.terminal_miss.shape
    (True, 2, (2,))
    >>> bool(rs.terminal_miss_scaled < 0.05)
    True
    """
    if not isinstance(solution, OptimalControlSolution):
        raise InputTypeError(f"solution must be an OptimalControlSolution; got {type(solution).__name__}")
    check_choice("control", control, ("lagrange", "nearest", "switching"))
    rtol = check_positive("rtol", rtol)
    atol = check_positive("atol", atol)
    points_per_interval = check_int("points_per_interval", points_per_interval, minimum=1, maximum=100_000)
    prob = solution.problem
    f = solution.dynamics_fun
    if control == "switching":
        bb = bang_bang(solution).is_bang_bang
        lo, hi = prob.control_lower, prob.control_upper
        tc, sw = solution.t_control, solution.switching

        def ufun(t):
            u = solution.control_at(t, kind="lagrange")
            for j in np.flatnonzero(bb):
                u[j] = lo[j] if np.interp(t, tc, sw[:, j]) > 0 else hi[j]
            return u
    else:

        def ufun(t):
            return solution.control_at(t, kind=control)
    x = solution.x[0].copy()
    ts, xs = [np.array([solution.t0])], [x[None, :]]
    nfev = 0
    ok, msg = True, "integrated to tf"
    t_start = solution.t0
    for p in solution.pieces:
        t_end = p.t_end

        def rhs(t, y):
            return np.asarray(f(y, ufun(t), t)).ravel()

        t_eval = np.linspace(t_start, t_end, points_per_interval + 1)[1:]
        sol = solve_ivp(rhs, (t_start, t_end), x, method=method, rtol=rtol, atol=atol, t_eval=t_eval)
        nfev += sol.nfev
        if not sol.success:
            ok, msg = False, f"solve_ivp failed at t={t_start:.4g} s: {sol.message}"
            break
        ts.append(sol.t)
        xs.append(sol.y.T)
        x = sol.y[:, -1]
        t_start = t_end
    t = np.concatenate(ts)
    xx = np.vstack(xs)
    miss = xx[-1] - solution.x[-1]
    sx, _ = prob.scales()
    return ResimulationResult(
        success=ok,
        message=msg,
        t=t,
        x=xx,
        terminal_miss=miss,
        terminal_miss_scaled=float(np.max(np.abs(miss) / sx)),
        nfev=int(nfev),
    )
