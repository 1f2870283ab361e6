"""Counter-free random draws inside the batched kernels: one SplitMix64 state per sample.

Both closed-loop kernels (thrusters: :mod:`adcskit.simulation._kernels`; wheels:
:mod:`adcskit.simulation._wheel_kernels`) draw their sensor noise from these device helpers,
so a sample's noise depends only on its own 64-bit seed (reproducible under any thread or
process split, and on a GPU thread). SplitMix64: Steele, Lea & Flood 2014, "Fast splittable
pseudorandom number generators" (constants of Vigna's reference implementation); normals by
Box-Muller.
"""

from __future__ import annotations

import math

import numpy as np

from adcskit._targets import device

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)
_S30 = np.uint64(30)
_S27 = np.uint64(27)
_S31 = np.uint64(31)
_S11 = np.uint64(11)
_TWO_M53 = 1.0 / 9007199254740992.0
_TWO_PI = 2.0 * math.pi


@device
def uniform(s):
    """SplitMix64 step: returns (new state, uniform in (0, 1))."""
    s = s + _GOLDEN
    z = s
    z = (z ^ (z >> _S30)) * _MIX1
    z = (z ^ (z >> _S27)) * _MIX2
    z = z ^ (z >> _S31)
    return s, (float(z >> _S11) + 0.5) * _TWO_M53


@device
def normal(s):
    """(new state, standard normal) by Box-Muller (one of the pair is used)."""
    s, u1 = uniform(s)
    s, u2 = uniform(s)
    return s, math.sqrt(-2.0 * math.log(u1)) * math.cos(_TWO_PI * u2)


@device
def normal2(s):
    """(new state, two independent standard normals) by Box-Muller (both of the pair)."""
    s, u1 = uniform(s)
    s, u2 = uniform(s)
    rr = math.sqrt(-2.0 * math.log(u1))
    return s, rr * math.cos(_TWO_PI * u2), rr * math.sin(_TWO_PI * u2)
