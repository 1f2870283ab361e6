"""Device helpers of S4's thruster actuator: Schmitt trigger, pure delay, two-lag thruster.

One source for the actuator model that both per-sample kernels use: the on-off loop
(:mod:`adcskit.control._onoff_kernels`) and the closed-loop simulator
(:mod:`adcskit.simulation._kernels`). Each is declared with :func:`adcskit._targets.device`:
numba compiles it into the calling kernel on the CPU (``njit``) or the GPU (``cuda.jit``);
called from plain Python it is the plain function (the reference path).

The thruster is two cascaded first-order lags with time constant ``tau``, discretised exactly
for a command held over one step (zero-order hold): ``x1+ = A11 x1 + B1 u``,
``x2+ = A21 x1 + A22 x2 + B2 u``; the delivered thrust fraction's integral over the step is
``v = V1 x1 + V2 x2 + VU u`` (s). The callers build the coefficients
(:func:`adcskit.control.onoff`'s ``_coefficients``, :func:`adcskit.simulation.core`'s
``_lag_coefficients``).

References
----------
S4 Fig. 1 (PID + Schmitt trigger + thruster lag and delay), Table 3 (tau = 0.01 s,
delay = 0.02 s).
"""

from __future__ import annotations

from adcskit._targets import device

__all__ = ["schmitt", "delay_mix", "lag_step"]


@device
def schmitt(s, u, u_on, u_off):
    """Three-level Schmitt trigger with memory (S4 Fig. 1): next output in {-1, 0, +1}.

    Examples
    --------
    >>> schmitt(0.0, 0.2, 0.15, 0.075), schmitt(1.0, 0.1, 0.15, 0.075), schmitt(1.0, 0.05, 0.15, 0.075)
    (1.0, 1.0, 0.0)
    """
    if s == 0.0:
        if u >= u_on:
            return 1.0
        if u <= -u_on:
            return -1.0
        return 0.0
    if s == 1.0:
        if u <= -u_on:
            return -1.0
        if u < u_off:
            return 0.0
        return 1.0
    if u >= u_on:
        return 1.0
    if u > -u_off:
        return 0.0
    return -1.0


@device
def delay_mix(ua, ub, frac):
    """Command after a pure delay of ``nd + frac`` steps: linear interpolation between the
    samples ``nd`` (``ua``) and ``nd + 1`` (``ub``) steps back.

    Examples
    --------
    >>> delay_mix(1.0, 0.0, 0.25)
    0.75
    """
    return (1.0 - frac) * ua + frac * ub


@device
def lag_step(x1, x2, u, a11, b1, a21, a22, b2, v1, v2, vu):
    """One exact step of the two-lag thruster: returns ``(v, x1+, x2+)`` (``v`` in s).

    Examples
    --------
    >>> lag_step(0.0, 0.0, 1.0, 0.5, 0.5, 0.2, 0.5, 0.3, 0.1, 0.2, 0.05)
    (0.05, 0.5, 0.3)
    """
    v = v1 * x1 + v2 * x2 + vu * u
    x2n = a21 * x1 + a22 * x2 + b2 * u
    x1n = a11 * x1 + b1 * u
    return v, x1n, x2n
