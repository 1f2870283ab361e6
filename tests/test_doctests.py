"""Docstring examples: every one runs and holds, and every public callable has one (issue 16).

``test_docstring_examples_run`` executes the doctests of every module of adcskit.
``test_every_public_callable_has_an_example`` checks that each public function or class of
each subpackage's ``__all__`` shows an example (a ``>>>`` line) in its docstring; the API
reference site renders them.
"""

from __future__ import annotations

import doctest
import importlib
import inspect
import pkgutil

import pytest

import adcskit

MODULES = sorted(
    m.name
    for m in pkgutil.walk_packages(adcskit.__path__, "adcskit.")
    if not m.name.endswith("__main__")
)

SUBPACKAGES = [
    "adcskit.attitude",
    "adcskit.dynamics",
    "adcskit.environment",
    "adcskit.sensors",
    "adcskit.determination",
    "adcskit.estimation",
    "adcskit.optimal_control",
    "adcskit.thrusters",
    "adcskit.control",
    "adcskit.uncertainty",
    "adcskit.simulation",
    "adcskit.studies",
    "adcskit.report",
    "adcskit.config",
    "adcskit.errors",
]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, report=True)
    assert result.failed == 0, f"{result.failed} docstring example(s) of {name} failed"


def _public_callables():
    for pkg in SUBPACKAGES:
        if importlib.util.find_spec(pkg) is None:
            continue
        module = importlib.import_module(pkg)
        for n in module.__all__:
            obj = getattr(module, n)
            if callable(obj) or inspect.isclass(obj):
                yield f"{pkg}.{n}", obj


def test_every_public_callable_has_an_example():
    missing = sorted(name for name, obj in _public_callables() if ">>>" not in (inspect.getdoc(obj) or ""))
    assert not missing, f"{len(missing)} public callables without a docstring example: {missing}"
