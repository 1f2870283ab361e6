"""Study ``wahba-table1``: S0 Table 1 — one epoch, ±20 % interval noise, point vs robust solvers.

The printed single-epoch vectors (S0 eq. 9, from Ahmed & Kerrigan 2011) are perturbed by
uniform bounded noise of ±``noise_bound`` of each component's value, on both the reference
and the body vectors, then renormalised. Each trial is solved by the q-method (S0's
baseline), the paper's min-max goal attainment — exactly (``minmax``, closed form + KKT on the
box) and iteratively as the paper does (``minmax-slsqp``: SLSQP on the full epigraph problem
from TRIAD, the kind of solver MATLAB's ``fminimax`` is) — NSGA-II with a truth-free knee pick
and with the paper's pick by the true attitude (not deployable), the worst-case robust solver
(Ahmed & Kerrigan), and QUEST/SVD as sanity rows. A noise-bound sweep gives the slope reading
of the "200× less dependence on input accuracy" claim.

Every claim is decided over ``n_seeds`` independent replicas of the whole Table 1 (``n_trials``
noise draws each, own NSGA-II seeds); the iterative rows (``minmax-slsqp`` and NSGA-II) run on
the first ``n_iterative`` trials of each replica, where the cheap rows are compared on the same
trials.

Interval given to the robust solvers: midpoint = the measured (noisy, normalised) vector,
radius = ``noise_bound`` × |measured component| (S0 §4-1: "bounds ±b^r, ±r^r ... 20 % of
the input value").
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from adcskit.determination import robust_wahba, solve_wahba
from adcskit.studies._base import Check, Comparison, Study, StudyResult, new_figure
from adcskit.studies._verdict import ClaimSpec, FindingSpec

# S0 eq. 9 (printed). q_exact is printed scalar-first with Shuster's A(q) (seeds digest).
R_EXACT = np.array([[-0.54, -0.326, 0.775], [-0.673, 0.000133, 0.74]])
B_EXACT = np.array([[-0.776, -0.46, 0.43], [-0.927, 0.01, 0.374]])
Q_EXACT_SCALAR_FIRST = np.array([-0.9746, 0.0707, -0.2122, -0.0125])

# S0 Table 1 (100 trials): mean δθ [deg], variance [deg²], run time [s]
PAPER_TABLE1 = {
    "q-method": {"mean_deg": 15.1352, "var_deg2": 95.1604, "runtime_s": 0.006},
    "nsga2-truth-pick": {"mean_deg": 0.5699, "var_deg2": 0.1915, "runtime_s": 124.58},
    "minmax": {"mean_deg": 2.2025, "var_deg2": 0.4409, "runtime_s": 0.287},
}
#: Rows run on every trial (cheap). The two "box-at" rows are diagnostics, NOT deployable:
#: the min-max search box centred on the noise-free answer.
CHEAP_ROWS = (
    "q-method", "minmax", "worst-case", "quest", "svd",
    "minmax-box-at-exact-triad", "minmax-box-at-truth",
)
#: Iterative rows, run on the first ``n_iterative`` trials of each replica.
ITER_ROWS = ("minmax-slsqp", "nsga2-knee", "nsga2-truth-pick")
ROWS = CHEAP_ROWS[:3] + ITER_ROWS + CHEAP_ROWS[3:]
#: Rows of the noise-bound sweep.
SWEEP_ROWS = ("q-method", "minmax", "worst-case", "minmax-box-at-exact-triad", "minmax-box-at-truth")


@dataclass(frozen=True, kw_only=True)
class Config:
    """Settings of S0 §4-1 (defaults) and of our repetitions and noise sweep.

    Attributes
    ----------
    n_seeds : int
        Independent replicas of the whole experiment (noise draws and optimiser seeds); each
        claim is decided over them (>= 5 at full settings).
    n_trials : int
        Perturbed trials per replica (S0: 100).
    n_iterative : int
        Trials per replica on which the iterative rows (SLSQP min-max, NSGA-II) also run.
    noise_bound : float
        Uniform noise bound as a fraction of each component (S0: 0.2).
    search_range : float
        Min-max / NSGA-II search box around TRIAD, fraction of each component (S0: 0.1).
    pop_size, n_gen : int
        NSGA-II population and generations (not printed in S0; ours).
    sweep_bounds : tuple of float
        Noise bounds of the sensitivity sweep (slope reading).
    sweep_trials : int
        Trials per sweep point and replica.
    """

    n_seeds: int = 5
    n_trials: int = 100
    n_iterative: int = 20
    noise_bound: float = 0.2
    search_range: float = 0.1
    pop_size: int = 100
    n_gen: int = 100
    sweep_bounds: tuple[float, ...] = (0.01, 0.02, 0.05, 0.1, 0.2, 0.3)
    sweep_trials: int = 30

    def __post_init__(self) -> None:
        from adcskit.errors import ConfigError

        for name, lo in (("n_seeds", 1), ("n_trials", 2), ("sweep_trials", 2), ("n_iterative", 2)):
            v = getattr(self, name)
            if not (isinstance(v, int) and v >= lo):
                raise ConfigError(f"{name} must be an integer >= {lo}; got {v!r}")
        if self.n_iterative > self.n_trials:
            raise ConfigError(f"n_iterative must be <= n_trials ({self.n_trials}); got {self.n_iterative}")
        for name in ("pop_size", "n_gen"):
            v = getattr(self, name)
            if not (isinstance(v, int) and v >= 4):
                raise ConfigError(f"{name} must be an integer >= 4; got {v!r}")
        if not 0 < self.noise_bound < 1:
            raise ConfigError(f"noise_bound must be in (0, 1); got {self.noise_bound}")
        if not 0 < self.search_range <= 1:
            raise ConfigError(f"search_range must be in (0, 1]; got {self.search_range}")
        if not self.sweep_bounds or len(self.sweep_bounds) < 2 or any(not 0 < b < 1 for b in self.sweep_bounds):
            raise ConfigError(f"sweep_bounds must hold >= 2 bounds, each in (0, 1); got {self.sweep_bounds}")


def q_exact() -> np.ndarray:
    """S0's q_exact in our convention (scalar last, q4 >= 0)."""
    q = np.r_[Q_EXACT_SCALAR_FIRST[1:], Q_EXACT_SCALAR_FIRST[0]]
    q = q / np.linalg.norm(q)
    return -q if q[3] < 0 else q


