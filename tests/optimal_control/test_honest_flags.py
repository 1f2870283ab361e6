"""Honest flags of solve_adaptive and check_optimality (issue 43, item 3): no optimality claim
without a check, the checks listed, "locally optimal" wording, causes named on blow-up."""

from __future__ import annotations

import numpy as np
import pytest

from adcskit.errors import InputError
from adcskit.optimal_control import Guess, check_optimality, solve, solve_adaptive
from adcskit.optimal_control.problems import bryson_denham, double_integrator_min_time


def test_guess_tf_must_match_its_last_sample():
    t = np.linspace(0.0, 1.0, 3)
    with pytest.raises(InputError, match=r"guess\.tf = 2\.0 s must equal guess\.t\[-1\] = 1\.0"):
        Guess(t=t, x=np.zeros((3, 2)), u=np.zeros((3, 1)), tf=2.0)
    assert Guess(t=t, x=np.zeros((3, 2)), u=np.zeros((3, 1)), tf=1.0 + 1e-12).tf == pytest.approx(1.0)


def test_no_applicable_check_is_not_checked_never_true():
    # Bryson-Denham (Bryson & Ho 1975 §3.11): the state bound x <= 1/9 is active, tf is fixed
    # and u unbounded, so no first-order check of check_optimality applies
    sol = solve(bryson_denham(), method="radau", mesh=(10, 4))
    chk = check_optimality(sol, threshold=0.02)
    assert chk.checks == () and chk.met is None and chk.detail.startswith("not checked")


def test_bryson_denham_certificate_says_not_checked():
    sol = solve_adaptive(bryson_denham(), tol=1e-5, method="radau")
    cert = sol.certificate
    assert cert.optimality_met is None and cert.optimality_checks == ()
    assert "not checked" in cert.optimality_detail
    if sol.success:  # J* = 4 / (9 l) = 4 (Bryson & Ho 1975 §3.11)
        assert abs(sol.objective - 4.0) <= 1e-3
        assert sol.message.startswith("locally optimal") and "multistart" in sol.message


def test_success_message_says_locally_optimal_and_lists_the_checks():
    sol = solve_adaptive(double_integrator_min_time(), tol=1e-6)  # tf* = 2 sqrt(d / a) = 2
    assert sol.success and abs(sol.tf - 2.0) < 1e-6
    assert sol.certificate.optimality_met is True and sol.certificate.optimality_checks
    assert sol.message.startswith("locally optimal") and "multistart" in sol.message
    for name in sol.certificate.optimality_checks:
        assert name in sol.message


def test_unbounded_min_time_control_blow_up_names_the_cause():
    # unbounded acceleration, minimum time: the optimum is an impulse, tf runs to its lower bound
    p = double_integrator_min_time().replace(control_lower=[-np.inf], control_upper=[np.inf],
                                            tf_bounds=(0.2, 10.0), tf_guess=2.0)
    sol = solve_adaptive(p, tol=1e-6, max_iterations=3)
    assert not sol.success
    assert "likely cause" in sol.message and "tf_bounds" in sol.message
    assert "unbounded in a free-final-time problem" in sol.message
