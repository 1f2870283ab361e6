"""Thruster geometry: directions from S3's angles, thruster sets, torque and force matrices.

Conventions
-----------
* Body frame, SI units, radians. Positions are measured from the body origin; the centre of
  mass ``com`` is subtracted when the torque matrix is formed (S3 puts the CoM at the origin).
* A thruster's ``direction`` is the unit vector of the **force on the spacecraft**; the
  exhaust leaves along ``-direction`` (S3 §3: "the thruster pushes the body opposite to the
  expelled gas").
* S3 eq. 4 parametrises the direction by two angles: ``alpha`` (angle with X_B in the
  X_B-Y_B plane) and ``beta`` (angle with X_B in the X_B-Z_B plane),
  ``d = (cos a cos b, sin a, cos a sin b)``, and the torque per newton is ``r x d``.

Hand-written here (no library offers it): the angle parametrisation and the positive-span
controllability test, which is one small linear programme solved by
:func:`scipy.optimize.linprog`.

References
----------
S3: Kosari, Kaviri, Moshiri, Fakoor, "Design of optimal thruster configuration for attitude
control of geostationary satellite", eq. 3-5 (torque of one thruster, ``M = A F``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import linprog

from adcskit._results import Result
from adcskit._validation import as_array, as_batch, check_positive, check_positive_array, short_repr
from adcskit.errors import InputError, InputTypeError

__all__ = [
    "Thruster",
    "ThrusterSet",
    "Controllability",
    "direction_from_angles",
    "angles_from_direction",
    "torque_matrix",
    "check_controllability",
]


def direction_from_angles(alpha: Any, beta: Any) -> np.ndarray:
    """Unit thrust direction from S3's angles.

    Parameters
    ----------
    alpha : float or array_like, rad
        Angle of the thrust vector with X_B in the X_B-Y_B plane.
    beta : float or array_like, rad
        Angle of the thrust vector with X_B in the X_B-Z_B plane (same shape as ``alpha``).

    Returns
    -------
    numpy.ndarray, shape ``(..., 3)``
        ``d = (cos(alpha) cos(beta), sin(alpha), cos(alpha) sin(beta))``.

    References
    ----------
    S3 eq. 4: the torque per newton printed there equals ``r x d`` with this ``d``.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import direction_from_angles
    >>> direction_from_angles(0.0, 0.0)
    array([1., 0., 0.])
    >>> direction_from_angles(np.pi / 2, 0.0).round(12)    # alpha = 90 deg: along +Y
    array([0., 1., 0.])
    >>> direction_from_angles(np.zeros(4), np.linspace(0.0, np.pi, 4)).shape
    (4, 3)
    """
    a = as_array("alpha", alpha)
    b = as_array("beta", beta)
    if a.shape != b.shape:
        raise InputError(f"alpha and beta must have the same shape; got {a.shape} and {b.shape}")
    ca = np.cos(a)
    return np.stack([ca * np.cos(b), np.sin(a), ca * np.sin(b)], axis=-1)


def angles_from_direction(direction: Any) -> tuple[np.ndarray, np.ndarray]:
    """S3's ``(alpha, beta)`` of a unit direction, principal values.

    Returns ``alpha = arcsin(d_y)`` in ``[-pi/2, pi/2]`` and ``beta = atan2(d_z, d_x)`` in
    ``(-pi, pi]``. The pair ``(pi - alpha, beta + pi)`` describes the same direction; S3's
    Tables 1 and 3 use that second branch for the X faces. For ``d = ±Y`` ``beta`` is 0.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import angles_from_direction, direction_from_angles
    >>> alpha, beta = angles_from_direction(direction_from_angles(0.3, -1.2))
    >>> round(float(alpha), 12), round(float(beta), 12)
    (0.3, -1.2)
    """
    d, batched = as_batch("direction", direction, (3,))
    scale = np.abs(d).max(axis=1, keepdims=True) if d.size else np.ones((0, 1))
    if np.any(scale == 0):
        raise InputError("direction must be non-zero vectors (a zero vector has no angles)")
    d = d / scale
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    alpha = np.arcsin(np.clip(d[:, 1], -1.0, 1.0))
    beta = np.arctan2(d[:, 2], d[:, 0])
    if not batched:
        return alpha[0], beta[0]
    return alpha, beta


def _unit_rows(name: str, value: Any) -> np.ndarray:
    d = as_array(name, value, ndim=2)
    if d.shape[1] != 3:
        raise InputError(f"{name} must have shape (n, 3); got shape {d.shape}")
    norm = np.linalg.norm(d, axis=1)
    if np.any(norm < 1e-12):
        i = int(np.argmin(norm))
        raise InputError(f"{name} must be non-zero vectors; row {i} has norm {norm[i]:g}")
    return d / norm[:, None]


@dataclass(frozen=True, slots=True, kw_only=True)
class Thruster:
    """One thruster.

    Attributes
    ----------
    position : ndarray, shape (3,), m
        Mounting point in the body frame.
    direction : ndarray, shape (3,)
        Unit vector of the force on the spacecraft (normalised on construction).
    f_max : float, N
        Force when on (S3 Table 5: 10 N).
    t_min : float, s
        Minimum on-time (S3 §6: 3 ms).
    mdot : float, kg/s
        Propellant mass flow when on (S3 Table 5: 3.5 g/s).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import Thruster
    >>> th = Thruster(position=np.array([1.0, 0.0, 0.0]), direction=np.array([0.0, 2.0, 0.0]))
    >>> th.direction, th.f_max, th.t_min       # normalised; S3 Table 5 defaults
    (array([0., 1., 0.]), 10.0, 0.003)
    >>> round(th.isp_s, 1)                                # s, from f_max / (mdot g0)
    291.3
    """

    position: np.ndarray
    direction: np.ndarray
    f_max: float = 10.0
    t_min: float = 3e-3
    mdot: float = 3.5e-3

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", as_array("position", self.position, shape=(3,)))
        object.__setattr__(self, "direction", _unit_rows("direction", [self.direction])[0])
        object.__setattr__(self, "f_max", check_positive("f_max", self.f_max, unit="N"))
        object.__setattr__(self, "t_min", check_positive("t_min", self.t_min, allow_zero=True, unit="s"))
        object.__setattr__(self, "mdot", check_positive("mdot", self.mdot, unit="kg/s"))

    @classmethod
    def from_angles(cls, position: Any, alpha: float, beta: float, **kw: Any) -> Thruster:
        """A thruster whose direction is given by S3's angles (eq. 4), in rad."""
        return cls(position=position, direction=direction_from_angles(alpha, beta), **kw)

    @property
    def exhaust_velocity(self) -> float:
        """Effective exhaust velocity ``f_max / mdot``, N s/kg = m/s (S3 Table 5 prints 2845 as "Isp").

        >>> round(Thruster(position=[1, 0, 0], direction=[-1, 0, 0]).exhaust_velocity, 1)
        2857.1
        """
        return self.f_max / self.mdot

    @property
    def isp_s(self) -> float:
        """Specific impulse in seconds, ``exhaust_velocity / g0`` (g0 = 9.80665 m/s²).

        >>> round(Thruster(position=[1, 0, 0], direction=[-1, 0, 0]).isp_s, 1)
        291.3
        """
        return self.f_max / self.mdot / 9.80665


