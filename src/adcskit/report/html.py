"""Render ``DIR/index.html`` from the ``DIR/<study>/result.json`` files.

The first screen says, per study, how many of the paper's claims hold, do not hold, are
inconclusive, depend on reading or are not comparable (a custom run), then the claims matrix
(one row per claim). An indicative outcome (fewer than 5 seeds, a quick run) keeps its verdict
and is drawn pale ("does not hold · indicative 0/2"); one decided below the paper's protocol is
hatched; a custom run reads "not comparable · <the outcome it got>" under a banner at the top.
Each study links its documentation page (see :func:`_doc_href`).

The page shows, per study: the paper's values beside ours (the study's ``comparison`` rows),
a verdict per claim, our sanity checks, what we did differently from the paper and why,
the figures, CSV tables and the resolved configuration. Studies that are registered but
not yet run, or that failed, are listed with their status, so a partial reproduction still
gives a complete page.

A study's CSV tables are linked, and shown inline when they are small (at most
:data:`INLINE_MAX_ROWS` rows and :data:`INLINE_MAX_COLUMNS` columns): collapsed, except a
sign-off table (a name ending in ``requirements``), which is shown open. An empty CSV cell (a
NaN or an infinity: no finite value, e.g. a percentile bound that too few samples cannot give)
is shown as a dash.
"""

from __future__ import annotations

import csv
import datetime as _dt
import html
import json
import math
import platform
from importlib import resources
from pathlib import Path
from typing import Any

from adcskit import __version__
from adcskit._validation import check_path
from adcskit.errors import InputError

__all__ = ["build_report", "load_results", "format_value"]

ERRORS_FILE = "errors.json"
#: The largest CSV table shown inline in the report (larger ones are only linked).
INLINE_MAX_ROWS = 60
INLINE_MAX_COLUMNS = 16


def format_value(value: Any) -> str:
    """Short human form of a result value: floats to 4 significant digits."""
    if value is None:
        return "—"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, int):
        return f"{value:,}" if abs(value) >= 10000 else str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            return str(value)
        if value == 0:
            return "0"
        a = abs(value)
        if a >= 1e5 or a < 1e-3:
            return f"{value:.3e}"
        return f"{value:.4g}"
    if isinstance(value, list | tuple):
        if len(value) <= 8 and all(not isinstance(v, list | dict) for v in value):
            return "[" + ", ".join(format_value(v) for v in value) + "]"
        return f"[{len(value)} items]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {format_value(v)}" for k, v in list(value.items())[:6]) + ("…}" if len(value) > 6 else "}")
    return str(value)


def load_results(out: str | Path) -> dict[str, dict[str, Any]]:
    """Read every ``out/<study>/result.json`` (keyed by study name).

    Examples
    --------
    >>> import tempfile
    >>> from adcskit.studies import StudyResult, write_result
    >>> with tempfile.TemporaryDirectory() as out:
    ...     _ = write_result(StudyResult(study="demo"), out)
    ...     list(load_results(out))
    ['demo']
    """
    out = check_path("out", out)
    results: dict[str, dict[str, Any]] = {}
    for path in sorted(out.glob("*/result.json")):
        if path.parent.name.startswith("."):
            continue
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, json.JSONDecodeError) as exc:
            results[path.parent.name] = {"study": path.parent.name, "_load_error": str(exc)}
            continue
        results[data.get("study", path.parent.name)] = data
    return results


def _flatten(prefix: str, value: Any, rows: list[tuple[str, str]], limit: int = 60) -> None:
    if len(rows) >= limit:
        return
    if isinstance(value, dict):
        for k, v in value.items():
            _flatten(f"{prefix}.{k}" if prefix else str(k), v, rows, limit)
    else:
        rows.append((prefix, format_value(value)))


