"""Per-sample kernels of the multiplicative EKF (MEKF) with gyro-bias estimation.

Private module: the validated public API is :mod:`adcskit.estimation.mekf`. The functions
below are the *per-sample step* of the batched kernels (docs/architecture.md, "Kernels and targets"): plain Python functions that
work in place on preallocated ``float64`` arrays, allocate nothing, raise nothing and use only
``math`` scalar functions, so the same source compiles

* with ``numba.njit`` (CPU; the ``*_jit`` dispatchers below, and :func:`filter_batch`, a
  ``prange`` loop over samples), and
* with ``numba.cuda.jit(device=True)`` (GPU, one thread per sample).

Every function (and its helpers) is registered with ``numba.extending.register_jitable``, so
code compiled by numba (an ``njit`` kernel, or a CUDA kernel through numba's generic-target
overloads) may call the plain names directly; plain Python calls run the interpreted source
(slow, but handy for debugging and the CUDA simulator).

Interface (all arrays ``float64``, C-contiguous or strided views; nothing is allocated)
--------------------------------------------------------------------------------------------
``q`` (4,)
    Attitude estimate, quaternion scalar last, ``A(q)`` maps reference to body
    (``b = A(q) r``, docs/architecture.md), kept unit norm with ``q[3] >= 0`` by every step.
``b`` (3,)
    Gyro-bias estimate [rad/s]: ``omega_meas = omega_true + b + noise``.
``P`` (6, 6)
    Covariance of the error state ``x = [dθ, Δb]`` with ``q_true = δq(dθ) ⊗ q``
    (``dθ`` the rotation vector of the attitude error in the *body* frame, rad) and
    ``Δb = b_true − b`` (rad/s). Kept symmetric.
``work`` (WORK_SIZE,) = (48,)
    Scratch, contents on entry ignored and on exit unspecified. One per parallel lane.

``mekf_propagate(q, b, P, omega_meas, dt, sigma_v, sigma_u, work) -> None``
    Propagate over ``dt`` [s] (``dt >= 0``) with the gyro reading ``omega_meas`` (3,)
    [rad/s] held constant over the step. ``sigma_v`` [rad/s^0.5] angle random walk,
    ``sigma_u`` [rad/s^1.5] bias random walk (Farrenkopf model). Exact discrete ``Φ`` and
    ``Q`` for the held rate (closed forms below).
``mekf_update_vector(q, b, P, v_body_meas, v_ref, sigma, underweight, work) -> float``
    One vector measurement ``v_body_meas ≈ A(q_true) v_ref`` (both (3,), normalised here),
    isotropic noise ``sigma`` [rad] per axis (the 3-vector model ``R = σ² I``, Markley &
    Crassidis 2014 §6.2.1). Processed as three sequential scalar updates with a frozen
    linearisation point (algebraically identical to the 3-vector update), each with the
    Joseph-form covariance update, then the multiplicative reset. Returns the normalised
    innovation squared ``νᵀ S⁻¹ ν`` (NIS; ~χ²(2) for unit vectors with noise transverse to
    the direction, ~χ²(3) for isotropic 3-vector noise). If either vector is non-finite or
    zero, or ``sigma`` is not > 0, nothing changes and NaN is returned. ``underweight`` is
    the measurement-underweighting factor ``p >= 0`` (below; 0: the plain EKF update).
``mekf_update_quaternion(q, b, P, q_meas, sigma, work) -> float``
    Star-tracker update: ``q_meas = δq(v) ⊗ q_true``, ``v ~ N(0, σ² I)`` [rad], body frame.
    Returns the NIS (~χ²(3)); NaN and no change for a non-finite/zero ``q_meas``. Never
    underweighted: its innovation ``rotvec(q_meas ⊗ q⁻¹) = v + dθ + ½ v × dθ + …`` is linear
    in ``dθ`` up to a term of relative size ``|dθ|/2``, so a precise first star-tracker
    update is consistent as it is (and underweighting it only slows the convergence).
``mekf_nees(q_est, b_est, P, q_true, b_true, work) -> float``
    Normalised estimation error squared ``eᵀ P⁻¹ e``, ``e = [rotvec(q_true ⊗ q_est⁻¹),
    b_true − b_est]`` (~χ²(6) for a consistent filter), by Cholesky in ``work``; NaN if ``P``
    is not positive definite.
``gyro_step(omega_true, bias, sigma_v, sigma_u, dt, n_v, n_u, out) -> None``
    Discrete Farrenkopf gyro reading (re-exported from :mod:`adcskit.sensors._gyro_kernels`,
    where it is documented): with standard normal draws ``n_v``, ``n_u`` (3,),
    ``b⁺ = b + σu √dt n_u``; ``out = omega_true + (b + b⁺)/2 + sqrt(σv²/dt + σu² dt/12) n_v``;
    ``bias`` is updated in place to ``b⁺``.

Model and equations
-------------------
Error dynamics with ``ω̂ = omega_meas − b`` (Lefferts, Markley & Shuster 1982; Markley &
Crassidis 2014 eqs. 6.60-6.62)::

    dθ' = −[ω̂×] dθ − Δb − η_v ,   Δb' = η_u ,   E[η_v η_vᵀ] = σv² I δ(t), E[η_u η_uᵀ] = σu² I δ(t)

With ``W = [ω̂×]``, ``w = |ω̂|``, ``x = w dt`` and the entire functions
``g_n(x) = Σ_k (−1)^k x^{2k} / (2k + n)!`` (``g1 = sin x / x``, ``g2 = (1 − cos x)/x²``,
``g3 = (x − sin x)/x³``, ``g4 = (x²/2 − 1 + cos x)/x⁴``, ``g5 = (x³/6 − x + sin x)/x⁵``;
their series are used for ``x < 1``, so nothing cancels catastrophically at small rates)::

    Φ11 = I − dt g1 W + dt² g2 W²                       (M&C eq. 6.83 / 6.84)
    Φ12 = −dt I + dt² g2 W − dt³ g3 W²
    Q11 = (σv² dt + σu² dt³/3) I + 2 σu² dt⁵ g5 W²
    Q12 = −σu² (dt²/2 I − dt³ g3 W + dt⁴ g4 W²),   Q22 = σu² dt I

``Q = ∫₀^dt Φ(s) G Q_c Gᵀ Φ(s)ᵀ ds`` in closed form (``Φ11(s)`` is a rotation, so the
angle-random-walk part integrates to ``σv² dt I`` exactly); for ``w → 0`` it reduces to
Markley & Crassidis eq. 6.93. Quaternion: ``q⁺ = δq(ω̂ dt) ⊗ q`` (exact for the held rate),
``δq(θ) = [sin(|θ|/2) θ/|θ|, cos(|θ|/2)]``; reset ``q⁺ = δq(dθ̂) ⊗ q⁻``, ``b⁺ = b⁻ + Δb̂``.

Measurement underweighting (Zanetti, DeMars & Bishop 2010, after Lear's Shuttle practice;
the remedy for a precise first update that Lefferts, Markley & Shuster 1982 discuss; ``p``
default 0.2, chosen by the Monte-Carlo NEES in docs/estimation-mekf.md): for each scalar row ``h`` with noise variance ``σ²``, while
``h P hᵀ > σ²`` the update uses the inflated variance ``σ² + p h P hᵀ`` (gain, Joseph form
and NIS alike), i.e. ``S = (1 + p) h P hᵀ + σ²``. A precise measurement of a poorly known
attitude then removes only about ``1/(1 + p)`` of the innovation per update, so the EKF's
linearisation error — for a unit vector ``½ |dθ_∥| |dθ_⊥|`` transverse to it, with ``dθ_∥``
the unobserved rotation about it — is never folded in with a covariance that cannot hold
it; once ``h P hᵀ <= σ²`` the update is the plain EKF one. Both update kernels go through
the one helper ``_scalar_update``, which the batch filter, the stepping class and the
closed-loop simulator share; the star-tracker update passes ``p = 0`` (see above).

References
----------
.. [1] Lefferts, E. J., Markley, F. L. and Shuster, M. D., "Kalman filtering for spacecraft
   attitude estimation", JGCD 5(5), 1982, 417-429.
.. [2] Markley, F. L. and Crassidis, J. L., *Fundamentals of Spacecraft Attitude
   Determination and Control*, Springer, 2014, §6.2 (MEKF, eqs. 6.60-6.93).
.. [3] Crassidis, J. L. and Junkins, J. L., *Optimal Estimation of Dynamic Systems*, 2nd ed.,
   CRC, 2012, §7.2 (gyro model and its discrete simulation).
.. [4] Farrenkopf, R. L., "Analytic steady-state accuracy solutions for two common spacecraft
   attitude estimators", JGC 1(4), 1978 (gyro noise model).
.. [5] Lear, W. M., "Multi-phase navigation program for the space shuttle orbiter", NASA
   JSC internal note 73-FM-132, 1973, and Zanetti, R., DeMars, K. J. and Bishop, R. H.,
   "Underweighting nonlinear measurements", JGCD 33(5), 2010, 1670-1675 (measurement
   underweighting).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange
from numba.extending import register_jitable

from adcskit.attitude._device import compose_rotvec as _compose_rotvec
from adcskit.attitude._device import qerr as _qerr
from adcskit.attitude._device import rotate as _rotate
from adcskit.sensors._gyro_kernels import gyro_step, gyro_step_jit  # noqa: F401 (re-export)

#: Length of the ``work`` scratch array every kernel takes.
WORK_SIZE = 48

# work layout: propagate uses [0, 45): Φ11 (9), Φ12 (9), T = top rows of Φ P (18), W (9);
# updates use [0, 21): u (6), K (6), dx (6), bhat (3) and [21, 24): residual;
# NEES uses [0, 42): Cholesky factor (36) + error vector (6).
_U, _K, _DX, _BH, _Y = 0, 6, 12, 18, 21
_SERIES_X = 1.0  # below this |ω̂| dt the g_n series are used


#: 1/k! for k = 0..25 (a global tuple: a compile-time constant for njit and CUDA alike)
_INV_FACT = (1.0, 1.0, 0.5, 0.16666666666666666, 0.041666666666666664, 0.008333333333333333, 0.001388888888888889, 0.0001984126984126984, 2.48015873015873e-05, 2.7557319223985893e-06, 2.755731922398589e-07, 2.505210838544172e-08, 2.08767569878681e-09, 1.6059043836821613e-10, 1.1470745597729725e-11, 7.647163731819816e-13, 4.779477332387385e-14, 2.8114572543455206e-15, 1.5619206968586225e-16, 8.22063524662433e-18, 4.110317623312165e-19, 1.9572941063391263e-20, 8.896791392450574e-22, 3.8681701706306835e-23, 1.6117375710961184e-24, 6.446950284384474e-26)


@register_jitable
def _g(n, x):
    """``g_n(x) = Σ_k (−1)^k x^{2k} / (2k + n)!`` for n = 1..5 (see module docstring).

    Below ``x = 1`` a truncated series in Horner form (no divisions); the number of terms is
    chosen so the first omitted one is below 1e-17 relative (4 terms for x < 0.01, 7 for
    x < 0.2, 10 below 1). The Horner steps ``s = 1/(2k + n)! - x² s`` from ``k = m - 1`` down
    to 0 are written out (the same operations in the same order as the loop over ``k`` they
    replace, so the same doubles): numba's loop with a run-time trip count and tuple index
    made a propagation several times slower (docs/benchmarks.md, "Two cores per
    CPU-second")."""
    if x < _SERIES_X:
        x2 = x * x
        s = 0.0
        if not (x < 0.01):
            if not (x < 0.2):
                s = _INV_FACT[18 + n] - x2 * s  # k = 9 .. 7: ten terms
                s = _INV_FACT[16 + n] - x2 * s
                s = _INV_FACT[14 + n] - x2 * s
            s = _INV_FACT[12 + n] - x2 * s  # k = 6 .. 4: seven terms
            s = _INV_FACT[10 + n] - x2 * s
            s = _INV_FACT[8 + n] - x2 * s
        s = _INV_FACT[6 + n] - x2 * s  # k = 3 .. 0: four terms
        s = _INV_FACT[4 + n] - x2 * s
        s = _INV_FACT[2 + n] - x2 * s
        return _INV_FACT[n] - x2 * s
    if n == 1:
        return math.sin(x) / x
    if n == 2:
        return (1.0 - math.cos(x)) / (x * x)
    if n == 3:
        return (x - math.sin(x)) / (x * x * x)
    if n == 4:
        return (0.5 * x * x - 1.0 + math.cos(x)) / (x * x * x * x)
    return (x * x * x / 6.0 - x + math.sin(x)) / (x * x * x * x * x)


@register_jitable
def _error_rotvec(qa, qb, out, off):
    """Rotation vector of ``qa ⊗ qb⁻¹`` (rad) into ``out[off:off+3]``; returns False if a
    quaternion is zero or non-finite.

    The rotation vector is :func:`adcskit.attitude._device.qerr`'s (one source with the
    closed-loop simulator; bit-identical to the former copy here, whose ``f = 2 / d4`` at a zero
    vector part multiplied three zeros as qerr's ``f = 2`` does).
    """
    na = qa[0] * qa[0] + qa[1] * qa[1] + qa[2] * qa[2] + qa[3] * qa[3]
    nb = qb[0] * qb[0] + qb[1] * qb[1] + qb[2] * qb[2] + qb[3] * qb[3]
    if not (na > 0.0 and nb > 0.0 and math.isfinite(na) and math.isfinite(nb)):
        return False
    e0, e1, e2, _ = _qerr(qa[0], qa[1], qa[2], qa[3], qb[0], qb[1], qb[2], qb[3])
    out[off] = e0
    out[off + 1] = e1
    out[off + 2] = e2
    return True


@register_jitable
def _symmetrize(P):
    for i in range(6):
        for j in range(i + 1, 6):
            m = 0.5 * (P[i, j] + P[j, i])
            P[i, j] = m
            P[j, i] = m


@register_jitable
def mekf_propagate(q, b, P, omega_meas, dt, sigma_v, sigma_u, work):
    """Propagate ``q``, ``P`` over ``dt`` (``b`` is constant); see the module docstring."""
    w0 = omega_meas[0] - b[0]
    w1 = omega_meas[1] - b[1]
    w2 = omega_meas[2] - b[2]
    wn = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    x = wn * dt
    g1 = _g(1, x)
    g2 = _g(2, x)
    g3 = _g(3, x)
    g4 = _g(4, x)
    g5 = _g(5, x)
    # quaternion: q ← δq(ω̂ dt) ⊗ q
    _compose_rotvec(q, w0 * dt, w1 * dt, w2 * dt)
    # W = [ω̂×], W² = ω̂ω̂ᵀ − w² I; Φ11 in work[0:9], Φ12 in work[9:18] (row-major)
    dt2 = dt * dt
    dt3 = dt2 * dt
    a1 = -dt * g1
    a2 = dt2 * g2
    c1 = dt2 * g2
    c2 = -dt3 * g3
    # W = [ω̂×] in work[36:45] (row-major); W² = ω̂ω̂ᵀ − w² I
    work[36] = 0.0
    work[37] = -w2
    work[38] = w1
    work[39] = w2
    work[40] = 0.0
    work[41] = -w0
    work[42] = -w1
    work[43] = w0
    work[44] = 0.0
    wn2 = wn * wn
    for i in range(3):
        wi = w0 if i == 0 else (w1 if i == 1 else w2)
        for j in range(3):
            wj = w0 if j == 0 else (w1 if j == 1 else w2)
            wij = work[36 + 3 * i + j]
            w2ij = wi * wj - (wn2 if i == j else 0.0)
            work[3 * i + j] = (1.0 if i == j else 0.0) + a1 * wij + a2 * w2ij
            work[9 + 3 * i + j] = (-dt if i == j else 0.0) + c1 * wij + c2 * w2ij
    # T = rows 0..2 of Φ P = Φ11 P[0:3, :] + Φ12 P[3:6, :]  -> work[18:36]
    for i in range(3):
        for j in range(6):
            s = 0.0
            for k in range(3):
                s += work[3 * i + k] * P[k, j] + work[9 + 3 * i + k] * P[3 + k, j]
            work[18 + 6 * i + j] = s
    # Φ P Φᵀ: top-left T[:, 0:3] Φ11ᵀ + T[:, 3:6] Φ12ᵀ; top-right T[:, 3:6];
    # bottom-right P[3:6, 3:6] unchanged; bottom-left = transpose of top-right
    for i in range(3):
        for j in range(3):
            s = 0.0
            for k in range(3):
                s += work[18 + 6 * i + k] * work[3 * j + k] + work[18 + 6 * i + 3 + k] * work[9 + 3 * j + k]
            P[i, j] = s
    for i in range(3):
        for j in range(3):
            P[i, 3 + j] = work[18 + 6 * i + 3 + j]
            P[3 + j, i] = work[18 + 6 * i + 3 + j]
    # + Q (exact for the held rate)
    su2 = sigma_u * sigma_u
    q11d = sigma_v * sigma_v * dt + su2 * dt3 / 3.0
    q11w2 = 2.0 * su2 * dt3 * dt2 * g5
    q12d = -su2 * 0.5 * dt2
    q12w = su2 * dt3 * g3
    q12w2 = -su2 * dt2 * dt2 * g4
    q22 = su2 * dt
    for i in range(3):
        wi = w0 if i == 0 else (w1 if i == 1 else w2)
        for j in range(3):
            wj = w0 if j == 0 else (w1 if j == 1 else w2)
            w2ij = wi * wj - (wn2 if i == j else 0.0)
            wij = work[36 + 3 * i + j]
            P[i, j] += (q11d if i == j else 0.0) + q11w2 * w2ij
            q12 = (q12d if i == j else 0.0) + q12w * wij + q12w2 * w2ij
            P[i, 3 + j] += q12
            P[3 + j, i] += q12
        P[3 + i, 3 + i] += q22
    _symmetrize(P)


@register_jitable
def _scalar_update(P, work, h0, h1, h2, innov, var, underweight):
    """One scalar measurement ``z = h · dθ`` (the vector and star-tracker rows have no bias part) with
    residual ``innov`` (already corrected for the accumulated ``dx``) and noise variance
    ``var``: Joseph-form update of ``P`` and ``dx`` (work[_DX:_DX+6]); returns ``innov²/s``.

    Joseph form ``(I − K h)P(I − K h)ᵀ + var K Kᵀ`` expanded with ``u = P hᵀ``,
    ``s = h u + var``: ``P − K uᵀ − u Kᵀ + s K Kᵀ`` (symmetric by construction and, unlike
    ``P − u uᵀ / s``, first-order insensitive to errors in ``K``).

    Underweighting (module docstring): while ``h u > var`` the noise variance is inflated to
    ``var + underweight · h u`` (gain, Joseph form and NIS all use the inflated value)."""
    for i in range(6):
        work[_U + i] = P[i, 0] * h0 + P[i, 1] * h1 + P[i, 2] * h2
    hu = work[_U] * h0 + work[_U + 1] * h1 + work[_U + 2] * h2
    if hu > var:
        var = var + underweight * hu
    s = hu + var
    inv_s = 1.0 / s
    for i in range(6):
        work[_K + i] = work[_U + i] * inv_s
    for i in range(6):
        ki = work[_K + i]
        ui = work[_U + i]
        for j in range(i, 6):
            v = P[i, j] - ki * work[_U + j] - ui * work[_K + j] + s * ki * work[_K + j]
            P[i, j] = v
            P[j, i] = v
        work[_DX + i] += ki * innov
    return innov * innov * inv_s


@register_jitable
def _reset(q, b, work):
    _compose_rotvec(q, work[_DX], work[_DX + 1], work[_DX + 2])
    b[0] += work[_DX + 3]
    b[1] += work[_DX + 4]
    b[2] += work[_DX + 5]


@register_jitable
def mekf_update_vector(q, b, P, v_body_meas, v_ref, sigma, underweight, work):
    """Vector-measurement update (see the module docstring); returns the NIS or NaN."""
    nb = v_body_meas[0] * v_body_meas[0] + v_body_meas[1] * v_body_meas[1] + v_body_meas[2] * v_body_meas[2]
    nr = v_ref[0] * v_ref[0] + v_ref[1] * v_ref[1] + v_ref[2] * v_ref[2]
    if not (nb > 0.0 and nr > 0.0 and math.isfinite(nb) and math.isfinite(nr) and sigma > 0.0):
        return math.nan
    nb = 1.0 / math.sqrt(nb)
    nr = 1.0 / math.sqrt(nr)
    r0 = v_ref[0] * nr
    r1 = v_ref[1] * nr
    r2 = v_ref[2] * nr
    # bhat = A(q) r, A(q) = (q4² − |e|²) I + 2 e eᵀ − 2 q4 [e×]
    bh0, bh1, bh2 = _rotate(q[0], q[1], q[2], q[3], r0, r1, r2)
    work[_Y] = v_body_meas[0] * nb - bh0
    work[_Y + 1] = v_body_meas[1] * nb - bh1
    work[_Y + 2] = v_body_meas[2] * nb - bh2
    for i in range(6):
        work[_DX + i] = 0.0
    var = sigma * sigma
    nis = 0.0
    # H = [[bhat×], 0]: b_true ≈ bhat + [bhat×] dθ ; row i of [bhat×]
    for i in range(3):
        if i == 0:
            h0, h1, h2 = 0.0, -bh2, bh1
        elif i == 1:
            h0, h1, h2 = bh2, 0.0, -bh0
        else:
            h0, h1, h2 = -bh1, bh0, 0.0
        innov = work[_Y + i] - (h0 * work[_DX] + h1 * work[_DX + 1] + h2 * work[_DX + 2])
        nis += _scalar_update(P, work, h0, h1, h2, innov, var, underweight)
    _reset(q, b, work)
    return nis


@register_jitable
def mekf_update_quaternion(q, b, P, q_meas, sigma, work):
    """Star-tracker quaternion update (see the module docstring); returns the NIS or NaN."""
    if not (sigma > 0.0) or not _error_rotvec(q_meas, q, work, _Y):
        return math.nan
    for i in range(6):
        work[_DX + i] = 0.0
    var = sigma * sigma
    nis = 0.0
    for i in range(3):
        innov = work[_Y + i] - work[_DX + i]
        nis += _scalar_update(P, work, 1.0 if i == 0 else 0.0, 1.0 if i == 1 else 0.0,
                              1.0 if i == 2 else 0.0, innov, var, 0.0)
    _reset(q, b, work)
    return nis


@register_jitable
def mekf_nees(q_est, b_est, P, q_true, b_true, work):
    """NEES ``eᵀ P⁻¹ e`` (see the module docstring); NaN if ``P`` is not positive definite."""
    if not _error_rotvec(q_true, q_est, work, 36):
        return math.nan
    for i in range(3):
        work[39 + i] = b_true[i] - b_est[i]
    # Cholesky P = L Lᵀ (lower, row-major in work[0:36]) and forward substitution L y = e
    for i in range(6):
        for j in range(i + 1):
            s = P[i, j]
            for k in range(j):
                s -= work[6 * i + k] * work[6 * j + k]
            if i == j:
                if not (s > 0.0) or not math.isfinite(s):
                    return math.nan
                work[6 * i + i] = math.sqrt(s)
            else:
                work[6 * i + j] = s / work[6 * j + j]
    nees = 0.0
    for i in range(6):
        s = work[36 + i]
        for k in range(i):
            s -= work[6 * i + k] * work[36 + k]
        y = s / work[6 * i + i]
        work[36 + i] = y
        nees += y * y
    return nees


# --- whole-batch filter: the time loop of one sample, and the prange wrapper -----------------


@register_jitable
def _filter_one(k, q0, b0, P0, dt, gyro, vb, vr, sig, qst, sig_st, sigma_v, sigma_u, uw,
                qtrue, btrue, q_out, b_out, Pd_out, P_out, nees, nis, nis_st, P, work):
    """Run sample ``k`` over all ``T`` epochs (see :func:`filter_batch`). ``P``, ``work``:
    this lane's scratch (6, 6) and (WORK_SIZE,)."""
    T = gyro.shape[1]
    m = vb.shape[2]
    kr = k if vr.shape[0] > 1 else 0
    has_st = qst.shape[0] > 0
    has_truth = qtrue.shape[0] > 0
    full_P = P_out.shape[0] > 0
    for i in range(6):
        for j in range(6):
            P[i, j] = P0[k, i, j]
    for t in range(T):
        q = q_out[k, t]
        b = b_out[k, t]
        if t == 0:
            for i in range(4):
                q[i] = q0[k, i]
            for i in range(3):
                b[i] = b0[k, i]
        else:
            for i in range(4):
                q[i] = q_out[k, t - 1, i]
            for i in range(3):
                b[i] = b_out[k, t - 1, i]
            mekf_propagate(q, b, P, gyro[k, t - 1], dt[t - 1], sigma_v, sigma_u, work)
        for j in range(m):
            if math.isfinite(vb[k, t, j, 0]):
                nis[k, t, j] = mekf_update_vector(q, b, P, vb[k, t, j], vr[kr, t, j], sig[j], uw, work)
            else:
                nis[k, t, j] = math.nan
        if has_st:
            if math.isfinite(qst[k, t, 0]):
                nis_st[k, t] = mekf_update_quaternion(q, b, P, qst[k, t], sig_st, work)
            else:
                nis_st[k, t] = math.nan
        for i in range(6):
            Pd_out[k, t, i] = P[i, i]
        if full_P:
            for i in range(6):
                for j in range(6):
                    P_out[k, t, i, j] = P[i, j]
        if has_truth:
            nees[k, t] = mekf_nees(q, b, P, qtrue[k, t], btrue[k, t], work)


@njit(cache=True, parallel=True, nogil=True)
def filter_batch(q0, b0, P0, dt, gyro, vb, vr, sig, qst, sig_st, sigma_v, sigma_u, uw, qtrue,
                 btrue, q_out, b_out, Pd_out, P_out, nees, nis, nis_st, P_scr, work):
    """All samples in parallel (``prange``), each through :func:`_filter_one`.

    Shapes: ``q0`` (N, 4), ``b0`` (N, 3), ``P0`` (N, 6, 6), ``dt`` (T − 1,), ``gyro``
    (N, T, 3) (``gyro[:, t]`` held over ``[t_t, t_{t+1})``), ``vb`` (N, T, m, 3) body
    measurements (a NaN first component: no measurement), ``vr`` (1 or N, T, m, 3),
    ``sig`` (m,), ``qst`` (N, T, 4) or (0, T, 4) star-tracker quaternions (NaN: none),
    ``qtrue`` (N, T, 4) / ``btrue`` (N, T, 3) or (0, ...) for NEES. Outputs ``q_out``
    (N, T, 4), ``b_out`` (N, T, 3), ``Pd_out`` (N, T, 6) diagonal of P, ``P_out``
    (N, T, 6, 6) or (0, ...), ``nees`` (N, T), ``nis`` (N, T, m), ``nis_st`` (N, T);
    scratch ``P_scr`` (N, 6, 6), ``work`` (N, WORK_SIZE).
    """
    N = q0.shape[0]
    for k in prange(N):
        # prange's index is uint64, which would unify with the int 0 of a shared-reference
        # index to float64: pass it as int64
        _filter_one(np.int64(k), q0, b0, P0, dt, gyro, vb, vr, sig, qst, sig_st, sigma_v,
                    sigma_u, uw, qtrue, btrue, q_out, b_out, Pd_out, P_out, nees, nis, nis_st, P_scr[k], work[k])


# --- njit dispatchers for callers outside compiled code (the stepping class, tests) ---------
mekf_propagate_jit = njit(cache=True, nogil=True)(mekf_propagate)
mekf_update_vector_jit = njit(cache=True, nogil=True)(mekf_update_vector)
mekf_update_quaternion_jit = njit(cache=True, nogil=True)(mekf_update_quaternion)
mekf_nees_jit = njit(cache=True, nogil=True)(mekf_nees)
