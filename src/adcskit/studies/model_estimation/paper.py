"""What S1 prints for the ``model-estimation`` study: Table 1, the eq. (12) poles, eq. (13).

References
----------
S1, Table 1 (% model error per method and case), the text next to Fig. 13 (the 3-DOF
sinusoid range), eq. (12) (closed-loop poles) and eq. (13) (discrete closed-loop matrices).
"""

from __future__ import annotations

import numpy as np

from adcskit.studies._pages import Statement

__all__ = ["STATEMENTS", "CASES", "PAPER_METHODS", "STANDARD", "TABLE_CASES", "PAPER_TABLE", "AXIS_POLES", "A13", "B13",
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


#: S1's statements within this study's scope, each to the claim that decides it or to why it is
#: not decided (S1 is in Persian; the words are our translation, shortened).
STATEMENTS = (
    Statement(where="Abstract; Table 1", text="The online meta-heuristic GMRES shows the highest accuracy in the "
              "estimation.", claim="online-most-accurate"),
    Statement(where="Abstract; conclusion", text="... and the highest stability in the estimation.", claim=None,
              reason="S1 defines no measure of stability (no bound, eigenvalue margin or divergence test) and prints "
              "no number for it, so there is nothing to compare with"),
    Statement(where="Text at Figs 1-2", text="1-DOF, random input: the model-error norm is reduced more than 10 "
              "times (offline variant).", claim="adaptive-10x-fig2"),
    Statement(where="Text at Figs 5-6", text="1-DOF, step + noise: the other methods' error rises a lot; the "
              "adaptive GMRES reduces the model error more than 10 times.", claim="adaptive-10x-fig6"),
    Statement(where="Text at Fig. 13", text="3-DOF, sinusoidal input: the online variant's final error is 9-16 % "
              "over different simulations ...", claim="online-3dof-sine-9-16"),
    Statement(where="Text at Fig. 13", text="... more than 10 times more accurate than the other methods.",
              claim="adaptive-10x-fig13"),
    Statement(where="Table 1 rows 1-5; text below it", text="The other methods' error varies from 37 to 195 %.",
              claim="standard-37-195"),
    Statement(where="Table 1 row 6", text="Offline adaptive GMRES, 1-DOF random input: 4-8 %.",
              claim="offline-1dof-random-4-8"),
    Statement(where="Table 1 row 6", text="Offline adaptive GMRES, 1-DOF step input: 6-9 %.",
              claim="offline-1dof-step-6-9"),
    Statement(where="Table 1 row 6", text="Offline adaptive GMRES, 3-DOF random input: 6-15 %.",
              claim="offline-3dof-random-6-15"),
    Statement(where="Table 1 row 7", text="Online adaptive GMRES, 1-DOF random input: 1-4 %.",
              claim="online-1dof-random-1-4"),
    Statement(where="Table 1 row 7", text="Online adaptive GMRES, 1-DOF step input: 2-5 %.",
              claim="online-1dof-step-2-5"),
    Statement(where="Table 1 row 7", text="Online adaptive GMRES, 3-DOF random input: 8-16 %.",
              claim="online-3dof-random-8-16"),
    Statement(where="Text below Table 1", text="The adaptive GMRES error is about 4-15 % (offline) and 1-16 % "
              "(online).", claim=None,
              reason="it is the span of Table 1's adaptive cells, decided cell by cell (offline-*, online-* "
              "claims)"),
    Statement(where="Text at Figs 3 and 7; below Table 1", text="On the 1-DOF model the online (automatic) method "
              "is more accurate than the offline one.", claim="online-beats-offline-1dof"),
    Statement(where="Text at Fig. 11; below Table 1", text="On the 3-DOF model both variants are equally accurate "
              "(Fig. 11); the offline one is slightly more accurate (below Table 1).", claim=None,
              reason="S1 gives no tolerance for 'equally' or 'slightly', and any we chose would decide the "
              "statement; Table 1's 3-DOF cells are decided"),
    Statement(where="Text at Fig. 11", text="On the 3-DOF model the online variant converges faster than the "
              "offline one.", claim=None,
              reason="S1 defines no convergence time and prints none; the error-vs-time figures show ours"),
    Statement(where="Text at Fig. 12", text="The online variant improves the 3-DOF estimate relative to the initial "
              "A0.", claim="online-improves-on-a0-fig12"),
    Statement(where="Text at Figs 1, 5, 9, 13", text="The attitude state is estimated well (after about 100 s on "
              "the 1-DOF model).", claim=None,
              reason="qualitative: S1 prints no state-estimation error or threshold"),
    Statement(where="Text at Fig. 7", text="Unlike the usual methods, the online variant guarantees convergence "
              "to the overall answer (step input).", claim=None,
              reason="a property of the algorithm, not a measured result; S1 gives no proof or criterion"),
    Statement(where="Text below Table 1; conclusion", text="The accurate model lets the moments of inertia be "
              "estimated and the estimated model is usable for control design.", claim=None,
              reason="S1 prints no inertia estimate and no closed-loop test with the estimated model"),
)
