"""Private kernels of the on-off loop: a per-sample source for the GPU (and for traces), a
lane-block source for the CPU, plus the NumPy reference path.

:func:`_sample` simulates one sample; it is compiled twice from this one source
(:mod:`adcskit._targets`): by ``numba.njit`` (the CPU driver's path when traces are
recorded) and by ``numba.cuda.jit(device=True)`` for the GPU driver :func:`simulate_cuda`
(one thread per sample). Without traces the CPU driver :func:`simulate_parallel` runs
:func:`_lanes` instead: blocks of up to :data:`LANES` samples advanced together, each piece of
a step a short loop over the block's samples that LLVM vectorises (SIMD across samples, 1.7-2x
the per-sample kernel's sample-steps per CPU-second; docs/benchmarks.md, "On-off kernel:
samples in lanes"). It is a second source of the same model, kept to *the same operations in
the same order per sample*, so the two give identical numbers (tested bit for bit, with
partial blocks and time-varying disturbances: tests/control/test_onoff.py).
:func:`simulate_numpy` is an independent reference vectorised over samples.

The CPU kernels perform *the same floating-point operations in the same order* as the NumPy
path, so their results agree bit for bit (no fused multiply-add: numba runs without
``fastmath`` and LLVM does not contract on the CPU; NumPy ufuncs never fuse). The only
exception is ``sin`` of a time-varying disturbance, where libm and NumPy may differ in the
last ulp. On a real GPU, NVVM contracts ``a * b + c`` into fused multiply-adds (one rounding
instead of two), so the continuous metrics differ from the CPU's by rounding-level amounts
(a relative 1e-9 on a 30 s run is the budget the tests allow: the loop is a marginally
stable limit cycle that amplifies 1e-16 differences slowly), while the discrete events
(firings) are identical unless a controller output falls within rounding of a Schmitt
threshold. numba's CUDA simulator executes the device function as Python (no FMA), so
there the GPU driver reproduces the CPU kernel bit for bit.

Per-sample parameter columns (``P[i, col]``) and shared coefficients (``C[col]``) are
listed below; :mod:`adcskit.control.onoff` builds both. The actuator pieces (Schmitt
trigger, delay interpolation, thruster lags) are the device helpers of
:mod:`adcskit.control._actuator`, shared with the closed-loop simulator.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from adcskit._targets import LazyKernels, PerSample, device, import_cuda
from adcskit.control._actuator import delay_mix, lag_step, schmitt

# --- per-sample parameter columns ---------------------------------------------------------
KP, KI, KD, UON, UOFF, INERTIA, TORQUE, DELAY, D0, DAMP, DOMEGA, THREF, TH0, OM0 = range(14)
N_PARAMS = 14

# --- shared coefficient columns --------------------------------------------------------------
# thruster (two cascaded first-order lags, exact ZOH discretisation of the delayed command):
#   x1+ = A11 x1 + B1 u ;  x2+ = A21 x1 + A22 x2 + B2 u
# integrals over one step (zero initial v, p):  v = int x2 dt ; p = int int x2 dt dt
#   v = V1 x1 + V2 x2 + VU u ;  p = P1 x1 + P2 x2 + PU u
# derivative filter: xf+ = xf + ALPHA (e - xf), derivative = (e - xf) * INV_TD
(A11, B1, A21, A22, B2, V1, V2, VU, P1, P2, PU, ALPHA, INV_TD, DT, HALF_DT2, BAND_FRAC) = range(16)
N_COEFS = 16

# --- metric columns -------------------------------------------------------------------------
OVERSHOOT_PCT, MEAN_ABS_ERR, MAX_ABS_ERR, FUEL, FIRINGS, SETTLING_TIME, FINAL_ERR = range(7)
N_METRICS = 7
METRIC_NAMES = (
    "overshoot_pct",
    "mean_abs_err_last",
    "max_abs_err_last",
    "fuel",
    "firings",
    "settling_time",
    "final_error",
)

# --- trace columns ----------------------------------------------------------------------
TR_THETA, TR_OMEGA, TR_U, TR_CMD, TR_THRUST = range(5)
N_TRACE = 5


@device
def _metrics(out, i, max_over, abs_step, acc, n_win, max_win, fuel, firings, last_out, n_steps, dt, e):
    """Write sample ``i``'s metrics (``out[i, :]``) from its accumulators."""
    if abs_step > 0.0:
        out[i, OVERSHOOT_PCT] = max(max_over, 0.0) / abs_step * 100.0
    else:
        out[i, OVERSHOOT_PCT] = math.nan
    out[i, MEAN_ABS_ERR] = acc / n_win
    out[i, MAX_ABS_ERR] = max_win
    out[i, FUEL] = fuel
    out[i, FIRINGS] = firings
    if last_out < 0:
        out[i, SETTLING_TIME] = 0.0
    elif last_out >= n_steps:
        out[i, SETTLING_TIME] = math.nan
    else:
        out[i, SETTLING_TIME] = (last_out + 1) * dt
    out[i, FINAL_ERR] = e


