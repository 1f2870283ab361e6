"""Pulse-width model, minimum impulse bit, minimum reachable error and fuel (S3 eq. 6-11).

An on-off thruster delivers a constant force ``F_max`` for an on-time ``t_p`` inside each
control sample ``t_s``; a requested mean force ``F`` is realised by pulse-width modulation,

    t_p = F t_s / F_max                                   (S3 eq. 6)
    m_fuel = mdot t_p                                     (S3 eq. 7)

**Minimum impulse bit — where the lever arm goes (S3 eq. 8-10).** S3 prints
``MTIB = F_max Δ t_min`` and ``e_min = F_max Δ t_min / (t_s K)``, with ``Δ = ||r x d||`` the
lever arm of eq. 8. Read as ``Δt_min`` (a time) the product ``F_max Δt_min`` is a *force*
impulse (N s), and dividing it by ``t_s K`` (s · N m/rad) would not give radians. The
shortest pulse ``t_min`` of a thruster with lever arm ``Δ`` gives the angular-momentum
increment

    ΔH_min = ∫ ||r x F|| dt = Δ F_max t_min                [N m s]

which is the minimum *torque* impulse bit. A controller with proportional gain
``K = ω_n² J`` (S3 eq. 11, N m/rad) commands over one sample a torque impulse ``K e t_s`` for
an attitude error ``e``; errors whose commanded impulse is below ``ΔH_min`` cannot be acted
on, so the smallest reachable error is

    e_min = Δ F_max t_min / (t_s K)                        [rad]

— the lever arm belongs in the impulse bit, and only with it is ``e_min`` an angle. With
S3's numbers (F_max = 10 N, t_min = 3 ms, t_s = 0.2 s, K = 600 N m/rad) this is
``2.5e-4 Δ`` rad, at most ``4.3e-4`` rad for ``Δ <= sqrt(3)`` m in the 2x2x2 m box.

References
----------
S3 eq. 6-11; Sidi M., "Spacecraft Dynamics and Control", CUP 1997, §7 (S3 ref. [18]).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from adcskit._validation import as_array, check_positive, check_positive_array
from adcskit.errors import InputError

__all__ = [
    "pulse_width",
    "min_impulse_bit",
    "min_reachable_error",
    "fuel_mass",
    "realisable_pulses",
    "manoeuvre_fuel",
]


def pulse_width(force: Any, *, f_max: Any = 10.0, t_s: float = 0.2) -> np.ndarray:
    """On-time per sample that realises a mean force (S3 eq. 6).

    Parameters
    ----------
    force : array_like, N
        Requested forces, any shape ``(..., n)``; must lie in ``[0, f_max]``.
    f_max : float or array_like (n,), N
    t_s : float, s
        Control sample time (S3 Table 6: 0.2 s).

    Returns
    -------
    numpy.ndarray, s
        ``t_p = F t_s / F_max``, same shape as ``force``.

    Examples
    --------
    >>> from adcskit.thrusters import pulse_width
    >>> pulse_width([0.0, 2.5, 10.0])                     # s: F t_s / F_max with 0.2 s, 10 N
    array([0.  , 0.05, 0.2 ])
    """
    return _pulse_width("force", force, f_max, t_s)


def _pulse_width(name: str, force: Any, f_max: Any, t_s: Any) -> np.ndarray:
    F = as_array(name, force)
    fmax = check_positive_array("f_max", f_max, unit="N", min_value=1e-100, broadcast_to=F.shape[-1:])
    t_s = check_positive("t_s", t_s, unit="s", min_value=1e-100)
    tol = 1e-9 * np.max(fmax)
    if np.any(F < -tol) or np.any(F > fmax + tol):
        raise InputError(
            f"{name} must lie in [0, f_max] N (thrusters push one way); got range "
            f"[{F.min():g}, {F.max():g}] with f_max {np.max(fmax):g}"
        )
    return np.clip(F, 0.0, fmax) * t_s / fmax


def realisable_pulses(t_p: Any, *, t_min: Any = 3e-3, mode: str = "drop") -> np.ndarray:
    """Apply the minimum on-time to pulse widths.

    ``mode="drop"``: pulses shorter than ``t_min`` are not fired (dead zone of S3 §2-2);
    ``mode="round"``: they are rounded to 0 or ``t_min``, whichever is nearer.

    Examples
    --------
    >>> from adcskit.thrusters import realisable_pulses
    >>> t_p = [0.001, 0.002, 0.05]                        # s
    >>> realisable_pulses(t_p)                            # below 3 ms: not fired
    array([0.  , 0.  , 0.05])
    >>> realisable_pulses(t_p, mode="round")              # nearer of 0 and t_min
    array([0.   , 0.003, 0.05 ])
    """
    tp = check_positive_array("t_p", t_p, allow_zero=True, unit="s")
    tm = check_positive_array("t_min", t_min, allow_zero=True, unit="s",
                              broadcast_to=tp.shape[-1:] if tp.ndim else ())
    short = tp < tm
    if mode == "drop":
        return np.where(short, 0.0, tp)
    if mode == "round":
        return np.where(short, np.where(tp >= tm / 2, tm, 0.0), tp)
    raise InputError(f"mode must be one of 'drop', 'round'; got {mode!r}")


def min_impulse_bit(lever_arm: Any, *, f_max: Any = 10.0, t_min: Any = 3e-3) -> np.ndarray:
    """Minimum torque impulse bit ``Δ F_max t_min`` (N m s); see the module docstring.

    Parameters
    ----------
    lever_arm : array_like, m
        ``Δ = ||r x d||`` per thruster (S3 eq. 8; :meth:`ThrusterSet.lever_arms`).
    f_max : float or array_like, N
    t_min : float or array_like, s
        Minimum on-time (S3: 3 ms).

    References
    ----------
    S3 eq. 9 with the lever arm of eq. 8 (derived in the module docstring).

    Examples
    --------
    >>> from adcskit.thrusters import min_impulse_bit
    >>> min_impulse_bit([1.0, 0.5]).round(9)              # N m s: lever arm x 10 N x 3 ms
    array([0.03 , 0.015])
    """
    d = as_array("lever_arm", lever_arm)
    if np.any(d < 0):
        raise InputError(f"lever_arm must be >= 0 m; got minimum {d.min():g}")
    fm = check_positive_array("f_max", f_max, unit="N", min_value=1e-100, broadcast_to=d.shape[-1:] if d.ndim else ())
    tm = check_positive_array("t_min", t_min, allow_zero=True, unit="s", broadcast_to=d.shape[-1:] if d.ndim else ())
    return d * fm * tm


def min_reachable_error(
    lever_arm: Any, *, f_max: Any = 10.0, t_min: Any = 3e-3, t_s: float = 0.2, gain: float = 600.0
) -> np.ndarray:
    """Smallest attitude error the thruster can correct, ``Δ F_max t_min / (t_s K)`` (rad).

    Parameters
    ----------
    lever_arm : array_like, m
    f_max : float or array_like, N
    t_min : float or array_like, s
    t_s : float, s
        Control sample time (S3 Table 6: 0.2 s).
    gain : float, N m/rad
        ``K = ω_n² J`` (S3 eq. 11; Table 6: 600).

    References
    ----------
    S3 eq. 10 and 16 with the lever arm in the impulse bit (module docstring).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import min_reachable_error
    >>> e = min_reachable_error([1.0, 0.5])               # rad: 0.03 N m s / (0.2 s x 600 N m/rad)
    >>> e.round(9), np.degrees(e).round(6)
    (array([0.00025 , 0.000125]), array([0.014324, 0.007162]))
    """
    t_s = check_positive("t_s", t_s, unit="s", min_value=1e-100)
    gain = check_positive("gain", gain, unit="N m/rad", min_value=1e-100)
    return min_impulse_bit(lever_arm, f_max=f_max, t_min=t_min) / (t_s * gain)


def fuel_mass(t_p: Any, *, mdot: Any = 3.5e-3) -> np.ndarray:
    """Propellant used by pulses of width ``t_p`` (kg), S3 eq. 7; sum it for a manoeuvre.

    Examples
    --------
    >>> from adcskit.thrusters import fuel_mass
    >>> fuel_mass([0.1, 0.2])                             # kg, 3.5 g/s x on-time
    array([0.00035, 0.0007 ])
    >>> round(float(fuel_mass([[0.2, 0.0], [0.1, 0.1]]).sum()), 9)   # kg for a 2-sample manoeuvre
    0.0014
    """
    tp = check_positive_array("t_p", t_p, allow_zero=True, unit="s")
    md = check_positive_array("mdot", mdot, allow_zero=True, unit="kg/s", broadcast_to=tp.shape[-1:] if tp.ndim else ())
    return tp * md


def manoeuvre_fuel(
    forces: Any, *, f_max: Any = 10.0, t_s: float = 0.2, mdot: Any = 3.5e-3, t_min: Any = None
) -> float:
    """Propellant of a whole manoeuvre (kg): sum over samples and thrusters of ``mdot t_p``.

    Parameters
    ----------
    forces : array_like (..., n), N
        Allocated mean forces per sample (e.g. ``allocate(...).x`` for each demand).
    f_max, mdot : float or (n,)
        Thruster force (N) and mass flow (kg/s).
    t_s : float, s
    t_min : float or (n,), optional
        If given, pulses shorter than the minimum on-time are dropped
        (:func:`realisable_pulses`).

    References
    ----------
    S3 eq. 6-7.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.thrusters import manoeuvre_fuel
    >>> forces = np.array([[5.0, 0.0], [10.0, 0.1]])        # N, 2 samples x 2 thrusters
    >>> round(manoeuvre_fuel(forces), 9)                  # kg: (0.1 + 0.2 + 0.002) s x 3.5 g/s
    0.001057
    >>> round(manoeuvre_fuel(forces, t_min=0.003), 9)     # the 2 ms pulse is dropped
    0.00105
    """
    tp = _pulse_width("forces", forces, f_max, t_s)
    if t_min is not None:
        tp = realisable_pulses(tp, t_min=t_min)
    return float(np.sum(fuel_mass(tp, mdot=mdot)))
