"""Settings of the ``closed-loop`` study (:class:`Config`)."""

from __future__ import annotations

from dataclasses import dataclass, field

from adcskit.config import ConfigError
from adcskit.errors import InputError
from adcskit.studies._base import NEUTRAL, NOT_PRINTED, protocol
from adcskit.uncertainty import read_requirements

__all__ = ["Config", "Q6_REQUIREMENTS"]

#: Field metadata of every setting that defines the study's scenarios: no paper closes the loop,
#: so no paper prints these settings (the printed numbers the scenarios reuse are in ``paper.py``);
#: the findings are our questions and their protocol is ours.
_OURS = protocol("findings", paper=NOT_PRINTED)
#: The keys of question 5 (wheels vs the S4 thruster loop; our question, no paper prints them).
_Q5 = "q5-wheels-vs-thrusters"
#: Keys shared by the findings and question 5 (the S4 plant's step, duration and sample count).
_OURS_Q5 = protocol("findings", _Q5, paper=NOT_PRINTED)
#: The keys of question 6 (the 12U reference mode sequence against its sign-off table; ours).
_Q6 = "q6-reference-mode-sequence"
#: Q6's default sign-off table: the reference Monte-Carlo's table of ``docs/wheels.md`` and
#: ``benchmarks/bench_wheels.py`` (metrics of :class:`adcskit.simulation.WheelSimulationResult`;
#: the third orbit, from 11 400 s, is the reference scenario's metrics window).
Q6_REQUIREMENTS = (
    "Q6-1: pointing_max_deg p99 <= 0.2 after 11400 s",
    "Q6-2: pointing_rms_deg p99 <= 0.1 after 11400 s",
    "Q6-3: knowledge_rms_deg p99 <= 0.02 after 11400 s",
    "Q6-4: P(t_acquired_s > 11400) <= 1 %",
    "Q6-5: max_wheel_speed_rpm max <= 6000",
)


