"""Closed-loop 3-axis ADCS simulation, batched over Monte-Carlo samples.

The five pieces in one loop: a nonlinear rigid-body plant with gravity-gradient and
disturbance torques on a circular orbit; thrusters from an S3 layout with S4's lag + delay
model; sun sensor (with eclipse), magnetometer, Farrenkopf gyro and optional star tracker,
each at its own rate; per-epoch Wahba determination or the MEKF; hold / step / time-table
guidance; S4's PID + Schmitt loop per axis or a continuous PID with pulse-width modulation;
allocation through :mod:`adcskit.thrusters`. All samples advance together in one numba
kernel (``prange`` over samples).

* :mod:`~adcskit.simulation.scenario` — the scenario as data (frozen dataclasses, TOML);
* :mod:`~adcskit.simulation.core` — :func:`simulate` and :class:`SimulationResult`;
* :mod:`~adcskit.simulation.profiles` — reference tables from optimal-control slews;
* :mod:`~adcskit.simulation.export` — xarray Dataset, netCDF and Zarr export (``adcskit[export]``);
* :mod:`~adcskit.simulation.envelopes` — Monte-Carlo envelope figures of the traces;
* :mod:`~adcskit.simulation.signoff` — a requirement table checked on a result;
* :mod:`~adcskit.simulation.wheels` — reaction wheels, magnetorquers, momentum management and
  a detumble -> sun -> nadir mode sequence in their own batched kernel (:func:`simulate_wheels`).

Layering: this package composes attitude, dynamics, environment, sensors, determination,
estimation, thrusters, control and uncertainty; nothing below imports it.
"""

from adcskit.simulation.core import (
    METRIC_NAMES,
    S3_REFERENCE_A,
    WAHBA_CODES,
    SimulationResult,
    reference_profile,
    simulate,
)
from adcskit.simulation.envelopes import attitude_error_figure, body_rate_figure, envelope_figure
from adcskit.simulation.export import read_dataset, to_dataset, write_netcdf, write_zarr
from adcskit.simulation.scenario import (
    ControllerSpec,
    DispersionSpec,
    DisturbanceSpec,
    EstimatorSpec,
    GuidanceSpec,
    OrbitSpec,
    Scenario,
    SensorSpec,
    SimSpec,
    SpacecraftSpec,
    ThrusterSpec,
    load_scenario,
    scenario_toml,
)
from adcskit.simulation.signoff import SignOffTable, check_simulation
from adcskit.simulation.wheels import (
    MODE_NAMES,
    WHEEL_FILTER_METRIC_NAMES,
    WHEEL_METRIC_NAMES,
    WHEEL_UNLOAD_METRIC_NAMES,
    MagnetorquerSpec,
    ModeSpec,
    ThrusterUnloadSpec,
    WheelControlSpec,
    WheelDispersionSpec,
    WheelScenario,
    WheelSimulationResult,
    WheelSpec,
    load_wheel_scenario,
    simulate_wheels,
    wheel_envelope_figure,
)

__all__ = [
    "METRIC_NAMES", "S3_REFERENCE_A", "WAHBA_CODES", "SimulationResult", "reference_profile", "simulate",
    "ControllerSpec", "DispersionSpec", "DisturbanceSpec", "EstimatorSpec", "GuidanceSpec", "OrbitSpec",
    "Scenario", "SensorSpec", "SimSpec", "SpacecraftSpec", "ThrusterSpec", "load_scenario",
    "scenario_toml",
    "to_dataset", "write_netcdf", "write_zarr", "read_dataset",
    "envelope_figure", "attitude_error_figure", "body_rate_figure",
    "SignOffTable", "check_simulation",
    "MODE_NAMES", "WHEEL_METRIC_NAMES", "WHEEL_UNLOAD_METRIC_NAMES", "WHEEL_FILTER_METRIC_NAMES",
    "MagnetorquerSpec", "ModeSpec",
    "ThrusterUnloadSpec", "WheelControlSpec", "WheelDispersionSpec",
    "WheelScenario", "WheelSimulationResult", "WheelSpec", "wheel_envelope_figure", "load_wheel_scenario",
    "simulate_wheels",
]
