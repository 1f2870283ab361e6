"""Shared pieces of ``profile_thruster_layout.py`` and ``profile_rendezvous.py`` (issue 24, item 1).

The model is ``profile_closed_loop.py``: light wrappers that only time and count (no number of
the study changes), process CPU (``time.process_time``) per phase and per part, numba
compilation taken out, an optional ``cProfile`` pass that sums ``tottime`` by library, and a
``--compare`` of two output directories outside the run-time fields.

* :class:`Recorder` -- ``phase(label, fn)`` wraps a function as a phase (only the outermost
  phase counts; a phase called inside another is recorded as a part of it), ``part(name, fn)``
  as a part of whatever phase is running (parts may nest: "of it"), ``hook_numba()`` times
  ``Dispatcher.compile`` (compiles vs cache loads) and takes it out of the parts.
* :func:`by_library` -- a ``pstats.Stats`` summed by library (pymoo, scipy's HiGHS, numpy,
  CasADi, matplotlib, numba, adcskit, ...): what dominates. A numba kernel call is no Python
  function to ``cProfile``: its time is in the ``tottime`` of the function that calls it.
* :func:`compare` -- what differs between two output directories of one study (``result.json``
  and every CSV, outside the run-time fields the caller names; the PNG file names too).
* :func:`outermost_compiles` -- ``Dispatcher.compile`` timed per outermost call (all profile
  scripts use it).
* :func:`main` -- the two scripts' command line (``OUT [--cprofile] ...`` or ``--compare A B``).
"""

from __future__ import annotations

import collections
import csv
import json
import os
import re
import sys
import time
from collections.abc import Callable
from typing import Any

#: result.json keys that hold run times or machine facts (differ between any two runs)
RUNTIME_KEYS = ("runtime_s", "adcskit_version", "created", "executor", "host", "python", "platform")


def outermost_compiles(compile_fn: Callable[..., Any],
                       record: Callable[[str, bool, float, float, float], None]) -> Callable[..., Any]:
    """``numba``'s ``Dispatcher.compile`` wrapped so that each outermost call (a compile that
    triggers others counts once) reports ``record(name, compiled, cpu_s, wall_s, thread_s)``:
    ``module.function``, whether it compiled (a cache miss) or loaded from the disk cache, and
    its process CPU, wall and calling-thread CPU seconds. Shared by every profile script."""
    depth = [0]

    def wrapped(disp, sig):
        if depth[0]:
            return compile_fn(disp, sig)
        misses = sum(disp._cache_misses.values())
        depth[0] += 1
        t0, c0, h0 = time.perf_counter(), time.process_time(), time.thread_time()
        try:
            return compile_fn(disp, sig)
        finally:
            depth[0] -= 1
            name = getattr(disp.py_func, "__module__", "?").rsplit(".", 1)[-1] + "." + disp.py_func.__name__
            record(name, sum(disp._cache_misses.values()) > misses, time.process_time() - c0,
                   time.perf_counter() - t0, time.thread_time() - h0)

    return wrapped


