"""The quaternion device helpers (adcskit.attitude._device) shared by the closed-loop
simulator and the MEKF kernels: against the public attitude algebra and scipy."""

import math

import numba
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from adcskit.attitude import error_angle, quat_to_dcm
from adcskit.attitude._device import compose_rotvec, qdiff, qdot, qerr, rotate, unit_q4_pos

_unit = st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4).filter(lambda v: np.linalg.norm(v) > 0.1)
_vec = st.lists(st.floats(-10.0, 10.0), min_size=3, max_size=3)


@settings(max_examples=40, deadline=None)
@given(_unit, _vec)
def test_rotate_is_the_attitude_matrix(q, r):
    # A(q) r with A(q) of Markley & Crassidis (2014) eq. 2.125 (adcskit.attitude.quat_to_dcm);
    # two implementations, rounding-level agreement relative to |r|
    q = np.asarray(q) / np.linalg.norm(q)
    np.testing.assert_allclose(rotate(*q, *r), quat_to_dcm(q) @ np.asarray(r), rtol=0,
                               atol=1e-13 * (1.0 + np.linalg.norm(r)))


@settings(max_examples=40, deadline=None)
@given(_unit, _unit)
def test_qerr_angle_is_error_angle(a, b):
    # the error angle of q_a (x) q_b^-1 (adcskit.attitude.error_angle, 2 atan2 form): 1e-12 rad
    a = np.asarray(a) / np.linalg.norm(a)
    b = np.asarray(b) / np.linalg.norm(b)
    ex, ey, ez, ang = qerr(*a, *b)
    assert abs(ang - error_angle(a, b)) < 1e-12
    assert abs(np.linalg.norm([ex, ey, ez]) - ang) < 1e-12


@settings(max_examples=40, deadline=None)
@given(_unit, st.lists(st.floats(-1.5, 1.5), min_size=3, max_size=3))
def test_compose_rotvec_then_qerr_round_trip(q, rv):
    # dq(r) (x) q then the error rotation vector of the result against q gives r back
    # (|r| < pi); and A(dq (x) q) = A(dq) A(q) with A(dq) = scipy's from_rotvec(r).inv() (the
    # scalar-last convention of design.md). Tolerances: rounding of a few products, 1e-12.
    q = np.asarray(q) / np.linalg.norm(q)
    q = q if q[3] >= 0 else -q
    p = q.copy()
    compose_rotvec(p, *rv)
    np.testing.assert_allclose(qerr(*p, *q)[:3], rv, rtol=0, atol=1e-12)
    np.testing.assert_allclose(quat_to_dcm(p), Rotation.from_rotvec(rv).inv().as_matrix() @ quat_to_dcm(q),
                               rtol=0, atol=1e-12)


def test_same_bits_compiled_and_in_python():
    # one source, two targets: compiled into an njit caller, the helpers return the
    # plain-Python numbers bit for bit
    @numba.njit(cache=False)
    def compiled(q, r):
        p = q.copy()
        compose_rotvec(p, r[0], r[1], r[2])
        return rotate(q[0], q[1], q[2], q[3], r[0], r[1], r[2]), qerr(p[0], p[1], p[2], p[3], q[0], q[1], q[2], q[3]), p

    rng = np.random.default_rng(5)
    for _ in range(20):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        r = rng.normal(size=3)
        p = q.copy()
        compose_rotvec(p, *r)
        b, e, pc = compiled(q, r)
        assert b == rotate(*q, *r) and e == qerr(*p, *q)
        assert np.array_equal(pc, p)


