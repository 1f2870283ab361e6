"""The closed-loop (thruster) simulator's CUDA target: simulator agreement with the CPU kernel,
backend choice and errors, and real-device agreement (skipped without a GPU).

The GPU driver (:func:`adcskit.simulation._kernels.run_cuda`) compiles the same per-sample
source as the CPU driver, with the CPU-only dispatchers (MEKF steps, gyro model) rebound to
device compilations of their own sources. numba's CUDA simulator runs the device function as
Python, without fused multiply-adds, so under the simulator the GPU driver must reproduce the
CPU kernel bit for bit. The simulator is switched on by an environment variable read when
numba is imported, hence the subprocess (which runs the GPU driver only; the CPU reference
runs here, from numba's disk cache).
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
from adcskit.simulation import (
    ControllerSpec,
    DispersionSpec,
    DisturbanceSpec,
    EstimatorSpec,
    GuidanceSpec,
    OrbitSpec,
    Scenario,
    SensorSpec,
    SimSpec,
    ThrusterSpec,
    simulate,
)
from adcskit.thrusters import S3_REFERENCE_A

SRC = str(Path(__file__).resolve().parents[2] / "src")

pytestmark = [
    pytest.mark.compile,  # the CPU reference compiles the closed-loop kernel (cached)
    pytest.mark.filterwarnings("ignore::adcskit.errors.UncontrollableWarning"),  # a failed thruster
]


def _scenarios(t_final):
    """Every branch the GPU runs: MEKF (sun + magnetometer, star tracker), truth; Schmitt,
    PWM with the redistributed pseudo-inverse and with NNLS (BVLS), open loop; dispersions,
    delay, disturbances, gravity gradient, a known failure (the branches of
    benchmarks/kernel_identity.py without the Wahba / min-max estimators)."""
    disp = DispersionSpec(inertia_rel=0.05, thrust_rel=0.03, misalignment_deg=0.3, delay_std_s=0.005,
                          disturbance_rel=0.2, initial_attitude_deg=2.0, initial_rate_deg_s=0.05)
    sim = SimSpec(dt=0.02, t_final=t_final, metrics_from_s=0.2, nees_from_s=0.1, record_every=5)
    step = GuidanceSpec(kind="step", target_rotvec_deg=(3.0, -2.0, 10.0), t_step=0.1)
    lay = ThrusterSpec.from_torque_matrix(S3_REFERENCE_A)
    pwm = dict(kp=(60.0,) * 3, ki=(0.1,) * 3, kd=(300.0,) * 3)
    on = np.random.default_rng(5).integers(0, 3, size=(20, lay.n)) * 0.02
    return {
        "mekf_schmitt_step_disp": Scenario(
            estimator=EstimatorSpec(kind="mekf"), guidance=step, dispersions=disp, sim=sim,
            disturbance=DisturbanceSpec(constant=(1e-4, -2e-4, 5e-5), amplitude=(1e-4, 1e-4, 1e-4),
                                        period_s=50.0)),
        "mekf_st_pwm_nnls_gg": Scenario(
            estimator=EstimatorSpec(kind="mekf", underweight=0.0),
            sensors=SensorSpec(star_tracker_rate_hz=10.0, sun_rate_hz=10.0, noise="uniform"),
            controller=ControllerSpec(kind="pwm", allocation="nnls", **pwm),
            orbit=OrbitSpec(gravity_gradient=True, altitude_km=700.0), guidance=step, dispersions=disp,
            sim=sim, thrusters=lay.replace(failed=(2,))),
        "truth_pwm_pinv": Scenario(estimator=EstimatorSpec(kind="truth"), guidance=step, dispersions=disp,
                                   sim=sim, controller=ControllerSpec(kind="pwm", **pwm)),
        "truth_openloop": Scenario(estimator=EstimatorSpec(kind="truth"), sim=sim,
                                   controller=ControllerSpec(kind="open-loop", on_times=tuple(map(tuple, on)))),
    }


def _arrays(res):
    return {"metrics": np.column_stack([res.metrics[m] for m in sorted(res.metrics)]),
            "tot": res.on_time_per_thruster, "trace": res.trace}


_CHILD = textwrap.dedent(
    """
    import sys
    import numpy as np
    from adcskit import _targets
    from adcskit.simulation import _kernels as k, simulate
    sys.path.insert(0, sys.argv[3])
    from test_simulate_cuda import _arrays, _scenarios

    assert _targets.simulator_enabled()
    n, t_final = int(sys.argv[2]), float(sys.argv[4])
    out = {}
    for name, sc in _scenarios(t_final).items():
        res = simulate(sc, n_samples=n, rng=7, record=True, backend="cuda")
        assert res.backend == "cuda", res.backend
        for key, a in _arrays(res).items():
            out[f"{name}/{key}"] = a
    k.CUDA_CHUNK = 2  # device chunks of 2 samples, the last one partial: the same numbers
    res = simulate(_scenarios(t_final)["truth_pwm_pinv"], n_samples=n, rng=7, record=True, backend="cuda")
    for key, a in _arrays(res).items():
        out[f"chunked/{key}"] = a
    np.savez(sys.argv[1], **out)
    """
)


def _compare(tmp_path, n, t_final):
    pytest.importorskip("numba.cuda", reason="no numba CUDA target (simulator) installed")
    out = tmp_path / "sim.npz"
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1", PYTHONPATH=SRC)
    here = str(Path(__file__).resolve().parent)
    proc = subprocess.run([sys.executable, "-c", _CHILD, str(out), str(n), here, str(t_final)], env=env,
                          capture_output=True, text=True, timeout=1800)
    assert proc.returncode == 0, proc.stderr[-3000:]
    gpu = np.load(out)
    fired = 0.0
    for name, sc in _scenarios(t_final).items():
        cpu = simulate(sc, n_samples=n, rng=7, record=True)
        assert cpu.backend == "cpu"
        for key, a in _arrays(cpu).items():
            # bit for bit (NaN == NaN): same source, same operation order, no FMA in the simulator
            np.testing.assert_array_equal(gpu[f"{name}/{key}"], a, err_msg=f"{name}/{key}")
            if name == "truth_pwm_pinv":
                np.testing.assert_array_equal(gpu[f"chunked/{key}"], a, err_msg=f"chunked/{key}")
        fired += float(np.sum(cpu.on_time_per_thruster))
    assert fired > 0.0  # thrusters fired: the comparison covers the actuator path


def test_cuda_driver_under_simulator_equals_cpu_kernel(tmp_path):
    # 3 samples x 0.4 s at dt = 0.02 s (20 steps): the simulator runs the loop as Python
    _compare(tmp_path, 3, 0.4)


@pytest.mark.slow
def test_cuda_driver_under_simulator_equals_cpu_kernel_long(tmp_path):
    _compare(tmp_path, 6, 4.0)


def test_cuda_refuses_estimators_with_cpu_only_solvers():
    # checked before the device: the same error on every machine
    for kind in ("wahba", "minmax"):
        with pytest.raises(InputError, match=rf"estimator.kind='{kind}'.*allowed with backend='cuda': 'truth', 'mekf'"):
            simulate(Scenario(estimator=EstimatorSpec(kind=kind)), backend="cuda")


def test_auto_runs_cpu_for_cpu_only_estimators_and_without_a_device(monkeypatch):
    sc = Scenario(estimator=EstimatorSpec(kind="wahba"), sim=SimSpec(dt=0.02, t_final=0.2, metrics_from_s=0.1))
    assert simulate(sc, n_samples=2, rng=0, backend="auto").backend == "cpu"
    monkeypatch.setattr(_targets, "cuda_status", lambda: (False, "no CUDA device is visible"))
    sc = Scenario(sim=SimSpec(dt=0.02, t_final=0.2, metrics_from_s=0.1))
    auto = simulate(sc, n_samples=2, rng=0, backend="auto")
    assert auto.backend == "cpu"
    np.testing.assert_array_equal(auto.metrics["pointing_rms_deg"], simulate(sc, n_samples=2, rng=0).metrics["pointing_rms_deg"])


def test_explicit_cuda_without_device_names_the_extra(monkeypatch):
    monkeypatch.setattr(_targets, "cuda_status", lambda: (False, "no CUDA device is visible"))
    with pytest.raises(SolverError, match=r"adcskit\[gpu\].*backend='cpu'"):
        simulate(Scenario(), backend="cuda")


def test_backend_name_is_validated():
    with pytest.raises(InputError, match="backend must be one of 'cpu', 'cuda', 'auto'; got 'gpu'"):
        simulate(Scenario(), backend="gpu")


needs_gpu = pytest.mark.skipif(not _targets.cuda_usable(), reason="no CUDA device visible")


@needs_gpu
def test_real_gpu_matches_cpu_kernel():
    # FMA contraction on the GPU: a rounding difference can move a Schmitt switch, after which
    # a sample's limit cycle differs, so the comparison is statistical (docs/architecture.md "seeded
    # statistical bounds"): over the same 4096 samples (same parameters and noise seeds) the
    # mean pointing RMS and propellant agree within 4 standard errors of the difference of
    # two means (a bound that holds even if every sample decorrelated); the fraction of
    # samples with the same firings is reported by benchmarks/bench_simulators_gpu.py
    sc = Scenario(sim=SimSpec(dt=0.02, t_final=20.0, metrics_from_s=10.0),
                  dispersions=DispersionSpec(inertia_rel=0.05, thrust_rel=0.03))
    n = 4096
    gpu = simulate(sc, n_samples=n, rng=4, backend="cuda")
    cpu = simulate(sc, n_samples=n, rng=4, backend="cpu")
    assert gpu.backend == "cuda" and gpu.success, gpu.message
    for m in ("pointing_rms_deg", "propellant_kg"):
        g, c = gpu.metrics[m], cpu.metrics[m]
        se = np.sqrt((np.var(g, ddof=1) + np.var(c, ddof=1)) / n)
        assert abs(np.mean(g) - np.mean(c)) <= 4.0 * se + 1e-12 * abs(np.mean(c)), (m, np.mean(g), np.mean(c), se)


def _cpu_twice(x):
    return 2.0 * x


def _device_twice(x):
    return x + x


def _per_sample_uses_twice(i, x, out):
    out[i] = _cpu_twice(x[i])


def test_per_sample_device_names_rebind_only_the_cuda_source():
    from adcskit._targets import PerSample

    ps = PerSample(_per_sample_uses_twice, cache=False, device_names={"_cpu_twice": _device_twice})
    dev = ps.device_source()
    assert dev is not _per_sample_uses_twice and dev.__code__ is _per_sample_uses_twice.__code__
    assert dev.__globals__["_cpu_twice"] is _device_twice
    assert globals()["_cpu_twice"] is _cpu_twice  # the module's own globals are untouched
    out = np.zeros(1)
    dev(0, np.array([1.5]), out)
    assert out[0] == 3.0
    with pytest.raises(InputError, match="device_names must name globals"):
        PerSample(_per_sample_uses_twice, cache=False, device_names={"not_used": _device_twice})
