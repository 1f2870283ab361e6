"""Private batch kernel of the wheel / magnetorquer loop: one sample per parallel lane.

The per-sample function :func:`wheel_sample` is declared as a
:class:`adcskit._targets.PerSample` (``SAMPLE``) and the CPU driver :func:`run_wheels` runs
blocks of samples on threads, each through the compiled, GIL-free :func:`run_block` that calls
``SAMPLE.cpu`` (not a ``prange`` driver: see :func:`run_wheels`); its helpers are
:func:`adcskit._targets.device` functions. Rules of the one-source idiom: scalars, ``math``
and indexing of arrays passed in; the per-sample scratch rows (``X``, ``XT``, ``KS``,
``KD``, ``TM``) are allocated by the Python driver (:mod:`adcskit.simulation.wheels`). The
function calls only device helpers (no CPU-only dispatcher), so the same source is also
compiled by ``numba.cuda.jit(device=True)``: the GPU driver :func:`run_wheels_cuda` runs one
CUDA thread per sample (tested bit for bit against the CPU driver under numba's CUDA
simulator, and compiled to PTX for sm_90 when numba-cuda and NVVM are installed).

Plant (Markley & Crassidis 2014, §3.3.5, eqs. 3.147-3.150 in their notation; Wie 2008,
§7.2): a rigid spacecraft with ``n_w`` reaction wheels along unit axes ``a_j`` (columns of
``A``). ``h_j = J_w,j (a_j . omega + Omega_j)`` is wheel ``j``'s *absolute* axial angular
momentum and ``Omega_j`` its speed relative to the body; ``J`` is the spacecraft inertia
without the wheels' axial inertia. Then ::

    H_body = J omega + A h                                   (total angular momentum, body)
    J omega' = -omega x (J omega + A h) - A tau_w + tau_ext
    h'       = tau_w,         tau_w = tau_motor - tau_friction(Omega)
    q'       = 1/2 [omega; 0] (x) q                          (Markley's product, scalar last)

``tau_friction = c_v Omega + c_c Omega / sqrt(Omega^2 + eps^2)`` (viscous + smoothed
Coulomb, eps = :data:`COULOMB_EPS`). Without external torque ``A(q)^T H_body`` is constant
(tested to 1e-10). Integration: classical RK4 with the motor torques and the external torque
held over a step; the quaternion is renormalised (``q4 >= 0``).

Thruster unloading (optional; ``C[NT]`` thrusters described by the columns of ``THR``): above a
wheel-momentum threshold, the torque ``-T h/|h|`` is allocated by the thruster loop's
:func:`~adcskit.simulation._kernels.rpi_allocate` (a device-compatible ``register_jitable``
helper), fired as pulses centred in the control period (:func:`unload_plan`,
:func:`thrust_step`; their scratch is the tail of the sample's ``TM`` row, :func:`tm_len`), and
fed forward into the wheel command so that the wheels hold the attitude.

Attitude filter (optional, ``C[EST_ON]``): the MEKF kernels of
:mod:`adcskit.estimation._mekf_kernels` (``register_jitable``, device-compatible) on the
sample's ``KP[i]`` (covariance, 6 x 6) and ``KW[i]`` (state and scratch, ``N_KW``): propagated
every step with a rate-integrating gyro reading (the step's mean rate from the attitude
increment plus the held reading error), updated by the star tracker, sun sensor and magnetometer;
the controller then uses its attitude and bias-corrected rate.

Randomness: a SplitMix64 stream per sample (Steele, Lea & Flood 2014) seeded with one 64-bit
integer, normals by Box-Muller; the generator is the thruster simulator's
(:mod:`adcskit.simulation._random`). The quaternion helpers (``qdiff``, ``qdot``,
``unit_q4_pos``, ``rotate``, ``compose_rotvec``) are :mod:`adcskit.attitude._device`'s, shared
with the thruster simulator and the MEKF.

Conventions: quaternion scalar last, ``A(q)`` maps ECI to body; SI units, rad.
"""

from __future__ import annotations

import math
from collections import namedtuple
from typing import NamedTuple

import numpy as np
from numba import njit

from adcskit._targets import LazyKernels, PerSample, device, import_cuda, launch_chunked, rebound
from adcskit.attitude._device import compose_rotvec, qdiff, qdot, rotate, unit_q4_pos
from adcskit.estimation import _mekf_kernels as _mk
from adcskit.estimation._mekf_kernels import (
    mekf_nees,
    mekf_propagate,
    mekf_update_quaternion,
    mekf_update_vector,
)
from adcskit.simulation._kernels import Arg, outside, rpi_allocate, settle_bounds
from adcskit.simulation._kernels import qangle as _angle
from adcskit.simulation._random import normal as _normal
from adcskit.simulation._random import normal2 as _normal2

# ----------------------------------------------------------------- shared coefficients C
(
    DT, N_STEPS, H_CTRL, H_GYRO, H_SUN, H_MAG, H_ST, NW, N2ORB, D_OMEGA,
    SIG_SUN, SIG_MAG, SIG_ST, SIG_V, SIG_U,
    LAW, K_GAIN, C_GAIN, RATE_MAX, TAU_MAX, OMEGA_MAX, C_VISC, C_COUL, TQ_QUANT, TQ_NOISE,
    NULL_GAIN, MTQ_MAX, MTQ_ON_STEPS, MAG_MODE, MAG_COUPLING, BDOT_GAIN, UNLOAD_GAIN,
    MODE0, SEQUENCE, RATE_THR, DWELL_STEPS, SUN_THR_COS, SUN_AX0, SUN_AX1, SUN_AX2,
    POINT_KIND, ORBIT_RATE, K_WIN, SETTLE_BAND, REC_EVERY,
    JN0,  # nominal inertia, 9 entries JN0..JN0+8
) = range(46)
# thruster unloading (after the nominal inertia): thruster count, start / stop thresholds on
# |A_nom h| (N m s), requested unloading torque (N m), allocation regularisation
NT, UNL_START, UNL_STOP, UNL_TORQUE, UNL_EPS = range(JN0 + 9, JN0 + 14)
# attitude filter (MEKF) in the loop: on (1) / off (0), initial attitude sigma (rad), initial
# gyro-bias sigma (rad/s), measurement underweighting factor
EST_ON, EST_SIG0, EST_SIGB0, EST_UW = range(JN0 + 14, JN0 + 18)
# open-loop dipole command (law "open-loop"), 3 entries OL_DIP0..OL_DIP0+2
OL_DIP0 = JN0 + 18
N_COEFS = JN0 + 21

# per-sample filter scratch KW: q (4), b (3), gyro reading (3), body and reference vectors (3 + 3),
# true q (4) and bias (3) for the NEES, then the MEKF work array (from KW_WORK); P is KP[i] (6, 6)
KW_Q, KW_B, KW_WM, KW_VB, KW_VR, KW_QT, KW_BT, KW_WORK = 0, 4, 7, 10, 13, 16, 20, 24
N_KW = KW_WORK + _mk.WORK_SIZE

LAW_PD, LAW_WIE, LAW_OPEN = 0, 1, 2
MODE_DETUMBLE, MODE_SUN, MODE_POINT = 0, 1, 2
MAG_BLANK, MAG_CORRUPT = 0, 1
POINT_NADIR, POINT_INERTIAL = 0, 1

#: Smoothing rate of the Coulomb friction sign, rad/s.
COULOMB_EPS = 0.01

# ----------------------------------------------------------------- per-sample parameters P
# J (9), Jinv (9), q0 (4), w0 (3), gyro bias (3), noise scale, d0 (3), damp (3), dphase (3)
(P_J, P_JI, P_Q0, P_W0, P_BIAS, P_NS, P_D0, P_DAMP, P_DPH) = (0, 9, 18, 22, 25, 28, 29, 32, 35)
N_PARAMS = 38

# ----------------------------------------------------------------- ENV columns (per step)
# r_hat (3), sun (3), B ECI in T (3), lit, q_ref (4): LVLH (nadir) or the inertial target
E_R, E_SUN, E_B, E_LIT, E_QREF = 0, 3, 6, 9, 10
N_ENV = 14

# ----------------------------------------------------------------- WPAR columns (per wheel)
W_JW, W_FAILED, W_OMEGA0, W_OPEN = 0, 1, 2, 3
N_WPAR = 4

# ----------------------------------------------------------------- THR rows (per thruster)
# torque matrix (r_j - com) x d_j (3 rows, N m per N), f_max (N), allocation mask (1: the
# allocator may use it), failed (1: never fires), mdot (kg/s), minimum on-time (s)
T_A, T_FMAX, T_MASK, T_FAILED, T_MDOT, T_TMIN = 0, 3, 4, 5, 6, 7
N_THR_ROWS = 8

