"""What S4 prints for the ``onoff-schmitt`` study: Table 2's recommended thresholds, Table 3's
loop and the 0.25° pointing-accuracy claim.

References
----------
S4, Table 2 (recommended Schmitt thresholds per criterion, digits decoded in the seeds digest),
Table 3 (nominal loop), §3 text under Fig. 7 (pointing accuracy 0.25°); :data:`STATEMENTS`:
S4's statements of §3 (the Schmitt study, Figs 2-7), each to the claim that decides it.
"""

from __future__ import annotations

from typing import Any

from adcskit.studies._pages import Statement

__all__ = ["ACCURACY_DEG", "PAPER", "RECOMMENDED", "STATEMENTS", "TABLE2_ROWS"]

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

#: S4 §3 (Schmitt parametric study, Table 2, Figs 2-7): every statement, to the claim deciding it
#: or to why it is not decided (S4's robust tuning, Figs 8-19, is the ``onoff-tuning`` study's).
STATEMENTS = (
    Statement(where="§3, Figs. 3-4", text="a larger on threshold U_on gives fewer thruster firings and a larger "
              "pointing error (the maps of firings and mean |error| against U_on and U_off/U_on)",
              claim="u-on-trends"),
    Statement(where="§3, Fig. 2", text="fuel against U_on and U_off/U_on: parts of the map where the fuel jumps are "
              "removed from the recommended range", claim=None,
              reason="a method of deriving Table 2, no statement to test; the fuel map is drawn (fig2_fuel.png) "
              "and enters Table 2's claim"),
    Statement(where="§3, Table 2", text="recommended range of U_on and U_off/U_on per criterion (fuel, thruster "
              "activity, pointing error) and for all three criteria (0.1 < U_on < 0.6, 0.1 < U_off/U_on < 0.85)",
              claim="table2-recommended-region"),
    Statement(where="§3, text with Table 2", text="the on threshold depends on K_p: gains and thresholds can be "
              "divided by K_p, so U_on/K_p is what must lie in the recommended range", claim=None,
              reason="a scaling identity of the loop (the trigger compares the PID output with U_on), not a "
              "measured result; our sweep keeps S4's gains fixed, as Table 2 does"),
    Statement(where="§3, text with Table 2", text="Table 2 was derived as an example for applications that need a "
              "relatively fast attitude response", claim=None, reason="a statement of scope, nothing to measure"),
    Statement(where="§3, Figs. 5-7", text="with U_on = 0.15 and U_off/U_on = 0.5 (inside Table 2's range) and "
              "Table 3's loop: step response, thruster on/off history and a (quasi) limit cycle whose amplitude "
              "and frequency depend on the system parameters", claim=None,
              reason="qualitative: S4 prints no number for the response or the cycle; ours are drawn "
              "(fig5-fig7) and the nominal run's overshoot, fuel and firings are reported"),
    Statement(where="§3, text under Fig. 7", text="the control algorithm reaches a pointing accuracy of 0.25° "
              "despite the constant 0.05 N m disturbance", claim="pointing-accuracy-0.25deg"),
)
