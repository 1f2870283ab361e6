"""adcskit._results: to_jsonable and the Result base (issue 20, item 2: serialisation at the
bottom layer).

The classes moved onto :class:`Result` had the hand-written
``{name: to_jsonable(getattr(self, name)) for name in self.__slots__}``; the base must give the
same dict in the same key order (a key-order change would reorder result.json).
"""

from __future__ import annotations

import dataclasses
import json
import pickle

import numpy as np
import pytest

from adcskit._results import Result, to_jsonable
from adcskit.determination.robust import RobustWahbaResult
from adcskit.determination.wahba import WahbaResult
from adcskit.estimation.mekf import MEKFResult
from adcskit.sensors.models import GyroMeasurement

RESULT_CLASSES = [WahbaResult, RobustWahbaResult, MEKFResult, GyroMeasurement]


def _hand_written_to_dict(obj):
    # the removed per-class method, verbatim
    return {name: to_jsonable(getattr(obj, name)) for name in obj.__slots__}


def _instance(cls, rng):
    values = {}
    for i, f in enumerate(dataclasses.fields(cls)):
        # a mix of every kind to_jsonable converts: arrays with a NaN, numpy scalars, text
        kind = i % 4
        if kind == 0:
            values[f.name] = np.append(rng.normal(size=11), np.nan).reshape(3, 4)
        elif kind == 1:
            values[f.name] = np.float64(rng.normal())
        elif kind == 2:
            values[f.name] = np.bool_(True)
        else:
            values[f.name] = f"text {i}"
    return cls(**values)


@pytest.mark.parametrize("cls", RESULT_CLASSES, ids=lambda c: c.__name__)
def test_base_to_dict_equals_the_hand_written_one(cls):
    obj = _instance(cls, np.random.default_rng(20))
    got, want = obj.to_dict(), _hand_written_to_dict(obj)
    assert list(got) == list(want) == [f.name for f in dataclasses.fields(cls)]
    assert json.dumps(got, allow_nan=False) == json.dumps(want, allow_nan=False)


@pytest.mark.parametrize("cls", RESULT_CLASSES, ids=lambda c: c.__name__)
def test_result_classes_keep_a_compact_repr_and_pickle(cls):
    obj = _instance(cls, np.random.default_rng(5))
    assert isinstance(obj, Result)
    text = repr(obj)
    assert text.startswith(f"{cls.__name__}(") and "shape=(3, 4)" in text
    assert len(text) < 80 * len(dataclasses.fields(cls))
    back = pickle.loads(pickle.dumps(obj))
    assert json.dumps(back.to_dict(), allow_nan=False) == json.dumps(obj.to_dict(), allow_nan=False)


def test_studies_base_still_re_exports_to_jsonable():
    from adcskit.studies._base import to_jsonable as old

    assert old is to_jsonable


# ----------------------------------------------------------------------------------------------
# issue 20 (leftovers): 36 more classes moved onto Result. Each removed to_dict wrote these keys,
# in this order, with values that to_jsonable turns into the same JSON (arrays via tolist,
# nested results via their to_dict). A byte-for-byte comparison with main e20e8e2 on 128
# synthetic and real instances (NaN, inf, numpy scalars, nested results) found no difference
# in json.dumps(to_jsonable(x)) nor in the pickles (campaign cache keys pickle the tasks).

