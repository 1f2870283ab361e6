"""``benchmarks/bench_reproduce.py``: the ratio it prints for issue 24's full-reproduction goal.

No reproduction is run here (< 1 s): the pairing of runs into candidate / baseline ratios and
their median is what the benchmark's verdict rests on (docs/benchmarks.md, "Full reproduction").
"""

from __future__ import annotations

import pytest


@pytest.fixture(scope="module")
def br(benchmark_script):
    return benchmark_script("bench_reproduce")


def _run(pair, side, wall):
    return {"pair": pair, "side": side, "wall_s": wall}


def test_ratio_is_per_pair_whatever_the_order_and_the_median_of_pairs(br):
    # docs/benchmarks.md, "Full reproduction" (2026-12-02): 438.6 s after 875.2 s, 492.4 s before
    # 1027.9 s, 521.5 s before 957.2 s -> 0.501, 0.479, 0.545; median 0.501
    runs = [_run(1, "baseline", 875.2), _run(1, "candidate", 438.6),
            _run(2, "candidate", 492.4), _run(2, "baseline", 1027.9),
            _run(3, "baseline", 957.2), _run(3, "candidate", 521.5)]
    s = br._summary(runs)
    assert s["wall_ratio_per_pair"] == [0.501, 0.479, 0.545]
    assert s["wall_ratio_median"] == 0.501


def test_an_unfinished_pair_gives_no_ratio(br):
    s = br._summary([_run(1, "baseline", 900.0), _run(1, "candidate", 450.0), _run(2, "candidate", 470.0)])
    assert s["wall_ratio_per_pair"] == [0.5]
    assert br._summary([_run(1, "candidate", 470.0)])["wall_ratio_median"] is None


def test_pairs_must_be_positive(br, capsys):
    with pytest.raises(SystemExit):
        br.main(["--pairs", "0"])
    assert "--pairs must be >= 1; got 0" in capsys.readouterr().err


def test_per_study_cpu_comes_from_the_jobs_summary(br, tmp_path, monkeypatch):
    # the summary lines of `adcskit reproduce --jobs N` (src/adcskit/cli.py, _run_parallel)
    log = tmp_path / "run.log"
    exe = tmp_path / "venv" / "bin" / "adcskit"
    exe.parent.mkdir(parents=True)

    def fake_run(cmd, cwd, env, stdout, stderr):
        stdout.write("summary (2 studies at once, 9.0 s wall; logs in X):\n"
                     "  wahba-table1  done in 623.3 s (700.2 CPU-s)\n"
                     "  onoff-schmitt  done in 7.0 s (6.9 CPU-s)\n"
                     "  rendezvous  failed after 1.0 s (0.5 CPU-s)\n")
        return type("R", (), {"returncode": 0})()

    monkeypatch.setattr(br.subprocess, "run", fake_run)
    r = br.run_once(exe, tmp_path / "out", quick=True, jobs=2, log=log)
    assert r["studies_cpu_s"] == {"wahba-table1": 700.2, "onoff-schmitt": 6.9}


def test_first_candidate_swaps_every_pair(br, tmp_path, monkeypatch):
    order = []
    monkeypatch.setattr(br, "checkout", lambda rev, where: where / ".venv" / "bin" / "adcskit")
    monkeypatch.setattr(br, "run_once", lambda exe, out, quick, jobs, log: order.append(exe.parts[-4]) or
                        {"wall_s": 1.0, "cpu_s": 1.0, "cpu_share_pct": 100.0, "exit": 0, "errors": {},
                         "studies_runtime_s": {}, "studies_cpu_s": {}})
    assert br.main(["--pairs", "2", "--first", "candidate", "--quick", "--workdir", str(tmp_path)]) == 0
    assert order == ["candidate-src", "baseline-src", "baseline-src", "candidate-src"]
