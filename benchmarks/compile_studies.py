"""Which numba kernels a first ``adcskit reproduce`` compiles, and the CPU each costs.

Runs ``adcskit reproduce --quick --jobs 1`` (extra arguments are passed on: e.g. ``--only
closed-loop``) in this process from an empty numba cache (a new ``NUMBA_CACHE_DIR``) and times
``Dispatcher.compile`` per outermost call (:func:`_profiling.outermost_compiles`: a kernel that
compiles the dispatchers it calls counts once, with them). Prints the process's CPU seconds,
the part spent compiling, and the compiled kernels by CPU::

    python benchmarks/compile_studies.py            # from the repository root, installed adcskit

One process, one study at a time: what ``--jobs N`` adds (two studies that start together
compile the kernels they share twice; numba's cache has no cross-process lock) is not counted.
"""

from __future__ import annotations

import collections
import os
import sys
import tempfile
import time

os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="numba-cold-")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from numba.core.dispatcher import Dispatcher  # noqa: E402

from _profiling import outermost_compiles  # noqa: E402

_ROWS: dict[str, list] = collections.defaultdict(lambda: [0, 0.0])


def _record(name: str, compiled: bool, cpu: float, wall: float, thread: float) -> None:
    if compiled:
        _ROWS[name][0] += 1
        _ROWS[name][1] += cpu


def main(argv: list[str]) -> None:
    Dispatcher.compile = outermost_compiles(Dispatcher.compile, _record)
    from adcskit import cli

    out = tempfile.mkdtemp(prefix="compile-studies-")
    c0 = time.process_time()
    try:
        cli.main(["reproduce", "--quick", "--jobs", "1", "--out", out, *argv])
    except SystemExit:
        pass
    total = time.process_time() - c0
    compiled = sum(v[1] for v in _ROWS.values())
    print(f"process CPU {total:.1f} s, of it compiling {compiled:.1f} s (outputs in {out})")
    for name, (n, cpu) in sorted(_ROWS.items(), key=lambda kv: -kv[1][1]):
        print(f"{cpu:8.1f} s  {n:2d}x  {name}")


if __name__ == "__main__":
    main(sys.argv[1:])
