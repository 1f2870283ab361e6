"""Profile of the ``rendezvous`` study (S2): CPU per phase, NLP build vs IPOPT, what repeats.

Runs ``adcskit run rendezvous`` in this process with light instrumentation (no change to any
number: the wrappers only time and count; model: ``profile_closed_loop.py``, shared pieces in
``_profiling.py``) and prints, per phase:

* the multistart on the paper's 20×3 mesh (``multistart``), the error-controlled refinement
  of every branch (``_refine`` -> ``solve_adaptive``) under the first reading and under the
  others, the continuation solves of the other readings (``solve`` on 20×3), the open-loop
  re-simulations of the checks (``resimulate``), the records (branch records, bang-bang test,
  derived quantities), claims / findings / checks, report, figures (drawing) and files
  (``write_result``: result.json, CSVs, ``savefig``);
* within them: the CasADi NLP builds (``_Transcription`` / ``_MultiTranscription``, timed
  where the NLP cache builds them), IPOPT (``_run_ipopt``: calls, iterations), the error
  estimate (``estimate_error``), the optimality check (``check_optimality``), the mesh
  refinement (``refine_mesh``), the switch-time re-solve (``_switch_time_solve``, which holds
  its own builds and IPOPT calls);
* counters: NLP cache look-ups, hits, builds, builds whose key was built before (evicted from
  the LRU cache), builds that differ from an earlier build only in the IPOPT options (CasADi
  cannot change the options of a built solver), IPOPT calls that repeat an earlier one exactly
  (same solver, start point, parameters, bounds and multipliers), and error estimates and
  optimality checks of a solution object already estimated / checked.

``--cprofile`` runs the study under ``cProfile`` as well and sums ``tottime`` by library
(CasADi's C++ builds and IPOPT are in the ``casadi`` built-ins); its overhead inflates the
Python parts, so read its shares, not its seconds.

``--compare A B`` compares two rendezvous output directories (``result.json``, every CSV, the
PNG names) and exits 1 if they differ outside the run-time fields (wall and CPU times).

Usage::

    PYTHONPATH=src python benchmarks/profile_rendezvous.py OUT [--quick | --config FILE.toml] [--cprofile]
    python benchmarks/profile_rendezvous.py --compare A/rendezvous B/rendezvous
"""

from __future__ import annotations

import hashlib
import os
import re
import sys
import time
from typing import Any

if not os.environ.get("PYTHONPATH"):  # PYTHONPATH=... selects the source tree (e.g. a tree before a change)
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import _profiling  # noqa: E402

#: keys whose value is a measured run time
_RUNTIME_PATTERN = re.compile(r"((^|_)wall_s|(^|_)cpu_s|solve_s|build_s|ipopt_s|runtime)")


def _digest(*arrays: Any) -> str:
    import numpy as np

    h = hashlib.sha1()
    for a in arrays:
        if isinstance(a, dict):
            for k in sorted(a):
                h.update(k.encode())
                h.update(np.ascontiguousarray(np.asarray(a[k], float)).tobytes())
        else:
            h.update(np.ascontiguousarray(np.asarray(a, float)).tobytes())
    return h.hexdigest()


