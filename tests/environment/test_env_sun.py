"""Sun direction (Vallado 2013, Alg. 29)."""

from __future__ import annotations

import numpy as np
import pytest

from adcskit.environment import AU, sun_direction, sun_position, utc_times
from adcskit.errors import InputTypeError


def _angle_deg(a, b):
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    return np.degrees(np.arccos(np.clip(np.sum(a * b, axis=-1), -1.0, 1.0)))


def test_vallado_example_5_1():
    # Vallado (2013), Example 5-1: 2006-04-02 00:00 UTC, r_sun = [0.9771945, 0.1924424,
    # 0.0834308] AU = [146186178, 28789122, 12481127] km (MOD), RA 11.140899 deg, dec
    # 4.788425 deg. The same algorithm, so only the book's 7-digit rounding separates us:
    # tolerance 1e-3 deg (10x below the algorithm's stated 0.01 deg accuracy).
    t = "2006-04-02T00:00:00"
    book_au = np.array([0.9771945, 0.1924424, 0.0834308])
    assert _angle_deg(sun_direction(t), book_au) < 1e-3
    s = sun_direction(t)
    assert np.degrees(np.arctan2(s[1], s[0])) == pytest.approx(11.140899, abs=1e-3)
    assert np.degrees(np.arcsin(s[2])) == pytest.approx(4.788425, abs=1e-3)
    # distance: book 0.9994 AU level agreement (5e-6 AU is the book's rounding)
    assert np.linalg.norm(sun_position(t)) / AU == pytest.approx(np.linalg.norm(book_au), abs=5e-6)


def test_equinox_and_solstice_declination():
    # USNO "Earth's Seasons" 2024: March equinox 2024-03-20 03:06 UTC (declination 0) and
    # June solstice 2024-06-20 20:51 UTC (declination = obliquity 23.436 deg). Tolerance 0.01
    # deg = the algorithm's accuracy (Vallado 2013, Alg. 29).
    s = sun_direction(["2024-03-20T03:06", "2024-06-20T20:51"])
    dec = np.degrees(np.arcsin(s[:, 2]))
    assert dec[0] == pytest.approx(0.0, abs=0.01)
    assert dec[1] == pytest.approx(23.4361, abs=0.01)


def test_unit_vectors_batched_and_annual_motion():
    t = utc_times("2024-01-01", np.arange(0, 366) * 86400.0)
    s = sun_direction(t)
    assert s.shape == (366, 3)
    assert np.allclose(np.linalg.norm(s, axis=1), 1.0, atol=1e-15)
    # The Sun moves ~0.9856 deg/day along the ecliptic (360 deg / 365.2422 days), modulated by
    # the eccentricity (0.953..1.019 deg/day, perihelion in January).
    step = _angle_deg(s[1:], s[:-1])
    assert 0.95 < step.min() and step.max() < 1.025
    assert np.allclose(sun_direction(t[10]), s[10])
    # Distance: perihelion ~0.983 AU (early January), aphelion ~1.017 AU (early July).
    d = np.linalg.norm(sun_position(t), axis=1) / AU
    assert d.min() == pytest.approx(0.9833, abs=5e-4) and d.max() == pytest.approx(1.0167, abs=5e-4)


def test_numbers_rejected():
    with pytest.raises(InputTypeError, match="times"):
        sun_direction(2451545.0)


def test_in_shadow_cylindrical_fraction():
    # Closed form: for an orbit plane containing the Sun line (beta angle 0), the cylindrical
    # shadow covers the arc |u - pi| < arcsin(R / a): fraction arcsin(R/a) / pi (Vallado 2013,
    # sec. 5.3). Build that orbit around the Sun direction of the epoch.
    from adcskit.environment import R_EARTH, in_shadow

    t0 = np.datetime64("2024-03-20T03:06", "ns")
    s = sun_direction(t0)
    z = np.array([0.0, 0.0, 1.0])
    p = np.cross(s, z)
    p /= np.linalg.norm(p)
    a = R_EARTH + 800e3
    u = np.linspace(0, 2 * np.pi, 36000, endpoint=False)
    r = a * (np.outer(np.cos(u), s) + np.outer(np.sin(u), p))
    shadow = in_shadow(r, t0)
    assert shadow.mean() == pytest.approx(np.arcsin(R_EARTH / a) / np.pi, abs=2 / 36000)
    assert not shadow[0] and shadow[18000]  # sunward point lit, anti-sun point dark
    assert in_shadow(r[18000], t0).shape == ()
