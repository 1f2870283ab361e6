"""What S1 prints for the ``model-estimation`` study: Table 1, the eq. (12) poles, eq. (13).

References
----------
S1, Table 1 (% model error per method and case), the text next to Fig. 13 (the 3-DOF
sinusoid range), eq. (12) (closed-loop poles) and eq. (13) (discrete closed-loop matrices).
"""

from __future__ import annotations

import numpy as np

__all__ = ["CASES", "PAPER_METHODS", "STANDARD", "TABLE_CASES", "PAPER_TABLE", "AXIS_POLES", "A13", "B13",
           "PAPER", "paper_range"]

#: S1's seven methods, in table order.
PAPER_METHODS = ("gmres", "bicg", "bicgstab", "cgs", "qr", "adaptive-gmres-offline", "adaptive-gmres-online")
#: S1's "standard solvers" (Table 1, rows 1-5).
STANDARD = ("gmres", "bicg", "bicgstab", "cgs", "qr")
#: S1's scenarios: 1-DOF random and step input, 3-DOF random and sinusoidal input.
CASES = ("1dof-random", "1dof-step", "3dof-random", "3dof-sine")
#: S1 Table 1's columns.
TABLE_CASES = ("1dof-random", "1dof-step", "3dof-random")


#: S1 Table 1 (% error), with the 3-DOF sinusoid range from the text next to Fig. 13.
PAPER_TABLE: dict[str, dict[str, dict[str, float]]] = {
    "gmres": {"1dof-random": {"value": 79}, "1dof-step": {"value": 194}, "3dof-random": {"value": 82}},
    "bicg": {"1dof-random": {"value": 80}, "1dof-step": {"value": 195}, "3dof-random": {"value": 91}},
    "bicgstab": {"1dof-random": {"value": 115}, "1dof-step": {"value": 195}, "3dof-random": {"value": 89}},
    "cgs": {"1dof-random": {"value": 37}, "1dof-step": {"value": 194}, "3dof-random": {"value": 61}},
    "qr": {"1dof-random": {"value": 99}, "1dof-step": {"value": 195}, "3dof-random": {"value": 97}},
    "adaptive-gmres-offline": {
        "1dof-random": {"min": 4, "max": 8}, "1dof-step": {"min": 6, "max": 9}, "3dof-random": {"min": 6, "max": 15},
    },
    "adaptive-gmres-online": {
        "1dof-random": {"min": 1, "max": 4}, "1dof-step": {"min": 2, "max": 5}, "3dof-random": {"min": 8, "max": 16},
        "3dof-sine": {"min": 9, "max": 16},
    },
}

#: S1 eq. (12) poles, assigned per axis from the eigenstructure of the printed eq. (13):
#: roll, pitch, yaw.
AXIS_POLES = (
    (-0.2041 + 0.4115j, -0.2041 - 0.4115j),
    (-0.2536 + 0.4550j, -0.2536 - 0.4550j),
    (-0.5441, -7.5034),
)

#: S1 eq. (13), printed discrete closed-loop matrices.
A13 = np.array([
    [0.91, 0, 0, 0.79, 0, 0],
    [0, 0.89, 0, 0, 0.75, 0],
    [-3.2e-4, 0, 0.66, -3.1e-4, 0, 0.16],
    [-0.16, 0, 0, 0.59, 0, 0],
    [0, -0.205, 0, 0, 0.51, 0],
    [-6e-4, 0, -0.66, -6e-4, 0, -0.67],
])
B13 = np.vstack([np.zeros((3, 3)), np.diag([0.012, 0.0125, 0.25])])


#: The ``paper`` block of ``result.json``.
PAPER = {
    "table": PAPER_TABLE,
    "metric": "e = 100 ||A_hat - A||_2 / ||A||_2 at the end of the run (S1 Table 1)",
    "claim": "adaptive GMRES reduces the model-error norm more than 10x vs the standard solvers (S1 text at Figs 2, 6, 13)",
    "source": "S1 Table 1; 3dof-sine range from the text at Fig. 13",
}


def paper_range(pv):
    """S1's printed entry as a value or a ``"min-max"`` range (``None`` when S1 prints none).

    Examples
    --------
    >>> paper_range(PAPER_TABLE["gmres"]["1dof-random"]), paper_range(PAPER_TABLE["adaptive-gmres-online"]["3dof-sine"])
    (79, '9-16')
    >>> paper_range(None) is None
    True
    """
    if not pv:
        return None
    return pv.get("value", f"{pv.get('min')}-{pv.get('max')}")
