"""The filter step's Cholesky calls in model-estimation: scipy's ``cho_factor``/``cho_solve`` vs LAPACK.

``adcskit.estimation.kalman`` factors the innovation covariance and solves with it once per
filter step through ``dpotrf``/``dpotrs`` directly (issue 24 item 1); before, it called
``scipy.linalg.cho_factor``/``cho_solve``, which run the same LAPACK routines after ~12 µs of
per-call checks. This script runs one seed's worth of the model-estimation study's tasks
(every reading, case and method at full per-run sizes: 200 steps) in this process, alternately
with the scipy calls put back and with the direct LAPACK calls, and prints the process CPU time
(``time.process_time``) of each pass: pairs in alternating order (before/after, then
after/before, ...), medians, the load average; then, in one more pass each, the calls and the
wall time spent inside them. The outputs of the two variants are compared bit for bit (every
task's final errors and error histories).

Usage::

    PYTHONPATH=src python benchmarks/bench_kalman_cholesky.py [--pairs 4] [--seeds 1]
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

from adcskit.estimation import kalman  # noqa: E402
from adcskit.studies.model_estimation import experiment as ex  # noqa: E402
from adcskit.studies.model_estimation.config import Config  # noqa: E402

_LAPACK = (kalman._cho_factor, kalman._cho_solve)
_SCIPY = (lambda S: sla.cho_factor(S, lower=True, check_finite=False),
          lambda cf, b: sla.cho_solve(cf, b, check_finite=False))


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
    kalman._cho_factor, kalman._cho_solve = variant
    c0 = time.process_time()
    runs = [ex._run_task(t) for t in tasks]
    return time.process_time() - c0, runs


def _inside(variant, tasks) -> tuple[int, float]:
    """Calls of the Cholesky helpers in one pass and the wall time spent inside them [s]
    (``perf_counter``: this VM books the CPU time of a call of microseconds in 4 ms ticks)."""
    n, t = [0], [0.0]

    def timed(fn):
        def wrapped(*a):
            t0 = time.perf_counter()
            out = fn(*a)
            t[0] += time.perf_counter() - t0
            n[0] += 1
            return out
        return wrapped

    _pass((timed(variant[0]), timed(variant[1])), tasks)
    return n[0], t[0]


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
    times: dict[str, list[float]] = {"scipy cho_factor/cho_solve (before)": [], "LAPACK dpotrf/dpotrs (after)": []}
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
            print(f"pair {i + 1}: {names[k]:<38} {dt:7.2f} CPU-s")
    med = {k: statistics.median(v) for k, v in times.items()}
    b, a = med[names[0]], med[names[1]]
    print(f"{len(tasks)} tasks x {args.pairs} pairs; medians: before {b:.2f} CPU-s, after {a:.2f} CPU-s "
          f"({100 * (a - b) / b:+.1f} %); outputs bit-identical; load average {min(loads):.1f}-{max(loads):.1f}")
    for k, variant in ((0, _SCIPY), (1, _LAPACK)):
        n, t = _inside(variant, tasks)
        print(f"inside the calls, one more pass: {names[k]:<38} {n} calls, {t:.3f} s wall ({1e6 * t / n:.1f} us/call)")
    kalman._cho_factor, kalman._cho_solve = _LAPACK
    return 0


if __name__ == "__main__":
    sys.exit(main())