class Recorder:
    """Phases, parts and numba compilation of one in-process study run (times and counts only)."""

    def __init__(self) -> None:
        zero = {"calls": 0, "wall_s": 0.0, "cpu_s": 0.0}
        self.phases: dict[str, dict[str, float]] = collections.defaultdict(lambda: dict(zero))
        self.parts: dict[str, dict[str, dict[str, float]]] = collections.defaultdict(
            lambda: collections.defaultdict(lambda: dict(zero)))
        self.compile: dict[str, dict[str, Any]] = collections.defaultdict(
            lambda: {"compiles": 0, "loads": 0, "compile_cpu_s": 0.0, "load_cpu_s": 0.0, "compiled": []})
        self.counters: dict[str, dict[str, Any]] = collections.defaultdict(lambda: collections.defaultdict(int))
        self.stack = ["rest"]
        self.compile_cpu = 0.0  # running total, taken out of the parts
        self._undo: list[Callable[[], None]] = []

    @property
    def current(self) -> str:
        return self.stack[-1]

    def phase(self, label: str | Callable[..., str], fn: Callable[..., Any]) -> Callable[..., Any]:
        """``fn`` as a phase named ``label`` (or ``label(*args, **kwargs)``)."""

        def wrapped(*a, **k):
            name = label(*a, **k) if callable(label) else label
            if len(self.stack) > 1:  # inside another phase: a part of it
                return self.part(name, fn)(*a, **k)
            self.stack.append(name)
            t0, c0 = time.perf_counter(), time.process_time()
            try:
                return fn(*a, **k)
            finally:
                d = self.phases[name]
                d["calls"] += 1
                d["wall_s"] += time.perf_counter() - t0
                d["cpu_s"] += time.process_time() - c0
                self.stack.pop()

        return wrapped

    def part(self, name: str, fn: Callable[..., Any]) -> Callable[..., Any]:
        """``fn`` as a part of the running phase (CPU without numba compilation)."""

        def wrapped(*a, **k):
            t0, c0, k0 = time.perf_counter(), time.process_time(), self.compile_cpu
            try:
                return fn(*a, **k)
            finally:
                d = self.parts[self.current][name]
                d["calls"] += 1
                d["wall_s"] += time.perf_counter() - t0
                d["cpu_s"] += time.process_time() - c0 - (self.compile_cpu - k0)

        return wrapped

    def patch(self, owner: Any, name: str, wrapper: Callable[[Callable[..., Any]], Callable[..., Any]]) -> None:
        """Replace ``owner.name`` by ``wrapper(owner.name)`` (undone by :meth:`restore`)."""
        old = getattr(owner, name)
        setattr(owner, name, wrapper(old))
        self._undo.append(lambda: setattr(owner, name, old))

    def restore(self) -> None:
        while self._undo:
            self._undo.pop()()

    def hook_numba(self) -> None:
        """Time the outermost ``Dispatcher.compile`` calls: real compiles vs cache loads."""
        import numba.core.dispatcher as nd

        def record(name: str, compiled: bool, cpu_s: float, wall_s: float, thread_s: float) -> None:
            self.compile_cpu += cpu_s
            d = self.compile[self.current]
            if compiled:
                d["compiles"] += 1
                d["compile_cpu_s"] += cpu_s
                d["compiled"].append(f"{name} {cpu_s:.1f} s")
            else:
                d["loads"] += 1
                d["load_cpu_s"] += cpu_s

        self.patch(nd.Dispatcher, "compile", lambda compile_fn: outermost_compiles(compile_fn, record))

    def report(self, total_wall: float, total_cpu: float) -> dict[str, Any]:
        rest = {"calls": 1, "wall_s": total_wall - sum(p["wall_s"] for p in self.phases.values()),
                "cpu_s": total_cpu - sum(p["cpu_s"] for p in self.phases.values())}
        return {
            "total": {"wall_s": total_wall, "cpu_s": total_cpu},
            "phases": {**self.phases, "rest": rest},
            "parts": {k: dict(v) for k, v in self.parts.items()},
            "compile": dict(self.compile),
            "counters": {k: dict(v) for k, v in self.counters.items()},
            "load_average": os.getloadavg(), "cpus": os.cpu_count(),
        }


