"""The closed-loop study's measurements: six Monte-Carlo campaigns as typed, frozen records.

:func:`measure` runs every :func:`adcskit.simulation.simulate` (and, for Q5 and Q6,
:func:`adcskit.simulation.simulate_wheels`) call of the study, in one fixed order of the random
stream (Q1 layouts, Q2 estimators and the NEES trace, Q3 gains, Q4 slews and the recorded slew
traces, Q5 wheels and the recorded Q5 traces), then Q6 (the 12U reference mode sequence) from
its own node of the root ``SeedSequence`` (spawn key :data:`Q6_STREAM`, so that it never moves
Q1-Q5's streams), and returns :class:`Measurements`; the claims,
tables and figures are functions of it. Each question's campaigns share one dispersion/noise
``SeedSequence`` per seed across the configurations they compare (common random numbers; Q5's
two loops are different kernels that draw their dispersions differently, so its seeds pair the
campaigns but not the samples). Q5's thruster side is Q3's nominal-gain campaign (the same
runs, not re-run).

References
----------
S0 (LEO scenario, bounded errors), S2 (pseudospectral time-optimal guidance), S3 (GEO
spacecraft, layouts, allocation), S4 (loop, gains, dispersions); Lefferts, Markley & Shuster
(1982) for the MEKF.
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from adcskit._progress import status
from adcskit._results import Result
from adcskit.constants import RAD_PER_DEG
from adcskit.errors import UncontrollableWarning
from adcskit.simulation import (
    MODE_NAMES,
    ControllerSpec,
    DispersionSpec,
    DisturbanceSpec,
    EstimatorSpec,
    GuidanceSpec,
    MagnetorquerSpec,
    ModeSpec,
    OrbitSpec,
    Scenario,
    SensorSpec,
    SimSpec,
    SpacecraftSpec,
    ThrusterSpec,
    WheelControlSpec,
    WheelDispersionSpec,
    WheelScenario,
    WheelSpec,
    check_simulation,
    simulate,
    simulate_wheels,
)
from adcskit.simulation.profiles import optimal_slew_table
from adcskit.studies._s4 import S4_LOOP
from adcskit.studies.closed_loop.config import Config
from adcskit.studies.closed_loop.paper import (
    S0_INERTIA,
    S0_INITIAL_ROTVEC_DEG,
    S3_INERTIA,
    S4_GAINS,
    S4_TABLE5_DISPERSIONS,
)
from adcskit.thrusters.reference import S3_REFERENCE_A, s3_manoeuvre_demands
from adcskit.uncertainty import read_requirements

__all__ = ["Q1_READINGS", "Q2_READINGS", "Q2_MINMAX_READINGS", "SeedRatio", "Trace", "LayoutRow", "Layouts",
           "EstimatorRow", "Estimators", "GainRow", "Gains", "SlewRow", "Slews", "LoopRow", "RequirementRow",
           "WheelsVsThrusters", "Q6_READINGS", "Q6_STREAM", "SeedTable", "ModeSeedRow", "ModeRequirementRow",
           "ModeSequence", "Measurements", "measure", "q5_requirements", "q6_scenario", "q6_tables"]


Q1_READINGS = ("pinv-redistribute, all thrusters", "lp-min-fuel, all thrusters",
               "pinv-redistribute, one failed", "lp-min-fuel, one failed")
Q2_READINGS = ("bounded (uniform) errors", "Gaussian errors")
Q2_MINMAX_READINGS = Q2_READINGS + ("bounded errors, equal weights",)
#: Q6: what "meets its sign-off table at 95 % confidence" means for a table of k rows: every row
#: at its own stated confidence (how a table is signed, docs/signoff.md), or the whole table at
#: once (Bonferroni: each row's risk divided by k, so that all k bounds hold together at 95 %).
Q6_READINGS = ("each row at its stated confidence", "whole table at once (Bonferroni)")
#: Q6: spawn key of its own SeedSequence node beside the per-seed children ``0 .. n_seeds - 1``
#: of the study's root that Q1-Q5 draw from, so Q6 never moves their streams.
Q6_STREAM = 6_000_006


# ----------------------------------------------------------------------------- records


@dataclass(frozen=True, slots=True, repr=False)
class SeedRatio(Result):
    """One seed's deciding ratio (``numerator / denominator``, means over the samples)."""

    ratio: float
    numerator: float = math.nan
    denominator: float = math.nan


@dataclass(frozen=True, slots=True, repr=False)
class Trace(Result):
    """Recorded time histories of a ``simulate(record=True)`` call (the figures draw them)."""

    t: np.ndarray
    trace: np.ndarray  # (samples, times, channels)
    channels: tuple[str, ...]
    n_samples: int


@dataclass(frozen=True, slots=True, repr=False)
class LayoutRow(Result):
    """Q1, one seed x reading x layout: a row of ``q1_layouts.csv``."""

    seed: int
    reading: str
    layout: str
    failed_thruster: int
    still_controllable: bool
    controllable_fraction: float
    torque_authority_mean_nm: float
    propellant_mean_kg: float
    pointing_rms_mean_deg: float
    settled_fraction: float
    firings_mean: float


@dataclass(frozen=True, slots=True, repr=False)
class Layouts(Result):
    """Q1 (GEO): optimised vs reference layout, per reading and seed."""

    runs: Mapping[str, tuple[SeedRatio, ...]]  # reading -> propellant optimised / reference
    rows: tuple[LayoutRow, ...]
    controllable_fraction: Mapping[str, float]  # "layout, reading" -> mean over samples and seeds
    torque_authority_nm: Mapping[str, float]
    propellant_samples: Mapping[str, np.ndarray]  # layout -> per-sample kg (last seed, first reading)


