"""Compiled solver of ``max qᵀ K q`` on the unit sphere inside a box (min-max stage 2), and
the whole compiled min-max interval determination of one epoch (:func:`minmax_one`).

Private helper of :mod:`adcskit.determination.robust` and of the closed-loop kernel
(:mod:`adcskit.simulation._kernels`). By the KKT conditions an optimum has
a set C of components at a bound and the free rest F satisfying ``(μ I − K_FF) q_F = K_FC q_C``
with ``|q_F|² = 1 − |q_C|²``. For every one of the 3⁴ = 81 active-set patterns we solve this
trust-region-type secular equation for its global root ``μ > λ_max(K_FF)`` (Moré & Sorensen
1983; including the "hard case"), keep the candidates inside the box and return the best.
Hand-written because no library solves a 4-variable sphere-and-box quadratic in microseconds
(scipy's SLSQP takes ~2 ms per call with its Python overhead); agreement with SLSQP is
tested.
"""

from __future__ import annotations

import numpy as np
from numba import int64, njit

from adcskit.determination._kernels import NOT_CONVERGED, OK, QMETHOD, TRIAD, solve_one


@njit(cache=True, error_model="numpy")
def _consider(K, q, lb, ub, best, qbest):
    tol = 1e-12
    for i in range(4):
        if q[i] < lb[i] - tol or q[i] > ub[i] + tol:
            return best
    v = 0.0
    for i in range(4):
        for j in range(4):
            v += q[i] * K[i, j] * q[j]
    if v > best:
        for i in range(4):
            qbest[i] = q[i]
        return v
    return best


@njit(cache=True, error_model="numpy")
def box_sphere_max(K, lb, ub, qbest):
    """Maximise qᵀKq over |q| = 1, lb <= q <= ub. Returns the value (-inf if none found)."""
    best = -np.inf
    q = np.empty(4)
    for pat in range(81):
        code = pat
        state = np.empty(4, dtype=np.int64)
        for j in range(4):
            state[j] = code % 3
            code //= 3
        nf = 0
        rho2 = 1.0
        for j in range(4):
            if state[j] == 0:
                nf += 1
            else:
                q[j] = lb[j] if state[j] == 1 else ub[j]
                rho2 -= q[j] * q[j]
        if rho2 < -1e-14:
            continue
        rho2 = max(rho2, 0.0)
        if nf == 0:
            if rho2 < 1e-12:
                best = _consider(K, q, lb, ub, best, qbest)
            continue
        F = np.empty(nf, dtype=np.int64)
        k = 0
        for j in range(4):
            if state[j] == 0:
                F[k] = j
                k += 1
        H = np.empty((nf, nf))
        c = np.zeros(nf)
        for a in range(nf):
            for b in range(nf):
                H[a, b] = K[F[a], F[b]]
            for j in range(4):
                if state[j] != 0:
                    c[a] += K[F[a], j] * q[j]
        rho = np.sqrt(rho2)
        if nf == 1:
            for s in (-1.0, 1.0):
                q[F[0]] = s * rho
                best = _consider(K, q, lb, ub, best, qbest)
            continue
        lam, V = np.linalg.eigh(H)
        d = V.T @ c
        lmax = lam[nf - 1]
        dn = np.sqrt(np.sum(d * d))
        x = np.zeros(nf)
        if abs(d[nf - 1]) <= 1e-14 * max(dn, 1.0):
            # hard case candidate: μ = λmax, x = particular + τ v_max
            part = np.zeros(nf)
            for i in range(nf - 1):
                gap = lmax - lam[i]
                if gap > 1e-14:
                    part += (d[i] / gap) * V[:, i]
            rem = rho2 - np.sum(part * part)
            if rem >= 0:
                for s in (-1.0, 1.0):
                    x = part + s * np.sqrt(rem) * V[:, nf - 1]
                    for a in range(nf):
                        q[F[a]] = x[a]
                    best = _consider(K, q, lb, ub, best, qbest)
        if dn == 0.0 or rho == 0.0:
            if rho == 0.0:
                for a in range(nf):
                    q[F[a]] = 0.0
                best = _consider(K, q, lb, ub, best, qbest)
            continue
        # secular equation Σ d_i²/(μ − λ_i)² = ρ² on (λmax, ∞): root in [λmax + |d_n|/ρ, λmax + |d|/ρ]
        lo = lmax + abs(d[nf - 1]) / rho
        hi = lmax + dn / rho
        mu = 0.5 * (lo + hi)
        for _ in range(100):
            g = 0.0
            gp = 0.0
            for i in range(nf):
                t = 1.0 / (mu - lam[i])
                g += d[i] * d[i] * t * t
                gp += -2.0 * d[i] * d[i] * t * t * t
            g -= rho2
            if g > 0:
                lo = mu
            else:
                hi = mu
            step = g / gp if gp != 0.0 else 0.0
            nmu = mu - step
            if not (lo < nmu < hi):
                nmu = 0.5 * (lo + hi)
            if abs(nmu - mu) <= 1e-16 * max(abs(mu), 1.0) or hi - lo <= 1e-16 * max(abs(mu), 1.0):
                mu = nmu
                break
            mu = nmu
        for i in range(nf):
            x += (d[i] / (mu - lam[i])) * V[:, i]
        for a in range(nf):
            q[F[a]] = x[a]
        best = _consider(K, q, lb, ub, best, qbest)
    return best


