"""Profile of the ``closed-loop`` study: CPU and wall time per finding, kernel share, thread split.

Runs ``adcskit run closed-loop`` in this process with light instrumentation (no change to any
number: the wrappers only time and count; model: ``profile_onoff_tuning.py``) and prints, per
phase (Q1 layouts, Q2 estimators, Q3 gains, Q4 slews, Q5 wheels vs thrusters, Q6 reference mode
sequence, claims + report, figures + files, the rest: start-up and config):

* wall and process CPU time;
* numba compilation (or loading from numba's disk cache) inside the phase: CPU and wall of the
  outermost ``Dispatcher.compile`` calls, split into real compiles (cache misses) and cache loads;
* the kernel calls made in it (``_run_block`` of :func:`adcskit.simulation.simulate`,
  ``_run_wheel_block`` of :func:`adcskit.simulation.simulate_wheels`): calls, samples,
  sample-steps per CPU-second, and the CPU of the calling thread vs the other threads of the
  process during those calls (numba's ``prange`` workers), all with compilation taken out;
* the Python work (phase CPU minus kernel and compile CPU), split further into the set-up of
  each simulation (``_prepare``: environment tables, dispersion draws, allocation table,
  feasibility), of which the environment tables (``_environment``) alone, and the thruster
  layout optimisation of Q1 (``_design_layout``, differential evolution);
* how many ``simulate``/``simulate_wheels`` calls repeat an earlier one exactly (same scenario,
  seed, samples, record flag: a re-simulation) and how many environment tables repeat one
  (same orbit, step, duration and sampling: a rebuilt table).

The calling thread's CPU is ``time.thread_time``, the other threads' the process CPU
(``time.process_time``, which keeps the CPU of threads that ended, such as the wheel driver's
thread pool) minus it; on a loaded machine wall time says little and CPU time is the figure to
read. Run it twice: the first run in a fresh checkout compiles the kernels
(cold numba cache), the second loads them (warm).

``--compare A B`` compares two closed-loop output directories (``result.json`` and every CSV)
and exits 1 if they differ anywhere but in run-time fields (run times, kernel rates, CPU
seconds; the summary's "Kernel median ... sample-steps/s").

Usage::

    PYTHONPATH=src python benchmarks/profile_closed_loop.py OUT [--quick | --config FILE.toml]
    python benchmarks/profile_closed_loop.py --compare A/closed-loop B/closed-loop
"""

from __future__ import annotations

import collections
import csv
import json
import os
import re
import sys
import time
from typing import Any

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _profiling import outermost_compiles  # noqa: E402

#: result.json keys that hold run times or machine facts (differ between any two runs)
_RUNTIME_KEYS = ("runtime_s", "adcskit_version", "created", "executor", "host", "python", "platform")
#: result.json / CSV keys whose value is a measured run time or rate
_RUNTIME_PATTERN = re.compile(r"(sample_steps_per_s|(^|_)cpu_s(_|$)|(^|_)wall_s(_|$))")
_SUMMARY_RATE = re.compile(r"Kernel median [-+0-9.e]+ sample-steps/s")
#: phases in study order (``measure`` calls the Q functions in this order)
_QUESTIONS = {"_q1_layouts": "Q1 layouts", "_q2_estimators": "Q2 estimators", "_q3_gains": "Q3 gains",
              "_q4_slews": "Q4 slews", "_q5_wheels": "Q5 wheels", "_q6_modes": "Q6 modes"}


def _seq_key(rng: Any) -> Any:
    import numpy as np

    if isinstance(rng, np.random.SeedSequence):
        return (rng.entropy, tuple(rng.spawn_key), rng.n_children_spawned)
    return repr(rng)


