"""Multiple-stage launch-vehicle ascent (the GPOPS-II example): four phases, mass jumps at
booster and stage separation, thrust direction with a unit-norm path constraint, and a
terminal event on five orbital elements; maximise the final mass.

Vehicle (Delta III-like, Benson 2004; Patterson & Rao 2014 §7.5): nine solid boosters (six
burn in phase 1, three in phase 2), a first stage burning through phases 1–3 and a second
stage in phase 4; the dry masses are dropped by linkage jumps. Rotating spherical Earth,
exponential atmosphere, drag on the air-relative velocity. Published optimum: final mass
7529.712680 kg (Patterson & Rao 2014).

References
----------
Patterson & Rao, ACM TOMS 41(1), 2014, §7.5 (multiple-stage launch vehicle ascent). Benson,
"A Gauss pseudospectral transcription for optimal control", PhD thesis, MIT, 2004.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from adcskit.errors import InputTypeError
from adcskit.optimal_control.multiphase import Link, MultiPhaseGuess, MultiPhaseProblem, Phase
from adcskit.optimal_control.problem import Guess

__all__ = ["LAUNCH", "launch_ascent", "launch_ascent_guess"]

LAUNCH = {
    "mu": 3.986012e14,  # m^3/s^2
    "Re": 6378145.0,  # m
    "omega": 7.29211585e-5,  # rad/s
    "rho0": 1.225,  # kg/m^3
    "H": 7200.0,  # m
    "CD": 0.5,
    "S": 4.0 * np.pi,  # m^2
    "g0": 9.80665,  # m/s^2
    "lat0": np.deg2rad(28.5),  # rad, launch site
    "srb": {"m": 19290.0, "prop": 17010.0, "T": 628500.0, "isp": 283.33364, "burn": 75.2},
    "s1": {"m": 104380.0, "prop": 95550.0, "T": 1083100.0, "isp": 301.68776, "burn": 261.0},
    "s2": {"m": 19300.0, "prop": 16820.0, "T": 110094.0, "isp": 467.21311, "burn": 700.0},
    "payload": 4164.0,
    # target orbit: a (m), e, i, Ω, ω (rad)
    "orbit": (24361140.0, 0.7308, np.deg2rad(28.5), np.deg2rad(269.8), np.deg2rad(130.5)),
}


def _stage_dynamics(thrust: float, mdot: float):
    L = LAUNCH

    def f(x, u, t, p):
        r, v, m = x[0:3], x[3:6], x[6]
        rn = ca.sqrt(ca.dot(r, r))
        w = ca.vertcat(0.0, 0.0, L["omega"])
        vrel = v - ca.cross(w, r)
        vr = ca.sqrt(ca.dot(vrel, vrel) + 1e-6)  # smooth at zero air speed (the launch pad)
        rho = L["rho0"] * ca.exp(-(rn - L["Re"]) / L["H"])
        drag = -0.5 * L["CD"] * L["S"] * rho * vr * vrel
        acc = -L["mu"] / rn**3 * r + (thrust * u[0:3] + drag) / m
        return ca.vertcat(v, acc, -mdot)

    return f


def _unit(x, u, t, p):
    return [u[0] * u[0] + u[1] * u[1] + u[2] * u[2]]


def _orbit_events(ends, p):
    L = LAUNCH
    r, v = ends[3].xf[0:3], ends[3].xf[3:6]
    mu = L["mu"]
    rn = ca.sqrt(ca.dot(r, r))
    v2 = ca.dot(v, v)
    h = ca.cross(r, v)
    hn = ca.sqrt(ca.dot(h, h))
    n = ca.vertcat(-h[1], h[0], 0.0)
    nn = ca.sqrt(ca.dot(n, n))
    evec = ((v2 - mu / rn) * r - ca.dot(r, v) * v) / mu
    en = ca.sqrt(ca.dot(evec, evec))
    a = 1.0 / (2.0 / rn - v2 / mu)
    a_t, e_t, i_t, O_t, w_t = L["orbit"]
    return [
        a / a_t - 1.0,
        en - e_t,
        h[2] / hn - np.cos(i_t),
        (n[0] * np.sin(O_t) - n[1] * np.cos(O_t)) / nn,  # node line along Ω
        ca.dot(n, evec) / (nn * en) - np.cos(w_t),  # argument of perigee (e_z > 0 branch)
    ]


def _final_mass(ends, p):
    return -ends[3].xf[6]


def launch_ascent() -> MultiPhaseProblem:
    """The four-phase launch-vehicle ascent (maximise the final mass, kg).

    States per phase: position (m, ECI), velocity (m/s), mass (kg); controls: the thrust
    direction ``u`` with ``|u| = 1`` (path constraint).

    Examples
    --------
    >>> from adcskit.optimal_control.problems.launch import launch_ascent
    >>> [ph.name for ph in launch_ascent().phases]
    ['6 SRB + stage 1', '3 SRB + stage 1', 'stage 1', 'stage 2']
    """
    L = LAUNCH
    srb, s1, s2 = L["srb"], L["s1"], L["s2"]
    md_srb = srb["T"] / (L["g0"] * srb["isp"])
    md_1 = s1["T"] / (L["g0"] * s1["isp"])
    md_2 = s2["T"] / (L["g0"] * s2["isp"])
    m0 = L["payload"] + s2["m"] + s1["m"] + 9 * srb["m"]
    lat = L["lat0"]
    r0 = L["Re"] * np.array([np.cos(lat), 0.0, np.sin(lat)])
    v0 = np.cross([0.0, 0.0, L["omega"]], r0)
    t1 = srb["burn"]
    t2 = 2 * srb["burn"]
    t3 = s1["burn"]
    rmax, vmax = 2.0 * L["Re"], 14000.0
    common = dict(
        n_states=7,
        n_controls=3,
        state_names=("rx", "ry", "rz", "vx", "vy", "vz", "m"),
        control_names=("ux", "uy", "uz"),
        control_lower=[-1.0] * 3,
        control_upper=[1.0] * 3,
        path=_unit,
        path_lower=[1.0],
        path_upper=[1.0],
        state_scale=[L["Re"]] * 3 + [vmax / 2] * 3 + [m0 / 3],
        control_scale=[1.0] * 3,
    )
    lo = [-rmax] * 3 + [-vmax] * 3
    hi = [rmax] * 3 + [vmax] * 3
    phases = [
        Phase(name="6 SRB + stage 1", dynamics=_stage_dynamics(6 * srb["T"] + s1["T"], 6 * md_srb + md_1),
              state_lower=lo + [L["payload"]], state_upper=hi + [m0],
              initial_state=list(r0) + list(v0) + [m0], t0_bounds=(0.0, 0.0), tf_bounds=(t1, t1), **common),
        Phase(name="3 SRB + stage 1", dynamics=_stage_dynamics(3 * srb["T"] + s1["T"], 3 * md_srb + md_1),
              state_lower=lo + [L["payload"]], state_upper=hi + [m0], t0_bounds=(t1, t1), tf_bounds=(t2, t2), **common),
        Phase(name="stage 1", dynamics=_stage_dynamics(s1["T"], md_1),
              state_lower=lo + [L["payload"]], state_upper=hi + [m0], t0_bounds=(t2, t2), tf_bounds=(t3, t3), **common),
        Phase(name="stage 2", dynamics=_stage_dynamics(s2["T"], md_2),
              state_lower=lo + [L["payload"]], state_upper=hi + [m0], t0_bounds=(t3, t3),
              tf_bounds=(t3, t3 + s2["burn"]), tf_guess=t3 + 0.8 * s2["burn"], **common),
    ]
    pos_vel = tuple(range(6))
    links = []
    for k, dm in ((0, 6 * (srb["m"] - srb["prop"])), (1, 3 * (srb["m"] - srb["prop"])), (2, s1["m"] - s1["prop"])):
        links.append(Link(k, k + 1, states=pos_vel))
        links.append(Link(k, k + 1, states=(6,), jump=-dm, time=False))
    return MultiPhaseProblem(
        name="launch-ascent",
        phases=phases,
        objective=_final_mass,
        events=_orbit_events,
        event_lower=[0.0] * 5,
        event_upper=[0.0] * 5,
        links=links,
    )


def _oe2rv(a, e, i, O, w, nu, mu):
    p = a * (1 - e * e)
    r_pf = p / (1 + e * np.cos(nu)) * np.array([np.cos(nu), np.sin(nu), 0.0])
    v_pf = np.sqrt(mu / p) * np.array([-np.sin(nu), e + np.cos(nu), 0.0])
    cO, sO, ci, si, cw, sw = np.cos(O), np.sin(O), np.cos(i), np.sin(i), np.cos(w), np.sin(w)
    R = np.array(
        [
            [cO * cw - sO * sw * ci, -cO * sw - sO * cw * ci, sO * si],
            [sO * cw + cO * sw * ci, -sO * sw + cO * cw * ci, -cO * si],
            [sw * si, cw * si, ci],
        ]
    )
    return R @ r_pf, R @ v_pf


def launch_ascent_guess(problem: MultiPhaseProblem) -> MultiPhaseGuess:
    """A naive guess: phases 1–3 hold the launch-site position and velocity, phase 4 runs to
    the target orbit's perigee (straight line in direction, radius interpolated so that it
    stays above the surface); masses linear at the burn rates; thrust along the local
    vertical."""
    if not isinstance(problem, MultiPhaseProblem):
        raise InputTypeError(f"problem must be a MultiPhaseProblem; got {type(problem).__name__}")
    L = LAUNCH
    out = []
    x_end = None
    rf, vf = _oe2rv(*L["orbit"], 0.0, L["mu"])
    for k, ph in enumerate(problem.phases):
        t0 = ph.t0_bounds[0]
        tf = ph.tf_guess if ph.tf_guess is not None else ph.tf_bounds[1]
        x0 = np.array(ph.initial_state) if k == 0 else x_end.copy()
        if k > 0:
            x0[6] += problem.links[2 * (k - 1) + 1].jump
        mdot = -float(ph.dynamics(ca.DM(x0), ca.DM([1.0, 0, 0]), 0.0, ca.DM([]))[6])
        xf = x0.copy()
        xf[6] = x0[6] - mdot * (tf - t0)
        if k == 3:
            xf[:3], xf[3:6] = rf, vf
        s = np.linspace(0.0, 1.0, 21)[:, None]
        x = x0 + s * (xf - x0)
        # the chord from the pad to the orbit passes below the surface: keep the direction of
        # the straight line but interpolate the radius
        rad = np.linalg.norm(x0[:3]) + s[:, 0] * (np.linalg.norm(xf[:3]) - np.linalg.norm(x0[:3]))
        x[:, :3] *= (rad / np.linalg.norm(x[:, :3], axis=1))[:, None]
        up = x[:, :3] / np.linalg.norm(x[:, :3], axis=1)[:, None]
        out.append(Guess(t=t0 + s[:, 0] * (tf - t0), x=x, u=up, tf=tf))
        x_end = xf
    return MultiPhaseGuess(phases=tuple(out), parameters=np.zeros(0))
