"""Mutation engine and outcome checks of the robustness suite (issue 12).

A *case* (see ``cases.py``) is a valid call of one public callable. The engine derives, for
every argument of that call, a list of *mutations* from the argument's kind (inferred from the
valid value, or given explicitly) and checks each outcome against the guarantee of
``docs/conventions.md`` ("Errors"):

* an exception must be an :class:`adcskit.errors.AdcskitError` or a ``ValueError`` /
  ``TypeError`` subclass whose message names the mutated argument (or one of its aliases);
* a returned value must contain only finite numbers when the input was finite (NaN and inf are
  allowed only in result fields a case declares with ``nan_ok``), and must have the shape of
  the valid call's result when the mutation keeps the input's shape;
* mutations that only change the *container* of a valid value (0-d array instead of a float,
  a read-only or non-contiguous array, a numpy scalar, ``numpy.bool_``) must be accepted and
  give the valid call's result;
* a mutation a case declares degenerate must be rejected or answered with ``success=False``;
* a negative value of an argument a case declares ``positive`` must be rejected;
* no call may use more than ``CALL_TIMEOUT_S`` of CPU time or ``CALL_WALL_TIMEOUT_S`` of
  wall-clock time (a hang).
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import signal
from collections import Counter
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from adcskit.errors import AdcskitError

#: CPU-time limit of one call in the suite (seconds, all threads of the process); a call that
#: takes longer is a hang. CPU time, not wall-clock time, so that a loaded machine (a shared CI
#: runner, JIT compilation while other jobs run) does not turn a slow call into a "hang".
CALL_TIMEOUT_S = float(os.environ.get("ADCSKIT_ROBUSTNESS_TIMEOUT", "30"))

#: Wall-clock limit of one call (seconds): catches calls that block without using the CPU
#: (a lock, a lost worker), with room for a loaded machine.
CALL_WALL_TIMEOUT_S = float(os.environ.get("ADCSKIT_ROBUSTNESS_WALL_TIMEOUT", str(4 * CALL_TIMEOUT_S)))

#: Counts of the whole session, printed by ``conftest.py`` at the end of the run.
STATS: Counter[str] = Counter()


# --------------------------------------------------------------------------------------------
# Cases
# --------------------------------------------------------------------------------------------


@dataclass
class Case:
    """One valid call of a public callable plus what the suite may assume about it.

    Attributes
    ----------
    name : str
        ``"subpackage.attr"`` as listed in the subpackage's ``__all__`` (``"attitude.skew"``),
        optionally followed by ``".method"`` for a method of a public class.
    valid : callable
        Returns a fresh ``dict`` of keyword arguments of a valid call (fresh objects each time,
        since mutations may be applied in place).
    target : callable, optional
        Returns the callable to call with those arguments; default: the object named by
        ``name`` (``adcskit.<subpackage>.<attr>``).
    kinds : dict
        Per-argument kind overriding the inferred one (see ``MUTATORS``); ``"skip"`` leaves the
        argument alone.
    positive : tuple of str
        Arguments that are physical quantities which must be > 0 (or >= 0): their negative
        mutation must be rejected.
    degenerate : dict
        ``label -> dict of argument overrides`` that make the problem degenerate: the call
        must raise a clean error or return ``success=False``.
    nonfinite_ok : tuple of str
        Arguments for which inf is a legal value (e.g. an unbounded truncation limit).
    nan_ok : tuple of str
        Result fields (attribute / key names, or ``"*"``) that may legitimately hold NaN or inf.
    aliases : dict
        ``arg -> tuple of words``: an error about ``arg`` may name it by one of these instead
        (e.g. a config field named inside its own validation).
    exact : bool
        Container mutations must reproduce the valid result (set False for random outputs
        that depend on object identity).
    slow : bool
        Mutations of this case run only in the exhaustive (``-m slow``) variant; the default
        run still makes the valid call and a few mutations.
    extra : dict
        ``label -> (arg, value, category)``: hand-written mutations on top of the generated
        ones (e.g. an ill-typed solver option); ``category`` as in :class:`Mutation`.
    shape_stable : bool
        Whether a finite mutation keeps the result's shapes (False where the output size
        depends on the values, e.g. the number of distinct optima).
    exit_ok : bool
        A command-line entry point: ``SystemExit(2)`` (argparse's one-line usage error) is a
        clean rejection.
    open_keys : tuple of str
        Mapping arguments whose keys are open (passed on, e.g. solver options): an unknown key
        may be accepted.
    signature_flags : bool
        Also mutate the ``bool``-default parameters of the callable's signature that the valid
        call leaves out (non-bool stand-ins must be rejected).
    known_open : str
        A known, reported failure owned elsewhere (the issue and who fixes it): the case still
        runs and its failures are counted, but the test is an expected failure until fixed.
    """

    name: str
    valid: Callable[[], dict[str, Any]]
    target: Callable[[], Callable[..., Any]] | None = None
    kinds: dict[str, str] = field(default_factory=dict)
    positive: tuple[str, ...] = ()
    degenerate: dict[str, dict[str, Any]] = field(default_factory=dict)
    nonfinite_ok: tuple[str, ...] = ()
    nan_ok: tuple[str, ...] = ()
    aliases: dict[str, tuple[str, ...]] = field(default_factory=dict)
    exact: bool = True
    slow: bool = False
    extra: dict[str, tuple[str, Any, str]] = field(default_factory=dict)
    exit_ok: bool = False
    shape_stable: bool = True
    open_keys: tuple[str, ...] = ()
    signature_flags: bool = True
    known_open: str = ""

    def resolve(self) -> Callable[..., Any]:
        if self.target is not None:
            return self.target()
        import importlib

        parts = self.name.split(".")
        for cut in range(len(parts) - 1, 0, -1):
            try:
                obj: Any = importlib.import_module("adcskit." + ".".join(parts[:cut]))
            except ImportError:
                continue
            for attr in parts[cut:]:
                obj = getattr(obj, attr)
            return obj
        raise LookupError(self.name)


# --------------------------------------------------------------------------------------------
# Mutations
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Mutation:
    """One change of one argument.

    ``category`` is one of

    * ``"same"``: a container change of the valid value; must be accepted with equal result;
    * ``"finite"``: a finite but extreme or odd value of the right shape; clean error or a
      finite result of the valid result's shape;
    * ``"reshape"``: finite, different shape; clean error or a finite result;
    * ``"nonfinite"``: NaN/inf inside; clean error (or a result, if the argument is in
      ``nonfinite_ok``);
    * ``"type"``: a wrong type (None, string, complex, ...); clean error, or a finite result;
    * ``"negative"``: negative physical quantity; rejected if the argument is ``positive``;
    * ``"strict"``: a value that must be rejected outright, since accepting it would silently do
      something else than the caller wrote: a non-bool flag (``"no"`` is truthy), an unknown
      choice, an unknown key of a mapping with a closed set of keys (a case lists the mappings
      that pass unknown keys on in ``open_keys``).
    """

    label: str
    value: Any
    category: str


def _arr(v: Any) -> np.ndarray:
    return np.array(v, dtype=float)


def _set_one(a: np.ndarray, x: float, idx: int = 0) -> np.ndarray:
    b = np.array(a, dtype=float, copy=True)
    if b.size:
        b.flat[idx % b.size] = x
    return b


def _noncontiguous(a: np.ndarray) -> np.ndarray:
    if a.ndim == 0 or a.size == 0:
        return a
    big = np.repeat(a, 2, axis=-1)
    view = big[..., ::2]
    assert not view.flags.c_contiguous or a.shape[-1] == 1
    return view


def _readonly(a: np.ndarray) -> np.ndarray:
    b = np.array(a, copy=True)
    b.flags.writeable = False
    return b


def mutate_array(v: Any, idx: int = 0, big: float = 1e300) -> list[Mutation]:
    orig = np.asarray(v)
    if orig.dtype.kind not in "iuf":
        return []
    a = orig.astype(float)
    out = [
        Mutation("readonly", _readonly(orig), "same"),
        Mutation("noncontiguous", _noncontiguous(orig), "same"),
        Mutation("nan", _set_one(a, math.nan, idx), "nonfinite"),
        Mutation("inf", _set_one(a, math.inf, idx), "nonfinite"),
        Mutation("-inf", _set_one(a, -math.inf, idx), "nonfinite"),
        Mutation("+big", _set_one(a, big, idx), "finite"),
        Mutation("-big", _set_one(a, -big, idx), "finite"),
        Mutation("all-big", np.full_like(a, big), "finite"),
        Mutation("tiny", np.full_like(a, 1e-300), "finite"),
        Mutation("zeros", np.zeros_like(a), "finite"),
        Mutation("negative", -np.abs(a) - (a == 0), "negative"),
        Mutation("complex", a + 1j, "type"),
        Mutation("complex0", a.astype(complex), "type"),
        Mutation("string", "abc", "type"),
        Mutation("none", None, "type"),
        Mutation("list-of-str", [["x"]], "type"),
    ]
    if a.ndim >= 1:
        out += [
            Mutation("empty", np.empty((0,) + a.shape[1:]), "reshape"),
            Mutation("extra-row", np.concatenate([a, a[-1:]], axis=0) if a.shape[0] else a, "reshape"),
            Mutation("extra-col", np.concatenate([a, a[..., -1:]], axis=-1), "reshape"),
            Mutation("add-dim", a[None, ...], "reshape"),
            Mutation("first-elem", a.reshape(-1)[0], "reshape"),
        ]
        if a.ndim == 1:
            out.append(Mutation("as-list", orig.tolist(), "same"))
    else:
        out += [Mutation("0d", np.array(float(a)), "same"), Mutation("vector", np.array([float(a)] * 2), "reshape")]
    return out


def mutate_float(v: float) -> list[Mutation]:
    out = [
        Mutation("0d-array", np.array(v), "same"),
        Mutation("np-float", np.float64(v), "same"),
        Mutation("nan", math.nan, "nonfinite"),
        Mutation("inf", math.inf, "nonfinite"),
        Mutation("-inf", -math.inf, "nonfinite"),
        Mutation("+big", 1e300, "finite"),
        Mutation("-big", -1e300, "finite"),
        Mutation("tiny", 1e-300, "finite"),
        Mutation("zero", 0.0, "finite"),
        Mutation("negative", -abs(v) if v else -1.0, "negative"),
        Mutation("complex", complex(v, 1.0), "type"),
        Mutation("string", "abc", "type"),
        Mutation("none", None, "type"),
        Mutation("bool", True, "strict"),
        Mutation("vector", [v, v], "reshape"),
    ]
    return out


def mutate_int(v: int) -> list[Mutation]:
    return [
        Mutation("0d-array", np.array(v), "same"),
        Mutation("np-int", np.int64(v), "same"),
        Mutation("zero", 0, "finite"),
        Mutation("negative", -abs(v) - 1, "negative"),
        Mutation("huge", 2**62, "finite"),
        Mutation("float", float(v) + 0.5, "strict"),
        Mutation("big-float", 1e300, "strict"),
        Mutation("nan", math.nan, "strict"),
        Mutation("string", "3", "strict"),
        Mutation("none", None, "type"),
        Mutation("bool", True, "strict"),
    ]


def mutate_flag(v: bool) -> list[Mutation]:
    return [
        Mutation("np-bool", np.bool_(v), "same"),
        Mutation("string-no", "no", "strict"),
        Mutation("int-1", 1, "strict"),
        Mutation("int-0", 0, "strict"),
        Mutation("none", None, "type"),
    ]


def mutate_choice(v: str) -> list[Mutation]:
    return [
        Mutation("unknown", v + "-no-such-choice", "strict"),
        Mutation("empty", "", "strict"),
        Mutation("upper", v.upper() if v.upper() != v else v + "X", "type"),
        Mutation("none", None, "type"),
        Mutation("int", 1, "strict"),
    ]


def _nan_fn(*args: Any, **kw: Any) -> Any:
    return math.nan


def mutate_callable(v: Any) -> list[Mutation]:
    return [
        Mutation("none-callable", 1, "type"),
        Mutation("string", "f", "type"),
        Mutation("returns-nan", _nan_fn, "nonfinite"),
    ]


def mutate_mapping(v: Any) -> list[Mutation]:
    return [
        Mutation("none", None, "type"),
        Mutation("int", 1, "type"),
        Mutation("string", "abc", "type"),
        Mutation("unknown-key", {**dict(v), "no_such_key_xyz": 1}, "strict"),
    ]


def mutate_object(v: Any) -> list[Mutation]:
    return [
        Mutation("none", None, "type"),
        Mutation("int", 1, "type"),
        Mutation("string", "abc", "type"),
    ]


def mutate_path(v: Any) -> list[Mutation]:
    return [
        Mutation("none", None, "type"),
        Mutation("int", 1, "type"),
        Mutation("missing", "/nonexistent-adcskit-dir/x/y", "type"),
        Mutation("dev-null-child", "/dev/null/sub", "type"),
        Mutation("proc-root", "/proc/adcskit-no-such-dir", "type"),
    ]


def mutate_times(v: Any) -> list[Mutation]:
    return [
        Mutation("year-9999", "9999-12-31", "type"),
        Mutation("year-1000", "1000-01-01", "type"),
        Mutation("garbage", "not-a-date", "type"),
        Mutation("nat", np.datetime64("NaT"), "type"),
        Mutation("none", None, "type"),
        Mutation("float", 1.5, "type"),
        Mutation("complex", 1j, "type"),
        Mutation("empty", np.array([], dtype="datetime64[ns]"), "reshape"),
    ]


MUTATORS: dict[str, Callable[[Any], list[Mutation]]] = {
    "array": mutate_array,
    "float": mutate_float,
    "int": mutate_int,
    "flag": mutate_flag,
    "choice": mutate_choice,
    "callable": mutate_callable,
    "mapping": mutate_mapping,
    "object": mutate_object,
    "path": mutate_path,
    "times": mutate_times,
}


def infer_kind(value: Any) -> str:
    """Kind of a valid argument value, for choosing its mutations."""
    if isinstance(value, (bool, np.bool_)):
        return "flag"
    if isinstance(value, (int, np.integer)):
        return "int"
    if isinstance(value, (float, np.floating)):
        return "float"
    if isinstance(value, str):
        return "choice"
    if isinstance(value, (os.PathLike,)):
        return "path"
    if isinstance(value, np.ndarray) and value.dtype.kind == "M":
        return "times"
    if isinstance(value, Mapping):
        return "mapping"
    if isinstance(value, (np.ndarray, list, tuple)):
        try:
            a = np.asarray(value)
        except ValueError:
            return "object"
        return "array" if a.dtype.kind in "iuf" and a.size else "object"
    if value is None:
        return "skip"
    if callable(value) and not dataclasses.is_dataclass(value):
        return "callable"
    return "object"


def mutations_for(case: Case, arg: str, value: Any) -> list[Mutation]:
    kind = case.kinds.get(arg) or infer_kind(value)
    if kind == "skip":
        return []
    return MUTATORS[kind](value)


# --------------------------------------------------------------------------------------------
# Running and checking
# --------------------------------------------------------------------------------------------


class Hang(Exception):
    """A call exceeded CALL_TIMEOUT_S."""


def _alarm(signum: int, frame: Any) -> None:
    if signum == signal.SIGPROF:
        raise Hang(f"call exceeded {CALL_TIMEOUT_S} s of CPU time")
    raise Hang(f"call exceeded {CALL_WALL_TIMEOUT_S} s of wall-clock time")


def call_with_timeout(fn: Callable[..., Any], kwargs: dict[str, Any]) -> Any:
    old_real = signal.signal(signal.SIGALRM, _alarm)
    old_prof = signal.signal(signal.SIGPROF, _alarm)
    signal.setitimer(signal.ITIMER_REAL, CALL_WALL_TIMEOUT_S)
    signal.setitimer(signal.ITIMER_PROF, CALL_TIMEOUT_S)
    try:
        return fn(**kwargs)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.signal(signal.SIGALRM, old_real)
        signal.signal(signal.SIGPROF, old_prof)


def leaves(obj: Any, path: str = "") -> list[tuple[str, Any]]:
    """Numeric leaves of a result: ``(dotted field path, array-or-number)``."""
    out: list[tuple[str, Any]] = []
    if obj is None or isinstance(obj, (str, bytes, bool, np.bool_, Path)):
        return out
    if isinstance(obj, (int, float, complex, np.number)):
        return [(path, obj)]
    if isinstance(obj, np.ndarray):
        if obj.dtype.kind in "iufcb":
            return [(path, obj)]
        if obj.dtype == object:
            for i, x in enumerate(obj.ravel().tolist()[:50]):
                out += leaves(x, f"{path}[{i}]")
        return out
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        for f in dataclasses.fields(obj):
            out += leaves(getattr(obj, f.name), f"{path}.{f.name}" if path else f.name)
        return out
    if isinstance(obj, Mapping):
        for k, x in list(obj.items())[:200]:
            out += leaves(x, f"{path}.{k}" if path else str(k))
        return out
    if isinstance(obj, (list, tuple)):
        for i, x in enumerate(list(obj)[:200]):
            out += leaves(x, f"{path}[{i}]")
        return out
    return out


def _field_ok(path: str, nan_ok: tuple[str, ...]) -> bool:
    if "*" in nan_ok:
        return True
    parts = set(re.split(r"[.\[\]]+", path))
    return any(n in parts or path.startswith(n) for n in nan_ok)


def nonfinite_fields(result: Any, nan_ok: tuple[str, ...]) -> list[str]:
    bad = []
    for path, x in leaves(result):
        arr = np.asarray(x)
        if arr.dtype.kind in "fc" and not np.all(np.isfinite(arr)) and not _field_ok(path, nan_ok):
            bad.append(path or "<result>")
    return bad


def shape_signature(result: Any) -> list[tuple[str, tuple[int, ...]]]:
    return [(p, np.shape(x)) for p, x in leaves(result)]


#: Result fields that measure the machine, not the answer (excluded from equality checks).
VOLATILE = ("runtime_s", "cpu_s", "wall_s", "build_s", "solve_s", "ipopt_s", "sample_steps_per_s")


def same_values(a: Any, b: Any) -> bool:
    la = [(p, x) for p, x in leaves(a) if not _field_ok(p, VOLATILE)]
    lb = [(p, x) for p, x in leaves(b) if not _field_ok(p, VOLATILE)]
    if [p for p, _ in la] != [p for p, _ in lb]:
        return False
    for (_, x), (_, y) in zip(la, lb):
        x, y = np.asarray(x), np.asarray(y)
        if x.shape != y.shape:
            return False
        if x.dtype.kind in "fc" or y.dtype.kind in "fc":
            if not np.allclose(x, y, rtol=1e-9, atol=1e-12, equal_nan=True):
                return False
        elif not np.array_equal(x, y):
            return False
    return True


def names_argument(message: str, arg: str, aliases: tuple[str, ...] = ()) -> bool:
    words = (arg, *aliases)
    return any(re.search(rf"(?<![A-Za-z0-9_]){re.escape(w)}(?![A-Za-z0-9])", message) for w in words)


def success_of(result: Any) -> bool | None:
    s = getattr(result, "success", None)
    if s is None and isinstance(result, Mapping):
        s = result.get("success")
    if s is None:
        return None
    return bool(np.all(s))


@dataclass
class Outcome:
    ok: bool
    kind: str  # "rejected" | "accepted"
    detail: str = ""


def check_outcome(
    case: Case,
    arg: str | None,
    mutation: Mutation | None,
    run: Callable[[], Any],
    reference: Any = None,
    *,
    degenerate: bool = False,
) -> Outcome:
    """Run one call and judge it against the guarantee. Never raises."""
    label = f"{case.name}({arg}={mutation.label})" if mutation else f"{case.name}(valid)"
    STATS["calls"] += 1
    try:
        result = run()
    except Hang as exc:
        STATS["hangs"] += 1
        return Outcome(False, "hang", f"{label}: {exc}")
    except (ValueError, TypeError) as exc:
        msg = str(exc)
        if mutation is None:
            return Outcome(False, "rejected", f"{label}: valid call raised {type(exc).__name__}: {msg}")
        if mutation.category == "same":
            return Outcome(False, "rejected", f"{label}: an equivalent valid value was rejected: "
                           f"{type(exc).__name__}: {msg}")
        aliases = case.aliases.get(arg, ()) if arg else ()
        if mutation.category in ("reshape", "degenerate", "finite", "negative") or mutation.label.startswith("hyp="):
            # a well-typed but extreme value may break a relation with another argument: the
            # consistency error may then name that argument (type and NaN errors may not)
            aliases = (*aliases, *case.valid().keys())
        if arg is not None and not names_argument(msg, arg, aliases):
            return Outcome(False, "rejected", f"{label}: {type(exc).__name__} does not name {arg!r}: {msg}")
        if not isinstance(exc, AdcskitError) and ("\n" in msg.strip() or msg.startswith("could not convert")):
            return Outcome(False, "rejected", f"{label}: raw {type(exc).__name__}: {msg}")
        STATS["rejected"] += 1
        return Outcome(True, "rejected")
    except KeyboardInterrupt:
        raise
    except SystemExit as exc:
        if case.exit_ok and exc.code == 2 and mutation is not None and mutation.category != "same":
            STATS["rejected"] += 1
            return Outcome(True, "rejected")
        return Outcome(False, "foreign", f"{label}: foreign SystemExit({exc.code})")
    except BaseException as exc:  # noqa: BLE001 - the point of the suite (SystemExit included)
        return Outcome(False, "foreign", f"{label}: foreign {type(exc).__name__}: {exc}")
    STATS["accepted"] += 1
    if mutation is None:
        bad = nonfinite_fields(result, case.nan_ok)
        if bad:
            return Outcome(False, "accepted", f"{label}: valid call returned non-finite {bad}")
        return Outcome(True, "accepted")
    if degenerate:
        if success_of(result) is not False:
            return Outcome(False, "accepted", f"{label}: degenerate input answered without success=False")
        return Outcome(True, "accepted")
    cat = mutation.category
    if cat == "strict" and not (mutation.label == "unknown-key" and arg in case.open_keys):
        return Outcome(False, "accepted", f"{label}: accepted; it must be rejected (it silently means "
                       "something else than written)")
    if cat == "negative" and arg in case.positive:
        return Outcome(False, "accepted", f"{label}: negative physical quantity accepted")
    finite_input = cat in ("same", "finite", "reshape", "negative")
    if cat == "nonfinite" and arg in case.nonfinite_ok:
        return Outcome(True, "accepted")  # a documented non-finite value (e.g. an inf bound)
    if cat == "nonfinite":
        if success_of(result) is False:
            return Outcome(True, "accepted")
        return Outcome(False, "accepted", f"{label}: non-finite input accepted")
    if finite_input or cat == "type":
        if success_of(result) is False:
            return Outcome(True, "accepted")
        bad = nonfinite_fields(result, case.nan_ok)
        if bad:
            return Outcome(False, "accepted", f"{label}: finite input gave non-finite output in {bad}")
    if cat in ("same", "finite", "negative") and reference is not None and case.shape_stable:
        if shape_signature(result) != shape_signature(reference):
            return Outcome(False, "accepted", f"{label}: result shape differs from the valid call's")
    if cat == "same" and reference is not None and case.exact and not same_values(result, reference):
        return Outcome(False, "accepted", f"{label}: equivalent input gave a different result")
    return Outcome(True, "accepted")


#: Failure classes of an outcome (issue 23): a foreign exception, a silently accepted bad
#: input, a rejection that is unclear (does not name the argument, a raw message), a hang.
FAILURE_CLASS = {"foreign": "FOREIGN", "accepted": "SILENT", "rejected": "VAGUE", "hang": "HANG"}


def record(outcome: Outcome) -> Outcome:
    """Count a failed outcome under its class in ``STATS`` and return it."""
    if not outcome.ok:
        STATS[FAILURE_CLASS[outcome.kind]] += 1
    return outcome


def signature_flags(case: Case, valid: dict[str, Any]) -> list[str]:
    """Parameters of the case's callable with a ``bool`` default that the valid call leaves out."""
    import inspect

    if not case.signature_flags:
        return []
    try:
        sig = inspect.signature(case.resolve())
    except (TypeError, ValueError):
        return []
    return [n for n, p in sig.parameters.items()
            if n not in valid and not n.startswith("_") and isinstance(p.default, bool)
            and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)]


