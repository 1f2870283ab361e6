"""Multi-phase optimal control: phases linked in time and state, static parameters, event
(boundary) constraints and integral constraints, transcribed phase by phase by the Gauss or
Radau method and solved as one NLP by IPOPT.

Problem (the general multiple-phase problem of GPOPS-II, Patterson & Rao 2014, eq. 1–6)::

    minimise   Φ(E¹, …, E^P, p) + Σ_k ∫ g_k(x, u, t, p) dt
    subject to ẋ = f_k(x, u, t, p)                 in phase k,
               C_k,min <= C_k(x, u, t, p) <= C_k,max   (path),
               q_k,min <= ∫ q_k(x, u, t, p) dt <= q_k,max   (integral constraints),
               ψ_min <= ψ(E¹, …, E^P, p) <= ψ_max      (events / boundary conditions),
               x₀^(b)[S] − x_f^(a)[S] = Δ,  t₀^(b) = t_f^(a)   (linkages),

with ``E^k = (x₀, t₀, x_f, t_f, q)`` the endpoint of phase ``k`` and ``p`` static parameters
optimised with the trajectory. Phase start and end times are decision variables within
their bounds (free phase durations).

Each phase uses the multi-interval layout of :mod:`adcskit.optimal_control.transcription`
(support states, controls at the collocation points, Gauss end state and quadrature row,
continuity rows between intervals) and the same scaling; costates and the Hamiltonian of
every phase come from the KKT multipliers by the same mapping as :func:`solve`.

References
----------
Patterson & Rao, "GPOPS-II", ACM Trans. Math. Softw. 41(1), 2014, §2 (multiple-phase
problem). Benson et al. 2006; Garg et al. 2010 (transcriptions and costate mapping). S2
eq. 17–37.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from adcskit._results import compact_repr
from adcskit._validation import as_array, check_choice, check_flag, check_int
from adcskit.errors import InputError, InputTypeError
from adcskit.optimal_control._nlp import (
    _as_mesh,
    _assemble,
    _bound_duals,
    _defect_duals,
    _interp_fun,
    _path_duals,
    _resolve_options,
    _run_ipopt,
    _solution_funs,
    cached_nlp,
)
from adcskit.optimal_control.problem import Guess, Mesh, OptimalControlProblem, _default_scale, _vec
from adcskit.optimal_control.solve import OptimalControlSolution, ipopt_status_code
from adcskit.optimal_control.transcription import (
    METHODS,
    _as_list,
    _scalar,
    collocation_rows,
    interval_bounds,
    interval_layout,
    interval_symbols,
    interval_times,
    pack_intervals,
    quadrature,
    unpack_intervals,
)

__all__ = [
    "Endpoint",
    "Link",
    "MultiPhaseGuess",
    "MultiPhaseProblem",
    "MultiPhaseSolution",
    "Phase",
    "solve_multiphase",
]


def _pair(name: str, value) -> tuple[float, float]:
    lo, hi = as_array(name, value, shape=(2,), finite=False, max_abs=None).tolist()
    if np.isnan(lo) or np.isnan(hi) or lo > hi:
        raise InputError(f"{name} must satisfy lower <= upper; got ({lo}, {hi})")
    return lo, hi


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Phase:
    """One phase of a :class:`MultiPhaseProblem`.

    Parameters
    ----------
    dynamics : callable
        ``f(x, u, t, p) -> (n_states,)`` with CasADi-compatible operations (``p``: the
        static parameters, an empty vector when there are none).
    n_states, n_controls : int
    state_names, control_names : tuple of str, optional
    state_lower, state_upper, control_lower, control_upper : array_like, optional
        Box bounds (``±inf`` allowed).
    initial_state, final_state : array_like, optional
        Fixed boundary values; ``NaN`` entries are free.
    t0_bounds, tf_bounds : (float, float)
        Bounds of the phase's start and end times (s); equal values fix them.
    duration_bounds : (float, float)
        Bounds of ``tf − t0`` (s).
    t0_guess, tf_guess : float, optional
        Initial guesses (s); default from the bounds and the previous phase.
    lagrange : callable, optional
        ``g(x, u, t, p) -> scalar``, integrated over the phase and added to the cost.
    path : callable, optional
        ``C(x, u, t, p) -> (n_path,)`` at the collocation points, with ``path_lower``,
        ``path_upper``.
    integrand : callable, optional
        ``q(x, u, t, p) -> (n_integrals,)``; ``∫ q dt`` is bounded by ``integral_lower``,
        ``integral_upper`` and passed to the objective and events as ``Endpoint.q``.
    state_scale, control_scale : array_like, optional
        NLP scaling magnitudes (default from bounds / boundary values).
    name : str

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.optimal_control import Phase, MultiPhaseProblem, solve_multiphase
    >>> f = lambda x, u, t, p: [x[1], u[0]]
    >>> acc = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[1], control_upper=[1],
    ...             initial_state=[0, 0], tf_bounds=(0, 10))
    >>> dec = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[-1], control_upper=[-1],
    ...             final_state=[np.nan, 0], t0_bounds=(0, 10), tf_bounds=(0, 10))
    >>> prob = MultiPhaseProblem(phases=[acc, dec], n_parameters=1, parameter_lower=[1],
    ...     parameter_upper=[1], objective=lambda e, p: e[1].tf,
    ...     events=lambda e, p: [e[1].xf[0] - p[0]], event_lower=[0], event_upper=[0])

    >>> acc.n_states, acc.n_controls
    (2, 1)
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
    t0_bounds: tuple[float, float] = (0.0, 0.0)
    tf_bounds: tuple[float, float] = (0.0, np.inf)
    duration_bounds: tuple[float, float] = (0.0, np.inf)
    t0_guess: float | None = None
    tf_guess: float | None = None
    lagrange: Callable[..., Any] | None = None
    path: Callable[..., Any] | None = None
    path_lower: Any = None
    path_upper: Any = None
    integrand: Callable[..., Any] | None = None
    integral_lower: Any = None
    integral_upper: Any = None
    state_scale: Any = None
    control_scale: Any = None
    name: str = "phase"

    def __post_init__(self) -> None:
        if not callable(self.dynamics):
            raise InputTypeError(f"dynamics must be callable f(x, u, t, p); got {self.dynamics!r}")
        nx = check_int("n_states", self.n_states, minimum=1, maximum=100_000)
        nu = check_int("n_controls", self.n_controls, minimum=0, maximum=100_000)
        s = object.__setattr__
        s(self, "state_names", tuple(self.state_names) or tuple(f"x{i}" for i in range(nx)))
        s(self, "control_names", tuple(self.control_names) or tuple(f"u{i}" for i in range(nu)))
        if len(self.state_names) != nx or len(self.control_names) != nu:
            raise InputError(f"state_names/control_names must have {nx}/{nu} entries")
        for nm, n, d, allow in (
            ("state_lower", nx, -np.inf, "inf"),
            ("state_upper", nx, np.inf, "inf"),
            ("control_lower", nu, -np.inf, "inf"),
            ("control_upper", nu, np.inf, "inf"),
            ("initial_state", nx, np.nan, "nan"),
            ("final_state", nx, np.nan, "nan"),
            ("state_scale", nx, np.nan, "any"),
            ("control_scale", nu, np.nan, "any"),
        ):
            s(self, nm, _vec(nm, getattr(self, nm), n, d, allow=allow))
        if np.any(self.state_lower > self.state_upper):
            raise InputError("state_lower must be <= state_upper")
        if np.any(self.control_lower > self.control_upper):
            raise InputError("control_lower must be <= control_upper")
        for which in ("initial_state", "final_state"):
            v = getattr(self, which)
            if np.any(np.isfinite(v) & ((v < self.state_lower) | (v > self.state_upper))):
                raise InputError(f"{which} must lie inside the state bounds; got {v}")
        for nm in ("t0_bounds", "tf_bounds", "duration_bounds"):
            s(self, nm, _pair(nm, getattr(self, nm)))
        if not np.isfinite(self.t0_bounds[0]) or not np.isfinite(self.t0_bounds[1]):
            raise InputError(f"t0_bounds must be finite (s); got {self.t0_bounds}")
        if self.tf_bounds[1] <= self.t0_bounds[0]:
            raise InputError(f"tf_bounds {self.tf_bounds} must allow tf > t0 (t0_bounds {self.t0_bounds})")
        for nm in ("lagrange", "path", "integrand"):
            v = getattr(self, nm)
            if v is not None and not callable(v):
                raise InputTypeError(f"{nm} must be callable (x, u, t, p); got {v!r}")
        for fn, lo, hi in (("path", "path_lower", "path_upper"), ("integrand", "integral_lower", "integral_upper")):
            if getattr(self, fn) is None:
                continue
            lv, hv = getattr(self, lo), getattr(self, hi)
            if lv is None and hv is None:
                raise InputError(f"{fn} needs {lo} and/or {hi}")
            n = int(np.size(lv if lv is not None else hv))
            s(self, lo, _vec(lo, lv, n, -np.inf, allow="inf"))
            s(self, hi, _vec(hi, hv, n, np.inf, allow="inf"))
            if np.any(getattr(self, lo) > getattr(self, hi)):
                raise InputError(f"{lo} must be <= {hi}; got {getattr(self, lo)} > {getattr(self, hi)}")
        for nm in ("t0_guess", "tf_guess"):
            v = getattr(self, nm)
            if v is not None and not np.isfinite(float(v)):
                raise InputError(f"{nm} must be finite (s); got {v}")

    @property
    def n_path(self) -> int:
        return 0 if self.path is None else int(self.path_lower.size)

    @property
    def n_integrals(self) -> int:
        return 0 if self.integrand is None else int(self.integral_lower.size)

    def scales(self) -> tuple[np.ndarray, np.ndarray]:
        return _default_scale(
            self.state_scale, self.state_lower, self.state_upper, self.initial_state, self.final_state
        ), _default_scale(self.control_scale, self.control_lower, self.control_upper)


