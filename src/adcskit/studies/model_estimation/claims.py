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
from adcskit.studies.model_estimation.paper import PAPER_METHODS, PAPER_TABLE, STANDARD, TABLE_CASES

__all__ = ["CHECKS", "CLAIMS", "FINDINGS", "Declared", "evaluate"]

_ON, _OFF = "adaptive-gmres-online", "adaptive-gmres-offline"
_VARIANT = {_OFF: "offline ('empirical') adaptive GMRES", _ON: "online meta-heuristic adaptive GMRES"}
#: Reading of ours that only changes the standard Krylov solvers (claims that compare with them).
_KRYLOV_READING = "S1-like Krylov"
#: S1 prints whole percents: a range [lo, hi] covers [lo - 0.5, hi + 0.5] before rounding.
_HALF = 0.5


def _keys(cases, *, online: bool = False) -> tuple[str, ...]:
    """Protocol of a claim on ``cases``: the shared keys, the 3-DOF model's keys when a 3-DOF case
    is among them, ``alpha0`` when the online variant decides (declared on :class:`~.config.Config`)."""
    tags = ("claims",) + (("3dof",) if any(c.startswith("3dof") for c in cases) else ()) + (
        ("adaptive",) if online else ())
    return protocol_keys(Config, *tags)


def _readings(m: Measurements, *, krylov: bool = False) -> tuple[str, ...]:
    """The readings a spec lists: all of them, or none when only the default ran. The
    "S1-like Krylov" reading is listed only by statements that compare with the standard solvers
    (``krylov``); for the others it equals the default."""
    names = tuple(r for r in m.readings if krylov or r != _KRYLOV_READING)
    return names if len(names) > 1 else ()


def _runs(m: Measurements, readings: tuple[str, ...]) -> dict:
    return {r: m.per_seed[r] for r in (readings or ("default",))}


def _best(s, methods, c):
    return min(s.err[x][c] for x in methods)


def _std(cfg: Config) -> tuple[str, ...]:
    return tuple(x for x in STANDARD if x in cfg.methods)


# ----------------------------------------------------------------------------- claims (S1's)

#: S1's ">10x" statements, one per figure: (case the figure shows, the variant it shows, where,
#: S1's words). Figs 1-2 and 5-6 show the offline ("empirical") variant; Fig. 13 the online one.
_TEN_X = {
    "adaptive-10x-fig2": ("1dof-random", _OFF, "S1 text at Figs 1-2 (1-DOF model, random input)",
                          "With the offline adaptive GMRES the model-error norm is reduced more than 10 times "
                          "(compared with the standard methods of Fig. 2)."),
    "adaptive-10x-fig6": ("1dof-step", _OFF, "S1 text at Figs 5-6 (1-DOF model, step + noise input)",
                          "The error of the other methods rises a lot, while the offline adaptive GMRES reduces "
                          "the model error more than 10 times."),
    "adaptive-10x-fig13": ("3dof-sine", _ON, "S1 text at Fig. 13 (3-DOF model, sinusoidal input)",
                           "The final model-error norm of the online adaptive GMRES, 9-16 % over different "
                           "simulations, is more than 10 times more accurate than the other methods."),
}


def _ten_x(cid: str):
    case, variant, where, statement = _TEN_X[cid]

    def make(cfg: Config, m: Measurements) -> Declared | None:
        std = _std(cfg)
        if not std or variant not in cfg.methods or case not in cfg.cases:
            return None
        names = _readings(m, krylov=True)
        return Declared(ClaimSpec(
            id=cid, statement=statement, where=where,
            quantity=f"per seed: best standard solver's final error ({', '.join(std)}) / {_VARIANT[variant]}'s "
            f"final error, on {case}; > 10",
            value=lambda s: _best(s, std, case) / max(s.err[variant][case], 1e-12),
            threshold=10.0, paper="> 10", readings=names, protocol_keys=_keys((case,), online=variant == _ON),
        ), _runs(m, names))

    make.__name__ = f"_{cid.replace('-', '_')}"
    return make


def _standard_37_195(cfg: Config, m: Measurements) -> Declared | None:
    std = _std(cfg)
    tcases = tuple(c for c in TABLE_CASES if c in cfg.cases)
    if not (std and tcases):
        return None
    names = _readings(m, krylov=True)
    lo, hi = 37.0 - _HALF, 195.0 + _HALF
    return Declared(ClaimSpec(
        id="standard-37-195",
        statement="The standard solvers QR, GMRES, Bi-CG, CGS and Bi-CGSTAB leave 37-195 % model error.",
        where="S1 Table 1, rows 1-5, and the text below it",
        quantity="per seed: every standard solver's final error in [37, 195] % (whole percents as printed: "
        f"[{lo:g}, {hi:g}]) on every Table 1 case ({', '.join(tcases)})",
        held=lambda s: all(lo <= s.err[x][c] <= hi for x in std for c in tcases),
        paper="37-195 %", readings=names, protocol_keys=_keys(tcases),
    ), _runs(m, names))


