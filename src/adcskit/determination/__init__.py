"""Attitude determination: Wahba point solvers (batched) and robust interval solvers.

* :func:`solve_wahba` — TRIAD, q-method, QUEST, ESOQ2, SVD, FOAM on one problem or a batch
  (compiled numba kernels), with loss, covariance, conditioning and per-problem status.
* :func:`robust_wahba` — the interval (bounded-uncertainty) Wahba problem of S0 eqs. 3–8:
  min-max goal attainment, NSGA-II Pareto set, and the worst-case (Ahmed & Kerrigan) solver.

Quaternions are scalar last and ``A(q)`` maps reference to body (``b = A r``); see
``docs/architecture.md``.
"""

from adcskit.determination.wahba import (
    METHODS,
    STATUS_MESSAGES,
    WahbaResult,
    davenport_k,
    solve_wahba,
    wahba_loss,
)

__all__ = [
    "METHODS",
    "STATUS_MESSAGES",
    "WahbaResult",
    "davenport_k",
    "solve_wahba",
    "wahba_loss",
]

from adcskit.determination.robust import (  # noqa: E402
    ROBUST_METHODS,
    RobustWahbaResult,
    interval_objectives,
    robust_wahba,
)

__all__ += ["ROBUST_METHODS", "RobustWahbaResult", "interval_objectives", "robust_wahba"]
