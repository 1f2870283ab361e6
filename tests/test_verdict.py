"""The verdict model (issue 11 §1): four outcomes decided over seeds and readings."""

from __future__ import annotations

import json

import pytest
from hypothesis import given
from hypothesis import strategies as st

from adcskit.studies import Claim, ClaimSpec, Finding, FindingSpec, StudyResult, decide
from adcskit.studies._verdict import (
    DEPENDS_ON_READING,
    OUTCOMES,
    combine_readings,
    mean_interval,
    tally,
)


def test_unanimous_seeds_hold():
    r = decide([True] * 5)
    assert r.outcome == "holds" and r.n_seeds == 5 and r.fraction_held == 1.0
    assert r.interval[0] > 0.5  # Wilson 95 % interval of 5/5 is [0.566, 1]


def test_single_seed_stochastic_is_inconclusive():
    assert decide([True]).outcome == "inconclusive"
    assert decide([True], stochastic=False).outcome == "holds"


def test_disagreeing_seeds_inconclusive():
    assert decide([True, False, True, True, True]).outcome == "inconclusive"


def test_straddling_interval_inconclusive():
    # every seed is above 1, but the t interval of the mean reaches below it
    r = decide(values=[1.01, 1.5, 1.02], threshold=1.0)
    assert r.fraction_held == 1.0
    assert r.interval[0] < 1.0 < r.interval[1]
    assert r.outcome == "inconclusive"


def test_clear_interval_decides_both_ways():
    assert decide(values=[5.0, 5.2, 4.9, 5.1, 5.0], threshold=1.0).outcome == "holds"
    assert decide(values=[5.0, 5.2, 4.9, 5.1, 5.0], threshold=1.0, better="below").outcome == "does not hold"


def test_nonfinite_value_does_not_support():
    assert decide(values=[float("nan"), 2.0], threshold=1.0).outcome == "inconclusive"


def test_disagreeing_readings_depend_on_reading():
    spec = ClaimSpec(
        id="c", statement="s", where="Table 1", quantity="ratio", value=lambda m: m["r"], threshold=100.0,
        readings=("variance", "slope"),
    )
    runs = {
        "default": [{"r": 216.0}] * 5,
        "variance": [{"r": 216.0 + i} for i in range(5)],
        "slope": [{"r": 14.0 + i} for i in range(5)],
    }
    c = spec.evaluate(runs)
    assert c.outcome == DEPENDS_ON_READING
    assert [r.outcome for r in c.readings] == ["holds", "holds", "does not hold"]
    d = c.to_dict()
    assert d["readings"][2] == {**d["readings"][2], "reading": "slope", "outcome": "does not hold"}
    json.dumps(d)


def test_spec_without_readings_has_empty_list():
    spec = ClaimSpec(id="c", statement="s", where="Fig. 2", quantity="q", held=lambda m: m["ok"])
    c = spec.evaluate({"default": [{"ok": True}] * 5})
    assert c.outcome == "holds" and c.readings == () and c.to_dict()["readings"] == []


def test_missing_reading_is_an_error():
    spec = ClaimSpec(id="c", statement="s", where="", quantity="q", held=lambda m: True, readings=("a",))
    with pytest.raises(ValueError, match="no runs for readings"):
        spec.evaluate({"default": [{}]})


def test_finding_spec_gives_finding_and_result_lists_apart():
    f = FindingSpec(id="f", statement="ours beats baseline", quantity="q", held=lambda m: True).evaluate({"default": [{}] * 5})
    assert isinstance(f, Finding)
    c = Claim(id="c", statement="paper", where="Sec. 4", outcome="does not hold", n_seeds=5, fraction_held=0.0)
    d = StudyResult(study="x", claims=(c,), findings=(f,)).to_dict()
    assert [x["id"] for x in d["claims"]] == ["c"]
    assert [x["id"] for x in d["findings"]] == ["f"]
    for key in ("id", "statement", "where", "outcome", "n_seeds", "fraction_held", "interval", "readings"):
        assert key in d["claims"][0]


def test_claim_rejects_unknown_outcome():
    with pytest.raises(ValueError, match="outcome"):
        Claim(id="c", statement="s", outcome="held")


@given(st.lists(st.booleans(), min_size=1, max_size=12))
def test_outcome_is_one_of_four_and_consistent(held):
    r = decide(held)
    assert r.outcome in OUTCOMES
    if r.outcome == "holds":
        assert all(held) and len(held) >= 2
    if r.outcome == "does not hold":
        assert not any(held) and len(held) >= 2


def test_combine_and_tally():
    assert combine_readings([decide([True] * 5), decide([True] * 5)]) == "holds"
    assert tally(["holds", "not comparable"])["not comparable"] == 1
    lo, hi = mean_interval([2.0])
    assert lo == hi == 2.0
