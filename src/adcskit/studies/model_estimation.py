"""Study ``model-estimation``: S1 Table 1 — joint Kalman state and A-matrix estimation.

Every identification method (QR, GMRES, Bi-CG, CGS, Bi-CGSTAB, LSQR, S1's offline and
online adaptive GMRES, ridge toward the prior, RLS, and an augmented-state EKF that
estimates the inertia ratios) runs S1's joint loop on the *same* simulated manoeuvre, for
the cases ``1dof-random``, ``1dof-step``, ``3dof-random``, ``3dof-sine`` and many seeds.
The error is S1's ``e = 100 ||A_hat - A||_2 / ||A||_2`` at the end of the manoeuvre.

Models (see ``docs/studies/model-estimation.md`` for every choice):

* 1-DOF: S1 eq. (3) as printed, ``A = [[1, 1], [-1, -1]]``, ``B = [0, 2.66]^T``. It equals
  ``I + A_c`` with ``A_c = [[0, 1], [-kp/I, -kd/I]]``, ``kp/I = 1``, ``kd/I = 2`` (a forward-Euler
  step of 1 s of a PD loop with a double pole at -1 rad/s), which is why it is nilpotent
  (deadbeat). The prior ``A0`` is the same loop with the inertia 50 % larger.
* 3-DOF: S1 eq. (8)-(12) from physics (``adcskit.dynamics.lvlh_attitude_model``, derived
  skew gyroscopic matrix), per-axis PD gains from ``scipy.signal.place_poles`` with the eq.
  (12) poles, Crank-Nicolson with ``dt = 1 s``. This reproduces the printed eq. (13) ``A``
  to about 1 % (the printed ``B`` is the continuous ``M^-1``). The prior uses the same gains
  with all moments of inertia 50 % larger.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Any, Literal

import numpy as np
import scipy.signal as sig

from adcskit.dynamics import discretize, lvlh_attitude_model, orbit_rate
from adcskit.estimation import augmented_ekf, identify_model, joint_estimate, simulate_linear
from adcskit.studies._base import Check, Comparison, Study, StudyResult, new_figure
from adcskit.studies._verdict import ClaimSpec, FindingSpec

__all__ = ["Config", "run", "STUDY", "CASES", "METHODS", "build_case"]

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
READINGS = ("default", "spacecraft changed", "per-axis inertia", "step dominant", "low noise")
PAPER_METHODS = ("gmres", "bicg", "bicgstab", "cgs", "qr", "adaptive-gmres-offline", "adaptive-gmres-online")
STANDARD = ("gmres", "bicg", "bicgstab", "cgs", "qr")
CASES = ("1dof-random", "1dof-step", "3dof-random", "3dof-sine")

#: S1 Table 1 (% error), with the 3-DOF sinusoid range from the text next to Fig. 13.
PAPER_TABLE: dict[str, dict[str, dict[str, float]]] = {
    "gmres": {"1dof-random": {"value": 79}, "1dof-step": {"value": 194}, "3dof-random": {"value": 82}},
    "bicg": {"1dof-random": {"value": 80}, "1dof-step": {"value": 195}, "3dof-random": {"value": 91}},
    "bicgstab": {"1dof-random": {"value": 115}, "1dof-step": {"value": 195}, "3dof-random": {"value": 89}},
    "cgs": {"1dof-random": {"value": 37}, "1dof-step": {"value": 194}, "3dof-random": {"value": 61}},
    "qr": {"1dof-random": {"value": 99}, "1dof-step": {"value": 195}, "3dof-random": {"value": 97}},
    "adaptive-gmres-offline": {
        "1dof-random": {"min": 4, "max": 8}, "1dof-step": {"min": 6, "max": 9}, "3dof-random": {"min": 6, "max": 15},
    },
    "adaptive-gmres-online": {
        "1dof-random": {"min": 1, "max": 4}, "1dof-step": {"min": 2, "max": 5}, "3dof-random": {"min": 8, "max": 16},
        "3dof-sine": {"min": 9, "max": 16},
    },
}

#: S1 eq. (12) poles, assigned per axis from the eigenstructure of the printed eq. (13):
#: roll, pitch, yaw.
AXIS_POLES = (
    (-0.2041 + 0.4115j, -0.2041 - 0.4115j),
    (-0.2536 + 0.4550j, -0.2536 - 0.4550j),
    (-0.5441, -7.5034),
)

#: S1 eq. (13), printed discrete closed-loop matrices.
A13 = np.array([
    [0.91, 0, 0, 0.79, 0, 0],
    [0, 0.89, 0, 0, 0.75, 0],
    [-3.2e-4, 0, 0.66, -3.1e-4, 0, 0.16],
    [-0.16, 0, 0, 0.59, 0, 0],
    [0, -0.205, 0, 0, 0.51, 0],
    [-6e-4, 0, -0.66, -6e-4, 0, -0.67],
])
B13 = np.vstack([np.zeros((3, 3)), np.diag([0.012, 0.0125, 0.25])])


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
    readings : tuple of str
        Alternative readings to run beside the default (subset of ``READINGS[1:]``): each
        changes one choice — ``"spacecraft changed"`` (``inertia_direction="truth"``),
        ``"per-axis inertia"`` (``inertia_axes="transverse"``, 3-DOF cases), ``"step dominant"``
        (``step_level_nm = step_level_dominant_nm``, ``1dof-step``), ``"low noise"``
        (``noise_std = noise_std_low``).
    """

    n_seeds: int = 10
    n_steps: int = 200
    dt_s: float = 1.0
    cases: tuple[str, ...] = CASES
    methods: tuple[str, ...] = METHODS
    noise_std: float = 1.0
    noise_std_low: float = 0.01
    inertia_kgm2: tuple[float, float, float] = (82.0, 80.0, 4.0)
    altitude_km: float = 500.0
    inertia_error: float = 0.5
    model_3dof: Literal["physics", "printed"] = "physics"
    gyroscopic: Literal["derived", "printed"] = "derived"
    kalman_q: float = 1e-4
    krylov_rtol: float = 1e-8
    alpha0: float = 0.5
    rls_forgetting: float = 0.99
    rls_delta: float = 100.0
    ridge_rule: Literal["gcv", "discrepancy"] = "gcv"
    step_level_nm: float = 1.0
    sine_amplitude_nm: float = 1.0
    sine_omega_rad_s: tuple[float, float, float] = (0.05, 0.08, 0.13)
    ekf_q_param: float = 1e-6
    inertia_direction: Literal["prior", "truth"] = "prior"
    inertia_axes: Literal["uniform", "transverse"] = "uniform"
    step_level_dominant_nm: float = 10.0
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
        if not self.noise_std > 0 or self.noise_std_low < 0:
            raise ValueError("noise_std must be > 0 and noise_std_low >= 0")
        if min(self.inertia_kgm2) <= 0:
            raise ValueError(f"inertia_kgm2 must be positive (kg m^2); got {self.inertia_kgm2}")
        if not -1 < self.inertia_error:
            raise ValueError(f"inertia_error must be > -1; got {self.inertia_error}")
        if not 0 <= self.alpha0 <= 1:
            raise ValueError(f"alpha0 must be in [0, 1]; got {self.alpha0}")
        if not 0 < self.rls_forgetting <= 1:
            raise ValueError(f"rls_forgetting must be in (0, 1]; got {self.rls_forgetting}")
        if self.kalman_q < 0 or self.krylov_rtol <= 0 or self.rls_delta <= 0 or self.ekf_q_param < 0:
            raise ValueError("kalman_q, ekf_q_param must be >= 0; krylov_rtol, rls_delta > 0")
        if self.altitude_km < 0:
            raise ValueError(f"altitude_km must be >= 0 km; got {self.altitude_km}")
        if self.inertia_direction not in ("prior", "truth"):
            raise ValueError(f"inertia_direction must be 'prior' or 'truth'; got {self.inertia_direction!r}")
        if self.inertia_axes not in ("uniform", "transverse"):
            raise ValueError(f"inertia_axes must be 'uniform' or 'transverse'; got {self.inertia_axes!r}")
        for r in self.readings:
            if r not in READINGS[1:]:
                raise ValueError(f"readings must be a subset of {READINGS[1:]}; got {r!r}")
        if "low noise" in self.readings and not self.noise_std_low > 0:
            raise ValueError("the 'low noise' reading needs noise_std_low > 0")


