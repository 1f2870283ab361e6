"""Benchmark: the reference wheel + magnetorquer mode sequence, N Monte-Carlo samples.

The 12U-class reference smallsat of :class:`adcskit.simulation.WheelScenario` (4 pyramid
wheels, 3 rods, sun sensor + magnetometer + gyro + star tracker; detumble -> sun -> nadir over
three orbits at dt = 0.2 s) with dispersions on inertia (10 %), wheel misalignment (0.5 deg),
sensor noise (20 %), initial rates (1 deg/s per axis) and uniformly random initial attitudes.
Prints the wall time, the process CPU time (all numba threads) and sample-steps per
CPU-second (the per-core rate; wall-clock rates depend on what else runs), the metric
summary and a requirement table (:mod:`adcskit.uncertainty.requirements`); ``--out DIR``
also writes the envelope figure (median, p5-p95, p1-p99, worst sample) and the summary.

Usage: python benchmarks/bench_wheels.py [--samples N] [--out DIR]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

from adcskit.simulation import (  # noqa: E402
    SimSpec,
    WheelDispersionSpec,
    WheelScenario,
    simulate_wheels,
    wheel_envelope_figure,
)

REQUIREMENTS = [
    "pointing_max_deg p99 <= 0.2 after 11400 s",
    "pointing_rms_deg p99 <= 0.1 after 11400 s",
    "knowledge_rms_deg p99 <= 0.02 after 11400 s",
    "P(t_acquired_s > 11400) <= 1 %",
    "max_wheel_speed_rpm max <= 6000",
]


def _cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=1000)
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    sc = WheelScenario(dispersions=WheelDispersionSpec(inertia_rel=0.1, wheel_misalignment_deg=0.5,
                                                       sensor_noise_rel=0.2, initial_rate_deg_s=1.0,
                                                       initial_attitude="random"))
    if a.out:
        sc = sc.replace(sim=sc.sim.replace(record_every=250))
    simulate_wheels(sc.replace(sim=SimSpec(dt=0.2, t_final=2.0, metrics_from_s=1.0)), 2, rng=0)  # compile / load
    c0, t0 = _cpu(), time.perf_counter()
    res = simulate_wheels(sc, a.samples, rng=0, record=bool(a.out))
    wall, cpu = time.perf_counter() - t0, _cpu() - c0
    steps = a.samples * res.n_steps
    print(f"{a.samples} samples x {res.n_steps} steps: wall {wall:.1f} s, CPU {cpu:.1f} s, "
          f"{steps / cpu:.3g} sample-steps per CPU-second ({os.cpu_count()} CPUs, load {os.getloadavg()[0]:.1f})")
    print(res.message)
    for name, row in res.summary().items():
        print(f"  {name:26s} " + "  ".join(f"{k} {v:.4g}" for k, v in row.items()))
    table = res.check_requirements(REQUIREMENTS, nan_policy="fail")
    for row in table.table_rows():
        print("  " + " | ".join(str(v) for v in row.values()))
    if a.out:
        os.makedirs(a.out, exist_ok=True)
        wheel_envelope_figure(res).savefig(os.path.join(a.out, "wheels-envelopes.png"), dpi=110)
        with open(os.path.join(a.out, "wheels-summary.json"), "w") as fh:
            json.dump({"wall_s": wall, "cpu_s": cpu, "sample_steps_per_cpu_s": steps / cpu, "result": res.to_dict(),
                       "requirements": table.table_rows()}, fh, indent=1, default=str)


if __name__ == "__main__":
    main()