@dataclass(frozen=True, slots=True)
class Link:
    """Linkage of phase ``b``'s start to phase ``a``'s end.

    ``x₀^(b)[states_b] − x_f^(a)[states_a] = jump`` and, when ``time``, ``t₀^(b) = t_f^(a)``.

    Parameters
    ----------
    a, b : int
        Phase indices.
    states : sequence of int or None
        Linked state indices (the same in both phases); None links all (equal dimensions).
    jump : float or array_like
        Prescribed state jump (e.g. a stage's dropped mass); 0 for continuity.
    time : bool
        Link the times.

    Examples
    --------
    >>> from adcskit.optimal_control import Link
    >>> Link(0, 1)          # state and time continuity from phase 0 to phase 1
    Link(a=0, b=1, states=None, jump=0.0, time=True)
    """

    a: int
    b: int
    states: tuple[int, ...] | None = None
    jump: Any = 0.0
    time: bool = True

    def __post_init__(self) -> None:
        check_int("a", self.a, minimum=0)
        check_int("b", self.b, minimum=0)
        as_array("jump", self.jump)
        check_flag("time", self.time)


@dataclass(slots=True)
class Endpoint:
    """Symbolic endpoint of a phase passed to the objective and event functions.

    Attributes
    ----------
    x0, xf : casadi vector
        Initial / final state.
    t0, tf : casadi scalar
        Initial / final time (s).
    q : casadi vector
        Integrals ``∫ q dt`` of the phase's ``integrand`` (empty without one).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.optimal_control import Phase, MultiPhaseProblem, solve_multiphase
    >>> f = lambda x, u, t, p: [x[1], u[0]]
    >>> acc = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[1], control_upper=[1],
    ...             initial_state=[0, 0], tf_bounds=(0, 10))
    >>> dec = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[-1], control_upper=[-1],
    ...             final_state=[np.nan, 0], t0_bounds=(0, 10), tf_bounds=(0, 10))
    >>> prob = MultiPhaseProblem(phases=[acc, dec], n_parameters=1, parameter_lower=[1],
    ...     parameter_upper=[1], objective=lambda e, p: e[1].tf,
    ...     events=lambda e, p: [e[1].xf[0] - p[0]], event_lower=[0], event_upper=[0])

    >>> sol = solve_multiphase(prob, meshes=[(1, 3), (1, 3)])   # events/objective receive Endpoints
    >>> round(sol.phases[1].tf, 8)
    2.0
    """

    x0: Any
    t0: Any
    xf: Any
    tf: Any
    q: Any


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class MultiPhaseProblem:
    """A multiple-phase optimal-control problem (Patterson & Rao 2014, §2).

    Parameters
    ----------
    phases : sequence of Phase
    objective : callable, optional
        ``Φ(ends, p) -> scalar`` with ``ends`` a list of :class:`Endpoint`, one per phase.
        The phases' Lagrange terms are added.
    n_parameters : int
        Static parameters ``p`` optimised with the trajectory.
    parameter_names : tuple of str, optional
    parameter_lower, parameter_upper, parameter_guess, parameter_scale : array_like, optional
    events : callable, optional
        ``ψ(ends, p) -> (n_events,)`` with ``event_lower <= ψ <= event_upper``.
    event_lower, event_upper : array_like, optional
    links : "continuous" or sequence of Link
        ``"continuous"``: state and time continuity between consecutive phases.
    name : str

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.optimal_control import Phase, MultiPhaseProblem, solve_multiphase
    >>> f = lambda x, u, t, p: [x[1], u[0]]
    >>> acc = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[1], control_upper=[1],
    ...             initial_state=[0, 0], tf_bounds=(0, 10))
    >>> dec = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[-1], control_upper=[-1],
    ...             final_state=[np.nan, 0], t0_bounds=(0, 10), tf_bounds=(0, 10))
    >>> prob = MultiPhaseProblem(phases=[acc, dec], n_parameters=1, parameter_lower=[1],
    ...     parameter_upper=[1], objective=lambda e, p: e[1].tf,
    ...     events=lambda e, p: [e[1].xf[0] - p[0]], event_lower=[0], event_upper=[0])

    >>> len(prob.phases), prob.n_parameters
    (2, 1)
    """

    phases: Sequence[Phase]
    objective: Callable[..., Any] | None = None
    n_parameters: int = 0
    parameter_names: tuple[str, ...] = ()
    parameter_lower: Any = None
    parameter_upper: Any = None
    parameter_guess: Any = None
    parameter_scale: Any = None
    events: Callable[..., Any] | None = None
    event_lower: Any = None
    event_upper: Any = None
    links: Any = "continuous"
    name: str = "multiphase"

    def __post_init__(self) -> None:
        s = object.__setattr__
        phases = tuple(self.phases) if isinstance(self.phases, Sequence) else None
        if not phases or not all(isinstance(p, Phase) for p in phases):
            raise InputTypeError(f"phases must be a non-empty sequence of Phase; got {self.phases!r}")
        s(self, "phases", phases)
        npar = check_int("n_parameters", self.n_parameters, minimum=0, maximum=100_000)
        s(self, "parameter_names", tuple(self.parameter_names) or tuple(f"p{i}" for i in range(npar)))
        if len(self.parameter_names) != npar:
            raise InputError(f"parameter_names must have {npar} entries")
        s(self, "parameter_lower", _vec("parameter_lower", self.parameter_lower, npar, -np.inf))
        s(self, "parameter_upper", _vec("parameter_upper", self.parameter_upper, npar, np.inf))
        if np.any(self.parameter_lower > self.parameter_upper):
            raise InputError("parameter_lower must be <= parameter_upper")
        lo, hi = self.parameter_lower, self.parameter_upper
        mid = np.where(np.isfinite(lo) & np.isfinite(hi), 0.5 * (lo + hi), np.where(np.isfinite(lo), lo, np.where(np.isfinite(hi), hi, 0.0)))
        g = _vec("parameter_guess", self.parameter_guess, npar, np.nan)
        g = np.where(np.isfinite(g), g, mid)
        g.setflags(write=False)
        s(self, "parameter_guess", g)
        sc = _vec("parameter_scale", self.parameter_scale, npar, np.nan)
        sc = np.where(np.isfinite(sc), sc, np.maximum(np.abs(g), 1.0))
        if np.any(sc <= 0):
            raise InputError(f"parameter_scale must be > 0; got {sc}")
        sc.setflags(write=False)
        s(self, "parameter_scale", sc)
        if self.objective is None and all(p.lagrange is None for p in phases):
            raise InputError("the problem needs a cost: objective(ends, p) and/or a phase lagrange")
        if self.objective is not None and not callable(self.objective):
            raise InputTypeError(f"objective must be callable (ends, p); got {self.objective!r}")
        if self.events is not None:
            if not callable(self.events):
                raise InputTypeError(f"events must be callable (ends, p); got {self.events!r}")
            if self.event_lower is None and self.event_upper is None:
                raise InputError("events need event_lower and/or event_upper")
            n = int(np.size(self.event_lower if self.event_lower is not None else self.event_upper))
            s(self, "event_lower", _vec("event_lower", self.event_lower, n, -np.inf))
            s(self, "event_upper", _vec("event_upper", self.event_upper, n, np.inf))
        links = self.links
        if isinstance(links, str):
            if links != "continuous":
                raise InputError(f"links must be 'continuous' or a sequence of Link; got {links!r}")
            links = tuple(Link(k, k + 1) for k in range(len(phases) - 1))
        if links is None or not hasattr(links, "__iter__"):
            raise InputTypeError(f"links must be 'continuous' or a sequence of Link (use () for no links); got {links!r}")
        links = tuple(links)
        for lk in links:
            if not isinstance(lk, Link):
                raise InputTypeError(f"links must hold Link objects; got {lk!r}")
            if not (0 <= lk.a < len(phases) and 0 <= lk.b < len(phases)) or lk.a == lk.b:
                raise InputError(f"link phases must be two distinct indices in [0, {len(phases)}); got {lk}")
            na, nb = phases[lk.a].n_states, phases[lk.b].n_states
            if lk.states is None and na != nb:
                raise InputError(f"link {lk.a}->{lk.b}: phases have {na} and {nb} states; give Link.states")
            idx = range(na) if lk.states is None else lk.states
            if any(not (0 <= i < min(na, nb)) for i in idx):
                raise InputError(f"link {lk.a}->{lk.b}: state indices must be < {min(na, nb)}; got {lk.states}")
        s(self, "links", links)

    @property
    def n_events(self) -> int:
        return 0 if self.events is None else int(self.event_lower.size)


