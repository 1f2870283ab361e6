"""Circular, Keplerian and SGP4 orbits."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from adcskit.environment import (
    MU_EARTH,
    R_EARTH,
    KeplerOrbit,
    circular_orbit,
    elements_to_rv,
    kepler_orbit,
    rv_to_elements,
    sgp4_orbit,
    solve_kepler,
)
from adcskit.errors import InputError

S0_INC = np.radians(75.0)  # S0 orbit scenario: 800 km circular, inclination 75 deg, RAAN 0


def test_circular_closed_forms():
    t = np.linspace(0.0, 20000.0, 2001)
    st_ = circular_orbit(800e3, S0_INC, 0.3, 0.2, t)
    a = R_EARTH + 800e3
    n = np.sqrt(MU_EARTH / a**3)
    rn = np.linalg.norm(st_.r, axis=1)
    vn = np.linalg.norm(st_.v, axis=1)
    # Closed forms to rounding: |r| = a, |v| = sqrt(mu/a), r.v = 0.
    assert np.allclose(rn, a, rtol=1e-14)
    assert np.allclose(vn, np.sqrt(MU_EARTH / a), rtol=1e-14)
    assert np.max(np.abs(np.sum(st_.r * st_.v, axis=1))) < 1e-6 * a * vn[0]
    # Angular momentum along [sin i sin raan, -sin i cos raan, cos i] (Vallado eq. 2-xx, W).
    h = np.cross(st_.r, st_.v)
    W = np.array([np.sin(S0_INC) * np.sin(0.3), -np.sin(S0_INC) * np.cos(0.3), np.cos(S0_INC)])
    assert np.allclose(h / np.linalg.norm(h, axis=1, keepdims=True), W, atol=1e-14)
    # Period 2 pi / n: back to the start.
    T = 2 * np.pi / n
    st_T = circular_orbit(800e3, S0_INC, 0.3, 0.2, [0.0, T])
    assert np.allclose(st_T.r[1], st_T.r[0], atol=1e-6)
    # Velocity is the time derivative of position (central difference, O(dt^2) ~ 1e-6 m/s).
    dt = 0.01
    rp = circular_orbit(800e3, S0_INC, 0.3, 0.2, [5.0 - dt, 5.0 + dt]).r
    assert np.allclose((rp[1] - rp[0]) / (2 * dt), circular_orbit(800e3, S0_INC, 0.3, 0.2, 5.0).v[0],
                       atol=1e-4)


def test_circular_unpacks_and_times():
    r, v = circular_orbit(800e3, S0_INC, 0.0, 0.0, np.arange(3.0))
    assert r.shape == v.shape == (3, 3)
    st_ = circular_orbit(800e3, S0_INC, 0.0, 0.0, [0.0, 60.0], epoch="2024-01-01")
    assert st_.times[1] == np.datetime64("2024-01-01T00:01:00", "ns")
    assert st_.success and st_.to_dict()["epoch"].startswith("2024-01-01")
    with pytest.raises(InputError, match="epoch"):
        circular_orbit(800e3, S0_INC, 0.0, 0.0, [0.0]).times  # noqa: B018


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"altitude": -1.0}, "altitude"),
        ({"inclination": np.radians(200)}, "inclination"),
        ({"raan": np.nan}, "raan"),
        ({"t": [[0.0, 1.0]]}, "t"),
        ({"t": [0.0, np.inf]}, "t"),
    ],
)
def test_circular_bad_inputs(kwargs, name):
    args = {"altitude": 800e3, "inclination": S0_INC, "raan": 0.0, "arg_lat0": 0.0, "t": [0.0]}
    args.update(kwargs)
    with pytest.raises(InputError, match=name):
        circular_orbit(**args)


def test_kepler_equals_circular_for_zero_eccentricity():
    # Two independent closed forms must agree when e = 0 (argp = 0, M0 = u0).
    t = np.linspace(0, 7000, 50)
    a = R_EARTH + 800e3
    k = kepler_orbit(a, 0.0, S0_INC, 0.4, 0.0, 1.1, t)
    c = circular_orbit(800e3, S0_INC, 0.4, 1.1, t)
    assert np.allclose(k.r, c.r, atol=1e-6) and np.allclose(k.v, c.v, atol=1e-9)


def test_kepler_conservation_and_numerical_integration():
    orb = KeplerOrbit(a=9000e3, e=0.3, inclination=0.9, raan=1.0, argp=2.0, mean_anomaly0=0.5)
    t = np.linspace(0.0, 1.5 * orb.period, 400)
    s = orb.propagate(t)
    rn = np.linalg.norm(s.r, axis=1)
    energy = 0.5 * np.sum(s.v**2, axis=1) - MU_EARTH / rn
    h = np.cross(s.r, s.v)
    # Energy -mu/2a and angular momentum sqrt(mu a (1-e^2)) are constants (Vallado eq. 1-xx);
    # rounding-level tolerances.
    assert np.allclose(energy, -MU_EARTH / (2 * orb.a), rtol=1e-12)
    assert np.allclose(np.linalg.norm(h, axis=1), np.sqrt(MU_EARTH * orb.a * (1 - 0.09)), rtol=1e-12)
    assert rn.min() == pytest.approx(orb.a * 0.7, rel=1e-4) and rn.max() == pytest.approx(orb.a * 1.3, rel=1e-4)
    # Independent oracle: integrate r'' = -mu r / |r|^3 with a tight RK tolerance.
    def f(_t, y):
        r = y[:3]
        return np.concatenate([y[3:], -MU_EARTH * r / np.linalg.norm(r) ** 3])

    sol = solve_ivp(f, (0, t[-1]), np.concatenate([s.r[0], s.v[0]]), t_eval=t, rtol=1e-11, atol=1e-6,
                    method="DOP853")
    assert np.max(np.linalg.norm(sol.y[:3].T - s.r, axis=1)) < 1.0  # metres after 1.5 orbits


@settings(max_examples=100, deadline=None)
@given(st.floats(-50.0, 50.0), st.floats(0.0, 0.99))
def test_kepler_equation_round_trip(M, e):
    E = solve_kepler(M, e)
    assert E - e * np.sin(E) == pytest.approx(M, abs=1e-12)


def test_kepler_vectorised_high_eccentricity():
    M = np.linspace(-20, 20, 10001)
    for e in (0.0, 0.5, 0.9, 0.999):
        E = solve_kepler(M, e)
        assert np.max(np.abs(E - e * np.sin(E) - M)) < 1e-12
        assert np.all(np.diff(E) > 0)  # monotone in M
    with pytest.raises(InputError, match="e must be in"):
        solve_kepler(0.1, 1.0)


@settings(max_examples=60, deadline=None)
@given(
    st.floats(6.6e6, 4.2e7), st.floats(0.001, 0.8), st.floats(0.05, 3.09), st.floats(0, 6.28),
    st.floats(0, 6.28), st.floats(0, 6.28),
)
def test_elements_round_trip(a, e, i, raan, argp, nu):
    r, v = elements_to_rv(a, e, i, raan, argp, nu)
    el = rv_to_elements(r, v)
    assert el["a"] == pytest.approx(a, rel=1e-9)
    assert el["e"] == pytest.approx(e, abs=1e-9)
    assert el["inclination"] == pytest.approx(i, abs=1e-9)
    for key, ref in (("raan", raan), ("argp", argp), ("true_anomaly", nu)):
        assert np.cos(el[key] - ref) == pytest.approx(1.0, abs=1e-12)
    r2, v2 = elements_to_rv(el["a"], el["e"], el["inclination"], el["raan"], el["argp"],
                            el["true_anomaly"])
    assert np.allclose(r2, r, rtol=0, atol=1e-5) and np.allclose(v2, v, rtol=0, atol=1e-8)


TLE_00005 = (
    "1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753",
    "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667",
)


def test_sgp4_vallado_verification_case():
    # Vallado et al. (2006), "Revisiting Spacetrack Report #3", verification output tcppver.out,
    # satellite 00005 at tsince = 0: r = [7022.46529266, -1400.08296755, 0.03995155] km,
    # v = [1.893841015, 6.405893759, 4.534807250] km/s (TEME). Tolerance 1 mm / 1e-6 m/s:
    # the printed precision.
    epoch = sgp4_orbit(*TLE_00005, "2000-06-27").epoch
    s = sgp4_orbit(*TLE_00005, [epoch, epoch + np.timedelta64(360, "m")])
    assert np.allclose(s.r[0], np.array([7022.46529266, -1400.08296755, 0.03995155]) * 1e3, atol=1e-3)
    assert np.allclose(s.v[0], np.array([1.893841015, 6.405893759, 4.534807250]) * 1e3, atol=1e-6)
    # tcppver.out, tsince = 360 min: r = [-7154.03120202, -3783.17682504, -3536.19412294] km.
    assert np.allclose(s.r[1], np.array([-7154.03120202, -3783.17682504, -3536.19412294]) * 1e3,
                       atol=1e-3)
    assert s.t[1] == pytest.approx(21600.0) and s.success


def test_sgp4_bad_tle():
    with pytest.raises(InputError, match="tle_line1"):
        sgp4_orbit("garbage", TLE_00005[1], "2000-06-28")
    with pytest.raises(InputError, match="tle_line2"):
        sgp4_orbit(TLE_00005[0], TLE_00005[0], "2000-06-28")
