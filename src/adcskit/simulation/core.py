"""The closed-loop simulator: scenario -> batched numba kernel -> metrics and traces.

:func:`simulate` draws the Monte-Carlo dispersions (:mod:`adcskit.uncertainty`), one 64-bit
noise seed per sample, precomputes everything the samples share (orbit, sun, eclipse,
magnetic reference along the orbit; the guidance table; the allocation table), splits the
samples into chunks and runs them on an executor through
:func:`adcskit.uncertainty.run_campaign` (resumable with ``directory``). A sample's result
depends only on its parameters and seed, so every executor and chunking gives bit-identical
results for the same ``rng``.

Hand-written here: the loop kernel (:mod:`adcskit.simulation._kernels`); no kept library
simulates a thruster-controlled closed loop with an estimator across thousands of samples
in compiled code (Basilisk runs one sample per process, in C/C++ modules called from
Python each step).

References
----------
Markley F. L., Crassidis J. L. (2014), ch. 3 (dynamics), ch. 6 (MEKF); S3 eq. 5-7, 12;
S4 Fig. 1, Table 3.
"""

from __future__ import annotations

import functools
import math
import time
import warnings
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import scipy.linalg
from scipy.spatial.transform import Rotation, Slerp

from adcskit._jit import CLOSED_LOOP_NOTICE, will_compile
from adcskit._progress import auto_session, progress_flag, status
from adcskit._targets import TARGET_BACKENDS, resolve_backend
from adcskit._validation import as_rng, check_flag, check_int
from adcskit.attitude._kernels import quat_multiply as _quat_multiply
from adcskit.constants import RAD_PER_DEG
from adcskit.determination.wahba import METHODS as _WAHBA_METHODS
from adcskit.errors import InputError, InputTypeError, UncontrollableWarning
from adcskit.simulation import _kernels as _k
from adcskit.simulation.scenario import Scenario, _triangle_ok
from adcskit.thrusters.reference import S3_REFERENCE_A  # re-exported (S3 §6 reference layout)

__all__ = [
    "SimulationResult",
    "simulate",
    "METRIC_NAMES",
    "TRACE_CHANNELS",
    "S3_REFERENCE_A",
    "WAHBA_CODES",
    "reference_profile",
]

#: Per-sample metrics: name -> (kernel slot, factor from the kernel's SI value). Angles are in
#: degrees like the scenario's inputs (names end ``_deg``), times in s, propellant in kg.
_METRICS: dict[str, tuple[int, float]] = {
    "pointing_mean_deg": (_k.M_MEAN_ERR, 1.0 / RAD_PER_DEG),
    "pointing_rms_deg": (_k.M_RMS_ERR, 1.0 / RAD_PER_DEG),
    "pointing_max_deg": (_k.M_MAX_ERR, 1.0 / RAD_PER_DEG),
    "pointing_rms_x_deg": (_k.M_RMS_X, 1.0 / RAD_PER_DEG),
    "pointing_rms_y_deg": (_k.M_RMS_Y, 1.0 / RAD_PER_DEG),
    "pointing_rms_z_deg": (_k.M_RMS_Z, 1.0 / RAD_PER_DEG),
    "settling_time_s": (_k.M_SETTLE, 1.0),
    "final_error_deg": (_k.M_FINAL_ERR, 1.0 / RAD_PER_DEG),
    "propellant_kg": (_k.M_PROP, 1.0),
    "firings": (_k.M_FIRINGS, 1.0),
    "on_time_s": (_k.M_ONTIME, 1.0),
    "knowledge_rms_deg": (_k.M_KNOW_RMS, 1.0 / RAD_PER_DEG),
    "nees_mean": (_k.M_NEES, 1.0),
    "nees_count": (_k.M_NEES_N, 1.0),
    "max_rate_deg_s": (_k.M_MAX_RATE, 1.0 / RAD_PER_DEG),
    "box_active_fraction": (_k.M_BOX_ACTIVE, 1.0),
}
#: Names of the per-sample metrics of :class:`SimulationResult` (units in the names).
METRIC_NAMES: tuple[str, ...] = tuple(_METRICS)
#: Wahba methods usable in the loop -> kernel code.
WAHBA_CODES: dict[str, int] = {name: int(v[0]) for name, v in _WAHBA_METHODS.items()}

_ARCSEC = RAD_PER_DEG / 3600.0
_MU = 3.986004418e14
_RE = 6378137.0


def _trace_channels(n: int) -> tuple[str, ...]:
    return ("err_x", "err_y", "err_z", "pointing_error", "knowledge_error", "omega_x", "omega_y",
            "omega_z", "nees", "propellant") + tuple(f"thrust_{j}" for j in range(n))


TRACE_CHANNELS = _trace_channels(0)


