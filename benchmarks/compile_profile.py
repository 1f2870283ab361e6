"""Where a cold compilation of the closed-loop kernel spends its CPU: per function, per phase.

Compiles the thruster closed-loop kernel from an empty numba cache (``simulate`` of
bench_basilisk.py's full chain, 2 samples: the same ``run_parallel`` signature as every study)
and attributes the process's CPU seconds (``time.process_time``) to

* the function being compiled (numba's ``numba:compile`` events, nested: a dispatcher that
  ``sample_loop`` calls is compiled inside it; each row is *self* time, children excluded);
* the phase: numba's typing passes, numba's lowering (Python building LLVM IR), LLVM's
  per-function passes (``_optimize_functions``), LLVM's module passes on the library's final
  module after the callees' modules are linked in (``_optimize_final_module``), machine-code
  generation (``finalize_object``), and the rest (linking, other numba passes);

and prints, per code library finalized, the size of its final module (LLVM IR instructions
before / after the module passes, defined functions) and the CPU of its module passes and
code generation. numba links the module of every dispatcher a function calls into the
caller's library (``linkonce_odr``) and optimises and code-generates the linked module again,
so a callee's code is optimised once per library that (transitively) calls it.

Run with an empty cache (the script makes one if ``NUMBA_CACHE_DIR`` is unset)::

    PYTHONPATH=src python benchmarks/compile_profile.py [--json OUT.json] [--sizes]

``--sizes`` counts the final modules' instructions (adds Python CPU to the timings: use it in a
separate run).
"""

import json
import os
import sys
import tempfile
import time
import warnings

if not os.environ.get("NUMBA_CACHE_DIR"):
    os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="numba-cold-")

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import numba.core.codegen as _cg  # noqa: E402
import numba.core.event as _ev  # noqa: E402

_STACK = []  # frames: [kind, name, start, child]
_SELF = {}  # (dispatcher, phase) -> CPU s
_LIBS = []  # per finalized library
_PASSES = {}  # (qualname, pass) -> self CPU s of numba's passes (register_jitable helpers too)
_SIZES = "--sizes" in sys.argv


def _disp():
    for f in reversed(_STACK):
        if f[0] == "compile":
            return f[1]
    return "(top level)"


def _push(kind, name):
    _STACK.append([kind, name, time.process_time(), 0.0])


def _pop():
    kind, name, t0, child = _STACK.pop()[:4]
    total = time.process_time() - t0
    key = (name, "other") if kind == "compile" else (_disp(), name)
    _SELF[key] = _SELF.get(key, 0.0) + total - child
    if _STACK:
        _STACK[-1][3] += total
    return total


class _Events(_ev.Listener):
    def __init__(self, kind):
        self.kind = kind

    def on_start(self, event):
        if self.kind == "compile":
            d = event.data["dispatcher"]
            name = getattr(d, "py_func", None)
            name = f"{name.__module__}.{name.__qualname__}" if name else str(d)
            _push("compile", name)
        else:
            _push("pass", _phase_of(event.data["name"]))
            _STACK[-1].append(event.data["qualname"])
            _STACK[-1].append(event.data["name"].split(" ")[0])

    def on_end(self, event):
        frame = _STACK[-1]
        t = time.process_time() - frame[2] - frame[3]
        if frame[0] == "pass":
            k = (frame[4], frame[5])
            _PASSES[k] = _PASSES.get(k, 0.0) + t
        _pop()


def _phase_of(pass_name):
    """Phase of a numba compiler pass (``pss.name()``: ``nopython_type_inference [qualname]``)."""
    p = pass_name.split(" ")[0]
    if "type_inference" in p:
        return "numba typing"
    if "inline" in p:
        return "numba inlining"
    if "lowering" in p:
        return "numba lowering"
    return "numba other passes"


def _wrap(cls, meth, phase):
    orig = getattr(cls, meth)

    def wrapped(self, *a, **k):
        _push("llvm", phase)
        try:
            return orig(self, *a, **k)
        finally:
            _pop()

    setattr(cls, meth, wrapped)


def _n_ins(mod):
    return sum(1 for f in mod.functions for b in f.blocks for _ in b.instructions)


