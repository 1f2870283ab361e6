"""Private batch kernel of the closed-loop simulator: samples in parallel lanes.

The per-sample step is written as plain functions (docs/architecture.md, "Kernels and targets"; :mod:`adcskit._targets`):
scalars, ``math`` functions and indexing of arrays passed in; no allocation, no NumPy calls,
no Python objects inside :func:`sample_loop` and its helpers. :func:`sample_loop` is declared
as a :class:`adcskit._targets.PerSample` (``SAMPLE``), the GPU driver's per-sample function.
The CPU driver :func:`run_parallel` (``prange`` over blocks of :data:`LANES` samples) runs
:func:`block_loop`: the same step functions for each sample of a block in turn, then the
block's RK4 steps in one loop that LLVM vectorises across the lanes; bit for bit what
:func:`sample_loop` computes for each sample (tests/simulation/test_lanes.py; why two loops:
docs/decisions/kernel-step-functions.md). The helpers are
``register_jitable`` / :func:`adcskit._targets.device` functions, the quaternion ones and the
S4 actuator model (Schmitt trigger, delay, thruster lags) shared with the MEKF and the on-off
kernel (:mod:`adcskit.attitude._device`, :mod:`adcskit.control._actuator`). The kernel's
arrays (inputs, per-sample scratch, outputs) are declared once, in :data:`ARGS`; they travel
as one named tuple (:data:`Arrays`) that :mod:`adcskit.simulation.core` allocates from it.
The GPU driver :func:`run_cuda` runs the same source, one CUDA thread per sample: its
compilation binds the names that the CPU build resolves to CPU-only dispatchers (the MEKF
steps, the gyro model, the rotation-vector update) to device compilations of the same
sources (``PerSample(device_names=...)``), and the Wahba / min-max solvers, numba kernels
with NumPy linear algebra (``eigh``, ``svd``) that the device compiler cannot take, to
stand-ins that are never reached: :func:`adcskit.simulation.simulate` refuses those
estimators with ``backend="cuda"`` (:data:`CUDA_EST_MODES`).

Randomness is a counter-free per-sample stream (SplitMix64, Steele, Lea & Flood 2014) seeded
with one 64-bit integer per sample: a sample's noise depends only on its seed, never on the
thread, chunk or executor that runs it, so results are bit-identical however a campaign is
split. Normals by Box-Muller.

Conventions: quaternion scalar last, ``A(q)`` maps reference (ECI) to body; kinematics
``q' = 1/2 [omega; 0] (x) q`` with Markley's product (``A(p (x) q) = A(p) A(q)``); body
rates in rad/s; SI units.

Layout of the shared coefficient vector ``C`` and of the per-sample parameter matrix ``P``
is given by the index constants below; :mod:`adcskit.simulation.core` fills both.

References
----------
Markley F. L., Crassidis J. L., *Fundamentals of Spacecraft Attitude Determination and
Control*, Springer 2014: eq. 3.81 (Euler), 3.20 (kinematics), 3.155 (gravity gradient).
S3 eq. 5-7 (torque matrix, pulse width, fuel); S4 Fig. 1 (PID + Schmitt loop, thruster lag
and delay).
"""

from __future__ import annotations

import math
from collections import namedtuple
from collections.abc import Callable
from typing import NamedTuple

import numba
import numpy as np
from numba import int64, njit, prange
from numba.extending import register_jitable

from adcskit._stack import stack_f64
from adcskit._targets import (
    LazyKernels,
    PerSample,
    import_cuda,
    lane_block_size,
    lane_slots,
    launch_chunked,
    rebound,
)
from adcskit.attitude._device import compose_rotvec, qdiff, qdot, qerr, rotate, unit_q4_pos
from adcskit.control._actuator import delay_mix, lag_step, schmitt
from adcskit.determination._box import minmax_one
from adcskit.determination._kernels import solve_one
from adcskit.estimation import _mekf_kernels as _mk
from adcskit.simulation._random import normal as _normal
from adcskit.simulation._random import uniform as _uniform

# The heavy per-sample pieces of other packages are called through their own compiled
# (and disk-cached) numba dispatchers rather than inlined into this kernel, so numba compiles
# each of them once. The CUDA build of the loop binds these names to device compilations of
# the same sources (the MEKF kernels are plain ``register_jitable`` functions): see SAMPLE.
mekf_propagate = _mk.mekf_propagate_jit
mekf_update_vector = _mk.mekf_update_vector_jit
mekf_update_quaternion = _mk.mekf_update_quaternion_jit
mekf_nees = _mk.mekf_nees_jit
gyro_step = _mk.gyro_step_jit
_compose_rotvec = njit(cache=True, nogil=True)(compose_rotvec)


@njit(cache=True, nogil=True, error_model="numpy", _nrt=True)
def wahba_one(VB, VR, WW, i, method, WQ, WO, WC, b, r, q, B, F, K, A, Bk, qp):
    """Wahba solve of sample ``i``'s two observations (a non-inlined wrapper of the
    determination kernel's per-problem solver, itself compiled once); returns its status
    code. Compiled with numba's reference counting (``_nrt=True``, which the solvers'
    allocations need) although the loop that calls it is compiled without (``SAMPLE``)."""
    return solve_one(VB, VR, WW, i, i, method, WQ, WO, WC, b, r, q, B, F, K, A, Bk, qp)

# ----------------------------------------------------------------- shared coefficients C
(
    DT, N_STEPS, H_CTRL, H_GYRO, H_SUN, H_MAG, H_ST,
    A11, B1, A21, A22, B2, V1, V2, VU,
    N2ORB, D_OMEGA,
    SIG_SUN, SIG_MAG, SIG_ST, NOISE_UNIFORM,
    SIG_V, SIG_U,
    EST_MODE, WAHBA_METHOD, CTRL_MODE,
    U_ON, U_OFF, T_S, T_MIN, PULSE_ROUND,
    KP0, KP1, KP2, KI0, KI1, KI2, KD0, KD1, KD2, TL0, TL1, TL2,
    K_WIN, SETTLE_BAND, REC_EVERY, K_NEES, BUF_MASK, W_SUN, W_MAG, RPI_EPS,
    ALLOC_MODE, SEARCH_RANGE, UNDERWEIGHT,
) = range(54)
N_COEFS = 54

EST_TRUTH, EST_WAHBA, EST_MEKF, EST_MINMAX = 0, 1, 2, 3
CTRL_SCHMITT, CTRL_PWM, CTRL_OPEN = 0, 1, 2
ALLOC_RPI, ALLOC_BVLS = 0, 1

# ----------------------------------------------------------------- per-sample parameters P
# J (9, row-major), Jinv (9), q0 (4), w0 (3), delay, d0 (3), damp (3), dphase (3),
# gyro bias (3), q_est0 (4), sig_att0, sig_b0
(P_J, P_JI, P_Q0, P_W0, P_DELAY, P_D0, P_DAMP, P_DPH, P_BIAS, P_QE0, P_SIGA0, P_SIGB0) = (
    0, 9, 18, 22, 25, 26, 29, 32, 35, 38, 42, 43)
N_PARAMS = 44

# ----------------------------------------------------------------- metrics
(M_MEAN_ERR, M_RMS_ERR, M_MAX_ERR, M_RMS_X, M_RMS_Y, M_RMS_Z, M_SETTLE, M_FINAL_ERR, M_PROP,
 M_FIRINGS, M_ONTIME, M_KNOW_RMS, M_NEES, M_NEES_N, M_MAX_RATE, M_BOX_ACTIVE) = range(16)
N_METRICS = 16
METRIC_NAMES = (
    "mean_error", "rms_error", "max_error", "rms_error_x", "rms_error_y", "rms_error_z",
    "settling_time", "final_error", "propellant", "firings", "on_time", "knowledge_rms",
    "nees_mean", "nees_count", "max_rate", "box_active_fraction",
)

# ----------------------------------------------------------------- trace channels
(R_EX, R_EY, R_EZ, R_ERR, R_KNOW, R_WX, R_WY, R_WZ, R_NEES, R_PROP) = range(10)
N_REC_FIXED = 10  # + one channel per thruster (delivered thrust fraction)

# ----------------------------------------------------------------- per-sample scratch TS
# x1 (n), x2 (n), tp/dt (n), tp_prev (n), F (n), free (n), torque arms r x d (3n, per
# thruster a0, a1, a2), then S (9), r (3), y (3), idx (3)
N_TS_PER_THR = 9
N_TS_EXTRA = 18


# ----------------------------------------------------------------- the kernel's arrays
class Dims(NamedTuple):
    """The sizes that the kernel's array shapes depend on (one kernel call)."""

    n: int  # samples
    nt: int  # thrusters
    buf_len: int  # delay-line length (a power of two)
    n_rec: int  # trace rows (0 when not recording)


class Arg(NamedTuple):
    """One array of the kernel's argument tuple (:data:`ARGS`).

    ``role``: ``"in"`` (filled by :mod:`adcskit.simulation.core`), ``"scratch"`` (allocated
    per call, not read back) or ``"out"`` (allocated per call, read back). ``rows``: one row
    per sample (a GPU chunk gets its rows; otherwise the array goes to the device once).
    ``shape`` (scratch and outputs): the shape for :class:`Dims`; ``fill``: ``"empty"``,
    ``"zeros"``, ``"ones"`` or ``"nan"``."""

    name: str
    dtype: str
    ndim: int
    role: str
    rows: bool
    shape: Callable[[Dims], tuple[int, ...]] | None = None
    fill: str = "empty"

    def allocate(self, d: Dims) -> np.ndarray:
        """A new array of this argument's shape for ``d``, filled as declared."""
        shape = self.shape(d)
        if self.fill == "nan":
            return np.full(shape, np.nan)
        return {"empty": np.empty, "zeros": np.zeros, "ones": np.ones}[self.fill](shape, self.dtype)


def _rec_shape(d: Dims) -> tuple[int, ...]:
    return (d.n if d.n_rec else 0, d.n_rec, N_REC_FIXED + d.nt)