# ``_nrt=True`` explicitly: the closed-loop kernel that calls this is compiled without numba's
# reference counting, which a callee inherits unless it sets its own (this one allocates)
@njit(cache=True, nogil=True, error_model="numpy", _nrt=True)
def minmax_one(VB, VR, WW, i, search_range, WQ, WO, WC, b, r, q, B, F, K, A, Bk, qp, qt, lb, ub, qb):
    """S0's min-max interval solution of problem ``i`` (compiled; no Python objects).

    The same two stages as ``robust_wahba(method="minmax", solver="closed-form")``: the
    q-method of the interval midpoints ``VB[i]``/``VR[i]`` (weights ``WW[i]``, normalised to
    sum 1) is the global optimum when it lies in the box ``q_T ± search_range·|q_T|`` around
    the TRIAD quaternion ``q_T`` of the same midpoints (S0 §4-1); otherwise the box is active
    and :func:`box_sphere_max` maximises ``qᵀ K^m q`` on the sphere inside it exactly. The
    interval radii do not enter: ``α = β = 0`` is feasible and gives ``ΔL = 0`` (S0 eq. 7;
    see :mod:`adcskit.determination.robust`).

    Writes the canonical quaternion (``q4 >= 0``) to ``WQ[i]``. ``qt``, ``lb``, ``ub``,
    ``qb`` (4,) are scratch; the rest are :func:`~adcskit.determination._kernels.solve_one`'s
    arguments (called, not inlined: one compilation of the Wahba solver for both stages). Returns
    ``(status, box_active)``: status 0 on success, else a Wahba status code
    (:data:`adcskit.determination.wahba.STATUS_MESSAGES`) or ``NOT_CONVERGED`` when no point
    of the sphere inside the box was found.
    """
    # int64(...): a plain integer method code, so that both calls (and the closed-loop Wahba
    # step) share one compilation of solve_one; a literal argument would compile one per code
    st = solve_one(VB, VR, WW, i, i, int64(TRIAD), WQ, WO, WC, b, r, q, B, F, K, A, Bk, qp)
    if st != OK:
        return st, False
    for a in range(4):
        qt[a] = WQ[i, a]
    # q-method of the same midpoints; leaves K = K^m (normalised weights) in K
    st = solve_one(VB, VR, WW, i, i, int64(QMETHOD), WQ, WO, WC, b, r, q, B, F, K, A, Bk, qp)
    if st != OK:
        return st, False
    dot = 0.0
    for a in range(4):
        dot += WQ[i, a] * qt[a]
    sgn = -1.0 if dot < 0.0 else 1.0  # the box is around the TRIAD sign
    inside = True
    for a in range(4):
        half = search_range * abs(qt[a])
        lb[a] = qt[a] - half
        ub[a] = qt[a] + half
        v = sgn * WQ[i, a]
        if v < lb[a] - 1e-15 or v > ub[a] + 1e-15:
            inside = False
    if inside:
        return OK, False
    val = box_sphere_max(K, lb, ub, qb)
    if not np.isfinite(val):
        for a in range(4):
            WQ[i, a] = np.nan
        return NOT_CONVERGED, True
    nrm = 0.0
    for a in range(4):
        nrm += qb[a] * qb[a]
    nrm = np.sqrt(nrm)
    if qb[3] < 0.0:
        nrm = -nrm
    for a in range(4):
        WQ[i, a] = qb[a] / nrm
    return OK, True
