"""adcskit.simulation.wheels vs Basilisk: torque rods (open loop and B-dot) and speed.

Needs Basilisk (``pip install 'adcskit[validate]'``, i.e. ``bsk`` from PyPI). Run::

    PYTHONPATH=src python benchmarks/bench_basilisk_mtb.py [--quick] [--repeats 3] [--json out.json]

Sibling of ``bench_basilisk_wheels.py`` (shares its helpers). Both sides fly the same rigid
body (the 12U reference hub, diag(0.30, 0.27, 0.17) kg m^2, non-isotropic), three torque rods
along the body axes (0.2 A m^2 each), on the same 500 km, 97.4 deg circular orbit and **the same
field model**: a tilted centred dipole with IGRF-14's degree-1 coefficients ``g10, g11, h11`` at
the epoch's day (``adcskit.environment.dipole_coefficients``), reference radius 6371.2 km,
fixed in the Earth and turned with the IAU-82 GMST.

* Basilisk: ``spacecraft`` (RK4 at ``dt``, point-mass Earth with our ``mu``, started on our
  circular orbit) + ``magneticFieldCenteredDipole`` (the same ``g10, g11, h11`` and radius) +
  ``MtbEffector`` (``GtMatrix_B = I``). Its dipole model is evaluated in the planet-fixed frame
  given by a ``SpicePlanetStateMsg``; a small Python ``SysModel`` writes that message every step
  with ``J20002Pfix = R3(GMST(t))`` from :func:`adcskit.environment.gmst` (Basilisk would
  otherwise need SPICE kernels for the Earth's rotation).
* adcskit: ``simulate_wheels`` with ``OrbitSpec(magnetic_model="dipole")``, rods on for the whole
  period (``duty = 1``), no gravity gradient, no disturbance, and three idle wheels of 1e-12 kg m^2
  (the scenario needs wheels spanning 3 axes; their momentum is 1e-11 of the body's).

Differences that remain by construction: our kernel holds ``m x B`` over a step with ``B`` and the
attitude at the step's start and samples the field every 10 s along the closed-form orbit
(linear interpolation); ``MtbEffector`` evaluates ``m x B`` at every RK4 stage with the stage's
attitude and the field message of the step's start, on Basilisk's integrated orbit.

1. **Open loop.** A constant commanded dipole (0.1, -0.15, 0.2) A m^2 (``law = "open-loop"``,
   ``open_loop_dipole_am2``; Basilisk: a constant ``MTBCmdMsg``) from the initial rate
   (1.15, -0.86, 0.57) deg/s over a quarter orbit: body-rate and attitude differences, the rate
   difference relative to the rate range (issue 25's < 1 % criterion), and the field difference.
2. **B-dot detumble, closed loop.** Our B-dot (``m = -k dB/dt`` from consecutive 1 Hz
   magnetometer samples, noise-free, scaled so that the largest component is 0.2 A m^2, every
   1 s) vs the same law in a Python ``SysModel`` driving Basilisk's ``MtbEffector`` (Basilisk
   2.12.1 has no B-dot module: its ``mtbFeedforward`` / ``mtbMomentumManagement`` /
   ``dipoleMapping`` map a torque or a wheel momentum to dipoles). The law reads the body field
   ``[BN] B_N`` from the spacecraft state and the field message, as a perfect magnetometer would.
   From (2, -1.5, 1.5) deg/s over two orbits: the rate-norm histories, time to 1 and 0.5 deg/s,
   the rate after one and two orbits.
3. **Speed** per scenario: ``--repeats`` interleaved repeats of (Basilisk, ours); Basilisk one
   sample (one thread; for timing the Earth-rotation writer is off: a constant planet message,
   the same C++ modules), ours ``--samples`` samples in one call; sample-steps per CPU-second
   (``time.process_time``, all threads of the process), medians; the load average is printed.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

from adcskit.environment import circular_orbit, dipole_coefficients, gmst, magnetic_field  # noqa: E402
from adcskit.environment.magnetic import IGRF_REFERENCE_RADIUS  # noqa: E402
from adcskit.environment.orbits import MU_EARTH  # noqa: E402
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
from bench_basilisk_wheels import I_HUB, _mrp_to_quat, _ours_speed  # noqa: E402

ORBIT = OrbitSpec(altitude_km=500.0, inclination_deg=97.4, raan_deg=30.0, arg_lat0_deg=20.0,
                  epoch="2026-03-21T06:00:00", gravity_gradient=False, magnetic_model="dipole")
M_MAX = 0.2  # A m^2 per rod
DIPOLE = (0.1, -0.15, 0.2)  # A m^2, open loop
W_OPEN = np.array([0.02, -0.015, 0.01])  # rad/s
W_BDOT_DEG = (2.0, -1.5, 1.5)  # deg/s (the reference scenario's initial rate)
K_BDOT = 2e5  # A m^2 s/T (MagnetorquerSpec default)
RE = 6378137.0  # m: OrbitSpec altitude is above the equatorial radius (wheels._RE)


def _orbit_state(t: np.ndarray):
    o = ORBIT
    return circular_orbit(o.altitude_km * 1e3, math.radians(o.inclination_deg), math.radians(o.raan_deg),
                          math.radians(o.arg_lat0_deg), t, epoch=np.datetime64(o.epoch))


def _rot3(th: float) -> list[list[float]]:
    c, s = math.cos(th), math.sin(th)
    return [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]


def _bsk(kind: str, t_final: float, dt: float, w0: np.ndarray, *, rotate_earth: bool = True,
         period: float = 1.0) -> dict:
    """One Basilisk run: ``kind`` is ``"open"`` (constant dipole) or ``"bdot"`` (Python B-dot)."""
    from Basilisk.architecture import messaging, sysModel
    from Basilisk.simulation import MtbEffector, magneticFieldCenteredDipole, spacecraft
    from Basilisk.utilities import SimulationBaseClass, macros, simIncludeGravBody

    n_steps = int(round(t_final / dt))
    epoch = np.datetime64(ORBIT.epoch)
    th = gmst(epoch + (np.arange(n_steps + 2) * dt * 1e9).astype("timedelta64[ns]"))
    sim = SimulationBaseClass.SimBaseClass()
    proc = sim.CreateNewProcess("dyn")
    proc.addTask(sim.CreateNewTask("dynTask", macros.sec2nano(dt)))
    sc = spacecraft.Spacecraft()
    sc.ModelTag = "sc"
    sc.hub.mHub = 20.0
    sc.hub.r_BcB_B = [[0.0], [0.0], [0.0]]
    sc.hub.IHubPntBc_B = I_HUB.tolist()
    st = _orbit_state(np.array([0.0]))
    sc.hub.r_CN_NInit = [[float(x)] for x in np.asarray(st.r)[0]]
    sc.hub.v_CN_NInit = [[float(x)] for x in np.asarray(st.v)[0]]
    sc.hub.sigma_BNInit = [[0.0], [0.0], [0.0]]
    sc.hub.omega_BN_BInit = [[float(x)] for x in w0]
    grav = simIncludeGravBody.gravBodyFactory()
    earth = grav.createEarth()
    earth.isCentralBody = True
    earth.mu = MU_EARTH
    sc.gravField.gravBodies = spacecraft.GravBodyVector(list(grav.gravBodies.values()))
    g10, g11, h11 = dipole_coefficients(ORBIT.epoch) * 1e-9
    mag = magneticFieldCenteredDipole.MagneticFieldCenteredDipole()
    mag.ModelTag = "dipole"
    mag.g10, mag.g11, mag.h11 = float(g10), float(g11), float(h11)
    mag.planetRadius = IGRF_REFERENCE_RADIUS
    mag.addSpacecraftToModel(sc.scStateOutMsg)
    planet = messaging.SpicePlanetStateMsgPayload()
    planet.J20002Pfix = _rot3(float(th[0]))
    planet_msg = messaging.SpicePlanetStateMsg().write(planet)
    mag.planetPosInMsg.subscribeTo(planet_msg)

    class EarthRotation(sysModel.SysModel):
        """Writes J20002Pfix = R3(GMST(t)) before the field module runs."""

        def UpdateState(self, now):  # noqa: N802 (Basilisk's name)
            k = int(round(now * 1e-9 / dt))
            p = messaging.SpicePlanetStateMsgPayload()
            p.J20002Pfix = _rot3(float(th[k]))
            planet_msg.write(p, now, self.moduleID)

    mtb = MtbEffector.MtbEffector()
    mtb.ModelTag = "mtb"
    sc.addDynamicEffector(mtb)
    cfg = messaging.MTBArrayConfigMsgPayload()
    cfg.numMTB = 3
    cfg.GtMatrix_B = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    cfg.maxMtbDipoles = [M_MAX] * 3
    cfg_msg = messaging.MTBArrayConfigMsg().write(cfg)
    mtb.mtbParamsInMsg.subscribeTo(cfg_msg)
    mtb.magInMsg.subscribeTo(mag.envOutMsgs[0])
    keep = [planet_msg, cfg_msg]
    if kind == "open":
        cmd = messaging.MTBCmdMsgPayload()
        cmd.mtbDipoleCmds = list(DIPOLE)
        cmd_msg = messaging.MTBCmdMsg().write(cmd)
        keep.append(cmd_msg)
    else:
        cmd_msg = messaging.MTBCmdMsg()
        zero = messaging.MTBCmdMsgPayload()
        zero.mtbDipoleCmds = [0.0, 0.0, 0.0]
        cmd_msg.write(zero)
        h = int(round(period / dt))
        sc_rd = sc.scStateOutMsg.addSubscriber()
        mag_rd = mag.envOutMsgs[0].addSubscriber()

        class BDot(sysModel.SysModel):
            """adcskit's B-dot law: m = -k (B_k - B_{k-1}) / (t_k - t_{k-1}), largest component <= max."""

            def __init__(self):
                super().__init__()
                self.prev = None

            def UpdateState(self, now):  # noqa: N802 (Basilisk's name)
                k = int(round(now * 1e-9 / dt))
                if k % h:
                    return
                s = np.asarray(sc_rd().sigma_BN)
                s2 = s @ s
                sx = np.array([[0.0, -s[2], s[1]], [s[2], 0.0, -s[0]], [-s[1], s[0], 0.0]])
                c_nb = np.eye(3) + (8 * sx @ sx + 4 * (1 - s2) * sx) / (1 + s2) ** 2  # [NB]
                b = c_nb.T @ np.asarray(mag_rd().magField_N)
                t = now * 1e-9
                out = messaging.MTBCmdMsgPayload()
                m = np.zeros(3)
                if self.prev is not None:
                    m = -K_BDOT * (b - self.prev[1]) / (t - self.prev[0])
                    big = np.max(np.abs(m))
                    if big > M_MAX:
                        m *= M_MAX / big
                out.mtbDipoleCmds = m.tolist()
                cmd_msg.write(out, now, self.moduleID)
                self.prev = (t, b)

        bdot = BDot()
        bdot.ModelTag = "bdot"
        keep += [bdot, sc_rd, mag_rd]
    mtb.mtbCmdInMsg.subscribeTo(cmd_msg)
    # order within a step: Earth rotation -> spacecraft (integrates to t, writes its state) ->
    # field (B at t) -> B-dot (command for [t, t + dt]) -> torque rods
    if rotate_earth:
        rot = EarthRotation()
        rot.ModelTag = "earthRotation"
        keep.append(rot)
        sim.AddModelToTask("dynTask", rot, 400)
    sim.AddModelToTask("dynTask", sc, 300)
    sim.AddModelToTask("dynTask", mag, 200)
    if kind == "bdot":
        sim.AddModelToTask("dynTask", bdot, 150)
    sim.AddModelToTask("dynTask", mtb, 100)
    rec = sc.scStateOutMsg.recorder(macros.sec2nano(1.0))
    rec_b = mag.envOutMsgs[0].recorder(macros.sec2nano(1.0))
    sim.AddModelToTask("dynTask", rec)
    sim.AddModelToTask("dynTask", rec_b)
    sim.InitializeSimulation()
    sim.ConfigureStopTime(macros.sec2nano(t_final))
    c0, t0 = time.process_time(), time.perf_counter()
    sim.ExecuteSimulation()
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    del keep
    return {"q": _mrp_to_quat(np.asarray(rec.sigma_BN)), "w": np.asarray(rec.omega_BN_B),
            "r": np.asarray(rec.r_BN_N), "B_N": np.asarray(rec_b.magField_N), "steps": n_steps,
            "wall_s": wall, "cpu_s": cpu}


