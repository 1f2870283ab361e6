"""What the papers print that the closed-loop study's scenarios use.

The closed-loop study answers questions the papers leave open (findings, no claims), so this
module holds only the printed numbers its scenarios are built from.

References
----------
S3, Table 5 (GEO spacecraft inertia); S0, orbit scenario (LEO inertia, initial Euler angles
(0, 0, 5 deg)); S4, Table 4 (nominal, minimum-error Pareto gains) and Table 6 ("all" robust
gains), read as (K_p, K_i, K_d). S4's plant (Table 3, Table 5 dispersions, the 15 deg step) is
:data:`adcskit.studies._s4.S4_LOOP`; S3's reference layout is
:data:`adcskit.thrusters.reference.S3_REFERENCE_A`.
"""

from __future__ import annotations

__all__ = ["S0_INERTIA", "S3_INERTIA", "S4_GAINS"]

S3_INERTIA = (1218.6, 442.2, 1429.4)  # S3 Table 5
S0_INERTIA = (80.0, 80.0, 4.0)  # S0 orbit scenario
S4_GAINS = {"nominal": (56.24, 0.02, 49.99), "robust": (22.63, 0.03, 44.44)}  # (Kp, Ki, Kd): S4 Tables 4, 6
