"""Private NumPy kernels of the attitude algebra.

They work on plain ``float64`` arrays of shape ``(N, 4)``, ``(N, 3, 3)`` or ``(N, 3)``, do
not validate, and never modify their inputs. The public, validating API is in
:mod:`adcskit.attitude.quaternion`, :mod:`~adcskit.attitude.mrp`,
:mod:`~adcskit.attitude.euler` and :mod:`~adcskit.attitude.kinematics`.

Convention: scalar-last quaternion ``q = [e, q4]`` with the attitude matrix
``A(q) = (q4² − |e|²) I + 2 e eᵀ − 2 q4 [e×]`` mapping reference to body components
(Markley & Crassidis 2014, eq. 2.125).
"""

from __future__ import annotations

import numpy as np


def skew(v: np.ndarray) -> np.ndarray:
    """Cross-product matrices ``[v×]`` of ``(N, 3)`` vectors, shape ``(N, 3, 3)``."""
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1] = -v[..., 2]
    out[..., 0, 2] = v[..., 1]
    out[..., 1, 0] = v[..., 2]
    out[..., 1, 2] = -v[..., 0]
    out[..., 2, 0] = -v[..., 1]
    out[..., 2, 1] = v[..., 0]
    return out


def canonical(q: np.ndarray) -> np.ndarray:
    """Unit quaternions with ``q4 >= 0`` (for ``q4 == 0`` the first non-zero component > 0)."""
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    sign = np.where(q[..., 3] < 0, -1.0, 1.0)
    zero = q[..., 3] == 0
    if np.any(zero):
        # Tie break on the 180-degree set: first non-zero vector component positive.
        v = q[zero, :3]
        first = v[np.arange(v.shape[0]), np.argmax(v != 0, axis=1)]
        sign[zero] = np.where(first < 0, -1.0, 1.0)
    return q * sign[..., None]


def quat_to_dcm(q: np.ndarray) -> np.ndarray:
    """``A(q)`` for unit ``(N, 4)`` quaternions."""
    x, y, z, w = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    xx, yy, zz, ww = x * x, y * y, z * z, w * w
    xy, xz, yz = x * y, x * z, y * z
    xw, yw, zw = x * w, y * w, z * w
    A = np.empty((q.shape[0], 3, 3))
    A[:, 0, 0] = xx - yy - zz + ww
    A[:, 0, 1] = 2 * (xy + zw)
    A[:, 0, 2] = 2 * (xz - yw)
    A[:, 1, 0] = 2 * (xy - zw)
    A[:, 1, 1] = -xx + yy - zz + ww
    A[:, 1, 2] = 2 * (yz + xw)
    A[:, 2, 0] = 2 * (xz + yw)
    A[:, 2, 1] = 2 * (yz - xw)
    A[:, 2, 2] = -xx - yy + zz + ww
    return A


def dcm_to_quat(A: np.ndarray) -> np.ndarray:
    """Inverse of :func:`quat_to_dcm` by Shepperd's method (largest-pivot branch).

    Shepperd, S. W. (1978), "Quaternion from rotation matrix", J. Guidance Control 1(3);
    Markley & Crassidis (2014), eq. 2.135-2.137.
    """
    n = A.shape[0]
    tr = A[:, 0, 0] + A[:, 1, 1] + A[:, 2, 2]
    piv = np.stack([A[:, 0, 0], A[:, 1, 1], A[:, 2, 2], tr], axis=1)
    k = np.argmax(piv, axis=1)
    q = np.empty((n, 4))
    # Branch q4 largest.
    m = k == 3
    if np.any(m):
        a = A[m]
        q[m] = np.stack(
            [a[:, 1, 2] - a[:, 2, 1], a[:, 2, 0] - a[:, 0, 2], a[:, 0, 1] - a[:, 1, 0], 1 + tr[m]],
            axis=1,
        )
    m = k == 0
    if np.any(m):
        a = A[m]
        q[m] = np.stack(
            [1 + 2 * a[:, 0, 0] - tr[m], a[:, 0, 1] + a[:, 1, 0], a[:, 0, 2] + a[:, 2, 0], a[:, 1, 2] - a[:, 2, 1]],
            axis=1,
        )
    m = k == 1
    if np.any(m):
        a = A[m]
        q[m] = np.stack(
            [a[:, 1, 0] + a[:, 0, 1], 1 + 2 * a[:, 1, 1] - tr[m], a[:, 1, 2] + a[:, 2, 1], a[:, 2, 0] - a[:, 0, 2]],
            axis=1,
        )
    m = k == 2
    if np.any(m):
        a = A[m]
        q[m] = np.stack(
            [a[:, 2, 0] + a[:, 0, 2], a[:, 2, 1] + a[:, 1, 2], 1 + 2 * a[:, 2, 2] - tr[m], a[:, 0, 1] - a[:, 1, 0]],
            axis=1,
        )
    return canonical(q)


def quat_multiply(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """``p ⊗ q`` with ``A(p ⊗ q) = A(p) A(q)`` (Markley & Crassidis 2014, eq. 2.82a)."""
    pv, p4 = p[..., :3], p[..., 3:]
    qv, q4 = q[..., :3], q[..., 3:]
    vec = p4 * qv + q4 * pv - np.cross(pv, qv)
    sca = p4 * q4 - np.sum(pv * qv, axis=-1, keepdims=True)
    return np.concatenate([vec, sca], axis=-1)


def quat_conjugate(q: np.ndarray) -> np.ndarray:
    out = q.copy()
    out[..., :3] *= -1.0
    return out


def error_angle(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Rotation angle of ``p ⊗ q⁻¹`` in [0, π], robust near 0 and π (atan2 form)."""
    d = quat_multiply(p, quat_conjugate(q))
    return 2.0 * np.arctan2(np.linalg.norm(d[..., :3], axis=-1), np.abs(d[..., 3]))


def quat_to_mrp(q: np.ndarray) -> np.ndarray:
    """``σ = e / (1 + q4)`` of canonical quaternions (``q4 >= 0`` ⇒ ``|σ| <= 1``)."""
    return q[:, :3] / (1.0 + q[:, 3:4])


def mrp_to_quat(s: np.ndarray) -> np.ndarray:
    s2 = np.sum(s * s, axis=1, keepdims=True)
    q = np.concatenate([2 * s, 1 - s2], axis=1) / (1 + s2)
    return canonical(q)


def mrp_shadow(s: np.ndarray) -> np.ndarray:
    """Shadow set ``σˢ = −σ / |σ|²`` (Schaub & Junkins 2018, eq. 3.153)."""
    return -s / np.sum(s * s, axis=1, keepdims=True)


def mrp_to_dcm(s: np.ndarray) -> np.ndarray:
    """``C(σ) = I + (8[σ×]² − 4(1 − σ²)[σ×]) / (1 + σ²)²`` (Schaub & Junkins 2018, eq. 3.154)."""
    S = skew(s)
    s2 = np.sum(s * s, axis=1)[:, None, None]
    return np.eye(3) + (8 * S @ S - 4 * (1 - s2) * S) / (1 + s2) ** 2


def elementary(axis: int, angle: np.ndarray) -> np.ndarray:
    """Frame (passive) rotation matrices about body axis ``axis`` (0, 1, 2) by ``angle``."""
    c, s = np.cos(angle), np.sin(angle)
    R = np.zeros(angle.shape + (3, 3))
    i, j = (axis + 1) % 3, (axis + 2) % 3
    R[..., axis, axis] = 1.0
    R[..., i, i] = c
    R[..., j, j] = c
    R[..., i, j] = s
    R[..., j, i] = -s
    return R
