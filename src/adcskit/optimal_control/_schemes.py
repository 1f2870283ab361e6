"""Collocation schemes: what distinguishes the Gauss (LG) and the Radau (LGR) transcriptions.

One object per scheme, found by name in :data:`SCHEMES` (as scipy's ``solve_ivp`` finds its
``OdeSolver`` classes in ``METHODS``, and dymos' ``GaussLobatto`` / ``Radau`` share
``PseudospectralBase``). A scheme says, per sub-interval with ``n`` collocation points:

* its nodes: differentiation matrix ``D`` ``(n, n+1)``, collocation points ``τ``, quadrature
  weights ``w`` and the ``n+1`` state support points;
* which support states are the collocated ones, and whether the end state ``X_f`` is a
  decision variable of its own with a quadrature row (Gauss, S2 eq. 30) or the last support
  state (Radau);
* the costate map from the NLP multipliers (S2 eq. 35-37 for Gauss; Garg et al. 2010 for
  Radau) and its inverse (multipliers implied by a costate, for warm starts).

The transcriptions (single- and multi-phase) and the solution assembly never test the scheme's
name; they ask the scheme.

References
----------
S2, eq. 17-37. Benson et al., J. Guid. Control Dyn. 29(6), 2006. Garg et al., Automatica
46(11), 2010.
"""

from __future__ import annotations

import numpy as np

from adcskit.optimal_control.nodes import gauss_differentiation_matrix, radau_differentiation_matrix

__all__ = ["SCHEMES", "Scheme"]


class Scheme:
    """Base of a collocation scheme (see module docstring)."""

    name: str = ""
    description: str = ""
    #: ``True``: the end state ``X_f`` is a decision variable tied by a quadrature row.
    end_state_variable: bool = False
    #: Slice of the ``n+1`` support states that are collocated.
    collocated: slice = slice(None)

    #: Slice of the support states that are the solution's samples (the rest: the next
    #: interval's start).
    sampled: slice = slice(None)

    def nodes(self, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(D, tau, w, support)`` of one sub-interval with ``n`` collocation points."""
        raise NotImplementedError

    def costates(self, lt: np.ndarray, lf: np.ndarray | None, iv):
        """``(lam_c, lam_s, lam_end)`` from the defect multipliers ``lt`` ``(n, nx)`` and (Gauss)
        the quadrature multiplier ``lf`` of interval ``iv``, all in physical units: costates at
        the collocation points, at the support points, and at the interval's end."""
        raise NotImplementedError

    def costate_times(self, ts: np.ndarray, t_end: float) -> np.ndarray:
        """Times of an interval's costate samples ``vstack([lam_s, lam_end])``."""
        raise NotImplementedError

    def defect_multipliers(self, lc: np.ndarray, le: np.ndarray, w: np.ndarray) -> np.ndarray:
        """``Λ̃`` of the defect rows implied by costates ``lc`` at the collocation points and
        ``le`` at the interval's end (the costate map inverted)."""
        raise NotImplementedError


class _Gauss(Scheme):
    name = "gauss"
    description = "multi-interval Legendre-Gauss collocation (S2 eq. 17-34)"
    end_state_variable = True
    collocated = slice(1, None)

    def nodes(self, n):
        D, tau, w = gauss_differentiation_matrix(n)
        return D, tau, w, np.concatenate(([-1.0], tau))

    def costates(self, lt, lf, iv):
        lam_c = lt / iv.w[:, None] + lf  # S2 eq. 36
        lam_s = np.vstack([lf - iv.D[:, 0] @ lt, lam_c])  # eq. 37 at τ₀ = −1
        return lam_c, lam_s, lf  # eq. 35

    def costate_times(self, ts, t_end):
        return np.append(ts, t_end)

    def defect_multipliers(self, lc, le, w):
        return w[:, None] * (lc - le)


class _Radau(Scheme):
    name = "radau"
    description = "multi-interval Legendre-Gauss-Radau collocation"
    end_state_variable = False
    collocated = slice(None, -1)
    sampled = slice(None, -1)

    def nodes(self, n):
        D, tau, w = radau_differentiation_matrix(n)
        return D, tau, w, np.concatenate((tau, [1.0]))

    def costates(self, lt, lf, iv):
        lam_c = lt / iv.w[:, None]
        return lam_c, lam_c, iv.D[:, -1] @ lt

    def costate_times(self, ts, t_end):
        return ts  # the support point τ = +1 is the end

    def defect_multipliers(self, lc, le, w):
        return w[:, None] * lc


#: The collocation schemes by name.
SCHEMES: dict[str, Scheme] = {s.name: s for s in (_Gauss(), _Radau())}
