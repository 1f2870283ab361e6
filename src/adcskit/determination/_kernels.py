"""Compiled (numba) kernels of the Wahba point solvers.

Private: the public front end is :func:`adcskit.determination.solve_wahba`, which validates
its inputs and calls :func:`solve_batch_serial` (small batches, single calls) or
:func:`solve_batch_parallel` (large batches, all cores) on plain ``float64`` arrays.

Why hand-written: no kept library offers a *batched*, compiled Wahba solver (scipy's
``Rotation.align_vectors`` solves one problem per call through an SVD; ``ahrs`` is pure
Python per call). The kernels are self-contained (their own quaternion/DCM helpers) so that
numba compiles them without importing the rest of adcskit.

Conventions: quaternion scalar last ``q = [q1, q2, q3, q4]``,
``A(q) = (q4² − |e|²) I + 2 e eᵀ − 2 q4 [e×]`` maps reference to body (``b = A r``),
canonical sign ``q4 >= 0``. Davenport's matrix
``K = [[B + Bᵀ − tr(B) I, z], [zᵀ, tr(B)]]``, ``B = Σ a_i b_i r_iᵀ``, ``z = Σ a_i b_i × r_i``
with the weights normalised to ``Σ a_i = 1`` (Markley & Crassidis 2014, §5.5).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

# method codes (order of METHODS in wahba.py)
TRIAD, QMETHOD, QUEST, ESOQ2, SVD, FOAM, TWO_VECTOR, FLAE = 0, 1, 2, 3, 4, 5, 6, 7

# status codes
OK = 0
NONFINITE = 1
ZERO_LENGTH = 2
TOO_FEW = 3
COLLINEAR_BODY = 4
COLLINEAR_REF = 5
NOT_CONVERGED = 6

# a pair of unit vectors whose cross product is below this is treated as parallel:
# at 1e-12 rad the rotation about the common axis is undetermined to double precision
COLLINEAR_SIN = 1e-12
# residual ||K q - λ q|| above this multiple of machine epsilon (K has norm <= ~3) sends
# QUEST/ESOQ2/FOAM to the eigen-solver fallback
RESIDUAL_TOL = 64.0 * 2.220446049250313e-16


@njit(cache=True, inline="always", error_model="numpy")
def _det3(m00, m01, m02, m10, m11, m12, m20, m21, m22):
    return m00 * (m11 * m22 - m12 * m21) - m01 * (m10 * m22 - m12 * m20) + m02 * (m10 * m21 - m11 * m20)


@njit(cache=True, error_model="numpy")
def _unit_scaled(v, out):
    """Normalise v into out, scaling by max |v_i| first (no over/underflow); status code."""
    m = 0.0
    for j in range(3):
        if not np.isfinite(v[j]):
            return NONFINITE
        m = max(m, abs(v[j]))
    if m == 0.0:
        return ZERO_LENGTH
    s = 0.0
    for j in range(3):
        out[j] = v[j] / m
        s += out[j] * out[j]
    s = 1.0 / np.sqrt(s)
    for j in range(3):
        out[j] *= s
    return OK


@njit(cache=True, error_model="numpy")
def _dcm_to_quat(A, q):
    """Shepperd's method (robust at every attitude), canonical sign q4 >= 0."""
    tr = A[0, 0] + A[1, 1] + A[2, 2]
    if tr >= A[0, 0] and tr >= A[1, 1] and tr >= A[2, 2]:
        q4 = 0.5 * np.sqrt(max(1.0 + tr, 0.0))
        f = 0.25 / q4
        q[0] = (A[1, 2] - A[2, 1]) * f
        q[1] = (A[2, 0] - A[0, 2]) * f
        q[2] = (A[0, 1] - A[1, 0]) * f
        q[3] = q4
    elif A[0, 0] >= A[1, 1] and A[0, 0] >= A[2, 2]:
        e = 0.5 * np.sqrt(max(1.0 + 2.0 * A[0, 0] - tr, 0.0))
        f = 0.25 / e
        q[0] = e
        q[1] = (A[0, 1] + A[1, 0]) * f
        q[2] = (A[0, 2] + A[2, 0]) * f
        q[3] = (A[1, 2] - A[2, 1]) * f
    elif A[1, 1] >= A[2, 2]:
        e = 0.5 * np.sqrt(max(1.0 + 2.0 * A[1, 1] - tr, 0.0))
        f = 0.25 / e
        q[0] = (A[0, 1] + A[1, 0]) * f
        q[1] = e
        q[2] = (A[1, 2] + A[2, 1]) * f
        q[3] = (A[2, 0] - A[0, 2]) * f
    else:
        e = 0.5 * np.sqrt(max(1.0 + 2.0 * A[2, 2] - tr, 0.0))
        f = 0.25 / e
        q[0] = (A[0, 2] + A[2, 0]) * f
        q[1] = (A[1, 2] + A[2, 1]) * f
        q[2] = e
        q[3] = (A[0, 1] - A[1, 0]) * f
    _normalise_quat(q)


@njit(cache=True, inline="always", error_model="numpy")
def _normalise_quat(q):
    s = 1.0 / np.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    if q[3] < 0.0:
        s = -s
    q[0] *= s
    q[1] *= s
    q[2] *= s
    q[3] *= s