def profile(argv: list[str]) -> dict[str, Any]:
    """Run the study with ``argv`` (``adcskit run closed-loop`` arguments) and return the profile."""
    import numba.core.dispatcher as nd

    from adcskit import cli
    from adcskit.simulation import _kernels as _k
    from adcskit.simulation import _wheel_kernels as _wk
    from adcskit.simulation import core, wheels
    from adcskit.studies import _runner
    from adcskit.studies.closed_loop import claims, figures, report
    from adcskit.studies.closed_loop import experiment as ex

    zero = {"calls": 0, "wall_s": 0.0, "cpu_s": 0.0}
    phases: dict[str, dict[str, float]] = collections.defaultdict(lambda: dict(zero))
    parts: dict[str, dict[str, dict[str, float]]] = collections.defaultdict(
        lambda: collections.defaultdict(lambda: dict(zero)))
    kern: dict[str, dict[str, float]] = collections.defaultdict(
        lambda: {"calls": 0, "samples": 0, "sample_steps": 0.0, "wall_s": 0.0, "cpu_s": 0.0,
                 "cpu_calling_thread_s": 0.0, "cpu_other_threads_s": 0.0, "compile_cpu_s": 0.0})
    comp: dict[str, dict[str, float]] = collections.defaultdict(
        lambda: {"compiles": 0, "loads": 0, "compile_cpu_s": 0.0, "compile_wall_s": 0.0, "load_cpu_s": 0.0,
                 "load_wall_s": 0.0, "compiled": [], "loaded": []})
    sims: dict[str, dict[str, Any]] = collections.defaultdict(lambda: {"simulate": 0, "simulate_wheels": 0,
                                                                       "repeats": 0, "samples": 0})
    seen_sims: set = set()
    envs = {"tables": 0, "distinct": set()}
    stack = ["rest"]
    compile_total = [0.0, 0.0]  # running compile CPU (process, calling thread): taken out of kernel and parts

    # ------------------------------------------------------------------ numba compilation
    compile_fn = nd.Dispatcher.compile

    def record(name, compiled, dc, dw, dh):
        compile_total[0] += dc
        compile_total[1] += dh
        d = comp[stack[-1]]
        if compiled:
            d["compiled"].append(f"{name} {dc:.1f} s")
            d["compiles"] += 1
            d["compile_cpu_s"] += dc
            d["compile_wall_s"] += dw
        else:
            d["loaded"].append(name)
            d["loads"] += 1
            d["load_cpu_s"] += dc
            d["load_wall_s"] += dw

    nd.Dispatcher.compile = outermost_compiles(compile_fn, record)

    # ------------------------------------------------------------------ kernel calls
    def kernel(fn, n_steps_of):
        def wrapped(task, *a):
            t0, c0, (k0, h0), m0 = time.perf_counter(), time.process_time(), compile_total, time.thread_time()
            res = fn(task, *a)
            dm, dc = time.thread_time() - m0, time.process_time() - c0
            # thruster task: (shared, per_sample, seeds, record); wheel task: (P, AX, seeds, record)
            n = task[1]["P"].shape[0] if isinstance(task[0], dict) else task[0].shape[0]
            d = kern[stack[-1]]
            d["calls"] += 1
            d["samples"] += n
            d["sample_steps"] += float(n) * n_steps_of(task, *a)
            d["wall_s"] += time.perf_counter() - t0
            dk, dh = compile_total[0] - k0, compile_total[1] - h0
            d["compile_cpu_s"] += dk
            d["cpu_s"] += dc - dk
            # the process's CPU includes threads that ended during the call (the wheel driver's
            # thread pool); compilation runs on the calling thread (dh), other threads meanwhile dk - dh
            d["cpu_calling_thread_s"] += dm - dh
            d["cpu_other_threads_s"] += (dc - dm) - (dk - dh)
            return res
        return wrapped

    core._run_block = kernel(core._run_block, lambda task: task.shared["n_steps"])
    wheels._run_wheel_block = kernel(wheels._run_wheel_block, lambda task, shared: shared["n_steps"])

    # ------------------------------------------------------------------ Python parts
    def part(name, fn):
        def wrapped(*a, **k):
            t0, c0, k0 = time.perf_counter(), time.process_time(), compile_total[0]
            try:
                return fn(*a, **k)
            finally:
                d = parts[stack[-1]][name]
                d["calls"] += 1
                d["wall_s"] += time.perf_counter() - t0
                d["cpu_s"] += time.process_time() - c0 - (compile_total[0] - k0)
        return wrapped

    def env_key(fn):
        def wrapped(sc, n_steps, *a):
            envs["tables"] += 1
            envs["distinct"].add(repr((sc.orbit, sc.sim.dt, n_steps, *a)))
            return fn(sc, n_steps, *a)
        return wrapped

    core._prepare = part("set-up (thruster loop)", core._prepare)
    core._environment = part("environment tables", env_key(core._environment))
    wheels._prepare = part("set-up (wheel loop)", wheels._prepare)
    wheels._environment = part("environment tables", env_key(wheels._environment))
    ex._design_layout = part("layout DE", ex._design_layout)

    def counted(name, fn):
        def wrapped(sc, n_samples=1, rng=None, *a, **k):
            key = (name, repr(sc), n_samples, _seq_key(rng), bool(k.get("record", False)))
            d = sims[stack[-1]]
            d[name] += 1
            d["samples"] += n_samples
            if key in seen_sims:
                d["repeats"] += 1
            seen_sims.add(key)
            return fn(sc, n_samples, rng, *a, **k)
        return wrapped

    ex.simulate = counted("simulate", ex.simulate)
    ex.simulate_wheels = counted("simulate_wheels", ex.simulate_wheels)

    # ------------------------------------------------------------------ phases
    def phase(name, fn):
        def wrapped(*a, **k):
            stack.append(name)
            t0, c0 = time.perf_counter(), time.process_time()
            try:
                return fn(*a, **k)
            finally:
                phases[name]["calls"] += 1
                phases[name]["wall_s"] += time.perf_counter() - t0
                phases[name]["cpu_s"] += time.process_time() - c0
                stack.pop()
        return wrapped

    for fn_name, label in _QUESTIONS.items():
        setattr(ex, fn_name, phase(label, getattr(ex, fn_name)))
    claims.evaluate = phase("claims + report", claims.evaluate)
    for fn_name in ("summary", "measured", "tables"):
        setattr(report, fn_name, phase("claims + report", getattr(report, fn_name)))
    figures.figures = phase("figures + files", figures.figures)
    for fn_name in [n for n in vars(figures) if n.startswith("_fig_")]:
        setattr(figures, fn_name, part(f"draw {fn_name[5:]}", getattr(figures, fn_name)))
    from matplotlib.figure import Figure

    savefig = Figure.savefig
    Figure.savefig = part("savefig (PNG)", savefig)
    _runner.write_result = phase("figures + files", _runner.write_result)

    t0, c0 = time.perf_counter(), time.process_time()
    rc = cli.main(["run", "closed-loop", *argv])
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    rest = {"calls": 1, "wall_s": wall - sum(p["wall_s"] for p in phases.values()),
            "cpu_s": cpu - sum(p["cpu_s"] for p in phases.values())}
    nd.Dispatcher.compile = compile_fn
    Figure.savefig = savefig
    return {
        "command": "adcskit run closed-loop " + " ".join(argv), "exit": rc,
        "total": {"wall_s": wall, "cpu_s": cpu}, "phases": {**phases, "rest": rest}, "kernel": dict(kern),
        "compile": dict(comp), "parts": {k: dict(v) for k, v in parts.items()}, "simulations": dict(sims),
        "environment_tables": {"built": envs["tables"], "distinct": len(envs["distinct"])},
        "signatures": {"_kernels.run_parallel": len(_k.run_parallel.signatures),
                       "_wheel_kernels.run_block": len(_wk.run_block.signatures)},
        "load_average": os.getloadavg(), "cpus": os.cpu_count(),
        "numba_threads": __import__("numba").get_num_threads(),
    }