def angle_deg(q1: np.ndarray, q2: np.ndarray) -> float:
    """δθ between two attitudes [deg] (S0's error metric, chord form for accuracy)."""
    d = min(np.linalg.norm(q1 - q2), np.linalg.norm(q1 + q2))
    return float(np.degrees(4.0 * np.arcsin(min(d / 2.0, 1.0))))


def perturb_raw(rng: np.random.Generator, bound: float) -> tuple[np.ndarray, np.ndarray]:
    """Noisy body and reference vectors *before* renormalisation (±bound of each component)."""
    b = B_EXACT * (1.0 + bound * rng.uniform(-1, 1, B_EXACT.shape))
    r = R_EXACT * (1.0 + bound * rng.uniform(-1, 1, R_EXACT.shape))
    return b, r


def perturb(rng: np.random.Generator, bound: float) -> tuple[np.ndarray, np.ndarray]:
    """Noisy, renormalised body and reference vectors (±bound of each component)."""
    b, r = perturb_raw(rng, bound)
    return b / np.linalg.norm(b, axis=1, keepdims=True), r / np.linalg.norm(r, axis=1, keepdims=True)


def qmethod_in_box(b: np.ndarray, r: np.ndarray, search_range: float) -> bool:
    """Whether the unconstrained q-method attitude lies in the ±search_range TRIAD box (S0 §4-1)."""
    qt = solve_wahba(b, r, method="triad").q
    qo = solve_wahba(b, r, method="q-method").q
    if qo @ qt < 0:
        qo = -qo
    return bool(np.all(np.abs(qo - qt) <= search_range * np.abs(qt) + 1e-15))