@dataclass(frozen=True, slots=True, repr=False)
class EstimatorRow(Result):
    """Q2, one seed x reading: a row of ``q2_estimators.csv`` (NaN: the MEKF is not run)."""

    seed: int
    reading: str
    pointing_rms_qmethod_deg: float
    pointing_rms_minmax_deg: float
    pointing_rms_mekf_deg: float
    knowledge_rms_qmethod_deg: float
    knowledge_rms_minmax_deg: float
    knowledge_rms_mekf_deg: float
    minmax_box_active_fraction: float
    mekf_nees_mean: float


@dataclass(frozen=True, slots=True, repr=False)
class Estimators(Result):
    """Q2 (LEO): MEKF and min-max vs the per-epoch q-method."""

    mekf_runs: Mapping[str, tuple[SeedRatio, ...]]
    minmax_runs: Mapping[str, tuple[SeedRatio, ...]]
    rows: tuple[EstimatorRow, ...]
    box_active_fraction: Mapping[str, float]  # reading -> mean over seeds
    nees_gaussian: np.ndarray  # per-seed mean NEES, Gaussian errors
    nees_trace: Trace  # recorded MEKF run, Gaussian errors


@dataclass(frozen=True, slots=True, repr=False)
class GainRow(Result):
    """Q3, one seed: a row of ``q3_gains.csv``."""

    seed: int
    std_nominal_deg: float
    std_robust_deg: float
    mean_nominal_deg: float
    mean_robust_deg: float


@dataclass(frozen=True, slots=True, repr=False)
class Gains(Result):
    """Q3 (S4 in 3 axes): robust vs nominal gains."""

    runs: tuple[SeedRatio, ...]  # std robust / nominal
    rows: tuple[GainRow, ...]


@dataclass(frozen=True, slots=True, repr=False)
class SlewRow(Result):
    """Q4, one seed: a row of ``q4_slew.csv``."""

    seed: int
    settling_step_s: float
    settling_optimal_s: float
    settled_fraction_step: float
    settled_fraction_optimal: float
    propellant_step_kg: float
    propellant_optimal_kg: float


@dataclass(frozen=True, slots=True, repr=False)
class Slews(Result):
    """Q4 (GEO): time-optimal profile vs step command."""

    optimal_tf_s: float
    bang_bang_tf_s: float
    settling_runs: tuple[SeedRatio, ...]
    propellant_runs: tuple[SeedRatio, ...]
    rows: tuple[SlewRow, ...]
    step_trace: Trace
    optimal_trace: Trace


@dataclass(frozen=True, slots=True, repr=False)
class LoopRow(Result):
    """Q5, one seed x loop: a row of ``q5_wheels_vs_thrusters.csv`` (NaN: not this loop's)."""

    seed: int
    loop: str
    pointing_max_p99_deg: float
    pointing_max_p50_deg: float
    pointing_rms_mean_deg: float
    settling_p99_s: float
    settled_fraction: float
    max_wheel_speed_p99_rpm: float
    max_wheel_momentum_p99_nms: float
    propellant_mean_kg: float


@dataclass(frozen=True, slots=True, repr=False)
class RequirementRow(Result):
    """Q5, one loop x requirement (last seed): a row of ``q5_requirements.csv``."""

    loop: str
    name: str
    requirement: str
    n: int
    estimate: float
    bound: float
    outcome: str
    verdict: str


@dataclass(frozen=True, slots=True, repr=False)
class WheelsVsThrusters(Result):
    """Q5 (S4's spacecraft): reaction wheels (quaternion PD) vs S4's on-off thruster loop."""

    runs: tuple[SeedRatio, ...]  # p99 over samples of the window's largest error, wheels / thrusters
    rows: tuple[LoopRow, ...]
    requirements: tuple[RequirementRow, ...]
    wheel_trace: Trace
    thruster_trace: Trace
    wheel_sample_steps_per_s: float  # median over the wheel kernel's calls


@dataclass(frozen=True, slots=True, repr=False)
class SeedTable(Result):
    """Q6, one seed x reading: the sign-off table's outcome and the finding's per-seed score.

    ``score`` is +1 when every row is met, -1 when a row is not met, 0 otherwise (a row
    inconclusive: too few samples to bound it either way, which decides nothing)."""

    seed: int
    outcome: str  # "met" | "not met" | "inconclusive"
    score: float
    n_met: int
    n_not_met: int
    n_inconclusive: int
    open_rows: str  # the rows that are not met, with their verdicts ("" when all are met)


@dataclass(frozen=True, slots=True, repr=False)
class ModeSeedRow(Result):
    """Q6, one seed's campaign: a row of ``q6_seeds.csv`` (percentiles over the samples; NaN counts as infinite)."""

    seed: int
    n_samples: int
    table: str
    table_bonferroni: str
    n_met: int
    n_not_met: int
    n_inconclusive: int
    n_pointing_at_end: int
    t_detumbled_p50_s: float
    t_detumbled_p99_s: float
    t_acquired_p99_s: float
    pointing_max_p99_deg: float
    pointing_rms_p99_deg: float
    knowledge_rms_p99_deg: float
    max_wheel_speed_max_rpm: float
    wall_s: float
    cpu_s: float


@dataclass(frozen=True, slots=True, repr=False)
class ModeRequirementRow(Result):
    """Q6, one seed x requirement: a row of ``q6_requirements.csv`` (both readings' verdicts)."""

    seed: int
    name: str
    requirement: str
    n: int
    n_violating: int
    estimate: float
    bound: float
    verdict: str
    bound_bonferroni: float
    verdict_bonferroni: str


