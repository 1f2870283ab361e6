"""Load-proof timing of ``speed-600x``: repeats of the same solve, interleaved, single-threaded.

The speed claim compares CPU times of solvers that differ by two to four orders of magnitude;
a single solve per epoch moved the per-replica ratios by a factor 3 between a quiet and a
loaded run on one machine (issue 45). Here every timed epoch is solved ``repeats`` times by
each compared method, the methods interleaved round-robin (a load spike hits all alike; the
order rotates each round), with numba and BLAS/OpenMP threads pinned to 1 (so the CPU time of
the calling thread, ``time.thread_time``, is all the work and no helper thread is left out),
and a method's time on an epoch is the median of its repeats. Every repeat of a method solves
the same inputs with the same seed, so its answer is identical (checked).

:func:`time_epochs` runs serially in the calling process, after the study's executor map.

References
----------
S0 Table 1 (run times), §4-1.
"""

from __future__ import annotations

import time
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

import numpy as np

from adcskit._results import Result

__all__ = ["TIMED", "TimedEpoch", "single_threaded", "time_epochs"]

#: The methods timed for ``speed-600x``: the two min-max solvers and NSGA-II at our budget and
#: at the big budget (the latter only on the big-budget epochs).
TIMED = ("minmax", "minmax-slsqp", "nsga2-knee", "nsga2-big-knee")


@contextmanager
def single_threaded() -> Iterator[None]:
    """numba and every BLAS / OpenMP pool pinned to one thread inside the block (restored after).

    Examples
    --------
    >>> import numba
    >>> with single_threaded():
    ...     numba.get_num_threads()
    1
    """
    import numba
    from threadpoolctl import threadpool_limits

    before = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        with threadpool_limits(limits=1):
            yield
    finally:
        numba.set_num_threads(before)


@dataclass(frozen=True, slots=True, kw_only=True, repr=False)
class TimedEpoch(Result):
    """One epoch of one replica, each method solved ``len(times[m])`` times.

    ``times[m]`` are the CPU seconds of each repeat (in order), ``error_deg[m]`` the attitude
    error of the (identical) answer, ``identical`` whether every repeat returned the same
    attitude as the first.
    """

    replica: int
    epoch: int
    times: Mapping[str, tuple[float, ...]]
    error_deg: Mapping[str, float]
    nfev: Mapping[str, int]
    identical: bool

    def median(self, method: str) -> float:
        """Median CPU time of ``method`` over this epoch's repeats [s]."""
        return float(np.median(self.times[method]))

    def spread(self, method: str) -> float:
        """Relative spread of the repeats: (max - min) / median."""
        t = np.asarray(self.times[method])
        return float((t.max() - t.min()) / max(np.median(t), 1e-300))


def _solver(method: str, b, br, r, rr, sr: float, cfg: Mapping[str, Any], seed_ns: int):
    from adcskit.determination import robust_wahba

    if method == "minmax":
        return lambda: robust_wahba(b, br, r, rr, method="minmax", search_range=sr, solver="closed-form")
    if method == "minmax-slsqp":
        return lambda: robust_wahba(b, br, r, rr, method="minmax", search_range=sr, solver="slsqp")
    n_gen = cfg["n_gen"] if method == "nsga2-knee" else cfg["big_n_gen"]
    return lambda: robust_wahba(b, br, r, rr, method="nsga2", search_range=sr, pop_size=cfg["pop_size"],
                                n_gen=n_gen, rng=seed_ns)


def time_epochs(epochs: list[tuple[int, int, Any, float]], cfg: Mapping[str, Any], *, repeats: int,
                n_big: int) -> tuple[TimedEpoch, ...]:
    """Time every method on each ``(replica, epoch, seed, noise bound)``, ``repeats`` times each.

    The epoch's vectors and NSGA-II seed are drawn from ``seed`` exactly as the study's
    :func:`~.experiment.trial` draws them. ``nsga2-big-knee`` runs only on epochs with index
    ``< n_big``. Methods are interleaved round-robin, the starting method rotating each round.

    Examples
    --------
    >>> cfg = {"search_range": 0.1, "pop_size": 8, "n_gen": 4, "big_n_gen": 8}
    >>> t = time_epochs([(0, 0, np.random.SeedSequence(1), 0.2)], cfg, repeats=3, n_big=1)
    >>> sorted(t[0].times), len(t[0].times["nsga2-big-knee"]), t[0].identical
    (['minmax', 'minmax-slsqp', 'nsga2-big-knee', 'nsga2-knee'], 3, True)
    """
    from adcskit.studies.wahba_table1.draws import angle_deg, epoch_inputs
    from adcskit.studies.wahba_table1.paper import q_exact

    out = []
    with single_threaded():
        for replica, epoch, seed, bound in epochs:
            b, r, seed_ns = epoch_inputs(seed, bound)
            br, rr = bound * np.abs(b), bound * np.abs(r)
            methods = [m for m in TIMED if m != "nsga2-big-knee" or epoch < n_big]
            solve = {m: _solver(m, b, br, r, rr, cfg["search_range"], cfg, seed_ns) for m in methods}
            times: dict[str, list[float]] = {m: [] for m in methods}
            first: dict[str, np.ndarray] = {}
            nfev: dict[str, int] = {}
            same = True
            for k in range(repeats):
                for m in methods[k % len(methods):] + methods[:k % len(methods)]:
                    t0 = time.thread_time()
                    res = solve[m]()
                    times[m].append(time.thread_time() - t0)
                    q = res.q
                    nfev[m] = int(getattr(res, "nfev", 0) or 0)
                    if m in first:
                        same &= bool(np.array_equal(q, first[m]))
                    else:
                        first[m] = q
            out.append(TimedEpoch(replica=replica, epoch=epoch, times={m: tuple(v) for m, v in times.items()},
                                  error_deg={m: angle_deg(q, q_exact()) for m, q in first.items()}, nfev=nfev,
                                  identical=same))
    return tuple(out)
