"""The ``wahba-table1`` study's claims (S0's), findings (ours) and checks, as declarations.

:data:`CLAIMS` and :data:`FINDINGS` are the framework's :class:`ClaimSpec` / :class:`FindingSpec`
data, each reading one :class:`~.experiment.Replica` per seed; :func:`evaluate` hands them to
:meth:`ClaimSpec.evaluate`, which decides the outcome. A claim with readings reads the
:class:`~.experiment.Replica` field that :data:`READING_FIELDS` names for each reading.
:data:`CHECKS` are small factories ``(config, measurements) -> Check``, decided in order by the
framework's ``decide_declared`` (the checks' declaration in every study). "Holds" for a claim means the measured factor reaches at
least half the paper's factor.

Examples
--------
>>> from adcskit.studies.wahba_table1.claims import CHECKS, CLAIMS, FINDINGS
>>> [c.id for c in CLAIMS], len(FINDINGS), len(CHECKS)
(['error-7x', 'nsga2-error', 'sensitivity-200x', 'speed-600x'], 5, 4)
"""

from __future__ import annotations

from collections.abc import Sequence

from adcskit.studies._base import Check, protocol_keys
from adcskit.studies._verdict import Claim, ClaimSpec, Finding, FindingSpec
from adcskit.studies.wahba_table1.config import Config
from adcskit.studies.wahba_table1.experiment import Measurements
from adcskit.studies.wahba_table1.paper import PAPER_TABLE1, paper_ratio

__all__ = ["CHECKS", "CLAIMS", "FINDINGS", "READING_FIELDS", "evaluate"]

#: Per reading of a claim, the :class:`~.experiment.Replica` field that is its deciding value.
READING_FIELDS = {"variance ratio": "var_ratio", "slope ratio": "slope_ratio"}

#: S0's claims, in report order. "Holds" means the measured factor reaches at least half the paper's factor.
CLAIMS = (
    ClaimSpec(
        id="error-7x",
        statement="The attitude determination error with the proposed method is reduced (7 times) "
        "compared to the quaternion method.",
        where="S0 abstract; Table 1 (15.1352 vs 2.2025 deg)",
        quantity="mean δθ q-method / mean δθ min-max over one replica's trials (>= 3.5: half the claimed factor)",
        value=lambda m: m.err_ratio, threshold=3.5, paper=round(paper_ratio("q-method", "minmax", "mean_deg"), 3),
        protocol_keys=protocol_keys(Config, "error-7x"),
    ),
    ClaimSpec(
        id="nsga2-error",
        statement="Proposed method solved with NSGA-II: mean attitude error 0.5699 deg, variance 0.1915 deg².",
        where="S0 Table 1, NSGA-II row (26.6x below the q-method row)",
        quantity="mean δθ q-method / mean δθ NSGA-II with the paper's pick (Pareto point nearest the TRUE "
        "attitude) on the same trials (>= 13: half the table's factor)",
        value=lambda m: m.nsga_truth_ratio, threshold=13.0,
        paper=round(paper_ratio("q-method", "nsga2-truth-pick", "mean_deg"), 3),
        protocol_keys=protocol_keys(Config, "nsga2-error"),
    ),
    ClaimSpec(
        id="sensitivity-200x",
        statement="Its dependence on the accuracy of the input vectors is reduced (200 times).",
        where="S0 abstract; Table 1 variances (95.1604 vs 0.4409 deg² = 216x)",
        quantity="q-method / min-max: variance of δθ at the Table 1 noise (variance reading) or slope of "
        "mean δθ vs noise bound over the sweep (slope reading); >= 100 (half the claimed factor)",
        value=float, threshold=100.0, paper=round(paper_ratio("q-method", "minmax", "var_deg2"), 1),
        readings=("variance ratio", "slope ratio"),
        protocol_keys=protocol_keys(Config, "sensitivity-200x"),
    ),
    ClaimSpec(
        id="speed-600x",
        statement="Using the min-max algorithm has reduced the execution time of the algorithm (about 600 "
        "times) compared to the NSGA II algorithm.",
        where="S0 abstract; Table 1 run times (124.58 s / 0.287 s = 434x, not 600x)",
        quantity="median run time per epoch: NSGA-II / iterative min-max (SLSQP goal attainment on "
        "(q, α, β, γ) from TRIAD, the paper's kind of solver), same trials and machine; >= 300 (half of 600)",
        value=lambda m: m.speed_ratio, threshold=300.0,
        paper=round(paper_ratio("nsga2-truth-pick", "minmax", "runtime_s"), 1),
        protocol_keys=protocol_keys(Config, "speed-600x"),
    ),
)

