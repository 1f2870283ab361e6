"""Interval (midpoint-radius) boxes of S0 eq. 4-5."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adcskit.errors import InputError
from adcskit.sensors import (
    Magnetometer,
    SunSensor,
    interval_from_bounds,
    midpoint_radius,
    vector_bounds,
)


def _random_truth(n, seed, scale=1.0):
    rng = np.random.default_rng(seed)
    r = rng.normal(size=(n, 3))
    return scale * r / np.linalg.norm(r, axis=1, keepdims=True)


def _encloses(mid, rad, x, tol):
    return np.all(np.abs(x - mid) <= rad + tol)


def test_interval_from_bounds():
    mid, rad = interval_from_bounds([-1.0, 0.0, 2.0], [1.0, 0.5, 2.0])
    assert np.allclose(mid, [0.0, 0.25, 2.0]) and np.allclose(rad, [1.0, 0.25, 0.0])
    with pytest.raises(InputError, match="lower must be <= upper"):
        interval_from_bounds([1.0], [0.0])
    with pytest.raises(InputError, match="upper"):
        interval_from_bounds([0.0, 0.0], [1.0])


@pytest.mark.parametrize(
    "sensor, scale",
    [
        (SunSensor(angle_bound=np.radians(0.005)), 1.0),  # S0 sun sensor
        (Magnetometer(angle_bound=np.radians(0.5)), 4e-5),  # S0 magnetometer
        (SunSensor(component_fraction=0.2), 1.0),  # S0 Table 1, re-normalised
        (Magnetometer(component_fraction=0.2), 4e-5),  # S0 Table 1, raw
        (Magnetometer(component_fraction=0.1, angle_bound=np.radians(2.0)), 4e-5),
        (SunSensor(component_fraction=0.05, angle_bound=np.radians(1.0)), 1.0),
    ],
)
def test_sensor_interval_encloses_truth(sensor, scale):
    truth = _random_truth(5000, 1, scale)
    m = sensor.measure(np.eye(3), truth, rng=9)
    mid, rad = sensor.interval(m)
    assert np.all(rad >= 0)
    assert _encloses(mid, rad, truth, 1e-12 * scale)


def test_angle_box_is_tight():
    # Exactness: for each axis the extreme rotations (towards / away from the axis by the full
    # bound) reach the box edges.
    th = np.radians(3.0)
    v = np.array([0.36, 0.48, 0.8])
    lo, hi = vector_bounds(v, angle_bound=th)
    for i in range(3):
        e = np.eye(3)[i]
        axis = np.cross(v, e)
        axis /= np.linalg.norm(axis)
        for sign, edge in ((1, hi[i]), (-1, lo[i])):
            # rotate v about v x e_i by sign*th (Rodrigues); +th turns v towards e_i
            c, s = np.cos(sign * th), np.sin(sign * th)
            w = v * c + np.cross(axis, v) * s + axis * (axis @ v) * (1 - c)
            assert w[i] == pytest.approx(edge, abs=1e-12)


def test_fraction_box_exact_and_naive_box_undercovers():
    # Measured m = t (1 + f u): true t in [m/(1+f), m/(1-f)] (edges reached at u = -+1).
    f = 0.2
    mid, rad = midpoint_radius([1.0, -2.0, 0.0], fraction=f)
    assert np.allclose(mid - rad, [1 / 1.2, -2 / 0.8, 0.0]) and np.allclose(mid + rad, [1 / 0.8, -2 / 1.2, 0.0])
    # The naive S0-style box m +- f|m| misses some true vectors (which the exact one keeps).
    truth = _random_truth(5000, 2)
    m = Magnetometer(component_fraction=f).measure(np.eye(3), truth, rng=3)
    naive_ok = np.all(np.abs(truth - m) <= f * np.abs(m) + 1e-15, axis=1)
    assert not np.all(naive_ok)
    assert _encloses(*midpoint_radius(m, fraction=f), truth, 1e-15)


@settings(max_examples=50, deadline=None)
@given(st.floats(0.0, 1.0), st.floats(0.0, 0.9), st.integers(0, 1000))
def test_any_bounds_enclose(angle, frac, seed):
    truth = _random_truth(200, seed)
    sensor = SunSensor(angle_bound=angle, component_fraction=frac)
    m = sensor.measure(np.eye(3), truth, rng=seed)
    assert _encloses(*sensor.interval(m), truth, 1e-12)


def test_bad_bounds_raise():
    with pytest.raises(InputError, match="fraction"):
        midpoint_radius([1.0, 0.0, 0.0], fraction=1.2)
    with pytest.raises(InputError, match="angle_bound"):
        midpoint_radius([1.0, 0.0, 0.0], angle_bound=-0.1)
    with pytest.raises(InputError, match="measured"):
        midpoint_radius([1.0, 0.0], fraction=0.1)
    # no bound -> degenerate box at the measurement, batched shape kept
    mid, rad = midpoint_radius(np.ones((4, 3)))
    assert mid.shape == (4, 3) and np.all(rad == 0)
