"""Typed configuration: TOML files and mappings loaded into frozen dataclasses.

Every study's configuration is a frozen, keyword-only dataclass. :func:`load_config` builds
one from a mapping (for example a parsed TOML file) and checks every key against the
dataclass fields: an unknown key, a missing required key or a value of the wrong type is a
:class:`~adcskit.errors.ConfigError` that names the key (with its dotted path for nested
tables), the value and what is allowed — never silently ignored (house style rule 4).

Supported field types: ``bool``, ``int``, ``float`` (ints are accepted and converted),
``str``, ``typing.Literal[...]``, ``tuple[T, ...]``, ``tuple[T1, T2]``, ``X | None``, and
nested config dataclasses (TOML tables). Lists in the file become tuples, so loaded
configs are hashable and immutable.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
import types
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Literal, TypeVar, Union, get_args, get_origin, get_type_hints

import numpy as np

from adcskit._validation import check_mapping, check_path, short_repr
from adcskit.errors import ConfigError, InputTypeError

__all__ = ["load_config", "config_to_dict", "config_help", "dump_toml", "read_toml", "merge_mappings"]

C = TypeVar("C")


def read_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML file, turning a syntax error into a :class:`ConfigError`.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d, "my.toml")
    ...     _ = p.write_text("noise_bound = 0.1")
    ...     read_toml(p)
    {'noise_bound': 0.1}
    """
    p = check_path("path", path)
    if not p.is_file():
        why = "a directory" if p.is_dir() else ("not a regular file" if p.exists() else "not found")
        raise ConfigError(f"config file path must be an existing TOML file; got {str(p)!r} ({why})")
    try:
        with p.open("rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"config file path {str(p)!r} is not valid TOML: {exc}") from None
    except UnicodeDecodeError:
        raise ConfigError(f"config file path {str(p)!r} is not valid TOML: not UTF-8 text (a binary file?)") from None
    except OSError as exc:
        raise ConfigError(f"config file path {str(p)!r} cannot be read: {exc.strerror}") from None


def merge_mappings(base: Mapping[str, Any], override: Mapping[str, Any]) -> dict[str, Any]:
    """Recursive merge: tables are merged key by key, other values are replaced.

    Examples
    --------
    >>> merge_mappings({"a": 1, "t": {"x": 1, "y": 2}}, {"t": {"y": 3}})
    {'a': 1, 't': {'x': 1, 'y': 3}}
    """
    check_mapping("base", base)
    check_mapping("override", override)
    out: dict[str, Any] = dict(base)
    for key, value in override.items():
        if isinstance(value, Mapping) and isinstance(out.get(key), Mapping):
            out[key] = merge_mappings(out[key], value)
        else:
            out[key] = value
    return out


def _type_name(tp: Any) -> str:
    origin = get_origin(tp)
    if origin is Literal:
        return "one of " + ", ".join(repr(a) for a in get_args(tp))
    if origin in (Union, types.UnionType):
        return " or ".join(_type_name(a) for a in get_args(tp))
    if origin is tuple:
        args = get_args(tp)
        if len(args) == 2 and args[1] is Ellipsis:
            return f"list of {_type_name(args[0])}"
        return "list [" + ", ".join(_type_name(a) for a in args) + "]"
    if tp is type(None):
        return "nothing (omit the key)"
    if dataclasses.is_dataclass(tp):
        return f"table ({tp.__name__})"
    return getattr(tp, "__name__", str(tp))


def _convert(path: str, value: Any, tp: Any) -> Any:
    origin = get_origin(tp)
    if tp is Any:
        return value
    if origin in (Union, types.UnionType):
        args = get_args(tp)
        if value is None and type(None) in args:
            return None
        for arg in args:
            if arg is type(None):
                continue
            try:
                return _convert(path, value, arg)
            except ConfigError:
                continue
        raise ConfigError(f"{path} must be {_type_name(tp)}; got {value!r}")
    if origin is Literal:
        if value not in get_args(tp):
            raise ConfigError(f"{path} must be {_type_name(tp)}; got {value!r}")
        return value
    if origin is tuple:
        if isinstance(value, str | bytes) or not isinstance(value, list | tuple):
            raise ConfigError(f"{path} must be {_type_name(tp)}; got {value!r}")
        args = get_args(tp)
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_convert(f"{path}[{i}]", v, args[0]) for i, v in enumerate(value))
        if len(value) != len(args):
            raise ConfigError(
                f"{path} must be a list of {len(args)} items ({_type_name(tp)}); got {value!r}"
            )
        return tuple(_convert(f"{path}[{i}]", v, a) for i, (v, a) in enumerate(zip(value, args)))
    if dataclasses.is_dataclass(tp):
        if dataclasses.is_dataclass(value) and isinstance(value, tp):
            return value
        if not isinstance(value, Mapping):
            raise ConfigError(f"{path} must be a table ({tp.__name__}); got {value!r}")
        return _build(tp, value, prefix=path + ".")
    if tp is bool:
        if not isinstance(value, bool):
            raise ConfigError(f"{path} must be a boolean (true/false); got {value!r}")
        return value
    if tp is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigError(f"{path} must be an integer; got {value!r}")
        return value
    if tp is float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ConfigError(f"{path} must be a number; got {value!r}")
        v = float(value)
        if math.isnan(v):
            raise ConfigError(f"{path} must be a number, not NaN; got {value!r}")
        return v
    if tp is str:
        if not isinstance(value, str):
            raise ConfigError(f"{path} must be a string; got {value!r}")
        return value
    raise TypeError(f"unsupported config field type {tp!r} for {path}")  # programming error


