"""MEKF consistency numbers for docs/estimation-mekf.md (not a speed benchmark).

Monte-Carlo runs of the scenario of ``tests/estimation/test_mekf.py``: rotating spacecraft
(ω = [0.01, −0.02, 0.02] rad/s), gyro at 10 Hz (σv = 1e-5 rad/s^0.5, σu = 1e-7 rad/s^1.5,
:class:`adcskit.sensors.RateGyro`), two unit vectors at 1 Hz (σ = 1 and 2 mrad), initial
errors drawn from ``P0`` (1° per axis, 1e-3 rad/s bias), 300 s. For each seed: mean NEES at
the last epoch against the χ² 95 % band, the fraction of epochs whose mean NEES is inside the
band, the time-averaged NEES and NIS, and the final bias and attitude errors.

Usage: python benchmarks/mekf_consistency.py [--runs N] [--seeds S] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import os
import sys

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


def run(N: int, seed: int) -> dict:
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
    bt = np.empty((N, T, 3))
    gyro = np.empty((N, T, 3))
    for k in range(N):  # one RateGyro per run: its initial bias is drawn from P0
        m = RateGyro(sigma_v=SV, sigma_u=SU, rate_hz=1 / DT, bias0=b_hat0[k] + x0[k, 3:]).measure(
            np.broadcast_to(RATE, (T, 3)), rng=rng)
        gyro[k], bt[k] = m.omega, m.bias
    body = np.full((N, T, 2, 3), np.nan)
    A = quat_to_dcm(qt[:, ::10].reshape(-1, 4)).reshape(N, -1, 3, 3)
    for i in range(2):
        v = np.einsum("ntij,j->nti", A, r[i]) + SIG[i] * rng.standard_normal(A.shape[:2] + (3,))
        body[:, ::10, i] = v / np.linalg.norm(v, axis=-1, keepdims=True)
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


def main(argv: list[str] | None = None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--json", metavar="PATH")
    args = ap.parse_args(argv)
    out = [run(args.runs, seed) for seed in range(args.seeds)]
    for o in out:
        print(f"seed {o['seed']}: NEES(last) {o['mean_nees_last_epoch']:.2f} "
              f"band [{o['band_95'][0]:.2f}, {o['band_95'][1]:.2f}] in={o['last_epoch_in_band']}; "
              f"epochs in band {100 * o['fraction_of_epochs_in_band']:.0f} %; "
              f"time-mean NEES {o['time_mean_nees_after_100s']:.2f}; NIS {o['mean_nis_after_100s']:.3f}; "
              f"bias rms {o['final_bias_rms_rad_s']:.2e} (filter σ {o['final_bias_sigma_filter_rad_s']:.2e}); "
              f"attitude rms {o['final_attitude_rms_rad']:.2e} rad "
              f"(filter σ {o['final_attitude_sigma_filter_rad']:.2e})")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=2)
    return out


if __name__ == "__main__":
    main()
