"""Dynamics: Euler equations, gravity gradient, LVLH model, CW, discretisation."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from adcskit import attitude as att
from adcskit import dynamics as dyn
from adcskit.constants import MU_EARTH, R_EARTH
from adcskit.errors import InputError


def test_torque_free_axisymmetric_precession_closed_form():
    # Axisymmetric body, torque free: ω3 const, (ω1, ω2) rotate at λ = (I3 − I1)/I1 · ω3
    # (Markley & Crassidis 2014, §3.3.5). Tolerance: integrator rtol 1e-10 over 60 s.
    J = np.array([10.0, 10.0, 4.0])
    w0 = np.array([0.1, 0.0, 0.5])
    t = np.linspace(0, 60, 61)
    tr = dyn.propagate_attitude([0, 0, 0, 1], w0, J, t)
    assert tr.success
    lam = (J[2] - J[0]) / J[0] * w0[2]
    np.testing.assert_allclose(tr.omega[:, 0], 0.1 * np.cos(lam * t), atol=1e-8)
    np.testing.assert_allclose(tr.omega[:, 1], 0.1 * np.sin(lam * t), atol=1e-8)
    # angular momentum magnitude and kinetic energy conserved
    H = np.linalg.norm(tr.omega * J, axis=1)
    np.testing.assert_allclose(H, H[0], rtol=1e-9)
    # inertial angular momentum direction conserved: A(q)^T (J ω) constant
    h_ref = np.einsum("nji,nj->ni", att.quat_to_dcm(tr.q), tr.omega * J)
    np.testing.assert_allclose(h_ref, np.broadcast_to(h_ref[0], h_ref.shape), atol=1e-8)


def test_euler_equations_batch_and_gyroscopic_term():
    J = np.diag([2.0, 3.0, 4.0])
    w = np.array([[1.0, 2.0, 3.0], [0.0, 0.0, 1.0]])
    wd = dyn.euler_equations(w, J, torque=[0.0, 0.0, 0.0])
    # ω̇1 = (I2 − I3) ω2 ω3 / I1 = (3 − 4)·6/2 = −3
    np.testing.assert_allclose(wd[0], [(3 - 4) * 6 / 2, (4 - 2) * 3 / 3, (2 - 3) * 2 / 4])
    np.testing.assert_allclose(wd[1], 0.0)


def test_gravity_gradient_closed_form():
    # Pitch offset θ about y in LVLH-like geometry: τ_y = (3μ/2r³)(Iz − Ix) sin 2θ (Wie §6.4).
    J = np.array([100.0, 80.0, 50.0])
    r = 7000e3
    th = 0.1
    nadir_in_body = np.array([-np.sin(th), 0, np.cos(th)])  # body z tilted by θ from nadir
    tau = dyn.gravity_gradient_torque(-r * nadir_in_body, J)
    np.testing.assert_allclose(tau[1], 1.5 * MU_EARTH / r**3 * (J[2] - J[0]) * np.sin(2 * th), rtol=1e-12)
    assert abs(tau[0]) < 1e-18 and abs(tau[2]) < 1e-18


def test_orbit_rate():
    n = dyn.orbit_rate(500e3)
    assert abs(2 * np.pi / n - 5676.98) < 0.5  # 500 km circular orbit period ≈ 94.6 min
    with pytest.raises(InputError, match="altitude must be >= 0 m"):
        dyn.orbit_rate(-1.0)


def _nonlinear_vs_linear(J, printed, horizon_frac=0.25):
    """Propagate the full nonlinear rigid body in a circular orbit with gravity gradient and
    return the max deviation of the small LVLH angles from the linear model's prediction."""
    alt = 500e3
    a = R_EARTH + alt
    n = dyn.orbit_rate(alt)

    def lvlh_from_eci(t):
        c, s = np.cos(n * t), np.sin(n * t)
        r_hat = np.array([c, s, 0.0])
        z = -r_hat
        y = np.array([0, 0, -1.0])
        x = np.cross(y, z)
        return np.vstack([x, y, z])

    x0 = np.array([2e-3, -1e-3, 1.5e-3, 1e-5, 0.0, -1e-5])
    A_bl = att.euler_to_dcm(x0[:3], "XYZ")
    A_be = A_bl @ lvlh_from_eci(0.0)
    w_l = np.array([0.0, -n, 0.0])
    w0 = x0[3:] + A_bl @ w_l
    t = np.linspace(0, horizon_frac * 2 * np.pi / n, 40)

    def torque(tt, q, w):
        r_eci = a * np.array([np.cos(n * tt), np.sin(n * tt), 0.0])
        return dyn.gravity_gradient_torque(att.quat_to_dcm(q) @ r_eci, J)

    tr = dyn.propagate_attitude(att.dcm_to_quat(A_be), w0, J, t, torque)
    assert tr.success
    ang = []
    for tk, q in zip(t, tr.q):
        M = att.quat_to_dcm(q) @ lvlh_from_eci(tk).T
        S = (M.T - M) / 2
        ang.append([S[2, 1], S[0, 2], S[1, 0]])
    ang = np.array(ang)
    A, _ = dyn.lvlh_attitude_model(J, n, printed=printed)
    lin = np.array([expm(A * tk) @ x0 for tk in t])[:, :3]
    return np.abs(ang - lin).max(), np.abs(lin).max()