@dataclass(frozen=True, slots=True, kw_only=True)
class MultiPhaseGuess:
    """Initial guess of a multi-phase problem: one :class:`Guess` per phase (its ``t`` spans
    ``t0`` to ``tf`` of the phase) and the parameters.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.optimal_control import Phase, MultiPhaseProblem, solve_multiphase
    >>> f = lambda x, u, t, p: [x[1], u[0]]
    >>> acc = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[1], control_upper=[1],
    ...             initial_state=[0, 0], tf_bounds=(0, 10))
    >>> dec = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[-1], control_upper=[-1],
    ...             final_state=[np.nan, 0], t0_bounds=(0, 10), tf_bounds=(0, 10))
    >>> prob = MultiPhaseProblem(phases=[acc, dec], n_parameters=1, parameter_lower=[1],
    ...     parameter_upper=[1], objective=lambda e, p: e[1].tf,
    ...     events=lambda e, p: [e[1].xf[0] - p[0]], event_lower=[0], event_upper=[0])

    >>> from adcskit.optimal_control import default_multiphase_guess
    >>> g = default_multiphase_guess(prob)
    >>> len(g.phases), g.parameters.shape
    (2, (1,))
    """

    phases: tuple[Guess, ...]
    parameters: np.ndarray

    def __post_init__(self) -> None:
        if not isinstance(self.phases, Sequence) or not all(isinstance(g, Guess) for g in self.phases):
            raise InputTypeError("MultiPhaseGuess.phases must hold Guess objects")
        object.__setattr__(self, "phases", tuple(self.phases))
        object.__setattr__(self, "parameters", as_array("parameters", self.parameters, ndim=1, nonempty=False))