#: Every array the kernel takes, in argument order: the one declaration from which the argument
#: tuple (:data:`Arrays`), the allocations of :mod:`adcskit.simulation.core`, the CUDA
#: signature (:func:`_cuda_signature`) and the GPU driver's transfers (:func:`run_cuda`) are
#: made. Adding a scratch array is one line here (and its use in the step functions).
ARGS = (
    Arg("P", "f8", 2, "in", True),  # per-sample parameters (P_* columns)
    Arg("C", "f8", 1, "in", False),  # shared coefficients (the constants above)
    Arg("SEEDS", "u8", 1, "in", True),  # SplitMix64 seed per sample
    Arg("DIRS", "f8", 3, "in", True),  # dispersed thrust directions (n, nt, 3)
    Arg("FLEV", "f8", 2, "in", True),  # dispersed thrust levels, N
    Arg("POS", "f8", 2, "in", False),  # thruster positions about the centre of mass (nt, 3)
    Arg("MDOT", "f8", 2, "in", True),  # mass flow per thruster, kg/s
    Arg("FAILED", "f8", 1, "in", False),  # 1: the thruster never fires
    Arg("ENV", "f8", 2, "in", False),  # per-step environment (orbit frame, sun, field, lit)
    Arg("QREF", "f8", 2, "in", False),  # reference attitude per step
    Arg("WREF", "f8", 2, "in", False),  # reference rate per step
    Arg("ATAB", "f8", 2, "in", False),  # Schmitt table / open-loop on-times
    Arg("ANOM", "f8", 2, "in", False),  # nominal torque matrix (3, nt)
    Arg("FNOM", "f8", 1, "in", False),  # nominal thrust, N
    Arg("AMASK", "f8", 1, "in", False),  # 1: the allocator may use the thruster
    Arg("BUF", "f8", 3, "scratch", True, lambda d: (d.n, d.buf_len, d.nt), "zeros"),  # delay line
    Arg("TS", "f8", 2, "scratch", True, lambda d: (d.n, N_TS_PER_THR * d.nt + N_TS_EXTRA), "zeros"),
    Arg("QE", "f8", 2, "scratch", True, lambda d: (d.n, 4)),  # attitude estimate
    Arg("BE", "f8", 2, "scratch", True, lambda d: (d.n, 3)),  # gyro-bias estimate
    Arg("PE", "f8", 3, "scratch", True, lambda d: (d.n, 6, 6)),  # MEKF covariance
    Arg("WK", "f8", 2, "scratch", True, lambda d: (d.n, _mk.WORK_SIZE)),  # MEKF work
    Arg("GY", "f8", 2, "scratch", True, lambda d: (d.n, 12)),  # gyro reading, rate, noise draws
    Arg("BIAS", "f8", 2, "scratch", True, lambda d: (d.n, 3)),  # true gyro bias
    Arg("VB", "f8", 3, "scratch", True, lambda d: (d.n, 2, 3), "zeros"),  # body vectors
    Arg("VR", "f8", 3, "scratch", True, lambda d: (d.n, 2, 3), "zeros"),  # reference vectors
    Arg("WW", "f8", 2, "scratch", True, lambda d: (d.n, 2), "ones"),  # their weights
    Arg("WQ", "f8", 2, "scratch", True, lambda d: (d.n, 4)),  # Wahba / min-max quaternion
    Arg("WO", "f8", 2, "scratch", True, lambda d: (d.n, 3)),  # their status outputs
    Arg("WC", "f8", 3, "scratch", False, lambda d: (1, 0, 0)),  # (unused covariance output)
    Arg("SB", "f8", 3, "scratch", True, lambda d: (d.n, 2, 3)),  # determination solver scratch
    Arg("SR", "f8", 3, "scratch", True, lambda d: (d.n, 2, 3)),
    Arg("SQ", "f8", 2, "scratch", True, lambda d: (d.n, 4)),  # star-tracker quaternion
    Arg("SBB", "f8", 3, "scratch", True, lambda d: (d.n, 3, 3)),
    Arg("SFF", "f8", 3, "scratch", True, lambda d: (d.n, 3, 3)),
    Arg("SKK", "f8", 3, "scratch", True, lambda d: (d.n, 4, 4)),
    Arg("SAA", "f8", 3, "scratch", True, lambda d: (d.n, 3, 3)),
    Arg("SBK", "f8", 3, "scratch", True, lambda d: (d.n, 3, 3)),
    Arg("SQP", "f8", 2, "scratch", True, lambda d: (d.n, 8)),
    Arg("RS", "f8", 2, "scratch", True, lambda d: (d.n, 16)),  # min-max box search
    Arg("OUT", "f8", 2, "out", True, lambda d: (d.n, N_METRICS)),  # metrics (M_* columns)
    Arg("REC", "f8", 3, "out", True, _rec_shape, "nan"),  # traces (R_* channels), or empty
    Arg("TOT", "f8", 2, "out", True, lambda d: (d.n, d.nt)),  # on-time per thruster, s
)

#: The kernel's argument tuple: one field per :data:`ARGS` entry (numba passes it as one
#: argument; ``A.P``, ``A.C``... inside the kernel).
Arrays = namedtuple("Arrays", [a.name for a in ARGS])


def allocate_arrays(inputs: dict[str, np.ndarray], d: Dims) -> Arrays:
    """The kernel's argument tuple: the ``"in"`` arrays from ``inputs`` (by name), the others
    allocated for ``d`` as :data:`ARGS` declares."""
    return Arrays(*(inputs[a.name] if a.role == "in" else a.allocate(d) for a in ARGS))

@register_jitable
def _noise(s, uniform):
    """(new state, one noise draw): standard normal, or uniform in [-1, 1] (bounded errors)."""
    if uniform:
        s, u = _uniform(s)
        return s, 2.0 * u - 1.0
    return _normal(s)


@register_jitable
def _rhs(q0, q1, q2, q3, w0, w1, w2, J, Ji, t0, t1, t2):
    """Time derivative of (q, omega): q' = 1/2 [w; 0] (x) q ; J w' = tau - w x J w."""
    dq0, dq1, dq2, dq3 = qdot(q0, q1, q2, q3, w0, w1, w2)
    h0 = J[0] * w0 + J[1] * w1 + J[2] * w2
    h1 = J[3] * w0 + J[4] * w1 + J[5] * w2
    h2 = J[6] * w0 + J[7] * w1 + J[8] * w2
    m0 = t0 - (w1 * h2 - w2 * h1)
    m1 = t1 - (w2 * h0 - w0 * h2)
    m2 = t2 - (w0 * h1 - w1 * h0)
    dw0 = Ji[0] * m0 + Ji[1] * m1 + Ji[2] * m2
    dw1 = Ji[3] * m0 + Ji[4] * m1 + Ji[5] * m2
    dw2 = Ji[6] * m0 + Ji[7] * m1 + Ji[8] * m2
    return dq0, dq1, dq2, dq3, dw0, dw1, dw2


@register_jitable
def _rk4_combine(x, a, b, c, d, dt):
    """RK4's last step from the state ``x`` and the stage derivatives ``a, b, c, d`` (7-tuples:
    q, omega): ``x + dt/6 (a + 2b + 2c + d)``, the quaternion renormalised (q4 >= 0)."""
    s = dt / 6.0
    u0, u1, u2, u3 = unit_q4_pos(x[0] + s * (a[0] + 2.0 * b[0] + 2.0 * c[0] + d[0]),
                                 x[1] + s * (a[1] + 2.0 * b[1] + 2.0 * c[1] + d[1]),
                                 x[2] + s * (a[2] + 2.0 * b[2] + 2.0 * c[2] + d[2]),
                                 x[3] + s * (a[3] + 2.0 * b[3] + 2.0 * c[3] + d[3]))
    return (u0, u1, u2, u3,
            x[4] + s * (a[4] + 2.0 * b[4] + 2.0 * c[4] + d[4]),
            x[5] + s * (a[5] + 2.0 * b[5] + 2.0 * c[5] + d[5]),
            x[6] + s * (a[6] + 2.0 * b[6] + 2.0 * c[6] + d[6]))


@register_jitable
def rk4_step(q0, q1, q2, q3, w0, w1, w2, J, Ji, t0, t1, t2, dt):
    """One classical Runge-Kutta step of the rigid body with the torque held over the step;
    the quaternion is renormalised (q4 >= 0). Returns the new (q, omega) as 7 scalars."""
    a0, a1, a2, a3, a4, a5, a6 = _rhs(q0, q1, q2, q3, w0, w1, w2, J, Ji, t0, t1, t2)
    h = 0.5 * dt
    b0, b1, b2, b3, b4, b5, b6 = _rhs(q0 + h * a0, q1 + h * a1, q2 + h * a2, q3 + h * a3,
                                      w0 + h * a4, w1 + h * a5, w2 + h * a6, J, Ji, t0, t1, t2)
    c0, c1, c2, c3, c4, c5, c6 = _rhs(q0 + h * b0, q1 + h * b1, q2 + h * b2, q3 + h * b3,
                                      w0 + h * b4, w1 + h * b5, w2 + h * b6, J, Ji, t0, t1, t2)
    d0, d1, d2, d3, d4, d5, d6 = _rhs(q0 + dt * c0, q1 + dt * c1, q2 + dt * c2, q3 + dt * c3,
                                      w0 + dt * c4, w1 + dt * c5, w2 + dt * c6, J, Ji, t0, t1, t2)
    return _rk4_combine((q0, q1, q2, q3, w0, w1, w2), (a0, a1, a2, a3, a4, a5, a6),
                        (b0, b1, b2, b3, b4, b5, b6), (c0, c1, c2, c3, c4, c5, c6),
                        (d0, d1, d2, d3, d4, d5, d6), dt)


@register_jitable
def _rhs_principal(q0, q1, q2, q3, w0, w1, w2, j0, j1, j2, i0, i1, i2, t0, t1, t2):
    """:func:`_rhs` for a diagonal inertia ``diag(j0, j1, j2)`` (inverse ``diag(i0, i1, i2)``):
    the same operations less the products with the zero entries."""
    dq0, dq1, dq2, dq3 = qdot(q0, q1, q2, q3, w0, w1, w2)
    h0 = j0 * w0
    h1 = j1 * w1
    h2 = j2 * w2
    m0 = t0 - (w1 * h2 - w2 * h1)
    m1 = t1 - (w2 * h0 - w0 * h2)
    m2 = t2 - (w0 * h1 - w1 * h0)
    return dq0, dq1, dq2, dq3, i0 * m0, i1 * m1, i2 * m2


@register_jitable(inline="always")
def rk4_step_principal(q0, q1, q2, q3, w0, w1, w2, j0, j1, j2, i0, i1, i2, t0, t1, t2, dt):
    """:func:`rk4_step` for a diagonal inertia (body axes = principal axes): ``j0, j1, j2`` and
    ``i0, i1, i2`` the diagonals of J and J^-1. For finite rates it returns what :func:`rk4_step`
    returns with J's zero off-diagonal entries: each skipped term is a signed zero, and adding
    one leaves a sum unchanged unless the sum is itself zero (then at most its sign differs).
    About a quarter fewer operations (≈ 370 → 260 per step; docs/benchmarks.md)."""
    a0, a1, a2, a3, a4, a5, a6 = _rhs_principal(q0, q1, q2, q3, w0, w1, w2, j0, j1, j2, i0, i1, i2,
                                                t0, t1, t2)
    h = 0.5 * dt
    b0, b1, b2, b3, b4, b5, b6 = _rhs_principal(q0 + h * a0, q1 + h * a1, q2 + h * a2, q3 + h * a3,
                                                w0 + h * a4, w1 + h * a5, w2 + h * a6,
                                                j0, j1, j2, i0, i1, i2, t0, t1, t2)
    c0, c1, c2, c3, c4, c5, c6 = _rhs_principal(q0 + h * b0, q1 + h * b1, q2 + h * b2, q3 + h * b3,
                                                w0 + h * b4, w1 + h * b5, w2 + h * b6,
                                                j0, j1, j2, i0, i1, i2, t0, t1, t2)
    d0, d1, d2, d3, d4, d5, d6 = _rhs_principal(q0 + dt * c0, q1 + dt * c1, q2 + dt * c2,
                                                q3 + dt * c3, w0 + dt * c4, w1 + dt * c5,
                                                w2 + dt * c6, j0, j1, j2, i0, i1, i2, t0, t1, t2)
    return _rk4_combine((q0, q1, q2, q3, w0, w1, w2), (a0, a1, a2, a3, a4, a5, a6),
                        (b0, b1, b2, b3, b4, b5, b6), (c0, c1, c2, c3, c4, c5, c6),
                        (d0, d1, d2, d3, d4, d5, d6), dt)