#: The paper's verdicts, in the order the report counts them, and their colour classes.
VERDICTS = ("holds", "does not hold", "inconclusive", "depends on reading")
OUTCOME_CLASS = {
    "holds": "ok",
    "does not hold": "bad",
    "inconclusive": "warn",
    "depends on reading": "read",
    "not comparable": "nc",
}

#: The legend of the report: each bucket of :func:`_bucket`, its colour class and meaning.
LEGEND = (
    ("holds", "ok", "every independent seed supports the claim and the 95 % interval lies on its side"),
    ("does not hold", "bad", "the mirror image: no seed supports it and the interval lies on the other side"),
    ("inconclusive", "warn", "seeds disagree, the interval straddles the threshold, a tie within a declared "
                             "margin, a failed seed, or one reading decided while others are not"),
    ("depends on reading", "read", "one documented reading of the paper holds and another does not"),
    ("not comparable", "nc", "the run changed a protocol key of the claim (custom settings); the outcome it got "
                             "is shown beside the label"),
)

#: How a verdict's badge is drawn when it is not a full verdict on the paper.
STYLES = (
    ("ind", "indicative", "pale with a dashed border: fewer than 5 independent seeds (a quick run); "
                          "the outcome those seeds gave, never a verdict on the paper"),
    ("reduced", "reduced protocol", "hatched: decided below the paper's protocol (a protocol key differs "
                                    "from the paper's printed value: hover for which)"),
)


def _custom(c: dict[str, Any]) -> bool:
    """A claim whose protocol keys the user changed (custom settings)."""
    if "protocol" in c:
        return c["protocol"] == "custom settings"
    return not c.get("comparable", True) and not c.get("indicative")  # result.json of an older version


def _bucket(c: dict[str, Any]) -> str:
    """The column a claim is counted in: ``"not comparable"`` under custom settings, else its
    outcome (an indicative outcome keeps its outcome's bucket and is drawn pale)."""
    if _custom(c):
        return "not comparable"
    outcome = c.get("outcome", "inconclusive")
    return outcome if outcome in OUTCOME_CLASS else "inconclusive"


def _held(c: dict[str, Any]) -> str:
    """``"k/n"`` supporting seeds of the default reading (``"n seeds"`` where a count says nothing)."""
    n = int(c.get("n_seeds") or 0)
    f = c.get("fraction_held")
    if c.get("outcome") == "depends on reading" or not isinstance(f, int | float) or not math.isfinite(f):
        return f"{n} seed{'s' if n != 1 else ''}"
    return f"{round(f * n)}/{n}"


def _label(c: dict[str, Any]) -> str:
    """The badge text: the outcome, with what qualifies it (issue 44: an indicative outcome keeps
    its verdict visible, e.g. ``"does not hold · indicative 0/2"``; issue 45: ``"not comparable ·
    holds"`` says what a custom run got)."""
    outcome = c.get("outcome", "inconclusive")
    if _custom(c):
        return f"not comparable · {outcome}"
    if c.get("indicative"):
        return f"{outcome} · indicative {_held(c)}"
    if c.get("protocol") == "reduced protocol":
        return f"{outcome} (reduced protocol)"
    return outcome


def _style(c: dict[str, Any]) -> str:
    """``"ind"``, ``"reduced"`` or ``""``: how :func:`_label`'s badge is drawn."""
    if _custom(c):
        return ""
    if c.get("indicative"):
        return "ind"
    return "reduced" if c.get("protocol") == "reduced protocol" else ""


def _tooltip(c: dict[str, Any]) -> str:
    parts = [f"{_label(c)} — {c.get('statement', '')}"]
    if c.get("indicative"):
        parts.append(f"indicative: {c.get('n_seeds')} independent seeds (fewer than 5), not a verdict on the paper")
    if c.get("quantity"):
        parts.append(f"decided by: {c['quantity']}")
    if c.get("measured") is not None:
        parts.append(f"ours {format_value(c.get('measured'))} {c.get('unit', '')}".rstrip()
                     + (f", paper {format_value(c.get('paper'))}" if c.get("paper") is not None else ""))
    for r in c.get("readings") or []:
        parts.append(f"reading {r.get('reading')}: {r.get('outcome')} ({r.get('n_seeds')} seeds)")
    if c.get("protocol_differences"):
        what = "custom settings" if _custom(c) else "reduced protocol"
        parts.append(f"{what}: " + "; ".join(c["protocol_differences"]))
    if c.get("detail"):
        parts.append(str(c["detail"])[:400])
    return "\n".join(parts)


