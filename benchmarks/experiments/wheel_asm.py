"""Assembly of the wheel kernel's block driver, per function: for kernel rewrites.

Compiles the wheel kernel (``wheel_rates.py``'s reference scenario, 2 short samples), writes the
assembly of the module of :func:`adcskit.simulation._wheel_kernels.run_block` (numba's
``inspect_asm``: the driver, ``wheel_sample`` and the device helpers it calls out of line) and
prints, per function, the instruction count, the calls, the double spills and reloads
(``kernel_asm.py``'s counts) and the reference-count calls (``NRT_incref`` / ``NRT_decref``:
an atomic instruction each), then the functions that each one calls. Needs a cold
compilation (a kernel loaded from the disk cache has no assembly)::

    NUMBA_CACHE_DIR=$(mktemp -d) PYTHONPATH=src python benchmarks/experiments/wheel_asm.py /tmp/w.s
"""

import collections
import os
import re
import sys
import warnings

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # benchmarks/
from kernel_asm import _RELOAD, _SPILL, functions  # noqa: E402

from adcskit.simulation import SimSpec, WheelScenario, simulate_wheels  # noqa: E402
from adcskit.simulation import _wheel_kernels as _k  # noqa: E402


def _short(name):
    return re.sub(r"B\d+v\d+.*", "", name).split("_kernels")[-1].split("_device")[-1]


def main(path):
    warnings.simplefilter("ignore")
    simulate_wheels(WheelScenario(sim=SimSpec(dt=0.2, t_final=2.0, metrics_from_s=1.0)), 2, rng=0)
    f = _k.run_block
    asm = f.inspect_asm(f.signatures[0])
    with open(path, "w") as fh:
        fh.write(asm)
    for name, ins in functions(asm).items():
        if not ins or name.startswith(("_ZN7cpython", "cfunc")):
            continue
        targets = collections.Counter()
        reg = {}
        for i in ins:  # numba calls through a register loaded with movabsq $symbol
            m = re.match(r"movabsq\s+\$([A-Za-z_][\w]*), (%\w+)", i)
            if m:
                reg[m.group(2)] = m.group(1)
            m = re.match(r"callq\s+\*(%\w+)", i)
            if m:
                targets[_short(reg.get(m.group(1), "?"))] += 1
        spill = sum(bool(_SPILL.match(i)) for i in ins)
        reload = sum(bool(_RELOAD.match(i)) for i in ins)
        nrt = targets.get("NRT_incref", 0) + targets.get("NRT_decref", 0)
        print(f"{len(ins):6d} ins {sum(targets.values()):4d} calls {nrt:3d} NRT {spill:4d} spills {reload:4d} reloads  "
              f"{_short(name)}")
        if targets:
            print("        calls:", dict(targets.most_common()))


if __name__ == "__main__":
    main(sys.argv[1])