@dataclass(frozen=True, slots=True, repr=False)
class ModeSequence(Result):
    """Q6 (12U reference smallsat): detumble -> sun -> nadir against its sign-off table."""

    runs: Mapping[str, tuple[SeedTable, ...]]  # reading -> per-seed table outcome
    rows: tuple[ModeSeedRow, ...]
    requirements: tuple[ModeRequirementRow, ...]
    trace: Trace  # the first seed's whole campaign (channels: error, rate, speeds, momentum, dipole, mode)
    pointing_max_deg: np.ndarray  # the first seed's per-sample largest pointing error (ranks the worst sample)
    metrics_from_s: float
    sample_steps_per_s: float  # median over the campaigns (kernel wall time)


@dataclass(frozen=True, slots=True, repr=False)
class Measurements(Result):
    """Everything the study measures, in campaign order."""

    layouts: Layouts
    estimators: Estimators
    gains: Gains
    slews: Slews
    wheels: WheelsVsThrusters
    modes: ModeSequence
    feasibility: Mapping[str, float]  # question -> smallest controllable fraction over its calls
    sample_steps_per_s: tuple[float, ...]  # one per simulate call


# ----------------------------------------------------------------------------- scenarios


def _geo_base(cfg: Config, thrusters: ThrusterSpec, allocation: str) -> Scenario:
    srp = cfg.geo_srp_torque_nm
    return Scenario(
        spacecraft=SpacecraftSpec(inertia=S3_INERTIA),
        orbit=OrbitSpec(altitude_km=35786.0),
        disturbance=DisturbanceSpec(constant=(srp, -0.5 * srp, 0.8 * srp), amplitude=(srp, srp, srp)),
        thrusters=thrusters,
        sensors=SensorSpec(sun_rate_hz=0.0, mag_rate_hz=0.0, gyro_rate_hz=10.0, star_tracker_rate_hz=2.0,
                           star_tracker_noise_arcsec=10.0),
        estimator=EstimatorSpec(kind="mekf", init_error_deg=0.05),
        controller=ControllerSpec(kind="schmitt", period_s=cfg.command_period_s,
                                  torque_level=(cfg.geo_torque_level_nm,) * 3,
                                  kp=(S4_GAINS["nominal"][0],) * 3, ki=(S4_GAINS["nominal"][1],) * 3,
                                  kd=(cfg.switch_tc_s * S4_GAINS["nominal"][0],) * 3, allocation=allocation),
        dispersions=DispersionSpec(inertia_rel=0.05, thrust_rel=0.05, misalignment_deg=0.5, delay_std_s=0.005,
                                   initial_attitude_deg=0.1, initial_rate_deg_s=0.005),
        guidance=GuidanceSpec(kind="step", target_rotvec_deg=tuple(cfg.geo_slew_deg / math.sqrt(3) * np.ones(3))),
        sim=SimSpec(dt=cfg.geo_dt_s, t_final=cfg.geo_t_final_s, metrics_from_s=0.75 * cfg.geo_t_final_s,
                    settle_band_deg=0.2, record_every=max(1, int(round(0.2 / cfg.geo_dt_s)))),
    )
def _leo_base(cfg: Config, kind: str, noise: str, weights: str = "inverse-variance") -> Scenario:
    return Scenario(
        spacecraft=SpacecraftSpec(inertia=S0_INERTIA),
        orbit=OrbitSpec(altitude_km=800.0, inclination_deg=75.0, magnetic_model="dipole"),
        thrusters=ThrusterSpec.from_torque_matrix(S3_REFERENCE_A, f_max=0.5, t_min=3e-3),
        sensors=SensorSpec(sun_rate_hz=1.0, sun_noise_deg=0.005, mag_rate_hz=1.0, mag_noise_deg=0.5, noise=noise,
                           gyro_rate_hz=10.0),
        estimator=EstimatorSpec(kind=kind, wahba_method="q-method", search_range=0.1, weights=weights,
                                init_error_deg=0.05),
        # torque levels: each allocated pulse at 50 Hz stays above the 3 ms minimum on-time
        # (0.16 N m about z = two 0.08 N thrusters = 3.2 ms pulses of 0.5 N)
        controller=ControllerSpec(kind="schmitt", period_s=cfg.command_period_s, torque_level=(0.4, 0.4, 0.16),
                                  kp=(S4_GAINS["nominal"][0],) * 3, ki=(S4_GAINS["nominal"][1],) * 3,
                                  kd=(cfg.switch_tc_s * S4_GAINS["nominal"][0],) * 3),
        dispersions=DispersionSpec(inertia_rel=0.05, thrust_rel=0.05, misalignment_deg=0.5,
                                   initial_attitude_deg=0.5, initial_rate_deg_s=0.01),
        guidance=GuidanceSpec(kind="hold"),
        initial_rotvec_deg=S0_INITIAL_ROTVEC_DEG,
        sim=SimSpec(dt=cfg.leo_dt_s, t_final=cfg.leo_t_final_s, metrics_from_s=cfg.leo_t_final_s - cfg.leo_window_s,
                    nees_from_s=10.0, record_every=max(1, int(round(0.5 / cfg.leo_dt_s)))),
    )


