"""Benchmark: on-off loop batch simulation, numba kernel vs NumPy reference path vs plain Python.

All three run the same loop (S4 Table 3 nominal parameters with Table 5 LHS spread, 50 Hz
command rate, 1 ms step) in one process and report sample-steps per second (samples ×
integration steps / wall time, best of several repeats; numba compilation excluded).
Target (issue 7): >= 1e8 sample-steps/s with numba on the 2-core project machine.

Usage: python benchmarks/bench_onoff.py [--quick] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

from adcskit.control import LoopParams, LoopSettings, simulate_batch  # noqa: E402
from adcskit.uncertainty import Gaussian, TruncatedGaussian, latin_hypercube  # noqa: E402


def _params(n: int) -> LoopParams:
    s = latin_hypercube(
        {
            "inertia": TruncatedGaussian(mean=10.0, std=2.0, low=0.01),
            "torque": TruncatedGaussian(mean=1.0, std=0.2, low=0.001),
            "disturbance": Gaussian(mean=0.05, std=0.05),
            "delay": TruncatedGaussian(mean=0.02, std=0.01, low=0.0),
        },
        n,
        rng=0,
    )
    return LoopParams(**s)


def _rate(backend: str, n: int, t_final: float, repeats: int) -> float:
    params = _params(n)
    settings = LoopSettings(t_final=t_final, t_window=min(10.0, t_final / 2))
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        simulate_batch(params, settings, backend=backend)
        best = min(best, time.perf_counter() - t0)
    return n * settings.n_steps / best


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smaller problem sizes")
    ap.add_argument("--json", metavar="PATH", help="write the results as JSON")
    args = ap.parse_args(argv)

    # warm-up: compile (or load from numba's cache) outside the timed runs
    simulate_batch(_params(4), LoopSettings(t_final=0.1, t_window=0.05))
    if args.quick:
        sizes = {"numba": (4000, 10.0, 3), "numpy": (4000, 0.5, 1), "python": (4, 0.5, 1)}
    else:
        sizes = {"numba": (20000, 30.0, 3), "numpy": (20000, 2.0, 2), "python": (10, 2.0, 2)}
    results = {}
    for backend, (n, t_final, repeats) in sizes.items():
        rate = _rate(backend, n, t_final, repeats)
        results[f"{backend}_sample_steps_per_s"] = rate
        print(f"{backend:>7}: {n:6d} samples x {int(round(t_final / 1e-3)):6d} steps -> {rate:.3e} sample-steps/s")
    ratios = {
        "numba_vs_numpy": results["numba_sample_steps_per_s"] / results["numpy_sample_steps_per_s"],
        "numba_vs_python": results["numba_sample_steps_per_s"] / results["python_sample_steps_per_s"],
    }
    print(f"numba / numpy  = {ratios['numba_vs_numpy']:.1f}x")
    print(f"numba / python = {ratios['numba_vs_python']:.0f}x")
    target = results["numba_sample_steps_per_s"] >= 1e8
    print(f"target >= 1e8 sample-steps/s: {'met' if target else 'NOT met'}")
    out = {"results": results, "ratios": ratios}
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=2)
            fh.write("\n")
    return out


if __name__ == "__main__":
    main()