# ----------------------------------------------------------------- metrics
(M_T_DETUMBLED, M_T_ACQUIRED, M_FINAL_MODE, M_POINT_MEAN, M_POINT_RMS, M_POINT_MAX, M_POINT_FRAC,
 M_SETTLE, M_KNOW_RMS, M_FINAL_RATE, M_MAX_RATE_WIN, M_MAX_SPEED, M_MAX_HW, M_FINAL_HW, M_MAX_DIPOLE,
 M_H_DRIFT, M_SUN_FINAL, M_PROPELLANT, M_IMPULSE, M_ON_TIME, M_UNLOADS, M_UNLOAD_TIME, M_NEES,
 M_NEES_N) = range(24)
N_METRICS = 24

# ----------------------------------------------------------------- trace channels
(R_ERR, R_WX, R_WY, R_WZ, R_RATE, R_HX, R_HY, R_HZ, R_HW, R_HIX, R_HIY, R_HIZ, R_MX, R_MY, R_MZ,
 R_MODE, R_KNOW) = range(17)
N_REC_FIXED = 17  # + wheel speeds (n_w) + wheel momenta (n_w) [+ N_REC_THR with unloading thrusters]
# [+ the filter's NEES (1 channel) with the MEKF on]
# with unloading thrusters, after the wheel channels: thruster torque on the body (3, N m),
# cumulative thruster angular impulse in ECI (3, N m s), cumulative propellant (kg)
(RT_TX, RT_TY, RT_TZ, RT_LX, RT_LY, RT_LZ, RT_PROP) = range(7)
N_REC_THR = 7


def tm_len(nw, nt):
    """Length of a sample's ``TM`` scratch row: wheel motor torques (``nw``) and, with
    thrusters, their commanded on-times, allocation forces and flags (``2 nt``) and the
    allocator's 3x3 scratch (15)."""
    return nw if nt == 0 else nw + 2 * nt + 15

@device
def _normal3(s):
    """(new state, three independent standard normals)."""
    s, z0, z1 = _normal2(s)
    s, z2 = _normal(s)
    return s, z0, z1, z2


@device
def _mat3(M, o, x0, x1, x2):
    """``M[o:o+9]`` (row-major 3x3) times ``x``."""
    return (M[o] * x0 + M[o + 1] * x1 + M[o + 2] * x2,
            M[o + 3] * x0 + M[o + 4] * x1 + M[o + 5] * x2,
            M[o + 6] * x0 + M[o + 7] * x1 + M[o + 8] * x2)


@device
def rk4(X, XT, KS, KD, J, JI, AX, nw, TM, JW, cv, cc, t0, t1, t2, dt):
    """One classical RK4 step of the gyrostat ``X = [q (4), omega (3), h (n_w)]`` in place
    (torques held); ``q`` renormalised.

    The four stages are one loop over the gyrostat derivative (module docstring), written out
    here rather than called: a called derivative took its seven arrays as numba's flattened
    structs through the stack at each of the four calls, and the caller's reference counts of
    them (18 atomic increments and decrements per step). The attitude and rate (``y``, their
    derivative ``k``, the stage sum ``g``) stay in scalars; the wheel momenta use the rows
    ``XT``, ``KD``, ``KS`` from index 7. The operations and their order are those of the former
    ``rhs`` and element-wise stage updates (``XT = X + 0.5 dt KD``, ``KS += 2 KD``, ...).
    """
    n = 7 + nw
    x0, x1, x2, x3, x4, x5, x6 = X[0], X[1], X[2], X[3], X[4], X[5], X[6]
    y0, y1, y2, y3, y4, y5, y6 = x0, x1, x2, x3, x4, x5, x6
    g0 = g1 = g2 = g3 = g4 = g5 = g6 = 0.0
    k0 = k1 = k2 = k3 = k4 = k5 = k6 = 0.0
    for m in range(7, n):
        XT[m] = X[m]
    for stage in range(4):
        # ---- derivative of (y, XT[7:]) into (k, KD[7:])
        w0, w1, w2 = y4, y5, y6
        ah0 = 0.0
        ah1 = 0.0
        ah2 = 0.0
        at0 = 0.0
        at1 = 0.0
        at2 = 0.0
        if cc == 0.0:
            # no Coulomb friction (the default): for cc = +-0 the term cc om / sqrt(om^2 + eps^2)
            # IS the product cc om, bit for bit -- a signed zero divided by a positive divisor
            # (finite, or +inf when om^2 overflows) keeps its sign, and an infinite or NaN om
            # gives the same NaN either way -- so the square root and the division are skipped
            # and the sum keeps its operands (cv om + cc om), signed zeros included. Two copies
            # of the wheel loop: with the test inside one loop LLVM computed both terms and
            # selected one, keeping the square root and the division.
            for j in range(nw):
                a0, a1, a2 = AX[0, j], AX[1, j], AX[2, j]
                h = XT[7 + j]
                om = h / JW[j] - (a0 * w0 + a1 * w1 + a2 * w2)
                tw = TM[j] - (cv * om + cc * om)
                KD[7 + j] = tw
                ah0 += a0 * h
                ah1 += a1 * h
                ah2 += a2 * h
                at0 += a0 * tw
                at1 += a1 * tw
                at2 += a2 * tw
        else:
            for j in range(nw):
                a0, a1, a2 = AX[0, j], AX[1, j], AX[2, j]
                h = XT[7 + j]
                om = h / JW[j] - (a0 * w0 + a1 * w1 + a2 * w2)
                tw = TM[j] - (cv * om + cc * om / math.sqrt(om * om + COULOMB_EPS * COULOMB_EPS))
                KD[7 + j] = tw
                ah0 += a0 * h
                ah1 += a1 * h
                ah2 += a2 * h
                at0 += a0 * tw
                at1 += a1 * tw
                at2 += a2 * tw
        j0, j1, j2 = _mat3(J, 0, w0, w1, w2)
        H0 = j0 + ah0
        H1 = j1 + ah1
        H2 = j2 + ah2
        m0 = t0 - at0 - (w1 * H2 - w2 * H1)
        m1 = t1 - at1 - (w2 * H0 - w0 * H2)
        m2 = t2 - at2 - (w0 * H1 - w1 * H0)
        k4, k5, k6 = _mat3(JI, 0, m0, m1, m2)
        k0, k1, k2, k3 = qdot(y0, y1, y2, y3, w0, w1, w2)
        # ---- stage update
        if stage == 0:
            g0, g1, g2, g3, g4, g5, g6 = k0, k1, k2, k3, k4, k5, k6
            hh = 0.5 * dt
            y0, y1, y2, y3 = x0 + hh * k0, x1 + hh * k1, x2 + hh * k2, x3 + hh * k3
            y4, y5, y6 = x4 + hh * k4, x5 + hh * k5, x6 + hh * k6
            for m in range(7, n):
                KS[m] = KD[m]
                XT[m] = X[m] + 0.5 * dt * KD[m]
        elif stage < 3:
            g0, g1, g2, g3 = g0 + 2.0 * k0, g1 + 2.0 * k1, g2 + 2.0 * k2, g3 + 2.0 * k3
            g4, g5, g6 = g4 + 2.0 * k4, g5 + 2.0 * k5, g6 + 2.0 * k6
            hh = 0.5 * dt if stage == 1 else dt
            y0, y1, y2, y3 = x0 + hh * k0, x1 + hh * k1, x2 + hh * k2, x3 + hh * k3
            y4, y5, y6 = x4 + hh * k4, x5 + hh * k5, x6 + hh * k6
            for m in range(7, n):
                KS[m] += 2.0 * KD[m]
                XT[m] = X[m] + hh * KD[m]
    s = dt / 6.0
    for m in range(7, n):
        X[m] = X[m] + s * (KS[m] + KD[m])
    X[4] = x4 + s * (g4 + k4)
    X[5] = x5 + s * (g5 + k5)
    X[6] = x6 + s * (g6 + k6)
    X[0], X[1], X[2], X[3] = unit_q4_pos(x0 + s * (g0 + k0), x1 + s * (g1 + k1), x2 + s * (g2 + k2),
                                         x3 + s * (g3 + k3))


@device
def _wheel_momentum(X, AX, nw):
    h0 = 0.0
    h1 = 0.0
    h2 = 0.0
    for j in range(nw):
        h0 += AX[0, j] * X[7 + j]
        h1 += AX[1, j] * X[7 + j]
        h2 += AX[2, j] * X[7 + j]
    return h0, h1, h2


@device
def _clip_norm(x0, x1, x2, lim):
    """Scale a vector to norm ``lim`` if longer (direction kept)."""
    n = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    if n > lim:
        f = lim / n
        return x0 * f, x1 * f, x2 * f
    return x0, x1, x2