@njit(cache=True, inline="always", error_model="numpy")
def _build_K(B, K):
    """Davenport's K from the attitude profile matrix B (z from B's antisymmetric part)."""
    sig = B[0, 0] + B[1, 1] + B[2, 2]
    for i in range(3):
        for j in range(3):
            K[i, j] = B[i, j] + B[j, i]
        K[i, i] -= sig
    K[0, 3] = K[3, 0] = B[1, 2] - B[2, 1]
    K[1, 3] = K[3, 1] = B[2, 0] - B[0, 2]
    K[2, 3] = K[3, 2] = B[0, 1] - B[1, 0]
    K[3, 3] = sig


@njit(cache=True, inline="always", error_model="numpy")
def _rayleigh(K, q):
    s = 0.0
    for i in range(4):
        t = 0.0
        for j in range(4):
            t += K[i, j] * q[j]
        s += q[i] * t
    return s


@njit(cache=True, inline="always", error_model="numpy")
def _residual(K, q, lam):
    s = 0.0
    for i in range(4):
        t = -lam * q[i]
        for j in range(4):
            t += K[i, j] * q[j]
        s += t * t
    return np.sqrt(s)


@njit(cache=True, error_model="numpy")
def _eig_quat(K, q):
    """q-method: eigenvector of the largest eigenvalue of K (LAPACK syevd via numba)."""
    w, v = np.linalg.eigh(K)
    for i in range(4):
        q[i] = v[i, 3]
    _normalise_quat(q)


@njit(cache=True, inline="always", error_model="numpy")
def _lambda_max(B, n_obs, lam2):
    """Largest eigenvalue of K by Newton's method on Shuster's characteristic polynomial.

    ``lam2`` > 0 is the closed-form two-observation value, used directly (Markley 1999).
    Returns (lambda, converged).
    """
    if lam2 > 0.0:
        return lam2, True
    sig = B[0, 0] + B[1, 1] + B[2, 2]
    S00 = 2 * B[0, 0]
    S11 = 2 * B[1, 1]
    S22 = 2 * B[2, 2]
    S01 = B[0, 1] + B[1, 0]
    S02 = B[0, 2] + B[2, 0]
    S12 = B[1, 2] + B[2, 1]
    z0 = B[1, 2] - B[2, 1]
    z1 = B[2, 0] - B[0, 2]
    z2 = B[0, 1] - B[1, 0]
    kap = (S11 * S22 - S12 * S12) + (S00 * S22 - S02 * S02) + (S00 * S11 - S01 * S01)
    detS = _det3(S00, S01, S02, S01, S11, S12, S02, S12, S22)
    Sz0 = S00 * z0 + S01 * z1 + S02 * z2
    Sz1 = S01 * z0 + S11 * z1 + S12 * z2
    Sz2 = S02 * z0 + S12 * z1 + S22 * z2
    zz = z0 * z0 + z1 * z1 + z2 * z2
    zSz = z0 * Sz0 + z1 * Sz1 + z2 * Sz2
    zS2z = Sz0 * Sz0 + Sz1 * Sz1 + Sz2 * Sz2
    a = sig * sig - kap
    b = sig * sig + zz
    c = detS + zSz
    d = zS2z
    lam = 1.0
    for _ in range(50):
        l2 = lam * lam
        f = (l2 - a) * (l2 - b) - c * lam + (c * sig - d)
        fp = 2.0 * lam * (2.0 * l2 - a - b) - c
        if fp == 0.0:
            return lam, False
        step = f / fp
        lam -= step
        if abs(step) <= 1e-15 * abs(lam):
            return lam, True
    return lam, False


@njit(cache=True, inline="always", error_model="numpy")
def _rotated_B(B, k, Bk):
    """B of the problem with reference vectors rotated by 180° about axis k (-1: none)."""
    for i in range(3):
        for j in range(3):
            s = 1.0 if (k < 0 or j == k) else -1.0
            Bk[i, j] = B[i, j] * s


@njit(cache=True, inline="always", error_model="numpy")
def _unrotate(qp, k, q):
    """q such that A(q) = A(qp) R_k, R_k the 180° rotation about axis k (q = qp ⊗ [e_k; 0])."""
    if k < 0:
        for i in range(4):
            q[i] = qp[i]
    elif k == 0:
        q[0], q[1], q[2], q[3] = qp[3], -qp[2], qp[1], -qp[0]
    elif k == 1:
        q[0], q[1], q[2], q[3] = qp[2], qp[3], -qp[0], -qp[1]
    else:
        q[0], q[1], q[2], q[3] = -qp[1], qp[0], qp[3], -qp[2]
    # not normalised here: the caller's refinement step normalises


