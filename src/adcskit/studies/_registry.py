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

__all__ = ["EXPECTED_WALL_S", "PAPERS", "Paper", "StudyInfo", "STUDIES", "get_study", "is_available", "study_names"]


@dataclass(frozen=True, slots=True)
class Paper:
    """Bibliographic reference of a source paper, as printed in it.

    Fields a paper does not print are empty (``missing`` says which); nothing is guessed.
    """

    id: str
    authors: str
    title: str
    journal: str = ""
    volume: str = ""
    issue: str = ""
    pages: str = ""
    year: str = ""
    doi: str = ""
    language: str = "Persian, English abstract"
    missing: str = ""

    def citation(self) -> str:
        """One-line reference: authors, "title", journal vol(issue), pages, year. DOI."""
        parts = [f"{self.authors}, \u201c{self.title}\u201d"]
        if self.journal:
            j = self.journal
            if self.volume:
                j += f" {self.volume}"
                if self.issue:
                    j += f"({self.issue})"
            parts.append(j)
        if self.pages:
            parts.append(f"pp. {self.pages}")
        if self.year:
            parts.append(self.year)
        text = ", ".join(parts) + "."
        if self.doi:
            text += f" doi:{self.doi}"
        return text


#: The five source papers (S0..S4). Five papers give seven paper studies (plus our closed loop,
#: eight in all) because S0 (robust Wahba)
#: reports two experiments (one epoch, Table 1; an orbit, Figs 1-4) and S4 (on-off control)
#: two (the Schmitt-trigger loop itself, Figs 2-7; the gain tuning, Tables 4-6).
PAPERS: dict[str, Paper] = {
    p.id: p
    for p in (
        Paper(
            "S0",
            "H. Ghadiri, R. Esmaelzadeh, R. Zardashti",
            "Robust optimal attitude determination of the satellite based on the min-max optimization algorithm",
            journal="Journal of Space Science, Technology and Applications",
            volume="3",
            issue="2",
            pages="126-139",
            year="2024",
            doi="10.22034/jssta.2023.412482.1139",
        ),
        Paper(
            "S1",
            "M. Navabi, Sh. Hosseini",
            "A new online meta-heuristic adaptive GMRES method to estimate the attitude and the model of a satellite",
            missing="journal, volume, pages, year and DOI are not printed in the source text",
        ),
        Paper(
            "S2",
            "S. M. Mousavi, S. M. Esmailifar, M. Chiniforoushan",
            "Time-optimal control of spacecraft rotational and translational dynamics in orbital rendezvous maneuver",
            journal="Journal of Space Science, Technology and Applications",
            volume="1",
            issue="2",
            pages="147-166",
            year="2022",
            doi="10.22034/jssta.2022.315191.1038",
        ),
        Paper(
            "S3",
            "A. Kosari, S. Kaviri, B. Moshiri, M. Fakoor",
            "Design of optimal thruster configuration for attitude control of geostationary satellite",
            missing="journal, volume, pages, year and DOI are not printed in the source text",
        ),
        Paper(
            "S4",
            "V. Bohlouri, S. H. Jalali Naini",
            "Robust optimization of satellite attitude control with thruster actuators based on a combined objective function",
            journal="Journal of Space Science and Technology (Persian)",
            volume="10",
            issue="4",
            year="Winter 1396 SH (2018)",
            missing=(
                "pages (page 56 is printed in a running header) and DOI are not printed in the source text; "
                "the English title is truncated there and is translated from the Persian title"
            ),
        ),
    )
}


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
            "Closed-loop 3-axis ADCS Monte-Carlo: layouts, MEKF vs q-method, robust gains, optimal slews, wheels vs "
            "thrusters, the 12U reference mode sequence signed off",
        ),
    )
}


#: Expected wall time (s) of each study at full settings, the scheduling hint of
#: ``adcskit reproduce --jobs N`` (longest first, so that the workers finish together; a study
#: without an entry counts as 0 s). From docs/benchmarks.md, "Full reproduction", the Xeon
#: instance: the per-study "done in" wall times of the ``--jobs 2`` run of ``fdb03c9``
#: (2026-12-03 03:30 UTC, each study on one of the 2 cores since the cores are shared out).
#: The order they give is also the better one on the Zen 5 instance's times. Only the order
#: matters; the hint never changes a result.
EXPECTED_WALL_S: dict[str, float] = {
    "wahba-table1": 367.2,
    "wahba-orbit": 153.9,
    "model-estimation": 147.6,
    "rendezvous": 127.3,
    "thruster-layout": 403.8,
    "onoff-schmitt": 6.0,
    "onoff-tuning": 404.1,
    "closed-loop": 660.6,
}


def study_names() -> list[str]:
    """All registered study names, in report order.

    Examples
    --------
    >>> study_names()[:2]
    ['wahba-table1', 'wahba-orbit']
    """
    return list(STUDIES)


def is_available(name: str) -> bool:
    """Whether the study's module is present in this installation.

    Examples
    --------
    >>> is_available("onoff-tuning")
    True
    """
    check_choice("study", name, STUDIES)
    return importlib.util.find_spec(STUDIES[name].module) is not None


def get_study(name: str) -> Study:
    """Import and return the :class:`Study` registered as ``name``.

    Raises
    ------
    InputError
        If ``name`` is not registered (the message lists the valid names) or its module is
        not available yet.

    Examples
    --------
    >>> get_study("rendezvous").paper
    'S2'
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
