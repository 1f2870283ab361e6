"""Tests of adcskit.estimation.joint: S1's alternation loop and the augmented-state EKF."""

from __future__ import annotations

import numpy as np
import pytest

from adcskit.errors import InputError
from adcskit.estimation import augmented_ekf, identify_model, joint_estimate, simulate_linear

# S1 eq. (3): printed 1-DOF closed-loop model, read as I + A_c with
# A_c = [[0, 1], [-kp/I, -kd/I]], kp/I = 1, kd/I = 2 (see docs/studies/model-estimation.md).
A1 = np.array([[1.0, 1.0], [-1.0, -1.0]])
B1 = np.array([[0.0], [2.66]])


def model_1dof(p):
    """Discrete 1-DOF model for the inertia ratio p = I_true / I_assumed (p = 1: printed)."""
    r = 1.0 / float(p[0])
    return np.array([[1.0, 1.0], [-r, 1.0 - 2.0 * r]]), np.array([[0.0], [2.66 * r]])


A0_1 = model_1dof([1.5])[0]  # prior with the inertia overestimated by 50 %


def _sim(N=150, seed=0, noise=0.3):
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((N, 1))
    sim = simulate_linear(A1, B1, np.eye(2), u, R=noise**2, rng=rng)
    return sim, u


def _err(A):
    return np.linalg.norm(A - A1, 2) / np.linalg.norm(A1, 2)


def test_joint_qr_converges_to_truth_with_low_noise():
    # Low noise (sigma 0.3, states ~3): final error well below the prior's 37 %
    # (||A0 - A||_2/||A||_2 = 0.373 from the matrices above); 10 % bound.
    sim, u = _sim()
    assert _err(A0_1) == pytest.approx(0.3727, abs=1e-3)
    res = joint_estimate(sim.y, u, A_prior=A0_1, B=B1, Q=1e-3, R=0.09, method="qr")
    assert res.success and res.n_failed == 0
    assert _err(res.A) < 0.10
    assert res.A_history.shape == (150, 2, 2)
    np.testing.assert_array_equal(res.A_history[0], A0_1)  # prior until the LS is determined
    np.testing.assert_array_equal(res.A_history[-1], res.A)


def test_joint_final_step_is_the_batch_least_squares_of_its_own_estimates():
    # The last identification (qr) is exactly the LS fit of the targets on the Kalman
    # estimates it had: pairs s = 0..N-2 (oracle: identify_model on the stored data).
    sim, u = _sim(N=60)
    res = joint_estimate(sim.y, u, A_prior=A0_1, B=B1, Q=1e-3, R=0.09, method="qr")
    N = 60
    ref = identify_model(res.x[: N - 1], sim.y[1:N], u[: N - 1], B=B1, method="qr")
    np.testing.assert_allclose(res.A_history[-1], ref.A, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("method", ["adaptive-gmres-online", "adaptive-gmres-offline", "ridge-prior", "rls"])
def test_joint_prior_anchored_methods_run_and_are_reproducible(method):
    sim, u = _sim(N=80, noise=1.0)
    kw = dict(A_prior=A0_1, B=B1, Q=1e-2, R=1.0, method=method)
    r1 = joint_estimate(sim.y, u, rng=4, **kw)
    r2 = joint_estimate(sim.y, u, rng=4, **kw)
    np.testing.assert_array_equal(r1.A_history, r2.A_history)
    assert r1.success and r1.n_calls == 79


def test_joint_rls_online_equals_batch_rls_on_the_same_estimates():
    sim, u = _sim(N=50)
    opts = {"forgetting": 0.98, "delta": 50.0}
    res = joint_estimate(sim.y, u, A_prior=A0_1, B=B1, Q=1e-3, R=0.09, method="rls", options=opts)
    ref = identify_model(res.x[:49], sim.y[1:50], u[:49], B=B1, method="rls", A_init=A0_1, options=opts)
    np.testing.assert_allclose(res.A, ref.A, rtol=1e-12, atol=1e-12)


def test_joint_estimate_B_and_passes():
    sim, u = _sim(N=120, noise=0.1)
    res = joint_estimate(sim.y, u, A_prior=A0_1, B=np.zeros((2, 1)), Q=1e-3, R=0.01,
                         method="qr", estimate_B=True, passes=2)
    assert _err(res.A) < 0.1
    np.testing.assert_allclose(res.B, B1, atol=0.2)  # 0.2 of 2.66: noise sigma 0.1 over 120 samples


def test_joint_rejects_non_identity_C():
    sim, u = _sim(N=10)
    with pytest.raises(InputError, match="C must be the identity"):
        joint_estimate(sim.y, u, A_prior=A0_1, B=B1, C=2 * np.eye(2))


def test_augmented_ekf_recovers_inertia_ratio():
    # The truth is p = 1 (printed model); the EKF starts at p = 1.5 with 50 % std.
    # Seeded; bound: 3 filter standard deviations plus 0.02 for linearisation bias.
    sim, u = _sim(N=200, noise=1.0)
    res = augmented_ekf(sim.y, u, model_1dof, [1.5], P_p0=0.5**2, Q=1e-4, R=1.0, P0=1.0)
    assert res.success
    assert abs(res.p[-1, 0] - 1.0) < 3 * res.p_std[-1, 0] + 0.02
    assert res.p_std[-1, 0] < 0.1
    np.testing.assert_allclose(res.A, model_1dof(res.p[-1])[0], rtol=1e-12)
    assert res.nfev == 200 * 3
