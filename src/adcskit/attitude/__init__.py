"""Attitude representations and algebra: quaternion, DCM, MRP, Euler sequences, kinematics.

One convention throughout (``docs/architecture.md``, "Conventions"): scalar-last unit quaternion ``q = [e, q4]``,
canonical sign ``q4 >= 0``, attitude matrix ``A(q)`` mapping reference-frame components to
body-frame components (``b = A r``); ``A(p ⊗ q) = A(p) A(q)``. Every function accepts one item
or a batch (leading axis ``N``) and returns the same rank. See ``docs/conventions.md``.
"""

from adcskit.attitude.euler import EULER_SEQUENCES, dcm_to_euler, euler_to_dcm
from adcskit.attitude.kinematics import mrp_b_matrix, mrp_kinematics, quat_kinematics, xi_matrix
from adcskit.attitude.mrp import (
    dcm_to_mrp,
    mrp_shadow,
    mrp_switch,
    mrp_to_dcm,
    mrp_to_quat,
    quat_to_mrp,
)
from adcskit.attitude.quaternion import (
    dcm_to_quat,
    error_angle,
    from_scipy,
    quat_canonical,
    quat_from_scalar_first,
    quat_inverse,
    quat_multiply,
    quat_normalize,
    quat_to_dcm,
    quat_to_scalar_first,
    random_quat,
    skew,
    to_scipy,
)

__all__ = [
    "EULER_SEQUENCES",
    "dcm_to_euler",
    "dcm_to_mrp",
    "dcm_to_quat",
    "error_angle",
    "euler_to_dcm",
    "from_scipy",
    "mrp_b_matrix",
    "mrp_kinematics",
    "mrp_shadow",
    "mrp_switch",
    "mrp_to_dcm",
    "mrp_to_quat",
    "quat_canonical",
    "quat_from_scalar_first",
    "quat_inverse",
    "quat_kinematics",
    "quat_multiply",
    "quat_normalize",
    "quat_to_dcm",
    "quat_to_mrp",
    "quat_to_scalar_first",
    "random_quat",
    "skew",
    "to_scipy",
    "xi_matrix",
]
