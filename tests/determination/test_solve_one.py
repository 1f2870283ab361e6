"""The out-of-line per-problem Wahba solver against the batch kernel that inlines it.

``_kernels.solve_one`` is ``_kernels._solve_one`` compiled as its own function (so that the
min-max step and the closed-loop simulator compile the solver once instead of inlining it at
each call site); ``solve_batch_serial`` inlines the same ``_solve_one``. Same source, same
operations in the same order (no fast-math), so every output must be the same bits.
"""

import numpy as np
import pytest

from adcskit.determination import _kernels as k

METHODS = (k.TRIAD, k.QMETHOD, k.QUEST, k.ESOQ2, k.SVD, k.FOAM, k.TWO_VECTOR, k.FLAE)


def _problems(rng, n_prob, n_obs):
    """Seeded noisy problems (unit reference vectors, body = reference + 0.01-scale noise,
    random weights) plus one degenerate problem (all body vectors equal)."""
    ref = rng.normal(size=(n_prob, n_obs, 3))
    ref /= np.linalg.norm(ref, axis=2, keepdims=True)
    body = ref + 0.01 * rng.normal(size=ref.shape)
    body[-1, :] = body[-1, 0]  # collinear body vectors: a failure status or a degenerate answer
    w = rng.uniform(0.2, 1.0, size=(n_prob, n_obs))
    return body, ref, w


@pytest.mark.parametrize("n_obs", [2, 3])
def test_solve_one_bitwise_equal_to_batch(n_obs):
    rng = np.random.default_rng(24)
    n_prob = 6
    body, ref, w = _problems(rng, n_prob, n_obs)
    for method in METHODS:
        q_b, out_b = np.empty((n_prob, 4)), np.empty((n_prob, 3))
        cov_b, st_b = np.empty((n_prob, 0, 0)), np.empty(n_prob, dtype=np.int8)  # as wahba() passes them
        k.solve_batch_serial(body, ref, w, method, q_b, out_b, cov_b, st_b)
        q_o, out_o, cov_o = np.empty((n_prob, 4)), np.empty((n_prob, 3)), np.empty((n_prob, 0, 0))
        sc = [np.empty((n_obs, 3)), np.empty((n_obs, 3)), np.empty(4), np.empty((3, 3)), np.empty((3, 3)),
              np.empty((4, 4)), np.empty((3, 3)), np.empty((3, 3)), np.empty(4)]
        st_o = [k.solve_one(body, ref, w, i, i, method, q_o, out_o, cov_o, *sc) for i in range(n_prob)]
        assert st_o == list(st_b)
        assert st_o[0] == k.OK
        # bytewise (NaN-aware): the same compiled operations, so the same bits
        assert q_o.tobytes() == q_b.tobytes(), method
        assert out_o.tobytes() == out_b.tobytes(), method
