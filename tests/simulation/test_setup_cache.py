"""The set-up caches of :func:`adcskit.simulation.simulate` (issue 24 item 1): a cached
environment table, allocation table or lag-coefficient vector is the same numbers as a fresh
computation, and every caller gets its own writable copy (the kernel takes plain writable
arrays; a read-only one would be another numba signature).

No kernel runs here: these are the Python set-up functions only.
"""

from __future__ import annotations

import numpy as np

from adcskit.simulation import ControllerSpec, OrbitSpec, Scenario, SimSpec, ThrusterSpec, core
from adcskit.thrusters import S3_REFERENCE_A


def _scenario(**kw) -> Scenario:
    # S0's LEO orbit (800 km, 75 deg, dipole field: the closed-loop study's Q2 scenario) for 20 s
    return Scenario(orbit=OrbitSpec(altitude_km=800.0, inclination_deg=75.0, magnetic_model="dipole"),
                    sim=SimSpec(dt=0.02, t_final=20.0, metrics_from_s=10.0), **kw)


def test_environment_table_cached_equals_fresh_and_is_a_private_copy():
    sc = _scenario()
    first, n2, n_orb = core._environment(sc, 1000, 5)
    first[:] = np.nan  # a caller that writes into its table must not change the next caller's
    again, n2b, n_orb_b = core._environment(sc, 1000, 5)
    fresh, n2c, n_orb_c = core._environment_table(sc.orbit, sc.sim.dt, 1000, 5)
    assert again.flags.writeable and again is not first
    np.testing.assert_array_equal(again, fresh)  # bit for bit: the same computation, kept
    assert (n2, n_orb) == (n2b, n_orb_b) == (n2c, n_orb_c)
    # another orbit, step or sampling is another table
    other, *_ = core._environment(sc.replace(orbit=sc.orbit.replace(altitude_km=801.0)), 1000, 5)
    assert not np.array_equal(other, fresh)


def test_allocation_table_cached_equals_fresh_and_is_a_private_copy():
    from adcskit.thrusters import allocate

    th = ThrusterSpec.from_torque_matrix(S3_REFERENCE_A)
    sc = _scenario(thrusters=th, controller=ControllerSpec(kind="schmitt", torque_level=(0.4, 0.4, 0.16),
                                                           allocation="lp-min-fuel"))
    A = S3_REFERENCE_A.astype(float)
    mask = np.ones(A.shape[1])
    t1 = core._allocation_table(sc, A, mask)
    t1[:] = -1.0
    t2 = core._allocation_table(sc, A, mask)
    assert t2.flags.writeable and t2 is not t1
    # the 27 Schmitt demands T * (sx, sy, sz), allocated directly (S3 eq. 5-7 as an LP)
    levels = np.array([-1.0, 0.0, 1.0])
    D = np.array([[x, y, z] for x in levels for y in levels for z in levels]) * np.array([0.4, 0.4, 0.16])
    np.testing.assert_array_equal(t2, allocate(A, D, method="lp-min-fuel", f_max=th.f_max).x)


def test_lag_coefficients_cached_are_read_only():
    c = core._lag_coefficients(0.01, 0.005)  # S4 Table 3: tau = 0.01 s; S4's 5 ms step
    assert not c.flags.writeable and core._lag_coefficients(0.01, 0.005) is c