@njit(cache=True, inline="always", error_model="numpy")
def _quest_quat(B, lam, q, Bk, qp):
    """QUEST (Shuster & Oh 1981) with the method of sequential rotations.

    For each frame k in {none, x, y, z}: q' ∝ [adj(M) z; det M], M = (λ+σ)I − S; the frame
    with the largest |q4'| is kept (avoids the 180° singularity), then rotated back.
    """
    best = -1.0
    bestk = -1
    for k in range(-1, 3):
        _rotated_B(B, k, Bk)
        sig = Bk[0, 0] + Bk[1, 1] + Bk[2, 2]
        m00 = lam + sig - 2 * Bk[0, 0]
        m11 = lam + sig - 2 * Bk[1, 1]
        m22 = lam + sig - 2 * Bk[2, 2]
        m01 = -(Bk[0, 1] + Bk[1, 0])
        m02 = -(Bk[0, 2] + Bk[2, 0])
        m12 = -(Bk[1, 2] + Bk[2, 1])
        z0 = Bk[1, 2] - Bk[2, 1]
        z1 = Bk[2, 0] - Bk[0, 2]
        z2 = Bk[0, 1] - Bk[1, 0]
        c00 = m11 * m22 - m12 * m12
        c11 = m00 * m22 - m02 * m02
        c22 = m00 * m11 - m01 * m01
        c01 = m02 * m12 - m01 * m22
        c02 = m01 * m12 - m02 * m11
        c12 = m01 * m02 - m00 * m12
        x0 = c00 * z0 + c01 * z1 + c02 * z2
        x1 = c01 * z0 + c11 * z1 + c12 * z2
        x2 = c02 * z0 + c12 * z1 + c22 * z2
        g = m00 * c00 + m01 * c01 + m02 * c02
        nrm = np.sqrt(x0 * x0 + x1 * x1 + x2 * x2 + g * g)
        if nrm > 0.0 and abs(g) / nrm > best:
            best = abs(g) / nrm
            bestk = k
            qp[0] = x0 / nrm
            qp[1] = x1 / nrm
            qp[2] = x2 / nrm
            qp[3] = g / nrm
        if best > 0.5:  # |q4'| > 0.5: the rotation angle is < 120°, well conditioned
            break
    if best < 0.0:
        return False
    _unrotate(qp, bestk, q)
    return True


@njit(cache=True, inline="always", error_model="numpy")
def _esoq2_quat(B, lam, q, Bk, qp):
    """ESOQ2 (Mortari 1997): rotation axis as the null vector of the 3×3 matrix
    M = (λ − σ)[(λ + σ) I − S] − z zᵀ (cross product of its two most independent rows),
    q' ∝ [(λ − σ) e; zᵀ e]. The frame (none/x/y/z 180° rotation) maximising λ − σ is used,
    which keeps M of rank two (Mortari's sequential rotation).
    """
    # trace of B in each frame: rotating about axis k flips the signs of the other diagonals
    b0, b1, b2 = B[0, 0], B[1, 1], B[2, 2]
    bestk = -1
    best = lam - (b0 + b1 + b2)
    for k in range(3):
        t = lam - ((b0 if k == 0 else -b0) + (b1 if k == 1 else -b1) + (b2 if k == 2 else -b2))
        if t > best:
            best = t
            bestk = k
    _rotated_B(B, bestk, Bk)
    sig = Bk[0, 0] + Bk[1, 1] + Bk[2, 2]
    t = lam - sig
    z0 = Bk[1, 2] - Bk[2, 1]
    z1 = Bk[2, 0] - Bk[0, 2]
    z2 = Bk[0, 1] - Bk[1, 0]
    p = lam + sig
    m00 = t * (p - 2 * Bk[0, 0]) - z0 * z0
    m11 = t * (p - 2 * Bk[1, 1]) - z1 * z1
    m22 = t * (p - 2 * Bk[2, 2]) - z2 * z2
    m01 = -t * (Bk[0, 1] + Bk[1, 0]) - z0 * z1
    m02 = -t * (Bk[0, 2] + Bk[2, 0]) - z0 * z2
    m12 = -t * (Bk[1, 2] + Bk[2, 1]) - z1 * z2
    # cross products of row pairs (M symmetric)
    a0 = m01 * m12 - m02 * m11  # row0 x row1
    a1 = m02 * m01 - m00 * m12
    a2 = m00 * m11 - m01 * m01
    b0 = m01 * m22 - m02 * m12  # row0 x row2
    b1 = m02 * m02 - m00 * m22
    b2 = m00 * m12 - m01 * m02
    c0 = m11 * m22 - m12 * m12  # row1 x row2
    c1 = m12 * m02 - m01 * m22
    c2 = m01 * m12 - m11 * m02
    na = a0 * a0 + a1 * a1 + a2 * a2
    nb = b0 * b0 + b1 * b1 + b2 * b2
    nc = c0 * c0 + c1 * c1 + c2 * c2
    if na >= nb and na >= nc:
        e0, e1, e2 = a0, a1, a2
    elif nb >= nc:
        e0, e1, e2 = b0, b1, b2
    else:
        e0, e1, e2 = c0, c1, c2
    qp[0] = t * e0
    qp[1] = t * e1
    qp[2] = t * e2
    qp[3] = z0 * e0 + z1 * e1 + z2 * e2
    nrm = np.sqrt(qp[0] * qp[0] + qp[1] * qp[1] + qp[2] * qp[2] + qp[3] * qp[3])
    if not nrm > 0.0:
        return False
    _unrotate(qp, bestk, q)
    return True


