"""Linear discrete Kalman filtering in two equivalent forms, and a seeded linear simulator.

Model (time index ``t = 0 .. N-1``)::

    x(t+1) = A x(t) + B u(t) + w(t),   w ~ N(0, Q)
    y(t)   = C x(t) + v(t),            v ~ N(0, R)

Two forms are provided through the registry :data:`KALMAN_FORMS`:

``"predict-update"``
    The textbook filter: measurement update ``x(t|t)`` with the Kalman gain
    ``K_f = P C^T S^-1`` and the Joseph-form covariance
    ``P(t|t) = (I - K_f C) P (I - K_f C)^T + K_f R K_f^T``, then the time update
    ``x(t+1|t) = A x(t|t) + B u(t)``, ``P(t+1|t) = A P(t|t) A^T + Q``.
``"predictor"``
    The one-step predictor of S1 eq. (18), written correctly:
    ``x(t+1|t) = A x(t|t-1) + B u(t) + K_p (y(t) - C x(t|t-1))`` with the predictor gain
    ``K_p = A P C^T S^-1`` and ``S = C P C^T + R``, and the Riccati update in the Joseph-like
    form that is valid (and stays symmetric positive semi-definite) for any gain,
    ``P(t+1|t) = (A - K_p C) P (A - K_p C)^T + K_p R K_p^T + Q``.

S1 prints the predictor with ``R = I``, no process noise and the covariance update
``P+ = A P A^T - A L C P C^T L^T A^T`` in which ``L = A P C^T (I + C P C^T)^-1`` already
contains ``A``; the printed update applies ``A`` twice and omits ``Q``. With ``Q = 0`` and
``R = I`` our predictor reduces to the algebraically correct version of that equation
(``P+ = A P A^T - K_p S K_p^T``). The two forms give the same ``x(t+1|t)`` and ``P(t+1|t)``
up to rounding; the tests check this to 1e-10.

Hand-written here: the recursions themselves (a few lines each). scipy has no discrete
Kalman filter; filterpy is unmaintained and not a dependency. Every inverse is a Cholesky
solve, never an explicit inverse: LAPACK ``potrf``/``potrs`` through ``scipy.linalg.lapack``, the
routines ``scipy.linalg.cho_factor``/``cho_solve`` call, without their per-call checks (≈ 10 of
15 µs per call on S1's 2 x 2 and 6 x 6 innovation covariances, two calls per filter step;
bit-identical, tested against ``cho_factor``/``cho_solve``).

References
----------
S1: "Adaptive GMRES for joint attitude-state and model estimation", eq. (2) (measurement
model ``y = C x + v`` with ``v ~ N(0, 1)``) and eq. (18) (Kalman predictor).
Simon, D., *Optimal State Estimation*, Wiley 2006, §5.1 (one-step predictor) and eq. (5.19)
(Joseph form).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import LinAlgError
from scipy.linalg.lapack import dpotrf, dpotrs

from adcskit._results import Result
from adcskit._validation import as_array, as_rng, check_choice, check_flag, check_positive
from adcskit.errors import InputError

__all__ = [
    "KALMAN_FORMS",
    "KalmanFilter",
    "KalmanResult",
    "LinearSimulation",
    "kalman_filter",
    "simulate_linear",
]

KALMAN_FORMS: dict[str, str] = {
    "predict-update": "measurement update (Joseph form) then time update",
    "predictor": "one-step predictor of S1 eq. 18 with process noise, Joseph-like Riccati update",
}


# --------------------------------------------------------------------------- kernels


def _cho_factor(S):
    """``scipy.linalg.cho_factor(S, lower=True, check_finite=False)`` for a float64 ``S``, unchecked.

    The same LAPACK call (``dpotrf``, lower, triangle above not cleaned), so the same bits,
    without scipy's per-call argument checks and batch wrapper, which cost several times the
    factorisation of the small matrices of a filter step. Raises ``LinAlgError`` with scipy's
    message when ``S`` is not positive definite.
    """
    c, info = dpotrf(S, lower=1, clean=0)
    if info > 0:
        raise LinAlgError(f"{info}-th leading minor of the array is not positive definite")
    if info < 0:
        raise ValueError(f"LAPACK reported an illegal value in {-info}-th argument on entry to \"POTRF\".")
    return c, True


def _cho_solve(S_cf, b):
    """``scipy.linalg.cho_solve(S_cf, b, check_finite=False)`` for a factor of :func:`_cho_factor`,
    unchecked (the same LAPACK ``dpotrs`` call)."""
    x, info = dpotrs(S_cf[0], b, lower=1)
    if info != 0:
        raise ValueError(f"illegal value in {-info}th argument of internal potrs")
    return x


def _innovation(x_pred, P_pred, y, C, R):
    """Innovation ``nu``, its covariance ``S`` and the Cholesky factor of ``S``."""
    nu = y - C @ x_pred
    S = C @ P_pred @ C.T + R
    S = 0.5 * (S + S.T)
    return nu, S, _cho_factor(S)


def _measurement_update(x_pred, P_pred, nu, C, R, S_cf):
    """Filtered state and Joseph-form covariance."""
    K = _cho_solve(S_cf, C @ P_pred).T  # P C^T S^-1 (P, S symmetric)
    x_f = x_pred + K @ nu
    IKC = np.eye(P_pred.shape[0]) - K @ C
    P_f = IKC @ P_pred @ IKC.T + K @ R @ K.T
    return x_f, 0.5 * (P_f + P_f.T)


def _step_predict_update(x_pred, P_pred, y, u, A, B, C, Q, R):
    nu, S, S_cf = _innovation(x_pred, P_pred, y, C, R)
    x_f, P_f = _measurement_update(x_pred, P_pred, nu, C, R, S_cf)
    x_next = A @ x_f + B @ u
    P_next = A @ P_f @ A.T + Q
    return x_f, P_f, x_next, 0.5 * (P_next + P_next.T), nu, S, S_cf


def _step_predictor(x_pred, P_pred, y, u, A, B, C, Q, R):
    nu, S, S_cf = _innovation(x_pred, P_pred, y, C, R)
    Kp = _cho_solve(S_cf, C @ P_pred @ A.T).T  # A P C^T S^-1
    x_next = A @ x_pred + B @ u + Kp @ nu
    AKC = A - Kp @ C
    P_next = AKC @ P_pred @ AKC.T + Kp @ R @ Kp.T + Q
    # filtered quantities as a by-product (not used by the recursion)
    x_f, P_f = _measurement_update(x_pred, P_pred, nu, C, R, S_cf)
    return x_f, P_f, x_next, 0.5 * (P_next + P_next.T), nu, S, S_cf


_STEPS = {"predict-update": _step_predict_update, "predictor": _step_predictor}


def _loglik_term(nu, S_cf):
    m = nu.shape[0]
    logdet = 2.0 * np.sum(np.log(np.abs(np.diag(S_cf[0]))))
    return -0.5 * (nu @ _cho_solve(S_cf, nu) + logdet + m * np.log(2 * np.pi))


# --------------------------------------------------------------------------- results


@dataclass(frozen=True, slots=True, repr=False, kw_only=True)
class KalmanResult(Result):
    """Output of :func:`kalman_filter`.

    Attributes
    ----------
    x : ndarray, shape (N, n)
        Filtered estimates ``x(t|t)`` (state units).
    P : ndarray, shape (N, n, n)
        Filtered covariances ``P(t|t)``.
    x_pred : ndarray, shape (N + 1, n)
        Predicted estimates ``x(t|t-1)``; row 0 is the prior ``x0``, row ``N`` the
        prediction past the last measurement.
    P_pred : ndarray, shape (N + 1, n, n)
        Predicted covariances ``P(t|t-1)``.
    innovations : ndarray, shape (N, m)
        ``y(t) - C x(t|t-1)`` (measurement units).
    S : ndarray, shape (N, m, m)
        Innovation covariances ``C P(t|t-1) C^T + R``.
    loglik : float
        Gaussian log-likelihood of the innovations.
    form : str
        Which recursion produced the result (key of :data:`KALMAN_FORMS`).
    success, status, message : bool, int, str
        ``success`` is False if a covariance became non-finite (``status=1``).
    nit : int
        Number of filter steps.

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[1.0, 0.1], [0.0, 1.0]])          # double integrator, dt = 0.1 s
    >>> B = np.array([[0.005], [0.1]])
    >>> C = np.eye(2)
    >>> u = np.sin(0.3 * np.arange(40))[:, None]         # N = 40 input samples
    >>> from adcskit.estimation import kalman_filter, simulate_linear
    >>> sim = simulate_linear(A, B, C, u, R=0.01, rng=0)
    >>> res = kalman_filter(A, B, C, sim.y, u, R=0.01)
    >>> type(res).__name__, res.x.shape, res.x_pred.shape, res.P.shape, res.success
    ('KalmanResult', (40, 2), (41, 2), (40, 2, 2), True)
    """

    x: np.ndarray
    P: np.ndarray
    x_pred: np.ndarray
    P_pred: np.ndarray
    innovations: np.ndarray
    S: np.ndarray
    loglik: float
    form: str
    success: bool = True
    status: int = 0
    message: str = "filter completed"
    nit: int = 0


@dataclass(frozen=True, slots=True, kw_only=True)
class LinearSimulation(Result):
    """Output of :func:`simulate_linear`: true states ``x`` (N+1, n), measurements ``y``
    (N, m) taken at ``x[0..N-1]``, the inputs ``u`` (N, p) and the noise draws.

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[1.0, 0.1], [0.0, 1.0]])          # double integrator, dt = 0.1 s
    >>> B = np.array([[0.005], [0.1]])
    >>> C = np.eye(2)
    >>> u = np.sin(0.3 * np.arange(40))[:, None]         # N = 40 input samples
    >>> from adcskit.estimation import simulate_linear
    >>> sim = simulate_linear(A, B, C, u, rng=0)
    >>> type(sim).__name__, sim.x.shape, sim.y.shape, sim.u.shape
    ('LinearSimulation', (41, 2), (40, 2), (40, 1))
    """

    x: np.ndarray
    y: np.ndarray
    u: np.ndarray
    v: np.ndarray
    w: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))


# --------------------------------------------------------------------------- validation


def _check_model(A, B, C, Q, R, *, a_name="A"):
    A = as_array(a_name, A, ndim=2)
    n = A.shape[0]
    if A.shape != (n, n):
        raise InputError(f"{a_name} must be square (n, n); got shape {A.shape}")
    B = as_array("B", B, ndim=2)
    if B.shape[0] != n:
        raise InputError(f"B must have shape ({n}, p) to match {a_name}; got shape {B.shape}")
    C = as_array("C", C, ndim=2)
    if C.shape[1] != n:
        raise InputError(f"C must have shape (m, {n}) to match {a_name}; got shape {C.shape}")
    m = C.shape[0]
    Q = _check_cov("Q", Q, n)
    R = _check_cov("R", R, m, positive=True)
    return A, B, C, Q, R


def _check_cov(name, value, n, *, positive=False):
    M = as_array(name, value)
    if M.ndim == 0:
        # a scalar variance: exactly >= 0 (> 0); the eigenvalue tolerance below is for matrices
        M = check_positive(name, M, allow_zero=not positive) * np.eye(n)
    if M.shape != (n, n):
        raise InputError(f"{name} must be a scalar or have shape ({n}, {n}); got shape {M.shape}")
    if not np.allclose(M, M.T, rtol=1e-10, atol=1e-14 * max(1.0, np.abs(M).max())):
        raise InputError(f"{name} must be symmetric")
    ev = np.linalg.eigvalsh(M)
    tol = 1e-12 * max(1.0, float(np.abs(ev).max()))
    if (positive and ev.min() <= 0) or ev.min() < -tol:
        what = "positive definite" if positive else "positive semi-definite"
        raise InputError(f"{name} must be {what}; smallest eigenvalue {ev.min():.3g}")
    return 0.5 * (M + M.T)


class KalmanFilter:
    """A steppable linear Kalman filter (the state of :func:`kalman_filter`).

    The model matrices may change from step to step (the joint estimation loop replaces
    ``A`` by the latest identified model), so they are arguments of :meth:`step`.

    Parameters
    ----------
    x0 : array_like, shape (n,)
        Prior mean ``x(0|-1)`` (state units).
    P0 : array_like, shape (n, n) or scalar
        Prior covariance ``P(0|-1)``; a scalar means ``P0 * I``.
    form : {"predict-update", "predictor"}
        Recursion (see :data:`KALMAN_FORMS`).

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[1.0, 0.1], [0.0, 1.0]])          # double integrator, dt = 0.1 s
    >>> B = np.array([[0.005], [0.1]])
    >>> C = np.eye(2)
    >>> u = np.sin(0.3 * np.arange(40))[:, None]         # N = 40 input samples
    >>> from adcskit.estimation import KalmanFilter
    >>> kf = KalmanFilter(np.zeros(2), 1.0)
    >>> y0, u0 = np.array([0.5, 0.1]), np.array([0.0])
    >>> x_f, P_f, nu, S = kf.step(y0, u0, A, B, C, 0.0, 0.01 * np.eye(2))   # Q = 0, R = 0.01 I
    >>> x_f.round(4), P_f.shape, nu.shape
    (array([0.495, 0.099]), (2, 2), (2,))
    """

    def __init__(self, x0, P0, *, form: str = "predict-update") -> None:
        self.x_pred = as_array("x0", x0, ndim=1)
        n = self.x_pred.shape[0]
        self.P_pred = _check_cov("P0", P0, n)
        self.form = check_choice("form", form, KALMAN_FORMS)
        self._step = _STEPS[form]

    def step(self, y, u, A, B, C, Q, R, *, validate: bool = True):
        """Process measurement ``y(t)`` and input ``u(t)``; returns ``(x_f, P_f, nu, S)``.

        Parameters
        ----------
        y : array_like, shape (m,)
            Measurement ``y(t)``.
        u : array_like, shape (p,)
            Input ``u(t)``.
        A, B, C : array_like
            Model matrices of shapes (n, n), (n, p) and (m, n); ``n`` is the state size of
            ``x0``.
        Q : array_like, shape (n, n) or float
            Process-noise covariance, symmetric positive semi-definite (scalar -> ``Q * I``).
        R : array_like, shape (m, m) or float
            Measurement-noise covariance, symmetric positive definite (scalar -> ``R * I``).
        validate : bool
            Check every argument (finite real numbers, consistent shapes, ``Q`` positive
            semi-definite, ``R`` positive definite) and raise
            :class:`~adcskit.errors.InputError` naming the argument otherwise (default).
            ``False`` is the fast path for inner loops that pass already validated float
            arrays (:func:`kalman_filter`, the joint estimator): nothing is checked, ``Q`` and
            ``R`` must be ``(n, n)`` and ``(m, m)`` arrays, and the result of invalid input is
            undefined. Both paths give bit-identical results on valid array input.
        """
        if validate is not False and (validate is True or check_flag("validate", validate)):
            y, u, A, B, C, Q, R = self._check_step(y, u, A, B, C, Q, R)
        x_f, P_f, self.x_pred, self.P_pred, nu, S, _ = self._step(
            self.x_pred, self.P_pred, y, u, A, B, C, Q, R
        )
        return x_f, P_f, nu, S

    def _check_step(self, y, u, A, B, C, Q, R):
        n = self.x_pred.shape[0]
        A = as_array("A", A, ndim=2)
        if A.shape != (n, n):
            raise InputError(f"A must have shape ({n}, {n}) to match x0; got shape {A.shape}")
        A, B, C, Q, R = _check_model(A, B, C, Q, R)
        m, p = C.shape[0], B.shape[1]
        y = as_array("y", y, ndim=(0, 1))
        if y.shape != (m,) and not (m == 1 and y.shape == ()):
            raise InputError(f"y must have shape ({m},) to match C; got shape {y.shape}")
        u = as_array("u", u, ndim=(0, 1))
        if u.shape != (p,) and not (p == 1 and u.shape == ()):
            raise InputError(f"u must have shape ({p},) to match B; got shape {u.shape}")
        return y.reshape(m), u.reshape(p), A, B, C, Q, R


def kalman_filter(
    A,
    B,
    C,
    y,
    u=None,
    *,
    Q=0.0,
    R=1.0,
    x0=None,
    P0=1.0,
    form: str = "predict-update",
) -> KalmanResult:
    """Run a linear Kalman filter over a measurement sequence.

    Parameters
    ----------
    A : array_like, shape (n, n)
        State transition matrix (discrete time).
    B : array_like, shape (n, p)
        Input matrix.
    C : array_like, shape (m, n)
        Measurement matrix.
    y : array_like, shape (N, m)
        Measurements ``y(t) = C x(t) + v(t)``.
    u : array_like, shape (N, p), optional
        Inputs applied between ``t`` and ``t + 1`` (zeros if omitted).
    Q : array_like, shape (n, n) or float
        Process-noise covariance (scalar -> ``Q * I``). S1 does not specify it.
    R : array_like, shape (m, m) or float
        Measurement-noise covariance (S1 eq. 2 and 18: ``R = I``).
    x0 : array_like, shape (n,), optional
        Prior mean ``x(0|-1)`` (zeros if omitted).
    P0 : array_like, shape (n, n) or float
        Prior covariance (S1 eq. 18: ``P(1) = I``).
    form : {"predict-update", "predictor"}
        Recursion, see :data:`KALMAN_FORMS`; both give the same estimates.

    Returns
    -------
    KalmanResult
        Filtered and predicted estimates, covariances, innovations and log-likelihood.

    References
    ----------
    S1 eq. (18) (predictor form); Simon (2006) §5.1 and eq. (5.19) (Joseph form).

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[1.0, 0.1], [0.0, 1.0]])          # double integrator, dt = 0.1 s
    >>> B = np.array([[0.005], [0.1]])
    >>> C = np.eye(2)
    >>> u = np.sin(0.3 * np.arange(40))[:, None]         # N = 40 input samples
    >>> from adcskit.estimation import kalman_filter, simulate_linear
    >>> sim = simulate_linear(A, B, C, u, x0=[1.0, 0.0], R=0.01, Q=1e-6, rng=0)
    >>> res = kalman_filter(A, B, C, sim.y, u, Q=1e-6, R=0.01, x0=[1.0, 0.0])
    >>> res.x.shape, res.P.shape, res.innovations.shape, res.success
    ((40, 2), (40, 2, 2), (40, 2), True)
    >>> rms_filter = np.sqrt(np.mean((res.x - sim.x[:-1]) ** 2))
    >>> rms_raw = np.sqrt(np.mean((sim.y - sim.x[:-1]) ** 2))
    >>> bool(rms_filter < rms_raw)                         # the filter beats the raw measurements
    True
    """
    A, B, C, Q, R = _check_model(A, B, C, Q, R)
    n, p, m = A.shape[0], B.shape[1], C.shape[0]
    y = as_array("y", y, ndim=2)
    if y.shape[1] != m:
        raise InputError(f"y must have shape (N, {m}) to match C; got shape {y.shape}")
    N = y.shape[0]
    if u is None:
        u = np.zeros((N, p))
    u = as_array("u", u, ndim=2)
    if u.shape != (N, p):
        raise InputError(f"u must have shape ({N}, {p}) to match y and B; got shape {u.shape}")
    x0 = np.zeros(n) if x0 is None else as_array("x0", x0, shape=(n,))
    kf = KalmanFilter(x0, P0, form=form)

    xs = np.empty((N, n))
    Ps = np.empty((N, n, n))
    xp = np.empty((N + 1, n))
    Pp = np.empty((N + 1, n, n))
    nus = np.empty((N, m))
    Ss = np.empty((N, m, m))
    xp[0], Pp[0] = kf.x_pred, kf.P_pred
    loglik = 0.0
    step = _STEPS[form]
    x_pred, P_pred = kf.x_pred, kf.P_pred
    for t in range(N):
        xs[t], Ps[t], x_pred, P_pred, nus[t], Ss[t], S_cf = step(
            x_pred, P_pred, y[t], u[t], A, B, C, Q, R
        )
        xp[t + 1], Pp[t + 1] = x_pred, P_pred
        loglik += _loglik_term(nus[t], S_cf)
    ok = bool(np.all(np.isfinite(Pp)))
    return KalmanResult(
        x=xs,
        P=Ps,
        x_pred=xp,
        P_pred=Pp,
        innovations=nus,
        S=Ss,
        loglik=float(loglik),
        form=form,
        success=ok,
        status=0 if ok else 1,
        message="filter completed" if ok else "covariance became non-finite",
        nit=N,
    )


def simulate_linear(A, B, C, u, *, x0=None, R=1.0, Q=0.0, rng=None) -> LinearSimulation:
    """Simulate ``x(t+1) = A x + B u + w``, ``y = C x + v`` with Gaussian noise (seeded).

    Parameters
    ----------
    A, B, C : array_like
        Discrete model, shapes (n, n), (n, p), (m, n).
    u : array_like, shape (N, p)
        Inputs.
    x0 : array_like, shape (n,), optional
        Initial true state (zeros if omitted).
    R : array_like or float
        Measurement-noise covariance (S1 eq. 2: ``v ~ N(0, 1)``, i.e. ``R = I``).
    Q : array_like or float
        Process-noise covariance (0: none, as in S1).
    rng : Generator or int, optional
        Random source; ``None`` means seed 0.

    Returns
    -------
    LinearSimulation
        States ``x`` (N+1, n), measurements ``y`` (N, m), inputs and noise draws.

    References
    ----------
    S1 eq. (1)-(2).

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[1.0, 0.1], [0.0, 1.0]])          # double integrator, dt = 0.1 s
    >>> B = np.array([[0.005], [0.1]])
    >>> C = np.eye(2)
    >>> u = np.sin(0.3 * np.arange(40))[:, None]         # N = 40 input samples
    >>> from adcskit.estimation import simulate_linear
    >>> sim = simulate_linear(A, B, C, u, x0=[1.0, 0.0], R=0.01, rng=0)
    >>> sim.x.shape, sim.y.shape
    ((41, 2), (40, 2))
    >>> np.allclose(sim.x[1], A @ sim.x[0] + B @ u[0])     # noise-free dynamics (Q = 0)
    True
    >>> again = simulate_linear(A, B, C, u, x0=[1.0, 0.0], R=0.01, rng=0)
    >>> bool(np.array_equal(again.y, sim.y))              # seeded: reproducible
    True
    """
    A, B, C, Q, R = _check_model(A, B, C, Q, R)
    n, p, m = A.shape[0], B.shape[1], C.shape[0]
    u = as_array("u", u, ndim=2)
    if u.shape[1] != p:
        raise InputError(f"u must have shape (N, {p}) to match B; got shape {u.shape}")
    N = u.shape[0]
    x0 = np.zeros(n) if x0 is None else as_array("x0", x0, shape=(n,))
    gen = as_rng(rng)
    v = gen.standard_normal((N, m)) @ np.linalg.cholesky(R).T
    if np.any(Q):
        w = gen.standard_normal((N, n)) @ _psd_sqrt(Q).T
    else:
        w = np.zeros((N, n))
    x = np.empty((N + 1, n))
    x[0] = x0
    with np.errstate(over="ignore", invalid="ignore"):
        for t in range(N):
            x[t + 1] = A @ x[t] + B @ u[t] + w[t]
        y = x[:N] @ C.T + v
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise InputError(f"the simulated state overflows float64 within {N} steps: A is too unstable "
                         f"(spectral radius {np.abs(np.linalg.eigvals(A)).max():.3g}) for this horizon")
    return LinearSimulation(x=x, y=y, u=u, v=v, w=w)


def _psd_sqrt(M):
    ev, V = np.linalg.eigh(M)
    return V * np.sqrt(np.clip(ev, 0.0, None))
