"""Boundary validation helpers shared by every public API.

Public functions call these at their boundary and then hand plain ``float64`` arrays to the
private kernels (house style rule 1 of ``docs/architecture.md``). Every failure raises
:class:`adcskit.errors.InputError` or :class:`adcskit.errors.InputTypeError` with a message
of the form ``"<name> must be <what is allowed>; got <value>"``.
"""

from __future__ import annotations

import numbers
import operator
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from adcskit.errors import InputError, InputTypeError

__all__ = [
    "as_array",
    "as_batch",
    "as_rng",
    "check_callable",
    "check_choice",
    "check_finite",
    "check_flag",
    "check_int",
    "check_magnitude",
    "check_mapping",
    "check_path",
    "check_positive",
    "check_positive_array",
    "check_range",
    "check_real",
    "short_repr",
]

#: Largest magnitude accepted by :func:`check_magnitude` by default: squares and products of
#: two such numbers stay finite in float64 (``1e150 ** 2 = 1e300 < 1.8e308``).
MAX_MAGNITUDE = 1e150


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
    nonempty: bool = True,
    max_abs: float | None = MAX_MAGNITUDE,
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
    nonempty : bool
        Reject arrays with no elements (default); pass ``False`` where an empty array is a
        meaningful input (e.g. an empty batch).
    max_abs : float or None
        Reject entries whose magnitude exceeds this bound (a guard against overflow in
        quantities derived from the array, e.g. squares of 1e300). Defaults to
        ``MAX_MAGNITUDE`` (1e150); applies to the finite entries; ``None`` disables it.

    Returns
    -------
    numpy.ndarray
        A fresh array (never a view of the input).

    Notes
    -----
    ``None``, strings, complex numbers (even with zero imaginary part) and objects that are not
    numbers raise :class:`~adcskit.errors.InputTypeError`: a complex value is never silently
    truncated to its real part. Booleans are accepted as 0/1 only where ``dtype`` is ``bool``.
    """
    if value is None:
        raise InputTypeError(f"{name} must be an array of numbers; got None")
    if isinstance(value, (str, bytes)):
        raise InputTypeError(f"{name} must be an array of numbers; got {short_repr(value)}")
    try:
        probe = value if isinstance(value, np.ndarray) else np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise InputTypeError(
            f"{name} must be an array of numbers; got {short_repr(value)} ({_first_line(exc)})"
        ) from None
    if np.iscomplexobj(probe) or (
        probe.dtype == object and any(isinstance(v, complex) for v in probe.ravel().tolist())
    ):
        raise InputTypeError(
            f"{name} must be real (complex values are not accepted); got {short_repr(value)}"
        )
    if probe.dtype.kind == "b" and np.dtype(dtype).kind != "b":
        # True/False for a number would silently mean 1/0 (a flag passed in the wrong place)
        raise InputTypeError(f"{name} must be an array of numbers, not True/False; got {short_repr(value)}")
    if probe.dtype.kind in "USV" or (
        probe.dtype == object and any(v is None or isinstance(v, (str, bytes)) for v in probe.ravel().tolist())
    ):
        raise InputTypeError(f"{name} must be an array of numbers; got {short_repr(value)}")
    try:
        # complex values were refused above, so the conversion cannot drop an imaginary part;
        # a probe freshly built from a list is converted in place of a second copy
        arr = np.array(probe, dtype=dtype, copy=probe is value or probe.dtype != dtype)
        if arr is value:
            arr = arr.copy()
    except (TypeError, ValueError, OverflowError) as exc:
        raise InputTypeError(
            f"{name} must be an array of numbers; got {short_repr(value)} ({_first_line(exc)})"
        ) from None
    if nonempty and arr.size == 0:
        raise InputError(f"{name} must not be empty; got shape {arr.shape}")
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
    if not (arr.size and np.issubdtype(arr.dtype, np.number)):
        return arr
    amax = max(arr.max(), -arr.min())  # no temporary array; NaN propagates, inf shows as inf
    if finite and not np.isfinite(amax):
        bad = np.argwhere(~np.isfinite(arr))
        where = tuple(int(i) for i in bad[0]) if arr.ndim else ()
        raise InputError(
            f"{name} must be finite (no NaN or inf); got {arr[where] if arr.ndim else arr} "
            f"at index {where}"
        )
    if max_abs is not None and not amax <= max_abs:
        big = np.isfinite(arr) & (np.abs(arr) > max_abs)  # inf is judged by ``finite`` alone
        if np.any(big):
            where = tuple(int(i) for i in np.argwhere(big)[0]) if arr.ndim else ()
            raise InputError(
                f"{name} must have entries of magnitude <= {max_abs:g} (larger values overflow "
                f"derived quantities); got "
                f"{arr[where] if arr.ndim else arr:g} at index {where}"
            )
    return arr


def _first_line(exc: BaseException) -> str:
    return str(exc).splitlines()[0] if str(exc) else type(exc).__name__


def _as_scalar(value: Any) -> Any:
    """Unwrap a 0-d numpy array (or a size-1 numpy scalar) to its Python scalar."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        return value[()]
    return value


