"""The rendezvous study's measurements (S2): solves, branch tracking, typed frozen records.

For every initial position of S2 Table 4 and every reading of the rotational dynamics
(eq. 2 as printed, and the full relative dynamics):

1. *Multistart* on the paper's mesh (20 equal sub-intervals × 3 LG points): the straight-line
   guess and seeded random guesses; every distinct local optimum of the 20×3 NLP is kept.
2. *Branch tracking by error-controlled refinement*: each distinct optimum is handed to
   :func:`adcskit.optimal_control.solve_adaptive` on its own 20×3 mesh (the first solve
   re-solves it from itself with primal and dual warm start, a check that it is a KKT point
   IPOPT stays at), which refines the mesh by hp rules, warm-starting every solve from the
   previous one, until the relative state error of every mesh interval is below
   ``adaptive_tol`` or ``adaptive_max_iterations`` solves are spent. Its error certificate
   (achieved error, tolerance met or not, intervals, nodes, iterations) is reported beside
   the converged ``tf``. A refinement whose ``tf`` moves by more than
   ``jump_factor × adaptive_tol`` (relative) from its 20×3 start is flagged as a branch jump.
3. The second reading continues each branch of the first (same 20×3 mesh, warm start with the
   first reading's multipliers; the dynamics differ by O(|ω| n) terms) and refines it the same
   way.

:func:`run_experiment` does all solving (and the open-loop re-simulations of the checks) and
returns an :class:`Experiment` of frozen records; claims, figures and tables read only those.
The records' fields are the keys of ``result.json``'s ``measured`` section, in its order, and
each field is also readable by that key (``record["tf_converged_s"]``).

References
----------
S2, eq. 2–16 (model), 17–37 (method), Tables 2–4, Figs 3–15, §6–7. Patterson, Hager & Rao,
Optim. Control Appl. Meth. 36(4), 2015 and Liu, Hager & Rao, J. Franklin Inst. 352(10), 2015
(the error estimate and hp rules of :func:`solve_adaptive`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from adcskit._progress import status, track
from adcskit._results import Result, to_jsonable
from adcskit.optimal_control import bang_bang, multistart, resimulate, solve, solve_adaptive
from adcskit.optimal_control.problems.rendezvous import rendezvous_problem
from adcskit.studies.rendezvous.config import Config
from adcskit.studies.rendezvous.paper import PAPER_ROWS, paper_row

__all__ = [
    "BranchRecord",
    "Experiment",
    "MainRecord",
    "MeshStep",
    "ReadingMeasure",
    "RowRecord",
    "RowRun",
    "Trajectory",
    "match_tol",
    "repeatability",
    "run_experiment",
]


class _Record(Result):
    """Base of the study's records: ``to_dict`` and compact ``repr`` of :class:`Result`, and
    read access by field name (``record["key"]``, the key ``result.json`` writes)."""

    __slots__ = ()

    def __getitem__(self, key: str) -> Any:
        return getattr(self, key)


@dataclass(frozen=True, slots=True, repr=False)
class MeshStep(_Record):
    """One NLP solve of a branch's refinement."""

    iteration: int
    n_intervals: int
    n_nodes: int
    max_error: float
    tf_s: float
    nit: int
    warm_start: str


@dataclass(frozen=True, slots=True, repr=False)
class BranchRecord(_Record):
    """One local branch under one reading: 20×3 value, converged value, error certificate."""

    tf_paper_mesh_s: float
    tf_converged_s: float
    converged: bool
    on_branch: bool
    max_error: float
    tol: float
    tolerance_met: bool
    n_intervals: int
    n_nodes: int
    mesh_iterations: int
    worst_time_s: float
    mesh: str
    max_tf_move: float
    starts_on_paper_mesh: bool
    self_resolve_change: float
    self_resolve_nit: int
    self_resolve_mode: str
    continuation_change: float
    refine_cpu_s: float
    history: tuple[MeshStep, ...]
    message: str


