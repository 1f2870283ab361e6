"""The study registry: CLI names -> modules that define ``STUDY``.

Names are listed here so that ``adcskit list`` needs no heavy imports; a study module that
does not exist yet is listed as not available and skipped by ``adcskit reproduce``.
"""

from __future__ import annotations

import importlib
import importlib.util
from dataclasses import dataclass

from adcskit._validation import check_choice
from adcskit.studies._base import Study

__all__ = ["StudyInfo", "STUDIES", "get_study", "is_available", "study_names"]


@dataclass(frozen=True, slots=True)
class StudyInfo:
    name: str
    module: str
    paper: str
    description: str


STUDIES: dict[str, StudyInfo] = {
    info.name: info
    for info in (
        StudyInfo(
            "wahba-table1",
            "adcskit.studies.wahba_table1",
            "S0",
            "Robust Wahba, one epoch with ±20 % interval noise: q-method vs min-max vs NSGA-II vs worst case (S0 Table 1)",
        ),
        StudyInfo(
            "wahba-orbit",
            "adcskit.studies.wahba_orbit",
            "S0",
            "Sun sensor + magnetometer attitude along an 800 km orbit, point vs robust solvers (S0 Figs 1-4)",
        ),
        StudyInfo(
            "model-estimation",
            "adcskit.studies.model_estimation",
            "S1",
            "Joint Kalman state + A-matrix identification: QR, Krylov, adaptive GMRES, ridge, RLS (S1 Table 1)",
        ),
        StudyInfo(
            "rendezvous",
            "adcskit.studies.rendezvous",
            "S2",
            "Time-optimal 6-DOF rendezvous by Gauss pseudospectral collocation, costates, Hamiltonian (S2 Table 4)",
        ),
        StudyInfo(
            "thruster-layout",
            "adcskit.studies.thruster_layout",
            "S3",
            "GEO thruster layout design with GA vs DE, allocation and fuel vs a reference layout (S3 Tables 5-8)",
        ),
        StudyInfo(
            "onoff-schmitt",
            "adcskit.studies.onoff_schmitt",
            "S4",
            "On-off thruster loop: Schmitt trigger threshold sweep, step response, limit cycle (S4 Figs 2-7)",
        ),
        StudyInfo(
            "onoff-tuning",
            "adcskit.studies.onoff_tuning",
            "S4",
            "Deterministic NSGA-II and robust GA tuning of the PID gains under uncertainty (S4 Tables 4-6)",
        ),
        StudyInfo(
            "closed-loop",
            "adcskit.studies.closed_loop",
            "S0-S4",
            "Closed-loop 3-axis ADCS Monte-Carlo: layouts, MEKF vs q-method, robust gains, optimal slews",
        ),
    )
}


def study_names() -> list[str]:
    """All registered study names, in report order."""
    return list(STUDIES)


def is_available(name: str) -> bool:
    """Whether the study's module is present in this installation."""
    check_choice("study", name, STUDIES)
    return importlib.util.find_spec(STUDIES[name].module) is not None


def get_study(name: str) -> Study:
    """Import and return the :class:`Study` registered as ``name``.

    Raises
    ------
    InputError
        If ``name`` is not registered (the message lists the valid names) or its module is
        not available yet.
    """
    from adcskit.errors import InputError

    check_choice("study", name, STUDIES)
    if not is_available(name):
        raise InputError(f"study {name!r} is registered but not implemented in this version")
    module = importlib.import_module(STUDIES[name].module)
    study = module.STUDY
    if study.name != name:  # programming error in the study module
        raise RuntimeError(f"{STUDIES[name].module}.STUDY.name is {study.name!r}, expected {name!r}")
    return study
