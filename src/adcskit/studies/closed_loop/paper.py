"""What the papers print that the closed-loop study's scenarios use.

The closed-loop study answers questions the papers leave open (findings, no claims), so this
module holds only the printed numbers its scenarios are built from.

References
----------
S3, Table 5 (GEO spacecraft inertia); S0, orbit scenario (LEO inertia, initial Euler angles
(0, 0, 5 deg)); S4, Table 4 (nominal, minimum-error Pareto gains), Table 5 (dispersions) and
Table 6 ("all" robust gains), gains read as (K_p, K_i, K_d). S4's plant (Table 3, the 15 deg
step, the Schmitt trigger) is :data:`adcskit.studies._s4.S4_LOOP`; S3's reference layout is
:data:`adcskit.thrusters.reference.S3_REFERENCE_A`.
"""

from __future__ import annotations

__all__ = ["S0_INERTIA", "S0_INITIAL_ROTVEC_DEG", "S3_INERTIA", "S4_GAINS", "S4_TABLE5_DISPERSIONS"]

S3_INERTIA = (1218.6, 442.2, 1429.4)  # S3 Table 5
S0_INERTIA = (80.0, 80.0, 4.0)  # S0 orbit scenario
S4_GAINS = {"nominal": (56.24, 0.02, 49.99), "robust": (22.63, 0.03, 44.44)}  # (Kp, Ki, Kd): S4 Tables 4, 6
S0_INITIAL_ROTVEC_DEG = (0.0, 0.0, 5.0)  # S0 orbit scenario: initial Euler angles (0, 0, 5 deg)
#: S4 Table 5 as relative dispersions of the simulator: J std 2/10, thrust std 0.2/1,
#: disturbance std 0.05/0.05, delay std 0.01 s
S4_TABLE5_DISPERSIONS = {"inertia_rel": 0.2, "thrust_rel": 0.2, "disturbance_rel": 1.0, "delay_std_s": 0.01}
