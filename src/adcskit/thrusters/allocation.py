"""Thruster force allocation: ``M = A F`` with ``0 <= F <= F_max``, batched over demands.

Methods (registry :data:`ALLOCATION_METHODS`):

``pinv-redistribute``
    S3's allocation: the pseudo-inverse ``F = A^T (A A^T)^-1 M`` (S3 eq. 12), then the
    thrusters that come out negative or above ``F_max`` are fixed at the violated bound and
    the remaining torque is handed to the other thrusters by the pseudo-inverse of the free
    columns, until no bound is violated (the redistributed pseudo-inverse of S3 ref. [14],
    Jin 2005). S3 describes it for symmetric layouts ("negative demands are supplied by the
    opposite thrusters"); for an opposite pair ``a_j = -a_i`` this is exactly what the
    iteration does, and it also defines the method for any layout. Fast and vectorised, but
    neither exact nor fuel-optimal in general: it may stop with a torque error although a
    feasible allocation exists.
``nnls``
    Bounded least squares ``min ||A F - M||_2, 0 <= F <= F_max``
    (:func:`scipy.optimize.lsq_linear`, method ``bvls``). Exact whenever the demand is
    feasible; not fuel-optimal.
``lp-min-fuel``
    ``min sum F`` s.t. ``A F = M``, ``0 <= F <= F_max`` (:func:`scipy.optimize.linprog`,
    HiGHS). Fuel is proportional to ``sum F`` (S3 eq. 6-7). When the demand is infeasible
    the torque error is minimised first: the bounded least-squares torque ``T* = A F_ls`` is
    unique, and the LP then finds the least-fuel forces producing ``T*``.

Hand-written here: the redistribution loop (no library offers the method), as a numba kernel
over plain arrays so that a whole GA/DE population x all demands is allocated in one call;
its 3x3 pseudo-inverse is a cyclic Jacobi eigen-solve (a LAPACK call per 3x3 costs more
than the whole solve).

References
----------
S3 eq. 5, 12, 13 and §3. Jin J., "Modified pseudoinverse redistribution methods for
redundant controls allocation", JGCD 28(5), 2005 (S3 ref. [14]).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numba
import numpy as np
from scipy.optimize import linprog, lsq_linear

from adcskit._results import Result
from adcskit._validation import as_array, as_batch, check_choice, check_positive_array

__all__ = ["AllocationResult", "ALLOCATION_METHODS", "allocate"]


@dataclass(frozen=True, slots=True, repr=False, kw_only=True)
class AllocationResult(Result):
    """Forces allocated to the thrusters for one or many torque demands.

    Shapes follow the demand: ``(3,)`` gives ``x`` of shape ``(n,)``; ``(N, 3)`` gives
    ``(N, n)``.

    Attributes
    ----------
    x : ndarray, N
        Thruster forces, within ``[0, f_max]``.
    torque : ndarray, N m
        Achieved torque ``A x``.
    error : ndarray, N m
        ``||M - A x||_2`` per demand (S3 eq. 15, as a norm).
    feasible : ndarray of bool
        Demand met to ``1e-9`` relative (``error <= 1e-9 ||M|| + 1e-14 ||A|| f_max``).
    success : bool
        The solver ran on every demand (an unreachable demand is not a failure: see
        ``feasible``).
    status : ndarray of int
        0 exact, 1 torque error left, 2 solver failure.
    message : str
    method : str
    nit : int
        Redistribution passes (``pinv-redistribute``) or solver calls.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import ThrusterSet
    >>> r = [[1, 0, 0], [1, 0, 0], [0, 1, 0], [0, 1, 0], [0, 0, 1], [0, 0, 1]]     # m
    >>> d = [[0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0]]  # +-z +-x +-y
    >>> ts = ThrusterSet(positions=np.array(r, float), directions=np.array(d, float), f_max=10.0)
    >>> from adcskit.thrusters import allocate
    >>> res = allocate(ts, [0.0, 0.0, 5.0])
    >>> type(res).__name__, res.success, bool(res.feasible), res.x.shape
    ('AllocationResult', True, True, (6,))
    >>> res.torque.round(9) + 0.0
    array([0., 0., 5.])
    """

    x: np.ndarray
    torque: np.ndarray
    error: np.ndarray
    feasible: np.ndarray
    success: bool
    status: np.ndarray
    message: str
    method: str
    nit: int


# ----------------------------------------------------------------------------- kernels


@numba.njit(cache=True)
def _sym3_pinv_apply(S: np.ndarray, r: np.ndarray, y: np.ndarray) -> None:
    """``y = S^+ r`` for a symmetric PSD 3x3 ``S``.

    Cholesky when every pivot exceeds ``1e-8 trace(S)`` (then ``S^+ = S^-1``), otherwise a
    cyclic Jacobi eigen-solve with relative cut-off 1e-12. Jacobi rotations are accurate to machine precision for symmetric matrices and cost a
    few hundred flops here, far less than a LAPACK call per 3x3 matrix.
    """
    # well-conditioned (the common case): Cholesky, ~30 flops
    tr = S[0, 0] + S[1, 1] + S[2, 2]
    l00 = S[0, 0]
    if l00 > 1e-8 * tr:
        l00 = np.sqrt(l00)
        l10 = S[1, 0] / l00
        l20 = S[2, 0] / l00
        d1 = S[1, 1] - l10 * l10
        if d1 > 1e-8 * tr:
            l11 = np.sqrt(d1)
            l21 = (S[2, 1] - l20 * l10) / l11
            d2 = S[2, 2] - l20 * l20 - l21 * l21
            if d2 > 1e-8 * tr:
                l22 = np.sqrt(d2)
                z0 = r[0] / l00
                z1 = (r[1] - l10 * z0) / l11
                z2 = (r[2] - l20 * z0 - l21 * z1) / l22
                y[2] = z2 / l22
                y[1] = (z1 - l21 * y[2]) / l11
                y[0] = (z0 - l10 * y[1] - l20 * y[2]) / l00
                return
    a = S.copy()
    V = np.eye(3)
    for _sweep in range(30):
        off = a[0, 1] ** 2 + a[0, 2] ** 2 + a[1, 2] ** 2
        scale = a[0, 0] ** 2 + a[1, 1] ** 2 + a[2, 2] ** 2
        if off <= 1e-32 * scale or off == 0.0:
            break
        for p in range(2):
            for q in range(p + 1, 3):
                apq = a[p, q]
                if apq == 0.0:
                    continue
                theta = (a[q, q] - a[p, p]) / (2.0 * apq)
                t = (1.0 if theta >= 0 else -1.0) / (abs(theta) + np.sqrt(theta * theta + 1.0))
                c = 1.0 / np.sqrt(t * t + 1.0)
                s = t * c
                for k in range(3):
                    akp = a[k, p]
                    akq = a[k, q]
                    a[k, p] = c * akp - s * akq
                    a[k, q] = s * akp + c * akq
                for k in range(3):
                    apk = a[p, k]
                    aqk = a[q, k]
                    a[p, k] = c * apk - s * aqk
                    a[q, k] = s * apk + c * aqk
                for k in range(3):
                    vkp = V[k, p]
                    vkq = V[k, q]
                    V[k, p] = c * vkp - s * vkq
                    V[k, q] = s * vkp + c * vkq
    wmax = max(a[0, 0], a[1, 1], a[2, 2])
    y[:] = 0.0
    if wmax <= 0.0:
        return
    for k in range(3):
        w = a[k, k]
        if w > 1e-12 * wmax:
            proj = (V[0, k] * r[0] + V[1, k] * r[1] + V[2, k] * r[2]) / w
            for i in range(3):
                y[i] += proj * V[i, k]


@numba.njit(cache=True)
def _rpi_one(A: np.ndarray, m: np.ndarray, fmax: np.ndarray, F: np.ndarray) -> int:
    """Redistributed pseudo-inverse for one demand; writes ``F``, returns the passes used.

    Each pass solves ``F_free = pinv(A_free) (m - A_fixed F_fixed)`` through
    ``pinv(A W) = W A^T (A W A^T)^+`` and fixes every free thruster that violates a bound at
    that bound; it stops when no bound is violated or no thruster is free.
    """
    n = A.shape[1]
    free = np.ones(n, dtype=np.bool_)
    S = np.empty((3, 3))
    r = np.empty(3)
    y = np.empty(3)
    for j in range(n):
        F[j] = 0.0
    passes = 0
    for _ in range(n + 1):
        passes += 1
        S[:, :] = 0.0
        for i in range(3):
            r[i] = m[i]
        nfree = 0
        for j in range(n):
            if free[j]:
                nfree += 1
                for i in range(3):
                    for k in range(3):
                        S[i, k] += A[i, j] * A[k, j]
            else:
                for i in range(3):
                    r[i] -= A[i, j] * F[j]
        if nfree == 0:
            break
        _sym3_pinv_apply(S, r, y)
        any_viol = False
        for j in range(n):
            if free[j]:
                f = A[0, j] * y[0] + A[1, j] * y[1] + A[2, j] * y[2]
                if f < 0.0:
                    F[j] = 0.0
                    free[j] = False
                    any_viol = True
                elif f > fmax[j]:
                    F[j] = fmax[j]
                    free[j] = False
                    any_viol = True
                else:
                    F[j] = f
        if not any_viol:
            break
    return passes


@numba.njit(cache=True)
def _rpi_layouts(A: np.ndarray, D: np.ndarray, fmax: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every layout x every demand: A (P, 3, n), D (K, 3) -> forces (P, K, n), errors (P, K)."""
    P, _, n = A.shape
    K = D.shape[0]
    F = np.empty((P, K, n))
    err = np.empty((P, K))
    for p in range(P):
        Ap = A[p]
        for k in range(K):
            _rpi_one(Ap, D[k], fmax, F[p, k])
            e2 = 0.0
            for i in range(3):
                t = D[k, i]
                for j in range(n):
                    t -= Ap[i, j] * F[p, k, j]
                e2 += t * t
            err[p, k] = np.sqrt(e2)
    return F, err


