"""Spacecraft environment: orbits, time, frames, sun direction, geomagnetic field.

Conventions (see ``docs/environment.md``): SI units and radians; UTC instants as numpy
``datetime64``; adcskit's ECI is the frame obtained from ECEF by the IAU-82 GMST rotation
(= SGP4's TEME); vectors batch-first, shape (3,) or (N, 3).

Typical use (S0's "wahba-orbit" scenario)::

    st = circular_orbit(800e3, np.radians(75), 0.0, 0.0, t, epoch="2024-01-01")
    s_eci = sun_direction(st.times)
    b_eci = magnetic_field(st.r, st.times, model="igrf")
"""

from adcskit.environment.frames import (
    EARTH_ROTATION_RATE,
    WGS84_A,
    WGS84_E2,
    WGS84_F,
    ecef_to_eci,
    ecef_to_eci_state,
    ecef_to_geocentric,
    ecef_to_geodetic,
    eci_to_ecef,
    eci_to_ecef_matrix,
    eci_to_ecef_state,
    enu_to_ecef_matrix,
    geocentric_to_ecef,
    geodetic_to_ecef,
    ned_to_ecef_matrix,
)
from adcskit.environment.magnetic import (
    IGRF_REFERENCE_RADIUS,
    MAGNETIC_MODELS,
    dipole_coefficients,
    magnetic_field,
)
from adcskit.environment.orbits import (
    MU_EARTH,
    R_EARTH,
    KeplerOrbit,
    OrbitState,
    circular_orbit,
    elements_to_rv,
    kepler_orbit,
    rv_to_elements,
    sgp4_orbit,
    solve_kepler,
)
from adcskit.environment.sun import AU, in_shadow, sun_direction, sun_position
from adcskit.environment.time import (
    J2000,
    as_utc,
    decimal_year,
    gmst,
    julian_centuries,
    julian_date,
    utc_times,
)

__all__ = [
    "AU",
    "EARTH_ROTATION_RATE",
    "IGRF_REFERENCE_RADIUS",
    "J2000",
    "MAGNETIC_MODELS",
    "MU_EARTH",
    "R_EARTH",
    "WGS84_A",
    "WGS84_E2",
    "WGS84_F",
    "KeplerOrbit",
    "OrbitState",
    "as_utc",
    "circular_orbit",
    "decimal_year",
    "dipole_coefficients",
    "ecef_to_eci",
    "ecef_to_eci_state",
    "ecef_to_geocentric",
    "ecef_to_geodetic",
    "eci_to_ecef",
    "eci_to_ecef_matrix",
    "eci_to_ecef_state",
    "elements_to_rv",
    "enu_to_ecef_matrix",
    "geocentric_to_ecef",
    "geodetic_to_ecef",
    "gmst",
    "in_shadow",
    "julian_centuries",
    "julian_date",
    "kepler_orbit",
    "magnetic_field",
    "ned_to_ecef_matrix",
    "rv_to_elements",
    "sgp4_orbit",
    "solve_kepler",
    "sun_direction",
    "sun_position",
    "utc_times",
]
