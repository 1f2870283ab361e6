"""Execute every ```python block of the user guide, so the documentation cannot rot.

The user guide's blocks run each on its own; a tutorial chapter (``CHAPTERS``) runs its
blocks in order in one namespace, as a reader would.
"""

from __future__ import annotations

import re
import tempfile
from pathlib import Path

import pytest

GUIDE = Path(__file__).resolve().parents[1] / "docs" / "user-guide.md"
BLOCKS = re.findall(r"```python\n(.*?)```", GUIDE.read_text(encoding="utf-8"), flags=re.S)


@pytest.mark.parametrize("code", BLOCKS, ids=[f"block{i}" for i in range(len(BLOCKS))])
def test_user_guide_block_runs(code, capsys, tmp_path, monkeypatch):
    _temporary_files_under(tmp_path, monkeypatch)
    exec(compile(code, str(GUIDE), "exec"), {"__name__": "__docs__"})


def _temporary_files_under(tmp_path, monkeypatch):
    """Point ``tempfile`` at pytest's ``tmp_path``: a block that makes a working directory as a
    reader would (``tempfile.mkdtemp``, signoff.md's 5 MB of netCDF and figures) leaves
    nothing in the system's temporary directory after the run."""
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))


DOCS = GUIDE.parent
#: Tutorial chapters whose blocks build on each other.
CHAPTERS = ["signoff.md"]


@pytest.mark.compile
@pytest.mark.parametrize("chapter", CHAPTERS)
def test_tutorial_chapter_runs_in_order(chapter, capsys, tmp_path, monkeypatch):
    _temporary_files_under(tmp_path, monkeypatch)
    if chapter == "signoff.md":
        pytest.importorskip("xarray")
    path = DOCS / chapter
    namespace = {"__name__": "__docs__"}
    for code in re.findall(r"```python\n(.*?)```", path.read_text(encoding="utf-8"), flags=re.S):
        exec(compile(code, str(path), "exec"), namespace)
