"""Study ``model-estimation``: S1 Table 1 — joint Kalman state and A-matrix estimation.

Every identification method (QR, GMRES, Bi-CG, CGS, Bi-CGSTAB, LSQR, S1's offline and
online adaptive GMRES, ridge toward the prior, RLS, and an augmented-state EKF that
estimates the inertia ratios) runs S1's joint loop on the *same* simulated manoeuvre, for
the cases ``1dof-random``, ``1dof-step``, ``3dof-random``, ``3dof-sine`` and many seeds.
The error is S1's ``e = 100 ||A_hat - A||_2 / ||A||_2`` at the end of the manoeuvre.

The package: ``paper`` (what S1 prints), ``config`` (:class:`Config`, the methods and
readings), ``experiment`` (the models, :func:`~.experiment.measure` and its frozen records),
``claims`` (claims, findings and checks, decided by the verdict framework), ``figures`` and
``report`` (pure functions of the records); :func:`run` only wires them together. The models
are described in :mod:`adcskit.studies.model_estimation.experiment` and
``docs/studies/model-estimation.md``.
"""

from __future__ import annotations

import numpy as np

from adcskit.studies._base import Study, StudyResult
from adcskit.studies.model_estimation import claims, figures, report
from adcskit.studies.model_estimation.config import METHODS, PRIOR_BASELINES, READINGS, Config  # noqa: F401
from adcskit.studies.model_estimation.experiment import (  # noqa: F401 (benchmark)
    _method_options,
    build_case,
    inertia_scales,
    measure,
)
from adcskit.studies.model_estimation.paper import A13, AXIS_POLES, B13, CASES, PAPER, PAPER_TABLE  # noqa: F401

__all__ = ["Config", "run", "STUDY", "CASES", "METHODS", "build_case"]

def run(config: Config, *, quick: bool = False, rng=None, executor=None) -> StudyResult:
    """Run the study (see the module docstring and ``docs/studies/model-estimation.md``)."""
    from adcskit.uncertainty.executor import SerialExecutor

    cfg = config
    gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    m = measure(cfg, gen, executor or SerialExecutor())
    decided_claims = claims.evaluate(claims.CLAIMS, cfg, m)
    return StudyResult(
        study="model-estimation",
        title="S1 Table 1: joint Kalman state + A-matrix estimation",
        summary=report.summary(cfg, m, decided_claims),
        config={},
        paper=PAPER,
        measured=report.measured(cfg, m),
        checks=claims.evaluate(claims.CHECKS, cfg, m),
        claims=decided_claims,
        findings=claims.evaluate(claims.FINDINGS, cfg, m),
        comparison=report.comparison(cfg, m),
        differences=report.DIFFERENCES,
        figures=figures.figures(cfg, m),
        tables=report.tables(cfg, m),
        doc="docs/studies/model-estimation.md",
    )


STUDY = Study(
    name="model-estimation",
    title="S1 Table 1: joint Kalman state + A-matrix estimation (QR, Krylov, adaptive GMRES, baselines)",
    paper="S1 — adaptive GMRES for joint attitude-state and model estimation",
    config_cls=Config,
    run=run,
    quick={"n_seeds": 2, "n_steps": 100},
    doc="docs/studies/model-estimation.md",
)