@njit(cache=True, error_model="numpy")
def _foam_quat(B, q, A):
    """FOAM (Markley 1993): λ by Newton on (λ² − ‖B‖²)² − 8λ det B − 4‖adj B‖² = 0, then
    A = [(κ + ‖B‖²) B + λ adj(B)ᵀ − B Bᵀ B] / ζ, κ = (λ² − ‖B‖²)/2, ζ = κλ − det B.
    """
    nB2 = 0.0
    for i in range(3):
        for j in range(3):
            nB2 += B[i, j] * B[i, j]
    # cofactor matrix C = adj(B)ᵀ
    C00 = B[1, 1] * B[2, 2] - B[1, 2] * B[2, 1]
    C01 = B[1, 2] * B[2, 0] - B[1, 0] * B[2, 2]
    C02 = B[1, 0] * B[2, 1] - B[1, 1] * B[2, 0]
    C10 = B[0, 2] * B[2, 1] - B[0, 1] * B[2, 2]
    C11 = B[0, 0] * B[2, 2] - B[0, 2] * B[2, 0]
    C12 = B[0, 1] * B[2, 0] - B[0, 0] * B[2, 1]
    C20 = B[0, 1] * B[1, 2] - B[0, 2] * B[1, 1]
    C21 = B[0, 2] * B[1, 0] - B[0, 0] * B[1, 2]
    C22 = B[0, 0] * B[1, 1] - B[0, 1] * B[1, 0]
    nadj2 = (C00 * C00 + C01 * C01 + C02 * C02 + C10 * C10 + C11 * C11 + C12 * C12
             + C20 * C20 + C21 * C21 + C22 * C22)
    detB = B[0, 0] * C00 + B[0, 1] * C01 + B[0, 2] * C02
    lam = 1.0
    ok = False
    for _ in range(50):
        u = lam * lam - nB2
        f = u * u - 8.0 * lam * detB - 4.0 * nadj2
        fp = 4.0 * lam * u - 8.0 * detB
        if fp == 0.0:
            break
        step = f / fp
        lam -= step
        if abs(step) <= 1e-15 * abs(lam):
            ok = True
            break
    kap = 0.5 * (lam * lam - nB2)
    zeta = kap * lam - detB
    if zeta == 0.0 or not np.isfinite(zeta):
        return False
    # B Bᵀ B
    BBt = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            BBt[i, j] = B[i, 0] * B[j, 0] + B[i, 1] * B[j, 1] + B[i, 2] * B[j, 2]
    C = ((C00, C01, C02), (C10, C11, C12), (C20, C21, C22))
    for i in range(3):
        for j in range(3):
            bbb = BBt[i, 0] * B[0, j] + BBt[i, 1] * B[1, j] + BBt[i, 2] * B[2, j]
            A[i, j] = ((kap + nB2) * B[i, j] + lam * C[i][j] - bbb) / zeta
    _dcm_to_quat(A, q)
    return ok


@njit(cache=True, error_model="numpy")
def _flae_quat(B, K, q):
    """FLAE (Wu et al. 2018): λ_max of the traceless K from the symbolic roots of its
    characteristic quartic ``λ⁴ + τ1 λ² + τ2 λ + τ3`` (their eqs. 48-53), then the eigenvector
    by Gauss-Jordan elimination of ``N = K − λ I`` (their eqs. 54-55). Returns (λ, ok).

    ``τ1 = −2 ||B||²_F``, ``τ2 = −8 det B``, ``τ3 = det K`` (Wu et al.'s ``W`` is ``K``
    under a signed permutation of the quaternion, same spectrum). Differences from the paper,
    for robustness: the complex cube root of their ``T1`` is taken in its trigonometric form
    when the resolvent has three real roots (the usual case; the paper leaves it to complex
    arithmetic), the largest of the four roots is kept (the paper: the root closest to 1,
    the same root for consistent data), the symbolic root is polished by Newton steps on
    the same quartic (FLAE's own "newton" variant, started here from the symbolic root: the
    cube-root formula loses up to ~1e-8 relative where three roots nearly coincide, i.e.
    for near noise-free data), and the elimination uses full pivoting, so no component of
    ``q`` is assumed non-zero (the paper's back-substitution divides by ``q4`` and fails at
    180° rotations).
    """
    nB2 = 0.0
    for i in range(3):
        for j in range(3):
            nB2 += B[i, j] * B[i, j]
    detB = _det3(B[0, 0], B[0, 1], B[0, 2], B[1, 0], B[1, 1], B[1, 2], B[2, 0], B[2, 1], B[2, 2])
    t1 = -2.0 * nB2
    t2 = -8.0 * detB
    # τ3 = det K by the Laplace expansion in 2×2 minors of rows (0, 1) and (2, 3)
    s0 = K[0, 0] * K[1, 1] - K[1, 0] * K[0, 1]
    s1 = K[0, 0] * K[1, 2] - K[1, 0] * K[0, 2]
    s2 = K[0, 0] * K[1, 3] - K[1, 0] * K[0, 3]
    s3 = K[0, 1] * K[1, 2] - K[1, 1] * K[0, 2]
    s4 = K[0, 1] * K[1, 3] - K[1, 1] * K[0, 3]
    s5 = K[0, 2] * K[1, 3] - K[1, 2] * K[0, 3]
    c5 = K[2, 2] * K[3, 3] - K[3, 2] * K[2, 3]
    c4 = K[2, 1] * K[3, 3] - K[3, 1] * K[2, 3]
    c3 = K[2, 1] * K[3, 2] - K[3, 1] * K[2, 2]
    c2 = K[2, 0] * K[3, 3] - K[3, 0] * K[2, 3]
    c1 = K[2, 0] * K[3, 2] - K[3, 0] * K[2, 2]
    c0 = K[2, 0] * K[3, 1] - K[3, 0] * K[2, 1]
    t3 = s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0
    T0 = 2.0 * t1 * t1 * t1 + 27.0 * t2 * t2 - 72.0 * t1 * t3
    u = t1 * t1 + 12.0 * t3
    D = T0 * T0 - 4.0 * u * u * u
    if D >= 0.0:
        T1 = np.cbrt(T0 + np.sqrt(D))
        s2 = 2.0 ** (4.0 / 3.0) * u / T1 + 2.0 ** (2.0 / 3.0) * T1 if T1 != 0.0 else 0.0
    else:  # T1 = (T0 + i sqrt(−D))^(1/3); 2^(4/3) u / T1 + 2^(2/3) T1 = 2^(5/3) Re(T1)
        rho = (4.0 * u * u * u) ** (1.0 / 6.0)
        s2 = 2.0 ** (5.0 / 3.0) * rho * np.cos(np.arctan2(np.sqrt(-D), T0) / 3.0)
    T2 = np.sqrt(max(-4.0 * t1 + s2, 0.0))
    alpha = 1.0 / (2.0 * np.sqrt(6.0))
    lam = -np.inf
    if T2 > 0.0:
        k1 = -T2 * T2 - 12.0 * t1
        k2 = 12.0 * np.sqrt(6.0) * t2 / T2
        r1 = np.sqrt(max(k1 - k2, 0.0))
        r2 = np.sqrt(max(k1 + k2, 0.0))
        lam = max(alpha * (T2 + r1), alpha * (T2 - r1), -alpha * (T2 - r2), -alpha * (T2 + r2))
    else:
        lam = 1.0
    # Newton polish on f(λ) = λ⁴ + τ1 λ² + τ2 λ + τ3
    for _ in range(8):
        l2 = lam * lam
        f = (l2 + t1) * l2 + t2 * lam + t3
        fp = 4.0 * l2 * lam + 2.0 * t1 * lam + t2
        if fp == 0.0:
            break
        step = f / fp
        lam -= step
        if abs(step) <= 1e-15 * abs(lam):
            break
    if not np.isfinite(lam):
        return lam, False
    # Gauss-Jordan elimination of N = K − λ I with full pivoting: three pivots (rows p,
    # columns recorded in the bit mask ``used``), the remaining column is the free variable
    # of the one-dimensional null space. Done in place in K (no allocation); K is rebuilt
    # from B afterwards for the caller's refinement and residual check.
    M = K
    for i in range(4):
        M[i, i] -= lam
    used = 0
    pc0 = pc1 = pc2 = -1
    for p in range(3):
        bi, bj, bv = p, 0, -1.0
        for i in range(p, 4):
            for j in range(4):
                if not (used >> j) & 1:
                    v = abs(M[i, j])
                    if v > bv:
                        bi, bj, bv = i, j, v
        if not bv > 0.0:
            _build_K(B, K)
            return lam, False
        if bi != p:
            for j in range(4):
                M[p, j], M[bi, j] = M[bi, j], M[p, j]
        used |= 1 << bj
        if p == 0:
            pc0 = bj
        elif p == 1:
            pc1 = bj
        else:
            pc2 = bj
        piv = 1.0 / M[p, bj]
        for j in range(4):
            M[p, j] *= piv
        for i in range(4):
            if i != p:
                f = M[i, bj]
                if f != 0.0:
                    for j in range(4):
                        M[i, j] -= f * M[p, j]
    free = 0
    while (used >> free) & 1:
        free += 1
    q[free] = 1.0
    q[pc0] = -M[0, free]
    q[pc1] = -M[1, free]
    q[pc2] = -M[2, free]
    _build_K(B, K)
    _normalise_quat(q)
    return lam, True


