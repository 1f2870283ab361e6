"""The ``model-estimation`` study's claims (S1's), findings (ours) and checks, as declarations.

:data:`CLAIMS`, :data:`FINDINGS` and :data:`CHECKS` list one small factory per statement, in
report order (the convention of ``thruster_layout.claims``). Each takes the config and the
:class:`~.experiment.Measurements` and returns

* for a claim or finding: a :class:`Declared` — the framework's :class:`ClaimSpec` /
  :class:`FindingSpec` and its per-seed :class:`~.experiment.SeedErrors` keyed by reading —
  that :func:`evaluate` hands to :meth:`ClaimSpec.evaluate` (the framework decides);
* for a check: a :class:`~adcskit.studies.Check`;

or ``None`` when the configured methods or cases leave the statement out. They are factories
rather than constants because the quantities name the configured methods and cases.
"""

from __future__ import annotations

from adcskit.studies._base import Check, protocol_keys
from adcskit.studies._verdict import ClaimSpec, Declared, FindingSpec, decide_declared
from adcskit.studies.model_estimation.config import FINDING_KEYS, PRIOR_BASELINES, Config
from adcskit.studies.model_estimation.experiment import Measurements
from adcskit.studies.model_estimation.paper import PAPER_METHODS, STANDARD, TABLE_CASES

__all__ = ["CHECKS", "CLAIMS", "FINDINGS", "Declared", "evaluate"]

#: Protocol of the S1 claims (``alpha0`` added where the adaptive variants decide), declared on
#: :class:`~.config.Config`'s fields.
_CLAIM_KEYS = protocol_keys(Config, "claims")
_ADAPTIVE_KEYS = protocol_keys(Config, "claims", "adaptive")
_ON = "adaptive-gmres-online"


def _readings(m: Measurements) -> tuple[str, ...]:
    """The readings a spec lists: all of them, or none when only the default ran."""
    return m.readings if len(m.readings) > 1 else ()


def _best(s, methods, c):
    return min(s.err[x][c] for x in methods)


def _std(cfg: Config) -> tuple[str, ...]:
    return tuple(x for x in STANDARD if x in cfg.methods)


# ----------------------------------------------------------------------------- claims (S1's)


def _adaptive_10x(cfg: Config, m: Measurements) -> Declared | None:
    std, cases = _std(cfg), cfg.cases
    adaptive = tuple(x for x in ("adaptive-gmres-offline", _ON) if x in cfg.methods)
    if not (std and adaptive):
        return None
    return Declared(ClaimSpec(
        id="adaptive-10x",
        statement="The adaptive GMRES methods reduce the model error norm more than 10 times compared "
        "with the standard solvers (QR, GMRES, Bi-CG, CGS, Bi-CGSTAB).",
        where="S1 text at Figs 2, 6, 13; Table 1 (37-195 % vs 1-16 %)",
        quantity="min over cases and over both adaptive variants of (best standard-solver error / "
        "adaptive error), one seed; >= 10",
        value=lambda s: min(_best(s, std, c) / max(s.err[a][c], 1e-12) for c in cases for a in adaptive),
        threshold=10.0, paper=">= 10", readings=_readings(m), protocol_keys=_ADAPTIVE_KEYS,
    ), m.per_seed)


def _standard_37_195(cfg: Config, m: Measurements) -> Declared | None:
    std = _std(cfg)
    tcases = tuple(c for c in TABLE_CASES if c in cfg.cases)
    if not (std and tcases):
        return None
    return Declared(ClaimSpec(
        id="standard-37-195",
        statement="The standard solvers QR, GMRES, Bi-CG, CGS and Bi-CGSTAB leave 37-195 % model error.",
        where="S1 Table 1, rows 1-5",
        quantity="every standard solver's final error in [37, 195] % on every Table 1 case "
        f"({', '.join(tcases)}), one seed",
        held=lambda s: all(37.0 <= s.err[x][c] <= 195.0 for x in std for c in tcases),
        paper="37-195 %", readings=_readings(m), protocol_keys=_CLAIM_KEYS,
    ), m.per_seed)


def _online_most_accurate(cfg: Config, m: Measurements) -> Declared | None:
    paper_ms, cases = tuple(x for x in PAPER_METHODS if x in cfg.methods), cfg.cases
    if _ON not in cfg.methods or len(paper_ms) <= 1:
        return None
    return Declared(ClaimSpec(
        id="online-most-accurate",
        statement="The online meta-heuristic adaptive GMRES is the most accurate of the methods.",
        where="S1 abstract; Table 1",
        quantity="online adaptive GMRES has the smallest final error of S1's seven methods on every case, "
        "one seed",
        held=lambda s: all(s.err[_ON][c] <= _best(s, paper_ms, c) + 1e-12 for c in cases),
        readings=_readings(m), protocol_keys=_ADAPTIVE_KEYS,
    ), m.per_seed)


