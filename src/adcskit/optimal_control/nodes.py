"""Orthogonal-collocation node sets, quadrature weights and differentiation matrices.

Legendre–Gauss (LG) and Legendre–Gauss–Radau (LGR) points on ``τ ∈ [-1, 1]`` and the
Lagrange differentiation matrices of the Gauss pseudospectral method (S2 eq. 22–28) and of
the Radau method. Nodes and weights come from :func:`scipy.special.roots_legendre` and
:mod:`numpy.polynomial.legendre`; the differentiation matrices are written here because no
kept library exposes the *rectangular* ``N × (N+1)`` matrices the two transcriptions need
(support points ≠ collocation points). They use the barycentric form (Berrut & Trefethen
2004), which is algebraically eq. 28 of S2 but does not lose accuracy for many nodes.

References
----------
S2: time-optimal 6-DOF rendezvous by the Gauss pseudospectral method, eq. 17, 22–30.
Benson, Huntington, Thorvaldsen & Rao, J. Guid. Control Dyn. 29(6), 2006 (Gauss method).
Garg et al., Automatica 46(11), 2010 (Radau method).
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial import legendre as _leg
from scipy.special import roots_legendre

from adcskit._validation import as_array, check_int, short_repr
from adcskit.errors import InputError

__all__ = [
    "legendre_gauss",
    "legendre_gauss_radau",
    "barycentric_weights",
    "lagrange_matrix",
    "lagrange_derivative_matrix",
    "gauss_differentiation_matrix",
    "radau_differentiation_matrix",
]


def legendre_gauss(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Legendre–Gauss points and weights on ``(-1, 1)``.

    Parameters
    ----------
    n : int
        Number of points, >= 1.

    Returns
    -------
    tau : (n,) ndarray
        Roots of the Legendre polynomial ``P_n``, ascending.
    w : (n,) ndarray
        Gauss quadrature weights (sum 2); exact for polynomials of degree ``2n - 1``.

    References
    ----------
    S2, eq. 30–31 (Gauss quadrature of the end state and of the cost).

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.optimal_control import legendre_gauss
    >>> tau, w = legendre_gauss(2)
    >>> tau.round(6), w.round(6)                          # +-1/sqrt(3), weights 1
    (array([-0.57735,  0.57735]), array([1., 1.]))
    >>> tau, w = legendre_gauss(5)
    >>> round(float(w @ tau**8), 12), round(2.0 / 9.0, 12)   # exact up to degree 2n - 1 = 9
    (0.222222222222, 0.222222222222)
    """
    n = check_int("n", n, minimum=1, maximum=1000)
    tau, w = roots_legendre(n)
    return np.asarray(tau, float), np.asarray(w, float)