@device
def _clip_max(x0, x1, x2, lim):
    """Scale a vector so that its largest component is at most ``lim`` (direction kept)."""
    m = max(abs(x0), abs(x1), abs(x2))
    if m > lim:
        f = lim / m
        return x0 * f, x1 * f, x2 * f
    return x0, x1, x2


@device
def allocate(C, X, PINV, NULLP, HSTAR, nw, TM, c0, c1, c2):
    """Body torque demand ``c`` (N m, on the body) -> motor torques ``TM`` on the wheels:
    ``-A^+ c`` (working wheels only: ``PINV`` has zero rows for known failures) plus the
    null motion ``-k_n N (h - h*)`` (``N = I - A^+ A``), scaled uniformly to the torque limit."""
    tmax = C[TAU_MAX]
    kn = C[NULL_GAIN]
    big = 0.0
    for j in range(nw):
        v = -(PINV[j, 0] * c0 + PINV[j, 1] * c1 + PINV[j, 2] * c2)
        if kn > 0.0:
            acc = 0.0
            for m in range(nw):
                acc += NULLP[j, m] * (X[7 + m] - HSTAR[m])
            v -= kn * acc
        TM[j] = v
        if abs(v) > big:
            big = abs(v)
    if big > tmax:
        f = tmax / big
        for j in range(nw):
            TM[j] *= f


@device
def actuate(C, X, AX, WPAR, nw, TM, s):
    """Wheel drive electronics: quantisation, noise, torque and speed limits, failures."""
    tmax = C[TAU_MAX]
    qs = C[TQ_QUANT]
    sig = C[TQ_NOISE]
    wmax = C[OMEGA_MAX]
    w0, w1, w2 = X[4], X[5], X[6]
    for j in range(nw):
        v = TM[j]
        if qs > 0.0:
            v = qs * math.floor(v / qs + 0.5)
        if sig > 0.0:
            s, z = _normal(s)
            v += sig * z
        if v > tmax:
            v = tmax
        elif v < -tmax:
            v = -tmax
        om = X[7 + j] / WPAR[j, W_JW] - (AX[0, j] * w0 + AX[1, j] * w1 + AX[2, j] * w2)
        if abs(om) >= wmax and v * om > 0.0:
            v = 0.0
        if WPAR[j, W_FAILED] > 0.0:
            v = 0.0
        TM[j] = v
    return s


@device
def unload_plan(THR, TF, TFREE, TS, TR, TY, nt, tq, eps, tp, h0, h1, h2):
    """Thruster on-times of one control period for the unloading torque ``-tq h/|h|``.

    The torque over ``tp`` seconds is allocated to forces ``0 <= F_j <= f_max,j`` by the
    closed loop's redistributed pseudo-inverse (:func:`adcskit.simulation._kernels.rpi_allocate`,
    S3 eq. 12; thrusters with a zero mask left out), turned into pulse widths
    ``t_j = F_j / f_max,j * tp`` (S3 eq. 6; fired centred in the period, :func:`thrust_step`) and
    pulses shorter than the minimum on-time
    dropped (S3 §2-2, :func:`adcskit.thrusters.realisable_pulses` ``"drop"``). The on-times are
    written to ``TF``; returns the commanded torque averaged over the period (N m, body), the
    wheels' feed-forward.
    """
    hn = math.sqrt(h0 * h0 + h1 * h1 + h2 * h2)
    f = -tq / hn
    rpi_allocate(THR, f * h0, f * h1, f * h2, THR[T_FMAX], THR[T_MASK], TF, TFREE, TS, TR, TY, eps)
    c0 = 0.0
    c1 = 0.0
    c2 = 0.0
    for j in range(nt):
        fm = THR[T_FMAX, j]
        ton = TF[j] / fm * tp
        if ton < THR[T_TMIN, j]:
            ton = 0.0
        TF[j] = ton
        c0 += THR[T_A, j] * fm * ton
        c1 += THR[T_A + 1, j] * fm * ton
        c2 += THR[T_A + 2, j] * fm * ton
    return c0 / tp, c1 / tp, c2 / tp


@device
def thrust_step(THR, TF, nt, t_in, tp, dt):
    """The thrusters over one step that starts ``t_in`` seconds into the control period of
    length ``tp``: pulse ``j`` is centred in the period, ``[(tp - TF[j]) / 2, (tp + TF[j]) / 2]``
    (a failed thruster never fires). Centred, a pulse and the wheels' constant counter-torque
    over the period leave no net rotation over the period (a pulse at the start of the period
    would turn the body by ``I (tp - t_on) / (2 J)`` every period, a bias the attitude loop
    must hold against).

    Returns the body torque held over the step (N m: the step's angular impulse over ``dt``),
    the step's linear impulse ``sum f_max,j o_j`` (N s), propellant ``sum mdot_j o_j`` (kg) and
    on-time ``sum o_j`` (s), with ``o_j`` the part of pulse ``j`` inside the step."""
    c0 = 0.0
    c1 = 0.0
    c2 = 0.0
    imp = 0.0
    prop = 0.0
    on = 0.0
    for j in range(nt):
        o = min(t_in + dt, 0.5 * (tp + TF[j])) - max(t_in, 0.5 * (tp - TF[j]))
        if o > 0.0 and THR[T_FAILED, j] == 0.0:
            fm = THR[T_FMAX, j]
            c0 += THR[T_A, j] * fm * o
            c1 += THR[T_A + 1, j] * fm * o
            c2 += THR[T_A + 2, j] * fm * o
            imp += fm * o
            prop += THR[T_MDOT, j] * o
            on += o
    return c0 / dt, c1 / dt, c2 / dt, imp, prop, on


def _step(fn):
    """A step function of :func:`wheel_sample`: numba inlines it into the CPU compilation at the
    untyped IR (``njit(inline="always")``: compiled once, with the loop; as a call it would get
    the kernel's named tuple of arrays as about 200 flattened scalars each step, and numba's
    typed inlining, ``device(inline="always")``, compiles it on its own first: 8 CPU-s more);
    the CUDA compilation takes the plain function (``SAMPLE``'s ``device_names``)."""
    return njit(inline="always")(fn)


@_step
def _rows(i, A):
    """Sample ``i``'s views, made once per sample: the gyrostat state and RK4 scratch rows, the
    motor torques, J and J^-1 (row-major), the wheel axes; the unloading thrusters' on-times
    and allocator scratch (the tail of the ``TM`` row, :func:`tm_len`); the filter's covariance
    and the slices of its ``KW`` row (``KW_*``)."""
    nw = int(A.C[NW])
    nt = int(A.C[NT])
    TMi = A.TM[i]
    KWi = A.KW[i]
    o = nw + 2 * nt
    rows = (A.X[i], A.XT[i], A.KS[i], A.KD[i], TMi, A.P[i, P_J:P_J + 9], A.P[i, P_JI:P_JI + 9], A.AX[i])
    jets = (TMi[nw:nw + nt], TMi[nw + nt:o], TMi[o:o + 9], TMi[o + 9:o + 12], TMi[o + 12:o + 15])
    kf = (A.KP[i], KWi[KW_Q:KW_Q + 4], KWi[KW_B:KW_B + 3], KWi[KW_WM:KW_WM + 3], KWi[KW_VB:KW_VB + 3],
          KWi[KW_VR:KW_VR + 3], KWi[KW_QT:KW_QT + 4], KWi[KW_BT:KW_BT + 3], KWi[KW_WORK:KW_WORK + _mk.WORK_SIZE])
    return rows, jets, kf


@_step
def _init(i, A, rows, kf):
    """Sample ``i``'s initial gyrostat state (``X`` row), zero motor torques and, with the
    filter, its initial estimate (the truth turned by a Gaussian rotation vector of sigma
    ``EST_SIG0``, no bias) and covariance. Returns the noise state and the knowledge
    ``(q_est, rate used by the controller)``."""
    C = A.C
    P = A.P
    nw = int(C[NW])
    Xi, _, _, _, TMi, _, _, AXi = rows
    KPi, kq, kb, _, _, _, _, _, _ = kf
    s = A.SEEDS[i]
    for m in range(4):
        Xi[m] = P[i, P_Q0 + m]
    for m in range(3):
        Xi[4 + m] = P[i, P_W0 + m]
    for j in range(nw):
        Xi[7 + j] = A.JW[j] * (A.WPAR[j, W_OMEGA0] + AXi[0, j] * Xi[4] + AXi[1, j] * Xi[5] + AXi[2, j] * Xi[6])
        TMi[j] = 0.0
    qe0, qe1, qe2, qe3 = Xi[0], Xi[1], Xi[2], Xi[3]
    if C[EST_ON] > 0.0:
        s, z0, z1, z2 = _normal3(s)
        sg = C[EST_SIG0]
        for m in range(4):
            kq[m] = Xi[m]
        compose_rotvec(kq, sg * z0, sg * z1, sg * z2)
        qe0, qe1, qe2, qe3 = kq[0], kq[1], kq[2], kq[3]
        for a in range(6):
            kb[a % 3] = 0.0
            for c in range(6):
                KPi[a, c] = 0.0
        for a in range(3):
            KPi[a, a] = sg * sg
            KPi[3 + a, 3 + a] = C[EST_SIGB0] * C[EST_SIGB0]
    return s, (qe0, qe1, qe2, qe3)


