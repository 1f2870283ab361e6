"""The rendezvous study's figures: pure functions of the measurement records.

No solving and no random numbers here: every figure reads the records of
:mod:`adcskit.studies.rendezvous.experiment` (S2 Table 4 summary, the refinement history of
every branch, and S2 Figs 3-15 from the main row's best converged :class:`Trajectory`).

References
----------
S2 Figs 3-15 (main scenario), Table 4.
"""

from __future__ import annotations

import numpy as np

from adcskit.studies._base import new_figure
from adcskit.studies.rendezvous.config import Config
from adcskit.studies.rendezvous.experiment import ReadingMeasure, Trajectory, _mesh_text
from adcskit.studies.rendezvous.paper import READING_NAMES, paper_row

__all__ = ["table4_figure", "refinement_figure", "trajectory_figures"]


def table4_figure(m: ReadingMeasure, cfg: Config):
    """S2 Table 4 beside our 20x3 optima and their mesh-converged branches (one reading).

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> b = NS(tf_paper_mesh_s=25.8727, tf_converged_s=25.8703, tolerance_met=True, history=())
    >>> m = NS(rows={0: NS(s0_m=(20.0, 0.0, 0.0), branches=(b,))}, reading="paper")
    >>> table4_figure(m, Config()).axes[0].get_xlabel()
    'initial position s0 (m)'
    """
    fig, ax = new_figure(figsize=(7.5, 4.2))
    rows = list(m.rows.values())
    for x, r in enumerate(rows):
        paper = paper_row(r.s0_m)
        if paper is not None:
            ax.plot(
                x - 0.2, paper[1], "s", color="C0", label="GPM, 20x3 (paper)" if x == 0 else None
            )
            ax.plot(x + 0.2, paper[2], "D", color="C1", label="GPOPS (paper)" if x == 0 else None)
        for j, b in enumerate(r.branches):
            ax.plot(
                [x - 0.07, x + 0.07],
                [b.tf_paper_mesh_s, b.tf_converged_s],
                "-",
                color="0.5",
                lw=0.8,
            )
            ax.plot(
                x - 0.07,
                b.tf_paper_mesh_s,
                "o",
                mfc="none",
                color="C2",
                label="our 20x3 optima" if x == 0 and j == 0 else None,
            )
            met = b.tolerance_met
            ax.plot(
                x + 0.07,
                b.tf_converged_s,
                "*",
                ms=9,
                color="C3",
                mfc="C3" if met else "none",
                label=None,
            )
    ax.plot([], [], "*", ms=9, color="C3", label="same branch, error-controlled refinement (tol met)")
    if any(not b.tolerance_met for r in rows for b in r.branches):
        ax.plot([], [], "*", ms=9, color="C3", mfc="none", label="same branch, refinement (tol NOT met)")
    ax.set_xticks(range(len(rows)), [str([int(v) for v in r.s0_m]) for r in rows], fontsize=8)
    ax.set_xlabel("initial position s0 (m)")
    ax.set_ylabel("tf (s)")
    ax.set_title(f"S2 Table 4: local optima per row ({READING_NAMES[m.reading]})")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return fig


def refinement_figure(m: ReadingMeasure, cfg: Config):
    """Error-controlled refinement of every branch: max relative state error vs nodes.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> h = (NS(n_nodes=60, max_error=2e-3), NS(n_nodes=90, max_error=4e-4))
    >>> b = NS(tf_paper_mesh_s=25.8727, tf_converged_s=25.8703, tolerance_met=True, history=h)
    >>> m = NS(rows={0: NS(s0_m=(20.0, 0.0, 0.0), branches=(b,))}, reading="paper")
    >>> refinement_figure(m, Config()).axes[0].get_yscale()
    'log'
    """
    fig, ax = new_figure(figsize=(7.5, 4.4))
    styles = ("-", "--", ":", "-.")
    for x, r in enumerate(m.rows.values()):
        for j, b in enumerate(r.branches):
            h = b.history
            ax.semilogy(
                [q.n_nodes for q in h],
                [q.max_error for q in h],
                styles[j % len(styles)],
                marker="os^D"[j % 4],
                ms=4,
                color=f"C{x}",
                label=f"s0={[int(v) for v in r.s0_m]}, branch {j + 1} ({b.tf_converged_s:.3f} s)",
            )
    ax.axhline(cfg.adaptive_tol, color="k", lw=0.8, ls="--", label=f"tolerance {cfg.adaptive_tol:g}")
    ax.set_xlabel("collocation points (all intervals)")
    ax.set_ylabel("max relative state error (-)")
    ax.set_title(f"hp refinement of every branch from its 20x3 optimum ({READING_NAMES[m.reading]})")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, ncol=2, loc="upper right")
    return fig


