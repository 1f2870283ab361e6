"""adcskit.simulation vs Basilisk: open-loop agreement, closed-loop behaviour and speed.

Needs Basilisk (``pip install 'adcskit[validate]'``, i.e. ``bsk`` from PyPI). Run::

    PYTHONPATH=src python benchmarks/bench_basilisk.py [--quick] [--json out.json] [--fig-dir docs/figures]

1. **Open loop.** The same rigid body (S3's GEO inertia), the same six 10 N thrusters (S3's
   reference layout, realised geometrically) and the *identical* sequence of on-times
   (seeded, one row per 0.2 s period, multiples of the 0.01 s step) drive Basilisk
   (``spacecraft`` + ``thrusterDynamicEffector``, RK4 at 0.01 s, no ramps) and our kernel
   (``controller.kind = "open-loop"``, thruster lag 1 us, no delay, no gravity gradient).
   We print the largest attitude difference (rad) and rate difference (rad/s) over the run.
2. **Closed loop.** Basilisk's own chain: ``simpleNav`` (no noise) -> ``inertial3D`` ->
   ``attTrackingError`` -> ``mrpFeedback`` -> ``thrForceMapping`` -> ``thrFiringSchmitt``
   -> thrusters, FSW at 0.2 s, dynamics at 0.01 s, from a 10 deg initial error. Ours with the
   same elements: truth navigation, a PD law on the error rotation vector with ``K/4`` and
   ``P`` (``sigma ~ theta/4`` for small angles), the redistributed pseudo-inverse and
   PWM with the 3 ms minimum on-time. Compared: settling time to 0.5 deg, final error,
   total on-time (propellant = on-time x mdot).
3. **Speed.** Sample-steps per second of the closed loop: Basilisk one sample at a time (it
   has no batch kernel), ours for a batch of samples in one kernel call, with the same
   elements and with the full chain (sun sensor + magnetometer + gyro + MEKF + Schmitt
   control + allocation + dynamics). ``--repeats R`` (default 3) interleaved repeats of
   (Basilisk, ours same elements, ours full chain); each Basilisk repeat simulates the closed
   loop for at least ``--bsk-cpu-s`` (default 2) CPU-seconds (whole multiples of the 150 s
   run), so Basilisk is timed over >= 6 s in all. Rates are per wall second and per
   CPU-second of the process (``time.process_time``: all threads); the ratios printed are
   medians over the repeats, measured in this one run: full chain per CPU-second (Basilisk is
   one thread) and per wall second (our kernel uses every core, Basilisk one).

   Idle OpenMP threads sleep (``OMP_WAIT_POLICY=PASSIVE``, set here before the first kernel
   unless the environment sets it, as the ``adcskit`` command line does): with libgomp's
   default an idle thread spins 5-8 ms after every parallel region (and at each chunk's
   barrier), CPU that does no work and that ``process_time`` counts. The policy in force is
   printed; ``--spinning-omp`` leaves libgomp's default.

   Two more per-core ratios compare like with like, because on this 2-vCPU machine our kernel
   ran 5-15 % fewer sample-steps per CPU-second on two threads than on one (medians of 10
   alternated pairs, with either wait policy; ``benchmarks/experiments/two_cores.py``, docs/benchmarks.md
   "Two cores per CPU-second"). **One thread each**: ours with ``numba.set_num_threads(1)``,
   the other cores idle, as for Basilisk. **Every core busy**: ours on all threads; Basilisk
   one process per core, started together behind a barrier, counted as the sum of their steps
   over the sum of their CPU-seconds.

   S3's inertia is diagonal (body axes = principal axes), and our RK4 step then skips the
   products with the zero entries (``rk4_step_principal``; Basilisk multiplies the full
   matrix either way). So that the ratio does not hide what a body frame off the principal
   axes costs, the full chain is also timed with the same spacecraft's inertia expressed in a
   body frame rotated by 30 deg about (1, 2, 3) (a full matrix: the general path), and its
   ratio printed beside the others.
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing
import os
import platform
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from adcskit.attitude import quat_to_dcm
from adcskit.simulation import (
    ControllerSpec,
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
from adcskit.thrusters import S3_REFERENCE_A

INERTIA = (1218.6, 442.2, 1429.4)  # S3 Table 5, kg m^2
MASS = 900.0  # S3 §6
F_MAX = 10.0
MDOT = 3.5e-3
DT = 0.01
T_S = 0.2
ISP = F_MAX / (MDOT * 9.80665)


def _layout() -> ThrusterSpec:
    return ThrusterSpec.from_torque_matrix(S3_REFERENCE_A, f_max=F_MAX, mdot=MDOT, t_min=0.0, tau=1e-6,
                                           delay=0.0)


def _mrp_to_quat(s: np.ndarray) -> np.ndarray:
    """Basilisk MRP sigma_BN -> our quaternion (scalar last, A(q) = [BN])."""
    s = np.atleast_2d(s)
    n2 = np.sum(s * s, axis=1, keepdims=True)
    q = np.concatenate([2 * s / (1 + n2), (1 - n2) / (1 + n2)], axis=1)
    return q * np.where(q[:, 3:] < 0, -1, 1)


def _angle(q1: np.ndarray, q2: np.ndarray) -> np.ndarray:
    d = np.abs(np.sum(q1 * q2, axis=1))
    return 2 * np.arccos(np.clip(d, 0, 1))


def _bsk_setup(layout: ThrusterSpec, sigma0, omega0, *, closed: bool, target=(0.0, 0.0, 0.0),
               gains=(0.0, 0.0), t_final: float = 60.0):
    from Basilisk.architecture import messaging
    from Basilisk.simulation import simpleNav, spacecraft, thrusterDynamicEffector
    from Basilisk.utilities import SimulationBaseClass, macros, simIncludeThruster

    sim = SimulationBaseClass.SimBaseClass()
    dyn = sim.CreateNewProcess("dyn")
    dyn.addTask(sim.CreateNewTask("dynTask", macros.sec2nano(DT)))
    sc = spacecraft.Spacecraft()
    sc.ModelTag = "sc"
    sc.hub.mHub = MASS
    sc.hub.r_BcB_B = [[0.0], [0.0], [0.0]]
    sc.hub.IHubPntBc_B = np.diag(INERTIA).tolist()
    sc.hub.sigma_BNInit = [[float(x)] for x in sigma0]
    sc.hub.omega_BN_BInit = [[float(x)] for x in omega0]
    sim.AddModelToTask("dynTask", sc)
    thr = thrusterDynamicEffector.ThrusterDynamicEffector()
    sim.AddModelToTask("dynTask", thr)
    fac = simIncludeThruster.thrusterFactory()
    for p, d in zip(layout.positions, layout.directions):
        fac.create("MOOG_Monarc_1", list(p), list(d), MaxThrust=float(F_MAX), MinOnTime=0.0, steadyIsp=float(ISP))
    fac.addToSpacecraft("thr", thr, sc)
    out = {"sim": sim, "sc": sc, "thr": thr, "macros": macros, "messaging": messaging}
    if not closed:
        cmd = messaging.THRArrayOnTimeCmdMsg()
        thr.cmdsInMsg.subscribeTo(cmd)
        out["cmd"] = cmd
        out["rec"] = sc.scStateOutMsg.recorder(macros.sec2nano(T_S))
        sim.AddModelToTask("dynTask", out["rec"])
        return out
    from Basilisk.fswAlgorithms import (
        attTrackingError,
        inertial3D,
        mrpFeedback,
        thrFiringSchmitt,
        thrForceMapping,
    )

    fsw = sim.CreateNewProcess("fsw")
    fsw.addTask(sim.CreateNewTask("fswTask", macros.sec2nano(T_S)))
    nav = simpleNav.SimpleNav()
    sim.AddModelToTask("dynTask", nav)
    ref = inertial3D.inertial3D()
    ref.sigma_R0N = list(target)
    err = attTrackingError.attTrackingError()
    ctl = mrpFeedback.mrpFeedback()
    ctl.K, ctl.P, ctl.Ki = float(gains[0]), float(gains[1]), -1.0
    fmap = thrForceMapping.thrForceMapping()
    fmap.controlAxes_B = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    fmap.thrForceSign = +1
    fire = thrFiringSchmitt.thrFiringSchmitt()
    fire.thrMinFireTime = 0.003
    fire.level_on = 0.75
    fire.level_off = 0.25
    for m in (ref, err, ctl, fmap, fire):
        sim.AddModelToTask("fswTask", m)
    veh = messaging.VehicleConfigMsg().write(messaging.VehicleConfigMsgPayload(
        ISCPntB_B=list(np.diag(INERTIA).reshape(-1))))
    conf = fac.getConfigMessage()
    nav.scStateInMsg.subscribeTo(sc.scStateOutMsg)
    err.attNavInMsg.subscribeTo(nav.attOutMsg)
    err.attRefInMsg.subscribeTo(ref.attRefOutMsg)
    ctl.guidInMsg.subscribeTo(err.attGuidOutMsg)
    ctl.vehConfigInMsg.subscribeTo(veh)
    fmap.cmdTorqueInMsg.subscribeTo(ctl.cmdTorqueOutMsg)
    fmap.thrConfigInMsg.subscribeTo(conf)
    fmap.vehConfigInMsg.subscribeTo(veh)
    fire.thrConfInMsg.subscribeTo(conf)
    fire.thrForceInMsg.subscribeTo(fmap.thrForceCmdOutMsg)
    thr.cmdsInMsg.subscribeTo(fire.onTimeOutMsg)
    out["rec"] = sc.scStateOutMsg.recorder(macros.sec2nano(T_S))
    out["on"] = fire.onTimeOutMsg.recorder(macros.sec2nano(T_S))
    out["keep"] = (nav, ref, err, ctl, fmap, fire, veh, conf, fsw, dyn)
    sim.AddModelToTask("dynTask", out["rec"])
    sim.AddModelToTask("fswTask", out["on"])
    return out


def open_loop(t_final: float, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    layout = _layout()
    n_per = int(round(t_final / T_S))
    # on-times: multiples of DT in [0, T_S), about a third of the thrusters firing per period
    on = rng.integers(0, int(T_S / DT), size=(n_per, layout.n)) * DT
    on *= rng.random((n_per, layout.n)) < 0.35
    w0 = (0.002, -0.001, 0.0015)
    b = _bsk_setup(layout, (0.0, 0.0, 0.0), w0, closed=False)
    sim, macros = b["sim"], b["macros"]
    sim.InitializeSimulation()
    t0 = time.perf_counter()
    for k in range(n_per):
        payload = b["messaging"].THRArrayOnTimeCmdMsgPayload(OnTimeRequest=list(on[k]) + [0.0] * (36 - layout.n))
        b["cmd"].write(payload, macros.sec2nano(k * T_S))  # a new write time: the effector re-reads
        # stop 1 ns before the next period so that its command is read at the period start
        sim.ConfigureStopTime(macros.sec2nano((k + 1) * T_S) - 1)
        sim.ExecuteSimulation()
    wall_b = time.perf_counter() - t0
    qb = _mrp_to_quat(np.asarray(b["rec"].sigma_BN))
    wb = np.asarray(b["rec"].omega_BN_B)
    sc = Scenario(
        spacecraft=SpacecraftSpec(inertia=INERTIA), thrusters=layout,
        orbit=OrbitSpec(gravity_gradient=False), disturbance=DisturbanceSpec(),
        controller=ControllerSpec(kind="open-loop", period_s=T_S, on_times=tuple(map(tuple, on))),
        estimator=EstimatorSpec(kind="truth"), guidance=GuidanceSpec(kind="hold"),
        sim=SimSpec(dt=DT, t_final=n_per * T_S, metrics_from_s=0.0, record_every=int(round(T_S / DT))),
        initial_rate_deg_s=tuple(np.degrees(w0)),
    )
    res = simulate(sc, 1, rng=0, record=True)
    # our error channels are w.r.t. the identity reference: rebuild q from the rotation vector
    rv = res.trace[0, :, 0:3]
    ang = np.linalg.norm(rv, axis=1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        ax = np.where(ang > 0, rv / np.where(ang > 0, ang, 1), 0.0)
    qo = np.concatenate([np.sin(ang / 2) * ax, np.cos(ang / 2)], axis=1)
    wo = res.trace[0, :, 5:8]
    m = min(len(qb), len(qo))
    dq = _angle(qb[:m], qo[:m])
    dw = np.max(np.abs(wb[:m] - wo[:m]))
    # impulse per pulse: Basilisk vs the exact F * t_on * lever / J of the first pulse
    return {"t_final_s": n_per * T_S, "max_attitude_diff_rad": float(np.max(dq)), "max_rate_diff_rad_s": float(dw),
            "rel_rate_diff": float(dw / np.max(np.abs(wb))),
            "max_angle_rad": float(np.max(2 * np.arccos(np.clip(np.abs(qb[:m, 3]), 0, 1)))),
            "max_rate_rad_s": float(np.max(np.abs(wb))), "final_angle_rad": float(2 * np.arccos(min(1.0, abs(qb[m - 1, 3])))),
            "basilisk_wall_s": wall_b, "n_thrusters": layout.n}


def closed_loop(t_final: float, n_samples: int, with_basilisk: bool = True) -> dict:
    layout = _layout().replace(t_min=3e-3)
    K, Pg = 120.0, 400.0  # mrpFeedback gains: L = -K sigma - P omega (N m, N m s); ~critically damped
    ang0 = math.radians(10.0)
    axis = np.array([1.0, 1.0, 0.5]) / np.linalg.norm([1.0, 1.0, 0.5])
    sigma0 = axis * math.tan(ang0 / 4)
    steps = int(round(t_final / DT))
    if not with_basilisk:
        return _ours(t_final, n_samples, layout, K, Pg, axis, ang0, steps, None)
    b = _bsk_setup(layout, sigma0, (0.0, 0.0, 0.0), closed=True, gains=(K, Pg))
    sim, macros = b["sim"], b["macros"]
    sim.InitializeSimulation()
    sim.ConfigureStopTime(macros.sec2nano(t_final))
    t0 = time.perf_counter()
    c0 = time.process_time()
    sim.ExecuteSimulation()
    wall_b = time.perf_counter() - t0
    cpu_b = time.process_time() - c0
    qb = _mrp_to_quat(np.asarray(b["rec"].sigma_BN))
    err_b = 2 * np.arccos(np.clip(np.abs(qb[:, 3]), 0, 1))
    tb = np.arange(len(err_b)) * T_S
    on_b = np.asarray(b["on"].OnTimeRequest)[:, : layout.n]
    band = math.radians(0.5)
    out_b = np.flatnonzero(err_b > band)
    settle_b = float(tb[out_b[-1] + 1]) if out_b.size and out_b[-1] + 1 < len(tb) else (0.0 if not out_b.size else math.nan)
    bsk = {"settling_time_s": settle_b, "final_error_deg": float(np.degrees(err_b[-1])),
           "total_on_time_s": float(on_b.sum()), "propellant_kg": float(on_b.sum() * MDOT),
           "wall_s": wall_b, "cpu_s": cpu_b, "sample_steps_per_s": steps / wall_b, "t": tb.tolist(),
           "err_deg": np.degrees(err_b).tolist()}
    return _ours(t_final, n_samples, layout, K, Pg, axis, ang0, steps, bsk)


def bsk_speed(t_final: float, min_cpu_s: float, barrier=None) -> dict:
    """Basilisk's closed loop (the chain of :func:`closed_loop`) continued in ``t_final``
    chunks until it has used ``min_cpu_s`` CPU-seconds: (steps, wall s, CPU s). With a
    ``barrier``, timing starts once every party has finished its set-up."""
    layout = _layout().replace(t_min=3e-3)
    axis = np.array([1.0, 1.0, 0.5]) / np.linalg.norm([1.0, 1.0, 0.5])
    sigma0 = axis * math.tan(math.radians(10.0) / 4)
    b = _bsk_setup(layout, sigma0, (0.0, 0.0, 0.0), closed=True, gains=(120.0, 400.0))
    sim, macros = b["sim"], b["macros"]
    sim.InitializeSimulation()
    if barrier is not None:
        barrier.wait()
    wall = cpu = 0.0
    m = 0
    while cpu < min_cpu_s:
        m += 1
        sim.ConfigureStopTime(macros.sec2nano(m * t_final))
        t0 = time.perf_counter()
        c0 = time.process_time()
        sim.ExecuteSimulation()
        wall += time.perf_counter() - t0
        cpu += time.process_time() - c0
    steps = m * int(round(t_final / DT))
    return {"steps": steps, "wall_s": wall, "cpu_s": cpu, "sample_steps_per_s": steps / wall,
            "sample_steps_per_cpu_s": steps / cpu}


_BARRIER = None


def _bsk_worker_init(barrier) -> None:
    global _BARRIER
    _BARRIER = barrier


def _bsk_speed_synced(t_final: float, min_cpu_s: float) -> dict:
    """:func:`bsk_speed` in a pool worker: set up, then wait for every worker before timing."""
    return bsk_speed(t_final, min_cpu_s, barrier=_BARRIER)


def bsk_speed_all_cores(t_final: float, min_cpu_s: float, n_proc: int) -> dict:
    """Basilisk with every core busy: ``n_proc`` processes run :func:`bsk_speed` together (a
    barrier after their set-up); sample-steps per CPU-second = the sum of their steps over the
    sum of their CPU-seconds, per wall second = the sum of their steps over the longest wall."""
    ctx = multiprocessing.get_context("spawn")
    barrier = ctx.Manager().Barrier(n_proc)
    with ProcessPoolExecutor(n_proc, mp_context=ctx, initializer=_bsk_worker_init,
                             initargs=(barrier,)) as pool:
        parts = list(pool.map(_bsk_speed_synced, [t_final] * n_proc, [min_cpu_s] * n_proc))
    steps = sum(p["steps"] for p in parts)
    cpu = sum(p["cpu_s"] for p in parts)
    wall = max(p["wall_s"] for p in parts)
    return {"processes": n_proc, "parts": parts, "steps": steps, "wall_s": wall, "cpu_s": cpu,
            "sample_steps_per_s": steps / wall, "sample_steps_per_cpu_s": steps / cpu}


def _speed_scenarios(t_final: float):
    layout = _layout().replace(t_min=3e-3)
    K, Pg = 120.0, 400.0
    axis = np.array([1.0, 1.0, 0.5]) / np.linalg.norm([1.0, 1.0, 0.5])
    base = dict(
        spacecraft=SpacecraftSpec(inertia=INERTIA), thrusters=layout, orbit=OrbitSpec(gravity_gradient=False),
        guidance=GuidanceSpec(kind="hold"),
        sim=SimSpec(dt=DT, t_final=t_final, metrics_from_s=0.75 * t_final, settle_band_deg=0.5,
                    record_every=int(round(T_S / DT))),
        initial_rotvec_deg=tuple(np.degrees(axis * math.radians(10.0))),
    )
    same = Scenario(**base, estimator=EstimatorSpec(kind="truth"),
                    controller=ControllerSpec(kind="pwm", period_s=T_S, kp=(K / 4,) * 3, ki=(0.0,) * 3, kd=(Pg,) * 3))
    full = Scenario(**base, estimator=EstimatorSpec(kind="mekf", init_error_deg=0.2),
                    sensors=SensorSpec(sun_rate_hz=2.0, mag_rate_hz=2.0, gyro_rate_hz=10.0, sun_noise_deg=0.05,
                                       mag_noise_deg=0.5),
                    controller=ControllerSpec(kind="schmitt", period_s=T_S, torque_level=(10.0, 10.0, 10.0)))
    return same, full


def _general_inertia(sc: Scenario) -> Scenario:
    """``sc`` with its inertia in a body frame 30 deg about (1, 2, 3) off the principal axes."""
    half = 0.5 * math.radians(30.0)
    A = quat_to_dcm(np.r_[math.sin(half) * np.array([1.0, 2.0, 3.0]) / math.sqrt(14.0), math.cos(half)])
    J = A @ np.diag(INERTIA) @ A.T
    J = 0.5 * (J + J.T)
    return sc.replace(spacecraft=SpacecraftSpec(inertia=tuple(J.reshape(-1))))


def _ours_speed(sc: Scenario, n_samples: int, seed: int, threads: int | None = None) -> dict:
    """One timed kernel call; ``threads``: numba's thread count for it (default: all)."""
    import numba

    before = numba.get_num_threads()
    if threads is not None:
        numba.set_num_threads(threads)
    try:
        t0 = time.perf_counter()
        c0 = time.process_time()
        res = simulate(sc, n_samples, rng=seed)
        wall = time.perf_counter() - t0
        cpu = time.process_time() - c0  # all threads of this process
    finally:
        numba.set_num_threads(before)
    ss = n_samples * res.n_steps
    return {"wall_s": wall, "cpu_s": cpu, "sample_steps_per_s": ss / wall, "sample_steps_per_cpu_s": ss / cpu}