def print_report(rep: dict[str, Any]) -> None:
    tot = rep["total"]
    la = rep["load_average"]
    print(f"{rep['command']}: {tot['wall_s']:.1f} s wall, {tot['cpu_s']:.1f} s CPU "
          f"(load average {la[0]:.1f} / {la[1]:.1f} / {la[2]:.1f} at the end, {rep['cpus']} CPUs)")
    print(f"{'phase':<34} {'calls':>5} {'wall s':>8} {'CPU s':>8} {'CPU %':>6} {'compile':>8}")
    for name, p in rep["phases"].items():
        c = rep["compile"].get(name, {})
        cc = c.get("compile_cpu_s", 0.0) + c.get("load_cpu_s", 0.0)
        print(f"{name:<34} {p['calls']:5d} {p['wall_s']:8.2f} {p['cpu_s']:8.2f} "
              f"{100 * p['cpu_s'] / max(tot['cpu_s'], 1e-9):6.1f} {cc:8.2f}")
    print("parts per phase (CPU s without compilation, calls; nested parts are 'of it'):")
    for name, ps in rep["parts"].items():
        print(f"  {name}:")
        for k, v in ps.items():
            print(f"    {k:<44} {v['cpu_s']:8.3f} ({v['calls']})")
    if rep["counters"]:
        print("counters:")
        for name, cs in rep["counters"].items():
            print(f"  {name}: " + "; ".join(f"{k} {v}" for k, v in cs.items()))
    print("numba compilation (outermost Dispatcher.compile; CPU s):")
    for name, c in rep["compile"].items():
        print(f"  {name:<34} {c['compiles']} compiled {c['compile_cpu_s']:.1f}; {c['loads']} loaded "
              f"{c['load_cpu_s']:.2f}" + (f" ({', '.join(c['compiled'])})" if c["compiled"] else ""))
    if "libraries" in rep:
        print("cProfile tottime by library (a separate run under cProfile: its overhead inflates Python):")
        total = sum(rep["libraries"].values()) or 1.0
        for k, v in rep["libraries"].items():
            print(f"  {k:<44} {v:8.2f} s {100 * v / total:5.1f} %")
        print("top functions by tottime:")
        for line in rep["top"]:
            print("  " + line)


# ----------------------------------------------------------------------------- cProfile by library

_LIBS = (
    ("scipy linprog / HiGHS", ("scipy/optimize/_linprog", "_highs", "highs")),
    ("scipy nnls", ("_nnls",)),
    ("scipy other", ("scipy",)),
    ("pymoo", ("pymoo",)),
    ("CasADi (incl. IPOPT, NLP build)", ("casadi",)),
    ("matplotlib / PIL (figures)", ("matplotlib", "PIL")),
    ("numba (dispatch, compile, cache)", ("numba", "llvmlite")),
    ("numpy", ("numpy",)),
    ("adcskit (incl. the numba kernels it calls)", ("adcskit",)),
    ("import machinery", ("importlib", "<frozen")),
)


def _library(path: str, func: str) -> str:
    text = path if path != "~" else func
    for name, keys in _LIBS:
        if any(k in text for k in keys):
            return name
    return "builtins / other" if path == "~" else "other Python"


def by_library(stats: Any, top: int = 20) -> tuple[dict[str, float], list[str]]:
    """``tottime`` of a ``pstats.Stats`` summed by library, and the ``top`` functions."""
    out: dict[str, float] = collections.defaultdict(float)
    rows = []
    for (path, line, func), (_cc, nc, tt, ct, _callers) in stats.stats.items():
        out[_library(path, func)] += tt
        rows.append((tt, ct, nc, f"{os.path.basename(path)}:{line}({func})" if path != "~" else func))
    rows.sort(reverse=True)
    lines = [f"{tt:8.2f} s tottime {ct:8.2f} s cumtime {nc:8d} calls  {name[:90]}" for tt, ct, nc, name in rows[:top]]
    return dict(sorted(out.items(), key=lambda kv: -kv[1])), lines


# ----------------------------------------------------------------------------- compare


def _strip(obj: Any, pattern: re.Pattern, text_subs: tuple[tuple[re.Pattern, str], ...]) -> Any:
    if isinstance(obj, dict):
        return {k: _strip(v, pattern, text_subs) for k, v in obj.items()
                if k not in RUNTIME_KEYS and not pattern.search(str(k))}
    if isinstance(obj, list):
        return [_strip(v, pattern, text_subs) for v in obj]
    if isinstance(obj, str):
        for rx, sub in text_subs:
            obj = rx.sub(sub, obj)
        return obj
    return obj


