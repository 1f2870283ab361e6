"""Quick run of the rendezvous study (S2) and the rendezvous problem's physics."""

from __future__ import annotations

import csv
import json
import math

import casadi as ca
import numpy as np
import pytest

from adcskit.optimal_control.problems.rendezvous import (
    RendezvousParams,
    mean_motion,
    mrp_dcm,
    mrp_kinematics_matrix,
    rendezvous_problem,
)
from adcskit.studies._runner import run_study


def _num(f, *args):
    return np.array(f(*[ca.DM(a) for a in args])).squeeze()


def test_mrp_dcm_matches_quaternion_convention():
    # design.md: A(q) = (q4² − |e|²) I + 2 e eᵀ − 2 q4 [e×]; MRP σ = e / (1 + q4)
    rng = np.random.default_rng(3)
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    q *= np.sign(q[3])
    e, q4 = q[:3], q[3]
    ex = np.array([[0, -e[2], e[1]], [e[2], 0, -e[0]], [-e[1], e[0], 0]])
    A = (q4**2 - e @ e) * np.eye(3) + 2 * np.outer(e, e) - 2 * q4 * ex
    np.testing.assert_allclose(_num(mrp_dcm, e / (1 + q4)), A, atol=1e-14)


def test_mrp_kinematics_matches_eq5():
    s = np.array([0.1, -0.2, 0.3])
    s2 = s @ s
    # S2 eq. 5 printed element by element
    B = np.array(
        [
            [1 - s2 + 2 * s[0] ** 2, 2 * (s[0] * s[1] - s[2]), 2 * (s[0] * s[2] + s[1])],
            [2 * (s[1] * s[0] + s[2]), 1 - s2 + 2 * s[1] ** 2, 2 * (s[1] * s[2] - s[0])],
            [2 * (s[2] * s[0] - s[1]), 2 * (s[2] * s[1] + s[0]), 1 - s2 + 2 * s[2] ** 2],
        ]
    )
    np.testing.assert_allclose(_num(mrp_kinematics_matrix, s), B, atol=1e-15)


def test_mrp_dcm_agrees_with_attitude_package():
    from adcskit.attitude.mrp import mrp_to_dcm

    s = np.array([0.2, -0.1, 0.35])
    np.testing.assert_allclose(_num(mrp_dcm, s), mrp_to_dcm(s), atol=1e-14)


def test_translation_agrees_with_cw_matrices():
    # independent implementation: adcskit.dynamics.cw_matrices (same LVLH axes as S2)
    from adcskit.dynamics.relative_motion import cw_matrices

    n = mean_motion(580e3)
    A, B = cw_matrices(n)
    p = rendezvous_problem((20, 0, 0))
    x = np.zeros(12)
    x[6:9] = [0.1, -0.2, 0.3]
    x[9:12] = [5.0, 2.0, -3.0]
    F = np.array([0, 0, 0, 30.0, -50.0, 80.0])
    f = np.array(p.dynamics(ca.DM(x), ca.DM(F), 0)).ravel()
    ref = A @ np.r_[x[9:12], x[6:9]] + B @ (F[3:] / RendezvousParams().mass)
    np.testing.assert_allclose(np.r_[f[9:12], f[6:9]], ref, atol=1e-15)


def test_hill_equations_and_mean_motion():
    # 580 km circular orbit: n = sqrt(mu/a^3) = 1.0887e-3 rad/s (period ~96.2 min)
    n = mean_motion(580e3)
    assert 2 * math.pi / n / 60 == pytest.approx(96.2, abs=0.1)
    p = rendezvous_problem((20, 0, 0))
    x = np.zeros(12)
    x[6:9] = [0.1, 0.2, 0.3]
    x[9:12] = [1.0, 2.0, 3.0]
    f = np.array(p.dynamics(ca.DM(x), ca.DM.zeros(6), 0)).ravel()
    # S2 eq. 6 with zero force: v̇ = −M v − N s
    M = np.array([[0, 0, -2 * n], [0, 0, 0], [2 * n, 0, 0]])
    N = np.diag([0, n**2, -3 * n**2])
    np.testing.assert_allclose(f[6:9], -M @ x[6:9] - N @ x[9:12], atol=1e-15)
    np.testing.assert_allclose(f[9:12], x[6:9])