def _timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def trial(task: tuple[np.random.SeedSequence, float, dict[str, Any], tuple[str, ...]]) -> dict[str, Any]:
    """One perturbed epoch solved by every requested row.

    Returns ``{row: (error_deg, runtime_s)}`` plus ``"_in_box"`` (the q-method attitude lies
    in the search box) and, when both min-max solvers ran, ``"_cf_vs_slsqp_deg"`` (angle
    between the closed-form and the SLSQP min-max attitudes).
    """
    seed, bound, cfg, rows = task
    rng = np.random.default_rng(seed)
    b, r = perturb(rng, bound)
    seed_ns = int(rng.integers(2**31 - 1))
    qt = q_exact()
    br, rr = bound * np.abs(b), bound * np.abs(r)
    sr = cfg["search_range"]
    out: dict[str, Any] = {"_in_box": qmethod_in_box(b, r, sr)}
    for m in ("q-method", "quest", "svd"):
        if m in rows:
            res, dt = _timed(lambda m=m: solve_wahba(b, r, method=m))
            out[m] = (angle_deg(res.q, qt), dt)
    qs = {}
    for row, solver in (("minmax", "closed-form"), ("minmax-slsqp", "slsqp")):
        if row in rows:
            res, dt = _timed(lambda s=solver: robust_wahba(b, br, r, rr, method="minmax", search_range=sr, solver=s))
            out[row] = (angle_deg(res.q, qt), dt)
            qs[row] = res.q
    if len(qs) == 2:
        out["_cf_vs_slsqp_deg"] = angle_deg(qs["minmax"], qs["minmax-slsqp"])
    # diagnostics: S0's search box centred on TRIAD of the *noise-free* vectors / on q_exact
    for row, centre in (("minmax-box-at-exact-triad", "triad"), ("minmax-box-at-truth", "truth")):
        if row in rows:
            q0 = qt if centre == "truth" else solve_wahba(B_EXACT, R_EXACT, method="triad").q
            res, dt = _timed(lambda q0=q0: robust_wahba(b, br, r, rr, method="minmax", search_range=sr, q0=q0))
            out[row] = (angle_deg(res.q, qt), dt)
    if "worst-case" in rows:
        res, dt = _timed(lambda: robust_wahba(b, br, r, rr, method="worst-case"))
        out["worst-case"] = (angle_deg(res.q, qt), dt)
    if "nsga2-knee" in rows or "nsga2-truth-pick" in rows:
        res, dt = _timed(
            lambda: robust_wahba(b, br, r, rr, method="nsga2", search_range=sr,
                                 pop_size=cfg["pop_size"], n_gen=cfg["n_gen"], rng=seed_ns)
        )
        out["nsga2-knee"] = (angle_deg(res.q, qt), dt)
        # the paper's selection: the Pareto point closest to the TRUE attitude (needs truth)
        out["nsga2-truth-pick"] = (float(min(angle_deg(q, qt) for q in res.pareto_q)), dt)
    return out


def _stats(results: list[dict[str, Any]], rows) -> dict[str, dict[str, float]]:
    stats = {}
    for m in rows:
        e = np.array([res[m][0] for res in results if m in res])
        t = np.array([res[m][1] for res in results if m in res])
        stats[m] = {
            "mean_deg": float(e.mean()),
            "var_deg2": float(e.var(ddof=1)) if e.size > 1 else float("nan"),
            "max_deg": float(e.max()),
            "runtime_s": float(np.median(t)),
            "n_trials": int(e.size),
        }
    return stats


