"""Dynamics: rigid body (Euler's equations), gravity gradient, linearised LVLH attitude model,
Hill/Clohessy–Wiltshire relative motion, discretisation (zero-order hold, Crank–Nicolson)."""

from adcskit.dynamics.discretize import DISCRETIZATION_METHODS, discretize
from adcskit.dynamics.gravity_gradient import gravity_gradient_torque, orbit_rate
from adcskit.dynamics.lvlh import lvlh_attitude_model, lvlh_second_order
from adcskit.dynamics.relative_motion import cw_matrices, cw_stm
from adcskit.dynamics.rigid_body import (
    AttitudeTrajectory,
    as_inertia,
    euler_equations,
    propagate_attitude,
)

__all__ = [
    "DISCRETIZATION_METHODS",
    "AttitudeTrajectory",
    "as_inertia",
    "cw_matrices",
    "cw_stm",
    "discretize",
    "euler_equations",
    "gravity_gradient_torque",
    "lvlh_attitude_model",
    "lvlh_second_order",
    "orbit_rate",
    "propagate_attitude",
]
