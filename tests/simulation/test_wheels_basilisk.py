"""Torque rods against Basilisk's ``MtbEffector`` and the wheel loop against ``mrpFeedback`` on a
non-isotropic body (issue 25, item 3): short versions of ``benchmarks/bench_basilisk_mtb.py`` and
``benchmarks/bench_basilisk_wheels.py`` (the same hub, orbit, dipole field, commands and laws).

Skipped when Basilisk (``bsk``, ``pip install 'adcskit[validate]'``) is not installed.
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("Basilisk")

pytestmark = pytest.mark.compile


@pytest.fixture(scope="module")
def bench(benchmark_script):
    return benchmark_script("bench_basilisk_mtb")


def test_open_loop_dipole_agrees_with_basilisk_mtb_effector(bench):
    # Issue 25 "done when": < 1 % of the rate range on open-loop histories. Measured with the
    # bench over 300 s at dt 0.1 s: 0.023 % (3.7e-6 rad/s; 0.006 % at dt 0.02 s: our m x B is
    # held over a step at the step-start attitude, MtbEffector's follows the RK4 stages). Here
    # 120 s (measured 0.043 % of a smaller range); the bound 0.2 % leaves a 4x margin over that
    # first-order step effect. The field models are the same formula (centred dipole, IGRF-14
    # degree 1): measured 1e-15 relative, 1e-12 bounds the rounding; the orbit (Basilisk's RK4 vs
    # our closed form) measured 1e-8 m, bound 1 m.
    r = bench.open_loop(120.0, 0.1, dt_check=False)
    assert r["rel_rate_diff"] < 2e-3
    assert r["max_field_rel_diff"] < 1e-12
    assert r["max_orbit_diff_m"] < 1.0
    assert r["rate_range_rad_s"] > 1e-3  # the rods really turned the body


def test_bdot_rate_history_agrees_with_basilisk(bench):
    # The same B-dot law (m = -k dB/dt, 1 Hz, largest component 0.2 A m^2) on both plants from
    # (2, -1.5, 1.5) deg/s: the rate norms stay within 1e-3 deg/s over 600 s (measured 2e-5 here,
    # 7.6e-5 deg/s over a whole orbit with the bench), while B-dot removes > 0.3 deg/s in that
    # time (measured 0.72 deg/s).
    r = bench.bdot(600.0, 0.1, 1.0)
    assert r["max_rate_norm_diff_deg_s"] < 1e-3
    rb = np.asarray(r["traces"]["basilisk_rate_deg_s"])
    assert rb[0] - rb[-1] > 0.3


def test_wheel_closed_loop_on_a_principal_axis_agrees_with_mrpfeedback(bench):
    # 12U hub diag(0.30, 0.27, 0.17), 20 deg about principal z: mrpFeedback with K = 4 J_z k,
    # P = J_z c and controlLawType 1 is our PD law (omega_n 0.1 rad/s, zeta 1) to first order
    # (sigma ~ q_e / 2). Measured (bench): settling 56 s on both, errors within 0.047 deg (the
    # MRP's q_e / (1 + q4) vs our q_e / 2, 0.8 % apart at 20 deg), wheel speeds within 2.3 rpm
    # of a 488 rpm range. Bounds: one 1 s trace sample of settling, 0.1 deg, 2 % of the range.
    import bench_basilisk_wheels as bw

    r = bw.closed_loop(150.0, 0.1, 0.5, inertia=(0.30, 0.27, 0.17), axis=(0.0, 0.0, 1.0), gain_inertia=0.17)
    assert abs(r["settling_time_s"]["basilisk"] - r["settling_time_s"]["adcskit"]) <= 1.0
    assert r["max_error_diff_deg"] < 0.1
    assert r["max_wheel_speed_diff_rpm"] < 0.02 * r["wheel_speed_range_rpm"]
