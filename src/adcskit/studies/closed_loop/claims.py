"""The ``closed-loop`` study's findings (our questions; the papers make no claim here) and checks.

:data:`FINDINGS` and :data:`CHECKS` list one small factory per statement, in report order, each
``(config, measurements) -> Declared | Check``: a finding is a module-level
:class:`~adcskit.studies._verdict.FindingSpec` (``F1`` ... ``F6``) with its per-seed
:class:`~.experiment.SeedRatio` runs keyed by reading, decided by the framework's
:meth:`~adcskit.studies._verdict.ClaimSpec.evaluate`; a check is computed from the records (its
text quotes measured numbers). :data:`CLAIMS` is empty. :func:`evaluate` decides a list.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from adcskit.studies._base import Check, protocol_keys
from adcskit.studies._verdict import Declared, FindingSpec, decide_declared
from adcskit.studies.closed_loop.config import Config
from adcskit.studies.closed_loop.experiment import (
    Q1_READINGS,
    Q2_MINMAX_READINGS,
    Q2_READINGS,
    Q6_READINGS,
    Measurements,
)

__all__ = ["CHECKS", "CLAIMS", "FINDINGS", "F1", "F2", "F2B", "F3", "F4A", "F4B", "F5", "F6", "Declared",
           "chi2_mean_band", "evaluate"]


def _ratio(run: Any) -> float:
    return run.ratio


#: Protocol keys of questions 1-4 (F1 ... F4B): the settings tagged ``"findings"`` on
#: :class:`~.config.Config` (the GEO, LEO and S4 scenarios, the layout search, the slew, the
#: sample count). One group, not a split per question: several keys are shared (``n_samples`` by
#: all, the S4 plant by Q3 and Q5) and the questions draw from the same per-seed seed sequences.
#: Q5's and Q6's own keys (``q5_*``, ``q6_*``) are not in it: changing one of them leaves Q1-Q4's
#: protocol label unchanged (before, with no keys declared, any non-neutral key marked them).
_Q1_Q4_KEYS: tuple[str, ...] = protocol_keys(Config, "findings")


F1 = FindingSpec(
    id="q1-layout-propellant",
    statement="the S3-optimised 6-thruster layout uses less propellant than S3's reference layout in closed loop "
              "(slew + hold, S4 controller)",
    where="S3 Fig. 5 (open-loop on-times) taken into the closed loop",
    quantity="mean propellant, optimised / reference",
    value=_ratio, threshold=1.0, better="below", readings=Q1_READINGS,
    protocol_keys=_Q1_Q4_KEYS,
)
F2 = FindingSpec(
    id="q2-mekf-vs-qmethod",
    statement="the MEKF gives better closed-loop pointing than the per-epoch q-method under S0's sensor errors",
    where="S0 orbit scenario (bounded errors) in closed loop",
    quantity="mean RMS pointing error, MEKF / q-method",
    value=_ratio, threshold=1.0, better="below", readings=Q2_READINGS,
    protocol_keys=_Q1_Q4_KEYS,
)
F2B = FindingSpec(
    id="q2-minmax-vs-qmethod",
    statement="S0's robust min-max interval determination gives better closed-loop pointing than the per-epoch "
              "q-method under S0's sensor errors",
    where="S0 eqs. 3-8 (min-max, TRIAD +-10 % search box) per epoch in the S0 orbit scenario, closed loop",
    quantity="mean RMS pointing error, min-max / q-method",
    value=_ratio, threshold=1.0, better="below", readings=Q2_MINMAX_READINGS,
    protocol_keys=_Q1_Q4_KEYS,
)
F3 = FindingSpec(
    id="q3-robust-gains-spread",
    statement="S4's robust gains reduce the spread of the 3-axis pointing error under S4's dispersions + sensor noise",
    where="S4 Tables 4-6 in a 3-axis loop",
    quantity="std of the per-sample RMS pointing error (last 10 s), robust / nominal",
    value=_ratio, threshold=1.0, better="below",
    protocol_keys=_Q1_Q4_KEYS,
)
F4A = FindingSpec(
    id="q4-optimal-slew-settling",
    statement="tracking a time-optimal slew profile settles sooner than a step command",
    where="S2 guidance in an S3/S4 loop",
    quantity="mean settling time, optimal profile / step",
    value=_ratio, threshold=1.0, better="below",
    protocol_keys=_Q1_Q4_KEYS,
)
F4B = FindingSpec(
    id="q4-optimal-slew-propellant",
    statement="tracking a time-optimal slew profile uses less propellant than a step command",
    where="S2 guidance in an S3/S4 loop",
    quantity="mean propellant, optimal profile / step",
    value=_ratio, threshold=1.0, better="below",
    protocol_keys=_Q1_Q4_KEYS,
)

F5 = FindingSpec(
    id="q5-wheels-vs-thrusters",
    statement="on S4's spacecraft (same inertia, orbit, disturbance, sensors and 15 deg step), reaction wheels under "
              "quaternion PD point better after settling than S4's on-off thruster loop (our question, not a paper's)",
    where="S4 Tables 3-5 plant and nominal gains (Table 4) vs a 4-wheel pyramid with S4's torque level per axis",
    quantity="p99 over samples of the largest pointing error in S4's last 10 s, wheels / thrusters",
    value=_ratio, threshold=1.0, better="below",
    # only Q5's keys and the S4 plant keys it shares: Q1-Q4's settings do not define it
    protocol_keys=protocol_keys(Config, "q5-wheels-vs-thrusters"),
)


def _score(run: Any) -> float:
    return run.score


F6 = FindingSpec(
    id="q6-reference-mode-sequence",
    statement="the 12U reference smallsat (4 pyramid wheels, 3 magnetorquers, sun sensor + magnetometer + gyro + "
              "star tracker; detumble -> sun acquisition -> nadir pointing over three orbits, with the reference "
              "dispersions) meets its sign-off requirement table at 95 % confidence (our question, not a paper's)",
    where="docs/wheels.md, the reference Monte-Carlo and its requirement table",
    quantity="per seed, the sign-off table of one Monte-Carlo campaign: +1 every row met, -1 a row not met, "
             "0 otherwise (a row inconclusive); mean over seeds",
    value=_score, threshold=0.0, better="above", readings=Q6_READINGS,
    # a table that neither meets nor fails (a row "inconclusive (need ~N samples)") is a tie:
    # it counts neither for nor against, and makes the reading inconclusive
    margin=0.5,
    margin_reason="a seed whose table has an inconclusive row and no failed one scores 0: too few samples to "
                  "bound that row either way, so it counts neither as met nor as failed (a tie)",
    protocol_keys=protocol_keys(Config, "q6-reference-mode-sequence"),
)


def chi2_mean_band(dof: int, n: int) -> tuple[float, float]:
    """95 % band of the mean of ``n`` independent chi2(``dof``) values.

    Examples
    --------
    >>> lo, hi = chi2_mean_band(6, 1000); round(lo, 2), round(hi, 2)
    (5.79, 6.22)
    """
    from scipy.stats import chi2

    return float(chi2.ppf(0.025, dof * n) / n), float(chi2.ppf(0.975, dof * n) / n)


# ----------------------------------------------------------------------------- findings


def _q1(cfg: Config, m: Measurements) -> Declared:
    return Declared(F1, m.layouts.runs, Q1_READINGS[0])


def _q2_mekf(cfg: Config, m: Measurements) -> Declared:
    return Declared(F2, m.estimators.mekf_runs, Q2_READINGS[0])


def _q2_minmax(cfg: Config, m: Measurements) -> Declared:
    return Declared(F2B, m.estimators.minmax_runs, Q2_MINMAX_READINGS[0])


def _q3(cfg: Config, m: Measurements) -> Declared:
    return Declared(F3, {"default": m.gains.runs})


def _q4_settling(cfg: Config, m: Measurements) -> Declared:
    return Declared(F4A, {"default": m.slews.settling_runs})


def _q4_propellant(cfg: Config, m: Measurements) -> Declared:
    return Declared(F4B, {"default": m.slews.propellant_runs})


def _q5(cfg: Config, m: Measurements) -> Declared:
    return Declared(F5, {"default": m.wheels.runs})


def _q6(cfg: Config, m: Measurements) -> Declared:
    runs = m.modes.runs

    def describe(r: Any) -> str:  # the per-seed tables in words, with the rows that keep one open
        return "per-seed tables: " + ", ".join(
            t.outcome + (f" ({t.open_rows})" if t.open_rows else "") for t in runs[r.reading])

    return Declared(dataclasses.replace(F6, describe=describe), runs, Q6_READINGS[0])


# ----------------------------------------------------------------------------- checks


def _mekf_consistent(cfg: Config, m: Measurements) -> Check:
    nees_all = np.asarray(m.estimators.nees_gaussian, dtype=float)
    n = cfg.n_samples * nees_all.size  # the grand mean averages every sample of every seed
    lo, hi = chi2_mean_band(6, n)
    mean = float(np.mean(nees_all))
    side = "inside" if lo <= mean <= hi else ("below: the covariance is larger than the errors (conservative)"
                                               if mean < lo else "above: the covariance is too small (overconfident)")
    return Check(
        name="MEKF consistency in the loop: mean NEES over the Gaussian-error LEO campaigns within the strict chi2(6) "
             "95 % band of a mean over all their samples",
        passed=bool(np.all(np.isfinite(nees_all)) and lo <= mean <= hi),
        detail=f"mean NEES {mean:.3f} (per-seed {', '.join(f'{v:.2f}' for v in nees_all)}); 95 % band of the mean "
               f"of {n} chi2(6) values ({nees_all.size} seeds x {cfg.n_samples} samples) [{lo:.3f}, {hi:.3f}]: "
               f"{side}. Each sample's NEES is a time average over its epochs, whose spread is at most one chi2(6) "
               "value's, so this band is the widest a consistent filter's mean can need (the MEKF underweights "
               "measurements while its covariance exceeds their noise)",
        kind="check")


def _bang_bang(cfg: Config, m: Measurements) -> Check:
    tf, bb = m.slews.optimal_tf_s, m.slews.bang_bang_tf_s
    return Check(
        name="the pseudospectral slew reaches the bang-bang optimum t_f = 2 sqrt(angle / accel_max)",
        passed=bool(abs(tf - bb) <= 1e-3 * bb),
        detail=f"t_f {tf:.4f} s vs {bb:.4f} s", kind="check")


def _feasible(cfg: Config, m: Measurements) -> Check:
    fr = m.feasibility
    return Check(
        name="feasibility before flight: in Q2-Q4 every Monte-Carlo sample's thrusters (dispersed misalignment) "
             "can produce torque in every direction",
        passed=bool(fr) and all(v == 1.0 for v in fr.values()),
        detail="smallest controllable fraction per question over its simulate calls: "
               + ", ".join(f"{q} {v:.3g}" for q, v in fr.items())
               + " (Q1 with a failed thruster: see q1_controllable_fraction in measured)",
        kind="check")


#: The papers' claims: none (the study answers questions they leave open).
CLAIMS: tuple = ()
#: Our findings, in report order.
FINDINGS = (_q1, _q2_mekf, _q2_minmax, _q3, _q4_settling, _q4_propellant, _q5, _q6)
#: Our consistency checks, in report order.
CHECKS = (_mekf_consistent, _bang_bang, _feasible)


#: Decide the declared statements (the framework's :func:`~adcskit.studies._verdict.decide_declared`).
evaluate = decide_declared
