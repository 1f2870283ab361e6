"""Robust (interval) Wahba problem of S0: min-max goal attainment, NSGA-II, worst case.

Interval model (S0 eqs. 3–4): every observation and reference vector is known only to lie
in a box, ``b_i = b_i^m + diag(α_i) b_i^r`` and ``r_i = r_i^m + diag(β_i) r_i^r`` with
``α_i, β_i ∈ [−1, 1]³`` (midpoint ``^m``, radius ``^r``), and both must stay unit vectors
(S0 eq. 5). Wahba's loss then splits (S0 eqs. 6–7, weights normalised to ``Σ a_i = 1``) into

* ``L^m(q) = 1 − qᵀ K^m q`` — the loss at the midpoints, and
* ``ΔL(q, α, β) = −qᵀ (K^{Δr} + K^{Δb} + K^{Δr,Δb}) q = −qᵀ K(B_Δ) q`` with
  ``B_Δ = Σ a_i (Δb_i r_i^{mT} + b_i^m Δr_iᵀ + Δb_i Δr_iᵀ)`` (``K`` is linear in ``B``).

Three solvers (registry :data:`ROBUST_METHODS`):

``"minmax"`` — the paper's goal attainment (S0 eq. 8 and the text before it): decision
    variables ``q, α, β``; ``min max(λ_1 |L^m − z_1*|, λ_2 |ΔL − z_2*|)`` with ``z* = 0``,
    ``λ = 1``, subject to ``|q| = 1``, the unit-norm constraints of S0 eq. 5, ``α, β ∈
    [−1, 1]``, and ``q`` inside ``q_TRIAD ± search_range·|q_TRIAD|`` (the paper's "search
    range 10 % of the initial population", componentwise). Solved as the epigraph problem
    ``min γ  s.t.  L^m ≤ γ, ±ΔL ≤ γ`` by a dedicated two-stage solver:

    1. *Closed form.* With the midpoints normalised, ``α = β = 0`` satisfies eq. 5 and gives
       ``ΔL = 0``; and ``γ ≥ L^m(q) ≥ L^m(q_opt)`` for every feasible point, where
       ``q_opt`` is Davenport's eigenvector. So when ``q_opt`` lies in the search box the
       point ``(q_opt, 0, 0, γ = L^m(q_opt))`` is the *global* optimum — no iteration.
    2. Otherwise the box is active and SLSQP solves ``min 1 − qᵀK^m q`` on the unit sphere
       inside the box (4 variables, analytic gradients).

    ``solver="slsqp"`` skips stage 1 and runs SLSQP on the full epigraph problem in
    ``(q, α, β, γ)`` from the TRIAD start, as the paper does with MATLAB's ``fminimax``; the
    tests check both give the same attitude. **Consequence, stated plainly:** as printed,
    the paper's min-max problem *is* the q-method restricted to the search box; it cannot
    beat the q-method by using the intervals. See ``docs/studies/wahba-table1.md``.

``"nsga2"`` — pymoo's NSGA-II on the two objectives ``{L^m, ΔL}`` over ``x = (q, α, β)``
    with the same search box (the authors' earlier approach, S0 ref. 29). ``q`` is
    normalised inside the objectives and eq. 5 is enforced by normalising
    ``b^m + diag(α) b^r`` (the direction of a box point). ``delta="signed"`` (default for
    NSGA-II) minimises ``ΔL`` itself; ``delta="abs"`` minimises ``|ΔL|`` as the goal
    attainment does — with ``abs`` the front collapses to the q-method point. The returned
    point is chosen from the final Pareto set by ``select``: ``"knee"`` (truth-free:
    largest distance to the chord between the normalised extreme points) or a callable
    ``select(F, Q) -> index`` (e.g. the paper's pick by the true attitude, which is *not*
    deployable).

``"worst-case"`` — the robust formulation of Ahmed & Kerrigan (2011, S0 ref. 18):
    ``min_q max_{α,β} L(q, α, β)``. The inner maximum separates per observation into
    ``a_i (1 − min cos∠(b_i, A r_i))`` over the cones spanned by the two boxes (a superset
    of the box ∩ sphere of eq. 5, so the solution is conservative). ``b ↦ cos∠(b, u)`` is
    quasi-concave where ``b·u > 0`` (its super-level sets are convex cones), so the minimum
    over a box is at a vertex: 8 × 8 vertex pairs per observation. The outer problem
    ``min Σ a_i t_i  s.t.  t_i ≥ 1 − qᵀ K(b̂_ij r̂_ikᵀ) q, |q| = 1`` is solved by SLSQP from
    the q-method start. If a vertex pair is ≥ 90° apart the vertex argument no longer holds
    and the message says so.

Hand-written because no library solves these formulations; the optimisers themselves are
scipy's SLSQP and pymoo's NSGA-II.

References
----------
.. [1] S0: Ghadiri et al., robust optimal attitude determination based on min-max
   optimisation (interval analysis), eqs. 3–8, Table 1.
.. [2] Ahmed, S. and Kerrigan, E. C., "Robust static attitude determination via robust
   optimization", IFAC Proc. 44(1), 5807–5812, 2011.
.. [3] Deb, K. et al., "A fast and elitist multiobjective genetic algorithm: NSGA-II",
   IEEE TEC 6(2), 2002.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.optimize import minimize

from adcskit._results import Result
from adcskit._validation import as_array, as_rng, check_choice, check_int, check_positive
from adcskit.determination._box import box_sphere_max
from adcskit.determination.wahba import _k_from, solve_wahba
from adcskit.errors import InputError, InputTypeError

__all__ = ["ROBUST_METHODS", "RobustWahbaResult", "robust_wahba", "interval_objectives"]


@dataclass(frozen=True, slots=True, repr=False)
class RobustWahbaResult(Result):
    """Solution of one robust (interval) Wahba problem.

    Attributes
    ----------
    q : ndarray (4,)
        Chosen attitude quaternion (scalar last, ``b ≈ A(q) r``, ``q4 >= 0``).
    alpha, beta : ndarray (n, 3)
        Interval coefficients of the chosen point (body, reference). For ``worst-case``:
        the worst-case vertex coefficients at ``q``.
    fun : ndarray (2,)
        ``[L^m(q), ΔL(q, α, β)]`` at the chosen point (S0 eq. 7).
    objective : float
        Value of the method's own objective (min-max ``γ``; worst-case loss; NSGA-II: ``L^m``).
    pareto_q : ndarray (k, 4)
        NSGA-II: the Pareto set's attitudes; other methods: ``q[None]``.
    pareto_f : ndarray (k, 2)
        NSGA-II: the Pareto front ``{L^m, ΔL}``; other methods: ``fun[None]``.
    success : bool
    status : int
        0 success, 1 optimiser did not converge, 2 vertex argument of the worst case not valid.
    message : str
    nit, nfev : int
        Iterations (generations) and objective evaluations.
    method : str

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.determination import robust_wahba
    >>> mid = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    >>> res = robust_wahba(mid, 0.01, mid, 0.0)
    >>> type(res).__name__, res.success, res.q.shape, res.fun.shape, res.pareto_f.shape
    ('RobustWahbaResult', True, (4,), (2,), (1, 2))
    """

    q: np.ndarray
    alpha: np.ndarray
    beta: np.ndarray
    fun: np.ndarray
    objective: float
    pareto_q: np.ndarray
    pareto_f: np.ndarray
    success: bool
    status: int
    message: str
    nit: int
    nfev: int
    method: str


# ----------------------------------------------------------------------------- helpers


def _kmat(B: np.ndarray) -> np.ndarray:
    """Davenport K of one or many B (..., 3, 3) (linear in B)."""
    sig = np.trace(B, axis1=-2, axis2=-1)
    K = np.empty(B.shape[:-2] + (4, 4))
    K[..., :3, :3] = B + np.swapaxes(B, -1, -2) - sig[..., None, None] * np.eye(3)
    z = np.stack(
        [B[..., 1, 2] - B[..., 2, 1], B[..., 2, 0] - B[..., 0, 2], B[..., 0, 1] - B[..., 1, 0]],
        axis=-1,
    )
    K[..., :3, 3] = z
    K[..., 3, :3] = z
    K[..., 3, 3] = sig
    return K


@dataclass(frozen=True, slots=True)
class _Problem:
    bm: np.ndarray  # (n, 3) unit midpoints
    br: np.ndarray  # (n, 3) radii (scaled with the midpoints)
    rm: np.ndarray
    rr: np.ndarray
    a: np.ndarray  # (n,) weights, sum 1
    wsum: float
    Km: np.ndarray  # (4, 4)


def _problem(body_mid, body_radius, ref_mid, ref_radius, weights) -> _Problem:
    bm = as_array("body_mid", body_mid)
    rm = as_array("ref_mid", ref_mid)
    if bm.ndim != 2 or bm.shape[1] != 3 or bm.shape[0] < 2:
        raise InputError(f"body_mid must have shape (n, 3) with n >= 2; got shape {bm.shape}")
    if rm.shape != bm.shape:
        raise InputError(f"ref_mid must have the shape of body_mid {bm.shape}; got {rm.shape}")
    n = bm.shape[0]
    radii = []
    for name, val in (("body_radius", body_radius), ("ref_radius", ref_radius)):
        rad = as_array(name, val)
        try:
            rad = np.broadcast_to(rad, (n, 3)).copy()
        except ValueError:
            raise InputError(f"{name} must broadcast to shape ({n}, 3); got shape {rad.shape}") from None
        if np.any(rad < 0):
            raise InputError(f"{name} must be >= 0 (interval radii); got {rad.min():g}")
        radii.append(rad)
    nb = np.linalg.norm(bm, axis=1)
    nr = np.linalg.norm(rm, axis=1)
    if np.any(nb == 0) or np.any(nr == 0):
        raise InputError("body_mid and ref_mid must not contain zero-length vectors")
    if weights is None:
        w = np.ones(n)
    else:
        w = as_array("weights", weights, shape=(n,))
        if np.any(w <= 0):
            raise InputError(f"weights must be > 0; got {w.min():g}")
    a = w / w.sum()
    bmu = bm / nb[:, None]
    rmu = rm / nr[:, None]
    for name, u in (("body_mid", bmu), ("ref_mid", rmu)):
        # the attitude is unobservable from parallel directions, whatever the start point
        if np.abs(np.cross(u[:, None, :], u[None, :, :])).max() < 1e-9:
            raise InputError(f"{name} vectors must not all be parallel (the attitude about their "
                             f"common axis is undetermined); got shape {u.shape} of collinear vectors")
    Km = _kmat(np.einsum("n,ni,nj->ij", a, bmu, rmu))
    return _Problem(bm=bmu, br=radii[0] / nb[:, None], rm=rmu, rr=radii[1] / nr[:, None], a=a,
                    wsum=float(w.sum()), Km=Km)


def _objectives(p: _Problem, q: np.ndarray, alpha: np.ndarray, beta: np.ndarray, *, normalise: bool):
    """(L^m, ΔL) for one q (4,) and α, β (n, 3) — S0 eq. 7."""
    db = alpha * p.br
    dr = beta * p.rr
    if normalise:  # eq. 5 by renormalisation (NSGA-II)
        b = p.bm + db
        r = p.rm + dr
        b = b / np.linalg.norm(b, axis=-1, keepdims=True)
        r = r / np.linalg.norm(r, axis=-1, keepdims=True)
        db = b - p.bm
        dr = r - p.rm
    Bd = np.einsum("n,ni,nj->ij", p.a, db, p.rm) + np.einsum("n,ni,nj->ij", p.a, p.bm, dr) + np.einsum(
        "n,ni,nj->ij", p.a, db, dr
    )
    Lm = 1.0 - q @ p.Km @ q
    dL = -(q @ _kmat(Bd) @ q)
    return Lm, dL


def interval_objectives(q, alpha, beta, body_mid, body_radius, ref_mid, ref_radius, weights=None):
    """``(L^m, ΔL)`` of S0 eq. 7 at ``q`` (4,) and interval coefficients ``α, β`` (n, 3).

    Midpoints are normalised (radii scaled with them), weights normalised to sum 1.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.determination import interval_objectives
    >>> mid = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    >>> Lm, dL = interval_objectives([0.0, 0.0, 0.0, 1.0], np.zeros((2, 3)), np.zeros((2, 3)),
    ...                              mid, 0.01, mid, 0.0)
    >>> round(float(Lm), 12), round(float(dL), 12) + 0.0   # exact midpoints, zero coefficients
    (0.0, 0.0)
    """
    p = _problem(body_mid, body_radius, ref_mid, ref_radius, weights)
    qa = as_array("q", q, shape=(4,))
    if not np.linalg.norm(qa / max(np.abs(qa).max(), 1e-300)) > 0 or np.abs(qa).max() < 1e-150:
        raise InputError(f"q must be a non-zero quaternion; got {qa.tolist()}")
    qa = qa / np.linalg.norm(qa)
    n = p.bm.shape[0]
    al = as_array("alpha", alpha, shape=(n, 3))
    be = as_array("beta", beta, shape=(n, 3))
    Lm, dL = _objectives(p, qa, al, be, normalise=False)
    return float(Lm), float(dL)


def _canon(q: np.ndarray) -> np.ndarray:
    q = q / np.linalg.norm(q)
    return -q if q[3] < 0 else q


def _start_box(p: _Problem, search_range: float | None, q0: np.ndarray | None = None):
    """TRIAD start (or the caller's ``q0``) and the ±search_range box around it (S0 §4-1)."""
    if q0 is None:
        q0 = solve_wahba(p.bm, p.rm, p.a, method="triad").q
    if search_range is None:
        return q0, -np.ones(4), np.ones(4)
    half = search_range * np.abs(q0)
    return q0, q0 - half, q0 + half


def _in_box(q, lb, ub) -> bool:
    return bool(np.all(q >= lb - 1e-15) and np.all(q <= ub + 1e-15))


# ----------------------------------------------------------------------------- min-max


def _minmax(p: _Problem, search_range, solver: str, delta: str, maxiter: int, q0=None):
    n = p.bm.shape[0]
    q_start, lb, ub = _start_box(p, search_range, q0)
    zeros = np.zeros((n, 3))
    if solver == "closed-form":
        w, v = np.linalg.eigh(p.Km)
        q_opt = v[:, 3]
        if q_opt @ q_start < 0:  # the box is around the TRIAD sign
            q_opt = -q_opt
        if _in_box(q_opt, lb, ub):
            Lm = max(1.0 - w[3], 0.0)
            return q_opt, zeros, zeros, Lm, 0, 0, 1, "global optimum: q-method point inside the search box"
        # box active: min L^m(q) = max qᵀK^m q on the sphere inside the box, solved exactly
        # by enumerating the KKT active sets (adcskit.determination._box)
        qb = np.empty(4)
        val = box_sphere_max(p.Km, lb, ub, qb)
        if np.isfinite(val):
            return qb, zeros, zeros, max(1.0 - val, 0.0), 0, 1, 81, (
                "search box active: optimum on the box boundary (KKT active-set enumeration)"
            )
        return q_start, zeros, zeros, float(1.0 - q_start @ p.Km @ q_start), 1, 1, 81, (
            "no feasible point of the unit sphere inside the search box"
        )
    # full epigraph problem x = (q 4, α 3n, β 3n, γ)
    m = 3 * n

    def split(x):
        return x[:4], x[4 : 4 + m].reshape(n, 3), x[4 + m : 4 + 2 * m].reshape(n, 3), x[-1]

    def cons_ineq(x):
        q, al, be, g = split(x)
        Lm, dL = _objectives(p, q, al, be, normalise=False)
        if delta == "abs":
            return np.array([g - Lm, g - dL, g + dL])
        return np.array([g - Lm, g - dL])

    def cons_eq(x):
        q, al, be, _ = split(x)
        b = p.bm + al * p.br
        r = p.rm + be * p.rr
        return np.concatenate([[q @ q - 1.0], np.sum(b * b, 1) - 1.0, np.sum(r * r, 1) - 1.0])

    x0 = np.concatenate([q_start, np.zeros(2 * m), [1.0 - q_start @ p.Km @ q_start]])
    bounds = list(zip(lb, ub)) + [(-1.0, 1.0)] * (2 * m) + [(None, None)]
    c = np.zeros_like(x0)
    c[-1] = 1.0
    res = minimize(
        lambda x: x[-1],
        x0,
        jac=lambda x: c,
        method="SLSQP",
        bounds=bounds,
        constraints=[{"type": "ineq", "fun": cons_ineq}, {"type": "eq", "fun": cons_eq}],
        options={"maxiter": maxiter, "ftol": 1e-12},
    )
    q, al, be, g = split(res.x)
    return q / np.linalg.norm(q), al.copy(), be.copy(), float(g), 0 if res.success else 1, int(
        res.nit
    ), int(res.nfev), str(res.message)


# ----------------------------------------------------------------------------- NSGA-II


def _knee(F: np.ndarray) -> int:
    """Knee of a 2-D front: max distance to the chord between the normalised extremes."""
    if len(F) <= 2:
        Fn = (F - F.min(0)) / np.where(np.ptp(F, 0) > 0, np.ptp(F, 0), 1.0)
        return int(np.argmin(np.linalg.norm(Fn, axis=1)))
    span = np.ptp(F, 0)
    Fn = (F - F.min(0)) / np.where(span > 0, span, 1.0)
    i0 = int(np.argmin(Fn[:, 0]))
    i1 = int(np.argmin(Fn[:, 1]))
    d = Fn[i1] - Fn[i0]
    nd = np.linalg.norm(d)
    if nd == 0:
        return i0
    rel = Fn - Fn[i0]
    dist = np.abs(rel[:, 0] * d[1] - rel[:, 1] * d[0]) / nd
    return int(np.argmax(dist))


def _nsga2(p: _Problem, search_range, delta, pop_size, n_gen, select, rng, q0=None):
    try:
        from pymoo.algorithms.moo.nsga2 import NSGA2
        from pymoo.core.problem import Problem
        from pymoo.optimize import minimize as pymoo_minimize
    except ImportError as exc:  # pragma: no cover - pymoo is a dependency
        from adcskit.errors import SolverError

        raise SolverError(f"method 'nsga2' needs pymoo: {exc}") from None
    n = p.bm.shape[0]
    m = 3 * n
    q_start, lb, ub = _start_box(p, search_range, q0)
    xl = np.concatenate([np.minimum(lb, ub), -np.ones(2 * m)])
    xu = np.concatenate([np.maximum(lb, ub), np.ones(2 * m)])
    xu = np.where(xu - xl < 1e-12, xl + 1e-12, xu)

    def evaluate(X):
        q = X[:, :4] / np.linalg.norm(X[:, :4], axis=1, keepdims=True)
        al = X[:, 4 : 4 + m].reshape(-1, n, 3)
        be = X[:, 4 + m :].reshape(-1, n, 3)
        b = p.bm + al * p.br
        r = p.rm + be * p.rr
        b = b / np.linalg.norm(b, axis=-1, keepdims=True)
        r = r / np.linalg.norm(r, axis=-1, keepdims=True)
        Kt = _k_from(b, r, np.broadcast_to(p.a, (len(X), n)))
        Lm = 1.0 - np.einsum("ki,ij,kj->k", q, p.Km, q)
        dL = -np.einsum("ki,kij,kj->k", q, Kt - p.Km, q)
        return np.column_stack([Lm, np.abs(dL) if delta == "abs" else dL]), q

    class _P(Problem):
        def __init__(self):
            super().__init__(n_var=4 + 2 * m, n_obj=2, xl=xl, xu=xu)

        def _evaluate(self, X, out, *args, **kwargs):
            out["F"] = evaluate(X)[0]

    seed = int(rng.integers(2**31 - 1))
    # initial population: TRIAD (the paper's start) plus uniform samples of the box
    from pymoo.core.population import Population

    X0 = xl + (xu - xl) * rng.random((pop_size, len(xl)))
    X0[0, :4] = np.clip(q_start, xl[:4], xu[:4])
    X0[0, 4:] = 0.0
    algo = NSGA2(pop_size=pop_size, sampling=Population.new(X=X0))
    res = pymoo_minimize(_P(), algo, ("n_gen", n_gen), seed=seed, verbose=False)
    X = np.atleast_2d(res.X)
    F, Q = evaluate(X)
    Q = np.array([_canon(q) for q in Q])
    if select == "knee":
        k = _knee(F)
    else:
        k = int(select(F.copy(), Q.copy()))
        if not 0 <= k < len(F):
            raise InputError(f"select callback must return an index in [0, {len(F)}); got {k}")
    al = X[k, 4 : 4 + m].reshape(n, 3)
    be = X[k, 4 + m :].reshape(n, 3)
    return Q[k], al.copy(), be.copy(), F[k], Q, F, int(res.algorithm.n_gen), int(res.algorithm.evaluator.n_eval)


# ----------------------------------------------------------------------------- worst case


_SIGNS = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float)


