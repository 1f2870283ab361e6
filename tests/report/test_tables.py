"""Study tables in the report (issue 25: "its requirement table ... appear[s] in the report"):
small CSV tables are shown inline, a sign-off table (name ending in ``requirements``) open, the
others collapsed; large ones are only linked."""

from __future__ import annotations

from adcskit.report.html import INLINE_MAX_ROWS, build_report
from adcskit.studies import StudyResult, write_result


def test_small_tables_inline_signoff_open_large_only_linked(tmp_path):
    tables = {
        "q_requirements": [{"name": "R1", "bound": 0.118, "verdict": "met"},
                           {"name": "R2", "bound": float("inf"), "verdict": "inconclusive (need ~299 samples)"}],
        "per_seed": [{"seed": i, "ratio": 0.5 + i} for i in range(3)],
        "big": [{"i": i} for i in range(INLINE_MAX_ROWS + 1)],
    }
    write_result(StudyResult(study="closed-loop", tables=tables), tmp_path)
    page = build_report(tmp_path).read_text(encoding="utf-8")
    assert '<details class="csv" open><summary><code>q_requirements.csv</code> (2 rows)' in page
    assert '<details class="csv"><summary><code>per_seed.csv</code> (3 rows)' in page
    assert "<code>big.csv</code>" not in page and 'href="closed-loop/big.csv"' in page  # linked only
    # numbers are right-aligned and formatted like the rest of the report; text stays as written
    assert '<td class="num">0.118</td>' in page and '<td class="num">—</td>' in page  # inf: an empty CSV cell
    assert "<td>inconclusive (need ~299 samples)</td>" in page