@register_jitable
def _inertia_times(J, diag, c0, c1, c2):
    """``J c`` (``J`` row-major, 9 entries); from the diagonal alone when ``diag`` (the same
    doubles for finite ``c``: see :func:`rk4_step_principal`)."""
    if diag:
        return J[0] * c0, J[4] * c1, J[8] * c2
    return (J[0] * c0 + J[1] * c1 + J[2] * c2,
            J[3] * c0 + J[4] * c1 + J[5] * c2,
            J[6] * c0 + J[7] * c1 + J[8] * c2)


@register_jitable
def principal(J, Ji):
    """True when the 3x3 inertia ``J`` (row-major, 9 entries) and its inverse are diagonal."""
    for a in (1, 2, 3, 5, 6, 7):
        if J[a] != 0.0 or Ji[a] != 0.0:
            return False
    return True


@register_jitable
def rpi_allocate(A, m0, m1, m2, fmax, mask, F, free, S, r, y, eps):
    """Redistributed pseudo-inverse (S3 eq. 12 with Jin 2005's redistribution), no allocation.

    ``F`` (n,) receives forces in ``[0, fmax]``; thrusters with ``mask == 0`` (failed, known
    to the allocator) stay at 0. Each pass solves ``F_free = A_free^T (A_free A_free^T)^-1 r``
    for the torque ``r`` left by the fixed thrusters, fixes every free thruster that violates a
    bound at that bound, and stops when none does. The 3x3 solve is a Cholesky factorisation of
    ``S + eps tr(S) I`` (``eps`` ~1e-12: the pseudo-inverse's minimum-norm solution when the
    free columns lose rank). ``S``: (9,), ``r``, ``y``: (3,), ``free``: (n,) scratch.
    """
    n = F.shape[0]
    for j in range(n):
        F[j] = 0.0
        free[j] = 1.0 if mask[j] > 0.0 else 0.0
    for _ in range(n + 1):
        for a in range(9):
            S[a] = 0.0
        r[0] = m0
        r[1] = m1
        r[2] = m2
        nfree = 0
        for j in range(n):
            a0 = A[0, j]
            a1 = A[1, j]
            a2 = A[2, j]
            if free[j] > 0.0:
                nfree += 1
                S[0] += a0 * a0
                S[1] += a0 * a1
                S[2] += a0 * a2
                S[4] += a1 * a1
                S[5] += a1 * a2
                S[8] += a2 * a2
            else:
                f = F[j]
                r[0] -= a0 * f
                r[1] -= a1 * f
                r[2] -= a2 * f
        if nfree == 0:
            break
        tr = S[0] + S[4] + S[8]
        reg = eps * tr + 1e-300
        l00 = math.sqrt(S[0] + reg)
        l10 = S[1] / l00
        l20 = S[2] / l00
        l11 = math.sqrt(max(S[4] + reg - l10 * l10, reg))
        l21 = (S[5] - l20 * l10) / l11
        l22 = math.sqrt(max(S[8] + reg - l20 * l20 - l21 * l21, reg))
        z0 = r[0] / l00
        z1 = (r[1] - l10 * z0) / l11
        z2 = (r[2] - l20 * z0 - l21 * z1) / l22
        y[2] = z2 / l22
        y[1] = (z1 - l21 * y[2]) / l11
        y[0] = (z0 - l10 * y[1] - l20 * y[2]) / l00
        viol = False
        for j in range(n):
            if free[j] > 0.0:
                f = A[0, j] * y[0] + A[1, j] * y[1] + A[2, j] * y[2]
                if f < 0.0:
                    F[j] = 0.0
                    free[j] = 0.0
                    viol = True
                elif f > fmax[j]:
                    F[j] = fmax[j]
                    free[j] = 0.0
                    viol = True
                else:
                    F[j] = f
        if not viol:
            break


@register_jitable
def _free_lsq(A, F, state, fmax, m0, m1, m2, idx, nfree, G, rhs, y, eps):
    """Least-squares values ``y[:nfree]`` of the free thrusters ``idx[:nfree]`` (<= 3) for the
    torque left by the bound ones: ``min |A_F y - (m - A_B F_B)|`` through the normal
    equations ``(A_Fᵀ A_F + eps tr I) y = A_Fᵀ r`` (Cholesky, at most 3x3)."""
    n = F.shape[0]
    r0 = m0
    r1 = m1
    r2 = m2
    for j in range(n):
        if state[j] != 2.0:
            f = F[j]
            r0 -= A[0, j] * f
            r1 -= A[1, j] * f
            r2 -= A[2, j] * f
    tr = 0.0
    for a in range(nfree):
        ja = int(idx[a])
        rhs[a] = A[0, ja] * r0 + A[1, ja] * r1 + A[2, ja] * r2
        for c in range(nfree):
            jc = int(idx[c])
            G[3 * a + c] = A[0, ja] * A[0, jc] + A[1, ja] * A[1, jc] + A[2, ja] * A[2, jc]
        tr += G[4 * a]
    reg = eps * tr + 1e-300
    # in-place Cholesky G = L Lᵀ (lower triangle), then two triangular solves into y
    for a in range(nfree):
        d = G[4 * a] + reg
        for c in range(a):
            d -= G[3 * a + c] * G[3 * a + c]
        d = math.sqrt(max(d, reg))
        G[4 * a] = d
        for e in range(a + 1, nfree):
            v = G[3 * e + a]
            for c in range(a):
                v -= G[3 * e + c] * G[3 * a + c]
            G[3 * e + a] = v / d
    for a in range(nfree):
        v = rhs[a]
        for c in range(a):
            v -= G[3 * a + c] * y[c]
        y[a] = v / G[4 * a]
    for a in range(nfree - 1, -1, -1):
        v = y[a]
        for c in range(a + 1, nfree):
            v -= G[3 * c + a] * y[c]
        y[a] = v / G[4 * a]


@register_jitable
def bvls_allocate(A, m0, m1, m2, fmax, mask, F, state, G, rhs, y, idx, eps):
    """Exact bounded least-squares allocation ``min |A F - m|, 0 <= F <= fmax`` (NNLS with
    upper bounds), no allocation: the active-set method of Lawson & Hanson (1974, ch. 23)
    extended to two-sided bounds as in Stark & Parker's BVLS (1995).

    Hand-written because it must run inside the numba closed-loop kernel once per command
    period and per sample (scipy's ``lsq_linear(method="bvls")``, which
    :func:`adcskit.thrusters.allocate` uses for ``"nnls"``, cannot be called from compiled
    code). The produced torque ``A F`` is the unique projection of ``m`` onto the attainable
    set, so it agrees with the library's; the forces themselves are not unique when the
    layout is redundant.

    Starts with every thruster at its lower bound; each outer step frees the bound thruster
    whose gradient ``a_jᵀ (m - A F)`` most violates the KKT conditions, then the inner loop
    solves the free set's least-squares problem (:func:`_free_lsq`), steps back to the
    feasible box where it leaves it and re-binds the thrusters that hit a bound. With three
    torque components at most three thrusters are free (the residual vanishes with three
    independent free columns). ``state`` (n,): 0 at 0, 1 at ``fmax``, 2 free, 3/4 at 0/``fmax``
    but excluded for this step (its free solution moved it out of the box: Lawson & Hanson's
    guard against cycling), -1 failed (``mask == 0``, stays at 0). ``G`` (9), ``rhs``, ``y``,
    ``idx`` (3): scratch. Returns the number of outer iterations.

    References
    ----------
    Lawson C. L., Hanson R. J., *Solving Least Squares Problems*, Prentice-Hall 1974, ch. 23;
    Stark P. B., Parker R. L., "Bounded-variable least-squares: an algorithm and
    applications", Computational Statistics 10, 129-141, 1995. S3 eq. 13 (bounds).
    """
    n = F.shape[0]
    amax = 0.0
    fsum = 0.0
    for j in range(n):
        F[j] = 0.0
        state[j] = 0.0 if mask[j] > 0.0 else -1.0
        for a in range(3):
            amax = max(amax, abs(A[a, j]))
        if mask[j] > 0.0:
            fsum += fmax[j]
    mn = math.sqrt(m0 * m0 + m1 * m1 + m2 * m2)
    tol = 1e-11 * amax * (mn + amax * fsum) + 1e-300
    nfree = 0
    nit = 0
    for _ in range(3 * n + 10):
        nit += 1
        r0 = m0
        r1 = m1
        r2 = m2
        for j in range(n):
            f = F[j]
            r0 -= A[0, j] * f
            r1 -= A[1, j] * f
            r2 -= A[2, j] * f
        best = tol
        js = -1
        for j in range(n):
            st = state[j]
            if st == 0.0 or st == 1.0:
                w = A[0, j] * r0 + A[1, j] * r1 + A[2, j] * r2
                v = w if st == 0.0 else -w
                if v > best:
                    best = v
                    js = j
        if js < 0 or nfree >= 3:
            break
        prev = state[js]
        state[js] = 2.0
        idx[nfree] = js
        nfree += 1
        first = True
        for _ in range(n + 4):
            _free_lsq(A, F, state, fmax, m0, m1, m2, idx, nfree, G, rhs, y, eps)
            if first:
                first = False
                zs = y[nfree - 1]
                if (prev == 0.0 and zs <= 0.0) or (prev == 1.0 and zs >= fmax[js]):
                    nfree -= 1
                    state[js] = prev + 3.0
                    break
            ok = True
            for a in range(nfree):
                ja = int(idx[a])
                if y[a] < 0.0 or y[a] > fmax[ja]:
                    ok = False
            if ok:
                for a in range(nfree):
                    F[int(idx[a])] = y[a]
                for j in range(n):  # progress made: the excluded thrusters may re-enter
                    if state[j] >= 3.0:
                        state[j] -= 3.0
                break
            # step from the feasible F_F towards y up to the first bound
            alpha = 1.0
            for a in range(nfree):
                ja = int(idx[a])
                f = F[ja]
                if y[a] < 0.0:
                    t = f / (f - y[a])
                    if t < alpha:
                        alpha = t
                elif y[a] > fmax[ja]:
                    t = (fmax[ja] - f) / (y[a] - f)
                    if t < alpha:
                        alpha = t
            k = 0
            for a in range(nfree):
                ja = int(idx[a])
                f = F[ja] + alpha * (y[a] - F[ja])
                if f <= 1e-14 * fmax[ja]:
                    F[ja] = 0.0
                    state[ja] = 0.0
                elif f >= fmax[ja] * (1.0 - 1e-14):
                    F[ja] = fmax[ja]
                    state[ja] = 1.0
                else:
                    F[ja] = f
                    idx[k] = ja
                    k += 1
            nfree = k
            if nfree == 0:
                break
    for j in range(n):
        if mask[j] <= 0.0:
            F[j] = 0.0
        elif F[j] < 0.0:
            F[j] = 0.0
        elif F[j] > fmax[j]:
            F[j] = fmax[j]
    return nit


