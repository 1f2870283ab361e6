"""adcskit.simulation.wheels vs Basilisk: open-loop reaction-wheel agreement and speed.

Needs Basilisk (``pip install 'adcskit[validate]'``, i.e. ``bsk`` from PyPI). Run::

    python benchmarks/bench_basilisk_wheels.py [--t-final 300] [--samples 256] [--json out.json]

**Open loop.** The same rigid hub (the 12U reference inertia), the same four wheels (the
pyramid of :meth:`adcskit.simulation.WheelSpec.pyramid`, ``J_s`` = 2.4e-5 kg m^2, initial speeds
(1000, -500, 300, 0) rpm, no friction, no limits) and the *identical* constant motor torques
(seeded, up to 0.1 mN m) drive Basilisk (``spacecraft`` + ``reactionWheelStateEffector`` with
``custom`` balanced wheels, RK4 at ``dt``) and our kernel (``law = "open-loop"``, no gravity
gradient, no disturbance, rods off), from the same initial body rate. Basilisk's balanced wheel
adds ``J_t = J_g = J_s / 2`` about its transverse axes to the hub; our ``J`` is the spacecraft
inertia without the wheels' *axial* inertia, so we fly ``J = I_hub + sum J_s/2 (I - g g^T)``.
Printed: the largest difference of the attitude angle from the initial attitude (rad), of the
body rates and of the wheel speeds, relative to their ranges (the issue's < 1 % criterion),
sampled every second.

**Measured difference and its cause.** With ``J = I_hub + sum J_s/2 (I - g g^T)`` (the physical
reading above) the body rates differ by 0.16 % of their range over 300 s, independent of the
step (0.1 s and 0.02 s give the same numbers): a model difference, not integration error. With
``J = I_hub - sum J_s/2 (I - g g^T)`` the two agree to 1e-14 rad/s, i.e. Basilisk 2.12.1's
balanced wheels act as if the hub inertia were *reduced* by the wheels' transverse inertia
(``J_t = J_g = J_s/2`` from ``rwFactory``). Cause (Basilisk's ``reactionWheelStateEffector.cpp``):
``BalancedWheels`` add no mass properties to the spacecraft and subtract ``J_s g g^T`` in the
back-substitution, i.e. ``IHubPntBc_B`` is the inertia *with* the wheels and our ``J`` is
``I_hub - sum J_s g g^T``, equal to ``I_hub - sum J_s/2 (I - g g^T)`` for this pyramid (both
``(4/3) J_s I``). Both readings are printed.

**Closed loop.** Basilisk's chain (``simpleNav`` -> ``inertial3D`` -> ``attTrackingError`` ->
``mrpFeedback`` -> ``rwMotorTorque`` -> wheels) vs our PD law on the same plant from a 20 deg error
(isotropic inertia so that the scalar MRP gains equal ours): settling time, final error, the
largest error and wheel-speed differences. ``mrpFeedback.controlLawType = 1`` feeds forward
``omega_BN x ([I] omega + G_s h_s)`` as our law does; the default 0 uses ``omega_RN`` instead, which
is zero for an inertial target (no gyroscopic feed-forward): both are printed. **Non-isotropic**
(the 12U hub diag(0.30, 0.27, 0.17)): mrpFeedback's gains are scalars and ours scale with ``J``,
so the laws coincide only for a rotation about a principal axis ``i`` with ``K = 4 J_i k``,
``P = J_i c`` (three runs); a fourth run about (1, 1, 0.5) with the mean-inertia gains shows how
far apart the two laws then are.

**Speed.** Basilisk runs one sample at a time (no batch kernel); ours a batch of samples in
one kernel call, with the same elements; both in sample-steps per CPU-second (all threads of the
process): ``--repeats`` interleaved repeats of (Basilisk, ours) for the open and the closed
loop, medians (each Basilisk repeat timed over at least ``--bsk-cpu-s`` CPU-seconds).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import resource
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

from adcskit.simulation import (  # noqa: E402
    DisturbanceSpec,
    MagnetorquerSpec,
    ModeSpec,
    OrbitSpec,
    SensorSpec,
    SimSpec,
    SpacecraftSpec,
    WheelControlSpec,
    WheelScenario,
    WheelSpec,
    simulate_wheels,
)

I_HUB = np.diag([0.30, 0.27, 0.17])
JS = 2.4e-5
SPEEDS_RPM = (1000.0, -500.0, 300.0, 0.0)
W0 = np.array([0.02, -0.015, 0.01])  # rad/s
RPM = 2 * np.pi / 60


def _cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def _mrp_to_quat(s: np.ndarray) -> np.ndarray:
    """Basilisk MRP sigma_BN -> our quaternion (scalar last, A(q) = [BN])."""
    s = np.atleast_2d(s)
    n2 = np.sum(s * s, axis=1, keepdims=True)
    q = np.concatenate([2 * s / (1 + n2), (1 - n2) / (1 + n2)], axis=1)
    return q * np.where(q[:, 3:] < 0, -1, 1)


def basilisk(torques: np.ndarray, t_final: float, dt: float) -> dict:
    from Basilisk.architecture import messaging
    from Basilisk.simulation import reactionWheelStateEffector, spacecraft
    from Basilisk.utilities import SimulationBaseClass, macros, simIncludeRW

    sim = SimulationBaseClass.SimBaseClass()
    proc = sim.CreateNewProcess("dyn")
    proc.addTask(sim.CreateNewTask("dynTask", macros.sec2nano(dt)))
    sc = spacecraft.Spacecraft()
    sc.ModelTag = "sc"
    sc.hub.mHub = 20.0
    sc.hub.r_BcB_B = [[0.0], [0.0], [0.0]]
    sc.hub.IHubPntBc_B = I_HUB.tolist()
    sc.hub.sigma_BNInit = [[0.0], [0.0], [0.0]]
    sc.hub.omega_BN_BInit = [[float(x)] for x in W0]
    fac = simIncludeRW.rwFactory()
    for g, om in zip(WheelSpec.pyramid().axes, SPEEDS_RPM):
        fac.create("custom", list(g), Js=JS, Omega=float(om), useRWfriction=False, useMaxTorque=False,
                   useMinTorque=False, RWModel=messaging.BalancedWheels)
    rws = reactionWheelStateEffector.ReactionWheelStateEffector()
    rws.ModelTag = "rw"
    fac.addToSpacecraft("rw", rws, sc)
    sim.AddModelToTask("dynTask", rws, 2)
    sim.AddModelToTask("dynTask", sc, 1)
    cmd = messaging.ArrayMotorTorqueMsgPayload()
    cmd.motorTorque = list(torques) + [0.0] * (36 - len(torques))
    msg = messaging.ArrayMotorTorqueMsg().write(cmd)
    rws.rwMotorCmdInMsg.subscribeTo(msg)
    rec = sc.scStateOutMsg.recorder(macros.sec2nano(1.0))
    rec_w = rws.rwSpeedOutMsg.recorder(macros.sec2nano(1.0))
    sim.AddModelToTask("dynTask", rec)
    sim.AddModelToTask("dynTask", rec_w)
    sim.InitializeSimulation()
    sim.ConfigureStopTime(macros.sec2nano(t_final))
    c0, t0 = _cpu(), time.perf_counter()
    sim.ExecuteSimulation()
    wall, cpu = time.perf_counter() - t0, _cpu() - c0
    return {"q": _mrp_to_quat(np.asarray(rec.sigma_BN)), "w": np.asarray(rec.omega_BN_B),
            "speeds": np.asarray(rec_w.wheelSpeeds)[:, :4], "wall_s": wall, "cpu_s": cpu}


def ours_scenario(torques: np.ndarray, t_final: float, dt: float, transverse: float = 1.0) -> WheelScenario:
    wheels = WheelSpec.pyramid(inertia_kgm2=JS, initial_speed_rpm=SPEEDS_RPM, max_torque_nm=1.0, max_speed_rpm=1e6)
    A = wheels.axis_matrix()
    J = I_HUB + transverse * sum(0.5 * JS * (np.eye(3) - np.outer(g, g)) for g in A.T)
    return WheelScenario(
        spacecraft=SpacecraftSpec(inertia=tuple(J.reshape(-1))), wheels=wheels,
        orbit=OrbitSpec(altitude_km=500.0, inclination_deg=97.4, gravity_gradient=False),
        disturbance=DisturbanceSpec(), magnetorquers=MagnetorquerSpec(max_dipole_am2=0.0, unload_gain=0.0),
        sensors=SensorSpec(sun_rate_hz=0.0, mag_rate_hz=0.0, star_tracker_rate_hz=0.0, gyro_rate_hz=1.0 / dt,
                           gyro_arw=0.0, gyro_rrw=0.0, gyro_bias0_deg_h=0.0),
        control=WheelControlSpec(law="open-loop", open_loop_torque_nm=tuple(float(x) for x in torques), period_s=dt),
        modes=ModeSpec(initial="point", sequence=False, pointing="inertial"),
        sim=SimSpec(dt=dt, t_final=t_final, metrics_from_s=0.0, record_every=int(round(1.0 / dt))),
        initial_rate_deg_s=tuple(np.degrees(W0)),
    )


def closed_scenario(t_final: float, dt: float, period: float, *, inertia=(0.25, 0.25, 0.25), axis=(1.0, 1.0, 0.5),
                    wn: float = 0.1, zeta: float = 1.0) -> WheelScenario:
    """Our side of :func:`closed_loop`: PD on the pyramid, truth navigation, 20 deg about ``axis``."""
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    return WheelScenario(
        spacecraft=SpacecraftSpec(inertia=tuple(float(x) for x in inertia)),
        wheels=WheelSpec.pyramid(inertia_kgm2=JS, initial_speed_rpm=SPEEDS_RPM, max_torque_nm=1.0, max_speed_rpm=1e6),
        orbit=OrbitSpec(altitude_km=500.0, inclination_deg=97.4, gravity_gradient=False), disturbance=DisturbanceSpec(),
        magnetorquers=MagnetorquerSpec(max_dipole_am2=0.0, unload_gain=0.0),
        sensors=SensorSpec(sun_rate_hz=0.0, mag_rate_hz=0.0, star_tracker_rate_hz=0.0, gyro_rate_hz=1.0 / dt,
                           gyro_arw=0.0, gyro_rrw=0.0, gyro_bias0_deg_h=0.0),
        control=WheelControlSpec(law="pd", bandwidth_rad_s=wn, damping=zeta, period_s=period),
        modes=ModeSpec(initial="point", sequence=False, pointing="inertial"),
        sim=SimSpec(dt=dt, t_final=t_final, metrics_from_s=0.5 * t_final, settle_band_deg=0.5,
                    record_every=int(round(1.0 / dt))),
        initial_rotvec_deg=tuple(np.degrees(axis * np.radians(20.0))), initial_rate_deg_s=(0.0, 0.0, 0.0))


def closed_loop(t_final: float, dt: float, period: float, *, inertia=(0.25, 0.25, 0.25),
                axis=(1.0, 1.0, 0.5), gain_inertia: float | None = None, with_ours: bool = True,
                law_type: int = 1) -> dict:
    """Basilisk's own chain (simpleNav -> inertial3D -> attTrackingError -> mrpFeedback ->
    rwMotorTorque -> wheels) vs our PD law on the same plant (our ``J = diag(inertia)``), from a
    20 deg error about ``axis``. mrpFeedback's gains are scalars, ``L = -K sigma - P omega``; ours
    ``-J (2 k q_e + c omega)`` scale with ``J``. With ``K = 4 j k``, ``P = j c`` (``sigma ~ q_e / 2``)
    the two laws coincide to first order when ``J = j I`` (the default, isotropic), or on a
    non-isotropic body for a rotation about principal axis ``i`` with ``j = J_i``
    (``gain_inertia``; the closed loops are decoupled by both laws' gyroscopic feed-forward, so the
    motion stays on that axis). Otherwise (``gain_inertia`` = the mean inertia, any axis) the
    laws differ: axis ``i`` of mrpFeedback has ``omega_n sqrt(j / J_i)``."""
    from Basilisk.architecture import messaging
    from Basilisk.fswAlgorithms import attTrackingError, inertial3D, mrpFeedback, rwMotorTorque
    from Basilisk.simulation import reactionWheelStateEffector, simpleNav, spacecraft
    from Basilisk.utilities import SimulationBaseClass, macros, simIncludeRW

    J = np.diag(np.asarray(inertia, dtype=float))
    if gain_inertia is None:
        if np.ptp(np.diag(J)) != 0.0:
            raise ValueError(f"gain_inertia is needed for a non-isotropic inertia; got inertia={inertia}")
        gain_inertia = float(J[0, 0])
    j, wn, zeta = gain_inertia, 0.1, 1.0
    k, c = wn * wn, 2 * zeta * wn
    axes = np.asarray(WheelSpec.pyramid().axes)
    i_hub = J + sum(0.5 * JS * (np.eye(3) - np.outer(g, g)) for g in axes)  # Basilisk-equivalent: our J
    ang0 = np.radians(20.0)
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    sim = SimulationBaseClass.SimBaseClass()
    dyn = sim.CreateNewProcess("dyn", 10)
    dyn.addTask(sim.CreateNewTask("dynTask", macros.sec2nano(dt)))
    fsw = sim.CreateNewProcess("fsw", 5)
    fsw.addTask(sim.CreateNewTask("fswTask", macros.sec2nano(period)))
    sc = spacecraft.Spacecraft()
    sc.hub.mHub = 20.0
    sc.hub.r_BcB_B = [[0.0], [0.0], [0.0]]
    sc.hub.IHubPntBc_B = i_hub.tolist()
    sc.hub.sigma_BNInit = [[float(x)] for x in axis * np.tan(ang0 / 4)]
    sc.hub.omega_BN_BInit = [[0.0], [0.0], [0.0]]
    fac = simIncludeRW.rwFactory()
    for g, om in zip(axes, SPEEDS_RPM):
        fac.create("custom", list(g), Js=JS, Omega=float(om), useRWfriction=False, useMaxTorque=False,
                   useMinTorque=False, RWModel=messaging.BalancedWheels)
    rws = reactionWheelStateEffector.ReactionWheelStateEffector()
    fac.addToSpacecraft("rw", rws, sc)
    sim.AddModelToTask("dynTask", rws, 2)
    sim.AddModelToTask("dynTask", sc, 1)
    nav = simpleNav.SimpleNav()
    sim.AddModelToTask("dynTask", nav)
    ref = inertial3D.inertial3D()
    ref.sigma_R0N = [0.0, 0.0, 0.0]
    err = attTrackingError.attTrackingError()
    ctl = mrpFeedback.mrpFeedback()
    ctl.K, ctl.P, ctl.Ki = 4 * j * k, j * c, -1.0
    ctl.controlLawType = law_type  # 1: gyroscopic feed-forward omega_BN x H as ours; 0: omega_RN x H (= 0 here)
    alloc = rwMotorTorque.rwMotorTorque()
    alloc.controlAxes_B = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    for mdl in (ref, err, ctl, alloc):
        sim.AddModelToTask("fswTask", mdl)
    veh = messaging.VehicleConfigMsg().write(messaging.VehicleConfigMsgPayload(ISCPntB_B=list(J.reshape(-1))))
    rw_conf = fac.getConfigMessage()
    nav.scStateInMsg.subscribeTo(sc.scStateOutMsg)
    err.attNavInMsg.subscribeTo(nav.attOutMsg)
    err.attRefInMsg.subscribeTo(ref.attRefOutMsg)
    ctl.guidInMsg.subscribeTo(err.attGuidOutMsg)
    ctl.vehConfigInMsg.subscribeTo(veh)
    ctl.rwParamsInMsg.subscribeTo(rw_conf)
    ctl.rwSpeedsInMsg.subscribeTo(rws.rwSpeedOutMsg)
    alloc.rwParamsInMsg.subscribeTo(rw_conf)
    alloc.vehControlInMsg.subscribeTo(ctl.cmdTorqueOutMsg)
    rws.rwMotorCmdInMsg.subscribeTo(alloc.rwMotorTorqueOutMsg)
    rec = sc.scStateOutMsg.recorder(macros.sec2nano(1.0))
    rec_w = rws.rwSpeedOutMsg.recorder(macros.sec2nano(1.0))
    sim.AddModelToTask("dynTask", rec)
    sim.AddModelToTask("dynTask", rec_w)
    sim.InitializeSimulation()
    sim.ConfigureStopTime(macros.sec2nano(t_final))
    c0 = _cpu()
    sim.ExecuteSimulation()
    cpu_b = _cpu() - c0
    steps = int(round(t_final / dt))
    if not with_ours:  # timing only
        return {"steps": steps, "cpu_s": cpu_b}
    qb = _mrp_to_quat(np.asarray(rec.sigma_BN))
    err_b = np.degrees(2 * np.arccos(np.clip(np.abs(qb[:, 3]), 0, 1)))
    sp_b = np.asarray(rec_w.wheelSpeeds)[:, :4] / RPM
    ours = closed_scenario(t_final, dt, period, inertia=np.diag(J), axis=axis, wn=wn, zeta=zeta)
    res = simulate_wheels(ours, 1, rng=0, record=True)
    ch = res.channels
    err_o = np.degrees(res.trace[0][:, ch.index("error")])
    sp_o = res.trace[0][:, [ch.index(f"speed_{i}") for i in range(4)]] / RPM
    m = min(len(err_b), len(err_o))
    t = np.arange(m) * 1.0

    def settle(e):
        out = np.flatnonzero(e > 0.5)
        return float(t[out[-1] + 1]) if out.size and out[-1] + 1 < m else math.nan

    return {"settling_time_s": {"basilisk": settle(err_b[:m]), "adcskit": settle(err_o[:m])},
            "final_error_deg": {"basilisk": float(err_b[m - 1]), "adcskit": float(err_o[m - 1])},
            "max_error_diff_deg": float(np.max(np.abs(err_b[:m] - err_o[:m]))),
            "final_wheel_speeds_rpm": {"basilisk": sp_b[m - 1].tolist(), "adcskit": sp_o[m - 1].tolist()},
            "max_wheel_speed_diff_rpm": float(np.max(np.abs(sp_b[:m] - sp_o[:m]))),
            "wheel_speed_range_rpm": float(np.max(np.ptp(sp_b[:m], axis=0))),
            "basilisk_sample_steps_per_cpu_s": steps / cpu_b,
            "traces": {"t": t.tolist(), "basilisk_err_deg": err_b[:m].tolist(), "adcskit_err_deg": err_o[:m].tolist(),
                       "basilisk_speed_rpm": sp_b[:m].tolist(), "adcskit_speed_rpm": sp_o[:m].tolist()}}


def _compare(b: dict, res) -> dict:
    ch = res.channels
    wo = res.trace[0][:, [ch.index(c) for c in ("omega_x", "omega_y", "omega_z")]]
    so = res.trace[0][:, [ch.index(f"speed_{j}") for j in range(4)]]
    err_o = res.trace[0][:, ch.index("error")]  # angle from the inertial target = the initial attitude
    m = min(len(b["w"]), len(wo))
    err_b = 2 * np.arccos(np.clip(np.abs(b["q"][:m, 3]), 0, 1))
    d_w = float(np.max(np.abs(b["w"][:m] - wo[:m])))
    d_s = float(np.max(np.abs(b["speeds"][:m] - so[:m])))
    rng_w = float(np.max(np.ptp(b["w"][:m], axis=0)))
    rng_s = float(np.max(np.ptp(b["speeds"][:m], axis=0)))
    return {"max_attitude_angle_diff_rad": float(np.max(np.abs(err_b - err_o[:m]))), "max_rate_diff_rad_s": d_w,
            "rate_range_rad_s": rng_w, "rel_rate_diff": d_w / rng_w, "max_speed_diff_rad_s": d_s,
            "speed_range_rad_s": rng_s, "rel_speed_diff": d_s / rng_s}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-final", type=float, default=300.0)
    ap.add_argument("--dt", type=float, default=0.1)
    ap.add_argument("--samples", type=int, default=256)
    ap.add_argument("--period", type=float, default=0.5)
    ap.add_argument("--closed-t-final", type=float, default=150.0)
    ap.add_argument("--repeats", type=int, default=3, help="interleaved speed repeats (median)")
    ap.add_argument("--bsk-cpu-s", type=float, default=1.0, help="CPU-seconds per Basilisk speed repeat")
    ap.add_argument("--json")
    a = ap.parse_args()
    torques = np.random.default_rng(7).uniform(-1e-4, 1e-4, 4)
    b = basilisk(torques, a.t_final, a.dt)
    readings = {}
    for name, tr in (("physical J = I_hub + sum Jt (I - g g^T)", 1.0), ("Basilisk-equivalent J = I_hub - sum Jt (I - g g^T)", -1.0)):
        readings[name] = _compare(b, simulate_wheels(ours_scenario(torques, a.t_final, a.dt, tr), 1, rng=0, record=True))
    sc = ours_scenario(torques, a.t_final, a.dt)
    steps = int(round(a.t_final / a.dt))
    simulate_wheels(sc, 2, rng=0)  # warm
    c0, t0 = _cpu(), time.perf_counter()
    batch = simulate_wheels(sc, a.samples, rng=1)
    wall, cpu = time.perf_counter() - t0, _cpu() - c0
    rate_b = steps / b["cpu_s"]
    rate_o = a.samples * steps / cpu
    out = {"t_final_s": a.t_final, "dt_s": a.dt, "torques_nm": torques.tolist(), "readings": readings,
           "basilisk_sample_steps_per_cpu_s": rate_b,
           "ours_sample_steps_per_cpu_s": rate_o, "ours_wall_s": wall, "ours_kernel_rate": batch.sample_steps_per_s,
           "speed_ratio_per_core": rate_o / rate_b}
    print(f"open loop ({a.t_final:.0f} s, dt {a.dt} s, 4 pyramid wheels, identical torques {np.round(torques * 1e3, 3)} mN m):")
    for name, r in readings.items():
        print(f"  {name}: attitude angle difference {r['max_attitude_angle_diff_rad']:.2e} rad; body rate "
              f"difference {r['max_rate_diff_rad_s']:.2e} rad/s ({100 * r['rel_rate_diff']:.2e} % of the range); "
              f"wheel speed difference {r['max_speed_diff_rad_s']:.2e} rad/s ({100 * r['rel_speed_diff']:.2e} %)")
    print(f"  speed: Basilisk {rate_b:.3g} sample-steps per CPU-second (one sample); adcskit {rate_o:.3g} "
          f"({a.samples} samples) -> {rate_o / rate_b:.0f}x per core")
    for law_type in (1, 0):
        cl = closed_loop(a.closed_t_final, a.dt, a.period, law_type=law_type)
        out["closed_loop" if law_type == 1 else "closed_loop_law_type_0"] = cl
        print(f"closed loop ({a.closed_t_final:.0f} s from 20 deg, PD / mrpFeedback controlLawType {law_type}, "
              f"J = 0.25 I, control every {a.period} s):")
        for key in ("settling_time_s", "final_error_deg"):
            print(f"  {key}: Basilisk {cl[key]['basilisk']:.4g}, adcskit {cl[key]['adcskit']:.4g}")
        print(f"  largest error difference {cl['max_error_diff_deg']:.3g} deg; largest wheel-speed difference "
              f"{cl['max_wheel_speed_diff_rpm']:.3g} rpm of a {cl['wheel_speed_range_rpm']:.3g} rpm range")
    out["non_isotropic"] = non_isotropic(a.closed_t_final, a.dt, a.period)
    out["speed"] = speed(torques, a.t_final, a.closed_t_final, a.dt, a.period, a.samples, a.repeats, a.bsk_cpu_s)
    out.update(date=time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), machine=platform.platform(),
               cpus=os.cpu_count())
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=1)


def non_isotropic(t_final: float, dt: float, period: float) -> dict:
    """Closed loop on the 12U hub diag(0.30, 0.27, 0.17): per principal axis with the gains that
    make mrpFeedback's law ours (``K = 4 J_i k``, ``P = J_i c``), and about (1, 1, 0.5) with the
    mean-inertia gains (the laws differ: mrpFeedback's bandwidth is ``omega_n sqrt(j / J_i)``)."""
    J = tuple(float(x) for x in np.diag(I_HUB))
    runs = {}
    for i, name in enumerate("xyz"):
        ax = np.eye(3)[i]
        runs[f"about {name}, K = 4 J_{name} k, P = J_{name} c"] = closed_loop(
            t_final, dt, period, inertia=J, axis=ax, gain_inertia=J[i])
    jm = sum(J) / 3
    runs[f"about (1, 1, 0.5), K = 4 j k, P = j c, j = trace(J)/3 = {jm:.4f}"] = closed_loop(
        t_final, dt, period, inertia=J, axis=(1.0, 1.0, 0.5), gain_inertia=jm)
    print(f"closed loop on J = diag{J} ({t_final:.0f} s from 20 deg, PD / mrpFeedback, control every {period} s):")
    for name, cl in runs.items():
        cl.pop("traces")
        print(f"  {name}: settling Basilisk {cl['settling_time_s']['basilisk']:.4g} s, adcskit "
              f"{cl['settling_time_s']['adcskit']:.4g} s; largest error difference {cl['max_error_diff_deg']:.3g} deg; "
              f"wheel speeds within {cl['max_wheel_speed_diff_rpm']:.3g} rpm of a {cl['wheel_speed_range_rpm']:.3g} "
              f"rpm range")
    return runs


def _ours_speed(sc: WheelScenario, n: int, seed: int) -> dict:
    """CPU and wall time of ``n`` samples of ``sc`` in one call; sample-steps per CPU-second (all threads)."""
    c0, t0 = _cpu(), time.perf_counter()
    res = simulate_wheels(sc, n, rng=seed)
    cpu, wall = _cpu() - c0, time.perf_counter() - t0
    steps = int(round(sc.sim.t_final / sc.sim.dt))
    return {"cpu_s": cpu, "wall_s": wall, "sample_steps_per_cpu_s": n * steps / cpu,
            "sample_steps_per_s": n * steps / wall, "kernel_rate": res.sample_steps_per_s}


def speed(torques, t_open: float, t_closed: float, dt: float, period: float, n: int, repeats: int,
          bsk_cpu_s: float) -> dict:
    """Interleaved repeats of (Basilisk, ours) for the open and the closed loop (isotropic);
    each Basilisk repeat runs whole simulations until it has used ``bsk_cpu_s`` CPU-seconds;
    ours ``n`` samples in one call; sample-steps per CPU-second (all threads), medians."""
    ours = {"open": ours_scenario(torques, t_open, dt), "closed": closed_scenario(t_closed, dt, period)}
    for sc in ours.values():
        simulate_wheels(sc, 2, rng=0)  # compile / warm
    runs = {k: {"basilisk": [], "adcskit": []} for k in ours}
    for r in range(repeats):
        for kind, sc in ours.items():
            cpu, steps = 0.0, 0
            while cpu < bsk_cpu_s:
                if kind == "open":
                    b = basilisk(torques, t_open, dt)
                    cpu, steps = cpu + b["cpu_s"], steps + int(round(t_open / dt))
                else:
                    b = closed_loop(t_closed, dt, period, with_ours=False)
                    cpu, steps = cpu + b["cpu_s"], steps + b["steps"]
            runs[kind]["basilisk"].append({"cpu_s": cpu, "sample_steps_per_cpu_s": steps / cpu})
            runs[kind]["adcskit"].append(_ours_speed(sc, n, 10 + r))
    out = {"repeats": repeats, "n_samples": n, "load_avg": os.getloadavg(), "runs": runs}
    for kind, rr in runs.items():
        med = {k: float(np.median([x["sample_steps_per_cpu_s"] for x in v])) for k, v in rr.items()}
        out[kind] = {"median_sample_steps_per_cpu_s": med, "ratio_per_cpu_s": med["adcskit"] / med["basilisk"]}
        print(f"speed {kind} loop ({repeats} interleaved repeats, medians; Basilisk one sample, timed over >= "
              f"{bsk_cpu_s:g} CPU-s per repeat; ours {n} samples in one call; load {out['load_avg'][0]:.1f}): "
              f"Basilisk {med['basilisk']:.3g}, adcskit {med['adcskit']:.3g} sample-steps per CPU-second -> "
              f"{out[kind]['ratio_per_cpu_s']:.0f}x per core")
    return out


if __name__ == "__main__":
    main()
