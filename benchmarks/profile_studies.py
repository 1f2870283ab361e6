"""Profile of the ``wahba-table1``, ``wahba-orbit`` and ``model-estimation`` studies: CPU per phase.

Runs ``adcskit run STUDY`` in this process with light instrumentation (model:
``profile_closed_loop.py``; the wrappers only time and count, no number changes) and prints, per
phase of the study (its experiment's task functions, then claims + report, figure drawing, files,
and the rest: start-up, config, runner):

* wall and process CPU time, share of the run's CPU and number of calls;
* the library calls inside the phase that the study's CPU goes to (``parts``): per solver and
  method (``robust_wahba`` by method / solver / NSGA-II budget, ``solve_wahba``, pymoo's
  ``Problem.evaluate`` (the objective) inside NSGA-II, the numba kernels ``solve_single`` /
  ``solve_batch_*`` / ``box_sphere_max``), the environment models (sun, magnetic field: IGRF via
  ppigrf or the dipole), the sensors, the attitude propagation, the estimators
  (``joint_estimate`` by method, ``augmented_ekf``, ``identify_model``), ``simulate_linear``,
  and ``savefig``. A part's CPU includes the parts it calls (pymoo's objective is inside the
  ``robust_wahba nsga2`` row);
* numba compilation or disk-cache loads inside the phase (outermost ``Dispatcher.compile``);
* exact repeats: how many magnetic-field / sun tables, truth simulations, ``simulate_linear``
  data sets and ``joint_estimate`` solves repeat an earlier call with the same inputs (same
  arrays, same random state): the "same computation done again" that a cache would save.

``--cprofile`` adds, per phase, a cProfile of the phase grouped by where the time is spent
(``tottime`` by package: pymoo, scipy, numpy, matplotlib, ppigrf, sgp4, adcskit's own Python,
other Python, C built-ins) and its top functions by own time. cProfile slows Python-heavy code
(pymoo, SLSQP callbacks) by up to ~2x: read its shares, and the CPU seconds of a run without it.
It changes the measured solve times, so never ``--compare`` a ``--cprofile`` run's timing claims.

The calling thread's CPU is ``time.thread_time``, the process's ``time.process_time`` (numba's
``prange`` workers, BLAS threads). On a shared machine wall time says little; read CPU seconds.

``--compare A B`` compares two output directories of one study (``result.json``, every CSV and
the list of figure files) and exits 1 if they differ anywhere but in run-time fields: run times
(``runtime_s``), speed ratios, the timing claims' values (claims with ``timing: true``: their
values and intervals, and their outcome, which a loaded machine can move: listed, not failed) and
the summary's timing sentence.

Usage::

    PYTHONPATH=src python benchmarks/profile_studies.py STUDY OUT [--cprofile] [--quick | --config FILE.toml]
    python benchmarks/profile_studies.py --compare A/STUDY B/STUDY
"""

from __future__ import annotations

import collections
import cProfile
import csv
import hashlib
import json
import os
import pstats
import re
import sys
import time
from typing import Any

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _profiling import outermost_compiles  # noqa: E402

STUDIES = ("wahba-table1", "wahba-orbit", "model-estimation")
#: result.json keys that hold run times or machine facts (differ between any two runs)
_RUNTIME_KEYS = ("runtime_s", "adcskit_version", "created", "executor", "host", "python", "platform")
#: result.json / CSV keys whose value is a measured run time or a ratio of run times
_RUNTIME_PATTERN = re.compile(r"(runtime_s|^speed_ratio|(^|_)cpu_s(_|$)|(^|_)wall_s(_|$))")
#: wahba-table1's summary: the speed claim's outcome and its measured ratios
_SUMMARY_TIMING = re.compile(r": [a-z ]+ \(ratios [-0-9.e+, ]+;")
#: fields of a timing claim (and of its readings) that are measured run times or follow from them
_TIMING_FIELDS = ("measured", "interval", "values", "detail", "fraction_held", "outcome", "display_outcome")


