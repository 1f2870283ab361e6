"""Quick run of the onoff-schmitt study (S4 Figs 2-7): structure and key physics."""

from __future__ import annotations

import json

import numpy as np

from adcskit.studies._runner import run_study


def test_onoff_schmitt_quick(tmp_path):
    run_study("onoff-schmitt", out=tmp_path, quick=True, seed=0)
    d = json.loads((tmp_path / "onoff-schmitt" / "result.json").read_text())
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
    names = {c["name"] for c in d["checks"] if c["kind"] == "claim"}
    assert any("0.25" in n for n in names)
    assert all(c["passed"] for c in d["checks"] if c["kind"] == "check")
    for f in d["figures"]:
        assert (tmp_path / "onoff-schmitt" / f).stat().st_size > 1000
