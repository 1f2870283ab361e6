"""Reaction wheels, magnetorquers, momentum management and a mode sequence, batched.

A :class:`WheelScenario` (frozen dataclasses, loadable from TOML with
:func:`load_wheel_scenario`) describes a spacecraft pointed by reaction wheels and
magnetorquers; :func:`simulate_wheels` flies it for many Monte-Carlo samples at once in one
numba kernel (:mod:`adcskit.simulation._wheel_kernels`, blocks of samples on threads).

What the loop holds
-------------------
* **Plant** — a gyrostat: rigid body + ``n_w`` reaction wheels of any orientation
  (:meth:`WheelSpec.pyramid` for the 4-wheel pyramid), ``J w' = -w x (J w + A h) - A tau_w +
  tau_ext``, ``h' = tau_w`` (Markley & Crassidis 2014, §3.3.5; Wie 2008, §7.2), RK4; wheel
  torque and speed limits, viscous + Coulomb friction, torque quantisation and noise, failed
  wheels (motor off; friction still acts). External torques: gravity gradient (Markley &
  Crassidis eq. 3.155), the :class:`~adcskit.simulation.DisturbanceSpec` torque, and the
  magnetorquers' ``m x B`` with ``B`` from :func:`adcskit.environment.magnetic_field`
  (dipole or IGRF-14) along a circular orbit.
* **Sensors** (:class:`~adcskit.simulation.SensorSpec`, each at its own rate): gyro (angle and
  rate random walk, bias), star tracker (Gaussian rotation vector; attitude knowledge is the
  last star-tracker quaternion propagated with the gyro; without a star tracker the true
  attitude), sun sensor (Gaussian per component, nothing in eclipse), magnetometer (Gaussian
  per component, relative to ``|B|``; *blanked* or *corrupted* by ``coupling x m`` while the
  magnetorquers fire). By default no filter: the knowledge is the raw sensors'; optionally
  (``estimator=EstimatorSpec(kind="mekf")``) the thruster loop's MEKF with gyro-bias
  estimation (Lefferts, Markley & Shuster 1982), with its NEES as a consistency metric.
* **Modes** (:class:`ModeSpec`), switched inside the kernel at every control period:
  ``detumble`` (B-dot on the magnetorquers, ``m = -k dB/dt``, Stickler & Alfriend 1976; wheels
  idle) -> ``sun`` (wheels align ``sun_axis`` with the measured sun: ``u = J (k (n x s) -
  c w)``, rate damping only in eclipse) -> ``point`` (nadir / LVLH or an inertial target).
  Detumble ends when the measured rate stays below ``rate_threshold_deg_s`` for ``dwell_s``;
  sun acquisition ends when the sun is visible and within ``sun_threshold_deg`` of the axis
  for ``dwell_s``.
* **Control** (:class:`WheelControlSpec`): quaternion feedback ``u = -J (2 k q_e + c w_e) +
  w x (J w + A h)`` with ``k = omega_n^2``, ``c = 2 zeta omega_n`` (Wie 2008, §7.3; Wie,
  Weiss & Arapostathis 1989), or Wie's rate-limited variant in which the ``2 k q_e`` term is
  scaled along the eigenaxis to at most ``c omega_max`` (Wie & Lu 1995; Wie 2008, §7.3), so
  the eigenaxis slew rate settles at ``omega_max``; the torque limit scales the whole wheel
  command (direction kept). Allocation: ``tau_w = -A^+ u`` over the working wheels, plus the
  null motion ``-k_n (I - A^+ A)(h - h*)`` that keeps the wheel speeds near a non-zero bias
  ``h*`` in the null space (away from zero crossings).
* **Momentum management**: magnetic unloading in ``sun`` and ``point`` modes with the
  cross-product law ``m = k (h_w x B) / |B|^2`` (torque ``m x B = -k h_w,perp``;
  Camillo & Markley 1980); thruster unloading (:class:`ThrusterUnloadSpec`, optional): above
  a wheel-momentum threshold the thrusters produce a torque opposite the wheel momentum,
  allocated by the thruster loop's redistributed pseudo-inverse and fired as pulses with a
  minimum on-time, while the wheels hold the attitude (the thruster torque fed forward), until
  the momentum is below a lower threshold; propellant is a metric (Sidi 1997, §7.5).

Hand-written here: the specs, the set-up and the kernel; no kept library simulates a
wheel + magnetorquer mode sequence across thousands of samples in compiled code (Basilisk
runs one sample per process).

References
----------
Markley F. L., Crassidis J. L., *Fundamentals of Spacecraft Attitude Determination and
Control*, Springer 2014, §3.3.5 (spacecraft with reaction wheels), eq. 3.155 (gravity
gradient). Wie B., *Space Vehicle Dynamics and Control*, 2nd ed., AIAA 2008, §7.2-7.3.
Wie B., Weiss H., Arapostathis A., "Quaternion feedback regulator for spacecraft eigenaxis
rotations", JGCD 12(3), 1989. Wie B., Lu J., "Feedback control logic for spacecraft eigenaxis
rotations under slew rate and control constraints", JGCD 18(6), 1995. Stickler A. C.,
Alfriend K. T., "Elementary magnetic attitude control system", J. Spacecraft 13(5), 1976.
Camillo P. J., Markley F. L., "Orbit-averaged behavior of magnetic control laws for momentum
unloading", J. Guidance and Control 3(6), 1980.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from scipy.spatial.transform import Rotation

from adcskit._progress import auto_session, progress_flag
from adcskit._targets import resolve_backend
from adcskit._validation import (
    as_array,
    as_rng,
    check_choice,
    check_flag,
    check_flag_fields,
    check_int,
    check_positive,
    check_range,
    short_repr,
)
from adcskit.constants import RAD_PER_DEG
from adcskit.errors import InputError, InputTypeError
from adcskit.simulation import _wheel_kernels as _k
from adcskit.simulation.scenario import (
    DisturbanceSpec,
    EstimatorSpec,
    OrbitSpec,
    SensorSpec,
    SimSpec,
    SpacecraftSpec,
    ThrusterSpec,
    _check_parts,
    _load_spec,
    _Spec,
    _triangle_ok,
    _vec,
    _whole_steps,
)

__all__ = [
    "WheelSpec",
    "MagnetorquerSpec",
    "WheelControlSpec",
    "ModeSpec",
    "WheelDispersionSpec",
    "ThrusterUnloadSpec",
    "WheelScenario",
    "WheelSimulationResult",
    "load_wheel_scenario",
    "simulate_wheels",
    "wheel_envelope_figure",
    "MODE_NAMES",
    "WHEEL_METRIC_NAMES",
    "WHEEL_UNLOAD_METRIC_NAMES",
    "WHEEL_FILTER_METRIC_NAMES",
    "WHEEL_ENVELOPE_CHANNELS",
]

_RPM = 2.0 * math.pi / 60.0
_ARCSEC = RAD_PER_DEG / 3600.0
_MU = 3.986004418e14
_RE = 6378137.0

#: Mode names, indexed by the mode number in the traces and ``final_mode``.
MODE_NAMES: tuple[str, ...] = ("detumble", "sun", "point")


def _per_wheel(name: str, v: Any, n: int, unit: str, *, allow_zero: bool = True) -> tuple[float, ...]:
    """A scalar broadcast to ``n`` wheels, or ``n`` values; each finite and >= 0 (> 0)."""
    a = as_array(name, v).reshape(-1)
    if a.size == 1:
        a = np.full(n, float(a[0]))
    if a.size != n:
        raise InputError(f"{name} must be one value or {n} values (one per wheel) {unit}; got {a.size}")
    bad = a < 0 if allow_zero else a <= 0
    if np.any(bad):
        raise InputError(f"{name} must be {'>=' if allow_zero else '>'} 0 {unit} for every wheel; got {a.tolist()}")
    return tuple(float(x) for x in a)


@dataclass(frozen=True, slots=True, kw_only=True)
class WheelSpec(_Spec):
    """Reaction wheels: axes, inertia, limits, friction, drive errors and failures.

    Attributes
    ----------
    axes : sequence of 3-vectors
        Spin axes in the body frame, one per wheel (1 to 12 wheels; normalised here). The
        default is the 4-wheel pyramid of :meth:`pyramid`.
    inertia_kgm2 : float or one per wheel, kg m^2
        Axial inertia ``J_w`` of each wheel (default 2.4e-5: 0.015 N m s at 6000 rpm, a
        12U-class wheel).
    max_torque_nm : float, N m
        Motor torque limit per wheel (the demand is scaled uniformly, direction kept).
    max_speed_rpm : float, rpm
        Speed limit: at ``|Omega| >= max`` a torque that would spin the wheel faster is cut.
    viscous_nms : float, N m s/rad
        Viscous friction ``c_v Omega``.
    coulomb_nm : float, N m
        Coulomb friction ``c_c sign(Omega)`` (smoothed over 0.01 rad/s).
    torque_quantum_nm : float, N m
        Torque command quantisation step (0: none).
    torque_noise_nm : float, N m
        Std of a Gaussian torque error drawn per wheel and control period.
    initial_speed_rpm : float or one per wheel, rpm
        Wheel speeds relative to the body at t = 0.
    failed : tuple of int
        Indices of failed wheels: motor off (friction still acts), excluded from allocation.

    Examples
    --------
    >>> from adcskit.simulation import WheelSpec
    >>> w = WheelSpec(axes=((1, 0, 0), (0, 1, 0), (0, 0, 1), (0.577, 0.577, 0.577)), max_torque_nm=0.004,
    ...               failed=(3,))                 # 3 orthogonal wheels + a skewed spare, failed
    >>> w.n, w.failed, w.axis_matrix().shape
    (4, (3,), (3, 4))

    References
    ----------
    Markley & Crassidis 2014, §3.3.5 (wheel momentum and torque); Wie 2008, §7.2.
    """

    axes: tuple[tuple[float, float, float], ...] = field(default_factory=lambda: _pyramid_axes(35.26438968275466))
    inertia_kgm2: Any = 2.4e-5
    max_torque_nm: float = 4e-3
    max_speed_rpm: float = 6000.0
    viscous_nms: float = 0.0
    coulomb_nm: float = 0.0
    torque_quantum_nm: float = 0.0
    torque_noise_nm: float = 0.0
    initial_speed_rpm: Any = 0.0
    failed: tuple[int, ...] = ()

    def __post_init__(self) -> None:
        ax = as_array("axes", self.axes)
        if ax.ndim != 2 or ax.shape[1] != 3 or not 1 <= ax.shape[0] <= 12:
            raise InputError(f"axes must be a list of 1 to 12 3-vectors (one per wheel); got shape {ax.shape}")
        nrm = np.linalg.norm(ax, axis=1)
        if np.any(nrm < 1e-9):
            raise InputError(f"axes must be non-zero vectors; wheel(s) {np.flatnonzero(nrm < 1e-9).tolist()} are zero")
        ax = ax / nrm[:, None]
        n = ax.shape[0]
        object.__setattr__(self, "axes", tuple(tuple(float(x) for x in a) for a in ax))
        object.__setattr__(self, "inertia_kgm2", _per_wheel("inertia_kgm2", self.inertia_kgm2, n, "kg m^2",
                                                            allow_zero=False))
        check_positive("max_torque_nm", self.max_torque_nm, unit="N m")
        check_positive("max_speed_rpm", self.max_speed_rpm, unit="rpm")
        for name in ("viscous_nms", "coulomb_nm", "torque_quantum_nm", "torque_noise_nm"):
            check_positive(name, getattr(self, name), allow_zero=True)
        sp = as_array("initial_speed_rpm", self.initial_speed_rpm).reshape(-1)
        if sp.size == 1:
            sp = np.full(n, float(sp[0]))
        if sp.size != n:
            raise InputError(f"initial_speed_rpm must be one value or {n} values (one per wheel) rpm; got {sp.size}")
        object.__setattr__(self, "initial_speed_rpm", tuple(float(x) for x in sp))
        failed = []
        for j in self.failed:
            if isinstance(j, bool) or not isinstance(j, (int, np.integer)) or not 0 <= int(j) < n:
                raise InputError(f"failed must hold wheel indices in [0, {n - 1}]; got {j!r}")
            failed.append(int(j))
        object.__setattr__(self, "failed", tuple(sorted(set(failed))))
        if np.linalg.matrix_rank(np.delete(ax, list(self.failed), axis=0), tol=1e-9) < 3:
            raise InputError(f"the working wheels (axes without failed {list(self.failed)}) must span 3 axes; "
                             f"got {n - len(self.failed)} wheel(s) of rank < 3")

    @property
    def n(self) -> int:
        """Number of wheels."""
        return len(self.axes)

    def axis_matrix(self) -> np.ndarray:
        """``A`` (3, n_w): the unit spin axes as columns (body frame)."""
        return np.asarray(self.axes, dtype=float).T.copy()

    @classmethod
    def pyramid(cls, elevation_deg: float = 35.26438968275466, **kw: Any) -> WheelSpec:
        """Four wheels in a pyramid about body z: ``a_j = (cos e cos p_j, cos e sin p_j, sin e)``,
        ``p_j = 45 + 90 j`` deg (the default ``e = atan(1/sqrt 2)`` gives every body axis the
        same momentum capacity, ``4/sqrt 3`` wheel momenta).

        Examples
        --------
        >>> from adcskit.simulation import WheelSpec
        >>> w = WheelSpec.pyramid(max_torque_nm=0.004)
        >>> w.n, round(w.axes[0][2], 4)
        (4, 0.5774)
        """
        e = check_range("elevation_deg", elevation_deg, 0.0, 90.0, lo_open=True, hi_open=True, unit="deg")
        if min(math.sin(e * RAD_PER_DEG), math.cos(e * RAD_PER_DEG)) < 1e-6:
            raise InputError(f"elevation_deg must keep the pyramid's axes spanning 3 axes (between 6e-5 and "
                             f"89.99994 deg); got {e!r} deg")
        return cls(axes=_pyramid_axes(e), **kw)


def _pyramid_axes(elevation_deg: float) -> tuple[tuple[float, float, float], ...]:
    e = elevation_deg * RAD_PER_DEG
    return tuple((math.cos(e) * math.cos(p), math.cos(e) * math.sin(p), math.sin(e))
                 for p in (math.pi / 4 + j * math.pi / 2 for j in range(4)))


@dataclass(frozen=True, slots=True, kw_only=True)
class MagnetorquerSpec(_Spec):
    """Three magnetorquers along the body axes, B-dot detumbling and magnetic unloading.

    Attributes
    ----------
    max_dipole_am2 : float, A m^2
        Dipole limit per rod (the command is scaled so that its largest component fits).
    duty : float
        Fraction of each control period during which the rods are on (in (0, 1]), realised as
        ``floor(duty * steps)`` whole steps at the start of the period, at least one and, for
        ``duty < 1``, at most all but one (then the magnetometer sample at the start of the
        next period is taken with the rods off; ``duty < 1`` needs a control period of >= 2
        steps).
    magnetometer : {"blank", "corrupt"}
        A magnetometer sample taken while the rods are on is dropped (``blank``) or gets
        ``coupling_t_per_am2 * m`` added (``corrupt``).
    coupling_t_per_am2 : float, T/(A m^2)
        Field error per unit dipole at the magnetometer (``corrupt``).
    bdot_gain : float, A m^2 s/T
        B-dot gain ``k`` of ``m = -k dB/dt`` (``dB/dt`` from consecutive magnetometer samples).
    unload_gain : float, 1/s
        Gain ``k`` of the cross-product law ``m = k (h_w x B) / |B|^2`` (0: no unloading).

    Examples
    --------
    >>> from adcskit.simulation import MagnetorquerSpec
    >>> m = MagnetorquerSpec(max_dipole_am2=0.2, duty=0.8, bdot_gain=2e5)
    >>> m.magnetometer
    'blank'

    References
    ----------
    Stickler & Alfriend 1976 (B-dot); Camillo & Markley 1980 (cross-product unloading).
    """

    max_dipole_am2: float = 0.2
    duty: float = 0.8
    magnetometer: Literal["blank", "corrupt"] = "blank"
    coupling_t_per_am2: float = 0.0
    bdot_gain: float = 2e5
    unload_gain: float = 2e-3

    def __post_init__(self) -> None:
        check_positive("max_dipole_am2", self.max_dipole_am2, allow_zero=True, unit="A m^2")
        check_range("duty", self.duty, 0.0, 1.0, lo_open=True)
        check_choice("magnetometer", self.magnetometer, ("blank", "corrupt"))
        check_positive("coupling_t_per_am2", self.coupling_t_per_am2, allow_zero=True, unit="T/(A m^2)")
        check_positive("bdot_gain", self.bdot_gain, allow_zero=True, unit="A m^2 s/T")
        check_positive("unload_gain", self.unload_gain, allow_zero=True, unit="1/s")


@dataclass(frozen=True, slots=True, kw_only=True)
class WheelControlSpec(_Spec):
    """Wheel control law, gains and allocation.

    Attributes
    ----------
    law : {"pd", "wie", "open-loop"}
        ``pd``: quaternion feedback ``u = -J (2 k q_e + c w_e) + w x (J w + A h)``;
        ``wie``: the same with ``2 k q_e`` scaled (along the eigenaxis) to at most
        ``c * rate_limit`` (Wie & Lu 1995), so large slews run at ``rate_limit``;
        ``open-loop``: the wheel motor torques ``open_loop_torque_nm`` (validation runs).
        ``J`` is the nominal inertia, ``k = bandwidth^2``, ``c = 2 damping bandwidth``: for
        small errors each axis is ``theta'' + c theta' + k theta = 0``.
    bandwidth_rad_s : float, rad/s
        Natural frequency ``omega_n``.
    damping : float
        Damping ratio ``zeta``.
    rate_limit_deg_s : float, deg/s
        ``wie``: eigenaxis rate limit.
    period_s : float, s
        Control period (a whole number of steps).
    null_motion : bool
        Add the null-motion term (needs more working wheels than 3).
    null_gain : float, 1/s
        Gain ``k_n`` of the null motion.
    null_speed_rpm : float, rpm
        Bias speed of the null-space momentum ``h*`` (the smallest biased wheel speed).
    open_loop_torque_nm : tuple of float, N m
        ``open-loop``: constant motor torque per wheel.
    open_loop_dipole_am2 : 3 floats, A m^2
        ``open-loop``: constant commanded magnetorquer dipole (body axes), scaled like every
        dipole command so that its largest component is at most
        ``MagnetorquerSpec.max_dipole_am2``, on for ``duty`` of each period (validation runs).

    Examples
    --------
    >>> from adcskit.simulation import WheelControlSpec
    >>> c = WheelControlSpec(law="wie", bandwidth_rad_s=0.2, damping=0.9, rate_limit_deg_s=1.0)
    >>> c.law, c.null_motion
    ('wie', False)

    References
    ----------
    Wie 2008, §7.3; Wie, Weiss & Arapostathis 1989; Wie & Lu 1995.
    """

    law: Literal["pd", "wie", "open-loop"] = "wie"
    bandwidth_rad_s: float = 0.1
    damping: float = 0.9
    rate_limit_deg_s: float = 1.0
    period_s: float = 1.0
    null_motion: bool = False
    null_gain: float = 0.01
    null_speed_rpm: float = 1000.0
    open_loop_torque_nm: tuple[float, ...] = ()
    open_loop_dipole_am2: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        check_flag_fields(self)
        check_choice("law", self.law, ("pd", "wie", "open-loop"))
        check_positive("bandwidth_rad_s", self.bandwidth_rad_s, unit="rad/s")
        check_positive("damping", self.damping)
        check_positive("rate_limit_deg_s", self.rate_limit_deg_s, unit="deg/s")
        check_positive("period_s", self.period_s, unit="s")
        check_positive("null_gain", self.null_gain, unit="1/s")
        check_positive("null_speed_rpm", self.null_speed_rpm, allow_zero=True, unit="rpm")
        ot = as_array("open_loop_torque_nm", self.open_loop_torque_nm, nonempty=False).reshape(-1)
        object.__setattr__(self, "open_loop_torque_nm", tuple(float(x) for x in ot))
        object.__setattr__(self, "open_loop_dipole_am2", _vec("open_loop_dipole_am2", self.open_loop_dipole_am2))
        if self.law == "open-loop" and ot.size == 0:
            raise InputError("open_loop_torque_nm must give one torque per wheel (N m) with law='open-loop'; got ()")


@dataclass(frozen=True, slots=True, kw_only=True)
class ModeSpec(_Spec):
    """Mode sequence detumble -> sun -> point and its switching conditions.

    Attributes
    ----------
    initial : {"detumble", "sun", "point"}
        Mode at t = 0.
    sequence : bool
        Switch modes on the conditions below (else stay in ``initial``).
    rate_threshold_deg_s : float, deg/s
        Detumble ends when the measured rate stays below this for ``dwell_s``.
    dwell_s : float, s
        Dwell time of both switching conditions.
    sun_axis : 3 floats
        Body axis to point at the sun (normalised).
    sun_threshold_deg : float, deg
        Sun acquisition ends when the sun is visible and within this angle of ``sun_axis``
        for ``dwell_s``.
    pointing : {"nadir", "inertial"}
        ``nadir``: body z to nadir, body x along the velocity (LVLH); ``inertial``: the
        attitude ``target_rotvec_deg`` (rotation vector from ECI).
    target_rotvec_deg : 3 floats, deg

    Examples
    --------
    >>> from adcskit.simulation import ModeSpec
    >>> ModeSpec(initial="point", sequence=False, pointing="inertial").pointing
    'inertial'
    """

    initial: Literal["detumble", "sun", "point"] = "detumble"
    sequence: bool = True
    rate_threshold_deg_s: float = 1.0
    dwell_s: float = 60.0
    sun_axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    sun_threshold_deg: float = 10.0
    pointing: Literal["nadir", "inertial"] = "nadir"
    target_rotvec_deg: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        check_flag_fields(self)
        check_choice("initial", self.initial, MODE_NAMES)
        check_positive("rate_threshold_deg_s", self.rate_threshold_deg_s, unit="deg/s")
        check_positive("dwell_s", self.dwell_s, allow_zero=True, unit="s")
        a = np.asarray(_vec("sun_axis", self.sun_axis))
        if np.linalg.norm(a) < 1e-9:
            raise InputError(f"sun_axis must be a non-zero 3-vector; got {self.sun_axis!r}")
        object.__setattr__(self, "sun_axis", tuple(float(x) for x in a / np.linalg.norm(a)))
        check_range("sun_threshold_deg", self.sun_threshold_deg, 0.0, 180.0, lo_open=True, unit="deg")
        check_choice("pointing", self.pointing, ("nadir", "inertial"))
        object.__setattr__(self, "target_rotvec_deg", _vec("target_rotvec_deg", self.target_rotvec_deg))


@dataclass(frozen=True, slots=True, kw_only=True)
class WheelDispersionSpec(_Spec):
    """Monte-Carlo dispersions of a wheel scenario (0 turns one off).

    Attributes
    ----------
    inertia_rel : float
        Relative std of each principal moment (truncated at +-90 %, principal axes kept).
    wheel_misalignment_deg : float, deg
        Std per axis of a small rotation of each wheel's true spin axis (the controller
        allocates with the nominal axes).
    sensor_noise_rel : float
        Relative std of a per-sample factor on every sensor's noise (truncated to [0, 3]).
    initial_rate_deg_s : float, deg/s
        Std per axis of the initial body rate about the nominal.
    initial_attitude : {"nominal", "random"}
        ``random``: uniformly distributed initial attitudes (a tumbling spacecraft after
        separation); ``nominal``: the scenario's, perturbed by ``initial_attitude_deg``.
    initial_attitude_deg : float, deg
        Std per axis of the initial attitude about the nominal.
    sampling : {"lhs", "random"}

    Examples
    --------
    >>> from adcskit.simulation import WheelDispersionSpec
    >>> WheelDispersionSpec(inertia_rel=0.1, initial_attitude="random").initial_attitude
    'random'
    """

    inertia_rel: float = 0.0
    wheel_misalignment_deg: float = 0.0
    sensor_noise_rel: float = 0.0
    initial_rate_deg_s: float = 0.0
    initial_attitude: Literal["nominal", "random"] = "nominal"
    initial_attitude_deg: float = 0.0
    sampling: Literal["lhs", "random"] = "lhs"

    def __post_init__(self) -> None:
        for name in ("inertia_rel", "wheel_misalignment_deg", "sensor_noise_rel", "initial_rate_deg_s",
                     "initial_attitude_deg"):
            check_positive(name, getattr(self, name), allow_zero=True)
        check_choice("initial_attitude", self.initial_attitude, ("nominal", "random"))
        check_choice("sampling", self.sampling, ("lhs", "random"))


@dataclass(frozen=True, slots=True, kw_only=True)
class ThrusterUnloadSpec(_Spec):
    """Thruster unloading of the wheel momentum ("momentum dumping" with reaction jets).

    When the wheel momentum ``|A h|`` (nominal axes and the wheel tachometers, as the
    controller knows it) exceeds ``start_nms``, the thrusters produce the torque
    ``-torque_nm h / |h|`` until it falls below ``stop_nms`` (hysteresis), in the ``sun``
    and ``point`` modes. The wheels hold the attitude meanwhile: the thrusters' commanded
    torque is fed forward into the wheel command, so the wheels absorb it and their momentum
    falls (Sidi 1997, §7.5; Wie 2008, §7.5; Markley & Crassidis 2014, §7.7). Each control
    period the torque is allocated to forces ``0 <= F_j <= f_max`` by the closed loop's
    redistributed pseudo-inverse (S3 eq. 12), fired as pulses of width
    ``t_j = F_j / f_max * period`` from the start of the period (S3 eq. 6), pulses shorter
    than ``t_min`` are dropped (the minimum impulse bit, S3 §2-2), and thrusters in
    ``thrusters.failed`` never fire (the allocator leaves them out when ``failure_known``).

    Attributes
    ----------
    thrusters : ThrusterSpec or adcskit.thrusters.ThrusterSet
        The thruster set (positions, directions, ``f_max``, ``mdot``, ``t_min``, ``com``,
        failures), the description of the thruster closed loop; the layout must give a
        torque in every direction (positive span of R^3; failed thrusters may leave some
        directions unreachable, which the metrics then show). A
        :class:`~adcskit.thrusters.ThrusterSet` (e.g. a layout from
        :func:`~adcskit.thrusters.design_layout`) is converted with
        :meth:`ThrusterSpec.from_thruster_set` (its ``f_max``, ``mdot`` and ``t_min`` must
        be the same for every thruster). ``tau`` and ``delay`` are not modelled here: the
        pulses are ideal on-off. The thrusters' force on the orbit is not modelled.
    start_nms : float, N m s
        Unloading starts when ``|A h|`` exceeds this.
    stop_nms : float, N m s
        Unloading stops when ``|A h|`` falls below this (``< start_nms``).
    torque_nm : float, N m
        Magnitude of the requested unloading torque (at most the wheels' ``max_torque_nm``:
        the wheels absorb it).

    Examples
    --------
    >>> from adcskit.simulation import ThrusterSpec, ThrusterUnloadSpec
    >>> pos = ((0.1, 0, 0), (-0.1, 0, 0), (0, 0.1, 0), (0, -0.1, 0), (0, 0, 0.15), (0, 0, -0.15))
    >>> d = ((0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1), (1, 0, 0), (-1, 0, 0))
    >>> jets = ThrusterSpec(positions=pos + pos, directions=d + tuple((-a, -b, -c) for a, b, c in d),
    ...                     f_max=0.01, mdot=1.4e-5, t_min=0.01)   # 12 x 10 mN cold gas, Isp ~73 s
    >>> u = ThrusterUnloadSpec(thrusters=jets, start_nms=0.01, stop_nms=0.002, torque_nm=5e-4)
    >>> u.thrusters.n, u.stop_nms
    (12, 0.002)

    References
    ----------
    Sidi M. J., *Spacecraft Dynamics and Control*, Cambridge 1997, §7.5 (momentum dumping).
    Wie B., *Space Vehicle Dynamics and Control*, 2nd ed., AIAA 2008, §7.5. Markley F. L.,
    Crassidis J. L., 2014, §7.7 (momentum management). S3: Servidia & Sanchez Pena (the
    allocation and the pulse model, eqs. 6 and 12). Section numbers were not checked against
    the texts.
    """

    thrusters: ThrusterSpec
    start_nms: float = 0.01
    stop_nms: float = 0.002
    torque_nm: float = 5e-4

    def __post_init__(self) -> None:
        from adcskit.thrusters import ThrusterSet, check_controllability

        th = self.thrusters
        if isinstance(th, ThrusterSet):
            for name in ("f_max", "mdot", "t_min"):
                v = np.asarray(getattr(th, name))
                if np.ptp(v) != 0.0:
                    raise InputError(f"thrusters.{name} must be the same for every thruster of a ThrusterSet to "
                                     f"convert it to a ThrusterSpec; got {v.tolist()}")
            th = ThrusterSpec.from_thruster_set(th)
            object.__setattr__(self, "thrusters", th)
        elif not isinstance(th, ThrusterSpec):
            raise InputTypeError(f"thrusters must be a ThrusterSpec or an adcskit.thrusters.ThrusterSet; got "
                                 f"{short_repr(th)}")
        check_positive("start_nms", self.start_nms, unit="N m s")
        check_positive("stop_nms", self.stop_nms, allow_zero=True, unit="N m s")
        if not self.stop_nms < self.start_nms:
            raise InputError(f"stop_nms must be < start_nms = {self.start_nms:g} N m s (hysteresis); got "
                             f"{self.stop_nms:g} N m s")
        check_positive("torque_nm", self.torque_nm, unit="N m")
        ctrl = check_controllability(th.torque_matrix())
        if not ctrl.success:
            raise InputError(f"thrusters must produce a torque in every direction (their torque-matrix columns must "
                             f"positively span R^3) to unload any wheel momentum; {ctrl.message}")

    def torque_matrix(self) -> np.ndarray:
        """``(3, n_t)``, N m per N: column ``j`` is ``(r_j - com) x d_j``."""
        return self.thrusters.torque_matrix()


def _ref_spacecraft() -> SpacecraftSpec:
    return SpacecraftSpec(inertia=(0.30, 0.27, 0.17))


def _ref_orbit() -> OrbitSpec:
    return OrbitSpec(altitude_km=500.0, inclination_deg=97.4, raan_deg=30.0, arg_lat0_deg=0.0,
                     epoch="2026-03-21T06:00:00", gravity_gradient=True, magnetic_model="dipole")


def _ref_sensors() -> SensorSpec:
    return SensorSpec(sun_rate_hz=1.0, sun_noise_deg=0.5, mag_rate_hz=1.0, mag_noise_deg=0.5, gyro_rate_hz=5.0,
                      gyro_arw=1.5e-5, gyro_rrw=1e-7, gyro_bias0_deg_h=5.0, star_tracker_rate_hz=1.0,
                      star_tracker_noise_arcsec=20.0)


def _ref_sim() -> SimSpec:
    return SimSpec(dt=0.2, t_final=17100.0, metrics_from_s=11400.0, settle_band_deg=0.5, record_every=50)


@dataclass(frozen=True, slots=True, kw_only=True)
class WheelScenario(_Spec):
    """A wheel + magnetorquer scenario (all parts are data). The defaults are the reference
    12U-class LEO smallsat: diag(0.30, 0.27, 0.17) kg m^2, 500 km sun-synchronous orbit
    (97.4 deg), 4-wheel pyramid (0.015 N m s, 4 mN m), three 0.2 A m^2 rods, sun sensor +
    magnetometer + gyro + star tracker, detumble -> sun -> nadir over three orbits (17 100 s,
    dt 0.2 s, control at 1 Hz), pointing metrics over the third orbit (from 11 400 s).

    Attributes
    ----------
    spacecraft : SpacecraftSpec
        Inertia without the wheels' axial inertia, kg m^2.
    orbit : OrbitSpec
        Circular orbit, epoch and environment models (as in :class:`~adcskit.simulation.Scenario`).
    disturbance : DisturbanceSpec
        Body-frame disturbance torque.
    sensors : SensorSpec
        Sun sensor, magnetometer, gyro and star tracker (``mag_noise_deg`` is the
        per-component std relative to ``|B|``, in the angle it subtends).
    sim : SimSpec
        Time grid and metrics.
    wheels : WheelSpec
        Reaction wheels.
    magnetorquers : MagnetorquerSpec
        Torque rods (B-dot and magnetic unloading).
    control : WheelControlSpec
        Wheel control law, gains and allocation.
    modes : ModeSpec
        Mode sequence detumble -> sun -> point.
    dispersions : WheelDispersionSpec
        Monte-Carlo dispersions.
    estimator : EstimatorSpec or None
        ``None`` (default): the knowledge is the raw sensors' (the last star-tracker
        quaternion propagated with the gyro; the truth without a star tracker) and the
        controller uses the raw gyro rate. ``EstimatorSpec(kind="mekf")``: the thruster
        loop's multiplicative EKF with gyro-bias estimation (Lefferts, Markley & Shuster 1982;
        :mod:`adcskit.estimation.mekf`'s kernels), propagated every step with a rate-integrating
        gyro (the step's mean body rate plus the reading's held bias and noise: a held
        instantaneous rate made it inconsistent when the rate changes within a step) and
        updated by the star tracker (quaternion), the sun sensor and the
        magnetometer (unit vectors, ``underweight`` as in the thruster loop), with the
        *nominal* sensor sigmas; the controller uses its attitude and the bias-corrected rate.
        Initial estimate: the truth turned by a Gaussian rotation vector of
        ``init_error_deg`` per axis, zero bias (covariance from ``init_error_deg`` and
        ``sensors.gyro_bias0_deg_h``). Only ``kind="mekf"`` is available here.
    thruster_unloading : ThrusterUnloadSpec or None
        Thrusters that unload the wheel momentum (``None``, the default: none; magnetic
        unloading is :attr:`MagnetorquerSpec.unload_gain`). One optional part holds both the
        thruster set and its law, since neither means anything without the other.
    initial_rotvec_deg : 3 floats, deg
    initial_rate_deg_s : 3 floats, deg/s
        Default: the reference's tumble after separation, (2, -1.5, 1.5) deg/s; set (0, 0, 0)
        for a spacecraft at rest.

    Examples
    --------
    >>> from adcskit.simulation import WheelScenario
    >>> sc = WheelScenario()
    >>> sc.wheels.n, sc.modes.initial, sc.sim.dt
    (4, 'detumble', 0.2)
    """

    spacecraft: SpacecraftSpec = field(default_factory=_ref_spacecraft)
    orbit: OrbitSpec = field(default_factory=_ref_orbit)
    disturbance: DisturbanceSpec = field(default_factory=lambda: DisturbanceSpec(constant=(2e-7, -1e-7, 1e-7)))
    wheels: WheelSpec = field(default_factory=WheelSpec)
    magnetorquers: MagnetorquerSpec = field(default_factory=MagnetorquerSpec)
    sensors: SensorSpec = field(default_factory=_ref_sensors)
    control: WheelControlSpec = field(default_factory=WheelControlSpec)
    modes: ModeSpec = field(default_factory=ModeSpec)
    dispersions: WheelDispersionSpec = field(default_factory=WheelDispersionSpec)
    sim: SimSpec = field(default_factory=_ref_sim)
    thruster_unloading: ThrusterUnloadSpec | None = None
    estimator: EstimatorSpec | None = None
    initial_rotvec_deg: tuple[float, float, float] = (0.0, 0.0, 0.0)
    initial_rate_deg_s: tuple[float, float, float] = (2.0, -1.5, 1.5)

    def __post_init__(self) -> None:
        parts = {"spacecraft": SpacecraftSpec, "orbit": OrbitSpec, "disturbance": DisturbanceSpec,
                 "wheels": WheelSpec, "magnetorquers": MagnetorquerSpec, "sensors": SensorSpec,
                 "control": WheelControlSpec, "modes": ModeSpec, "dispersions": WheelDispersionSpec, "sim": SimSpec}
        _check_parts(self, parts)
        tu = self.thruster_unloading
        if tu is not None and not isinstance(tu, ThrusterUnloadSpec):
            raise InputError(f"thruster_unloading must be a ThrusterUnloadSpec or None; got {type(tu).__name__}")
        if tu is not None and tu.torque_nm > self.wheels.max_torque_nm:
            raise InputError(f"thruster_unloading.torque_nm must be <= wheels.max_torque_nm = "
                             f"{self.wheels.max_torque_nm:g} N m (the wheels absorb the unloading torque); got "
                             f"{tu.torque_nm:g} N m")
        est = self.estimator
        if est is not None:
            if not isinstance(est, EstimatorSpec):
                raise InputError(f"estimator must be an EstimatorSpec or None; got {type(est).__name__}")
            if est.kind != "mekf":
                raise InputError(f"estimator.kind must be 'mekf' in the wheel loop (None: the raw sensors); got "
                                 f"{est.kind!r}")
            if not est.init_error_deg > 0:
                raise InputError(f"estimator.init_error_deg must be > 0 deg (the MEKF's initial sigma); got "
                                 f"{est.init_error_deg!r}")
        object.__setattr__(self, "initial_rotvec_deg", _vec("initial_rotvec_deg", self.initial_rotvec_deg))
        object.__setattr__(self, "initial_rate_deg_s", _vec("initial_rate_deg_s", self.initial_rate_deg_s))
        dt = self.sim.dt
        steps = _whole_steps(dt)

        steps("control.period_s", self.control.period_s)
        steps("1 / sensors.gyro_rate_hz", 1.0 / self.sensors.gyro_rate_hz)
        for name in ("sun_rate_hz", "mag_rate_hz", "star_tracker_rate_hz"):
            rate = getattr(self.sensors, name)
            if rate > 0:
                steps(f"1 / sensors.{name}", 1.0 / rate)
        hc = int(round(self.control.period_s / dt))
        mt = self.magnetorquers
        rods_used = mt.max_dipole_am2 > 0 and self.control.law != "open-loop" and self.sensors.mag_rate_hz > 0 and (
            self.modes.initial == "detumble" or mt.unload_gain > 0)
        if rods_used and mt.duty < 1.0 and hc < 2:
            raise InputError(f"magnetorquers.duty={self.magnetorquers.duty:g} < 1 needs an off step in each control "
                             f"period: control.period_s must be >= 2 steps (2 dt = {2 * dt:g} s); got "
                             f"{self.control.period_s:g} s")
        nw = self.wheels.n
        if self.control.law == "open-loop" and len(self.control.open_loop_torque_nm) != nw:
            raise InputError(f"control.open_loop_torque_nm must have {nw} entries (one per wheel); "
                             f"got {len(self.control.open_loop_torque_nm)}")
        working = nw - len(self.wheels.failed)
        if self.control.null_motion and working <= 3:
            raise InputError(f"control.null_motion needs more than 3 working wheels (a null space); got {working}")
        if self.modes.initial == "detumble" and self.control.law != "open-loop" and self.sensors.mag_rate_hz <= 0:
            raise InputError("modes.initial='detumble' needs the magnetometer (sensors.mag_rate_hz > 0) for B-dot")


def load_wheel_scenario(source: Any = None, overrides: Any = None) -> WheelScenario:
    """A :class:`WheelScenario` from a TOML file path or a mapping (unknown keys are errors).

    A partial file is completed from ``WheelScenario()``: a table sets only the keys it names
    (``[orbit] altitude_km = 600.0`` keeps the reference's sun-synchronous inclination);
    ``adcskit scenario --wheels`` prints the full default.

    Examples
    --------
    >>> sc = load_wheel_scenario({"sim": {"t_final": 60.0, "metrics_from_s": 30.0}})
    >>> sc.sim.t_final, sc.wheels.n
    (60.0, 4)
    """
    return _load_spec(WheelScenario, source, overrides)


# ------------------------------------------------------------------------------- results

#: Per-sample metrics: name -> (kernel slot, factor from SI). Angles in degrees, speeds in rpm.
_METRICS: dict[str, tuple[int, float]] = {
    "t_detumbled_s": (_k.M_T_DETUMBLED, 1.0),
    "t_acquired_s": (_k.M_T_ACQUIRED, 1.0),
    "final_mode": (_k.M_FINAL_MODE, 1.0),
    "pointing_mean_deg": (_k.M_POINT_MEAN, 1.0 / RAD_PER_DEG),
    "pointing_rms_deg": (_k.M_POINT_RMS, 1.0 / RAD_PER_DEG),
    "pointing_max_deg": (_k.M_POINT_MAX, 1.0 / RAD_PER_DEG),
    "pointing_fraction": (_k.M_POINT_FRAC, 1.0),
    "settling_time_s": (_k.M_SETTLE, 1.0),
    "knowledge_rms_deg": (_k.M_KNOW_RMS, 1.0 / RAD_PER_DEG),
    "final_rate_deg_s": (_k.M_FINAL_RATE, 1.0 / RAD_PER_DEG),
    "max_rate_deg_s": (_k.M_MAX_RATE_WIN, 1.0 / RAD_PER_DEG),
    "max_wheel_speed_rpm": (_k.M_MAX_SPEED, 1.0 / _RPM),
    "max_wheel_momentum_nms": (_k.M_MAX_HW, 1.0),
    "final_wheel_momentum_nms": (_k.M_FINAL_HW, 1.0),
    "max_dipole_am2": (_k.M_MAX_DIPOLE, 1.0),
    "momentum_drift_rel": (_k.M_H_DRIFT, 1.0),
    "final_sun_angle_deg": (_k.M_SUN_FINAL, 1.0 / RAD_PER_DEG),
}
#: Metrics added when the scenario has unloading thrusters (``thruster_unloading``).
_UNLOAD_METRICS: dict[str, tuple[int, float]] = {
    "propellant_kg": (_k.M_PROPELLANT, 1.0),
    "thruster_impulse_ns": (_k.M_IMPULSE, 1.0),
    "thruster_on_time_s": (_k.M_ON_TIME, 1.0),
    "unload_count": (_k.M_UNLOADS, 1.0),
    "unload_time_s": (_k.M_UNLOAD_TIME, 1.0),
}
#: Names of the per-sample metrics of :class:`WheelSimulationResult` (units in the names).
WHEEL_METRIC_NAMES: tuple[str, ...] = tuple(_METRICS)
#: Names of the metrics added with unloading thrusters (:class:`ThrusterUnloadSpec`).
WHEEL_UNLOAD_METRIC_NAMES: tuple[str, ...] = tuple(_UNLOAD_METRICS)
#: Metrics added with the attitude filter (``estimator``).
_FILTER_METRICS: dict[str, tuple[int, float]] = {
    "nees_mean": (_k.M_NEES, 1.0),
    "nees_count": (_k.M_NEES_N, 1.0),
}
#: Names of the metrics added with the attitude filter (``WheelScenario.estimator``).
WHEEL_FILTER_METRIC_NAMES: tuple[str, ...] = tuple(_FILTER_METRICS)
#: Metrics computed over ``[sim.metrics_from_s, t_final]`` (the others cover the whole run).
_WINDOWED = ("pointing_mean_deg", "pointing_rms_deg", "pointing_max_deg", "pointing_fraction",
             "knowledge_rms_deg", "max_rate_deg_s", "nees_mean", "nees_count")


def _channels(nw: int, thrusters: bool = False, filt: bool = False) -> tuple[str, ...]:
    thr = ("thruster_torque_x", "thruster_torque_y", "thruster_torque_z", "thruster_impulse_eci_x",
           "thruster_impulse_eci_y", "thruster_impulse_eci_z", "propellant") if thrusters else ()
    return (("error", "omega_x", "omega_y", "omega_z", "rate", "h_body_x", "h_body_y", "h_body_z", "h_wheels",
             "H_eci_x", "H_eci_y", "H_eci_z", "dipole_x", "dipole_y", "dipole_z", "mode", "knowledge_error")
            + tuple(f"speed_{j}" for j in range(nw)) + tuple(f"h_{j}" for j in range(nw)) + thr
            + (("nees",) if filt else ()))


@dataclass(frozen=True, slots=True, kw_only=True)
class WheelSimulationResult:
    """Outcome of :func:`simulate_wheels`.

    Attributes
    ----------
    metrics : dict of str to ndarray (N,)
        :data:`WHEEL_METRIC_NAMES`: ``t_detumbled_s`` / ``t_acquired_s`` (mode switches; NaN:
        never), ``final_mode`` (index into :data:`MODE_NAMES`), pointing error to the
        pointing target over ``[metrics_from_s, end]`` *while in the pointing mode*
        (``pointing_mean_deg``, ``pointing_rms_deg``, ``pointing_max_deg``; NaN when never
        pointing there) and the fraction of that window spent pointing
        (``pointing_fraction``), ``settling_time_s`` (last time the pointing error exceeded
        ``settle_band_deg`` while pointing; NaN if not pointing at the end),
        ``knowledge_rms_deg``, ``final_rate_deg_s``, ``max_rate_deg_s`` (window),
        ``max_wheel_speed_rpm``, ``max_wheel_momentum_nms`` and ``final_wheel_momentum_nms``
        (``|A h|``), ``max_dipole_am2`` (largest commanded dipole norm),
        ``momentum_drift_rel`` (max ``|H_eci(t) - H_eci(0)| / |H_eci(0)|``),
        ``final_sun_angle_deg``. With unloading thrusters (``thruster_unloading``) also
        :data:`WHEEL_UNLOAD_METRIC_NAMES`: ``propellant_kg`` (``sum mdot t_on``, i.e. the
        total impulse over ``Isp g0 = f_max / mdot``), ``thruster_impulse_ns`` (total impulse
        ``sum f_max t_on``), ``thruster_on_time_s``, ``unload_count`` (unloading episodes
        started) and ``unload_time_s`` (time spent unloading). With the filter
        (``estimator``) also :data:`WHEEL_FILTER_METRIC_NAMES`: ``nees_mean``, the mean over
        the control periods of ``[metrics_from_s, end]`` of the filter's normalised
        estimation error squared ``e^T P^-1 e`` (``e`` = attitude and gyro-bias errors; 6 for a
        consistent filter), and ``nees_count``, the number of those epochs.
    t : ndarray (R,) or None, s
    trace : ndarray (N, R, C) or None
        Channels :attr:`channels`, SI (rad, rad/s, N m s, A m^2): ``error`` is the pointing
        error in ``point``, the sun-axis angle in ``sun`` and NaN in ``detumble``; ``mode``
        the mode index; ``speed_j`` wheel speeds relative to the body, ``h_j`` wheel momenta;
        with unloading thrusters also ``thruster_torque_x/y/z`` (body, N m, over the step
        that ends at ``t``), ``thruster_impulse_eci_x/y/z`` (their angular impulse since
        t = 0 in ECI, N m s) and ``propellant`` (kg since t = 0); with the filter ``nees`` (the
        last NEES computed in the window; NaN before).
    channels : tuple of str
    parameters : dict of str to ndarray
        Dispersed per-sample parameters (inertia, axes, initial state, gyro bias, noise scale).
    seeds : ndarray (N,) uint64
    n_samples, n_steps : int
    sample_steps_per_s : float
        ``n_samples * n_steps`` / kernel wall time.
    runtime_s : float
    metrics_from_s : float, s
    success : bool
        Every sample's final rate finite and, with a mode sequence that starts before
        ``point``, every sample pointing at the end.
    message : str
    n_chunks : int
        Tasks the samples were split into (``chunk_size``).
    n_resumed : int
        Chunks loaded from the campaign ``directory`` instead of computed.
    backend : {"cpu", "cuda"}
        The target that ran the samples.

    Examples
    --------
    >>> from adcskit.simulation import ModeSpec, SimSpec, WheelScenario, simulate_wheels
    >>> sc = WheelScenario(modes=ModeSpec(initial="point", sequence=False),
    ...                    sim=SimSpec(dt=0.1, t_final=5.0, metrics_from_s=1.0))
    >>> res = simulate_wheels(sc, n_samples=2, rng=1)
    >>> res.success, res.metrics["pointing_max_deg"].shape
    (True, (2,))
    """

    metrics: dict[str, np.ndarray]
    t: np.ndarray | None
    trace: np.ndarray | None
    channels: tuple[str, ...]
    parameters: dict[str, np.ndarray]
    seeds: np.ndarray
    n_samples: int
    n_steps: int
    sample_steps_per_s: float
    runtime_s: float
    metrics_from_s: float
    success: bool
    message: str
    n_chunks: int = 1
    n_resumed: int = 0
    backend: str = "cpu"

    def summary(self) -> dict[str, dict[str, float]]:
        """Mean, 5/50/95/99 % quantiles, max and NaN count of every metric."""
        out: dict[str, dict[str, float]] = {}
        for name, v in self.metrics.items():
            f = v[np.isfinite(v)]
            q = np.quantile(f, [0.05, 0.5, 0.95, 0.99]) if f.size else [math.nan] * 4
            out[name] = {"mean": float(np.mean(f)) if f.size else math.nan, "p05": float(q[0]),
                         "p50": float(q[1]), "p95": float(q[2]), "p99": float(q[3]),
                         "max": float(np.max(f)) if f.size else math.nan, "n_nan": int(v.size - f.size)}
        return out

    def check_requirements(self, requirements: Any, **kw: Any) -> Any:
        """A requirement table on :attr:`metrics` (:func:`adcskit.uncertainty.check_requirements`),
        with the windowed metrics declared over ``[metrics_from_s, end]``.

        Examples
        --------
        >>> from adcskit.simulation import ModeSpec, SimSpec, WheelScenario, simulate_wheels
        >>> sc = WheelScenario(modes=ModeSpec(initial="point", sequence=False),
        ...                    sim=SimSpec(dt=0.1, t_final=5.0, metrics_from_s=1.0))
        >>> table = simulate_wheels(sc, n_samples=4, rng=1).check_requirements(["max_rate_deg_s max <= 10"])
        >>> table.rows[0].outcome
        'met'
        """
        from adcskit.uncertainty import check_requirements

        windows = {name: self.metrics_from_s for name in _WINDOWED}
        return check_requirements(requirements, self.metrics, metrics_from_s=windows, **kw)

    def envelope(self, channel: str) -> dict[str, np.ndarray]:
        """Monte-Carlo envelope of a recorded channel over time: median, 5/95 % and 1/99 %
        bands, and the worst sample (largest peak ``|value|``; NaN samples ignored).

        Returns
        -------
        dict
            ``t`` (R,), ``p50``, ``p05``, ``p95``, ``p01``, ``p99`` (R,) in the channel's SI
            unit, ``worst`` (R,) the worst sample's trace and ``worst_index`` (its sample).

        Examples
        --------
        >>> from adcskit.simulation import ModeSpec, SimSpec, WheelScenario, simulate_wheels
        >>> sc = WheelScenario(modes=ModeSpec(initial="point", sequence=False),
        ...                    sim=SimSpec(dt=0.1, t_final=5.0, metrics_from_s=1.0))
        >>> env = simulate_wheels(sc, n_samples=8, rng=1, record=True).envelope("rate")
        >>> env["p50"].shape, bool((env["p05"] <= env["p95"]).all())
        ((6,), True)
        """
        if self.trace is None or self.t is None:
            raise InputError("envelope needs the traces: run simulate_wheels(..., record=True)")
        check_choice("channel", channel, self.channels)
        x = self.trace[:, :, self.channels.index(channel)]
        out: dict[str, np.ndarray] = {"t": self.t.copy()}
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN columns (e.g. error in detumble)
            q = np.nanquantile(x, [0.5, 0.05, 0.95, 0.01, 0.99], axis=0)
            peak = np.nanmax(np.abs(x), axis=1)
        for name, row in zip(("p50", "p05", "p95", "p01", "p99"), q):
            out[name] = row
        worst = int(np.nanargmax(np.where(np.isfinite(peak), peak, -np.inf)))
        out["worst"] = x[worst].copy()
        out["worst_index"] = np.asarray(worst)
        return out

    def to_dict(self) -> dict[str, Any]:
        return {"summary": self.summary(), "n_samples": self.n_samples, "n_steps": self.n_steps,
                "sample_steps_per_s": self.sample_steps_per_s, "runtime_s": self.runtime_s,
                "metrics_from_s": self.metrics_from_s, "success": self.success, "message": self.message}


#: Channels drawn by :func:`wheel_envelope_figure` by default, with their display unit and factor.
WHEEL_ENVELOPE_CHANNELS: dict[str, tuple[str, float]] = {
    "error": ("pointing / sun error, deg", 1.0 / RAD_PER_DEG),
    "rate": ("body rate, deg/s", 1.0 / RAD_PER_DEG),
    "speed_0": ("wheel 0 speed, rpm", 1.0 / _RPM),
    "h_wheels": ("wheel momentum |A h|, N m s", 1.0),
    "dipole_x": ("dipole x, A m^2", 1.0),
}


def wheel_envelope_figure(result: WheelSimulationResult, channels: Any = None) -> Any:
    """Monte-Carlo envelope figure: median, p5-p95 and p1-p99 bands over time and the worst
    sample, one panel per channel (a :class:`matplotlib.figure.Figure`, no pyplot).

    Parameters
    ----------
    result : WheelSimulationResult
        From ``simulate_wheels(..., record=True)``.
    channels : sequence of str, optional
        Trace channels (default: attitude error, rate, wheel 0 speed, wheel momentum, dipole x).

    Examples
    --------
    >>> from adcskit.simulation import ModeSpec, SimSpec, WheelScenario, simulate_wheels, wheel_envelope_figure
    >>> sc = WheelScenario(modes=ModeSpec(initial="point", sequence=False),
    ...                    sim=SimSpec(dt=0.1, t_final=5.0, metrics_from_s=1.0))
    >>> fig = wheel_envelope_figure(simulate_wheels(sc, n_samples=8, rng=1, record=True), ["rate"])
    >>> len(fig.axes)
    1
    """
    from matplotlib.figure import Figure

    if not isinstance(result, WheelSimulationResult):
        raise InputTypeError(f"result must be a WheelSimulationResult; got {type(result).__name__}")
    if channels is None:
        names = list(WHEEL_ENVELOPE_CHANNELS)
    elif isinstance(channels, (list, tuple)) and channels and all(isinstance(c, str) for c in channels):
        names = list(channels)
    else:
        raise InputTypeError(f"channels must be a non-empty list of channel names (str); got {short_repr(channels)}")
    fig = Figure(figsize=(7.0, 2.2 * len(names)), layout="constrained")
    axes = fig.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]
    for ax, name in zip(axes, names):
        env = result.envelope(name)
        label, f = WHEEL_ENVELOPE_CHANNELS.get(name, (name + " (SI)", 1.0))
        t = env["t"]
        ax.fill_between(t, env["p01"] * f, env["p99"] * f, color="C0", alpha=0.2, lw=0, label="p1-p99")
        ax.fill_between(t, env["p05"] * f, env["p95"] * f, color="C0", alpha=0.4, lw=0, label="p5-p95")
        ax.plot(t, env["p50"] * f, color="C0", lw=1.2, label="median")
        ax.plot(t, env["worst"] * f, color="C3", lw=0.8, label=f"worst (sample {int(env['worst_index'])})")
        ax.set_ylabel(label)
    axes[0].legend(loc="upper right", fontsize="small")
    axes[-1].set_xlabel("time, s")
    fig.suptitle(f"{result.n_samples} samples")
    return fig


# ------------------------------------------------------------------------------- set-up


def _lvlh_quaternions(r: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Quaternions (scalar last, ``A(q)`` ECI -> LVLH) of z nadir, y opposite the orbit normal."""
    z = -r / np.linalg.norm(r, axis=1, keepdims=True)
    hvec = np.cross(r, v)
    y = -hvec / np.linalg.norm(hvec, axis=1, keepdims=True)
    x = np.cross(y, z)
    A = np.stack([x, y, z], axis=1)  # rows: LVLH axes in ECI -> A maps ECI to LVLH
    q = Rotation.from_matrix(A).inv().as_quat()  # from_quat(q).inv() has matrix A(q)
    return q * np.where(q[:, 3:] < 0, -1.0, 1.0)


def _rotvec_quat(rv: np.ndarray) -> np.ndarray:
    """Quaternion ``[sin(a/2) e, cos(a/2)]`` of rotation vectors, scalar last, ``q4 >= 0``
    (as :func:`adcskit.simulation.reference_profile`: ``A(q)`` is the body rotated by ``rv``)."""
    q = Rotation.from_rotvec(np.atleast_2d(rv)).as_quat()
    return q * np.where(q[:, 3:] < 0, -1.0, 1.0)


def _environment(sc: WheelScenario, n_steps: int) -> tuple[np.ndarray, float]:
    """ENV (K+1, 14) and the orbit rate (rad/s)."""
    from adcskit.environment import circular_orbit, in_shadow, magnetic_field, sun_direction

    o = sc.orbit
    dt = sc.sim.dt
    t = np.arange(n_steps + 1) * dt
    alt = o.altitude_km * 1e3
    st = circular_orbit(alt, o.inclination_deg * RAD_PER_DEG, o.raan_deg * RAD_PER_DEG, o.arg_lat0_deg * RAD_PER_DEG, t,
                        epoch=np.datetime64(o.epoch))
    r = np.asarray(st.r)
    v = np.asarray(st.v)
    env = np.zeros((n_steps + 1, _k.N_ENV))
    env[:, _k.E_R:_k.E_R + 3] = r / np.linalg.norm(r, axis=1, keepdims=True)
    stride = max(1, int(round(10.0 / dt)))  # field, sun and shadow every ~10 s, interpolated
    idx = np.unique(np.r_[np.arange(0, n_steps + 1, stride), n_steps])
    times = st.times
    sun = np.asarray(sun_direction(times[idx]))
    lit = ~np.asarray(in_shadow(r[idx], times[idx]), dtype=bool)
    mag = np.asarray(magnetic_field(r[idx], times[idx], model=o.magnetic_model))  # T
    for j in range(3):
        env[:, _k.E_SUN + j] = np.interp(t, t[idx], sun[:, j])
        env[:, _k.E_B + j] = np.interp(t, t[idx], mag[:, j])
    env[:, _k.E_SUN:_k.E_SUN + 3] /= np.linalg.norm(env[:, _k.E_SUN:_k.E_SUN + 3], axis=1, keepdims=True)
    env[:, _k.E_LIT] = np.interp(t, t[idx], lit.astype(float)) > 0.5
    if sc.modes.pointing == "nadir":
        env[:, _k.E_QREF:_k.E_QREF + 4] = _lvlh_quaternions(r, v)
    else:
        env[:, _k.E_QREF:_k.E_QREF + 4] = _rotvec_quat(np.asarray(sc.modes.target_rotvec_deg) * RAD_PER_DEG)
    return env, math.sqrt(_MU / (_RE + alt) ** 3)


def _draw(sc: WheelScenario, n: int, gen: np.random.Generator) -> dict[str, np.ndarray]:
    from adcskit.uncertainty import Gaussian, TruncatedGaussian, latin_hypercube

    d = sc.dispersions
    dists: dict[str, Any] = {}
    for a in range(3):
        dists[f"inertia_{a}"] = TruncatedGaussian(mean=1.0, std=d.inertia_rel, low=0.1, high=1.9)
        dists[f"rate_{a}"] = Gaussian(mean=sc.initial_rate_deg_s[a] * RAD_PER_DEG, std=d.initial_rate_deg_s * RAD_PER_DEG)
        dists[f"att_{a}"] = Gaussian(mean=0.0, std=d.initial_attitude_deg * RAD_PER_DEG)
        dists[f"bias_{a}"] = Gaussian(mean=0.0, std=sc.sensors.gyro_bias0_deg_h * RAD_PER_DEG / 3600.0)
    for j in range(sc.wheels.n):
        for a in range(3):
            dists[f"mis_{j}_{a}"] = Gaussian(mean=0.0, std=d.wheel_misalignment_deg * RAD_PER_DEG)
    dists["noise"] = TruncatedGaussian(mean=1.0, std=d.sensor_noise_rel, low=0.0, high=3.0)
    if d.sampling == "lhs":
        draws = latin_hypercube(dists, n, gen)
    else:
        u = np.clip(gen.random((n, len(dists))), 1e-12, 1 - 1e-12)
        draws = {k: np.asarray(v.ppf(u[:, j]), float) for j, (k, v) in enumerate(dists.items())}
    if d.initial_attitude == "random":  # uniform on SO(3): normalised 4-D Gaussians
        qr = gen.standard_normal((n, 4))
        draws["random_q"] = qr / np.linalg.norm(qr, axis=1, keepdims=True)
    return draws


def _allocation(sc: WheelScenario) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """PINV (n_w, 3), null projector (n_w, n_w) and the null-space bias h* (n_w,) of the working wheels."""
    w = sc.wheels
    A = w.axis_matrix()
    nw = w.n
    work = np.ones(nw, bool)
    work[list(w.failed)] = False
    cols = np.flatnonzero(work)
    Aw = A[:, cols]
    pinv = np.zeros((nw, 3))
    pinv[cols] = np.linalg.pinv(Aw)  # SVD-based Moore-Penrose inverse of a 3 x k matrix
    nullp = np.zeros((nw, nw))
    nullp[np.ix_(cols, cols)] = np.eye(cols.size) - pinv[cols] @ Aw
    hstar = np.zeros(nw)
    if cols.size > 3:
        _, _, vt = np.linalg.svd(Aw)
        nvec = vt[-1]  # a unit vector of the null space
        jw = np.asarray(w.inertia_kgm2)[cols]
        small = np.max(np.abs(nvec)) * 1e-6
        scale = np.min(jw * sc.control.null_speed_rpm * _RPM / np.maximum(np.abs(nvec), small))
        hstar[cols] = nvec * scale
    return pinv, nullp, hstar


def _on_steps(duty: float, hc: int) -> int:
    """Steps per control period with the rods on: ``floor(duty hc)``, at least 1, and at most
    ``hc - 1`` when ``duty < 1`` (an off step is left for the magnetometer)."""
    if duty >= 1.0:
        return hc
    return max(1, min(hc - 1, int(math.floor(duty * hc + 1e-9))))


def _prepare(sc: WheelScenario, n: int, gen: np.random.Generator) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    dt = sc.sim.dt
    n_steps = int(round(sc.sim.t_final / dt))
    w = sc.wheels
    nw = w.n

    def hrate(rate: float) -> int:
        return 0 if rate <= 0 else int(round(1.0 / (rate * dt)))

    env, n_orb = _environment(sc, n_steps)
    draws = _draw(sc, n, gen)
    J0 = sc.spacecraft.matrix()
    scale = np.stack([draws[f"inertia_{a}"] for a in range(3)], axis=1)
    if np.count_nonzero(J0 - np.diag(np.diag(J0))) == 0:
        lam0, V = np.diag(J0).copy(), np.eye(3)
    else:
        lam0, V = np.linalg.eigh(J0)
    lam = lam0[None] * scale
    J = np.einsum("ab,sb,cb->sac", V, lam, V)
    J = 0.5 * (J + np.swapaxes(J, 1, 2))
    P = np.zeros((n, _k.N_PARAMS))
    P[:, _k.P_J:_k.P_J + 9] = J.reshape(n, 9)
    P[:, _k.P_JI:_k.P_JI + 9] = np.linalg.inv(J).reshape(n, 9)
    att = np.stack([draws[f"att_{a}"] for a in range(3)], axis=1)
    if sc.dispersions.initial_attitude == "random":
        q0 = draws["random_q"] * np.where(draws["random_q"][:, 3:] < 0, -1.0, 1.0)
    else:
        q_nom = Rotation.from_quat(_rotvec_quat(np.asarray(sc.initial_rotvec_deg) * RAD_PER_DEG)[0])
        q0 = (q_nom * Rotation.from_quat(_rotvec_quat(att))).as_quat()  # A(q) = A(dq) A(q_nom)
        q0 *= np.where(q0[:, 3:] < 0, -1.0, 1.0)
    P[:, _k.P_Q0:_k.P_Q0 + 4] = q0
    P[:, _k.P_W0:_k.P_W0 + 3] = np.stack([draws[f"rate_{a}"] for a in range(3)], axis=1)
    P[:, _k.P_BIAS:_k.P_BIAS + 3] = np.stack([draws[f"bias_{a}"] for a in range(3)], axis=1)
    P[:, _k.P_NS] = draws["noise"]
    P[:, _k.P_D0:_k.P_D0 + 3] = np.asarray(sc.disturbance.constant)
    P[:, _k.P_DAMP:_k.P_DAMP + 3] = np.asarray(sc.disturbance.amplitude)
    P[:, _k.P_DPH:_k.P_DPH + 3] = np.asarray(sc.disturbance.phase_deg) * RAD_PER_DEG
    A_nom = w.axis_matrix()
    mis = np.stack([np.stack([draws[f"mis_{j}_{a}"] for a in range(3)], axis=1) for j in range(nw)], axis=1)
    R = Rotation.from_rotvec(mis.reshape(-1, 3)).as_matrix().reshape(n, nw, 3, 3)
    AX = np.ascontiguousarray(np.einsum("sjab,bj->saj", R, A_nom))  # (n, 3, n_w) true axes
    pinv, nullp, hstar = _allocation(sc)
    jw = np.asarray(w.inertia_kgm2, dtype=float)
    wpar = np.zeros((nw, _k.N_WPAR))
    wpar[:, _k.W_JW] = jw
    wpar[list(w.failed), _k.W_FAILED] = 1.0
    wpar[:, _k.W_OMEGA0] = np.asarray(w.initial_speed_rpm) * _RPM
    if sc.control.law == "open-loop":
        wpar[:, _k.W_OPEN] = sc.control.open_loop_torque_nm
    C = np.zeros(_k.N_COEFS)
    C[_k.DT] = dt
    C[_k.N_STEPS] = n_steps
    hc = int(round(sc.control.period_s / dt))
    C[_k.H_CTRL] = hc
    C[_k.H_GYRO] = hrate(sc.sensors.gyro_rate_hz)
    C[_k.H_SUN] = hrate(sc.sensors.sun_rate_hz)
    C[_k.H_MAG] = hrate(sc.sensors.mag_rate_hz)
    C[_k.H_ST] = hrate(sc.sensors.star_tracker_rate_hz)
    C[_k.NW] = nw
    C[_k.N2ORB] = n_orb**2 if sc.orbit.gravity_gradient else 0.0
    per = sc.disturbance.period_s if sc.disturbance.period_s > 0 else 2 * math.pi / n_orb
    C[_k.D_OMEGA] = 2 * math.pi / per
    C[_k.SIG_SUN] = sc.sensors.sun_noise_deg * RAD_PER_DEG
    C[_k.SIG_MAG] = sc.sensors.mag_noise_deg * RAD_PER_DEG
    C[_k.SIG_ST] = sc.sensors.star_tracker_noise_arcsec * _ARCSEC
    C[_k.SIG_V] = sc.sensors.gyro_arw
    C[_k.SIG_U] = sc.sensors.gyro_rrw
    c = sc.control
    C[_k.LAW] = {"pd": _k.LAW_PD, "wie": _k.LAW_WIE, "open-loop": _k.LAW_OPEN}[c.law]
    C[_k.K_GAIN] = c.bandwidth_rad_s**2
    C[_k.C_GAIN] = 2.0 * c.damping * c.bandwidth_rad_s
    C[_k.RATE_MAX] = c.rate_limit_deg_s * RAD_PER_DEG
    C[_k.TAU_MAX] = w.max_torque_nm
    C[_k.OMEGA_MAX] = w.max_speed_rpm * _RPM
    C[_k.C_VISC] = w.viscous_nms
    C[_k.C_COUL] = w.coulomb_nm
    C[_k.TQ_QUANT] = w.torque_quantum_nm
    C[_k.TQ_NOISE] = w.torque_noise_nm
    C[_k.NULL_GAIN] = c.null_gain if c.null_motion else 0.0
    m = sc.magnetorquers
    C[_k.MTQ_MAX] = m.max_dipole_am2
    C[_k.MTQ_ON_STEPS] = _on_steps(m.duty, hc)
    C[_k.MAG_MODE] = _k.MAG_BLANK if m.magnetometer == "blank" else _k.MAG_CORRUPT
    C[_k.MAG_COUPLING] = m.coupling_t_per_am2
    C[_k.BDOT_GAIN] = m.bdot_gain
    C[_k.UNLOAD_GAIN] = m.unload_gain
    md = sc.modes
    C[_k.MODE0] = MODE_NAMES.index(md.initial)
    C[_k.SEQUENCE] = 1.0 if md.sequence else 0.0
    C[_k.RATE_THR] = md.rate_threshold_deg_s * RAD_PER_DEG
    C[_k.DWELL_STEPS] = int(round(md.dwell_s / dt))
    C[_k.SUN_THR_COS] = math.cos(md.sun_threshold_deg * RAD_PER_DEG)
    C[_k.SUN_AX0:_k.SUN_AX2 + 1] = md.sun_axis
    C[_k.POINT_KIND] = _k.POINT_NADIR if md.pointing == "nadir" else _k.POINT_INERTIAL
    C[_k.ORBIT_RATE] = n_orb
    C[_k.K_WIN] = int(math.ceil(sc.sim.metrics_from_s / dt - 1e-9))
    C[_k.SETTLE_BAND] = sc.sim.settle_band_deg * RAD_PER_DEG
    C[_k.REC_EVERY] = sc.sim.record_every
    C[_k.JN0:_k.JN0 + 9] = J0.reshape(9)
    if c.law == "open-loop":
        C[_k.OL_DIP0:_k.OL_DIP0 + 3] = c.open_loop_dipole_am2
    thr = np.zeros((_k.N_THR_ROWS, 0))
    tu = sc.thruster_unloading
    if tu is not None:
        th = tu.thrusters
        thr = np.zeros((_k.N_THR_ROWS, th.n))
        thr[_k.T_A:_k.T_A + 3] = th.torque_matrix()
        thr[_k.T_FMAX] = th.f_max
        thr[_k.T_MASK] = 1.0
        thr[_k.T_FAILED, list(th.failed)] = 1.0
        if th.failure_known:
            thr[_k.T_MASK, list(th.failed)] = 0.0
        thr[_k.T_MDOT] = th.mdot
        thr[_k.T_TMIN] = th.t_min
        C[_k.NT] = th.n
        C[_k.UNL_START] = tu.start_nms
        C[_k.UNL_STOP] = tu.stop_nms
        C[_k.UNL_TORQUE] = tu.torque_nm
        C[_k.UNL_EPS] = 1e-12  # as the thruster loop's allocator (core.py RPI_EPS)
    est = sc.estimator
    if est is not None:
        C[_k.EST_ON] = 1.0
        C[_k.EST_SIG0] = est.init_error_deg * RAD_PER_DEG
        C[_k.EST_SIGB0] = sc.sensors.gyro_bias0_deg_h * RAD_PER_DEG / 3600.0
        C[_k.EST_UW] = est.underweight
    shared = dict(C=C, ENV=env, AXN=np.ascontiguousarray(A_nom), PINV=pinv, NULLP=nullp, HSTAR=hstar,
                  WPAR=wpar, JW=jw, THR=thr, n_steps=n_steps)
    params = {"inertia": J, "inertia_physical": _triangle_ok(lam), "wheel_axes": AX, "initial_quaternion": q0,
              "initial_rate": P[:, _k.P_W0:_k.P_W0 + 3].copy(), "gyro_bias": P[:, _k.P_BIAS:_k.P_BIAS + 3].copy(),
              "sensor_noise_scale": P[:, _k.P_NS].copy(), "null_momentum": hstar}
    return {"shared": shared, "P": P, "AX": AX}, params


def _run_wheel_block(task: tuple[np.ndarray, np.ndarray, np.ndarray, bool], shared: dict[str, Any]) -> dict[str, Any]:
    """Run one chunk of samples through the kernel (module level: picklable for executors). The
    kernel's arrays are allocated as :data:`adcskit.simulation._wheel_kernels.ARGS` declares."""
    P, AX, seeds, record = task
    C = shared["C"]
    n_rec = shared["n_steps"] // int(C[_k.REC_EVERY]) + 1 if record else 0
    dims = _k.Dims(n=P.shape[0], nw=shared["JW"].shape[0], nt=shared["THR"].shape[1], n_rec=n_rec,
                   filt=bool(C[_k.EST_ON] > 0.0))
    A = _k.allocate_arrays({**shared, "P": P, "AX": AX, "SEEDS": seeds}, dims)
    t0 = time.perf_counter()
    run = _k.run_wheels_cuda if shared.get("backend") == "cuda" else _k.run_wheels
    run(A)
    return {"out": A.OUT, "rec": A.REC if record else None, "wall": time.perf_counter() - t0}


def simulate_wheels(scenario: WheelScenario, n_samples: int = 1, rng: Any = None, executor: Any = None, *,
                    record: bool = False, chunk_size: int | None = None,
                    directory: Any = None, backend: str = "cpu",
                    progress: bool | None = None) -> WheelSimulationResult:
    """Run ``n_samples`` Monte-Carlo samples of a wheel + magnetorquer scenario.

    The samples are split into chunks (tasks of :func:`adcskit.uncertainty.run_campaign`) run
    on ``executor`` (with a progress display inside the ``adcskit`` CLI; an interrupted run
    keeps its finished chunks in ``directory`` and a re-run resumes from them); inside a
    chunk they run in blocks on ``numba.get_num_threads()`` threads, each block one call of
    the compiled, GIL-free kernel. A sample's result depends only on its parameters and its
    64-bit noise seed, so it does not depend on the executor, the chunks, the thread count
    or the blocks: bit-identical results whatever the split. With ``backend="cuda"`` one CUDA
    thread per sample runs the same per-sample source (all samples in one chunk by default).

    Parameters
    ----------
    scenario : WheelScenario
    n_samples : int
    rng : int, SeedSequence or Generator, optional
        Randomness of the dispersions and per-sample seeds (``None`` -> seed 0).
    executor : spec or Executor, optional
        ``serial`` (default: one process, its cores through numba threads),
        ``processes[:N]``, ``dask-local[:N]``, ``dask://HOST:PORT``
        (:func:`adcskit.uncertainty.make_executor`).
    record : bool
        Return the time histories (every ``scenario.sim.record_every`` steps).
    chunk_size : int, optional
        Samples per task (default: all samples in 8 chunks at most, >= 64 each).
    directory : path, optional
        Campaign directory: finished chunks are kept (written atomically) and a re-run with
        the same scenario, samples and ``rng`` resumes from them.
    backend : {"cpu", "cuda", "auto"}
        ``"cpu"`` (default): numba on the CPU cores. ``"cuda"``: the same per-sample function
        compiled for an NVIDIA GPU (one thread per sample; needs the ``gpu`` extra and a
        device). ``"auto"``: CUDA when a real device is usable, else the CPU. On a device the
        results agree with the CPU's to rounding (the GPU contracts ``a * b + c`` into fused
        multiply-adds); under numba's CUDA simulator they are bit-identical.
    progress : bool or None
        Progress bar over the chunks on the console: ``None`` (default) at a terminal or in a
        notebook only, ``False`` never, ``True`` always; it appears once the run has taken
        :data:`adcskit._progress.AUTO_DELAY_S` (3 s) (as :func:`adcskit.simulation.simulate`).

    Returns
    -------
    WheelSimulationResult

    Raises
    ------
    SolverError
        ``backend="cuda"`` without numba-cuda or without a visible device (the message names
        the ``gpu`` extra).

    Notes
    -----
    The first call in a fresh installation compiles the kernel (about 12 s of CPU; cached on
    disk afterwards); the CUDA kernel compiles on its first use in a process (not cached).

    Examples
    --------
    >>> from adcskit.simulation import ModeSpec, SimSpec, WheelScenario, simulate_wheels
    >>> sc = WheelScenario(modes=ModeSpec(initial="point", sequence=False),
    ...                    sim=SimSpec(dt=0.1, t_final=5.0, metrics_from_s=1.0))
    >>> res = simulate_wheels(sc, n_samples=3, rng=0, record=True)
    >>> res.trace.shape[0], res.channels[:2], res.metrics["final_mode"].tolist()
    (3, ('error', 'omega_x'), [2.0, 2.0, 2.0])

    References
    ----------
    Markley & Crassidis 2014, §3.3.5; Wie 2008, §7.3; Stickler & Alfriend 1976; Camillo &
    Markley 1980 (see :mod:`adcskit.simulation.wheels`).
    """
    if not isinstance(scenario, WheelScenario):
        raise InputTypeError(f"scenario must be a WheelScenario; got {type(scenario).__name__}")
    n_samples = check_int("n_samples", n_samples, minimum=1, maximum=10_000_000)
    record = check_flag("record", record)
    progress = progress_flag(progress)
    target = resolve_backend(backend)
    if isinstance(rng, np.random.SeedSequence):
        rng = np.random.SeedSequence(rng.entropy, spawn_key=rng.spawn_key, pool_size=rng.pool_size,
                                     n_children_spawned=rng.n_children_spawned)
    if chunk_size is not None:
        chunk_size = check_int("chunk_size", chunk_size, minimum=1)
    gen = as_rng(rng)
    t_start = time.perf_counter()
    prep, params = _prepare(scenario, n_samples, gen)
    seeds = np.random.SeedSequence(int(gen.integers(2**63))).generate_state(n_samples, dtype=np.uint64)
    sh = prep["shared"]
    nw = scenario.wheels.n
    n = n_samples
    n_steps = sh["n_steps"]
    rec_every = scenario.sim.record_every
    n_rec = n_steps // rec_every + 1
    nt = sh["THR"].shape[1]
    filt = scenario.estimator is not None
    if target == "cuda":  # the device driver chunks for itself: one campaign task by default
        sh = {**sh, "backend": "cuda"}
    if chunk_size is None:
        chunk_size = n if target == "cuda" else max(64, -(-n // 8))
    tasks = [(np.ascontiguousarray(prep["P"][lo:lo + chunk_size]), np.ascontiguousarray(prep["AX"][lo:lo + chunk_size]),
              seeds[lo:lo + chunk_size], record) for lo in range(0, n, chunk_size)]
    from adcskit.uncertainty import run_campaign

    with auto_session(progress):
        camp = run_campaign(_run_wheel_block, tasks, executor=executor, directory=directory, chunk_size=1,
                            description="wheel samples", shared=sh)
    blocks = camp.values
    OUT = np.concatenate([b["out"] for b in blocks], axis=0)
    REC = np.concatenate([b["rec"] for b in blocks], axis=0) if record else None
    wall = sum(b["wall"] for b in blocks)
    names = _METRICS | (_UNLOAD_METRICS if nt else {}) | (_FILTER_METRICS if filt else {})
    metrics = {name: OUT[:, j] * f for name, (j, f) in names.items()}
    md = scenario.modes
    finite = bool(np.all(np.isfinite(metrics["final_rate_deg_s"])))
    expect_point = md.sequence or md.initial == "point"
    n_point = int(np.count_nonzero(metrics["final_mode"] == MODE_NAMES.index("point")))
    reached = n_point == n or not expect_point or scenario.control.law == "open-loop"
    msg = (f"{n} samples x {n_steps} steps; {n_point} pointing at the end"
           + (f"; {camp.n_resumed} of {camp.n_chunks} chunk(s) resumed" if camp.n_resumed else "")
           + ("" if finite else "; some samples produced non-finite states")
           + ("" if reached else f"; {n - n_point} sample(s) did not reach the pointing mode"))
    t = np.arange(n_rec) * rec_every * scenario.sim.dt if record else None
    return WheelSimulationResult(
        metrics=metrics, t=t, trace=REC, channels=_channels(nw, nt > 0, filt), parameters=params,
        seeds=seeds, n_samples=n, n_steps=n_steps, sample_steps_per_s=n * n_steps / wall if wall > 0 else math.inf,
        runtime_s=time.perf_counter() - t_start, metrics_from_s=scenario.sim.metrics_from_s,
        success=finite and reached, message=msg, n_chunks=camp.n_chunks, n_resumed=camp.n_resumed,
        backend=target)

