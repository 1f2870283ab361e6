"""Quaternions and attitude matrices (DCMs).

Convention (``docs/architecture.md``, "Conventions"): ``q = [q1, q2, q3, q4] = [e, q4]``, vector part first, **scalar
last**, unit norm, canonical sign ``q4 >= 0``. ``q`` represents the attitude matrix

``A(q) = (q4² − |e|²) I₃ + 2 e eᵀ − 2 q4 [e×]``

which maps *reference-frame* components to *body-frame* components, ``b = A r``
(Markley & Crassidis 2014, eq. 2.125). Composition ``p ⊗ q`` is defined so that
``A(p ⊗ q) = A(p) A(q)`` (ibid., eq. 2.82a). In scipy terms,
``Rotation.from_quat(q).inv().as_matrix() == A(q)``; :func:`to_scipy` / :func:`from_scipy`
convert. Every function takes one item (``(4,)``, ``(3, 3)``) or a batch (``(N, 4)``,
``(N, 3, 3)``) and returns the same rank.

References
----------
F. L. Markley and J. L. Crassidis, *Fundamentals of Spacecraft Attitude Determination and
Control*, Springer, 2014, ch. 2.
S. W. Shepperd, "Quaternion from rotation matrix", J. Guidance and Control 1(3), 1978.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from adcskit._validation import as_rng, check_int, short_repr
from adcskit.attitude import _kernels as _k
from adcskit.attitude._checks import broadcast, dcms, out, quats, vectors
from adcskit.errors import InputTypeError

__all__ = [
    "dcm_to_quat",
    "error_angle",
    "from_scipy",
    "quat_canonical",
    "quat_from_scalar_first",
    "quat_inverse",
    "quat_multiply",
    "quat_normalize",
    "quat_to_dcm",
    "quat_to_scalar_first",
    "random_quat",
    "skew",
    "to_scipy",
]


def skew(v: Any) -> np.ndarray:
    """Cross-product matrix ``[v×]`` with ``[v×] w = v × w``.

    Parameters
    ----------
    v : array_like, shape (3,) or (N, 3)

    Returns
    -------
    numpy.ndarray, shape (3, 3) or (N, 3, 3)

    Examples
    --------
    >>> import numpy as np
    >>> np.allclose(skew([1.0, 2.0, 3.0]) @ [4.0, 5.0, 6.0], np.cross([1, 2, 3], [4, 5, 6]))
    True
    """
    arr, batched = vectors("v", v)
    return out(_k.skew(arr), batched)


def quat_normalize(q: Any) -> np.ndarray:
    """Unit quaternion(s) ``q / |q|`` (sign unchanged). Zero norm raises ``InputError``.

    Examples
    --------
    >>> quat_normalize([0.0, 0.0, 0.0, 2.0])
    array([0., 0., 0., 1.])
    """
    arr, batched = quats("q", q)
    return out(arr, batched)


def quat_canonical(q: Any) -> np.ndarray:
    """Unit quaternion(s) with the canonical sign ``q4 >= 0``.

    ``q`` and ``−q`` are the same attitude. On the 180° set (``q4 == 0``) the first non-zero
    vector component is made positive, so the canonical form is unique.

    Examples
    --------
    >>> quat_canonical([0.0, 0.0, 0.0, -2.0])
    array([-0., -0., -0.,  1.])
    """
    arr, batched = quats("q", q)
    return out(_k.canonical(arr), batched)


def quat_to_dcm(q: Any) -> np.ndarray:
    """Attitude matrix ``A(q)`` (reference → body) of scalar-last quaternion(s).

    Parameters
    ----------
    q : array_like, shape (4,) or (N, 4)
        Scalar-last quaternion(s); normalised before use.

    Returns
    -------
    numpy.ndarray, shape (3, 3) or (N, 3, 3)

    References
    ----------
    Markley & Crassidis (2014), eq. 2.125.

    Examples
    --------
    >>> import numpy as np
    >>> A = quat_to_dcm([0.0, 0.0, np.sin(np.pi / 4), np.cos(np.pi / 4)])   # 90 deg about z
    >>> (A @ [1.0, 0.0, 0.0]).round(12)
    array([ 0., -1.,  0.])
    """
    arr, batched = quats("q", q)
    return out(_k.quat_to_dcm(arr), batched)


def dcm_to_quat(A: Any) -> np.ndarray:
    """Canonical scalar-last quaternion(s) of attitude matrix/matrices (Shepperd's method).

    Parameters
    ----------
    A : array_like, shape (3, 3) or (N, 3, 3)
        Proper orthogonal matrices (checked to 1e-6).

    Returns
    -------
    numpy.ndarray, shape (4,) or (N, 4), with ``q4 >= 0``.

    References
    ----------
    Shepperd (1978); Markley & Crassidis (2014), eq. 2.135-2.137.

    Examples
    --------
    >>> from adcskit.attitude import euler_to_dcm
    >>> import numpy as np
    >>> dcm_to_quat(np.eye(3))
    array([0., 0., 0., 1.])
    >>> dcm_to_quat(euler_to_dcm([np.pi / 2, 0.0, 0.0], "ZYX")).round(6)
    array([0.      , 0.      , 0.707107, 0.707107])
    """
    arr, batched = dcms("A", A)
    return out(_k.dcm_to_quat(arr), batched)


def quat_multiply(p: Any, q: Any) -> np.ndarray:
    """Quaternion product ``p ⊗ q`` with ``A(p ⊗ q) = A(p) A(q)``.

    ``p`` and ``q`` broadcast over the batch axis (one of them may be a single quaternion).
    Inputs are normalised; the result is a unit quaternion (sign not canonicalised).

    References
    ----------
    Markley & Crassidis (2014), eq. 2.82a.

    Examples
    --------
    >>> import numpy as np
    >>> p, q = random_quat(2, rng=1)
    >>> np.allclose(quat_to_dcm(quat_multiply(p, q)), quat_to_dcm(p) @ quat_to_dcm(q))
    True
    """
    pa, pb = quats("p", p)
    qa, qb = quats("q", q)
    pa, qa = broadcast("p", pa, "q", qa)
    return out(_k.quat_multiply(pa, qa), pb or qb)


def quat_inverse(q: Any) -> np.ndarray:
    """Inverse (conjugate) of unit quaternion(s): ``A(q⁻¹) = A(q)ᵀ``.

    Examples
    --------
    >>> import numpy as np
    >>> q = random_quat(rng=0)
    >>> np.allclose(quat_to_dcm(quat_inverse(q)), quat_to_dcm(q).T)
    True
    """
    arr, batched = quats("q", q)
    return out(_k.quat_conjugate(arr), batched)


def error_angle(q1: Any, q2: Any) -> np.ndarray | float:
    """Rotation angle between two attitudes, in radians, in ``[0, π]``.

    Equal to ``arccos((tr(A₁ᵀ A₂) − 1) / 2)`` (S0's error metric δθ) but computed as
    ``2 atan2(|v|, |s|)`` of ``q1 ⊗ q2⁻¹``, accurate near 0 and near π. Sign-invariant.

    Returns
    -------
    float or numpy.ndarray, shape (N,)

    Examples
    --------
    >>> from adcskit.attitude import euler_to_dcm
    >>> import numpy as np
    >>> q = dcm_to_quat(euler_to_dcm([np.radians(10.0), 0.0, 0.0], "ZYX"))
    >>> round(float(np.degrees(error_angle(q, [0.0, 0.0, 0.0, 1.0]))), 9)
    10.0
    """
    a, ab = quats("q1", q1)
    b, bb = quats("q2", q2)
    a, b = broadcast("q1", a, "q2", b)
    ang = _k.error_angle(a, b)
    return ang if (ab or bb) else float(ang[0])


def quat_from_scalar_first(q: Any) -> np.ndarray:
    """Reorder scalar-first ``[q0, q1, q2, q3]`` (Basilisk, Shuster, S0's printed values)
    to adcskit's scalar-last ``[q1, q2, q3, q0]``. The attitude matrix formula is the same
    with the scalar moved (Shuster 1993), so the represented attitude is unchanged.

    Examples
    --------
    >>> quat_from_scalar_first([1.0, 0.0, 0.0, 0.0])   # Basilisk / Shuster order
    array([0., 0., 0., 1.])
    """
    arr, batched = quats("q", q)
    return out(np.roll(arr, -1, axis=1), batched)


def quat_to_scalar_first(q: Any) -> np.ndarray:
    """Reorder scalar-last ``[q1, q2, q3, q4]`` to scalar-first ``[q4, q1, q2, q3]``.

    Examples
    --------
    >>> quat_to_scalar_first([0.0, 0.0, 0.0, 1.0])
    array([1., 0., 0., 0.])
    """
    arr, batched = quats("q", q)
    return out(np.roll(arr, 1, axis=1), batched)


def to_scipy(q: Any) -> Rotation:
    """scipy ``Rotation`` ``R`` whose *inverse* has matrix ``A(q)``.

    ``R`` rotates body axes onto the reference axes actively (``R.apply(b) = r``); the
    quaternion components are the same numbers (scipy is scalar-last too).

    Examples
    --------
    >>> import numpy as np
    >>> q = random_quat(rng=3)
    >>> np.allclose(to_scipy(q).inv().as_matrix(), quat_to_dcm(q))
    True
    """
    arr, batched = quats("q", q)
    return Rotation.from_quat(arr if batched else arr[0])


def from_scipy(rotation: Rotation) -> np.ndarray:
    """Canonical quaternion(s) ``q`` with ``A(q) = rotation.inv().as_matrix()``.

    Inverse of :func:`to_scipy`.

    Examples
    --------
    >>> from scipy.spatial.transform import Rotation
    >>> q = from_scipy(Rotation.from_euler("z", 90, degrees=True))
    >>> q.round(6)
    array([0.      , 0.      , 0.707107, 0.707107])
    """
    if not isinstance(rotation, Rotation):
        raise InputTypeError(
            f"rotation must be a scipy.spatial.transform.Rotation; got {short_repr(rotation)}"
        )
    q = np.asarray(rotation.as_quat(), dtype=float)
    return _k.canonical(q.reshape(-1, 4)).reshape(q.shape)


def random_quat(n: int | None = None, rng: Any = None) -> np.ndarray:
    """Uniformly distributed random attitude(s) (Haar measure on SO(3)), canonical sign.

    Parameters
    ----------
    n : int or None
        Number of quaternions; ``None`` returns one ``(4,)`` quaternion.
    rng : numpy.random.Generator, int or None
        Random source (``None`` = seed 0).

    Examples
    --------
    >>> q = random_quat(1000, rng=42)
    >>> q.shape, bool((q[:, 3] >= 0).all())
    ((1000, 4), True)
    """
    gen = as_rng(rng)
    m = 1 if n is None else check_int("n", n, minimum=1, maximum=10**8)
    q = gen.standard_normal((m, 4))
    q = _k.canonical(q)  # normalised Gaussian 4-vectors are uniform on S³
    return q[0] if n is None else q
