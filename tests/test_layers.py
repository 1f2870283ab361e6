"""The import layers hold (issue 20, item 2): ``lint-imports`` passes on the source tree.

The contracts live in ``pyproject.toml`` (``[tool.importlinter]``): the layers of design.md
read from the code (cli > report > studies > simulation > control | thrusters |
optimal_control | determination | estimation > uncertainty | sensors | dynamics |
environment > attitude > config > utilities > errors; ``a | b`` are independent siblings),
the studies framework used through its public face, and no import cycle inside any package.
``import-linter`` is in the ``dev`` extra, so CI always runs this; it is skipped only where it
is not installed.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

_RUN = (
    "import sys; from importlinter.cli import lint_imports_command; "
    "sys.exit(lint_imports_command(['--no-cache', '--no-logo']))"
)


def _lint_imports() -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))  # this tree, not an installed copy
    return subprocess.run([sys.executable, "-c", _RUN], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=300)


def test_lint_imports_keeps_every_contract():
    pytest.importorskip("importlinter")
    proc = _lint_imports()
    assert proc.returncode == 0, proc.stdout[-6000:] + proc.stderr[-3000:]
    assert "0 broken" in proc.stdout, proc.stdout[-3000:]


def test_every_subpackage_is_in_the_layers_contract():
    # an unlisted package would be left out of the check (the contract is also exhaustive)
    import tomllib

    conf = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    layers = next(c for c in conf["tool"]["importlinter"]["contracts"] if c["id"] == "layers")["layers"]
    listed = {name.strip() for row in layers for name in row.split("|")}
    pkg = ROOT / "src" / "adcskit"
    present = {p.name for p in pkg.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    present |= {p.stem for p in pkg.glob("*.py") if p.stem != "__init__"}
    assert present == listed
