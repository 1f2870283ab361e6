"""The wheel simulator's CUDA target: simulator agreement (every machine), backend choice and
errors, and real-device agreement (skipped without a GPU).

The GPU driver (:func:`adcskit.simulation._wheel_kernels.run_wheels_cuda`) compiles the same
per-sample source as the CPU driver (``adcskit._targets``). numba's CUDA simulator runs that
device function as Python, without fused multiply-adds, so under the simulator the GPU driver
(threads, blocks, chunks, scratch rows) must reproduce the CPU kernel bit for bit. The
simulator is switched on by an environment variable read when numba is imported, hence the
subprocess.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from adcskit import _targets
from adcskit.errors import InputError, SolverError
from adcskit.simulation import ModeSpec, SimSpec, WheelScenario, simulate_wheels

SRC = str(Path(__file__).resolve().parents[2] / "src")

_CHILD = textwrap.dedent(
    """
    import sys
    import numpy as np
    from adcskit import _targets
    from adcskit.simulation import (EstimatorSpec, ModeSpec, SimSpec, ThrusterSpec, ThrusterUnloadSpec,
                                    WheelControlSpec, WheelScenario, WheelSpec, simulate_wheels)
    from adcskit.simulation import _wheel_kernels as k

    assert _targets.simulator_enabled()
    n, t_final = int(sys.argv[2]), float(sys.argv[3])
    out = {}
    # pointing with the default PD law (star tracker + gyro), and the full mode sequence
    # (B-dot detumbling with magnetometer noise, sun acquisition, pointing)
    cases = {
        "point": WheelScenario(modes=ModeSpec(initial="point", sequence=False),
                               sim=SimSpec(dt=0.1, t_final=t_final, metrics_from_s=1.0, record_every=5)),
        "sequence": WheelScenario(modes=ModeSpec(initial="detumble", sequence=True),
                                  sim=SimSpec(dt=0.1, t_final=t_final, metrics_from_s=1.0, record_every=5)),
    }
    # thruster unloading (12 x 10 mN in +- pairs, from wheels above the start threshold) with the
    # MEKF in the loop: the per-sample thruster table and the filter's scratch rows
    pos = ((0.1, 0, 0), (-0.1, 0, 0), (0, 0.1, 0), (0, -0.1, 0), (0, 0, 0.15), (0, 0, -0.15))
    dirs = ((0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1), (1, 0, 0), (-1, 0, 0))
    jets = ThrusterSpec(positions=pos + pos, directions=dirs + tuple((-a, -b, -c) for a, b, c in dirs),
                        f_max=0.01, mdot=1.4e-5, t_min=0.01)
    cases["unload_mekf"] = WheelScenario(
        modes=ModeSpec(initial="point", sequence=False),
        wheels=WheelSpec.pyramid(initial_speed_rpm=(3000.0, 3000.0, 2000.0, 3500.0)),
        control=WheelControlSpec(law="pd", bandwidth_rad_s=0.2, damping=1.0),
        thruster_unloading=ThrusterUnloadSpec(thrusters=jets, start_nms=0.01, stop_nms=0.002, torque_nm=5e-4),
        estimator=EstimatorSpec(kind="mekf", init_error_deg=0.1),
        sim=SimSpec(dt=0.1, t_final=t_final, metrics_from_s=1.0, record_every=5))
    for name, sc in cases.items():
        gpu = simulate_wheels(sc, n_samples=n, rng=3, record=True, backend="cuda")
        cpu = simulate_wheels(sc, n_samples=n, rng=3, record=True, backend="cpu")
        assert gpu.backend == "cuda" and cpu.backend == "cpu"
        out[name + "_gpu"] = np.column_stack([gpu.metrics[m] for m in sorted(gpu.metrics)])
        out[name + "_cpu"] = np.column_stack([cpu.metrics[m] for m in sorted(cpu.metrics)])
        out[name + "_tr_gpu"] = gpu.trace
        out[name + "_tr_cpu"] = cpu.trace
    # chunks of 2 samples (the last one partial): the same numbers
    k.CUDA_CHUNK = 2
    chunked = simulate_wheels(cases["point"], n_samples=n, rng=3, backend="cuda")
    out["chunked"] = np.column_stack([chunked.metrics[m] for m in sorted(chunked.metrics)])
    np.savez(sys.argv[1], **out)
    """
)


def _run_child(tmp_path, n, t_final):
    pytest.importorskip("numba.cuda", reason="no numba CUDA target (simulator) installed")
    out = tmp_path / "sim.npz"
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1", PYTHONPATH=SRC)
    proc = subprocess.run([sys.executable, "-c", _CHILD, str(out), str(n), str(t_final)], env=env,
                          capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return np.load(out)


def _assert_identical(r):
    # bit for bit: same source, same operation order, no FMA in the simulator (NaN == NaN)
    for name in ("point", "sequence", "unload_mekf"):
        np.testing.assert_array_equal(r[name + "_gpu"], r[name + "_cpu"])
        np.testing.assert_array_equal(r[name + "_tr_gpu"], r[name + "_tr_cpu"])
    np.testing.assert_array_equal(r["chunked"], r["point_cpu"])


def test_cuda_driver_under_simulator_equals_cpu_driver(tmp_path):
    # 3 samples x 3 s at dt = 0.1 s (30 steps): the simulator runs the device function as
    # Python, about 1e3 sample-steps/s
    r = _run_child(tmp_path, 3, 3.0)
    _assert_identical(r)
    assert np.all(np.isfinite(r["point_tr_cpu"][:, :, 1:4]))  # body rates recorded on every sample


@pytest.mark.slow
def test_cuda_driver_under_simulator_equals_cpu_driver_long(tmp_path):
    # long enough for the sequence to leave detumbling on some samples (mode switches compared)
    r = _run_child(tmp_path, 5, 60.0)
    _assert_identical(r)


def test_auto_falls_back_to_cpu_without_a_device(monkeypatch):
    monkeypatch.setattr(_targets, "cuda_status", lambda: (False, "no CUDA device is visible"))
    sc = WheelScenario(modes=ModeSpec(initial="point", sequence=False),
                       sim=SimSpec(dt=0.1, t_final=1.0, metrics_from_s=0.5))
    auto = simulate_wheels(sc, n_samples=2, rng=0, backend="auto")
    cpu = simulate_wheels(sc, n_samples=2, rng=0)
    assert auto.backend == "cpu"
    for m in auto.metrics:
        np.testing.assert_array_equal(auto.metrics[m], cpu.metrics[m])


def test_explicit_cuda_without_device_names_the_extra(monkeypatch):
    monkeypatch.setattr(_targets, "cuda_status", lambda: (False, "no CUDA device is visible"))
    with pytest.raises(SolverError, match=r"adcskit\[gpu\].*backend='cpu'"):
        simulate_wheels(WheelScenario(), backend="cuda")


def test_backend_name_is_validated():
    with pytest.raises(InputError, match="backend must be one of 'cpu', 'cuda', 'auto'; got 'gpu'"):
        simulate_wheels(WheelScenario(), backend="gpu")


needs_gpu = pytest.mark.skipif(not _targets.cuda_usable(), reason="no CUDA device visible")


@needs_gpu
def test_real_gpu_matches_cpu_driver():
    # FMA contraction on the GPU, and the torque quantisation of the wheel electronics can move
    # a level on a rounding difference, so the comparison is statistical (docs/architecture.md "seeded
    # statistical bounds"): over the same 512 samples (same parameters and noise seeds) the
    # metric means agree within 4 standard errors of the difference of two means, and every
    # sample ends in the same mode
    sc = WheelScenario(modes=ModeSpec(initial="point", sequence=False),
                       sim=SimSpec(dt=0.1, t_final=60.0, metrics_from_s=30.0))
    n = 512
    gpu = simulate_wheels(sc, n_samples=n, rng=2, backend="cuda")
    cpu = simulate_wheels(sc, n_samples=n, rng=2, backend="cpu")
    assert gpu.backend == "cuda" and gpu.success, gpu.message
    np.testing.assert_array_equal(gpu.metrics["final_mode"], cpu.metrics["final_mode"])
    for m in ("pointing_rms_deg", "final_rate_deg_s", "max_wheel_momentum_nms"):
        g, c = gpu.metrics[m], cpu.metrics[m]
        se = np.sqrt((np.var(g, ddof=1) + np.var(c, ddof=1)) / n)
        assert abs(np.mean(g) - np.mean(c)) <= 4.0 * se + 1e-12 * abs(np.mean(c)), (m, np.mean(g), np.mean(c), se)
