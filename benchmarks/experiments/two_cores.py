"""Why the closed-loop kernel runs fewer sample-steps per CPU-second on two cores than on one.

bench_basilisk.py's full chain (512 samples x 150 s, as :func:`adcskit.simulation.simulate`
runs it: 8 chunks, one parallel kernel call each) on this machine's two cores gave 10-15 %
fewer sample-steps per CPU-second than on one thread. Three measurements, under the OpenMP wait
policy of this process's environment:

1. **spin after a call**: numba's ``prange`` kernels run on GNU OpenMP here
   (``numba.threading_layer()`` → ``omp``); with libgomp's default wait policy an idle thread
   spins before it sleeps, and ``time.process_time`` counts it. Printed: the process's
   CPU-milliseconds while the main thread sleeps 100 ms right after a tiny parallel kernel
   (min / median of 7);
2. **two threads vs one**: the full chain's sample-steps per CPU-second with
   ``numba.set_num_threads(2)`` over the same with 1, alternated in this one process (order
   swapped every round), per round and median (``--rounds``);
3. **two processes vs one** (``--processes``): two single-thread worker processes, each timing
   256 samples, once one after the other (alone) and once both at the same time; median
   rate at once over median rate alone. No OpenMP barrier and no shared memory between them:
   what is left is the machine (clock, caches, memory, the hypervisor).

Run::

    env -u OMP_WAIT_POLICY python benchmarks/experiments/two_cores.py --rounds 10 --processes 6
    OMP_WAIT_POLICY=PASSIVE python benchmarks/experiments/two_cores.py --rounds 10

Results: docs/benchmarks.md, "Two cores per CPU-second".
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time

import numba
import numpy as np
from numba import njit, prange

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # benchmarks/


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


def _process_worker() -> None:
    numba.set_num_threads(1)
    from adcskit.simulation import simulate
    from bench_basilisk import _speed_scenarios

    _, full = _speed_scenarios(150.0)
    simulate(full, 16, rng=0)
    print("ready", flush=True)
    for line in sys.stdin:
        c0 = time.process_time()
        res = simulate(full, 256, rng=int(line))
        print(256 * res.n_steps / (time.process_time() - c0), flush=True)


def two_processes(rounds: int) -> tuple[float, float]:
    """Median single-thread rate of two worker processes: alone (in turn), and at once."""
    env = dict(os.environ, NUMBA_NUM_THREADS="1")
    ps = [subprocess.Popen([sys.executable, os.path.abspath(__file__), "--worker"], env=env,
                           stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True) for _ in range(2)]
    try:
        for p in ps:
            if p.stdout.readline().strip() != "ready":
                sys.exit("a worker did not start")
        alone, both = [], []
        for r in range(rounds):
            for p in ps:
                p.stdin.write(f"{r}\n")
                p.stdin.flush()
                alone.append(float(p.stdout.readline()))
            for p in ps:
                p.stdin.write(f"{r}\n")
                p.stdin.flush()
            both += [float(p.stdout.readline()) for p in ps]
    finally:
        for p in ps:
            p.stdin.close()
            p.wait()
    return statistics.median(alone), statistics.median(both)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=10)
    ap.add_argument("--processes", type=int, default=0, help="rounds of the two-process measurement (0: skip)")
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
    if args.processes > 0:
        alone, both = two_processes(args.processes)
        print(f"  two single-thread processes: alone {alone:.3g}, both at once {both:.3g} sample-steps per "
              f"CPU-second each (medians of {args.processes} rounds): ratio {both / alone:.3f}")


if __name__ == "__main__":
    if sys.argv[1:] == ["--worker"]:
        _process_worker()
    else:
        main()