def test_lvlh_model_matches_nonlinear_simulation_and_printed_does_not():
    # Inertia with a large gyroscopic coefficient Ix − Iy + Iz so that the N-matrix sign matters.
    J = np.array([120.0, 100.0, 90.0])
    err, scale = _nonlinear_vs_linear(J, printed=False)
    err_printed, _ = _nonlinear_vs_linear(J, printed=True)
    # Linearisation error is O(angle²) ~ (3e-3)² ≈ 1e-5 relative to angles ~ 3e-3.
    assert err < 0.01 * scale, (err, scale)
    assert err_printed > 10 * err, (err_printed, err)


def test_lvlh_model_structure_s1_inertia():
    # S1 eq. 8-11 with Ix, Iy, Iz = 82, 80, 4 kg m².
    n = dyn.orbit_rate(500e3)
    A, B = dyn.lvlh_attitude_model([82, 80, 4], n)
    M, N, L = dyn.lvlh_second_order([82, 80, 4], n)
    np.testing.assert_allclose(N, -N.T)  # gyroscopic: skew-symmetric
    np.testing.assert_allclose(np.diag(L), n**2 * np.array([4 * 76, 3 * 78, -2]))
    np.testing.assert_allclose(B[3:], np.diag([1 / 82, 1 / 80, 1 / 4]))
    _, Np, _ = dyn.lvlh_second_order([82, 80, 4], n, printed=True)
    np.testing.assert_allclose(Np, Np.T)
    assert Np[0, 2] == pytest.approx(N[0, 2]) and Np[2, 0] == pytest.approx(-N[2, 0])
    with pytest.raises(InputError, match="inertia must be diagonal"):
        dyn.lvlh_attitude_model(np.array([[82, 1, 0], [1, 80, 0], [0, 0, 4.0]]), n)


def test_cw_matrices_against_closed_form_stm():
    # Vallado (2013) eq. 6-66 closed form vs expm of the S2 eq. 6 system.
    n = 0.0011
    A, B = dyn.cw_matrices(n)
    for t in (10.0, 1000.0, 5000.0):
        np.testing.assert_allclose(expm(A * t), dyn.cw_stm(n, t), atol=1e-9 * (1 + n * t) * 10)
    # S2 eq. 6: v̇ + M v + N s = 0 with M = [[0,0,-2n],[0,0,0],[2n,0,0]], N = diag(0, n², -3n²)
    Mm = np.array([[0, 0, -2 * n], [0, 0, 0], [2 * n, 0, 0]])
    Nm = np.diag([0, n**2, -3 * n**2])
    np.testing.assert_allclose(A[3:, 3:], -Mm)
    np.testing.assert_allclose(A[3:, :3], -Nm)


def test_discretize_zoh_and_crank_nicolson():
    A = np.array([[0.0, 1.0], [-4.0, -0.4]])
    B = np.array([[0.0], [1.0]])
    h = 0.05
    Ad, Bd = dyn.discretize(A, B, h, "zoh")
    np.testing.assert_allclose(Ad, expm(A * h), atol=1e-14)
    # Bd = A^{-1}(Ad - I)B for invertible A (closed form)
    np.testing.assert_allclose(Bd, np.linalg.solve(A, (Ad - np.eye(2)) @ B), atol=1e-14)
    Ac, Bc = dyn.discretize(A, B, h, "crank-nicolson")
    # Trapezoidal rule is second order: one-step error O(h³) vs the exact propagator.
    assert np.abs(Ac - Ad).max() < 5 * h**3 * np.abs(A).max() ** 3
    # A-stability: the stable continuous poles map inside the unit disc
    assert np.all(np.abs(np.linalg.eigvals(Ac)) < 1)
    # Cayley form: Ac = (I - hA/2)^{-1}(I + hA/2)
    I = np.eye(2)
    np.testing.assert_allclose((I - h / 2 * A) @ Ac, I + h / 2 * A, atol=1e-14)
    with pytest.raises(InputError, match="method must be one of 'zoh', 'crank-nicolson'"):
        dyn.discretize(A, B, h, "tustin2")
    with pytest.raises(InputError, match="dt must be > 0 s"):
        dyn.discretize(A, B, 0.0)
    with pytest.raises(InputError, match="B must have shape"):
        dyn.discretize(A, np.ones((3, 1)), h)


def test_inertia_validation():
    with pytest.raises(InputError, match="inertia must be positive definite"):
        dyn.euler_equations([0, 0, 1], [1.0, -1.0, 1.0])
    with pytest.raises(InputError, match="inertia must be symmetric"):
        dyn.euler_equations([0, 0, 1], [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]])