def _polish(A: np.ndarray, m: np.ndarray, F: np.ndarray, fmax: np.ndarray) -> np.ndarray:
    """Refine a solver's forces to machine precision on its own active set.

    Thrusters at a bound (within 1e-9 relative) stay there; the others are re-solved by
    least squares for the remaining torque. The refined forces are kept only if they stay
    within bounds and reduce the torque error (solver tolerances are ~1e-7 absolute).
    """
    tol = 1e-9 * fmax
    at_lo = F <= tol
    at_hi = F >= fmax - tol
    free = ~(at_lo | at_hi)
    if not free.any():
        return F
    Fb = np.where(at_hi, fmax, 0.0)
    r = m - A @ Fb
    sol, *_ = np.linalg.lstsq(A[:, free], r, rcond=None)
    G = Fb.copy()
    G[free] = sol
    if np.all(G >= -1e-12) and np.all(G <= fmax + 1e-12):
        G = np.clip(G, 0.0, fmax)
        if np.linalg.norm(A @ G - m) <= np.linalg.norm(A @ F - m):
            return G
    return F


def _nnls(A: np.ndarray, M: np.ndarray, fmax: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    N, n = M.shape[0], A.shape[1]
    F = np.zeros((N, n))
    status = np.zeros(N, dtype=int)
    for k in range(N):
        res = lsq_linear(A, M[k], bounds=(np.zeros(n), fmax), method="bvls", tol=1e-14)
        F[k] = _polish(A, M[k], np.clip(res.x, 0.0, fmax), fmax)
        status[k] = 0 if res.status >= 0 else 2
    return F, status, N


def _lp_min_fuel(A: np.ndarray, M: np.ndarray, fmax: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    N, n = M.shape[0], A.shape[1]
    F = np.zeros((N, n))
    status = np.zeros(N, dtype=int)
    calls = 0
    bounds = list(zip(np.zeros(n), fmax))
    c = np.ones(n)
    for k in range(N):
        res = linprog(c, A_eq=A, b_eq=M[k], bounds=bounds, method="highs")
        calls += 1
        if res.status == 0:
            F[k] = _polish(A, M[k], np.clip(res.x, 0.0, fmax), fmax)
            continue
        # infeasible (or numerically borderline): least-squares torque first, then least fuel
        ls = lsq_linear(A, M[k], bounds=(np.zeros(n), fmax), method="bvls", tol=1e-14)
        Fls = _polish(A, M[k], np.clip(ls.x, 0.0, fmax), fmax)
        T = A @ Fls
        res = linprog(c, A_eq=A, b_eq=T, bounds=bounds, method="highs")
        calls += 2
        G = _polish(A, T, np.clip(res.x, 0.0, fmax), fmax) if res.status == 0 else Fls
        if np.sum(G) <= np.sum(Fls) and np.linalg.norm(A @ G - M[k]) <= np.linalg.norm(T - M[k]) * (1 + 1e-9) + 1e-12:
            F[k] = G
        else:
            F[k] = Fls
            status[k] = 2 if ls.status < 0 else 0
    return F, status, calls


_Kernel = Callable[[np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray, int]]


def _pinv_kernel(A: np.ndarray, M: np.ndarray, fmax: np.ndarray):
    N = M.shape[0]
    F, _ = _rpi_layouts(np.ascontiguousarray(A[None]), np.ascontiguousarray(M), fmax)
    return F[0], np.zeros(N, dtype=int), N


#: Allocation methods; see the module docstring.
ALLOCATION_METHODS: dict[str, _Kernel] = {
    "pinv-redistribute": _pinv_kernel,
    "nnls": _nnls,
    "lp-min-fuel": _lp_min_fuel,
}


def allocate(
    torque_matrix: Any,
    demand: Any,
    *,
    method: str = "lp-min-fuel",
    f_max: Any = None,
) -> AllocationResult:
    """Allocate thruster forces that produce the demanded torque(s).

    Parameters
    ----------
    torque_matrix : ThrusterSet or array_like, shape (3, n), N m per N
        The thrusters (their torque matrix and their own ``f_max`` are used), or ``A`` of
        S3 eq. 5 (:meth:`ThrusterSet.torque_matrix`).
    demand : array_like, shape (3,) or (N, 3), N m
        Demanded torque(s) ``M``.
    method : str
        One of :data:`ALLOCATION_METHODS`.
    f_max : float or array_like, shape (n,), N, optional
        Upper force bound per thruster (S3 eq. 13, ``u^+``; lower bound 0). With a
        :class:`ThrusterSet` leave it out: the set's own limits are used, and a different
        explicit value is an error. With a bare matrix it defaults to 10 N (S3 Table 5).

    Returns
    -------
    AllocationResult
        Unreachable demands give ``feasible=False`` with the residual torque in ``error``;
        nothing is raised for them.

    References
    ----------
    S3 eq. 5, 12, 13.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import ThrusterSet
    >>> r = [[1, 0, 0], [1, 0, 0], [0, 1, 0], [0, 1, 0], [0, 0, 1], [0, 0, 1]]     # m
    >>> d = [[0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0]]  # +-z +-x +-y
    >>> ts = ThrusterSet(positions=np.array(r, float), directions=np.array(d, float), f_max=10.0)
    >>> from adcskit.thrusters import allocate
    >>> res = allocate(ts, [2.0, -1.0, 5.0])               # N m
    >>> res.x.round(9) + 0.0                               # N, within [0, f_max]
    array([5., 0., 2., 0., 0., 1.])
    >>> bool(res.feasible), float(res.error) < 1e-9
    (True, True)
    >>> big = allocate(ts, [[0.0, 0.0, 5.0], [0.0, 0.0, 50.0]], method="pinv-redistribute")
    >>> big.x.shape, big.feasible                          # 50 N m exceeds 10 N x 1 m
    ((2, 6), array([ True, False]))
    """
    method = check_choice("method", method, ALLOCATION_METHODS)
    from adcskit.thrusters.geometry import ThrusterSet

    if isinstance(torque_matrix, ThrusterSet):
        own = np.asarray(torque_matrix.f_max, dtype=float)
        if f_max is not None:
            given = np.broadcast_to(as_array("f_max", f_max, ndim=(0, 1)), own.shape)
            if not np.allclose(given, own, rtol=1e-12, atol=0.0):
                from adcskit.errors import InputError

                raise InputError(
                    f"f_max conflicts with the ThrusterSet's own limits ({own.tolist()} N); "
                    f"got {f_max!r} — leave f_max out to use the set's limits"
                )
        f_max = own
        torque_matrix = torque_matrix.torque_matrix()
    elif f_max is None:
        f_max = 10.0
    A = as_array("torque_matrix", torque_matrix, ndim=2)
    if A.shape[0] != 3 or A.shape[1] < 1:
        from adcskit.errors import InputError

        raise InputError(f"torque_matrix must have shape (3, n) with n >= 1; got {A.shape}")
    n = A.shape[1]
    M, batched = as_batch("demand", demand, (3,))
    fmax = check_positive_array("f_max", f_max, unit="N", min_value=1e-100, broadcast_to=(n,))
    F, status, nit = ALLOCATION_METHODS[method](A, M, fmax)
    T = F @ A.T
    err = np.linalg.norm(M - T, axis=1)
    feasible = err <= 1e-9 * np.linalg.norm(M, axis=1) + 1e-14 * np.linalg.norm(A, 2) * fmax.max()
    status = np.where(status == 2, 2, np.where(feasible, 0, 1))
    # a non-finite force or residual is a solver failure, never a met demand
    status = np.where(np.isfinite(err) & np.all(np.isfinite(F), axis=1), status, 2)
    feasible = feasible & (status != 2)
    n_bad = int(np.sum(status == 2))
    n_err = int(np.sum(status == 1))
    msg = (
        f"{method}: {M.shape[0] - n_bad - n_err} demand(s) met exactly, {n_err} with torque "
        f"error left, {n_bad} solver failure(s)"
    )
    if not batched:
        F, T, err, feasible, status = F[0], T[0], err[0], feasible[0], status[0]
    return AllocationResult(
        x=F, torque=T, error=np.asarray(err), feasible=np.asarray(feasible), success=n_bad == 0,
        status=np.asarray(status), message=msg, method=method, nit=int(nit),
    )
