"""Export, envelopes and sign-off of closed-loop results (issue 25, items 4 wiring and 5).

One tiny campaign (12 samples x 100 steps, every step recorded) serves every test; the
simulator kernel is compiled once and cached (see ``docs/simulation.md``).
"""

from __future__ import annotations

import dataclasses
import math
import sys
import tomllib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from adcskit.errors import InputError, InputTypeError, SolverError
from adcskit.simulation import (
    MODE_NAMES,
    DispersionSpec,
    EstimatorSpec,
    GuidanceSpec,
    ModeSpec,
    Scenario,
    SimSpec,
    ThrusterSpec,
    ThrusterUnloadSpec,
    WheelDispersionSpec,
    WheelScenario,
    WheelSpec,
    load_scenario,
    load_wheel_scenario,
    simulate,
    simulate_wheels,
)
from adcskit.simulation import envelopes as env
from adcskit.simulation import export as ex
from adcskit.simulation import signoff as so
from adcskit.uncertainty import check_requirements

xr = pytest.importorskip("xarray")

pytestmark = pytest.mark.compile


def _scenario(record_every: int = 1) -> Scenario:
    return Scenario(guidance=GuidanceSpec(kind="step", target_rotvec_deg=(0.5, 0.0, 0.0)),
                    dispersions=DispersionSpec(inertia_rel=0.05, initial_rate_deg_s=0.01),
                    sim=SimSpec(dt=0.02, t_final=2.0, metrics_from_s=1.0, record_every=record_every))


@pytest.fixture(scope="module")
def run():
    sc = _scenario()
    return sc, simulate(sc, n_samples=12, rng=3, record=True)


# ------------------------------------------------------------------------------------ export


def test_dataset_layout_units_and_scenario(run):
    sc, res = run
    ds = ex.to_dataset(res, sc, rng_seed=3)
    assert dict(ds.sizes) == {"sample": 12, "time": 101, "thruster": 6, "row": 3, "col": 3, "axis": 3,
                              "quaternion_component": 4}
    for name in res.metrics:
        np.testing.assert_array_equal(ds[name].values, res.metrics[name])
        assert ds[name].attrs["units"] == ex.metric_units(name) and ds[name].attrs["long_name"]
    assert ds["pointing_rms_deg"].attrs["units"] == "deg" and ds["settling_time_s"].attrs["units"] == "s"
    assert ds["propellant_kg"].attrs["units"] == "kg" and ds["max_rate_deg_s"].attrs["units"] == "deg/s"
    # traces: SI, one variable per channel, indexed thrust channels grouped on "thruster"
    c = res.channels.index("omega_y")
    np.testing.assert_array_equal(ds["omega_y"].values, res.trace[:, :, c])
    assert ds["omega_y"].attrs["units"] == "rad/s" and ds["pointing_error"].attrs["units"] == "rad"
    np.testing.assert_array_equal(ds["thrust"].values, res.trace[:, :, res.channels.index("thrust_0"):])
    np.testing.assert_array_equal(ds["time"].values, res.t)
    np.testing.assert_array_equal(ds["noise_seed"].values, res.seeds)
    np.testing.assert_array_equal(ds["param_inertia"].values, res.parameters["inertia"])
    assert ds["param_inertia"].attrs["units"] == "kg m^2"
    # the scenario's TOML text reads back to the same scenario
    assert load_scenario(tomllib.loads(ds.attrs["scenario_toml"])) == sc
    assert ds.attrs["rng_seed"] == 3 and ds.attrs["metrics_from_s"] == 1.0 and ds.attrs["channels"].split() == list(res.channels)


def test_dataset_without_traces_has_no_time(run):
    sc, _ = run
    res = simulate(sc, n_samples=2, rng=0)
    ds = ex.to_dataset(res)
    assert "time" not in ds.sizes and "scenario_toml" not in ds.attrs and "pointing_rms_deg" in ds