def speed(t_final: float, n_samples: int, repeats: int, bsk_cpu_s: float, with_basilisk: bool = True) -> dict:
    """Interleaved repeats of (Basilisk, ours same elements, ours full chain); medians and ratios."""
    same, full = _speed_scenarios(t_final)
    full_general = _general_inertia(full)
    simulate(same, min(n_samples, 64), rng=0)  # compile / warm
    simulate(full, min(n_samples, 64), rng=0)
    n_cores = os.cpu_count() or 1
    runs = {"basilisk": [], "basilisk_all_cores": [], "same": [], "full": [], "full_one_thread": [],
            "full_general": []}
    for r in range(repeats):
        if with_basilisk:
            runs["basilisk"].append(bsk_speed(t_final, bsk_cpu_s))
            if n_cores > 1:
                runs["basilisk_all_cores"].append(bsk_speed_all_cores(t_final, bsk_cpu_s, n_cores))
        runs["same"].append(_ours_speed(same, n_samples, 10 + r))
        runs["full"].append(_ours_speed(full, n_samples, 20 + r))
        runs["full_one_thread"].append(_ours_speed(full, n_samples, 20 + r, threads=1))
        runs["full_general"].append(_ours_speed(full_general, n_samples, 20 + r))
    med = {k: {q: float(np.median([x[q] for x in v])) for q in ("sample_steps_per_s", "sample_steps_per_cpu_s")}
           for k, v in runs.items() if v}
    out = {"repeats": repeats, "n_samples": n_samples, "t_final_s": t_final, "cores": n_cores,
           "omp_wait_policy": os.environ.get("OMP_WAIT_POLICY"), "runs": runs,
           "median": med}
    if with_basilisk:
        b = med["basilisk"]
        for k in ("same", "full"):
            out[f"ratio_{k}_per_cpu_s"] = med[k]["sample_steps_per_cpu_s"] / b["sample_steps_per_cpu_s"]
            out[f"ratio_{k}_wall"] = med[k]["sample_steps_per_s"] / b["sample_steps_per_s"]
        # like with like: one thread each; every core busy on both sides
        out["ratio_full_one_thread_each"] = (med["full_one_thread"]["sample_steps_per_cpu_s"]
                                             / b["sample_steps_per_cpu_s"])
        out["ratio_full_general_per_cpu_s"] = (med["full_general"]["sample_steps_per_cpu_s"]
                                               / b["sample_steps_per_cpu_s"])
        if "basilisk_all_cores" in med:
            ba = med["basilisk_all_cores"]
            out["ratio_full_all_cores_busy_per_cpu_s"] = (med["full"]["sample_steps_per_cpu_s"]
                                                          / ba["sample_steps_per_cpu_s"])
            out["ratio_full_all_cores_busy_wall"] = med["full"]["sample_steps_per_s"] / ba["sample_steps_per_s"]
    return out


