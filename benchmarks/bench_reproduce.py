"""The full reproduction against issue 24's baseline, side by side in one run (issue 24, item 1).

The target: ``adcskit reproduce`` on a fresh checkout takes at most half the wall time of issue
24's baseline main (``89cf3b6``) on the same machine, using both cores (≥ 180 % CPU). This
script measures both in one run, as a user would meet them: each commit cloned from this
repository into its own directory with its own venv (``python -m venv --system-site-packages``,
``pip install -e . --no-deps``: the dependencies come from the Python that runs this script),
an empty numba cache for every run (a new ``NUMBA_CACHE_DIR``, so every run compiles its
kernels as a first run does), then ``adcskit reproduce`` (the candidate with its default
``--jobs``, the baseline as it is: it has no ``--jobs``). The runs alternate in pairs, the order
swapped every pair (baseline first in pair 1 unless ``--first candidate``, then the other way
round, ...), because the project's VM drifts by up to 20 % within an hour: the ratio to read
is each pair's, and their median.

Printed per run: wall, CPU (user + system of the ``adcskit`` process and its workers), CPU
share, exit status, ``errors.json``, the per-study ``runtime_s`` and, for a ``--jobs`` run, the
per-study CPU seconds of its summary; then each pair's wall ratio
(candidate / baseline) and the median. ``--json`` writes all of it after every run (an
interrupted run keeps the finished ones). Uncommitted changes are not measured: the candidate
is a commit (default ``HEAD``).

Usage (from anywhere; one pair of full reproductions takes about 25 minutes on 2 cores)::

    python benchmarks/bench_reproduce.py --pairs 1 --json bench_reproduce.json
    python benchmarks/bench_reproduce.py --quick --pairs 1      # the quick reproduction (~5 min)
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import platform
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

REPO = pathlib.Path(__file__).resolve().parents[1]
BASELINE = "89cf3b6"  # main when issue 24 was filed (its measurements are of this commit)


def _git(*args: str, cwd: pathlib.Path = REPO) -> str:
    return subprocess.run(["git", *args], cwd=cwd, check=True, capture_output=True, text=True).stdout.strip()


def checkout(rev: str, where: pathlib.Path) -> pathlib.Path:
    """Clone this repository at ``rev`` into ``where`` and install it into its own venv;
    returns the venv's ``adcskit`` executable."""
    subprocess.run(["git", "clone", "-q", "--no-checkout", str(REPO), str(where)], check=True)
    _git("checkout", "-q", rev, cwd=where)
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(where / ".venv")],
                   check=True)
    subprocess.run([str(where / ".venv" / "bin" / "python"), "-m", "pip", "install", "-q", "-e", ".",
                    "--no-deps"], cwd=where, check=True, stdout=subprocess.DEVNULL)
    return where / ".venv" / "bin" / "adcskit"


def run_once(adcskit: pathlib.Path, out: pathlib.Path, quick: bool, jobs: int | None,
             log: pathlib.Path) -> dict:
    """One ``adcskit reproduce`` from an empty numba cache; wall, CPU of the process tree, per-study
    times."""
    cmd = [str(adcskit), "reproduce", "--out", str(out)] + (["--quick"] if quick else [])
    if jobs is not None:
        cmd += ["--jobs", str(jobs)]
    env = dict(os.environ, NUMBA_CACHE_DIR=tempfile.mkdtemp(prefix="numba-cold-"))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    with open(log, "w") as fh:
        rc = subprocess.run(cmd, cwd=adcskit.parents[2], env=env, stdout=fh, stderr=subprocess.STDOUT).returncode
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    shutil.rmtree(env["NUMBA_CACHE_DIR"], ignore_errors=True)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    studies = {}
    for res in sorted(out.glob("*/result.json")):
        studies[res.parent.name] = round(float(json.loads(res.read_text()).get("runtime_s", float("nan"))), 1)
    # per-study CPU: the --jobs summary's "  STUDY  done in W s (C CPU-s)" lines (since issue 24)
    studies_cpu = {m.group(1): float(m.group(2)) for m in
                   re.finditer(r"^\s+(\S+)\s+done in [\d.]+ s \(([\d.]+) CPU-s\)$", log.read_text(), re.M)}
    errors = out / "errors.json"
    return {"command": " ".join(cmd), "exit": rc, "wall_s": round(wall, 1), "cpu_s": round(cpu, 1),
            "cpu_share_pct": round(100.0 * cpu / wall, 1),
            "errors": json.loads(errors.read_text()) if errors.exists() else None,
            "studies_runtime_s": studies, "studies_cpu_s": studies_cpu, "log": str(log),
            "started_utc": time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime(time.time() - wall))}


