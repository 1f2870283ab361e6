"""Study ``rendezvous`` (S2): time-optimal 6-DOF rendezvous by Gauss pseudospectral collocation.

For every initial position of S2 Table 4: solve on the paper's mesh (20 equal sub-intervals
× 3 LG points) from the straight-line guess and from seeded random guesses (multistart),
keep every distinct local optimum, refine the best one on a warm-started mesh sequence until
``tf`` changes by less than ``rtol``, and report costates, Hamiltonian, bang-bang structure
and the open-loop re-simulation miss. Verdicts say, per row, whether the paper's GPM and GPOPS
``tf`` are the best optimum we found or a local one.

References
----------
S2, eq. 2–16 (model), 17–37 (method), Tables 2–4, Figs 3–15.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Literal

import numpy as np

from adcskit._progress import status, track
from adcskit.optimal_control import bang_bang, multistart, resimulate, solve, solve_mesh_sequence
from adcskit.optimal_control.problems.rendezvous import rendezvous_problem
from adcskit.studies._base import Check, Comparison, Study, StudyResult, new_figure

__all__ = ["Config", "run", "STUDY", "PAPER_ROWS"]

# S2 Table 4: initial position (m), tf by the paper's GPM (s), tf by GPOPS (s), difference (%)
PAPER_ROWS = (
    ((20.0, 0.0, 0.0), 25.8727, 25.87, 0.0104),
    ((20.0, 4.0, 0.0), 26.1674, 26.0336, 0.5113),
    ((20.0, 4.0, 4.0), 25.9360, 26.1652, 0.8837),
    ((20.0, 4.0, -5.0), 25.6607, 25.8986, 0.9271),
    ((25.0, -5.0, -5.0), 28.7185, 28.2784, 1.5325),
)
# GPOPS prints 4 decimals except the main row (2 decimals, "25.87")
_GPOPS_DECIMALS = (2, 4, 4, 4, 4)


@dataclass(frozen=True, kw_only=True)
class Config:
    """Settings of the rendezvous study (defaults: S2 §6 and Table 4).

    Attributes
    ----------
    rows : tuple of (3,) tuples
        Initial relative positions in LVLH (m), S2 Table 4.
    dynamics : {"paper", "full"}
        Rotational model for the table (eq. 2 as printed, or the exact relative dynamics).
    method : {"gauss", "radau"}
    paper_mesh : (int, int)
        Sub-intervals × LG points of the paper, ``(20, 3)``.
    refine_meshes : tuple of (int, int)
        Warm-started refinement after the paper mesh.
    rtol : float
        Mesh refinement stops when ``tf`` changes by less than this (relative).
    n_starts : int
        Starts per row on the paper mesh (start 0 is the straight-line guess, the rest random).
    distinct_rtol : float
        Two optima closer than this (relative) are the same.
    verdict_rtol : float
        A paper value equals one of ours within this relative distance (plus half a unit
        of its last printed digit).
    compare_full_dynamics : bool
        Also solve the main row with the full relative dynamics.
    """

    rows: tuple[tuple[float, float, float], ...] = tuple(r[0] for r in PAPER_ROWS)
    dynamics: Literal["paper", "full"] = "paper"
    method: Literal["gauss", "radau"] = "gauss"
    paper_mesh: tuple[int, int] = (20, 3)
    refine_meshes: tuple[tuple[int, int], ...] = ((40, 4), (80, 4), (160, 4), (320, 4))
    rtol: float = 1e-5
    n_starts: int = 9
    distinct_rtol: float = 1e-4
    verdict_rtol: float = 1e-4
    compare_full_dynamics: bool = True

    def __post_init__(self) -> None:
        if not self.rows:
            raise ValueError("rows must list at least one initial position (m)")
        for r in self.rows:
            if len(r) != 3 or not all(math.isfinite(float(v)) for v in r):
                raise ValueError(f"each row must be 3 finite numbers (m); got {r!r}")
        if self.n_starts < 1:
            raise ValueError(f"n_starts must be >= 1; got {self.n_starts}")
        for m in (self.paper_mesh, *self.refine_meshes):
            if len(m) != 2 or min(m) < 1:
                raise ValueError(f"meshes must be (n_intervals >= 1, n_nodes >= 1); got {m!r}")
        for name in ("rtol", "distinct_rtol", "verdict_rtol"):
            if not 0 < getattr(self, name) < 1:
                raise ValueError(f"{name} must be in (0, 1); got {getattr(self, name)}")


def _paper_row(s0):
    for r in PAPER_ROWS:
        if np.allclose(r[0], s0):
            return r
    return None


def _solve_row(s0, cfg: Config, seed: int) -> dict:
    prob = rendezvous_problem(s0, dynamics=cfg.dynamics)
    t_start = time.perf_counter()
    ms = multistart(
        prob, cfg.n_starts, method=cfg.method, mesh=cfg.paper_mesh, rng=seed, rtol=cfg.distinct_rtol
    )
    default = ms.solutions[0]
    best = ms.best
    seq = None
    local = []  # (paper-mesh tf, converged tf, converged?) of every distinct optimum
    for value in ms.distinct_objectives:
        rep = next(
            s for s in ms.solutions if s.success and abs(s.objective - value) <= cfg.distinct_rtol * value
        )
        if best is not None and abs(value - best.objective) <= cfg.distinct_rtol * value:
            rep = best
        q = solve_mesh_sequence(
            prob, [cfg.paper_mesh, *cfg.refine_meshes], method=cfg.method, guess=rep, rtol=cfg.rtol
        )
        local.append((float(value), q.final.tf if q.final.success else math.nan, bool(q.converged)))
        if rep is best:
            seq = q
    wall = time.perf_counter() - t_start
    return {
        "s0": s0, "multistart": ms, "default": default, "best": best, "sequence": seq, "local": local, "wall_s": wall,
    }


def _verdict(value: float, decimals: int, reference: float, others: np.ndarray, rtol: float) -> str:
    tol = rtol * reference + 0.5 * 10.0**-decimals
    if abs(value - reference) <= tol:
        return "global"
    pct = 100.0 * (value - reference) / reference
    if value < reference:
        return f"below our best optimum by {-pct:.3f} % (not reproduced)"
    if others.size and np.min(np.abs(others - value)) <= rtol * value + 0.5 * 10.0**-decimals:
        return f"local ({pct:.3f} % above our best)"
    return f"not optimal: {pct:.3f} % above our best, matches none of our local optima"


def run(config: Config, *, quick: bool = False, rng=None, executor=None) -> StudyResult:
    rng = np.random.default_rng(0) if rng is None else rng
    seeds = [int(s) for s in rng.integers(0, 2**31 - 1, size=len(config.rows))]
    rows_out, details, comparison, checks, tables_rows = [], [], [], [], []
    results = []
    for s0, seed in track(list(zip(config.rows, seeds, strict=True)), "rendezvous rows"):
        status(f"rendezvous row s0={s0}")
        results.append(_solve_row(tuple(float(v) for v in s0), config, seed))

    main = None
    for res in results:
        ms, best, seq, default = res["multistart"], res["best"], res["sequence"], res["default"]
        s0 = res["s0"]
        final = seq.final if seq is not None else None
        conv_ok = seq is not None and seq.final.success
        tf_conv = final.tf if conv_ok else math.nan
        bb_src = final if conv_ok else best
        bb = bang_bang(bb_src) if bb_src is not None else None
        ham = best.hamiltonian if best is not None else np.array([math.nan])
        row = {
            "s0_m": list(s0),
            "tf_paper_mesh_s": default.tf if default.success else None,
            "tf_converged_s": tf_conv,
            "tf_best_multistart_s": best.tf if best is not None else None,
            "distinct_local_optima_s": ms.distinct_objectives.tolist(),
            "solve_s": best.solve_s if best is not None else default.solve_s,
            "hamiltonian_mean": float(np.mean(ham)),
            "hamiltonian_std": float(np.std(ham)),
            "bang_bang": bool(bb.all_bang_bang) if bb is not None else False,
        }
        resim = resimulate(final) if conv_ok else None
        detail = {
            "s0_m": list(s0),
            "default_guess_status": default.status,
            "default_guess_tf_s": default.tf,
            "multistart": ms.to_dict(),
            "mesh_sequence": seq.to_dict() if seq is not None else None,
            "hamiltonian_converged_mean": float(np.mean(final.hamiltonian)) if conv_ok else None,
            "hamiltonian_converged_std": float(np.std(final.hamiltonian)) if conv_ok else None,
            "bang_bang": bb.to_dict() if bb is not None else None,
            "resimulation_miss_scaled": resim.terminal_miss_scaled if resim else None,
            "resimulation_miss": resim.terminal_miss if resim else None,
            "distinct_local_optima_converged_s": [c for _, c, _ in res["local"]],
            "distinct_local_optima_converged": [ok for _, _, ok in res["local"]],
            "row_wall_s": res["wall_s"],
        }
        paper = _paper_row(s0)
        if paper is not None and best is not None:
            i = PAPER_ROWS.index(paper)
            v_gpm = _verdict(paper[1], 4, best.tf, ms.distinct_objectives, config.verdict_rtol)
            ref = tf_conv if conv_ok else best.tf
            conv_optima = np.array([c for _, c, _ in res["local"] if math.isfinite(c)])
            v_gpops = _verdict(paper[2], _GPOPS_DECIMALS[i], ref, conv_optima, config.verdict_rtol)
            detail["verdict_gpm"] = v_gpm
            detail["verdict_gpops"] = v_gpops
            comparison.append(
                Comparison(
                    quantity=f"tf, s0={list(s0)}, {config.paper_mesh[0]}x{config.paper_mesh[1]} mesh",
                    paper=paper[1],
                    measured=best.tf,
                    unit="s",
                    note=f"paper GPM vs our best of {ms.n_success} successful starts: {v_gpm}",
                )
            )
            comparison.append(
                Comparison(
                    quantity=f"tf, s0={list(s0)}, converged",
                    paper=paper[2],
                    measured=tf_conv,
                    unit="s",
                    note=f"paper GPOPS vs our mesh-converged best: {v_gpops}",
                )
            )
            checks.append(
                Check(
                    name=f"s0={list(s0)}: the paper's GPM tf {paper[1]} s is the global optimum (paper mesh)",
                    passed=v_gpm == "global",  # verdict strings start with "global"/"local"/...
                    detail=f"our best on the paper mesh {best.tf:.5f} s; distinct optima "
                    f"{np.round(ms.distinct_objectives, 5).tolist()} s; verdict: {v_gpm}",
                )
            )
            checks.append(
                Check(
                    name=f"s0={list(s0)}: GPOPS tf {paper[2]} s is the global optimum (converged mesh)",
                    passed=v_gpops == "global",
                    detail=f"our mesh-converged best {tf_conv:.5f} s ({seq.message if seq else 'no solve'}); "
                    f"mesh-converged local optima {np.round(conv_optima, 5).tolist()} s; verdict: {v_gpops}",
                )
            )
        tables_rows.append(
            {
                "s0_m": str(list(s0)),
                "tf_gpm_paper_s": paper[1] if paper else None,
                "tf_gpops_paper_s": paper[2] if paper else None,
                "tf_default_guess_paper_mesh_s": row["tf_paper_mesh_s"],
                "default_guess_status": default.status,
                "tf_best_multistart_s": row["tf_best_multistart_s"],
                "n_distinct_optima": int(ms.distinct_objectives.size),
                "distinct_optima_paper_mesh_s": " ".join(f"{v:.5f}" for v in ms.distinct_objectives),
                "distinct_optima_converged_s": " ".join(f"{c:.5f}" for _, c, _ in res["local"]),
                "tf_converged_s": tf_conv,
                "converged_mesh": seq.final.mesh.label() if seq else None,
                "hamiltonian_mean": row["hamiltonian_mean"],
                "hamiltonian_std": row["hamiltonian_std"],
                "bang_bang": row["bang_bang"],
                "verdict_gpm": detail.get("verdict_gpm"),
                "verdict_gpops": detail.get("verdict_gpops"),
            }
        )
        rows_out.append(row)
        details.append(detail)
        if np.allclose(s0, PAPER_ROWS[0][0]):
            main = (res, final if conv_ok else best, bb, row)

    # ------------------------------------------------------------------ claims on the main row
    if main is None:
        main = (results[0], results[0]["best"], None, rows_out[0])
    mres, msol, mbb, mrow = main
    if msol is not None:
        bb_now = bang_bang(msol)
        checks.append(
            Check(
                name="Controls are bang-bang on all six channels (S2 Figs 3-4)",
                passed=bb_now.all_bang_bang,
                detail=f"fraction of collocation points on a bound per channel T1..F3: "
                f"{np.round(bb_now.at_bound_fraction, 3).tolist()} (>= 0.9 required, 2 % band); "
                f"switches {bb_now.n_switches.tolist()} on mesh {msol.mesh.label()}",
            )
        )
        best_pm = mres["best"]
        h = best_pm.hamiltonian
        checks.append(
            Check(
                name="The Hamiltonian is constant and equal to -1 (S2 eq. 39, Fig. 15)",
                passed=bool(abs(np.mean(h) + 1) < 1e-2 and np.std(h) < 5e-2),
                detail=f"paper mesh: mean {np.mean(h):.5f}, std {np.std(h):.2e}; converged mesh "
                f"{msol.mesh.label()}: mean {np.mean(msol.hamiltonian):.6f}, std {np.std(msol.hamiltonian):.2e} "
                "(pass: |mean+1| < 1e-2 and std < 5e-2)",
            )
        )
        checks.append(
            Check(
                name="Main scenario tf = 25.8727 s on the 20x3 mesh (S2 §6)",
                passed=abs(best_pm.tf - 25.8727) <= config.verdict_rtol * 25.8727 + 5e-5,
                detail=f"our best on the paper mesh {best_pm.tf:.5f} s; mesh-converged {msol.tf:.6f} s",
            )
        )
        d = mres["default"]
        checks.append(
            Check(
                name="The straight-line initial guess solves the main scenario",
                passed=d.success,
                detail=f"IPOPT: {d.status}, tf {d.tf:.4f} s after {d.nit} iterations. The straight-line "
                "guess is planar (no y motion, rotation about body axis 2 only) and stays in that "
                "symmetric subspace; random guesses break the symmetry.",
                kind="check",
            )
        )
    # ------------------------------------------------------------------ consistency checks
    n_ok = sum(1 for d in details if d["mesh_sequence"] and d["mesh_sequence"]["converged"])
    checks.append(
        Check(
            name=f"Mesh refinement converged (|Δtf|/tf < {config.rtol:g}) for every row",
            passed=n_ok == len(details),
            detail=f"{n_ok}/{len(details)} rows converged; meshes {list(config.refine_meshes)}",
            kind="check",
        )
    )
    misses = [d["resimulation_miss_scaled"] for d in details if d["resimulation_miss_scaled"] is not None]
    checks.append(
        Check(
            name="Open-loop re-simulation (solve_ivp DOP853) reaches the final state",
            passed=bool(misses) and max(misses) < 0.05,
            detail=f"max terminal miss over rows {max(misses) if misses else float('nan'):.3g} in units of "
            "the state scales (pass < 0.05; controls interpolated by the LG Lagrange polynomials)",
            kind="check",
        )
    )
    full_info = None
    if config.compare_full_dynamics and mres["best"] is not None:
        other = "full" if config.dynamics == "paper" else "paper"
        pf = rendezvous_problem(mres["s0"], dynamics=other)
        sf = solve(pf, method=config.method, mesh=config.paper_mesh, guess=mres["best"])
        full_info = {"dynamics": other, "tf_s": sf.tf, "status": sf.status, "tf_table_dynamics_s": mres["best"].tf}
        checks.append(
            Check(
                name=f"Dropped terms of eq. 2 change tf by < 0.1 % (main row, {other} vs {config.dynamics})",
                passed=sf.success and abs(sf.tf - mres["best"].tf) < 1e-3 * mres["best"].tf,
                detail=f"{other} dynamics: {sf.tf:.6f} s ({sf.status}); {config.dynamics}: {mres['best'].tf:.6f} s",
                kind="check",
            )
        )

    figures = _figures(msol) if msol is not None else {}
    figures["table4_tf"] = _table4_figure(rows_out)
    measured = {"rows": rows_out, "row_details": details, "full_dynamics_main_row": full_info}
    paper = {
        "source": "S2 Table 4 (tf in s); main scenario S2 §6, Tables 2-3",
        "rows": [
            {"s0_m": list(r[0]), "tf_gpm_s": r[1], "tf_gpops_s": r[2], "difference_percent": r[3]}
            for r in PAPER_ROWS
        ],
        "hamiltonian": -1.0,
        "bang_bang": True,
    }
    summary = (
        f"{len(rows_out)} rows of S2 Table 4 on the {config.paper_mesh[0]}x{config.paper_mesh[1]} Gauss mesh "
        f"with {config.n_starts} starts each, refined to |Δtf|/tf < {config.rtol:g}. "
        + " ".join(
            f"s0={r['s0_m']}: best {r['tf_best_multistart_s'] or float('nan'):.4f} s, converged "
            f"{r['tf_converged_s']:.5f} s;"
            for r in rows_out
        )
    )
    differences = [
        "NLP solved by IPOPT (interior point, exact Hessian, MUMPS) through CasADi instead of the "
        "paper's SQP; the transcription is the paper's (eq. 17-34).",
        "The paper reports one solve per row; we run a seeded multistart and mesh refinement, "
        "so 'tf' is split into the paper-mesh value and the mesh-converged value.",
        "Table 3 prints sigma_f = tan(90 deg/2); we use tan(90 deg/4) = 0.4142, the value printed "
        "next to it and the MRP definition of eq. 3.",
        "LVLH rotation omega_LI = [0, -n, 0] (Y = minus orbit normal), n from 580 km altitude with "
        "WGS-84 radius and mu = 3.986004418e14 m^3/s^2 (the paper does not print n).",
        "Full relative rigid-body dynamics also offered (adds omega x I omega_LI and I(omega x "
        "omega_LI), dropped by eq. 2); the table uses eq. 2 as printed.",
        "Euler angles (Fig. 7) are intrinsic Y-X-Z angles of the body frame relative to LVLH.",
    ]
    tables = {
        "table4": tables_rows,
        "mesh_history": [
            {"s0_m": str(d["s0_m"]), "mesh": m, "tf_s": tf, "rel_change": rc, "status": st}
            for d in details
            if d["mesh_sequence"]
            for m, tf, rc, st in zip(
                d["mesh_sequence"]["meshes"],
                d["mesh_sequence"]["tf"],
                d["mesh_sequence"]["rel_change"],
                d["mesh_sequence"]["status"],
                strict=True,
            )
        ],
        "multistart": [
            {"s0_m": str(d["s0_m"]), "start": i, "tf_s": tf, "status": st}
            for d in details
            for i, (tf, st) in enumerate(zip(d["multistart"]["objectives"], d["multistart"]["status"], strict=True))
        ],
    }
    return StudyResult(
        study="rendezvous",
        title="Time-optimal 6-DOF rendezvous by Gauss pseudospectral collocation (S2)",
        summary=summary,
        config={},
        paper=paper,
        measured=measured,
        checks=checks,
        comparison=comparison,
        differences=differences,
        figures=figures,
        tables=tables,
        doc="docs/studies/rendezvous.md",
    )


def _table4_figure(rows_out):
    """S2 Table 4 beside our paper-mesh and mesh-converged optima."""
    fig, ax = new_figure(figsize=(7.0, 4.0))
    x = np.arange(len(rows_out))
    for i, r in enumerate(rows_out):
        paper = _paper_row(r["s0_m"])
        if paper is not None:
            ax.plot(i - 0.15, paper[1], "s", color="C0", label="GPM (paper)" if i == 0 else None)
            ax.plot(i - 0.05, paper[2], "D", color="C1", label="GPOPS (paper)" if i == 0 else None)
        for v in r["distinct_local_optima_s"]:
            ax.plot(i + 0.05, v, "o", mfc="none", color="C2", label="our 20x3 optima" if i == 0 else None)
        ax.plot(i + 0.15, r["tf_converged_s"], "*", ms=10, color="C3", label="ours, converged" if i == 0 else None)
    ax.set_xticks(x, [str([int(v) for v in r["s0_m"]]) for r in rows_out], fontsize=8)
    ax.set_xlabel("initial position s0 (m)")
    ax.set_ylabel("tf (s)")
    ax.set_title("S2 Table 4: minimum time per initial position")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return fig


def _euler_yxz(sigma: np.ndarray) -> np.ndarray:
    """Intrinsic Y-X-Z Euler angles (rad) of the body frame relative to LVLH from MRPs."""
    from adcskit.attitude.euler import dcm_to_euler
    from adcskit.attitude.mrp import mrp_to_dcm

    return dcm_to_euler(mrp_to_dcm(sigma), "YXZ")


def _figures(sol) -> dict:
    t = sol.t
    tc = sol.t_control
    x, u, lam = sol.x, sol.u, sol.costate
    figs = {}

    def panel(name, title, tt, data, labels, ylabel, style="-", step=False):
        fig, ax = new_figure()
        for j, lab in enumerate(labels):
            if step:
                ax.step(tt, data[:, j], where="mid", label=lab)
            else:
                ax.plot(tt, data[:, j], style, ms=3, label=lab)
        ax.set_xlabel("t (s)")
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        figs[name] = fig

    lbl = f" ({sol.mesh.label()} mesh, tf = {sol.tf:.4f} s)"
    panel("fig03_torques", "Control torques" + lbl, tc, u[:, :3], ["T1", "T2", "T3"], "N m", ".-")
    panel("fig04_forces", "Control forces" + lbl, tc, u[:, 3:], ["F1", "F2", "F3"], "N", ".-")
    panel("fig05_rates", "Angular rate relative to LVLH", t, x[:, :3], ["ω1", "ω2", "ω3"], "rad/s")
    panel("fig06_mrp", "Modified Rodrigues parameters", t, x[:, 3:6], ["σ1", "σ2", "σ3"], "-")
    panel("fig07_euler_yxz", "Euler angles, sequence YXZ", t, np.degrees(_euler_yxz(x[:, 3:6])),
          ["θ_Y", "θ_X", "θ_Z"], "deg")
    panel("fig08_velocity", "Relative velocity (LVLH)", t, x[:, 6:9], ["v1", "v2", "v3"], "m/s")
    panel("fig09_position", "Relative position (LVLH)", t, x[:, 9:12], ["s1", "s2", "s3"], "m")
    fig = __import__("matplotlib.figure", fromlist=["Figure"]).Figure(figsize=(6.4, 5.0), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    ax.plot(x[:, 9], x[:, 10], x[:, 11], "-")
    ax.scatter([x[0, 9]], [x[0, 10]], [x[0, 11]], marker="o", label="start")
    ax.scatter([x[-1, 9]], [x[-1, 10]], [x[-1, 11]], marker="s", label="end")
    ax.scatter([0], [0], [0], marker="*", s=80, label="target")
    ax.set_xlabel("X (m)")
    ax.set_ylabel("Y (m)")
    ax.set_zlabel("Z (m)")
    ax.invert_zaxis()
    ax.set_title("3-D path in LVLH (Z toward Earth)")
    ax.legend(fontsize=8)
    figs["fig10_path3d"] = fig
    panel("fig11_costate_rates", "Costates of ω", t, lam[:, :3], ["λω1", "λω2", "λω3"], "-", ".-")
    panel("fig12_costate_mrp", "Costates of σ", t, lam[:, 3:6], ["λσ1", "λσ2", "λσ3"], "-", ".-")
    panel("fig13_costate_velocity", "Costates of v", t, lam[:, 6:9], ["λv1", "λv2", "λv3"], "-", ".-")
    panel("fig14_costate_position", "Costates of s", t, lam[:, 9:12], ["λs1", "λs2", "λs3"], "-", ".-")
    fig, ax = new_figure()
    ax.plot(tc, sol.hamiltonian, ".-")
    ax.axhline(-1.0, color="k", lw=0.8, ls="--", label="H = -1 (theory)")
    ax.set_ylim(-1.1, -0.9)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("H")
    ax.set_title("Hamiltonian at the collocation points")
    ax.legend(fontsize=8)
    figs["fig15_hamiltonian"] = fig
    return figs


STUDY = Study(
    name="rendezvous",
    title="Time-optimal 6-DOF rendezvous by Gauss pseudospectral collocation (S2 Table 4)",
    paper="S2",
    config_cls=Config,
    run=run,
    quick={
        "rows": ((20.0, 0.0, 0.0), (20.0, 4.0, 4.0)),
        "n_starts": 3,
        "refine_meshes": ((40, 4),),
        "rtol": 1e-3,
        "compare_full_dynamics": False,
    },
    doc="docs/studies/rendezvous.md",
)
