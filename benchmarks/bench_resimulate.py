"""CPU seconds of :func:`adcskit.optimal_control.resimulate` on the rendezvous study's main branch.

Solves S2's main row (20, 0, 0) m on the paper's 20×3 Gauss mesh and refines it as the study
does (``solve_adaptive``, tol 1e-3, up to 7 solves), then times ``resimulate`` of the refined
solution (the re-simulation of the study's checks; DOP853, rtol 1e-10) and prints the median
process CPU of ``REPEATS`` calls as ``CPU <seconds>`` (the line ``interleaved_cpu.py`` reads),
and the terminal miss (equal before and after a speed change).

Usage::

    PYTHONPATH=src python benchmarks/bench_resimulate.py [REPEATS]
    python benchmarks/interleaved_cpu.py BEFORE/src src 4 -- python benchmarks/bench_resimulate.py
"""

from __future__ import annotations

import statistics
import sys
import time

from adcskit.optimal_control import resimulate, solve, solve_adaptive
from adcskit.optimal_control.problems.rendezvous import rendezvous_problem


def main() -> int:
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    prob = rendezvous_problem((20.0, 0.0, 0.0), dynamics="paper")
    start = solve(prob, method="gauss", mesh=(20, 3))
    fin = solve_adaptive(prob, tol=1e-3, method="gauss", mesh=start.mesh, guess=start, max_iterations=7)
    cpu = []
    for _ in range(repeats):
        c0 = time.process_time()
        r = resimulate(fin)
        cpu.append(time.process_time() - c0)
    print(f"mesh {fin.mesh.n_intervals} intervals, {r.nfev} right-hand-side evaluations, "
          f"terminal miss (scaled) {r.terminal_miss_scaled!r}; per call {', '.join(f'{c:.3f}' for c in cpu)} CPU-s")
    print(f"CPU {statistics.median(cpu):.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
