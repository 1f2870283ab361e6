"""Error-controlled hp mesh refinement for the Gauss and Radau transcriptions.

:func:`estimate_error` measures, in every mesh interval, the relative error of the state:
the collocation polynomial ``X(τ)`` is compared with an integration of the dynamics under
the interpolated control on a finer set of ``N + extra`` Legendre–Gauss–Radau points
(Patterson, Hager & Rao 2015, eq. 26–29)::

    X̂(s_j) = X(s_1) + (h/2) Σ_l I_jl f(X(s_l), U(s_l), t_l),
    e_i    = max_j |X̂_i(s_j) − X_i(s_j)| / (1 + max_j |X_i(s_j)|),

with ``I`` the LGR integration matrix of the finer points and ``U`` the Lagrange
interpolant of the collocation controls (clipped to the bounds). State bounds hold only at
the support points; a violation ``max(X − x_max, x_min − X, 0) / (1 + max|X|)`` at the finer
points counts as error too (it is what limits the objective's accuracy on state-constrained
arcs such as Bryson–Denham's). The interval's error is the largest over the states.

:func:`solve_adaptive` solves, estimates, and refines each interval whose error exceeds
``tol`` until every interval meets it:

* **p** (degree increase) where the state is smooth: the new number of collocation points is
  ``N + P`` with ``P = ⌈log(e / tol) / log N⌉`` (Patterson, Hager & Rao 2015, eq. 31), as long
  as it stays ``<= n_max``;
* **h** (split) otherwise: an interval whose control jumps between collocation points (a
  bang-bang switch, a constraint corner: Liu, Hager & Rao 2015 bracket such
  nonsmoothness) is split at the jump; an interval whose Legendre coefficients of the state
  do not decay (Liu, Hager & Rao 2018), or whose required degree exceeds ``n_max``, is split
  into ``B = max(2, ⌈(N + P) / n_min⌉)`` equal sub-intervals of ``n_min`` points
  (Patterson, Hager & Rao 2015, eq. 32).

* **reduction** (``mesh_reduction``, default on) where the error is below ``tol / 10``: the
  degree is lowered, and adjacent such intervals are merged, as far as a coarser polynomial
  still represents the current solution to ``tol / 10`` (the idea of Liu, Hager & Rao 2015
  §4; the representability criterion is this package's; see :func:`refine_mesh`).

Each refinement is warm-started from the previous solution, primal and dual: the
multipliers are interpolated onto the new mesh (:func:`solve`'s ``transfer_duals``).
Multi-phase problems (:class:`MultiPhaseProblem`) are refined phase by phase with the same
rules.

References
----------
Patterson, Hager & Rao, "A ph mesh refinement method for optimal control", Optim. Control
Appl. Meth. 36(4), 2015. Liu, Hager & Rao, "Adaptive mesh refinement method for optimal
control using nonsmoothness detection and mesh size reduction", J. Franklin Inst. 352(10),
2015. Liu, Hager & Rao, "An hp mesh refinement method for optimal control", Optim. Control
Appl. Meth. 39(4), 2018. Garg et al., Automatica 46(11), 2010 (LGR integration matrix).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, fields
from typing import Any

import casadi as ca
import numpy as np
from numpy.polynomial import legendre as _leg

from adcskit._results import Result, compact_repr
from adcskit._validation import (
    as_array,
    check_choice,
    check_finite,
    check_flag,
    check_int,
    check_positive,
    check_range,
)
from adcskit.errors import InputError, InputTypeError
from adcskit.optimal_control.nodes import lagrange_matrix, legendre_gauss_radau
from adcskit.optimal_control.problem import Guess, Mesh, OptimalControlProblem
from adcskit.optimal_control.solve import OptimalControlSolution, solve
from adcskit.optimal_control.transcription import METHODS

__all__ = [
    "AdaptiveSolution",
    "ErrorCertificate",
    "MeshIteration",
    "default_optimality_threshold",
    "estimate_error",
    "refine_mesh",
    "solve_adaptive",
    "symmetry_breaking_guess",
    "guess_from_function",
]


# ----------------------------------------------------------------------------- estimate
_INT_CACHE: dict[int, tuple[np.ndarray, np.ndarray]] = {}


def _lgr_integration(m: int) -> tuple[np.ndarray, np.ndarray]:
    """LGR points ``s`` (m) and the matrix ``I`` (m × m) with ``I[j, l] = ∫_{-1}^{e_j} L_l``,
    ``e = (s_2, …, s_m, +1)`` (Garg et al. 2010, integral form of the Radau method)."""
    hit = _INT_CACHE.get(m)
    if hit is not None:
        return hit
    s, _ = legendre_gauss_radau(m)
    V = _leg.legvander(s, m - 1)  # V[j, k] = P_k(s_j)
    C = np.linalg.inv(V)  # column l: Legendre coefficients of L_l
    ends = np.concatenate((s[1:], [1.0]))
    Cint = _leg.legint(C, lbnd=-1.0, axis=0)
    I = _leg.legvander(ends, m) @ Cint
    _INT_CACHE[m] = (s, I)
    return s, I


def _interval_error(piece, f_map, lo, hi, s_lo, s_hi, extra: int) -> tuple[float, np.ndarray]:
    """Relative state error of one interval and the per-state errors."""
    t_a, t_b = float(piece.ts[0]), float(piece.t_end)
    h = t_b - t_a
    n = piece.uc.shape[0]
    m = n + extra
    s, I = _lgr_integration(m)
    tau_sup = 2.0 * (piece.ts - t_a) / h - 1.0
    tau_c = 2.0 * (piece.tc - t_a) / h - 1.0
    pts = np.concatenate((s, [1.0]))
    X = lagrange_matrix(tau_sup, pts) @ piece.xs  # (m+1, nx)
    if piece.uc.shape[1]:
        U = np.clip(lagrange_matrix(tau_c, s) @ piece.uc, lo, hi)
    else:
        U = np.zeros((m, 0))
    tt = t_a + (s + 1.0) / 2.0 * h
    F = np.asarray(f_map(m)(X[:m].T, U.T, tt[None, :])).T  # (m, nx)
    Xhat = X[0] + h / 2.0 * (I @ F)
    denom = 1.0 + np.max(np.abs(X), axis=0)
    e_state = np.max(np.abs(Xhat - X[1:]), axis=0) / denom
    # state bounds are enforced only at the support points: count a violation between them
    viol = np.maximum(np.max(X - s_hi, axis=0), np.max(s_lo - X, axis=0))
    e_state = np.maximum(e_state, np.maximum(viol, 0.0) / denom)
    if not np.all(np.isfinite(e_state)):
        e_state = np.full_like(e_state, np.inf)
    return float(np.max(e_state)), e_state


def estimate_error(solution: OptimalControlSolution, *, extra_points: int = 1) -> np.ndarray:
    """Relative state error of every mesh interval of a solution.

    Parameters
    ----------
    solution : OptimalControlSolution
        A Gauss or Radau solution (of :func:`solve` or one phase of :func:`solve_multiphase`).
    extra_points : int
        The dynamics are integrated on ``N + extra_points`` LGR points per interval
        (``N``: the interval's collocation points); Patterson, Hager & Rao use 1.

    Returns
    -------
    (n_intervals,) ndarray
        ``max_i max_j |X̂_i − X_i| / (1 + max_j |X_i|)`` per interval (dimensionless),
        or the relative state-bound violation between the support points when larger.

    References
    ----------
    Patterson, Hager & Rao, Optim. Control Appl. Meth. 36(4), 2015, eq. 26–29.

    Examples
    --------
    >>> from adcskit.optimal_control import solve, estimate_error
    >>> from adcskit.optimal_control.problems import double_integrator_min_energy
    >>> sol = solve(double_integrator_min_energy(), method="radau", mesh=(2, 3))
    >>> bool(estimate_error(sol).max() < 1e-10)  # cubic state: exact on any mesh
    True
    """
    if not isinstance(solution, OptimalControlSolution):
        raise InputTypeError(f"solution must be an OptimalControlSolution; got {type(solution).__name__}")
    extra = check_int("extra_points", extra_points, minimum=1, maximum=10)
    f_map = _mapper(solution.dynamics_fun)
    pr = solution.problem
    lo, hi = pr.control_lower, pr.control_upper
    return np.array(
        [_interval_error(p, f_map, lo, hi, pr.state_lower, pr.state_upper, extra)[0] for p in solution.pieces]
    )


def _mapper(f: ca.Function):
    cache: dict[int, ca.Function] = {}

    def get(m: int) -> ca.Function:
        if m not in cache:
            cache[m] = f.map(m)
        return cache[m]

    return get


# ----------------------------------------------------------------------------- refine
def _legendre_decay(piece) -> float:
    """Exponential decay rate σ of the Legendre coefficients of the state polynomial,
    ``|a_k| ≈ c e^{−σ k}`` fitted over ``k >= 1`` (the smallest over the states; +inf when
    every state is a constant or a line)."""
    t_a, t_b = float(piece.ts[0]), float(piece.t_end)
    tau = 2.0 * (piece.ts - t_a) / (t_b - t_a) - 1.0
    n = tau.size - 1
    if n < 2:
        return np.inf
    a = np.abs(_leg.legfit(tau, piece.xs, n))  # (n+1, nx)
    sig = np.inf
    for i in range(a.shape[1]):
        ai = a[1:, i]
        floor = 1e-13 * (np.max(np.abs(piece.xs[:, i])) + 1e-300)
        ok = ai > floor
        if ok.sum() < 2 or np.max(ai[1:]) <= floor:
            continue  # (nearly) linear state in this interval
        k = np.arange(1, n + 1)[ok]
        slope = np.polyfit(k, np.log(ai[ok]), 1)[0]
        sig = min(sig, -slope)
    return float(sig)


def _control_jump(piece, lo, hi, threshold: float, *, junctions: bool = True) -> float | None:
    """Fraction of the interval (0..1) where a control jumps, or None.

    A jump is a change between consecutive collocation points larger than ``threshold``
    times the channel's range (its bound span where finite, else its range over the interval),
    a bang-bang switch or a constraint corner; or a bang-bang switch beside a mesh point,
    shown only by an edge collocation value off the bound all the others lie on
    (:func:`_edge_switch`; the jump between points there can be below ``threshold``).
    """
    uc = piece.uc
    if uc.shape[0] < 2 or uc.shape[1] == 0:
        return None
    span = np.where(np.isfinite(hi - lo), hi - lo, np.ptp(uc, axis=0))
    span = np.where(span > 0, span, np.inf)
    d = np.abs(np.diff(uc, axis=0)) / span  # (n-1, nu)
    k, j = np.unravel_index(np.argmax(d), d.shape)
    t_a, t_b = float(piece.ts[0]), float(piece.t_end)
    edge = False
    if d[k, j] < threshold:
        j = _edge_switch(uc, lo, hi)
        if j is None:
            jn = _bound_junction(uc, lo, hi) if junctions else None
            if jn is None:
                return None
            # a bound <-> interior junction (e.g. bang -> singular, -1 -> 0: half the range,
            # smeared below ``threshold``): break mid-way between the two points
            j, k = jn
            tm = 0.5 * (piece.tc[k] + piece.tc[k + 1])
            return float((tm - t_a) / (t_b - t_a))
        edge = True
        k = 0 if d[0, j] >= d[-1, j] else d.shape[0] - 1
    tm = 0.5 * (piece.tc[k] + piece.tc[k + 1])
    frac = (tm - t_a) / (t_b - t_a)
    lo_j, hi_j = lo[j], hi[j]
    if np.isfinite(hi_j - lo_j) and hi_j > lo_j:
        # a bang-bang switch (first and last collocation values on opposite bounds, or, for a
        # switch beside a mesh point, all values but the first or last on one bound): place
        # the break where a single switch gives the same quadrature-weighted mean control as
        # the collocation solution, ``∫ u dt`` (exact for a control entering linearly)
        a, b = uc[0, j], uc[-1, j]
        tol_b = 0.05 * (hi_j - lo_j)
        if edge:
            # the value off the bound belongs to the opposite bound's side of the switch
            first_hi = bool(
                np.all(np.abs(uc[:-1, j] - hi_j) <= tol_b) or np.all(np.abs(uc[1:, j] - lo_j) <= tol_b)
            )
            first_lo = not first_hi
        else:
            first_hi = abs(a - hi_j) <= tol_b and abs(b - lo_j) <= tol_b
            first_lo = abs(a - lo_j) <= tol_b and abs(b - hi_j) <= tol_b
        if first_hi or first_lo:
            tau_c = 2.0 * (piece.tc - t_a) / (t_b - t_a) - 1.0
            w = _quadrature_weights(tau_c)
            mean = float(w @ uc[:, j]) / 2.0
            on_hi = (mean - lo_j) / (hi_j - lo_j)  # fraction of the interval on the upper bound
            f_sw = on_hi if first_hi else 1.0 - on_hi
            if 0.0 < f_sw < 1.0:
                frac = f_sw
    return float(frac)


def _bound_junction(uc: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple[int, int] | None:
    """``(channel, k)`` of a junction between a control on a finite bound (within 0.1 % of
    the span) at collocation point ``k`` or ``k + 1`` and one strictly inside (more than 2 %
    of the span from both bounds) at the other (the largest change), or None."""
    best, arg = 0.0, None
    for j in range(uc.shape[1]):
        lo_j, hi_j = lo[j], hi[j]
        if not (np.isfinite(hi_j - lo_j) and hi_j > lo_j):
            continue
        span = hi_j - lo_j
        col = uc[:, j]
        near_lo, near_hi = np.abs(col - lo_j) <= 0.05 * span, np.abs(col - hi_j) <= 0.05 * span
        if np.any(near_lo) and np.any(near_hi):
            continue  # both bounds: a (smeared) bang-bang switch, placed by _control_jump's rule
        on = (np.abs(col - lo_j) <= 1e-3 * span) | (np.abs(col - hi_j) <= 1e-3 * span)
        inner = (col - lo_j > 0.02 * span) & (hi_j - col > 0.02 * span)
        for k in range(col.size - 1):
            if (on[k] and inner[k + 1]) or (inner[k] and on[k + 1]):
                dk = abs(col[k + 1] - col[k]) / span
                if dk > best:
                    best, arg = dk, (j, k)
    return arg


def _edge_switch(uc: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> int | None:
    """The control channel (or None) whose collocation values all lie on one bound but for
    the first or the last, which is off that bound: a bang-bang switch so close to a mesh
    point that only the edge collocation value shows it (the largest such edge offset)."""
    best, arg = 0.0, None
    if uc.shape[0] < 2:
        return None
    for j in range(uc.shape[1]):
        lo_j, hi_j = lo[j], hi[j]
        if not (np.isfinite(hi_j - lo_j) and hi_j > lo_j):
            continue
        span = hi_j - lo_j
        tol_b = 0.05 * span
        col = uc[:, j]
        for bound in (lo_j, hi_j):
            for rest, edge_v in ((col[:-1], col[-1]), (col[1:], col[0])):
                off = abs(edge_v - bound) / span
                if off > 0.05 and off > best and np.all(np.abs(rest - bound) <= tol_b):
                    best, arg = off, j
    return arg


def _quadrature_weights(tau: np.ndarray) -> np.ndarray:
    """Interpolatory quadrature weights on ``[-1, 1]`` of the points ``tau``."""
    n = tau.size
    V = _leg.legvander(tau, n - 1)
    rhs = np.zeros(n)
    rhs[0] = 2.0
    return np.linalg.solve(V.T, rhs)


def _span_samples(pieces, lo_idx: int, hi_idx: int):
    """State and control values of ``pieces[lo_idx..hi_idx]`` on sample points, with the
    points' position ``τ ∈ [-1, 1]`` over the union of those intervals."""
    t_a, t_b = float(pieces[lo_idx].ts[0]), float(pieces[hi_idx].t_end)
    tx, X, tu, U = [], [], [], []
    for piece in pieces[lo_idx : hi_idx + 1]:
        a, b = float(piece.ts[0]), float(piece.t_end)
        n = piece.uc.shape[0]
        m = 2 * n + 3
        s = -np.cos(np.pi * np.arange(m) / (m - 1))  # Chebyshev–Lobatto samples of the interval
        tau_sup = 2.0 * (piece.ts - a) / (b - a) - 1.0
        X.append(lagrange_matrix(tau_sup, s) @ piece.xs)
        tx.append(a + (s + 1.0) / 2.0 * (b - a))
        if piece.uc.shape[1]:
            tau_c = 2.0 * (piece.tc - a) / (b - a) - 1.0
            U.append(lagrange_matrix(tau_c, s) @ piece.uc)
            tu.append(tx[-1])
    to_tau = lambda t: 2.0 * (np.concatenate(t) - t_a) / (t_b - t_a) - 1.0  # noqa: E731
    Xa = np.vstack(X)
    Ua = np.vstack(U) if U else np.zeros((Xa.shape[0], 0))
    return to_tau(tx), Xa, (to_tau(tu) if tu else to_tau(tx)), Ua


def _fit_error(tau: np.ndarray, values: np.ndarray, degree: int) -> float:
    """Largest relative deviation ``max |P − v| / (1 + max |v|)`` (over the columns) of the
    least-squares Legendre polynomial of ``degree`` from the samples."""
    if values.shape[1] == 0:
        return 0.0
    if degree < 0:
        dev = np.abs(values)
    else:
        coef = _leg.legfit(tau, values, degree)
        dev = np.abs(_leg.legval(tau, coef).T - values)
    return float(np.max(np.max(dev, axis=0) / (1.0 + np.max(np.abs(values), axis=0))))


def _represented(pieces, lo_idx: int, hi_idx: int, n: int, bound: float) -> bool:
    """Whether ``n`` collocation points over ``pieces[lo_idx..hi_idx]`` represent the current
    solution to ``bound``: the state by a polynomial of degree ``n``, the control of ``n − 1``."""
    tx, X, tu, U = _span_samples(pieces, lo_idx, hi_idx)
    return _fit_error(tx, X, n) <= bound and _fit_error(tu, U, n - 1) <= bound


def _continuous_control(left, right, lo, hi, threshold: float) -> bool:
    """No control jump across the mesh point between two intervals (a switch placed on the
    mesh point by an ``h-jump`` split must stay a mesh point)."""
    if left.uc.shape[1] == 0:
        return True
    a, b = float(left.ts[0]), float(left.t_end)
    u_end = lagrange_matrix(2.0 * (left.tc - a) / (b - a) - 1.0, np.array([1.0])) @ left.uc
    a2, b2 = float(right.ts[0]), float(right.t_end)
    u_start = lagrange_matrix(2.0 * (right.tc - a2) / (b2 - a2) - 1.0, np.array([-1.0])) @ right.uc
    both = np.vstack([left.uc, right.uc])
    span = np.where(np.isfinite(hi - lo), hi - lo, np.ptp(both, axis=0))
    span = np.where(span > 0, span, np.inf)
    return bool(np.all(np.abs(u_end - u_start).ravel() / span < threshold))


#: Smallest relative error target: below double precision's resolution no mesh can meet it
#: (and ``e / tol`` would overflow the degree estimate).
MIN_TOL = 1e-15


def refine_mesh(
    mesh: Mesh,
    errors,
    *,
    tol: float,
    pieces=None,
    control_lower=None,
    control_upper=None,
    n_min: int = 3,
    n_max: int = 10,
    smooth_decay: float = 1.0,
    jump_threshold: float = 0.5,
    bound_junctions: bool = True,
    reduce: bool = False,
    reduce_margin: float = 10.0,
    snap: float = 0.02,
    min_width: float = 0.0,
) -> tuple[Mesh, tuple[str, ...]]:
    """The next mesh of the hp scheme and the action taken per interval.

    Parameters
    ----------
    mesh : Mesh
    errors : (n_intervals,) array_like
        Relative errors from :func:`estimate_error`.
    tol : float
        Target relative error.
    pieces : sequence, optional
        The solution's interval pieces (``solution.pieces``); enable the smoothness and
        control-jump tests. Without them every interval is refined by the ph rule alone.
    control_lower, control_upper : array_like, optional
        Control bounds for the jump test.
    n_min, n_max : int
        Fewest / most collocation points per interval.
    smooth_decay : float
        An interval is smooth when the Legendre coefficients of every state decay at least as
        ``e^{−smooth_decay k}`` (Liu, Hager & Rao 2018).
    jump_threshold : float
        A control jump larger than this fraction of its range between consecutive
        collocation points marks a nonsmooth interval (Liu, Hager & Rao 2015).
    bound_junctions : bool
        Also split at a junction between a control on a finite bound and one strictly
        inside its bounds (a bang -> singular arc corner such as -1 -> 0, half the range
        and smeared below ``jump_threshold``). :func:`solve_adaptive` turns it off for
        problems with path constraints, whose interior arcs (a mixed constraint riding)
        converged in fewer solves without it (rest-to-rest with ``u + v <= 1``: 6 vs > 12).
    reduce : bool
        Mesh size reduction (Liu, Hager & Rao 2015, §4: where the tolerance is met, lower the
        degree or merge adjacent intervals). Needs ``pieces``. An interval with
        ``e <= tol / reduce_margin`` gets the fewest points (``>= n_min``) whose polynomials
        (state of degree ``N``, control of ``N − 1``, least squares) reproduce its current
        state and control to ``tol / reduce_margin`` (relative, as the error); then adjacent
        such intervals with smooth states and no control jump across their common mesh point
        are merged, greedily from the left, while ``max`` of their point counts represents
        the union to the same bound. (The representability test is this package's criterion;
        Liu, Hager & Rao decide by their error model.)
    reduce_margin : float
        Safety factor (> 1) of the reduction tests.
    snap : float
        A bang-bang switch detected within this fraction of an interval from a mesh point
        shared with a neighbour moves that mesh point onto the switch (the interval keeps its
        points; the two intervals' fractions change, their sum does not) instead of splitting
        the interval; in ``[0, 0.5)``, 0 disables it. A switch that moved a little after the
        re-solve is tracked by the mesh point rather than cut off in a sliver interval.
    min_width : float
        Smallest interval, as a fraction of the phase's duration (``[0, 0.1]``): an interval
        the refinement would make narrower is merged into its narrower neighbour (with the
        larger point count), so a switch cannot pile up slivers (:func:`solve_adaptive`
        uses 1e-6).

    Returns
    -------
    mesh : Mesh
        The refined mesh (the same mesh when every error is below ``tol``).
    action : tuple of str
        ``"keep"``, ``"p"`` (degree raised), ``"h"`` (split into equal parts), ``"h-jump"``
        (split at a detected control jump), ``"snap"`` (a neighbouring mesh point moved onto
        a detected switch), and with ``reduce``: ``"p-"`` (degree lowered)
        or ``"merge"`` (joined with its neighbour(s)).

    References
    ----------
    Patterson, Hager & Rao 2015, eq. 31–32; Liu, Hager & Rao 2015, §3; 2018, §3.

    Examples
    --------
    >>> from adcskit.optimal_control import Mesh, refine_mesh
    >>> new, action = refine_mesh(Mesh.uniform(2, 4), [1e-3, 1e-9], tol=1e-6)
    >>> new.nodes, action
    ((9, 4), ('p', 'keep'))
    """
    if not isinstance(mesh, Mesh):
        raise InputTypeError(f"mesh must be a Mesh; got {type(mesh).__name__}")
    err = as_array("errors", errors, max_abs=None)
    check_finite("smooth_decay", smooth_decay)
    check_finite("jump_threshold", jump_threshold)
    if err.shape != (mesh.n_intervals,):
        raise InputError(f"errors must have shape ({mesh.n_intervals},); got {err.shape}")
    tol = check_range("tol", tol, MIN_TOL, math.inf)
    n_min = check_int("n_min", n_min, minimum=1)
    n_max = check_int("n_max", n_max, minimum=n_min)
    reduce = check_flag("reduce", reduce)
    bound_junctions = check_flag("bound_junctions", bound_junctions)
    margin = check_positive("reduce_margin", reduce_margin)
    snap = check_range("snap", snap, 0.0, 0.5, hi_open=True)
    min_width = check_range("min_width", min_width, 0.0, 0.1)
    if reduce and pieces is None:
        raise InputError("reduce=True needs the solution's pieces")
    if pieces is not None and len(pieces) != mesh.n_intervals:
        raise InputError(f"pieces must have {mesh.n_intervals} entries (one per interval); got {len(pieces)}")
    nodes: list[int] = []
    fracs: list[float] = []
    actions = []
    origin: list[int] = []  # the input interval of every output interval (-1: from a split)
    bound = tol / max(margin, 1.0)
    nu = pieces[0].uc.shape[1] if pieces is not None else 0
    lo_u = np.full(nu, -np.inf) if control_lower is None else np.asarray(control_lower, float)
    hi_u = np.full(nu, np.inf) if control_upper is None else np.asarray(control_upper, float)
    starts: list[int] = []  # first output interval of every input interval
    snaps: list[tuple[int, int, float]] = []  # (input interval, side -1/+1, switch fraction)
    for r, (n, fr, e) in enumerate(zip(mesh.nodes, mesh.fractions, err, strict=True)):
        starts.append(len(nodes))
        if e <= tol:
            act = "keep"
            if reduce and e <= bound and n > n_min:
                for n_new in range(n_min, n):
                    if _represented(pieces, r, r, n_new, bound):
                        n, act = n_new, "p-"
                        break
            nodes.append(n)
            fracs.append(fr)
            actions.append(act)
            origin.append(r if reduce and e <= bound else -1)
            continue
        if np.isfinite(e):
            P = max(1, math.ceil(math.log(e / tol) / math.log(max(n, 2))))
        else:
            P = n_max
        piece = pieces[r] if pieces is not None else None
        jump = None
        smooth = True
        if piece is not None:
            lo = np.full(piece.uc.shape[1], -np.inf) if control_lower is None else np.asarray(control_lower, float)
            hi = np.full(piece.uc.shape[1], np.inf) if control_upper is None else np.asarray(control_upper, float)
            jump = _control_jump(piece, lo, hi, jump_threshold, junctions=bound_junctions)
            smooth = jump is None and _legendre_decay(piece) >= smooth_decay
        side = 0
        if jump is not None and snap > 0.0:
            if jump <= snap and r > 0:
                side = -1
            elif jump >= 1.0 - snap and r < mesh.n_intervals - 1:
                side = 1
        if smooth and n + P <= n_max:
            nodes.append(n + P)
            fracs.append(fr)
            actions.append("p")
        elif side:
            # a switch beside a mesh point: move that mesh point onto it (below)
            nodes.append(n)
            fracs.append(fr)
            actions.append("snap")
            snaps.append((r, side, float(jump)))
        elif jump is not None and 0.02 < jump < 0.98:
            nodes += [max(n_min, n), max(n_min, n)]
            fracs += [fr * jump, fr * (1.0 - jump)]
            actions.append("h-jump")
        else:
            B = max(2, math.ceil((n + P) / n_min)) if np.isfinite(e) else 2
            B = min(B, 8)
            nodes += [n_min] * B
            fracs += [fr / B] * B
            actions.append("h")
        origin += [-1] * (len(nodes) - len(origin))
    starts.append(len(nodes))
    moved: set[int] = set()  # input mesh points already moved (k: between intervals k-1 and k)
    for r, side, f in snaps:
        k = r if side < 0 else r + 1
        if k in moved:
            continue
        moved.add(k)
        b = starts[k]  # output mesh point between output intervals b-1 and b
        d = f * mesh.fractions[r] if side < 0 else -(1.0 - f) * mesh.fractions[r]
        if fracs[b - 1] + d <= 0.0 or fracs[b] - d <= 0.0:
            continue
        fracs[b - 1] += d
        fracs[b] -= d
    if reduce:
        nodes, fracs, actions = _merge(nodes, fracs, actions, origin, pieces, lo_u, hi_u, bound,
                                       smooth_decay, jump_threshold)
    if min_width > 0.0:
        nodes, fracs = list(nodes), list(fracs)
        while len(fracs) > 1 and min(fracs) < min_width * sum(fracs):
            i = int(np.argmin(fracs))
            j = i - 1 if i == len(fracs) - 1 or (i > 0 and fracs[i - 1] <= fracs[i + 1]) else i + 1
            a, b = min(i, j), max(i, j)
            nodes[a:b + 1] = [max(nodes[a], nodes[b])]
            fracs[a:b + 1] = [fracs[a] + fracs[b]]
    fr_arr = np.array(fracs)
    fr_arr = fr_arr / fr_arr.sum()
    return Mesh(nodes=tuple(nodes), fractions=tuple(float(v) for v in fr_arr)), tuple(actions)


def _merge(nodes, fracs, actions, origin, pieces, lo, hi, bound, smooth_decay, jump_threshold):
    """Join runs of adjacent reducible intervals (see :func:`refine_mesh`)."""
    out_n: list[int] = []
    out_f: list[float] = []
    actions = list(actions)
    i = 0
    while i < len(nodes):
        n, fr, j = nodes[i], fracs[i], i
        r0 = origin[i]
        if r0 >= 0 and _legendre_decay(pieces[r0]) >= smooth_decay:
            while (
                j + 1 < len(nodes)
                and origin[j + 1] == origin[j] + 1
                and _legendre_decay(pieces[origin[j + 1]]) >= smooth_decay
                and _continuous_control(pieces[origin[j]], pieces[origin[j + 1]], lo, hi, jump_threshold)
                and _represented(pieces, r0, origin[j + 1], max(n, nodes[j + 1]), bound)
            ):
                n = max(n, nodes[j + 1])
                fr += fracs[j + 1]
                j += 1
            if j > i:
                for r in range(r0, origin[j] + 1):
                    actions[r] = "merge"
        out_n.append(n)
        out_f.append(fr)
        i = j + 1
    return out_n, out_f, tuple(actions)


# ----------------------------------------------------------------------------- results
@compact_repr
@dataclass(frozen=True, slots=True, kw_only=True)
class MeshIteration:
    """One solve of the refinement loop.

    Attributes
    ----------
    meshes : tuple of Mesh
        The mesh of every phase (one for a single-phase problem).
    n_collocation : int
        Collocation points over all intervals and phases.
    max_error : float
        Largest relative interval error of this solve.
    objective : float
    success : bool
        The NLP solve succeeded.
    nit : int
        IPOPT iterations.
    solve_s : float
        Wall time of the NLP build and solve (s).
    warm_start : str
        How the solve started: ``"cold"``, ``"primal"`` (previous solution interpolated onto
        the new mesh), ``"primal-dual-interpolated"`` (and its multipliers interpolated) or
        ``"primal-dual"`` (same mesh; see :func:`solve`).
    build_s : float
        Wall time of the CasADi NLP build(s) of this step (s); near 0 when the compiled NLP
        of the same mesh structure came from the cache (issue 22, item 5).
    ipopt_s : float
        Wall time inside IPOPT (s). ``solve_s − build_s − ipopt_s`` is the guess
        interpolation, costates and error estimate. For the ``"switch-times"`` step both are
        sums over its own multi-phase refinement.

    Examples
    --------
    >>> from adcskit.optimal_control import solve_adaptive
    >>> from adcskit.optimal_control.problems import double_integrator_min_time
    >>> sol = solve_adaptive(double_integrator_min_time(), tol=1e-6)

    >>> it = sol.mesh_history[0]
    >>> it.n_collocation > 0, it.warm_start
    (True, 'cold')
    >>> it.build_s >= 0.0 and 0.0 < it.ipopt_s <= it.solve_s
    True
    """

    meshes: tuple[Mesh, ...]
    n_collocation: int
    max_error: float
    objective: float
    success: bool
    nit: int
    solve_s: float
    warm_start: str = "cold"
    build_s: float = 0.0
    ipopt_s: float = 0.0

    def to_dict(self) -> dict[str, Any]:
        return {
            "nodes": [list(m.nodes) for m in self.meshes],
            "fractions": [list(m.fractions) for m in self.meshes],
            "n_collocation": self.n_collocation,
            "max_error": self.max_error,
            "objective": self.objective,
            "success": self.success,
            "nit": self.nit,
            "solve_s": self.solve_s,
            "warm_start": self.warm_start,
            "build_s": self.build_s,
            "ipopt_s": self.ipopt_s,
        }


@dataclass(frozen=True, slots=True, repr=False, kw_only=True)
class ErrorCertificate(Result):
    """Final error statement of an adaptive solve.

    Attributes
    ----------
    satisfied : bool
        ``error_met`` and no applied optimality check failed (``optimality_met`` is True, or
        None when no check applied): what ``success`` of :func:`solve_adaptive` requires.
    tol : float
    max_error : float
    worst_phase, worst_interval : int
        Location of ``max_error``.
    worst_time : float
        Mid-time of the worst interval (s).
    n_collocation : int
    mesh_iterations : int
    estimator : str
        How the error was measured.
    error_met : bool
        The NLP converged and every interval's relative state error is ``<= tol``.
    optimality_met : bool or None
        True/False: the first-order optimality checks of
        :func:`~adcskit.optimal_control.check_optimality` (single-phase problems) hold / fail.
        None ("not checked") when no check applied: a multi-phase problem,
        ``check_optimality=False`` or a failed NLP; ``optimality_checks`` is then empty and
        ``optimality_detail`` says why. Never True without a check.
    optimality_checks : tuple of str
        The checks applied (``"H-constant"``, ``"transversality"``, ``"switching-sign"``,
        ``"singular-arc"``, ``"legendre-clebsch"``).
    optimality_figures : dict
        ``h_spread``, ``h_target_error``, ``switching_violation``, ``singular_violation``,
        ``legendre_clebsch_violation`` and the ``threshold`` they were held to (relative to
        the size of the Hamiltonian's terms).
    optimality_detail : str

    Examples
    --------
    >>> from adcskit.optimal_control import solve_adaptive
    >>> from adcskit.optimal_control.problems import double_integrator_min_time
    >>> sol = solve_adaptive(double_integrator_min_time(), tol=1e-6)

    >>> c = sol.certificate
    >>> c.satisfied, c.tol
    (True, 1e-06)
    """

    satisfied: bool
    tol: float
    max_error: float
    worst_phase: int
    worst_interval: int
    worst_time: float
    n_collocation: int
    mesh_iterations: int
    estimator: str
    error_met: bool = False
    optimality_met: bool | None = None
    optimality_checks: tuple[str, ...] = ()
    optimality_figures: dict[str, float] = field(default_factory=dict)
    optimality_detail: str = ""


@compact_repr
@dataclass(frozen=True, slots=True, kw_only=True)
class AdaptiveSolution(OptimalControlSolution):
    """An :class:`OptimalControlSolution` on an error-controlled mesh.

    Attributes
    ----------
    max_error : float
        Largest relative state error over the final mesh's intervals.
    interval_errors : (n_intervals,) ndarray
        Relative state error per interval of the final mesh (:func:`estimate_error`).
    mesh_history : tuple of MeshIteration
        Every solve of the refinement loop, first to last.
    certificate : ErrorCertificate

    Examples
    --------
    >>> from adcskit.optimal_control import solve_adaptive
    >>> from adcskit.optimal_control.problems import double_integrator_min_time
    >>> sol = solve_adaptive(double_integrator_min_time(), tol=1e-6)

    >>> sol.success, round(sol.tf, 6), bool(sol.max_error <= 1e-6)
    (True, 2.0, True)
    """

    max_error: float
    interval_errors: np.ndarray
    mesh_history: tuple[MeshIteration, ...]
    certificate: ErrorCertificate

    def to_dict(self) -> dict[str, Any]:
        out = OptimalControlSolution.to_dict(self)
        out.update(
            max_error=self.max_error,
            interval_errors=self.interval_errors,
            mesh_history=[m.to_dict() for m in self.mesh_history],
            certificate=self.certificate.to_dict(),
        )
        return out


# ----------------------------------------------------------------------------- driver
def _estimator_text(extra: int) -> str:
    return (
        f"collocation polynomial vs LGR integration of the dynamics under the interpolated control "
        f"on N+{extra} points per interval (Patterson, Hager & Rao 2015)"
    )


def _phase_errors(phase_sols, extra):
    return [estimate_error(s, extra_points=extra) for s in phase_sols]


def default_optimality_threshold(tol: float) -> float:
    """Threshold of the optimality figures used by :func:`solve_adaptive` for a tolerance.

    ``max(0.02, 2 √tol)``: see :func:`~adcskit.optimal_control.check_optimality` and
    docs/optimal-control.md ("What success certifies") for the calibration.

    Examples
    --------
    >>> from adcskit.optimal_control import default_optimality_threshold
    >>> default_optimality_threshold(1e-6), default_optimality_threshold(1.0)
    (0.02, 2.0)
    """
    tol = check_positive("tol", tol)
    return float(max(0.02, 2.0 * math.sqrt(tol)))


def _certificate(phase_sols, errs, tol, success, n_iter, extra, *, multi=False, check=True,
                 threshold=0.02) -> ErrorCertificate:
    from adcskit.optimal_control.analysis import check_optimality as _check

    worst = (-1, -1, -np.inf)
    for i, e in enumerate(errs):
        if e.size and np.max(e) > worst[2]:
            worst = (i, int(np.argmax(e)), float(np.max(e)))
    ip, ir, emax = worst
    piece = phase_sols[ip].pieces[ir]
    opt = None
    if check and not multi and success:
        opt = _check(phase_sols[0], threshold=threshold, singular_threshold=min(threshold, 2.0 * math.sqrt(tol)))
    if opt is not None:
        o_met, o_checks, o_fig, o_detail = opt.met, opt.checks, dict(
            h_spread=opt.h_spread, h_target_error=opt.h_target_error,
            switching_violation=opt.switching_violation, singular_violation=opt.singular_violation,
            legendre_clebsch_violation=opt.legendre_clebsch_violation, threshold=opt.threshold), opt.detail
    else:
        why = ("not checked (check_optimality=False)" if not check else
               "not checked (multi-phase problem)" if multi else "not checked (the NLP failed)")
        o_met, o_checks, o_fig, o_detail = None, (), {}, why
    dyn_ok = bool(success and emax <= tol)
    return ErrorCertificate(
        satisfied=bool(dyn_ok and o_met is not False),
        tol=tol,
        max_error=emax,
        worst_phase=ip,
        worst_interval=ir,
        worst_time=float(0.5 * (piece.ts[0] + piece.t_end)),
        n_collocation=int(sum(sum(s.mesh.nodes) for s in phase_sols)),
        mesh_iterations=n_iter,
        estimator=_estimator_text(extra),
        error_met=dyn_ok,
        optimality_met=None if o_met is None else bool(o_met),
        optimality_checks=tuple(o_checks),
        optimality_figures=o_fig,
        optimality_detail=o_detail,
    )


def _likely_causes(sol) -> str:
    """Likely causes, with the parameter to change, when refinement of a converged solution stalls.

    Looks at a single-phase solution for three patterns that make hp refinement blow up:
    ``tf`` sitting at a finite bound of ``tf_bounds`` (the optimum may lie beyond it), an
    unbounded control in a free-final-time problem (a minimum-time optimum that wants an
    impulse) and an unbounded control whose values span more than ``2π`` or jump by about
    ``2π`` (an angle the NLP can wrap onto another branch). Returns ``""`` when none applies.
    :func:`solve_adaptive` applies it to every phase of a multi-phase solution.
    """
    pr = getattr(sol, "problem", None)
    if not isinstance(pr, OptimalControlProblem) or not np.isfinite(sol.tf):
        return ""
    out = []
    if pr.free_final_time:
        lo_tf, hi_tf = pr.tf_bounds
        span = max(abs(sol.tf - pr.t0), 1e-12)
        for name, b in (("lower", lo_tf), ("upper", hi_tf)):
            if np.isfinite(b) and b > pr.t0 and abs(sol.tf - b) <= 1e-6 * span:
                out.append(f"tf = {sol.tf:.6g} s sits at its {name} bound (tf_bounds={pr.tf_bounds}): "
                           "the optimum may lie beyond it; widen tf_bounds")
    names = pr.control_names
    u = np.asarray(sol.u, float)
    for j in range(pr.n_controls):
        if np.isfinite(pr.control_lower[j]) and np.isfinite(pr.control_upper[j]):
            continue
        uj = u[:, j][np.isfinite(u[:, j])]
        if uj.size < 2:
            continue
        jumps = np.abs(np.diff(uj))
        if np.ptp(uj) > 2.0 * np.pi or np.any(np.abs(jumps - 2.0 * np.pi) < 0.5):
            out.append(f"control {names[j]!r} is unbounded and spans {np.ptp(uj):.3g} (> 2π or a ~2π jump): "
                       "if it is an angle the NLP can wrap it onto another 2π branch; bound it to one branch "
                       "(control_lower/control_upper) or write it as (cos, sin)")
        if pr.free_final_time:
            out.append(f"control {names[j]!r} is unbounded in a free-final-time problem (max |u| = "
                       f"{np.max(np.abs(uj)):.3g}): a minimum-time optimum may want an impulse; bound it "
                       "with control_lower/control_upper")
    return "; ".join(out)


def solve_adaptive(
    problem,
    *,
    tol: float = 1e-6,
    method: str = "radau",
    mesh=None,
    guess=None,
    max_iterations: int = 12,
    n_min: int = 3,
    n_max: int = 10,
    max_intervals: int = 400,
    extra_points: int = 1,
    ipopt_options: dict[str, Any] | None = None,
    transfer_duals: bool = True,
    mesh_reduction: bool = True,
    min_width: float = 1e-6,
    check_optimality: bool = True,
    optimality_threshold: float | None = None,
    switch_times: bool = True,
):
    """Solve an optimal-control problem to a relative state-error tolerance by hp refinement.

    Parameters
    ----------
    problem : OptimalControlProblem or MultiPhaseProblem
    tol : float
        Relative state error required in every mesh interval (:func:`estimate_error`).
    method : {"radau", "gauss"}
    mesh : Mesh or (int, int) or sequence of them, optional
        Initial mesh (one per phase for a multi-phase problem); default 10 intervals of
        ``n_min + 1`` points, as GPOPS-II starts.
    guess : Guess, OptimalControlSolution, callable, "linear", optional
        Accepted: single phase — ``None``, a :class:`Guess`, a previous solution, a callable,
        ``"linear"``; multi-phase — ``None``, ``"linear"``, a :class:`MultiPhaseGuess` or
        :class:`MultiPhaseSolution`. Initial guess (see :func:`solve` / :func:`solve_multiphase`; a callable
        ``t -> (x, u)`` is sampled by :func:`guess_from_function`; ``"linear"`` is
        :func:`default_guess`). Default for a single phase: :func:`symmetry_breaking_guess`,
        which does not start on the symmetric stationary point (e.g. the eigenaxis slew of
        the rigid-body reorientation, a KKT point that IPOPT does not leave).
    max_iterations : int
        Most NLP solves (the first mesh counts).
    n_min, n_max : int
        Fewest / most collocation points per interval.
    max_intervals : int
        Refinement stops (``success=False``) rather than exceed this many intervals per phase.
    extra_points : int
        Extra LGR points of the error estimate.
    ipopt_options : dict, optional
    transfer_duals : bool
        Warm-start every refined mesh from the previous solution's primal values *and* its
        multipliers interpolated onto the new mesh (:func:`solve`'s ``transfer_duals``;
        ``MeshIteration.warm_start == "primal-dual-interpolated"``). False passes the primal
        values only (multi-phase: with IPOPT's default options, as :func:`solve_multiphase`).
    mesh_reduction : bool
        Also lower degrees and merge intervals where the error is far below ``tol``
        (:func:`refine_mesh`'s ``reduce``; Liu, Hager & Rao 2015, §4). Default on: measured
        smaller final meshes at equal wall time (docs/benchmarks.md).
    min_width : float
        Narrowest interval the refinement makes, as a fraction of the phase (``[0, 0.1]``).
    check_optimality : bool
        Require the first-order optimality checks of
        :func:`~adcskit.optimal_control.check_optimality` (single phase) for ``success``;
        when the error test passes and they fail, refinement goes on where ``H`` departs
        from its median.
    optimality_threshold : float, optional
        Bound of the relative optimality figures; default
        :func:`default_optimality_threshold` ``(tol) = max(0.02, 2 √tol)``.
    switch_times : bool
        Once a bang-bang structure is stable over two meshes, re-solve with the switch times
        as free phase boundaries (one constant-bound arc per phase, :func:`solve_multiphase`)
        and continue from the joined solution (single phase; counts as one solve). A re-solve
        that raises ``J`` by more than ``tol·|J|`` over the solution it started from (when
        that solution's mesh error ``e`` has ``e² <= tol``, so its ``J`` is trusted to
        ``tol·|J|``) is rejected (the arc structure was not bang-bang, e.g. a short singular arc) and listed
        in ``mesh_history``.

    Returns
    -------
    AdaptiveSolution or MultiPhaseSolution
        The usual solution with ``max_error``, ``interval_errors``, ``mesh_history`` and
        ``certificate``. ``success`` is True only when IPOPT converged, the tolerance holds
        in every interval *and* the optimality checks hold (``certificate.error_met``,
        ``certificate.optimality_met``); otherwise ``message`` says what failed, opening with
        ``"infeasible:"`` when IPOPT proved the NLP infeasible. A failed NLP is never
        refined from: it is retried (cold IPOPT options and more iterations; a fixed-``tf``
        feasibility step before any converged solve of a free-final-time problem; a perturbed
        guess after an infeasible first solve), and the last *converged* solution is returned.
        Two consecutive meshes proved infeasible end the run.

    References
    ----------
    Patterson, Hager & Rao 2015 (ph); Liu, Hager & Rao 2015, 2018 (hp).

    Examples
    --------
    >>> from adcskit.optimal_control import solve_adaptive
    >>> from adcskit.optimal_control.problems import double_integrator_min_time
    >>> sol = solve_adaptive(double_integrator_min_time(), tol=1e-6)
    >>> sol.success, round(sol.tf, 6)  # bang-bang, tf = 2 sqrt(d/a) = 2
    (True, 2.0)
    """
    from adcskit.optimal_control.multiphase import MultiPhaseProblem, solve_multiphase

    multi = isinstance(problem, MultiPhaseProblem)
    if not multi and not isinstance(problem, OptimalControlProblem):
        raise InputTypeError(
            f"problem must be an OptimalControlProblem or MultiPhaseProblem; got {type(problem).__name__}"
        )
    tol = check_range("tol", tol, MIN_TOL, math.inf)
    method = check_choice("method", method, METHODS)
    max_iterations = check_int("max_iterations", max_iterations, minimum=1)
    n_min = check_int("n_min", n_min, minimum=1)
    n_max = check_int("n_max", n_max, minimum=n_min)
    max_intervals = check_int("max_intervals", max_intervals, minimum=1)
    extra = check_int("extra_points", extra_points, minimum=1, maximum=10)
    transfer_duals = check_flag("transfer_duals", transfer_duals)
    mesh_reduction = check_flag("mesh_reduction", mesh_reduction)
    min_width = check_range("min_width", min_width, 0.0, 0.1)
    check_optimality_flag = check_flag("check_optimality", check_optimality)
    switch_times = check_flag("switch_times", switch_times)
    from adcskit.optimal_control.analysis import check_optimality as _check_optimality
    optimality_threshold = (
        default_optimality_threshold(tol) if optimality_threshold is None
        else check_positive("optimality_threshold", optimality_threshold)
    )
    n_phases = len(problem.phases) if multi else 1
    meshes = _initial_meshes(mesh, n_phases, n_min)
    if guess is None and not multi:
        guess = symmetry_breaking_guess(problem)
    elif isinstance(guess, str):
        if guess != "linear":
            raise InputError(f"guess must be a Guess, a solution, a callable, None or 'linear'; got {guess!r}")
        guess = None
    elif callable(guess) and not isinstance(guess, Guess | OptimalControlSolution):
        if multi:
            raise InputTypeError("for a multi-phase problem give guess as a MultiPhaseGuess or solution")
        guess = guess_from_function(guess, problem.t0, problem.tf_guess)

    history: list[MeshIteration] = []
    message = ""
    converged = False
    sol = None
    good = None  # (solution, phase solutions, errors, meshes) of the last converged NLP
    errs: list[np.ndarray] = []
    phase_sols: list = []
    n_solves = 0
    infeasible_meshes = 0  # consecutive meshes on which IPOPT proved the NLP infeasible
    stop_infeasible = False
    cold_next = False
    last_sig = None
    tried_sigs: set[bytes] = set()

    def run(meshes, guess, opts, warm, prob=None):
        t_start = time.perf_counter()
        if multi:
            out = solve_multiphase(problem, method=method, meshes=meshes, guess=guess, ipopt_options=opts,
                                   transfer_duals=transfer_duals and warm is not False)
            ps = list(out.phases)
        else:
            out = solve(prob or problem, method=method, mesh=meshes[0], guess=guess, ipopt_options=opts,
                        transfer_duals=transfer_duals and warm is not False, warm_start=warm)
            ps = [out]
        wall = time.perf_counter() - t_start
        e = _phase_errors(ps, extra)
        history.append(
            MeshIteration(
                meshes=tuple(meshes),
                n_collocation=int(sum(sum(m.nodes) for m in meshes)),
                max_error=float(max(np.max(v) for v in e)),
                objective=float(out.objective),
                success=bool(out.success),
                nit=int(out.nit),
                solve_s=wall,
                warm_start=str(out.warm_start),
                build_s=float(out.build_s),
                ipopt_s=float(out.solve_s),
            )
        )
        return out, ps, e

    while n_solves < max_iterations:
        # after a failed optimality check the refined mesh is solved with IPOPT's cold defaults
        # (from the previous primal point): the warm start's tiny barrier keeps a switch
        # where it sits, cold ones let it move
        sol, phase_sols, errs = run(meshes, guess, ipopt_options, False if cold_next else None)
        cold_next = False
        n_solves += 1
        # a failed NLP is never refined from: retry on the same mesh (IPOPT's cold defaults
        # from the last good point or the guess, more iterations), then fall back to the last
        # good solution (below)
        retry_opts = dict(ipopt_options or {})
        retry_opts["max_iter"] = 3 * int(retry_opts.get("max_iter", 500))
        if not sol.success and n_solves < max_iterations and sol.status != 3:
            start = good[0] if good is not None else guess
            sol, phase_sols, errs = run(meshes, start, retry_opts, False)
            n_solves += 1
        if (not sol.success and not multi and good is None and problem.free_final_time
                and n_solves + 1 < max_iterations):
            # no solution yet of a free-final-time problem: a feasibility step with tf fixed at
            # its guess, then the free problem from there (IPOPT tends to shrink tf from a poor
            # guess until the NLP is locally infeasible: the minimum-time oscillator)
            fixed = problem.replace(tf_bounds=(problem.tf_guess, problem.tf_guess))
            feas, _, _ = run(meshes, guess, retry_opts, False, prob=fixed)
            n_solves += 1
            if feas.success:
                sol, phase_sols, errs = run(meshes, feas, retry_opts, False)
                n_solves += 1
        if not sol.success and sol.status == 3 and n_solves < max_iterations and not multi and good is None:
            # proved infeasible from the first guess: once more from a perturbed (symmetry-breaking) guess
            sol, phase_sols, errs = run(meshes, symmetry_breaking_guess(problem, amplitude=0.5), retry_opts, False)
            n_solves += 1
        emax = float(max(np.max(e) for e in errs))
        if sol.success and switch_times and not multi and n_solves < max_iterations:
            structure = _bang_structure(sol)
            sig = None if structure is None else structure[0].tobytes()
            if sig is not None and sig == last_sig and sig not in tried_sigs:
                # the bang-bang structure is stable over two meshes: free the switch times
                tried_sigs.add(sig)
                t_start = time.perf_counter()
                polished = _switch_time_solve(problem, sol, structure, tol=tol, method=method, n_min=n_min,
                                              n_max=n_max, min_width=min_width, ipopt_options=ipopt_options)
                n_solves += 1
                rise = (-np.inf if polished is None or not polished[0].success
                        else float(polished[0].objective) - float(sol.objective))
                # judged only when the mesh before is accurate enough for its J to be trusted to
                # tol·|J| (cost error ~ state error squared): emax² <= tol
                if rise > tol * max(abs(float(sol.objective)), 1e-12) and emax * emax <= tol:
                    # the bang-bang re-solve raised J over the solution it started from: the
                    # structure is not bang-bang (e.g. a short singular arc read as a smeared
                    # switch); keep refining the solution before it
                    p_sol, nit_p, build_p, ipopt_p = polished
                    history.append(MeshIteration(
                        meshes=(p_sol.mesh,), n_collocation=int(sum(p_sol.mesh.nodes)),
                        max_error=float(np.max(_phase_errors([p_sol], extra)[0])),
                        objective=float(p_sol.objective), success=True, nit=int(nit_p),
                        solve_s=time.perf_counter() - t_start,
                        warm_start=f"switch-times rejected (J rose by {rise:.3g} > tol·|J|)",
                        build_s=build_p, ipopt_s=ipopt_p))
                elif polished is not None and polished[0].success:
                    sol, nit_p, build_p, ipopt_p = polished
                    phase_sols = [sol]
                    errs = _phase_errors(phase_sols, extra)
                    emax = float(np.max(errs[0]))
                    meshes = [sol.mesh]
                    history.append(MeshIteration(
                        meshes=(sol.mesh,), n_collocation=int(sum(sol.mesh.nodes)), max_error=emax,
                        objective=float(sol.objective), success=True, nit=int(nit_p),
                        solve_s=time.perf_counter() - t_start, warm_start="switch-times",
                        build_s=build_p, ipopt_s=ipopt_p))
            last_sig = sig
        if sol.success:
            infeasible_meshes = 0
            good = (sol, phase_sols, errs, list(meshes))
            guess = sol  # warm start of the next mesh
        else:
            infeasible_meshes = infeasible_meshes + 1 if sol.status == 3 else 0
            if infeasible_meshes >= 2:
                stop_infeasible = True
                where = meshes[0].label() if not multi else "per-phase meshes"
                if good is not None:
                    # an earlier mesh converged: the problem is feasible, the refined NLPs lost its basin
                    message = (
                        f"IPOPT reported local infeasibility on {infeasible_meshes} consecutive refined meshes "
                        f"(last {where}) after an earlier mesh had converged (the problem is feasible): the "
                        "refinement left the converged solution's basin; try the other method, a different "
                        "initial mesh or guess, or a larger max_iterations"
                    )
                else:
                    message = (
                        f"infeasible: IPOPT proved the NLP locally infeasible on {infeasible_meshes} consecutive "
                        f"meshes (last {where}); the problem's constraints (bounds, boundary values, tf_bounds, "
                        "path) may have no solution"
                    )
                break
        opt_split = None
        if sol.success and emax <= tol:
            opt = None
            if check_optimality_flag and not multi:
                opt = _check_optimality(sol, threshold=optimality_threshold,
                                        singular_threshold=min(optimality_threshold, 2.0 * math.sqrt(tol)))
            if opt is None or opt.met is not False:  # None: no check applies (certificate says so)
                converged = True
                message = f"tolerance {tol:g} met on mesh iteration {len(history)}: max relative error {emax:.3g}"
                break
            # the dynamics meet tol but the optimality conditions do not: refine where H departs
            # from its median (a misplaced switch bounds an arc of wrong H), else beside switches
            opt_split = _optimality_split(sol, opt, min_width)
            cold_next = True
            if n_solves < max_iterations and opt_split is not None:
                new_meshes = [opt_split]
                if new_meshes[0] == meshes[0]:
                    message = (f"tolerance {tol:g} met but the optimality conditions are not and the mesh cannot be "
                               f"refined further (min_width={min_width:g})")
                    break
        if n_solves >= max_iterations:
            message = f"max_iterations={max_iterations} reached with max relative error {emax:.3g} > tol {tol:g}"
            break
        if opt_split is not None:
            pass
        elif sol.success:
            new_meshes = []
            for m, ps, e in zip(meshes, phase_sols, errs, strict=True):
                nm, _ = refine_mesh(
                    m,
                    e,
                    tol=tol,
                    pieces=ps.pieces,
                    control_lower=ps.problem.control_lower,
                    control_upper=ps.problem.control_upper,
                    n_min=n_min,
                    n_max=n_max,
                    reduce=mesh_reduction,
                    min_width=min_width,
                    bound_junctions=getattr(ps.problem, "path", None) is None,
                )
                new_meshes.append(nm)
            if all(nm == m for nm, m in zip(new_meshes, meshes, strict=True)):
                message = (
                    f"the mesh cannot be refined further (min_width={min_width:g}, n_max={n_max}); stopped with "
                    f"max relative error {emax:.3g} > tol {tol:g}"
                )
                break
        else:
            # the NLP failed on this mesh even after the retry: refine it uniformly (p, or h at
            # n_max) and start again from the last good solution
            new_meshes = [_uniform_refinement(m, n_max, min_width) for m in meshes]
        if any(nm.n_intervals > max_intervals for nm in new_meshes):
            message = (
                f"max_intervals={max_intervals} would be exceeded; stopped with max relative error {emax:.3g} > tol {tol:g}"
            )
            break
        meshes = new_meshes
    failed_nlp = sol
    if not sol.success and good is not None:
        # report the last converged NLP, never a failed iterate
        sol, phase_sols, errs, meshes = good
        message = f"{message}; the last NLP failed ({failed_nlp.message}): the last converged mesh is reported"
    elif not sol.success:
        if sol.status == 3 and not stop_infeasible:
            message = f"infeasible: IPOPT proved the NLP locally infeasible ({sol.message}); {message}"
        else:
            message = f"{message}; last NLP: {sol.message}"
    cert = _certificate(phase_sols, errs, tol, sol.success, len(history), extra, multi=multi,
                        check=check_optimality_flag, threshold=optimality_threshold)
    emax = cert.max_error
    extras = dict(
        max_error=emax,
        interval_errors=tuple(errs) if multi else errs[0],
        mesh_history=tuple(history),
        certificate=cert,
    )
    ok = bool(converged and sol.success and cert.satisfied)
    if sol.success and cert.error_met and cert.optimality_met is False:
        message = f"optimality conditions NOT met ({cert.optimality_detail}); {message}"
    if ok:
        checked = ("optimality checks " + ", ".join(cert.optimality_checks) + " hold"
                   if cert.optimality_checks else f"optimality {cert.optimality_detail}")
        message = (f"locally optimal: {message}; {checked}; a local optimum of the NLP: "
                   "multistart (or other guesses) searches for better ones")
    elif sol.success and not cert.error_met:
        parts = [_likely_causes(ps) for ps in phase_sols]
        causes = "; ".join(f"phase {i}: {c}" if multi else c for i, c in enumerate(parts) if c)
        if causes:
            message = f"{message}; likely cause: {causes}"
    if multi:
        return sol.with_adaptive(success=ok, message=f"{message} ({sol.message})", **extras)
    base = {f.name: getattr(sol, f.name) for f in fields(OptimalControlSolution)}
    base.update(success=ok, message=f"{message} ({sol.message})")
    return AdaptiveSolution(**base, **extras)


def _optimality_split(sol, opt, min_width: float) -> Mesh | None:
    """Halve the intervals holding a collocation point whose ``H`` departs from the median by
    more than the threshold (else those beside a control switch), keeping ``min_width``."""
    mesh = sol.mesh
    lo, hi = sol.problem.control_lower, sol.problem.control_upper
    from adcskit.optimal_control.analysis import _switch_adjacent

    dev = np.abs(sol.hamiltonian - opt.h_median) / opt.h_scale
    bad = dev > opt.threshold if np.isfinite(opt.h_spread) and opt.h_spread > opt.threshold else None
    if opt.singular_points and not (opt.singular_violation <= opt.singular_threshold):
        # a singular arc whose switching function does not vanish: refine the arc
        sing = np.zeros(sol.t_control.size, bool)
        sing[list(opt.singular_points)] = True
        bad = sing if bad is None else bad | sing
    if bad is None or not np.any(bad):
        bad = _switch_adjacent(sol.u, lo, hi)
    if not np.any(bad):
        return None
    owner = np.repeat(np.arange(mesh.n_intervals), mesh.nodes)
    marked = set(owner[bad].tolist())
    nodes: list[int] = []
    fr: list[float] = []
    for r, (n, f) in enumerate(zip(mesh.nodes, mesh.fractions, strict=True)):
        if r in marked and f / 2.0 >= min_width:
            nodes += [n, n]
            fr += [f / 2.0, f / 2.0]
        else:
            nodes.append(n)
            fr.append(f)
    a = np.array(fr)
    return Mesh(nodes=tuple(nodes), fractions=tuple((a / a.sum()).tolist()))


def _uniform_refinement(mesh: Mesh, n_max: int, min_width: float) -> Mesh:
    """One more collocation point per interval; intervals already at ``n_max`` are halved
    (while the halves stay at least ``min_width`` wide)."""
    nodes: list[int] = []
    fr: list[float] = []
    for n, f in zip(mesh.nodes, mesh.fractions, strict=True):
        if n < n_max:
            nodes.append(n + 1)
            fr.append(f)
        elif f / 2.0 >= min_width:
            nodes += [n, n]
            fr += [f / 2.0, f / 2.0]
        else:
            nodes.append(n)
            fr.append(f)
    a = np.array(fr)
    return Mesh(nodes=tuple(nodes), fractions=tuple((a / a.sum()).tolist()))


# ----------------------------------------------------------------------------- switch times
def _bang_structure(sol, on_bound: float = 0.02, max_transition: float = 0.05):
    """The arcs of a bang-bang solution: ``(values, boundaries)`` with ``values`` (K, nu) in
    {−1, +1} (lower / upper bound) and the K − 1 switch-time estimates (s), or None.

    Per channel, consecutive on-bound collocation points on opposite bounds bracket a switch
    (placed mid-way); off-bound points between them are the discretisation smearing it, as
    long as the gap is at most ``max_transition`` of the horizon. A longer off-bound run (a
    singular or smooth arc), an infinite bound, or no switch at all gives None: such
    solutions are left to the general refinement. Switches of different channels closer than
    ``1e-4`` of the horizon are one boundary.
    """
    pr = sol.problem
    lo, hi = pr.control_lower, pr.control_upper
    if pr.n_controls == 0 or not np.all(np.isfinite(lo) & np.isfinite(hi) & (hi > lo)):
        return None
    span = hi - lo
    u, tc = sol.u, sol.t_control
    T = float(sol.tf - sol.t0)
    cls = np.where(np.abs(u - hi) <= on_bound * span, 1, np.where(np.abs(u - lo) <= on_bound * span, -1, 0))
    switch_t: list[float] = []
    for j in range(u.shape[1]):
        k_on = np.flatnonzero(cls[:, j] != 0)
        if k_on.size == 0:
            return None
        # off-bound stretches at the ends of the horizon are not a bang-bang control either
        if tc[k_on[0]] - sol.t0 > max_transition * T or sol.tf - tc[k_on[-1]] > max_transition * T:
            return None
        for a, b in zip(k_on[:-1], k_on[1:], strict=True):
            gap = tc[b] - tc[a]
            if b > a + 1 and gap > max_transition * T:
                return None  # a long off-bound run: singular or smooth arc
            if cls[a, j] != cls[b, j]:
                switch_t.append(0.5 * (tc[a] + tc[b]))
    if not switch_t:
        return None
    ts = np.sort(np.array(switch_t))
    merged = [ts[0]]
    for t in ts[1:]:
        if t - merged[-1] > 1e-4 * T:
            merged.append(t)
    edges = np.concatenate(([sol.t0], merged, [sol.tf]))
    vals = []
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        row = []
        for j in range(u.shape[1]):
            k_on = np.flatnonzero(cls[:, j] != 0)
            k = k_on[np.argmin(np.abs(tc[k_on] - 0.5 * (a + b)))]
            row.append(cls[k, j])
        vals.append(row)
    return np.array(vals, dtype=int), np.array(merged)


def _switch_time_solve(problem, sol, structure, *, tol, method, n_min, n_max, min_width, ipopt_options):
    """Re-solve a bang-bang solution with its switch times as free phase boundaries.

    One phase per arc with the control fixed at the arc's bounds, state and time continuity
    between phases (:func:`solve_multiphase`, refined by :func:`solve_adaptive`); the optimal
    switch times then become mesh points of a single-phase mesh (each phase's final mesh
    scaled into its arc) on which the original problem is solved warm from the multi-phase
    trajectory. Returns ``(solution, nit, build_s, ipopt_s)`` (sums over its meshes) or None when a step fails.
    """
    from adcskit.optimal_control.multiphase import MultiPhaseGuess, MultiPhaseProblem, Phase

    vals, bounds = structure
    pr = problem
    lo, hi = pr.control_lower, pr.control_upper
    sx, su = pr.scales()
    t_hi = pr.tf_bounds[1] if np.isfinite(pr.tf_bounds[1]) else pr.t0 + 10.0 * (sol.tf - pr.t0)
    edges = np.concatenate(([pr.t0], bounds, [sol.tf]))
    K = len(vals)
    phases, guesses = [], []
    for k in range(K):
        uval = np.where(vals[k] > 0, hi, lo)
        phases.append(Phase(
            name=f"arc{k}",
            dynamics=lambda x, u, t, p, _f=pr.dynamics: _f(x, u, t),
            lagrange=None if pr.lagrange is None else (lambda x, u, t, p, _g=pr.lagrange: _g(x, u, t)),
            path=None if pr.path is None else (lambda x, u, t, p, _c=pr.path: _c(x, u, t)),
            path_lower=pr.path_lower if pr.path is not None else None,
            path_upper=pr.path_upper if pr.path is not None else None,
            n_states=pr.n_states,
            n_controls=pr.n_controls,
            state_names=pr.state_names,
            control_names=pr.control_names,
            state_lower=pr.state_lower,
            state_upper=pr.state_upper,
            control_lower=uval,
            control_upper=uval,
            initial_state=pr.initial_state if k == 0 else None,
            final_state=pr.final_state if k == K - 1 else None,
            t0_bounds=(pr.t0, pr.t0) if k == 0 else (pr.t0, t_hi),
            tf_bounds=pr.tf_bounds if k == K - 1 else (pr.t0, t_hi),
            t0_guess=float(edges[k]),
            tf_guess=float(edges[k + 1]),
            state_scale=sx,
            control_scale=su,
        ))
        tt = np.linspace(edges[k], edges[k + 1], 9)
        guesses.append(Guess(t=tt, x=sol.state_at(tt), u=np.tile(uval, (tt.size, 1)), tf=float(max(edges[k + 1], 1e-12))))
    mayer = pr.mayer
    multi = MultiPhaseProblem(
        name=f"{pr.name}-switch-times",
        phases=phases,
        objective=None if mayer is None else (lambda ends, p: mayer(ends[0].x0, ends[0].t0, ends[-1].xf, ends[-1].tf)),
    )
    try:
        msol = solve_adaptive(multi, tol=tol, method=method, mesh=[Mesh.uniform(2, n_min + 1)] * K,
                              guess=MultiPhaseGuess(phases=tuple(guesses), parameters=np.zeros(0)),
                              max_iterations=6, n_min=n_min, n_max=n_max, ipopt_options=ipopt_options)
    except (ValueError, RuntimeError):
        return None
    nit = sum(m.nit for m in msol.mesh_history)
    build_s = sum(m.build_s for m in msol.mesh_history)
    ipopt_s = sum(m.ipopt_s for m in msol.mesh_history)
    if not msol.success:
        return None
    return _join_phases(pr, msol, min_width), nit, build_s, ipopt_s


def _join_phases(pr, msol, min_width: float) -> OptimalControlSolution:
    """The single-phase solution made of a multi-phase solution's arcs (collapsed arcs,
    shorter than ``min_width`` of the horizon, left out): one mesh whose points include the
    phase boundaries, the phases' pieces, samples and costates in sequence."""
    T = msol.phases[-1].tf - pr.t0
    keep = [ph for ph in msol.phases if (ph.tf - ph.t0) / T >= max(min_width, 1e-12)]
    nodes: list[int] = []
    fr: list[float] = []
    cat: dict[str, list] = {k: [] for k in ("t", "x", "costate", "t_control", "u", "hamiltonian", "switching")}
    pieces: list = []
    for n, ph in enumerate(keep):
        d = (ph.tf - ph.t0) / T
        nodes += list(ph.mesh.nodes)
        fr += [f * d for f in ph.mesh.fractions]
        end = None if n == len(keep) - 1 else -1  # the next phase starts where this one ends
        cat["t"].append(ph.t[:end])
        cat["x"].append(ph.x[:end])
        cat["costate"].append(ph.costate[:end])
        for k in ("t_control", "u", "hamiltonian", "switching"):
            cat[k].append(getattr(ph, k))
        pieces += list(ph.pieces)
    a = np.array(fr)
    mesh = Mesh(nodes=tuple(nodes), fractions=tuple((a / a.sum()).tolist()))
    samples = {k: (np.concatenate(v) if k in ("t", "t_control", "hamiltonian") else np.vstack(v)) for k, v in cat.items()}
    return OptimalControlSolution(
        success=bool(msol.success),
        status=int(msol.status),
        ipopt_status=str(getattr(msol, "ipopt_status", "")),
        message=f"switch times as free phase boundaries ({len(keep)} arcs): {msol.message}",
        nit=int(msol.nit),
        nfev=int(msol.nfev),
        objective=float(msol.objective),
        t0=float(pr.t0),
        tf=float(keep[-1].tf),
        method=keep[0].method,
        mesh=mesh,
        **samples,
        max_violation=float(msol.max_violation),
        build_s=float(getattr(msol, "build_s", 0.0)),
        solve_s=float(getattr(msol, "solve_s", 0.0)),
        problem=pr,
        pieces=tuple(pieces),
        dynamics_fun=keep[0].dynamics_fun,
        warm_start="switch-times",
        nlp=None,
    )


def _initial_meshes(mesh, n_phases: int, n_min: int) -> list[Mesh]:
    from adcskit.optimal_control._nlp import _as_mesh

    if mesh is None:
        return [Mesh.uniform(10, n_min + 1) for _ in range(n_phases)]
    if n_phases == 1 and (isinstance(mesh, Mesh) or (isinstance(mesh, tuple) and len(mesh) == 2 and all(isinstance(v, int) for v in mesh))):
        return [_as_mesh(mesh)]
    try:
        items = list(mesh)
    except TypeError:
        raise InputTypeError(f"mesh must be a Mesh, (n_intervals, n_nodes) or one per phase; got {mesh!r}") from None
    if len(items) != n_phases:
        raise InputError(f"mesh must give {n_phases} meshes (one per phase); got {len(items)}")
    return [_as_mesh(m) for m in items]


def symmetry_breaking_guess(problem: OptimalControlProblem, *, amplitude: float = 0.25) -> Guess:
    """Straight-line states (:func:`default_guess`) with deterministic, channel-distinct
    control perturbations.

    ``u_k(t) = u_mid,k + amplitude · r_k · sin(2π (k + 1) s + k)``, ``s = (t − t0)/(tf − t0)``,
    with ``r_k`` the half-range of finite bounds (else the control scale), clipped to the
    bounds. A guess with zero controls is symmetric; on problems such as the rigid-body
    reorientation the symmetric (eigenaxis) trajectory is a KKT point that IPOPT converges
    to; perturbing each channel differently starts away from it. Deterministic, so results
    are reproducible.

    Parameters
    ----------
    problem : OptimalControlProblem
    amplitude : float
        Perturbation as a fraction of the control half-range, in ``[0, 1]``.

    Returns
    -------
    Guess

    Examples
    --------
    >>> from adcskit.optimal_control import symmetry_breaking_guess
    >>> from adcskit.optimal_control.problems import double_integrator_min_time
    >>> g = symmetry_breaking_guess(double_integrator_min_time())
    >>> g.u.shape, bool(abs(g.u).max() <= 1.0)
    ((21, 1), True)
    """
    from adcskit._validation import check_range
    from adcskit.optimal_control.solve import default_guess

    if not isinstance(problem, OptimalControlProblem):
        raise InputTypeError(f"problem must be an OptimalControlProblem; got {type(problem).__name__}")
    amplitude = check_range("amplitude", amplitude, 0.0, 1.0)
    base = default_guess(problem)
    t = np.linspace(base.t[0], base.t[-1], 21)
    s = (t - t[0]) / (t[-1] - t[0])
    x = base.x[0] + s[:, None] * (base.x[1] - base.x[0])
    lo, hi = problem.control_lower, problem.control_upper
    _, su = problem.scales()
    fin = np.isfinite(lo) & np.isfinite(hi)
    mid = np.where(fin, 0.5 * (np.where(fin, lo, 0) + np.where(fin, hi, 0)), base.u[0])
    half = np.where(fin, 0.5 * (np.where(fin, hi, 0) - np.where(fin, lo, 0)), su)
    k = np.arange(problem.n_controls)
    u = mid + amplitude * half * np.sin(2 * np.pi * (k + 1) * s[:, None] + k)
    u = np.clip(u, lo, hi)
    return Guess(t=t, x=x, u=u, tf=base.tf)


def guess_from_function(fun, t0: float, tf: float, *, n_samples: int = 41) -> Guess:
    """An initial guess sampled from a user function ``fun(t) -> (x, u)``.

    Parameters
    ----------
    fun : callable
        ``fun(t)`` with ``t`` a time (s) returning the state ``(n_states,)`` and control
        ``(n_controls,)`` guesses.
    t0, tf : float
        Time span (s) of the guess.
    n_samples : int
        Samples (linearly interpolated onto the mesh by :func:`solve`).

    Returns
    -------
    Guess

    Examples
    --------
    >>> from adcskit.optimal_control import guess_from_function
    >>> g = guess_from_function(lambda t: ([t, 1.0], [0.0]), 0.0, 2.0, n_samples=3)
    >>> g.x[:, 0].tolist(), g.tf
    ([0.0, 1.0, 2.0], 2.0)
    """
    if not callable(fun):
        raise InputTypeError(f"fun must be callable t -> (x, u); got {fun!r}")
    n = check_int("n_samples", n_samples, minimum=2, maximum=1_000_000)
    a = check_finite("t0", t0)
    b = check_finite("tf", tf)
    if not b > a:
        raise InputError(f"tf must be > t0 (s); got t0 = {a:g}, tf = {b:g}")
    t = np.linspace(a, b, n)
    if not np.all(np.diff(t) > 0):
        raise InputError(f"tf - t0 = {b - a:g} s is too short to sample n_samples = {n} distinct increasing times; "
                         "allowed: a span that floating point resolves into n_samples points (e.g. >= 1e-9 s)")
    xs, us = [], []
    for tk in t:
        try:
            x, u = fun(tk)
        except (TypeError, ValueError) as exc:
            raise InputTypeError(f"fun(t) must return (x, u); got an error at t={tk}: {exc}") from None
        xs.append(np.atleast_1d(np.asarray(x, float)))
        us.append(np.atleast_1d(np.asarray(u, float)))
    return Guess(t=t, x=np.vstack(xs), u=np.vstack(us), tf=float(tf))