@dataclass(frozen=True, slots=True, kw_only=True)
class ThrusterSet(Result):
    """``n`` thrusters as arrays (batch-first).

    Attributes
    ----------
    positions : ndarray, shape (n, 3), m
    directions : ndarray, shape (n, 3)
        Unit force directions.
    f_max, t_min, mdot : ndarray, shape (n,)
        Per-thruster force (N), minimum on-time (s), mass flow (kg/s); scalars broadcast.
    com : ndarray, shape (3,), m
        Centre of mass in the same frame as ``positions``.
    names : tuple of str
        Optional labels (for example the mounting face).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import ThrusterSet
    >>> r = [[1, 0, 0], [1, 0, 0], [0, 1, 0], [0, 1, 0], [0, 0, 1], [0, 0, 1]]     # m
    >>> d = [[0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0]]  # +-z +-x +-y
    >>> ts = ThrusterSet(positions=np.array(r, float), directions=np.array(d, float), f_max=10.0)
    >>> ts.n, ts.torque_matrix().shape
    (6, (3, 6))
    >>> ts.torque_matrix()[:, :2]               # r x d of the first two thrusters, N m per N
    array([[ 0.,  0.],
           [ 0.,  0.],
           [ 1., -1.]])
    >>> ts.lever_arms()
    array([1., 1., 1., 1., 1., 1.])
    """

    positions: np.ndarray
    directions: np.ndarray
    f_max: Any = 10.0
    t_min: Any = 3e-3
    mdot: Any = 3.5e-3
    com: Any = (0.0, 0.0, 0.0)
    names: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        pos = as_array("positions", self.positions, ndim=2)
        if pos.shape[1] != 3 or pos.shape[0] < 1:
            raise InputError(f"positions must have shape (n, 3) with n >= 1; got {pos.shape}")
        d = _unit_rows("directions", self.directions)
        if d.shape != pos.shape:
            raise InputError(
                f"directions must have the same shape as positions {pos.shape}; got {d.shape}"
            )
        n = pos.shape[0]
        object.__setattr__(self, "positions", pos)
        object.__setattr__(self, "directions", d)
        for name, unit, zero in (("f_max", "N", False), ("t_min", "s", True), ("mdot", "kg/s", False)):
            v = check_positive_array(name, as_array(name, getattr(self, name), ndim=(0, 1)), allow_zero=zero,
                                     unit=unit, broadcast_to=(n,))
            object.__setattr__(self, name, v)
        object.__setattr__(self, "com", as_array("com", self.com, shape=(3,)))
        names = tuple(str(s) for s in self.names)
        if names and len(names) != n:
            raise InputError(f"names must have {n} entries (one per thruster); got {len(names)}")
        object.__setattr__(self, "names", names)

    @classmethod
    def from_thrusters(cls, thrusters: Sequence[Thruster], com: Any = (0.0, 0.0, 0.0)) -> ThrusterSet:
        """Stack :class:`Thruster` objects."""
        if isinstance(thrusters, str) or not hasattr(thrusters, "__len__") or not all(
                isinstance(t, Thruster) for t in thrusters):
            raise InputTypeError(f"thrusters must be a sequence of Thruster; got {short_repr(thrusters)}")
        if len(thrusters) == 0:
            raise InputError("thrusters must contain at least one Thruster; got an empty sequence")
        return cls(
            positions=[t.position for t in thrusters],
            directions=[t.direction for t in thrusters],
            f_max=[t.f_max for t in thrusters],
            t_min=[t.t_min for t in thrusters],
            mdot=[t.mdot for t in thrusters],
            com=com,
        )

    @property
    def n(self) -> int:
        """Number of thrusters."""
        return self.positions.shape[0]

    def torque_matrix(self) -> np.ndarray:
        """``A`` (3, n), N m per N: column ``i`` is ``(r_i - com) x d_i`` (S3 eq. 4-5)."""
        return torque_matrix(self.positions - self.com, self.directions)

    def force_matrix(self) -> np.ndarray:
        """(3, n), N per N: column ``i`` is ``d_i``; the net force is ``force_matrix @ F``."""
        return self.directions.T.copy()

    def lever_arms(self) -> np.ndarray:
        """``Delta_i = ||(r_i - com) x d_i||`` (m), S3 eq. 8."""
        return np.linalg.norm(self.torque_matrix(), axis=0)

    def angles(self) -> tuple[np.ndarray, np.ndarray]:
        """S3's ``(alpha, beta)`` of every thruster (rad, principal branch)."""
        return angles_from_direction(self.directions)


