"""Device helpers of the attitude algebra: scalar quaternion operations for compiled kernels.

One source for the quaternion pieces that the per-sample kernels share (the closed-loop
simulator :mod:`adcskit.simulation._kernels` and the MEKF :mod:`adcskit.estimation._mekf_kernels`).
Each is declared with :func:`adcskit._targets.device`: a plain Python function that numba
compiles into whichever kernel calls it, on the CPU (``njit``) or the GPU (``cuda.jit``). Rules
as for a per-sample function (:mod:`adcskit._targets`): scalars, ``math`` and indexing only.

Conventions: quaternion scalar last, ``A(q)`` maps reference components to body components;
Markley's product, ``A(p (x) q) = A(p) A(q)``; angles in rad.

References
----------
Markley F. L., Crassidis J. L., *Fundamentals of Spacecraft Attitude Determination and
Control*, Springer 2014: eq. 2.125 (``A(q)``), 2.82a (product), 2.124 (rotation vector).
"""

from __future__ import annotations

import math

from adcskit._targets import device

__all__ = ["rotate", "qdiff", "qerr", "qdot", "unit_q4_pos", "compose_rotvec"]


@device
def rotate(q0, q1, q2, q3, r0, r1, r2):
    """``A(q) r`` (reference -> body) as three scalars.

    Examples
    --------
    >>> rotate(0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 3.0)
    (1.0, 2.0, 3.0)
    """
    c = q3 * q3 - (q0 * q0 + q1 * q1 + q2 * q2)
    er = q0 * r0 + q1 * r1 + q2 * r2
    b0 = c * r0 + 2.0 * q0 * er - 2.0 * q3 * (q1 * r2 - q2 * r1)
    b1 = c * r1 + 2.0 * q1 * er - 2.0 * q3 * (q2 * r0 - q0 * r2)
    b2 = c * r2 + 2.0 * q2 * er - 2.0 * q3 * (q0 * r1 - q1 * r0)
    return b0, b1, b2


@device
def qdiff(a0, a1, a2, a3, b0, b1, b2, b3):
    """``qa (x) qb^-1`` (Markley's product with the conjugate), sign fixed to ``q4 >= 0``.

    Examples
    --------
    >>> qdiff(0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0)
    (0.0, 0.0, -1.0, 0.0)
    """
    c0, c1, c2, c3 = -b0, -b1, -b2, b3
    d0 = a3 * c0 + c3 * a0 - (a1 * c2 - a2 * c1)
    d1 = a3 * c1 + c3 * a1 - (a2 * c0 - a0 * c2)
    d2 = a3 * c2 + c3 * a2 - (a0 * c1 - a1 * c0)
    d3 = a3 * c3 - (a0 * c0 + a1 * c1 + a2 * c2)
    if d3 < 0.0:
        return -d0, -d1, -d2, -d3
    return d0, d1, d2, d3


@device
def qerr(a0, a1, a2, a3, b0, b1, b2, b3):
    """Rotation vector (rad, body frame) of ``qa (x) qb^-1`` and its angle (rad).

    Examples
    --------
    >>> qerr(0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    (0.0, 0.0, 0.0, 0.0)
    """
    d0, d1, d2, d3 = qdiff(a0, a1, a2, a3, b0, b1, b2, b3)
    ev = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    ang = 2.0 * math.atan2(ev, d3)
    if ev > 0.0:
        f = ang / ev
    else:
        f = 2.0
    return f * d0, f * d1, f * d2, ang


@device
def qdot(q0, q1, q2, q3, w0, w1, w2):
    """Kinematics ``q' = 1/2 [w; 0] (x) q`` (``w``: body rate, rad/s) as four scalars (1/s).

    Markley & Crassidis (2014) eq. 3.20 with the product of eq. 2.82a.

    Examples
    --------
    >>> qdot(0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.2)
    (0.0, 0.0, 0.1, -0.0)
    """
    return (0.5 * (q3 * w0 - (w1 * q2 - w2 * q1)),
            0.5 * (q3 * w1 - (w2 * q0 - w0 * q2)),
            0.5 * (q3 * w2 - (w0 * q1 - w1 * q0)),
            -0.5 * (w0 * q0 + w1 * q1 + w2 * q2))


@device
def compose_rotvec(q, r0, r1, r2):
    """``q <- dq(r) (x) q`` in place (Markley's product), renormalised, ``q4 >= 0``.

    Examples
    --------
    >>> import numpy as np
    >>> q = np.array([0.0, 0.0, 0.0, 1.0])
    >>> compose_rotvec(q, 0.0, 0.0, np.pi / 2)
    >>> np.round(q, 6).tolist()
    [0.0, 0.0, 0.707107, 0.707107]
    """
    ang = math.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
    h = 0.5 * ang
    if h < 1e-4:
        s = 0.5 * (1.0 - h * h / 6.0)  # sin(h)/h / 2 to O(h⁴) ~ 1e-17
    else:
        s = 0.5 * math.sin(h) / h
    p0 = s * r0
    p1 = s * r1
    p2 = s * r2
    p3 = math.cos(h)
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    # p ⊗ q = [p4 q_v + q4 p_v − p_v × q_v ; p4 q4 − p_v · q_v]
    n0 = p3 * q0 + q3 * p0 - (p1 * q2 - p2 * q1)
    n1 = p3 * q1 + q3 * p1 - (p2 * q0 - p0 * q2)
    n2 = p3 * q2 + q3 * p2 - (p0 * q1 - p1 * q0)
    n3 = p3 * q3 - (p0 * q0 + p1 * q1 + p2 * q2)
    q[0], q[1], q[2], q[3] = unit_q4_pos(n0, n1, n2, n3)


@device
def unit_q4_pos(n0, n1, n2, n3):
    """``n / |n|`` with the sign that makes ``q4 >= 0`` (one division per component).

    Examples
    --------
    >>> unit_q4_pos(0.0, 0.0, 3.0, -4.0)
    (-0.0, -0.0, -0.6, 0.8)
    """
    nrm = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2 + n3 * n3)
    if n3 < 0.0:
        nrm = -nrm
    return n0 / nrm, n1 / nrm, n2 / nrm, n3 / nrm