def ours_scenario(kind: str, t_final: float, dt: float, *, period: float = 1.0) -> WheelScenario:
    """Our side of scenario ``kind`` (``"open"`` or ``"bdot"``)."""
    wheel = WheelSpec(axes=((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)), inertia_kgm2=1e-12)
    rods = MagnetorquerSpec(max_dipole_am2=M_MAX, duty=1.0, magnetometer="corrupt", coupling_t_per_am2=0.0,
                            bdot_gain=K_BDOT, unload_gain=0.0)
    if kind == "open":
        control = WheelControlSpec(law="open-loop", open_loop_torque_nm=(0.0, 0.0, 0.0), open_loop_dipole_am2=DIPOLE,
                                   period_s=period)
        modes = ModeSpec(initial="point", sequence=False, pointing="inertial")
        sensors = SensorSpec(sun_rate_hz=0.0, mag_rate_hz=0.0, star_tracker_rate_hz=0.0, gyro_rate_hz=1.0 / dt,
                             gyro_arw=0.0, gyro_rrw=0.0, gyro_bias0_deg_h=0.0)
        w0 = tuple(np.degrees(W_OPEN))
    else:
        control = WheelControlSpec(law="pd", period_s=period)
        modes = ModeSpec(initial="detumble", sequence=False)
        sensors = SensorSpec(sun_rate_hz=0.0, mag_rate_hz=1.0 / period, mag_noise_deg=0.0, star_tracker_rate_hz=0.0,
                             gyro_rate_hz=1.0 / period, gyro_arw=0.0, gyro_rrw=0.0, gyro_bias0_deg_h=0.0)
        w0 = W_BDOT_DEG
    return WheelScenario(
        spacecraft=SpacecraftSpec(inertia=tuple(np.diag(I_HUB))), wheels=wheel, orbit=ORBIT,
        disturbance=DisturbanceSpec(), magnetorquers=rods, sensors=sensors, control=control, modes=modes,
        sim=SimSpec(dt=dt, t_final=t_final, metrics_from_s=0.0, record_every=int(round(1.0 / dt))),
        initial_rate_deg_s=w0)


