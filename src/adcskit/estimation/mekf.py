"""Multiplicative extended Kalman filter (MEKF) with gyro-bias estimation.

The attitude filter of Lefferts, Markley & Shuster (1982) in the form of Markley & Crassidis
(2014, §6.2): the global attitude is a unit quaternion, the filter state is the 6-vector
error ``x = [dθ, Δb]`` (attitude-error rotation vector in the body frame, rad; gyro-bias
error, rad/s) with ``q_true = δq(dθ) ⊗ q̂`` and ``b_true = b̂ + Δb``; after every measurement
update the error is folded back into ``q̂`` and ``b̂`` (multiplicative reset). The gyro
follows Farrenkopf's model ``ω̃ = ω + b + η_v``, ``ḃ = η_u`` with angle random walk ``σv``
[rad/s^0.5] and bias random walk ``σu`` [rad/s^1.5]. Propagation uses the exact discrete
``Φ`` and ``Q`` for the rate held over the step; measurement updates are unit-vector
observations (sun sensor, magnetometer, ...; ``R = σ² I`` per vector, Markley & Crassidis
eq. 6.72 style) and star-tracker quaternions, each processed as sequential scalar updates
with the Joseph form. While a vector-measurement row's predicted variance ``h P hᵀ`` exceeds
its noise variance ``σ²`` the update is *underweighted* (noise ``σ² + p h P hᵀ``, ``p`` =
:data:`UNDERWEIGHT` = 0.2 by default, ``underweight=0`` switches it off), so that a precise
first sun update of a 1° prior does not lock in the EKF's linearisation error (issue 23: the
closed-loop NEES fell from 8.2 to the χ² band); star-tracker updates, linear in the error,
are not underweighted. The equations are in
:mod:`adcskit.estimation._mekf_kernels`.

Two entry points (docs/architecture.md, house style rule 2):

* :class:`MultiplicativeEKF` — a validated stepping filter for one spacecraft
  (``propagate``, ``update_vector``, ``update_quaternion``, ``nees``);
* :func:`mekf_filter` — a whole batch ``(N samples, T epochs)`` in one compiled call
  (numba ``prange`` over samples), returning :class:`MEKFResult` with NEES/NIS statistics.

The simulator (:mod:`adcskit.simulation`) calls the per-sample kernels directly.

Hand-written because no maintained Python library provides a MEKF with bias estimation
(filterpy has linear/unscented filters on vector states; ``ahrs``'s EKF estimates the
quaternion additively, without gyro bias, one sample per Python call).

Conventions: quaternion scalar last, ``A(q)`` maps reference to body (``b = A(q) r``),
canonical sign ``q4 >= 0`` (docs/architecture.md, "Conventions").

References
----------
.. [1] Lefferts, E. J., Markley, F. L. and Shuster, M. D., "Kalman filtering for spacecraft
   attitude estimation", JGCD 5(5), 1982, 417-429.
.. [2] Markley, F. L. and Crassidis, J. L., *Fundamentals of Spacecraft Attitude
   Determination and Control*, Springer, 2014, §6.2 (eqs. 6.60-6.93).
.. [3] Bar-Shalom, Y., Li, X. R. and Kirubarajan, T., *Estimation with Applications to
   Tracking and Navigation*, Wiley, 2001, §5.4 (NEES/NIS consistency tests).
.. [4] Zanetti, R., DeMars, K. J. and Bishop, R. H., "Underweighting nonlinear
   measurements", JGCD 33(5), 2010, 1670-1675.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import stats

from adcskit._results import Result
from adcskit._validation import as_array, check_finite, check_int, check_positive, short_repr
from adcskit.errors import InputError, InputTypeError
from adcskit.estimation import _mekf_kernels as _mk

__all__ = ["MEKFResult", "MultiplicativeEKF", "mekf_filter", "chi2_band", "UNDERWEIGHT"]

#: Default measurement-underweighting factor ``p`` (module docstring): while a scalar
#: vector-measurement row's predicted variance ``h P hᵀ`` exceeds its noise variance ``σ²``, the
#: update uses ``σ² + p h P hᵀ``. ``0`` switches underweighting off (the plain EKF update).
UNDERWEIGHT = 0.2


# ------------------------------------------------------------------------- validation


def _quat(name: str, value: Any) -> np.ndarray:
    q = as_array(name, value, shape=(4,))
    if not np.any(q):
        raise InputError(f"{name} must be a non-zero quaternion (scalar last); got {short_repr(q)}")
    q = q / np.max(np.abs(q))  # rescale first: the norm of a 1e-300 quaternion underflows
    q = q / np.linalg.norm(q)
    return -q if q[3] < 0 else q


def _vec3(name: str, value: Any, *, nonzero: bool = False) -> np.ndarray:
    v = as_array(name, value, shape=(3,))
    if nonzero and not np.any(v):
        raise InputError(f"{name} must be a non-zero 3-vector; got {short_repr(v)}")
    if nonzero:  # a direction: rescale so that the kernel's normalisation cannot underflow
        v = v / np.max(np.abs(v))
    return v


#: Smallest measurement noise accepted [rad]: 1/σ² must stay finite in the gain.
MIN_SIGMA = 1e-100


def _sigma(name: str, value: Any) -> float:
    return check_positive(name, value, unit="rad", min_value=MIN_SIGMA)


def _rows_rescaled(a: np.ndarray) -> np.ndarray:
    """Each last-axis row divided by its largest magnitude (direction kept, no underflow in the
    kernel's normalisation); zero and NaN rows are left as they are."""
    with np.errstate(invalid="ignore"):
        m = np.max(np.abs(a), axis=-1, keepdims=True)
    m = np.where(np.isfinite(m) & (m > 0), m, 1.0)
    return a / m


def _covariance(name: str, value: Any, lead: tuple[int, ...] = ()) -> np.ndarray:
    P = as_array(name, value)
    if P.shape not in ((6, 6), (*lead, 6, 6)):
        allowed = "(6, 6)" + (f" or ({lead[0]}, 6, 6)" if lead else "")
        raise InputError(f"{name} must have shape {allowed}; got shape {P.shape}")
    Pt = np.swapaxes(P, -1, -2)
    scale = np.max(np.abs(P)) if P.size else 0.0
    if np.any(np.abs(P - Pt) > 1e-9 * max(scale, 1e-300)):
        raise InputError(f"{name} must be symmetric (the 6x6 error covariance [rad², rad²/s, "
                         "rad²/s²]); it is not")
    P = 0.5 * (P + Pt)
    w = np.linalg.eigvalsh(P)
    if np.any(w < -1e-12 * max(scale, 1e-300)):
        raise InputError(f"{name} must be positive semi-definite; smallest eigenvalue {w.min():g}")
    return P


def _noise(name: str, value: Any, unit: str) -> float:
    return check_positive(name, value, allow_zero=True, unit=unit)


def _underweight(value: Any) -> float:
    if isinstance(value, (bool, np.bool_)):
        raise InputTypeError("underweight must be a number >= 0 (the underweighting factor p; 0 "
                             f"switches it off); got {value!r}")
    return check_positive("underweight", value, allow_zero=True, max_value=1e6)


def chi2_band(dof: int, n_runs: int, alpha: float = 0.05) -> tuple[float, float]:
    """Two-sided ``1 − alpha`` band of the mean of ``n_runs`` independent χ²(dof) values.

    ``n_runs · mean ~ χ²(n_runs · dof)`` for a consistent filter (Bar-Shalom et al. 2001,
    §5.4.2), so the band is ``[χ²_{α/2}, χ²_{1−α/2}](n_runs · dof) / n_runs``.

    Parameters
    ----------
    dof : int
        Degrees of freedom of one value (6 for the MEKF NEES, 2 or 3 for a vector NIS).
    n_runs : int
        Number of independent values averaged (Monte-Carlo runs).
    alpha : float
        Two-sided significance level, in (0, 1).

    Returns
    -------
    (float, float)
        Lower and upper bound of the mean.

    Examples
    --------
    >>> lo, hi = chi2_band(6, 200)
    >>> round(lo, 2), round(hi, 2)
    (5.53, 6.49)
    """
    dof = check_int("dof", dof, minimum=1, maximum=10**9)
    n_runs = check_int("n_runs", n_runs, minimum=1, maximum=10**9)
    a = check_finite("alpha", alpha)
    # below 1e-300, alpha / 2 is subnormal or zero and the upper end of the band is inf
    if not 1e-300 <= a < 1.0:
        raise InputError(f"alpha must be in [1e-300, 1) (a probability; smaller has no finite band); got {a:g}")
    k = dof * n_runs
    # isf for the upper end: ppf(1 - a/2) rounds to ppf(1) = inf for a tiny alpha
    return float(stats.chi2.ppf(a / 2, k) / n_runs), float(stats.chi2.isf(a / 2, k) / n_runs)


# ------------------------------------------------------------------------- stepping class


class MultiplicativeEKF:
    """Stepping MEKF for one spacecraft: attitude quaternion and gyro bias.

    Parameters
    ----------
    q0 : array_like, shape (4,)
        Initial attitude estimate, scalar last, reference -> body (normalised here).
    b0 : array_like, rad/s, shape (3,)
        Initial gyro-bias estimate (``ω̃ = ω + b + noise``).
    P0 : array_like, shape (6, 6)
        Initial error covariance of ``[dθ (rad), Δb (rad/s)]``, symmetric PSD.
    sigma_v : float, rad/s^0.5
        Gyro angle random walk (Farrenkopf ``σv``), >= 0.
    sigma_u : float, rad/s^1.5
        Gyro bias random walk (Farrenkopf ``σu``), >= 0.
    underweight : float
        Measurement-underweighting factor ``p`` >= 0 (default :data:`UNDERWEIGHT` = 0.2):
        while a vector-measurement row's predicted variance ``h P hᵀ`` exceeds its noise
        variance ``σ²`` the update uses ``σ² + p h P hᵀ`` (Lefferts, Markley & Shuster 1982;
        Zanetti, DeMars & Bishop 2010), so that a precise first measurement of a poorly
        known attitude does not lock in the EKF's linearisation error. ``0`` gives the plain
        EKF update. Star-tracker updates are never underweighted (linear in the error).

    Notes
    -----
    Each method validates its arguments and then calls the compiled per-sample kernel of
    :mod:`adcskit.estimation._mekf_kernels` (the same code the batch function and the
    simulator run), so a step costs a few microseconds of Python overhead. For many samples
    or long runs use :func:`mekf_filter`.

    References
    ----------
    Lefferts, Markley & Shuster 1982; Markley & Crassidis 2014 §6.2 (see the module).

    Examples
    --------
    Static spacecraft, two reference directions observed once per second:

    >>> import numpy as np
    >>> f = MultiplicativeEKF([0, 0, 0, 1], np.zeros(3), np.diag([1e-2] * 3 + [1e-8] * 3),
    ...                       sigma_v=1e-5, sigma_u=1e-8)
    >>> for _ in range(10):
    ...     f.propagate([0.0, 0.0, 0.0], 1.0)
    ...     nis = f.update_vector([1.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1e-3)
    ...     nis = f.update_vector([0.0, 1.0, 0.0], [0.0, 1.0, 0.0], 1e-3)
    >>> bool(np.sqrt(f.P[0, 0]) < 1e-3)
    True
    """

    __slots__ = ("_q", "_b", "_P", "_work", "_sigma_v", "_sigma_u", "_uw")

    def __init__(self, q0: Any, b0: Any, P0: Any, *, sigma_v: float, sigma_u: float,
                 underweight: float = UNDERWEIGHT) -> None:
        self._q = _quat("q0", q0)
        self._b = _vec3("b0", b0)
        self._P = np.ascontiguousarray(_covariance("P0", P0))
        self._sigma_v = _noise("sigma_v", sigma_v, "rad/s^0.5")
        self._sigma_u = _noise("sigma_u", sigma_u, "rad/s^1.5")
        self._uw = _underweight(underweight)
        self._work = np.zeros(_mk.WORK_SIZE)

    @property
    def q(self) -> np.ndarray:
        """Attitude estimate (4,), scalar last, ``q4 >= 0`` (a copy)."""
        return self._q.copy()

    @property
    def b(self) -> np.ndarray:
        """Gyro-bias estimate (3,) [rad/s] (a copy)."""
        return self._b.copy()

    @property
    def P(self) -> np.ndarray:
        """Error covariance (6, 6) of ``[dθ, Δb]`` [rad², rad²/s, rad²/s²] (a copy)."""
        return self._P.copy()

    @property
    def sigma_v(self) -> float:
        """Angle random walk [rad/s^0.5]."""
        return self._sigma_v

    @property
    def sigma_u(self) -> float:
        """Bias random walk [rad/s^1.5]."""
        return self._sigma_u

    @property
    def underweight(self) -> float:
        """Measurement-underweighting factor ``p`` (0: off)."""
        return self._uw

    def propagate(self, omega_meas: Any, dt: float) -> None:
        """Propagate over ``dt`` with the gyro reading held constant.

        Parameters
        ----------
        omega_meas : array_like, rad/s, shape (3,)
            Measured body rate (bias included).
        dt : float, s
            Step, >= 0.

        References
        ----------
        Markley & Crassidis 2014 eqs. 6.60-6.93 (exact closed-form ``Φ``, ``Q`` here).
        """
        om = _vec3("omega_meas", omega_meas)
        h = check_positive("dt", dt, allow_zero=True, unit="s")
        saved = (self._q.copy(), self._b.copy(), self._P.copy())
        _mk.mekf_propagate_jit(self._q, self._b, self._P, om, h, self._sigma_v, self._sigma_u,
                               self._work)
        if not np.all(np.isfinite(self._P)):  # the process noise grows as dt^3: an absurd step overflows
            self._q[:], self._b[:], self._P[:] = saved
            raise InputError(f"dt = {h:g} s is too long a step for this filter: the propagated covariance "
                             "overflows (the filter state is left unchanged)")

    def update_vector(self, v_body: Any, v_ref: Any, sigma: float) -> float:
        """Update with one observed direction.

        Parameters
        ----------
        v_body : array_like, shape (3,)
            Measured direction in the body frame (normalised here).
        v_ref : array_like, shape (3,)
            The same direction in the reference frame (normalised here).
        sigma : float, rad
            Measurement noise per axis, >= 1e-100 (``R = σ² I``).

        Returns
        -------
        float
            NIS ``νᵀ S⁻¹ ν`` of this measurement (about χ²(2) for unit vectors).

        References
        ----------
        Markley & Crassidis 2014 §6.2.1 (vector measurement model); Joseph form: see
        :mod:`adcskit.estimation._mekf_kernels`.
        """
        vb = _vec3("v_body", v_body, nonzero=True)
        vr = _vec3("v_ref", v_ref, nonzero=True)
        s = _sigma("sigma", sigma)
        return float(_mk.mekf_update_vector_jit(self._q, self._b, self._P, vb, vr, s, self._uw,
                                                  self._work))

    def update_quaternion(self, q_meas: Any, sigma: float) -> float:
        """Update with a star-tracker attitude ``q_meas = δq(v) ⊗ q_true``, ``v ~ N(0, σ² I)``.

        Parameters
        ----------
        q_meas : array_like, shape (4,)
            Measured attitude, scalar last (normalised here).
        sigma : float, rad
            Noise per body axis, > 0.

        Returns
        -------
        float
            NIS (about χ²(3)).
        """
        qm = _quat("q_meas", q_meas)
        s = _sigma("sigma", sigma)
        return float(_mk.mekf_update_quaternion_jit(self._q, self._b, self._P, qm, s, self._work))

    def nees(self, q_true: Any, b_true: Any) -> float:
        """NEES ``eᵀ P⁻¹ e`` of the current estimate against the truth (about χ²(6)).

        ``e = [rotvec(q_true ⊗ q̂⁻¹), b_true − b̂]``; NaN if ``P`` is singular.
        """
        qt = _quat("q_true", q_true)
        bt = _vec3("b_true", b_true)
        return float(_mk.mekf_nees_jit(self._q, self._b, self._P, qt, bt, self._work))


# ------------------------------------------------------------------------- batch function


@dataclass(frozen=True, slots=True, repr=False)
class MEKFResult(Result):
    """Output of :func:`mekf_filter` (leading ``N`` axis only for a batched call).

    Attributes
    ----------
    t : ndarray, s, shape (T,)
        Epochs.
    q : ndarray, shape ([N,] T, 4)
        Posterior attitude estimates at each epoch, scalar last, ``q4 >= 0``.
    b : ndarray, rad/s, shape ([N,] T, 3)
        Posterior gyro-bias estimates.
    P_diag : ndarray, shape ([N,] T, 6)
        Diagonal of the posterior error covariance [rad², rad²/s²].
    P : ndarray, shape ([N,] T, 6, 6)
        Full posterior covariance if ``full_covariance=True``; otherwise a read-only all-NaN
        array of that shape (no memory).
    nees : ndarray, shape ([N,] T)
        NEES per epoch (NaN without the truth).
    nis : ndarray, shape ([N,] T, m)
        NIS of each vector measurement (NaN where none was processed).
    nis_quaternion : ndarray, shape ([N,] T)
        NIS of the star-tracker update (NaN where none).
    mean_nees : ndarray, shape (T,)
        NEES averaged over the samples at each epoch (compare with :func:`chi2_band`
        ``(6, N)``).
    success : bool
        False if any sample produced a non-finite estimate or a non-positive variance.
    message : str

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.estimation import mekf_filter
    >>> T = 20
    >>> t = np.arange(T, dtype=float)
    >>> ref = np.broadcast_to(np.eye(3)[:2], (T, 2, 3))
    >>> res = mekf_filter([0, 0, 0, 1], np.zeros(3), np.diag([1e-2] * 3 + [1e-8] * 3), t,
    ...                   np.zeros((T, 3)), ref, ref, [1e-3, 1e-3], sigma_v=1e-6, sigma_u=1e-9)
    >>> res.success, res.q.shape
    (True, (20, 4))
    """

    t: np.ndarray
    q: np.ndarray
    b: np.ndarray
    P_diag: np.ndarray
    P: np.ndarray
    nees: np.ndarray
    nis: np.ndarray
    nis_quaternion: np.ndarray
    mean_nees: np.ndarray
    success: bool
    message: str


def _series(name: str, value: Any, tail: tuple[int, ...], N: int | None, T: int, *,
            finite: bool = True) -> np.ndarray:
    """``([N,] T, *tail)`` array: returns (N, T, *tail) (N = 1 for a single run)."""
    arr = as_array(name, value, finite=finite)
    single = (T, *tail)
    if N is None:
        if arr.shape != single:
            raise InputError(f"{name} must have shape {single}; got shape {arr.shape}")
        return arr[None]
    if arr.shape != (N, *single):
        raise InputError(f"{name} must have shape {(N, *single)}; got shape {arr.shape}")
    return arr


def _per_sample(name: str, value: Any, tail: tuple[int, ...], N: int) -> np.ndarray:
    arr = as_array(name, value)
    if arr.shape == tail:
        return np.broadcast_to(arr, (N, *tail)).copy()
    if arr.shape != (N, *tail):
        raise InputError(f"{name} must have shape {tail} or {(N, *tail)}; got shape {arr.shape}")
    return arr


def mekf_filter(
    q0: Any,
    b0: Any,
    P0: Any,
    t: Any,
    gyro: Any,
    vectors_body: Any = None,
    vectors_ref: Any = None,
    sigmas: Any = None,
    *,
    sigma_v: float,
    sigma_u: float,
    q_star: Any = None,
    sigma_star: float | None = None,
    q_true: Any = None,
    b_true: Any = None,
    full_covariance: bool = False,
    underweight: float = UNDERWEIGHT,
) -> MEKFResult:
    """Run the MEKF over a batch of samples in one compiled call.

    At epoch ``t[0]`` the prior ``(q0, b0, P0)`` is updated with that epoch's measurements;
    from each epoch to the next the filter propagates with the gyro sample of the earlier
    epoch held over the interval (zero-order hold), then processes the vector measurements
    in order and the star-tracker quaternion.

    Parameters
    ----------
    q0 : array_like, shape (4,) or (N, 4)
        Initial attitude estimate(s), scalar last, reference -> body.
    b0 : array_like, rad/s, shape (3,) or (N, 3)
        Initial gyro-bias estimate(s).
    P0 : array_like, shape (6, 6) or (N, 6, 6)
        Initial error covariance(s) of ``[dθ (rad), Δb (rad/s)]``, symmetric PSD.
    t : array_like, s, shape (T,)
        Strictly increasing epochs.
    gyro : array_like, rad/s, shape (T, 3) or (N, T, 3)
        Gyro readings at the epochs; ``(N, T, 3)`` makes the call batched.
    vectors_body : array_like, shape ([N,] T, m, 3), optional
        Measured directions in the body frame (normalised here). A row of NaN means "no
        measurement of this sensor at this epoch" (sensors at their own rates, eclipses).
    vectors_ref : array_like, shape (T, m, 3) or (N, T, m, 3), optional
        The same directions in the reference frame (finite, non-zero).
    sigmas : array_like, rad, shape (m,), optional
        Noise per axis of each vector sensor, > 0.
    sigma_v : float, rad/s^0.5
        Gyro angle random walk, >= 0.
    sigma_u : float, rad/s^1.5
        Gyro bias random walk, >= 0.
    q_star : array_like, shape ([N,] T, 4), optional
        Star-tracker quaternions (NaN rows: none at that epoch).
    sigma_star : float, rad, optional
        Star-tracker noise per axis, > 0; required with ``q_star``.
    q_true, b_true : array_like, shape ([N,] T, 4) and ([N,] T, 3), optional
        Truth for the NEES (both or neither).
    full_covariance : bool
        Store the full ``(6, 6)`` covariance per epoch (else only its diagonal).
    underweight : float
        Measurement-underweighting factor ``p`` >= 0 (default :data:`UNDERWEIGHT` = 0.2; see
        :class:`MultiplicativeEKF`); ``0`` gives the plain EKF update.

    Returns
    -------
    MEKFResult

    Raises
    ------
    InputError, InputTypeError
        Bad shapes, non-finite inputs (other than whole NaN measurement rows), zero vectors,
        non-positive noise, a non-symmetric or indefinite ``P0``, non-increasing ``t``.

    Notes
    -----
    Samples run in parallel on all cores (numba ``prange``); each sample is the per-sample
    kernel of :mod:`adcskit.estimation._mekf_kernels`, the code the stepping
    :class:`MultiplicativeEKF` and the closed-loop simulator use.

    References
    ----------
    Lefferts, Markley & Shuster 1982; Markley & Crassidis 2014 §6.2; Bar-Shalom et al. 2001
    §5.4 (NEES/NIS).

    Examples
    --------
    One static run, two vectors every epoch, 60 s at 1 Hz:

    >>> import numpy as np
    >>> T = 60
    >>> t = np.arange(T, dtype=float)
    >>> ref = np.broadcast_to(np.eye(3)[:2], (T, 2, 3))
    >>> rng = np.random.default_rng(0)
    >>> body = ref + 1e-3 * rng.standard_normal((T, 2, 3))
    >>> gyro = 1e-4 + 1e-5 * rng.standard_normal((T, 3))   # bias 1e-4 rad/s on each axis
    >>> res = mekf_filter([0, 0, 0, 1], np.zeros(3), np.diag([1e-2] * 3 + [1e-6] * 3), t,
    ...                   gyro, body, ref, [1e-3, 1e-3], sigma_v=1e-5, sigma_u=1e-7)
    >>> res.q.shape, bool(np.allclose(res.b[-1], 1e-4, atol=3e-5))
    ((60, 4), True)
    """
    sv = _noise("sigma_v", sigma_v, "rad/s^0.5")
    su = _noise("sigma_u", sigma_u, "rad/s^1.5")
    uw = _underweight(underweight)
    if not isinstance(full_covariance, (bool, np.bool_)):
        raise InputTypeError(f"full_covariance must be True or False; got {short_repr(full_covariance)}")
    tt = as_array("t", t, ndim=1)
    T = tt.shape[0]
    if T < 1:
        raise InputError("t must hold at least one epoch; got an empty array")
    dts = np.diff(tt)
    if np.any(dts <= 0):
        i = int(np.argmax(dts <= 0))
        raise InputError(f"t must be strictly increasing; t[{i + 1}] = {tt[i + 1]:g} <= t[{i}] = {tt[i]:g}")
    g = as_array("gyro", gyro)
    if g.ndim == 3 and g.shape[1:] == (T, 3):
        N: int | None = g.shape[0]
    elif g.shape == (T, 3):
        N = None
    else:
        raise InputError(f"gyro must have shape ({T}, 3) or (N, {T}, 3) for T = {T} epochs; "
                         f"got shape {g.shape}")
    n = 1 if N is None else N
    if n < 1:
        raise InputError("gyro must hold at least one sample (N >= 1)")
    g = g.reshape(n, T, 3)
    q0a = _per_sample("q0", q0, (4,), n)
    if np.any((q0a == 0).all(axis=-1)):
        raise InputError("q0 must be non-zero quaternions (scalar last)")
    q0a = _rows_rescaled(q0a)
    q0a = q0a / np.linalg.norm(q0a, axis=-1)[:, None]
    q0a *= np.where(q0a[:, 3:] < 0, -1.0, 1.0)
    b0a = _per_sample("b0", b0, (3,), n)
    P0a = _covariance("P0", P0, (n,))
    P0a = np.array(np.broadcast_to(P0a, (n, 6, 6)))  # writeable: one compiled signature

    # vector measurements
    given = [x is not None for x in (vectors_body, vectors_ref, sigmas)]
    if any(given) and not all(given):
        raise InputError("vectors_body, vectors_ref and sigmas must be given together")
    if all(given):
        vb = as_array("vectors_body", vectors_body, finite=False)
        if vb.ndim != (4 if N is not None else 3) or vb.shape[-1] != 3:
            want = f"({'N, ' if N is not None else ''}{T}, m, 3)"
            raise InputError(f"vectors_body must have shape {want}; got shape {vb.shape}")
        m = vb.shape[-2]
        vb = _series("vectors_body", vb, (m, 3), N, T, finite=False)
        missing = np.isnan(vb).all(axis=-1)
        bad = ~np.isfinite(vb).all(axis=-1) & ~missing
        if np.any(bad):
            idx = tuple(int(i) for i in np.argwhere(bad)[0])
            raise InputError("vectors_body must be finite, or a whole row of NaN for 'no "
                             f"measurement'; got a partly non-finite row at index {idx}")
        zero = (vb == 0).all(axis=-1)
        if np.any(zero):
            raise InputError("vectors_body must be non-zero vectors (NaN rows for missing ones)")
        vr = as_array("vectors_ref", vectors_ref)
        if vr.shape == (T, m, 3):
            vr = vr[None]
        elif vr.shape != (n, T, m, 3) or N is None:
            raise InputError(f"vectors_ref must have shape ({T}, {m}, 3)"
                             + (f" or ({n}, {T}, {m}, 3)" if N is not None else "")
                             + f"; got shape {vr.shape}")
        if np.any((vr == 0).all(axis=-1)):
            raise InputError("vectors_ref must be non-zero vectors")
        sg = as_array("sigmas", sigmas, shape=(m,))
        if np.any(sg < MIN_SIGMA):
            raise InputError(f"sigmas must be >= {MIN_SIGMA:g} rad; got {sg[sg < MIN_SIGMA][0]:g}")
        vb, vr = _rows_rescaled(vb), _rows_rescaled(vr)
    else:
        m = 0
        vb = np.zeros((n, T, 0, 3))
        vr = np.zeros((1, T, 0, 3))
        sg = np.zeros(0)

    # star tracker
    if (q_star is None) != (sigma_star is None):
        raise InputError("q_star and sigma_star must be given together")
    if q_star is not None:
        qs = _series("q_star", q_star, (4,), N, T, finite=False)
        miss = np.isnan(qs).all(axis=-1)
        if np.any(~np.isfinite(qs).all(axis=-1) & ~miss):
            raise InputError("q_star must be finite, or a whole row of NaN for 'no measurement'")
        if np.any((qs == 0).all(axis=-1)):
            raise InputError("q_star must be non-zero quaternions")
        ss = _sigma("sigma_star", sigma_star)
        qs = _rows_rescaled(qs)
    else:
        qs = np.zeros((0, T, 4))
        ss = 1.0

    # truth
    if (q_true is None) != (b_true is None):
        raise InputError("q_true and b_true must be given together")
    if q_true is not None:
        qt = _series("q_true", q_true, (4,), N, T)
        if np.any((qt == 0).all(axis=-1)):
            raise InputError("q_true must be non-zero quaternions")
        bt = _series("b_true", b_true, (3,), N, T)
        qt = _rows_rescaled(qt)
    else:
        qt = np.zeros((0, T, 4))
        bt = np.zeros((0, T, 3))

    q_out = np.empty((n, T, 4))
    b_out = np.empty((n, T, 3))
    Pd = np.empty((n, T, 6))
    P_full = np.empty((n, T, 6, 6) if full_covariance else (0, T, 6, 6))
    nees = np.full((n, T), np.nan)
    nis = np.empty((n, T, m))
    nis_st = np.full((n, T), np.nan)
    c = np.ascontiguousarray
    _mk.filter_batch(c(q0a), c(b0a), P0a, c(dts), c(g), c(vb), c(vr), c(sg), c(qs), float(ss),
                     sv, su, uw, c(qt), c(bt), q_out, b_out, Pd, P_full, nees, nis, nis_st,
                     np.empty((n, 6, 6)), np.empty((n, _mk.WORK_SIZE)))
    bad = ~(np.isfinite(q_out).all(axis=(1, 2)) & np.isfinite(Pd).all(axis=(1, 2))
            & (Pd > 0).all(axis=(1, 2)))
    success = not bool(bad.any())
    message = ("filtered" if success else
               f"{int(bad.sum())} of {n} samples produced a non-finite estimate or a non-positive "
               "variance (check the noise levels and P0)")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # epochs without any finite NEES
        mean_nees = np.nanmean(nees, axis=0)
    if not full_covariance:
        P_full = np.broadcast_to(np.nan, (n, T, 6, 6))
    out = (q_out, b_out, Pd, P_full, nees, nis, nis_st)
    if N is None:
        out = tuple(a[0] for a in out)
    return MEKFResult(t=tt, q=out[0], b=out[1], P_diag=out[2], P=out[3], nees=out[4],
                      nis=out[5], nis_quaternion=out[6], mean_nees=mean_nees, success=success,
                      message=message)