#: Our findings, in report order.
FINDINGS = (
    FindingSpec(
        id="speed-closed-form",
        statement="Our exact (closed-form + KKT) min-max is >= 300x faster than NSGA-II. Reported beside "
        "the claim; it does not decide it (a closed form against the paper's iterative solver is not like for like).",
        quantity="median run time NSGA-II / closed-form min-max",
        value=lambda m: m.speed_ratio_closed_form, threshold=300.0,
    ),
    FindingSpec(
        id="qmethod-in-box-minority",
        statement="The unconstrained q-method attitude lies inside the ±search-range TRIAD box in only a "
        "minority of trials, so the min-max optimum (the q-method optimum restricted to the box) is "
        "usually on the box boundary.",
        quantity="fraction of trials with the q-method attitude inside the box (< 0.5)",
        value=lambda m: m.frac_in_box, threshold=0.5, better="below",
    ),
    FindingSpec(
        id="box-at-truth-consistent",
        statement="Consistent with the paper's min-max row coming from a search box centred on the "
        "noise-free attitude: that (non-deployable) box gives a mean error closer to 2.2025 deg than "
        "the deployable box around TRIAD of the measured vectors.",
        quantity="|mean δθ box-at-truth − 2.2025| < |mean δθ min-max − 2.2025|",
        held=lambda m: m.box_truth_closer,
    ),
    FindingSpec(
        id="knee-beats-qmethod",
        statement="NSGA-II with a truth-free (knee) pick is more accurate than the q-method.",
        quantity="mean δθ q-method / mean δθ NSGA-II knee pick, same trials (> 1)",
        value=lambda m: m.nsga_knee_ratio, threshold=1.0,
    ),
    FindingSpec(
        id="worst-case-beats-qmethod",
        statement="The worst-case robust estimator (Ahmed & Kerrigan) is more accurate than the q-method.",
        quantity="mean δθ q-method / mean δθ worst-case (> 1)",
        value=lambda m: m.worst_case_ratio, threshold=1.0,
    ),
)


# ----------------------------------------------------------------------------- checks (ours)


def _exact_vectors(cfg: Config, m: Measurements) -> Check:
    ex_err = m.exact.qmethod_vs_qexact_deg
    return Check(
        name="q-method on the exact eq. 9 vectors returns q_exact (scalar-first reading)",
        passed=ex_err < 0.1,
        detail=f"δθ = {ex_err:.4f} deg (4-digit printed quaternion: < 0.1 deg expected)",
        kind="check",
    )


def _sanity_rows(cfg: Config, m: Measurements) -> Check:
    st, qm = m.stats, m.stats["q-method"]
    return Check(
        name="QUEST and SVD rows equal the q-method row",
        passed=abs(st["quest"].mean_deg - qm.mean_deg) < 1e-6 and abs(st["svd"].mean_deg - qm.mean_deg) < 1e-6,
        detail=f"means {st['quest'].mean_deg:.9f}, {st['svd'].mean_deg:.9f}, {qm.mean_deg:.9f} deg",
        kind="check",
    )


def _minmax_solvers_agree(cfg: Config, m: Measurements) -> Check:
    cf_slsqp = m.cf_vs_slsqp_max_deg
    return Check(
        name="the exact and the iterative (SLSQP) min-max solvers return the same attitude",
        passed=cf_slsqp < 1e-2,
        detail=f"largest angle between them over {cfg.n_seeds} x {cfg.n_iterative} trials: "
        f"{cf_slsqp:.2e} deg (pass if < 0.01 deg)",
        kind="check",
    )


def _noise_model(cfg: Config, m: Measurements) -> Check:
    qm, paper = m.stats["q-method"], PAPER_TABLE1["q-method"]["mean_deg"]
    return Check(
        name="the noise model reproduces the paper's q-method row (mean within ±30 %)",
        passed=0.7 * paper < qm.mean_deg < 1.3 * paper,
        detail=f"q-method mean δθ {qm.mean_deg:.3f} deg over {len(m.pooled)} trials; paper 15.1352 deg",
        kind="check",
    )


#: Our consistency checks, in report order.
CHECKS = (_exact_vectors, _sanity_rows, _minmax_solvers_agree, _noise_model)


def evaluate(specs: Sequence[ClaimSpec], m: Measurements) -> list[Claim | Finding]:
    """Decide each claim or finding over the replicas, by the framework's :meth:`ClaimSpec.evaluate`.

    A spec without readings reads the :class:`~.experiment.Replica` records; one with readings
    reads, per reading, the replica field :data:`READING_FIELDS` names (its first reading is the
    default).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> reps = [SimpleNamespace(err_ratio=1.1), SimpleNamespace(err_ratio=0.9)]
    >>> evaluate(CLAIMS[:1], SimpleNamespace(replicas=reps))[0].outcome
    'does not hold'
    """
    out = []
    for spec in specs:
        if spec.readings:
            runs = {rd: [getattr(rep, READING_FIELDS[rd]) for rep in m.replicas] for rd in spec.readings}
            out.append(spec.evaluate(runs, default=spec.readings[0]))
        else:
            out.append(spec.evaluate({"default": m.replicas}))
    return out