def _moved():
    from adcskit.control.onoff import LoopParams, LoopSettings, OnOffMetrics, OnOffTrace
    from adcskit.control.tuning import (
        ParetoResult,
        RobustTuningResult,
        RobustTuningScale,
        TuningTimeEstimate,
    )
    from adcskit.dynamics.rigid_body import AttitudeTrajectory
    from adcskit.estimation.identification import IdentificationResult
    from adcskit.estimation.joint import AugmentedEKFResult, JointResult
    from adcskit.estimation.kalman import KalmanResult, LinearSimulation
    from adcskit.optimal_control.adaptive import ErrorCertificate
    from adcskit.optimal_control.analysis import BangBangResult, OptimalityCheck, ResimulationResult
    from adcskit.simulation.envelopes import Envelope
    from adcskit.simulation.signoff import SignOffTable
    from adcskit.studies._base import Check, Comparison
    from adcskit.thrusters.allocation import AllocationResult
    from adcskit.thrusters.geometry import Controllability, ThrusterSet
    from adcskit.thrusters.layout import LayoutResult, LayoutScore, MountingFace
    from adcskit.uncertainty.requirements import (
        PercentileBound,
        ProportionInterval,
        RequirementTable,
    )
    from adcskit.uncertainty.sampling import Fixed, Gaussian, SampleStats, TruncatedGaussian

    plain = [LoopSettings, LoopParams, OnOffMetrics, OnOffTrace, ParetoResult, RobustTuningResult,
             RobustTuningScale, TuningTimeEstimate, AttitudeTrajectory, IdentificationResult, JointResult,
             AugmentedEKFResult, KalmanResult, LinearSimulation, ErrorCertificate, BangBangResult,
             OptimalityCheck, Envelope, SignOffTable, Check, Comparison, AllocationResult, ThrusterSet,
             Controllability, MountingFace, PercentileBound, ProportionInterval, SampleStats]
    out = {c: ([f.name for f in dataclasses.fields(c)], []) for c in plain}
    out[ResimulationResult] = (["success", "message", "terminal_miss", "terminal_miss_scaled", "nfev"], [])
    out[LayoutScore] = (["fun", "error", "e_min", "sum_tp"], [])
    out[LayoutResult] = ([f.name for f in dataclasses.fields(LayoutResult) if f.name != "extra"], [])
    out[RequirementTable] = (["rows", "n_met", "n_not_met", "n_inconclusive", "success", "message"], [])
    out[Gaussian] = (["mean", "std"], [("kind", "gaussian")])
    out[TruncatedGaussian] = (["mean", "std", "low", "high"], [("kind", "truncated_gaussian")])
    out[Fixed] = (["value"], [("kind", "fixed")])
    return out


def _raw(cls, rng):
    # a field-by-field instance without validation: every kind to_jsonable converts
    obj = object.__new__(cls)
    for i, f in enumerate(dataclasses.fields(cls)):
        v = [np.append(rng.normal(size=5), [np.nan, -np.inf]).reshape(7, 1), np.float64(rng.normal()),
             np.bool_(i % 2), f"text {i}", None, float("inf"), (np.int64(i), np.nan)][i % 7]
        object.__setattr__(obj, f.name, v)
    return obj


def test_moved_classes_keep_their_keys_and_json():
    moved = _moved()
    assert len(moved) + 1 == 36  # + Requirement below
    rng = np.random.default_rng(36)
    for cls, (keys, tag) in moved.items():
        obj = _raw(cls, rng)
        want = dict(tag) | {k: to_jsonable(getattr(obj, k)) for k in keys}
        got = obj.to_dict()
        assert isinstance(obj, Result) and list(got) == list(want), cls.__name__
        assert json.dumps(got, allow_nan=False) == json.dumps(want, allow_nan=False), cls.__name__


def test_requirement_appends_its_text_and_nests_in_its_verdicts():
    from adcskit.uncertainty import Requirement, check_requirements

    req = Requirement(metric="pointing_max_deg", statistic="percentile", percentile=99.0, comparison="<=",
                      threshold=0.5)
    d = req.to_dict()
    assert list(d) == [f.name for f in dataclasses.fields(Requirement)] + ["text"] and d["text"] == req.text
    table = check_requirements(["x max <= 1"], {"x": [0.1, np.nan]}, nan_policy="fail")
    row = table.to_dict()["rows"][0]
    assert row["spec"] == to_jsonable(table.rows[0].requirement) and row["bound"] is None  # inf -> null
