"""Uncertainty: executors for campaigns, sampling, robust objectives, statistics and requirement
statistics (percentile bounds, exceedance probabilities, sample sizes, requirement tables)."""

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
from adcskit.uncertainty.robust import mean_change_converged, robust_objective, weights_from_ratio
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
    "mean_change_converged",
    "parse_requirement",
    "percentile_bound",
    "proportion_interval",
    "read_requirements",
    "robust_objective",
    "run_campaign",
    "sample_stats",
    "samples_needed",
    "weights_from_ratio",
]
