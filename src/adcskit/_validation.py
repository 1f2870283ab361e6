"""Boundary validation helpers shared by every public API.

Public functions call these at their boundary and then hand plain ``float64`` arrays to the
private kernels (house style rule 1 of ``design.md``). Every failure raises
:class:`adcskit.errors.InputError` or :class:`adcskit.errors.InputTypeError` with a message
of the form ``"<name> must be <what is allowed>; got <value>"``.
"""

from __future__ import annotations

import numbers
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from adcskit.errors import InputError, InputTypeError

__all__ = [
    "as_array",
    "as_batch",
    "as_rng",
    "check_choice",
    "check_finite",
    "check_int",
    "check_positive",
    "check_range",
    "short_repr",
]


def short_repr(value: Any, limit: int = 80) -> str:
    """Repr of ``value`` cut to ``limit`` characters, for error messages."""
    if isinstance(value, np.ndarray):
        text = f"array of shape {value.shape}, dtype {value.dtype}"
        if value.size <= 8:
            text += f": {np.array2string(value, precision=6, separator=', ')}"
        return text
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _describe_shape(shape: tuple[int | None, ...]) -> str:
    return "(" + ", ".join("n" if s is None else str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"


def as_array(
    name: str,
    value: Any,
    *,
    shape: tuple[int | None, ...] | None = None,
    ndim: int | Iterable[int] | None = None,
    finite: bool = True,
    dtype: Any = np.float64,
) -> np.ndarray:
    """Convert ``value`` to a new ``dtype`` array and check its shape and finiteness.

    Parameters
    ----------
    name : str
        Parameter name used in error messages.
    value : array_like
        Input value. It is copied, never modified.
    shape : tuple of int or None, optional
        Required shape; ``None`` entries accept any length.
    ndim : int or iterable of int, optional
        Allowed numbers of dimensions.
    finite : bool
        Reject NaN and infinities.
    dtype : numpy dtype
        Target dtype (``float64`` by default).

    Returns
    -------
    numpy.ndarray
        A fresh array (never a view of the input).
    """
    try:
        arr = np.array(value, dtype=dtype, copy=True)
    except (TypeError, ValueError) as exc:
        raise InputTypeError(
            f"{name} must be an array of numbers; got {short_repr(value)} ({exc})"
        ) from None
    if ndim is not None:
        allowed = (ndim,) if isinstance(ndim, int) else tuple(ndim)
        if arr.ndim not in allowed:
            raise InputError(
                f"{name} must have {' or '.join(map(str, allowed))} dimension(s); "
                f"got shape {arr.shape}"
            )
    if shape is not None:
        ok = arr.ndim == len(shape) and all(s is None or s == a for s, a in zip(shape, arr.shape))
        if not ok:
            raise InputError(f"{name} must have shape {_describe_shape(shape)}; got shape {arr.shape}")
    if finite and np.issubdtype(arr.dtype, np.number) and not np.all(np.isfinite(arr)):
        bad = np.argwhere(~np.isfinite(arr))
        where = tuple(int(i) for i in bad[0]) if arr.ndim else ()
        raise InputError(
            f"{name} must be finite (no NaN or inf); got {arr[where] if arr.ndim else arr} "
            f"at index {where}"
        )
    return arr


def as_batch(
    name: str, value: Any, tail: tuple[int, ...], *, finite: bool = True
) -> tuple[np.ndarray, bool]:
    """Accept one item of shape ``tail`` or a batch ``(N, *tail)``.

    Returns the array reshaped to ``(N, *tail)`` and whether the input was batched, so that
    callers can return the same rank they were given.
    """
    arr = as_array(name, value, finite=finite)
    if arr.shape == tail:
        return arr.reshape((1, *tail)), False
    if arr.ndim == len(tail) + 1 and arr.shape[1:] == tail:
        return arr, True
    raise InputError(
        f"{name} must have shape {_describe_shape(tail)} or {_describe_shape((None, *tail))}; "
        f"got shape {arr.shape}"
    )


def check_finite(name: str, value: Any) -> float:
    """Return ``value`` as a finite float."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputTypeError(f"{name} must be a real number; got {short_repr(value)}")
    v = float(value)
    if not np.isfinite(v):
        raise InputError(f"{name} must be finite; got {v}")
    return v


def check_positive(name: str, value: Any, *, allow_zero: bool = False, unit: str = "") -> float:
    """Return ``value`` as a float that is > 0 (or >= 0 with ``allow_zero``)."""
    v = check_finite(name, value)
    if v < 0 or (v == 0 and not allow_zero):
        what = ">= 0" if allow_zero else "> 0"
        raise InputError(f"{name} must be {what}{' ' + unit if unit else ''}; got {v:g}")
    return v


def check_range(
    name: str,
    value: Any,
    lo: float,
    hi: float,
    *,
    unit: str = "",
    lo_open: bool = False,
    hi_open: bool = False,
) -> float:
    """Return ``value`` as a float inside ``[lo, hi]`` (ends open on request)."""
    v = check_finite(name, value)
    bad_lo = v <= lo if lo_open else v < lo
    bad_hi = v >= hi if hi_open else v > hi
    if bad_lo or bad_hi:
        interval = f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
        raise InputError(
            f"{name} must be in {interval}{' ' + unit if unit else ''}; got {v:g}"
        )
    return v


def check_int(name: str, value: Any, *, minimum: int | None = None, maximum: int | None = None) -> int:
    """Return ``value`` as an int inside ``[minimum, maximum]``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise InputTypeError(f"{name} must be an integer; got {short_repr(value)}")
    v = int(value)
    if (minimum is not None and v < minimum) or (maximum is not None and v > maximum):
        lo = "-inf" if minimum is None else str(minimum)
        hi = "inf" if maximum is None else str(maximum)
        raise InputError(f"{name} must be an integer in [{lo}, {hi}]; got {v}")
    return v


def check_choice(name: str, value: Any, allowed: Mapping[str, Any] | Iterable[str]) -> str:
    """Return ``value`` if it is one of ``allowed`` (a registry's keys), else list them."""
    keys = list(allowed.keys() if isinstance(allowed, Mapping) else allowed)
    if not isinstance(value, str) or value not in keys:
        raise InputError(
            f"{name} must be one of {', '.join(repr(k) for k in keys)}; got {short_repr(value)}"
        )
    return value


def as_rng(rng: Any) -> np.random.Generator:
    """Convert ``rng`` (None, int seed, SeedSequence or Generator) to a Generator.

    ``None`` means seed 0, not fresh entropy: adcskit results are reproducible by default.
    """
    if isinstance(rng, np.random.Generator):
        return rng
    if rng is None:
        return np.random.default_rng(0)
    if isinstance(rng, np.random.SeedSequence):
        return np.random.default_rng(rng)
    if isinstance(rng, numbers.Integral) and not isinstance(rng, bool):
        if int(rng) < 0:
            raise InputError(f"rng seed must be a non-negative integer; got {int(rng)}")
        return np.random.default_rng(int(rng))
    raise InputTypeError(
        "rng must be None, a non-negative int seed, a numpy SeedSequence or a numpy "
        f"Generator; got {short_repr(rng)}"
    )