def as_batch(
    name: str,
    value: Any,
    tail: tuple[int, ...],
    *,
    finite: bool = True,
    max_abs: float | None = MAX_MAGNITUDE,
) -> tuple[np.ndarray, bool]:
    """Accept one item of shape ``tail`` or a batch ``(N, *tail)``.

    Returns the array reshaped to ``(N, *tail)`` and whether the input was batched, so that
    callers can return the same rank they were given.
    """
    arr = as_array(name, value, finite=finite, max_abs=max_abs, nonempty=False)
    if arr.shape == tail:
        return arr.reshape((1, *tail)), False
    if arr.ndim == len(tail) + 1 and arr.shape[1:] == tail:
        return arr, True
    raise InputError(
        f"{name} must have shape {_describe_shape(tail)} or {_describe_shape((None, *tail))}; "
        f"got shape {arr.shape}"
    )


def check_finite(name: str, value: Any, *, max_abs: float | None = MAX_MAGNITUDE) -> float:
    """Return ``value`` as a finite float.

    Accepts Python and numpy real numbers and 0-d real arrays; rejects ``bool``, complex
    numbers, strings and ``None`` with :class:`~adcskit.errors.InputTypeError`. Magnitudes
    above ``max_abs`` (default ``MAX_MAGNITUDE`` = 1e150) are rejected as a guard against
    overflow in derived quantities; ``None`` disables the guard.
    """
    value = _as_scalar(value)
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise InputTypeError(f"{name} must be a real number; got {short_repr(value)}")
    try:
        v = float(value)
    except (OverflowError, ValueError, TypeError):
        raise InputError(f"{name} must be a finite real number; got {short_repr(value)}") from None
    if not np.isfinite(v):
        raise InputError(f"{name} must be finite; got {v}")
    if max_abs is not None and abs(v) > max_abs:
        raise InputError(
            f"{name} must have magnitude <= {max_abs:g} (larger values overflow derived "
            f"quantities); got {v:g}"
        )
    return v


def check_real(name: str, value: Any, *, max_abs: float | None = MAX_MAGNITUDE) -> float:
    """Return ``value`` as a float that may be ±inf (an unbounded limit) but not NaN."""
    value = _as_scalar(value)
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise InputTypeError(f"{name} must be a real number (or ±inf); got {short_repr(value)}")
    v = float(value)
    if np.isnan(v):
        raise InputError(f"{name} must be a number or ±inf, not NaN; got {v}")
    if max_abs is not None and np.isfinite(v) and abs(v) > max_abs:
        raise InputError(f"{name} must have magnitude <= {max_abs:g} or be ±inf; got {v:g}")
    return v


def check_magnitude(name: str, value: Any, *, max_abs: float = MAX_MAGNITUDE, unit: str = "") -> float:
    """Return ``value`` as a finite float with ``|value| <= max_abs`` (overflow guard)."""
    v = check_finite(name, value, max_abs=None)
    if abs(v) > max_abs:
        raise InputError(
            f"{name} must have magnitude <= {max_abs:g}{' ' + unit if unit else ''}; got {v:g}"
        )
    return v


