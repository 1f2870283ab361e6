"""Study pages that cannot go stale: generated blocks and quoted values from a committed snapshot.

Each study page ``docs/studies/<study>.md`` quotes one stored full run, its *snapshot*
``docs/studies/snapshots/<study>.json`` (:func:`snapshot_of` of that run's ``result.json``:
everything but the large per-sample arrays). Two kinds of marked text in the page are
generated from it and nothing else:

* **blocks** ``<!-- BEGIN generated:KIND -->`` ... ``<!-- END generated:KIND -->`` with KIND
  one of ``run`` (which run, when, where), ``claims``, ``findings``, ``checks``,
  ``protocol`` (what differs from the paper's protocol) and ``statements`` (each paper
  statement of the study's ``paper.STATEMENTS`` to its claim id, or to "not decided: reason");
* **inline values** ``<!--v PATH FORMAT-->text<!--/v-->``: ``PATH`` is a dotted path into the
  snapshot (``claims.<id>.measured``, ``claims.<id>.readings.<reading>.outcome``,
  ``findings.<id>.interval.0``, ``measured.fuel_ns``, ``comparison.2.measured``) and
  ``FORMAT`` a Python format spec (``.3g``) or ``s`` (as text).

:func:`render_page` rewrites both from the snapshot; ``tests/test_pages.py`` fails when a
page and its snapshot disagree. ``adcskit pages --results DIR`` writes the snapshots of a full
run and regenerates the pages; ``adcskit pages --results DIR --check`` compares a new run with
the committed snapshots: every outcome (claims, findings, each reading, checks) exactly, values
to 1e-6 relative, except the values of stochastic optimisers (:data:`OPTIMISER_RTOL`: another
CPU's floating point moves an optimiser's path) and of timing claims (not compared by value).
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from adcskit.errors import InputError

__all__ = ["BLOCKS", "OPTIMISER_RTOL", "Statement", "compare_snapshots", "load_snapshot", "render_page", "resolve", "snapshot_of",
           "study_statements", "sync_pages", "value_rtol"]

#: The generated block kinds a page may hold.
BLOCKS = ("run", "claims", "findings", "checks", "protocol", "statements")

_BLOCK = re.compile(r"(<!-- BEGIN generated:(\w+) -->\n)(.*?)(<!-- END generated:\2 -->)", re.S)
_VALUE = re.compile(r"<!--v ([^ >]+) ([^ >]+)-->(.*?)<!--/v-->", re.S)

#: ``measured`` entries kept in a snapshot: scalars, strings and short lists only.
_MAX_LIST = 12

#: Declared relative tolerance of the ``measured`` values that come from a stochastic optimiser
#: (GA, DE, NSGA-II), per study and claim / finding id prefix: on another CPU the floating point
#: of the first generations differs in the last bits and the population takes another path.
#: Measured between two CPUs with every outcome equal (issue 45): thruster-layout
#: de-more-accurate 13.43 vs 13.29 (1.1 %), wahba-orbit rms-50pct 0.0031378 vs 0.0031372
#: (0.02 %), an NSGA-II knee -2.52 vs -2.50 (0.8 %); declared 5 %, four times the largest.
#: Outcomes are always compared exactly.
OPTIMISER_RTOL: dict[str, tuple[float, tuple[str, ...]]] = {
    "thruster-layout": (0.05, ("de-more-accurate", "six-thrusters-best", "optimal-layout-less-fuel",
                               "table8-e-min", "de-settings-n6")),
    "wahba-orbit": (0.05, ("rms-50pct",)),
    "wahba-table1": (0.05, ("nsga2-", "knee-beats-qmethod")),
}


@dataclass(frozen=True, slots=True, kw_only=True)
class Statement:
    """One statement of the paper and where the study decides it.

    Attributes
    ----------
    where : str
        Section, table or figure of the paper.
    text : str
        The paper's words (shortened).
    claim : str or None
        The claim id that decides it; None when we do not decide it.
    reason : str
        Why it is not decided (required when ``claim`` is None).

    Examples
    --------
    >>> Statement(where="Fig. 5", text="0.25 deg accuracy", claim="pointing-accuracy-0.25deg").claim
    'pointing-accuracy-0.25deg'
    >>> Statement(where="§5", text="the loop is stable", claim=None, reason="no margin is printed").reason
    'no margin is printed'
    """

    where: str
    text: str
    claim: str | None = None
    reason: str = ""

    def __post_init__(self) -> None:
        if self.claim is None and not self.reason.strip():
            raise InputError(f"statement {self.text!r}: claim is None, so give the reason it is not decided")


def _prune(value: Any) -> Any:
    if isinstance(value, Mapping):
        out = {}
        for k, v in value.items():
            p = _prune(v)
            if p is not _DROP:
                out[k] = p
        return out
    if isinstance(value, list):
        if len(value) > _MAX_LIST:
            return _DROP
        items = [_prune(v) for v in value]
        return _DROP if any(i is _DROP for i in items) else items
    return value


_DROP = object()


def snapshot_of(result: Mapping[str, Any], *, commit: str = "", date: str = "", command: str = "",
                machine: str = "") -> dict[str, Any]:
    """The committed snapshot of one study's full run: ``result.json`` without bulky arrays.

    Parameters
    ----------
    result : mapping
        A parsed ``result.json``.
    commit, date, command, machine : str
        Provenance of the run, shown in the page's ``run`` block.

    Examples
    --------
    >>> snap = snapshot_of({"study": "demo", "quick": False, "measured": {"x": 1.5, "trace": list(range(100))},
    ...                     "claims": [], "findings": [], "checks": []}, date="2026-12-01")
    >>> snap["measured"], snap["provenance"]["date"]
    ({'x': 1.5}, '2026-12-01')
    """
    if result.get("quick"):
        raise InputError("result is a --quick run; a page quotes a full run (run without --quick)")
    keep = ("study", "title", "adcskit_version", "config", "seed", "quick", "runtime_s", "executor", "paper",
            "claims", "findings", "checks", "config_changes", "protocol_differences", "comparison", "differences")
    snap = {k: result.get(k) for k in keep}
    snap["measured"] = _prune(result.get("measured") or {})
    snap["provenance"] = {"commit": commit, "date": date, "command": command, "machine": machine}
    for kind in ("claims", "findings"):
        for c in snap.get(kind) or []:
            for r in c.get("readings") or []:
                if len(r.get("values") or []) > _MAX_LIST:
                    r["values"] = r["values"][:_MAX_LIST]
    return snap


def resolve(snapshot: Mapping[str, Any], path: str) -> Any:
    """The value at a dotted ``path`` of ``snapshot`` (claims, findings, readings and checks by id).

    An id or key that itself contains dots (``pointing-accuracy-0.25deg``) is matched whole:
    the longest run of path segments that names an entry wins.

    Examples
    --------
    >>> snap = {"claims": [{"id": "c1", "measured": 0.5, "readings": [{"reading": "max", "outcome": "holds"}]},
    ...                    {"id": "acc-0.25deg", "measured": 0.04}]}
    >>> resolve(snap, "claims.c1.measured"), resolve(snap, "claims.c1.readings.max.outcome")
    (0.5, 'holds')
    >>> resolve(snap, "claims.acc-0.25deg.measured")
    0.04
    """
    parts = path.split(".")
    node: Any = snapshot
    i = 0
    while i < len(parts):
        found = False
        for j in range(len(parts), i, -1):  # longest key first
            key = ".".join(parts[i:j])
            if isinstance(node, list):
                if key.lstrip("-").isdigit() and -len(node) <= int(key) < len(node):
                    node, found = node[int(key)], True
                else:
                    keyed = [x for x in node if isinstance(x, Mapping) and key in (x.get("id"), x.get("reading"),
                                                                                     x.get("name"))]
                    if keyed:
                        node, found = keyed[0], True
            elif isinstance(node, Mapping) and key in node:
                node, found = node[key], True
            if found:
                i = j
                break
        if not found:
            _missing(path, parts[i])
    return node


def _missing(path: str, part: str) -> Any:
    raise InputError(f"page value {path!r}: no entry {part!r} in the snapshot")


def _fmt(value: Any, spec: str) -> str:
    if spec == "s" or isinstance(value, str):
        return str(value)
    if value is None:
        return "n/a"
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float) and not math.isfinite(value):
        return "n/a"
    return format(value, spec)


def _cell(v: Any) -> str:
    if v is None:
        return "—"
    if isinstance(v, float):
        return f"{v:.4g}"
    if isinstance(v, list):
        return "[" + ", ".join(_cell(x) for x in v) + "]"
    return str(v).replace("|", "\\|").replace("\n", " ")


def _outcome(c: Mapping[str, Any]) -> str:
    shown = c.get("display_outcome") or c.get("outcome", "")
    text = f"**{shown}**"
    readings = c.get("readings") or []
    if readings:
        text += " (" + "; ".join(f"{_cell(r['reading'])}: {r['outcome']}" for r in readings) + ")"
    return text


def _verdict_table(items: Sequence[Mapping[str, Any]], *, claims: bool) -> str:
    if not items:
        return "None in this study.\n"
    head = ("| id | where | deciding quantity | outcome (per reading) | ours | paper |\n|---|---|---|---|---|---|\n"
            if claims else "| id | question | deciding quantity | outcome (per reading) | ours |\n|---|---|---|---|---|\n")
    rows = []
    for c in items:
        ours = _cell(c.get("measured"))
        if c.get("unit") and c.get("measured") is not None:
            ours += f" {c['unit']}"
        seeds = f"{c.get('n_seeds', 1)} seed{'s' if c.get('n_seeds', 1) != 1 else ''}"
        if claims:
            rows.append(f"| `{c['id']}` | {_cell(c.get('where'))} | {_cell(c.get('quantity'))} | {_outcome(c)} | "
                        f"{ours} ({seeds}) | {_cell(c.get('paper'))} |")
        else:
            rows.append(f"| `{c['id']}` | {_cell(c.get('statement'))} | {_cell(c.get('quantity'))} | {_outcome(c)} | "
                        f"{ours} ({seeds}) |")
    return head + "\n".join(rows) + "\n"


def _block(kind: str, snap: Mapping[str, Any], statements: Sequence[Statement]) -> str:
    if kind == "run":
        p = snap.get("provenance") or {}
        rt = snap.get("runtime_s")
        rt_s = f"{rt:.0f} s wall" if isinstance(rt, int | float) else "n/a"
        return (f"Quoted run: `{p.get('command') or 'adcskit reproduce'}`, seed {snap.get('seed')}, "
                f"{p.get('date') or 'date not recorded'}, commit `{p.get('commit') or '?'}`, "
                f"adcskit {snap.get('adcskit_version')}, {rt_s} ({p.get('machine') or 'machine not recorded'}). "
                f"Snapshot: `docs/studies/snapshots/{snap.get('study')}.json`.\n")
    if kind == "claims":
        return _verdict_table(snap.get("claims") or [], claims=True)
    if kind == "findings":
        return _verdict_table(snap.get("findings") or [], claims=False)
    if kind == "checks":
        checks = snap.get("checks") or []
        if not checks:
            return "None in this study.\n"
        return ("| check | passed | evidence |\n|---|---|---|\n"
                + "\n".join(f"| {_cell(c['name'])} | {'yes' if c['passed'] else '**no**'} | {_cell(c.get('detail'))} |"
                            for c in checks) + "\n")
    if kind == "protocol":
        diff = snap.get("protocol_differences") or {}
        if not diff:
            return "Every protocol key the paper prints is at the paper's value: claims are at the paper's protocol.\n"
        return ("Below the paper's protocol (the claims using these keys read \"reduced protocol\"):\n\n"
                "| key | ours | paper |\n|---|---|---|\n"
                + "\n".join(f"| `{k}` | {_cell(v.get('value'))} | {_cell(v.get('paper'))} |" for k, v in diff.items())
                + "\n")
    if kind == "statements":
        if not statements:
            raise InputError(f"study {snap.get('study')!r} declares no paper.STATEMENTS for its statements block")
        by_id = {c["id"]: c for c in snap.get("claims") or []}
        rows = []
        for s in statements:
            if s.claim is None:
                rows.append(f"| {_cell(s.where)} | {_cell(s.text)} | — | not decided: {_cell(s.reason)} |")
            elif s.claim not in by_id:
                raise InputError(f"statement {s.text!r} names claim {s.claim!r}, not in the snapshot; "
                                 f"claims: {sorted(by_id)}")
            else:
                rows.append(f"| {_cell(s.where)} | {_cell(s.text)} | `{s.claim}` | {_outcome(by_id[s.claim])} |")
        return "| where | the paper's statement | claim | outcome |\n|---|---|---|---|\n" + "\n".join(rows) + "\n"
    raise InputError(f"unknown generated block {kind!r}; allowed: {BLOCKS}")


def render_page(text: str, snapshot: Mapping[str, Any], statements: Sequence[Statement] = ()) -> str:
    """``text`` with every generated block and inline value rewritten from ``snapshot``.

    Examples
    --------
    >>> snap = {"study": "demo", "claims": [{"id": "c1", "measured": 0.04417, "outcome": "holds"}]}
    >>> render_page("max error <!--v claims.c1.measured .3f-->0.1<!--/v--> deg", snap)
    'max error <!--v claims.c1.measured .3f-->0.044<!--/v--> deg'
    """
    def block(m: re.Match) -> str:
        return m.group(1) + "\n" + _block(m.group(2), snapshot, statements) + "\n" + m.group(4)

    def value(m: re.Match) -> str:
        return f"<!--v {m.group(1)} {m.group(2)}-->{_fmt(resolve(snapshot, m.group(1)), m.group(2))}<!--/v-->"

    return _VALUE.sub(value, _BLOCK.sub(block, text))


def _close(a: Any, b: Any, rtol: float) -> bool:
    if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, int | float) or not isinstance(b, int | float):
        return a == b
    return math.isclose(a, b, rel_tol=rtol, abs_tol=1e-12)


def value_rtol(study: str, ident: str, default: float = 1e-6) -> float:
    """The relative tolerance of one claim's or finding's value between two runs.

    :data:`OPTIMISER_RTOL` for a value of a stochastic optimiser, else ``default``.

    >>> value_rtol("thruster-layout", "de-more-accurate"), value_rtol("wahba-table1", "error-7x")
    (0.05, 1e-06)
    """
    rtol, prefixes = OPTIMISER_RTOL.get(study, (default, ()))
    return rtol if any(ident.startswith(p) for p in prefixes) else default


def compare_snapshots(new: Mapping[str, Any], old: Mapping[str, Any], *, rtol: float = 1e-6) -> list[str]:
    """Differences between two snapshots of the same study, in words (empty: equal).

    Outcomes must be equal for every claim, finding, reading and check, timing claims included
    (a reading that flips between runs is a failure: a timing claim declares the margin within
    which a ratio is a tie). Values (``measured``) within ``rtol``, or the declared
    :data:`OPTIMISER_RTOL` of a stochastic optimiser's value; a timing claim's value (a measured
    time) and ``runtime_s`` are not compared.

    Examples
    --------
    >>> a = {"claims": [{"id": "c", "outcome": "holds", "measured": 1.0}], "findings": [], "checks": []}
    >>> compare_snapshots(a, a)
    []
    """
    out = []
    study = str(new.get("study") or old.get("study") or "")
    for kind in ("claims", "findings"):
        olds = {c["id"]: c for c in old.get(kind) or []}
        news = {c["id"]: c for c in new.get(kind) or []}
        for i in sorted(set(olds) ^ set(news)):
            out.append(f"{kind[:-1]} {i!r} is only in the {'new run' if i in news else 'snapshot'}")
        for i in sorted(set(olds) & set(news)):
            o, n = olds[i], news[i]
            if o.get("outcome") != n.get("outcome"):
                out.append(f"{kind[:-1]} {i!r}: outcome {o.get('outcome')!r} -> {n.get('outcome')!r}")
            ro = {r["reading"]: r["outcome"] for r in o.get("readings") or []}
            rn = {r["reading"]: r["outcome"] for r in n.get("readings") or []}
            if ro != rn:
                out.append(f"{kind[:-1]} {i!r}: readings {ro} -> {rn}")
            if o.get("timing") or n.get("timing"):
                continue  # a measured time: outcomes only
            tol = max(rtol, value_rtol(study, i, rtol))
            if not _close(o.get("measured"), n.get("measured"), tol):
                out.append(f"{kind[:-1]} {i!r}: measured {o.get('measured')!r} -> {n.get('measured')!r}"
                           + (f" (beyond the declared optimiser tolerance {tol:g})" if tol > rtol else ""))
    oc = [(c["name"], c["passed"]) for c in old.get("checks") or []]
    nc = [(c["name"], c["passed"]) for c in new.get("checks") or []]
    if oc != nc:
        out.append(f"checks differ: {sorted(set(oc) ^ set(nc))}")
    return out


def load_snapshot(path: str | Path) -> dict[str, Any]:
    """Read a snapshot file (a clear error when it is missing)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"snapshot {str(path)!r} does not exist; write it with `adcskit pages --results DIR`")
    return json.loads(path.read_text(encoding="utf-8"))


