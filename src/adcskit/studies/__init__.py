"""Paper studies: one module per reproduced experiment (see :mod:`adcskit.studies._registry`)."""

from adcskit.studies._base import Check, Comparison, Study, StudyResult, new_figure
from adcskit.studies._registry import STUDIES, get_study, is_available, study_names
from adcskit.studies._runner import resolve_config, run_study, write_result
from adcskit.studies._verdict import (
    OUTCOMES,
    Claim,
    ClaimSpec,
    Finding,
    FindingSpec,
    Reading,
    decide,
)

__all__ = [
    "STUDIES",
    "Check",
    "Claim",
    "ClaimSpec",
    "Finding",
    "FindingSpec",
    "OUTCOMES",
    "Reading",
    "decide",
    "Comparison",
    "Study",
    "StudyResult",
    "get_study",
    "is_available",
    "new_figure",
    "resolve_config",
    "run_study",
    "study_names",
    "write_result",
]
