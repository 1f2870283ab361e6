"""Render ``DIR/index.html`` from the ``DIR/<study>/result.json`` files.

The page shows, per study: the paper's values beside ours (the study's ``comparison`` rows),
a verdict per claim, our sanity checks, what we did differently from the paper and why,
the figures, CSV tables and the resolved configuration. Studies that are registered but
not yet run, or that failed, are listed with their status, so a partial reproduction still
gives a complete page.
"""

from __future__ import annotations

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


OUTCOME_CLASS = {
    "holds": "ok",
    "does not hold": "bad",
    "inconclusive": "warn",
    "depends on reading": "read",
    "not comparable": "muted",
}


def _display_outcome(c: dict[str, Any]) -> str:
    return c.get("outcome", "inconclusive") if c.get("comparable", True) else "not comparable"


def _claims_of(data: dict[str, Any]) -> list[dict[str, Any]]:
    """The claims of a result, with ``display`` and ``css`` set (old result files: checks of kind claim)."""
    claims = [dict(c) for c in data.get("claims", [])]
    if not claims and "claims" not in data:  # result.json of an older adcskit version
        claims = [
            {"statement": c.get("name", ""), "outcome": "holds" if c.get("passed") else "does not hold", "detail": c.get("detail", ""), "n_seeds": 1}
            for c in data.get("checks", [])
            if c.get("kind", "claim") == "claim"
        ]
    for c in claims:
        c["display"] = _display_outcome(c)
        c["css"] = OUTCOME_CLASS.get(c["display"], "muted")
    return claims


def _tally(items: list[dict[str, Any]]) -> list[tuple[str, int, str]]:
    """``[(outcome, count, css)]`` for the outcomes present, in a fixed order."""
    for c in items:
        c.setdefault("display", _display_outcome(c))
        c.setdefault("css", OUTCOME_CLASS.get(c["display"], "muted"))
    order = list(OUTCOME_CLASS)
    counts = {o: sum(1 for c in items if c["display"] == o) for o in order}
    return [(o, n, OUTCOME_CLASS[o]) for o, n in counts.items() if n]


def _verdict_class(claims: list[dict[str, Any]]) -> str:
    """Badge colour of a study's claim tally: green only when every claim holds."""
    if not claims:
        return "muted"
    shown = {c["display"] for c in claims}
    if shown == {"holds"}:
        return "ok"
    if "holds" not in shown:
        return "bad" if "does not hold" in shown else "warn"
    return "warn"


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
            checks = [c for c in data.get("checks", []) if c.get("kind", "check") == "check"]
            findings = list(data.get("findings", []))
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
                finding_tally=_tally(findings),
                verdict_class=_verdict_class(claims),
                changes=data.get("config_changes") or {},
                checks_passed=sum(bool(c.get("passed")) for c in checks),
                flat_paper=flat_paper,
                flat_measured=flat_measured,
                config_json=json.dumps(data.get("config", {}), indent=2),
            )
        sections.append(section)

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
        papers=PAPERS,
        any_quick=any(s.get("data", {}).get("quick") for s in sections),
    )
    target = out / "index.html"
    tmp = target.with_suffix(".html.tmp")
    tmp.write_text(page, encoding="utf-8")
    tmp.replace(target)
    return target


