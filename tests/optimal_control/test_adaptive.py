"""hp mesh refinement: error estimate, refinement rules, adaptive solves (quick settings)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adcskit.errors import InputError, InputTypeError
from adcskit.optimal_control import (
    AdaptiveSolution,
    Mesh,
    OptimalControlSolution,
    bang_bang,
    estimate_error,
    guess_from_function,
    refine_mesh,
    solve,
    solve_adaptive,
    symmetry_breaking_guess,
)
from adcskit.optimal_control.adaptive import _lgr_integration
from adcskit.optimal_control.problems import (
    double_integrator_min_energy,
    double_integrator_min_time,
    hypersensitive,
)


@settings(max_examples=20, deadline=None)
@given(m=st.integers(2, 12), deg=st.integers(0, 11), seed=st.integers(0, 1000))
def test_lgr_integration_matrix_is_exact_for_polynomials(m, deg, seed):
    # ∫_{-1}^{e_j} p is exact for deg(p) <= m - 1 (m interpolation points)
    deg = min(deg, m - 1)
    c = np.random.default_rng(seed).normal(size=deg + 1)
    s, I = _lgr_integration(m)
    ends = np.concatenate((s[1:], [1.0]))
    exact = np.polynomial.polynomial.polyval(ends, np.polynomial.polynomial.polyint(c, lbnd=-1.0))
    assert np.allclose(I @ np.polynomial.polynomial.polyval(s, c), exact, atol=1e-12)


def test_error_estimate_zero_for_polynomial_solution_and_large_across_a_switch():
    # minimum energy: the state is a cubic, represented exactly by 3 LGR points + end point
    sol = solve(double_integrator_min_energy(), method="radau", mesh=(2, 3))
    assert estimate_error(sol).max() < 1e-10
    # minimum time is bang-bang with the switch at tf/2 = 1: on a 3-interval mesh the switch
    # falls inside the middle interval, whose error must dominate
    sol = solve(double_integrator_min_time(), method="radau", mesh=(3, 4))
    err = estimate_error(sol)
    assert err.argmax() == 1 and err[1] > 1e-3 and max(err[0], err[2]) < 1e-8


def test_refine_mesh_rules():
    mesh = Mesh.uniform(3, 4)
    # ph rule (Patterson, Hager & Rao 2015 eq. 31): P = ceil(log(e/tol)/log N) = ceil(log(1e3)/log 4) = 5
    new, act = refine_mesh(mesh, [1e-3, 1e-9, 1e-9], tol=1e-6)
    assert act == ("p", "keep", "keep") and new.nodes == (9, 4, 4)
    # beyond n_max: split into B = ceil((N+P)/n_min) = ceil(9/3) = 3 equal parts (eq. 32)
    new, act = refine_mesh(mesh, [1e-3, 1e-9, 1e-9], tol=1e-6, n_max=8)
    assert act[0] == "h" and new.nodes == (3, 3, 3, 4, 4)
    assert np.allclose(new.fractions[:3], 1 / 9)
    # a control jump splits at the jump
    sol = solve(double_integrator_min_time(), method="radau", mesh=(3, 4))
    new, act = refine_mesh(
        sol.mesh, estimate_error(sol), tol=1e-6, pieces=sol.pieces,
        control_lower=sol.problem.control_lower, control_upper=sol.problem.control_upper,
    )
    assert act[1] == "h-jump" and new.n_intervals == 4
    t_break = new.breaks[2] * sol.tf
    assert abs(t_break - 1.0) < 0.2  # the switch time is tf/2 = 1 s (Bryson & Ho §7.3)
    with pytest.raises(InputError):
        refine_mesh(mesh, [1.0], tol=1e-6)


@pytest.mark.parametrize("method", ["radau", "gauss"])
def test_solve_adaptive_bang_bang_meets_tolerance(method):
    # Bryson & Ho §7.3: tf = 2 sqrt(d/a) = 2, switch at 1, costate λ_x = -2/(a tf) = -1
    # 3 equal intervals: the switch (t = 1) lies inside the middle one and must be resolved
    sol = solve_adaptive(double_integrator_min_time(), tol=1e-7, method=method, mesh=(3, 4))
    assert isinstance(sol, AdaptiveSolution) and isinstance(sol, OptimalControlSolution)
    assert sol.success and sol.certificate.satisfied
    assert sol.max_error <= 1e-7 and np.all(sol.interval_errors <= 1e-7)
    assert sol.interval_errors.shape == (sol.mesh.n_intervals,)
    assert abs(sol.tf - 2.0) < 1e-6
    assert np.allclose(sol.state_at(1.0), [0.5, 1.0], atol=1e-5)  # x(1) = a/2, v(1) = a
    # the refinement put a mesh break on the switch (quadrature-mean placement, exact for a
    # control entering linearly)
    assert np.min(np.abs(sol.mesh.breaks * sol.tf - 1.0)) < 1e-6
    if method == "gauss":  # switching-function zero from the (exact) Gauss costates
        assert abs(bang_bang(sol).switch_times[0][0] - 1.0) < 1e-3
    assert len(sol.mesh_history) >= 2 and sol.mesh_history[-1].max_error == sol.max_error
    if method == "gauss":  # Gauss costates are exact here to solver tolerance (test_solve.py)
        assert np.allclose(sol.costate[:, 0], -1.0, atol=1e-5)
    d = sol.to_dict()
    assert d["certificate"]["satisfied"] and len(d["mesh_history"]) == len(sol.mesh_history)


def test_hp_needs_fewer_points_than_uniform_on_hypersensitive():
    # hypersensitive (Rao & Mease 2000), tf = 10, quick tolerance 1e-4
    prob = hypersensitive(10.0)
    hp = solve_adaptive(prob, tol=1e-4)
    assert hp.success
    n_hp = sum(hp.mesh.nodes)
    # uniform refinement: the fewest equal 4-point intervals meeting the same tolerance
    n_uniform = None
    for k in (10, 20, 40, 80, 160):
        s = solve(prob, method="radau", mesh=(k, 4))
        if s.success and estimate_error(s).max() <= 1e-4:
            n_uniform = 4 * k
            break
    assert n_uniform is not None and n_hp < n_uniform


def test_limits_give_success_false_with_message():
    sol = solve_adaptive(hypersensitive(10.0), tol=1e-10, max_iterations=2)
    assert not sol.success and not sol.certificate.satisfied
    assert "max_iterations=2" in sol.message
    sol = solve_adaptive(hypersensitive(10.0), tol=1e-10, max_intervals=12)
    assert not sol.success and "max_intervals=12" in sol.message


def test_guess_options():
    prob = double_integrator_min_time()
    g = guess_from_function(lambda t: ([t / 2, 0.5], [0.0]), 0.0, 2.0)
    a = solve_adaptive(prob, tol=1e-6, guess=g)
    b = solve_adaptive(prob, tol=1e-6, guess=lambda t: ([t / 2, 0.5], [0.0]))
    c = solve_adaptive(prob, tol=1e-6, guess="linear")
    for s in (a, b, c):
        assert s.success and abs(s.tf - 2.0) < 1e-6
    sb = symmetry_breaking_guess(prob)
    assert np.all(np.abs(sb.u) <= 1.0) and np.ptp(sb.u) > 0.1
    with pytest.raises(InputError):
        solve_adaptive(prob, guess="zeros")


def test_input_validation():
    prob = double_integrator_min_time()
    with pytest.raises(InputError):
        solve_adaptive(prob, tol=-1.0)
    with pytest.raises(InputError):
        solve_adaptive(prob, method="euler")
    with pytest.raises(InputTypeError):
        solve_adaptive("problem")
    with pytest.raises(InputError):
        solve_adaptive(prob, n_min=5, n_max=3)
    with pytest.raises(InputTypeError):
        estimate_error(prob)


def test_refinements_are_warm_started():
    sol = solve_adaptive(hypersensitive(10.0), tol=1e-5)
    modes = [m.warm_start for m in sol.mesh_history]
    # refined meshes start from the interpolated primal values and multipliers
    assert modes[0] == "cold" and all(m == "primal-dual-interpolated" for m in modes[1:])
    assert sol.success and len(modes) > 1
    # warm-started refinements need few IPOPT iterations (the first, cold solve needs more)
    assert max(m.nit for m in sol.mesh_history[1:]) < sol.mesh_history[0].nit


# ------------------------------------------------------------ duals across meshes
def _bryson_denham_path(l=1.0 / 9.0):  # noqa: E741 - Bryson & Ho's symbol
    # the state inequality x <= l as a path constraint (so the path multipliers are exercised)
    from adcskit.optimal_control.problems import bryson_denham

    return bryson_denham(l).replace(state_upper=[np.inf, np.inf], path=lambda x, u, t: [x[0]], path_upper=[l])


@pytest.mark.parametrize("method", ["gauss", "radau"])
@pytest.mark.parametrize("which", ["min-energy", "hypersensitive", "bryson-denham-path"])
def test_interpolated_duals_reproduce_the_multipliers_on_the_same_mesh(method, which):
    # the dual transfer inverts the costate mapping; on the mesh the solution came from it
    # must return IPOPT's own multipliers (constraint rows exactly, bound multipliers from
    # stationarity) up to round-off — checks the signs and scalings of every row type
    from adcskit.optimal_control.solve import _interpolated_duals, _resolve_options
    from adcskit.optimal_control.transcription import get_transcription

    prob = {
        "min-energy": double_integrator_min_energy(distance=1.0, duration=1.0),
        "hypersensitive": hypersensitive(10.0),
        "bryson-denham-path": _bryson_denham_path(),
    }[which]
    opts = {"tol": 1e-12}
    a = solve(prob, method=method, mesh=(5, 4), ipopt_options=opts)
    assert a.success
    tr = get_transcription(prob, method, a.mesh, _resolve_options(opts))
    sx, su = prob.scales()
    lbz, ubz, _, _ = tr.bounds(prob, sx, su, max(abs(prob.tf_guess), 1e-9))
    lam_x, lam_g = _interpolated_duals(a, prob, tr, a.nlp.z, a.nlp.p, lbz, ubz, a.t0, a.tf)
    scale_g = np.abs(a.nlp.lam_g).max()
    np.testing.assert_allclose(lam_g, a.nlp.lam_g, rtol=0, atol=1e-9 * scale_g)
    # bound multipliers: equal where IPOPT's are not at its interior-point noise level
    np.testing.assert_allclose(lam_x, a.nlp.lam_x, rtol=0, atol=1e-6 * max(np.abs(a.nlp.lam_x).max(), 1.0))


@pytest.mark.parametrize("method", ["gauss", "radau"])
def test_primal_dual_warm_start_on_a_refined_mesh_reaches_the_same_optimum(method):
    prob = _bryson_denham_path()
    coarse = solve(prob, method=method, mesh=(6, 4))
    fine_mesh = Mesh(nodes=(4, 4, 5, 5, 4, 4, 6), fractions=(0.1, 0.15, 0.15, 0.2, 0.15, 0.15, 0.1))
    warm = solve(prob, method=method, mesh=fine_mesh, guess=coarse, transfer_duals=True)
    primal = solve(prob, method=method, mesh=fine_mesh, guess=coarse)
    cold = solve(prob, method=method, mesh=fine_mesh)
    assert warm.warm_start == "primal-dual-interpolated" and primal.warm_start == "primal"
    assert warm.success and cold.success
    # same NLP, same (unique) optimum: IPOPT tol 1e-9 on the scaled problem
    assert warm.objective == pytest.approx(cold.objective, rel=1e-8)
    np.testing.assert_allclose(warm.x, cold.x, atol=1e-6)
    np.testing.assert_allclose(warm.costate, cold.costate, atol=1e-4 * np.abs(cold.costate).max())


# ------------------------------------------------------------ mesh reduction
def test_reduction_lowers_degrees_and_merges_where_the_solution_is_a_low_polynomial():
    # minimum-energy double integrator: x cubic, u linear in t (Bryson & Ho §2.3), so one
    # interval of n_min = 3 points (state degree 3, control degree 2) represents it exactly
    sol = solve(double_integrator_min_energy(), method="radau", mesh=Mesh.uniform(4, 6))
    err = estimate_error(sol)
    assert err.max() < 1e-10
    lo, hi = sol.problem.control_lower, sol.problem.control_upper
    new, act = refine_mesh(sol.mesh, err, tol=1e-6, pieces=sol.pieces, control_lower=lo, control_upper=hi,
                           n_min=3, reduce=True)
    assert new.nodes == (3,) and act == ("merge",) * 4
    # without reduction the mesh is kept
    same, act0 = refine_mesh(sol.mesh, err, tol=1e-6, pieces=sol.pieces, n_min=3)
    assert same == sol.mesh and act0 == ("keep",) * 4
    # an interval above tol / reduce_margin is neither lowered nor merged
    err2 = err.copy()
    err2[1] = 5e-7
    new2, act2 = refine_mesh(sol.mesh, err2, tol=1e-6, pieces=sol.pieces, n_min=3, reduce=True)
    assert act2[1] == "keep" and new2.nodes[act2.index("keep")] == 6 and "merge" in act2
    with pytest.raises(InputError, match="pieces"):
        refine_mesh(sol.mesh, err, tol=1e-6, reduce=True)


def test_reduction_keeps_a_switch_on_its_mesh_point():
    # minimum-time double integrator with a mesh point on the switch (tf/2): both arcs are
    # exact (quadratic state, constant control) and may lose points, but merging across the
    # bang-bang switch would lose it
    sol = solve(double_integrator_min_time(), method="radau", mesh=Mesh(nodes=(5, 5), fractions=(0.5, 0.5)))
    assert abs(sol.tf - 2.0) < 1e-8
    err = estimate_error(sol)
    new, act = refine_mesh(sol.mesh, err, tol=1e-6, pieces=sol.pieces, control_lower=sol.problem.control_lower,
                           control_upper=sol.problem.control_upper, n_min=3, reduce=True)
    assert act == ("p-", "p-") and new.nodes == (3, 3) and new.fractions == (0.5, 0.5)


def test_solve_adaptive_with_mesh_reduction_reaches_the_optimum_on_fewer_points():
    from adcskit.optimal_control.problems import bryson_denham

    # Bryson & Ho 1975 §3.11: J* = 4/(9 l) = 4 for l = 1/9
    plain = solve_adaptive(bryson_denham(1.0 / 9.0), tol=1e-6, mesh_reduction=False)
    red = solve_adaptive(bryson_denham(1.0 / 9.0), tol=1e-6, mesh_reduction=True)
    assert plain.success and red.success and red.certificate.satisfied
    assert abs(red.objective - 4.0) / 4.0 < 1e-5
    # measured: 26 vs 60 collocation points (the unconstrained arcs are cubic)
    assert red.certificate.n_collocation < plain.certificate.n_collocation


@pytest.mark.parametrize("method", ["radau", "gauss"])
def test_a_switch_beside_a_mesh_point_moves_the_mesh_point_onto_it(method):
    # minimum-time double integrator (Bryson & Ho §7.3): tf = 2, one switch at tf/2 = 1 s.
    # A mesh point at 0.495 tf lies just before it: the switch shows only in the first
    # collocation value of the second interval (off the bound, the jump to the next value
    # below jump_threshold); the interval's quadrature-mean control puts the switch at
    # ~1% of it, beside the mesh point, which is moved there instead of splitting
    p = double_integrator_min_time()
    sol = solve(p, method=method, mesh=Mesh(nodes=(4, 4), fractions=(0.495, 0.505)))
    kw = dict(tol=1e-6, pieces=sol.pieces, control_lower=p.control_lower, control_upper=p.control_upper)
    new, act = refine_mesh(sol.mesh, estimate_error(sol), **kw)
    assert act == ("keep", "snap") and new.nodes == (4, 4)
    # on the current solution's switch tf/2: the mean estimate is exact for a control entering
    # linearly (agreement to the NLP tolerance, 1e-8 relative)
    assert abs(new.breaks[1] - 0.5) < 1e-6
    # re-solved on the moved mesh point: tf and the switch are exact to the NLP tolerance
    # (each arc's state is quadratic, represented exactly by 4 points)
    s2 = solve(p, method=method, mesh=new, guess=sol)
    assert abs(s2.tf - 2.0) < 1e-6 and abs(new.breaks[1] * s2.tf - 1.0) < 1e-6
    assert np.max(estimate_error(s2)) < 1e-6
    # snap=0: the old rule, the interval is split into equal parts with the switch still
    # beside the mesh point
    new0, act0 = refine_mesh(sol.mesh, estimate_error(sol), snap=0.0, **kw)
    assert act0 == ("keep", "h") and abs(new0.breaks[1] - 0.495) < 1e-12
    with pytest.raises(InputError):
        refine_mesh(sol.mesh, estimate_error(sol), snap=0.5, **kw)


def test_tiny_inputs_are_clear_errors():
    """Robustness findings: tol below double resolution, a span too short to sample, -0.0 spread,
    a gravity that overflows the brachistochrone time."""
    from adcskit.optimal_control import guess_from_function, random_guess
    from adcskit.optimal_control.problems import double_integrator_min_time
    from adcskit.optimal_control.problems.standard import brachistochrone_time

    with pytest.raises(InputError, match="tol must be in"):
        refine_mesh(Mesh.uniform(2, 4), [1e-3, 1e-9], tol=5e-324)
    with pytest.raises(InputError, match="too short to sample"):
        guess_from_function(lambda t: ([0.0, 0.0], [0.0]), 0.0, 5e-324)
    assert random_guess(double_integrator_min_time(), rng=0, spread=-0.0).x.shape[1] == 2
    with pytest.raises(InputError, match="overflow"):
        brachistochrone_time(1.0, 1.0, g=5e-324)
