"""Can the closed-loop kernel's RK4 step go faster by working on several samples at once?

The kernel (:func:`adcskit.simulation._kernels.sample_loop`) advances one sample over all
steps; its RK4 step (:func:`~adcskit.simulation._kernels.rk4_step`, ≈ 70 ns of the full chain's
≈ 210 ns per sample-step) was thought to be a serial dependency chain that two samples advanced
together would overlap (instruction-level parallelism). Three ways of advancing several samples,
each bit-identical to ``rk4_step`` sample by sample (checked here, ``np.array_equal``), single
thread, CPU time per sample-step, best of ``--repeats``:

* ``calls``: two ``rk4_step`` calls per iteration on two independent samples;
* ``interleaved``: one function that computes the two samples' four stages alternately
  (A's stage 1, B's stage 1, A's stage 2 ...), so the two chains sit side by side in the
  instruction stream;
* ``lanes L``: L samples in structure-of-arrays layout, every operation a loop over the lanes
  (LLVM's loop vectoriser turns those into SIMD; same IEEE operations per lane, no FMA).

Run::

    PYTHONPATH=src python benchmarks/experiments/kernel_ilp.py [--repeats 3] [--steps 2000000]

Results: docs/benchmarks.md, "Closed-loop kernel: several samples at once".
"""

import argparse
import json
import math
import time

import numpy as np
from numba import njit
from numba.extending import register_jitable

from adcskit.attitude._device import unit_q4_pos
from adcskit.simulation._kernels import _rhs, rk4_step

DT = 0.01


@njit(error_model="numpy")
def serial(J, Ji, n, X, T):
    """Each sample over ``n`` steps, one after the other (the kernel's order)."""
    out = np.empty_like(X)
    for lane in range(X.shape[1]):
        q0, q1, q2, q3 = X[0, lane], X[1, lane], X[2, lane], X[3, lane]
        w0, w1, w2 = X[4, lane], X[5, lane], X[6, lane]
        for _ in range(n):
            q0, q1, q2, q3, w0, w1, w2 = rk4_step(q0, q1, q2, q3, w0, w1, w2, J[:, lane], Ji[:, lane],
                                                  T[0, lane], T[1, lane], T[2, lane], DT)
        out[0, lane], out[1, lane], out[2, lane], out[3, lane] = q0, q1, q2, q3
        out[4, lane], out[5, lane], out[6, lane] = w0, w1, w2
    return out


@njit(error_model="numpy")
def calls(J, Ji, n, X, T):
    """Two samples per iteration, one ``rk4_step`` call each (``X.shape[1]`` even)."""
    out = np.empty_like(X)
    for a in range(0, X.shape[1], 2):
        b = a + 1
        q0, q1, q2, q3, w0, w1, w2 = X[0, a], X[1, a], X[2, a], X[3, a], X[4, a], X[5, a], X[6, a]
        p0, p1, p2, p3, v0, v1, v2 = X[0, b], X[1, b], X[2, b], X[3, b], X[4, b], X[5, b], X[6, b]
        Ja, Jia, Jb, Jib = J[:, a], Ji[:, a], J[:, b], Ji[:, b]
        for _ in range(n):
            q0, q1, q2, q3, w0, w1, w2 = rk4_step(q0, q1, q2, q3, w0, w1, w2, Ja, Jia,
                                                  T[0, a], T[1, a], T[2, a], DT)
            p0, p1, p2, p3, v0, v1, v2 = rk4_step(p0, p1, p2, p3, v0, v1, v2, Jb, Jib,
                                                  T[0, b], T[1, b], T[2, b], DT)
        out[0, a], out[1, a], out[2, a], out[3, a], out[4, a], out[5, a], out[6, a] = q0, q1, q2, q3, w0, w1, w2
        out[0, b], out[1, b], out[2, b], out[3, b], out[4, b], out[5, b], out[6, b] = p0, p1, p2, p3, v0, v1, v2
    return out


@register_jitable
def _stage(x, k, h):
    return (x[0] + h * k[0], x[1] + h * k[1], x[2] + h * k[2], x[3] + h * k[3],
            x[4] + h * k[4], x[5] + h * k[5], x[6] + h * k[6])


