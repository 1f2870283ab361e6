"""model-estimation's small LAPACK calls: through scipy's public functions vs LAPACK directly.

Two inner-loop calls of the study go to LAPACK directly since issue 24 item 1, each the routine
scipy's function calls, without its per-call checks: the filter step's Cholesky factor and solves
(``adcskit.estimation.kalman._cho_factor``/``_cho_solve``: ``dpotrf``/``dpotrs``, before
``scipy.linalg.cho_factor``/``cho_solve``) and the online adaptive GMRES's Hessenberg least
squares (``adcskit.estimation.identification._lstsq_tall``: ``dgelsd``, before
``scipy.linalg.lstsq``). This script runs one seed's worth of the model-estimation study's tasks
(every reading, case and method at full per-run sizes: 200 steps) in this process, alternately
with the scipy calls put back and with the direct LAPACK calls, and prints the process CPU time
(``time.process_time``) of each pass: pairs in alternating order (before/after, then
after/before, ...), medians, the load average; then, in one more pass each, the calls and the
wall time spent inside them, per helper. The outputs of the two variants are compared bit for bit (every
task's final errors and error histories).

Usage::

    PYTHONPATH=src python benchmarks/bench_estimation_lapack.py [--pairs 4] [--seeds 1]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

import numpy as np
import scipy.linalg as sla

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

from adcskit.estimation import identification, kalman  # noqa: E402
from adcskit.studies.model_estimation import experiment as ex  # noqa: E402
from adcskit.studies.model_estimation.config import Config  # noqa: E402

_LAPACK = (kalman._cho_factor, kalman._cho_solve, identification._lstsq_tall)
_SCIPY = (lambda S: sla.cho_factor(S, lower=True, check_finite=False),
          lambda cf, b: sla.cho_solve(cf, b, check_finite=False),
          lambda H, rhs: sla.lstsq(H, rhs, check_finite=False)[0])
_NAMES = ("Cholesky factor", "Cholesky solve", "Hessenberg lstsq")


def _install(variant) -> None:
    kalman._cho_factor, kalman._cho_solve, identification._lstsq_tall = variant


def _tasks(n_seeds: int) -> list[dict]:
    """The study's task list (as ``measure`` builds it) for ``n_seeds`` seeds of the default config."""
    cfg = Config(n_seeds=n_seeds)
    root = np.random.SeedSequence(12345)
    seeds = [int(s.generate_state(1)[0]) for s in root.spawn(n_seeds)]
    cap = {"S1-like Krylov": cfg.s1_krylov_maxiter}
    return [{"cfg": rcfg, "case": case, "sigma": sigma, "seed": seed, "index": i, "reading": reading,
             "krylov_maxiter": cap.get(reading)}
            for reading, (rcfg, sigma, cases) in ex._reading_plan(cfg).items() for case in cases
            for i, seed in enumerate(seeds)]


def _pass(variant, tasks):
    _install(variant)
    c0 = time.process_time()
    runs = [ex._run_task(t) for t in tasks]
    return time.process_time() - c0, runs


def _inside(variant, tasks) -> list[tuple[int, float]]:
    """Calls of each helper in one pass and the wall time spent inside them [s]
    (``perf_counter``: this VM books the CPU time of a call of microseconds in 4 ms ticks)."""
    acc = [[0, 0.0] for _ in variant]

    def timed(fn, c):
        def wrapped(*a):
            t0 = time.perf_counter()
            out = fn(*a)
            c[1] += time.perf_counter() - t0
            c[0] += 1
            return out
        return wrapped

    _pass(tuple(timed(fn, c) for fn, c in zip(variant, acc, strict=True)), tasks)
    return [(n, t) for n, t in acc]


def _same(a, b) -> bool:
    return all(ra.methods[m].final == rb.methods[m].final and np.array_equal(ra.methods[m].e2, rb.methods[m].e2)
               for ra, rb in zip(a, b, strict=True) for m in ra.methods)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--pairs", type=int, default=4)
    ap.add_argument("--seeds", type=int, default=1)
    args = ap.parse_args()
    tasks = _tasks(args.seeds)
    _pass(_LAPACK, tasks[:2])  # warm up imports and caches
    times: dict[str, list[float]] = {"scipy's functions (before)": [], "LAPACK directly (after)": []}
    names = list(times)
    ref = None
    loads = []
    for i in range(args.pairs):
        order = (0, 1) if i % 2 == 0 else (1, 0)
        for k in order:
            loads.append(os.getloadavg()[0])
            dt, runs = _pass(_SCIPY if k == 0 else _LAPACK, tasks)
            times[names[k]].append(dt)
            if ref is None:
                ref = runs
            elif not _same(ref, runs):
                print("OUTPUTS DIFFER between the variants")
                return 1
            print(f"pair {i + 1}: {names[k]:<27} {dt:7.2f} CPU-s")
    med = {k: statistics.median(v) for k, v in times.items()}
    b, a = med[names[0]], med[names[1]]
    print(f"{len(tasks)} tasks x {args.pairs} pairs; medians: before {b:.2f} CPU-s, after {a:.2f} CPU-s "
          f"({100 * (a - b) / b:+.1f} %); outputs bit-identical; load average {min(loads):.1f}-{max(loads):.1f}")
    for k, variant in ((0, _SCIPY), (1, _LAPACK)):
        for what, (n, t) in zip(_NAMES, _inside(variant, tasks), strict=True):
            print(f"inside the calls, one more pass: {names[k]:<27} {what:<17} {n:6d} calls, {t:.3f} s wall "
                  f"({1e6 * t / max(n, 1):.1f} us/call)")
    _install(_LAPACK)
    return 0


if __name__ == "__main__":
    sys.exit(main())
