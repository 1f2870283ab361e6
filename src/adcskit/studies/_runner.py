"""Run a registered study and write its outputs atomically.

Outputs of ``run_study(name, out=DIR)`` go to ``DIR/<name>/``: ``result.json``, one PNG per
figure and one CSV per table. They are first written to a temporary sibling directory and
swapped in only when complete, so an interrupted run (Ctrl-C, crash) never leaves a
half-written study directory and never destroys the previous complete result.
"""

from __future__ import annotations

import csv
import io
import json
import os
import shutil
import time
import uuid
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from adcskit._progress import status
from adcskit._results import to_jsonable
from adcskit._validation import check_flag, check_int
from adcskit.config import config_to_dict, load_config
from adcskit.studies._base import StudyResult
from adcskit.studies._registry import get_study

#: Resolution of every written figure (issue 16: >= 150 dpi, readable when zoomed).
FIGURE_DPI = 150

__all__ = ["config_changes", "protocol_differences", "resolve_config", "run_study", "write_result", "write_json_atomic"]


def resolve_config(name: str, config: Mapping[str, Any] | str | Path | None = None, *, quick: bool = False):
    """The study's config dataclass: defaults <- quick overrides <- ``config``.

    Examples
    --------
    >>> resolve_config("wahba-table1", {"n_trials": 50}).n_trials
    50
    """
    study = get_study(name)
    quick = check_flag("quick", quick)
    return load_config(study.config_cls, config, overrides=study.quick if quick else None)


def _flat(prefix: str, value: Any, out: dict[str, Any]) -> None:
    if isinstance(value, Mapping):
        for k, v in value.items():
            _flat(f"{prefix}.{k}" if prefix else str(k), v, out)
    else:
        out[prefix] = value


def config_changes(name: str, config: Any, *, quick: bool = False) -> dict[str, dict[str, Any]]:
    """Config keys of ``config`` that differ from the study's settings of study ``name``.

    The reference is the study's defaults with the ``--quick`` overrides applied when
    ``quick`` is true (a quick run is reduced, not custom). Returns ``{dotted.key: {"value":
    ours, "default": the study's setting, "paper": the paper's value}}``, where "paper" is the
    printed value the top-level key declares (``protocol(..., paper=...)``), ``"not printed"``,
    or ``"not declared"`` (a neutral key, or one that declares nothing). Our defaults are never
    recorded as the paper's. Empty for the study's settings.
    """
    from adcskit.studies._base import paper_protocol

    ref, ours = {}, {}
    _flat("", config_to_dict(resolve_config(name, None, quick=quick)), ref)
    _flat("", config_to_dict(config), ours)
    printed = paper_protocol(get_study(name).config_cls)
    out = {}
    for k, v in ours.items():
        if to_jsonable(v) == to_jsonable(ref.get(k)):
            continue
        top = k.split(".", 1)[0]
        paper = printed.get(top, "not declared")
        if "." in k and isinstance(paper, Mapping):
            _sub: dict[str, Any] = {}
            _flat(top, paper, _sub)
            paper = _sub.get(k, "not declared")
        out[k] = {"value": to_jsonable(v), "default": to_jsonable(ref.get(k)), "paper": to_jsonable(paper)}
    return out


def protocol_differences(config_cls: Any, config: Any) -> dict[str, dict[str, Any]]:
    """Protocol keys whose value in ``config`` differs from the value the paper prints.

    Returns ``{key: {"value": ours, "paper": printed}}``; keys whose paper value is
    ``"not printed"`` (or undeclared) never differ.
    """
    from adcskit.studies._base import NOT_PRINTED, paper_protocol

    ours = config_to_dict(config)
    out = {}
    for k, p in paper_protocol(config_cls).items():
        if isinstance(p, str) and p == NOT_PRINTED:
            continue
        if to_jsonable(ours.get(k)) != to_jsonable(p):
            out[k] = {"value": to_jsonable(ours.get(k)), "paper": to_jsonable(p)}
    return out


