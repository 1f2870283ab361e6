"""Allocation: exactness of nnls / lp-min-fuel, S3's redistributed pseudo-inverse, infeasible demands."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adcskit.errors import InputError
from adcskit.thrusters import ALLOCATION_METHODS, allocate
from adcskit.thrusters.allocation import _rpi_layouts

A_REF = np.array([[-1, 1, -1, 1, 0, 0], [0, 0, 0, 0, 1, -1], [-1, 1, 1, -1, 0, 0]], float)


def _random_feasible(seed, n=8, N=30, f_max=10.0):
    rng = np.random.default_rng(seed)
    A = rng.uniform(-1.5, 1.5, size=(3, n))
    F_true = rng.uniform(0, f_max, size=(N, n))
    return A, F_true @ A.T, F_true


@pytest.mark.parametrize("method", ["nnls", "lp-min-fuel"])
@pytest.mark.parametrize("seed", range(5))
def test_exact_on_feasible_demands(method, seed):
    # issue 6: on any feasible demand nnls and lp-min-fuel reproduce the torque to 1e-9 relative
    A, M, _ = _random_feasible(seed)
    res = allocate(A, M, method=method, f_max=10.0)
    rel = res.error / np.linalg.norm(M, axis=1)
    assert rel.max() <= 1e-9
    assert res.feasible.all() and res.success
    assert np.all(res.x >= 0) and np.all(res.x <= 10.0)
    np.testing.assert_allclose(res.torque, res.x @ A.T)


def test_lp_uses_least_fuel():
    A, M, F_true = _random_feasible(11)
    lp = allocate(A, M, method="lp-min-fuel")
    nn = allocate(A, M, method="nnls")
    # LP optimum <= any feasible point: the generating forces and the nnls solution
    assert np.all(lp.x.sum(1) <= F_true.sum(1) + 1e-9)
    assert np.all(lp.x.sum(1) <= nn.x.sum(1) + 1e-9)


def test_pinv_redistribute_symmetric_layout_exact_and_minimal():
    # For opposite pairs (S3's symmetric case) the redistribution gives each pair's net force
    # to one thruster: exact and least fuel (LP optimum as the independent oracle).
    rng = np.random.default_rng(5)
    M = rng.uniform(-3, 3, size=(40, 3))
    pr = allocate(A_REF, M, method="pinv-redistribute")
    lp = allocate(A_REF, M, method="lp-min-fuel")
    assert pr.feasible.all()
    np.testing.assert_allclose(pr.x.sum(1), lp.x.sum(1), rtol=1e-9)


def test_pinv_redistribute_equals_pinv_when_no_bound_active():
    # S3 eq. 12: F = A^T (A A^T)^-1 M; choose M = A F0 with F0 well inside the bounds and in
    # the row space of A, so the pseudo-inverse is already admissible.
    rng = np.random.default_rng(2)
    A = rng.normal(size=(3, 6))
    y = rng.normal(size=3)
    A = A * np.sign(A.T @ y)  # flip columns so that F0 = A^T y > 0 (row space, in bounds)
    F0 = A.T @ y
    assert F0.min() > 0
    M = A @ F0
    res = allocate(A, M, method="pinv-redistribute", f_max=1e6)
    np.testing.assert_allclose(res.x, np.linalg.pinv(A) @ M, rtol=1e-9, atol=1e-9)


def test_pinv_redistribute_rank_deficient_pass_matches_lstsq():
    # two coplanar thrusters: the free set has rank 2, the Jacobi pseudo-inverse path is used
    A = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])
    M = np.array([2.0, 3.0, 5.0])  # the Z part is unreachable
    F, err = _rpi_layouts(A[None], M[None], np.array([10.0, 10.0]))
    np.testing.assert_allclose(F[0, 0], np.linalg.lstsq(A, M, rcond=None)[0], atol=1e-12)
    assert err[0, 0] == pytest.approx(5.0)


def test_pinv_redistribute_miss_on_random_layouts_is_measurable():
    # not exact in general (the study reports the size of the miss); errors are >= the exact
    # least-squares error of nnls on the same demands
    A, M, _ = _random_feasible(7, n=8, N=50)
    pr = allocate(A, M, method="pinv-redistribute")
    nn = allocate(A, M, method="nnls")
    assert np.all(pr.error >= nn.error - 1e-9)
    assert np.all(pr.x >= 0) and np.all(pr.x <= 10)


def test_infeasible_demands_handled():
    # 300 N m about X exceeds what A_REF can give (|A| <= 1 per thruster, 10 N): no exception,
    # feasible False, and lp-min-fuel reaches the least-squares torque (same as nnls).
    M = np.array([[300.0, -2.0, 1.0], [1.0, 1.0, 1.0]])
    for method in ALLOCATION_METHODS:
        res = allocate(A_REF, M, method=method)
        assert res.success
        assert not res.feasible[0] and res.feasible[1]
        assert res.status[0] == 1 and res.status[1] == 0
    lp = allocate(A_REF, M, method="lp-min-fuel")
    nn = allocate(A_REF, M, method="nnls")
    assert lp.error[0] == pytest.approx(nn.error[0], rel=1e-9)


def test_shapes_follow_the_demand():
    r1 = allocate(A_REF, [1.0, 0, 0], method="nnls")
    assert r1.x.shape == (6,) and r1.torque.shape == (3,) and np.ndim(r1.error) == 0
    r2 = allocate(A_REF, [[1.0, 0, 0]], method="nnls")
    assert r2.x.shape == (1, 6)


def test_inputs_not_modified_and_errors():
    A = A_REF.copy()
    M = np.array([1.0, 2.0, 3.0])
    allocate(A, M, method="lp-min-fuel")
    np.testing.assert_array_equal(A, A_REF)
    np.testing.assert_array_equal(M, [1.0, 2.0, 3.0])
    with pytest.raises(InputError, match="'pinv-redistribute', 'nnls', 'lp-min-fuel'"):
        allocate(A, M, method="pinv")
    with pytest.raises(InputError, match="f_max"):
        allocate(A, M, f_max=0.0)


@pytest.mark.parametrize("method", ["nnls", "lp-min-fuel"])
def test_exact_on_demands_at_the_bounds(method):
    # feasible demands generated by forces with many thrusters exactly at 0 or f_max: the
    # hardest feasible case (the solution sits on the boundary of the box)
    rng = np.random.default_rng(21)
    A = rng.uniform(-1.5, 1.5, size=(3, 6))
    F = rng.uniform(0, 10, size=(40, 6))
    F[rng.random(F.shape) < 0.4] = 0.0
    F[rng.random(F.shape) < 0.3] = 10.0
    M = F @ A.T
    res = allocate(A, M, method=method, f_max=10.0)
    assert (res.error <= 1e-9 * np.linalg.norm(M, axis=1) + 1e-12).all()


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(4, 12))
def test_lp_exact_and_no_more_fuel_than_any_feasible_point(seed, n):
    # property: for any layout and any feasible demand, lp-min-fuel is exact (1e-9 relative)
    # and its fuel is <= the fuel of the forces that generated the demand
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(3, n))
    F = rng.uniform(0, 10, size=n)
    M = A @ F
    if np.linalg.norm(M) < 1e-6:
        return
    res = allocate(A, M, method="lp-min-fuel", f_max=10.0)
    assert res.error <= 1e-9 * np.linalg.norm(M)
    assert res.x.sum() <= F.sum() + 1e-9


def test_allocate_uses_a_thruster_sets_own_force_limit():
    """Issue 16: a 1 N thruster set must never receive more than 1 N (the bare-matrix default is 10 N)."""
    from adcskit.errors import InputError
    from adcskit.thrusters import ThrusterSet

    pos = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]
    dirs = [[0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0]]
    ts = ThrusterSet(positions=pos, directions=dirs, f_max=1.0)
    big = [3.0, 0.0, 0.0]  # needs 1.5 N from each of two thrusters
    bare = allocate(ts.torque_matrix(), big, method="nnls")
    own = allocate(ts, big, method="nnls")
    assert bare.x.max() > 1.0  # the old trap: 10 N default
    assert own.x.max() <= 1.0 + 1e-12 and not bool(own.feasible)
    assert allocate(ts, big, method="nnls", f_max=1.0).x.max() <= 1.0 + 1e-12  # same value: fine
    with pytest.raises(InputError, match="conflicts"):
        allocate(ts, big, f_max=10.0)
