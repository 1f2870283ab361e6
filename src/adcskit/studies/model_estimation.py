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

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import scipy.signal as sig

from adcskit.dynamics import discretize, lvlh_attitude_model, orbit_rate
from adcskit.estimation import augmented_ekf, identify_model, joint_estimate, simulate_linear
from adcskit.studies._base import Check, Comparison, Study, StudyResult, new_figure

__all__ = ["Config", "run", "STUDY", "CASES", "METHODS", "build_case"]

#: Methods of the study, in table order (paper's first, then the baselines it omits).
METHODS = (
    "gmres", "bicg", "bicgstab", "cgs", "qr", "lsqr",
    "adaptive-gmres-offline", "adaptive-gmres-online",
    "ridge-prior", "rls", "augmented-ekf",
)
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
        Manoeuvre length ``L`` in steps of ``dt`` (S1 does not state it; its figures show
        the estimates settling after ~100 s).
    dt : float, s
        Sample time (S1: ``dt = 1``).
    cases, methods : tuple of str
        Subsets of :data:`CASES` and :data:`METHODS`.
    noise_std : float
        Measurement-noise standard deviation on every state (S1 eq. 2: ``v ~ N(0, 1)``).
    noise_std_low : float
        Second, realistic level (0 disables it).
    inertia : tuple of 3 float, kg m^2
        True principal moments (S1: 82, 80, 4).
    altitude_m : float, m
        Circular-orbit altitude for the orbit rate (S1: LEO, value not stated).
    inertia_error : float
        The prior model assumes inertias ``(1 + inertia_error)`` times the truth (S1: 50 %).
    model_3dof : {"physics", "printed"}
        True 3-DOF model: built from physics (default) or S1 eq. (13) as printed.
    gyroscopic : {"derived", "printed"}
        Gyroscopic matrix of the physics model (S1 eq. 10 prints a sign error).
    kalman_q : float
        Kalman process-noise variance per state, relative to ``noise_std**2``'s units
        (``Q = kalman_q * I``); S1 leaves it unspecified.
    krylov_rtol : float
        Stopping tolerance of the standard Krylov solvers (normal equations).
    alpha0 : float
        Search half-width of the online adaptive GMRES (S1 Alg. 21; not stated in S1).
    rls_forgetting, rls_delta : float
        RLS forgetting factor and initial covariance scale.
    ridge_rule : {"gcv", "discrepancy"}
        How the ridge weight is chosen (never from the truth).
    step_level : float, N m
        Level of the step in ``1dof-step`` (plus N(0, 1) noise, S1 Fig. 7).
    sine_amplitude : float, N m
    sine_omega : tuple of 3 float, rad/s
        Per-axis sinusoid frequencies of ``3dof-sine`` (S1 gives none).
    ekf_q_param : float
        Random-walk variance of the inertia ratios in the augmented EKF.
    """

    n_seeds: int = 20
    n_steps: int = 200
    dt: float = 1.0
    cases: tuple[str, ...] = CASES
    methods: tuple[str, ...] = METHODS
    noise_std: float = 1.0
    noise_std_low: float = 0.01
    inertia: tuple[float, float, float] = (82.0, 80.0, 4.0)
    altitude_m: float = 500e3
    inertia_error: float = 0.5
    model_3dof: Literal["physics", "printed"] = "physics"
    gyroscopic: Literal["derived", "printed"] = "derived"
    kalman_q: float = 1e-4
    krylov_rtol: float = 1e-8
    alpha0: float = 0.5
    rls_forgetting: float = 0.99
    rls_delta: float = 100.0
    ridge_rule: Literal["gcv", "discrepancy"] = "gcv"
    step_level: float = 1.0
    sine_amplitude: float = 1.0
    sine_omega: tuple[float, float, float] = (0.05, 0.08, 0.13)
    ekf_q_param: float = 1e-6

    def __post_init__(self) -> None:
        if self.n_seeds < 1:
            raise ValueError(f"n_seeds must be >= 1; got {self.n_seeds}")
        if self.n_steps < 20:
            raise ValueError(f"n_steps must be >= 20 (the 3-DOF regression has 6 unknowns per row); got {self.n_steps}")
        if not self.dt > 0:
            raise ValueError(f"dt must be > 0 s; got {self.dt}")
        for c in self.cases:
            if c not in CASES:
                raise ValueError(f"cases must be a subset of {CASES}; got {c!r}")
        for m in self.methods:
            if m not in METHODS:
                raise ValueError(f"methods must be a subset of {METHODS}; got {m!r}")
        if not self.noise_std > 0 or self.noise_std_low < 0:
            raise ValueError("noise_std must be > 0 and noise_std_low >= 0")
        if min(self.inertia) <= 0:
            raise ValueError(f"inertia must be positive kg m^2; got {self.inertia}")
        if not -1 < self.inertia_error:
            raise ValueError(f"inertia_error must be > -1; got {self.inertia_error}")
        if not 0 <= self.alpha0 <= 1:
            raise ValueError(f"alpha0 must be in [0, 1]; got {self.alpha0}")
        if not 0 < self.rls_forgetting <= 1:
            raise ValueError(f"rls_forgetting must be in (0, 1]; got {self.rls_forgetting}")
        if self.kalman_q < 0 or self.krylov_rtol <= 0 or self.rls_delta <= 0 or self.ekf_q_param < 0:
            raise ValueError("kalman_q, ekf_q_param must be >= 0; krylov_rtol, rls_delta > 0")
        if self.altitude_m < 0:
            raise ValueError(f"altitude_m must be >= 0 m; got {self.altitude_m}")


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


def build_case(name: str, cfg: Config) -> _Case:
    """Truth, prior and parameterised model of one case (see the module docstring)."""
    s0 = 1.0 + cfg.inertia_error
    if name.startswith("1dof"):
        A, B = _model_1dof(1.0)
        A0, _ = _model_1dof(s0)
        return _Case(name, A, B, A0, _Model1(s0), 1, np.array([1.0 / s0]), name.split("-")[1])
    n = orbit_rate(cfg.altitude_m)
    inertia = np.array(cfg.inertia)
    K = _axis_gains(inertia, n, cfg.gyroscopic)
    model = _Model3(inertia, n, K, cfg.dt, cfg.gyroscopic, s0)
    A0, _ = model(np.ones(3))
    if cfg.model_3dof == "printed":
        A, B = A13.copy(), B13.copy()
    else:
        A, B = _Model3(inertia, n, K, cfg.dt, cfg.gyroscopic, 1.0)(np.ones(3))
    return _Case(name, A, B, A0, model, 3, np.full(3, 1.0 / s0), name.split("-")[1])


def _inputs(case: _Case, cfg: Config, N: int, rng) -> np.ndarray:
    p = case.B.shape[1]
    if case.input_kind == "random":
        return rng.standard_normal((N, p))
    if case.input_kind == "step":
        return cfg.step_level + rng.standard_normal((N, p))
    t = np.arange(N) * cfg.dt
    phase = rng.uniform(0, 2 * np.pi, size=p)
    return cfg.sine_amplitude * np.sin(np.outer(t, np.array(cfg.sine_omega[:p])) + phase)


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
    if method == "rls":
        return {"forgetting": cfg.rls_forgetting, "delta": cfg.rls_delta}
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
                                 method=method, options=_method_options(method, case, cfg, sigma), rng=mrng)
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


def run(config: Config, *, quick: bool = False, rng=None, executor=None) -> StudyResult:
    """Run the study (see the module docstring and ``docs/studies/model-estimation.md``)."""
    from adcskit.uncertainty.executor import SerialExecutor

    cfg = config
    ex = executor or SerialExecutor()
    gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    root = np.random.SeedSequence(int(gen.integers(2**32)))
    seeds = root.spawn(cfg.n_seeds)
    sigmas = [cfg.noise_std] + ([cfg.noise_std_low] if cfg.noise_std_low > 0 else [])
    tasks = []
    for sigma in sigmas:
        for case in cfg.cases:
            for i, s in enumerate(seeds):
                seed = int(s.generate_state(1)[0])  # same seed across cases and noise levels
                tasks.append({"cfg": cfg, "case": case, "sigma": sigma, "seed": seed, "index": i})
    results = ex.map(_run_task, tasks, description="model-estimation runs")

    by = {(r["sigma"], r["case"]): [] for r in results}
    for r in results:
        by[(r["sigma"], r["case"])].append(r)

    def table(sigma):
        t: dict[str, dict[str, Any]] = {}
        for m in cfg.methods:
            t[m] = {c: _stats([r["methods"][m]["final"] for r in by[(sigma, c)]]) for c in cfg.cases}
        return t

    main = table(cfg.noise_std)
    low = table(cfg.noise_std_low) if len(sigmas) > 1 else {}
    prior_err = {c: by[(cfg.noise_std, c)][0]["prior_error"] for c in cfg.cases}
    diffs = [r["solver_rel_diff"] for r in results if "solver_rel_diff" in r]
    rel_diff = max(diffs) if diffs else None
    ls_final = {
        f"{s:g}": {c: _stats([r["ls_final_error"] for r in by[(s, c)]]) for c in cfg.cases} for s in sigmas
    } if diffs else {}
    ekf_p = {c: [r["methods"]["augmented-ekf"]["p_final"] for r in by[(cfg.noise_std, c)]]
             for c in cfg.cases} if "augmented-ekf" in cfg.methods else {}

    # fraction of runs whose final estimate is exactly the prior A0 (nothing accepted / kept)
    at_prior = {
        f"{sg:g}": {m: {c: float(np.mean([r["methods"][m]["at_prior"] for r in by[(sg, c)]])) for c in cfg.cases}
                    for m in cfg.methods if m != "augmented-ekf"}
        for sg in sigmas
    }
    checks, comparison = _verdicts(cfg, main, low, prior_err, rel_diff)
    figures = _figures(cfg, by, sigmas)
    rows = []
    for label, tab, sigma in (("main", main, cfg.noise_std), ("low-noise", low, cfg.noise_std_low)):
        for m, per in tab.items():
            for c, st in per.items():
                pv = PAPER_TABLE.get(m, {}).get(c, {}) if label == "main" else {}
                rows.append({"noise_std": sigma, "method": m, "case": c, **st,
                             "paper": _paper_range(pv) or ""})
    per_seed = [
        {"noise_std": r["sigma"], "case": r["case"], "seed_index": r["seed_index"], "method": m,
         "final_error_pct": v["final"], "success": v["success"]}
        for r in results for m, v in r["methods"].items()
    ]
    n_fail = sum(1 for row in per_seed if not row["success"])
    summary = (
        f"{len(cfg.methods)} methods x {len(cfg.cases)} cases x {cfg.n_seeds} seeds x {len(sigmas)} noise "
        f"levels, L = {cfg.n_steps} steps. With S1's N(0, 1) noise, converged least squares "
        "(QR = GMRES = Bi-CG = CGS = Bi-CGSTAB = LSQR to "
        f"{rel_diff if rel_diff is not None else float('nan'):.1e}) gives "
        + ", ".join(f"{c} {main['qr'][c]['median']:.0f} %" for c in cfg.cases if "qr" in main)
        + "; online adaptive GMRES gives "
        + ", ".join(f"{c} {main['adaptive-gmres-online'][c]['median']:.0f} %" for c in cfg.cases
                    if "adaptive-gmres-online" in main)
        + "; the prior A0 alone has " + ", ".join(f"{c} {prior_err[c]:.0f} %" for c in cfg.cases) + "."
    )
    if "adaptive-gmres-online" in cfg.methods:
        fr = at_prior[f"{cfg.noise_std:g}"]["adaptive-gmres-online"]
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
            "table_low_noise": low,
            "noise_std": cfg.noise_std,
            "noise_std_low": cfg.noise_std_low,
            "prior_error": prior_err,
            "converged_solver_max_rel_diff": rel_diff,
            "least_squares_final_error": ls_final,
            "augmented_ekf_inertia_ratio": ekf_p,
            "unsuccessful_runs": n_fail,
            "fraction_final_equals_prior": at_prior,
        },
        checks=checks,
        comparison=comparison,
        differences=_DIFFERENCES,
        figures=figures,
        tables={"table1": rows, "per-seed": per_seed},
        doc="docs/studies/model-estimation.md",
    )


_DIFFERENCES = [
    "1-DOF: S1 eq. (3) is used as printed; it is I + A_c for a PD loop with a double pole at -1 rad/s "
    "(forward Euler, dt = 1 s), hence nilpotent (deadbeat). The prior has the inertia 50 % larger.",
    "3-DOF: built from physics with the derived skew gyroscopic matrix (S1 eq. 10 prints a sign error), "
    "per-axis place_poles with the eq. (12) poles (axis assignment read from eq. 13's eigenvalues), "
    "Crank-Nicolson with the 1/2 factors (S1 drops them in print); reproduces eq. (13)'s A to ~1 %.",
    "Krylov solvers act on the normal equations (I kron Phi^T Phi) theta = vec(Phi^T Z) -- S1 does not say "
    "how its tall system is made square; LSQR (no squaring) is added as a check.",
    "Kalman filter: S1 eq. (18) written correctly (Joseph-form covariance, process noise Q = kalman_q I, "
    "which S1 leaves unspecified); filtered estimates x(t|t) are the regressors.",
    "Unregularised solvers start once the regression is determined (q samples); the prior-anchored ones "
    "(adaptive GMRES, ridge, RLS) from the first sample. Before that the prior A0 is used.",
    "Manoeuvre length, alpha0, the sinusoid and step levels and the orbit altitude are not in S1; our "
    "choices are in the config and the doc page.",
    "Baselines S1 omits: ridge toward A0 (GCV), RLS with forgetting, augmented-state EKF on inertia ratios.",
]


def _paper_range(pv):
    if not pv:
        return None
    return pv.get("value", f"{pv.get('min')}-{pv.get('max')}")


def _verdicts(cfg, main, low, prior_err, rel_diff):
    checks: list[Check] = []
    comparison: list[Comparison] = []
    for m in cfg.methods:
        for c in cfg.cases:
            pv = PAPER_TABLE.get(m, {}).get(c)
            st = main[m][c]
            comparison.append(Comparison(
                quantity=f"{m} / {c}", paper=_paper_range(pv),
                measured=f"{st['median']:.1f} [{st['min']:.1f}, {st['max']:.1f}]",
                unit="%", note="median [min, max] over seeds" + ("" if pv else "; not in S1"),
            ))
    for c in cfg.cases:
        comparison.append(Comparison(quantity=f"prior A0 / {c}", paper=None, measured=round(prior_err[c], 2),
                                     unit="%", note="error of the prior model itself (no identification)"))
    std = [m for m in STANDARD if m in cfg.methods]
    for adaptive in ("adaptive-gmres-offline", "adaptive-gmres-online"):
        if adaptive not in cfg.methods or not std:
            continue
        ratios = {c: min(main[m][c]["median"] for m in std) / max(main[adaptive][c]["median"], 1e-12) for c in cfg.cases}
        checks.append(Check(
            name=f"{adaptive} is >10x more accurate than the standard solvers (S1 text, Table 1)",
            passed=all(r >= 10 for r in ratios.values()),
            detail="best standard median / adaptive median: "
            + ", ".join(f"{c} {r:.2f}x" for c, r in ratios.items())
            + f" (noise std {cfg.noise_std:g})",
        ))
        # does the adaptive method beat simply keeping the prior?
        checks.append(Check(
            name=f"{adaptive} improves on the prior A0 (implicit in S1's claim of estimating the model)",
            passed=all(main[adaptive][c]["median"] < prior_err[c] for c in cfg.cases),
            detail=", ".join(f"{c}: {main[adaptive][c]['median']:.1f} % vs prior {prior_err[c]:.1f} %" for c in cfg.cases),
        ))
    if "adaptive-gmres-online" in cfg.methods:
        paper_ms = [m for m in PAPER_METHODS if m in cfg.methods]
        best = {c: min(paper_ms, key=lambda m, c=c: main[m][c]["median"]) for c in cfg.cases}
        checks.append(Check(
            name="online meta-heuristic adaptive GMRES is the most accurate of S1's methods (abstract)",
            passed=all(b == "adaptive-gmres-online" for b in best.values()),
            detail="best of S1's methods per case: " + ", ".join(f"{c} {b}" for c, b in best.items()),
        ))
        base = [m for m in ("ridge-prior", "rls", "augmented-ekf") if m in cfg.methods]
        if base:
            checks.append(Check(
                name="online adaptive GMRES beats the fair baselines S1 omits (ridge to A0, RLS, augmented EKF)",
                passed=all(main["adaptive-gmres-online"][c]["median"] <= min(main[b][c]["median"] for b in base)
                           for c in cfg.cases),
                detail=", ".join(
                    f"{c}: online {main['adaptive-gmres-online'][c]['median']:.1f} %, "
                    + ", ".join(f"{b} {main[b][c]['median']:.1f} %" for b in base) for c in cfg.cases),
            ))
    if std:
        in_range = {c: [main[m][c]["median"] for m in std] for c in cfg.cases}
        checks.append(Check(
            name="standard solvers give 37-195 % error (S1 Table 1)",
            passed=all(37 <= v <= 195 for vs in in_range.values() for v in vs),
            detail=", ".join(f"{c}: {min(v):.0f}-{max(v):.0f} %" for c, v in in_range.items()),
        ))
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
    one = [c for c in cfg.cases if c.startswith("1dof")]
    if low and "qr" in low and one:
        # physics check: with sigma = 0.01 the well-excited 1-DOF regression is informative,
        # so least squares must beat the 37 % prior by far (the 3-DOF cases are reported only)
        checks.append(Check(
            name="with a realistic noise level least squares identifies the 1-DOF model (< prior / 10)",
            passed=all(low["qr"][c]["median"] < prior_err[c] / 10 for c in one),
            detail=f"noise std {cfg.noise_std_low:g}: " + ", ".join(
                f"{c}: QR {low['qr'][c]['median']:.2f} % vs prior {prior_err[c]:.1f} %" for c in cfg.cases),
            kind="check",
        ))
    return checks, comparison


_STYLE = {
    "gmres": ("C0", "-"), "bicg": ("C1", "--"), "bicgstab": ("C2", ":"), "cgs": ("C3", "-."), "qr": ("k", "-"),
    "lsqr": ("0.5", "--"), "adaptive-gmres-offline": ("C4", "-"), "adaptive-gmres-online": ("C5", "-"),
    "ridge-prior": ("C6", "-"), "rls": ("C7", "--"), "augmented-ekf": ("C8", "-"),
}


def _figures(cfg, by, sigmas):
    figs = {}
    for sigma in sigmas:
        tag = "" if sigma == cfg.noise_std else "-low-noise"
        fig, axes = new_figure(2, 2, figsize=(11, 7.5), squeeze=False)
        for ax, c in zip(axes.ravel(), cfg.cases):
            runs = by[(sigma, c)]
            for m in cfg.methods:
                e = np.median(np.stack([r["methods"][m]["e2"] for r in runs]), axis=0)
                col, ls = _STYLE[m]
                ax.semilogy(np.arange(e.size) * cfg.dt, e, color=col, ls=ls, label=m, lw=1.2)
            ax.axhline(runs[0]["prior_error"], color="k", lw=0.6, ls=":", label="prior A0")
            ax.set_title(f"{c} (median of {len(runs)} seeds)")
            ax.set_xlabel("time [s]")
            ax.set_ylabel("100 ||Â − A||₂ / ||A||₂ [%]")
        axes[0, 0].legend(fontsize=6, ncol=2)
        fig.suptitle(f"Model-error norm vs time, noise std {sigma:g} (cf. S1 Figs 2, 6, 10)")
        figs[f"model-error-vs-time{tag}"] = fig
    sigma = cfg.noise_std
    fig, axes = new_figure(2, 2, figsize=(11, 7.5), squeeze=False)
    for ax, c in zip(axes.ravel(), cfg.cases):
        runs = by[(sigma, c)]
        for m in ("adaptive-gmres-online", "adaptive-gmres-offline"):
            if m not in cfg.methods:
                continue
            col = _STYLE[m][0]
            for key, ls in (("e2", "-"), ("efro", "--")):
                e = np.median(np.stack([r["methods"][m][key] for r in runs]), axis=0)
                ax.plot(np.arange(e.size) * cfg.dt, e, color=col, ls=ls,
                        label=f"{m} {'2-norm' if key == 'e2' else 'Frobenius'}")
        ax.set_title(c)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("relative error [%]")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle("Frobenius and 2-norm convergence of the adaptive GMRES estimates (cf. S1 Figs 4, 8, 12)")
    figs["norm-convergence"] = fig
    fig, axes = new_figure(2, 2, figsize=(11, 7.5), squeeze=False)
    for ax, c in zip(axes.ravel(), cfg.cases):
        r0 = next(r for r in by[(sigma, c)] if r["seed_index"] == 0)
        t = np.arange(r0["angle_true"].size) * cfg.dt
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
    quick={"n_seeds": 3, "n_steps": 100},
    doc="docs/studies/model-estimation.md",
)
