"""Study runner, result writing, report and CLI, on a fake study registered for the test."""

from __future__ import annotations

import json
import math

import pytest

import adcskit.studies
import adcskit.studies._registry as registry
from adcskit.cli import main
from adcskit.errors import ConfigError, InputError
from adcskit.report.html import build_report, format_value
from adcskit.studies import run_study


@pytest.fixture
def fake(monkeypatch):
    studies = dict(registry.STUDIES)
    studies["fake"] = registry.StudyInfo("fake", "fake_study", "none", "A fake study")
    monkeypatch.setattr(registry, "STUDIES", studies)
    monkeypatch.setattr(adcskit.studies, "STUDIES", studies)  # the public face the CLI reads
    return "fake"


def test_run_study_writes_complete_result(fake, tmp_path):
    result = run_study(fake, quick=True, seed=3, out=tmp_path)
    d = tmp_path / "fake"
    data = json.loads((d / "result.json").read_text())
    for key in ("study", "adcskit_version", "config", "seed", "quick", "runtime_s", "paper", "measured", "checks", "figures"):
        assert key in data
    assert data["config"] == {"n_tasks": 3, "fail": False}  # quick override applied and recorded
    assert data["seed"] == 3 and data["quick"] is True
    assert data["measured"]["nan_value"] is None  # NaN -> null, JSON stays valid
    assert (d / "means.png").stat().st_size > 1000
    assert (d / "means.csv").read_text().splitlines()[0] == "i,mean"
    assert len(result.measured["means"]) == 3
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temp dirs left


def test_same_seed_same_result_different_seed_differs(fake, tmp_path):
    a = run_study(fake, seed=1, out=None).measured["means"]
    b = run_study(fake, seed=1, out=None).measured["means"]
    c = run_study(fake, seed=2, out=None).measured["means"]
    assert a == b and a != c


def test_failed_rerun_keeps_previous_result(fake, tmp_path):
    run_study(fake, out=tmp_path)
    before = (tmp_path / "fake" / "result.json").read_text()
    with pytest.raises(RuntimeError, match="asked to fail"):
        run_study(fake, config={"fail": True}, out=tmp_path)
    assert (tmp_path / "fake" / "result.json").read_text() == before


def test_config_errors(fake, tmp_path):
    with pytest.raises(ConfigError, match="unknown config key n_task"):
        run_study(fake, config={"n_task": 2}, out=None)
    with pytest.raises(InputError, match="study must be one of"):
        run_study("no-such-study", out=None)
    with pytest.raises(InputError, match="seed must be an integer"):
        run_study(fake, seed=-1, out=None)


def test_report_renders_claims_figures_and_missing_studies(fake, tmp_path):
    run_study(fake, quick=True, out=tmp_path)
    page = build_report(tmp_path).read_text()
    assert 'id="fake"' in page and "fake/means.png" in page
    assert "mean is near zero" in page and "It is fake." in page
    assert "wahba-table1" in page  # every registered study listed, run or not


def test_report_on_missing_dir(tmp_path):
    with pytest.raises(InputError, match="existing directory"):
        build_report(tmp_path / "nope")


def test_format_value():
    assert format_value(None) == "—"
    assert format_value(1.23456789) == "1.235"
    assert format_value(1.5e-7) == "1.500e-07"
    assert format_value(True) == "yes"
    assert format_value([1.0, 2.0]) == "[1, 2]"
    assert format_value(math.inf) == "inf"


def test_cli_run_reproduce_report(fake, tmp_path, capsys):
    out = tmp_path / "res"
    assert main(["run", "fake", "--quick", "--out", str(out), "--quiet"]) == 0
    assert (out / "fake" / "result.json").is_file() and (out / "index.html").is_file()
    assert main(["reproduce", "--quick", "--only", "fake", "--out", str(out), "--quiet"]) == 0
    assert main(["report", str(out)]) == 0
    assert main(["list"]) == 0
    listing = capsys.readouterr().out
    assert "fake" in listing and "wahba-table1" in listing