def _digest(*arrays: Any) -> str:
    """A short digest of arrays and scalars (exact bytes: equal digests are equal inputs)."""
    import numpy as np

    h = hashlib.blake2b(digest_size=12)
    for a in arrays:
        if isinstance(a, np.ndarray):
            h.update(str((a.dtype, a.shape)).encode())
            h.update(np.ascontiguousarray(a).tobytes())
        elif isinstance(a, np.random.Generator):
            h.update(repr(a.bit_generator.state).encode())
        else:
            h.update(repr(a).encode())
    return h.hexdigest()


class _Profiler:
    """Phases (outermost wins), parts inside them, compiles and repeat counters."""

    def __init__(self, use_cprofile: bool) -> None:
        zero = {"calls": 0, "wall_s": 0.0, "cpu_s": 0.0}
        self.phases: dict[str, dict[str, float]] = collections.defaultdict(lambda: dict(zero))
        self.parts: dict[str, dict[str, dict[str, float]]] = collections.defaultdict(
            lambda: collections.defaultdict(lambda: dict(zero)))
        self.comp: dict[str, dict[str, Any]] = collections.defaultdict(
            lambda: {"compiles": 0, "loads": 0, "compile_cpu_s": 0.0, "load_cpu_s": 0.0, "compiled": []})
        self.repeats: dict[str, dict[str, Any]] = collections.defaultdict(lambda: {"calls": 0, "repeats": 0})
        self._seen: dict[str, set] = collections.defaultdict(set)
        self.stack = ["rest"]
        self.active_parts: set[str] = set()
        self.use_cprofile = use_cprofile
        self.cprofiles: dict[str, cProfile.Profile] = {}
        if use_cprofile:
            self.cprofiles["rest"] = cProfile.Profile()

    # -------------------------------------------------------------- wrappers
    def phase(self, name: Any, fn):
        """Wrap ``fn`` as a phase; ``name`` is a label or a function of the call's arguments."""
        def wrapped(*a, **k):
            if len(self.stack) > 1:  # already inside a phase: the outermost one counts
                return fn(*a, **k)
            label = name(*a, **k) if callable(name) else name
            prev = self.stack[-1]
            self.stack.append(label)
            if self.use_cprofile:
                self.cprofiles[prev].disable()
                prof = self.cprofiles.setdefault(label, cProfile.Profile())
                prof.enable()
            t0, c0 = time.perf_counter(), time.process_time()
            try:
                return fn(*a, **k)
            finally:
                d = self.phases[label]
                d["calls"] += 1
                d["wall_s"] += time.perf_counter() - t0
                d["cpu_s"] += time.process_time() - c0
                if self.use_cprofile:
                    prof.disable()
                    self.cprofiles[prev].enable()
                self.stack.pop()
        return wrapped

    def part(self, name: Any, fn, key=None):
        """Wrap ``fn`` as a part of the current phase (a part inside itself counts once).

        ``key(*a, **k)``, when given, names the call's inputs: a call whose key was seen before is
        counted as an exact repeat under the part's label.
        """
        def wrapped(*a, **k):
            label = name(*a, **k) if callable(name) else name
            if key is not None:
                kk = key(*a, **k)
                r = self.repeats[label]
                r["calls"] += 1
                if kk in self._seen[label]:
                    r["repeats"] += 1
                self._seen[label].add(kk)
            if label in self.active_parts:
                return fn(*a, **k)
            self.active_parts.add(label)
            t0, c0 = time.perf_counter(), time.process_time()
            try:
                return fn(*a, **k)
            finally:
                self.active_parts.discard(label)
                d = self.parts[self.stack[-1]][label]
                d["calls"] += 1
                d["wall_s"] += time.perf_counter() - t0
                d["cpu_s"] += time.process_time() - c0
        return wrapped

    def install_compile_timer(self):
        import numba.core.dispatcher as nd

        def record(name: str, compiled: bool, cpu_s: float, wall_s: float, thread_s: float) -> None:
            d = self.comp[self.stack[-1]]
            if compiled:
                d["compiles"] += 1
                d["compile_cpu_s"] += cpu_s
                d["compiled"].append(f"{name.rsplit('.', 1)[-1]} {cpu_s:.1f} s")
            else:
                d["loads"] += 1
                d["load_cpu_s"] += cpu_s

        compile_fn = nd.Dispatcher.compile
        nd.Dispatcher.compile = outermost_compiles(compile_fn, record)
        return lambda: setattr(nd.Dispatcher, "compile", compile_fn)


