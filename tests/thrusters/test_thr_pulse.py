"""Pulse model (S3 eq. 6-11)."""

from __future__ import annotations

import numpy as np
import pytest

from adcskit.errors import InputError
from adcskit.thrusters import (
    fuel_mass,
    manoeuvre_fuel,
    min_impulse_bit,
    min_reachable_error,
    pulse_width,
    realisable_pulses,
)


def test_pulse_width_eq6():
    # S3 eq. 6: t_p = F t_s / F_max; 5 N of 10 N over 0.2 s -> 0.1 s
    np.testing.assert_allclose(pulse_width([0.0, 5.0, 10.0], f_max=10.0, t_s=0.2), [0, 0.1, 0.2])
    with pytest.raises(InputError, match="one way"):
        pulse_width([-1.0], f_max=10.0)


def test_min_impulse_bit_and_error_with_lever_arm():
    # derived in adcskit.thrusters.pulse: H_min = Delta F_max t_min; e_min = H_min / (t_s K)
    # S3 data (Table 5, 6, §6): 10 N, 3 ms, t_s 0.2 s, K 600 N m/rad -> 2.5e-4 rad per metre
    assert min_impulse_bit(1.5, f_max=10.0, t_min=3e-3) == pytest.approx(0.045)
    assert min_reachable_error(1.0) == pytest.approx(2.5e-4, rel=1e-12)
    # the largest lever arm in the 2x2x2 m box is sqrt(3) m: e_min <= 4.33e-4 rad, below the
    # 8.2e-4..8.4e-4 rad of S3 Table 8 (documented in docs/studies/thruster-layout.md)
    assert min_reachable_error(np.sqrt(3.0)) == pytest.approx(4.330e-4, rel=1e-3)


def test_fuel_and_min_on_time():
    # S3 eq. 7: m = mdot t_p; 3.5 g/s for 0.1 s = 0.35 g
    assert fuel_mass(0.1, mdot=3.5e-3) == pytest.approx(3.5e-4)
    np.testing.assert_allclose(realisable_pulses([0.001, 0.002, 0.01], t_min=3e-3), [0, 0, 0.01])
    np.testing.assert_allclose(
        realisable_pulses([0.001, 0.002, 0.01], t_min=3e-3, mode="round"), [0, 0.003, 0.01]
    )


def test_manoeuvre_fuel_sums_pulses():
    # two samples, two thrusters: forces 5 and 10 N then 0.1 and 0 N with t_s = 0.2 s:
    # t_p = 0.1, 0.2, 0.002, 0 s -> 0.302 s x 3.5 g/s = 1.057 g (S3 eq. 6-7); with t_min = 3 ms
    # the 2 ms pulse is dropped -> 0.3 s -> 1.05 g
    F = [[5.0, 10.0], [0.1, 0.0]]
    assert manoeuvre_fuel(F) == pytest.approx(0.302 * 3.5e-3)
    assert manoeuvre_fuel(F, t_min=3e-3) == pytest.approx(0.3 * 3.5e-3)