def default_multiphase_guess(problem: MultiPhaseProblem) -> MultiPhaseGuess:
    """Straight lines between boundary values (free ends: the linked neighbour's value, the
    middle of finite bounds, else 0), controls at the middle of finite bounds (else 0), times
    from the guesses/bounds, each phase starting where the previous one ends.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.optimal_control import Phase, MultiPhaseProblem, solve_multiphase
    >>> f = lambda x, u, t, p: [x[1], u[0]]
    >>> acc = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[1], control_upper=[1],
    ...             initial_state=[0, 0], tf_bounds=(0, 10))
    >>> dec = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[-1], control_upper=[-1],
    ...             final_state=[np.nan, 0], t0_bounds=(0, 10), tf_bounds=(0, 10))
    >>> prob = MultiPhaseProblem(phases=[acc, dec], n_parameters=1, parameter_lower=[1],
    ...     parameter_upper=[1], objective=lambda e, p: e[1].tf,
    ...     events=lambda e, p: [e[1].xf[0] - p[0]], event_lower=[0], event_upper=[0])

    >>> g = default_multiphase_guess(prob)
    >>> len(g.phases)
    2
    """
    if not isinstance(problem, MultiPhaseProblem):
        raise InputTypeError(f"problem must be a MultiPhaseProblem; got {type(problem).__name__}")
    out = []
    t_prev = None
    x_prev = None
    for ph in problem.phases:
        lo, hi = ph.t0_bounds
        t0 = ph.t0_guess if ph.t0_guess is not None else (lo if lo == hi or t_prev is None else float(np.clip(t_prev, lo, hi)))
        if ph.tf_guess is not None:
            tf = ph.tf_guess
        else:
            dlo, dhi = ph.duration_bounds
            dur = 0.5 * (dlo + dhi) if np.isfinite(dhi) else max(dlo, 1.0)
            flo, fhi = ph.tf_bounds
            tf = t0 + dur
            if np.isfinite(fhi) and flo > t0:
                tf = 0.5 * (flo + fhi) if flo < fhi else flo
            tf = float(np.clip(tf, flo, fhi))
            if tf <= t0:
                tf = t0 + max(dlo, 1.0)
        both = np.isfinite(ph.state_lower) & np.isfinite(ph.state_upper)
        mid = np.zeros(ph.n_states)
        mid[both] = 0.5 * (ph.state_lower[both] + ph.state_upper[both])
        x0 = np.array(ph.initial_state, float)
        if x_prev is not None and x_prev.size == x0.size:
            x0 = np.where(np.isfinite(x0), x0, x_prev)
        xf = np.array(ph.final_state, float)
        x0 = np.where(np.isfinite(x0), x0, np.where(np.isfinite(xf), xf, mid))
        xf = np.where(np.isfinite(xf), xf, x0)
        cb = np.isfinite(ph.control_lower) & np.isfinite(ph.control_upper)
        u = np.zeros(ph.n_controls)
        u[cb] = 0.5 * (ph.control_lower[cb] + ph.control_upper[cb])
        u = np.clip(u, ph.control_lower, ph.control_upper)
        out.append(Guess(t=np.array([t0, tf]), x=np.vstack([x0, xf]), u=np.vstack([u, u]), tf=max(tf, 1e-12)))
        t_prev, x_prev = tf, xf
    return MultiPhaseGuess(phases=tuple(out), parameters=np.array(problem.parameter_guess, float))


# ----------------------------------------------------------------------------- transcription
@dataclass(slots=True)
class _PhaseLayout:
    intervals: list
    i_t0: int
    i_tf: int
    g_path: slice
    g_dur: int
    g_int: slice
    f_fun: Any
    g_fun: Any
    h_fun: Any