class _KernelProxy:
    """Stands for ``adcskit.determination._kernels`` inside ``wahba.py`` only, with its solve
    entry points timed (the jitted functions themselves are not touched)."""

    def __init__(self, mod, prof: _Profiler) -> None:
        self._mod = mod
        for n in ("solve_single", "solve_batch_serial", "solve_batch_parallel"):
            setattr(self, n, prof.part(f"numba {n}", getattr(mod, n)))

    def __getattr__(self, n):
        return getattr(self._mod, n)


# ------------------------------------------------------------------ the studies' instrumentation


def _common(prof: _Profiler, pkg, claims, report, figures) -> list:
    """Claims + report, figure drawing, files; the determination library's solvers and kernels."""
    from matplotlib.figure import Figure
    from pymoo.core.problem import Problem

    from adcskit.determination import robust, wahba
    from adcskit.studies import _runner

    undo = []
    for mod in (claims, report):
        for n, f in list(vars(mod).items()):
            if callable(f) and getattr(f, "__module__", None) == mod.__name__ and not isinstance(f, type):
                setattr(mod, n, prof.phase("claims + report", f))
    if hasattr(pkg, "decide_declared"):
        pkg.decide_declared = prof.phase("claims + report", pkg.decide_declared)
    figures.figures = prof.phase("figures (draw)", figures.figures)
    _runner.write_result = prof.phase("files (PNG, CSV, JSON)", _runner.write_result)
    savefig = Figure.savefig
    Figure.savefig = prof.part("savefig", savefig)
    undo.append(lambda: setattr(Figure, "savefig", savefig))
    evaluate = Problem.evaluate
    Problem.evaluate = prof.part("  of it pymoo Problem.evaluate (our objective)", evaluate)
    undo.append(lambda: setattr(Problem, "evaluate", evaluate))
    wahba._k = _KernelProxy(wahba._k, prof)
    robust.box_sphere_max = prof.part("numba box_sphere_max", robust.box_sphere_max)
    return undo


def _robust_label(b, br, r, rr, w=None, *, method="minmax", solver="closed-form", n_gen=None, q0=None, **k):
    if method == "minmax":
        return f"robust_wahba minmax/{solver}" + (" (box at q0)" if q0 is not None else "")
    if method == "nsga2":
        return f"robust_wahba nsga2 pop {k.get('pop_size')} x {n_gen} gen"
    return f"robust_wahba {method}"


def _wahba_table1(prof: _Profiler) -> list:
    from adcskit.studies import wahba_table1 as pkg
    from adcskit.studies.wahba_table1 import claims, figures, report
    from adcskit.studies.wahba_table1 import experiment as ex

    undo = _common(prof, pkg, claims, report, figures)

    def trial_label(task):
        rows = task[3]
        if "minmax-slsqp" in rows:
            return "Table 1 trials, iterative rows" + (" + big NSGA-II" if "nsga2-big-knee" in rows else "")
        return "Table 1 trials, cheap rows" if "q-method" in rows and "quest" in rows else "noise sweep trials"

    ex.trial = prof.phase(trial_label, ex.trial)
    ex._replica = prof.phase("reduction (replicas, pooled stats)", ex._replica)
    ex._stats = prof.phase("reduction (replicas, pooled stats)", ex._stats)
    ex._exact_vectors = prof.phase("reduction (replicas, pooled stats)", ex._exact_vectors)
    ex.robust_wahba = prof.part(_robust_label, ex.robust_wahba)
    ex.solve_wahba = prof.part(lambda b, r, *a, method="q-method", **k: f"solve_wahba {method}", ex.solve_wahba)
    ex.qmethod_in_box = prof.part("qmethod_in_box (TRIAD + q-method)", ex.qmethod_in_box)
    ex.perturb = prof.part("perturb (noise draw)", ex.perturb)
    return undo