def _build(cls: type[C], data: Mapping[str, Any], prefix: str = "") -> C:
    if not isinstance(data, Mapping):
        raise ConfigError(f"{prefix.rstrip('.') or 'config'} must be a table; got {data!r}")
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    hints = get_type_hints(cls)
    unknown = [k for k in data if k not in fields]
    if unknown:
        allowed = ", ".join(sorted(fields)) or "(none)"
        from adcskit._validation import did_you_mean

        raise ConfigError(
            f"unknown config key {prefix}{unknown[0]!s} = {data[unknown[0]]!r}{did_you_mean(unknown[0], fields)}; "
            f"allowed keys{' in ' + prefix.rstrip('.') if prefix else ''}: {allowed}"
        )
    kwargs = {}
    for name, f in fields.items():
        if name in data:
            kwargs[name] = _convert(prefix + name, data[name], hints[name])
        elif f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
            raise ConfigError(f"config key {prefix}{name} is required ({_type_name(hints[name])})")
    try:
        return cls(**kwargs)
    except ConfigError:
        raise
    except (ValueError, TypeError) as exc:
        raise ConfigError(f"invalid config{' table ' + prefix.rstrip('.') if prefix else ''}: {exc}") from None


def load_config(
    cls: type[C],
    source: Mapping[str, Any] | str | Path | None = None,
    overrides: Mapping[str, Any] | None = None,
) -> C:
    """Build the frozen config dataclass ``cls`` from a mapping or TOML file.

    Parameters
    ----------
    cls : dataclass type
        The configuration class (frozen, keyword-only).
    source : mapping, path or None
        Parsed TOML data or the path of a TOML file. ``None`` uses the defaults.
    overrides : mapping, optional
        Merged under ``source`` (``source`` wins): used for the ``--quick`` settings, so a
        user file can still override them.

    Raises
    ------
    ConfigError
        On an unknown key (the message lists the allowed ones), a missing required key, or a
        value of the wrong type.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True, kw_only=True)
    ... class Settings:
    ...     n_trials: int = 100
    ...     noise_bound: float = 0.2
    >>> load_config(Settings, {"noise_bound": 0.1})
    Settings(n_trials=100, noise_bound=0.1)
    >>> load_config(Settings, {"noise_bnd": 0.1})
    Traceback (most recent call last):
    ...
    adcskit.errors.ConfigError: ...
    """
    if source is None:
        data: Mapping[str, Any] = {}
    elif isinstance(source, str | Path):
        data = read_toml(source)
    elif isinstance(source, Mapping):
        data = source
    else:
        raise ConfigError(f"config source must be a mapping or a TOML path; got {source!r}")
    check_mapping("overrides", overrides, allow_none=True)
    if overrides:
        data = merge_mappings(overrides, data)
    return _build(cls, data)


def config_to_dict(config: Any) -> dict[str, Any]:
    """Plain-JSON view of a config dataclass (tuples become lists).

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True)
    ... class Mesh:
    ...     shape: tuple = (20, 3)
    >>> config_to_dict(Mesh())
    {'shape': [20, 3]}
    """

    def plain(v: Any) -> Any:
        if dataclasses.is_dataclass(v) and not isinstance(v, type):
            return {f.name: plain(getattr(v, f.name)) for f in dataclasses.fields(v)}
        if isinstance(v, tuple | list):
            return [plain(x) for x in v]
        if isinstance(v, Mapping):
            return {str(k): plain(x) for k, x in v.items()}
        return v

    return plain(config)



def _toml_string(v: str) -> str:
    # a JSON string literal is a valid TOML basic string (same escapes; control characters as \uXXXX)
    import json

    return json.dumps(v, ensure_ascii=False)


def _toml_key(key: Any, where: str) -> str:
    """A key as TOML writes it: bare when it can be, quoted otherwise (``"a b"``)."""
    import re

    if not isinstance(key, str):
        raise InputTypeError(f"data keys must be strings (TOML keys are strings); got {short_repr(key)} in {where}")
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else _toml_string(key)


