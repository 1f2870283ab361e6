"""Closed-loop scenarios as data: frozen keyword-only dataclasses, loadable from TOML.

A :class:`Scenario` holds everything :func:`adcskit.simulation.simulate` needs: spacecraft,
orbit, disturbances, thrusters, sensors, estimator, guidance, controller, Monte-Carlo
dispersions and the simulation grid. Every class validates its fields in ``__post_init__``
and raises :class:`adcskit.errors.InputError` naming the field, the value and what is
allowed; :func:`load_scenario` builds one from a TOML file or a mapping through
:func:`adcskit.config.load_config` (unknown keys are errors).

Units: SI and radians inside; angles in the scenario carry ``_deg`` in their names.

Guidance attitudes are inertial (ECI): ``hold`` keeps the identity attitude, ``step`` jumps
to ``target_rotvec_deg`` at ``t_step`` and ``table`` follows a time table of quaternions
(for instance the attitude part of an :mod:`adcskit.optimal_control` solution,
:func:`adcskit.simulation.slew_table`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any, Literal

import numpy as np

from adcskit._validation import (
    as_array,
    check_choice,
    check_finite,
    check_flag_fields,
    check_int,
    check_positive,
    check_range,
    short_repr,
)
from adcskit.errors import InputError, InputTypeError

__all__ = [
    "SpacecraftSpec",
    "OrbitSpec",
    "DisturbanceSpec",
    "ThrusterSpec",
    "SensorSpec",
    "EstimatorSpec",
    "GuidanceSpec",
    "ControllerSpec",
    "DispersionSpec",
    "SimSpec",
    "Scenario",
    "load_scenario",
    "scenario_toml",
]

Vec3 = tuple[float, float, float]


def _vec(name: str, v: Any, n: int = 3) -> tuple[float, ...]:
    a = as_array(name, v).reshape(-1)  # real, finite, |x| <= 1e150: names the field otherwise
    if a.shape != (n,):
        raise InputError(f"{name} must be {n} finite numbers; got {v!r}")
    return tuple(float(x) for x in a)


def _nonneg(name: str, v: Any, unit: str = "") -> float:
    return check_positive(name, v, allow_zero=True, unit=unit)


class _Spec:
    """Shared helpers: ``replace`` and ``to_dict``."""

    __slots__ = ()

    def replace(self, **changes: Any) -> Any:
        """A copy with some fields changed (validated again)."""
        names = {f.name for f in fields(self)}  # type: ignore[arg-type]
        unknown = set(changes) - names
        if unknown:
            raise InputError(f"{type(self).__name__} has no field(s) {sorted(unknown)}; valid: {', '.join(sorted(names))}")
        return replace(self, **changes)  # type: ignore[type-var]

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for f in fields(self):  # type: ignore[arg-type]
            v = getattr(self, f.name)
            out[f.name] = v.to_dict() if hasattr(v, "to_dict") else (list(v) if isinstance(v, tuple) else v)
        return out


#: Relative rounding allowance of the inertia triangle inequality ``I_max <= (1 + rtol) (I_a + I_b)``.
_TRIANGLE_RTOL = 1e-9


def _triangle_ok(moments: Any) -> np.ndarray:
    """Whether principal moments ``(..., 3)`` satisfy the rigid-body triangle inequality.

    ``I_a <= I_b + I_c`` for every axis (Markley & Crassidis 2014, §3.3.5: the moments are
    sums of ``m (y^2 + z^2)`` etc. over the body's mass), to a relative ``_TRIANGLE_RTOL`` = 1e-9.

    Examples
    --------
    >>> bool(_triangle_ok([1218.6, 442.2, 1429.4])), bool(_triangle_ok([1.0, 1.0, 100.0]))
    (True, False)
    """
    m = np.asarray(moments, dtype=float)
    big = np.max(m, axis=-1)
    return np.asarray(big <= (np.sum(m, axis=-1) - big) * (1.0 + _TRIANGLE_RTOL))


@dataclass(frozen=True, slots=True, kw_only=True)
class SpacecraftSpec(_Spec):
    """Rigid body.

    Attributes
    ----------
    inertia : tuple of 3 or 9 floats, kg m^2
        Principal moments (diagonal) or the full row-major matrix (symmetric positive
        definite). The principal moments must satisfy the triangle inequality of a rigid body,
        ``I_a <= I_b + I_c`` for every axis (equality: a flat plate), to a relative
        1e-9 (rounding); a body such as diag(1, 1, 100) is an :class:`InputError`.
        Default: S3's GEO satellite, diag(1218.6, 442.2, 1429.4).

    Examples
    --------
    >>> from adcskit.simulation import Scenario, SpacecraftSpec
    >>> Scenario(spacecraft=SpacecraftSpec(inertia=(10.0, 12.0, 8.0))).spacecraft.inertia
    (10.0, 12.0, 8.0)
    """

    inertia: tuple[float, ...] = (1218.6, 442.2, 1429.4)

    def __post_init__(self) -> None:
        a = as_array("inertia", self.inertia).reshape(-1)
        if a.size == 3:
            J = np.diag(a)
        elif a.size == 9:
            J = a.reshape(3, 3)
        else:
            raise InputError(f"inertia must have 3 (diagonal) or 9 (matrix) entries kg m^2; got {len(a)}")
        if not np.all(np.isfinite(J)) or not np.allclose(J, J.T, rtol=1e-12, atol=0.0):
            raise InputError(f"inertia must be finite and symmetric; got {self.inertia!r}")
        ev = np.linalg.eigvalsh(J)
        if np.min(ev) <= 0.0:
            raise InputError(f"inertia must be positive definite; got eigenvalues {ev}")
        if not _triangle_ok(ev):
            raise InputError(
                "inertia must satisfy the triangle inequality of a rigid body (each principal moment "
                f"<= the sum of the other two, to a relative {_TRIANGLE_RTOL:g}); got principal moments "
                f"{np.array2string(ev, precision=6)} kg m^2: {ev[2]:.6g} > {ev[0]:.6g} + {ev[1]:.6g}"
            )
        object.__setattr__(self, "inertia", tuple(float(x) for x in a))

    def matrix(self) -> np.ndarray:
        """Inertia matrix (3, 3), kg m^2."""
        a = np.asarray(self.inertia, dtype=float)
        return np.diag(a) if a.size == 3 else a.reshape(3, 3).copy()


@dataclass(frozen=True, slots=True, kw_only=True)
class OrbitSpec(_Spec):
    """Circular orbit (closed form, :func:`adcskit.environment.circular_orbit`).

    Attributes
    ----------
    altitude_km : float, km
        Height above the Earth's equatorial radius (GEO: 35786 km; S0: 800 km).
    inclination_deg, raan_deg, arg_lat0_deg : float, deg
        Inclination, right ascension of the node, initial argument of latitude.
    epoch : str
        UTC start (ISO 8601); sets the sun direction and the field model date.
    gravity_gradient : bool
        Apply the gravity-gradient torque ``3 n^2 c x J c`` (Markley & Crassidis eq. 3.155).
    magnetic_model : {"dipole", "igrf"}
        Reference field for the magnetometer (:func:`adcskit.environment.magnetic_field`).

    Examples
    --------
    >>> from adcskit.simulation import OrbitSpec
    >>> leo = OrbitSpec(altitude_km=800.0, inclination_deg=98.6, magnetic_model="dipole")
    >>> leo.altitude_km, leo.gravity_gradient
    (800.0, True)
    """

    altitude_km: float = 35786.0
    inclination_deg: float = 0.0
    raan_deg: float = 0.0
    arg_lat0_deg: float = 0.0
    epoch: str = "2026-03-21T06:00:00"
    gravity_gradient: bool = True
    magnetic_model: Literal["dipole", "igrf"] = "dipole"

    def __post_init__(self) -> None:
        check_flag_fields(self)
        check_positive("altitude_km", self.altitude_km, unit="km")
        check_range("inclination_deg", self.inclination_deg, 0.0, 180.0, unit="deg")
        check_finite("raan_deg", self.raan_deg)
        check_finite("arg_lat0_deg", self.arg_lat0_deg)
        check_choice("magnetic_model", self.magnetic_model, ("dipole", "igrf"))


@dataclass(frozen=True, slots=True, kw_only=True)
class DisturbanceSpec(_Spec):
    """Body-frame disturbance torque ``d0 + a * sin(2 pi t / period + phase)`` per axis.

    Attributes
    ----------
    constant : 3 floats, N m
        Constant part ``d0`` per body axis.
    amplitude : 3 floats, N m
        Amplitude ``a`` of the sinusoid per body axis.
    period_s : float, s
        Period of the sinusoid; 0 means one orbit period (solar-pressure-like, S3 §2).
    phase_deg : 3 floats, deg
        Phase of the sinusoid per body axis.

    Examples
    --------
    >>> from adcskit.simulation import DisturbanceSpec
    >>> d = DisturbanceSpec(constant=(1e-5, 0.0, 0.0), amplitude=(0.0, 2e-5, 0.0), period_s=86164.0)
    >>> d.period_s
    86164.0
    """

    constant: Vec3 = (0.0, 0.0, 0.0)
    amplitude: Vec3 = (0.0, 0.0, 0.0)
    period_s: float = 0.0
    phase_deg: Vec3 = (0.0, 90.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "constant", _vec("constant", self.constant))
        object.__setattr__(self, "amplitude", _vec("amplitude", self.amplitude))
        object.__setattr__(self, "phase_deg", _vec("phase_deg", self.phase_deg))
        _nonneg("period_s", self.period_s, "s")


@dataclass(frozen=True, slots=True, kw_only=True)
class ThrusterSpec(_Spec):
    """Thruster layout (S3) and thruster model (S4).

    Attributes
    ----------
    positions : sequence of 3-vectors, m
        Mounting points in the body frame (S3 §3).
    directions : sequence of 3-vectors
        Force directions on the spacecraft (normalised here).
    f_max : float, N
        Thrust when on (S3 Table 5: 10 N).
    mdot : float, kg/s
        Mass flow when on (S3 Table 5: 3.5 g/s).
    t_min : float, s
        Minimum on-time (S3 §6: 3 ms); shorter pulses are dropped or rounded.
    tau : float, s
        Time constant of each of the two cascaded first-order lags (S4 Table 3: 0.01 s).
    delay : float, s
        Pure delay (S4 Table 3: 0.02 s).
    com : 3 floats, m
        Centre of mass.
    failed : tuple of int
        Indices of thrusters stuck off.
    failure_known : bool
        The allocator knows the failures and re-allocates without them (else it keeps
        commanding the failed thrusters, which do not fire).
    min_authority_fraction : float
        :func:`adcskit.simulation.simulate`'s per-sample feasibility test: a sample is
        controllable only if its torque authority in its weakest direction (failed thrusters
        removed, dispersed directions and thrusts) is at least this fraction of the intact
        nominal layout's (all thrusters at ``f_max``, no dispersion), in [0, 1). Default 0.05:
        a lost torque direction that only a misalignment ``delta`` tilts back into reach
        gives an authority of order ``sin(delta)`` of the nominal (0.9 % at 0.5 deg; up to
        3.2 % over the closed-loop study's 5000 Q1 samples of S3's reference layout
        missing one thruster), which the allocator (it knows only the nominal geometry) does not use;
        an intact layout dispersed by 5 % thrust and 0.5 deg keeps at least 79 % of it
        (docs/simulation.md, "Feasibility before flight"). 0 keeps only the positive-span test.
        Not used by :func:`adcskit.simulation.simulate_wheels` (unloading thrusters).

    Examples
    --------
    >>> from adcskit.simulation import ThrusterSpec
    >>> pos = ((1.0, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, 1.0), (0.0, 0.0, -1.0))
    >>> dirs = ((0.0, 1.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, 1.0), (0.0, 0.0, -1.0), (1.0, 0.0, 0.0), (-1.0, 0.0, 0.0))
    >>> ts = ThrusterSpec(positions=pos, directions=dirs, f_max=10.0, failed=(2,))   # thruster 2 stuck off
    >>> len(ts.positions), ts.failed
    (6, (2,))
    """

    positions: tuple[Vec3, ...]
    directions: tuple[Vec3, ...]
    f_max: float = 10.0
    mdot: float = 3.5e-3
    t_min: float = 3e-3
    tau: float = 0.01
    delay: float = 0.02
    com: Vec3 = (0.0, 0.0, 0.0)
    failed: tuple[int, ...] = ()
    failure_known: bool = True
    min_authority_fraction: float = 0.05

    def __post_init__(self) -> None:
        check_flag_fields(self)
        pos = as_array("positions", self.positions)
        d = as_array("directions", self.directions)
        if pos.ndim != 2 or pos.shape[1] != 3 or pos.shape[0] < 1:
            raise InputError(f"positions must be a list of n >= 1 3-vectors (m); got shape {pos.shape}")
        if d.shape != pos.shape:
            raise InputError(f"directions must have the shape of positions {pos.shape}; got {d.shape}")
        if pos.shape[0] > 32:
            raise InputError(f"at most 32 thrusters are supported; got {pos.shape[0]}")
        nrm = np.linalg.norm(d, axis=1)
        if not np.all(np.isfinite(pos)) or not np.all(np.isfinite(d)) or np.any(nrm < 1e-12):
            raise InputError("positions and directions must be finite, directions non-zero")
        d = d / nrm[:, None]
        object.__setattr__(self, "positions", tuple(tuple(float(x) for x in p) for p in pos))
        object.__setattr__(self, "directions", tuple(tuple(float(x) for x in p) for p in d))
        check_positive("f_max", self.f_max, unit="N")
        check_positive("mdot", self.mdot, unit="kg/s")
        _nonneg("t_min", self.t_min, "s")
        check_positive("tau", self.tau, unit="s")
        _nonneg("delay", self.delay, "s")
        object.__setattr__(self, "com", _vec("com", self.com))
        n = pos.shape[0]
        failed = tuple(int(j) for j in self.failed)
        for j in failed:
            if not 0 <= j < n:
                raise InputError(f"failed must hold thruster indices in [0, {n - 1}]; got {j}")
        object.__setattr__(self, "failed", tuple(sorted(set(failed))))
        if not 0.0 <= check_finite("min_authority_fraction", self.min_authority_fraction) < 1.0:
            raise InputError(f"min_authority_fraction must be in [0, 1) (a fraction of the intact layout's torque "
                             f"authority); got {self.min_authority_fraction!r}")

    @property
    def n(self) -> int:
        """Number of thrusters."""
        return len(self.positions)

    def torque_matrix(self) -> np.ndarray:
        """``A`` (3, n), N m per N: column ``j`` is ``(r_j - com) x d_j`` (S3 eq. 5)."""
        r = np.asarray(self.positions) - np.asarray(self.com)
        return np.cross(r, np.asarray(self.directions)).T

    @classmethod
    def from_thruster_set(cls, ts: Any, **kw: Any) -> ThrusterSpec:
        """From an :class:`adcskit.thrusters.ThrusterSet` (its first thruster's f_max, mdot, t_min)."""
        from adcskit.thrusters import ThrusterSet

        if not isinstance(ts, ThrusterSet):
            raise InputTypeError(f"ts must be an adcskit.thrusters.ThrusterSet; got {short_repr(ts)}")
        return cls(positions=tuple(map(tuple, ts.positions)), directions=tuple(map(tuple, ts.directions)),
                   f_max=float(ts.f_max[0]), mdot=float(ts.mdot[0]), t_min=float(ts.t_min[0]),
                   com=tuple(ts.com), **kw)

    @classmethod
    def from_torque_matrix(cls, A: Any, **kw: Any) -> ThrusterSpec:
        """A geometric layout whose torque matrix is ``A`` (3, n) (for layouts printed only as
        ``A``, e.g. S3's reference of Servidia & Sanchez Pena).

        Column ``a_j`` is realised by a direction ``d_j`` orthogonal to ``a_j`` and the
        position ``r_j = d_j x a_j`` (then ``r_j x d_j = a_j``); ``d_j`` is the unit
        component orthogonal to ``a_j`` of the body axis least aligned with it.
        """
        A = as_array("A", A, ndim=2, max_abs=1e100)  # its squared column norms stay finite
        if A.shape[0] != 3:
            raise InputError(f"A must have shape (3, n); got {A.shape}")
        pos, dirs = [], []
        for a in A.T:
            na = np.linalg.norm(a)
            if na == 0.0:
                raise InputError("A must not have a zero column (a thruster without torque)")
            e = np.eye(3)[int(np.argmin(np.abs(a)))]
            d = e - a * (a @ e) / (na * na)
            d /= np.linalg.norm(d)
            pos.append(tuple(np.cross(d, a)))
            dirs.append(tuple(d))
        return cls(positions=tuple(pos), directions=tuple(dirs), **kw)


@dataclass(frozen=True, slots=True, kw_only=True)
class SensorSpec(_Spec):
    """Sensors, each at its own rate (a rate of 0 turns it off).

    The sun sensor and magnetometer measure a unit vector ``A r + e`` (renormalised), with
    per-component errors ``e`` either Gaussian (std = ``*_noise_deg`` in rad) or uniform in
    ``[-bound, bound]`` (``noise="uniform"``: S0's bounded errors, bound = ``*_noise_deg``).
    The sun sensor gives nothing in eclipse. The gyro is Farrenkopf's model (angle random
    walk ``gyro_arw``, bias random walk ``gyro_rrw``). The optional star tracker measures
    ``delta q (x) q`` with a Gaussian rotation vector.

    Rates must be whole fractions of the gyro rate, and the gyro rate a whole fraction of
    ``1/dt``.

    Attributes
    ----------
    sun_rate_hz : float, Hz
        Sun-sensor rate (0: off).
    sun_noise_deg : float, deg
        Sun-sensor error per component: Gaussian std, or the bound with ``noise="uniform"``.
    mag_rate_hz : float, Hz
        Magnetometer rate (0: off).
    mag_noise_deg : float, deg
        Magnetometer error per component, relative to ``|B|`` in the angle it subtends.
    noise : {"gaussian", "uniform"}
        Error model of the sun sensor and magnetometer.
    gyro_rate_hz : float, Hz
        Gyro rate.
    gyro_arw : float, rad/s^0.5
        Angle random walk (Farrenkopf ``sigma_v``).
    gyro_rrw : float, rad/s^1.5
        Bias random walk (Farrenkopf ``sigma_u``).
    gyro_bias0_deg_h : float, deg/h
        Std per axis of the initial gyro bias.
    star_tracker_rate_hz : float, Hz
        Star-tracker rate (0: off).
    star_tracker_noise_arcsec : float, arcsec
        Star-tracker error per body axis (std).

    Examples
    --------
    >>> from adcskit.simulation import SensorSpec
    >>> s = SensorSpec(sun_noise_deg=0.005, mag_noise_deg=0.5, noise="uniform")   # S0's bounded errors
    >>> s.noise, s.gyro_rate_hz
    ('uniform', 10.0)
    """

    sun_rate_hz: float = 1.0
    sun_noise_deg: float = 0.005
    mag_rate_hz: float = 1.0
    mag_noise_deg: float = 0.5
    noise: Literal["gaussian", "uniform"] = "gaussian"
    gyro_rate_hz: float = 10.0
    gyro_arw: float = 3.16e-7
    gyro_rrw: float = 3.16e-10
    gyro_bias0_deg_h: float = 1.0
    star_tracker_rate_hz: float = 0.0
    star_tracker_noise_arcsec: float = 10.0

    def __post_init__(self) -> None:
        for name in ("sun_rate_hz", "mag_rate_hz", "star_tracker_rate_hz", "sun_noise_deg", "mag_noise_deg",
                     "gyro_arw", "gyro_rrw", "gyro_bias0_deg_h", "star_tracker_noise_arcsec"):
            _nonneg(name, getattr(self, name))
        check_positive("gyro_rate_hz", self.gyro_rate_hz, unit="Hz")
        check_choice("noise", self.noise, ("gaussian", "uniform"))


@dataclass(frozen=True, slots=True, kw_only=True)
class EstimatorSpec(_Spec):
    """Attitude knowledge used by the controller.

    Attributes
    ----------
    kind : {"truth", "wahba", "minmax", "mekf"}
        ``truth``: the true attitude and rate (ideal knowledge); ``wahba``: a point solution
        of Wahba's problem from the sun sensor and magnetometer at every epoch with both
        (``wahba_method``), propagated with the raw gyro in between; ``minmax``: S0's robust
        interval determination at those epochs (min-max goal attainment, eqs. 3-8, the
        ``closed-form`` solver of :func:`adcskit.determination.robust_wahba`, compiled:
        the q-method of the interval midpoints restricted to the box
        ``q_TRIAD ± search_range |q_TRIAD|``), propagated like ``wahba``; ``mekf``: the
        multiplicative EKF with gyro-bias estimation (Lefferts, Markley & Shuster 1982).
        The intervals are the sensors' bounded-error boxes (the measured vector ± the error
        bound per component, reference vectors exact); min-max does not depend on their
        radii (``α = β = 0`` is feasible with ``ΔL = 0``), so they need not be passed.
        The worst-case formulation (Ahmed & Kerrigan 2011) is not available in the loop
        (a nonsmooth min-max over the box vertices solved by SLSQP, not compiled).
    wahba_method : str
        ``wahba``: a compiled :func:`adcskit.determination.solve_wahba` method
        (``q-method``, ``quest``, ``esoq2``, ``svd``, ``foam``, ``flae``, ``triad``,
        ``two-vector``).
    search_range : float
        ``minmax``: half-width of the search box relative to each TRIAD component (S0 §4-1:
        0.1).
    weights : {"inverse-variance", "equal"}
        ``wahba`` and ``minmax``: Wahba weights of the sun sensor and magnetometer,
        ``1/σ²`` of each sensor's error (σ = bound/√3 for bounded errors) or equal (S0
        prints only ``Σ a_i = 1``).
    init_error_deg : float
        Std of the initial knowledge error per axis (also the MEKF's initial sigma).
    underweight : float
        ``mekf``: measurement-underweighting factor ``p`` >= 0 (default 0.2, on): while a
        sun-sensor or magnetometer measurement's predicted variance ``h P hᵀ`` exceeds its noise variance ``σ²`` the
        update uses ``σ² + p h P hᵀ`` (Lefferts, Markley & Shuster 1982), which keeps the
        filter consistent after a precise first sun update of a 1° prior; ``0`` is the
        plain EKF update (see :func:`adcskit.estimation.mekf_filter`). Star-tracker updates
        are never underweighted.

    Examples
    --------
    >>> from adcskit.simulation import EstimatorSpec
    >>> EstimatorSpec(kind="wahba", wahba_method="q-method").kind
    'wahba'
    >>> EstimatorSpec(kind="minmax", search_range=0.1, weights="equal").search_range   # S0 §4-1
    0.1
    """

    kind: Literal["truth", "wahba", "minmax", "mekf"] = "mekf"
    wahba_method: str = "q-method"
    search_range: float = 0.1
    weights: Literal["inverse-variance", "equal"] = "inverse-variance"
    init_error_deg: float = 1.0
    underweight: float = 0.2

    def __post_init__(self) -> None:
        if self.kind == "worst-case":
            raise InputError(
                "kind='worst-case' is not available inside the closed loop: the worst-case "
                "(Ahmed & Kerrigan) solution is a nonsmooth optimisation over the interval box "
                "vertices solved by SLSQP, not a compiled kernel; use kind='minmax', or "
                "adcskit.determination.robust_wahba(method='worst-case') epoch by epoch"
            )
        check_choice("kind", self.kind, ("truth", "wahba", "minmax", "mekf"))
        from adcskit.determination.wahba import METHODS as WAHBA_CODES

        check_choice("wahba_method", self.wahba_method, WAHBA_CODES)
        check_positive("search_range", self.search_range)
        check_choice("weights", self.weights, ("inverse-variance", "equal"))
        _nonneg("init_error_deg", self.init_error_deg, "deg")
        if isinstance(self.underweight, bool):
            raise InputError(f"underweight must be a number >= 0 (0 switches it off); got {self.underweight!r}")
        check_positive("underweight", self.underweight, allow_zero=True, max_value=1e6)


@dataclass(frozen=True, slots=True, kw_only=True)
class GuidanceSpec(_Spec):
    """Reference attitude (inertial).

    Attributes
    ----------
    kind : {"hold", "step", "table"}
        Reference attitude: the identity, a step at ``t_step``, or a time table.
    target_rotvec_deg : 3 floats, deg
        ``step``: rotation vector of the target attitude from the identity.
    t_step : float, s
        ``step``: when the command changes.
    table_t : tuple of float, s
        ``table``: increasing times (the reference is held before the first and after the
        last entry).
    table_q : tuple of 4-vectors
        ``table``: quaternions (scalar last), slerp-interpolated.
    table_w : tuple of 3-vectors, rad/s
        ``table``: reference body rates (linear interpolation); empty: from the slerp.

    Examples
    --------
    >>> from adcskit.simulation import GuidanceSpec
    >>> g = GuidanceSpec(kind="step", target_rotvec_deg=(0.0, 0.0, 20.0), t_step=1.0)
    >>> g.kind, g.t_step
    ('step', 1.0)
    """

    kind: Literal["hold", "step", "table"] = "hold"
    target_rotvec_deg: Vec3 = (0.0, 0.0, 0.0)
    t_step: float = 0.0
    table_t: tuple[float, ...] = ()
    table_q: tuple[tuple[float, float, float, float], ...] = ()
    table_w: tuple[Vec3, ...] = ()

    def __post_init__(self) -> None:
        check_choice("kind", self.kind, ("hold", "step", "table"))
        object.__setattr__(self, "target_rotvec_deg", _vec("target_rotvec_deg", self.target_rotvec_deg))
        _nonneg("t_step", self.t_step, "s")
        if self.kind == "table":
            t = np.asarray(self.table_t, dtype=float)
            q = np.asarray(self.table_q, dtype=float)
            if t.ndim != 1 or t.size < 2 or np.any(np.diff(t) <= 0) or not np.all(np.isfinite(t)):
                raise InputError("table_t must hold >= 2 strictly increasing finite times (s)")
            if q.shape != (t.size, 4) or not np.all(np.isfinite(q)) or np.any(np.linalg.norm(q, axis=1) < 1e-9):
                raise InputError(f"table_q must be {t.size} non-zero quaternions (shape ({t.size}, 4)); got shape {q.shape}")
            if len(self.table_w) not in (0, t.size):
                raise InputError(f"table_w must be empty or hold {t.size} rates; got {len(self.table_w)}")


@dataclass(frozen=True, slots=True, kw_only=True)
class ControllerSpec(_Spec):
    """Three-axis controller and allocation.

    ``schmitt`` is S4's loop per axis: ``u = kp e + ki int e + kd de/dt`` (dimensionless
    gains of S4 Table 4: kp [1/rad], ki [1/(rad s)], kd [s/rad]) through a three-level
    Schmitt trigger (``u_on``, ``u_off = off_ratio u_on``); the axis outputs {-1, 0, 1}
    scaled by ``torque_level`` [N m] form the torque demand. ``pwm`` is a continuous PID with
    gains in N m/rad, N m/(rad s), N m s/rad (S3 eq. 11: ``K = omega_n^2 J``). Both run at
    the command period ``period_s`` (S4's command-rate limit; S3's ``t_s``); the demand is
    allocated to the thrusters (``allocation``) and each force is realised as a pulse of
    width ``t_p = F t_s / F_max`` (S3 eq. 6) at the start of the period, with the minimum
    on-time rule ``min_on_time``.

    ``open-loop`` fires the thrusters with the given ``on_times`` table (one row per
    command period, one column per thruster, seconds; zero after the table ends): for
    validation against other simulators with an identical command sequence.

    ``schmitt`` demands take only 27 values, so they are allocated once, outside the kernel,
    by any :data:`adcskit.thrusters.ALLOCATION_METHODS` entry (``pinv-redistribute``,
    ``nnls``, ``lp-min-fuel``); ``pwm`` demands are allocated inside the kernel at every
    command period, by the redistributed pseudo-inverse (``pinv-redistribute``) or by the
    exact bounded least squares (``nnls``: a compiled Lawson-Hanson / BVLS active set whose
    torque equals :func:`adcskit.thrusters.allocate`'s ``nnls``); ``lp-min-fuel`` is not
    compiled and serves ``schmitt`` only.

    Attributes
    ----------
    kind : {"schmitt", "pwm", "open-loop"}
        Control law (above).
    period_s : float, s
        Command period.
    kp, ki, kd : 3 floats
        PID gains per axis: ``schmitt`` dimensionless (1/rad, 1/(rad s), s/rad); ``pwm``
        N m/rad, N m/(rad s), N m s/rad.
    u_on : float
        ``schmitt``: switch-on level of the trigger (dimensionless).
    off_ratio : float
        ``schmitt``: switch-off level as a fraction of ``u_on``, in [0, 1].
    torque_level : 3 floats, N m
        ``schmitt``: torque demand per axis when the trigger is on.
    allocation : str
        Torque allocation (:data:`adcskit.thrusters.ALLOCATION_METHODS`).
    min_on_time : {"drop", "round"}
        Pulses shorter than ``thrusters.t_min``: dropped, or rounded to 0 or ``t_min``.
    on_times : table of floats, s
        ``open-loop``: on-time per command period (rows) and thruster (columns).

    Examples
    --------
    >>> from adcskit.simulation import ControllerSpec
    >>> c = ControllerSpec(kind="pwm", period_s=0.2)      # continuous PID + pulse-width modulation
    >>> c.kind, c.allocation
    ('pwm', 'pinv-redistribute')
    >>> ControllerSpec(kind="pwm", allocation="nnls").allocation   # exact allocation in the kernel
    'nnls'
    """

    kind: Literal["schmitt", "pwm", "open-loop"] = "schmitt"
    period_s: float = 0.2
    kp: Vec3 = (56.24, 56.24, 56.24)
    ki: Vec3 = (0.02, 0.02, 0.02)
    kd: Vec3 = (49.99, 49.99, 49.99)
    u_on: float = 0.15
    off_ratio: float = 0.5
    torque_level: Vec3 = (10.0, 10.0, 10.0)
    allocation: str = "pinv-redistribute"
    min_on_time: Literal["drop", "round"] = "drop"
    on_times: tuple[tuple[float, ...], ...] = ()

    def __post_init__(self) -> None:
        check_choice("kind", self.kind, ("schmitt", "pwm", "open-loop"))
        if self.kind == "open-loop":
            ot = np.asarray(self.on_times, dtype=float)
            if ot.ndim != 2 or ot.shape[0] < 1 or not np.all(np.isfinite(ot)):
                raise InputError("on_times must be a non-empty table (periods x thrusters) of finite on-times (s)")
            if np.any(ot < 0) or np.any(ot > self.period_s * (1 + 1e-12)):
                raise InputError(f"on_times must lie in [0, period_s={self.period_s:g}] s")
        check_positive("period_s", self.period_s, unit="s")
        for name in ("kp", "ki", "kd", "torque_level"):
            object.__setattr__(self, name, _vec(name, getattr(self, name)))
        check_positive("u_on", self.u_on)
        check_range("off_ratio", self.off_ratio, 0.0, 1.0)
        if any(t <= 0 for t in self.torque_level):
            raise InputError(f"torque_level must be > 0 N m per axis; got {self.torque_level!r}")
        from adcskit.thrusters import ALLOCATION_METHODS

        check_choice("allocation", self.allocation, ALLOCATION_METHODS)
        if self.kind == "pwm" and self.allocation not in ("pinv-redistribute", "nnls"):
            raise InputError(
                "allocation must be 'pinv-redistribute' or 'nnls' with kind='pwm' (continuous "
                f"demands are allocated inside the compiled kernel); got {self.allocation!r}"
            )
        check_choice("min_on_time", self.min_on_time, ("drop", "round"))


@dataclass(frozen=True, slots=True, kw_only=True)
class DispersionSpec(_Spec):
    """Monte-Carlo dispersions (Gaussian, drawn by Latin-hypercube or plain random sampling
    through :mod:`adcskit.uncertainty`); 0 turns one off.

    Attributes
    ----------
    inertia_rel : float
        Relative std of each principal moment (truncated at +-90 %): a sample's inertia is
        ``V diag(s_a I_a) V^T`` with ``J = V diag(I_a) V^T`` the nominal's eigen-decomposition
        (principal axes kept; for a diagonal inertia ``V = I`` and ``s_a`` scales the moment
        about body axis ``a``). A sample whose moments break the triangle inequality
        (possible for a large ``inertia_rel`` or a near-flat body) is simulated as drawn (the
        equations of motion stay well posed for any positive definite inertia) and flagged:
        ``SimulationResult.parameters["inertia_physical"]`` is False for it and the result's
        ``message`` counts such samples.
    thrust_rel : float
        Relative std of each thruster's force.
    misalignment_deg : float
        Std per axis of a small rotation of each thruster's direction.
    delay_std_s : float
        Std of the thruster delay (truncated at 0).
    disturbance_rel : float
        Relative std of the constant and sinusoidal disturbance amplitudes.
    initial_attitude_deg : float
        Std per axis of the initial attitude.
    initial_rate_deg_s : float
        Std per axis of the initial rate.
    sampling : {"lhs", "random"}
        Latin-hypercube or plain random draws.

    Examples
    --------
    >>> from adcskit.simulation import DispersionSpec
    >>> d = DispersionSpec(inertia_rel=0.1, thrust_rel=0.05, misalignment_deg=0.5)
    >>> d.sampling
    'lhs'
    """

    inertia_rel: float = 0.0
    thrust_rel: float = 0.0
    misalignment_deg: float = 0.0
    delay_std_s: float = 0.0
    disturbance_rel: float = 0.0
    initial_attitude_deg: float = 0.0
    initial_rate_deg_s: float = 0.0
    sampling: Literal["lhs", "random"] = "lhs"

    def __post_init__(self) -> None:
        for f in fields(self):
            if f.name != "sampling":
                _nonneg(f.name, getattr(self, f.name))
        check_choice("sampling", self.sampling, ("lhs", "random"))


@dataclass(frozen=True, slots=True, kw_only=True)
class SimSpec(_Spec):
    """Time grid and metrics.

    Attributes
    ----------
    dt : float, s
        Integration step (RK4; thruster lag exact for a held command).
    t_final : float, s
        Duration of each sample's run.
    metrics_from_s : float, s
        Pointing statistics (mean, RMS, max, per-axis RMS) and knowledge error over
        ``[metrics_from_s, t_final]``.
    settle_band_deg : float, deg
        Settling: the last time the error to the *final* reference exceeds this band.
    nees_from_s : float, s
        NEES averaged over the MEKF epochs from this time.
    record_every : int
        Trace decimation (steps) when traces are requested.

    Examples
    --------
    >>> from adcskit.simulation import SimSpec
    >>> s = SimSpec(dt=0.02, t_final=60.0, metrics_from_s=30.0)
    >>> round(s.t_final / s.dt)                          # steps per sample
    3000
    """

    dt: float = 0.02
    t_final: float = 100.0
    metrics_from_s: float = 50.0
    settle_band_deg: float = 0.5
    nees_from_s: float = 0.0
    record_every: int = 10

    def __post_init__(self) -> None:
        check_positive("dt", self.dt, unit="s")
        check_positive("t_final", self.t_final, unit="s")
        if self.t_final / self.dt > 1e7:
            raise InputError(f"t_final/dt must be <= 1e7 steps; got {self.t_final / self.dt:g}")
        if not 0.0 <= check_finite("metrics_from_s", self.metrics_from_s) < self.t_final:
            raise InputError(f"metrics_from_s must be in [0, t_final) s; got {self.metrics_from_s!r}")
        check_positive("settle_band_deg", self.settle_band_deg, unit="deg")
        _nonneg("nees_from_s", self.nees_from_s, "s")
        check_int("record_every", self.record_every, minimum=1)


def _default_thrusters() -> ThrusterSpec:
    # S3 §6 reference layout (Servidia & Sanchez Pena 2000), realised geometrically
    from adcskit.thrusters.reference import S3_REFERENCE_A

    return ThrusterSpec.from_torque_matrix(S3_REFERENCE_A)


def _check_parts(spec: Any, parts: dict[str, type]) -> None:
    """Each named part of a scenario is an instance of its spec class (an InputError naming it otherwise)."""
    for name, cls in parts.items():
        if not isinstance(getattr(spec, name), cls):
            raise InputError(f"{name} must be a {cls.__name__}; got {type(getattr(spec, name)).__name__}")


def _whole_steps(dt: float):
    """``steps(name, period)``: an InputError unless ``period`` is a whole number (>= 1) of ``dt``."""

    def steps(name: str, period: float) -> None:
        r = period / dt
        if r < 1.0 - 1e-9 or abs(r - round(r)) > 1e-6 * r:
            raise InputError(f"{name} must be a whole number (>= 1) of steps dt={dt:g} s; got {period:g} s")

    return steps


@dataclass(frozen=True, slots=True, kw_only=True)
class Scenario(_Spec):
    """A closed-loop scenario (all parts are data).

    Attributes
    ----------
    spacecraft : SpacecraftSpec
        Rigid body (inertia).
    orbit : OrbitSpec
        Circular orbit, epoch and environment models.
    disturbance : DisturbanceSpec
        Body-frame disturbance torque.
    thrusters : ThrusterSpec
        Thruster layout and model.
    sensors : SensorSpec
        Sun sensor, magnetometer, gyro and star tracker.
    estimator : EstimatorSpec
        Attitude knowledge used by the controller.
    guidance : GuidanceSpec
        Reference attitude (hold, step or time table).
    controller : ControllerSpec
        Three-axis controller and allocation.
    dispersions : DispersionSpec
        Monte-Carlo dispersions.
    sim : SimSpec
        Time grid and metrics.
    initial_rotvec_deg : 3 floats, deg
        Nominal initial attitude (rotation vector from the identity).
    initial_rate_deg_s : 3 floats, deg/s
        Nominal initial body rate.

    Examples
    --------
    >>> from adcskit.simulation import Scenario, GuidanceSpec
    >>> sc = Scenario(guidance=GuidanceSpec(kind="step", target_rotvec_deg=(0.0, 0.0, 10.0)))
    >>> sc.guidance.kind, sc.spacecraft.inertia      # S3's GEO inertia by default, kg m^2
    ('step', (1218.6, 442.2, 1429.4))
    """

    spacecraft: SpacecraftSpec = field(default_factory=SpacecraftSpec)
    orbit: OrbitSpec = field(default_factory=OrbitSpec)
    disturbance: DisturbanceSpec = field(default_factory=DisturbanceSpec)
    thrusters: ThrusterSpec = field(default_factory=_default_thrusters)
    sensors: SensorSpec = field(default_factory=SensorSpec)
    estimator: EstimatorSpec = field(default_factory=EstimatorSpec)
    guidance: GuidanceSpec = field(default_factory=GuidanceSpec)
    controller: ControllerSpec = field(default_factory=ControllerSpec)
    dispersions: DispersionSpec = field(default_factory=DispersionSpec)
    sim: SimSpec = field(default_factory=SimSpec)
    initial_rotvec_deg: Vec3 = (0.0, 0.0, 0.0)
    initial_rate_deg_s: Vec3 = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        parts = {"spacecraft": SpacecraftSpec, "orbit": OrbitSpec, "disturbance": DisturbanceSpec,
                 "thrusters": ThrusterSpec, "sensors": SensorSpec, "estimator": EstimatorSpec,
                 "guidance": GuidanceSpec, "controller": ControllerSpec, "dispersions": DispersionSpec,
                 "sim": SimSpec}
        _check_parts(self, parts)
        object.__setattr__(self, "initial_rotvec_deg", _vec("initial_rotvec_deg", self.initial_rotvec_deg))
        object.__setattr__(self, "initial_rate_deg_s", _vec("initial_rate_deg_s", self.initial_rate_deg_s))
        # rates must divide each other
        dt = self.sim.dt
        steps = _whole_steps(dt)

        steps("controller.period_s", self.controller.period_s)
        g = 1.0 / self.sensors.gyro_rate_hz
        steps("1 / sensors.gyro_rate_hz", g)
        for name in ("sun_rate_hz", "mag_rate_hz", "star_tracker_rate_hz"):
            rate = getattr(self.sensors, name)
            if rate > 0:
                p = 1.0 / rate
                m = p / g
                if m < 1.0 - 1e-9 or abs(m - round(m)) > 1e-6 * m:
                    raise InputError(f"1 / sensors.{name} must be a whole multiple (>= 1) of the gyro period "
                                     f"{g:g} s; got {p:g} s")
        if self.estimator.kind in ("wahba", "minmax") and (self.sensors.sun_rate_hz <= 0
                                                            or self.sensors.mag_rate_hz <= 0):
            raise InputError(f"estimator.kind={self.estimator.kind!r} needs both the sun sensor and the "
                             "magnetometer (rates > 0)")
        if self.estimator.kind == "mekf" and max(self.sensors.sun_rate_hz, self.sensors.mag_rate_hz,
                                                 self.sensors.star_tracker_rate_hz) <= 0:
            raise InputError("estimator.kind='mekf' needs at least one attitude sensor (a rate > 0)")
        if self.controller.kind == "open-loop" and len(self.controller.on_times[0]) != self.thrusters.n:
            raise InputError(f"controller.on_times must have {self.thrusters.n} columns (one per thruster); "
                             f"got {len(self.controller.on_times[0])}")
        if max(self.thrusters.failed, default=-1) >= self.thrusters.n:
            raise InputError("thrusters.failed holds an index beyond the layout")


def _inherited(scenario: Any) -> dict[str, Any]:
    """What a partial file inherits from the default ``scenario``, part by part: every key of
    a part whose class has no default of its own (``ThrusterSpec``: the layout), else the keys
    where the scenario's default part differs from its class's default (``WheelScenario``'s
    500 km sun-synchronous orbit). Keys equal to the class default are left to the class, so
    that values sized by another key follow it (``[wheels]`` with three ``axes`` gets three
    wheel inertias, not the default pyramid's four)."""
    from dataclasses import is_dataclass

    from adcskit.config import config_to_dict

    base: dict[str, Any] = {}
    for f in fields(scenario):
        part = getattr(scenario, f.name)
        if not is_dataclass(part):
            continue
        mine = config_to_dict(part)
        try:
            ref = config_to_dict(type(part)())
        except TypeError:  # required fields: no class default to fall back on
            base[f.name] = mine
            continue
        differ = {k: v for k, v in mine.items() if v != ref.get(k)}
        if differ:
            base[f.name] = differ
    return base


def _load_spec(cls: type, source: Any = None, overrides: Any = None) -> Any:
    """A scenario of class ``cls`` from a TOML path or a mapping, over ``cls()``'s defaults.

    A table in ``source`` sets only the keys it names: the others keep the default
    scenario's values (``[thrusters] f_max = 5.0`` keeps the default layout; see
    :func:`_inherited` for the keys a part's class sizes by another key). ``overrides``
    (a mapping) goes under ``source``. Unknown keys are a :class:`~adcskit.errors.ConfigError`
    naming the dotted key and the allowed ones; a missing file is an
    :class:`~adcskit.errors.InputError`. Used by :func:`load_scenario` and
    :func:`adcskit.simulation.load_wheel_scenario`.
    """
    from collections.abc import Mapping

    from adcskit._validation import check_mapping
    from adcskit.config import load_config, merge_mappings, read_toml
    from adcskit.errors import ConfigError

    if source is None:
        data: Mapping[str, Any] = {}
    elif isinstance(source, str | Path):
        if not Path(source).exists():
            raise InputError(f"scenario file {str(source)!r} does not exist")
        data = read_toml(source)
    elif isinstance(source, Mapping):
        data = source
    else:
        raise ConfigError(f"scenario source must be a mapping or a TOML path; got {short_repr(source)}")
    check_mapping("overrides", overrides, allow_none=True)
    base = _inherited(cls())
    if overrides:
        base = merge_mappings(base, overrides)
    try:
        return load_config(cls, merge_mappings(base, data))
    except ConfigError as exc:
        if not str(exc).startswith("invalid config"):
            raise
        cmd = "adcskit scenario" + (" --wheels" if cls.__name__ == "WheelScenario" else "")
        raise ConfigError(f"{exc} (the keys a table does not set keep the default scenario's values: "
                          f"'{cmd}' prints them)") from None


def load_scenario(source: Any = None, overrides: Any = None) -> Scenario:
    """A :class:`Scenario` from a TOML file path or a mapping (unknown keys are errors).

    A partial file is completed from ``Scenario()``: a table sets only the keys it names
    (see :func:`_load_spec`); ``adcskit scenario`` prints the full default
    (:func:`scenario_toml`).

    Examples
    --------
    >>> sc = load_scenario({"sim": {"t_final": 20.0, "metrics_from_s": 10.0}})
    >>> sc.sim.t_final
    20.0
    >>> load_scenario({"thrusters": {"f_max": 5.0}}).thrusters == Scenario().thrusters.replace(f_max=5.0)
    True
    """
    return _load_spec(Scenario, source, overrides)


def scenario_toml(scenario: Any = None, *, comments: bool = True) -> str:
    """A scenario (default: ``Scenario()``) as TOML text that :func:`load_scenario` (or
    :func:`adcskit.simulation.load_wheel_scenario` for a ``WheelScenario``) reads back to an
    equal scenario.

    With ``comments`` each key is preceded by a ``#`` line with its type, unit and meaning
    (from the part classes' docstrings, :func:`adcskit.config.config_help`); an unset
    optional part (``None``) is written as a comment.

    Examples
    --------
    >>> import tomllib
    >>> text = scenario_toml()
    >>> "# float, N: Thrust when on (S3 Table 5: 10 N)." in text.splitlines()
    True
    >>> load_scenario(tomllib.loads(text)) == Scenario()
    True
    """
    from adcskit._validation import check_flag
    from adcskit.config import config_help, config_to_dict, dump_toml

    comments = check_flag("comments", comments)
    if scenario is None:
        scenario = Scenario()
    if not isinstance(scenario, _Spec) or not hasattr(scenario, "sim"):
        raise InputTypeError(f"scenario must be a Scenario or a WheelScenario; got {short_repr(scenario)}")
    notes = config_help(type(scenario)) if comments else None
    return dump_toml(config_to_dict(scenario), comments=notes)
