"""The report opens with a claims matrix (issue 21 item 5): one row per paper claim, one
coloured cell per verdict, a legend, quick outcomes shown as indicative (never red)."""

from __future__ import annotations

import re

from adcskit.report.html import LEGEND, build_report
from adcskit.studies import STUDIES, Claim, Finding, StudyResult, write_result


def _result(tmp_path):
    claims = [
        Claim(id="c-holds", statement="A", where="Table 1", outcome="holds", n_seeds=5, fraction_held=1.0),
        # a quick run: 2 seeds, indicative — its raw outcome must not show as a red verdict
        Claim(id="c-quick", statement="B", where="Fig. 2", outcome="does not hold", n_seeds=2, fraction_held=0.0,
              indicative=True, comparable=False, protocol="reduced protocol",
              protocol_differences=("n_trials: ours 10, paper 100",)),
        Claim(id="c-reduced", statement="C", where="Fig. 3", outcome="holds", n_seeds=5, fraction_held=1.0,
              comparable=False, protocol="reduced protocol", protocol_differences=("n_gen: ours 30, paper 1000",)),
    ]
    findings = [Finding(id="f-1", statement="ours", outcome="inconclusive", n_seeds=5)]
    r = StudyResult(study="wahba-table1", claims=claims, findings=findings,
                    protocol_differences={"n_gen": {"value": 30, "paper": 1000}})
    write_result(r, tmp_path)
    return build_report(tmp_path).read_text(encoding="utf-8")


def test_matrix_has_one_row_per_claim_and_a_legend(tmp_path):
    page = _result(tmp_path)
    matrix = page[page.index('id="claims-matrix"'):page.index('<nav class="toc">')]
    assert page.index('id="claims-matrix"') < page.index('<nav class="toc">')  # it opens the report
    for cid in ("c-holds", "c-quick", "c-reduced"):
        assert f'href="#wahba-table1--claim-{cid}"' in matrix
        assert f'id="wahba-table1--claim-{cid}"' in page  # the link lands on the evidence
    for name, _css, _meaning in LEGEND:
        assert f">{name}</span>" in matrix
    assert "Findings" in matrix and "Checks" in matrix


def test_quick_outcome_is_indicative_not_red_and_reduced_is_marked(tmp_path):
    page = _result(tmp_path)
    cells = dict(re.findall(r'claim-(c-[a-z]+)" title="[^"]*"><span class="badge ([a-z ]+)">', page))
    assert cells["c-holds"] == "ok"
    assert cells["c-quick"] == "ind"  # its own colour: neither red nor the inconclusive amber
    assert cells["c-reduced"] == "ok reduced"
    assert "indicative (2 seeds)" in page and "holds (reduced protocol)" in page
    assert "n_gen</code> ours 30, paper 1000" in page


def test_report_counts_eight_studies(tmp_path):
    page = _result(tmp_path)
    assert len(STUDIES) == 8
    assert "five papers, 8 studies: 7 reproduce the papers" in page
