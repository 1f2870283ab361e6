"""The concrete failures listed in issue 12, one test each.

The generic suite (``test_robustness.py``) cannot know that a finite answer is *wrong*; these
tests pin the silent-wrong-answer cases, the foreign exceptions, the hangs and the CLI
behaviour the issue reports, with the expected outcome.
"""

from __future__ import annotations

import inspect
import time

import numpy as np
import pytest

from adcskit import (
    attitude,
    control,
    determination,
    dynamics,
    environment,
    estimation,
    thrusters,
    uncertainty,
)
from adcskit.errors import AdcskitError, InputError, InputTypeError

# --- silent wrong answers ---------------------------------------------------------------------


def test_complex_input_is_rejected_not_truncated():
    with pytest.raises(InputTypeError, match="q must be real"):
        attitude.quat_to_dcm([0, 0, 1j, 1])


def test_complex_with_zero_imaginary_part_is_rejected_too():
    with pytest.raises(InputTypeError, match="r_ecef must be real"):
        environment.ecef_to_geodetic(np.array([7e6, 0, 0], dtype=complex))


@pytest.mark.parametrize("when", ["9999-12-31", "1000-01-01", np.datetime64("2300-01-01", "D")])
def test_dates_outside_datetime64_ns_are_rejected(when):
    with pytest.raises(InputError, match="between 1678-01-01 and 2262-04-11"):
        environment.as_utc(when)
    with pytest.raises(InputError, match="times must be between"):
        environment.gmst(when)


@pytest.mark.parametrize("t", [8e9, -1.2e10, 1e10, [0.0, 1e12]])
def test_huge_time_offsets_are_rejected_not_nat(t):
    with pytest.raises(InputError, match=r"\bt must"):
        environment.utc_times("2024-01-01", t)


def test_utc_times_near_the_range_end_still_works():
    assert environment.utc_times("2024-01-01", 7e9).dtype == np.dtype("datetime64[ns]")


@pytest.mark.parametrize("method", ["gmres", "bicgstab", "lsqr", "qr"])
def test_identify_model_zero_data_is_rank_deficient_for_every_unregularised_method(method):
    zeros = np.zeros((30, 2))
    res = estimation.identify_model(zeros, zeros, method=method)
    assert not res.success and res.status == 2 and "rank-deficient" in res.message