def _replica_measure(results: list[dict[str, Any]], sweep: list[list[dict[str, Any]]], bounds: np.ndarray,
                     n_iter: int) -> dict[str, Any]:
    """The deciding quantities of one replica (one seed of the whole pipeline)."""
    st = _stats(results, CHEAP_ROWS)
    sub = results[:n_iter]
    si = _stats(sub, ("q-method", "minmax", *ITER_ROWS))
    sw = {m: [float(np.mean([res[m][0] for res in pt])) for pt in sweep] for m in SWEEP_ROWS}
    slopes = {m: float(np.polyfit(bounds, np.array(sw[m]), 1)[0]) for m in SWEEP_ROWS}
    q, mm = st["q-method"], st["minmax"]
    tiny = 1e-12
    return {
        "stats": st,
        "stats_iterative": si,
        "sweep_mean_deg": sw,
        "slopes": slopes,
        "err_ratio": q["mean_deg"] / max(mm["mean_deg"], tiny),
        "err_ratio_slsqp": si["q-method"]["mean_deg"] / max(si["minmax-slsqp"]["mean_deg"], tiny),
        "nsga_truth_ratio": si["q-method"]["mean_deg"] / max(si["nsga2-truth-pick"]["mean_deg"], tiny),
        "nsga_knee_ratio": si["q-method"]["mean_deg"] / max(si["nsga2-knee"]["mean_deg"], tiny),
        "worst_case_ratio": q["mean_deg"] / max(st["worst-case"]["mean_deg"], tiny),
        "var_ratio": q["var_deg2"] / max(mm["var_deg2"], tiny),
        "slope_ratio": slopes["q-method"] / max(slopes["minmax"], tiny),
        "speed_ratio": si["nsga2-knee"]["runtime_s"] / max(si["minmax-slsqp"]["runtime_s"], tiny),
        "speed_ratio_closed_form": si["nsga2-knee"]["runtime_s"] / max(si["minmax"]["runtime_s"], tiny),
        "frac_in_box": float(np.mean([res["_in_box"] for res in results])),
        "cf_vs_slsqp_max_deg": float(max(res["_cf_vs_slsqp_deg"] for res in sub)),
        "box_truth_mean_deg": st["minmax-box-at-truth"]["mean_deg"],
        "box_truth_closer": abs(st["minmax-box-at-truth"]["mean_deg"] - PAPER_TABLE1["minmax"]["mean_deg"])
        < abs(mm["mean_deg"] - PAPER_TABLE1["minmax"]["mean_deg"]),
        "box_truth_var_deg2": st["minmax-box-at-truth"]["var_deg2"],
    }


def _ratio(row_a: str, row_b: str, key: str) -> float:
    return PAPER_TABLE1[row_a][key] / PAPER_TABLE1[row_b][key]


#: "Holds" means the measured factor reaches at least half the paper's factor.
CLAIMS = (
    ClaimSpec(
        id="error-7x",
        statement="The attitude determination error with the proposed method is reduced (7 times) "
        "compared to the quaternion method.",
        where="S0 abstract; Table 1 (15.1352 vs 2.2025 deg)",
        quantity="mean δθ q-method / mean δθ min-max over one replica's trials (>= 3.5: half the claimed factor)",
        value=lambda m: m["err_ratio"], threshold=3.5, paper=round(_ratio("q-method", "minmax", "mean_deg"), 3),
        protocol_keys=("noise_bound", "search_range", "n_trials"),
    ),
    ClaimSpec(
        id="nsga2-error",
        statement="Proposed method solved with NSGA-II: mean attitude error 0.5699 deg, variance 0.1915 deg².",
        where="S0 Table 1, NSGA-II row (26.6x below the q-method row)",
        quantity="mean δθ q-method / mean δθ NSGA-II with the paper's pick (Pareto point nearest the TRUE "
        "attitude) on the same trials (>= 13: half the table's factor)",
        value=lambda m: m["nsga_truth_ratio"], threshold=13.0,
        paper=round(_ratio("q-method", "nsga2-truth-pick", "mean_deg"), 3),
        protocol_keys=("noise_bound", "search_range", "pop_size", "n_gen"),
    ),
    ClaimSpec(
        id="sensitivity-200x",
        statement="Its dependence on the accuracy of the input vectors is reduced (200 times).",
        where="S0 abstract; Table 1 variances (95.1604 vs 0.4409 deg² = 216x)",
        quantity="q-method / min-max: variance of δθ at the Table 1 noise (variance reading) or slope of "
        "mean δθ vs noise bound over the sweep (slope reading); >= 100 (half the claimed factor)",
        value=lambda m: m["sens"], threshold=100.0, paper=round(_ratio("q-method", "minmax", "var_deg2"), 1),
        readings=("variance ratio", "slope ratio"),
        protocol_keys=("noise_bound", "search_range", "sweep_bounds", "n_trials"),
    ),
    ClaimSpec(
        id="speed-600x",
        statement="Using the min-max algorithm has reduced the execution time of the algorithm (about 600 "
        "times) compared to the NSGA II algorithm.",
        where="S0 abstract; Table 1 run times (124.58 s / 0.287 s = 434x, not 600x)",
        quantity="median run time per epoch: NSGA-II / iterative min-max (SLSQP goal attainment on "
        "(q, α, β, γ) from TRIAD, the paper's kind of solver), same trials and machine; >= 300 (half of 600)",
        value=lambda m: m["speed_ratio"], threshold=300.0,
        paper=round(_ratio("nsga2-truth-pick", "minmax", "runtime_s"), 1),
        protocol_keys=("pop_size", "n_gen", "search_range"),
    ),
)

