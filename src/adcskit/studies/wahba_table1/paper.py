"""What S0 prints for the ``wahba-table1`` study, with where it prints it.

S0 eq. 9 prints the single-epoch vectors (from Ahmed & Kerrigan 2011) and the exact attitude
``q_exact``; Table 1 the mean attitude error, its variance and the run time of the q-method,
NSGA-II and min-max rows (100 trials, ±20 % bounded noise); the abstract the claimed factors
(7x lower error, 200x less dependence on input accuracy, about 600x faster than NSGA-II).

Examples
--------
>>> from adcskit.studies.wahba_table1.paper import PAPER_TABLE1, paper_ratio
>>> PAPER_TABLE1["q-method"]["mean_deg"], round(paper_ratio("nsga2-truth-pick", "minmax", "runtime_s"), 2)
(15.1352, 434.08)
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["B_EXACT", "CLAIMED", "PAPER", "PAPER_TABLE1", "Q_EXACT_SCALAR_FIRST", "R_EXACT", "paper_ratio",
           "q_exact"]

# S0 eq. 9 (printed). q_exact is printed scalar-first with Shuster's A(q) (seeds digest).
R_EXACT = np.array([[-0.54, -0.326, 0.775], [-0.673, 0.000133, 0.74]])
B_EXACT = np.array([[-0.776, -0.46, 0.43], [-0.927, 0.01, 0.374]])
Q_EXACT_SCALAR_FIRST = np.array([-0.9746, 0.0707, -0.2122, -0.0125])

# S0 Table 1 (100 trials): mean δθ [deg], variance [deg²], run time [s]
PAPER_TABLE1 = {
    "q-method": {"mean_deg": 15.1352, "var_deg2": 95.1604, "runtime_s": 0.006},
    "nsga2-truth-pick": {"mean_deg": 0.5699, "var_deg2": 0.1915, "runtime_s": 124.58},
    "minmax": {"mean_deg": 2.2025, "var_deg2": 0.4409, "runtime_s": 0.287},
}

#: S0 abstract: the claimed factors (error, sensitivity to input accuracy, speed vs NSGA-II).
CLAIMED = {"error": 7, "sensitivity": 200, "speed": 600}


def q_exact() -> np.ndarray:
    """S0's q_exact in our convention (scalar last, q4 >= 0).

    Examples
    --------
    >>> q_exact().round(4)
    array([-0.0707,  0.2122,  0.0125,  0.9746])
    """
    q = np.r_[Q_EXACT_SCALAR_FIRST[1:], Q_EXACT_SCALAR_FIRST[0]]
    q = q / np.linalg.norm(q)
    return -q if q[3] < 0 else q


def paper_ratio(row_a: str, row_b: str, key: str) -> float:
    """Ratio of two S0 Table 1 entries, ``row_a[key] / row_b[key]``.

    Examples
    --------
    >>> round(paper_ratio("q-method", "minmax", "var_deg2"), 1)
    215.8
    """
    return PAPER_TABLE1[row_a][key] / PAPER_TABLE1[row_b][key]


#: The ``paper`` block of ``result.json``.
PAPER: dict[str, Any] = {
    "methods": PAPER_TABLE1, "source": "S0 Table 1 (100 trials, ±20 % bounded noise), eq. 9",
    "ratios": {"error_qmethod_over_minmax": paper_ratio("q-method", "minmax", "mean_deg"),
               "variance_qmethod_over_minmax": paper_ratio("q-method", "minmax", "var_deg2"),
               "runtime_nsga2_over_minmax": paper_ratio("nsga2-truth-pick", "minmax", "runtime_s"),
               "claimed": CLAIMED},
}
