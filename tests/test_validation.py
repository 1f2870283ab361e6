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


# --- issue 12: the boundary layer's new mechanisms -------------------------------------------

from adcskit._validation import (  # noqa: E402
    check_callable,
    check_finite,
    check_flag,
    check_mapping,
    check_path,
    check_positive_array,
    check_real,
)


@pytest.mark.parametrize("value", [[1j, 0.0], np.array([1.0, 2.0], dtype=complex), [1.0, complex(1, 0)]])
def test_as_array_rejects_complex_even_with_zero_imaginary_part(value):
    with pytest.raises(InputTypeError, match="x must be real"):
        as_array("x", value)


@pytest.mark.parametrize("value", [None, "1.0", [1.0, None], [["a"]]])
def test_as_array_rejects_non_numbers_naming_the_parameter(value):
    with pytest.raises(InputTypeError, match="x must be an array of numbers"):
        as_array("x", value)


def test_as_array_empty_and_magnitude_guards():
    with pytest.raises(InputError, match="x must not be empty"):
        as_array("x", [])
    assert as_array("x", [], nonempty=False).shape == (0,)
    with pytest.raises(InputError, match=r"x must have entries of magnitude <= 1e\+150"):
        as_array("x", [1.0, 1e300])
    assert as_array("x", [1.0, 1e300], max_abs=None)[1] == 1e300
    assert np.isinf(as_array("x", [1.0, np.inf], finite=False)[1])  # inf is judged by finite only


def test_as_array_accepts_read_only_and_non_contiguous_arrays():
    a = np.arange(6.0)
    a.flags.writeable = False
    np.testing.assert_array_equal(as_array("x", a[::2]), [0.0, 2.0, 4.0])
    assert as_array("x", a).flags.writeable


def test_scalars_accept_zero_d_arrays_and_numpy_scalars():
    assert check_finite("x", np.array(2.5)) == 2.5
    assert check_int("n", np.array(3)) == 3 and check_int("n", np.int32(3)) == 3
    with pytest.raises(InputTypeError, match="n must be an integer"):
        check_int("n", np.array(3.0))
    with pytest.raises(InputTypeError, match="x must be a real number"):
        check_finite("x", 1 + 0j)
    with pytest.raises(InputError, match="x must have magnitude"):
        check_finite("x", 1e300)


@pytest.mark.parametrize("value", ["no", 1, 0, None, "True", np.array([True])])
def test_check_flag_accepts_only_booleans(value):
    with pytest.raises(InputTypeError, match="flag must be True or False"):
        check_flag("flag", value)


def test_check_flag_numpy_bool():
    assert check_flag("flag", np.True_) is True and check_flag("flag", np.array(False)) is False


def test_callable_mapping_real_and_positive_array():
    with pytest.raises(InputTypeError, match="fn must be a callable"):
        check_callable("fn", 3)
    assert check_callable("fn", None, allow_none=True) is None
    with pytest.raises(InputTypeError, match=r"m must be a mapping \(dict\)"):
        check_mapping("m", [1, 2])
    assert check_real("low", -np.inf) == -np.inf
    with pytest.raises(InputError, match="low must be a number or ±inf, not NaN"):
        check_real("low", np.nan)
    with pytest.raises(InputError, match="f_max must be > 0 N; got -1"):
        check_positive_array("f_max", [1.0, -1.0], unit="N")
    with pytest.raises(InputError, match=r"f_max must be a scalar or broadcast to shape \(3,\)"):
        check_positive_array("f_max", [1.0, 2.0], broadcast_to=(3,))
    with pytest.raises(InputError, match="f_max must be >= 1e-100 N"):
        check_positive_array("f_max", 5e-324, unit="N", min_value=1e-100)


def test_check_range_names_a_bound_that_is_another_parameter():
    with pytest.raises(InputError, match=r"t_window must be in \(0, t_final = 1\] s; got 2"):
        check_range("t_window", 2.0, 0.0, 1.0, unit="s", lo_open=True, hi_name="t_final")


def test_check_path(tmp_path):
    f = tmp_path / "f"
    f.write_text("x")
    assert check_path("p", str(f), must_exist=True, kind="file") == f
    with pytest.raises(InputTypeError, match="p must be a path"):
        check_path("p", None)
    with pytest.raises(InputError, match="p must be a directory"):
        check_path("p", f, kind="dir")
    with pytest.raises(InputError, match="an existing file"):
        check_path("p", f, writable_dir=True)
    with pytest.raises(InputError, match="is not a directory"):
        check_path("p", f / "sub", writable_dir=True)
    assert check_path("p", tmp_path / "new" / "dir", writable_dir=True) == tmp_path / "new" / "dir"
