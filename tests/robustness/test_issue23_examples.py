"""The concrete unclear failures of issue 23 (item 5), one test each.

Each was found by a held-out fuzz of the public API: a foreign exception, a silently accepted
ill-typed or unknown value, invalid output, or an error that blames the wrong argument. The
optimal-control examples of the same list are tested in ``tests/optimal_control``.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from adcskit import determination, environment, estimation, thrusters
from adcskit.config import dump_toml
from adcskit.errors import InputError, InputTypeError


def _gain_model(p):
    """A model with a pole at p = 0 (1/p scales the input gain), as an inertia ratio would have."""
    return np.array([[1.0, 0.1], [0.0, 1.0]]), (1.0 / p[0]) * np.array([[0.005], [0.1]])


def test_augmented_ekf_evaluates_the_model_only_above_the_p_min_floor():
    # issue 23: model(p0) was called on the raw p0 = 0 (ZeroDivisionError) before the floor;
    # since issue 44 a p0 below p_min is an input error (tests/robustness/test_issue44_examples.py)
    calls = []

    def model(p):
        calls.append(np.array(p, copy=True))
        return _gain_model(p)

    u = np.sin(0.3 * np.arange(20))[:, None]
    res = estimation.augmented_ekf(np.zeros((20, 2)), u, model, [0.05], P_p0=1.0, C=np.eye(2), R=1e-4,
                                   p_min=0.05)
    assert res.success
    assert min(float(c.min()) for c in calls) >= 0.05  # the documented floor, first call included


@pytest.mark.parametrize("flag", ["no", 1, 0, None, "False"])
def test_non_bool_flags_are_rejected(flag):
    # issue 23: solve_wahba(covariance='no') was accepted (a single problem skipped the check)
    body = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    with pytest.raises(InputTypeError, match="covariance must be True or False"):
        determination.solve_wahba(body, body, covariance=flag)
    with pytest.raises(InputTypeError, match="covariance must be True or False"):
        determination.solve_wahba(np.stack([body, body]), body, covariance=flag)


def test_numpy_bool_flags_are_accepted():
    body = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    assert determination.solve_wahba(body, body, covariance=np.bool_(True)).success


def test_box_faces_rejects_a_cant_limit_for_an_unknown_face():
    # issue 23: box_faces(max_cant={'+W': 0.5}) silently ignored the unknown face
    with pytest.raises(InputError, match=r"max_cant names faces .*\['\+W'\]"):
        thrusters.box_faces(max_cant={"+W": 0.5})
    # a limit for a face left out of ``names`` would be ignored just as silently
    with pytest.raises(InputError, match="max_cant"):
        thrusters.box_faces(names=("+X", "-X"), max_cant={"+Z": 0.5})
    faces = thrusters.box_faces(names=("+X", "-X"), max_cant={"-X": 0.5})
    assert [f.max_cant for f in faces] == [pytest.approx(np.pi / 2), 0.5]


def test_box_faces_rejects_a_string_for_names():
    with pytest.raises(InputTypeError, match="names must be a sequence"):
        thrusters.box_faces(names="+X")


@pytest.mark.parametrize(
    "data",
    [
        {"a b": 1},
        {"x": {"c.d": {"e": [1.5, 2.0]}}, "s": 'line\nbreak "quoted"', "n": np.int64(3)},
        {"": True, "ü": "ä"},
    ],
)
def test_dump_toml_writes_valid_toml_that_reads_back(data):
    # issue 23: dump_toml({'a b': 1}) wrote 'a b = 1', which no TOML reader accepts
    back = tomllib.loads(dump_toml(data))

    def plain(d):
        return {k: plain(v) if isinstance(v, dict) else (v.item() if isinstance(v, np.generic) else v)
                for k, v in d.items()}

    assert back == plain(data)


@pytest.mark.parametrize(("data", "match"), [({1: 2}, "keys must be strings"),
                                              ({"a": {"b": [None]}}, r"a\.b = None cannot be written")])
def test_dump_toml_rejects_what_toml_cannot_hold(data, match):
    with pytest.raises(InputTypeError, match=match):
        dump_toml(data)


@pytest.mark.parametrize("r_bad", [[7e6, 0.0], [[7e6, 0.0, 0.0, 1.0]]])
def test_ecef_to_eci_state_blames_r_ecef_for_its_own_shape(r_bad):
    # issue 23: a bad r_ecef was reported as "v_ecef must have shape ..."
    with pytest.raises(InputError, match="r_ecef must have shape"):
        environment.ecef_to_eci_state(r_bad, [0.0, 7.5e3, 0.0], "2024-01-01")
    with pytest.raises(InputError, match="v_ecef must have shape"):
        environment.ecef_to_eci_state([7e6, 0.0, 0.0], [0.0, 7.5e3], "2024-01-01")


# --- found by the extended registry (issue 23: every public name, strict flags/choices/keys) ---


@pytest.mark.parametrize("flag", ["no", 1, None])
def test_config_dataclass_flags_are_checked_by_the_validation_layer(flag):
    from adcskit.simulation import OrbitSpec, ThrusterSpec

    with pytest.raises(InputTypeError, match="gravity_gradient must be True or False"):
        OrbitSpec(gravity_gradient=flag)
    with pytest.raises(InputTypeError, match="failure_known must be True or False"):
        ThrusterSpec.from_torque_matrix(np.eye(3), failure_known=flag)


def test_thruster_constructors_name_their_argument():
    from adcskit.simulation import ThrusterSpec

    with pytest.raises(InputTypeError, match="ts must be an adcskit.thrusters.ThrusterSet"):
        ThrusterSpec.from_thruster_set(None)
    with pytest.raises(InputError, match="A must be finite"):
        ThrusterSpec.from_torque_matrix([[np.nan, 0.0], [0.0, 1.0], [1.0, 0.0]])
    with pytest.raises(InputTypeError, match="thrusters must be a sequence of Thruster"):
        thrusters.ThrusterSet.from_thrusters("abc")


def test_sgp4_orbit_rejects_a_line_longer_than_a_tle_line():
    # sgp4 reads fixed columns and ignored anything after column 69; TLE of satellite 00005, the
    # first case of the SGP4 verification set (Vallado et al. 2006, AIAA 2006-6753)
    line1 = "1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753"
    line2 = "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667"
    environment.sgp4_orbit(line1, line2, "2000-06-28")
    with pytest.raises(InputError, match="tle_line2 must be a TLE line of 69 characters"):
        environment.sgp4_orbit(line1, line2 + "-extra", "2000-06-28")


@pytest.mark.parametrize("flag", ["no", 1])
def test_estimation_and_study_flags_are_checked(flag):
    x = np.random.default_rng(0).standard_normal((6, 2))
    with pytest.raises(InputTypeError, match="estimate_B must be True or False"):
        estimation.regression_data(x[:-1], x[1:], np.zeros((5, 1)), B=np.zeros((2, 1)), estimate_B=flag)
    from adcskit.studies import resolve_config

    with pytest.raises(InputTypeError, match="quick must be True or False"):
        resolve_config("wahba-table1", None, quick=flag)


def test_claim_rejects_runs_under_a_reading_it_does_not_declare():
    from adcskit.studies import ClaimSpec

    spec = ClaimSpec(id="c", statement="s", where="w", quantity="q", value=lambda m: m["r"], threshold=1.0,
                     better="below", stochastic=False, margin=0.0, margin_reason="test: exact")
    assert spec.evaluate({"default": [{"r": 0.5}]}).outcome == "holds"
    with pytest.raises(InputError, match=r"runs has readings \['other'\] that claim 'c' does not declare"):
        spec.evaluate({"default": [{"r": 0.5}], "other": [{"r": 2.0}]})


def test_chi2_band_is_finite_down_to_the_smallest_allowed_alpha():
    lo, hi = estimation.chi2_band(3, 10, alpha=1e-300)
    assert 0.0 <= lo < hi < np.inf
    with pytest.raises(InputError, match=r"alpha must be in \[1e-300, 1\)"):
        estimation.chi2_band(3, 10, alpha=5e-324)  # alpha / 2 rounds to 0: upper end inf


def test_numbers_refuse_true_false_and_flags_accept_numpy_bools():
    # a flag passed where a number goes was read as 1/0 (as_array converted bools silently)
    with pytest.raises(InputTypeError, match="f_max must be an array of numbers, not True/False"):
        thrusters.min_impulse_bit(0.5, f_max=True, t_min=0.003)
    from adcskit.control import schmitt_trigger

    with pytest.raises(InputError, match="state must be -1, 0 or 1"):
        schmitt_trigger([0.0, 0.2], u_on=0.15, u_off=0.07, state=True)
    with pytest.raises(InputTypeError, match="rng must be None"):
        determination.robust_wahba([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], 0.01, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                                   0.0, rng="3")  # minmax never draws from rng, and accepted anything


def test_simulate_accepts_a_numpy_bool_for_record():
    from adcskit.simulation import Scenario, SimSpec, simulate

    sc = Scenario(sim=SimSpec(dt=0.02, t_final=0.2, metrics_from_s=0.1))
    with pytest.raises(InputTypeError, match="record must be True or False"):
        simulate(sc, 1, rng=0, record="no")
    assert simulate(sc, 1, rng=0, record=np.bool_(False)).success


# --- found by the exhaustive hypothesis variant (-m slow) -------------------------------------


def test_loop_settings_reject_a_command_rate_whose_period_overflows():
    from adcskit.control import LoopSettings

    # 5e-324 Hz * dt underflowed to 0 and raised ZeroDivisionError
    for rate in (5e-324, 1e-300):
        with pytest.raises(InputError, match="command_rate_hz must give a command period"):
            LoopSettings(command_rate_hz=rate)


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # numpy's overflow on the way to the failure
def test_propagate_attitude_reports_an_early_step_size_failure():
    from adcskit.dynamics import propagate_attitude

    # a needle-like inertia (it breaks the triangle inequality) makes the step size vanish before
    # the first output time; solve_ivp then left a plain list where an array was expected
    res = propagate_attitude([0.1, -0.2, 0.3, 0.9273618495495703], [0.01, -0.02, 0.03],
                             [[10.0, 0.1, 0.0], [0.1, 8.0, 0.0], [0.0, 0.0, 2.4e-289]],
                             [0.0, 1.0, 2.0], torque=lambda t, q, w: np.array([1e-3, 0.0, 0.0]))
    assert not res.success and res.q.shape[1] == 4 and np.all(np.isfinite(res.q))


def test_mekf_propagate_refuses_a_step_that_overflows_the_covariance():
    f = estimation.MultiplicativeEKF(q0=[0.0, 0.0, 0.0, 1.0], b0=np.zeros(3), P0=np.diag([1e-2] * 3 + [1e-8] * 3),
                                     sigma_v=1e-5, sigma_u=1e-8)
    P = f.P.copy()
    with pytest.raises(InputError, match="dt = 6.2e\\+64 s is too long a step"):
        f.propagate([0.01, -0.02, 0.005], 6.2e64)  # the value hypothesis found
    np.testing.assert_array_equal(f.P, P)  # left unchanged
    f.propagate([0.01, -0.02, 0.005], 0.5)
    assert np.all(np.isfinite(f.P))