@dataclass(frozen=True, slots=True, repr=False)
class RowRecord(_Record):
    """One Table 4 row under one reading: its multistart and its branches."""

    s0_m: tuple[float, ...]
    reading: str
    n_starts: int
    n_success: int
    optima_paper_mesh_s: tuple[float, ...]
    starts_per_optimum: tuple[int, ...]
    spread_per_optimum_s: tuple[float, ...]
    best_paper_mesh_s: float
    branches: tuple[BranchRecord, ...]
    converged_optima_s: tuple[float, ...]
    branches_per_converged_optimum: tuple[int, ...]
    best_converged_s: float
    default_guess_status: str
    default_guess_tf_s: float


@dataclass(frozen=True, slots=True, repr=False)
class MainRecord(_Record):
    """The main row's best branch: bang-bang structure and Hamiltonian (S2 Figs 3-4, 15)."""

    tf_paper_mesh_s: float
    tf_converged_s: float
    mesh: str
    max_error: float
    tolerance_met: bool
    bang_bang_all: bool
    at_bound_fraction: tuple[float, ...]
    n_switches: tuple[int, ...]
    h_mean_paper_mesh: float
    h_std_paper_mesh: float
    h_max_dev_paper_mesh: float
    h_mean_converged: float
    h_std_converged: float


@dataclass(frozen=True, slots=True, repr=False)
class ReadingMeasure(_Record):
    """Everything the claims and findings of one dynamics reading are decided from.

    ``rows[i]`` is Table 4 row ``i`` (a row not in Table 4 gets an index past the table);
    the four lists hold one value per Table 4 row present, in row order. ``main`` is None
    when the main row has no successful branch. ``precision`` names the tolerance reading of
    the tf claims (set only on the copies the claims are evaluated on).
    ``repeatability_s`` is the solver's repeatability on a 20×3 ``tf`` (s): the largest
    spread of IPOPT's answers for one 20×3 optimum, over the starts that reached it and its
    primal-dual re-solve from itself (:func:`repeatability`).
    """

    rows: Mapping[int, RowRecord]
    reading: str
    repeatability_s: float
    fraction_branches_distinct: float
    gpm_gpops_gap: list[float]
    gpm_best_gpops_gap: list[float]
    gpm_gain_over_gpops: list[float]
    gpops_branch: list[int | None]
    gpops_rank: list[int | None]
    main: MainRecord | None = None
    precision: str | None = field(default=None, compare=False)

    @property
    def bang_bang_all(self) -> bool:
        """Every channel of the main row's best converged solution is bang-bang."""
        return bool(self.main is not None and self.main.bang_bang_all)

    @property
    def h_max_dev_paper_mesh(self) -> float:
        """max |H + 1| of the main row's best 20×3 solution (inf without one)."""
        return math.inf if self.main is None else self.main.h_max_dev_paper_mesh

    def to_dict(self) -> dict[str, Any]:
        """The ``measured`` entry of this reading (rows keyed by their s0, no ``precision``)."""
        main = {"bang_bang_all": False, "h_max_dev_paper_mesh": math.inf} if self.main is None else self.main
        return to_jsonable(
            {
                "rows": {str(list(r.s0_m)): r for r in self.rows.values()},
                "reading": self.reading,
                "repeatability_s": self.repeatability_s,
                "fraction_branches_distinct": self.fraction_branches_distinct,
                "gpm_gpops_gap": self.gpm_gpops_gap,
                "gpm_best_gpops_gap": self.gpm_best_gpops_gap,
                "gpm_gain_over_gpops": self.gpm_gain_over_gpops,
                "gpops_branch": self.gpops_branch,
                "gpops_rank": self.gpops_rank,
                "main": main,
            }
        )


@dataclass(frozen=True, slots=True, repr=False)
class RowRun(_Record):
    """One configured initial position: its multistart starts and its record per reading."""

    s0: tuple[float, ...]
    paper_index: int | None
    start_tf_s: tuple[float, ...]
    start_status: tuple[str, ...]
    wall_s: float
    records: Mapping[str, RowRecord]


@dataclass(frozen=True, slots=True, repr=False)
class Trajectory(_Record):
    """The main row's best converged solution (first reading), as S2 Figs 3-15 plot it."""

    t: np.ndarray
    t_control: np.ndarray
    x: np.ndarray
    u: np.ndarray
    costate: np.ndarray
    hamiltonian: np.ndarray
    n_intervals: int
    n_nodes: int
    tf: float


