"""Property-based robustness suite over every public callable (issue 12).

Every public name of every subpackage's ``__all__`` has an entry in ``cases.py`` (a valid call)
or in ``cases.EXEMPT`` (with a reason). For each entry the suite makes the valid call, the
degenerate calls the entry declares, every generated mutation of every argument (see
``harness.py`` for the mutations and the rules an outcome must satisfy) and, through
hypothesis, random extreme values at random positions. Counts are printed at the end of the
run (``robustness: N calls, R clean rejections, A accepted``).

Run: ``python -m pytest tests/robustness -q`` (default, under a minute) or with ``-m slow`` for
the exhaustive variant (all mutations of the expensive entries and more hypothesis examples).
"""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest
from cases import CASES, EXEMPT
from harness import Mutation, call_with_timeout, check_outcome, record, run_case
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st


def test_every_public_name_has_an_entry():
    """Every callable of every ``__all__`` and every public method of a public class has a case
    or an ``EXEMPT`` reason (the gap is listed by ``python tests/robustness/public_gap.py``)."""
    import public_gap

    missing = public_gap.uncovered()
    assert not missing, (
        "public names without a robustness entry (add one to tests/robustness/cases.py, "
        f"or an EXEMPT reason): {missing}"
    )
    names = public_gap.public_callables()
    known = set(names) | {m for n, obj in names.items() if inspect.isclass(obj)
                          for m in public_gap.public_methods(n, obj, {})}
    stale = sorted(n for n in EXEMPT if n not in known)
    assert not stale, f"EXEMPT names that are not public any more: {stale}"
    unknown = sorted(n for n in CASES if n not in known and n.rsplit(".", 1)[0] not in names)
    assert not unknown, f"cases for names that are not public: {unknown}"


def test_valid_calls_write_only_under_the_scratch_root():
    """Files and directories of valid calls live under ``cases.scratch_path``'s root, which the
    session removes at its end (earlier runs left ~1000 ``/tmp/adcskit-rob-*`` entries behind)."""
    import os
    import tempfile

    import cases

    tmp = os.path.realpath(tempfile.gettempdir())
    outside = []
    for name, c in CASES.items():
        for arg, v in c.valid().items():
            if isinstance(v, (str, os.PathLike)) and os.path.exists(v):
                real = os.path.realpath(v)
                if real.startswith(tmp + os.sep) and not real.startswith(os.path.realpath(cases._SCRATCH[0]) + os.sep):
                    outside.append(f"{name}({arg}={v!r})")
    assert cases._SCRATCH, "no valid call used the scratch root"
    assert not outside, f"valid calls that create temporary files outside cases.scratch_path: {outside}"


FAST = sorted(n for n, c in CASES.items() if not c.slow)
SLOW = sorted(n for n, c in CASES.items() if c.slow)


def _judge(name, failures):
    if failures and CASES[name].known_open:
        pytest.xfail(f"{CASES[name].known_open}:\n" + "\n".join(failures))
    assert not failures, "\n".join(failures)


@pytest.mark.parametrize("name", FAST)
def test_mutations(name):
    _judge(name, run_case(CASES[name]))


@pytest.mark.parametrize("name", SLOW)
def test_mutations_expensive_entries_sampled(name):
    """Valid call, degenerate calls and a spread sample of the mutations of a slow entry."""
    _judge(name, run_case(CASES[name], limit=12))


@pytest.mark.slow
@pytest.mark.parametrize("name", SLOW)
def test_mutations_expensive_entries_exhaustive(name):
    _judge(name, run_case(CASES[name]))


# --- hypothesis: random extreme values at random positions of random numeric arguments -------

EXTREMES = st.one_of(
    st.sampled_from([math.nan, math.inf, -math.inf, 1e300, -1e300, 1e-300, -1e-300, 0.0, 5e-324]),
    st.floats(allow_nan=False, allow_infinity=False, min_value=-1e308, max_value=1e308),
)


def _numeric_args(case):
    valid = case.valid()
    out = []
    for arg, v in valid.items():
        if case.kinds.get(arg, "") in ("skip", "object", "times", "path", "choice", "callable", "mapping"):
            continue
        if isinstance(v, (bool, np.bool_)) or isinstance(v, (str, dict)) or callable(v) or v is None:
            continue
        try:
            a = np.asarray(v, dtype=float)
        except (TypeError, ValueError):
            continue
        if a.size and isinstance(v, (float, list, tuple, np.ndarray)) and not isinstance(v, (int, np.integer)):
            out.append(arg)
    return out


# a known open failure (``known_open``) is shown by test_mutations as an expected failure
HYP_CASES = sorted(n for n in FAST if _numeric_args(CASES[n]) and not CASES[n].known_open)


_REFERENCE: dict[str, object] = {}


def _hyp(name, data):
    case = CASES[name]
    fn = case.resolve()
    if name not in _REFERENCE:
        _REFERENCE[name] = call_with_timeout(fn, case.valid())
    ref = _REFERENCE[name]
    arg = data.draw(st.sampled_from(_numeric_args(case)), label="arg")
    kwargs = case.valid()
    a = np.array(kwargs[arg], dtype=float)
    x = data.draw(EXTREMES, label="value")
    if a.ndim:
        idx = data.draw(st.integers(0, a.size - 1), label="index")
        a.flat[idx] = x
        value = a
    else:
        value = x
    # a negative within a rounding tolerance (> -1e-6) may legitimately be read as zero
    cat = "nonfinite" if not math.isfinite(x) else ("negative" if x < -1e-6 else "finite")
    kwargs[arg] = value
    out = record(check_outcome(case, arg, Mutation(f"hyp={x!r}", value, cat), lambda: call_with_timeout(fn, kwargs), ref))
    assert out.ok, out.detail


@pytest.mark.parametrize("name", HYP_CASES)
@settings(max_examples=6, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_random_extremes(name, data):
    _hyp(name, data)


@pytest.mark.slow
@pytest.mark.parametrize("name", HYP_CASES)
@settings(max_examples=100, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_random_extremes_exhaustive(name, data):
    _hyp(name, data)
