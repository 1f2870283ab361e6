"""Robust objective ``w₁·E|e| + w₂·σ(e) + penalty`` (S4 eq. 10) and the S4 stopping rule.

References
----------
S4, eq. (10) and Fig. 8 (Venanzi's robust-optimisation loop: stop when the mean change of
the objective over the last 10 iterations is below 1e-7).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from adcskit._validation import as_array, check_choice, check_int, check_positive
from adcskit.errors import InputError

__all__ = ["robust_objective", "weights_from_ratio", "mean_change_converged"]


def weights_from_ratio(ratio: float) -> tuple[float, float]:
    """Weights ``(w₁, w₂)`` with ``w₂/w₁ = ratio`` and ``w₁ + w₂ = 1``.

    S4 reports only the ratio ``w₂/w₁``; normalising the sum leaves the minimiser
    unchanged and keeps the objective on the scale of the error.

    Examples
    --------
    >>> from adcskit.control import weights_from_ratio
    >>> weights_from_ratio(1.0)
    (0.5, 0.5)
    >>> tuple(round(w, 6) for w in weights_from_ratio(3.0))   # w2 / w1 = 3, w1 + w2 = 1
    (0.25, 0.75)
    """
    r = check_positive("ratio", ratio, allow_zero=True)
    return 1.0 / (1.0 + r), r / (1.0 + r)


def robust_objective(
    errors: Any,
    overshoot_pct: Any = None,
    *,
    w1: float = 1.0,
    w2: float = 1.0,
    overshoot_max_pct: float = 10.0,
    penalty_weight: float = 1.0,
    penalty_on: str = "sample",
    nonfinite: str = "raise",
) -> np.ndarray:
    """S4 eq. (10): ``F = w₁ E(|Error|) + w₂ σ(Error) + penalty`` over the last axis.

    Parameters
    ----------
    errors : array_like (..., n)
        Per-sample error measure (S4: mean ``|e|`` over the last 10 s) for ``n`` uncertain
        samples; any leading axes are candidates (e.g. a GA population).
    overshoot_pct : array_like (..., n), optional
        Per-sample overshoot [%]; the constraint ``overshoot <= overshoot_max_pct``
        (S4 eq. 10) is enforced by the penalty.
    w1, w2 : float
        Weights of the mean and of the standard deviation (``ddof=0``), >= 0.
    overshoot_max_pct : float
        Overshoot limit [%] (S4: 10 %).
    penalty_weight : float
        Penalty per percent of overshoot excess, in the units of ``errors``.
    penalty_on : {"sample", "mean"}
        S4 does not print its penalty. ``"sample"``: the mean over the samples of each
        sample's excess ``max(os - os_max, 0)``; ``"mean"``: the excess of the expected
        overshoot, ``max(E[os] - os_max, 0)`` (a constraint on E[overshoot]).

    Returns
    -------
    ndarray (...)
        Objective per candidate.

    References
    ----------
    S4, eq. (10).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.control import robust_objective
    >>> errors = np.array([[1.0, 2.0, 3.0], [2.0, 2.0, 2.0]])   # 2 candidates x 3 samples
    >>> robust_objective(errors).round(6)                 # mean + std (ddof=0)
    array([2.816497, 2.      ])
    >>> overshoot = [[5.0, 5.0, 5.0], [12.0, 14.0, 16.0]]   # %, the 2nd candidate exceeds 10 %
    >>> robust_objective(errors, overshoot).round(6)
    array([2.816497, 6.      ])
    """
    check_choice("nonfinite", nonfinite, ("raise", "infeasible"))
    finite = nonfinite == "raise"
    e = as_array("errors", errors, finite=finite)
    if e.ndim == 0 or e.shape[-1] < 1:
        raise InputError(f"errors must have at least one sample on its last axis; got shape {e.shape}")
    w1 = check_positive("w1", w1, allow_zero=True)
    w2 = check_positive("w2", w2, allow_zero=True)
    check_positive("overshoot_max_pct", overshoot_max_pct)
    check_positive("penalty_weight", penalty_weight, allow_zero=True)
    check_choice("penalty_on", penalty_on, ("sample", "mean"))
    a = np.abs(e)
    f = w1 * a.mean(axis=-1) + w2 * a.std(axis=-1)
    if overshoot_pct is not None:
        os = as_array("overshoot_pct", overshoot_pct, finite=finite)
        if os.shape != e.shape:
            raise InputError(f"overshoot_pct must have the shape of errors {e.shape}; got {os.shape}")
        os = np.nan_to_num(os, nan=0.0)
        if penalty_on == "mean":
            excess = np.maximum(os.mean(axis=-1) - overshoot_max_pct, 0.0)
        else:
            excess = np.maximum(os - overshoot_max_pct, 0.0).mean(axis=-1)
        f = f + penalty_weight * excess
    # a non-finite error (diverged sample) makes the candidate infeasible, not NaN
    return np.where(np.isfinite(f), f, np.inf)


def mean_change_converged(history: Sequence[float], *, tol: float = 1e-7, window: int = 10) -> bool:
    """S4 stopping rule: mean ``|F_k − F_{k−1}|`` over the last ``window`` iterations < ``tol``.

    Parameters
    ----------
    history : sequence of float
        Best objective value after each iteration.
    tol : float
        Threshold on the mean change (S4: 1e-7).
    window : int
        Number of recent changes averaged (S4: 10).

    Returns
    -------
    bool
        False until ``window + 1`` values are available.

    Examples
    --------
    >>> from adcskit.control import mean_change_converged
    >>> history = [1.0, 0.5, 0.3] + [0.2] * 10            # best objective per generation
    >>> mean_change_converged(history, tol=1e-7, window=10)   # 0.3 -> 0.2 is still in the window
    False
    >>> mean_change_converged(history + [0.2], tol=1e-7, window=10)
    True
    >>> mean_change_converged(history[:5])                # too short to judge
    False
    """
    tol = check_positive("tol", tol)
    window = check_int("window", window, minimum=1)
    h = as_array("history", history, ndim=1, nonempty=False)
    if h.size < window + 1:
        return False
    d = np.abs(np.diff(h[-(window + 1) :]))
    return bool(np.mean(d) < tol)