def test_full_and_paper_dynamics_differ_only_by_dropped_terms():
    pa = rendezvous_problem((20, 0, 0), dynamics="paper")
    pf = rendezvous_problem((20, 0, 0), dynamics="full")
    rng = np.random.default_rng(1)
    x = rng.normal(scale=0.2, size=12)
    u = rng.normal(size=6)
    fa = np.array(pa.dynamics(ca.DM(x), ca.DM(u), 0)).ravel()
    ff = np.array(pf.dynamics(ca.DM(x), ca.DM(u), 0)).ravel()
    np.testing.assert_array_equal(fa[3:], ff[3:])
    I = np.array(RendezvousParams().inertia)
    w = x[:3]
    A = np.array(mrp_dcm(ca.DM(x[3:6])))
    wli = A @ np.array([0, -mean_motion(580e3), 0])
    # dropped terms: −ω × I ω_LI − I (ω_LI × ω), divided by I
    dropped = (-np.cross(w, I * wli) - I * np.cross(wli, w)) / I
    np.testing.assert_allclose(ff[:3] - fa[:3], dropped, atol=1e-15)


@pytest.fixture(scope="module")
def quick_runs(tmp_path_factory):
    # two root seeds = two independent multistart draws (the claims are deterministic given
    # the starts; the seeds test that their outcomes do not hinge on which starts were drawn)
    out = tmp_path_factory.mktemp("rv")
    docs = []
    for seed in (0, 1):
        run_study("rendezvous", quick=True, seed=seed, out=out / str(seed))
        d = out / str(seed) / "rendezvous"
        doc = json.loads((d / "result.json").read_text())
        doc["_tables"] = {
            name.removesuffix(".csv"): list(csv.DictReader((d / name).open())) for name in doc["tables"]
        }
        docs.append(doc)
    return docs


def test_quick_study_structure(quick_runs):
    doc = quick_runs[0]
    assert {"claims", "checks", "findings"} <= set(doc)
    ids = {c["id"] for c in doc["claims"]}
    # quick rows: the main scenario and Table 4 row 3
    assert ids == {"tf_main", "bang_bang", "hamiltonian", "table4_gpm_row3"}
    for c in doc["claims"]:
        assert c["outcome"] in ("holds", "does not hold", "inconclusive", "depends on reading")
        dyn = ["eq. 2 as printed", "full relative dynamics"]
        names = [r["reading"] for r in c["readings"]]
        if c["id"] in ("bang_bang", "hamiltonian"):
            assert names == dyn
        else:  # tf values: dynamics x precision (printed digits / same optimum)
            assert names == [f"{d} / {p}" for d in dyn for p in ("printed digits", "same optimum")]
        assert c["where"] and c["statement"]
    assert all(c["passed"] for c in doc["checks"]), [c for c in doc["checks"] if not c["passed"]]
    assert len(doc["figures"]) == 15  # Figs 3-15 (13) + Table 4 summary + refinement history
    # every branch carries its error certificate, and its refinement starts with the primal-dual
    # re-solve of its own 20x3 optimum (20 intervals x 3 LG points = 60 nodes)
    br = doc["_tables"]["branches"]
    assert br and all(math.isfinite(float(b["max_state_error"])) and int(b["n_nodes"]) >= 60 for b in br)
    assert all(
        (b["tolerance_met"] == "True") == (float(b["max_state_error"]) <= float(b["tol"])) for b in br
    )
    d0 = "eq. 2 as printed"
    first = [h for h in doc["_tables"]["mesh_history"] if h["iteration"] == "1" and h["dynamics"] == d0]
    assert len(first) == sum(b["dynamics"] == d0 for b in br)
    assert all(
        (h["n_intervals"], h["n_nodes"], h["warm_start"]) == ("20", "60", "primal-dual") for h in first
    )
    m = doc["measured"]["readings"]["eq. 2 as printed"]["rows"]["[20.0, 0.0, 0.0]"]
    # tf between the pure-translation bound 2*sqrt(20/(sqrt2*0.1)) and the single-axis bound
    # 2*sqrt(20/0.1) = 28.28 s (S2 Table 2 limits: 320 N / 3200 kg = 0.1 m/s^2)
    assert 2 * math.sqrt(20 / (math.sqrt(2) * 0.1)) < m["best_paper_mesh_s"] < 28.29