class _MultiTranscription:
    def __init__(self, problem: MultiPhaseProblem, method: str, meshes: tuple[Mesh, ...], ipopt: dict):
        self.method = method
        self.meshes = meshes
        npar = problem.n_parameters
        iz = 0
        ig = 0
        layouts: list[_PhaseLayout] = []
        for ph, mesh in zip(problem.phases, meshes, strict=True):
            nx, nu = ph.n_states, ph.n_controls
            ivs, iz, ig = interval_layout(method, mesh, nx, nu, iz, ig)
            i_t0, i_tf = iz, iz + 1
            iz += 2
            g_path = slice(ig, ig + ph.n_path * sum(mesh.nodes))
            ig = g_path.stop
            g_dur = ig
            ig += 1
            g_int = slice(ig, ig + ph.n_integrals)
            ig = g_int.stop
            x = ca.SX.sym("x", nx)
            u = ca.SX.sym("u", nu)
            t = ca.SX.sym("t")
            p = ca.SX.sym("p", npar)
            fx = ca.vertcat(*_as_list(ph.dynamics(x, u, t, p), nx, f"{ph.name} dynamics"))
            gx = ca.SX(0) if ph.lagrange is None else _scalar(ph.lagrange(x, u, t, p), "lagrange")
            lam = ca.SX.sym("lam", nx)
            ham = gx + ca.dot(lam, fx)
            layouts.append(
                _PhaseLayout(
                    ivs,
                    i_t0,
                    i_tf,
                    g_path,
                    g_dur,
                    g_int,
                    ca.Function("f", [x, u, t, p], [fx]),
                    ca.Function("g", [x, u, t, p], [gx]),
                    ca.Function("H", [x, u, t, p, lam], [ham, ca.gradient(ham, u) if nu else ca.SX(0, 1)]),
                )
            )
        self.i_p = slice(iz, iz + npar)
        iz += npar
        self.nz = iz
        self.layouts = layouts
        n_link_rows = sum(
            (problem.phases[lk.a].n_states if lk.states is None else len(lk.states)) + (1 if lk.time else 0)
            for lk in problem.links
        )
        self.g_links = slice(ig, ig + n_link_rows)
        ig = self.g_links.stop
        self.g_events = slice(ig, ig + problem.n_events)
        ig = self.g_events.stop
        self.ng = ig

        # ------------------------------------------------------------ symbolic NLP
        z = ca.SX.sym("z", self.nz)
        # parameters of the NLP: per phase [sx, su], then [s_t (per phase), s_p, cJ]
        n_np = sum(ph.n_states + ph.n_controls + 1 for ph in problem.phases) + npar + 1
        par = ca.SX.sym("par", n_np)
        off = 0
        phase_scales = []
        for ph in problem.phases:
            nx, nu = ph.n_states, ph.n_controls
            phase_scales.append((par[off : off + nx], par[off + nx : off + nx + nu], par[off + nx + nu]))
            off += nx + nu + 1
        pscale = par[off : off + npar]
        cJ = par[off + npar]
        pvec = z[self.i_p] * pscale if npar else ca.SX(0, 1)
        ordered = []
        J = ca.SX(0)
        ends = []
        for ph, lay, (sx, su, st) in zip(problem.phases, layouts, phase_scales, strict=True):
            nx, nu = ph.n_states, ph.n_controls
            t0 = z[lay.i_t0] * st
            tf = z[lay.i_tf] * st
            T = tf - t0
            per = interval_symbols(method, lay.intervals, z, sx, su, t0, T, nx, nu, ca.SX)
            ntot = sum(iv.n for iv in lay.intervals)
            Xc_all = ca.horzcat(*[q.Xc for q in per])
            U_all = ca.horzcat(*[q.U for q in per])
            T_all = ca.horzcat(*[q.tc for q in per])
            P_all = ca.repmat(pvec, 1, ntot)
            F_all = lay.f_fun.map(ntot)(Xc_all, U_all, T_all, P_all)
            ordered += collocation_rows(lay.intervals, per, F_all, sx)
            if ph.lagrange is not None:
                J = quadrature(lay.intervals, per, lay.g_fun.map(ntot)(Xc_all, U_all, T_all, P_all), J)
            qint = ca.SX.zeros(ph.n_integrals)
            if ph.integrand is not None:
                qf = _fun("q", ph.integrand, nx, nu, npar, ph.n_integrals)
                qint = quadrature(lay.intervals, per, qf.map(ntot)(Xc_all, U_all, T_all, P_all), qint)
            if ph.n_path:
                cf = _fun("C", ph.path, nx, nu, npar, ph.n_path)
                ordered.append(ca.vec(cf.map(ntot)(Xc_all, U_all, T_all, P_all)))
            ordered.append((tf - t0) / st)
            if ph.n_integrals:
                ordered.append(qint)
            ends.append(Endpoint(x0=per[0].Xs[:, 0], t0=t0, xf=per[-1].Xend, tf=tf, q=qint))
        for lk in problem.links:
            ea, eb = ends[lk.a], ends[lk.b]
            idx = list(range(problem.phases[lk.a].n_states)) if lk.states is None else list(lk.states)
            sxa = phase_scales[lk.a][0]
            ordered.append((eb.x0[idx] - ea.xf[idx]) / sxa[idx])
            if lk.time:
                ordered.append((eb.t0 - ea.tf) / phase_scales[lk.a][2])
        if problem.events is not None:
            ordered.append(ca.vertcat(*_as_list(problem.events(ends, pvec), problem.n_events, "events")))
        if problem.objective is not None:
            J = J + _scalar(problem.objective(ends, pvec), "objective")
        g = ca.vertcat(*ordered)
        if g.numel() != self.ng:
            raise RuntimeError(f"internal layout error: {g.numel()} rows, expected {self.ng}")
        self.J_fun = ca.Function("J", [z, par], [J])
        self.g_fun = ca.Function("g", [z, par], [g])
        self.ends_fun = ca.Function(
            "E", [z, par], [ca.vertcat(*[ca.vertcat(e.t0, e.tf, e.q) for e in ends])]
        )
        self.events_fun = (
            ca.Function("psi", [z, par], [ordered[-1]]) if problem.events is not None else None
        )
        self.solver = ca.nlpsol("mpocp", "ipopt", {"x": z, "p": par, "f": J / cJ, "g": g}, {"print_time": False, "ipopt": dict(ipopt)})

    # ------------------------------------------------------------------ numeric helpers
    def scales(self, problem, t_guess):
        out = []
        vec = []
        for ph, g in zip(problem.phases, t_guess, strict=True):
            sx, su = ph.scales()
            st = max(abs(g[0]), abs(g[1]), abs(g[1] - g[0]), 1e-9)
            out.append((sx, su, st))
            vec += [sx, su, [st]]
        vec += [problem.parameter_scale, [1.0]]
        return out, np.concatenate(vec)

    def bounds(self, problem, scales):
        lbz = np.full(self.nz, -np.inf)
        ubz = np.full(self.nz, np.inf)
        lbg = np.zeros(self.ng)
        ubg = np.zeros(self.ng)
        for ph, lay, (sx, su, st), mesh in zip(problem.phases, self.layouts, scales, self.meshes, strict=True):
            interval_bounds(lbz, ubz, self.method, lay.intervals, ph, sx, su)
            lbz[lay.i_t0], ubz[lay.i_t0] = ph.t0_bounds[0] / st, ph.t0_bounds[1] / st
            lbz[lay.i_tf], ubz[lay.i_tf] = ph.tf_bounds[0] / st, ph.tf_bounds[1] / st
            if ph.n_path:
                ntot = sum(mesh.nodes)
                lbg[lay.g_path] = np.tile(ph.path_lower, ntot)
                ubg[lay.g_path] = np.tile(ph.path_upper, ntot)
            lbg[lay.g_dur], ubg[lay.g_dur] = ph.duration_bounds[0] / st, ph.duration_bounds[1] / st
            if ph.n_integrals:
                lbg[lay.g_int], ubg[lay.g_int] = ph.integral_lower, ph.integral_upper
        row = self.g_links.start
        for lk in problem.links:
            n = problem.phases[lk.a].n_states if lk.states is None else len(lk.states)
            idx = list(range(n)) if lk.states is None else list(lk.states)
            jump = np.broadcast_to(np.asarray(lk.jump, float), (n,)) / scales[lk.a][0][idx]
            lbg[row : row + n] = ubg[row : row + n] = jump
            row += n + (1 if lk.time else 0)
        if problem.n_events:
            lbg[self.g_events], ubg[self.g_events] = problem.event_lower, problem.event_upper
        npar = problem.n_parameters
        if npar:
            lbz[self.i_p] = problem.parameter_lower / problem.parameter_scale
            ubz[self.i_p] = problem.parameter_upper / problem.parameter_scale
        return lbz, ubz, lbg, ubg

    def times(self, lay, t0, tf):
        return interval_times(lay.intervals, t0, tf)

    def lagrangian_gradient(self, z, p, lam_f, lam_g):
        """``(f, g, ∇_z(lam_f f + lam_gᵀ g), ∇_p)`` of the scaled NLP (IPOPT's oracle)."""
        fun = getattr(self, "_grad_fun", None)
        if fun is None:
            fun = self._grad_fun = self.solver.get_function("nlp_grad")
        return fun(z, p, lam_f, lam_g)


def _fun(name, fn, nx, nu, npar, nout):
    x, u, t, p = ca.SX.sym("x", nx), ca.SX.sym("u", nu), ca.SX.sym("t"), ca.SX.sym("p", npar)
    return ca.Function(name, [x, u, t, p], [ca.vertcat(*_as_list(fn(x, u, t, p), nout, name))])


def _get(problem, method, meshes, opts):
    """The cached compiled NLP of this problem object on these meshes (the one cache of
    :mod:`adcskit.optimal_control._nlp`)."""
    key = ("multi-phase", problem, method, meshes, tuple(sorted((k, repr(v)) for k, v in opts.items())))
    return cached_nlp(key, lambda: _MultiTranscription(problem, method, meshes, opts))


