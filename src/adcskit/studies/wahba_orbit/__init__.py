"""Study ``wahba-orbit``: S0 §4-2 — sun sensor + magnetometer attitude along an 800 km orbit.

A rigid spacecraft (inertia diag(80, 80, 4) kg m², S0 Table 3) starts at Euler angles
(0, 0, 5°) with zero body rate (S0 Table 2) and is propagated torque-free plus gravity
gradient for 20 minutes on a circular 800 km, 75° orbit (RAAN 0). At every sample a sun
sensor (±0.005° bounded error) and a three-axis magnetometer (±0.5° bounded error) measure
the sun direction (Vallado) and the geomagnetic field; the attitude is then determined by the
q-method and by the robust interval solvers, and compared with the truth (S0 Figs. 1–4).

Each *case* names the field model used for the truth and the one used as the solver's
reference, ``"truth/reference"``: ``dipole/dipole`` (the paper), ``igrf/igrf`` (IGRF-14
everywhere) and ``igrf/dipole`` (the real field measured, the paper's dipole used as
reference: a model error the intervals do not cover).

The package: ``paper`` (what S0 prints), ``config`` (:class:`Config`), ``experiment``
(:func:`~.experiment.measure` and its frozen records), ``claims`` (the claim, findings and
checks, decided by the verdict framework), ``figures`` and ``report`` (pure functions of the
records); :func:`run` only wires them together.
"""

from __future__ import annotations

from dataclasses import asdict
from typing import Any

from adcskit.studies._base import Study, StudyResult
from adcskit.studies.wahba_orbit import claims, figures, report
from adcskit.studies.wahba_orbit.claims import CLAIM, FINDING_KEYS, NSGA2_KEYS
from adcskit.studies.wahba_orbit.config import CASES, Config
from adcskit.studies.wahba_orbit.experiment import (
    METHODS,
    angle_deg,
    measure,
    run_case,
    simulate_truth,
)
from adcskit.studies.wahba_orbit.paper import PAPER

__all__ = ["CASES", "CLAIM", "Config", "FINDING_KEYS", "METHODS", "NSGA2_KEYS", "PAPER", "STUDY", "angle_deg",
           "run", "run_case", "simulate_truth"]

STUDY_TITLE = "Sun sensor + magnetometer attitude along an 800 km orbit (S0 Figs. 1-4)"
_DOC = "docs/studies/wahba-orbit.md"


def run(config: Config, *, quick: bool = False, rng: Any = None, executor: Any = None) -> StudyResult:
    """Run the study (see the module docstring): measure, decide, then tables, text and figures."""
    m = measure(config, rng=rng, executor=executor)
    decided_claims = claims.evaluate(claims.CLAIMS, config, m)
    return StudyResult(
        study="wahba-orbit",
        title=STUDY_TITLE,
        summary=report.summary(config, m, decided_claims[0]),
        config=asdict(config),
        paper=PAPER,
        measured=report.measured(config, m),
        checks=claims.evaluate(claims.CHECKS, config, m),
        claims=decided_claims,
        findings=claims.evaluate(claims.FINDINGS, config, m),
        comparison=report.comparison(config, m),
        differences=report.differences(config, m),
        figures=figures.figures(config, m),
        tables=report.tables(config, m),
        doc=_DOC,
    )


STUDY = Study(
    name="wahba-orbit",
    title=STUDY_TITLE,
    paper="S0",
    config_cls=Config,
    run=run,
    quick={"dt_s": 20.0, "nsga2_every": 10, "pop_size": 16, "n_gen": 12, "n_seeds": 2},
    doc=_DOC,
)