def _ours(kind: str, t_final: float, dt: float) -> dict:
    res = simulate_wheels(ours_scenario(kind, t_final, dt), 1, rng=0, record=True)
    ch = res.channels
    w = res.trace[0][:, [ch.index(c) for c in ("omega_x", "omega_y", "omega_z")]]
    return {"w": w, "err": res.trace[0][:, ch.index("error")], "t": res.t}


def _field_check(b: dict, t_final: float) -> float:
    """Largest relative difference between Basilisk's field message and our magnetic_field on
    Basilisk's own positions (the model, not the orbit)."""
    m = len(b["B_N"])
    t = np.arange(m) * 1.0
    times = np.datetime64(ORBIT.epoch) + (t * 1e9).astype("timedelta64[ns]")
    ours = magnetic_field(b["r"][:m], times, model="dipole")
    # the recorders run last in a step: sample k holds the state at t_k and the field computed from it
    return float(np.max(np.linalg.norm(b["B_N"][1:] - ours[1:], axis=1) / np.linalg.norm(ours[1:], axis=1)))


def open_loop(t_final: float, dt: float, *, dt_check: bool = True) -> dict:
    """Open-loop comparison at ``dt`` and (``dt_check``) at ``dt / 5``: a difference that falls
    with the step is the torque's hold over a step, not the model."""
    out = _open_loop(t_final, dt)
    if dt_check:
        fine = _open_loop(t_final, dt / 5)
        out["at_dt_over_5"] = {k: fine[k] for k in ("dt_s", "max_rate_diff_rad_s", "rel_rate_diff",
                                                     "max_attitude_angle_diff_rad")}
    return out


