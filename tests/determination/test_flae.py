"""FLAE (Wu et al. 2018) as a ``solve_wahba`` method.

The generic tests of test_wahba.py already run every optimal method of the registry (FLAE
included) against the eigen-solution, scipy, noise-free data at identity and 180°, extreme
weight ratios vs mpmath, and the degenerate batch flags; here: the FLAE kernel itself, that
its fast path (not the eigen-solver fallback) does the work, and the single-call path.
"""

from __future__ import annotations

import numpy as np
import pytest

from adcskit.attitude import quat_to_dcm, random_quat
from adcskit.determination import _kernels as _k
from adcskit.determination import davenport_k, solve_wahba
from adcskit.errors import InputError


def _problems(rng, N, n, noise):
    q = random_quat(N, rng=rng)
    ref = rng.normal(size=(N, n, 3))
    body = np.einsum("kij,knj->kni", quat_to_dcm(q), ref) + noise * rng.normal(size=(N, n, 3))
    return body, ref


@pytest.mark.parametrize("noise", [0.0, 1e-6, 1e-2, 0.3])
def test_flae_kernel_root_and_eigenvector(noise):
    # λ_max from the symbolic quartic roots (+ Newton polish) equals LAPACK's largest
    # eigenvalue of K to rounding (|K| <= 3: 1e-14 absolute), and the eliminated null vector
    # satisfies K q = λ q to the same order before the shared refinement step
    rng = np.random.default_rng(21)
    body, ref = _problems(rng, 200, 4, noise)
    K = davenport_k(body, ref)
    for k in range(len(K)):
        B = np.einsum("ni,nj->ij", body[k] / np.linalg.norm(body[k], axis=1, keepdims=True),
                      ref[k] / np.linalg.norm(ref[k], axis=1, keepdims=True)) / 4
        q = np.empty(4)
        lam, ok = _k._flae_quat(B, np.ascontiguousarray(K[k]), q)
        assert ok
        assert lam == pytest.approx(np.linalg.eigvalsh(K[k])[-1], abs=1e-14)
        assert np.linalg.norm(K[k] @ q - lam * q) < 1e-12


def test_flae_fast_path_does_the_work():
    # the residual check sends a problem to the q-method only when FLAE's eigen-residual
    # exceeds 64 eps; on random problems that must be rare, else "flae" would be the
    # q-method in disguise (measured: 0 % for n >= 3, ~0.2 % for n = 2)
    rng = np.random.default_rng(22)
    for n, limit in ((2, 0.01), (3, 0.0), (6, 0.0)):
        body, ref = _problems(rng, 2000, n, 1e-3)
        res = solve_wahba(body, ref, method="flae")
        ref_q = solve_wahba(body, ref, method="q-method").q
        assert res.success.all()
        assert res.fallback.mean() <= limit, (n, res.fallback.mean())
        d = np.minimum(np.linalg.norm(res.q - ref_q, axis=1), np.linalg.norm(res.q + ref_q, axis=1))
        assert d.max() < 1e-10


def test_flae_single_call_and_degenerate():
    b = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    r = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # A = 90 deg about z
    res = solve_wahba(b, r, method="flae")
    assert res.method == "flae" and res.success and res.status == 0
    np.testing.assert_allclose(res.q, solve_wahba(b, r).q, atol=1e-15)
    with pytest.raises(InputError, match="parallel"):
        solve_wahba([[1.0, 0, 0], [2.0, 0, 0]], r, method="flae")
