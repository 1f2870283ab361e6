"""The CPU driver's lane blocks (:func:`adcskit.simulation._kernels.block_loop`) against the
per-sample loop that the GPU driver runs (:func:`~adcskit.simulation._kernels.sample_loop`,
here as plain Python): bit for bit, every branch.

The CPU driver advances :data:`~adcskit.simulation._kernels.LANES` samples together (their RK4
steps in one vectorised loop); the same operations in the same order per sample, so every
metric, on-time and trace value must equal the one-sample loop's bytes. 11 samples make one
full block and one partial block (3 lanes); a block mixing diagonal and full inertia matrices
takes the scalar RK4 path for every lane.
"""

from __future__ import annotations

import warnings

import numba
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

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
    SpacecraftSpec,
    ThrusterSpec,
    core,
)
from adcskit.simulation import (
    _kernels as K,
)
from adcskit.thrusters import S3_REFERENCE_A

pytestmark = [
    pytest.mark.compile,  # compiles the closed-loop kernel (cached)
    pytest.mark.filterwarnings("ignore::adcskit.errors.UncontrollableWarning"),  # failed thrusters
]

N = 11  # one full block of K.LANES = 8 and a partial block of 3
FULL_J = (1218.6, 35.0, -20.0, 35.0, 442.2, 12.0, -20.0, 12.0, 1429.4)  # kg m^2, off the principal axes


def _scenarios():
    """The branches of benchmarks/kernel_identity.py on a 1 s horizon (50 steps)."""
    disp = DispersionSpec(inertia_rel=0.05, thrust_rel=0.03, misalignment_deg=0.3, delay_std_s=0.005,
                          disturbance_rel=0.2, initial_attitude_deg=2.0, initial_rate_deg_s=0.05)
    sim = SimSpec(dt=0.02, t_final=1.0, metrics_from_s=0.3, nees_from_s=0.1, record_every=5)
    step = GuidanceSpec(kind="step", target_rotvec_deg=(3.0, -2.0, 10.0), t_step=0.1)
    lay = ThrusterSpec.from_torque_matrix(S3_REFERENCE_A)
    pwm = dict(kp=(60.0,) * 3, ki=(0.1,) * 3, kd=(300.0,) * 3)
    on = np.random.default_rng(5).integers(0, 3, size=(50, lay.n)) * 0.02
    fast = SensorSpec(sun_rate_hz=10.0, mag_rate_hz=10.0)
    return {
        "mekf_schmitt_step_disp": Scenario(
            estimator=EstimatorSpec(kind="mekf"), guidance=step, dispersions=disp, sim=sim, sensors=fast,
            disturbance=DisturbanceSpec(constant=(1e-4, -2e-4, 5e-5), amplitude=(1e-4, 1e-4, 1e-4),
                                        period_s=50.0)),
        "mekf_st_pwm_nnls_gg_fail": Scenario(
            estimator=EstimatorSpec(kind="mekf", underweight=0.0),
            sensors=SensorSpec(star_tracker_rate_hz=10.0, sun_rate_hz=10.0, noise="uniform"),
            controller=ControllerSpec(kind="pwm", allocation="nnls", **pwm),
            orbit=OrbitSpec(gravity_gradient=True, altitude_km=700.0), guidance=step, dispersions=disp,
            sim=sim, thrusters=lay.replace(failed=(2,))),
        "qmethod_pwm_pinv": Scenario(estimator=EstimatorSpec(kind="wahba", wahba_method="q-method"),
                                     controller=ControllerSpec(kind="pwm", min_on_time="round", **pwm),
                                     guidance=step, dispersions=disp, sim=sim, sensors=fast),
        "minmax_schmitt_unknown_fail": Scenario(
            estimator=EstimatorSpec(kind="minmax"), guidance=step, sim=sim, sensors=fast,
            thrusters=lay.replace(failed=(1,), failure_known=False)),
        "truth_openloop": Scenario(estimator=EstimatorSpec(kind="truth"), sim=sim,
                                   controller=ControllerSpec(kind="open-loop", on_times=tuple(map(tuple, on)))),
        "truth_pwm_fastlag_delay": Scenario(estimator=EstimatorSpec(kind="truth"), guidance=step, dispersions=disp,
                                            sim=sim, thrusters=lay.replace(tau=1e-6, delay=0.03),
                                            controller=ControllerSpec(kind="pwm", **pwm)),
        "mekf_fullJ_gg": Scenario(spacecraft=SpacecraftSpec(inertia=FULL_J), estimator=EstimatorSpec(kind="mekf"),
                                  orbit=OrbitSpec(gravity_gradient=True, altitude_km=700.0), guidance=step,
                                  dispersions=disp, sim=sim, sensors=fast),
    }


@pytest.fixture(autouse=True)
def one_thread():
    """One numba thread: the driver then makes blocks of K.LANES (8 + 3 for N = 11)."""
    before = numba.get_num_threads()
    numba.set_num_threads(1)
    yield
    numba.set_num_threads(before)


