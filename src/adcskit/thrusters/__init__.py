"""Thrusters: geometry, allocation, pulse/fuel model and layout design (S3).

* :mod:`~adcskit.thrusters.geometry` — thrusters from S3's angles or vectors, torque/force
  matrices, the positive-span controllability test;
* :mod:`~adcskit.thrusters.allocation` — ``allocate`` with ``pinv-redistribute`` (S3),
  ``nnls`` and ``lp-min-fuel``, batched over demands;
* :mod:`~adcskit.thrusters.pulse` — pulse width, minimum impulse bit (with the lever arm),
  minimum reachable error, fuel;
* :mod:`~adcskit.thrusters.layout` — mounting faces as data, S3's fitness (eq. 18), layout
  design on pymoo GA / DE;
* :mod:`~adcskit.thrusters.reference` — S3's reference layout and manoeuvre (data used by the
  simulator and the studies, imported downward).
"""

from adcskit.thrusters.allocation import ALLOCATION_METHODS, AllocationResult, allocate
from adcskit.thrusters.geometry import (
    Controllability,
    Thruster,
    ThrusterSet,
    angles_from_direction,
    check_controllability,
    direction_from_angles,
    torque_matrix,
)
from adcskit.thrusters.layout import (
    DE_STRATEGIES,
    DEFAULT_WEIGHTS,
    DESIGN_ALGORITHMS,
    LayoutResult,
    LayoutScore,
    MountingFace,
    box_faces,
    decode_layout,
    design_layout,
    score_layout,
)
from adcskit.thrusters.pulse import (
    fuel_mass,
    manoeuvre_fuel,
    min_impulse_bit,
    min_reachable_error,
    pulse_width,
    realisable_pulses,
)
from adcskit.thrusters.reference import S3_REFERENCE_A, s3_manoeuvre_demands

__all__ = [
    "ALLOCATION_METHODS", "AllocationResult", "allocate",
    "Controllability", "Thruster", "ThrusterSet", "angles_from_direction",
    "check_controllability", "direction_from_angles", "torque_matrix",
    "DE_STRATEGIES", "DEFAULT_WEIGHTS", "DESIGN_ALGORITHMS", "LayoutResult", "LayoutScore",
    "MountingFace", "box_faces", "decode_layout", "design_layout", "score_layout",
    "fuel_mass", "manoeuvre_fuel", "min_impulse_bit", "min_reachable_error", "pulse_width", "realisable_pulses",
    "S3_REFERENCE_A", "s3_manoeuvre_demands",
]