@pytest.mark.parametrize("fmt", ["netcdf", "zarr"])
def test_round_trip_values_and_units(run, tmp_path, fmt):
    sc, res = run
    ds = ex.to_dataset(res, sc, rng_seed=3)
    if fmt == "zarr":
        pytest.importorskip("zarr")
        path = ex.write_zarr(res, tmp_path / "run.zarr", sc, rng_seed=3)
    else:
        path = ex.write_netcdf(res, tmp_path / "run.nc", sc, rng_seed=3)
    back = ex.read_dataset(path)
    assert set(back.data_vars) == set(ds.data_vars)
    for name in ds.variables:
        np.testing.assert_array_equal(back[name].values, ds[name].values, err_msg=name)  # NaN == NaN here
        assert back[name].dtype == ds[name].dtype or (fmt == "netcdf" and back[name].dtype.kind == ds[name].dtype.kind
                                                      and back[name].dtype.kind == "i"), name
        assert back[name].attrs.get("units") == ds[name].attrs.get("units"), name
        assert back[name].attrs.get("long_name") == ds[name].attrs.get("long_name"), name
    assert back.attrs["scenario_toml"] == ds.attrs["scenario_toml"]
    assert back["noise_seed"].dtype == np.uint64


def test_write_accepts_a_dataset_and_refuses_mixed_arguments(run, tmp_path):
    sc, res = run
    ds = ex.to_dataset(res, sc)
    p = ex.write_netcdf(ds, tmp_path / "d.nc")
    assert ex.read_dataset(p).attrs["n_samples"] == 12
    with pytest.raises(InputError, match="scenario and rng_seed"):
        ex.write_netcdf(ds, tmp_path / "e.nc", sc)
    with pytest.raises(InputError, match="a directory"):
        ex.write_netcdf(res, tmp_path)


def test_missing_xarray_names_the_extra(run, monkeypatch):
    _, res = run
    monkeypatch.setitem(sys.modules, "xarray", None)  # import xarray -> ImportError
    with pytest.raises(SolverError, match=r"adcskit\[export\]"):
        ex.to_dataset(res)


def test_export_type_errors(run):
    sc, res = run
    with pytest.raises(InputTypeError, match="SimulationResult"):
        ex.to_dataset({"metrics": {}})
    with pytest.raises(InputTypeError, match="scenario"):
        ex.to_dataset(res, "scenario.toml")
    with pytest.raises(InputError, match="rng_seed"):
        ex.to_dataset(res, sc, rng_seed=-1)
    with pytest.raises(InputError, match="must be an existing"):
        ex.read_dataset("/nonexistent/run.nc")


# ------------------------------------------------------------------------------ wheel export

#: 12 x 10 mN cold-gas unloading thrusters in +-pairs (as tests/simulation/test_wheels.py's JETS).
_POS = ((0.1, 0.0, 0.0), (-0.1, 0.0, 0.0), (0.0, 0.1, 0.0), (0.0, -0.1, 0.0), (0.0, 0.0, 0.15), (0.0, 0.0, -0.15))
_DIR = ((0.0, 1.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, 1.0), (0.0, 0.0, -1.0), (1.0, 0.0, 0.0), (-1.0, 0.0, 0.0))
_JETS = ThrusterSpec(positions=_POS + _POS, directions=_DIR + tuple((-a, -b, -c) for a, b, c in _DIR),
                     f_max=0.01, mdot=1.4e-5, t_min=0.01)


def _wheel_scenario(extras: bool = True) -> WheelScenario:
    """Inertial hold of the 12U reference with dispersions; wheels at |A h| = 0.0168 N m s, above
    the unloading start (0.01 N m s), so that the thrusters fire within the 10 s."""
    kw = dict(thruster_unloading=ThrusterUnloadSpec(thrusters=_JETS, start_nms=0.01, stop_nms=0.002, torque_nm=5e-4),
              estimator=EstimatorSpec(kind="mekf")) if extras else {}
    return WheelScenario(modes=ModeSpec(initial="point", sequence=False, pointing="inertial"),
                         wheels=WheelSpec.pyramid(initial_speed_rpm=(3000.0, 3000.0, 2000.0, 3500.0)),
                         dispersions=WheelDispersionSpec(inertia_rel=0.05, initial_rate_deg_s=0.05, sensor_noise_rel=0.2,
                                                         wheel_misalignment_deg=0.1),
                         initial_rate_deg_s=(0.0, 0.0, 0.0),
                         sim=SimSpec(dt=0.1, t_final=10.0, metrics_from_s=2.0, record_every=2), **kw)


