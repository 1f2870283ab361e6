"""Time (JD, GMST) and frame conversions."""

from __future__ import annotations

import datetime as dt

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adcskit.environment import (
    WGS84_A,
    as_utc,
    decimal_year,
    ecef_to_eci,
    ecef_to_geocentric,
    ecef_to_geodetic,
    eci_to_ecef,
    eci_to_ecef_matrix,
    enu_to_ecef_matrix,
    geocentric_to_ecef,
    geodetic_to_ecef,
    gmst,
    julian_date,
    ned_to_ecef_matrix,
    utc_times,
)
from adcskit.errors import InputError, InputTypeError


def test_julian_date_vallado_example_3_4():
    # Vallado (2013) Example 3-4: 1996-10-26 14:20:00 UT -> JD 2450383.09722222 (printed to 8
    # decimals; float64 JD resolves ~1e-9 day here).
    assert julian_date("1996-10-26T14:20:00") == pytest.approx(2450383.09722222, abs=1e-8)


def test_gmst_vallado_example_3_5():
    # Vallado (2013) Example 3-5: 1992-08-20 12:14:00 UT1 -> GMST = 152.578787810 deg.
    # Tolerance 1e-6 deg: the book evaluates T from a float JD (its rounding ~1e-7 deg).
    assert np.degrees(gmst("1992-08-20T12:14:00")) == pytest.approx(152.578787810, abs=1e-6)


def test_gmst_rate_is_sidereal():
    # Closed form: dGMST/dt = 1.00273790935 rev/day (Vallado eq. 3-40 omega_earth).
    t = utc_times("2024-05-01T00:00:00", [0.0, 3600.0])
    d = np.mod(np.diff(gmst(t))[0], 2 * np.pi)
    assert d == pytest.approx(2 * np.pi * 1.00273790935 / 24.0, rel=1e-9)


def test_time_inputs_equivalent():
    iso = as_utc("2024-01-01T06:00:00")
    assert as_utc(dt.datetime(2024, 1, 1, 6)) == iso
    aware = dt.datetime(2024, 1, 1, 7, tzinfo=dt.timezone(dt.timedelta(hours=1)))
    assert as_utc(aware) == iso
    assert as_utc(np.datetime64("2024-01-01T06:00")) == iso
    assert as_utc("2024-01-01T06:00:00Z") == iso
    assert as_utc([aware, "2024-01-01T06:00"]).shape == (2,)
    assert decimal_year("2025-01-01") == pytest.approx(2025.0)
    assert decimal_year("2024-07-02T00:00") == pytest.approx(2024.5, abs=1.5 / 366)


@pytest.mark.parametrize("bad", [2460000.5, [1.0, 2.0], "not a date", ["2024-01-01", "NaT"]])
def test_bad_times_raise_naming_parameter(bad):
    with pytest.raises((InputError, InputTypeError), match="times"):
        gmst(bad)


vec3 = st.lists(st.floats(-5e7, 5e7, allow_nan=False), min_size=3, max_size=3)


@settings(max_examples=60, deadline=None)
@given(vec3, st.integers(0, 3_000_000_000))
def test_eci_ecef_round_trip(v, seconds):
    t = np.datetime64("2000-01-01T00:00:00", "ns") + np.timedelta64(seconds, "s")
    r = np.array(v)
    back = ecef_to_eci(eci_to_ecef(r, t), t)
    assert np.allclose(back, r, rtol=0, atol=1e-8 * (1 + np.linalg.norm(r)))
    # rotation about z only: z component and norm preserved
    e = eci_to_ecef(r, t)
    assert e[2] == pytest.approx(r[2], abs=1e-9 * (1 + abs(r[2])))
    assert np.linalg.norm(e) == pytest.approx(np.linalg.norm(r), rel=1e-12, abs=1e-9)


def test_eci_ecef_batched_matches_single_and_greenwich():
    t = utc_times("2024-01-01", np.arange(5) * 1000.0)
    r = np.random.default_rng(0).normal(size=(5, 3)) * 7e6
    batch = eci_to_ecef(r, t)
    single = np.array([eci_to_ecef(r[i], t[i]) for i in range(5)])
    assert np.allclose(batch, single, atol=1e-6)
    # The ECEF x axis (Greenwich) is at right ascension GMST in ECI.
    g = gmst(t[0])
    x_eci = ecef_to_eci([1.0, 0.0, 0.0], t[0])
    assert np.allclose(x_eci, [np.cos(g), np.sin(g), 0.0], atol=1e-15)
    assert eci_to_ecef_matrix(t).shape == (5, 3, 3)