@dataclass(frozen=True, slots=True, repr=False)
class Experiment(_Record):
    """All measurements of one run: per row, per reading, the main trajectory, re-simulations.

    ``readings`` is keyed by config value (``"paper"``, ``"full"``); ``terminal_misses`` are the
    scaled terminal misses of each row's best converged solution of the first reading,
    re-simulated open loop (:func:`adcskit.optimal_control.resimulate`).
    """

    runs: tuple[RowRun, ...]
    rows_present: tuple[int, ...]
    readings: Mapping[str, ReadingMeasure]
    trajectory: Trajectory | None
    terminal_misses: tuple[float, ...]


# --------------------------------------------------------------------------- solving


@dataclass(frozen=True, slots=True)
class _Branch:
    """One local branch under one dynamics reading: its 20×3 optimum and its refinement."""

    start: Any  # OptimalControlSolution on the paper mesh (multistart optimum or continuation)
    final: Any  # AdaptiveSolution of solve_adaptive started from ``start``
    continuation_change: float  # |tf(start) - tf(first reading's 20x3)| / tf (NaN: first reading)
    cpu_s: float  # CPU time of the refinement (s)


@dataclass(frozen=True, slots=True)
class _RowSolve:
    """The solver output of one row (multistart and branches per reading)."""

    s0: tuple[float, ...]
    multistart: Any
    readings: dict[str, list[_Branch]]
    wall_s: float


def _cluster(values, rtol):
    """Sorted distinct values (relative distance > rtol) and the members of each."""
    out: list[list[float]] = []
    for v in sorted(v for v in values if math.isfinite(v)):
        if out and abs(v - out[-1][0]) <= rtol * abs(v):
            out[-1].append(v)
        else:
            out.append([v])
    return [g[0] for g in out], [len(g) for g in out]


def _mesh_text(n_intervals: int, n_nodes: int) -> str:
    return f"{n_intervals} intervals / {n_nodes} nodes"


def _nlp_ok(br: _Branch) -> bool:
    """The last NLP solve of the branch's refinement succeeded (its tf is a KKT point)."""
    return bool(br.final.mesh_history[-1].success)


def _best_branch(branches: list[_Branch]) -> _Branch | None:
    """The branch with the smallest converged tf (among successful final solves)."""
    return min((b for b in branches if _nlp_ok(b)), key=lambda b: b.final.tf, default=None)


def _refine(prob, start, cfg: Config) -> tuple[Any, float]:
    """Error-controlled refinement of the branch of ``start`` (a 20×3 optimum, or a refined
    solution), warm-started from it with primal and dual values on its own mesh, then from
    each previous solve."""
    t = time.process_time()
    sol = solve_adaptive(
        prob,
        tol=cfg.adaptive_tol,
        method=cfg.method,
        mesh=start.mesh,
        guess=start,
        max_iterations=cfg.adaptive_max_iterations,
    )
    return sol, time.process_time() - t


def _solve_row(s0, cfg: Config, seed: int) -> _RowSolve:
    """Multistart + branch tracking for the first reading, continuation for the others."""
    t_start = time.perf_counter()
    first = cfg.readings[0]
    prob = rendezvous_problem(s0, dynamics=first)
    ms = multistart(
        prob, cfg.n_starts, method=cfg.method, mesh=cfg.paper_mesh, rng=seed, rtol=cfg.distinct_rtol
    )
    reps = []
    for value in ms.distinct_objectives:  # the best-converged start of each distinct optimum
        cands = [
            s
            for s in ms.solutions
            if s.success and abs(s.objective - value) <= cfg.distinct_rtol * value
        ]
        reps.append(min(cands, key=lambda s: s.objective))
    per: dict[str, list[_Branch]] = {first: []}
    for r in reps:
        status(f"rendezvous s0={s0}: refining the {r.tf:.4f} s branch")
        fin, cpu = _refine(prob, r, cfg)
        per[first].append(_Branch(r, fin, math.nan, cpu))
    for other in cfg.readings[1:]:
        po = rendezvous_problem(s0, dynamics=other)
        per[other] = []
        for b in per[first]:
            # continue the branch to this reading on the 20x3 mesh (primal-dual warm start)
            cont = solve(po, method=cfg.method, mesh=b.start.mesh, guess=b.start)
            change = abs(cont.tf - b.start.tf) / b.start.tf if cont.success else math.inf
            if cfg.other_readings_start == "refined_mesh" and _nlp_ok(b):
                fin, cpu = _refine(po, b.final, cfg)
            else:
                fin, cpu = _refine(po, cont, cfg)
            per[other].append(_Branch(cont, fin, change, cpu))
    return _RowSolve(s0, ms, per, time.perf_counter() - t_start)


