"""A single reference set shared by a batch gives the same answers as repeating it."""

import numpy as np
import pytest

from adcskit.determination import solve_wahba
from adcskit.errors import InputError


def test_shared_reference_set_broadcasts():
    rng = np.random.default_rng(4)
    r = rng.standard_normal((3, 3))
    b = rng.standard_normal((50, 3, 3))
    shared = solve_wahba(b, r, method="q-method")
    repeated = solve_wahba(b, np.repeat(r[None], 50, axis=0), method="q-method")
    np.testing.assert_array_equal(shared.q, repeated.q)
    with pytest.raises(InputError, match="body and ref must have the same shape"):
        solve_wahba(b, r[:2])


def test_covariance_flag_keeps_attitudes_and_type():
    rng = np.random.default_rng(5)
    b, r = rng.standard_normal((40, 2, 3)), rng.standard_normal((40, 2, 3))
    full = solve_wahba(b, r, method="esoq2")
    lean = solve_wahba(b, r, method="esoq2", covariance=False)
    np.testing.assert_array_equal(full.q, lean.q)
    np.testing.assert_array_equal(full.cond, lean.cond)  # cond is always computed
    assert lean.cov.shape == (40, 3, 3) and np.all(np.isnan(lean.cov))
    assert np.all(np.isfinite(full.cov))
    with pytest.raises(TypeError, match="covariance must be True or False"):
        solve_wahba(b, r, covariance="no")