#: Protocol of our findings (the doc page's answers): every key but ``n_seeds``, which only adds
#: evidence. A finding compares estimators on the documented scenario, so a changed estimator
#: setting, case list or reading changes the question.
FINDING_KEYS = tuple(f.name for f in fields(Config) if f.name != "n_seeds")


# --------------------------------------------------------------------------- scenario


def _model_1dof(scale: float):
    """1-DOF discrete model for inertia ``scale`` x the true one (scale 1: S1 eq. 3)."""
    r = 1.0 / scale
    return np.array([[1.0, 1.0], [-r, 1.0 - 2.0 * r]]), np.array([[0.0], [2.66 * r]])


def _axis_gains(inertia, n, gyroscopic):
    """Per-axis PD gains by ``scipy.signal.place_poles`` on each decoupled axis (K: 3 x 6)."""
    A, _ = lvlh_attitude_model(inertia, n, printed=gyroscopic == "printed")
    K = np.zeros((3, 6))
    for i, poles in enumerate(AXIS_POLES):
        Ai = np.array([[0.0, 1.0], [A[3 + i, i], 0.0]])
        Bi = np.array([[0.0], [1.0 / inertia[i]]])
        k = sig.place_poles(Ai, Bi, np.array(poles)).gain_matrix
        K[i, i], K[i, 3 + i] = k[0]
    return K


@dataclass(frozen=True)
class _Case:
    name: str
    A: np.ndarray  # truth
    B: np.ndarray
    A0: np.ndarray  # prior
    model: Any  # p -> (A, B), p = inertia ratio true/assumed (prior p = 1)
    n_param: int
    p_true: np.ndarray
    input_kind: str


