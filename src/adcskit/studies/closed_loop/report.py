"""The ``closed-loop`` study's ``measured`` values, tables and text: pure functions of the records."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from adcskit.studies.closed_loop.config import Config
from adcskit.studies.closed_loop.experiment import Measurements

__all__ = ["DIFFERENCES", "TITLE", "measured", "q5_text", "q6_text", "row", "summary", "tables"]

TITLE = "Closed-loop 3-axis ADCS: layouts, estimators, robust gains and optimal slews in Monte-Carlo"

#: ``result.json`` -> ``differences``: where the study departs from the papers.
DIFFERENCES = (
    "Questions the papers leave open, answered in a closed loop none of them simulates: findings, not claims.",
    "Derivative term from the estimated rate (gyro minus estimated bias) instead of S4's filtered derivative.",
    "Q2's robust determination is S0's min-max (compiled in the loop); the worst-case formulation "
    "(Ahmed & Kerrigan) is not run inside the loop: it is an SLSQP optimisation per epoch, not compiled "
    "(see the docs page).",
    "Q5 (wheels vs S4's thrusters, our question): both loops fly S4's spacecraft (J = 10 kg m^2 per axis, 20 % "
    "dispersion), orbit, 0.05 N m constant disturbance, star tracker 10 Hz + gyro 50 Hz, 15 deg step and last-10 s "
    "window at S4's 50 Hz command rate. They differ in: the actuator (4-wheel pyramid, per-wheel torque limit "
    "sqrt(3)/4 T so that each body axis gets S4's T = 1 N m, vs S4's thruster pair with lag, delay and 20 % thrust "
    "dispersion); the law (quaternion PD, no integral, vs S4's PID + Schmitt trigger); the knowledge (star tracker "
    "propagated by the gyro vs the MEKF); the disturbance (nominal in the wheel loop, 100 % dispersed in the "
    "thruster loop: the wheel kernel has no disturbance dispersion).",
    "Q6 (the 12U reference mode sequence, our question): the reference scenario of docs/wheels.md with its "
    "dispersions, one Monte-Carlo campaign per seed from Q6's own random stream, signed off by the requirement "
    "table of docs/wheels.md; a table with an inconclusive row (too few samples to bound it) counts as a tie, "
    "neither met nor failed.",
)


def row(record: Any) -> dict[str, Any]:
    """A record's fields as a table row, values as measured (NaN stays NaN in the CSV).

    Examples
    --------
    >>> from adcskit.studies.closed_loop.experiment import GainRow
    >>> row(GainRow(seed=0, std_nominal_deg=0.1, std_robust_deg=0.2, mean_nominal_deg=1.0, mean_robust_deg=1.5))
    {'seed': 0, 'std_nominal_deg': 0.1, 'std_robust_deg': 0.2, 'mean_nominal_deg': 1.0, 'mean_robust_deg': 1.5}
    """
    return {f.name: getattr(record, f.name) for f in dataclasses.fields(record)}


def measured(m: Measurements) -> dict[str, Any]:
    """``result.json`` -> ``measured``, in the study's historical key order."""
    out: dict[str, Any] = {}
    q1 = m.layouts
    for key, fr in q1.controllable_fraction.items():
        # fraction of the Monte-Carlo samples whose thrusters (failed one removed, dispersed
        # misalignment) can produce torque in every direction (simulate's feasibility test)
        out[f"q1_controllable_fraction[{key}]"] = fr
        # torque available in the weakest direction (N m), mean over samples and seeds
        out[f"q1_torque_authority_nm[{key}]"] = q1.torque_authority_nm[key]
    for reading, v in m.estimators.box_active_fraction.items():
        out[f"q2_minmax_box_active_fraction[{reading}]"] = v
    out["q2_mekf_mean_nees_gaussian"] = float(np.mean(m.estimators.nees_gaussian))
    out["q4_optimal_tf_s"] = m.slews.optimal_tf_s
    out["q4_bang_bang_tf_s"] = m.slews.bang_bang_tf_s
    for r in m.wheels.rows:
        if r.seed == m.wheels.rows[-1].seed:  # last seed: the sign-off table's campaigns
            key = "wheels" if r.loop.startswith("wheels") else "thrusters"
            out[f"q5_pointing_max_p99_deg[{key}]"] = r.pointing_max_p99_deg
            out[f"q5_pointing_rms_mean_deg[{key}]"] = r.pointing_rms_mean_deg
            out[f"q5_settling_p99_s[{key}]"] = r.settling_p99_s
    out["q5_max_wheel_speed_p99_rpm"] = float(np.nanmax([r.max_wheel_speed_p99_rpm for r in m.wheels.rows]))
    out["q5_wheel_kernel_sample_steps_per_s"] = m.wheels.wheel_sample_steps_per_s
    out["kernel_sample_steps_per_s_median"] = float(np.median(m.sample_steps_per_s))
    out["n_simulate_calls"] = len(m.sample_steps_per_s)
    q6 = m.modes.rows  # medians over the seeds' campaigns
    for key in ("t_detumbled_p99_s", "t_acquired_p99_s", "pointing_max_p99_deg", "pointing_rms_p99_deg",
                "knowledge_rms_p99_deg", "max_wheel_speed_max_rpm", "cpu_s"):
        out[f"q6_{key}_median"] = float(np.median([getattr(r, key) for r in q6]))
    out["q6_pointing_at_end_fraction"] = float(sum(r.n_pointing_at_end for r in q6) / sum(r.n_samples for r in q6))
    out["q6_wheel_kernel_sample_steps_per_s"] = m.modes.sample_steps_per_s
    return out


