"""What S2 prints for the rendezvous study: Table 4, the main scenario's theory values.

References
----------
S2, Sec. 6 (main scenario, Tables 2-3, Figs 3-15), Table 4 (p. of Sec. 7: five initial
positions, tf by the paper's GPM and by GPOPS), eq. 38-39 (H = -1), Sec. 6-8 (claims).
"""

from __future__ import annotations

import numpy as np

from adcskit.studies._pages import Statement

__all__ = ["PAPER_ROWS", "READING_NAMES", "PAPER_DOC", "GPM_DECIMALS", "GPOPS_DECIMALS", "STATEMENTS", "paper_row"]

# S2 Table 4: initial position (m), tf by the paper's GPM (s), tf by GPOPS (s), difference (%,
# |GPM - GPOPS| / GPM: 0.1338 / 26.1674 = 0.5113 %)
PAPER_ROWS = (
    ((20.0, 0.0, 0.0), 25.8727, 25.87, 0.0104),
    ((20.0, 4.0, 0.0), 26.1674, 26.0336, 0.5113),
    ((20.0, 4.0, 4.0), 25.9360, 26.1652, 0.8837),
    ((20.0, 4.0, -5.0), 25.6607, 25.8986, 0.9271),
    ((25.0, -5.0, -5.0), 28.7185, 28.2784, 1.5325),
)
# GPM prints 4 decimals; GPOPS 4 except the main row (2 decimals, "25.87")
GPM_DECIMALS = 4
GPOPS_DECIMALS = (2, 4, 4, 4, 4)

#: Names of the two readings of the rotational dynamics (config values "paper" / "full").
READING_NAMES = {"paper": "eq. 2 as printed", "full": "full relative dynamics"}

#: The ``paper`` section of ``result.json``: Table 4 and the main scenario's theory values
#: (S2 eq. 38-39: H = -1; Sec. 6, Figs 3-4: bang-bang).
PAPER_DOC = {
    "source": "S2 Table 4 (tf in s); main scenario S2 Sec. 6, Tables 2-3; claims Sec. 6-8",
    "rows": [
        {"s0_m": list(r[0]), "tf_gpm_s": r[1], "tf_gpops_s": r[2], "difference_percent": r[3]}
        for r in PAPER_ROWS
    ],
    "hamiltonian": -1.0,
    "bang_bang": True,
}


#: S2's statements within this study's scope, each to the claim that decides it or to why none
#: does (the page's statement table, ``adcskit.studies._pages``).
STATEMENTS = (
    Statement(where="Abstract; Sec. 6, Figs 3-4; Sec. 7",
              text="The control structure of all control forces and torques is bang-bang", claim="bang_bang"),
    Statement(where="Sec. 6", text="The time-optimal 6-DOF manoeuvre of the main scenario lasts t_f = 25.8727 s",
              claim="tf_main"),
    Statement(where="Sec. 6, Figs 3-4",
              text="Although the attitude manoeuvre is a pure rotation about one body axis, the torques about the "
              "other body axes are engaged to reach a shorter time (generalised to the 6-DOF manoeuvre)",
              claim=None,
              reason="the bang_bang claim shows T1 and T3 on their bounds, but 'for a shorter time' needs the "
              "manoeuvre with torque about axis 2 only, which we do not solve"),
    Statement(where="Sec. 6, Figs 5-9",
              text="Angular velocity, attitude, relative velocity and position reach the final conditions of Table 3",
              claim=None,
              reason="the NLP imposes them as boundary conditions; our check that the open-loop re-simulation of "
              "each row's solution reaches the final state tests the controls (a check, not a claim)"),
    Statement(where="Sec. 6, Theorem 1, Figs 11-14",
              text="The costates are estimated from the KKT multipliers of the NLP", claim=None,
              reason="a statement of method: implemented and tested against analytic costates "
              "(tests/optimal_control); S2 prints no costate value to compare"),
    Statement(where="Sec. 6, eq. 38-39, Fig. 15; abstract; Sec. 7",
              text="The Hamiltonian is approximately constant and equal to -1, so the solution satisfies the "
              "first-order optimality conditions", claim="hamiltonian"),
    *(Statement(where=f"Table 4, row {i + 1}", text=f"GPM t_f from s0 = {list(r[0])} m: {r[1]} s",
                claim=f"table4_gpm_row{i + 1}") for i, r in enumerate(PAPER_ROWS) if i),
    Statement(where="Table 4, GPOPS column", text="t_f by GPOPS: 25.87, 26.0336, 26.1652, 25.8986, 28.2784 s",
              claim=None,
              reason="a third-party solver's output, not S2's result; our findings gpops_on_converged_branches "
              "and gpops_is_best place each value among our mesh-converged optima"),
    Statement(where="Table 4, last column", text="Differences 0.0104, 0.5113, 0.8837, 0.9271, 1.5325 %",
              claim=None,
              reason="arithmetic on the two printed columns (|GPM - GPOPS| / GPM), reproduced to every printed "
              "digit by tests/studies/test_rendezvous.py; the claim it supports is agrees_with_gpops"),
    Statement(where="Sec. 7 (after Table 4); Sec. 8",
              text="The Gauss pseudospectral results agree well with those of GPOPS", claim="agrees_with_gpops"),
    Statement(where="Sec. 7 (after Table 4)",
              text="In some cases the Gauss pseudospectral method even gives a shorter manoeuvre time than GPOPS",
              claim="gpm_sometimes_shorter"),
)


def paper_row(s0):
    """The S2 Table 4 row whose initial position is ``s0`` (m), or None.

    Parameters
    ----------
    s0 : (3,) array_like, m
        Initial relative position in LVLH.

    Returns
    -------
    tuple or None
        ``(s0, tf_gpm_s, tf_gpops_s, difference_percent)`` of S2 Table 4.

    Examples
    --------
    >>> paper_row((20.0, 4.0, 4.0))[1:3]
    (25.936, 26.1652)
    >>> paper_row((1.0, 2.0, 3.0)) is None
    True
    """
    for r in PAPER_ROWS:
        if np.allclose(r[0], s0):
            return r
    return None