def _s4_base(cfg: Config, gains: tuple[float, float, float]) -> Scenario:
    kp, ki, kd = gains
    return Scenario(
        spacecraft=SpacecraftSpec(inertia=(S4_LOOP.inertia_kgm2,) * 3),  # S4 Table 3: J = 10 kg m^2
        orbit=OrbitSpec(altitude_km=800.0, inclination_deg=75.0),
        disturbance=DisturbanceSpec(constant=(S4_LOOP.disturbance_nm,) * 3),  # S4 Table 3
        thrusters=ThrusterSpec.from_torque_matrix(S3_REFERENCE_A, f_max=1.5, t_min=0.0, tau=S4_LOOP.tau_thruster_s,
                                                   delay=S4_LOOP.delay_s),
        sensors=SensorSpec(sun_rate_hz=0.0, mag_rate_hz=0.0, gyro_rate_hz=50.0, star_tracker_rate_hz=10.0,
                           star_tracker_noise_arcsec=10.0),
        estimator=EstimatorSpec(kind="mekf", init_error_deg=0.05),
        controller=ControllerSpec(kind="schmitt", period_s=1.0 / S4_LOOP.command_rate_hz, kp=(kp,) * 3, ki=(ki,) * 3, kd=(kd,) * 3,
                                  u_on=S4_LOOP.u_on, off_ratio=S4_LOOP.off_ratio, torque_level=(S4_LOOP.torque_nm,) * 3),
        dispersions=DispersionSpec(**S4_TABLE5_DISPERSIONS),
        guidance=GuidanceSpec(kind="step", target_rotvec_deg=(S4_LOOP.step_deg, 0.0, 0.0)),  # S4: 15 deg step
        sim=SimSpec(dt=cfg.s4_dt_s, t_final=cfg.s4_t_final_s, metrics_from_s=cfg.s4_t_final_s - S4_LOOP.t_window_s,
                    settle_band_deg=0.3, record_every=max(1, int(round(0.05 / cfg.s4_dt_s)))),
    )


def _design_layout(cfg: Config, seed: int) -> ThrusterSpec:
    from adcskit.thrusters import design_layout

    res = design_layout(6, s3_manoeuvre_demands(), algorithm="de", pop_size=cfg.layout_pop, n_gen=cfg.layout_gens,
                        rng=np.random.default_rng(seed))
    return ThrusterSpec.from_thruster_set(res.thrusters)


def _failure_index(th: ThrusterSpec) -> tuple[int, bool]:
    """The thruster whose loss leaves the largest positive-span margin (and whether the rest
    still spans every torque direction)."""
    from adcskit.thrusters import check_controllability

    A = th.torque_matrix()
    best, best_m, ok = 0, -1.0, False
    for j in range(th.n):
        c = check_controllability(np.delete(A, j, axis=1))
        m = c.margin if c.success else -1.0 + 1e-3 * c.rank
        if m > best_m:
            best, best_m, ok = j, m, c.success
    return best, ok


def _mean(x: np.ndarray) -> float:
    f = x[np.isfinite(x)]
    return float(np.mean(f)) if f.size else math.nan


class _Sim:
    """``simulate`` with the study's bookkeeping: kernel rates and per-question feasibility."""

    def __init__(self, n_samples: int, executor: Any) -> None:
        self.n_samples = n_samples
        self.executor = executor
        self.rates: list[float] = []
        self.feasible: dict[str, list[float]] = {}  # question -> controllable fraction of each call

    def __call__(self, sc: Scenario, seq: np.random.SeedSequence, record: bool = False, n: int | None = None,
                 question: str = ""):
        # the SeedSequence itself (simulate copies it): every configuration run with the same
        # `seq` gets the same dispersions and noise seeds (common random numbers). A Generator
        # made from `seq` would not: scipy's Latin-hypercube sampler spawns from its
        # SeedSequence, so each call would draw other dispersions.
        with warnings.catch_warnings():
            # an uncontrollable layout (Q1 with a failed thruster) is reported in the tables and
            # `measured` (controllable fractions), not as a warning per call
            warnings.simplefilter("ignore", UncontrollableWarning)
            res = simulate(sc, n or self.n_samples, rng=seq, executor=self.executor, record=record)
        self.rates.append(res.sample_steps_per_s)
        if question:
            self.feasible.setdefault(question, []).append(float(np.mean(res.controllable)))
        return res


def _trace(res: Any) -> Trace:
    return Trace(t=res.t, trace=res.trace, channels=tuple(res.channels), n_samples=res.n_samples)


def _layout_row(s_i: int, reading: str, name: str, fail: tuple[int, bool], failed: bool, r: Any) -> LayoutRow:
    return LayoutRow(seed=s_i, reading=reading, layout=name, failed_thruster=fail[0] if failed else -1,
                     still_controllable=fail[1] if failed else True,
                     controllable_fraction=float(np.mean(r.controllable)),
                     torque_authority_mean_nm=float(np.mean(r.parameters["torque_authority"])),
                     propellant_mean_kg=_mean(r.metrics["propellant_kg"]),
                     pointing_rms_mean_deg=_mean(r.metrics["pointing_rms_deg"]),
                     settled_fraction=float(np.mean(np.isfinite(r.metrics["settling_time_s"]))),
                     firings_mean=_mean(r.metrics["firings"]))


def _q1_layouts(cfg: Config, sim: _Sim, seeds: list, ref_layout: ThrusterSpec) -> Layouts:
    status("closed-loop: Q1 layouts (GEO)")
    runs: dict[str, list[SeedRatio]] = {r: [] for r in Q1_READINGS}
    rows = []
    prop_hist: dict[str, np.ndarray] = {}
    ctrl: dict[str, list[float]] = {}
    auth: dict[str, list[float]] = {}
    for s_i, seq in enumerate(seeds):
        sub = seq.spawn(3)
        opt_layout = _design_layout(cfg, int(sub[0].generate_state(1)[0]))
        layouts = {"reference": ref_layout, "optimised": opt_layout}
        fail = {name: _failure_index(L) for name, L in layouts.items()}
        for reading in Q1_READINGS:
            alloc, failed = reading.split(", ")
            res = {}
            for name, L in layouts.items():
                th = L.replace(failed=(fail[name][0],)) if failed == "one failed" else L
                r = sim(_geo_base(cfg, th, alloc), sub[1])  # same dispersion/noise seed for both layouts
                res[name] = r
                row = _layout_row(s_i, reading, name, fail[name], failed == "one failed", r)
                ctrl.setdefault(f"{name}, {reading}", []).append(row.controllable_fraction)
                auth.setdefault(f"{name}, {reading}", []).append(row.torque_authority_mean_nm)
                rows.append(row)
            pr = _mean(res["reference"].metrics["propellant_kg"])
            po = _mean(res["optimised"].metrics["propellant_kg"])
            runs[reading].append(SeedRatio(ratio=po / pr, numerator=po, denominator=pr))
            if s_i == len(seeds) - 1 and reading == Q1_READINGS[0]:
                prop_hist = {k: v.metrics["propellant_kg"] for k, v in res.items()}
    # controllable fraction: Monte-Carlo samples whose thrusters (failed one removed, dispersed
    # misalignment) can produce torque in every direction (simulate's feasibility test);
    # torque authority: torque available in the weakest direction (N m); both means over seeds
    return Layouts(runs={k: tuple(v) for k, v in runs.items()}, rows=tuple(rows),
                   controllable_fraction={k: float(np.mean(v)) for k, v in ctrl.items()},
                   torque_authority_nm={k: float(np.mean(v)) for k, v in auth.items()},
                   propellant_samples=prop_hist)


