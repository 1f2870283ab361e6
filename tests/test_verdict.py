"""The verdict model (issue 11 §1): four outcomes decided over seeds and readings."""

from __future__ import annotations

import json
import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from adcskit.errors import InputError
from adcskit.studies import Claim, ClaimSpec, Finding, FindingSpec, StudyResult, decide
from adcskit.studies._verdict import (
    DEPENDS_ON_READING,
    OUTCOMES,
    Premise,
    Reading,
    combine_readings,
    mean_interval,
    sign_test_p,
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


def test_interval_is_the_sign_tests_and_agrees_with_the_outcome():
    # issue 45: the interval shown is what decides (exact bounds of the median), never an
    # interval above the bar beside "inconclusive" or one straddling it beside "holds"
    r = decide(values=[1.01, 1.5, 1.02, 1.03, 1.2], threshold=1.0)
    assert r.outcome == "holds" and r.interval == (1.01, 1.5)
    r = decide(values=[0.99, 1.5, 1.02, 1.03, 1.2], threshold=1.0)
    assert r.outcome == "inconclusive" and r.interval[0] < 1.0 < r.interval[1]
    assert "sign test p = 0.188" in r.detail  # 4 of 5: P(X >= 4 | n=5, 1/2) = 6/32


def test_sign_test_decides_counts_and_skewed_ratios():
    # issue 45: model-estimation online-beats-offline-1dof (low noise) had 10/10 seeds against
    # by 80-2927x and read inconclusive (t-interval of the raw mean); the sign test says does not hold
    low_noise = [630.75, 103.39, 96.45, 2142.44, 87.37, 154.45, 160.99, 80.34, 687.55, 2926.86]
    assert decide(values=low_noise, threshold=1.0, better="below").outcome == "does not hold"
    # onoff-tuning robust-mean-higher-typically: 3, 3, 3, 5, 3 of 5 cases (majority: > 2.5) held
    # only while no seed was "too good"; every seed supports it, so it holds
    assert decide(values=[3, 3, 3, 5, 3], threshold=2.5).outcome == "holds"
    assert decide(values=[3, 3, 3, 3, 3], threshold=2.5).outcome == "holds"
    # 9 of 10 seeds: exact one-sided p = 11/1024 = 0.0107 <= 0.05 (8 of 10: 0.0547, not decided)
    assert decide([True] * 9 + [False]).outcome == "holds"
    assert decide([True] * 8 + [False] * 2).outcome == "inconclusive"
    assert decide([False] * 9 + [True]).outcome == "does not hold"
    assert sign_test_p(5, 5) == 1 / 32


def test_log_scale_margin_is_relative():
    # timing ratios vs a 300x bar with a declared factor-1.5 margin: 250-450 is a tie
    vals = [380.0, 520.0, 610.0, 450.0, 700.0]
    assert decide(values=vals, threshold=300.0, scale="log", margin=math.log(1.5)).outcome == "inconclusive"
    assert decide(values=[v * 2 for v in vals], threshold=300.0, scale="log", margin=math.log(1.5)).outcome == "holds"
    assert decide(values=[30.0] * 5, threshold=300.0, scale="log", margin=math.log(1.5)).outcome == "does not hold"
    r = decide(values=[2.0, -1.0, 3.0, 2.0, 2.0], threshold=1.0, scale="log")
    assert r.outcome == "inconclusive" and "1/5 seeds failed" in r.detail
    with pytest.raises(InputError, match="positive threshold"):
        decide(values=[1.0], threshold=0.0, scale="log")


def test_a_reading_can_declare_its_own_margin():
    spec = ClaimSpec(id="fuel", statement="s", where="w", quantity="q", value=lambda m: m, threshold=1.0,
                     better="below", scale="log", readings=("fixed",), margin=0.05, reading_margins={"fixed": 0.0},
                     margin_reason="sampling error of random directions; fixed demands: none")
    c = spec.evaluate({"default": [0.98, 0.8, 0.8, 0.8, 0.8], "fixed": [0.98, 0.8, 0.8, 0.8, 0.8]})
    assert [r.outcome for r in c.readings] == ["inconclusive", "holds"]  # 0.98 ties only within 0.05
    with pytest.raises(ValueError, match="reading_margins"):
        ClaimSpec(id="c", statement="s", where="w", quantity="q", value=lambda m: m, threshold=1.0,
                  reading_margins={"x": -1.0})


def test_premise_failure_makes_the_reading_inconclusive_with_the_reason():
    torque = Premise(name="equal torque", holds=lambda m: m["missed"] == 0,
                     why=lambda m: f"{m['missed']} of 200 demands missed", readings=("pinv",))
    spec = ClaimSpec(id="fuel", statement="s", where="Fig. 5", quantity="fuel ratio", value=lambda m: m["r"],
                     threshold=1.0, better="below", readings=("pinv", "lp"), premises=(torque,))
    good = [{"r": 0.8, "missed": 0}] * 5
    bad = [{"r": 0.8, "missed": 0}] * 4 + [{"r": 0.8, "missed": 27}]
    c = spec.evaluate({"default": good, "pinv": bad, "lp": good})
    outs = {r.reading: r for r in c.readings}
    assert outs["pinv"].outcome == "inconclusive" and outs["lp"].outcome == "holds"
    assert outs["pinv"].premise_failures == ("seed 4: equal torque fails (27 of 200 demands missed)",)
    assert c.outcome == "inconclusive" and "premise failed on 1 seeds" in c.detail
    assert c.to_dict()["readings"][1]["premise_failures"] == list(outs["pinv"].premise_failures)
    with pytest.raises(InputError, match="Premise objects"):
        ClaimSpec(id="c", statement="s", where="w", quantity="q", held=lambda m: True, premises=(lambda m: True,))


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
        assert len(held) >= 2 and (all(held) or sign_test_p(sum(held), len(held)) <= 0.05)
    if r.outcome == "does not hold":
        assert len(held) >= 2 and (not any(held) or sign_test_p(len(held) - sum(held), len(held)) <= 0.05)


def test_combine_and_tally():
    assert combine_readings([decide([True] * 5), decide([True] * 5)]) == "holds"
    assert tally(["holds", "not comparable"])["not comparable"] == 1
    lo, hi = mean_interval([2.0])
    assert lo == hi == 2.0


# ---- issue 21: a symmetric rule that states its evidence -------------------------------


def _r(outcome: str) -> Reading:
    return Reading(reading=outcome, outcome=outcome, n_seeds=5, fraction_held=1.0, interval=(0.0, 1.0))


@pytest.mark.parametrize(
    ("outcomes", "expected"),
    [
        (["holds", "holds"], "holds"),
        (["does not hold", "does not hold"], "does not hold"),
        (["holds", "does not hold"], "depends on reading"),
        (["holds", "does not hold", "inconclusive"], "depends on reading"),
        # no reading holds: never "depends on reading" (was: S1 standard-37-195)
        (["does not hold", "inconclusive"], "inconclusive"),
        # a decided outcome beside inconclusive readings is not rescued either
        (["holds", "inconclusive"], "inconclusive"),
        (["inconclusive", "inconclusive"], "inconclusive"),
    ],
)
def test_combine_readings_is_symmetric(outcomes, expected):
    assert combine_readings([_r(o) for o in outcomes]) == expected


def test_fewer_than_five_seeds_is_indicative_and_never_comparable():
    spec = ClaimSpec(id="c", statement="s", where="w", quantity="q", held=lambda m: m)
    two = spec.evaluate({"default": [True, True]})
    assert two.outcome == "holds" and two.indicative and "indicative" in two.detail
    assert two.display_outcome == "indicative (2 seeds)"
    five = spec.evaluate({"default": [True] * 5})
    assert not five.indicative and five.display_outcome == "holds"
    # a deterministic claim is never indicative: one run decides it
    det = ClaimSpec(id="d", statement="s", where="w", quantity="q", held=lambda m: m, stochastic=False)
    assert not det.evaluate({"default": [True]}).indicative


def test_failed_seeds_give_inconclusive_with_the_reason():
    r = decide(values=[math.nan, math.nan, math.nan], threshold=1.0)
    assert r.outcome == "inconclusive" and "3/3 seeds failed" in r.detail
    r = decide(values=[0.2, math.nan, 0.3, 0.2, 0.1], threshold=1.0, better="below")
    assert r.outcome == "inconclusive" and "1/5 seeds failed" in r.detail


def test_added_condition_cannot_contradict_the_interval():
    with pytest.raises(InputError, match="not both"):
        decide([True, False], values=[0.5, 0.6], threshold=1.0)
    with pytest.raises(InputError, match="value or held, not both"):
        ClaimSpec(id="c", statement="s", where="w", quantity="q", value=lambda m: m, threshold=1.0,
                  held=lambda m: True)


def test_deterministic_comparison_declares_a_margin_and_ties_are_inconclusive():
    with pytest.raises(InputError, match="equivalence margin"):
        ClaimSpec(id="c", statement="s", where="w", quantity="q", value=lambda m: m, threshold=4.54,
                  stochastic=False)
    spec = ClaimSpec(id="c", statement="s", where="w", quantity="fuel", value=lambda m: m, threshold=4.54,
                     better="above", stochastic=False, margin=0.05, margin_reason="grid step 0.05")
    tie = spec.evaluate({"default": [4.56]})  # the S4 Table 2 box (issue 21 rule 5)
    assert tie.outcome == "inconclusive" and "equivalence margin" in tie.detail
    assert tie.to_dict()["margin_reason"] == "grid step 0.05"
    assert spec.evaluate({"default": [4.70]}).outcome == "holds"
    assert spec.evaluate({"default": [4.40]}).outcome == "does not hold"
    # a stochastic interval that reaches into threshold ± margin is inconclusive too
    assert decide(values=[1.06, 1.07, 1.08, 1.06, 1.07], threshold=1.0, margin=0.1).outcome == "inconclusive"
    assert decide(values=[1.06, 1.07, 1.08, 1.06, 1.07], threshold=1.0).outcome == "holds"


def test_check_is_never_a_claim():
    from adcskit.studies import Check

    assert Check(name="n", passed=True, detail="").kind == "check"
    with pytest.raises(InputError, match="must be 'check'"):
        Check(name="n", passed=True, detail="", kind="claim")


@given(st.lists(st.floats(-10, 10), min_size=5, max_size=12), st.floats(-5, 5))
def test_rule_is_mirror_symmetric(values, thr):
    """Flipping the side that supports the claim swaps holds and does not hold, nothing else."""
    a = decide(values=values, threshold=thr, better="above").outcome
    b = decide(values=values, threshold=thr, better="below").outcome
    swap = {"holds": "does not hold", "does not hold": "holds", "inconclusive": "inconclusive"}
    assert b == swap[a]


_RANK = {"does not hold": 0, "inconclusive": 1, "holds": 2}


@given(st.lists(st.floats(-10, 10), min_size=1, max_size=12), st.floats(-5, 5), st.sampled_from(["above", "below"]),
       st.floats(0, 2), st.booleans(), st.data())
def test_rule_is_monotone(values, thr, better, margin, stochastic, data):
    """Issue 45: moving any seed's value further to the supporting side never weakens the outcome."""
    i = data.draw(st.integers(0, len(values) - 1))
    step = data.draw(st.floats(0, 20))
    moved = list(values)
    moved[i] += step if better == "above" else -step
    kw = {"threshold": thr, "better": better, "margin": margin, "stochastic": stochastic}
    assert _RANK[decide(values=moved, **kw).outcome] >= _RANK[decide(values=values, **kw).outcome]


@given(st.lists(st.floats(0.01, 1e4), min_size=1, max_size=12), st.floats(0.1, 100), st.floats(0, 1), st.data())
def test_rule_is_monotone_on_log_ratios(values, thr, margin, data):
    i = data.draw(st.integers(0, len(values) - 1))
    moved = list(values)
    moved[i] *= data.draw(st.floats(1, 1e3))
    kw = {"threshold": thr, "margin": margin, "scale": "log"}
    assert _RANK[decide(values=moved, **kw).outcome] >= _RANK[decide(values=values, **kw).outcome]


@given(st.lists(st.booleans(), min_size=1, max_size=12), st.data())
def test_rule_is_monotone_in_held_seeds(held, data):
    i = data.draw(st.integers(0, len(held) - 1))
    more = list(held)
    more[i] = True
    assert _RANK[decide(more).outcome] >= _RANK[decide(held).outcome]


@given(st.lists(st.floats(0.01, 100), min_size=5, max_size=12), st.floats(0.1, 10))
def test_log_rule_is_mirror_symmetric(values, thr):
    a = decide(values=values, threshold=thr, scale="log", better="above").outcome
    b = decide(values=values, threshold=thr, scale="log", better="below").outcome
    swap = {"holds": "does not hold", "does not hold": "holds", "inconclusive": "inconclusive"}
    assert b == swap[a]
