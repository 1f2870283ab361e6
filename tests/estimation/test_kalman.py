"""Tests of adcskit.estimation.kalman: closed-form scalar cases, DARE, the two forms."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
from hypothesis import given, settings
from hypothesis import strategies as st

from adcskit.errors import InputError
from adcskit.estimation import KalmanFilter, kalman_filter, simulate_linear


def _random_system(seed=3, n=4, m=2, p=2):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    A *= 0.95 / max(abs(np.linalg.eigvals(A)))  # stable, spectral radius 0.95
    B = rng.normal(size=(n, p))
    C = rng.normal(size=(m, n))
    Q = 0.1 * np.eye(n)
    R = np.diag([0.5, 2.0])[:m, :m]
    return A, B, C, Q, R


def test_scalar_first_step_closed_form():
    # Scalar filter, one step by hand (Simon 2006 eq. 5.19): S = P0 + r, K = P0/S,
    # P(0|0) = P0 r/(P0 + r), x(0|0) = x0 + K (y - x0), P(1|0) = a^2 P(0|0) + q.
    a, q, r, P0, x0, y0, u0, b = 0.9, 0.3, 2.0, 1.5, 0.2, 1.1, 0.7, 0.4
    res = kalman_filter([[a]], [[b]], [[1.0]], [[y0]], [[u0]], Q=q, R=r, x0=[x0], P0=P0)
    K = P0 / (P0 + r)
    xf = x0 + K * (y0 - x0)
    Pf = P0 * r / (P0 + r)
    # tolerance: a few ulps of O(1) numbers
    assert res.x[0, 0] == pytest.approx(xf, abs=1e-14)
    assert res.P[0, 0, 0] == pytest.approx(Pf, abs=1e-14)
    assert res.x_pred[1, 0] == pytest.approx(a * xf + b * u0, abs=1e-14)
    assert res.P_pred[1, 0, 0] == pytest.approx(a * a * Pf + q, abs=1e-14)
    assert res.innovations[0, 0] == pytest.approx(y0 - x0, abs=1e-15)
    assert res.S[0, 0, 0] == pytest.approx(P0 + r, abs=1e-14)


@pytest.mark.parametrize("form", ["predict-update", "predictor"])
def test_scalar_steady_state_riccati_closed_form(form):
    # Scalar predictor Riccati P = a^2 P r/(P + r) + q has the positive root of
    # P^2 + (r - a^2 r - q) P - q r = 0 (quadratic formula); the recursion contracts
    # geometrically, so 300 steps reach it to rounding (1e-10 relative).
    a, q, r = 0.95, 0.2, 1.3
    bq = r - a * a * r - q
    P_inf = (-bq + np.sqrt(bq * bq + 4 * q * r)) / 2
    y = np.zeros((300, 1))
    res = kalman_filter([[a]], np.zeros((1, 1)), [[1.0]], y, Q=q, R=r, P0=1.0, form=form)
    assert res.P_pred[-1, 0, 0] == pytest.approx(P_inf, rel=1e-10)


def test_matrix_steady_state_equals_scipy_dare():
    # Predictor covariance converges to the stabilising DARE solution (scipy oracle).
    A, B, C, Q, R = _random_system()
    P_dare = sla.solve_discrete_are(A.T, C.T, Q, R)
    y = np.zeros((400, C.shape[0]))
    res = kalman_filter(A, B, C, y, Q=Q, R=R, P0=np.eye(4), form="predictor")
    np.testing.assert_allclose(res.P_pred[-1], P_dare, rtol=1e-9, atol=1e-10)


def test_two_forms_agree():
    # The corrected S1 eq. 18 predictor and predict/update are the same filter: agreement
    # to 1e-10 (rounding accumulates over 200 steps of O(1) numbers).
    A, B, C, Q, R = _random_system()
    rng = np.random.default_rng(7)
    u = rng.normal(size=(200, 2))
    sim = simulate_linear(A, B, C, u, R=R, Q=Q, rng=rng)
    r1 = kalman_filter(A, B, C, sim.y, u, Q=Q, R=R, P0=2.0, form="predict-update")
    r2 = kalman_filter(A, B, C, sim.y, u, Q=Q, R=R, P0=2.0, form="predictor")
    for f in ("x", "P", "x_pred", "P_pred", "innovations", "S"):
        np.testing.assert_allclose(getattr(r1, f), getattr(r2, f), rtol=1e-10, atol=1e-10)
    assert r1.loglik == pytest.approx(r2.loglik, rel=1e-10)


def test_printed_eq18_predictor_without_process_noise():
    # With Q = 0 and R = I (S1 eq. 18's setting) the predictor covariance equals the
    # algebraically correct form of S1's update, P+ = A P A^T - K_p S K_p^T.
    A, B, C, _, _ = _random_system()
    R = np.eye(2)
    P = np.diag([1.0, 2.0, 0.5, 1.5])
    res = kalman_filter(A, B, C, np.zeros((1, 2)), Q=0.0, R=R, P0=P, form="predictor")
    S = C @ P @ C.T + R
    Kp = A @ P @ C.T @ np.linalg.inv(S)  # test oracle, explicit inverse is fine here
    np.testing.assert_allclose(res.P_pred[1], A @ P @ A.T - Kp @ S @ Kp.T, rtol=1e-12, atol=1e-12)


def test_normalised_innovation_squared_is_chi2():
    # With the true model, nu^T S^-1 nu ~ chi2(m) per step: mean m, std sqrt(2m/N) for the
    # average of N steps; 5 sigma bound (seeded, so this is deterministic).
    A, B, C, Q, R = _random_system()
    rng = np.random.default_rng(11)
    N = 4000
    u = rng.normal(size=(N, 2))
    sim = simulate_linear(A, B, C, u, R=R, Q=Q, rng=rng)
    res = kalman_filter(A, B, C, sim.y, u, Q=Q, R=R, P0=np.eye(4) * 10)
    nis = np.einsum("ti,tij,tj->t", res.innovations, np.linalg.inv(res.S), res.innovations)
    m = 2
    assert abs(nis[50:].mean() - m) < 5 * np.sqrt(2 * m / (N - 50))


def test_simulation_is_seeded_and_inputs_untouched():
    A, B, C, Q, R = _random_system()
    u = np.ones((10, 2))
    u_copy = u.copy()
    s1 = simulate_linear(A, B, C, u, R=R, Q=Q, rng=5)
    s2 = simulate_linear(A, B, C, u, R=R, Q=Q, rng=np.random.default_rng(5))
    s3 = simulate_linear(A, B, C, u, R=R, Q=Q, rng=6)
    np.testing.assert_array_equal(s1.y, s2.y)
    assert not np.array_equal(s1.y, s3.y)
    np.testing.assert_array_equal(u, u_copy)
    assert s1.x.shape == (11, 4) and s1.y.shape == (10, 2)


def test_stepping_class_equals_batch():
    A, B, C, Q, R = _random_system()
    rng = np.random.default_rng(2)
    u = rng.normal(size=(20, 2))
    sim = simulate_linear(A, B, C, u, R=R, Q=Q, rng=rng)
    res = kalman_filter(A, B, C, sim.y, u, Q=Q, R=R, P0=1.0)
    kf = KalmanFilter(np.zeros(4), 1.0)
    for t in range(20):
        x_f, _P, _nu, _S = kf.step(sim.y[t], u[t], A, B, C, Q, R)
        np.testing.assert_array_equal(x_f, res.x[t])


def test_bad_inputs():
    A, B, C, Q, R = _random_system()
    with pytest.raises(InputError, match="A must be square"):
        kalman_filter(np.ones((2, 3)), B, C, np.zeros((3, 2)))
    with pytest.raises(InputError, match="R must be positive definite"):
        kalman_filter(A, B, C, np.zeros((3, 2)), R=np.zeros((2, 2)))
    with pytest.raises(InputError, match="Q must be positive semi-definite"):
        kalman_filter(A, B, C, np.zeros((3, 2)), Q=-np.eye(4))
    with pytest.raises(InputError, match="y must have shape"):
        kalman_filter(A, B, C, np.zeros((3, 3)))
    with pytest.raises(InputError, match="form must be one of 'predict-update', 'predictor'"):
        kalman_filter(A, B, C, np.zeros((3, 2)), form="ukf")


@settings(max_examples=25, deadline=None)
@given(n=st.integers(1, 5), m=st.integers(1, 3), seed=st.integers(0, 2**31 - 1))
def test_forms_agree_property(n, m, seed):
    # Property: for any stable system and any prior, predictor == predict/update (1e-9;
    # 30 steps of O(1) quantities, the Riccati map is contractive for stable A).
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    A *= 0.9 / max(max(abs(np.linalg.eigvals(A))), 1e-9)
    B, C = rng.normal(size=(n, 1)), rng.normal(size=(m, n))
    L = rng.normal(size=(m, m))
    R = L @ L.T + 0.1 * np.eye(m)
    y, u = rng.normal(size=(30, m)), rng.normal(size=(30, 1))
    kw = dict(Q=0.05, R=R, P0=np.eye(n) * 3.0)
    r1 = kalman_filter(A, B, C, y, u, form="predict-update", **kw)
    r2 = kalman_filter(A, B, C, y, u, form="predictor", **kw)
    np.testing.assert_allclose(r1.x_pred, r2.x_pred, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(r1.P_pred, r2.P_pred, rtol=1e-9, atol=1e-9)
    # Joseph-form covariances stay symmetric positive semi-definite
    assert np.all(np.linalg.eigvalsh(r2.P_pred) > -1e-12)


def test_cholesky_helpers_equal_scipy_bit_for_bit():
    # The filter step factors S with LAPACK potrf/potrs directly (issue 24 item 1: scipy's
    # per-call checks were ~12 of 14 us per step); the routines scipy.linalg.cho_factor /
    # cho_solve call, so the bits must be scipy's: exact equality, no tolerance.
    from adcskit.estimation import kalman

    rng = np.random.default_rng(7)
    for m in range(1, 7):
        G = rng.normal(size=(m, m))
        S = G @ G.T + 0.1 * np.eye(m)
        S = 0.5 * (S + S.T)
        ours = kalman._cho_factor(S)
        ref = sla.cho_factor(S, lower=True, check_finite=False)
        assert ours[1] is True and np.array_equal(ours[0], ref[0])
        for b in (rng.normal(size=m), rng.normal(size=(m, 6))):
            assert np.array_equal(kalman._cho_solve(ours, b), sla.cho_solve(ref, b, check_finite=False))
    with pytest.raises(sla.LinAlgError, match="2-th leading minor of the array is not positive definite"):
        kalman._cho_factor(np.diag([1.0, -1.0]))


@pytest.mark.parametrize("form", ["predict-update", "predictor"])
def test_filter_bits_unchanged_by_direct_lapack(form, monkeypatch):
    # The whole filter with the direct LAPACK helpers equals the filter with scipy's
    # cho_factor / cho_solve in their place: every output array, exactly.
    from adcskit.estimation import kalman

    A, B, C, Q, R = _random_system(seed=11)
    u = np.sin(0.2 * np.arange(60))[:, None] * np.ones((1, 2))
    sim = simulate_linear(A, B, C, u, Q=Q, R=R, rng=5)
    ours = kalman_filter(A, B, C, sim.y, u, Q=Q, R=R, form=form)
    monkeypatch.setattr(kalman, "_cho_factor", lambda S: sla.cho_factor(S, lower=True, check_finite=False))
    monkeypatch.setattr(kalman, "_cho_solve", lambda cf, b: sla.cho_solve(cf, b, check_finite=False))
    ref = kalman_filter(A, B, C, sim.y, u, Q=Q, R=R, form=form)
    for name in ("x", "P", "x_pred", "P_pred", "innovations", "S"):
        assert np.array_equal(getattr(ours, name), getattr(ref, name)), name
    assert ours.loglik == ref.loglik
