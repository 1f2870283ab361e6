"""Export a simulation result (thruster or wheel loop) to an xarray Dataset, netCDF or Zarr.

:func:`to_dataset` (and :func:`write_netcdf` / :func:`write_zarr`) take either loop's result:
a :class:`~adcskit.simulation.SimulationResult` (:func:`~adcskit.simulation.simulate`) or a
:class:`~adcskit.simulation.WheelSimulationResult`
(:func:`~adcskit.simulation.simulate_wheels`), one public API that dispatches on the type. For
a thruster-loop result it lays a Monte-Carlo campaign out on labelled dimensions:

* ``sample`` — one entry per Monte-Carlo sample: every metric of
  :data:`~adcskit.simulation.METRIC_NAMES` (unit in the name, degrees for angles),
  ``controllable``, ``on_time_per_thruster`` (``sample, thruster``), the per-sample noise
  seed ``noise_seed`` and every dispersed parameter as ``param_<name>``;
* ``time`` (s) — the recorded traces (``record=True``), one variable per channel in SI units
  (``pointing_error`` in rad, ``omega_x`` in rad/s, ...); indexed channels (``thrust_0``,
  ``thrust_1``, ...) become one variable with a third dimension (``thrust``:
  ``sample, time, thruster``).

For a wheel-loop result the same rules give (:data:`WHEEL_CHANNEL_INFO`,
:data:`WHEEL_METRIC_INFO`):

* ``sample`` — every metric the scenario produced (:data:`~adcskit.simulation.WHEEL_METRIC_NAMES`,
  plus the unloading-thruster and filter metrics when those parts are configured),
  ``noise_seed`` and the dispersed parameters (``param_inertia``, ``param_wheel_axes``
  (``sample, axis, wheel``), ``param_initial_rate``, ``param_gyro_bias``,
  ``param_sensor_noise_scale``, ...; ``param_null_momentum`` is one per wheel, not per sample);
* ``time`` — every recorded channel, SI: ``error``, ``omega_x``, ..., ``h_body_x``, ...,
  ``H_eci_x``, ..., ``dipole_x``, ..., ``knowledge_error``, the per-wheel channels grouped on
  a ``wheel`` dimension (``speed`` and ``h``: ``sample, time, wheel``), and, when configured,
  ``thruster_torque_x``, ..., ``propellant`` and ``nees``. Channel names are the result's
  (``omega_x`` as in the thruster loop), so one script reads both loops' files;
* the modes as integer codes: ``mode`` (``sample, time``) and the metric ``final_mode`` are
  ``int8`` with the CF attributes ``flag_values`` (0, 1, 2) and ``flag_meanings``
  (``"detumble sun point"``, :data:`~adcskit.simulation.MODE_NAMES`).

Every variable carries ``units`` and ``long_name`` attributes (CF conventions); the dataset
carries the scenario as TOML text (``scenario_toml``, read back with
:func:`adcskit.simulation.load_scenario`, or :func:`adcskit.simulation.load_wheel_scenario`
for a wheel run — the attribute ``scenario_loader`` names it — after :func:`tomllib.loads`),
the campaign seed (``rng_seed``, when given), the run's bookkeeping (``n_steps``,
``runtime_s``, ``success``, ``message``, ...), the result type (``adcskit_result``) and the
adcskit version (``adcskit_version``).

The per-sample seeds are a variable on ``sample`` rather than one dataset attribute, so
that selecting samples (``ds.isel(sample=...)``) keeps each sample's seed with it.

:func:`write_netcdf` writes netCDF3 (64-bit offset) through xarray's ``scipy`` engine, which
needs no C library. NetCDF3 has no 64-bit integers, so ``noise_seed`` (uint64) is written as
decimal text and :func:`read_dataset` turns it back into uint64. :func:`write_zarr` writes a
Zarr store (``pip install zarr``). Both need the optional extra ``adcskit[export]``
(xarray, zarr); without xarray they raise :class:`adcskit.errors.SolverError` naming it.

Hand-written here: only the mapping of a result's arrays to named dimensions, units and
descriptions; storage is xarray's.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import numpy as np

from adcskit._validation import check_int, check_path, short_repr
from adcskit.errors import InputError, InputTypeError, SolverError
from adcskit.simulation.core import SimulationResult
from adcskit.simulation.scenario import Scenario
from adcskit.simulation.wheels import MODE_NAMES, WheelScenario, WheelSimulationResult

__all__ = [
    "CHANNEL_INFO",
    "METRIC_INFO",
    "WHEEL_CHANNEL_INFO",
    "WHEEL_METRIC_INFO",
    "metric_units",
    "to_dataset",
    "write_netcdf",
    "write_zarr",
    "read_dataset",
]

#: The optional extra that brings xarray and zarr.
EXPORT_EXTRA_HINT = "install the export extra: pip install 'adcskit[export]' (xarray, zarr)"

#: Trace channels: name (indexed channels by their base, ``thrust`` for ``thrust_0`` ...) ->
#: (units, long_name). Channels are in SI units (see :class:`~adcskit.simulation.SimulationResult`).
#: A channel missing here is exported with ``units = ""`` and its name as ``long_name``.
CHANNEL_INFO: dict[str, tuple[str, str]] = {
    "err_x": ("rad", "attitude error rotation vector to the reference, body x"),
    "err_y": ("rad", "attitude error rotation vector to the reference, body y"),
    "err_z": ("rad", "attitude error rotation vector to the reference, body z"),
    "pointing_error": ("rad", "pointing error: rotation angle from the reference to the true attitude"),
    "knowledge_error": ("rad", "knowledge error: rotation angle from the true to the estimated attitude"),
    "omega_x": ("rad/s", "body rate, body x"),
    "omega_y": ("rad/s", "body rate, body y"),
    "omega_z": ("rad/s", "body rate, body z"),
    "nees": ("1", "MEKF normalised estimation error squared at its last epoch (NaN without MEKF)"),
    "propellant": ("kg", "cumulative propellant"),
    "thrust": ("1", "delivered thrust as a fraction of f_max"),
}
#: Third dimension of indexed channels (``thrust_<j>`` -> ``thruster``); others get ``<base>_index``.
CHANNEL_DIMS: dict[str, str] = {"thrust": "thruster"}

#: Per-sample metrics -> long_name (units from the name, :func:`metric_units`).
METRIC_INFO: dict[str, str] = {
    "pointing_mean_deg": "mean pointing error over [metrics_from_s, t_final]",
    "pointing_rms_deg": "RMS pointing error over [metrics_from_s, t_final]",
    "pointing_max_deg": "maximum pointing error over [metrics_from_s, t_final]",
    "pointing_rms_x_deg": "RMS attitude error about body x over [metrics_from_s, t_final]",
    "pointing_rms_y_deg": "RMS attitude error about body y over [metrics_from_s, t_final]",
    "pointing_rms_z_deg": "RMS attitude error about body z over [metrics_from_s, t_final]",
    "settling_time_s": "last exit from settle_band_deg around the final reference (NaN: not settled)",
    "final_error_deg": "pointing error at t_final",
    "propellant_kg": "propellant used",
    "firings": "number of thruster pulses",
    "on_time_s": "commanded thruster on-time, all thrusters",
    "knowledge_rms_deg": "RMS knowledge error (estimate vs truth) over [metrics_from_s, t_final]",
    "nees_mean": "MEKF NEES averaged over its epochs (NaN without MEKF)",
    "nees_count": "number of MEKF epochs in the NEES average",
    "max_rate_deg_s": "largest body rate magnitude over the run",
    "box_active_fraction": "minmax estimator: fraction of epochs with the search box active (NaN otherwise)",
}

#: Wheel-loop trace channels (:class:`~adcskit.simulation.WheelSimulationResult`): name (the
#: per-wheel ``speed_<j>`` and ``h_<j>`` by their base) -> (units, long_name), SI.
WHEEL_CHANNEL_INFO: dict[str, tuple[str, str]] = {
    "error": ("rad", "pointing error to the target in mode point, sun-axis angle to the sun in mode sun, "
                     "NaN in mode detumble"),
    "omega_x": ("rad/s", "body rate, body x"),
    "omega_y": ("rad/s", "body rate, body y"),
    "omega_z": ("rad/s", "body rate, body z"),
    "rate": ("rad/s", "body rate magnitude"),
    "h_body_x": ("N m s", "wheel angular momentum A h, body x"),
    "h_body_y": ("N m s", "wheel angular momentum A h, body y"),
    "h_body_z": ("N m s", "wheel angular momentum A h, body z"),
    "h_wheels": ("N m s", "wheel angular momentum magnitude |A h|"),
    "H_eci_x": ("N m s", "total angular momentum (body + wheels), ECI x"),
    "H_eci_y": ("N m s", "total angular momentum (body + wheels), ECI y"),
    "H_eci_z": ("N m s", "total angular momentum (body + wheels), ECI z"),
    "dipole_x": ("A m^2", "commanded magnetorquer dipole, body x"),
    "dipole_y": ("A m^2", "commanded magnetorquer dipole, body y"),
    "dipole_z": ("A m^2", "commanded magnetorquer dipole, body z"),
    "mode": ("1", "mode of the mode manager (integer code, see flag_values and flag_meanings)"),
    "knowledge_error": ("rad", "knowledge error: rotation angle from the true to the estimated attitude"),
    "speed": ("rad/s", "wheel speed relative to the body"),
    "h": ("N m s", "wheel axial angular momentum"),
    "thruster_torque_x": ("N m", "unloading-thruster torque over the step ending at time, body x"),
    "thruster_torque_y": ("N m", "unloading-thruster torque over the step ending at time, body y"),
    "thruster_torque_z": ("N m", "unloading-thruster torque over the step ending at time, body z"),
    "thruster_impulse_eci_x": ("N m s", "unloading-thruster angular impulse since t = 0, ECI x"),
    "thruster_impulse_eci_y": ("N m s", "unloading-thruster angular impulse since t = 0, ECI y"),
    "thruster_impulse_eci_z": ("N m s", "unloading-thruster angular impulse since t = 0, ECI z"),
    "propellant": ("kg", "cumulative propellant of the unloading thrusters"),
    "nees": ("1", "MEKF normalised estimation error squared, last value in the metrics window (NaN before)"),
}
#: Third dimension of the wheel loop's indexed channels.
WHEEL_CHANNEL_DIMS: dict[str, str] = {"speed": "wheel", "h": "wheel"}

#: Wheel-loop metrics -> long_name (units from the name, :func:`metric_units`).
WHEEL_METRIC_INFO: dict[str, str] = {
    "t_detumbled_s": "time of the switch detumble -> sun (NaN: never)",
    "t_acquired_s": "time of the switch sun -> point (NaN: never)",
    "final_mode": "mode at the end of the run (integer code, see flag_values and flag_meanings)",
    "pointing_mean_deg": "mean pointing error over [metrics_from_s, t_final] while in mode point",
    "pointing_rms_deg": "RMS pointing error over [metrics_from_s, t_final] while in mode point",
    "pointing_max_deg": "maximum pointing error over [metrics_from_s, t_final] while in mode point",
    "pointing_fraction": "fraction of [metrics_from_s, t_final] spent in mode point",
    "settling_time_s": "last time the pointing error exceeded settle_band_deg while pointing (NaN: not pointing at "
                       "the end)",
    "knowledge_rms_deg": "RMS knowledge error (estimate vs truth) over [metrics_from_s, t_final]",
    "final_rate_deg_s": "body rate magnitude at t_final",
    "max_rate_deg_s": "largest body rate magnitude over [metrics_from_s, t_final]",
    "max_wheel_speed_rpm": "largest wheel speed magnitude over the run",
    "max_wheel_momentum_nms": "largest wheel angular momentum |A h| over the run",
    "final_wheel_momentum_nms": "wheel angular momentum |A h| at t_final",
    "max_dipole_am2": "largest commanded dipole norm over the run",
    "momentum_drift_rel": "max |H_eci(t) - H_eci(0)| / |H_eci(0)| over the trace grid",
    "final_sun_angle_deg": "angle of the sun axis to the sun at t_final",
    "propellant_kg": "propellant used by the unloading thrusters",
    "thruster_impulse_ns": "total impulse of the unloading thrusters, sum f_max t_on",
    "thruster_on_time_s": "commanded on-time of the unloading thrusters, all thrusters",
    "unload_count": "thruster unloading episodes started",
    "unload_time_s": "time spent unloading with thrusters",
    "nees_mean": "MEKF NEES averaged over the control periods of [metrics_from_s, t_final] (6: consistent)",
    "nees_count": "number of MEKF epochs in the NEES average",
}

#: Wheel-loop dispersed parameters: name -> (dims after ``sample``, units, long_name).
#: ``null_momentum`` is one per wheel for the whole campaign (no ``sample`` dimension).
_WHEEL_PARAM_INFO: dict[str, tuple[tuple[str, ...], str, str]] = {
    "inertia": (("row", "col"), "kg m^2", "dispersed inertia matrix without the wheels' axial inertia, body axes"),
    "inertia_physical": ((), "1", "dispersed principal moments satisfy the triangle inequality"),
    "wheel_axes": (("axis", "wheel"), "1", "dispersed (misaligned) wheel spin axes, body axes, one column per wheel"),
    "initial_quaternion": (("quaternion_component",), "1", "initial attitude quaternion (scalar last)"),
    "initial_rate": (("axis",), "rad/s", "initial body rate"),
    "gyro_bias": (("axis",), "rad/s", "initial gyro bias"),
    "sensor_noise_scale": ((), "1", "scale of every sensor noise standard deviation"),
    "null_momentum": (("wheel",), "N m s", "null-motion wheel-momentum bias h* (all samples)"),
}

#: Unit suffixes of metric names, longest first.
_SUFFIX_UNITS = (("_deg_s", "deg/s"), ("_rad_s", "rad/s"), ("_rpm", "rpm"), ("_nms", "N m s"),
                 ("_nm", "N m"), ("_ns", "N s"), ("_am2", "A m^2"), ("_deg", "deg"), ("_rad", "rad"),
                 ("_kg", "kg"), ("_s", "s"))

#: Dispersed parameters: name -> (trailing dims, units, long_name).
_PARAM_INFO: dict[str, tuple[tuple[str, ...], str, str]] = {
    "inertia": (("row", "col"), "kg m^2", "dispersed inertia matrix, body axes"),
    "inertia_physical": ((), "1", "dispersed principal moments satisfy the triangle inequality"),
    "thrust": (("thruster",), "N", "dispersed thrust level"),
    "mass_flow": (("thruster",), "kg/s", "mass flow at full thrust"),
    "torque_authority": ((), "N m", "torque available in every direction"),
    "directions": (("thruster", "axis"), "1", "dispersed thrust direction, body axes"),
    "delay": ((), "s", "thruster command delay"),
    "initial_quaternion": (("quaternion_component",), "1", "initial attitude quaternion (scalar last)"),
    "initial_rate": (("axis",), "rad/s", "initial body rate"),
    "gyro_bias": (("axis",), "rad/s", "initial gyro bias"),
    "disturbance_scale": ((), "1", "scale of the disturbance torque"),
}

_INDEXED = re.compile(r"(?P<base>.+)_(?P<j>\d+)\Z")


def metric_units(name: str) -> str:
    """Units of a metric from its name's suffix (``"1"``: dimensionless or a count).

    Parameters
    ----------
    name : str
        A metric name such as ``"pointing_rms_deg"``.

    Returns
    -------
    str

    Examples
    --------
    >>> from adcskit.simulation.export import metric_units
    >>> metric_units("pointing_rms_deg"), metric_units("max_rate_deg_s"), metric_units("firings")
    ('deg', 'deg/s', '1')
    """
    if not isinstance(name, str):
        raise InputTypeError(f"name must be a str; got {short_repr(name)}")
    for suffix, unit in _SUFFIX_UNITS:
        if name.endswith(suffix):
            return unit
    return "1"


def _xarray() -> Any:
    try:
        import xarray
    except ImportError as exc:  # pragma: no cover - exercised by monkeypatching in the tests
        raise SolverError(f"exporting a simulation result needs xarray, which is not installed; "
                          f"{EXPORT_EXTRA_HINT}") from exc
    return xarray


def _group_channels(channels: tuple[str, ...],
                    dims: dict[str, str] | None = None) -> list[tuple[str, list[int], str | None]]:
    """[(variable name, channel indices, third dim or None)] in channel order."""
    dims = CHANNEL_DIMS if dims is None else dims
    out: list[tuple[str, list[int], str | None]] = []
    seen: dict[str, int] = {}
    for c, name in enumerate(channels):
        m = _INDEXED.match(name)
        if m and m["base"] not in channels:
            base = m["base"]
            if base in seen:
                out[seen[base]][1].append(c)
            else:
                seen[base] = len(out)
                out.append((base, [c], dims.get(base, f"{base}_index")))
        else:
            out.append((name, [c], None))
    return out


def _scenario_toml(scenario: Any) -> str:
    from adcskit.config import dump_toml

    return dump_toml(scenario.to_dict())


#: CF flag attributes of the wheel loop's mode codes (``mode``, ``final_mode``).
_MODE_FLAGS: dict[str, Any] = {"flag_values": np.arange(len(MODE_NAMES), dtype=np.int8),
                               "flag_meanings": " ".join(MODE_NAMES)}


def _mode_codes(values: np.ndarray) -> np.ndarray:
    """Mode indices as int8 codes (float kept when a value is not finite: a failed sample)."""
    v = np.asarray(values, dtype=float)
    return v.astype(np.int8) if np.all(np.isfinite(v)) else v


def _metric_vars(metrics: dict[str, np.ndarray], info: dict[str, str], data: dict[str, Any], modes: bool) -> None:
    for name, v in metrics.items():
        attrs = {"units": metric_units(name), "long_name": info.get(name, name)}
        if modes and name == "final_mode":
            data[name] = (("sample",), _mode_codes(v), attrs | dict(_MODE_FLAGS))
        else:
            data[name] = (("sample",), np.asarray(v, dtype=float), attrs)


def _param_vars(params: dict[str, Any], n: int, info: dict[str, tuple[tuple[str, ...], str, str]],
                data: dict[str, Any]) -> None:
    for name, v in params.items():
        arr = np.asarray(v)
        tail, units, long_name = info.get(name, ((), "", name))
        per_sample = arr.ndim >= 1 and arr.shape[0] == n and len(tail) == arr.ndim - 1
        if per_sample:
            dims: tuple[str, ...] = ("sample",) + tail
        elif len(tail) == arr.ndim and name in info:  # one value for the whole campaign
            dims = tail
        else:
            dims = ("sample",) + tuple(f"param_{name}_dim{j}" for j in range(1, arr.ndim))
        data[f"param_{name}"] = (dims, arr, {"units": units, "long_name": long_name})


def _trace_vars(result: Any, info: dict[str, tuple[str, str]], dims: dict[str, str], data: dict[str, Any],
                coords: dict[str, Any], modes: bool) -> None:
    if result.trace is None or result.t is None:
        return
    trace = np.asarray(result.trace, dtype=float)
    coords["time"] = ("time", np.asarray(result.t, dtype=float), {"units": "s", "long_name": "time"})
    for var, idx, dim in _group_channels(tuple(result.channels), dims):
        units, long_name = info.get(var, ("", var))
        attrs: dict[str, Any] = {"units": units, "long_name": long_name}
        if dim is not None:
            data[var] = (("sample", "time", dim), trace[:, :, idx], attrs)
        elif modes and var == "mode":
            data[var] = (("sample", "time"), _mode_codes(trace[:, :, idx[0]]), attrs | dict(_MODE_FLAGS))
        else:
            data[var] = (("sample", "time"), trace[:, :, idx[0]], attrs)


def _run_attrs(result: Any, kind: str, function: str) -> dict[str, Any]:
    rate = float(result.sample_steps_per_s)
    return {
        "title": f"adcskit {kind} Monte-Carlo simulation",
        "Conventions": "CF-1.8",
        "source": f"adcskit {_version()} adcskit.simulation.{function}",
        "adcskit_version": _version(),
        "adcskit_result": type(result).__name__,
        "n_samples": int(result.n_samples),
        "n_steps": int(result.n_steps),
        "runtime_s": float(result.runtime_s),
        "sample_steps_per_s": rate if math.isfinite(rate) else -1.0,
    }


def to_dataset(result: SimulationResult | WheelSimulationResult, scenario: Scenario | WheelScenario | None = None, *,
               rng_seed: Any = None) -> Any:
    """The metrics, traces and parameters of a simulation as an :class:`xarray.Dataset`.

    One function for both loops: a thruster-loop :class:`~adcskit.simulation.SimulationResult`
    or a wheel-loop :class:`~adcskit.simulation.WheelSimulationResult`; the layout follows
    the result (see :mod:`adcskit.simulation.export` for both).

    Parameters
    ----------
    result : SimulationResult or WheelSimulationResult
        From :func:`adcskit.simulation.simulate` or
        :func:`adcskit.simulation.simulate_wheels` (with or without ``record=True``).
    scenario : Scenario or WheelScenario, optional
        The scenario that produced ``result`` (of the same loop); stored as TOML text in the
        attribute ``scenario_toml`` (the result itself does not hold it), and its
        ``metrics_from_s``, ``dt`` and ``record_every`` as attributes.
    rng_seed : int, optional
        The ``rng`` the campaign was run with, stored as the attribute ``rng_seed`` (with it
        and the scenario, :func:`~adcskit.simulation.simulate` or
        :func:`~adcskit.simulation.simulate_wheels` reproduces every sample).

    Returns
    -------
    xarray.Dataset
        Dimensions ``sample`` and, with traces, ``time`` (coordinate, s), and the third
        dimension of indexed channels (``thruster``; ``wheel`` for a wheel run). Each variable
        has ``units`` and ``long_name`` attributes; the wheel loop's modes are ``int8`` codes
        with ``flag_values`` / ``flag_meanings``. Metrics keep their units (degrees, s, kg,
        rpm, as named); traces and parameters are SI (rad, rad/s, kg, N, N m s, A m^2).

    Raises
    ------
    SolverError
        xarray is not installed (``pip install 'adcskit[export]'``).
    InputTypeError
        ``result`` is neither result type, or ``scenario`` is not the scenario of its loop.

    Examples
    --------
    >>> from adcskit.simulation import Scenario, SimSpec, simulate
    >>> from adcskit.simulation.export import to_dataset
    >>> sc = Scenario(sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0, record_every=10))
    >>> ds = to_dataset(simulate(sc, n_samples=3, rng=1, record=True), sc, rng_seed=1)
    >>> ds.sizes["sample"], ds.sizes["time"], ds.sizes["thruster"]
    (3, 11, 6)
    >>> ds["pointing_rms_deg"].attrs["units"], ds["omega_x"].attrs["units"], ds["thrust"].dims
    ('deg', 'rad/s', ('sample', 'time', 'thruster'))
    >>> "[sim]" in ds.attrs["scenario_toml"].splitlines(), ds.attrs["rng_seed"]
    (True, 1)

    A wheel run: per-wheel channels on ``wheel``, modes as CF flags.

    >>> from adcskit.simulation import ModeSpec, WheelScenario, simulate_wheels
    >>> wsc = WheelScenario(modes=ModeSpec(initial="point", sequence=False),
    ...                     sim=SimSpec(dt=0.1, t_final=5.0, metrics_from_s=1.0, record_every=10))
    >>> wds = to_dataset(simulate_wheels(wsc, n_samples=2, rng=1, record=True), wsc)
    >>> wds["speed"].dims, wds["speed"].attrs["units"], wds["max_wheel_speed_rpm"].attrs["units"]
    (('sample', 'time', 'wheel'), 'rad/s', 'rpm')
    >>> wds["mode"].dtype, wds["mode"].attrs["flag_meanings"], wds.attrs["scenario_loader"]
    (dtype('int8'), 'detumble sun point', 'adcskit.simulation.load_wheel_scenario')
    """
    xr = _xarray()
    if isinstance(result, WheelSimulationResult):
        return _wheel_dataset(xr, result, scenario, rng_seed)
    if not isinstance(result, SimulationResult):
        raise InputTypeError(f"result must be a SimulationResult or a WheelSimulationResult (from "
                             f"adcskit.simulation.simulate or simulate_wheels); got {type(result).__name__}")
    if scenario is not None and not isinstance(scenario, Scenario):
        raise InputTypeError(f"scenario must be a Scenario (the thruster loop's, as the result) or None; "
                             f"got {type(scenario).__name__}")
    if rng_seed is not None:
        rng_seed = check_int("rng_seed", rng_seed, minimum=0)
    n = int(result.n_samples)
    data: dict[str, Any] = {}
    coords: dict[str, Any] = {"sample": ("sample", np.arange(n), {"long_name": "Monte-Carlo sample index",
                                                                    "units": "1"})}
    _metric_vars(result.metrics, METRIC_INFO, data, modes=False)
    data["controllable"] = (("sample",), np.asarray(result.controllable, dtype=bool),
                            {"units": "1", "long_name": "thrusters can produce torque in every direction"})
    data["on_time_per_thruster"] = (("sample", "thruster"), np.asarray(result.on_time_per_thruster, dtype=float),
                                    {"units": "s", "long_name": "commanded on-time per thruster"})
    data["noise_seed"] = (("sample",), np.asarray(result.seeds, dtype=np.uint64),
                          {"units": "1", "long_name": "per-sample 64-bit noise seed (SplitMix64 stream)"})
    _param_vars(result.parameters, n, _PARAM_INFO, data)
    _trace_vars(result, CHANNEL_INFO, CHANNEL_DIMS, data, coords, modes=False)
    attrs = _run_attrs(result, "closed-loop", "simulate") | {
        "executor": str(result.executor),
        "success": int(bool(result.success)),
        "message": str(result.message),
        "channels": " ".join(result.channels),
        "metrics_units_note": "metrics in the units their names end with (deg, s, kg); traces and parameters SI",
    }
    if scenario is not None:
        attrs["scenario_toml"] = _scenario_toml(scenario)
        attrs["scenario_loader"] = "adcskit.simulation.load_scenario"
        attrs["metrics_from_s"] = float(scenario.sim.metrics_from_s)
        attrs["dt_s"] = float(scenario.sim.dt)
        attrs["record_every"] = int(scenario.sim.record_every)
    if rng_seed is not None:
        attrs["rng_seed"] = rng_seed
    return xr.Dataset(data_vars=data, coords=coords, attrs=attrs)


def _wheel_dataset(xr: Any, result: WheelSimulationResult, scenario: Any, rng_seed: Any) -> Any:
    """:func:`to_dataset` of a wheel-loop result."""
    if scenario is not None and not isinstance(scenario, WheelScenario):
        raise InputTypeError(f"scenario must be a WheelScenario (the wheel loop's, as the result) or None; "
                             f"got {type(scenario).__name__}")
    if rng_seed is not None:
        rng_seed = check_int("rng_seed", rng_seed, minimum=0)
    n = int(result.n_samples)
    data: dict[str, Any] = {}
    coords: dict[str, Any] = {"sample": ("sample", np.arange(n), {"long_name": "Monte-Carlo sample index",
                                                                    "units": "1"})}
    _metric_vars(result.metrics, WHEEL_METRIC_INFO, data, modes=True)
    data["noise_seed"] = (("sample",), np.asarray(result.seeds, dtype=np.uint64),
                          {"units": "1", "long_name": "per-sample 64-bit noise seed (SplitMix64 stream)"})
    _param_vars(result.parameters, n, _WHEEL_PARAM_INFO, data)
    _trace_vars(result, WHEEL_CHANNEL_INFO, WHEEL_CHANNEL_DIMS, data, coords, modes=True)
    attrs = _run_attrs(result, "reaction-wheel", "simulate_wheels") | {
        "n_chunks": int(result.n_chunks),
        "n_resumed": int(result.n_resumed),
        "success": int(bool(result.success)),
        "message": str(result.message),
        "channels": " ".join(result.channels),
        "mode_names": " ".join(MODE_NAMES),
        "metrics_from_s": float(result.metrics_from_s),
        "metrics_units_note": "metrics in the units their names end with (deg, s, rpm, N m s, A m^2, kg, N s); "
                              "traces and parameters SI",
    }
    if scenario is not None:
        attrs["scenario_toml"] = _scenario_toml(scenario)
        attrs["scenario_loader"] = "adcskit.simulation.load_wheel_scenario"
        attrs["dt_s"] = float(scenario.sim.dt)
        attrs["record_every"] = int(scenario.sim.record_every)
    if rng_seed is not None:
        attrs["rng_seed"] = rng_seed
    return xr.Dataset(data_vars=data, coords=coords, attrs=attrs)


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("adcskit")
    except PackageNotFoundError:  # pragma: no cover - source checkout without install
        return "unknown"


def _target(name: str, path: Any) -> Path:
    """A path to write: its parent directory must exist (nothing is created above it)."""
    p = check_path(name, path)
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{name} must be in an existing directory; got {str(p)!r} ({str(parent)!r} is not a directory)")
    return p


def _as_dataset(obj: Any, scenario: Any, rng_seed: Any) -> Any:
    xr = _xarray()
    if isinstance(obj, xr.Dataset):
        if scenario is not None or rng_seed is not None:
            raise InputError("scenario and rng_seed apply to a simulation result, not to a Dataset "
                             "(pass them to to_dataset); got a Dataset with scenario/rng_seed")
        return obj
    return to_dataset(obj, scenario, rng_seed=rng_seed)


def write_netcdf(result: Any, path: Any, scenario: Scenario | WheelScenario | None = None, *,
                 rng_seed: Any = None) -> Path:
    """Write a simulation result (or its :func:`to_dataset`) as a netCDF3 file.

    Uses xarray's ``scipy`` engine (netCDF3, 64-bit offset format: no C library needed).
    NetCDF3 has no 64-bit integer type, so ``noise_seed`` is stored as decimal text (exact);
    :func:`read_dataset` restores it as uint64, and booleans come back as bool through
    xarray's own encoding (the wheel loop's ``int8`` mode codes are netCDF3 bytes).

    Parameters
    ----------
    result : SimulationResult, WheelSimulationResult or xarray.Dataset
        Either loop's result (see :func:`to_dataset`), or a dataset made from one.
    path : str or os.PathLike
        The file to write (overwritten).
    scenario : Scenario or WheelScenario, optional
    rng_seed : int, optional
        See :func:`to_dataset`.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    SolverError
        xarray is not installed (``pip install 'adcskit[export]'``).

    Examples
    --------
    >>> import os, tempfile
    >>> from adcskit.simulation import Scenario, SimSpec, simulate
    >>> from adcskit.simulation.export import read_dataset, write_netcdf
    >>> sc = Scenario(sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0))
    >>> res = simulate(sc, n_samples=3, rng=1, record=True)
    >>> p = write_netcdf(res, os.path.join(tempfile.mkdtemp(), "run.nc"), sc, rng_seed=1)
    >>> ds = read_dataset(p)
    >>> bool((ds["noise_seed"].values == res.seeds).all()), ds["pointing_error"].attrs["units"]
    (True, 'rad')

    A wheel run, with its scenario read back from the file:

    >>> import tomllib
    >>> from adcskit.simulation import ModeSpec, WheelScenario, load_wheel_scenario, simulate_wheels
    >>> wsc = WheelScenario(modes=ModeSpec(initial="point", sequence=False),
    ...                     sim=SimSpec(dt=0.1, t_final=5.0, metrics_from_s=1.0))
    >>> p = write_netcdf(simulate_wheels(wsc, n_samples=2, rng=1, record=True),
    ...                  os.path.join(tempfile.mkdtemp(), "wheels.nc"), wsc, rng_seed=1)
    >>> wds = read_dataset(p)
    >>> wds["h"].dims, wds["h"].attrs["units"], wds["mode"].attrs["flag_meanings"]
    (('sample', 'time', 'wheel'), 'N m s', 'detumble sun point')
    >>> load_wheel_scenario(tomllib.loads(wds.attrs["scenario_toml"])) == wsc
    True
    """
    ds = _as_dataset(result, scenario, rng_seed)
    p = _target("path", path)
    if p.exists() and p.is_dir():
        raise InputError(f"path must be a file path for netCDF; got {str(p)!r} (a directory)")
    out = ds.copy()
    if "noise_seed" in out and out["noise_seed"].dtype == np.uint64:
        attrs = dict(out["noise_seed"].attrs) | {"adcskit_encoding": "uint64 as decimal text (netCDF3)"}
        out["noise_seed"] = (out["noise_seed"].dims, out["noise_seed"].values.astype(str), attrs)
    for k, v in list(out.attrs.items()):
        if isinstance(v, bool):
            out.attrs[k] = int(v)
    try:
        out.to_netcdf(p, engine="scipy", format="NETCDF3_64BIT")
    except OSError as exc:
        raise InputError(f"path cannot be written ({exc.strerror or exc}); got {str(p)!r}") from None
    return p


def write_zarr(result: Any, path: Any, scenario: Scenario | WheelScenario | None = None, *,
               rng_seed: Any = None) -> Path:
    """Write a simulation result (or its :func:`to_dataset`) as a Zarr store (a directory).

    Parameters
    ----------
    result : SimulationResult, WheelSimulationResult or xarray.Dataset
        Either loop's result (see :func:`to_dataset`), or a dataset made from one.
    path : str or os.PathLike
        The store (a directory; overwritten).
    scenario : Scenario or WheelScenario, optional
    rng_seed : int, optional
        See :func:`to_dataset`.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    SolverError
        xarray or zarr is not installed (``pip install 'adcskit[export]'``).

    Examples
    --------
    >>> import os, tempfile
    >>> from adcskit.simulation import Scenario, SimSpec, simulate
    >>> from adcskit.simulation.export import read_dataset, write_zarr
    >>> sc = Scenario(sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0))
    >>> p = write_zarr(simulate(sc, n_samples=3, rng=1), os.path.join(tempfile.mkdtemp(), "run.zarr"), sc)
    >>> read_dataset(p)["pointing_rms_deg"].attrs["units"]
    'deg'
    >>> from adcskit.simulation import ModeSpec, WheelScenario, simulate_wheels
    >>> wsc = WheelScenario(modes=ModeSpec(initial="point", sequence=False),
    ...                     sim=SimSpec(dt=0.1, t_final=5.0, metrics_from_s=1.0))
    >>> p = write_zarr(simulate_wheels(wsc, n_samples=2, rng=1), os.path.join(tempfile.mkdtemp(), "w.zarr"), wsc)
    >>> read_dataset(p)["max_wheel_speed_rpm"].attrs["units"]
    'rpm'
    """
    ds = _as_dataset(result, scenario, rng_seed)
    try:
        import zarr  # noqa: F401
    except ImportError as exc:  # pragma: no cover - zarr comes with the export extra
        raise SolverError(f"write_zarr needs zarr, which is not installed; {EXPORT_EXTRA_HINT}") from exc
    p = _target("path", path)
    if p.exists() and not p.is_dir():
        raise InputError(f"path must be a directory (a Zarr store) or a new path; got {str(p)!r} (an existing file)")
    out = ds.copy()
    for k, v in list(out.attrs.items()):
        if isinstance(v, bool):
            out.attrs[k] = int(v)
    try:
        out.to_zarr(p, mode="w", consolidated=False)
    except OSError as exc:
        raise InputError(f"path cannot be written ({exc.strerror or exc}); got {str(p)!r}") from None
    return p


def read_dataset(path: Any) -> Any:
    """Read a file written by :func:`write_netcdf` or :func:`write_zarr` (loaded in memory).

    Restores ``noise_seed`` as uint64 (netCDF3 stores it as text).

    Parameters
    ----------
    path : str or os.PathLike
        A netCDF file or a Zarr store (directory).

    Returns
    -------
    xarray.Dataset

    Raises
    ------
    SolverError
        xarray is not installed (``pip install 'adcskit[export]'``).
    InputError
        ``path`` does not exist.

    Examples
    --------
    >>> import os, tempfile
    >>> from adcskit.simulation import Scenario, SimSpec, simulate
    >>> from adcskit.simulation.export import read_dataset, write_netcdf
    >>> sc = Scenario(sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0))
    >>> p = write_netcdf(simulate(sc, n_samples=2, rng=1), os.path.join(tempfile.mkdtemp(), "r.nc"))
    >>> read_dataset(p)["noise_seed"].dtype
    dtype('uint64')
    """
    xr = _xarray()
    p = check_path("path", path, must_exist=True)
    try:
        if p.is_dir():
            ds = xr.open_zarr(p, consolidated=False).load()
        else:
            with xr.open_dataset(p, engine="scipy") as f:
                ds = f.load()
    except (OSError, ValueError, TypeError, KeyError) as exc:
        kind = "a Zarr store" if p.is_dir() else "a netCDF3 file"
        raise InputError(f"path must be {kind} written by write_netcdf/write_zarr; got {str(p)!r} "
                         f"({type(exc).__name__}: {str(exc)[:120]})") from None
    if "noise_seed" in ds and ds["noise_seed"].dtype != np.uint64:
        attrs = {k: v for k, v in ds["noise_seed"].attrs.items() if k != "adcskit_encoding"}
        ds["noise_seed"] = (ds["noise_seed"].dims, np.array([int(s) for s in ds["noise_seed"].values],
                                                           dtype=np.uint64), attrs)
    return ds
