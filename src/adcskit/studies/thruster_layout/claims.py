"""The ``thruster-layout`` study's claims (S3's), findings (ours) and checks, as declarations.

:data:`CLAIMS`, :data:`FINDINGS` and :data:`CHECKS` list one small factory per statement, in
report order. Each takes the config and the :class:`~.experiment.Measurements` and returns

* for a claim or finding: a :class:`Declared` — the framework's :class:`ClaimSpec` /
  :class:`FindingSpec` and its per-seed runs keyed by reading — that :func:`evaluate` hands
  to :meth:`ClaimSpec.evaluate` (the framework decides the outcome);
* for a check: a :class:`~adcskit.studies.Check`;

or ``None`` when the configuration leaves the statement out (e.g. no GA, no n = 6). They are
factories rather than constants because the framework's specs are frozen strings and numbers
and S3's statements quote the configured protocol (generations, demands, tolerance).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from adcskit.studies._base import Check, protocol_keys
from adcskit.studies._verdict import ClaimSpec, Declared, FindingSpec, Premise, decide_declared
from adcskit.studies.thruster_layout.config import Config
from adcskit.studies.thruster_layout.experiment import (
    FUEL_DEFAULT,
    Measurements,
    torque_tolerance_nm,
)
from adcskit.studies.thruster_layout.paper import PAPER

__all__ = ["CHECKS", "CLAIMS", "FINDINGS", "Declared", "evaluate", "torque_tolerance_nm"]



@dataclass(frozen=True, slots=True)
class _Value:
    """One seed's deciding quantity (a ratio or a fraction)."""

    value: float


@dataclass(frozen=True, slots=True)
class _Held:
    """One run's yes / no answer."""

    ok: bool


def _per_seed(label: str) -> Callable[[Any], str]:
    return lambda r: label + ", ".join(f"{v:.2f}" for v in r.values)


def _ratios(cfg: Config, m: Measurements, key: str, ns: Sequence[int]) -> list[_Value]:
    """Per seed, the largest DE/GA ratio of ``key`` over ``ns``."""
    return [_Value(max(getattr(m.run(n, "de", s), key) / getattr(m.run(n, "ga", s), key) for n in ns))
            for s in range(cfg.n_seeds)]


# ----------------------------------------------------------------------------- claims (S3's)


def _de_more_accurate(cfg: Config, m: Measurements) -> Declared | None:
    if not {"ga", "de"} <= set(cfg.algorithms):
        return None
    return Declared(ClaimSpec(
        id="de-more-accurate",
        statement="the differential evolution algorithm has better accuracy than the genetic algorithm "
                  "in solving this problem (lower fitness F_best)",
        where="abstract; §6, Fig. 4",
        quantity="per seed, the largest DE/GA ratio of F_best over n in "
                 f"{list(cfg.n_thrusters)}; holds below 1 (DE lower at every n)",
        value=lambda r: r.value, threshold=1.0, better="below", unit="-",
        protocol_keys=protocol_keys(Config, "de-more-accurate"),
        describe=_per_seed("DE/GA F_best ratio (worst n) per seed: "),
    ), {"default": _ratios(cfg, m, "f_best", cfg.n_thrusters)})


def _de_faster(cfg: Config, m: Measurements) -> Declared | None:
    if not {"ga", "de"} <= set(cfg.algorithms):
        return None
    reps = cfg.timing_repeats
    return Declared(ClaimSpec(
        id="de-faster",
        statement="the differential evolution algorithm has a shorter run time than the genetic algorithm",
        where="abstract; §6, Fig. 3",
        quantity="per seed, the largest DE/GA ratio over n of the process CPU time per optimisation "
                 f"(time.process_time of the process that runs it, median of {reps} repeat{'s' if reps != 1 else ''} "
                 f"of the same seeded run inside this run; equal evaluations: {cfg.n_gen} generations x "
                 f"{cfg.pop_size}); holds below 1",
        value=lambda r: r.value, threshold=1.0, better="below", unit="-", timing=True,
        protocol_keys=protocol_keys(Config, "de-faster"),
        describe=lambda r: "DE/GA CPU-time ratio (worst n) per seed: " + ", ".join(f"{v:.2f}" for v in r.values)
        + " (same number of evaluations: the difference is pymoo's per-generation overhead)",
    ), {"default": _ratios(cfg, m, "cpu_s_median", cfg.n_thrusters)})