def _worst_case(p: _Problem, maxiter: int):
    n = p.bm.shape[0]
    bv = p.bm[:, None, :] + _SIGNS[None] * p.br[:, None, :]  # (n, 8, 3)
    rv = p.rm[:, None, :] + _SIGNS[None] * p.rr[:, None, :]
    nbv = np.linalg.norm(bv, axis=-1, keepdims=True)
    nrv = np.linalg.norm(rv, axis=-1, keepdims=True)
    if np.any(nbv == 0) or np.any(nrv == 0):
        return None
    bv = bv / nbv
    rv = rv / nrv
    # K of every vertex pair: (n, 64, 4, 4); cos∠(b, A r) = qᵀ K(b rᵀ) q
    Bp = bv[:, :, None, :, None] * rv[:, None, :, None, :]  # (n, 8, 8, 3, 3)
    Kp = _kmat(Bp).reshape(n, 64, 4, 4)
    q0 = solve_wahba(p.bm, p.rm, p.a, method="q-method").q

    def cosines(q):
        return np.einsum("i,nkij,j->nk", q, Kp, q)

    t0 = 1.0 - cosines(q0).min(axis=1)
    x0 = np.concatenate([q0, t0])

    def cons(x):
        q, t = x[:4], x[4:]
        return (t[:, None] - 1.0 + cosines(q)).ravel()

    def cons_jac(x):
        q = x[:4]
        J = np.zeros((n, 64, 4 + n))
        J[:, :, :4] = 2.0 * np.einsum("nkij,j->nki", Kp, q)
        for i in range(n):
            J[i, :, 4 + i] = 1.0
        return J.reshape(n * 64, 4 + n)

    c = np.concatenate([np.zeros(4), p.a])
    res = minimize(
        lambda x: c @ x,
        x0,
        jac=lambda x: c,
        method="SLSQP",
        constraints=[
            {"type": "ineq", "fun": cons, "jac": cons_jac},
            {"type": "eq", "fun": lambda x: x[:4] @ x[:4] - 1.0, "jac": lambda x: np.concatenate([2 * x[:4], np.zeros(n)])},
        ],
        options={"maxiter": maxiter, "ftol": 1e-14},
    )
    q = _canon(res.x[:4])
    cs = cosines(q)
    worst = cs.argmin(axis=1)
    jb, kr = np.divmod(worst, 8)
    alpha = _SIGNS[jb] * (p.br > 0)
    beta = _SIGNS[kr] * (p.rr > 0)
    valid = bool(cs.min() > 0)
    return q, alpha, beta, float(np.sum(p.a * (1.0 - cs.min(axis=1)))), res, valid


