"""Multi-interval Gauss (LG) and Radau (LGR) transcriptions of an optimal-control problem.

The NLP is built once per *structure* (the problem's callables, dimensions, method, mesh and
solver options) with CasADi ``SX`` symbols and compiled into an IPOPT ``nlpsol``; boundary
values, bounds, scales and ``t0`` enter as bounds and NLP parameters, so problems that differ
only in those numbers (e.g. the five rows of S2 Table 4) reuse the same solver object.

Gauss (S2 eq. 17–34), per sub-interval ``r`` with ``N`` LG points:

* variables: state ``X₀`` at ``τ₀ = −1`` and ``X₁..X_N`` at the LG points, control
  ``U₁..U_N`` at the LG points, and the end state ``X_f`` (eq. 22–25);
* defects ``Σ_i D_ki X_i − (h/2) f(X_k, U_k, t_k) = 0``, ``k = 1..N`` (eq. 29, D of eq. 28);
* end state by Gauss quadrature ``X_f − X₀ − (h/2) Σ w_k f_k = 0`` (eq. 30);
* continuity linkage ``X_f^(r) − X₀^(r+1) = 0`` (eq. 34); boundary values as bounds on
  ``X₀^(1)`` and ``X_f^(P)`` (eq. 32); path constraints at the LG points (eq. 33).

Radau (LGR), per sub-interval: state at the ``N`` LGR points (``τ₁ = −1``) and at ``τ = +1``,
control at the LGR points, defects at the LGR points, and the same linkage.

Scaling: decision variables are ``z = x / s`` with ``s`` the problem's state/control scales
and ``tf_guess`` for ``tf``; the defect, quadrature and linkage rows of state ``i`` are divided
by ``s_i``; the objective is divided by ``|J(guess)|``. IPOPT's gradient-based scaling is kept
on top. Multipliers are un-scaled before costate estimation.

References
----------
S2, eq. 17–37. Benson et al., J. Guid. Control Dyn. 29(6), 2006. Garg et al., Automatica
46(11), 2010.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from adcskit.optimal_control._nlp import DEFAULT_IPOPT_OPTIONS, cached_nlp
from adcskit.optimal_control._schemes import SCHEMES
from adcskit.optimal_control.problem import Mesh, OptimalControlProblem

__all__ = ["METHODS", "DEFAULT_IPOPT_OPTIONS", "get_transcription"]

#: The transcriptions by name, with a one-line description (the scheme objects behind them:
#: ``adcskit.optimal_control._schemes.SCHEMES``).
METHODS: dict[str, str] = {name: scheme.description for name, scheme in SCHEMES.items()}

# "sx": the whole NLP in SX (fast evaluation, slower build); "mx": MX graph calling the mapped
# SX dynamics (fast build, derivatives of f computed once and mapped); "mx-expand": MX
# expanded to SX by nlpsol. Chosen by measurement (docs/benchmarks.md).
SYMBOLIC = "sx"


@dataclass(slots=True)
class _Interval:
    n: int
    D: np.ndarray  # (n, n+1)
    tau: np.ndarray  # collocation points (n,)
    w: np.ndarray  # quadrature weights (n,)
    support: np.ndarray  # (n+1,) state support points
    a: float  # start fraction
    b: float  # end fraction
    xs: slice  # support states in z, (n+1)*nx, column-major by node
    us: slice  # controls, n*nu
    xe: slice | None  # gauss end state
    g_def: slice  # defect rows n*nx
    g_quad: slice | None
    g_link: slice | None


def interval_layout(method: str, mesh: Mesh, nx: int, nu: int, iz: int, ig: int) -> tuple[list[_Interval], int, int]:
    """Per-interval nodes, weights and the slices of ``z`` / ``g`` they own, from offsets ``iz``/``ig``.

    Shared by the single-phase and the multi-phase transcriptions; returns the intervals and the
    offsets after them.
    """
    breaks = mesh.breaks
    P = mesh.n_intervals
    scheme = SCHEMES[method]
    out: list[_Interval] = []
    for r, n in enumerate(mesh.nodes):
        D, tau, w, support = scheme.nodes(n)
        xs = slice(iz, iz + (n + 1) * nx)
        iz = xs.stop
        us = slice(iz, iz + n * nu)
        iz = us.stop
        xe = None
        if scheme.end_state_variable:
            xe = slice(iz, iz + nx)
            iz = xe.stop
        g_def = slice(ig, ig + n * nx)
        ig = g_def.stop
        g_quad = None
        if scheme.end_state_variable:
            g_quad = slice(ig, ig + nx)
            ig = g_quad.stop
        g_link = None
        if r < P - 1:
            g_link = slice(ig, ig + nx)
            ig = g_link.stop
        out.append(_Interval(n, D, tau, w, support, breaks[r], breaks[r + 1], xs, us, xe, g_def, g_quad, g_link))
    return out, iz, ig


def interval_times(intervals: list[_Interval], t0: float, tf: float):
    """``(support times, collocation times, end time)`` of every interval on ``[t0, tf]`` (s)."""
    out = []
    for iv in intervals:
        ts = t0 + (tf - t0) * (iv.a + (iv.support + 1.0) / 2.0 * (iv.b - iv.a))
        tc = t0 + (tf - t0) * (iv.a + (iv.tau + 1.0) / 2.0 * (iv.b - iv.a))
        out.append((ts, tc, t0 + (tf - t0) * iv.b))
    return out


def unpack_intervals(intervals: list[_Interval], z: np.ndarray, sx: np.ndarray, su: np.ndarray):
    """Physical ``(support states, controls, end state)`` of every interval from the scaled ``z``."""
    nx, nu = sx.size, su.size
    out = []
    for iv in intervals:
        xs = z[iv.xs].reshape(iv.n + 1, nx) * sx
        us = z[iv.us].reshape(iv.n, nu) * su if nu else np.zeros((iv.n, 0))
        xe = z[iv.xe] * sx if iv.xe is not None else xs[-1]
        out.append((xs, us, xe))
    return out


def interval_bounds(lbz, ubz, method: str, intervals: list[_Interval], phase, sx, su) -> None:
    """Write the scaled box bounds of the states and controls of every interval and the fixed
    boundary states of ``phase`` (an :class:`OptimalControlProblem` or a multi-phase
    ``Phase``: ``state_lower/upper``, ``control_lower/upper``, ``initial_state``,
    ``final_state``; NaN: free) into ``lbz``, ``ubz`` (in place)."""
    nx = sx.size
    for iv in intervals:
        lbz[iv.xs] = np.tile(phase.state_lower / sx, iv.n + 1)
        ubz[iv.xs] = np.tile(phase.state_upper / sx, iv.n + 1)
        if np.size(su):
            lbz[iv.us] = np.tile(phase.control_lower / su, iv.n)
            ubz[iv.us] = np.tile(phase.control_upper / su, iv.n)
        if iv.xe is not None:
            lbz[iv.xe], ubz[iv.xe] = phase.state_lower / sx, phase.state_upper / sx
    first, last = intervals[0], intervals[-1]
    fix0 = np.isfinite(phase.initial_state)
    i0 = np.arange(first.xs.start, first.xs.start + nx)
    lbz[i0[fix0]] = ubz[i0[fix0]] = (phase.initial_state / sx)[fix0]
    fixf = np.isfinite(phase.final_state)
    i_f = np.arange(last.xe.start, last.xe.stop) if last.xe is not None else np.arange(last.xs.stop - nx, last.xs.stop)
    lbz[i_f[fixf]] = ubz[i_f[fixf]] = (phase.final_state / sx)[fixf]


def pack_intervals(z: np.ndarray, intervals: list[_Interval], t0: float, tf: float, xfun, ufun, sx, su) -> None:
    """Write the scaled states and controls of guess functions ``xfun(t) -> (M, nx)``,
    ``ufun(t) -> (M, nu)`` into ``z`` at the intervals' slices (in place)."""
    nu = np.size(su)
    for iv, (ts, tc, tend) in zip(intervals, interval_times(intervals, t0, tf), strict=True):
        z[iv.xs] = (xfun(ts) / sx).ravel()
        if nu:
            z[iv.us] = (ufun(tc) / su).ravel()
        if iv.xe is not None:
            z[iv.xe] = xfun(np.array([tend]))[0] / sx


