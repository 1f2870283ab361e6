"""Quick run of the closed-loop study: every finding decided on 2 seeds, figures written."""

from __future__ import annotations

import json

import pytest

from adcskit.studies._runner import run_study
from adcskit.studies._verdict import OUTCOMES


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("closed-loop")
    run_study("closed-loop", out=out, quick=True, seed=0)
    return out, json.loads((out / "closed-loop" / "result.json").read_text())


def test_every_finding_decided_on_two_seeds(quick):
    _, d = quick
    ids = {f["id"] for f in d["findings"]}
    assert ids == {"q1-layout-propellant", "q2-mekf-vs-qmethod", "q2-minmax-vs-qmethod", "q3-robust-gains-spread",
                   "q4-optimal-slew-settling", "q4-optimal-slew-propellant"}
    for f in d["findings"]:
        assert f["outcome"] in (*OUTCOMES, "not comparable"), f
        assert f["n_seeds"] == 2
    q1 = next(f for f in d["findings"] if f["id"] == "q1-layout-propellant")
    assert len(q1["readings"]) == 4  # two allocations x (all thrusters, one failed)
    q2m = next(f for f in d["findings"] if f["id"] == "q2-minmax-vs-qmethod")
    assert len(q2m["readings"]) == 3  # bounded / Gaussian errors, bounded with equal weights
    # the min-max box statistic is measured for every reading and is a fraction
    for key, v in d["measured"].items():
        if key.startswith("q2_minmax_box_active_fraction"):
            assert 0.0 <= v <= 1.0


def test_stable_outcomes(quick):
    # categories the full run (5 seeds x 1000 samples) decides with margin; see
    # docs/studies/closed-loop.md. Tracking the time-optimal profile arrives at the target
    # about 10 s before the step command's switching-line approach (16.5 s vs ~27 s).
    _, d = quick
    out = {f["id"]: f["outcome"] for f in d["findings"]}
    assert out["q4-optimal-slew-settling"] == "holds"


def test_checks_and_figures(quick):
    path, d = quick
    checks = {c["name"]: c for c in d["checks"]}
    assert any("bang-bang" in n for n in checks)
    assert next(c for n, c in checks.items() if "bang-bang" in n)["passed"]
    assert set(d["figures"]) == {"attitude-error.png", "thruster-activity.png", "nees.png", "propellant.png"}
    for f in d["figures"]:
        assert (path / "closed-loop" / f).stat().st_size > 1000
    rows = d["tables"]
    assert "q1_layouts.csv" in rows and "q4_slew.csv" in rows
