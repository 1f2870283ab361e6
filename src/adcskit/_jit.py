"""Whether a numba kernel will compile on its next call (for an honest "compiling once" notice).

numba compiles a dispatcher on its first call in a process unless its on-disk cache
(``cache=True``: an index ``*.nbi`` in the module's ``__pycache__`` and one ``*.nbc`` file
per compiled signature) holds an entry that numba will accept: one written from the same
source file (numba's source stamp; in numba 0.68 a SHA-256 of the file's contents), for the
same numba version, for this machine's
code generator and for the function's current bytecode. :func:`will_compile` applies the same
tests to the index as numba's own loader (``numba.core.caching.IndexDataCacheFile``), so a
notice printed from it is not printed on a warm cache and is printed after an edit of the
kernel's source or a numba upgrade.

Reading the index uses numba's cache objects (``dispatcher._cache``), which are not public
API; if they change shape, :func:`will_compile` answers ``None`` (unknown) and no notice is
printed rather than a wrong one.
"""

from __future__ import annotations

import hashlib
from typing import Any

__all__ = ["will_compile", "CLOSED_LOOP_NOTICE"]

#: One-line notice before the closed-loop simulator compiles (the cold compile time is measured in docs/benchmarks.md, "Compile time of the kernels").
CLOSED_LOOP_NOTICE = "compiling the closed-loop simulator once, about 1-2 min; cached afterwards"


def will_compile(dispatcher: Any) -> bool | None:
    """``True`` if calling ``dispatcher`` now compiles it, ``False`` if it is already compiled
    in this process or its disk cache holds a usable entry, ``None`` if that cannot be told.

    Examples
    --------
    >>> import numba
    >>> f = numba.njit(lambda x: x + 1)          # no disk cache: the first call compiles
    >>> will_compile(f)
    True
    >>> f(1), will_compile(f)
    (2, False)
    """
    try:
        if dispatcher.signatures:
            return False
        cache = getattr(dispatcher, "_cache", None)
        if cache is None or type(cache).__name__ == "NullCache" or not getattr(cache, "_enabled", False):
            return True
        overloads = cache._cache_file._load_index()  # {} when absent, stale or another numba version
        if not overloads:
            return True
        magic = dispatcher.targetctx.codegen().magic_tuple()
        code = hashlib.sha256(dispatcher.py_func.__code__.co_code).hexdigest()
        for key in overloads:
            if key[1] == magic and key[2][0] == code:
                return False
        return True
    except Exception:  # noqa: BLE001 - numba internals changed: say nothing rather than something wrong
        return None
