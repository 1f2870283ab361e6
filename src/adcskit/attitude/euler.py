"""Euler-angle sequences (all 12: six Tait–Bryan, six proper Euler).

A sequence ``seq = "a1 a2 a3"`` (letters ``XYZ`` or digits ``123``, e.g. ``"ZYX"`` = ``"321"``)
means successive rotations of the *body* frame about its own axes a1, then a2, then a3
(intrinsic), by angles ``(θ1, θ2, θ3)``. The attitude matrix is

``A = R_a3(θ3) R_a2(θ2) R_a1(θ1)``,  with frame rotations such as
``R_X(φ) = [[1, 0, 0], [0, cos φ, sin φ], [0, −sin φ, cos φ]]``,

(Markley & Crassidis 2014, §2.9; Schaub & Junkins 2018, §3.2). Equivalently
``A = Rotation.from_euler(seq, angles).inv().as_matrix()`` in scipy with an upper-case
(intrinsic) ``seq``. Lower-case letters are accepted and mean the same intrinsic sequence —
adcskit has no extrinsic form, to avoid scipy's case-sensitive trap.

:func:`dcm_to_euler` uses scipy's robust algorithm (Bernardes & Viollet 2022): angles 1 and 3
in ``[−π, π]``, angle 2 in ``[−π/2, π/2]`` (Tait–Bryan) or ``[0, π]`` (proper Euler). At a
gimbal lock the split between angles 1 and 3 is not unique; angle 3 is set to 0 and a
``UserWarning`` is suppressed (the returned angles still reproduce ``A``).

References
----------
Markley & Crassidis (2014), §2.9. Schaub & Junkins (2018), §3.2.
E. Bernardes and S. Viollet, "Quaternion to Euler angles conversion: a direct, general and
computationally efficient method", PLOS ONE 17(11), 2022.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from adcskit._validation import short_repr
from adcskit.attitude import _kernels as _k
from adcskit.attitude._checks import dcms, out, vectors
from adcskit.errors import InputError

__all__ = ["EULER_SEQUENCES", "dcm_to_euler", "euler_to_dcm"]

EULER_SEQUENCES: tuple[str, ...] = (
    "XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX",  # Tait–Bryan
    "XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ",  # proper Euler
)
_DIGITS = str.maketrans("123", "XYZ")


def _seq(seq: Any) -> str:
    s = seq.upper().translate(_DIGITS) if isinstance(seq, str) else None
    if s not in EULER_SEQUENCES:
        raise InputError(
            "seq must be one of the 12 Euler sequences "
            f"{', '.join(EULER_SEQUENCES)} (or digits, e.g. '321'); got {short_repr(seq)}"
        )
    return s


def euler_to_dcm(angles: Any, seq: str) -> np.ndarray:
    """Attitude matrix of intrinsic Euler angles.

    Parameters
    ----------
    angles : array_like, shape (3,) or (N, 3), rad
        ``(θ1, θ2, θ3)`` about the axes of ``seq`` in order.
    seq : str
        One of :data:`EULER_SEQUENCES` (or digits, ``"321"``).

    Returns
    -------
    numpy.ndarray, shape (3, 3) or (N, 3, 3)
        ``A = R_a3(θ3) R_a2(θ2) R_a1(θ1)`` (reference → body).

    Examples
    --------
    >>> import numpy as np
    >>> A = euler_to_dcm([np.pi / 2, 0.0, 0.0], "ZYX")   # yaw 90 deg
    >>> (A @ [1.0, 0.0, 0.0]).round(12)                 # reference x seen in the body frame
    array([ 0., -1.,  0.])
    """
    s = _seq(seq)
    arr, batched = vectors("angles", angles)
    ax = ["XYZ".index(c) for c in s]
    A = _k.elementary(ax[2], arr[:, 2]) @ _k.elementary(ax[1], arr[:, 1]) @ _k.elementary(ax[0], arr[:, 0])
    return out(A, batched)


def dcm_to_euler(A: Any, seq: str) -> np.ndarray:
    """Intrinsic Euler angles (rad) of attitude matrix/matrices ``A`` for sequence ``seq``.

    Returns
    -------
    numpy.ndarray, shape (3,) or (N, 3), rad
        See the module docstring for the angle ranges and the gimbal-lock rule.

    Examples
    --------
    >>> import numpy as np
    >>> A = euler_to_dcm(np.radians([30.0, -5.0, 10.0]), "ZYX")
    >>> np.degrees(dcm_to_euler(A, "ZYX")).round(6)
    array([30., -5., 10.])
    """
    s = _seq(seq)
    arr, batched = dcms("A", A)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        ang = Rotation.from_matrix(np.transpose(arr, (0, 2, 1))).as_euler(s)
    return out(np.asarray(ang, dtype=float).reshape(-1, 3), batched)
