"""The campaign engine on Dask (issue 23, item 4): successive maps that share data under the
same dict keys, a worker killed mid-campaign, the onoff-tuning campaign path, and an existing
cluster reached as ``dask://HOST:PORT``.

Every comparison is bit for bit against the serial executor: the randomness lives in the tasks
(design.md: same seed -> bit-identical results). Every Dask wait is bounded (the executors'
``timeout``, ``wait_for_workers(timeout=...)``, subprocess timeouts), so a lost task fails a test
instead of hanging CI, and the clusters' logs are silenced.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from adcskit.uncertainty import DaskExecutor, SerialExecutor, run_campaign

pytest.importorskip("dask.distributed")

TESTS = Path(__file__).resolve().parents[1]
SRC = TESTS.parent / "src"
WAIT_S = 60.0  # bound of every wait for workers / processes in this file


# --- task functions (module level: the workers import them from this module by name) ------
def _weighted(task, shared):
    """Task (lo, hi, key): sum of shared[key][lo:hi] * shared['disturbance'][lo:hi].

    ``key`` is the string 'inertia': with the old scatter of the dict itself, a task argument
    equal to a Dask key was replaced by that key's data (Client.scatter notes)."""
    lo, hi, key = task
    return float(np.sum(shared[key][lo:hi] * shared["disturbance"][lo:hi]))


def _slow_weighted(task, shared):
    """``_weighted`` that first records (file ``<lo>.<pid>`` in ``task[3]``) which worker
    process started it, then takes 0.1 s, so that a worker can be killed mid-campaign."""
    lo, hi, key, marks = task
    Path(marks, f"{lo}.{os.getpid()}").touch()
    time.sleep(0.1)
    return _weighted((lo, hi, key), shared)


def _shared(seed: int, n: int = 600) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    return {"inertia": rng.normal(10.0, 2.0, n), "disturbance": rng.normal(0.05, 0.05, n)}


def _n_scheduler_tasks(client) -> int:
    return client.run_on_scheduler(lambda dask_scheduler: len(dask_scheduler.tasks))


def _wait_until(predicate, what: str, timeout: float = WAIT_S) -> None:
    end = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > end:
            raise AssertionError(f"timed out after {timeout:g} s waiting for {what}")
        time.sleep(0.05)


def test_successive_maps_sharing_a_dict_with_the_same_keys_equal_serial(dask_local2):
    # issue 23's reproduction: 20 successive maps, shared = {'inertia': ..., 'disturbance': ...}
    # with the same keys every call; on main 89cf3b6 the 2nd call ended in FutureCancelledError
    # (lost dependencies) because the dict's keys were the Dask keys of the scattered data
    import test_dask as mod  # the workers import the task function by this name

    tasks = [(lo, lo + 150, "inertia") for lo in range(0, 600, 150)]
    for call in range(20):
        shared = _shared(call)
        expected = SerialExecutor().map(mod._weighted, tasks, shared=shared)
        assert dask_local2.map(mod._weighted, tasks, shared=shared) == expected, f"call {call}"
    # the shared data and the results are released once a map has returned
    _wait_until(lambda: _n_scheduler_tasks(dask_local2.client) == 0, "the scheduler to forget every key")


def _sleep(seconds):
    time.sleep(seconds)
    return seconds


def _raise_timeout(_):
    raise TimeoutError("the task's own timeout")


def test_a_map_past_its_timeout_raises_instead_of_hanging(dask_local2):
    import test_dask as mod

    # a second client of the session's cluster, with a short bound on each map
    with DaskExecutor(dask_local2.client.scheduler.address, timeout=0.3) as ex:
        with pytest.raises(TimeoutError, match=r"did not finish within timeout = 0.3 s"):
            ex.map(mod._sleep, [1.5, 1.5])
        with pytest.raises(TimeoutError, match="the task's own timeout"):  # not mistaken for ours
            dask_local2.map(mod._raise_timeout, [0])
    assert dask_local2.map(mod._sleep, [0.0, 0.0]) == [0.0, 0.0]  # the cluster is usable again


