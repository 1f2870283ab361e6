"""Profile of the ``thruster-layout`` study (S3): CPU per phase, what dominates, what repeats.

Runs ``adcskit run thruster-layout`` in this process with light instrumentation (no change to
any number: the wrappers only time and count; model: ``profile_closed_loop.py``, shared pieces
in ``_profiling.py``) and prints, per phase:

* the layout optimisations (``experiment._design_task``), split by kind: the main
  (n, algorithm, seed) designs, their timing repeats (``timing_repeats`` - 1 per design: the
  ``de-faster`` claim's protocol, not waste), the DE-settings sensitivity at n = 6 and the
  paired-couple reading of Table 8; within them the objective (the pymoo problem's
  ``_evaluate``: gene decoding, torque matrices, ``_score``) and, of it, the batched
  redistributed pseudo-inverse (the numba kernel ``_rpi_layouts``); the rest of a design's CPU
  is pymoo (selection, crossover, mutation, survival, duplicate elimination, populations);
  counters: generations, layouts evaluated, designs that repeat an earlier one exactly (same
  n, algorithm, seed, settings; timing repeats counted apart);
* the post-processing of the records (``_summaries``: the exact LP on each best layout;
  ``_reference_vs_optimal``; ``_paper_layouts``; ``_pinv_miss``: the three allocators on random
  layouts; ``_fuel``: optimal vs reference out of sample; ``_e_min``, ``_sensitivity``), with
  every :func:`adcskit.thrusters.allocate` call by method (calls, demands, CPU) and how many
  repeat an earlier call exactly (same matrix, demands, method and f_max: a repeated solve);
* claims, report, figures (drawing), files (``write_result``: result.json, CSVs, ``savefig``);
* numba compilation (compiles vs cache loads); the rest (start-up, config).

``--cprofile`` runs the study under ``cProfile`` as well and sums ``tottime`` by library
(pymoo, scipy's HiGHS, numpy, matplotlib, ...; a numba kernel's time is in its Python caller's
``tottime``); its overhead inflates the Python parts, so read its shares, not its seconds.

``--compare A B`` compares two thruster-layout output directories (``result.json``, every CSV,
the PNG names) and exits 1 if they differ outside the run-time fields (run and CPU times; the
``de-faster`` claim, a CPU-time comparison, but for its id, statement and protocol keys; its
verdict in the summary; comparison rows about run times).

Usage::

    PYTHONPATH=src python benchmarks/profile_thruster_layout.py OUT [--quick | --config FILE.toml] [--cprofile]
    python benchmarks/profile_thruster_layout.py --compare A/thruster-layout B/thruster-layout
"""

from __future__ import annotations

import copy
import json
import os
import re
import sys
from typing import Any

if not os.environ.get("PYTHONPATH"):  # PYTHONPATH=... selects the source tree (e.g. a tree before a change)
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import _profiling  # noqa: E402

#: keys whose value is a measured run time (or a figure of one)
_RUNTIME_PATTERN = re.compile(r"(runtime|(^|_)cpu_s|time_s|wall_s|cpu_ratio)")


def _design_kind(task: Any) -> str:
    if task.repeat > 0:
        return "designs: timing repeats"
    if task.setting is not None:
        return "designs: DE settings (n = 6)"
    if task.paired:
        return "designs: paired couples (Table 8)"
    return "designs: main (n, alg, seed)"


