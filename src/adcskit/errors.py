"""Exception types of adcskit.

Every error raised on bad input is a subclass of the built-in :class:`ValueError` or
:class:`TypeError`, so ``except ValueError`` keeps working for callers that do not know
adcskit, and its message names the parameter, the offending value and what is allowed
(house style rule 6 of ``docs/architecture.md``).
"""

from __future__ import annotations

__all__ = [
    "AdcskitError", "InputError", "InputTypeError", "ConfigError", "SolverError", "AdcskitWarning",
    "UncontrollableWarning",
]


class AdcskitError(Exception):
    """Base class of every exception adcskit raises on purpose.

    Examples
    --------
    >>> from adcskit.attitude import quat_to_dcm
    >>> try:
    ...     quat_to_dcm([0.0, 0.0, 0.0, 0.0])
    ... except AdcskitError as exc:
    ...     print(type(exc).__name__)
    InputError
    """


class InputError(AdcskitError, ValueError):
    """A parameter has the right type but a value outside what is allowed.

    Examples
    --------
    >>> isinstance(InputError("x must be > 0; got -1"), ValueError)
    True
    """


class InputTypeError(AdcskitError, TypeError):
    """A parameter has a type that cannot be converted to what is expected.

    Examples
    --------
    >>> isinstance(InputTypeError("x must be a number; got 'a'"), TypeError)
    True
    """


class ConfigError(InputError):
    """A configuration file or mapping has an unknown, missing or ill-typed key.

    Examples
    --------
    >>> issubclass(ConfigError, InputError)
    True
    """


class SolverError(AdcskitError, RuntimeError):
    """A numerical solver could not be run at all (not: ran and did not converge).

    A solver that runs and fails to converge returns a result with ``success=False``;
    this exception is for conditions such as a missing optional dependency.

    Examples
    --------
    >>> issubclass(SolverError, RuntimeError)
    True
    """


class AdcskitWarning(UserWarning):
    """Base class of every warning adcskit issues on purpose (a result that runs but that the
    caller should not trust without reading why).

    Examples
    --------
    >>> issubclass(AdcskitWarning, UserWarning)
    True
    """


class UncontrollableWarning(AdcskitWarning):
    """A thruster layout (after failures and dispersions) cannot produce torque in every
    direction, so the closed loop cannot reach or hold every attitude.

    Issued by :func:`adcskit.simulation.simulate` before it flies such a scenario; the
    message names the unreachable torque direction (the positive-span test of
    :func:`adcskit.thrusters.check_controllability`).

    Examples
    --------
    >>> issubclass(UncontrollableWarning, AdcskitWarning)
    True
    """