def _per_sample_python(A):
    """The one-sample loop (plain Python; its compiled helpers as compiled) over every sample."""
    with np.errstate(over="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # SplitMix64's uint64 wrap-around
        for i in range(A.P.shape[0]):
            K.SAMPLE.py(i, A)


def _both(prep, seeds, monkeypatch):
    task = core._Block(prep["shared"], prep["per_sample"], seeds, True)
    lanes = core._run_block(task)
    with monkeypatch.context() as m:
        m.setattr(K, "run_cpu", _per_sample_python)
        ref = core._run_block(task)
    return lanes, ref


def _assert_same(lanes, ref, what):
    for key in ("out", "tot", "rec"):
        assert lanes[key].tobytes() == ref[key].tobytes(), f"{what}: {key} differs"


@pytest.mark.parametrize("name", list(_scenarios()))
def test_lane_blocks_equal_the_per_sample_loop(name, monkeypatch):
    sc = _scenarios()[name]
    prep, _ = core._prepare(sc, N, np.random.default_rng(11))
    seeds = np.random.SeedSequence(3).generate_state(N, dtype=np.uint64)
    lanes, ref = _both(prep, seeds, monkeypatch)
    _assert_same(lanes, ref, name)
    assert np.isfinite(lanes["out"][:, K.M_RMS_ERR]).all()


def test_block_mixing_diagonal_and_full_inertia(monkeypatch):
    # samples 0, 2, 5 and 9 on their principal axes, the others not: both blocks take the
    # per-lane RK4 path (principal or general step per lane), the same numbers
    sc = _scenarios()["mekf_fullJ_gg"]
    prep, _ = core._prepare(sc, N, np.random.default_rng(12))
    P = prep["per_sample"]["P"]
    for i in (0, 2, 5, 9):
        J = np.diag(np.diag(P[i, K.P_J:K.P_J + 9].reshape(3, 3)))
        P[i, K.P_J:K.P_J + 9] = J.reshape(-1)
        P[i, K.P_JI:K.P_JI + 9] = np.linalg.inv(J).reshape(-1)
    seeds = np.random.SeedSequence(4).generate_state(N, dtype=np.uint64)
    lanes, ref = _both(prep, seeds, monkeypatch)
    _assert_same(lanes, ref, "mixed inertia")


def test_balanced_blocks_on_two_threads(monkeypatch):
    # 24 samples on 2 threads: 4 blocks of 6 (block_size), not 3 of 8; the same numbers
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("one numba thread on this machine")
    numba.set_num_threads(2)
    assert K.block_size(24, 2) == 6
    sc = _scenarios()["mekf_schmitt_step_disp"]
    prep, _ = core._prepare(sc, 24, np.random.default_rng(14))
    seeds = np.random.SeedSequence(6).generate_state(24, dtype=np.uint64)
    lanes, ref = _both(prep, seeds, monkeypatch)
    _assert_same(lanes, ref, "two threads")


def _busiest(n, size, threads):
    """Samples on the busiest thread: prange's contiguous runs of ceil(blocks / threads)."""
    blocks = -(-n // size)  # ceil(n / size)
    return min(n, -(-blocks // threads) * size)


@settings(max_examples=300, deadline=None)
@given(n=st.integers(0, 5000), threads=st.integers(1, 64))
def test_block_size_balances_the_threads(n, threads):
    size = K.block_size(n, threads)
    assert 1 <= size <= K.LANES
    if n == 0 or threads == 1:
        assert size == (1 if n == 0 else K.LANES)
        return
    load = _busiest(n, size, threads)
    best = min(_busiest(n, s, threads) for s in range(1, K.LANES + 1))
    if size == K.LANES:  # full blocks: within 5/4 of an even share, or nothing does better
        assert 4 * load * threads <= 5 * n or load == best
    else:  # smaller blocks: the least loaded busiest thread there is
        assert load == best


def test_block_size_examples():
    # the docstring's cases: 64 samples on 16 threads, 24 on 2; a campaign's chunks on 2
    assert K.block_size(64, 16) == 4
    assert K.block_size(24, 2) == 6
    assert K.block_size(64, 2) == K.LANES
    assert K.block_size(125_000, 2) == K.LANES
    assert K.block_size(11, 1) == K.LANES


def test_single_sample_and_exact_blocks(monkeypatch):
    # one lane, and exactly two full blocks
    sc = _scenarios()["truth_pwm_fastlag_delay"]
    for n in (1, 2 * K.LANES):
        prep, _ = core._prepare(sc, n, np.random.default_rng(13))
        seeds = np.random.SeedSequence(5).generate_state(n, dtype=np.uint64)
        lanes, ref = _both(prep, seeds, monkeypatch)
        _assert_same(lanes, ref, f"n={n}")


def test_lane_slots_are_consecutive_and_validated():
    from adcskit._targets import lane_slots
    from adcskit.errors import InputError

    slots, width = lane_slots("S", a=3, b=1, c=2)
    assert (slots.a, slots.b, slots.c, width) == (0, 3, 4, 6)
    assert (K.N_FS, K.N_IS) == (36, 6)  # the block rows' widths of the kernel's declared slots
    with pytest.raises(InputError, match="width of b"):
        lane_slots("S", a=3, b=0)
