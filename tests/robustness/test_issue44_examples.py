"""The silent and vague input cases of issue 44 (item 6), one test each.

Each case must raise an adcskit error whose message names the argument and the value (or what
is allowed), or return ``success=False``; the valid neighbours of each case still work and
give the numbers they gave before.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from adcskit import control, environment, estimation, sensors, thrusters, uncertainty
from adcskit.errors import AdcskitError, InputError, InputTypeError

# --- KalmanFilter.step -------------------------------------------------------------------------

A = np.array([[1.0, 0.1], [0.0, 1.0]])  # double integrator, dt = 0.1 s (the class docstring)
B = np.array([[0.005], [0.1]])
C = np.eye(2)
GOOD = dict(y=[0.5, 0.1], u=[0.0], A=A, B=B, C=C, Q=1e-6 * np.eye(2), R=0.01 * np.eye(2))


def _kf():
    return estimation.KalmanFilter(np.zeros(2), 1.0)


@pytest.mark.parametrize(
    ("arg", "value", "pattern"),
    [
        ("y", [np.nan, 0.1], r"y must be finite.*nan"),
        ("y", [np.inf, 0.1], r"y must be finite.*inf"),
        ("y", [0.5 + 1j, 0.1], r"y must be real"),
        ("u", [np.nan], r"u must be finite"),
        ("u", [1j], r"u must be real"),
        ("A", np.full((2, 2), np.nan), r"A must be finite"),
        ("A", A + 0j, r"A must be real"),
        ("B", np.full((2, 1), np.inf), r"B must be finite"),
        ("C", np.eye(2) * np.nan, r"C must be finite"),
        ("Q", np.nan, r"Q must be finite"),
        ("Q", -1.0, r"Q must be >= 0; got -1"),
        ("Q", -np.eye(2), r"Q must be positive semi-definite"),
        ("R", 0.0, r"R must be > 0; got 0"),
        ("R", -0.01, r"R must be > 0"),
        ("R", np.zeros((2, 2)), r"R must be positive definite"),
        ("R", np.inf, r"R must be finite"),
        # shape mismatches: adcskit errors naming the argument, not numpy broadcast errors
        ("y", [0.5, 0.1, 0.0], r"y must have shape \(2,\) to match C; got shape \(3,\)"),
        ("u", [0.0, 1.0], r"u must have shape \(1,\) to match B; got shape \(2,\)"),
        ("A", np.eye(3), r"A must have shape \(2, 2\) to match x0; got shape \(3, 3\)"),
        ("B", np.ones((3, 1)), r"B must have shape \(2, p\) to match A; got shape \(3, 1\)"),
        ("C", np.eye(3), r"C must have shape \(m, 2\) to match A; got shape \(3, 3\)"),
        ("Q", np.eye(3), r"Q must be a scalar or have shape \(2, 2\); got shape \(3, 3\)"),
        ("R", np.eye(3), r"R must be a scalar or have shape \(2, 2\); got shape \(3, 3\)"),
    ],
)
def test_kalman_step_rejects_bad_input(arg, value, pattern):
    kf = _kf()
    with pytest.raises(AdcskitError, match=pattern):
        kf.step(**{**GOOD, arg: value})
    # a rejected step leaves the filter's state untouched
    np.testing.assert_array_equal(kf.x_pred, np.zeros(2))


def test_kalman_step_validated_and_fast_paths_are_bit_identical():
    rng = np.random.default_rng(44)
    ys, us = rng.standard_normal((25, 2)), rng.standard_normal((25, 1))
    checked, fast = _kf(), _kf()
    for y, u in zip(ys, us):
        a = checked.step(list(y), list(u), A, B, C, 1e-6, 0.01)  # scalars -> Q I, R I
        b = fast.step(y, u, A, B, C, 1e-6 * np.eye(2), 0.01 * np.eye(2), validate=False)
        for x1, x2 in zip(a, b):
            np.testing.assert_array_equal(x1, x2)
    # and both equal the validated batch entry point kalman_filter (same recursion)
    res = estimation.kalman_filter(A, B, C, ys, us, Q=1e-6, R=0.01)
    np.testing.assert_array_equal(res.x_pred[-1], fast.x_pred)


# --- RecursiveLeastSquares.update --------------------------------------------------------------


@pytest.mark.parametrize(
    ("phi", "z", "pattern"),
    [
        ([np.nan, 1.0], [0.0, 0.0], r"phi must be finite"),
        ([1.0, 1.0], [np.inf, 0.0], r"z must be finite"),
        ([1j, 1.0], [0.0, 0.0], r"phi must be real"),
        ([1.0, 1.0, 1.0], [0.0, 0.0], r"phi must have shape \(2,\); got shape \(3,\)"),
        ([1.0, 1.0], [0.0], r"z must have shape \(2,\); got shape \(1,\)"),
        ("ab", [0.0, 0.0], r"phi must be an array of numbers"),
    ],
)
def test_rls_update_rejects_bad_input(phi, z, pattern):
    rls = estimation.RecursiveLeastSquares(np.zeros((2, 2)))
    with pytest.raises(AdcskitError, match=pattern):
        rls.update(phi, z)
    assert rls.nit == 0


def test_rls_validated_and_fast_paths_are_bit_identical():
    theta = np.array([[1.0, 0.1], [0.0, 0.9]])  # the class docstring's example
    phis = np.random.default_rng(0).standard_normal((20, 2))
    a = estimation.RecursiveLeastSquares(np.zeros((2, 2)), delta=1e4, forgetting=0.98)
    b = estimation.RecursiveLeastSquares(np.zeros((2, 2)), delta=1e4, forgetting=0.98)
    for phi in phis:
        a.update(list(phi), list(theta @ phi))
        b.update(phi, theta @ phi, validate=False)
    np.testing.assert_array_equal(a.Theta, b.Theta)
    np.testing.assert_array_equal(a.P, b.P)


# --- environment -------------------------------------------------------------------------------


@pytest.mark.parametrize("r", [[0.0, 0.0, 0.0], [1e3, 0.0, 0.0], [[7e6, 0, 0], [0.0, 0.0, 10e3]]])
def test_ecef_to_geodetic_rejects_the_earths_centre(r):
    # was: latitude 180 deg and h = -6378 km at the centre
    with pytest.raises(InputError, match=r"r_ecef must be at least 42.8 km from the Earth's centre"):
        environment.ecef_to_geodetic(r)


def test_ecef_to_geodetic_rejects_empty_input():
    with pytest.raises(InputError, match=r"r_ecef must hold at least one position"):
        environment.ecef_to_geodetic(np.zeros((0, 3)))


def test_ecef_to_geodetic_still_inverts_geodetic_to_ecef_deep_inside():
    r = environment.geodetic_to_ecef(np.radians(30.0), np.radians(5.0), -6.0e6)  # ~380 km from the centre
    lat, lon, h = environment.ecef_to_geodetic(r)
    assert abs(np.degrees(lat) - 30.0) < 1e-9 and abs(h + 6.0e6) < 1e-3


@pytest.mark.parametrize("radius", [0.0, [7e6, 0.0]])
def test_geocentric_to_ecef_rejects_zero_radius(radius):
    with pytest.raises(InputError, match=r"radius must be > 0 m.*got 0"):
        environment.geocentric_to_ecef(radius, 1.0, 0.5)


def test_elements_to_rv_rejects_a_2d_true_anomaly():
    with pytest.raises(InputError, match=r"true_anomaly must have 0 or 1 dimension"):
        environment.elements_to_rv(7e6, 0.01, 0.9, 0.1, 0.2, np.zeros((2, 3)))
    r, _v = environment.elements_to_rv(7e6, 0.01, 0.9, 0.1, 0.2, np.zeros(4))
    assert r.shape == (4, 3)


# --- control, uncertainty ---------------------------------------------------------------------


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_robust_objective_rejects_nonfinite_errors_by_default(bad):
    with pytest.raises(InputError, match=r"errors must be finite"):
        control.robust_objective([[0.1, bad]])
    with pytest.raises(InputError, match=r"overshoot_pct must be finite"):
        control.robust_objective([[0.1, 0.2]], [[1.0, bad]])


def test_robust_objective_infeasible_mode_keeps_the_ga_behaviour():
    f = control.robust_objective([[0.1, np.nan], [1.0, 2.0]], nonfinite="infeasible")
    assert f[0] == np.inf and f[1] == pytest.approx(1.5 + 0.5)  # mean + std (ddof=0), S4 eq. 10
    with pytest.raises(InputError, match=r"nonfinite must be one of"):
        control.robust_objective([[0.1]], nonfinite="ignore")


def test_truncated_gaussian_nonfinite_quantiles_are_an_error():
    d = uncertainty.TruncatedGaussian(mean=1.0, std=0.1, low=0.0, high=1e-300)
    with pytest.raises(InputError, match=r"low and high must span .*high=1e-300"):
        d.ppf(np.array([0.1, 0.5, 0.9]))
    x = uncertainty.TruncatedGaussian(mean=1.0, std=0.1, high=1e-300).ppf(np.array([0.5]))
    assert np.all(np.isfinite(x)) and np.all(x <= 1e-300)


def test_simulate_batch_rejects_zero_torque():
    with pytest.raises(InputError, match=r"torque must be > 0 N m.*got 0"):
        control.LoopParams(torque=0.0)
    with pytest.raises(InputError, match=r"torque must be > 0 N m.*at sample 1"):
        control.simulate_batch(control.LoopParams(torque=np.array([1.0, 0.0])), backend="python")


# --- thrusters ---------------------------------------------------------------------------------


def test_torque_matrix_rejects_zero_directions():
    with pytest.raises(InputError, match=r"directions must be non-zero.*index \(1,\)"):
        thrusters.torque_matrix([[1.0, 0, 0], [0, 1.0, 0]], [[0, 1.0, 0], [0.0, 0.0, 0.0]])
    with pytest.raises(InputError, match=r"directions must be non-zero.*index \(0, 0\)"):
        thrusters.torque_matrix(np.ones((2, 1, 3)), np.zeros((2, 1, 3)))


@pytest.mark.parametrize(
    ("gene", "value", "pattern"),
    [
        (0, 6.0, r"genes\[0\] \(face gene s of thruster 0\) must be in \[0, 6\) for 6 faces; got 6.0"),
        (0, -1.0, r"genes\[0\] .* must be in \[0, 6\)"),
        (1, 1.5, r"genes\[1\] \(u of thruster 0\) must be in \[-1, 1\]; got 1.5"),
        (3, -0.2, r"genes\[3\] \(cant gene c of thruster 0\) must be in \[0, 1\]"),
    ],
)
def test_decode_layout_rejects_genes_outside_their_box(gene, value, pattern):
    genes = [0.5, 0.0, 0.0, 0.0, 0.0]
    genes[gene] = value
    with pytest.raises(InputError, match=pattern):
        thrusters.decode_layout(genes, thrusters.box_faces())
    assert thrusters.decode_layout([5.999, 1.0, -1.0, 1.0, 0.0], thrusters.box_faces()).names == ("-Z",)


@pytest.mark.parametrize("mounting", [3, "+X", 2.5])
def test_design_layout_mounting_must_be_a_sequence_of_faces(mounting):
    # was: "'int' object is not iterable"
    with pytest.raises(InputTypeError, match=r"mounting must be a non-empty sequence of MountingFace; got"):
        thrusters.design_layout(4, [[1.0, 0.0, 0.0]], mounting=mounting)


# --- estimation --------------------------------------------------------------------------------


def _gain_model(p):
    return np.array([[1.0, 0.1], [0.0, 1.0]]), (1.0 / p[0]) * np.array([[0.005], [0.1]])


@pytest.mark.parametrize("p0", [[0.0], [-1.0], [0.01]])
def test_augmented_ekf_rejects_p0_below_p_min(p0):
    # was: p0 = [0] silently floored at p_min and reported success
    u = np.sin(0.3 * np.arange(20))[:, None]
    with pytest.raises(InputError, match=r"p0 must be >= p_min = 0.05.*got p0\[0\]"):
        estimation.augmented_ekf(np.zeros((20, 2)), u, _gain_model, p0, P_p0=1.0, p_min=0.05)


def _xu():
    rng = np.random.default_rng(1)
    return rng.standard_normal((30, 2)), rng.standard_normal((30, 1))


def test_regression_data_names_the_arguments():
    x, u = _xu()
    with pytest.raises(InputError, match=r"(?s)B is only used with inputs.*inputs=None"):
        estimation.regression_data(x, x, None, B=np.ones((2, 1)))
    with pytest.raises(InputError, match=r"B must be None with estimate_B=True"):
        estimation.regression_data(x, x, u, B=np.ones((2, 1)), estimate_B=True)
    with pytest.raises(InputError, match=r"inputs must be given with estimate_B=True .*; got None"):
        estimation.regression_data(x, x, estimate_B=True)


def test_identify_model_names_the_arguments():
    x, u = _xu()
    with pytest.raises(InputError, match=r"B_init needs A_init"):
        estimation.identify_model(x, x, u, estimate_B=True, B_init=np.ones((2, 1)))
    with pytest.raises(InputError, match=r"B_init must have shape \(2, 1\)"):
        estimation.identify_model(x, x, u, estimate_B=True, A_init=np.eye(2), B_init=np.ones((3, 1)))
    with pytest.raises(InputError, match=r"B_prior is only used with inputs and estimate_B=True"):
        estimation.identify_model(x, x, A_prior=np.eye(2), B_prior=np.ones((2, 1)), method="ridge-prior")
    with pytest.raises(InputTypeError, match=r"options\['atol'\] must be"):
        estimation.identify_model(x, x, method="lsqr", options={"atol": "a"})


def test_joint_estimate_names_a_prior_not_an_internal_a():
    x, u = _xu()
    with pytest.raises(InputError, match=r"B must have shape \(2, p\) to match A_prior; got shape \(3, 1\)"):
        estimation.joint_estimate(x, u, A_prior=np.eye(2), B=np.ones((3, 1)))


# --- sensors -----------------------------------------------------------------------------------


def test_sun_sensor_interval_rejects_a_zero_vector():
    ss = sensors.SunSensor(angle_bound=1e-4)
    with pytest.raises(InputError, match=r"measured must be non-zero direction vectors.*index 1"):
        ss.interval([[1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    mid, rad = ss.interval([1.0, 0.0, 0.0])
    assert mid.shape == rad.shape == (3,) and np.all(rad > 0)


def test_validate_flag_is_strict():
    with pytest.raises(InputTypeError, match=r"validate must be True or False"):
        _kf().step(**GOOD, validate="no")
    with pytest.raises(InputTypeError, match=r"validate must be True or False"):
        estimation.RecursiveLeastSquares(np.zeros((2, 2))).update([1.0, 1.0], [0.0, 0.0], validate=1)


# --- executor and CLI --------------------------------------------------------------------------


def test_unreachable_dask_address_is_an_error_naming_it():
    # was: a 32 s hang, then a raw traceback; the connect wait is CONNECT_TIMEOUT_S (5 s)
    pytest.importorskip("dask.distributed")
    with pytest.raises(InputError, match=r"executor address 'tcp://127.0.0.1:1' is not reachable"):
        uncertainty.make_executor("dask://127.0.0.1:1")


def test_cli_unreachable_dask_address_exits_2_with_one_line(tmp_path: Path, capsys):
    pytest.importorskip("dask.distributed")
    from adcskit.cli import main

    out = tmp_path / "out"
    rc = main(["run", "wahba-table1", "--quick", "--out", str(out), "--executor", "dask://127.0.0.1:1"])
    err = capsys.readouterr().err
    assert rc == 2
    assert "127.0.0.1:1" in err and "not reachable" in err and "Traceback" not in err
    assert not out.exists()


def test_cli_config_range_error_names_key_and_value(tmp_path: Path, capsys):
    from adcskit.cli import main

    cfg = tmp_path / "c.toml"
    cfg.write_text("n_samples = -10\n")
    rc = main(["run", "closed-loop", "--config", str(cfg), "--out", str(tmp_path / "o")])
    assert rc == 2
    assert "n_samples must be >= 2; got -10" in capsys.readouterr().err


def test_cli_console_run_time_is_the_reports(monkeypatch, tmp_path: Path, capsys):
    # issue 44: the console said 3.3 s, the report 2.0 s for the same custom-config run (two
    # clocks: one around run_study, config and figure writing included, one around the study)
    import json
    import re

    import adcskit.studies
    import adcskit.studies._registry as registry
    from adcskit.cli import main

    monkeypatch.syspath_prepend(str(Path(__file__).parents[1]))  # tests/fake_study.py
    studies = dict(registry.STUDIES)
    studies["fake"] = registry.StudyInfo("fake", "fake_study", "none", "A fake study")
    monkeypatch.setattr(registry, "STUDIES", studies)
    monkeypatch.setattr(adcskit.studies, "STUDIES", studies)
    out = tmp_path / "out"
    assert main(["run", "fake", "--quick", "--out", str(out)]) == 0
    console = re.search(r"fake: done in (\d+\.\d) s", capsys.readouterr().out)
    report = json.loads((out / "fake" / "result.json").read_text())["runtime_s"]
    assert console is not None and console.group(1) == f"{report:.1f}"


@pytest.mark.parametrize(
    ("study", "changes", "message"),
    [
        ("closed-loop", {"n_samples": -10}, "n_samples must be >= 2; got -10"),
        ("closed-loop", {"record_samples": 0}, "record_samples must be >= 1; got 0"),
        ("closed-loop", {"q6_record_every": 0}, "q6_record_every must be >= 1; got 0"),
        ("closed-loop", {"leo_window_s": 100.0}, "leo_window_s must be < leo_t_final_s = 60.0 s; got 100.0"),
        ("thruster-layout", {"box_half_size_m": [1.0, -1.0, 1.0]}, "box_half_size_m must be > 0 per axis; got"),
        ("model-estimation", {"rls_delta": 0.0}, "rls_delta must be > 0; got 0.0"),
        ("model-estimation", {"noise_std_low": -1.0}, "noise_std_low must be >= 0; got -1.0"),
        ("onoff-schmitt", {"n_ratio": 1}, "n_ratio must be >= 2; got 1"),
        ("onoff-tuning", {"sweep_ratios": [1.0, -2.0]}, "sweep_ratios must be > 0 each; got"),
        ("rendezvous", {"rows_m": []}, "rows_m must list at least one initial position (m); got"),
        ("wahba-orbit", {"pop_size": 2}, "pop_size must be an integer >= 4; got 2"),
    ],
)
def test_config_range_errors_name_the_key_and_the_value(study, changes, message):
    from adcskit.errors import ConfigError
    from adcskit.studies import resolve_config

    with pytest.raises(ConfigError) as err:
        resolve_config(study, changes)
    assert message in str(err.value)
