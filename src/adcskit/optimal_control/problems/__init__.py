"""Ready-made optimal-control problems (data, not code paths): rendezvous, test problems."""

from adcskit.optimal_control.problems.double_integrator import (
    double_integrator_min_energy,
    double_integrator_min_time,
)

__all__ = ["double_integrator_min_energy", "double_integrator_min_time"]
