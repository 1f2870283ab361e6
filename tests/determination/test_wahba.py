"""Tests of the Wahba point solvers (adcskit.determination.solve_wahba).

Oracles: (1) the eigen-solution of Davenport's K computed independently here with
numpy.linalg.eigh (S0 eq. 2; Markley & Crassidis 2014 eq. 5.17), (2) scipy's
Rotation.align_vectors (an SVD solver, an independent implementation), (3) noise-free data
built from a known attitude (closed-form oracle), (4) an mpmath 50-digit eigen-solution for
the extreme-weight cases, (5) a seeded Monte Carlo for the covariance.
"""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from adcskit.determination import METHODS, davenport_k, solve_wahba, wahba_loss
from adcskit.determination.wahba import quat_to_dcm_np
from adcskit.errors import InputError

OPTIMAL = [m for m, (_, optimal, _) in METHODS.items() if optimal]
EPS = np.finfo(float).eps


def qangle(q1, q2):
    """Rotation angle between quaternions [rad], accurate near zero (chord formula)."""
    q1 = np.atleast_2d(q1)
    q2 = np.atleast_2d(q2)
    d = np.minimum(np.linalg.norm(q1 - q2, axis=-1), np.linalg.norm(q1 + q2, axis=-1))
    return 4.0 * np.arcsin(np.clip(d / 2.0, 0.0, 1.0))


def eigen_reference(body, ref, weights=None):
    K = davenport_k(body, ref, weights)
    w, v = np.linalg.eigh(K)
    q = v[..., :, 3]
    q = q * np.where(q[..., 3:] < 0, -1.0, 1.0)
    return q, w


def random_problems(rng, N, n, noise=1e-3):
    q_true = Rotation.random(N, random_state=rng).as_quat()
    q_true *= np.where(q_true[:, 3:] < 0, -1.0, 1.0)
    ref = rng.normal(size=(N, n, 3))
    body = np.einsum("kij,knj->kni", quat_to_dcm_np(q_true), ref)
    body += noise * rng.normal(size=body.shape)
    return body, ref, q_true


@pytest.mark.parametrize("method", OPTIMAL)
@pytest.mark.parametrize("n", [2, 3, 7])
def test_optimal_methods_match_eigen_solution(method, n):
    if method == "two-vector" and n != 2:
        pytest.skip("two-vector takes exactly two observations (tested separately)")
    rng = np.random.default_rng(10 + n)
    body, ref, _ = random_problems(rng, 500, n)
    weights = rng.uniform(0.1, 10.0, size=(500, n))
    res = solve_wahba(body, ref, weights, method=method)
    q_ref, lam = eigen_reference(body, ref, weights)
    assert res.success.all()
    # eigenvector accuracy of a backward-stable solver is ~ eps*|K|/gap (|K| <= 3): allow
    # 100x that, and never more than the 1e-10 deg the issue asks for on these inputs
    gap = lam[:, 3] - lam[:, 2]
    tol = np.minimum(100 * 3 * EPS / gap, np.radians(1e-10))
    err = qangle(res.q, q_ref)
    assert np.all(err <= np.maximum(tol, 100 * EPS)), (err.max(), tol.min())
    assert np.max(np.degrees(err)) < 1e-10


@pytest.mark.parametrize("method", OPTIMAL)
def test_optimal_methods_match_scipy_align_vectors(method):
    rng = np.random.default_rng(3)
    n = 2 if method == "two-vector" else 4
    body, ref, _ = random_problems(rng, 50, n, noise=1e-2)
    weights = rng.uniform(0.5, 2.0, size=(50, n))
    res = solve_wahba(body, ref, weights, method=method)
    for k in range(50):
        b = body[k] / np.linalg.norm(body[k], axis=1, keepdims=True)
        r = ref[k] / np.linalg.norm(ref[k], axis=1, keepdims=True)
        rot, _ = Rotation.align_vectors(b, r, weights=weights[k])  # b ≈ R r, so R = A(q)
        q_sp = rot.inv().as_quat()  # design.md: from_quat(q).inv() has matrix A(q)
        # scipy's SVD path is accurate to ~1e-15 rad on these well-conditioned problems
        assert qangle(res.q[k], q_sp)[0] < 1e-12


