"""Wahba's problem: batched point solvers (TRIAD, q-method, QUEST, ESOQ2, SVD, FOAM, FLAE).

Wahba's problem (Wahba 1965; S0 eq. 1): find the attitude matrix ``A`` minimising
``L(A) = 1/2 Σ a_i ||b_i − A r_i||²`` for body-frame observations ``b_i`` and reference
vectors ``r_i``. All optimal methods solve Davenport's eigenproblem ``K q = λ_max q``
(S0 eq. 2) in different ways; TRIAD is the classic sub-optimal two-vector solution.

The solvers run in compiled numba kernels (:mod:`adcskit.determination._kernels`): a
parallel loop for batches of 4096 problems or more, a serial loop for single calls and small
batches. No kept library solves batches of Wahba problems (scipy's
``Rotation.align_vectors`` takes one problem per call), hence the hand-written kernels.

Conventions: quaternion scalar last, ``A(q) = (q4² − |e|²) I + 2 e eᵀ − 2 q4 [e×]`` maps
reference-frame components to body-frame components (``b ≈ A(q) r``), canonical sign
``q4 >= 0``. Vectors need not be unit length: each is normalised (its length carries no
information here; the weights carry the confidence).

References
----------
.. [1] Markley, F. L. and Crassidis, J. L., *Fundamentals of Spacecraft Attitude
   Determination and Control*, Springer, 2014, §5.2–5.5 (q-method, QUEST, ESOQ2, SVD,
   FOAM, covariance eq. 5.66 / 5.99).
.. [2] Shuster, M. D. and Oh, S. D., "Three-axis attitude determination from vector
   observations", JGC 4(1), 1981 (QUEST, method of sequential rotations).
.. [3] Mortari, D., "ESOQ-2 single-point algorithm for fast optimal spacecraft attitude
   determination", Adv. Astronaut. Sci. 95, 1997.
.. [4] Markley, F. L., "Attitude determination using vector observations and the singular
   value decomposition", J. Astronaut. Sci. 36(3), 1988; "... a fast optimal matrix
   algorithm", J. Astronaut. Sci. 41(2), 1993 (FOAM).
.. [5] S0 (Ghadiri et al., robust min-max attitude determination), eqs. 1–2.
.. [6] Wu, J., Zhou, Z., Gao, B., Li, R., Cheng, Y. and Fourati, H., "Fast linear quaternion
   attitude estimator using vector observations", IEEE Trans. Autom. Sci. Eng. 15(1),
   2018, 307–319 (FLAE, eqs. 48–55).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from adcskit._results import Result
from adcskit._validation import as_array, check_choice, check_flag, short_repr
from adcskit.determination import _kernels as _k
from adcskit.errors import InputError, InputTypeError

__all__ = ["METHODS", "STATUS_MESSAGES", "WahbaResult", "solve_wahba", "wahba_loss", "davenport_k"]

#: Registry of point solvers: name -> (kernel code, optimal?, one-line description).
METHODS: dict[str, tuple[int, bool, str]] = {
    "triad": (_k.TRIAD, False, "TRIAD on the two heaviest non-parallel observations (sub-optimal)"),
    "q-method": (_k.QMETHOD, True, "Davenport's q-method: symmetric 4x4 eigen-decomposition (LAPACK)"),
    "quest": (_k.QUEST, True, "QUEST: Newton on the characteristic polynomial, sequential rotations"),
    "esoq2": (_k.ESOQ2, True, "ESOQ2: rotation axis as null vector of a 3x3 matrix, sequential rotations"),
    "svd": (_k.SVD, True, "Markley's SVD method on the attitude profile matrix B"),
    "foam": (_k.FOAM, True, "Markley's fast optimal attitude matrix (FOAM)"),
    "two-vector": (_k.TWO_VECTOR, True, "Markley's closed-form optimum for exactly two observations"),
    "flae": (_k.FLAE, True, "FLAE (Wu et al. 2018): symbolic quartic root, Gauss-Jordan eigenvector"),
}

#: Per-problem status codes and their messages.
STATUS_MESSAGES: dict[int, str] = {
    _k.OK: "solved",
    _k.NONFINITE: "an observation, reference vector or weight is NaN or infinite",
    _k.ZERO_LENGTH: "an observation or reference vector has zero length",
    _k.TOO_FEW: "fewer than 2 observations",
    _k.COLLINEAR_BODY: "all body vectors are parallel: rotation about them is undetermined",
    _k.COLLINEAR_REF: "all reference vectors are parallel: rotation about them is undetermined",
    _k.NOT_CONVERGED: "solver did not converge",
}

_PARALLEL_MIN = 4096


@dataclass(frozen=True, slots=True, repr=False)
class WahbaResult(Result):
    """Solution of one or a batch of Wahba problems.

    Attributes
    ----------
    q : ndarray, shape (4,) or (N, 4)
        Optimal quaternion, scalar last, ``b ≈ A(q) r``, ``q4 >= 0``. NaN where a problem
        failed.
    loss : float or ndarray (N,)
        Wahba loss ``1/2 Σ a_i ||b_i − A r_i||²`` at ``q`` with the caller's weights and the
        normalised vectors [dimensionless, weights' units].
    cov : ndarray, shape (3, 3) or (N, 3, 3)
        Attitude-error covariance in the body frame [rad²], ``P = [Σ a_i (I − b_i b_iᵀ)]⁻¹``
        (Markley & Crassidis 2014 eq. 5.66), reading the weights as ``a_i = 1/σ_i²``
        [rad⁻²]. With normalised weights multiply by the total variance ``σ_tot²``.
    cond : float or ndarray (N,)
        Frobenius-norm condition number of the Fisher information ``Σ a_i (I − b_i b_iᵀ)``
        (``inf`` when one axis is unobservable); large values mean poorly observed attitude.
    success : bool or ndarray (N,)
        Whether each problem was solved.
    status : int or ndarray (N,)
        Status code per problem (keys of :data:`STATUS_MESSAGES`).
    message : str
        Summary: ``"solved"`` or the count of failures of each kind.
    method : str
        Solver used.
    fallback : bool or ndarray (N,)
        QUEST/ESOQ2/FOAM/FLAE only: the fast path's eigen-residual exceeded ``64 ε`` (or its
        Newton iteration did not converge) and the problem was re-solved by the q-method.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.determination import solve_wahba
    >>> res = solve_wahba([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    >>> type(res).__name__, res.success, res.message
    ('WahbaResult', True, 'solved')
    >>> res.q.round(12) + 0.0, res.cov.shape
    (array([0., 0., 0., 1.]), (3, 3))
    >>> sorted(res.to_dict())[:3]
    ['cond', 'cov', 'fallback']
    """

    q: np.ndarray
    loss: Any
    cov: np.ndarray
    cond: Any
    success: Any
    status: Any
    message: str
    method: str
    fallback: Any

    def messages(self) -> list[str]:
        """One message per problem (a single-element list for a single problem)."""
        return [STATUS_MESSAGES[int(s)] for s in np.atleast_1d(self.status)]


_SLOT_SETTERS = tuple(getattr(WahbaResult, name).__set__ for name in WahbaResult.__slots__)


def _single_result(buf: np.ndarray, method: str) -> WahbaResult:
    """Fast constructor for the single-call path (slot descriptors, ~3x cheaper than the
    frozen dataclass ``__init__``; the instance is as frozen as any other)."""
    res = object.__new__(WahbaResult)
    values = (buf[0:4], float(buf[4]), buf[7:16].reshape(3, 3), float(buf[5]), True, 0, "solved",
              method, bool(buf[6]))
    for setter, value in zip(_SLOT_SETTERS, values):
        setter(res, value)
    return res


def _as_vectors(name: str, value: Any) -> np.ndarray:
    if isinstance(value, np.ndarray) and value.dtype == np.float64:
        arr = value  # read only by the kernels: no copy needed
    else:
        arr = as_array(name, value, finite=False)
    if arr.ndim not in (2, 3) or arr.shape[-1] != 3:
        raise InputError(
            f"{name} must have shape (n, 3) or (N, n, 3) (n observations of 3-vectors); "
            f"got shape {arr.shape}"
        )
    return arr


_UNIT_WEIGHTS: dict[int, np.ndarray] = {}


def _unit_weights(n: int) -> np.ndarray:
    """Cached read-only ones(n) for single calls without weights."""
    w = _UNIT_WEIGHTS.get(n)
    if w is None:
        w = np.ones(n)  # writeable: numba compiles read-only arrays as a separate type
        _UNIT_WEIGHTS[n] = w
    return w


def _prepare(body: Any, ref: Any, weights: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    b = _as_vectors("body", body)
    r = _as_vectors("ref", ref)
    if b.ndim == 3 and r.ndim == 2 and r.shape == b.shape[1:]:
        r = np.broadcast_to(r, b.shape)  # one reference set shared by every problem
    elif r.ndim == 3 and b.ndim == 2 and b.shape == r.shape[1:]:
        b = np.broadcast_to(b, r.shape)
    if b.shape != r.shape:
        raise InputError(
            "body and ref must have the same shape, or one of them (n, 3) shared by a batch "
            f"(N, n, 3); got {b.shape} and {r.shape}"
        )
    batched = b.ndim == 3
    n = b.shape[-2]
    N = b.shape[0] if batched else 1
    if weights is None:
        w = _unit_weights(n)[None] if batched else _unit_weights(n)  # one shared row
    else:
        w = as_array("weights", weights, finite=False)
        if batched and w.shape == (n,):
            w = w[None]  # one shared row: the kernels read w[0] for every problem
        elif w.shape != ((N, n) if batched else (n,)):
            allowed = f"({n},)" + (f" or ({N}, {n})" if batched else "")
            raise InputError(f"weights must have shape {allowed}; got shape {w.shape}")
        if np.any(w[np.isfinite(w)] <= 0):
            bad = w[np.isfinite(w) & (w <= 0)][0]
            raise InputError(f"weights must be > 0 (they are 1/σ² of each observation); got {bad:g}")
        fin = w[np.isfinite(w)]
        if fin.size and (fin.max() > 1e100 or fin.min() < 1e-100):
            bad = fin.max() if fin.max() > 1e100 else fin.min()
            raise InputError(f"weights must be in [1e-100, 1e100] (1/σ², the covariance and condition "
                             f"number overflow outside); got {bad:g}")
    return _kernel_ready(b), _kernel_ready(r), _kernel_ready(w), batched


def _kernel_ready(a: np.ndarray) -> np.ndarray:
    """C-contiguous and writeable (numba compiles read-only arrays as a separate type)."""
    a = np.ascontiguousarray(a)
    return a if a.flags.writeable else a.copy()


def solve_wahba(
    body: Any, ref: Any, weights: Any = None, method: str = "q-method", *, covariance: bool = True
) -> WahbaResult:
    """Solve Wahba's problem for one or a batch of observation sets.

    Parameters
    ----------
    body : array_like, shape (n, 3) or (N, n, 3)
        Observed directions in the body frame (any length; normalised here), ``n >= 2``.
    ref : array_like, same shape as ``body``
        The same directions in the reference frame. One of ``body``/``ref`` may be a single
        ``(n, 3)`` set shared by every problem of a ``(N, n, 3)`` batch.
    weights : array_like, shape (n,) or (N, n), optional
        Positive weights ``a_i`` (read as ``1/σ_i²`` [rad⁻²] for the covariance). Default 1.
    method : str
        One of :data:`METHODS`: ``"triad"``, ``"q-method"`` (default), ``"quest"``,
        ``"esoq2"``, ``"svd"``, ``"foam"``, ``"flae"`` (Wu et al. 2018: symbolic roots of
        the characteristic quartic, eigenvector by Gauss-Jordan elimination),
        ``"two-vector"`` (exactly two observations:
        Markley's closed form, the fastest optimal method for the sun + magnetometer case).
    covariance : bool, default True
        For a batch, ``False`` skips storing the ``(N, 3, 3)`` covariance (72 bytes per
        problem, a sizeable part of the batch time when only attitudes are needed); ``cov``
        is then a read-only all-NaN array of the same shape. ``cond`` is always computed.
        A single problem always gets its covariance.

    Returns
    -------
    WahbaResult
        ``q`` has shape ``(4,)`` for one problem and ``(N, 4)`` for a batch.

    Raises
    ------
    InputError
        Bad shapes, an unknown method, non-positive weights; for a *single* problem also any
        degenerate input (NaN, zero-length or all-parallel vectors, fewer than 2
        observations). In a batch, degenerate problems are flagged in ``success``/``status``
        instead and the others are solved.

    Notes
    -----
    The optimal methods agree with the eigen-solution to the accuracy the problem's
    conditioning allows (``~ε / gap``, gap = λ_max − λ_2 of ``K``); QUEST/ESOQ2/FOAM/FLAE check
    their eigen-residual and fall back to the eigen-solver above ``64 ε``.

    References
    ----------
    Markley & Crassidis 2014 §5.2–5.5; S0 eqs. 1–2; see the module docstring.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.attitude import euler_to_dcm, error_angle, dcm_to_quat
    >>> from adcskit.determination import solve_wahba
    >>> A = euler_to_dcm(np.radians([30.0, 10.0, -5.0]), "ZYX")
    >>> ref = np.array([[1.0, 0.0, 0.0], [0.0, 0.6, 0.8], [0.0, 0.0, 1.0]])
    >>> body = ref @ A.T                                  # b_i = A r_i
    >>> res = solve_wahba(body, ref, weights=[1.0, 2.0, 1.0], method="quest")
    >>> res.success, res.q.shape
    (True, (4,))
    >>> float(error_angle(res.q, dcm_to_quat(A))) < 1e-7
    True
    >>> batch = solve_wahba(np.stack([body, body]), ref)   # N = 2 problems at once
    >>> batch.q.shape, batch.success
    ((2, 4), array([ True,  True]))
    """
    entry = METHODS.get(method) if isinstance(method, str) else None
    if entry is None:
        if not isinstance(method, str):
            raise InputTypeError(f"method must be a string; got {short_repr(method)}")
        check_choice("method", method, METHODS)
    covariance = check_flag("covariance", covariance)
    b, r, w, batched = _prepare(body, ref, weights)
    code = entry[0]
    if code == _k.TWO_VECTOR and b.shape[-2] != 2:
        raise InputError(
            f"method 'two-vector' needs exactly 2 observations per problem; got n = {b.shape[-2]} "
            "(use 'esoq2', 'quest' or 'q-method' for n >= 2)"
        )
    if not batched:
        buf = np.empty(16)
        s = _k.solve_single(b, r, w, code, buf)
        if s != 0:
            raise InputError(f"cannot solve this Wahba problem: {_blame(s, b, r, w)}")
        return _single_result(buf, method)
    N = b.shape[0]
    q = np.empty((N, 4))
    out = np.empty((N, 3))
    cov = np.empty((N, 3, 3) if covariance else (N, 0, 0))
    status = np.empty(N, dtype=np.int8)
    kernel = _k.solve_batch_parallel if N >= _PARALLEL_MIN else _k.solve_batch_serial
    kernel(b, r, w, code, q, out, cov, status)
    if not covariance:
        cov = np.broadcast_to(np.nan, (N, 3, 3))
    success = status == 0
    if success.all():
        message = "solved"
    else:
        codes, counts = np.unique(status[~success], return_counts=True)
        message = "; ".join(
            f"{c} of {N} problems: {STATUS_MESSAGES[int(k)]}" for k, c in zip(codes, counts)
        )
    return WahbaResult(
        q=q, loss=out[:, 0], cov=cov, cond=out[:, 1], success=success,
        status=status, message=message, method=method, fallback=out[:, 2] != 0,
    )


def davenport_k(body: Any, ref: Any, weights: Any = None) -> np.ndarray:
    """Davenport's ``K`` matrix (S0 eq. 2) with weights normalised to sum 1.

    Parameters
    ----------
    body, ref : array_like, shape (n, 3) or (N, n, 3)
        Observations and reference vectors (normalised here).
    weights : array_like, shape (n,) or (N, n), optional

    Returns
    -------
    ndarray, shape (4, 4) or (N, 4, 4)

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.determination import davenport_k
    >>> K = davenport_k([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    >>> K.shape, np.allclose(K, K.T)
    ((4, 4), True)
    >>> float(np.linalg.eigvalsh(K)[-1])   # lambda_max = sum of weights for noise-free data
    1.0
    """
    b, r, w, batched = _prepare(body, ref, weights)
    if not batched:
        b, r, w = b[None], r[None], w[None]
    w = np.broadcast_to(_finite_weights(w), b.shape[:2])
    b, r = _unit("body", b), _unit("ref", r)
    a = w / w.sum(axis=1, keepdims=True)
    K = _k_from(b, r, a)
    return K if batched else K[0]


def _blame(status: int, b: np.ndarray, r: np.ndarray, w: np.ndarray) -> str:
    """The kernel's status as a message naming the argument at fault (error path only)."""
    text = STATUS_MESSAGES[status]
    if status == _k.NONFINITE:
        for name, a in (("body", b), ("ref", r), ("weights", w)):
            if not np.all(np.isfinite(a)):
                return f"{name} must be finite ({text})"
    if status == _k.ZERO_LENGTH:
        name = "body" if np.any(np.all(b == 0, axis=-1)) else "ref"
        return f"{name} must not contain zero-length vectors ({text})"
    if status == _k.COLLINEAR_BODY:
        return f"body vectors must not all be parallel ({text})"
    if status == _k.COLLINEAR_REF:
        return f"ref vectors must not all be parallel ({text})"
    if status == _k.TOO_FEW:
        return f"body and ref must hold at least 2 observations ({text})"
    return text


def _unit(name: str, v: np.ndarray) -> np.ndarray:
    """Unit vectors of ``v`` (..., 3), rejecting what ``solve_wahba`` reports as unusable.

    NaN/inf entries and zero vectors raise :class:`InputError`; the scaling by the largest
    component first keeps 1e-300 and 1e300 vectors from under- or overflowing the norm.
    """
    if not np.all(np.isfinite(v)):
        raise InputError(f"{name} must be finite (no NaN or inf); got {STATUS_MESSAGES[_k.NONFINITE]}")
    scale = np.abs(v).max(axis=-1, keepdims=True)
    if np.any(scale == 0):
        idx = tuple(int(i) for i in np.argwhere(scale[..., 0] == 0)[0])
        raise InputError(f"{name} must contain non-zero vectors (they are normalised); got a zero "
                         f"vector at index {idx}")
    u = v / scale
    return u / np.linalg.norm(u, axis=-1, keepdims=True)


def _finite_weights(w: np.ndarray) -> np.ndarray:
    if not np.all(np.isfinite(w)):
        raise InputError(f"weights must be finite (no NaN or inf); got {w[~np.isfinite(w)][0]}")
    return w


def _k_from(b: np.ndarray, r: np.ndarray, a: np.ndarray) -> np.ndarray:
    """K for unit vectors b, r (N, n, 3) and weights a (N, n) — NumPy, no validation."""
    B = np.einsum("kn,kni,knj->kij", a, b, r)
    z = np.einsum("kn,kni->ki", a, np.cross(b, r))
    sig = np.trace(B, axis1=1, axis2=2)
    N = B.shape[0]
    K = np.empty((N, 4, 4))
    K[:, :3, :3] = B + B.transpose(0, 2, 1) - sig[:, None, None] * np.eye(3)
    K[:, :3, 3] = z
    K[:, 3, :3] = z
    K[:, 3, 3] = sig
    return K


def wahba_loss(q: Any, body: Any, ref: Any, weights: Any = None) -> Any:
    """Wahba loss ``1/2 Σ a_i ||b_i − A(q) r_i||²`` of the attitude ``q`` (S0 eq. 1).

    Vectors are normalised; weights default to 1. Returns a float for one problem and an
    ``(N,)`` array for a batch.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.determination import wahba_loss
    >>> ref = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    >>> float(wahba_loss([0.0, 0.0, 0.0, 1.0], ref, ref))          # identity fits exactly
    0.0
    >>> q90 = [0.0, 0.0, np.sin(np.pi / 4), np.cos(np.pi / 4)]      # 90 deg about z
    >>> round(float(wahba_loss(q90, ref, ref)), 9)                  # 1/2 (2 + 2)
    2.0
    """
    b, r, w, batched = _prepare(body, ref, weights)
    if not batched:
        b, r, w = b[None], r[None], w[None]
    w = np.broadcast_to(w, b.shape[:2])
    w = _finite_weights(w)
    qa, _ = _as_quat(q, b.shape[0], batched)
    b, r = _unit("body", b), _unit("ref", r)
    A = quat_to_dcm_np(qa)
    res = b - np.einsum("kij,knj->kni", A, r)
    loss = 0.5 * np.einsum("kn,kni,kni->k", w, res, res)
    return loss if batched else float(loss[0])


def _as_quat(q: Any, N: int, batched: bool) -> tuple[np.ndarray, bool]:
    arr = as_array("q", q)
    if arr.shape == (4,):
        arr = np.broadcast_to(arr, (N, 4))
    elif not (batched and arr.shape == (N, 4)):
        extra = f" or ({N}, 4)" if batched else ""
        raise InputError(f"q must have shape (4,){extra}; got {arr.shape}")
    nrm = np.linalg.norm(arr, axis=-1, keepdims=True)
    if np.any(nrm == 0):
        raise InputError("q must be a non-zero quaternion")
    return arr / nrm, batched


def quat_to_dcm_np(q: np.ndarray) -> np.ndarray:
    """``A(q)`` for quaternions (N, 4), scalar last (private NumPy helper, no validation)."""
    e = q[..., :3]
    q4 = q[..., 3]
    A = (q4**2 - np.sum(e * e, axis=-1))[..., None, None] * np.eye(3)
    A = A + 2.0 * e[..., :, None] * e[..., None, :]
    ex = np.zeros(q.shape[:-1] + (3, 3))
    ex[..., 0, 1], ex[..., 0, 2], ex[..., 1, 2] = -e[..., 2], e[..., 1], -e[..., 0]
    ex[..., 1, 0], ex[..., 2, 0], ex[..., 2, 1] = e[..., 2], -e[..., 1], e[..., 0]
    return A - 2.0 * q4[..., None, None] * ex


def method_info() -> Mapping[str, str]:
    """Method name -> one-line description."""
    return {k: v[2] for k, v in METHODS.items()}
