"""Study ``closed-loop``: the five pieces in one 3-axis loop, answered by Monte-Carlo campaigns.

The papers leave open how their pieces behave together. With :mod:`adcskit.simulation`
(nonlinear rigid body, gravity gradient and disturbance torques, thrusters with S4's lag and
delay, sensors, Wahba / MEKF, guidance, S4's Schmitt loop, allocation) and
:func:`adcskit.simulation.simulate_wheels` (reaction wheels, magnetorquers, mode sequences) we answer six
questions as findings, each decided over ``n_seeds`` independent seeds of the whole pipeline
(layout design, dispersions, noise) with intervals:

1. GEO (S3 inertia, gravity gradient + a solar-pressure-like torque): does the S3-optimised
   6-thruster layout use less propellant than S3's reference layout in closed loop (slew +
   hold), with S4's controller, under both allocations, and with one thruster failed?
2. LEO (S0's orbit, inertia and bounded sensor errors): does S0's robust min-max interval
   determination, or the MEKF, give better closed-loop pointing than the per-epoch q-method?
3. S4's spacecraft in 3 axes under S4's dispersions + sensor noise: do S4's robust gains
   (Table 6, all four uncertainties) reduce the spread of the pointing error against the
   nominal gains (Table 4)?
4. GEO: does tracking a time-optimal slew profile (from :mod:`adcskit.optimal_control`)
   settle sooner and use less propellant than a step command?
5. S4's spacecraft, orbit, disturbance, sensors and 15 deg step: do reaction wheels (4-wheel
   pyramid, quaternion PD, S4's torque level per axis) point better after settling than S4's
   on-off thruster loop (p99 over samples of the largest error in S4's last 10 s)? Its
   requirement table for both loops is the ``q5_requirements`` table and part of the summary.
6. The 12U reference smallsat of :class:`adcskit.simulation.WheelScenario` (4 pyramid wheels,
   3 magnetorquers; detumble -> sun acquisition -> nadir pointing over three orbits) under the
   reference dispersions: does it meet its sign-off requirement table at 95 % confidence, per
   seed one campaign of ``q6_n_samples`` samples? A table with an inconclusive row (too few
   samples to bound it) is a tie, neither met nor failed; two readings: each row at its own
   confidence, or the whole table at once (Bonferroni). The tables ``q6_requirements`` and
   ``q6_seeds``, the summary and the envelope figure ``q6-mode-sequence-envelopes`` show it.

The package: ``paper`` (the printed numbers the scenarios use), ``config`` (:class:`Config`),
``experiment`` (:func:`~.experiment.measure` and its frozen records), ``claims`` (findings and
checks, decided by the verdict framework), ``figures`` and ``report`` (pure functions of the
records); :func:`run` only wires them together.

References
----------
S0 (LEO scenario, bounded errors), S2 (pseudospectral time-optimal guidance), S3 (GEO
spacecraft, layouts, allocation), S4 (loop, gains, dispersions); Lefferts, Markley & Shuster
(1982) for the MEKF; Wie 2008, §7.3 (quaternion feedback, Q5 and Q6); Stickler & Alfriend 1976
(B-dot), Camillo & Markley 1980 (magnetic unloading), Wilks 1941 and Clopper & Pearson 1934 (the
sign-off table's bounds, Q6).
"""

from __future__ import annotations

from typing import Any

from adcskit.studies._base import Study, StudyResult
from adcskit.studies.closed_loop import claims, figures, report
from adcskit.studies.closed_loop.config import Config
from adcskit.studies.closed_loop.experiment import measure

__all__ = ["Config", "run", "STUDY"]


def run(config: Config, *, quick: bool = False, rng: Any = None, executor: Any = None) -> StudyResult:
    """Run the six closed-loop campaigns (see the package docstring): measure, decide, report."""
    cfg = config
    m = measure(cfg, rng=rng, executor=executor)
    findings = claims.evaluate(claims.FINDINGS, cfg, m)
    return StudyResult(
        study="closed-loop",
        title=report.TITLE,
        summary=report.summary(cfg, m, findings),
        measured=report.measured(m),
        findings=findings,
        checks=claims.evaluate(claims.CHECKS, cfg, m),
        figures=figures.figures(m),
        tables=report.tables(m),
        differences=list(report.DIFFERENCES),
    )


STUDY = Study(
    name="closed-loop",
    title=report.TITLE,
    paper="S0-S4 together (the answers the papers leave open)",
    config_cls=Config,
    run=run,
    quick={"n_seeds": 2, "n_samples": 48, "layout_pop": 16, "layout_gens": 25, "record_samples": 8,
           "geo_t_final_s": 40.0, "leo_t_final_s": 40.0, "leo_window_s": 20.0, "s4_t_final_s": 20.0, "q6_n_samples": 24},
    doc="docs/studies/closed-loop.md",
)