def _ours(t_final, n_samples, layout, K, Pg, axis, ang0, steps, bsk) -> dict:
    same, _ = _speed_scenarios(t_final)
    one = simulate(same, 1, rng=0, record=True)
    ours_err = one.trace[0, :, 3]
    return {
        "t_final_s": t_final, "steps": steps,
        "basilisk": {k: v for k, v in (bsk or {}).items() if k not in ("t", "err_deg")},
        "ours_same_elements": {"settling_time_s": float(one.metrics["settling_time_s"][0]),
                               "final_error_deg": float(np.degrees(ours_err[-1])),
                               "total_on_time_s": float(one.metrics["on_time_s"][0]),
                               "propellant_kg": float(one.metrics["propellant_kg"][0])},
        "traces": {"t": (bsk or {}).get("t", []), "basilisk_err_deg": (bsk or {}).get("err_deg", []),
                   "ours_t": one.t.tolist(), "ours_err_deg": np.degrees(ours_err).tolist()},
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--json")
    ap.add_argument("--fig-dir")
    ap.add_argument("--repeats", type=int, default=3, help="interleaved speed repeats (median)")
    ap.add_argument("--bsk-cpu-s", type=float, default=2.0, help="CPU-seconds per Basilisk speed repeat")
    ap.add_argument("--speed-only", action="store_true", help="skip the open-loop and behaviour runs")
    ap.add_argument("--spinning-omp", action="store_true",
                    help="leave OpenMP's wait policy at libgomp's default (idle threads spin) unless "
                         "OMP_WAIT_POLICY is set; by default it is set to PASSIVE, as the adcskit CLI does")
    args = ap.parse_args()
    if not args.spinning_omp:
        # before numba loads OpenMP (at the first parallel kernel, none has run yet): idle
        # threads sleep, as under the CLI; a value in the environment is kept
        os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    t_open = 20.0 if args.quick else 120.0
    t_closed = 40.0 if args.quick else 150.0
    n = 64 if args.quick else 512
    try:
        import Basilisk  # noqa: F401

        have_bsk = True
    except ImportError:
        have_bsk = False
        print("Basilisk is not installed (pip install 'adcskit[validate]', i.e. bsk from PyPI): "
              "only the adcskit kernel speed is measured")
    if not have_bsk:
        sp = speed(t_closed, n, args.repeats, args.bsk_cpu_s, with_basilisk=False)
        _print_speed(sp, n)
        if args.json:
            with open(args.json, "w") as fh:
                json.dump({"speed": sp, "basilisk": None}, fh, indent=1)
        return
    if args.speed_only:
        sp = speed(t_closed, n, args.repeats, args.bsk_cpu_s)
        _print_speed(sp, n)
        if args.json:
            with open(args.json, "w") as fh:
                json.dump({"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
                           "machine": platform.platform(), "cpus": os.cpu_count(), "speed": sp}, fh, indent=1)
        return
    ol = open_loop(t_open, seed=7)
    print(f"open loop ({ol['t_final_s']:.0f} s, {ol['n_thrusters']} thrusters, identical on-times): "
          f"max attitude difference {ol['max_attitude_diff_rad']:.3e} rad, max rate difference "
          f"{ol['max_rate_diff_rad_s']:.3e} rad/s (rates up to {ol['max_rate_rad_s']:.3e} rad/s, "
          f"{100 * ol['rel_rate_diff']:.2f} %; angles up to {ol['max_angle_rad']:.3f} rad)")
    cl = closed_loop(t_closed, n)
    bb, oo = cl["basilisk"], cl["ours_same_elements"]
    print(f"closed loop ({t_closed:.0f} s, 10 deg initial error):")
    print(f"  Basilisk : settle {bb['settling_time_s']:.1f} s, final {bb['final_error_deg']:.3f} deg, "
          f"on-time {bb['total_on_time_s']:.2f} s")
    print(f"  adcskit  : settle {oo['settling_time_s']:.1f} s, final {oo['final_error_deg']:.3f} deg, "
          f"on-time {oo['total_on_time_s']:.2f} s")
    sp = speed(t_closed, n, args.repeats, args.bsk_cpu_s)
    _print_speed(sp, n)
    info = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "machine": platform.platform(),
            "cpus": os.cpu_count(), "quick": args.quick, "open_loop": ol, "closed_loop": cl, "speed": sp}
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(info, fh, indent=1)
    if args.fig_dir:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(6.4, 3.6), layout="constrained")
        ax = fig.subplots()
        ax.plot(cl["traces"]["t"], cl["traces"]["basilisk_err_deg"], "-", label="Basilisk (mrpFeedback, thrForceMapping, thrFiringSchmitt)")
        ax.plot(cl["traces"]["ours_t"], cl["traces"]["ours_err_deg"], "--", label="adcskit (PD, redistributed pinv, PWM)")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("pointing error [deg]")
        ax.set_yscale("log")
        ax.legend(fontsize=7)
        ax.set_title("Closed loop from 10 deg: S3 inertia, S3 reference layout", fontsize=10)
        os.makedirs(args.fig_dir, exist_ok=True)
        fig.savefig(os.path.join(args.fig_dir, "bench-basilisk-closed-loop.png"), dpi=150)


