"""What the single- and the multi-phase solvers share: one NLP cache, IPOPT options and calls,
guess interpolation, solution assembly (costates, Hamiltonian) and the multiplier transfer of
warm starts.

Private: :mod:`adcskit.optimal_control.solve` and :mod:`adcskit.optimal_control.multiphase`
both import it (neither imports the other's private helpers); the public names defined here
(:data:`DEFAULT_IPOPT_OPTIONS`, :data:`WARM_START_IPOPT_OPTIONS`, :func:`clear_cache`) are
re-exported by :mod:`adcskit.optimal_control`.

NLP cache: one least-recently-used cache of compiled NLPs (``nlpsol`` objects with their
layout), single- and multi-phase alike, keyed by everything that shapes the NLP (the problem's
callables or object, dimensions, scheme, mesh(es), symbolic mode and solver options) and
holding the :data:`NLP_CACHE_SIZE` most recently used builds.
"""

from __future__ import annotations

import time
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from adcskit._validation import check_int
from adcskit.errors import InputTypeError
from adcskit.optimal_control._schemes import SCHEMES
from adcskit.optimal_control.problem import Mesh

__all__ = ["DEFAULT_IPOPT_OPTIONS", "WARM_START_IPOPT_OPTIONS", "NLP_CACHE_SIZE", "clear_cache"]

DEFAULT_IPOPT_OPTIONS: dict[str, Any] = {
    "print_level": 0,
    "sb": "yes",
    "linear_solver": "mumps",
    "hessian_approximation": "exact",
    "tol": 1e-9,
    "acceptable_tol": 1e-7,
    "max_iter": 500,
    "mu_strategy": "adaptive",
}

#: IPOPT options of a warm start (:func:`solve` with a previous solution as ``guess``): start
#: from the given primal and dual point (``warm_start_init_point``), move it off the bounds by
#: almost nothing, and keep the barrier parameter small and monotone. IPOPT's cold defaults
#: (bound push 1e-2, ``mu_init`` 0.1, adaptive μ) push a bang-bang optimum into the interior
#: and re-solve from there, which can land on another local optimum (issue 11).
WARM_START_IPOPT_OPTIONS: dict[str, Any] = {
    "warm_start_init_point": "yes",
    "warm_start_bound_push": 1e-9,
    "warm_start_bound_frac": 1e-9,
    "warm_start_slack_bound_push": 1e-9,
    "warm_start_slack_bound_frac": 1e-9,
    "warm_start_mult_bound_push": 1e-9,
    "mu_strategy": "monotone",
    "mu_init": 1e-8,
}


#: Number of compiled NLPs (single- and multi-phase together) the cache keeps.
NLP_CACHE_SIZE = 24

_CACHE: OrderedDict[tuple, Any] = OrderedDict()


def cached_nlp(key: tuple, build: Callable[[], Any]) -> Any:
    """The cached build for ``key``, or ``build()`` stored under it (least recently used out)."""
    tr = _CACHE.get(key)
    if tr is None:
        tr = build()
        _CACHE[key] = tr
        while len(_CACHE) > NLP_CACHE_SIZE:
            _CACHE.popitem(last=False)
    else:
        _CACHE.move_to_end(key)
    return tr


def clear_cache() -> None:
    """Forget every compiled NLP, single- and multi-phase (e.g. to time a cold build).

    Examples
    --------
    >>> from adcskit.optimal_control import clear_cache
    >>> clear_cache()                                     # the next solve rebuilds its NLP
    """
    _CACHE.clear()


def _resolve_options(options: dict[str, Any] | None, *, warm: bool = False) -> dict[str, Any]:
    opts = dict(DEFAULT_IPOPT_OPTIONS)
    if warm:
        opts.update(WARM_START_IPOPT_OPTIONS)
    if options is not None:
        if not isinstance(options, dict):
            raise InputTypeError(f"ipopt_options must be a dict of IPOPT options; got {options!r}")
        for key, value in options.items():
            if not isinstance(key, str) or not (
                isinstance(value, str) or (isinstance(value, int | float) and not isinstance(value, bool)
                                           and np.isfinite(value))):
                raise InputTypeError(f"ipopt_options must map option names (str) to a string or a finite "
                                     f"number; got {key!r}: {value!r}")
        opts.update(options)
    return opts