@dataclass(frozen=True, slots=True, kw_only=True)
class SimulationResult:
    """Outcome of :func:`simulate`.

    Attributes
    ----------
    metrics : dict of str to ndarray (N,)
        Per-sample metrics (:data:`METRIC_NAMES`; each name carries its unit, angles in
        degrees like the scenario's inputs): pointing error to the reference over the
        metrics window, ``pointing_mean_deg`` / ``pointing_rms_deg`` / ``pointing_max_deg``
        and per-axis ``pointing_rms_x_deg`` (y, z); ``settling_time_s`` (NaN = not settled
        by the end; 0 = never outside the band); ``final_error_deg``; ``propellant_kg``
        (each thruster's delivered impulse times its mass flow, which scales with the
        sample's dispersed thrust at constant specific impulse); ``firings`` (pulses);
        ``on_time_s`` (commanded, all thrusters); ``knowledge_rms_deg`` (estimate vs truth
        over the window); ``nees_mean`` (MEKF NEES averaged over its epochs; NaN without
        MEKF); ``nees_count``; ``max_rate_deg_s``; ``box_active_fraction`` (``minmax``
        estimator: fraction of its determination epochs at which the search box was active,
        i.e. the answer differs from the q-method of the same midpoints; NaN otherwise).
    controllable : ndarray (N,) bool
        Whether the sample's thrusters (failed ones removed, each with its dispersed
        direction and thrust) can produce torque in every direction (their torques
        positively span R^3, the test of :func:`adcskit.thrusters.check_controllability`)
        with a torque authority in the weakest direction, ``parameters["torque_authority"]``
        (N m), of at least ``thrusters.min_authority_fraction`` (default 0.05) of the intact
        nominal layout's. Checked before the run; uncontrollable samples are still
        simulated, with an :class:`adcskit.errors.UncontrollableWarning` and
        ``success=False``. A layout that is uncontrollable without dispersions gives both
        even if some misaligned samples span every direction (with a tiny authority).
    on_time_per_thruster : ndarray (N, n), s
        Commanded on-time of each thruster.
    t : ndarray (R,) or None, s
        Trace times (``record=True``).
    trace : ndarray (N, R, C) or None
        Time histories, channels :attr:`channels` (SI: errors in rad, rates in rad/s,
        propellant in kg, thrust as a fraction of ``f_max``).
    channels : tuple of str
    parameters : dict of str to ndarray
        The dispersed parameters of every sample (inertia, thrust levels, delay, ...);
        ``inertia_physical`` (bool) flags the samples whose dispersed principal moments
        satisfy the triangle inequality (see :class:`~adcskit.simulation.DispersionSpec`);
        ``mass_flow`` (kg/s per thruster) scales with the dispersed ``thrust``;
        ``torque_authority`` (N m) is the torque available in every direction.
    seeds : ndarray (N,) uint64
        Per-sample noise seeds.
    n_samples, n_steps : int
    sample_steps_per_s : float
        ``n_samples * n_steps / wall time`` of the kernel runs (excludes set-up).
    runtime_s : float
        Wall time of the whole call.
    n_chunks, n_resumed : int
        Campaign bookkeeping (chunks resumed from ``directory``).
    executor : str
    success : bool
        The layout and every sample controllable, and every metric finite where it must be
        (pointing error, propellant).
    message : str
    backend : {"cpu", "cuda"}
        The target that ran the samples.

    Examples
    --------
    >>> from adcskit.simulation import Scenario, SimSpec, simulate
    >>> res = simulate(Scenario(sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0)), n_samples=4, rng=1)
    >>> res.success, res.n_samples, res.metrics["pointing_rms_deg"].shape, bool(res.controllable.all())
    (True, 4, (4,), True)
    """

    metrics: dict[str, np.ndarray]
    controllable: np.ndarray
    on_time_per_thruster: np.ndarray
    t: np.ndarray | None
    trace: np.ndarray | None
    channels: tuple[str, ...]
    parameters: dict[str, np.ndarray]
    seeds: np.ndarray
    n_samples: int
    n_steps: int
    sample_steps_per_s: float
    runtime_s: float
    n_chunks: int
    n_resumed: int
    executor: str
    success: bool
    message: str
    backend: str = "cpu"

    def summary(self) -> dict[str, dict[str, float]]:
        """Mean, std, 5/50/95 % quantiles and NaN count of every metric."""
        out: dict[str, dict[str, float]] = {}
        for name, v in self.metrics.items():
            f = v[np.isfinite(v)]
            out[name] = {
                "mean": float(np.mean(f)) if f.size else math.nan,
                "std": float(np.std(f, ddof=1)) if f.size > 1 else math.nan,
                "p05": float(np.quantile(f, 0.05)) if f.size else math.nan,
                "p50": float(np.quantile(f, 0.5)) if f.size else math.nan,
                "p95": float(np.quantile(f, 0.95)) if f.size else math.nan,
                "n_nan": int(v.size - f.size),
            }
        return out

    def to_dict(self) -> dict[str, Any]:
        return {
            "summary": self.summary(),
            "controllable_fraction": float(np.mean(self.controllable)) if self.controllable.size else math.nan,
            "n_samples": self.n_samples,
            "n_steps": self.n_steps,
            "sample_steps_per_s": self.sample_steps_per_s,
            "runtime_s": self.runtime_s,
            "n_chunks": self.n_chunks,
            "n_resumed": self.n_resumed,
            "executor": self.executor,
            "success": self.success,
            "message": self.message,
        }


# ------------------------------------------------------------------------- preparation


@functools.lru_cache(maxsize=64, typed=True)
def _lag_coefficients(tau: float, dt: float) -> np.ndarray:
    # cached (read-only result, copied into the coefficient vector): a 4x4 expm per simulate
    # call, ~5 ms, for the few (tau, dt) pairs of a study (profile of closed-loop, issue 24)
    # states [x1, x2, v, u]: x1' = (u - x1)/tau, x2' = (x1 - x2)/tau, v' = x2, u' = 0 (held)
    m = np.zeros((4, 4))
    m[0, 0] = -1.0 / tau
    m[0, 3] = 1.0 / tau
    m[1, 0] = 1.0 / tau
    m[1, 1] = -1.0 / tau
    m[2, 1] = 1.0
    phi = scipy.linalg.expm(m * dt)
    out = np.array([phi[0, 0], phi[0, 3], phi[1, 0], phi[1, 1], phi[1, 3], phi[2, 0], phi[2, 1], phi[2, 3]])
    out.setflags(write=False)
    return out


