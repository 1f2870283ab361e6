"""Per-piece cost of the closed-loop kernel's sample-step (single thread, ns per call).

Each piece of :mod:`adcskit.simulation._kernels` (the kernel's own device functions) in a
small njit loop, best of 3, CPU time. Run::

    PYTHONPATH=src python benchmarks/experiments/kernel_micro.py

Results and the per-sample-step breakdown: docs/benchmarks.md, "Closed-loop kernel".
"""

import math
import time

import numpy as np
from numba import njit

from adcskit.attitude._device import qerr, rotate
from adcskit.control._actuator import delay_mix, lag_step, schmitt
from adcskit.estimation import _mekf_kernels as mk
from adcskit.sensors._gyro_kernels import gyro_step
from adcskit.simulation import _kernels as K

N = 2_000_000


@njit(cache=False)
def b_loop(n):
    s = 0.0
    for k in range(n):
        s += k * 1e-9
    return s


@njit(cache=False)
def b_rk4(n, J, Ji):
    q0, q1, q2, q3, w0, w1, w2 = 0.1, 0.2, 0.3, 0.927, 1e-3, -2e-3, 5e-4
    for _ in range(n):
        q0, q1, q2, q3, w0, w1, w2 = K.rk4_step(
            q0, q1, q2, q3, w0, w1, w2, J, Ji, 1e-3, 0.0, -1e-3, 0.01
        )
    return q0 + w0


@njit(cache=False)
def b_qerr(n):
    s = 0.0
    for k in range(n):
        a, b, c, d = qerr(0.1 + k * 1e-12, 0.2, 0.3, 0.927, 0.1, 0.2, 0.31, 0.92)
        s += a + d
    return s


@njit(cache=False)
def b_sin3(n):
    s = 0.0
    for k in range(n):
        t = k * 0.01
        s += math.sin(0.001 * t + 0.1) + math.sin(0.001 * t + 1.6) + math.sin(0.001 * t)
    return s


@njit(cache=False)
def b_mod(n, h1, h2):
    c = 0
    for k in range(n):
        if k % h1 == 0:
            c += 1
        if k % h2 == 0:
            c += 2
    return c


@njit(cache=False)
def b_thr(n, ts, buf, FLEV, MDOT, DIRS, POS, FAILED, nthr):
    t0 = 0.0
    prop = 0.0
    for k in range(n):
        m = k % 20
        for j in range(nthr):
            c = ts[2 * nthr + j] / 0.01 - m
            if c > 1.0:
                c = 1.0
            elif c < 0.0:
                c = 0.0
            if FAILED[j] > 0.0:
                c = 0.0
            buf[k & 3, j] = c
            ua = buf[k & 3, j] if k >= 0 else 0.0
            ub = buf[(k - 1) & 3, j] if k >= 1 else 0.0
            ud = delay_mix(ua, ub, 0.0)
            v, x1, x2 = lag_step(ts[j], ts[nthr + j], ud, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.01)
            ts[nthr + j] = x2
            ts[j] = x1
            fav = FLEV[0, j] * v / 0.01
            prop += MDOT[0, j] * v
            d0 = DIRS[0, j, 0]
            d1 = DIRS[0, j, 1]
            d2 = DIRS[0, j, 2]
            r0 = POS[j, 0]
            r1 = POS[j, 1]
            r2 = POS[j, 2]
            t0 += fav * (r1 * d2 - r2 * d1) + fav * (r2 * d0 - r0 * d2) + fav * (r0 * d1 - r1 * d0)
    return t0 + prop


@njit(cache=False)
def b_gyro(n, gy, bias):
    s = np.uint64(12345)
    for _ in range(n):
        s, z0 = K._normal(s)
        s, z1 = K._normal(s)
        s, z2 = K._normal(s)
        gy[6] = z0
        gy[7] = z1
        gy[8] = z2
        s, z0 = K._normal(s)
        s, z1 = K._normal(s)
        s, z2 = K._normal(s)
        gy[9] = z0
        gy[10] = z1
        gy[11] = z2
        gy[3] = 1e-3
        gy[4] = 2e-3
        gy[5] = 0.0
        gyro_step(gy[3:6], bias, 3e-7, 3e-10, 0.1, gy[6:9], gy[9:12], gy[0:3])
    return gy[0]


@njit(cache=False)
def b_prop(n, q, b, P, om, wk):
    for k in range(n):
        mk.mekf_propagate(q, b, P, om, 0.1, 3e-7, 3e-10, wk)
        if k % 100 == 0:
            for a in range(6):
                for c in range(6):
                    P[a, c] = 1e-6 if a == c else 0.0
    return q[0]