def _kill_mid_campaign(pids: list[int], marks: Path, n_started: int, victims: str, killed: list[int]):
    """Watchdog thread body: once ``n_started`` tasks have started, SIGKILL the worker process
    that ran the first task (``victims='one'``) or every worker process (``victims='all'``)."""
    end = time.monotonic() + WAIT_S
    while len(os.listdir(marks)) < n_started:
        if time.monotonic() > end:
            return
        time.sleep(0.01)
    first = sorted(os.listdir(marks), key=lambda name: int(name.split(".")[0]))[0]
    targets = pids if victims == "all" else [int(first.split(".")[1])]
    for pid in targets:
        os.kill(pid, signal.SIGKILL)
    killed.extend(targets)


@pytest.mark.parametrize("victims", ["one", "all"])
def test_worker_killed_mid_campaign_still_equals_serial(dask_local2, tmp_path, victims):
    # one worker killed: the scheduler reruns its tasks on the other one (the shared data is
    # broadcast to both). Every worker killed: the shared data is lost with them and cannot be
    # recomputed, so map scatters it again and resubmits the unfinished tasks.
    import test_dask as mod

    client = dask_local2.client
    client.wait_for_workers(2, timeout=WAIT_S)
    marks = tmp_path / "started"
    marks.mkdir()
    tasks = [(lo, lo + 25, "inertia", str(marks)) for lo in range(0, 600, 25)]  # 24 tasks
    shared = _shared(99)
    expected = SerialExecutor().map(mod._weighted, [t[:3] for t in tasks], shared=shared)
    pids = list(client.run(os.getpid).values())
    killed: list[int] = []
    watchdog = threading.Thread(target=_kill_mid_campaign, args=(pids, marks, 4, victims, killed))
    watchdog.start()
    try:
        got = dask_local2.map(mod._slow_weighted, tasks, shared=shared)
    finally:
        watchdog.join(WAIT_S)
    assert len(killed) == (2 if victims == "all" else 1)
    assert got == expected
    ran_on = {int(name.split(".")[1]) for name in os.listdir(marks)}
    assert ran_on - set(killed), "tasks also ran after the kill, on a surviving or restarted worker"
    client.wait_for_workers(2, timeout=WAIT_S)  # the nannies restart the killed workers


def test_campaign_resumes_from_its_directory_on_dask(dask_local2, tmp_path):
    # the other recovery path: chunks finished before an interruption are on disk, written by
    # the workers themselves; a re-run on Dask loads them and equals the serial campaign
    import test_dask as mod

    tasks = [(lo, lo + 50, "inertia") for lo in range(0, 600, 50)]
    shared = _shared(5)
    expected = run_campaign(mod._weighted, tasks, chunk_size=3, shared=shared).values
    first = run_campaign(mod._weighted, tasks[:6], executor=dask_local2, directory=tmp_path, chunk_size=3,
                         shared=shared)
    again = run_campaign(mod._weighted, tasks, executor=dask_local2, directory=tmp_path, chunk_size=3,
                         shared=shared)
    assert first.n_resumed == 0 and again.n_resumed == 2 and again.executor == "dask-local:2"
    assert again.values == expected


