"""What the papers print that the closed-loop study's scenarios use.

The closed-loop study answers questions the papers leave open (findings, no claims), so this
module holds only the printed numbers its scenarios are built from.

References
----------
S3, Table 5 (GEO spacecraft inertia); S0, orbit scenario (LEO inertia, initial Euler angles
(0, 0, 5 deg)); S4, Table 4 (nominal, minimum-error Pareto gains), Table 5 (dispersions) and
Table 6 ("all" robust gains), gains read as (K_p, K_i, K_d). S4's plant (Table 3, the 15 deg
step, the Schmitt trigger) is :data:`adcskit.studies._s4.S4_LOOP`; S3's reference layout is
:data:`adcskit.thrusters.reference.S3_REFERENCE_A`. :data:`STATEMENTS`: the papers' statements
whose pieces the study flies in one loop, each to the question (finding) that asks what becomes of
it there; the study decides no claim of a paper (those are decided in the papers' own studies).
"""

from __future__ import annotations

from adcskit.studies._pages import Statement

__all__ = ["S0_INERTIA", "S0_INITIAL_ROTVEC_DEG", "S3_INERTIA", "S4_GAINS", "S4_TABLE5_DISPERSIONS", "STATEMENTS"]

S3_INERTIA = (1218.6, 442.2, 1429.4)  # S3 Table 5
S0_INERTIA = (80.0, 80.0, 4.0)  # S0 orbit scenario
S4_GAINS = {"nominal": (56.24, 0.02, 49.99), "robust": (22.63, 0.03, 44.44)}  # (Kp, Ki, Kd): S4 Tables 4, 6
S0_INITIAL_ROTVEC_DEG = (0.0, 0.0, 5.0)  # S0 orbit scenario: initial Euler angles (0, 0, 5 deg)
#: S4 Table 5 as relative dispersions of the simulator: J std 2/10, thrust std 0.2/1,
#: disturbance std 0.05/0.05, delay std 0.01 s
S4_TABLE5_DISPERSIONS = {"inertia_rel": 0.2, "thrust_rel": 0.2, "disturbance_rel": 1.0, "delay_std_s": 0.01}

#: The papers' statements whose pieces this study flies, and the question it asks of each: the
#: study has no claims (none of S0-S4 closes the loop), so every entry says where the paper's own
#: statement is decided and which finding of ours carries it into the closed loop.
STATEMENTS = (
    Statement(where="S0, orbit scenario; S0 eqs. 3-8", text="S0: robust min-max interval determination under "
              "bounded sensor errors (sun sensor, magnetometer)", claim=None,
              reason="S0's claims are decided in wahba-table1 and wahba-orbit; here our question Q2 flies the "
              "min-max solver in the loop against the q-method (finding q2-minmax-vs-qmethod) and the MEKF "
              "(finding q2-mekf-vs-qmethod)"),
    Statement(where="S1", text="S1: joint attitude-state and model estimation", claim=None,
              reason="not flown: the loop estimates attitude and gyro bias only (gyro-driven MEKF), no model "
              "parameters; S1's claims are decided in model-estimation"),
    Statement(where="S2, Gauss pseudospectral method", text="S2: time-optimal manoeuvres by the Gauss "
              "pseudospectral method", claim=None,
              reason="S2's claims are decided in rendezvous; here our question Q4 tracks a pseudospectral "
              "time-optimal slew against a step command (findings q4-optimal-slew-settling, "
              "q4-optimal-slew-propellant; check: the bang-bang optimum)"),
    Statement(where="S3 Fig. 5, eq. 18", text="S3: the optimised thruster layout needs less on-time (fuel) than "
              "the reference layout", claim=None,
              reason="S3's open-loop claims are decided in thruster-layout; here our question Q1 flies both "
              "layouts in a closed loop with S4's controller (finding q1-layout-propellant)"),
    Statement(where="S4 Tables 4-6", text="S4: robust gains give a slightly higher mean and a lower spread of the "
              "pointing error than the deterministic gains", claim=None,
              reason="S4's single-axis claims are decided in onoff-tuning; here our question Q3 flies both gain "
              "sets in a 3-axis loop with MEKF feedback (finding q3-robust-gains-spread)"),
)