@_step
def _truth(k, A, rows, q, w, qe, mode, rrow, grid, ctrl, in_win, band, tb, mt):
    """The truth quantities of step ``k`` that a metric or the trace reads (each only where it
    is read): pointing and knowledge errors, rate, wheel momentum and speeds, inertial total
    angular momentum, sun angle; adds them to the metric accumulators ``mt`` (the window's sums,
    pointing only in the pointing mode). Returns ``mt``, the pointing and knowledge errors and
    the rate (NaN where not computed) and the body wheel momentum and its norm and the inertial
    momentum (the values of the last grid or control step)."""
    ENV = A.ENV
    C = A.C
    nw = int(C[NW])
    Xi, _, _, _, _, Ji, _, AXi = rows
    q0, q1, q2, q3 = q
    w0, w1, w2 = w
    qe0, qe1, qe2, qe3 = qe
    (n_win, n_pt, sum_e, sum_e2, max_e, sum_k2, last_out, max_rate_win, max_speed, max_hw, max_drift,
     hi0, hi1, hi2, hin, sun_err, hb0, hb1, hb2, hw, H0, H1, H2) = mt
    t = k * C[DT]
    point = mode == MODE_POINT
    rate = math.nan
    if in_win or rrow:
        rate = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    qr0, qr1, qr2, qr3 = ENV[k, E_QREF], ENV[k, E_QREF + 1], ENV[k, E_QREF + 2], ENV[k, E_QREF + 3]
    perr = math.nan
    kerr = math.nan
    if point:
        # the error's value only for the window's metrics and the trace; elsewhere only
        # whether it exceeds the settling band
        if in_win or rrow:
            d0, d1, d2, d3 = qdiff(q0, q1, q2, q3, qr0, qr1, qr2, qr3)
            perr = _angle(d0, d1, d2, d3)
            if perr > band:
                last_out = t
        elif outside(q0, q1, q2, q3, qr0, qr1, qr2, qr3, band, tb[0], tb[1]):
            last_out = t
    if (point and in_win) or rrow:
        d0, d1, d2, d3 = qdiff(qe0, qe1, qe2, qe3, q0, q1, q2, q3)
        kerr = _angle(d0, d1, d2, d3)
    if grid or ctrl:
        hb0, hb1, hb2 = _wheel_momentum(Xi, AXi, nw)
        hw = math.sqrt(hb0 * hb0 + hb1 * hb1 + hb2 * hb2)
        if hw > max_hw:
            max_hw = hw
        for j in range(nw):
            om = abs(Xi[7 + j] / A.JW[j] - (AXi[0, j] * w0 + AXi[1, j] * w1 + AXi[2, j] * w2))
            if om > max_speed:
                max_speed = om
    if grid:
        # inertial total angular momentum A(q)^T (J w + A h) (rotation by the conjugate)
        j0, j1, j2 = _mat3(Ji, 0, w0, w1, w2)
        H0, H1, H2 = rotate(-q0, -q1, -q2, q3, j0 + hb0, j1 + hb1, j2 + hb2)
        if k == 0:
            hi0, hi1, hi2 = H0, H1, H2
            hin = math.sqrt(H0 * H0 + H1 * H1 + H2 * H2)
        dr = math.sqrt((H0 - hi0) ** 2 + (H1 - hi1) ** 2 + (H2 - hi2) ** 2) / max(hin, 1e-300)
        if dr > max_drift:
            max_drift = dr
        st0, st1, st2 = rotate(q0, q1, q2, q3, ENV[k, E_SUN], ENV[k, E_SUN + 1], ENV[k, E_SUN + 2])
        ca = st0 * C[SUN_AX0] + st1 * C[SUN_AX1] + st2 * C[SUN_AX2]
        sun_err = math.acos(min(1.0, max(-1.0, ca)))
    # ---- metrics over the window, pointing only while in the pointing mode
    if in_win:
        n_win += 1
        if rate > max_rate_win:
            max_rate_win = rate
        if point:
            n_pt += 1
            sum_e += perr
            sum_e2 += perr * perr
            sum_k2 += kerr * kerr
            if perr > max_e:
                max_e = perr
    mt = (n_win, n_pt, sum_e, sum_e2, max_e, sum_k2, last_out, max_rate_win, max_speed, max_hw, max_drift,
          hi0, hi1, hi2, hin, sun_err, hb0, hb1, hb2, hw, H0, H1, H2)
    return mt, perr, kerr, rate


@device
def _record(i, r, A, rows, w, mode, perr, kerr, rate, mt, dip, nees, jet):
    """Trace row ``r`` of sample ``i`` (the ``R_*`` channels, wheel speeds and momenta, the
    filter's NEES, the unloading thrusters' torque, impulse and propellant)."""
    REC = A.REC
    nw = int(A.C[NW])
    nt = int(A.C[NT])
    Xi, _, _, _, _, _, _, AXi = rows
    w0, w1, w2 = w
    hb0, hb1, hb2, hw, H0, H1, H2 = mt[16], mt[17], mt[18], mt[19], mt[20], mt[21], mt[22]
    m0, m1, m2 = dip
    tt0, tt1, tt2, li0, li1, li2, prop = jet
    if mode == MODE_POINT:
        REC[i, r, R_ERR] = perr
    elif mode == MODE_SUN:
        REC[i, r, R_ERR] = mt[15]
    else:
        REC[i, r, R_ERR] = math.nan
    REC[i, r, R_WX] = w0
    REC[i, r, R_WY] = w1
    REC[i, r, R_WZ] = w2
    REC[i, r, R_RATE] = rate
    REC[i, r, R_HX] = hb0
    REC[i, r, R_HY] = hb1
    REC[i, r, R_HZ] = hb2
    REC[i, r, R_HW] = hw
    REC[i, r, R_HIX] = H0
    REC[i, r, R_HIY] = H1
    REC[i, r, R_HIZ] = H2
    REC[i, r, R_MX] = m0
    REC[i, r, R_MY] = m1
    REC[i, r, R_MZ] = m2
    REC[i, r, R_MODE] = mode
    REC[i, r, R_KNOW] = kerr
    for j in range(nw):
        REC[i, r, N_REC_FIXED + j] = Xi[7 + j] / A.JW[j] - (AXi[0, j] * w0 + AXi[1, j] * w1 + AXi[2, j] * w2)
        REC[i, r, N_REC_FIXED + nw + j] = Xi[7 + j]
    rec_thr = N_REC_FIXED + 2 * nw
    if A.C[EST_ON] > 0.0:
        REC[i, r, rec_thr + (N_REC_THR if nt > 0 else 0)] = nees
    if nt > 0:
        REC[i, r, rec_thr + RT_TX] = tt0
        REC[i, r, rec_thr + RT_TY] = tt1
        REC[i, r, rec_thr + RT_TZ] = tt2
        REC[i, r, rec_thr + RT_LX] = li0
        REC[i, r, rec_thr + RT_LY] = li1
        REC[i, r, rec_thr + RT_LZ] = li2
        REC[i, r, rec_thr + RT_PROP] = prop


@_step
def _gyro(s, w, sig_g, sig_b, bias):
    """Gyro reading at a gyro epoch: the true rate plus the bias and white noise (sigma
    ``sig_g``), then the bias random walk (sigma ``sig_b``). Returns the noise state, the
    reading, the reading's error (bias + noise: the filter's held delta-angle error) and the
    new bias."""
    b0, b1, b2 = bias
    s, z0, z1 = _normal2(s)
    s, z2, z3 = _normal2(s)
    s, z4, z5 = _normal2(s)
    wm = (w[0] + b0 + sig_g * z0, w[1] + b1 + sig_g * z1, w[2] + b2 + sig_g * z2)
    eg = (b0 + sig_g * z0, b1 + sig_g * z1, b2 + sig_g * z2)
    return s, wm, eg, (b0 + sig_b * z3, b1 + sig_b * z4, b2 + sig_b * z5)


