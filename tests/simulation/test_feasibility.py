"""Feasibility before flight, units of the metrics, dispersion semantics and the compile notice
(issue 23 items 2, 3, 6).

Every simulation here is short (<= 100 steps x <= 8 samples): the kernel itself is checked in
test_simulation.py; these tests check what ``simulate`` decides before and around it.
"""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from adcskit._jit import CLOSED_LOOP_NOTICE, will_compile
from adcskit.dynamics import propagate_attitude
from adcskit.errors import InputError, UncontrollableWarning
from adcskit.simulation import (
    METRIC_NAMES,
    ControllerSpec,
    DispersionSpec,
    EstimatorSpec,
    GuidanceSpec,
    Scenario,
    SimSpec,
    SpacecraftSpec,
    ThrusterSpec,
    load_scenario,
    simulate,
)
from adcskit.simulation.core import S3_REFERENCE_A, _controllability
from adcskit.thrusters import check_controllability

TINY = SimSpec(dt=0.02, t_final=1.0, metrics_from_s=0.5)

# docs/simulation.md, "Scenario reference": one working thruster (the other failed) for three axes
DOCS_TOML = """[sim]
dt = 0.02
t_final = 60.0
metrics_from_s = 45.0

[controller]
kind = "schmitt"
allocation = "lp-min-fuel"

[thrusters]
positions = [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]
directions = [[0.0, 1.0, 0.0], [0.0, -1.0, 0.0]]
failed = [1]
"""


# ----------------------------------------------------------------- feasibility before flight


def test_issue23_failed_reference_thruster_warns_and_is_not_success():
    # issue 23 reproduction: S3's reference layout (S3 §6) without thruster 2 cannot produce
    # torque along -x+z (columns left in the x-z plane: (-1,-1), (1,1), (1,-1)); the issue ran
    # 100 samples x 100 s, the verdict comes before the flight, so 4 samples x 1 s suffice
    sc = Scenario(thrusters=ThrusterSpec.from_torque_matrix(S3_REFERENCE_A, failed=(2,)),
                  guidance=GuidanceSpec(kind="step", target_rotvec_deg=(0, 0, 30), t_step=5), sim=TINY)
    with pytest.warns(UncontrollableWarning, match=r"thruster\(s\) \[2\] failed.*cannot produce torque") as rec:
        res = simulate(sc, 4, rng=42)
    assert "[-0.707  0.     0.707]" in str(rec[0].message)  # the unreachable direction, -x+z
    assert res.controllable.dtype == bool and not res.controllable.any()
    assert not res.success and "cannot produce torque" in res.message
    assert res.to_dict()["controllable_fraction"] == 0.0


def test_issue23_docs_toml_example_warns():
    # the TOML example of docs/simulation.md: one working thruster for three axes
    docs = (Path(__file__).parents[2] / "docs" / "simulation.md").read_text(encoding="utf-8")
    assert DOCS_TOML in docs  # the example tested is the one printed
    import tomllib

    sc = load_scenario(tomllib.loads(DOCS_TOML))
    with pytest.warns(UncontrollableWarning, match="rank 1 < 3"):
        res = simulate(sc.replace(sim=TINY), 2, rng=0)
    assert not res.success and not res.controllable.any()


def test_controllable_scenario_does_not_warn():
    import warnings

    sc = Scenario(sim=TINY, dispersions=DispersionSpec(misalignment_deg=0.5, thrust_rel=0.05))
    with warnings.catch_warnings():
        warnings.simplefilter("error", UncontrollableWarning)
        res = simulate(sc, 4, rng=1)
    assert res.success and res.controllable.all()


def _layout_dirs(th: ThrusterSpec, n: int, mis_deg: float, seed: int) -> np.ndarray:
    from scipy.spatial.transform import Rotation

    rv = np.random.default_rng(seed).normal(0.0, math.radians(mis_deg), (n * th.n, 3))
    R = Rotation.from_rotvec(rv).as_matrix().reshape(n, th.n, 3, 3)
    return np.einsum("sjab,jb->sja", R, np.asarray(th.directions))