# ----------------------------------------------------------------------------- solution
@compact_repr
@dataclass(frozen=True, slots=True, kw_only=True)
class MultiPhaseSolution:
    """Result of :func:`solve_multiphase` (and of :func:`solve_adaptive` on a multi-phase
    problem, which fills the error fields).

    Attributes
    ----------
    success : bool
    status : int
        scipy-style code (see :data:`adcskit.optimal_control.solve.IPOPT_STATUS_CODES`).
    ipopt_status, message : str
        IPOPT's ``return_status`` and a one-line summary.
    nit, nfev : int
    objective : float
    parameters : (n_parameters,) ndarray
        Optimised static parameters.
    phases : tuple of OptimalControlSolution
        Per phase: states, controls, costates, Hamiltonian, switching function, with the
        parameters fixed at their optimum (so :func:`resimulate` and :func:`bang_bang` apply).
    integrals : tuple of ndarray
        ``∫ q dt`` per phase.
    events : (n_events,) ndarray
        ``ψ`` at the solution.
    method : str
    meshes : tuple of Mesh
    max_violation : float
    build_s, solve_s : float
    max_error : float
        Adaptive solves: largest relative interval error (NaN otherwise).
    interval_errors : tuple of ndarray
        Adaptive solves: per phase, the relative error of every interval.
    mesh_history : tuple of MeshIteration
    certificate : ErrorCertificate or None
    warm_start : str
        ``"cold"``, ``"primal"`` (a previous solution's polynomials on these meshes) or
        ``"primal-dual-interpolated"`` (and its multipliers; ``transfer_duals``).
    nlp : object or None
        The raw NLP point and row layout (for warm starts).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.optimal_control import Phase, MultiPhaseProblem, solve_multiphase
    >>> f = lambda x, u, t, p: [x[1], u[0]]
    >>> acc = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[1], control_upper=[1],
    ...             initial_state=[0, 0], tf_bounds=(0, 10))
    >>> dec = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[-1], control_upper=[-1],
    ...             final_state=[np.nan, 0], t0_bounds=(0, 10), tf_bounds=(0, 10))
    >>> prob = MultiPhaseProblem(phases=[acc, dec], n_parameters=1, parameter_lower=[1],
    ...     parameter_upper=[1], objective=lambda e, p: e[1].tf,
    ...     events=lambda e, p: [e[1].xf[0] - p[0]], event_lower=[0], event_upper=[0])

    >>> sol = solve_multiphase(prob, meshes=[(1, 3), (1, 3)])
    >>> sol.success, len(sol.phases), round(float(sol.parameters[0]), 8)
    (True, 2, 1.0)
    """

    success: bool
    status: int
    message: str
    nit: int
    nfev: int
    objective: float
    parameters: np.ndarray
    phases: tuple[OptimalControlSolution, ...]
    integrals: tuple[np.ndarray, ...]
    events: np.ndarray
    method: str
    meshes: tuple[Mesh, ...]
    max_violation: float
    build_s: float
    solve_s: float
    problem: MultiPhaseProblem = field(repr=False)
    max_error: float = float("nan")
    interval_errors: tuple = ()
    mesh_history: tuple = ()
    certificate: Any = None
    ipopt_status: str = ""
    warm_start: str = "cold"
    nlp: Any = field(repr=False, default=None)

    def with_adaptive(self, **changes) -> MultiPhaseSolution:
        """A copy with the adaptive-refinement fields (used by :func:`solve_adaptive`)."""
        return dataclasses.replace(self, **changes)

    def as_guess(self) -> MultiPhaseGuess:
        """This solution as an initial guess (warm start) on any meshes."""
        return MultiPhaseGuess(phases=tuple(p.as_guess() for p in self.phases), parameters=self.parameters)

    def to_dict(self) -> dict[str, Any]:
        return {
            "success": self.success,
            "status": self.status,
            "ipopt_status": self.ipopt_status,
            "message": self.message,
            "nit": self.nit,
            "warm_start": self.warm_start,
            "objective": self.objective,
            "parameters": self.parameters,
            "events": self.events,
            "integrals": list(self.integrals),
            "method": self.method,
            "meshes": [m.label() for m in self.meshes],
            "max_violation": self.max_violation,
            "build_s": self.build_s,
            "solve_s": self.solve_s,
            "max_error": self.max_error,
            "mesh_history": [m.to_dict() for m in self.mesh_history],
            "certificate": None if self.certificate is None else self.certificate.to_dict(),
            "phases": [p.to_dict() for p in self.phases],
        }


def _as_multiguess(problem, guess) -> MultiPhaseGuess:
    if guess is None:
        return default_multiphase_guess(problem)
    if isinstance(guess, MultiPhaseSolution):
        return guess.as_guess()
    if isinstance(guess, MultiPhaseGuess):
        if len(guess.phases) != len(problem.phases) or guess.parameters.size != problem.n_parameters:
            raise InputError(
                f"guess must have {len(problem.phases)} phases and {problem.n_parameters} parameters; "
                f"got {len(guess.phases)} and {guess.parameters.size}"
            )
        for i, (ph, g) in enumerate(zip(problem.phases, guess.phases, strict=True)):
            g.check_widths(ph.n_states, ph.n_controls, what=f"guess.phases[{i}]")
        return guess
    raise InputTypeError(f"guess must be a MultiPhaseGuess or MultiPhaseSolution; got {type(guess).__name__}")


