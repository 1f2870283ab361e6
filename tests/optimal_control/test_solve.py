"""Transcription + IPOPT on problems with analytic solutions (closed-form oracles)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adcskit.errors import InputError, InputTypeError
from adcskit.optimal_control import (
    Mesh,
    OptimalControlProblem,
    bang_bang,
    multistart,
    resimulate,
    solve,
    solve_mesh_sequence,
)
from adcskit.optimal_control.problems import (
    double_integrator_min_energy,
    double_integrator_min_time,
)

D, A = 2.0, 0.5  # move 2 m with |u| <= 0.5 m/s^2: tf* = 2 sqrt(d/a) = 4 s (Bryson & Ho §7.3)
TF = 2 * math.sqrt(D / A)


@pytest.fixture(scope="module")
def min_time_gauss():
    # even number of equal intervals: the switch at tf/2 falls on a mesh point, so the
    # piecewise-quadratic state is represented exactly and tf is exact to IPOPT's tolerance
    return solve(double_integrator_min_time(D, A), method="gauss", mesh=(10, 4))


def test_min_time_tf_exact(min_time_gauss):
    s = min_time_gauss
    assert s.success and s.status == 0 and s.ipopt_status == "Solve_Succeeded"
    assert s.tf == pytest.approx(TF, abs=1e-6)  # issue 5: "solved to 1e-6"
    assert s.objective == pytest.approx(s.tf)
    np.testing.assert_allclose(s.x[-1], [D, 0.0], atol=1e-9)


def test_min_time_costates_match_analytic(min_time_gauss):
    # λ_x = -2/(a tf), λ_v(t) = -1/a + 2t/(a tf) (minimum principle, H = λᵀf, H(tf) = -1);
    # exact here because the LG nodes are symmetric about the switch at tf/2 (the multiplier
    # family of test_min_time_costate_offset_is_a_kkt_degeneracy... is then centred on c = 0)
    s = min_time_gauss
    exact = np.column_stack([np.full(s.t.size, -2 / (A * TF)), -1 / A + 2 * s.t / (A * TF)])
    np.testing.assert_allclose(s.costate, exact, atol=1e-6 / A)  # solver tol 1e-9, scale 1/a


def test_min_time_hamiltonian_is_minus_one(min_time_gauss):
    # S2 eq. 38-39: J = tf, boundary conditions independent of tf -> H ≡ -1
    np.testing.assert_allclose(min_time_gauss.hamiltonian, -1.0, atol=1e-6)


def test_min_time_bang_bang_and_switch(min_time_gauss):
    bb = bang_bang(min_time_gauss)
    assert bb.all_bang_bang
    assert bb.n_switches.tolist() == [1]
    # switching function λ_v is linear and crosses zero at tf/2
    assert bb.switch_times[0][0] == pytest.approx(TF / 2, abs=1e-6)


def test_odd_mesh_switch_time_from_switching_function():
    # 7 intervals: tf/2 lies inside an interval, found by the zero of ∂H/∂u
    s = solve(double_integrator_min_time(D, A), mesh=(7, 4))
    assert s.success
    assert s.tf == pytest.approx(TF, rel=1e-2)  # discontinuity inside an interval: O(h) error
    bb = bang_bang(s, min_fraction=0.8)
    assert bb.switch_times[0].size == 1
    assert bb.switch_times[0][0] == pytest.approx(TF / 2, rel=2e-2)


def test_radau_min_time():
    s = solve(double_integrator_min_time(D, A), method="radau", mesh=(10, 4))
    assert s.success
    assert s.tf == pytest.approx(TF, abs=1e-6)
    # H = -1 + c u at the nodes, with c the multiplier offset of the next test (~6e-3 here)
    np.testing.assert_allclose(s.hamiltonian, -1.0, atol=2e-2)


@pytest.mark.parametrize("method", ["gauss", "radau"])
@pytest.mark.parametrize("mesh", [(1, 3), (4, 3), (3, 5)])
def test_costates_exact_where_the_multipliers_are_unique(method, mesh):
    # issue 11: the costate mapping (Gauss: λ_k = Λ_k/w_k + Λ_f, λ_0, λ_f; Radau, Garg et al.
    # 2010: λ_k = Λ_k/w_k at the LGR points, λ(+1) = Σ_k D_k,N+1 Λ_k) is exact on the
    # minimum-energy double integrator: J = ∫u², u = 6d/T² − 12dt/T³, λ_v = −2u and
    # λ_x = −λ̇_v = −24d/T³ are polynomials the transcription represents exactly, and the KKT
    # multipliers are unique (no active bounds), so the estimate matches to solver tolerance
    # at every node, interval ends and the final point included.
    d, T = 1.5, 3.0
    s = solve(double_integrator_min_energy(d, T), method=method, mesh=mesh)
    exact = np.column_stack([np.full(s.t.size, -24 * d / T**3), -2 * (6 * d / T**2 - 12 * d * s.t / T**3)])
    np.testing.assert_allclose(s.costate, exact, atol=1e-8)


@pytest.mark.parametrize("method", ["gauss", "radau"])
@pytest.mark.parametrize("fractions", [(0.5, 0.5), (0.25, 0.25, 0.5)])
def test_min_time_costate_offset_is_a_kkt_degeneracy_not_a_mapping_error(method, fractions):
    # On the bang-bang minimum-time problem the NLP's multipliers are not unique: a constant
    # shift c of λ_v leaves every KKT equation satisfied (D of a constant is 0; the shift
    # enters the tf-stationarity row as c·Σ w_k u_k h/2 = c·(v(tf) − v(0)) = 0; the control
    # bound multipliers absorb it) as long as the sign condition u_k = −a·sign(λ_v,k) holds at
    # the nodes next to the switch. IPOPT returns an interior member of that family, so the
    # estimate is λ_v + c with c = O(h) — for Gauss too when the nodes are not symmetric
    # about the switch (measured c = -0.096 on (0.25, 0.25, 0.5)); for Radau even on a
    # symmetric mesh, whose LGR point τ = −1 sits at the switch (measured c = 0.042).
    mesh = Mesh(nodes=(4,) * len(fractions), fractions=fractions)
    s = solve(double_integrator_min_time(D, A), method=method, mesh=mesh)
    assert s.tf == pytest.approx(TF, abs=1e-6)
    lam_x = -2 / (A * TF)
    lam_v = -1 / A + 2 * s.t / (A * TF)
    np.testing.assert_allclose(s.costate[:, 0], lam_x, atol=1e-6)  # λ_x is unique and exact
    off = s.costate[:, 1] - lam_v
    assert np.ptp(off) < 1e-6  # the error is one constant, not a first-order mapping error
    c = float(off.mean())
    # admissible shifts: u = +a needs λ_v + c <= 0, u = -a needs λ_v + c >= 0 at the nodes
    lv_c = -1 / A + 2 * s.t_control / (A * TF)
    up = s.u[:, 0] > 0
    assert np.max(lv_c[up]) + c <= 1e-6 and np.min(lv_c[~up]) + c >= -1e-6
    # the Hamiltonian shows the same family: H_k = -1 + c u_k
    np.testing.assert_allclose(s.hamiltonian, -1.0 + c * s.u[:, 0], atol=1e-6)


@pytest.mark.parametrize("method", ["gauss", "radau"])
def test_min_energy_fixed_tf_lagrange_cost(method):
    # u = 6d/T² - 12 d t/T³, J = 12 d²/T³ (cubic state: exact for >= 3 nodes per interval)
    d, T = 1.5, 3.0
    s = solve(double_integrator_min_energy(d, T), method=method, mesh=(4, 3))
    assert s.success and s.tf == T
    assert s.objective == pytest.approx(12 * d**2 / T**3, rel=1e-9)
    np.testing.assert_allclose(s.u[:, 0], 6 * d / T**2 - 12 * d * s.t_control / T**3, atol=1e-7)
    r = resimulate(s)
    assert r.success and r.terminal_miss_scaled < 1e-8  # linear control reproduced exactly


def test_path_constraint_is_enforced():
    base = double_integrator_min_energy(1.0, 2.0)  # unconstrained peak speed 1.5 d/T = 0.75
    p = base.replace(path=lambda x, u, t: [x[1]], path_upper=[0.6])
    s = solve(p, mesh=(10, 4))
    assert s.success
    # enforced at the collocation points (S2 eq. 33), not between them
    assert s.state_at(s.t_control)[:, 1].max() <= 0.6 + 1e-7
    assert s.x[:, 1].max() > 0.59  # and active
    assert s.objective > 12 * 1.0 / 8  # constrained optimum costs more


def test_failure_is_a_result_not_an_exception():
    # tf capped below the minimum time: infeasible
    p = double_integrator_min_time(D, A).replace(tf_bounds=(0.1, 0.5 * TF), tf_guess=0.4 * TF)
    s = solve(p, mesh=(6, 3), ipopt_options={"max_iter": 200})
    assert not s.success
    assert s.status != 0 and s.ipopt_status != "Solve_Succeeded" and "IPOPT" in s.message


def test_mesh_sequence_converges_and_warm_starts():
    res = solve_mesh_sequence(double_integrator_min_time(D, A), [(4, 3), (8, 3), (16, 3)], rtol=1e-6)
    assert res.success and res.converged
    assert res.final.tf == pytest.approx(TF, abs=1e-6)


def test_multistart_reports_distinct_optima_seeded():
    p = double_integrator_min_time(D, A)
    a = multistart(p, 3, mesh=(6, 3), rng=5)
    b = multistart(p, 3, mesh=(6, 3), rng=5)
    np.testing.assert_array_equal(a.objectives, b.objectives)  # same seed, same starts
    assert a.n_success == 3
    assert a.distinct_objectives.size == 1  # the double integrator has one optimum
    assert a.distinct_objectives[0] == pytest.approx(TF, abs=1e-6)


def test_interpolation_reproduces_nodes(min_time_gauss):
    s = min_time_gauss
    np.testing.assert_allclose(s.state_at(s.t[:-1]), s.x[:-1], atol=1e-12)
    np.testing.assert_allclose(s.control_at(s.t_control), s.u, atol=1e-12)
    # exact trajectory: x(t) = a t²/2 before the switch
    t = np.linspace(0, TF / 2, 9)
    np.testing.assert_allclose(s.state_at(t)[:, 0], A * t**2 / 2, atol=1e-7)


@pytest.mark.parametrize("kind", ["lagrange", "nearest"])
def test_scalar_control_function_equals_control_at_bit_for_bit(min_time_gauss, kind):
    # resimulate's per-evaluation control (tables kept per interval, issue 24 item 1) must be
    # control_at itself: same bits at interior times, mesh points (the interval ending there),
    # t0, tf, times just outside within the rounding margin; arrays and errors as control_at
    s = min_time_gauss
    ends = [p.t_end for p in s.pieces]
    eps = 1e-10 * (s.tf - s.t0)  # inside control_at's clipping margin 1e-9 (tf - t0)
    times = [*np.linspace(s.t0, s.tf, 97), *ends, *s.t_control, s.t0 - eps, s.tf + eps, np.float64(1.3)]
    u = s._control_function(kind)
    for t in times:
        assert u(t).tobytes() == s.control_at(t, kind=kind).tobytes(), t
    for arr in (np.array([0.5, 1.5]), np.array([0.5]), [1.5]):
        assert u(arr).shape == s.control_at(arr, kind=kind).shape
        assert u(arr).tobytes() == s.control_at(arr, kind=kind).tobytes()
    with pytest.raises(InputError, match="horizon"):
        u(s.tf + 1.0)


def test_validation_messages():
    p = double_integrator_min_time()
    with pytest.raises(InputError, match="method must be one of 'gauss', 'radau'"):
        solve(p, method="trapezoid")
    with pytest.raises(InputError, match="needs a cost"):
        OptimalControlProblem(dynamics=lambda x, u, t: [x[0]], n_states=1, n_controls=0)
    with pytest.raises(InputError, match="fractions"):
        Mesh(nodes=(3, 3), fractions=(0.3, 0.3))
    with pytest.raises(InputError, match="tf_bounds"):
        p.replace(tf_bounds=(2.0, 1.0))


# ------------------------------------------------------------------ warm starts (issue 11)
@pytest.mark.parametrize("method", ["gauss", "radau"])
def test_warm_start_from_itself_returns_the_same_optimum(method):
    p = double_integrator_min_time(D, A)
    a = solve(p, method=method, mesh=(7, 4))  # switch inside an interval: not the exact tf
    b = solve(p, method=method, mesh=(7, 4), guess=a)
    assert b.success and b.warm_start == "primal-dual"
    # IPOPT tol 1e-9 on the scaled NLP: the cold optimum is accurate to ~1e-8 s here
    assert b.tf == pytest.approx(a.tf, rel=1e-7)
    assert b.nit <= 3  # measured 1
    c = solve(p, method=method, mesh=(7, 4), guess=b)
    assert c.tf == pytest.approx(b.tf, rel=1e-12) and c.nit <= 1  # a fixed point
    np.testing.assert_allclose(c.x, b.x, atol=1e-10)


def test_warm_start_on_another_mesh_is_primal_only():
    p = double_integrator_min_time(D, A)
    a = solve(p, mesh=(4, 3))
    b = solve(p, mesh=(8, 3), guess=a)
    assert b.success and b.warm_start == "primal"
    assert b.tf == pytest.approx(TF, abs=1e-6)
    cold = solve(p, mesh=(8, 3), guess=a, warm_start=False)
    assert cold.warm_start == "cold" and cold.tf == pytest.approx(TF, abs=1e-6)
    with pytest.raises(InputTypeError, match="warm_start"):
        solve(p, mesh=(8, 3), guess=a, warm_start="yes")


@pytest.fixture(scope="module")
def rendezvous_second_branch():
    # S2 Table 4 row 2, s0 = [20, 4, 0] m: on a 10x3 mesh, random guess 2 (seeded) converges
    # to a local optimum tf ≈ 26.0356 s; the best one there is 25.7922 s (measured).
    from adcskit.optimal_control import random_guess
    from adcskit.optimal_control.problems.rendezvous import rendezvous_problem

    p = rendezvous_problem((20.0, 4.0, 0.0))
    s = solve(p, mesh=(10, 3), guess=random_guess(p, 2))
    assert s.success and s.tf > 25.9
    return p, s


def test_warm_start_keeps_a_local_optimum_that_a_cold_restart_leaves(rendezvous_second_branch):
    p, s = rendezvous_second_branch
    same = solve(p, mesh=(10, 3), guess=s)
    assert same.success and same.warm_start == "primal-dual"
    assert same.tf == pytest.approx(s.tf, rel=1e-7) and same.nit <= 3  # measured 1
    # on the finer 20x3 mesh: warm (primal, small bound push and mu) stays on the branch
    # (measured 26.0365 s); IPOPT's cold defaults (bound push 1e-2, mu_init 0.1, adaptive mu)
    # from the same interpolated point leave it (measured: to the 25.7892 s optimum)
    warm = solve(p, mesh=(20, 3), guess=s)
    cold = solve(p, mesh=(20, 3), guess=s, warm_start=False)
    assert warm.success and warm.warm_start == "primal" and abs(warm.tf - s.tf) < 1e-3 * s.tf
    assert cold.success and cold.warm_start == "cold" and abs(cold.tf - s.tf) > 5e-3 * s.tf


def test_mesh_sequence_follows_the_branch_and_flags_jumps(rendezvous_second_branch):
    p, s = rendezvous_second_branch
    seq = solve_mesh_sequence(p, [(10, 3), (20, 3)], guess=s, rtol=1e-5)
    assert seq.success and seq.on_branch and seq.branch_jumps == ()
    assert [x.warm_start for x in seq.solutions] == ["primal-dual", "primal"]
    # with IPOPT's cold options the same sequence jumps at 20x3, and the jump is flagged
    cold = {"warm_start_init_point": "no", "mu_strategy": "adaptive", "mu_init": 0.1}
    bad = solve_mesh_sequence(p, [(10, 3), (20, 3)], guess=s, rtol=1e-5, ipopt_options=cold)
    assert bad.branch_jumps == (1,) and not bad.on_branch and "branch jump" in bad.message


def test_guess_from_a_solution_keeps_the_control_timing():
    # regression: Guess.t_u (collocation times) was stretched onto [t0, tf], shifting the
    # controls of as_guess() in time; zero IPOPT iterations must return the guess itself
    p = double_integrator_min_time(D, A)
    a = solve(p, mesh=(7, 4))
    z = solve(p, mesh=(7, 4), guess=a.as_guess(), warm_start=True, ipopt_options={"max_iter": 0})
    assert z.warm_start == "primal"
    np.testing.assert_allclose(z.u, a.u, atol=1e-6)
    np.testing.assert_allclose(z.x, a.x, atol=1e-6)
