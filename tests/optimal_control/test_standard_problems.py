"""Standard test problems with published optima, solved by hp refinement from naive guesses
at quick settings (benchmarks/bench_optimal_control.py runs the full settings)."""

from __future__ import annotations

import numpy as np
import pytest

from adcskit.errors import InputError
from adcskit.optimal_control import MultiPhaseGuess, solve_adaptive
from adcskit.optimal_control.problem import Guess
from adcskit.optimal_control.problems import (
    brachistochrone,
    brachistochrone_time,
    bryson_denham,
    goddard_rocket,
    hypersensitive,
    orbit_raising,
    reference_objective,
    robot_arm,
)


def test_hypersensitive():
    # Rao & Mease 2000 problem with tf = 10: ½∫(x²+u²) = 6.723925391/2 (Tomlab PROPT ex. 51,
    # SNOPT, 50-point collocation; its own discretisation error is ~1e-8 relative)
    sol = solve_adaptive(hypersensitive(10.0), tol=1e-6)
    ref, _ = reference_objective("hypersensitive")
    assert sol.success and sol.max_error <= 1e-6
    assert abs(sol.objective - ref) / ref < 1e-6


def test_bryson_denham_state_constraint():
    # Bryson & Ho 1975 §3.11: J* = 4/(9 l) = 4 for l = 1/9; x <= l on the middle arc [3l, 1-3l]
    sol = solve_adaptive(bryson_denham(1.0 / 9.0), tol=1e-6)
    assert sol.success
    assert abs(sol.objective - 4.0) / 4.0 < 1e-5  # state bound enforced at nodes: J converges from below
    assert np.all(sol.x[:, 0] <= 1.0 / 9.0 * (1 + 1e-7))  # IPOPT relaxes bounds by ~1e-8
    # on the constrained arc x = l; junctions at 3l and 1 - 3l are located to the mesh's
    # accuracy, so the check keeps 0.02 s away from them and allows 1e-4 (~1e-3 l)
    on_arc = (sol.t > 3 / 9 + 0.02) & (sol.t < 1 - 3 / 9 - 0.02)
    assert on_arc.sum() >= 3 and np.allclose(sol.x[on_arc, 0], 1.0 / 9.0, atol=1e-4)


@pytest.mark.parametrize("method", ["radau", "gauss"])
def test_brachistochrone_closed_form(method):
    # cycloid through (10, 5) m below the start: T = φ_f sqrt(R/g) = 1.8016 s
    sol = solve_adaptive(brachistochrone(10.0, 5.0), tol=1e-7, method=method)
    assert sol.success
    assert abs(sol.tf - brachistochrone_time(10.0, 5.0)) < 1e-7
    # H ≡ -1 for a minimum-time problem with time-invariant dynamics (Gauss costates exact order)
    if method == "gauss":
        assert np.allclose(sol.hamiltonian, -1.0, atol=1e-5)


def _goddard_guess():
    # naive piecewise-linear guess: 10 s full thrust, 20 s singular arc, 15 s coast
    def g(t0, tf, x0, xf, u):
        return Guess(t=np.array([t0, tf]), x=np.array([x0, xf], float), u=np.array([[u], [u]], float), tf=tf)

    return MultiPhaseGuess(
        phases=(
            g(0, 10, [0, 0, 3], [3000, 600, 2.0], 193.044),
            g(10, 30, [3000, 600, 2.0], [12000, 500, 1.2], 100.0),
            g(30, 45, [12000, 500, 1.2], [18000, 0, 1.2], 0.0),
        ),
        parameters=np.zeros(0),
    )


def test_goddard_rocket_three_phases_singular_arc():
    # GPOPS-II example / Bryson 1999 §9.3: maximum altitude h(tf) = 18550.872 ft
    sol = solve_adaptive(goddard_rocket(), tol=1e-6, guess=_goddard_guess(), mesh=[(4, 4)] * 3)
    assert sol.success and sol.certificate.satisfied
    h_ref = -reference_objective("goddard-rocket")[0]
    assert abs(-sol.objective - h_ref) / h_ref < 1e-5
    full, sing, coast = sol.phases
    assert abs(full.u[:, 0] - 193.044).max() < 1e-9 and abs(coast.u).max() < 1e-12
    assert 0.0 < sing.u.min() and sing.u.max() < 193.044  # interior (singular) thrust
    assert abs(coast.x[-1, 1]) < 1e-9  # v(tf) = 0
    # costates / Hamiltonian for every phase on the refined meshes: time-invariant dynamics,
    # free phase times and a Mayer cost make H ≡ 0 in all phases. Compared with the size of
    # its leading term λ_h v (|λ_h| ~ 1); the Radau costate estimate is of limited order
    # (solve.py), hence 1e-3. Transversality: λ_h(tf) = ∂(-h)/∂h = -1.
    H = np.concatenate([p.hamiltonian for p in sol.phases])
    lam_h = np.concatenate([p.costate[:, 0] for p in sol.phases])
    v = np.concatenate([p.x[:, 1] for p in sol.phases])
    assert abs(coast.costate[-1, 0] + 1.0) < 1e-3
    assert np.abs(H).max() < 1e-3 * np.abs(lam_h).max() * np.abs(v).max()


