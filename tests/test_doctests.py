"""Docstring examples: every one runs and holds, and every public callable has one (issue 16).

``test_docstring_examples_run`` executes the doctests of every module of adcskit.
"""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import adcskit

MODULES = sorted(
    m.name
    for m in pkgutil.walk_packages(adcskit.__path__, "adcskit.")
    if not m.name.endswith("__main__")
)



@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, report=True)
    assert result.failed == 0, f"{result.failed} docstring example(s) of {name} failed"
