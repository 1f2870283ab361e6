"""Stored robust-GA runs of ``onoff-tuning``: replay a finished GA whose inputs match, keep new ones.

S4's robust GA at the paper's protocol (population 70, up to 1000 generations, 1000 LHS
samples per candidate) takes 5-9 minutes per run on two CPU cores, and the study's claims need
30 of them (5 seeds x (5 Table 6 cases + the all-four case under the second penalty reading)).
A run like that is made once -- on a GPU machine or over several CPU sessions -- and its results
are kept as one small JSON file per GA; a later study run with the same inputs reads them
instead of re-running the GA and re-does everything else (the 10 000-run evaluations, sweeps,
claims) itself.

A stored run is used only when its **fingerprint** equals the one the study would run now: every
input of :func:`~adcskit.control.tuning.tune_robust` (distributions, weight ratio, sample count,
nominal loop and settings, population, generation cap, stopping rule, bounds, overshoot limit and
penalty, pymoo seed, penalty reading) plus a **model probe** -- three nominal closed-loop
simulations (S4 Table 4's and Table 6's gains, one damped triple) whose metrics, to 9
significant digits, change whenever the loop model or its kernel does. A model change therefore
invalidates every stored run instead of replaying a GA of another model. The backend is not in
the fingerprint (CPU and CUDA agree to ~1e-9 relative and fire identically); it is in each file's
provenance, with the date, machine, adcskit commit and wall time of the run.

Hand-written here: only the file bookkeeping (JSON, atomic writes); the GA is pymoo's.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import hashlib
import inspect
import json
import os
import platform
import subprocess
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from adcskit.control.tuning import RobustTuningResult, evaluate_gains, tune_robust
from adcskit.errors import AdcskitWarning, ConfigError
from adcskit.studies._runner import write_json_atomic

__all__ = ["PACKAGED", "GAStore", "model_probe", "resolve_store"]

#: The stored paper-scale runs that ship with adcskit (``ga_store = "auto"`` reads them when
#: ``paper_scale`` is true)
PACKAGED = Path(__file__).with_name("paper_scale_ga")

_PROBE_GAINS = np.array([[56.24, 0.02, 49.99], [39.7, 0.03, 46.3], [20.0, 0.5, 30.0]])
_FORMAT = 1


def model_probe(base, settings) -> list[str]:
    """Nominal metrics of three gain triples (mean |error| over the window, overshoot, fuel) to
    9 significant digits: the part of the fingerprint that follows the loop model itself.

    Examples
    --------
    >>> from adcskit.studies.onoff_tuning.config import Config
    >>> c = Config()
    >>> p = model_probe(c.base(), c.settings())
    >>> len(p), p == model_probe(c.base(), c.settings())
    (9, True)
    """
    m = evaluate_gains(_PROBE_GAINS, base=base, settings=settings)
    vals = np.concatenate([np.asarray(m.mean_abs_err_last, float), np.nan_to_num(np.asarray(m.overshoot_pct, float)),
                           np.asarray(m.fuel, float)])
    return [f"{v:.9g}" for v in vals]


def _canon(obj: Any) -> Any:
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {"type": type(obj).__name__, **{f.name: _canon(getattr(obj, f.name)) for f in dataclasses.fields(obj)}}
    if isinstance(obj, dict):
        return {str(k): _canon(v) for k, v in sorted(obj.items())}
    if isinstance(obj, list | tuple):
        return [_canon(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [_canon(v) for v in obj.tolist()]
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, float):
        return repr(obj)  # exact
    return obj


def fingerprint(inputs: dict[str, Any], probe: list[str]) -> str:
    """SHA-256 of the canonical JSON of the GA's inputs and the model probe."""
    text = json.dumps({"format": _FORMAT, "inputs": _canon(inputs), "probe": probe}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()


def _commit() -> str:
    try:
        out = subprocess.run(["git", "-C", str(Path(__file__).parent), "rev-parse", "--short", "HEAD"],
                             capture_output=True, text=True, timeout=10)
        return out.stdout.strip() if out.returncode == 0 else ""
    except (OSError, subprocess.SubprocessError):
        return ""


def _machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{cpu}, {os.cpu_count()} cores"


def _result_from(d: dict[str, Any]) -> RobustTuningResult:
    """The stored ``RobustTuningResult.to_dict()`` back as the result (floats exact: JSON keeps repr)."""
    return RobustTuningResult(**{**d, "x": np.array(d["x"], dtype=float),
                                 "history": np.array(d["history"], dtype=float)})


class GAStore:
    """A directory of stored robust-GA runs (one JSON file each).

    Parameters
    ----------
    directory : path
        Where the runs are (created on the first write).
    writable : bool
        Keep newly run GAs there (False: read only, e.g. the packaged snapshot).

    Examples
    --------
    >>> import tempfile
    >>> from adcskit.studies.onoff_tuning.config import Config
    >>> c = Config(n_lhs=3, ga_max_gen=1, ga_pop=4)
    >>> store = GAStore(tempfile.mkdtemp(), writable=True)
    >>> kw = dict(ratio=10.0, n_samples=3, base=c.base(), settings=c.settings(), pop_size=4, max_gen=1, rng=7)
    >>> r1, src1 = store.tune("s0_delay_sample", c.dists("delay"), **kw)
    >>> r2, src2 = store.tune("s0_delay_sample", c.dists("delay"), **kw)
    >>> src1 is None, src2["label"], bool((r1.x == r2.x).all()), r1.fun == r2.fun
    (True, 's0_delay_sample', True, True)
    """

    def __init__(self, directory: str | os.PathLike[str], *, writable: bool) -> None:
        self.directory = Path(directory)
        self.writable = bool(writable)
        self._probe: dict[tuple, list[str]] = {}

    def _probe_of(self, base, settings) -> list[str]:
        key = (repr(base), repr(settings))
        if key not in self._probe:
            self._probe[key] = model_probe(base, settings)
        return self._probe[key]

    def _find(self, fp: str) -> dict[str, Any] | None:
        if not self.directory.is_dir():
            return None
        for path in sorted(self.directory.glob(f"*_{fp[:16]}.json")):
            try:
                data = json.loads(path.read_text(encoding="utf-8"))
            except (OSError, ValueError):
                continue  # a damaged file is ignored (and overwritten when writable)
            if data.get("fingerprint") == fp:
                return data
        return None

    def _fingerprint(self, dists, kwargs: dict[str, Any]) -> str:
        bound = inspect.signature(tune_robust).bind(dists, **kwargs)
        bound.apply_defaults()  # every input explicit: a changed default changes the fingerprint
        inputs = {k: v for k, v in bound.arguments.items() if k not in ("backend", "time_estimate")}
        inputs["dists"] = dict(dists)
        return fingerprint(inputs, self._probe_of(inputs["base"], inputs["settings"]))

    def has(self, dists, **kwargs: Any) -> bool:
        """Whether the store holds the run :meth:`tune` would replay for these arguments."""
        return self._find(self._fingerprint(dists, kwargs)) is not None

    def tune(self, label: str, dists, **kwargs: Any) -> tuple[RobustTuningResult, dict[str, Any] | None]:
        """:func:`~adcskit.control.tuning.tune_robust` ``(dists, **kwargs)``, or its stored result.

        Returns the result and, when it was read from the store, that run's provenance (else None).
        ``label`` names the file (e.g. ``s0_all_sample``); the fingerprint decides the match.
        """
        backend = kwargs.pop("backend", "cpu")
        fp = self._fingerprint(dists, kwargs)
        hit = self._find(fp)
        if hit is not None:
            return _result_from(hit["result"]), {"label": label, **hit["provenance"]}
        t0 = time.perf_counter()
        res = tune_robust(dists, backend=backend, **kwargs)
        wall = time.perf_counter() - t0
        if self.writable:
            try:
                self._write(label, fp, res, wall)
            except OSError as exc:  # the result stands; only its copy for later runs is lost
                warnings.warn(f"ga_store: could not keep GA run {label!r} in {str(self.directory)!r} "
                              f"({exc.strerror or exc}); it will run again next time", AdcskitWarning, stacklevel=2)
        return res, None

    def _write(self, label: str, fp: str, res: RobustTuningResult, wall_s: float) -> None:
        data = {"format": _FORMAT, "label": label, "fingerprint": fp, "result": res.to_dict(),
                "provenance": {"date": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC"),
                               "backend": res.backend, "machine": _machine(), "commit": _commit(),
                               "wall_s": round(wall_s, 1)}}
        path = self.directory / f"{label}_{fp[:16]}.json"
        write_json_atomic(path, data)


def resolve_store(spec: str, paper_scale: bool) -> GAStore | None:
    """The store a config's ``ga_store`` names: ``"auto"`` = the packaged snapshot, read only,
    when ``paper_scale`` is true (else none); ``"none"`` = none; a path = that directory, read
    and written."""
    allowed = f"ga_store must be 'auto', 'none' or a writable directory; got {spec!r}"
    if not isinstance(spec, str) or not spec.strip():
        raise ConfigError(allowed)
    if spec == "none" or (spec == "auto" and not paper_scale):
        return None
    if spec == "auto":
        return GAStore(PACKAGED, writable=False)
    path = Path(spec).expanduser()
    try:  # checked before hours of GA runs, not after the first one
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ConfigError(f"{allowed} ({exc.strerror or exc})") from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise ConfigError(f"{allowed} (not writable)")
    return GAStore(path, writable=True)