def sample_loop(i, A):
    """Simulate sample ``i`` over all steps; write ``OUT[i]``, ``TOT[i]`` and ``REC[i]``.

    ``A``: the kernel's arrays (:data:`Arrays`; shapes in :data:`ARGS`); every array indexed
    ``[i]`` is this lane's own memory. :func:`_init` and :func:`_finish` around the loop; a step is
    :func:`_sense_estimate` (at gyro epochs; :func:`_determine` after it for the Wahba and
    min-max estimators), :func:`_control` (at command instants), :func:`_actuate`, then the
    environment torques, the RK4 step and the metrics in the loop's own body (as calls, they
    cost 14-20 % CPU: docs/decisions/kernel-step-functions.md); the scalar state travels as tuples,
    the lane's arrays as tuples of views made once per sample. ``_sense_estimate`` and
    ``_control`` are inlined by numba (``inline="always"``: as calls they cost 6-8 % CPU on the
    full chain, 3-5 % on the truth path), the others are calls (LLVM inlines ``_actuate``).
    The RK4 step is :func:`rk4_step_principal` (numba-inlined) when the sample's inertia is
    diagonal, :func:`rk4_step` (a call) otherwise: the same doubles, a quarter fewer operations
    (docs/benchmarks.md, "Principal axes").
    """
    n = A.POS.shape[0]
    dt = A.C[DT]
    n_steps = int(A.C[N_STEPS])
    h_ctrl = int(A.C[H_CTRL])
    h_gyro = int(A.C[H_GYRO])
    est_mode = int(A.C[EST_MODE])
    k_win = int(A.C[K_WIN])
    band = A.C[SETTLE_BAND]
    rec_every = int(A.C[REC_EVERY])
    bmask = int(A.C[BUF_MASK])
    record = A.REC.shape[0] > 0
    lag = (A.C[A11], A.C[B1], A.C[A21], A.C[A22], A.C[B2], A.C[V1], A.C[V2], A.C[VU])
    J = A.P[i, P_J:P_J + 9]
    Ji = A.P[i, P_JI:P_JI + 9]
    diag = principal(J, Ji)  # body axes = principal axes: the RK4 step without the zero terms
    jd, jid = (J[0], J[4], J[8]), (Ji[0], Ji[4], Ji[8])
    buf = A.BUF[i]
    ts = A.TS[i]
    x2o = n
    so = 9 * n
    scr = (ts[4 * n:5 * n], ts[5 * n:6 * n], ts[so:so + 9], ts[so + 9:so + 12],
           ts[so + 12:so + 15], ts[so + 15:so + 18])  # F, free, S, r, y, idx
    qe = A.QE[i]
    # this lane's views, made once per sample and passed grouped: estimator state and gyro
    # scratch, vector observations; the determination solvers' arrays (Wahba / min-max only)
    est = (qe, A.BE[i], A.PE[i], A.WK[i], A.GY[i], A.BIAS[i], A.SQ[i])
    obs = (A.VB[i], A.VR[i], A.WW[i])
    det = (A.VB, A.VR, A.WW, A.WQ, A.WO, A.WC, A.SB[i], A.SR[i], A.SQP[i], A.SBB[i], A.SFF[i], A.SKK[i], A.SAA[i], A.SBK[i],
           A.RS[i])
    thr = (A.QREF, A.WREF, A.ATAB, A.ANOM, A.FNOM, A.AMASK)
    _init(i, A.P, A.DIRS, A.POS, buf, ts, est, A.TOT, n)
    dist = (A.P[i, P_D0], A.P[i, P_D0 + 1], A.P[i, P_D0 + 2], A.P[i, P_DAMP], A.P[i, P_DAMP + 1],
            A.P[i, P_DAMP + 2], A.P[i, P_DPH], A.P[i, P_DPH + 1], A.P[i, P_DPH + 2])
    # settling: |error| > band decided without atan2 away from the band's edge (exact there)
    tb_lo, tb_hi = settle_bounds(band)
    n2orb = A.C[N2ORB]
    d_omega = A.C[D_OMEGA]
    q = (A.P[i, P_Q0], A.P[i, P_Q0 + 1], A.P[i, P_Q0 + 2], A.P[i, P_Q0 + 3])
    w = (A.P[i, P_W0], A.P[i, P_W0 + 1], A.P[i, P_W0 + 2])
    delay_steps = A.P[i, P_DELAY] / dt
    nd = int(math.floor(delay_steps))
    dfrac = delay_steps - nd
    s = A.SEEDS[i]
    we = (0.0, 0.0, 0.0)  # estimated rate
    ws = (0.0, 0.0, 0.0)  # integrated true rate since the last gyro epoch
    ctl = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)  # Schmitt outputs, PID integrals
    fire = (0.0, 0.0)  # firings, on-time
    kc = 0
    prop = 0.0
    kacc2 = 0.0
    nkw = 0
    ec = (math.nan, 0.0, 0, 0, 0)  # last NEES, NEES sum and count, determinations, box active
    qf = (A.QREF[n_steps, 0], A.QREF[n_steps, 1], A.QREF[n_steps, 2], A.QREF[n_steps, 3])
    e = qerr(q[0], q[1], q[2], q[3], A.QREF[0, 0], A.QREF[0, 1], A.QREF[0, 2], A.QREF[0, 3])
    errf = qerr(q[0], q[1], q[2], q[3], qf[0], qf[1], qf[2], qf[3])[3]
    mt = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0)  # acc, acc2, ax2, ay2, az2, emax, nwin
    last_out = 0 if errf > band else -1
    wmax2 = 0.0
    if record:
        _record(A.REC, i, 0, e[0], e[1], e[2], e[3], qe, q[0], q[1], q[2], q[3], w[0], w[1], w[2],
                math.nan, 0.0, ts, x2o, n)
    k_gyro = 0  # next gyro epoch
    k_ctrl = 0  # next command instant
    for k in range(n_steps + 1):
        if est_mode == EST_TRUTH:
            qe[0] = q[0]
            qe[1] = q[1]
            qe[2] = q[2]
            qe[3] = q[3]
            we = w
        elif k == k_gyro:
            k_gyro += h_gyro
            s, we, ec, nobs = _sense_estimate(k, A.C, A.ENV, q, w, s, ws, ec, est, obs)
            if (est_mode == EST_WAHBA or est_mode == EST_MINMAX) and nobs == 2:
                ec = _determine(i, A.C, qe, ec, det)
            ws = (0.0, 0.0, 0.0)
        if k >= k_win:  # knowledge error at t_k, after this epoch's estimation
            kerr = qerr(qe[0], qe[1], qe[2], qe[3], q[0], q[1], q[2], q[3])[3]
            kacc2 += kerr * kerr
            nkw += 1
        if k == n_steps:
            break
        if k == k_ctrl:
            k_ctrl += h_ctrl
            kc = k
            ctl, fire = _control(i, k, A.C, qe, we, ctl, fire, thr, scr, ts, A.TOT, n)
        t0, t1, t2, prop = _actuate(i, k, k - kc, nd, dfrac, ts, buf, bmask, A.FAILED, A.FLEV, A.MDOT,
                                    lag, dt, prop, n)
        # environment torques (a zero amplitude adds a signed zero: its sine is skipped)
        tk = k * dt
        t0 += dist[0] + dist[3] * math.sin(d_omega * tk + dist[6]) if dist[3] != 0.0 else dist[0]
        t1 += dist[1] + dist[4] * math.sin(d_omega * tk + dist[7]) if dist[4] != 0.0 else dist[1]
        t2 += dist[2] + dist[5] * math.sin(d_omega * tk + dist[8]) if dist[5] != 0.0 else dist[2]
        if n2orb > 0.0:
            c0, c1, c2 = rotate(q[0], q[1], q[2], q[3], A.ENV[k, 0], A.ENV[k, 1], A.ENV[k, 2])
            h0, h1, h2 = _inertia_times(J, diag, c0, c1, c2)
            t0 += 3.0 * n2orb * (c1 * h2 - c2 * h1)
            t1 += 3.0 * n2orb * (c2 * h0 - c0 * h2)
            t2 += 3.0 * n2orb * (c0 * h1 - c1 * h0)
        if diag:
            q0, q1, q2, q3, w0n, w1n, w2n = rk4_step_principal(
                q[0], q[1], q[2], q[3], w[0], w[1], w[2], jd[0], jd[1], jd[2], jid[0], jid[1], jid[2],
                t0, t1, t2, dt)
        else:
            q0, q1, q2, q3, w0n, w1n, w2n = rk4_step(q[0], q[1], q[2], q[3], w[0], w[1], w[2], J,
                                                     Ji, t0, t1, t2, dt)
        q = (q0, q1, q2, q3)
        # mean rate over the step (trapezoid) for the rate-integrating gyro
        ws = (ws[0] + 0.5 * (w[0] + w0n), ws[1] + 0.5 * (w[1] + w1n), ws[2] + 0.5 * (w[2] + w2n))
        w = (w0n, w1n, w2n)
        kk = k + 1
        rec_now = record and kk % rec_every == 0
        if kk >= k_win or rec_now or kk == n_steps:  # used in the window, traces, final error
            e = qerr(q0, q1, q2, q3, A.QREF[kk, 0], A.QREF[kk, 1], A.QREF[kk, 2], A.QREF[kk, 3])
        if outside(q0, q1, q2, q3, qf[0], qf[1], qf[2], qf[3], band, tb_lo, tb_hi):
            last_out = kk
        wn2 = w0n * w0n + w1n * w1n + w2n * w2n  # max |w| = sqrt(max |w|^2): one sqrt
        if wn2 > wmax2:
            wmax2 = wn2
        if kk >= k_win:
            mt = _window(mt, e)
        if rec_now:
            _record(A.REC, i, kk // rec_every, e[0], e[1], e[2], e[3], qe, q[0], q[1], q[2], q[3],
                    w[0], w[1], w[2], ec[0], prop, ts, x2o, n)
    _finish(A.OUT, i, mt, last_out, wmax2, e[3], kacc2, nkw, prop, fire, ec, n_steps, dt)


@register_jitable
def _init(i, P, DIRS, POS, buf, ts, est, TOT, n):
    """Clear sample ``i``'s scratch, set its torque arms and its estimator's initial state."""
    qe, be, Pe, _, gy, bias, _ = est
    armo = 6 * n
    for j in range(N_TS_PER_THR * n + N_TS_EXTRA):
        ts[j] = 0.0
    for j in range(n):  # torque arm r x d of each (dispersed) thruster, N m per N
        d0 = DIRS[i, j, 0]
        d1 = DIRS[i, j, 1]
        d2 = DIRS[i, j, 2]
        r0 = POS[j, 0]
        r1 = POS[j, 1]
        r2 = POS[j, 2]
        ts[armo + 3 * j] = r1 * d2 - r2 * d1
        ts[armo + 3 * j + 1] = r2 * d0 - r0 * d2
        ts[armo + 3 * j + 2] = r0 * d1 - r1 * d0
    for a in range(buf.shape[0]):
        for j in range(n):
            buf[a, j] = 0.0
    for a in range(4):
        qe[a] = P[i, P_QE0 + a]
    for a in range(3):
        be[a] = 0.0
        bias[a] = P[i, P_BIAS + a]
        gy[a] = 0.0
        gy[3 + a] = 0.0
        gy[6 + a] = 0.0
    for a in range(6):
        for b in range(6):
            Pe[a, b] = 0.0
    sa2 = P[i, P_SIGA0] * P[i, P_SIGA0]
    sb2 = P[i, P_SIGB0] * P[i, P_SIGB0]
    for a in range(3):
        Pe[a, a] = sa2
        Pe[3 + a, 3 + a] = sb2
    for j in range(n):
        TOT[i, j] = 0.0


