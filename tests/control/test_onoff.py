"""The on-off loop of S4: closed-form checks of its pieces and kernel agreement."""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest

from adcskit.control import (
    LoopParams,
    LoopSettings,
    schmitt_trigger,
    simulate_batch,
    simulate_trace,
)
from adcskit.errors import InputError

TAU = 0.01  # thruster time constant, S4 Table 3


def _open_loop_params(**kw):
    # a huge reference keeps the command at +1 for the whole (short) run: open-loop thrust
    base = dict(kp=1.0, ki=0.0, kd=0.0, u_on=0.15, theta_ref=1e3, disturbance=0.0)
    base.update(kw)
    return LoopParams(**base)


def _lag_step(t):
    """Unit step response of 1/(tau s + 1)^2 (two cascaded lags)."""
    t = np.maximum(t, 0.0)
    return 1.0 - (1.0 + t / TAU) * np.exp(-t / TAU)


def _lag_step_double_integral(t):
    """int_0^t int_0^s of _lag_step (derived by hand, checked by differentiation)."""
    t = np.maximum(t, 0.0)
    return t**2 / 2 - 2 * TAU * t + 3 * TAU**2 - TAU * np.exp(-t / TAU) * (3 * TAU + t)


@pytest.mark.parametrize("delay", [0.0, 0.02, 0.035])
def test_delay_and_second_order_lag_step_response(delay):
    # closed form: torque = T * step response of the lag, delayed by tau (S4 Fig. 1 thruster)
    s = LoopSettings(t_final=0.2, t_window=0.1, command_rate_hz=1000.0)
    tr = simulate_trace(_open_loop_params(delay=delay, torque=2.0), s)
    expected = 2.0 * _lag_step(tr.t - delay)
    # delays on the 1 ms grid are exact up to rounding; machine precision tolerance
    np.testing.assert_allclose(tr.thrust_torque, expected, atol=1e-12)
    assert np.all(tr.thrust_torque[tr.t < delay - 1e-12] == 0.0)


def test_fractional_delay_is_interpolated():
    # a delay of 2.5 steps lies between the 2- and 3-step responses (linear interpolation)
    s = LoopSettings(t_final=0.1, t_window=0.05, command_rate_hz=1000.0)
    lo = simulate_trace(_open_loop_params(delay=0.002), s).thrust_torque
    hi = simulate_trace(_open_loop_params(delay=0.003), s).thrust_torque
    mid = simulate_trace(_open_loop_params(delay=0.0025), s).thrust_torque
    np.testing.assert_allclose(mid, 0.5 * (lo + hi), atol=1e-12)


def test_rigid_body_double_integrates_the_torque():
    # J theta'' = T y(t - tau) + T_d, theta(0) = omega(0) = 0: exact for ZOH inputs
    s = LoopSettings(t_final=0.3, t_window=0.1, command_rate_hz=1000.0)
    J, T, Td, d = 10.0, 1.0, 0.05, 0.02
    tr = simulate_trace(_open_loop_params(delay=d, torque=T, inertia=J, disturbance=Td), s)
    expected = T / J * _lag_step_double_integral(tr.t - d) + Td / J * tr.t**2 / 2
    np.testing.assert_allclose(tr.theta, expected, rtol=1e-9, atol=1e-15)


def test_schmitt_hysteresis():
    u = np.array([0.0, 0.1, 0.15, 0.1, 0.08, 0.07, -0.1, -0.2, -0.1, -0.05, 0.2, -0.2])
    # U_on = 0.15, U_off = 0.075: on at >= 0.15, stays on until < 0.075, flips directly
    expected = [0, 0, 1, 1, 1, 0, 0, -1, -1, 0, 1, -1]
    np.testing.assert_array_equal(schmitt_trigger(u, 0.15, 0.075), expected)
    # with U_off = U_on there is no memory band
    np.testing.assert_array_equal(schmitt_trigger([0.2, 0.1], 0.15, 0.15), [1, 0])


def test_loop_trace_matches_batch_and_schmitt_reference():
    s = LoopSettings(t_final=5.0, t_window=2.0)
    tr = simulate_trace(LoopParams(), s)
    m = simulate_batch(LoopParams(), s)
    np.testing.assert_array_equal(tr.metrics.as_array(), m.as_array())
    # the recorded command equals the Schmitt trigger applied to the held PID output
    hold = s.hold_steps
    u_held = tr.u[1::hold]
    cmd = tr.command[1::hold]
    np.testing.assert_array_equal(schmitt_trigger(u_held, 0.15, 0.075), cmd)


