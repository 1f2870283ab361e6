"""Every batched kernel is cached between processes (issue 41, "Cache and feedback").

A child process runs the thruster closed loop (every estimator kind: one kernel signature), the
wheel / magnetorquer loop (MEKF and thruster unloading on: the largest signature) and the on-off
loop (lane blocks, traces, serial), then reports numba's compile statistics of every dispatcher
in ``adcskit``. The child runs twice: the first run fills numba's disk cache (or finds it full),
the second must compile nothing (``dispatcher.stats.cache_misses`` empty for every dispatcher:
each signature it used came from the disk cache, or was linked into a cached caller), and
neither may print a numba warning (the regression of issue 41: ``run_parallel`` referenced a
ctypes function pointer, numba's ``get_num_threads``, and was recompiled in every process with
"Cannot cache compiled function ... uses dynamic globals" printed into the user's script).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

SRC = str(Path(__file__).resolve().parents[2] / "src")

_CHILD = textwrap.dedent(
    """
    import json
    import sys
    import warnings

    import numba
    from numba.core.dispatcher import Dispatcher

    from adcskit.control import LoopSettings, simulate_batch, simulate_trace
    from adcskit.simulation import (
        EstimatorSpec, Scenario, SimSpec, ThrusterSpec, ThrusterUnloadSpec, WheelScenario,
        simulate, simulate_wheels,
    )
    from adcskit.thrusters import S3_REFERENCE_A

    warnings.simplefilter("ignore", UserWarning)  # adcskit's own (e.g. uncontrollable layouts)
    sim = SimSpec(dt=0.05, t_final=1.0, metrics_from_s=0.5)
    for kind in ("truth", "mekf", "wahba", "minmax"):
        simulate(Scenario(estimator=EstimatorSpec(kind=kind), sim=sim), 3, rng=1, record=kind == "mekf")
    lay = ThrusterSpec.from_torque_matrix(S3_REFERENCE_A)
    wsc = WheelScenario(sim=SimSpec(dt=0.2, t_final=20.0, metrics_from_s=10.0),
                        estimator=EstimatorSpec(kind="mekf"),
                        thruster_unloading=ThrusterUnloadSpec(thrusters=lay))
    simulate_wheels(wsc, 2, rng=1, record=True)
    settings = LoopSettings(t_final=2.0, t_window=1.0)
    simulate_batch(settings=settings)
    simulate_batch(settings=settings, parallel=False)
    simulate_trace(settings=settings)

    report = {}
    for name, mod in list(sys.modules.items()):
        if not name.startswith("adcskit"):
            continue
        for attr, obj in list(vars(mod).items()):
            if isinstance(obj, Dispatcher) and obj.signatures:
                st = obj.stats
                report[f"{name}.{attr}"] = {"misses": sum(st.cache_misses.values()),
                                            "hits": sum(st.cache_hits.values()),
                                            "cached": obj._cache.__class__.__name__ != "NullCache"}
    print(json.dumps(report))
    """
)


def _child() -> tuple[dict, str]:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [SRC] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
    env.pop("NUMBA_ENABLE_CUDASIM", None)
    env.pop("NUMBA_DISABLE_JIT", None)
    proc = subprocess.run([sys.executable, "-c", _CHILD], env=env, capture_output=True, text=True,
                          timeout=1800)
    assert proc.returncode == 0, proc.stderr[-4000:]
    return json.loads(proc.stdout.strip().splitlines()[-1]), proc.stderr


@pytest.mark.compile
def test_second_process_compiles_no_kernel():
    first, err1 = _child()  # fills the disk cache (compiles on a cold one)
    assert "NumbaWarning" not in err1, err1[-4000:]
    second, err2 = _child()
    assert "NumbaWarning" not in err2, err2[-4000:]
    # the kernels the workload must have reached (directly, or linked into their cached callers)
    for name in ("adcskit.simulation._kernels.run_parallel", "adcskit.simulation._wheel_kernels.run_block",
                 "adcskit.control._onoff_kernels.simulate_parallel",
                 "adcskit.control._onoff_kernels.simulate_serial"):
        assert name in second, sorted(second)
        assert second[name]["hits"] >= 1, (name, second[name])
    compiled = {k: v for k, v in second.items() if v["misses"] or not v["cached"]}
    assert not compiled, compiled