def _sample(i, P, C, n_steps, hold, n_win, buf_len, buf, rec, out):
    """Simulate sample ``i`` (row ``P[i]``) and write its metrics to ``out[i, :]``.

    The per-sample function of the one-source/two-targets pattern (:mod:`adcskit._targets`):
    compiled by ``numba.njit`` (called from :func:`simulate_parallel` under ``prange``) and
    by ``numba.cuda.jit(device=True)`` (called by one GPU thread per sample).

    ``buf`` is the sample's delay line, scratch of length ``>= buf_len`` supplied by the
    driver: a float64 ``np.empty`` on the CPU (in L1 there anyway), an int8
    ``cuda.local.array`` on the GPU. ``buf_len`` is a power of two larger than the longest
    delay in steps + 2. The line holds Schmitt outputs {-1, 0, +1}, exact in either dtype
    (stores cast, ``1.0 * buf[j]`` reads back a float64), so both give the same numbers; on
    the GPU 1 byte per entry instead of 8 keeps a thread's line at 32 B for S4's delays, so
    the resident threads' local memory can stay in L1 instead of spilling to L2. ``rec`` is
    ``(N, n_steps + 1, N_TRACE)`` (record traces) or has a zero first axis.
    """
    record = rec.shape[0] > 0
    mask = buf_len - 1
    a11 = C[A11]
    b1 = C[B1]
    a21 = C[A21]
    a22 = C[A22]
    b2 = C[B2]
    v1 = C[V1]
    v2 = C[V2]
    vu = C[VU]
    p1 = C[P1]
    p2 = C[P2]
    pu = C[PU]
    alpha = C[ALPHA]
    inv_td = C[INV_TD]
    dt = C[DT]
    half_dt2 = C[HALF_DT2]
    band_frac = C[BAND_FRAC]
    k_win0 = n_steps - n_win + 1  # first sample index inside the final window
    kp = P[i, KP]
    ki = P[i, KI]
    kd = P[i, KD]
    u_on = P[i, UON]
    u_off = P[i, UOFF]
    inv_j = 1.0 / P[i, INERTIA]
    torque = P[i, TORQUE]
    g = torque * inv_j
    abs_torque = abs(torque)
    delay_steps = P[i, DELAY] / dt
    nd = int(math.floor(delay_steps))
    frac = delay_steps - nd
    d0 = P[i, D0]
    d_amp = P[i, DAMP]
    d_omega = P[i, DOMEGA]
    theta_ref = P[i, THREF]
    theta = P[i, TH0]
    omega = P[i, OM0]
    step = theta_ref - theta
    sgn = 1.0 if step >= 0.0 else -1.0
    abs_step = abs(step)
    band = band_frac * abs_step
    for j in range(buf_len):
        buf[j] = 0
    e = theta_ref - theta
    integ = 0.0
    xf = e  # derivative filter starts at rest on the initial error (no derivative kick)
    x1 = 0.0
    x2 = 0.0
    s = 0.0  # Schmitt output (held command)
    u = 0.0
    cnt = 0
    firings = 0.0
    fuel = 0.0
    max_over = -math.inf
    acc = 0.0
    max_win = 0.0
    last_out = -1
    if abs(e) > band:
        last_out = 0
    if record:
        rec[i, 0, TR_THETA] = theta
        rec[i, 0, TR_OMEGA] = omega
        rec[i, 0, TR_U] = 0.0
        rec[i, 0, TR_CMD] = 0.0
        rec[i, 0, TR_THRUST] = 0.0
    for k in range(n_steps):
        # controller at the command instants (sample and hold)
        if cnt == 0:
            cnt = hold
            u = kp * e + ki * integ + kd * ((e - xf) * inv_td)
            prev = s
            s = schmitt(s, u, u_on, u_off)
            if s != 0.0 and s != prev:
                firings += 1.0
        cnt -= 1
        # pure delay (linear interpolation between the two neighbouring command samples)
        buf[k & mask] = s  # exact in any dtype of the line: s is -1, 0 or +1
        if k - nd >= 0:
            ua = 1.0 * buf[(k - nd) & mask]
        else:
            ua = 0.0
        if k - nd - 1 >= 0:
            ub = 1.0 * buf[(k - nd - 1) & mask]
        else:
            ub = 0.0
        ud = delay_mix(ua, ub, frac)
        # disturbance (held over the step, evaluated at its midpoint)
        if d_amp != 0.0:
            td = d0 + d_amp * math.sin(d_omega * ((k + 0.5) * dt))
        else:
            td = d0
        # thruster lag and rigid body, exact for a command held over the step
        p = p1 * x1 + p2 * x2 + pu * ud
        v, x1, x2 = lag_step(x1, x2, ud, a11, b1, a21, a22, b2, v1, v2, vu)
        theta = theta + omega * dt + g * p + (td * inv_j) * half_dt2
        omega = omega + g * v + (td * inv_j) * dt
        fuel += abs_torque * abs(v)
        # PID states
        integ = integ + e * dt
        xf = xf + alpha * (e - xf)
        # metrics at t_{k+1}
        e = theta_ref - theta
        over = sgn * (theta - theta_ref)
        if over > max_over:
            max_over = over
        ae = abs(e)
        if ae > band:
            last_out = k + 1
        if k + 1 >= k_win0:
            acc += ae
            if ae > max_win:
                max_win = ae
        if record:
            rec[i, k + 1, TR_THETA] = theta
            rec[i, k + 1, TR_OMEGA] = omega
            rec[i, k + 1, TR_U] = u
            rec[i, k + 1, TR_CMD] = s
            rec[i, k + 1, TR_THRUST] = torque * x2
    _metrics(out, i, max_over, abs_step, acc, n_win, max_win, fuel, firings, last_out, n_steps, dt, e)