@register_jitable(inline="always")
def _sense_estimate(k, C, ENV, q, w, s, ws, ec, est, obs):
    """Sensors and estimation at gyro epoch ``k``: the gyro, the attitude propagation, the
    vector sensors and star tracker, the estimator's update; returns the noise state, the
    estimated rate, ``ec`` (last NEES, NEES sum and count, determinations, box active) and the
    number of vector observations made (:func:`_determine` then solves Wahba's problem).
    ``est`` and ``obs``: the lane's views made once per sample by :func:`sample_loop`."""
    qe, be, Pe, wk, gy, bias, sq = est
    vb, vr, ww = obs
    q0, q1, q2, q3 = q
    nees_last, nees_sum, nees_n, n_det, n_box = ec
    est_mode = int(C[EST_MODE])
    h_gyro = int(C[H_GYRO])
    h_sun = int(C[H_SUN])
    h_mag = int(C[H_MAG])
    h_st = int(C[H_ST])
    uni = C[NOISE_UNIFORM] > 0.0
    # the filter's noise sigma: the std of a uniform [-a, a] error is a / sqrt(3)
    fil = 1.0 / math.sqrt(3.0) if uni else 1.0
    sig_v = C[SIG_V]
    sig_u = C[SIG_U]
    uw = C[UNDERWEIGHT]
    dt_g = h_gyro * C[DT]
    # gyro reading at t_k: Farrenkopf model on the mean true rate over the last interval (a
    # rate-integrating gyro's delta-angle / dt); the attitude is then propagated over that
    # interval with it
    if k > 0:
        gy[3] = ws[0] / h_gyro
        gy[4] = ws[1] / h_gyro
        gy[5] = ws[2] / h_gyro
    else:
        gy[3] = w[0]
        gy[4] = w[1]
        gy[5] = w[2]
    for a in range(6):
        s, z = _normal(s)
        gy[6 + a] = z
    gyro_step(gy[3:6], bias, sig_v, sig_u, dt_g, gy[6:9], gy[9:12], gy[0:3])
    if k > 0:
        if est_mode == EST_MEKF:
            mekf_propagate(qe, be, Pe, gy[0:3], dt_g, sig_v, sig_u, wk)
        else:
            _compose_rotvec(qe, gy[0] * dt_g, gy[1] * dt_g, gy[2] * dt_g)
    # vector sensors at this epoch
    nobs = 0
    for kind in range(2):
        h = h_sun if kind == 0 else h_mag
        if h > 0 and k % h == 0 and (kind == 1 or ENV[k, 9] > 0.5):
            o = 3 + 3 * kind
            sig = C[SIG_SUN] if kind == 0 else C[SIG_MAG]
            b0, b1, b2 = rotate(q0, q1, q2, q3, ENV[k, o], ENV[k, o + 1], ENV[k, o + 2])
            s, n0 = _noise(s, uni)
            s, n1 = _noise(s, uni)
            s, n2 = _noise(s, uni)
            vb[nobs, 0] = b0 + sig * n0
            vb[nobs, 1] = b1 + sig * n1
            vb[nobs, 2] = b2 + sig * n2
            vr[nobs, 0] = ENV[k, o]
            vr[nobs, 1] = ENV[k, o + 1]
            vr[nobs, 2] = ENV[k, o + 2]
            ww[nobs] = C[W_SUN] if kind == 0 else C[W_MAG]
            if est_mode == EST_MEKF:
                mekf_update_vector(qe, be, Pe, vb[nobs], vr[nobs], sig * fil, uw, wk)
            nobs += 1
    if h_st > 0 and k % h_st == 0:
        s, n0 = _normal(s)
        s, n1 = _normal(s)
        s, n2 = _normal(s)
        sq[0] = q0
        sq[1] = q1
        sq[2] = q2
        sq[3] = q3
        sig_st = C[SIG_ST]
        _compose_rotvec(sq, sig_st * n0, sig_st * n1, sig_st * n2)
        if est_mode == EST_MEKF:
            mekf_update_quaternion(qe, be, Pe, sq, sig_st, wk)
        else:
            for a in range(4):
                qe[a] = sq[a]
    if est_mode == EST_MEKF:
        we = (gy[0] - be[0], gy[1] - be[1], gy[2] - be[2])
        if k >= int(C[K_NEES]):
            nees_last = mekf_nees(qe, be, Pe, _tmp4(sq, q0, q1, q2, q3), bias, wk)
            if nees_last == nees_last:
                nees_sum += nees_last
                nees_n += 1
    else:
        we = (gy[0], gy[1], gy[2])
    return s, we, (nees_last, nees_sum, nees_n, n_det, n_box), nobs


@register_jitable
def _determine(i, C, qe, ec, det):
    """Wahba (or min-max) solve of the epoch's two vector observations of sample ``i`` into the
    attitude estimate ``qe`` (on success); returns ``ec`` with the determination counters."""
    VB, VR, WW, WQ, WO, WC, sb, sr, sqp, sbb, sff, skk, saa, sbk, rs = det
    nees_last, nees_sum, nees_n, n_det, n_box = ec
    st = -1
    if int(C[EST_MODE]) == EST_WAHBA:
        st = wahba_one(VB, VR, WW, i, int(C[WAHBA_METHOD]), WQ, WO, WC, sb, sr, sqp[0:4], sbb,
                       sff, skk, saa, sbk, sqp[4:8])
    else:
        st, active = minmax_one(VB, VR, WW, i, C[SEARCH_RANGE], WQ, WO, WC, sb, sr, sqp[0:4],
                                sbb, sff, skk, saa, sbk, sqp[4:8], rs[0:4], rs[4:8], rs[8:12],
                                rs[12:16])
        n_det += 1
        if active:
            n_box += 1
    if st == 0:
        for a in range(4):
            qe[a] = WQ[i, a]
    return (nees_last, nees_sum, nees_n, n_det, n_box)


@register_jitable(inline="always")
def _control(i, k, C, qe, we, ctl, fire, thr, scr, ts, TOT, n):
    """PID law, Schmitt trigger or allocation, and pulse widths at command instant ``k``;
    returns the Schmitt outputs and PID integrals ``ctl`` and (firings, on-time) ``fire``.
    ``thr``: the reference and thruster tables, ``scr``: the allocation's scratch views."""
    QREF, WREF, ATAB, ANOM, FNOM, AMASK = thr
    F, free, Ssc, rsc, ysc, isc = scr
    sx, sy, sz, ix, iy, iz = ctl
    firings, ontime = fire
    h_ctrl = int(C[H_CTRL])
    t_s = C[T_S]
    t_min = C[T_MIN]
    tppo = 3 * n
    tpo = 2 * n
    cx, cy, cz, _ = qerr(qe[0], qe[1], qe[2], qe[3], QREF[k, 0], QREF[k, 1], QREF[k, 2],
                         QREF[k, 3])
    exk = -cx
    eyk = -cy
    ezk = -cz
    dx = WREF[k, 0] - we[0]
    dy = WREF[k, 1] - we[1]
    dz = WREF[k, 2] - we[2]
    ux = C[KP0] * exk + C[KI0] * ix + C[KD0] * dx
    uy = C[KP1] * eyk + C[KI1] * iy + C[KD1] * dy
    uz = C[KP2] * ezk + C[KI2] * iz + C[KD2] * dz
    ix += exk * t_s
    iy += eyk * t_s
    iz += ezk * t_s
    ctrl_mode = int(C[CTRL_MODE])
    if ctrl_mode == CTRL_SCHMITT:
        sx = schmitt(sx, ux, C[U_ON], C[U_OFF])
        sy = schmitt(sy, uy, C[U_ON], C[U_OFF])
        sz = schmitt(sz, uz, C[U_ON], C[U_OFF])
        row = int((sx + 1.0) * 9.0 + (sy + 1.0) * 3.0 + (sz + 1.0))
        for j in range(n):
            F[j] = ATAB[row, j]
    elif ctrl_mode == CTRL_OPEN:  # open loop: ATAB holds the on-times per period
        row = k // h_ctrl
        for j in range(n):
            F[j] = ATAB[row, j] / t_s * FNOM[j] if row < ATAB.shape[0] else 0.0
    elif int(C[ALLOC_MODE]) == ALLOC_BVLS:
        bvls_allocate(ANOM, C[TL0] * ux, C[TL1] * uy, C[TL2] * uz, FNOM, AMASK, F, free,
                      Ssc, rsc, ysc, isc, C[RPI_EPS])
    else:
        rpi_allocate(ANOM, C[TL0] * ux, C[TL1] * uy, C[TL2] * uz, FNOM, AMASK, F, free,
                     Ssc, rsc, ysc, C[RPI_EPS])
    pround = C[PULSE_ROUND] > 0.0
    dt = C[DT]
    for j in range(n):
        tp = F[j] / FNOM[j] * t_s
        if tp > t_s:
            tp = t_s
        if tp < t_min:
            if pround and tp >= 0.5 * t_min:
                tp = t_min
            else:
                tp = 0.0
        if AMASK[j] <= 0.0:
            tp = 0.0
        # a new pulse unless the previous one ran to the end of its period
        if tp > 0.0 and ts[tppo + j] < t_s:
            firings += 1.0
        ts[tppo + j] = tp
        ts[tpo + j] = tp / dt  # the pulse in steps (read at every step below)
        TOT[i, j] += tp
        ontime += tp
    return (sx, sy, sz, ix, iy, iz), (firings, ontime)


@register_jitable
def _actuate(i, k, m, nd, dfrac, ts, buf, bmask, FAILED, FLEV, MDOT, lag, dt, prop, n):
    """Thrusters over step ``k``, ``m`` steps into the pulse period: delay line, lags,
    thrust torque; returns the torque and the propellant used so far."""
    a11, b1, a21, a22, b2, v1, v2, vu = lag
    x2o = n
    tpo = 2 * n
    armo = 6 * n
    t0 = 0.0
    t1 = 0.0
    t2 = 0.0
    for j in range(n):
        c = ts[tpo + j] - m
        if c > 1.0:
            c = 1.0
        elif c < 0.0:
            c = 0.0
        if FAILED[j] > 0.0:
            c = 0.0
        buf[k & bmask, j] = c
        if k - nd >= 0:
            ua = buf[(k - nd) & bmask, j]
        else:
            ua = 0.0
        if k - nd - 1 >= 0:
            ub = buf[(k - nd - 1) & bmask, j]
        else:
            ub = 0.0
        ud = delay_mix(ua, ub, dfrac)
        v, x1, x2 = lag_step(ts[j], ts[x2o + j], ud, a11, b1, a21, a22, b2, v1, v2, vu)
        ts[x2o + j] = x2
        ts[j] = x1
        if v != 0.0:  # an idle thruster adds (signed) zeros: skipped, same sums
            fav = FLEV[i, j] * v / dt  # mean force over the step (N)
            prop += MDOT[i, j] * v  # per-sample mass flow (dispersed thrust, constant Isp)
            t0 += fav * ts[armo + 3 * j]
            t1 += fav * ts[armo + 3 * j + 1]
            t2 += fav * ts[armo + 3 * j + 2]
    return t0, t1, t2, prop


