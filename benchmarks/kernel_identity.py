"""Bit-identity check of the closed-loop kernel over every branch (for kernel rewrites).

12 scenarios x traces on/off: q-method, QUEST, min-max and MEKF estimators, star tracker,
uniform noise, Schmitt / PWM / open-loop control, pseudo-inverse and NNLS allocation, hold,
step and slew-table guidance, gravity gradient, dispersions, known and unknown failures,
diagonal and full inertia matrices (the two paths of the RK4 step), fast thruster lags
(lag states exactly zero between pulses) with and without a delay.
Save the metrics, on-times and traces before a change, compare after (np.array_equal,
NaN-aware, and bytewise)::

    PYTHONPATH=src python benchmarks/kernel_identity.py save /tmp/base.npz
    PYTHONPATH=src python benchmarks/kernel_identity.py compare /tmp/base.npz
"""

import math
import sys
import time

import numpy as np

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
    simulate,
)
from adcskit.simulation.profiles import table_from_angle
from adcskit.thrusters import S3_REFERENCE_A

disp = DispersionSpec(
    inertia_rel=0.05,
    thrust_rel=0.03,
    misalignment_deg=0.3,
    delay_std_s=0.005,
    disturbance_rel=0.2,
    initial_attitude_deg=2.0,
    initial_rate_deg_s=0.05,
)
#: samples per chunk: 12 samples run as chunks of 10 and 2, i.e. (on one numba thread, set in
#: run()) lane blocks (``_kernels.LANES`` = 8) of 8, 2 and 2 samples: a full block, whose RK4
#: steps run vectorised, and partial ones (the outputs do not depend on the split: each
#: sample's noise comes from its own seed)
CHUNK = 10
sim = SimSpec(dt=0.02, t_final=30.0, metrics_from_s=10.0, nees_from_s=5.0, record_every=5)
th = np.linspace(0, math.radians(20), 11)
tt = np.linspace(2.0, 22.0, 11)
slew = table_from_angle(tt, th, np.full(11, math.radians(1.0)), (0.0, 0.0, 1.0))
step = GuidanceSpec(kind="step", target_rotvec_deg=(3.0, -2.0, 10.0), t_step=1.0)
lay = ThrusterSpec.from_torque_matrix(S3_REFERENCE_A)
rng0 = np.random.default_rng(5)
FULL_J = (1218.6, 35.0, -20.0, 35.0, 442.2, 12.0, -20.0, 12.0, 1429.4)  # kg m^2
on = rng0.integers(0, 10, size=(100, lay.n)) * 0.02 * (rng0.random((100, lay.n)) < 0.4)
S = {
    "mekf_schmitt_step_disp": Scenario(
        estimator=EstimatorSpec(kind="mekf"),
        guidance=step,
        dispersions=disp,
        sim=sim,
        disturbance=DisturbanceSpec(
            constant=(1e-4, -2e-4, 5e-5), amplitude=(1e-4, 1e-4, 1e-4), period_s=50.0
        ),
    ),
    "mekf_st_pwm_nnls_gg": Scenario(
        estimator=EstimatorSpec(kind="mekf", underweight=0.0),
        sensors=SensorSpec(star_tracker_rate_hz=1.0, sun_rate_hz=2.0, noise="uniform"),
        controller=ControllerSpec(
            kind="pwm", allocation="nnls", kp=(60.0,) * 3, ki=(0.1,) * 3, kd=(300.0,) * 3
        ),
        orbit=OrbitSpec(gravity_gradient=True, altitude_km=700.0),
        guidance=slew,
        dispersions=disp,
        sim=sim,
        thrusters=lay.replace(failed=(2,)),
    ),
    "qmethod_pwm_pinv_slew": Scenario(
        estimator=EstimatorSpec(kind="wahba", wahba_method="q-method"),
        controller=ControllerSpec(
            kind="pwm", kp=(60.0,) * 3, ki=(0.1,) * 3, kd=(300.0,) * 3, min_on_time="round"
        ),
        guidance=slew,
        dispersions=disp,
        sim=sim,
    ),
    "quest_schmitt_unknownfail": Scenario(
        estimator=EstimatorSpec(kind="wahba", wahba_method="quest", weights="equal"),
        thrusters=lay.replace(failed=(1,), failure_known=False),
        guidance=step,
        dispersions=disp,
        sim=sim,
    ),
    "minmax_pwm_nnls_uniform": Scenario(
        estimator=EstimatorSpec(kind="minmax", search_range=0.1),
        sensors=SensorSpec(noise="uniform", sun_noise_deg=0.05),
        controller=ControllerSpec(
            kind="pwm", allocation="nnls", kp=(60.0,) * 3, ki=(0.1,) * 3, kd=(300.0,) * 3
        ),
        guidance=step,
        dispersions=disp,
        sim=sim,
    ),
    "minmax_schmitt": Scenario(estimator=EstimatorSpec(kind="minmax"), guidance=step, sim=sim),
    "truth_openloop": Scenario(
        estimator=EstimatorSpec(kind="truth"),
        sim=sim,
        controller=ControllerSpec(kind="open-loop", on_times=tuple(map(tuple, on))),
    ),
    "truth_pwm_pinv": Scenario(
        estimator=EstimatorSpec(kind="truth"),
        guidance=step,
        dispersions=disp,
        sim=sim,
        controller=ControllerSpec(kind="pwm", kp=(60.0,) * 3, ki=(0.1,) * 3, kd=(300.0,) * 3),
    ),
    # a full inertia matrix (products of inertia): the general rigid-body path of the RK4 step
    "mekf_schmitt_fullJ_gg": Scenario(
        spacecraft=SpacecraftSpec(inertia=FULL_J),
        estimator=EstimatorSpec(kind="mekf"),
        orbit=OrbitSpec(gravity_gradient=True, altitude_km=700.0),
        guidance=step,
        dispersions=disp,
        sim=sim,
    ),
    "truth_pwm_fullJ": Scenario(
        spacecraft=SpacecraftSpec(inertia=FULL_J),
        estimator=EstimatorSpec(kind="truth"),
        guidance=step,
        sim=sim,
        controller=ControllerSpec(kind="pwm", kp=(60.0,) * 3, ki=(0.1,) * 3, kd=(300.0,) * 3),
    ),
    # fast thruster lags (states exactly zero between pulses), with a fractional delay
    # (1.5 steps, dispersed) and with none
    "mekf_schmitt_fastlag_delay": Scenario(
        estimator=EstimatorSpec(kind="mekf"),
        thrusters=lay.replace(tau=1e-6, delay=0.03),
        guidance=step,
        dispersions=disp,
        sim=sim,
    ),
    "truth_pwm_fastlag_fail": Scenario(
        estimator=EstimatorSpec(kind="truth"),
        thrusters=lay.replace(tau=1e-6, delay=0.0, t_min=0.02, failed=(4,)),
        guidance=step,
        sim=sim,
        controller=ControllerSpec(kind="pwm", kp=(60.0,) * 3, ki=(0.1,) * 3, kd=(300.0,) * 3),
    ),
}


