"""Node sets, weights and differentiation matrices against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adcskit.optimal_control.nodes import (
    gauss_differentiation_matrix,
    lagrange_derivative_matrix,
    lagrange_matrix,
    legendre_gauss,
    legendre_gauss_radau,
    radau_differentiation_matrix,
)

TOL = 1e-13  # closed forms vs double-precision root finding: a few ulp of O(1) numbers


@pytest.mark.parametrize(
    ("n", "tau", "w"),
    [
        # Abramowitz & Stegun Table 25.4 (Gauss-Legendre abscissae/weights)
        (1, [0.0], [2.0]),
        (2, [-1 / math.sqrt(3), 1 / math.sqrt(3)], [1.0, 1.0]),
        (3, [-math.sqrt(3 / 5), 0.0, math.sqrt(3 / 5)], [5 / 9, 8 / 9, 5 / 9]),
    ],
)
def test_legendre_gauss_closed_form(n, tau, w):
    t, ww = legendre_gauss(n)
    np.testing.assert_allclose(t, tau, atol=TOL)
    np.testing.assert_allclose(ww, w, atol=TOL)


@pytest.mark.parametrize(
    ("n", "tau", "w"),
    [
        # Radau closed forms: roots of P_{n-1} + P_n (Abramowitz & Stegun 25.4.31)
        (2, [-1.0, 1 / 3], [0.5, 1.5]),
        (
            3,
            [-1.0, (1 - math.sqrt(6)) / 5, (1 + math.sqrt(6)) / 5],
            [2 / 9, (16 + math.sqrt(6)) / 18, (16 - math.sqrt(6)) / 18],
        ),
    ],
)
def test_legendre_gauss_radau_closed_form(n, tau, w):
    t, ww = legendre_gauss_radau(n)
    np.testing.assert_allclose(t, tau, atol=TOL)
    np.testing.assert_allclose(ww, w, atol=TOL)


@pytest.mark.parametrize("n", [1, 2, 5, 12])
def test_quadrature_exactness(n):
    # Gauss exact to degree 2n-1, Radau to 2n-2: ∫_{-1}^{1} τ^k dτ = (1 - (-1)^{k+1}) / (k+1)
    t, w = legendre_gauss(n)
    for k in range(2 * n):
        assert w @ t**k == pytest.approx((1 - (-1) ** (k + 1)) / (k + 1), abs=1e-12)
    t, w = legendre_gauss_radau(n)
    for k in range(2 * n - 1):
        assert w @ t**k == pytest.approx((1 - (-1) ** (k + 1)) / (k + 1), abs=1e-12)


def _eq28(support, points):
    """S2 eq. 28 evaluated literally (sum over l of products)."""
    m = len(support)
    D = np.zeros((len(points), m))
    for k, tk in enumerate(points):
        for i in range(m):
            den = np.prod([support[i] - support[j] for j in range(m) if j != i])
            num = 0.0
            for l in range(m):
                if l == i:
                    continue
                num += np.prod([tk - support[j] for j in range(m) if j not in (i, l)])
            D[k, i] = num / den
    return D


@pytest.mark.parametrize("n", [1, 3, 6])
def test_gauss_D_equals_eq28(n):
    D, tau, _ = gauss_differentiation_matrix(n)
    assert D.shape == (n, n + 1)
    np.testing.assert_allclose(D, _eq28(np.r_[-1.0, tau], tau), atol=1e-11)


def test_gauss_D_closed_form_n1():
    # N = 1: support {-1, 0}, line through them has slope X1 - X0 -> D = [[-1, 1]]
    D, _, _ = gauss_differentiation_matrix(1)
    np.testing.assert_allclose(D, [[-1.0, 1.0]], atol=TOL)


def test_radau_D_closed_form_n1():
    # N = 1: support {-1, +1}, slope (X1 - X0)/2 -> D = [[-1/2, 1/2]]
    D, tau, _ = radau_differentiation_matrix(1)
    np.testing.assert_allclose(D, [[-0.5, 0.5]], atol=TOL)
    np.testing.assert_allclose(tau, [-1.0])


@settings(max_examples=25, deadline=None)
@given(n=st.integers(1, 10), coef=st.lists(st.floats(-3, 3), min_size=11, max_size=11))
def test_D_differentiates_polynomials_exactly(n, coef):
    # D is exact for polynomials of degree <= n (n+1 support points)
    c = np.array(coef[: n + 1])
    p = np.polynomial.Polynomial(c)
    for builder, support_of in (
        (gauss_differentiation_matrix, lambda t: np.r_[-1.0, t]),
        (radau_differentiation_matrix, lambda t: np.r_[t, 1.0]),
    ):
        D, tau, _ = builder(n)
        scale = 1 + np.abs(c).sum() * n
        np.testing.assert_allclose(D @ p(support_of(tau)), p.deriv()(tau), atol=1e-11 * scale)


def test_lagrange_matrix_interpolates_and_is_cardinal():
    s = np.array([-1.0, -0.3, 0.4, 1.0])
    np.testing.assert_allclose(lagrange_matrix(s, s), np.eye(4), atol=TOL)  # eq. 26
    x = np.linspace(-1, 1, 7)
    p = np.polynomial.Polynomial([0.3, -1.0, 2.0, 0.5])
    np.testing.assert_allclose(lagrange_matrix(s, x) @ p(s), p(x), atol=1e-13)
    np.testing.assert_allclose(lagrange_derivative_matrix(s, x) @ p(s), p.deriv()(x), atol=1e-12)


def test_bad_inputs():
    with pytest.raises(ValueError, match="n must be an integer"):
        legendre_gauss(0)
    with pytest.raises(ValueError, match="distinct"):
        lagrange_matrix([0.0, 0.0], [0.5])