FINDINGS = (
    FindingSpec(
        id="speed-closed-form",
        statement="Our exact (closed-form + KKT) min-max is >= 300x faster than NSGA-II. Reported beside "
        "the claim; it does not decide it (a closed form against the paper's iterative solver is not like for like).",
        quantity="median run time NSGA-II / closed-form min-max",
        value=lambda m: m["speed_ratio_closed_form"], threshold=300.0,
    ),
    FindingSpec(
        id="qmethod-in-box-minority",
        statement="The unconstrained q-method attitude lies inside the ±search-range TRIAD box in only a "
        "minority of trials, so the min-max optimum (the q-method optimum restricted to the box) is "
        "usually on the box boundary.",
        quantity="fraction of trials with the q-method attitude inside the box (< 0.5)",
        value=lambda m: m["frac_in_box"], threshold=0.5, better="below",
    ),
    FindingSpec(
        id="box-at-truth-consistent",
        statement="Consistent with the paper's min-max row coming from a search box centred on the "
        "noise-free attitude: that (non-deployable) box gives a mean error closer to 2.2025 deg than "
        "the deployable box around TRIAD of the measured vectors.",
        quantity="|mean δθ box-at-truth − 2.2025| < |mean δθ min-max − 2.2025|",
        held=lambda m: m["box_truth_closer"],
    ),
    FindingSpec(
        id="knee-beats-qmethod",
        statement="NSGA-II with a truth-free (knee) pick is more accurate than the q-method.",
        quantity="mean δθ q-method / mean δθ NSGA-II knee pick, same trials (> 1)",
        value=lambda m: m["nsga_knee_ratio"], threshold=1.0,
    ),
    FindingSpec(
        id="worst-case-beats-qmethod",
        statement="The worst-case robust estimator (Ahmed & Kerrigan) is more accurate than the q-method.",
        quantity="mean δθ q-method / mean δθ worst-case (> 1)",
        value=lambda m: m["worst_case_ratio"], threshold=1.0,
    ),
)