def _quick_reductions(name: str, config: Any) -> dict[str, dict[str, Any]]:
    """The ``--quick`` overrides that differ from the study's full settings, as protocol differences.

    A quick run is below our documented full run even where the paper prints nothing (a coarser
    grid, fewer trials): its claims and findings on those keys read "reduced protocol".
    ``paper`` names the printed value, or the full run's setting when the paper prints none.
    """
    from adcskit.studies._base import NOT_PRINTED, paper_protocol

    full = config_to_dict(resolve_config(name, None, quick=False))
    ours = config_to_dict(config)
    printed = paper_protocol(get_study(name).config_cls)
    neutral = set(get_study(name).neutral_keys)  # fewer seeds: indicative, not a reduced protocol
    out = {}
    for k in get_study(name).quick:
        if k in neutral:
            continue
        if k in ours and to_jsonable(ours[k]) != to_jsonable(full.get(k)):
            p = printed.get(k, NOT_PRINTED)
            shown = p if not (isinstance(p, str) and p == NOT_PRINTED) else f"not printed; full run {to_jsonable(full.get(k))!r}"
            out[k] = {"value": to_jsonable(ours[k]), "paper": to_jsonable(shown)}
    return out


def _in(key: str, names) -> bool:
    return any(key == n or key.startswith(n + ".") for n in names)


def _mark_comparable(claims, changes: Mapping[str, Any], neutral: tuple[str, ...] = (),
                     differences: Mapping[str, Any] | None = None):
    """``claims`` (or findings) with ``protocol``, ``protocol_differences`` and ``comparable`` set.

    A claim's protocol keys are its ``protocol_keys`` (None: every key but the study's
    ``neutral`` ones). It is ``"custom settings"`` when the run changed one of them against
    the study's settings (``changes``), else ``"reduced protocol"`` when one differs from the
    paper's printed value (``differences``), else ``"paper protocol"``. It is comparable only
    at the paper's protocol and when not indicative (fewer than ``MIN_SEEDS`` seeds).
    """
    from dataclasses import replace

    from adcskit.studies._verdict import CUSTOM_SETTINGS, PAPER_PROTOCOL, REDUCED_PROTOCOL

    differences = differences or {}
    # a change *to* the paper's printed value is not a custom setting (e.g. a paper-scale run)
    changes = {k: v for k, v in changes.items() if to_jsonable(v.get("value")) != to_jsonable(v.get("paper"))}
    out = []
    for c in claims:
        if c.protocol_keys is None:
            changed = [k for k in changes if not _in(k, neutral)]
            differ = [k for k in differences if not _in(k, neutral)]
        else:
            changed = [k for k in changes if _in(k, c.protocol_keys)]
            differ = [k for k in differences if _in(k, c.protocol_keys)]
        if changed:
            status = CUSTOM_SETTINGS
            what = [f"{k}: ours {changes[k]['value']!r}, study setting {changes[k]['default']!r}" for k in changed]
        elif differ:
            status = REDUCED_PROTOCOL
            what = [f"{k}: ours {differences[k]['value']!r}, paper {differences[k]['paper']!r}" for k in differ]
        else:
            status, what = PAPER_PROTOCOL, []
        out.append(replace(c, protocol=status, protocol_differences=tuple(what),
                           comparable=status == PAPER_PROTOCOL and not c.indicative))
    return tuple(out)


def _temp_name(name: str) -> str:
    """A hidden, unique sibling name for writing ``name`` before an atomic rename."""
    return f".{name}.{uuid.uuid4().hex}.tmp"


