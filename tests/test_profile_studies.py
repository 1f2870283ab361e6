"""``benchmarks/profile_studies.py --compare``: run-time fields are ignored, anything else is not.

The profile script's check that profiling leaves a study's output unchanged (issue 24 item 1) is
only as good as this comparison: it must pass two runs that differ only in measured run times
(wahba-table1's solve times, speed ratios and its timing claim ``speed-600x``, whose outcome a
loaded machine can move) and fail on any other difference. No study is run here (< 1 s).
"""

from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest


@pytest.fixture(scope="module")
def ps(benchmark_script):
    return benchmark_script("profile_studies")


# the shape of wahba-table1's result.json (quick run), cut to the fields the comparison treats
_RESULT = {
    "study": "wahba-table1",
    "runtime_s": 4.1,
    "summary": "7x lower error: does not hold; ~600x faster than NSGA-II (CPU time; NSGA-II 24x20 or 24x60): "
               "inconclusive (ratios 2, 5, 63, 163; the paper's own table gives 434x). NSGA-II: inconclusive.",
    "measured": {"methods": {"minmax": {"mean_deg": 17.01, "runtime_s": 6.0e-4}},
                 "ratio_means": {"err_ratio": 0.997, "speed_ratio": 1.82}},
    "claims": [
        {"id": "error-7x", "outcome": "does not hold", "measured": 0.997, "interval": [0.87, 1.13], "timing": False},
        {"id": "speed-600x", "outcome": "inconclusive", "measured": 1.82, "interval": [-3.6, 7.3], "timing": True,
         "readings": [{"reading": "slsqp", "outcome": "inconclusive", "values": [2.25, 1.40]}]},
    ],
    "comparison": [{"quantity": "minmax: mean_deg", "measured": 17.01},
                   {"quantity": "minmax: runtime_s", "measured": 6.0e-4}],
    "figures": ["table1-errors.png"],
}
_CSV = "method,mean_deg,runtime_s\nminmax,17.01,0.0006\n"


def _write(d: Path, result: dict, csv_text: str = _CSV) -> Path:
    d.mkdir()
    (d / "result.json").write_text(json.dumps(result))
    (d / "table1.csv").write_text(csv_text)
    (d / "table1-errors.png").write_bytes(b"png")
    return d


def test_run_time_fields_are_ignored(ps, tmp_path):
    """Another run's solve times, speed ratios and timing-claim outcome: identical, with a note."""
    other = copy.deepcopy(_RESULT)
    other["runtime_s"] = 47.9
    other["summary"] = other["summary"].replace("inconclusive (ratios 2, 5, 63, 163;", "holds (ratios 5, 15, 87, 247;")
    other["measured"]["methods"]["minmax"]["runtime_s"] = 1.0e-3
    other["measured"]["ratio_means"]["speed_ratio"] = 5.37
    speed = other["claims"][1]
    speed.update(outcome="holds", measured=5.37, interval=[5.3, 5.4])
    speed["readings"][0].update(outcome="holds", values=[5.38, 5.36])
    other["comparison"][1]["measured"] = 1.0e-3
    a = _write(tmp_path / "a", _RESULT)
    b = _write(tmp_path / "b", other, _CSV.replace("0.0006", "0.0010"))
    diff, notes = ps.compare(str(a), str(b))
    assert diff == []
    assert len(notes) == 1 and notes[0].startswith("timing claim speed-600x")


@pytest.mark.parametrize("change", ["claim", "measured", "comparison", "csv", "figure"])
def test_other_fields_are_not(ps, tmp_path, change):
    """A non-timing number, a CSV cell or a figure file name that differs is reported."""
    other = copy.deepcopy(_RESULT)
    csv_text = _CSV
    if change == "claim":
        other["claims"][0]["outcome"] = "holds"
    elif change == "measured":
        other["measured"]["ratio_means"]["err_ratio"] = 0.998
    elif change == "comparison":
        other["comparison"][0]["measured"] = 17.02
    elif change == "csv":
        csv_text = _CSV.replace("17.01", "17.02")
    a = _write(tmp_path / "a", _RESULT)
    b = _write(tmp_path / "b", other, csv_text)
    if change == "figure":
        (b / "table1-errors.png").rename(b / "table1-error.png")
    diff, _ = ps.compare(str(a), str(b))
    assert diff, f"a changed {change} went unnoticed"