def profile(argv: list[str], cprofile: bool = False) -> dict[str, Any]:
    """Run the study with ``argv`` (``adcskit run thruster-layout`` arguments); return the profile."""
    import numpy as np
    from matplotlib.figure import Figure

    import adcskit.thrusters as th
    from adcskit.studies import _runner
    from adcskit.studies.thruster_layout import claims, figures, report
    from adcskit.studies.thruster_layout import experiment as ex
    from adcskit.thrusters import layout

    rec = _profiling.Recorder()
    rec.hook_numba()
    seen_designs: set = set()
    seen_allocs: set = set()

    def design(fn):
        def wrapped(task):
            kind = _design_kind(task)
            key = (task.n, task.alg, task.seed.entropy, tuple(task.seed.spawn_key), task.de_strategy, task.de_F,
                   task.de_CR, task.paired, task.pop_size, task.n_gen)
            c = rec.counters[kind]
            if task.repeat == 0:
                c["exact repeats of an earlier design"] += key in seen_designs
                seen_designs.add(key)
            res = fn(task)
            c["designs"] += 1
            c["generations"] += len(res.history)
            c["layouts evaluated"] += res.evaluations
            return res
        return wrapped

    rec.patch(ex, "_design_task", lambda fn: rec.phase(lambda task: _design_kind(task), design(fn)))

    def problem(fn):
        def wrapped(*a, **k):
            p = fn(*a, **k)
            p._evaluate = rec.part("objective (problem._evaluate)", p._evaluate)
            return p
        return wrapped

    rec.patch(layout, "_make_problem", problem)
    rec.patch(layout, "_decode", lambda fn: rec.part("  of it: decode genes (_decode)", fn))
    rec.patch(layout, "_score", lambda fn: rec.part("  of it: _score (kernel + terms)", fn))
    rec.patch(layout, "_rpi_layouts", lambda fn: rec.part("    of it: _rpi_layouts (numba kernel)", fn))

    def alloc(fn):
        def wrapped(A, M, *, method="pinv-redistribute", **k):
            Aa, Ma = np.asarray(A, float), np.asarray(M, float)
            key = (method, Aa.shape, Aa.tobytes(), Ma.shape, Ma.tobytes(), repr(sorted(k.items())))
            c = rec.counters[f"allocate ({rec.current})"]
            n_dem = 1 if Ma.ndim == 1 else Ma.shape[0]
            c[f"{method} calls"] += 1
            c[f"{method} demands"] += n_dem
            if key in seen_allocs:
                c[f"{method} exact repeats"] += 1
                c[f"{method} demands in repeats"] += n_dem
            seen_allocs.add(key)
            return rec.part(f"allocate {method}", fn)(A, M, method=method, **k)
        return wrapped

    rec.patch(th, "allocate", alloc)
    for name in ("check_controllability", "score_layout", "decode_layout"):
        rec.patch(th, name, lambda fn, name=name: rec.part(name, fn))
    for name in ("_summaries", "_reference_vs_optimal", "_paper_layouts", "_pinv_miss", "_fuel", "_e_min",
                 "_sensitivity"):
        rec.patch(ex, name, lambda fn, name=name: rec.phase(f"records: {name.lstrip('_')}", fn))
    rec.patch(claims, "evaluate", lambda fn: rec.phase("claims, findings, checks", fn))
    for name in ("summary", "measured", "comparison", "differences", "tables"):
        rec.patch(report, name, lambda fn: rec.phase("report (text, tables)", fn))
    rec.patch(figures, "figures", lambda fn: rec.phase("figures (drawing)", fn))
    rec.patch(Figure, "savefig", lambda fn: rec.part("savefig (PNG)", fn))
    rec.patch(_runner, "write_result", lambda fn: rec.phase("files (result.json, CSVs, PNGs)", fn))
    return _profiling.run_cli("thruster-layout", argv, rec, cprofile)


def _drop(r: dict[str, Any]) -> dict[str, Any]:
    """The run-time parts of a thruster-layout result.json that have no run-time key name: the
    ``de-faster`` claim's measured ratios, interval, readings and detail (CPU-time medians), and
    the summary / comparison sentences that quote run times."""
    r = copy.deepcopy(r)
    r["claims"] = [{k: c.get(k) for k in ("id", "statement", "where", "protocol_keys")} if c.get("id") == "de-faster"
                   else c for c in r.get("claims", [])]
    r["summary"] = re.sub(r"de-faster: [^;]*;", "de-faster: (timing);", str(r.get("summary", "")))
    for c in r.get("comparison", []) or []:
        if isinstance(c, dict) and re.search(r"time|faster|CPU", json.dumps(c), re.I):
            for k in ("measured", "ours", "value", "note", "agrees"):
                c.pop(k, None)
    return r


def main() -> int:
    return _profiling.main(__doc__, profile, _RUNTIME_PATTERN, drop=_drop)


if __name__ == "__main__":
    sys.exit(main())
