"""Profile of the ``onoff-tuning`` study: CPU and wall time per phase, kernel share, thread split.

Runs ``adcskit run onoff-tuning`` in this process with light instrumentation (no change to
any number: the wrappers only time and count) and prints, per phase (deterministic NSGA-II,
printed gain order, robust GAs, Monte-Carlo evaluations, the rest: report and figures):

* wall and process CPU time;
* the on-off kernel calls made in it (``simulate_batch``): calls, samples, sample-steps per
  CPU-second, and the CPU time of the calling thread vs the other threads of the process
  during those calls (numba's ``prange`` workers), i.e. how evenly a call's work is split;
* the Python work between kernel calls (phase CPU minus kernel CPU);
* for the robust GAs: candidates evaluated and how many were exact repeats of an earlier
  candidate of the same GA run (what a cache of objective values could save);
* the numba signatures of the kernel drivers (a count above one means a recompilation).

Thread CPU comes from ``/proc/self/task/*/stat`` (clock ticks, 10 ms), so it is meaningful
for phases of seconds, not for single calls; on a loaded machine wall time says little and
CPU time is the figure to read.

``--compare A B`` compares two ``result.json`` files (claims, findings, checks, measured,
config, summary, tables) and exits 1 if they differ anywhere but in run-time fields.

Usage::

    PYTHONPATH=src python benchmarks/profile_onoff_tuning.py OUT [--quick | --config FILE.toml]
    python benchmarks/profile_onoff_tuning.py --compare A/onoff-tuning/result.json B/onoff-tuning/result.json
"""

from __future__ import annotations

import collections
import json
import os
import sys
import time
from typing import Any

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

_TICK = os.sysconf("SC_CLK_TCK")
#: result.json keys that hold run times (differ between any two runs)
_RUNTIME_KEYS = ("runtime_s", "adcskit_version", "created", "executor", "host", "python", "platform")


def _thread_cpu() -> dict[str, float]:
    """CPU seconds (user + system) of every thread of this process, by thread id."""
    out = {}
    for tid in os.listdir("/proc/self/task"):
        try:
            with open(f"/proc/self/task/{tid}/stat") as fh:
                f = fh.read().rsplit(")", 1)[1].split()
        except OSError:  # the thread ended meanwhile
            continue
        out[tid] = (int(f[11]) + int(f[12])) / _TICK
    return out


