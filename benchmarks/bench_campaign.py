"""Benchmark: a Monte-Carlo campaign (S4 loop, Table 5 LHS) on each executor, and its task size.

One run measures ``monte_carlo`` of S4's Table 4 minimum-error gains on ``n`` LHS samples:

* ``serial, 1 thread``: the serial executor with numba limited to one thread (one core);
* ``serial, all threads``: the serial executor, numba's ``prange`` over all cores;
* ``processes:W`` and ``dask-local:W``: W single-threaded workers (started and warmed up --
  adcskit imported, the numba kernel loaded from its cache -- before the clock; start-up
  reported separately);

and prints wall times, the speed-up of each against ``serial, 1 thread`` and whether every
executor gave bit-identical metrics. It also prints the bytes the executor ships per
campaign at S4-like sizes (320 000 samples): tasks that carry copies of the sample arrays
(the old design, which made Dask warn about a ~10 MiB graph) against tasks that carry an
index range while the samples are scattered once.

Usage: python benchmarks/bench_campaign.py [--n 4000] [--t-final 30] [--workers 2] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

from adcskit.control import LoopSettings  # noqa: E402
from adcskit.control.tuning import monte_carlo  # noqa: E402
from adcskit.uncertainty import Gaussian, TruncatedGaussian, latin_hypercube, make_executor  # noqa: E402

TABLE5 = {
    "inertia": TruncatedGaussian(mean=10.0, std=2.0, low=0.5),
    "torque": TruncatedGaussian(mean=1.0, std=0.2, low=0.05),
    "disturbance": Gaussian(mean=0.05, std=0.05),
    "delay": TruncatedGaussian(mean=0.02, std=0.01, low=0.0),
}
GAINS = (56.24, 0.02, 49.99)


def _payload_bytes(n: int, task_size: int) -> dict:
    """Bytes shipped for n samples: tasks with sample copies vs index ranges + one scatter."""
    samples = latin_hypercube(TABLE5, n, 0)
    g = np.asarray(GAINS)
    s = LoopSettings()
    old = [(g, {k: v[i:i + task_size] for k, v in samples.items()}, None, s, False)
           for i in range(0, n, task_size)]
    new = [(g, (i, min(n, i + task_size)), None, s, False, "cpu") for i in range(0, n, task_size)]
    return {
        "n": n,
        "tasks": len(new),
        # each task is serialised on its own (as Dask and a process pool do)
        "old_tasks_bytes": sum(len(pickle.dumps(t)) for t in old),
        "new_tasks_bytes": sum(len(pickle.dumps(t)) for t in new),
        "scattered_once_bytes": len(pickle.dumps(samples)),
    }


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=4000, help="Monte-Carlo runs")
    ap.add_argument("--t-final", type=float, default=30.0, help="simulated time per run [s]")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--task-size", type=int, default=250)
    ap.add_argument("--json", metavar="PATH")
    args = ap.parse_args(argv)
    import numba

    settings = LoopSettings(t_final=args.t_final, t_window=min(10.0, args.t_final / 2))
    kw = dict(settings=settings, task_size=args.task_size, rng=1)
    steps = args.n * settings.n_steps
    monte_carlo(GAINS, TABLE5, 8, settings=LoopSettings(t_final=0.1, t_window=0.05))  # compile
    rows: dict = {}
    ref = None

    def timed(label, executor):
        nonlocal ref
        t0 = time.perf_counter()
        r = monte_carlo(GAINS, TABLE5, args.n, executor=executor, **kw)
        dt = time.perf_counter() - t0
        arr = r.metrics.as_array()
        same = True if ref is None else bool(np.array_equal(arr, ref, equal_nan=True))
        ref = arr if ref is None else ref
        rows[label] = {"wall_s": dt, "sample_steps_per_s": steps / dt, "identical": same}

    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    timed("serial, 1 thread", "serial")
    numba.set_num_threads(threads)
    timed(f"serial, {threads} threads", "serial")
    for spec in (f"processes:{args.workers}", f"dask-local:{args.workers}"):
        t0 = time.perf_counter()
        ex = make_executor(spec)
        start = time.perf_counter() - t0
        try:
            # warm-up: every worker imports adcskit and loads the cached numba kernel
            monte_carlo(GAINS, TABLE5, 4 * args.workers, executor=ex, task_size=1,
                        settings=LoopSettings(t_final=0.1, t_window=0.05))
            timed(spec, ex)
        finally:
            ex.close()
        rows[spec]["startup_s"] = start
    base = rows["serial, 1 thread"]["wall_s"]
    print(f"monte_carlo: {args.n} runs x {settings.n_steps} steps, task_size {args.task_size}, "
          f"{os.cpu_count()} CPUs")
    for label, r in rows.items():
        r["speedup_vs_serial_1_thread"] = base / r["wall_s"]
        extra = f", start-up {r['startup_s']:.1f} s" if "startup_s" in r else ""
        print(f"{label:>20}: {r['wall_s']:7.2f} s  {r['sample_steps_per_s']:.3e} sample-steps/s  "
              f"speed-up {r['speedup_vs_serial_1_thread']:.2f}x  identical={r['identical']}{extra}")
    pb = _payload_bytes(320_000, 1000)
    print(f"shipped for {pb['n']} samples in {pb['tasks']} tasks: samples inside tasks "
          f"{pb['old_tasks_bytes'] / 2**20:.1f} MiB; index-range tasks {pb['new_tasks_bytes'] / 2**10:.0f} KiB "
          f"+ samples scattered once {pb['scattered_once_bytes'] / 2**20:.1f} MiB")
    out = {"executors": rows, "payload": pb, "n": args.n, "n_steps": settings.n_steps}
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=2)
            fh.write("\n")
    return out


if __name__ == "__main__":
    main()
