"""Before/after CPU seconds of one command on two source trees, in interleaved pairs.

Runs ``CMD`` alternately with ``PYTHONPATH=BEFORE`` and ``PYTHONPATH=AFTER`` (the order swapped
every pair), ``PAIRS`` pairs, and prints each run's CPU seconds, the medians and the load
average: the protocol of docs/benchmarks.md for a speed change on a shared machine. A run's
figure is the user + system CPU of the child process (``os.wait4``), or, when the command
prints a line ``CPU <seconds>``, that value (a script that times only the part it changes).
``{out}`` in ``CMD`` becomes a fresh directory per run, ``{tree}`` ``before`` or ``after``.
Every run must exit 0. ``--keep DIR`` keeps the ``{out}`` directories under ``DIR`` (to compare
the outputs of the two trees afterwards), otherwise they are removed.

Usage::

    python benchmarks/interleaved_cpu.py BEFORE_SRC AFTER_SRC PAIRS [--keep DIR] -- CMD...

Example (the source tree before a change from git, the worktree's after it)::

    mkdir -p /tmp/before && git archive HEAD~1 src | tar -x -C /tmp/before
    python benchmarks/interleaved_cpu.py /tmp/before/src src 3 -- \\
        python -m adcskit.cli run rendezvous --quick --quiet --out {out}
"""

from __future__ import annotations

import os
import re
import statistics
import subprocess
import sys
import tempfile


def _run(cmd: list[str], src: str, tree: str, workdir: str, k: int) -> float:
    out = os.path.join(workdir, f"{tree}{k}")
    args = [a.replace("{out}", out).replace("{tree}", tree) for a in cmd]
    env = dict(os.environ, PYTHONPATH=os.path.abspath(src))
    proc = subprocess.Popen(args, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    text = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise SystemExit(f"{tree} run {k} exited {proc.returncode}:\n{text[-2000:]}")
    found = re.findall(r"^CPU ([0-9.eE+-]+)\s*$", text, re.M)
    return float(found[-1]) if found else usage.ru_utime + usage.ru_stime


def main() -> int:
    if "--" not in sys.argv or len(sys.argv) < 6:
        print(__doc__)
        return 2
    i = sys.argv.index("--")
    before, after, pairs = sys.argv[1], sys.argv[2], int(sys.argv[3])
    opts = sys.argv[4:i]
    keep = opts[opts.index("--keep") + 1] if "--keep" in opts else None
    cmd = sys.argv[i + 1:]
    res: dict[str, list[float]] = {"before": [], "after": []}
    loads = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp:
        workdir = keep or tmp
        for k in range(pairs):
            order = [("before", before), ("after", after)]
            if k % 2:
                order.reverse()
            for tree, src in order:
                cpu = _run(cmd, src, tree, workdir, k)
                res[tree].append(cpu)
                loads.append(os.getloadavg()[0])
                print(f"pair {k + 1} {tree:<6} {cpu:8.2f} CPU-s (load {loads[-1]:.1f})", flush=True)
    mb, ma = statistics.median(res["before"]), statistics.median(res["after"])
    print(f"before {' / '.join(f'{v:.2f}' for v in res['before'])} -> after {' / '.join(f'{v:.2f}' for v in res['after'])}"
          f" CPU-s; medians {mb:.2f} -> {ma:.2f} ({100 * (ma - mb) / mb:+.1f} %); "
          f"load average {min(loads):.1f}-{max(loads):.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