class _Model3:
    """Picklable 3-DOF closed-loop model as a function of inertia scale factors."""

    def __init__(self, inertia, n, K, dt, gyroscopic, base_scale):
        self.inertia, self.n, self.K, self.dt = np.asarray(inertia, float), n, K, dt
        self.printed = gyroscopic == "printed"
        self.base = base_scale

    def __call__(self, p):
        return self.reference(p) if self.slow else self._fast(p)

    slow = False

    def reference(self, p):
        """Through the public dynamics API (validated; used by the tests as the oracle)."""
        Ac, Bc = lvlh_attitude_model(self.inertia * self.base * np.asarray(p, float), self.n, printed=self.printed)
        return discretize(Ac - Bc @ self.K, Bc, self.dt, "crank-nicolson")

    def _fast(self, p):
        # Same equations as adcskit.dynamics.lvlh_attitude_model + discretize(crank-nicolson)
        # without their boundary validation: the augmented EKF calls this 7 times per step
        # (central differences), where validation cost ~5x the arithmetic.
        Ix, Iy, Iz = self.inertia * self.base * np.asarray(p, float)
        n = self.n
        g = n * (-Ix + Iy - Iz) if self.printed else n * (Ix - Iy + Iz)
        Nm = g * (np.array([[0.0, 0, 1], [0, 0, 0], [1, 0, 0]]) if self.printed
                  else np.array([[0.0, 0, -1], [0, 0, 0], [1, 0, 0]]))
        Lm = n * n * np.diag([4 * (Iy - Iz), 3 * (Ix - Iz), Iy - Ix])
        Minv = np.diag([1 / Ix, 1 / Iy, 1 / Iz])
        Ac = np.zeros((6, 6))
        Ac[:3, 3:] = np.eye(3)
        Ac[3:, :3] = -Minv @ Lm
        Ac[3:, 3:] = -Minv @ Nm
        Bc = np.zeros((6, 3))
        Bc[3:] = Minv
        Acl = Ac - Bc @ self.K
        lhs = np.eye(6) - 0.5 * self.dt * Acl
        sol = np.linalg.solve(lhs, np.hstack([np.eye(6) + 0.5 * self.dt * Acl, self.dt * Bc]))
        return sol[:, :6], sol[:, 6:]


class _Model1:
    def __init__(self, base_scale):
        self.base = base_scale

    def __call__(self, p):
        return _model_1dof(self.base * float(p[0]))


def inertia_scales(cfg: Config) -> tuple[np.ndarray, np.ndarray]:
    """Per-axis inertia scale factors ``(truth, prior)`` relative to the printed model."""
    s = 1.0 + cfg.inertia_error
    f = np.array([s, s, s]) if cfg.inertia_axes == "uniform" else np.array([s, s, 1.0])
    one = np.ones(3)
    return (one, f) if cfg.inertia_direction == "prior" else (f, one)


def build_case(name: str, cfg: Config) -> _Case:
    """Truth, prior and parameterised model of one case (see the module docstring).

    The model's parameter ``p`` is the inertia ratio truth / prior per axis (prior: ``p = 1``).
    """
    f_true, f_prior = inertia_scales(cfg)
    if name.startswith("1dof"):
        A, B = _model_1dof(f_true[0])
        A0, _ = _model_1dof(f_prior[0])
        return _Case(name, A, B, A0, _Model1(f_prior[0]), 1, np.array([f_true[0] / f_prior[0]]), name.split("-")[1])
    n = orbit_rate(cfg.altitude_km * 1e3)
    inertia = np.array(cfg.inertia_kgm2)
    K = _axis_gains(inertia, n, cfg.gyroscopic)
    model = _Model3(inertia, n, K, cfg.dt_s, cfg.gyroscopic, f_prior)
    A, B = _Model3(inertia, n, K, cfg.dt_s, cfg.gyroscopic, f_true)(np.ones(3))
    if cfg.model_3dof == "printed":  # S1 eq. (13) stands for the printed (unchanged) model
        if cfg.inertia_direction == "prior":
            A, B = A13.copy(), B13.copy()
            A0, _ = model(np.ones(3))
        else:
            A0 = A13.copy()
    else:
        A0, _ = model(np.ones(3))
    return _Case(name, A, B, A0, model, 3, f_true / f_prior, name.split("-")[1])


def _inputs(case: _Case, cfg: Config, N: int, rng) -> np.ndarray:
    p = case.B.shape[1]
    if case.input_kind == "random":
        return rng.standard_normal((N, p))
    if case.input_kind == "step":
        return cfg.step_level_nm + rng.standard_normal((N, p))
    t = np.arange(N) * cfg.dt_s
    phase = rng.uniform(0, 2 * np.pi, size=p)
    return cfg.sine_amplitude_nm * np.sin(np.outer(t, np.array(cfg.sine_omega_rad_s[:p])) + phase)


def _err(Ah, A, ord_):
    return 100.0 * np.linalg.norm(Ah - A, ord_, axis=(-2, -1)) / np.linalg.norm(A, ord_)


