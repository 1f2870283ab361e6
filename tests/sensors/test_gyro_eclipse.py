"""Rate gyro (Farrenkopf model) and the sun sensor's eclipse flag."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from adcskit.errors import InputError, InputTypeError
from adcskit.sensors import RateGyro, SunSensor
from adcskit.sensors._gyro_kernels import gyro_step, gyro_step_jit


def test_rate_gyro_equals_kernel_with_same_draws():
    # the vectorised class and the per-sample kernel (used by compiled simulators) are two
    # implementations of Crassidis & Junkins (2012) §7.2's discrete model: same draws, same
    # readings to rounding (cumulative sum vs sequential sum: ~1e-18 rad/s)
    g = RateGyro(sigma_v=1e-4, sigma_u=1e-5, rate_hz=20.0, bias0=[1e-3, -2e-3, 5e-4])
    rng = np.random.default_rng(3)
    omega = rng.normal(size=(2, 50, 3)) * 0.1
    m = g.measure(omega, rng=9)
    gen = np.random.default_rng(9)
    n_u = gen.standard_normal((2, 50, 3))
    n_v = gen.standard_normal((2, 50, 3))
    for k in range(2):
        bias = g.bias0.copy()
        out = np.empty(3)
        for t in range(50):
            np.testing.assert_allclose(m.bias[k, t], bias, atol=1e-17)
            gyro_step_jit(omega[k, t], bias, g.sigma_v, g.sigma_u, g.dt, n_v[k, t], n_u[k, t], out)
            np.testing.assert_allclose(m.omega[k, t], out, atol=1e-16)
    # the interpreted source gives the same as the compiled one
    b1, b2, o1, o2 = g.bias0.copy(), g.bias0.copy(), np.empty(3), np.empty(3)
    gyro_step(omega[0, 0], b1, 1e-4, 1e-5, 0.05, n_v[0, 0], n_u[0, 0], o1)
    gyro_step_jit(omega[0, 0], b2, 1e-4, 1e-5, 0.05, n_v[0, 0], n_u[0, 0], o2)
    np.testing.assert_array_equal(o1, o2)
    np.testing.assert_array_equal(b1, b2)


def test_rate_gyro_statistics():
    # Farrenkopf model: bias increments have variance σu² Δt; readings minus true rate minus
    # mean bias have variance σv²/Δt + σu² Δt/12. 3 x 20000 draws: sample variances within
    # 4 % (>5σ of their relative sd sqrt(2/60000) = 0.6 %)
    g = RateGyro(sigma_v=2e-4, sigma_u=3e-5, rate_hz=4.0)
    m = g.measure(np.zeros((20000, 3)), rng=1)
    dt = 0.25
    inc = np.diff(m.bias, axis=0)
    assert inc.var() == pytest.approx(g.sigma_u**2 * dt, rel=0.04)
    mid = 0.5 * (m.bias[:-1] + m.bias[1:])
    assert (m.omega[:-1] - mid).var() == pytest.approx(g.sigma_v**2 / dt + g.sigma_u**2 * dt / 12,
                                                      rel=0.04)
    np.testing.assert_allclose(m.t[:3], [0.0, 0.25, 0.5])


def test_rate_gyro_noise_free_and_validation():
    g = RateGyro(rate_hz=5.0, bias0=[1.0, 2.0, 3.0])
    m = g.measure(np.ones((4, 3)), t0=10.0)
    np.testing.assert_array_equal(m.omega, np.ones((4, 3)) + [1.0, 2.0, 3.0])
    np.testing.assert_allclose(m.t, [10.0, 10.2, 10.4, 10.6])
    assert m.omega.shape == (4, 3) and m.bias.shape == (4, 3)
    assert set(m.to_dict()) == {"t", "omega", "bias"}
    with pytest.raises(InputError, match="rate_hz"):
        RateGyro(rate_hz=0.0)
    with pytest.raises(InputError, match="sigma_u"):
        RateGyro(sigma_u=-1.0)
    with pytest.raises(InputError, match="omega"):
        g.measure(np.ones((4, 2)))
    with pytest.raises(InputError, match="omega"):
        g.measure(np.full((4, 3), np.nan))
    assert pickle.loads(pickle.dumps(g)) == g and hash(g) == hash(RateGyro(rate_hz=5.0, bias0=[1, 2, 3]))


def test_sun_sensor_eclipse_flag():
    ss = SunSensor(noise_std=1e-3)
    A = np.broadcast_to(np.eye(3), (5, 3, 3))
    r = np.tile([1.0, 0.0, 0.0], (5, 1))
    ecl = np.array([False, True, True, False, False])
    lit = ss.measure(A, r, rng=4)
    m = ss.measure(A, r, rng=4, eclipse=ecl)
    assert np.all(np.isnan(m[ecl])) and np.all(np.isfinite(m[~ecl]))
    np.testing.assert_array_equal(m[~ecl], lit[~ecl])  # same draws with or without eclipse
    one = ss.measure(np.eye(3), [0.0, 1.0, 0.0], rng=1, eclipse=True)
    assert one.shape == (3,) and np.all(np.isnan(one))
    assert np.all(np.isfinite(ss.measure(np.eye(3), [0.0, 1.0, 0.0], eclipse=np.bool_(False))))
    with pytest.raises(InputError, match="eclipse"):
        ss.measure(A, r, eclipse=np.array([True, False]))
    with pytest.raises(InputTypeError, match="eclipse"):
        ss.measure(A, r, eclipse=np.zeros(5))
