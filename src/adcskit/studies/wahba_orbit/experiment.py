"""The measurements of the ``wahba-orbit`` study (S0 §4-2), as typed frozen records.

A rigid spacecraft (inertia diag(80, 80, 4) kg m², S0 Table 3) starts at Euler angles
(0, 0, 5°) with zero body rate (S0 Table 2) and is propagated torque-free plus gravity
gradient for 20 minutes on a circular 800 km, 75° orbit (RAAN 0). At every sample a sun
sensor (±0.005° bounded error) and a three-axis magnetometer (±0.5° bounded error) measure
the sun direction (Vallado) and the geomagnetic field; the attitude is then determined by the
q-method and by the robust interval solvers, and compared with the truth (S0 Figs. 1–4).

:func:`measure` runs every (case, weighting, seed) pass and returns :class:`Measurements`;
claims, figures and tables are pure functions of it (``claims.py``, ``figures.py``,
``report.py``). The random stream is one :class:`numpy.random.SeedSequence` drawn from
``rng`` and spawned per seed, then per run; that order fixes every number.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from adcskit._progress import track
from adcskit._results import Result
from adcskit.attitude import dcm_to_euler, euler_to_dcm, quat_to_dcm
from adcskit.determination import robust_wahba, solve_wahba
from adcskit.dynamics import propagate_attitude
from adcskit.dynamics.gravity_gradient import gravity_gradient_torque
from adcskit.environment import circular_orbit, magnetic_field, sun_direction
from adcskit.sensors import Magnetometer, SunSensor
from adcskit.studies.wahba_orbit.config import Config

__all__ = ["METHODS", "CaseRun", "Measurements", "PassSeries", "SeedRun", "angle_deg", "measure", "run_case",
           "simulate_truth"]

#: The estimators compared at every sample (NSGA-II's knee on every ``nsga2_every``-th only).
METHODS = ("q-method", "minmax", "worst-case", "nsga2-knee")


def angle_deg(q1: np.ndarray, q2: np.ndarray) -> np.ndarray:
    """δθ between attitudes (N, 4) [deg] (chord form)."""
    d = np.minimum(np.linalg.norm(q1 - q2, axis=-1), np.linalg.norm(q1 + q2, axis=-1))
    return np.degrees(4.0 * np.arcsin(np.clip(d / 2.0, 0.0, 1.0)))


def simulate_truth(config: Config):
    """Orbit, true attitude and reference directions."""
    t = np.arange(0.0, config.duration_s + 1e-9, config.dt_s)
    orbit = circular_orbit(config.altitude_km * 1e3, np.radians(config.inclination_deg),
                           np.radians(config.raan_deg), 0.0, t, epoch=config.epoch)
    roll, pitch, yaw = np.radians(config.euler0_deg)
    A0 = euler_to_dcm([yaw, pitch, roll], "ZYX")  # 3-2-1: yaw, then pitch, then roll
    from adcskit.attitude import dcm_to_quat

    q0 = dcm_to_quat(A0)
    J = np.asarray(config.inertia_kgm2, float)
    a = 6378137.0 + config.altitude_km * 1e3
    n_orb = np.sqrt(3.986004418e14 / a**3)

    def torque(tt, q, w):
        if not config.gravity_gradient:
            return np.zeros(3)
        st = circular_orbit(config.altitude_km * 1e3, np.radians(config.inclination_deg),
                            np.radians(config.raan_deg), 0.0, np.array([tt]))
        return gravity_gradient_torque(quat_to_dcm(q) @ st.r[0], J)

    traj = propagate_attitude(q0, np.zeros(3), J, t, torque=torque)
    return t, orbit, traj, n_orb


@dataclass(frozen=True, slots=True, repr=False)
class CaseRun(Result):
    """One noise realisation of one case: every estimator's attitude and error at every sample.

    ``est`` and ``err`` map each of :data:`METHODS` to an (N, 4) quaternion / (N,) error [deg]
    series (NaN where NSGA-II did not run); ``rms`` and ``runtime_s`` (median per solve) by
    method; ``rms_q_on_nsga2_samples`` is the q-method's RMS on NSGA-II's samples
    ``nsga_idx``; ``sun_mag_angle_deg`` the angle between the sun and the reference field.
    """

    A: np.ndarray
    est: Mapping[str, np.ndarray]
    err: Mapping[str, np.ndarray]
    rms: Mapping[str, float]
    rms_q_on_nsga2_samples: float
    runtime_s: Mapping[str, float]
    nsga_idx: np.ndarray
    sun_mag_angle_deg: np.ndarray


@dataclass(frozen=True, slots=True, repr=False)
class PassSeries(Result):
    """The per-sample series the figures draw (kept for the first seed only)."""

    est: Mapping[str, np.ndarray]
    err: Mapping[str, np.ndarray]
    nsga_idx: np.ndarray
    sun_mag_angle_deg: np.ndarray


@dataclass(frozen=True, slots=True, repr=False)
class SeedRun(Result):
    """One (case, weighting, seed) pass, summarised: RMS, max error and median run time by method."""

    rms: Mapping[str, float]
    rms_q_on_nsga2_samples: float
    runtime_s: Mapping[str, float]
    max_deg: Mapping[str, float]
    series: PassSeries | None = None

    def reduction(self, m: str) -> float:
        """1 − RMS(method) / RMS(q-method); NSGA-II against the q-method on its own samples."""
        base = self.rms["q-method"] if m != "nsga2-knee" else self.rms_q_on_nsga2_samples
        return 1.0 - self.rms[m] / base


@dataclass(frozen=True, slots=True, repr=False)
class Measurements(Result):
    """Everything the study decides and draws from.

    ``by[(case, weighting)]`` holds the :class:`SeedRun` of each seed, in seed order; the
    keys are in run order (every case with the default weighting, then the paper's case with
    the other weightings). ``euler_true_deg`` is the true 3-2-1 (yaw, pitch, roll) series.
    """

    t: np.ndarray
    euler_true_deg: np.ndarray
    orbit_rate_rad_s: float
    paper_case: str
    weightings: tuple[str, ...]
    by: Mapping[tuple[str, str], tuple[SeedRun, ...]]

    @property
    def first(self) -> SeedRun:
        """Seed 0 of the paper's case with the default weighting (the one with series)."""
        return next(iter(self.by[(self.paper_case, self.weightings[0])]))

    def mean_rms(self, case: str, w: str, m: str) -> float:
        """Mean over seeds of the RMS error [deg] of method ``m``."""
        return float(np.mean([o.rms[m] for o in self.by[(case, w)]]))