def _wahba_orbit(prof: _Profiler) -> list:
    from adcskit.studies import wahba_orbit as pkg
    from adcskit.studies.wahba_orbit import claims, figures, report
    from adcskit.studies.wahba_orbit import experiment as ex

    undo = _common(prof, pkg, claims, report, figures)
    ex.simulate_truth = prof.phase("truth (orbit + attitude propagation)", ex.simulate_truth)
    ex._case_task = prof.phase(lambda task: f"pass {task[1]} ({task[2]})", ex._case_task)
    ex.propagate_attitude = prof.part("propagate_attitude (RK45, gravity gradient)", ex.propagate_attitude)
    ex.circular_orbit = prof.part("circular_orbit", ex.circular_orbit)
    ex.sun_direction = prof.part("sun_direction", ex.sun_direction, key=lambda t, *a, **k: _digest(t, a, k))
    ex.magnetic_field = prof.part(lambda r, t, model="dipole", **k: f"magnetic_field {model}", ex.magnetic_field,
                                  key=lambda r, t, model="dipole", **k: _digest(r, t, model, k))
    for cls in (ex.SunSensor, ex.Magnetometer):
        for n in ("measure", "interval"):
            f = getattr(cls, n)
            setattr(cls, n, prof.part(f"{cls.__name__}.{n}", f))
            undo.append(lambda cls=cls, n=n, f=f: setattr(cls, n, f))
    ex.quat_to_dcm = prof.part("quat_to_dcm", ex.quat_to_dcm)
    ex.robust_wahba = prof.part(_robust_label, ex.robust_wahba)
    ex.solve_wahba = prof.part(lambda b, r, *a, method="q-method", **k: f"solve_wahba {method}", ex.solve_wahba)
    ex.angle_deg = prof.part("angle_deg", ex.angle_deg)
    return undo


def _model_estimation(prof: _Profiler) -> list:
    from adcskit.studies import model_estimation as pkg
    from adcskit.studies.model_estimation import claims, figures, report
    from adcskit.studies.model_estimation import experiment as ex

    undo = _common(prof, pkg, claims, report, figures)
    ex._run_task = prof.phase(lambda task: f"runs: {task['reading']}", ex._run_task)
    ex.build_case = prof.part("build_case", ex.build_case, key=lambda name, cfg: (name, repr(cfg)))
    ex.simulate_linear = prof.part("simulate_linear", ex.simulate_linear,
                                   key=lambda A, B, C, u, R=None, rng=None, **k: _digest(A, B, C, u, R, rng, k))

    def joint_label(y, u, *, method="qr", options=None, **k):
        cap = f", maxiter {options['maxiter']}" if options and "maxiter" in options else ""
        return f"joint_estimate {method}{cap}"

    def joint_key(y, u, **k):
        return _digest(y, u, *(k[n] for n in sorted(k) if n != "rng"), k.get("rng"))

    ex.joint_estimate = prof.part(joint_label, ex.joint_estimate, key=joint_key)
    ex.augmented_ekf = prof.part("augmented_ekf", ex.augmented_ekf)
    ex.identify_model = prof.part(lambda X, Z, U, *, method="qr", **k: f"identify_model {method} (converged)",
                                  ex.identify_model)
    ex._err = prof.part("model error norms (_err)", ex._err)
    return undo


_INSTALL = {"wahba-table1": _wahba_table1, "wahba-orbit": _wahba_orbit, "model-estimation": _model_estimation}

# ------------------------------------------------------------------ cProfile grouping

_GROUPS = (("pymoo", "pymoo"), ("scipy", "scipy"), ("numpy", "numpy"), ("matplotlib", "matplotlib"),
           ("ppigrf", "ppigrf"), ("sgp4", "sgp4"), ("numba", "numba"), ("pandas", "pandas"),
           ("adcskit", "adcskit (Python; numba kernels it calls count here)"))


def _group(func: tuple) -> str:
    filename, _, name = func
    text = filename if filename != "~" else name
    for needle, label in _GROUPS:
        if f"/{needle}/" in text or f"{needle}." in text or f"'{needle}" in text:
            return label
    if filename == "~":
        return "C built-ins (other)"
    return "Python (stdlib, other)"


