"""Settings of the ``onoff-tuning`` study: the S4 Table 3 loop, Table 5 spreads, GA protocol.

References
----------
S4, Tables 3, 5 and 6; §4 (GA settings).
"""

from __future__ import annotations

import textwrap
from dataclasses import dataclass, field, fields
from typing import Any

from adcskit.control.tuning import PAPER_SCALE
from adcskit.studies._base import NEUTRAL, NOT_PRINTED, protocol
from adcskit.studies._s4 import S4_LOOP_ATTRIBUTES, S4Loop
from adcskit.uncertainty.sampling import Gaussian, TruncatedGaussian

__all__ = ["Config", "CASE_PARAMS"]

CASE_PARAMS = {
    "inertia": ("inertia",),
    "thrust": ("torque",),
    "disturbance": ("disturbance",),
    "delay": ("delay",),
    "all": ("inertia", "torque", "disturbance", "delay"),
}
# config key holding the Table 5 standard deviation of each uncertain loop input
_STD_KEYS = {"inertia": "std_inertia_kgm2", "torque": "std_torque_nm", "disturbance": "std_disturbance_nm",
             "delay": "std_delay_s"}


_CONFIG_DOC = """Settings of the tuning study (defaults: S4 Tables 3 and 5, printed GA settings).

Every protocol key declares the value S4 prints (``paper=``; ``adcskit config onoff-tuning``
shows ours): a run whose keys differ from a printed value reads "reduced protocol". Our
defaults are below S4's GA protocol (generation cap, LHS samples, evaluation runs) to fit
two CPU cores; ``paper_scale=True`` sets those keys to S4's values.

Table 5 standard deviations: inertia 2 kg m², thrust level 0.2 N m, disturbance
0.05 N m, delay 0.01 s around the Table 3 means. Inertia, thrust level and delay are
truncated Gaussians (kept positive); the disturbance is a plain Gaussian.

``n_seeds`` independent repetitions of the whole pipeline (NSGA-II, robust GA with its own
LHS training draw and seed, fresh evaluation samples) decide every claim.
``penalty_readings``: S4 prints no overshoot penalty; ``"sample"`` penalises each sample's
excess, ``"mean"`` the excess of E[overshoot]; the first is the default reading, the
others are run for the all-four case. ``paper_scale=True`` sets the claim GAs to S4's
protocol (``ga_pop`` 70, ``ga_max_gen`` 1000 with the S4 stopping rule, ``n_lhs`` 1000 LHS
samples per candidate, ``n_mc`` 10 000-run evaluations: ``PAPER_SCALE`` of
:mod:`adcskit.control.tuning`; giving one of these keys another value beside it is an error)
and prints a time estimate first (issue 14's timed probe,
:func:`~adcskit.control.tuning.estimate_tuning_time`); up to ≈ 2 h per case at the
generation cap on two CPU cores (2026-12-02), minutes with ``backend="cuda"`` (robust GA,
evaluations).

Attributes
----------
{loop}\
overshoot_max_pct : float, %
    Overshoot constraint of both optimisations (S4 eq. 9: 10 %).
gain_max : float
    Upper search bound of every gain, each in its own unit (``K_p`` 1/rad, ``K_i``
    1/(rad s), ``K_d`` s/rad; S4 eq. 9: 100); the lower bound is 1e-3.
std_inertia_kgm2 : float, kg m²
    Standard deviation of the inertia (S4 Table 5: 2).
std_torque_nm : float, N m
    Standard deviation of the torque level (S4 Table 5: 0.2).
std_disturbance_nm : float, N m
    Standard deviation of the disturbance torque (S4 Table 5: 0.05).
std_delay_s : float, s
    Standard deviation of the delay (S4 Table 5: 0.01).
nsga_pop, nsga_gen : int
    NSGA-II population and generations of the deterministic front (S4 prints neither).
ga_pop, ga_max_gen : int
    Robust GA population (S4 §4: 70) and generation cap (S4 §4: 1000 iterations).
ga_tol_deg : float, deg
    S4's stopping rule: change of the best objective below this over ``ga_window`` (S4 §4:
    1e-7, unit not printed).
ga_window : int
    Generations of the stopping rule (S4 §4: 10).
n_lhs : int
    LHS training samples per candidate of the robust GA (S4 §4, Fig. 11: 1000 LHS samples
    for the inertia, "the same for the other uncertainties").
penalty_weight_deg_per_pct : float, deg/%
    Weight of the overshoot penalty added to eq. 10 per % of excess over
    ``overshoot_max_pct`` (S4 prints no penalty).
ratio_inertia, ratio_thrust, ratio_disturbance, ratio_delay, ratio_all : float
    Weight ratio ``w2/w1`` of eq. 10 per uncertainty case (S4 Table 6: 25, 22, 15, 10, 180).
sweep_ratios : tuple of float
    ``w2/w1`` values of the all-four ratio sweep (Figs 10-11).
sweep_max_gen : int
    Generation cap of the GA of that sweep.
sweep_cases_max_gen, sweep_cases_n_lhs : int
    Generation cap and LHS samples of the single-uncertainty ratio sweep (Figs 12-13).
sweep_cases_ratios : tuple of float
    ``w2/w1`` values of the single-uncertainty ratio sweep.
n_mc_ratio_cases : int
    Monte-Carlo runs evaluating each gain set of the single-uncertainty sweep.
n_mc : int
    Monte-Carlo runs (fresh samples) evaluating the deterministic and robust gains, per seed
    (S4 §5: 10 000).
std_factors : tuple of float
    Multiples of the Table 5 standard deviations of the spread sweep.
n_mc_sweep : int
    Monte-Carlo runs per point of the ratio and spread sweeps.
command_rates_hz : tuple of float, Hz
    Schmitt evaluation rates of the command-rate claim (S4 §5, Figs 20-21: 50, 200, 1000).
n_mc_rate : int
    Monte-Carlo runs of the command-rate claim, per seed (S4 prints no count for Figs 20-21).
n_mc_order : int
    Monte-Carlo runs of the gain-order check.
task_size : int
    Samples per task handed to the executor.
campaign_dir : str
    Directory for resumable Monte-Carlo campaigns ("" = in memory).
n_seeds : int
    Independent repetitions of the whole pipeline that decide every claim.
penalty_readings : tuple of {{"sample", "mean"}}
    Readings of the overshoot penalty, the default first.
paper_scale : bool
    Set the claim GAs and evaluations to S4's protocol (``PAPER_SCALE``; S4 ran at it).
paper_scale_from_store : bool
    Before a run (:func:`~adcskit.studies.onoff_tuning.resolve_paper_scale`): when
    ``paper_scale`` is false, the GA sizes are ours and the packaged store holds every claim GA
    of the same run at S4's protocol (same seed, fingerprints matching), run at S4's protocol
    instead -- its claims then read "paper protocol" and say which stored run they replay.
    False: always our GA sizes.
ga_store : str
    Stored robust-GA runs (:mod:`~adcskit.studies.onoff_tuning.ga_store`): ``"auto"`` replays
    the paper-scale runs shipped with adcskit when ``paper_scale`` is true and their
    fingerprints match; ``"none"`` runs every GA; a directory is read and written (a long
    paper-scale run resumes there GA by GA).
backend : str
    ``"cpu"``, ``"cuda"`` or ``"auto"`` for the batch simulations.

Examples
--------
>>> Config().ga_max_gen, Config(paper_scale=True).ga_max_gen  # ours, S4's
(30, 1000)
>>> Config(paper_scale=True, n_lhs=200)
Traceback (most recent call last):
...
ValueError: paper_scale=true sets n_lhs to S4's 1000; got n_lhs=200 beside it
"""

