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

The package: ``paper`` (what S3 prints), ``config`` (:class:`Config`), ``experiment``
(:func:`~.experiment.measure` and its frozen records), ``claims`` (claims, findings and
checks, decided by the verdict framework), ``figures`` and ``report`` (pure functions of the
records); :func:`run` only wires them together.
"""

from __future__ import annotations

from typing import Any

from adcskit.studies._base import Study, StudyResult
from adcskit.studies.thruster_layout import claims, figures, report
from adcskit.studies.thruster_layout.config import Config
from adcskit.studies.thruster_layout.experiment import measure
from adcskit.studies.thruster_layout.paper import A_REF, PAPER, manoeuvre_demands

__all__ = ["Config", "run", "STUDY", "manoeuvre_demands", "A_REF", "PAPER"]

STUDY_TITLE = "GEO thruster layout design with GA vs DE, allocation and fuel vs a reference layout (S3)"


def run(config: Config, *, quick: bool = False, rng: Any = None, executor: Any = None) -> StudyResult:
    """Run the study (see the module docstring): measure, decide, then tables, text and figures."""
    cfg = config
    m = measure(cfg, rng=rng, executor=executor)
    decided_claims = claims.evaluate(claims.CLAIMS, cfg, m)
    return StudyResult(
        study="thruster-layout",
        title=STUDY_TITLE,
        summary=report.summary(cfg, m, decided_claims),
        paper=PAPER,
        measured=report.measured(cfg, m),
        checks=claims.evaluate(claims.CHECKS, cfg, m),
        claims=decided_claims,
        findings=claims.evaluate(claims.FINDINGS, cfg, m),
        comparison=report.comparison(cfg, m),
        differences=report.differences(cfg, m),
        figures=figures.figures(cfg, m),
        tables=report.tables(cfg, m),
        doc="docs/studies/thruster-layout.md",
    )


STUDY = Study(
    name="thruster-layout",
    title=STUDY_TITLE,
    paper="S3: Kosari, Kaviri, Moshiri, Fakoor - optimal thruster configuration for a GEO satellite",
    config_cls=Config,
    run=run,
    quick={"n_gen": 60, "pop_size": 24, "n_random_layouts": 40, "timing_repeats": 1},
    doc="docs/studies/thruster-layout.md",
)