SAMPLE = PerSample(_sample)
_sample_cpu = SAMPLE.cpu

# --- CPU: many samples at once ----------------------------------------------------------------
#: Most samples one CPU thread advances together (:func:`_lanes`); fewer when a batch is small,
#: so that every thread gets a block (:func:`lane_count`).
LANES = 64
#: Fewest samples per block: below ~16 the per-lane loops cost more than they vectorise.
MIN_LANES = 16
# rows of a block's per-lane scratch F (one float per lane each)
(_KP, _KI, _KD, _UON, _UOFF, _INVJ, _G, _ABST, _FRAC, _D0, _DAMP, _DOM, _TREF, _TH, _OM, _SGN,
 _BAND, _E, _INTEG, _XF, _X1, _X2, _S, _FIR, _FUEL, _MO, _ACC, _MW, _TD, _ABSSTEP, _UA, _UB,
 _UD, _PP, _VV) = range(35)
N_LANE_ROWS = 35


@numba.njit(nogil=True, cache=True)
def _lanes(i0, L, P, C, n_steps, hold, n_win, buf_len, out, buf, ndi, lo, F):
    """Simulate samples ``i0 .. i0 + L - 1`` together and write their metrics to ``out``.

    The same floating-point operations in the same order per sample as :func:`_sample`
    (identical results, bit for bit), but time-major over a block of samples: each piece of a
    step is a loop over the block's lanes (structure of arrays: one row of ``F`` per state
    variable), which LLVM turns into SIMD instructions (AVX2: four samples per instruction)
    without changing one operation. A step is split into several short lane loops, not one:
    a loop touching many arrays is not vectorised (too many run-time overlap checks), and the
    delay line's reads (a different row per lane) are gathered in a loop of their own. Measured
    1.9-2.0x the per-sample kernel on one thread (docs/benchmarks.md, "On-off kernel: samples
    in lanes"). No traces (the drivers use :func:`_sample` when recording).

    ``buf``: (``buf_len``, >= L) delay line, one column per lane; ``ndi``, ``lo``: int64 (>= L,)
    (delay in whole steps, last step outside the band); ``F``: (:data:`N_LANE_ROWS`, >= L).
    """
    mask = buf_len - 1
    a11, b1, a21, a22, b2 = C[A11], C[B1], C[A21], C[A22], C[B2]
    v1, v2, vu, p1, p2, pu = C[V1], C[V2], C[VU], C[P1], C[P2], C[PU]
    alpha = C[ALPHA]
    inv_td = C[INV_TD]
    dt = C[DT]
    half_dt2 = C[HALF_DT2]
    band_frac = C[BAND_FRAC]
    k_win0 = n_steps - n_win + 1
    kp, ki, kd, uon, uoff, invj, g, abst = F[_KP], F[_KI], F[_KD], F[_UON], F[_UOFF], F[_INVJ], F[_G], F[_ABST]
    frac, d0, damp, dom, tref, th, om, sgn = F[_FRAC], F[_D0], F[_DAMP], F[_DOM], F[_TREF], F[_TH], F[_OM], F[_SGN]
    band, e, integ, xf, x1, x2, s, fir = F[_BAND], F[_E], F[_INTEG], F[_XF], F[_X1], F[_X2], F[_S], F[_FIR]
    fuel, mo, acc, mw, td, absstep = F[_FUEL], F[_MO], F[_ACC], F[_MW], F[_TD], F[_ABSSTEP]
    ua, ub, ud, pp, vv = F[_UA], F[_UB], F[_UD], F[_PP], F[_VV]
    varying = False
    for j in range(L):  # as _sample's set-up
        i = i0 + j
        kp[j] = P[i, KP]
        ki[j] = P[i, KI]
        kd[j] = P[i, KD]
        uon[j] = P[i, UON]
        uoff[j] = P[i, UOFF]
        invj[j] = 1.0 / P[i, INERTIA]
        torque = P[i, TORQUE]
        g[j] = torque * invj[j]
        abst[j] = abs(torque)
        delay_steps = P[i, DELAY] / dt
        nd = int(math.floor(delay_steps))
        ndi[j] = nd
        frac[j] = delay_steps - nd
        d0[j] = P[i, D0]
        damp[j] = P[i, DAMP]
        dom[j] = P[i, DOMEGA]
        tref[j] = P[i, THREF]
        th[j] = P[i, TH0]
        om[j] = P[i, OM0]
        step = tref[j] - th[j]
        sgn[j] = 1.0 if step >= 0.0 else -1.0
        absstep[j] = abs(step)
        band[j] = band_frac * absstep[j]
        e[j] = tref[j] - th[j]
        integ[j] = 0.0
        xf[j] = e[j]
        x1[j] = 0.0
        x2[j] = 0.0
        s[j] = 0.0
        fir[j] = 0.0
        fuel[j] = 0.0
        mo[j] = -math.inf
        acc[j] = 0.0
        mw[j] = 0.0
        lo[j] = 0 if abs(e[j]) > band[j] else -1
        td[j] = d0[j]
        varying = varying or damp[j] != 0.0
    for r in range(buf_len):
        for j in range(L):
            buf[r, j] = 0.0
    cnt = 0
    for k in range(n_steps):
        if cnt == 0:  # controller at the command instants (the same for every lane)
            cnt = hold
            for j in range(L):
                u = kp[j] * e[j] + ki[j] * integ[j] + kd[j] * ((e[j] - xf[j]) * inv_td)
                prev = s[j]
                s[j] = schmitt(prev, u, uon[j], uoff[j])
                if s[j] != 0.0 and s[j] != prev:
                    fir[j] += 1.0
        cnt -= 1
        row = k & mask
        for j in range(L):
            buf[row, j] = s[j]
        for j in range(L):  # the delay line's two reads (gathers: a loop of their own)
            ka = k - ndi[j]
            ua[j] = buf[ka & mask, j] if ka >= 0 else 0.0
            ub[j] = buf[(ka - 1) & mask, j] if ka - 1 >= 0 else 0.0
        for j in range(L):
            ud[j] = delay_mix(ua[j], ub[j], frac[j])
        if varying:
            for j in range(L):
                if damp[j] != 0.0:
                    td[j] = d0[j] + damp[j] * math.sin(dom[j] * ((k + 0.5) * dt))
        for j in range(L):  # thruster lag
            pp[j] = p1 * x1[j] + p2 * x2[j] + pu * ud[j]
            vv[j], x1[j], x2[j] = lag_step(x1[j], x2[j], ud[j], a11, b1, a21, a22, b2, v1, v2, vu)
        for j in range(L):  # rigid body, exact for a command held over the step
            th[j] = th[j] + om[j] * dt + g[j] * pp[j] + (td[j] * invj[j]) * half_dt2
            om[j] = om[j] + g[j] * vv[j] + (td[j] * invj[j]) * dt
        for j in range(L):  # fuel, PID states
            fuel[j] += abst[j] * abs(vv[j])
            integ[j] = integ[j] + e[j] * dt
            xf[j] = xf[j] + alpha * (e[j] - xf[j])
        for j in range(L):  # metrics at t_{k+1}
            ej = tref[j] - th[j]
            e[j] = ej
            over = sgn[j] * (th[j] - tref[j])
            mo[j] = over if over > mo[j] else mo[j]
            lo[j] = k + 1 if abs(ej) > band[j] else lo[j]
        if k + 1 >= k_win0:
            for j in range(L):
                acc[j] += abs(e[j])
            for j in range(L):
                ae = abs(e[j])
                mw[j] = ae if ae > mw[j] else mw[j]
    for j in range(L):
        _metrics(out, i0 + j, mo[j], absstep[j], acc[j], n_win, mw[j], fuel[j], fir[j], lo[j], n_steps,
                 dt, e[j])