def _cprofile_summary(prof: cProfile.Profile, top: int = 6) -> dict[str, Any]:
    st = pstats.Stats(prof)
    groups: dict[str, float] = collections.defaultdict(float)
    funcs = []
    for func, (_cc, nc, tt, _ct, _callers) in st.stats.items():
        groups[_group(func)] += tt
        funcs.append((tt, nc, f"{os.path.basename(func[0])}:{func[1]}({func[2]})"))
    funcs.sort(reverse=True)
    return {"total_s": st.total_tt, "groups": dict(sorted(groups.items(), key=lambda x: -x[1])),
            "top": [{"tottime_s": t, "calls": n, "function": f} for t, n, f in funcs[:top]]}


# ------------------------------------------------------------------ run and print


def profile(study: str, argv: list[str], use_cprofile: bool = False) -> dict[str, Any]:
    """Run ``adcskit run STUDY argv`` in this process and return the profile."""
    from adcskit import cli

    prof = _Profiler(use_cprofile)
    undo = [prof.install_compile_timer(), *_INSTALL[study](prof)]
    if use_cprofile:
        prof.cprofiles["rest"].enable()
    t0, c0 = time.perf_counter(), time.process_time()
    rc = cli.main(["run", study, *argv])
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    if use_cprofile:
        prof.cprofiles["rest"].disable()
    for u in undo:
        u()
    rest = {"calls": 1, "wall_s": wall - sum(p["wall_s"] for p in prof.phases.values()),
            "cpu_s": cpu - sum(p["cpu_s"] for p in prof.phases.values())}
    return {
        "command": f"adcskit run {study} " + " ".join(argv), "exit": rc,
        "total": {"wall_s": wall, "cpu_s": cpu}, "phases": {**prof.phases, "rest": rest},
        "parts": {k: dict(v) for k, v in prof.parts.items()}, "compile": dict(prof.comp),
        "repeats": dict(prof.repeats),
        "cprofile": {k: _cprofile_summary(p) for k, p in prof.cprofiles.items()} if use_cprofile else None,
        "load_average": os.getloadavg(), "cpus": os.cpu_count(),
        "numba_threads": __import__("numba").get_num_threads(),
        "date_utc": time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime()),
    }


def _print(rep: dict[str, Any]) -> None:
    tot = rep["total"]
    la = rep["load_average"]
    print(f"{rep['command']}: {tot['wall_s']:.1f} s wall, {tot['cpu_s']:.1f} s CPU (load average "
          f"{la[0]:.1f} / {la[1]:.1f} / {la[2]:.1f} at the end, {rep['cpus']} CPUs, {rep['numba_threads']} numba "
          f"threads; {rep['date_utc']} UTC)")
    print(f"{'phase':<44} {'calls':>6} {'wall s':>8} {'CPU s':>8} {'CPU %':>6} {'compile/load':>12}")
    for name, p in rep["phases"].items():
        c = rep["compile"].get(name, {})
        cc = c.get("compile_cpu_s", 0.0) + c.get("load_cpu_s", 0.0)
        print(f"{name:<44} {p['calls']:6d} {p['wall_s']:8.2f} {p['cpu_s']:8.2f} "
              f"{100 * p['cpu_s'] / tot['cpu_s']:6.1f} {cc:12.2f}")
        for pn, ps in sorted(rep["parts"].get(name, {}).items(), key=lambda x: -x[1]["cpu_s"]):
            print(f"    {pn:<62} {ps['calls']:7d} calls {ps['cpu_s']:8.2f} CPU s "
                  f"({100 * ps['cpu_s'] / max(p['cpu_s'], 1e-12):5.1f} % of the phase)")
        if c.get("compiled"):
            print(f"    compiled: {', '.join(c['compiled'])}")
        cp = (rep.get("cprofile") or {}).get(name)
        if cp:
            g = ", ".join(f"{k} {v:.2f}" for k, v in list(cp["groups"].items())[:6])
            print(f"    cProfile own time by package (s, of {cp['total_s']:.2f}): {g}")
            for f in cp["top"]:
                print(f"      {f['tottime_s']:7.2f} s {f['calls']:8d}x {f['function']}")
    print("exact repeats (same inputs as an earlier call):")
    for name, r in rep["repeats"].items():
        print(f"  {name:<40} {r['calls']} calls, {r['repeats']} repeats")