@dataclass(frozen=True, slots=True)
class _Symbols:
    """Symbolic states, controls and times of one interval (physical units)."""

    Xs: Any  # (nx, n+1) support states
    U: Any  # (nu, n) controls
    h: Any  # interval length (s)
    Xc: Any  # (nx, n) collocated states
    Xend: Any  # (nx,) end state
    tc: Any  # (1, n) collocation times


def interval_symbols(method: str, intervals: list[_Interval], z, sx, su, t0, T, nx: int, nu: int, Sym) -> list[_Symbols]:
    """Per-interval symbols of a phase on ``[t0, t0 + T]`` from the scaled decision vector ``z``.

    The one collocation core shared by the single- and the multi-phase transcriptions.
    """
    scheme = SCHEMES[method]
    per = []
    for iv in intervals:
        Xs = ca.reshape(z[iv.xs], nx, iv.n + 1) * ca.repmat(sx, 1, iv.n + 1)
        U = ca.reshape(z[iv.us], nu, iv.n) * ca.repmat(su, 1, iv.n) if nu else Sym(0, iv.n)
        h = T * (iv.b - iv.a)
        tc = t0 + T * iv.a + ca.DM((iv.tau[None, :] + 1.0) / 2.0) * h
        Xend = z[iv.xe] * sx if scheme.end_state_variable else Xs[:, -1]
        per.append(_Symbols(Xs, U, h, Xs[:, scheme.collocated], Xend, tc))
    return per