@pytest.fixture(scope="module")
def wheel_run():
    sc = _wheel_scenario()
    return sc, simulate_wheels(sc, n_samples=5, rng=4, record=True)


def test_wheel_dataset_has_every_metric_channel_and_parameter_with_units(wheel_run):
    sc, res = wheel_run
    ds = ex.to_dataset(res, sc, rng_seed=4)
    assert dict(ds.sizes) == {"sample": 5, "time": 51, "wheel": 4, "row": 3, "col": 3, "axis": 3,
                              "quaternion_component": 4}
    for name in res.metrics:  # every metric, declared (a long_name of its own) and with its unit
        np.testing.assert_array_equal(ds[name].values, res.metrics[name], err_msg=name)
        assert ds[name].attrs["units"] == ex.metric_units(name) and name in ex.WHEEL_METRIC_INFO, name
    units = {"max_wheel_speed_rpm": "rpm", "max_wheel_momentum_nms": "N m s", "max_dipole_am2": "A m^2",
             "thruster_impulse_ns": "N s", "propellant_kg": "kg", "t_acquired_s": "s", "final_rate_deg_s": "deg/s",
             "momentum_drift_rel": "1", "nees_mean": "1"}
    assert {k: ds[k].attrs["units"] for k in units} == units
    # every channel: scalar ones under their own name, speed_j / h_j on "wheel", SI units
    for c, name in enumerate(res.channels):
        base, _, j = name.rpartition("_")
        if base in ("speed", "h") and j.isdigit():
            np.testing.assert_array_equal(ds[base].values[:, :, int(j)], res.trace[:, :, c], err_msg=name)
        elif name != "mode":
            np.testing.assert_array_equal(ds[name].values, res.trace[:, :, c], err_msg=name)
            assert ds[name].attrs["units"] == ex.WHEEL_CHANNEL_INFO[name][0] and ds[name].dims == ("sample", "time")
    assert ds["speed"].dims == ds["h"].dims == ("sample", "time", "wheel")
    chan_units = {"speed": "rad/s", "h": "N m s", "omega_x": "rad/s", "error": "rad", "H_eci_z": "N m s",
                  "dipole_y": "A m^2", "thruster_torque_x": "N m", "thruster_impulse_eci_y": "N m s",
                  "propellant": "kg", "nees": "1"}
    assert {k: ds[k].attrs["units"] for k in chan_units} == chan_units
    # the extra parts' channels carry data: the thrusters fired, the filter ran
    assert ds["propellant"].values[:, -1].min() > 0 and np.isfinite(ds["nees"].values[:, -1]).all()
    # modes: int8 codes with CF flag attributes (flag_values / flag_meanings, CF-1.8 section 3.5)
    for name in ("mode", "final_mode"):
        assert ds[name].dtype == np.int8 and ds[name].attrs["flag_meanings"] == " ".join(MODE_NAMES)
        np.testing.assert_array_equal(ds[name].attrs["flag_values"], [0, 1, 2])
    np.testing.assert_array_equal(ds["mode"].values, res.trace[:, :, res.channels.index("mode")])
    # parameters: per sample, except the campaign's null-motion bias (one per wheel)
    np.testing.assert_array_equal(ds["param_wheel_axes"].values, res.parameters["wheel_axes"])
    assert ds["param_wheel_axes"].dims == ("sample", "axis", "wheel") and ds["param_null_momentum"].dims == ("wheel",)
    assert ds["param_initial_rate"].attrs["units"] == "rad/s" and ds["param_inertia"].attrs["units"] == "kg m^2"
    assert np.ptp(ds["param_sensor_noise_scale"].values) > 0  # dispersed
    np.testing.assert_array_equal(ds["noise_seed"].values, res.seeds)
    assert load_wheel_scenario(tomllib.loads(ds.attrs["scenario_toml"])) == sc
    assert ds.attrs["scenario_loader"] == "adcskit.simulation.load_wheel_scenario"
    assert ds.attrs["adcskit_result"] == "WheelSimulationResult" and ds.attrs["adcskit_version"]
    assert ds.attrs["rng_seed"] == 4 and ds.attrs["metrics_from_s"] == 2.0 and ds.attrs["dt_s"] == 0.1