def _six_thrusters_best(cfg: Config, m: Measurements) -> Declared | None:
    if 6 not in cfg.n_thrusters or len(cfg.n_thrusters) < 2:
        return None
    others = [n for n in cfg.n_thrusters if n != 6]
    runs = [_Value(max(m.run(6, a, s).f_best / min(m.run(n, a, s).f_best for n in others) for a in cfg.algorithms))
            for s in range(cfg.n_seeds)]
    return Declared(ClaimSpec(
        id="six-thrusters-best",
        statement="for both algorithms the lowest value of the fitness function is obtained with 6 thrusters",
        where="§6, Fig. 4",
        quantity="per seed and algorithm, F_best(6) / min over the other n of F_best; the largest over "
                 "the algorithms; holds below 1",
        value=lambda r: r.value, threshold=1.0, better="below", unit="-",
        protocol_keys=protocol_keys(Config, "six-thrusters-best"),
        describe=_per_seed("F_best(6)/best other n per seed: "),
    ), {"default": runs})


def _optimal_layout_less_fuel(cfg: Config, m: Measurements) -> Declared | None:
    runs = m.fuel_by_reading()
    if not runs:
        return None
    from scipy.stats import norm

    mag, tol = float(np.linalg.norm(m.demands[0])), torque_tolerance_nm(cfg)
    z = float(norm.ppf(0.975))
    # each reading's margin from its own sampling error (the fixed design demands have none)
    sd = {k: max(r.log_ratio_sd for r in v) for k, v in runs.items()}
    margins = {k: z * v for k, v in sd.items()}
    equal_torque = Premise(
        name="equal torque",
        holds=lambda r: r.equal_torque,
        why=lambda r: f"the optimal layout misses {r.opt_n_missed}/{r.n_demands} demands by more than {tol:.3f} N m "
                      f"(up to {r.opt_max_error_nm:.3g} N m), the reference {r.ref_n_missed}",
    )
    return Declared(ClaimSpec(
        id="optimal-layout-less-fuel",
        statement="the fuel consumption of the optimal layout is lower than that of the empirically chosen "
                  "(reference) layout",
        where="§6, Fig. 5",
        quantity="per seed, summed on-time of the optimal 6-thruster layout / that of the reference "
                 f"(mean over {cfg.n_fuel_demands} random demand directions of |M| = {mag:.3f} N m); holds "
                 f"below 1, decided on log ratios. Premise of every reading, per seed: equal torque (every demand "
                 f"met by both layouts within {tol:.3f} N m = {100 * tol / mag:.1f} % of |M|, the reference's minimum "
                 "torque impulse per sample F_max Delta t_min / t_s, S3 eq. 9-10); a seed that misses one is no "
                 "evidence for its reading",
        value=lambda r: r.ratio, threshold=1.0, better="below", unit="-", scale="log",
        margin=margins[FUEL_DEFAULT], reading_margins=margins,
        margin_reason=f"per reading, the sampling error of its random directions, measured: each out-of-sample ratio "
                      f"recomputed on {cfg.fuel_redraws} independent redraws of its {cfg.n_fuel_demands} directions; "
                      f"margin = {z:.2f} x the largest standard deviation of a seed's log ratio over its "
                      f"{cfg.fuel_redraws + 1} draws: "
                      + "; ".join(f"{k}: {v:.3g} (a factor {math.exp(v):.3f})" for k, v in margins.items())
                      + " (the fixed design demands are not sampled: 0)",
        readings=tuple(k for k in runs if k != FUEL_DEFAULT),
        protocol_keys=protocol_keys(Config, "optimal-layout-less-fuel"),
        premises=(equal_torque,),
        describe=lambda r: "optimal/reference on-time per seed: " + ", ".join(f"{v:.3f}" for v in r.values),
    ), runs, FUEL_DEFAULT)


def _table8_e_min(cfg: Config, m: Measurements) -> Declared | None:
    if not m.e_min:
        return None
    return Declared(ClaimSpec(
        id="table8-e-min",
        statement="Table 8: minimum reachable error e_min of the four DE layouts 0.00084, 0.00083, 0.00082 "
                  "and 0.00083 rad (4, 6, 8, 12 thrusters), an acceptable level",
        where="§6, Table 8",
        quantity=f"per seed, the largest relative distance of the DE layouts' e_min from Table 8 over n; holds "
                 f"below {cfg.e_min_tolerance:g}",
        value=lambda r: r.rel_dev, threshold=cfg.e_min_tolerance, better="below", unit="-",
        paper=PAPER["table8_e_min_rad"], readings=tuple(cfg.e_min_readings[1:]),
        protocol_keys=protocol_keys(Config, "table8-e-min"),
        describe=lambda r: "largest relative deviation per seed: " + ", ".join(f"{v:.2f}" for v in r.values),
    ), m.e_min, cfg.e_min_readings[0])


# ----------------------------------------------------------------------------- findings (ours)


