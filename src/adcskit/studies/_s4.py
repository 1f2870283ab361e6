"""S4's nominal on-off loop (Table 3), declared once for the studies that simulate it.

``onoff-schmitt`` and ``onoff-tuning`` derive their ``Config`` from :class:`S4Loop` (the same
13 keys, defaults and checks); ``closed-loop`` reads its S4 scenario's plant from
:data:`S4_LOOP`.

References
----------
S4: Bohlouri V., Jalali-Naini S. H., "Robust optimization of satellite attitude control using
on-off thrusters based on a combined objective function", Journal of Space Science and
Technology 10(4), 2017 — Table 3 (nominal parameters), nomenclature (derivative filter),
§5 (15° step, 30 s run, last 10 s window, 50 Hz command rate).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from adcskit.control.onoff import LoopParams, LoopSettings
from adcskit.studies._base import NOT_PRINTED, protocol

__all__ = ["S4Loop", "S4_LOOP", "S4_LOOP_ATTRIBUTES"]


#: The numpydoc ``Attributes`` entries of the 13 loop keys (indented for a class docstring); the
#: configs derived from :class:`S4Loop` put them into their own docstrings instead of copying them.
S4_LOOP_ATTRIBUTES = """\
    u_on : float
        Schmitt on threshold on the (dimensionless) PID output (S4 Table 3: 0.15).
    off_ratio : float
        ``U_off / U_on`` in [0, 1] (S4 Table 3: 0.5).
    inertia_kgm2 : float, kg m²
        Moment of inertia ``J``, the mean where it is uncertain (S4 Table 3: 10).
    torque_nm : float, N m
        Torque level ``T`` of the thruster pair, the mean where it is uncertain (S4 Table 3: 1).
    delay_s : float, s
        Pure thruster delay ``τ``, the mean where it is uncertain (S4 Table 3: 0.02), >= 0.
    disturbance_nm : float, N m
        Constant disturbance torque ``T_d``, the mean where it is uncertain (S4 Table 3: 0.05).
    tau_thruster_s : float, s
        Time constant of each of the thruster's two first-order lags (S4 Table 3: 0.01).
    tau_deriv_s : float, s
        Time constant of the PID's derivative filter (named in S4's nomenclature, no value
        printed: 0.01 s is ours).
    step_deg : float, deg
        Commanded attitude step (S4 Table 3 and §4: 15°).
    command_rate_hz : float, Hz
        Rate at which the Schmitt trigger is evaluated (sample and hold; S4 §5: 50 Hz).
    dt_s : float, s
        Fixed integration step (S4 prints none).
    t_final_s : float, s
        Simulated duration (S4 prints none: 30 s is ours, ~25 s after the ~3 s slew).
    t_window_s : float, s
        Pointing statistics (the error objective) over the last ``t_window_s`` of the run
        (S4 eq. 9: 10 s).
"""

_S4_DOC = '''The nominal single-axis on-off loop of S4 (defaults: S4 Table 3).

    Each key declares the value S4 prints (``paper=``) or ``NOT_PRINTED``: S4 names the
    derivative filter's time constant in its nomenclature but prints no value, and prints
    neither an integration step nor the simulated duration.

    Attributes
    ----------
{attributes}
    Examples
    --------
    >>> S4_LOOP.settings().command_rate_hz, S4_LOOP.settings(200.0).command_rate_hz
    (50.0, 200.0)
    >>> round(S4_LOOP.base().theta_ref, 6)  # 15 deg step
    0.261799
    >>> S4Loop(delay_s=-1.0)
    Traceback (most recent call last):
    ...
    ValueError: delay_s must be >= 0; got -1.0
'''


@dataclass(frozen=True, kw_only=True)
class S4Loop:
    __doc__ = _S4_DOC.format(attributes=S4_LOOP_ATTRIBUTES)

    u_on: float = field(default=0.15, metadata=protocol("s4-loop", paper=0.15))
    off_ratio: float = field(default=0.5, metadata=protocol("s4-loop", paper=0.5))
    inertia_kgm2: float = field(default=10.0, metadata=protocol("s4-loop", paper=10.0))
    torque_nm: float = field(default=1.0, metadata=protocol("s4-loop", paper=1.0))
    delay_s: float = field(default=0.02, metadata=protocol("s4-loop", paper=0.02))
    disturbance_nm: float = field(default=0.05, metadata=protocol("s4-loop", paper=0.05))
    tau_thruster_s: float = field(default=0.01, metadata=protocol("s4-loop", paper=0.01))
    tau_deriv_s: float = field(default=0.01, metadata=protocol("s4-loop", paper=NOT_PRINTED))
    step_deg: float = field(default=15.0, metadata=protocol("s4-loop", paper=15.0))
    command_rate_hz: float = field(default=50.0, metadata=protocol("s4-loop", paper=50.0))
    dt_s: float = field(default=1e-3, metadata=protocol("s4-loop", paper=NOT_PRINTED))
    t_final_s: float = field(default=30.0, metadata=protocol("s4-loop", paper=NOT_PRINTED))
    t_window_s: float = field(default=10.0, metadata=protocol("s4-loop", paper=10.0))

    def __post_init__(self) -> None:
        for name in ("u_on", "inertia_kgm2", "torque_nm", "tau_thruster_s", "tau_deriv_s", "command_rate_hz",
                     "dt_s", "t_final_s", "t_window_s"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0; got {getattr(self, name)!r}")
        if not 0 <= self.off_ratio <= 1:
            raise ValueError(f"off_ratio must be in [0, 1]; got {self.off_ratio!r}")
        if self.delay_s < 0:
            raise ValueError(f"delay_s must be >= 0; got {self.delay_s!r}")

    def settings(self, command_rate_hz: float | None = None) -> LoopSettings:
        """The loop's :class:`~adcskit.control.onoff.LoopSettings` (optionally at another command rate)."""
        return LoopSettings(
            dt=self.dt_s, t_final=self.t_final_s, t_window=self.t_window_s, tau_thruster=self.tau_thruster_s,
            tau_deriv=self.tau_deriv_s, command_rate_hz=command_rate_hz or self.command_rate_hz,
        )

    def base(self) -> LoopParams:
        """The loop's :class:`~adcskit.control.onoff.LoopParams` with the default gains (SI: rad)."""
        return LoopParams(
            u_on=self.u_on, off_ratio=self.off_ratio, inertia=self.inertia_kgm2, torque=self.torque_nm,
            delay=self.delay_s, disturbance=self.disturbance_nm, theta_ref=math.radians(self.step_deg),
        )


#: S4 Table 3's loop, as printed.
S4_LOOP = S4Loop()
