"""A large closed-loop campaign on a Dask cluster through the public API, resumable.

One ``simulate(scenario, n, rng=seed, executor=SPEC, directory=DIR, chunk_size=C)``: the
samples are drawn once in this process, split into ``n / C`` tasks, and each finished task
is written atomically to ``DIR`` by the worker that computed it
(:func:`adcskit.uncertainty.run_campaign`). Interrupt it (Ctrl-C / SIGINT) and run the same
command again: the finished chunks are loaded and only the missing ones computed.

Then the per-sample results go to a Zarr store (``write_zarr``; one row per sample: every
metric, the dispersed parameters, the noise seed) and the requirement statistics are
computed on all samples (``percentile_bound``: p99 with its distribution-free 95 % upper
bound; ``check_requirements``: a small requirement table).

The script prints (and writes with ``--json``) wall time, CPU time of this process and its
worker processes (as in ``bench_scaleout.py``), the peak resident memory of this process and
of the process tree (sampled every 0.5 s with psutil), the number of chunks computed and
resumed, and a SHA-256 digest of the outputs (every metric, on-times, seeds, controllability
in sample order) that two runs can be compared by.

Usage: python benchmarks/scaleout_campaign.py --n 1000000 --t-final 10 --executor dask-local:2
       --dir /path/campaign --chunk-size 25000 [--zarr PATH] [--json PATH]
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import resource
import sys
import threading
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

from adcskit.simulation import Scenario, SimSpec, simulate, write_zarr  # noqa: E402
from adcskit.uncertainty import check_requirements, percentile_bound  # noqa: E402
from bench_scaleout import _cpu_seconds  # noqa: E402  (benchmarks/ is the script's folder: on sys.path)

REQUIREMENTS = [
    "ADCS-1: pointing_rms_deg p99 <= 0.5",
    "ADCS-2: pointing_max_deg p99 <= 1.0",
    "ADCS-3: knowledge_rms_deg p99 <= 0.1",
    "ADCS-4: P(pointing_max_deg > 1.0) <= 1 %",
    "ADCS-5: propellant_kg mean <= 1.0",
]


class _RssSampler(threading.Thread):
    """Peak RSS of this process and of the whole process tree (sum), every ``every`` s."""

    def __init__(self, every: float = 0.5) -> None:
        super().__init__(daemon=True)
        self.every = every
        self.peak_self = 0
        self.peak_tree = 0
        self._stop_event = threading.Event()

    def run(self) -> None:
        import psutil

        me = psutil.Process()
        while not self._stop_event.is_set():
            try:
                own = me.memory_info().rss
                tree = own
                for c in me.children(recursive=True):
                    try:
                        tree += c.memory_info().rss
                    except (psutil.NoSuchProcess, psutil.AccessDenied):
                        pass
                self.peak_self = max(self.peak_self, own)
                self.peak_tree = max(self.peak_tree, tree)
            except psutil.Error:
                pass
            self._stop_event.wait(self.every)

    def stop(self) -> None:
        self._stop_event.set()
        self.join()


def digest(res) -> str:
    h = hashlib.sha256()
    for k in sorted(res.metrics):
        h.update(k.encode())
        h.update(np.ascontiguousarray(res.metrics[k]).tobytes())
    for a in (res.on_time_per_thruster, res.seeds, res.controllable):
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--t-final", type=float, default=10.0, help="simulated time per sample [s] (default scenario: 100)")
    ap.add_argument("--executor", default="dask-local:2")
    ap.add_argument("--dir", required=True, help="campaign directory (chunk files; a re-run resumes)")
    ap.add_argument("--chunk-size", type=int, default=25_000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--zarr", metavar="PATH", help="write the per-sample results to this Zarr store")
    ap.add_argument("--json", metavar="PATH")
    args = ap.parse_args(argv)

    base = Scenario()
    sc = base if args.t_final == base.sim.t_final else Scenario(
        sim=SimSpec(dt=base.sim.dt, t_final=args.t_final, metrics_from_s=args.t_final / 2))
    n_steps = int(round(sc.sim.t_final / sc.sim.dt))
    load0 = [round(x, 2) for x in os.getloadavg()]
    sampler = _RssSampler()
    sampler.start()
    c0 = _cpu_seconds()
    t0 = time.perf_counter()
    res = simulate(sc, n_samples=args.n, rng=args.seed, executor=args.executor, directory=args.dir,
                   chunk_size=args.chunk_size)
    wall_sim = time.perf_counter() - t0
    cpu_sim = _cpu_seconds() - c0
    load1 = [round(x, 2) for x in os.getloadavg()]
    print(f"simulate: {res.message}; executor {res.executor}; wall {wall_sim:.1f} s, CPU {cpu_sim:.1f} s "
          f"(this process + workers); load {load0} -> {load1}", flush=True)
    out: dict = {
        "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "n": args.n, "n_steps": n_steps, "t_final_s": sc.sim.t_final, "dt_s": sc.sim.dt,
        "executor": res.executor, "chunk_size": args.chunk_size, "n_chunks": res.n_chunks,
        "n_resumed": res.n_resumed, "success": res.success, "message": res.message,
        "wall_simulate_s": wall_sim, "cpu_simulate_s": cpu_sim,
        "sample_steps_per_wall_s": args.n * n_steps / wall_sim,
        "load_before": load0, "load_after_simulate": load1, "digest": digest(res),
    }
    if args.zarr:
        t1 = time.perf_counter()
        write_zarr(res, args.zarr, sc, rng_seed=args.seed)
        out["wall_zarr_s"] = time.perf_counter() - t1
        out["zarr"] = args.zarr
    t2 = time.perf_counter()
    stats = {}
    for name in ("pointing_rms_deg", "pointing_max_deg", "knowledge_rms_deg"):
        b = percentile_bound(res.metrics[name], 99.0, confidence=0.95)
        stats[name] = {"p99": b.estimate, "upper95": b.upper, "rank_upper": b.rank_upper, "n": b.n}
        print(f"{name}: p99 = {b.estimate:.5g} deg, 95 % upper bound {b.upper:.5g} deg "
              f"(order statistic {b.rank_upper} of {b.n})")
    table = check_requirements(REQUIREMENTS, res.metrics)
    rows = table.table_rows()
    for row in rows:
        print(f"  {row['name']:7s} {row['requirement']:45s} {row['verdict']}")
    out["wall_statistics_s"] = time.perf_counter() - t2
    out["p99"] = stats
    out["requirements"] = rows
    out["wall_total_s"] = time.perf_counter() - t0
    out["cpu_total_s"] = _cpu_seconds() - c0
    sampler.stop()
    out["peak_rss_self_mib"] = sampler.peak_self / 2**20
    out["peak_rss_tree_mib"] = sampler.peak_tree / 2**20
    out["ru_maxrss_self_mib"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    out["load_end"] = [round(x, 2) for x in os.getloadavg()]
    print(f"digest {out['digest']}; chunks {res.n_chunks} ({res.n_resumed} resumed); "
          f"total wall {out['wall_total_s']:.1f} s, CPU {out['cpu_total_s']:.1f} s; peak RSS "
          f"{out['peak_rss_self_mib']:.0f} MiB this process, {out['peak_rss_tree_mib']:.0f} MiB with workers")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=2, default=str)
            fh.write("\n")
    return out


if __name__ == "__main__":
    main()