def _q2_row(s_i: int, reading: str, rq: Any, rr: Any, rm: Any | None) -> EstimatorRow:
    return EstimatorRow(
        seed=s_i, reading=reading, pointing_rms_qmethod_deg=_mean(rq.metrics["pointing_rms_deg"]),
        pointing_rms_minmax_deg=_mean(rr.metrics["pointing_rms_deg"]),
        pointing_rms_mekf_deg=math.nan if rm is None else _mean(rm.metrics["pointing_rms_deg"]),
        knowledge_rms_qmethod_deg=_mean(rq.metrics["knowledge_rms_deg"]),
        knowledge_rms_minmax_deg=_mean(rr.metrics["knowledge_rms_deg"]),
        knowledge_rms_mekf_deg=math.nan if rm is None else _mean(rm.metrics["knowledge_rms_deg"]),
        minmax_box_active_fraction=_mean(rr.metrics["box_active_fraction"]),
        mekf_nees_mean=math.nan if rm is None else _mean(rm.metrics["nees_mean"]))


def _q2_estimators(cfg: Config, sim: _Sim, seeds: list) -> Estimators:
    status("closed-loop: Q2 estimators (LEO)")
    mekf_runs: dict[str, list[SeedRatio]] = {r: [] for r in Q2_READINGS}
    minmax_runs: dict[str, list[SeedRatio]] = {r: [] for r in Q2_MINMAX_READINGS}
    rows = []
    for s_i, seq in enumerate(seeds):
        sub = seq.spawn(1)
        for reading in Q2_MINMAX_READINGS:
            noise = "uniform" if reading.startswith("bounded") else "gaussian"
            weights = "equal" if reading.endswith("equal weights") else "inverse-variance"
            # the same dispersion and noise seed for every estimator: paired comparisons
            rq = sim(_leo_base(cfg, "wahba", noise, weights), sub[0], question="q2")
            rr = sim(_leo_base(cfg, "minmax", noise, weights), sub[0], question="q2")
            rm = None
            if reading in Q2_READINGS:  # the MEKF uses no Wahba weights
                rm = sim(_leo_base(cfg, "mekf", noise), sub[0], question="q2")
            row = _q2_row(s_i, reading, rq, rr, rm)
            eq = row.pointing_rms_qmethod_deg
            minmax_runs[reading].append(SeedRatio(ratio=row.pointing_rms_minmax_deg / eq,
                                                  numerator=row.pointing_rms_minmax_deg, denominator=eq))
            if rm is not None:
                mekf_runs[reading].append(SeedRatio(ratio=row.pointing_rms_mekf_deg / eq,
                                                    numerator=row.pointing_rms_mekf_deg, denominator=eq))
            rows.append(row)
    box = {reading: float(np.mean([r.minmax_box_active_fraction for r in rows if r.reading == reading]))
           for reading in Q2_MINMAX_READINGS}
    # NEES trace for the figure (Gaussian errors: the filter's noise model)
    nres = sim(_leo_base(cfg, "mekf", "gaussian"), seeds[0].spawn(2)[1], record=True, n=cfg.record_samples)
    return Estimators(mekf_runs={k: tuple(v) for k, v in mekf_runs.items()},
                      minmax_runs={k: tuple(v) for k, v in minmax_runs.items()}, rows=tuple(rows),
                      box_active_fraction=box,
                      nees_gaussian=np.array([r.mekf_nees_mean for r in rows if r.reading == "Gaussian errors"]),
                      nees_trace=_trace(nres))


def _q3_gains(cfg: Config, sim: _Sim, seeds: list) -> tuple[Gains, list]:
    """Q3's record and its nominal-gain results per seed (Q5's thruster side)."""
    status("closed-loop: Q3 S4 gains")
    runs, rows, nominal = [], [], []
    for s_i, seq in enumerate(seeds):
        sub = seq.spawn(1)
        out = {}
        for name, g in S4_GAINS.items():
            r = sim(_s4_base(cfg, g), sub[0], question="q3")
            if name == "nominal":
                nominal.append(r)
            e = r.metrics["pointing_rms_deg"]
            out[name] = (float(np.nanstd(e, ddof=1)), _mean(e))
        runs.append(SeedRatio(ratio=out["robust"][0] / out["nominal"][0], numerator=out["robust"][0],
                              denominator=out["nominal"][0]))
        rows.append(GainRow(seed=s_i, std_nominal_deg=out["nominal"][0], std_robust_deg=out["robust"][0],
                            mean_nominal_deg=out["nominal"][1], mean_robust_deg=out["robust"][1]))
    return Gains(runs=tuple(runs), rows=tuple(rows)), nominal