def check_positive(
    name: str,
    value: Any,
    *,
    allow_zero: bool = False,
    unit: str = "",
    max_value: float | None = None,
    min_value: float | None = None,
) -> float:
    """Return ``value`` as a float that is > 0 (or >= 0 with ``allow_zero``).

    ``max_value`` and ``min_value`` optionally bound it further (guards against overflow or
    underflow of derived quantities, e.g. ``1 / 1e-300``); the unit is named in the message.
    """
    v = check_finite(name, value)
    u = " " + unit if unit else ""
    if v < 0 or (v == 0 and not allow_zero):
        what = ">= 0" if allow_zero else "> 0"
        raise InputError(f"{name} must be {what}{u}; got {v:g}")
    if max_value is not None and v > max_value:
        raise InputError(f"{name} must be <= {max_value:g}{u}; got {v:g}")
    if min_value is not None and 0 < v < min_value:
        raise InputError(f"{name} must be 0 or >= {min_value:g}{u}; got {v:g}"
                         if allow_zero else f"{name} must be >= {min_value:g}{u}; got {v:g}")
    return v


def check_positive_array(
    name: str,
    value: Any,
    *,
    allow_zero: bool = False,
    unit: str = "",
    broadcast_to: tuple[int, ...] | None = None,
    max_value: float | None = None,
    min_value: float | None = None,
) -> np.ndarray:
    """A float array (scalar or array) of physical quantities that are > 0 (>= 0).

    With ``broadcast_to``, the value must broadcast to that shape (a per-item array or one
    scalar for all); the broadcast copy is returned. ``min_value`` rejects positive values
    below it (a floor for quantities used as divisors). The unit is named in messages.
    """
    arr = as_array(name, value)
    u = " " + unit if unit else ""
    bad = arr < 0 if allow_zero else arr <= 0
    if np.any(bad):
        what = ">= 0" if allow_zero else "> 0"
        raise InputError(f"{name} must be {what}{u}; got {arr[bad].ravel()[0]:g}")
    if min_value is not None and np.any((arr > 0) & (arr < min_value)):
        raise InputError(f"{name} must be >= {min_value:g}{u} (it divides other quantities); got "
                         f"{arr[(arr > 0) & (arr < min_value)].ravel()[0]:g}")
    if max_value is not None and np.any(arr > max_value):
        raise InputError(f"{name} must be <= {max_value:g}{u}; got {arr.max():g}")
    if broadcast_to is not None:
        try:
            arr = np.broadcast_to(arr, broadcast_to).copy()
        except ValueError:
            raise InputError(
                f"{name} must be a scalar or broadcast to shape {broadcast_to}; got shape {arr.shape}"
            ) from None
    return arr


def check_range(
    name: str,
    value: Any,
    lo: float,
    hi: float,
    *,
    unit: str = "",
    lo_open: bool = False,
    hi_open: bool = False,
    lo_name: str = "",
    hi_name: str = "",
) -> float:
    """Return ``value`` as a float inside ``[lo, hi]`` (ends open on request).

    ``lo_name``/``hi_name`` name a bound that is another parameter (e.g. ``"t_final"``), so
    that the message blames the relation rather than only this parameter.
    """
    v = check_finite(name, value)
    bad_lo = v <= lo if lo_open else v < lo
    bad_hi = v >= hi if hi_open else v > hi
    if bad_lo or bad_hi:
        lo_txt = f"{lo_name} = {lo:g}" if lo_name else f"{lo:g}"
        hi_txt = f"{hi_name} = {hi:g}" if hi_name else f"{hi:g}"
        interval = f"{'(' if lo_open else '['}{lo_txt}, {hi_txt}{')' if hi_open else ']'}"
        raise InputError(
            f"{name} must be in {interval}{' ' + unit if unit else ''}; got {v:g}"
        )
    return v


