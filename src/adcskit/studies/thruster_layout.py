"""Study ``thruster-layout``: GEO thruster layout design with GA vs DE (S3).

S3 designs thruster layouts for a 2 x 2 x 2 m GEO satellite by minimising
``F_best = K1 error + K2 e_min + K3 sum t_p`` (eq. 18) with a genetic algorithm and
differential evolution, for 4, 6, 8 and 12 thrusters, and compares the on-times of its
optimal 6-thruster layout with a reference layout (Servidia & Sanchez Pena 2000).

What this study does (details and every choice: ``docs/studies/thruster-layout.md``):

* the manoeuvre is a set of attitude corrections the paper does not give: the first-sample
  PD torque ``M = K theta e`` for ``theta = correction_deg`` about the 6 body half-axes and
  the 8 cube diagonals (14 demands), with S3's ``K = 600 N m/rad``;
* each (n, algorithm) pair is run with ``n_seeds`` independent seeds on pymoo's GA and DE
  (:func:`adcskit.thrusters.design_layout`), equal population and 400 generations;
* the best 6-thruster layouts are compared with the reference on the same manoeuvre with
  S3's allocation (``pinv-redistribute``) and the exact least-fuel LP (``lp-min-fuel``);
* the redistributed pseudo-inverse's torque miss is measured on random 8-thruster layouts;
* the paper's printed layout matrices are checked for physical realisability in the box.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from adcskit.studies._base import Check, Comparison, Study, StudyResult, new_figure
from adcskit.studies._verdict import ClaimSpec, FindingSpec
from adcskit.thrusters.reference import S3_REFERENCE_A, s3_manoeuvre_demands

__all__ = ["Config", "run", "STUDY", "manoeuvre_demands", "A_REF", "PAPER"]

#: S3 §6: reference 6-thruster layout (:data:`adcskit.thrusters.S3_REFERENCE_A`) and the manoeuvre
#: (:func:`adcskit.thrusters.s3_manoeuvre_demands`), kept under the study's names.
A_REF = S3_REFERENCE_A
manoeuvre_demands = s3_manoeuvre_demands

#: S3's printed results (§6, Table 8) and layouts. The 4-thruster GA matrix prints "101" in
#: row 2 (read as 1.01); the 8-thruster matrix is printed wrapped as a 6 x 5 block (columns
#: 1-5 in rows 1-3, columns 6-8 in rows 4-6).
PAPER: dict[str, Any] = {
    "source": "S3 §6 (printed F_best and layout matrices), Table 8 (e_min, rad), Tables 5-7",
    "f_best": {"4": {"ga": 4.5, "de": 3.1}, "6": {"de": 3.4}, "8": {"de": 3.6}},
    "table8_e_min_rad": {"4": 0.00084, "6": 0.00083, "8": 0.00082, "12": 0.00083},
    "claims": [
        "DE reaches lower fitness and runs faster than GA (Figs 3-4)",
        "the lowest fitness is at 6 thrusters for both algorithms (Fig 4)",
        "the optimal 6-thruster layout needs shorter on-times (less fuel) than the reference (Fig 5)",
    ],
    "layouts": {
        "4-ga": [[0.66, 0, -1, -0.90], [0, 1.01, 0.19, -0.62], [-0.997, 1.2, 0.93, -0.68]],
        "4-de": [[0.351, 0, -0.99, -0.77], [0, 0.72, 0.02, -0.66], [-0.998, 0.71, 0.93, -0.56]],
        "6-de": [
            [-1.3, -1.4, -1.3, 1.4, 0.99, 0.99],
            [0.81, -0.47, -0.39, 0.96, 0, 0],
            [-0.57, -1.24, 1.27, -0.4, 0.99, 0.99],
        ],
        "8-de": [
            [-1.3, -1.3, 1.4, 1.41, 1.4, -1.3, -1.26, -1.18],
            [-1.06, -0.89, 0.69, -0.13, 0.69, -0.77, 0.27, 0.56],
            [-1.38, -0.4, 0.82, 0.03, -0.27, 0.89, -1.11, -0.58],
        ],
        "reference": A_REF.tolist(),
    },
}

_FACE_NAMES = ("+X", "-X", "+Y", "-Y", "+Z", "-Z")
_EMIN_READINGS = ("single thruster", "paired couple")


@dataclass(frozen=True, kw_only=True)
class Config:
    """Settings of the ``thruster-layout`` study; defaults are S3's where S3 gives them.

    Attributes
    ----------
    n_thrusters : tuple of int
        Layout sizes (S3: 4, 6, 8, 12).
    algorithms : tuple of {"ga", "de"}
    n_seeds : int
        Independent runs per (n, algorithm) for the verdicts (>= 5 by the issue).
    n_gen : int
        Generations (S3 Table 6: 400).
    pop_size : int
        Population, equal for GA and DE (S3: equal, size not printed).
    box_half_size_m : (float, float, float), m
        Half sizes of the mounting box, CoM at the centre (S3: 2 x 2 x 2 m box; eq. 20:
        -1 <= r <= 1 m).
    inertia_kgm2 : (float, float, float), kg m²
        Principal moments of inertia (S3 eq. 19; reported for the natural frequencies
        ``sqrt(K/J)``; not used by eq. 18).
    f_max_n : float, N
        Largest thrust of each thruster (S3 Table 5 and §6: 10 N).
    t_min_s : float, s
        Minimum on-time of a thruster (S3 Table 5 and §6: 3 ms).
    mdot_kg_s : float, kg/s
        Propellant mass flow of a firing thruster (S3 Table 5 and §6: 3.5 g/s).
    t_s_s : float, s
        Sample time (S3 Table 6: 0.2 s).
    gain_nm_per_rad : float, N m/rad
        Attitude gain ``K`` (S3 Table 6: 600).
    weights : (float, float, float)
        ``K1, K2, K3`` of eq. 18 (S3 Table 7: 100, -99, 12, signs as printed).
    correction_deg : float, deg
        Size of each attitude correction of the manoeuvre set (ours; S3 gives none).
    faces : tuple of str
        Mounting faces allowed (S3: all six, "solar arrays impose no limit").
    max_cant_deg : float, deg
        Largest angle between thrust and inward face normal (S3 Tables 1-4: 90).
    de_strategy : str
        ``"current-to-best/1/bin"`` (Storn & Price DE2, S3's "second strategy") or
        ``"rand/1/bin"``.
    de_F, de_CR : float
        DE weight and crossover rate.
    n_random_layouts : int
        Random 8-thruster layouts for the pseudo-inverse miss measurement.
    de_sensitivity : tuple of str
        Extra DE settings ``"strategy:F:CR"`` run for 6 thrusters with the same seeds, so
        that the GA-vs-DE verdict does not hinge on one DE setting (empty: skip).
    n_fuel_demands : int
        Random demand directions per seed (magnitude of the manoeuvre's demands) on which
        the fuel of the optimal and the reference layout is compared out of sample.
    e_min_readings : tuple of {"single thruster", "paired couple"}
        Readings of S3's impulse bit for Table 8; the first is the default. "paired couple"
        (S3 §4-1: thrusters on parallel faces act as a pair) re-runs the DE designs with one
        gene per couple, whose impulse bit is ``2 Delta F_max t_min``.
    e_min_tolerance : float
        Relative distance from S3 Table 8 within which an ``e_min`` counts as reproduced
        (Table 8 prints two significant digits; 0.1 is generous).
    """

    n_thrusters: tuple[int, ...] = (4, 6, 8, 12)
    algorithms: tuple[str, ...] = ("ga", "de")
    n_seeds: int = 5
    n_gen: int = 400
    pop_size: int = 50
    box_half_size_m: tuple[float, float, float] = (1.0, 1.0, 1.0)
    inertia_kgm2: tuple[float, float, float] = (1218.6, 442.2, 1429.4)
    f_max_n: float = 10.0
    t_min_s: float = 3e-3
    mdot_kg_s: float = 3.5e-3
    t_s_s: float = 0.2
    gain_nm_per_rad: float = 600.0
    weights: tuple[float, float, float] = (100.0, -99.0, 12.0)
    correction_deg: float = 0.5
    faces: tuple[str, ...] = _FACE_NAMES
    max_cant_deg: float = 90.0
    de_strategy: str = "current-to-best/1/bin"
    de_F: float = 0.8
    de_CR: float = 0.9
    n_random_layouts: int = 200
    de_sensitivity: tuple[str, ...] = ("rand/1/bin:0.5:0.9", "current-to-best/1/bin:0.5:0.2")
    n_fuel_demands: int = 200
    e_min_readings: tuple[str, ...] = ("single thruster", "paired couple")
    e_min_tolerance: float = 0.1

    def __post_init__(self) -> None:
        from adcskit.errors import ConfigError

        if not self.n_thrusters or any(int(n) < 4 for n in self.n_thrusters):
            raise ConfigError(f"n_thrusters must be a non-empty tuple of ints >= 4; got {self.n_thrusters}")
        if not self.algorithms or any(a not in ("ga", "de") for a in self.algorithms):
            raise ConfigError(f"algorithms must be a non-empty subset of ('ga', 'de'); got {self.algorithms}")
        for name, lo in (("n_seeds", 1), ("n_gen", 1), ("pop_size", 4), ("n_random_layouts", 1),
                         ("n_fuel_demands", 1)):
            if int(getattr(self, name)) < lo:
                raise ConfigError(f"{name} must be >= {lo}; got {getattr(self, name)}")
        for name in ("f_max_n", "mdot_kg_s", "t_s_s", "gain_nm_per_rad", "correction_deg", "de_F"):
            if not getattr(self, name) > 0:
                raise ConfigError(f"{name} must be > 0; got {getattr(self, name)}")
        if self.t_min_s < 0:
            raise ConfigError(f"t_min_s must be >= 0 s; got {self.t_min_s}")
        if any(h <= 0 for h in self.box_half_size_m) or any(j <= 0 for j in self.inertia_kgm2):
            raise ConfigError("box_half_size_m and inertia_kgm2 must be > 0 per axis")
        if not self.faces or any(f not in _FACE_NAMES for f in self.faces) or len(set(self.faces)) != len(self.faces):
            raise ConfigError(f"faces must be distinct names from {_FACE_NAMES}; got {self.faces}")
        if not 0 <= self.max_cant_deg <= 90:
            raise ConfigError(f"max_cant_deg must be in [0, 90] deg; got {self.max_cant_deg}")
        if self.de_strategy not in ("current-to-best/1/bin", "rand/1/bin"):
            raise ConfigError(
                f"de_strategy must be 'current-to-best/1/bin' or 'rand/1/bin'; got {self.de_strategy!r}"
            )
        if not 0 <= self.de_CR <= 1:
            raise ConfigError(f"de_CR must be in [0, 1]; got {self.de_CR}")
        for spec in self.de_sensitivity:
            _parse_de(spec)
        if (not self.e_min_readings or len(set(self.e_min_readings)) != len(self.e_min_readings)
                or any(r not in _EMIN_READINGS for r in self.e_min_readings)):
            raise ConfigError(f"e_min_readings must be distinct names from {_EMIN_READINGS}; got {self.e_min_readings}")
        if "paired couple" in self.e_min_readings and any(int(n) % 2 for n in self.n_thrusters):
            raise ConfigError("the 'paired couple' reading needs even n_thrusters")
        opposite = {"+X": "-X", "-X": "+X", "+Y": "-Y", "-Y": "+Y", "+Z": "-Z", "-Z": "+Z"}
        if "paired couple" in self.e_min_readings and any(opposite[f] not in self.faces for f in self.faces):
            raise ConfigError(f"the 'paired couple' reading needs the parallel face of every face; got {self.faces}")
        if not 0 < self.e_min_tolerance < 1:
            raise ConfigError(f"e_min_tolerance must be in (0, 1); got {self.e_min_tolerance}")


def _parse_de(spec: str) -> tuple[str, float, float]:
    from adcskit.errors import ConfigError

    parts = str(spec).split(":")
    try:
        strat, F, CR = parts[0], float(parts[1]), float(parts[2])
    except (IndexError, ValueError):
        raise ConfigError(f"de_sensitivity entries must be 'strategy:F:CR'; got {spec!r}") from None
    if strat not in ("current-to-best/1/bin", "rand/1/bin") or len(parts) != 3 or F <= 0 or not 0 <= CR <= 1:
        raise ConfigError(
            f"de_sensitivity entry {spec!r} must be 'strategy:F:CR' with strategy "
            "'current-to-best/1/bin' or 'rand/1/bin', F > 0, CR in [0, 1]"
        )
    return strat, F, CR


# ----------------------------------------------------------------------------- tasks


def _design_task(task: dict[str, Any]) -> dict[str, Any]:
    """One optimisation run (picklable, for any executor)."""
    from adcskit.thrusters import box_faces, design_layout

    faces = box_faces(task["half"], task["faces"], max_cant=math.radians(task["max_cant_deg"]))
    res = design_layout(
        task["n"], task["demands"], mounting=faces, algorithm=task["alg"],
        weights=task["weights"], f_max=task["f_max"], t_min=task["t_min"], mdot=task["mdot"],
        t_s=task["t_s"], gain=task["gain"], pop_size=task["pop_size"], n_gen=task["n_gen"],
        de_strategy=task["de_strategy"], de_F=task["de_F"], de_CR=task["de_CR"],
        rng=np.random.default_rng(task["seed"]), paired=task.get("paired", False),
    )
    return {
        "n": task["n"], "alg": task["alg"], "seed_index": task["seed_index"],
        "f_best": res.fun, "torque_error": res.error, "e_min": res.e_min, "sum_tp_s": res.sum_tp,
        "runtime_s": res.runtime_s, "cpu_s": res.cpu_s, "evaluations": res.nfev, "history": res.history,
        "torque_matrix": res.torque_matrix, "positions": res.thrusters.positions,
        "directions": res.thrusters.directions, "faces": list(res.thrusters.names),
    }


def _face_ok(row: dict[str, Any], half: np.ndarray, max_cant: float) -> bool:
    normals = {"+X": (0, 1), "-X": (0, -1), "+Y": (1, 1), "-Y": (1, -1), "+Z": (2, 1), "-Z": (2, -1)}
    for p, d, f in zip(row["positions"], row["directions"], row["faces"]):
        k, s = normals[f]
        n = np.zeros(3)
        n[k] = s
        on_face = abs(p[k] - s * half[k]) < 1e-9 and np.all(np.abs(p) <= half + 1e-9)
        cant = math.acos(min(1.0, max(-1.0, float(-d @ n))))
        if not (on_face and d @ n <= 1e-12 and cant <= max_cant + 1e-9):
            return False
    return True


def _alloc_stats(A: np.ndarray, demands: np.ndarray, method: str, cfg: Config) -> dict[str, Any]:
    from adcskit.thrusters import allocate, fuel_mass, pulse_width

    res = allocate(A, demands, method=method, f_max=cfg.f_max_n)
    tp = pulse_width(res.x, f_max=cfg.f_max_n, t_s=cfg.t_s_s)
    return {
        "sum_tp_s": float(tp.sum(axis=1).mean()),
        "error_nm": float(res.error.mean()),
        "all_met": bool(res.feasible.all()),
        "fuel_kg": float(fuel_mass(tp, mdot=cfg.mdot_kg_s).sum()),
        "on_times_s": tp.sum(axis=0),
    }


def _pinv_miss(cfg: Config, rng: np.random.Generator) -> dict[str, Any]:
    """Relative torque miss of each allocator on random 8-thruster layouts, feasible demands."""
    from adcskit.thrusters import allocate, box_faces, decode_layout

    faces = box_faces(cfg.box_half_size_m)
    n = 8
    lo = np.tile([0, -1, -1, 0, 0], n)
    hi = np.tile([len(faces) - 1e-9, 1, 1, 1, 2 * np.pi], n)
    rel: dict[str, list[float]] = {"pinv-redistribute": [], "nnls": [], "lp-min-fuel": []}
    for _ in range(cfg.n_random_layouts):
        A = decode_layout(rng.uniform(lo, hi), faces).torque_matrix()
        F_true = rng.uniform(0, cfg.f_max_n, size=n)
        M = A @ F_true  # feasible by construction
        for method in rel:
            r = allocate(A, M, method=method, f_max=cfg.f_max_n)
            rel[method].append(float(r.error / np.linalg.norm(M)))
    out: dict[str, Any] = {"n_layouts": cfg.n_random_layouts, "n_thrusters": n}
    for method, v in rel.items():
        a = np.asarray(v)
        out[method] = {
            "median_rel_error": float(np.median(a)), "p90_rel_error": float(np.quantile(a, 0.9)),
            "max_rel_error": float(a.max()), "fraction_exact_1e-9": float(np.mean(a <= 1e-9)),
        }
    return out


# ----------------------------------------------------------------------------- figures


def _fig_runtime(cfg, agg):
    fig, ax = new_figure()
    for alg, mk in (("ga", "s-"), ("de", "o-")):
        if alg not in cfg.algorithms:
            continue
        ns = list(cfg.n_thrusters)
        med = [agg[str(n)][alg]["cpu_s"] for n in ns]
        lo = [min(agg[str(n)][alg]["cpu_s_seeds"]) for n in ns]
        hi = [max(agg[str(n)][alg]["cpu_s_seeds"]) for n in ns]
        color = "C0" if alg == "ga" else "C1"
        ax.errorbar(ns, med, yerr=[np.subtract(med, lo), np.subtract(hi, med)], fmt=mk, color=color,
                    capsize=3, label=f"{alg.upper()} CPU time (median, min-max over seeds)")
        ax.plot(ns, [agg[str(n)][alg]["runtime_s"] for n in ns], mk[0] + ":", color=color, alpha=0.5,
                label=f"{alg.upper()} wall time (median; shared machine)")
    ax.set_xlabel("number of thrusters")
    ax.set_ylabel("time per optimisation (s)")
    ax.set_title(f"Run time vs n ({cfg.n_gen} generations x {cfg.pop_size}; cf. S3 Fig 3)")
    ax.set_xticks(list(cfg.n_thrusters))
    ax.legend()
    return fig


def _fig_fitness(cfg, agg):
    fig, ax = new_figure()
    off = {"ga": -0.12, "de": 0.12}
    for alg, mk in (("ga", "s"), ("de", "o")):
        if alg not in cfg.algorithms:
            continue
        ns = list(cfg.n_thrusters)
        for n in ns:
            v = agg[str(n)][alg]["f_best_seeds"]
            ax.plot(np.full(len(v), n + off[alg]), v, mk, alpha=0.35, color="C0" if alg == "ga" else "C1")
        ax.plot(np.add(ns, off[alg]), [agg[str(n)][alg]["f_best_median"] for n in ns], mk + "-",
                color="C0" if alg == "ga" else "C1", label=f"{alg.upper()} median (dots: seeds)")
    for n, d in PAPER["f_best"].items():
        for _alg, v in d.items():
            ax.plot(int(n), v, "x", color="k", ms=8)
    ax.plot([], [], "x", color="k", label="S3 printed F_best (own manoeuvre)")
    ax.set_xlabel("number of thrusters")
    ax.set_ylabel("F_best (S3 eq. 18)")
    ax.set_yscale("log")
    ax.set_title("Fitness vs n (cf. S3 Fig 4)")
    ax.set_xticks(list(cfg.n_thrusters))
    ax.legend(fontsize=8)
    return fig


def _fig_on_times(rvo):
    fig, axes = new_figure(1, 2, figsize=(9.0, 3.8))
    for ax, method in zip(axes, ("pinv-redistribute", "lp-min-fuel")):
        d = rvo["by_allocation"][method]
        ref, opt = np.asarray(d["on_times_ref_s"]), np.asarray(d["on_times_opt_s"])
        i = np.arange(1, len(ref) + 1)
        ax.bar(i - 0.2, ref, 0.4, label=f"reference (sum {ref.sum():.3f} s)")
        ax.bar(i + 0.2, opt, 0.4, label=f"optimal (sum {opt.sum():.3f} s)")
        ax.set_xlabel("thruster")
        ax.set_ylabel("total on-time over the manoeuvre (s)")
        ax.set_title(method, fontsize=10)
        ax.set_xticks(i)
        ax.legend(fontsize=8)
    fig.suptitle("On-times on the 14 design demands: reference vs best 6-thruster layout (cf. S3 Fig 5)")
    return fig


def _fig_convergence(cfg, rows):
    ns = list(cfg.n_thrusters)
    ncols = min(len(ns), 2)
    nrows = math.ceil(len(ns) / ncols)
    fig, axes = new_figure(nrows, ncols, figsize=(9.0, 3.2 * nrows), squeeze=False)
    for ax, n in zip(axes.flat, ns):
        for alg, color in (("ga", "C0"), ("de", "C1")):
            H = np.array([r["history"] for r in rows if r["n"] == n and r["alg"] == alg])
            if H.size == 0:
                continue
            g = np.arange(1, H.shape[1] + 1)
            ax.fill_between(g, H.min(0), H.max(0), color=color, alpha=0.2)
            ax.plot(g, np.median(H, 0), color=color, label=f"{alg.upper()} median, min-max band")
        ax.set_yscale("log")
        ax.set_title(f"n = {n}", fontsize=10)
        ax.set_xlabel("generation")
        ax.set_ylabel("best F_best")
        ax.legend(fontsize=8)
    for ax in list(axes.flat)[len(ns):]:
        ax.set_visible(False)
    fig.suptitle("Convergence (best so far) over seeds")
    return fig


def _draw_box(ax, h):
    corners = np.array([[x, y, z] for x in (-h[0], h[0]) for y in (-h[1], h[1]) for z in (-h[2], h[2])])
    for i in range(8):
        for j in range(i + 1, 8):
            if np.sum(corners[i] != corners[j]) == 1:
                ax.plot(*zip(corners[i], corners[j]), color="0.6", lw=0.8)


def _fig_layouts(cfg, best):
    from matplotlib.figure import Figure

    ns = list(cfg.n_thrusters)
    ncols = min(len(ns), 2)
    nrows = math.ceil(len(ns) / ncols)
    fig = Figure(figsize=(9.0, 4.2 * nrows), layout="constrained")
    h = np.asarray(cfg.box_half_size_m)
    for k, n in enumerate(ns):
        ax = fig.add_subplot(nrows, ncols, k + 1, projection="3d")
        _draw_box(ax, h)
        row = best[n]
        P, D = np.asarray(row["positions"]), np.asarray(row["directions"])
        ax.scatter(*P.T, color="C3", s=18)
        ax.quiver(*P.T, *(-0.5 * D).T, color="C1", lw=1.2, label="exhaust (-d)")
        ax.quiver(*P.T, *(0.5 * D).T, color="C0", lw=1.2, label="force d")
        ax.set_title(f"n = {n} ({row['alg'].upper()}), F_best {row['f_best']:.3f}", fontsize=9)
        ax.set_xlabel("X (m)")
        ax.set_ylabel("Y (m)")
        ax.set_zlabel("Z (m)")
        lim = 1.5 * h.max()
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
        ax.set_zlim(-lim, lim)
        if k == 0:
            ax.legend(fontsize=7, loc="upper left")
    fig.suptitle("Best layouts on the 2 x 2 x 2 m box")
    return fig


# ----------------------------------------------------------------------------- run


def run(config: Config, *, quick: bool = False, rng: Any = None, executor: Any = None) -> StudyResult:
    """Run the study (see the module docstring)."""
    from adcskit._validation import as_rng
    from adcskit.thrusters import check_controllability, score_layout
    from adcskit.uncertainty.executor import SerialExecutor

    cfg = config
    rng = as_rng(rng)
    ex = executor if executor is not None else SerialExecutor()
    demands = manoeuvre_demands(cfg.correction_deg, cfg.gain_nm_per_rad)
    half = np.asarray(cfg.box_half_size_m, float)
    root = np.random.SeedSequence(int(rng.integers(2**63)))
    tasks = []
    children = iter(root.spawn(len(cfg.n_thrusters) * len(cfg.algorithms) * cfg.n_seeds))
    for s in range(cfg.n_seeds):
        for n in cfg.n_thrusters:
            for alg in cfg.algorithms:  # interleaved so background load hits GA and DE alike
                tasks.append({
                    "n": int(n), "alg": alg, "seed_index": s, "seed": next(children),
                    "demands": demands, "half": tuple(half), "faces": tuple(cfg.faces),
                    "max_cant_deg": cfg.max_cant_deg, "weights": tuple(cfg.weights),
                    "f_max": cfg.f_max_n, "t_min": cfg.t_min_s, "mdot": cfg.mdot_kg_s,
                    "t_s": cfg.t_s_s, "gain": cfg.gain_nm_per_rad, "pop_size": cfg.pop_size,
                    "n_gen": cfg.n_gen, "de_strategy": cfg.de_strategy, "de_F": cfg.de_F,
                    "de_CR": cfg.de_CR,
                })
    sens_specs = list(cfg.de_sensitivity) if 6 in cfg.n_thrusters and "de" in cfg.algorithms else []
    six_seeds = {t["seed_index"]: t["seed"] for t in tasks if t["n"] == 6 and t["alg"] == "de"}
    for spec in sens_specs:
        strat, F, CR = _parse_de(spec)
        for si, seed in six_seeds.items():
            base = next(t for t in tasks if t["n"] == 6 and t["alg"] == "de" and t["seed_index"] == si)
            tasks.append({**base, "de_strategy": strat, "de_F": F, "de_CR": CR, "sens": spec, "seed": seed})
    miss_seed = root.spawn(1)[0]  # spawned second, as before the paired reading existed
    # paired reading of Table 8 (S3 §4-1): DE designs with one gene per couple, own seeds
    paired_on = "paired couple" in cfg.e_min_readings and "de" in cfg.algorithms
    fuel_seeds = root.spawn(cfg.n_seeds)  # random demand directions, one set per seed
    if paired_on:
        pchildren = iter(root.spawn(len(cfg.n_thrusters) * cfg.n_seeds))
        for s in range(cfg.n_seeds):
            for n in cfg.n_thrusters:
                base = next(t for t in tasks if t["n"] == n and t["alg"] == "de" and t["seed_index"] == s)
                tasks.append({**base, "paired": True, "seed": next(pchildren)})
    all_rows = ex.map(_design_task, tasks, description="thruster layouts")
    rows = [r for r, t in zip(all_rows, tasks) if "sens" not in t and not t.get("paired")]
    sens_rows = [(t["sens"], r) for r, t in zip(all_rows, tasks) if "sens" in t]
    paired_rows = [r for r, t in zip(all_rows, tasks) if t.get("paired")]

    # ---- aggregate per (n, alg)
    agg: dict[str, dict[str, Any]] = {}
    best_per_n: dict[int, dict[str, Any]] = {}
    for n in cfg.n_thrusters:
        agg[str(n)] = {}
        for alg in cfg.algorithms:
            rs = sorted((r for r in rows if r["n"] == n and r["alg"] == alg), key=lambda r: r["seed_index"])
            b = min(rs, key=lambda r: r["f_best"])
            f = [r["f_best"] for r in rs]
            rt = [r["runtime_s"] for r in rs]
            cpu = [r["cpu_s"] for r in rs]
            agg[str(n)][alg] = {
                "f_best": b["f_best"], "torque_error": b["torque_error"], "e_min": b["e_min"],
                "sum_tp_s": b["sum_tp_s"], "runtime_s": float(np.median(rt)),
                "cpu_s": float(np.median(cpu)), "cpu_s_seeds": cpu,
                "evaluations": int(b["evaluations"]),
                "f_best_median": float(np.median(f)), "f_best_seeds": f, "runtime_s_seeds": rt,
                "torque_error_seeds": [r["torque_error"] for r in rs],
                "e_min_seeds": [r["e_min"] for r in rs], "sum_tp_s_seeds": [r["sum_tp_s"] for r in rs],
                "best_layout": {
                    "torque_matrix": b["torque_matrix"], "positions": b["positions"],
                    "directions": b["directions"], "faces": b["faces"],
                    "controllable": check_controllability(b["torque_matrix"]).success,
                    # the same layout with the exact least-fuel allocation instead of S3's
                    **{f"lp_{k}": v for k, v in _alloc_stats(np.asarray(b["torque_matrix"]), demands,
                                                             "lp-min-fuel", cfg).items()
                       if k in ("sum_tp_s", "error_nm", "all_met")},
                },
            }
            if n not in best_per_n or b["f_best"] < best_per_n[n]["f_best"]:
                best_per_n[n] = b

    # ---- reference vs optimal (6 thrusters)
    rvo: dict[str, Any] = {}
    checks: list[Check] = []
    if 6 in cfg.n_thrusters:
        opt6 = best_per_n[6]
        by_alloc = {}
        for method in ("pinv-redistribute", "lp-min-fuel"):
            ref = _alloc_stats(A_REF, demands, method, cfg)
            opt = _alloc_stats(np.asarray(opt6["torque_matrix"]), demands, method, cfg)
            per_seed = {
                alg: [
                    _alloc_stats(np.asarray(r["torque_matrix"]), demands, method, cfg)["sum_tp_s"]
                    for r in sorted((r for r in rows if r["n"] == 6 and r["alg"] == alg),
                                    key=lambda r: r["seed_index"])
                ]
                for alg in cfg.algorithms
            }
            by_alloc[method] = {
                "sum_tp_ref_s": ref["sum_tp_s"], "sum_tp_opt_s": opt["sum_tp_s"],
                "error_ref_nm": ref["error_nm"], "error_opt_nm": opt["error_nm"],
                "all_met_ref": ref["all_met"], "all_met_opt": opt["all_met"],
                "fuel_ref_kg": ref["fuel_kg"], "fuel_opt_kg": opt["fuel_kg"],
                "on_times_ref_s": ref["on_times_s"], "on_times_opt_s": opt["on_times_s"],
                "sum_tp_opt_s_per_seed": per_seed,
            }
        rvo = {
            "sum_tp_ref_s": by_alloc["pinv-redistribute"]["sum_tp_ref_s"],
            "sum_tp_opt_s": by_alloc["pinv-redistribute"]["sum_tp_opt_s"],
            "allocation": "pinv-redistribute",
            "optimal_layout": f"best 6-thruster layout ({opt6['alg'].upper()}, seed {opt6['seed_index']})",
            "sum_tp_definition": "mean over the 14 demands of the summed on-times (s)",
            "by_allocation": by_alloc,
        }

    # ---- paper's printed layouts evaluated on our manoeuvre
    paper_layouts: dict[str, Any] = {}
    for name, A in PAPER["layouts"].items():
        A = np.asarray(A, float)
        sc = score_layout(A, demands, weights=cfg.weights, f_max=cfg.f_max_n, t_min=cfg.t_min_s,
                          t_s=cfg.t_s_s, gain=cfg.gain_nm_per_rad)
        col = np.linalg.norm(A, axis=0)
        paper_layouts[name] = {
            "max_column_norm_m": float(col.max()),
            "realisable_in_box": bool(col.max() <= np.linalg.norm(half) + 1e-9),
            "controllable": check_controllability(A).success,
            "f_best_our_manoeuvre": sc.fun, "error_nm": sc.error, "e_min_rad": sc.e_min,
            "sum_tp_s": sc.sum_tp,
        }

    miss = _pinv_miss(cfg, np.random.default_rng(miss_seed))

    # ---- checks (ours)
    max_cant = math.radians(cfg.max_cant_deg)
    faces_ok = all(_face_ok(r, half, max_cant) for r in [*rows, *paired_rows])
    checks.append(Check(
        name="every designed layout respects the mounting faces and thrust-leaves-face limits",
        passed=faces_ok, kind="check",
        detail=f"{len(rows) + len(paired_rows)} layouts: positions on allowed faces {cfg.faces}, d . n_out <= 0, "
               f"cant <= {cfg.max_cant_deg} deg",
    ))
    if paired_rows:
        worst_force = max(float(np.abs(np.asarray(r["directions"]).sum(axis=0)).max()) for r in paired_rows)
        twin_ok = all(
            np.allclose(np.asarray(r["positions"])[: r["n"] // 2], -np.asarray(r["positions"])[r["n"] // 2:])
            for r in paired_rows
        )
        checks.append(Check(
            name="paired reading: every gene is a couple (twin at -r on the parallel face, no net force)",
            passed=twin_ok and worst_force < 1e-12, kind="check",
            detail=f"{len(paired_rows)} paired layouts; largest |sum of force directions| {worst_force:.1e}",
        ))
    exact = max(miss["nnls"]["max_rel_error"], miss["lp-min-fuel"]["max_rel_error"])
    checks.append(Check(
        name="nnls and lp-min-fuel reproduce feasible demands to 1e-9 relative",
        passed=exact <= 1e-9, kind="check",
        detail=f"max relative torque error {exact:.2e} on {miss['n_layouts']} random 8-thruster layouts",
    ))
    ctrl = {n: check_controllability(np.asarray(best_per_n[n]["torque_matrix"])).success for n in best_per_n}
    checks.append(Check(
        name="best layout of every n is controllable (positive span)",
        passed=all(ctrl.values()), kind="check", detail=", ".join(f"n={n}: {v}" for n, v in ctrl.items()),
    ))
    if rvo:
        ref_ok = rvo["by_allocation"]["lp-min-fuel"]["all_met_ref"]
        checks.append(Check(
            name="the reference layout meets every demand of the manoeuvre",
            passed=ref_ok, kind="check",
            detail=f"{cfg.correction_deg} deg corrections, |M| = {np.linalg.norm(demands[0]):.3f} N m; "
                   "fuel comparison is then on equal (exact) torque",
        ))

    # ---- fuel: optimal vs reference per seed, out of sample, both allocations
    fuel_runs: dict[str, list[dict[str, Any]]] = {}
    fuel_rows: list[dict[str, Any]] = []
    if 6 in cfg.n_thrusters:
        mag = float(np.linalg.norm(demands[0]))
        names = {
            "default": "out of sample, pinv-redistribute, best design",
            "lp": "out of sample, lp-min-fuel, best design",
            "design": "design demands, pinv-redistribute, best design",
            "de": "out of sample, pinv-redistribute, DE design",
        }
        if "de" not in cfg.algorithms or len(cfg.algorithms) == 1:
            names.pop("de")
        fuel_runs = {v: [] for v in names.values()}
        for s in range(cfg.n_seeds):
            g = np.random.default_rng(fuel_seeds[s])
            dirs = g.standard_normal((cfg.n_fuel_demands, 3))
            rand = mag * dirs / np.linalg.norm(dirs, axis=1, keepdims=True)
            six = {a: next(r for r in rows if r["n"] == 6 and r["alg"] == a and r["seed_index"] == s)
                   for a in cfg.algorithms}
            best = min(six.values(), key=lambda r: r["f_best"])
            cases = {"default": (best, rand, "pinv-redistribute"), "lp": (best, rand, "lp-min-fuel"),
                     "design": (best, demands, "pinv-redistribute")}
            if "de" in names:
                cases["de"] = (six["de"], rand, "pinv-redistribute")
            for key, (lay, D, method) in cases.items():
                ref = _alloc_stats(A_REF, D, method, cfg)
                opt = _alloc_stats(np.asarray(lay["torque_matrix"]), D, method, cfg)
                m = {"ratio": opt["sum_tp_s"] / ref["sum_tp_s"], "opt_error_nm": opt["error_nm"],
                     "ref_error_nm": ref["error_nm"], "layout": f"{lay['alg'].upper()} seed {s}"}
                fuel_runs[names[key]].append(m)
                fuel_rows.append({"reading": names[key], "seed_index": s, "layout": m["layout"],
                                  "sum_tp_ref_s": ref["sum_tp_s"], "sum_tp_opt_s": opt["sum_tp_s"], **m})

    # ---- Table 8 e_min per reading (DE layouts)
    emin_runs: dict[str, list[dict[str, Any]]] = {}
    table8 = PAPER["table8_e_min_rad"]
    emin_ns = [n for n in cfg.n_thrusters if str(n) in table8]
    if "de" in cfg.algorithms and emin_ns:
        src = {"single thruster": [r for r in rows if r["alg"] == "de"], "paired couple": paired_rows}
        for reading in cfg.e_min_readings:
            rr = src[reading]
            emin_runs[reading] = [
                {"rel_dev": max(abs(next(r["e_min"] for r in rr if r["n"] == n and r["seed_index"] == s)
                                    - table8[str(n)]) / table8[str(n)] for n in emin_ns),
                 "e_min": {str(n): next(r["e_min"] for r in rr if r["n"] == n and r["seed_index"] == s)
                           for n in emin_ns}}
                for s in range(cfg.n_seeds)
            ]

    # ---- the paper's claims, decided per seed (and per reading)
    ns = [str(n) for n in cfg.n_thrusters]
    claims = []
    by_seed = {a: {n: {r["seed_index"]: r for r in rows if r["n"] == int(n) and r["alg"] == a} for n in ns}
               for a in cfg.algorithms}
    seeds = range(cfg.n_seeds)
    if {"ga", "de"} <= set(cfg.algorithms):
        acc_runs = [{"ratio": max(by_seed["de"][n][s]["f_best"] / by_seed["ga"][n][s]["f_best"] for n in ns)}
                    for s in seeds]
        claims.append(ClaimSpec(
            id="de-more-accurate",
            statement="the differential evolution algorithm has better accuracy than the genetic algorithm "
                      "in solving this problem (lower fitness F_best)",
            where="abstract; §6, Fig. 4",
            quantity="per seed, the largest DE/GA ratio of F_best over n in "
                     f"{list(cfg.n_thrusters)}; holds below 1 (DE lower at every n)",
            value=lambda m: m["ratio"], threshold=1.0, better="below", unit="-",
            protocol_keys=("n_thrusters", "algorithms", "n_gen", "pop_size", "weights", "de_strategy", "de_F",
                           "de_CR", "correction_deg", "faces", "max_cant_deg", "f_max_n", "t_min_s", "t_s_s",
                           "gain_nm_per_rad", "box_half_size_m"),
            describe=lambda r: "DE/GA F_best ratio (worst n) per seed: " + ", ".join(f"{v:.2f}" for v in r.values),
        ).evaluate({"default": acc_runs}))
        time_runs = [{"ratio": max(by_seed["de"][n][s]["cpu_s"] / by_seed["ga"][n][s]["cpu_s"] for n in ns)}
                     for s in seeds]
        claims.append(ClaimSpec(
            id="de-faster",
            statement="the differential evolution algorithm has a shorter run time than the genetic algorithm",
            where="abstract; §6, Fig. 3",
            quantity="per seed, the largest DE/GA ratio of CPU time per optimisation over n (equal "
                     f"evaluations: {cfg.n_gen} generations x {cfg.pop_size}); holds below 1",
            value=lambda m: m["ratio"], threshold=1.0, better="below", unit="-",
            protocol_keys=("n_thrusters", "algorithms", "n_gen", "pop_size"),
            describe=lambda r: "DE/GA CPU-time ratio (worst n) per seed: " + ", ".join(f"{v:.2f}" for v in r.values)
            + " (same number of evaluations: the difference is pymoo's per-generation overhead)",
        ).evaluate({"default": time_runs}))
    if 6 in cfg.n_thrusters and len(ns) > 1:
        others = [n for n in ns if n != "6"]
        six_runs = [{"ratio": max(by_seed[a]["6"][s]["f_best"] / min(by_seed[a][n][s]["f_best"] for n in others)
                                  for a in cfg.algorithms)} for s in seeds]
        claims.append(ClaimSpec(
            id="six-thrusters-best",
            statement="for both algorithms the lowest value of the fitness function is obtained with 6 thrusters",
            where="§6, Fig. 4",
            quantity="per seed and algorithm, F_best(6) / min over the other n of F_best; the largest over "
                     "the algorithms; holds below 1",
            value=lambda m: m["ratio"], threshold=1.0, better="below", unit="-",
            protocol_keys=("n_thrusters", "algorithms", "n_gen", "pop_size", "weights", "correction_deg"),
            describe=lambda r: "F_best(6)/best other n per seed: " + ", ".join(f"{v:.2f}" for v in r.values),
        ).evaluate({"default": six_runs}))
    fuel_default = "out of sample, pinv-redistribute, best design"
    if fuel_runs:
        claims.append(ClaimSpec(
            id="optimal-layout-less-fuel",
            statement="the fuel consumption of the optimal layout is lower than that of the empirically chosen "
                      "(reference) layout",
            where="§6, Fig. 5",
            quantity="per seed, summed on-time of the optimal 6-thruster layout / that of the reference "
                     f"(mean over {cfg.n_fuel_demands} random demand directions of |M| = "
                     f"{np.linalg.norm(demands[0]):.3f} N m); holds below 1 if the optimal layout also meets the "
                     "torque as well as the reference",
            value=lambda m: m["ratio"], threshold=1.0, better="below",
            held=lambda m: m["opt_error_nm"] <= m["ref_error_nm"] + 1e-6, unit="-",
            readings=tuple(k for k in fuel_runs if k != fuel_default),
            protocol_keys=("n_thrusters", "algorithms", "n_gen", "pop_size", "weights", "correction_deg",
                           "n_fuel_demands", "faces", "max_cant_deg"),
            describe=lambda r: "optimal/reference on-time per seed: " + ", ".join(f"{v:.3f}" for v in r.values),
        ).evaluate(fuel_runs, default=fuel_default))
    if emin_runs:
        table8 = PAPER["table8_e_min_rad"]
        claims.append(ClaimSpec(
            id="table8-e-min",
            statement="Table 8: minimum reachable error e_min of the four DE layouts 0.00084, 0.00083, 0.00082 "
                      "and 0.00083 rad (4, 6, 8, 12 thrusters), an acceptable level",
            where="§6, Table 8",
            quantity=f"per seed, the largest relative distance of the DE layouts' e_min from Table 8 over n; holds "
                     f"below {cfg.e_min_tolerance:g}",
            value=lambda m: m["rel_dev"], threshold=cfg.e_min_tolerance, better="below", unit="-",
            paper=table8, readings=tuple(cfg.e_min_readings[1:]),
            protocol_keys=("n_thrusters", "algorithms", "n_gen", "pop_size", "weights", "f_max_n", "t_min_s",
                           "t_s_s", "gain_nm_per_rad", "box_half_size_m", "e_min_tolerance"),
            describe=lambda r: "largest relative deviation per seed: " + ", ".join(f"{v:.2f}" for v in r.values),
        ).evaluate(emin_runs, default=cfg.e_min_readings[0]))

    # ---- comparison rows
    comparison = []
    for n, d in PAPER["f_best"].items():
        for alg, v in d.items():
            if n in agg and alg in agg[n]:
                comparison.append(Comparison(
                    quantity=f"F_best, {n} thrusters, {alg.upper()}", paper=v,
                    measured=agg[n][alg]["f_best"], unit="-",
                    note="best of seeds; manoeuvre differs (S3's is not printed)",
                ))
    for reading, runs_r in emin_runs.items():
        for n in emin_ns:
            vals = [m["e_min"][str(n)] for m in runs_r]
            comparison.append(Comparison(
                quantity=f"e_min, {n} thrusters (Table 8), {reading}", paper=table8[str(n)],
                measured=float(np.median(vals)), unit="rad",
                note=f"median over {len(vals)} DE seeds (range {min(vals):.2e}..{max(vals):.2e}); lever arm in the "
                     "impulse bit" + (", a couple's bit is twice a thruster's" if reading == "paired couple" else ""),
            ))
    if rvo:
        for method in ("pinv-redistribute", "lp-min-fuel"):
            d = rvo["by_allocation"][method]
            comparison.append(Comparison(
                quantity=f"sum t_p reference -> optimal ({method})", paper="optimal < reference (Fig 5)",
                measured=f"{d['sum_tp_ref_s']:.4f} -> {d['sum_tp_opt_s']:.4f}", unit="s",
                note="mean over the 14 demands",
            ))
    comparison.append(Comparison(
        quantity="pinv-redistribute median torque miss, random 8-thruster layouts",
        paper="n/a (Basilisk's mapping: 66 %)", measured=miss["pinv-redistribute"]["median_rel_error"],
        unit="relative", note=f"{miss['n_layouts']} layouts, feasible demands",
    ))

    sens: dict[str, Any] = {}
    findings = []
    for spec in sens_specs:
        f = [r["f_best"] for sp, r in sorted(((sp, r) for sp, r in sens_rows if sp == spec),
                                              key=lambda x: x[1]["seed_index"])]
        sens[spec] = {"f_best_seeds": f, "f_best_median": float(np.median(f))}
    if sens and "ga" in cfg.algorithms:
        sens[f"{cfg.de_strategy}:{cfg.de_F}:{cfg.de_CR} (default)"] = {
            "f_best_seeds": agg["6"]["de"]["f_best_seeds"], "f_best_median": agg["6"]["de"]["f_best_median"],
        }
        ga6 = agg["6"]["ga"]["f_best_seeds"]
        de_keys = [k for k in sens if not k.startswith("ga")]
        sens_runs = [{"ratio": min(sens[k]["f_best_seeds"][s] for k in de_keys) / ga6[s]} for s in seeds]
        sens["ga (pymoo defaults)"] = {"f_best_seeds": ga6, "f_best_median": agg["6"]["ga"]["f_best_median"]}
        findings.append(FindingSpec(
            id="de-settings-n6",
            statement=f"at n = 6, the best of {len(de_keys)} DE settings ({', '.join(de_keys)}) reaches a lower "
                      "F_best than the GA (is the GA-vs-DE ranking an artefact of one DE setting?)",
            quantity="per seed, min over DE settings of F_best / GA F_best; holds below 1",
            value=lambda m: m["ratio"], threshold=1.0, better="below", unit="-",
            describe=lambda r: "best DE / GA per seed: " + ", ".join(f"{v:.2f}" for v in r.values),
        ).evaluate({"default": sens_runs}))
    printed_bad = [k for k in ("6-de", "8-de") if not paper_layouts[k]["realisable_in_box"]]
    findings.append(FindingSpec(
        id="printed-layouts-realisable",
        statement="S3's printed 6- and 8-thruster DE layout matrices can be produced by thrusters in the "
                  "2 x 2 x 2 m box (column norm |r x d| <= |r| <= sqrt(3) m)",
        quantity="largest column norm of each printed matrix vs the box's largest lever arm",
        held=lambda m: m["ok"], stochastic=False,
        describe=lambda r: "column norms: " + ", ".join(
            f"{k} {paper_layouts[k]['max_column_norm_m']:.2f} m" for k in ("6-de", "8-de"))
        + f" vs {np.linalg.norm(half):.2f} m",
    ).evaluate({"default": [{"ok": not printed_bad}]}))
    findings.append(FindingSpec(
        id="pinv-redistribute-exact",
        statement="S3's redistributed pseudo-inverse meets every feasible demand exactly (as the exact "
                  "allocators do), on random 8-thruster layouts",
        quantity=f"fraction of {miss['n_layouts']} random layouts (feasible demand M = A F_true) met to 1e-9 "
                 "relative; holds if all are",
        held=lambda m: m["frac"] >= 1.0, stochastic=False,
        describe=lambda r: f"pinv-redistribute: {100 * miss['pinv-redistribute']['fraction_exact_1e-9']:.0f} % exact, "
        f"median miss {miss['pinv-redistribute']['median_rel_error']:.1e}, worst "
        f"{100 * miss['pinv-redistribute']['max_rel_error']:.0f} %; nnls / lp-min-fuel worst "
        f"{max(miss['nnls']['max_rel_error'], miss['lp-min-fuel']['max_rel_error']):.1e}",
    ).evaluate({"default": [{"frac": miss["pinv-redistribute"]["fraction_exact_1e-9"]}]}))
    if sens:
        # our check: the ranking statement the DE-settings finding rests on is computed, not asserted
        ga_med = sens["ga (pymoo defaults)"]["f_best_median"]
        ranks = {k: v["f_best_median"] < ga_med for k, v in sens.items() if not k.startswith("ga")}
        checks.append(Check(
            name="every DE setting at n = 6 ran on the same seeds as the default DE and the GA",
            passed=all(len(v["f_best_seeds"]) == cfg.n_seeds for v in sens.values()), kind="check",
            detail="median F_best over the same seeds: "
                   + ", ".join(f"{k}: {v['f_best_median']:.3f}" for k, v in sens.items())
                   + f"; DE settings with a lower median than the GA: {sum(ranks.values())}/{len(ranks)}",
        ))

    measured = {
        "de_sensitivity_n6": sens,
        "runs": {n: {a: {k: v for k, v in agg[n][a].items()} for a in agg[n]} for n in agg},
        "paired_runs": [{k: r[k] for k in ("n", "seed_index", "f_best", "torque_error", "e_min", "sum_tp_s")}
                        for r in paired_rows],
        "fuel_out_of_sample": fuel_rows,
        "e_min_by_reading": emin_runs,
        "reference_vs_optimal": rvo,
        "pinv_miss_random_layouts": miss,
        "paper_layouts_on_our_manoeuvre": paper_layouts,
        "manoeuvre_demands_nm": demands,
        "natural_frequency_rad_s": [math.sqrt(cfg.gain_nm_per_rad / j) for j in cfg.inertia_kgm2],
        "total_optimisation_time_s": float(sum(r["runtime_s"] for r in all_rows)),
        "total_optimisation_cpu_s": float(sum(r["cpu_s"] for r in all_rows)),
    }

    run_rows = [
        {k: r[k] for k in ("n", "alg", "seed_index", "f_best", "torque_error", "e_min", "sum_tp_s",
                           "runtime_s", "cpu_s", "evaluations")}
        for r in rows
    ]
    tables = {
        "runs": run_rows,
        "paper_layouts": [{"layout": k, **v} for k, v in paper_layouts.items()],
    }
    if fuel_rows:
        tables["fuel_per_seed"] = fuel_rows
    if rvo:
        tables["reference_vs_optimal"] = [
            {"allocation": m, **{k: v for k, v in d.items() if not k.startswith("on_times") and k != "sum_tp_opt_s_per_seed"}}
            for m, d in rvo["by_allocation"].items()
        ]
    figures = {
        "runtime_vs_n": _fig_runtime(cfg, agg),
        "fitness_vs_n": _fig_fitness(cfg, agg),
        "convergence": _fig_convergence(cfg, rows),
        "layouts_3d": _fig_layouts(cfg, best_per_n),
    }
    if rvo:
        figures["on_times_ref_vs_opt"] = _fig_on_times(rvo)

    lever_max = float(np.linalg.norm(half))
    bit = cfg.f_max_n * cfg.t_min_s / (cfg.t_s_s * cfg.gain_nm_per_rad)
    k2_term = [cfg.weights[1] * r["e_min"] for r in rows]
    k3_term = [cfg.weights[2] * r["sum_tp_s"] for r in rows]
    differences = [
        "S3 does not print its manoeuvre; ours is the first-sample PD torque K*theta about the 6 body "
        f"half-axes and 8 cube diagonals with theta = {cfg.correction_deg} deg (|M| = "
        f"{np.linalg.norm(demands[0]):.2f} N m), used for the design; the fuel claim is decided on "
        f"{cfg.n_fuel_demands} random demand directions of the same magnitude per seed (out of sample).",
        "Thrusters are mounted on the box surface (face + in-face position), not anywhere in the cube of "
        "eq. 20; directions are parametrised per face so 'thrust leaves the face' (S3 Tables 1-4) is a box bound.",
        "e_min includes the lever arm in the impulse bit (Delta F_max t_min / (t_s K)); the layout's e_min is the "
        f"largest per-thruster value, at most {lever_max * bit:.3g} rad in the box for a single thruster and "
        f"{2 * lever_max * bit:.3g} rad for a couple (paired reading of S3 §4-1).",
        f"K2 = {cfg.weights[1]:g} is used as printed: a negative K2 rewards a *larger* e_min (coarser impulse bit); "
        f"its term is {min(k2_term):.3g}..{max(k2_term):.3g} in our runs, next to K3 sum_tp "
        f"{min(k3_term):.3g}..{max(k3_term):.3g}.",
        f"Population {cfg.pop_size} (S3: equal for GA and DE, size not printed); GA = pymoo defaults "
        f"(SBX, polynomial mutation, tournament); DE = {cfg.de_strategy} "
        f"(F = {cfg.de_F}, CR = {cfg.de_CR}).",
        f"Each (n, algorithm) is run with {cfg.n_seeds} independent seeds; claims are decided per seed "
        "(verdict model: unanimous seeds and an interval on one side of the threshold). GA and DE do the same "
        "number of evaluations, so run-time differences are pymoo's per-generation overhead only.",
        "S3's redistribution of negative forces to the 'opposite' thrusters is generalised to any layout as "
        "the redistributed pseudo-inverse (S3 ref. [14]); the exact least-fuel LP is the stronger baseline.",
        "S3 calls its layouts 'symmetric' and says thrusters on parallel faces act as a pair; the default "
        "reading imposes no symmetry, the 'paired couple' reading (Table 8 only) designs couples.",
    ]
    for name in ("6-de", "8-de"):
        pl = paper_layouts[name]
        if not pl["realisable_in_box"]:
            differences.append(
                f"S3's printed {name} layout matrix has a column of norm {pl['max_column_norm_m']:.2f} m > "
                f"{lever_max:.2f} m: no thruster in the box with the CoM at its centre can "
                "produce it (|r x d| <= |r|)."
            )
    verdicts = "; ".join(f"{c.id}: {c.outcome}" for c in claims)
    summary = (
        f"{len(cfg.n_thrusters)} layout sizes x {len(cfg.algorithms)} algorithms x {cfg.n_seeds} seeds, "
        f"{cfg.n_gen} generations of {cfg.pop_size}; design manoeuvre of 14 corrections of {cfg.correction_deg} deg. "
        f"Verdicts: {verdicts}. "
        + ("Optimal/reference summed on-time, out of sample, pinv-redistribute, per seed: "
           + ", ".join(f"{m['ratio']:.3f}" for m in fuel_runs[fuel_default]) + ". " if fuel_runs else "")
        + "On random 8-thruster layouts pinv-redistribute meets "
        f"{100 * miss['pinv-redistribute']['fraction_exact_1e-9']:.0f} % of feasible demands exactly "
        f"(worst miss {100 * miss['pinv-redistribute']['max_rel_error']:.0f} %)."
    )
    return StudyResult(
        study="thruster-layout",
        title=STUDY_TITLE,
        summary=summary,
        paper=PAPER,
        measured=measured,
        checks=checks,
        claims=claims,
        findings=findings,
        comparison=comparison,
        differences=differences,
        figures=figures,
        tables=tables,
        doc="docs/studies/thruster-layout.md",
    )


STUDY_TITLE = "GEO thruster layout design with GA vs DE, allocation and fuel vs a reference layout (S3)"

STUDY = Study(
    name="thruster-layout",
    title=STUDY_TITLE,
    paper="S3: Kosari, Kaviri, Moshiri, Fakoor - optimal thruster configuration for a GEO satellite",
    config_cls=Config,
    run=run,
    quick={"n_gen": 60, "pop_size": 24, "n_random_layouts": 40},
    doc="docs/studies/thruster-layout.md",
)
