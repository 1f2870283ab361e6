"""The quaternion device helpers (adcskit.attitude._device) shared by the closed-loop
simulator and the MEKF kernels: against the public attitude algebra and scipy."""

import numba
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from adcskit.attitude import error_angle, quat_to_dcm
from adcskit.attitude._device import compose_rotvec, qerr, rotate

_unit = st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4).filter(lambda v: np.linalg.norm(v) > 0.1)
_vec = st.lists(st.floats(-10.0, 10.0), min_size=3, max_size=3)


@settings(max_examples=40, deadline=None)
@given(_unit, _vec)
def test_rotate_is_the_attitude_matrix(q, r):
    # A(q) r with A(q) of Markley & Crassidis (2014) eq. 2.125 (adcskit.attitude.quat_to_dcm);
    # two implementations, rounding-level agreement relative to |r|
    q = np.asarray(q) / np.linalg.norm(q)
    np.testing.assert_allclose(rotate(*q, *r), quat_to_dcm(q) @ np.asarray(r), rtol=0,
                               atol=1e-13 * (1.0 + np.linalg.norm(r)))


@settings(max_examples=40, deadline=None)
@given(_unit, _unit)
def test_qerr_angle_is_error_angle(a, b):
    # the error angle of q_a (x) q_b^-1 (adcskit.attitude.error_angle, 2 atan2 form): 1e-12 rad
    a = np.asarray(a) / np.linalg.norm(a)
    b = np.asarray(b) / np.linalg.norm(b)
    ex, ey, ez, ang = qerr(*a, *b)
    assert abs(ang - error_angle(a, b)) < 1e-12
    assert abs(np.linalg.norm([ex, ey, ez]) - ang) < 1e-12


@settings(max_examples=40, deadline=None)
@given(_unit, st.lists(st.floats(-1.5, 1.5), min_size=3, max_size=3))
def test_compose_rotvec_then_qerr_round_trip(q, rv):
    # dq(r) (x) q then the error rotation vector of the result against q gives r back
    # (|r| < pi); and A(dq (x) q) = A(dq) A(q) with A(dq) = scipy's from_rotvec(r).inv() (the
    # scalar-last convention of design.md). Tolerances: rounding of a few products, 1e-12.
    q = np.asarray(q) / np.linalg.norm(q)
    q = q if q[3] >= 0 else -q
    p = q.copy()
    compose_rotvec(p, *rv)
    np.testing.assert_allclose(qerr(*p, *q)[:3], rv, rtol=0, atol=1e-12)
    np.testing.assert_allclose(quat_to_dcm(p), Rotation.from_rotvec(rv).inv().as_matrix() @ quat_to_dcm(q),
                               rtol=0, atol=1e-12)


def test_same_bits_compiled_and_in_python():
    # one source, two targets: compiled into an njit caller, the helpers return the
    # plain-Python numbers bit for bit
    @numba.njit(cache=False)
    def compiled(q, r):
        p = q.copy()
        compose_rotvec(p, r[0], r[1], r[2])
        return rotate(q[0], q[1], q[2], q[3], r[0], r[1], r[2]), qerr(p[0], p[1], p[2], p[3], q[0], q[1], q[2], q[3]), p

    rng = np.random.default_rng(5)
    for _ in range(20):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        r = rng.normal(size=3)
        p = q.copy()
        compose_rotvec(p, *r)
        b, e, pc = compiled(q, r)
        assert b == rotate(*q, *r) and e == qerr(*p, *q)
        assert np.array_equal(pc, p)
