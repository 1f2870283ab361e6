"""Resumable Monte-Carlo campaigns on any executor.

A campaign maps a picklable function over tasks, in chunks. Each chunk runs as one executor
task and its result is written atomically (temporary file + :func:`os.replace`) to the
campaign directory *by the worker that computed it*, under a name that contains a hash of
the function and of the chunk's tasks. A campaign that is interrupted (Ctrl-C, a crash, a
failing task) keeps every finished chunk on disk; running it again with the same tasks
loads them and computes only the missing ones. Results are returned in task order and do
not depend on the executor (the randomness lives in the tasks, never in the executor).

With ``dask://`` on several machines the directory must be on a shared file system for the
workers' writes to be visible; the parent writes every result it receives as well.

Large inputs common to every task (sample arrays) go in ``shared``: they are sent to the
workers once (scattered on Dask, one temporary file for a process pool) and each task
receives them as a second argument, so a task carries only its own small description (a
seed, an index range). The chunk file names then hash ``shared`` as well.

Hand-written here: only the chunk/checkpoint bookkeeping; the pools are
:mod:`adcskit.uncertainty.executor`'s.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import tempfile
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from adcskit._results import compact_repr
from adcskit._validation import check_callable, check_int, check_path, short_repr
from adcskit.errors import InputError, InputTypeError
from adcskit.uncertainty.executor import NO_SHARED, Executor, make_executor

__all__ = ["CampaignResult", "run_campaign"]


@compact_repr
@dataclass(frozen=True, slots=True, kw_only=True)
class CampaignResult:
    """Outcome of :func:`run_campaign`.

    Attributes
    ----------
    values : list
        ``fn(task)`` for every task, in task order.
    n_chunks : int
        Number of chunks.
    n_resumed : int
        Chunks loaded from the campaign directory instead of being computed.
    directory : str or None
        Where chunk results are kept (None: not kept).
    executor : str
        Spec of the executor that ran the computed chunks.

    Examples
    --------
    >>> import math
    >>> from adcskit.uncertainty import run_campaign
    >>> res = run_campaign(math.sqrt, [1.0, 4.0, 9.0], chunk_size=2)
    >>> type(res).__name__, res.values, res.n_chunks, res.n_resumed, res.executor
    ('CampaignResult', [1.0, 2.0, 3.0], 2, 0, 'serial')
    """

    values: list
    n_chunks: int
    n_resumed: int
    directory: str | None
    executor: str

    def to_dict(self) -> dict[str, Any]:
        return {
            "n_values": len(self.values),
            "n_chunks": self.n_chunks,
            "n_resumed": self.n_resumed,
            "directory": self.directory,
            "executor": self.executor,
        }


def _digest(fn: Callable[[Any], Any], tasks: Sequence[Any], shared_digest: str = "") -> str:
    h = hashlib.sha256()
    h.update(f"{getattr(fn, '__module__', '?')}.{getattr(fn, '__qualname__', repr(fn))}".encode())
    h.update(pickle.dumps(list(tasks), protocol=4))
    h.update(shared_digest.encode())
    return h.hexdigest()[:16]


def _shared_digest(shared: Any) -> str:
    """Hash of the shared data (arrays hashed from their buffers, without a pickled copy)."""
    if shared is NO_SHARED:
        return ""
    h = hashlib.sha256()

    def feed(obj: Any) -> None:
        if isinstance(obj, np.ndarray):
            a = np.ascontiguousarray(obj)
            h.update(f"ndarray{a.dtype.str}{a.shape}".encode())
            h.update(memoryview(a).cast("B"))
        elif isinstance(obj, dict):
            h.update(b"dict")
            for k in sorted(obj, key=repr):
                h.update(repr(k).encode())
                feed(obj[k])
        elif isinstance(obj, (list, tuple)):
            h.update(type(obj).__name__.encode())
            for v in obj:
                feed(v)
        else:
            h.update(pickle.dumps(obj, protocol=4))

    feed(shared)
    return h.hexdigest()


def _write_atomic(path: Path, value: Any) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            pickle.dump(value, fh, protocol=4)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _run_chunk(payload: tuple[Callable[[Any], Any], list, str | None], *shared: Any) -> list:
    fn, chunk, path = payload
    values = [fn(t, *shared) for t in chunk]
    if path is not None:
        _write_atomic(Path(path), values)
    return values


def run_campaign(
    fn: Callable[[Any], Any],
    tasks: Sequence[Any],
    *,
    executor: str | Executor | None = None,
    directory: str | os.PathLike[str] | None = None,
    chunk_size: int | None = None,
    description: str = "campaign",
    shared: Any = NO_SHARED,
) -> CampaignResult:
    """Run ``fn`` over ``tasks`` in chunks on ``executor``, keeping finished chunks on disk.

    Parameters
    ----------
    fn : callable
        A picklable (module-level) function of one task, ``fn(task)``, or of a task and the
        shared data, ``fn(task, shared)`` when ``shared`` is given.
    tasks : sequence
        Picklable tasks; each carries its own seed (or its slice of ``shared``), so results
        are the same on every executor.
    executor : spec or Executor, optional
        ``serial`` (default), ``processes[:N]``, ``dask-local[:N]``, ``dask://HOST:PORT``.
    directory : path, optional
        Campaign directory for chunk results; with it, a re-run resumes.
    chunk_size : int, optional
        Tasks per chunk (default: spread over ``4 × n_workers`` chunks).
    description : str
        Progress-bar label.
    shared : object, optional
        Picklable data common to every task (e.g. a dict of sample arrays), sent to the
        workers once instead of inside every task.

    Returns
    -------
    CampaignResult
        Values in task order, and how many chunks were resumed.

    Examples
    --------
    >>> import math, tempfile
    >>> from adcskit.uncertainty import run_campaign
    >>> with tempfile.TemporaryDirectory() as d:
    ...     first = run_campaign(math.sqrt, [1.0, 4.0, 9.0, 16.0], directory=d, chunk_size=2)
    ...     again = run_campaign(math.sqrt, [1.0, 4.0, 9.0, 16.0], directory=d, chunk_size=2)
    >>> first.values, first.n_resumed
    ([1.0, 2.0, 3.0, 4.0], 0)
    >>> again.values, again.n_resumed                    # every chunk loaded from disk
    ([1.0, 2.0, 3.0, 4.0], 2)
    """
    check_callable("fn", fn)
    if isinstance(tasks, str | bytes) or not isinstance(tasks, Iterable):
        raise InputTypeError(f"tasks must be a sequence of tasks; got {short_repr(tasks)}")
    tasks = list(tasks)
    if not tasks:
        raise InputError("tasks must not be empty")
    if directory is not None:
        directory = check_path("directory", directory, writable_dir=True)
        try:
            directory.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"directory cannot be created: {str(directory)!r} ({exc.strerror})") from None
    owns = not isinstance(executor, Executor)
    ex = make_executor(executor)
    try:
        if chunk_size is None:
            n_chunks_target = max(1, 4 * ex.n_workers)
            chunk_size = max(1, -(-len(tasks) // n_chunks_target))
        chunk_size = check_int("chunk_size", chunk_size, minimum=1)
        chunks = [tasks[i : i + chunk_size] for i in range(0, len(tasks), chunk_size)]
        root = Path(directory) if directory is not None else None
        sdig = _shared_digest(shared) if root is not None else ""
        paths: list[Path | None] = []
        for j, chunk in enumerate(chunks):
            paths.append(None if root is None else root / f"chunk_{j:05d}_{_digest(fn, chunk, sdig)}.pkl")
        results: list[list | None] = [None] * len(chunks)
        n_resumed = 0
        for j, path in enumerate(paths):
            if path is not None and path.exists():
                try:
                    with open(path, "rb") as fh:
                        results[j] = pickle.load(fh)
                    n_resumed += 1
                except (OSError, pickle.UnpicklingError, EOFError):
                    results[j] = None  # a damaged file is recomputed
        todo = [j for j in range(len(chunks)) if results[j] is None]
        if todo:
            payloads = [(fn, chunks[j], None if paths[j] is None else str(paths[j])) for j in todo]
            computed = ex.map(_run_chunk, payloads, description=description, shared=shared)
            for j, values in zip(todo, computed):
                results[j] = values
                path = paths[j]
                if path is not None and not path.exists():
                    _write_atomic(path, values)
        values = [v for chunk_values in results for v in chunk_values]  # type: ignore[union-attr]
        return CampaignResult(
            values=values,
            n_chunks=len(chunks),
            n_resumed=n_resumed,
            directory=None if root is None else str(root),
            executor=ex.spec,
        )
    finally:
        if owns:
            ex.close()
