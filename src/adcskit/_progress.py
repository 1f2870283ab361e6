"""Progress display for long runs (rich), off unless a caller turns it on.

Library code wraps long loops in :func:`track`; it is a pass-through unless a
:func:`progress_session` is active (the CLI opens one unless ``--quiet``). Bars of nested
loops are shown together and removed when their loop ends. A long library call opens its own
display with :func:`auto_session` (``simulate(..., progress=None)``: at a terminal only, and
only once the call has run a few seconds). Stage lines (:func:`status`) can also be handed
to a sink (:func:`forward_status`): ``adcskit reproduce --jobs N`` forwards its worker
processes' stage lines to the console that way. Nothing is printed by library code otherwise.
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from typing import TypeVar

T = TypeVar("T")

_SESSION = None  # the active rich.progress.Progress, if any
_FORWARD: Callable[[str], None] | None = None  # where status() lines also go (forward_status)

#: Seconds a call under :func:`auto_session` runs before its display appears (shorter calls show nothing).
AUTO_DELAY_S = 3.0

__all__ = ["AUTO_DELAY_S", "FORWARD_EVERY_S", "auto_session", "forward_status", "progress_flag", "progress_session", "track", "status", "bar"]


def _new_progress():
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        SpinnerColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    return Progress(
        SpinnerColumn(),
        TextColumn("[progress.description]{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
        transient=False,
    )


@contextlib.contextmanager
def progress_session(enabled: bool = True) -> Iterator[None]:
    """Show rich progress bars for every :func:`track` call inside the ``with`` block."""
    global _SESSION
    if not enabled or _SESSION is not None:
        yield
        return
    progress = _new_progress()
    _SESSION = progress
    try:
        with progress:
            yield
    finally:
        _SESSION = None


@contextlib.contextmanager
def auto_session(progress: bool | None = None, delay_s: float | None = None) -> Iterator[None]:
    """A progress display for one long library call (``simulate(..., progress=...)``).

    ``progress`` None: on when the console is a terminal (or a Jupyter notebook), False:
    off, True: on. Inside an active session (the CLI's) it adds nothing: that session shows
    the bars. The bars appear only after ``delay_s`` seconds (default :data:`AUTO_DELAY_S`),
    so a short call draws none; :func:`status` lines (a compile notice) are printed at once.
    """
    global _SESSION
    progress = progress_flag(progress)
    if _SESSION is not None or progress is False:
        yield
        return
    live = _new_progress()
    if progress is None and not (live.console.is_terminal or live.console.is_jupyter):
        yield
        return
    lock = threading.Lock()
    state = {"started": False, "closed": False}

    def start() -> None:
        with lock:
            if not state["closed"]:
                live.start()
                state["started"] = True

    timer = threading.Timer(AUTO_DELAY_S if delay_s is None else delay_s, start)
    timer.daemon = True
    _SESSION = live
    timer.start()
    try:
        yield
    finally:
        timer.cancel()
        with lock:
            state["closed"] = True
            if state["started"]:
                live.stop()
        _SESSION = None


def progress_flag(progress: object) -> bool | None:
    """``progress`` checked: True, False or None (an InputTypeError naming it otherwise)."""
    if progress is None or isinstance(progress, bool):
        return progress
    import numpy as np

    if isinstance(progress, np.bool_):
        return bool(progress)
    from adcskit.errors import InputTypeError

    text = repr(progress)
    text = text if len(text) <= 60 else text[:57] + "..."
    raise InputTypeError(f"progress must be True, False or None (on at a terminal); got {text}")


def forward_status(sink: Callable[[str], None] | None) -> None:
    """Hand every later :func:`status` line to ``sink`` as well (``None``: stop).

    The ``--jobs`` workers of ``adcskit reproduce`` forward their stage lines to the parent
    process's console through a queue (their own console output goes to a log file).
    """
    global _FORWARD
    _FORWARD = sink


#: A loop shown by :func:`track` or :func:`bar` also hands a line ``"DESCRIPTION: k/N after T s"``
#: to the :func:`forward_status` sink at most this often (seconds), so that a forwarded study
#: inside a long loop is never silent for longer.
FORWARD_EVERY_S = 30.0


class _Beat:
    """The periodic forwarded progress line of one loop (nothing without a sink)."""

    __slots__ = ("description", "total", "t0", "last")

    def __init__(self, description: str, total: int | None) -> None:
        self.description, self.total = description, total
        self.t0 = self.last = time.monotonic()

    def __call__(self, done: int) -> None:
        sink = _FORWARD
        if sink is None:
            return
        now = time.monotonic()
        if now - self.last >= FORWARD_EVERY_S:
            self.last = now
            of = "" if self.total is None else f"/{self.total}"
            sink(f"{self.description}: {done}{of} after {now - self.t0:.0f} s")


def track(iterable: Iterable[T], description: str, total: int | None = None) -> Iterator[T]:
    """Iterate over ``iterable`` with a progress bar when a session is active (and a
    periodic progress line to the :func:`forward_status` sink, if any)."""
    progress = _SESSION
    if progress is None and _FORWARD is None:
        yield from iterable
        return
    if total is None:
        try:
            total = len(iterable)  # type: ignore[arg-type]
        except TypeError:
            total = None
    beat = _Beat(description, total)
    task = progress.add_task(description, total=total) if progress is not None else None
    try:
        for done, item in enumerate(iterable, 1):
            yield item
            if task is not None:
                progress.advance(task)
            beat(done)
    finally:
        if task is not None:
            progress.remove_task(task)


@contextlib.contextmanager
def bar(description: str, total: int | None) -> Iterator[Callable[[int], None]]:
    """A progress bar advanced by hand: ``with bar("GA", 1000) as advance: ... advance(1)``.

    For loops driven by someone else's code (an optimiser's callback), where :func:`track`
    cannot wrap the iterable. A no-op without an active session (but for the periodic line
    to the :func:`forward_status` sink, if any).
    """
    progress = _SESSION
    if progress is None and _FORWARD is None:
        yield lambda n=1: None
        return
    beat = _Beat(description, total)
    done = [0]
    task = progress.add_task(description, total=total) if progress is not None else None

    def advance(n: int = 1) -> None:
        done[0] += n
        if task is not None:
            progress.advance(task, n)
        beat(done[0])

    try:
        yield advance
    finally:
        if task is not None:
            progress.remove_task(task)


def status(message: str) -> None:
    """Print a one-line status message above the bars (no-op without a session) and hand it
    to the :func:`forward_status` sink, if any."""
    if _FORWARD is not None:
        _FORWARD(message)
    if _SESSION is not None:
        # soft_wrap: a long path stays on one line (also when output is not a terminal)
        _SESSION.console.print(message, soft_wrap=True, highlight=False)