def check_int(name: str, value: Any, *, minimum: int | None = None, maximum: int | None = None) -> int:
    """Return ``value`` as an int inside ``[minimum, maximum]``.

    Accepts anything :func:`operator.index` accepts (Python and numpy integers, 0-d integer
    arrays) except ``bool``.
    """
    value = _as_scalar(value)
    if isinstance(value, (bool, np.bool_)):
        raise InputTypeError(f"{name} must be an integer; got {short_repr(value)}")
    try:
        v = operator.index(value)
    except TypeError:
        raise InputTypeError(f"{name} must be an integer; got {short_repr(value)}") from None
    if (minimum is not None and v < minimum) or (maximum is not None and v > maximum):
        lo = "-inf" if minimum is None else str(minimum)
        hi = "inf" if maximum is None else str(maximum)
        raise InputError(f"{name} must be an integer in [{lo}, {hi}]; got {v}")
    return v


#: Unit suffixes of config keys (``inertia_kgm2``, ``delay_s``, ...; docs/architecture.md, "Conventions").
UNIT_SUFFIXES = frozenset({
    "s", "ms", "hz", "deg", "rad", "rad_s", "deg_s", "m", "km", "m_s", "n", "nm", "kgm2", "kg", "kg_s",
    "pct", "t", "nm_per_rad", "deg_per_pct",
})