def _as_mesh(mesh) -> Mesh:
    if isinstance(mesh, Mesh):
        return mesh
    try:
        n_int, n_nodes = mesh
    except (TypeError, ValueError):
        raise InputTypeError(f"mesh must be a Mesh or (n_intervals, n_nodes); got {mesh!r}") from None
    n_int = check_int("mesh[0] (number of intervals)", n_int, minimum=1, maximum=100_000)
    n_nodes = check_int("mesh[1] (nodes per interval)", n_nodes, minimum=1, maximum=1000)
    return Mesh.uniform(n_int, n_nodes)


def _run_ipopt(solver, z0, p, lbz, ubz, lbg, ubg, duals: dict[str, np.ndarray]):
    """One IPOPT call of a built NLP: ``(z, lam_g, lam_x, g, stats, status, success, solve_s)``."""
    t_solve = time.perf_counter()
    res = solver(x0=z0, p=p, lbx=lbz, ubx=ubz, lbg=lbg, ubg=ubg, **duals)
    solve_s = time.perf_counter() - t_solve
    stats = solver.stats()
    z, lam_g, lam_x, g = (np.asarray(res[k]).ravel() for k in ("x", "lam_g", "lam_x", "g"))
    status = str(stats.get("return_status", "unknown"))
    return z, lam_g, lam_x, g, stats, status, bool(stats.get("success", False)), solve_s


def _interp_fun(t_samples, values, t0_src, tf_src, t0_new, tf_new):
    """Linear interpolation of samples given on ``[t0_src, tf_src]``, time-scaled onto
    ``[t0_new, tf_new]`` (the samples need not span the whole interval: controls sampled at
    collocation points are held constant outside them by :func:`numpy.interp`)."""
    ts = np.asarray(t_samples, float)
    vals = np.asarray(values, float)

    def f(t):
        s = t0_src + (np.asarray(t, float) - t0_new) / (tf_new - t0_new) * (tf_src - t0_src)
        return np.column_stack([np.interp(s, ts, vals[:, i]) for i in range(vals.shape[1])]) if vals.shape[1] else np.zeros((np.size(t), 0))

    return f


def _solution_funs(prev, t0: float, tf: float):
    """State and control functions of a previous solution on ``[t0, tf]`` (time rescaled)."""
    a, b = prev.t0, prev.tf

    def s(t):
        return a + (np.asarray(t, float) - t0) / (tf - t0) * (b - a)

    return (lambda t: prev.state_at(s(t))), (lambda t: prev.control_at(s(t)))


def _defect_duals(lam_g, method, intervals, times, lamfun, sx, cJ) -> None:
    """Write the multipliers of the defect, Gauss quadrature and interval-link rows that the
    costate function ``lamfun(t) -> (M, nx)`` implies (the costate mapping inverted) into
    ``lam_g`` (CasADi's sign and scaling: objective ``J / cJ``, rows of state ``i`` over
    ``sx_i``).

    Radau: ``Λ̃_k = w_k λ(t_k)``; Gauss: ``Λ̃_k = w_k (λ(t_k) − λ(t_end))`` and ``Λ̃_f =
    λ(t_end)``; the row linking an interval's end state to the next interval's start:
    ``−λ(t_end)``; CasADi's multiplier is ``−Λ̃ sx / cJ``.
    """
    for iv, (_ts, tc, tend) in zip(intervals, times, strict=True):
        lc = lamfun(tc, "right")  # Radau's τ = −1 point: the estimate of the interval starting there
        le = lamfun(np.array([tend]), "left")[0]
        lt = SCHEMES[method].defect_multipliers(lc, le, iv.w)
        if iv.g_quad is not None:
            lam_g[iv.g_quad] = -le * sx / cJ
        lam_g[iv.g_def] = (-lt * sx / cJ).ravel()
        if iv.g_link is not None:
            lam_g[iv.g_link] = le * sx / cJ


def _path_duals(old_intervals, old_lam_path: np.ndarray, new_intervals) -> np.ndarray:
    """Path-constraint multipliers carried to another mesh as a density in time.

    An NLP path multiplier at collocation point ``k`` is ``μ(t_k) w_k h/2`` for a multiplier
    density ``μ``; ``μ`` is interpolated linearly in the normalised time (it jumps where a
    constraint becomes active, so no polynomial) and multiplied by the new weights.
    """
    frac_old = np.concatenate([iv.a + (iv.tau + 1.0) / 2.0 * (iv.b - iv.a) for iv in old_intervals])
    wh_old = np.concatenate([iv.w * (iv.b - iv.a) / 2.0 for iv in old_intervals])
    dens = old_lam_path / wh_old[:, None]
    frac_new = np.concatenate([iv.a + (iv.tau + 1.0) / 2.0 * (iv.b - iv.a) for iv in new_intervals])
    wh_new = np.concatenate([iv.w * (iv.b - iv.a) / 2.0 for iv in new_intervals])
    out = np.column_stack([np.interp(frac_new, frac_old, dens[:, i]) for i in range(dens.shape[1])])
    return out * wh_new[:, None]