def collocation_rows(intervals: list[_Interval], per: list[_Symbols], F_all, sx) -> list:
    """Constraint rows of a phase in NLP order, per interval: defects (S2 eq. 29), [Gauss:
    end-state quadrature, eq. 30], linkage to the next interval (eq. 34); all rows of state
    ``i`` divided by ``sx_i``. ``F_all``: the dynamics at every collocation point, ``(nx, ntot)``."""
    rows: list[Any] = []
    off = 0
    for r, (iv, q) in enumerate(zip(intervals, per, strict=True)):
        Fm = F_all[:, off : off + iv.n]
        rows.append(ca.vec((ca.mtimes(q.Xs, ca.DM(iv.D.T)) - q.h / 2.0 * Fm) / ca.repmat(sx, 1, iv.n)))
        if iv.g_quad is not None:
            rows.append((q.Xend - q.Xs[:, 0] - q.h / 2.0 * ca.mtimes(Fm, ca.DM(iv.w))) / sx)
        if iv.g_link is not None:
            rows.append((q.Xend - per[r + 1].Xs[:, 0]) / sx)
        off += iv.n
    return rows


def quadrature(intervals: list[_Interval], per: list[_Symbols], V_all, acc):
    """``acc + Σ_r (h_r/2) Σ_k w_k V_k``: the quadrature of the values ``V_all`` at every
    collocation point (Lagrange cost, integrals)."""
    off = 0
    for iv, q in zip(intervals, per, strict=True):
        acc = acc + q.h / 2.0 * ca.mtimes(V_all[:, off : off + iv.n], ca.DM(iv.w))
        off += iv.n
    return acc