def test_reference_objective_names():
    assert reference_objective("brachistochrone")[0] == pytest.approx(1.8016, abs=1e-4)
    with pytest.raises(InputError):
        reference_objective("nope")


def test_launch_ascent_events_vanish_on_the_target_orbit():
    # quick check of the four-phase launch problem's data and orbital-element events: the
    # guess ends on the target orbit's perigee (from an independent elements -> r, v
    # conversion), where all five event residuals must vanish
    import casadi as ca

    from adcskit.optimal_control import Endpoint
    from adcskit.optimal_control.problems import launch_ascent, launch_ascent_guess

    prob = launch_ascent()
    g = launch_ascent_guess(prob)
    assert len(prob.phases) == 4 and len(prob.links) == 6
    xf = ca.DM(g.phases[3].x[-1])
    ends = [Endpoint(x0=xf, t0=0.0, xf=xf, tf=0.0, q=ca.DM.zeros(0))] * 4
    assert np.allclose(np.array(prob.events(ends, ca.DM.zeros(0)), float).ravel(), 0.0, atol=1e-12)
    # mass bookkeeping: the guess drops 6 and 3 booster casings and the first stage's dry mass
    jumps = [lk.jump for lk in prob.links if lk.time is False]
    assert jumps == [-6 * 2280.0, -3 * 2280.0, -8830.0]


@pytest.mark.slow
def test_launch_ascent_final_mass():
    # Patterson & Rao 2014 (GPOPS-II) §7.5: maximum final mass 7529.712680 kg
    from adcskit.optimal_control import solve_multiphase
    from adcskit.optimal_control.problems import launch_ascent, launch_ascent_guess

    prob = launch_ascent()
    first = solve_multiphase(prob, meshes=[(8, 4)] * 4, guess=launch_ascent_guess(prob),
                             ipopt_options={"max_iter": 1500})
    assert first.success
    sol = solve_adaptive(prob, tol=1e-6, guess=first, mesh=[(4, 4)] * 4)
    assert sol.success
    ref = -reference_objective("launch-ascent")[0]
    assert abs(-sol.objective - ref) / ref < 1e-6


# ----------------------------------------------------------------- issue 22 suite, quick variants
# (benchmarks/bench_optimal_control.py --suite runs both methods at tol 1e-6; docs/benchmarks.md)


def test_orbit_raising_unit_thrust_direction():
    # Bryson & Ho 1975 §2.5, Fig. 2.5.1: r(tf) = 1.525 r0, printed to 4 digits (half a unit
    # of the last digit is 3.3e-4 relative, hence the 4e-4 tolerance); our Radau and Gauss
    # answers at tol 1e-6 agree to 1e-9 on 1.5252777 (docs/benchmarks.md)
    sol = solve_adaptive(orbit_raising(), tol=1e-3, method="radau")
    assert sol.success
    r_f = -sol.objective
    assert abs(r_f - 1.525) / 1.525 < 4e-4
    ph = sol.phases[0]
    # the thrust direction is a unit vector at every collocation point (path constraint,
    # IPOPT's constraint tolerance) and the final orbit is circular: v_r = 0, v_t² r = μ = 1
    assert np.allclose(np.hypot(ph.u[:, 0], ph.u[:, 1]), 1.0, atol=1e-7)
    xf = ph.x[-1]
    assert abs(xf[2]) < 1e-9 and abs(xf[3] ** 2 * xf[0] - 1.0) < 1e-8


def test_robot_arm_cops_optimum():
    # COPS 3.0 (Dolan, Moré & Munson 2004) §8: tf* = 9.1409118 (8 digits printed, so
    # 1e-7 relative is the published value's own precision); bang-bang in all three
    # channels, solved with the switch times as free phase boundaries
    sol = solve_adaptive(robot_arm(), tol=1e-4, method="gauss")
    ref, _ = reference_objective("robot-arm")
    assert sol.success and sol.certificate.optimality_met
    assert abs(sol.tf - ref) / ref < 1e-6
    assert np.all(np.abs(sol.u) <= 1.0 + 1e-8)
