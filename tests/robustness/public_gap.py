"""List the public names of adcskit without a robustness case (issue 23, item 5).

A *public name* is a callable in a public module's ``__all__`` (functions and classes) or a
public method of such a class (a name not starting with ``_``, defined by adcskit itself, not
inherited from ``object``/``Exception``/a dataclass helper). A name is *covered* when
``cases.CASES`` has an entry for it and *exempt* when ``cases.EXEMPT`` gives a reason (a method
is also exempt when its class is). Run from the repository root::

    PYTHONPATH=src python tests/robustness/public_gap.py

It prints the uncovered names, one a line, and exits 1 if there are any.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import adcskit  # noqa: E402

#: Methods every result or config object has (serialisation, representation): their inputs are
#: the object itself, checked where the object is built.
GENERIC_METHODS = frozenset({"to_dict", "from_dict", "summary", "replace", "copy", "keys", "items", "values"})


def public_modules() -> list[str]:
    """Every subpackage plus the public top-level modules of adcskit."""
    mods = []
    for info in pkgutil.walk_packages(adcskit.__path__, "adcskit."):
        if any(part.startswith("_") for part in info.name.split(".")[1:]):
            continue
        if info.name.startswith("adcskit.studies."):
            # one package per study (paper.py, config.py, experiment.py, ...): the reproduction
            # layer, entered through adcskit.studies.run_study / the CLI (cases here and in
            # test_cli_errors.py) with every config key validated (tests/test_config.py)
            continue
        if info.ispkg or info.name.count(".") == 1:
            mods.append(info.name)
    return sorted(mods)


def public_callables() -> dict[str, object]:
    """``{"subpackage.name": object}`` of the callables in the public modules' ``__all__``."""
    out = {}
    for mod_name in public_modules():
        mod = importlib.import_module(mod_name)
        for name in getattr(mod, "__all__", ()):
            obj = getattr(mod, name)
            if not callable(obj):
                continue  # constants and registries: data, not entry points
            if inspect.isclass(obj) and issubclass(obj, BaseException):
                continue  # exception types
            out[f"{mod_name.removeprefix('adcskit.')}.{name}"] = obj
    return out


def public_methods(name: str, cls: type, owners: dict[type, str]) -> list[str]:
    """``"owner.method"`` for the public methods and static/class methods of ``cls``.

    A method inherited from another public class is named after that class (``owners``), so
    ``SunSensor.measure`` is covered by the ``VectorSensor.measure`` case.
    """
    out = []
    for klass in cls.__mro__:
        if not (klass.__module__ or "").startswith("adcskit"):
            continue
        owner = owners.get(klass, name)
        for attr, raw in vars(klass).items():
            if attr.startswith("_") or attr in GENERIC_METHODS:
                continue
            if isinstance(raw, (staticmethod, classmethod)) or inspect.isfunction(raw):
                out.append(f"{owner}.{attr}")
    return sorted(set(out))


def uncovered() -> list[str]:
    """Public names (callables and public methods of public classes) with neither a case nor an exemption."""
    from cases import CASES, EXEMPT, RESULT

    names = public_callables()
    owners = {obj: n for n, obj in names.items() if inspect.isclass(obj)}
    missing = set()
    for name, obj in names.items():
        if name not in CASES and name not in EXEMPT:
            missing.add(name)
        # a result dataclass is exempt as an entry point, but its methods that take input
        # (``state_at(t)``) are public names of their own; other exempt classes take theirs along
        if inspect.isclass(obj) and (name not in EXEMPT or EXEMPT[name] == RESULT):
            missing |= {m for m in public_methods(name, obj, owners) if m not in CASES and m not in EXEMPT
                        and (m.rsplit(".", 1)[0] not in EXEMPT or EXEMPT[m.rsplit(".", 1)[0]] == RESULT)}
    return sorted(missing)


if __name__ == "__main__":
    gap = uncovered()
    print("\n".join(gap) if gap else "every public name has a robustness case or an exemption")
    sys.exit(1 if gap else 0)