def _open_loop(t_final: float, dt: float) -> dict:
    b = _bsk("open", t_final, dt, W_OPEN)
    o = _ours("open", t_final, dt)
    m = min(len(b["w"]), len(o["w"]))
    d_w = float(np.max(np.abs(b["w"][:m] - o["w"][:m])))
    rng_w = float(np.max(np.ptp(b["w"][:m], axis=0)))
    # attitude: our inertial target is the initial attitude (identity), so "error" is the angle
    # from it; the angle between the two attitudes needs our quaternion, read from Basilisk's
    ang_b = 2 * np.arccos(np.clip(np.abs(b["q"][:m, 3]), 0, 1))
    st = _orbit_state(np.arange(m) * 1.0)
    return {"t_final_s": t_final, "dt_s": dt, "dipole_am2": list(DIPOLE),
            "max_rate_diff_rad_s": d_w, "rate_range_rad_s": rng_w, "rel_rate_diff": d_w / rng_w,
            "max_attitude_angle_diff_rad": float(np.max(np.abs(ang_b - o["err"][:m]))),
            "max_angle_rad": float(np.max(ang_b)),
            "max_orbit_diff_m": float(np.max(np.linalg.norm(b["r"][:m] - np.asarray(st.r), axis=1))),
            "max_field_rel_diff": _field_check(b, t_final),
            "basilisk_cpu_s": b["cpu_s"]}