def solve_multiphase(
    problem: MultiPhaseProblem,
    *,
    method: str = "radau",
    meshes: Sequence[Mesh | tuple[int, int]] | None = None,
    guess: MultiPhaseGuess | MultiPhaseSolution | None = None,
    ipopt_options: dict[str, Any] | None = None,
    transfer_duals: bool = False,
) -> MultiPhaseSolution:
    """Transcribe a multi-phase problem and solve it with IPOPT.

    Parameters
    ----------
    problem : MultiPhaseProblem
    method : {"radau", "gauss"}
    meshes : sequence of Mesh or (int, int), optional
        One mesh per phase; default ``(10, 4)`` each.
    guess : MultiPhaseGuess or MultiPhaseSolution, optional
        Default :func:`default_multiphase_guess`; a previous solution on any meshes
        warm-starts (primal values, from its collocation polynomials).
    ipopt_options : dict, optional
    transfer_duals : bool
        With a previous solution of the same problem as ``guess``: also pass IPOPT its
        multipliers interpolated onto ``meshes`` (each phase as in :func:`solve`; the
        phase-duration, integral, linkage and event multipliers, whose rows do not depend on
        the mesh, as they are) and use :data:`WARM_START_IPOPT_OPTIONS`
        (``warm_start="primal-dual-interpolated"``). Default False: primal values with
        IPOPT's default options (``"primal"``).

    Returns
    -------
    MultiPhaseSolution
        ``success=False`` with IPOPT's status when the solve fails.

    References
    ----------
    Patterson & Rao 2014, §2–3 (multiple-phase transcription); S2 eq. 17–37.

    Examples
    --------
    Two phases of a double integrator joined at a free switch time, with the distance as a
    static parameter fixed by an event (``x_f = p``, ``p = 1``): the minimum-time
    rest-to-rest move, ``tf = 2``.

    >>> from adcskit.optimal_control import Phase, MultiPhaseProblem, solve_multiphase
    >>> f = lambda x, u, t, p: [x[1], u[0]]
    >>> acc = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[1], control_upper=[1],
    ...             initial_state=[0, 0], tf_bounds=(0, 10))
    >>> dec = Phase(dynamics=f, n_states=2, n_controls=1, control_lower=[-1], control_upper=[-1],
    ...             final_state=[np.nan, 0], t0_bounds=(0, 10), tf_bounds=(0, 10))
    >>> prob = MultiPhaseProblem(phases=[acc, dec], n_parameters=1, parameter_lower=[1],
    ...     parameter_upper=[1], objective=lambda e, p: e[1].tf,
    ...     events=lambda e, p: [e[1].xf[0] - p[0]], event_lower=[0], event_upper=[0])
    >>> sol = solve_multiphase(prob, meshes=[(1, 3), (1, 3)])
    >>> sol.success, round(sol.objective, 8)
    (True, 2.0)
    """
    if not isinstance(problem, MultiPhaseProblem):
        raise InputTypeError(f"problem must be a MultiPhaseProblem; got {type(problem).__name__}")
    method = check_choice("method", method, METHODS)
    if meshes is None:
        meshes = [Mesh.uniform(10, 4)] * len(problem.phases)
    if isinstance(meshes, Mesh) or not isinstance(meshes, Sequence) or len(meshes) != len(problem.phases):
        raise InputError(f"meshes must be a sequence of {len(problem.phases)} meshes (one per phase); got {meshes!r}")
    meshes = tuple(_as_mesh(m) for m in meshes)
    transfer_duals = check_flag("transfer_duals", transfer_duals)
    g = _as_multiguess(problem, guess)
    prev = guess if isinstance(guess, MultiPhaseSolution) and guess.problem is problem else None
    transfer = transfer_duals and prev is not None and prev.nlp is not None and prev.method == method
    opts = _resolve_options(ipopt_options, warm=transfer)
    t_build = time.perf_counter()
    try:
        tr = _get(problem, method, meshes, opts)
    except (TypeError, ValueError, RuntimeError, NotImplementedError) as exc:
        if isinstance(exc, RuntimeError) and "ipopt" in str(exc).lower() and "option" in str(exc).lower():
            # CasADi refusing an IPOPT option (unknown name, wrong type): the options, not the problem
            lines = [ln for ln in str(exc).splitlines() if ln.strip()]
            raise InputError(f"ipopt_options not accepted by IPOPT: {lines[-1] if lines else exc}; "
                             f"got {ipopt_options!r}") from None
        # a user function with the wrong signature, output size or a non-CasADi operation
        raise InputTypeError(
            f"problem functions must be f(x, u, t, p) / g / path / integrand (x, u, t, p) and "
            f"objective / events (ends, p) returning the declared sizes with CasADi operations; "
            f"building the NLP failed: {exc}"
        ) from None
    build_s = time.perf_counter() - t_build
    return _solve(problem, tr, g, build_s, prev, transfer)


def _solve(
    problem: MultiPhaseProblem,
    tr: _MultiTranscription,
    g: MultiPhaseGuess,
    build_s: float,
    prev=None,
    transfer: bool = False,
) -> MultiPhaseSolution:
    t_guess = []
    for ph, gp in zip(problem.phases, g.phases, strict=True):
        t0 = float(np.clip(gp.t[0], *ph.t0_bounds))
        tf = float(np.clip(gp.tf, *ph.tf_bounds))
        if tf <= t0:
            tf = t0 + max(ph.duration_bounds[0], 1e-3)
        t_guess.append((t0, tf))
    scales, par = tr.scales(problem, t_guess)
    z0 = np.zeros(tr.nz)
    for k, (_ph, lay, gp, (t0, tf), (sx, su, st)) in enumerate(
        zip(problem.phases, tr.layouts, g.phases, t_guess, scales, strict=True)
    ):
        if prev is not None:  # a previous solution: its own polynomials, time-rescaled
            xfun, ufun = _solution_funs(prev.phases[k], t0, tf)
        else:
            g0, gf = float(gp.t[0]), float(gp.tf)
            xfun = _interp_fun(gp.t, gp.x, g0, gf, t0, tf)
            ufun = _interp_fun(gp.t if gp.t_u is None else gp.t_u, gp.u, g0, gf, t0, tf)
        pack_intervals(z0, lay.intervals, t0, tf, xfun, ufun, sx, su)
        z0[lay.i_t0], z0[lay.i_tf] = t0 / st, tf / st
    if problem.n_parameters:
        z0[tr.i_p] = g.parameters / problem.parameter_scale
    lbz, ubz, lbg, ubg = tr.bounds(problem, scales)
    z0 = np.clip(z0, lbz, ubz)
    j0 = float(tr.J_fun(z0, par))
    cJ = abs(j0) if np.isfinite(j0) and abs(j0) > 1e-12 else 1.0
    par[-1] = cJ
    duals: dict[str, np.ndarray] = {}
    mode = "cold" if prev is None else "primal"
    if transfer:
        d = _multi_duals(problem, tr, prev, z0, par, scales, t_guess, lbz, ubz)
        if d is not None:
            duals = {"lam_x0": d[0], "lam_g0": d[1]}
            mode = "primal-dual-interpolated"
    z, lam_g, lam_x, gv, stats, status, success, solve_s = _run_ipopt(tr.solver, z0, par, lbz, ubz, lbg, ubg, duals)
    if not (np.all(np.isfinite(z)) and np.all(np.isfinite(lam_g))):
        # IPOPT stopped on a non-finite iterate: report the starting point, never NaN
        z, lam_g, lam_x = z0.copy(), np.zeros_like(lam_g), np.zeros_like(lam_x)
        gv = np.asarray(tr.g_fun(z, par)).ravel()
        success = False
        status = f"{status} (non-finite iterate; the initial guess is reported)"
    gfin = np.where(np.isfinite(gv), gv, 0.0)
    viol = float(np.max(np.concatenate([[0.0], lbg - gfin, gfin - ubg, lbz - z, z - ubz])))
    nit = int(stats.get("iter_count", 0))
    pval = z[tr.i_p] * problem.parameter_scale if problem.n_parameters else np.zeros(0)
    endv = np.asarray(tr.ends_fun(z, par)).ravel()
    phases = []
    integrals = []
    off = 0
    for k, (ph, lay, (sx, su, st)) in enumerate(zip(problem.phases, tr.layouts, scales, strict=True)):
        t0 = float(z[lay.i_t0] * st)
        tf = float(z[lay.i_tf] * st)
        integrals.append(endv[off + 2 : off + 2 + ph.n_integrals].copy())
        off += 2 + ph.n_integrals
        phases.append(_phase_solution(k, ph, lay, tr, z, lam_g, sx, su, t0, tf, pval, cJ, success, status, nit, viol))
    events = np.asarray(tr.events_fun(z, par)).ravel() if tr.events_fun is not None else np.zeros(0)
    objective = float(tr.J_fun(z, par))
    labels = ", ".join(m.label() for m in tr.meshes)
    return MultiPhaseSolution(
        success=success,
        status=ipopt_status_code(status),
        ipopt_status=status,
        message=f"IPOPT: {status} after {nit} iterations ({tr.method}, meshes {labels})",
        nit=nit,
        nfev=int(stats.get("n_call_nlp_f", 0)),
        objective=objective,
        parameters=pval,
        phases=tuple(phases),
        integrals=tuple(integrals),
        events=events,
        method=tr.method,
        meshes=tr.meshes,
        max_violation=viol,
        build_s=build_s,
        solve_s=solve_s,
        problem=problem,
        warm_start=mode,
        nlp=_MultiNLPPoint(
            method=tr.method, meshes=tr.meshes, z=z, lam_x=lam_x, lam_g=lam_g, par=par.copy(),
            st=tuple(sc[2] for sc in scales), g_path=tuple(lay.g_path for lay in tr.layouts),
            g_dur=tuple(lay.g_dur for lay in tr.layouts), g_int=tuple(lay.g_int for lay in tr.layouts),
            g_links=tr.g_links, g_events=tr.g_events,
        ),
    )


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _MultiNLPPoint:
    """Raw NLP point of a multi-phase solve and the rows it needs to be carried to other meshes."""

    method: str
    meshes: tuple[Mesh, ...]
    z: np.ndarray
    lam_x: np.ndarray
    lam_g: np.ndarray
    par: np.ndarray
    st: tuple[float, ...]
    g_path: tuple[slice, ...]
    g_dur: tuple[int, ...]
    g_int: tuple[slice, ...]
    g_links: slice
    g_events: slice