def _random_batch(n, rng, varying=False):
    return LoopParams(
        kp=rng.uniform(1, 100, n),
        ki=rng.uniform(0, 50, n),
        kd=rng.uniform(0, 100, n),
        u_on=rng.uniform(0.05, 0.5, n),
        off_ratio=rng.uniform(0, 1, n),
        inertia=rng.uniform(5, 15, n),
        torque=rng.uniform(0.6, 1.4, n),
        delay=rng.uniform(0, 0.05, n),
        disturbance=rng.normal(0.05, 0.05, n),
        disturbance_amp=rng.uniform(0, 0.05, n) if varying else 0.0,
        disturbance_freq_hz=rng.uniform(0, 1, n) if varying else 0.0,
        theta_ref=rng.uniform(-0.5, 0.5, n),
    )


@pytest.mark.parametrize("rate", [50.0, 200.0, 1000.0])
def test_numba_matches_numpy_bit_for_bit(rate):
    # same operations in the same order, no fastmath: identical floats
    p = _random_batch(64, np.random.default_rng(3))
    s = LoopSettings(t_final=6.0, t_window=2.0, command_rate_hz=rate)
    a = simulate_batch(p, s, backend="numba").as_array()
    b = simulate_batch(p, s, backend="numpy").as_array()
    c = simulate_batch(p, s, backend="numba", parallel=False).as_array()
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(a, c)


@pytest.mark.parametrize("n, varying, lanes", [(5, True, 16), (70, False, 16), (70, True, 64), (133, False, 64)])
def test_lane_blocks_match_the_per_sample_kernel_bit_for_bit(n, varying, lanes):
    # the CPU driver advances blocks of samples together (SIMD across samples) with the same
    # operations per sample as the per-sample kernel (used with traces and on the GPU):
    # identical floats, whatever the block size, a partial last block, a sinusoidal disturbance
    from adcskit.control import _onoff_kernels as k
    from adcskit.control.onoff import _buffer_length, _coefficients, _param_matrix

    s = LoopSettings(t_final=2.0, t_window=0.5, command_rate_hz=200.0)
    P = _param_matrix(_random_batch(n, np.random.default_rng(n), varying=varying))
    C = _coefficients(s)
    n_steps, hold, n_win = s.n_steps, s.hold_steps, s.n_window
    L = _buffer_length(P, s.dt)
    traces = np.zeros((n, n_steps + 1, k.N_TRACE))  # traces: one sample at a time
    per_sample = k.simulate_serial(P, C, n_steps, hold, n_win, L, traces, lanes)
    none = np.empty((0, 0, k.N_TRACE))
    for fn in (k.simulate_serial, k.simulate_parallel):
        blocks = fn(P, C, n_steps, hold, n_win, L, none, lanes)
        assert blocks.tobytes() == per_sample.tobytes()


def test_lane_count_gives_every_thread_a_block():
    from adcskit.control import _onoff_kernels as k

    threads = numba.get_num_threads()
    for n in (1, 20, 100, 2800, 10**6):
        lanes = k.lane_count(n)
        assert k.MIN_LANES <= lanes <= k.LANES
        if n >= k.MIN_LANES * threads:
            assert -(-n // lanes) >= threads  # at least one block per thread


def test_numba_matches_numpy_time_varying_disturbance():
    # libm sin vs numpy sin may differ by an ulp; relay switching can amplify that, so we
    # compare a short run where no switching instant is close to a threshold (10 s -> 1e-9)
    p = _random_batch(16, np.random.default_rng(4), varying=True)
    s = LoopSettings(t_final=1.0, t_window=0.5)
    a = simulate_batch(p, s, backend="numba").as_array()
    b = simulate_batch(p, s, backend="numpy").as_array()
    np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-12)


def test_python_backend_matches_numba():
    p = _random_batch(3, np.random.default_rng(5))
    s = LoopSettings(t_final=0.5, t_window=0.2)
    np.testing.assert_array_equal(
        simulate_batch(p, s, backend="python").as_array(), simulate_batch(p, s).as_array()
    )


