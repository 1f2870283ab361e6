"""Render the HTML report in headless Chromium and check it reads well (skipped without a
browser; the layout checks also need Playwright, which drives the system Chromium — it never
downloads a browser). The screenshots are kept in the test's tmp directory for a human to look at."""

from __future__ import annotations

import shutil
import subprocess

import pytest

import adcskit.studies
import adcskit.studies._registry as registry
from adcskit.studies import Claim, Reading, StudyResult, run_study, write_result

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
    # a study with every kind of badge: indicative, reduced protocol, custom settings, readings
    reading = Reading(reading="slope ratio", outcome="does not hold", n_seeds=2, fraction_held=0.0,
                      interval=(0.9, 1.1))
    claims = [
        Claim(id="error-7x", statement="The error is 7 times lower.", where="S0 abstract; Table 1",
              outcome="does not hold", n_seeds=2, fraction_held=0.0, indicative=True, comparable=False,
              protocol="reduced protocol", readings=(reading,)),
        Claim(id="speed-600x", statement="It is 600 times faster.", where="S0 abstract", outcome="holds",
              n_seeds=5, fraction_held=1.0, comparable=False, protocol="reduced protocol"),
        Claim(id="custom", statement="A claim on a changed key.", outcome="inconclusive", n_seeds=5,
              fraction_held=0.6, comparable=False, protocol="custom settings"),
    ]
    write_result(StudyResult(study="wahba-table1", claims=claims, quick=True, doc="docs/studies/wahba-table1.md",
                             config_changes={"n_trials": {"value": 7, "default": 100, "paper": 100}}), tmp_path)
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


# every table header's text inside its own cell, and no two headers of a row overlapping
_HEADER_BOXES = """() => {
  const bad = [];
  for (const tr of document.querySelectorAll('thead tr')) {
    const boxes = [];
    for (const th of tr.querySelectorAll('th')) {
      const cell = th.getBoundingClientRect();
      if (cell.width === 0) continue;  // hidden at this width
      const range = document.createRange();
      range.selectNodeContents(th);
      const text = range.getBoundingClientRect();
      if (text.width && (text.left < cell.left - 1 || text.right > cell.right + 1))
        bad.push(`"${th.textContent.trim()}" overflows its cell`);
      boxes.push([th.textContent.trim(), text]);
    }
    for (let i = 0; i + 1 < boxes.length; i++) {
      const [a, ra] = boxes[i], [b, rb] = boxes[i + 1];
      if (ra.width && rb.width && ra.right > rb.left + 1 && ra.bottom > rb.top && rb.bottom > ra.top)
        bad.push(`"${a}" overlaps "${b}"`);
    }
  }
  return bad;
}"""


@pytest.mark.parametrize("width", [1400, 1920])
def test_first_screen_layout_in_chromium(report_dir, tmp_path, width):
    """Issue 44: at 1400 x 900 and 1920 x 900 the per-study claim counts are on the first
    screen, no table header overlaps another, and the page logs no console error."""
    playwright = pytest.importorskip("playwright.sync_api")
    with playwright.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox", "--disable-gpu"])
        try:
            page = browser.new_page(viewport={"width": width, "height": 900})
            errors = []
            page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto(report_dir.as_uri(), wait_until="load")
            assert page.evaluate(_HEADER_BOXES) == []
            table = page.locator("#summary table.summary").bounding_box()
            assert table is not None and table["y"] + table["height"] <= 900  # every study's counts, first screen
            assert page.locator("#summary .headline").bounding_box()["y"] < 900
            for study in ("fake", "wahba-table1"):  # the studies that ran have their row of counts
                assert page.locator(f'#summary a[href="#{study}"]').is_visible()
            banner = page.locator("#custom-configuration").bounding_box()
            assert banner is not None and banner["y"] < table["y"]  # a custom run says so at the top
            assert page.locator("text=does not hold · indicative 0/2").first.is_visible()
            page.screenshot(path=str(tmp_path / f"first-screen-{width}.png"))
            assert errors == []
        finally:
            browser.close()