def study_statements(name: str) -> tuple[Statement, ...]:
    """The ``STATEMENTS`` a study's ``paper.py`` declares (empty when it declares none)."""
    import importlib

    from adcskit.studies._registry import get_study

    module = get_study(name).run.__module__  # adcskit.studies.<package>
    try:
        return tuple(getattr(importlib.import_module(f"{module}.paper"), "STATEMENTS", ()))
    except ModuleNotFoundError:
        return ()


def sync_pages(docs: str | Path, names: Sequence[str], *, results: str | Path | None = None, check: bool = False,
               provenance: Mapping[str, str] | None = None) -> list[str]:
    """Write snapshots from ``results`` (when given) and regenerate the study pages under ``docs``.

    With ``check``: write nothing; return the differences between ``results`` and the committed
    snapshots (:func:`compare_snapshots`) and the pages that are not what their snapshot
    generates. Without: return the files written.
    """
    docs = Path(docs)
    snapdir = docs / "snapshots"
    report: list[str] = []
    for name in names:
        page = docs / f"{name}.md"
        snap_path = snapdir / f"{name}.json"
        if results is not None:
            rj = Path(results) / name / "result.json"
            if not rj.is_file():
                raise InputError(f"results {str(results)!r} has no {name}/result.json")
            new = snapshot_of(json.loads(rj.read_text(encoding="utf-8")), **dict(provenance or {}))
            if check:
                report += [f"{name}: {d}" for d in compare_snapshots(new, load_snapshot(snap_path))]
                continue
            snapdir.mkdir(parents=True, exist_ok=True)
            snap_path.write_text(json.dumps(new, indent=1, allow_nan=False) + "\n", encoding="utf-8")
            report.append(str(snap_path))
        snap = load_snapshot(snap_path)
        text = page.read_text(encoding="utf-8")
        rendered = render_page(text, snap, study_statements(name))
        if check:
            if rendered != text:
                report.append(f"{name}: page {str(page)!r} differs from what its snapshot generates")
        elif rendered != text:
            page.write_text(rendered, encoding="utf-8")
            report.append(str(page))
    return report