def _link_row_scales(problem: MultiPhaseProblem, sx_of, st_of) -> np.ndarray:
    """Scale of every linkage row (state rows: the ``a`` phase's state scales; time rows: its
    time scale)."""
    out = []
    for lk in problem.links:
        idx = list(range(problem.phases[lk.a].n_states)) if lk.states is None else list(lk.states)
        out.append(np.asarray(sx_of(lk.a), float)[idx])
        if lk.time:
            out.append([st_of(lk.a)])
    return np.concatenate(out) if out else np.zeros(0)


def _multi_duals(problem, tr, prev, z0, par, scales, t_guess, lbz, ubz):
    """``(lam_x0, lam_g0)`` of a previous multi-phase solution on ``tr``'s meshes, or None.

    Per phase as :func:`adcskit.optimal_control.solve._interpolated_duals`; the
    mesh-independent rows (phase durations, integrals, linkages, events) keep their
    multipliers, rescaled to the new row and objective scales (a row ``g/s`` of a problem
    with objective ``J/cJ`` has the multiplier ``ν s / cJ`` for the physical ``ν``).
    """
    old = prev.nlp
    def rows(sl):
        return sl.stop - sl.start

    if (
        len(old.meshes) != len(tr.layouts)
        or rows(old.g_links) != rows(tr.g_links)
        or rows(old.g_events) != rows(tr.g_events)
    ):
        return None
    cJ, cJ_old = float(par[-1]), float(old.par[-1])
    r = cJ_old / cJ
    lam_g = np.zeros(tr.ng)
    for k, (ph, lay, (sx, _su, st), (t0, tf)) in enumerate(
        zip(problem.phases, tr.layouts, scales, t_guess, strict=True)
    ):
        ps = prev.phases[k]
        if not ps.pieces or ps.pieces[0].lam is None:
            return None
        a, b = ps.t0, ps.tf

        def lamfun(t, side, _ps=ps, _a=a, _b=b, _t0=t0, _tf=tf):
            return _ps._costate_at(_a + (np.asarray(t, float) - _t0) / (_tf - _t0) * (_b - _a), side)

        _defect_duals(lam_g, tr.method, lay.intervals, tr.times(lay, t0, tf), lamfun, sx, cJ)
        if ph.n_path:
            old_ivs = interval_layout(tr.method, old.meshes[k], ph.n_states, ph.n_controls, 0, 0)[0]
            lam_old = old.lam_g[old.g_path[k]].reshape(-1, ph.n_path) * r
            lam_g[lay.g_path] = _path_duals(old_ivs, lam_old, lay.intervals).ravel()
        lam_g[lay.g_dur] = old.lam_g[old.g_dur[k]] * r * st / old.st[k]
        lam_g[lay.g_int] = old.lam_g[old.g_int[k]] * r
    if tr.g_links.stop > tr.g_links.start:
        s_new = _link_row_scales(problem, lambda i: scales[i][0], lambda i: scales[i][2])
        s_old = _link_row_scales(problem, lambda i: scales[i][0], lambda i: old.st[i])
        lam_g[tr.g_links] = old.lam_g[old.g_links] * r * s_new / s_old
    lam_g[tr.g_events] = old.lam_g[old.g_events] * r
    if not np.all(np.isfinite(lam_g)):
        return None
    lam_x = _bound_duals(tr.lagrangian_gradient, z0, par, lam_g, lbz, ubz)
    if not np.all(np.isfinite(lam_x)):
        return None
    return lam_x, lam_g


def _zero_mayer(x0, t0, xf, tf):
    return 0.0


def _phase_solution(iphase, ph, lay, tr, z, lam_g, sx, su, t0, tf, pval, cJ, success, status, nit, viol):
    nx, nu = ph.n_states, ph.n_controls
    pdm = ca.DM(pval)
    parts = unpack_intervals(lay.intervals, z, sx, su)
    pieces, samples = _assemble(
        tr.method, lay.intervals, parts, tr.times(lay, t0, tf), lam_g, cJ, sx,
        lambda xk, uk, tk, lk: lay.h_fun(xk, uk, tk, pdm, lk),
    )
    x = ca.SX.sym("x", nx)
    u = ca.SX.sym("u", nu)
    t = ca.SX.sym("t")
    f_fixed = ca.Function("f", [x, u, t], [lay.f_fun(x, u, t, pdm)])
    # the phase as a single-phase problem with p fixed at its optimum (a container for
    # bounds, names and scales used by control_at / resimulate / bang_bang)
    t_end = max(tf, t0 + 1e-9 * max(1.0, abs(t0)))
    proxy = OptimalControlProblem(
        name=ph.name,
        dynamics=lambda xx, uu, tt, _f=ph.dynamics, _p=pdm: _f(xx, uu, tt, _p),
        n_states=nx,
        n_controls=nu,
        state_names=ph.state_names,
        control_names=ph.control_names,
        state_lower=ph.state_lower,
        state_upper=ph.state_upper,
        control_lower=ph.control_lower,
        control_upper=ph.control_upper,
        t0=t0,
        tf_bounds=(t_end, t_end),
        mayer=_zero_mayer,
        state_scale=sx,
        control_scale=su,
    )
    return OptimalControlSolution(
        success=success,
        status=ipopt_status_code(status),
        ipopt_status=status,
        message=f"phase {ph.name}: IPOPT {status}",
        nit=nit,
        nfev=0,
        objective=float("nan"),
        t0=t0,
        tf=tf,
        method=tr.method,
        mesh=tr.meshes[iphase],
        **samples,
        max_violation=viol,
        build_s=0.0,
        solve_s=0.0,
        problem=proxy,
        pieces=pieces,
        dynamics_fun=f_fixed,
    )