@register_jitable
def _rk4_two(x, y, Ja, Jia, ta, Jb, Jib, tb, dt):
    """``rk4_step`` of two samples with their stages alternating (same operations per sample)."""
    a = _rhs(*x, Ja, Jia, *ta)
    A = _rhs(*y, Jb, Jib, *tb)
    h = 0.5 * dt
    b = _rhs(*_stage(x, a, h), Ja, Jia, *ta)
    B = _rhs(*_stage(y, A, h), Jb, Jib, *tb)
    c = _rhs(*_stage(x, b, h), Ja, Jia, *ta)
    C = _rhs(*_stage(y, B, h), Jb, Jib, *tb)
    d = _rhs(*_stage(x, c, dt), Ja, Jia, *ta)
    D = _rhs(*_stage(y, C, dt), Jb, Jib, *tb)
    s = dt / 6.0
    n = (x[0] + s * (a[0] + 2.0 * b[0] + 2.0 * c[0] + d[0]), x[1] + s * (a[1] + 2.0 * b[1] + 2.0 * c[1] + d[1]),
         x[2] + s * (a[2] + 2.0 * b[2] + 2.0 * c[2] + d[2]), x[3] + s * (a[3] + 2.0 * b[3] + 2.0 * c[3] + d[3]))
    N = (y[0] + s * (A[0] + 2.0 * B[0] + 2.0 * C[0] + D[0]), y[1] + s * (A[1] + 2.0 * B[1] + 2.0 * C[1] + D[1]),
         y[2] + s * (A[2] + 2.0 * B[2] + 2.0 * C[2] + D[2]), y[3] + s * (A[3] + 2.0 * B[3] + 2.0 * C[3] + D[3]))
    u = unit_q4_pos(n[0], n[1], n[2], n[3])
    U = unit_q4_pos(N[0], N[1], N[2], N[3])
    return ((u[0], u[1], u[2], u[3], x[4] + s * (a[4] + 2.0 * b[4] + 2.0 * c[4] + d[4]),
             x[5] + s * (a[5] + 2.0 * b[5] + 2.0 * c[5] + d[5]), x[6] + s * (a[6] + 2.0 * b[6] + 2.0 * c[6] + d[6])),
            (U[0], U[1], U[2], U[3], y[4] + s * (A[4] + 2.0 * B[4] + 2.0 * C[4] + D[4]),
             y[5] + s * (A[5] + 2.0 * B[5] + 2.0 * C[5] + D[5]), y[6] + s * (A[6] + 2.0 * B[6] + 2.0 * C[6] + D[6])))


@njit(error_model="numpy")
def interleaved(J, Ji, n, X, T):
    """Two samples per iteration, their RK4 stages alternating in one function."""
    out = np.empty_like(X)
    for a in range(0, X.shape[1], 2):
        b = a + 1
        x = (X[0, a], X[1, a], X[2, a], X[3, a], X[4, a], X[5, a], X[6, a])
        y = (X[0, b], X[1, b], X[2, b], X[3, b], X[4, b], X[5, b], X[6, b])
        ta = (T[0, a], T[1, a], T[2, a])
        tb = (T[0, b], T[1, b], T[2, b])
        Ja, Jia, Jb, Jib = J[:, a], Ji[:, a], J[:, b], Ji[:, b]
        for _ in range(n):
            x, y = _rk4_two(x, y, Ja, Jia, ta, Jb, Jib, tb, DT)
        for j in range(7):
            out[j, a] = x[j]
            out[j, b] = y[j]
    return out


@register_jitable(inline="always")
def _rhs_lanes(X, J, Ji, T, D, L):
    for lane in range(L):  # _rhs, one lane per iteration (same expressions)
        q0, q1, q2, q3 = X[0, lane], X[1, lane], X[2, lane], X[3, lane]
        w0, w1, w2 = X[4, lane], X[5, lane], X[6, lane]
        D[0, lane] = 0.5 * (q3 * w0 - (w1 * q2 - w2 * q1))
        D[1, lane] = 0.5 * (q3 * w1 - (w2 * q0 - w0 * q2))
        D[2, lane] = 0.5 * (q3 * w2 - (w0 * q1 - w1 * q0))
        D[3, lane] = -0.5 * (w0 * q0 + w1 * q1 + w2 * q2)
        h0 = J[0, lane] * w0 + J[1, lane] * w1 + J[2, lane] * w2
        h1 = J[3, lane] * w0 + J[4, lane] * w1 + J[5, lane] * w2
        h2 = J[6, lane] * w0 + J[7, lane] * w1 + J[8, lane] * w2
        m0 = T[0, lane] - (w1 * h2 - w2 * h1)
        m1 = T[1, lane] - (w2 * h0 - w0 * h2)
        m2 = T[2, lane] - (w0 * h1 - w1 * h0)
        D[4, lane] = Ji[0, lane] * m0 + Ji[1, lane] * m1 + Ji[2, lane] * m2
        D[5, lane] = Ji[3, lane] * m0 + Ji[4, lane] * m1 + Ji[5, lane] * m2
        D[6, lane] = Ji[6, lane] * m0 + Ji[7, lane] * m1 + Ji[8, lane] * m2