@pytest.mark.parametrize("method", [*OPTIMAL, "triad"])
@pytest.mark.parametrize(
    "q_true",
    [
        [0, 0, 0, 1],  # identity
        [1, 0, 0, 0],  # exact 180 deg about x
        [0, 1, 0, 0],  # 180 deg about y
        [0, 0, 1, 0],  # 180 deg about z
        [0.6, 0.0, 0.8, 0.0],  # 180 deg about an oblique axis
        [0.5, 0.5, 0.5, 0.5],
    ],
)
def test_noise_free_recovers_truth_including_identity_and_180(method, q_true):
    # closed-form oracle: b_i = A(q) r_i exactly, so every solver must return q
    q_true = np.asarray(q_true, dtype=float)
    rng = np.random.default_rng(5)
    ref = rng.normal(size=(3, 3))
    body = ref @ quat_to_dcm_np(q_true[None])[0].T
    weights = [1.0, 2.0, 0.5]
    if method == "two-vector":
        body, ref, weights = body[:2], ref[:2], weights[:2]
    res = solve_wahba(body, ref, weights, method=method)
    # rounding of the constructed data and the solver: a few eps, 1e-13 rad is generous
    assert qangle(res.q, q_true)[0] < 1e-13
    assert res.q[3] >= 0
    assert res.loss < 1e-28  # residual form: (few eps)^2


def mp_reference(body, ref, weights, dps=50):
    """Largest eigenvector of K in 50-digit arithmetic from the exact double inputs."""
    mpmath.mp.dps = dps
    a = [mpmath.mpf(w) for w in weights]
    s = sum(a)
    a = [x / s for x in a]
    bs, rs = [], []
    for b, r in zip(body, ref):
        bm = [mpmath.mpf(x) for x in b]
        rm = [mpmath.mpf(x) for x in r]
        nb = mpmath.sqrt(sum(x * x for x in bm))
        nr = mpmath.sqrt(sum(x * x for x in rm))
        bs.append([x / nb for x in bm])
        rs.append([x / nr for x in rm])
    B = mpmath.matrix(3, 3)
    for ai, b, r in zip(a, bs, rs):
        for i in range(3):
            for j in range(3):
                B[i, j] += ai * b[i] * r[j]
    sig = B[0, 0] + B[1, 1] + B[2, 2]
    z = [B[1, 2] - B[2, 1], B[2, 0] - B[0, 2], B[0, 1] - B[1, 0]]
    K = mpmath.matrix(4, 4)
    for i in range(3):
        for j in range(3):
            K[i, j] = B[i, j] + B[j, i] - (sig if i == j else 0)
        K[i, 3] = K[3, i] = z[i]
    K[3, 3] = sig
    E, Q = mpmath.eigsy(K)
    k = max(range(4), key=lambda i: E[i])
    q = np.array([float(Q[i, k]) for i in range(4)])
    ev = sorted(float(e) for e in E)
    return q * (1 if q[3] >= 0 else -1), ev[3] - ev[2]


@pytest.mark.parametrize("ratio", [1e6, 1e12])
@pytest.mark.parametrize("method", OPTIMAL)
def test_extreme_weight_ratios_match_extended_precision(method, ratio):
    # At weight ratio 1e6 the gap λ_max − λ_2 of K is ~1e-6, so no double-precision solver
    # (LAPACK's eigh included) can be closer to the true optimum than ~eps/gap ~ 1e-10 rad
    # ~ 1e-8 deg; the 1e-10 deg is below that floor. We require what conditioning
    # allows: error vs a 50-digit mpmath solution <= 100 eps/gap (measured: <= 6 eps/gap for
    # every method except FOAM, <= 24 eps/gap; docs/studies/wahba-table1.md).
    rng = np.random.default_rng(8)
    body, ref, _ = random_problems(rng, 5, 2, noise=1e-2)
    for k in range(5):
        w = np.array([1.0, 1.0 / ratio])
        res = solve_wahba(body[k], ref[k], w, method=method)
        q_mp, gap = mp_reference(body[k], ref[k], w)
        err = qangle(res.q, q_mp)[0]
        bound = 100 * EPS / gap
        assert err <= max(bound, 1e-14), (err, bound)


def test_batch_flags_degenerate_problems_and_keeps_inputs():
    rng = np.random.default_rng(2)
    body, ref, q_true = random_problems(rng, 6, 2, noise=0.0)
    body[1, 0] = np.nan  # NaN
    body[2, 1] = 0.0  # zero length
    body[3, 1] = 3.0 * body[3, 0]  # parallel body vectors
    ref[4, 1] = -2.0 * ref[4, 0]  # anti-parallel reference vectors
    keep_b, keep_r = body.copy(), ref.copy()
    for method in METHODS:
        res = solve_wahba(body, ref, method=method)
        np.testing.assert_array_equal(body, keep_b)  # never modify inputs
        np.testing.assert_array_equal(ref, keep_r)
        assert res.success.tolist() == [True, False, False, False, False, True]
        assert res.status.tolist() == [0, 1, 2, 4, 5, 0]
        assert np.all(np.isnan(res.q[~res.success]))
        assert qangle(res.q[[0, 5]], q_true[[0, 5]]).max() < 1e-13
        assert "4 of 6" not in res.message and "1 of 6" in res.message
        msgs = res.messages()
        assert "NaN" in msgs[1] and "zero length" in msgs[2] and "parallel" in msgs[3]


