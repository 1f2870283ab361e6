"""What S4 prints for the tuning study: Tables 4-6, the GA protocol and the claim.

S4 prints each gain triple as (g1, g2, g3) without saying which of K_i and K_d comes second;
:func:`_reorder` maps a printed triple to (K_p, K_i, K_d) under either reading (the study
simulates both).

References
----------
S4, Table 4 (deterministic Pareto points), Table 5 (standard deviations), Table 6 (robust
gains and weight ratios w2/w1), §4 (GA: population 70, 1000 iterations, stopping rule), §5
(the claim); digits as decoded in the seeds digest.
"""

from __future__ import annotations

__all__ = ["PAPER_TABLE4", "PAPER_TABLE6", "CASES", "CLAIM_FIGURES", "PAPER", "_reorder"]

# S4 Table 4 / Table 6 as printed (digest-decoded), in the printed order (g1, g2, g3)
PAPER_TABLE4 = {"min_error": (56.24, 49.99, 0.02), "min_fuel": (10.93, 46.46, 0.25)}
PAPER_TABLE6 = {
    "inertia": {"ratio": 25.0, "printed": (43.54, 49.98, 0.01)},
    "thrust": {"ratio": 22.0, "printed": (43.05, 49.7, 0.02)},
    "disturbance": {"ratio": 15.0, "printed": (33.51, 45.08, 0.3)},
    "delay": {"ratio": 10.0, "printed": (56.9, 49.91, 0.02)},
    "all": {"ratio": 180.0, "printed": (22.63, 44.44, 0.03)},
}
#: S4 Table 5's uncertainty cases (each input alone, then all four), in the paper's order
CASES = ("inertia", "thrust", "disturbance", "delay", "all")
#: S4 §5: the figure that shows each case's deterministic-vs-robust comparison
CLAIM_FIGURES = {"inertia": "Fig. 15", "thrust": "Fig. 16", "disturbance": "Fig. 17", "delay": "Fig. 18",
                 "all": "Fig. 19"}

#: ``result.json`` → ``paper``: S4 Tables 4-6, the GA protocol (§4) and the claim (§5)
PAPER = {
    "gain_order_printed": "ambiguous: (K_p, K_d, K_i) or (K_p, K_i, K_d)",
    "table4": {k: list(v) for k, v in PAPER_TABLE4.items()},
    "table5": {"inertia": {"mean": 10.0, "std": 2.0}, "thrust": {"mean": 1.0, "std": 0.2},
               "disturbance": {"mean": 0.05, "std": 0.05}, "delay": {"mean": 0.02, "std": 0.01}},
    "table6": {k: {"ratio": v["ratio"], "gains": list(v["printed"])} for k, v in PAPER_TABLE6.items()},
    "ga": {"population": 70, "iterations": 1000, "stop": "mean change over last 10 < 1e-7"},
    "claim": "robust gains: slightly higher mean, lower std of |error|",
}


def _reorder(printed, order: str) -> tuple[float, float, float]:
    """Printed (g1, g2, g3) → (K_p, K_i, K_d) under the reading ``order``."""
    g1, g2, g3 = printed
    if order == "kp_kd_ki":
        return (g1, g3, g2)
    return (g1, g2, g3)
