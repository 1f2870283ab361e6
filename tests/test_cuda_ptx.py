"""Every CUDA kernel compiles for a real device: PTX for sm_90 (H100/H200), without a GPU.

numba's CUDA simulator runs device functions as Python, so it cannot tell whether the device
compiler accepts them (NumPy linear algebra, allocation, a CPU ``numba.njit`` dispatcher
called from a device function all fail on a real device only). ``numba.cuda.compile_ptx``
runs the real front end and NVVM, with no device needed; this test compiles each GPU driver
kernel (the on-off loop, the wheel simulator, the thruster closed-loop simulator) that way.

Needs numba-cuda (the ``gpu`` extra: numba's own deprecated ``numba.cuda`` cannot compile
``max(a, b)`` for the device in numba 0.68) and libNVVM / NVRTC / libdevice; skipped with the
reason when they are absent, failed when a kernel does not compile. Without a device, numba
asks the (absent) current device for its compute capability when it compiles a device
helper (``register_jitable``); the child answers sm_90, the target of the PTX. Runs in a
subprocess so that the test process keeps its own ``numba.cuda``.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

SRC = str(Path(__file__).resolve().parents[1] / "src")

_CHILD = textwrap.dedent(
    """
    import importlib.util
    import json
    import math
    import sys
    import time
    import types

    try:  # numba-cuda reached through PYTHONPATH instead of site-packages: its import hook
        import _numba_cuda_redirector  # noqa: F401
    except ImportError:
        pass

    def skip(why):
        print(json.dumps({"skip": why}))
        sys.exit(0)

    if importlib.util.find_spec("numba_cuda") is None:
        skip("numba-cuda (the gpu extra) is not installed")
    from numba import cuda
    from numba import types as t
    import numba.cuda.dispatcher as disp

    if not cuda.is_available():
        disp.get_current_device = lambda: types.SimpleNamespace(compute_capability=(9, 0))

    def probe(x):
        return math.sin(x) + max(x, 0.0)

    try:
        cuda.compile_ptx(probe, (t.float64,), device=True, cc=(9, 0))
    except Exception as exc:  # a missing libNVVM / NVRTC / libdevice: not a code error
        skip(f"the CUDA compiler toolchain is incomplete ({type(exc).__name__}: {str(exc)[:300]})")

    f1, f2, f3 = t.float64[::1], t.float64[:, ::1], t.float64[:, :, ::1]
    i8 = t.int64
    report = {}

    def compile_kernel(name, kernel, sig):
        t0 = time.perf_counter()
        ptx, _ = cuda.compile_ptx(kernel.py_func, sig, cc=(9, 0))
        assert ".target sm_90" in ptx, name
        report[name] = {"ptx_chars": len(ptx), "compile_s": round(time.perf_counter() - t0, 1)}

    from adcskit.control import _onoff_kernels as ok
    compile_kernel("onoff", ok._make_cuda_kernel(32), (f2, f1, i8, i8, i8, f3, f2))
    from adcskit.simulation import _wheel_kernels as wk
    compile_kernel("wheels", wk._make_cuda_kernel(), wk._cuda_signature())  # thruster unloading and MEKF too
    from adcskit.simulation import _kernels as sk
    compile_kernel("closed_loop", sk._make_cuda_kernel(), sk._cuda_signature())
    print(json.dumps(report))
    """
)


@pytest.mark.compile
def test_cuda_kernels_compile_to_ptx_for_sm90():
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [SRC] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
    env.pop("NUMBA_ENABLE_CUDASIM", None)
    proc = subprocess.run([sys.executable, "-c", _CHILD], env=env, capture_output=True, text=True, timeout=1800)
    assert proc.returncode == 0, proc.stderr[-4000:]
    result = json.loads(proc.stdout.strip().splitlines()[-1])
    if "skip" in result:
        pytest.skip(result["skip"])
    assert set(result) == {"onoff", "wheels", "closed_loop"}, result
    print(result)  # PTX size and compile time per kernel (shown with -s)