def did_you_mean(value: Any, allowed: Iterable[str]) -> str:
    """``" (did you mean 'x'?)"`` for the closest of ``allowed`` to a mistyped ``value``, else ``""``.

    A name without its unit suffix (an old config key such as ``inertia`` for
    ``inertia_kgm2``) is matched to the suffixed name first, whatever else is close.

    >>> did_you_mean("inertia", ["inertia_error", "inertia_axes", "inertia_kgm2"])
    " (did you mean 'inertia_kgm2'?)"
    >>> did_you_mean("n_seed", ["n_seeds", "n_steps"])
    " (did you mean 'n_seeds'?)"
    """
    import difflib

    if not isinstance(value, str):
        return ""
    names = [str(a) for a in allowed]
    suffixed = [a for a in names if a.startswith(value + "_") and a[len(value) + 1:] in UNIT_SUFFIXES]
    if len(suffixed) == 1:
        return f" (did you mean {suffixed[0]!r}?)"
    close = difflib.get_close_matches(value, names, n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def check_choice(name: str, value: Any, allowed: Mapping[str, Any] | Iterable[str]) -> str:
    """Return ``value`` if it is one of ``allowed`` (a registry's keys), else list them.

    >>> check_choice("method", "q-methd", ["q-method", "triad"])
    Traceback (most recent call last):
    ...
    adcskit.errors.InputError: method must be one of 'q-method', 'triad'; got 'q-methd' (did you mean 'q-method'?)
    """
    keys = list(allowed.keys() if isinstance(allowed, Mapping) else allowed)
    if not isinstance(value, str) or value not in keys:
        raise InputError(
            f"{name} must be one of {', '.join(repr(k) for k in keys)}; got {short_repr(value)}"
            + did_you_mean(value, keys)
        )
    return value


def check_flag(name: str, value: Any) -> bool:
    """Return ``value`` as a ``bool``; only ``bool`` and ``numpy.bool_`` are accepted.

    Truthy stand-ins such as ``"no"``, ``1`` or ``None`` are rejected: ``"no"`` is truthy, so
    accepting it would silently do the opposite of what the caller wrote.
    """
    value = _as_scalar(value)
    if not isinstance(value, (bool, np.bool_)):
        raise InputTypeError(f"{name} must be True or False; got {short_repr(value)}")
    return bool(value)


def check_flag_fields(obj: Any) -> None:
    """Check (and store as ``bool``) every field of a frozen dataclass annotated ``bool``.

    For a ``__post_init__``: a configuration's flags get :func:`check_flag`'s rule (``"no"``,
    ``1`` or ``None`` for a flag are errors) without one call per field.

    >>> import dataclasses
    >>> @dataclasses.dataclass(frozen=True)
    ... class Spec:
    ...     verbose: bool = False
    ...     def __post_init__(self):
    ...         check_flag_fields(self)
    >>> Spec(verbose="no")
    Traceback (most recent call last):
    ...
    adcskit.errors.InputTypeError: verbose must be True or False; got 'no'
    """
    import dataclasses

    for f in dataclasses.fields(obj):
        if f.type in (bool, "bool"):
            object.__setattr__(obj, f.name, check_flag(f.name, getattr(obj, f.name)))


def check_callable(name: str, value: Any, *, allow_none: bool = False) -> Any:
    """Return ``value`` if it is callable (or ``None`` with ``allow_none``)."""
    if value is None and allow_none:
        return None
    if not callable(value):
        allowed = "a callable or None" if allow_none else "a callable"
        raise InputTypeError(f"{name} must be {allowed}; got {short_repr(value)}")
    return value


def check_mapping(name: str, value: Any, *, allow_none: bool = False) -> Any:
    """Return ``value`` if it is a mapping (or ``None`` with ``allow_none``)."""
    if value is None and allow_none:
        return None
    if not isinstance(value, Mapping):
        allowed = "a mapping (dict) or None" if allow_none else "a mapping (dict)"
        raise InputTypeError(f"{name} must be {allowed}; got {short_repr(value)}")
    return value


def check_path(
    name: str,
    value: Any,
    *,
    must_exist: bool = False,
    kind: str | None = None,
    writable_dir: bool = False,
) -> Path:
    """Return ``value`` as a :class:`pathlib.Path` after checking it can be used.

    Parameters
    ----------
    name : str
        Parameter name used in error messages.
    value : str or os.PathLike
        The path.
    must_exist : bool
        Require the path to exist.
    kind : {"file", "dir"}, optional
        Require an existing path to be a regular file or a directory.
    writable_dir : bool
        The path is a directory that will be created if missing and written into: it must
        not be an existing non-directory, and its nearest existing ancestor must be a
        writable directory. Nothing is created here.
    """
    if isinstance(value, (bytes, bool)) or not isinstance(value, (str, os.PathLike)):
        raise InputTypeError(f"{name} must be a path (str or os.PathLike); got {short_repr(value)}")
    path = Path(os.fspath(value))
    if str(value) == "" or "\x00" in str(value):
        raise InputError(f"{name} must be a non-empty path without NUL characters; got {short_repr(value)}")
    exists = path.exists()
    if must_exist and not exists:
        raise InputError(f"{name} must be an existing {kind or 'path'}; got {str(path)!r} (not found)")
    if exists and kind == "file" and not path.is_file():
        raise InputError(f"{name} must be a regular file; got {str(path)!r} (a directory or special file)")
    if exists and kind == "dir" and not path.is_dir():
        raise InputError(f"{name} must be a directory; got {str(path)!r} (not a directory)")
    if writable_dir:
        if exists and not path.is_dir():
            raise InputError(f"{name} must be a directory or a path that can be created; got "
                             f"{str(path)!r} (an existing file)")
        probe = path if exists else path.parent
        while not probe.exists() and probe != probe.parent:
            probe = probe.parent
        if not probe.is_dir():
            raise InputError(f"{name} cannot be created: {str(probe)!r} is not a directory; got {str(path)!r}")
        if not os.access(probe, os.W_OK | os.X_OK):
            raise InputError(f"{name} is not writable: no write permission on {str(probe)!r}; got {str(path)!r}")
    return path


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
    rng = _as_scalar(rng)
    if isinstance(rng, numbers.Integral) and not isinstance(rng, (bool, np.bool_)):
        if int(rng) < 0:
            raise InputError(f"rng seed must be a non-negative integer; got {int(rng)}")
        return np.random.default_rng(int(rng))
    raise InputTypeError(
        "rng must be None, a non-negative int seed, a numpy SeedSequence or a numpy "
        f"Generator; got {short_repr(rng)}"
    )
