"""Benchmark: the S2 rendezvous on a 20×3 mesh, adcskit (CasADi + IPOPT) vs dymos.

Measures in one run the wall time of (and prints, for the cold adcskit solves, the NLP build
and IPOPT parts)

* adcskit: ``solve(rendezvous_problem(s0), mesh=(20, 3))`` — "cold" includes building and
  compiling the NLP (cache cleared), "warm" reuses the cached ``nlpsol`` (the normal case
  when several rows or a multistart share one problem structure); Gauss and Radau;
* dymos (OpenMDAO): the same dynamics (eq. 2 as printed) as an OpenMDAO component with
  complex-step partials and coloring, ``Radau(num_segments=20, order=3)`` (3 LGR collocation
  points per segment, the same grid as our Radau 20×3), solved by ``ScipyOptimizeDriver``
  SLSQP (pyoptsparse/IPOPT is not installable here from PyPI), from the same straight-line
  initial guess, including problem setup.

The row is ``s0 = [20, 4, 4]`` m (S2 Table 4, row 3): the main row's straight-line guess is a
symmetric stationary point from which no local solver moves (see docs/studies/rendezvous.md),
so a deterministic comparison uses a row that both tools can start from the same guess.

Usage: ``python benchmarks/bench_rendezvous.py [--quick] [--json PATH] [--no-dymos] [--dymos-maxiter N]``

``--quick`` runs dymos on 4 segments (its 20-segment SLSQP solve takes ~27 min); the
JSON records ``dymos_num_segments`` so the ratio is never mistaken for the 20×3 one.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import statistics
import sys
import tempfile
import time
import warnings

import numpy as np

S0 = (20.0, 4.0, 4.0)


def bench_adcskit(repeats: int) -> dict:
    from adcskit.optimal_control import clear_cache, solve
    from adcskit.optimal_control.problems.rendezvous import rendezvous_problem

    out = {}
    for method in ("gauss", "radau"):
        cold, warm, tfs, status, build, ipopt = [], [], [], [], [], []
        for _ in range(repeats):
            clear_cache()
            t = time.perf_counter()
            s = solve(rendezvous_problem(S0), method=method, mesh=(20, 3))
            cold.append(time.perf_counter() - t)
            build.append(s.build_s)  # the cold solve's NLP build and IPOPT wall times
            ipopt.append(s.solve_s)
            t = time.perf_counter()
            s = solve(rendezvous_problem(S0), method=method, mesh=(20, 3))
            warm.append(time.perf_counter() - t)
            tfs.append(s.tf)
            status.append(s.ipopt_status)
        out[method] = {
            "cold_s": statistics.median(cold),
            "cold_build_s": statistics.median(build),
            "cold_ipopt_s": statistics.median(ipopt),
            "warm_s": statistics.median(warm),
            "tf_s": tfs[-1],
            "status": status[-1],
            "nit": s.nit,
        }
    return out


def bench_dymos(repeats: int, *, num_segments: int = 20, maxiter: int = 500) -> dict:
    import dymos as dm
    import openmdao.api as om

    from adcskit.optimal_control.problems.rendezvous import RendezvousParams

    prm = RendezvousParams()
    n = prm.mean_motion
    inertia = np.array(prm.inertia)
    mass = prm.mass

    class ODE(om.ExplicitComponent):
        def initialize(self):
            self.options.declare("num_nodes", types=int)

        def setup(self):
            nn = self.options["num_nodes"]
            for name in ("w", "sigma", "v", "s", "T", "F"):
                self.add_input(name, shape=(nn, 3))
            for name in ("w_dot", "sigma_dot", "v_dot", "s_dot"):
                self.add_output(name, shape=(nn, 3))
            self.declare_partials("*", "*", method="cs")
            self.declare_coloring(wrt="*", method="cs", show_summary=False)

        def compute(self, i, o):
            w, sig, v, s, T, F = i["w"], i["sigma"], i["v"], i["s"], i["T"], i["F"]
            s2 = np.sum(sig * sig, axis=1)[:, None, None]
            S = np.zeros(sig.shape + (3,), dtype=sig.dtype)
            S[:, 0, 1], S[:, 0, 2], S[:, 1, 2] = -sig[:, 2], sig[:, 1], -sig[:, 0]
            S[:, 1, 0], S[:, 2, 0], S[:, 2, 1] = sig[:, 2], -sig[:, 1], sig[:, 0]
            eye = np.eye(3)[None]
            A = eye + (8 * S @ S - 4 * (1 - s2) * S) / (1 + s2) ** 2
            wli = A @ np.array([0.0, -n, 0.0])
            wbi = w + wli
            o["w_dot"] = (T - np.cross(w, inertia * w) - np.cross(wli, inertia * wbi)) / inertia
            B = (1 - s2) * eye + 2 * S + 2 * sig[:, :, None] * sig[:, None, :]
            o["sigma_dot"] = 0.25 * np.einsum("nij,nj->ni", B, w)
            FL = np.einsum("nji,nj->ni", A, F)
            acc = FL / mass
            acc[:, 0] += 2 * n * v[:, 2]
            acc[:, 1] += -(n**2) * s[:, 1]
            acc[:, 2] += -2 * n * v[:, 0] + 3 * n**2 * s[:, 2]
            o["v_dot"] = acc
            o["s_dot"] = v

    def build_and_solve():
        p = om.Problem(reports=False)
        phase = dm.Phase(ode_class=ODE, transcription=dm.Radau(num_segments=num_segments, order=3))
        traj = dm.Trajectory()
        traj.add_phase("p", phase)
        p.model.add_subsystem("traj", traj)
        phase.set_time_options(fix_initial=True, duration_bounds=(1.0, 500.0), duration_ref=25.0)
        refs = {"w": 0.05, "sigma": 0.4, "v": 0.6, "s": 20.0}
        for name, ref in refs.items():
            phase.add_state(name, shape=(3,), rate_source=f"{name}_dot", fix_initial=True, fix_final=True,
                            ref=ref, defect_ref=ref)
        phase.add_control("T", shape=(3,), lower=-50.0, upper=50.0, ref=50.0, continuity=False, rate_continuity=False)
        phase.add_control("F", shape=(3,), lower=-320.0, upper=320.0, ref=320.0, continuity=False, rate_continuity=False)
        phase.add_objective("time", loc="final", ref=25.0)
        p.driver = om.ScipyOptimizeDriver(optimizer="SLSQP", maxiter=maxiter, tol=1e-8, disp=False)
        p.driver.declare_coloring(show_summary=False, show_sparsity=False)
        p.setup(force_alloc_complex=True)
        sf = math.tan(math.pi / 8)
        phase.set_time_val(initial=0.0, duration=25.0)
        phase.set_state_val("w", [[0, 0, 0], [0, 0, 0]])
        phase.set_state_val("sigma", [[0, 0, 0], [0, sf, 0]])
        phase.set_state_val("v", [[0, 0, 0], [0, 0, 0]])
        phase.set_state_val("s", [list(S0), [0, 0, -10.0]])
        phase.set_control_val("T", [[0, 0, 0], [0, 0, 0]])
        phase.set_control_val("F", [[0, 0, 0], [0, 0, 0]])
        failed = dm.run_problem(p, run_driver=True, simulate=False)
        tf = float(p.get_val("traj.p.timeseries.time")[-1, 0])
        res = getattr(p.driver, "result", None)
        ok = bool(res.success) if res is not None else not failed
        nit = int(getattr(res, "nit", -1)) if res is not None else -1
        msg = str(getattr(res, "message", "")) if res is not None else ""
        return tf, ok, nit, msg

    times, tf, ok, nit, msg = [], math.nan, False, -1, ""
    for _ in range(repeats):
        t = time.perf_counter()
        cwd = os.getcwd()
        with (
            tempfile.TemporaryDirectory() as tmp,  # OpenMDAO writes <problem>_out/ into the cwd
            warnings.catch_warnings(),
            contextlib.redirect_stdout(sys.stderr),  # keep stdout pure JSON
        ):
            os.chdir(tmp)
            try:
                warnings.simplefilter("ignore")
                tf, ok, nit, msg = build_and_solve()
            finally:
                os.chdir(cwd)
        times.append(time.perf_counter() - t)
    return {"solve_s": statistics.median(times), "tf_s": tf, "success": ok, "nit": nit, "message": msg,
            "repeats": repeats, "num_segments": num_segments, "maxiter": maxiter}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="1 repetition instead of 5; dymos on 4 segments instead of 20 (20 takes ~30 min)")
    ap.add_argument("--dymos-maxiter", type=int, default=2000, help="SLSQP iteration limit (default 2000)")
    ap.add_argument("--json", metavar="PATH", help="write the results as JSON")
    ap.add_argument("--no-dymos", action="store_true", help="skip dymos")
    args = ap.parse_args(argv)
    reps = 1 if args.quick else 5
    ours = bench_adcskit(reps)
    results = {
        "adcskit_solve_s": ours["gauss"]["cold_s"],
        "adcskit_solve_warm_s": ours["gauss"]["warm_s"],
        "adcskit_radau_solve_s": ours["radau"]["cold_s"],
        "adcskit_radau_solve_warm_s": ours["radau"]["warm_s"],
        "adcskit_tf_s": ours["gauss"]["tf_s"],
        "adcskit_radau_tf_s": ours["radau"]["tf_s"],
        "adcskit_status": ours["gauss"]["status"],
        "adcskit_build_s": ours["gauss"]["cold_build_s"],
        "adcskit_ipopt_s": ours["gauss"]["cold_ipopt_s"],
        "adcskit_radau_build_s": ours["radau"]["cold_build_s"],
        "adcskit_radau_ipopt_s": ours["radau"]["cold_ipopt_s"],
        "dymos_solve_s": None,
    }
    for m in ("gauss", "radau"):
        print(f"adcskit {m} 20x3 cold: NLP build {ours[m]['cold_build_s']:.2f} s, IPOPT {ours[m]['cold_ipopt_s']:.2f} s "
              "(wall, medians)", file=sys.stderr)
    note = ""
    if not args.no_dymos:
        try:
            d = bench_dymos(1, num_segments=4 if args.quick else 20, maxiter=args.dymos_maxiter)
            results.update(
                {
                    "dymos_solve_s": d["solve_s"],
                    "dymos_tf_s": d["tf_s"],
                    "dymos_success": d["success"],
                    "dymos_num_segments": d["num_segments"],
                    "dymos_maxiter": d["maxiter"],
                }
            )
            if not d["success"]:
                note = (
                    f"dymos/SLSQP stopped without converging (iteration limit {d['maxiter']}); "
                    "its time is a lower bound"
                )
        except ImportError as exc:  # dymos is in the "bench" extra
            note = f"dymos not run: {exc}"
    ratios = {
        "dymos_vs_adcskit": (results["dymos_solve_s"] / results["adcskit_solve_s"]) if results["dymos_solve_s"] else None,
        "dymos_vs_adcskit_warm": (results["dymos_solve_s"] / results["adcskit_solve_warm_s"]) if results["dymos_solve_s"] else None,
    }
    doc = {
        "benchmark": "rendezvous 20x3",
        "s0_m": list(S0),
        "repeats": reps,
        "results": results,
        "ratios": ratios,
        "note": note,
    }
    print(json.dumps(doc, indent=2))
    if ratios["dymos_vs_adcskit"]:
        print(f"dymos / adcskit (cold, incl. build): {ratios['dymos_vs_adcskit']:.1f}x", file=sys.stderr)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(doc, fh, indent=2)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
