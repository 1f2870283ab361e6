"""What S0 prints for its orbit scenario (§4-2), with table, figure and page provenance.

S0 §4-2 propagates a rigid spacecraft (inertia diag(80, 80, 4) kg m², Table 3) from Euler
angles (0, 0, 5°) with zero body rate (Table 2) for 20 minutes on a circular 800 km, 75°
orbit (RAAN 0, Table 3), measures the sun (±0.005° bounded error) and the geomagnetic field
(±0.5°), and compares the robust interval solution with the q-method (Figs. 1–4); its
abstract claims a > 50 % lower RMS attitude error.
"""

from __future__ import annotations

__all__ = ["PAPER"]

#: S0 §4-2's scenario and claim as printed (Tables 2-3, Figs. 1-4, abstract).
PAPER = {
    "altitude_km": 800.0,
    "inclination_deg": 75.0,
    "raan_deg": 0.0,
    "duration_min": 20.0,
    "inertia_kgm2": [80.0, 80.0, 4.0],
    "euler0_deg": [0.0, 0.0, 5.0],
    "sun_sensor_bound_deg": 0.005,
    "magnetometer_bound_deg": 0.5,
    "rms_reduction_claim": "> 50 % lower RMS attitude error than the q-method (S0 abstract, Fig. 4)",
    "source": "S0 §4-2, Tables 2-3, Figs. 1-4",
}