def test_single_degenerate_problem_raises_clear_error():
    b = np.array([[1.0, 0, 0], [2.0, 0, 0]])
    r = np.array([[0.0, 1, 0], [0.0, 0, 1]])
    with pytest.raises(InputError, match="body vectors are parallel"):
        solve_wahba(b, r)
    with pytest.raises(InputError, match="NaN"):
        solve_wahba([[np.nan, 0, 1], [0, 1, 0]], r)
    with pytest.raises(InputError, match="fewer than 2"):
        solve_wahba([[1.0, 0, 0]], [[0.0, 1, 0]])
    with pytest.raises(InputError, match="shape"):
        solve_wahba(np.ones((2, 2)), np.ones((2, 2)))
    with pytest.raises(InputError, match="weights must be > 0"):
        solve_wahba(np.eye(3), np.eye(3), [1.0, -1.0, 1.0])


def test_batch_of_one_vector_problems_is_flagged_not_raised():
    res = solve_wahba(np.ones((3, 1, 3)), np.ones((3, 1, 3)))
    assert not res.success.any()
    assert "fewer than 2" in res.message


def test_wrong_method_lists_valid_ones():
    with pytest.raises(InputError, match="'q-method'.*'quest'.*'esoq2'"):
        solve_wahba(np.eye(3), np.eye(3), method="davenport")


def test_large_batch_parallel_path_matches_serial():
    rng = np.random.default_rng(4)
    body, ref, _ = random_problems(rng, 5000, 2)  # >= 4096: parallel kernel
    big = solve_wahba(body, ref, method="esoq2")
    small = solve_wahba(body[:100], ref[:100], method="esoq2")
    np.testing.assert_array_equal(big.q[:100], small.q)


def test_loss_matches_wahba_loss_and_eigenvalue():
    rng = np.random.default_rng(6)
    body, ref, _ = random_problems(rng, 20, 3, noise=0.05)
    w = rng.uniform(1, 3, size=(20, 3))
    res = solve_wahba(body, ref, w, method="quest")
    np.testing.assert_allclose(res.loss, wahba_loss(res.q, body, ref, w), rtol=1e-10, atol=1e-15)
    # S0 eq. 8: L = Σa − λ_max with the caller's weights
    _, lam = eigen_reference(body, ref, w)
    np.testing.assert_allclose(res.loss, w.sum(1) * (1 - lam[:, 3]), rtol=1e-8, atol=1e-14)


def test_covariance_matches_monte_carlo():
    # Markley & Crassidis 2014 eq. 5.66 with a_i = 1/σ_i²: P = [Σ a_i (I − b_i b_iᵀ)]⁻¹ is the
    # covariance of the BODY-frame attitude error. Checked at a large, non-identity attitude,
    # full matrix (off-diagonals too), against the sample covariance of q-method errors over
    # 4000 seeded trials. The relative standard error of a covariance entry is ~sqrt(2/4000)
    # = 2.2 %; 10 % in Frobenius norm is > 4 sigma. The reference-frame covariance
    # Aᵀ P A (a body/reference swap) differs from P by ~100 % here and must fail.
    from scipy.spatial.transform import Rotation

    from adcskit.attitude import quat_to_dcm

    rng = np.random.default_rng(7)
    sig = np.array([1e-3, 3e-3, 2e-3])
    r = np.array([[1.0, 0, 0], [0.3, 1.0, 0], [0.1, 0.2, 1.0]])
    r /= np.linalg.norm(r, axis=1, keepdims=True)
    A = Rotation.from_rotvec([0.9, -1.7, 0.6]).as_matrix()  # independent of adcskit (b = A r)
    b = r @ A.T
    N = 4000
    noise = rng.normal(size=(N, 3, 3)) * sig[None, :, None]
    body = b[None] + noise - np.einsum("kni,ni->kn", noise, b)[..., None] * b[None]  # ⟂ to b
    res = solve_wahba(body, np.broadcast_to(r, body.shape), 1 / sig**2, method="q-method")
    E = quat_to_dcm(res.q) @ A.T  # A_est A_trueᵀ ≈ I − [δθ×], δθ in the body frame
    assert np.abs(E - np.eye(3)).max() < 0.05  # right attitude (a transposed A fails here)
    dth = 0.5 * np.stack([E[:, 1, 2] - E[:, 2, 1], E[:, 2, 0] - E[:, 0, 2], E[:, 0, 1] - E[:, 1, 0]], axis=1)
    P_mc = np.cov(dth.T)
    P = solve_wahba(b, r, 1 / sig**2).cov
    P_indep = np.linalg.inv(sum((1 / s**2) * (np.eye(3) - np.outer(bi, bi)) for s, bi in zip(sig, b)))
    np.testing.assert_allclose(P, P_indep, rtol=1e-10)
    rel = np.linalg.norm(P_mc - P) / np.linalg.norm(P)
    assert rel < 0.10, rel
    assert abs(P[0, 1]) > 0.1 * np.sqrt(P[0, 0] * P[1, 1])  # off-diagonals are not negligible here
    swapped = A.T @ P @ A  # covariance in the reference frame: must be distinguishable
    assert np.linalg.norm(P_mc - swapped) / np.linalg.norm(P) > 3 * rel
    assert res.cond.min() >= 1.0


