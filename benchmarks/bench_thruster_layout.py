"""Benchmark for S3 (issue 6): the full ``thruster-layout`` study must take <= 2 minutes.

Measures, in one run:

1. fitness evaluation of one population (50 layouts x 14 demands, S3 eq. 18) with adcskit's
   vectorised kernel (numba redistributed pseudo-inverse over the whole population) against
   the straightforward per-layout, per-demand loop with ``numpy.linalg.pinv`` — the way
   a pymoo ``ElementwiseProblem`` would evaluate it — and prints the speed-up ratio;
2. the wall time of the whole study (``--quick``: the quick variant) against the 120 s target.

Usage: python benchmarks/bench_thruster_layout.py [--quick] [--json PATH] [--executor SPEC]
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import time

import numpy as np


def _naive_score(A, demands, fmax=10.0, tmin=3e-3, t_s=0.2, gain=600.0, w=(100.0, -99.0, 12.0)):
    """Per-layout, per-demand redistributed pseudo-inverse with numpy.linalg.pinv."""
    n = A.shape[1]
    errs, tps = [], []
    for m in demands:
        free = np.ones(n, bool)
        F = np.zeros(n)
        for _ in range(n + 1):
            r = m - A[:, ~free] @ F[~free]
            Ff = np.linalg.pinv(A[:, free]) @ r
            F[free] = Ff
            lo, hi = free & (F < 0), free & (F > fmax)
            F[lo], F[hi] = 0.0, fmax
            free &= ~(lo | hi)
            if not (lo | hi).any() or not free.any():
                break
        errs.append(np.linalg.norm(m - A @ F))
        tps.append(F.sum() * t_s / fmax)
    e_min = np.linalg.norm(A, axis=0).max() * fmax * tmin / (t_s * gain)
    return w[0] * np.mean(errs) + w[1] * e_min + w[2] * np.mean(tps)


def bench_eval(repeat: int = 5) -> dict:
    from adcskit.thrusters import box_faces, score_layout
    from adcskit.thrusters import s3_manoeuvre_demands as manoeuvre_demands
    from adcskit.thrusters.layout import _decode, _face_table

    D = manoeuvre_demands(0.5, 600.0)
    out = {}
    for n in (6, 12):
        rng = np.random.default_rng(0)
        lo = np.tile([0, -1, -1, 0, 0], n)
        hi = np.tile([6 - 1e-9, 1, 1, 1, 2 * math.pi], n)
        X = rng.uniform(lo, hi, size=(50, 5 * n))
        pos, d, _ = _decode(X, _face_table(box_faces()))
        A = np.swapaxes(np.cross(pos, d), -1, -2)
        ours = score_layout(A, D).fun  # also compiles / loads the numba cache
        naive = np.array([_naive_score(a, D) for a in A])
        agree = float(np.max(np.abs(ours - naive) / np.maximum(1.0, np.abs(naive))))
        t_ours = min(_timeit(lambda A=A: score_layout(A, D)) for _ in range(repeat))
        t_naive = min(_timeit(lambda A=A: [_naive_score(a, D) for a in A]) for _ in range(2))
        out[f"n{n}"] = {
            "ours_ms": 1e3 * t_ours, "naive_ms": 1e3 * t_naive, "speedup": t_naive / t_ours,
            "max_rel_disagreement": agree,
        }
    return out


def _timeit(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def bench_study(quick: bool, executor: str) -> dict:
    import os

    from adcskit.studies._runner import run_study

    t0, c0 = time.perf_counter(), os.times()
    res = run_study("thruster-layout", quick=quick, out=None, executor=executor)
    wall, c1 = time.perf_counter() - t0, os.times()
    # CPU time of this process and its finished children (worker processes): independent of
    # how many other jobs share the machine, unlike the wall time
    cpu = (c1.user - c0.user) + (c1.system - c0.system) + (c1.children_user - c0.children_user) + (
        c1.children_system - c0.children_system)
    return {"quick": quick, "executor": executor, "wall_s": wall, "cpu_s": cpu, "target_s": 120.0,
            "ratio_to_target": wall / 120.0, "load_avg_1min_after": os.getloadavg()[0],
            "sum_of_run_times_s": res.measured["total_optimisation_time_s"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="time the quick study instead of the full one")
    ap.add_argument("--json", help="write the measurements to this JSON file")
    ap.add_argument("--executor", default="serial", help="executor spec for the study (default serial)")
    args = ap.parse_args()
    ev = bench_eval()
    for k, v in ev.items():
        print(f"population eval {k}: adcskit {v['ours_ms']:.2f} ms, per-layout numpy pinv loop "
              f"{v['naive_ms']:.1f} ms -> speed-up x{v['speedup']:.0f} "
              f"(max rel. disagreement {v['max_rel_disagreement']:.1e})")
    st = bench_study(args.quick, args.executor)
    print(f"study thruster-layout ({'quick' if args.quick else 'full'}, {args.executor}): "
          f"{st['wall_s']:.1f} s wall ({st['cpu_s']:.1f} s CPU, load average {st['load_avg_1min_after']:.1f}) "
          f"vs target 120 s -> ratio {st['ratio_to_target']:.2f}")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump({"machine": platform.platform(), "eval": ev, "study": st}, fh, indent=2)


if __name__ == "__main__":
    main()
