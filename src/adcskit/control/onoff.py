"""Single-axis on-off thruster attitude loop (PID + Schmitt trigger), batch-simulated.

The loop of S4 (Fig. 1): the pointing error ``e = θ_ref − θ`` drives a PID controller with a
first-order filtered derivative; its output ``u`` goes through a three-level Schmitt trigger
(outputs −1, 0, +1 for a pair of opposite on-off thrusters; switches on at ``|u| ≥ U_on``,
off at ``|u| < U_off``, and remembers its previous output in between); the thruster command
is sampled and held at the command rate (50 Hz baseline), delayed by a pure delay ``τ`` and
shaped by a second-order lag (two equal first-order lags, time constant ``τ_t``); the
thrusters apply the torque ``T_c = T · y`` to the rigid body ``J θ̈ = T_c + T_d`` with a
constant or sinusoidal disturbance ``T_d``.

Numerics (fixed step ``dt``, 1 ms by default):

* the thruster lag and the rigid body are advanced *exactly* for a command held constant
  over the step (zero-order hold; the 5×5 matrix exponential is computed once);
* the delay line keeps the command history; a delay that is not a multiple of ``dt`` is
  linear interpolation between the two neighbouring command samples, which is exactly the
  step-average of the delayed (piecewise-constant) command;
* the PID integrator is a forward-Euler sum and the derivative filter is the exact
  discretisation of ``1/(τ_d s + 1)`` for an error held over the step; both states are
  updated every step, while the Schmitt trigger is evaluated only at the command instants
  (a digital controller running at the command rate).

Metrics (per sample): overshoot [%] of the step, mean and max ``|e|`` over the final window
(last 10 s), fuel = delivered angular impulse ``∫ |T_c| dt`` [N m s] (the propellant
used is this divided by the lever arm and the effective exhaust velocity; S4 calls it the
fuel use "ΔV"), number of firings (transitions of the command to a non-zero level), the
2 % settling time and the final error.

Hand-written here: the loop kernel. No kept library simulates a hybrid relay loop with a
delay line across thousands of parameter samples at ≥ 1e8 sample-steps per second; the
kernel is compiled with numba and checked against a NumPy reference path (bit-identical).

References
----------
S4: Bohlouri V., Jalali-Naini S. H., "Robust optimization of satellite attitude control
using on-off thrusters based on a combined objective function", Journal of Space Science
and Technology 10(4), 2017 — Fig. 1 (loop), Table 3 (nominal parameters).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np
import scipy.linalg

from adcskit._results import Result
from adcskit._targets import TARGET_BACKENDS, resolve_backend
from adcskit._validation import as_array, check_choice, check_flag, check_positive, check_range
from adcskit.control import _onoff_kernels as _k
from adcskit.control._actuator import schmitt
from adcskit.errors import InputError

__all__ = [
    "LoopSettings",
    "LoopParams",
    "OnOffMetrics",
    "OnOffTrace",
    "BACKENDS",
    "METRIC_NAMES",
    "simulate_batch",
    "simulate_trace",
    "schmitt_trigger",
    "fuel_to_propellant",
]

METRIC_NAMES = _k.METRIC_NAMES


@dataclass(frozen=True, slots=True, kw_only=True)
class LoopSettings(Result):
    """Settings shared by every sample of a batch (fixed-step simulation).

    Attributes
    ----------
    dt : float
        Integration step [s]. The command period must be a whole number of steps.
    t_final : float
        Simulated time [s].
    t_window : float
        Final window for the steady-state metrics (mean and max ``|e|``) [s]; S4 uses the
        last 10 s.
    tau_thruster : float
        Time constant of each of the two first-order lags of the thruster [s]
        (S4 Table 3: 0.01 s).
    tau_deriv : float
        Time constant of the derivative filter ``K_d s / (τ_d s + 1)`` [s] (not printed in
        S4; 0.01 s by default).
    command_rate_hz : float
        Thruster command (sample-and-hold) rate [Hz] (S4: 50 Hz baseline; 200 and 1000 Hz
        compared).
    settle_band : float
        Settling band as a fraction of the step size (0.02 = 2 %).

    Examples
    --------
    >>> from adcskit.control import LoopSettings
    >>> s = LoopSettings(t_final=10.0, t_window=5.0, command_rate_hz=200.0)
    >>> s.dt, s.t_final, s.command_rate_hz
    (0.001, 10.0, 200.0)
    """

    dt: float = 1e-3
    t_final: float = 30.0
    t_window: float = 10.0
    tau_thruster: float = 0.01
    tau_deriv: float = 0.01
    command_rate_hz: float = 50.0
    settle_band: float = 0.02

    def __post_init__(self) -> None:
        check_positive("dt", self.dt, unit="s")
        check_positive("t_final", self.t_final, unit="s")
        check_range("t_window", self.t_window, 0.0, self.t_final, unit="s", lo_open=True, hi_name="t_final")
        if self.t_final / self.dt > 1e9:
            raise InputError(f"dt must be >= t_final / 1e9 (at most 1e9 steps); got dt = {self.dt:g} s "
                             f"with t_final = {self.t_final:g} s")
        check_positive("tau_thruster", self.tau_thruster, unit="s")
        check_positive("tau_deriv", self.tau_deriv, unit="s")
        check_positive("command_rate_hz", self.command_rate_hz, unit="Hz")
        check_range("settle_band", self.settle_band, 0.0, 1.0, lo_open=True)
        if self.t_final / self.dt > 5e7:
            raise InputError(f"t_final/dt must be <= 5e7 steps; got {self.t_final / self.dt:g}")
        period_steps = self.command_rate_hz * self.dt  # may underflow to 0 for a tiny rate (period: inf)
        ratio = 1.0 / period_steps if period_steps > 0 else math.inf
        if not ratio <= 2.0**53 or ratio < 1.0 - 1e-9 or abs(ratio - round(ratio)) > 1e-6 * ratio:
            raise InputError(
                "command_rate_hz must give a command period that is a whole number (1 to 2**53) of "
                f"steps dt={self.dt:g} s; got command_rate_hz={self.command_rate_hz:g} "
                f"(period/dt = {ratio:g})"
            )

    @property
    def n_steps(self) -> int:
        """Number of integration steps."""
        return int(round(self.t_final / self.dt))

    @property
    def hold_steps(self) -> int:
        """Integration steps per command period."""
        return int(round(1.0 / (self.command_rate_hz * self.dt)))

    @property
    def n_window(self) -> int:
        """Samples in the final metrics window."""
        return max(1, min(self.n_steps, int(round(self.t_window / self.dt))))


@dataclass(frozen=True, slots=True, kw_only=True)
class LoopParams(Result):
    """Per-sample loop parameters; S4 Table 3 nominal values by default.

    Every field is a scalar or a 1-D array; :func:`simulate_batch` broadcasts them to a
    common length ``N``.

    Attributes
    ----------
    kp, ki, kd : float or array
        PID gains (``K_p`` [1/rad], ``K_i`` [1/(rad s)], ``K_d`` [s/rad]); the defaults are
        S4 Table 4's minimum-error point read as (K_p, K_d, K_i) = (56.24, 49.99, 0.02).
    u_on : float or array
        Schmitt on threshold (S4 Table 3: 0.15).
    off_ratio : float or array
        ``U_off / U_on`` (S4 Table 3: 0.5), in [0, 1].
    inertia : float or array
        Moment of inertia ``J`` [kg m²] (S4 Table 3: 10).
    torque : float or array
        Torque level ``T`` of the thruster pair [N m] (S4 Table 3: 1), > 0.
    delay : float or array
        Pure thruster delay ``τ`` [s] (S4 Table 3: 0.02), >= 0.
    disturbance : float or array
        Constant disturbance torque ``T_d`` [N m] (S4 Table 3: 0.05).
    disturbance_amp : float or array
        Amplitude of an added sinusoidal disturbance [N m] (0 = constant disturbance).
    disturbance_freq_hz : float or array
        Its frequency [Hz].
    theta_ref : float or array
        Commanded angle [rad] (S4: 15° step).
    theta0, omega0 : float or array
        Initial angle [rad] and rate [rad/s] (S4 Table 3: 0, 0).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.control import LoopParams
    >>> p = LoopParams()                                  # S4 Table 3 nominal loop
    >>> p.inertia, p.torque, p.u_on, round(float(np.degrees(p.theta_ref)), 6)
    (10.0, 1.0, 0.15, 15.0)
    >>> batch = LoopParams(kp=np.array([40.0, 56.24, 70.0]), delay=0.03)   # 3 samples, one delay
    >>> batch.kp.shape
    (3,)
    """

    kp: Any = 56.24
    ki: Any = 0.02
    kd: Any = 49.99
    u_on: Any = 0.15
    off_ratio: Any = 0.5
    inertia: Any = 10.0
    torque: Any = 1.0
    delay: Any = 0.02
    disturbance: Any = 0.05
    disturbance_amp: Any = 0.0
    disturbance_freq_hz: Any = 0.0
    theta_ref: Any = math.radians(15.0)
    theta0: Any = 0.0
    omega0: Any = 0.0

    def __post_init__(self) -> None:
        _param_matrix(self)  # validate at construction (finite, ranges, broadcastable)

    def replace(self, **changes: Any) -> LoopParams:
        """A copy with some fields changed."""
        d = {f.name: getattr(self, f.name) for f in fields(self)}
        unknown = set(changes) - set(d)
        if unknown:
            raise InputError(
                f"LoopParams has no field(s) {sorted(unknown)}; valid: {', '.join(d)}"
            )
        d.update(changes)
        return LoopParams(**d)


@dataclass(frozen=True, slots=True, repr=False, kw_only=True)
class OnOffMetrics(Result):
    """Metrics of a batch simulation, one entry per sample.

    Attributes
    ----------
    overshoot_pct : ndarray (N,)
        Peak overshoot beyond the commanded angle, % of the step (NaN for a zero step).
    mean_abs_err_last : ndarray (N,)
        Mean ``|e|`` over the final window [rad] (S4's "Error").
    max_abs_err_last : ndarray (N,)
        Max ``|e|`` over the final window [rad] (pointing accuracy).
    fuel : ndarray (N,)
        Delivered angular impulse ``∫|T_c| dt`` [N m s] (S4's fuel "ΔV").
    firings : ndarray (N,)
        Number of thruster firings (command transitions to a non-zero level).
    settling_time : ndarray (N,)
        Time after which ``|e|`` stays inside the settling band [s] (NaN: never settled).
    final_error : ndarray (N,)
        Error at ``t_final`` [rad].
    n_steps : int
        Integration steps per sample.
    backend : str
        Kernel that produced the metrics (``numba``, ``cuda``, ``numpy`` or ``python``).

    Examples
    --------
    >>> from adcskit.control import LoopParams, LoopSettings, simulate_batch
    >>> m = simulate_batch(LoopParams(kp=[40.0, 56.24]), LoopSettings(t_final=10.0, t_window=5.0),
    ...                    backend="python")                # plain loops: no JIT wait
    >>> type(m).__name__, m.fuel.shape, m.n_steps, m.backend
    ('OnOffMetrics', (2,), 10000, 'python')
    >>> sorted(m.to_dict())[:3]
    ['backend', 'final_error', 'firings']
    """

    overshoot_pct: np.ndarray
    mean_abs_err_last: np.ndarray
    max_abs_err_last: np.ndarray
    fuel: np.ndarray
    firings: np.ndarray
    settling_time: np.ndarray
    final_error: np.ndarray
    n_steps: int = 0
    backend: str = "numba"

    @property
    def n_samples(self) -> int:
        return int(self.fuel.shape[0])

    def as_array(self) -> np.ndarray:
        """The metrics as an (N, 7) array in :data:`METRIC_NAMES` order."""
        return np.stack([getattr(self, name) for name in METRIC_NAMES], axis=1)


@dataclass(frozen=True, slots=True, repr=False, kw_only=True)
class OnOffTrace(Result):
    """Time histories of one simulation (sampled every ``dt``).

    Attributes
    ----------
    t : ndarray (n+1,)
        Time [s].
    theta, omega : ndarray (n+1,)
        Angle [rad] and rate [rad/s].
    u : ndarray (n+1,)
        PID output (held at the command rate).
    command : ndarray (n+1,)
        Schmitt-trigger output {−1, 0, +1} (before the delay).
    thrust_torque : ndarray (n+1,)
        Torque delivered by the thrusters ``T_c`` [N m].
    metrics : OnOffMetrics
        Metrics of this run (N = 1).

    Examples
    --------
    >>> from adcskit.control import LoopSettings, simulate_trace
    >>> tr = simulate_trace(settings=LoopSettings(t_final=5.0, t_window=2.0), backend="python")
    >>> type(tr).__name__, tr.t.shape, tr.theta.shape, tr.command.shape
    ('OnOffTrace', (5001,), (5001,), (5001,))
    >>> sorted(set(tr.command.tolist()))                  # Schmitt-trigger levels used
    [-1.0, 0.0, 1.0]
    """

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    u: np.ndarray
    command: np.ndarray
    thrust_torque: np.ndarray
    metrics: OnOffMetrics = field(repr=False)


def schmitt_trigger(u: Any, u_on: float, u_off: float, state: float = 0.0) -> np.ndarray:
    """Three-level Schmitt trigger with hysteresis applied to a sequence.

    Parameters
    ----------
    u : array_like (n,)
        Input sequence.
    u_on, u_off : float
        On and off thresholds, ``0 <= u_off <= u_on``.
    state : {-1, 0, 1}
        Output before the first sample.

    Returns
    -------
    ndarray (n,)
        Outputs in {−1, 0, +1}: from 0 the output switches to ±1 when ``±u >= u_on``; from
        ±1 it returns to 0 when ``±u < u_off`` and flips sign when ``∓u >= u_on``.

    References
    ----------
    S4, Fig. 1 (Schmitt trigger block).

    Examples
    --------
    >>> from adcskit.control import schmitt_trigger
    >>> schmitt_trigger([0.0, 0.2, 0.1, 0.05, -0.2, -0.1, 0.0], u_on=0.15, u_off=0.075)
    array([ 0.,  1.,  1.,  0., -1., -1.,  0.])
    """
    arr = as_array("u", u, ndim=1)
    on = check_positive("u_on", u_on, allow_zero=True)
    off = check_range("u_off", u_off, 0.0, on, hi_name="u_on")
    if isinstance(state, (bool, np.bool_)) or state not in (-1, 0, 1, -1.0, 0.0, 1.0):
        raise InputError(f"state must be -1, 0 or 1; got {state!r}")
    out = np.empty_like(arr)
    s = float(state)
    for k, x in enumerate(arr):  # the kernels' device helper, run as plain Python
        s = schmitt(s, x, on, off)
        out[k] = s
    return out


G0 = 9.80665  # standard gravity [m/s^2]


def fuel_to_propellant(
    fuel: Any, *, lever_arm: float, isp: float | None = None, mass: float | None = None
) -> dict[str, np.ndarray]:
    """Convert the loop's fuel measure (angular impulse) to thrust impulse, propellant, ΔV.

    Parameters
    ----------
    fuel : float or array
        Delivered angular impulse ``∫|T_c| dt`` [N m s] (:attr:`OnOffMetrics.fuel`).
    lever_arm : float
        Moment arm of each thruster about the control axis [m].
    isp : float, optional
        Specific impulse [s]; gives the propellant mass.
    mass : float, optional
        Spacecraft mass [kg]; gives the ΔV-equivalent.

    Returns
    -------
    dict
        ``impulse_Ns`` = fuel / lever arm [N s]; with ``isp``: ``propellant_kg`` =
        impulse / (isp g₀); with ``mass``: ``delta_v_mps`` = impulse / mass [m/s], the
        velocity change the same thruster impulse would give the spacecraft (S4's "ΔV").

    References
    ----------
    S4, eq. (9) (fuel objective "ΔV", no formula printed).

    Examples
    --------
    >>> from adcskit.control import fuel_to_propellant
    >>> out = fuel_to_propellant(2.0, lever_arm=0.5, isp=220.0, mass=100.0)   # 2 N m s
    >>> float(out["impulse_Ns"]), round(float(out["propellant_kg"]), 9), float(out["delta_v_mps"])
    (4.0, 0.001854029, 0.04)
    """
    f = as_array("fuel", fuel, ndim=(0, 1))
    if np.any(f < 0):
        raise InputError(f"fuel must be >= 0 N m s; got min {float(np.min(f)):g}")
    arm = check_positive("lever_arm", lever_arm, unit="m", min_value=1e-100)
    out = {"impulse_Ns": f / arm}
    if isp is not None:
        out["propellant_kg"] = out["impulse_Ns"] / (check_positive("isp", isp, unit="s", min_value=1e-100) * G0)
    if mass is not None:
        out["delta_v_mps"] = out["impulse_Ns"] / check_positive("mass", mass, unit="kg", min_value=1e-100)
    return out


def _coefficients(settings: LoopSettings) -> np.ndarray:
    """The kernel's coefficient vector for ``settings`` (a fresh, writable copy)."""
    return _coefficients_of(settings).copy()


@functools.lru_cache(maxsize=64)
def _coefficients_of(settings: LoopSettings) -> np.ndarray:
    # cached: a GA calls simulate_batch once per generation with the same settings, and the
    # 5x5 expm cost ~1-30 ms a call (profile of onoff-tuning --quick, issue 24), more than a
    # small batch's simulation. Same inputs, same numbers: results are unchanged.
    tau = settings.tau_thruster
    dt = settings.dt
    # states [x1, x2, v, p, u]: x1' = (u - x1)/tau, x2' = (x1 - x2)/tau, v' = x2, p' = v, u' = 0
    m = np.zeros((5, 5))
    m[0, 0] = -1.0 / tau
    m[0, 4] = 1.0 / tau
    m[1, 0] = 1.0 / tau
    m[1, 1] = -1.0 / tau
    m[2, 1] = 1.0
    m[3, 2] = 1.0
    phi = scipy.linalg.expm(m * dt)
    c = np.zeros(_k.N_COEFS)
    c[_k.A11], c[_k.B1] = phi[0, 0], phi[0, 4]
    c[_k.A21], c[_k.A22], c[_k.B2] = phi[1, 0], phi[1, 1], phi[1, 4]
    c[_k.V1], c[_k.V2], c[_k.VU] = phi[2, 0], phi[2, 1], phi[2, 4]
    c[_k.P1], c[_k.P2], c[_k.PU] = phi[3, 0], phi[3, 1], phi[3, 4]
    c[_k.ALPHA] = -math.expm1(-dt / settings.tau_deriv)
    c[_k.INV_TD] = 1.0 / settings.tau_deriv
    c[_k.DT] = dt
    c[_k.HALF_DT2] = 0.5 * dt * dt
    c[_k.BAND_FRAC] = settings.settle_band
    return c


_PARAM_COLUMNS = {
    "kp": _k.KP,
    "ki": _k.KI,
    "kd": _k.KD,
    "inertia": _k.INERTIA,
    "torque": _k.TORQUE,
    "delay": _k.DELAY,
    "disturbance": _k.D0,
    "disturbance_amp": _k.DAMP,
    "theta_ref": _k.THREF,
    "theta0": _k.TH0,
    "omega0": _k.OM0,
}


def _param_matrix(params: LoopParams) -> np.ndarray:
    values = {f.name: as_array(f.name, getattr(params, f.name), ndim=(0, 1)) for f in fields(params)}
    try:
        bcast = np.broadcast_arrays(*values.values())
    except ValueError:
        shapes = {k: v.shape for k, v in values.items()}
        raise InputError(f"loop parameters must broadcast to one length N; got shapes {shapes}") from None
    b = dict(zip(values, bcast))
    n = int(np.atleast_1d(bcast[0]).shape[0])
    if n < 1:
        raise InputError("loop parameters must describe at least one sample; got N=0")
    P = np.empty((n, _k.N_PARAMS))
    for name, col in _PARAM_COLUMNS.items():
        P[:, col] = np.atleast_1d(b[name])
    u_on = np.atleast_1d(b["u_on"])
    ratio = np.atleast_1d(b["off_ratio"])
    P[:, _k.UON] = u_on
    P[:, _k.UOFF] = ratio * u_on
    P[:, _k.DOMEGA] = 2.0 * math.pi * np.atleast_1d(b["disturbance_freq_hz"])
    checks = {
        "inertia": (P[:, _k.INERTIA] > 0, "> 0 kg m^2"),
        "torque": (P[:, _k.TORQUE] > 0, "> 0 N m (a thruster pair without torque cannot control)"),
        "delay": (P[:, _k.DELAY] >= 0, ">= 0 s"),
        "u_on": (u_on >= 0, ">= 0"),
        "off_ratio": ((ratio >= 0) & (ratio <= 1), "in [0, 1]"),
        "disturbance_freq_hz": (np.atleast_1d(b["disturbance_freq_hz"]) >= 0, ">= 0 Hz"),
    }
    for name, (ok, what) in checks.items():
        if not np.all(ok):
            i = int(np.argmin(ok))
            raise InputError(f"{name} must be {what}; got {float(np.atleast_1d(b[name])[i])!r} at sample {i}")
    return P


def _buffer_length(P: np.ndarray, dt: float) -> int:
    delay = float(np.max(P[:, _k.DELAY]))
    if delay / dt > 2**24:  # the delay line holds delay/dt samples
        raise InputError(f"delay must be <= 2**24 * dt = {2**24 * dt:g} s (the delay line's length); got {delay:g} s")
    max_steps = int(math.floor(delay / dt)) + 2
    return 1 << max(1, max_steps.bit_length())


_Kernel = Callable[..., np.ndarray]


def _run_numba(P, C, n_steps, hold, n_win, L, rec, parallel):
    fn = _k.simulate_parallel if parallel else _k.simulate_serial
    return fn(P, C, n_steps, hold, n_win, L, rec, _k.lane_count(P.shape[0]))


def _run_numpy(P, C, n_steps, hold, n_win, L, rec, parallel):
    return _k.simulate_numpy(P, C, n_steps, hold, n_win, L, rec)


def _run_python(P, C, n_steps, hold, n_win, L, rec, parallel):
    return _k.simulate_python(P, C, n_steps, hold, n_win, L, rec)


def _run_cuda(P, C, n_steps, hold, n_win, L, rec, parallel):
    if L > _k.MAX_CUDA_BUFFER:
        raise InputError(
            f"backend='cuda' supports delays up to {_k.MAX_CUDA_BUFFER - 2} steps; got "
            f"{float(np.max(P[:, _k.DELAY])):g} s at dt={float(C[_k.DT]):g} s (use backend='cpu')"
        )
    return _k.simulate_cuda(P, C, n_steps, hold, n_win, L, rec)


BACKENDS: Mapping[str, _Kernel | None] = {
    "numba": _run_numba,
    "numpy": _run_numpy,
    "python": _run_python,
    "cpu": _run_numba,
    "cuda": _run_cuda,
    "auto": None,  # resolved to "cpu" or "cuda" at call time
}
"""Kernels: ``numba`` (compiled for the CPU, the default; ``cpu`` is the same kernel),
``cuda`` (the same per-sample source compiled for an NVIDIA GPU, one thread per sample;
needs the ``gpu`` extra), ``auto`` (``cuda`` when a GPU is usable, else ``cpu``), ``numpy``
(reference path vectorised over samples), ``python`` (plain loops; for benchmarks)."""


def _kernel(backend: str) -> tuple[str, _Kernel]:
    """The kernel that runs for ``backend`` and the name it is reported under."""
    if backend in TARGET_BACKENDS:
        target = resolve_backend(backend)
        return ("cuda", _run_cuda) if target == "cuda" else ("numba", _run_numba)
    return backend, BACKENDS[backend]  # type: ignore[return-value]


def _metrics(out: np.ndarray, n_steps: int, backend: str) -> OnOffMetrics:
    cols = {name: np.ascontiguousarray(out[:, j]) for j, name in enumerate(METRIC_NAMES)}
    return OnOffMetrics(**cols, n_steps=n_steps, backend=backend)


def _checked_inputs(
    params: LoopParams | None, settings: LoopSettings | None, backend: str
) -> tuple[LoopParams, LoopSettings]:
    """Defaults (S4 Table 3) and boundary checks shared by the simulation entry points."""
    params = LoopParams() if params is None else params
    settings = LoopSettings() if settings is None else settings
    if not isinstance(params, LoopParams):
        raise InputError(f"params must be a LoopParams; got {type(params).__name__}")
    if not isinstance(settings, LoopSettings):
        raise InputError(f"settings must be a LoopSettings; got {type(settings).__name__}")
    check_choice("backend", backend, BACKENDS)
    return params, settings


def simulate_batch(
    params: LoopParams | None = None,
    settings: LoopSettings | None = None,
    *,
    backend: str = "numba",
    parallel: bool = True,
) -> OnOffMetrics:
    """Simulate ``N`` independent loops (one per parameter sample) and return their metrics.

    Parameters
    ----------
    params : LoopParams, optional
        Per-sample parameters (scalars or 1-D arrays broadcast to length ``N``); S4 Table 3
        nominal values by default.
    settings : LoopSettings, optional
        Shared step, duration, thruster and filter time constants, command rate.
    backend : {"numba", "cpu", "cuda", "auto", "numpy", "python"}
        Kernel (see :data:`BACKENDS`). The CPU kernels give the same numbers bit for bit;
        ``cuda`` gives identical firings and continuous metrics within a relative ~1e-9
        (fused multiply-adds on the GPU). ``auto`` is ``cuda`` when a GPU is usable.
    parallel : bool
        Let the numba CPU kernel spread samples over threads (``prange``).

    Returns
    -------
    OnOffMetrics
        Per-sample overshoot [%], mean/max ``|e|`` over the final window [rad], fuel
        [N m s], firings, settling time [s] and final error [rad].

    References
    ----------
    S4, Fig. 1 and Table 3; "Error" (mean ``|e|`` over the last 10 s) and "ΔV" of eq. (9).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.control import LoopParams, LoopSettings, simulate_batch
    >>> params = LoopParams(kp=np.array([40.0, 56.24]))            # two PID gain samples
    >>> settings = LoopSettings(t_final=10.0, t_window=5.0)
    >>> m = simulate_batch(params, settings, backend="python")   # same numbers as numba
    >>> m.firings, m.fuel.round(4)                                  # firings, N m s
    (array([48., 50.]), array([6.4585, 7.7492]))
    >>> np.degrees(m.mean_abs_err_last).round(4)                    # S4 "Error", deg
    array([0.1139, 0.0277])
    >>> m_numba = simulate_batch(params, settings)   # default numba kernel (JIT)  # doctest: +SKIP
    >>> np.array_equal(m_numba.fuel, m.fuel)  # doctest: +SKIP
    True
    """
    params, settings = _checked_inputs(params, settings, backend)
    parallel = check_flag("parallel", parallel)
    P = _param_matrix(params)
    C = _coefficients(settings)
    L = _buffer_length(P, settings.dt)
    rec = np.empty((0, 0, _k.N_TRACE))
    name, kernel = _kernel(backend)
    out = kernel(P, C, settings.n_steps, settings.hold_steps, settings.n_window, L, rec, parallel)
    return _metrics(out, settings.n_steps, name)


def simulate_trace(
    params: LoopParams | None = None,
    settings: LoopSettings | None = None,
    *,
    backend: str = "numba",
) -> OnOffTrace:
    """Simulate one loop and return its time histories (for plots).

    Parameters
    ----------
    params : LoopParams, optional
        Scalar parameters (N must be 1); S4 Table 3 by default.
    settings : LoopSettings, optional
        Shared settings.
    backend : {"numba", "cpu", "cuda", "auto", "numpy", "python"}
        Kernel.

    Returns
    -------
    OnOffTrace
        Time, angle, rate, PID output, command and thrust torque, plus the run's metrics.

    References
    ----------
    S4, Figs. 5-7 (step response, thruster on/off history, limit cycle).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.control import LoopParams, LoopSettings, simulate_trace
    >>> settings = LoopSettings(t_final=10.0, t_window=5.0)
    >>> tr = simulate_trace(LoopParams(), settings, backend="python")
    >>> tr.t.shape, float(tr.t[-1])
    ((10001,), 10.0)
    >>> round(float(np.degrees(tr.theta[-1])), 2)     # settles near the 15 deg command
    15.04
    >>> tr.metrics.firings
    array([50.])
    """
    params, settings = _checked_inputs(params, settings, backend)
    P = _param_matrix(params)
    if P.shape[0] != 1:
        raise InputError(f"simulate_trace takes one sample; got N={P.shape[0]}")
    C = _coefficients(settings)
    L = _buffer_length(P, settings.dt)
    n = settings.n_steps
    rec = np.zeros((1, n + 1, _k.N_TRACE))
    name, kernel = _kernel(backend)
    out = kernel(P, C, n, settings.hold_steps, settings.n_window, L, rec, False)
    r = rec[0]
    return OnOffTrace(
        t=np.arange(n + 1) * settings.dt,
        theta=r[:, _k.TR_THETA].copy(),
        omega=r[:, _k.TR_OMEGA].copy(),
        u=r[:, _k.TR_U].copy(),
        command=r[:, _k.TR_CMD].copy(),
        thrust_torque=r[:, _k.TR_THRUST].copy(),
        metrics=_metrics(out, n, name),
    )