# --------------------------------------------------------------------------- records


def _branch_record(br: _Branch, cfg: Config) -> BranchRecord:
    """Plain numbers of one branch: 20×3 value, converged value and its error certificate."""
    fin = br.final
    hist = fin.mesh_history
    cert = fin.certificate
    tf0 = float(br.start.tf) if br.start.success else math.nan
    # J = tf for this problem (S2: minimum time), so each solve's objective is its tf
    tfs = [float(h.objective) if h.success else math.nan for h in hist]
    moves = [abs(t - tf0) / tf0 for t in tfs]
    finite = [d for d in moves if math.isfinite(d)]
    jumps = [k for k, d in enumerate(moves) if math.isfinite(d) and d > cfg.same_rtol]
    ok = bool(hist[-1].success)
    # the first solve re-solves the 20x3 optimum from itself unless the refinement started on
    # another mesh (other_readings_start="refined_mesh")
    from_paper_mesh = hist[0].meshes[0] == br.start.mesh
    msg = fin.message
    if jumps:
        msg += "; branch jump at mesh iteration " + ", ".join(
            f"{k + 1} (tf {tfs[k]:.5f} s, |dtf|/tf {moves[k]:.2e} > {cfg.same_rtol:.0e})"
            for k in jumps
        )
    return BranchRecord(
        tf_paper_mesh_s=tf0,
        tf_converged_s=float(fin.tf) if ok else math.nan,
        converged=bool(cert.satisfied),
        on_branch=ok and not jumps and math.isfinite(tf0),
        max_error=float(cert.max_error),
        tol=float(cert.tol),
        tolerance_met=bool(cert.satisfied),
        n_intervals=int(fin.mesh.n_intervals),
        n_nodes=int(cert.n_collocation),
        mesh_iterations=int(cert.mesh_iterations),
        worst_time_s=float(cert.worst_time),
        mesh=_mesh_text(fin.mesh.n_intervals, cert.n_collocation),
        max_tf_move=max(finite) if finite else math.nan,
        starts_on_paper_mesh=bool(from_paper_mesh),
        self_resolve_change=moves[0] if from_paper_mesh else math.nan,
        self_resolve_nit=int(hist[0].nit) if from_paper_mesh else -1,
        self_resolve_mode=hist[0].warm_start if from_paper_mesh else "",
        continuation_change=float(br.continuation_change),
        refine_cpu_s=float(br.cpu_s),
        history=tuple(
            MeshStep(
                iteration=k + 1,
                n_intervals=int(h.meshes[0].n_intervals),
                n_nodes=int(h.n_collocation),
                max_error=float(h.max_error),
                tf_s=tfs[k],
                nit=int(h.nit),
                warm_start=h.warm_start,
            )
            for k, h in enumerate(hist)
        ),
        message=msg,
    )


def _row_measure(res: _RowSolve, reading: str, cfg: Config) -> RowRecord:
    """Per-row, per-reading measurements (plain numbers) the claims are decided from."""
    branches = tuple(_branch_record(b, cfg) for b in res.readings[reading])
    conv_distinct, conv_counts = _cluster([b.tf_converged_s for b in branches], cfg.same_rtol)
    pm = tuple(b.tf_paper_mesh_s for b in branches)
    ms = res.multistart
    counts = dict(zip(np.round(ms.distinct_objectives, 6), ms.counts.tolist(), strict=True))
    spread = []
    for value in ms.distinct_objectives:  # the starts _solve_row assigns to this optimum
        tfs = [s.objective for s in ms.solutions if s.success and abs(s.objective - value) <= cfg.distinct_rtol * value]
        spread.append(float(max(tfs) - min(tfs)) if tfs else math.nan)
    return RowRecord(
        s0_m=tuple(res.s0),
        reading=reading,
        n_starts=len(ms.solutions),
        n_success=int(ms.n_success),
        optima_paper_mesh_s=pm,
        starts_per_optimum=tuple(int(counts.get(round(v, 6), 0)) for v in ms.distinct_objectives),
        spread_per_optimum_s=tuple(spread),
        best_paper_mesh_s=float(np.nanmin(pm)) if np.isfinite(pm).any() else math.nan,
        branches=branches,
        converged_optima_s=tuple(conv_distinct),
        branches_per_converged_optimum=tuple(conv_counts),
        best_converged_s=float(conv_distinct[0]) if conv_distinct else math.nan,
        default_guess_status=ms.solutions[0].ipopt_status,
        default_guess_tf_s=float(ms.solutions[0].tf),
    )