def _install():
    _wrap(_cg.CPUCodeLibrary, "_optimize_functions", "LLVM function passes")
    _wrap(_cg.JITCodeLibrary, "_finalize_specific", "LLVM code generation")
    orig_final = _cg.CPUCodeLibrary._optimize_final_module

    def final(self):
        before = _n_ins(self._final_module) if _SIZES else -1
        _push("llvm", "LLVM module passes")
        try:
            orig_final(self)
        finally:
            cpu = _pop()
        mod = self._final_module
        _LIBS.append({"library": self.name, "in": _disp(), "ir_before": before, "ir_after": _n_ins(mod) if _SIZES else -1,
                      "functions": sum(not f.is_declaration for f in mod.functions),
                      "linked_libraries": len(self._linking_libraries), "module_pass_cpu_s": cpu})

    _cg.CPUCodeLibrary._optimize_final_module = final
    orig_spec = _cg.JITCodeLibrary._finalize_specific

    def spec(self):
        t0 = time.process_time()
        orig_spec(self)
        if _LIBS and _LIBS[-1]["library"] == self.name:
            _LIBS[-1]["codegen_cpu_s"] = time.process_time() - t0

    _cg.JITCodeLibrary._finalize_specific = spec
    _ev.register("numba:compile", _Events("compile"))
    _ev.register("numba:run_pass", _Events("pass"))


def main(argv):
    warnings.simplefilter("ignore")
    _install()
    from adcskit.simulation import _kernels, simulate
    from bench_basilisk import _speed_scenarios

    _, full = _speed_scenarios(1.0)
    t0 = time.process_time()
    w0 = time.perf_counter()
    simulate(full, 2, rng=0)
    cpu = time.process_time() - t0
    wall = time.perf_counter() - w0
    phases = ("numba typing", "numba inlining", "numba lowering", "numba other passes", "LLVM function passes",
              "LLVM module passes", "LLVM code generation", "other")
    by_disp = {}
    for (d, ph), v in _SELF.items():
        by_disp.setdefault(d, dict.fromkeys(phases, 0.0))[ph] += v
    rows = sorted(by_disp.items(), key=lambda kv: -sum(kv[1].values()))
    print(f"simulate(full chain, 2 samples), cold cache: {cpu:.1f} CPU-s, {wall:.1f} s wall, "
          f"load {os.getloadavg()[0]:.2f}; NUMBA_CACHE_DIR={os.environ['NUMBA_CACHE_DIR']}")
    print(f"{'self CPU-s':>10} " + " ".join(f"{p[:12]:>12}" for p in phases) + "  function")
    for d, v in rows:
        tot = sum(v.values())
        if tot < 0.05:
            continue
        print(f"{tot:10.2f} " + " ".join(f"{v[p]:12.2f}" for p in phases) + f"  {d}")
    tot = {p: sum(v[p] for _, v in rows) for p in phases}
    print(f"{sum(tot.values()):10.2f} " + " ".join(f"{tot[p]:12.2f}" for p in phases) + "  (all)")
    print("\nfinal modules (LLVM IR instructions before -> after the module passes):")
    for lib in sorted(_LIBS, key=lambda x: -x["module_pass_cpu_s"])[:25]:
        print(f"{lib['module_pass_cpu_s']:7.2f} s module passes {lib.get('codegen_cpu_s', 0.0):7.2f} s codegen "
              f"{lib['ir_before']:7d} -> {lib['ir_after']:7d} ins {lib['functions']:4d} fns "
              f"{lib['linked_libraries']:3d} linked  {lib['library'][:70]}")
    print("\nnumba passes (self CPU-s: LLVM work inside a lowering pass excluded) per compiled Python "
          "function, top 20:")
    for (q, ph), v in sorted(_PASSES.items(), key=lambda kv: -kv[1])[:20]:
        print(f"{v:7.2f}  {ph:32s} {q}")
    sig = _kernels.run_parallel.signatures
    print(f"run_parallel signatures: {len(sig)}; block_loop: {len(_kernels.block_loop_jit.signatures)}; "
          f"sample_loop (GPU driver's, compiled on the CPU only when called): {len(_kernels.sample_loop_jit.signatures)}")
    if "--json" in argv:
        with open(argv[argv.index("--json") + 1], "w") as fh:
            json.dump({"cpu_s": cpu, "wall_s": wall, "load": os.getloadavg()[0],
                       "by_function": {d: v for d, v in rows}, "libraries": _LIBS}, fh, indent=1)


if __name__ == "__main__":
    main(sys.argv[1:])
