"""Progress display for long runs (rich), off unless a caller turns it on.

Library code wraps long loops in :func:`track`; it is a pass-through unless a
:func:`progress_session` is active (the CLI opens one unless ``--quiet``). Bars of nested
loops are shown together and removed when their loop ends. Nothing is printed by library
code otherwise.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterable, Iterator
from typing import TypeVar

T = TypeVar("T")

_SESSION = None  # the active rich.progress.Progress, if any

__all__ = ["progress_session", "track", "status", "bar"]


@contextlib.contextmanager
def progress_session(enabled: bool = True) -> Iterator[None]:
    """Show rich progress bars for every :func:`track` call inside the ``with`` block."""
    global _SESSION
    if not enabled or _SESSION is not None:
        yield
        return
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        SpinnerColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    progress = Progress(
        SpinnerColumn(),
        TextColumn("[progress.description]{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
        transient=False,
    )
    _SESSION = progress
    try:
        with progress:
            yield
    finally:
        _SESSION = None


def track(iterable: Iterable[T], description: str, total: int | None = None) -> Iterator[T]:
    """Iterate over ``iterable`` with a progress bar when a session is active."""
    progress = _SESSION
    if progress is None:
        yield from iterable
        return
    if total is None:
        try:
            total = len(iterable)  # type: ignore[arg-type]
        except TypeError:
            total = None
    task = progress.add_task(description, total=total)
    try:
        for item in iterable:
            yield item
            progress.advance(task)
    finally:
        progress.remove_task(task)


@contextlib.contextmanager
def bar(description: str, total: int | None) -> Iterator[Callable[[int], None]]:
    """A progress bar advanced by hand: ``with bar("GA", 1000) as advance: ... advance(1)``.

    For loops driven by someone else's code (an optimiser's callback), where :func:`track`
    cannot wrap the iterable. A no-op without an active session.
    """
    progress = _SESSION
    if progress is None:
        yield lambda n=1: None
        return
    task = progress.add_task(description, total=total)
    try:
        yield lambda n=1: progress.advance(task, n)
    finally:
        progress.remove_task(task)


def status(message: str) -> None:
    """Print a one-line status message above the bars (no-op without a session)."""
    if _SESSION is not None:
        _SESSION.console.print(message)