@njit(cache=False)
def b_upd(n, q, b, P, vb, vr, wk):
    s = 0.0
    for k in range(n):
        s += mk.mekf_update_vector(q, b, P, vb, vr, 1e-3, 0.2, wk)
        if k % 100 == 0:
            for a in range(6):
                for c in range(6):
                    P[a, c] = 1e-6 if a == c else 0.0
    return s


@njit(cache=False)
def b_nees(n, q, b, P, qt, bt, wk):
    s = 0.0
    for _ in range(n):
        s += mk.mekf_nees(q, b, P, qt, bt, wk)
    return s


@njit(cache=False)
def b_sensor(n):
    s = np.uint64(7)
    acc = 0.0
    for _ in range(n):
        b0, b1, b2 = rotate(0.1, 0.2, 0.3, 0.927, 0.6, 0.8, 0.0)
        s, n0 = K._noise(s, False)
        s, n1 = K._noise(s, False)
        s, n2 = K._noise(s, False)
        acc += b0 + n0 + b1 + n1 + b2 + n2
    return acc


@njit(cache=False)
def b_ctrl(n, ATAB, F, nthr):
    sx = 0.0
    sy = 0.0
    sz = 0.0
    ix = 0.0
    acc = 0.0
    for k in range(n):
        cx, cy, cz, _ = qerr(0.01 * math.sin(k * 1.0), 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
        ux = 50.0 * -cx + 0.02 * ix + 50.0 * 1e-4
        uy = 50.0 * -cy + 50.0 * 1e-4
        uz = 50.0 * -cz
        ix += -cx * 0.2
        sx = schmitt(sx, ux, 0.15, 0.075)
        sy = schmitt(sy, uy, 0.15, 0.075)
        sz = schmitt(sz, uz, 0.15, 0.075)
        row = int((sx + 1.0) * 9.0 + (sy + 1.0) * 3.0 + (sz + 1.0))
        for j in range(nthr):
            F[j] = ATAB[row, j]
        for j in range(nthr):
            tp = F[j] / 10.0 * 0.2
            if tp < 3e-3:
                tp = 0.0
            acc += tp
    return acc


def t(f, *a, n=N, reps=3):
    f(100, *a)
    best = 1e9
    for _ in range(reps):
        c = time.process_time()
        f(n, *a)
        best = min(best, time.process_time() - c)
    return best / n * 1e9


J = np.array([1218.6, 0, 0, 0, 442.2, 0, 0, 0, 1429.4])
Ji = np.array([1 / 1218.6, 0, 0, 0, 1 / 442.2, 0, 0, 0, 1 / 1429.4])
nthr = 6
rng = np.random.default_rng(0)
ts = np.zeros(6 * nthr + 18)
ts[2 * nthr : 3 * nthr] = rng.random(nthr) * 0.1
res = {
    "loop": t(b_loop),
    "rk4_step": t(b_rk4, J, Ji),
    "qerr (1 atan2, 1 sqrt)": t(b_qerr),
    "3 sin": t(b_sin3),
    "2 int modulo": t(b_mod, 10, 20),
    "thrusters (6)": t(
        b_thr,
        ts,
        np.zeros((4, nthr)),
        rng.random((1, nthr)),
        rng.random((1, nthr)),
        rng.random((1, nthr, 3)),
        rng.random((nthr, 3)),
        np.zeros(nthr),
        nthr,
    ),
    "gyro epoch (6 normals + gyro_step)": t(b_gyro, np.zeros(12), np.zeros(3), n=N // 4),
    "mekf_propagate": t(
        b_prop,
        np.array([0.1, 0.2, 0.3, 0.927]),
        np.zeros(3),
        np.eye(6) * 1e-6,
        np.array([1e-3, 2e-3, -1e-3]),
        np.zeros(48),
        n=N // 4,
    ),
    "mekf_update_vector": t(
        b_upd,
        np.array([0.1, 0.2, 0.3, 0.927]),
        np.zeros(3),
        np.eye(6) * 1e-6,
        np.array([0.6, 0.8, 0.0]),
        np.array([0.61, 0.79, 0.01]),
        np.zeros(48),
        n=N // 4,
    ),
    "mekf_nees": t(
        b_nees,
        np.array([0.1, 0.2, 0.3, 0.927]),
        np.zeros(3),
        np.eye(6) * 1e-6,
        np.array([0.1, 0.2, 0.3, 0.9271]),
        np.zeros(3),
        np.zeros(48),
        n=N // 4,
    ),
    "sensor (rotate + 3 normals)": t(b_sensor, n=N // 4),
    "control (qerr + PID + Schmitt + table + pulses)": t(
        b_ctrl, rng.random((27, nthr)) * 10, np.zeros(nthr), nthr
    ),
}
for k, v in res.items():
    print(f"{k:50s} {v:7.1f} ns")
