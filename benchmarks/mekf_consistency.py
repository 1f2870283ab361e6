"""MEKF consistency numbers for docs/estimation-mekf.md (not a speed benchmark).

Monte-Carlo runs of the scenario of ``tests/estimation/test_mekf.py``: rotating spacecraft
(ω = [0.01, −0.02, 0.02] rad/s), gyro at 10 Hz (σv = 1e-5 rad/s^0.5, σu = 1e-7 rad/s^1.5,
:class:`adcskit.sensors.RateGyro`), two unit vectors at 1 Hz (σ = 1 and 2 mrad), initial
errors drawn from ``P0`` (1° per axis, 1e-3 rad/s bias), 300 s. For each seed: mean NEES at
the last epoch against the χ² 95 % band, the fraction of epochs whose mean NEES is inside the
band, the time-averaged NEES and NIS, and the final bias and attitude errors.

Closed loop (``--loop``): the MEKF inside :func:`adcskit.simulation.simulate` (plant, gyro,
sensors, controller and thrusters all in the loop), ``--loop-runs`` samples, seed 7, 300 s at
dt = 0.05 s, NEES recorded every 0.5 s, each case with the default measurement underweighting
(p = 0.2) and without it (p = 0, the plain EKF update):

* ``default``: ``Scenario(estimator=EstimatorSpec(kind="mekf", init_error_deg=1.0))`` (hold at
  the identity in the default scenario's GEO orbit, 35786 km, gravity gradient only; S3's GEO
  satellite and thrusters; sun sensor 1 Hz 0.005°, magnetometer 1 Hz 0.5°, gyro 10 Hz) —
  issue 23's reproduction;
* ``slew``: the same with a 30° step about z at t = 5 s (the gyro rate and the sensor
  geometry change during the estimation transient);
* ``star-tracker``: no sun sensor or magnetometer, a 10 arcsec star tracker at 1 Hz.

Perfect-knowledge baseline (``--baseline``): the ``default`` case with ``estimator.kind =
"truth"`` (no initial error; a true 1° initial attitude error per axis), beside the MEKF with
a 1° and a 0.01° prior, p = 0.2 and 0 (:data:`BASELINES`).

NIS (``--nis standalone,static-default``): the standalone scenario, or the static analogue
of ``default`` (below), through the stepping filter with p = 0.2 and p = 0, the mean NIS as
the filter reports it (underweighted updates use the inflated variance) beside the plain NIS
``νᵀ (H P Hᵀ + σ² I)⁻¹ ν`` of the same prior (:func:`run_nis`).

Remedy choice (``--choice``): the standalone filter on a static analogue of ``default`` (two
fixed directions at 1 Hz with σ = 0.005° and 0.5°, the simulator's default gyro at 10 Hz,
1° prior, 300 s), with underweighting ``p`` in {0, 0.05, 0.2, 0.5, 1} and with the plain
update initialised from a Wahba solution (q-method) of the first measurement pair and its
covariance (Markley & Crassidis 2014 eq. 5.66), 2 seeds.

For the closed-loop cases: the ensemble-mean NEES at 1 s, its time mean over 100–300 s against the χ²(6N)/N
95 % band of one epoch's mean of N values, and the fraction of 100–300 s epochs inside it.
``--figure PATH`` draws the ensemble-mean NEES traces.

Usage: python benchmarks/mekf_consistency.py [--runs N] [--seeds S] [--json PATH]
       [--choice] [--choice-init D,D] [--loop] [--loop-sweep P,P] [--loop-runs N]
       [--figure PATH] [--no-standalone] [--baseline] [--nis CASES]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

from adcskit.attitude import quat_inverse, quat_multiply, quat_to_dcm, random_quat  # noqa: E402
from adcskit.estimation import chi2_band, mekf_filter  # noqa: E402
from adcskit.sensors import RateGyro  # noqa: E402

DT, T = 0.1, 3001
SV, SU = 1e-5, 1e-7
SIG = np.array([1e-3, 2e-3])
RATE = np.array([0.01, -0.02, 0.02])
P0 = np.diag([np.radians(1.0) ** 2] * 3 + [1e-6] * 3)


def _rotvec_quat(r):
    a = np.linalg.norm(r, axis=-1, keepdims=True)
    s = np.where(a > 0, np.sin(a / 2) / np.where(a > 0, a, 1.0), 0.5)
    return np.concatenate([s * r, np.cos(a / 2)], axis=-1)


def _standalone_data(N: int, seed: int):
    """Truth, gyro readings and vector measurements of the standalone scenario (seeded)."""
    rng = np.random.default_rng(seed)
    r = np.array([[1.0, 0.2, -0.1], [0.1, 1.0, 0.4]])
    r /= np.linalg.norm(r, axis=1, keepdims=True)
    q_hat0 = random_quat(N, rng=rng)
    x0 = rng.standard_normal((N, 6)) @ np.linalg.cholesky(P0).T
    q = quat_multiply(_rotvec_quat(x0[:, :3]), q_hat0)
    b_hat0 = np.full((N, 3), 2e-3)
    dq = _rotvec_quat(RATE * DT)
    qt = np.empty((N, T, 4))
    for t in range(T):
        qt[:, t] = q * np.where(q[:, 3:] < 0, -1.0, 1.0)
        q = quat_multiply(np.broadcast_to(dq, (N, 4)), q)
    bt, gyro, body = _gyro_and_vectors(rng, qt, r, SIG, SV, SU, DT, np.broadcast_to(RATE, (T, 3)), b_hat0 + x0[:, 3:])
    return r, q_hat0, b_hat0, qt, bt, gyro, body


def _gyro_and_vectors(rng, qt, r, sig, sv, su, dt, rate, bias0):
    """Gyro readings and true biases (one RateGyro per run, initial bias ``bias0[k]``) and two
    unit vector measurements every 10th step (noise ``sig``; NaN between), drawn from ``rng``."""
    N, T = qt.shape[:2]
    bt = np.empty((N, T, 3))
    gyro = np.empty((N, T, 3))
    for k in range(N):
        m = RateGyro(sigma_v=sv, sigma_u=su, rate_hz=1 / dt, bias0=bias0[k]).measure(rate, rng=rng)
        gyro[k], bt[k] = m.omega, m.bias
    body = np.full((N, T, 2, 3), np.nan)
    A = quat_to_dcm(qt[:, ::10].reshape(-1, 4)).reshape(N, -1, 3, 3)
    for i in range(2):
        v = np.einsum("ntij,j->nti", A, r[i]) + sig[i] * rng.standard_normal(A.shape[:2] + (3,))
        body[:, ::10, i] = v / np.linalg.norm(v, axis=-1, keepdims=True)
    return bt, gyro, body


def run(N: int, seed: int) -> dict:
    r, q_hat0, b_hat0, qt, bt, gyro, body = _standalone_data(N, seed)
    res = mekf_filter(q_hat0, b_hat0, P0, np.arange(T) * DT, gyro, body,
                      np.broadcast_to(r, (T, 2, 3)), SIG, sigma_v=SV, sigma_u=SU, q_true=qt,
                      b_true=bt)
    lo, hi = chi2_band(6, N)
    err_q = quat_multiply(qt[:, -1], quat_inverse(res.q[:, -1]))
    att_err = 2 * np.arcsin(np.clip(np.linalg.norm(err_q[:, :3], axis=1), 0, 1))
    return {
        "seed": seed,
        "runs": N,
        "band_95": [lo, hi],
        "mean_nees_last_epoch": float(res.mean_nees[-1]),
        "last_epoch_in_band": bool(lo <= res.mean_nees[-1] <= hi),
        "fraction_of_epochs_in_band": float(np.mean((res.mean_nees >= lo) & (res.mean_nees <= hi))),
        "time_mean_nees_after_100s": float(np.mean(res.mean_nees[1000:])),
        "mean_nis_after_100s": float(np.nanmean(res.nis[:, 1000:])),
        "final_bias_rms_rad_s": float(np.sqrt(np.mean((res.b[:, -1] - bt[:, -1]) ** 2))),
        "final_bias_sigma_filter_rad_s": float(np.sqrt(np.mean(res.P_diag[:, -1, 3:]))),
        "final_attitude_rms_rad": float(np.sqrt(np.mean(att_err**2))),
        "final_attitude_sigma_filter_rad": float(np.sqrt(np.mean(res.P_diag[:, -1, :3].sum(axis=1)))),
    }


def run_choice(N: int, seed: int, init_deg: float = 1.0) -> list[dict]:
    """Underweighting factors and Wahba initialisation on the static analogue of ``default``
    (prior σ ``init_deg`` per axis)."""
    from adcskit.determination import solve_wahba

    r, q_hat0, p0, qt, bt, gyro, body = _choice_data(N, seed, init_deg)
    sv, su, dt, T = CHOICE_SV, CHOICE_SU, 0.1, 3001
    sig = CHOICE_SIG
    t = np.arange(T) * dt
    ref = np.broadcast_to(r, (T, 2, 3))
    lo, hi = chi2_band(6, N)
    rows = []

    def row(name, res):
        late = res.mean_nees[1000:]
        rows.append({"seed": seed, "runs": N, "init_deg": init_deg, "variant": name, "band_95": [lo, hi],
                     "mean_nees_at_1s": float(res.mean_nees[10]),
                     "time_mean_nees_100_300s": float(np.mean(late)),
                     "fraction_of_epochs_in_band_100_300s": float(np.mean((late >= lo) & (late <= hi)))})

    for p in (0.0, 0.01, 0.05, 0.2, 0.5, 1.0):
        row(f"underweight p = {p:g}", mekf_filter(q_hat0, np.zeros(3), p0, t, gyro, body, ref, sig, sigma_v=sv,
                                                  sigma_u=su, q_true=qt, b_true=bt, underweight=p))
    w = solve_wahba(body[:, 0], r, weights=1 / sig**2)
    p0w = np.zeros((N, 6, 6))
    p0w[:, :3, :3] = w.cov
    p0w[:, 3:, 3:] = p0[3:, 3:]
    b2 = body.copy()
    b2[:, 0] = np.nan  # the first pair is in the Wahba prior
    row("Wahba initialisation, p = 0", mekf_filter(w.q, np.zeros(3), p0w, t, gyro, b2, ref, sig, sigma_v=sv,
                                                   sigma_u=su, q_true=qt, b_true=bt, underweight=0.0))
    return rows


#: The static analogue of the closed-loop ``default`` case (``--choice``): the simulator's
#: default gyro (σv, σu) and the sun sensor's and magnetometer's σ.
CHOICE_SV, CHOICE_SU, CHOICE_SIG = 3.16e-7, 3.16e-10, np.radians([0.005, 0.5])


def _choice_data(N: int, seed: int, init_deg: float = 1.0):
    """Truth, gyro readings and vectors of the static analogue (prior σ ``init_deg``)."""
    sv, su, dt, T = CHOICE_SV, CHOICE_SU, 0.1, 3001
    sig = CHOICE_SIG
    p0 = np.diag([np.radians(init_deg) ** 2] * 3 + [(np.radians(1.0) / 3600) ** 2] * 3)
    rng = np.random.default_rng(seed)
    r = np.array([[1.0, 0.2, -0.1], [0.3, 1.0, 0.4]])
    r /= np.linalg.norm(r, axis=1, keepdims=True)
    q_hat0 = random_quat(N, rng=rng)
    x0 = rng.standard_normal((N, 6)) @ np.sqrt(p0)
    q = quat_multiply(_rotvec_quat(x0[:, :3]), q_hat0)
    qt = np.broadcast_to((q * np.where(q[:, 3:] < 0, -1.0, 1.0))[:, None], (N, T, 4))
    bt, gyro, body = _gyro_and_vectors(rng, qt, r, sig, sv, su, dt, np.zeros((T, 3)), x0[:, 3:])
    return r, q_hat0, p0, qt, bt, gyro, body


def _plain_nis(f, v_body, v_ref, sigma) -> float:
    """NIS of one vector measurement against the filter's prior, ``νᵀ (H P Hᵀ + σ² I)⁻¹ ν``
    (``ν = b̃ − A(q̂) r``, ``H = [[A(q̂) r ×], 0]``): the textbook statistic, whatever the update
    then does. For a plain (not underweighted) update it equals the kernel's sequential
    ``Σ ν_i² / s_i`` (the sequential scalar updates are the 3-vector update)."""
    b_hat = quat_to_dcm(f.q) @ v_ref
    nu = v_body / np.linalg.norm(v_body) - b_hat
    bx = np.array([[0.0, -b_hat[2], b_hat[1]], [b_hat[2], 0.0, -b_hat[0]], [-b_hat[1], b_hat[0], 0.0]])
    S = bx @ f.P[:3, :3] @ bx.T + sigma**2 * np.eye(3)
    return float(nu @ np.linalg.solve(S, nu))


def run_nis(N: int, seed: int, underweight: float = 0.2, case: str = "standalone") -> dict:
    """Mean NIS of the standalone scenario as the filter reports it (with underweighting the
    inflated ``S = (1 + p) h P hᵀ + σ²`` while ``h P hᵀ > σ²``) and the plain NIS
    (:func:`_plain_nis`, computed before each update of the stepping filter), over the whole
    run and over 100-300 s, against the χ²(2 M)/M 95 % band of the M values' mean.
    ``case``: ``"standalone"`` (σ = 1, 2 mrad, :func:`run`) or ``"static-default"`` (the
    1° static analogue of the closed-loop ``default`` case, σ = 0.005° and 0.5°,
    :func:`run_choice`)."""
    from adcskit.estimation import MultiplicativeEKF

    if case == "standalone":
        r, q_hat0, b_hat0, qt, bt, gyro, body = _standalone_data(N, seed)
        p0, sv, su, sig = np.broadcast_to(P0, (N, 6, 6)), SV, SU, SIG
    else:
        r, q_hat0, p0, qt, bt, gyro, body = _choice_data(N, seed, 1.0)
        b_hat0, p0, sv, su, sig = np.zeros((N, 3)), np.broadcast_to(p0, (N, 6, 6)), CHOICE_SV, CHOICE_SU, CHOICE_SIG
    rep = np.full((N, T, 2), np.nan)
    plain = np.full((N, T, 2), np.nan)
    for k in range(N):
        f = MultiplicativeEKF(q_hat0[k], b_hat0[k], p0[k], sigma_v=sv, sigma_u=su, underweight=underweight)
        for t in range(T):
            if t > 0:
                f.propagate(gyro[k, t - 1], DT)
            for j in range(2):
                if np.isfinite(body[k, t, j, 0]):
                    plain[k, t, j] = _plain_nis(f, body[k, t, j], r[j], sig[j])
                    rep[k, t, j] = f.update_vector(body[k, t, j], r[j], sig[j])
    out = {"seed": seed, "runs": N, "underweight": underweight, "case": case}
    for label, sl in (("whole_run", slice(None)), ("after_100s", slice(1000, None))):
        a, b = rep[:, sl], plain[:, sl]
        m = int(np.count_nonzero(np.isfinite(a)))
        lo, hi = chi2_band(2, m)
        out[label] = {"count": m, "band_95": [lo, hi], "nis_reported": float(np.nanmean(a)),
                      "nis_plain": float(np.nanmean(b)),
                      "epochs_inflated": int(np.count_nonzero(np.abs(a - b) > 1e-6 * np.abs(b)))}
    return out


LOOP_CASES = ("default", "slew", "star-tracker")


def loop_scenario(case: str, underweight: float, *, init_error_deg: float = 1.0, kind: str = "mekf",
                  initial_attitude_deg: float = 0.0, initial_rotvec_deg: tuple = (0.0, 0.0, 0.0)):
    """The closed-loop scenario of one ``--loop`` case (see the module docstring); ``kind``,
    ``init_error_deg``, ``initial_attitude_deg`` (the true attitude's dispersion per axis) and
    ``initial_rotvec_deg`` (the true initial attitude) for the ``--baseline`` cases."""
    from adcskit.simulation import (
        DispersionSpec,
        EstimatorSpec,
        GuidanceSpec,
        Scenario,
        SensorSpec,
        SimSpec,
    )

    est = EstimatorSpec(kind=kind, init_error_deg=init_error_deg, underweight=underweight)
    sim = SimSpec(dt=0.05, t_final=300.0, metrics_from_s=100.0, record_every=10)
    kw = {"dispersions": DispersionSpec(initial_attitude_deg=initial_attitude_deg)} if initial_attitude_deg else {}
    if case == "slew":
        kw["guidance"] = GuidanceSpec(kind="step", target_rotvec_deg=(0.0, 0.0, 30.0), t_step=5.0)
    elif case == "star-tracker":
        kw["sensors"] = SensorSpec(sun_rate_hz=0.0, mag_rate_hz=0.0, star_tracker_rate_hz=1.0,
                                   star_tracker_noise_arcsec=10.0)
    return Scenario(estimator=est, sim=sim, initial_rotvec_deg=initial_rotvec_deg, **kw)


def run_loop(case: str, underweight: float, N: int, **kw) -> dict:
    from adcskit.simulation import simulate

    res = simulate(loop_scenario(case, underweight, **kw), N, rng=7, record=True)
    nees = res.trace[:, :, res.channels.index("nees")]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # t = 0: no NEES recorded yet
        mean = np.nanmean(nees, axis=0)
    lo, hi = chi2_band(6, N)
    late = (res.t >= 100.0) & (res.t <= 300.0)
    i1 = int(np.argmin(np.abs(res.t - 1.0)))
    return {
        "case": case,
        "underweight": underweight,
        "runs": N,
        "band_95": [lo, hi],
        "mean_nees_at_1s": float(mean[i1]),
        "time_mean_nees_100_300s": float(np.nanmean(mean[late])),
        "time_mean_in_band": bool(lo <= np.nanmean(mean[late]) <= hi),
        "fraction_of_epochs_in_band_100_300s": float(np.mean((mean[late] >= lo) & (mean[late] <= hi))),
        "max_error_deg_p95": float(np.percentile(res.metrics["pointing_max_deg"], 95)),
        "rms_error_deg_mean": float(np.mean(res.metrics["pointing_rms_deg"])),
        "propellant_mean": float(np.mean(res.metrics["propellant_kg"])),
        "knowledge_rms_deg_mean": float(np.mean(res.metrics["knowledge_rms_deg"])),
        "fired_fraction": float(np.mean(res.metrics["propellant_kg"] > 0)),
        "t": res.t.tolist(),
        "mean_nees": mean.tolist(),
    }


#: ``--baseline``: the ``default`` case's cost of the estimator beside perfect knowledge
#: (label, run_loop keywords).
BASELINES = (
    ("truth, no initial error", {"kind": "truth", "underweight": 0.2}),
    ("truth, 1° initial attitude error per axis", {"kind": "truth", "underweight": 0.2, "initial_attitude_deg": 1.0}),
    *((f"truth, 1° initial rotation about {name}", {"kind": "truth", "underweight": 0.2,
                                                   "initial_rotvec_deg": tuple(float(x) for x in axis)})
      for name, axis in (("x", (1, 0, 0)), ("y", (0, 1, 0)), ("z", (0, 0, 1)),
                         ("(1,1,1)", np.ones(3) / np.sqrt(3)))),
    ("MEKF 1° prior, p = 0.2", {"underweight": 0.2}),
    ("MEKF 1° prior, p = 0", {"underweight": 0.0}),
    ("MEKF 0.01° prior, p = 0.2", {"underweight": 0.2, "init_error_deg": 0.01}),
    ("MEKF 0.01° prior, p = 0", {"underweight": 0.0, "init_error_deg": 0.01}),
)


def loop_figure(rows: list[dict], path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(LOOP_CASES), figsize=(4.2 * len(LOOP_CASES), 3.4), sharey=True)
    for ax, case in zip(np.atleast_1d(axes), LOOP_CASES):
        for r in (r for r in rows if r["case"] == case):
            lab = (f"underweighting p = {r['underweight']:g}" if r["underweight"] > 0
                   else "plain EKF (p = 0)")
            ax.plot(r["t"], r["mean_nees"], lw=0.9, label=f"{lab}: {r['time_mean_nees_100_300s']:.2f}")
            lo, hi = r["band_95"]
        ax.axhspan(lo, hi, color="0.8", label=f"χ²(6N)/N 95 % band, N = {rows[0]['runs']}")
        ax.axvspan(100, 300, color="0.95", zorder=0)
        ax.set_yscale("log")
        ax.set_title(case)
        ax.set_xlabel("t [s]")
        ax.legend(fontsize=7, loc="upper right")
    np.atleast_1d(axes)[0].set_ylabel("ensemble-mean NEES (6 states)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--json", metavar="PATH")
    ap.add_argument("--loop", action="store_true", help="also run the closed-loop cases")
    ap.add_argument("--loop-runs", type=int, default=200)
    ap.add_argument("--figure", metavar="PATH", help="NEES traces of the closed-loop cases (PNG)")
    ap.add_argument("--no-standalone", action="store_true", help="skip the standalone-filter seeds")
    ap.add_argument("--choice", action="store_true", help="underweighting factors vs Wahba initialisation")
    ap.add_argument("--choice-init", default="1", help="prior sigmas [deg] of --choice, comma-separated")
    ap.add_argument("--loop-sweep", metavar="P,P,...", help="closed-loop default case for these p only")
    ap.add_argument("--baseline", action="store_true",
                    help="closed-loop default case: MEKF priors and p beside perfect knowledge (truth)")
    ap.add_argument("--nis", metavar="CASE,CASE", help="reported vs plain NIS (stepping filter) of these cases: "
                    "standalone, static-default")
    args = ap.parse_args(argv)
    out = [] if args.no_standalone else [run(args.runs, seed) for seed in range(args.seeds)]
    for o in out:
        print(f"seed {o['seed']}: NEES(last) {o['mean_nees_last_epoch']:.2f} "
              f"band [{o['band_95'][0]:.2f}, {o['band_95'][1]:.2f}] in={o['last_epoch_in_band']}; "
              f"epochs in band {100 * o['fraction_of_epochs_in_band']:.0f} %; "
              f"time-mean NEES {o['time_mean_nees_after_100s']:.2f}; NIS {o['mean_nis_after_100s']:.3f}; "
              f"bias rms {o['final_bias_rms_rad_s']:.2e} (filter σ {o['final_bias_sigma_filter_rad_s']:.2e}); "
              f"attitude rms {o['final_attitude_rms_rad']:.2e} rad "
              f"(filter σ {o['final_attitude_sigma_filter_rad']:.2e})", flush=True)
    nis_rows = []
    for case, uw in ((c, p) for c in (args.nis.split(",") if args.nis else ()) for p in (0.2, 0.0)):
        for seed in range(args.seeds):
            o = run_nis(args.runs, seed, underweight=uw, case=case)
            nis_rows.append(o)
            for label in ("whole_run", "after_100s"):
                w = o[label]
                print(f"nis {case} p={uw:g} seed {seed} {label:10s}: reported {w['nis_reported']:.4f}, plain {w['nis_plain']:.4f}; "
                      f"band [{w['band_95'][0]:.4f}, {w['band_95'][1]:.4f}] of {w['count']} values; "
                      f"{w['epochs_inflated']} underweighted updates", flush=True)
    choice_rows = []
    if args.choice:
        for init, seed in ((float(i), s) for i in args.choice_init.split(",") for s in (0, 1)):
            for r in run_choice(args.runs, seed, init):
                choice_rows.append(r)
                print(f"choice {init:g} deg seed {seed} {r['variant']:28s}: NEES(1 s) {r['mean_nees_at_1s']:.2f}; time mean "
                      f"100-300 s {r['time_mean_nees_100_300s']:.3f} band [{r['band_95'][0]:.2f}, "
                      f"{r['band_95'][1]:.2f}]; epochs in band {100 * r['fraction_of_epochs_in_band_100_300s']:.0f} %",
                      flush=True)
    loop_rows = []
    if args.loop_sweep:
        for uw in (float(p) for p in args.loop_sweep.split(",")):
            r = run_loop("default", uw, args.loop_runs)
            loop_rows.append(r)
            print(f"sweep default p={uw:g}: NEES(1 s) {r['mean_nees_at_1s']:.2f}; time mean 100-300 s "
                  f"{r['time_mean_nees_100_300s']:.3f} in={r['time_mean_in_band']}; pointing rms "
                  f"{r['rms_error_deg_mean']:.4f} deg; knowledge rms {r['knowledge_rms_deg_mean']:.4f} deg; "
                  f"propellant {r['propellant_mean']:.4g}", flush=True)
    if args.baseline:
        for label, kw in BASELINES:
            r = run_loop("default", N=args.loop_runs, **kw)
            r["case"] = f"baseline: {label}"
            loop_rows.append(r)
            print(f"baseline {label:42s}: pointing rms {r['rms_error_deg_mean']:.4f} deg; propellant "
                  f"{r['propellant_mean']:.4g} kg; fired {100 * r['fired_fraction']:.0f} % of samples; knowledge rms "
                  f"{r['knowledge_rms_deg_mean']:.4f} deg; NEES time mean {r['time_mean_nees_100_300s']:.3f}",
                  flush=True)
    if args.loop:
        for case in LOOP_CASES:
            for uw in (0.2, 0.0):
                r = run_loop(case, uw, args.loop_runs)
                loop_rows.append(r)
                print(f"loop {case:12s} p={uw:g}: NEES(1 s) {r['mean_nees_at_1s']:.2f}; time mean "
                      f"100-300 s {r['time_mean_nees_100_300s']:.2f} band [{r['band_95'][0]:.2f}, "
                      f"{r['band_95'][1]:.2f}] in={r['time_mean_in_band']}; epochs in band "
                      f"{100 * r['fraction_of_epochs_in_band_100_300s']:.0f} %; knowledge rms "
                      f"{r['knowledge_rms_deg_mean']:.2e} deg; p95 max error {r['max_error_deg_p95']:.3f} deg",
                      flush=True)
        if args.figure:
            loop_figure(loop_rows, args.figure)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(out + nis_rows + choice_rows + [{k: v for k, v in r.items() if k not in ("t", "mean_nees")} for r in loop_rows],
                      fh, indent=2)
    return out + nis_rows + choice_rows + loop_rows


if __name__ == "__main__":
    main()
