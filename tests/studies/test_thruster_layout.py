"""Quick run of the ``thruster-layout`` study (S3): result structure and key physics."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from adcskit.studies._base import paper_protocol, protocol_keys
from adcskit.studies._runner import protocol_differences, run_study
from adcskit.studies._verdict import OUTCOMES
from adcskit.studies.thruster_layout import A_REF, Config, manoeuvre_demands
from adcskit.studies.thruster_layout.experiment import torque_tolerance_nm


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("s3")
    res = run_study("thruster-layout", quick=True, seed=0, out=out)
    return res, json.loads((out / "thruster-layout" / "result.json").read_text()), out / "thruster-layout"


def test_result_structure(quick):
    _, doc, folder = quick
    runs = doc["measured"]["runs"]
    assert set(runs) == {"4", "6", "8", "12"}
    for n in runs:
        assert set(runs[n]) == {"ga", "de"}
        for alg in ("ga", "de"):
            for key in ("f_best", "torque_error", "e_min", "sum_tp_s", "runtime_s", "evaluations"):
                assert runs[n][alg][key] is not None
            assert len(runs[n][alg]["f_best_seeds"]) == 5  # verdicts over >= 5 seeds (issue 6)
    rvo = doc["measured"]["reference_vs_optimal"]
    assert {"sum_tp_ref_s", "sum_tp_opt_s"} <= set(rvo)
    assert set(rvo["by_allocation"]) == {"pinv-redistribute", "lp-min-fuel"}
    assert doc["paper"]["f_best"]["4"] == {"ga": 4.5, "de": 3.1}  # S3 §6 as printed
    for stem in ("runtime_vs_n", "fitness_vs_n", "on_times_ref_vs_opt", "convergence", "layouts_3d"):
        assert f"{stem}.png" in doc["figures"] and (folder / f"{stem}.png").is_file()
    # our own consistency checks are computed; the equal-torque premise of the fuel claim is one of
    # them (issue 21 §3 S3) and is reported, not asserted: it is a property of S3's allocation
    premise = "fuel comparison on equal torque"
    assert doc["checks"] and all(c["passed"] for c in doc["checks"] if not c["name"].startswith(premise))
    assert sum(c["name"].startswith(premise) for c in doc["checks"]) == 1
    assert all(c["kind"] == "check" for c in doc["checks"])


def test_claims_are_the_papers_and_decided_over_seeds(quick):
    _, doc, _ = quick
    claims = {c["id"]: c for c in doc["claims"]}
    assert set(claims) == {"de-more-accurate", "de-faster", "six-thrusters-best", "optimal-layout-less-fuel",
                           "table8-e-min"}
    for c in claims.values():
        assert c["statement"] and c["where"] and c["quantity"]
        assert c["outcome"] in OUTCOMES
        assert c["n_seeds"] == 5 and c["interval"][0] is not None
        # quick: 60 generations where S3 Table 6 prints 400, so every claim is below the paper's protocol
        # (issue 21 item 2); 5 seeds, so not indicative
        assert c["protocol"] == "reduced protocol" and not c["comparable"] and not c["indicative"]
        assert any(d.startswith("n_gen: ours 60, paper 400") for d in c["protocol_differences"])
    # de-faster is a timing claim (compared with a snapshot by outcome only) on process CPU time
    assert claims["de-faster"]["timing"] and "process_time" in claims["de-faster"]["quantity"]
    # the fuel claim is decided on the on-time ratio (log ratio, margin from its measured sampling
    # error); equal torque is the declared premise of every reading (issue 45 item 1): a seed that
    # misses a demand is no evidence for that reading, which is then inconclusive with the reason
    fuel_claim = claims["optimal-layout-less-fuel"]
    assert "0.212 N m" in fuel_claim["quantity"] and "4.1 % of |M|" in fuel_claim["quantity"]
    assert "redraws" in fuel_claim["margin_reason"] and fuel_claim["margin"] > 0
    assert "design demands, pinv-redistribute, best design: 0 (a factor 1.000)" in fuel_claim["margin_reason"]
    for r in fuel_claim["readings"]:
        if r["premise_failures"]:
            assert r["outcome"] == "inconclusive" and "equal torque" in r["detail"]
        elif all(math.log(v) < -0.5 for v in r["values"]):
            assert r["outcome"] == "holds"  # 5 of 5 seeds below 1 beyond any margin
    # readings: the fuel claim is decided out of sample with both allocations and both layouts,
    # Table 8 with the single-thruster and the paired-couple impulse bit
    fuel = {r["reading"] for r in claims["optimal-layout-less-fuel"]["readings"]}
    assert fuel == {"out of sample, pinv-redistribute, best design", "out of sample, lp-min-fuel, best design",
                    "design demands, pinv-redistribute, best design", "out of sample, pinv-redistribute, DE design",
                    "out of sample, lp-min-fuel, DE design"}
    t8 = {r["reading"]: r for r in claims["table8-e-min"]["readings"]}
    assert set(t8) == {"single thruster", "paired couple"}
    # outcome categories that the full run also finds, stable over the 5 quick seeds:
    # a single thruster in the 2x2x2 m box cannot exceed sqrt(3) F t_min/(t_s K) = 4.33e-4 rad,
    # half of Table 8's 8.3e-4 rad (physics, not the optimiser), so every seed misses Table 8
    assert t8["single thruster"]["outcome"] == "does not hold"
    assert all(v > 0.45 for v in t8["single thruster"]["values"])
    # eq. 18 never penalises extra thrusters: F_best(6) > min over the other n on every seed
    assert claims["six-thrusters-best"]["outcome"] == "does not hold"
    assert claims["de-more-accurate"]["outcome"] == "does not hold"
    findings = {f["id"]: f for f in doc["findings"]}
    assert findings["printed-layouts-realisable"]["outcome"] == "does not hold"  # S3's matrices: |column| > sqrt(3) m


def test_verdicts_follow_the_config(tmp_path):
    # a custom config changes the protocol: claims are marked not comparable, and the summary
    # and differences follow the actual settings (no hard-coded numbers)
    cfg = {"n_thrusters": [4, 6], "n_seeds": 2, "n_gen": 3, "pop_size": 8, "n_random_layouts": 2,
           "de_sensitivity": [], "n_fuel_demands": 5, "correction_deg": 0.25, "timing_repeats": 2}
    res = run_study("thruster-layout", config=cfg, seed=5, out=None)
    assert all(not c.comparable and c.protocol == "custom settings" for c in res.claims)
    assert all(c.indicative for c in res.claims)  # 2 < 5 seeds (issue 21 item 1)
    assert "corrections of 0.25 deg" in res.summary and "2 seeds" in res.summary
    assert all(c.n_seeds == 2 for c in res.claims)
    # timing repeats: each main design ran twice with its own seed, same F_best (a check), and the
    # CPU time per run is the median of the repeats
    checks = {c.name: c for c in res.checks}
    rep = next(c for n, c in checks.items() if n.startswith("every timing repeat"))
    assert rep.passed and "8 repeats of 8 designs" in rep.detail
    for r in res.measured["runs"].values():
        for by_alg in r.values():
            assert len(by_alg["cpu_s_seeds"]) == 2 and all(t > 0 for t in by_alg["cpu_s_seeds"])


def test_protocol_keys_declare_the_papers_values():
    # issue 21 item 2: every protocol key declares S3's printed value or "not printed"; our defaults
    # equal every printed value (Tables 5-7, §6, eq. 20), so the full run is at the paper's protocol
    declared = paper_protocol(Config)
    assert set(protocol_keys(Config)) - {"inertia_kgm2", "mdot_kg_s", "n_random_layouts", "de_sensitivity",
                                         "e_min_readings"} == set(declared)
    assert declared["n_gen"] == 400 and declared["weights"] == (100.0, -99.0, 12.0)  # S3 Tables 6, 7
    assert declared["pop_size"] == "not printed" and declared["correction_deg"] == "not printed"
    assert protocol_differences(Config, Config()) == {}
    assert set(protocol_differences(Config, Config(n_gen=60))) == {"n_gen"}


def test_torque_tolerance_is_the_references_minimum_torque_impulse():
    # S3 eq. 9-10: MTIB = F_max Delta t_min; per sample t_s it is a torque F_max Delta t_min / t_s.
    # Reference layout (S3 §6): largest lever sqrt(2) m; Table 5 / §6: 10 N, 3 ms; Table 6: 0.2 s
    assert torque_tolerance_nm(Config()) == pytest.approx(10 * math.sqrt(2) * 3e-3 / 0.2, rel=1e-12)
    # relative to the demand |M| = K theta (0.5 deg, K = 600): e_min,ref / theta = 4.05 %
    assert torque_tolerance_nm(Config()) / (600 * math.radians(0.5)) == pytest.approx(0.0405, abs=5e-5)


def test_reference_on_time_by_hand(quick):
    # A_REF (S3 §6): an axis demand |M| costs sum F = |M| (X/Z: two sqrt(2) thrusters at |M|/2;
    # Y: lever 1), a diagonal one 2|M|/sqrt(3). Mean over 6 axes + 8 diagonals, times t_s/F_max.
    _, doc, _ = quick
    M = 600 * math.radians(0.5)
    expected = 0.2 / 10 * M * (6 + 8 * 2 / math.sqrt(3)) / 14
    rvo = doc["measured"]["reference_vs_optimal"]
    assert rvo["sum_tp_ref_s"] == pytest.approx(expected, rel=1e-12)
    # the LP is the least-fuel allocation: never above the pseudo-inverse on the same layout
    by = rvo["by_allocation"]
    assert by["lp-min-fuel"]["sum_tp_opt_s"] <= by["pinv-redistribute"]["sum_tp_opt_s"] + 1e-12


def test_physical_bounds(quick):
    _, doc, _ = quick
    # e_min <= sqrt(3) F_max t_min / (t_s K) in the 2x2x2 m box (pulse-model derivation)
    bound = math.sqrt(3) * 10 * 3e-3 / (0.2 * 600)
    for n, by_alg in doc["measured"]["runs"].items():
        for _alg, r in by_alg.items():
            assert 0 < r["e_min"] <= bound * (1 + 1e-12)
            assert r["evaluations"] == 24 * 60  # quick: pop 24 x 60 generations
            A = np.asarray(r["best_layout"]["torque_matrix"])
            assert A.shape == (3, int(n))
            assert np.linalg.norm(A, axis=0).max() <= math.sqrt(3) + 1e-12


def test_manoeuvre_and_config():
    D = manoeuvre_demands(0.5, 600.0)
    assert D.shape == (14, 3)
    np.testing.assert_allclose(np.linalg.norm(D, axis=1), 600 * math.radians(0.5))
    assert A_REF.shape == (3, 6)
    from adcskit.errors import ConfigError

    with pytest.raises(ConfigError, match="algorithms"):
        Config(algorithms=("pso",))
    with pytest.raises(ConfigError, match="max_cant_deg"):
        Config(max_cant_deg=120.0)


def test_same_results_on_process_pool():
    # every optimisation carries its own SeedSequence: serial and process-pool runs must agree
    tiny = {"n_thrusters": [4, 6], "n_seeds": 1, "n_gen": 4, "pop_size": 8,
            "n_random_layouts": 2, "de_sensitivity": [], "n_fuel_demands": 3}
    a = run_study("thruster-layout", config=tiny, seed=3, out=None, executor="serial")
    b = run_study("thruster-layout", config=tiny, seed=3, out=None, executor="processes:2")
    for n in ("4", "6"):
        for alg in ("ga", "de"):
            assert a.measured["runs"][n][alg]["f_best_seeds"] == b.measured["runs"][n][alg]["f_best_seeds"]
