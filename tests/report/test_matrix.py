"""The report's first screen (issue 44 item 1) and its claims matrix (issue 21 item 5): per study,
how many paper claims hold / do not hold / are inconclusive / depend on reading, then one row per
claim. A quick (indicative) outcome keeps its verdict visible, drawn pale; a custom run reads
"not comparable" beside the outcome it got (issue 45 item 5)."""

from __future__ import annotations

import re
from pathlib import Path

from adcskit.report.html import LEGEND, build_report
from adcskit.studies import STUDIES, Claim, Finding, StudyResult, write_result


def _result(tmp_path, **extra):
    claims = [
        Claim(id="c-holds", statement="A", where="Table 1", outcome="holds", n_seeds=5, fraction_held=1.0),
        # a quick run: 2 seeds, indicative — its raw outcome stays visible, pale, never a solid red verdict
        Claim(id="c-quick", statement="B", where="Fig. 2", outcome="does not hold", n_seeds=2, fraction_held=0.0,
              indicative=True, comparable=False, protocol="reduced protocol",
              protocol_differences=("n_trials: ours 10, paper 100",)),
        Claim(id="c-reduced", statement="C", where="Fig. 3", outcome="holds", n_seeds=5, fraction_held=1.0,
              comparable=False, protocol="reduced protocol", protocol_differences=("n_gen: ours 30, paper 1000",)),
    ]
    findings = [Finding(id="f-1", statement="ours", outcome="inconclusive", n_seeds=5)]
    r = StudyResult(study="wahba-table1", claims=claims, findings=findings, doc="docs/studies/wahba-table1.md",
                    protocol_differences={"n_gen": {"value": 30, "paper": 1000}}, **extra)
    write_result(r, tmp_path)
    return build_report(tmp_path).read_text(encoding="utf-8")


def _cells(page):
    """``{claim id: (badge classes, badge text)}`` of the claims matrix."""
    found = re.findall(r'claim-(c-[a-z]+)" title="[^"]*"><span class="badge ([a-z ]+)">([^<]*)</span>', page)
    return {k: (css, label) for k, css, label in found}


def test_first_screen_counts_claims_per_study_before_the_matrix(tmp_path):
    page = _result(tmp_path)
    summary = page[page.index('id="summary"'):page.index('id="claims-matrix"')]
    # the headline over all studies: 2 hold (one of them at a reduced protocol), 1 does not hold (indicative)
    assert 'class="badge ok">2 hold</span>' in summary and 'class="badge bad">1 does not hold</span>' in summary
    assert "1 of these are indicative" in summary and "1 decided below the paper's protocol" in summary
    row = summary[summary.index('href="#wahba-table1"'):]
    row = row[:row.index("</tr>")]
    # holds: one at the paper's protocol, one hatched (reduced); does not hold: one pale (indicative)
    assert '<span class="badge ok" title="1 holds">1</span>' in row
    assert '<span class="badge ok reduced" title="1 holds (reduced protocol)">1</span>' in row
    assert '<span class="badge bad ind" title="1 does not hold · indicative">1</span>' in row
    assert "docs</a>" in row
    for name, _css, _meaning in LEGEND:
        assert f">{name}</span>" in summary  # the legend sits under the counts


def test_matrix_has_one_row_per_claim(tmp_path):
    page = _result(tmp_path)
    matrix = page[page.index('id="claims-matrix"'):page.index('<section class="study"')]
    for cid in ("c-holds", "c-quick", "c-reduced"):
        assert f'href="#wahba-table1--claim-{cid}"' in matrix
        assert f'id="wahba-table1--claim-{cid}"' in page  # the link lands on the evidence
    assert "Findings" in matrix and "Checks" in matrix


def test_quick_outcome_keeps_its_verdict_pale_and_reduced_is_marked(tmp_path):
    page = _result(tmp_path)
    cells = _cells(page)
    assert cells["c-holds"] == ("ok", "holds")
    # issue 44: "a muted red 'does not hold · indicative 0/2'" — 0 of its 2 seeds support it
    assert cells["c-quick"] == ("bad ind", "does not hold · indicative 0/2")
    assert cells["c-reduced"] == ("ok reduced", "holds (reduced protocol)")
    assert "n_gen</code> ours 30, paper 1000" in page
    assert "Custom configuration" not in page  # nothing was changed by the user


def test_badge_colours_are_distinct(tmp_path):
    """Issue 44: the "quick" badge shared inconclusive's ochre; every badge class has its own colour."""
    page = _result(tmp_path, quick=True)
    style = page[page.index("<style>"):page.index("</style>")]
    colours = {}
    for css in ("ok", "bad", "warn", "read", "nc", "muted", "ran", "qk"):
        m = re.search(r"\." + css + r" \{ background:([^;]+);", style)
        assert m, css
        colours[css] = m.group(1).strip()
    assert len(set(colours.values())) == len(colours), colours
    assert '<span class="badge qk">quick</span>' in page


def test_custom_run_has_the_banner_at_the_top_and_the_outcome_beside_not_comparable(tmp_path):
    claims = [Claim(id="c-custom", statement="D", outcome="holds", n_seeds=5, fraction_held=1.0,
                    comparable=False, protocol="custom settings",
                    protocol_differences=("n_trials: ours 7, study setting 100",))]
    write_result(StudyResult(study="wahba-table1", claims=claims,
                             config_changes={"n_trials": {"value": 7, "default": 100, "paper": 100}}), tmp_path)
    page = build_report(tmp_path).read_text(encoding="utf-8")
    top = page.index('id="custom-configuration"')
    assert top < page.index('id="summary"')  # above the first screen's counts
    assert "<code>n_trials</code> 7 (study setting 100; paper 100)" in page[top:page.index('id="summary"')]
    assert _cells(page)["c-custom"] == ("nc", "not comparable · holds")
    summary = page[page.index('id="summary"'):]
    row = summary[summary.index('href="#wahba-table1"'):]
    assert '<span class="badge nc" title="1 not comparable (1 holds)">1</span>' in row[:row.index("</tr>")]


def test_docs_link_is_a_relative_path_to_the_page(tmp_path):
    page = _result(tmp_path)
    hrefs = set(re.findall(r'<a href="([^"]+)" title="docs/studies/wahba-table1.md">docs</a>', page))
    assert len(hrefs) == 1
    (href,) = hrefs
    assert not href.startswith(("/", "file:"))  # relative to the report's folder
    target = (tmp_path / href).resolve()
    assert target.is_file() and target.name in ("wahba-table1.md", "wahba-table1.html")
    assert Path(target).read_text(encoding="utf-8")  # it opens the study's page


def test_report_counts_eight_studies(tmp_path):
    page = _result(tmp_path)
    assert len(STUDIES) == 8
    assert "five papers, 8 studies: 7 reproduce the papers" in page