def _print_speed(sp: dict, n: int) -> None:
    med = sp["median"]
    print(f"speed ({sp['repeats']} interleaved repeats, medians; {n} samples x {sp['t_final_s']:.0f} s in one call, "
          f"{os.cpu_count()} cores, OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY')}; Basilisk one sample, "
          f"one thread):")
    if "basilisk" in med:
        b = med["basilisk"]
        tot = sum(r["cpu_s"] for r in sp["runs"]["basilisk"])
        print(f"  Basilisk            : {b['sample_steps_per_s']:.3g} sample-steps/s wall, "
              f"{b['sample_steps_per_cpu_s']:.3g} per CPU-second (timed over {tot:.1f} CPU-s in all)")
    for k, label in (("same", "adcskit same elements"), ("full", "adcskit full chain  ")):
        m = med[k]
        ratio = (f"; ratio {sp[f'ratio_{k}_per_cpu_s']:.0f}x per CPU-second, {sp[f'ratio_{k}_wall']:.0f}x wall"
                 if f"ratio_{k}_wall" in sp else "")
        print(f"  {label}: {m['sample_steps_per_s']:.3g} sample-steps/s wall, "
              f"{m['sample_steps_per_cpu_s']:.3g} per CPU-second{ratio}")
    m1 = med["full_one_thread"]
    print(f"  adcskit full chain, one thread: {m1['sample_steps_per_cpu_s']:.3g} per CPU-second"
          + (f"; ratio {sp['ratio_full_one_thread_each']:.0f}x per core, one thread each (like with like)"
             if "ratio_full_one_thread_each" in sp else ""))
    mg = med["full_general"]
    print(f"  adcskit full chain, body axes off the principal axes (full inertia matrix): "
          f"{mg['sample_steps_per_cpu_s']:.3g} per CPU-second"
          + (f"; ratio {sp['ratio_full_general_per_cpu_s']:.0f}x per CPU-second"
             if "ratio_full_general_per_cpu_s" in sp else ""))
    if "basilisk_all_cores" in med:
        ba = med["basilisk_all_cores"]
        print(f"  Basilisk, every core busy ({sp['cores']} processes): {ba['sample_steps_per_cpu_s']:.3g} per "
              f"CPU-second, {ba['sample_steps_per_s']:.3g} wall; full chain on every core: ratio "
              f"{sp['ratio_full_all_cores_busy_per_cpu_s']:.0f}x per CPU-second, "
              f"{sp['ratio_full_all_cores_busy_wall']:.0f}x wall (like with like)")
    for k in ("basilisk", "basilisk_all_cores", "same", "full", "full_one_thread", "full_general"):
        if sp["runs"].get(k):
            print(f"    {k:18s} per CPU-second by repeat: "
                  + ", ".join(f"{r['sample_steps_per_cpu_s']:.3g}" for r in sp["runs"][k]))


if __name__ == "__main__":
    main()
