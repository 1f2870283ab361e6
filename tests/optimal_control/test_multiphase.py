"""Multi-phase problems: links, free phase durations, parameters, events, integral constraints,
per-phase costates and Hamiltonian, adaptive refinement of every phase."""

from __future__ import annotations

import numpy as np
import pytest

from adcskit.errors import InputError, InputTypeError
from adcskit.optimal_control import (
    Link,
    MultiPhaseGuess,
    MultiPhaseProblem,
    MultiPhaseSolution,
    Phase,
    default_multiphase_guess,
    resimulate,
    solve_adaptive,
    solve_multiphase,
)


def _f(x, u, t, p):
    return [x[1], u[0]]


def _two_phase(distance_free: bool = False):
    """Rest-to-rest double integrator split at a free switch time into an accelerating and a
    braking phase; the distance is a static parameter p fixed by the event x_f = p."""
    acc = Phase(dynamics=_f, n_states=2, n_controls=1, control_lower=[1.0], control_upper=[1.0],
                initial_state=[0.0, 0.0], tf_bounds=(0.0, 10.0), name="accelerate")
    dec = Phase(dynamics=_f, n_states=2, n_controls=1, control_lower=[-1.0], control_upper=[-1.0],
                final_state=[np.nan, 0.0], t0_bounds=(0.0, 10.0), tf_bounds=(0.0, 10.0), name="brake")
    lo, hi = (0.5, 4.0) if distance_free else (1.0, 1.0)
    # with a free distance the controls (fixed at ±1) make tf = 2 sqrt(p) (Bryson & Ho §7.3);
    # J = p - tf = p - 2 sqrt(p) is least where 1 - 1/sqrt(p) = 0: p = 1, tf = 2, J = -1
    obj = (lambda e, p: p[0] - e[1].tf) if distance_free else (lambda e, p: e[1].tf)
    return MultiPhaseProblem(
        phases=[acc, dec], n_parameters=1, parameter_lower=[lo], parameter_upper=[hi], parameter_guess=[2.0 if distance_free else 1.0],
        objective=obj, events=lambda e, p: [e[1].xf[0] - p[0]], event_lower=[0.0], event_upper=[0.0],
    )


@pytest.mark.parametrize("method", ["radau", "gauss"])
def test_two_phase_min_time_with_parameter_and_event(method):
    sol = solve_multiphase(_two_phase(), method=method, meshes=[(2, 3), (2, 3)])
    assert isinstance(sol, MultiPhaseSolution) and sol.success
    a, b = sol.phases
    # Bryson & Ho §7.3: tf = 2 sqrt(d/a) = 2, switch at tf/2 = 1
    assert abs(a.tf - 1.0) < 1e-7 and abs(b.tf - 2.0) < 1e-7 and abs(b.t0 - a.tf) < 1e-9
    assert np.allclose(b.x[0], a.x[-1], atol=1e-9)  # state continuity link
    assert abs(sol.parameters[0] - 1.0) < 1e-12 and abs(sol.events[0]) < 1e-8
    # costates and Hamiltonian per phase: λ_x = -2/(a tf) = -1 and H ≡ -1 (free final time)
    for ph in sol.phases:
        assert np.allclose(ph.costate[:, 0], -1.0, atol=1e-5)
        assert np.allclose(ph.hamiltonian, -1.0, atol=1e-5)
    r = resimulate(b)  # each phase is an OptimalControlSolution with p fixed at its optimum
    assert r.success and r.terminal_miss_scaled < 1e-8


def test_free_parameter_is_optimised():
    sol = solve_multiphase(_two_phase(distance_free=True), meshes=[(2, 3), (2, 3)])
    assert sol.success
    assert abs(sol.parameters[0] - 1.0) < 1e-6 and abs(sol.objective + 1.0) < 1e-8


def _jump_integral_problem():
    p1 = Phase(dynamics=_f, n_states=2, n_controls=1, initial_state=[0.0, 0.0], tf_bounds=(1.0, 1.0),
               integrand=lambda x, u, t, p: [u[0] * u[0]], integral_upper=[3.0], name="burn")
    p2 = Phase(dynamics=_f, n_states=2, n_controls=1, control_lower=[0.0], control_upper=[0.0],
               t0_bounds=(1.0, 1.0), tf_bounds=(2.0, 2.0), name="coast")
    return MultiPhaseProblem(
        phases=[p1, p2], objective=lambda e, p: -e[1].xf[0],
        links=[Link(0, 1, states=(0,)), Link(0, 1, states=(1,), jump=0.5, time=False)],
    )


