"""Uncertainty: executors for campaigns, sampling, robust objectives and statistics."""

from adcskit.uncertainty.campaign import CampaignResult, run_campaign
from adcskit.uncertainty.executor import (
    EXECUTOR_SPECS,
    DaskExecutor,
    Executor,
    ProcessExecutor,
    SerialExecutor,
    make_executor,
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
    "EXECUTOR_SPECS",
    "CampaignResult",
    "DaskExecutor",
    "Executor",
    "Fixed",
    "Gaussian",
    "ProcessExecutor",
    "SampleStats",
    "SerialExecutor",
    "TruncatedGaussian",
    "latin_hypercube",
    "make_executor",
    "mean_change_converged",
    "robust_objective",
    "run_campaign",
    "sample_stats",
    "weights_from_ratio",
]