@dataclass(frozen=True, kw_only=True)
class Config:
    """Settings of the closed-loop study.

    Attributes
    ----------
    n_seeds : int
        Independent seeds of the whole pipeline per finding (>= 5 at full settings).
    n_samples : int
        Monte-Carlo samples per configuration and seed.
    geo_dt_s, geo_t_final_s : float, s
        GEO step and duration (questions 1 and 4).
    geo_slew_deg : float, deg
        Question 1: step about the (1, 1, 1) axis, then hold.
    geo_torque_level_nm : float, N m
        Schmitt torque level per axis on the GEO spacecraft.
    geo_srp_torque_nm : float, N m
        Amplitude of the solar-pressure-like torque (constant + orbit-periodic part; S3
        names the torques but prints no value).
    layout_pop, layout_gens : int
        Differential evolution for the S3-optimised 6-thruster layout (S3 eq. 18).
    leo_dt_s, leo_t_final_s, leo_window_s : float, s
        Question 2 (S0 LEO); pointing statistics over the last ``leo_window_s``.
    s4_dt_s, s4_t_final_s : float, s
        Question 3 (S4's 30 s step, statistics over the last 10 s).
    switch_tc_s : float, s
        GEO and LEO: S4's Schmitt loop keeps Table 4's ``K_p`` and ``K_i`` with
        ``K_d = switch_tc_s K_p`` (the switching line ``e + (K_d/K_p) de/dt = 0``); S4's own
        ``K_d/K_p = 0.89 s`` suits its plant's angular acceleration (T/J = 0.1 rad/s^2), 12x
        that of the GEO spacecraft with 10 N m per axis, and overshoots there.
    command_period_s : float, s
        GEO and LEO command (sample-and-hold) period of the Schmitt loop: S4's 50 Hz. At S3's
        t_s = 0.2 s a held pulse changes ``K_d omega`` by more than the Schmitt hysteresis on
        the low-inertia y axis and the loop chatters between opposite thrusters.
    slew_deg : float, deg
        Question 4: slew about the body z axis.
    slew_accel_fraction : float
        Question 4: the optimal profile uses this fraction of the torque level's angular
        acceleration.
    q5_wheel_bandwidth_rad_s : float, rad/s
        Question 5: natural frequency ``omega_n`` of the wheels' quaternion PD on S4's
        spacecraft (``k = omega_n^2``, ``c = 2 zeta omega_n``; Wie 2008, §7.3). The PD has no
        integral: S4's constant disturbance ``d`` leaves a bias of about ``sqrt(3) d / (J omega_n^2)``
        rad (0.50 deg at 1 rad/s, 0.13 deg at 2 rad/s), which decides Q5 (see the docs page).
    q5_wheel_damping : float
        Question 5: damping ratio ``zeta`` of the wheels' PD.
    q5_wheel_momentum_nms : float, N m s
        Question 5: momentum capacity of each of the four pyramid wheels at 6000 rpm.
    q5_pointing_req_deg : float, deg
        Question 5: requirement on the p99 over samples of the per-sample largest pointing
        error over S4's last 10 s (the sign-off table of both loops; half of it bounds the RMS).
    q6_n_samples : int
        Question 6: Monte-Carlo samples per seed of the 12U reference mode sequence
        (:class:`adcskit.simulation.WheelScenario` with the reference dispersions of
        ``docs/wheels.md``; about 0.07 CPU-s per sample). A p99 row needs >= 299 samples for a
        95 % bound at all (Wilks).
    q6_requirements : tuple of str
        Question 6: the sign-off table (one line each,
        :func:`adcskit.uncertainty.parse_requirement`; metrics of
        :class:`adcskit.simulation.WheelSimulationResult`, windowed ones after 11 400 s).
    q6_record_every : int
        Question 6: steps between recorded trace points (and the grid of the wheel-momentum
        checks) of the reference scenario; the first seed's campaign is recorded for the
        envelope figure.
    record_samples : int
        Samples whose time histories are kept for the figures.
    """

    n_seeds: int = field(default=5, metadata=NEUTRAL)
    n_samples: int = field(default=1000, metadata=_OURS_Q5)
    geo_dt_s: float = field(default=0.02, metadata=_OURS)
    geo_t_final_s: float = field(default=45.0, metadata=_OURS)
    geo_slew_deg: float = field(default=5.0, metadata=_OURS)
    geo_torque_level_nm: float = field(default=10.0, metadata=_OURS)
    geo_srp_torque_nm: float = field(default=5e-5, metadata=_OURS)
    layout_pop: int = field(default=30, metadata=_OURS)
    layout_gens: int = field(default=150, metadata=_OURS)
    leo_dt_s: float = field(default=0.02, metadata=_OURS)
    leo_t_final_s: float = field(default=60.0, metadata=_OURS)
    leo_window_s: float = field(default=30.0, metadata=_OURS)
    s4_dt_s: float = field(default=0.005, metadata=_OURS_Q5)
    s4_t_final_s: float = field(default=30.0, metadata=_OURS_Q5)
    switch_tc_s: float = field(default=5.0, metadata=_OURS)
    command_period_s: float = field(default=0.02, metadata=_OURS)
    slew_deg: float = field(default=20.0, metadata=_OURS)
    slew_accel_fraction: float = field(default=0.7, metadata=_OURS)
    q5_wheel_bandwidth_rad_s: float = field(default=2.0, metadata=protocol(_Q5, paper=NOT_PRINTED))
    q5_wheel_damping: float = field(default=0.9, metadata=protocol(_Q5, paper=NOT_PRINTED))
    q5_wheel_momentum_nms: float = field(default=4.0, metadata=protocol(_Q5, paper=NOT_PRINTED))
    q5_pointing_req_deg: float = field(default=0.25, metadata=protocol(_Q5, paper=NOT_PRINTED))
    q6_n_samples: int = field(default=1000, metadata=protocol(_Q6, paper=NOT_PRINTED))
    q6_requirements: tuple[str, ...] = field(default=Q6_REQUIREMENTS, metadata=protocol(_Q6, paper=NOT_PRINTED))
    q6_record_every: int = field(default=250, metadata=protocol(_Q6, paper=NOT_PRINTED))
    # record_samples only sizes the recorded traces drawn in the figures (no finding uses them)
    record_samples: int = field(default=32, metadata=NEUTRAL)

    def __post_init__(self) -> None:
        for name, lo in (("n_seeds", 1), ("n_samples", 2), ("record_samples", 1)):
            if getattr(self, name) < lo:
                raise ConfigError(f"{name} must be >= {lo}; got {getattr(self, name)!r}")
        for name in ("geo_dt_s", "geo_t_final_s", "geo_slew_deg", "geo_torque_level_nm", "leo_dt_s", "leo_t_final_s",
                     "leo_window_s", "s4_dt_s", "s4_t_final_s", "slew_deg", "switch_tc_s", "command_period_s",
                     "q5_wheel_bandwidth_rad_s", "q5_wheel_damping", "q5_wheel_momentum_nms", "q5_pointing_req_deg"):
            if not getattr(self, name) > 0:
                raise ConfigError(f"{name} must be > 0; got {getattr(self, name)!r}")
        for name, lo in (("q6_n_samples", 2), ("q6_record_every", 1)):
            if getattr(self, name) < lo:
                raise ConfigError(f"{name} must be >= {lo}; got {getattr(self, name)!r}")
        if isinstance(self.q6_requirements, str) or not self.q6_requirements:
            raise ConfigError(f"q6_requirements must be a non-empty list of requirement lines; got "
                              f"{self.q6_requirements!r}")
        try:
            read_requirements(list(self.q6_requirements))
        except (InputError, TypeError) as exc:
            raise ConfigError(f"q6_requirements: {exc}") from exc
        object.__setattr__(self, "q6_requirements", tuple(self.q6_requirements))
        if not 0 < self.slew_accel_fraction <= 1:
            raise ConfigError(f"slew_accel_fraction must be in (0, 1]; got {self.slew_accel_fraction!r}")
        if self.leo_window_s >= self.leo_t_final_s:
            raise ConfigError(f"leo_window_s must be < leo_t_final_s = {self.leo_t_final_s!r} s; "
                              f"got {self.leo_window_s!r}")
        if self.s4_t_final_s <= 10.0:
            raise ConfigError(f"s4_t_final_s must exceed S4's 10 s statistics window; got {self.s4_t_final_s!r}")
