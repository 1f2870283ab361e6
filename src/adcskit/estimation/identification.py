"""Least-squares identification of a discrete state matrix ``A`` (and optionally ``B``).

Problem (S1 eq. 14-17). Given regressor states ``x(t)`` (Kalman estimates in S1), the
next-step targets ``z(t)`` (S1: the measurements ``y(t+1)``) and inputs ``u(t)``, find

    min_Theta  sum_t || z(t) - Theta phi(t) ||^2 ,

with ``Theta = A`` and ``phi = x`` and targets ``z - B u`` when ``B`` is known (S1's case),
or ``Theta = [A B]`` and ``phi = [x; u]`` when ``B`` is estimated too. Stacking the rows
gives ``Phi Theta^T = Z`` with ``Phi`` of shape (N, q); every row of ``Theta`` is an
independent least-squares problem with the same matrix ``Phi``. The unknown vector is
``theta = Theta.ravel()`` (rows of ``Theta`` stacked, i.e. ``vec(Theta^T)``), so the full
system is ``(I_n kron Phi) theta = vec(Z)``, with ``n q`` unknowns (36 for S1's 3-DOF model).

Solvers (registry :data:`IDENTIFICATION_METHODS`):

``qr``
    Dense least squares by a thin QR factorisation of ``Phi`` (``scipy.linalg.qr``), one
    triangular solve for all rows. The reference solution.
``gmres``, ``bicg``, ``cgs``, ``bicgstab``
    ``scipy.sparse.linalg`` Krylov solvers. They need a *square* system, and S1 applies them
    to ``H theta = Y`` without saying how a tall ``H`` is made square. We use the **normal
    equations** ``(I_n kron Phi^T Phi) theta = vec(Phi^T Z)``: their unique solution (for
    full-rank ``Phi``) *is* the least-squares solution, the matrix is symmetric positive
    definite so all four methods are applicable and converge, and S1's Algorithm (21)
    warm-starts from ``vec(A_hat)`` in exactly this unknown space. The price is the squared
    condition number (``kappa(Phi)^2``); the alternative with the same solution, the
    augmented system ``[[I, Phi], [Phi^T, 0]]``, is indefinite and twice as large, which
    slows every method here. Run to convergence, all of them reach the ``qr`` solution.
    ``maxiter`` caps the iterations per call (for ``gmres`` the Arnoldi steps, in restart
    cycles of at most the system size); a capped solve that has not reached ``rtol`` returns
    its last iterate with ``status`` 1.
    Note that ``I_n kron G`` has the minimal polynomial of the ``q x q`` matrix ``G``, so a
    Krylov space of this system has dimension at most ``q``: GMRES reaches the exact
    least-squares solution in at most ``q`` steps (2 for the 1-DOF, 6 for the 3-DOF model).
    S1's "k <= n" cap in Algorithm (21) therefore allows the full solution.
``lsqr``
    ``scipy.sparse.linalg.lsqr`` on the tall operator ``I_n kron Phi`` (no squaring).
``adaptive-gmres-offline``
    S1's "empirical" adaptive GMRES: a fixed schedule of GMRES iterations per call
    (``first_iterations`` for the first ``first_steps`` time steps, then
    ``later_iterations``, or to ``rtol`` if that is None), always warm-started from the
    previous estimate. Implemented with ``scipy.sparse.linalg.gmres(restart=k, maxiter=1)``,
    which performs exactly ``k`` Arnoldi steps from ``x0``.
``adaptive-gmres-online``
    S1's Algorithm (21): from ``x0 = vec(A_hat(t))`` run ``k = 1 .. kmax`` Arnoldi/GMRES
    steps; each iterate ``A_min^k`` replaces the current estimate if it is closer in the
    Frobenius norm than the current estimate to ``A_unc = A0 * (2 alpha rand + 1 - alpha)``,
    a fresh uniform random scaling of the prior ``A0`` in ``[1 - alpha0, 1 + alpha0]``.
    **Hand-written Arnoldi/GMRES** here: the algorithm inspects every intermediate GMRES
    iterate of one Krylov cycle, and scipy's ``gmres`` exposes only the residual norm per
    inner iteration (``callback_type="pr_norm"``) and the iterate at restarts. Our Arnoldi
    uses modified Gram-Schmidt (S1 prints classical Gram-Schmidt; identical in exact
    arithmetic) and solves the small Hessenberg least-squares problem with
    ``scipy.linalg.lstsq``; a test checks that its iterates equal scipy's
    ``gmres(restart=k, maxiter=1)`` for every ``k``.
``ridge-prior``
    Baseline S1 omits: Tikhonov regularisation toward the prior,
    ``min ||Z - Phi Theta^T||^2 + lam ||Theta - Theta0||_F^2``, solved through the SVD of
    ``Phi``; ``lam`` from generalised cross-validation (default), the discrepancy
    principle with a stated noise level, or fixed by the caller -- never from the true
    model.
``rls``
    Baseline: recursive least squares with exponential forgetting, started at
    ``A_init``/the prior with covariance ``delta I`` (:class:`RecursiveLeastSquares`).

References
----------
S1 eq. (14)-(17) (least-squares model estimation), Algorithm (19) (GMRES),
Algorithm (20) (Arnoldi), Algorithm (21) (online meta-heuristic adaptive GMRES), Table 1.
Saad, Y., *Iterative Methods for Sparse Linear Systems*, 2nd ed., SIAM 2003, Alg. 6.9.
Golub, Heath & Wahba, "Generalized cross-validation as a method for choosing a good ridge
parameter", Technometrics 21(2), 1979.
Ljung, L., *System Identification*, 2nd ed., 1999, §11.2 (RLS with forgetting).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla
from scipy.optimize import brentq

from adcskit._results import Result
from adcskit._validation import (
    as_array,
    as_rng,
    check_choice,
    check_flag,
    check_int,
    check_positive,
    check_range,
    short_repr,
)
from adcskit.errors import InputError, InputTypeError

__all__ = [
    "IDENTIFICATION_METHODS",
    "IdentificationResult",
    "RecursiveLeastSquares",
    "identify_model",
    "offline_schedule",
    "regression_data",
]


# --------------------------------------------------------------------------- result


@dataclass(frozen=True, slots=True, repr=False, kw_only=True)
class IdentificationResult(Result):
    """Output of :func:`identify_model`.

    Attributes
    ----------
    A : ndarray, shape (n, n)
        Identified state matrix.
    B : ndarray, shape (n, p)
        Identified input matrix if ``estimate_B``, else the known ``B`` that was passed
        (shape (n, 0) if there were no inputs).
    x : ndarray, shape (n * q,)
        Unknown vector ``Theta.ravel()`` (rows of ``[A B]`` stacked).
    success : bool
        The solver reached its stopping rule (for the fixed-iteration adaptive methods:
        it ran its iterations without breakdown).
    status : int
        0 success; 1 iteration limit; 2 rank-deficient regressors (``qr``); 3 numerical
        breakdown.
    message : str
    nit : int
        Iterations (Krylov steps, LSQR iterations, RLS samples; 1 for ``qr``).
    nfev : int
        Operator products (matrix-vector products with the system matrix).
    residual_norm : float
        ``||Z - Phi Theta^T||_F`` at the returned estimate (target units).
    method : str
    reg_param : float
        Ridge weight ``lam`` (``ridge-prior``), else NaN.
    n_accepted : int
        Candidates accepted by ``adaptive-gmres-online`` (else 0).

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[1.0, 0.1], [0.0, 1.0]])          # double integrator, dt = 0.1 s
    >>> B = np.array([[0.005], [0.1]])
    >>> C = np.eye(2)
    >>> u = np.sin(0.3 * np.arange(40))[:, None]         # N = 40 input samples
    >>> from adcskit.estimation import identify_model, simulate_linear
    >>> sim = simulate_linear(A, B, C, u, x0=[1.0, -0.5], rng=0)   # Q = 0: x is noise-free
    >>> res = identify_model(sim.x[:-1], sim.x[1:], u, B=B)
    >>> type(res).__name__, res.success, res.method, res.A.shape
    ('IdentificationResult', True, 'qr', (2, 2))
    """

    A: np.ndarray
    B: np.ndarray
    x: np.ndarray
    success: bool
    status: int
    message: str
    nit: int
    nfev: int
    residual_norm: float
    method: str
    reg_param: float = math.nan
    n_accepted: int = 0


# --------------------------------------------------------------------------- helpers


def regression_data(states, targets, inputs=None, *, B=None, estimate_B=False):
    """Build the regression matrices ``(Phi, Z)`` of S1 eq. (17).

    Parameters
    ----------
    states : array_like, shape (N, n)
        Regressor states ``x(t)``.
    targets : array_like, shape (N, n)
        Next-step targets (S1: the measurements ``y(t+1)``).
    inputs : array_like, shape (N, p), optional
        Inputs ``u(t)``.
    B : array_like, shape (n, p), optional
        Known input matrix; ``B u`` is subtracted from the targets.
    estimate_B : bool
        Append the inputs to the regressors and estimate ``[A B]``.

    Returns
    -------
    Phi : ndarray, shape (N, q)
    Z : ndarray, shape (N, n)

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.estimation import regression_data
    >>> x = np.array([[1.0, 0.0], [1.0, 0.1], [1.01, 0.2]])
    >>> Phi, Z = regression_data(x[:-1], x[1:])
    >>> Phi.shape, Z.shape
    ((2, 2), (2, 2))
    >>> Phi, Z = regression_data(x[:-1], x[1:], np.zeros((2, 1)), estimate_B=True)
    >>> Phi.shape                                          # regressors [x, u]
    (2, 3)
    """
    X = as_array("states", states, ndim=2)
    N, n = X.shape
    Z = as_array("targets", targets, shape=(N, n))
    if inputs is None:
        U = np.zeros((N, 0))
    else:
        U = as_array("inputs", inputs, ndim=2)
        if U.shape[0] != N:
            raise InputError(f"inputs must have shape ({N}, p) to match states; got {U.shape}")
    p = U.shape[1]
    estimate_B = check_flag("estimate_B", estimate_B)
    if estimate_B:
        if p == 0:
            raise InputError("inputs must be given with estimate_B=True (the regressors are [x, u]); got None")
        if B is not None:
            raise InputError(f"B must be None with estimate_B=True (B is estimated); got {short_repr(B)}")
        return np.hstack([X, U]), Z
    if B is not None and p == 0:
        raise InputError(f"B is only used with inputs (B u is subtracted from the targets); got B={short_repr(B)} "
                         "and inputs=None")
    if B is not None and p > 0:
        Bm = as_array("B", B, shape=(n, p))
        Z = Z - U @ Bm.T
    elif p > 0 and B is None:
        raise InputError("B must be given when inputs are given and estimate_B is False; got None")
    return X, Z


def offline_schedule(n_states: int) -> dict[str, Any]:
    """The offline ("empirical") adaptive-GMRES schedule S1 prints for its two models.

    S1: for the 1-DOF model (``n = 2``) one GMRES iteration for the first 3 time steps, then
    solve to tolerance 1e-6; for the 3-DOF model (``n = 6``) one iteration for the first 7
    time steps, then 3 iterations. Other sizes get the 3-DOF rule.

    Examples
    --------
    >>> from adcskit.estimation import offline_schedule
    >>> offline_schedule(2)
    {'first_steps': 3, 'first_iterations': 1, 'later_iterations': None, 'rtol': 1e-06}
    """
    n = check_int("n_states", n_states, minimum=1)
    if n <= 2:
        return {"first_steps": 3, "first_iterations": 1, "later_iterations": None, "rtol": 1e-6}
    return {"first_steps": 7, "first_iterations": 1, "later_iterations": 3, "rtol": 1e-6}


class _Counter:
    """Matrix-vector product counter around a dense matrix (for ``nfev``)."""

    __slots__ = ("M", "n")

    def __init__(self, M):
        self.M = M
        self.n = 0

    def op(self):
        def mv(v):
            self.n += 1
            return self.M @ v

        def rmv(v):
            self.n += 1
            return self.M.T @ v

        return spla.LinearOperator(self.M.shape, matvec=mv, rmatvec=rmv, dtype=float)


def _normal_system(Phi, Z):
    """Normal equations ``(I_n kron G) theta = vec(Z^T Phi)`` as a dense matrix."""
    n, q = Z.shape[1], Phi.shape[1]
    G = Phi.T @ Phi
    M = np.zeros((n * q, n * q))
    for i in range(n):  # the n diagonal blocks of I_n kron G (np.kron costs ~4x more here)
        M[i * q:(i + 1) * q, i * q:(i + 1) * q] = G
    return M, (Z.T @ Phi).ravel()


def _residual(Phi, Z, Theta):
    return float(np.linalg.norm(Z - Phi @ Theta.T))


# --------------------------------------------------------------------------- kernels
# Every kernel: (Phi, Z, Theta_init, Theta_prior, opts, gen) -> dict with Theta, nit, nfev,
# status, message and optional reg_param / n_accepted.


def _k_qr(Phi, Z, T0, Tp, o, gen):
    N, q = Phi.shape
    if N < q:
        return dict(Theta=T0.copy(), nit=0, nfev=0, status=2,
                    message=f"rank-deficient: {N} samples < {q} unknowns per row")
    Qm, Rm = sla.qr(Phi, mode="economic", check_finite=False)
    d = np.abs(np.diag(Rm))
    if d.min() <= o["rank_tol"] * d.max():
        return dict(Theta=T0.copy(), nit=1, nfev=0, status=2,
                    message=f"rank-deficient regressors (|R_ii| min/max = {d.min() / d.max() if d.max() > 0 else 0.0:.2e})")
    # LAPACK trtrs with a Fortran-order right-hand side: with a C-order one (and with
    # scipy.linalg.solve_triangular) OpenBLAS takes ~3 ms per tiny solve on this machine
    ThT, info = sla.lapack.dtrtrs(Rm, np.asfortranarray(Qm.T @ Z), lower=0)
    if info != 0:
        return dict(Theta=T0.copy(), nit=1, nfev=0, status=2, message=f"triangular solve failed (info={info})")
    return dict(Theta=ThT.T, nit=1, nfev=0, status=0, message="QR least squares")


def _krylov(name):
    solver = {"gmres": spla.gmres, "bicg": spla.bicg, "cgs": spla.cgs, "bicgstab": spla.bicgstab}[name]

    def kernel(Phi, Z, T0, Tp, o, gen):
        M, b = _normal_system(Phi, Z)
        deficient = _rank_deficient(Phi)
        if deficient:
            return dict(Theta=T0.copy(), nit=0, nfev=0, status=2, message=deficient)
        cnt = _Counter(M)
        nit = [0]
        kw: dict[str, Any] = dict(rtol=o["rtol"], atol=o["atol"], maxiter=o["maxiter"] or 10 * M.shape[0])
        if name == "gmres":
            # ``maxiter`` counts Arnoldi (inner) iterations, as for the other methods' iterations:
            # at most that many, in restart cycles of at most the system size
            restart = min(M.shape[0], o["maxiter"] or M.shape[0])
            kw.update(restart=restart, callback_type="pr_norm",
                      maxiter=-(-o["maxiter"] // restart) if o["maxiter"] else 10 * M.shape[0])
        x, info = solver(cnt.op(), b, x0=T0.ravel(), callback=lambda _: nit.__setitem__(0, nit[0] + 1), **kw)
        if info == 0:
            status, msg = 0, f"{name} converged (normal equations)"
        elif info > 0:
            status, msg = 1, f"{name} reached the iteration limit without converging"
        else:
            status, msg = 3, f"{name} broke down (info={info})"
        if not np.all(np.isfinite(x)):
            x, status, msg = T0.ravel().copy(), 3, f"{name} produced non-finite values"
        return dict(Theta=x.reshape(T0.shape), nit=nit[0], nfev=cnt.n, status=status, message=msg)

    return kernel


def _rank_deficient(Phi) -> str | None:
    """Message if the regressors do not determine Theta (the test QR applies), else None."""
    N, q = Phi.shape
    if N < q:
        return f"rank-deficient: {N} samples < {q} unknowns per row"
    sv = np.linalg.svd(Phi, compute_uv=False)
    if sv.max() == 0 or sv.min() <= 1e-12 * sv.max():
        ratio = 0.0 if sv.max() == 0 else sv.min() / sv.max()
        return f"rank-deficient regressors (singular value min/max = {ratio:.2e})"
    return None


def _k_lsqr(Phi, Z, T0, Tp, o, gen):
    deficient = _rank_deficient(Phi)
    if deficient:
        return dict(Theta=T0.copy(), nit=0, nfev=0, status=2, message=deficient)
    n = Z.shape[1]
    H = np.kron(np.eye(n), Phi)  # rows: (row i of Theta, time t)
    b = Z.T.ravel()
    cnt = _Counter(H)
    out = spla.lsqr(cnt.op(), b, atol=o["atol"], btol=o["btol"], iter_lim=o["maxiter"], x0=T0.ravel())
    x, istop, itn = out[0], out[1], out[2]
    status = 0 if istop in (0, 1, 2, 4, 5) else 1
    return dict(Theta=x.reshape(T0.shape), nit=int(itn), nfev=cnt.n, status=status,
                message=f"lsqr istop={istop}")


def _k_offline(Phi, Z, T0, Tp, o, gen):
    M, b = _normal_system(Phi, Z)
    step = o["step"]
    k = o["first_iterations"] if step < o["first_steps"] else o["later_iterations"]
    cnt = _Counter(M)
    nit = [0]
    cb = lambda _: nit.__setitem__(0, nit[0] + 1)  # noqa: E731
    if k is None:  # to tolerance
        x, info = spla.gmres(cnt.op(), b, x0=T0.ravel(), rtol=o["rtol"], atol=0.0,
                             restart=M.shape[0], maxiter=o["maxiter"] or 10,
                             callback=cb, callback_type="pr_norm")
        status = 0 if info == 0 else 1
        msg = f"GMRES to rtol {o['rtol']:g}" + ("" if info == 0 else " (not reached)")
    else:
        x, info = spla.gmres(cnt.op(), b, x0=T0.ravel(), rtol=0.0, atol=0.0,
                             restart=int(k), maxiter=1, callback=cb, callback_type="pr_norm")
        status, msg = 0, f"{k} GMRES iteration(s) from the previous estimate (step {step})"
    if not np.all(np.isfinite(x)):
        x, status, msg = T0.ravel().copy(), 3, "GMRES produced non-finite values"
    return dict(Theta=x.reshape(T0.shape), nit=nit[0], nfev=cnt.n, status=status, message=msg)


#: gelsd's workspace sizes by (rows, columns) of a one-right-hand-side problem, as scipy's
#: ``lstsq`` queries them (``dgelsd_lwork``, rounded by ``int``): the same workspace, so the
#: same blocking inside LAPACK and the same bits
_GELSD_WORK: dict[tuple[int, int], tuple[int, int]] = {}
_EPS = float(np.finfo(np.float64).eps)


def _lstsq_tall(H, rhs):
    """``scipy.linalg.lstsq(H, rhs, check_finite=False)[0]`` for a float64 ``H`` (m, n), m > n,
    and a 1-D ``rhs``: the same LAPACK ``dgelsd`` call (``cond`` = machine epsilon, scipy's
    default, and scipy's workspace query, cached per shape) without scipy's per-call checks,
    which cost about twice the solve of the few-by-few Hessenberg problems of
    :func:`_gmres_iterates` (41 vs 15 µs per 8 x 7 problem; issue 24 item 1). Bit-identical;
    tested against ``scipy.linalg.lstsq``."""
    m, n = H.shape
    work = _GELSD_WORK.get((m, n))
    if work is None:
        lw, iw, info = sla.lapack.dgelsd_lwork(m, n, 1, _EPS)
        if info != 0:
            raise ValueError(f"Internal work array size computation failed: {info}")
        work = _GELSD_WORK[(m, n)] = (int(lw.real), int(iw.real))
    x, _s, _rank, info = sla.lapack.dgelsd(H, rhs, work[0], work[1], _EPS, False, False)
    if info > 0:
        raise np.linalg.LinAlgError("SVD did not converge in Linear Least Squares")
    if info < 0:
        raise ValueError(f"illegal value in {-info}-th argument of internal gelsd")
    return x[:n]


def _gmres_iterates(M, b, x0, kmax):
    """Yield ``(k, x_k, rho_k)`` for k = 1..kmax GMRES steps from ``x0`` (one cycle).

    Arnoldi with modified Gram-Schmidt (Saad 2003, Alg. 6.2) and the Hessenberg
    least-squares problem ``min ||beta e1 - H_k y||`` (S1 Algorithm 21, lines 8-17).
    Stops early at a (happy) breakdown ``h_{k+1,k} = 0``.
    """
    r0 = b - M @ x0
    beta = float(np.linalg.norm(r0))
    if beta == 0.0:
        return
    dim = M.shape[0]
    kmax = min(kmax, dim)
    V = np.zeros((dim, kmax + 1))
    H = np.zeros((kmax + 1, kmax))
    V[:, 0] = r0 / beta
    for k in range(kmax):
        w = M @ V[:, k]
        for j in range(k + 1):
            H[j, k] = w @ V[:, j]
            w = w - H[j, k] * V[:, j]
        H[k + 1, k] = np.linalg.norm(w)
        e1 = np.zeros(k + 2)
        e1[0] = beta
        y = _lstsq_tall(H[: k + 2, : k + 1], e1)
        rho = float(np.linalg.norm(e1 - H[: k + 2, : k + 1] @ y))
        yield k + 1, x0 + V[:, : k + 1] @ y, rho
        if H[k + 1, k] <= 1e-14 * beta:
            return
        V[:, k + 1] = w / H[k + 1, k]


def _k_online(Phi, Z, T0, Tp, o, gen):
    if Tp is None:
        raise InputError("adaptive-gmres-online needs the prior model A_prior (S1's A0)")
    M, b = _normal_system(Phi, Z)
    n = T0.shape[0]  # state dimension
    kmax = o["max_iterations"] or (n + 1)  # S1 Alg. 21: "while k <= n: k = k + 1"
    alpha = o["alpha0"]
    current = T0.copy()
    accepted = 0
    nit = 0
    for _k, x, _rho in _gmres_iterates(M, b, T0.ravel(), kmax):
        nit += 1
        cand = x.reshape(T0.shape)
        A_unc = Tp * (2.0 * alpha * gen.random() + 1.0 - alpha)  # Alg. 21 line 19
        if np.linalg.norm(cand - A_unc) < np.linalg.norm(current - A_unc):  # Frobenius
            current = cand
            accepted += 1
    return dict(Theta=current, nit=nit, nfev=nit + 1, status=0,
                message=f"{accepted} of {nit} GMRES iterates accepted", n_accepted=accepted)


def _k_ridge(Phi, Z, T0, Tp, o, gen):
    prior = T0 if Tp is None else Tp
    N, q = Phi.shape
    R0 = Z - Phi @ prior.T
    U, s, Vt = sla.svd(Phi, full_matrices=False, check_finite=False)
    C = U.T @ R0  # (r, n)
    c2 = np.sum(C**2, axis=1)
    rss_perp = max(float(np.sum(R0**2) - c2.sum()), 0.0)
    s2 = s**2
    smax2 = float(s2.max()) if s2.size else 1.0

    def rss(lam):
        f = lam / (s2 + lam)
        return rss_perp + float(np.sum(f**2 * c2))

    rule = o["rule"]
    if rule == "fixed":
        if o["lam"] is None:
            raise InputError("ridge-prior with rule='fixed' needs options['lam']")
        lam, msg = float(o["lam"]), f"fixed ridge weight {float(o['lam']):.3g}"
    elif rule == "gcv":
        # GCV(lam) = RSS(lam) / (N - dof(lam))^2 on a log grid (vectorised), then a finer
        # grid around the best point; lam spans 1e-12 .. 1e4 times the largest s^2.
        def gcv(lams):
            f = lams[:, None] / (s2[None, :] + lams[:, None])
            r = rss_perp + np.sum(f**2 * c2[None, :], axis=1)
            dof = np.sum(1.0 - f, axis=1)
            return r / np.maximum(N - dof, 1e-12) ** 2

        grid = smax2 * np.logspace(-12, 4, 97)
        i = int(np.argmin(gcv(grid)))
        fine = np.geomspace(grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)], 41)
        lam = float(fine[int(np.argmin(gcv(fine)))])
        msg = f"GCV ridge weight {lam:.3g}"
    else:  # discrepancy principle
        sigma = o["noise_std"]
        if sigma is None:
            raise InputError("ridge-prior with rule='discrepancy' needs options['noise_std']")
        target = o["tau"] * R0.size * sigma**2
        if rss(0.0) >= target:
            lam, msg = 0.0, "discrepancy target below the least-squares residual: lam = 0"
        elif rss_perp + c2.sum() <= target:
            lam, msg = math.inf, "prior already within the discrepancy target: lam = inf"
        else:
            f = lambda ll: rss(math.exp(ll)) - target  # noqa: E731
            lo, hi = np.log(smax2) - 40.0, np.log(smax2) + 40.0
            lam = math.exp(brentq(f, lo, hi, xtol=1e-6))
            msg = f"discrepancy-principle ridge weight {lam:.3g}"
    if math.isinf(lam):
        Theta = prior.copy()
    else:
        with np.errstate(divide="ignore", invalid="ignore"):
            filt = np.where(s2 + lam > 0, s / (s2 + lam), 0.0)
        Theta = prior + (Vt.T @ (filt[:, None] * C)).T
    return dict(Theta=Theta, nit=1, nfev=0, status=0, message=msg, reg_param=lam)


class RecursiveLeastSquares:
    """Recursive least squares with exponential forgetting for ``z = Theta phi``.

    All rows of ``Theta`` share the regressor, hence one ``q x q`` covariance ``P``.

    Parameters
    ----------
    Theta0 : array_like, shape (n, q)
        Initial estimate (e.g. the prior model).
    delta : float
        Initial covariance ``P0 = delta I`` in (regressor units)^-2; small values trust
        ``Theta0`` more.
    forgetting : float
        Forgetting factor in (0, 1]; 1 is ordinary (growing-memory) least squares.

    References
    ----------
    Ljung (1999) §11.2, eq. (11.63)-(11.65).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.estimation import RecursiveLeastSquares
    >>> Theta_true = np.array([[1.0, 0.1], [0.0, 0.9]])
    >>> rls = RecursiveLeastSquares(np.zeros((2, 2)), delta=1e4, forgetting=1.0)
    >>> rng = np.random.default_rng(0)
    >>> for phi in rng.standard_normal((20, 2)):
    ...     rls.update(phi, Theta_true @ phi)
    >>> rls.Theta.round(3), rls.nit
    (array([[1. , 0.1],
           [0. , 0.9]]), 20)
    """

    def __init__(self, Theta0, *, delta: float = 100.0, forgetting: float = 0.99) -> None:
        self.Theta = as_array("Theta0", Theta0, ndim=2)
        self.delta = check_positive("delta", delta)
        self.forgetting = check_range("forgetting", forgetting, 0.0, 1.0, lo_open=True)
        self.P = self.delta * np.eye(self.Theta.shape[1])
        self.nit = 0

    def update(self, phi, z, *, validate: bool = True) -> None:
        """One sample: regressor ``phi`` (q,) and target ``z`` (n,).

        With ``validate=True`` (default) ``phi`` and ``z`` must be finite real arrays of shapes
        ``(q,)`` and ``(n,)`` (``Theta0`` has shape ``(n, q)``), otherwise
        :class:`~adcskit.errors.InputError` names the argument. ``validate=False`` is the
        fast path for inner loops that pass already validated float arrays (:meth:`update_batch`,
        the joint estimator): nothing is checked and the result of invalid input is undefined.
        Both paths give bit-identical results on valid input.
        """
        if validate is not False and (validate is True or check_flag("validate", validate)):
            n, q = self.Theta.shape
            phi = as_array("phi", phi, shape=(q,))
            z = as_array("z", z, shape=(n,))
        lam = self.forgetting
        Pphi = self.P @ phi
        k = Pphi / (lam + phi @ Pphi)
        self.Theta = self.Theta + np.outer(z - self.Theta @ phi, k)
        P = (self.P - np.outer(k, Pphi)) / lam
        self.P = 0.5 * (P + P.T)
        self.nit += 1

    def update_batch(self, Phi, Z) -> None:
        """Validated entry point: samples ``Phi`` (N, q) and targets ``Z`` (N, n), in order.

        Checks shapes and finiteness once, then runs :meth:`update` per sample.
        """
        n, q = self.Theta.shape
        Phi = as_array("Phi", Phi, ndim=2, nonempty=False)
        if Phi.shape[1:] != (q,):
            raise InputError(f"Phi must have shape (N, {q}) to match Theta0; got shape {Phi.shape}")
        Z = as_array("Z", Z, shape=(Phi.shape[0], n), nonempty=False)
        for phi, z in zip(Phi, Z):
            self.update(phi, z, validate=False)


def _k_rls(Phi, Z, T0, Tp, o, gen):
    rls = RecursiveLeastSquares(T0, delta=o["delta"], forgetting=o["forgetting"])
    rls.update_batch(Phi, Z)
    ok = bool(np.all(np.isfinite(rls.Theta)))
    return dict(Theta=rls.Theta if ok else T0.copy(), nit=rls.nit, nfev=0,
                status=0 if ok else 3, message="RLS" if ok else "RLS diverged")


_KRYLOV_OPTS = {"rtol": 1e-10, "atol": 0.0, "maxiter": None}

#: name -> (kernel, default options). A wrong name lists the valid ones.
IDENTIFICATION_METHODS: dict[str, tuple[Callable, Mapping[str, Any]]] = {
    "qr": (_k_qr, {"rank_tol": 1e-12}),
    "gmres": (_krylov("gmres"), _KRYLOV_OPTS),
    "bicg": (_krylov("bicg"), _KRYLOV_OPTS),
    "cgs": (_krylov("cgs"), _KRYLOV_OPTS),
    "bicgstab": (_krylov("bicgstab"), _KRYLOV_OPTS),
    "lsqr": (_k_lsqr, {"atol": 1e-12, "btol": 1e-12, "maxiter": None}),
    "adaptive-gmres-offline": (
        _k_offline,
        {"step": 0, "first_steps": 3, "first_iterations": 1, "later_iterations": None,
         "rtol": 1e-6, "maxiter": None},
    ),
    "adaptive-gmres-online": (_k_online, {"alpha0": 0.5, "max_iterations": None}),
    "ridge-prior": (_k_ridge, {"rule": "gcv", "noise_std": None, "tau": 1.0, "lam": None}),
    "rls": (_k_rls, {"delta": 100.0, "forgetting": 0.99}),
}


def _resolve_options(method, options):
    defaults = IDENTIFICATION_METHODS[method][1]
    opts = dict(defaults)
    if options:
        if not isinstance(options, Mapping):
            raise InputTypeError(f"options must be a mapping; got {type(options).__name__}")
        unknown = set(options) - set(defaults)
        if unknown:
            raise InputError(
                f"options {sorted(unknown)} are not valid for method {method!r}; "
                f"valid: {sorted(defaults) or 'none'}"
            )
        opts.update(options)
    return opts


def _solve(method, Phi, Z, T0, Tp, opts, gen):
    """Run one registered kernel on plain arrays (no validation); returns a dict."""
    return IDENTIFICATION_METHODS[method][0](Phi, Z, T0, Tp, opts, gen)


def identify_model(
    states,
    targets,
    inputs=None,
    *,
    B=None,
    estimate_B: bool = False,
    method: str = "qr",
    A_init=None,
    B_init=None,
    A_prior=None,
    B_prior=None,
    rng=None,
    options: Mapping[str, Any] | None = None,
) -> IdentificationResult:
    """Identify ``A`` (and optionally ``B``) of ``x(t+1) = A x(t) + B u(t)`` by least squares.

    Parameters
    ----------
    states : array_like, shape (N, n)
        Regressor states ``x(t)`` (S1: Kalman estimates ``x_hat(t-1)``).
    targets : array_like, shape (N, n)
        Next-step targets (S1 eq. 17: measurements ``y_o(t)``).
    inputs : array_like, shape (N, p), optional
        Inputs ``u(t)``.
    B : array_like, shape (n, p), optional
        Known input matrix (S1's case); required with inputs unless ``estimate_B``.
    estimate_B : bool
        Also estimate ``B`` (unknowns ``[A B]``).
    method : str
        Key of :data:`IDENTIFICATION_METHODS`.
    A_init, B_init : array_like, optional
        Warm start (Krylov ``x0``, RLS start). Defaults: the prior if given, else zeros.
    A_prior, B_prior : array_like, optional
        Prior model (S1's ``A0``), used by ``adaptive-gmres-online`` (required) and
        ``ridge-prior`` (shrinkage target; zeros if absent).
    rng : Generator or int, optional
        Random source of ``adaptive-gmres-online`` (``None`` means seed 0).
    options : mapping, optional
        Method options (see the registry defaults), e.g. ``{"rtol": 1e-8}`` for Krylov
        methods, ``{"step": t}`` for ``adaptive-gmres-offline``, ``{"alpha0": 0.5}`` for
        ``adaptive-gmres-online``, ``{"rule": "gcv" | "discrepancy", "noise_std": s}`` for
        ``ridge-prior`` (or ``{"rule": "fixed", "lam": w}``), ``{"forgetting": 0.99, "delta": 100}`` for ``rls``.

    Returns
    -------
    IdentificationResult
        ``success=False`` (not an exception) if the solver did not converge or the
        regressors are rank deficient.

    References
    ----------
    S1 eq. (14)-(17), Algorithms (19)-(21), Table 1.

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[1.0, 0.1], [0.0, 1.0]])          # double integrator, dt = 0.1 s
    >>> B = np.array([[0.005], [0.1]])
    >>> C = np.eye(2)
    >>> u = np.sin(0.3 * np.arange(40))[:, None]         # N = 40 input samples
    >>> from adcskit.estimation import identify_model, simulate_linear
    >>> sim = simulate_linear(A, B, C, u, x0=[1.0, -0.5], rng=0)   # Q = 0: x is noise-free
    >>> res = identify_model(sim.x[:-1], sim.x[1:], u, B=B, method="qr")
    >>> res.success, res.A.round(6) + 0.0
    (True, array([[1. , 0.1],
           [0. , 1. ]]))
    >>> gm = identify_model(sim.x[:-1], sim.x[1:], u, B=B, method="gmres")
    >>> gm.success, np.allclose(gm.A, A, atol=1e-6)
    (True, True)
    """
    check_choice("method", method, IDENTIFICATION_METHODS)
    opts = _resolve_options(method, options)
    _check_opts(method, opts)
    Phi, Z = regression_data(states, targets, inputs, B=B, estimate_B=estimate_B)
    N, q = Phi.shape
    n = Z.shape[1]
    p = q - n

    def theta(name_a, a, name_b, b, default):
        if b is not None and p == 0:
            raise InputError(f"{name_b} is only used with inputs and estimate_B=True; got {short_repr(b)}")
        if b is not None and a is None:
            raise InputError(f"{name_b} needs {name_a} (the pair is the model [A B]); got {name_a}=None")
        if a is None:
            return None if default is None else default.copy()
        Am = as_array(name_a, a, shape=(n, n))
        if p == 0:
            return Am
        Bm = np.zeros((n, p)) if b is None else as_array(name_b, b, shape=(n, p))
        return np.hstack([Am, Bm])

    Tp = theta("A_prior", A_prior, "B_prior", B_prior, None)
    T0 = theta("A_init", A_init, "B_init", B_init, Tp if Tp is not None else np.zeros((n, q)))
    gen = as_rng(rng)
    out = _solve(method, Phi, Z, T0, Tp, opts, gen)
    Theta = out["Theta"]
    if estimate_B:
        A_hat, B_hat = Theta[:, :n].copy(), Theta[:, n:].copy()
    else:
        A_hat = Theta.copy()
        if inputs is None:
            B_hat = np.zeros((n, 0))
        else:
            B_hat = as_array("B", B)
    return IdentificationResult(
        A=A_hat,
        B=B_hat,
        x=Theta.ravel().copy(),
        success=out["status"] == 0,
        status=int(out["status"]),
        message=out["message"],
        nit=int(out["nit"]),
        nfev=int(out["nfev"]),
        residual_norm=_residual(Phi, Z, Theta),
        method=method,
        reg_param=float(out.get("reg_param", math.nan)),
        n_accepted=int(out.get("n_accepted", 0)),
    )


def _check_opts(method, o):
    if method in ("gmres", "bicg", "cgs", "bicgstab"):
        check_positive("options['rtol']", o["rtol"], allow_zero=True)
        check_positive("options['atol']", o["atol"], allow_zero=True)
        if o["maxiter"] is not None:
            check_int("options['maxiter']", o["maxiter"], minimum=1)
    elif method == "adaptive-gmres-offline":
        check_int("options['step']", o["step"], minimum=0)
        check_int("options['first_steps']", o["first_steps"], minimum=0)
        check_int("options['first_iterations']", o["first_iterations"], minimum=1)
        if o["later_iterations"] is not None:
            check_int("options['later_iterations']", o["later_iterations"], minimum=1)
        check_positive("options['rtol']", o["rtol"])
    elif method == "adaptive-gmres-online":
        check_range("options['alpha0']", o["alpha0"], 0.0, 1.0)
        if o["max_iterations"] is not None:
            check_int("options['max_iterations']", o["max_iterations"], minimum=1)
    elif method == "ridge-prior":
        check_choice("options['rule']", o["rule"], ("gcv", "discrepancy", "fixed"))
        if o["lam"] is not None:
            check_positive("options['lam']", o["lam"], allow_zero=True)
        if o["noise_std"] is not None:
            check_positive("options['noise_std']", o["noise_std"])
        check_positive("options['tau']", o["tau"])
    elif method == "rls":
        check_positive("options['delta']", o["delta"])
        check_range("options['forgetting']", o["forgetting"], 0.0, 1.0, lo_open=True)
    elif method == "lsqr":
        check_positive("options['atol']", o["atol"], allow_zero=True)
        check_positive("options['btol']", o["btol"], allow_zero=True)
        if o["maxiter"] is not None:
            check_int("options['maxiter']", o["maxiter"], minimum=1)
    elif method == "qr":
        check_positive("options['rank_tol']", o["rank_tol"], allow_zero=True)