def _q4_slews(cfg: Config, sim: _Sim, seeds: list, ref_layout: ThrusterSpec) -> Slews:
    status("closed-loop: Q4 optimal slew vs step (GEO)")
    amax = cfg.slew_accel_fraction * cfg.geo_torque_level_nm / S3_INERTIA[2]
    table, sol = optimal_slew_table(cfg.slew_deg * RAD_PER_DEG, amax, (0.0, 0.0, 1.0), t0=1.0)
    step = GuidanceSpec(kind="step", target_rotvec_deg=(0.0, 0.0, cfg.slew_deg), t_step=1.0)
    settling, propellant, rows = [], [], []
    base4 = _geo_base(cfg, ref_layout, "pinv-redistribute").replace(
        sim=SimSpec(dt=cfg.geo_dt_s, t_final=cfg.geo_t_final_s + 20.0, metrics_from_s=cfg.geo_t_final_s,
                    settle_band_deg=0.2, record_every=max(1, int(round(0.2 / cfg.geo_dt_s)))))
    for s_i, seq in enumerate(seeds):
        sub = seq.spawn(1)
        rs = sim(base4.replace(guidance=step), sub[0], question="q4")
        ro = sim(base4.replace(guidance=table), sub[0], question="q4")
        ts_, to_ = _mean(rs.metrics["settling_time_s"]), _mean(ro.metrics["settling_time_s"])
        ps_, po_ = _mean(rs.metrics["propellant_kg"]), _mean(ro.metrics["propellant_kg"])
        settling.append(SeedRatio(ratio=to_ / ts_, numerator=to_, denominator=ts_))
        propellant.append(SeedRatio(ratio=po_ / ps_, numerator=po_, denominator=ps_))
        rows.append(SlewRow(seed=s_i, settling_step_s=ts_, settling_optimal_s=to_,
                            settled_fraction_step=float(np.mean(np.isfinite(rs.metrics["settling_time_s"]))),
                            settled_fraction_optimal=float(np.mean(np.isfinite(ro.metrics["settling_time_s"]))),
                            propellant_step_kg=ps_, propellant_optimal_kg=po_))
    rec_s = sim(base4.replace(guidance=step), seeds[0].spawn(2)[1], record=True, n=cfg.record_samples)
    rec_o = sim(base4.replace(guidance=table), seeds[0].spawn(2)[1], record=True, n=cfg.record_samples)
    return Slews(optimal_tf_s=float(sol.tf), bang_bang_tf_s=2 * math.sqrt(cfg.slew_deg * RAD_PER_DEG / amax),
                 settling_runs=tuple(settling), propellant_runs=tuple(propellant), rows=tuple(rows),
                 step_trace=_trace(rec_s), optimal_trace=_trace(rec_o))


_RPM = math.pi / 30.0
#: Q5: wheel speed limit (rpm) and the margin kept below it in the sign-off table.
Q5_MAX_SPEED_RPM = 6000.0


def _q5_wheel_scenario(cfg: Config) -> WheelScenario:
    """S4's spacecraft, orbit, constant disturbance, sensors, 15 deg step and windows, pointed by
    a 4-wheel pyramid under quaternion PD at S4's 50 Hz (no magnetorquers, no mode sequence).

    The per-wheel torque limit gives every body axis S4's torque level through the
    pseudo-inverse allocation (``|A^+ e_x|_inf = sqrt(3)/4`` for the default pyramid)."""
    th = _s4_base(cfg, S4_GAINS["nominal"])
    period = 1.0 / S4_LOOP.command_rate_hz
    return WheelScenario(
        spacecraft=th.spacecraft, orbit=th.orbit,
        disturbance=th.disturbance,  # S4 Table 3: 0.05 N m per axis (not dispersed here, see the docs)
        wheels=WheelSpec.pyramid(inertia_kgm2=cfg.q5_wheel_momentum_nms / (Q5_MAX_SPEED_RPM * _RPM),
                                 max_torque_nm=math.sqrt(3.0) / 4.0 * S4_LOOP.torque_nm,
                                 max_speed_rpm=Q5_MAX_SPEED_RPM),
        magnetorquers=MagnetorquerSpec(max_dipole_am2=0.0, unload_gain=0.0),
        sensors=th.sensors,
        control=WheelControlSpec(law="pd", bandwidth_rad_s=cfg.q5_wheel_bandwidth_rad_s, damping=cfg.q5_wheel_damping,
                                 period_s=period),
        modes=ModeSpec(initial="point", sequence=False, pointing="inertial",
                       target_rotvec_deg=(S4_LOOP.step_deg, 0.0, 0.0)),
        dispersions=WheelDispersionSpec(inertia_rel=S4_TABLE5_DISPERSIONS["inertia_rel"]),
        sim=SimSpec(dt=cfg.s4_dt_s, t_final=cfg.s4_t_final_s, metrics_from_s=cfg.s4_t_final_s - S4_LOOP.t_window_s,
                    settle_band_deg=th.sim.settle_band_deg, record_every=th.sim.record_every),
        initial_rate_deg_s=(0.0, 0.0, 0.0),
    )


def q5_requirements(cfg: Config) -> tuple[str, ...]:
    """Q5's requirement table (one line each, :func:`adcskit.uncertainty.parse_requirement`).

    Examples
    --------
    >>> from adcskit.studies.closed_loop import Config
    >>> q5_requirements(Config())[0]
    'Q5-1: pointing_max_deg p99 <= 0.25 after 20 s'
    """
    win = cfg.s4_t_final_s - S4_LOOP.t_window_s
    return (f"Q5-1: pointing_max_deg p99 <= {cfg.q5_pointing_req_deg:g} after {win:g} s",
            f"Q5-2: settling_time_s p99 <= {win:g}",
            f"Q5-3: P(pointing_rms_deg > {0.6 * cfg.q5_pointing_req_deg:g}) <= 5 % after {win:g} s")