@_step
def _vectors(k, A, kf, q, s, ns, sun_due, mag_due, firing, sun, mag, dip):
    """Sun sensor (when lit) and magnetometer at step ``k`` when due (the magnetometer blanked
    or corrupted while the rods were on, ``firing``), each followed by the filter's vector
    update when it is on. ``sun`` = (valid, unit vector), ``mag`` = (count, reading, previous
    reading, their times, new): returns the noise state, ``sun``, ``mag``."""
    C = A.C
    ENV = A.ENV
    KPi, kq, kb, _, kvb, kvr, _, _, kwk = kf
    q0, q1, q2, q3 = q
    filt = C[EST_ON] > 0.0
    uw = C[EST_UW]
    sv, s0, s1, s2 = sun
    nmag, bm0, bm1, bm2, bp0, bp1, bp2, tmag, tprev, newmag = mag
    if sun_due:
        if ENV[k, E_LIT] > 0.5:
            st0, st1, st2 = rotate(q0, q1, q2, q3, ENV[k, E_SUN], ENV[k, E_SUN + 1], ENV[k, E_SUN + 2])
            sg = C[SIG_SUN] * ns
            s, z0, z1, z2 = _normal3(s)
            x0 = st0 + sg * z0
            x1 = st1 + sg * z1
            x2 = st2 + sg * z2
            nn = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
            s0, s1, s2 = x0 / nn, x1 / nn, x2 / nn
            sv = 1
            if filt:
                kvb[0], kvb[1], kvb[2] = s0, s1, s2
                kvr[0], kvr[1], kvr[2] = ENV[k, E_SUN], ENV[k, E_SUN + 1], ENV[k, E_SUN + 2]
                mekf_update_vector(kq, kb, KPi, kvb, kvr, C[SIG_SUN], uw, kwk)
        else:
            sv = 0
    if mag_due and not (firing and C[MAG_MODE] == MAG_BLANK):
        Bb0, Bb1, Bb2 = rotate(q0, q1, q2, q3, ENV[k, E_B], ENV[k, E_B + 1], ENV[k, E_B + 2])
        bn = math.sqrt(Bb0 * Bb0 + Bb1 * Bb1 + Bb2 * Bb2)
        sg = C[SIG_MAG] * ns * bn
        s, z0, z1, z2 = _normal3(s)
        bp0, bp1, bp2, tprev = bm0, bm1, bm2, tmag
        bm0 = Bb0 + sg * z0
        bm1 = Bb1 + sg * z1
        bm2 = Bb2 + sg * z2
        if firing:
            bm0 += C[MAG_COUPLING] * dip[0]
            bm1 += C[MAG_COUPLING] * dip[1]
            bm2 += C[MAG_COUPLING] * dip[2]
        tmag = k * C[DT]
        nmag += 1
        newmag = 1
        if filt:
            kvb[0], kvb[1], kvb[2] = bm0, bm1, bm2
            kvr[0], kvr[1], kvr[2] = ENV[k, E_B], ENV[k, E_B + 1], ENV[k, E_B + 2]
            mekf_update_vector(kq, kb, KPi, kvb, kvr, C[SIG_MAG], uw, kwk)
    return s, (sv, s0, s1, s2), (nmag, bm0, bm1, bm2, bp0, bp1, bp2, tmag, tprev, newmag)


@_step
def _modes(C, md, t, rm, sun):
    """The mode sequence at a control instant ``t``: detumble -> sun once the measured rate
    ``rm`` stayed below ``RATE_THR``, sun -> pointing once the sun stayed within the
    acquisition cone, each for ``DWELL_STEPS``. ``md`` = (mode, dwell, t_detumbled, t_acquired)."""
    mode, dwell, t_det, t_acq = md
    hc = int(C[H_CTRL])
    sv, s0, s1, s2 = sun
    if C[SEQUENCE] > 0.0 and mode == MODE_DETUMBLE:
        if rm < C[RATE_THR]:
            dwell += hc
        else:
            dwell = 0
        if dwell >= int(C[DWELL_STEPS]):
            mode = MODE_SUN
            dwell = 0
            t_det = t
    elif C[SEQUENCE] > 0.0 and mode == MODE_SUN:
        if sv == 1 and s0 * C[SUN_AX0] + s1 * C[SUN_AX1] + s2 * C[SUN_AX2] >= C[SUN_THR_COS]:
            dwell += hc
        else:
            dwell = 0
        if dwell >= int(C[DWELL_STEPS]):
            mode = MODE_POINT
            dwell = 0
            t_acq = t
    return mode, dwell, t_det, t_acq


@_step
def _law(k, A, mode, qe, wc, sun):
    """The attitude law's body acceleration demand (sun pointing or quaternion feedback on the
    reference of step ``k``, ``pd`` or ``wie`` with its rate clip), without the gyroscopic
    term."""
    C = A.C
    kk = C[K_GAIN]
    cc_ = C[C_GAIN]
    rmax = C[RATE_MAX]
    law = int(C[LAW])
    wc0, wc1, wc2 = wc
    if mode == MODE_SUN:
        sv, s0, s1, s2 = sun
        if sv == 1:
            ax0, ax1, ax2 = C[SUN_AX0], C[SUN_AX1], C[SUN_AX2]
            e0 = kk * (ax1 * s2 - ax2 * s1)
            e1 = kk * (ax2 * s0 - ax0 * s2)
            e2 = kk * (ax0 * s1 - ax1 * s0)
            if law == LAW_WIE:
                e0, e1, e2 = _clip_norm(e0, e1, e2, cc_ * rmax)
        else:
            e0 = 0.0
            e1 = 0.0
            e2 = 0.0
        return e0 - cc_ * wc0, e1 - cc_ * wc1, e2 - cc_ * wc2
    ENV = A.ENV
    f0, f1, f2, f3 = qdiff(qe[0], qe[1], qe[2], qe[3], ENV[k, E_QREF], ENV[k, E_QREF + 1], ENV[k, E_QREF + 2],
                           ENV[k, E_QREF + 3])
    if C[POINT_KIND] == POINT_NADIR:
        # reference rate (0, -n, 0) in the LVLH frame, seen in the body
        o0, o1, o2 = rotate(f0, f1, f2, f3, 0.0, -C[ORBIT_RATE], 0.0)
    else:
        o0 = 0.0
        o1 = 0.0
        o2 = 0.0
    e0 = 2.0 * kk * f0
    e1 = 2.0 * kk * f1
    e2 = 2.0 * kk * f2
    if law == LAW_WIE:
        e0, e1, e2 = _clip_norm(e0, e1, e2, cc_ * rmax)
    return -e0 - cc_ * (wc0 - o0), -e1 - cc_ * (wc1 - o1), -e2 - cc_ * (wc2 - o2)


@_step
def _control(k, A, rows, jets, mode, qe, wc, sun, mag, unl):
    """Control at the control instant ``k``: wheel motor torques (``TM`` row) and the dipole for
    the mode (open loop, B-dot detumbling, or the attitude law with the gyroscopic term, thruster
    unloading fed forward and magnetic unloading). ``unl`` = (unloading on, count, time).
    Returns the dipole, whether the thrusters fire this period and ``unl``."""
    C = A.C
    nw = int(C[NW])
    nt = int(C[NT])
    mmax = C[MTQ_MAX]
    Xi, _, _, _, TMi, _, _, _ = rows
    TF, TFREE, TS, TR, TY = jets
    nmag, bm0, bm1, bm2, bp0, bp1, bp2, tmag, tprev, newmag = mag
    on, n_unl, t_unl = unl
    m0 = 0.0
    m1 = 0.0
    m2 = 0.0
    tfire = 0
    if int(C[LAW]) == LAW_OPEN:
        for j in range(nw):
            TMi[j] = A.WPAR[j, W_OPEN]
        m0, m1, m2 = _clip_max(C[OL_DIP0], C[OL_DIP0 + 1], C[OL_DIP0 + 2], mmax)
    elif mode == MODE_DETUMBLE:
        for j in range(nw):
            TMi[j] = 0.0
        if nmag >= 2 and newmag == 1 and tmag > tprev:
            inv = C[BDOT_GAIN] / (tmag - tprev)
            m0, m1, m2 = _clip_max(-inv * (bm0 - bp0), -inv * (bm1 - bp1), -inv * (bm2 - bp2), mmax)
    else:
        wc0, wc1, wc2 = wc
        hn0, hn1, hn2 = _wheel_momentum(Xi, A.AXN, nw)
        jw0, jw1, jw2 = _mat3(C, JN0, wc0, wc1, wc2)
        g0 = wc1 * (jw2 + hn2) - wc2 * (jw1 + hn1)
        g1 = wc2 * (jw0 + hn0) - wc0 * (jw2 + hn2)
        g2 = wc0 * (jw1 + hn1) - wc1 * (jw0 + hn0)
        a0, a1, a2 = _law(k, A, mode, qe, wc, sun)
        u0, u1, u2 = _mat3(C, JN0, a0, a1, a2)
        if nt > 0:
            # thruster unloading with hysteresis on |A_nom h| (start above, stop below);
            # the wheels take the thrusters' torque as a feed-forward and hold attitude
            hh = math.sqrt(hn0 * hn0 + hn1 * hn1 + hn2 * hn2)
            if on == 0 and hh > C[UNL_START]:
                on = 1
                n_unl += 1
            elif on == 1 and hh < C[UNL_STOP]:
                on = 0
            if on == 1:
                tp = int(C[H_CTRL]) * C[DT]
                f0, f1, f2 = unload_plan(A.THR, TF, TFREE, TS, TR, TY, nt, C[UNL_TORQUE], C[UNL_EPS], tp,
                                         hn0, hn1, hn2)
                u0 -= f0
                u1 -= f1
                u2 -= f2
                tfire = 1
                t_unl += tp
        allocate(C, Xi, A.PINV, A.NULLP, A.HSTAR, nw, TMi, u0 + g0, u1 + g1, u2 + g2)
        # magnetic unloading, cross-product law m = k (h x B) / |B|^2
        if C[UNLOAD_GAIN] > 0.0 and nmag >= 1:
            bb = bm0 * bm0 + bm1 * bm1 + bm2 * bm2
            if bb > 0.0:
                ku = C[UNLOAD_GAIN] / bb
                m0, m1, m2 = _clip_max(ku * (hn1 * bm2 - hn2 * bm1), ku * (hn2 * bm0 - hn0 * bm2),
                                       ku * (hn0 * bm1 - hn1 * bm0), mmax)
    return (m0, m1, m2), tfire, (on, n_unl, t_unl)


