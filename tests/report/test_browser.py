"""Render the HTML report in headless Chromium and check it reads well (skipped without a
browser). The screenshot is kept in the test's tmp directory for a human to look at."""

from __future__ import annotations

import shutil
import subprocess

import pytest

import adcskit.studies
import adcskit.studies._registry as registry
from adcskit.studies import run_study

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(CHROMIUM is None, reason="no headless Chromium installed"),
]

FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--hide-scrollbars",
]


@pytest.fixture
def report_dir(tmp_path, monkeypatch):
    studies = dict(registry.STUDIES)
    studies["fake"] = registry.StudyInfo("fake", "fake_study", "none", "A fake study")
    monkeypatch.setattr(registry, "STUDIES", studies)
    monkeypatch.setattr(adcskit.studies, "STUDIES", studies)  # the public face the report reads
    run_study("fake", quick=True, out=tmp_path)
    from adcskit.report import build_report

    return build_report(tmp_path)


def test_report_renders_in_headless_chromium(report_dir, tmp_path):
    profile = tmp_path / "profile"
    dom = subprocess.run(
        [CHROMIUM, *FLAGS, f"--user-data-dir={profile}", "--dump-dom", report_dir.as_uri()],
        capture_output=True, text=True, timeout=90, check=False,
    )
    assert dom.returncode == 0, dom.stderr[-2000:]
    # the DOM after parsing holds the study section, its claim verdict and the figure
    assert 'id="fake"' in dom.stdout
    assert "The paper's claims" in dom.stdout and "fake/means.png" in dom.stdout
    from adcskit.studies import OUTCOMES

    assert any(f">{o}<" in dom.stdout for o in OUTCOMES)  # a verdict badge
    shot = tmp_path / "report.png"
    res = subprocess.run(
        [CHROMIUM, *FLAGS, f"--user-data-dir={profile}", "--window-size=1280,2400",
         f"--screenshot={shot}", report_dir.as_uri()],
        capture_output=True, text=True, timeout=90, check=False,
    )
    assert res.returncode == 0, res.stderr[-2000:]
    assert shot.stat().st_size > 20_000  # a rendered page with content, not a blank image