def test_cli_failure_is_recorded_and_report_still_written(fake, tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text("fail = true\n")
    out = tmp_path / "res"
    # 'run' with a failing study exits 1, records the error and writes the report
    assert main(["run", "fake", "--config", str(cfg), "--out", str(out), "--quiet"]) == 1
    errors = json.loads((out / "errors.json").read_text())
    assert "asked to fail" in errors["fake"]["message"]
    assert "failed" in (out / "index.html").read_text()
    # a later success clears the error
    assert main(["run", "fake", "--out", str(out), "--quiet"]) == 0
    assert "fake" not in json.loads((out / "errors.json").read_text())


@pytest.mark.parametrize(
    "argv",
    [
        ["run", "no-such-study", "--quiet"],
        ["run", "fake", "--executor", "threads", "--quiet"],
        ["reproduce", "--only", "nope", "--quiet"],
        ["report", "/nonexistent/dir"],
    ],
)
def test_cli_bad_arguments_exit_2(fake, argv, tmp_path, capsys):
    assert main([*argv, *(["--out", str(tmp_path)] if argv[0] != "report" else [])]) == 2
    assert "adcskit: error:" in capsys.readouterr().err


def test_cli_bad_seed_is_argparse_error(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["run", "fake", "--seed", "-3"])
    assert exc.value.code == 2


def test_cli_config_prints_loadable_toml(fake, tmp_path, capsys):
    assert main(["config", "fake", "--quick"]) == 0
    text = capsys.readouterr().out
    p = tmp_path / "c.toml"
    p.write_text(text)
    import fake_study
    from adcskit.config import load_config

    assert load_config(fake_study.Config, p).n_tasks == 3


def test_every_available_study_default_config_roundtrips(tmp_path):
    from adcskit.config import config_to_dict, dump_toml, load_config
    from adcskit.studies import get_study, is_available, study_names

    for name in study_names():
        if not is_available(name):
            continue
        study = get_study(name)
        for quick in (False, True):
            cfg = load_config(study.config_cls, None, overrides=study.quick if quick else None)
            p = tmp_path / f"{name}-{quick}.toml"
            p.write_text(dump_toml(config_to_dict(cfg)))
            assert load_config(study.config_cls, p) == cfg, name



def test_custom_config_is_recorded_and_claims_not_comparable(fake, tmp_path):
    """Issue 16 §2: a user's settings are labelled, and claims on changed protocol keys are not judged."""
    paper = run_study("fake", out=tmp_path / "a")
    assert paper.config_changes == {} and paper.protocol_differences == {}
    assert all(c.comparable for c in paper.claims)
    assert [c.protocol for c in paper.claims] == ["paper protocol"]
    # issue 21: a quick run (3 tasks, the paper's 8) is below the paper's protocol and, with
    # fewer than 5 seeds, indicative: never comparable, never a red verdict
    quick = run_study("fake", quick=True, out=tmp_path / "q")
    assert quick.config_changes == {}
    assert quick.protocol_differences == {"n_tasks": {"value": 3, "paper": 8}}
    (c,) = quick.claims
    assert (c.protocol, c.indicative, c.comparable) == ("reduced protocol", True, False)
    assert c.display_outcome == "indicative (3 seeds)"
    assert c.protocol_differences == ("n_tasks: ours 3, paper 8",)
    # a finding (our question) on a quick-overridden key is below the documented full run too
    assert {f.id: f.protocol for f in quick.findings} == {"small-spread": "reduced protocol",
                                                          "finite": "paper protocol"}
    custom = run_study("fake", quick=True, config={"n_tasks": 5}, out=tmp_path / "b")
    # the study's setting is recorded as "default", the paper's printed value as "paper"
    assert custom.config_changes == {"n_tasks": {"value": 5, "default": 3, "paper": 8}}
    assert [c.comparable for c in custom.claims] == [False]
    assert [c.protocol for c in custom.claims] == ["custom settings"]
    # a change *to* the paper's printed value (8 tasks) restores the paper's protocol
    back = run_study("fake", quick=True, config={"n_tasks": 8}, out=None)
    assert back.config_changes == {"n_tasks": {"value": 8, "default": 3, "paper": 8}}
    assert [(c.protocol, c.comparable) for c in back.claims] == [("paper protocol", True)]
    # findings get the same treatment: the one on the changed key is not comparable with the
    # documented answer, the one whose protocol does not include n_tasks still is
    assert all(f.comparable for f in paper.findings)
    assert {f.id: f.comparable for f in custom.findings} == {"small-spread": False, "finite": True}
    assert {f.id: f.protocol for f in custom.findings} == {"small-spread": "custom settings",
                                                           "finite": "paper protocol"}
    assert [f.display_outcome for f in custom.findings][0] == "not comparable"
    data = json.loads((tmp_path / "b" / "fake" / "result.json").read_text())
    assert data["config_changes"]["n_tasks"]["value"] == 5
    assert {f["id"]: f["comparable"] for f in data["findings"]} == {"small-spread": False, "finite": True}
    page = build_report(tmp_path / "b").read_text()
    assert "not comparable" in page and "Custom configuration" in page
    assert "not comparable" in page.split("Our findings", 1)[1]


def test_mark_comparable_rule_for_claims_and_findings():
    """protocol_keys None: any changed key but the study's neutral ones (n_seeds) breaks
    comparability; explicit protocol keys (and their sub-keys) are matched by name."""
    from adcskit.studies._runner import _mark_comparable
    from adcskit.studies._verdict import Claim, Finding

    items = (
        Claim(id="any", statement="s", outcome="holds"),
        Finding(id="f-any", statement="s", outcome="holds"),
        Finding(id="f-mesh", statement="s", outcome="holds", protocol_keys=("mesh",)),
    )

    def comparable(changes):
        return {c.id: c.comparable for c in _mark_comparable(items, changes, ("n_seeds",))}

    ch = {"value": 1, "default": 2, "paper": "not declared"}
    assert comparable({}) == {"any": True, "f-any": True, "f-mesh": True}
    assert comparable({"n_seeds": ch}) == {"any": True, "f-any": True, "f-mesh": True}
    assert comparable({"mesh.size": ch}) == {"any": False, "f-any": False, "f-mesh": False}
    assert comparable({"noise": ch}) == {"any": False, "f-any": False, "f-mesh": True}
    # a protocol key that differs from the paper's printed value: "reduced protocol"
    diff = {"mesh": {"value": 10, "paper": 40}}
    marked = {c.id: c for c in _mark_comparable(items, {}, ("n_seeds",), diff)}
    assert {k: (c.protocol, c.comparable) for k, c in marked.items()} == {
        "any": ("reduced protocol", False), "f-any": ("reduced protocol", False), "f-mesh": ("reduced protocol", False)}
    assert marked["f-mesh"].display_outcome == "holds (reduced protocol)"
    assert marked["any"].protocol_differences == ("mesh: ours 10, paper 40",)



@pytest.mark.parametrize("kind", ["claims", "findings", "neither"])
def test_cli_run_line_tallies_findings_of_a_study_without_claims(kind, monkeypatch, tmp_path):
    # a study of our own questions (closed-loop) has findings, not paper claims: its `run`
    # line tallies the findings; a study with claims keeps the claims tally unchanged
    import argparse

    import adcskit.cli as cli
    import adcskit.studies as runner  # the public face the CLI imports run_study from
    from adcskit.studies._base import StudyResult
    from adcskit.studies._verdict import Claim, Finding

    claims = [Claim(id="c", statement="s", outcome="holds")] if kind == "claims" else []
    findings = ([Finding(id="f1", statement="a", outcome="holds"), Finding(id="f2", statement="b", outcome="holds"),
                 Finding(id="f3", statement="c", outcome="does not hold")] if kind != "neither" else [])
    monkeypatch.setattr(runner, "run_study", lambda *a, **k: StudyResult(study="x", claims=claims, findings=findings))
    ok, line = cli._run_one("x", argparse.Namespace(quick=True, seed=0, out=str(tmp_path)), None)
    assert ok
    expected = {"claims": "paper's claims: 1 holds ->",
                "findings": "paper's claims: none; findings: 2 holds, 1 does not hold ->",
                "neither": "paper's claims: no claims ->"}[kind]
    assert expected in line, line


def test_execution_only_keys_are_neutral_in_the_studies_that_have_them():
    # changing only how a campaign runs (task size, cache directory, backend, recorded traces)
    # must not label the paper's claims or our findings "not comparable"
    from adcskit.studies import get_study

    assert {"task_size", "campaign_dir", "backend", "n_seeds"} <= set(get_study("onoff-tuning").neutral_keys)
    assert {"record_samples", "n_seeds"} <= set(get_study("closed-loop").neutral_keys)
    for name in ("onoff-tuning", "closed-loop"):
        fields = set(get_study(name).config_cls.__dataclass_fields__)
        assert set(get_study(name).neutral_keys) <= fields, name


def test_config_keys_are_declared_as_field_metadata():
    # issue 20 item 1: protocol and neutral keys are read from the Config's fields, in field
    # order; a tag no field declares is an error (a typo would make a claim always comparable)
    from dataclasses import dataclass, field

    from adcskit.studies import NEUTRAL, neutral_keys, protocol, protocol_keys

    @dataclass(frozen=True, kw_only=True)
    class Config:
        n_seeds: int = field(default=5, metadata=NEUTRAL)
        b: float = field(default=0.2, metadata=protocol("c1", "c2"))
        plain: int = 3
        a: float = field(default=0.1, metadata=protocol("c2"))

    assert neutral_keys(Config) == ("n_seeds",)
    assert protocol_keys(Config, "c1") == ("b",)
    assert protocol_keys(Config, "c2") == protocol_keys(Config, "c1", "c2") == ("b", "a")  # field order
    assert protocol_keys(Config) == ("b", "plain", "a")  # no tag: every key but the neutral ones
    with pytest.raises(InputError, match="c3"):
        protocol_keys(Config, "c3")
    with pytest.raises(InputError, match="config dataclass"):
        neutral_keys(dict)
    with pytest.raises(InputError, match="non-empty"):
        protocol()


@pytest.mark.parametrize("study", ["wahba-table1", "wahba-orbit", "model-estimation", "rendezvous",
                                   "thruster-layout", "onoff-schmitt", "onoff-tuning", "closed-loop"])
def test_study_configs_declare_keys_one_way(study):
    # a key is neutral or protocol, never both; the Study's neutral keys are its Config's; and
    # no claims.py hand-lists protocol keys (they are read with protocol_keys)
    import ast
    from dataclasses import fields
    from pathlib import Path

    from adcskit.studies import get_study

    s = get_study(study)
    for f in fields(s.config_cls):
        assert not (f.metadata.get("neutral") and "protocol" in f.metadata), f.name
    assert s.neutral_keys == tuple(f.name for f in fields(s.config_cls) if f.metadata.get("neutral"))
    claims = Path(adcskit.studies.__file__).parent / study.replace("-", "_") / "claims.py"
    for node in ast.walk(ast.parse(claims.read_text(encoding="utf-8"))):
        if isinstance(node, ast.keyword) and node.arg == "protocol_keys":
            assert not isinstance(node.value, ast.Tuple | ast.List), (study, node.lineno)


def test_cli_announces_kernel_compilation_only_when_pending(fake, tmp_path, monkeypatch, capsys):
    # issue 23 item 6: a cold first run was silent for 106 s while numba compiled
    import adcskit.cli as cli

    monkeypatch.setattr(cli, "_KERNEL_STUDIES", frozenset({"fake"}))
    monkeypatch.setattr(cli, "_kernels_pending", lambda: 3)
    assert main(["run", "fake", "--quick", "--out", str(tmp_path / "a")]) == 0
    assert cli.KERNELS_NOTICE in capsys.readouterr().out
    monkeypatch.setattr(cli, "_kernels_pending", lambda: 0)
    assert main(["run", "fake", "--quick", "--out", str(tmp_path / "b")]) == 0
    assert cli.KERNELS_NOTICE not in capsys.readouterr().out


def test_kernels_pending_counts_modules_with_nothing_compiled(monkeypatch):
    # a warm run printed "compiling adcskit's numba kernels once" (2026-12-02): IR-inlined helpers
    # and entry points a run never calls have no cache entry of their own; a module counts only
    # when none of its own dispatchers is compiled or cached
    import sys
    import types

    import numba

    import adcskit.cli as cli

    called = numba.njit(lambda x: x + 1)
    assert called(1) == 2
    unused = numba.njit(lambda x: x + 2)
    inlined = numba.njit(inline="always")(lambda x: x * 2)
    warm = types.ModuleType("_adcskit_fake_warm")
    warm.called, warm.unused, warm.inlined = called, unused, inlined
    cold = types.ModuleType("_adcskit_fake_cold")
    cold.entry, cold.inlined = numba.njit(lambda x: x - 1), inlined
    only_inlined = types.ModuleType("_adcskit_fake_inlined")
    only_inlined.inlined = inlined
    for m in (warm, cold, only_inlined):
        monkeypatch.setitem(sys.modules, m.__name__, m)
    monkeypatch.setattr(cli, "_KERNEL_MODULES", (warm.__name__, cold.__name__, only_inlined.__name__))
    assert cli._kernels_pending() == 1  # the cold module only


def test_kernels_pending_reads_the_numba_caches():
    from adcskit.cli import _kernels_pending

    n = _kernels_pending()
    assert isinstance(n, int) and n >= 0


def test_run_study_records_and_marks_the_config_a_study_resolves(fake, monkeypatch):
    """Study.resolve(config, seed) decides settings before the run (onoff-tuning: S4's protocol
    when every paper-scale GA is stored); the runner runs, records and marks that config."""
    from dataclasses import replace

    import fake_study

    seen = []

    def resolve(cfg, seed):
        seen.append(seed)
        return replace(cfg, n_tasks=5)

    monkeypatch.setattr(fake_study, "STUDY", replace(fake_study.STUDY, resolve=resolve))
    result = run_study(fake, seed=4, out=None)
    assert seen == [4] and result.config["n_tasks"] == 5 and len(result.measured["means"]) == 5
    # issue 45 item 5: the study's own resolve step is its setting, not a custom configuration
    # (a default onoff-tuning run showed a "Custom configuration" banner for paper_scale)
    assert result.config_changes == {}
    assert result.claims[0].protocol == "reduced protocol"  # 5 tasks against the paper's 8
    assert result.claims[0].protocol_differences == ("n_tasks: ours 5, paper 8",)
    # a user's change is still one, recorded with the value that ran (here the resolve step's)
    custom = run_study(fake, seed=4, config={"n_tasks": 6}, out=None)
    assert custom.config_changes == {"n_tasks": {"value": 5, "default": 8, "paper": 8}}
    assert custom.claims[0].protocol == "custom settings"


def test_written_results_follow_the_umask_not_mkstemps_private_modes(tmp_path):
    """result.json and the study directory are created like any file (0o666 / 0o777 less the
    umask), so a shared results directory stays readable; the CSVs always were."""
    import os
    import stat

    from adcskit.studies import StudyResult, write_json_atomic, write_result

    mask = os.umask(0o022)
    try:
        d = write_result(StudyResult(study="demo", tables={"t": [{"a": 1}]}), tmp_path)
        write_json_atomic(tmp_path / "errors.json", {})
    finally:
        os.umask(mask)
    assert stat.S_IMODE(d.stat().st_mode) == 0o755
    for f in (d / "result.json", d / "t.csv", tmp_path / "errors.json"):
        assert stat.S_IMODE(f.stat().st_mode) == 0o644
    assert sorted(p.name for p in tmp_path.iterdir()) == ["demo", "errors.json"]  # no temporary left
