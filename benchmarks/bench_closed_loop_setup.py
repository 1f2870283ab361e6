"""CPU time of the closed-loop study's simulation set-ups (``simulate``'s ``_prepare``), no kernel.

Runs ``adcskit.simulation.core._prepare`` for the thruster-loop configurations that
``adcskit run closed-loop`` simulates at full settings (per seed: Q1 2 layouts x 4 readings on
GEO, Q2 8 LEO runs, Q3 2 gain sets, Q4 2 GEO slews; the recorded runs aside) with 1000 samples
each, ``--seeds`` times, and prints the process CPU seconds of the whole sequence (imports and
the first-use costs are paid before the clock starts). The set-up is what ``simulate`` does in
Python before the kernel: environment tables, the reference profile, dispersion draws, the
allocation table, the thruster lag coefficients, the feasibility test.

Used to time the set-up caches of issue 24 item 1 against the code before them: run it with
``PYTHONPATH`` on each tree, alternating (see ``docs/benchmarks.md``)::

    git archive <commit-before> src | tar -x -C /tmp/old
    PYTHONPATH=/tmp/old/src python benchmarks/bench_closed_loop_setup.py
    PYTHONPATH=src python benchmarks/bench_closed_loop_setup.py
"""

from __future__ import annotations

import argparse
import json
import os
import time


def configurations(n_seeds: int) -> list:
    """The study's thruster-loop scenarios in its order (the optimised layout: one fixed design)."""
    from adcskit.simulation import ThrusterSpec
    from adcskit.studies.closed_loop import Config
    from adcskit.studies.closed_loop import experiment as ex
    from adcskit.studies.closed_loop.paper import S4_GAINS
    from adcskit.thrusters.reference import S3_REFERENCE_A

    cfg = Config()
    ref = ThrusterSpec.from_torque_matrix(S3_REFERENCE_A)
    opt = ex._design_layout(Config(layout_pop=16, layout_gens=25), 1)
    layouts = {"reference": ref, "optimised": opt}
    fail = {k: ex._failure_index(v)[0] for k, v in layouts.items()}
    out = []
    for _ in range(n_seeds):
        for reading in ex.Q1_READINGS:
            alloc, failed = reading.split(", ")
            for name, lay in layouts.items():
                th = lay.replace(failed=(fail[name],)) if failed == "one failed" else lay
                out.append(ex._geo_base(cfg, th, alloc))
        for reading in ex.Q2_MINMAX_READINGS:
            noise = "uniform" if reading.startswith("bounded") else "gaussian"
            weights = "equal" if reading.endswith("equal weights") else "inverse-variance"
            out += [ex._leo_base(cfg, "wahba", noise, weights), ex._leo_base(cfg, "minmax", noise, weights)]
            if reading in ex.Q2_READINGS:
                out.append(ex._leo_base(cfg, "mekf", noise))
        out += [ex._s4_base(cfg, g) for g in S4_GAINS.values()]
        from adcskit.simulation import GuidanceSpec, SimSpec

        base4 = ex._geo_base(cfg, ref, "pinv-redistribute").replace(
            sim=SimSpec(dt=cfg.geo_dt_s, t_final=cfg.geo_t_final_s + 20.0, metrics_from_s=cfg.geo_t_final_s,
                        settle_band_deg=0.2, record_every=10))
        out += [base4.replace(guidance=GuidanceSpec(kind="step", target_rotvec_deg=(0.0, 0.0, cfg.slew_deg),
                                                    t_step=1.0)), base4]
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--samples", type=int, default=1000)
    args = ap.parse_args()
    import numpy as np

    import adcskit.environment  # noqa: F401  (imports and first-use costs before the clock)
    from adcskit.simulation import core

    scs = configurations(args.seeds)
    w = scs[2]  # lp-min-fuel: warms up scipy's LP too; another orbit and levels, so no cache entry is shared
    core._prepare(w.replace(orbit=w.orbit.replace(altitude_km=900.0),
                            controller=w.controller.replace(torque_level=(1.0, 1.0, 1.0))), 8, np.random.default_rng(0))
    c0, t0 = time.process_time(), time.perf_counter()
    for i, sc in enumerate(scs):
        core._prepare(sc, args.samples, np.random.default_rng(i))
    cpu, wall = time.process_time() - c0, time.perf_counter() - t0
    print(json.dumps({"tree": os.path.dirname(os.path.dirname(os.path.abspath(core.__file__))),
                      "calls": len(scs), "samples": args.samples, "cpu_s": round(cpu, 3), "wall_s": round(wall, 3),
                      "load_average": os.getloadavg()[0]}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