def profile(argv: list[str], cprofile: bool = False) -> dict[str, Any]:
    """Run the study with ``argv`` (``adcskit run rendezvous`` arguments); return the profile."""
    import importlib

    from matplotlib.figure import Figure

    import adcskit.studies.rendezvous as rv
    from adcskit.optimal_control import adaptive, analysis, multiphase, transcription
    from adcskit.studies import _runner
    from adcskit.studies.rendezvous import experiment as ex
    from adcskit.studies.rendezvous import figures, report

    solve_mod = importlib.import_module("adcskit.optimal_control.solve")  # the package rebinds the name
    rec = _profiling.Recorder()
    rec.hook_numba()
    keys_built: set = set()
    keys_no_opts: set = set()
    ipopt_seen: set = set()
    estimated: set = set()
    checked: set = set()
    dynamics_of: dict[int, str] = {}

    def cache(fn):
        def wrapped(key, build):
            c = rec.counters["NLP cache"]
            c["look-ups"] += 1
            built = []

            def timed_build():
                built.append(1)
                return rec.part("NLP build (CasADi, cache miss)", build)()

            out = fn(key, timed_build)
            if built:
                c["builds"] += 1
                c["builds of a key built before (LRU eviction)"] += key in keys_built
                c["builds differing from an earlier one only in IPOPT options"] += (
                    key not in keys_built and key[:-1] in keys_no_opts)
                keys_built.add(key)
                keys_no_opts.add(key[:-1])
            else:
                c["hits"] += 1
            return out
        return wrapped

    rec.patch(transcription, "cached_nlp", cache)
    rec.patch(multiphase, "cached_nlp", cache)

    def ipopt(fn):
        def wrapped(solver, z0, p, lbz, ubz, lbg, ubg, duals):
            key = (id(solver), _digest(z0, p, lbz, ubz, lbg, ubg, duals))
            c = rec.counters[f"IPOPT ({rec.current})"]
            c["calls"] += 1
            c["exact repeats"] += key in ipopt_seen
            ipopt_seen.add(key)
            out = rec.part("IPOPT (_run_ipopt)", fn)(solver, z0, p, lbz, ubz, lbg, ubg, duals)
            c["iterations"] += int(out[4].get("iter_count", 0))
            return out
        return wrapped

    rec.patch(solve_mod, "_run_ipopt", ipopt)
    rec.patch(multiphase, "_run_ipopt", ipopt)

    def seen(name, store):
        def wrap(fn):
            def wrapped(sol, *a, **k):
                key = (id(sol), repr(sorted(k.items())))
                c = rec.counters[name]
                c["calls"] += 1
                c["repeats on a solution already done"] += key in store
                store.add(key)
                return rec.part(name, fn)(sol, *a, **k)
            return wrapped
        return wrap

    rec.patch(adaptive, "estimate_error", seen("error estimate (estimate_error)", estimated))
    rec.patch(analysis, "check_optimality", seen("optimality check (check_optimality)", checked))
    rec.patch(adaptive, "refine_mesh", lambda fn: rec.part("refine_mesh", fn))
    rec.patch(adaptive, "_switch_time_solve", lambda fn: rec.part("switch-time re-solve (multi-phase)", fn))
    rec.patch(ex, "bang_bang", lambda fn: rec.part("bang_bang", fn))

    def problem(fn):
        def wrapped(*a, **k):
            p = fn(*a, **k)
            dynamics_of[id(p)] = k.get("dynamics", "paper")
            return p
        return wrapped

    rec.patch(ex, "rendezvous_problem", problem)
    rec.patch(ex, "multistart", lambda fn: rec.phase("multistart (20x3)", fn))
    rec.patch(ex, "_refine", lambda fn: rec.phase(
        lambda prob, *a, **k: f"refinement ({dynamics_of.get(id(prob), '?')} reading)", fn))
    rec.patch(ex, "solve", lambda fn: rec.phase("continuation (other readings, 20x3)", fn))
    rec.patch(ex, "resimulate", lambda fn: rec.phase("re-simulation (checks)", fn))
    for name in ("_row_measure", "_derive", "_main_record", "_trajectory"):
        rec.patch(ex, name, lambda fn: rec.phase("records", fn))
    rec.patch(rv, "_decide", lambda fn: rec.phase("claims, findings, checks", fn))
    rec.patch(rv, "check_list", lambda fn: rec.phase("claims, findings, checks", fn))
    for name in ("title", "tables", "comparison", "summary"):
        rec.patch(report, name, lambda fn: rec.phase("report (text, tables)", fn))
    for name in ("trajectory_figures", "table4_figure", "refinement_figure"):
        rec.patch(figures, name, lambda fn: rec.phase("figures (drawing)", fn))
    rec.patch(Figure, "savefig", lambda fn: rec.part("savefig (PNG)", fn))
    rec.patch(_runner, "write_result", lambda fn: rec.phase("files (result.json, CSVs, PNGs)", fn))
    t0 = time.process_time()
    rep = _profiling.run_cli("rendezvous", argv, rec, cprofile)
    rep["process_cpu_s"] = time.process_time() - t0
    return rep


def main() -> int:
    return _profiling.main(__doc__, profile, _RUNTIME_PATTERN)


if __name__ == "__main__":
    sys.exit(main())