def _cell(variant: str, case: str):
    """A Table 1 cell of an adaptive row (3dof-sine: the range printed in the text at Fig. 13)."""
    pv = PAPER_TABLE[variant][case]
    lo, hi = pv["min"], pv["max"]
    short = "offline" if variant == _OFF else "online"
    cid = f"{short}-{case}-{lo}-{hi}"
    where = ("S1 text at Fig. 13 (not in Table 1)" if case not in TABLE_CASES
             else f"S1 Table 1, row '{short.capitalize()} Adaptive GMRES', column {case}")

    def make(cfg: Config, m: Measurements) -> Declared | None:
        if variant not in cfg.methods or case not in cfg.cases:
            return None
        names = _readings(m)
        return Declared(ClaimSpec(
            id=cid, statement=f"The {_VARIANT[variant]} leaves {lo}-{hi} % model error on {case} "
            "(the range over S1's different simulations).", where=where,
            quantity=f"per seed: final error in [{lo}, {hi}] % (whole percents as printed: "
            f"[{lo - _HALF:g}, {hi + _HALF:g}])",
            held=lambda s: lo - _HALF <= s.err[variant][case] <= hi + _HALF,
            paper=f"{lo}-{hi} %", readings=names, protocol_keys=_keys((case,), online=variant == _ON),
        ), _runs(m, names))

    make.__name__ = f"_{cid.replace('-', '_')}"
    return make


def _online_most_accurate(cfg: Config, m: Measurements) -> Declared | None:
    paper_ms, cases = tuple(x for x in PAPER_METHODS if x in cfg.methods), cfg.cases
    if _ON not in cfg.methods or len(paper_ms) <= 1:
        return None
    names = _readings(m, krylov=True)
    return Declared(ClaimSpec(
        id="online-most-accurate",
        statement="The online meta-heuristic adaptive GMRES shows the highest accuracy in the estimation.",
        where="S1 abstract; Table 1",
        quantity="per seed: online adaptive GMRES has the smallest final error of S1's seven methods on every case",
        held=lambda s: all(s.err[_ON][c] <= _best(s, paper_ms, c) + 1e-12 for c in cases),
        readings=names, protocol_keys=_keys(cases, online=True),
    ), _runs(m, names))


def _online_beats_offline_1dof(cfg: Config, m: Measurements) -> Declared | None:
    one = tuple(c for c in cfg.cases if c.startswith("1dof"))
    if not one or _ON not in cfg.methods or _OFF not in cfg.methods:
        return None
    names = _readings(m)
    return Declared(ClaimSpec(
        id="online-beats-offline-1dof",
        statement="On the 1-DOF model the online (automatic) adaptive GMRES is more accurate than the offline "
        "(empirical) one.",
        where="S1 text at Figs 3 and 7 and below Table 1",
        quantity=f"per seed: max over {', '.join(one)} of (online final error / offline final error); < 1",
        value=lambda s: max(s.err[_ON][c] / max(s.err[_OFF][c], 1e-12) for c in one),
        threshold=1.0, better="below", paper="< 1", readings=names, protocol_keys=_keys(one, online=True),
    ), _runs(m, names))


def _online_improves_on_a0_fig12(cfg: Config, m: Measurements) -> Declared | None:
    case = "3dof-random"
    if _ON not in cfg.methods or case not in cfg.cases:
        return None
    names = _readings(m)
    return Declared(ClaimSpec(
        id="online-improves-on-a0-fig12",
        statement="The online adaptive GMRES improves the 3-DOF model estimate relative to the initial A0.",
        where="S1 text at Fig. 12 (3-DOF model, random input)",
        quantity="per seed: online adaptive GMRES's final error on 3dof-random below the prior A0's own error "
        "(ending exactly at A0 is no improvement)",
        held=lambda s: s.err[_ON][case] < s.prior[case],
        readings=names, protocol_keys=_keys((case,), online=True),
    ), _runs(m, names))


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
    ), _runs(m, _readings(m)))


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
    ), _runs(m, _readings(m)))


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
    ), _runs(m, _readings(m)))


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
    ), _runs(m, _readings(m)))


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


CLAIMS = (
    *(_ten_x(cid) for cid in _TEN_X),
    _standard_37_195,
    *(_cell(v, c) for v in (_OFF, _ON) for c in PAPER_TABLE[v]),
    _online_most_accurate,
    _online_beats_offline_1dof,
    _online_improves_on_a0_fig12,
)
FINDINGS = (_online_improves_on_prior, _prior_baselines_match_online, _ekf_beats_online,
            _least_squares_identifies_1dof)
CHECKS = (_converged_same_ls, _standard_same_row_as_qr)


#: Decide the declared statements (the framework's :func:`~adcskit.studies._verdict.decide_declared`).
evaluate = decide_declared