def _cpu_name() -> str:
    """The CPU's model name (``/proc/cpuinfo`` on Linux), else what ``platform`` knows."""
    try:
        for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _summary(runs: list[dict]) -> dict:
    ratios = []
    for p in sorted({r["pair"] for r in runs}):
        side = {r["side"]: r for r in runs if r["pair"] == p}
        if {"baseline", "candidate"} <= side.keys():
            ratios.append(round(side["candidate"]["wall_s"] / side["baseline"]["wall_s"], 3))
    return {"wall_ratio_per_pair": ratios,
            "wall_ratio_median": statistics.median(ratios) if ratios else None,
            "goal": "wall ratio <= 0.5 with >= 180 % CPU (issue 24, item 1)"}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--baseline", default=BASELINE, help=f"baseline commit (default {BASELINE})")
    ap.add_argument("--candidate", default="HEAD", help="candidate commit (default HEAD)")
    ap.add_argument("--pairs", type=int, default=1, help="baseline/candidate pairs, order swapped each pair")
    ap.add_argument("--first", choices=("baseline", "candidate"), default="baseline",
                    help="which side runs first in pair 1 (then alternating; default baseline)")
    ap.add_argument("--jobs", type=int, default=None, help="candidate's --jobs (default: its own default)")
    ap.add_argument("--quick", action="store_true", help="the quick reproduction instead of the full one")
    ap.add_argument("--workdir", default=None, help="where the checkouts and outputs go (default: a new temporary directory)")
    ap.add_argument("--json", default=None, help="write the runs and ratios here (after every run)")
    a = ap.parse_args(argv)
    if a.pairs < 1:
        ap.error(f"--pairs must be >= 1; got {a.pairs}")
    work = pathlib.Path(a.workdir or tempfile.mkdtemp(prefix="bench-reproduce-")).resolve()
    work.mkdir(parents=True, exist_ok=True)
    revs = {"baseline": _git("rev-parse", "--short", a.baseline),
            "candidate": _git("rev-parse", "--short", a.candidate)}
    print(f"bench_reproduce: baseline {revs['baseline']}, candidate {revs['candidate']}, "
          f"{'quick' if a.quick else 'full'}, {a.pairs} pair(s), {os.cpu_count()} CPUs; work in {work}",
          flush=True)
    exe = {side: checkout(rev, work / f"{side}-src") for side, rev in revs.items()}
    jobs = {"baseline": None, "candidate": a.jobs}  # the baseline as it was: it has no --jobs
    report = {"machine": f"{_cpu_name()}, {os.cpu_count()} CPUs, {platform.platform()}",
              "commits": revs, "quick": a.quick, "runs": []}
    for p in range(1, a.pairs + 1):
        order = ("baseline", "candidate") if (p % 2) == (a.first == "baseline") else ("candidate", "baseline")
        for side in order:
            out = work / f"out-{side}-{p}"
            shutil.rmtree(out, ignore_errors=True)
            print(f"pair {p}: {side} {revs[side]} ...", flush=True)
            r = run_once(exe[side], out, a.quick, jobs[side], work / f"{side}-{p}.log")
            r.update(pair=p, side=side, commit=revs[side])
            report["runs"].append(r)
            print(f"pair {p}: {side} {revs[side]}: wall {r['wall_s']:.1f} s, CPU {r['cpu_s']:.1f} s "
                  f"({r['cpu_share_pct']:.0f} %), exit {r['exit']}, errors {r['errors']}", flush=True)
            print("    wall: " + ", ".join(f"{k} {v}" for k, v in r["studies_runtime_s"].items()), flush=True)
            if r["studies_cpu_s"]:
                print("    CPU:  " + ", ".join(f"{k} {v}" for k, v in r["studies_cpu_s"].items()), flush=True)
            report.update(_summary(report["runs"]))
            if a.json:
                tmp = pathlib.Path(a.json + ".tmp")
                tmp.write_text(json.dumps(report, indent=2))
                tmp.replace(a.json)
    print(f"wall ratio candidate / baseline per pair: {report['wall_ratio_per_pair']}, median "
          f"{report['wall_ratio_median']} (goal: <= 0.5 with >= 180 % CPU)")
    return 0 if all(r["exit"] == 0 for r in report["runs"]) else 1


if __name__ == "__main__":
    sys.exit(main())
