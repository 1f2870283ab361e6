"""Time-optimal 6-DOF rendezvous of S2: chaser attitude (MRP) and Hill relative motion.

State ``x = [ω_BL (3), σ (3), v (3), s (3)]`` (rad/s, –, m/s, m): body rate relative to the
target's LVLH frame in body axes, MRPs of the body frame relative to LVLH, relative velocity
and position in LVLH. Control ``u = [T_B (3), F_B (3)]`` (N m, N), body-fixed thrusters,
``|T_i| <= T_max``, ``|F_i| <= F_max``. Cost ``J = tf`` (S2 eq. 12–16).

LVLH (S2 §2): ``Z`` radial toward the Earth's centre, ``X`` along the target's velocity,
``Y = Z × X`` (minus the orbit normal). The frame rotates at ``ω_LI^L = [0, −n, 0]`` for a
circular orbit of mean motion ``n``; this is the sign that makes S2's ``M`` and ``N``
(eq. 6) the Clohessy–Wiltshire equations ``ẍ − 2n ż = F_x/m``, ``ÿ + n² y = F_y/m``,
``z̈ + 2n ẋ − 3n² z = F_z/m``.

Two rotational models (``dynamics=``):

``"paper"`` — eq. 2/13 exactly as printed:
    ``I ω̇ = T − ω × Iω − ω_LI × I ω_BI``, ``ω_BI = ω + ω_LI`` (all in body axes).

``"full"`` — the exact relative rigid-body dynamics. From Euler's equation for ``ω_BI`` and
``D^B ω_LI = D^L ω_LI + ω_LB × ω_LI = −ω × ω_LI`` (``ω_LI`` constant in ``L``):
    ``I ω̇ = T − ω_BI × I ω_BI + I (ω × ω_LI)``.
    Expanding ``ω_BI × Iω_BI`` shows what eq. 2 drops: ``ω × I ω_LI`` (a gyroscopic
    cross-term) and the transport term ``−I (ω × ω_LI)``; both are ``O(|ω| n)``, i.e.
    ~1e-3 of the retained terms here. Eq. 1's ``I D^L[ω_LI]^B`` is the term the paper sets
    to zero; it is not zero in body axes (it is the transport term above).

MRP kinematics (eq. 4–5): ``σ̇ = ¼ [(1 − σᵀσ) I + 2[σ×] + 2σσᵀ] ω``; the DCM
``A(σ) = I + (8[σ×]² − 4(1 − σᵀσ)[σ×]) / (1 + σᵀσ)²`` maps LVLH to body components, so
``F_L = A(σ)ᵀ F_B`` (eq. 7). Translation (eq. 6): ``v̇ = F_L/m − M v − N s``, ``ṡ = v``.
Gravity-gradient torque and differential drag are not modelled (as in S2).

References
----------
S2, eq. 1–7, 12–16, Tables 2–3. Schaub & Junkins, Analytical Mechanics of Space Systems,
§3.8 (MRP). Fehse, Automated Rendezvous and Docking of Spacecraft, 2003, §3.2 (CW, LVLH).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from adcskit._validation import as_array, check_choice, check_positive
from adcskit.constants import MU_EARTH, R_EARTH
from adcskit.errors import InputError
from adcskit.optimal_control.problem import OptimalControlProblem

__all__ = [
    "RendezvousParams",
    "RENDEZVOUS_DYNAMICS",
    "rendezvous_problem",
    "mrp_kinematics_matrix",
    "mrp_dcm",
    "mean_motion",
    "STATE_NAMES",
    "CONTROL_NAMES",
]


#: Final MRPs of S2 Table 3: pure 90° rotation about body axis 2, tan(90°/4) = 0.4142.
SIGMA_F_PAPER = (0.0, math.tan(math.pi / 8), 0.0)

STATE_NAMES = ("w1", "w2", "w3", "sigma1", "sigma2", "sigma3", "v1", "v2", "v3", "s1", "s2", "s3")
CONTROL_NAMES = ("T1", "T2", "T3", "F1", "F2", "F3")

RENDEZVOUS_DYNAMICS: dict[str, str] = {
    "paper": "rotational dynamics exactly as printed in S2 eq. 2/13",
    "full": "exact relative rigid-body dynamics (adds ω×Iω_LI and the transport term I(ω×ω_LI))",
}


@dataclass(frozen=True, slots=True, kw_only=True)
class RendezvousParams:
    """Chaser of S2 Table 2 (after NASA XTE) on a circular target orbit.

    Attributes
    ----------
    inertia : (3,) tuple
        Principal moments of inertia (kg m²); body axes are principal axes.
    mass : float
        Chaser mass (kg).
    torque_max, force_max : (3,) tuple
        Per-axis limits (N m, N).
    altitude : float
        Target orbit altitude (m).
    """

    inertia: tuple[float, float, float] = (5621.0, 4547.0, 2364.0)
    mass: float = 3200.0
    torque_max: tuple[float, float, float] = (50.0, 50.0, 50.0)
    force_max: tuple[float, float, float] = (320.0, 320.0, 320.0)
    altitude: float = 580e3

    def __post_init__(self) -> None:
        for name in ("inertia", "torque_max", "force_max"):
            arr = as_array(name, getattr(self, name), shape=(3,))
            if np.any(arr <= 0):
                raise InputError(f"{name} must be three positive numbers; got {arr}")
            object.__setattr__(self, name, tuple(float(v) for v in arr))
        object.__setattr__(self, "mass", check_positive("mass", self.mass, unit="kg"))
        object.__setattr__(self, "altitude", check_positive("altitude", self.altitude, unit="m"))

    @property
    def mean_motion(self) -> float:
        """Orbital rate ``n = sqrt(μ / a³)`` (rad/s) of the circular target orbit."""
        return mean_motion(self.altitude)


def mean_motion(altitude: float) -> float:
    """Mean motion (rad/s) of a circular orbit at ``altitude`` (m) above the WGS-84 radius."""
    a = R_EARTH + check_positive("altitude", altitude, unit="m")
    return math.sqrt(MU_EARTH / a**3)


def _skew(v):
    return ca.vertcat(
        ca.horzcat(0, -v[2], v[1]),
        ca.horzcat(v[2], 0, -v[0]),
        ca.horzcat(-v[1], v[0], 0),
    )


def mrp_kinematics_matrix(sigma):
    """``B(σ) = (1 − σᵀσ) I + 2[σ×] + 2σσᵀ`` (S2 eq. 5), CasADi-compatible."""
    s2 = ca.dot(sigma, sigma)
    return (1 - s2) * ca.DM.eye(3) + 2 * _skew(sigma) + 2 * ca.mtimes(sigma, sigma.T)


def mrp_dcm(sigma):
    """DCM ``A(σ)`` mapping reference (LVLH) to body components, CasADi-compatible."""
    s2 = ca.dot(sigma, sigma)
    S = _skew(sigma)
    return ca.DM.eye(3) + (8 * ca.mtimes(S, S) - 4 * (1 - s2) * S) / (1 + s2) ** 2


@functools.lru_cache(maxsize=16)
def _dynamics(params: RendezvousParams, variant: str):
    I = ca.DM(params.inertia)
    I_inv = 1.0 / I
    m = params.mass
    n = params.mean_motion
    w_li_L = ca.DM([0.0, -n, 0.0])
    M = ca.DM([[0, 0, -2 * n], [0, 0, 0], [2 * n, 0, 0]])
    N = ca.DM([[0, 0, 0], [0, n**2, 0], [0, 0, -3 * n**2]])

    def f(x, u, t):
        w, sig, v, s = x[0:3], x[3:6], x[6:9], x[9:12]
        T, F = u[0:3], u[3:6]
        A = mrp_dcm(sig)
        w_li = ca.mtimes(A, w_li_L)
        w_bi = w + w_li
        if variant == "paper":
            rhs = T - ca.cross(w, I * w) - ca.cross(w_li, I * w_bi)
            wdot = I_inv * rhs
        else:
            wdot = I_inv * (T - ca.cross(w_bi, I * w_bi)) + ca.cross(w, w_li)
        sdot = 0.25 * ca.mtimes(mrp_kinematics_matrix(sig), w)
        vdot = ca.mtimes(A.T, F) / m - ca.mtimes(M, v) - ca.mtimes(N, s)
        return ca.vertcat(wdot, sdot, vdot, v)

    return f


def _mayer_tf(x0, t0, xf, tf):
    return tf


def rendezvous_problem(
    s0=(20.0, 0.0, 0.0),
    *,
    sf=(0.0, 0.0, -10.0),
    sigma_f=SIGMA_F_PAPER,
    params: RendezvousParams | None = None,
    dynamics: str = "paper",
    tf_guess: float = 25.0,
) -> OptimalControlProblem:
    """The minimum-time rendezvous problem of S2 (eq. 12–16, Tables 2–3).

    Parameters
    ----------
    s0 : (3,) array_like
        Initial relative position in LVLH (m); S2 Table 3 uses ``[20, 0, 0]``, Table 4 four more.
    sf : (3,) array_like
        Final relative position (m); ``[0, 0, −10]`` (10 m above the target).
    sigma_f : (3,) array_like
        Final MRPs; a pure 90° rotation about body axis 2, ``tan(90°/4) = 0.4142``. (Table 3
        prints ``tan(90°/2)`` but the value 0.4142 and eq. 3 give ``tan(Φ/4)``.)
    params : RendezvousParams, optional
        Chaser of Table 2 by default.
    dynamics : {"paper", "full"}
        Rotational model (module docstring).
    tf_guess : float
        Initial guess of the final time (s).

    Returns
    -------
    OptimalControlProblem
        Problems built with the same ``params`` and ``dynamics`` share one compiled NLP.

    References
    ----------
    S2, eq. 2–7, 12–16, Tables 2–3.
    """
    params = RendezvousParams() if params is None else params
    if not isinstance(params, RendezvousParams):
        raise InputError(f"params must be a RendezvousParams; got {type(params).__name__}")
    dynamics = check_choice("dynamics", dynamics, RENDEZVOUS_DYNAMICS)
    tf_guess = check_positive("tf_guess", tf_guess, unit="s")
    s0 = as_array("s0", s0, shape=(3,))
    sf = as_array("sf", sf, shape=(3,))
    sigma_f = as_array("sigma_f", sigma_f, shape=(3,))
    if np.linalg.norm(sigma_f) > 1.0:
        raise InputError(f"sigma_f must be a short-rotation MRP set (|σ| <= 1); got {sigma_f}")
    tmax = np.array(params.torque_max)
    fmax = np.array(params.force_max)
    x0 = np.concatenate([np.zeros(6), np.zeros(3), s0])
    xf = np.concatenate([np.zeros(3), sigma_f, np.zeros(3), sf])
    big_s = max(100.0, 5 * float(np.max(np.abs(np.concatenate([s0, sf])))))
    upper = np.array([1.0] * 3 + [1.0] * 3 + [10.0] * 3 + [big_s] * 3)
    inertia = np.array(params.inertia)
    return OptimalControlProblem(
        name=f"rendezvous-{dynamics}",
        dynamics=_dynamics(params, dynamics),
        n_states=12,
        n_controls=6,
        state_names=STATE_NAMES,
        control_names=CONTROL_NAMES,
        state_lower=-upper,
        state_upper=upper,
        control_lower=-np.concatenate([tmax, fmax]),
        control_upper=np.concatenate([tmax, fmax]),
        initial_state=x0,
        final_state=xf,
        tf_bounds=(1.0, 500.0),
        tf_guess=tf_guess,
        mayer=_mayer_tf,
        # characteristic magnitudes: rate reached by max torque over half the manoeuvre,
        # MRP of the final attitude, speed reached by max force, distance travelled
        state_scale=np.concatenate(
            [
                np.maximum(tmax / inertia * tf_guess / 4, 1e-3),
                [0.4, 0.4, 0.4],
                np.full(3, max(fmax.max() / params.mass * tf_guess / 4, 1e-2)),
                np.full(3, max(float(np.max(np.abs(np.concatenate([s0, sf])))), 1.0)),
            ]
        ),
        control_scale=np.concatenate([tmax, fmax]),
    )