def _method_options(method, case, cfg, sigma):
    n = case.A.shape[0]
    if method in ("gmres", "bicg", "cgs", "bicgstab"):
        return {"rtol": cfg.krylov_rtol}
    if method == "adaptive-gmres-offline":
        # S1: 1-DOF one iteration for 3 steps then to 1e-6; 3-DOF one for 7 then 3
        return ({"first_steps": 3, "first_iterations": 1, "later_iterations": None, "rtol": 1e-6}
                if n == 2 else {"first_steps": 7, "first_iterations": 1, "later_iterations": 3, "rtol": 1e-6})
    if method == "adaptive-gmres-online":
        return {"alpha0": cfg.alpha0}
    if method == "ridge-prior":
        return {"rule": cfg.ridge_rule, "noise_std": sigma if cfg.ridge_rule == "discrepancy" else None}
    if method == "ridge-prior-discrepancy":  # discrepancy principle at the known noise level
        return {"rule": "discrepancy", "noise_std": sigma}
    if method == "rls":
        return {"forgetting": cfg.rls_forgetting, "delta": cfg.rls_delta}
    if method == "rls-prior":
        # Bayesian anchoring at A0: no forgetting, P0 = delta I with delta = (prior std of an
        # entry / noise std)^2, the prior std from the stated inertia uncertainty times the rms
        # entry of A0 -- RLS is then ridge toward A0 with weight sigma^2 / prior variance.
        prior_std = cfg.inertia_error * float(np.sqrt(np.mean(case.A0**2)))
        return {"forgetting": 1.0, "delta": (prior_std / sigma) ** 2}
    return None