def tables(m: Measurements) -> dict[str, list[dict[str, Any]]]:
    """One CSV per question."""
    return {
        "q1_layouts": [row(r) for r in m.layouts.rows],
        "q2_estimators": [row(r) for r in m.estimators.rows],
        "q3_gains": [row(r) for r in m.gains.rows],
        "q4_slew": [row(r) for r in m.slews.rows],
        "q5_wheels_vs_thrusters": [row(r) for r in m.wheels.rows],
        "q5_requirements": [row(r) for r in m.wheels.requirements],
        "q6_seeds": [row(r) for r in m.modes.rows],
        "q6_requirements": [row(r) for r in m.modes.requirements],
    }


def summary(cfg: Config, m: Measurements, findings: list) -> str:
    """One paragraph: protocol size, each finding's outcome, the kernel's speed."""
    rate = float(np.median(m.sample_steps_per_s))
    return (
        f"{cfg.n_seeds} seeds x {cfg.n_samples} samples per configuration (Q6: {cfg.q6_n_samples} per seed). "
        + "; ".join(f"{f.id}: {f.outcome} (mean {'score' if f.id.startswith('q6') else 'ratio'} {f.measured:.3g})"
                    for f in findings)
        + f". Kernel median {rate:.3g} sample-steps/s. " + q5_text(m) + " " + q6_text(m)
    )


def q5_text(m: Measurements) -> str:
    """Q5's requirement table in one sentence per loop (last seed's campaigns).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from adcskit.studies.closed_loop.experiment import RequirementRow
    >>> r = RequirementRow(loop="wheels", name="Q5-1", requirement="pointing_max_deg p99 <= 0.5 after 20 s", n=1000,
    ...                    estimate=0.1, bound=0.12, outcome="met", verdict="met")
    >>> q5_text(SimpleNamespace(wheels=SimpleNamespace(requirements=(r,))))
    'Q5 sign-off (last seed): wheels: Q5-1 met (estimate 0.1, bound 0.12).'
    """
    loops: dict[str, list[str]] = {}
    for r in m.wheels.requirements:
        loops.setdefault(r.loop, []).append(f"{r.name} {r.outcome} (estimate {r.estimate:.3g}, bound {r.bound:.3g})")
    return "Q5 sign-off (last seed): " + "; ".join(f"{k}: {', '.join(v)}" for k, v in loops.items()) + "."


def q6_text(m: Measurements) -> str:
    """Q6's sign-off: the first seed's table row by row, then every seed's table outcome.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from adcskit.studies.closed_loop.experiment import ModeRequirementRow, Q6_READINGS, SeedTable
    >>> r = ModeRequirementRow(seed=0, name="Q6-1", requirement="pointing_max_deg p99 <= 0.2 after 11400 s",
    ...                        n=1000, n_violating=0, estimate=0.114, bound=0.118, verdict="met",
    ...                        bound_bonferroni=0.12, verdict_bonferroni="met")
    >>> t = SeedTable(seed=0, outcome="met", score=1.0, n_met=1, n_not_met=0, n_inconclusive=0, open_rows="")
    >>> q6_text(SimpleNamespace(modes=SimpleNamespace(requirements=(r,), runs={q: (t,) for q in Q6_READINGS})))
    'Q6 sign-off, reference mode sequence (seed 0, 1000 samples, each row at its stated confidence): Q6-1 met (estimate 0.114, bound 0.118). Table per seed, each row at its stated confidence: met; whole table at once (Bonferroni): met.'
    """
    rows = [r for r in m.modes.requirements if r.seed == 0]
    n = rows[0].n if rows else 0
    head = "; ".join(f"{r.name or r.requirement} {r.verdict} (estimate {r.estimate:.3g}, bound {r.bound:.3g})"
                     for r in rows)
    per_seed = "; ".join(f"{reading}: {', '.join(t.outcome for t in runs)}" for reading, runs in m.modes.runs.items())
    return (f"Q6 sign-off, reference mode sequence (seed 0, {n} samples, each row at its stated confidence): {head}. "
            f"Table per seed, {per_seed}.")
