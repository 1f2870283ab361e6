"""Issue 43's problem classes: bang-singular-bang (short and long singular arcs), a mixed
state-control path constraint, the 4-switch oscillator. Each ends correct with success=True or
success=False with a message naming the cause -- never a false success."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from adcskit.errors import InputError
from adcskit.optimal_control import check_optimality, solve, solve_adaptive
from adcskit.optimal_control.problems import (
    bang_singular_bang,
    bang_singular_bang_objective,
    oscillator_min_time,
    rest_to_rest_mixed_path,
    rest_to_rest_mixed_path_time,
)

TOL = 1e-6
# minimum principle by shooting (Pontryagin et al. 1962 §I.5), 4 switches: issue 43's table
OSC_T = 10.10346299


def _no_false_success(sol, ref):
    """success=True only with the objective within tol (relative) of the known optimum."""
    if sol.success:
        assert abs(sol.objective - ref) <= TOL * abs(ref) * 2.0, (sol.objective, ref, sol.message)
    else:
        assert sol.message  # says what failed


def test_references():
    # J* = 2 ∫_0^1 (1 - t)^2 dt = 2/3 for every tf >= 2 (derivation: problems/singular.py)
    assert bang_singular_bang_objective(2.04) == pytest.approx(2.0 / 3.0, abs=0)
    # T*: ∫_0^T min(1 - e^-t, T - t) dt = 1 (comparison argument, problems/singular.py)
    T = rest_to_rest_mixed_path_time(1.0)
    t1 = brentq(lambda t: 1.0 - np.exp(-t) - (T - t), 0.0, T)  # the profile's corner
    d = quad(lambda t: 1.0 - np.exp(-t), 0.0, t1)[0] + quad(lambda t: T - t, t1, T)[0]
    assert d == pytest.approx(1.0, abs=1e-12)
    with pytest.raises(InputError, match="tf"):
        bang_singular_bang(1.5)


def test_ringing_singular_arc_fails_the_singular_check():
    # issue 43: Gauss 10x4 rings +-0.4 on the singular arc, H constant, error estimate 1e-9,
    # J 4.1e-5 high: the switching function's derivative (sigma' = -2x) does not vanish
    sol = solve(bang_singular_bang(3.0), method="gauss", mesh=(10, 4))
    assert sol.success and sol.objective - 2.0 / 3.0 > 1e-5
    chk = check_optimality(sol, threshold=0.02)
    assert "singular-arc" in chk.checks and "legendre-clebsch" in chk.checks
    assert chk.met is False and chk.singular_violation > 0.02
    assert chk.legendre_clebsch_violation == 0.0  # -d/du (sigma'') = 2 >= 0 (Kelley)


@pytest.mark.parametrize(("tf", "method"), [(3.0, "gauss"), (3.0, "radau"), (2.04, "gauss"), (2.06, "gauss")])
def test_bang_singular_bang_never_a_false_success(tf, method):
    sol = solve_adaptive(bang_singular_bang(tf), tol=TOL, method=method)
    _no_false_success(sol, 2.0 / 3.0)


@pytest.mark.parametrize("tf", [3.0, 2.06])
def test_singular_arc_success_only_with_the_state_held(tf):
    # on a singular arc J is flat in the state (J - J* = ∫ δx² dt), so J right to tol leaves
    # the state O(sqrt(tol)) free: success must also hold the state near the exact
    # x*(t) = max(1 - t, 0, t - (tf - 1)) (problems/singular.py), else name the singular arc
    sol = solve_adaptive(bang_singular_bang(tf), tol=TOL, method="gauss")
    assert abs(sol.objective - 2.0 / 3.0) <= 2.0 * TOL  # J right either way
    if sol.success:
        t = np.linspace(0.0, tf, 2001)
        x_star = np.maximum.reduce([1.0 - t, np.zeros_like(t), t - (tf - 1.0)])
        assert np.max(np.abs(sol.state_at(t)[:, 0] - x_star)) <= 1e-3
    else:
        assert "singular arc" in sol.message


def test_mixed_path_constraint_min_time():
    sol = solve_adaptive(rest_to_rest_mixed_path(), tol=TOL, method="radau")
    ref = rest_to_rest_mixed_path_time(1.0)
    assert sol.success and abs(sol.tf - ref) <= TOL * ref


@pytest.mark.parametrize("method", ["gauss", "radau"])
def test_oscillator_from_5_3_3_1(method):
    sol = solve_adaptive(oscillator_min_time(5.3, 3.1), tol=TOL, method=method)
    _no_false_success(sol, OSC_T)
    # an earlier mesh converged: never an infeasibility claim
    if any(h.success for h in sol.mesh_history):
        assert not sol.message.startswith("infeasible")