def test_onoff_tuning_campaign_path_on_dask_equals_serial(dask_local2, tmp_path):
    # The study hands its executor only to monte_carlo (the GAs run in-process), so its Dask
    # path is a sequence of Monte-Carlo campaigns with the same sample keys (S4 Table 5:
    # inertia, torque, disturbance, delay) on the quick config's loop, in memory and resumable.
    # Smallest faithful version: every uncertainty case of the study, alternating S4's Table 4
    # min-error and Table 6 all-four gains (in (K_p, K_d, K_i) order, the reading the study found
    # consistent) and in-memory / resumable campaigns, 20 runs of 30 s in tasks of 10. The
    # full quick run is the slow test below.
    from adcskit.control.tuning import monte_carlo
    from adcskit.studies.onoff_tuning import (
        CASES,
        PAPER_TABLE4,
        PAPER_TABLE6,
        STUDY,
        Config,
        _reorder,
    )

    config = Config(**{**STUDY.quick, "task_size": 10})
    gains = [_reorder(PAPER_TABLE4["min_error"], "kp_kd_ki"), _reorder(PAPER_TABLE6["all"]["printed"], "kp_kd_ki")]
    kw = dict(base=config.base(), settings=config.settings(), task_size=config.task_size)
    for i, case in enumerate(CASES):
        g, directory = gains[i % 2], (tmp_path / case if i % 2 else None)
        serial = monte_carlo(g, config.dists(case), 20, rng=100 + i, **kw)
        dask = monte_carlo(g, config.dists(case), 20, rng=100 + i, executor=dask_local2, directory=directory, **kw)
        assert dask.executor == "dask-local:2"
        np.testing.assert_array_equal(dask.metrics.as_array(), serial.metrics.as_array(), err_msg=case)


def _comparable(result) -> str:
    """The result as JSON text (floats as repr: bit for bit; NaN compares as text)."""
    d = result.to_dict()
    d.pop("runtime_s", None)
    d.pop("executor", None)  # the one field that names where the campaigns ran
    return json.dumps(d, default=repr, sort_keys=True)


@pytest.mark.slow
def test_onoff_tuning_quick_run_on_dask_equals_serial(dask_local2):
    # issue 23's command: adcskit run onoff-tuning --quick --seed 3 --executor dask-local:2
    from adcskit.studies import run_study

    serial = run_study("onoff-tuning", quick=True, seed=3, out=None, executor="serial")
    dask = run_study("onoff-tuning", quick=True, seed=3, out=None, executor=dask_local2)
    assert _comparable(dask) == _comparable(serial)


# --- an existing cluster: dask-scheduler + 2 dask-worker processes on loopback ------------
def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _dask_cli(kind: str) -> list[str]:
    """The command that starts a scheduler / worker of this Python's dask.distributed: the
    module behind the `dask-scheduler` / `dask scheduler` executables, run by this interpreter
    so that the processes import this Python's distributed and adcskit from this checkout."""
    import importlib.util

    module = f"distributed.cli.dask_{kind}"
    if importlib.util.find_spec(module) is None:
        pytest.skip(f"no dask-{kind} executable ({module} is missing)")
    return [sys.executable, "-m", module]