def _p(x: np.ndarray, q: float) -> float:
    """Percentile over samples; a NaN sample (never settled, never pointing) counts as infinite."""
    return float(np.percentile(np.where(np.isnan(x), np.inf, x), q))


def _loop_row(s_i: int, loop: str, r: Any) -> LoopRow:
    m = r.metrics
    st = m["settling_time_s"]
    nan = math.nan
    return LoopRow(seed=s_i, loop=loop, pointing_max_p99_deg=_p(m["pointing_max_deg"], 99),
                   pointing_max_p50_deg=_p(m["pointing_max_deg"], 50), pointing_rms_mean_deg=_mean(m["pointing_rms_deg"]),
                   settling_p99_s=_p(st, 99), settled_fraction=float(np.mean(np.isfinite(st))),
                   max_wheel_speed_p99_rpm=_p(m["max_wheel_speed_rpm"], 99) if "max_wheel_speed_rpm" in m else nan,
                   max_wheel_momentum_p99_nms=(_p(m["max_wheel_momentum_nms"], 99)
                                               if "max_wheel_momentum_nms" in m else nan),
                   propellant_mean_kg=_mean(m["propellant_kg"]) if "propellant_kg" in m else nan)


def _requirement_rows(loop: str, rows: Any) -> list[RequirementRow]:
    out = []
    for v in rows:
        d = v.table_row()
        out.append(RequirementRow(loop=loop, name=d["name"] or "", requirement=d["requirement"], n=int(d["n"]),
                                  estimate=float(d["estimate"]), bound=float(d["bound"]), outcome=v.outcome,
                                  verdict=d["verdict"]))
    return out


def _q5_wheels(cfg: Config, sim: _Sim, seeds: list, s4_nominal: list) -> WheelsVsThrusters:
    status("closed-loop: Q5 wheels vs S4 thrusters")
    wsc = _q5_wheel_scenario(cfg)
    runs, rows, rates = [], [], []
    reqs = q5_requirements(cfg)
    speed_req = f"Q5-4: max_wheel_speed_rpm max <= {0.9 * Q5_MAX_SPEED_RPM:g}"
    req_rows: list[RequirementRow] = []
    for s_i, (seq, rt) in enumerate(zip(seeds, s4_nominal)):
        rw = simulate_wheels(wsc, cfg.n_samples, rng=seq.spawn(1)[0])
        rates.append(rw.sample_steps_per_s)
        w_row, t_row = _loop_row(s_i, "wheels (quaternion PD)", rw), _loop_row(s_i, "S4 thrusters", rt)
        rows += [w_row, t_row]
        runs.append(SeedRatio(ratio=w_row.pointing_max_p99_deg / t_row.pointing_max_p99_deg,
                              numerator=w_row.pointing_max_p99_deg, denominator=t_row.pointing_max_p99_deg))
        if s_i == len(seeds) - 1:  # the sign-off table of the last seed's campaigns
            req_rows = (_requirement_rows(w_row.loop, rw.check_requirements([*reqs, speed_req]).rows)
                        + _requirement_rows(t_row.loop, check_simulation(
                            list(reqs), rt, _s4_base(cfg, S4_GAINS["nominal"])).rows))
    rec = seeds[0].spawn(2)[1]
    rec_w = simulate_wheels(wsc, cfg.record_samples, rng=rec, record=True)
    rec_t = sim(_s4_base(cfg, S4_GAINS["nominal"]), rec, record=True, n=cfg.record_samples)
    return WheelsVsThrusters(runs=tuple(runs), rows=tuple(rows), requirements=tuple(req_rows),
                             wheel_trace=_trace(rec_w), thruster_trace=_trace(rec_t),
                             wheel_sample_steps_per_s=float(np.median(rates)))


def q6_scenario(cfg: Config) -> WheelScenario:
    """Q6's scenario: the 12U reference smallsat of :class:`~adcskit.simulation.WheelScenario`
    (its defaults) with the reference Monte-Carlo dispersions of ``docs/wheels.md`` and
    ``benchmarks/bench_wheels.py``: 10 % per principal moment, 0.5 deg wheel misalignment, a
    20 % sensor-noise factor, 1 deg/s initial rate per axis, uniformly random initial attitudes.

    Examples
    --------
    >>> from adcskit.studies.closed_loop import Config
    >>> sc = q6_scenario(Config())
    >>> sc.modes.initial, sc.sim.t_final, sc.sim.metrics_from_s, sc.dispersions.initial_attitude
    ('detumble', 17100.0, 11400.0, 'random')
    """
    sc = WheelScenario(dispersions=WheelDispersionSpec(inertia_rel=0.1, wheel_misalignment_deg=0.5,
                                                       sensor_noise_rel=0.2, initial_rate_deg_s=1.0,
                                                       initial_attitude="random"))
    return sc.replace(sim=sc.sim.replace(record_every=cfg.q6_record_every))


def q6_tables(cfg: Config) -> dict[str, tuple]:
    """Q6's requirement table under each reading (:data:`Q6_READINGS`): the rows as written, and
    the Bonferroni rows (each row's risk ``1 - confidence`` divided by the number of rows).

    Examples
    --------
    >>> from adcskit.studies.closed_loop import Config
    >>> t = q6_tables(Config())
    >>> [r.confidence for r in t[Q6_READINGS[0]]][:2], round(t[Q6_READINGS[1]][0].confidence, 6)
    ([0.95, 0.95], 0.99)
    """
    rows = read_requirements(list(cfg.q6_requirements))
    k = len(rows)
    joint = tuple(dataclasses.replace(r, confidence=1.0 - (1.0 - r.confidence) / k) for r in rows)
    return {Q6_READINGS[0]: rows, Q6_READINGS[1]: joint}


