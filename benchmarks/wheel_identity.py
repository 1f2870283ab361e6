"""Bit-identity check of the wheel / magnetorquer kernel over every branch (for kernel rewrites).

``simulate_wheels`` over scenarios that together take every branch of
:func:`adcskit.simulation._wheel_kernels.wheel_sample`: the reference detumble -> sun -> nadir
sequence with dispersions (full three orbits, traces on and off, a second trace grid); the same
with the MEKF (star tracker on) and with the MEKF without a star tracker; nadir and inertial
pointing; the ``pd``, ``wie`` and ``open-loop`` laws; viscous and Coulomb friction, torque
quantisation and noise, a failed wheel; null motion on five wheels; raw knowledge without a star
tracker; thruster unloading (a known and an unknown failed thruster, MEKF on); magnetic unloading;
magnetometer blanking and corruption; a sinusoidal disturbance; a sun-pointing hold through
eclipse; a settling band so tight that the pointing error crosses it near the end; star-tracker
resets that do not coincide with the control periods (0.5 Hz against 1 / 0.6 s); a magnetometer
at every step, blanked and corrupted while the rods are on. Few samples
(4-6) and campaign chunks of 2-3 samples. Every output array of each result (metrics, trace,
``t``, parameters, seeds) is saved before a change and compared after, ``np.array_equal``
(NaN-aware) and bytewise (``tobytes``: the sign of a zero, a NaN's bits)::

    PYTHONPATH=src python benchmarks/wheel_identity.py save /tmp/wheel_base.npz
    PYTHONPATH=src python benchmarks/wheel_identity.py compare /tmp/wheel_base.npz

About a minute of CPU with the kernel cached (most of it the three full reference runs).
"""

import sys
import time

import numpy as np

from adcskit.simulation import (
    DisturbanceSpec,
    EstimatorSpec,
    MagnetorquerSpec,
    ModeSpec,
    OrbitSpec,
    SensorSpec,
    SimSpec,
    SpacecraftSpec,
    ThrusterSpec,
    ThrusterUnloadSpec,
    WheelControlSpec,
    WheelDispersionSpec,
    WheelScenario,
    WheelSpec,
    simulate_wheels,
)

DISP = WheelDispersionSpec(inertia_rel=0.1, wheel_misalignment_deg=0.5, sensor_noise_rel=0.2,
                           initial_rate_deg_s=1.0, initial_attitude="random")
REF = WheelScenario(dispersions=DISP)
SMALL = WheelDispersionSpec(inertia_rel=0.05, wheel_misalignment_deg=0.3, sensor_noise_rel=0.2,
                            initial_rate_deg_s=0.05, initial_attitude_deg=3.0)
POINT_NADIR = ModeSpec(initial="point", sequence=False, pointing="nadir")
POINT_INERTIAL = ModeSpec(initial="point", sequence=False, pointing="inertial", target_rotvec_deg=(20.0, -10.0, 5.0))
SHORT = SimSpec(dt=0.2, t_final=1200.0, metrics_from_s=600.0, settle_band_deg=0.5, record_every=7)
FRICTION = WheelSpec.pyramid(viscous_nms=2e-8, coulomb_nm=2e-6, torque_quantum_nm=1e-6, torque_noise_nm=2e-6,
                             initial_speed_rpm=(500.0, -300.0, 200.0, 0.0), failed=(1,))