def bdot(t_final: float, dt: float, period: float) -> dict:
    w0 = np.radians(W_BDOT_DEG)
    b = _bsk("bdot", t_final, dt, w0, period=period)
    o = _ours("bdot", t_final, dt)
    m = min(len(b["w"]), len(o["w"]))
    t = np.arange(m) * 1.0
    rb = np.degrees(np.linalg.norm(b["w"][:m], axis=1))
    ro = np.degrees(np.linalg.norm(o["w"][:m], axis=1))
    n = math.sqrt(MU_EARTH / (RE + ORBIT.altitude_km * 1e3) ** 3)
    t_orb = 2 * math.pi / n

    def first_below(r, x):
        i = np.flatnonzero(r < x)
        return float(t[i[0]]) if i.size else math.nan

    def at(r, tt):
        return float(r[min(m - 1, int(round(tt)))])

    out = {"t_final_s": t_final, "dt_s": dt, "period_s": period, "orbit_period_s": t_orb,
           "initial_rate_deg_s": float(rb[0]), "max_rate_norm_diff_deg_s": float(np.max(np.abs(rb - ro))),
           "basilisk_cpu_s": b["cpu_s"]}
    for name, r in (("basilisk", rb), ("adcskit", ro)):
        out[name] = {"t_below_1_deg_s": first_below(r, 1.0), "t_below_0.5_deg_s": first_below(r, 0.5),
                     "rate_after_1_orbit_deg_s": at(r, t_orb), "rate_after_2_orbits_deg_s": at(r, 2 * t_orb),
                     "final_rate_deg_s": float(r[-1])}
    stride = 10
    out["traces"] = {"t": t[::stride].tolist(), "basilisk_rate_deg_s": rb[::stride].tolist(),
                     "adcskit_rate_deg_s": ro[::stride].tolist()}
    return out


