"""Quick run of the onoff-schmitt study (S4 Figs 2-7, Table 2): structure, physics, verdicts."""

from __future__ import annotations

import json

import numpy as np
import pytest

from adcskit.studies._runner import run_study
from adcskit.studies._verdict import OUTCOMES


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("schmitt")
    run_study("onoff-schmitt", out=out, quick=True, seed=0)
    return json.loads((out / "onoff-schmitt" / "result.json").read_text()), out / "onoff-schmitt"


def test_onoff_schmitt_quick(quick):
    d, folder = quick
    nominal = d["measured"]["nominal"]
    assert set(nominal) >= {"overshoot_pct", "mean_abs_err_last10_deg", "fuel", "firings"}
    # physics: the nominal loop (S4 Table 3) settles with a small overshoot and a limit cycle
    # far inside the 15 deg step; mean |e| <= max |e|
    assert 0 <= nominal["overshoot_pct"] < 10
    assert 0 < nominal["mean_abs_err_last10_deg"] <= nominal["max_abs_err_last10_deg"] < 1.0
    assert nominal["fuel"] > 0.05 * 10  # at least the disturbance impulse over 10 s
    sweep = d["measured"]["sweep"]
    fuel = np.array(sweep["fuel"])
    assert fuel.shape == (len(sweep["off_ratio"]), len(sweep["u_on"]))
    assert np.all(np.isfinite(fuel))
    assert all(c["passed"] for c in d["checks"])
    for f in d["figures"]:
        assert (folder / f).stat().st_size > 1000


def test_claims_are_the_papers(quick):
    d, _ = quick
    claims = {c["id"]: c for c in d["claims"]}
    assert set(claims) == {"pointing-accuracy-0.25deg", "table2-recommended-region", "u-on-trends"}
    for c in claims.values():
        assert c["outcome"] in OUTCOMES and c["where"] and c["statement"]
        assert c["n_seeds"] == 1  # deterministic simulations: one run decides
    # S4 text under Fig. 7: 0.25 deg; our nominal run stays far inside it in both readings
    acc = claims["pointing-accuracy-0.25deg"]
    assert acc["outcome"] == "holds" and acc["paper"] == 0.25
    assert {r["reading"]: r["outcome"] for r in acc["readings"]} == {"max |error|": "holds", "mean |error|": "holds"}
    assert claims["u-on-trends"]["outcome"] == "holds"
    # Table 2: each criterion's own row is met, the all-criteria box is not cheaper than the rest
    t2 = {r["reading"]: r["outcome"] for r in claims["table2-recommended-region"]["readings"]}
    assert t2 == {"all-criteria box": "does not hold", "per-criterion rows": "holds"}
    assert claims["table2-recommended-region"]["outcome"] == "depends on reading"


def test_outcomes_do_not_depend_on_the_seed(quick, tmp_path):
    # the study is deterministic: another seed must give the same outcome for every claim
    d, _ = quick
    other = run_study("onoff-schmitt", out=None, quick=True, seed=1)
    assert {c.id: c.outcome for c in other.claims} == {c["id"]: c["outcome"] for c in d["claims"]}