@_step
def _external(i, k, A, q, Ji, has_sine, rods_on, dip):
    """The external torque held over step ``k`` (N m, body): gravity gradient, the sample's
    disturbance (constant and, when ``has_sine``, sinusoidal) and, while the rods are on, the
    dipole's ``m x B``."""
    C = A.C
    P = A.P
    ENV = A.ENV
    q0, q1, q2, q3 = q
    x0, x1, x2 = rotate(q0, q1, q2, q3, ENV[k, E_R], ENV[k, E_R + 1], ENV[k, E_R + 2])
    jx0, jx1, jx2 = _mat3(Ji, 0, x0, x1, x2)
    g = 3.0 * C[N2ORB]
    t0 = g * (x1 * jx2 - x2 * jx1) + P[i, P_D0]
    t1 = g * (x2 * jx0 - x0 * jx2) + P[i, P_D0 + 1]
    t2 = g * (x0 * jx1 - x1 * jx0) + P[i, P_D0 + 2]
    if has_sine:
        ph = C[D_OMEGA] * (k * C[DT])
        t0 += P[i, P_DAMP] * math.sin(ph + P[i, P_DPH])
        t1 += P[i, P_DAMP + 1] * math.sin(ph + P[i, P_DPH + 1])
        t2 += P[i, P_DAMP + 2] * math.sin(ph + P[i, P_DPH + 2])
    if rods_on:
        m0, m1, m2 = dip
        Bb0, Bb1, Bb2 = rotate(q0, q1, q2, q3, ENV[k, E_B], ENV[k, E_B + 1], ENV[k, E_B + 2])
        t0 += m1 * Bb2 - m2 * Bb1
        t1 += m2 * Bb0 - m0 * Bb2
        t2 += m0 * Bb1 - m1 * Bb0
    return t0, t1, t2


@device
def _finish(i, A, Xi, AXi, mt, md, dip_max, unl, jet, thr, nees):
    """Sample ``i``'s metrics ``OUT[i]`` (the ``M_*`` columns) from the accumulators."""
    OUT = A.OUT
    n_steps = int(A.C[N_STEPS])
    nw = int(A.C[NW])
    (n_win, n_pt, sum_e, sum_e2, max_e, sum_k2, last_out, max_rate_win, max_speed, max_hw, max_drift,
     _, _, _, _, sun_err, _, _, _, _, _, _, _) = mt
    mode, _, t_det, t_acq = md
    OUT[i, M_T_DETUMBLED] = t_det
    OUT[i, M_T_ACQUIRED] = t_acq
    OUT[i, M_FINAL_MODE] = mode
    if n_pt > 0:
        OUT[i, M_POINT_MEAN] = sum_e / n_pt
        OUT[i, M_POINT_RMS] = math.sqrt(sum_e2 / n_pt)
        OUT[i, M_POINT_MAX] = max_e
        OUT[i, M_KNOW_RMS] = math.sqrt(sum_k2 / n_pt)
    else:
        OUT[i, M_POINT_MEAN] = math.nan
        OUT[i, M_POINT_RMS] = math.nan
        OUT[i, M_POINT_MAX] = math.nan
        OUT[i, M_KNOW_RMS] = math.nan
    OUT[i, M_POINT_FRAC] = n_pt / n_win if n_win > 0 else 0.0
    if mode != MODE_POINT:
        OUT[i, M_SETTLE] = math.nan
    elif last_out < 0.0:
        OUT[i, M_SETTLE] = 0.0
    elif last_out >= n_steps * A.C[DT]:
        OUT[i, M_SETTLE] = math.nan
    else:
        OUT[i, M_SETTLE] = last_out
    OUT[i, M_FINAL_RATE] = math.sqrt(Xi[4] * Xi[4] + Xi[5] * Xi[5] + Xi[6] * Xi[6])
    OUT[i, M_MAX_RATE_WIN] = max_rate_win
    OUT[i, M_MAX_SPEED] = max_speed
    OUT[i, M_MAX_HW] = max_hw
    hb0, hb1, hb2 = _wheel_momentum(Xi, AXi, nw)
    OUT[i, M_FINAL_HW] = math.sqrt(hb0 * hb0 + hb1 * hb1 + hb2 * hb2)
    OUT[i, M_MAX_DIPOLE] = dip_max
    OUT[i, M_H_DRIFT] = max_drift
    OUT[i, M_SUN_FINAL] = sun_err
    OUT[i, M_PROPELLANT] = jet[6]
    OUT[i, M_IMPULSE] = thr[0]
    OUT[i, M_ON_TIME] = thr[1]
    OUT[i, M_UNLOADS] = unl[1]
    OUT[i, M_UNLOAD_TIME] = unl[2]
    OUT[i, M_NEES] = nees[1] / nees[2] if nees[2] > 0 else math.nan
    OUT[i, M_NEES_N] = nees[2]


@_step
def _knowledge(k, A, rows, kf, q, qe, wm, eg, kst, kc, krec):
    """The attitude knowledge after the step from ``q`` (step ``k``) to the ``X`` row's new
    attitude: with the filter its propagation (a rate-integrating gyro: the step's mean rate
    plus the reading's held error ``eg``); without, the last star-tracker attitude propagated
    with the gyro reading ``wm``, only when the knowledge is read before the next reset."""
    C = A.C
    dt = C[DT]
    Xi, XTi, _, _, _, _, _, _ = rows
    KPi, kq, kb, kwm, _, _, _, _, kwk = kf
    q0, q1, q2, q3 = q
    hst = int(C[H_ST])
    if C[EST_ON] > 0.0:
        # rate-integrating gyro: the step's mean rate (rotation vector of q(t+dt) (x) q(t)^-1
        # over dt: exact for the body's motion) plus the reading's held error, so that the
        # filter's held-rate propagation has no model error when the rate changes in a step
        d0, d1, d2, d3 = qdiff(Xi[0], Xi[1], Xi[2], Xi[3], q0, q1, q2, q3)
        vn = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        f = (2.0 * math.atan2(vn, d3) / vn if vn > 0.0 else 2.0 / d3) / dt
        kwm[0] = f * d0 + eg[0]
        kwm[1] = f * d1 + eg[1]
        kwm[2] = f * d2 + eg[2]
        mekf_propagate(kq, kb, KPi, kwm, dt, C[SIG_V], C[SIG_U], kwk)
        return kq[0], kq[1], kq[2], kq[3]
    rec_on = A.REC.shape[1] > 0
    if hst > 0 and (k + hst - kst >= int(C[K_WIN]) or k + int(C[H_CTRL]) - kc < k + hst - kst
                    or (rec_on and k + int(C[REC_EVERY]) - krec <= k + hst - kst)):
        # propagated only when the knowledge is read before the next star-tracker reset K
        # (step k + hst - kst, which overwrites it without reading it): by the error in the
        # window (K >= k_win: K itself reads it before its reset), the control at a period
        # start before K, or a trace row up to K. A step that skips it is followed only by
        # skipping steps until K (the same K, fewer steps to it), so a propagated value
        # always continues an unbroken chain from the last reset.
        XTi[0], XTi[1], XTi[2], XTi[3] = qe[0], qe[1], qe[2], qe[3]
        compose_rotvec(XTi, wm[0] * dt, wm[1] * dt, wm[2] * dt)
        return XTi[0], XTi[1], XTi[2], XTi[3]
    return qe


