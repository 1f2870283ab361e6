"""Attitude algebra: closed forms, scipy agreement, round trips, properties (hypothesis).

Reference identities: Markley & Crassidis (2014) eq. 2.125 (A(q)), 2.82a (composition),
Schaub & Junkins (2018) eq. 3.154 (MRP DCM). Tolerances: 1e-12 is ~ 5000 ulp of the O(1)
entries, loose enough for a few dozen flops and tight enough to catch any sign error.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial.transform import Rotation

from adcskit import attitude as att
from adcskit.errors import InputError, InputTypeError

finite = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)
quat_st = arrays(np.float64, (4,), elements=finite).filter(lambda q: np.linalg.norm(q) > 1e-3)
vec_st = arrays(np.float64, (3,), elements=st.floats(-3.0, 3.0, allow_nan=False))
TOL = 1e-12


def test_identity_and_axis_rotation_closed_form():
    # A rotation of the frame by +90 deg about z maps reference x to body -y: b = A r.
    q = np.array([0, 0, np.sin(np.pi / 4), np.cos(np.pi / 4)])
    A = att.quat_to_dcm(q)
    np.testing.assert_allclose(A @ [1, 0, 0], [0, -1, 0], atol=1e-15)
    np.testing.assert_allclose(att.quat_to_dcm([0, 0, 0, 1]), np.eye(3), atol=0)
    np.testing.assert_allclose(att.euler_to_dcm([np.pi / 2, 0, 0], "ZYX"), A, atol=1e-15)


@settings(max_examples=200, deadline=None)
@given(quat_st)
def test_matches_scipy_and_round_trips(q):
    A = att.quat_to_dcm(q)
    np.testing.assert_allclose(A, Rotation.from_quat(q).inv().as_matrix(), atol=TOL)
    q2 = att.dcm_to_quat(A)
    assert q2[3] >= 0
    assert att.error_angle(q, q2) < 1e-7  # angle from |v| ~ sqrt(eps)-limited only near 0
    np.testing.assert_allclose(att.quat_to_dcm(q2), A, atol=TOL)
    np.testing.assert_allclose(att.quat_to_dcm(att.from_scipy(att.to_scipy(q))), A, atol=TOL)
    np.testing.assert_allclose(att.to_scipy(q).inv().as_matrix(), A, atol=TOL)


@settings(max_examples=200, deadline=None)
@given(quat_st, quat_st)
def test_composition_homomorphism(p, q):
    lhs = att.quat_to_dcm(att.quat_multiply(p, q))
    np.testing.assert_allclose(lhs, att.quat_to_dcm(p) @ att.quat_to_dcm(q), atol=TOL)
    np.testing.assert_allclose(att.quat_to_dcm(att.quat_inverse(q)), att.quat_to_dcm(q).T, atol=TOL)


@settings(max_examples=100, deadline=None)
@given(quat_st, quat_st)
def test_error_angle_matches_trace_formula(p, q):
    # S0's error metric: arccos((tr(A1^T A2) - 1)/2), evaluated with mpmath-free care away from 0/pi.
    A1, A2 = att.quat_to_dcm(p), att.quat_to_dcm(q)
    c = np.clip((np.trace(A1.T @ A2) - 1) / 2, -1, 1)
    ang = att.error_angle(p, q)
    if 1e-3 < ang < np.pi - 1e-3:
        assert abs(ang - np.arccos(c)) < 1e-9
    assert abs(att.error_angle(p, -p)) < 1e-7


def test_error_angle_accurate_near_zero_and_pi():
    for a in (1e-9, 1e-5, np.pi - 1e-9, np.pi):
        q = np.array([np.sin(a / 2), 0, 0, np.cos(a / 2)])
        assert abs(att.error_angle(q, [0, 0, 0, 1]) - a) < 1e-15 * max(1, a) + 1e-16


@settings(max_examples=100, deadline=None)
@given(quat_st)
def test_scalar_first_round_trip(q):
    qf = att.quat_to_scalar_first(q)
    np.testing.assert_allclose(att.quat_from_scalar_first(qf), q / np.linalg.norm(q), atol=1e-15)


def test_s0_exact_quaternion_is_scalar_first():
    # S0 eq. 9 (from Ahmed & Kerrigan): q_exact printed scalar-first; digest checked this.
    q_exact_sf = np.array([-0.9746, 0.0707, -0.2122, -0.0125])
    q = att.quat_from_scalar_first(q_exact_sf)
    np.testing.assert_allclose(q, [0.0707, -0.2122, -0.0125, -0.9746] / np.linalg.norm(q_exact_sf), atol=1e-15)


def test_dcm_to_quat_near_180_degrees_all_axes():
    rng = np.random.default_rng(0)
    axes = rng.normal(size=(500, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    for ang in (np.pi, np.pi - 1e-10, np.pi - 1e-4):
        q = np.column_stack([axes * np.sin(ang / 2), np.full(500, np.cos(ang / 2))])
        q2 = att.dcm_to_quat(att.quat_to_dcm(q))
        assert np.all(att.error_angle(q, q2) < 1e-7)
        np.testing.assert_allclose(att.quat_to_dcm(q2), att.quat_to_dcm(q), atol=TOL)
    # canonical sign on the 180-degree set: q4 == 0 and first non-zero component positive
    q180 = att.dcm_to_quat(np.diag([-1.0, -1.0, 1.0]))
    np.testing.assert_allclose(q180, [0, 0, 1, 0], atol=1e-15)


def test_batch_equals_loop():
    q = att.random_quat(50, rng=3)
    A = att.quat_to_dcm(q)
    assert A.shape == (50, 3, 3)
    for i in (0, 17, 49):
        np.testing.assert_array_equal(A[i], att.quat_to_dcm(q[i]))
    assert att.error_angle(q, q[0]).shape == (50,)
    assert isinstance(att.error_angle(q[0], q[1]), float)


def test_random_quat_is_seeded_and_uniform():
    a, b = att.random_quat(2000, rng=7), att.random_quat(2000, rng=7)
    np.testing.assert_array_equal(a, b)
    # Haar measure: each DCM entry has mean 0 and variance 1/3; 6-sigma bound on the mean.
    A = att.quat_to_dcm(a)
    assert np.all(np.abs(A.mean(axis=0)) < 6 * np.sqrt(1 / 3 / 2000))


@pytest.mark.parametrize("seq", att.EULER_SEQUENCES + ("321", "zyx"))
def test_euler_all_sequences_match_scipy_and_round_trip(seq):
    rng = np.random.default_rng(1)
    ang = rng.uniform(-1.2, 1.2, size=(200, 3))
    A = att.euler_to_dcm(ang, seq)
    s = seq.upper().translate(str.maketrans("123", "XYZ"))
    np.testing.assert_allclose(A, Rotation.from_euler(s, ang).inv().as_matrix(), atol=TOL)
    back = att.dcm_to_euler(A, seq)
    np.testing.assert_allclose(att.euler_to_dcm(back, seq), A, atol=1e-11)


def test_euler_gimbal_lock_still_reproduces_matrix():
    A = att.euler_to_dcm([0.3, np.pi / 2, -0.2], "ZYX")
    back = att.dcm_to_euler(A, "ZYX")
    np.testing.assert_allclose(att.euler_to_dcm(back, "ZYX"), A, atol=1e-9)


@settings(max_examples=200, deadline=None)
@given(quat_st)
def test_mrp_round_trips_and_dcm(q):
    s = att.quat_to_mrp(q)
    assert np.linalg.norm(s) <= 1 + 1e-12
    np.testing.assert_allclose(att.mrp_to_dcm(s), att.quat_to_dcm(q), atol=1e-11)
    assert att.error_angle(att.mrp_to_quat(s), q) < 1e-7
    if np.linalg.norm(s) > 1e-3:
        np.testing.assert_allclose(att.mrp_to_dcm(att.mrp_shadow(s)), att.quat_to_dcm(q), atol=1e-10)


def test_mrp_switch():
    s = np.array([[0.0, 0, 2.0], [0.0, 0.5, 0]])
    sw = att.mrp_switch(s)
    np.testing.assert_allclose(sw, [[0, 0, -0.5], [0, 0.5, 0]])
    np.testing.assert_allclose(att.mrp_to_dcm(sw), att.mrp_to_dcm(s), atol=1e-14)


@settings(max_examples=50, deadline=None)
@given(quat_st, vec_st)
def test_kinematics_match_dcm_derivative(q, w):
    # Ȧ = −[ω×] A (Markley & Crassidis eq. 3.19); central differences, error O(h²) ~ 1e-10.
    h = 1e-5
    q = q / np.linalg.norm(q)
    qd = att.quat_kinematics(q, w)
    dA = (att.quat_to_dcm(q + h * qd) - att.quat_to_dcm(q - h * qd)) / (2 * h)
    np.testing.assert_allclose(dA, -att.skew(w) @ att.quat_to_dcm(q), atol=1e-8 * (1 + np.abs(w).max() ** 2))
    s = att.quat_to_mrp(q)
    if np.linalg.norm(s) < 0.9:
        sd = att.mrp_kinematics(s, w)
        dC = (att.mrp_to_dcm(s + h * sd) - att.mrp_to_dcm(s - h * sd)) / (2 * h)
        np.testing.assert_allclose(dC, -att.skew(w) @ att.mrp_to_dcm(s), atol=1e-7 * (1 + np.abs(w).max() ** 2))
        np.testing.assert_allclose(att.mrp_b_matrix(s) @ w / 4, sd, atol=1e-15)
    np.testing.assert_allclose(att.xi_matrix(q) @ w / 2, qd, atol=1e-15)


def test_inputs_not_modified_and_normalised():
    q = np.array([0.0, 0.0, 0.0, 2.0])
    before = q.copy()
    np.testing.assert_allclose(att.quat_to_dcm(q), np.eye(3))
    np.testing.assert_array_equal(q, before)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: att.quat_to_dcm([0, 0, 0, 0]), "q must have non-zero norm"),
        (lambda: att.quat_to_dcm([1, 2, 3]), r"q must have shape \(4,\)"),
        (lambda: att.quat_to_dcm([np.nan, 0, 0, 1]), "q must be finite"),
        (lambda: att.dcm_to_quat(np.diag([1.0, 1.0, -1.0])), "A must be a rotation matrix"),
        (lambda: att.dcm_to_quat(2 * np.eye(3)), "A must be a rotation matrix"),
        (lambda: att.euler_to_dcm([0, 0, 0], "XXY"), "seq must be one of the 12 Euler sequences"),
        (lambda: att.quat_multiply(np.ones((3, 4)), np.ones((2, 4))), "same batch length"),
        (lambda: att.mrp_shadow([0, 0, 0]), "sigma must be non-zero"),
        (lambda: att.random_quat(0), r"n must be an integer in \[1, 100000000\]"),
    ],
)
def test_bad_input_raises_clear_error(call, match):
    with pytest.raises(InputError, match=match):
        call()


def test_from_scipy_type_error():
    with pytest.raises(InputTypeError, match="rotation must be a scipy"):
        att.from_scipy(np.eye(3))
