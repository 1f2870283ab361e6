"""Benchmark: one closed-loop campaign serially and on process / Dask workers, in one run.

The same ``simulate(Scenario(), n, rng=seed)`` campaign (the default thruster scenario: S3's
GEO satellite and reference layout, MEKF on sun sensor + magnetometer + gyro, S4's Schmitt
loop, 100 s at 0.02 s = 5000 steps per sample) runs on

* ``serial, 1 thread``: the serial executor with numba limited to one thread (one core);
* ``serial, T threads``: the serial executor, numba's ``prange`` over every core (the
  default executor);
* ``processes:W`` and ``dask-local:W``: W worker processes (started and warmed up --
  adcskit imported, the kernel loaded from numba's disk cache -- before the clock; the
  start-up is reported separately),

in interleaved repeats (repeat 1 of every variant, then repeat 2, ...), and prints the median
wall time, the median CPU time and the speed-up of each variant against ``serial, 1 thread``
and against the default serial executor. Every variant's outputs (every metric, the
per-thruster on-times, the per-sample seeds and the controllability flags) must be
bit-identical to the first variant's; the bench stops with an error otherwise.

What the CPU time counts: user + system seconds of this process (``resource.getrusage
(RUSAGE_SELF)``: the serial kernel's threads, and the parent's share of a pool: pickling,
the Dask scheduler and client threads) plus those of every live descendant process
(``psutil.Process().children(recursive=True)``: the pool's workers, and the Dask nannies and
their workers), read before and after each campaign. Children that already ended are added
from ``RUSAGE_CHILDREN``. CPU time of other users' jobs on a shared machine is not counted,
so CPU seconds stay comparable under load while wall seconds do not.

Usage: python benchmarks/bench_scaleout.py [--n 12000] [--repeats 3] [--workers 2]
       [--chunk-size N] [--t-final 100] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

from adcskit.simulation import Scenario, SimSpec, simulate  # noqa: E402
from adcskit.uncertainty import make_executor  # noqa: E402


def _cpu_seconds() -> float:
    """User + system CPU of this process, its live descendants and its reaped children."""
    import psutil

    own = resource.getrusage(resource.RUSAGE_SELF)
    reaped = resource.getrusage(resource.RUSAGE_CHILDREN)
    total = own.ru_utime + own.ru_stime + reaped.ru_utime + reaped.ru_stime
    for child in psutil.Process().children(recursive=True):
        try:
            t = child.cpu_times()
        except (psutil.NoSuchProcess, psutil.AccessDenied):
            continue
        total += t.user + t.system
    return total


def _load() -> list[float]:
    return [round(x, 2) for x in os.getloadavg()]


def _outputs(res) -> dict[str, np.ndarray]:
    out = {f"metric:{k}": v for k, v in res.metrics.items()}
    out["on_time_per_thruster"] = res.on_time_per_thruster
    out["seeds"] = res.seeds
    out["controllable"] = res.controllable
    return out


def _identical(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> list[str]:
    """Names of the outputs that differ (bit for bit; NaN equals NaN)."""
    bad = []
    for k in a:
        x, y = a[k], b[k]
        if x.shape != y.shape or x.dtype != y.dtype:
            bad.append(k)
        elif x.dtype.kind == "f":
            if not np.array_equal(x.view(np.uint64), y.view(np.uint64)):
                bad.append(k)
        elif not np.array_equal(x, y):
            bad.append(k)
    return bad


def _worker_threads(ex) -> list[int]:
    """numba's thread count inside each worker of a pool (what its kernels' prange uses)."""
    from adcskit.uncertainty import DaskExecutor

    if isinstance(ex, DaskExecutor):
        return sorted(ex.client.run(_numba_threads).values())
    return sorted(set(ex.map(_numba_threads_task, list(range(4 * ex.n_workers)))))


def _numba_threads() -> int:
    import numba

    return int(numba.get_num_threads())


def _numba_threads_task(_task) -> int:
    return _numba_threads()


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=12000, help="Monte-Carlo samples per campaign")
    ap.add_argument("--repeats", type=int, default=3, help="interleaved repeats of every variant")
    ap.add_argument("--workers", type=int, default=2, help="worker processes of the pools")
    ap.add_argument("--chunk-size", type=int, default=None,
                    help="samples per task (default: n / (4 x workers), as a campaign spreads them)")
    ap.add_argument("--t-final", type=float, default=100.0, help="simulated time per sample [s] (default scenario: 100)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--skip", default="", help="comma-separated variants to leave out: serial1,processes,dask")
    ap.add_argument("--json", metavar="PATH")
    args = ap.parse_args(argv)
    import numba

    skip = {s.strip() for s in args.skip.split(",") if s.strip()}
    base = Scenario()
    sc = base if args.t_final == base.sim.t_final else Scenario(
        sim=SimSpec(dt=base.sim.dt, t_final=args.t_final, metrics_from_s=args.t_final / 2))
    chunk = args.chunk_size or max(1, -(-args.n // (4 * args.workers)))
    n_steps = int(round(sc.sim.t_final / sc.sim.dt))
    threads = numba.get_num_threads()
    load_start = _load()
    t_wall0 = time.perf_counter()
    simulate(sc, n_samples=4, rng=args.seed)  # compile or load the kernel before any clock

    variants: list[tuple[str, object, int]] = []  # (label, executor spec or Executor, numba threads)
    if "serial1" not in skip:
        variants.append(("serial, 1 thread", "serial", 1))
    variants.append((f"serial, {threads} threads", "serial", threads))
    startup: dict[str, float] = {}
    worker_threads: dict[str, list[int]] = {}
    pools = []
    for name, spec in (("processes", f"processes:{args.workers}"), ("dask", f"dask-local:{args.workers}")):
        if name in skip:
            continue
        t0 = time.perf_counter()
        ex = make_executor(spec)
        # warm-up: every worker imports adcskit and loads the cached kernel (one task each and more)
        simulate(sc, n_samples=8 * args.workers, rng=args.seed, executor=ex, chunk_size=4)
        startup[spec] = time.perf_counter() - t0
        worker_threads[spec] = _worker_threads(ex)
        pools.append(ex)
        variants.append((spec, ex, threads))

    runs: dict[str, list[dict]] = {label: [] for label, _, _ in variants}
    ref = None
    ref_label = variants[0][0]
    try:
        for rep in range(args.repeats):
            for label, ex, nthreads in variants:
                numba.set_num_threads(nthreads)
                load0 = _load()
                c0 = _cpu_seconds()
                t0 = time.perf_counter()
                res = simulate(sc, n_samples=args.n, rng=args.seed, executor=ex, chunk_size=chunk)
                wall = time.perf_counter() - t0
                cpu = _cpu_seconds() - c0
                numba.set_num_threads(threads)
                outs = _outputs(res)
                if ref is None:
                    ref = outs
                    bad = []
                else:
                    bad = _identical(ref, outs)
                if bad:
                    raise SystemExit(f"{label} (repeat {rep + 1}) differs from {ref_label} in {bad}")
                runs[label].append({"wall_s": wall, "cpu_s": cpu, "load_before": load0, "load_after": _load(),
                                    "n_chunks": res.n_chunks, "success": res.success})
                print(f"repeat {rep + 1} {label:>20}: wall {wall:7.2f} s  CPU {cpu:7.2f} s  "
                      f"load {load0[0]:.2f}", flush=True)
    finally:
        for ex in pools:
            ex.close()

    rows: dict[str, dict] = {}
    for label, rs in runs.items():
        walls = [r["wall_s"] for r in rs]
        cpus = [r["cpu_s"] for r in rs]
        rows[label] = {
            "wall_s_median": statistics.median(walls), "wall_s": walls,
            "cpu_s_median": statistics.median(cpus), "cpu_s": cpus,
            "cpu_per_wall": statistics.median(cpus) / statistics.median(walls),
            "sample_steps_per_wall_s": args.n * n_steps / statistics.median(walls),
            "sample_steps_per_cpu_s": args.n * n_steps / statistics.median(cpus),
            "identical_to_first": True,
            "runs": rs,
        }
        if label in startup:
            rows[label]["startup_s"] = startup[label]
            rows[label]["worker_numba_threads"] = worker_threads[label]
    serial_all = rows[f"serial, {threads} threads"]["wall_s_median"]
    serial_one = rows.get("serial, 1 thread", {}).get("wall_s_median")
    print(f"\nclosed-loop campaign: {args.n} samples x {n_steps} steps ({args.n * n_steps:.3g} sample-steps), "
          f"{-(-args.n // chunk)} tasks of {chunk}, {args.repeats} interleaved repeats, {os.cpu_count()} CPUs, "
          f"numba {threads} threads in this process")
    print(f"{'variant':>20} | {'wall [s]':>8} | {'CPU [s]':>8} | CPU/wall | sample-steps/s | "
          f"vs serial 1 thr | vs serial {threads} thr | identical")
    for label, r in rows.items():
        r["speedup_vs_serial_all_threads"] = serial_all / r["wall_s_median"]
        if serial_one is not None:
            r["speedup_vs_serial_1_thread"] = serial_one / r["wall_s_median"]
        extra = ""
        if "startup_s" in r:
            extra = f"  (start-up {r['startup_s']:.1f} s; numba threads per worker {r['worker_numba_threads']})"
        s1 = f"{r['speedup_vs_serial_1_thread']:.2f}x" if serial_one is not None else "-"
        print(f"{label:>20} | {r['wall_s_median']:8.2f} | {r['cpu_s_median']:8.2f} | {r['cpu_per_wall']:8.2f} | "
              f"{r['sample_steps_per_wall_s']:14.3e} | {s1:>15} | {r['speedup_vs_serial_all_threads']:>15.2f}x | "
              f"yes{extra}")
    load_end = _load()
    print(f"load average (1, 5, 15 min): {load_start} at the start, {load_end} at the end; "
          f"bench wall {time.perf_counter() - t_wall0:.0f} s")
    out = {
        "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(), "python": platform.python_version(),
                    "processor": platform.processor()},
        "scenario": {"t_final_s": sc.sim.t_final, "dt_s": sc.sim.dt, "n_steps": n_steps,
                     "default": sc == base},
        "n": args.n, "chunk_size": chunk, "repeats": args.repeats, "workers": args.workers,
        "numba_threads": threads, "load_start": load_start, "load_end": load_end,
        "cpu_counted": "RUSAGE_SELF + live descendants (psutil, recursive) + RUSAGE_CHILDREN",
        "variants": rows,
    }
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=2)
            fh.write("\n")
    return out


if __name__ == "__main__":
    main()
