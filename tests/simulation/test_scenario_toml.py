"""Scenarios as TOML: partial files over the defaults, the printed default, unknown keys (issue 41 item 5).

No kernel runs here: loading and printing scenarios only.
"""

from __future__ import annotations

import tomllib

import pytest

from adcskit.cli import main
from adcskit.errors import ConfigError, InputError, InputTypeError
from adcskit.simulation import (
    Scenario,
    WheelScenario,
    load_scenario,
    load_wheel_scenario,
    scenario_toml,
)


def test_partial_table_keeps_the_default_layout(tmp_path):
    # before issue 41: `[thrusters] f_max = 5.0` failed ("thrusters.positions is required")
    path = tmp_path / "my.toml"
    path.write_text("[thrusters]\nf_max = 5.0\n[sim]\nt_final = 20.0\nmetrics_from_s = 10.0\n", encoding="utf-8")
    sc = load_scenario(str(path))
    default = Scenario()
    assert sc.thrusters == default.thrusters.replace(f_max=5.0)
    assert sc.sim == default.sim.replace(t_final=20.0, metrics_from_s=10.0)
    assert sc.replace(thrusters=default.thrusters, sim=default.sim) == default


def test_partial_wheel_table_keeps_the_scenario_default_not_the_class_default():
    # WheelScenario's orbit is the 500 km sun-synchronous reference (97.4 deg), not OrbitSpec()'s GEO
    sc = load_wheel_scenario({"orbit": {"altitude_km": 600.0}})
    assert sc.orbit == WheelScenario().orbit.replace(altitude_km=600.0)
    assert sc.orbit.inclination_deg == 97.4


def test_keys_sized_by_another_follow_it():
    # a part equal to its class default (WheelScenario's wheels: the 4-wheel pyramid) is left to
    # the class: three axes get three inertias and speeds, not the pyramid's four
    sc = load_wheel_scenario({"wheels": {"axes": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}})
    assert sc.wheels.n == 3 and sc.wheels.inertia_kgm2 == (2.4e-5,) * 3
    # the wheel reference's time grid is inherited (dt 0.2 s, not SimSpec's 0.02 s), so a
    # shorter t_final needs its own metrics window; the error says where the rest comes from
    assert load_wheel_scenario({"sim": {"t_final": 60.0, "metrics_from_s": 30.0}}).sim.dt == 0.2
    with pytest.raises(ConfigError, match=r"metrics_from_s.*'adcskit scenario --wheels' prints them"):
        load_wheel_scenario({"sim": {"t_final": 60.0}})


def test_overrides_go_under_the_source():
    sc = load_scenario({"sim": {"t_final": 30.0}}, overrides={"sim": {"t_final": 40.0, "metrics_from_s": 5.0}})
    assert (sc.sim.t_final, sc.sim.metrics_from_s, sc.sim.dt) == (30.0, 5.0, Scenario().sim.dt)


@pytest.mark.parametrize("cls, loader", [(Scenario, load_scenario), (WheelScenario, load_wheel_scenario)])
@pytest.mark.parametrize("comments", [True, False])
def test_printed_default_round_trips(cls, loader, comments):
    text = scenario_toml(cls(), comments=comments)
    assert loader(tomllib.loads(text)) == cls()
    assert loader({}) == cls()


def test_printed_scenario_round_trips_a_changed_one():
    sc = load_scenario({"thrusters": {"failed": [2]}, "dispersions": {"misalignment_deg": 0.5}})
    assert load_scenario(tomllib.loads(scenario_toml(sc))) == sc


def test_comments_carry_units():
    lines = scenario_toml().splitlines()
    for key, note in [("f_max", "# float, N: Thrust when on"), ("gyro_arw", "# float, rad/s^0.5"),
                      ("torque_level", "# 3 floats, N m"), ("altitude_km", "# float, km")]:
        i = next(i for i, line in enumerate(lines) if line.startswith(f"{key} = "))
        assert lines[i - 1].startswith(note), (key, lines[i - 1])


@pytest.mark.parametrize("data, key", [
    ({"thrusters": {"f_maxx": 5.0}}, "thrusters.f_maxx"),
    ({"sim": {"dtt": 0.1}}, "sim.dtt"),
    ({"unknown_part": {"x": 1}}, "unknown_part"),
])
def test_unknown_keys_name_the_key(data, key):
    with pytest.raises(ConfigError, match=f"unknown config key {key}"):
        load_scenario(data)


def test_bad_sources():
    with pytest.raises(InputError, match="does not exist"):
        load_scenario("/nonexistent/scenario.toml")
    with pytest.raises(ConfigError, match="mapping or a TOML path"):
        load_scenario(3.0)
    with pytest.raises(InputTypeError, match="Scenario or a WheelScenario"):
        scenario_toml({"sim": {}})


@pytest.mark.parametrize("wheels", [False, True])
def test_cli_scenario_prints_a_loadable_default(capsys, tmp_path, wheels):
    assert main(["scenario"] + (["--wheels"] if wheels else [])) == 0
    out = capsys.readouterr().out
    assert out.startswith("# adcskit ")
    path = tmp_path / "default.toml"
    path.write_text(out, encoding="utf-8")
    if wheels:
        assert load_wheel_scenario(str(path)) == WheelScenario()
    else:
        assert load_scenario(str(path)) == Scenario()
    assert main(["scenario", "--quiet"]) == 0
    assert not any(line.startswith("#") for line in capsys.readouterr().out.splitlines())