def legendre_gauss_radau(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Legendre–Gauss–Radau points (including ``τ = -1``) and weights.

    Parameters
    ----------
    n : int
        Number of points, >= 1.

    Returns
    -------
    tau : (n,) ndarray
        ``-1`` and the roots of ``P_{n-1} + P_n``, ascending.
    w : (n,) ndarray
        Radau weights: ``2/n²`` at ``-1`` and ``(1-τ)/(n² P_{n-1}(τ)²)`` elsewhere; exact
        for polynomials of degree ``2n - 2``.

    References
    ----------
    Garg et al., Automatica 46(11), 2010, eq. 5–6.

    Examples
    --------
    >>> from adcskit.optimal_control import legendre_gauss_radau
    >>> tau, w = legendre_gauss_radau(3)
    >>> tau.round(6), w.round(6), round(float(w.sum()), 12)
    (array([-1.      , -0.289898,  0.689898]), array([0.222222, 1.024972, 0.752806]), 2.0)
    """
    n = check_int("n", n, minimum=1, maximum=1000)
    if n == 1:
        return np.array([-1.0]), np.array([2.0])
    c = np.zeros(n + 1)
    c[n - 1] = 1.0
    c[n] = 1.0
    tau = np.sort(np.real(_leg.legroots(c)))
    tau[0] = -1.0
    pn1 = _leg.legval(tau, np.eye(n)[n - 1])
    w = (1.0 - tau) / (n**2 * pn1**2)
    w[0] = 2.0 / n**2
    return tau, w


def barycentric_weights(support: np.ndarray) -> np.ndarray:
    """Barycentric weights ``1 / Π_{j≠i} (τ_i − τ_j)`` of distinct support points."""
    s = as_array("support", support, ndim=1)
    diff = s[:, None] - s[None, :]
    np.fill_diagonal(diff, 1.0)
    if np.any(diff == 0.0):
        raise InputError(f"support points must be distinct; got {short_repr(s)}")
    with np.errstate(over="ignore", divide="ignore", under="ignore"):
        w = 1.0 / np.prod(diff, axis=1)
    if not np.all(np.isfinite(w)) or np.any(w == 0.0):
        raise InputError(f"support points are too close together or too spread for float64 "
                         f"(barycentric weights overflow); got {short_repr(s)}")
    return w


def _finite_matrix(out: np.ndarray) -> np.ndarray:
    if not np.all(np.isfinite(out)):
        raise InputError("points must not lie within rounding distance of a support point (other than "
                         "exactly on it): the interpolation matrix overflows")
    return out


def lagrange_matrix(support, points) -> np.ndarray:
    """Matrix ``L`` with ``L[k, i] = L_i(points[k])`` (S2 eq. 23), so ``p(points) = L @ p(support)``.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.optimal_control import lagrange_matrix
    >>> support = np.array([-1.0, 0.0, 1.0])
    >>> L = lagrange_matrix(support, [0.5])
    >>> L.round(6), (L @ support**2).round(12)             # quadratics are interpolated exactly
    (array([[-0.125,  0.75 ,  0.375]]), array([0.25]))
    """
    s = as_array("support", support, ndim=1)
    p = as_array("points", points, ndim=1)
    return _lagrange_rows(s, barycentric_weights(s), p)


def _lagrange_rows(s: np.ndarray, bw: np.ndarray, p: np.ndarray) -> np.ndarray:
    """:func:`lagrange_matrix` from validated float arrays and the support's barycentric
    weights ``bw`` (:func:`barycentric_weights`), for callers that keep ``bw`` for many calls."""
    diff = p[:, None] - s[None, :]
    out = np.empty((p.size, s.size))
    exact = diff == 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        terms = bw[None, :] / diff
        out[:] = terms / terms.sum(axis=1, keepdims=True)
    rows = exact.any(axis=1)
    out[rows] = exact[rows].astype(float)
    return _finite_matrix(out)


def lagrange_derivative_matrix(support, points) -> np.ndarray:
    """Matrix ``D`` with ``D[k, i] = dL_i/dτ (points[k])`` (S2 eq. 27–28).

    ``D @ p(support)`` is the derivative at ``points`` of the interpolating polynomial of
    degree ``len(support) − 1``; it is exact for polynomials of that degree.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.optimal_control import lagrange_derivative_matrix
    >>> support = np.array([-1.0, 0.0, 1.0])
    >>> D = lagrange_derivative_matrix(support, [0.5])
    >>> (D @ support**2).round(12)                         # d(tau^2)/dtau at 0.5
    array([1.])
    """
    s = as_array("support", support, ndim=1)
    p = as_array("points", points, ndim=1)
    bw = barycentric_weights(s)
    m = s.size
    out = np.zeros((p.size, m))
    for k, x in enumerate(p):
        hit = np.flatnonzero(s == x)
        if hit.size:  # x is support point j: D_ji = (bw_i/bw_j)/(x_j - x_i), D_jj = -Σ
            j = hit[0]
            d = s[j] - s
            d[j] = 1.0
            row = (bw / bw[j]) / d
            row[j] = 0.0
            row[j] = -row.sum()
            out[k] = row
        else:  # L_i'(x) = L_i(x) Σ_{l≠i} 1/(x - s_l)
            d = x - s
            ell = np.prod(d)
            li = ell * bw / d
            inv = 1.0 / d
            out[k] = li * (inv.sum() - inv)
    return _finite_matrix(out)


def gauss_differentiation_matrix(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Gauss pseudospectral differentiation matrix ``D`` of shape ``(n, n+1)`` (S2 eq. 28).

    The state is interpolated on ``τ₀ = −1`` plus the ``n`` LG points (eq. 22–23) and its
    derivative is evaluated at the ``n`` LG points (eq. 27).

    Returns
    -------
    D : (n, n+1) ndarray
    tau : (n,) ndarray
        LG points.
    w : (n,) ndarray
        LG weights.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.optimal_control import gauss_differentiation_matrix
    >>> D, tau, w = gauss_differentiation_matrix(3)
    >>> D.shape, tau.shape, w.shape
    ((3, 4), (3,), (3,))
    >>> support = np.concatenate([[-1.0], tau])
    >>> np.allclose(D @ support**2, 2.0 * tau)            # exact derivative of tau^2
    True
    """
    tau, w = legendre_gauss(n)
    support = np.concatenate(([-1.0], tau))
    return lagrange_derivative_matrix(support, tau), tau, w


def radau_differentiation_matrix(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Radau (LGR) differentiation matrix of shape ``(n, n+1)``.

    The state is interpolated on the ``n`` LGR points plus ``τ = +1`` and its derivative is
    evaluated at the ``n`` LGR points (Garg et al. 2010, eq. 12).

    Returns
    -------
    D : (n, n+1) ndarray
    tau : (n,) ndarray
        LGR points (``tau[0] = -1``).
    w : (n,) ndarray
        LGR weights.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.optimal_control import radau_differentiation_matrix
    >>> D, tau, w = radau_differentiation_matrix(3)
    >>> D.shape, float(tau[0])
    ((3, 4), -1.0)
    >>> support = np.concatenate([tau, [1.0]])
    >>> np.allclose(D @ support**3, 3.0 * tau**2)         # exact derivative of tau^3
    True
    """
    tau, w = legendre_gauss_radau(n)
    support = np.concatenate((tau, [1.0]))
    return lagrange_derivative_matrix(support, tau), tau, w
