"""adcskit — spacecraft attitude determination and control design toolkit.

Subpackages (dependencies flow downward in this list's reverse order; nothing imports
from a package above it):

* :mod:`adcskit.attitude` — quaternions (scalar last), DCMs, MRPs, Euler sequences.
* :mod:`adcskit.dynamics` — rigid body, gravity gradient, linearised LVLH model, Hill/CW.
* :mod:`adcskit.environment` — orbits, sun direction, geomagnetic field.
* :mod:`adcskit.sensors` — sun sensor and magnetometer models.
* :mod:`adcskit.determination` — Wahba solvers, robust interval Wahba.
* :mod:`adcskit.estimation` — Kalman filtering and model identification.
* :mod:`adcskit.optimal_control` — Gauss/Radau pseudospectral optimal control.
* :mod:`adcskit.thrusters` — thruster geometry, allocation, layout design.
* :mod:`adcskit.control` — on-off thruster attitude loop, batch simulation.
* :mod:`adcskit.uncertainty` — sampling, executors, campaigns, robust objectives.
* :mod:`adcskit.studies` — one module per reproduced paper study.
* :mod:`adcskit.report` — HTML report from ``result.json`` files.

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