def _toml_value(v: Any, where: str = "data") -> str:
    if isinstance(v, bool | np.bool_):
        return "true" if v else "false"
    if isinstance(v, int | np.integer):
        return str(int(v))
    if isinstance(v, float | np.floating):
        v = float(v)
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return _toml_string(v)
    if isinstance(v, list | tuple):
        return "[" + ", ".join(_toml_value(x, where) for x in v) + "]"
    raise InputTypeError(f"data value {where} = {short_repr(v)} cannot be written as TOML "
                         "(bool, int, float, str, list or a nested mapping)")


def _doc_attributes(cls: type) -> dict[str, str]:
    """``{field: "type: description"}`` from the numpydoc ``Attributes``/``Parameters`` section."""
    import inspect

    doc = inspect.getdoc(cls) or ""
    out: dict[str, str] = {}
    lines = doc.splitlines()
    in_section = False
    names: list[str] = []
    for i, line in enumerate(lines):
        stripped = line.strip()
        if stripped in ("Attributes", "Parameters") and i + 1 < len(lines) and set(lines[i + 1].strip()) == {"-"}:
            in_section, names = True, []
            continue
        if not in_section or set(stripped) == {"-"}:
            continue
        if line and not line.startswith(" "):
            if " : " in line or stripped.isidentifier() or "," in stripped:
                head, _, typ = line.partition(" : ")
                names = [n.strip() for n in head.split(",") if n.strip()]
                for n in names:
                    out[n] = typ.strip()
                continue
            in_section = False  # another section starts
        elif stripped and names:
            for n in names:
                sep = ": " if out[n] and not out[n].endswith(": ") and ": " not in out[n] else " "
                out[n] = f"{out[n]}{sep}{stripped}".strip()
    return out


def config_help(cls: type) -> dict[str, str]:
    """One line per config key of dataclass ``cls``: its type and meaning (with unit).

    Nested config dataclasses give dotted keys. Taken from the class docstring's numpydoc
    ``Attributes`` section; a key it does not describe gets its annotated type only.

    Examples
    --------
    >>> from adcskit.studies import get_study
    >>> config_help(get_study("wahba-table1").config_cls)["noise_bound"]
    'float: Uniform noise bound as a fraction of each component (S0: 0.2).'
    """
    if not (isinstance(cls, type) and dataclasses.is_dataclass(cls)):
        raise InputTypeError(f"cls must be a config dataclass (a class); got {short_repr(cls)}")
    hints = get_type_hints(cls)
    doc = _doc_attributes(cls)
    out: dict[str, str] = {}
    for f in dataclasses.fields(cls):
        tp = hints.get(f.name, Any)
        if isinstance(tp, type) and dataclasses.is_dataclass(tp):
            out[f.name] = doc.get(f.name, "")
            for k, v in config_help(tp).items():
                out[f"{f.name}.{k}"] = v
        else:
            out[f.name] = doc.get(f.name) or _type_name(tp)
    return out


def dump_toml(data: Mapping[str, Any], _prefix: str = "", *, comments: Mapping[str, str] | None = None) -> str:
    """Write a plain mapping (as from :func:`config_to_dict`) as TOML text.

    ``None`` values are written as comments, since TOML has no null. ``comments`` maps a
    (dotted) key to a line written as a ``#`` comment above it (see :func:`config_help`).
    A key that is not a bare TOML key (``a b``, ``c.d``) is written quoted, strings are escaped,
    so the text always reads back with :mod:`tomllib`; a non-string key or a value TOML cannot
    hold (``None`` inside a list, an object) raises :class:`~adcskit.errors.InputTypeError`.

    Examples
    --------
    >>> print(dump_toml({"n_trials": 100, "mesh": {"shape": [20, 3]}}), end="")
    n_trials = 100
    <BLANKLINE>
    [mesh]
    shape = [20, 3]
    >>> print(dump_toml({"a b": 1}), end="")
    "a b" = 1
    """
    check_mapping("data", data)
    return _dump_toml(data, _prefix, _prefix, comments or {})


def _dump_toml(data: Mapping[str, Any], prefix: str, header: str, comments: Mapping[str, str]) -> str:
    # prefix: the dotted path of raw keys (for ``comments``); header: the same path as TOML writes it
    lines: list[str] = []
    tables = []
    for key, value in data.items():
        bare = _toml_key(key, "data" + ("." + prefix.rstrip(".") if prefix else ""))
        if isinstance(value, Mapping):
            tables.append((key, bare, value))
            continue
        note = comments.get(f"{prefix}{key}")
        if note:
            lines.append(f"# {note}")
        if value is None:
            lines.append(f"# {bare} = (unset)")
        else:
            lines.append(f"{bare} = {_toml_value(value, prefix + key)}")
    for key, bare, value in tables:
        name = f"{prefix}{key}"
        lines.append("")
        if comments.get(name):
            lines.append(f"# {comments[name]}")
        lines.append(f"[{header}{bare}]")
        lines.append(_dump_toml(value, name + ".", f"{header}{bare}.", comments).rstrip("\n"))
    return "\n".join(lines).lstrip("\n") + "\n"