@register_jitable
def _window(mt, e):
    """Add the pointing error ``e`` at one step of the metric window to the sums ``mt``."""
    acc, acc2, ax2, ay2, az2, emax, nwin = mt
    ex, ey, ez, err = e
    acc += err
    acc2 += err * err
    ax2 += ex * ex
    ay2 += ey * ey
    az2 += ez * ez
    if err > emax:
        emax = err
    return (acc, acc2, ax2, ay2, az2, emax, nwin + 1)


@register_jitable
def _finish(OUT, i, mt, last_out, wmax2, err, kacc2, nkw, prop, fire, ec, n_steps, dt):
    """Write sample ``i``'s metrics ``OUT[i]`` from the loop's accumulators."""
    acc, acc2, ax2, ay2, az2, emax, nwin = mt
    _, nees_sum, nees_n, n_det, n_box = ec
    fw = 1.0 / nwin if nwin > 0 else math.nan
    OUT[i, M_MEAN_ERR] = acc * fw
    OUT[i, M_RMS_ERR] = math.sqrt(acc2 * fw)
    OUT[i, M_MAX_ERR] = emax if nwin > 0 else math.nan
    OUT[i, M_RMS_X] = math.sqrt(ax2 * fw)
    OUT[i, M_RMS_Y] = math.sqrt(ay2 * fw)
    OUT[i, M_RMS_Z] = math.sqrt(az2 * fw)
    if last_out < 0:
        OUT[i, M_SETTLE] = 0.0
    elif last_out >= n_steps:
        OUT[i, M_SETTLE] = math.nan
    else:
        OUT[i, M_SETTLE] = (last_out + 1) * dt
    OUT[i, M_FINAL_ERR] = err
    OUT[i, M_PROP] = prop
    OUT[i, M_FIRINGS] = fire[0]
    OUT[i, M_ONTIME] = fire[1]
    OUT[i, M_KNOW_RMS] = math.sqrt(kacc2 / nkw) if nkw > 0 else math.nan
    OUT[i, M_NEES] = nees_sum / nees_n if nees_n > 0 else math.nan
    OUT[i, M_NEES_N] = nees_n
    OUT[i, M_MAX_RATE] = math.sqrt(wmax2)
    OUT[i, M_BOX_ACTIVE] = n_box / n_det if n_det > 0 else math.nan


@register_jitable
def settle_bounds(band):
    """``(tb_lo, tb_hi)`` of :func:`outside` for the settling band ``band`` (rad):
    ``tan(band/2)^2 (1 -/+ 1e-6)``, or negative (always the exact test) for ``band >= 3``."""
    tb2 = math.tan(0.5 * band) ** 2 if 0.5 * band < 1.5 else -1.0
    return tb2 * (1.0 - 1e-6), tb2 * (1.0 + 1e-6)


@register_jitable
def qangle(d0, d1, d2, d3):
    """Rotation angle (rad, in [0, pi]) of the quaternion ``d``."""
    return 2.0 * math.atan2(math.sqrt(d0 * d0 + d1 * d1 + d2 * d2), abs(d3))


@register_jitable
def outside(q0, q1, q2, q3, r0, r1, r2, r3, band, tb_lo, tb_hi):
    """Whether the angle of ``q (x) r^-1`` exceeds ``band`` (rad): exactly
    ``qangle(*qdiff(q, r)) > band`` (the angle of :func:`adcskit.attitude._device.qerr`, whose
    ``qdiff`` has ``d4 >= 0``: the same double except for ``d = (0, 0, 0, -0.0)``, a zero
    quaternion, where ``qerr``'s ``atan2(0, -0.0)`` gives 2 pi), with the ``atan2`` and the
    square root only within a relative 1e-6 of the edge. Away from it ``tan(angle/2)^2 = |d|^2 / d4^2`` decides against
    ``tb_lo`` / ``tb_hi`` (:func:`settle_bounds`; rounding of the squares: ~1e-16 relative); a
    non-positive ``tb_hi`` always takes the exact path, as do NaNs (both comparisons false).
    The settling test of both closed-loop kernels (thrusters and wheels)."""
    # the sign that qdiff fixes (q4 >= 0) does not change the squares below
    d0, d1, d2, d3 = qdiff(q0, q1, q2, q3, r0, r1, r2, r3)
    e2 = d0 * d0 + d1 * d1 + d2 * d2
    c2 = d3 * d3
    if tb_hi > 0.0:
        if e2 > tb_hi * c2:
            return True
        if e2 < tb_lo * c2:
            return False
    return qangle(d0, d1, d2, d3) > band


@register_jitable
def _tmp4(buf, q0, q1, q2, q3):
    """Write a quaternion into a 4-element scratch row and return it (for kernel calls)."""
    buf[0] = q0
    buf[1] = q1
    buf[2] = q2
    buf[3] = q3
    return buf


@register_jitable
def _record(REC, i, r, ex, ey, ez, err, qe, q0, q1, q2, q3, w0, w1, w2, nees, prop, ts, x2o, n):
    REC[i, r, R_EX] = ex
    REC[i, r, R_EY] = ey
    REC[i, r, R_EZ] = ez
    REC[i, r, R_ERR] = err
    _, _, _, kerr = qerr(qe[0], qe[1], qe[2], qe[3], q0, q1, q2, q3)
    REC[i, r, R_KNOW] = kerr
    REC[i, r, R_WX] = w0
    REC[i, r, R_WY] = w1
    REC[i, r, R_WZ] = w2
    REC[i, r, R_NEES] = nees
    REC[i, r, R_PROP] = prop
    for j in range(n):
        REC[i, r, N_REC_FIXED + j] = ts[x2o + j]


@register_jitable
def _wahba_unavailable(VB, VR, WW, i, method, WQ, WO, WC, b, r, q, B, F, K, A, Bk, qp):
    """Device stand-in of :func:`wahba_one` (never reached: the GPU driver refuses the Wahba
    estimator); returns a failure status."""
    return -1


@register_jitable
def _minmax_unavailable(VB, VR, WW, i, search_range, WQ, WO, WC, b, r, q, B, F, K, A, Bk, qp, qt, lb,
                        ub, qb):
    """Device stand-in of :func:`adcskit.determination._box.minmax_one` (never reached: the GPU
    driver refuses the min-max estimator); returns a failure status."""
    return -1, False


#: Estimator modes the GPU driver runs (the others call CPU-only determination kernels).
CUDA_EST_MODES = (EST_TRUTH, EST_MEKF)

#: The per-sample function, declared through :mod:`adcskit._targets` (one source for the CPU
#: and the GPU driver). ``inline="never"``: the loop stays one compiled function called by
#: :func:`run_parallel` (as before the declaration: same code, same numbers). ``nrt=False``:
#: no reference counting in the loop and its step functions (nothing there allocates; numba
#: otherwise increments and decrements the count of every array a step function receives, at
#: each call). The CUDA compilation rebinds the CPU-only dispatchers to the device sources they
#: were built from.
SAMPLE = PerSample(
    sample_loop, inline="never", error_model="numpy", nrt=False,
    device_names={
        "_sense_estimate": register_jitable(rebound(_sense_estimate, {
            "mekf_propagate": _mk.mekf_propagate, "mekf_update_vector": _mk.mekf_update_vector,
            "mekf_update_quaternion": _mk.mekf_update_quaternion, "mekf_nees": _mk.mekf_nees,
            "gyro_step": _mk.gyro_step, "_compose_rotvec": compose_rotvec})),
        "_determine": register_jitable(rebound(_determine, {
            "wahba_one": _wahba_unavailable, "minmax_one": _minmax_unavailable})),
        # calls, not numba IR inlining, on the device: numba-cuda does not type the inlined
        # copies ("mul(omitted, omitted)"); NVVM inlines them itself
        "_control": register_jitable(rebound(_control, {})),
        "rk4_step_principal": register_jitable(rebound(rk4_step_principal, {})),
    },
)
sample_loop_jit = SAMPLE.cpu


# --- CPU driver: samples in lanes --------------------------------------------------------------
#: Samples advanced together by :func:`block_loop` (one ``prange`` iteration, at most): the RK4
#: step runs as one loop over the lanes, which LLVM vectorises (2 x 4 doubles in 256-bit
#: registers: LLVM's choice also on the AVX-512 CPU measured); docs/benchmarks.md, "Samples in
#: lanes". 16 measured no faster.
LANES = 8

# The per-lane scalar state of block_loop (what sample_loop keeps in locals), one line per
# variable (name=width): FS[lane, _F.NAME + k] (float) and IS[lane, _I.NAME + k] (int).
_F, N_FS = lane_slots(
    "FloatSlots",
    WE=3,  # estimated rate
    CTL=6,  # Schmitt outputs, PID integrals
    FIRE=2,  # firings, on-time
    PROP=1,  # propellant used
    KACC2=1,  # knowledge error sum of squares
    NEES=2,  # last NEES, NEES sum
    MT=6,  # metric window sums: acc, acc2, ax2, ay2, az2, emax
    E=4,  # pointing error ex, ey, ez, angle
    WMAX2=1,  # max |w|^2
    DIST=9,  # disturbance constant, amplitude, phase
    DFRAC=1,  # fractional delay
)
_I, N_IS = lane_slots(
    "IntSlots",
    NEES_N=3,  # NEES count, determinations, box active
    LAST_OUT=1,  # last step outside the settling band
    ND=1,  # whole delay steps
    DIAG=1,  # 1: principal axes (the RK4 step without the zero terms)
)


#: :func:`rk4_step` inlined by numba into the lane loops (a copy of its code: the same
#: operations), so that LLVM sees the whole step inside the loop it vectorises.
_rk4_step_inline = register_jitable(inline="always")(rebound(rk4_step, {}))


@register_jitable(inline="always")
def _lane_principal(X, JG, T, l, dt):
    """:func:`rk4_step_principal` of lane ``l``: state ``X[0:7, l]`` (q, omega), J and J^-1
    row-major in ``JG[0:9, l]``, ``JG[9:18, l]`` (their diagonals read), torque ``T[0:3, l]``."""
    return rk4_step_principal(X[0, l], X[1, l], X[2, l], X[3, l], X[4, l], X[5, l], X[6, l],
                              JG[0, l], JG[4, l], JG[8, l], JG[9, l], JG[13, l], JG[17, l],
                              T[0, l], T[1, l], T[2, l], dt)


@register_jitable(inline="always")
def _lane_general(X, JG, T, l, dt):
    """:func:`rk4_step` of lane ``l`` (the arrays as in :func:`_lane_principal`)."""
    return _rk4_step_inline(
        X[0, l], X[1, l], X[2, l], X[3, l], X[4, l], X[5, l], X[6, l],
        (JG[0, l], JG[1, l], JG[2, l], JG[3, l], JG[4, l], JG[5, l], JG[6, l], JG[7, l], JG[8, l]),
        (JG[9, l], JG[10, l], JG[11, l], JG[12, l], JG[13, l], JG[14, l], JG[15, l], JG[16, l],
         JG[17, l]), T[0, l], T[1, l], T[2, l], dt)