class _Transcription:
    """The compiled NLP of one problem structure on one mesh."""

    def __init__(
        self, problem: OptimalControlProblem, method: str, mesh: Mesh, ipopt: dict[str, Any], symbolic: str = "sx"
    ):
        self.method = method
        self.mesh = mesh
        nx, nu, npath = problem.n_states, problem.n_controls, problem.n_path
        self.nx, self.nu, self.npath = nx, nu, npath
        x = ca.SX.sym("x", nx)
        u = ca.SX.sym("u", nu)
        t = ca.SX.sym("t")
        fx = ca.vertcat(*_as_list(problem.dynamics(x, u, t), nx, "dynamics"))
        self.f_fun = ca.Function("f", [x, u, t], [fx])
        gx = ca.SX(0) if problem.lagrange is None else _scalar(problem.lagrange(x, u, t), "lagrange")
        self.g_fun = ca.Function("g", [x, u, t], [gx])
        lam = ca.SX.sym("lam", nx)
        ham = gx + ca.dot(lam, fx)
        self.h_fun = ca.Function("H", [x, u, t, lam], [ham, ca.gradient(ham, u) if nu else ca.SX(0, 1)])
        if npath:
            cx = ca.vertcat(*_as_list(problem.path(x, u, t), npath, "path"))
            self.c_fun = ca.Function("C", [x, u, t], [cx])

        # ---------------- layout
        self.intervals, iz, ig = interval_layout(method, mesh, nx, nu, 0, 0)
        self.g_path = slice(ig, ig + npath * sum(mesh.nodes))
        ig = self.g_path.stop
        self.i_tf = iz
        self.nz = iz + 1
        self.ng = ig

        # ---------------- symbolic NLP (vectorised: one mapped call of f over all nodes)
        Sym = ca.MX if symbolic.startswith("mx") else ca.SX
        z = Sym.sym("z", self.nz)
        p = Sym.sym("p", nx + nu + 3)  # [sx, su, s_tf, t0, cJ]
        sx, su = p[:nx], p[nx : nx + nu]
        tf = p[nx + nu] * z[self.i_tf]
        t0 = p[nx + nu + 1]
        cJ = p[nx + nu + 2]
        T = tf - t0
        ntot = sum(mesh.nodes)
        per = interval_symbols(method, self.intervals, z, sx, su, t0, T, nx, nu, Sym)
        Xc_all = ca.horzcat(*[q.Xc for q in per])
        U_all = ca.horzcat(*[q.U for q in per])
        T_all = ca.horzcat(*[q.tc for q in per])
        F_all = self.f_fun.map(ntot)(Xc_all, U_all, T_all)
        ordered = collocation_rows(self.intervals, per, F_all, sx)
        lag = Sym(0)
        if problem.lagrange is not None:
            lag = quadrature(self.intervals, per, self.g_fun.map(ntot)(Xc_all, U_all, T_all), lag)
        if npath:
            ordered.append(ca.vec(self.c_fun.map(ntot)(Xc_all, U_all, T_all)))
        g = ca.vertcat(*ordered)
        J = lag
        if problem.mayer is not None:
            J = J + _scalar(problem.mayer(per[0].Xs[:, 0], t0, per[-1].Xend, tf), "mayer")
        self.J_fun = ca.Function("J", [z, p], [J])
        nlp = {"x": z, "p": p, "f": J / cJ, "g": g}
        opts = {"print_time": False, "ipopt": dict(ipopt)}
        if symbolic == "mx-expand":
            opts["expand"] = True
        self.solver = ca.nlpsol("ocp", "ipopt", nlp, opts)

    # ------------------------------------------------------------------ numeric helpers
    def lagrangian_gradient(self, z, p, lam_f, lam_g):
        """``(f, g, ∇_z(lam_f f + lam_gᵀ g), ∇_p)`` of the scaled NLP (IPOPT's oracle)."""
        fun = getattr(self, "_grad_fun", None)
        if fun is None:
            fun = self._grad_fun = self.solver.get_function("nlp_grad")
        return fun(z, p, lam_f, lam_g)

    def times(self, t0: float, tf: float):
        """Support-state times, collocation times and end times per interval."""
        return interval_times(self.intervals, t0, tf)

    def bounds(self, problem: OptimalControlProblem, sx, su, s_tf):
        lbz = np.full(self.nz, -np.inf)
        ubz = np.full(self.nz, np.inf)
        interval_bounds(lbz, ubz, self.method, self.intervals, problem, sx, su)
        lbz[self.i_tf], ubz[self.i_tf] = problem.tf_bounds[0] / s_tf, problem.tf_bounds[1] / s_tf
        lbg = np.zeros(self.ng)
        ubg = np.zeros(self.ng)
        if self.npath:
            ntot = sum(self.mesh.nodes)
            lbg[self.g_path] = np.tile(problem.path_lower, ntot)
            ubg[self.g_path] = np.tile(problem.path_upper, ntot)
        return lbz, ubz, lbg, ubg

    def pack(self, t0, tf, xfun, ufun, sx, su, s_tf) -> np.ndarray:
        """Scaled decision vector from guess functions ``xfun(t) -> (M, nx)``, ``ufun``."""
        z = np.zeros(self.nz)
        pack_intervals(z, self.intervals, t0, tf, xfun, ufun, sx, su)
        z[self.i_tf] = tf / s_tf
        return z

    def unpack(self, z, sx, su, s_tf):
        """Physical states (support points), controls and end states per interval, and tf."""
        return unpack_intervals(self.intervals, z, sx, su), float(z[self.i_tf] * s_tf)


def _as_list(expr, n: int, what: str) -> list:
    if isinstance(expr, ca.SX | ca.MX | ca.DM):
        if expr.numel() != n:
            raise ValueError(f"{what} must return {n} values; got {expr.numel()}")
        return [expr[i] for i in range(n)]
    items = list(expr)
    if len(items) != n:
        raise ValueError(f"{what} must return {n} values; got {len(items)}")
    return items


def _scalar(expr, what: str):
    if isinstance(expr, ca.SX | ca.MX | ca.DM):
        if expr.numel() != 1:
            raise ValueError(f"{what} must return a scalar; got {expr.numel()} values")
        return expr
    return ca.SX(expr) if isinstance(expr, int | float) else expr


def get_transcription(
    problem: OptimalControlProblem, method: str, mesh: Mesh, ipopt: dict[str, Any], symbolic: str | None = None
) -> _Transcription:
    """The cached compiled NLP for this problem structure (see module docstring; the one
    cache of :mod:`adcskit.optimal_control._nlp`)."""
    symbolic = SYMBOLIC if symbolic is None else symbolic
    key = (
        "single-phase",
        symbolic,
        problem.dynamics,
        problem.mayer,
        problem.lagrange,
        problem.path,
        problem.n_states,
        problem.n_controls,
        problem.n_path,
        method,
        mesh,
        tuple(sorted((k, repr(v)) for k, v in ipopt.items())),
    )
    return cached_nlp(key, lambda: _Transcription(problem, method, mesh, ipopt, symbolic))