@contextlib.contextmanager
def _loopback_cluster(n_workers: int = 2):
    """A `dask-scheduler` and ``n_workers`` `dask-worker` processes on 127.0.0.1, torn down on
    exit (SIGTERM to each process group, then SIGKILL; the scheduler also exits by itself
    after 300 s without a client and the workers 60 s after losing it)."""
    port = _free_port()
    address = f"127.0.0.1:{port}"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(SRC), str(TESTS), str(Path(__file__).parent)])}
    common = dict(env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    procs = [subprocess.Popen([*_dask_cli("scheduler"), "--host", "127.0.0.1", "--port", str(port),
                               "--no-dashboard", "--no-show", "--idle-timeout", "300"], **common)]
    try:
        for _ in range(n_workers):
            procs.append(subprocess.Popen([*_dask_cli("worker"), f"tcp://{address}", "--host", "127.0.0.1",
                                           "--nthreads", "1", "--no-dashboard", "--death-timeout", str(WAIT_S)],
                                          **common))
        yield address
    finally:
        for p in reversed(procs):
            with contextlib.suppress(ProcessLookupError):
                os.killpg(p.pid, signal.SIGTERM)
        for p in reversed(procs):
            try:
                p.wait(timeout=15)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait(timeout=15)
            with contextlib.suppress(ProcessLookupError):  # no orphaned worker process either
                os.killpg(p.pid, signal.SIGKILL)


_CLI_WITH_FAKE_STUDY = """
import sys
import adcskit.studies._registry as registry
from adcskit.cli import main
registry.STUDIES = {**registry.STUDIES, "fake": registry.StudyInfo("fake", "fake_study", "none", "A fake study")}
sys.exit(main(sys.argv[1:]))
"""


def test_existing_cluster_via_dask_url(tmp_path):
    import test_dask as mod

    from adcskit.studies._registry import STUDIES, StudyInfo
    from adcskit.uncertainty import make_executor

    with _loopback_cluster(2) as address:
        # the executor the CLI builds from --executor dask://HOST:PORT
        with make_executor(f"dask://{address}") as ex:
            assert isinstance(ex, DaskExecutor) and ex.spec == f"dask://{address}"
            ex.client.wait_for_workers(2, timeout=WAIT_S)
            assert ex.n_workers == 2
        # successive maps sharing a dict with the same keys, bounded in time
        with DaskExecutor(f"tcp://{address}", timeout=120.0) as ex:
            tasks = [(lo, lo + 50, "inertia") for lo in range(0, 600, 50)]
            for call in range(3):
                shared = _shared(call)
                expected = SerialExecutor().map(mod._weighted, tasks, shared=shared)
                assert ex.map(mod._weighted, tasks, shared=shared) == expected
        # a study run from the command line on that cluster (the fake study of
        # tests/fake_study.py), in a subprocess with a bounded run time
        env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(SRC), str(TESTS)])}
        cmd = [sys.executable, "-c", _CLI_WITH_FAKE_STUDY, "run", "fake", "--seed", "4",
               "--executor", f"dask://{address}", "--out", str(tmp_path), "--quiet"]
        done = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=2 * WAIT_S)
        assert done.returncode == 0, done.stderr[-2000:]
    d = json.loads((tmp_path / "fake" / "result.json").read_text())
    import adcskit.studies._registry as registry
    from adcskit.studies import run_study

    studies = {**STUDIES, "fake": StudyInfo("fake", "fake_study", "none", "A fake study")}
    old = registry.STUDIES
    registry.STUDIES = studies
    try:
        serial = run_study("fake", seed=4, out=None)
    finally:
        registry.STUDIES = old
    assert d["measured"]["means"] == serial.measured["means"]


def _array_checksum(task):
    """Task (index, array): the index and a SHA-256 of the array's bytes, taken in the worker.

    (Not ``np.sum``: its pairwise SIMD summation depends on the buffer's alignment, which
    differs after unpickling, so a sum can differ in the last bit for the same data.)"""
    import hashlib

    i, a = task
    return i, a.shape, hashlib.sha256(np.ascontiguousarray(a).tobytes()).hexdigest()


def test_large_tasks_travel_by_scatter_not_inside_the_task_graph(dask_local2, monkeypatch):
    # Found with benchmarks/scaleout_campaign.py: simulate's tasks carry their samples (a
    # 1e6-sample closed-loop campaign: 572 MiB of task arguments), and client.map put them
    # all in the task graph ("UserWarning: Sending large graph of size 572.28 MiB"), through
    # the scheduler. Tasks this large are now scattered to the workers (fresh random keys),
    # the graph carries references, and the data is released once the results are back.
    # (scaled down to keep the test fast: our threshold 1 MiB, Dask's warning from 1 MB)
    import warnings

    import dask
    import test_dask as mod

    from adcskit.uncertainty import executor as executor_module

    monkeypatch.setattr(executor_module, "SCATTER_TASKS_BYTES", 2**20)
    rng = np.random.default_rng(3)
    n_items = -(-(2**20) // 8 // 3)  # three tasks together exceed the threshold
    tasks = [(i, rng.normal(size=n_items)) for i in range(4)]
    expected = SerialExecutor().map(mod._array_checksum, tasks)
    with warnings.catch_warnings(record=True) as caught, \
            dask.config.set({"distributed.admin.large-graph-warning-threshold": "1MB"}):
        warnings.simplefilter("always")
        got = dask_local2.map(mod._array_checksum, tasks)
    assert got == expected
    assert not [w for w in caught if "large graph" in str(w.message)], [str(w.message) for w in caught]
    _wait_until(lambda: _n_scheduler_tasks(dask_local2.client) == 0, "the scheduler to forget every key")
