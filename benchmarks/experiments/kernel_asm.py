"""Assembly of the closed-loop CPU kernel's ``block_loop``, per function: for kernel rewrites.

Compiles the kernel (bench_basilisk.py's full chain, 2 samples), writes the assembly of the
module that holds ``block_loop`` (numba's ``inspect_asm``: ``block_loop``, the device
helpers linked into it and the dispatchers it calls) and prints, per function, the
instruction count, the call instructions, the stores of a double to the stack (spills,
``movsd %xmm, n(%rsp)``) and the loads of a double from it, the packed (vector) double
instructions, and the symbols that ``block_loop`` itself calls. (Until the lane blocks,
2026-12-03, the CPU driver ran ``sample_loop``, the GPU driver's per-sample function, which
this script then read; ``sample_loop_jit`` compiles only when called.) Needs a cold compilation, so set ``NUMBA_CACHE_DIR`` to an
empty folder (a kernel loaded from the disk cache has no assembly)::

    NUMBA_CACHE_DIR=$(mktemp -d) PYTHONPATH=src python benchmarks/experiments/kernel_asm.py /tmp/k.s
"""

import collections
import os
import re
import sys
import warnings

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # benchmarks/
from adcskit.simulation import _kernels, simulate
from bench_basilisk import _speed_scenarios

_SPILL = re.compile(r"v?movsd\s+%xmm\d+, -?\d*\(%r[sb]p\)")
_RELOAD = re.compile(r"v?movsd\s+-?\d*\(%r[sb]p\), %xmm")
_PACKED = re.compile(r"v(add|sub|mul|div|sqrt)pd\s")


def functions(asm):
    """Instructions per top-level symbol of an assembly listing (labels ``.L*`` excluded)."""
    out = collections.OrderedDict()
    cur = None
    for line in asm.splitlines():
        m = re.match(r"^([A-Za-z_.$][\w.$@]*):", line)
        if m and not m.group(1).startswith(".L"):
            cur = m.group(1)
            out[cur] = []
        elif cur and line.startswith("\t") and not line.strip().startswith("."):
            out[cur].append(line.strip())
    return out


def main(path):
    warnings.simplefilter("ignore")
    _, full = _speed_scenarios(1.0)
    simulate(full, 2, rng=0)
    f = _kernels.block_loop_jit
    asm = f.inspect_asm(f.signatures[0])
    with open(path, "w") as fh:
        fh.write(asm)
    funcs = functions(asm)
    for name, ins in funcs.items():
        if not ins:
            continue
        calls = sum(i.startswith("call") for i in ins)
        spill = sum(bool(_SPILL.match(i)) for i in ins)
        reload = sum(bool(_RELOAD.match(i)) for i in ins)
        packed = sum(bool(_PACKED.match(i)) for i in ins)
        print(f"{len(ins):6d} ins {calls:4d} calls {spill:4d} spills {reload:4d} reloads {packed:4d} packed  "
              f"{name[:90]}")
    loop = next(ins for n, ins in funcs.items() if "10block_loop" in n and not n.startswith(("_ZN7cpython", "cfunc")))
    called = collections.Counter(
        re.sub(r"B\d+v\d+.*", "", m) for i in loop for m in re.findall(r"\$([A-Za-z_][\w]*)", i)
    )
    print("block_loop references:", dict(called.most_common()))


if __name__ == "__main__":
    main(sys.argv[1])
