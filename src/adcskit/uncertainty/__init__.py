"""Uncertainty: executors for campaigns, sampling, statistics and requirement statistics
(percentile bounds, exceedance probabilities, sample sizes, requirement tables); generic: no
paper's loop.

S4's robust objective (eq. 10), its stopping rule and the gain tuning built on them live in
:mod:`adcskit.control` (:mod:`adcskit.control.robust`, :mod:`adcskit.control.tuning`).
"""

from adcskit.uncertainty.campaign import CampaignResult, run_campaign
from adcskit.uncertainty.executor import (
    EXECUTOR_SPECS,
    DaskExecutor,
    Executor,
    ProcessExecutor,
    SerialExecutor,
    make_executor,
)
from adcskit.uncertainty.requirements import (
    PercentileBound,
    ProportionInterval,
    Requirement,
    RequirementTable,
    RequirementVerdict,
    check_requirements,
    exceedance_probability,
    parse_requirement,
    percentile_bound,
    proportion_interval,
    read_requirements,
    samples_needed,
)
from adcskit.uncertainty.sampling import (
    Fixed,
    Gaussian,
    SampleStats,
    TruncatedGaussian,
    latin_hypercube,
    sample_stats,
)

__all__ = [
    "CampaignResult",
    "DaskExecutor",
    "EXECUTOR_SPECS",
    "Executor",
    "Fixed",
    "Gaussian",
    "PercentileBound",
    "ProcessExecutor",
    "ProportionInterval",
    "Requirement",
    "RequirementTable",
    "RequirementVerdict",
    "SampleStats",
    "SerialExecutor",
    "TruncatedGaussian",
    "check_requirements",
    "exceedance_probability",
    "latin_hypercube",
    "make_executor",
    "parse_requirement",
    "percentile_bound",
    "proportion_interval",
    "read_requirements",
    "run_campaign",
    "sample_stats",
    "samples_needed",
]
