"""Stored robust-GA runs of ``onoff-tuning``: replay a finished GA whose inputs and code match, keep new ones.

S4's robust GA at the paper's protocol (population 70, up to 1000 generations, 1000 LHS
samples per candidate) takes 2-9 minutes per run on two CPU cores, and the study's claims need
30 of them (5 seeds x (5 Table 6 cases + the all-four case under the second penalty reading)).
A run like that is made once -- on a GPU machine or over several CPU sessions -- and its results
are kept as one small JSON file per GA; a later study run with the same inputs reads them
instead of re-running the GA and re-does everything else (the 10 000-run evaluations, sweeps,
claims) itself.

A stored run is replayed only when all of this holds, and a stored run that fails a check is
refused with an error naming its file (never silently replayed, never silently skipped):

* its **fingerprint** equals the one the study would run now. It binds (1) every input of
  :func:`~adcskit.control.tuning.tune_robust` (distributions, weight ratio, sample count, nominal
  loop and settings, population, generation cap, stopping rule, bounds, overshoot limit and
  penalty, pymoo seed, penalty reading) and a **model probe** -- three nominal closed-loop
  simulations whose metrics, to 9 significant digits, follow the loop model (``inputs_fingerprint``);
  (2) the **code** the GA runs: a SHA-256 per module of :data:`CODE_MODULES` (GA driver and
  objective, eq. 10 and the stopping rule, the LHS sampler, the on-off loop and its kernels), of
  the module's tokens without comments and docstrings (:func:`code_hash`), so a changed penalty,
  sampler, stopping rule or kernel misses every stored run while a reworded docstring does not;
  (3) the versions of :data:`LIBRARIES` (pymoo runs the GA; numpy, scipy and numba compute it).
  A run whose fingerprint differs is not replayed (the GA runs again, or the study keeps its
  reduced protocol when the packaged runs do not cover it);
* its file matches the store's **manifest** (``SHA256SUMS`` beside the files, when the
  directory has one -- the packaged store does): a file whose SHA-256 differs, or that the
  manifest does not list, is refused;
* **re-evaluated** on the GA's own training samples (the same LHS draw from the same seed),
  the stored gains give the stored objective, mean, std and largest overshoot **bit for bit**
  (:func:`~adcskit.control.tuning.robust_objective_at`, the computation ``tune_robust`` made
  its result with; its cost: docs/benchmarks.md). An edited ``x`` or ``fun`` is refused.

The backend is not in the fingerprint (CPU and CUDA agree to ~1e-9 relative and fire
identically), but the exact re-evaluation runs on the backend of the study run: a CUDA-made run
verifies on the CUDA backend. Each file's provenance records the backend, the date and time of
day, machine, adcskit commit, wall time, code hashes and library versions of the run that made
it, and every later **re-stamp** (:func:`restamp`: a new fingerprint definition or changed code
adopted without re-running the GAs, only after the exact re-evaluation of every run passed and
at least one run recomputed from scratch came out bit-identical in ``x`` and ``fun``; what was
re-verified and what was recomputed is written into the provenance).

Hand-written here: only the file bookkeeping (JSON, hashes, atomic writes); the GA is pymoo's.

Re-stamp the packaged store after a change of the code or the libraries (the quick test
``tests/studies/test_ga_store.py`` fails until it is done)::

    PYTHONPATH=src python benchmarks/restamp_ga_store.py --recompute sweep_all_1 s4_all_mean
"""

from __future__ import annotations

import ast
import dataclasses
import datetime as _dt
import functools
import hashlib
import importlib
import importlib.metadata
import inspect
import io
import json
import os
import platform
import subprocess
import time
import tokenize
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from adcskit.control.tuning import (
    RobustTuningResult,
    evaluate_gains,
    robust_objective_at,
    tune_robust,
)
from adcskit.errors import AdcskitWarning, ConfigError
from adcskit.studies._runner import write_json_atomic

__all__ = ["PACKAGED", "MANIFEST", "CODE_MODULES", "LIBRARIES", "GAStore", "StoredRunError", "code_hash",
           "code_stamp", "model_probe", "resolve_store", "restamp", "write_manifest"]