def run_case(config: Config, case: str, t, orbit, traj, rng: np.random.Generator,
             weighting: str | None = None) -> CaseRun:
    """One noise realisation of one case: every estimator at every sample, errors and RMS."""
    weighting = config.weighting if weighting is None else weighting
    truth_model, ref_model = case.split("/")
    times = orbit.times
    A = quat_to_dcm(traj.q)
    s_eci = sun_direction(times)
    B_truth = magnetic_field(orbit.r, times, model=truth_model)
    B_ref = B_truth if ref_model == truth_model else magnetic_field(orbit.r, times, model=ref_model)
    sun = SunSensor(angle_bound=np.radians(config.sun_bound_deg))
    mag = Magnetometer(angle_bound=np.radians(config.mag_bound_deg))
    s_meas = sun.measure(A, s_eci, rng=rng)
    m_meas = mag.measure(A, B_truth, rng=rng)
    s_mid, s_rad = sun.interval(s_meas)
    m_mid, m_rad = mag.interval(m_meas)
    body = np.stack([s_meas, m_meas], axis=1)
    ref = np.stack([s_eci, B_ref], axis=1)
    if weighting == "equal":
        w = np.array([1.0, 1.0])
    else:
        w = 1.0 / np.radians([config.sun_bound_deg, config.mag_bound_deg]) ** 2
    N = len(t)
    est = {m: np.full((N, 4), np.nan) for m in METHODS}
    rt = {m: [] for m in METHODS}
    solve_wahba(body[:2], ref[:2], method="q-method")  # warm the compiled kernel before timing
    t0 = time.perf_counter()
    est["q-method"] = solve_wahba(body, ref, np.broadcast_to(w, (N, 2)), method="q-method").q
    rt["q-method"].append((time.perf_counter() - t0) / N)
    zero = np.zeros((2, 3))
    nsga_idx = np.arange(0, N, config.nsga2_every)
    for k in track(range(N), f"{case} epochs", total=N):
        bm = np.stack([s_mid[k], m_mid[k]])
        br = np.stack([s_rad[k], m_rad[k]])
        for m in ("minmax", "worst-case"):
            t1 = time.perf_counter()
            res = robust_wahba(bm, br, ref[k], zero, w, method=m)
            rt[m].append(time.perf_counter() - t1)
            est[m][k] = res.q
        if k in nsga_idx:
            t1 = time.perf_counter()
            res = robust_wahba(bm, br, ref[k], zero, w, method="nsga2", pop_size=config.pop_size,
                               n_gen=config.n_gen, rng=int(rng.integers(2**31 - 1)))
            rt["nsga2-knee"].append(time.perf_counter() - t1)
            est["nsga2-knee"][k] = res.q
    err = {m: angle_deg(est[m], traj.q) for m in METHODS}
    rms = {m: float(np.sqrt(np.nanmean(err[m] ** 2))) for m in METHODS}
    # q-method RMS on the NSGA-II subsample, for a like-for-like comparison
    rms_q_sub = float(np.sqrt(np.mean(err["q-method"][nsga_idx] ** 2)))
    return CaseRun(
        A=A, est=est, err=err, rms=rms, rms_q_on_nsga2_samples=rms_q_sub,
        runtime_s={m: float(np.median(rt[m])) for m in METHODS},
        nsga_idx=nsga_idx,
        sun_mag_angle_deg=np.degrees(np.arccos(np.clip(np.sum(
            s_eci * B_ref / np.linalg.norm(B_ref, axis=1, keepdims=True), axis=1), -1, 1))),
    )


