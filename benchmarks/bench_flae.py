"""Benchmark: FLAE in ``solve_wahba`` (numba batch) vs ESOQ2/QUEST/q-method and ahrs' FLAE.

Random two- and four-vector problems (unit vectors, noise 1e-3), one process; problems per
second (best of repeats, compilation excluded). Anchor: ``ahrs.filters.FLAE`` (the maintained
Python implementation of Wu et al. 2018, one two-vector problem per call,
``method='symbolic'``), run on a subset and reported side by side with the ratio, with the
attitude disagreement of its 'symbolic' and 'eig' variants from ours.

Usage: python benchmarks/bench_flae.py [--quick] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

from adcskit.attitude import quat_to_dcm, random_quat  # noqa: E402
from adcskit.determination import solve_wahba  # noqa: E402


def _problems(N, n, seed=0):
    rng = np.random.default_rng(seed)
    q = random_quat(N, rng=rng)
    ref = rng.normal(size=(N, n, 3))
    ref /= np.linalg.norm(ref, axis=-1, keepdims=True)
    body = np.einsum("kij,knj->kni", quat_to_dcm(q), ref) + 1e-3 * rng.normal(size=(N, n, 3))
    return body, ref


def _best(fn, repeats):
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--json", metavar="PATH")
    args = ap.parse_args(argv)
    N, n_anchor, repeats = (100_000, 500, 3) if args.quick else (1_000_000, 2000, 5)
    out = {}
    for n in (2, 4):
        body, ref = _problems(N, n)
        row = {}
        for method in ("flae", "esoq2", "quest", "q-method"):
            M = N if method != "q-method" else N // 10
            solve_wahba(body[:10], ref[:10], method=method)  # compile / load cache
            def ours(M=M, method=method, body=body, ref=ref):
                solve_wahba(body[:M], ref[:M], method=method, covariance=False)

            row[method] = M / _best(ours, repeats)
        res = solve_wahba(body, ref, method="flae")
        row["flae_fallback_fraction"] = float(res.fallback.mean())
        if n == 2:  # ahrs' FLAE takes exactly two vectors (accelerometer, magnetometer)
            try:
                from ahrs.filters import FLAE

                flae = FLAE()
                flae.a = np.array([0.5, 0.5])
                qa = np.empty((n_anchor, 4))

                def anchor(flae=flae, ref=ref, body=body, qa=qa):
                    for k in range(n_anchor):
                        flae.ref = ref[k]
                        qa[k] = flae.estimate(body[k, 0], body[k, 1], method="symbolic")

                row["ahrs_flae"] = n_anchor / _best(anchor, repeats)
                row["ratio_flae_vs_ahrs"] = row["flae"] / row["ahrs_flae"]
                # agreement with ours (ahrs' quaternion is scalar first; compare attitude
                # matrices, either transpose): its 'symbolic' variant (timed) and its 'eig'
                ours = quat_to_dcm(res.q[:n_anchor])
                for variant in ("symbolic", "eig"):
                    d = []
                    for k in range(n_anchor):
                        flae.ref = ref[k]
                        B = _ahrs_dcm(flae.estimate(body[k, 0], body[k, 1], method=variant))
                        d.append(min(_angle(ours[k], B), _angle(ours[k], B.T)))
                    d = np.degrees(d)
                    row[f"ahrs_{variant}_median_disagreement_deg"] = float(np.median(d))
                    row[f"ahrs_{variant}_max_disagreement_deg"] = float(np.max(d))
            except ImportError:
                pass
        out[f"n={n}"] = row
        print(f"n = {n}: " + ", ".join(f"{k} {v:.3g}" for k, v in row.items()))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=2)
    return out


def _ahrs_dcm(q_sf):
    """Rotation matrix of a scalar-first quaternion (ahrs' order), Hamilton convention."""
    w, x, y, z = q_sf / np.linalg.norm(q_sf)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def _angle(A, B):
    return float(np.arccos(np.clip((np.trace(A @ B.T) - 1) / 2, -1.0, 1.0)))


if __name__ == "__main__":
    main()