#: The stored paper-scale runs that ship with adcskit (``ga_store = "auto"`` reads them when
#: ``paper_scale`` is true)
PACKAGED = Path(__file__).with_name("paper_scale_ga")
#: The manifest of a store directory: ``<sha256>  <file name>`` per stored run (``sha256sum`` format)
MANIFEST = "SHA256SUMS"
#: The modules whose code a stored GA ran: the GA driver and its objective, eq. 10 and the S4
#: stopping rule, the LHS sampler, the on-off loop, its kernels and actuator pieces
CODE_MODULES = ("adcskit.control.tuning", "adcskit.control.robust", "adcskit.uncertainty.sampling",
                "adcskit.control.onoff", "adcskit.control._onoff_kernels", "adcskit.control._actuator")
#: The libraries whose versions a stored GA is bound to (pymoo runs the GA, numpy/scipy/numba compute it)
LIBRARIES = ("pymoo", "numpy", "scipy", "numba")

_PROBE_GAINS = np.array([[56.24, 0.02, 49.99], [39.7, 0.03, 46.3], [20.0, 0.5, 30.0]])
_FORMAT = 2


class StoredRunError(ConfigError):
    """A stored GA run that fails its manifest entry or its exact re-evaluation (the message names the file)."""


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


def code_hash(source: str) -> str:
    r"""SHA-256 of a module's code: its token stream without comments, blank lines and bare string
    statements (docstrings), so a behaviour change changes it and a reworded docstring does not.

    Examples
    --------
    >>> a = code_hash('def f(x):\n    "Twice."\n    return 2 * x  # double\n')
    >>> a == code_hash('def f(x):\n    "Two times x."\n\n    return 2 * x\n')
    True
    >>> a == code_hash('def f(x):\n    return 3 * x\n')
    False
    """
    tree = ast.parse(source)
    spans = [(n.lineno, n.col_offset, n.end_lineno, n.end_col_offset) for n in ast.walk(tree)
             if isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant) and isinstance(n.value.value, str)]

    def in_doc(pos: tuple[int, int]) -> bool:
        return any((a, b) <= pos < (c, d) for a, b, c, d in spans)

    keep = []
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type in (tokenize.COMMENT, tokenize.NL) or in_doc(tok.start):
            continue
        keep.append(tokenize.tok_name[tok.type] if tok.type in (tokenize.INDENT, tokenize.DEDENT, tokenize.NEWLINE)
                    else tok.string)
    return hashlib.sha256("\n".join(keep).encode()).hexdigest()


@functools.cache
def code_stamp() -> dict[str, dict[str, str]]:
    """``{"code": {module: code_hash}, "versions": {library: version}}`` of this installation."""
    code = {}
    for name in CODE_MODULES:
        mod = importlib.import_module(name)
        code[name] = code_hash(Path(inspect.getfile(mod)).read_text(encoding="utf-8"))
    return {"code": code, "versions": {lib: importlib.metadata.version(lib) for lib in LIBRARIES}}


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


