"""What idle OpenMP threads cost the closed-loop kernel's CPU-seconds on several threads.

numba's ``prange`` kernels run on GNU OpenMP here (``numba.threading_layer()`` → ``omp``). With
libgomp's default wait policy an idle thread spins before it sleeps: after every parallel
region (while the main thread is back in Python) and at the barrier that ends it (the thread
that finished its share first). ``time.process_time`` counts that CPU. Two measurements under
the policy of this process's environment (run once with and once without
``OMP_WAIT_POLICY=PASSIVE``):

1. **spin after a call**: the process's CPU-milliseconds while the main thread sleeps 100 ms
   right after a tiny parallel kernel (min / median of 7);
2. **two threads vs one**: bench_basilisk.py's full chain (512 samples x 150 s, as
   :func:`adcskit.simulation.simulate` runs it: 8 chunks, one kernel call each), sample-steps
   per CPU-second with ``numba.set_num_threads(2)`` over the same with 1, alternated in this
   one process, per round and median (``--rounds``).

Run::

    env -u OMP_WAIT_POLICY python benchmarks/omp_spin.py --rounds 10
    OMP_WAIT_POLICY=PASSIVE python benchmarks/omp_spin.py --rounds 10

Results: docs/benchmarks.md, "Two threads per CPU-second".
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

import numba
import numpy as np
from numba import njit, prange

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


@njit(parallel=True)
def _tiny(n):
    out = np.zeros(n)
    for i in prange(n):
        out[i] = 2.0 * i
    return out


def spin_after_call(reps: int = 7) -> list[float]:
    """CPU-ms of the process while its main thread sleeps 100 ms after a parallel call."""
    _tiny(100)
    out = []
    for _ in range(reps):
        _tiny(1000)
        c0 = time.process_time()
        time.sleep(0.1)
        out.append(1e3 * (time.process_time() - c0))
    return out


def two_vs_one(rounds: int, n: int = 512) -> list[float]:
    """Per-round ratio (2 threads / 1 thread) of full-chain sample-steps per CPU-second."""
    from adcskit.simulation import simulate
    from bench_basilisk import _speed_scenarios

    _, full = _speed_scenarios(150.0)
    simulate(full, 64, rng=0)
    ratios = []
    for r in range(rounds):
        rate = {}
        for th in ((1, 2) if r % 2 == 0 else (2, 1)):
            numba.set_num_threads(th)
            c0 = time.process_time()
            res = simulate(full, n, rng=20 + r)
            rate[th] = n * res.n_steps / (time.process_time() - c0)
        ratios.append(rate[2] / rate[1])
    return ratios


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=10)
    args = ap.parse_args()
    if numba.config.NUMBA_NUM_THREADS < 2:
        sys.exit("needs at least two numba threads")
    spin = spin_after_call()
    print(f"OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY')}, threading layer "
          f"{numba.threading_layer()}")
    print(f"  CPU while the main thread sleeps 100 ms after a parallel call: min {min(spin):.1f} ms, "
          f"median {statistics.median(spin):.1f} ms")
    r = two_vs_one(args.rounds)
    print(f"  full chain, sample-steps per CPU-second, 2 threads / 1 thread: median "
          f"{statistics.median(r):.3f} (rounds: {', '.join(f'{x:.3f}' for x in r)})")


if __name__ == "__main__":
    main()