def torque_matrix(positions: Any, directions: Any) -> np.ndarray:
    """Torque matrix ``A`` with ``M = A F`` (S3 eq. 5), batched.

    Parameters
    ----------
    positions : array_like, shape (n, 3) or (B, n, 3), m
        Thruster positions relative to the centre of mass.
    directions : array_like, same shape
        Unit force directions.

    Returns
    -------
    numpy.ndarray, shape (3, n) or (B, 3, n), N m per N
        Column ``i`` is ``r_i x d_i`` (equal to S3 eq. 4 written with the angles).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import torque_matrix
    >>> torque_matrix([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    array([[0., 1.],
           [0., 0.],
           [1., 0.]])
    >>> torque_matrix(np.zeros((5, 4, 3)), np.ones((5, 4, 3))).shape   # a batch of 5 layouts
    (5, 3, 4)
    """
    r = as_array("positions", positions, ndim=(2, 3))
    d = as_array("directions", directions, ndim=(2, 3))
    if r.shape != d.shape or r.shape[-1] != 3:
        raise InputError(
            f"positions and directions must have equal shapes (n, 3) or (B, n, 3); got {r.shape} and {d.shape}"
        )
    zero = ~np.any(d != 0.0, axis=-1)
    if np.any(zero):
        where = tuple(int(i) for i in np.argwhere(zero)[0])
        raise InputError(
            f"directions must be non-zero force directions (unit vectors); got [0, 0, 0] at index {where}"
        )
    return _torque_matrix(r, d)


def _torque_matrix(r: np.ndarray, d: np.ndarray) -> np.ndarray:
    return np.swapaxes(np.cross(r, d), -1, -2)


@dataclass(frozen=True, slots=True, kw_only=True)
class Controllability(Result):
    """Result of the positive-span test.

    Attributes
    ----------
    success : bool
        True if every torque direction can be produced with non-negative forces.
    rank : int
        Rank of the torque matrix.
    margin : float
        Optimal ``t`` of the LP ``max t : A F = 0, t <= F_i <= 1``; positive iff a strictly
        positive null-space combination exists.
    unreachable : ndarray, shape (3,)
        A unit torque direction that cannot be produced (zeros when ``success``).
    message : str

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import ThrusterSet
    >>> r = [[1, 0, 0], [1, 0, 0], [0, 1, 0], [0, 1, 0], [0, 0, 1], [0, 0, 1]]     # m
    >>> d = [[0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0]]  # +-z +-x +-y
    >>> ts = ThrusterSet(positions=np.array(r, float), directions=np.array(d, float), f_max=10.0)
    >>> from adcskit.thrusters import check_controllability
    >>> c = check_controllability(ts.torque_matrix())
    >>> type(c).__name__, c.success, c.rank
    ('Controllability', True, 3)
    """

    success: bool
    rank: int
    margin: float
    unreachable: np.ndarray
    message: str


