"""Control: the single-axis on-off thruster loop of S4 (PID + Schmitt trigger), batch-simulated.

See :mod:`adcskit.control.onoff`.
"""

from adcskit.control.onoff import (
    BACKENDS,
    METRIC_NAMES,
    LoopParams,
    LoopSettings,
    OnOffMetrics,
    OnOffTrace,
    fuel_to_propellant,
    schmitt_trigger,
    simulate_batch,
    simulate_trace,
)

__all__ = [
    "BACKENDS",
    "METRIC_NAMES",
    "LoopParams",
    "LoopSettings",
    "OnOffMetrics",
    "OnOffTrace",
    "fuel_to_propellant",
    "schmitt_trigger",
    "simulate_batch",
    "simulate_trace",
]
