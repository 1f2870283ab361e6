"""Physical constants (SI). Values: WGS-84 / EGM-96 as used by Vallado (2013), Table D-1."""

#: Earth's gravitational parameter, m³/s² (EGM-96).
MU_EARTH = 3.986004418e14
#: Earth's equatorial radius, m (WGS-84).
R_EARTH = 6378137.0
#: Earth's rotation rate, rad/s (WGS-84).
OMEGA_EARTH = 7.292115e-5
#: Standard gravity, m/s² (for Isp conversions).
G0 = 9.80665
#: Radians per degree (``x_deg * RAD_PER_DEG``; the factor of ``math.radians``).
RAD_PER_DEG = 3.141592653589793 / 180.0
#: Degrees per radian (``x_rad * DEG_PER_RAD``; the factor of ``math.degrees``).
DEG_PER_RAD = 180.0 / 3.141592653589793
