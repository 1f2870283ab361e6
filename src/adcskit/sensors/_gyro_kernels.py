"""Per-sample rate-gyro noise step (Farrenkopf model), for compiled batch kernels.

Private: the validated public API is :class:`adcskit.sensors.RateGyro`. Like the MEKF
kernels (:mod:`adcskit.estimation._mekf_kernels`, which re-exports it), the function is plain
Python registered with ``numba.extending.register_jitable``: no allocation, no exceptions,
``math`` only, so it compiles with ``numba.njit`` and as a ``numba.cuda.jit(device=True)``
function from the same source. Random draws are the caller's (pre-drawn standard normals),
so CPU and GPU paths consume identical streams.

``gyro_step(omega_true, bias, sigma_v, sigma_u, dt, n_v, n_u, out) -> None``
    One reading over ``[t, t + dt)`` (``dt > 0`` s): with standard normal ``n_v``, ``n_u``
    (3,), ``b⁺ = b + σu √dt n_u`` and
    ``out = omega_true + (b + b⁺)/2 + sqrt(σv²/dt + σu² dt/12) n_v``; ``bias`` (3,) is
    updated in place to ``b⁺``. ``σv`` [rad/s^0.5] angle random walk, ``σu`` [rad/s^1.5]
    bias random walk. This is the exact discretisation of the continuous model
    ``ω̃ = ω + b + η_v``, ``ḃ = η_u`` for the mean rate over the interval (Crassidis &
    Junkins 2012 §7.2 eq. 7.35 form; Markley & Crassidis 2014 §6.2.1).

References
----------
.. [1] Crassidis, J. L. and Junkins, J. L., *Optimal Estimation of Dynamic Systems*, 2nd ed.,
   CRC, 2012, §7.2.
.. [2] Farrenkopf, R. L., "Analytic steady-state accuracy solutions for two common spacecraft
   attitude estimators", JGC 1(4), 1978.
"""

from __future__ import annotations

import math

from numba import njit
from numba.extending import register_jitable


@register_jitable
def gyro_step(omega_true, bias, sigma_v, sigma_u, dt, n_v, n_u, out):
    """One discrete Farrenkopf gyro reading (see the module docstring); updates ``bias``."""
    sb = sigma_u * math.sqrt(dt)
    sn = math.sqrt(sigma_v * sigma_v / dt + sigma_u * sigma_u * dt / 12.0)
    for i in range(3):
        b_new = bias[i] + sb * n_u[i]
        out[i] = omega_true[i] + 0.5 * (bias[i] + b_new) + sn * n_v[i]
        bias[i] = b_new


gyro_step_jit = njit(cache=True, nogil=True)(gyro_step)