def _decorate(items: list[dict[str, Any]], study: str, prefix: str) -> list[dict[str, Any]]:
    for i, c in enumerate(items):
        c["bucket"] = _bucket(c)
        c["style"] = _style(c)
        c["label"] = _label(c)
        c["css"] = f"{OUTCOME_CLASS[c['bucket']]} {c['style']}".strip()
        c["anchor"] = f"{study}--{prefix}-{c.get('id') or i}"
        c["tooltip"] = _tooltip(c)
        pale = " ind" if c["style"] == "ind" or c["bucket"] == "not comparable" else ""
        for r in c.get("readings") or []:
            r["css"] = OUTCOME_CLASS.get(r.get("outcome", ""), "nc") + pale
    return items


def _cell(text: str) -> tuple[str, bool]:
    """A CSV cell as shown: numbers through :func:`format_value` (right-aligned), text as is, an
    empty cell (how the CSV writer stores NaN and infinities) as a dash."""
    if not text.strip():
        return format_value(None), True
    try:
        x = float(text)
    except ValueError:
        return text, False
    if text.strip().lstrip("+-").isdigit():
        return format_value(int(text)), True
    return format_value(x), True


def _inline_tables(study_dir: Path, names: list[str]) -> list[dict[str, Any]]:
    """The study's small CSV tables, read for inline display (see the module docstring).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     _ = (Path(d) / "q_requirements.csv").write_text("name,bound\\nR1,0.118\\n")
    ...     t = _inline_tables(Path(d), ["q_requirements.csv", "missing.csv"])
    >>> t[0]["header"], t[0]["rows"], t[0]["open"]
    (['name', 'bound'], [[('R1', False), ('0.118', True)]], True)
    """
    out = []
    for name in names:
        path = study_dir / name
        try:
            with open(path, newline="", encoding="utf-8") as fh:
                rows = list(csv.reader(fh))
        except (OSError, csv.Error, UnicodeDecodeError):
            continue
        if not rows or len(rows) - 1 > INLINE_MAX_ROWS or len(rows[0]) > INLINE_MAX_COLUMNS:
            continue
        out.append({"name": name, "header": rows[0], "rows": [[_cell(c) for c in r] for r in rows[1:]],
                    "open": Path(name).stem.endswith("requirements")})
    return out


def _claims_of(data: dict[str, Any]) -> list[dict[str, Any]]:
    """The claims of a result, with ``bucket``, ``style``, ``label``, ``css``, ``anchor`` and ``tooltip`` set."""
    claims = [dict(c) for c in data.get("claims", [])]
    if not claims and "claims" not in data:  # result.json of an older adcskit version
        claims = [
            {"statement": c.get("name", ""), "outcome": "holds" if c.get("passed") else "does not hold", "detail": c.get("detail", ""), "n_seeds": 1}
            for c in data.get("checks", [])
            if c.get("kind", "claim") == "claim"
        ]
    return _decorate(claims, data.get("study", ""), "claim")