@njit(cache=True, error_model="numpy")
def _svd_quat(B, q, A):
    """Markley's SVD method (1988): A = U diag(1, 1, det U det V) Vᵀ, B = U S Vᵀ."""
    U, s, Vt = np.linalg.svd(B)
    d = np.linalg.det(U) * np.linalg.det(Vt)
    for i in range(3):
        for j in range(3):
            A[i, j] = U[i, 0] * Vt[0, j] + U[i, 1] * Vt[1, j] + d * U[i, 2] * Vt[2, j]
    _dcm_to_quat(A, q)


@njit(cache=True, error_model="numpy")
def _triad_quat(b, r, i1, i2, q, A):
    """TRIAD (Black 1964; Markley & Crassidis eq. 5.33) anchored on observation i1."""
    tb = np.empty((3, 3))
    tr = np.empty((3, 3))
    for V, T in ((b, tb), (r, tr)):
        x0, x1, x2 = V[i1, 0], V[i1, 1], V[i1, 2]
        y0 = x1 * V[i2, 2] - x2 * V[i2, 1]
        y1 = x2 * V[i2, 0] - x0 * V[i2, 2]
        y2 = x0 * V[i2, 1] - x1 * V[i2, 0]
        ny = np.sqrt(y0 * y0 + y1 * y1 + y2 * y2)
        y0 /= ny
        y1 /= ny
        y2 /= ny
        T[0, 0], T[1, 0], T[2, 0] = x0, x1, x2
        T[0, 1], T[1, 1], T[2, 1] = y0, y1, y2
        T[0, 2] = x1 * y2 - x2 * y1
        T[1, 2] = x2 * y0 - x0 * y2
        T[2, 2] = x0 * y1 - x1 * y0
    for i in range(3):
        for j in range(3):
            A[i, j] = tb[i, 0] * tr[j, 0] + tb[i, 1] * tr[j, 1] + tb[i, 2] * tr[j, 2]
    _dcm_to_quat(A, q)