def _de_settings_n6(cfg: Config, m: Measurements) -> Declared | None:
    if not m.sensitivity or "ga" not in cfg.algorithms:
        return None
    ga = m.sensitivity[-1]
    de_keys = [k.setting for k in m.sensitivity if not k.setting.startswith("ga")]
    return Declared(FindingSpec(
        id="de-settings-n6",
        statement=f"at n = 6, the best of {len(de_keys)} DE settings ({', '.join(de_keys)}) reaches a lower "
                  "F_best than the GA (is the GA-vs-DE ranking an artefact of one DE setting?)",
        quantity="per seed, min over DE settings of F_best / GA F_best; holds below 1",
        value=lambda r: r.value, threshold=1.0, better="below", unit="-",
        describe=_per_seed("best DE / GA per seed: "),
    ), {"default": [_Value(v) for v in ga.ratio_seeds]})


def _printed_layouts_realisable(cfg: Config, m: Measurements) -> Declared:
    pl = m.paper_layouts
    ok = all(pl[k].realisable_in_box for k in ("6-de", "8-de"))
    return Declared(FindingSpec(
        id="printed-layouts-realisable",
        statement="S3's printed 6- and 8-thruster DE layout matrices can be produced by thrusters in the "
                  "2 x 2 x 2 m box (column norm |r x d| <= |r| <= sqrt(3) m)",
        quantity="largest column norm of each printed matrix vs the box's largest lever arm",
        held=lambda r: r.ok, stochastic=False,
        describe=lambda r: "column norms: " + ", ".join(f"{k} {pl[k].max_column_norm_m:.2f} m" for k in ("6-de", "8-de"))
        + f" vs {np.linalg.norm(m.half):.2f} m",
    ), {"default": [_Held(ok)]})


def _pinv_redistribute_exact(cfg: Config, m: Measurements) -> Declared:
    miss = m.miss.by_method
    pinv = miss["pinv-redistribute"]
    return Declared(FindingSpec(
        id="pinv-redistribute-exact",
        statement="S3's redistributed pseudo-inverse meets every feasible demand exactly (as the exact "
                  "allocators do), on random 8-thruster layouts",
        quantity=f"fraction of {m.miss.n_layouts} random layouts (feasible demand M = A F_true) met to 1e-9 "
                 "relative; holds if all are",
        held=lambda r: r.value >= 1.0, stochastic=False,
        describe=lambda r: f"pinv-redistribute: {100 * pinv.fraction_exact:.0f} % exact, "
        f"median miss {pinv.median_rel_error:.1e}, worst {100 * pinv.max_rel_error:.0f} %; nnls / lp-min-fuel worst "
        f"{max(miss['nnls'].max_rel_error, miss['lp-min-fuel'].max_rel_error):.1e}",
    ), {"default": [_Value(pinv.fraction_exact)]})


# ----------------------------------------------------------------------------- checks (ours)


def _faces_respected(cfg: Config, m: Measurements) -> Check:
    max_cant = math.radians(cfg.max_cant_deg)
    designs = [*m.runs, *m.paired_runs]
    return Check(
        name="every designed layout respects the mounting faces and thrust-leaves-face limits",
        passed=all(_face_ok(r, m.half, max_cant) for r in designs),
        detail=f"{len(designs)} layouts: positions on allowed faces {cfg.faces}, d . n_out <= 0, "
               f"cant <= {cfg.max_cant_deg} deg",
    )


def _face_ok(row: Any, half: np.ndarray, max_cant: float) -> bool:
    normals = {"+X": (0, 1), "-X": (0, -1), "+Y": (1, 1), "-Y": (1, -1), "+Z": (2, 1), "-Z": (2, -1)}
    for p, d, f in zip(row.positions, row.directions, row.faces):
        k, s = normals[f]
        n = np.zeros(3)
        n[k] = s
        on_face = abs(p[k] - s * half[k]) < 1e-9 and np.all(np.abs(p) <= half + 1e-9)
        cant = math.acos(min(1.0, max(-1.0, float(-d @ n))))
        if not (on_face and d @ n <= 1e-12 and cant <= max_cant + 1e-9):
            return False
    return True