def match_tol(decimals: int) -> float:
    """Tolerance of "equal to the printed digits": half a unit of the last decimal printed (s).

    The solver's repeatability is not added to it: it is the claims' equivalence margin
    around this tolerance (a value within it is a tie, :mod:`.claims`).

    Examples
    --------
    >>> match_tol(4)
    5e-05
    """
    return 0.5 * 10.0**-decimals


def repeatability(rows: Mapping[int, Any]) -> float:
    """The solver's repeatability on a 20×3 ``tf`` (s), measured over every optimum of ``rows``.

    The largest of: the spread (max − min) of the ``tf`` of the multistart starts that reached
    one 20×3 optimum (different guesses), and the change of each branch's 20×3 ``tf`` when its
    refinement re-solves it from itself with primal and dual warm start (other IPOPT options,
    ``self_resolve_change × tf``). NaN entries (a re-solve that did not start on 20×3) are
    skipped; NaN when nothing was measured.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> b = NS(tf_paper_mesh_s=25.0, self_resolve_change=2e-8)
    >>> repeatability({0: NS(spread_per_optimum_s=(6e-8, 0.0), branches=(b,))})
    5e-07
    """
    vals = []
    for r in rows.values():
        vals += [float(v) for v in r.spread_per_optimum_s]
        vals += [float(b.self_resolve_change) * float(b.tf_paper_mesh_s) for b in r.branches]
    vals = [v for v in vals if math.isfinite(v)]
    return max(vals) if vals else math.nan


def identify(value: float, row, cfg: Config, *, converged: bool) -> int | None:
    """The branch whose 20×3 (``converged=False``) or mesh-converged tf *is* ``value``.

    ``value`` identifies a branch when that branch's value is the nearest of all our values of
    the row (every branch's 20×3 *and* converged tf, so that a 20×3 value is not mistaken for a
    converged one or the reverse) and lies within ``jump_factor × adaptive_tol`` (relative) of it.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> row = NS(branches=[NS(tf_paper_mesh_s=25.8727, tf_converged_s=25.8703)])
    >>> identify(25.87, row, Config(), converged=True), identify(25.8727, row, Config(), converged=True)
    (0, None)
    """
    want = "tf_converged_s" if converged else "tf_paper_mesh_s"
    cands = [
        (abs(getattr(b, k) - value), i, k)
        for i, b in enumerate(row.branches)
        for k in ("tf_paper_mesh_s", "tf_converged_s")
    ]
    cands = [c for c in cands if math.isfinite(c[0])]
    if not cands:
        return None
    d, i, k = min(cands)
    if k != want or d > cfg.same_rtol * abs(value):
        return None
    return i


def _gpm_gpops_gap(row, paper, cfg: Config) -> float:
    """Relative distance between the converged branch of the paper's GPM value and GPOPS; when
    the GPM value is no 20×3 optimum of ours, between the paper's two values themselves (finite:
    a non-finite value would read as a failed solve)."""
    k = identify(paper[1], row, cfg, converged=False)
    tf = paper[1] if k is None else row.branches[k].tf_converged_s
    return abs(tf - paper[2]) / paper[2]