def signature_defaults(case: Case, valid: dict[str, Any]) -> dict[str, Any]:
    """Float, int and str defaults of the case's callable that the valid call leaves out.

    Opt-in audit (``ADCSKIT_ROBUSTNESS_DEFAULTS=1``): free-text parameters (labels, units,
    descriptions) are left out, since any string is valid for them.
    """
    import inspect

    try:
        sig = inspect.signature(case.resolve())
    except (TypeError, ValueError):
        return {}
    return {n: p.default for n, p in sig.parameters.items()
            if n not in valid and not n.startswith("_") and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)
            and isinstance(p.default, (int, float, str)) and not isinstance(p.default, bool)
            and n not in FREE_TEXT}


#: Parameter names whose values are free text (never a choice among names).
FREE_TEXT = frozenset({"name", "unit", "title", "description", "label", "detail", "where", "statement"})


def plan(case: Case) -> list[tuple[str, Mutation]]:
    """Every (argument, mutation) pair of a case, in a fixed order."""
    valid = case.valid()
    out = []
    for arg, value in valid.items():
        for m in mutations_for(case, arg, value):
            out.append((arg, m))
    for arg in signature_flags(case, valid):
        out += [(arg, m) for m in mutate_flag(True) if m.category == "strict"]
    if os.environ.get("ADCSKIT_ROBUSTNESS_DEFAULTS"):
        for arg, default in signature_defaults(case, valid).items():
            out += [(arg, m) for m in mutations_for(case, arg, default) if m.category != "same"]
    for label, (arg, value, category) in case.extra.items():
        out.append((arg, Mutation(label, value, category)))
    return out