@register_jitable(inline="always")
def _lane_store(X, WS, l, x):
    """Lane ``l``'s new state ``x`` (q, omega) into ``X``, after adding the step's mean rate
    (the trapezoid of :func:`sample_loop`) to the gyro's rate sums ``WS``."""
    WS[0, l] = WS[0, l] + 0.5 * (X[4, l] + x[4])
    WS[1, l] = WS[1, l] + 0.5 * (X[5, l] + x[5])
    WS[2, l] = WS[2, l] + 0.5 * (X[6, l] + x[6])
    X[0, l] = x[0]
    X[1, l] = x[1]
    X[2, l] = x[2]
    X[3, l] = x[3]
    X[4, l] = x[4]
    X[5, l] = x[5]
    X[6, l] = x[6]


@register_jitable(inline="always")
def _lanes_rk4(X, JG, T, WS, nl, dt, general):
    """The RK4 step of lanes ``0..nl-1`` in place (:func:`_lane_principal`, or
    :func:`_lane_general` when ``general``) and the gyro's rate sums: the same operations per
    lane as :func:`sample_loop`, in a loop that LLVM vectorises across lanes."""
    if general:
        for l in range(nl):
            _lane_store(X, WS, l, _lane_general(X, JG, T, l, dt))
    else:
        for l in range(nl):
            _lane_store(X, WS, l, _lane_principal(X, JG, T, l, dt))


@register_jitable
def _lanes_init(i0, nl, A, X, WS, JG, FS, IS, SS, blk):
    """The lanes of :func:`block_loop` at the start: each sample's scratch (:func:`_init`),
    state, inertia, delay, disturbance, counters and first trace row. Returns whether the
    block's inertias are all diagonal, and whether none is."""
    n, n_steps, dt, est_mode, bmask, rec_every, lag, thr, n2orb, d_omega, qf, band, tb_lo, tb_hi = blk
    record = A.REC.shape[0] > 0
    x2o = n
    all_diag = True
    all_full = True
    for l in range(nl):
        i = i0 + l
        J = A.P[i, P_J:P_J + 9]
        Ji = A.P[i, P_JI:P_JI + 9]
        diag = principal(J, Ji)
        all_diag = all_diag and diag
        all_full = all_full and not diag
        IS[l, _I.DIAG] = 1 if diag else 0
        for a in range(9):
            JG[a, l] = J[a]
            JG[9 + a, l] = Ji[a]
        buf = A.BUF[i]
        ts = A.TS[i]
        est = (A.QE[i], A.BE[i], A.PE[i], A.WK[i], A.GY[i], A.BIAS[i], A.SQ[i])
        _init(i, A.P, A.DIRS, A.POS, buf, ts, est, A.TOT, n)
        for a in range(9):
            FS[l, _F.DIST + a] = A.P[i, P_D0 + a]  # P_D0, P_DAMP, P_DPH: 3 each, consecutive
        delay_steps = A.P[i, P_DELAY] / dt
        nd = int(math.floor(delay_steps))
        IS[l, _I.ND] = nd
        FS[l, _F.DFRAC] = delay_steps - nd
        SS[l] = A.SEEDS[i]
        for a in range(4):
            X[a, l] = A.P[i, P_Q0 + a]
        for a in range(3):
            X[4 + a, l] = A.P[i, P_W0 + a]
            WS[a, l] = 0.0
        for a in range(_F.MT):  # we, ctl, fire, prop, kacc2, last NEES, NEES sum
            FS[l, a] = 0.0
        FS[l, _F.NEES] = math.nan
        for a in range(6):
            FS[l, _F.MT + a] = 0.0
        FS[l, _F.WMAX2] = 0.0
        IS[l, _I.NEES_N] = 0
        IS[l, _I.NEES_N + 1] = 0
        IS[l, _I.NEES_N + 2] = 0
        q0, q1, q2, q3 = X[0, l], X[1, l], X[2, l], X[3, l]
        e = qerr(q0, q1, q2, q3, A.QREF[0, 0], A.QREF[0, 1], A.QREF[0, 2], A.QREF[0, 3])
        FS[l, _F.E] = e[0]
        FS[l, _F.E + 1] = e[1]
        FS[l, _F.E + 2] = e[2]
        FS[l, _F.E + 3] = e[3]
        errf = qerr(q0, q1, q2, q3, qf[0], qf[1], qf[2], qf[3])[3]
        IS[l, _I.LAST_OUT] = 0 if errf > band else -1
        if record:
            _record(A.REC, i, 0, e[0], e[1], e[2], e[3], A.QE[i], q0, q1, q2, q3, X[4, l], X[5, l],
                    X[6, l], math.nan, 0.0, ts, x2o, n)
    return all_diag, all_full


@njit(inline="always")
def _lane_step(i, l, k, A, X, T, WS, FS, IS, SS, at, blk):
    """Lane ``l`` (sample ``i``) at step ``k`` of :func:`block_loop`: the metrics of the step
    that ended at ``k`` and the trace row, then (the step functions of :func:`sample_loop`, in
    its order) the estimation, the metrics at the last step, or the control, the thrusters and
    the environment torques into ``T[:, l]``. ``at``: the block's step flags and counters
    (shared by its lanes); ``blk``: the block's constants."""
    post, rec_now, win, need_e, gyro, know, last, ctrl, nwin, nkw, kc, tk = at
    n, n_steps, dt, est_mode, bmask, rec_every, lag, thr, n2orb, d_omega, qf, band, tb_lo, tb_hi = blk
    x2o = n
    so = 9 * n
    q = (X[0, l], X[1, l], X[2, l], X[3, l])
    w = (X[4, l], X[5, l], X[6, l])
    qe = A.QE[i]
    ts = A.TS[i]
    if post:  # (the settling and rate tests do not read the pointing error)
        if outside(q[0], q[1], q[2], q[3], qf[0], qf[1], qf[2], qf[3], band, tb_lo,
                    tb_hi):
            IS[l, _I.LAST_OUT] = k
        wn2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2]
        if wn2 > FS[l, _F.WMAX2]:
            FS[l, _F.WMAX2] = wn2
    if need_e:
        e = qerr(q[0], q[1], q[2], q[3], A.QREF[k, 0], A.QREF[k, 1], A.QREF[k, 2], A.QREF[k, 3])
        FS[l, _F.E] = e[0]
        FS[l, _F.E + 1] = e[1]
        FS[l, _F.E + 2] = e[2]
        FS[l, _F.E + 3] = e[3]
        if win:
            mt = _window((FS[l, _F.MT], FS[l, _F.MT + 1], FS[l, _F.MT + 2],
                          FS[l, _F.MT + 3], FS[l, _F.MT + 4], FS[l, _F.MT + 5], nwin), e)
            FS[l, _F.MT] = mt[0]
            FS[l, _F.MT + 1] = mt[1]
            FS[l, _F.MT + 2] = mt[2]
            FS[l, _F.MT + 3] = mt[3]
            FS[l, _F.MT + 4] = mt[4]
            FS[l, _F.MT + 5] = mt[5]
        if rec_now:
            _record(A.REC, i, k // rec_every, e[0], e[1], e[2], e[3], qe, q[0], q[1], q[2],
                    q[3], w[0], w[1], w[2], FS[l, _F.NEES], FS[l, _F.PROP], ts, x2o, n)
    if est_mode == EST_TRUTH:
        qe[0] = q[0]
        qe[1] = q[1]
        qe[2] = q[2]
        qe[3] = q[3]
        FS[l, _F.WE] = w[0]
        FS[l, _F.WE + 1] = w[1]
        FS[l, _F.WE + 2] = w[2]
    elif gyro:
        est = (qe, A.BE[i], A.PE[i], A.WK[i], A.GY[i], A.BIAS[i], A.SQ[i])
        obs = (A.VB[i], A.VR[i], A.WW[i])
        ws = (WS[0, l], WS[1, l], WS[2, l])
        ec = (FS[l, _F.NEES], FS[l, _F.NEES + 1], IS[l, _I.NEES_N], IS[l, _I.NEES_N + 1],
              IS[l, _I.NEES_N + 2])
        s, we, ec, nobs = _sense_estimate(k, A.C, A.ENV, q, w, SS[l], ws, ec, est, obs)
        if (est_mode == EST_WAHBA or est_mode == EST_MINMAX) and nobs == 2:
            det = (A.VB, A.VR, A.WW, A.WQ, A.WO, A.WC, A.SB[i], A.SR[i], A.SQP[i], A.SBB[i], A.SFF[i], A.SKK[i],
                   A.SAA[i], A.SBK[i], A.RS[i])
            ec = _determine(i, A.C, qe, ec, det)
        SS[l] = s
        FS[l, _F.WE] = we[0]
        FS[l, _F.WE + 1] = we[1]
        FS[l, _F.WE + 2] = we[2]
        FS[l, _F.NEES] = ec[0]
        FS[l, _F.NEES + 1] = ec[1]
        IS[l, _I.NEES_N] = ec[2]
        IS[l, _I.NEES_N + 1] = ec[3]
        IS[l, _I.NEES_N + 2] = ec[4]
        WS[0, l] = 0.0
        WS[1, l] = 0.0
        WS[2, l] = 0.0
    if know:  # knowledge error at t_k, after this epoch's estimation
        kerr = qerr(qe[0], qe[1], qe[2], qe[3], q[0], q[1], q[2], q[3])[3]
        FS[l, _F.KACC2] += kerr * kerr
    if last:
        _finish(A.OUT, i, (FS[l, _F.MT], FS[l, _F.MT + 1], FS[l, _F.MT + 2],
                         FS[l, _F.MT + 3], FS[l, _F.MT + 4], FS[l, _F.MT + 5], nwin),
                IS[l, _I.LAST_OUT], FS[l, _F.WMAX2], FS[l, _F.E + 3], FS[l, _F.KACC2], nkw,
                FS[l, _F.PROP], (FS[l, _F.FIRE], FS[l, _F.FIRE + 1]),
                (FS[l, _F.NEES], FS[l, _F.NEES + 1], IS[l, _I.NEES_N],
                 IS[l, _I.NEES_N + 1], IS[l, _I.NEES_N + 2]), n_steps, dt)
        return
    if ctrl:
        scr = (ts[4 * n:5 * n], ts[5 * n:6 * n], ts[so:so + 9], ts[so + 9:so + 12],
               ts[so + 12:so + 15], ts[so + 15:so + 18])  # F, free, S, r, y, idx
        ctl, fire = _control(
            i, k, A.C, qe, (FS[l, _F.WE], FS[l, _F.WE + 1], FS[l, _F.WE + 2]),
            (FS[l, _F.CTL], FS[l, _F.CTL + 1], FS[l, _F.CTL + 2], FS[l, _F.CTL + 3],
             FS[l, _F.CTL + 4], FS[l, _F.CTL + 5]),
            (FS[l, _F.FIRE], FS[l, _F.FIRE + 1]), thr, scr, ts, A.TOT, n)
        FS[l, _F.CTL] = ctl[0]
        FS[l, _F.CTL + 1] = ctl[1]
        FS[l, _F.CTL + 2] = ctl[2]
        FS[l, _F.CTL + 3] = ctl[3]
        FS[l, _F.CTL + 4] = ctl[4]
        FS[l, _F.CTL + 5] = ctl[5]
        FS[l, _F.FIRE] = fire[0]
        FS[l, _F.FIRE + 1] = fire[1]
    t0, t1, t2, prop = _actuate(i, k, k - kc, IS[l, _I.ND], FS[l, _F.DFRAC], ts, A.BUF[i],
                                bmask, A.FAILED, A.FLEV, A.MDOT, lag, dt, FS[l, _F.PROP], n)
    FS[l, _F.PROP] = prop
    # environment torques (a zero amplitude adds a signed zero: its sine is skipped)
    d0 = FS[l, _F.DIST]
    d1 = FS[l, _F.DIST + 1]
    d2 = FS[l, _F.DIST + 2]
    a0 = FS[l, _F.DIST + 3]
    a1 = FS[l, _F.DIST + 4]
    a2 = FS[l, _F.DIST + 5]
    t0 += d0 + a0 * math.sin(d_omega * tk + FS[l, _F.DIST + 6]) if a0 != 0.0 else d0
    t1 += d1 + a1 * math.sin(d_omega * tk + FS[l, _F.DIST + 7]) if a1 != 0.0 else d1
    t2 += d2 + a2 * math.sin(d_omega * tk + FS[l, _F.DIST + 8]) if a2 != 0.0 else d2
    if n2orb > 0.0:
        c0, c1, c2 = rotate(q[0], q[1], q[2], q[3], A.ENV[k, 0], A.ENV[k, 1], A.ENV[k, 2])
        h0, h1, h2 = _inertia_times(A.P[i, P_J:P_J + 9], IS[l, _I.DIAG] != 0, c0, c1, c2)
        t0 += 3.0 * n2orb * (c1 * h2 - c2 * h1)
        t1 += 3.0 * n2orb * (c2 * h0 - c0 * h2)
        t2 += 3.0 * n2orb * (c0 * h1 - c1 * h0)
    T[0, l] = t0
    T[1, l] = t1
    T[2, l] = t2


