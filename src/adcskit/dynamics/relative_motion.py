"""Hill / Clohessy–Wiltshire relative translational motion (S2 eq. 6).

Target on a circular orbit with mean motion ``n``; chaser position ``s = [x, y, z]`` in the
target's LVLH frame of S2: ``x`` along the velocity, ``z`` toward the Earth's centre,
``y = z × x`` (negative orbit normal). With force per unit mass ``a = F/m``::

    ẍ =  2 n ż            + a_x
    ÿ =        − n² y      + a_y
    z̈ = −2 n ẋ + 3 n² z   + a_z

which is S2's ``v̇ + M v + N s = F/m`` with ``M = [[0, 0, −2n], [0, 0, 0], [2n, 0, 0]]`` and
``N = diag(0, n², −3n²)``.

References
----------
W. H. Clohessy and R. S. Wiltshire, J. Aerospace Sci. 27(9), 1960.
S2, eq. 6. Vallado (2013), §6.8 (in the RSW frame; here rotated to S2's LVLH axes).
"""

from __future__ import annotations

import numpy as np

from adcskit._validation import check_finite, check_positive

__all__ = ["cw_matrices", "cw_stm"]


def cw_matrices(n: float) -> tuple[np.ndarray, np.ndarray]:
    """Continuous ``(A, B)`` (6×6, 6×3) for state ``[x, y, z, ẋ, ẏ, ż]`` (m, m/s), input
    acceleration (m/s²), in S2's LVLH axes.

    Parameters
    ----------
    n : float, rad/s
        Target's orbital mean motion.

    Examples
    --------
    >>> A, B = cw_matrices(1.1e-3)
    >>> A.shape, B.shape
    ((6, 6), (6, 3))
    """
    n = check_positive("n", n, allow_zero=True, unit="rad/s")
    A = np.zeros((6, 6))
    A[:3, 3:] = np.eye(3)
    A[3, 5] = 2 * n
    A[4, 1] = -(n**2)
    A[5, 3] = -2 * n
    A[5, 2] = 3 * n**2
    B = np.zeros((6, 3))
    B[3:, :] = np.eye(3)
    return A, B


def cw_stm(n: float, t: float) -> np.ndarray:
    """Closed-form state-transition matrix ``Φ(t)`` of :func:`cw_matrices` (6×6).

    Obtained from the classical CW solution (Vallado 2013, eq. 6-66) with the axes mapped
    ``x_RSW = −z``, ``y_RSW = x``, ``z_RSW = −y``; used as an oracle in tests.

    Examples
    --------
    >>> import numpy as np
    >>> np.allclose(cw_stm(1.1e-3, 0.0), np.eye(6))
    True
    """
    n = check_positive("n", n, unit="rad/s", min_value=1e-150)
    t = check_finite("t", t)
    c, s = np.cos(n * t), np.sin(n * t)
    # Vallado's RSW state [xr, yr, zr, vxr, vyr, vzr] (xr radial out, yr along-track, zr normal)
    P = np.array(
        [
            [4 - 3 * c, 0, 0, s / n, 2 * (1 - c) / n, 0],
            [6 * (s - n * t), 1, 0, -2 * (1 - c) / n, (4 * s - 3 * n * t) / n, 0],
            [0, 0, c, 0, 0, s / n],
            [3 * n * s, 0, 0, c, 2 * s, 0],
            [-6 * n * (1 - c), 0, 0, -2 * s, 4 * c - 3, 0],
            [0, 0, -n * s, 0, 0, c],
        ]
    )
    # RSW <- LVLH(S2): xr = -z, yr = x, zr = -y  (orthogonal, det +1)
    R = np.array([[0.0, 0, -1], [1, 0, 0], [0, -1, 0]])
    T = np.zeros((6, 6))
    T[:3, :3] = R
    T[3:, 3:] = R
    return T.T @ P @ T
