"""Sample-steps per CPU-second of the on-off loop's CPU driver (for kernel comparisons).

``simulate_batch`` of ``N`` samples of ``bench_onoff.py``'s dispersed S4 loop (inertia,
torque, disturbance, delay from Gaussians, LHS) over 30 s at dt = 1 ms, ``R`` repeats, CPU time of
the process (all threads). Prints JSON (median and runs). Compare two trees by starting both
at the same moment, one numba thread each::

    NUMBA_NUM_THREADS=1 PYTHONPATH=src python benchmarks/experiments/onoff_rates.py 2800 2
"""

import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # benchmarks/
from adcskit.control import LoopSettings, simulate_batch  # noqa: E402
from bench_onoff import _params  # noqa: E402


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 2800
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 2
    p = _params(n)
    s = LoopSettings(t_final=30.0, t_window=10.0)
    simulate_batch(_params(64), LoopSettings(t_final=0.1, t_window=0.05))  # compile / load
    rates = []
    for _ in range(repeats):
        c = time.process_time()
        simulate_batch(p, s)
        rates.append(n * s.n_steps / (time.process_time() - c))
    print(json.dumps({"median": float(np.median(rates)), "runs": rates}))


if __name__ == "__main__":
    main()
