"""Study ``rendezvous`` (S2): time-optimal 6-DOF rendezvous by Gauss pseudospectral collocation.

For every initial position of S2 Table 4 and every reading of the rotational dynamics (eq. 2
as printed, and the full relative dynamics), a seeded multistart on the paper's 20×3 mesh
finds every local optimum, and each is followed by warm-started error-controlled hp mesh
refinement (:func:`adcskit.optimal_control.solve_adaptive`) to its converged ``tf`` with an
error certificate; the second reading continues the first's branches. The paper's claims
(S2 §6–7, Table 4) are decided from these branches by the verdict model
(:mod:`adcskit.studies._verdict`); our questions (how many local optima, where the GPOPS
column sits) are findings.

The package: :mod:`.paper` (what S2 prints), :mod:`.config` (:class:`Config`),
:mod:`.experiment` (the solves, reduced to typed frozen records), :mod:`.claims` (claims,
findings and checks), :mod:`.figures` (pure functions of the records), :mod:`.report`
(tables and text); :func:`run` only orchestrates them.

References
----------
S2, eq. 2–16 (model), 17–37 (method), Tables 2–4, Figs 3–15, §6–7. Patterson, Hager & Rao,
Optim. Control Appl. Meth. 36(4), 2015 and Liu, Hager & Rao, J. Franklin Inst. 352(10), 2015
(the error estimate and hp rules of :func:`solve_adaptive`).
"""

from __future__ import annotations

import numpy as np

from adcskit.studies._base import Study, StudyResult
from adcskit.studies.rendezvous import figures, report
from adcskit.studies.rendezvous.claims import _decide, check_list
from adcskit.studies.rendezvous.config import Config
from adcskit.studies.rendezvous.experiment import run_experiment
from adcskit.studies.rendezvous.paper import PAPER_DOC, PAPER_ROWS, READING_NAMES

__all__ = ["Config", "run", "STUDY", "PAPER_ROWS", "READING_NAMES"]


def run(config: Config, *, quick: bool = False, rng=None, executor=None) -> StudyResult:
    """Run the study: solve (:func:`.experiment.run_experiment`), decide, draw, tabulate.

    ``quick`` and ``executor`` are accepted for the study interface; the quick settings are
    :data:`STUDY`'s config overrides, and the solves run in this process.
    """
    rng = np.random.default_rng(0) if rng is None else rng
    cfg = config
    exp = run_experiment(cfg, rng)
    first = exp.readings[cfg.readings[0]]
    claims, findings = _decide(exp.readings, cfg, exp.rows_present)
    checks = check_list(exp, cfg)
    figs = figures.trajectory_figures(exp.trajectory) if exp.trajectory is not None else {}
    figs["table4_tf"] = figures.table4_figure(first, cfg)
    figs["mesh_refinement"] = figures.refinement_figure(first, cfg)
    tables = report.tables(exp, cfg)
    reps = [exp.readings[r].repeatability_s for r in cfg.readings if np.isfinite(exp.readings[r].repeatability_s)]
    measured = {
        "readings": {READING_NAMES[r]: exp.readings[r] for r in cfg.readings},
        "row_wall_s": [run.wall_s for run in exp.runs],
        # the tf claims' equivalence margin, and Table 4 beside ours (short keys the page quotes)
        "repeatability_s": max(reps, default=float("nan")),
        "table4": tables["table4"],
        "main": exp.readings[cfg.readings[0]].main,
        "terminal_miss_max": max(exp.terminal_misses, default=float("nan")),
    }
    return StudyResult(
        study="rendezvous",
        title=report.title(cfg),
        summary=report.summary(exp, cfg, claims),
        config={},
        paper=PAPER_DOC,
        measured=measured,
        checks=checks,
        claims=claims,
        findings=findings,
        comparison=report.comparison(exp, cfg),
        differences=list(report.DIFFERENCES),
        figures=figs,
        tables=tables,
        doc="docs/studies/rendezvous.md",
    )


STUDY = Study(
    name="rendezvous",
    title="Time-optimal 6-DOF rendezvous by Gauss pseudospectral collocation (S2 Table 4)",
    paper="S2",
    config_cls=Config,
    run=run,
    quick={
        "rows_m": ((20.0, 0.0, 0.0), (20.0, 4.0, 4.0)),
        "n_starts": 4,
        "adaptive_tol": 1e-3,
        "adaptive_max_iterations": 5,
        "jump_factor": 5.0,
    },
    doc="docs/studies/rendezvous.md",
)