COLLINEAR = [[1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]


@pytest.mark.parametrize("q0", [None, [0.0, 0.0, 0.0, 1.0]])
def test_robust_wahba_collinear_is_rejected_with_or_without_q0(q0):
    with pytest.raises(InputError, match="must not all be parallel"):
        determination.robust_wahba(COLLINEAR, 0.01, [[0, 1.0, 0], [0, 2.0, 0], [0, -1.0, 0]], 0.01, q0=q0)


def _cube_tm():
    pos, dirs = [], []
    for sx in (1.0, -1.0):
        for sy in (1.0, -1.0):
            pos += [[sx, sy, 1.0], [sx, sy, -1.0]]
            dirs += [[-sy, sx, 0.3], [sy, -sx, -0.3]]
    d = np.array(dirs)
    return thrusters.torque_matrix(np.array(pos), d / np.linalg.norm(d, axis=1, keepdims=True))


def test_allocate_huge_demand_is_rejected_and_never_feasible_with_infinite_error():
    with pytest.raises(InputError, match="demand must have entries of magnitude"):
        thrusters.allocate(_cube_tm(), [1e299, 0.0, 0.0])
    res = thrusters.allocate(_cube_tm(), [1e140, 0.0, 0.0], method="pinv-redistribute")
    assert np.all(np.isfinite(res.error)) or not res.success
    assert not (res.success and res.feasible and not np.isfinite(res.error))


@pytest.mark.parametrize("f_max", [-1.0, 0.0, [10.0] * 7 + [-1.0]])
def test_allocate_rejects_non_positive_f_max(f_max):
    with pytest.raises(InputError, match="f_max must be > 0 N"):
        thrusters.allocate(_cube_tm(), [0.1, 0.0, 0.0], f_max=f_max)


@pytest.mark.parametrize("flag", ["no", 1, 0, None, "False"])
def test_flags_accept_only_booleans(flag):
    with pytest.raises(InputTypeError, match="printed must be True or False"):
        dynamics.lvlh_attitude_model(np.diag([10.0, 8.0, 6.0]), 1e-3, printed=flag)


def test_numpy_bool_is_a_flag():
    a = dynamics.lvlh_attitude_model(np.diag([10.0, 8.0, 6.0]), 1e-3, printed=np.True_)
    b = dynamics.lvlh_attitude_model(np.diag([10.0, 8.0, 6.0]), 1e-3, printed=True)
    np.testing.assert_array_equal(a[0], b[0])


BODY = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
REF = [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]


@pytest.mark.parametrize(
    ("fn", "kw", "fragment"),
    [
        (determination.davenport_k, dict(body=[[np.nan, 0, 0], [0, 1.0, 0]], ref=REF), "body must be finite"),
        (determination.davenport_k, dict(body=BODY, ref=[[0.0, 0, 0], [1.0, 0, 0]]), "ref must contain non-zero"),
        (determination.davenport_k, dict(body=BODY, ref=REF, weights=[1.0, np.inf]), "weights must be finite"),
        (determination.wahba_loss, dict(q=[0, 0, 0, 1.0], body=[[0.0, 0, 0], [0, 1.0, 0]], ref=REF),
         "body must contain non-zero"),
    ],
)
def test_davenport_k_and_wahba_loss_reject_what_solve_wahba_rejects(fn, kw, fragment):
    with pytest.raises(InputError, match=fragment):
        fn(**kw)
    with pytest.raises(InputError):
        determination.solve_wahba(kw["body"], kw["ref"], kw.get("weights"))


def test_wahba_extreme_but_valid_vectors_are_normalised_exactly():
    k1 = determination.davenport_k(np.array(BODY) * 1e-300, REF)
    k2 = determination.davenport_k(BODY, REF)
    np.testing.assert_allclose(k1, k2, atol=1e-15)


@pytest.mark.parametrize(
    ("A", "r", "fragment"),
    [
        (np.zeros((3, 3)), [1.0, 0, 0], "A must be a rotation matrix"),
        (np.diag([1.0, 2.0, 1.0]), [1.0, 0, 0], "A must be a rotation matrix"),
        (np.eye(3), [0.0, 0.0, 0.0], "r must contain non-zero"),
    ],
)
def test_sensor_measure_rejects_degenerate_attitude_and_reference(A, r, fragment):
    with pytest.raises(InputError, match=fragment):
        from adcskit.sensors import SunSensor

        SunSensor(noise_std=0.01).measure(A, r, rng=1)


@pytest.mark.parametrize(
    ("fn", "kw", "fragment"),
    [
        (lambda **k: control.LoopParams(**k), dict(torque=-1.0), "torque must be > 0"),
        (thrusters.fuel_mass, dict(t_p=[0.01], mdot=-1e-3), "mdot must be >= 0 kg/s"),
        (thrusters.min_impulse_bit, dict(lever_arm=[1.0], f_max=-10.0), "f_max must be > 0 N"),
        (thrusters.score_layout, dict(torque_matrix=_cube_tm(), demands=np.eye(3), f_max=0.0), "f_max must be > 0 N"),
        (thrusters.manoeuvre_fuel, dict(forces=[[1.0, 2.0]], mdot=-1.0), "mdot must be >= 0"),
    ],
)
def test_negative_or_zero_physical_quantities_are_rejected(fn, kw, fragment):
    with pytest.raises(InputError, match=fragment):
        fn(**kw)


@pytest.mark.parametrize("x", [[], [np.nan, np.nan], np.array([])])
def test_statistics_of_nothing_is_an_error(x):
    with pytest.raises(InputError, match="x must contain at least one finite value"):
        uncertainty.sample_stats(x)


# --- foreign exceptions --------------------------------------------------------------------


def _di():
    from adcskit.optimal_control.problems import double_integrator_min_energy

    return double_integrator_min_energy(1.0, 1.0)


@pytest.mark.parametrize(
    "options", [{"no_such_ipopt_option": 1}, {"max_iter": "many"}, {"tol": None}, {1: 2}, {"tol": float("nan")}]
)
def test_ill_typed_or_unknown_ipopt_options_are_input_errors(options):
    from adcskit.optimal_control import solve

    with pytest.raises((InputError, InputTypeError), match="ipopt_options"):
        solve(_di(), mesh=(3, 3), ipopt_options=options)


@pytest.mark.parametrize(
    ("call", "fragment"),
    [
        (lambda: __import__("adcskit.optimal_control", fromlist=["x"]).default_guess(None), "problem must be"),
        (lambda: __import__("adcskit.optimal_control", fromlist=["x"]).random_guess(_di(), 1, knots=0), "knots must"),
        (lambda: __import__("adcskit.config", fromlist=["x"]).merge_mappings(None, {}), "base must be a mapping"),
        (lambda: __import__("adcskit.config", fromlist=["x"]).dump_toml(3), "data must be a mapping"),
        (lambda: dynamics.orbit_rate(1e300), "altitude must have magnitude"),
        (lambda: environment.kepler_orbit(1e-300, 0.0, 0.0, 0.0, 0.0, 0.0, [0.0]), "a must be >= 1 m"),
        (lambda: control.LoopParams(delay=1e300), "delay must have"),
    ],
)
def test_former_foreign_exceptions_are_clean(call, fragment):
    with pytest.raises(AdcskitError, match=fragment):
        call()


def test_resimulate_points_per_interval_zero():
    from adcskit.optimal_control import resimulate, solve

    sol = solve(_di(), mesh=(3, 3))
    with pytest.raises(InputError, match="points_per_interval must be an integer in"):
        resimulate(sol, points_per_interval=0)


def test_huge_altitude_gives_a_finite_rate():
    assert 0.0 <= dynamics.orbit_rate(1e149) < 1e-200


def test_long_delay_is_rejected_before_allocating_the_delay_line():
    params = control.LoopParams(delay=1e100)
    with pytest.raises(InputError, match="delay must be <="):
        control.simulate_batch(params, control.LoopSettings(t_final=0.1, t_window=0.05), backend="numpy")


@pytest.mark.parametrize("bad", ["/dev/null/sub", "/proc/adcskit-no-such-dir/x"])
def test_campaign_directory_that_cannot_be_created_is_an_input_error(bad):
    calls = []

    def fn(x):
        calls.append(x)
        return x

    with pytest.raises(InputError, match="directory"):
        uncertainty.run_campaign(fn, [1, 2], directory=bad)
    assert calls == []  # nothing computed before the error


def test_augmented_ekf_never_evaluates_the_model_below_its_floor():
    seen = []

    def model(p):
        seen.append(float(p[0]))
        if p[0] <= 0:
            raise ZeroDivisionError("model undefined at p <= 0")
        return np.array([[0.9, 0.1 / p[0]], [0.0, 0.8]]), np.array([[0.0], [1.0]])

    y = np.zeros((5, 2))
    u = np.zeros((5, 1))
    estimation.augmented_ekf(y, u, model, [0.06], P_p0=1.0, p_min=0.05)
    assert min(seen) >= 0.05
    with pytest.raises(InputError, match="p_min must be > 0"):
        estimation.augmented_ekf(y, u, model, [0.06], P_p0=1.0, p_min=0.0)


# --- hangs ------------------------------------------------------------------------------------


Q = [0.0, 0.0, 0.0, 1.0]
J = [10.0, 8.0, 6.0]


def test_propagate_with_nan_torque_fails_fast():
    t0 = time.perf_counter()
    res = dynamics.propagate_attitude(Q, [0.01, 0, 0], J, [0.0, 10.0], torque=lambda t, q, w: np.full(3, np.nan))
    assert not res.success and "torque" in res.message
    assert time.perf_counter() - t0 < 30  # generous: a hang is minutes


def test_propagate_with_huge_quaternion_or_rate_does_not_hang():
    with pytest.raises(InputError, match="q0 must have entries of magnitude"):
        dynamics.propagate_attitude([0, 0, 1e299, 1e299], [0.0, 0, 0], J, [0.0, 1.0])
    res = dynamics.propagate_attitude(Q, [1e12, 0, 0], J, [0.0, 1.0])
    assert not res.success and "max_nfev" in res.message
    res = dynamics.propagate_attitude(Q, [0.1, 0, 0], J, [0.0, 1.0], max_nfev=5)
    assert not res.success and "max_nfev" in res.message


def test_propagate_bad_torque_callable_and_shape():
    with pytest.raises(InputTypeError, match="torque must be a callable"):
        dynamics.propagate_attitude(Q, [0.0, 0, 0], J, [0.0, 1.0], torque=3)
    res = dynamics.propagate_attitude(Q, [0.0, 0, 0], J, [0.0, 1.0], torque=lambda t, q, w: [0.0, 0.0])
    assert not res.success and "3 finite numbers" in res.message


# --- vague errors and valid input ---------------------------------------------------------------


def test_error_blames_the_right_argument():
    with pytest.raises(InputTypeError, match="r_ecef must be an array of numbers; got None"):
        environment.ecef_to_eci_state(None, [0.0, 7.5e3, 0.0], "2024-01-01")


@pytest.mark.parametrize("fn, arg", [(dynamics.orbit_rate, np.array(5e5)), (attitude.random_quat, np.array(3))])
def test_zero_d_arrays_are_accepted_where_scalars_are(fn, arg):
    plain = fn(arg[()]) if fn is dynamics.orbit_rate else fn(int(arg), rng=1)
    zero_d = fn(arg) if fn is dynamics.orbit_rate else fn(arg, rng=1)
    np.testing.assert_array_equal(plain, zero_d)


# --- inner loops: validated by default, a documented validate=False fast path (issue 44) ---------


@pytest.mark.parametrize(
    ("method", "entry"),
    [(estimation.KalmanFilter.step, "kalman_filter"), (estimation.RecursiveLeastSquares.update, "update_batch")],
)
def test_inner_loops_document_their_fast_path_and_its_callers(method, entry):
    doc = inspect.getdoc(method)
    assert "validate" in doc and "fast path" in doc and entry in doc
    assert inspect.signature(method).parameters["validate"].default is True


def test_rls_update_batch_is_validated():
    rls = estimation.RecursiveLeastSquares(np.zeros((3, 2)))
    with pytest.raises(InputError, match="Phi must have shape"):
        rls.update_batch(np.zeros((4, 3)), np.zeros((4, 3)))
    with pytest.raises(InputError, match="Z must be finite"):
        rls.update_batch(np.zeros((4, 2)), np.full((4, 3), np.nan))