def _bound_duals(grad_fun, z0, p, lam_g, lbz, ubz) -> np.ndarray:
    """Bound multipliers consistent with ``lam_g`` at ``z0``: ``λ_x = −∇_z(f + λ_gᵀ g)`` on
    active bounds (fixed variables: any sign; upper: >= 0; lower: <= 0), zero elsewhere."""
    grad = -np.asarray(grad_fun(z0, p, 1.0, lam_g)[2]).ravel()
    tol_b = 1e-9 * (1.0 + np.abs(z0))
    fixed = ubz - lbz <= tol_b
    up = ~fixed & (z0 >= ubz - tol_b)
    lo = ~fixed & (z0 <= lbz + tol_b)
    lam_x = np.zeros_like(z0)
    lam_x[fixed] = grad[fixed]
    lam_x[up] = np.maximum(grad[up], 0.0)
    lam_x[lo] = np.minimum(grad[lo], 0.0)
    return lam_x


@dataclass(frozen=True, slots=True)
class _Piece:
    ts: np.ndarray  # state support times
    xs: np.ndarray  # (n+1, nx)
    tc: np.ndarray  # collocation times
    uc: np.ndarray  # (n, nu)
    t_end: float
    x_end: np.ndarray
    lam_t: np.ndarray | None = None  # costate sample times: support points (Gauss: and t_end)
    lam: np.ndarray | None = None  # costate estimates at lam_t


def _assemble(method: str, intervals, parts, times, lam_g: np.ndarray, cJ: float, sx: np.ndarray, ham):
    """Pieces, samples, costates and Hamiltonian of one phase from its NLP point.

    Shared by :func:`solve` and the multi-phase solver. ``parts`` are the physical
    ``(xs, us, xe)`` per interval, ``times`` the ``(ts, tc, t_end)`` per interval,
    ``lam_g`` CasADi's constraint multipliers (objective scaled by ``1/cJ``, rows of state
    ``i`` by ``1/sx_i``) and ``ham(x, u, t, λ) -> (H, ∂H/∂u)``. Costate mapping: module
    docstring. Returns ``(pieces, samples)`` with ``samples`` the solution's ``t, x,
    t_control, u, costate, hamiltonian, switching`` arrays.
    """
    scheme = SCHEMES[method]
    nx = sx.size
    nu = parts[0][1].shape[1] if parts else 0
    pieces = []
    t_list, x_list, tc_list, u_list, lam_list, ham_list, sw_list = [], [], [], [], [], [], []
    last = len(intervals) - 1
    for r, (iv, (xs, us, xe), (ts, tc, tend)) in enumerate(zip(intervals, parts, times, strict=True)):
        # Λ̃_k in physical units; CasADi's Lagrangian is J + λᵀg, Pontryagin's sign is the opposite
        lt = -lam_g[iv.g_def].reshape(iv.n, nx) * cJ / sx
        lf = -lam_g[iv.g_quad] * cJ / sx if iv.g_quad is not None else None  # Gauss: Λ̃_f
        lam_c, lam_s, lam_end = scheme.costates(lt, lf, iv)
        xc = xs[scheme.collocated]
        t_list.append(ts[scheme.sampled])
        x_list.append(xs[scheme.sampled])
        lam_t, lam_all = scheme.costate_times(ts, tend), np.vstack([lam_s, lam_end[None, :]])
        pieces.append(_Piece(ts=ts, xs=xs, tc=tc, uc=us, t_end=tend, x_end=xe, lam_t=lam_t, lam=lam_all))
        lam_list.append(lam_s)
        tc_list.append(tc)
        u_list.append(us)
        for k in range(iv.n):
            hk, hu = ham(xc[k], us[k], tc[k], lam_c[k])
            ham_list.append(float(hk))
            sw_list.append(np.asarray(hu).ravel())
        if r == last:
            t_list.append([tend])
            x_list.append(xe[None, :])
            lam_list.append(lam_end[None, :])
    samples = {
        "t": np.concatenate(t_list),
        "x": np.vstack(x_list),
        "t_control": np.concatenate(tc_list),
        "u": np.vstack(u_list),
        "costate": np.vstack(lam_list),
        "hamiltonian": np.array(ham_list),
        "switching": np.vstack(sw_list) if sw_list else np.zeros((0, nu)),
    }
    return tuple(pieces), samples
