"""Benchmark: batched MEKF (numba, all cores) vs a textbook NumPy MEKF and ahrs' EKF.

One process, one data set: a rotating spacecraft, gyro at every epoch (10 Hz), two unit
vectors every 10th epoch (1 Hz), NEES against the truth. Rates are sample-steps per second
(samples × epochs / wall time, best of repeats, numba compilation excluded); one step is a
propagation plus whatever measurement updates fall on that epoch.

* ``adcskit mekf_filter``: the batched compiled filter (``prange`` over samples);
* ``adcskit MultiplicativeEKF``: the validated stepping class, one Python call per step;
* anchor ``NumPy MEKF``: the same filter written the straightforward way, one sample at a
  time with NumPy 3×3/6×6 matrix algebra per step (Markley & Crassidis 2014 §6.2 with the
  small-angle ``Q`` of eq. 6.93 and a 3-vector update with ``scipy.linalg.solve`` and the
  Joseph form) — what a user writes without a compiled kernel;
* anchor ``ahrs EKF``: ``ahrs.filters.EKF.update`` (the maintained ``ahrs`` package's
  quaternion EKF: additive quaternion state, no gyro bias, an update with both vectors at
  every call) — a speed reference for a library attitude filter, not the same estimator.

Usage: python benchmarks/bench_mekf.py [--quick] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np
import scipy.linalg as sla

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

from adcskit.attitude import quat_multiply, quat_to_dcm, random_quat, skew  # noqa: E402
from adcskit.estimation import MultiplicativeEKF, mekf_filter  # noqa: E402
from adcskit.sensors import RateGyro  # noqa: E402

DT, SV, SU = 0.1, 1e-5, 1e-7
SIG = np.array([1e-3, 2e-3])
RATE = np.array([0.01, -0.02, 0.02])


def _data(N: int, T: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    r = np.array([[1.0, 0.2, -0.1], [0.1, 1.0, 0.4]])
    r /= np.linalg.norm(r, axis=1, keepdims=True)
    q = random_quat(N, rng=rng)
    half = 0.5 * np.linalg.norm(RATE) * DT
    dq = np.r_[np.sin(half) * RATE / np.linalg.norm(RATE), np.cos(half)]
    qt = np.empty((N, T, 4))
    for t in range(T):
        qt[:, t] = q
        q = quat_multiply(np.broadcast_to(dq, (N, 4)), q)
    gyro = RateGyro(sigma_v=SV, sigma_u=SU, rate_hz=1 / DT, bias0=[2e-3, -1e-3, 5e-4])
    m = gyro.measure(np.broadcast_to(RATE, (N, T, 3)), rng=rng)
    body = np.full((N, T, 2, 3), np.nan)
    A = quat_to_dcm(qt[:, ::10].reshape(-1, 4)).reshape(N, -1, 3, 3)
    for i in range(2):
        v = np.einsum("ntij,j->nti", A, r[i]) + SIG[i] * rng.standard_normal(A.shape[:2] + (3,))
        body[:, ::10, i] = v / np.linalg.norm(v, axis=-1, keepdims=True)
    q0 = qt[:, 0]
    P0 = np.diag([1e-4] * 3 + [1e-6] * 3)
    return q0, P0, m.omega, body, np.broadcast_to(r, (T, 2, 3)), qt, m.bias


def _numpy_mekf(q, b, P, gyro, body, ref):
    """Straightforward per-sample NumPy MEKF (the anchor)."""
    eye3 = np.eye(3)
    for t in range(gyro.shape[0]):
        if t:
            w = gyro[t - 1] - b
            wn = np.linalg.norm(w)
            W = skew(w)
            s, c = np.sin(wn * DT), np.cos(wn * DT)
            Phi = np.eye(6)
            Phi[:3, :3] = eye3 - W * s / wn + W @ W * (1 - c) / wn**2
            Phi[:3, 3:] = W * (1 - c) / wn**2 - eye3 * DT - W @ W * (wn * DT - s) / wn**3
            Q = np.zeros((6, 6))
            Q[:3, :3] = (SV**2 * DT + SU**2 * DT**3 / 3) * eye3
            Q[:3, 3:] = Q[3:, :3] = -0.5 * SU**2 * DT**2 * eye3
            Q[3:, 3:] = SU**2 * DT * eye3
            dq = np.r_[np.sin(wn * DT / 2) * w / wn, np.cos(wn * DT / 2)]
            q = quat_multiply(dq, q)
            P = Phi @ P @ Phi.T + Q
        for j in range(body.shape[1]):
            if np.isnan(body[t, j, 0]):
                continue
            bh = quat_to_dcm(q) @ ref[t, j]
            H = np.hstack([skew(bh), np.zeros((3, 3))])
            R = SIG[j] ** 2 * eye3
            S = H @ P @ H.T + R
            K = sla.solve(S, H @ P, assume_a="pos").T
            dx = K @ (body[t, j] - bh)
            IKH = np.eye(6) - K @ H
            P = IKH @ P @ IKH.T + K @ R @ K.T
            dq = np.r_[0.5 * dx[:3], 1.0]
            q = quat_multiply(dq / np.linalg.norm(dq), q)
            b = b + dx[3:]
    return q, b, P


def _best(fn, repeats):
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smaller problem sizes")
    ap.add_argument("--json", metavar="PATH", help="write the results as JSON")
    args = ap.parse_args(argv)
    N, T = (500, 1000) if args.quick else (2000, 2000)
    n_anchor, repeats = (2, 2) if args.quick else (3, 3)

    q0, P0, gyro, body, ref, qt, bt = _data(N, T)
    b0 = np.zeros(3)
    kw = dict(sigma_v=SV, sigma_u=SU, q_true=qt, b_true=bt)
    mekf_filter(q0[:2], b0, P0, np.arange(20) * DT, gyro[:2, :20], body[:2, :20], ref[:20], SIG,
                **{**kw, "q_true": qt[:2, :20], "b_true": bt[:2, :20]})  # compile / load cache
    t = np.arange(T) * DT
    holder = {}

    def ours():
        holder["res"] = mekf_filter(q0, b0, P0, t, gyro, body, ref, SIG, **kw)

    rate_ours = N * T / _best(ours, repeats)
    c0 = time.process_time()  # CPU seconds of all threads: less sensitive to a loaded machine
    ours()
    cpu_ours = N * T / (time.process_time() - c0)
    res = holder["res"]

    def stepping():
        f = MultiplicativeEKF(q0[0], b0, P0, sigma_v=SV, sigma_u=SU)
        for k in range(T):
            if k:
                f.propagate(gyro[0, k - 1], DT)
            for j in range(2):
                if not np.isnan(body[0, k, j, 0]):
                    f.update_vector(body[0, k, j], ref[k, j], SIG[j])

    rate_step = T / _best(stepping, repeats)

    def anchor():
        for k in range(n_anchor):
            _numpy_mekf(q0[k], b0, P0, gyro[k], body[k], ref)

    rate_numpy = n_anchor * T / _best(anchor, repeats)
    # agreement of the anchor with ours (it uses the small-angle Q and a first-order reset):
    qa, ba, _ = _numpy_mekf(q0[0], b0, P0, gyro[0], body[0], ref)
    dq = quat_multiply(qa, res.q[0, -1] * [-1, -1, -1, 1])
    diff_rad = float(2 * np.arcsin(min(1.0, np.linalg.norm(dq[:3]))))

    rate_ahrs = None
    try:
        from ahrs.filters import EKF

        acc = body[0, ::10, 0].repeat(10, axis=0)[:T] * 9.81
        mag = body[0, ::10, 1].repeat(10, axis=0)[:T] * 50.0

        def ahrs_run():  # ahrs runs the whole sequence in its constructor (its own references)
            EKF(gyr=gyro[0], acc=acc, mag=mag, frequency=1 / DT, magnetic_ref=60.0)

        rate_ahrs = T / _best(ahrs_run, repeats)
    except ImportError:  # ahrs is in the dev extra only
        pass

    out = {
        "problem": {"samples": N, "epochs": T, "dt_s": DT, "vectors_every": 10},
        "numba_threads": int(os.environ.get("NUMBA_NUM_THREADS", os.cpu_count() or 1)),
        "ours_batch_sample_steps_per_s": rate_ours,
        "ours_batch_sample_steps_per_cpu_s": cpu_ours,
        "ours_stepping_class_steps_per_s": rate_step,
        "anchor_numpy_mekf_steps_per_s": rate_numpy,
        "anchor_ahrs_ekf_steps_per_s": rate_ahrs,
        "ratio_batch_vs_numpy": rate_ours / rate_numpy,
        "ratio_batch_vs_ahrs": None if rate_ahrs is None else rate_ours / rate_ahrs,
        "final_attitude_difference_ours_vs_numpy_rad": diff_rad,
        "mean_nees_last_epoch": float(res.mean_nees[-1]),
    }
    print(f"MEKF, {N} samples x {T} epochs (gyro 10 Hz, two vectors 1 Hz, NEES on)")
    print(f"  adcskit mekf_filter (numba, batch)  : {rate_ours:10.3e} sample-steps/s")
    print(f"    (per CPU-second of all threads: {cpu_ours:10.3e} sample-steps)")
    print(f"  adcskit MultiplicativeEKF (stepping): {rate_step:10.3e} steps/s")
    print(f"  anchor NumPy MEKF (per sample)      : {rate_numpy:10.3e} steps/s  "
          f"-> ratio {rate_ours / rate_numpy:.0f}x")
    if rate_ahrs is not None:
        print(f"  anchor ahrs.filters.EKF             : {rate_ahrs:10.3e} steps/s  "
              f"-> ratio {rate_ours / rate_ahrs:.0f}x")
    print(f"  ours vs NumPy anchor, final attitude: {diff_rad:.2e} rad apart; "
          f"mean NEES (last epoch) {res.mean_nees[-1]:.2f}")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=2)
    return out


if __name__ == "__main__":
    main()
