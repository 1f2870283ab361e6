"""The measurements of ``model-estimation``: S1's joint loop for every method, case, reading and seed.

:func:`measure` simulates each (reading, case, seed) manoeuvre once and runs every method on the
same data (:func:`_run_task`), then reduces the runs to frozen records: :class:`Measurements`
holding :class:`SeedRun` (one manoeuvre) with one :class:`MethodRun` per method, the tables of
:class:`Stats` and the per-seed :class:`SeedErrors` the claims decide on. Claims, figures and
report read these records only; nothing after :func:`measure` draws a random number or solves.

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

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import scipy.signal as sig

from adcskit._results import Result
from adcskit.dynamics import discretize, lvlh_attitude_model, orbit_rate
from adcskit.estimation import augmented_ekf, identify_model, joint_estimate, simulate_linear
from adcskit.studies.model_estimation.config import _IMPL, KRYLOV, METHODS, Config
from adcskit.studies.model_estimation.paper import A13, AXIS_POLES, B13

__all__ = ["MethodRun", "SeedRun", "Stats", "SeedErrors", "Measurements", "build_case", "inertia_scales", "measure"]


# --------------------------------------------------------------------------- records


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class MethodRun(Result):
    """One method's joint-loop run on one manoeuvre."""

    final: float  #: final 2-norm model error e, %
    success: bool
    at_prior: bool  #: the final estimate is exactly the prior A0
    e2: np.ndarray  #: e over time (2-norm), %, float32
    efro: np.ndarray  #: the Frobenius-norm version, %, float32
    angle: np.ndarray | None = None  #: estimated angle (seed 0 only), rad
    nit: Any = None  #: solver iterations (joint_estimate methods)
    n_failed: Any = None  #: failed solves (joint_estimate methods)
    p_final: list[float] | None = None  #: final inertia ratios (augmented EKF)
    p_true: list[float] | None = None  #: true inertia ratios (augmented EKF)


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class SeedRun(Result):
    """One (reading, case, seed) manoeuvre with every method run on its data."""

    reading: str
    case: str
    sigma: float  #: measurement-noise std
    seed_index: int
    methods: Mapping[str, MethodRun]  #: in ``cfg.methods`` order
    prior_error: float  #: error of the prior A0 itself, %
    angle_true: np.ndarray | None = None  #: seed 0 only, rad
    angle_meas: np.ndarray | None = None  #: seed 0 only, rad
    solver_rel_diff: float | None = None  #: converged QR/LSQR/GMRES/Bi-CGSTAB spread
    ls_final_error: float | None = None  #: converged least squares' final error, %


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class Stats(Result):
    """Median, min and max over seeds of one table cell, %."""

    median: float
    min: float
    max: float


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class SeedErrors(Result):
    """What a claim or finding reads from one seed: final errors and the prior's error, %."""

    err: Mapping[str, Mapping[str, float]]  #: method -> case -> final error
    prior: Mapping[str, float]  #: case -> error of A0


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class Measurements(Result):
    """Everything the study reports, measured once by :func:`measure`."""

    readings: tuple[str, ...]  #: "default" first, then the configured readings
    sigma: Mapping[str, float]  #: reading -> noise std
    runs: tuple[SeedRun, ...]  #: every run, in task order
    by: Mapping[tuple[str, str], tuple[SeedRun, ...]]  #: (reading, case) -> runs in seed order
    tables: Mapping[str, Mapping[str, Mapping[str, Stats]]]  #: reading -> method -> case
    prior_error: Mapping[str, Mapping[str, float]]  #: reading -> case
    solver_rel_diff: float | None
    ekf_inertia_ratio: Mapping[str, list]  #: case -> per-seed final ratios
    at_prior: Mapping[str, Mapping[str, Mapping[str, float]]]  #: reading -> method -> case -> fraction
    per_seed: Mapping[str, tuple[SeedErrors, ...]]  #: reading -> seeds


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


