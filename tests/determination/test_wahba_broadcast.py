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
