"""``adcskit reproduce --jobs N``: studies in worker processes give the serial run's results.

Fake studies (tests/fake_study.py, tests/fake_jobs/) are registered for the test; the spawn
workers get the registry entries from the parent. Each test starts one small process pool
(2 workers, a few seconds).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

import adcskit.studies
import adcskit.studies._registry as registry
from adcskit.cli import _longest_first, _usable_cores, _worker_executor_spec, _worker_threads, main
from adcskit.uncertainty.executor import make_executor

#: Keys of result.json that are timings (they differ between any two runs).
TIMING_KEYS = ("runtime_s",)

FAKES = {
    "fake": "fake_study",
    "fake-b": "fake_jobs.b",
    "fake-boom": "fake_jobs.boom",
    "fake-sleepy": "fake_jobs.sleepy",
    "fake-int": "fake_jobs.interrupter",
}


@pytest.fixture
def fakes(monkeypatch):
    studies = dict(registry.STUDIES)
    for name, module in FAKES.items():
        studies[name] = registry.StudyInfo(name, module, "none", "A fake study")
    monkeypatch.setattr(registry, "STUDIES", studies)
    monkeypatch.setattr(adcskit.studies, "STUDIES", studies)  # the public face the CLI reads
    return list(FAKES)


def _results(out: Path) -> dict[str, dict]:
    found = {}
    for path in sorted(out.glob("*/result.json")):
        data = json.loads(path.read_text())
        found[path.parent.name] = {k: v for k, v in data.items() if k not in TIMING_KEYS}
    return found


def test_jobs_2_equals_serial_including_a_failing_study(fakes, tmp_path, capsys):
    only = "fake,fake-b,fake-boom"
    serial, parallel = tmp_path / "serial", tmp_path / "parallel"
    argv = ["reproduce", "--quick", "--seed", "7", "--only", only]
    assert main([*argv, "--jobs", "1", "--out", str(serial)]) == 1  # one study failed
    assert main([*argv, "--jobs", "2", "--out", str(parallel)]) == 1
    a, b = _results(serial), _results(parallel)
    assert sorted(a) == ["fake", "fake-b"] and a == b  # the same result.json, timings aside
    for name in ("fake", "fake-b"):
        for csv in (serial / name).glob("*.csv"):
            assert csv.read_bytes() == (parallel / name / csv.name).read_bytes()
    # the failure is recorded exactly as in the serial run (same message, same traceback)
    err_a = json.loads((serial / "errors.json").read_text())
    err_b = json.loads((parallel / "errors.json").read_text())
    assert list(err_a) == list(err_b) == ["fake-boom"] and err_a == err_b
    assert "boom: fake study failed on purpose" in err_b["fake-boom"]["message"]
    assert (parallel / "index.html").is_file()
    # per-study logs, one line per finished study and a summary in the registry order
    assert "fake-b: done in" in (parallel / "logs" / "fake-b.log").read_text()
    out = capsys.readouterr()
    summary = [ln for ln in out.out[out.out.index("summary (2 studies at once"):].splitlines() if ln.startswith("  ")]
    assert [ln.split()[0] for ln in summary] == ["fake", "fake-b", "fake-boom"]
    # wall and CPU seconds of each study's worker (issue 24: per-study CPU beside the wall time)
    assert re.fullmatch(r"\s+fake\s+done in \d+\.\d s \(\d+\.\d CPU-s\)", summary[0])
    assert "failed" in summary[2] and "study fake-boom failed: RuntimeError: boom" in out.err


def test_ctrl_c_cancels_pending_studies_and_keeps_written_ones(fakes, tmp_path, monkeypatch, capsys):
    out = tmp_path / "res"
    monkeypatch.setenv("ADCSKIT_TEST_OUT", str(out))
    # schedule: fake-int and fake on the two workers; fake-sleepy next; fake-b last (pending)
    monkeypatch.setattr(adcskit.studies, "EXPECTED_WALL_S", {"fake-int": 30.0, "fake": 20.0, "fake-sleepy": 10.0})
    argv = ["reproduce", "--quick", "--jobs", "2", "--only", "fake,fake-b,fake-sleepy,fake-int", "--out", str(out)]
    # a shell without job control starts background jobs with SIGINT ignored (POSIX), and Python
    # then keeps it ignored: give this process the interactive Ctrl-C behaviour the test is about
    import signal

    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        assert main(argv) == 130
    finally:
        signal.signal(signal.SIGINT, old)
    assert set(_results(out)) == {"fake"}  # written before the Ctrl-C, intact
    assert json.loads((out / "fake" / "result.json").read_text())["study"] == "fake"
    assert not (out / "fake-b").exists() and not (out / "fake-sleepy").exists()
    assert json.loads((out / "errors.json").read_text()) == {}  # an interrupt is not a failure
    assert (out / "index.html").is_file()
    text = capsys.readouterr()
    assert "interrupted; studies already written are intact" in text.err
    rows = [ln for ln in text.out[text.out.index("summary ("):].splitlines() if ln.startswith("  ")]
    summary = dict(ln.split(None, 1) for ln in rows)
    assert summary["fake"].startswith("done") and summary["fake-b"] == "cancelled"
    assert summary["fake-int"] == "interrupted" and summary["fake-sleepy"] in ("interrupted", "cancelled")


def test_longest_first_schedule():
    # docs/benchmarks.md, "Full reproduction" (2026-12-02): closed-loop is the longest study since
    # onoff-tuning replays its stored paper-scale GA runs
    order = _longest_first(adcskit.studies.study_names())
    assert order[0] == "closed-loop" and order[-1] == "onoff-schmitt"
    assert sorted(order) == sorted(adcskit.studies.study_names())


def test_executor_per_study_does_not_oversubscribe(monkeypatch, capsys):
    import adcskit.cli as cli

    monkeypatch.setattr(cli, "_usable_cores", lambda: 4)
    with make_executor("serial") as ex:
        assert _worker_executor_spec("serial", ex, 2) == "serial"
    with make_executor("processes") as ex:  # no count: the cores shared among the studies
        assert _worker_executor_spec("processes", ex, 2) == "processes:2"
        assert _worker_executor_spec("processes", ex, 8) == "processes:1"
    with make_executor("processes:3") as ex:  # an explicit count is kept, with a warning
        assert _worker_executor_spec("processes:3", ex, 2) == "processes:3"
    assert "6 campaign processes on 4 cores" in capsys.readouterr().err


def test_jobs_must_be_positive(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["reproduce", "--jobs", "0"])
    assert exc.value.code == 2 and "jobs must be a positive integer" in capsys.readouterr().err


def test_cli_lets_idle_openmp_threads_sleep_unless_the_user_chose(monkeypatch):
    """``OMP_WAIT_POLICY=PASSIVE`` from the CLI (inherited by --jobs workers); a user's value stays."""
    import os

    monkeypatch.setenv("OMP_WAIT_POLICY", "placeholder")  # restored at teardown, whatever main does
    monkeypatch.delenv("OMP_WAIT_POLICY")
    assert main(["list", "--quiet"]) == 0
    assert os.environ["OMP_WAIT_POLICY"] == "PASSIVE"
    monkeypatch.setenv("OMP_WAIT_POLICY", "ACTIVE")
    assert main(["list", "--quiet"]) == 0
    assert os.environ["OMP_WAIT_POLICY"] == "ACTIVE"


def test_serial_studies_side_by_side_share_the_cores_out():
    # issue 24: a prange loop's static halves left a core idle when two studies ran every core each
    cores = _usable_cores()
    assert _worker_threads("serial", 2) == max(1, cores // 2)
    assert _worker_threads("serial", 4 * cores) == 1
    assert _worker_threads("processes:1", 2) == 0 and _worker_threads("dask://127.0.0.1:8786", 2) == 0
