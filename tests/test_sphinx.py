"""The documentation site builds with warnings as errors (issue 16), so it cannot rot.

Runs ``sphinx-build -W`` on ``docs/`` (the same command as the README's docs section). The
``docs`` tools are part of the ``dev`` extra, so CI always runs this; it is skipped only
where Sphinx is not installed.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"


def test_sphinx_build_without_warnings(tmp_path):
    pytest.importorskip("sphinx")
    pytest.importorskip("pydata_sphinx_theme")
    pytest.importorskip("numpydoc")
    pytest.importorskip("myst_parser")
    proc = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(DOCS), str(tmp_path / "html")],
        capture_output=True,
        text=True,
        timeout=1200,
    )
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-8000:]
    api = tmp_path / "html" / "api" / "generated"
    pages = {p.stem for p in api.glob("*.html")}
    # every public callable/class of every subpackage has a page
    import importlib

    sys.path.insert(0, str(DOCS))
    try:
        conf = importlib.import_module("conf")
    finally:
        sys.path.remove(str(DOCS))
    missing = []
    for pkg in conf.API_PACKAGES:
        if importlib.util.find_spec(pkg) is None:
            continue
        module = importlib.import_module(pkg)
        for name in module.__all__:
            obj = getattr(module, name)
            if (callable(obj) or isinstance(obj, type)) and f"{pkg}.{name}" not in pages:
                missing.append(f"{pkg}.{name}")
    assert not missing, f"no API page for: {missing}"
