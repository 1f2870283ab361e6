"""Wheel kernel sample-steps per CPU-second on ``bench_wheels.py``'s scenario (for kernel rewrites).

The reference 12U mode sequence (detumble -> sun -> nadir, 85 500 steps of 0.2 s) with
bench_wheels' dispersions, ``samples`` Monte-Carlo samples, ``repeats`` runs (seeds 0, 1, ...),
after a short warm-up call that loads (or compiles) the kernel. Prints one JSON list: the
median rate, then each run's rate, in sample-steps per CPU-second of this process
(``time.process_time``: every thread, so compare runs at the same ``NUMBA_NUM_THREADS``; the
per-core rate does not depend on what else runs on the machine, wall time does). A third
argument ``mekf`` turns the loop's MEKF on (``EstimatorSpec(kind="mekf")``). To compare two
trees, run it alternately in each (one process per tree and run, order swapped every pair,
medians)::

    NUMBA_NUM_THREADS=1 PYTHONPATH=src python benchmarks/experiments/wheel_rates.py 16 3
    NUMBA_NUM_THREADS=1 PYTHONPATH=src python benchmarks/experiments/wheel_rates.py 16 3 mekf
"""

import json
import sys
import time

from adcskit.simulation import SimSpec, WheelDispersionSpec, WheelScenario, simulate_wheels


def main(argv):
    sc = WheelScenario(dispersions=WheelDispersionSpec(inertia_rel=0.1, wheel_misalignment_deg=0.5,
                                                       sensor_noise_rel=0.2, initial_rate_deg_s=1.0,
                                                       initial_attitude="random"))
    if len(argv) > 3 and argv[3] == "mekf":
        from adcskit.simulation import EstimatorSpec

        sc = sc.replace(estimator=EstimatorSpec(kind="mekf"))
    simulate_wheels(sc.replace(sim=SimSpec(dt=0.2, t_final=2.0, metrics_from_s=1.0)), 2, rng=0)  # compile / load
    n, repeats = int(argv[1]), int(argv[2])
    out = []
    for r in range(repeats):
        c0 = time.process_time()
        res = simulate_wheels(sc, n, rng=r)
        out.append(n * res.n_steps / (time.process_time() - c0))
    print(json.dumps([sorted(out)[len(out) // 2]] + out))


if __name__ == "__main__":
    main(sys.argv)