def speed(kind: str, t_final: float, dt: float, n: int, repeats: int, bsk_cpu_s: float = 1.0) -> dict:
    """Interleaved repeats of (Basilisk, ours) for scenario ``kind``; medians and the ratio."""
    sc = ours_scenario(kind, t_final, dt)
    simulate_wheels(sc, 2, rng=0)  # compile / warm
    w0 = W_OPEN if kind == "open" else np.radians(W_BDOT_DEG)
    runs: dict[str, list] = {"basilisk": [], "adcskit": []}
    for r in range(repeats):
        cpu = wall = 0.0
        steps = 0
        while cpu < bsk_cpu_s:  # whole runs until Basilisk has been timed over bsk_cpu_s
            b = _bsk(kind, t_final, dt, w0, rotate_earth=False)
            cpu, wall, steps = cpu + b["cpu_s"], wall + b["wall_s"], steps + b["steps"]
        runs["basilisk"].append({"cpu_s": cpu, "wall_s": wall, "sample_steps_per_cpu_s": steps / cpu})
        runs["adcskit"].append(_ours_speed(sc, n, 10 + r))
    med = {k: float(np.median([x["sample_steps_per_cpu_s"] for x in v])) for k, v in runs.items()}
    return {"kind": kind, "repeats": repeats, "n_samples": n, "t_final_s": t_final, "dt_s": dt, "runs": runs,
            "median_sample_steps_per_cpu_s": med, "ratio_per_cpu_s": med["adcskit"] / med["basilisk"],
            "load_avg": os.getloadavg()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="shorter runs (open loop 300 s, B-dot one orbit)")
    ap.add_argument("--dt", type=float, default=0.1)
    ap.add_argument("--period", type=float, default=1.0)
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--repeats", type=int, default=3, help="interleaved speed repeats (median)")
    ap.add_argument("--bsk-cpu-s", type=float, default=1.0, help="CPU-seconds per Basilisk speed repeat")
    ap.add_argument("--json")
    a = ap.parse_args()
    n = math.sqrt(MU_EARTH / (RE + ORBIT.altitude_km * 1e3) ** 3)
    t_orb = 2 * math.pi / n
    t_open = 300.0 if a.quick else round(t_orb / 4)
    t_bdot = round(t_orb) if a.quick else round(2 * t_orb)
    info = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "machine": platform.platform(),
            "cpus": os.cpu_count(), "load_avg_start": os.getloadavg()}
    ol = open_loop(t_open, a.dt)
    print(f"open loop ({t_open:.0f} s, dt {a.dt} s, constant dipole {DIPOLE} A m^2, dipole field, J = diag(0.30, "
          f"0.27, 0.17)): body rate difference {ol['max_rate_diff_rad_s']:.2e} rad/s "
          f"({100 * ol['rel_rate_diff']:.3f} % of the {ol['rate_range_rad_s']:.3g} rad/s range); attitude angle "
          f"difference {ol['max_attitude_angle_diff_rad']:.2e} rad (angles up to {ol['max_angle_rad']:.3g} rad); "
          f"field {ol['max_field_rel_diff']:.1e} relative; orbit {ol['max_orbit_diff_m']:.2g} m")
    f = ol["at_dt_over_5"]
    print(f"  at dt {f['dt_s']:g} s: body rate difference {f['max_rate_diff_rad_s']:.2e} rad/s "
          f"({100 * f['rel_rate_diff']:.3f} %), attitude {f['max_attitude_angle_diff_rad']:.2e} rad")
    bd = bdot(t_bdot, a.dt, a.period)
    print(f"B-dot ({t_bdot:.0f} s = {t_bdot / t_orb:.2f} orbits, k = {K_BDOT:g} A m^2 s/T, 0.2 A m^2, control and "
          f"magnetometer every {a.period} s, from {bd['initial_rate_deg_s']:.2f} deg/s):")
    for name in ("basilisk", "adcskit"):
        r = bd[name]
        print(f"  {name:8s}: below 1 deg/s at {r['t_below_1_deg_s']:.0f} s, below 0.5 deg/s at "
              f"{r['t_below_0.5_deg_s']:.0f} s; rate after 1 orbit {r['rate_after_1_orbit_deg_s']:.4f} deg/s, "
              f"after 2 orbits {r['rate_after_2_orbits_deg_s']:.4f} deg/s; final {r['final_rate_deg_s']:.4f} deg/s")
    print(f"  largest rate-norm difference {bd['max_rate_norm_diff_deg_s']:.3g} deg/s")
    info.update(open_loop=ol, bdot=bd)
    sp = {}
    for kind, tf in (("open", t_open), ("bdot", min(t_bdot, 1200.0))):
        s = speed(kind, tf, a.dt, a.samples, a.repeats, a.bsk_cpu_s)
        sp[kind] = s
        med = s["median_sample_steps_per_cpu_s"]
        print(f"speed {kind} ({a.repeats} interleaved repeats, medians; {tf:.0f} s at dt {a.dt} s; Basilisk one "
              f"sample, ours {a.samples} in one call; load {s['load_avg'][0]:.1f}): Basilisk "
              f"{med['basilisk']:.3g} sample-steps per CPU-second, adcskit {med['adcskit']:.3g} -> "
              f"{s['ratio_per_cpu_s']:.0f}x per core (CPU s: Basilisk "
              + ", ".join(f"{x['cpu_s']:.2f}" for x in s["runs"]["basilisk"]) + "; adcskit "
              + ", ".join(f"{x['cpu_s']:.2f}" for x in s["runs"]["adcskit"]) + ")")
    print("  (Basilisk's B-dot law is a Python SysModel called every control period; its open-loop rate, the "
          "same modules with a constant command, bounds what a compiled B-dot module could reach)")
    info["speed"] = sp
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(info, fh, indent=1)


if __name__ == "__main__":
    main()