def _case_task(task) -> SeedRun:
    """Executor task: one (case, weighting, seed) run; returns a compact summary."""
    config, case, weighting, seed, truth, keep = task
    t, orbit, traj = truth
    res = run_case(config, case, t, orbit, traj, np.random.default_rng(seed), weighting)
    series = PassSeries(est=res.est, err=res.err, nsga_idx=res.nsga_idx,
                        sun_mag_angle_deg=res.sun_mag_angle_deg) if keep else None  # first seed only
    return SeedRun(rms=res.rms, rms_q_on_nsga2_samples=res.rms_q_on_nsga2_samples, runtime_s=res.runtime_s,
                   max_deg={m: float(np.nanmax(res.err[m])) for m in METHODS}, series=series)


def measure(config: Config, *, rng: Any = None, executor: Any = None) -> Measurements:
    """Propagate the truth, then run every (case, weighting, seed) pass through ``executor``.

    Examples
    --------
    >>> from adcskit.studies.wahba_orbit.experiment import measure
    >>> callable(measure)
    True
    """
    from adcskit.uncertainty.executor import make_executor

    rng = np.random.default_rng(0) if rng is None else rng
    ex = executor if executor is not None else make_executor("serial")
    t, orbit, traj, n_orb = simulate_truth(config)
    if not traj.success:
        raise RuntimeError(f"attitude propagation failed: {traj.message}")
    euler_true = np.degrees(dcm_to_euler(quat_to_dcm(traj.q), "ZYX"))
    paper_case = config.cases[0]
    weightings = tuple(dict.fromkeys([config.weighting, *config.readings_weighting]))
    runs_spec = [(c, config.weighting) for c in config.cases]
    runs_spec += [(paper_case, w) for w in weightings if w != config.weighting]
    seeds = np.random.SeedSequence(int(rng.integers(2**63 - 1))).spawn(config.n_seeds)
    tasks, keys = [], []
    for j, ss in enumerate(seeds):
        for i, (case, w) in enumerate(runs_spec):
            tasks.append((config, case, w, ss.spawn(len(runs_spec))[i], (t, orbit, traj), j == 0))
            keys.append((case, w, j))
    outs = ex.map(_case_task, tasks, description="orbit passes")
    by: dict[tuple[str, str], list[SeedRun]] = {}
    for (case, w, _j), o in zip(keys, outs):
        by.setdefault((case, w), []).append(o)
    return Measurements(t=t, euler_true_deg=euler_true, orbit_rate_rad_s=float(n_orb), paper_case=paper_case,
                        weightings=weightings, by={k: tuple(v) for k, v in by.items()})
