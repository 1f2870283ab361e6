"""The general optimal-control problem, meshes and initial guesses.

A problem is data: the dynamics ``f(x, u, t)`` written once with operations that CasADi
symbols support (``+ - * /``, ``casadi.vertcat``, ``casadi.sin``, ``casadi.mtimes`` ...),
box bounds, boundary values, a Mayer + Lagrange cost, free or fixed final time and optional
path constraints. The same function is evaluated symbolically for the NLP and numerically
(through a compiled :class:`casadi.Function`) for re-simulation.

References
----------
S2, eq. 8–11 (Bolza problem), eq. 17–21 (transformation to ``τ ∈ [-1, 1]``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from adcskit._validation import (
    as_array,
    check_finite,
    check_int,
    check_positive,
    check_real,
    short_repr,
)
from adcskit.errors import InputError, InputTypeError

__all__ = ["OptimalControlProblem", "Mesh", "Guess"]


def _vec(
    name: str, value: Any, n: int, default: float, *, finite: bool = False, allow: str = "any"
) -> np.ndarray:
    """A length-``n`` vector (a scalar is broadcast); ``allow`` says which non-finite entries
    are meaningful: ``"any"``, ``"nan"`` (free entries, no infinities), ``"inf"`` (``±inf``
    bounds, no NaN) or ``"nan-or-positive"`` (NaN = default, else finite > 0)."""
    if value is None:
        return np.full(n, default, dtype=float)
    arr = as_array(name, value, finite=False)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    if arr.shape != (n,):
        raise InputError(f"{name} must have shape ({n},); got shape {arr.shape}")
    if finite and not np.all(np.isfinite(arr)):
        raise InputError(f"{name} must be finite; got {arr}")
    if allow == "nan" and np.any(np.isinf(arr)):
        raise InputError(f"{name} must be finite or NaN (NaN: free); got {arr} (an infinite entry)")
    if allow == "inf" and np.any(np.isnan(arr)):
        raise InputError(f"{name} must be numbers or ±inf (no bound); got {arr} (NaN is not a bound)")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class OptimalControlProblem:
    """A single-phase Bolza optimal-control problem (S2 eq. 8–11).

    Minimise ``J = φ(x(t0), t0, x(tf), tf) + ∫ g(x, u, t) dt`` subject to ``ẋ = f(x, u, t)``,
    box bounds on states and controls, fixed or free boundary values and
    ``path_lower <= C(x, u, t) <= path_upper``.

    Parameters
    ----------
    dynamics : callable
        ``f(x, u, t) -> (n_states,)`` written with CasADi-compatible operations. ``x`` and
        ``u`` are column vectors (index them ``x[0]``), ``t`` a scalar (s).
    n_states, n_controls : int
    state_names, control_names : tuple of str, optional
    state_lower, state_upper, control_lower, control_upper : array_like, optional
        Box bounds (``±inf`` allowed), in the problem's units.
    initial_state, final_state : array_like, optional
        Boundary values; ``NaN`` entries are free (only the box bounds apply).
    t0 : float
        Initial time (s), fixed.
    tf_bounds : (float, float)
        Bounds of the final time (s); equal values fix it.
    tf_guess : float, optional
        Initial guess of ``tf`` (s); default the mid-point of finite ``tf_bounds``.
    mayer : callable, optional
        ``φ(x0, t0, xf, tf) -> scalar``.
    lagrange : callable, optional
        ``g(x, u, t) -> scalar``.
    path : callable, optional
        ``C(x, u, t) -> (n_path,)`` enforced at the collocation points (eq. 33).
    path_lower, path_upper : array_like, optional
    state_scale, control_scale : array_like, optional
        Characteristic magnitudes for NLP scaling (default from bounds/boundary values).
    name : str

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.optimal_control import OptimalControlProblem, solve
    >>> def f(x, u, t):                                   # double integrator x'' = u
    ...     return [x[1], u[0]]
    >>> def energy(x, u, t):
    ...     return u[0] * u[0]
    >>> ocp = OptimalControlProblem(dynamics=f, n_states=2, n_controls=1,
    ...                             initial_state=[0.0, 0.0], final_state=[1.0, 0.0],
    ...                             tf_bounds=(2.0, 2.0), lagrange=energy, name="move-1m-in-2s")
    >>> ocp.free_final_time
    False
    >>> sol = solve(ocp, mesh=(4, 3))
    >>> sol.success, round(sol.objective, 6)              # analytic 12 d^2 / T^3 = 1.5
    (True, 1.5)
    """

    dynamics: Callable[..., Any]
    n_states: int
    n_controls: int
    state_names: tuple[str, ...] = ()
    control_names: tuple[str, ...] = ()
    state_lower: Any = None
    state_upper: Any = None
    control_lower: Any = None
    control_upper: Any = None
    initial_state: Any = None
    final_state: Any = None
    t0: float = 0.0
    tf_bounds: tuple[float, float] = (0.0, np.inf)
    tf_guess: float | None = None
    mayer: Callable[..., Any] | None = None
    lagrange: Callable[..., Any] | None = None
    path: Callable[..., Any] | None = None
    path_lower: Any = None
    path_upper: Any = None
    state_scale: Any = None
    control_scale: Any = None
    name: str = "ocp"
    _n_path: int = field(default=0, repr=False)

    def __post_init__(self) -> None:
        if not callable(self.dynamics):
            raise InputTypeError(f"dynamics must be callable f(x, u, t); got {self.dynamics!r}")
        nx = check_int("n_states", self.n_states, minimum=1, maximum=100_000)
        nu = check_int("n_controls", self.n_controls, minimum=0, maximum=100_000)
        s = object.__setattr__
        s(self, "state_names", tuple(self.state_names) or tuple(f"x{i}" for i in range(nx)))
        s(self, "control_names", tuple(self.control_names) or tuple(f"u{i}" for i in range(nu)))
        if len(self.state_names) != nx or len(self.control_names) != nu:
            raise InputError(
                f"state_names/control_names must have {nx}/{nu} entries; got "
                f"{len(self.state_names)}/{len(self.control_names)}"
            )
        s(self, "state_lower", _vec("state_lower", self.state_lower, nx, -np.inf, allow="inf"))
        s(self, "state_upper", _vec("state_upper", self.state_upper, nx, np.inf, allow="inf"))
        s(self, "control_lower", _vec("control_lower", self.control_lower, nu, -np.inf, allow="inf"))
        s(self, "control_upper", _vec("control_upper", self.control_upper, nu, np.inf, allow="inf"))
        s(self, "initial_state", _vec("initial_state", self.initial_state, nx, np.nan, allow="nan"))
        s(self, "final_state", _vec("final_state", self.final_state, nx, np.nan, allow="nan"))
        for lo, hi, what in (
            (self.state_lower, self.state_upper, "state"),
            (self.control_lower, self.control_upper, "control"),
        ):
            if np.any(lo > hi):
                raise InputError(f"{what}_lower must be <= {what}_upper; got {lo} > {hi}")
        for which in ("initial_state", "final_state"):
            v = getattr(self, which)
            bad = np.isfinite(v) & ((v < self.state_lower) | (v > self.state_upper))
            if np.any(bad):
                raise InputError(f"{which} must lie inside the state bounds; got {v}")
        s(self, "t0", check_finite("t0", self.t0))
        try:
            lo, hi = (check_real("tf_bounds", v) for v in self.tf_bounds)
        except (TypeError, ValueError):
            raise InputTypeError(f"tf_bounds must be two numbers (s); got {self.tf_bounds!r}") from None
        if not (lo >= self.t0 and hi >= lo and hi > self.t0) or np.isnan(hi):
            raise InputError(
                f"tf_bounds must satisfy t0 <= lower <= upper, upper > t0 (s); got ({lo}, {hi}) with t0={self.t0}"
            )
        s(self, "tf_bounds", (lo, hi))
        if self.tf_guess is None:
            guess = 0.5 * (lo + hi) if np.isfinite(hi) else lo + 1.0
        else:
            guess = check_positive("tf_guess", self.tf_guess, unit="s")
            if not lo <= guess <= hi:
                raise InputError(f"tf_guess must be inside tf_bounds {self.tf_bounds} (s); got {guess}")
        s(self, "tf_guess", float(guess))
        for which, sig in (("mayer", "(x0, t0, xf, tf)"), ("lagrange", "(x, u, t)"), ("path", "(x, u, t)")):
            fn = getattr(self, which)
            if fn is not None and not callable(fn):
                raise InputTypeError(f"{which} must be a callable {which}{sig} or None; got {short_repr(fn)}")
        if self.mayer is None and self.lagrange is None:
            raise InputError("the problem needs a cost: give mayer(x0, t0, xf, tf) and/or lagrange(x, u, t)")
        npath = 0
        if self.path is not None:
            if self.path_lower is None and self.path_upper is None:
                raise InputError("path constraints need path_lower and/or path_upper")
            ref = self.path_lower if self.path_lower is not None else self.path_upper
            npath = int(np.size(ref))
            s(self, "path_lower", _vec("path_lower", self.path_lower, npath, -np.inf, allow="inf"))
            s(self, "path_upper", _vec("path_upper", self.path_upper, npath, np.inf, allow="inf"))
            if np.any(self.path_lower > self.path_upper):
                raise InputError(
                    f"path_lower must be <= path_upper; got {self.path_lower} > {self.path_upper}"
                )
        s(self, "_n_path", npath)
        for which, n in (("state_scale", nx), ("control_scale", nu)):
            given = getattr(self, which)
            v = _vec(which, given, n, np.nan)
            if given is not None and (np.any(~np.isfinite(v)) or np.any(v <= 0)):
                raise InputError(f"{which} must be finite and > 0 (or None for the default); got {v}")
            s(self, which, v)

    # ------------------------------------------------------------------ helpers
    @property
    def free_final_time(self) -> bool:
        """True when ``tf`` is a decision variable."""
        return self.tf_bounds[0] < self.tf_bounds[1]

    @property
    def n_path(self) -> int:
        """Number of path constraints."""
        return self._n_path

    def replace(self, **changes: Any) -> OptimalControlProblem:
        """A copy with some fields changed (e.g. new boundary values); callables are shared,
        so the compiled NLP is reused (see :func:`adcskit.optimal_control.solve`)."""
        kw = {f: getattr(self, f) for f in self.__dataclass_fields__ if not f.startswith("_")}
        for which in ("state_scale", "control_scale"):
            if np.all(np.isnan(kw[which])):  # the default (None), stored as NaN
                kw[which] = None
        kw.update(changes)
        return OptimalControlProblem(**kw)

    def scales(self) -> tuple[np.ndarray, np.ndarray]:
        """State and control scales used by the NLP (given, else from bounds/boundary values)."""
        return _default_scale(
            self.state_scale, self.state_lower, self.state_upper, self.initial_state, self.final_state
        ), _default_scale(self.control_scale, self.control_lower, self.control_upper)


def _default_scale(given, lower, upper, *values) -> np.ndarray:
    out = np.array(given, dtype=float)
    for i in range(out.size):
        if np.isfinite(out[i]):
            continue
        cands = [abs(lower[i]), abs(upper[i])]
        if not all(np.isfinite(cands)):
            cands = [abs(v[i]) for v in values if np.isfinite(v[i])]
        m = max(cands, default=0.0)
        out[i] = m if np.isfinite(m) and m > 0 else 1.0
    return out


@dataclass(frozen=True, slots=True)
class Mesh:
    """A multi-interval mesh: number of collocation points per interval and interval lengths.

    Parameters
    ----------
    nodes : tuple of int
        Collocation points in each interval (>= 1).
    fractions : tuple of float, optional
        Interval lengths as fractions of ``tf − t0`` (sum 1); default equal intervals, as in
        S2 ("20 equal sub-intervals × 3 LG points").

    Examples
    --------
    >>> from adcskit.optimal_control import Mesh
    >>> mesh = Mesh(nodes=(3, 3, 4), fractions=(0.25, 0.25, 0.5))
    >>> mesh.n_intervals, mesh.breaks.round(6)
    (3, array([0.  , 0.25, 0.5 , 1.  ]))
    >>> Mesh.uniform(20, 3).n_intervals                   # S2: 20 equal intervals x 3 LG points
    20
    """

    nodes: tuple[int, ...]
    fractions: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        if isinstance(self.nodes, str | bytes) or not isinstance(self.nodes, Iterable):
            raise InputTypeError(f"mesh nodes must be a sequence of integers; got {short_repr(self.nodes)}")
        nodes = tuple(check_int("mesh nodes", n, minimum=1, maximum=1000) for n in np.asarray(self.nodes, dtype=object).ravel())
        if not nodes:
            raise InputError("mesh nodes must list at least one interval; got ()")
        if len(nodes) > 100_000:
            raise InputError(f"mesh nodes must list at most 100000 intervals; got {len(nodes)}")
        fr = tuple(as_array("mesh fractions", self.fractions, ndim=1, nonempty=False).tolist()) or tuple(
            [1.0 / len(nodes)] * len(nodes))
        if len(fr) != len(nodes) or any(f <= 0 for f in fr) or abs(sum(fr) - 1.0) > 1e-12:
            raise InputError(f"mesh fractions must be {len(nodes)} positive numbers summing to 1; got {fr}")
        object.__setattr__(self, "nodes", nodes)
        object.__setattr__(self, "fractions", fr)

    @classmethod
    def uniform(cls, n_intervals: int, n_nodes: int) -> Mesh:
        """``n_intervals`` equal intervals with ``n_nodes`` collocation points each."""
        n_intervals = check_int("n_intervals", n_intervals, minimum=1, maximum=100_000)
        n_nodes = check_int("n_nodes", n_nodes, minimum=1, maximum=1000)
        return cls(nodes=(n_nodes,) * n_intervals)

    @property
    def n_intervals(self) -> int:
        return len(self.nodes)

    @property
    def breaks(self) -> np.ndarray:
        """Interval boundaries as fractions of ``tf − t0``, from 0 to 1."""
        return np.concatenate(([0.0], np.cumsum(self.fractions)))

    def label(self) -> str:
        n = set(self.nodes)
        return f"{self.n_intervals}x{self.nodes[0]}" if len(n) == 1 else f"{self.n_intervals} intervals"


@dataclass(frozen=True, slots=True, kw_only=True)
class Guess:
    """An initial guess: trajectories sampled at times ``t`` (linearly interpolated onto the mesh).

    Attributes
    ----------
    t : (M,) ndarray
        Sample times (s), increasing, from ``t0`` to ``tf``.
    x : (M, n_states) ndarray
    u : (M, n_controls) ndarray
    tf : float
        Final time (s); must equal ``t[-1]`` (to 1e-9·max(1, abs(tf))), else InputError.
    t_u : (K,) ndarray, optional
        Sample times of ``u`` when they differ from ``t``.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.optimal_control import Guess, solve
    >>> from adcskit.optimal_control.problems import double_integrator_min_energy
    >>> t = np.linspace(0.0, 1.0, 5)
    >>> guess = Guess(t=t, x=np.column_stack([t, np.ones(5)]), u=np.zeros((5, 1)), tf=1.0)
    >>> guess.x.shape, guess.tf
    ((5, 2), 1.0)
    >>> sol = solve(double_integrator_min_energy(), mesh=(4, 3), guess=guess)
    >>> sol.success, round(sol.objective, 6)
    (True, 12.0)
    """

    t: np.ndarray
    x: np.ndarray
    u: np.ndarray
    tf: float
    t_u: np.ndarray | None = None

    def __post_init__(self) -> None:
        t = as_array("guess.t", self.t, ndim=1)
        if t.size < 2 or np.any(np.diff(t) <= 0):
            raise InputError(f"guess.t must hold >= 2 increasing times (s); got {t}")
        x = as_array("guess.x", self.x, shape=(t.size, None))
        tu = t if self.t_u is None else as_array("guess.t_u", self.t_u, ndim=1)
        u = as_array("guess.u", self.u, shape=(tu.size, None))
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "x", x)
        object.__setattr__(self, "u", u)
        object.__setattr__(self, "t_u", None if self.t_u is None else tu)
        tf = check_positive("guess.tf", self.tf, unit="s")
        if abs(t[-1] - tf) > 1e-9 * max(1.0, abs(tf)):
            raise InputError(f"guess.tf = {tf!r} s must equal guess.t[-1] = {float(t[-1])!r} s (the samples end at the "
                             "final time); allowed: guess.t[-1] == guess.tf to 1e-9·max(1, |tf|)")
        object.__setattr__(self, "tf", tf)

    def check_widths(self, n_states: int, n_controls: int, *, what: str = "guess") -> None:
        """Raise :class:`InputError` unless ``x`` has ``n_states`` and ``u`` ``n_controls`` columns.

        Examples
        --------
        >>> import numpy as np
        >>> from adcskit.optimal_control import Guess
        >>> g = Guess(t=[0.0, 1.0], x=np.zeros((2, 3)), u=np.zeros((2, 1)), tf=1.0)
        >>> try:
        ...     g.check_widths(2, 1)
        ... except ValueError as exc:
        ...     print(exc)
        guess.x must have shape (2, 2) (samples, n_states); got shape (2, 3)
        """
        n_states = check_int("n_states", n_states, minimum=1)
        n_controls = check_int("n_controls", n_controls, minimum=0)
        for arr, n, field_name, label in ((self.x, n_states, "x", "n_states"), (self.u, n_controls, "u", "n_controls")):
            if arr.shape[1] != n:
                raise InputError(
                    f"{what}.{field_name} must have shape ({arr.shape[0]}, {n}) (samples, {label}); got shape {arr.shape}"
                )
