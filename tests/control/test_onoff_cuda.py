"""The on-off kernel's CUDA target: simulator agreement (every machine), backend choice and
errors, and real-device agreement (skipped without a GPU).

The CUDA kernel compiles the same per-sample source as the CPU kernel (adcskit._targets).
numba's CUDA simulator runs that device function as Python, without fused multiply-adds,
so under the simulator the GPU driver (threads, blocks, chunks, local-memory delay line)
must reproduce the CPU kernel bit for bit. The simulator is switched on by an environment
variable read when numba is imported, hence the subprocess.
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
from adcskit.control import LoopParams, LoopSettings, simulate_batch
from adcskit.errors import InputError, SolverError

SRC = str(Path(__file__).resolve().parents[2] / "src")

_CHILD = textwrap.dedent(
    """
    import sys
    import numpy as np
    from adcskit import _targets
    from adcskit.control import LoopParams, LoopSettings, simulate_batch, simulate_trace
    from adcskit.control import _onoff_kernels as k
    from adcskit.control.onoff import _buffer_length, _coefficients, _param_matrix

    assert _targets.simulator_enabled()
    assert _targets.resolve_backend("auto") == "cpu"  # auto never picks the simulator
    rng = np.random.default_rng(11)
    n = 7  # not a multiple of the chunk: the last chunk is partial
    p = LoopParams(
        kp=rng.uniform(5, 80, n), ki=rng.uniform(0, 1, n), kd=rng.uniform(5, 80, n),
        u_on=rng.uniform(0.05, 0.3, n), off_ratio=rng.uniform(0.2, 1.0, n),
        delay=rng.uniform(0, 0.045, n), disturbance=rng.normal(0.05, 0.05, n),
        disturbance_amp=np.r_[0.0, rng.uniform(0, 0.05, n - 1)],
        disturbance_freq_hz=rng.uniform(0, 2, n), theta_ref=rng.uniform(-0.5, 0.5, n),
    )
    s = LoopSettings(t_final=1.2, t_window=0.4, command_rate_hz=200.0)
    gpu = simulate_batch(p, s, backend="cuda")
    cpu = simulate_batch(p, s, backend="cpu")
    assert gpu.backend == "cuda" and cpu.backend == "numba"
    P, C = _param_matrix(p), _coefficients(s)
    L = _buffer_length(P, s.dt)
    chunked = k.simulate_cuda(P, C, s.n_steps, s.hold_steps, s.n_window, L,
                              np.empty((0, 0, k.N_TRACE)), chunk=3)
    tr_gpu = simulate_trace(LoopParams(delay=0.0125), s, backend="cuda")
    tr_cpu = simulate_trace(LoopParams(delay=0.0125), s, backend="cpu")
    np.savez(sys.argv[1], gpu=gpu.as_array(), cpu=cpu.as_array(), chunked=chunked,
             tr_gpu=np.c_[tr_gpu.theta, tr_gpu.thrust_torque, tr_gpu.command],
             tr_cpu=np.c_[tr_cpu.theta, tr_cpu.thrust_torque, tr_cpu.command])
    """
)


def test_cuda_kernel_under_simulator_equals_cpu_kernel(tmp_path):
    # numba's built-in CUDA target (with its simulator) or numba-cuda must be importable
    pytest.importorskip("numba.cuda", reason="no numba CUDA target (simulator) installed")
    out = tmp_path / "sim.npz"
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1", PYTHONPATH=SRC)
    proc = subprocess.run(
        [sys.executable, "-c", _CHILD, str(out)], env=env, capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    r = np.load(out)
    # bit for bit: same source, same operation order, no FMA in the simulator
    np.testing.assert_array_equal(r["gpu"], r["cpu"])
    np.testing.assert_array_equal(r["chunked"], r["cpu"])
    np.testing.assert_array_equal(r["tr_gpu"], r["tr_cpu"])
    assert np.all(r["cpu"][:, 4] >= 1)  # every sample fired: the comparison covers switching


def test_auto_falls_back_to_cpu_without_a_device(monkeypatch):
    monkeypatch.setattr(_targets, "cuda_status", lambda: (False, "no CUDA device is visible"))
    p = LoopParams(kp=[20.0, 56.24])
    s = LoopSettings(t_final=2.0, t_window=1.0)
    auto = simulate_batch(p, s, backend="auto")
    assert auto.backend == "numba"
    np.testing.assert_array_equal(auto.as_array(), simulate_batch(p, s, backend="cpu").as_array())


def test_explicit_cuda_without_device_names_the_extra(monkeypatch):
    monkeypatch.setattr(_targets, "cuda_status", lambda: (False, "no CUDA device is visible"))
    with pytest.raises(SolverError, match=r"adcskit\[gpu\].*backend='cpu'"):
        simulate_batch(backend="cuda")


def test_explicit_cuda_without_numba_cuda_names_the_extra(monkeypatch):
    def missing():
        raise SolverError("backend='cuda' needs numba's CUDA target, which failed to import "
                          f"(ImportError: no module); {_targets.GPU_EXTRA_HINT}")

    monkeypatch.setattr(_targets, "import_cuda", missing)
    ok, why = _targets.cuda_status()
    assert not ok and "adcskit[gpu]" in why
    with pytest.raises(SolverError, match=r"adcskit\[gpu\]"):
        simulate_batch(backend="cuda")
    assert _targets.resolve_backend("auto") == "cpu"


def test_backend_names_are_validated():
    with pytest.raises(InputError, match="backend"):
        _targets.resolve_backend("gpu")
    with pytest.raises(InputError, match="backend"):
        simulate_batch(backend="opencl")


needs_gpu = pytest.mark.skipif(not _targets.cuda_usable(), reason="no CUDA device visible")


@needs_gpu
def test_real_gpu_matches_cpu_kernel():
    # FMA contraction on the GPU: identical firings, continuous metrics within 1e-9 relative
    rng = np.random.default_rng(5)
    n = 4096
    p = LoopParams(kp=rng.uniform(5, 80, n), ki=rng.uniform(0, 1, n), kd=rng.uniform(5, 80, n),
                   delay=rng.uniform(0, 0.05, n), inertia=rng.uniform(5, 15, n))
    s = LoopSettings(t_final=30.0)
    gpu = simulate_batch(p, s, backend="cuda").as_array()
    cpu = simulate_batch(p, s, backend="cpu").as_array()
    np.testing.assert_array_equal(gpu[:, 4], cpu[:, 4])
    np.testing.assert_allclose(gpu, cpu, rtol=1e-9, atol=1e-12)


@needs_gpu
@pytest.mark.slow
def test_real_gpu_ten_million_samples_in_chunks():
    n = 10_000_000
    s = LoopSettings(t_final=0.2, t_window=0.1)
    m = simulate_batch(LoopParams(kp=np.linspace(1.0, 100.0, n)), s, backend="cuda")
    ref = simulate_batch(LoopParams(kp=np.linspace(1.0, 100.0, n)[::100_000]), s, backend="cpu")
    np.testing.assert_allclose(m.as_array()[::100_000], ref.as_array(), rtol=1e-9, atol=1e-12)