def test_link_with_jump_and_integral_constraint():
    # phase 1: from rest, 1 s with an energy budget ∫u² <= E = 3; phase 2: the velocity jumps
    # by +0.5 m/s (an impulse) and the body coasts 1 s. Maximise x(2) = x(1) + v(1) + 0.5
    # = ∫(2 - t) u dt + 0.5. Cauchy-Schwarz: u = c (2 - t) with c² ∫(2-t)² dt = c² 7/3 = E,
    # c = 3/sqrt(7); x(2) = sqrt(7 E / 3) + 0.5 = sqrt(7) + 0.5, x(1) = c ∫(1-t)(2-t) dt = 5/(2 sqrt 7).
    p1 = Phase(dynamics=_f, n_states=2, n_controls=1, initial_state=[0.0, 0.0], tf_bounds=(1.0, 1.0),
               integrand=lambda x, u, t, p: [u[0] * u[0]], integral_upper=[3.0], name="burn")
    p2 = Phase(dynamics=_f, n_states=2, n_controls=1, control_lower=[0.0], control_upper=[0.0],
               t0_bounds=(1.0, 1.0), tf_bounds=(2.0, 2.0), name="coast")
    prob = MultiPhaseProblem(
        phases=[p1, p2], objective=lambda e, p: -e[1].xf[0],
        links=[Link(0, 1, states=(0,)), Link(0, 1, states=(1,), jump=0.5, time=False)],
    )
    sol = solve_multiphase(prob, meshes=[(2, 4), (1, 3)])
    assert sol.success
    a, b = sol.phases
    assert abs(sol.integrals[0][0] - 3.0) < 1e-7  # the energy budget is active
    assert abs(a.x[-1, 0] - 5.0 / (2.0 * np.sqrt(7.0))) < 1e-7
    assert abs(b.x[0, 1] - (a.x[-1, 1] + 0.5)) < 1e-9  # the jump
    assert abs(sol.objective + np.sqrt(7.0) + 0.5) < 1e-7


def test_solve_adaptive_multiphase_refines_every_phase():
    sol = solve_adaptive(_two_phase(distance_free=True), tol=1e-8, mesh=[(1, 2), (1, 2)])
    assert isinstance(sol, MultiPhaseSolution) and sol.success and sol.certificate.satisfied
    assert len(sol.interval_errors) == 2 and all(np.all(e <= 1e-8) for e in sol.interval_errors)
    assert sol.mesh_history and sol.mesh_history[-1].n_collocation == sum(sum(m.nodes) for m in sol.meshes)
    d = sol.to_dict()
    assert d["certificate"]["satisfied"] and len(d["phases"]) == 2
    # warm start from a solution on other meshes
    again = solve_multiphase(sol.problem, meshes=[(3, 3), (3, 3)], guess=sol)
    assert again.success and again.nit <= sol.mesh_history[0].nit


def test_default_guess_chains_phases():
    g = default_multiphase_guess(_two_phase())
    assert isinstance(g, MultiPhaseGuess) and len(g.phases) == 2
    assert g.phases[1].t[0] == g.phases[0].t[-1]


def test_validation():
    ph = Phase(dynamics=_f, n_states=2, n_controls=1, tf_bounds=(1.0, 1.0), lagrange=lambda x, u, t, p: u[0] ** 2)
    with pytest.raises(InputTypeError):
        MultiPhaseProblem(phases=[])
    with pytest.raises(InputError):
        MultiPhaseProblem(phases=[ph, ph], links=[Link(0, 0)])
    with pytest.raises(InputError):
        MultiPhaseProblem(phases=[ph], events=lambda e, p: [e[0].xf[0]])
    with pytest.raises(InputError):
        Phase(dynamics=_f, n_states=2, n_controls=1, t0_bounds=(0.0, np.inf))
    with pytest.raises(InputTypeError):
        Phase(dynamics=None, n_states=2, n_controls=1)
    prob = MultiPhaseProblem(phases=[ph])
    with pytest.raises(InputError):
        solve_multiphase(prob, meshes=[(2, 3), (2, 3)])
    with pytest.raises(InputError):
        solve_multiphase(prob, method="euler")
    with pytest.raises(InputTypeError):
        solve_multiphase(prob, guess=3)