# ------------------------------------------------------------------ compare


def _strip(obj: Any) -> Any:
    if isinstance(obj, dict):
        if obj.get("timing") is True:  # a timing claim: its numbers are run times
            obj = {k: v for k, v in obj.items() if k not in _TIMING_FIELDS and k != "readings"} | {
                "readings": [r.get("reading") for r in obj.get("readings", [])]}
        if str(obj.get("quantity", "")).endswith("runtime_s"):
            obj = {k: v for k, v in obj.items() if k != "measured"}
        return {k: _strip(v) for k, v in obj.items()
                if k not in _RUNTIME_KEYS and not _RUNTIME_PATTERN.search(str(k))}
    if isinstance(obj, list):
        return [_strip(v) for v in obj]
    if isinstance(obj, str):
        return _SUMMARY_TIMING.sub(": (timing outcome) (ratios …;", obj)
    return obj


def _timing_outcomes(res: dict[str, Any]) -> dict[str, Any]:
    return {c["id"]: (c.get("outcome"), [r.get("outcome") for r in c.get("readings", [])])
            for c in res.get("claims", []) + res.get("findings", []) if c.get("timing") is True}


def _csv_rows(path: str) -> list[dict[str, str]]:
    with open(path, newline="") as fh:
        return [{k: v for k, v in row.items() if not _RUNTIME_PATTERN.search(k)} for row in csv.DictReader(fh)]


def compare(a: str, b: str) -> tuple[list[str], list[str]]:
    """``(differences, notes)`` between two output directories of one study: differences outside the
    run-time fields (``result.json`` top-level keys, CSV files, figure files), and notes on timing
    claims whose outcome differs (a run-time field)."""
    with open(os.path.join(a, "result.json")) as fa, open(os.path.join(b, "result.json")) as fb:
        ja, jb = json.load(fa), json.load(fb)
    ra, rb = _strip(ja), _strip(jb)
    diff = [f"result.json:{k}" for k in sorted(set(ra) | set(rb)) if ra.get(k) != rb.get(k)]
    ta, tb = _timing_outcomes(ja), _timing_outcomes(jb)
    notes = [f"timing claim {k}: {ta.get(k)} vs {tb.get(k)}" for k in sorted(set(ta) | set(tb)) if ta.get(k) != tb.get(k)]
    files = {d: sorted(f for f in os.listdir(d) if f.endswith((".csv", ".png"))) for d in (a, b)}
    if files[a] != files[b]:
        diff.append(f"file names: {files[a]} vs {files[b]}")
    csvs = sorted({f for d in (a, b) for f in files[d] if f.endswith(".csv")})
    for f in csvs:
        pa, pb = os.path.join(a, f), os.path.join(b, f)
        if not (os.path.exists(pa) and os.path.exists(pb)) or _csv_rows(pa) != _csv_rows(pb):
            diff.append(f)
    if not csvs:
        diff.append("(no CSV files)")
    return diff, notes


def main() -> int:
    args = sys.argv[1:]
    if len(args) == 3 and args[0] == "--compare":
        diff, notes = compare(args[1], args[2])
        for n in notes:
            print(f"note (run-time field): {n}")
        print("identical outside run-time fields (result.json, every CSV, figure file names)" if not diff
              else f"differ in: {', '.join(diff)}")
        return 1 if diff else 0
    if len(args) < 2 or args[0] not in STUDIES:
        print(__doc__)
        return 2
    study, out = args[0], args[1]
    use_cprofile = "--cprofile" in args
    rest = [x for x in args[2:] if x != "--cprofile"]
    rep = profile(study, ["--out", out, *rest], use_cprofile)
    _print(rep)
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, f"profile-{study}.json"), "w") as fh:
        json.dump(rep, fh, indent=1, default=str)
    return 0


if __name__ == "__main__":
    sys.exit(main())