@pytest.mark.parametrize("failed", [(), (2,)])
def test_batched_controllability_equals_the_lp_sample_by_sample(failed):
    # two implementations: the zonotope in-radius (support function over the generator-pair
    # normals) vs check_controllability (positive-span LP, Davis 1954) on every sample; 25 deg
    # misalignment makes both answers occur, a zero thrust level drops a column
    th = ThrusterSpec.from_torque_matrix(S3_REFERENCE_A, failed=failed)
    n = 120
    dirs = _layout_dirs(th, n, 25.0, seed=7)
    flev = np.full((n, th.n), 10.0)
    flev[::17, 4] = 0.0
    feas = _controllability(Scenario(thrusters=th), dirs, flev)
    pos = np.asarray(th.positions) - np.asarray(th.com)
    work = np.setdiff1d(np.arange(th.n), failed)
    ref = np.array([check_controllability(np.cross(pos, dirs[i]).T[:, [j for j in work if flev[i, j] > 0]]).success
                    for i in range(n)])
    np.testing.assert_array_equal(feas["span"], ref)
    assert 0 < ref.sum() < n  # dispersions change the answer in both directions of the test
    # controllable: positive span and >= min_authority_fraction (0.05) of the intact layout's authority
    np.testing.assert_array_equal(feas["controllable"], ref & (feas["authority"] >= 0.05 * feas["intact"]))
    assert feas["intact"] == pytest.approx(10.0, rel=1e-12)  # S3 reference at 10 N: 10 N m (closed form below)
    assert feas["nominal"].success == (failed == ())
    assert not feas["first_bad"].success
    assert np.all(feas["authority"][~ref] < 1e-12) and np.all(feas["authority"][ref] > 1e-6)  # N m


def test_issue41_sliver_of_authority_is_not_controllable():
    # issue 41 item 6: 20 dispersed samples (0.5 deg misalignment, 5 % thrust) of S3's reference
    # layout without thruster 2 (S3 §6); the positive-span test alone called most of them
    # controllable with at most 1-2 % of the intact layout's 10 N m, and none settles
    from adcskit._validation import as_rng
    from adcskit.simulation.core import _controllability_message, _prepare

    disp = DispersionSpec(misalignment_deg=0.5, thrust_rel=0.05)
    th = ThrusterSpec.from_torque_matrix(S3_REFERENCE_A, failed=(2,))
    for seed in range(3):
        sc = Scenario(thrusters=th, sim=TINY, dispersions=disp)
        feas = _prepare(sc, 20, as_rng(seed))[0]["feasibility"]
        assert feas["span"].sum() >= 9 and not feas["controllable"].any()
        assert np.max(feas["authority"]) < 0.03 * feas["intact"]
        msg = _controllability_message(sc, feas)
        assert "only through their misalignment" in msg and "below min_authority_fraction = 0.05" in msg
        # the fraction is the scenario's: 0 gives back the positive-span answer
        sc0 = sc.replace(thrusters=th.replace(min_authority_fraction=0.0))
        feas0 = _prepare(sc0, 20, as_rng(seed))[0]["feasibility"]
        np.testing.assert_array_equal(feas0["controllable"], feas["span"])
    # an intact layout dispersed alike keeps far more than 5 % (>= 83 % over 1000 samples)
    feas = _prepare(Scenario(sim=TINY, dispersions=disp), 1000, as_rng(0))[0]["feasibility"]
    assert feas["controllable"].all() and np.min(feas["authority"]) > 0.8 * feas["intact"]


def test_issue41_sliver_samples_do_not_settle():
    # the issue's reproduction flown: a 30 deg step about z (S3 reference layout without
    # thruster 2, 0.5 deg misalignment, 5 % thrust); 14 of 20 samples span R^3 (rng 2), none
    # settles within 100 s (the allocator never uses the sliver), and none reads controllable
    sc = Scenario(thrusters=ThrusterSpec.from_torque_matrix(S3_REFERENCE_A, failed=(2,)),
                  guidance=GuidanceSpec(kind="step", target_rotvec_deg=(0, 0, 30), t_step=5),
                  dispersions=DispersionSpec(misalignment_deg=0.5, thrust_rel=0.05))
    with pytest.warns(UncontrollableWarning, match="below min_authority_fraction"):
        res = simulate(sc, 20, rng=2)
    span = res.parameters["torque_authority"] > 0
    assert span.sum() == 14 and not res.controllable.any()
    assert not np.isfinite(res.metrics["settling_time_s"]).any()
    assert np.min(res.metrics["pointing_rms_deg"]) > 10.0  # far from the 30 deg target, deg


def test_weak_but_spanning_samples_are_reported():
    # a nominally controllable layout whose samples keep < 5 % authority: thruster 4's thrust
    # set to ~0 in a few samples of a layout that needs it (failed directions stay reachable
    # only through it)
    from adcskit.simulation.core import _controllability, _controllability_message

    th = ThrusterSpec.from_torque_matrix(S3_REFERENCE_A)
    n = 6
    dirs = np.broadcast_to(np.asarray(th.directions), (n, th.n, 3)).copy()
    flev = np.full((n, th.n), 10.0)
    flev[:3, 4] = 0.1  # 1 % of the thrust: 1 % of the authority in that direction
    sc = Scenario(thrusters=th)
    feas = _controllability(sc, dirs, flev)
    assert feas["span"].all() and feas["controllable"].tolist() == [False] * 3 + [True] * 3
    assert "3 of 6 samples have at most" in _controllability_message(sc, feas)