def run():
    import numba

    numba.set_num_threads(1)  # blocks of 8 (_kernels.block_size balances smaller ones over threads)
    out = {}
    for name, sc in S.items():
        for rec in (True, False):
            r = simulate(sc, 12, rng=3, record=rec, chunk_size=CHUNK)
            for k, v in r.metrics.items():
                out[f"{name}/{rec}/m/{k}"] = np.asarray(v)
            out[f"{name}/{rec}/tot"] = r.on_time_per_thruster
            if rec:
                out[f"{name}/{rec}/trace"] = r.trace
    return out


if __name__ == "__main__":
    mode = sys.argv[1]
    f = sys.argv[2] if len(sys.argv) > 2 else "kernel_identity_base.npz"
    t0 = time.time()
    out = run()
    print(f"run {time.time() - t0:.1f}s")
    if mode == "save":
        np.savez(f, **out)
        print("saved", len(out))
    else:
        base = np.load(f)
        bad = 0
        assert set(base.files) == set(out), "keys differ"
        for k in base.files:
            a, b = base[k], out[k]
            if not np.array_equal(a, b, equal_nan=True):
                bad += 1
                d = np.nanmax(np.abs(a - b)) if a.shape == b.shape else "shape"
                print("DIFF", k, d)
        nbytes = sum(base[k].tobytes() != out[k].tobytes() for k in base.files)
        print(
            "IDENTICAL" if bad == 0 else f"{bad} arrays differ",
            len(base.files),
            f"(bytewise: {nbytes} arrays differ, e.g. in the sign of a zero)",
        )
