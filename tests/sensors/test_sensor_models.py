"""Sun sensor and magnetometer models."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from adcskit.errors import InputError, InputTypeError
from adcskit.sensors import Magnetometer, SunSensor, VectorSensor


def _angles_deg(a, b):
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    return np.degrees(np.arccos(np.clip(np.sum(a * b, axis=-1), -1.0, 1.0)))


@pytest.fixture(scope="module")
def truth():
    rng = np.random.default_rng(11)
    n = 4000
    A = Rotation.random(n, random_state=12).inv().as_matrix()  # reference -> body
    r = rng.normal(size=(n, 3))
    r /= np.linalg.norm(r, axis=1, keepdims=True)
    return A, r, np.einsum("nij,nj->ni", A, r)


def test_error_free_sensor_is_A_r(truth):
    A, r, b = truth
    assert np.allclose(SunSensor().measure(A, r), b, atol=1e-15)
    B = 3e-5 * r
    assert np.allclose(Magnetometer().measure(A, B), 3e-5 * b, atol=1e-20)
    # Sun sensor normalises non-unit references (e.g. sun_position in metres).
    assert np.allclose(SunSensor().measure(A[0], 1.5e11 * r[0]), b[0], atol=1e-15)
    # Broadcasting: one attitude, many vectors and vice versa.
    assert SunSensor().measure(A[0], r[:5]).shape == (5, 3)
    assert SunSensor().measure(A[:5], r[0]).shape == (5, 3)


@pytest.mark.parametrize("bound_deg", [0.005, 0.5, 5.0, 60.0])
def test_angle_bound_never_exceeded_and_filled(truth, bound_deg):
    # S0: sun sensor +-0.005 deg, magnetometer +-0.5 deg bounded errors.
    A, r, b = truth
    for sensor, ref in ((SunSensor(angle_bound=np.radians(bound_deg)), r),
                        (Magnetometer(angle_bound=np.radians(bound_deg)), 4e-5 * r)):
        m = sensor.measure(A, ref, rng=5)
        ang = _angles_deg(m, b)
        assert ang.max() <= bound_deg * (1 + 1e-9) + 1e-9
        # Uniform over the cap: P(angle < 0.99 bound) ~ 0.98 per sample, so over 4000 samples the
        # max reaches 0.99 bound except with probability 0.98^4000 ~ 1e-35.
        assert ang.max() > 0.99 * bound_deg
        # Cap-uniform mean angle: for small bounds 2/3 bound; 5-sigma band of the sample mean
        # (sd of the angle = bound/sqrt(18) for the small-angle law).
        if bound_deg <= 5.0:
            assert abs(ang.mean() - 2 / 3 * bound_deg) < 5 * bound_deg / np.sqrt(18) / np.sqrt(len(ang))
        # The magnetometer keeps the field magnitude.
        if isinstance(sensor, Magnetometer):
            assert np.allclose(np.linalg.norm(m, axis=1), 4e-5, rtol=1e-12)


def test_component_fraction_never_exceeded(truth):
    # S0 Table 1: +-20 % of each component.
    A, r, b = truth
    B = 4e-5 * r
    m = Magnetometer(component_fraction=0.2).measure(A, B, rng=2)
    ratio = m / (4e-5 * b)
    assert np.all(np.abs(ratio - 1.0) <= 0.2 + 1e-12)
    # uniform on [-0.2, 0.2]: sample std 0.2/sqrt(3) within 5 sigma (sd of the sd ~ 0.2/sqrt(3)/sqrt(2N)*~1)
    assert abs(np.std(ratio - 1.0) - 0.2 / np.sqrt(3)) < 5 * 0.2 / np.sqrt(3) / np.sqrt(2 * ratio.size)


def test_gaussian_noise_statistics():
    # Seeded statistical bounds: mean within 5 sigma/sqrt(N), std within 5 sigma/sqrt(2N).
    n = 20000
    sigma = 1e-7  # 100 nT
    B = np.array([2e-5, -1e-5, 3e-5])
    m = Magnetometer(noise_std=sigma).measure(np.eye(3), np.tile(B, (n, 1)), rng=7)
    e = m - B
    assert np.all(np.abs(e.mean(axis=0)) < 5 * sigma / np.sqrt(n))
    assert np.all(np.abs(e.std(axis=0, ddof=1) - sigma) < 5 * sigma / np.sqrt(2 * n))
    assert abs(np.corrcoef(e.T)[0, 1]) < 5 / np.sqrt(n)
    # Sun sensor: noise_std is an angle per axis; the angular error is Rayleigh with scale
    # sigma, mean sigma sqrt(pi/2) (first order in sigma).
    sig = np.radians(0.01)
    s = SunSensor(noise_std=sig).measure(np.eye(3), np.tile([0.0, 0.6, 0.8], (n, 1)), rng=8)
    assert np.allclose(np.linalg.norm(s, axis=1), 1.0, atol=1e-15)
    ang = np.radians(_angles_deg(s, np.array([0.0, 0.6, 0.8])))
    sd_mean = sig * np.sqrt((4 - np.pi) / 2) / np.sqrt(n)
    assert abs(ang.mean() - sig * np.sqrt(np.pi / 2)) < 5 * sd_mean


def test_bias_and_misalignment():
    b = np.array([1.0, 0.0, 0.0])
    bias = np.array([1e-6, -2e-6, 3e-6])
    assert np.allclose(Magnetometer(bias=bias).measure(np.eye(3), 3e-5 * b), 3e-5 * b + bias)
    eps = np.radians(0.3)
    mis = Magnetometer(misalignment=[0.0, 0.0, eps])
    m = mis.measure(np.eye(3), b)
    # exp(-[theta x]) b: a vector perpendicular to theta turns by |theta|; sign convention:
    # (I - [theta x]) x_hat = x_hat - eps y_hat.
    assert np.allclose(m, [np.cos(eps), -np.sin(eps), 0.0], atol=1e-15)
    assert np.allclose(mis.measure(np.eye(3), [0.0, 0.0, 1.0]), [0.0, 0.0, 1.0])  # along theta
    # A general misalignment turns every vector by at most |theta|, perpendicular ones exactly.
    theta = np.array([1e-3, -2e-3, 0.5e-3])
    sensor = SunSensor(misalignment=theta)
    dirs = np.random.default_rng(0).normal(size=(500, 3))
    ang = np.radians(_angles_deg(sensor.measure(np.eye(3), dirs), dirs))
    assert ang.max() <= np.linalg.norm(theta) * (1 + 1e-9)
    perp = np.cross(theta, [1.0, 0.0, 0.0])
    assert np.radians(_angles_deg(sensor.measure(np.eye(3), perp), perp)) == pytest.approx(
        np.linalg.norm(theta), rel=1e-6)
    # Matrix is a rotation and equals scipy's (the inverse of) rotvec rotation.
    M = sensor.misalignment_matrix
    assert np.allclose(M, Rotation.from_rotvec(theta).inv().as_matrix(), atol=1e-15)


def test_seeded_reproducible_and_input_untouched(truth):
    A, r, _ = truth
    A0, r0 = A.copy(), r.copy()
    s = SunSensor(angle_bound=np.radians(0.5), component_fraction=0.1, noise_std=1e-4)
    m1 = s.measure(A, r, rng=3)
    m2 = s.measure(A, r, rng=np.random.default_rng(3))
    m3 = s.measure(A, r, rng=4)
    assert np.array_equal(m1, m2) and not np.array_equal(m1, m3)
    assert np.array_equal(s.measure(A, r), s.measure(A, r, rng=0))  # None -> seed 0
    assert np.array_equal(A, A0) and np.array_equal(r, r0)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"noise_std": -1.0}, "noise_std"),
        ({"angle_bound": np.pi}, "angle_bound"),
        ({"component_fraction": 1.0}, "component_fraction"),
        ({"bias": [0.0, 1.0]}, "bias"),
        ({"misalignment": [4.0, 0.0, 0.0]}, "misalignment"),
        ({"noise_std": np.nan}, "noise_std"),
    ],
)
def test_bad_configuration(kwargs, name):
    with pytest.raises(InputError, match=name):
        Magnetometer(**kwargs)


def test_bad_measure_inputs():
    s = SunSensor()
    with pytest.raises(InputError, match="A"):
        s.measure(np.eye(2), [1.0, 0.0, 0.0])
    with pytest.raises(InputError, match="r"):
        s.measure(np.eye(3), [1.0, 0.0])
    with pytest.raises(InputError, match="same batch length"):
        s.measure(np.tile(np.eye(3), (3, 1, 1)), np.ones((4, 3)))
    with pytest.raises(InputError, match="non-zero"):
        s.measure(np.eye(3), [0.0, 0.0, 0.0])
    with pytest.raises(InputError, match="finite"):
        s.measure(np.eye(3), [np.nan, 0.0, 1.0])
    with pytest.raises(InputTypeError, match="rng"):
        s.measure(np.eye(3), [1.0, 0.0, 0.0], rng="seed")
    with pytest.raises(InputTypeError, match="normalize"):
        VectorSensor(normalize=1)
    with pytest.raises(TypeError):
        SunSensor(0.1)  # keyword-only


def test_sensor_pickles_for_workers():
    import pickle

    s = Magnetometer(angle_bound=0.01, bias=[1e-7, 0.0, 0.0], misalignment=[0.0, 1e-3, 0.0])
    s2 = pickle.loads(pickle.dumps(s))
    assert isinstance(s2, Magnetometer) and np.array_equal(s2.bias, s.bias)
    assert np.array_equal(s2.measure(np.eye(3), [3e-5, 0, 0], rng=1), s.measure(np.eye(3), [3e-5, 0, 0], rng=1))
    assert s == s2 and hash(s) == hash(s2)  # value comparison (see Notes)
    assert s != Magnetometer(angle_bound=0.01) and s != SunSensor(angle_bound=0.01)
