"""Joint state and model estimation: S1's Kalman <-> least-squares alternation, and an
augmented-state extended Kalman filter as a physics-based baseline.

:func:`joint_estimate` is S1's scheme (eq. 14-18) run online along the manoeuvre. At each
time step ``t``:

1. identify ``A_hat(t)`` from all pairs ``(x_hat(s|s), y(s+1), u(s))``, ``s < t`` — the
   Kalman estimates of the previous steps as regressors and the measurements as targets
   (S1 eq. 17: ``A_hat X_hat(t-1) = Y_o(t) - B U(t-1)``), with any method of
   :data:`~adcskit.estimation.identification.IDENTIFICATION_METHODS`, warm-started from
   ``A_hat(t-1)``;
2. run one Kalman step with ``y(t)`` and the new ``A_hat(t)``.

Unregularised solvers (``qr``, Krylov, ``lsqr``) start once the regression is determined
(``q`` pairs for ``q`` unknowns per row); before that, and for the prior-anchored methods
from the first pair on, the model in use is the prior ``A0`` / the previous estimate.
``passes > 1`` repeats the manoeuvre, starting each pass from the last estimate (S1's
outer index ``k``).

:func:`augmented_ekf` estimates physical parameters (e.g. the ratios of the true to the
assumed moments of inertia) together with the state, through a user-supplied
``model(p) -> (A_d, B_d)``. The Jacobian with respect to ``p`` is taken by central
differences (the model typically contains a pole-placement gain and a Crank-Nicolson
discretisation, for which no closed-form derivative is worth writing).

Hand-written here: the loops; the linear algebra is numpy/scipy and the identification
kernels are those of :mod:`adcskit.estimation.identification`.

References
----------
S1 eq. (14)-(18) and the simulation section (joint Kalman filter + model estimation).
Simon, D., *Optimal State Estimation*, Wiley 2006, §13.4 (joint/augmented-state EKF
parameter estimation).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.linalg import cho_factor, cho_solve

from adcskit._results import Result
from adcskit._validation import (
    as_array,
    as_rng,
    check_callable,
    check_choice,
    check_flag,
    check_int,
    check_positive,
    short_repr,
)
from adcskit.errors import InputError, InputTypeError
from adcskit.estimation.identification import (
    IDENTIFICATION_METHODS,
    RecursiveLeastSquares,
    _check_opts,
    _resolve_options,
)
from adcskit.estimation.kalman import KALMAN_FORMS, KalmanFilter, _check_cov, _check_model

__all__ = ["AugmentedEKFResult", "JointResult", "augmented_ekf", "joint_estimate"]

#: Methods that need a determined regression (no prior information).
_UNREGULARISED = {"qr", "gmres", "bicg", "cgs", "bicgstab", "lsqr"}


@dataclass(frozen=True, slots=True, repr=False, kw_only=True)
class JointResult(Result):
    """Output of :func:`joint_estimate`.

    Attributes
    ----------
    A : ndarray, shape (n, n)
        Final model estimate (``A_history[-1]``).
    B : ndarray, shape (n, p)
        Final input matrix (estimated if ``estimate_B``, else the given one).
    A_history : ndarray, shape (N, n, n)
        Model in use at each step (identified from the data up to ``y(t)``), last pass.
    x : ndarray, shape (N, n)
        Filtered state estimates ``x(t|t)`` of the last pass.
    innovations : ndarray, shape (N, m)
    nit : int
        Total solver iterations over all identification calls and passes.
    n_calls, n_failed : int
        Identification calls and how many returned ``success=False`` (their estimate is
        still used if finite, as S1's loop does).
    success, status, message : bool, int, str
    method : str

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[1.0, 0.1], [0.0, 1.0]])          # double integrator, dt = 0.1 s
    >>> B = np.array([[0.005], [0.1]])
    >>> C = np.eye(2)
    >>> u = np.sin(0.3 * np.arange(40))[:, None]         # N = 40 input samples
    >>> from adcskit.estimation import joint_estimate, simulate_linear
    >>> sim = simulate_linear(A, B, C, u, x0=[1.0, 0.0], R=1e-4, rng=0)
    >>> res = joint_estimate(sim.y, u, A_prior=np.eye(2), B=B, R=1e-4, method="qr")
    >>> type(res).__name__, res.A.shape, res.A_history.shape, res.x.shape
    ('JointResult', (2, 2), (40, 2, 2), (40, 2))
    """

    A: np.ndarray
    B: np.ndarray
    A_history: np.ndarray
    x: np.ndarray
    innovations: np.ndarray
    nit: int
    n_calls: int
    n_failed: int
    success: bool
    status: int
    message: str
    method: str


def joint_estimate(
    y,
    u,
    *,
    A_prior,
    B,
    C=None,
    Q=0.0,
    R=1.0,
    x0=None,
    P0=1.0,
    method: str = "adaptive-gmres-online",
    options: Mapping[str, Any] | None = None,
    estimate_B: bool = False,
    start: int | None = None,
    passes: int = 1,
    form: str = "predict-update",
    rng=None,
) -> JointResult:
    """Alternate Kalman filtering and least-squares model identification (S1's loop).

    Parameters
    ----------
    y : array_like, shape (N, n)
        Measurements ``y(t) = x(t) + v(t)`` (S1: ``C = I``, full-state measurements).
    u : array_like, shape (N, p)
        Inputs ``u(t)``.
    A_prior : array_like, shape (n, n)
        Prior model ``A0`` (before the change; S1's initial guess).
    B : array_like, shape (n, p)
        Known input matrix (S1), or the starting ``B`` when ``estimate_B``.
    C : array_like, shape (n, n), optional
        Measurement matrix; must be the identity (default) because the targets of the
        regression are the measurements themselves (S1 eq. 17).
    Q, R : array_like or float
        Kalman process- and measurement-noise covariances (scalars mean multiples of I).
    x0, P0 : array_like, optional
        Kalman prior (zeros and S1's ``P(1) = I`` by default).
    method : str
        Identification method (key of ``IDENTIFICATION_METHODS``).
    options : mapping, optional
        Options of the method; ``step`` of ``adaptive-gmres-offline`` is set by the loop.
    estimate_B : bool
        Identify ``[A B]`` instead of ``A``.
    start : int, optional
        Number of regression pairs before the first identification call. Default: ``q``
        (unknowns per row) for unregularised methods, 1 for prior-anchored ones.
    passes : int
        Passes over the manoeuvre.
    form : {"predict-update", "predictor"}
        Kalman recursion.
    rng : Generator or int, optional
        Random source (used by ``adaptive-gmres-online``); ``None`` means seed 0.

    Returns
    -------
    JointResult

    References
    ----------
    S1 eq. (14)-(18).

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[1.0, 0.1], [0.0, 1.0]])          # double integrator, dt = 0.1 s
    >>> B = np.array([[0.005], [0.1]])
    >>> C = np.eye(2)
    >>> u = np.sin(0.3 * np.arange(40))[:, None]         # N = 40 input samples
    >>> from adcskit.estimation import joint_estimate, simulate_linear
    >>> A_true = np.array([[1.0, 0.1], [-0.05, 0.98]])   # the model changed: spring + damping
    >>> sim = simulate_linear(A_true, B, C, u, x0=[1.0, 0.0], R=1e-4, rng=0)
    >>> res = joint_estimate(sim.y, u, A_prior=A, B=B, R=1e-4, method="qr")
    >>> res.success, res.x.shape
    (True, (40, 2))
    >>> bool(np.abs(res.A - A_true).max() < 0.05)
    True
    """
    check_choice("method", method, IDENTIFICATION_METHODS)
    opts = _resolve_options(method, options)
    _check_opts(method, opts)
    check_choice("form", form, KALMAN_FORMS)
    estimate_B = check_flag("estimate_B", estimate_B)
    A_prior = as_array("A_prior", A_prior, ndim=2)
    n = A_prior.shape[0]
    if C is None:
        C = np.eye(n)
    A_prior, B, C, Q, R = _check_model(A_prior, B, C, Q, R, a_name="A_prior")
    if C.shape != (n, n) or not np.allclose(C, np.eye(n)):
        raise InputError("C must be the identity: the regression targets are the measurements (S1 eq. 17)")
    p = B.shape[1]
    y = as_array("y", y, ndim=2)
    N = y.shape[0]
    if y.shape != (N, n):
        raise InputError(f"y must have shape (N, {n}); got {y.shape}")
    u = as_array("u", u, shape=(N, p))
    x0 = np.zeros(n) if x0 is None else as_array("x0", x0, shape=(n,))
    P0 = _check_cov("P0", P0, n)
    passes = check_int("passes", passes, minimum=1, maximum=10_000)
    q = n + p if estimate_B else n
    if start is None:
        start = q if method in _UNREGULARISED else 1
    start = check_int("start", start, minimum=1)
    gen = as_rng(rng)
    return _joint_kernel(y, u, A_prior, B, C, Q, R, x0, P0, method, opts, estimate_B, start, passes, form, gen)


def _joint_kernel(y, u, A_prior, B, C, Q, R, x0, P0, method, opts, estimate_B, start, passes, form, gen):
    N, n = y.shape
    Tp = np.hstack([A_prior, B]) if estimate_B else A_prior.copy()
    Theta = Tp.copy()
    Z_all = y[1:] if estimate_B else y[1:] - u[:-1] @ B.T  # targets of pairs s = 0..N-2
    Xf = np.empty((N, n))
    nus = np.empty((N, n))
    hist = np.empty((N, n, n))
    nit = n_calls = n_failed = 0
    kernel = IDENTIFICATION_METHODS[method][0]
    for _pass in range(passes):
        kf = KalmanFilter(x0, P0, form=form)
        rls = RecursiveLeastSquares(Theta, delta=opts["delta"], forgetting=opts["forgetting"]) if method == "rls" else None
        call = 0
        for t in range(N):
            if t >= start:  # pairs s = 0..t-1 available
                if rls is not None:
                    for s in range(rls.nit, t):
                        phi = np.concatenate([Xf[s], u[s]]) if estimate_B else Xf[s]
                        rls.update(phi, Z_all[s], validate=False)
                    Theta_new, ok, k_it = rls.Theta, bool(np.all(np.isfinite(rls.Theta))), 1
                else:
                    Phi = np.hstack([Xf[:t], u[:t]]) if estimate_B else Xf[:t]
                    if method == "adaptive-gmres-offline":
                        opts["step"] = call
                    out = kernel(Phi, Z_all[:t], Theta, Tp, opts, gen)
                    Theta_new, ok, k_it = out["Theta"], out["status"] == 0, out["nit"]
                n_calls += 1
                call += 1
                nit += int(k_it)
                if not ok:
                    n_failed += 1
                if np.all(np.isfinite(Theta_new)):
                    Theta = Theta_new
            A_cur = Theta[:, :n]
            B_cur = Theta[:, n:] if estimate_B else B
            hist[t] = A_cur
            Xf[t], _P, nus[t], _S = kf.step(y[t], u[t], A_cur, B_cur, C, Q, R, validate=False)
    ok = bool(np.all(np.isfinite(Xf)))
    return JointResult(
        A=Theta[:, :n].copy(),
        B=(Theta[:, n:] if estimate_B else B).copy(),
        A_history=hist,
        x=Xf,
        innovations=nus,
        nit=nit,
        n_calls=n_calls,
        n_failed=n_failed,
        success=ok,
        status=0 if ok else 1,
        message=(f"{n_calls} identification calls, {n_failed} unsuccessful" if ok
                 else "state estimate became non-finite"),
        method=method,
    )


# --------------------------------------------------------------------------- augmented EKF


@dataclass(frozen=True, slots=True, repr=False, kw_only=True)
class AugmentedEKFResult(Result):
    """Output of :func:`augmented_ekf`.

    Attributes
    ----------
    x : ndarray, shape (N, n)
        Filtered state estimates.
    p : ndarray, shape (N, n_p)
        Filtered parameter estimates (e.g. true/assumed inertia ratios, dimensionless).
    p_std : ndarray, shape (N, n_p)
        Their standard deviations from the filter covariance.
    A_history : ndarray, shape (N, n, n)
        ``model(p_hat(t))[0]``, the model implied by the parameter estimate.
    A : ndarray, shape (n, n)
        Final model.
    innovations : ndarray, shape (N, m)
    success, status, message, nit, nfev : as scipy
        ``nfev`` counts model evaluations.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.estimation import augmented_ekf, simulate_linear
    >>> def model(p):                                     # p[0] scales the input gain
    ...     return np.array([[1.0, 0.1], [0.0, 1.0]]), p[0] * np.array([[0.005], [0.1]])
    >>> u = np.sin(0.3 * np.arange(30))[:, None]
    >>> sim = simulate_linear(*model([2.0]), np.eye(2), u, R=1e-4, rng=0)
    >>> res = augmented_ekf(sim.y, u, model, [1.0], P_p0=1.0, C=np.eye(2), R=1e-4)
    >>> type(res).__name__, res.p.shape, res.A_history.shape, res.success
    ('AugmentedEKFResult', (30, 1), (30, 2, 2), True)
    """

    x: np.ndarray
    p: np.ndarray
    p_std: np.ndarray
    A_history: np.ndarray
    A: np.ndarray
    innovations: np.ndarray
    success: bool
    status: int
    message: str
    nit: int
    nfev: int


def augmented_ekf(
    y,
    u,
    model: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
    p0,
    *,
    P_p0,
    Q_p=0.0,
    C=None,
    Q=0.0,
    R=1.0,
    x0=None,
    P0=1.0,
    p_min: float = 0.05,
    fd_step: float = 1e-6,
) -> AugmentedEKFResult:
    """Estimate the state and physical model parameters with an augmented-state EKF.

    Augmented state ``z = [x; p]`` with ``x(t+1) = A_d(p) x + B_d(p) u + w`` and a random
    walk ``p(t+1) = p(t) + w_p``.

    Parameters
    ----------
    y : array_like, shape (N, m)
        Measurements ``y = C x + v``.
    u : array_like, shape (N, n_u)
        Inputs.
    model : callable
        ``model(p) -> (A_d, B_d)``, discrete model for parameters ``p`` (n_p,).
    p0 : array_like, shape (n_p,)
        Prior parameter mean (e.g. ones: the assumed inertias are right), each >= ``p_min``.
    P_p0 : array_like, shape (n_p, n_p) or float
        Prior parameter covariance (e.g. ``0.5**2`` for 50 % uncertainty).
    Q_p : array_like or float
        Parameter random-walk covariance per step (0: constant parameters).
    C, Q, R, x0, P0 : as in :func:`~adcskit.estimation.kalman.kalman_filter`.
    p_min : float
        Parameters are floored at ``p_min`` whenever the model is evaluated, its first call on
        ``p0`` included (a negative or zero inertia ratio has no model).
    fd_step : float
        Relative central-difference step for ``d(A_d x + B_d u)/dp``.

    Returns
    -------
    AugmentedEKFResult

    References
    ----------
    Simon (2006) §13.4; S1 (the baseline S1 does not run; its uncertainty is in the
    moments of inertia).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.estimation import augmented_ekf, simulate_linear
    >>> def model(p):                                     # p[0] scales the input gain
    ...     return np.array([[1.0, 0.1], [0.0, 1.0]]), p[0] * np.array([[0.005], [0.1]])
    >>> u = np.sin(0.3 * np.arange(60))[:, None]
    >>> sim = simulate_linear(*model([2.0]), np.eye(2), u, R=1e-4, rng=0)   # true p = 2
    >>> res = augmented_ekf(sim.y, u, model, [1.0], P_p0=1.0, C=np.eye(2), R=1e-4)
    >>> res.x.shape, res.p.shape, res.success
    ((60, 2), (60, 1), True)
    >>> bool(abs(res.p[-1, 0] - 2.0) < 0.1)
    True
    """
    check_callable("model", model)
    p0 = as_array("p0", p0, ndim=1)
    n_p = p0.shape[0]
    p_min = float(check_positive("p_min", p_min))  # > 0: the model is evaluated at the floor
    if np.any(p0 < p_min):
        i = int(np.argmin(p0 >= p_min))
        raise InputError(
            f"p0 must be >= p_min = {p_min:g} (the model has no meaning below its floor); "
            f"got p0[{i}] = {float(p0[i])!r}"
        )
    # the model is only ever evaluated at or above the documented floor, the first call included
    pair = model(np.maximum(p0, p_min))
    if not (isinstance(pair, tuple | list) and len(pair) == 2):
        raise InputTypeError(
            f"model must return a pair (A_d, B_d); model(max(p0, p_min)) returned {short_repr(pair)}")
    A0, B0 = pair
    A0 = as_array("model(p0)[0]", A0, ndim=2)
    n = A0.shape[0]
    if C is None:
        C = np.eye(n)
    A0, B0, C, Q, R = _check_model(A0, B0, C, Q, R)
    m = C.shape[0]
    y = as_array("y", y, ndim=2)
    N = y.shape[0]
    if y.shape[1] != m:
        raise InputError(f"y must have shape (N, {m}); got {y.shape}")
    u = as_array("u", u, shape=(N, B0.shape[1]))
    x0 = np.zeros(n) if x0 is None else as_array("x0", x0, shape=(n,))
    P0 = _check_cov("P0", P0, n)
    P_p0 = _check_cov("P_p0", P_p0, n_p)
    Q_p = _check_cov("Q_p", Q_p, n_p)
    h = check_positive("fd_step", fd_step)

    nz = n + n_p
    z = np.concatenate([x0, p0])
    Pz = np.zeros((nz, nz))
    Pz[:n, :n], Pz[n:, n:] = P0, P_p0
    Qz = np.zeros((nz, nz))
    Qz[:n, :n], Qz[n:, n:] = Q, Q_p
    Cz = np.hstack([C, np.zeros((m, n_p))])
    xs, ps, pstd = np.empty((N, n)), np.empty((N, n_p)), np.empty((N, n_p))
    hist, nus = np.empty((N, n, n)), np.empty((N, m))
    nfev = 0
    Iz = np.eye(nz)
    for t in range(N):
        # measurement update (Joseph form)
        nu = y[t] - Cz @ z
        S = Cz @ Pz @ Cz.T + R
        cf = cho_factor(0.5 * (S + S.T), lower=True, check_finite=False)
        K = cho_solve(cf, Cz @ Pz, check_finite=False).T
        z = z + K @ nu
        IKC = Iz - K @ Cz
        Pz = IKC @ Pz @ IKC.T + K @ R @ K.T
        x_f, p_f = z[:n], np.maximum(z[n:], p_min)
        Ad, Bd = model(p_f)
        nfev += 1
        xs[t], ps[t], nus[t], hist[t] = x_f, z[n:], nu, Ad
        pstd[t] = np.sqrt(np.clip(np.diag(Pz)[n:], 0.0, None))
        # time update with a central-difference parameter Jacobian
        J = np.empty((n, n_p))
        for i in range(n_p):
            d = h * max(1.0, abs(p_f[i]))
            e = np.zeros(n_p)
            e[i] = d
            Ap, Bp = model(p_f + e)
            lo = np.maximum(p_f - e, p_min)  # never below the documented floor
            Am, Bm = model(lo)
            J[:, i] = ((Ap - Am) @ x_f + (Bp - Bm) @ u[t]) / (d + p_f[i] - lo[i])
            nfev += 2
        F = np.zeros((nz, nz))
        F[:n, :n], F[:n, n:], F[n:, n:] = Ad, J, np.eye(n_p)
        z = np.concatenate([Ad @ x_f + Bd @ u[t], z[n:]])
        Pz = F @ Pz @ F.T + Qz
        Pz = 0.5 * (Pz + Pz.T)
    ok = bool(np.all(np.isfinite(xs)) and np.all(np.isfinite(Pz)))
    return AugmentedEKFResult(
        x=xs,
        p=ps,
        p_std=pstd,
        A_history=hist,
        A=hist[-1].copy() if N else A0,
        innovations=nus,
        success=ok,
        status=0 if ok else 1,
        message="augmented EKF completed" if ok else "estimate became non-finite",
        nit=N,
        nfev=nfev,
    )