def wheel_sample(i, A):
    """Simulate sample ``i`` over the whole grid: at each step the truth metrics and the trace
    row (:func:`_truth`, :func:`_record`), the sensors and the filter's updates (:func:`_gyro`,
    the star tracker, :func:`_vectors`), at control instants the modes (:func:`_modes`) and the
    control (:func:`_control`, :func:`actuate`), the external torque (:func:`_external`), the
    unloading thrusters (:func:`thrust_step`), the RK4 step (:func:`rk4`) and the knowledge's
    propagation (:func:`_knowledge`); :func:`_finish` writes the metrics. ``A``: the kernel's
    arrays (:data:`Arrays`). The scalar state travels as tuples; the sensor epochs, control
    periods and trace rows are step counters (no integer modulo)."""
    C = A.C
    dt = C[DT]
    n_steps = int(C[N_STEPS])
    hc = int(C[H_CTRL])
    hg = int(C[H_GYRO])
    hs = int(C[H_SUN])
    hm = int(C[H_MAG])
    hst = int(C[H_ST])
    nw = int(C[NW])
    nt = int(C[NT])
    on_steps = int(C[MTQ_ON_STEPS])
    rec_every = int(C[REC_EVERY])
    k_win = int(C[K_WIN])
    rec_on = A.REC.shape[1] > 0
    ns = A.P[i, P_NS]
    sig_g = C[SIG_V] * ns / math.sqrt(hg * dt)
    sig_b = C[SIG_U] * ns * math.sqrt(hg * dt)
    filt = C[EST_ON] > 0.0
    rows, jets, kf = _rows(i, A)
    Xi, XTi, KSi, KDi, TMi, Ji, JIi, AXi = rows
    KPi, kq, kb, _, _, _, kqt, kbt, kwk = kf
    s, qe = _init(i, A, rows, kf)
    bias = (A.P[i, P_BIAS], A.P[i, P_BIAS + 1], A.P[i, P_BIAS + 2])
    wm = (Xi[4] + bias[0], Xi[5] + bias[1], Xi[6] + bias[2])
    wc = wm  # the rate the controller uses (bias-corrected with the filter)
    eg = bias  # the gyro reading's error (the filter's held delta-angle error)
    sun = (0, 0.0, 0.0, 1.0)  # valid, unit vector
    mag = (0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0)  # count, reading, previous, times, new
    md = (int(C[MODE0]), 0, math.nan, math.nan)  # mode, dwell, t_detumbled, t_acquired
    dip = (0.0, 0.0, 0.0)
    dip_max = 0.0
    unl = (0, 0, 0.0)  # unloading on, count, time
    tfire = 0  # on-times planned for this control period
    tt = (0.0, 0.0, 0.0)  # thruster torque over the step
    li = (0.0, 0.0, 0.0)  # cumulative thruster angular impulse, ECI
    prop = 0.0
    imp = 0.0
    t_on = 0.0
    nees = (math.nan, 0.0, 0)  # last, sum, count
    mt = (0, 0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, math.nan,
          0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)  # see _truth
    r = 0
    has_sine = A.P[i, P_DAMP] != 0.0 or A.P[i, P_DAMP + 1] != 0.0 or A.P[i, P_DAMP + 2] != 0.0
    band = C[SETTLE_BAND]
    tb = settle_bounds(band)
    krec = 0
    kc = 0
    kg = 0
    kst = 0
    ks = 0
    km = 0
    for k in range(n_steps + 1):
        q = (Xi[0], Xi[1], Xi[2], Xi[3])
        w = (Xi[4], Xi[5], Xi[6])
        rrow = rec_on and krec == 0  # a trace row
        ctrl = kc == 0
        in_win = k >= k_win
        mt, perr, kerr, rate = _truth(k, A, rows, q, w, qe, md[0], rrow, krec == 0 or k == n_steps, ctrl,
                                      in_win, band, tb, mt)
        if rrow:
            _record(i, r, A, rows, w, md[0], perr, kerr, rate, mt, dip, nees[0],
                    (tt[0], tt[1], tt[2], li[0], li[1], li[2], prop))
            r += 1
        if k == n_steps:
            break
        # ---- sensors
        if kg == 0:
            s, wm, eg, bias = _gyro(s, w, sig_g, sig_b, bias)
        if hst > 0 and kst == 0:
            s, z0, z1, z2 = _normal3(s)
            sg = C[SIG_ST] * ns
            XTi[0], XTi[1], XTi[2], XTi[3] = q[0], q[1], q[2], q[3]
            compose_rotvec(XTi, sg * z0, sg * z1, sg * z2)
            qe = (XTi[0], XTi[1], XTi[2], XTi[3])
            if filt:
                mekf_update_quaternion(kq, kb, KPi, XTi[0:4], C[SIG_ST], kwk)
        elif hst == 0 and not filt:
            qe = q
        # the rods were on during the previous step (the sample is taken before this step's command)
        firing = False
        if hm > 0 and km == 0:
            firing = (k > 0 and (kc - 1 if kc > 0 else hc - 1) < on_steps
                      and (dip[0] != 0.0 or dip[1] != 0.0 or dip[2] != 0.0))
        s, sun, mag = _vectors(k, A, kf, q, s, ns, hs > 0 and ks == 0, hm > 0 and km == 0, firing, sun, mag,
                               dip)
        if filt:
            qe = (kq[0], kq[1], kq[2], kq[3])
            wc = (wm[0] - kb[0], wm[1] - kb[1], wm[2] - kb[2])
            if ctrl and in_win:
                for m in range(4):
                    kqt[m] = Xi[m]
                kbt[0], kbt[1], kbt[2] = bias
                nv = mekf_nees(kq, kb, KPi, kqt, kbt, kwk)
                nees = (nv, nees[1] + nv, nees[2] + 1) if nv == nv else (nv, nees[1], nees[2])
        else:
            wc = wm
        # ---- control and modes, every control period
        if ctrl:
            md = _modes(C, md, k * dt, math.sqrt(wc[0] * wc[0] + wc[1] * wc[1] + wc[2] * wc[2]), sun)
            dip, tfire, unl = _control(k, A, rows, jets, md[0], qe, wc, sun, mag, unl)
            s = actuate(C, Xi, AXi, A.WPAR, nw, TMi, s)
            mag = (mag[0], mag[1], mag[2], mag[3], mag[4], mag[5], mag[6], mag[7], mag[8], 0)
            dm = math.sqrt(dip[0] * dip[0] + dip[1] * dip[1] + dip[2] * dip[2])
            if dm > dip_max:
                dip_max = dm
        # ---- external torque held over the step, the unloading thrusters, the plant
        t0, t1, t2 = _external(i, k, A, q, Ji, has_sine, kc < on_steps, dip)
        if tfire == 1:
            tt0, tt1, tt2, di, dp, do = thrust_step(A.THR, jets[0], nt, kc * dt, hc * dt, dt)
            tt = (tt0, tt1, tt2)
            t0 += tt0
            t1 += tt1
            t2 += tt2
            imp += di
            prop += dp
            t_on += do
        elif nt > 0:
            tt = (0.0, 0.0, 0.0)
        rk4(Xi, XTi, KSi, KDi, Ji, JIi, AXi, nw, TMi, A.JW, C[C_VISC], C[C_COUL], t0, t1, t2, dt)
        if tfire == 1:
            # inertial angular impulse of the thrusters, trapezoid over the step's attitudes
            ia0, ia1, ia2 = rotate(-q[0], -q[1], -q[2], q[3], tt[0], tt[1], tt[2])
            ib0, ib1, ib2 = rotate(-Xi[0], -Xi[1], -Xi[2], Xi[3], tt[0], tt[1], tt[2])
            li = (li[0] + 0.5 * dt * (ia0 + ib0), li[1] + 0.5 * dt * (ia1 + ib1), li[2] + 0.5 * dt * (ia2 + ib2))
        qe = _knowledge(k, A, rows, kf, q, qe, wm, eg, kst, kc, krec)
        # ---- step counters
        krec = 0 if krec + 1 == rec_every else krec + 1
        kc = 0 if kc + 1 == hc else kc + 1
        kg = 0 if kg + 1 == hg else kg + 1
        kst = 0 if kst + 1 == hst else kst + 1
        ks = 0 if ks + 1 == hs else ks + 1
        km = 0 if km + 1 == hm else km + 1
    _finish(i, A, Xi, AXi, mt, md, dip_max, unl, (tt[0], tt[1], tt[2], li[0], li[1], li[2], prop), (imp, t_on), nees)


# ----------------------------------------------------------------- the kernel's arrays
class Dims(NamedTuple):
    """The sizes that the kernel's array shapes depend on (one kernel call)."""

    n: int  # samples
    nw: int  # wheels
    nt: int  # unloading thrusters (0: none)
    n_rec: int  # trace rows (0 when not recording)
    filt: bool  # the attitude filter is on


