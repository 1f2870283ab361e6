"""The wheel kernel's bit-identical cuts (issue 24 item 1), each against what it replaced.

``benchmarks/wheel_identity.py`` compares every output of ``simulate_wheels`` over 13 scenarios
bytewise before and after a kernel change; these tests keep the three cuts that rest on an
argument rather than on an unchanged operation list honest on inputs built to reach their
edges: the settling test decided from ``tan^2`` (exact within 1e-6 of the band), the Coulomb
term skipped for ``c_c = +-0`` (the product ``c_c om`` is the term, signed zeros and NaNs
included) and ``rk4`` with the derivative written out against the former ``rk4`` + ``rhs``
(main ``18ed915``, verbatim below). All compared bytewise, as plain Python and compiled into
one ``njit`` caller (no fused multiply-add on the CPU). Seeded; about 6 s of compilation.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest

from adcskit._targets import device
from adcskit.attitude._device import qdiff, qdot, qerr, unit_q4_pos
from adcskit.simulation import _wheel_kernels as _k
from adcskit.simulation._kernels import outside, settle_bounds
from adcskit.simulation._wheel_kernels import COULOMB_EPS, _mat3


def _random_q(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _pairs_near(rng, n, band):
    """Pairs (q, r) whose error angle is band * (1 + eps), eps from 1e-3 down to 1e-12 and 0,
    of both signs, plus random pairs, identical pairs and opposite ones."""
    q = _random_q(rng, n)
    axis = rng.normal(size=(n, 3))
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    eps = np.concatenate([np.zeros(8), np.outer([1.0, -1.0], 10.0 ** -np.arange(3, 13)).ravel()])
    ang = band * (1.0 + np.resize(eps, n))
    dq = np.hstack([np.sin(ang / 2)[:, None] * axis, np.cos(ang / 2)[:, None]])  # A(dq) rotates by ang
    r = np.array([_compose(dq[i], q[i]) for i in range(n)])
    r[: n // 8] = _random_q(rng, n // 8)
    r[n // 8: n // 8 + 4] = q[n // 8: n // 8 + 4]
    r[n // 8 + 4: n // 8 + 8] = -q[n // 8 + 4: n // 8 + 8]
    return q, r


def _compose(p, q):
    # Markley's product p (x) q, scalar last (eq. 2.82a)
    pv, p4, qv, q4 = p[:3], p[3], q[:3], q[3]
    return np.r_[p4 * qv + q4 * pv - np.cross(pv, qv), p4 * q4 - pv @ qv]


@device
def _exact(q0, q1, q2, q3, r0, r1, r2, r3, band):
    d0, d1, d2, d3 = qdiff(q0, q1, q2, q3, r0, r1, r2, r3)
    return _k._angle(d0, d1, d2, d3) > band


_outside = outside  # the settling test of both closed-loop kernels


@numba.njit(cache=False)
def _both(x, band, tb_lo, tb_hi, out):
    for i in range(x.shape[0]):
        out[i, 0] = _outside(x[i, 0], x[i, 1], x[i, 2], x[i, 3], x[i, 4], x[i, 5], x[i, 6], x[i, 7], band, tb_lo,
                             tb_hi)
        out[i, 1] = _exact(x[i, 0], x[i, 1], x[i, 2], x[i, 3], x[i, 4], x[i, 5], x[i, 6], x[i, 7], band)


@pytest.mark.parametrize("band_deg", [1e-6, 0.02, 0.5, 5.0, 90.0, 170.0, 179.9])
def test_settling_test_from_tan_squared_equals_the_exact_angle(band_deg):
    # the kernels' outside() is exactly _angle(qdiff(q, r)) > band: away from the edge by more
    # than 1e-6 relative the tan^2 comparison cannot flip (its rounding is ~1e-16 relative), and
    # within it (and for band >= 3 rad, where tb_hi <= 0) the atan2 path decides; and that angle
    # is qerr's (the thruster kernel's own exact test before the two kernels shared this one)
    band = math.radians(band_deg)
    tb_lo, tb_hi = settle_bounds(band)
    rng = np.random.default_rng(2024)
    q, r = _pairs_near(rng, 400, band)
    x = np.hstack([q, r])
    py = np.array([[outside(*row, band, tb_lo, tb_hi), _exact(*row, band)] for row in x])
    np.testing.assert_array_equal(py[:, 0], py[:, 1])
    np.testing.assert_array_equal(py[:, 1], [qerr(*row)[3] > band for row in x])
    out = np.empty((x.shape[0], 2), dtype=np.bool_)
    _both(x, band, tb_lo, tb_hi, out)
    np.testing.assert_array_equal(out[:, 0], out[:, 1])
    np.testing.assert_array_equal(out, py)
    assert 0 < np.count_nonzero(out[:, 1]) < x.shape[0] or band_deg > 170.0  # both outcomes reached


@device
def _coulomb_terms(om, cc):
    return cc * om, cc * om / math.sqrt(om * om + COULOMB_EPS * COULOMB_EPS)


@numba.njit(cache=False)
def _coulomb_batch(om, cc, out):
    for i in range(om.shape[0]):
        a, b = _coulomb_terms(om[i], cc)
        out[i, 0] = a
        out[i, 1] = b


def test_coulomb_term_is_the_product_for_a_zero_coefficient():
    # for cc = +-0, cc om / sqrt(om^2 + eps^2) == cc om bit for bit: a signed zero over a
    # positive (or +inf) divisor keeps its sign; inf and NaN om give the NaN of cc om
    rng = np.random.default_rng(7)
    om = np.concatenate([rng.normal(scale=500.0, size=200), [0.0, -0.0, 1e-320, -1e-320, 1e200, -1e200, math.inf,
                                                             -math.inf, math.nan, -math.nan, 1.7e308, -5e-324]])
    for cc in (0.0, -0.0):
        with np.errstate(over="ignore", invalid="ignore"):  # 0 * inf, inf^2 on purpose
            py = np.array([_coulomb_terms(o, cc) for o in om])
        assert py[:, 0].tobytes() == py[:, 1].tobytes()
        out = np.empty((om.size, 2))
        _coulomb_batch(om, cc, out)
        assert out[:, 0].tobytes() == out[:, 1].tobytes() == py[:, 0].tobytes()


# ------------------------------------------------------------------ the former rk4 + rhs, verbatim
@device
def _former_rhs(X, D, J, JI, AX, nw, TM, JW, cv, cc, t0, t1, t2):
    q0, q1, q2, q3 = X[0], X[1], X[2], X[3]
    w0, w1, w2 = X[4], X[5], X[6]
    ah0 = 0.0
    ah1 = 0.0
    ah2 = 0.0
    at0 = 0.0
    at1 = 0.0
    at2 = 0.0
    for j in range(nw):
        a0, a1, a2 = AX[0, j], AX[1, j], AX[2, j]
        h = X[7 + j]
        om = h / JW[j] - (a0 * w0 + a1 * w1 + a2 * w2)
        tw = TM[j] - (cv * om + cc * om / math.sqrt(om * om + COULOMB_EPS * COULOMB_EPS))
        D[7 + j] = tw
        ah0 += a0 * h
        ah1 += a1 * h
        ah2 += a2 * h
        at0 += a0 * tw
        at1 += a1 * tw
        at2 += a2 * tw
    j0, j1, j2 = _mat3(J, 0, w0, w1, w2)
    H0 = j0 + ah0
    H1 = j1 + ah1
    H2 = j2 + ah2
    m0 = t0 - at0 - (w1 * H2 - w2 * H1)
    m1 = t1 - at1 - (w2 * H0 - w0 * H2)
    m2 = t2 - at2 - (w0 * H1 - w1 * H0)
    d0, d1, d2 = _mat3(JI, 0, m0, m1, m2)
    D[0], D[1], D[2], D[3] = qdot(q0, q1, q2, q3, w0, w1, w2)
    D[4] = d0
    D[5] = d1
    D[6] = d2


@device
def _former_rk4(X, XT, KS, KD, J, JI, AX, nw, TM, JW, cv, cc, t0, t1, t2, dt):
    n = 7 + nw
    _former_rhs(X, KD, J, JI, AX, nw, TM, JW, cv, cc, t0, t1, t2)
    for m in range(n):
        KS[m] = KD[m]
        XT[m] = X[m] + 0.5 * dt * KD[m]
    _former_rhs(XT, KD, J, JI, AX, nw, TM, JW, cv, cc, t0, t1, t2)
    for m in range(n):
        KS[m] += 2.0 * KD[m]
        XT[m] = X[m] + 0.5 * dt * KD[m]
    _former_rhs(XT, KD, J, JI, AX, nw, TM, JW, cv, cc, t0, t1, t2)
    for m in range(n):
        KS[m] += 2.0 * KD[m]
        XT[m] = X[m] + dt * KD[m]
    _former_rhs(XT, KD, J, JI, AX, nw, TM, JW, cv, cc, t0, t1, t2)
    s = dt / 6.0
    for m in range(n):
        X[m] = X[m] + s * (KS[m] + KD[m])
    X[0], X[1], X[2], X[3] = unit_q4_pos(X[0], X[1], X[2], X[3])


def _make_steps(step):
    @device
    def steps(X, J, JI, AX, TM, JW, cv, cc, torque, dt, XT, KS, KD, out):
        nw = JW.shape[0]
        for k in range(out.shape[0]):
            step(X, XT, KS, KD, J, JI, AX, nw, TM[k], JW, cv, cc, torque[k, 0], torque[k, 1], torque[k, 2], dt)
            for m in range(X.shape[0]):
                out[k, m] = X[m]
    return steps


_STEPS_NEW = _make_steps(_k.rk4)
_STEPS_FORMER = _make_steps(_former_rk4)


@numba.njit(cache=False)
def _steps_compiled(X, J, JI, AX, TM, JW, cv, cc, torque, dt, XT, KS, KD, out, out2):
    X2 = X.copy()
    _STEPS_NEW(X, J, JI, AX, TM, JW, cv, cc, torque, dt, XT, KS, KD, out)
    _STEPS_FORMER(X2, J, JI, AX, TM, JW, cv, cc, torque, dt, XT, KS, KD, out2)


@pytest.mark.parametrize(("cv", "cc"), [(0.0, 0.0), (2e-8, 0.0), (0.0, -0.0), (2e-8, 2e-6)])
def test_rk4_with_the_derivative_written_out_equals_the_former_rk4_and_rhs(cv, cc):
    # 300 RK4 steps of a 4-wheel gyrostat (dt 0.2 s, tumbling 1-3 deg/s, wheels near 0 and at
    # speed, random motor and external torques), bytewise, with and without friction terms
    rng = np.random.default_rng(11)
    nw, n_steps, dt = 4, 300, 0.2
    J = np.diag([0.30, 0.27, 0.17]) + 0.01 * (lambda a: a + a.T)(rng.normal(size=(3, 3)))
    X = np.r_[_random_q(rng, 1)[0], np.radians(rng.uniform(-3, 3, 3)), 2.4e-5 * np.r_[0.0, 300.0, -150.0, 1e-3]]
    AX = rng.normal(size=(3, nw))
    AX /= np.linalg.norm(AX, axis=0)
    JW = np.full(nw, 2.4e-5)
    TM = rng.normal(scale=2e-3, size=(n_steps, nw))
    torque = rng.normal(scale=1e-6, size=(n_steps, 3))
    args = (J.ravel().copy(), np.linalg.inv(J).ravel().copy(), AX, TM, JW, cv, cc, torque, dt)
    outs = []
    for steps in (_STEPS_NEW, _STEPS_FORMER):
        out = np.empty((n_steps, 7 + nw))
        steps(X.copy(), *args, np.zeros(7 + nw), np.zeros(7 + nw), np.zeros(7 + nw), out)
        outs.append(out)
    assert outs[0].tobytes() == outs[1].tobytes()
    c1, c2 = np.empty((n_steps, 7 + nw)), np.empty((n_steps, 7 + nw))
    _steps_compiled(X.copy(), *args, np.zeros(7 + nw), np.zeros(7 + nw), np.zeros(7 + nw), c1, c2)
    assert c1.tobytes() == c2.tobytes()
    # compiled and Python agree to rounding only where libm's sqrt / the compiler differ: they don't
    assert c1.tobytes() == outs[0].tobytes()
    assert np.ptp(outs[0][:, 7]) > 0.0 and np.all(np.isfinite(outs[0]))
