"""Boundary checks shared by the attitude API: quaternions, DCMs, MRPs, vectors."""

from __future__ import annotations

from typing import Any

import numpy as np

from adcskit._validation import as_batch
from adcskit.errors import InputError

#: Tolerance on ``|AᵀA − I|`` and ``|det A − 1|`` for a matrix to count as a rotation.
DCM_TOL = 1e-6


def quats(name: str, q: Any) -> tuple[np.ndarray, bool]:
    """``(N, 4)`` unit quaternions (normalised) and whether the input was batched.

    Non-unit input is normalised; a zero-norm quaternion is an error.
    """
    arr, batched = as_batch(name, q, (4,))
    norm = np.linalg.norm(arr, axis=1)
    bad = np.flatnonzero(norm < 1e-12)
    if bad.size:
        raise InputError(
            f"{name} must have non-zero norm (a quaternion is normalised before use); "
            f"got norm {norm[bad[0]]:.3g} at index {int(bad[0])}"
        )
    return arr / norm[:, None], batched


def dcms(name: str, A: Any, *, tol: float = DCM_TOL) -> tuple[np.ndarray, bool]:
    """``(N, 3, 3)`` proper orthogonal matrices, checked to ``tol``."""
    arr, batched = as_batch(name, A, (3, 3))
    err = np.abs(np.einsum("nki,nkj->nij", arr, arr) - np.eye(3)).max(axis=(1, 2))
    det = np.linalg.det(arr)
    bad = np.flatnonzero((err > tol) | (np.abs(det - 1.0) > tol))
    if bad.size:
        i = int(bad[0])
        raise InputError(
            f"{name} must be a rotation matrix (AᵀA = I and det A = +1 to {tol:g}); "
            f"at index {i}: max|AᵀA − I| = {err[i]:.3g}, det = {det[i]:.6g}"
        )
    return arr, batched


def vectors(name: str, v: Any) -> tuple[np.ndarray, bool]:
    return as_batch(name, v, (3,))


#: Largest MRP magnitude accepted: the MRP formulas use ``|σ|⁴``, which must stay finite.
MRP_MAX = 1e75


def mrps(name: str, sigma: Any) -> tuple[np.ndarray, bool]:
    """``(N, 3)`` MRP vectors with ``|σ_i| <= MRP_MAX`` (``|σ|⁴`` must not overflow)."""
    return as_batch(name, sigma, (3,), max_abs=MRP_MAX)


def out(arr: np.ndarray, batched: bool) -> np.ndarray:
    """Return ``arr`` with the leading batch axis removed when the input was a single item."""
    return arr if batched else arr[0]


def broadcast(name_a: str, a: np.ndarray, name_b: str, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Broadcast two ``(N, k)`` / ``(1, k)`` batches to a common length."""
    if a.shape[0] != b.shape[0] and 1 not in (a.shape[0], b.shape[0]):
        raise InputError(
            f"{name_a} and {name_b} must have the same batch length N or one of them a single "
            f"item; got N = {a.shape[0]} and N = {b.shape[0]}"
        )
    n = max(a.shape[0], b.shape[0])
    return np.broadcast_to(a, (n,) + a.shape[1:]), np.broadcast_to(b, (n,) + b.shape[1:])
