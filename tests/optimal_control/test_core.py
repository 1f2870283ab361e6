"""The transcription core (issue 20, item 3): scheme objects, one collocation core, one NLP cache."""

from __future__ import annotations

import numpy as np
import pytest

from adcskit.optimal_control import (
    METHODS,
    MultiPhaseProblem,
    Phase,
    _nlp,
    clear_cache,
    solve,
    solve_multiphase,
)
from adcskit.optimal_control._nlp import DEFAULT_IPOPT_OPTIONS, NLP_CACHE_SIZE, cached_nlp
from adcskit.optimal_control._schemes import SCHEMES
from adcskit.optimal_control.multiphase import _get
from adcskit.optimal_control.nodes import gauss_differentiation_matrix, radau_differentiation_matrix
from adcskit.optimal_control.problem import Mesh
from adcskit.optimal_control.problems.standard import bryson_denham
from adcskit.optimal_control.transcription import get_transcription


def test_schemes_are_the_registered_methods_with_their_nodes():
    assert set(SCHEMES) == set(METHODS)
    for name, fun in (("gauss", gauss_differentiation_matrix), ("radau", radau_differentiation_matrix)):
        D, tau, w, support = SCHEMES[name].nodes(4)
        D0, tau0, w0 = fun(4)
        assert np.array_equal(D, D0) and np.array_equal(tau, tau0) and np.array_equal(w, w0)
        assert support.size == 5
    # S2 eq. 22-30: Gauss adds τ₀ = −1 and an end-state variable; Radau ends at τ = +1
    assert SCHEMES["gauss"].end_state_variable and not SCHEMES["radau"].end_state_variable
    assert SCHEMES["gauss"].nodes(3)[3][0] == -1.0 and SCHEMES["radau"].nodes(3)[3][-1] == 1.0


@pytest.mark.parametrize("method", sorted(SCHEMES))
def test_costate_map_and_its_inverse_round_trip(method):
    # defect multipliers -> costates (S2 eq. 35-37; Garg et al. 2010) -> defect multipliers
    scheme = SCHEMES[method]
    rng = np.random.default_rng(0)
    D, tau, w, _ = scheme.nodes(5)

    class _Iv:
        pass

    iv = _Iv()
    iv.D, iv.w = D, w
    lt = rng.standard_normal((5, 3))
    lf = rng.standard_normal(3) if scheme.end_state_variable else None
    lam_c, lam_s, lam_end = scheme.costates(lt, lf, iv)
    back = scheme.defect_multipliers(lam_c, lam_end, w)
    np.testing.assert_allclose(back, lt, rtol=0, atol=1e-13)  # a division and a multiplication by w
    assert lam_s.shape[0] == 5 + (1 if scheme.end_state_variable else 0)


def _one_phase(prob):
    ph = Phase(dynamics=lambda x, u, t, p: prob.dynamics(x, u, t),
               lagrange=lambda x, u, t, p: prob.lagrange(x, u, t),
               n_states=prob.n_states, n_controls=prob.n_controls, state_upper=prob.state_upper,
               initial_state=prob.initial_state, final_state=prob.final_state,
               t0_bounds=(0.0, 0.0), tf_bounds=prob.tf_bounds, state_scale=prob.state_scale,
               control_scale=prob.control_scale)
    return MultiPhaseProblem(phases=[ph])


@pytest.mark.parametrize("method", sorted(SCHEMES))
def test_single_and_one_phase_transcriptions_share_the_collocation_rows(method):
    # both transcriptions build their defect, quadrature and interval-link rows with the same
    # core: on the same mesh and point (t0 = 0, unit time scale) the rows agree to round-off
    prob = bryson_denham()
    mesh = Mesh.uniform(3, 3)
    opts = dict(DEFAULT_IPOPT_OPTIONS)
    single = get_transcription(prob, method, mesh, opts)
    multi = _get(_one_phase(prob), method, (mesh,), opts)
    lay = multi.layouts[0]
    n_rows = lay.g_path.start
    assert single.g_path.start == n_rows and single.i_tf == lay.i_t0
    sx, su = prob.scales()
    z = np.random.default_rng(1).uniform(-1.0, 1.0, single.nz)
    z[single.i_tf] = 1.0
    zm = np.concatenate([z[: single.i_tf], [0.0, 1.0]])  # [..., t0, tf] with unit time scale
    g1 = np.asarray(single.solver.get_function("nlp_g")(z, np.concatenate([sx, su, [1.0, 0.0, 1.0]]))).ravel()
    g2 = np.asarray(multi.g_fun(zm, np.concatenate([sx, su, [1.0, 1.0]]))).ravel()
    np.testing.assert_allclose(g1[:n_rows], g2[:n_rows], rtol=0, atol=1e-14)


def test_one_nlp_cache_for_single_and_multi_phase():
    clear_cache()
    solve(bryson_denham(), method="radau", mesh=(2, 3))
    solve_multiphase(_one_phase(bryson_denham()), meshes=[(2, 3)])
    kinds = sorted(k[0] for k in _nlp._CACHE)
    assert kinds == ["multi-phase", "single-phase"]
    clear_cache()
    assert not _nlp._CACHE


def test_nlp_cache_keeps_the_most_recently_used():
    clear_cache()
    builds = []
    for i in range(NLP_CACHE_SIZE):
        cached_nlp(("test", i), lambda i=i: builds.append(i) or i)
    assert cached_nlp(("test", 0), lambda: builds.append(-1)) == 0  # hit: moved to the end
    cached_nlp(("test", "new"), lambda: "new")  # evicts the least recently used: key 1
    assert ("test", 1) not in _nlp._CACHE and ("test", 0) in _nlp._CACHE
    assert len(_nlp._CACHE) == NLP_CACHE_SIZE and builds == list(range(NLP_CACHE_SIZE))
    clear_cache()