def _paired_couples(cfg: Config, m: Measurements) -> Check | None:
    if not m.paired_runs:
        return None
    worst_force = max(float(np.abs(np.asarray(r.directions).sum(axis=0)).max()) for r in m.paired_runs)
    twin_ok = all(np.allclose(np.asarray(r.positions)[: r.n // 2], -np.asarray(r.positions)[r.n // 2:])
                  for r in m.paired_runs)
    return Check(
        name="paired reading: every gene is a couple (twin at -r on the parallel face, no net force)",
        passed=twin_ok and worst_force < 1e-12,
        detail=f"{len(m.paired_runs)} paired layouts; largest |sum of force directions| {worst_force:.1e}",
    )


def _exact_allocators(cfg: Config, m: Measurements) -> Check:
    exact = max(m.miss.by_method["nnls"].max_rel_error, m.miss.by_method["lp-min-fuel"].max_rel_error)
    return Check(
        name="nnls and lp-min-fuel reproduce feasible demands to 1e-9 relative",
        passed=exact <= 1e-9,
        detail=f"max relative torque error {exact:.2e} on {m.miss.n_layouts} random 8-thruster layouts",
    )


def _fuel_equal_torque(cfg: Config, m: Measurements) -> Check | None:
    # the fuel claim compares on-times at equal torque: its declared premise (a seed that fails it
    # is no evidence for that reading); this check reports it over every reading
    if not m.fuel:
        return None
    mag, tol = float(np.linalg.norm(m.demands[0])), torque_tolerance_nm(cfg)
    by = m.fuel_by_reading()
    worst = {k: max(r.opt_max_error_nm for r in v) for k, v in by.items()}
    missed = {k: (sum(r.opt_n_missed for r in v), sum(r.n_demands for r in v)) for k, v in by.items()}
    ref = max(r.ref_max_error_nm for r in m.fuel)
    return Check(
        name="fuel comparison on equal torque: in every reading, every demand is met by the optimal and the "
             f"reference layout within {tol:.3f} N m ({100 * tol / mag:.1f} % of |M|; S3 eq. 9-10's minimum "
             "torque impulse of the reference per sample)",
        passed=all(v <= tol for v in worst.values()) and ref <= tol,
        detail="optimal layout, demands missed beyond the tolerance (all seeds) and the largest miss: "
               + "; ".join(f"{k}: {missed[k][0]}/{missed[k][1]}, {v:.3g} N m ({100 * v / mag:.2g} % of |M|)"
                           for k, v in worst.items())
               + f"; reference: largest miss {ref:.1e} N m",
    )


def _timing_repeats_identical(cfg: Config, m: Measurements) -> Check | None:
    if not m.timing_runs:
        return None
    same = all(r.f_best == m.run(r.n, r.alg, r.seed_index).f_best for r in m.timing_runs)
    return Check(
        name="every timing repeat re-ran the same seeded optimisation (identical F_best)",
        passed=same,
        detail=f"{len(m.timing_runs)} repeats of {len(m.runs)} designs ({cfg.timing_repeats} runs each); the "
               "de-faster claim reads the median process CPU time of each",
    )


def _best_layouts_controllable(cfg: Config, m: Measurements) -> Check:
    from adcskit.thrusters import check_controllability

    ctrl = {n: check_controllability(np.asarray(r.torque_matrix)).success for n, r in m.best_per_n.items()}
    return Check(
        name="best layout of every n is controllable (positive span)",
        passed=all(ctrl.values()), detail=", ".join(f"n={n}: {v}" for n, v in ctrl.items()),
    )


def _reference_meets_demands(cfg: Config, m: Measurements) -> Check | None:
    if m.reference_vs_optimal is None:
        return None
    return Check(
        name="the reference layout meets every demand of the manoeuvre",
        passed=m.reference_vs_optimal.by_allocation["lp-min-fuel"].all_met_ref,
        detail=f"{cfg.correction_deg} deg corrections, |M| = {np.linalg.norm(m.demands[0]):.3f} N m; "
               "fuel comparison is then on equal (exact) torque",
    )


def _de_settings_same_seeds(cfg: Config, m: Measurements) -> Check | None:
    # the ranking statement the DE-settings finding rests on is computed, not asserted
    if not m.sensitivity:
        return None
    detail = "median F_best over the same seeds: " + ", ".join(
        f"{k.setting}: {k.f_best_median:.3f}" for k in m.sensitivity)
    ga = [k for k in m.sensitivity if k.setting.startswith("ga")]
    if ga:  # without the GA there is no ranking to state
        ranks = [k.f_best_median < ga[0].f_best_median for k in m.sensitivity if not k.setting.startswith("ga")]
        detail += f"; DE settings with a lower median than the GA: {sum(ranks)}/{len(ranks)}"
    return Check(
        name="every DE setting at n = 6 ran on the same seeds as the default DE and the GA",
        passed=all(len(k.f_best_seeds) == cfg.n_seeds for k in m.sensitivity), detail=detail,
    )


# ----------------------------------------------------------------------------- declarations

#: S3's claims, in report order.
CLAIMS = (_de_more_accurate, _de_faster, _six_thrusters_best, _optimal_layout_less_fuel, _table8_e_min)
#: Our findings, in report order.
FINDINGS = (_de_settings_n6, _printed_layouts_realisable, _pinv_redistribute_exact)
#: Our consistency checks, in report order.
CHECKS = (_faces_respected, _paired_couples, _exact_allocators, _best_layouts_controllable,
          _reference_meets_demands, _fuel_equal_torque, _de_settings_same_seeds, _timing_repeats_identical)


#: Decide the declared statements (the framework's :func:`~adcskit.studies._verdict.decide_declared`).
evaluate = decide_declared
