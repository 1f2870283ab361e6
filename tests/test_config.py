"""Typed TOML configuration (adcskit.config)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import pytest

from adcskit.config import config_to_dict, dump_toml, load_config
from adcskit.errors import ConfigError


@dataclass(frozen=True, kw_only=True)
class Inner:
    bound: float = 0.2
    methods: tuple[str, ...] = ("q-method", "minmax")


@dataclass(frozen=True, kw_only=True)
class Outer:
    n_trials: int = 100
    noise: Literal["uniform", "gaussian"] = "uniform"
    enabled: bool = True
    scale: float | None = None
    pair: tuple[float, float] = (1.0, 2.0)
    inner: Inner = field(default_factory=Inner)

    def __post_init__(self) -> None:
        if self.n_trials < 1:
            raise ValueError(f"n_trials must be >= 1; got {self.n_trials}")


def test_defaults_and_overrides():
    cfg = load_config(Outer, {"n_trials": 5, "inner": {"bound": 1}})
    assert cfg.n_trials == 5 and cfg.inner.bound == 1.0 and isinstance(cfg.inner.bound, float)
    assert cfg.inner.methods == ("q-method", "minmax")


def test_quick_overrides_yield_to_user_values():
    cfg = load_config(Outer, {"n_trials": 7}, overrides={"n_trials": 3, "enabled": False})
    assert cfg.n_trials == 7 and cfg.enabled is False


@pytest.mark.parametrize(
    ("data", "fragment"),
    [
        ({"n_trail": 5}, "unknown config key n_trail = 5 (did you mean 'n_trials'?); allowed keys: enabled, inner, n_trials, noise, pair, scale"),
        ({"inner": {"bund": 1}}, "unknown config key inner.bund = 1 (did you mean 'bound'?); allowed keys in inner: bound, methods"),
        ({"n_trials": 2.5}, "n_trials must be an integer; got 2.5"),
        ({"n_trials": True}, "n_trials must be an integer; got True"),
        ({"noise": "laplace"}, "noise must be one of 'uniform', 'gaussian'; got 'laplace'"),
        ({"pair": [1.0]}, "pair must be a list of 2 items"),
        ({"inner": {"methods": ["a", 3]}}, "inner.methods[1] must be a string; got 3"),
        ({"n_trials": 0}, "n_trials must be >= 1; got 0"),
        ({"scale": "big"}, "scale must be float or nothing"),
    ],
)
def test_bad_keys_name_key_value_and_allowed(data, fragment):
    with pytest.raises(ConfigError) as err:
        load_config(Outer, data)
    assert fragment in str(err.value)


def test_toml_file_roundtrip(tmp_path):
    cfg = load_config(Outer, {"n_trials": 9, "scale": 2.0, "inner": {"methods": ["svd"]}})
    text = dump_toml(config_to_dict(cfg))
    path = tmp_path / "c.toml"
    path.write_text(text)
    assert load_config(Outer, path) == cfg


def test_bad_toml_and_missing_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("n_trials = = 3")
    with pytest.raises(ConfigError, match="not valid TOML"):
        load_config(Outer, bad)
    with pytest.raises(ConfigError, match="not found"):
        load_config(Outer, tmp_path / "missing.toml")


# --- issue 16 §4: config keys carry their unit, consistently across studies ------------------

#: Unit suffix of a config key -> the unit its documentation (``adcskit config`` comment) states.
SUFFIX_UNITS = {
    "_deg_per_pct": {"deg/%"},
    "_nm_per_rad": {"N m/rad"},
    "_rad_s": {"rad/s"},
    "_kg_s": {"kg/s"},
    "_kgm2": {"kg m²", "kg m^2"},
    "_nm": {"N m"},
    "_pct": {"%"},
    "_deg": {"deg"},
    "_hz": {"Hz"},
    "_km": {"km"},
    "_s": {"s"},
    "_m": {"m"},
    "_n": {"N"},
}


def _documented_unit(help_line: str) -> str | None:
    """``"float, N m: meaning"`` -> ``"N m"``; None without a unit after the type."""
    head = help_line.split(": ", 1)[0]
    if head.startswith("(") or "," not in head:
        head = head.rsplit(")", 1)[-1]
    _, sep, unit = head.rpartition(", ")
    return unit.strip() if sep else None


def _study_config_help():
    from adcskit.config import config_help
    from adcskit.studies import get_study, is_available, study_names

    return {name: config_help(get_study(name).config_cls) for name in study_names() if is_available(name)}


def test_every_study_key_with_a_unit_has_the_matching_suffix():
    """A key documented with a physical unit ends in that unit's suffix, and a suffixed key
    documents its unit (so ``adcskit config`` shows the unit on every such line)."""
    unit_to_suffix = {u: sfx for sfx, units in SUFFIX_UNITS.items() for u in units}
    bad = []
    for study, helps in _study_config_help().items():
        for key, line in helps.items():
            unit = _documented_unit(line)
            suffix = next((s for s in SUFFIX_UNITS if key.endswith(s)), None)
            if unit in unit_to_suffix and not key.endswith(unit_to_suffix[unit]):
                bad.append(f"{study}: {key} is documented in {unit} but lacks the suffix {unit_to_suffix[unit]}")
            if suffix is not None and unit not in SUFFIX_UNITS[suffix]:
                bad.append(f"{study}: {key} ends in {suffix} but documents the unit {unit!r}")
    assert not bad, "\n".join(bad)


#: Keys renamed to their unit-suffixed names (issue 16 §4), per study: old -> new.
RENAMED = [
    ("wahba-orbit", "inertia", "inertia_kgm2"),
    ("model-estimation", "dt", "dt_s"),
    ("model-estimation", "inertia", "inertia_kgm2"),
    ("model-estimation", "altitude_m", "altitude_km"),
    ("model-estimation", "step_level", "step_level_nm"),
    ("model-estimation", "step_level_dominant", "step_level_dominant_nm"),
    ("model-estimation", "sine_amplitude", "sine_amplitude_nm"),
    ("model-estimation", "sine_omega", "sine_omega_rad_s"),
    ("onoff-schmitt", "inertia", "inertia_kgm2"),
    ("onoff-schmitt", "delay", "delay_s"),
    ("onoff-schmitt", "dt", "dt_s"),
    ("onoff-tuning", "std_delay", "std_delay_s"),
    ("onoff-tuning", "penalty_weight", "penalty_weight_deg_per_pct"),
    ("closed-loop", "geo_dt", "geo_dt_s"),
    ("rendezvous", "rows", "rows_m"),
]


@pytest.mark.parametrize("study, old, new", RENAMED, ids=[f"{s}-{o}" for s, o, _ in RENAMED])
def test_old_key_names_are_rejected_with_the_new_name(study, old, new, tmp_path):
    """A user's TOML with a pre-rename key is an error naming the old key and suggesting the new."""
    from adcskit.studies._runner import resolve_config

    path = tmp_path / "old.toml"
    path.write_text(f"{old} = 1.0\n")
    with pytest.raises(ConfigError) as err:
        resolve_config(study, path)
    msg = str(err.value)
    assert f"unknown config key {old} = 1.0 (did you mean {new!r}?)" in msg
    assert resolve_config(study, None) == resolve_config(study, {new: getattr(resolve_config(study, None), new)})


def test_old_key_through_the_cli_exits_2_with_the_suggestion(tmp_path, capsys):
    from adcskit.cli import main

    path = tmp_path / "my.toml"
    path.write_text("inertia = [80.0, 80.0, 4.0]\n")
    out = tmp_path / "results"
    assert main(["run", "wahba-orbit", "--quick", "--quiet", "--config", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "unknown config key inertia" in err and "did you mean 'inertia_kgm2'?" in err
    assert not out.exists()
