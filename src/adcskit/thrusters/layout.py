"""Thruster layout design on pymoo's GA and DE, with mounting faces as data (S3 §5-6).

Decision variables
------------------
Each thruster has five genes ``[s, u, v, c, phi]``:

* ``s in [0, n_faces)`` — the mounting face, ``faces[floor(s)]`` (a real gene so that the
  same real-coded GA and DE operators apply);
* ``u, v in [-1, 1]`` — the mounting point on that face, ``p = centre + u h_u e_u + v h_v e_v``;
  for the faces of the S3 box this is exactly the box bound ``-1 <= r_x, r_y, r_z <= 1`` of
  S3 eq. 20, restricted to the surface (a thruster inside the body is not mountable);
* ``c in [0, 1]``, ``phi in [0, 2 pi]`` — the force direction
  ``d = -cos(theta) n + sin(theta) (cos(phi) e_u + sin(phi) e_v)``, ``theta = c * max_cant``,
  with ``n`` the face's outward normal. ``theta <= pi/2`` says the thrust *leaves the face*:
  the exhaust (``-d``) points outward, the force on the body inward — S3 Tables 1-4, which
  each state this in one coordinate plane (for the +Y face ``pi <= alpha <= 2 pi`` is
  ``d_y <= 0``). A face's ``max_cant < pi/2`` keeps plumes away from the face, and leaving
  a face out of ``faces`` forbids it (e.g. the faces that carry the solar arrays).

All bounds are box bounds, so no constraint handling is needed and every individual of every
generation is a mountable layout.

Objective (S3 eq. 18)
---------------------
``F_best = K1 * error + K2 * e_min + K3 * sum_tp`` with S3 Table 7's ``K = (100, -99, 12)``:

* ``error`` (N m): mean over the manoeuvre demands of ``||M_k - A F_k||`` (eq. 15), with
  ``F_k`` from the chosen allocation (S3: ``pinv-redistribute``);
* ``e_min`` (rad): the largest per-thruster minimum reachable error (eq. 16 with the lever
  arm; see :mod:`adcskit.thrusters.pulse`) — the coarsest thruster limits the accuracy;
* ``sum_tp`` (s): mean over the demands of ``sum_i t_p,i`` (eq. 17, with eq. 6).

The population is evaluated in one vectorised call (decoding, torque matrices and the
batched redistributed pseudo-inverse for all individuals x demands at once).

DE strategy
-----------
S3 uses "the second of the two strategies" of Price & Storn (S3 ref. [20]). Storn & Price's
scheme DE2 (ICSI TR-95-012, 1995; JGO 11, 1997) builds the mutant
``v = x_i + lambda (x_best - x_i) + F (x_r1 - x_r2)`` followed by binomial crossover; with
``lambda = F`` (their recommendation to save a control parameter) it is
``DE/current-to-best/1/bin``. pymoo's ``DE`` offers ``rand``, ``best`` and
``target-to-best`` (``x_i + F (x_best - x_r1)``) but not DE2, so DE2 is a small pymoo
infill operator here (:class:`_CurrentToBest`) plugged into ``pymoo``'s ``DE`` loop. Scheme
DE1 (``DE/rand/1/bin``) is pymoo's own variant.

References
----------
S3 eq. 4-20, Tables 1-7. Storn R., Price K., "Differential evolution - a simple and efficient
heuristic for global optimization over continuous spaces", J. Global Optim. 11, 1997.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from adcskit._results import Result
from adcskit._validation import (
    as_array,
    as_rng,
    check_choice,
    check_int,
    check_positive,
    check_positive_array,
    check_range,
    short_repr,
)
from adcskit.errors import InputError, InputTypeError
from adcskit.thrusters.allocation import _rpi_layouts
from adcskit.thrusters.geometry import ThrusterSet

__all__ = [
    "MountingFace",
    "box_faces",
    "LayoutScore",
    "LayoutResult",
    "score_layout",
    "design_layout",
    "DESIGN_ALGORITHMS",
    "DEFAULT_WEIGHTS",
    "decode_layout",
]

#: S3 Table 7 weights (K1, K2, K3), signs as printed.
DEFAULT_WEIGHTS = (100.0, -99.0, 12.0)

GENES_PER_THRUSTER = 5


@dataclass(frozen=True, slots=True, kw_only=True)
class MountingFace(Result):
    """A rectangular face on which thrusters may be mounted.

    Attributes
    ----------
    name : str
    centre : ndarray (3,), m
    normal : ndarray (3,)
        Outward unit normal; the exhaust must leave through this side.
    axis_u, axis_v : ndarray (3,)
        Unit in-plane axes (orthogonal to ``normal`` and to each other).
    half_u, half_v : float, m
        Half extents along ``axis_u`` and ``axis_v``.
    max_cant : float, rad
        Largest angle between the force and the inward normal, in ``[0, pi/2]``
        (``pi/2``: any direction whose exhaust leaves the face, S3 Tables 1-4).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import MountingFace, decode_layout
    >>> face = MountingFace(name="+X", centre=np.array([1.0, 0.0, 0.0]),
    ...                     normal=np.array([1.0, 0.0, 0.0]),
    ...                     axis_u=np.array([0.0, 1.0, 0.0]), axis_v=np.array([0.0, 0.0, 1.0]),
    ...                     half_u=0.5, half_v=0.5)
    >>> ts = decode_layout([0.0, 1.0, 0.0, 0.0, 0.0], [face])   # corner u = 1, force along -normal
    >>> ts.positions, ts.directions.round(12) + 0.0
    (array([[1. , 0.5, 0. ]]), array([[-1.,  0.,  0.]]))
    """

    name: str
    centre: np.ndarray
    normal: np.ndarray
    axis_u: np.ndarray
    axis_v: np.ndarray
    half_u: float
    half_v: float
    max_cant: float = math.pi / 2

    def __post_init__(self) -> None:
        vecs = {}
        for key in ("centre", "normal", "axis_u", "axis_v"):
            vecs[key] = as_array(key, getattr(self, key), shape=(3,))
        for key in ("normal", "axis_u", "axis_v"):
            nv = np.linalg.norm(vecs[key])
            if nv < 1e-12:
                raise InputError(f"{key} of face {self.name!r} must be non-zero")
            vecs[key] = vecs[key] / nv
        G = np.stack([vecs["normal"], vecs["axis_u"], vecs["axis_v"]])
        if not np.allclose(G @ G.T, np.eye(3), atol=1e-9):
            raise InputError(
                f"normal, axis_u and axis_v of face {self.name!r} must be mutually orthogonal"
            )
        for key, value in vecs.items():
            object.__setattr__(self, key, value)
        object.__setattr__(self, "half_u", check_positive("half_u", self.half_u, allow_zero=True, unit="m"))
        object.__setattr__(self, "half_v", check_positive("half_v", self.half_v, allow_zero=True, unit="m"))
        mc = check_range("max_cant", self.max_cant, 0.0, math.pi / 2, unit="rad")
        object.__setattr__(self, "max_cant", mc)


_BOX_AXES = {
    "+X": (0, 1.0, 1, 2), "-X": (0, -1.0, 1, 2),
    "+Y": (1, 1.0, 2, 0), "-Y": (1, -1.0, 2, 0),
    "+Z": (2, 1.0, 0, 1), "-Z": (2, -1.0, 0, 1),
}


def box_faces(
    half_size: Any = (1.0, 1.0, 1.0),
    names: Sequence[str] = ("+X", "-X", "+Y", "-Y", "+Z", "-Z"),
    *,
    max_cant: float | dict[str, float] = math.pi / 2,
) -> tuple[MountingFace, ...]:
    """The faces of a box centred on the body origin (S3: 2 x 2 x 2 m, half size 1 m).

    Parameters
    ----------
    half_size : array_like (3,), m
    names : sequence of {"+X", "-X", "+Y", "-Y", "+Z", "-Z"}
        Faces allowed for mounting; leave out e.g. the solar-array faces.
    max_cant : float or dict name -> float, rad
        Per-face limit on the angle between force and inward normal.

    Examples
    --------
    >>> from adcskit.thrusters import box_faces
    >>> faces = box_faces((1.0, 1.0, 1.0))                 # S3: 2 x 2 x 2 m body
    >>> [f.name for f in faces]
    ['+X', '-X', '+Y', '-Y', '+Z', '-Z']
    >>> faces[0].centre, faces[0].normal
    (array([1., 0., 0.]), array([1., 0., 0.]))
    >>> len(box_faces(names=("+X", "-X")))
    2
    """
    h = as_array("half_size", half_size, shape=(3,))
    if np.any(h <= 0):
        raise InputError(f"half_size must be > 0 m per axis; got {h}")
    if isinstance(names, str) or not hasattr(names, "__len__"):
        raise InputTypeError(f"names must be a sequence of face names such as ('+X', '-Z'); got {short_repr(names)}")
    if len(names) == 0:
        raise InputError("names must list at least one face")
    for name in names:
        check_choice("names (a face name)", name, _BOX_AXES)
    if isinstance(max_cant, Mapping):
        unknown = [k for k in max_cant if k not in names]
        if unknown:
            raise InputError(f"max_cant names faces that are not among names {list(names)}: {unknown} "
                             "(a limit for a face that is not built would be ignored)")
    elif isinstance(max_cant, str) or max_cant is None:
        raise InputTypeError(f"max_cant must be an angle in rad or a dict face name -> rad; got {short_repr(max_cant)}")
    faces = []
    for name in names:
        k, sign, iu, iv = _BOX_AXES[name]
        e = np.eye(3)
        mc = max_cant.get(name, math.pi / 2) if isinstance(max_cant, Mapping) else max_cant
        faces.append(
            MountingFace(
                name=name, centre=sign * h[k] * e[k], normal=sign * e[k], axis_u=e[iu], axis_v=e[iv],
                half_u=float(h[iu]), half_v=float(h[iv]), max_cant=mc,
            )
        )
    if len({f.name for f in faces}) != len(faces):
        raise InputError(f"names must not repeat a face; got {list(names)}")
    return tuple(faces)


def _face_table(faces: Sequence[MountingFace]) -> dict[str, np.ndarray]:
    if isinstance(faces, str | bytes | MountingFace) or not isinstance(faces, Sequence) or not faces or not all(
            isinstance(f, MountingFace) for f in faces):
        raise InputTypeError(f"faces must be a non-empty sequence of MountingFace; got {short_repr(faces)}")
    return {
        "centre": np.stack([f.centre for f in faces]),
        "normal": np.stack([f.normal for f in faces]),
        "eu": np.stack([f.axis_u * f.half_u for f in faces]),
        "ev": np.stack([f.axis_v * f.half_v for f in faces]),
        "tu": np.stack([f.axis_u for f in faces]),
        "tv": np.stack([f.axis_v for f in faces]),
        "cant": np.array([f.max_cant for f in faces]),
    }


def _decode(X: np.ndarray, table: dict[str, np.ndarray]):
    """Genes (P, 5n) -> positions (P, n, 3), directions (P, n, 3), face index (P, n)."""
    P = X.shape[0]
    G = X.reshape(P, -1, GENES_PER_THRUSTER)
    nf = table["centre"].shape[0]
    k = np.clip(np.floor(G[..., 0]).astype(int), 0, nf - 1)
    u, v, c, phi = G[..., 1], G[..., 2], G[..., 3], G[..., 4]
    pos = table["centre"][k] + u[..., None] * table["eu"][k] + v[..., None] * table["ev"][k]
    theta = c * table["cant"][k]
    st = np.sin(theta)[..., None]
    d = (
        -np.cos(theta)[..., None] * table["normal"][k]
        + st * np.cos(phi)[..., None] * table["tu"][k]
        + st * np.sin(phi)[..., None] * table["tv"][k]
    )
    return pos, d, k


def decode_layout(
    genes: Any, faces: Sequence[MountingFace], *, com: Any = (0.0, 0.0, 0.0), **thruster_kw: Any
) -> ThrusterSet:
    """The :class:`ThrusterSet` encoded by a gene vector of length ``5 n`` (module docstring).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import box_faces, decode_layout
    >>> genes = [0.5, 0.0, 0.0, 0.0, 0.0,                  # face 0 (+X), centre, along -normal
    ...          2.5, 1.0, -1.0, 1.0, 0.0]                 # face 2 (+Y), corner, fully canted
    >>> ts = decode_layout(genes, box_faces())
    >>> ts.n, ts.names
    (2, ('+X', '+Y'))
    >>> ts.positions, ts.directions.round(12) + 0.0
    (array([[ 1.,  0.,  0.],
           [-1.,  1.,  1.]]), array([[-1.,  0.,  0.],
           [ 0.,  0.,  1.]]))
    """
    g = as_array("genes", genes, ndim=1)
    if g.size % GENES_PER_THRUSTER or g.size == 0:
        raise InputError(f"genes must have length 5 n (n >= 1); got {g.size}")
    table = _face_table(faces)
    G = g.reshape(-1, GENES_PER_THRUSTER)
    nf = len(faces)
    tol = 1e-9  # the optimisers' box bounds, up to rounding
    for col, what, lo, hi in ((0, "face gene s", 0.0, nf), (1, "u", -1.0, 1.0), (2, "v", -1.0, 1.0),
                              (3, "cant gene c", 0.0, 1.0)):
        bad = (G[:, col] < lo - tol) | (G[:, col] > hi + tol) | ((col == 0) & (G[:, col] >= hi))
        if np.any(bad):
            i = int(np.argmax(bad))
            span = f"[0, {nf}) for {nf} faces" if col == 0 else f"[{lo:g}, {hi:g}]"
            raise InputError(
                f"genes[{GENES_PER_THRUSTER * i + col}] ({what} of thruster {i}) must be in {span}; "
                f"got {float(G[i, col])!r}"
            )
    pos, d, k = _decode(g[None, :], table)
    return ThrusterSet(
        positions=pos[0], directions=d[0], com=com, names=tuple(faces[i].name for i in k[0]),
        **thruster_kw,
    )


# ----------------------------------------------------------------------------- objective


@dataclass(frozen=True, slots=True, kw_only=True)
class LayoutScore(Result):
    """S3 eq. 18 and its terms, per layout (arrays of shape ``(B,)``, or scalars).

    Attributes
    ----------
    fun : F_best (-)
    error : mean torque error over the demands (N m), eq. 15
    e_min : largest per-thruster minimum reachable error (rad), eq. 16
    sum_tp : mean over the demands of the summed on-times (s), eq. 17
    on_times : on-time per demand and thruster (s), shape ``(..., K, n)``

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import ThrusterSet
    >>> r = [[1, 0, 0], [1, 0, 0], [0, 1, 0], [0, 1, 0], [0, 0, 1], [0, 0, 1]]     # m
    >>> d = [[0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0]]  # +-z +-x +-y
    >>> ts = ThrusterSet(positions=np.array(r, float), directions=np.array(d, float), f_max=10.0)
    >>> from adcskit.thrusters import score_layout
    >>> s = score_layout(ts.torque_matrix(), np.array([[5.0, 0.0, 0.0], [0.0, 0.0, -3.0]]))
    >>> type(s).__name__, s.on_times.shape, round(float(s.error), 9)
    ('LayoutScore', (2, 6), 0.0)
    """

    fun: Any
    error: Any
    e_min: Any
    sum_tp: Any
    on_times: np.ndarray

    _dict_exclude = ("on_times",)  # per-thruster, per-demand on-times stay out


def _score(
    A: np.ndarray, demands: np.ndarray, fmax: np.ndarray, tmin: np.ndarray,
    t_s: float, gain: float, weights: tuple[float, float, float], per_actuator: int = 1,
):
    """A (B, 3, n), demands (K, 3), fmax/tmin (n,) -> fun, error, e_min, sum_tp, t_p (B, K, n).

    ``per_actuator`` thrusters fire together per column of ``A`` (2 for a couple of the
    paired reading): each burns the column's on-time, so ``sum_tp`` counts it that often.
    """
    F, errs = _rpi_layouts(np.ascontiguousarray(A), np.ascontiguousarray(demands), fmax)
    err = errs.mean(axis=1)
    tp = F * (t_s / fmax)
    sum_tp = per_actuator * tp.sum(axis=2).mean(axis=1)
    lever = np.linalg.norm(A, axis=1)  # (B, n)
    e_min = (lever * fmax * tmin / (t_s * gain)).max(axis=1)
    k1, k2, k3 = weights
    fun = k1 * err + k2 * e_min + k3 * sum_tp
    return fun, err, e_min, sum_tp, tp


def _check_weights(weights: Any) -> tuple[float, float, float]:
    w = as_array("weights", weights, shape=(3,))
    return float(w[0]), float(w[1]), float(w[2])


def score_layout(
    torque_matrix: Any,
    demands: Any,
    *,
    weights: Any = DEFAULT_WEIGHTS,
    f_max: Any = 10.0,
    t_min: Any = 3e-3,
    t_s: float = 0.2,
    gain: float = 600.0,
) -> LayoutScore:
    """Evaluate S3 eq. 18 for one layout ``(3, n)`` or a batch ``(B, 3, n)``.

    Forces come from ``pinv-redistribute`` (S3's allocation), the on-times from eq. 6.

    Parameters
    ----------
    torque_matrix : array_like, (3, n) or (B, 3, n), N m per N
    demands : array_like, (K, 3), N m
        The manoeuvre's demanded torques.
    weights : (K1, K2, K3)
        S3 Table 7 by default: (100, -99, 12).
    f_max, t_min : float or (n,), N and s
    t_s : float, s
    gain : float, N m/rad
        ``K`` of S3 eq. 11.

    References
    ----------
    S3 eq. 6, 15-18, Table 7.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import ThrusterSet
    >>> r = [[1, 0, 0], [1, 0, 0], [0, 1, 0], [0, 1, 0], [0, 0, 1], [0, 0, 1]]     # m
    >>> d = [[0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0]]  # +-z +-x +-y
    >>> ts = ThrusterSet(positions=np.array(r, float), directions=np.array(d, float), f_max=10.0)
    >>> from adcskit.thrusters import score_layout
    >>> demands = np.array([[5.0, 0.0, 0.0], [0.0, 0.0, -3.0]])   # N m
    >>> s = score_layout(ts.torque_matrix(), demands)
    >>> round(float(s.error), 9), round(float(s.sum_tp), 6)       # exact; mean on-time 0.08 s
    (0.0, 0.08)
    >>> s.on_times.round(6)
    array([[0.  , 0.  , 0.1 , 0.  , 0.  , 0.  ],
           [0.  , 0.06, 0.  , 0.  , 0.  , 0.  ]])
    >>> batch = score_layout(np.stack([ts.torque_matrix()] * 3), demands)
    >>> batch.fun.shape
    (3,)
    """
    A = as_array("torque_matrix", torque_matrix, ndim=(2, 3))
    single = A.ndim == 2
    if single:
        A = A[None]
    if A.shape[1] != 3:
        raise InputError(f"torque_matrix must have shape (3, n) or (B, 3, n); got {A.shape}")
    n = A.shape[2]
    D = as_array("demands", demands, ndim=2)
    if D.shape[1] != 3:
        raise InputError(f"demands must have shape (K, 3); got {D.shape}")
    fmax = check_positive_array("f_max", f_max, unit="N", min_value=1e-100, broadcast_to=(n,))
    tmin = check_positive_array("t_min", t_min, allow_zero=True, unit="s", broadcast_to=(n,))
    fun, err, e_min, sum_tp, tp = _score(
        A, D, fmax, tmin, check_positive("t_s", t_s, unit="s", min_value=1e-100),
        check_positive("gain", gain, unit="N m/rad", min_value=1e-100), _check_weights(weights),
    )
    if single:
        return LayoutScore(fun=float(fun[0]), error=float(err[0]), e_min=float(e_min[0]),
                           sum_tp=float(sum_tp[0]), on_times=tp[0])
    return LayoutScore(fun=fun, error=err, e_min=e_min, sum_tp=sum_tp, on_times=tp)


# ----------------------------------------------------------------------------- pymoo glue


def _make_problem(n: int, faces, demands, fmax, tmin, t_s, gain, weights, com, paired=False):
    from pymoo.core.problem import Problem

    table = _face_table(faces)
    per = 2 if paired else 1
    nf = len(faces)
    xl = np.tile([0.0, -1.0, -1.0, 0.0, 0.0], n)
    xu = np.tile([nf - 1e-9, 1.0, 1.0, 1.0, 2 * math.pi], n)

    class _LayoutProblem(Problem):
        def __init__(self) -> None:
            super().__init__(n_var=GENES_PER_THRUSTER * n, n_obj=1, xl=xl, xu=xu)

        def _evaluate(self, X, out, *args, **kwargs):
            pos, d, _ = _decode(X, table)
            # a couple (p, d) + (-p, -d) gives 2 p x d about any CoM (paired reading)
            A = np.swapaxes(2.0 * np.cross(pos, d) if paired else np.cross(pos - com, d), -1, -2)
            fun, *_ = _score(A, demands, fmax, tmin, t_s, gain, weights, per)
            out["F"] = fun[:, None]

    return _LayoutProblem()


def _current_to_best_variant(F: float, CR: float):
    """Storn & Price scheme DE2 (``lambda = F``) as a pymoo infill operator."""
    from pymoo.core.infill import InfillCriterion
    from pymoo.core.population import Population
    from pymoo.operators.repair.bounds_repair import repair_random_init

    class _CurrentToBest(InfillCriterion):
        def do(self, problem, pop, n_offsprings, random_state=None, algorithm=None, **kwargs):
            rs = random_state if random_state is not None else algorithm.random_state
            X = pop.get("X")
            f = pop.get("F")[:, 0]
            N, m = X.shape
            best = X[int(np.argmin(f))]
            idx = np.arange(n_offsprings) % N
            r1 = rs.integers(0, N - 1, size=n_offsprings)
            r1 = r1 + (r1 >= idx)
            r2 = rs.integers(0, N - 2, size=n_offsprings)
            lo, hi = np.minimum(idx, r1), np.maximum(idx, r1)
            r2 = r2 + (r2 >= lo)
            r2 = r2 + (r2 >= hi)
            Xi = X[idx]
            donor = Xi + F * (best - Xi) + F * (X[r1] - X[r2])
            donor = repair_random_init(donor, Xi, *problem.bounds(), random_state=rs)
            cross = rs.random((n_offsprings, m)) < CR
            cross[np.arange(n_offsprings), rs.integers(0, m, size=n_offsprings)] = True
            trial = np.where(cross, donor, Xi)
            return Population.new(X=trial)

    return _CurrentToBest()


def _make_algorithm(name: str, pop_size: int, de_strategy: str, F: float, CR: float):
    if name == "ga":
        from pymoo.algorithms.soo.nonconvex.ga import GA

        return GA(pop_size=pop_size, eliminate_duplicates=True)
    from pymoo.algorithms.soo.nonconvex.de import DE

    if de_strategy == "current-to-best/1/bin":
        return DE(pop_size=pop_size, variant=_current_to_best_variant(F, CR))
    return DE(pop_size=pop_size, variant="DE/rand/1/bin", F=F, CR=CR)


#: Optimisers of :func:`design_layout`.
DESIGN_ALGORITHMS = {
    "ga": "pymoo GA: tournament selection, SBX crossover, polynomial mutation, elitist survival",
    "de": "pymoo DE loop (one-to-one improvement replacement) with the chosen strategy",
}

#: DE strategies: Storn & Price's DE2 (S3's choice) and DE1.
DE_STRATEGIES = {
    "current-to-best/1/bin": "Storn & Price scheme DE2, lambda = F (S3: 'the second strategy')",
    "rand/1/bin": "Storn & Price scheme DE1 (pymoo 'DE/rand/1/bin')",
}


@dataclass(frozen=True, slots=True, repr=False, kw_only=True)
class LayoutResult(Result):
    """Outcome of :func:`design_layout`.

    Attributes
    ----------
    x : ndarray (5 n,)
        Best gene vector.
    thrusters : ThrusterSet
        The decoded best layout (``names`` = mounting faces).
    fun : float
        Best F_best (S3 eq. 18).
    error, e_min, sum_tp : float
        Its terms (N m, rad, s).
    torque_matrix : ndarray (3, n)
    success : bool
    status : int
    message : str
    nit : int
        Generations run.
    nfev : int
        Layouts evaluated.
    history : ndarray (nit,)
        Best F_best after each generation.
    runtime_s : float
        Wall-clock time of the optimisation.
    cpu_s : float
        CPU time of the optimisation in this process (insensitive to other jobs on the
        machine, unlike ``runtime_s``).
    algorithm : str

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import design_layout
    >>> demands = np.array([[5.0, 0.0, 0.0], [0.0, -5.0, 2.0]])     # N m
    >>> res = design_layout(4, demands, pop_size=8, n_gen=3, rng=0)
    >>> type(res).__name__, res.thrusters.n, res.x.shape, res.history.shape
    ('LayoutResult', 4, (20,), (3,))
    """

    x: np.ndarray
    thrusters: ThrusterSet
    fun: float
    error: float
    e_min: float
    sum_tp: float
    torque_matrix: np.ndarray
    success: bool
    status: int
    message: str
    nit: int
    nfev: int
    history: np.ndarray
    runtime_s: float
    cpu_s: float
    algorithm: str
    extra: dict[str, Any] = field(default_factory=dict)

    _dict_exclude = ("extra",)  # algorithm-specific extras stay out


def design_layout(
    n_thrusters: int,
    demands: Any,
    *,
    mounting: Sequence[MountingFace] | None = None,
    algorithm: str = "de",
    weights: Any = DEFAULT_WEIGHTS,
    f_max: float = 10.0,
    t_min: float = 3e-3,
    mdot: float = 3.5e-3,
    t_s: float = 0.2,
    gain: float = 600.0,
    com: Any = (0.0, 0.0, 0.0),
    pop_size: int = 50,
    n_gen: int = 400,
    de_strategy: str = "current-to-best/1/bin",
    de_F: float = 0.8,
    de_CR: float = 0.9,
    rng: Any = None,
    paired: bool = False,
) -> LayoutResult:
    """Design a thruster layout minimising S3 eq. 18 with pymoo's GA or DE.

    Parameters
    ----------
    n_thrusters : int
        Number of thrusters (S3: 4, 6, 8, 12).
    demands : array_like (K, 3), N m
        Demanded torques of the manoeuvre(s) the layout must serve.
    mounting : sequence of MountingFace, optional
        Allowed faces (default: the six faces of S3's 2 x 2 x 2 m box, :func:`box_faces`).
    algorithm : {"de", "ga"}
    weights : (K1, K2, K3)
        S3 Table 7: (100, -99, 12).
    f_max, t_min, mdot : float
        Thruster force (N), minimum on-time (s), mass flow (kg/s) — S3 Table 5, §6.
    t_s : float, s
        Sample time (S3 Table 6: 0.2).
    gain : float, N m/rad
        ``K`` (S3 Table 6: 600).
    com : array_like (3,), m
        Centre of mass (S3: origin).
    pop_size, n_gen : int
        Population (equal for GA and DE in S3; not printed) and generations (S3: 400).
    de_strategy : str
        One of ``DE_STRATEGIES``; default DE2 (module docstring).
    de_F, de_CR : float
        DE weight and crossover rate (Storn & Price 1997: F in [0.5, 1], CR = 0.9).
    rng : Generator or int, optional
        Seeds pymoo; same seed -> same layout.
    paired : bool
        The paired reading of S3 §4-1 ("thrusters on parallel faces act as a pair"): each
        gene is a couple, a thruster ``(p, d)`` and its twin ``(-p, -d)`` on the parallel
        face (point reflection through the box centre), fired together. A couple gives
        torque ``2 p x d`` and no net force; its impulse bit is ``2 Delta F_max t_min``, so
        its ``e_min`` is twice the single thruster's, and both members burn the on-time.
        ``n_thrusters`` must be even and every face's parallel face must be allowed.
        ``torque_matrix`` / ``thrusters`` list all ``n`` thrusters (twins second);
        ``extra["couple_matrix"]`` is the ``(3, n/2)`` matrix the allocation works on.

    Returns
    -------
    LayoutResult

    References
    ----------
    S3 §4-1 (constraint 2), §4-6, eq. 9-10, 18-20, Tables 1-7.

    Examples
    --------
    >>> from adcskit.thrusters import design_layout
    >>> demands = [[5.0, 0, 0], [0, 5.0, 0], [0, 0, 5.0], [-5.0, 0, 0], [0, -5.0, 0], [0, 0, -5.0]]
    >>> r = design_layout(6, demands, paired=True, pop_size=8, n_gen=3, rng=0)
    >>> r.torque_matrix.shape, r.extra["couple_matrix"].shape
    ((3, 6), (3, 3))
    >>> bool(abs(r.thrusters.force_matrix().sum(axis=1)).max() < 1e-12)  # couples: no net force
    True

    >>> import numpy as np
    >>> from adcskit.thrusters import design_layout
    >>> demands = np.array([[5.0, 0.0, 0.0], [0.0, -5.0, 2.0], [0.0, 0.0, 5.0]])   # N m
    >>> res = design_layout(6, demands, pop_size=10, n_gen=4, rng=0)   # S3: n_gen=400
    >>> res.thrusters.n, res.nit, res.history.shape, bool(np.all(np.diff(res.history) <= 0))
    (6, 4, (4,), True)
    >>> res2 = design_layout(6, demands, pop_size=10, n_gen=4, rng=0)
    >>> bool(res2.fun == res.fun)                          # same seed, same layout
    True
    """
    n = check_int("n_thrusters", n_thrusters, minimum=1, maximum=10_000)
    check_choice("algorithm", algorithm, DESIGN_ALGORITHMS)
    check_choice("de_strategy", de_strategy, DE_STRATEGIES)
    if mounting is not None and (
            isinstance(mounting, str | bytes | MountingFace) or not isinstance(mounting, Iterable)):
        raise InputTypeError(f"mounting must be a non-empty sequence of MountingFace; got {short_repr(mounting)}")
    faces = tuple(mounting) if mounting is not None else box_faces()
    if len(faces) == 0 or not all(isinstance(f, MountingFace) for f in faces):
        raise InputError(f"mounting must be a non-empty sequence of MountingFace; got {short_repr(mounting)}")
    if not isinstance(paired, bool | np.bool_):
        raise InputError(f"paired must be a bool; got {paired!r}")
    twin = _parallel_faces(faces) if paired else None
    if paired and n % 2:
        raise InputError(f"n_thrusters must be even with paired=True (couples); got {n}")
    D = as_array("demands", demands, ndim=2)
    if D.shape[1] != 3 or D.shape[0] < 1:
        raise InputError(f"demands must have shape (K, 3) with K >= 1; got {D.shape}")
    w = _check_weights(weights)
    fmax = np.full(n, check_positive("f_max", f_max, unit="N", min_value=1e-100))
    tmin = np.full(n, check_positive("t_min", t_min, allow_zero=True, unit="s"))
    mdot = check_positive("mdot", mdot, unit="kg/s")
    t_s = check_positive("t_s", t_s, unit="s", min_value=1e-100)
    gain = check_positive("gain", gain, unit="N m/rad", min_value=1e-100)
    com = as_array("com", com, shape=(3,))
    pop_size = check_int("pop_size", pop_size, minimum=4, maximum=100_000)
    n_gen = check_int("n_gen", n_gen, minimum=1, maximum=1_000_000)
    de_F = check_positive("de_F", de_F)
    de_CR = check_range("de_CR", de_CR, 0.0, 1.0)
    seed = int(as_rng(rng).integers(2**31 - 1))

    from pymoo.core.callback import Callback
    from pymoo.optimize import minimize

    class _Best(Callback):
        def __init__(self) -> None:
            super().__init__()
            self.best: list[float] = []

        def notify(self, algo) -> None:
            self.best.append(float(np.min(algo.pop.get("F"))))

    n_act = n // 2 if paired else n
    problem = _make_problem(n_act, faces, D, fmax[:n_act], tmin[:n_act], t_s, gain, w, com, paired)
    algo = _make_algorithm(algorithm, pop_size, de_strategy, de_F, de_CR)
    cb = _Best()
    t0, c0 = time.perf_counter(), time.process_time()
    res = minimize(problem, algo, ("n_gen", n_gen), seed=seed, verbose=False, callback=cb,
                   copy_algorithm=False)
    runtime, cpu = time.perf_counter() - t0, time.process_time() - c0
    x = np.atleast_2d(res.X)[0]
    extra: dict[str, Any] = {}
    if paired:
        face_names = [f.name for f in faces]
        one = decode_layout(x, faces)
        ts = ThrusterSet(
            positions=np.vstack([one.positions, -one.positions]),
            directions=np.vstack([one.directions, -one.directions]), com=com,
            names=tuple(one.names) + tuple(faces[twin[face_names.index(nm)]].name for nm in one.names),
            f_max=fmax, t_min=tmin, mdot=mdot,
        )
        A = ts.torque_matrix()
        A_score = 2.0 * np.cross(one.positions, one.directions).T
        extra = {"paired": True, "couple_matrix": A_score}
    else:
        ts = decode_layout(x, faces, com=com, f_max=fmax, t_min=tmin, mdot=mdot)
        A = A_score = ts.torque_matrix()
    fun, err, e_min, sum_tp, _ = _score(A_score[None], D, fmax[:n_act], tmin[:n_act], t_s, gain, w,
                                        2 if paired else 1)
    history = np.minimum.accumulate(np.asarray(cb.best)) if cb.best else np.array([float(fun[0])])
    return LayoutResult(
        x=x, thrusters=ts, fun=float(fun[0]), error=float(err[0]), e_min=float(e_min[0]),
        sum_tp=float(sum_tp[0]), torque_matrix=A, success=True, status=0,
        message=f"{algorithm}: {len(cb.best)} generations of {pop_size}",
        nit=len(cb.best), nfev=int(algo.evaluator.n_eval), history=history, runtime_s=runtime, cpu_s=cpu,
        algorithm=algorithm if algorithm == "ga" else f"de:{de_strategy}", extra=extra,
    )


def _parallel_faces(faces: Sequence[MountingFace]) -> list[int]:
    """Index of each face's parallel (point-reflected) face; InputError if one is missing."""
    out = []
    for f in faces:
        j = next((i for i, g in enumerate(faces)
                  if np.allclose(g.centre, -f.centre) and np.allclose(g.normal, -f.normal)
                  and np.isclose(g.half_u, f.half_u) and np.isclose(g.half_v, f.half_v)), None)
        if j is None:
            raise InputError(
                f"paired=True needs the parallel face of every mounting face; face {f.name!r} has none "
                f"among {[g.name for g in faces]}"
            )
        out.append(j)
    return out