def _euler_yxz(sigma: np.ndarray) -> np.ndarray:
    """Intrinsic Y-X-Z Euler angles (rad) of the body frame relative to LVLH from MRPs."""
    from adcskit.attitude.euler import dcm_to_euler
    from adcskit.attitude.mrp import mrp_to_dcm

    return dcm_to_euler(mrp_to_dcm(sigma), "YXZ")


def trajectory_figures(sol: Trajectory) -> dict:
    """S2 Figs 3-15 of the main row's best converged solution (name -> figure).

    Examples
    --------
    >>> t = np.linspace(0.0, 25.87, 5)
    >>> x = np.zeros((5, 12)); u = np.ones((4, 6)); lam = np.zeros((5, 12))
    >>> traj = Trajectory(t=t, t_control=t[:4], x=x, u=u, costate=lam, hamiltonian=-np.ones(4),
    ...                   n_intervals=20, n_nodes=60, tf=25.87)
    >>> figs = trajectory_figures(traj)
    >>> sorted(figs)[:2], len(figs)
    (['fig03_torques', 'fig04_forces'], 13)
    """
    t = sol.t
    tc = sol.t_control
    x, u, lam = sol.x, sol.u, sol.costate
    figs = {}

    def panel(name, title, tt, data, labels, ylabel, style="-", step=False):
        fig, ax = new_figure()
        for j, lab in enumerate(labels):
            if step:
                ax.step(tt, data[:, j], where="mid", label=lab)
            else:
                ax.plot(tt, data[:, j], style, ms=3, label=lab)
        ax.set_xlabel("t (s)")
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        figs[name] = fig

    lbl = f" ({_mesh_text(sol.n_intervals, sol.n_nodes)}, tf = {sol.tf:.4f} s)"
    panel("fig03_torques", "Control torques" + lbl, tc, u[:, :3], ["T1", "T2", "T3"], "N m", ".-")
    panel("fig04_forces", "Control forces" + lbl, tc, u[:, 3:], ["F1", "F2", "F3"], "N", ".-")
    panel("fig05_rates", "Angular rate relative to LVLH", t, x[:, :3], ["ω1", "ω2", "ω3"], "rad/s")
    panel("fig06_mrp", "Modified Rodrigues parameters", t, x[:, 3:6], ["σ1", "σ2", "σ3"], "-")
    panel(
        "fig07_euler_yxz",
        "Euler angles, sequence YXZ",
        t,
        np.degrees(_euler_yxz(x[:, 3:6])),
        ["θ_Y", "θ_X", "θ_Z"],
        "deg",
    )
    panel("fig08_velocity", "Relative velocity (LVLH)", t, x[:, 6:9], ["v1", "v2", "v3"], "m/s")
    panel("fig09_position", "Relative position (LVLH)", t, x[:, 9:12], ["s1", "s2", "s3"], "m")
    fig = __import__("matplotlib.figure", fromlist=["Figure"]).Figure(
        figsize=(6.4, 5.0), layout="constrained"
    )
    ax = fig.add_subplot(projection="3d")
    ax.plot(x[:, 9], x[:, 10], x[:, 11], "-")
    ax.scatter([x[0, 9]], [x[0, 10]], [x[0, 11]], marker="o", label="start")
    ax.scatter([x[-1, 9]], [x[-1, 10]], [x[-1, 11]], marker="s", label="end")
    ax.scatter([0], [0], [0], marker="*", s=80, label="target")
    ax.set_xlabel("X (m)")
    ax.set_ylabel("Y (m)")
    ax.set_zlabel("Z (m)")
    ax.invert_zaxis()
    ax.set_title("3-D path in LVLH (Z toward Earth)")
    ax.legend(fontsize=8)
    figs["fig10_path3d"] = fig
    panel("fig11_costate_rates", "Costates of ω", t, lam[:, :3], ["λω1", "λω2", "λω3"], "-", ".-")
    panel("fig12_costate_mrp", "Costates of σ", t, lam[:, 3:6], ["λσ1", "λσ2", "λσ3"], "-", ".-")
    panel(
        "fig13_costate_velocity", "Costates of v", t, lam[:, 6:9], ["λv1", "λv2", "λv3"], "-", ".-"
    )
    panel(
        "fig14_costate_position", "Costates of s", t, lam[:, 9:12], ["λs1", "λs2", "λs3"], "-", ".-"
    )
    fig, ax = new_figure()
    ax.plot(tc, sol.hamiltonian, ".-")
    ax.axhline(-1.0, color="k", lw=0.8, ls="--", label="H = -1 (theory)")
    ax.set_ylim(-1.1, -0.9)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("H")
    ax.set_title("Hamiltonian at the collocation points")
    ax.legend(fontsize=8)
    figs["fig15_hamiltonian"] = fig
    return figs
