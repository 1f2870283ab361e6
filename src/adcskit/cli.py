"""The ``adcskit`` command: a thin layer over :mod:`adcskit.studies` and :mod:`adcskit.report`.

::

    adcskit list                                  # studies with one-line descriptions
    adcskit run STUDY [--config FILE.toml] [--quick] [--seed N] [--out DIR] [--executor SPEC]
    adcskit reproduce [--quick] [--out DIR] [--only A,B] [--seed N] [--executor SPEC] [--jobs N]
    adcskit report DIR                            # rebuild the HTML report from results
    adcskit config STUDY [--quick]                # print the resolved default config as TOML
    adcskit scenario [--wheels] [--quiet]         # print the default closed-loop scenario as TOML
    adcskit pages [--results DIR] [--check]       # study pages from their committed snapshots

Exit codes: 0 success, 1 a study failed, 2 bad arguments or input, 130 interrupted.

``reproduce --jobs N`` (default: the usable core count) runs up to ``N`` studies at once, each
in its own ``spawn`` worker process, longest expected study first
(:data:`adcskit.studies.EXPECTED_WALL_S`). Every study's result depends only on its
name, config and seed, so the result files equal a serial run's (``--jobs 1``) but for the
timing fields. How ``--jobs`` combines with ``--executor`` (no oversubscription):

* ``serial`` (default): studies run side by side, each study's campaigns serially, and each
  study's numba kernels on ``max(1, cores // N)`` threads (``numba.set_num_threads``; the
  kernels' results do not depend on their thread count). With every worker's kernels on every
  core, a ``prange`` loop's static halves waited for the half that shared its core with the
  study beside it while the other core idled (measured in docs/benchmarks.md, "Full
  reproduction").
* ``processes`` without a count: each study gets ``max(1, cores // N)`` campaign workers;
  an explicit ``processes:M`` is kept (a warning says when ``N * M`` exceeds the cores).
* ``dask-local[:M]``: one local cluster, started here and shared by every study (they
  connect to its scheduler); ``dask://HOST:PORT``: every study connects to that scheduler.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import signal
import sys
import time
import traceback
from pathlib import Path

from adcskit import __version__
from adcskit._validation import check_path
from adcskit.errors import AdcskitError, InputError, InputTypeError

__all__ = ["main", "build_parser"]

EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130


def _seed(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"seed must be a non-negative integer; got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"seed must be a non-negative integer; got {value}")
    return value


def _jobs(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"jobs must be a positive integer; got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"jobs must be a positive integer; got {value}")
    return value


def _usable_cores() -> int:
    """CPU cores this process may run on: the affinity mask where the OS has one, else ``os.cpu_count()``."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="adcskit",
        description="Spacecraft ADCS design toolkit: run and report the paper reproductions.",
    )
    parser.add_argument("--version", action="version", version=f"adcskit {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)

    p_list = sub.add_parser("list", help="list the registered studies and cite their papers")
    p_list.add_argument("--quiet", action="store_true", help="names only")

    def common(p: argparse.ArgumentParser, out_default: str = "results") -> None:
        p.add_argument("--quick", action="store_true", help="reduced but honest run (fewer trials, coarser meshes)")
        p.add_argument("--seed", type=_seed, default=0, help="root random seed (default 0)")
        p.add_argument("--out", default=out_default, help=f"results directory (default {out_default!r})")
        p.add_argument(
            "--executor",
            default="serial",
            help="serial (default), processes[:N], dask-local[:N] or dask://HOST:PORT",
        )
        p.add_argument("--quiet", action="store_true", help="no progress bars, only errors")

    p_run = sub.add_parser("run", help="run one study and write DIR/STUDY/")
    p_run.add_argument("study", help="study name (see 'adcskit list')")
    p_run.add_argument("--config", help="TOML file with config overrides")
    common(p_run)

    p_rep = sub.add_parser("reproduce", help="run every study and write DIR/index.html")
    p_rep.add_argument("--only", help="comma-separated subset of studies")
    p_rep.add_argument(
        "--jobs",
        type=_jobs,
        default=None,
        help="studies run at once, each in its own process (default: the usable core count; 1 = one after another)",
    )
    common(p_rep)

    p_report = sub.add_parser("report", help="rebuild DIR/index.html from DIR/*/result.json")
    p_report.add_argument("dir", help="results directory")
    p_report.add_argument("--quiet", action="store_true", help="print nothing on success")

    p_pages = sub.add_parser(
        "pages",
        help="regenerate docs/studies/*.md from their snapshots (--results DIR: new snapshots from a full run)",
    )
    p_pages.add_argument("--results", help="a full (not --quick) reproduction's results directory")
    p_pages.add_argument("--docs", default="docs/studies", help="the study pages' directory (default docs/studies)")
    p_pages.add_argument("--only", help="comma-separated subset of studies")
    p_pages.add_argument("--check", action="store_true",
                         help="write nothing; exit 1 when RESULTS differ from the snapshots or a page from its snapshot")
    p_pages.add_argument("--commit", default="", help="provenance: the commit the results were run at")
    p_pages.add_argument("--date", default="", help="provenance: the date of the run")
    p_pages.add_argument("--machine", default="", help="provenance: the machine")
    p_pages.add_argument("--command-line", dest="command_line", default="",
                         help="provenance: the command that produced the results")

    p_cfg = sub.add_parser("config", help="print a study's resolved default config as TOML")
    p_cfg.add_argument("study")
    p_cfg.add_argument("--quick", action="store_true", help="the --quick settings")
    p_cfg.add_argument("--quiet", action="store_true", help="keys and values only, no comments")

    p_scn = sub.add_parser("scenario", help="print the default closed-loop scenario as TOML (a template for simulate)")
    p_scn.add_argument("--wheels", action="store_true", help="the wheel + magnetorquer scenario (simulate_wheels)")
    p_scn.add_argument("--quiet", action="store_true", help="keys and values only, no comments")
    return parser


def _err(message: str) -> None:
    print(f"adcskit: error: {message}", file=sys.stderr)


def _cmd_list(quiet: bool = False) -> int:
    from adcskit.studies import PAPERS, STUDIES, is_available

    if quiet:
        print("\n".join(n for n in STUDIES if is_available(n)))
        return EXIT_OK
    width = max(len(n) for n in STUDIES)
    for name, info in STUDIES.items():
        mark = "" if is_available(name) else "  [not implemented yet]"
        print(f"{name:<{width}}  {info.paper}  {info.description}{mark}")
    n_paper = sum(1 for i in STUDIES.values() if i.paper in PAPERS)
    print(f"\n{len(STUDIES)} studies: {n_paper} reproduce the {len(PAPERS)} papers, "
          f"{len(STUDIES) - n_paper} ({', '.join(n for n, i in STUDIES.items() if i.paper not in PAPERS)}) is ours.")
    print("\nSource papers:")
    for pid, paper in PAPERS.items():
        print(f"  {pid}  {paper.citation()}")
    return EXIT_OK


def _only(text: str) -> list[str]:
    """The study names of an ``--only A,B`` option (unknown names: an error naming the valid ones)."""
    from adcskit.studies import STUDIES

    wanted = [s.strip() for s in text.split(",") if s.strip()]
    for w in wanted:
        if w not in STUDIES:
            raise AdcskitError(f"--only names unknown study {w!r}; valid: {', '.join(STUDIES)}")
    return wanted


def _cmd_pages(args: argparse.Namespace) -> int:
    from adcskit.studies import study_names
    from adcskit.studies._pages import sync_pages

    names = _only(args.only) if args.only else list(study_names())
    prov = {"commit": args.commit, "date": args.date, "machine": args.machine, "command": args.command_line}
    out = sync_pages(args.docs, names, results=args.results, check=args.check, provenance=prov)
    for line in out:
        print(line)
    if args.check:
        print(f"{len(out)} difference(s)" if out else "pages and snapshots agree")
        return 1 if out else EXIT_OK
    return EXIT_OK


def _cmd_config(args: argparse.Namespace) -> int:
    from adcskit.config import config_help, config_to_dict, dump_toml
    from adcskit.studies import resolve_config

    cfg = resolve_config(args.study, None, quick=args.quick)
    if args.quiet:
        print(dump_toml(config_to_dict(cfg)), end="")
        return EXIT_OK
    print(f"# adcskit {__version__}: default config of study {args.study!r}{' (--quick)' if args.quick else ''}")
    print("# The defaults are the paper's settings; a changed key is reported as a custom configuration.")
    print(dump_toml(config_to_dict(cfg), comments=config_help(type(cfg))), end="")
    return EXIT_OK


def _cmd_scenario(args: argparse.Namespace) -> int:
    from adcskit.simulation import Scenario, WheelScenario, scenario_toml

    sc = WheelScenario() if args.wheels else Scenario()
    if args.quiet:
        print(scenario_toml(sc, comments=False), end="")
        return EXIT_OK
    func, loader = ("simulate_wheels", "load_wheel_scenario") if args.wheels else ("simulate", "load_scenario")
    print(f"# adcskit {__version__}: default {type(sc).__name__} of adcskit.simulation.{func}")
    print(f"# Load with adcskit.simulation.{loader}(PATH); keep only the keys you change: a table's")
    print("# other keys keep these defaults. Units are in the comments and the key names (_deg, _s, _hz).")
    print(scenario_toml(sc), end="")
    return EXIT_OK


def _run_one(name: str, args: argparse.Namespace, executor, config=None) -> tuple[bool, str]:
    from adcskit.studies import run_study

    result = run_study(name, config=config, quick=args.quick, seed=args.seed, out=args.out, executor=executor)
    from adcskit.studies import tally

    def label(c) -> str:  # indicative (quick) outcomes are counted apart, never as a red verdict
        return "indicative" if c.indicative else c.display_outcome

    counts = tally(label(c) for c in result.all_claims())
    verdicts = ", ".join(f"{n} {o}" for o, n in counts.items() if n)
    if not verdicts and result.findings:
        # a study of our own questions (e.g. closed-loop): tally its findings instead
        found = tally(label(f) for f in result.findings)
        verdicts = "none; findings: " + ", ".join(f"{n} {o}" for o, n in found.items() if n)
    verdicts = verdicts or "no claims"
    # the run time the report shows (result.runtime_s, the study's own run), one measurement
    return True, f"{name}: done in {result.runtime_s:.1f} s, paper's claims: {verdicts} -> {Path(args.out) / name}"


def _attempt(name: str, args: argparse.Namespace, executor, config=None) -> tuple[str, dict | None]:
    """Run one study: ``(line, None)`` on success, ``("", failure)`` when it raised.

    ``failure`` is what ``errors.json`` records: ``{"message", "traceback"}``. The serial loop
    and the ``--jobs`` workers both call this, so a failure is recorded alike in both. With
    ``adcskit run`` an input error propagates (exit 2).
    """
    try:
        return _run_one(name, args, executor, config)[1], None
    except KeyboardInterrupt:
        raise
    except AdcskitError:
        if args.command == "run":
            raise
        return "", {"message": traceback.format_exc(limit=0).strip(), "traceback": traceback.format_exc()}
    except Exception as exc:  # noqa: BLE001 - one failed study must not lose the others
        if args.command == "run":
            traceback.print_exc()
        return "", {"message": f"{type(exc).__name__}: {exc}", "traceback": traceback.format_exc()}


# --- reproduce --jobs N: studies in spawn worker processes --------------------------------
_CANCEL = None  # multiprocessing Event shared with the parent; set on Ctrl-C
_STAGES = None  # multiprocessing Queue of stage lines, printed by the parent (None: --quiet)
_RUNNING = False  # a study is running in this worker (SIGINT interrupts it; idle workers ignore it)


def _on_sigint(signum, frame) -> None:
    if _RUNNING:
        raise KeyboardInterrupt


def _job_init(cancel, stages=None) -> None:
    """Initializer of a ``--jobs`` worker process (``stages``: the parent's queue of stage lines)."""
    global _CANCEL, _STAGES
    _CANCEL = cancel
    _STAGES = stages
    if stages is not None:
        stages.cancel_join_thread()  # an exiting worker never waits for the parent to read its stage lines
    signal.signal(signal.SIGINT, _on_sigint)


def _cpu_s() -> float:
    """User + system CPU seconds of this process (all threads) and its reaped children."""
    try:
        import resource
    except ImportError:  # not on POSIX: this process only
        return time.process_time()
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def _study_job(name: str, info, args: argparse.Namespace, spec: str, log_path: str, threads: int = 0):
    """Worker: run study ``name`` with its console output in ``log_path``.

    Returns ``(name, line, failure, wall_s, cpu_s)``; ``line`` None means cancelled before the
    start. ``cpu_s`` is the CPU time (user + system, every thread) of this worker process and of
    the child processes it reaped during the study (a ``processes`` executor's workers); a
    shared Dask cluster's workers are not counted.
    ``info`` is the parent's registry entry, so a study registered at run time (a test's fake
    study) is found in the fresh worker too. ``threads`` > 0 caps this worker's numba threads
    (at most numba's own ``NUMBA_NUM_THREADS``); 0 leaves them.
    """
    global _RUNNING
    _RUNNING = True  # first, then the flag: a Ctrl-C between the two still stops this study
    try:
        if _CANCEL is not None and _CANCEL.is_set():
            return name, None, None, 0.0, 0.0
        from adcskit._progress import forward_status, progress_session
        from adcskit.studies import STUDIES
        from adcskit.uncertainty.executor import make_executor

        if _STAGES is not None:  # this study's stage lines to the parent's console, named
            put = _STAGES.put
            forward_status(lambda line: put(line if line.startswith(name) else f"{name}: {line}"))

        if info is not None and name not in STUDIES:  # a fresh process: the registry's own dict
            STUDIES[name] = info
        if threads > 0:
            import numba

            numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
        t0, c0 = time.perf_counter(), _cpu_s()
        with (
            open(log_path, "w", encoding="utf-8") as log,
            contextlib.redirect_stdout(log),
            contextlib.redirect_stderr(log),
        ):
            executor = make_executor(spec)
            try:
                with progress_session(not args.quiet):
                    line, failure = _attempt(name, args, executor)
            finally:
                _RUNNING = False  # the study is over: a Ctrl-C from now on does not undo it
                executor.close()
            print(line if failure is None else f"study {name} failed: {failure['traceback']}")
        return name, line, failure, time.perf_counter() - t0, _cpu_s() - c0
    finally:
        _RUNNING = False


def _cores_per_study(jobs: int) -> int:
    """Each of ``jobs`` concurrent studies' share of the usable cores (at least one)."""
    return max(1, _usable_cores() // jobs)


def _worker_executor_spec(text: str, executor, jobs: int) -> str:
    """The ``--executor`` each of ``jobs`` concurrent studies gets (see the module docstring)."""
    from adcskit.uncertainty.executor import DaskExecutor, ProcessExecutor

    if isinstance(executor, DaskExecutor):  # one cluster for all studies: connect to its scheduler
        return "dask://" + executor.client.scheduler_info()["address"].removeprefix("tcp://")
    if isinstance(executor, ProcessExecutor):
        cores = _usable_cores()
        if ":" not in text:
            return f"processes:{_cores_per_study(jobs)}"
        if jobs * executor.n_workers > cores:
            _err(f"warning: --jobs {jobs} studies x --executor {text.strip()} = {jobs * executor.n_workers} "
                 f"campaign processes on {cores} cores")
    return executor.spec


def _worker_threads(spec: str, jobs: int) -> int:
    """numba threads of each of ``jobs`` concurrent studies: the cores shared out under the
    ``serial`` executor (see the module docstring), 0 (numba's default) under the others."""
    return _cores_per_study(jobs) if spec == "serial" else 0


def _longest_first(names: list[str]) -> list[str]:
    """``names`` by expected wall time, longest first (registry order among equals)."""
    from adcskit.studies import EXPECTED_WALL_S

    return sorted(names, key=lambda n: -EXPECTED_WALL_S.get(n, 0.0))


def _run_parallel(names: list[str], args: argparse.Namespace, executor, jobs: int,
                  failures: dict[str, dict], done: list[str]) -> bool:
    """Run ``names`` on ``jobs`` worker processes, longest expected first; True if interrupted.

    One line per study as it finishes, then a summary in ``names`` order (each study's wall and
    CPU seconds: a study's CPU against its wall says how much of the cores it had); each study's
    console output is in ``OUT/logs/STUDY.log``, and its stage lines (``status``: its start,
    its stages, and inside a long loop a progress line every
    :data:`adcskit._progress.FORWARD_EVERY_S` s) are printed here as they come, named. Ctrl-C cancels the studies not started,
    interrupts the running ones (their previous results stay, see :func:`write_result`) and
    keeps every study already written.
    """
    import concurrent.futures as cf
    import multiprocessing

    from adcskit._progress import bar, progress_session, status
    from adcskit.studies import STUDIES

    spec = _worker_executor_spec(args.executor, executor, jobs)
    threads = _worker_threads(spec, jobs)
    order = _longest_first(names)
    logs = Path(args.out) / "logs"
    logs.mkdir(exist_ok=True)
    ctx = multiprocessing.get_context("spawn")
    cancel = ctx.Event()
    stages = None if args.quiet else ctx.Queue()  # the workers' stage lines, printed here (issue 41)
    pool = cf.ProcessPoolExecutor(max_workers=jobs, mp_context=ctx, initializer=_job_init,
                                  initargs=(cancel, stages))
    outcome: dict[str, str] = {}
    t0 = time.perf_counter()
    interrupted = False

    def collect(fut, name: str) -> None:
        if fut.cancelled():
            outcome[name] = "cancelled"
            return
        exc = fut.exception()
        if isinstance(exc, KeyboardInterrupt):
            outcome[name] = "interrupted"
            return
        if exc is not None:  # the worker itself failed (e.g. it was killed): record like a failed study
            tb = "".join(traceback.format_exception(exc))
            failures[name] = {"message": f"{type(exc).__name__}: {exc}", "traceback": tb}
            outcome[name] = "failed"
            _err(f"study {name} failed: {failures[name]['message']}")
            return
        _, line, failure, wall, cpu = fut.result()
        if line is None:
            outcome[name] = "cancelled"
        elif failure is None:
            done.append(name)
            outcome[name] = f"done in {wall:.1f} s ({cpu:.1f} CPU-s)"
            if not args.quiet:
                status(line)
        else:
            failures[name] = failure
            outcome[name] = f"failed after {wall:.1f} s ({cpu:.1f} CPU-s)"
            _err(f"study {name} failed: {failure['message']}")

    if not args.quiet and "closed-loop" in names:  # its worker's notice goes to its log: say it here
        from adcskit._jit import CLOSED_LOOP_NOTICE, will_compile
        from adcskit.simulation import _kernels

        if will_compile(_kernels.run_parallel):
            print(f"closed-loop: {CLOSED_LOOP_NOTICE}", flush=True)
    futures: dict = {}
    try:
        with (progress_session(not args.quiet), _print_stages(stages),
              bar(f"studies ({jobs} at once)", len(order)) as advance):
            for n in order:
                log = str(logs / f"{n}.log")
                futures[pool.submit(_study_job, n, STUDIES.get(n), args, spec, log, threads)] = n
            for fut in cf.as_completed(futures):
                collect(fut, futures[fut])
                advance(1)
    except KeyboardInterrupt:
        interrupted = True
        _cancel_jobs(pool, futures, cancel)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
    for fut, name in futures.items():  # finished while shutting down after an interrupt
        if name not in outcome:
            collect(fut, name)
    if not args.quiet:
        width = max(len(n) for n in names)
        print(f"summary ({jobs} studies at once, {time.perf_counter() - t0:.1f} s wall; logs in {logs}):")
        for n in names:
            print(f"  {n:<{width}}  {outcome.get(n, 'not run')}")
    return interrupted


@contextlib.contextmanager
def _print_stages(stages):
    """Print the stage lines the ``--jobs`` workers put on ``stages`` (a queue; None: nothing)
    as they come, from a thread, until the ``with`` block ends."""
    if stages is None:
        yield
        return
    import threading

    from adcskit._progress import status

    def pump() -> None:
        while (line := stages.get()) is not None:
            status(line)

    thread = threading.Thread(target=pump, name="adcskit-stages", daemon=True)
    thread.start()
    try:
        yield
    finally:
        stages.put(None)
        thread.join(timeout=5.0)


def _cancel_jobs(pool, futures, cancel) -> None:
    """Ctrl-C: no study starts any more, the running ones are interrupted.

    Sets the shared ``cancel`` event (a worker checks it before it starts a study: the pool
    may already have handed it one), cancels the futures not yet handed out, and sends
    SIGINT to the workers (idle ones ignore it; a Ctrl-C at a terminal reached them already).
    """
    cancel.set()
    for fut in futures:
        fut.cancel()
    for proc in list((getattr(pool, "_processes", None) or {}).values()):
        with contextlib.suppress(OSError, AttributeError):
            os.kill(proc.pid, signal.SIGINT)


def _record_errors(out: Path, errors: dict, clear: list[str]) -> None:
    from adcskit.report.html import ERRORS_FILE
    from adcskit.studies import write_json_atomic

    path = out / ERRORS_FILE
    current = {}
    if path.is_file():
        try:
            current = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, json.JSONDecodeError):
            current = {}
    for name in clear:
        current.pop(name, None)
    current.update(errors)
    write_json_atomic(path, current)


#: Modules whose numba kernels (``cache=True``) the studies compile on first use, besides the
#: closed-loop simulator (which announces itself: :data:`adcskit._jit.CLOSED_LOOP_NOTICE`).
_KERNEL_MODULES = (
    "adcskit.determination._kernels",
    "adcskit.determination._box",
    "adcskit.estimation._mekf_kernels",
    "adcskit.sensors._gyro_kernels",
    "adcskit.thrusters.allocation",
    "adcskit.control._onoff_kernels",
)
#: Studies that call those kernels (rendezvous runs on CasADi/IPOPT only).
_KERNEL_STUDIES = frozenset({"wahba-table1", "wahba-orbit", "model-estimation", "thruster-layout", "onoff-schmitt",
                             "onoff-tuning", "closed-loop"})
#: Issue 23: the first output of a cold `adcskit reproduce --quick` came after 106 s (2 cores).
KERNELS_NOTICE = "compiling adcskit's numba kernels once, about 2 min on 2 cores; cached afterwards"


def _kernels_pending() -> int:
    """How many of the studies' kernel modules (closed-loop simulator aside) compile on first use.

    A module counts when none of its own dispatchers would load from numba's disk cache: a
    cold cache, or a module whose source changed (numba then ignores its entries). Helpers that
    numba inlines into their callers (``inline="always"``) never get a cache entry of their own,
    and a module may hold entry points a given run does not call (``solve_batch_parallel`` in a
    quick run), so a single pending dispatcher says nothing: before this rule the notice was
    printed on every warm run.
    """
    import importlib

    from numba.core.registry import CPUDispatcher

    from adcskit._jit import will_compile

    pending = 0
    for mod_name in _KERNEL_MODULES:
        mod = importlib.import_module(mod_name)
        own = [obj for obj in vars(mod).values()
               if isinstance(obj, CPUDispatcher) and getattr(obj, "_cache", None) is not None
               and obj.targetoptions.get("inline", "never") == "never"]
        if own and all(will_compile(obj) for obj in own):
            pending += 1
    return pending


def _cmd_run_or_reproduce(args: argparse.Namespace) -> int:
    from adcskit._progress import progress_session, status, track
    from adcskit.report.html import build_report
    from adcskit.studies import STUDIES, is_available
    from adcskit.uncertainty.executor import make_executor

    out = Path(args.out)
    if args.command == "run":
        from adcskit.studies import get_study

        get_study(args.study)  # validates the name before any work
        names = [args.study]
    else:
        names = [n for n in STUDIES if is_available(n)]
        if args.only:
            wanted = _only(args.only)
            names = [n for n in names if n in wanted]
        skipped = [n for n in STUDIES if not is_available(n)]
        if skipped and not args.quiet:
            print(f"adcskit: not implemented yet, skipped: {', '.join(skipped)}", file=sys.stderr)
    # every argument is checked before anything is written (exit 2, one line, no output)
    check_path("--out", args.out, writable_dir=True)
    if getattr(args, "config", None) is not None:
        from adcskit.studies import resolve_config

        resolve_config(args.study, args.config, quick=args.quick)  # unreadable/bad TOML -> ConfigError
    executor = make_executor(args.executor)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        executor.close()
        raise InputError(f"--out directory cannot be created: {str(out)!r} ({exc.strerror})") from None
    if not args.quiet and set(names) & _KERNEL_STUDIES and _kernels_pending():
        print(f"adcskit: {KERNELS_NOTICE}", flush=True)
    failures: dict[str, dict] = {}
    done: list[str] = []
    interrupted = False
    jobs = getattr(args, "jobs", None) or _usable_cores()
    try:
        if jobs > 1 and len(names) > 1:
            interrupted = _run_parallel(names, args, executor, min(jobs, len(names)), failures, done)
        else:
            with progress_session(not args.quiet):
                for name in track(names, "studies", total=len(names)) if len(names) > 1 else names:
                    line, failure = _attempt(name, args, executor, getattr(args, "config", None))
                    if failure is None:
                        done.append(name)
                        if not args.quiet:
                            status(line)
                    else:
                        failures[name] = failure
                        _err(f"study {name} failed: {failure['message']}")
    except KeyboardInterrupt:
        interrupted = True
    finally:
        if interrupted:
            _err("interrupted; studies already written are intact")
        executor.close()
        _record_errors(out, failures, done)
        index = build_report(out)
    if not args.quiet:
        print(f"report: {index}")
    if interrupted:
        return EXIT_INTERRUPTED
    return EXIT_FAILED if failures else EXIT_OK


def _quiet_openmp_waits() -> None:
    """Idle OpenMP threads sleep instead of spinning, unless the user set ``OMP_WAIT_POLICY``.

    numba's ``prange`` kernels run on GNU OpenMP, whose idle threads spin (≈ 3e5 iterations)
    after every parallel region before they sleep. A study calls short kernels thousands of
    times (a GA generation, a Monte-Carlo task), and under ``reproduce --jobs N`` the spinning
    threads take the cores from the study beside them. Must run before the first parallel
    kernel loads OpenMP; ``spawn`` workers (``--jobs``, ``processes``, ``dask-local``) inherit
    it. It changes no result, only CPU time (docs/benchmarks.md, "OpenMP threads that sleep").
    """
    os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``adcskit`` console script."""
    if argv is not None and (isinstance(argv, str | bytes) or not all(isinstance(a, str) for a in argv)):
        raise InputTypeError(f"argv must be None or a list of strings; got {argv!r}")
    parser = build_parser()
    args = parser.parse_args(argv)
    _quiet_openmp_waits()
    try:
        if args.command == "list":
            return _cmd_list(args.quiet)
        if args.command == "config":
            return _cmd_config(args)
        if args.command == "scenario":
            return _cmd_scenario(args)
        if args.command == "pages":
            return _cmd_pages(args)
        if args.command == "report":
            from adcskit.report.html import ERRORS_FILE, build_report, load_results

            if Path(args.dir).is_dir() and not load_results(args.dir) and not (Path(args.dir) / ERRORS_FILE).is_file():
                raise AdcskitError(
                    f"report directory {args.dir!r} holds no results (no */result.json); "
                    "run 'adcskit run STUDY --out DIR' or 'adcskit reproduce --out DIR' first"
                )
            index = build_report(args.dir)
            if not args.quiet:
                print(index)
            return EXIT_OK
        return _cmd_run_or_reproduce(args)
    except AdcskitError as exc:
        _err(str(exc))
        return EXIT_USAGE
    except KeyboardInterrupt:
        _err("interrupted")
        return EXIT_INTERRUPTED


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