def test_wheel_dataset_without_extras_or_traces(wheel_run):
    # the thrusters' and the filter's metrics and channels exist only when those parts are configured
    sc = _wheel_scenario(extras=False)
    ds = ex.to_dataset(simulate_wheels(sc, n_samples=2, rng=0, record=True), sc)
    assert not {"propellant_kg", "nees_mean", "thruster_torque_x", "propellant", "nees"} & set(ds.data_vars)
    assert "speed" in ds and "max_wheel_speed_rpm" in ds
    ds = ex.to_dataset(simulate_wheels(sc, n_samples=2, rng=0))
    assert "time" not in ds.sizes and "scenario_toml" not in ds.attrs and ds["final_mode"].dtype == np.int8


@pytest.mark.parametrize("fmt", ["netcdf", "zarr"])
def test_wheel_round_trip_values_dims_and_units(wheel_run, tmp_path, fmt):
    sc, res = wheel_run
    ds = ex.to_dataset(res, sc, rng_seed=4)
    if fmt == "zarr":
        pytest.importorskip("zarr")
        path = ex.write_zarr(res, tmp_path / "wheels.zarr", sc, rng_seed=4)
    else:
        path = ex.write_netcdf(res, tmp_path / "wheels.nc", sc, rng_seed=4)
    back = ex.read_dataset(path)
    assert set(back.data_vars) == set(ds.data_vars) and dict(back.sizes) == dict(ds.sizes)
    for name in ds.variables:
        np.testing.assert_array_equal(back[name].values, ds[name].values, err_msg=name)  # NaN == NaN here
        assert back[name].dims == ds[name].dims, name
        assert back[name].dtype == ds[name].dtype or (fmt == "netcdf" and back[name].dtype.kind == ds[name].dtype.kind
                                                      and back[name].dtype.kind == "i"), name
        for key in ("units", "long_name", "flag_meanings"):
            assert back[name].attrs.get(key) == ds[name].attrs.get(key), (name, key)
    assert list(back["mode"].attrs["flag_values"]) == [0, 1, 2] and back["mode"].dtype == np.int8
    assert back.attrs["scenario_toml"] == ds.attrs["scenario_toml"] and back.attrs["rng_seed"] == 4


def test_export_refuses_the_other_loops_scenario(run, wheel_run):
    sc, res = run
    wsc, wres = wheel_run
    with pytest.raises(InputTypeError, match="WheelScenario"):
        ex.to_dataset(wres, sc)
    with pytest.raises(InputTypeError, match="must be a Scenario"):
        ex.to_dataset(res, wsc)


# ----------------------------------------------------------------------------------- envelopes


def test_envelope_matches_numpy_percentiles():
    # closed form: 0..100 in each column -> the p-th percentile is p (linear interpolation)
    e = env.envelope(np.arange(101.0)[:, None] * np.ones((1, 4)), np.arange(4.0))
    for name, p in (("p1", 1), ("p5", 5), ("median", 50), ("p95", 95), ("p99", 99)):
        np.testing.assert_allclose(getattr(e, name), p, rtol=0, atol=1e-12)
    x = np.random.default_rng(5).normal(size=(300, 7))
    x[0, 2] = np.nan  # ignored
    e = env.envelope(x, np.arange(7.0))
    np.testing.assert_allclose(e.p95, np.nanpercentile(x, 95, axis=0), rtol=1e-15)
    with pytest.raises(InputError, match="one time per column"):
        env.envelope(x, np.arange(6.0))
    with pytest.raises(InputError, match="2-D"):
        env.envelope(np.ones(3), [0.0, 1.0, 2.0])


@settings(max_examples=40, deadline=None)
@given(arrays(np.float64, st.tuples(st.integers(1, 30), st.integers(1, 5)),
              elements=st.floats(-1e6, 1e6, allow_nan=False)))
def test_envelope_bands_are_ordered(x):
    e = env.envelope(x, np.arange(x.shape[1], dtype=float))
    for lo, hi in ((e.p1, e.p5), (e.p5, e.median), (e.median, e.p95), (e.p95, e.p99)):
        assert np.all(lo <= hi + 1e-9 * (1 + np.abs(hi)))
    assert np.all(e.p1 >= x.min(axis=0) - 1e-9 * (1 + np.abs(x.min(axis=0))))