def _former_mekf_error_rotvec(qa, qb, out, off):
    # estimation/_mekf_kernels._error_rotvec before it called qerr (main e20e8e2), verbatim
    na = qa[0] * qa[0] + qa[1] * qa[1] + qa[2] * qa[2] + qa[3] * qa[3]
    nb = qb[0] * qb[0] + qb[1] * qb[1] + qb[2] * qb[2] + qb[3] * qb[3]
    if not (na > 0.0 and nb > 0.0 and math.isfinite(na) and math.isfinite(nb)):
        return False
    a0, a1, a2, a3 = qa[0], qa[1], qa[2], qa[3]
    c0, c1, c2, c3 = -qb[0], -qb[1], -qb[2], qb[3]
    d0 = a3 * c0 + c3 * a0 - (a1 * c2 - a2 * c1)
    d1 = a3 * c1 + c3 * a1 - (a2 * c0 - a0 * c2)
    d2 = a3 * c2 + c3 * a2 - (a0 * c1 - a1 * c0)
    d3 = a3 * c3 - (a0 * c0 + a1 * c1 + a2 * c2)
    if d3 < 0.0:
        d0, d1, d2, d3 = -d0, -d1, -d2, -d3
    ev = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    if ev == 0.0:
        f = 2.0 / d3
    else:
        f = 2.0 * math.atan2(ev, d3) / ev
    out[off] = f * d0
    out[off + 1] = f * d1
    out[off + 2] = f * d2
    return True


def test_mekf_error_rotvec_is_qerr_bit_for_bit():
    # issue 20: the MEKF's error rotation vector now calls qerr (one source with the simulator);
    # it must return the former copy's bits, in Python and compiled, on random unit and
    # unnormalised quaternions, equal and opposite pairs (zero vector part, both signs of q4)
    # and the rejected inputs (zero, NaN, inf)
    from adcskit.estimation._mekf_kernels import _error_rotvec

    rng = np.random.default_rng(20)
    qa = rng.normal(size=(400, 4)) * rng.choice([1.0, 1e-3, 1e3], size=(400, 1))
    qb = rng.normal(size=(400, 4))
    qb[:50] = qa[:50]
    qb[50:100] = -qa[50:100] * 2.0
    qa[100:105] = [0.0, 0.0, 0.0, 1.0]
    qb[100:105] = [0.0, 0.0, 0.0, -1.0]
    qa[105:110] = [-0.0, 0.0, -0.0, 1.0]
    qa[110] = 0.0
    qb[111] = np.nan
    qa[112] = np.inf
    new_py, old_py = np.full((400, 3), 7.0), np.full((400, 3), 7.0)
    ok_new = [_error_rotvec(qa[i], qb[i], new_py[i], 0) for i in range(400)]
    ok_old = [_former_mekf_error_rotvec(qa[i], qb[i], old_py[i], 0) for i in range(400)]
    assert ok_new == ok_old and sum(ok_new) == 397

    def batch(fn):
        @numba.njit(cache=False)
        def run(qa, qb, out):
            ok = np.zeros(qa.shape[0], dtype=np.bool_)
            for i in range(qa.shape[0]):
                ok[i] = fn(qa[i], qb[i], out[i], 0)
            return ok
        return run

    new_c, old_c = np.full((400, 3), 7.0), np.full((400, 3), 7.0)
    assert batch(_error_rotvec)(qa, qb, new_c).tolist() == ok_new
    batch(numba.extending.register_jitable(_former_mekf_error_rotvec))(qa, qb, old_c)
    for a, b in ((new_py, old_py), (new_c, old_c), (new_c, new_py)):
        assert a.tobytes() == b.tobytes()  # same bits, signed zeros included


def test_simulation_qmul_is_the_attitude_product_with_sign():
    # issue 20: simulation.core._qmul now calls attitude._kernels.quat_multiply; its former
    # NumPy copy (main e20e8e2), verbatim, gives the same bits on random, batched and broadcast
    # inputs
    from adcskit.simulation.core import _qmul

    def former(p, q):
        pv, p4 = p[..., :3], p[..., 3:]
        qv, q4 = q[..., :3], q[..., 3:]
        v = p4 * qv + q4 * pv - np.cross(pv, qv)
        s = p4 * q4 - np.sum(pv * qv, axis=-1, keepdims=True)
        out = np.concatenate([v, s], axis=-1)
        return out * np.where(out[..., 3:] < 0, -1.0, 1.0)

    rng = np.random.default_rng(21)
    p, q = rng.normal(size=(200, 4)), rng.normal(size=(200, 4))
    for a, b in ((p, q), (p[0], q), (p, q[0]), (p[3], q[4] * np.array([-1, -1, -1, 1.0]))):
        assert _qmul(a, b).tobytes() == former(a, b).tobytes()


