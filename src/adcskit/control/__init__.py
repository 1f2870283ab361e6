"""Control: the single-axis on-off thruster loop of S4 (PID + Schmitt trigger), batch-simulated,
and its tuning.

See :mod:`adcskit.control.onoff` (the loop), :mod:`adcskit.control.robust` (S4 eq. 10's robust
objective and stopping rule) and :mod:`adcskit.control.tuning` (S4 eqs. 9-10: NSGA-II and
robust GA tuning of the PID gains, Monte-Carlo evaluation).
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
from adcskit.control.robust import mean_change_converged, robust_objective, weights_from_ratio

__all__ = [
    "BACKENDS",
    "METRIC_NAMES",
    "LoopParams",
    "LoopSettings",
    "OnOffMetrics",
    "OnOffTrace",
    "fuel_to_propellant",
    "mean_change_converged",
    "robust_objective",
    "schmitt_trigger",
    "simulate_batch",
    "simulate_trace",
    "weights_from_ratio",
]
