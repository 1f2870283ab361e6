"""Stage lines on the console (issue 41 item 3): ``reproduce --jobs N`` forwards each study's
stage lines from its worker process; ``track``/``bar`` hand periodic progress lines to the
sink; ``auto_session`` (``simulate(progress=...)``) shows a display only when asked or at a
terminal.

Fake studies as in tests/test_jobs.py (one small process pool of 2 workers).
"""

from __future__ import annotations

import pytest

import adcskit._progress as progress
import adcskit.studies
import adcskit.studies._registry as registry
from adcskit.cli import main
from adcskit.errors import InputTypeError

FAKES = {"fake": "fake_study", "fake-stages": "fake_jobs.stages"}


@pytest.fixture
def fakes(monkeypatch):
    studies = dict(registry.STUDIES)
    for name, module in FAKES.items():
        studies[name] = registry.StudyInfo(name, module, "none", "A fake study")
    monkeypatch.setattr(registry, "STUDIES", studies)
    monkeypatch.setattr(adcskit.studies, "STUDIES", studies)
    return list(FAKES)


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_reproduce_prints_every_stage_line(fakes, tmp_path, capsys, jobs):
    argv = ["reproduce", "--quick", "--only", "fake,fake-stages", "--jobs", jobs, "--out", str(tmp_path)]
    assert main(argv) == 0
    out = capsys.readouterr().out
    # a start line for every study (also one without stages of its own) and each stage line
    assert "fake: started (quick settings, seed 0)" in out
    assert "fake-stages: started (quick settings, seed 0)" in out
    assert "fake-stages: stage one" in out
    if jobs == "2":  # forwarded from the worker: named, and the loop's progress lines too
        assert "fake-stages: stage two (no name)" in out
        assert "fake-stages: fake loop: 3/3 after" in out
        assert "fake-stages: stage one" in (tmp_path / "logs" / "fake-stages.log").read_text()
    else:
        assert "stage two (no name)" in out


def test_quiet_reproduce_prints_no_stage_line(fakes, tmp_path, capsys):
    assert main(["reproduce", "--quick", "--quiet", "--only", "fake,fake-stages", "--jobs", "2",
                 "--out", str(tmp_path)]) == 0
    assert "stage one" not in capsys.readouterr().out


def test_track_and_bar_forward_periodic_lines(monkeypatch):
    lines: list[str] = []
    monkeypatch.setattr(progress, "FORWARD_EVERY_S", 0.0)
    progress.forward_status(lines.append)
    try:
        assert list(progress.track(range(2), "loop")) == [0, 1]  # no session: items unchanged
        with progress.bar("hand", 4) as advance:
            advance(3)
        progress.status("a stage")
    finally:
        progress.forward_status(None)
    assert [ln.rsplit(" after ", 1)[0] for ln in lines] == ["loop: 1/2", "loop: 2/2", "hand: 3/4", "a stage"]
    monkeypatch.setattr(progress, "FORWARD_EVERY_S", 3600.0)
    progress.forward_status(lines.append)
    try:
        list(progress.track(range(5), "quiet loop"))
    finally:
        progress.forward_status(None)
    assert len(lines) == 4  # nothing before FORWARD_EVERY_S has passed


def test_auto_session_is_off_unless_asked_or_at_a_terminal(capsys, monkeypatch):
    monkeypatch.setattr(progress, "AUTO_DELAY_S", 0.0)
    for flag in (None, False):  # pytest's stdout is not a terminal
        with progress.auto_session(flag):
            assert progress._SESSION is None
            for _ in progress.track(range(2), "samples"):
                pass
    assert capsys.readouterr().out == ""
    with progress.auto_session(True, delay_s=0.0):
        assert progress._SESSION is not None
        progress.status("compiling once")
        import time

        time.sleep(0.2)  # the delayed start has run
        for _ in progress.track(range(2), "samples"):
            pass
    assert progress._SESSION is None
    out = capsys.readouterr().out
    assert "compiling once" in out
    with pytest.raises(InputTypeError, match="progress must be True, False or None"):
        with progress.auto_session("yes"):
            pass


def test_auto_session_inside_a_session_adds_nothing():
    with progress.progress_session(True):
        outer = progress._SESSION
        with progress.auto_session(True, delay_s=0.0):
            assert progress._SESSION is outer
    assert progress._SESSION is None


def test_short_call_draws_no_bar(capsys):
    with progress.auto_session(True, delay_s=30.0):
        for _ in progress.track(range(2), "samples"):
            pass
    assert "samples" not in capsys.readouterr().out


def test_simulate_wheels_validates_progress_before_running():
    from adcskit.simulation import WheelScenario, simulate_wheels

    with pytest.raises(InputTypeError, match="progress must be True, False or None"):
        simulate_wheels(WheelScenario(), 1, progress=1)