def test_layout_without_authority_even_intact():
    # torques +-x, +-y, +z (rotated off the body axes): the intact layout cannot push along -z,
    # its in-radius is 0 (3e-16 by rounding, read as 0), so the fraction asks nothing more; a
    # 10 deg misalignment tilts some samples into a positive span, the only test left
    from scipy.spatial.transform import Rotation

    from adcskit.simulation.core import _controllability, _controllability_message

    A = np.array([[1.0, -1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, -1.0, 0.0], [0.0, 0.0, 0.0, 0.0, 1.0]])
    th = ThrusterSpec.from_torque_matrix(Rotation.from_rotvec([0.4, 0.3, 0.0]).as_matrix() @ A)
    dirs = _layout_dirs(th, 40, 10.0, seed=1)
    sc = Scenario(thrusters=th)
    feas = _controllability(sc, dirs, np.full((40, th.n), 10.0))
    assert feas["intact"] == 0.0 and not feas["nominal"].success and 0 < feas["span"].sum() < 40
    np.testing.assert_array_equal(feas["controllable"], feas["span"])
    msg = _controllability_message(sc, feas)
    assert "span every direction only through their misalignment" in msg and "% of the intact" not in msg


def test_min_authority_fraction_validated():
    th = ThrusterSpec.from_torque_matrix(S3_REFERENCE_A)
    for bad in (-0.1, 1.0, float("nan")):
        with pytest.raises(InputError, match="min_authority_fraction"):
            th.replace(min_authority_fraction=bad)


def test_torque_authority_closed_form():
    # six thrusters giving +-x, +-y, +-z torques of 1 m x F: the attainable set is the box
    # [-F, F]^3, whose in-radius is F; one failed thruster leaves 0 along that direction
    from adcskit.simulation.core import _torque_authority

    A = np.hstack([np.eye(3), -np.eye(3)])[None] * 10.0
    assert _torque_authority(A)[0] == pytest.approx(10.0, rel=1e-12)
    assert _torque_authority(A[:, :, :5])[0] == pytest.approx(0.0, abs=1e-12)
    # S3's reference layout (S3 §6) at 10 N: an in-radius between 0 and the largest column
    r = _torque_authority((S3_REFERENCE_A * 10.0)[None])[0]
    assert 0.0 < r <= 10.0 * np.sqrt(2.0)


def test_misaligned_samples_flagged_individually():
    th = ThrusterSpec.from_torque_matrix(S3_REFERENCE_A)
    sc = Scenario(thrusters=th, sim=TINY, dispersions=DispersionSpec(misalignment_deg=25.0))
    with pytest.warns(UncontrollableWarning, match=r"\d+ of 8 samples cannot produce torque"):
        res = simulate(sc, 8, rng=3)
    assert 0 < res.controllable.sum() < 8 and not res.success


def test_nominally_uncontrollable_layout_fails_even_where_misalignment_spans():
    # S3 reference without thruster 2, 0.5 deg misalignment (the closed-loop study's Q1): some
    # samples' tilted torques positively span R^3 with a sliver of authority; the layout still
    # fails and the message quotes that sliver (N m) against 10 N thrusters
    sc = Scenario(thrusters=ThrusterSpec.from_torque_matrix(S3_REFERENCE_A, failed=(2,)), sim=TINY,
                  dispersions=DispersionSpec(misalignment_deg=0.5))
    with pytest.warns(UncontrollableWarning, match="only through their misalignment"):
        res = simulate(sc, 16, rng=0)
    # 9 of 16 span R^3, with at most 1.7 % of the intact 10 N m: none controllable (issue 41)
    assert 0 < np.count_nonzero(res.parameters["torque_authority"] > 0) < 16
    assert not res.controllable.any() and not res.success
    # a 3-sigma 0.5 deg tilt of a 14 N m column (sqrt(2) m x 10 N) gives ~0.4 N m; intact: ~9.9 N m
    assert np.max(res.parameters["torque_authority"]) < 0.5


# ----------------------------------------------------------------- inertia and q0


