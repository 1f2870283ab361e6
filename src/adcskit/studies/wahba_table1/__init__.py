"""Study ``wahba-table1``: S0 Table 1 — one epoch, ±20 % interval noise, point vs robust solvers.

The printed single-epoch vectors (S0 eq. 9) are perturbed by uniform bounded noise of
±``noise_bound`` of each component's value and solved by the q-method (S0's baseline), the
paper's min-max goal attainment (exactly and iteratively, as the paper does), NSGA-II with a
truth-free knee pick and with the paper's pick by the true attitude, the worst-case robust
solver (Ahmed & Kerrigan), and QUEST/SVD as sanity rows; a noise-bound sweep gives the slope
reading of the "200× less dependence on input accuracy" claim. Every claim is decided over
``n_seeds`` independent replicas of the whole Table 1 (details: ``docs/studies/wahba-table1.md``
and :mod:`~adcskit.studies.wahba_table1.experiment`).

The package: ``paper`` (what S0 prints), ``config`` (:class:`Config`), ``experiment``
(:func:`~.experiment.measure` and its frozen records), ``claims`` (claims, findings and checks,
decided by the verdict framework), ``figures`` and ``report`` (pure functions of the records);
:func:`run` only wires them together.
"""

from __future__ import annotations

from dataclasses import asdict
from typing import Any

from adcskit.studies._base import Study, StudyResult
from adcskit.studies._verdict import decide_declared
from adcskit.studies.wahba_table1 import claims, figures, report
from adcskit.studies.wahba_table1.config import Config
from adcskit.studies.wahba_table1.experiment import (
    CHEAP_ROWS,
    ITER_ROWS,
    ROWS,
    SWEEP_ROWS,
    angle_deg,
    measure,
    perturb,
    perturb_raw,
    qmethod_in_box,
    trial,
)
from adcskit.studies.wahba_table1.paper import (
    B_EXACT,
    PAPER,
    PAPER_TABLE1,
    Q_EXACT_SCALAR_FIRST,
    R_EXACT,
    q_exact,
)

__all__ = ["B_EXACT", "CHEAP_ROWS", "Config", "ITER_ROWS", "PAPER_TABLE1", "Q_EXACT_SCALAR_FIRST", "ROWS",
           "R_EXACT", "STUDY", "SWEEP_ROWS", "angle_deg", "perturb", "perturb_raw", "q_exact", "qmethod_in_box",
           "run", "trial"]


def run(config: Config, *, quick: bool = False, rng: Any = None, executor: Any = None) -> StudyResult:
    """Run the study (see the module docstring): measure, decide, then tables, text and figures."""
    cfg = config
    m = measure(cfg, rng=rng, executor=executor)
    decided_claims = claims.evaluate(claims.CLAIMS, m)
    return StudyResult(
        study="wahba-table1",
        title=report.title(cfg),
        summary=report.summary(cfg, m, decided_claims),
        config=asdict(cfg),
        paper=PAPER,
        measured=report.measured(cfg, m),
        checks=decide_declared(claims.CHECKS, cfg, m),
        claims=decided_claims,
        findings=claims.evaluate(claims.FINDINGS, m),
        comparison=report.comparison(cfg, m),
        differences=report.differences(),
        figures=figures.figures(cfg, m),
        tables=report.tables(cfg, m),
        doc=STUDY.doc,
    )


STUDY = Study(
    name="wahba-table1",
    title="Robust Wahba, one epoch with ±20 % interval noise (S0 Table 1)",
    paper="S0",
    config_cls=Config,
    run=run,
    quick={"n_seeds": 2, "n_trials": 12, "n_iterative": 3, "pop_size": 24, "n_gen": 20, "nsga2_big_n_gen": 60,
           "timing_epochs": 2, "n_big_epochs": 1, "timing_repeats": 3, "sweep_bounds": (0.02, 0.1, 0.2), "sweep_trials": 6},
    doc="docs/studies/wahba-table1.md",
)
