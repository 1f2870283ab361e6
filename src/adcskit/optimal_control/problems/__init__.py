"""Ready-made optimal-control problems (data, not code paths): rendezvous, test problems."""

from adcskit.optimal_control.problems.double_integrator import (
    double_integrator_min_energy,
    double_integrator_min_time,
)
from adcskit.optimal_control.problems.launch import launch_ascent, launch_ascent_guess
from adcskit.optimal_control.problems.rendezvous import RendezvousParams, rendezvous_problem
from adcskit.optimal_control.problems.singular import (
    bang_singular_bang,
    bang_singular_bang_objective,
    rest_to_rest_mixed_path,
    rest_to_rest_mixed_path_time,
)
from adcskit.optimal_control.problems.standard import (
    brachistochrone,
    brachistochrone_time,
    bryson_denham,
    free_flying_robot,
    goddard_rocket,
    hypersensitive,
    orbit_raising,
    oscillator_min_time,
    oscillator_min_time_reference,
    reference_objective,
    rigid_body_reorientation,
    robot_arm,
)

__all__ = [
    "RendezvousParams",
    "bang_singular_bang",
    "bang_singular_bang_objective",
    "rest_to_rest_mixed_path",
    "rest_to_rest_mixed_path_time",
    "brachistochrone",
    "brachistochrone_time",
    "bryson_denham",
    "double_integrator_min_energy",
    "double_integrator_min_time",
    "free_flying_robot",
    "goddard_rocket",
    "hypersensitive",
    "launch_ascent",
    "launch_ascent_guess",
    "oscillator_min_time",
    "oscillator_min_time_reference",
    "orbit_raising",
    "reference_objective",
    "rendezvous_problem",
    "rigid_body_reorientation",
    "robot_arm",
]