#: ``paper_scale=True``: the keys it sets to S4's protocol (``PAPER_SCALE``)
_PAPER_SCALE_KEYS = {"ga_pop": PAPER_SCALE.pop_size, "ga_max_gen": PAPER_SCALE.max_gen,
                     "n_lhs": PAPER_SCALE.n_samples, "n_mc": PAPER_SCALE.n_eval}


@dataclass(frozen=True, kw_only=True)
class Config(S4Loop):
    __doc__ = _CONFIG_DOC.format(loop=textwrap.dedent(S4_LOOP_ATTRIBUTES))

    # loop: S4 Table 3, the 13 keys of S4Loop (first, in its order)
    overshoot_max_pct: float = field(default=10.0, metadata=protocol("tuning", paper=10.0))
    gain_max: float = field(default=100.0, metadata=protocol("tuning", paper=100.0))
    # uncertainty (S4 Table 5)
    std_inertia_kgm2: float = field(default=2.0, metadata=protocol("tuning", paper=2.0))
    std_torque_nm: float = field(default=0.2, metadata=protocol("tuning", paper=0.2))
    std_disturbance_nm: float = field(default=0.05, metadata=protocol("tuning", paper=0.05))
    std_delay_s: float = field(default=0.01, metadata=protocol("tuning", paper=0.01))
    # deterministic NSGA-II (S4 prints no population/generations)
    nsga_pop: int = field(default=60, metadata=protocol("tuning", paper=NOT_PRINTED))
    nsga_gen: int = field(default=60, metadata=protocol("tuning", paper=NOT_PRINTED))
    # robust GA (S4 §4: population 70, 1000 iterations, stop at mean change < 1e-7 over 10; Fig. 11: 1000
    # LHS samples); our cap and sample count are below S4's (two CPU cores): "reduced protocol"
    ga_pop: int = field(default=70, metadata=protocol("tuning", paper=70))
    ga_max_gen: int = field(default=30, metadata=protocol("tuning", paper=1000))
    ga_tol_deg: float = field(default=1e-7, metadata=protocol("tuning", paper=1e-7))
    ga_window: int = field(default=10, metadata=protocol("tuning", paper=10))
    n_lhs: int = field(default=40, metadata=protocol("tuning", paper=1000))
    penalty_weight_deg_per_pct: float = field(default=1.0, metadata=protocol("tuning", paper=NOT_PRINTED))
    # S4 Table 6 weight ratios w2/w1
    ratio_inertia: float = field(default=25.0, metadata=protocol("tuning", paper=25.0))
    ratio_thrust: float = field(default=22.0, metadata=protocol("tuning", paper=22.0))
    ratio_disturbance: float = field(default=15.0, metadata=protocol("tuning", paper=15.0))
    ratio_delay: float = field(default=10.0, metadata=protocol("tuning", paper=10.0))
    ratio_all: float = field(default=180.0, metadata=protocol("tuning", paper=180.0))
    sweep_ratios: tuple[float, ...] = (1.0, 10.0, 50.0, 500.0)
    sweep_max_gen: int = 20
    # ratio sweep of each single uncertainty (Figs 12-13): a lighter GA
    sweep_cases_max_gen: int = 20
    sweep_cases_ratios: tuple[float, ...] = (1.0, 500.0)
    sweep_cases_n_lhs: int = 20
    n_mc_ratio_cases: int = 1000
    # evaluation
    n_mc: int = field(default=2000, metadata=protocol("tuning", paper=10_000))
    std_factors: tuple[float, ...] = (0.25, 0.5, 1.0, 1.5, 2.0)
    n_mc_sweep: int = 1000
    command_rates_hz: tuple[float, ...] = field(default=(50.0, 200.0, 1000.0),
                                               metadata=protocol("command-rates", paper=(50.0, 200.0, 1000.0)))
    n_mc_rate: int = field(default=1000, metadata=protocol("command-rates", paper=NOT_PRINTED))
    n_mc_order: int = 1000
    # execution only (NEUTRAL): the campaigns draw their samples once and tasks carry index ranges, so
    # task_size and campaign_dir leave every number unchanged; backend changes where the kernel
    # runs (CUDA: continuous metrics within ~1e-9 relative, identical firings), not the protocol
    task_size: int = field(default=1000, metadata=NEUTRAL)
    campaign_dir: str = field(default="", metadata=NEUTRAL)
    # verdicts: independent repetitions of the whole pipeline, readings, paper-scale setting
    n_seeds: int = field(default=5, metadata=NEUTRAL)
    penalty_readings: tuple[str, ...] = field(default=("sample", "mean"), metadata=protocol("tuning", paper=NOT_PRINTED))
    paper_scale: bool = field(default=False, metadata=protocol("tuning", paper=True))
    # execution only: a GA read from the store has the fingerprint (every input and a model
    # probe) of the GA it replaces, so the numbers equal a fresh run's
    ga_store: str = field(default="auto", metadata=NEUTRAL)
    # the full run at S4's protocol when every claim GA of it is stored (see resolve_paper_scale)
    paper_scale_from_store: bool = field(default=True, metadata=NEUTRAL)
    backend: str = field(default="cpu", metadata=NEUTRAL)

    def __post_init__(self) -> None:
        super().__post_init__()  # the S4 Table 3 loop keys
        pos = ("step_deg", "overshoot_max_pct", "gain_max", "std_inertia_kgm2", "std_torque_nm",
               "std_disturbance_nm", "std_delay_s", "ga_tol_deg", "ratio_inertia", "ratio_thrust",
               "ratio_disturbance", "ratio_delay", "ratio_all")
        for name in pos:
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0; got {getattr(self, name)!r}")
        ints = {"nsga_pop": 4, "nsga_gen": 1, "ga_pop": 4, "ga_max_gen": 1, "ga_window": 1, "n_lhs": 2,
                "sweep_max_gen": 1, "sweep_cases_max_gen": 1, "sweep_cases_n_lhs": 2,
                "n_mc_ratio_cases": 2, "n_mc": 2, "n_mc_sweep": 2, "n_mc_rate": 2, "n_mc_order": 2,
                "task_size": 1}
        for name, lo in ints.items():
            if getattr(self, name) < lo:
                raise ValueError(f"{name} must be >= {lo}; got {getattr(self, name)!r}")
        for name in ("sweep_ratios", "sweep_cases_ratios"):
            if any(r <= 0 for r in getattr(self, name)):
                raise ValueError(f"{name} must be > 0 each; got {getattr(self, name)!r}")
        if not self.std_factors or any(f < 0 for f in self.std_factors):
            raise ValueError(f"std_factors must be >= 0 and non-empty; got {self.std_factors!r}")
        if not self.command_rates_hz:
            raise ValueError(f"command_rates_hz must not be empty; got {self.command_rates_hz!r}")
        if self.n_seeds < 1:
            raise ValueError(f"n_seeds must be >= 1; got {self.n_seeds!r}")
        if (not self.penalty_readings or len(set(self.penalty_readings)) != len(self.penalty_readings)
                or any(p not in ("sample", "mean") for p in self.penalty_readings)):
            raise ValueError(f"penalty_readings must be distinct values of ('sample', 'mean'); got {self.penalty_readings!r}")
        if not isinstance(self.ga_store, str) or not self.ga_store.strip():
            raise ValueError(f"ga_store must be 'auto', 'none' or a directory; got {self.ga_store!r}")
        if self.backend not in ("cpu", "cuda", "auto"):
            raise ValueError(f"backend must be 'cpu', 'cuda' or 'auto'; got {self.backend!r}")
        if not isinstance(self.paper_scale_from_store, bool):
            raise ValueError(f"paper_scale_from_store must be true or false; got {self.paper_scale_from_store!r}")
        if not isinstance(self.paper_scale, bool):
            raise ValueError(f"paper_scale must be true or false; got {self.paper_scale!r}")
        if self.paper_scale:  # S4's protocol in the keys themselves, so the resolved config says what ran
            ours = {f.name: f.default for f in fields(self)}
            for name, value in _PAPER_SCALE_KEYS.items():
                if getattr(self, name) not in (ours[name], value):
                    raise ValueError(f"paper_scale=true sets {name} to S4's {value}; got {name}={getattr(self, name)!r} "
                                     "beside it")
                object.__setattr__(self, name, value)

    def ratio(self, case: str) -> float:
        return float(getattr(self, f"ratio_{case}"))

    def dists(self, case: str, factor: float = 1.0) -> dict[str, Any]:
        table5 = {
            "inertia": TruncatedGaussian(mean=self.inertia_kgm2, std=factor * self.std_inertia_kgm2, low=1e-3 * self.inertia_kgm2),
            "torque": TruncatedGaussian(mean=self.torque_nm, std=factor * self.std_torque_nm, low=1e-3 * self.torque_nm),
            "disturbance": Gaussian(mean=self.disturbance_nm, std=factor * self.std_disturbance_nm),
            "delay": TruncatedGaussian(mean=self.delay_s, std=factor * self.std_delay_s, low=0.0),
        }
        return {k: table5[k] for k in CASE_PARAMS[case]}

    def input_std(self, case: str) -> float:
        return float(getattr(self, _STD_KEYS[CASE_PARAMS[case][0]])) if case != "all" else 1.0
