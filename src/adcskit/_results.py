"""Short ``repr`` for result dataclasses (issue 16: reprs of large results are short).

The dataclass-generated ``repr`` of a result prints every array in full, which floods a
terminal or a notebook for a 10 000-sample batch. :func:`short_repr_result` prints each field
compactly: arrays by shape and dtype (with their values when they have at most 6 elements),
nested results by class name, long strings and sequences cut. Result classes opt in with
:func:`compact_repr` (a class decorator applied above ``@dataclass``).
"""

from __future__ import annotations

import dataclasses
from typing import Any, TypeVar

import numpy as np

__all__ = ["compact_repr", "short_repr_result"]

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
