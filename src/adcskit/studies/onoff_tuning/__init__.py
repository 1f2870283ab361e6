"""Study ``onoff-tuning``: deterministic (NSGA-II) vs robust (GA) PID tuning of the on-off loop (S4).

Reproduces S4 Tables 4-6 and Figs. 9-21:

1. deterministic two-objective tuning (S4 eq. 9) → Pareto front of error vs fuel (Fig. 9),
   step responses of its minimum-error and minimum-fuel points (Fig. 10);
2. robust GA tuning (S4 eq. 10, population 70, S4 stopping rule with a generation cap) for
   each uncertainty alone — inertia, thrust level, disturbance, delay (S4 Table 5) — and all
   four together, at the printed weight ratios w₂/w₁ = 25, 22, 15, 10, 180 (Table 6), plus
   a sweep of the ratio for the all-four case (Figs. 12-14);
3. evaluation of the deterministic and robust gains with 10 000 Monte-Carlo (LHS) runs each
   (the campaigns go through the executor and can resume), and mean/std of |error| vs the
   input standard deviation (Figs. 15-19);
4. the command-rate study at 50/200/1000 Hz (Figs. 20-21);
5. the printed gain order: Tables 4 and 6 are simulated in both readings, (K_p, K_d, K_i)
   and (K_p, K_i, K_d).

References
----------
S4, eqs. (9)-(10), Tables 3-6, Figs. 9-21.
"""

from __future__ import annotations

from dataclasses import replace

from adcskit._progress import status
from adcskit._validation import as_rng
from adcskit.studies._base import Study, StudyResult
from adcskit.studies.onoff_tuning import claims as _claims
from adcskit.studies.onoff_tuning import figures as _figures
from adcskit.studies.onoff_tuning import report as _report
from adcskit.studies.onoff_tuning.config import _PAPER_SCALE_KEYS, Config
from adcskit.studies.onoff_tuning.experiment import (  # noqa: F401 (tests)
    _ga_settings,
    _seed_pipeline,
    _seed_task,
    measure,
    stored_claim_gas,
)
from adcskit.studies.onoff_tuning.ga_store import resolve_store
from adcskit.studies.onoff_tuning.paper import CASES, PAPER, PAPER_TABLE4, PAPER_TABLE6, _reorder  # noqa: F401
from adcskit.studies.onoff_tuning.report import _front_note, _front_vs_paper  # noqa: F401 (tests)

__all__ = ["Config", "run", "resolve_paper_scale", "STUDY", "PAPER_TABLE4", "PAPER_TABLE6"]


def resolve_paper_scale(config: Config, seed: int) -> Config:
    """The config a run with root seed ``seed`` uses: S4's protocol (``paper_scale=True``) when
    ``paper_scale_from_store`` is set, ``paper_scale`` is false, the GA sizes are ours and the GA
    store (``ga_store``; ``"auto"``: the runs shipped with adcskit) holds every claim GA of that
    paper-scale run; else ``config`` unchanged.

    The study's claims are then decided at S4's protocol from stored GA runs (their evaluations,
    10 000 runs per gain set, and everything else computed in the run), in minutes instead of
    hours; without a complete store the run is our reduced protocol, as before.
    """
    if not config.paper_scale_from_store or config.paper_scale:
        return config
    ours = Config()
    if any(getattr(config, k) != getattr(ours, k) for k in _PAPER_SCALE_KEYS):
        return config  # the user chose GA sizes: keep them
    paper = replace(config, paper_scale=True)
    store = resolve_store(paper.ga_store, True)
    if store is None:
        return config
    n_stored, n_all = stored_claim_gas(paper, seed, store)
    if n_stored < n_all:
        status(f"onoff-tuning: {n_stored} of the {n_all} paper-scale claim GAs are stored ({store.directory}); "
               "running our reduced protocol")
        return config
    status(f"onoff-tuning: all {n_all} paper-scale claim GAs stored ({store.directory}): S4's protocol, GAs replayed")
    return paper


def run(config: Config, *, quick: bool = False, rng=None, executor=None) -> StudyResult:
    """Run the study (see the module docstring)."""
    m = measure(config, as_rng(rng), executor)
    claims = _claims.claims(config, m)
    return StudyResult(
        study="onoff-tuning",
        title=STUDY.title,
        summary=_report.summary(config, m, claims, quick),
        paper=PAPER,
        measured={**_report.measured(m), "mean_ratio": _claims.mean_ratio_table(config, m)},
        checks=_claims.checks(config, m),
        claims=claims,
        findings=_claims.findings(config, m),
        comparison=_report.comparison(config, m),
        differences=_report.differences(config, m),
        figures=_figures.figures(config, m),
        tables=_report.tables(m),
        doc=STUDY.doc,
    )


STUDY = Study(
    name="onoff-tuning",
    title="Deterministic NSGA-II and robust GA tuning of the on-off loop's PID gains (S4 Tables 4-6, Figs 9-21)",
    paper="S4 — Bohlouri & Jalali-Naini, robust optimisation of on-off thruster attitude control",
    config_cls=Config,
    run=run,
    resolve=resolve_paper_scale,
    quick={
        "n_seeds": 2,
        "nsga_pop": 32,
        "nsga_gen": 8,
        "ga_max_gen": 3,
        "n_lhs": 6,
        "sweep_ratios": (10.0,),
        "sweep_cases_ratios": (10.0,),
        "sweep_max_gen": 2,
        "sweep_cases_max_gen": 1,
        "sweep_cases_n_lhs": 4,
        "n_mc_ratio_cases": 40,
        "n_mc": 300,
        "std_factors": (0.5, 1.0),
        "n_mc_sweep": 60,
        "n_mc_rate": 60,
        "n_mc_order": 60,
        "task_size": 100,
    },
    doc="docs/studies/onoff-tuning.md",
)
