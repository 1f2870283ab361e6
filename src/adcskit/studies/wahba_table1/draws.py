"""The random draws of one S0 epoch, shared by the experiment and its timing (S0 eq. 9, Table 1).

Noisy body and reference vectors (±bound of each component of S0 eq. 9's vectors), the NSGA-II
seed of an epoch, and S0's attitude error metric.
"""

from __future__ import annotations

import numpy as np

from adcskit.studies.wahba_table1.paper import B_EXACT, R_EXACT

__all__ = ["angle_deg", "epoch_inputs", "perturb", "perturb_raw"]


def angle_deg(q1: np.ndarray, q2: np.ndarray) -> float:
    """δθ between two attitudes [deg] (S0's error metric, chord form for accuracy).

    Examples
    --------
    >>> angle_deg(np.array([0.0, 0.0, 0.0, 1.0]), np.array([0.0, 0.0, -0.0, -1.0]))
    0.0
    """
    d = min(np.linalg.norm(q1 - q2), np.linalg.norm(q1 + q2))
    return float(np.degrees(4.0 * np.arcsin(min(d / 2.0, 1.0))))


def perturb_raw(rng: np.random.Generator, bound: float) -> tuple[np.ndarray, np.ndarray]:
    """Noisy body and reference vectors *before* renormalisation (±bound of each component).

    Examples
    --------
    >>> b, r = perturb_raw(np.random.default_rng(0), 0.2)
    >>> bool(np.all(np.abs(b / B_EXACT - 1.0) <= 0.2))
    True
    """
    b = B_EXACT * (1.0 + bound * rng.uniform(-1, 1, B_EXACT.shape))
    r = R_EXACT * (1.0 + bound * rng.uniform(-1, 1, R_EXACT.shape))
    return b, r


def perturb(rng: np.random.Generator, bound: float) -> tuple[np.ndarray, np.ndarray]:
    """Noisy, renormalised body and reference vectors (±bound of each component).

    Examples
    --------
    >>> b, r = perturb(np.random.default_rng(0), 0.2)
    >>> np.linalg.norm(b, axis=1).round(12)
    array([1., 1.])
    """
    b, r = perturb_raw(rng, bound)
    return b / np.linalg.norm(b, axis=1, keepdims=True), r / np.linalg.norm(r, axis=1, keepdims=True)


def epoch_inputs(seed: np.random.SeedSequence, bound: float) -> tuple[np.ndarray, np.ndarray, int]:
    """The noisy vectors of one epoch and its NSGA-II seed, drawn from ``seed`` (as :func:`trial` does).

    Examples
    --------
    >>> b, r, s = epoch_inputs(np.random.SeedSequence(0), 0.2)
    >>> b.shape, r.shape, isinstance(s, int)
    ((2, 3), (2, 3), True)
    """
    rng = np.random.default_rng(seed)
    b, r = perturb(rng, bound)
    return b, r, int(rng.integers(2**31 - 1))
