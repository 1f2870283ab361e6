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
import tempfile
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from adcskit._results import to_jsonable
from adcskit._validation import check_flag, check_int
from adcskit.config import config_to_dict, load_config
from adcskit.studies._base import StudyResult
from adcskit.studies._registry import get_study

#: Resolution of every written figure (issue 16: >= 150 dpi, readable when zoomed).
FIGURE_DPI = 150

__all__ = ["config_changes", "resolve_config", "run_study", "write_result", "write_json_atomic"]


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
    """Config keys of ``config`` that differ from the paper's settings of study ``name``.

    The reference is the study's defaults (the paper's settings) with the ``--quick``
    overrides applied when ``quick`` is true (a quick run is reduced, not custom). Returns
    ``{dotted.key: {"value": ours, "paper": default}}``; empty for the paper's settings.
    """
    ref, ours = {}, {}
    _flat("", config_to_dict(resolve_config(name, None, quick=quick)), ref)
    _flat("", config_to_dict(config), ours)
    return {
        k: {"value": to_jsonable(v), "paper": to_jsonable(ref.get(k))}
        for k, v in ours.items()
        if to_jsonable(v) != to_jsonable(ref.get(k))
    }


def _mark_comparable(claims, changes: Mapping[str, Any], neutral: tuple[str, ...] = ()):
    """``claims`` (or findings) with ``comparable`` false where a changed key is one of their protocol keys.

    A claim is compared with the paper; a finding with the answer at the study's documented
    settings (the doc page's full run). Both are judged by the same rule: ``protocol_keys``
    None means that any changed key but the study's ``neutral`` ones (more seeds, execution
    settings) makes it not comparable.
    """
    from dataclasses import replace

    changed = set(changes)
    out = []
    for c in claims:
        if c.protocol_keys is None:
            keys = {k for k in changed if not any(k == n or k.startswith(n + ".") for n in neutral)}
        else:
            keys = {k for k in changed if any(k == p or k.startswith(p + ".") for p in c.protocol_keys)}
        out.append(replace(c, comparable=not keys))
    return tuple(out)


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
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
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
    tmp = Path(tempfile.mkdtemp(dir=out, prefix=f".{result.study}.", suffix=".tmp"))
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
    cfg = resolve_config(name, config, quick=quick)
    owns = not isinstance(executor, Executor)
    ex = make_executor(executor)
    try:
        t0 = time.perf_counter()
        result = study.run(cfg, quick=quick, rng=np.random.default_rng(seed), executor=ex)
        runtime = time.perf_counter() - t0
    finally:
        if owns:
            ex.close()
    from dataclasses import replace

    changes = config_changes(name, cfg, quick=quick)
    result = replace(
        result,
        config=config_to_dict(cfg),
        config_changes=changes,
        claims=_mark_comparable(result.claims, changes, study.neutral_keys),
        findings=_mark_comparable(result.findings, changes, study.neutral_keys),
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
