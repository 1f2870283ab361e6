"""Release hygiene: no stray binaries tracked by git, the files a release needs are present.

A binary file (one with a NUL byte in its first 8 KiB) may only live in a declared data folder;
anything else (a wheel, an archive, a compiled object) is a mistake that bloats every clone.
"""
from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: Folders where binary files are expected: figures of the docs and the report's screenshot.
BINARY_FOLDERS = ("docs/figures/",)


def _tracked() -> list[str]:
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("not a git checkout")
    out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True)
    return [p for p in out.stdout.decode().split("\0") if p]


def _is_binary(path: Path) -> bool:
    with path.open("rb") as fh:
        return b"\0" in fh.read(8192)


def test_no_binary_outside_data_folders():
    stray = [p for p in _tracked()
             if (ROOT / p).is_file() and not p.startswith(BINARY_FOLDERS) and _is_binary(ROOT / p)]
    assert not stray, f"binary files outside {BINARY_FOLDERS}: {stray}"


def test_binary_check_catches_a_wheel(tmp_path):
    wheel = tmp_path / "x-0.1-py3-none-any.whl"
    wheel.write_bytes(b"PK\x03\x04\x14\x00\x00\x00\x08\x00")
    assert _is_binary(wheel)
    assert not _is_binary(ROOT / "README.md")


def test_release_files_present_and_consistent():
    for name in ("LICENSE", "CHANGELOG.md", "CITATION.cff", "README.md"):
        assert (ROOT / name).is_file(), name
    assert "MIT License" in (ROOT / "LICENSE").read_text()
    pyproject = (ROOT / "pyproject.toml").read_text()
    version = re.search(r'^version = "([^"]+)"', pyproject, re.M).group(1)
    cff = (ROOT / "CITATION.cff").read_text()
    assert re.search(r"^cff-version: 1\.2\.0$", cff, re.M)
    assert re.search(rf"^version: {re.escape(version)}$", cff, re.M)
    assert re.search(r"^license: MIT$", cff, re.M)
    assert f"## {version}" in (ROOT / "CHANGELOG.md").read_text()


@pytest.mark.slow
def test_wheel_builds_installs_and_reproduces(tmp_path):
    """`python -m build`, a fresh venv with the wheel, then `adcskit reproduce --quick` from it."""
    pytest.importorskip("build")
    import sys
    subprocess.run([sys.executable, "-m", "build", "--outdir", str(tmp_path / "dist"), str(ROOT)],
                   check=True, capture_output=True)
    wheels = list((tmp_path / "dist").glob("adcskit-*.whl"))
    assert len(wheels) == 1 and list((tmp_path / "dist").glob("adcskit-*.tar.gz"))
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)  # no network
    py = venv / "bin" / "python"
    subprocess.run([str(py), "-m", "pip", "install", "-q", "--no-deps", "--force-reinstall", str(wheels[0])], check=True)
    where = subprocess.run([str(py), "-c", "import adcskit; print(adcskit.__file__)"], check=True, capture_output=True,
                           text=True, cwd=tmp_path).stdout
    assert str(venv) in where, f"adcskit imported from {where!r}, not from the wheel"
    out = tmp_path / "results"
    subprocess.run([str(venv / "bin" / "adcskit"), "reproduce", "--quick", "--out", str(out)],
                   check=True, cwd=tmp_path, timeout=3600)
    assert (out / "index.html").is_file()
