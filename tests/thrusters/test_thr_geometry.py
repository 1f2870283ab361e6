"""Geometry: torque matrix, S3 eq. 4, controllability (positive span)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adcskit.errors import InputError
from adcskit.thrusters import (
    Thruster,
    ThrusterSet,
    allocate,
    angles_from_direction,
    check_controllability,
    direction_from_angles,
    torque_matrix,
)

# S3 §6, reference layout of Servidia & Sanchez Pena (S3 ref. [6]) as printed
A_REF = np.array([[-1, 1, -1, 1, 0, 0], [0, 0, 0, 0, 1, -1], [-1, 1, 1, -1, 0, 0]], float)


def test_hand_computed_torque_thruster_on_plus_x_pointing_minus_y():
    # r = (1, 0, 0) m, d = (0, -1, 0): r x d = (0, 0, -1) N m per N (right-hand rule, by hand)
    ts = ThrusterSet(positions=[[1.0, 0, 0]], directions=[[0, -1.0, 0]])
    np.testing.assert_allclose(ts.torque_matrix()[:, 0], [0.0, 0.0, -1.0], atol=1e-15)
    np.testing.assert_allclose(ts.force_matrix()[:, 0], [0.0, -1.0, 0.0])
    assert ts.lever_arms()[0] == pytest.approx(1.0)


def test_hand_computed_torque_with_offset_com():
    # corner (1, 1, 1), force -X, CoM at (0, 0, 1): r = (1, 1, 0); r x (-1, 0, 0) = (0, 0, 1)
    ts = ThrusterSet(positions=[[1.0, 1, 1]], directions=[[-2.0, 0, 0]], com=[0, 0, 1.0])
    np.testing.assert_allclose(ts.torque_matrix()[:, 0], [0.0, 0.0, 1.0], atol=1e-15)


@settings(max_examples=200, deadline=None)
@given(
    st.floats(-2 * np.pi, 2 * np.pi), st.floats(-2 * np.pi, 2 * np.pi),
    st.lists(st.floats(-1, 1), min_size=3, max_size=3),
)
def test_s3_eq4_equals_r_cross_d(alpha, beta, r):
    rx, ry, rz = r
    sa, ca, sb, cb = np.sin(alpha), np.cos(alpha), np.sin(beta), np.cos(beta)
    # S3 eq. 4 exactly as printed
    eq4 = np.array([ry * sb * ca - rz * sa, rz * ca * cb - rx * ca * sb, rx * sa - ry * ca * cb])
    d = direction_from_angles(alpha, beta)
    assert np.linalg.norm(d) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(torque_matrix([r], [d])[:, 0], eq4, atol=1e-12)
    t = Thruster.from_angles(r, alpha, beta)
    np.testing.assert_allclose(np.cross(t.position, t.direction), eq4, atol=1e-12)


def test_angles_round_trip():
    rng = np.random.default_rng(3)
    d = rng.normal(size=(50, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    a, b = angles_from_direction(d)
    np.testing.assert_allclose(direction_from_angles(a, b), d, atol=1e-12)


def test_isp_of_s3_table5():
    # S3 Table 5: 10 N, 3.5 g/s, Isp 2845 N s/kg; 10/0.0035 = 2857 (0.4 % rounding in the table)
    t = Thruster(position=[1, 0, 0], direction=[-1, 0, 0])
    assert t.exhaust_velocity == pytest.approx(2845, rel=5e-3)  # S3 Table 5 "Isp" 2845 N s/kg
    assert t.isp_s == pytest.approx(2845 / 9.80665, rel=5e-3)  # the same in seconds


def test_batched_torque_matrix_shape():
    rng = np.random.default_rng(0)
    r, d = rng.normal(size=(7, 5, 3)), rng.normal(size=(7, 5, 3))
    A = torque_matrix(r, d)
    assert A.shape == (7, 3, 5)
    np.testing.assert_allclose(A[3], np.cross(r[3], d[3]).T)


def test_reference_layout_is_controllable():
    c = check_controllability(A_REF)
    assert c.success and c.rank == 3 and c.margin > 0.5


def test_tetrahedron_controllable_and_three_vectors_not():
    tet = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float).T
    assert check_controllability(tet).success
    # three independent vectors span R^3 but not positively
    c = check_controllability(A_REF[:, [0, 2, 4]])
    assert not c.success and c.rank == 3
    assert "cannot be produced" in c.message
    # the reported direction really is unreachable with forces >= 0 (independent check: LP)
    res = allocate(A_REF[:, [0, 2, 4]], 5.0 * c.unreachable, method="lp-min-fuel", f_max=1e6)
    assert not res.feasible


def test_rank_deficient_layout():
    planar = np.array([[1, -1, 0, 0], [0, 0, 1, -1], [0, 0, 0, 0]], float)
    c = check_controllability(planar)
    assert not c.success and c.rank == 2
    np.testing.assert_allclose(np.abs(c.unreachable), [0, 0, 1], atol=1e-12)
    assert "rank 2" in c.message


def test_validation_messages():
    with pytest.raises(InputError, match="directions"):
        ThrusterSet(positions=[[1, 0, 0]], directions=[[0, 0, 0]])
    with pytest.raises(InputError, match="f_max"):
        Thruster(position=[1, 0, 0], direction=[1, 0, 0], f_max=-1)
    with pytest.raises(InputError, match=r"shape \(3, n\)"):
        check_controllability(np.ones((2, 4)))