def test_new_indexed_channels_group_and_plot(run):
    # channels a later model adds (here: wheel speeds, rad/s) export and plot without changes
    _, res = run
    chans = tuple(c.replace("thrust_", "wheel_speed_") for c in res.channels)
    wheels = dataclasses.replace(res, channels=chans)
    ds = ex.to_dataset(wheels)
    assert ds["wheel_speed"].dims == ("sample", "time", "wheel_speed_index") and ds.sizes["wheel_speed_index"] == 6
    fig = env.envelope_figure(wheels, "wheel_speed", scale=30 / math.pi, units="rpm", worst=1)
    assert len(fig.axes) == 6 and fig.axes[0].get_ylabel() == "wheel_speed_0 [rpm]"


def test_worst_samples_rank_by_a_stated_metric(run):
    _, res = run
    m = res.metrics["pointing_max_deg"]
    np.testing.assert_array_equal(env.worst_samples(res, 3, by="pointing_max_deg"), np.argsort(-m, kind="stable")[:3])
    peak = np.max(np.abs(res.trace[:, :, res.channels.index("omega_x")]), axis=1)
    assert env.worst_samples(res, 1, by="peak", channel="omega_x")[0] == int(np.argmax(peak))
    with pytest.raises(InputError, match="by must be one of"):
        env.worst_samples(res, 2, by="pointing_worst")
    with pytest.raises(InputError, match="channel"):
        env.worst_samples(res, 2, by="peak")


def test_figures_have_units_and_name_the_ranking(run):
    _, res = run
    fig = env.attitude_error_figure(res, axes=True, worst=2)
    labels = [ax.get_ylabel() for ax in fig.axes]
    assert labels == ["pointing error [deg]", "error about x [deg]", "error about y [deg]", "error about z [deg]"]
    assert fig.axes[0].get_yscale() == "log" and fig.axes[-1].get_xlabel() == "time [s]"
    legend = {t.get_text() for t in fig.legends[0].get_texts()}
    worst = env.worst_samples(res, 2, by="pointing_max_deg")
    assert legend == {"median", "5-95 %", "1-99 %", f"worst by pointing_max_deg: sample {worst[0]}",
                      f"sample {worst[1]}"}
    fig = env.body_rate_figure(res, worst=1)
    assert [ax.get_ylabel() for ax in fig.axes] == [f"rate about {a} [deg/s]" for a in "xyz"]
    fig = env.envelope_figure(res, "propellant", units="kg", worst=0)
    assert fig.axes[0].get_ylabel() == "propellant [kg]"
    # the plotted median is the trace's median in the plotted unit (rad -> deg)
    fig = env.envelope_figure(res, "pointing_error", worst=0, label="pointing error")
    line = fig.axes[0].get_lines()[0]
    np.testing.assert_allclose(line.get_ydata(), np.degrees(np.median(res.trace[:, :, 3], axis=0)), rtol=1e-12)
    with pytest.raises(InputError, match="channel must be one of"):
        env.envelope_figure(res, "wheel_speed")
    with pytest.raises(InputError, match="record=True"):
        env.attitude_error_figure(simulate(_scenario(), n_samples=2, rng=0))


def test_log_axis_has_a_floor():
    # issue 41 item 8: with true knowledge the error before a 5 deg step sits at rounding level
    # (2e-15 deg); matplotlib's own log axis went down to 4e-16 deg. Now it spans at most
    # LOG_DECADES below its top (5 deg, the step)
    from adcskit.simulation import EstimatorSpec

    sc = Scenario(estimator=EstimatorSpec(kind="truth"),
                  guidance=GuidanceSpec(kind="step", target_rotvec_deg=(0.0, 0.0, 5.0), t_step=1.0),
                  sim=SimSpec(dt=0.05, t_final=5.0, metrics_from_s=2.0, record_every=1))
    res = simulate(sc, n_samples=6, rng=0, record=True)
    pe = np.degrees(res.trace[:, :, res.channels.index("pointing_error")])
    assert 0 < np.min(pe[pe > 0]) < 1e-10  # the rounding-level errors are there
    fig = env.attitude_error_figure(res)
    lo, hi = fig.axes[0].get_ylim()
    top = np.nanmax(pe)
    assert hi == pytest.approx(1.25 * top, rel=1e-9)
    assert lo == pytest.approx(top * 10.0 ** -env.LOG_DECADES / 1.25, rel=1e-9)
    lin = env.attitude_error_figure(res, yscale="linear")  # a linear axis is left to matplotlib
    assert lin.axes[0].get_ylim()[0] <= 0.0


