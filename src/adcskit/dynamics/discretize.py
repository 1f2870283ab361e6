"""Discretisation of linear time-invariant models ``ẋ = A x + B u``.

Methods (registry :data:`DISCRETIZATION_METHODS`):

* ``"zoh"`` — exact for a zero-order-hold input: ``[[Ad, Bd], [0, I]] = expm([[A, B], [0, 0]] h)``
  (Van Loan 1978), via ``scipy.linalg.expm``.
* ``"crank-nicolson"`` — trapezoidal rule (Tustin without pre-warping):
  ``Ad = (I − hA/2)⁻¹ (I + hA/2)``, ``Bd = (I − hA/2)⁻¹ h B`` (input held over the step).
  S1 (eq. 12) prints the scheme with ``λ = 0.5`` and ``Δt = 1`` and drops the ½ factors; the
  halves are required for second-order accuracy and for mapping the stable half-plane onto
  the unit disc (A-stability). Solved with ``scipy.linalg.solve``, never an explicit inverse.

References
----------
C. F. Van Loan, "Computing integrals involving the matrix exponential", IEEE TAC 23(3), 1978.
J. Crank and P. Nicolson, Proc. Camb. Phil. Soc. 43(1), 1947.
S1, eq. 12.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.linalg import expm, solve

from adcskit._validation import as_array, check_choice, check_positive
from adcskit.errors import InputError

__all__ = ["DISCRETIZATION_METHODS", "discretize"]


def _zoh(A: np.ndarray, B: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    n, m = B.shape
    M = np.zeros((n + m, n + m))
    M[:n, :n] = A
    M[:n, n:] = B
    E = expm(M * h)
    return E[:n, :n], E[:n, n:]


def _crank_nicolson(A: np.ndarray, B: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    n = A.shape[0]
    lhs = np.eye(n) - 0.5 * h * A
    return solve(lhs, np.eye(n) + 0.5 * h * A), solve(lhs, h * B)


DISCRETIZATION_METHODS = {"zoh": _zoh, "crank-nicolson": _crank_nicolson}


def discretize(A: Any, B: Any, dt: float, method: str = "zoh") -> tuple[np.ndarray, np.ndarray]:
    """Discrete ``(Ad, Bd)`` with ``x[k+1] = Ad x[k] + Bd u[k]``.

    Parameters
    ----------
    A : array_like (n, n)
    B : array_like (n, m)
    dt : float, s
        Sample time, > 0.
    method : {"zoh", "crank-nicolson"}

    Examples
    --------
    >>> import numpy as np
    >>> Ad, Bd = discretize([[0.0, 1.0], [0.0, 0.0]], [[0.0], [1.0]], 0.1)   # double integrator
    >>> Ad, Bd.round(6)
    (array([[1. , 0.1],
           [0. , 1. ]]), array([[0.005],
           [0.1  ]]))
    """
    method = check_choice("method", method, DISCRETIZATION_METHODS)
    Aa = as_array("A", A, ndim=2)
    if Aa.shape[0] != Aa.shape[1]:
        raise InputError(f"A must be square (n, n); got shape {Aa.shape}")
    Ba = as_array("B", B)
    if Ba.ndim == 1:
        Ba = Ba[:, None]
    if Ba.ndim != 2 or Ba.shape[0] != Aa.shape[0]:
        raise InputError(f"B must have shape ({Aa.shape[0]}, m) to match A; got shape {Ba.shape}")
    h = check_positive("dt", dt, unit="s")
    if method == "crank-nicolson":
        ev = np.linalg.eigvals(Aa)
        if np.any(np.isclose(ev * h / 2, 1.0, rtol=0, atol=1e-12)):
            raise InputError(f"dt = {h:g} s makes I − (dt/2) A singular (A has eigenvalue 2/dt); choose another dt")
    with np.errstate(over="ignore", invalid="ignore"):
        Ad, Bd = DISCRETIZATION_METHODS[method](Aa, Ba, h)
    if not (np.all(np.isfinite(Ad)) and np.all(np.isfinite(Bd))):
        raise InputError(f"A * dt is too large to discretise in float64 (exp(A dt) overflows); got "
                         f"max |A| = {np.abs(Aa).max():g}, dt = {h:g} s")
    return Ad, Bd
