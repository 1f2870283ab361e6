"""Execute every ```python block of the user guide, so the documentation cannot rot."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

GUIDE = Path(__file__).resolve().parents[1] / "docs" / "user-guide.md"
BLOCKS = re.findall(r"```python\n(.*?)```", GUIDE.read_text(encoding="utf-8"), flags=re.S)


@pytest.mark.parametrize("code", BLOCKS, ids=[f"block{i}" for i in range(len(BLOCKS))])
def test_user_guide_block_runs(code, capsys):
    exec(compile(code, str(GUIDE), "exec"), {"__name__": "__docs__"})