@njit(cache=True, inline="always", error_model="numpy")
def _two_vector_quat(b, r, a1, a2, sb, sr, A, q):
    """Closed-form optimal attitude for exactly two observations (Markley 1999; Markley &
    Crassidis 2014 eq. 5.70-5.71):
    ``A = b3 r3ᵀ + (a1/λ)[b1 r1ᵀ + (b1×b3)(r1×r3)ᵀ] + (a2/λ)[b2 r2ᵀ + (b2×b3)(r2×r3)ᵀ]``
    with ``b3 = b1×b2/|b1×b2|``, ``r3 = r1×r2/|r1×r2|`` and
    ``λ = sqrt(a1² + a2² + 2 a1 a2 [(b1·b2)(r1·r2) + |b1×b2||r1×r2|])``; weights sum to 1.
    ``sb = |b1×b2|`` and ``sr = |r1×r2|`` (> 0, checked by the caller)."""
    b30 = (b[0, 1] * b[1, 2] - b[0, 2] * b[1, 1]) / sb
    b31 = (b[0, 2] * b[1, 0] - b[0, 0] * b[1, 2]) / sb
    b32 = (b[0, 0] * b[1, 1] - b[0, 1] * b[1, 0]) / sb
    r30 = (r[0, 1] * r[1, 2] - r[0, 2] * r[1, 1]) / sr
    r31 = (r[0, 2] * r[1, 0] - r[0, 0] * r[1, 2]) / sr
    r32 = (r[0, 0] * r[1, 1] - r[0, 1] * r[1, 0]) / sr
    db = b[0, 0] * b[1, 0] + b[0, 1] * b[1, 1] + b[0, 2] * b[1, 2]
    dr = r[0, 0] * r[1, 0] + r[0, 1] * r[1, 1] + r[0, 2] * r[1, 2]
    lam = np.sqrt(max(a1 * a1 + a2 * a2 + 2.0 * a1 * a2 * (db * dr + sb * sr), 0.0))
    A[0, 0] = b30 * r30
    A[0, 1] = b30 * r31
    A[0, 2] = b30 * r32
    A[1, 0] = b31 * r30
    A[1, 1] = b31 * r31
    A[1, 2] = b31 * r32
    A[2, 0] = b32 * r30
    A[2, 1] = b32 * r31
    A[2, 2] = b32 * r32
    for i in range(2):
        c = (a1 if i == 0 else a2) / lam
        # u = b_i × b3, v = r_i × r3
        u0 = b[i, 1] * b32 - b[i, 2] * b31
        u1 = b[i, 2] * b30 - b[i, 0] * b32
        u2 = b[i, 0] * b31 - b[i, 1] * b30
        v0 = r[i, 1] * r32 - r[i, 2] * r31
        v1 = r[i, 2] * r30 - r[i, 0] * r32
        v2 = r[i, 0] * r31 - r[i, 1] * r30
        A[0, 0] += c * (b[i, 0] * r[i, 0] + u0 * v0)
        A[0, 1] += c * (b[i, 0] * r[i, 1] + u0 * v1)
        A[0, 2] += c * (b[i, 0] * r[i, 2] + u0 * v2)
        A[1, 0] += c * (b[i, 1] * r[i, 0] + u1 * v0)
        A[1, 1] += c * (b[i, 1] * r[i, 1] + u1 * v1)
        A[1, 2] += c * (b[i, 1] * r[i, 2] + u1 * v2)
        A[2, 0] += c * (b[i, 2] * r[i, 0] + u2 * v0)
        A[2, 1] += c * (b[i, 2] * r[i, 1] + u2 * v1)
        A[2, 2] += c * (b[i, 2] * r[i, 2] + u2 * v2)
    _dcm_to_quat(A, q)
    _normalise_quat(q)


