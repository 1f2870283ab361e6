"""Ready-made optimal-control problems (data, not code paths): rendezvous, test problems."""

from adcskit.optimal_control.problems.double_integrator import (
    double_integrator_min_energy,
    double_integrator_min_time,
)
from adcskit.optimal_control.problems.rendezvous import RendezvousParams, rendezvous_problem

__all__ = ["RendezvousParams", "double_integrator_min_energy", "double_integrator_min_time", "rendezvous_problem"]