def test_nominal_loop_physics():
    # S4 Table 3 nominal loop, 15 deg step: settles, overshoot small, limit cycle small
    m = simulate_batch()
    assert m.overshoot_pct[0] < 10.0
    assert math.degrees(m.max_abs_err_last[0]) < 0.25  # S4 claims 0.25 deg accuracy
    assert m.firings[0] > 1 and m.fuel[0] > 0
    # fuel is at least the impulse needed to cancel the disturbance over the final window
    assert m.fuel[0] > 0.05 * 10.0
    assert 0 < m.settling_time[0] < 30


def test_input_validation():
    with pytest.raises(InputError, match="inertia"):
        simulate_batch(LoopParams(inertia=-1.0))
    with pytest.raises(InputError, match="delay"):
        simulate_batch(LoopParams(delay=[0.01, -0.01]))
    with pytest.raises(InputError, match="backend"):
        simulate_batch(backend="fortran")
    with pytest.raises(InputError, match="command_rate_hz"):
        LoopSettings(command_rate_hz=300.0)
    with pytest.raises(InputError, match="broadcast"):
        simulate_batch(LoopParams(kp=[1.0, 2.0], ki=[1.0, 2.0, 3.0]))
    with pytest.raises(InputError, match="no field"):
        LoopParams().replace(gain=1.0)


def test_inputs_not_modified():
    kp = np.array([10.0, 20.0])
    before = kp.copy()
    simulate_batch(LoopParams(kp=kp), LoopSettings(t_final=0.5, t_window=0.1))
    np.testing.assert_array_equal(kp, before)


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


@given(
    st.lists(st.floats(-2.0, 2.0, allow_nan=False), min_size=1, max_size=40),
    st.floats(0.01, 1.0),
    st.floats(0.0, 1.0),
)
@settings(max_examples=60, deadline=None)
def test_schmitt_is_odd_and_three_level(u, u_on, ratio):
    u = np.array(u)
    out = schmitt_trigger(u, u_on, ratio * u_on)
    assert set(np.unique(out)) <= {-1.0, 0.0, 1.0}
    np.testing.assert_array_equal(schmitt_trigger(-u, u_on, ratio * u_on), -out)
    # the output is never on while |u| < U_off, never off while |u| >= U_on
    assert np.all(out[np.abs(u) < ratio * u_on] == 0.0)
    assert np.all(out[np.abs(u) >= u_on] != 0.0)


@given(
    kp=st.floats(1.0, 100.0), kd=st.floats(1.0, 100.0), ki=st.floats(0.0, 1.0),
    step_deg=st.floats(1.0, 30.0), td=st.floats(-0.1, 0.1), delay=st.floats(0.0, 0.04),
)
@settings(max_examples=15, deadline=None)
def test_loop_is_mirror_symmetric(kp, kd, ki, step_deg, td, delay):
    # negating the command and the disturbance mirrors the whole trajectory exactly
    s = LoopSettings(t_final=3.0, t_window=1.0)
    p = LoopParams(kp=kp, kd=kd, ki=ki, delay=delay, disturbance=td, theta_ref=math.radians(step_deg))
    a = simulate_batch(p, s, parallel=False)
    b = simulate_batch(p.replace(theta_ref=-math.radians(step_deg), disturbance=-td), s, parallel=False)
    for name in ("overshoot_pct", "mean_abs_err_last", "max_abs_err_last", "fuel", "firings", "settling_time"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    np.testing.assert_array_equal(a.final_error, -b.final_error)


def test_fuel_to_propellant():
    from adcskit.control import fuel_to_propellant

    # 10 N m s at a 0.5 m arm = 20 N s; Isp 220 s -> 20 / (220 * 9.80665) kg; 100 kg -> 0.2 m/s
    out = fuel_to_propellant(10.0, lever_arm=0.5, isp=220.0, mass=100.0)
    assert out["impulse_Ns"] == pytest.approx(20.0, rel=1e-15)
    assert out["propellant_kg"] == pytest.approx(20.0 / (220.0 * 9.80665), rel=1e-15)
    assert out["delta_v_mps"] == pytest.approx(0.2, rel=1e-15)
    with pytest.raises(InputError, match="lever_arm"):
        fuel_to_propellant(1.0, lever_arm=0.0)