@njit(cache=True, inline="always", error_model="numpy")
def _solve_one(body_all, ref_all, w_all, kk, kw, method, q_all, out_all, cov_all, b, r, q, B, F, K, A, Bk, qp):
    """Solve problem ``kk`` (weights row ``kw``); returns the status code.

    ``out_all[kk] = [loss, cond, fallback]``. The batch arrays are indexed in place rather
    than sliced into six per-problem array views (each a reference-counted object in numba).
    ``b``, ``r`` (n×3) and ``q`` (4,) are scratch buffers owned by the caller."""
    n = body_all.shape[1]
    for i in range(4):
        q_all[kk, i] = np.nan
    out_all[kk, 0] = np.nan
    out_all[kk, 1] = np.nan
    out_all[kk, 2] = 0.0
    want_cov = cov_all.shape[1] == 3  # a (0, 0) array means: covariance not requested
    if want_cov:
        for i in range(3):
            for j in range(3):
                cov_all[kk, i, j] = np.nan
    if n < 2:
        return TOO_FEW
    wsum = 0.0
    for i in range(n):
        nb = 0.0
        nr = 0.0
        for j in range(3):
            nb += body_all[kk, i, j] * body_all[kk, i, j]
            nr += ref_all[kk, i, j] * ref_all[kk, i, j]
        if (np.isfinite(nb) and np.isfinite(nr) and nb >= 1e-300 and nr >= 1e-300
                and np.isfinite(w_all[kw, i])):
            nb = 1.0 / np.sqrt(nb)
            nr = 1.0 / np.sqrt(nr)
            for j in range(3):
                b[i, j] = body_all[kk, i, j] * nb
                r[i, j] = ref_all[kk, i, j] * nr
        else:  # rare path: non-finite, zero, or a squared norm that over/underflows
            if not np.isfinite(w_all[kw, i]):
                return NONFINITE
            code = _unit_scaled(body_all[kk, i], b[i])
            if code == OK:
                code = _unit_scaled(ref_all[kk, i], r[i])
            if code != OK:
                return code
        wsum += w_all[kw, i]
    # anchor = heaviest observation (first on ties), second = heaviest non-parallel one
    i1 = 0
    for i in range(1, n):
        if w_all[kw, i] > w_all[kw, i1]:
            i1 = i
    i2 = -1
    maxsb = 0.0
    maxsr = 0.0
    for i in range(n):
        if i == i1:
            continue
        cb0 = b[i1, 1] * b[i, 2] - b[i1, 2] * b[i, 1]
        cb1 = b[i1, 2] * b[i, 0] - b[i1, 0] * b[i, 2]
        cb2 = b[i1, 0] * b[i, 1] - b[i1, 1] * b[i, 0]
        cr0 = r[i1, 1] * r[i, 2] - r[i1, 2] * r[i, 1]
        cr1 = r[i1, 2] * r[i, 0] - r[i1, 0] * r[i, 2]
        cr2 = r[i1, 0] * r[i, 1] - r[i1, 1] * r[i, 0]
        sb = np.sqrt(cb0 * cb0 + cb1 * cb1 + cb2 * cb2)
        sr = np.sqrt(cr0 * cr0 + cr1 * cr1 + cr2 * cr2)
        maxsb = max(maxsb, sb)
        maxsr = max(maxsr, sr)
        if sb > COLLINEAR_SIN and sr > COLLINEAR_SIN and (i2 < 0 or w_all[kw, i] > w_all[kw, i2]):
            i2 = i
    if maxsb <= COLLINEAR_SIN:
        return COLLINEAR_BODY
    if maxsr <= COLLINEAR_SIN:
        return COLLINEAR_REF
    if i2 < 0:  # each set has a non-parallel pair but not with the same partner
        i2 = 0 if i1 != 0 else 1
    for j in range(3):
        for k in range(3):
            B[j, k] = 0.0
            F[j, k] = 0.0
    iw = 1.0 / wsum
    for i in range(n):
        a = w_all[kw, i] * iw
        wi = w_all[kw, i]
        for j in range(3):
            abj = a * b[i, j]
            wbj = wi * b[i, j]
            for k in range(3):
                B[j, k] += abj * r[i, k]
                F[j, k] -= wbj * b[i, k]
        F[0, 0] += w_all[kw, i]
        F[1, 1] += w_all[kw, i]
        F[2, 2] += w_all[kw, i]
    status = OK
    if method != TWO_VECTOR:
        _build_K(B, K)
    if method == TWO_VECTOR:  # exactly two observations (checked by the public API)
        _two_vector_quat(b, r, w_all[kw, 0] / wsum, w_all[kw, 1] / wsum, maxsb, maxsr, A, q)
    elif method == QMETHOD:
        _eig_quat(K, q)
    elif method == TRIAD:
        _triad_quat(b, r, i1, i2, q, A)
    elif method == SVD:
        _svd_quat(B, q, A)
    else:
        ok = True
        lam = 1.0
        if method == FOAM:
            ok = _foam_quat(B, q, A)
        elif method == FLAE:
            lam, ok = _flae_quat(B, K, q)
        else:
            lam2 = -1.0
            if n == 2:  # closed form λmax for two observations (Markley 1999 / M&C eq. 5.71)
                a1 = w_all[kw, 0] / wsum
                a2 = w_all[kw, 1] / wsum
                db = b[0, 0] * b[1, 0] + b[0, 1] * b[1, 1] + b[0, 2] * b[1, 2]
                dr = r[0, 0] * r[1, 0] + r[0, 1] * r[1, 1] + r[0, 2] * r[1, 2]
                cc = maxsb * maxsr  # |b1 x b2| |r1 x r2| from the collinearity check
                lam2 = np.sqrt(max(a1 * a1 + a2 * a2 + 2.0 * a1 * a2 * (db * dr + cc), 0.0))
            lam, ok = _lambda_max(B, n, lam2)
            if ok:
                if method == QUEST:
                    ok = _quest_quat(B, lam, q, Bk, qp)
                else:
                    ok = _esoq2_quat(B, lam, q, Bk, qp)
        if ok and method != FOAM:
            # refinement: one shifted power step q <- (K + λ I) q damps the error components
            # along the far eigenvectors (λ_j ≈ −λ for near-consistent data) that the
            # adjugate/cross-product construction leaves at ~eps/gap
            for i in range(4):
                t = lam * q[i]
                for j in range(4):
                    t += K[i, j] * q[j]
                qp[i] = t
            for i in range(4):
                q[i] = qp[i]
            _normalise_quat(q)
        # residual check: above RESIDUAL_TOL the problem is re-solved by the eigen-solver
        if not ok or not np.isfinite(q[0]) or _residual(K, q, _rayleigh(K, q) if method == FOAM else lam) > RESIDUAL_TOL:
            _eig_quat(K, q)
            out_all[kk, 2] = 1.0
    # loss from the residuals (the eigenvalue form Σa(1 − qᵀKq) loses all digits of small losses)
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    A[0, 0] = q3 * q3 + q0 * q0 - q1 * q1 - q2 * q2
    A[1, 1] = q3 * q3 - q0 * q0 + q1 * q1 - q2 * q2
    A[2, 2] = q3 * q3 - q0 * q0 - q1 * q1 + q2 * q2
    A[0, 1] = 2.0 * (q0 * q1 + q3 * q2)
    A[1, 0] = 2.0 * (q0 * q1 - q3 * q2)
    A[0, 2] = 2.0 * (q0 * q2 - q3 * q1)
    A[2, 0] = 2.0 * (q0 * q2 + q3 * q1)
    A[1, 2] = 2.0 * (q1 * q2 + q3 * q0)
    A[2, 1] = 2.0 * (q1 * q2 - q3 * q0)
    loss = 0.0
    for i in range(n):
        for j in range(3):
            d = b[i, j] - (A[j, 0] * r[i, 0] + A[j, 1] * r[i, 1] + A[j, 2] * r[i, 2])
            loss += w_all[kw, i] * d * d
    out_all[kk, 0] = 0.5 * loss
    # covariance (Markley & Crassidis 2014 eq. 5.66 with weights = 1/σ²): P = F⁻¹
    c00 = F[1, 1] * F[2, 2] - F[1, 2] * F[2, 1]
    c01 = F[0, 2] * F[2, 1] - F[0, 1] * F[2, 2]
    c02 = F[0, 1] * F[1, 2] - F[0, 2] * F[1, 1]
    c11 = F[0, 0] * F[2, 2] - F[0, 2] * F[2, 0]
    c12 = F[0, 2] * F[1, 0] - F[0, 0] * F[1, 2]
    c22 = F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]
    detF = F[0, 0] * c00 + F[0, 1] * (F[1, 2] * F[2, 0] - F[1, 0] * F[2, 2]) + F[0, 2] * (F[1, 0] * F[2, 1] - F[1, 1] * F[2, 0])
    if detF > 0.0:
        idet = 1.0 / detF
        p00 = c00 * idet
        p01 = c01 * idet
        p02 = c02 * idet
        p11 = c11 * idet
        p12 = c12 * idet
        p22 = c22 * idet
        if want_cov:
            cov_all[kk, 0, 0] = p00
            cov_all[kk, 0, 1] = cov_all[kk, 1, 0] = p01
            cov_all[kk, 0, 2] = cov_all[kk, 2, 0] = p02
            cov_all[kk, 1, 1] = p11
            cov_all[kk, 1, 2] = cov_all[kk, 2, 1] = p12
            cov_all[kk, 2, 2] = p22
        nf = 0.0
        for i in range(3):
            for j in range(3):
                nf += F[i, j] * F[i, j]
        nc = p00 * p00 + p11 * p11 + p22 * p22 + 2.0 * (p01 * p01 + p02 * p02 + p12 * p12)
        out_all[kk, 1] = np.sqrt(nf * nc)
    else:
        out_all[kk, 1] = np.inf
    for i in range(4):
        q_all[kk, i] = q[i]
    return status