def _run_task(task: dict) -> dict:
    """One (case, noise level, seed): simulate once, run every method on the same data."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        return _run_task_inner(task)


def _run_task_inner(task):
    cfg: Config = task["cfg"]
    case = build_case(task["case"], cfg)
    sigma = task["sigma"]
    rng = np.random.default_rng(task["seed"])
    N = cfg.n_steps
    n = case.A.shape[0]
    u = _inputs(case, cfg, N, rng)
    sim = simulate_linear(case.A, case.B, np.eye(n), u, R=sigma**2, rng=rng)
    Q = cfg.kalman_q * np.eye(n)
    out: dict[str, Any] = {"case": case.name, "sigma": sigma, "seed_index": task["index"], "methods": {}}
    keep = task["index"] == 0
    for method in cfg.methods:
        mrng = np.random.default_rng([task["seed"], METHODS.index(method)])
        if method == "augmented-ekf":
            res = augmented_ekf(sim.y, u, case.model, np.ones(case.n_param), P_p0=cfg.inertia_error**2,
                                Q_p=cfg.ekf_q_param, Q=Q, R=sigma**2, P0=1.0)
            hist, x_est, extra = res.A_history, res.x, {"p_final": res.p[-1].tolist(), "p_true": case.p_true.tolist()}
            ok = res.success
        else:
            res = joint_estimate(sim.y, u, A_prior=case.A0, B=case.B, Q=Q, R=sigma**2, P0=1.0,
                                 method=_IMPL.get(method, method), options=_method_options(method, case, cfg, sigma),
                                 rng=mrng)
            hist, x_est, extra = res.A_history, res.x, {"nit": res.nit, "n_failed": res.n_failed}
            ok = res.success
            if "lsq_data" not in out:  # the first joint run's final regression
                out["lsq_data"] = (res.x[: N - 1], sim.y[1:N], u[: N - 1])
        e2 = _err(hist, case.A, 2)
        entry = {"final": float(e2[-1]), "success": bool(ok), **extra,
                 "at_prior": bool(np.array_equal(hist[-1], case.A0))}
        entry["e2"] = e2.astype(np.float32)
        entry["efro"] = _err(hist, case.A, "fro").astype(np.float32)
        if keep:
            entry["angle"] = x_est[:, 1 if n == 6 else 0].copy()
        out["methods"][method] = entry
    if keep:
        out["angle_true"] = sim.x[:N, 1 if n == 6 else 0].copy()
        out["angle_meas"] = sim.y[:, 1 if n == 6 else 0].copy()
    out["prior_error"] = float(_err(case.A0, case.A, 2))
    # converged solvers on the same least-squares system (the qr run's final regression)
    if "lsq_data" in out:
        X, Z, U = out.pop("lsq_data")
        sols = {}
        for m, o in (("qr", None), ("lsqr", {"atol": 1e-14, "btol": 1e-14}),
                     ("gmres", {"rtol": 1e-13}), ("bicgstab", {"rtol": 1e-13})):
            sols[m] = identify_model(X, Z, U, B=case.B, method=m, options=o).A
        ref = sols["qr"]
        out["solver_rel_diff"] = max(float(np.linalg.norm(a - ref) / np.linalg.norm(ref)) for a in sols.values())
        out["ls_final_error"] = float(_err(ref, case.A, 2))
    return out


# --------------------------------------------------------------------------- run


def _stats(v):
    v = np.asarray(v, float)
    return {"median": float(np.median(v)), "min": float(v.min()), "max": float(v.max())}


def _reading_plan(cfg: Config) -> dict[str, tuple[Config, float, tuple[str, ...]]]:
    """reading -> (config variant, noise std, cases it re-runs); other cases reuse the default."""
    plan = {"default": (cfg, cfg.noise_std, cfg.cases)}
    for r in cfg.readings:
        if r == "spacecraft changed":
            plan[r] = (replace(cfg, inertia_direction="truth" if cfg.inertia_direction == "prior" else "prior"),
                       cfg.noise_std, cfg.cases)
        elif r == "per-axis inertia":
            plan[r] = (replace(cfg, inertia_axes="transverse" if cfg.inertia_axes == "uniform" else "uniform"),
                       cfg.noise_std, tuple(c for c in cfg.cases if c.startswith("3dof")))
        elif r == "step dominant":
            plan[r] = (replace(cfg, step_level_nm=cfg.step_level_dominant_nm), cfg.noise_std,
                       tuple(c for c in cfg.cases if c.endswith("step")))
        elif r == "low noise":
            plan[r] = (cfg, cfg.noise_std_low, cfg.cases)
    return plan


def run(config: Config, *, quick: bool = False, rng=None, executor=None) -> StudyResult:
    """Run the study (see the module docstring and ``docs/studies/model-estimation.md``)."""
    from adcskit.uncertainty.executor import SerialExecutor

    cfg = config
    ex = executor or SerialExecutor()
    gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    root = np.random.SeedSequence(int(gen.integers(2**32)))
    seeds = [int(s.generate_state(1)[0]) for s in root.spawn(cfg.n_seeds)]  # same seeds for every reading
    plan = _reading_plan(cfg)
    tasks = []
    for reading, (rcfg, sigma, cases) in plan.items():
        for case in cases:
            for i, seed in enumerate(seeds):
                tasks.append({"cfg": rcfg, "case": case, "sigma": sigma, "seed": seed, "index": i, "reading": reading})
    results = ex.map(_run_task, tasks, description="model-estimation runs")
    for t, r in zip(tasks, results):
        r["reading"] = t["reading"]

    # by[(reading, case)] = runs, seed order; readings reuse the default run of cases they do not change
    by: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in results:
        by.setdefault((r["reading"], r["case"]), []).append(r)
    for reading in plan:
        for c in cfg.cases:
            by.setdefault((reading, c), by[("default", c)])

    def table(reading):
        return {m: {c: _stats([r["methods"][m]["final"] for r in by[(reading, c)]]) for c in cfg.cases}
                for m in cfg.methods}

    tables = {reading: table(reading) for reading in plan}
    main = tables["default"]
    prior_err = {reading: {c: by[(reading, c)][0]["prior_error"] for c in cfg.cases} for reading in plan}
    diffs = [r["solver_rel_diff"] for r in results if "solver_rel_diff" in r]
    rel_diff = max(diffs) if diffs else None
    ekf_p = {c: [r["methods"]["augmented-ekf"]["p_final"] for r in by[("default", c)]]
             for c in cfg.cases} if "augmented-ekf" in cfg.methods else {}
    at_prior = {reading: {m: {c: float(np.mean([r["methods"][m]["at_prior"] for r in by[(reading, c)]]))
                              for c in cfg.cases} for m in cfg.methods if m != "augmented-ekf"}
                for reading in plan}

    # per-seed measurements, per reading: {"err": {method: {case: e}}, "prior": {case: e}}
    per_seed = {reading: [{"err": {m: {c: by[(reading, c)][i]["methods"][m]["final"] for c in cfg.cases}
                                   for m in cfg.methods},
                           "prior": {c: by[(reading, c)][i]["prior_error"] for c in cfg.cases}}
                          for i in range(cfg.n_seeds)]
                for reading in plan}
    claims, findings = _verdicts(cfg, per_seed, list(plan))
    checks, comparison = _checks(cfg, main, prior_err["default"], rel_diff)
    figures = _figures(cfg, by, [r for r in ("default", "low noise") if r in plan])
    rows = []
    for reading, tab in tables.items():
        sigma = plan[reading][1]
        for m, per in tab.items():
            for c, st in per.items():
                pv = PAPER_TABLE.get(m, {}).get(c, {})
                rows.append({"reading": reading, "noise_std": sigma, "method": m, "case": c, **st,
                             "prior_error": prior_err[reading][c], "paper": _paper_range(pv) or ""})
    seed_rows = [
        {"reading": r["reading"], "noise_std": r["sigma"], "case": r["case"], "seed_index": r["seed_index"], "method": m,
         "final_error_pct": v["final"], "success": v["success"]}
        for r in results for m, v in r["methods"].items()
    ]
    n_fail = sum(1 for row in seed_rows if not row["success"])
    std_here = [m for m in STANDARD if m in cfg.methods]
    summary = (
        f"{len(cfg.methods)} methods x {len(cfg.cases)} cases x {cfg.n_seeds} seeds, L = {cfg.n_steps} steps, "
        f"readings: {', '.join(plan)}. With S1's N(0, 1) noise, converged least squares "
        "(QR = GMRES = Bi-CG = CGS = Bi-CGSTAB = LSQR to "
        f"{rel_diff if rel_diff is not None else float('nan'):.1e}) gives "
        + ", ".join(f"{c} {main[std_here[0]][c]['median']:.0f} %" for c in cfg.cases if std_here)
        + "; online adaptive GMRES gives "
        + ", ".join(f"{c} {main['adaptive-gmres-online'][c]['median']:.0f} %" for c in cfg.cases
                    if "adaptive-gmres-online" in main)
        + "; the prior A0 alone has " + ", ".join(f"{c} {prior_err['default'][c]:.0f} %" for c in cfg.cases) + ". "
        + "Claims: " + "; ".join(f"{c.id}: {c.outcome}" for c in claims) + "."
    )
    if "adaptive-gmres-online" in cfg.methods:
        fr = at_prior["default"]["adaptive-gmres-online"]
        summary += (
            " The online adaptive GMRES ends exactly at A0 in "
            + ", ".join(f"{c} {100 * fr[c]:.0f} %" for c in cfg.cases)
            + " of the runs: its acceptance test compares iterates with a random multiple of A0, so it "
            "acts as a prior-anchored (implicit) regulariser, not as a better least-squares solver."
        )
    return StudyResult(
        study="model-estimation",
        title="S1 Table 1: joint Kalman state + A-matrix estimation",
        summary=summary,
        config={},
        paper={
            "table": PAPER_TABLE,
            "metric": "e = 100 ||A_hat - A||_2 / ||A||_2 at the end of the run (S1 Table 1)",
            "claim": "adaptive GMRES reduces the model-error norm more than 10x vs the standard solvers (S1 text at Figs 2, 6, 13)",
            "source": "S1 Table 1; 3dof-sine range from the text at Fig. 13",
        },
        measured={
            "table": main,
            "table_by_reading": tables,
            "table_low_noise": tables.get("low noise", {}),
            "noise_std": cfg.noise_std,
            "noise_std_low": cfg.noise_std_low,
            "prior_error": prior_err["default"],
            "prior_error_by_reading": prior_err,
            "converged_solver_max_rel_diff": rel_diff,
            "augmented_ekf_inertia_ratio": ekf_p,
            "unsuccessful_runs": n_fail,
            "fraction_final_equals_prior": at_prior,
        },
        checks=checks,
        claims=claims,
        findings=findings,
        comparison=comparison,
        differences=_DIFFERENCES,
        figures=figures,
        tables={"table1": rows, "per-seed": seed_rows},
        doc="docs/studies/model-estimation.md",
    )


_DIFFERENCES = [
    "1-DOF: S1 eq. (3) is used as printed; it is I + A_c for a PD loop with a double pole at -1 rad/s "
    "(forward Euler, dt = 1 s), hence nilpotent (deadbeat).",
    "3-DOF: built from physics with the derived skew gyroscopic matrix (S1 eq. 10 prints a sign error), "
    "per-axis place_poles with the eq. (12) poles (axis assignment read from eq. 13's eigenvalues), "
    "Crank-Nicolson with the 1/2 factors (S1 drops them in print); reproduces eq. (13)'s A to ~1 %.",
    "50 % inertia uncertainty, default reading: the truth is the printed model and the prior A0 has the "
    "inertias 1.5x larger. Reading 'spacecraft changed' (S1's 'pre-change model'): A0 is the printed model "
    "and the truth's inertias are 1.5x larger. Reading 'per-axis inertia': only Ix, Iy change (equal "
    "scaling of all three leaves M^-1 L and M^-1 N unchanged). B is known (S1 eq. 17) in every reading.",
    "Step input: 1 + N(0, 1) N m (default) and 10 + N(0, 1) N m (reading 'step dominant'); noise: S1's "
    "sigma = 1 (default) and sigma = 0.01 (reading 'low noise').",
    "Krylov solvers act on the normal equations (I kron Phi^T Phi) theta = vec(Phi^T Z) -- S1 does not say "
    "how its tall system is made square; LSQR (no squaring) is added as a check.",
    "Kalman filter: S1 eq. (18) written correctly (Joseph-form covariance, process noise Q = kalman_q I, "
    "which S1 leaves unspecified); filtered estimates x(t|t) are the regressors.",
    "Unregularised solvers start once the regression is determined (q samples); the prior-anchored ones "
    "(adaptive GMRES, ridge, RLS) from the first sample. Before that the prior A0 is used.",
    "Manoeuvre length, alpha0, the sinusoid and step levels and the orbit altitude are not in S1; our "
    "choices are in the config and the doc page.",
    "Baselines S1 omits (findings, not claims): ridge toward A0 with GCV and with the discrepancy rule at "
    "the known noise level, RLS with forgetting started at A0, RLS anchored at A0 with the prior's weight "
    "(Bayesian), and an augmented-state EKF on the inertia ratios, which KNOWS the model structure "
    "(3 parameters instead of 36 matrix entries).",
]


def _paper_range(pv):
    if not pv:
        return None
    return pv.get("value", f"{pv.get('min')}-{pv.get('max')}")


_TABLE_CASES = ("1dof-random", "1dof-step", "3dof-random")  # S1 Table 1's columns


def _best(m, methods, c):
    return min(m["err"][x][c] for x in methods)


def _claim_specs(cfg: Config, readings: tuple[str, ...]):
    cases = cfg.cases
    std = tuple(x for x in STANDARD if x in cfg.methods)
    adaptive = tuple(x for x in ("adaptive-gmres-offline", "adaptive-gmres-online") if x in cfg.methods)
    paper_ms = tuple(x for x in PAPER_METHODS if x in cfg.methods)
    tcases = tuple(c for c in _TABLE_CASES if c in cases)
    specs = []
    if std and adaptive:
        specs.append(ClaimSpec(
            id="adaptive-10x",
            statement="The adaptive GMRES methods reduce the model error norm more than 10 times compared "
            "with the standard solvers (QR, GMRES, Bi-CG, CGS, Bi-CGSTAB).",
            where="S1 text at Figs 2, 6, 13; Table 1 (37-195 % vs 1-16 %)",
            quantity="min over cases and over both adaptive variants of (best standard-solver error / "
            "adaptive error), one seed; >= 10",
            value=lambda m: min(_best(m, std, c) / max(m["err"][a][c], 1e-12) for c in cases for a in adaptive),
            threshold=10.0, paper=">= 10", readings=readings,
            protocol_keys=("n_steps", "dt_s", "cases", "noise_std", "inertia_kgm2", "inertia_error", "model_3dof",
                           "gyroscopic", "step_level_nm", "alpha0"),
        ))
    if std and tcases:
        specs.append(ClaimSpec(
            id="standard-37-195",
            statement="The standard solvers QR, GMRES, Bi-CG, CGS and Bi-CGSTAB leave 37-195 % model error.",
            where="S1 Table 1, rows 1-5",
            quantity="every standard solver's final error in [37, 195] % on every Table 1 case "
            f"({', '.join(tcases)}), one seed",
            held=lambda m: all(37.0 <= m["err"][x][c] <= 195.0 for x in std for c in tcases),
            paper="37-195 %", readings=readings,
            protocol_keys=("n_steps", "dt_s", "cases", "noise_std", "inertia_kgm2", "inertia_error", "model_3dof",
                           "gyroscopic", "step_level_nm"),
        ))
    if "adaptive-gmres-online" in cfg.methods and len(paper_ms) > 1:
        specs.append(ClaimSpec(
            id="online-most-accurate",
            statement="The online meta-heuristic adaptive GMRES is the most accurate of the methods.",
            where="S1 abstract; Table 1",
            quantity="online adaptive GMRES has the smallest final error of S1's seven methods on every case, "
            "one seed",
            held=lambda m: all(m["err"]["adaptive-gmres-online"][c] <= _best(m, paper_ms, c) + 1e-12 for c in cases),
            readings=readings,
            protocol_keys=("n_steps", "dt_s", "cases", "noise_std", "inertia_kgm2", "inertia_error", "model_3dof",
                           "gyroscopic", "step_level_nm", "alpha0"),
        ))
    return specs


def _finding_specs(cfg: Config, readings: tuple[str, ...]):
    cases = cfg.cases
    specs = []
    on = "adaptive-gmres-online"
    if on in cfg.methods:
        specs.append(FindingSpec(
            id="online-improves-on-prior",
            statement="Online adaptive GMRES ends closer to the truth than the prior A0 it starts from, on every case.",
            quantity="max over cases of (online error / prior error); < 0.999 (ending exactly at A0 is no improvement)",
            value=lambda m: max(m["err"][on][c] / m["prior"][c] for c in cases), threshold=0.999, better="below",
            readings=readings, protocol_keys=FINDING_KEYS,
        ))
        base = tuple(b for b in PRIOR_BASELINES if b in cfg.methods)
        if base:
            specs.append(FindingSpec(
                id="prior-baselines-match-online",
                statement="An explicit prior-anchored estimator (ridge toward A0 with GCV or the discrepancy "
                "rule, or RLS anchored at A0) is at least as accurate as the online adaptive GMRES on every case.",
                quantity="max over cases of (best prior-anchored baseline error / online error); < 1.0001",
                value=lambda m: max(_best(m, base, c) / max(m["err"][on][c], 1e-12) for c in cases),
                threshold=1.0001, better="below", readings=readings, protocol_keys=FINDING_KEYS,
            ))
        if "augmented-ekf" in cfg.methods:
            specs.append(FindingSpec(
                id="ekf-knowing-structure-beats-online",
                statement="The augmented-state EKF, which knows the model structure (it estimates the inertia "
                "ratios of the physical model, not the matrix entries), is more accurate than the online "
                "adaptive GMRES on every case.",
                quantity="max over cases of (EKF error / online error); < 1",
                value=lambda m: max(m["err"]["augmented-ekf"][c] / max(m["err"][on][c], 1e-12) for c in cases),
                threshold=1.0, better="below", readings=readings, protocol_keys=FINDING_KEYS,
            ))
    one = tuple(c for c in cases if c.startswith("1dof"))
    std = tuple(x for x in STANDARD if x in cfg.methods)
    if one and std:
        specs.append(FindingSpec(
            id="least-squares-identifies-1dof",
            statement="Converged least squares (any standard solver) identifies the 1-DOF model: its error is "
            "below a tenth of the prior's.",
            quantity="max over 1-DOF cases of (standard-solver error / prior error); < 0.1",
            value=lambda m: max(_best(m, std, c) / m["prior"][c] for c in one), threshold=0.1, better="below",
            readings=readings, protocol_keys=FINDING_KEYS,
        ))
    return specs


def _verdicts(cfg, per_seed, readings):
    rd = tuple(readings) if len(readings) > 1 else ()
    runs = {r: per_seed[r] for r in readings}
    claims = [s.evaluate(runs) for s in _claim_specs(cfg, rd)]
    findings = [s.evaluate(runs) for s in _finding_specs(cfg, rd)]
    return claims, findings


def _checks(cfg, main, prior_err, rel_diff):
    checks: list[Check] = []
    comparison: list[Comparison] = []
    for m in cfg.methods:
        for c in cfg.cases:
            pv = PAPER_TABLE.get(m, {}).get(c)
            st = main[m][c]
            comparison.append(Comparison(
                quantity=f"{m} / {c}", paper=_paper_range(pv),
                measured=f"{st['median']:.1f} [{st['min']:.1f}, {st['max']:.1f}]",
                unit="%", note="median [min, max] over seeds, default reading" + ("" if pv else "; not in S1"),
            ))
    for c in cfg.cases:
        comparison.append(Comparison(quantity=f"prior A0 / {c}", paper=None, measured=round(prior_err[c], 2),
                                     unit="%", note="error of the prior model itself (no identification)"))
    std = [m for m in STANDARD if m in cfg.methods]
    if rel_diff is not None:
        checks.append(Check(
            name="converged QR, LSQR, GMRES, Bi-CGSTAB reach the same least-squares solution",
            passed=rel_diff < 1e-6, detail=f"max relative difference {rel_diff:.2e} over all runs", kind="check",
        ))
    if "qr" in cfg.methods and std:
        same = max(abs(main[m][c]["median"] - main["qr"][c]["median"]) for m in std for c in cfg.cases)
        checks.append(Check(
            name="the standard solvers, run to tolerance inside the loop, give the same table row as QR",
            passed=same < 1.0, detail=f"largest difference of medians from QR: {same:.3f} percentage points",
            kind="check",
        ))
    return checks, comparison


_STYLE = {
    "gmres": ("C0", "-"), "bicg": ("C1", "--"), "bicgstab": ("C2", ":"), "cgs": ("C3", "-."), "qr": ("k", "-"),
    "lsqr": ("0.5", "--"), "adaptive-gmres-offline": ("C4", "-"), "adaptive-gmres-online": ("C5", "-"),
    "ridge-prior": ("C6", "-"), "rls": ("C7", "--"), "augmented-ekf": ("C8", "-"),
    "ridge-prior-discrepancy": ("C6", ":"), "rls-prior": ("C7", "-."),
}


def _figures(cfg, by, readings):
    figs = {}
    for reading in readings:
        sigma = cfg.noise_std_low if reading == "low noise" else cfg.noise_std
        tag = "" if reading == "default" else "-low-noise"
        fig, axes = new_figure(2, 2, figsize=(11, 7.5), squeeze=False)
        for ax, c in zip(axes.ravel(), cfg.cases):
            runs = by[(reading, c)]
            for m in cfg.methods:
                e = np.median(np.stack([r["methods"][m]["e2"] for r in runs]), axis=0)
                col, ls = _STYLE[m]
                ax.semilogy(np.arange(e.size) * cfg.dt_s, e, color=col, ls=ls, label=m, lw=1.2)
            ax.axhline(runs[0]["prior_error"], color="k", lw=0.6, ls=":", label="prior A0")
            ax.set_title(f"{c} (median of {len(runs)} seeds)")
            ax.set_xlabel("time [s]")
            ax.set_ylabel("100 ||Â − A||₂ / ||A||₂ [%]")
        axes[0, 0].legend(fontsize=6, ncol=2)
        fig.suptitle(f"Model-error norm vs time, {reading} reading, noise std {sigma:g} (cf. S1 Figs 2, 6, 10)")
        figs[f"model-error-vs-time{tag}"] = fig
    sigma = cfg.noise_std
    fig, axes = new_figure(2, 2, figsize=(11, 7.5), squeeze=False)
    for ax, c in zip(axes.ravel(), cfg.cases):
        runs = by[("default", c)]
        for m in ("adaptive-gmres-online", "adaptive-gmres-offline"):
            if m not in cfg.methods:
                continue
            col = _STYLE[m][0]
            for key, ls in (("e2", "-"), ("efro", "--")):
                e = np.median(np.stack([r["methods"][m][key] for r in runs]), axis=0)
                ax.plot(np.arange(e.size) * cfg.dt_s, e, color=col, ls=ls,
                        label=f"{m} {'2-norm' if key == 'e2' else 'Frobenius'}")
        ax.set_title(c)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("relative error [%]")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle("Frobenius and 2-norm convergence of the adaptive GMRES estimates (cf. S1 Figs 4, 8, 12)")
    figs["norm-convergence"] = fig
    fig, axes = new_figure(2, 2, figsize=(11, 7.5), squeeze=False)
    for ax, c in zip(axes.ravel(), cfg.cases):
        r0 = next(r for r in by[("default", c)] if r["seed_index"] == 0)
        t = np.arange(r0["angle_true"].size) * cfg.dt_s
        ax.plot(t, r0["angle_meas"], ".", color="0.75", ms=2, label="measurement")
        ax.plot(t, r0["angle_true"], "k-", lw=2.0, label="truth")
        for m, col in (("adaptive-gmres-online", "C5"), ("qr", "C0"), ("augmented-ekf", "C8")):
            if m in cfg.methods:
                ax.plot(t, r0["methods"][m]["angle"], color=col, lw=1, label=f"estimate ({m})")
        lim = 2 * max(np.abs(r0["angle_true"]).max(), 1e-3)
        ax.set_ylim(-lim, lim)
        ax.set_title(f"{c}: {'pitch θ' if c.startswith('3dof') else 'angle'} (seed 0)")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("rad")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle(f"Angle estimate vs truth, noise std {sigma:g} (cf. S1 Figs 1, 5, 9, 13)")
    figs["angle-estimate"] = fig
    return figs


STUDY = Study(
    name="model-estimation",
    title="S1 Table 1: joint Kalman state + A-matrix estimation (QR, Krylov, adaptive GMRES, baselines)",
    paper="S1 — adaptive GMRES for joint attitude-state and model estimation",
    config_cls=Config,
    run=run,
    quick={"n_seeds": 2, "n_steps": 100},
    doc="docs/studies/model-estimation.md",
)
