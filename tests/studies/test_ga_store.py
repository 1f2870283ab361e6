"""The stored paper-scale GA runs of onoff-tuning (issue 45, item 4): manifest, exact
re-evaluation on replay, code- and library-bound fingerprint, re-stamping, recompute."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from adcskit.studies.onoff_tuning import ga_store
from adcskit.studies.onoff_tuning.config import Config
from adcskit.studies.onoff_tuning.experiment import ga_jobs
from adcskit.studies.onoff_tuning.ga_store import (
    MANIFEST,
    PACKAGED,
    GAStore,
    StoredRunError,
    code_stamp,
    read_manifest,
    restamp,
    write_manifest,
)

#: a GA small enough to run in a test (the TINY config of tests/studies/test_onoff_tuning.py)
TINY = dict(t_final_s=3.0, t_window_s=1.0, n_seeds=2, ga_pop=4, ga_max_gen=1, ga_window=1, n_lhs=2,
            sweep_ratios=(10.0,), sweep_max_gen=1)


def _packaged():
    return [json.loads(p.read_text()) for p in sorted(PACKAGED.glob("*.json"))]


def _job(label):
    """The (dists, tune_robust keywords) of a packaged run (the study's default paper-scale run, seed 0)."""
    return next((d, kw) for lab, d, kw in ga_jobs(Config(paper_scale=True), 0) if lab == label)


def test_manifest_lists_every_packaged_run_with_its_sha256():
    import hashlib

    manifest = read_manifest(PACKAGED)
    files = sorted(PACKAGED.glob("*.json"))
    assert len(files) == 34  # 30 claim GAs (5 seeds x 6) + 4 ratio-sweep GAs
    assert sorted(manifest) == [f.name for f in files]
    for f in files:
        assert hashlib.sha256(f.read_bytes()).hexdigest() == manifest[f.name], f.name


def test_packaged_runs_are_stamped_with_this_code_and_replay_only_with_these_libraries():
    """Every packaged run records the code hashes and library versions in its fingerprint and its
    provenance. Code: this tree's (else re-stamp: benchmarks/restamp_ga_store.py). Libraries:
    where they differ from the stamp, no packaged run is replayed."""
    stamp = code_stamp()
    store = GAStore(PACKAGED, writable=False)
    jobs = ga_jobs(Config(paper_scale=True), 0)
    for d in _packaged():
        assert d["format"] == 2
        prov = d["provenance"]
        stamped = prov["restamps"][-1] if prov.get("restamps") else prov  # the run's own stamp, or its last re-stamp
        assert d["code"] == stamped["code"] and d["versions"] == stamped["versions"]
        assert d["code"] == stamp["code"], (f"{d['label']}: the GA code changed since the packaged runs were stamped; "
                                            "run benchmarks/restamp_ga_store.py (see its docstring)")
        assert set(d["versions"]) == {"pymoo", "numpy", "scipy", "numba"}
        assert prov["date"][11:].count(":") >= 1 and prov["wall_s"] > 0  # time of day, wall time
    held = {lab for lab, dists, kw in jobs if store.has(dists, **kw)}
    if all(d["versions"] == stamp["versions"] for d in _packaged()):
        assert held == {lab for lab, _, _ in jobs}  # complete: the default full run is S4's protocol
    else:
        assert held == set()  # other libraries: never replayed


def _copy(tmp_path):
    target = tmp_path / "store"
    shutil.copytree(PACKAGED, target)
    return target


def _tamper(directory, label="s0_all_sample", old="54.849", new="44.849"):
    """One byte of a stored x changed (S0's all-four GA: K_p 54.85 -> 44.85)."""
    path = next(directory.glob(f"{label}_*.json"))
    text = path.read_text()
    assert text.count(old) == 1
    path.write_text(text.replace(old, new))
    return path


def test_a_tampered_copy_is_refused_by_the_manifest(tmp_path):
    directory = _copy(tmp_path)
    path = _tamper(directory)
    dists, kw = _job("s0_all_sample")
    store = GAStore(directory, writable=False)
    with pytest.raises(StoredRunError, match=rf"{path.name}.*SHA-256 differs from the store's manifest"):
        store.has(dists, **kw)
    with pytest.raises(StoredRunError, match=path.name):
        store.tune("s0_all_sample", dists, **kw)
    # a file the manifest does not list is refused as well
    extra = directory / path.name.replace("s0_all_sample", "s9_all_sample")
    shutil.copy(path, extra)
    other_dists, other_kw = _job("s0_delay_sample")
    path.write_text(path.read_text().replace("44.849", "54.849"))  # restored: only the extra file is foreign
    with pytest.raises(StoredRunError, match=rf"{extra.name}.*not listed"):
        GAStore(directory, writable=False).tune("s0_all_sample", dists, **kw)
    extra.unlink()
    assert GAStore(directory, writable=False).has(other_dists, **other_kw)


def test_a_tampered_copy_with_a_renewed_manifest_is_refused_by_the_exact_re_evaluation(tmp_path):
    """Rewriting the manifest does not help: replay re-evaluates the stored gains on the GA's own
    1000 training samples and requires the stored objective bit for bit."""
    directory = _copy(tmp_path)
    path = _tamper(directory)
    write_manifest(directory)
    dists, kw = _job("s0_all_sample")
    store = GAStore(directory, writable=False)
    assert store.has(dists, **kw)  # fingerprint and manifest match ...
    with pytest.raises(StoredRunError, match=rf"s0_all_sample.*{path.name}.*do not reproduce its stored result"):
        store.tune("s0_all_sample", dists, **kw)  # ... the gains do not give the stored objective
    # the untouched runs replay, verified, with their provenance
    dists, kw = _job("sweep_all_10")
    res, src = store.tune("sweep_all_10", dists, **kw)
    stored = next(d for d in _packaged() if d["label"] == "sweep_all_10")
    assert res.x.tolist() == stored["result"]["x"] and res.fun == stored["result"]["fun"]
    assert src["file"].startswith("sweep_all_10_") and "sweep_all_10" in store.verify_s
    assert src["restamps"] and src["restamps"][-1]["recomputed"]


def test_changed_code_or_libraries_never_replay_a_stored_run(monkeypatch):
    from adcskit.studies import onoff_tuning as ot

    stamp = code_stamp()
    dists, kw = _job("s1_delay_sample")
    store = GAStore(PACKAGED, writable=False)
    assert store.has(dists, **kw) == (stamp["versions"] == _packaged()[0]["versions"])
    changed_code = {"code": {**stamp["code"], "adcskit.control.robust": "0" * 64}, "versions": stamp["versions"]}
    changed_lib = {"code": stamp["code"], "versions": {**stamp["versions"], "pymoo": "9.9"}}
    for changed in (changed_code, changed_lib):
        monkeypatch.setattr(ga_store, "code_stamp", lambda changed=changed: changed)
        assert not GAStore(PACKAGED, writable=False).has(dists, **kw)
        assert ot.resolve_paper_scale(Config(), 0) == Config()  # the reduced protocol, not stale GAs


def test_code_hash_follows_code_not_docstrings_or_comments():
    src = '"""Module."""\nX = 1  # one\n\n\ndef f(a):\n    """Doc."""\n    return a + X\n'
    h = ga_store.code_hash(src)
    assert h == ga_store.code_hash(src.replace("Doc.", "Other words.").replace("# one", "# uno"))
    assert h != ga_store.code_hash(src.replace("a + X", "a - X"))
    assert h != ga_store.code_hash(src.replace("X = 1", "X = 2"))


def test_restamp_adopts_new_code_only_after_exact_re_evaluation_and_a_bit_identical_recompute(tmp_path, monkeypatch):
    cfg = Config(**TINY, ga_store=str(tmp_path / "s"))
    jobs = ga_jobs(cfg, 3)
    store = GAStore(tmp_path / "s", writable=True)
    for label, dists, kw in jobs:
        store.tune(label, dists, **kw)
    write_manifest(tmp_path / "s")
    old = {p.name for p in (tmp_path / "s").glob("*.json")}
    assert len(old) == len(jobs) == 2 * 6 + 1
    new_stamp = {**code_stamp(), "code": {**code_stamp()["code"], "adcskit.control.tuning": "1" * 64}}
    monkeypatch.setattr(ga_store, "code_stamp", lambda: new_stamp)
    assert not any(GAStore(tmp_path / "s", writable=False).has(d, **kw) for _, d, kw in jobs)
    with pytest.raises(ValueError, match="at least one run to recompute"):
        restamp(tmp_path / "s", jobs, ())
    # a tampered file stops the re-stamp before anything is written
    bad = next((tmp_path / "s").glob("s1_delay_sample_*.json"))
    d = json.loads(bad.read_text())
    d["result"]["fun"] = d["result"]["fun"] * (1 + 1e-15)
    bad.write_text(json.dumps(d))
    write_manifest(tmp_path / "s")
    with pytest.raises(StoredRunError, match=rf"s1_delay_sample.*{bad.name}"):
        restamp(tmp_path / "s", jobs, ("s0_all_sample",), log=lambda *a: None)
    assert {p.name for p in (tmp_path / "s").glob("*.json")} == old
    bad.unlink()
    jobs = [j for j in jobs if j[0] != "s1_delay_sample"]
    out = restamp(tmp_path / "s", jobs, ("s0_all_sample",), note="test", log=lambda *a: None)
    assert set(out["verify_s"]) == {lab for lab, _, _ in jobs} and set(out["recompute_s"]) == {"s0_all_sample"}
    store = GAStore(tmp_path / "s", writable=False)
    assert all(store.has(d, **kw) for _, d, kw in jobs)
    assert sorted(read_manifest(tmp_path / "s")) == sorted(out["files"])
    d = json.loads(next((tmp_path / "s").glob("s0_all_sample_*.json")).read_text())
    entry = d["provenance"]["restamps"][-1]
    assert d["code"] == entry["code"] == new_stamp["code"] and d["provenance"]["code"] != new_stamp["code"]
    assert list(entry["recomputed"]) == ["s0_all_sample"] and "bit-identical" in entry["verified"]


@pytest.mark.slow
def test_a_packaged_ga_recomputed_from_scratch_is_bit_identical():
    """sweep_all_1 (20 generations x 70 x 1000 loops, ~1 min on two cores) from scratch: the
    stored x, fun and history bit for bit (the quick tests cover the verification path)."""
    from adcskit.control.tuning import tune_robust

    dists, kw = _job("sweep_all_1")
    res = tune_robust(dists, **kw)
    st = next(d for d in _packaged() if d["label"] == "sweep_all_1")["result"]
    assert [v.hex() for v in res.x] == [float(v).hex() for v in st["x"]]
    assert res.fun.hex() == float(st["fun"]).hex() and res.nit == st["nit"]
    assert np.array_equal(res.history, np.array(st["history"]))


def test_manifest_file_is_named_as_documented():
    assert MANIFEST == "SHA256SUMS" and (PACKAGED / MANIFEST).is_file()
