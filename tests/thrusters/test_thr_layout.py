"""Layout design: mounting faces as data, S3 eq. 18, pymoo GA / DE."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adcskit.errors import InputError
from adcskit.thrusters import (
    box_faces,
    check_controllability,
    decode_layout,
    design_layout,
    score_layout,
)
from adcskit.thrusters.layout import _decode, _face_table

# a small manoeuvre: 0.5 deg corrections about the body axes with K = 600 N m/rad (S3 Table 6)
DEMANDS = 600 * np.deg2rad(0.5) * np.vstack([np.eye(3), -np.eye(3)])


def _check_faces(ts, faces):
    by_name = {f.name: f for f in faces}
    for p, d, name in zip(ts.positions, ts.directions, ts.names):
        f = by_name[name]
        rel = p - f.centre
        assert abs(rel @ f.normal) < 1e-12  # on the face plane
        assert abs(rel @ f.axis_u) <= f.half_u + 1e-12 and abs(rel @ f.axis_v) <= f.half_v + 1e-12
        # thrust leaves the face: force into the body, within the face's cant limit
        assert d @ f.normal <= 1e-12
        assert math.acos(np.clip(-d @ f.normal, -1, 1)) <= f.max_cant + 1e-9


def test_decoded_random_genes_respect_faces():
    faces = box_faces(max_cant={"+Z": 0.3, "-Z": 1.0})
    rng = np.random.default_rng(0)
    n = 10
    lo = np.tile([0, -1, -1, 0, 0], n)
    hi = np.tile([len(faces) - 1e-9, 1, 1, 1, 2 * np.pi], n)
    for g in rng.uniform(lo, hi, size=(20, 5 * n)):
        _check_faces(decode_layout(g, faces), faces)


@pytest.mark.parametrize("algorithm", ["de", "ga"])
def test_designed_layout_respects_restricted_faces(algorithm):
    # forbid the +-Y faces (solar arrays of a GEO satellite) and limit the cant on +-X to 45 deg
    faces = box_faces(names=("+X", "-X", "+Z", "-Z"), max_cant={"+X": math.pi / 4, "-X": math.pi / 4})
    res = design_layout(6, DEMANDS, mounting=faces, algorithm=algorithm, pop_size=20, n_gen=15, rng=1)
    assert set(res.thrusters.names) <= {"+X", "-X", "+Z", "-Z"}
    _check_faces(res.thrusters, faces)
    # terms reported separately and recombined by eq. 18 with S3 Table 7 weights
    assert res.fun == pytest.approx(100 * res.error - 99 * res.e_min + 12 * res.sum_tp, rel=1e-12)
    assert res.nfev == 20 * 15 and res.nit == 15
    assert np.all(np.diff(res.history) <= 0)


def test_design_is_reproducible_and_improves():
    a = design_layout(6, DEMANDS, algorithm="de", pop_size=20, n_gen=30, rng=7)
    b = design_layout(6, DEMANDS, algorithm="de", pop_size=20, n_gen=30, rng=7)
    np.testing.assert_array_equal(a.x, b.x)
    assert a.history[-1] < a.history[0]
    c = design_layout(6, DEMANDS, algorithm="de", de_strategy="rand/1/bin", pop_size=20, n_gen=30, rng=7)
    assert np.isfinite(c.fun)


def test_score_matches_decode_and_batch():
    faces = box_faces()
    rng = np.random.default_rng(4)
    n = 6
    lo = np.tile([0, -1, -1, 0, 0], n)
    hi = np.tile([6 - 1e-9, 1, 1, 1, 2 * np.pi], n)
    X = rng.uniform(lo, hi, size=(5, 5 * n))
    pos, d, _ = _decode(X, _face_table(faces))
    A = np.swapaxes(np.cross(pos, d), -1, -2)
    batch = score_layout(A, DEMANDS)
    for i in range(5):
        one = score_layout(decode_layout(X[i], faces).torque_matrix(), DEMANDS)
        assert one.fun == pytest.approx(batch.fun[i], rel=1e-12)


def test_reference_layout_score_by_hand():
    # A_REF meets every axis demand exactly: error 0. Per demand of 5.236 N m the pair with
    # lever 1 (Y) fires 5.236 N, the X/Z demands use two sqrt(2)-thrusters of 2.618 N each:
    # sum_tp = (4 * 5.236 + 2 * 5.236) * 0.2 / 10 / 6 = 0.10472 s; e_min = sqrt(2) * 2.5e-4
    A_REF = np.array([[-1, 1, -1, 1, 0, 0], [0, 0, 0, 0, 1, -1], [-1, 1, 1, -1, 0, 0]], float)
    s = score_layout(A_REF, DEMANDS)
    assert s.error == pytest.approx(0.0, abs=1e-12)
    assert s.sum_tp == pytest.approx(0.2 * 600 * np.deg2rad(0.5) / 10, rel=1e-12)
    assert s.e_min == pytest.approx(np.sqrt(2) * 2.5e-4, rel=1e-12)
    assert check_controllability(A_REF).success


def test_bad_arguments():
    with pytest.raises(InputError, match="'de', 'ga'|'ga', 'de'"):
        design_layout(4, DEMANDS, algorithm="pso")
    with pytest.raises(InputError, match="face name"):
        box_faces(names=("+W",))
    with pytest.raises(InputError, match="max_cant"):
        box_faces(max_cant=2.0)
    with pytest.raises(InputError, match="demands"):
        design_layout(4, np.ones((3, 2)))


# ----------------------------------------------------------------------------- paired reading (S3 §4-1)


def test_paired_design_is_couples():
    # S3 §4-1: "thrusters on parallel faces act as a pair" -> each gene is a couple
    # (p, d) + (-p, -d): torque 2 p x d, zero net force, impulse bit 2 Delta F_max t_min
    r = design_layout(6, DEMANDS, paired=True, pop_size=10, n_gen=5, rng=4)
    ts = r.thrusters
    assert ts.positions.shape == (6, 3)
    np.testing.assert_allclose(ts.positions[3:], -ts.positions[:3], atol=1e-15)
    np.testing.assert_allclose(ts.directions[3:], -ts.directions[:3], atol=1e-15)
    np.testing.assert_allclose(ts.force_matrix().sum(axis=1), 0.0, atol=1e-12)
    A = r.torque_matrix
    np.testing.assert_allclose(A[:, 3:], A[:, :3], atol=1e-12)  # twins give the same torque
    C = r.extra["couple_matrix"]
    np.testing.assert_allclose(C, 2 * A[:, :3], atol=1e-12)
    opposite = {"+X": "-X", "-X": "+X", "+Y": "-Y", "-Y": "+Y", "+Z": "-Z", "-Z": "+Z"}
    assert [opposite[n] for n in ts.names[:3]] == list(ts.names[3:])
    # e_min of a couple: 2 |p x d| F_max t_min / (t_s K) (S3 eq. 10 with the pair's impulse bit)
    lever = np.linalg.norm(A[:, :3], axis=0)
    assert r.e_min == pytest.approx(2 * lever.max() * 10.0 * 3e-3 / (0.2 * 600.0), rel=1e-12)
    # the reported score is S3 eq. 18 with both members' on-times
    sc = score_layout(C, DEMANDS)
    assert r.sum_tp == pytest.approx(2 * sc.sum_tp, rel=1e-12)
    assert r.error == pytest.approx(sc.error, abs=1e-12)


def test_paired_design_rejects_bad_input():
    with pytest.raises(InputError, match="even"):
        design_layout(5, DEMANDS, paired=True, pop_size=8, n_gen=1, rng=0)
    with pytest.raises(InputError, match="parallel face"):
        design_layout(4, DEMANDS, paired=True, mounting=box_faces(names=("+X", "-X", "+Y")), pop_size=8,
                      n_gen=1, rng=0)
    with pytest.raises(InputError, match="paired"):
        design_layout(4, DEMANDS, paired="yes", pop_size=8, n_gen=1, rng=0)