# ----------------------------------------------------------------------------- front end

ROBUST_METHODS: dict[str, str] = {
    "minmax": "S0 goal attainment min max(|L^m|, |ΔL|), z* = 0, λ = 1 (closed form + SLSQP)",
    "nsga2": "pymoo NSGA-II Pareto set of {L^m, ΔL}; knee or callback selection",
    "worst-case": "Ahmed & Kerrigan: min over q of the worst-case loss over the interval boxes",
}


def robust_wahba(
    body_mid: Any,
    body_radius: Any,
    ref_mid: Any,
    ref_radius: Any,
    weights: Any = None,
    method: str = "minmax",
    *,
    search_range: float | None = 0.1,
    q0: Any = None,
    solver: str = "closed-form",
    delta: str | None = None,
    pop_size: int = 100,
    n_gen: int = 100,
    select: str | Callable[[np.ndarray, np.ndarray], int] = "knee",
    maxiter: int = 200,
    rng: Any = None,
) -> RobustWahbaResult:
    """Solve the robust interval Wahba problem of S0 (eqs. 3–8) for one epoch.

    Parameters
    ----------
    body_mid, ref_mid : array_like (n, 3)
        Interval midpoints of the body observations and reference vectors (normalised here;
        the radii are scaled with them), ``n >= 2``.
    body_radius, ref_radius : array_like, broadcastable to (n, 3)
        Componentwise interval radii (>= 0), same units as the midpoints.
    weights : array_like (n,), optional
        Positive weights (normalised to sum 1, as S0 assumes). Default equal.
    method : {"minmax", "nsga2", "worst-case"}
        See the module docstring.
    search_range : float or None
        Half-width of the box around the TRIAD quaternion, relative to each component
        (S0: 0.1). ``None``: no box. Used by ``minmax`` and ``nsga2``.
    q0 : array_like (4,), optional
        Centre of the search box and start point (default: TRIAD of the midpoints, as in
        S0), e.g. the previous epoch's estimate. Scalar last.
    solver : {"closed-form", "slsqp"}
        ``minmax`` only: the closed-form-aware solver (default) or SLSQP on the full
        epigraph problem in ``(q, α, β, γ)``.
    delta : {"abs", "signed"}, optional
        How ``ΔL`` enters: ``|ΔL|`` (goal attainment as printed; default for ``minmax``) or
        ``ΔL`` (default for ``nsga2``).
    pop_size, n_gen : int
        NSGA-II population and generations.
    select : "knee" or callable
        NSGA-II pick from the Pareto set: ``"knee"`` or ``select(F, Q) -> index`` with
        ``F`` (k, 2) objectives and ``Q`` (k, 4) quaternions.
    maxiter : int
        SLSQP iteration limit.
    rng : None, int or Generator
        Seed of NSGA-II (``None`` → seed 0).

    Returns
    -------
    RobustWahbaResult
        ``success=False`` with a message when the optimiser did not converge.

    References
    ----------
    S0 eqs. 3–8 and §4-1; Ahmed & Kerrigan 2011; Deb et al. 2002.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.attitude import error_angle
    >>> from adcskit.determination import robust_wahba
    >>> ref = np.array([[1.0, 0.0, 0.0], [0.0, 0.6, 0.8]])
    >>> body = ref + np.array([[0.0, 0.01, 0.0], [0.01, 0.0, 0.0]])   # measured with small errors
    >>> res = robust_wahba(body, 0.02, ref, 0.0, method="minmax")
    >>> res.success, res.q.shape, res.fun.shape
    (True, (4,), (2,))
    >>> bool(np.degrees(error_angle(res.q, [0.0, 0.0, 0.0, 1.0])) < 2.0)
    True
    >>> nsga = robust_wahba(body, 0.02, ref, 0.0, method="nsga2", pop_size=12, n_gen=5, rng=1)
    >>> nsga.pareto_f.shape[1], nsga.q.shape
    (2, (4,))
    """
    if not isinstance(method, str):
        raise InputTypeError(f"method must be a string; got {method!r}")
    check_choice("method", method, ROBUST_METHODS)
    check_choice("solver", solver, ("closed-form", "slsqp"))
    if delta is None:
        delta = "signed" if method == "nsga2" else "abs"
    check_choice("delta", delta, ("abs", "signed"))
    if search_range is not None:
        search_range = check_positive("search_range", search_range)
    pop_size = check_int("pop_size", pop_size, minimum=4)
    n_gen = check_int("n_gen", n_gen, minimum=1)
    maxiter = check_int("maxiter", maxiter, minimum=1)
    gen = as_rng(rng)  # checked for every method, though only NSGA-II draws from it
    if not (select == "knee" or callable(select)):
        raise InputError(f"select must be 'knee' or a callable select(F, Q) -> index; got {select!r}")
    p = _problem(body_mid, body_radius, ref_mid, ref_radius, weights)
    n = p.bm.shape[0]
    if q0 is not None:
        q0 = as_array("q0", q0, shape=(4,))
        if not np.linalg.norm(q0) > 0:
            raise InputError("q0 must be a non-zero quaternion")
        q0 = q0 / np.linalg.norm(q0)
    if method == "minmax":
        q, al, be, g, status, nit, nfev, msg = _minmax(p, search_range, solver, delta, maxiter, q0)
        q = _canon(q)
        fun = np.array(_objectives(p, q, al, be, normalise=False))
        return RobustWahbaResult(
            q=q, alpha=al, beta=be, fun=fun, objective=g, pareto_q=q[None], pareto_f=fun[None],
            success=status == 0, status=status, message=msg, nit=nit, nfev=nfev, method=method,
        )
    if method == "nsga2":
        q, al, be, f, Q, F, nit, nfev = _nsga2(p, search_range, delta, pop_size, n_gen, select, gen, q0)
        return RobustWahbaResult(
            q=q, alpha=al, beta=be, fun=np.asarray(f, float), objective=float(f[0]), pareto_q=Q,
            pareto_f=F, success=True, status=0,
            message=f"NSGA-II: {len(F)} Pareto points after {nit} generations",
            nit=nit, nfev=nfev, method=method,
        )
    out = _worst_case(p, maxiter)
    if out is None:
        zeros = np.zeros((n, 3))
        nanq = np.full(4, np.nan)
        return RobustWahbaResult(
            q=nanq, alpha=zeros, beta=zeros, fun=np.full(2, np.nan), objective=np.nan,
            pareto_q=nanq[None], pareto_f=np.full((1, 2), np.nan), success=False, status=1,
            message="an interval box contains the zero vector: direction undefined", nit=0, nfev=0,
            method=method,
        )
    q, al, be, wc, res, valid = out
    fun = np.array(_objectives(p, q, al, be, normalise=True))
    status = 0 if res.success else 1
    msg = str(res.message)
    if not valid:
        status = 2
        msg = "a worst-case vertex pair is >= 90 deg apart: vertex enumeration may underestimate the worst case"
    return RobustWahbaResult(
        q=q, alpha=al, beta=be, fun=fun, objective=wc, pareto_q=q[None], pareto_f=fun[None],
        success=status == 0, status=status, message=msg, nit=int(res.nit), nfev=int(res.nfev),
        method=method,
    )