def run_mutation(case: Case, fn: Callable[..., Any], arg: str, mutation: Mutation, reference: Any) -> Outcome:
    kwargs = case.valid()
    kwargs[arg] = mutation.value
    return check_outcome(case, arg, mutation, lambda: call_with_timeout(fn, kwargs), reference)


def run_case(case: Case, *, limit: int | None = None) -> list[str]:
    """Valid call, degenerate calls and every mutation; returns the failure descriptions."""
    failures: list[str] = []
    fn = case.resolve()
    kwargs = case.valid()
    reference = None
    ref_box: dict[str, Any] = {}

    def valid_run() -> Any:
        ref_box["r"] = call_with_timeout(fn, kwargs)
        return ref_box["r"]

    out = record(check_outcome(case, None, None, valid_run))
    if not out.ok:
        return [out.detail]
    reference = ref_box.get("r")
    for label, overrides in case.degenerate.items():
        kw = case.valid()
        kw.update(overrides)
        deg = Mutation(label, None, "degenerate")
        o = record(check_outcome(case, next(iter(overrides)), deg, lambda kw=kw: call_with_timeout(fn, kw),
                                 reference, degenerate=True))
        if not o.ok:
            failures.append(o.detail)
    pairs = plan(case)
    if limit is not None:
        pairs = pairs[:: max(1, len(pairs) // limit)][:limit]
    for arg, m in pairs:
        o = record(run_mutation(case, fn, arg, m, reference))
        if not o.ok:
            failures.append(o.detail)
    return failures
