"""Sphinx configuration of the adcskit documentation site.

Build: ``python -m pip install -e ".[docs]" && sphinx-build -W -b html docs docs/_build/html``
(warnings are errors, so the site cannot rot; ``tests/test_sphinx.py`` runs the same build).

The API reference is generated from each subpackage's ``__all__`` at build time
(:func:`_write_api_pages`): a new public name gets its page without editing the docs.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "src"))

import adcskit  # noqa: E402

project = "adcskit"
author = "adcskit developers"
copyright = "2026, adcskit developers"  # noqa: A001
version = release = adcskit.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "myst_parser",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store"]
templates_path = ["_templates"]

myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3

autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": False}
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

html_theme = "pydata_sphinx_theme"
html_title = f"adcskit {release}"
html_theme_options = {
    "navigation_depth": 3,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
    "header_links_before_dropdown": 4,
}
html_static_path: list[str] = []

#: Subpackages documented in the API reference, in the layering order of design.md.
API_PACKAGES = [
    "adcskit.attitude",
    "adcskit.dynamics",
    "adcskit.environment",
    "adcskit.sensors",
    "adcskit.determination",
    "adcskit.estimation",
    "adcskit.optimal_control",
    "adcskit.thrusters",
    "adcskit.control",
    "adcskit.uncertainty",
    "adcskit.simulation",
    "adcskit.studies",
    "adcskit.report",
    "adcskit.config",
    "adcskit.errors",
]


def _public_names(module_name: str) -> list[str]:
    module = importlib.import_module(module_name)
    return list(getattr(module, "__all__", []))


def _write_api_pages() -> None:
    """Write ``api/index.rst`` and one page per subpackage listing every name of ``__all__``."""
    api = HERE / "api"
    api.mkdir(exist_ok=True)
    index = [
        "API reference",
        "=============",
        "",
        "Every public name of every subpackage (its ``__all__``), one page each, with its",
        "docstring and a runnable example. Conventions: SI units and radians, quaternions scalar",
        "last, ``A(q)`` maps reference to body components, batch-first arrays (see :doc:`../conventions`).",
        "",
        ".. toctree::",
        "   :maxdepth: 1",
        "",
    ]
    for name in API_PACKAGES:
        if importlib.util.find_spec(name) is None:
            continue
        short = name.split(".", 1)[1]
        index.append(f"   {short}")
        module = importlib.import_module(name)
        first = (module.__doc__ or "").strip().splitlines()[0] if module.__doc__ else ""
        names = sorted(_public_names(name), key=str.lower)
        documented = [n for n in names if callable(getattr(module, n)) or isinstance(getattr(module, n), type)]
        constants = [n for n in names if n not in documented]
        lines = [
            f"``{name}``",
            "=" * (len(name) + 4),
            "",
            f".. automodule:: {name}",
            "   :no-members:",
            "",
            f".. currentmodule:: {name}",
            "",
            ".. autosummary::",
            "   :toctree: generated",
            "",
            *[f"   {n}" for n in documented if not n.startswith("_")],
            "",
        ]
        if constants:
            lines += ["Constants", "---------", ""]
            for n in constants:
                if n.startswith("_"):
                    continue
                text = " ".join(repr(getattr(module, n)).split())  # one line: inline literals cannot wrap
                lines.append(f"``{n}``\n    ``{text}``\n")
        del first
        text = "\n".join(lines)
        page = api / f"{short}.rst"
        if not page.exists() or page.read_text(encoding="utf-8") != text:
            page.write_text(text, encoding="utf-8")
    (api / "index.rst").write_text("\n".join(index) + "\n", encoding="utf-8")


_write_api_pages()