def check_controllability(torque_matrix: Any, *, tol: float = 1e-9) -> Controllability:
    """Can every torque direction be produced with non-negative thruster forces?

    The columns ``a_i`` of ``A`` positively span R^3 iff (i) ``rank A = 3`` and (ii) some
    strictly positive ``F`` has ``A F = 0`` (a classical theorem; e.g. Davis 1954, "Theory
    of positive linear dependence"). (ii) is the LP ``max t`` s.t. ``A F = 0``,
    ``t <= F_i <= 1``. When it fails, Gordan's alternative gives ``w != 0`` with
    ``w . a_i >= 0`` for all i; then the torque direction ``-w`` is unreachable.

    Parameters
    ----------
    torque_matrix : array_like, shape (3, n)
    tol : float
        Margin below which (ii) counts as failed.

    Returns
    -------
    Controllability
        Never raises on an uncontrollable layout; ``message`` says why.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import ThrusterSet
    >>> r = [[1, 0, 0], [1, 0, 0], [0, 1, 0], [0, 1, 0], [0, 0, 1], [0, 0, 1]]     # m
    >>> d = [[0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0]]  # +-z +-x +-y
    >>> ts = ThrusterSet(positions=np.array(r, float), directions=np.array(d, float), f_max=10.0)
    >>> from adcskit.thrusters import check_controllability
    >>> A = ts.torque_matrix()
    >>> ok = check_controllability(A)
    >>> ok.success, ok.rank, bool(ok.margin > 0)
    (True, 3, True)
    >>> bad = check_controllability(A[:, :5])              # drop the -y thruster
    >>> bad.success, bad.unreachable.round(6) + 0.0         # -y torque cannot be produced
    (False, array([ 0., -1.,  0.]))
    """
    A = as_array("torque_matrix", torque_matrix, ndim=2)
    if A.shape[0] != 3:
        raise InputError(f"torque_matrix must have shape (3, n); got {A.shape}")
    n = A.shape[1]
    tol = check_positive("tol", tol, allow_zero=True)
    scale = max(float(np.abs(A).max()), 1e-300)
    As = A / scale
    rank = int(np.linalg.matrix_rank(As, tol=1e-10))
    if rank < 3:
        _, _, vt = np.linalg.svd(As.T)
        w = vt[-1]
        return Controllability(
            success=False,
            rank=rank,
            margin=0.0,
            unreachable=w,
            message=(
                f"torque matrix has rank {rank} < 3: no torque can be produced along "
                f"{np.array2string(w, precision=3)} (nor its opposite)"
            ),
        )
    # variables [F (n), t]; minimise -t
    c = np.zeros(n + 1)
    c[-1] = -1.0
    A_eq = np.hstack([As, np.zeros((3, 1))])
    A_ub = np.hstack([-np.eye(n), np.ones((n, 1))])  # t - F_i <= 0
    res = linprog(
        c, A_ub=A_ub, b_ub=np.zeros(n), A_eq=A_eq, b_eq=np.zeros(3),
        bounds=[(0.0, 1.0)] * n + [(None, 1.0)], method="highs",
    )
    margin = max(0.0, float(-res.fun)) if res.status == 0 else 0.0
    if margin > tol:
        return Controllability(
            success=True, rank=3, margin=margin, unreachable=np.zeros(3),
            message="columns positively span R^3: every torque direction is reachable",
        )
    # Gordan: find w with A^T w >= 0, maximise sum(A^T w), -1 <= w <= 1
    res2 = linprog(
        -As.sum(axis=1), A_ub=-As.T, b_ub=np.zeros(n), bounds=[(-1.0, 1.0)] * 3, method="highs"
    )
    w = res2.x if res2.status == 0 else np.zeros(3)
    nw = np.linalg.norm(w)
    u = -w / nw if nw > 0 else np.zeros(3)
    return Controllability(
        success=False,
        rank=3,
        margin=margin,
        unreachable=u,
        message=(
            "columns do not positively span R^3: every thruster torque has a non-negative "
            f"component along {np.array2string(-u, precision=3)}, so torque along "
            f"{np.array2string(u, precision=3)} cannot be produced with forces >= 0"
        ),
    )
