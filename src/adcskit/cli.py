"""The ``adcskit`` command: a thin layer over :mod:`adcskit.studies` and :mod:`adcskit.report`.

::

    adcskit list                                  # studies with one-line descriptions
    adcskit run STUDY [--config FILE.toml] [--quick] [--seed N] [--out DIR] [--executor SPEC]
    adcskit reproduce [--quick] [--out DIR] [--only A,B] [--seed N] [--executor SPEC]
    adcskit report DIR                            # rebuild the HTML report from results
    adcskit config STUDY [--quick]                # print the resolved default config as TOML

Exit codes: 0 success, 1 a study failed, 2 bad arguments or input, 130 interrupted.
"""

from __future__ import annotations

import argparse
import json
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
    common(p_rep)

    p_report = sub.add_parser("report", help="rebuild DIR/index.html from DIR/*/result.json")
    p_report.add_argument("dir", help="results directory")
    p_report.add_argument("--quiet", action="store_true", help="print nothing on success")

    p_cfg = sub.add_parser("config", help="print a study's resolved default config as TOML")
    p_cfg.add_argument("study")
    p_cfg.add_argument("--quick", action="store_true", help="the --quick settings")
    p_cfg.add_argument("--quiet", action="store_true", help="keys and values only, no comments")
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
    print("\nSource papers:")
    for pid, paper in PAPERS.items():
        print(f"  {pid}  {paper.citation()}")
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


def _run_one(name: str, args: argparse.Namespace, executor, config=None) -> tuple[bool, str]:
    from adcskit.studies import run_study

    t0 = time.perf_counter()
    result = run_study(name, config=config, quick=args.quick, seed=args.seed, out=args.out, executor=executor)
    from adcskit.studies import tally

    counts = tally(c.display_outcome for c in result.all_claims())
    verdicts = ", ".join(f"{n} {o}" for o, n in counts.items() if n)
    if not verdicts and result.findings:
        # a study of our own questions (e.g. closed-loop): tally its findings instead
        found = tally(f.display_outcome for f in result.findings)
        verdicts = "none; findings: " + ", ".join(f"{n} {o}" for o, n in found.items() if n)
    verdicts = verdicts or "no claims"
    return True, f"{name}: done in {time.perf_counter() - t0:.1f} s, paper's claims: {verdicts} -> {Path(args.out) / name}"


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
            wanted = [s.strip() for s in args.only.split(",") if s.strip()]
            for w in wanted:
                if w not in STUDIES:
                    raise AdcskitError(f"--only names unknown study {w!r}; valid: {', '.join(STUDIES)}")
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
    failures: dict[str, dict] = {}
    done: list[str] = []
    interrupted = False
    try:
        with progress_session(not args.quiet):
            for name in track(names, "studies", total=len(names)) if len(names) > 1 else names:
                try:
                    _, line = _run_one(name, args, executor, getattr(args, "config", None))
                    done.append(name)
                    if not args.quiet:
                        status(line)
                except KeyboardInterrupt:
                    raise
                except AdcskitError:
                    if args.command == "run":
                        raise
                    failures[name] = {"message": traceback.format_exc(limit=0).strip(), "traceback": traceback.format_exc()}
                    _err(f"study {name} failed: {failures[name]['message']}")
                except Exception as exc:  # noqa: BLE001 - one failed study must not lose the others
                    failures[name] = {"message": f"{type(exc).__name__}: {exc}", "traceback": traceback.format_exc()}
                    _err(f"study {name} failed: {type(exc).__name__}: {exc}")
                    if args.command == "run":
                        traceback.print_exc()
    except KeyboardInterrupt:
        interrupted = True
        _err("interrupted; studies already written are intact")
    finally:
        executor.close()
        _record_errors(out, failures, done)
        index = build_report(out)
    if not args.quiet:
        print(f"report: {index}")
    if interrupted:
        return EXIT_INTERRUPTED
    return EXIT_FAILED if failures else EXIT_OK


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``adcskit`` console script."""
    if argv is not None and (isinstance(argv, str | bytes) or not all(isinstance(a, str) for a in argv)):
        raise InputTypeError(f"argv must be None or a list of strings; got {argv!r}")
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        if args.command == "list":
            return _cmd_list(args.quiet)
        if args.command == "config":
            return _cmd_config(args)
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