def n_channels(d: Dims) -> int:
    """Trace channels: the fixed ones, wheel speeds and momenta, the unloading thrusters' and
    the filter's NEES when present."""
    return N_REC_FIXED + 2 * d.nw + (N_REC_THR if d.nt else 0) + (1 if d.filt else 0)


#: Every array the kernel takes, in argument order: the one declaration from which the argument
#: tuple (:data:`Arrays`), the allocations of :mod:`adcskit.simulation.wheels`, the CUDA
#: signature (:func:`_cuda_signature`) and the GPU driver's transfers are made
#: (:class:`adcskit.simulation._kernels.Arg`). Adding a scratch array is one line here.
ARGS = (
    Arg("P", "f8", 2, "in", True),  # per-sample parameters (P_* columns)
    Arg("AX", "f8", 3, "in", True),  # dispersed wheel axes (n, 3, nw)
    Arg("C", "f8", 1, "in", False),  # shared coefficients (the constants above)
    Arg("ENV", "f8", 2, "in", False),  # per-step environment (E_* columns)
    Arg("AXN", "f8", 2, "in", False),  # nominal wheel axes (3, nw)
    Arg("PINV", "f8", 2, "in", False),  # wheel allocation (nw, 3)
    Arg("NULLP", "f8", 2, "in", False),  # null-motion projector (nw, nw)
    Arg("HSTAR", "f8", 1, "in", False),  # null-motion target momenta
    Arg("WPAR", "f8", 2, "in", False),  # per-wheel parameters (W_* columns)
    Arg("JW", "f8", 1, "in", False),  # wheel axial inertias
    Arg("SEEDS", "u8", 1, "in", True),  # SplitMix64 seed per sample
    Arg("X", "f8", 2, "scratch", True, lambda d: (d.n, 7 + d.nw), "zeros"),  # q, omega, h
    Arg("XT", "f8", 2, "scratch", True, lambda d: (d.n, 7 + d.nw), "zeros"),  # RK4 stage state
    Arg("KS", "f8", 2, "scratch", True, lambda d: (d.n, 7 + d.nw), "zeros"),  # RK4 stage sum
    Arg("KD", "f8", 2, "scratch", True, lambda d: (d.n, 7 + d.nw), "zeros"),  # RK4 derivative
    Arg("TM", "f8", 2, "scratch", True, lambda d: (d.n, tm_len(d.nw, d.nt)), "zeros"),  # motors, jets
    Arg("OUT", "f8", 2, "out", True, lambda d: (d.n, N_METRICS)),  # metrics (M_* columns)
    Arg("REC", "f8", 3, "out", True, lambda d: (d.n, d.n_rec, n_channels(d)), "nan"),  # traces
    Arg("THR", "f8", 2, "in", False),  # unloading thrusters (T_* rows, nt)
    Arg("KP", "f8", 3, "scratch", True, lambda d: (d.n, 6, 6) if d.filt else (d.n, 0, 0), "zeros"),
    Arg("KW", "f8", 2, "scratch", True, lambda d: (d.n, N_KW if d.filt else 0), "zeros"),  # KW_*
)

#: The kernel's argument tuple: one field per :data:`ARGS` entry (``A.P``, ``A.C``...).
Arrays = namedtuple("Arrays", [a.name for a in ARGS])


def allocate_arrays(inputs: dict[str, np.ndarray], d: Dims) -> Arrays:
    """The kernel's argument tuple: the ``"in"`` arrays from ``inputs`` (by name), the others
    allocated for ``d`` as :data:`ARGS` declares."""
    return Arrays(*(inputs[a.name] if a.role == "in" else a.allocate(d) for a in ARGS))


#: The per-sample function, one source for the CPU and the CUDA driver. ``error_model="numpy"``:
#: no zero-divisor test and exception branch at each division (as the thruster kernel); the loop
#: never divides by zero (inertias > 0, normalised vectors, guarded quotients), so the numbers are
#: the same, and a zero divisor would give inf / NaN instead of a ZeroDivisionError.
#: The CUDA compilation's step functions: the plain sources (``_control`` calling ``_law``'s).
_DEVICE_STEPS = {name: device(globals()[name].py_func)
                 for name in ("_rows", "_init", "_truth", "_gyro", "_vectors", "_modes", "_external", "_knowledge")}
_DEVICE_STEPS["_control"] = device(rebound(_control.py_func, {"_law": device(_law.py_func)}))
SAMPLE = PerSample(wheel_sample, inline="never", error_model="numpy", nrt=False, device_names=_DEVICE_STEPS)
wheel_sample_jit = SAMPLE.cpu


@njit(cache=True, nogil=True)
def run_block(lo, hi, A):
    """CPU block driver: samples ``lo`` to ``hi - 1`` of the arrays ``A``, each through
    :func:`wheel_sample` (serial, GIL released: :func:`run_wheels` runs blocks on threads)."""
    for i in range(lo, hi):
        wheel_sample_jit(i, A)


def run_wheels(A, n_threads=0):
    """CPU driver: blocks of the samples of ``A`` (:data:`Arrays`) on ``n_threads`` threads (0:
    numba's thread count), each block one call of the compiled, GIL-free :func:`run_block`.

    A thread pool over a serial compiled driver instead of a ``numba.prange`` driver: the same
    parallelism and numbers (samples are independent), but the parallel (parfor) driver cost
    about 15 s of extra compilation on a cold cache, the serial one about 1 s. Without unloading
    thrusters ``THR`` has no column and ``C[NT]`` is 0; without the filter ``KP`` and ``KW``
    have no columns and ``C[EST_ON]`` is 0.
    """
    import numba

    n = A.P.shape[0]
    nt = int(n_threads) if n_threads > 0 else numba.get_num_threads()
    nt = max(1, min(nt, n))
    if nt == 1:
        run_block(0, n, A)
        return
    from concurrent.futures import ThreadPoolExecutor

    edges = np.linspace(0, n, min(n, 4 * nt) + 1).astype(np.int64)  # 4 blocks per thread: balance
    with ThreadPoolExecutor(max_workers=nt) as pool:
        futures = [pool.submit(run_block, int(lo), int(hi), A) for lo, hi in zip(edges[:-1], edges[1:]) if hi > lo]
        for f in futures:
            f.result()


# --- CUDA driver -----------------------------------------------------------------------------
# One thread per sample. The scratch rows (X, XT, KS, KD: 7 + n_w floats; TM: n_w) stay what
# the CPU driver passes: per-sample rows of global device arrays, not ``cuda.local.array``.
# Why: the per-sample function indexes ``X[i]``..., so rows of (n, 7 + n_w) arrays need no
# change to its source, the lengths are runtime values (n_w: no kernel per wheel count), and the
# rows are small (4 x 11 + 4 floats for four wheels) and read/written by their own thread only,
# so they live in L1/L2 like local memory would. The per-sample function compiles to PTX for
# sm_90 unchanged (tests/test_cuda_ptx.py).
THREADS_PER_BLOCK = 128
CUDA_CHUNK = 1 << 18  # samples per device round trip (scratch + params: ~0.3 KB per sample)

cuda = None  # numba.cuda, bound on first GPU use (a module global: see adcskit._targets)


def _make_cuda_kernel():
    global cuda
    cuda = import_cuda()
    sample = SAMPLE.cuda()

    @cuda.jit
    def kernel(A):
        i = cuda.grid(1)
        if i < A.P.shape[0]:
            sample(i, A)

    return kernel


CUDA_KERNELS = LazyKernels(_make_cuda_kernel)


def _cuda_signature():
    """numba argument types of the CUDA kernel: one :data:`Arrays` of C-contiguous arrays."""
    from numba import types as t

    dtypes = {"f8": t.float64, "u8": t.uint64}
    return (t.NamedTuple(tuple(t.Array(dtypes[a.dtype], a.ndim, "C") for a in ARGS), Arrays),)


def run_wheels_cuda(A, chunk=None):
    """GPU driver: the same per-sample function as :func:`run_wheels`, one CUDA thread per sample.

    ``A`` as for :func:`run_wheels` (host arrays; ``OUT`` and, when its second axis is non-zero,
    ``REC`` are filled in place). Samples go to the device in chunks of ``chunk`` rows (default
    :data:`CUDA_CHUNK`, read at call time); the arrays without a row per sample (``C``, ``ENV``,
    the allocation matrices, the thruster table) are copied once.
    """
    if chunk is None:
        chunk = CUDA_CHUNK
    kernel = CUDA_KERNELS.get()  # binds the module global ``cuda``
    record = A.REC.shape[1] > 0
    launch_chunked(kernel, A._asdict(), Arrays._fields, n=A.P.shape[0], chunk=chunk, threads=THREADS_PER_BLOCK,
                   shared={a.name for a in ARGS if not a.rows},
                   outputs=("OUT", "REC") if record else ("OUT",), pack=Arrays)