def profile(argv: list[str]) -> dict[str, Any]:
    """Run the study with ``argv`` (``adcskit run onoff-tuning`` arguments) and return the profile."""
    import numpy as np

    from adcskit import cli
    from adcskit.control import _onoff_kernels as kernels
    from adcskit.control import onoff, tuning
    from adcskit.studies.onoff_tuning import experiment as ex

    main_tid = str(os.getpid())
    kern: dict[str, dict[str, float]] = collections.defaultdict(
        lambda: {"calls": 0, "samples": 0, "sample_steps": 0.0, "wall_s": 0.0, "cpu_s": 0.0,
                 "cpu_calling_thread_s": 0.0, "cpu_other_threads_s": 0.0})
    phases: dict[str, dict[str, float]] = collections.defaultdict(lambda: {"calls": 0, "wall_s": 0.0, "cpu_s": 0.0})
    ga = {"candidates": 0, "repeats": 0}
    stack = ["rest"]
    seen: list[set] = []
    simulate_batch = onoff.simulate_batch

    def timed_batch(params, settings=None, **kw):
        t0, c0, th0 = time.perf_counter(), time.process_time(), _thread_cpu()
        res = simulate_batch(params, settings, **kw)
        th1 = _thread_cpu()
        d = kern[stack[-1]]
        d["calls"] += 1
        d["samples"] += res.n_samples
        d["sample_steps"] += float(res.n_samples) * res.n_steps
        d["wall_s"] += time.perf_counter() - t0
        d["cpu_s"] += time.process_time() - c0
        for tid, v in th1.items():
            key = "cpu_calling_thread_s" if tid == main_tid else "cpu_other_threads_s"
            d[key] += v - th0.get(tid, 0.0)
        return res

    evaluate_gains = tuning.evaluate_gains

    def counted_gains(gains, samples=None, **kw):
        if stack[-1] == "robust GA" and samples is not None:
            for row in np.atleast_2d(np.asarray(gains, dtype=float)):
                ga["candidates"] += 1
                key = row.tobytes()
                if key in seen[-1]:
                    ga["repeats"] += 1
                seen[-1].add(key)
        return evaluate_gains(gains, samples, **kw)

    def phase(name, fn):
        def wrapped(*a, **k):
            stack.append(name)
            if name == "robust GA":
                seen.append(set())
            t0, c0 = time.perf_counter(), time.process_time()
            try:
                return fn(*a, **k)
            finally:
                phases[name]["calls"] += 1
                phases[name]["wall_s"] += time.perf_counter() - t0
                phases[name]["cpu_s"] += time.process_time() - c0
                stack.pop()
        return wrapped

    tuning.simulate_batch = timed_batch
    ex.simulate_batch = timed_batch
    tuning.evaluate_gains = counted_gains
    ex.tune_deterministic = phase("NSGA-II", ex.tune_deterministic)
    ex._gain_order = phase("gain order", ex._gain_order)
    ex.tune_robust = phase("robust GA", ex.tune_robust)
    ex.monte_carlo = phase("Monte-Carlo", ex.monte_carlo)
    t0, c0 = time.perf_counter(), time.process_time()
    rc = cli.main(["run", "onoff-tuning", *argv])
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    rest = {"calls": 1, "wall_s": wall - sum(p["wall_s"] for p in phases.values()),
            "cpu_s": cpu - sum(p["cpu_s"] for p in phases.values())}
    return {
        "command": "adcskit run onoff-tuning " + " ".join(argv), "exit": rc,
        "total": {"wall_s": wall, "cpu_s": cpu}, "phases": {**phases, "rest": rest}, "kernel": dict(kern),
        "robust_ga": ga,
        "signatures": {"simulate_parallel": len(kernels.simulate_parallel.signatures),
                       "simulate_serial": len(kernels.simulate_serial.signatures)},
        "load_average": os.getloadavg(), "cpus": os.cpu_count(),
    }


def _print(rep: dict[str, Any]) -> None:
    tot = rep["total"]
    print(f"{rep['command']}: {tot['wall_s']:.1f} s wall, {tot['cpu_s']:.1f} s CPU "
          f"(load average {rep['load_average'][0]:.1f} on {rep['cpus']} CPUs)")
    print(f"{'phase':<12} {'wall s':>8} {'CPU s':>8} {'CPU %':>6} {'kernel CPU s':>12} {'Python CPU s':>12} "
          f"{'calls':>6} {'samples':>9} {'steps/CPU-s':>11} {'thread split':>13}")
    for name, p in rep["phases"].items():
        k = rep["kernel"].get(name, {})
        kc = k.get("cpu_s", 0.0)
        split = (f"{k['cpu_calling_thread_s']:.1f}/{k['cpu_other_threads_s']:.1f}" if k else "-")
        rate = f"{k['sample_steps'] / kc:.3g}" if kc > 0 else "-"
        print(f"{name:<12} {p['wall_s']:8.1f} {p['cpu_s']:8.1f} {100 * p['cpu_s'] / tot['cpu_s']:6.1f} {kc:12.1f} "
              f"{p['cpu_s'] - kc:12.1f} {k.get('calls', 0):6d} {k.get('samples', 0):9d} {rate:>11} {split:>13}")
    g = rep["robust_ga"]
    print(f"robust GA candidates {g['candidates']}, exact repeats within a run {g['repeats']}; "
          f"kernel signatures {rep['signatures']}")


def _strip(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {k: _strip(v) for k, v in obj.items() if k not in _RUNTIME_KEYS}
    if isinstance(obj, list):
        return [_strip(v) for v in obj]
    return obj


def compare(a: str, b: str) -> list[str]:
    """Top-level keys of two result.json files that differ outside the run-time fields."""
    with open(a) as fa, open(b) as fb:
        ra, rb = _strip(json.load(fa)), _strip(json.load(fb))
    return sorted(k for k in set(ra) | set(rb) if ra.get(k) != rb.get(k))


def main() -> int:
    if len(sys.argv) == 4 and sys.argv[1] == "--compare":
        diff = compare(sys.argv[2], sys.argv[3])
        print("identical outside run-time fields" if not diff else f"differ in: {', '.join(diff)}")
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