def run(config: Config, *, quick: bool = False, rng=None, executor=None) -> StudyResult:
    from adcskit.uncertainty.executor import make_executor

    rng = np.random.default_rng(0) if rng is None else rng
    ex = executor if executor is not None else make_executor("serial")
    cfg = {"search_range": config.search_range, "pop_size": config.pop_size, "n_gen": config.n_gen}
    root = np.random.SeedSequence(int(rng.integers(2**63 - 1)))
    bounds = np.array(config.sweep_bounds, float)
    nb = len(bounds)

    # ---- every replica: Table 1 trials + the noise sweep, all tasks in one map
    tasks, where = [], []
    for j, rep in enumerate(root.spawn(config.n_seeds)):
        main_ss, sweep_ss = rep.spawn(2)
        for i, s in enumerate(main_ss.spawn(config.n_trials)):
            rows = CHEAP_ROWS + ITER_ROWS if i < config.n_iterative else CHEAP_ROWS
            tasks.append((s, config.noise_bound, cfg, rows))
            where.append((j, "table", 0))
        for k, ss in enumerate(sweep_ss.spawn(nb)):
            for s in ss.spawn(config.sweep_trials):
                tasks.append((s, float(bounds[k]), cfg, SWEEP_ROWS))
                where.append((j, "sweep", k))
    out = ex.map(trial, tasks, description="Table 1 replicas and sweep")
    table = [[] for _ in range(config.n_seeds)]
    sweep = [[[] for _ in range(nb)] for _ in range(config.n_seeds)]
    for (j, kind, k), res in zip(where, out):
        (table[j] if kind == "table" else sweep[j][k]).append(res)
    reps = [_replica_measure(table[j], sweep[j], bounds, config.n_iterative) for j in range(config.n_seeds)]

    # ---- verdicts
    claims = []
    for spec in CLAIMS:
        if spec.id == "sensitivity-200x":
            runs = {"variance ratio": [{"sens": m["var_ratio"]} for m in reps],
                    "slope ratio": [{"sens": m["slope_ratio"]} for m in reps]}
            claims.append(spec.evaluate(runs, default="variance ratio"))
        else:
            claims.append(spec.evaluate({"default": reps}))
    findings = [spec.evaluate({"default": reps}) for spec in FINDINGS]

    # ---- pooled statistics (all replicas' trials)
    pooled = [res for rep in table for res in rep]
    stats = _stats(pooled, CHEAP_ROWS)
    stats.update({m: v for m, v in _stats([r for rep in table for r in rep[: config.n_iterative]], ITER_ROWS).items()})
    sweep_mean = {m: [float(np.mean([res[m][0] for j in range(config.n_seeds) for res in sweep[j][k]]))
                      for k in range(nb)] for m in SWEEP_ROWS}
    slopes = {m: float(np.polyfit(bounds, np.array(sweep_mean[m]), 1)[0]) for m in SWEEP_ROWS}

    # ---- checks (ours)
    q_ex = solve_wahba(B_EXACT, R_EXACT).q
    ex_err = angle_deg(q_ex, q_exact())
    ang_r = np.degrees(np.arccos(np.dot(R_EXACT[0], R_EXACT[1]) / np.prod(np.linalg.norm(R_EXACT, axis=1))))
    ang_b = np.degrees(np.arccos(np.dot(B_EXACT[0], B_EXACT[1]) / np.prod(np.linalg.norm(B_EXACT, axis=1))))
    cf_slsqp = max(m["cf_vs_slsqp_max_deg"] for m in reps)
    qm = stats["q-method"]
    checks = [
        Check(
            name="q-method on the exact eq. 9 vectors returns q_exact (scalar-first reading)",
            passed=ex_err < 0.1,
            detail=f"δθ = {ex_err:.4f} deg (4-digit printed quaternion: < 0.1 deg expected)",
            kind="check",
        ),
        Check(
            name="QUEST and SVD rows equal the q-method row",
            passed=abs(stats["quest"]["mean_deg"] - qm["mean_deg"]) < 1e-6
            and abs(stats["svd"]["mean_deg"] - qm["mean_deg"]) < 1e-6,
            detail=f"means {stats['quest']['mean_deg']:.9f}, {stats['svd']['mean_deg']:.9f}, {qm['mean_deg']:.9f} deg",
            kind="check",
        ),
        Check(
            name="the exact and the iterative (SLSQP) min-max solvers return the same attitude",
            passed=cf_slsqp < 1e-2,
            detail=f"largest angle between them over {config.n_seeds} x {config.n_iterative} trials: "
            f"{cf_slsqp:.2e} deg (pass if < 0.01 deg)",
            kind="check",
        ),
        Check(
            name="the noise model reproduces the paper's q-method row (mean within ±30 %)",
            passed=0.7 * PAPER_TABLE1["q-method"]["mean_deg"] < qm["mean_deg"] < 1.3 * PAPER_TABLE1["q-method"]["mean_deg"],
            detail=f"q-method mean δθ {qm['mean_deg']:.3f} deg over {len(pooled)} trials; paper 15.1352 deg",
            kind="check",
        ),
    ]

    # ---- figures
    fig1, ax = new_figure(figsize=(7.0, 4.2))
    styles = {"q-method": ("k", "o-"), "minmax": ("C0", "s-"), "worst-case": ("C2", "^-"),
              "minmax-box-at-exact-triad": ("C3", "v--"), "minmax-box-at-truth": ("C1", "d--")}
    for m in SWEEP_ROWS:
        col, st_ = styles[m]
        ax.plot(bounds * 100, sweep_mean[m], st_, color=col, label=m)
    ax.set_xlabel("noise bound [% of component]")
    ax.set_ylabel("mean attitude error δθ [deg]")
    ax.set_title(f"S0 sensitivity sweep ({config.n_seeds} x {config.sweep_trials} trials per point)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig2, ax2 = new_figure(figsize=(7.6, 4.4))
    names = list(ROWS)
    data = [[res[m][0] for res in pooled if m in res] for m in names]
    ax2.boxplot(data, tick_labels=names)
    ax2.set_ylabel("δθ [deg]")
    ax2.set_title(f"Table 1 trials (±{config.noise_bound:.0%}, {config.n_seeds} x {config.n_trials} trials; "
                  f"iterative rows {config.n_seeds} x {config.n_iterative})")
    ax2.tick_params(axis="x", labelrotation=30)
    fig3, ax3 = new_figure(figsize=(7.0, 4.2))
    keys = (("err_ratio", "error q/min-max"), ("nsga_truth_ratio", "error q/NSGA-II truth pick"),
            ("var_ratio", "variance q/min-max"), ("slope_ratio", "slope q/min-max"),
            ("speed_ratio", "time NSGA-II/SLSQP min-max"), ("speed_ratio_closed_form", "time NSGA-II/closed form"))
    for i, (k, _lab) in enumerate(keys):
        v = [m[k] for m in reps]
        ax3.plot(np.full(len(v), i), v, "o", color=f"C{i}", alpha=0.7)
    paper_marks = (_ratio("q-method", "minmax", "mean_deg"), _ratio("q-method", "nsga2-truth-pick", "mean_deg"),
                   _ratio("q-method", "minmax", "var_deg2"), 200.0, 600.0, 600.0)
    ax3.plot(range(len(keys)), paper_marks, "k_", ms=20, mew=2, label="paper's factor")
    ax3.set_yscale("log")
    ax3.set_xticks(range(len(keys)), [lab for _, lab in keys], rotation=25, fontsize=7)
    ax3.set_ylabel("ratio [-]")
    ax3.set_title(f"Deciding ratios per replica ({config.n_seeds} seeds) vs the paper")
    ax3.axhline(1.0, color="0.6", lw=0.8)
    ax3.legend(fontsize=8)

    comparison = []
    for m in ROWS:
        p = PAPER_TABLE1.get(m, {})
        for key, unit in (("mean_deg", "deg"), ("var_deg2", "deg²"), ("runtime_s", "s")):
            comparison.append(
                Comparison(quantity=f"{m}: {key}", paper=p.get(key), measured=stats[m][key], unit=unit,
                           note=("" if p else "not in the paper") + f" ({stats[m]['n_trials']} trials pooled)")
            )
    table_rows = [{"method": m, **stats[m], **({"sweep_slope_deg_per_unit": slopes[m]} if m in slopes else {})}
                  for m in ROWS]
    sweep_rows = [{"noise_bound": float(bd), **{m: sweep_mean[m][i] for m in SWEEP_ROWS}} for i, bd in enumerate(bounds)]
    replica_rows = [{"replica": j, **{k: m[k] for k in ("err_ratio", "err_ratio_slsqp", "nsga_truth_ratio",
                                                          "nsga_knee_ratio", "worst_case_ratio", "var_ratio",
                                                          "slope_ratio", "speed_ratio", "speed_ratio_closed_form",
                                                          "frac_in_box", "box_truth_mean_deg")}}
                    for j, m in enumerate(reps)]
    frac_box = float(np.mean([res["_in_box"] for res in pooled]))
    sr = f"±{config.search_range:.0%}"
    by_id = {c.id: c for c in claims}
    summary = (
        f"{config.n_seeds} replicas x {config.n_trials} trials (±{config.noise_bound:.0%} noise): q-method "
        f"{qm['mean_deg']:.2f} deg vs min-max {stats['minmax']['mean_deg']:.2f} deg (paper 15.14 vs 2.20). "
        f"The printed min-max problem is the q-method optimum restricted to the {sr} TRIAD box; the "
        f"unconstrained q-method attitude lies inside that box in only {100 * frac_box:.0f} % of trials. "
        f"7x lower error: {by_id['error-7x'].outcome}; 200x less sensitive: {by_id['sensitivity-200x'].outcome} "
        f"(variance ratio {np.mean([m['var_ratio'] for m in reps]):.2f}, slope ratio "
        f"{np.mean([m['slope_ratio'] for m in reps]):.2f}); ~600x faster than NSGA-II "
        f"({config.pop_size}x{config.n_gen}) with an iterative SLSQP min-max: {by_id['speed-600x'].outcome} "
        f"(ratio {np.mean([m['speed_ratio'] for m in reps]):.0f}; the paper's own table gives "
        f"{_ratio('nsga2-truth-pick', 'minmax', 'runtime_s'):.0f}x; closed form "
        f"{np.mean([m['speed_ratio_closed_form'] for m in reps]):.0f}x). NSGA-II with the paper's truth pick: "
        f"{stats['nsga2-truth-pick']['mean_deg']:.2f} deg (paper 0.57). A box centred on the true attitude gives "
        f"{stats['minmax-box-at-truth']['mean_deg']:.2f} deg, consistent with the paper's min-max row."
    )
    return StudyResult(
        study="wahba-table1",
        title=f"Robust Wahba, one epoch with ±{config.noise_bound:.0%} interval noise (S0 Table 1)",
        summary=summary,
        config=asdict(config),
        paper={"methods": PAPER_TABLE1, "source": "S0 Table 1 (100 trials, ±20 % bounded noise), eq. 9",
               "ratios": {"error_qmethod_over_minmax": _ratio("q-method", "minmax", "mean_deg"),
                          "variance_qmethod_over_minmax": _ratio("q-method", "minmax", "var_deg2"),
                          "runtime_nsga2_over_minmax": _ratio("nsga2-truth-pick", "minmax", "runtime_s"),
                          "claimed": {"error": 7, "sensitivity": 200, "speed": 600}}},
        measured={
            "methods": stats,
            "sweep": {"noise_bound": bounds.tolist(), "mean_deg": sweep_mean, "slope_deg_per_unit": slopes},
            "replicas": replica_rows,
            "fraction_qmethod_in_box": frac_box,
            "closed_form_vs_slsqp_max_deg": cf_slsqp,
            "exact_vectors": {"qmethod_vs_qexact_deg": ex_err, "angle_r1_r2_deg": float(ang_r),
                              "angle_b1_b2_deg": float(ang_b)},
        },
        checks=checks,
        claims=claims,
        findings=findings,
        comparison=comparison,
        differences=[
            "q_exact is printed scalar-first with Shuster's A(q); we convert to scalar-last.",
            "Noise: each component multiplied by (1 + u), u ~ U(−bound, bound), then renormalised; the "
            "interval given to the robust solvers is midpoint = measured vector, radius = bound·|measured "
            "component|.",
            "Min-max: the goal-attainment problem as printed (z* = 0, λ = 1, |ΔL|) is solved exactly "
            "(closed form + KKT on the TRIAD box: row 'minmax') and iteratively as the paper does "
            "(SLSQP on (q, α, β, γ) from TRIAD, finite-difference gradients like MATLAB fminimax: row "
            "'minmax-slsqp'). Both give the same attitude; the speed claim is decided with the iterative one.",
            "NSGA-II: pymoo, population/generations ours (not printed); eq. 5 enforced by renormalising "
            "the box points; ΔL minimised signed (with |ΔL| the front collapses to the q-method point). "
            "The NSGA-II run time scales with population x generations; the paper's 124.58 s suggests a "
            "larger budget than ours.",
            "The paper's NSGA-II row picks the Pareto point nearest the true attitude; we report it as "
            "'nsga2-truth-pick' (not deployable) beside a truth-free knee pick.",
            "Every claim is decided over independent replicas of the whole table (noise draws and "
            "NSGA-II seeds); the iterative rows run on the first n_iterative trials of each replica.",
            "'200 times less dependence': two readings, the variance ratio at ±20 % (the paper's table "
            "gives 95.16/0.4409 = 216) and the ratio of slopes of mean error vs noise bound.",
            "The paper's run-time table gives 124.58/0.287 = 434x, not the abstract's 600x.",
            "Worst-case row (Ahmed & Kerrigan) added; QUEST/SVD rows are sanity checks.",
            "Diagnostic rows minmax-box-at-exact-triad / minmax-box-at-truth centre the search box on "
            "the noise-free answer (not deployable) to test how the paper's min-max figures could arise.",
            "Run times: median per epoch on a loaded 2-core machine, Python + numba; not comparable to "
            "the paper's MATLAB figures in absolute terms.",
        ],
        figures={"sweep-mean-error": fig1, "table1-errors": fig2, "replica-ratios": fig3},
        tables={"table1": table_rows, "sweep": sweep_rows, "replicas": replica_rows},
        doc=STUDY.doc,
    )


STUDY = Study(
    name="wahba-table1",
    title="Robust Wahba, one epoch with ±20 % interval noise (S0 Table 1)",
    paper="S0",
    config_cls=Config,
    run=run,
    quick={"n_seeds": 2, "n_trials": 12, "n_iterative": 3, "pop_size": 24, "n_gen": 20,
           "sweep_bounds": (0.02, 0.1, 0.2), "sweep_trials": 6},
    doc="docs/studies/wahba-table1.md",
)