def test_nonfinite_dynamics_give_success_false_not_nan():
    import casadi as ca

    # sqrt of a negative number at the guess: IPOPT stops (invalid number); the result must
    # be a clean failure with finite arrays
    ph = Phase(dynamics=lambda x, u, t, p: [ca.sqrt(x[0] - 10.0) + u[0]], n_states=1, n_controls=1,
               initial_state=[0.0], final_state=[1.0], tf_bounds=(1.0, 1.0))
    sol = solve_multiphase(MultiPhaseProblem(phases=[ph], objective=lambda e, p: e[0].tf), meshes=[(2, 3)])
    assert not sol.success
    assert np.all(np.isfinite(sol.phases[0].x)) and np.isfinite(sol.max_violation)


def test_wrong_user_function_signature_is_an_input_error():
    ph = Phase(dynamics=lambda x, u, t: [x[1], u[0]], n_states=2, n_controls=1, tf_bounds=(1.0, 1.0),
               lagrange=lambda x, u, t, p: u[0] ** 2)
    with pytest.raises(InputTypeError, match="building the NLP failed"):
        solve_multiphase(MultiPhaseProblem(phases=[ph]), meshes=[(2, 3)])
    ph = Phase(dynamics=lambda x, u, t, p: [x[1]], n_states=2, n_controls=1, tf_bounds=(1.0, 1.0),
               lagrange=lambda x, u, t, p: u[0] ** 2)
    with pytest.raises(InputTypeError, match="2 values"):
        solve_multiphase(MultiPhaseProblem(phases=[ph]), meshes=[(2, 3)])


@pytest.mark.parametrize("method", ["radau", "gauss"])
@pytest.mark.parametrize("which", ["parameter-event", "jump-integral"])
def test_interpolated_duals_reproduce_the_multipliers_on_the_same_meshes(method, which):
    # every row type of the multi-phase NLP (defects, interval links, phase durations,
    # integral constraints, state/time linkages with a jump, events) carried onto the meshes
    # the solution came from returns IPOPT's multipliers up to round-off
    from adcskit.optimal_control.multiphase import _get, _multi_duals, _resolve_options

    prob, meshes = {
        "parameter-event": (_two_phase(distance_free=True), [(2, 3), (3, 3)]),
        "jump-integral": (_jump_integral_problem(), [(2, 4), (1, 3)]),
    }[which]
    opts = {"tol": 1e-12}
    a = solve_multiphase(prob, method=method, meshes=meshes, ipopt_options=opts)
    assert a.success
    old = a.nlp
    tr = _get(prob, method, a.meshes, _resolve_options(opts))
    scales = [(*ph.scales(), st) for ph, st in zip(prob.phases, old.st, strict=True)]
    lbz, ubz, _, _ = tr.bounds(prob, scales)
    t_guess = [(p.t0, p.tf) for p in a.phases]
    lam_x, lam_g = _multi_duals(prob, tr, a, old.z, old.par, scales, t_guess, lbz, ubz)
    np.testing.assert_allclose(lam_g, old.lam_g, rtol=0, atol=1e-9 * np.abs(old.lam_g).max())
    np.testing.assert_allclose(lam_x, old.lam_x, rtol=0, atol=1e-6 * max(np.abs(old.lam_x).max(), 1.0))


def test_primal_dual_warm_start_on_refined_meshes_reaches_the_same_optimum():
    prob = _jump_integral_problem()
    coarse = solve_multiphase(prob, meshes=[(1, 3), (1, 3)])
    warm = solve_multiphase(prob, meshes=[(3, 4), (2, 3)], guess=coarse, transfer_duals=True)
    cold = solve_multiphase(prob, meshes=[(3, 4), (2, 3)])
    assert coarse.warm_start == "cold" and warm.warm_start == "primal-dual-interpolated"
    assert warm.success and cold.success
    assert warm.objective == pytest.approx(-np.sqrt(7.0) - 0.5, abs=1e-7)  # closed form (above)
    assert warm.objective == pytest.approx(cold.objective, rel=1e-9)
    np.testing.assert_allclose(warm.phases[0].x, cold.phases[0].x, atol=1e-7)


def test_bad_ipopt_option_and_links_none_are_named():
    """Robustness findings of the slow sweep: the options are blamed, not the problem functions."""
    ph = Phase(dynamics=lambda x, u, t, p: [x[1], u[0]], n_states=2, n_controls=1, tf_bounds=(1.0, 1.0),
               lagrange=lambda x, u, t, p: u[0] ** 2)
    with pytest.raises(InputError, match="ipopt_options not accepted"):
        solve_multiphase(MultiPhaseProblem(phases=[ph]), meshes=[(2, 3)], ipopt_options={"no_such_option": 1})
    with pytest.raises(InputTypeError, match="links must be"):
        MultiPhaseProblem(phases=[ph], links=None)
