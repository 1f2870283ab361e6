"""Uncertainty: executors for campaigns, sampling, robust objectives and statistics."""

from adcskit.uncertainty.executor import (
    EXECUTOR_SPECS,
    DaskExecutor,
    Executor,
    ProcessExecutor,
    SerialExecutor,
    make_executor,
)

__all__ = [
    "EXECUTOR_SPECS",
    "DaskExecutor",
    "Executor",
    "ProcessExecutor",
    "SerialExecutor",
    "make_executor",
]