def lane_count(n):
    """Samples per block of the CPU driver for a batch of ``n``: :data:`LANES`, or fewer (not
    below :data:`MIN_LANES`) so that every numba thread gets a block. Any count gives the
    same numbers."""
    per_thread = -(-int(n) // numba.get_num_threads())
    return max(MIN_LANES, min(LANES, per_thread))


def _simulate(P, C, n_steps, hold, n_win, buf_len, rec, lanes):
    """CPU driver: simulate every row of ``P``; return the (N, N_METRICS) metrics.

    Without traces, blocks of ``lanes`` samples (:func:`lane_count`) through :func:`_lanes`
    (``prange`` over blocks); with
    traces, one sample at a time through :func:`_sample` (``prange`` over samples). The two
    give the same numbers."""
    n = P.shape[0]
    out = np.empty((n, N_METRICS))
    if rec.shape[0] > 0:
        for i in numba.prange(n):
            buf = np.empty(buf_len)
            _sample_cpu(i, P, C, n_steps, hold, n_win, buf_len, buf, rec, out)
        return out
    for b in numba.prange((n + lanes - 1) // lanes):
        i0 = b * lanes
        L = min(lanes, n - i0)
        F = np.empty((N_LANE_ROWS, L))
        _lanes(i0, L, P, C, n_steps, hold, n_win, buf_len, out, np.empty((buf_len, L)),
               np.empty(L, np.int64), np.empty(L, np.int64), F)
    return out


def _simulate_python(P, C, n_steps, hold, n_win, buf_len, rec, lanes=1):
    """The plain-Python driver around the plain per-sample function (benchmarks only)."""
    n = P.shape[0]
    out = np.empty((n, N_METRICS))
    for i in range(n):
        _sample(i, P, C, n_steps, hold, n_win, buf_len, np.empty(buf_len), rec, out)
    return out


simulate_parallel = numba.njit(parallel=True, cache=True, nogil=True)(_simulate)
simulate_serial = numba.njit(parallel=False, cache=True, nogil=True)(_simulate)
simulate_python = _simulate_python


# --- CUDA driver ---------------------------------------------------------------------------
# One thread per sample, THREADS_PER_BLOCK threads per block, the delay line in per-thread
# local memory (``cuda.local.array``: its index ``k & mask`` is dynamic, so it cannot live in
# registers; the compiler interleaves local memory by thread, so the write ``buf[k & mask]``,
# the same index in every lane, is one coalesced transaction, and the reads at
# ``(k - nd) & mask`` touch at most a few lines because the delays of a warp are close).
# The kernel is specialised on the line length L = buf_len (a compile-time constant), so a
# thread reserves exactly L bytes: 32 B for S4's delays (<= 30 ms at dt = 1 ms).
#
# Registers/occupancy. Compiled without a GPU (numba-cuda 0.30.4 -> PTX for sm_90, NVVM 13.0;
# ptxas 12.9 -v): 124 registers per thread, an 80-byte stack frame (the 32-byte delay line
# plus the slow path of the sin argument reduction), no spills; 31 FP64 multiply-adds of the
# loop are contracted to FMAs. At 124 (allocated as 128) registers an H100 SM (64 K
# registers) holds 512 threads = 4 blocks of 128 = 16 warps (25 % occupancy): the loop is one
# dependent FP64 chain per thread with almost no memory traffic, so its speed is set by how
# many warps hide the FP64 latency. Fewer registers buy more warps at the price of spills:
# ptxas gives 32 B of spills at a 96-register cap (640 threads/SM), 56 B at 80 (768) and
# 144 B at 64 (1024). Which wins can only be measured: max_registers (CUDA_MAX_REGISTERS,
# or the argument of simulate_cuda) is the knob, and bench_onoff.py --backend cuda sweeps it.
THREADS_PER_BLOCK = 128
CUDA_MAX_REGISTERS = None  # None: the compiler's choice (see above)
MAX_CUDA_BUFFER = 1 << 16  # longest delay line on the GPU [steps] (64 KiB of local memory)
CUDA_CHUNK = 1 << 21  # samples per device round trip (2M x (14 + 7) x 8 B = 352 MB on the GPU)


cuda = None  # numba.cuda, bound on first GPU use (a module global: see adcskit._targets)


def _make_cuda_kernel(buf_len, max_registers=None):
    global cuda
    cuda = import_cuda()
    sample = SAMPLE.cuda()
    int8 = numba.int8
    jit = cuda.jit if max_registers is None else cuda.jit(max_registers=int(max_registers))

    @jit
    def kernel(P, C, n_steps, hold, n_win, rec, out):
        i = cuda.grid(1)
        if i < P.shape[0]:
            buf = cuda.local.array(buf_len, int8)
            sample(i, P, C, n_steps, hold, n_win, buf_len, buf, rec, out)

    return kernel


CUDA_KERNELS = LazyKernels(_make_cuda_kernel)


def simulate_cuda(P, C, n_steps, hold, n_win, buf_len, rec, chunk=CUDA_CHUNK, max_registers=None):
    """GPU driver: the same per-sample function, one CUDA thread per sample.

    Samples go to the device in chunks of ``chunk`` rows, so the batch size is bounded by
    host memory only. ``rec`` (traces) is copied along when its first axis is non-zero.
    ``max_registers`` caps the registers per thread (default :data:`CUDA_MAX_REGISTERS`).
    """
    if max_registers is None:
        max_registers = CUDA_MAX_REGISTERS
    kernel = CUDA_KERNELS.get(int(buf_len), max_registers)  # binds the module global ``cuda``
    n = P.shape[0]
    out = np.empty((n, N_METRICS))
    record = rec.shape[0] > 0
    C_d = cuda.to_device(np.ascontiguousarray(C))
    no_rec = cuda.to_device(np.zeros((0, 1, N_TRACE)))
    for start in range(0, n, chunk):
        stop = min(n, start + chunk)
        m = stop - start
        P_d = cuda.to_device(np.ascontiguousarray(P[start:stop]))
        out_d = cuda.device_array((m, N_METRICS))
        rec_d = cuda.to_device(np.ascontiguousarray(rec[start:stop])) if record else no_rec
        blocks = (m + THREADS_PER_BLOCK - 1) // THREADS_PER_BLOCK
        kernel[blocks, THREADS_PER_BLOCK](P_d, C_d, n_steps, hold, n_win, rec_d, out_d)
        out[start:stop] = out_d.copy_to_host()
        if record:
            rec[start:stop] = rec_d.copy_to_host()
    return out


def simulate_numpy(P, C, n_steps, hold, n_win, buf_len, rec):
    """NumPy reference path: vectorised over samples, a Python loop over time steps.

    Same operations, same order as :func:`_simulate` (bit-identical results).
    """
    n = P.shape[0]
    record = rec.shape[0] > 0
    mask = buf_len - 1
    a11, b1, a21, a22, b2 = C[A11], C[B1], C[A21], C[A22], C[B2]
    v1, v2, vu, p1, p2, pu = C[V1], C[V2], C[VU], C[P1], C[P2], C[PU]
    alpha, inv_td, dt, half_dt2, band_frac = C[ALPHA], C[INV_TD], C[DT], C[HALF_DT2], C[BAND_FRAC]
    k_win0 = n_steps - n_win + 1
    kp, ki, kd = P[:, KP], P[:, KI], P[:, KD]
    u_on, u_off = P[:, UON], P[:, UOFF]
    inv_j = 1.0 / P[:, INERTIA]
    torque = P[:, TORQUE]
    g = torque * inv_j
    abs_torque = np.abs(torque)
    delay_steps = P[:, DELAY] / dt
    nd = np.floor(delay_steps).astype(np.int64)
    frac = delay_steps - nd
    d0, d_amp, d_omega = P[:, D0], P[:, DAMP], P[:, DOMEGA]
    varying = d_amp != 0.0
    theta_ref = P[:, THREF]
    theta = P[:, TH0].copy()
    omega = P[:, OM0].copy()
    step = theta_ref - theta
    sgn = np.where(step >= 0.0, 1.0, -1.0)
    abs_step = np.abs(step)
    band = band_frac * abs_step
    buf = np.zeros((n, buf_len))
    rows = np.arange(n)
    e = theta_ref - theta
    integ = np.zeros(n)
    xf = e.copy()
    x1 = np.zeros(n)
    x2 = np.zeros(n)
    s = np.zeros(n)
    u = np.zeros(n)
    firings = np.zeros(n)
    fuel = np.zeros(n)
    max_over = np.full(n, -np.inf)
    acc = np.zeros(n)
    max_win = np.zeros(n)
    last_out = np.where(np.abs(e) > band, 0, -1)
    if record:
        rec[:, 0, TR_THETA] = theta
        rec[:, 0, TR_OMEGA] = omega
        rec[:, 0, TR_U:] = 0.0
    cnt = 0
    for k in range(n_steps):
        if cnt == 0:
            cnt = hold
            u = kp * e + ki * integ + kd * ((e - xf) * inv_td)
            prev = s
            on_pos = u >= u_on
            on_neg = u <= -u_on
            from_zero = np.where(on_pos, 1.0, np.where(on_neg, -1.0, 0.0))
            from_pos = np.where(on_neg, -1.0, np.where(u < u_off, 0.0, 1.0))
            from_neg = np.where(on_pos, 1.0, np.where(u > -u_off, 0.0, -1.0))
            s = np.where(prev == 0.0, from_zero, np.where(prev == 1.0, from_pos, from_neg))
            firings += (s != 0.0) & (s != prev)
        cnt -= 1
        buf[:, k & mask] = s
        ia = k - nd
        ua = np.where(ia >= 0, buf[rows, ia & mask], 0.0)
        ub = np.where(ia - 1 >= 0, buf[rows, (ia - 1) & mask], 0.0)
        ud = (1.0 - frac) * ua + frac * ub
        if np.any(varying):
            td = np.where(varying, d0 + d_amp * np.sin(d_omega * ((k + 0.5) * dt)), d0)
        else:
            td = d0
        p = p1 * x1 + p2 * x2 + pu * ud
        v, x1, x2 = lag_step(x1, x2, ud, a11, b1, a21, a22, b2, v1, v2, vu)
        theta = theta + omega * dt + g * p + (td * inv_j) * half_dt2
        omega = omega + g * v + (td * inv_j) * dt
        fuel += abs_torque * np.abs(v)
        integ = integ + e * dt
        xf = xf + alpha * (e - xf)
        e = theta_ref - theta
        over = sgn * (theta - theta_ref)
        max_over = np.maximum(max_over, over)
        ae = np.abs(e)
        last_out = np.where(ae > band, k + 1, last_out)
        if k + 1 >= k_win0:
            acc += ae
            max_win = np.maximum(max_win, ae)
        if record:
            rec[:, k + 1, TR_THETA] = theta
            rec[:, k + 1, TR_OMEGA] = omega
            rec[:, k + 1, TR_U] = u
            rec[:, k + 1, TR_CMD] = s
            rec[:, k + 1, TR_THRUST] = torque * x2
    out = np.empty((n, N_METRICS))
    with np.errstate(invalid="ignore", divide="ignore"):
        out[:, OVERSHOOT_PCT] = np.where(
            abs_step > 0.0, np.maximum(max_over, 0.0) / abs_step * 100.0, np.nan
        )
    out[:, MEAN_ABS_ERR] = acc / n_win
    out[:, MAX_ABS_ERR] = max_win
    out[:, FUEL] = fuel
    out[:, FIRINGS] = firings
    out[:, SETTLING_TIME] = np.where(
        last_out < 0, 0.0, np.where(last_out >= n_steps, np.nan, (last_out + 1) * dt)
    )
    out[:, FINAL_ERR] = e
    return out