def test_inertia_triangle_inequality():
    # a rigid body has I_a <= I_b + I_c (Markley & Crassidis 2014 §3.3.5); issue 23's (1, 1, 100)
    with pytest.raises(InputError, match="triangle inequality"):
        SpacecraftSpec(inertia=(1.0, 1.0, 100.0))
    with pytest.raises(InputError, match="triangle inequality"):  # also a full matrix (rotated)
        c, s = math.cos(0.3), math.sin(0.3)
        R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
        SpacecraftSpec(inertia=tuple((R @ np.diag([1.0, 1.0, 100.0]) @ R.T).ravel()))
    assert SpacecraftSpec(inertia=(1.0, 1.0, 2.0)).inertia == (1.0, 1.0, 2.0)  # flat plate: equality
    assert SpacecraftSpec(inertia=(1.0, 1.0, 2.0 + 1e-12)).inertia[2] == 2.0 + 1e-12  # rounding


def test_dispersed_inertia_breaking_triangle_is_flagged_not_dropped():
    # near-flat body (10, 10, 19.9) with 30 % moment dispersion: some samples break the
    # triangle inequality; they are simulated as drawn and flagged
    sc = Scenario(spacecraft=SpacecraftSpec(inertia=(10.0, 10.0, 19.9)), sim=TINY,
                  dispersions=DispersionSpec(inertia_rel=0.3))
    res = simulate(sc, 8, rng=0)
    ev = np.linalg.eigvalsh(res.parameters["inertia"])
    phys = ev[:, 2] <= ev[:, 0] + ev[:, 1]
    np.testing.assert_array_equal(res.parameters["inertia_physical"], phys)
    assert 0 < phys.sum() < 8
    assert f"{int((~phys).sum())} sample(s) with dispersed principal moments" in res.message
    assert res.success  # physics flagged, not a failed run


def test_propagate_attitude_rejects_non_unit_q0():
    J = [10.0, 12.0, 8.0]
    with pytest.raises(InputError, match=r"q0 must be a unit quaternion.*\|q0\| = 2"):
        propagate_attitude([0.0, 0.0, 0.0, 2.0], [0.0, 0.0, 0.1], J, [0.0, 1.0])
    q = np.array([0.1, -0.2, 0.3, 0.9])
    q /= np.linalg.norm(q)
    assert propagate_attitude(q * (1 + 5e-10), [0.0, 0.0, 0.1], J, [0.0, 1.0]).success  # within rounding


# ----------------------------------------------------------------- units and dispersion meaning


def test_metric_names_carry_units_and_angles_are_degrees():
    assert all(n.endswith(("_deg", "_s", "_kg", "_deg_s")) or n in ("firings", "nees_mean", "nees_count",
                                                                      "box_active_fraction") for n in METRIC_NAMES)
    # hold with a 2 deg initial error about z, truth knowledge, no control torque (open loop,
    # zero on-times): the pointing error stays 2 deg (torque-free body at rest, GEO gravity
    # gradient ~1e-10 rad/s^2 moves it by < 1e-7 deg in 1 s)
    sc = Scenario(sim=TINY, initial_rotvec_deg=(0.0, 0.0, 2.0), estimator=EstimatorSpec(kind="truth"),
                  controller=ControllerSpec(kind="open-loop", on_times=((0.0,) * 6,)))
    res = simulate(sc, 1, rng=0)
    assert res.metrics["pointing_rms_deg"][0] == pytest.approx(2.0, abs=1e-6)
    assert res.metrics["final_error_deg"][0] == pytest.approx(2.0, abs=1e-6)
    assert res.metrics["pointing_rms_z_deg"][0] == pytest.approx(2.0, abs=1e-6)


def test_inertia_rel_scales_principal_moments_about_principal_axes():
    # non-diagonal nominal: every sample keeps the nominal's principal axes, its moments are
    # the nominal's scaled by factors in [0.1, 1.9] (DispersionSpec); the previous element-wise
    # scaling J_ab sqrt(s_a s_b) rotated the principal axes
    J0 = np.array([[100.0, 2.0, -1.0], [2.0, 80.0, 0.5], [-1.0, 0.5, 40.0]])
    sc = Scenario(spacecraft=SpacecraftSpec(inertia=tuple(J0.ravel())), sim=TINY,
                  dispersions=DispersionSpec(inertia_rel=0.1))
    res = simulate(sc, 6, rng=2)
    lam0, V = np.linalg.eigh(J0)
    D = np.einsum("ba,sbc,cd->sad", V, res.parameters["inertia"], V)
    off = D - np.einsum("sii->si", D)[:, :, None] * np.eye(3)
    assert np.max(np.abs(off)) < 1e-12 * lam0.max()
    s = np.einsum("sii->si", D) / lam0
    assert np.all((s >= 0.1) & (s <= 1.9)) and np.std(s) > 0.01
    # diagonal nominal: s_a scales the moment about body axis a, exactly
    sd = simulate(sc.replace(spacecraft=SpacecraftSpec(inertia=(100.0, 80.0, 40.0))), 6, rng=2)
    Jd = sd.parameters["inertia"]
    np.testing.assert_array_equal(Jd, np.einsum("si,ij->sij", np.einsum("sii->si", Jd), np.eye(3)))


