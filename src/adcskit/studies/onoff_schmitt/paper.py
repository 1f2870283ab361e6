"""What S4 prints for the ``onoff-schmitt`` study: Table 2's recommended thresholds, Table 3's
loop and the 0.25° pointing-accuracy claim.

References
----------
S4, Table 2 (recommended Schmitt thresholds per criterion, digits decoded in the seeds digest),
Table 3 (nominal loop), §3 text under Fig. 7 (pointing accuracy 0.25°).
"""

from __future__ import annotations

from typing import Any

__all__ = ["ACCURACY_DEG", "PAPER", "RECOMMENDED", "TABLE2_ROWS"]

#: S4 §3, text under Fig. 7: pointing accuracy reached under the 0.05 N m disturbance [deg].
ACCURACY_DEG = 0.25
#: S4 Table 2, "all three criteria": recommended (lower, upper) of ``U_on`` and ``U_off/U_on``.
RECOMMENDED = {"u_on": (0.1, 0.6), "off_ratio": (0.1, 0.85)}
#: S4 Table 2 rows as decoded in the seeds digest: recommended (U_on, U_off/U_on) per criterion,
#: each a half-open box (lower, upper); ``None`` = unbounded on that side.
TABLE2_ROWS = {
    "fuel": {"u_on": (0.05, None), "off_ratio": (0.1, None)},
    "firings": {"u_on": (0.1, None), "off_ratio": (None, 0.9)},
    "err_deg": {"u_on": (None, 0.6), "off_ratio": (None, 0.85)},
}

#: ``result.json`` → ``paper``: the values above and S4 Table 3's nominal loop.
PAPER: dict[str, Any] = {
    "accuracy_deg": ACCURACY_DEG,
    "table2_region": {"u_on": list(RECOMMENDED["u_on"]), "off_ratio": list(RECOMMENDED["off_ratio"])},
    "table2_rows": {
        "fuel": {"u_on": "> 0.05", "off_ratio": "> 0.1"},
        "thruster_activity": {"u_on": "> 0.1", "off_ratio": "< 0.9"},
        "pointing_error": {"u_on": "< 0.6", "off_ratio": "< 0.85"},
    },
    "table3": {"delay_s": 0.02, "tau_thruster_s": 0.01, "u_on": 0.15, "off_ratio": 0.5,
               "disturbance_Nm": 0.05, "torque_Nm": 1.0, "step_deg": 15.0, "inertia_kgm2": 10.0},
}
