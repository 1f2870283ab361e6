"""Two (or more) source trees' closed-loop kernels side by side, for a noisy machine.

``experiments/kernel_rates.py`` starts one process per tree and run; on a 2-vCPU VM whose rate moves by
±20 % from one minute to the next (the Xeon instance of 2026-12-02: the same run gave 2.8e6 to
4.4e6 sample-steps per CPU-second), whole-run alternation needs many runs. Here every tree gets
one persistent worker process (single numba thread, its own numba cache, warmed up), and the
driver asks the workers in turn for short timed kernel calls (``--samples`` samples × the
bench's 150 s): consecutive calls of the trees are seconds apart, so they see the same machine.
Printed per variant and tree: the best and the median sample-steps per CPU-second over
``--rounds`` and both relative to the first tree. Run::

    python benchmarks/kernel_ab.py /work/main /tmp/variant --variants full,truth,same --rounds 12

Variants: ``full`` (bench_basilisk's full chain), ``truth`` (the same with the truth
estimator), ``same`` (the same elements as Basilisk), ``general`` (the full chain with the
inertia off the principal axes: a full matrix, the general RK4 step). Results: docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def _worker() -> None:
    import numba

    numba.set_num_threads(1)
    sys.path.insert(0, HERE)
    from adcskit.simulation import EstimatorSpec, simulate
    from bench_basilisk import _general_inertia, _speed_scenarios

    same, full = _speed_scenarios(150.0)
    scen = {"full": full, "same": same, "truth": full.replace(estimator=EstimatorSpec(kind="truth")),
            "general": _general_inertia(full)}
    for sc in scen.values():
        simulate(sc, 8, rng=0)
    print("ready", flush=True)
    for line in sys.stdin:
        name, n = line.split()
        c0 = time.process_time()
        out = simulate(scen[name], int(n), rng=7)
        print(int(n) * out.n_steps / (time.process_time() - c0), flush=True)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("trees", nargs="+", help="source trees (each with src/adcskit)")
    ap.add_argument("--variants", default="full,truth,same")
    ap.add_argument("--rounds", type=int, default=12)
    ap.add_argument("--samples", type=int, default=128)
    args = ap.parse_args(argv)
    variants = args.variants.split(",")
    unknown = sorted(set(variants) - {"full", "truth", "same", "general"})
    if unknown or args.rounds < 1 or args.samples < 1 or len(args.trees) < 1:
        ap.error(f"variants must be among full, truth, same, general (got {unknown}); rounds and samples >= 1")
    workers = []
    for i, tree in enumerate(args.trees):
        tree = os.path.abspath(tree)
        if not os.path.isdir(os.path.join(tree, "src", "adcskit")):
            ap.error(f"{tree} has no src/adcskit")
        env = dict(os.environ, PYTHONPATH=os.path.join(tree, "src"), NUMBA_NUM_THREADS="1",
                   NUMBA_CACHE_DIR=os.path.join(os.environ.get("TMPDIR", "/tmp"), f"kernel_ab_cache_{i}"))
        p = subprocess.Popen([sys.executable, os.path.abspath(__file__), "--worker"], cwd=tree, env=env,
                             stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        if p.stdout.readline().strip() != "ready":
            sys.exit(f"worker for {tree} did not start")
        workers.append((tree, p))
    rates = {(t, v): [] for t, _ in workers for v in variants}
    try:
        for _ in range(args.rounds):
            for v in variants:
                for t, p in workers:
                    p.stdin.write(f"{v} {args.samples}\n")
                    p.stdin.flush()
                    rates[(t, v)].append(float(p.stdout.readline()))
    finally:
        for _, p in workers:
            p.stdin.close()
            p.wait()
    for v in variants:
        b0 = m0 = None
        for t, _ in workers:
            x = rates[(t, v)]
            b, m = max(x), statistics.median(x)
            b0, m0 = b0 or b, m0 or m
            print(f"{v:5s} {t}: best {b:.3e} ({1e9 / b:.0f} ns/sample-step), median {m:.3e}; "
                  f"vs first tree: best {b / b0:.3f}, median {m / m0:.3f}")


if __name__ == "__main__":
    if sys.argv[1:] == ["--worker"]:
        _worker()
    else:
        main()