def _derive(rows: Mapping[int, Any], reading: str, cfg: Config, main: MainRecord | None = None) -> ReadingMeasure:
    """The quantities the claims and findings read, from the per-row branch records
    (``rows[i]``: Table 4 row ``i``, as built by :func:`_row_measure`)."""
    n_pm = sum(len(r.branches) for r in rows.values())
    n_dist = 0
    for r in rows.values():
        tol_same = cfg.same_rtol
        for b in r.branches:
            others = [o.tf_converged_s for o in r.branches if o is not b]
            # a branch is distinct when no other branch of the row converges to its value
            clash = any(abs(o - b.tf_converged_s) <= tol_same * b.tf_converged_s for o in others)
            ok = b.on_branch and b.converged and math.isfinite(b.tf_converged_s)
            n_dist += bool(ok and not clash)
    gap, gap_best, gain, gb, grank = [], [], [], [], []
    for i in range(len(PAPER_ROWS)):
        if i not in rows:
            continue
        paper, r = PAPER_ROWS[i], rows[i]
        gap.append(_gpm_gpops_gap(r, paper, cfg))
        # our GPM result (best 20x3 optimum over the documented starts) against S2's GPOPS value,
        # relative to the GPM value as S2's Table 4 difference column is
        gap_best.append(abs(r.best_paper_mesh_s - paper[2]) / r.best_paper_mesh_s)
        k = identify(paper[1], r, cfg, converged=False)
        # the paper's own GPM value where it is no optimum of ours (finite, see _gpm_gpops_gap)
        gain.append((paper[2] - (r.branches[k].tf_converged_s if k is not None else paper[1])) / paper[2])
        kg = identify(paper[2], r, cfg, converged=True)
        gb.append(kg)
        if kg is None:
            grank.append(None)
        else:
            tfk = r.branches[kg].tf_converged_s
            grank.append(int(sum(v < tfk * (1 - cfg.same_rtol) for v in r.converged_optima_s)))
    return ReadingMeasure(
        rows=rows,
        reading=reading,
        repeatability_s=repeatability(rows),
        fraction_branches_distinct=n_dist / n_pm if n_pm else math.nan,
        gpm_gpops_gap=gap,
        gpm_best_gpops_gap=gap_best,
        gpm_gain_over_gpops=gain,
        gpops_branch=gb,
        gpops_rank=grank,
        main=main,
    )


def _main_record(best: _Branch) -> MainRecord:
    """Bang-bang structure and Hamiltonian of the main row's best branch."""
    fin = best.final
    bb = bang_bang(fin)
    h20 = best.start.hamiltonian
    cert = fin.certificate
    return MainRecord(
        tf_paper_mesh_s=float(best.start.tf),
        tf_converged_s=float(fin.tf),
        mesh=_mesh_text(fin.mesh.n_intervals, cert.n_collocation),
        max_error=float(cert.max_error),
        tolerance_met=bool(cert.satisfied),
        bang_bang_all=bool(bb.all_bang_bang),
        at_bound_fraction=tuple(bb.at_bound_fraction.tolist()),
        n_switches=tuple(bb.n_switches.tolist()),
        h_mean_paper_mesh=float(np.mean(h20)),
        h_std_paper_mesh=float(np.std(h20)),
        h_max_dev_paper_mesh=float(np.max(np.abs(h20 + 1.0))),
        h_mean_converged=float(np.mean(fin.hamiltonian)),
        h_std_converged=float(np.std(fin.hamiltonian)),
    )


def _trajectory(sol) -> Trajectory:
    return Trajectory(
        t=sol.t,
        t_control=sol.t_control,
        x=sol.x,
        u=sol.u,
        costate=sol.costate,
        hamiltonian=sol.hamiltonian,
        n_intervals=int(sol.mesh.n_intervals),
        n_nodes=int(sum(sol.mesh.nodes)),
        tf=float(sol.tf),
    )