def _tally(items: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Counts of items (from :func:`_decorate`) per bucket and style, in the legend's order:
    ``[{"bucket", "style", "n", "css", "label"}]``, e.g. ``"2 does not hold · indicative"``."""
    out = []
    for bucket in OUTCOME_CLASS:
        for style in ("", "reduced", "ind"):
            n = sum(1 for c in items if c["bucket"] == bucket and c["style"] == style)
            if n:
                label = f"{n} {bucket}" + {"": "", "reduced": " (reduced protocol)", "ind": " · indicative"}[style]
                if bucket == "not comparable":  # the outcomes the custom run got
                    got = [c.get("outcome", "inconclusive") for c in items if c["bucket"] == bucket]
                    label += " (" + ", ".join(f"{got.count(o)} {o}" for o in dict.fromkeys(got)) + ")"
                out.append({"bucket": bucket, "style": style, "n": n, "label": label,
                            "css": f"{OUTCOME_CLASS[bucket]} {style}".strip()})
    return out


def _columns(items: list[dict[str, Any]]) -> dict[str, list[dict[str, Any]]]:
    """:func:`_tally` grouped by bucket: the cells of the first screen's per-study counts."""
    cols: dict[str, list[dict[str, Any]]] = {b: [] for b in OUTCOME_CLASS}
    for t in _tally(items):
        cols[t["bucket"]].append(t)
    return cols


#: The verb of each bucket in the first screen's headline, singular and plural.
_PHRASE = {"holds": ("holds", "hold"), "does not hold": ("does not hold", "do not hold"),
           "inconclusive": ("is inconclusive", "are inconclusive"),
           "depends on reading": ("depends on reading", "depend on reading"),
           "not comparable": ("is not comparable", "are not comparable")}


def _totals(items: list[dict[str, Any]]) -> dict[str, Any]:
    """The first screen's headline over all studies' claims (items from :func:`_decorate`).

    Examples
    --------
    >>> t = _totals(_decorate([{"outcome": "holds"}, {"outcome": "holds", "indicative": True}], "s", "claim"))
    >>> t["n"], t["buckets"], t["indicative"]
    (2, [('holds', '2 hold', 'ok')], 1)
    """
    buckets = []
    for b, css in OUTCOME_CLASS.items():
        n = sum(1 for c in items if c["bucket"] == b)
        if n:
            buckets.append((b, f"{n} {_PHRASE[b][n != 1]}", css))
    return {"n": len(items), "buckets": buckets,
            "indicative": sum(1 for c in items if c["style"] == "ind"),
            "reduced": sum(1 for c in items if c["style"] == "reduced")}


def _doc_href(out: Path, doc: str) -> str | None:
    """A link from the report in ``out`` to the study's documentation page ``doc``
    (``docs/studies/<study>.md``, a path in the repository).

    The built documentation site's page (``docs/_build/html/studies/<study>.html``, made by
    ``sphinx-build -b html docs docs/_build/html``) where it exists, else the Markdown page in
    the repository; both as a path relative to ``out``, so the link survives moving the
    repository with its ``results/`` folder. None when adcskit runs outside a source checkout
    (an installed wheel has no ``docs/``): the report then shows the path as text.
    """
    if not doc:
        return None
    import os

    import adcskit

    root = Path(adcskit.__file__).resolve().parents[2]
    page = Path(doc)
    built = root / "docs" / "_build" / "html" / page.relative_to("docs").with_suffix(".html") \
        if page.parts[:1] == ("docs",) else None
    for target in (built, root / page):
        if target is not None and target.is_file():
            try:
                return Path(os.path.relpath(target, out.resolve())).as_posix()
            except ValueError:  # another drive (Windows): no relative path exists
                return target.as_uri()
    return None


def build_report(out: str | Path, *, title: str = "adcskit — reproduction report") -> Path:
    """Write ``out/index.html`` from the results under ``out`` and return its path.

    Raises
    ------
    InputError
        If ``out`` is not an existing directory.

    Examples
    --------
    >>> import tempfile
    >>> from adcskit.studies import StudyResult, write_result
    >>> with tempfile.TemporaryDirectory() as out:
    ...     _ = write_result(StudyResult(study="demo", summary="a demo"), out)
    ...     build_report(out).name
    'index.html'
    """
    from jinja2 import Environment, select_autoescape

    from adcskit.studies import PAPERS, STUDIES, is_available

    out = check_path("out", out)
    if not out.is_dir():
        raise InputError(f"out (the report directory) must be an existing directory; got {str(out)!r}")
    results = load_results(out)
    errors: dict[str, Any] = {}
    err_path = out / ERRORS_FILE
    if err_path.is_file():
        try:
            errors = json.loads(err_path.read_text(encoding="utf-8"))
        except (OSError, json.JSONDecodeError):
            errors = {}

    names = list(STUDIES) + [n for n in results if n not in STUDIES]
    sections = []
    for name in names:
        info = STUDIES.get(name)
        data = results.get(name)
        section: dict[str, Any] = {
            "name": name,
            "paper_id": info.paper if info else "",
            "citation": PAPERS[info.paper].citation() if info and info.paper in PAPERS else "",
            "description": info.description if info else "",
            "error": errors.get(name),
            "available": is_available(name) if info else True,
        }
        if data is None:
            section["status"] = "failed" if name in errors else ("not run" if section["available"] else "not implemented")
        elif "_load_error" in data:
            section["status"] = "unreadable"
            section["error"] = {"message": data["_load_error"]}
        else:
            claims = _claims_of(data)
            checks = [dict(c) for c in data.get("checks", []) if c.get("kind", "check") == "check"]
            for i, c in enumerate(checks):
                c["anchor"] = f"{name}--check-{i}"
            findings = _decorate([dict(f) for f in data.get("findings", [])], name, "finding")
            flat_paper: list[tuple[str, str]] = []
            flat_measured: list[tuple[str, str]] = []
            if not data.get("comparison"):
                _flatten("", data.get("paper", {}), flat_paper)
                _flatten("", data.get("measured", {}), flat_measured)
            section.update(
                status="failed (stale result shown)" if name in errors else "ok",
                data=data,
                claims=claims,
                checks=checks,
                findings=findings,
                tally=_tally(claims),
                columns=_columns(claims),
                finding_tally=_tally(findings),
                doc_href=_doc_href(out, str(data.get("doc") or "")),
                changes=data.get("config_changes") or {},
                # a key the user changed is shown as a custom setting, not as a reduced protocol
                protocol_differences={k: v for k, v in (data.get("protocol_differences") or {}).items()
                                      if k not in (data.get("config_changes") or {})},
                checks_passed=sum(bool(c.get("passed")) for c in checks),
                flat_paper=flat_paper,
                flat_measured=flat_measured,
                config_json=json.dumps(data.get("config", {}), indent=2),
                inline_tables=_inline_tables(out / name, [str(t) for t in data.get("tables") or []]),
            )
        sections.append(section)

    ran = [s for s in sections if s.get("data")]
    all_claims = [c for s in ran for c in s["claims"]]
    env = Environment(autoescape=select_autoescape(["html", "j2"]), trim_blocks=True, lstrip_blocks=True)
    env.filters["fmt"] = format_value
    template_text = resources.files("adcskit.report").joinpath("templates/report.html.j2").read_text(encoding="utf-8")
    template = env.from_string(template_text)
    page = template.render(
        title=title,
        version=__version__,
        generated=_dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        machine=html.escape(f"{platform.system()} {platform.machine()}, Python {platform.python_version()}"),
        sections=sections,
        legend=LEGEND,
        styles=STYLES,
        verdicts=VERDICTS,
        total=_totals(all_claims),
        custom=[s for s in ran if s["changes"]],
        n_studies=len(STUDIES),
        n_paper_studies=sum(1 for i in STUDIES.values() if i.paper in PAPERS),
        papers=PAPERS,
        any_quick=any(s.get("data", {}).get("quick") for s in sections),
    )
    target = out / "index.html"
    tmp = target.with_suffix(".html.tmp")
    tmp.write_text(page, encoding="utf-8")
    tmp.replace(target)
    return target