def test_quick_claims_stable_over_seeds(quick_runs):
    # outcomes of the full run (docs/studies/rendezvous.md) that the quick settings reach too:
    # 25.8727 s is the 20x3 optimum of eq. 2 as printed to every printed digit (S2 Sec. 6,
    # Table 4) and misses the full relative dynamics by 3.6e-4 s. Row 3's 25.9360 s misses our
    # optimum by 5.09e-5 s against the half unit 5e-5 s: the 8.9e-7 s excess is about the
    # solver repeatability (the equivalence margin), so that reading is a tie or does not hold
    # depending on the run's measured repeatability -- it never holds (issue 21)
    H, N, I = "holds", "does not hold", "inconclusive"
    expected = {
        "tf_main": ((H,), (H,), (N,), (H,)),
        "table4_gpm_row3": ((I, N), (H,), (N,), (H,)),
        "bang_bang": ((H,), (H,)),
        "hamiltonian": ((H,), (H,)),
    }
    for doc in quick_runs:
        got = {c["id"]: tuple(r["outcome"] for r in c["readings"]) for c in doc["claims"]}
        assert set(got) == set(expected)
        for cid, want in expected.items():
            assert all(g in w for g, w in zip(got[cid], want, strict=True)), (cid, got[cid])
        rep = doc["measured"]["repeatability_s"]
        assert 0 < rep < 1e-5  # IPOPT tol 1e-9 on the scaled NLP: re-solves agree to ~1e-6 s
        for c in doc["claims"]:
            # a quick run has 2 of S2's 5 rows: below the paper's protocol, never comparable
            assert c["protocol"] == "reduced protocol" and not c["comparable"] and not c["indicative"]
            assert c["protocol_differences"][0].startswith("rows_m:")
            if c["id"] in ("tf_main", "table4_gpm_row3"):
                assert c["margin"] == rep and c["margin_reason"]
        main = next(c for c in doc["claims"] if c["id"] == "tf_main")
        assert main["outcome"] == "depends on reading"
        # |25.8727 - ours| - 5e-5 s under eq. 2 as printed (s): the value is ours to its digits
        assert main["measured"] < -3e-5


def _fake_branch(tf0, tfs, errors, *, tol=1e-5, met=True, nlp_ok=True):
    """A branch as _branch_record reads it: 20x3 start and a refinement history (no solve)."""
    from types import SimpleNamespace as NS

    from adcskit.optimal_control import Mesh
    from adcskit.studies.rendezvous.experiment import _Branch

    hist = tuple(
        NS(
            objective=t,
            success=nlp_ok if k == len(tfs) - 1 else True,
            meshes=(Mesh.uniform(20 * (k + 1), 3),),
            n_collocation=60 * (k + 1),
            max_error=e,
            nit=1 if k == 0 else 30,
            warm_start="primal-dual" if k == 0 else "primal",
        )
        for k, (t, e) in enumerate(zip(tfs, errors, strict=True))
    )
    cert = NS(
        satisfied=met, tol=tol, max_error=errors[-1], n_collocation=hist[-1].n_collocation,
        mesh_iterations=len(hist), worst_time=1.0,
    )
    final = NS(mesh_history=hist, certificate=cert, message="m", tf=tfs[-1], mesh=hist[-1].meshes[0])
    return _Branch(NS(tf=tf0, success=True, mesh=hist[0].meshes[0]), final, float("nan"), 0.0)


def test_branch_record_flags_jumps_and_reports_the_certificate():
    # jump_factor x adaptive_tol = 1 x 1e-3 = 1e-3 (relative): a refinement of the 25.87 s
    # optimum that ends on the 26.15 s branch (1.1 % away, S2 row 1's second optimum) is a
    # jump; a move of 1e-4 (the 20x3 -> converged change of the main row) is not
    from adcskit.studies.rendezvous.config import Config
    from adcskit.studies.rendezvous.experiment import _branch_record

    cfg = Config()
    assert cfg.same_rtol == pytest.approx(1e-3)
    ok = _branch_record(_fake_branch(25.8727, [25.8727, 25.8705, 25.8700], [1e-3, 4e-5, 8e-6]), cfg)
    assert ok["on_branch"] and ok["tolerance_met"] and ok["converged"]
    assert ok["tf_converged_s"] == 25.8700 and ok["max_error"] == 8e-6 and ok["mesh_iterations"] == 3
    assert ok["self_resolve_mode"] == "primal-dual" and ok["self_resolve_change"] == 0.0
    assert ok["max_tf_move"] == pytest.approx(2.7e-3 / 25.8727)
    jump = _branch_record(_fake_branch(25.8727, [25.8727, 26.1540], [1e-3, 8e-6]), cfg)
    assert not jump["on_branch"] and "branch jump at mesh iteration 2" in jump["message"]
    # an intermediate excursion counts too, even if the last solve returns near the start
    back = _branch_record(_fake_branch(25.8727, [25.8727, 26.15, 25.8701], [1e-3, 1e-4, 8e-6]), cfg)
    assert not back["on_branch"]
    # tolerance not met: the achieved error is reported as it is, the value is kept
    miss = _branch_record(
        _fake_branch(25.8727, [25.8727, 25.8702], [1e-3, 3e-5], met=False), cfg
    )
    assert not miss["tolerance_met"] and not miss["converged"] and miss["max_error"] == 3e-5
    assert miss["tf_converged_s"] == 25.8702
    # a failed last NLP solve has no converged value
    bad = _branch_record(_fake_branch(25.8727, [25.8727, 25.9], [1e-3, 1e-2], met=False, nlp_ok=False), cfg)
    assert math.isnan(bad["tf_converged_s"]) and not bad["on_branch"]