def run_experiment(cfg: Config, rng: np.random.Generator) -> Experiment:
    """Solve every configured row under every reading and reduce the solutions to records.

    One seed per row is drawn from ``rng`` (the row's multistart); nothing else is random.

    Parameters
    ----------
    cfg : Config
    rng : numpy.random.Generator

    Returns
    -------
    Experiment

    Examples
    --------
    One row, one start, one reading on a 4×3 mesh (a few seconds of solving):

    >>> cfg = Config(rows_m=((20.0, 0.0, 0.0),), readings=("paper",), paper_mesh=(4, 3), n_starts=1,
    ...              adaptive_max_iterations=1)
    >>> exp = run_experiment(cfg, np.random.default_rng(0))  # doctest: +SKIP
    >>> exp.rows_present, exp.readings["paper"].rows[0].n_starts  # doctest: +SKIP
    ((0,), 1)
    """
    seeds = [int(s) for s in rng.integers(0, 2**31 - 1, size=len(cfg.rows_m))]
    results = []
    for s0, seed in track(list(zip(cfg.rows_m, seeds, strict=True)), "rendezvous rows"):
        status(f"rendezvous row s0={s0}")
        results.append(_solve_row(tuple(float(v) for v in s0), cfg, seed))
    index = [None if (p := paper_row(r.s0)) is None else PAPER_ROWS.index(p) for r in results]
    rows_present = tuple(sorted(i for i in index if i is not None))
    main_res = next((r for r in results if np.allclose(r.s0, PAPER_ROWS[0][0])), results[0])
    records: dict[str, list[RowRecord]] = {}
    readings: dict[str, ReadingMeasure] = {}
    trajectory = None
    for reading in cfg.readings:
        records[reading] = [_row_measure(res, reading, cfg) for res in results]
        rows: dict[int, RowRecord] = {}
        for i, rec in zip(index, records[reading], strict=True):
            rows[i if i is not None else len(PAPER_ROWS) + len(rows)] = rec
        best = _best_branch(main_res.readings[reading])
        readings[reading] = _derive(rows, reading, cfg, None if best is None else _main_record(best))
        if best is not None and reading == cfg.readings[0]:
            trajectory = _trajectory(best.final)
    misses = []
    for res in results:
        best = _best_branch(res.readings[cfg.readings[0]])
        if best is not None:
            misses.append(float(resimulate(best.final).terminal_miss_scaled))
    runs = tuple(
        RowRun(
            s0=res.s0,
            paper_index=i,
            start_tf_s=tuple(float(v) for v in res.multistart.objectives),
            start_status=tuple(s.ipopt_status for s in res.multistart.solutions),
            wall_s=res.wall_s,
            records={d: records[d][k] for d in cfg.readings},
        )
        for k, (res, i) in enumerate(zip(results, index, strict=True))
    )
    return Experiment(
        runs=runs,
        rows_present=rows_present,
        readings=readings,
        trajectory=trajectory,
        terminal_misses=tuple(misses),
    )


def _example_experiment() -> Experiment:
    """A one-row, one-branch :class:`Experiment` of plain numbers, no solve (for the examples).

    Its numbers are the main row's first branch of the full run (docs/studies/rendezvous.md):
    20×3 optimum 25.872706 s, converged 25.870312 s.
    """
    step = MeshStep(iteration=1, n_intervals=20, n_nodes=60, max_error=4e-4, tf_s=25.872706, nit=2,
                    warm_start="primal-dual")
    branch = BranchRecord(
        tf_paper_mesh_s=25.872706, tf_converged_s=25.870312, converged=True, on_branch=True, max_error=4e-4,
        tol=1e-3, tolerance_met=True, n_intervals=20, n_nodes=60, mesh_iterations=1, worst_time_s=1.0,
        mesh=_mesh_text(20, 60), max_tf_move=9.3e-5, starts_on_paper_mesh=True, self_resolve_change=0.0,
        self_resolve_nit=2, self_resolve_mode="primal-dual", continuation_change=math.nan, refine_cpu_s=0.0,
        history=(step,), message="tolerance met",
    )
    row = RowRecord(
        s0_m=(20.0, 0.0, 0.0), reading="paper", n_starts=1, n_success=1, optima_paper_mesh_s=(25.872706,),
        starts_per_optimum=(1,), spread_per_optimum_s=(0.0,), best_paper_mesh_s=25.872706, branches=(branch,),
        converged_optima_s=(25.870312,), branches_per_converged_optimum=(1,), best_converged_s=25.870312,
        default_guess_status="Solve_Succeeded", default_guess_tf_s=25.872706,
    )
    cfg = Config(rows_m=((20.0, 0.0, 0.0),), readings=("paper",), n_starts=1)
    run = RowRun(s0=(20.0, 0.0, 0.0), paper_index=0, start_tf_s=(25.872706,),
                 start_status=("Solve_Succeeded",), wall_s=0.0, records={"paper": row})
    return Experiment(runs=(run,), rows_present=(0,), readings={"paper": _derive({0: row}, "paper", cfg)},
                      trajectory=None, terminal_misses=(1e-3,))
