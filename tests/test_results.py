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