def _rotvec_quat(rv: np.ndarray) -> np.ndarray:
    """Quaternion (scalar last) ``[sin(a/2) e, cos(a/2)]`` of rotation vectors (..., 3)."""
    rv = np.asarray(rv, dtype=float)
    a = np.linalg.norm(rv, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(a > 1e-12, np.sin(a / 2) / np.where(a > 0, a, 1.0), 0.5)
    return np.concatenate([s * rv, np.cos(a / 2)], axis=-1)


def _qmul(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Markley's product ``p (x) q`` (``A(p (x) q) = A(p) A(q)``), batched, sign ``q4 >= 0``.

    The product is the attitude algebra's (:func:`adcskit.attitude._kernels.quat_multiply`, no
    normalisation); only the sign flip is added here.
    """
    out = _quat_multiply(p, q)
    return out * np.where(out[..., 3:] < 0, -1.0, 1.0)


def reference_profile(scenario: Scenario) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Reference attitude and rate on the simulation grid.

    Returns
    -------
    t : ndarray (K+1,), s
    q_ref : ndarray (K+1, 4)
        Reference quaternions (scalar last, ECI -> reference body).
    w_ref : ndarray (K+1, 3), rad/s
        Reference body rates.

    Examples
    --------
    >>> from adcskit.simulation import Scenario, SimSpec, reference_profile
    >>> t, q, w = reference_profile(Scenario(sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0)))
    >>> t.shape, q.shape, w.shape
    ((101,), (101, 4), (101, 3))
    """
    if not isinstance(scenario, Scenario):
        raise InputTypeError(f"scenario must be a Scenario; got {type(scenario).__name__}")
    g = scenario.guidance
    n_steps = int(round(scenario.sim.t_final / scenario.sim.dt))
    t = np.arange(n_steps + 1) * scenario.sim.dt
    q = np.zeros((n_steps + 1, 4))
    q[:, 3] = 1.0
    w = np.zeros((n_steps + 1, 3))
    if g.kind == "step":
        qt = _rotvec_quat(np.asarray(g.target_rotvec_deg) * RAD_PER_DEG)
        q[t >= g.t_step] = qt
    elif g.kind == "table":
        tt = np.asarray(g.table_t, float)
        qq = np.asarray(g.table_q, float)
        qq = qq / np.linalg.norm(qq, axis=1, keepdims=True)
        # scipy's from_quat(q) has matrix A(q)^T: interpolate the inverse rotations consistently
        rots = Rotation.from_quat(qq)
        tc = np.clip(t, tt[0], tt[-1])
        qi = Slerp(tt, rots)(tc).as_quat()
        qi *= np.where(qi[:, 3:] < 0, -1.0, 1.0)
        q = qi
        if len(g.table_w):
            ww = np.asarray(g.table_w, float)
            w = np.stack([np.interp(t, tt, ww[:, j], left=0.0, right=0.0) for j in range(3)], axis=1)
            w[(t < tt[0]) | (t > tt[-1])] = 0.0
        else:
            for a in range(len(tt) - 1):
                m = (t >= tt[a]) & (t < tt[a + 1])
                d = _qmul(qq[a + 1], qq[a] * np.array([-1, -1, -1, 1.0]))
                ang = 2 * np.arctan2(np.linalg.norm(d[:3]), d[3])
                nv = np.linalg.norm(d[:3])
                axis = d[:3] / nv if nv > 0 else np.zeros(3)
                w[m] = axis * ang / (tt[a + 1] - tt[a])
    return t, q, w


#: Environment tables up to this many floats (16 MB) are kept for the next call (below).
_ENV_CACHE_MAX_FLOATS = 2_000_000


def _environment(scenario: Scenario, n_steps: int, h_env: int) -> tuple[np.ndarray, float, float]:
    """ENV (K+1, 10) = [r_hat (3), sun (3), mag_hat (3), lit], n^2 (1/s^2), orbit rate.

    A function of the orbit, the step, the duration and the sampling only: a study simulates
    many configurations of one orbit (closed-loop Q1: 40 calls, one table), so tables of up to
    :data:`_ENV_CACHE_MAX_FLOATS` are kept (the last 8) and each call gets a fresh, writable
    copy of the same numbers.
    """
    key = (scenario.orbit, scenario.sim.dt, int(n_steps), int(h_env))
    if (n_steps + 1) * 10 > _ENV_CACHE_MAX_FLOATS:
        return _environment_table(*key)
    env, n2, n_orb = _environment_cached(*key)
    return env.copy(), n2, n_orb


@functools.lru_cache(maxsize=8, typed=True)
def _environment_cached(o: Any, dt: float, n_steps: int, h_env: int) -> tuple[np.ndarray, float, float]:
    env, n2, n_orb = _environment_table(o, dt, n_steps, h_env)
    env.setflags(write=False)
    return env, n2, n_orb


def _environment_table(o: Any, dt: float, n_steps: int, h_env: int) -> tuple[np.ndarray, float, float]:
    from adcskit.environment import circular_orbit, in_shadow, magnetic_field, sun_direction

    t = np.arange(n_steps + 1) * dt
    alt = o.altitude_km * 1e3
    st = circular_orbit(alt, o.inclination_deg * RAD_PER_DEG, o.raan_deg * RAD_PER_DEG, o.arg_lat0_deg * RAD_PER_DEG, t,
                        epoch=np.datetime64(o.epoch))
    r = np.asarray(st.r)
    env = np.zeros((n_steps + 1, 10))
    env[:, 0:3] = r / np.linalg.norm(r, axis=1, keepdims=True)
    idx = np.unique(np.r_[np.arange(0, n_steps + 1, max(1, h_env)), n_steps])
    times = st.times
    sun = sun_direction(times[idx])
    lit = ~np.asarray(in_shadow(r[idx], times[idx]), dtype=bool)
    mag = np.asarray(magnetic_field(r[idx], times[idx], model=o.magnetic_model))
    mag = mag / np.linalg.norm(mag, axis=1, keepdims=True)
    for j in range(3):
        env[:, 3 + j] = np.interp(t, t[idx], sun[:, j])
        env[:, 6 + j] = np.interp(t, t[idx], mag[:, j])
    env[:, 3:6] /= np.linalg.norm(env[:, 3:6], axis=1, keepdims=True)
    env[:, 6:9] /= np.linalg.norm(env[:, 6:9], axis=1, keepdims=True)
    env[:, 9] = np.interp(t, t[idx], lit.astype(float)) > 0.5
    rad = _RE + alt
    n_orb = math.sqrt(_MU / rad**3)
    return env, n_orb * n_orb, n_orb


def _allocation_table(scenario: Scenario, A: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Forces (27, n) for the Schmitt demands ``T * (sx, sy, sz)``, row ``9(sx+1)+3(sy+1)+(sz+1)``.

    Kept for the next call with the same layout, mask, levels and method (27 LPs with
    ``lp-min-fuel``, ~0.15 s; closed-loop Q1 repeats the reference layout's tables every seed);
    each call gets a fresh copy of the same numbers.
    """
    c = scenario.controller
    A = np.ascontiguousarray(A, dtype=float)
    mask = np.ascontiguousarray(mask, dtype=float)
    table = _allocation_table_cached(A.shape, A.tobytes(), mask.tobytes(), tuple(map(float, c.torque_level)),
                                     c.allocation, float(scenario.thrusters.f_max))
    return table.copy()


@functools.lru_cache(maxsize=32)
def _allocation_table_cached(shape: tuple[int, int], a_bytes: bytes, mask_bytes: bytes,
                             torque_level: tuple[float, ...], allocation: str, f_max: float) -> np.ndarray:
    from adcskit.thrusters import allocate

    A = np.frombuffer(a_bytes, dtype=float).reshape(shape)
    mask = np.frombuffer(mask_bytes, dtype=float)
    n = A.shape[1]
    levels = np.array([-1.0, 0.0, 1.0])
    D = np.array([[sx, sy, sz] for sx in levels for sy in levels for sz in levels]) * np.asarray(torque_level)
    table = np.zeros((27, n))
    cols = np.flatnonzero(mask > 0)
    if cols.size:
        res = allocate(A[:, cols], D, method=allocation, f_max=f_max)
        table[:, cols] = res.x
    table.setflags(write=False)
    return table


def _draw(scenario: Scenario, n: int, gen: np.random.Generator) -> dict[str, np.ndarray]:
    """Per-sample dispersed parameters through :mod:`adcskit.uncertainty`."""
    from adcskit.uncertainty import Gaussian, TruncatedGaussian, latin_hypercube

    d = scenario.dispersions
    nt = scenario.thrusters.n
    dists: dict[str, Any] = {}
    for a in range(3):
        dists[f"inertia_{a}"] = TruncatedGaussian(mean=1.0, std=d.inertia_rel, low=0.1, high=1.9)
    for j in range(nt):
        dists[f"thrust_{j}"] = TruncatedGaussian(mean=1.0, std=d.thrust_rel, low=0.0, high=2.0)
        for a in range(3):
            dists[f"mis_{j}_{a}"] = Gaussian(mean=0.0, std=d.misalignment_deg * RAD_PER_DEG)
    dists["delay"] = TruncatedGaussian(mean=scenario.thrusters.delay, std=d.delay_std_s, low=0.0,
                                       high=scenario.thrusters.delay + 10 * max(d.delay_std_s, 1e-12))
    dists["disturbance"] = TruncatedGaussian(mean=1.0, std=d.disturbance_rel, low=0.0, high=3.0)
    sens = scenario.sensors
    for a in range(3):
        dists[f"att_{a}"] = Gaussian(mean=0.0, std=d.initial_attitude_deg * RAD_PER_DEG)
        dists[f"rate_{a}"] = Gaussian(mean=scenario.initial_rate_deg_s[a] * RAD_PER_DEG, std=d.initial_rate_deg_s * RAD_PER_DEG)
        dists[f"bias_{a}"] = Gaussian(mean=0.0, std=sens.gyro_bias0_deg_h * RAD_PER_DEG / 3600.0)
        dists[f"kerr_{a}"] = Gaussian(mean=0.0, std=scenario.estimator.init_error_deg * RAD_PER_DEG)
    if d.sampling == "lhs":
        draws = latin_hypercube(dists, n, gen)
    else:
        from scipy.stats import qmc  # noqa: F401 (same ppf path as the LHS)

        u = gen.random((n, len(dists)))
        u = np.clip(u, 1e-12, 1 - 1e-12)
        draws = {k: np.asarray(v.ppf(u[:, j]), float) for j, (k, v) in enumerate(dists.items())}
    return draws


def _torque_authority(A: np.ndarray) -> np.ndarray:
    """Torque available in every direction: the radius of the largest ball about 0 inside the
    attainable set ``{A F : 0 <= F_j <= 1}`` of each sample, ``A`` (n, 3, k) in N m per unit
    command (columns ``F_max,j (r_j - com) x d_j``).

    The attainable set is a zonotope; every facet normal of a zonotope in R^3 is the cross
    product of two of its generators, and ``h(u) = sum_j max(0, u . a_j)`` is its support
    function, so the radius is ``min h(u)`` over the unit cross products ``+-(a_i x a_j)``
    (further normals only raise the minimum: ``h(u) >= r`` for every unit ``u``). It is > 0
    iff the columns positively span R^3 (Davis 1954), the test of
    :func:`adcskit.thrusters.check_controllability`.
    """
    n, _, k = A.shape
    out = np.zeros(n)
    if k < 2 or n == 0:
        return out
    ii, jj = np.triu_indices(k, 1)
    for lo in range(0, n, 128):  # chunks: (m, k(k-1)/2, k) temporaries
        a = A[lo:lo + 128]
        N = np.cross(a[:, :, ii], a[:, :, jj], axis=1)  # (m, 3, p)
        nrm = np.linalg.norm(N, axis=1)
        big = np.max(np.linalg.norm(a, axis=1), axis=1)  # largest column norm per sample
        ok = nrm > 1e-12 * (big * big)[:, None]
        U = N / np.where(ok, nrm, 1.0)[:, None, :]
        d = np.einsum("map,mak->mpk", U, a)
        h = np.minimum(np.maximum(d, 0.0).sum(axis=2), np.maximum(-d, 0.0).sum(axis=2))
        r = np.where(ok, h, np.inf).min(axis=1)
        out[lo:lo + 128] = np.where(np.isfinite(r), r, 0.0)  # all columns parallel: rank 1
    return out


def _controllability(scenario: Scenario, dirs: np.ndarray, flev: np.ndarray) -> dict[str, Any]:
    """Per-sample feasibility of the working thrusters, before the flight.

    A sample's torque columns are ``F_j (r_j - com) x d_j`` of its non-failed thrusters, with
    its dispersed directions ``d_j`` and thrust levels ``F_j`` (N). ``authority`` (N m) is the
    torque it can produce in *every* direction (:func:`_torque_authority`); the sample is
    controllable iff that is > 1e-9 of its largest column (positive span) and at least
    ``thrusters.min_authority_fraction`` of ``intact``, the authority of the nominal layout
    with every thruster (no failure, no dispersion). The nominal layout (failed thrusters
    removed, no dispersion) and the first uncontrollable sample also get
    :func:`adcskit.thrusters.check_controllability`, whose message names the unreachable
    direction.
    """
    from adcskit.thrusters import check_controllability

    th = scenario.thrusters
    n, nt = flev.shape
    pos = np.asarray(th.positions) - np.asarray(th.com)
    work = np.ones(nt, bool)
    work[list(th.failed)] = False
    cols = np.flatnonzero(work)
    A0 = np.cross(pos, np.asarray(th.directions)).T[:, cols] * th.f_max
    nominal = check_controllability(A0) if cols.size else None
    A = np.swapaxes(np.cross(pos[None], dirs), 1, 2)[:, :, cols] * flev[:, None, cols]  # (n, 3, k), N m
    auth = _torque_authority(A)
    A1 = np.cross(pos, np.asarray(th.directions)).T * th.f_max  # every thruster, no dispersion
    intact = float(_torque_authority(A1[None])[0])
    if not intact > 1e-9 * float(np.max(np.linalg.norm(A1, axis=0))):
        intact = 0.0  # no positive span even intact (rounding-level in-radius): the fraction asks nothing
    big = np.max(np.linalg.norm(A, axis=1), axis=1) if cols.size else np.zeros(n)
    span = auth > 1e-9 * big
    ok = span & (auth >= th.min_authority_fraction * intact)
    first_bad = None
    bad = np.flatnonzero(~span)
    if bad.size and cols.size:
        first_bad = check_controllability(A[bad[0]])
    return {"controllable": ok, "span": span, "authority": auth, "intact": intact, "nominal": nominal,
            "first_bad": first_bad}


def _controllability_message(scenario: Scenario, feas: dict[str, Any]) -> str:
    """Why a scenario fails the feasibility test (empty when it passes)."""
    th = scenario.thrusters
    ok, nominal, auth = feas["controllable"], feas["nominal"], feas["authority"]
    failed = f" with thruster(s) {list(th.failed)} failed" if th.failed else ""
    if nominal is None:
        return f"the layout has no working thruster{failed}: no torque can be produced"
    span, intact, frac = feas["span"], feas["intact"], th.min_authority_fraction
    n_ok, n_span = int(np.count_nonzero(ok)), int(np.count_nonzero(span))
    weak = span & ~ok  # positive span, but below the stated fraction of the intact layout's authority
    rule = (f"below min_authority_fraction = {frac:g} of the intact layout's {intact:.3g} N m, so counted "
            "uncontrollable")
    if not nominal.success:
        if n_span == 0:
            tail = "no sample can produce torque in every direction"
        else:
            top = float(np.max(auth[span]))
            pct = f" ({100 * top / intact:.2g} % of the intact layout's)" if intact > 0 else ""
            tail = (f"{n_span} of {ok.size} dispersed samples span every direction only through their misalignment, "
                    f"with at most {top:.3g} N m{pct} in their weakest direction"
                    + (f", {rule}" if n_ok == 0 else f"; {n_ok} of them reach min_authority_fraction = {frac:g}"))
        return f"the thruster layout{failed} cannot produce torque in every direction: {nominal.message}; {tail}"
    if n_ok == ok.size:
        return ""
    parts = []
    if n_span < ok.size:
        why = f" (first such sample: {feas['first_bad'].message})" if feas["first_bad"] is not None else ""
        parts.append(f"{ok.size - n_span} of {ok.size} samples cannot produce torque in every direction with their "
                     f"dispersed thrusters{failed} (misalignment or zero thrust){why}")
    if np.any(weak):
        parts.append(f"{int(np.count_nonzero(weak))} of {ok.size} samples have at most "
                     f"{float(np.max(auth[weak])):.3g} N m in their weakest direction with their dispersed "
                     f"thrusters{failed}, {rule}")
    return "; ".join(parts)


def _prepare(scenario: Scenario, n: int, gen: np.random.Generator) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    sc = scenario
    dt = sc.sim.dt
    n_steps = int(round(sc.sim.t_final / dt))
    th = sc.thrusters
    nt = th.n
    hc = int(round(sc.controller.period_s / dt))
    hg = int(round(1.0 / (sc.sensors.gyro_rate_hz * dt)))

    def hrate(rate: float) -> int:
        return 0 if rate <= 0 else int(round(1.0 / (rate * dt)))

    hs = hrate(sc.sensors.sun_rate_hz)
    hm = hrate(sc.sensors.mag_rate_hz)
    hst = hrate(sc.sensors.star_tracker_rate_hz)
    h_env = min([h for h in (hs, hm, hg) if h > 0])
    env, n2, n_orb = _environment(sc, n_steps, h_env)
    _, qref, wref = reference_profile(sc)
    draws = _draw(sc, n, gen)
    # --- per-sample parameters
    J0 = sc.spacecraft.matrix()
    scale = np.stack([draws[f"inertia_{a}"] for a in range(3)], axis=1)  # (n, 3)
    if np.count_nonzero(J0 - np.diag(np.diag(J0))) == 0:
        # diagonal: body axes are principal axes; s_a scales the moment about body axis a
        lam0, V = np.diag(J0).copy(), np.eye(3)
    else:
        lam0, V = np.linalg.eigh(J0)  # J0 = V diag(lam0) V^T
    lam = lam0[None] * scale  # dispersed principal moments (n, 3), > 0 (scale >= 0.1)
    J = np.einsum("ab,sb,cb->sac", V, lam, V)
    J = 0.5 * (J + np.swapaxes(J, 1, 2))
    P = np.zeros((n, _k.N_PARAMS))
    P[:, _k.P_J:_k.P_J + 9] = J.reshape(n, 9)
    P[:, _k.P_JI:_k.P_JI + 9] = np.linalg.inv(J).reshape(n, 9)
    att = np.stack([draws[f"att_{a}"] for a in range(3)], axis=1)
    q0 = _qmul(_rotvec_quat(att), np.broadcast_to(_rotvec_quat(np.asarray(sc.initial_rotvec_deg) * RAD_PER_DEG), (n, 4)))
    P[:, _k.P_Q0:_k.P_Q0 + 4] = q0
    P[:, _k.P_W0:_k.P_W0 + 3] = np.stack([draws[f"rate_{a}"] for a in range(3)], axis=1)
    P[:, _k.P_DELAY] = draws["delay"]
    dsc = draws["disturbance"][:, None]
    P[:, _k.P_D0:_k.P_D0 + 3] = np.asarray(sc.disturbance.constant)[None] * dsc
    P[:, _k.P_DAMP:_k.P_DAMP + 3] = np.asarray(sc.disturbance.amplitude)[None] * dsc
    P[:, _k.P_DPH:_k.P_DPH + 3] = np.asarray(sc.disturbance.phase_deg)[None] * RAD_PER_DEG
    P[:, _k.P_BIAS:_k.P_BIAS + 3] = np.stack([draws[f"bias_{a}"] for a in range(3)], axis=1)
    kerr = np.stack([draws[f"kerr_{a}"] for a in range(3)], axis=1)
    P[:, _k.P_QE0:_k.P_QE0 + 4] = _qmul(_rotvec_quat(kerr), q0)
    P[:, _k.P_SIGA0] = max(sc.estimator.init_error_deg * RAD_PER_DEG, 1e-9)
    P[:, _k.P_SIGB0] = max(sc.sensors.gyro_bias0_deg_h * RAD_PER_DEG / 3600.0, 1e-12)
    # thrusters: dispersed directions and force levels
    dirs0 = np.asarray(th.directions)
    mis = np.stack([np.stack([draws[f"mis_{j}_{a}"] for a in range(3)], axis=1) for j in range(nt)], axis=1)
    R = Rotation.from_rotvec(mis.reshape(-1, 3)).as_matrix().reshape(n, nt, 3, 3)
    dirs = np.einsum("sjab,jb->sja", R, dirs0)
    flev = th.f_max * np.stack([draws[f"thrust_{j}"] for j in range(nt)], axis=1)
    pos = np.asarray(th.positions) - np.asarray(th.com)
    failed = np.zeros(nt)
    failed[list(th.failed)] = 1.0
    # mass flow at constant specific impulse: proportional to the sample's thrust
    mdot = th.mdot * flev / th.f_max
    amask = np.ones(nt)
    if th.failure_known:
        amask[list(th.failed)] = 0.0
    A_nom = np.cross(pos, dirs0).T.copy()
    if sc.controller.kind == "schmitt":
        atab = _allocation_table(sc, A_nom, amask)
    elif sc.controller.kind == "open-loop":
        atab = np.ascontiguousarray(np.asarray(sc.controller.on_times, dtype=float))
    else:
        atab = np.zeros((27, nt))
    # --- shared coefficients
    C = np.zeros(_k.N_COEFS)
    C[_k.DT] = dt
    C[_k.N_STEPS] = n_steps
    C[_k.H_CTRL] = hc
    C[_k.H_GYRO] = hg
    C[_k.H_SUN] = hs
    C[_k.H_MAG] = hm
    C[_k.H_ST] = hst
    C[_k.A11:_k.VU + 1] = _lag_coefficients(th.tau, dt)
    C[_k.N2ORB] = n2 if sc.orbit.gravity_gradient else 0.0
    per = sc.disturbance.period_s if sc.disturbance.period_s > 0 else 2 * math.pi / n_orb
    C[_k.D_OMEGA] = 2 * math.pi / per
    s_sun = sc.sensors.sun_noise_deg * RAD_PER_DEG
    s_mag = sc.sensors.mag_noise_deg * RAD_PER_DEG
    C[_k.SIG_SUN] = s_sun
    C[_k.SIG_MAG] = s_mag
    C[_k.SIG_ST] = sc.sensors.star_tracker_noise_arcsec * _ARCSEC
    uni = sc.sensors.noise == "uniform"
    C[_k.NOISE_UNIFORM] = 1.0 if uni else 0.0
    fil = 1.0 / math.sqrt(3.0) if uni else 1.0
    if sc.estimator.weights == "equal":
        C[_k.W_SUN] = C[_k.W_MAG] = 1.0
    else:
        C[_k.W_SUN] = 1.0 / max(s_sun * fil, 1e-12) ** 2
        C[_k.W_MAG] = 1.0 / max(s_mag * fil, 1e-12) ** 2
    C[_k.SIG_V] = sc.sensors.gyro_arw
    C[_k.SIG_U] = sc.sensors.gyro_rrw
    C[_k.UNDERWEIGHT] = sc.estimator.underweight
    C[_k.EST_MODE] = {"truth": _k.EST_TRUTH, "wahba": _k.EST_WAHBA, "minmax": _k.EST_MINMAX,
                      "mekf": _k.EST_MEKF}[sc.estimator.kind]
    C[_k.SEARCH_RANGE] = sc.estimator.search_range
    C[_k.WAHBA_METHOD] = WAHBA_CODES[sc.estimator.wahba_method]
    c = sc.controller
    C[_k.CTRL_MODE] = {"schmitt": _k.CTRL_SCHMITT, "pwm": _k.CTRL_PWM, "open-loop": _k.CTRL_OPEN}[c.kind]
    C[_k.U_ON] = c.u_on
    C[_k.U_OFF] = c.u_on * c.off_ratio
    C[_k.T_S] = c.period_s
    C[_k.T_MIN] = th.t_min
    C[_k.PULSE_ROUND] = 1.0 if c.min_on_time == "round" else 0.0
    C[_k.KP0:_k.KP2 + 1] = c.kp
    C[_k.KI0:_k.KI2 + 1] = c.ki
    C[_k.KD0:_k.KD2 + 1] = c.kd
    C[_k.TL0:_k.TL2 + 1] = (1.0, 1.0, 1.0) if c.kind == "pwm" else c.torque_level
    C[_k.K_WIN] = int(math.ceil(sc.sim.metrics_from_s / dt - 1e-9))
    C[_k.SETTLE_BAND] = sc.sim.settle_band_deg * RAD_PER_DEG
    C[_k.REC_EVERY] = sc.sim.record_every
    C[_k.K_NEES] = int(math.ceil(sc.sim.nees_from_s / dt - 1e-9))
    max_delay = float(np.max(draws["delay"])) if n else th.delay
    buf_len = 1 << max(2, int(math.ceil(math.log2(max_delay / dt + 3))))
    C[_k.BUF_MASK] = buf_len - 1
    C[_k.RPI_EPS] = 1e-12
    C[_k.ALLOC_MODE] = _k.ALLOC_BVLS if (c.kind == "pwm" and c.allocation == "nnls") else _k.ALLOC_RPI
    shared = dict(C=C, POS=np.ascontiguousarray(pos), FAILED=failed,
                  ENV=env, QREF=np.ascontiguousarray(qref), WREF=np.ascontiguousarray(wref),
                  ATAB=atab, ANOM=A_nom, FNOM=np.full(nt, th.f_max), AMASK=amask, buf_len=buf_len,
                  n_steps=n_steps)
    feas = _controllability(sc, dirs, flev)
    per_sample = dict(P=P, DIRS=np.ascontiguousarray(dirs), FLEV=np.ascontiguousarray(flev),
                      MDOT=np.ascontiguousarray(mdot))
    params = {
        "inertia": J, "inertia_physical": _triangle_ok(lam), "thrust": flev, "mass_flow": mdot,
        "torque_authority": feas["authority"],
        "directions": dirs, "delay": draws["delay"],
        "initial_quaternion": q0, "initial_rate": P[:, _k.P_W0:_k.P_W0 + 3].copy(),
        "gyro_bias": P[:, _k.P_BIAS:_k.P_BIAS + 3].copy(), "disturbance_scale": draws["disturbance"],
    }
    return {"shared": shared, "per_sample": per_sample, "feasibility": feas}, params


@dataclass(frozen=True)
class _Block:
    """One kernel call of :func:`simulate` (a campaign task): the shared and per-sample inputs
    of :func:`_prepare` for a block of samples, their noise seeds, whether to record traces
    and the target that runs it."""

    shared: dict[str, Any]
    per_sample: dict[str, np.ndarray]
    seeds: np.ndarray
    record: bool
    backend: Literal["cpu", "cuda"] = "cpu"


def _run_block(task: _Block) -> dict[str, Any]:
    """Run one block of samples through the kernel (module level: picklable for executors).
    The kernel's arrays are allocated as :data:`adcskit.simulation._kernels.ARGS` declares."""
    shared, ps = task.shared, task.per_sample
    n = ps["P"].shape[0]
    n_rec = shared["n_steps"] // int(shared["C"][_k.REC_EVERY]) + 1 if task.record else 0
    dims = _k.Dims(n=n, nt=shared["POS"].shape[0], buf_len=shared["buf_len"], n_rec=n_rec)
    A = _k.allocate_arrays({**shared, **ps, "SEEDS": task.seeds}, dims)
    run = _k.run_cuda if task.backend == "cuda" else _k.run_cpu
    t0 = time.perf_counter()
    run(A)
    wall = time.perf_counter() - t0
    return {"out": A.OUT, "tot": A.TOT, "rec": A.REC if task.record else None, "wall": wall}


#: Estimator kinds that the GPU driver runs (the Wahba and min-max solvers are CPU-only).
CUDA_ESTIMATORS = ("truth", "mekf")


def _resolve_backend(backend: str, scenario: Scenario) -> str:
    """``"cpu"`` or ``"cuda"`` for :func:`simulate` (see its ``backend`` parameter)."""
    if backend not in TARGET_BACKENDS:
        return resolve_backend(backend)  # raises, listing the names
    kind = scenario.estimator.kind
    if kind not in CUDA_ESTIMATORS:
        if backend == "cuda":
            raise InputError(
                f"backend='cuda' cannot run estimator.kind={kind!r}: its {kind} solver is a CPU-only numba "
                f"kernel (NumPy linear algebra: eigen / singular value decompositions); allowed with "
                f"backend='cuda': {', '.join(map(repr, CUDA_ESTIMATORS))} (or use backend='cpu' or 'auto')")
        return "cpu"
    return resolve_backend(backend)


def simulate(
    scenario: Scenario,
    n_samples: int = 1,
    rng: Any = None,
    executor: Any = None,
    *,
    record: bool = False,
    chunk_size: int | None = None,
    directory: Any = None,
    backend: str = "cpu",
    progress: bool | None = None,
) -> SimulationResult:
    """Run ``n_samples`` Monte-Carlo samples of a closed-loop scenario.

    Parameters
    ----------
    scenario : Scenario
        The closed loop (see :mod:`adcskit.simulation.scenario`).
    n_samples : int
        Number of samples (dispersed parameters and independent noise per sample).
    rng : int, SeedSequence or Generator, optional
        Randomness of the dispersions and per-sample seeds (``None`` -> seed 0). The same
        ``rng`` gives bit-identical results on every executor and chunking; an int or a
        SeedSequence gives the same samples on every call (a SeedSequence is copied, not
        advanced), a Generator is consumed (and so is the SeedSequence inside it: scipy's
        Latin-hypercube sampler spawns from it).
    executor : spec or Executor, optional
        ``serial`` (default: one process, all cores through numba's ``prange``),
        ``processes[:N]``, ``dask-local[:N]``, ``dask://HOST:PORT``.
    record : bool
        Return time histories (decimated by ``scenario.sim.record_every``).
    chunk_size : int, optional
        Samples per kernel call (default: all samples in 8 chunks at most, >= 64 each; with
        ``backend="cuda"`` all samples in one call, which the GPU driver splits into device
        chunks of its own).
    directory : path, optional
        Campaign directory: finished chunks are kept and a re-run resumes.
    backend : {"cpu", "cuda", "auto"}
        ``"cpu"`` (default): numba on the CPU cores. ``"cuda"``: the same per-sample function
        compiled for an NVIDIA GPU, one thread per sample (needs the ``gpu`` extra and a
        device); the estimators ``"truth"`` and ``"mekf"`` only. ``"auto"``: CUDA when a real
        device is usable and the estimator runs there, else the CPU. On a device the results
        agree with the CPU's to rounding (fused multiply-adds); under numba's CUDA simulator
        they are bit-identical.
    progress : bool or None
        Progress bar over the chunks (and the compile notice) on the console: ``None``
        (default) at a terminal or in a notebook only, ``False`` never, ``True`` always. The
        bar appears once the run has taken :data:`adcskit._progress.AUTO_DELAY_S` (3 s);
        inside the ``adcskit`` CLI's display the CLI shows it.

    Returns
    -------
    SimulationResult
        ``success=False`` (and :attr:`~SimulationResult.controllable` False for the samples
        concerned) when a sample's thrusters cannot produce torque in every direction.

    Raises
    ------
    InputError
        ``backend="cuda"`` with an estimator the GPU cannot run (``"wahba"``, ``"minmax"``).
    SolverError
        ``backend="cuda"`` without numba-cuda or without a visible device (the message names
        the ``gpu`` extra).

    Warns
    -----
    UncontrollableWarning
        Before the run, when the layout without its failed thrusters, or a sample's
        dispersed layout (misalignment, zero thrust), cannot produce torque in every
        direction (:func:`adcskit.thrusters.check_controllability`); the message names the
        unreachable torque direction.

    Notes
    -----
    The first call in a fresh installation compiles the numba kernel (about 75 CPU-seconds,
    1-2 min; cached on disk afterwards); inside a progress display (the ``adcskit`` CLI) a
    one-line notice says so first. The notice
    is printed only when numba's disk cache holds no usable entry for the kernel.

    Examples
    --------
    >>> from adcskit.simulation import Scenario, SimSpec, simulate
    >>> sc = Scenario(sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0))
    >>> res = simulate(sc, n_samples=4, rng=1)
    >>> res.metrics["propellant_kg"].shape, res.controllable.tolist()
    ((4,), [True, True, True, True])

    References
    ----------
    S3 eq. 5-7, 12 (allocation, pulse width, fuel); S4 Fig. 1 (loop); Markley & Crassidis
    (2014) §6.2 (MEKF), eq. 3.155 (gravity gradient).
    """
    if not isinstance(scenario, Scenario):
        raise InputTypeError(f"scenario must be a Scenario; got {type(scenario).__name__}")
    n_samples = check_int("n_samples", n_samples, minimum=1, maximum=10_000_000)
    record = check_flag("record", record)
    progress = progress_flag(progress)
    target = _resolve_backend(backend, scenario)
    if isinstance(rng, np.random.SeedSequence):
        # a copy: the Latin-hypercube draw (scipy.stats.qmc) spawns from the generator's
        # SeedSequence, so reusing the caller's object would give every call other dispersions
        rng = np.random.SeedSequence(rng.entropy, spawn_key=rng.spawn_key, pool_size=rng.pool_size,
                                     n_children_spawned=rng.n_children_spawned)
    gen = as_rng(rng)
    t_start = time.perf_counter()
    prep, params = _prepare(scenario, n_samples, gen)
    feas = prep["feasibility"]
    controllable = feas["controllable"]
    feas_msg = _controllability_message(scenario, feas)
    if feas_msg:
        warnings.warn(f"simulate: {feas_msg}", UncontrollableWarning, stacklevel=2)
    seeds = np.random.SeedSequence(int(gen.integers(2**63))).generate_state(n_samples, dtype=np.uint64)
    if chunk_size is None:
        chunk_size = n_samples if target == "cuda" else max(64, -(-n_samples // 8))
    chunk_size = check_int("chunk_size", chunk_size, minimum=1)
    shared = prep["shared"]
    ps = prep["per_sample"]
    tasks = []
    for lo in range(0, n_samples, chunk_size):
        hi = min(n_samples, lo + chunk_size)
        tasks.append(_Block(shared, {k: np.ascontiguousarray(v[lo:hi]) for k, v in ps.items()}, seeds[lo:hi],
                            record, target))
    from adcskit.uncertainty import run_campaign

    with auto_session(progress):
        if target == "cpu" and will_compile(_k.run_parallel):
            status(CLOSED_LOOP_NOTICE)
        camp = run_campaign(_run_block, tasks, executor=executor, directory=directory, chunk_size=1,
                            description="closed-loop samples")
    blocks = camp.values
    out = np.concatenate([b["out"] for b in blocks], axis=0)
    tot = np.concatenate([b["tot"] for b in blocks], axis=0)
    wall = sum(b["wall"] for b in blocks)
    n_steps = shared["n_steps"]
    nt = scenario.thrusters.n
    if record:
        trace = np.concatenate([b["rec"] for b in blocks], axis=0)
        t = np.arange(trace.shape[1]) * scenario.sim.record_every * scenario.sim.dt
    else:
        trace = None
        t = None
    metrics = {name: out[:, j] * f for name, (j, f) in _METRICS.items()}
    finite = bool(np.all(np.isfinite(metrics["pointing_rms_deg"])) and np.all(np.isfinite(metrics["propellant_kg"])))
    ok = finite and not feas_msg
    n_unphys = int(np.count_nonzero(~params["inertia_physical"]))
    msg = (f"{n_samples} samples x {n_steps} steps; {camp.n_chunks} chunk(s), {camp.n_resumed} resumed"
           + ("" if finite else "; some samples produced non-finite metrics")
           + (f"; {feas_msg}" if feas_msg else "")
           + (f"; {n_unphys} sample(s) with dispersed principal moments that break the triangle inequality "
              "(parameters['inertia_physical'])" if n_unphys else ""))
    return SimulationResult(
        metrics=metrics, controllable=controllable, on_time_per_thruster=tot, t=t, trace=trace, channels=_trace_channels(nt),
        parameters=params, seeds=seeds, n_samples=n_samples, n_steps=n_steps,
        sample_steps_per_s=n_samples * n_steps / wall if wall > 0 else math.inf,
        runtime_s=time.perf_counter() - t_start, n_chunks=camp.n_chunks, n_resumed=camp.n_resumed,
        executor=camp.executor, success=ok, message=msg, backend=target,
    )