def block_loop(i0, size, A, FS, IS, SS):
    """Simulate samples ``i0 .. i0 + nl - 1`` (``nl = min(size, n - i0)``, ``size <= LANES``)
    over all steps: what
    :func:`sample_loop` computes for each of them, bit for bit, with the steps interleaved.

    At each step a pass over the lanes runs each sample's metrics of the previous step and its
    sensors, estimation, control, thrusters and environment torques (the step functions of
    :func:`sample_loop`, in its order for each sample), then :func:`_lanes_rk4` advances every
    lane's rigid body in one vectorised loop when the block's inertias are all diagonal
    (the general step when none is; in a block that mixes the two, each sample's step in
    turn). Between the passes a lane's state lives in arrays:
    on this function's stack (:func:`adcskit._stack.stack_f64`, which is what lets LLVM
    vectorise the RK4 loop) ``X`` (7 x LANES: q, omega), ``T`` (3 x LANES: torque), ``JG`` (18 x
    LANES: J and J^-1 row-major) and ``WS`` (3 x LANES: the gyro's rate sums); in the block's
    scratch (the last arguments, allocated by :func:`run_parallel`) ``FS`` (LANES x N_FS) and
    ``IS`` (LANES x N_IS): the scalar state of :func:`sample_loop` (``_F.*`` / ``_I.*``), and
    ``SS`` (LANES, uint64): the noise state.
    The counters that every sample shares (gyro and command instants, window counts) are the
    block's.
    """
    n = A.POS.shape[0]
    nl = min(size, A.P.shape[0] - i0)
    X = stack_f64(7, LANES)
    T = stack_f64(3, LANES)
    WS = stack_f64(3, LANES)
    JG = stack_f64(18, LANES)
    dt = A.C[DT]
    n_steps = int(A.C[N_STEPS])
    h_ctrl = int(A.C[H_CTRL])
    h_gyro = int(A.C[H_GYRO])
    est_mode = int(A.C[EST_MODE])
    k_win = int(A.C[K_WIN])
    band = A.C[SETTLE_BAND]
    rec_every = int(A.C[REC_EVERY])
    bmask = int(A.C[BUF_MASK])
    record = A.REC.shape[0] > 0
    lag = (A.C[A11], A.C[B1], A.C[A21], A.C[A22], A.C[B2], A.C[V1], A.C[V2], A.C[VU])
    thr = (A.QREF, A.WREF, A.ATAB, A.ANOM, A.FNOM, A.AMASK)
    tb_lo, tb_hi = settle_bounds(band)
    n2orb = A.C[N2ORB]
    d_omega = A.C[D_OMEGA]
    qf = (A.QREF[n_steps, 0], A.QREF[n_steps, 1], A.QREF[n_steps, 2], A.QREF[n_steps, 3])
    blk = (n, n_steps, dt, est_mode, bmask, rec_every, lag, thr, n2orb, d_omega, qf, band, tb_lo, tb_hi)
    all_diag, all_full = _lanes_init(i0, nl, A, X, WS, JG, FS, IS, SS, blk)
    k_gyro = 0  # next gyro epoch
    k_ctrl = 0  # next command instant
    kc = 0
    nkw = 0
    nwin = 0
    for k in range(n_steps + 1):
        last = k == n_steps
        post = k > 0  # the metrics of step k - 1 -> k (sample_loop's kk = k)
        rec_now = post and record and k % rec_every == 0
        win = post and k >= k_win
        if win:
            nwin += 1  # _window's own count (nwin + 1) is not used: every lane shares it
        need_e = win or rec_now or (post and last)  # the pointing error at t_k is used
        gyro = est_mode != EST_TRUTH and k == k_gyro
        if gyro:
            k_gyro += h_gyro
        know = k >= k_win
        if know:
            nkw += 1
        ctrl = not last and k == k_ctrl
        if ctrl:
            k_ctrl += h_ctrl
            kc = k
        tk = k * dt
        at = (post, rec_now, win, need_e, gyro, know, last, ctrl, nwin, nkw, kc, tk)
        for l in range(nl):
            _lane_step(i0 + l, l, k, A, X, T, WS, FS, IS, SS, at, blk)
        if last:
            break
        if all_diag or all_full:
            _lanes_rk4(X, JG, T, WS, nl, dt, all_full)
        else:  # diagonal and full inertias in one block: each lane's own step, not vectorised
            for l in range(nl):
                if IS[l, _I.DIAG] != 0:
                    x = _lane_principal(X, JG, T, l, dt)
                else:  # a call, not a third inlined copy of the step (compile time; rare path)
                    i = i0 + l
                    x = rk4_step(X[0, l], X[1, l], X[2, l], X[3, l], X[4, l], X[5, l], X[6, l],
                                 A.P[i, P_J:P_J + 9], A.P[i, P_JI:P_JI + 9], T[0, l], T[1, l], T[2, l],
                                 dt)
                _lane_store(X, WS, l, x)


def block_size(n, threads):
    """Samples per lane block for ``n`` samples on ``threads`` threads: blocks of at most
    :data:`LANES` (:func:`adcskit._targets.lane_block_size`)."""
    return lane_block_size(n, threads, LANES)


block_loop_jit = njit(cache=True, nogil=True, inline="never", error_model="numpy", _nrt=False)(block_loop)


@njit(parallel=True, cache=True, nogil=True)
def run_parallel(size, A):
    """CPU driver: blocks of up to :data:`LANES` samples in parallel (``prange``), each through
    :func:`block_loop` (what :func:`sample_loop` computes, bit for bit: the GPU driver's
    per-sample function and the reference of tests/simulation/test_lanes.py). ``A``: the
    kernel's arrays (:data:`Arrays`). ``size``: samples per block (:func:`run_cpu` passes
    :func:`block_size` of the sample and thread counts: numba's in-kernel ``get_num_threads``
    is a ctypes function pointer, a dynamic global that would stop numba from caching this
    driver on disk)."""
    n = A.P.shape[0]
    for b in prange((n + size - 1) // size):
        # the block's scratch: a few hundred bytes, once per block of LANES x n_steps
        FS = np.empty((LANES, N_FS))
        IS = np.empty((LANES, N_IS), dtype=np.int64)
        SS = np.empty(LANES, dtype=np.uint64)
        # prange's index is uint64 in the parallel loop but int64 when numba first types this
        # function: the cast makes both the same signature, compiled once (the one that runs)
        block_loop_jit(int64(b) * size, size, A, FS, IS, SS)


def run_cpu(A):
    """CPU driver entry: :func:`run_parallel` over the arrays ``A`` (:data:`Arrays`) with the
    block size for their sample count and numba's thread count (read here, in Python: see
    :func:`run_parallel`)."""
    run_parallel(block_size(A.P.shape[0], numba.get_num_threads()), A)


rpi_allocate_jit = njit(cache=True, nogil=True)(rpi_allocate)
bvls_allocate_jit = njit(cache=True, nogil=True)(bvls_allocate)
rk4_step_jit = njit(cache=True, nogil=True)(rk4_step)
rk4_step_principal_jit = njit(cache=True, nogil=True)(rk4_step_principal)
principal_jit = njit(cache=True, nogil=True)(principal)


# --- CUDA driver -----------------------------------------------------------------------------
# One thread per sample over the same arrays as run_parallel (one Arrays tuple). The scratch
# stays the per-sample rows of global arrays that the CPU driver gets (allocated from ARGS):
# the loop indexes A.BUF[i], A.TS[i], A.PE[i]..., whose lengths depend on the thruster count and the delay
# line (runtime values), so no change to the one source is needed and no kernel is compiled
# per layout; each row is touched by its own thread only.
THREADS_PER_BLOCK = 128
CUDA_CHUNK = 1 << 16  # samples per device round trip (scratch ~ (9 + 2 L) n_thr + 200 floats each)

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
    """numba argument types of the CUDA kernel: one :data:`Arrays` of C-contiguous arrays (as
    :func:`run_cuda` passes), from :data:`ARGS`."""
    from numba import types as t

    dtypes = {"f8": t.float64, "u8": t.uint64}
    return (t.NamedTuple(tuple(t.Array(dtypes[a.dtype], a.ndim, "C") for a in ARGS), Arrays),)


def run_cuda(A, chunk=None):
    """GPU driver: the same per-sample function as :func:`run_parallel` (the same arrays ``A``,
    host arrays), one CUDA thread per sample.

    Samples go to the device in chunks of ``chunk`` rows (default :data:`CUDA_CHUNK`, read at
    call time); the arrays without a row per sample (:attr:`Arg.rows`) are copied once.
    ``OUT``, ``TOT`` and (when recording) ``REC`` are filled in place; the scratch arrays are
    not copied back.
    """
    if not isinstance(A, Arrays):
        raise TypeError(f"run_cuda takes an Arrays tuple; got {type(A).__name__}")
    if chunk is None:
        chunk = CUDA_CHUNK
    kernel = CUDA_KERNELS.get()  # binds the module global ``cuda``
    record = A.REC.shape[0] > 0
    shared = {a.name for a in ARGS if not a.rows or (a.name == "REC" and not record)}
    outputs = tuple(a.name for a in ARGS if a.role == "out" and a.name not in shared)
    launch_chunked(kernel, A._asdict(), Arrays._fields, n=A.P.shape[0], chunk=chunk,
                   threads=THREADS_PER_BLOCK, shared=shared, outputs=outputs, pack=Arrays)