def _method_options(method, case, cfg, sigma, krylov_maxiter=None):
    n = case.A.shape[0]
    if method in KRYLOV:
        # "S1-like Krylov" reading: a fixed iteration count per time step, warm-started
        return {"rtol": cfg.krylov_rtol} if krylov_maxiter is None else {"rtol": cfg.krylov_rtol,
                                                                          "maxiter": krylov_maxiter}
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


def _run_task(task: dict) -> SeedRun:
    """One (case, noise level, seed): simulate once, run every method on the same data."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        return _run_task_inner(task)


def _run_task_inner(task) -> SeedRun:
    cfg: Config = task["cfg"]
    case = build_case(task["case"], cfg)
    sigma = task["sigma"]
    rng = np.random.default_rng(task["seed"])
    N = cfg.n_steps
    n = case.A.shape[0]
    u = _inputs(case, cfg, N, rng)
    sim = simulate_linear(case.A, case.B, np.eye(n), u, R=sigma**2, rng=rng)
    Q = cfg.kalman_q * np.eye(n)
    keep = task["index"] == 0
    ax = 1 if n == 6 else 0
    methods: dict[str, MethodRun] = {}
    lsq_data = None
    for method in cfg.methods:
        mrng = np.random.default_rng([task["seed"], METHODS.index(method)])
        if method == "augmented-ekf":
            res = augmented_ekf(sim.y, u, case.model, np.ones(case.n_param), P_p0=cfg.inertia_error**2,
                                Q_p=cfg.ekf_q_param, Q=Q, R=sigma**2, P0=1.0)
            extra = {"p_final": res.p[-1].tolist(), "p_true": case.p_true.tolist()}
        else:
            res = joint_estimate(sim.y, u, A_prior=case.A0, B=case.B, Q=Q, R=sigma**2, P0=1.0,
                                 method=_IMPL.get(method, method),
                                 options=_method_options(method, case, cfg, sigma, task.get("krylov_maxiter")),
                                 rng=mrng)
            extra = {"nit": res.nit, "n_failed": res.n_failed}
            if lsq_data is None and task.get("krylov_maxiter") is None:  # the first joint run's final regression
                # (not in the "S1-like Krylov" re-runs: same data as the default's, already checked)
                lsq_data = (res.x[: N - 1], sim.y[1:N], u[: N - 1])
        hist = res.A_history
        e2 = _err(hist, case.A, 2)
        methods[method] = MethodRun(
            final=float(e2[-1]), success=bool(res.success), at_prior=bool(np.array_equal(hist[-1], case.A0)),
            e2=e2.astype(np.float32), efro=_err(hist, case.A, "fro").astype(np.float32),
            angle=res.x[:, ax].copy() if keep else None, **extra,
        )
    rel_diff = ls_final = None
    # converged solvers on the same least-squares system (the first joint run's final regression)
    if lsq_data is not None:
        X, Z, U = lsq_data
        sols = {}
        for m, o in (("qr", None), ("lsqr", {"atol": 1e-14, "btol": 1e-14}),
                     ("gmres", {"rtol": 1e-13}), ("bicgstab", {"rtol": 1e-13})):
            sols[m] = identify_model(X, Z, U, B=case.B, method=m, options=o).A
        ref = sols["qr"]
        rel_diff = max(float(np.linalg.norm(a - ref) / np.linalg.norm(ref)) for a in sols.values())
        ls_final = float(_err(ref, case.A, 2))
    return SeedRun(
        reading=task["reading"], case=case.name, sigma=sigma, seed_index=task["index"], methods=methods,
        prior_error=float(_err(case.A0, case.A, 2)),
        angle_true=sim.x[:N, ax].copy() if keep else None, angle_meas=sim.y[:, ax].copy() if keep else None,
        solver_rel_diff=rel_diff, ls_final_error=ls_final,
    )


# --------------------------------------------------------------------------- measure


def _stats(v) -> Stats:
    v = np.asarray(v, float)
    return Stats(median=float(np.median(v)), min=float(v.min()), max=float(v.max()))


def _reading_plan(cfg: Config) -> dict[str, tuple[Config, float, tuple[str, ...]]]:
    """reading -> (config variant, noise std, cases it re-runs); other cases reuse the default.

    The "S1-like Krylov" variant runs only the capped Krylov solvers (its other methods are the
    default's runs: same seeds, same data).
    """
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
        elif r == "S1-like Krylov":
            krylov = tuple(x for x in cfg.methods if x in KRYLOV)
            plan[r] = (replace(cfg, methods=krylov), cfg.noise_std, cfg.cases if krylov else ())
    return plan


def measure(cfg: Config, gen: np.random.Generator, executor: Any) -> Measurements:
    """Run every (reading, case, seed) manoeuvre through ``executor`` and reduce the runs.

    One integer is drawn from ``gen`` to seed the per-seed streams (the same seeds for every
    reading); a reading re-runs only the cases it changes and reuses the default's others.
    """
    root = np.random.SeedSequence(int(gen.integers(2**32)))
    seeds = [int(s.generate_state(1)[0]) for s in root.spawn(cfg.n_seeds)]  # same seeds for every reading
    plan = _reading_plan(cfg)
    cap = {"S1-like Krylov": cfg.s1_krylov_maxiter}
    tasks = [{"cfg": rcfg, "case": case, "sigma": sigma, "seed": seed, "index": i, "reading": reading,
              "krylov_maxiter": cap.get(reading)}
             for reading, (rcfg, sigma, cases) in plan.items() for case in cases for i, seed in enumerate(seeds)]
    runs = tuple(executor.map(_run_task, tasks, description="model-estimation runs"))

    by: dict[tuple[str, str], list[SeedRun]] = {}
    for r in runs:
        by.setdefault((r.reading, r.case), []).append(r)
    for (reading, c), rs in by.items():  # a reading that re-ran some methods: the default's others
        if reading != "default" and set(rs[0].methods) != set(cfg.methods):
            base = by[("default", c)]
            rs[:] = [replace(r, methods={x: r.methods.get(x, b.methods[x]) for x in cfg.methods})
                     for r, b in zip(rs, base, strict=True)]
    for reading in plan:
        for c in cfg.cases:
            by.setdefault((reading, c), by[("default", c)])
    tables = {reading: {m: {c: _stats([r.methods[m].final for r in by[(reading, c)]]) for c in cfg.cases}
                        for m in cfg.methods} for reading in plan}
    prior_err = {reading: {c: by[(reading, c)][0].prior_error for c in cfg.cases} for reading in plan}
    diffs = [r.solver_rel_diff for r in runs if r.solver_rel_diff is not None]
    ekf_p = {c: [r.methods["augmented-ekf"].p_final for r in by[("default", c)]]
             for c in cfg.cases} if "augmented-ekf" in cfg.methods else {}
    at_prior = {reading: {m: {c: float(np.mean([r.methods[m].at_prior for r in by[(reading, c)]]))
                              for c in cfg.cases} for m in cfg.methods if m != "augmented-ekf"}
                for reading in plan}
    per_seed = {reading: tuple(
        SeedErrors(err={m: {c: by[(reading, c)][i].methods[m].final for c in cfg.cases} for m in cfg.methods},
                   prior={c: by[(reading, c)][i].prior_error for c in cfg.cases})
        for i in range(cfg.n_seeds)) for reading in plan}
    return Measurements(
        readings=tuple(plan), sigma={reading: p[1] for reading, p in plan.items()}, runs=runs,
        by={k: tuple(v) for k, v in by.items()}, tables=tables, prior_error=prior_err,
        solver_rel_diff=max(diffs) if diffs else None, ekf_inertia_ratio=ekf_p, at_prior=at_prior,
        per_seed=per_seed,
    )
