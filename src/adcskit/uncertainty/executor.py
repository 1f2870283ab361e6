"""Executors: run independent tasks serially, on a process pool, or on a Dask cluster.

An executor maps a picklable function over a sequence of tasks and returns the results in
task order, whatever order they finish in. Randomness never comes from the executor: every
task carries its own seed (spawned with :class:`numpy.random.SeedSequence`), so the same
campaign gives bit-identical results on every executor.

Specs (the CLI's ``--executor``):

``serial``
    In this process (the default).
``processes[:N]``
    A :class:`concurrent.futures.ProcessPoolExecutor` with ``N`` workers (default: CPU
    count), started with the ``spawn`` method so that numba/threads in the parent are safe.
``dask-local[:N]``
    A :class:`dask.distributed.LocalCluster` with ``N`` single-threaded worker processes
    (default: CPU count); its dashboard is bound to 127.0.0.1 on a free port.
``dask://HOST:PORT``
    An existing ``dask.distributed`` scheduler (``tcp://HOST:PORT``).

Hand-written here: only the thin adapter; the pools are the standard library's and Dask's.
"""

from __future__ import annotations

import abc
import concurrent.futures as cf
import multiprocessing
import os
from collections.abc import Callable, Iterable, Sequence, Sized
from typing import Any

from adcskit._progress import track
from adcskit._validation import check_callable, check_int, short_repr
from adcskit.errors import InputError, InputTypeError

__all__ = [
    "Executor",
    "SerialExecutor",
    "ProcessExecutor",
    "DaskExecutor",
    "make_executor",
    "EXECUTOR_SPECS",
]

EXECUTOR_SPECS = ("serial", "processes[:N]", "dask-local[:N]", "dask://HOST:PORT")


class Executor(abc.ABC):
    """Maps a function over tasks; results come back in task order."""

    spec: str = "?"

    @property
    @abc.abstractmethod
    def n_workers(self) -> int:
        """Number of tasks that run at once."""

    @abc.abstractmethod
    def map(self, fn: Callable[[Any], Any], tasks: Sequence[Any], *, description: str = "tasks") -> list[Any]:
        """Return ``[fn(t) for t in tasks]``, computed by this executor."""

    def close(self) -> None:  # noqa: B027 - optional hook
        """Release workers (no-op for the serial executor)."""

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.spec!r})"


class SerialExecutor(Executor):
    """Runs every task in the calling process, in order."""

    spec = "serial"

    @property
    def n_workers(self) -> int:
        return 1

    def map(self, fn, tasks, *, description="tasks"):
        _check_map(fn, tasks)
        return [fn(t) for t in track(tasks, description, total=len(tasks))]


def _check_map(fn: Any, tasks: Any) -> None:
    """Boundary check of ``Executor.map``: a callable and a sized sequence of tasks."""
    check_callable("fn", fn)
    if isinstance(tasks, str | bytes) or not isinstance(tasks, Sized) or not isinstance(tasks, Iterable):
        raise InputTypeError(f"tasks must be a sequence of tasks; got {short_repr(tasks)}")


class ProcessExecutor(Executor):
    """A local process pool (``spawn`` start method)."""

    def __init__(self, n_workers: int | None = None) -> None:
        if n_workers is not None:
            n_workers = check_int("n_workers", n_workers, minimum=1, maximum=1024)
        n = n_workers or os.cpu_count() or 1
        self._n = int(n)
        self.spec = f"processes:{self._n}"
        self._pool = cf.ProcessPoolExecutor(
            max_workers=self._n, mp_context=multiprocessing.get_context("spawn")
        )

    @property
    def n_workers(self) -> int:
        return self._n

    def map(self, fn, tasks, *, description="tasks"):
        _check_map(fn, tasks)
        futures = {self._pool.submit(fn, t): i for i, t in enumerate(tasks)}
        results: list[Any] = [None] * len(futures)
        try:
            for fut in track(cf.as_completed(futures), description, total=len(futures)):
                results[futures[fut]] = fut.result()
        except BaseException:
            for fut in futures:
                fut.cancel()
            raise
        return results

    def close(self) -> None:
        self._pool.shutdown(wait=True, cancel_futures=True)


class DaskExecutor(Executor):
    """Tasks on a ``dask.distributed`` cluster: a new local one or an existing scheduler."""

    def __init__(self, address: str | None = None, n_workers: int | None = None) -> None:
        from dask.distributed import Client, LocalCluster

        self._cluster = None
        if address is None:
            n = int(n_workers or os.cpu_count() or 1)
            self._cluster = LocalCluster(
                n_workers=n,
                threads_per_worker=1,
                processes=True,
                dashboard_address="127.0.0.1:0",
                host="127.0.0.1",
                silence_logs=40,
            )
            self._client = Client(self._cluster)
            self.spec = f"dask-local:{n}"
        else:
            self._client = Client(address, timeout=30)
            self.spec = f"dask://{address.removeprefix('tcp://')}"

    @property
    def dashboard_link(self) -> str:
        """URL of the Dask dashboard."""
        return self._client.dashboard_link

    @property
    def n_workers(self) -> int:
        info = self._client.scheduler_info()
        return max(1, sum(w.get("nthreads", 1) for w in info.get("workers", {}).values()))

    def map(self, fn, tasks, *, description="tasks"):
        from dask.distributed import as_completed

        futures = self._client.map(fn, list(tasks), pure=False)
        index = {f.key: i for i, f in enumerate(futures)}
        results: list[Any] = [None] * len(futures)
        try:
            for fut in track(as_completed(futures), description, total=len(futures)):
                results[index[fut.key]] = fut.result()
        except BaseException:
            self._client.cancel(futures)
            raise
        return results

    def close(self) -> None:
        self._client.close()
        if self._cluster is not None:
            self._cluster.close()


def _parse_count(spec: str, text: str) -> int | None:
    if not text:
        return None
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise InputError(
            f"executor spec {spec!r} must end with a positive worker count after ':'; got {text!r}"
        )
    return n


def make_executor(spec: str | Executor | None = None) -> Executor:
    """Build an executor from a spec string (see the module docstring).

    Raises
    ------
    InputError
        If ``spec`` is not one of ``serial``, ``processes[:N]``, ``dask-local[:N]`` or
        ``dask://HOST:PORT``.
    """
    if spec is None:
        return SerialExecutor()
    if isinstance(spec, Executor):
        return spec
    if not isinstance(spec, str):
        raise InputError(f"executor must be one of {', '.join(EXECUTOR_SPECS)}; got {spec!r}")
    s = spec.strip()
    if s == "serial":
        return SerialExecutor()
    name, _, count = s.partition(":")
    if name == "processes":
        return ProcessExecutor(_parse_count(spec, count))
    if name == "dask-local":
        return DaskExecutor(None, _parse_count(spec, count))
    if s.startswith("dask://"):
        address = s.removeprefix("dask://")
        host, _, port = address.rpartition(":")
        if not host or not port.isdigit():
            raise InputError(f"executor 'dask://HOST:PORT' needs a host and a numeric port; got {spec!r}")
        return DaskExecutor("tcp://" + address)
    raise InputError(f"executor must be one of {', '.join(EXECUTOR_SPECS)}; got {spec!r}")
