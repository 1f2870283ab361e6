"""The S4 actuator device helpers (adcskit.control._actuator), shared by the on-off kernel and
the closed-loop simulator: against the public Schmitt trigger and the closed-form step
response of two cascaded first-order lags."""

import math

import numba
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from adcskit.control import schmitt_trigger
from adcskit.control._actuator import delay_mix, lag_step, schmitt
from adcskit.simulation.core import _lag_coefficients


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(-0.5, 0.5), min_size=1, max_size=40), st.floats(0.01, 0.3),
       st.floats(0.1, 0.9))
def test_schmitt_helper_equals_public_trigger(u, u_on, ratio):
    # S4 Fig. 1's three-level trigger with memory: the kernels' scalar helper, the public
    # adcskit.control.schmitt_trigger (which now runs that helper, issue 20 item 4) and the
    # public trigger's former own loop (main bc6d017, verbatim, an independent statement of the
    # same rule); comparisons only, so exact equality
    u_off = ratio * u_on
    s = 0.0
    mine = []
    for x in u:
        s = schmitt(s, x, u_on, u_off)
        mine.append(s)
    former, s = [], 0.0
    for x in u:
        if s == 0.0:
            s = 1.0 if x >= u_on else (-1.0 if x <= -u_on else 0.0)
        elif s == 1.0:
            s = -1.0 if x <= -u_on else (0.0 if x < u_off else 1.0)
        else:
            s = 1.0 if x >= u_on else (0.0 if x > -u_off else -1.0)
        former.append(s)
    np.testing.assert_array_equal(mine, former)
    np.testing.assert_array_equal(mine, schmitt_trigger(u, u_on=u_on, u_off=u_off))


def test_lag_step_matches_closed_form_step_response():
    # two identical first-order lags (S4 Table 3: tau = 0.01 s) driven by a unit step from rest:
    # x2(t) = 1 - (1 + t/tau) exp(-t/tau), and its integral
    # v(0, t) = t - 2 tau + (2 tau + t) exp(-t/tau) (Laplace tables; our own derivation).
    # The ZOH coefficients are exact (scipy expm), so only rounding separates them: 1e-12.
    tau, dt = 0.01, 0.002
    c = _lag_coefficients(tau, dt)
    x1 = x2 = 0.0
    vsum = 0.0
    for k in range(1, 41):
        v, x1, x2 = lag_step(x1, x2, 1.0, *c)
        vsum += v
        t = k * dt
        assert math.isclose(x2, 1.0 - (1.0 + t / tau) * math.exp(-t / tau), rel_tol=0, abs_tol=1e-12)
        assert math.isclose(vsum, t - 2 * tau + (2 * tau + t) * math.exp(-t / tau), rel_tol=0, abs_tol=1e-12)


def test_helpers_compute_the_same_bits_compiled_and_in_python():
    # one source, two targets: the helpers compiled into an njit caller give the plain-Python
    # results bit for bit (no fused multiply-add on the CPU)
    @numba.njit(cache=False)
    def compiled(x1, x2, u, ua, ub, frac, c):
        v, y1, y2 = lag_step(x1, x2, u, c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7])
        return v, y1, y2, delay_mix(ua, ub, frac), schmitt(1.0, u, 0.15, 0.075)

    c = _lag_coefficients(0.01, 0.02)
    rng = np.random.default_rng(3)
    for _ in range(20):
        x1, x2, u, ua, ub, frac = rng.uniform(-1.0, 1.0, 6)
        py = lag_step(x1, x2, u, *c) + (delay_mix(ua, ub, frac), schmitt(1.0, u, 0.15, 0.075))
        assert compiled(x1, x2, u, ua, ub, frac, c) == py
