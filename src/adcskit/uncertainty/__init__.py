"""Uncertainty: executors for campaigns, sampling and statistics (generic: no paper's loop).

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
    "run_campaign",
    "sample_stats",
]
