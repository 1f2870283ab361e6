"""Sensor models: sun sensor (with eclipse), magnetometer, rate gyro, bounded (interval) and
Gaussian errors.

Sensors take the true attitude matrix ``A`` (reference -> body, ``b = A r``) and reference
vectors, and return body-frame measurements with misalignment, bounded angular or
per-component errors, Gaussian noise and bias (``rng``-seeded, batched over time). The
interval helpers build S0's midpoint-radius boxes ``b = b^m + diag(α) b^r`` (eq. 4-5).
"""

from adcskit.sensors.intervals import interval_from_bounds, midpoint_radius, vector_bounds
from adcskit.sensors.models import GyroMeasurement, Magnetometer, RateGyro, SunSensor, VectorSensor

__all__ = [
    "GyroMeasurement",
    "Magnetometer",
    "RateGyro",
    "SunSensor",
    "VectorSensor",
    "interval_from_bounds",
    "midpoint_radius",
    "vector_bounds",
]
