"""Modified Rodrigues parameters (MRPs).

``σ = e tan(Φ/4) = q_v / (1 + q4)`` (scalar-last quaternion, docs/architecture.md convention) with the
attitude matrix ``C(σ) = I + (8[σ×]² − 4(1 − σ²)[σ×]) / (1 + σ²)²`` equal to ``A(q)``.
``σ`` and its shadow set ``σˢ = −σ/|σ|²`` describe the same attitude; the set with
``|σ| <= 1`` (rotation angle ≤ 180°) is returned by the converters, and :func:`mrp_switch`
applies the switching rule used when integrating MRP kinematics.

References
----------
H. Schaub and J. L. Junkins, *Analytical Mechanics of Space Systems*, 4th ed., AIAA 2018,
§3.7 (eq. 3.145, 3.153, 3.154).
S2 (time-optimal rendezvous), eq. 3-5.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from adcskit._validation import check_range
from adcskit.attitude import _kernels as _k
from adcskit.attitude._checks import MRP_MAX, dcms, mrps, out, quats
from adcskit.errors import InputError

__all__ = ["dcm_to_mrp", "mrp_shadow", "mrp_switch", "mrp_to_dcm", "mrp_to_quat", "quat_to_mrp"]


def quat_to_mrp(q: Any) -> np.ndarray:
    """MRPs ``σ = q_v / (1 + q4)`` of canonical ``q`` (so ``|σ| <= 1``).

    Examples
    --------
    >>> import numpy as np
    >>> quat_to_mrp([0.0, 0.0, np.sin(np.pi / 4), np.cos(np.pi / 4)]).round(6)
    array([0.      , 0.      , 0.414214])
    """
    arr, batched = quats("q", q)
    return out(_k.quat_to_mrp(_k.canonical(arr)), batched)


def mrp_to_quat(sigma: Any) -> np.ndarray:
    """Canonical scalar-last quaternion(s) of MRPs ``σ`` (either set).

    Examples
    --------
    >>> import numpy as np
    >>> mrp_to_quat([0.0, 0.0, np.tan(np.pi / 8)]).round(6)
    array([0.      , 0.      , 0.707107, 0.707107])
    """
    arr, batched = mrps("sigma", sigma)
    return out(_k.mrp_to_quat(arr), batched)


def mrp_to_dcm(sigma: Any) -> np.ndarray:
    """Attitude matrix ``C(σ)`` (reference → body), Schaub & Junkins eq. 3.154.

    Examples
    --------
    >>> from adcskit.attitude import euler_to_dcm
    >>> import numpy as np
    >>> np.allclose(mrp_to_dcm([0.0, 0.0, np.tan(np.pi / 8)]), euler_to_dcm([np.pi / 2, 0, 0], "ZYX"))
    True
    """
    arr, batched = mrps("sigma", sigma)
    return out(_k.mrp_to_dcm(arr), batched)


def dcm_to_mrp(A: Any) -> np.ndarray:
    """MRPs with ``|σ| <= 1`` of attitude matrix/matrices ``A``.

    Examples
    --------
    >>> from adcskit.attitude import euler_to_dcm
    >>> import numpy as np
    >>> A = euler_to_dcm([np.pi / 2, 0.0, 0.0], "ZYX")   # 90 deg about z
    >>> dcm_to_mrp(A).round(6)                            # tan(90 deg / 4) about z
    array([0.      , 0.      , 0.414214])
    """
    arr, batched = dcms("A", A)
    return out(_k.quat_to_mrp(_k.dcm_to_quat(arr)), batched)


def mrp_shadow(sigma: Any) -> np.ndarray:
    """Shadow set ``σˢ = −σ / |σ|²`` (same attitude). ``σ = 0`` has no shadow (error).

    Examples
    --------
    >>> mrp_shadow([0.0, 0.0, 0.5])
    array([-0., -0., -2.])
    """
    arr, batched = mrps("sigma", sigma)
    n2 = np.sum(arr * arr, axis=1)
    bad = np.flatnonzero(n2 == 0)
    if bad.size:
        raise InputError(
            f"sigma must be non-zero to have a shadow set (the identity's shadow is at "
            f"infinity); got sigma = 0 at index {int(bad[0])}"
        )
    return out(_k.mrp_shadow(arr), batched)


def mrp_switch(sigma: Any, threshold: float = 1.0) -> np.ndarray:
    """Replace ``σ`` by its shadow set where ``|σ| > threshold`` (default 1, i.e. Φ > 180°).

    Examples
    --------
    >>> mrp_switch([[0.0, 0.0, 2.0], [0.0, 0.0, 0.5]])
    array([[-0. , -0. , -0.5],
           [ 0. ,  0. ,  0.5]])
    """
    threshold = check_range("threshold", threshold, 1.0, MRP_MAX)
    arr, batched = mrps("sigma", sigma)
    n2 = np.sum(arr * arr, axis=1)
    sw = n2 > threshold**2
    res = arr.copy()
    res[sw] = -arr[sw] / n2[sw, None]
    return out(res, batched)