# ------------------------------------------------------------------------------------ sign-off


@pytest.mark.parametrize("metric", so.TRACE_METRICS)
def test_trace_window_equals_the_kernel_metric(run, metric):
    # two implementations of one definition: the kernel's per-step window sums and the
    # re-windowed trace (record_every = 1) over the scenario's own window [metrics_from_s, end]
    sc, res = run
    after = 0.0 if metric == "max_rate_deg_s" else sc.sim.metrics_from_s  # max_rate: whole run
    v, src, exact = so._from_trace(res, sc, metric, after)
    np.testing.assert_allclose(v, res.metrics[metric], rtol=1e-12, atol=1e-15)
    assert exact and "every step" in src


def test_signoff_rows_bounds_and_samples_for_a_bound(run):
    sc, res = run
    reqs = ["R1: pointing_max_deg p95 <= 1 after 1 s", "R2: pointing_max_deg p99 <= 1 after 1.5 s",
            "R3: P(final_error_deg > 2) <= 1 % at 99 % confidence", "R4: settling_time_s max <= 0.01",
            "R5: pointing_rms_deg mean <= 1"]
    t = so.check_simulation(reqs, res, sc)
    # Wilks / Guba, Makai & Pal (2003) Table 1: 59 for 95/95; 299 for p99 at 95 %; 459 for 99/99
    assert t.n_for_bound == (59, 299, 459, None, None)
    assert [r.outcome for r in t.rows][:2] == ["inconclusive", "inconclusive"]  # 12 samples: no bound
    assert t.rows[0].bound == math.inf and t.rows[3].outcome == "not met" and t.rows[4].outcome == "met"
    # a row on the scenario's window is the same verdict as check_requirements on the metric
    direct = check_requirements([reqs[0]], res.metrics, metrics_from_s={"pointing_max_deg": 1.0}, nan_policy="fail")
    assert direct.rows[0].to_dict() == t.rows[0].to_dict()
    assert t.sources[0].startswith("metric, every step over [1, 2] s") and t.sources[1].startswith("trace")
    md = t.to_markdown().splitlines()
    assert md[0].startswith("| id | requirement |") and len(md) == 2 + len(reqs) + 2 and md[2].startswith("| R1 |")
    assert "samples for a bound" in t.to_text().splitlines()[0] and t.message in t.to_text()
    assert not t.success and t.exact


def test_signoff_decimated_traces_are_never_signed_off():
    sc = _scenario(record_every=5)
    res = simulate(sc, n_samples=60, rng=1, record=True)
    t = so.check_simulation(["pointing_max_deg p95 <= 5 after 1.5 s"], res, sc)
    assert t.rows[0].outcome == "met" and not t.exact and not t.success
    assert "decimated" in t.sources[0] and "not signed off" in t.message


def test_signoff_refuses_windows_it_cannot_answer(run):
    sc, res = run
    with pytest.raises(InputError, match="cannot be re-windowed"):
        so.check_simulation(["settling_time_s p95 <= 1 after 1.5 s"], res, sc)
    no_trace = simulate(sc, n_samples=2, rng=0)
    with pytest.raises(InputError, match="record=True"):
        so.check_simulation(["pointing_max_deg p95 <= 1 after 1.5 s"], no_trace, sc)
    with pytest.raises(InputError, match="at most t_final"):
        so.check_simulation(["pointing_max_deg p95 <= 1 after 5 s"], res, sc)
    with pytest.raises(InputError, match="metric of requirement"):
        so.check_simulation(["pointing_worst_deg p95 <= 1"], res, sc)
    with pytest.raises(InputTypeError, match="Scenario"):
        so.check_simulation(["pointing_max_deg p95 <= 1"], res, sc.sim)
