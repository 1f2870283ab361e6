"""CLI bad-argument cases of issue 12: exit status 2, one clear line, nothing written."""

from __future__ import annotations

from pathlib import Path

import pytest

from adcskit.cli import main

STUDY = "wahba-table1"


def _bad_out(tmp_path: Path, kind: str) -> str:
    if kind == "existing-file":
        f = tmp_path / "a-file"
        f.write_text("x")
        return str(f)
    if kind == "under-a-file":
        f = tmp_path / "a-file"
        f.write_text("x")
        return str(f / "sub")
    if kind == "dev-null-child":
        return "/dev/null/sub"
    return "/proc/adcskit-no-such-dir/results"  # cannot be created, even as root


def _config(tmp_path: Path, kind: str) -> str:
    if kind == "binary":
        p = tmp_path / "bin.toml"
        p.write_bytes(bytes(range(256)) * 4)
        return str(p)
    if kind == "directory":
        d = tmp_path / "conf.d"
        d.mkdir()
        return str(d)
    if kind == "missing":
        return str(tmp_path / "nope.toml")
    p = tmp_path / "bad.toml"
    p.write_text("no_such_key = 1\n")
    return str(p)


def _snapshot(tmp_path: Path) -> set[str]:
    return {str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*")}


def _one_clear_line(err: str, fragment: str) -> None:
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert lines[0].startswith("adcskit: error: ") and fragment in lines[0], lines[0]
    assert "Traceback" not in err


@pytest.mark.parametrize("command", ["run", "reproduce"])
@pytest.mark.parametrize("kind", ["existing-file", "under-a-file", "dev-null-child", "uncreatable"])
def test_out_that_cannot_be_a_results_directory(command, kind, tmp_path, capsys):
    out = _bad_out(tmp_path, kind)
    before = _snapshot(tmp_path)
    argv = ["run", STUDY] if command == "run" else ["reproduce", "--only", STUDY]
    assert main([*argv, "--quick", "--quiet", "--out", out]) == 2
    _one_clear_line(capsys.readouterr().err, "--out")
    assert _snapshot(tmp_path) == before


@pytest.mark.parametrize("kind", ["binary", "directory", "missing", "unknown-key"])
def test_config_that_cannot_be_read(kind, tmp_path, capsys):
    config = _config(tmp_path, kind)
    out = tmp_path / "results"
    before = _snapshot(tmp_path)
    assert main(["run", STUDY, "--quick", "--quiet", "--config", config, "--out", str(out)]) == 2
    _one_clear_line(capsys.readouterr().err, "config")
    assert not out.exists()
    assert _snapshot(tmp_path) == before


def test_report_on_a_file_or_missing_directory(tmp_path, capsys):
    f = tmp_path / "a-file"
    f.write_text("x")
    for target in (str(f), str(tmp_path / "missing")):
        assert main(["report", target]) == 2
        _one_clear_line(capsys.readouterr().err, "directory")


def test_argv_must_be_a_list_of_strings():
    from adcskit.errors import InputTypeError

    with pytest.raises(InputTypeError, match="argv must be None or a list of strings"):
        main("list")
