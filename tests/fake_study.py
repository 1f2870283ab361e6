"""A small registered-at-test-time study used to exercise the framework end to end."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from adcskit.studies import (
    Check,
    Comparison,
    Study,
    StudyResult,
    new_figure,
    protocol,
    protocol_keys,
)
from adcskit.studies._verdict import ClaimSpec, FindingSpec


@dataclass(frozen=True, kw_only=True)
class Config:
    n_tasks: int = field(default=8, metadata=protocol("near-zero", "small-spread", paper=8))
    fail: bool = field(default=False, metadata=protocol("finite", paper=False))

    def __post_init__(self) -> None:
        if self.n_tasks < 1:
            raise ValueError(f"n_tasks must be >= 1; got {self.n_tasks}")


NEAR_ZERO = ClaimSpec(
    id="near-zero", statement="the mean is near zero", where="nowhere", quantity="|mean| < 0.2",
    held=lambda m: abs(m["mean"]) < 0.2, protocol_keys=protocol_keys(Config, "near-zero"),
)

#: Our own questions: one depends on the campaign size, one only on whether the study fails.
SMALL_SPREAD = FindingSpec(
    id="small-spread", statement="the task means are within 0.5 of zero", quantity="max |mean| < 0.5",
    value=lambda m: abs(m["mean"]), threshold=0.5, better="below",
    protocol_keys=protocol_keys(Config, "small-spread"),
)
FINITE = FindingSpec(
    id="finite", statement="every task mean is finite", quantity="finite", held=lambda m: np.isfinite(m["mean"]),
    protocol_keys=protocol_keys(Config, "finite"),
)


def draw(seed: np.random.SeedSequence) -> float:
    """One task of a toy campaign: the mean of 1000 normal draws."""
    return float(np.random.default_rng(seed).normal(size=1000).mean())


def run(config: Config, *, quick=False, rng=None, executor=None) -> StudyResult:
    if config.fail:
        raise RuntimeError("fake study asked to fail")
    seeds = np.random.SeedSequence(int(rng.integers(2**32))).spawn(config.n_tasks)
    means = executor.map(draw, seeds, description="fake tasks")
    fig, ax = new_figure()
    ax.plot(means, "o-")
    ax.set_title("fake study")
    m = float(np.mean(means))
    return StudyResult(
        study="fake",
        summary="A fake study for framework tests.",
        paper={"mean": 0.0, "source": "none"},
        measured={"mean": m, "means": means, "nan_value": float("nan")},
        claims=[NEAR_ZERO.evaluate({"default": [{"mean": v} for v in means]})],
        checks=[Check(name="ran", passed=True, detail="", kind="check")],
        findings=[spec.evaluate({"default": [{"mean": v} for v in means]}) for spec in (SMALL_SPREAD, FINITE)],
        comparison=[Comparison(quantity="mean", paper=0.0, measured=m, unit="-", note="toy")],
        differences=["It is fake."],
        figures={"means": fig},
        tables={"means": [{"i": i, "mean": v} for i, v in enumerate(means)]},
    )


STUDY = Study(name="fake", title="Fake study", paper="none", config_cls=Config, run=run, quick={"n_tasks": 3})
