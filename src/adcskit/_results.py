"""Result plumbing shared by every layer: JSON conversion, ``to_dict`` and a short ``repr``.

This module sits at the bottom of the import layers (beside ``errors`` and ``_validation``):
any package may import it, it imports nothing from adcskit.

* :func:`to_jsonable` converts numpy scalars/arrays, tuples, dataclasses and non-finite floats
  into plain JSON values (the ``result.json`` writer and every generic ``to_dict`` use it).
* :class:`Result` is a small base for frozen, slotted result dataclasses: ``to_dict()`` maps
  every field, in declaration order, through :func:`to_jsonable`, and ``repr`` is the compact
  :func:`short_repr_result`. Declare subclasses with ``repr=False`` so that the dataclass does
  not replace that ``repr``.
* The dataclass-generated ``repr`` of a result prints every array in full, which floods a
  terminal or a notebook for a 10 000-sample batch. :func:`short_repr_result` prints each field
  compactly: arrays by shape and dtype (with their values when they have at most 6 elements),
  nested results by class name, long strings and sequences cut. Result classes with a
  hand-written ``to_dict`` opt in with :func:`compact_repr` (a class decorator applied above
  ``@dataclass``).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any, ClassVar, TypeVar

import numpy as np

__all__ = ["Result", "compact_repr", "short_repr_result", "to_jsonable"]

T = TypeVar("T")

_MAX_SMALL = 6
_MAX_TEXT = 60


def _field_repr(value: Any) -> str:
    if isinstance(value, np.ndarray):
        if value.size <= _MAX_SMALL:
            return np.array2string(value, precision=6, separator=", ", threshold=_MAX_SMALL)
        return f"<array shape={value.shape} dtype={value.dtype}>"
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return f"<{type(value).__name__}>"
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, str):
        text = value if len(value) <= _MAX_TEXT else value[: _MAX_TEXT - 3] + "..."
        return repr(text)
    if isinstance(value, list | tuple):
        if len(value) <= _MAX_SMALL and all(not isinstance(v, list | tuple | dict | np.ndarray) for v in value):
            inner = ", ".join(_field_repr(v) for v in value)
            return f"[{inner}]" if isinstance(value, list) else f"({inner}{',' if len(value) == 1 else ''})"
        return f"<{type(value).__name__} of {len(value)}>"
    if isinstance(value, dict):
        return f"<dict of {len(value)}>" if len(value) > _MAX_SMALL else repr(value)[:_MAX_TEXT]
    text = repr(value)
    return text if len(text) <= _MAX_TEXT else text[: _MAX_TEXT - 3] + "..."


def short_repr_result(obj: Any) -> str:
    """Compact one-line ``repr`` of a dataclass instance.

    >>> from dataclasses import dataclass
    >>> @compact_repr
    ... @dataclass(frozen=True)
    ... class Out:
    ...     x: np.ndarray
    ...     success: bool
    >>> Out(np.zeros((1000, 4)), True)
    Out(x=<array shape=(1000, 4) dtype=float64>, success=True)
    """
    parts = [f"{f.name}={_field_repr(getattr(obj, f.name))}" for f in dataclasses.fields(obj) if f.repr]
    return f"{type(obj).__name__}({', '.join(parts)})"


def compact_repr(cls: type[T]) -> type[T]:
    """Class decorator: give a dataclass the compact :func:`short_repr_result` ``repr``."""
    cls.__repr__ = short_repr_result  # type: ignore[method-assign]
    return cls


def to_jsonable(value: Any) -> Any:
    """Convert numpy scalars/arrays, tuples, dataclasses and non-finite floats for JSON.

    NaN and infinities become ``None`` (JSON has no NaN); arrays become nested lists; mappings
    get string keys; a dataclass with a ``to_dict`` method is converted through it, any other
    dataclass field by field.

    Examples
    --------
    >>> to_jsonable({"x": np.array([1.0, np.nan]), "n": np.int64(3), "ok": np.bool_(True)})
    {'x': [1.0, None], 'n': 3, 'ok': True}
    >>> to_jsonable((np.float32(0.5), float("inf")))
    [0.5, None]
    """
    if isinstance(value, Mapping):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        if hasattr(value, "to_dict"):
            return to_jsonable(value.to_dict())
        return {f.name: to_jsonable(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, np.ndarray):
        return to_jsonable(value.tolist())
    if isinstance(value, list | tuple):
        return [to_jsonable(v) for v in value]
    if isinstance(value, np.bool_ | bool):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, float | np.floating):
        v = float(value)
        return v if math.isfinite(v) else None
    return value


class Result:
    """Base of result dataclasses: a JSON-ready ``to_dict`` and the compact ``repr``.

    ``to_dict()`` returns ``{field: to_jsonable(value)}`` for every dataclass field in
    declaration order. Subclass it with ``@dataclass(frozen=True, slots=True, repr=False)``
    (``repr=False`` keeps this class's short ``repr``). Two class attributes declare the common
    departures from the plain field mapping:

    * ``_dict_exclude``: names of fields left out (large arrays, internal extras);
    * ``_dict_extra``: names of attributes (properties) appended after the fields.

    A result whose dictionary differs otherwise (renamed keys, a changed order, derived values
    in the middle) writes its own ``to_dict``.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True, slots=True, repr=False)
    ... class Fit(Result):
    ...     x: np.ndarray
    ...     success: bool
    ...     fun: float
    >>> r = Fit(x=np.zeros(1000), success=True, fun=float("nan"))
    >>> r
    Fit(x=<array shape=(1000,) dtype=float64>, success=True, fun=nan)
    >>> d = r.to_dict(); list(d), d["fun"], len(d["x"])
    (['x', 'success', 'fun'], None, 1000)
    >>> @dataclass(frozen=True, slots=True, repr=False)
    ... class Slim(Result):
    ...     x: np.ndarray
    ...     fun: float
    ...     _dict_exclude = ("x",)
    ...     _dict_extra = ("cost",)
    ...     @property
    ...     def cost(self):
    ...         return 2 * self.fun
    >>> Slim(x=np.zeros(1000), fun=np.float64(1.5)).to_dict()
    {'fun': 1.5, 'cost': 3.0}
    """

    __slots__ = ()

    #: Field names that ``to_dict`` leaves out.
    _dict_exclude: ClassVar[tuple[str, ...]] = ()
    #: Attribute names (e.g. properties) that ``to_dict`` appends after the fields.
    _dict_extra: ClassVar[tuple[str, ...]] = ()

    def to_dict(self) -> dict[str, Any]:
        """Every field in declaration order (less ``_dict_exclude``, plus ``_dict_extra``),
        converted by :func:`to_jsonable`."""
        skip = self._dict_exclude
        out = {f.name: to_jsonable(getattr(self, f.name)) for f in dataclasses.fields(self) if f.name not in skip}  # type: ignore[arg-type]
        for name in self._dict_extra:
            out[name] = to_jsonable(getattr(self, name))
        return out

    def __repr__(self) -> str:
        return short_repr_result(self)