# ``_nrt=True`` explicitly: its callers in the closed-loop kernel (compiled without reference
# counting) pass it on unless a callee sets its own, and the solvers allocate
@njit(cache=True, nogil=True, error_model="numpy", _nrt=True)
def solve_one(body_all, ref_all, w_all, kk, kw, method, q_all, out_all, cov_all, b, r, q, B, F, K, A, Bk, qp):
    """:func:`_solve_one` compiled once as its own function (not inlined into the caller).

    For callers that solve one problem at a time at a low rate (the min-max step
    :func:`adcskit.determination._box.minmax_one`, the closed-loop simulator's Wahba step):
    numba inlines ``_solve_one`` (every method, with its inlined helpers) at the IR level, and
    each inlined copy compiles for seconds (six copies in the closed-loop kernel; docs/
    benchmarks.md "Compile time of the kernels"); calling this dispatcher instead compiles
    that once and links it (same operations in the same order, so the same numbers).
    """
    return _solve_one(body_all, ref_all, w_all, kk, kw, method, q_all, out_all, cov_all, b, r, q, B, F, K,
                      A, Bk, qp)


def _scratch(n):
    return (np.empty((2 * n, 3)), np.empty((3, 3)), np.empty((3, 3)), np.empty((4, 4)),
            np.empty((3, 3)), np.empty((3, 3)), np.empty(4))


_scratch = njit(cache=True, error_model="numpy")(_scratch)


@njit(cache=True, error_model="numpy")
def solve_batch_serial(body, ref, w, method, q, out, cov, status):
    """Serial loop over problems (single calls and small batches)."""
    N, n = body.shape[0], body.shape[1]
    shared_w = w.shape[0] == 1  # one weight row for every problem
    work, B, F, K, A, Bk, qp = _scratch(n)
    b = work[0:n]
    r = work[n: 2 * n]
    qs = np.empty(4)
    for k in range(N):
        status[k] = _solve_one(body, ref, w, k, 0 if shared_w else k, method, q, out, cov, b, r, qs,
                               B, F, K, A, Bk, qp)


CHUNK = 512


@njit(cache=True, parallel=True, error_model="numpy")
def solve_batch_parallel(body, ref, w, method, q, out, cov, status):
    """Parallel loop over chunks of problems (numba prange); each chunk runs the serial
    kernel (compiled once, so the parallel wrapper compiles quickly)."""
    N = body.shape[0]
    nchunks = (N + CHUNK - 1) // CHUNK
    for c in prange(nchunks):
        lo = c * CHUNK
        hi = min(N, lo + CHUNK)
        wc = w if w.shape[0] == 1 else w[lo:hi]
        solve_batch_serial(body[lo:hi], ref[lo:hi], wc, method, q[lo:hi], out[lo:hi],
                           cov[lo:hi], status[lo:hi])


@njit(cache=True, error_model="numpy")
def solve_single(body, ref, w, method, buf):
    """One problem into ``buf`` (16,) = [q (4), loss, cond, fallback, cov (9)]; returns status.

    Calls the serial batch kernel on a batch of one (one heavy compilation, not two).
    """
    n = body.shape[0]
    status = np.empty(1, dtype=np.int8)
    solve_batch_serial(body.reshape((1, n, 3)), ref.reshape((1, n, 3)), w.reshape((1, n)), method,
                       buf[0:4].reshape((1, 4)), buf[4:7].reshape((1, 3)),
                       buf[7:16].reshape((1, 3, 3)), status)
    return status[0]