def test_condition_number_flags_weak_geometry():
    r = np.array([[1.0, 0, 0], [np.cos(1e-4), np.sin(1e-4), 0]])
    good = solve_wahba(np.eye(3)[:2], np.eye(3)[:2])
    weak = solve_wahba(r, r)
    assert weak.cond > 1e6 * good.cond


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 2**31 - 1),
    scale=st.floats(1e-3, 1e3),
    wscale=st.floats(1e-3, 1e3),
)
def test_invariances(seed, scale, wscale):
    # algebraic properties: vector length, overall weight scale and observation order do not
    # change the optimal attitude; rotating the reference frame by C changes q by C
    rng = np.random.default_rng(seed)
    body, ref, _ = random_problems(rng, 1, 3, noise=0.05)
    body, ref = body[0], ref[0]
    w = rng.uniform(0.5, 2, size=3)
    q0 = solve_wahba(body, ref, w, method="quest").q
    q1 = solve_wahba(scale * body, ref / scale, wscale * w, method="quest").q
    perm = rng.permutation(3)
    q2 = solve_wahba(body[perm], ref[perm], w[perm], method="quest").q
    assert qangle(q0, q1)[0] < 1e-12
    assert qangle(q0, q2)[0] < 1e-12
    C = Rotation.random(random_state=rng).as_matrix()
    q3 = solve_wahba(body, ref @ C.T, w, method="quest").q  # A' = A Cᵀ
    A3 = quat_to_dcm_np(q3[None])[0]
    A0 = quat_to_dcm_np(q0[None])[0]
    np.testing.assert_allclose(A3, A0 @ C.T, atol=1e-12)


def test_read_only_and_non_contiguous_inputs():
    rng = np.random.default_rng(9)
    body, ref, _ = random_problems(rng, 4, 3)
    expected = solve_wahba(body, ref, method="esoq2").q
    b_ro, r_ro = body.copy(), ref.copy()
    b_ro.flags.writeable = False
    r_ro.flags.writeable = False
    np.testing.assert_array_equal(solve_wahba(b_ro, r_ro, method="esoq2").q, expected)
    big = np.zeros((4, 3, 6))
    big[..., ::2] = body
    np.testing.assert_array_equal(solve_wahba(big[..., ::2], ref, method="esoq2").q, expected)
    np.testing.assert_array_equal(solve_wahba(body.tolist(), ref.tolist(), method="esoq2").q, expected)


def test_shared_weight_row_equals_per_problem_weights():
    rng = np.random.default_rng(11)
    body, ref, _ = random_problems(rng, 6, 3)
    w = np.array([1.0, 2.0, 3.0])
    a = solve_wahba(body, ref, w, method="quest")
    b = solve_wahba(body, ref, np.tile(w, (6, 1)), method="quest")
    np.testing.assert_array_equal(a.q, b.q)
    np.testing.assert_array_equal(a.loss, b.loss)
    np.testing.assert_allclose(davenport_k(body, ref, w), davenport_k(body, ref, np.tile(w, (6, 1))))
    np.testing.assert_allclose(wahba_loss(a.q, body, ref, w), a.loss, rtol=1e-10, atol=1e-15)


def test_huge_and_tiny_vectors_are_normalised_not_flagged():
    # lengths carry no information: 1e200 or 1e-200 (squared norm over/underflows) must give
    # the same attitude as unit vectors; an empty batch is fine
    rng = np.random.default_rng(12)
    body, ref, _ = random_problems(rng, 3, 2)
    q = solve_wahba(body, ref, method="esoq2").q
    res = solve_wahba(body * 1e200, ref * 1e-200, method="esoq2")
    assert res.success.all()
    assert qangle(res.q, q).max() < 1e-14
    empty = solve_wahba(np.zeros((0, 2, 3)), np.zeros((0, 2, 3)))
    assert empty.q.shape == (0, 4) and empty.message == "solved"


def test_two_vector_needs_exactly_two_observations():
    # Markley & Crassidis (2014) eq. 5.70-5.71 is the closed form for n = 2 only
    with pytest.raises(InputError, match="'two-vector' needs exactly 2 observations"):
        solve_wahba(np.eye(3), np.eye(3), method="two-vector")