@njit(error_model="numpy")
def lanes(J, Ji, n, X0, T):
    """All samples of ``X0`` (7 × L, structure of arrays) advanced together, step by step."""
    L = X0.shape[1]
    X = X0.copy()
    Y = np.empty_like(X)
    A = np.empty_like(X)
    B = np.empty_like(X)
    C = np.empty_like(X)
    D = np.empty_like(X)
    h = 0.5 * DT
    s = DT / 6.0
    for _ in range(n):
        _rhs_lanes(X, J, Ji, T, A, L)
        for j in range(7):
            for lane in range(L):
                Y[j, lane] = X[j, lane] + h * A[j, lane]
        _rhs_lanes(Y, J, Ji, T, B, L)
        for j in range(7):
            for lane in range(L):
                Y[j, lane] = X[j, lane] + h * B[j, lane]
        _rhs_lanes(Y, J, Ji, T, C, L)
        for j in range(7):
            for lane in range(L):
                Y[j, lane] = X[j, lane] + DT * C[j, lane]
        _rhs_lanes(Y, J, Ji, T, D, L)
        for j in range(7):
            for lane in range(L):
                Y[j, lane] = X[j, lane] + s * (A[j, lane] + 2.0 * B[j, lane] + 2.0 * C[j, lane] + D[j, lane])
        for lane in range(L):  # unit_q4_pos
            n0, n1, n2, n3 = Y[0, lane], Y[1, lane], Y[2, lane], Y[3, lane]
            nrm = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2 + n3 * n3)
            nrm = -nrm if n3 < 0.0 else nrm
            X[0, lane] = n0 / nrm
            X[1, lane] = n1 / nrm
            X[2, lane] = n2 / nrm
            X[3, lane] = n3 / nrm
            X[4, lane] = Y[4, lane]
            X[5, lane] = Y[5, lane]
            X[6, lane] = Y[6, lane]
    return X


def _inputs(L, seed=0):
    """L dispersed GEO spacecraft (S3's inertia ±5 %, a product of inertia), random states."""
    rng = np.random.default_rng(seed)
    J = np.empty((9, L))
    Ji = np.empty((9, L))
    for lane in range(L):
        Jm = np.diag([1218.6, 442.2, 1429.4]) * (1.0 + 0.05 * rng.standard_normal(3))
        Jm[0, 1] = Jm[1, 0] = 5.0
        J[:, lane] = Jm.ravel()
        Ji[:, lane] = np.linalg.inv(Jm).ravel()
    X = 0.02 * rng.standard_normal((7, L))
    q = rng.standard_normal((4, L))
    X[:4] = q / np.linalg.norm(q, axis=0) * np.sign(q[3])
    T = 1e-2 * rng.standard_normal((3, L))
    return J, Ji, X, T


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--steps", type=int, default=2_000_000, help="sample-steps per timing")
    a = ap.parse_args()
    variants = [("serial", serial, 8), ("calls", calls, 8), ("interleaved", interleaved, 8),
                ("lanes 2", lanes, 2), ("lanes 4", lanes, 4), ("lanes 8", lanes, 8), ("lanes 16", lanes, 16)]
    res = {}
    for name, f, L in variants:
        J, Ji, X, T = _inputs(L)
        ok = bool(np.array_equal(f(J, Ji, 3000, X, T), serial(J, Ji, 3000, X, T)))
        n = max(1, a.steps // L)
        best = math.inf
        for _ in range(a.repeats):
            c = time.process_time()
            f(J, Ji, n, X, T)
            best = min(best, (time.process_time() - c) / (n * L))
        res[name] = {"ns_per_sample_step": round(best * 1e9, 1), "bit_identical": ok}
        print(f"{name:12s} {best * 1e9:6.1f} ns per sample-step   bit-identical to rk4_step: {ok}")
    base = res["serial"]["ns_per_sample_step"]
    for v in res.values():
        v["speedup"] = round(base / v["ns_per_sample_step"], 2)
    print(json.dumps(res))


if __name__ == "__main__":
    main()
