"""Study ``onoff-schmitt``: Schmitt-trigger threshold sweep, step response and limit cycle (S4).

Reproduces S4 Figs. 2-7 and Table 2: with the nominal loop of S4 Table 3 (15° step, constant
0.05 N m disturbance), sweep the on threshold ``U_on`` and the ratio ``U_off/U_on`` and map
the fuel, the number of firings and the mean ``|error|`` over the last 10 s; then show the
nominal step response, thruster on/off history and limit-cycle phase portrait, and check
S4's 0.25° pointing-accuracy claim.

The package: ``paper`` (what S4 prints), ``config`` (:class:`Config`), ``experiment``
(:func:`~.experiment.measure` and its frozen records), ``claims`` (claims and checks, decided
by the verdict framework), ``figures`` and ``report`` (pure functions of the records);
:func:`run` only wires them together.

References
----------
S4, Figs. 2-7, Tables 2-3 (digits decoded in the seeds digest).
"""

from __future__ import annotations

from adcskit.studies._base import Study, StudyResult
from adcskit.studies.onoff_schmitt import claims, figures, report
from adcskit.studies.onoff_schmitt.config import Config
from adcskit.studies.onoff_schmitt.experiment import measure
from adcskit.studies.onoff_schmitt.paper import PAPER

__all__ = ["Config", "run", "STUDY"]


def run(config: Config, *, quick: bool = False, rng=None, executor=None) -> StudyResult:
    """Run the study (deterministic; ``rng`` and ``executor`` are not needed)."""
    m = measure(config)
    decided_claims = claims.evaluate(claims.CLAIMS, config, m)
    return StudyResult(
        study="onoff-schmitt",
        title=STUDY.title,
        summary=report.summary(config, m, decided_claims),
        paper=PAPER,
        measured=report.measured(m),
        checks=claims.evaluate(claims.CHECKS, config, m),
        claims=decided_claims,
        findings=claims.evaluate(claims.FINDINGS, config, m),
        comparison=report.comparison(config, m),
        differences=report.differences(config),
        figures=figures.figures(config, m),
        tables=report.tables(m),
        doc=STUDY.doc,
    )


STUDY = Study(
    name="onoff-schmitt",
    title="On-off thruster loop: Schmitt trigger threshold sweep, step response, limit cycle (S4 Figs 2-7)",
    paper="S4 — Bohlouri & Jalali-Naini, robust optimisation of on-off thruster attitude control",
    config_cls=Config,
    run=run,
    quick={"n_u_on": 10, "n_ratio": 8},
    doc="docs/studies/onoff-schmitt.md",
)
