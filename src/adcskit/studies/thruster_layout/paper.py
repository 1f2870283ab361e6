"""What S3 prints for the ``thruster-layout`` study, with where it prints it.

S3 (Kosari, Kaviri, Moshiri, Fakoor) §6 prints F_best and the layout matrices of its optimal
designs, Table 8 the minimum reachable error ``e_min`` of the DE layouts, Tables 5-7 the
settings (taken over as :class:`~adcskit.studies.thruster_layout.config.Config` defaults).
The reference 6-thruster layout and the manoeuvre are used by several layers, so they live
in :mod:`adcskit.thrusters.reference` and are only re-exported here under the study's names.

Examples
--------
>>> from adcskit.studies.thruster_layout.paper import A_REF, PAPER
>>> A_REF.shape, PAPER["table8_e_min_rad"]["6"]
((3, 6), 0.00083)
"""

from __future__ import annotations

from typing import Any

from adcskit.studies._pages import Statement
from adcskit.thrusters.reference import S3_REFERENCE_A, s3_manoeuvre_demands

__all__ = ["A_REF", "PAPER", "STATEMENTS", "manoeuvre_demands"]

#: S3 §6: reference 6-thruster layout (:data:`adcskit.thrusters.S3_REFERENCE_A`) and the manoeuvre
#: (:func:`adcskit.thrusters.s3_manoeuvre_demands`), kept under the study's names.
A_REF = S3_REFERENCE_A
manoeuvre_demands = s3_manoeuvre_demands

#: S3's printed results (§6, Table 8) and layouts. The 4-thruster GA matrix prints "101" in
#: row 2 (read as 1.01); the 8-thruster matrix is printed wrapped as a 6 x 5 block (columns
#: 1-5 in rows 1-3, columns 6-8 in rows 4-6).
PAPER: dict[str, Any] = {
    "source": "S3 §6 (printed F_best and layout matrices), Table 8 (e_min, rad), Tables 5-7",
    "f_best": {"4": {"ga": 4.5, "de": 3.1}, "6": {"de": 3.4}, "8": {"de": 3.6}},
    "table8_e_min_rad": {"4": 0.00084, "6": 0.00083, "8": 0.00082, "12": 0.00083},
    "claims": [
        "DE reaches lower fitness and runs faster than GA (Figs 3-4)",
        "the lowest fitness is at 6 thrusters for both algorithms (Fig 4)",
        "the optimal 6-thruster layout needs shorter on-times (less fuel) than the reference (Fig 5)",
    ],
    "layouts": {
        "4-ga": [[0.66, 0, -1, -0.90], [0, 1.01, 0.19, -0.62], [-0.997, 1.2, 0.93, -0.68]],
        "4-de": [[0.351, 0, -0.99, -0.77], [0, 0.72, 0.02, -0.66], [-0.998, 0.71, 0.93, -0.56]],
        "6-de": [
            [-1.3, -1.4, -1.3, 1.4, 0.99, 0.99],
            [0.81, -0.47, -0.39, 0.96, 0, 0],
            [-0.57, -1.24, 1.27, -0.4, 0.99, 0.99],
        ],
        "8-de": [
            [-1.3, -1.3, 1.4, 1.41, 1.4, -1.3, -1.26, -1.18],
            [-1.06, -0.89, 0.69, -0.13, 0.69, -0.77, 0.27, 0.56],
            [-1.38, -0.4, 0.82, 0.03, -0.27, 0.89, -1.11, -0.58],
        ],
        "reference": A_REF.tolist(),
    },
}


#: S3's statements within this study's scope, each to the claim that decides it or to the
#: reason it is not decided (issue 21 item 3: the page's statement-to-claim table).
STATEMENTS = (
    Statement(where="abstract; §6, Figs 3-4", text="DE outperforms GA in accuracy (lower fitness F_best)",
              claim="de-more-accurate"),
    Statement(where="abstract; §6, Fig. 3", text="DE has a shorter run (CPU) time than GA",
              claim="de-faster"),
    Statement(where="§6, Fig. 3", text="for both algorithms the computation time grows with the number of "
              "thrusters", claim=None,
              reason="we time every n (figure runtime_vs_n.png) but declare no claim: at equal evaluations the "
              "growth follows from the larger decision vector"),
    Statement(where="§6, Fig. 4", text="for both algorithms the lowest fitness is obtained with 6 thrusters",
              claim="six-thrusters-best"),
    Statement(where="§6, Fig. 5", text="the fuel consumption (on-time) of the optimal layout is lower than that of "
              "the empirically chosen reference layout", claim="optimal-layout-less-fuel"),
    Statement(where="§6, Table 8", text="e_min of the four DE layouts 0.00084, 0.00083, 0.00082, 0.00083 rad, "
              "an acceptable level", claim="table8-e-min"),
    Statement(where="§6", text="printed F_best 4.5 (4, GA), 3.1 (4, DE), 3.4 (6, DE), 3.6 (8, DE)", claim=None,
              reason="absolute F_best depends on S3's manoeuvre, which is not printed; ours are in the comparison "
              "table, the ranking statements are the claims above"),
    Statement(where="§6", text="printed layout matrices of the 4-, 6- and 8-thruster designs", claim=None,
              reason="a layout matrix is not a statement that can hold; our finding printed-layouts-realisable "
              "checks whether the 6- and 8-thruster matrices fit the 2 x 2 x 2 m box"),
    Statement(where="§6", text="for 4 thrusters the GA and DE results agree with each other", claim=None,
              reason="no measure of agreement is given; the layouts of both are printed and compared with ours "
              "only through F_best (de-more-accurate)"),
    Statement(where="§7", text="in both algorithms the fitness converges to the optimum with the same trend",
              claim=None, reason="qualitative, no measure given; our convergence curves are in figure "
              "convergence.png"),
    Statement(where="§5", text="six thrusters are needed in general; four can suffice in a special layout",
              claim=None, reason="a statement from S3's reference [18], not a result of S3's experiment"),
)