def test_propellant_uses_dispersed_thrust():
    # oracle: one 0.2 s pulse of thruster 0 (open loop); after the lags (tau = 0.01 s) settle,
    # the delivered on-time is the commanded 0.2 s, so propellant = 0.2 s x mdot x F_i / F_max
    # (mass flow proportional to thrust at constant specific impulse), sample by sample
    on = ((0.2, 0.0, 0.0, 0.0, 0.0, 0.0),)
    sc = Scenario(sim=TINY, estimator=EstimatorSpec(kind="truth"), dispersions=DispersionSpec(thrust_rel=0.2),
                  controller=ControllerSpec(kind="open-loop", on_times=on))
    res = simulate(sc, 6, rng=4)
    th = sc.thrusters
    expect = 0.2 * th.mdot * res.parameters["thrust"][:, 0] / th.f_max
    np.testing.assert_allclose(res.metrics["propellant_kg"], expect, rtol=1e-9)
    assert np.std(res.parameters["thrust"][:, 0]) > 0.5  # the dispersion is there (N)


# ----------------------------------------------------------------- compile notice


def _fresh_module(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


def test_will_compile_reads_numba_disk_cache(tmp_path):
    src = tmp_path / "jit_probe_mod.py"
    src.write_text("import numba\n\n@numba.njit(cache=True)\ndef f(x):\n    return x + 1\n")
    a = _fresh_module(src, "jit_probe_a")
    assert will_compile(a.f) is True  # no cache yet
    assert a.f(1) == 2
    assert will_compile(a.f) is False  # compiled in this process
    b = _fresh_module(src, "jit_probe_b")  # a new dispatcher on the same file: disk cache
    assert will_compile(b.f) is False
    src.write_text("import numba\n\n@numba.njit(cache=True)\ndef f(x):\n    return x + 2\n")
    c = _fresh_module(src, "jit_probe_c")  # edited source: the cache is stale
    assert will_compile(c.f) is True


@pytest.mark.parametrize("cold", [True, False])
def test_simulate_prints_compile_notice_only_when_cold(monkeypatch, capsys, cold):
    from adcskit._progress import progress_session
    from adcskit.simulation import core

    monkeypatch.setattr(core, "will_compile", lambda d: cold)
    with progress_session(True):
        simulate(Scenario(sim=TINY), 1, rng=0)
    assert (CLOSED_LOOP_NOTICE in capsys.readouterr().out) is cold


@pytest.mark.parametrize("flag, terminal", [(None, False), (False, False), (None, True), (False, True), (True, False)])
def test_simulate_progress_keyword(monkeypatch, capsys, flag, terminal):
    # issue 41 item 3: a plain call shows the compile notice and a bar over the chunks at a
    # terminal (None) or when asked (True), never with False; the bar appears after
    # AUTO_DELAY_S (0 here: the test's runs are short). The display's console is recorded.
    import io

    from rich.console import Console
    from rich.progress import Progress

    import adcskit._progress as progress
    from adcskit.errors import InputTypeError
    from adcskit.simulation import core

    consoles, bars = [], []

    class Recorded(Progress):
        def add_task(self, description, *args, **kw):
            bars.append(description)
            return super().add_task(description, *args, **kw)

    def recorded():
        console = Console(file=io.StringIO(), force_terminal=terminal, record=True, width=120)
        consoles.append(console)
        return Recorded(*Progress.get_default_columns(), console=console)

    monkeypatch.setattr(progress, "_new_progress", recorded)
    monkeypatch.setattr(progress, "AUTO_DELAY_S", 0.0)
    monkeypatch.setattr(core, "will_compile", lambda d: True)
    res = simulate(Scenario(sim=TINY), 2, rng=0, progress=flag)
    shown = flag is True or (flag is None and terminal)
    text = consoles[0].export_text() if consoles else ""
    assert (CLOSED_LOOP_NOTICE in text) is shown
    assert bars == (["closed-loop samples"] if shown else [])
    assert res.success and progress._SESSION is None and capsys.readouterr().out == ""
    with pytest.raises(InputTypeError, match="progress must be True, False or None"):
        simulate(Scenario(sim=TINY), 1, progress="yes")
