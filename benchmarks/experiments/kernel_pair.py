"""Two samples per loop iteration: does the closed-loop kernel gain from interleaving them?

``sample_loop`` advances one sample over all steps; its work is chains of dependent operations
(the RK4 stages, the MEKF's covariance, libm calls). If those chains, not the instruction
count, set its speed, two independent samples advanced step by step in one loop body would
overlap. This script generates that loop from ``sample_loop``'s own source (``ast``: every
local name gets a second copy for the second sample; the setup, the two halves of the step
around its ``break`` and the write-out are duplicated; the step index ``k`` is shared),
compiles it as ``SAMPLE`` is compiled (no reference counting, ``error_model="numpy"``), checks
that it writes the same bytes as the one-sample loop (``OUT``, ``TOT``) on the arguments of a
captured ``simulate`` call (64 samples of bench_basilisk.py's scenario), and times both
drivers on one thread, alternated: best and median sample-steps per CPU-second::

    PYTHONPATH=src python benchmarks/experiments/kernel_pair.py full 10

Results: docs/benchmarks.md, "Two cores per CPU-second" (tried and not kept). Since the
lane blocks (2026-12-03) the CPU driver runs ``block_loop``, not ``sample_loop``; this script
still compares its two-sample loop with the one-sample loop it was generated from.
"""

from __future__ import annotations

import ast
import copy
import inspect
import os
import statistics
import sys
import textwrap
import time
import warnings

import numba
from numba import njit, uint64
from numba.core.errors import NumbaIRAssumptionWarning

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # benchmarks/
from adcskit._targets import PerSample  # noqa: E402
from adcskit.simulation import _kernels as K  # noqa: E402
from adcskit.simulation import core, simulate  # noqa: E402
from bench_basilisk import _speed_scenarios  # noqa: E402


class _Second(ast.NodeTransformer):
    """Renames the given local names ``x`` to ``x_b`` (the second sample's copy)."""

    def __init__(self, names):
        self.names = names

    def visit_Name(self, node):
        if node.id in self.names:
            return ast.copy_location(ast.Name(id=node.id + "_b", ctx=node.ctx), node)
        return node


def pair_source() -> ast.Module:
    """``sample_pair(i, i_b, ...)``: sample_loop for samples i and i_b, interleaved per step."""
    fn = ast.parse(textwrap.dedent(inspect.getsource(K.sample_loop))).body[0]
    local = {n.id for n in ast.walk(fn) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)}
    local = (local | {"i"}) - {"k"}

    def second(stmts):
        return [_Second(local).visit(copy.deepcopy(s)) for s in stmts]

    body = [s for s in fn.body if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant))]
    at = next(n for n, s in enumerate(body) if isinstance(s, ast.For))
    setup, loop, tail = body[:at], body[at], body[at + 1:]
    cut = next(n for n, s in enumerate(loop.body) if isinstance(s, ast.If) and isinstance(s.body[0], ast.Break))
    pre, brk, post = loop.body[:cut], loop.body[cut], loop.body[cut + 1:]
    loop = copy.deepcopy(loop)
    loop.body = pre + second(pre) + [brk] + post + second(post)
    fn.body = setup + second(setup) + [loop] + tail + second(tail)
    fn.name = "sample_pair"
    fn.args.args.insert(1, ast.arg(arg="i_b"))
    fn.decorator_list = []
    return ast.fix_missing_locations(ast.Module(body=[fn], type_ignores=[]))


def build():
    ns = dict(K.__dict__)
    exec(compile(pair_source(), "<sample_pair>", "exec"), ns)
    pair = PerSample(ns["sample_pair"], cache=False, inline="never", error_model="numpy", nrt=False).cpu
    loop = K.sample_loop_jit

    @njit(nogil=True)
    def run_pairs(A):
        for h in range(A.P.shape[0] // 2):
            pair(uint64(2 * h), uint64(2 * h + 1), A)

    @njit(nogil=True)
    def run_single(A):
        for h in range(A.P.shape[0]):
            loop(uint64(h), A)

    return run_single, run_pairs


def captured_args(scenario):
    """The kernel's arrays (``K.Arrays``) of the call of ``simulate(scenario, 64)`` (one chunk)."""
    box = {}
    orig = core._k.run_parallel

    def spy(size, A):
        box["args"] = K.Arrays(*(x.copy() for x in A))
        return orig(size, A)

    core._k.run_parallel = spy
    try:
        simulate(scenario, 64, rng=5, chunk_size=64)
    finally:
        core._k.run_parallel = orig
    return box["args"]


def main() -> None:
    numba.set_num_threads(1)
    # numba's pedantic IR check on the inlined step functions' copies (harmless)
    warnings.simplefilter("ignore", NumbaIRAssumptionWarning)
    same, full = _speed_scenarios(150.0)
    scenario = {"full": full, "same": same}[sys.argv[1] if len(sys.argv) > 1 else "full"]
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 10
    args = captured_args(scenario)

    def fresh():
        return K.Arrays(*(x.copy() for x in args))

    run_single, run_pairs = build()
    a1, a2 = fresh(), fresh()
    run_single(a1)
    run_pairs(a2)
    for name in ("OUT", "TOT"):
        same = getattr(a1, name).tobytes() == getattr(a2, name).tobytes()
        print(f"{name}: the same bytes from both drivers: {same}")
    steps = args.P.shape[0] * int(args.C[K.N_STEPS])
    rates = {"single": [], "pairs": []}
    for r in range(rounds):
        order = ("single", "pairs") if r % 2 == 0 else ("pairs", "single")
        for name in order:
            a = fresh()
            c0 = time.process_time()
            (run_single if name == "single" else run_pairs)(a)
            rates[name].append(steps / (time.process_time() - c0))
    s, p = rates["single"], rates["pairs"]
    print(f"one sample: best {max(s):.3g}, median {statistics.median(s):.3g}; two interleaved: best "
          f"{max(p):.3g}, median {statistics.median(p):.3g} sample-steps per CPU-second; ratio best "
          f"{max(p) / max(s):.3f}, median {statistics.median(p) / statistics.median(s):.3f}")


if __name__ == "__main__":
    main()
