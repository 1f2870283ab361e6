"""Attitude kinematics: quaternion and MRP rates from the body angular velocity.

``ω`` is the angular velocity of the body frame relative to the reference frame, in body
components (rad/s). With ``A(q)`` reference → body (docs/architecture.md, "Conventions"), ``Ȧ = −[ω×] A``.

References
----------
Markley & Crassidis (2014), eq. 3.20-3.21 (``q̇ = ½ Ξ(q) ω``).
Schaub & Junkins (2018), eq. 3.165 (``σ̇ = ¼ B(σ) ω``); S2 eq. 4-5.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from adcskit.attitude import _kernels as _k
from adcskit.attitude._checks import broadcast, mrps, out, quats, vectors

__all__ = ["mrp_b_matrix", "mrp_kinematics", "quat_kinematics", "xi_matrix"]


def xi_matrix(q: Any) -> np.ndarray:
    """``Ξ(q) = [[q4 I₃ + [e×]], [−eᵀ]]``, shape (4, 3) or (N, 4, 3).

    Examples
    --------
    >>> xi_matrix([0.0, 0.0, 0.0, 1.0])
    array([[ 1.,  0.,  0.],
           [ 0.,  1.,  0.],
           [ 0.,  0.,  1.],
           [-0., -0., -0.]])
    """
    arr, batched = quats("q", q)
    xi = np.empty((arr.shape[0], 4, 3))
    xi[:, :3, :] = arr[:, 3, None, None] * np.eye(3) + _k.skew(arr[:, :3])
    xi[:, 3, :] = -arr[:, :3]
    return out(xi, batched)


def quat_kinematics(q: Any, omega: Any) -> np.ndarray:
    """Quaternion rate ``q̇ = ½ Ξ(q) ω`` (1/s).

    Parameters
    ----------
    q : array_like, shape (4,) or (N, 4)
        Attitude (normalised before use).
    omega : array_like, shape (3,) or (N, 3), rad/s
        Body rate relative to the reference frame, body components.

    Examples
    --------
    >>> quat_kinematics([0.0, 0.0, 0.0, 1.0], [0.0, 0.0, 0.2])   # q_dot = omega / 2 at identity
    array([ 0. ,  0. ,  0.1, -0. ])
    """
    qa, qb = quats("q", q)
    wa, wb = vectors("omega", omega)
    qa, wa = broadcast("q", qa, "omega", wa)
    v, s = qa[:, :3], qa[:, 3:]
    dv = 0.5 * (s * wa + np.cross(v, wa))
    ds = -0.5 * np.sum(v * wa, axis=1, keepdims=True)
    return out(np.concatenate([dv, ds], axis=1), qb or wb)


def mrp_b_matrix(sigma: Any) -> np.ndarray:
    """``B(σ) = (1 − σᵀσ) I₃ + 2[σ×] + 2σσᵀ`` (S2 eq. 5), shape (3, 3) or (N, 3, 3).

    Examples
    --------
    >>> mrp_b_matrix([0.0, 0.0, 0.0])
    array([[1., 0., 0.],
           [0., 1., 0.],
           [0., 0., 1.]])
    """
    s, batched = mrps("sigma", sigma)
    s2 = np.sum(s * s, axis=1)[:, None, None]
    B = (1 - s2) * np.eye(3) + 2 * _k.skew(s) + 2 * s[:, :, None] * s[:, None, :]
    return out(B, batched)


def mrp_kinematics(sigma: Any, omega: Any) -> np.ndarray:
    """MRP rate ``σ̇ = ¼ B(σ) ω`` (1/s); S2 eq. 4.

    Examples
    --------
    >>> mrp_kinematics([0.0, 0.0, 0.0], [0.0, 0.0, 0.4])   # sigma_dot = omega / 4 at identity
    array([0. , 0. , 0.1])
    """
    s, sb = mrps("sigma", sigma)
    w, wb = vectors("omega", omega)
    s, w = broadcast("sigma", s, "omega", w)
    s2 = np.sum(s * s, axis=1, keepdims=True)
    sd = 0.25 * ((1 - s2) * w + 2 * np.cross(s, w) + 2 * s * np.sum(s * w, axis=1, keepdims=True))
    return out(sd, sb or wb)