# Full run (root seed 0, 16 starts, error-controlled refinement to a relative state error of
# 1e-3 with solve_adaptive's defaults: transfer_duals, mesh_reduction, the switch snap, and the
# exact-switch-time re-solve and optimality check of issue 22; `adcskit run rendezvous` of
# 2026-12-01 at main 0b9ca01+, its branches.csv): per Table 4 row and dynamics reading, each
# local branch as (20x3 tf, converged tf) in s.
_FULL_RUN = {
    "paper": [
        [(25.872706, 25.870004), (26.156705, 26.153977)],
        [(25.789172, 25.787187), (26.036548, 26.033526)],
        [(25.93594910579, 25.932368), (26.168251, 26.165178)],  # row 3 to 11 decimals: a tie is at stake
        [(25.660545, 25.658952), (25.903083, 25.900051)],
        [(28.279789, 28.278427), (28.569247, 28.564589)],
    ],
    "full": [
        [(25.873064, 25.870405), (26.156518, 26.153848)],
        [(25.789525, 25.787583), (26.036981, 26.033915)],
        [(25.936541, 25.933021), (26.168945, 26.165896)],
        [(25.660937, 25.659335), (25.903429, 25.900396)],
        [(28.280283, 28.278949), (28.569770, 28.565115)],
    ],
}


def _rows_from(branches_per_row):
    # the fields of experiment.RowRecord / BranchRecord that the decisions read
    from types import SimpleNamespace as NS

    rows = {}
    for i, pairs in enumerate(branches_per_row):
        br = [
            NS(tf_paper_mesh_s=a, tf_converged_s=b, on_branch=True, converged=True, self_resolve_change=math.nan)
            for a, b in pairs
        ]
        rows[i] = NS(
            branches=br,
            spread_per_optimum_s=[0.0 for _ in pairs],
            optima_paper_mesh_s=[a for a, _ in pairs],
            best_paper_mesh_s=min(a for a, _ in pairs),
            converged_optima_s=sorted(b for _, b in pairs),
            best_converged_s=min(b for _, b in pairs),
            n_starts=16,
        )
    return rows


# The solver repeatability of that run (s): the largest change of a 20x3 tf when its refinement
# re-solves it from itself (row 4's second optimum, 25.903082770 -> 25.903083702 s, branches.csv
# and mesh_history.csv); the starts that reached one optimum spread by at most 6.5e-8 s.
_FULL_RUN_REPEAT_S = 9.32e-7


def _full_run_decisions(repeat_s=_FULL_RUN_REPEAT_S):
    from dataclasses import replace
    from types import SimpleNamespace as NS

    from adcskit.studies.rendezvous.claims import _decide
    from adcskit.studies.rendezvous.config import Config
    from adcskit.studies.rendezvous.experiment import _derive

    cfg = Config()
    meas = {}
    for dyn, rows in _FULL_RUN.items():
        m = _derive(_rows_from(rows), dyn, cfg)
        meas[dyn] = replace(m, main=NS(bang_bang_all=True, h_max_dev_paper_mesh=0.021), repeatability_s=repeat_s)
    claims, findings = _decide(meas, cfg, list(range(5)))
    return meas, claims, findings


