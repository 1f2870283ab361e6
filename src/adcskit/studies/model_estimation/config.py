"""Settings of the ``model-estimation`` study: the methods, readings and :class:`Config`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

from adcskit.studies._base import NEUTRAL, NOT_PRINTED, protocol, protocol_keys
from adcskit.studies.model_estimation.paper import CASES

__all__ = ["Config", "KRYLOV", "METHODS", "PRIOR_BASELINES", "READINGS", "FINDING_KEYS"]


#: Methods of the study, in table order (paper's first, then the baselines it omits).
METHODS = (
    "gmres", "bicg", "bicgstab", "cgs", "qr", "lsqr",
    "adaptive-gmres-offline", "adaptive-gmres-online",
    "ridge-prior", "rls", "augmented-ekf",
    "ridge-prior-discrepancy", "rls-prior",
)
#: Study method -> library method of :func:`adcskit.estimation.joint_estimate`.
_IMPL = {"ridge-prior-discrepancy": "ridge-prior", "rls-prior": "rls"}
#: Prior-anchored baselines S1 omits (the EKF is counted apart: it knows the model structure).
PRIOR_BASELINES = ("ridge-prior", "ridge-prior-discrepancy", "rls-prior")
#: Readings of S1's ambiguities; "default" is ours (see the doc page).
READINGS = ("default", "spacecraft changed", "per-axis inertia", "step dominant", "low noise", "S1-like Krylov")
#: The standard solvers the "S1-like Krylov" reading caps (QR is direct: it has no iterations to cap).
KRYLOV = ("gmres", "bicg", "bicgstab", "cgs")


@dataclass(frozen=True, kw_only=True)
class Config:
    """Settings of the ``model-estimation`` study (defaults: S1's settings or stated choices).

    Attributes
    ----------
    n_seeds : int
        Independent noise/input realisations per case (S1: "different simulations").
    n_steps : int
        Manoeuvre length ``L`` in steps of ``dt_s`` (S1 does not state it; its figures show
        the estimates settling after ~100 s).
    dt_s : float, s
        Sample time of the 3-DOF model (S1: ``dt = 1``; the 1-DOF model is S1 eq. 3 as printed,
        whose step is fixed at 1 s).
    cases : tuple of str
        Scenarios to run, a subset of :data:`CASES` (S1: 1-DOF random and step input, 3-DOF
        random and sinusoidal input).
    methods : tuple of str
        Estimators to run, a subset of :data:`METHODS` (S1's seven and our baselines).
    noise_std : float
        Measurement-noise standard deviation on every state, in each state's own unit (S1
        eq. 2: ``v ~ N(0, 1)``): one number for angles and rates alike (rad and rad/s in the
        3-DOF model), so the key has no unit suffix.
    noise_std_low : float
        Second, realistic level, in the same units (0 disables it).
    inertia_kgm2 : tuple of 3 float, kg m^2
        True principal moments (S1: 82, 80, 4).
    altitude_km : float, km
        Circular-orbit altitude for the orbit rate (S1: LEO, value not stated).
    inertia_error : float
        The prior model assumes inertias ``(1 + inertia_error)`` times the truth (S1: 50 %).
    model_3dof : {"physics", "printed"}
        True 3-DOF model: built from physics (default) or S1 eq. (13) as printed.
    gyroscopic : {"derived", "printed"}
        Gyroscopic matrix of the physics model (S1 eq. 10 prints a sign error).
    kalman_q : float
        Kalman process-noise variance per state, in the squared units of ``noise_std``
        (``Q = kalman_q * I``); S1 leaves it unspecified.
    krylov_rtol : float
        Stopping tolerance of the standard Krylov solvers (normal equations).
    alpha0 : float
        Search half-width of the online adaptive GMRES (S1 Alg. 21; not stated in S1).
    rls_forgetting : float
        RLS forgetting factor, in (0, 1].
    rls_delta : float
        Scale of the RLS initial covariance ``P0 = rls_delta * I``.
    ridge_rule : {"gcv", "discrepancy"}
        How the ridge weight is chosen (never from the truth).
    step_level_nm : float, N m
        Level of the step in ``1dof-step`` (plus N(0, 1) noise, S1 Fig. 7).
    sine_amplitude_nm : float, N m
        Amplitude of the per-axis sinusoidal torque of ``3dof-sine`` (S1 gives none).
    sine_omega_rad_s : tuple of 3 float, rad/s
        Per-axis sinusoid frequencies of ``3dof-sine`` (S1 gives none).
    ekf_q_param : float
        Random-walk variance per step of the inertia ratios (truth / prior, dimensionless) in
        the augmented EKF.
    inertia_direction : {"prior", "truth"}
        Which model carries the 50 % inertia change: ``"prior"`` — the truth is the printed
        model and the prior ``A0`` has the inertias ``(1 + inertia_error)`` times larger;
        ``"truth"`` — S1's wording ("pre-change model" A0): the prior is the printed model
        and the spacecraft's inertias changed by ``(1 + inertia_error)``.
    inertia_axes : {"uniform", "transverse"}
        Which moments change: all three equally (which leaves ``M^-1 L`` and ``M^-1 N``
        unchanged: only the control path ``M^-1 K`` moves), or only the transverse ``Ix, Iy``
        (``Iz`` kept: the physical triangle inequality ``Ix <= Iy + Iz`` then still holds).
        The 1-DOF model has one inertia.
    step_level_dominant_nm : float, N m
        Step level of the ``"step dominant"`` reading (input noise N(0, 1) stays).
    s1_krylov_maxiter : int
        Iterations per time step of the four standard Krylov solvers in the ``"S1-like
        Krylov"`` reading (warm-started from the previous estimate, as S1 says its GMRES is).
        Default 1: the smallest per-step count S1 prints for its GMRES on this system (the
        opening phase of its offline schedule), and the only count that leaves a Krylov
        solver unconverged on the 1-DOF model, which two steps solve exactly.
    readings : tuple of str
        Alternative readings to run beside the default (subset of ``READINGS[1:]``): each
        changes one choice — ``"spacecraft changed"`` (``inertia_direction="truth"``),
        ``"per-axis inertia"`` (``inertia_axes="transverse"``, 3-DOF cases), ``"step dominant"``
        (``step_level_nm = step_level_dominant_nm``, ``1dof-step``), ``"low noise"``
        (``noise_std = noise_std_low``), ``"S1-like Krylov"`` (GMRES, Bi-CG, CGS, Bi-CGSTAB stop
        after ``s1_krylov_maxiter`` iterations per time step; every other method as in the
        default).
    """

    n_seeds: int = field(default=10, metadata=NEUTRAL)
    n_steps: int = field(default=200, metadata=protocol("claims", paper=NOT_PRINTED))
    dt_s: float = field(default=1.0, metadata=protocol("3dof", paper=1.0))  # S1 eq. 2: dt = 1
    cases: tuple[str, ...] = field(default=CASES, metadata=protocol("claims", paper=CASES))
    methods: tuple[str, ...] = METHODS
    noise_std: float = field(default=1.0, metadata=protocol("claims", paper=1.0))  # S1 eq. 2
    noise_std_low: float = 0.01
    inertia_kgm2: tuple[float, float, float] = field(default=(82.0, 80.0, 4.0),
                                                     metadata=protocol("3dof", paper=(82.0, 80.0, 4.0)))
    altitude_km: float = field(default=500.0, metadata=protocol("3dof", paper=NOT_PRINTED))  # S1: "LEO"
    inertia_error: float = field(default=0.5, metadata=protocol("claims", paper=0.5))  # "50 %"
    # S1 simulates its own model, printed as eq. (13); ours is built from eq. (8)-(12) (matches eq. 13 to ~1 %)
    model_3dof: Literal["physics", "printed"] = field(default="physics", metadata=protocol("3dof", paper="printed"))
    # S1 eq. (10) prints a symmetric gyroscopic matrix (a sign error); ours is derived
    gyroscopic: Literal["derived", "printed"] = field(default="derived", metadata=protocol("3dof", paper="printed"))
    kalman_q: float = field(default=1e-4, metadata=protocol("claims", paper=NOT_PRINTED))
    krylov_rtol: float = field(default=1e-8, metadata=protocol("claims", paper=NOT_PRINTED))
    alpha0: float = field(default=0.5, metadata=protocol("adaptive", paper=NOT_PRINTED))  # "sensitive"
    rls_forgetting: float = 0.99
    rls_delta: float = 100.0
    ridge_rule: Literal["gcv", "discrepancy"] = "gcv"
    step_level_nm: float = field(default=1.0, metadata=protocol("claims", paper=NOT_PRINTED))
    sine_amplitude_nm: float = field(default=1.0, metadata=protocol("3dof", paper=NOT_PRINTED))
    sine_omega_rad_s: tuple[float, float, float] = field(default=(0.05, 0.08, 0.13),
                                                         metadata=protocol("3dof", paper=NOT_PRINTED))
    ekf_q_param: float = 1e-6
    inertia_direction: Literal["prior", "truth"] = "prior"
    inertia_axes: Literal["uniform", "transverse"] = "uniform"
    step_level_dominant_nm: float = 10.0
    s1_krylov_maxiter: int = field(default=1, metadata=protocol("claims", paper=NOT_PRINTED))
    readings: tuple[str, ...] = READINGS[1:]

    def __post_init__(self) -> None:
        if self.n_seeds < 1:
            raise ValueError(f"n_seeds must be >= 1; got {self.n_seeds}")
        if self.n_steps < 20:
            raise ValueError(f"n_steps must be >= 20 (the 3-DOF regression has 6 unknowns per row); got {self.n_steps}")
        if not self.dt_s > 0:
            raise ValueError(f"dt_s must be > 0 s; got {self.dt_s}")
        for c in self.cases:
            if c not in CASES:
                raise ValueError(f"cases must be a subset of {CASES}; got {c!r}")
        for m in self.methods:
            if m not in METHODS:
                raise ValueError(f"methods must be a subset of {METHODS}; got {m!r}")
        if not self.noise_std > 0:
            raise ValueError(f"noise_std must be > 0; got {self.noise_std!r}")
        if not self.noise_std_low >= 0:
            raise ValueError(f"noise_std_low must be >= 0; got {self.noise_std_low!r}")
        if min(self.inertia_kgm2) <= 0:
            raise ValueError(f"inertia_kgm2 must be positive (kg m^2); got {self.inertia_kgm2}")
        if not -1 < self.inertia_error:
            raise ValueError(f"inertia_error must be > -1; got {self.inertia_error}")
        if not 0 <= self.alpha0 <= 1:
            raise ValueError(f"alpha0 must be in [0, 1]; got {self.alpha0}")
        if not 0 < self.rls_forgetting <= 1:
            raise ValueError(f"rls_forgetting must be in (0, 1]; got {self.rls_forgetting}")
        for name, strict in (("kalman_q", False), ("ekf_q_param", False), ("krylov_rtol", True), ("rls_delta", True)):
            v = getattr(self, name)
            if not (v > 0 if strict else v >= 0):
                raise ValueError(f"{name} must be {'>' if strict else '>='} 0; got {v!r}")
        if self.altitude_km < 0:
            raise ValueError(f"altitude_km must be >= 0 km; got {self.altitude_km}")
        if self.inertia_direction not in ("prior", "truth"):
            raise ValueError(f"inertia_direction must be 'prior' or 'truth'; got {self.inertia_direction!r}")
        if self.inertia_axes not in ("uniform", "transverse"):
            raise ValueError(f"inertia_axes must be 'uniform' or 'transverse'; got {self.inertia_axes!r}")
        for r in self.readings:
            if r not in READINGS[1:]:
                raise ValueError(f"readings must be a subset of {READINGS[1:]}; got {r!r}")
        if isinstance(self.s1_krylov_maxiter, bool) or not isinstance(self.s1_krylov_maxiter, int) \
                or self.s1_krylov_maxiter < 1:
            raise ValueError(f"s1_krylov_maxiter must be an integer >= 1; got {self.s1_krylov_maxiter!r}")
        if "low noise" in self.readings and not self.noise_std_low > 0:
            raise ValueError(f"noise_std_low must be > 0 with the 'low noise' reading; got {self.noise_std_low!r}")


#: Protocol of our findings (the doc page's answers): every key but ``n_seeds``, which only adds
#: evidence. A finding compares estimators on the documented scenario, so a changed estimator
#: setting, case list or reading changes the question.
FINDING_KEYS = protocol_keys(Config)