def _print(rep: dict[str, Any]) -> None:
    tot = rep["total"]
    la = rep["load_average"]
    print(f"{rep['command']}: {tot['wall_s']:.1f} s wall, {tot['cpu_s']:.1f} s CPU "
          f"(load average {la[0]:.1f} / {la[1]:.1f} / {la[2]:.1f} at the end, {rep['cpus']} CPUs, "
          f"{rep['numba_threads']} numba threads)")
    print(f"{'phase':<16} {'wall s':>7} {'CPU s':>7} {'CPU %':>6} {'compile':>8} {'kernel':>7} {'Python':>7} "
          f"{'calls':>5} {'samples':>8} {'steps/CPU-s':>11} {'thread split':>12} {'sims (repeats)':>14}")
    for name, p in rep["phases"].items():
        k = rep["kernel"].get(name, {})
        c = rep["compile"].get(name, {})
        cc = c.get("compile_cpu_s", 0.0) + c.get("load_cpu_s", 0.0)
        kc = k.get("cpu_s", 0.0)
        split = f"{k['cpu_calling_thread_s']:.1f}/{k['cpu_other_threads_s']:.1f}" if k else "-"
        rate = f"{k['sample_steps'] / kc:.3g}" if kc > 0 else "-"
        s = rep["simulations"].get(name)
        sims = f"{s['simulate'] + s['simulate_wheels']} ({s['repeats']})" if s else "-"
        print(f"{name:<16} {p['wall_s']:7.1f} {p['cpu_s']:7.1f} {100 * p['cpu_s'] / tot['cpu_s']:6.1f} {cc:8.1f} "
              f"{kc:7.1f} {p['cpu_s'] - kc - cc:7.1f} {k.get('calls', 0):5d} {k.get('samples', 0):8d} {rate:>11} "
              f"{split:>12} {sims:>14}")
    print("compilation (outermost Dispatcher.compile; CPU s / wall s):")
    for name, c in rep["compile"].items():
        print(f"  {name:<16} {c['compiles']} compiled: {c['compile_cpu_s']:.1f} / {c['compile_wall_s']:.1f}; "
              f"{c['loads']} loaded from the cache: {c['load_cpu_s']:.2f} / {c['load_wall_s']:.2f}")
        if c["compiled"]:
            print(f"    compiled: {', '.join(c['compiled'])}")
    print("Python parts (CPU s, calls):")
    for name, ps in rep["parts"].items():
        print(f"  {name:<16} " + "; ".join(f"{k} {v['cpu_s']:.2f} ({v['calls']})" for k, v in ps.items()))
    e = rep["environment_tables"]
    print(f"environment tables: {e['built']} built, {e['distinct']} distinct; kernel signatures {rep['signatures']} "
          "(more than one: compiled again for other argument types)")


