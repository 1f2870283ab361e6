"""``benchmarks/bench_basilisk.py``'s speed section: the like-with-like per-core measurements of
issue 24 item 2 (docs/benchmarks.md, "Closed-loop simulator vs Basilisk").

Short runs only (1 s of simulated time, 4 samples): what is checked is what the ratios are made
of, not how fast anything is (no timing assertions)."""

from __future__ import annotations

import sys
from pathlib import Path

import numba
import pytest


@pytest.fixture(scope="module")
def bb(benchmark_script):
    return benchmark_script("bench_basilisk")


def test_one_thread_run_restores_the_thread_count_and_every_series_is_kept(bb):
    before = numba.get_num_threads()
    sp = bb.speed(1.0, 4, 2, 0.0, with_basilisk=False)
    assert numba.get_num_threads() == before
    assert [len(sp["runs"][k]) for k in ("same", "full", "full_one_thread")] == [2, 2, 2]
    assert sp["runs"]["basilisk"] == [] and sp["runs"]["basilisk_all_cores"] == []
    for k in ("same", "full", "full_one_thread"):
        assert sp["median"][k]["sample_steps_per_cpu_s"] > 0.0
    assert "ratio_full_one_thread_each" not in sp  # no Basilisk, no ratio


def test_one_thread_run_restores_the_thread_count_on_error(bb, monkeypatch):
    before = numba.get_num_threads()

    def boom(*a, **k):
        raise RuntimeError("boom")

    monkeypatch.setattr(bb, "simulate", boom)
    with pytest.raises(RuntimeError):
        bb._ours_speed(None, 1, 0, threads=1)
    assert numba.get_num_threads() == before


def test_basilisk_on_every_core_sums_steps_and_cpu_of_its_processes(bb, monkeypatch):
    pytest.importorskip("Basilisk")
    # spawned workers import bench_basilisk by name: its folder must be on their path
    monkeypatch.syspath_prepend(str(Path(bb.__file__).parent))
    r = bb.bsk_speed_all_cores(1.0, 0.02, 2)
    assert r["processes"] == 2 and len(r["parts"]) == 2
    assert r["steps"] == sum(p["steps"] for p in r["parts"]) >= 200  # >= one 1 s run each at 0.01 s
    assert r["cpu_s"] == pytest.approx(sum(p["cpu_s"] for p in r["parts"]))
    assert r["sample_steps_per_cpu_s"] == pytest.approx(r["steps"] / r["cpu_s"])
    assert r["wall_s"] == max(p["wall_s"] for p in r["parts"])
    assert "bench_basilisk" in sys.modules
