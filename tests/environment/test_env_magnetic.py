"""Geomagnetic field: dipole and IGRF-14 (ppigrf) in ECI."""

from __future__ import annotations

import datetime as dt

import numpy as np
import ppigrf
import pytest

from adcskit.environment import (
    circular_orbit,
    dipole_coefficients,
    ecef_to_eci,
    ecef_to_geocentric,
    eci_to_ecef,
    enu_to_ecef_matrix,
    geodetic_to_ecef,
    magnetic_field,
    utc_times,
)
from adcskit.errors import InputError

EPOCH = "2024-01-01T00:00:00"


@pytest.fixture(scope="module")
def s0_day():
    # S0 scenario orbit (800 km, 75 deg, RAAN 0) sampled every 30 s for one day.
    st = circular_orbit(800e3, np.radians(75.0), 0.0, 0.0, np.arange(0, 86400, 30.0), epoch=EPOCH)
    return st, magnetic_field(st.r, st.times, "dipole"), magnetic_field(st.r, st.times, "igrf")


def test_igrf_matches_ppigrf_geodetic_at_known_location():
    # Bergen (ppigrf's README location: 60.39299 N, 5.32415 E) at 0 and 800 km, 2024-01-01.
    # Our path (geodetic -> ECEF -> ECI -> field -> ECEF -> ENU) against ppigrf.igrf's direct
    # geodetic call; the only difference is round-off in the two coordinate conversions, so
    # 1e-6 relative.
    lat, lon = np.radians(60.39299), np.radians(5.32415)
    for h in (0.0, 800e3):
        r_ecef = geodetic_to_ecef(lat, lon, h)
        B_eci = magnetic_field(ecef_to_eci(r_ecef, EPOCH), EPOCH, "igrf")
        B_enu = enu_to_ecef_matrix(lat, lon).T @ eci_to_ecef(B_eci, EPOCH)
        Be, Bn, Bu = ppigrf.igrf(np.degrees(lon), np.degrees(lat), h / 1e3, dt.datetime(2024, 1, 1))
        ref = np.array([Be[0], Bn[0], Bu[0]]).ravel() * 1e-9
        assert np.allclose(B_enu, ref, rtol=0, atol=1e-6 * np.linalg.norm(ref))
    # Physical sanity at Bergen's surface: ~51 uT.
    Bs = ppigrf.igrf(5.32415, 60.39299, 0.0, dt.datetime(2024, 1, 1))
    assert 48e3 < np.linalg.norm([b[0] for b in Bs]) < 54e3


def test_dipole_is_igrf_degree_one():
    # The dipole model is IGRF's n = 1 term exactly: compare with ppigrf.igrf_gc(max_degree=1).
    rng = np.random.default_rng(3)
    r_ecef = rng.normal(size=(20, 3))
    r_ecef *= (6.8e6 + 1e6 * rng.random((20, 1))) / np.linalg.norm(r_ecef, axis=1, keepdims=True)
    B = eci_to_ecef(magnetic_field(ecef_to_eci(r_ecef, EPOCH), EPOCH, "dipole"), EPOCH)
    rad, th, ph = ecef_to_geocentric(r_ecef)
    Br, Bt, Bp = ppigrf.igrf_gc(rad / 1e3, np.degrees(th), np.degrees(ph), dt.datetime(2024, 1, 1),
                                max_degree=1)
    r_hat = r_ecef / rad[:, None]
    ph_hat = np.stack([-np.sin(ph), np.cos(ph), np.zeros_like(ph)], axis=1)
    assert np.allclose(np.sum(B * r_hat, 1), Br[0] * 1e-9, rtol=1e-9, atol=1e-15)
    assert np.allclose(np.sum(B * ph_hat, 1), Bp[0] * 1e-9, rtol=1e-9, atol=1e-15)
    # IGRF-14 2025.0 degree-1 coefficients (Alken et al. 2024): g10 = -29350.0,
    # g11 = -1410.3, h11 = 4545.5 nT.
    assert np.allclose(dipole_coefficients("2025-01-01"), [-29350.0, -1410.3, 4545.5], atol=0.05)


def test_leo_magnitudes(s0_day):
    # At 800 km the field is ~17-46 uT: equatorial surface ~30 uT scaled by (6371/7171)^3 ~ 0.70
    # is ~21 uT, twice that at the poles; the South Atlantic Anomaly lowers the minimum.
    _, Bd, Bi = s0_day
    for B in (Bd, Bi):
        n = np.linalg.norm(B, axis=1)
        assert 15e-6 < n.min() and n.max() < 50e-6


def test_dipole_vs_igrf_agreement(s0_day):
    # The dipole carries ~90 % of the field's power; at 800 km the higher degrees make a typical
    # (median) vector difference of ~20 % and a worst case (South Atlantic Anomaly) up to ~65 %.
    _, Bd, Bi = s0_day
    rel = np.linalg.norm(Bd - Bi, axis=1) / np.linalg.norm(Bi, axis=1)
    assert np.median(rel) < 0.3 and rel.max() < 0.8
    ratio = np.linalg.norm(Bd, axis=1) / np.linalg.norm(Bi, axis=1)
    # Magnitudes agree to a few % typically; the dipole has no South Atlantic Anomaly, where it
    # overestimates |B| by up to ~65 %.
    assert 0.9 < np.median(ratio) < 1.1 and 0.6 < ratio.min() and ratio.max() < 1.8


def test_vectorised_over_time_matches_single_calls(s0_day):
    st, Bd, Bi = s0_day
    idx = [0, 1000, 2879]
    for i in idx:
        assert np.allclose(magnetic_field(st.r[i], st.times[i], "igrf"), Bi[i], rtol=1e-12, atol=0)
        assert np.allclose(magnetic_field(st.r[i], st.times[i], "dipole"), Bd[i], rtol=1e-12, atol=0)
    # Spanning two UTC days: each sample uses its own day's coefficients.
    t = utc_times("2024-01-01T23:59:00", [0.0, 120.0])
    r = np.array([[7e6, 0, 0], [7e6, 0, 0]])
    B2 = magnetic_field(r, t, "igrf")
    assert np.allclose(B2[1], magnetic_field(r[1], t[1], "igrf"))


def test_field_rotates_with_earth():
    # Within one UTC day the model's coefficients are fixed, so a fixed ECEF point sees a
    # constant ECEF field: the ECI field just turns with GMST.
    t = utc_times("2024-03-01T01:00:00", [0.0, 3600.0])
    r_ecef = np.array([6.9e6, 1.0e6, 2.0e6])
    B_ecef = [eci_to_ecef(magnetic_field(ecef_to_eci(r_ecef, ti), ti, "igrf"), ti) for ti in t]
    assert np.allclose(B_ecef[0], B_ecef[1], rtol=1e-12, atol=1e-18)


def test_bad_inputs():
    r = [7e6, 0.0, 0.0]
    with pytest.raises(InputError, match="model must be one of 'dipole', 'igrf'"):
        magnetic_field(r, EPOCH, "wmm")
    with pytest.raises(InputError, match="r_eci"):
        magnetic_field([7000.0, 0.0, 0.0], EPOCH)  # km by mistake
    with pytest.raises(InputError, match="times must lie in IGRF-14"):
        magnetic_field(r, "2031-01-01")
    with pytest.raises(InputError, match="times"):
        magnetic_field(np.zeros((3, 3)) + 7e6, utc_times(EPOCH, [0.0, 1.0]))
