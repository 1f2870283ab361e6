"""S3's reference data used by several layers: the reference layout and the manoeuvre.

The thruster-layout study (S3), the closed-loop simulator's default thrusters and the
closed-loop study all use them; they live here, in the lowest package that needs them, and
are imported downward (``simulation`` and ``studies`` import ``thrusters``, never the reverse).

References
----------
S3 §6 (reference 6-thruster layout of Servidia & Sanchez Pena 2000, S3 ref. [6]).
"""

from __future__ import annotations

import math

import numpy as np

from adcskit._validation import check_positive

__all__ = ["S3_REFERENCE_A", "s3_manoeuvre_demands"]

#: S3 §6: reference 6-thruster layout of Servidia & Sanchez Pena (S3 ref. [6]), torque matrix
#: (3, 6) as printed (unit arm and unit force per column).
S3_REFERENCE_A = np.array([[-1, 1, -1, 1, 0, 0], [0, 0, 0, 0, 1, -1], [-1, 1, 1, -1, 0, 0]], float)


def s3_manoeuvre_demands(correction_deg: float = 0.5, gain: float = 600.0) -> np.ndarray:
    """The S3 manoeuvre's demanded torques (14, 3) [N m].

    First-sample PD torque ``K theta e`` of a ``theta`` correction about each body half-axis
    (+-X, +-Y, +-Z) and each cube diagonal ``(+-1, +-1, +-1)/sqrt(3)``. S3 does not print its
    manoeuvre; this set covers all octants with equal weight.

    Parameters
    ----------
    correction_deg : float
        Attitude correction ``theta`` [deg], > 0.
    gain : float
        Proportional gain ``K`` [N m / rad], > 0.

    Returns
    -------
    ndarray (14, 3)
        Demanded torques [N m]: six half-axes, then the eight cube diagonals.

    References
    ----------
    S3 §6 (the reference layout is checked on this manoeuvre set).

    Examples
    --------
    >>> from adcskit.thrusters import S3_REFERENCE_A, s3_manoeuvre_demands
    >>> D = s3_manoeuvre_demands(0.5, 600.0)
    >>> D.shape, round(float(D[0, 0]), 4)          # 600 N m/rad x 0.5 deg about +X
    ((14, 3), 5.236)
    >>> S3_REFERENCE_A.shape
    (3, 6)
    """
    correction = check_positive("correction_deg", correction_deg, unit="deg")
    k = check_positive("gain", gain, unit="N m/rad")
    axes = np.vstack([np.eye(3), -np.eye(3)])
    diag = np.array([[a, b, c] for a in (1, -1) for b in (1, -1) for c in (1, -1)], float) / math.sqrt(3)
    return k * math.radians(correction) * np.vstack([axes, diag])
