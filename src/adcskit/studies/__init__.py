"""Paper studies: one module per reproduced experiment, and the framework that runs them.

This package is the framework's public face; the CLI, the report and user code import from
here, never from the private modules behind it:

* registry — :data:`STUDIES`, :data:`PAPERS`, :func:`get_study`, :func:`is_available`,
  :func:`study_names`, :data:`EXPECTED_WALL_S` (``_registry``);
* runner — :func:`resolve_config`, :func:`run_study`, :func:`write_result`,
  :func:`write_json_atomic` (``_runner``);
* verdict — :class:`ClaimSpec`, :class:`FindingSpec`, :class:`Claim`, :class:`Finding`,
  :class:`Reading`, :func:`decide`, :func:`tally`, :data:`OUTCOMES` (``_verdict``);
* results — :class:`Study`, :class:`StudyResult`, :class:`Check`, :class:`Comparison`,
  :func:`new_figure` (``_base``);
* config keys — :data:`NEUTRAL`, :func:`protocol` (field metadata of a study's ``Config``),
  :func:`neutral_keys`, :func:`protocol_keys`, :data:`NOT_PRINTED`, :func:`paper_protocol` (``_base``).
"""

from adcskit.studies._base import (
    NEUTRAL,
    NOT_PRINTED,
    Check,
    Comparison,
    Study,
    StudyResult,
    neutral_keys,
    new_figure,
    paper_protocol,
    protocol,
    protocol_keys,
)
from adcskit.studies._registry import (
    EXPECTED_WALL_S,
    PAPERS,
    STUDIES,
    get_study,
    is_available,
    study_names,
)
from adcskit.studies._runner import resolve_config, run_study, write_json_atomic, write_result
from adcskit.studies._verdict import (
    OUTCOMES,
    Claim,
    ClaimSpec,
    Finding,
    FindingSpec,
    Reading,
    decide,
    tally,
)

__all__ = [
    "EXPECTED_WALL_S",
    "NEUTRAL",
    "NOT_PRINTED",
    "PAPERS",
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
    "neutral_keys",
    "new_figure",
    "paper_protocol",
    "protocol",
    "protocol_keys",
    "resolve_config",
    "run_study",
    "study_names",
    "tally",
    "write_json_atomic",
    "write_result",
]