# ----------------------------------------------------------------------------- findings (ours)


def _online_improves_on_prior(cfg: Config, m: Measurements) -> Declared | None:
    cases = cfg.cases
    if _ON not in cfg.methods:
        return None
    return Declared(FindingSpec(
        id="online-improves-on-prior",
        statement="Online adaptive GMRES ends closer to the truth than the prior A0 it starts from, on every case.",
        quantity="max over cases of (online error / prior error); < 0.999 (ending exactly at A0 is no improvement)",
        value=lambda s: max(s.err[_ON][c] / s.prior[c] for c in cases), threshold=0.999, better="below",
        readings=_readings(m), protocol_keys=FINDING_KEYS,
    ), m.per_seed)


def _prior_baselines_match_online(cfg: Config, m: Measurements) -> Declared | None:
    cases, base = cfg.cases, tuple(b for b in PRIOR_BASELINES if b in cfg.methods)
    if _ON not in cfg.methods or not base:
        return None
    return Declared(FindingSpec(
        id="prior-baselines-match-online",
        statement="An explicit prior-anchored estimator (ridge toward A0 with GCV or the discrepancy "
        "rule, or RLS anchored at A0) is at least as accurate as the online adaptive GMRES on every case.",
        quantity="max over cases of (best prior-anchored baseline error / online error); < 1.0001",
        value=lambda s: max(_best(s, base, c) / max(s.err[_ON][c], 1e-12) for c in cases),
        threshold=1.0001, better="below", readings=_readings(m), protocol_keys=FINDING_KEYS,
    ), m.per_seed)


def _ekf_beats_online(cfg: Config, m: Measurements) -> Declared | None:
    cases = cfg.cases
    if _ON not in cfg.methods or "augmented-ekf" not in cfg.methods:
        return None
    return Declared(FindingSpec(
        id="ekf-knowing-structure-beats-online",
        statement="The augmented-state EKF, which knows the model structure (it estimates the inertia "
        "ratios of the physical model, not the matrix entries), is more accurate than the online "
        "adaptive GMRES on every case.",
        quantity="max over cases of (EKF error / online error); < 1",
        value=lambda s: max(s.err["augmented-ekf"][c] / max(s.err[_ON][c], 1e-12) for c in cases),
        threshold=1.0, better="below", readings=_readings(m), protocol_keys=FINDING_KEYS,
    ), m.per_seed)


def _least_squares_identifies_1dof(cfg: Config, m: Measurements) -> Declared | None:
    one, std = tuple(c for c in cfg.cases if c.startswith("1dof")), _std(cfg)
    if not (one and std):
        return None
    return Declared(FindingSpec(
        id="least-squares-identifies-1dof",
        statement="Converged least squares (any standard solver) identifies the 1-DOF model: its error is "
        "below a tenth of the prior's.",
        quantity="max over 1-DOF cases of (standard-solver error / prior error); < 0.1",
        value=lambda s: max(_best(s, std, c) / s.prior[c] for c in one), threshold=0.1, better="below",
        readings=_readings(m), protocol_keys=FINDING_KEYS,
    ), m.per_seed)


# ----------------------------------------------------------------------------- checks


def _converged_same_ls(cfg: Config, m: Measurements) -> Check | None:
    rel_diff = m.solver_rel_diff
    if rel_diff is None:
        return None
    return Check(
        name="converged QR, LSQR, GMRES, Bi-CGSTAB reach the same least-squares solution",
        passed=rel_diff < 1e-6, detail=f"max relative difference {rel_diff:.2e} over all runs", kind="check",
    )


def _standard_same_row_as_qr(cfg: Config, m: Measurements) -> Check | None:
    std, main = _std(cfg), m.tables["default"]
    if "qr" not in cfg.methods or not std:
        return None
    same = max(abs(main[x][c].median - main["qr"][c].median) for x in std for c in cfg.cases)
    return Check(
        name="the standard solvers, run to tolerance inside the loop, give the same table row as QR",
        passed=same < 1.0, detail=f"largest difference of medians from QR: {same:.3f} percentage points",
        kind="check",
    )


CLAIMS = (_adaptive_10x, _standard_37_195, _online_most_accurate)
FINDINGS = (_online_improves_on_prior, _prior_baselines_match_online, _ekf_beats_online,
            _least_squares_identifies_1dof)
CHECKS = (_converged_same_ls, _standard_same_row_as_qr)


#: Decide the declared statements (the framework's :func:`~adcskit.studies._verdict.decide_declared`).
evaluate = decide_declared
