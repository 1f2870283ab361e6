"""Linearised attitude dynamics about the LVLH frame with gravity gradient (S1 eq. 8–11).

Frame (Wie 2008, §6.4; S1, S2): LVLH ``x`` along the velocity (roll axis), ``z`` toward the
Earth's centre (yaw), ``y = z × x`` along the negative orbit normal (pitch). Small roll ``φ``,
pitch ``θ``, yaw ``ψ`` of the body relative to LVLH, circular orbit with rate ``n``, principal
inertia ``J = diag(Ix, Iy, Iz)``. Linearising Euler's equations with the gravity-gradient
torque gives ``M q̈ + N q̇ + L q = G_u u`` with ``q = [φ, θ, ψ]``::

    Ix φ̈ − n (Ix − Iy + Iz) ψ̇ + 4 n² (Iy − Iz) φ = u_x
    Iy θ̈                      + 3 n² (Ix − Iz) θ = u_y
    Iz ψ̈ + n (Ix − Iy + Iz) φ̇ +    n² (Iy − Ix) ψ = u_z

so ``M = diag(Ix, Iy, Iz)``, ``L = n² diag(4(Iy − Iz), 3(Ix − Iz), Iy − Ix)`` and the gyroscopic
matrix is **skew-symmetric**: ``N = n (Ix − Iy + Iz) [[0, 0, −1], [0, 0, 0], [1, 0, 0]]``.

S1 prints ``N = n (−Ix + Iy − Iz) [[0, 0, 1], [0, 0, 0], [1, 0, 0]]`` (eq. 9): its (1, 3) entry
agrees with the derivation, but its (3, 1) entry has the wrong sign, which makes ``N``
symmetric — a symmetric velocity term is damping (or anti-damping), not gyroscopic coupling,
and it changes the open-loop eigenvalues. ``printed=True`` reproduces the printed matrix for
comparison; the default is the derived one. ``tests/dynamics/test_lvlh.py`` checks the
derived model against a nonlinear rigid-body simulation in a circular orbit.

State-space form ``ẋ = A x + B u`` with ``x = [φ, θ, ψ, φ̇, θ̇, ψ̇]``:
``A = [[0, I], [−M⁻¹L, −M⁻¹N]]``, ``B = [[0], [M⁻¹]]`` (S1 eq. 10–11).

References
----------
B. Wie, *Space Vehicle Dynamics and Control*, 2nd ed., AIAA 2008, §6.4 (linearised
gravity-gradient attitude equations).
M. J. Sidi, *Spacecraft Dynamics and Control*, Cambridge 1997, §4.8.
S1, eq. 8–11.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from adcskit._validation import check_flag, check_positive
from adcskit.dynamics.rigid_body import as_inertia
from adcskit.errors import InputError

__all__ = ["lvlh_attitude_model", "lvlh_second_order"]


def _principal(inertia: Any) -> np.ndarray:
    J = as_inertia(inertia)
    off = J - np.diag(np.diag(J))
    if np.abs(off).max() > 1e-12 * np.abs(J).max():
        raise InputError(
            "inertia must be diagonal (principal axes aligned with LVLH) for the linearised "
            f"LVLH model; got off-diagonal entries {off[np.abs(off) > 0].tolist()}"
        )
    return np.diag(J).copy()


def lvlh_second_order(inertia: Any, orbit_rate: float, *, printed: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(M, N, L)`` of ``M q̈ + N q̇ + L q = u`` (see module docstring).

    Parameters
    ----------
    inertia : array_like, shape (3,) or diagonal (3, 3), kg m²
    orbit_rate : float, rad/s
    printed : bool
        Use S1's printed (symmetric, sign-wrong) ``N`` instead of the derived skew one.

    Examples
    --------
    >>> from adcskit.dynamics import orbit_rate
    >>> M, N, L = lvlh_second_order([10.0, 12.0, 8.0], orbit_rate(800e3))
    >>> M.round(6)
    array([[10.,  0.,  0.],
           [ 0., 12.,  0.],
           [ 0.,  0.,  8.]])
    """
    Ix, Iy, Iz = _principal(inertia)
    n = check_positive("orbit_rate", orbit_rate, allow_zero=True, unit="rad/s")
    printed = check_flag("printed", printed)
    M = np.diag([Ix, Iy, Iz])
    if printed:
        N = n * (-Ix + Iy - Iz) * np.array([[0.0, 0, 1], [0, 0, 0], [1, 0, 0]])
    else:
        N = n * (Ix - Iy + Iz) * np.array([[0.0, 0, -1], [0, 0, 0], [1, 0, 0]])
    L = n**2 * np.diag([4 * (Iy - Iz), 3 * (Ix - Iz), Iy - Ix])
    return M, N, L


def lvlh_attitude_model(inertia: Any, orbit_rate: float, printed: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Continuous-time ``(A, B)`` (6×6, 6×3) of the linearised LVLH attitude model.

    State ``x = [φ, θ, ψ, φ̇, θ̇, ψ̇]`` (rad, rad/s), input ``u`` torque (N m, body).

    Parameters
    ----------
    inertia : array_like, shape (3,) or diagonal (3, 3), kg m²
        Principal moments ``(Ix, Iy, Iz)``; S1 uses (82, 80, 4).
    orbit_rate : float, rad/s
        Circular-orbit mean motion (:func:`adcskit.dynamics.orbit_rate`).
    printed : bool, default False
        ``True`` uses S1 eq. 9's printed gyroscopic matrix (see module docstring).

    References
    ----------
    S1 eq. 8–11; Wie (2008) §6.4.

    Examples
    --------
    >>> from adcskit.dynamics import orbit_rate
    >>> A, B = lvlh_attitude_model([10.0, 12.0, 8.0], orbit_rate(800e3))
    >>> A.shape, B.shape
    ((6, 6), (6, 3))
    """
    M, N, L = lvlh_second_order(inertia, orbit_rate, printed=printed)
    Minv = np.diag(1.0 / np.diag(M))
    A = np.zeros((6, 6))
    A[:3, 3:] = np.eye(3)
    A[3:, :3] = -Minv @ L
    A[3:, 3:] = -Minv @ N
    B = np.zeros((6, 3))
    B[3:, :] = Minv
    return A, B
