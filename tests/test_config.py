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