def _seed_table(s_i: int, table: Any) -> SeedTable:
    outcome = "met" if table.n_met == len(table.rows) else ("not met" if table.n_not_met else "inconclusive")
    open_rows = "; ".join(f"{r.requirement.name or r.requirement.text} {r.verdict}" for r in table.rows
                          if r.outcome != "met")
    return SeedTable(seed=s_i, outcome=outcome, score={"met": 1.0, "not met": -1.0}.get(outcome, 0.0),
                     n_met=table.n_met, n_not_met=table.n_not_met, n_inconclusive=table.n_inconclusive,
                     open_rows=open_rows)


def _q6_trace(res: Any) -> Trace:
    keep = [i for i, c in enumerate(res.channels)
            if c in ("error", "rate", "h_wheels", "mode") or c.startswith(("speed_", "dipole_"))]
    return Trace(t=res.t, trace=res.trace[:, :, keep], channels=tuple(res.channels[i] for i in keep),
                 n_samples=res.n_samples)


def _q6_modes(cfg: Config, seeds: list) -> ModeSequence:
    status(f"closed-loop: Q6 reference mode sequence ({cfg.n_seeds} x {cfg.q6_n_samples} samples)")
    sc = q6_scenario(cfg)
    tables = q6_tables(cfg)
    runs: dict[str, list[SeedTable]] = {r: [] for r in Q6_READINGS}
    rows, req_rows, rates = [], [], []
    trace, pmax = None, np.zeros(0)
    for s_i, seq in enumerate(seeds):
        c0 = time.process_time()
        res = simulate_wheels(sc, cfg.q6_n_samples, rng=seq, record=s_i == 0)
        cpu = time.process_time() - c0
        rates.append(res.sample_steps_per_s)
        # a sample that never points (NaN pointing metrics) violates every pointing row
        checked = {r: res.check_requirements(t, nan_policy="fail") for r, t in tables.items()}
        for reading, table in checked.items():
            runs[reading].append(_seed_table(s_i, table))
        own, joint = checked[Q6_READINGS[0]], checked[Q6_READINGS[1]]
        for a, b in zip(own.rows, joint.rows):
            d = a.table_row()
            req_rows.append(ModeRequirementRow(
                seed=s_i, name=d["name"] or "", requirement=d["requirement"], n=a.n, n_violating=a.n_violating,
                estimate=a.estimate, bound=a.bound, verdict=a.verdict, bound_bonferroni=b.bound,
                verdict_bonferroni=b.verdict))
        m = res.metrics
        rows.append(ModeSeedRow(
            seed=s_i, n_samples=res.n_samples, table=runs[Q6_READINGS[0]][-1].outcome,
            table_bonferroni=runs[Q6_READINGS[1]][-1].outcome, n_met=own.n_met, n_not_met=own.n_not_met,
            n_inconclusive=own.n_inconclusive,
            n_pointing_at_end=int(np.count_nonzero(m["final_mode"] == MODE_NAMES.index("point"))),
            t_detumbled_p50_s=_p(m["t_detumbled_s"], 50), t_detumbled_p99_s=_p(m["t_detumbled_s"], 99),
            t_acquired_p99_s=_p(m["t_acquired_s"], 99), pointing_max_p99_deg=_p(m["pointing_max_deg"], 99),
            pointing_rms_p99_deg=_p(m["pointing_rms_deg"], 99), knowledge_rms_p99_deg=_p(m["knowledge_rms_deg"], 99),
            max_wheel_speed_max_rpm=_p(m["max_wheel_speed_rpm"], 100), wall_s=res.runtime_s, cpu_s=cpu))
        if s_i == 0:  # the envelope figure: the first seed's whole campaign
            trace, pmax = _q6_trace(res), m["pointing_max_deg"].copy()
    return ModeSequence(runs={k: tuple(v) for k, v in runs.items()}, rows=tuple(rows), requirements=tuple(req_rows),
                        trace=trace, pointing_max_deg=pmax, metrics_from_s=sc.sim.metrics_from_s,
                        sample_steps_per_s=float(np.median(rates)))


def measure(cfg: Config, *, rng: Any = None, executor: Any = None) -> Measurements:
    """Run the six campaigns (Q1-Q6, see the package docstring) and return their records.

    Examples
    --------
    >>> from adcskit.studies.closed_loop.experiment import Q1_READINGS, measure
    >>> len(Q1_READINGS)  # two allocations x (all thrusters, one failed)
    4
    """
    gen = np.random.default_rng(rng)
    root = np.random.SeedSequence(int(gen.integers(2**32)))
    seeds = root.spawn(cfg.n_seeds)
    sim = _Sim(cfg.n_samples, executor)
    ref_layout = ThrusterSpec.from_torque_matrix(S3_REFERENCE_A)
    layouts = _q1_layouts(cfg, sim, seeds, ref_layout)
    estimators = _q2_estimators(cfg, sim, seeds)
    gains, s4_nominal = _q3_gains(cfg, sim, seeds)
    slews = _q4_slews(cfg, sim, seeds, ref_layout)
    wheels = _q5_wheels(cfg, sim, seeds, s4_nominal)
    # Q6 draws from its own node of the root (spawn key Q6_STREAM), never from Q1-Q5's children
    modes = _q6_modes(cfg, np.random.SeedSequence(root.entropy, spawn_key=(Q6_STREAM,)).spawn(cfg.n_seeds))
    return Measurements(layouts=layouts, estimators=estimators, gains=gains, slews=slews, wheels=wheels, modes=modes,
                        feasibility={q: float(np.min(v)) for q, v in sorted(sim.feasible.items())},
                        sample_steps_per_s=tuple(sim.rates))