def inputs_fingerprint(inputs: dict[str, Any], probe: list[str]) -> str:
    """SHA-256 of the canonical JSON of the GA's inputs and the model probe (the whole fingerprint
    of the format-1 files; the inputs part of format 2)."""
    text = json.dumps({"format": 1, "inputs": _canon(inputs), "probe": probe}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()


def fingerprint(inputs_fp: str, stamp: dict[str, dict[str, str]]) -> str:
    """SHA-256 binding the inputs fingerprint, the code hashes and the library versions."""
    text = json.dumps({"format": _FORMAT, "inputs": inputs_fp, "code": stamp["code"], "versions": stamp["versions"]},
                      sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()


def _commit() -> str:
    """The adcskit commit (short), with ``-dirty`` when tracked files differ from it ("" outside git)."""
    try:
        out = subprocess.run(["git", "-C", str(Path(__file__).parent), "describe", "--always", "--dirty", "--abbrev=7",
                              "--match", "no-tags-wanted"], capture_output=True, text=True, timeout=10)
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


def _now() -> str:
    return _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M:%S UTC")


def _result_from(d: dict[str, Any]) -> RobustTuningResult:
    """The stored ``RobustTuningResult.to_dict()`` back as the result (floats exact: JSON keeps repr)."""
    return RobustTuningResult(**{**d, "x": np.array(d["x"], dtype=float),
                                 "history": np.array(d["history"], dtype=float)})


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def read_manifest(directory: Path) -> dict[str, str] | None:
    """``{file name: sha256}`` of ``directory``'s manifest, or None when it has none."""
    path = Path(directory) / MANIFEST
    if not path.is_file():
        return None
    out = {}
    for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if not line.strip():
            continue
        digest, sep, name = line.partition("  ")
        if not sep or len(digest) != 64:
            raise StoredRunError(f"GA store manifest {str(path)!r} line {n} is not '<sha256>  <file>': {line!r}")
        out[name] = digest
    return out


def write_manifest(directory: str | os.PathLike[str]) -> Path:
    """Write ``directory``'s manifest: the SHA-256 of every stored run (``*.json``) in it."""
    directory = Path(directory)
    lines = [f"{_sha256(f)}  {f.name}" for f in sorted(directory.glob("*.json"))]
    path = directory / MANIFEST
    tmp = path.with_suffix(".tmp")
    tmp.write_text("\n".join(lines) + "\n", encoding="utf-8")
    os.replace(tmp, path)
    return path


def _bits(v: Any) -> str:
    return float(v).hex()


def _verify(path: Path, label: str, stored: dict[str, Any], dists, kwargs: dict[str, Any]) -> float:
    """Re-evaluate a stored run's gains on its training samples; refuse unless the stored objective,
    mean, std and largest overshoot come back bit for bit. Returns the seconds it took."""
    t0 = time.perf_counter()
    x = np.asarray(stored["x"], dtype=float)
    try:
        again = robust_objective_at(x, dists, **kwargs)
    except ValueError as exc:
        raise StoredRunError(f"stored GA run {label!r} ({str(path)!r}) cannot be re-evaluated: {exc}") from None
    bad = [f"{k} {stored[k]!r} stored, {again[k]!r} re-evaluated" for k in again if _bits(stored[k]) != _bits(again[k])]
    if bad:
        raise StoredRunError(f"stored GA run {label!r} ({str(path)!r}) refused: its gains x = {stored['x']} do not "
                             f"reproduce its stored result on its training samples ({'; '.join(bad)}); the file was "
                             "edited or made by other code")
    return time.perf_counter() - t0


class GAStore:
    """A directory of stored robust-GA runs (one JSON file each, and optionally a manifest).

    Parameters
    ----------
    directory : path
        Where the runs are (created on the first write).
    writable : bool
        Keep newly run GAs there (False: read only, e.g. the packaged snapshot).
    verify : bool
        Re-evaluate a stored run exactly before replaying it (True; False only to count runs).

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

    def __init__(self, directory: str | os.PathLike[str], *, writable: bool, verify: bool = True) -> None:
        self.directory = Path(directory)
        self.writable = bool(writable)
        self.verify = bool(verify)
        self._probe: dict[tuple, list[str]] = {}
        #: seconds spent re-evaluating replayed runs, per label
        self.verify_s: dict[str, float] = {}

    def _probe_of(self, base, settings) -> list[str]:
        key = (repr(base), repr(settings))
        if key not in self._probe:
            self._probe[key] = model_probe(base, settings)
        return self._probe[key]

    def _load(self, path: Path, manifest: dict[str, str] | None) -> dict[str, Any] | None:
        """A stored file's data: refused (error) when the manifest does not vouch for it; None when
        it cannot be read in a store without a manifest (a damaged file is then ignored)."""
        if manifest is not None:
            if path.name not in manifest:
                raise StoredRunError(f"stored GA run {str(path)!r} refused: not listed in the store's manifest "
                                     f"{str(self.directory / MANIFEST)!r}")
            if _sha256(path) != manifest[path.name]:
                raise StoredRunError(f"stored GA run {str(path)!r} refused: its SHA-256 differs from the store's "
                                     f"manifest {str(self.directory / MANIFEST)!r} (the file was changed)")
        try:
            return json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            if manifest is not None:
                raise StoredRunError(f"stored GA run {str(path)!r} refused: not readable JSON") from None
            return None  # a damaged file is ignored (and overwritten when writable)

    def _find(self, fp: str) -> tuple[Path, dict[str, Any]] | None:
        if not self.directory.is_dir():
            return None
        manifest = read_manifest(self.directory)
        # every candidate is loaded (and vouched for by the manifest) before one is returned
        found = [(path, self._load(path, manifest)) for path in sorted(self.directory.glob(f"*_{fp[:16]}.json"))]
        return next(((path, d) for path, d in found if d is not None and d.get("fingerprint") == fp), None)

    def _inputs_fingerprint(self, dists, kwargs: dict[str, Any]) -> str:
        bound = inspect.signature(tune_robust).bind(dists, **kwargs)
        bound.apply_defaults()  # every input explicit: a changed default changes the fingerprint
        inputs = {k: v for k, v in bound.arguments.items() if k not in ("backend", "time_estimate")}
        inputs["dists"] = dict(dists)
        return inputs_fingerprint(inputs, self._probe_of(inputs["base"], inputs["settings"]))

    def _fingerprint(self, dists, kwargs: dict[str, Any]) -> str:
        return fingerprint(self._inputs_fingerprint(dists, kwargs), code_stamp())

    def has(self, dists, **kwargs: Any) -> bool:
        """Whether the store holds the run :meth:`tune` would replay for these arguments (a file the
        manifest does not vouch for is refused here already; the exact re-evaluation is :meth:`tune`'s)."""
        kwargs.pop("backend", None)
        return self._find(self._fingerprint(dists, kwargs)) is not None

    def tune(self, label: str, dists, **kwargs: Any) -> tuple[RobustTuningResult, dict[str, Any] | None]:
        """:func:`~adcskit.control.tuning.tune_robust` ``(dists, **kwargs)``, or its stored result.

        Returns the result and, when it was read from the store, that run's provenance (else None).
        ``label`` names the file (e.g. ``s0_all_sample``); the fingerprint decides the match, the
        exact re-evaluation on the training samples whether the match is replayed
        (:class:`StoredRunError` naming the file if not).
        """
        backend = kwargs.pop("backend", "cpu")
        fp = self._fingerprint(dists, kwargs)
        hit = self._find(fp)
        if hit is not None:
            path, data = hit
            if self.verify:
                self.verify_s[label] = _verify(path, label, data["result"], dists, {**kwargs, "backend": backend})
            return _result_from(data["result"]), {"label": label, "file": path.name, **data["provenance"]}
        started = _now()
        t0 = time.perf_counter()
        res = tune_robust(dists, backend=backend, **kwargs)
        wall = time.perf_counter() - t0
        if self.writable:
            try:
                self._write(label, self._inputs_fingerprint(dists, kwargs), res, started, wall)
            except OSError as exc:  # the result stands; only its copy for later runs is lost
                warnings.warn(f"ga_store: could not keep GA run {label!r} in {str(self.directory)!r} "
                              f"({exc.strerror or exc}); it will run again next time", AdcskitWarning, stacklevel=2)
        return res, None

    def _write(self, label: str, inputs_fp: str, res: RobustTuningResult, started: str, wall_s: float) -> None:
        stamp = code_stamp()
        fp = fingerprint(inputs_fp, stamp)
        data = {"format": _FORMAT, "label": label, "fingerprint": fp, "inputs_fingerprint": inputs_fp, **stamp,
                "result": res.to_dict(),
                "provenance": {"date": started, "finished": _now(), "backend": res.backend, "machine": _machine(),
                               "commit": _commit(), "wall_s": round(wall_s, 1), "python": platform.python_version(),
                               **stamp}}
        path = self.directory / f"{label}_{fp[:16]}.json"
        write_json_atomic(path, data)
        if (self.directory / MANIFEST).is_file():  # keep the manifest of a store that has one
            entries = read_manifest(self.directory) or {}
            entries[path.name] = _sha256(path)
            _write_entries(self.directory, entries)


def _write_entries(directory: Path, entries: dict[str, str]) -> None:
    path = directory / MANIFEST
    tmp = path.with_suffix(".tmp")
    tmp.write_text("".join(f"{entries[n]}  {n}\n" for n in sorted(entries)), encoding="utf-8")
    os.replace(tmp, path)


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


def restamp(directory: str | os.PathLike[str], jobs, recompute: tuple[str, ...], *, backend: str = "cpu",
            note: str = "", log=print) -> dict[str, Any]:
    """Re-stamp the stored runs of ``directory`` with this installation's fingerprint (code hashes,
    library versions) without re-running their GAs -- only when the evidence says they are this
    code's results:

    1. every stored file belongs to a job of ``jobs`` (``(label, dists, tune_robust keywords)``,
       e.g. :func:`~adcskit.studies.onoff_tuning.experiment.ga_jobs`) with the same inputs
       fingerprint, and the manifest (if any) vouches for it;
    2. every stored run's gains reproduce its stored objective, mean, std and largest overshoot
       bit for bit on its training samples;
    3. each run of ``recompute`` (at least one) run again from scratch gives the stored ``x``,
       ``fun``, generations and history bit for bit.

    Only then is every file rewritten (new fingerprint and name, its provenance extended by a
    ``restamps`` entry saying what was re-verified and recomputed, when and where) and the
    manifest renewed; on any failure nothing is written and :class:`StoredRunError` says which
    file failed. Returns a summary with the measured seconds.
    """
    directory = Path(directory)
    if not recompute:
        raise ConfigError("restamp needs at least one run to recompute from scratch (recompute=('label', ...))")
    store = GAStore(directory, writable=False)
    manifest = read_manifest(directory)
    by_label = {label: (dists, kw) for label, dists, kw in jobs}
    unknown = [r for r in recompute if r not in by_label]
    if unknown:
        raise ConfigError(f"recompute names runs that are not among the jobs: {unknown}")
    stamp = code_stamp()
    files, verify_s, recompute_s = [], {}, {}
    t_all = time.perf_counter()
    for path in sorted(directory.glob("*.json")):
        data = store._load(path, manifest)
        if data is None:
            raise StoredRunError(f"stored GA run {str(path)!r} refused: not readable JSON")
        label = data.get("label")
        if label not in by_label:
            raise StoredRunError(f"stored GA run {str(path)!r}: label {label!r} is not one of the jobs")
        dists, kw = by_label[label]
        kw = {k: v for k, v in kw.items() if k != "backend"}
        inputs_fp = store._inputs_fingerprint(dists, kw)
        if data.get("inputs_fingerprint", data.get("fingerprint") if data.get("format") == 1 else None) != inputs_fp:
            raise StoredRunError(f"stored GA run {str(path)!r} was made from other inputs than job {label!r}")
        verify_s[label] = _verify(path, label, data["result"], dists, {**kw, "backend": backend})
        log(f"{label}: objective re-evaluated bit for bit ({verify_s[label]:.2f} s)")
        files.append((path, label, inputs_fp, data))
    for label in recompute:
        dists, kw = by_label[label]
        path, _, _, data = next(f for f in files if f[1] == label)
        t0 = time.perf_counter()
        res = tune_robust(dists, **{**kw, "backend": backend})
        recompute_s[label] = time.perf_counter() - t0
        st = data["result"]
        same = (len(res.x) == len(st["x"]) and all(_bits(a) == _bits(b) for a, b in zip(res.x, st["x"], strict=True))
                and _bits(res.fun) == _bits(st["fun"]) and res.nit == st["nit"]
                and [_bits(v) for v in res.history] == [_bits(v) for v in st["history"]])
        if not same:
            raise StoredRunError(f"stored GA run {label!r} ({str(path)!r}) recomputed from scratch differs: x "
                                 f"{res.x.tolist()} vs {st['x']}, fun {res.fun!r} vs {st['fun']!r}, generations "
                                 f"{res.nit} vs {st['nit']}")
        log(f"{label}: recomputed from scratch, x, fun, generations and history bit-identical "
            f"({recompute_s[label]:.1f} s)")
    when, commit, machine = _now(), _commit(), _machine()
    entry = {"date": when, "commit": commit, "machine": machine, "backend": backend,
             "python": platform.python_version(), **stamp,
             "verified": f"all {len(files)} stored runs of this store: gains re-evaluated on their training samples, "
                         "fun, mean, std and largest overshoot bit-identical to the stored values",
             "recomputed": {lab: f"from scratch in {recompute_s[lab]:.1f} s: x, fun, generations and history "
                                 "bit-identical" for lab in recompute},
             "wall_s": round(time.perf_counter() - t_all, 1)}
    if note:
        entry["note"] = note
    written = []
    for path, label, inputs_fp, data in files:
        fp = fingerprint(inputs_fp, stamp)
        prov = dict(data["provenance"])
        prov["restamps"] = [*prov.get("restamps", []), entry]
        new = {"format": _FORMAT, "label": label, "fingerprint": fp, "inputs_fingerprint": inputs_fp, **stamp,
               "result": data["result"], "provenance": prov}
        target = directory / f"{label}_{fp[:16]}.json"
        write_json_atomic(target, new)
        if target != path:
            path.unlink()
        written.append(target.name)
    write_manifest(directory)
    return {"files": written, "verify_s": verify_s, "recompute_s": recompute_s, "wall_s": entry["wall_s"]}