def _former_qerr(a0, a1, a2, a3, b0, b1, b2, b3):
    # attitude._device.qerr before qdiff was split out (main e20e8e2), verbatim
    c0, c1, c2, c3 = -b0, -b1, -b2, b3
    d0 = a3 * c0 + c3 * a0 - (a1 * c2 - a2 * c1)
    d1 = a3 * c1 + c3 * a1 - (a2 * c0 - a0 * c2)
    d2 = a3 * c2 + c3 * a2 - (a0 * c1 - a1 * c0)
    d3 = a3 * c3 - (a0 * c0 + a1 * c1 + a2 * c2)
    if d3 < 0.0:
        d0, d1, d2, d3 = -d0, -d1, -d2, -d3
    ev = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    ang = 2.0 * math.atan2(ev, d3)
    if ev > 0.0:
        f = ang / ev
    else:
        f = 2.0
    return f * d0, f * d1, f * d2, ang


def _former_compose_rotvec(q, r0, r1, r2):
    # attitude._device.compose_rotvec before unit_q4_pos was split out (main e20e8e2), verbatim
    ang = math.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
    h = 0.5 * ang
    if h < 1e-4:
        s = 0.5 * (1.0 - h * h / 6.0)
    else:
        s = 0.5 * math.sin(h) / h
    p0 = s * r0
    p1 = s * r1
    p2 = s * r2
    p3 = math.cos(h)
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    n0 = p3 * q0 + q3 * p0 - (p1 * q2 - p2 * q1)
    n1 = p3 * q1 + q3 * p1 - (p2 * q0 - p0 * q2)
    n2 = p3 * q2 + q3 * p2 - (p0 * q1 - p1 * q0)
    n3 = p3 * q3 - (p0 * q0 + p1 * q1 + p2 * q2)
    nrm = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2 + n3 * n3)
    if n3 < 0.0:
        nrm = -nrm
    q[0] = n0 / nrm
    q[1] = n1 / nrm
    q[2] = n2 / nrm
    q[3] = n3 / nrm


def _qerr_compose_batch(qerr_fn, compose_fn):
    @numba.njit(cache=False)
    def run(qa, qb, rv, e, qc):
        for i in range(qa.shape[0]):
            e[i, 0], e[i, 1], e[i, 2], e[i, 3] = qerr_fn(qa[i, 0], qa[i, 1], qa[i, 2], qa[i, 3],
                                                         qb[i, 0], qb[i, 1], qb[i, 2], qb[i, 3])
            compose_fn(qc[i], rv[i, 0], rv[i, 1], rv[i, 2])
    return run


def test_qerr_and_compose_rotvec_keep_their_bits():
    # issue 20: qerr now calls qdiff and compose_rotvec calls unit_q4_pos (helpers that the
    # wheel and thruster kernels can share); the former bodies, verbatim, give the same bits in
    # Python and compiled, on random, equal, opposite and small-angle inputs
    rng = np.random.default_rng(22)
    n = 300
    qa, qb = rng.normal(size=(n, 4)), rng.normal(size=(n, 4))
    qb[:30], qb[30:60] = qa[:30], -qa[30:60]
    rv = rng.normal(size=(n, 3)) * rng.choice([1e-9, 1e-5, 1.0, 3.0], size=(n, 1))
    outs = []
    for qerr_fn, compose_fn in ((qerr, compose_rotvec), (_former_qerr, _former_compose_rotvec)):
        e, qc = np.empty((n, 4)), qa.copy()
        for i in range(n):
            e[i] = qerr_fn(*qa[i], *qb[i])
            compose_fn(qc[i], *rv[i])
        ec, qcc = np.empty((n, 4)), qa.copy()
        jit = numba.extending.register_jitable
        _qerr_compose_batch(jit(qerr_fn), jit(compose_fn))(qa, qb, rv, ec, qcc)
        outs.append((e.tobytes(), qc.tobytes(), ec.tobytes(), qcc.tobytes()))
    assert outs[0] == outs[1]


