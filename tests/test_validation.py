"""Boundary validation helpers (adcskit._validation)."""

from __future__ import annotations

import numpy as np
import pytest

from adcskit._validation import (
    as_array,
    as_batch,
    as_rng,
    check_choice,
    check_int,
    check_positive,
    check_range,
)
from adcskit.errors import InputError, InputTypeError


def test_as_array_copies_and_never_aliases_input():
    x = np.arange(3.0)
    y = as_array("x", x, shape=(3,))
    y[0] = 99.0
    assert x[0] == 0.0


@pytest.mark.parametrize(
    ("value", "kwargs", "fragment"),
    [
        ([1.0, np.nan, 2.0], {}, "x must be finite"),
        ([[1.0, 2.0]], {"shape": (3,)}, "x must have shape (3,)"),
        ([1.0, 2.0], {"ndim": 2}, "x must have 2 dimension(s)"),
        (np.ones((2, 4)), {"shape": (None, 3)}, "x must have shape (n, 3)"),
    ],
)
def test_as_array_errors_name_parameter_and_value(value, kwargs, fragment):
    with pytest.raises(InputError) as err:
        as_array("x", value, **kwargs)
    assert fragment in str(err.value)
    assert "got" in str(err.value)


def test_as_array_rejects_non_numeric_with_type_error():
    with pytest.raises(InputTypeError, match="x must be an array of numbers"):
        as_array("x", ["a", "b"])


def test_as_batch_roundtrip_ranks():
    one, batched = as_batch("v", [1.0, 2.0, 3.0], (3,))
    assert one.shape == (1, 3) and not batched
    many, batched = as_batch("v", np.zeros((5, 3)), (3,))
    assert many.shape == (5, 3) and batched
    with pytest.raises(InputError, match=r"v must have shape \(3,\) or \(n, 3\); got shape \(5, 4\)"):
        as_batch("v", np.zeros((5, 4)), (3,))


def test_scalar_checks():
    assert check_positive("mass", 2) == 2.0
    with pytest.raises(InputError, match="mass must be > 0 kg; got -1"):
        check_positive("mass", -1, unit="kg")
    with pytest.raises(InputError, match=r"inclination must be in \[0, 180\] deg; got 200"):
        check_range("inclination", 200, 0, 180, unit="deg")
    with pytest.raises(InputTypeError):
        check_positive("mass", True)
    with pytest.raises(InputError, match=r"n must be an integer in \[1, inf\]; got 0"):
        check_int("n", 0, minimum=1)
    with pytest.raises(InputError, match="method must be one of 'a', 'b'; got 'c'"):
        check_choice("method", "c", {"a": 1, "b": 2})


def test_as_rng_is_reproducible():
    assert as_rng(3).random() == np.random.default_rng(3).random()
    assert as_rng(None).random() == np.random.default_rng(0).random()
    g = np.random.default_rng(1)
    assert as_rng(g) is g
    with pytest.raises(InputError):
        as_rng(-1)
    with pytest.raises(InputTypeError):
        as_rng("seed")
