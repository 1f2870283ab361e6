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
    An existing ``dask.distributed`` scheduler (``tcp://HOST:PORT``); see
    ``docs/user-guide.md`` ("Running a campaign on a Dask cluster").

Data shared by every task (e.g. the Monte-Carlo sample arrays) is passed once, as
``map(fn, tasks, shared=data)``, and every task then runs ``fn(task, data)``: the serial
executor passes the object, the process pool writes it once to a temporary file that each
worker loads once, and Dask scatters it once to the workers (:meth:`Client.scatter`,
broadcast, under a fresh random key per call, released once the results are back), so the
task graph holds only the small tasks and a reference to the data — never a copy of the
data per task. Tasks that are large themselves (a closed-loop campaign's tasks carry their
samples: 0.6 kB per sample) are scattered to the workers too, when together they hold
:data:`SCATTER_TASKS_BYTES` or more of arrays: each task under its own random key, spread
over the workers, so that the data goes to a worker directly instead of through the
scheduler inside the graph.

Hand-written here: only the thin adapter; the pools are the standard library's and Dask's.
"""

from __future__ import annotations

import abc
import concurrent.futures as cf
import multiprocessing
import os
import pickle
import tempfile
import uuid
from collections.abc import Callable, Iterable, Sequence, Sized
from pathlib import Path
from typing import Any

import numpy as np

from adcskit._progress import bar, track
from adcskit._validation import _first_line, check_callable, check_int, check_positive, short_repr
from adcskit.errors import InputError, InputTypeError

__all__ = [
    "Executor",
    "SerialExecutor",
    "ProcessExecutor",
    "DaskExecutor",
    "make_executor",
    "EXECUTOR_SPECS",
    "SCATTER_TASKS_BYTES",
]

EXECUTOR_SPECS = ("serial", "processes[:N]", "dask-local[:N]", "dask://HOST:PORT")

#: Seconds a :class:`DaskExecutor` waits for the scheduler at ``address`` to answer.
CONNECT_TIMEOUT_S = 5.0

#: Largest worker count an executor spec may ask for.
MAX_SPEC_WORKERS = 1024

NO_SHARED: Any = type("NoShared", (), {"__repr__": lambda self: "NO_SHARED"})()
"""Sentinel: ``map`` called without shared data (``fn(task)`` instead of ``fn(task, shared)``)."""

SCATTER_TASKS_BYTES: int = 8 * 2**20
"""A Dask ``map`` whose tasks hold at least this many bytes of arrays in all scatters the tasks
to the workers instead of putting them in the task graph (Dask warns from 10 MB of graph)."""


def _array_bytes(obj: Any, limit: int, depth: int = 0) -> int:
    """Bytes of the NumPy arrays and byte strings in ``obj`` (tuples, lists, dict values),
    counted until ``limit`` is reached."""
    if isinstance(obj, np.ndarray):
        return int(obj.nbytes)
    if isinstance(obj, bytes | bytearray | memoryview):
        return len(obj)
    if depth > 8:
        return 0
    items = obj.values() if isinstance(obj, dict) else obj if isinstance(obj, list | tuple) else ()
    total = 0
    for item in items:
        total += _array_bytes(item, limit - total, depth + 1)
        if total >= limit:
            break
    return total

# --- shared data for process-pool workers: one file, loaded once per worker -------------
_WORKER_SHARED: dict[str, Any] = {}


def _load_shared(path: str, token: str) -> Any:
    if token not in _WORKER_SHARED:
        _WORKER_SHARED.clear()  # one campaign at a time per worker
        with open(path, "rb") as fh:
            _WORKER_SHARED[token] = pickle.load(fh)
    return _WORKER_SHARED[token]


def _apply_file_shared(fn: Callable[[Any, Any], Any], task: Any, path: str, token: str) -> Any:
    return fn(task, _load_shared(path, token))


def _apply_shared(task: Any, fn: Callable[[Any, Any], Any], shared: Any) -> Any:
    return fn(task, shared)


class Executor(abc.ABC):
    """Maps a function over tasks; results come back in task order.

    Examples
    --------
    >>> import math
    >>> from adcskit.uncertainty import Executor, make_executor
    >>> ex = make_executor("serial")
    >>> isinstance(ex, Executor), ex.n_workers
    (True, 1)
    >>> ex.map(math.pow, [1.0, 2.0, 3.0], shared=2.0)        # fn(task, shared) in task order
    [1.0, 4.0, 9.0]
    """

    spec: str = "?"

    @property
    @abc.abstractmethod
    def n_workers(self) -> int:
        """Number of tasks that run at once."""

    @abc.abstractmethod
    def map(
        self,
        fn: Callable[..., Any],
        tasks: Sequence[Any],
        *,
        description: str = "tasks",
        shared: Any = NO_SHARED,
    ) -> list[Any]:
        """Return ``[fn(t) for t in tasks]`` (or ``[fn(t, shared) ...]``), computed here.

        ``shared`` is sent to the workers once, not once per task.
        """

    def close(self) -> None:  # noqa: B027 - optional hook
        """Release workers (no-op for the serial executor)."""

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.spec!r})"


class SerialExecutor(Executor):
    """Runs every task in the calling process, in order.

    Examples
    --------
    >>> import math
    >>> from adcskit.uncertainty import SerialExecutor
    >>> with SerialExecutor() as ex:
    ...     print(ex.spec, ex.n_workers, ex.map(math.sqrt, [1.0, 4.0, 9.0]))
    serial 1 [1.0, 2.0, 3.0]
    """

    spec = "serial"

    @property
    def n_workers(self) -> int:
        return 1

    def map(self, fn, tasks, *, description="tasks", shared=NO_SHARED):
        _check_map(fn, tasks)
        args = () if shared is NO_SHARED else (shared,)
        return [fn(t, *args) for t in track(tasks, description, total=len(tasks))]


def _check_map(fn: Any, tasks: Any) -> None:
    """Boundary check of ``Executor.map``: a callable and a sized sequence of tasks."""
    check_callable("fn", fn)
    if isinstance(tasks, str | bytes) or not isinstance(tasks, Sized) or not isinstance(tasks, Iterable):
        raise InputTypeError(f"tasks must be a sequence of tasks; got {short_repr(tasks)}")


class ProcessExecutor(Executor):
    """A local process pool (``spawn`` start method).

    Examples
    --------
    >>> import math
    >>> from adcskit.uncertainty import ProcessExecutor
    >>> with ProcessExecutor(n_workers=2) as ex:
    ...     print(ex.spec, ex.map(math.sqrt, [1.0, 4.0, 9.0]))
    processes:2 [1.0, 2.0, 3.0]
    """

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

    def map(self, fn, tasks, *, description="tasks", shared=NO_SHARED):
        _check_map(fn, tasks)
        tmpdir = None
        if shared is NO_SHARED:
            futures = {self._pool.submit(fn, t): i for i, t in enumerate(tasks)}
        else:
            tmpdir = tempfile.TemporaryDirectory(prefix="adcskit-shared-")
            path = str(Path(tmpdir.name) / "shared.pkl")
            with open(path, "wb") as fh:
                pickle.dump(shared, fh, protocol=pickle.HIGHEST_PROTOCOL)
            token = uuid.uuid4().hex
            futures = {
                self._pool.submit(_apply_file_shared, fn, t, path, token): i
                for i, t in enumerate(tasks)
            }
        results: list[Any] = [None] * len(futures)
        try:
            for fut in track(cf.as_completed(futures), description, total=len(futures)):
                results[futures[fut]] = fut.result()
        except BaseException:
            for fut in futures:
                fut.cancel()
            raise
        finally:
            if tmpdir is not None:
                cf.wait(futures)  # no worker may still be reading the file
                tmpdir.cleanup()
        return results

    def close(self) -> None:
        self._pool.shutdown(wait=True, cancel_futures=True)


class DaskExecutor(Executor):
    """Tasks on a ``dask.distributed`` cluster: a new local one or an existing scheduler.

    Parameters
    ----------
    address : str, optional
        ``tcp://HOST:PORT`` of a running scheduler; None starts a
        :class:`~dask.distributed.LocalCluster` on 127.0.0.1.
    n_workers : int, optional
        Worker processes of the local cluster (one thread each; default: CPU count). Not
        used with ``address``.
    timeout : float, s, optional
        Longest time one :meth:`map` may take (scatter, tasks and results together); past it
        the outstanding tasks are cancelled and :class:`TimeoutError` is raised. None (the
        default) waits as long as the tasks take. Connecting to ``address`` waits at most
        :data:`CONNECT_TIMEOUT_S` (or ``timeout`` if shorter); a scheduler that does not answer
        in that time raises :class:`~adcskit.errors.InputError` naming the address.

    Notes
    -----
    Shared data is scattered once per :meth:`map` call, broadcast to every worker, under a
    fresh random key (``hash=False`` on a one-element list). A dict is never scattered as
    such: :meth:`Client.scatter` would use its keys as Dask keys, so two successive calls
    with the same keys would share them, and releasing the first call's data would delete the
    second's (issue 23: ``FutureCancelledError ... lost dependencies``). The reference is held
    until every result is back and released afterwards.

    Tasks holding :data:`SCATTER_TASKS_BYTES` or more of arrays in all are scattered the same
    way (one random key per task, not broadcast: each goes to one worker and its task
    normally runs there) and released with the results; without this, a 10⁶-sample
    closed-loop campaign put 572 MiB of samples in the task graph.

    A worker that dies mid-campaign costs only its running tasks: the scheduler reruns them
    on another worker (up to ``distributed.scheduler.allowed-failures`` times per task). If
    every copy of the shared data is lost with it (it cannot be recomputed), :meth:`map`
    scatters it again and resubmits the tasks that did not finish, at most
    ``max_resubmits`` times. Every task is a pure function of its own seed and the shared
    data, so the results are the same as without the failure.

    The local cluster's logs are silenced (``silence_logs=CRITICAL``): every failure of a
    task reaches the caller as the exception :meth:`map` raises.

    Examples
    --------
    >>> import math
    >>> from adcskit.uncertainty import DaskExecutor
    >>> with DaskExecutor(n_workers=2) as ex:     # LocalCluster: slow start  # doctest: +SKIP
    ...     print(ex.n_workers, ex.map(math.sqrt, [1.0, 4.0, 9.0]))
    2 [1.0, 2.0, 3.0]
    >>> from adcskit.uncertainty import Executor
    >>> issubclass(DaskExecutor, Executor), DaskExecutor.max_resubmits
    (True, 3)
    """

    max_resubmits: int = 3
    """Rounds of re-scatter + resubmission after the shared data was lost with its workers."""

    def __init__(
        self, address: str | None = None, n_workers: int | None = None, *, timeout: float | None = None
    ) -> None:
        import logging

        from dask.distributed import Client, LocalCluster

        if n_workers is not None:
            n_workers = check_int("n_workers", n_workers, minimum=1, maximum=1024)
        if timeout is not None:
            timeout = check_positive("timeout", timeout, unit="s")
        if address is not None and not isinstance(address, str):
            raise InputTypeError(f"address must be a string 'tcp://HOST:PORT'; got {short_repr(address)}")
        self._timeout = timeout
        self._cluster = None
        if address is None:
            n = int(n_workers or os.cpu_count() or 1)
            self._cluster = LocalCluster(
                n_workers=n,
                threads_per_worker=1,
                processes=True,
                dashboard_address="127.0.0.1:0",
                host="127.0.0.1",
                silence_logs=logging.CRITICAL,
            )
            self._client = Client(self._cluster)
            self.spec = f"dask-local:{n}"
        else:
            connect = CONNECT_TIMEOUT_S if timeout is None else min(timeout, CONNECT_TIMEOUT_S)
            try:
                self._client = Client(address, timeout=connect)
            except (OSError, TimeoutError) as exc:  # refused, unreachable, no scheduler
                raise InputError(
                    f"executor address {address!r} is not reachable: no Dask scheduler answered "
                    f"within {connect:g} s ({type(exc).__name__}: {_first_line(exc)})"
                ) from None
            self.spec = f"dask://{address.removeprefix('tcp://')}"

    @property
    def client(self):
        """The :class:`dask.distributed.Client` (e.g. to inspect or restart workers)."""
        return self._client

    @property
    def dashboard_link(self) -> str:
        """URL of the Dask dashboard."""
        return self._client.dashboard_link

    @property
    def n_workers(self) -> int:
        info = self._client.scheduler_info()
        return max(1, sum(w.get("nthreads", 1) for w in info.get("workers", {}).values()))

    def map(self, fn, tasks, *, description="tasks", shared=NO_SHARED):
        import time

        _check_map(fn, tasks)
        tasks = list(tasks)
        results: list[Any] = [None] * len(tasks)
        todo = list(range(len(tasks)))
        if not todo:
            return results
        deadline = None if self._timeout is None else time.monotonic() + self._timeout
        reason = ""
        with bar(description, len(tasks)) as advance:
            for _ in range(1 + self.max_resubmits):
                todo, reason = self._round(fn, tasks, todo, shared, results, advance, deadline)
                if not todo:
                    return results
        raise RuntimeError(
            f"Dask lost {len(todo)} of {len(tasks)} tasks after {1 + self.max_resubmits} submissions "
            f"on {self.spec}: {reason}"
        )

    def _round(self, fn, tasks, todo, shared, results, advance, deadline):
        """Submit ``tasks[todo]`` once; return the indices whose futures were lost, and why."""
        import time

        from dask.distributed import TimeoutError as DaskTimeoutError
        from dask.distributed import as_completed

        client = self._client
        left = None if deadline is None else max(1e-3, deadline - time.monotonic())
        ref = None
        task_refs: list[Any] = []
        futures: list[Any] = []
        lost: list[int] = []
        reason = ""
        try:
            args: list[Any] = [tasks[i] for i in todo]
            if _array_bytes(args, SCATTER_TASKS_BYTES) >= SCATTER_TASKS_BYTES:
                # large tasks (a closed-loop campaign's samples) go straight to the workers, one
                # fresh random key each, spread over them; the graph holds only references
                task_refs = client.scatter(args, hash=False, timeout=left)
                args = task_refs
            if shared is NO_SHARED:
                futures = client.map(fn, args, pure=False)
            else:
                # one fresh random key per call: a one-element list with hash=False, never the
                # dict itself (Client.scatter would use the dict's keys as Dask keys)
                [ref] = client.scatter([shared], broadcast=True, hash=False, timeout=left)
                futures = client.map(_apply_shared, args, fn=fn, shared=ref, pure=False)
            index = {f.key: i for f, i in zip(futures, todo, strict=True)}
            left = None if deadline is None else max(1e-3, deadline - time.monotonic())
            for fut in as_completed(futures, timeout=left):
                try:
                    value = fut.result(timeout=None if deadline is None else max(1e-3, deadline - time.monotonic()))
                except cf.CancelledError as exc:  # lost with a worker, with the shared data it needs
                    lost.append(index[fut.key])
                    reason = str(exc)
                    continue
                results[index[fut.key]] = value
                advance(1)
        except (DaskTimeoutError, TimeoutError) as exc:
            client.cancel(futures)
            if deadline is None or time.monotonic() < deadline:
                raise  # a task's own TimeoutError, not this map's deadline
            raise TimeoutError(
                f"Dask map on {self.spec} did not finish within timeout = {self._timeout:g} s"
            ) from exc
        except BaseException:
            client.cancel(futures)
            raise
        finally:
            if ref is not None:
                ref.release()  # the workers drop the shared data once no task needs it
            for task_ref in task_refs:
                task_ref.release()
        return sorted(lost), reason

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
    if not 1 <= n <= MAX_SPEC_WORKERS:
        raise InputError(
            f"executor spec {spec!r} must end with a worker count in [1, {MAX_SPEC_WORKERS}] after ':'; got {text!r}"
        )
    return n


def make_executor(spec: str | Executor | None = None) -> Executor:
    """Build an executor from a spec string (see the module docstring).

    Raises
    ------
    InputError
        If ``spec`` is not one of ``serial``, ``processes[:N]``, ``dask-local[:N]`` or
        ``dask://HOST:PORT``.

    Examples
    --------
    >>> from adcskit.uncertainty import make_executor
    >>> make_executor("serial")
    SerialExecutor('serial')
    >>> make_executor(None).n_workers                     # default: serial
    1
    >>> ex = make_executor("processes:2")                 # spawn pool; workers start on first map
    >>> ex.n_workers
    2
    >>> ex.close()
    """
    if spec is None:
        return SerialExecutor()
    if isinstance(spec, Executor):
        return spec
    if not isinstance(spec, str):
        raise InputTypeError(
            f"executor spec must be an Executor or a string, one of {', '.join(EXECUTOR_SPECS)}; got {short_repr(spec)}"
        )
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
        if not host or not port.isdigit() or not 1 <= int(port) <= 65535:
            raise InputError(
                f"executor spec 'dask://HOST:PORT' needs a host and a numeric port in [1, 65535]; got {spec!r}"
            )
        return DaskExecutor("tcp://" + address)
    raise InputError(f"executor spec must be one of {', '.join(EXECUTOR_SPECS)}; got {spec!r}")