def test_eci_ecef_shape_mismatch_raises():
    with pytest.raises(InputError, match="times"):
        eci_to_ecef(np.zeros((4, 3)), utc_times("2024-01-01", [0.0, 1.0]))
    with pytest.raises(InputError, match="r_eci"):
        eci_to_ecef(np.zeros((4, 2)), "2024-01-01")


@settings(max_examples=80, deadline=None)
@given(st.floats(-np.pi / 2, np.pi / 2), st.floats(-np.pi, np.pi), st.floats(-5e3, 2e6))
def test_geodetic_round_trip(lat, lon, h):
    r = geodetic_to_ecef(lat, lon, h)
    lat2, lon2, h2 = ecef_to_geodetic(r)
    # 1e-9 rad ~ 6 mm on the surface; height to 1e-5 m (Bowring, five iterations).
    assert lat2 == pytest.approx(lat, abs=1e-9)
    if abs(lat) < np.pi / 2 - 1e-6:
        assert np.cos(lon2 - lon) == pytest.approx(1.0, abs=1e-12)
    assert h2 == pytest.approx(h, abs=1e-5)


def test_geodetic_known_points():
    # WGS-84 (NIMA TR8350.2): equator/Greenwich at h=0 is x = a; pole at z = b = a(1-f).
    assert np.allclose(geodetic_to_ecef(0.0, 0.0, 0.0), [WGS84_A, 0, 0])
    assert geodetic_to_ecef(np.pi / 2, 0.0, 0.0)[2] == pytest.approx(6356752.314245, abs=1e-5)
    with pytest.raises(InputError, match="lat"):
        geodetic_to_ecef(2.0, 0.0)


def test_geocentric_round_trip():
    r = np.array([[1e6, -2e6, 3e6], [7e6, 0.0, -1.0]])
    rad, th, ph = ecef_to_geocentric(r)
    assert np.allclose(geocentric_to_ecef(rad, th, ph), r, atol=1e-8)
    with pytest.raises(InputError, match="r_ecef"):
        ecef_to_geocentric([0.0, 0.0, 0.0])


def test_enu_ned_matrices():
    lat, lon = np.radians(52.0), np.radians(-1.5)
    M = enu_to_ecef_matrix(lat, lon)
    N = ned_to_ecef_matrix(lat, lon)
    for X in (M, N):
        assert np.allclose(X.T @ X, np.eye(3), atol=1e-15)
        assert np.linalg.det(X) == pytest.approx(1.0)
    # Up is the ellipsoid normal: parallel to the geodetic position direction gradient, i.e.
    # equal to the direction of r(h+1) - r(h).
    up = geodetic_to_ecef(lat, lon, 1.0) - geodetic_to_ecef(lat, lon, 0.0)
    assert np.allclose(M[:, 2], up / np.linalg.norm(up), atol=1e-12)
    assert np.allclose(N[:, 2], -M[:, 2]) and np.allclose(N[:, 0], M[:, 1])
    assert enu_to_ecef_matrix(np.zeros(4), np.zeros(4)).shape == (4, 3, 3)


def test_state_transform_earth_fixed_point_and_round_trip():
    # A point fixed on the rotating Earth has zero ECEF velocity; its ECI velocity is
    # omega x r (transport theorem). GMST's rate (1.00273790935 rev/day) and WGS-84's omega
    # differ by 5e-12 relative: 1e-6 m/s tolerance.
    from adcskit.environment import EARTH_ROTATION_RATE, ecef_to_eci_state, eci_to_ecef_state

    t = utc_times("2024-02-01", np.arange(4) * 900.0)
    r_ecef = np.tile(geodetic_to_ecef(0.3, 1.2, 100.0), (4, 1))
    r_eci, v_eci = ecef_to_eci_state(r_ecef, np.zeros((4, 3)), t)
    assert np.allclose(np.linalg.norm(v_eci, axis=1), EARTH_ROTATION_RATE * np.hypot(*r_ecef[0, :2]),
                       rtol=1e-12)
    # finite difference of the ECI track agrees with the transformed velocity
    t2 = utc_times("2024-02-01", [-0.5, 0.5])
    r2 = ecef_to_eci(np.tile(r_ecef[0], (2, 1)), t2)
    assert np.allclose(r2[1] - r2[0], v_eci[0], atol=1e-6)
    r_back, v_back = eci_to_ecef_state(r_eci, v_eci, t)
    assert np.allclose(r_back, r_ecef, atol=1e-7) and np.allclose(v_back, 0.0, atol=1e-9)
