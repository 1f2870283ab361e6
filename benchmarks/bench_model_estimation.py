"""Benchmark of the S1 model-estimation study: where the time goes, and one anchor ratio.

Measures in one run:

1. the whole study (``--quick``: the quick variant) with the serial executor, wall time;
2. one joint-estimation run (L = 200 steps) per method on ``3dof-random`` and
   ``1dof-random``: milliseconds per run, i.e. where the study's time goes;
3. the anchor: one least-squares identification call of ``identify_model(method="qr")``
   against ``numpy.linalg.lstsq`` on the same 200 x 6 regression (ratio ours / numpy), and
   ``identify_model(method="gmres")`` against a bare ``scipy.sparse.linalg.gmres`` call on
   the same normal equations (ratio = our wrapper's overhead).

Usage: ``python benchmarks/bench_model_estimation.py [--quick] [--json PATH] [--out DIR]``.
Timings on the shared 2-core machine are noisy (other jobs run concurrently).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse.linalg as spla
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from adcskit.estimation import augmented_ekf, identify_model, joint_estimate, simulate_linear  # noqa: E402
from adcskit.estimation.identification import _normal_system, regression_data  # noqa: E402
from adcskit.studies._runner import run_study  # noqa: E402
from adcskit.studies.model_estimation import METHODS, Config, _method_options, build_case  # noqa: E402


def _best(fn, repeat=5):
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return min(ts)


def per_method(case_name, N=200, repeat=3):
    cfg = Config()
    case = build_case(case_name, cfg)
    n = case.A.shape[0]
    rng = np.random.default_rng(0)
    u = rng.standard_normal((N, case.B.shape[1]))
    sim = simulate_linear(case.A, case.B, np.eye(n), u, R=1.0, rng=rng)
    Q = cfg.kalman_q * np.eye(n)
    out = {}
    for m in METHODS:
        if m == "augmented-ekf":
            def f():
                augmented_ekf(sim.y, u, case.model, np.ones(case.n_param), P_p0=0.25, Q_p=1e-6, Q=Q, R=1.0)
        else:
            def f(m=m):
                joint_estimate(sim.y, u, A_prior=case.A0, B=case.B, Q=Q, R=1.0, method=m,
                               options=_method_options(m, case, cfg, 1.0), rng=1)
        out[m] = 1e3 * _best(f, repeat)
    return out


def anchor():
    cfg = Config()
    case = build_case("3dof-random", cfg)
    rng = np.random.default_rng(1)
    N = 200
    u = rng.standard_normal((N, 3))
    sim = simulate_linear(case.A, case.B, np.eye(6), u, R=0.01**2, rng=rng)
    X, Z, U = sim.x[: N - 1], sim.y[1:N], u[: N - 1]
    Phi, Zc = regression_data(X, Z, U, B=case.B)
    t_ours = _best(lambda: identify_model(X, Z, U, B=case.B, method="qr"), 200)
    t_np = _best(lambda: np.linalg.lstsq(Phi, Zc, rcond=None), 200)
    M, b = _normal_system(Phi, Zc)
    t_g_ours = _best(lambda: identify_model(X, Z, U, B=case.B, method="gmres", options={"rtol": 1e-8}), 100)
    t_g_sp = _best(lambda: spla.gmres(M, b, rtol=1e-8, restart=36), 100)
    return {
        "qr_us": 1e6 * t_ours, "numpy_lstsq_us": 1e6 * t_np, "qr_over_lstsq": t_ours / t_np,
        "gmres_us": 1e6 * t_g_ours, "scipy_gmres_us": 1e6 * t_g_sp, "gmres_over_scipy": t_g_ours / t_g_sp,
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="time the quick study instead of the full one")
    ap.add_argument("--json", type=Path, help="write the measurements to this JSON file")
    ap.add_argument("--out", type=Path, default=None, help="also write the study's outputs here")
    args = ap.parse_args(argv)
    res: dict = {"quick": args.quick}
    t0 = time.perf_counter()
    run_study("model-estimation", quick=args.quick, seed=0, out=args.out, executor="serial")
    res["study_wall_s"] = time.perf_counter() - t0
    print(f"model-estimation ({'quick' if args.quick else 'full'}, serial): {res['study_wall_s']:.1f} s")
    with threadpool_limits(limits=1, user_api="blas"):
        for c in ("3dof-random", "1dof-random"):
            pm = per_method(c, repeat=1 if args.quick else 3)
            res[f"per_method_ms_{c}"] = pm
            tot = sum(pm.values())
            print(f"\none joint run, L = 200, {c} (ms; share of the 11 methods):")
            for m, v in sorted(pm.items(), key=lambda kv: -kv[1]):
                print(f"  {m:24s} {v:8.1f}  {100 * v / tot:5.1f} %")
        a = anchor()
    res["anchor"] = a
    print(f"\nanchor, one 200x6 LS solve: identify_model(qr) {a['qr_us']:.0f} us vs numpy.linalg.lstsq "
          f"{a['numpy_lstsq_us']:.0f} us -> ratio {a['qr_over_lstsq']:.2f}")
    print(f"identify_model(gmres) {a['gmres_us']:.0f} us vs bare scipy gmres {a['scipy_gmres_us']:.0f} us "
          f"-> ratio {a['gmres_over_scipy']:.2f}")
    if args.json:
        args.json.write_text(json.dumps(res, indent=2))


if __name__ == "__main__":
    main()