def write_json_atomic(path: Path, data: Any) -> None:
    """Write ``data`` as JSON to ``path`` via a temporary file and an atomic rename.

    ``data`` goes through :func:`adcskit._results.to_jsonable` first (NaN becomes ``null``);
    a reader never sees a half-written file, and a failed write leaves no temporary file.

    Parameters
    ----------
    path : str or pathlib.Path
        Target file; its directory is created if missing.
    data : object
        Anything :func:`~adcskit._results.to_jsonable` converts.

    Examples
    --------
    >>> import json, tempfile, pathlib
    >>> from adcskit.studies import write_json_atomic
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "errors.json"
    >>> write_json_atomic(p, {"ratio": float("nan"), "n": 3})
    >>> json.loads(p.read_text())
    {'ratio': None, 'n': 3}
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.parent / _temp_name(path.name)
    # created like any file (0o666 less the umask), not mkstemp's private 0o600
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            json.dump(to_jsonable(data), fh, indent=2, allow_nan=False)
            fh.write("\n")
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _write_csv(path: Path, rows: list[Mapping[str, Any]]) -> None:
    columns: list[str] = []
    for row in rows:
        for key in row:
            if key not in columns:
                columns.append(key)
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: _csv_cell(v) for k, v in row.items()})
    path.write_text(buf.getvalue(), encoding="utf-8")


def _csv_cell(v: Any) -> Any:
    v = to_jsonable(v)
    if isinstance(v, list | dict):
        return json.dumps(v)
    return "" if v is None else v


def write_result(result: StudyResult, out: str | Path) -> Path:
    """Write ``result`` into ``out/<study>/`` atomically and return that directory.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from adcskit.studies import StudyResult
    >>> with tempfile.TemporaryDirectory() as out:
    ...     d = write_result(StudyResult(study="demo"), out)
    ...     sorted(p.name for p in d.iterdir())
    ['result.json']
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    final = out / result.study
    tmp = out / _temp_name(result.study)
    tmp.mkdir()  # 0o777 less the umask, like the directory it replaces (not mkdtemp's 0o700)
    try:
        for stem, fig in result.figures.items():
            fig.savefig(tmp / f"{stem}.png", dpi=FIGURE_DPI)
        for stem, rows in result.tables.items():
            _write_csv(tmp / f"{stem}.csv", list(rows))
        write_json_atomic(tmp / "result.json", result.to_dict())
        old = None
        if final.exists():
            old = out / f".{result.study}.old-{os.getpid()}-{time.monotonic_ns()}"
            os.replace(final, old)
        os.replace(tmp, final)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    finally:
        # release figure memory; Figures made with matplotlib.figure.Figure need no pyplot
        for fig in result.figures.values():
            try:
                fig.clear()
            except Exception:  # noqa: BLE001 - never mask the real outcome
                pass
    return final


def run_study(
    name: str,
    *,
    config: Mapping[str, Any] | str | Path | None = None,
    quick: bool = False,
    seed: int = 0,
    out: str | Path | None = "results",
    executor: Any = None,
) -> StudyResult:
    """Run study ``name`` and (unless ``out`` is None) write its outputs.

    Parameters
    ----------
    name : str
        Registered study name (``adcskit list``).
    config : mapping or path, optional
        Config overrides (TOML file or mapping); unknown keys are an error.
    quick : bool
        Use the study's reduced-but-honest settings.
    seed : int
        Root seed; the study gets ``numpy.random.default_rng(seed)``.
    out : path or None
        Results directory.
    executor : spec or Executor, optional
        Where campaigns run (see :func:`adcskit.uncertainty.make_executor`).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as out:  # doctest: +SKIP
    ...     result = run_study("onoff-schmitt", quick=True, out=out)
    ...     print(result.claims[0].outcome)
    """
    from adcskit.uncertainty.executor import Executor, make_executor

    seed = check_int("seed", seed, minimum=0)
    study = get_study(name)
    requested = resolve_config(name, config, quick=quick)
    cfg = study.resolve(requested, seed) if study.resolve is not None else requested
    owns = not isinstance(executor, Executor)
    ex = make_executor(executor)
    try:
        # a stage line for every study, also those without stages of their own (shown inside a
        # progress session, and forwarded to the console by `reproduce --jobs N`)
        status(f"{name}: started ({'quick' if quick else 'full'} settings, seed {seed})")
        t0 = time.perf_counter()
        result = study.run(cfg, quick=quick, rng=np.random.default_rng(seed), executor=ex)
        runtime = time.perf_counter() - t0
    finally:
        if owns:
            ex.close()
    from dataclasses import replace

    # a change is a key the user changed (the request against the study's settings) whose run
    # value differs from the study's setting. The study's own resolve step (onoff-tuning: S4's
    # protocol from the stored GAs) is the study's setting, not a custom configuration: it is
    # recorded in ``config`` but never counted as a change.
    asked = config_changes(name, requested, quick=quick)
    changes = {k: v for k, v in config_changes(name, cfg, quick=quick).items() if k in asked}
    differ = protocol_differences(study.config_cls, cfg)
    reduced = _quick_reductions(name, cfg) if quick else {}
    result = replace(
        result,
        config=config_to_dict(cfg),
        config_changes=changes,
        protocol_differences=differ,
        claims=_mark_comparable(result.claims, changes, study.neutral_keys, {**reduced, **differ}),
        # a finding is our question, compared with our documented (full-run) settings, not the paper
        findings=_mark_comparable(result.findings, changes, study.neutral_keys, reduced),
        seed=seed,
        quick=quick,
        runtime_s=runtime,
        executor=ex.spec,
        title=result.title or study.title,
        doc=result.doc or study.doc,
    )
    if out is not None:
        write_result(result, out)
    return result
