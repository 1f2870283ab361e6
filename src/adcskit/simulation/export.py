"""Export a :class:`~adcskit.simulation.SimulationResult` to an xarray Dataset, netCDF or Zarr.

:func:`to_dataset` lays a Monte-Carlo campaign out on labelled dimensions:

* ``sample`` — one entry per Monte-Carlo sample: every metric of
  :data:`~adcskit.simulation.METRIC_NAMES` (unit in the name, degrees for angles),
  ``controllable``, ``on_time_per_thruster`` (``sample, thruster``), the per-sample noise
  seed ``noise_seed`` and every dispersed parameter as ``param_<name>``;
* ``time`` (s) — the recorded traces (``record=True``), one variable per channel in SI units
  (``pointing_error`` in rad, ``omega_x`` in rad/s, ...); indexed channels (``thrust_0``,
  ``thrust_1``, ...) become one variable with a third dimension (``thrust``:
  ``sample, time, thruster``).

Every variable carries ``units`` and ``long_name`` attributes (CF conventions); the dataset
carries the scenario as TOML text (``scenario_toml``, read back with
:func:`adcskit.simulation.load_scenario` after :func:`tomllib.loads`), the campaign seed
(``rng_seed``, when given), the run's bookkeeping (``n_steps``, ``runtime_s``, ``success``,
``message``, ...) and the adcskit version.

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

__all__ = [
    "CHANNEL_INFO",
    "METRIC_INFO",
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

#: Unit suffixes of metric names, longest first.
_SUFFIX_UNITS = (("_deg_s", "deg/s"), ("_rad_s", "rad/s"), ("_rpm", "rpm"), ("_nms", "N m s"),
                 ("_nm", "N m"), ("_am2", "A m^2"), ("_deg", "deg"), ("_rad", "rad"), ("_kg", "kg"),
                 ("_s", "s"))

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


def _group_channels(channels: tuple[str, ...]) -> list[tuple[str, list[int], str | None]]:
    """[(variable name, channel indices, third dim or None)] in channel order."""
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
                out.append((base, [c], CHANNEL_DIMS.get(base, f"{base}_index")))
        else:
            out.append((name, [c], None))
    return out


def _scenario_toml(scenario: Scenario) -> str:
    from adcskit.config import dump_toml

    return dump_toml(scenario.to_dict())


def to_dataset(result: SimulationResult, scenario: Scenario | None = None, *, rng_seed: Any = None) -> Any:
    """The metrics, traces and parameters of a simulation as an :class:`xarray.Dataset`.

    Parameters
    ----------
    result : SimulationResult
        From :func:`adcskit.simulation.simulate` (with or without ``record=True``).
    scenario : Scenario, optional
        The scenario that produced ``result``; stored as TOML text in the attribute
        ``scenario_toml`` (the result itself does not hold it), and its ``metrics_from_s``
        and ``dt`` as attributes.
    rng_seed : int, optional
        The ``rng`` the campaign was run with, stored as the attribute ``rng_seed`` (with it
        and the scenario, :func:`~adcskit.simulation.simulate` reproduces every sample).

    Returns
    -------
    xarray.Dataset
        Dimensions ``sample`` and, with traces, ``time`` (coordinate, s), ``thruster`` and
        the third dimension of other indexed channels. Each variable has ``units`` and
        ``long_name`` attributes. Metrics keep their units (degrees, s, kg, as named);
        traces and parameters are SI (rad, rad/s, kg, N).

    Raises
    ------
    SolverError
        xarray is not installed (``pip install 'adcskit[export]'``).
    InputTypeError
        ``result`` is not a SimulationResult or ``scenario`` not a Scenario.

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
    """
    xr = _xarray()
    if not isinstance(result, SimulationResult):
        raise InputTypeError(f"result must be a SimulationResult (from adcskit.simulation.simulate); "
                             f"got {type(result).__name__}")
    if scenario is not None and not isinstance(scenario, Scenario):
        raise InputTypeError(f"scenario must be a Scenario or None; got {type(scenario).__name__}")
    if rng_seed is not None:
        rng_seed = check_int("rng_seed", rng_seed, minimum=0)
    n = int(result.n_samples)
    data: dict[str, Any] = {}
    coords: dict[str, Any] = {"sample": ("sample", np.arange(n), {"long_name": "Monte-Carlo sample index",
                                                                    "units": "1"})}
    for name, v in result.metrics.items():
        data[name] = (("sample",), np.asarray(v, dtype=float),
                      {"units": metric_units(name), "long_name": METRIC_INFO.get(name, name)})
    data["controllable"] = (("sample",), np.asarray(result.controllable, dtype=bool),
                            {"units": "1", "long_name": "thrusters can produce torque in every direction"})
    data["on_time_per_thruster"] = (("sample", "thruster"), np.asarray(result.on_time_per_thruster, dtype=float),
                                    {"units": "s", "long_name": "commanded on-time per thruster"})
    data["noise_seed"] = (("sample",), np.asarray(result.seeds, dtype=np.uint64),
                          {"units": "1", "long_name": "per-sample 64-bit noise seed (SplitMix64 stream)"})
    for name, v in result.parameters.items():
        arr = np.asarray(v)
        tail, units, long_name = _PARAM_INFO.get(name, ((), "", name))
        if len(tail) != arr.ndim - 1:
            tail = tuple(f"param_{name}_dim{j}" for j in range(1, arr.ndim))
        data[f"param_{name}"] = (("sample",) + tail, arr, {"units": units, "long_name": long_name})
    if result.trace is not None and result.t is not None:
        trace = np.asarray(result.trace, dtype=float)
        coords["time"] = ("time", np.asarray(result.t, dtype=float), {"units": "s", "long_name": "time"})
        for var, idx, dim in _group_channels(tuple(result.channels)):
            base = var
            units, long_name = CHANNEL_INFO.get(base, ("", base))
            if dim is None:
                data[var] = (("sample", "time"), trace[:, :, idx[0]], {"units": units, "long_name": long_name})
            else:
                data[var] = (("sample", "time", dim), trace[:, :, idx], {"units": units, "long_name": long_name})
    attrs: dict[str, Any] = {
        "title": "adcskit closed-loop Monte-Carlo simulation",
        "Conventions": "CF-1.8",
        "source": f"adcskit {_version()} adcskit.simulation.simulate",
        "n_samples": n,
        "n_steps": int(result.n_steps),
        "runtime_s": float(result.runtime_s),
        "sample_steps_per_s": float(result.sample_steps_per_s) if math.isfinite(result.sample_steps_per_s) else -1.0,
        "executor": str(result.executor),
        "success": int(bool(result.success)),
        "message": str(result.message),
        "channels": " ".join(result.channels),
        "metrics_units_note": "metrics in the units their names end with (deg, s, kg); traces and parameters SI",
    }
    if scenario is not None:
        attrs["scenario_toml"] = _scenario_toml(scenario)
        attrs["metrics_from_s"] = float(scenario.sim.metrics_from_s)
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
            raise InputError("scenario and rng_seed apply to a SimulationResult, not to a Dataset "
                             "(pass them to to_dataset); got a Dataset with scenario/rng_seed")
        return obj
    return to_dataset(obj, scenario, rng_seed=rng_seed)


def write_netcdf(result: Any, path: Any, scenario: Scenario | None = None, *, rng_seed: Any = None) -> Path:
    """Write a simulation result (or its :func:`to_dataset`) as a netCDF3 file.

    Uses xarray's ``scipy`` engine (netCDF3, 64-bit offset format: no C library needed).
    NetCDF3 has no 64-bit integer type, so ``noise_seed`` is stored as decimal text (exact);
    :func:`read_dataset` restores it as uint64, and booleans come back as bool through
    xarray's own encoding.

    Parameters
    ----------
    result : SimulationResult or xarray.Dataset
    path : str or os.PathLike
        The file to write (overwritten).
    scenario : Scenario, optional
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


def write_zarr(result: Any, path: Any, scenario: Scenario | None = None, *, rng_seed: Any = None) -> Path:
    """Write a simulation result (or its :func:`to_dataset`) as a Zarr store (a directory).

    Parameters
    ----------
    result : SimulationResult or xarray.Dataset
    path : str or os.PathLike
        The store (a directory; overwritten).
    scenario : Scenario, optional
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
