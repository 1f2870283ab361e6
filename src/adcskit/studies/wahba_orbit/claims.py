"""The ``wahba-orbit`` study's claim (S0's), findings (ours) and checks, as declarations.

:data:`CLAIMS`, :data:`FINDINGS` and :data:`CHECKS` list one small factory per group of
statements, in report order, as in ``thruster_layout.claims``. Each takes the config and the
:class:`~.experiment.Measurements` and returns a list of

* :class:`Declared` — the framework's :class:`ClaimSpec` / :class:`FindingSpec` and its per-seed
  runs keyed by reading — that :func:`evaluate` hands to :meth:`ClaimSpec.evaluate` (the
  framework decides the outcome), or
* :class:`~adcskit.studies.Check` (computed).

A factory returns a list (possibly empty) because the findings are one per configured case
and solver. S0's one claim is module data (:data:`CLAIM`); its readings are the configured
weightings. Protocol keys are declared on :class:`~.config.Config`'s fields (tags ``claim``,
``finding``, ``nsga2``); :data:`CLAIM_KEYS`, :data:`FINDING_KEYS` and :data:`NSGA2_KEYS` are read
from them.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from adcskit.studies._base import Check, protocol_keys
from adcskit.studies._verdict import ClaimSpec, Declared, FindingSpec, decide_declared
from adcskit.studies.wahba_orbit.config import Config
from adcskit.studies.wahba_orbit.experiment import Measurements

__all__ = ["CHECKS", "CLAIM", "CLAIMS", "CLAIM_KEYS", "FINDINGS", "FINDING_KEYS", "NSGA2_KEYS", "Declared",
           "evaluate"]

#: Config keys S0's protocol fixes for its claim.
CLAIM_KEYS = protocol_keys(Config, "claim")
#: Keys that define the scenario of our findings (the doc page's answers); ``n_seeds`` only adds
#: evidence and ``cases`` only selects which findings run, so neither makes one not comparable.
FINDING_KEYS = protocol_keys(Config, "finding")
#: Keys that also fix the NSGA-II findings.
NSGA2_KEYS = protocol_keys(Config, "nsga2")


@dataclass(frozen=True, slots=True)
class _Value:
    """One seed's deciding quantity (a reduction or a ratio)."""

    value: float


#: S0's claim (abstract; §4-2, Fig. 4), decided on the paper's case, readings = weightings.
CLAIM = ClaimSpec(
    id="rms-50pct",
    statement="Based on the results, the proposed method has narrower bounds, so that the mean square "
    "error (RMS) is decreased by more than 50% over the q-method.",
    where="S0 abstract; §4-2, Fig. 4",
    quantity="1 − RMS δθ(min-max) / RMS δθ(q-method) over the 20-min pass, paper's case (dipole field "
    "for truth and reference); > 0.5",
    value=lambda r: r.value, threshold=0.5, paper="> 50 %", unit="fraction",
    protocol_keys=CLAIM_KEYS,
)


def _rms_50pct(cfg: Config, m: Measurements) -> list[Declared]:
    runs = {w: [_Value(o.reduction("minmax")) for o in m.by[(m.paper_case, w)]] for w in m.weightings}
    if len(m.weightings) > 1:
        return [Declared(replace(CLAIM, readings=m.weightings), runs, cfg.weighting)]
    return [Declared(CLAIM, {"default": runs[cfg.weighting]})]


def _solver_variants(cfg: Config, m: Measurements) -> list[Declared]:
    """Every robust solver on every case (default weighting), except the claim's own pair."""
    out = []
    for case in cfg.cases:
        for meth in ("minmax", "worst-case", "nsga2-knee"):
            if case == m.paper_case and meth == "minmax":
                continue  # that is the claim
            spec = FindingSpec(
                id=f"rms-50pct[{case}][{meth}]",
                statement=f"{meth} has > 50 % lower RMS attitude error than the q-method ({case} field, "
                f"{cfg.weighting} weights).",
                quantity="1 − RMS(" + meth + ") / RMS(q-method)" + (
                    f" on the NSGA-II samples (every {cfg.nsga2_every}th)" if meth == "nsga2-knee" else "")
                + "; > 0.5",
                value=lambda r: r.value, threshold=0.5, unit="fraction",
                protocol_keys=protocol_keys(Config, "finding", *(("nsga2",) if meth == "nsga2-knee" else ())),
            )
            out.append(Declared(spec, {"default": [_Value(o.reduction(meth)) for o in m.by[(case, cfg.weighting)]]}))
    return out


def _dipole_reference_model_error(cfg: Config, m: Measurements) -> list[Declared]:
    if not ("igrf/dipole" in cfg.cases and "igrf/igrf" in cfg.cases):
        return []
    spec = FindingSpec(
        id="dipole-reference-model-error",
        statement="A dipole reference for an IGRF world costs more than any estimator gains: the "
        "q-method RMS with the dipole reference is > 2x the RMS with IGRF as reference.",
        quantity="RMS q-method (igrf/dipole) / RMS q-method (igrf/igrf), same seed; > 2",
        value=lambda r: r.value, threshold=2.0, protocol_keys=FINDING_KEYS,
    )
    ratios = [_Value(a.rms["q-method"] / b.rms["q-method"])
              for a, b in zip(m.by[("igrf/dipole", cfg.weighting)], m.by[("igrf/igrf", cfg.weighting)])]
    return [Declared(spec, {"default": ratios})]


def _q_method_bounded(cfg: Config, m: Measurements) -> list[Check]:
    worst = max(o.max_deg["q-method"] for o in m.by[(m.paper_case, cfg.weighting)])
    return [Check(
        name="q-method error bounded by the sensor error bounds (max < 10x the magnetometer bound)",
        passed=bool(worst < 10 * cfg.mag_bound_deg),
        detail=f"max δθ q-method over {cfg.n_seeds} seeds {worst:.3f} deg with ±{cfg.mag_bound_deg} deg magnetometer",
        kind="check",
    )]


#: S0's claim.
CLAIMS = (_rms_50pct,)
#: Our questions: the other solvers and field-model cases, and the dipole reference's model error.
FINDINGS = (_solver_variants, _dipole_reference_model_error)
#: Our consistency checks.
CHECKS = (_q_method_bounded,)


#: Decide the declared statements (the framework's :func:`~adcskit.studies._verdict.decide_declared`).
evaluate = decide_declared
