"""Benchmark: hp mesh refinement on standard optimal-control problems with published optima,
beside uniform refinement and dymos.

For every problem, in one run:

* **hp**: ``solve_adaptive(problem, tol)`` (Radau) from the default naive guess (Goddard: a
  piecewise-linear guess, 4×4 meshes; launch ascent: :func:`launch_ascent_guess`, 8×4
  meshes) — objective vs the published value, collocation points, mesh
  iterations, total IPOPT iterations and wall time (NLP builds included);
* **uniform**: ``solve`` on equal 4-point intervals, the count doubling from 10, the first
  from :func:`symmetry_breaking_guess` (as hp), each next one warm started from the previous, until the same error estimate meets ``tol`` (or 640
  intervals): the collocation points uniform refinement needs for the same tolerance;
* **dymos** (where it runs: brachistochrone, hypersensitive, Bryson–Denham): the same
  problem in dymos' Radau transcription on a fixed grid with at least as many collocation
  points as our final hp mesh (order 3, ``ceil(n / 3)`` segments), solved by
  ``ScipyOptimizeDriver`` SLSQP (pyoptsparse — dymos' route to IPOPT — is not installable
  from PyPI here), same naive guess; wall time including setup.

Usage::

    python benchmarks/bench_optimal_control.py [--quick] [--tol 1e-6] [--no-dymos]
        [--rigid-body] [--json PATH] [--figures DIR]
    python benchmarks/bench_optimal_control.py --suite [--tol 1e-6] [--json PATH]

``--quick`` uses ``tol = 1e-4`` and skips dymos; ``--rigid-body`` adds the Bilimoria & Wie
reorientation (several minutes on a loaded machine); ``--only NAME`` runs one problem.

``--suite`` (issue 22, item 4) instead solves the standard bang-bang / constrained suite —
the free-flying robot (GPOPS-II J* = 7.9101471), the four-switch minimum-time oscillator
(reference: the shooting oracle), Bryson & Ho's orbit raising (thrust direction as a unit
vector; r(tf) = 1.525 printed), the COPS robot arm (tf* = 9.1409118) and the issue-43 rows
(bang-singular-bang at tf = 3, 2.04, 2.06, J* = 2/3; Bryson-Denham, J* = 4; rest-to-rest with
u + v <= 1; the oscillator from (5.3, 3.1), T* = 10.10346299) — each from the
default naive guess with Radau and Gauss at ``--tol`` (default 1e-6), and prints a Markdown
table: published value, our J, relative error, success / ``optimality_met``, collocation
points, IPOPT iterations, CPU s (the process's CPU time of the ``solve_adaptive`` call, NLP
builds included; the compiled-NLP cache is cleared first) and the split of wall time into
CasADi NLP builds and IPOPT (issue 22, item 5). dymos is run beside only where it is
importable (it is not installed by default).

``--ablation`` instead runs ``solve_adaptive`` on each selected problem in four settings side
by side — refined meshes warm-started with primal values only or with the interpolated
multipliers too (``transfer_duals``), with and without mesh reduction
(``mesh_reduction``) — and prints, per setting, the IPOPT iterations of every mesh
iteration, their sum over the refined meshes, the final collocation points and the wall
time (NLP builds included; the compiled-NLP cache is cleared before each run).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import sys
import tempfile
import time
import warnings

import numpy as np


def _goddard_guess():
    from adcskit.optimal_control import MultiPhaseGuess
    from adcskit.optimal_control.problem import Guess

    def g(t0, tf, x0, xf, u):
        return Guess(t=np.array([t0, tf]), x=np.array([x0, xf], float), u=np.array([[u], [u]], float), tf=tf)

    return MultiPhaseGuess(
        phases=(
            g(0, 10, [0, 0, 3], [3000, 600, 2.0], 193.044),
            g(10, 30, [3000, 600, 2.0], [12000, 500, 1.2], 100.0),
            g(30, 45, [12000, 500, 1.2], [18000, 0, 1.2], 0.0),
        ),
        parameters=np.zeros(0),
    )


def problems(rigid_body: bool):
    """(name, problem, guess, initial mesh) of every benchmarked problem."""
    from adcskit.optimal_control.problems import launch_ascent, launch_ascent_guess
    from adcskit.optimal_control.problems import standard as S

    launch = launch_ascent()
    out = [
        ("hypersensitive", S.hypersensitive(10.0), None, None),
        ("bryson-denham", S.bryson_denham(1.0 / 9.0), None, None),
        ("brachistochrone", S.brachistochrone(10.0, 5.0), None, None),
        ("goddard-rocket", S.goddard_rocket(), _goddard_guess(), [(4, 4)] * 3),
        ("launch-ascent", launch, launch_ascent_guess(launch), [(8, 4)] * 4),
        # issue 22: bang-bang problems (exact switch times through free phase boundaries)
        ("free-flying-robot", S.free_flying_robot(), None, None),
        ("oscillator-min-time", S.oscillator_min_time(), None, None),
    ]
    if rigid_body:
        out.append(("rigid-body-reorientation", S.rigid_body_reorientation(180.0), None, None))
    return out


SUITE = ("free-flying-robot", "oscillator-min-time", "orbit-raising", "robot-arm")


def suite_problems():
    """(name, problem factory, (reference, source)) of the issue-22 suite and the issue-43 rows
    (singular arcs, a state and a mixed path constraint, the oscillator from (5.3, 3.1))."""
    from adcskit.optimal_control.problems import singular as G
    from adcskit.optimal_control.problems import standard as S

    ref = S.reference_objective
    bsb = (2.0 / 3.0, "J* = 2/3 for tf >= 2 (minimum principle; problems/singular.py)")
    return (
        ("free-flying-robot", S.free_flying_robot, None),
        ("oscillator-min-time", S.oscillator_min_time, None),
        ("orbit-raising", S.orbit_raising, None),
        ("robot-arm", S.robot_arm, None),
        ("bang-singular-bang tf=3", lambda: G.bang_singular_bang(3.0), bsb),
        ("bang-singular-bang tf=2.04", lambda: G.bang_singular_bang(2.04), bsb),
        ("bang-singular-bang tf=2.06", lambda: G.bang_singular_bang(2.06), bsb),
        ("bryson-denham", S.bryson_denham, ref("bryson-denham")),
        ("rest-to-rest-mixed-path", G.rest_to_rest_mixed_path,
         (G.rest_to_rest_mixed_path_time(1.0), "T* from the speed envelope min(1 - e^-t, T - t) (problems/singular.py)")),
        ("oscillator (5.3, 3.1)", lambda: S.oscillator_min_time(5.3, 3.1),
         (S.oscillator_min_time_reference(5.3, 3.1)[0], "minimum principle by shooting, 4 switches (10.10346299)")),
    )


def run_suite(tol, only=None, methods=("radau", "gauss")):
    """Solve every suite problem with every method; one row per (problem, method)."""
    from adcskit.optimal_control import clear_cache, solve_adaptive
    from adcskit.optimal_control.problems import reference_objective

    rows = []
    for name, make, known in suite_problems():
        if only and name not in only:
            continue
        ref, src = known if known is not None else reference_objective(name)
        for method in methods:
            prob = make()
            clear_cache()
            c0, w0 = time.process_time(), time.perf_counter()
            sol = solve_adaptive(prob, tol=tol, method=method)
            cpu, wall = time.process_time() - c0, time.perf_counter() - w0
            h = sol.mesh_history
            row = {
                "problem": name, "method": method, "tol": tol, "reference": ref, "reference_source": src,
                "objective": sol.objective, "rel_error": abs(sol.objective - ref) / abs(ref),
                "success": bool(sol.success), "error_met": bool(sol.certificate.error_met),
                "optimality_met": sol.certificate.optimality_met,  # None: not checked
                "optimality_checks": list(sol.certificate.optimality_checks),
                "n_collocation": int(sol.certificate.n_collocation), "mesh_iterations": len(h),
                "ipopt_iterations": int(sum(m.nit for m in h)), "cpu_s": cpu, "wall_s": wall,
                "build_s": float(sum(m.build_s for m in h)), "ipopt_s": float(sum(m.ipopt_s for m in h)),
                "message": sol.message,
            }
            rows.append(row)
            print(f"{name:22s} {method:5s} J={sol.objective:.10g} rel={row['rel_error']:.2e} ok={sol.success} "
                  f"opt={row['optimality_met']} N={row['n_collocation']} it={row['ipopt_iterations']} "
                  f"cpu={cpu:.2f}s build={row['build_s']:.2f}s ipopt={row['ipopt_s']:.2f}s", file=sys.stderr, flush=True)
    return rows


def suite_table(rows) -> str:
    """The suite's rows as a Markdown table."""
    try:
        import dymos  # noqa: F401

        dymos_note = "dymos: installed but not wired for these problems"
    except ImportError:
        dymos_note = "dymos: not installed"
    out = ["| problem | method | known optimum | our J | rel. error | success / optimality_met | nodes | "
           "IPOPT it. | CPU s | build s / IPOPT s (wall) |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        opt = "not checked" if r["optimality_met"] is None else r["optimality_met"]
        out.append(f"| {r['problem']} | {r['method']} | {r['reference']:.10g} | {r['objective']:.10g} | "
                   f"{r['rel_error']:.1e} | {r['success']} / {opt} | {r['n_collocation']} | "
                   f"{r['ipopt_iterations']} | {r['cpu_s']:.2f} | {r['build_s']:.2f} / {r['ipopt_s']:.2f} |")
    out.append("")
    out.append(f"({dymos_note}.)")
    return "\n".join(out)


def run_hp(prob, guess, tol, mesh=None):
    from adcskit.optimal_control import clear_cache, solve_adaptive

    clear_cache()
    t = time.perf_counter()
    sol = solve_adaptive(prob, tol=tol, guess=guess, mesh=mesh, max_iterations=15,
                         ipopt_options={"max_iter": 1500})
    wall = time.perf_counter() - t
    return sol, wall


def run_uniform(prob, tol, max_intervals=640):
    from adcskit.optimal_control import estimate_error, solve, symmetry_breaking_guess

    hist = []
    guess = symmetry_breaking_guess(prob)  # the same start as solve_adaptive's default
    k = 10
    t = time.perf_counter()
    while k <= max_intervals:
        s = solve(prob, method="radau", mesh=(k, 4), guess=guess)
        e = float(estimate_error(s).max())
        hist.append((4 * k, e, s.objective, s.success))
        if s.success:
            guess = s
        if s.success and e <= tol:
            break
        k *= 2
    wall = time.perf_counter() - t
    met = bool(hist and hist[-1][3] and hist[-1][1] <= tol)
    return {"history": hist, "n_collocation": hist[-1][0] if met else None, "met": met, "wall_s": wall}


ABLATION = ((False, False), (True, False), (False, True), (True, True))


def run_ablation(name, prob, guess, tol, mesh=None):
    from adcskit.optimal_control import clear_cache, solve_adaptive

    rows = []
    for duals, reduce in ABLATION:
        clear_cache()
        t = time.perf_counter()
        sol = solve_adaptive(prob, tol=tol, guess=guess, mesh=mesh, max_iterations=15,
                             ipopt_options={"max_iter": 1500}, transfer_duals=duals, mesh_reduction=reduce)
        wall = time.perf_counter() - t
        h = sol.mesh_history
        row = {
            "problem": name, "transfer_duals": duals, "mesh_reduction": reduce, "success": sol.success,
            "objective": sol.objective, "n_collocation": sol.certificate.n_collocation,
            "mesh_iterations": len(h), "nit": [m.nit for m in h], "nit_refined": sum(m.nit for m in h[1:]),
            "nit_total": sum(m.nit for m in h), "points": [m.n_collocation for m in h],
            "warm_start": [m.warm_start for m in h], "wall_s": wall,
        }
        rows.append(row)
        print(f"{name:26s} duals={int(duals)} reduce={int(reduce)} ok={sol.success} J={sol.objective:.10g} "
              f"N={row['n_collocation']} mesh_its={row['mesh_iterations']} nit={row['nit']} "
              f"refined={row['nit_refined']} t={wall:.2f}s", file=sys.stderr, flush=True)
    return rows


# ----------------------------------------------------------------------------- dymos
def _dymos_solve(name: str, n_points: int, maxiter: int = 500):
    import dymos as dm
    import openmdao.api as om

    segs = max(2, math.ceil(n_points / 3))
    p = om.Problem(reports=False)
    tx = dm.Radau(num_segments=segs, order=3)
    if name == "brachistochrone":
        from dymos.examples.brachistochrone.brachistochrone_ode import BrachistochroneODE

        phase = dm.Phase(ode_class=BrachistochroneODE, transcription=tx)
        phase.set_time_options(fix_initial=True, duration_bounds=(0.5, 10.0))
        phase.add_state("x", fix_initial=True, fix_final=True)
        phase.add_state("y", fix_initial=True, fix_final=True)
        phase.add_state("v", fix_initial=True, fix_final=False)
        phase.add_control("theta", units="deg", lower=0.01, upper=179.9, continuity=True, rate_continuity=True)
        phase.add_parameter("g", units="m/s**2", val=9.80665, opt=False)
        phase.add_objective("time", loc="final", scaler=10)
    else:

        class ODE(om.ExplicitComponent):
            def initialize(self):
                self.options.declare("num_nodes", types=int)

            def setup(self):
                nn = self.options["num_nodes"]
                ar = np.arange(nn)
                if name == "hypersensitive":
                    self.add_input("x", shape=nn)
                    self.add_input("u", shape=nn)
                    self.add_output("x_dot", shape=nn)
                    self.add_output("L", shape=nn)
                    self.declare_partials("x_dot", ["x", "u"], rows=ar, cols=ar)
                    self.declare_partials("L", ["x", "u"], rows=ar, cols=ar)
                else:
                    for s in ("x", "v", "u"):
                        self.add_input(s, shape=nn)
                    for s in ("x_dot", "v_dot", "L"):
                        self.add_output(s, shape=nn)
                    self.declare_partials("x_dot", "v", rows=ar, cols=ar, val=1.0)
                    self.declare_partials("v_dot", "u", rows=ar, cols=ar, val=1.0)
                    self.declare_partials("L", "u", rows=ar, cols=ar)

            def compute(self, i, o):
                if name == "hypersensitive":
                    o["x_dot"] = -i["x"] ** 3 + i["u"]
                    o["L"] = 0.5 * (i["x"] ** 2 + i["u"] ** 2)
                else:
                    o["x_dot"] = i["v"]
                    o["v_dot"] = i["u"]
                    o["L"] = 0.5 * i["u"] ** 2

            def compute_partials(self, i, J):
                if name == "hypersensitive":
                    J["x_dot", "x"] = -3 * i["x"] ** 2
                    J["x_dot", "u"] = 1.0
                    J["L", "x"] = i["x"]
                    J["L", "u"] = i["u"]
                else:
                    J["L", "u"] = i["u"]

        phase = dm.Phase(ode_class=ODE, transcription=tx)
        tf = 10.0 if name == "hypersensitive" else 1.0
        phase.set_time_options(fix_initial=True, fix_duration=True, duration_val=tf)
        if name == "hypersensitive":
            phase.add_state("x", rate_source="x_dot", fix_initial=True, fix_final=True)
        else:
            phase.add_state("x", rate_source="x_dot", fix_initial=True, fix_final=True, upper=1.0 / 9.0)
            phase.add_state("v", rate_source="v_dot", fix_initial=True, fix_final=True)
        phase.add_state("J", rate_source="L", fix_initial=True)
        phase.add_control("u", continuity=True, rate_continuity=False)
        phase.add_objective("J", loc="final")
    traj = dm.Trajectory()
    traj.add_phase("phase0", phase)
    p.model.add_subsystem("traj", traj)
    p.driver = om.ScipyOptimizeDriver(optimizer="SLSQP", maxiter=maxiter, tol=1e-9, disp=False)
    p.driver.declare_coloring(show_summary=False, show_sparsity=False)
    p.setup()
    if name == "brachistochrone":
        phase.set_time_val(initial=0.0, duration=2.0)
        phase.set_state_val("x", [0, 10])
        phase.set_state_val("y", [10, 5])
        phase.set_state_val("v", [0, 9.9])
        phase.set_control_val("theta", [5, 100.5])
    elif name == "hypersensitive":
        phase.set_time_val(initial=0.0, duration=10.0)
        phase.set_state_val("x", [1.0, 1.5])
        phase.set_state_val("J", [0.0, 1.0])
        phase.set_control_val("u", [0.0, 0.0])
    else:
        phase.set_time_val(initial=0.0, duration=1.0)
        phase.set_state_val("x", [0.0, 0.0])
        phase.set_state_val("v", [1.0, -1.0])
        phase.set_state_val("J", [0.0, 1.0])
        phase.set_control_val("u", [0.0, 0.0])
    failed = dm.run_problem(p, run_driver=True, simulate=False)
    if name == "brachistochrone":
        obj = float(p.get_val("traj.phase0.timeseries.time")[-1, 0])
    else:
        obj = float(p.get_val("traj.phase0.timeseries.J")[-1, 0])
    res = getattr(p.driver, "result", None)
    ok = bool(res.success) if res is not None else not failed
    return {"objective": obj, "success": ok, "nit": int(getattr(res, "nit", -1)) if res is not None else -1,
            "num_segments": segs, "order": 3, "n_collocation": 3 * segs}


def run_dymos(name, n_points):
    cwd = os.getcwd()
    t = time.perf_counter()
    with (
        tempfile.TemporaryDirectory() as tmp,
        warnings.catch_warnings(),
        contextlib.redirect_stdout(sys.stderr),
    ):
        os.chdir(tmp)
        try:
            warnings.simplefilter("ignore")
            out = _dymos_solve(name, n_points)
        except Exception as exc:  # noqa: BLE001 - report, do not abort the benchmark
            out = {"error": f"{type(exc).__name__}: {exc}", "success": False}
        finally:
            os.chdir(cwd)
    out["wall_s"] = time.perf_counter() - t
    return out


# ----------------------------------------------------------------------------- figures
def figures(results, sols, outdir):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(outdir, exist_ok=True)
    fig, axes = plt.subplots(1, len(results), figsize=(3.6 * len(results), 3.4), squeeze=False)
    for ax, r in zip(axes[0], results, strict=True):
        hp = r["hp"]["history"]
        ax.semilogy([h["n_collocation"] for h in hp], [h["max_error"] for h in hp], "o-", label="hp (solve_adaptive)")
        if r.get("uniform"):
            un = r["uniform"]["history"]
            ax.semilogy([h[0] for h in un], [h[1] for h in un], "s--", label="uniform, 4 points/interval")
        ax.axhline(r["tol"], color="k", lw=0.8, ls=":", label="tolerance")
        ax.set_title(r["problem"], fontsize=9)
        ax.set_xlabel("collocation points (-)")
        ax.set_ylabel("max relative state error (-)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    f1 = os.path.join(outdir, "oc_hp_vs_uniform.png")
    fig.savefig(f1, dpi=150)
    plt.close(fig)

    sol = sols.get("hypersensitive")
    paths = [f1]
    if sol is not None:
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(6.4, 4.8), sharex=True)
        tt = np.linspace(sol.t0, sol.tf, 2000)
        a1.plot(tt, sol.state_at(tt)[:, 0], "-", label="x (collocation polynomial)")
        a1.plot(sol.t_control, sol.u[:, 0], ".", ms=3, label="u at collocation points")
        a1.set_ylabel("x, u (-)")
        a1.legend(fontsize=8)
        mids = 0.5 * (sol.mesh.breaks[1:] + sol.mesh.breaks[:-1]) * (sol.tf - sol.t0) + sol.t0
        a2.semilogy(mids, sol.interval_errors, "o", ms=4, label="interval error")
        a2.axhline(sol.certificate.tol, color="k", ls=":", lw=0.8, label="tolerance")
        for b in sol.mesh.breaks * (sol.tf - sol.t0) + sol.t0:
            a1.axvline(b, color="0.85", lw=0.5, zorder=0)
        a2.set_xlabel("t (s)")
        a2.set_ylabel("relative error (-)")
        a2.legend(fontsize=8)
        a1.set_title("hypersensitive, tf = 10 s: final hp mesh (grey lines: mesh breaks)", fontsize=9)
        fig.tight_layout()
        f2 = os.path.join(outdir, "oc_hypersensitive_mesh.png")
        fig.savefig(f2, dpi=150)
        plt.close(fig)
        paths.append(f2)
    return paths


def _emit(out: dict, path: str | None) -> int:
    """Write the results as JSON to ``path``, or print them when no path is given."""
    text = json.dumps(out, indent=1, default=float)
    if path:
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(text)
    else:
        print(text)
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="tol 1e-4, no dymos")
    ap.add_argument("--tol", type=float, default=None)
    ap.add_argument("--no-dymos", action="store_true")
    ap.add_argument("--rigid-body", action="store_true")
    ap.add_argument("--only", metavar="NAME", action="append", help="run only these problems (repeatable)")
    ap.add_argument("--json", metavar="PATH")
    ap.add_argument("--figures", metavar="DIR")
    ap.add_argument("--ablation", action="store_true", help="duals x mesh reduction, side by side")
    ap.add_argument("--suite", action="store_true", help="issue-22 suite: both methods, Markdown table")
    args = ap.parse_args(argv)
    from adcskit.optimal_control.problems import reference_objective

    tol = args.tol if args.tol is not None else (1e-4 if args.quick else 1e-6)
    use_dymos = not (args.quick or args.no_dymos)
    with_rigid_body = args.rigid_body or bool(args.only and "rigid-body-reorientation" in args.only)
    results, sols = [], {}
    if args.suite:
        rows = run_suite(tol, args.only)
        print(suite_table(rows), file=sys.stderr, flush=True)
        return _emit({"tol": tol, "suite": rows}, args.json)
    if args.ablation:
        for name, prob, guess, mesh in problems(with_rigid_body):
            if not args.only or name in args.only:
                results += run_ablation(name, prob, guess, tol, mesh)
        return _emit({"tol": tol, "ablation": results}, args.json)
    for name, prob, guess, mesh in problems(with_rigid_body):
        if args.only and name not in args.only:
            continue
        ref, src = reference_objective(name)
        sol, wall = run_hp(prob, guess, tol, mesh)
        print(f"{name}: hp J={sol.objective:.10g} ok={sol.success} N={sol.certificate.n_collocation} "
              f"it={len(sol.mesh_history)} t={wall:.2f}s", file=sys.stderr, flush=True)
        sols[name] = sol
        r = {
            "problem": name,
            "tol": tol,
            "reference": ref,
            "reference_source": src,
            "hp": {
                "objective": sol.objective,
                "rel_error_vs_reference": abs(sol.objective - ref) / abs(ref),
                "success": sol.success,
                "max_error": sol.max_error,
                "n_collocation": sol.certificate.n_collocation,
                "mesh_iterations": len(sol.mesh_history),
                "ipopt_iterations": sum(m.nit for m in sol.mesh_history),
                "wall_s": wall,
                "history": [m.to_dict() for m in sol.mesh_history],
                "message": sol.message,
            },
        }
        if guess is None:
            r["uniform"] = run_uniform(prob, tol)
        if use_dymos and name in ("brachistochrone", "hypersensitive", "bryson-denham"):
            d = run_dymos(name, r["hp"]["n_collocation"])
            if "objective" in d:
                d["rel_error_vs_reference"] = abs(d["objective"] - ref) / abs(ref)
            d["ratio_dymos_over_hp"] = d["wall_s"] / wall
            r["dymos"] = d
        results.append(r)
        hp = r["hp"]
        line = (f"{name:26s} J={hp['objective']:.10g} ref={ref:.10g} rel={hp['rel_error_vs_reference']:.2e} "
                f"ok={hp['success']} N={hp['n_collocation']} it={hp['mesh_iterations']} t={wall:.2f}s")
        if "uniform" in r:
            line += f" | uniform N={r['uniform']['n_collocation']}"
        if "dymos" in r:
            d = r["dymos"]
            line += (f" | dymos J={d.get('objective', float('nan')):.8g} ok={d['success']} t={d['wall_s']:.1f}s "
                     f"ratio={d['ratio_dymos_over_hp']:.0f}x")
        print(line, file=sys.stderr, flush=True)
    out = {"tol": tol, "results": results}
    if args.figures:
        out["figures"] = figures(results, sols, args.figures)
    return _emit(out, args.json)


if __name__ == "__main__":
    raise SystemExit(main())
