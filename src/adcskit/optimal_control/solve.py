"""Solve a transcribed optimal-control problem with IPOPT; costates, Hamiltonian, multistart.

:func:`solve` transcribes (cached), builds the initial guess, calls IPOPT (CasADi ``nlpsol``,
exact Hessian, MUMPS) and returns an :class:`OptimalControlSolution`. An IPOPT failure is a
result with ``success=False`` and IPOPT's status string, never an exception.

Costates come from the KKT multipliers by the costate mapping theorem (S2 Theorem 1,
eq. 37), applied interval by interval: at the LG points ``λ_k = Λ̃_k / w_k + Λ̃_f``, at the
interval end ``λ_f = Λ̃_f`` (``Λ̃_f``: multiplier of the quadrature row, eq. 30), at the start
``λ₀ = Λ̃_f − Σ_k D_k0 Λ̃_k`` (the multiplier of whatever fixes ``X₀``: the initial boundary
condition in the first interval, the linkage row elsewhere — S2's ``Λ₀ = Λ̃₀``). For Radau
``λ_k = Λ̃_k / w_k`` and ``λ(+1) = Σ_k D_{k,N+1} Λ̃_k`` (Garg et al. 2010). CasADi's
Lagrangian is ``L = J + λᵀ g``, so ``Λ̃`` is minus CasADi's ``lam_g``. Both mappings are exact
to solver tolerance where the NLP's multipliers are unique (tests: the minimum-energy double
integrator, 1e-8 at every node). On a bang-bang problem they are not unique: on the
minimum-time double integrator a constant shift ``c`` of ``λ_v`` satisfies every KKT equation
(the control-bound multipliers absorb it, and it enters the ``tf`` row as ``c·Σ w_k u_k = 0``)
within a range set by the nodes next to the switch; IPOPT returns an interior member, so the
estimate is off by a constant ``c = O(h)`` — for Radau, whose LGR point ``τ = −1`` sits at a
switch on a mesh point, and for Gauss when its nodes are not symmetric about the switch. That
first-order error of the Radau estimate (issue 11) is this degeneracy, not a mapping defect.
The Hamiltonian is ``H = g + λᵀ f`` at the collocation points.

Warm starts (:func:`solve` with a previous solution as ``guess``) pass IPOPT the previous
primal point (interpolated by its Lagrange polynomials on another mesh) and, on the same mesh,
its multipliers, with :data:`WARM_START_IPOPT_OPTIONS`; :func:`solve_mesh_sequence` follows
one local optimum through finer meshes and flags branch jumps.

References
----------
S2, eq. 35–37 and Theorem 1. Benson et al., J. Guid. Control Dyn. 29(6), 2006, Theorem 1.
Garg et al., Automatica 46(11), 2010, Theorem 1.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from adcskit._progress import track
from adcskit._results import compact_repr
from adcskit._validation import (
    as_array,
    as_rng,
    check_choice,
    check_flag,
    check_int,
    check_positive,
)
from adcskit.errors import InputError, InputTypeError
from adcskit.optimal_control._nlp import (  # noqa: F401 - _resolve_options: also imported from here
    WARM_START_IPOPT_OPTIONS,
    _as_mesh,
    _assemble,
    _bound_duals,
    _defect_duals,
    _interp_fun,
    _path_duals,
    _Piece,
    _resolve_options,
    _run_ipopt,
    _solution_funs,
)
from adcskit.optimal_control.nodes import _lagrange_rows, barycentric_weights, lagrange_matrix
from adcskit.optimal_control.problem import Guess, Mesh, OptimalControlProblem
from adcskit.optimal_control.transcription import (
    METHODS,
    get_transcription,
    interval_layout,
)

__all__ = [
    "OptimalControlSolution",
    "MeshSequenceResult",
    "MultistartResult",
    "solve",
    "solve_mesh_sequence",
    "multistart",
    "default_guess",
    "NLPPoint",
    "WARM_START_IPOPT_OPTIONS",
]

@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class NLPPoint:
    """The raw NLP point of a solve, kept for warm starts (primal and dual).

    Attributes
    ----------
    method : str
        Transcription (``"gauss"`` or ``"radau"``).
    mesh : Mesh
    z : (nz,) ndarray
        Scaled decision vector (states / ``sx``, controls / ``su``, ``tf`` / ``tf_guess``).
    lam_x : (nz,) ndarray
        Multipliers of the variable bounds (CasADi's ``lam_x``).
    lam_g : (ng,) ndarray
        Multipliers of the constraint rows (CasADi's ``lam_g``).
    p : (n_states + n_controls + 3,) ndarray
        NLP parameters: state scales, control scales, ``tf`` scale, ``t0`` and the objective
        scale ``|J(guess)|`` the multipliers refer to.

    Examples
    --------
    >>> from adcskit.optimal_control import solve
    >>> from adcskit.optimal_control.problems import double_integrator_min_time
    >>> sol = solve(double_integrator_min_time(), mesh=(4, 3))
    >>> sol.nlp.z.shape == sol.nlp.lam_x.shape
    True
    """

    method: str
    mesh: Mesh
    z: np.ndarray
    lam_x: np.ndarray
    lam_g: np.ndarray
    p: np.ndarray

    def compatible(self, method: str, mesh: Mesh, p: np.ndarray, nz: int, ng: int) -> bool:
        """Same transcription, mesh, layout and scales: the duals can be passed as they are."""
        return (
            self.method == method
            and self.mesh == mesh
            and self.z.size == nz
            and self.lam_g.size == ng
            and self.p.size == p.size
            and bool(np.array_equal(self.p[:-1], p[:-1]))
        )


@compact_repr
@dataclass(frozen=True, slots=True, kw_only=True)
class OptimalControlSolution:
    """Result of one transcribed solve.

    Attributes
    ----------
    success : bool
        IPOPT reported ``Solve_Succeeded`` or ``Solved_To_Acceptable_Level``.
    status : int
        scipy-style code (:data:`IPOPT_STATUS_CODES`): 0 converged, 1 converged to the
        acceptable level, 2 iteration or time limit, 3 infeasible, 4 other failure.
    ipopt_status : str
        IPOPT's ``return_status`` string.
    message : str
    nit, nfev : int
        IPOPT iterations and objective evaluations.
    objective : float
        ``J`` at the solution.
    t0, tf : float
        Initial and final time (s).
    method : str
        ``"gauss"`` or ``"radau"``.
    mesh : Mesh
    t : (M,) ndarray
        Times of the state samples (s): each interval's support points, then ``tf``.
    x : (M, n_states) ndarray
    t_control : (K,) ndarray
        Collocation times (s).
    u : (K, n_controls) ndarray
    costate : (M, n_states) ndarray
        Costate estimates at ``t`` (S2 eq. 37).
    hamiltonian : (K,) ndarray
        ``H = g + λᵀ f`` at the collocation points (S2 eq. 35).
    switching : (K, n_controls) ndarray
        ``∂H/∂u`` at the collocation points.
    max_violation : float
        Largest constraint violation of the NLP (scaled rows).
    build_s, solve_s : float
        Wall time of the NLP build (0 when cached) and of IPOPT (s).
    warm_start : str
        How the solve was started: ``"cold"`` (IPOPT defaults from a guess), ``"primal"``
        (warm-start options from a primal point: a previous solution on another mesh,
        interpolated, or a :class:`Guess` with ``warm_start=True``) or
        ``"primal-dual"`` (same mesh: the previous NLP point and its multipliers).
    nlp : NLPPoint or None
        The raw NLP point (for warm starts).

    Examples
    --------
    >>> from adcskit.optimal_control import solve
    >>> from adcskit.optimal_control.problems import double_integrator_min_energy
    >>> sol = solve(double_integrator_min_energy(distance=1.0, duration=1.0), mesh=(4, 3))
    >>> type(sol).__name__, sol.success, sol.method
    ('OptimalControlSolution', True, 'gauss')
    >>> sol.t.shape, sol.x.shape, sol.t_control.shape, sol.u.shape, sol.costate.shape
    ((17,), (17, 2), (12,), (12, 1), (17, 2))
    >>> sol.state_at(1.0).round(6) + 0.0                    # ends at rest at x = 1 m
    array([1., 0.])
    """

    success: bool
    status: int
    message: str
    nit: int
    nfev: int
    objective: float
    t0: float
    tf: float
    method: str
    mesh: Mesh
    t: np.ndarray
    x: np.ndarray
    t_control: np.ndarray
    u: np.ndarray
    costate: np.ndarray
    hamiltonian: np.ndarray
    switching: np.ndarray
    max_violation: float
    build_s: float
    solve_s: float
    problem: OptimalControlProblem = field(repr=False)
    pieces: tuple[_Piece, ...] = field(repr=False)
    dynamics_fun: Any = field(repr=False, default=None)
    warm_start: str = "cold"
    ipopt_status: str = ""
    nlp: NLPPoint | None = field(repr=False, default=None)

    # ---------------------------------------------------------------- interpolation
    def _locate(self, t: np.ndarray, side: str = "left") -> np.ndarray:
        """Interval of each time; at a mesh point the interval ending there (``side="left"``)
        or the one starting there (``"right"``)."""
        ends = np.array([p.t_end for p in self.pieces])
        return np.minimum(np.searchsorted(ends, t, side=side), len(self.pieces) - 1)

    def _times(self, t) -> np.ndarray:
        """``t`` (s) as a 1-D array inside ``[t0, tf]``: a 2-D array or a time outside the
        horizon (beyond a rounding margin of ``1e-9 (tf − t0)``, which is clipped) raises."""
        tt = as_array("t", t, ndim=(0, 1))
        tt = np.atleast_1d(tt)
        margin = 1e-9 * max(abs(self.tf - self.t0), 1e-300)
        out = (tt < self.t0 - margin) | (tt > self.tf + margin)
        if np.any(out):
            bad = float(tt[np.argmax(out)])
            raise InputError(
                f"t must lie in the solution's horizon [t0, tf] = [{self.t0:.9g}, {self.tf:.9g}] s (the "
                f"polynomials are not extrapolated); got {bad:.9g} s"
            )
        return np.clip(tt, min(self.t0, self.tf), max(self.t0, self.tf))

    def state_at(self, t) -> np.ndarray:
        """States at times ``t`` (s) by the interval's Lagrange polynomial (S2 eq. 22).

        ``t`` is a time or a 1-D array of times in ``[t0, tf]``; a time outside the horizon
        or a 2-D array raises :class:`~adcskit.errors.InputError` (no silent extrapolation).
        Returns ``(n_states,)`` for a scalar ``t``, else ``(len(t), n_states)``.

        Examples
        --------
        >>> from adcskit.optimal_control import solve
        >>> from adcskit.optimal_control.problems import double_integrator_min_energy
        >>> sol = solve(double_integrator_min_energy(distance=1.0, duration=1.0), mesh=(4, 3))
        >>> sol.state_at([0.0, 1.0]).round(6) + 0.0
        array([[0., 0.],
               [1., 0.]])
        >>> try:
        ...     sol.state_at(1.5)
        ... except ValueError as exc:
        ...     print(str(exc)[:40])
        t must lie in the solution's horizon [t0
        """
        tt = self._times(t)
        out = np.empty((tt.size, self.x.shape[1]))
        idx = self._locate(tt)
        for j in np.unique(idx):
            p = self.pieces[j]
            m = idx == j
            out[m] = lagrange_matrix(_tau(p.ts, p.ts[0], p.t_end), _tau(tt[m], p.ts[0], p.t_end)) @ p.xs
        return out if np.ndim(t) else out[0]

    def control_at(self, t, *, kind: str = "lagrange") -> np.ndarray:
        """Controls at ``t`` (s): ``"lagrange"`` (S2 eq. 24, clipped to the bounds) or
        ``"nearest"`` (value of the nearest collocation point in the same interval).

        ``t`` must lie in ``[t0, tf]`` and be a scalar or 1-D (else
        :class:`~adcskit.errors.InputError`, as :meth:`state_at`)."""
        check_choice("kind", kind, ("lagrange", "nearest"))
        tt = self._times(t)
        out = np.empty((tt.size, self.u.shape[1]))
        idx = self._locate(tt)
        for j in np.unique(idx):
            m = idx == j
            out[m] = _piece_control(self.pieces[j], tt[m], kind)
        out = np.clip(out, self.problem.control_lower, self.problem.control_upper)
        return out if np.ndim(t) else out[0]

    def _control_function(self, kind: str = "lagrange"):
        """``t -> self.control_at(t, kind=kind)`` for one scalar time, bit for bit, with the
        interval ends and each interval's support points and barycentric weights computed once
        (:func:`~adcskit.optimal_control.resimulate` calls it at every right-hand-side
        evaluation; ``control_at`` recomputed them and re-validated its arrays per call)."""
        check_choice("kind", kind, ("lagrange", "nearest"))
        ends = np.array([p.t_end for p in self.pieces])
        last = len(self.pieces) - 1
        lo, hi = min(self.t0, self.tf), max(self.t0, self.tf)
        margin = 1e-9 * max(abs(self.tf - self.t0), 1e-300)
        tables: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        lower, upper = self.problem.control_lower, self.problem.control_upper

        def control(t) -> np.ndarray:
            if np.ndim(t) != 0:
                return self.control_at(t, kind=kind)  # arrays: as before
            tt = np.atleast_1d(np.asarray(t, float))
            if not self.t0 - margin <= tt[0] <= self.tf + margin:
                return self.control_at(t, kind=kind)  # NaN, outside the horizon: as before
            tt = np.clip(tt, lo, hi)
            j = int(min(np.searchsorted(ends, tt[0], side="left"), last))
            p = self.pieces[j]
            if kind == "lagrange" and j not in tables:
                sup = _tau(p.tc, p.ts[0], p.t_end)
                tables[j] = (sup, barycentric_weights(sup))
            return np.clip(_piece_control(p, tt, kind, tables.get(j)), lower, upper)[0]

        return control

    def costate_at(self, t) -> np.ndarray:
        """Costate estimates at times ``t`` (s) by each interval's costate polynomial.

        The polynomial interpolates the costate mapping's values (module docstring) at the
        interval's state support points (Gauss: and its end); used to carry multipliers onto
        another mesh.

        Examples
        --------
        >>> from adcskit.optimal_control import solve
        >>> from adcskit.optimal_control.problems import double_integrator_min_energy
        >>> sol = solve(double_integrator_min_energy(distance=1.0, duration=1.0), mesh=(4, 3))
        >>> sol.costate_at(0.5).round(6) + 0.0   # λ_x = -24 d/T³ = -24, λ_v = 12 d/T³ (2t/T - 1) = 0
        array([-24.,   0.])
        """
        return self._costate_at(t)

    def _costate_at(self, t, side: str = "left") -> np.ndarray:
        if not self.pieces or self.pieces[0].lam is None:
            raise InputError("this solution carries no costate polynomials")
        tt = self._times(t)
        out = np.empty((tt.size, self.costate.shape[1]))
        idx = self._locate(tt, side)
        for j in np.unique(idx):
            p = self.pieces[j]
            m = idx == j
            out[m] = lagrange_matrix(_tau(p.lam_t, p.ts[0], p.t_end), _tau(tt[m], p.ts[0], p.t_end)) @ p.lam
        return out if np.ndim(t) else out[0]

    def as_guess(self) -> Guess:
        """This solution's samples as a :class:`Guess` (linearly interpolated onto a new mesh).

        For a warm start pass the solution itself as ``guess`` to :func:`solve`: it uses the
        Lagrange polynomials, the raw NLP point and its multipliers.
        """
        return Guess(t=self.t, x=self.x, u=self.u, tf=self.tf, t_u=self.t_control)

    def to_dict(self) -> dict[str, Any]:
        return {
            "success": self.success,
            "status": self.status,
            "ipopt_status": self.ipopt_status,
            "message": self.message,
            "nit": self.nit,
            "nfev": self.nfev,
            "objective": self.objective,
            "t0": self.t0,
            "tf": self.tf,
            "method": self.method,
            "mesh": self.mesh.label(),
            "max_violation": self.max_violation,
            "build_s": self.build_s,
            "solve_s": self.solve_s,
            "warm_start": self.warm_start,
            "t": self.t,
            "x": self.x,
            "t_control": self.t_control,
            "u": self.u,
            "costate": self.costate,
            "hamiltonian": self.hamiltonian,
        }


def _tau(t, a, b):
    return 2.0 * (np.asarray(t, float) - a) / (b - a) - 1.0


def _piece_control(p: _Piece, tt: np.ndarray, kind: str, table=None) -> np.ndarray:
    """Controls of one mesh interval at the times ``tt`` (1-D, inside it), before clipping:
    its Lagrange polynomial (``table``: its support points on [-1, 1] and their barycentric
    weights, computed here when None) or its nearest collocation value."""
    t_start = p.ts[0]
    if kind == "lagrange":
        points = _tau(tt, t_start, p.t_end)
        if table is None:  # validated as lagrange_matrix validates them
            sup = as_array("support", _tau(p.tc, t_start, p.t_end), ndim=1)
            table, points = (sup, barycentric_weights(sup)), as_array("points", points, ndim=1)
        return _lagrange_rows(table[0], table[1], points) @ p.uc
    k = np.abs(tt[:, None] - p.tc[None, :]).argmin(axis=1)
    return p.uc[k]


def default_guess(problem: OptimalControlProblem) -> Guess:
    """Straight-line state guess between the boundary values, mid-bound controls, ``tf_guess``.

    Free boundary components take the other end's value, else the middle of finite bounds,
    else 0. Controls are 0 clipped into their bounds.

    Examples
    --------
    >>> from adcskit.optimal_control import default_guess
    >>> from adcskit.optimal_control.problems import double_integrator_min_energy
    >>> g = default_guess(double_integrator_min_energy(distance=2.0, duration=4.0))
    >>> g.tf, g.x[0].round(6), g.x[-1].round(6)     # straight line between the boundary states
    (4.0, array([0., 0.]), array([2., 0.]))
    """
    _check_problem(problem)
    x0 = np.array(problem.initial_state, float)
    xf = np.array(problem.final_state, float)
    both = np.isfinite(problem.state_lower) & np.isfinite(problem.state_upper)
    mid = np.zeros(problem.n_states)
    mid[both] = 0.5 * (problem.state_lower[both] + problem.state_upper[both])
    x0 = np.where(np.isfinite(x0), x0, np.where(np.isfinite(xf), xf, mid))
    xf = np.where(np.isfinite(xf), xf, x0)
    u = np.clip(np.zeros(problem.n_controls), problem.control_lower, problem.control_upper)
    t = np.array([problem.t0, problem.tf_guess])
    return Guess(t=t, x=np.vstack([x0, xf]), u=np.vstack([u, u]), tf=problem.tf_guess)


#: IPOPT ``return_status`` -> scipy-style integer ``status`` of the solution objects.
IPOPT_STATUS_CODES: dict[str, int] = {
    "Solve_Succeeded": 0,
    "Solved_To_Acceptable_Level": 1,
    "Feasible_Point_Found": 1,
    "Maximum_Iterations_Exceeded": 2,
    "Maximum_CpuTime_Exceeded": 2,
    "Maximum_WallTime_Exceeded": 2,
    "Infeasible_Problem_Detected": 3,
    "Restoration_Failed": 4,
    "Search_Direction_Becomes_Too_Small": 4,
    "Diverging_Iterates": 4,
    "Error_In_Step_Computation": 4,
    "Invalid_Number_Detected": 4,
    "User_Requested_Stop": 4,
}


def ipopt_status_code(return_status: str) -> int:
    """scipy-style integer status of an IPOPT ``return_status`` (4 for anything unlisted).

    >>> ipopt_status_code("Solve_Succeeded"), ipopt_status_code("Maximum_Iterations_Exceeded")
    (0, 2)
    """
    return IPOPT_STATUS_CODES.get(str(return_status), 4)


def _check_problem(problem: Any) -> None:
    if not isinstance(problem, OptimalControlProblem):
        raise InputTypeError(f"problem must be an OptimalControlProblem; got {type(problem).__name__}")


def solve(
    problem: OptimalControlProblem,
    *,
    method: str = "gauss",
    mesh: Mesh | tuple[int, int] = (20, 3),
    guess: Guess | OptimalControlSolution | None = None,
    ipopt_options: dict[str, Any] | None = None,
    warm_start: bool | None = None,
    transfer_duals: bool = False,
) -> OptimalControlSolution:
    """Transcribe ``problem`` and solve the NLP with IPOPT.

    Parameters
    ----------
    problem : OptimalControlProblem
    method : {"gauss", "radau"}
        Transcription (see :data:`adcskit.optimal_control.transcription.METHODS`).
    mesh : Mesh or (int, int)
        Mesh or ``(n_intervals, n_nodes)`` for equal intervals; S2 uses ``(20, 3)``.
    guess : Guess or OptimalControlSolution, optional
        Accepted: ``None`` (:func:`default_guess`, straight lines), a :class:`Guess` (its ``x``
        and ``u`` must have ``n_states`` and ``n_controls`` columns), or a previous solution.
        (A callable or ``"linear"`` is accepted by :func:`solve_adaptive` only.) A previous solution is a warm start: on
        any mesh its states and controls are interpolated by their Lagrange polynomials
        (S2 eq. 22, 24) onto the new nodes; on the same mesh and transcription (and equal
        scales) its raw NLP point and multipliers (``x0``, ``lam_x0``, ``lam_g0``) are passed
        as they are, so that re-solving an optimum from itself returns it.
    ipopt_options : dict, optional
        IPOPT options overriding :data:`DEFAULT_IPOPT_OPTIONS` (and, for a warm start,
        :data:`WARM_START_IPOPT_OPTIONS`).
    warm_start : bool, optional
        Use :data:`WARM_START_IPOPT_OPTIONS`. Default: when ``guess`` is a previous solution.
        ``False`` re-solves a previous solution's trajectory with IPOPT's cold defaults.
    transfer_duals : bool
        When warm-starting from a previous solution on *another* mesh, also pass IPOPT the
        multipliers interpolated onto this mesh (``warm_start="primal-dual-interpolated"``):
        the defect, quadrature and interval-link multipliers that the previous costate
        polynomials imply (the costate mapping inverted), path multipliers carried as a
        density in time, and bound multipliers from stationarity at the interpolated point.
        Default False (primal values only, as before); :func:`solve_adaptive` sets it.

    Returns
    -------
    OptimalControlSolution
        ``success=False`` with IPOPT's status when the solve fails; ``warm_start`` says how
        the solve was started.

    References
    ----------
    S2, eq. 17–37 and Table 1 (pseudo-code; IPOPT replaces the paper's SQP). Wächter &
    Biegler, Math. Program. 106(1), 2006 (IPOPT; warm-start options in its documentation).

    Examples
    --------
    >>> from adcskit.optimal_control.problems import double_integrator_min_time
    >>> p = double_integrator_min_time(2.0, 0.5)
    >>> a = solve(p, mesh=(4, 3))
    >>> b = solve(p, mesh=(4, 3), guess=a)  # primal and dual warm start
    >>> b.warm_start, abs(b.tf - a.tf) < 1e-7, b.nit <= 3
    ('primal-dual', True, True)

    >>> from adcskit.optimal_control import solve
    >>> from adcskit.optimal_control.problems import double_integrator_min_energy
    >>> ocp = double_integrator_min_energy(distance=1.0, duration=1.0)
    >>> sol = solve(ocp, method="gauss", mesh=(4, 3))
    >>> sol.success, round(sol.objective, 6)              # analytic 12 d^2 / T^3 = 12
    (True, 12.0)
    >>> sol.x.shape, sol.u.shape
    ((17, 2), (12, 1))
    >>> fine = solve(ocp, method="radau", mesh=(8, 3), guess=sol)   # warm start
    >>> fine.success, round(fine.objective, 6)
    (True, 12.0)
    """
    if not isinstance(problem, OptimalControlProblem):
        raise InputTypeError(f"problem must be an OptimalControlProblem; got {type(problem).__name__}")
    method = check_choice("method", method, METHODS)
    mesh = _as_mesh(mesh)
    prev: OptimalControlSolution | None = None
    if guess is None:
        guess = default_guess(problem)
    elif isinstance(guess, OptimalControlSolution):
        prev = guess
        if prev.x.shape[1] != problem.n_states or prev.u.shape[1] != problem.n_controls:
            raise InputError(
                f"guess solution has {prev.x.shape[1]} states and {prev.u.shape[1]} controls; the problem "
                f"has {problem.n_states} and {problem.n_controls}"
            )
        guess = prev.as_guess()
    elif isinstance(guess, str):
        raise InputTypeError(
            f"guess must be a Guess, an OptimalControlSolution or None; got {guess!r} (the string 'linear' "
            "is accepted by solve_adaptive only; here None already means the straight-line default_guess)"
        )
    elif not isinstance(guess, Guess):
        raise InputTypeError(f"guess must be a Guess or OptimalControlSolution; got {type(guess).__name__}")
    else:
        guess.check_widths(problem.n_states, problem.n_controls)
    if warm_start is None:
        warm = prev is not None
    elif isinstance(warm_start, bool | np.bool_):
        warm = bool(warm_start)
    else:
        raise InputTypeError(f"warm_start must be True, False or None; got {warm_start!r}")
    opts = _resolve_options(ipopt_options, warm=warm)
    t_build = time.perf_counter()
    try:
        tr = get_transcription(problem, method, mesh, opts)
    except RuntimeError as exc:  # CasADi refusing an IPOPT option (unknown name, wrong type) or the problem
        lines = [ln for ln in str(exc).splitlines() if ln.strip()]
        last = lines[-1] if lines else str(exc)
        if "ipopt" in str(exc).lower():
            raise InputError(f"ipopt_options not accepted by IPOPT: {last}; got {ipopt_options!r}") from None
        raise InputError(f"problem could not be transcribed by CasADi: {last}") from None
    build_s = time.perf_counter() - t_build
    transfer_duals = check_flag("transfer_duals", transfer_duals)
    return _solve_with(problem, tr, guess, build_s, prev=prev, warm=warm, transfer_duals=transfer_duals)


def _interpolated_duals(prev: OptimalControlSolution, problem, tr, z0, p, lbz, ubz, t0: float, tf: float):
    """``(lam_x0, lam_g0)`` of a previous solution on this NLP's mesh, or None.

    The warm start of a refined mesh: constraint multipliers from the previous costate
    polynomials (:func:`_defect_duals`) and path-multiplier densities (:func:`_path_duals`),
    bound multipliers from stationarity at the interpolated point (:func:`_bound_duals`).
    """
    if prev.nlp is None or not prev.pieces or prev.pieces[0].lam is None:
        return None
    sx, _ = problem.scales()
    cJ = float(p[-1])
    a, b = prev.t0, prev.tf

    def lamfun(t, side):
        return prev._costate_at(a + (np.asarray(t, float) - t0) / (tf - t0) * (b - a), side)

    lam_g = np.zeros(tr.ng)
    _defect_duals(lam_g, tr.method, tr.intervals, tr.times(t0, tf), lamfun, sx, cJ)
    if tr.npath:
        old, _, g_end = interval_layout(prev.method, prev.mesh, tr.nx, tr.nu, 0, 0)
        n_old = tr.npath * sum(prev.mesh.nodes)
        if prev.nlp.lam_g.size != g_end + n_old:
            return None
        lam_old = prev.nlp.lam_g[g_end : g_end + n_old].reshape(-1, tr.npath) * (float(prev.nlp.p[-1]) / cJ)
        lam_g[tr.g_path] = _path_duals(old, lam_old, tr.intervals).ravel()
    if not np.all(np.isfinite(lam_g)):
        return None
    lam_x = _bound_duals(tr.lagrangian_gradient, z0, p, lam_g, lbz, ubz)
    if not np.all(np.isfinite(lam_x)):
        return None
    return lam_x, lam_g


def _solve_with(
    problem,
    tr,
    guess: Guess,
    build_s: float,
    *,
    prev: OptimalControlSolution | None = None,
    warm: bool = False,
    transfer_duals: bool = False,
) -> OptimalControlSolution:
    sx, su = problem.scales()
    t0 = problem.t0
    tf_g = float(np.clip(guess.tf, *problem.tf_bounds))
    s_tf = max(abs(problem.tf_guess), 1e-9)
    if prev is not None:
        xfun, ufun = _solution_funs(prev, t0, tf_g)
    else:
        # the guess's own time span: its state samples run from t[0] to tf (S2: t0 = 0)
        g0, gf = float(guess.t[0]), float(guess.tf)
        xfun = _interp_fun(guess.t, guess.x, g0, gf, t0, tf_g)
        ufun = _interp_fun(guess.t if guess.t_u is None else guess.t_u, guess.u, g0, gf, t0, tf_g)
    z0 = tr.pack(t0, tf_g, xfun, ufun, sx, su, s_tf)
    lbz, ubz, lbg, ubg = tr.bounds(problem, sx, su, s_tf)
    z0 = np.clip(z0, lbz, ubz)
    p = np.concatenate([sx, su, [s_tf, t0, 1.0]])
    duals: dict[str, np.ndarray] = {}
    mode = "primal" if warm else "cold"
    if warm and prev is not None and prev.nlp is not None and prev.nlp.compatible(tr.method, tr.mesh, p, tr.nz, tr.ng):
        # same NLP up to boundary values: pass the point and its multipliers as they are
        # (with the same objective scale, so that the multipliers mean the same thing)
        z0 = np.clip(prev.nlp.z, lbz, ubz)
        p = prev.nlp.p.copy()
        duals = {"lam_x0": prev.nlp.lam_x, "lam_g0": prev.nlp.lam_g}
        mode = "primal-dual"
        cJ = float(p[-1])
    else:
        j0 = float(tr.J_fun(z0, p))
        cJ = abs(j0) if np.isfinite(j0) and abs(j0) > 1e-12 else 1.0
        p[-1] = cJ
        if warm and transfer_duals and prev is not None:
            d = _interpolated_duals(prev, problem, tr, z0, p, lbz, ubz, t0, tf_g)
            if d is not None:
                duals = {"lam_x0": d[0], "lam_g0": d[1]}
                mode = "primal-dual-interpolated"
    z, lam_g, lam_x, g, stats, status, success, solve_s = _run_ipopt(tr.solver, z0, p, lbz, ubz, lbg, ubg, duals)
    viol = float(np.max(np.concatenate([[0.0], lbg - g, g - ubg, lbz - z, z - ubz]))) if g.size else 0.0
    parts, tf = tr.unpack(z, sx, su, s_tf)
    pieces, samples = _assemble(tr.method, tr.intervals, parts, tr.times(t0, tf), lam_g, cJ, sx, tr.h_fun)
    objective = float(tr.J_fun(z, p))
    msg = f"IPOPT: {status} after {int(stats.get('iter_count', 0))} iterations ({tr.method}, mesh {tr.mesh.label()})"
    return OptimalControlSolution(
        success=success,
        status=ipopt_status_code(status),
        ipopt_status=status,
        message=msg,
        nit=int(stats.get("iter_count", 0)),
        nfev=int(stats.get("n_call_nlp_f", 0)),
        objective=objective,
        t0=t0,
        tf=tf,
        method=tr.method,
        mesh=tr.mesh,
        **samples,
        max_violation=viol,
        build_s=build_s,
        solve_s=solve_s,
        problem=problem,
        pieces=pieces,
        dynamics_fun=tr.f_fun,
        warm_start=mode,
        nlp=NLPPoint(method=tr.method, mesh=tr.mesh, z=z, lam_x=lam_x, lam_g=lam_g, p=p),
    )


# ------------------------------------------------------------------------- mesh sequence
@compact_repr
@dataclass(frozen=True, slots=True, kw_only=True)
class MeshSequenceResult:
    """Solutions on a warm-started sequence of meshes (one local branch).

    Attributes
    ----------
    solutions : tuple of OptimalControlSolution
    objectives : (n,) ndarray
    rel_change : (n,) ndarray
        ``|J_k − J_{k−1}| / |J_k|`` (NaN for the first mesh).
    tf_change : (n,) ndarray
        ``|tf_k − tf_{k−1}| / tf_k``; for the first mesh, the change from the ``guess``
        solution when one was given (else NaN).
    branch_jumps : tuple of int
        Indices ``k`` of the solves whose objective or ``tf`` moved by more than
        ``jump_factor × rtol`` (relative) from the previous solve (or from the guess
        solution for ``k = 0``): the warm start left its local branch.
    converged : bool
        The last change is below ``rtol`` and the last solve succeeded.
    on_branch : bool
        No branch jump was flagged: the converged value belongs to the guess's branch.
    success : bool
        Every solve succeeded.
    message : str

    Examples
    --------
    >>> from adcskit.optimal_control import solve_mesh_sequence
    >>> from adcskit.optimal_control.problems import double_integrator_min_energy
    >>> seq = solve_mesh_sequence(double_integrator_min_energy(), [(2, 3), (4, 3)])
    >>> type(seq).__name__, len(seq.solutions), seq.success, seq.objectives.round(6)
    ('MeshSequenceResult', 2, True, array([12., 12.]))
    """

    solutions: tuple[OptimalControlSolution, ...]
    objectives: np.ndarray
    rel_change: np.ndarray
    tf_change: np.ndarray
    branch_jumps: tuple[int, ...]
    converged: bool
    success: bool
    message: str

    @property
    def final(self) -> OptimalControlSolution:
        return self.solutions[-1]

    @property
    def on_branch(self) -> bool:
        return not self.branch_jumps

    def to_dict(self) -> dict[str, Any]:
        return {
            "meshes": [s.mesh.label() for s in self.solutions],
            "objectives": self.objectives,
            "tf": [s.tf for s in self.solutions],
            "rel_change": self.rel_change,
            "tf_change": self.tf_change,
            "warm_start": [s.warm_start for s in self.solutions],
            "nit": [s.nit for s in self.solutions],
            "status": [s.status for s in self.solutions],
            "branch_jumps": list(self.branch_jumps),
            "on_branch": self.on_branch,
            "converged": self.converged,
            "success": self.success,
            "message": self.message,
        }


def _rel(a: float, b: float) -> float:
    return abs(a - b) / max(abs(a), 1e-300)


def solve_mesh_sequence(
    problem: OptimalControlProblem,
    meshes: Sequence[Mesh | tuple[int, int]] = ((20, 3), (40, 4), (80, 4), (160, 4)),
    *,
    method: str = "gauss",
    guess: Guess | OptimalControlSolution | None = None,
    rtol: float = 1e-5,
    jump_factor: float = 100.0,
    ipopt_options: dict[str, Any] | None = None,
) -> MeshSequenceResult:
    """Follow one local optimum through successively finer meshes.

    Each solve is warm-started (primal and, on the same mesh, dual; see :func:`solve`) from
    the previous successful solution, so the sequence tracks the local branch of ``guess``
    instead of re-solving from IPOPT's cold start. Stops as soon as the objective changes by
    less than ``rtol`` (relative) between two consecutive successful solves, or when
    ``meshes`` is exhausted. A step whose objective or ``tf`` changes by more than
    ``jump_factor × rtol`` is flagged as a branch jump (``branch_jumps``): discretisation
    changes of a converging branch shrink with the mesh, a jump to another local optimum
    does not.

    Parameters
    ----------
    meshes : sequence of Mesh or (int, int)
    guess : Guess or OptimalControlSolution, optional
        Start of the branch; a solution on ``meshes[0]`` is re-solved with its multipliers.
    rtol : float
        Relative change of the objective that ends the refinement.
    jump_factor : float
        A change larger than ``jump_factor × rtol`` is a branch jump (default 100).

    Examples
    --------
    >>> from adcskit.optimal_control.problems import double_integrator_min_time
    >>> r = solve_mesh_sequence(double_integrator_min_time(2.0, 0.5), [(4, 3), (8, 3)], rtol=1e-6)
    >>> r.converged, r.on_branch, round(r.final.tf, 6)
    (True, True, 4.0)

    >>> from adcskit.optimal_control import solve_mesh_sequence
    >>> from adcskit.optimal_control.problems import double_integrator_min_energy
    >>> meshes = [(2, 3), (4, 3), (8, 3)]
    >>> seq = solve_mesh_sequence(double_integrator_min_energy(), meshes, rtol=1e-6)
    >>> seq.converged, len(seq.solutions), seq.objectives.round(6)   # stops once J stops changing
    (True, 2, array([12., 12.]))
    """
    _check_problem(problem)
    rtol = check_positive("rtol", rtol)
    jump_factor = check_positive("jump_factor", jump_factor)
    if isinstance(meshes, str | bytes) or not isinstance(meshes, Iterable):
        raise InputTypeError(f"meshes must be a sequence of meshes; got {meshes!r}")
    meshes = [_as_mesh(m) for m in meshes]
    if not meshes:
        raise InputError("meshes must contain at least one mesh")
    ref = guess if isinstance(guess, OptimalControlSolution) and guess.success else None
    sols: list[OptimalControlSolution] = []
    changes: list[float] = []
    tf_changes: list[float] = []
    jumps: list[int] = []
    converged = False
    for k, mesh in enumerate(meshes):
        sol = solve(problem, method=method, mesh=mesh, guess=guess, ipopt_options=ipopt_options)
        prev = sols[-1] if sols else None
        sols.append(sol)
        if prev is None or not (prev.success and sol.success):
            changes.append(np.nan)
        else:
            changes.append(_rel(sol.objective, prev.objective))
        base = prev if prev is not None else ref
        if base is not None and base.success and sol.success:
            tf_changes.append(_rel(sol.tf, base.tf))
            if max(_rel(sol.objective, base.objective), tf_changes[-1]) > jump_factor * rtol:
                jumps.append(k)
        else:
            tf_changes.append(np.nan)
        if sol.success:
            guess = sol
        if np.isfinite(changes[-1]) and changes[-1] < rtol and sol.success:
            converged = True
            break
    ok = all(s.success for s in sols)
    msg = (
        f"converged on mesh {sols[-1].mesh.label()}: relative change {changes[-1]:.2e} < {rtol:g}"
        if converged
        else f"not converged to {rtol:g} after {len(sols)} meshes (last change {changes[-1]:.2e})"
    )
    if jumps:
        msg += "; branch jump at " + ", ".join(
            f"{sols[k].mesh.label()} (tf change {tf_changes[k]:.2e} > {jump_factor * rtol:.0e})" for k in jumps
        )
    return MeshSequenceResult(
        solutions=tuple(sols),
        objectives=np.array([s.objective for s in sols]),
        rel_change=np.array(changes),
        tf_change=np.array(tf_changes),
        branch_jumps=tuple(jumps),
        converged=converged,
        success=ok,
        message=msg,
    )


# ------------------------------------------------------------------------- multistart
@compact_repr
@dataclass(frozen=True, slots=True, kw_only=True)
class MultistartResult:
    """Solves from seeded random initial guesses.

    Attributes
    ----------
    solutions : tuple of OptimalControlSolution
        Every start, in order (start 0 is the default guess when ``include_default``).
    objectives : (n,) ndarray
        Objective of each start (NaN when the solve failed).
    distinct_objectives : (m,) ndarray
        Distinct local optima among the successful solves, ascending (clustered at ``rtol``).
    counts : (m,) ndarray of int
        Starts that reached each distinct optimum.
    best_index : int
        Start with the lowest successful objective (-1 if none succeeded).
    n_success : int

    Examples
    --------
    >>> from adcskit.optimal_control import multistart
    >>> from adcskit.optimal_control.problems import double_integrator_min_energy
    >>> ms = multistart(double_integrator_min_energy(), 2, mesh=(4, 3), rng=0)
    >>> type(ms).__name__, ms.n_success, ms.distinct_objectives.round(6), ms.counts
    ('MultistartResult', 2, array([12.]), array([2]))
    """

    solutions: tuple[OptimalControlSolution, ...]
    objectives: np.ndarray
    distinct_objectives: np.ndarray
    counts: np.ndarray
    best_index: int
    n_success: int

    @property
    def success(self) -> bool:
        return self.best_index >= 0

    @property
    def best(self) -> OptimalControlSolution | None:
        return self.solutions[self.best_index] if self.best_index >= 0 else None

    def to_dict(self) -> dict[str, Any]:
        return {
            "objectives": self.objectives,
            "status": [s.status for s in self.solutions],
            "distinct_objectives": self.distinct_objectives,
            "counts": self.counts,
            "best_index": self.best_index,
            "n_success": self.n_success,
        }


def random_guess(problem: OptimalControlProblem, rng, *, spread: float = 0.5, knots: int = 6) -> Guess:
    """A seeded random guess: straight line plus smooth noise, smooth random controls in bounds,
    ``tf`` uniformly in ``[0.7, 1.5] × tf_guess`` (clipped to the bounds).

    Examples
    --------
    >>> from adcskit.optimal_control import random_guess
    >>> from adcskit.optimal_control.problems import double_integrator_min_time
    >>> g = random_guess(double_integrator_min_time(), rng=0)
    >>> type(g).__name__, g.x.shape[1], g.u.shape[1]
    ('Guess', 2, 1)
    >>> g2 = random_guess(double_integrator_min_time(), rng=0)
    >>> bool(g.tf == g2.tf)                               # seeded: reproducible
    True
    """
    _check_problem(problem)
    spread = check_positive("spread", spread, allow_zero=True, max_value=1e6) + 0.0  # -0.0 -> 0.0 for numpy
    knots = check_int("knots", knots, minimum=2, maximum=100_000)
    rng = as_rng(rng)
    base = default_guess(problem)
    sx, su = problem.scales()
    tf = float(np.clip(problem.tf_guess * rng.uniform(0.7, 1.5), *problem.tf_bounds))
    t = np.linspace(problem.t0, tf, knots)
    s = (t - t[0]) / (t[-1] - t[0])
    x = base.x[0] + s[:, None] * (base.x[1] - base.x[0])
    bump = np.sin(np.pi * s)[:, None]  # keep the boundary values
    x = x + bump * rng.normal(0.0, spread, size=x.shape) * sx
    x = np.clip(x, problem.state_lower, problem.state_upper)
    lo = np.where(np.isfinite(problem.control_lower), problem.control_lower, -su)
    hi = np.where(np.isfinite(problem.control_upper), problem.control_upper, su)
    u = rng.uniform(lo, hi, size=(knots, problem.n_controls))
    return Guess(t=t, x=x, u=u, tf=tf)


def multistart(
    problem: OptimalControlProblem,
    n_starts: int = 8,
    *,
    method: str = "gauss",
    mesh: Mesh | tuple[int, int] = (20, 3),
    rng=None,
    include_default: bool = True,
    spread: float = 0.5,
    rtol: float = 1e-4,
    ipopt_options: dict[str, Any] | None = None,
) -> MultistartResult:
    """Solve from ``n_starts`` seeded random guesses and report every distinct local optimum.

    Parameters
    ----------
    n_starts : int
        Number of starts (including the default guess when ``include_default``).
    rng : Generator or int, optional
        Seed of the random guesses (``None`` → seed 0).
    spread : float
        Standard deviation of the state perturbation, in units of the state scales.
    rtol : float
        Objectives within this relative distance are the same optimum.

    Examples
    --------
    >>> from adcskit.optimal_control import multistart
    >>> from adcskit.optimal_control.problems import double_integrator_min_energy
    >>> ms = multistart(double_integrator_min_energy(), 3, mesh=(4, 3), rng=0)
    >>> len(ms.solutions), ms.n_success, ms.objectives.round(6)   # convex problem: one optimum
    (3, 3, array([12., 12., 12.]))
    >>> ms.distinct_objectives.round(6), ms.counts
    (array([12.]), array([3]))
    """
    _check_problem(problem)
    n_starts = check_int("n_starts", n_starts, minimum=1, maximum=100_000)
    include_default = check_flag("include_default", include_default)
    check_positive("spread", spread, allow_zero=True, max_value=1e6)
    check_positive("rtol", rtol)
    rng = as_rng(rng)
    sols = []
    for i in track(range(n_starts), f"multistart {problem.name}"):
        g = default_guess(problem) if (include_default and i == 0) else random_guess(problem, rng, spread=spread)
        sols.append(solve(problem, method=method, mesh=mesh, guess=g, ipopt_options=ipopt_options))
    obj = np.array([s.objective if s.success else np.nan for s in sols])
    ok = np.isfinite(obj)
    distinct: list[float] = []
    counts: list[int] = []
    for v in np.sort(obj[ok]):
        if distinct and abs(v - distinct[-1]) <= rtol * max(abs(v), 1e-300):
            counts[-1] += 1
        else:
            distinct.append(float(v))
            counts.append(1)
    best = int(np.nanargmin(obj)) if ok.any() else -1
    return MultistartResult(
        solutions=tuple(sols),
        objectives=obj,
        distinct_objectives=np.array(distinct),
        counts=np.array(counts, dtype=int),
        best_index=best,
        n_success=int(ok.sum()),
    )