def _strip(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {k: _strip(v) for k, v in obj.items()
                if k not in _RUNTIME_KEYS and not _RUNTIME_PATTERN.search(str(k))}
    if isinstance(obj, list):
        return [_strip(v) for v in obj]
    if isinstance(obj, str):
        return _SUMMARY_RATE.sub("Kernel median (rate) sample-steps/s", obj)
    return obj


def _csv_rows(path: str) -> list[dict[str, str]]:
    with open(path, newline="") as fh:
        return [{k: v for k, v in row.items() if not _RUNTIME_PATTERN.search(k)} for row in csv.DictReader(fh)]


def compare(a: str, b: str) -> list[str]:
    """What differs between two closed-loop output directories outside the run-time fields:
    top-level keys of ``result.json`` and names of CSV files (missing on one side included)."""
    with open(os.path.join(a, "result.json")) as fa, open(os.path.join(b, "result.json")) as fb:
        ra, rb = _strip(json.load(fa)), _strip(json.load(fb))
    diff = [f"result.json:{k}" for k in sorted(set(ra) | set(rb)) if ra.get(k) != rb.get(k)]
    csvs = sorted({f for d in (a, b) for f in os.listdir(d) if f.endswith(".csv")})
    for f in csvs:
        pa, pb = os.path.join(a, f), os.path.join(b, f)
        if not (os.path.exists(pa) and os.path.exists(pb)) or _csv_rows(pa) != _csv_rows(pb):
            diff.append(f)
    if not csvs:
        diff.append("(no CSV files)")
    return diff


def main() -> int:
    if len(sys.argv) == 4 and sys.argv[1] == "--compare":
        diff = compare(sys.argv[2], sys.argv[3])
        print("identical outside run-time fields (result.json and every CSV)" if not diff
              else f"differ in: {', '.join(diff)}")
        return 1 if diff else 0
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    out = sys.argv[1]
    rep = profile(["--out", out, *sys.argv[2:]])
    _print(rep)
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "profile.json"), "w") as fh:
        json.dump(rep, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
