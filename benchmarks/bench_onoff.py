"""Benchmark: on-off loop batch simulation, numba kernel vs NumPy reference path vs plain Python.

All three run the same loop (S4 Table 3 nominal parameters with Table 5 LHS spread, 50 Hz
command rate, 1 ms step) in one process and report sample-steps per second (samples ×
integration steps / wall time, best of several repeats; numba compilation excluded).
Target (issue 7): >= 1e8 sample-steps/s with numba on the 2-core project machine.

With ``--backend cuda`` it measures instead the CPU kernel on all cores and the CUDA kernel
(same per-sample source, one thread per sample) in one run and prints the GPU/CPU ratio
(issue 14 goals: >= 2e11 sample-steps/s on an H100 and >= 200x the all-core CPU kernel of
the same machine), plus the kernel's registers and local memory per thread and a CPU/GPU
agreement check (identical firings, max relative difference of the continuous metrics).
Without a usable GPU it says so and prints the CPU figure.

Usage: python benchmarks/bench_onoff.py [--quick] [--backend {all,cuda}] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

from adcskit import _targets  # noqa: E402
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


def _gpu_kernel_info(buf_len: int, max_registers: int | None = None) -> dict:
    """Registers and local memory per thread of the compiled CUDA kernel (best effort)."""
    from adcskit.control import _onoff_kernels as k

    kern = k.CUDA_KERNELS.get(buf_len, max_registers)
    info: dict = {"threads_per_block": k.THREADS_PER_BLOCK, "delay_line_bytes": buf_len}
    for name in ("get_regs_per_thread", "get_local_mem_per_thread", "get_shared_mem_per_block"):
        try:
            v = getattr(kern, name)()
            info[name.removeprefix("get_")] = list(v.values())[0] if isinstance(v, dict) else v
        except Exception as exc:  # API differs between numba-cuda versions
            info[name.removeprefix("get_")] = f"n/a ({type(exc).__name__})"
    return info


def _cuda_main(quick: bool) -> dict:
    """CPU (all cores) vs GPU in one run; ratio; agreement; kernel resources."""
    import numba

    from adcskit.control.onoff import _buffer_length, _param_matrix

    t_final = 10.0 if quick else 30.0
    n_cpu = 4000 if quick else 20000
    cpu = _rate("cpu", n_cpu, t_final, 3)
    out: dict = {"results": {"cpu_sample_steps_per_s": cpu, "cpu_threads": numba.get_num_threads(),
                             "t_final_s": t_final, "cpu_samples": n_cpu}}
    print(f"    cpu: {n_cpu:8d} samples x {int(round(t_final / 1e-3)):6d} steps, "
          f"{numba.get_num_threads()} threads -> {cpu:.3e} sample-steps/s")
    ok, why = _targets.cuda_status()
    if not ok or _targets.simulator_enabled():
        print(f"   cuda: pending: no GPU available ({why})")
        out["results"]["cuda_sample_steps_per_s"] = None
        out["gpu"] = f"pending: no GPU available ({why})"
        return out
    print(f"   cuda: device {why}")
    n_gpu = (1 << 18) if quick else (1 << 22)
    simulate_batch(_params(256), LoopSettings(t_final=0.1, t_window=0.05), backend="cuda")  # compile
    gpu = _rate("cuda", n_gpu, t_final, 3)
    print(f"   cuda: {n_gpu:8d} samples x {int(round(t_final / 1e-3)):6d} steps -> {gpu:.3e} sample-steps/s")
    ratio = gpu / cpu
    print(f"cuda / cpu(all cores) = {ratio:.0f}x   (goals: >= 2e11 sample-steps/s, >= 200x)")
    # agreement on the CPU run's samples: identical firings, FMA-level continuous differences
    settings = LoopSettings(t_final=t_final, t_window=min(10.0, t_final / 2))
    p = _params(n_cpu)
    a = simulate_batch(p, settings, backend="cpu").as_array()
    b = simulate_batch(p, settings, backend="cuda").as_array()
    same_firings = float(np.mean(a[:, 4] == b[:, 4]))
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.abs(a - b) / np.maximum(np.abs(a), 1e-300)
    max_rel = float(np.nanmax(np.where(np.abs(a) > 1e-12, rel, 0.0)))
    print(f"agreement: identical firings in {same_firings * 100:.3f}% of samples, max relative "
          f"difference of the metrics {max_rel:.2e}")
    L = _buffer_length(_param_matrix(p), settings.dt)
    info = _gpu_kernel_info(L)
    print(f"kernel: {info}")
    # occupancy experiment: cap the registers per thread (more resident warps, some spills)
    from adcskit.control import _onoff_kernels as k
    from adcskit.control.onoff import _coefficients

    P = _param_matrix(_params(n_gpu))
    C = _coefficients(settings)
    rec = np.empty((0, 0, k.N_TRACE))
    sweep = {}
    for cap in (96, 80, 64):
        k.simulate_cuda(P[:256], C, settings.n_steps, settings.hold_steps, settings.n_window, L, rec,
                        max_registers=cap)  # compile
        t0 = time.perf_counter()
        k.simulate_cuda(P, C, settings.n_steps, settings.hold_steps, settings.n_window, L, rec,
                        max_registers=cap)
        rate = n_gpu * settings.n_steps / (time.perf_counter() - t0)
        sweep[str(cap)] = {"sample_steps_per_s": rate, **_gpu_kernel_info(L, cap)}
        print(f"   cuda, max_registers={cap}: {rate:.3e} sample-steps/s  {sweep[str(cap)]}")
    out["max_registers_sweep"] = sweep
    out["results"].update(cuda_sample_steps_per_s=gpu, gpu_samples=n_gpu, device=why)
    out["ratios"] = {"cuda_vs_cpu": ratio}
    out["agreement"] = {"identical_firings_fraction": same_firings, "max_rel_diff": max_rel}
    out["kernel"] = info
    out["goals_met"] = {"2e11": gpu >= 2e11, "200x": ratio >= 200}
    return out


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smaller problem sizes")
    ap.add_argument("--backend", choices=("all", "cuda"), default="all",
                    help="all: numba vs NumPy vs Python (default); cuda: CPU all cores vs GPU")
    ap.add_argument("--json", metavar="PATH", help="write the results as JSON")
    args = ap.parse_args(argv)
    if args.backend == "cuda":
        simulate_batch(_params(4), LoopSettings(t_final=0.1, t_window=0.05))
        out = _cuda_main(args.quick)
        if args.json:
            with open(args.json, "w", encoding="utf-8") as fh:
                json.dump(out, fh, indent=2)
                fh.write("\n")
        return out

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
