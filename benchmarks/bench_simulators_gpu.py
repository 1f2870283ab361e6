"""Benchmark: the two closed-loop simulators on the CPU (all cores) and on the GPU, same source.

* thruster closed loop (:func:`adcskit.simulation.simulate`): the default S3/S4 scenario
  (MEKF with sun sensor + magnetometer + gyro, Schmitt control, 12 thrusters) with
  dispersions, dt = 0.02 s;
* wheel + magnetorquer loop (:func:`adcskit.simulation.simulate_wheels`): the reference
  smallsat pointing at nadir with dispersions, dt = 0.2 s.

For each: kernel sample-steps/s on the CPU (``numba.get_num_threads()`` threads) and on the
GPU (one thread per sample; the first call, which compiles the CUDA kernel, is a separate
warm-up), their ratio, and the CPU/GPU agreement on the same samples (same seeds): the GPU
contracts ``a * b + c`` into fused multiply-adds, so the numbers agree to rounding until a
discrete event (a Schmitt switch, a mode switch) lands on the other side of its threshold;
reported are the fraction of samples with the same firing count / final mode, and the
relative difference of the mean pointing error and propellant / wheel momentum.

Usage: python benchmarks/bench_simulators_gpu.py [--cpu-samples N] [--gpu-samples N]
       [--t-final S] [--only thruster|wheels] [--json FILE]
Without a usable GPU it prints the CPU figures and says why the GPU ones are missing.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

import numba  # noqa: E402
import numpy as np  # noqa: E402

from adcskit import _targets  # noqa: E402
from adcskit.simulation import (  # noqa: E402
    DispersionSpec,
    ModeSpec,
    Scenario,
    SimSpec,
    WheelDispersionSpec,
    WheelScenario,
    simulate,
    simulate_wheels,
)


def _thruster(t_final: float) -> tuple[Scenario, callable]:
    sc = Scenario(sim=SimSpec(dt=0.02, t_final=t_final, metrics_from_s=t_final / 2),
                  dispersions=DispersionSpec(inertia_rel=0.05, thrust_rel=0.03, misalignment_deg=0.3,
                                             delay_std_s=0.005, initial_attitude_deg=2.0))
    return sc, simulate


def _wheels(t_final: float) -> tuple[WheelScenario, callable]:
    sc = WheelScenario(modes=ModeSpec(initial="point", sequence=False),
                       sim=SimSpec(dt=0.2, t_final=t_final, metrics_from_s=t_final / 2),
                       dispersions=WheelDispersionSpec(inertia_rel=0.1, sensor_noise_rel=0.2,
                                                       initial_rate_deg_s=0.05))
    return sc, simulate_wheels


def _agreement(name: str, g, c) -> dict:
    out = {}
    if name == "thruster":
        out["same_firings_fraction"] = float(np.mean(g.metrics["firings"] == c.metrics["firings"]))
        keys = ("pointing_rms_deg", "propellant_kg")
    else:
        out["same_final_mode_fraction"] = float(np.mean(g.metrics["final_mode"] == c.metrics["final_mode"]))
        keys = ("pointing_rms_deg", "final_wheel_momentum_nms")
    for k in keys:
        gm, cm = float(np.nanmean(g.metrics[k])), float(np.nanmean(c.metrics[k]))
        out[f"mean_{k}_rel_diff"] = abs(gm - cm) / abs(cm) if cm else abs(gm - cm)
        with np.errstate(invalid="ignore", divide="ignore"):
            rel = np.abs(g.metrics[k] - c.metrics[k]) / np.abs(c.metrics[k])
        out[f"median_sample_{k}_rel_diff"] = float(np.nanmedian(rel))
    out["bit_identical_fraction"] = float(np.mean(np.all(
        [g.metrics[k] == c.metrics[k] for k in c.metrics if np.all(np.isfinite(c.metrics[k]))], axis=0)))
    return out


def bench(name: str, t_final: float, n_cpu: int, n_gpu: int, n_cmp: int, gpu: bool) -> dict:
    sc, run = (_thruster if name == "thruster" else _wheels)(t_final)
    r = {"simulator": name, "t_final_s": t_final, "dt_s": sc.sim.dt, "cpu_threads": numba.get_num_threads()}
    t0 = time.perf_counter()
    run(sc.replace(sim=sc.sim.replace(t_final=10 * sc.sim.dt, metrics_from_s=5 * sc.sim.dt)), 2, rng=0)
    r["cpu_first_call_s"] = round(time.perf_counter() - t0, 1)  # compile or load from cache
    res = run(sc, n_cpu, rng=1)
    r.update(cpu_samples=n_cpu, n_steps=res.n_steps, cpu_sample_steps_per_s=res.sample_steps_per_s)
    print(f"[{name}] CPU {n_cpu} x {res.n_steps}: {res.sample_steps_per_s:.3g} sample-steps/s "
          f"({r['cpu_threads']} threads; first call {r['cpu_first_call_s']} s)", flush=True)
    if not gpu:
        return r
    t0 = time.perf_counter()
    run(sc.replace(sim=sc.sim.replace(t_final=10 * sc.sim.dt, metrics_from_s=5 * sc.sim.dt)), 2, rng=0,
        backend="cuda")
    r["gpu_first_call_s"] = round(time.perf_counter() - t0, 1)  # CUDA JIT compile
    res = run(sc, n_gpu, rng=1, backend="cuda")
    r.update(gpu_samples=n_gpu, gpu_sample_steps_per_s=res.sample_steps_per_s,
             gpu_over_cpu=res.sample_steps_per_s / r["cpu_sample_steps_per_s"])
    print(f"[{name}] GPU {n_gpu} x {res.n_steps}: {res.sample_steps_per_s:.3g} sample-steps/s "
          f"= {r['gpu_over_cpu']:.1f}x the CPU (CUDA compile {r['gpu_first_call_s']} s)", flush=True)
    g = run(sc, n_cmp, rng=2, backend="cuda")
    c = run(sc, n_cmp, rng=2)
    r["agreement"] = _agreement(name, g, c)
    r["agreement"]["samples"] = n_cmp
    print(f"[{name}] agreement on {n_cmp} samples: {json.dumps(r['agreement'])}", flush=True)
    return r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cpu-samples", type=int, default=2048)
    ap.add_argument("--gpu-samples", type=int, default=65536)
    ap.add_argument("--compare-samples", type=int, default=1024)
    ap.add_argument("--t-final", type=float, default=20.0, help="thruster loop; the wheel loop runs 10x longer")
    ap.add_argument("--only", choices=("thruster", "wheels"), default=None)
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    ok, why = _targets.cuda_status()
    gpu = _targets.cuda_usable()
    out = {"device": why if ok else None, "gpu": gpu, "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    if not gpu:
        print(f"no GPU figures: {why}", flush=True)
    for name in ("thruster", "wheels"):
        if a.only in (None, name):
            t_final = a.t_final if name == "thruster" else 10 * a.t_final
            out[name] = bench(name, t_final, a.cpu_samples, a.gpu_samples, a.compare_samples, gpu)
            if a.json:  # written after each part: a timeout keeps what finished
                with open(a.json, "w") as f:
                    json.dump(out, f, indent=2)


if __name__ == "__main__":
    main()