def test_claim_decisions_from_the_full_run_branches():
    # the decision logic alone (no solves): the full run's branches must give the full run's
    # outcomes, so a change of a tolerance or of the branch identification that flips a
    # verdict fails here
    meas, claims, findings = _full_run_decisions()
    got = {c.id: (c.outcome, tuple(r.outcome for r in c.readings)) for c in claims}
    H, N, D, I = "holds", "does not hold", "depends on reading", "inconclusive"
    assert got["tf_main"] == (D, (H, H, N, H))  # digits / same optimum x printed / full
    assert got["table4_gpm_row2"] == (N, (N, N, N, N))  # 26.1674: no optimum of ours
    # S2 Table 4 row 3: |25.9360 - 25.935949| = 5.089e-5 s against the half unit 5e-5 s: the
    # excess 8.9e-7 s lies within the solver repeatability 9.3e-7 s, a tie (issue 21)
    assert got["table4_gpm_row3"] == (D, (I, H, N, H))
    assert got["table4_gpm_row4"] == (D, (N, H, N, H))  # 25.6607 vs 25.660546: 1.5e-4 s
    assert got["table4_gpm_row5"] == (N, (N, N, N, N))  # 28.7185: no optimum of ours
    # same optimum (1e-3): rows 3, 4 sit on different optima; S2's own 'agree well' (<= 1.5325 %,
    # Table 4 row 5): our best 20x3 optima are within 0.94 % of every GPOPS value
    assert got["agrees_with_gpops"] == (D, (N, H, N, H))
    loose = next(c for c in claims if c.id == "agrees_with_gpops").readings[1]
    # row 2: |25.789172 - 26.0336| / 25.789172 = 0.948 % (relative to the GPM value, as S2's column)
    assert loose.values[0] == pytest.approx(0.244428 / 25.789172 - 0.015325, abs=1e-6)
    assert got["gpm_sometimes_shorter"] == (H, (H, H))  # rows 3, 4: 0.89 %, 0.92 % shorter
    fnd = {f.id: f.outcome for f in findings}
    assert fnd == {
        "several_converged_optima": H,
        "second_optima_persist": H,
        "gpops_on_converged_branches": H,
        "gpops_is_best": N,  # rows 2, 3, 4: GPOPS sits on the second branch
    }
    # GPOPS rows 2-4 are the second converged branch, rows 1 and 5 the best
    assert meas["paper"]["gpops_branch"] == [0, 1, 1, 1, 0]


def test_row3_printed_digits_is_no_longer_rescued_by_a_cushion():
    # issue 21: the old 1e-5 s cushion (ten times the repeatability) made row 3 "hold" to its
    # printed digits; now the repeatability is the equivalence margin on both sides. Without
    # any margin, or with row 3's own repeatability (5.1e-7 s: 25.935949106 -> 25.935949612 s
    # on its re-solve), the 8.9e-7 s excess does not hold; it never holds
    for repeat_s, want in ((0.0, "does not hold"), (5.1e-7, "does not hold"), (_FULL_RUN_REPEAT_S, "inconclusive")):
        _, claims, _ = _full_run_decisions(repeat_s)
        row3 = next(c for c in claims if c.id == "table4_gpm_row3")
        assert row3.readings[0].outcome == want, repeat_s
        assert row3.margin == repeat_s and "repeatab" in row3.margin_reason


def test_table4_difference_column_is_relative_to_the_gpm_value():
    # S2 Table 4, last column: |GPM - GPOPS| / GPM in %, to its 4 printed decimals (e.g.
    # 0.1338 / 26.1674 = 0.5113 %); the 'agree well' reading uses the same definition
    from adcskit.studies.rendezvous.paper import PAPER_ROWS

    for _, gpm, gpops, pct in PAPER_ROWS:
        assert abs(100 * abs(gpm - gpops) / gpm - pct) <= 0.5e-4, (gpm, gpops, pct)


def test_repeatability_is_measured_from_starts_and_self_resolves():
    from types import SimpleNamespace as NS

    from adcskit.studies.rendezvous.experiment import repeatability

    b = [NS(tf_paper_mesh_s=25.903082770, self_resolve_change=3.6e-8), NS(tf_paper_mesh_s=26.0, self_resolve_change=math.nan)]
    rows = {0: NS(spread_per_optimum_s=(6.5e-8, 0.0), branches=b)}
    assert repeatability(rows) == pytest.approx(3.6e-8 * 25.903082770)
    rows = {0: NS(spread_per_optimum_s=(2e-6,), branches=b)}  # a spread over starts can dominate
    assert repeatability(rows) == 2e-6
    assert math.isnan(repeatability({0: NS(spread_per_optimum_s=(), branches=[])}))