FIVE = WheelSpec(axes=((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (0.577, 0.577, 0.577),
                       (-0.577, 0.577, 0.577)), initial_speed_rpm=(100.0, -200.0, 300.0, 0.0, 50.0))
_POS = ((0.1, 0.0, 0.0), (-0.1, 0.0, 0.0), (0.0, 0.1, 0.0), (0.0, -0.1, 0.0), (0.0, 0.0, 0.15), (0.0, 0.0, -0.15))
_DIR = ((0.0, 1.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, 1.0), (0.0, 0.0, -1.0), (1.0, 0.0, 0.0), (-1.0, 0.0, 0.0))
JETS = ThrusterSpec(positions=_POS + _POS, directions=_DIR + tuple((-a, -b, -c) for a, b, c in _DIR),
                    f_max=0.01, mdot=1.4e-5, t_min=0.01)
SATURATED = WheelSpec.pyramid(initial_speed_rpm=(3000.0, 3000.0, 2000.0, 3500.0))
NO_ST = SensorSpec(sun_rate_hz=1.0, sun_noise_deg=0.5, mag_rate_hz=1.0, mag_noise_deg=0.5, gyro_rate_hz=5.0,
                   gyro_arw=1.5e-5, gyro_rrw=1e-7, gyro_bias0_deg_h=5.0, star_tracker_rate_hz=0.0)

#: name -> (scenario, samples, chunk_size, record options)
S = {
    "reference": (REF, 6, 3, (False, True)),
    "reference_grid13": (REF.replace(sim=REF.sim.replace(record_every=13)), 4, None, (True,)),
    "reference_mekf": (REF.replace(estimator=EstimatorSpec(kind="mekf")), 4, 2, (False, True)),
    "mekf_no_star_tracker_nadir": (
        REF.replace(estimator=EstimatorSpec(kind="mekf"), sensors=NO_ST, modes=POINT_NADIR, dispersions=SMALL,
                    sim=SHORT, initial_rate_deg_s=(0.0, -0.06, 0.0)), 5, 2, (False, True)),
    "inertial_pd_friction_failed": (
        REF.replace(wheels=FRICTION, control=WheelControlSpec(law="pd", bandwidth_rad_s=0.15, damping=0.8),
                    modes=POINT_INERTIAL, dispersions=SMALL, sim=SHORT,
                    disturbance=DisturbanceSpec(constant=(2e-7, -1e-7, 1e-7), amplitude=(1e-6, 5e-7, 2e-7),
                                                period_s=300.0, phase_deg=(0.0, 30.0, 60.0)),
                    initial_rate_deg_s=(0.05, 0.0, -0.05)), 5, 2, (False, True)),
    "nadir_wie_null_motion_raw_knowledge": (
        REF.replace(wheels=FIVE, control=WheelControlSpec(law="wie", null_motion=True), modes=POINT_NADIR,
                    sensors=NO_ST, dispersions=SMALL, sim=SHORT.replace(settle_band_deg=0.01),
                    initial_rotvec_deg=(30.0, 10.0, -20.0)), 4, None, (False, True)),
    "open_loop": (
        REF.replace(control=WheelControlSpec(law="open-loop", open_loop_torque_nm=(1e-4, -2e-4, 5e-5, 0.0),
                                             open_loop_dipole_am2=(0.05, -0.1, 0.02)),
                    wheels=WheelSpec.pyramid(viscous_nms=1e-8, coulomb_nm=1e-6), dispersions=SMALL,
                    sim=SHORT), 4, None, (False, True)),
    "detumble_corrupt_full_duty": (
        REF.replace(magnetorquers=MagnetorquerSpec(duty=1.0, magnetometer="corrupt", coupling_t_per_am2=1e-6),
                    dispersions=DISP, sim=SimSpec(dt=0.2, t_final=3000.0, metrics_from_s=1500.0, record_every=11)),
        4, None, (False, True)),
    "sun_hold_eclipse_no_unload": (
        REF.replace(modes=ModeSpec(initial="sun", sequence=False), magnetorquers=MagnetorquerSpec(unload_gain=0.0),
                    dispersions=SMALL, sim=SimSpec(dt=0.2, t_final=4000.0, metrics_from_s=2000.0, record_every=20)),
        4, None, (False, True)),
    "thruster_unloading_mekf": (
        WheelScenario(wheels=SATURATED, control=WheelControlSpec(law="pd", bandwidth_rad_s=0.2, damping=1.0),
                      modes=POINT_INERTIAL, estimator=EstimatorSpec(kind="mekf"), dispersions=SMALL,
                      magnetorquers=MagnetorquerSpec(unload_gain=0.0),
                      sim=SimSpec(dt=0.1, t_final=60.0, metrics_from_s=10.0, record_every=3),
                      thruster_unloading=ThrusterUnloadSpec(thrusters=JETS.replace(failed=(3,)), start_nms=0.01,
                                                            stop_nms=0.002, torque_nm=5e-4),
                      initial_rate_deg_s=(0.0, 0.0, 0.0)), 4, 2, (False, True)),
    "thruster_unloading_unknown_failure": (
        WheelScenario(wheels=SATURATED, modes=POINT_NADIR, dispersions=SMALL, orbit=OrbitSpec(
            altitude_km=500.0, inclination_deg=97.4, gravity_gradient=False, magnetic_model="dipole"),
                      sim=SimSpec(dt=0.2, t_final=120.0, metrics_from_s=30.0, record_every=5),
                      thruster_unloading=ThrusterUnloadSpec(thrusters=JETS.replace(failed=(0,), failure_known=False),
                                                            start_nms=0.01, stop_nms=0.004, torque_nm=1e-3),
                      spacecraft=SpacecraftSpec(inertia=(0.30, 0.27, 0.17))), 4, None, (False, True)),
    "star_tracker_slower_than_control": (
        REF.replace(sensors=NO_ST.replace(star_tracker_rate_hz=0.5, star_tracker_noise_arcsec=20.0),
                    control=WheelControlSpec(period_s=0.6), modes=POINT_NADIR, dispersions=SMALL,
                    sim=SHORT.replace(record_every=4)), 4, None, (False, True)),
    "sequence_star_tracker_every_2s": (
        REF.replace(sensors=NO_ST.replace(star_tracker_rate_hz=0.5, star_tracker_noise_arcsec=20.0),
                    sim=SimSpec(dt=0.2, t_final=8000.0, metrics_from_s=6000.0, record_every=9)), 4, None, (False, True)),
    "magnetometer_every_step_blank_and_corrupt": (
        REF.replace(sensors=NO_ST.replace(mag_rate_hz=5.0, star_tracker_rate_hz=1.0), dispersions=DISP,
                    sim=SimSpec(dt=0.2, t_final=3000.0, metrics_from_s=1500.0, record_every=6)), 4, None, (False, True)),
    "magnetometer_every_step_corrupt": (
        REF.replace(sensors=NO_ST.replace(mag_rate_hz=5.0),
                    magnetorquers=MagnetorquerSpec(magnetometer="corrupt", coupling_t_per_am2=2e-6, duty=0.6),
                    dispersions=DISP, sim=SimSpec(dt=0.2, t_final=3000.0, metrics_from_s=1500.0, record_every=6)),
        4, None, (False, True)),
}


def run():
    out = {}
    for name, (sc, n, chunk, recs) in S.items():
        for rec in recs:
            r = simulate_wheels(sc, n, rng=7, record=rec, chunk_size=chunk)
            p = f"{name}/{rec}"
            for k, v in r.metrics.items():
                out[f"{p}/m/{k}"] = np.asarray(v)
            for k, v in r.parameters.items():
                out[f"{p}/p/{k}"] = np.asarray(v)
            out[f"{p}/seeds"] = r.seeds
            out[f"{p}/n"] = np.array([r.n_samples, r.n_steps, r.n_chunks, int(r.success)])
            if rec:
                out[f"{p}/trace"] = r.trace
                out[f"{p}/t"] = r.t
    return out


def main(argv):
    mode = argv[1]
    f = argv[2] if len(argv) > 2 else "wheel_identity_base.npz"
    c0 = time.process_time()
    out = run()
    print(f"run {time.process_time() - c0:.1f} CPU-s")
    if mode == "save":
        np.savez(f, **out)
        print("saved", len(out))
        return 0
    base = np.load(f)
    bad = 0
    if set(base.files) != set(out):
        print("keys differ:", sorted(set(base.files) ^ set(out)))
        return 1
    for k in base.files:
        a, b = base[k], out[k]
        if not np.array_equal(a, b, equal_nan=a.dtype.kind == "f"):
            bad += 1
            d = np.nanmax(np.abs(a - b)) if a.shape == b.shape else "shape"
            print("DIFF", k, d)
    nbytes = sum(base[k].tobytes() != out[k].tobytes() for k in base.files)
    print("IDENTICAL" if bad == 0 and nbytes == 0 else f"{bad} arrays differ, {nbytes} bytewise", len(base.files))
    return 0 if bad == 0 and nbytes == 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