def _former_kernel_pieces(q0, q1, q2, q3, w0, w1, w2, r0, r1, r2, r3):
    # the kernels' own copies before they called the shared helpers (main bc6d017, verbatim):
    # simulation._kernels._rhs's kinematics (= _wheel_kernels.rhs's, now written out in rk4), rk4_step's
    # renormalisation (= _wheel_kernels.rk4's), _wheel_kernels.qdiff, _kernels._outside's
    # squared vector part and squared scalar part of q (x) r^-1
    dq = (0.5 * (q3 * w0 - (w1 * q2 - w2 * q1)),
          0.5 * (q3 * w1 - (w2 * q0 - w0 * q2)),
          0.5 * (q3 * w2 - (w0 * q1 - w1 * q0)),
          -0.5 * (w0 * q0 + w1 * q1 + w2 * q2))
    nrm = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    if q3 < 0.0:
        nrm = -nrm
    un = (q0 / nrm, q1 / nrm, q2 / nrm, q3 / nrm)
    c0, c1, c2, c3 = -r0, -r1, -r2, r3
    d0 = q3 * c0 + c3 * q0 - (q1 * c2 - q2 * c1)
    d1 = q3 * c1 + c3 * q1 - (q2 * c0 - q0 * c2)
    d2 = q3 * c2 + c3 * q2 - (q0 * c1 - q1 * c0)
    d3 = q3 * c3 - (q0 * c0 + q1 * c1 + q2 * c2)
    dd = (-d0, -d1, -d2, -d3) if d3 < 0.0 else (d0, d1, d2, d3)
    e0 = q3 * -r0 + r3 * q0 - (q1 * -r2 - q2 * -r1)
    e1 = q3 * -r1 + r3 * q1 - (q2 * -r0 - q0 * -r2)
    e2 = q3 * -r2 + r3 * q2 - (q0 * -r1 - q1 * -r0)
    e3 = q3 * r3 - (q0 * -r0 + q1 * -r1 + q2 * -r2)
    return dq + un + dd + (e0 * e0 + e1 * e1 + e2 * e2, e3 * e3)


def _shared_kernel_pieces(q0, q1, q2, q3, w0, w1, w2, r0, r1, r2, r3):
    # the same pieces from the shared helpers, as the kernels now compute them
    d0, d1, d2, d3 = qdiff(q0, q1, q2, q3, r0, r1, r2, r3)
    return (qdot(q0, q1, q2, q3, w0, w1, w2) + unit_q4_pos(q0, q1, q2, q3) + (d0, d1, d2, d3)
            + (d0 * d0 + d1 * d1 + d2 * d2, d3 * d3))


def test_kernels_former_quaternion_copies_equal_the_shared_helpers_bit_for_bit():
    # issue 20 item 4: _kernels (_rhs, rk4_step, _outside) and _wheel_kernels (rhs, rk4, qdiff)
    # now call qdot, unit_q4_pos and qdiff; their former copies give the same bits, in Python
    # and compiled into one njit caller (no fused multiply-add on the CPU), on random inputs
    # including equal and opposite quaternions and negative scalar parts
    from adcskit.simulation import _kernels, _wheel_kernels

    assert _wheel_kernels.qdiff is qdiff and _kernels.qdot is qdot and _wheel_kernels.unit_q4_pos is unit_q4_pos
    rng = np.random.default_rng(24)
    q, w, r = rng.normal(size=(200, 4)), rng.normal(size=(200, 3)), rng.normal(size=(200, 4))
    r[:20], r[20:40] = q[:20], -q[20:40]
    x = np.hstack([q, w, r])
    jit = numba.extending.register_jitable

    def batch(fn):
        f = jit(fn)

        @numba.njit(cache=False)
        def run(x, out):
            for i in range(x.shape[0]):
                v = f(x[i, 0], x[i, 1], x[i, 2], x[i, 3], x[i, 4], x[i, 5], x[i, 6], x[i, 7], x[i, 8], x[i, 9],
                      x[i, 10])
                for m in range(14):
                    out[i, m] = v[m]
        out = np.empty((x.shape[0], 14))
        run(x, out)
        return out

    former = np.array([_former_kernel_pieces(*row) for row in x])
    shared = np.array([_shared_kernel_pieces(*row) for row in x])
    assert former.tobytes() == shared.tobytes()
    assert batch(_former_kernel_pieces).tobytes() == batch(_shared_kernel_pieces).tobytes() == former.tobytes()
