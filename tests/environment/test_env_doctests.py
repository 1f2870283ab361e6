"""The docstring examples of adcskit.environment and adcskit.sensors run and hold."""

from __future__ import annotations

import doctest
import importlib

import pytest

MODULES = [
    "adcskit.environment.time",
    "adcskit.environment.sun",
    "adcskit.environment.orbits",
    "adcskit.environment.magnetic",
    "adcskit.sensors.models",
    "adcskit.sensors.intervals",
]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS)
    assert result.failed == 0
    assert result.attempted > 0


def test_public_names_exported():
    import adcskit.environment as env
    import adcskit.sensors as sen

    for mod in (env, sen):
        for n in mod.__all__:
            assert hasattr(mod, n), n
    for n in ("circular_orbit", "sun_direction", "magnetic_field"):
        assert n in env.__all__
    for n in ("SunSensor", "Magnetometer", "midpoint_radius", "interval_from_bounds"):
        assert n in sen.__all__