def _csv_rows(path: str, pattern: re.Pattern) -> list[dict[str, str]]:
    with open(path, newline="") as fh:
        return [{k: v for k, v in row.items() if not pattern.search(k)} for row in csv.DictReader(fh)]


def compare(a: str, b: str, pattern: re.Pattern, *, text_subs: tuple = (),
            drop: Callable[[dict[str, Any]], dict[str, Any]] | None = None) -> list[str]:
    """What differs between two output directories of one study outside the run-time fields
    (keys matching ``pattern``, strings after ``text_subs``, whatever ``drop`` removes from the
    parsed result.json): top-level keys of ``result.json``, CSV files, the set of PNG names."""
    with open(os.path.join(a, "result.json")) as fa, open(os.path.join(b, "result.json")) as fb:
        ja, jb = json.load(fa), json.load(fb)
    if drop is not None:
        ja, jb = drop(ja), drop(jb)
    ra, rb = _strip(ja, pattern, text_subs), _strip(jb, pattern, text_subs)
    diff = [f"result.json:{k}" for k in sorted(set(ra) | set(rb)) if ra.get(k) != rb.get(k)]
    csvs = sorted({f for d in (a, b) for f in os.listdir(d) if f.endswith(".csv")})
    for f in csvs:
        pa, pb = os.path.join(a, f), os.path.join(b, f)
        if not (os.path.exists(pa) and os.path.exists(pb)) or _csv_rows(pa, pattern) != _csv_rows(pb, pattern):
            diff.append(f)
    pngs = [sorted(f for f in os.listdir(d) if f.endswith(".png")) for d in (a, b)]
    if pngs[0] != pngs[1]:
        diff.append("PNG file names")
    if not csvs:
        diff.append("(no CSV files)")
    return diff


def run_cli(study: str, argv: list[str], rec: Recorder, cprofile: bool) -> dict[str, Any]:
    """``adcskit run STUDY argv`` in this process under ``rec``'s hooks (and cProfile if asked)."""
    from adcskit import cli

    prof = None
    if cprofile:
        import cProfile

        prof = cProfile.Profile()
        prof.enable()
    t0, c0 = time.perf_counter(), time.process_time()
    try:
        rc = cli.main(["run", study, *argv])
    finally:
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        if prof is not None:
            prof.disable()
        rec.restore()
    rep = {"command": f"adcskit run {study} " + " ".join(argv), "exit": rc, **rec.report(wall, cpu)}
    if prof is not None:
        import pstats

        rep["libraries"], rep["top"] = by_library(pstats.Stats(prof))
    return rep


def main(doc: str, profile: Callable[..., dict[str, Any]], pattern: re.Pattern, *,
         drop: Callable[[dict[str, Any]], dict[str, Any]] | None = None) -> int:
    """Command line of a profile script: ``--compare A B`` (exit 1 on a difference), or
    ``OUT [--cprofile] [adcskit run arguments]``: profile into ``OUT/profile.json``."""
    if len(sys.argv) == 4 and sys.argv[1] == "--compare":
        diff = compare(sys.argv[2], sys.argv[3], pattern, drop=drop)
        print("identical outside run-time fields (result.json, every CSV, PNG names)" if not diff
              else f"differ in: {', '.join(diff)}")
        return 1 if diff else 0
    if len(sys.argv) < 2:
        print(doc)
        return 2
    out = sys.argv[1]
    args = [a for a in sys.argv[2:] if a != "--cprofile"]
    rep = profile(["--out", out, *args], cprofile="--cprofile" in sys.argv[2:])
    print_report(rep)
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "profile.json"), "w") as fh:
        json.dump(rep, fh, indent=1, default=str)
    return 0
