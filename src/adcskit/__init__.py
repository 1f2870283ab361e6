"""adcskit — spacecraft attitude determination and control design toolkit.

Subpackages, from the top layer down. A package imports only from the layers below its own;
packages on one line are independent siblings. ``pyproject.toml`` states these layers as
import-linter contracts and ``tests/test_layers.py`` checks them (``lint-imports``):

* :mod:`adcskit.cli` — the ``adcskit`` command.
* :mod:`adcskit.report` — HTML report from ``result.json`` files.
* :mod:`adcskit.studies` — the study framework (registry, runner, verdict) and one module per
  reproduced paper study.
* :mod:`adcskit.simulation` — the closed loop (plant, sensors, estimation, guidance, control,
  allocation, thrusters), batched over Monte-Carlo samples.
* :mod:`adcskit.control` (on-off thruster loop, S4's robust tuning),
  :mod:`adcskit.thrusters` (geometry, allocation, layout design, S3's reference data),
  :mod:`adcskit.optimal_control` (Gauss/Radau pseudospectral optimal control),
  :mod:`adcskit.determination` (Wahba solvers, robust interval Wahba),
  :mod:`adcskit.estimation` (Kalman filtering, MEKF, model identification).
* :mod:`adcskit.uncertainty` (generic: sampling, executors, campaigns, statistics),
  :mod:`adcskit.sensors` (sun sensor, magnetometer, rate gyro),
  :mod:`adcskit.dynamics` (rigid body, gravity gradient, LVLH model, Hill/CW),
  :mod:`adcskit.environment` (orbits, sun direction, geomagnetic field).
* :mod:`adcskit.attitude` — quaternions (scalar last), DCMs, MRPs, Euler sequences.
* :mod:`adcskit.config` — TOML study configurations.
* utilities: ``_results`` (``to_jsonable``, the ``Result`` base), ``_validation``,
  ``_targets``, ``_progress``, :mod:`adcskit.constants`.
* :mod:`adcskit.errors` — the error hierarchy.

Conventions (see ``docs/conventions.md``): SI units and radians inside, quaternions
``[q1, q2, q3, q4]`` with the scalar last and ``A(q)`` mapping reference-frame to body-frame
components, batch-first arrays, every stochastic function takes ``rng``.
"""

from adcskit.errors import (
    AdcskitError,
    AdcskitWarning,
    ConfigError,
    InputError,
    InputTypeError,
    UncontrollableWarning,
)

__version__ = "0.1.0"

__all__ = ["AdcskitError", "AdcskitWarning", "ConfigError", "InputError", "InputTypeError", "UncontrollableWarning",
           "__version__"]
