"""Study framework: the :class:`Study` descriptor and the :class:`StudyResult` it returns.

A study reproduces one paper's experiment. Its module defines

* ``Config`` — a frozen keyword-only dataclass whose defaults are the paper's settings;
* ``run(config, *, quick=False, rng=None, executor=None) -> StudyResult``;
* ``STUDY = Study(...)`` — the descriptor the registry loads, with the ``quick`` overrides
  (a reduced but honest run: fewer trials, coarser meshes, never different physics).

The runner (:mod:`adcskit.studies._runner`) resolves the configuration, times the run,
fills ``seed``/``runtime_s``/``quick`` and writes ``result.json``, the figures and CSVs.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from adcskit._results import Result, to_jsonable
from adcskit.errors import InputError
from adcskit.studies._verdict import Claim, Finding

__all__ = ["Check", "Comparison", "NEUTRAL", "NOT_PRINTED", "Study", "StudyResult", "figure_caption", "neutral_keys",
           "new_figure", "paper_protocol", "protocol", "protocol_keys", "to_jsonable"]

#: Field metadata of a config key that only adds evidence or steers the execution
#: (``n_seeds``, a task size, a cache directory): ``field(default=5, metadata=NEUTRAL)``.
NEUTRAL = {"neutral": True}

#: The paper's value of a protocol key when the paper does not print it:
#: ``protocol("claims", paper=NOT_PRINTED)``. Our default is then our reading, never "the paper's".
NOT_PRINTED = "not printed"

_MISSING = object()


def protocol(*tags: str, paper: Any = _MISSING) -> dict[str, Any]:
    """Field metadata of a config key that is part of the paper's protocol for ``tags``.

    A tag names a claim, a finding or a group of them (``"design"``, ``"table1"``);
    :func:`protocol_keys` collects the keys of a tag. ``paper`` is the value the paper prints
    for this key (in the config's units), or :data:`NOT_PRINTED`; the runner marks a claim
    "reduced protocol" when a key of its protocol differs from a printed value. Use as
    ``field(default=0.2, metadata=protocol("accuracy", "sweep", paper=0.2))``.

    Examples
    --------
    >>> protocol("accuracy", "sweep", paper=0.2)
    {'protocol': ('accuracy', 'sweep'), 'paper': 0.2}
    >>> protocol("accuracy", paper=NOT_PRINTED)["paper"]
    'not printed'
    """
    bad = [t for t in tags if not isinstance(t, str) or not t]
    if not tags or bad:
        raise InputError(f"protocol tags must be non-empty strings; got {tags!r}")
    if paper is _MISSING:
        return {"protocol": tuple(tags)}
    return {"protocol": tuple(tags), "paper": paper}


def paper_protocol(config_cls: Any) -> dict[str, Any]:
    """The paper's value of each protocol key that declares one (``protocol(..., paper=...)``).

    Values are the paper's printed value or :data:`NOT_PRINTED`; keys that declare nothing are
    absent (``tests/studies/test_package_shapes.py`` requires every study to declare all).

    Examples
    --------
    >>> from dataclasses import dataclass, field
    >>> @dataclass(frozen=True)
    ... class Config:
    ...     n_seeds: int = field(default=5, metadata=NEUTRAL)
    ...     n_gen: int = field(default=30, metadata=protocol("robust", paper=1000))
    ...     pop: int = field(default=70, metadata=protocol("robust", paper=NOT_PRINTED))
    >>> paper_protocol(Config)
    {'n_gen': 1000, 'pop': 'not printed'}
    """
    return {f.name: f.metadata["paper"] for f in _config_fields(config_cls) if "paper" in f.metadata}


def _config_fields(config_cls: Any) -> tuple:
    from dataclasses import fields, is_dataclass

    if not is_dataclass(config_cls):
        raise InputError(f"config_cls must be a config dataclass; got {config_cls!r}")
    return fields(config_cls)


def neutral_keys(config_cls: Any) -> tuple[str, ...]:
    """The config keys declared neutral (``metadata=NEUTRAL``), in field order.

    A change of a neutral key is recorded in ``config_changes`` but does not by itself make a
    claim or finding "not comparable".

    Examples
    --------
    >>> from dataclasses import dataclass, field
    >>> @dataclass(frozen=True)
    ... class Config:
    ...     n_seeds: int = field(default=5, metadata=NEUTRAL)
    ...     noise_bound: float = field(default=0.2, metadata=protocol("accuracy"))
    >>> neutral_keys(Config)
    ('n_seeds',)
    """
    return tuple(f.name for f in _config_fields(config_cls) if f.metadata.get("neutral", False))


def protocol_keys(config_cls: Any, *tags: str) -> tuple[str, ...]:
    """The config keys that define the paper's protocol for any of ``tags``, in field order.

    Without tags: every key that is not neutral. A tag that no field declares is an error (a
    typo would otherwise make a claim comparable under any change).

    Examples
    --------
    >>> from dataclasses import dataclass, field
    >>> @dataclass(frozen=True)
    ... class Config:
    ...     n_seeds: int = field(default=5, metadata=NEUTRAL)
    ...     n_trials: int = field(default=100, metadata=protocol("accuracy"))
    ...     noise_bound: float = field(default=0.2, metadata=protocol("accuracy", "sweep"))
    >>> protocol_keys(Config, "sweep"), protocol_keys(Config)
    (('noise_bound',), ('n_trials', 'noise_bound'))
    """
    fs = _config_fields(config_cls)
    if not tags:
        return tuple(f.name for f in fs if not f.metadata.get("neutral", False))
    declared = {t for f in fs for t in f.metadata.get("protocol", ())}
    unknown = [t for t in tags if t not in declared]
    if unknown:
        raise InputError(f"protocol tags {unknown} are declared by no field of {config_cls.__qualname__}; "
                         f"declared: {sorted(declared)}")
    return tuple(f.name for f in fs if set(f.metadata.get("protocol", ())) & set(tags))



@dataclass(frozen=True, slots=True, kw_only=True)
class Check(Result):
    """A consistency check of ours (pass / fail).

    The paper's claims are :class:`adcskit.studies._verdict.Claim` objects, decided over
    seeds and readings; a check is never a claim.

    Attributes
    ----------
    name : str
        The claim in the paper's words, or what the check verifies.
    passed : bool
        The check passed.
    detail : str
        The evidence: numbers, with units, and how they were obtained.
    kind : {"check"}
        Always ``"check"`` (kept in ``result.json`` for readers of older files).

    Examples
    --------
    >>> Check(name="quaternions are unit", passed=True, detail="max |q| - 1 = 2e-16").to_dict()["passed"]
    True
    """

    name: str
    passed: bool
    detail: str
    kind: str = "check"

    def __post_init__(self) -> None:
        if self.kind != "check":
            raise InputError(f"Check.kind must be 'check' (a paper's claim is a ClaimSpec); got {self.kind!r}")
        object.__setattr__(self, "passed", bool(self.passed))


@dataclass(frozen=True, slots=True, kw_only=True)
class Comparison(Result):
    """One row of the paper-vs-ours table shown in the report.

    Examples
    --------
    >>> Comparison(quantity="RMS error", paper=2.2, measured=2.15, unit="deg").to_dict()["measured"]
    2.15
    """

    quantity: str
    paper: Any
    measured: Any
    unit: str = ""
    note: str = ""


@dataclass(frozen=True, slots=True, kw_only=True)
class StudyResult:
    """Everything a study run produced.

    ``figures`` maps a file stem to a :class:`matplotlib.figure.Figure`; ``tables`` maps a
    file stem to a list of row mappings (one CSV each). Both are written by the runner and
    only their names go into ``result.json``.

    Examples
    --------
    >>> r = StudyResult(study="demo", summary="nothing measured")
    >>> sorted(k for k in r.to_dict() if k in ("claims", "checks", "findings"))
    ['checks', 'claims', 'findings']
    """

    study: str
    title: str = ""
    summary: str = ""
    config: Mapping[str, Any] = field(default_factory=dict)
    paper: Mapping[str, Any] = field(default_factory=dict)
    measured: Mapping[str, Any] = field(default_factory=dict)
    checks: Sequence[Check] = ()
    claims: Sequence[Claim] = ()
    findings: Sequence[Finding] = ()
    config_changes: Mapping[str, Any] = field(default_factory=dict)
    protocol_differences: Mapping[str, Any] = field(default_factory=dict)
    comparison: Sequence[Comparison] = ()
    differences: Sequence[str] = ()
    figures: Mapping[str, Any] = field(default_factory=dict)
    captions: Mapping[str, str] = field(default_factory=dict)
    tables: Mapping[str, Sequence[Mapping[str, Any]]] = field(default_factory=dict)
    doc: str = ""
    seed: int | None = None
    quick: bool = False
    runtime_s: float = math.nan
    executor: str = "serial"

    def all_claims(self) -> list[Claim]:
        """The paper's claims (a list copy of :attr:`claims`)."""
        return list(self.claims)

    def to_dict(self) -> dict[str, Any]:
        """The ``result.json`` document (schema in ``docs/architecture.md``, "Results and the result store")."""
        from adcskit import __version__

        return {
            "study": self.study,
            "title": self.title,
            "summary": self.summary,
            "adcskit_version": __version__,
            "config": to_jsonable(self.config),
            "seed": self.seed,
            "quick": bool(self.quick),
            "runtime_s": to_jsonable(self.runtime_s),
            "executor": self.executor,
            "paper": to_jsonable(self.paper),
            "measured": to_jsonable(self.measured),
            "claims": [c.to_dict() for c in self.all_claims()],
            "checks": [c.to_dict() for c in self.checks],
            "findings": [f.to_dict() for f in self.findings],
            "config_changes": to_jsonable(self.config_changes),
            "protocol_differences": to_jsonable(self.protocol_differences),
            "comparison": [c.to_dict() for c in self.comparison],
            "differences": list(self.differences),
            "figures": [f"{name}.png" for name in self.figures],
            "figure_captions": {f"{name}.png": self.captions.get(name) or figure_caption(fig, name) for name, fig in self.figures.items()},
            "tables": [f"{name}.csv" for name in self.tables],
            "doc": self.doc,
        }


@dataclass(frozen=True, slots=True, kw_only=True)
class Study:
    """Registry entry of one study.

    Attributes
    ----------
    name : str
        CLI name, e.g. ``"wahba-table1"``.
    title : str
        One line for ``adcskit list`` and the report.
    paper : str
        Source paper id (``"S0"`` .. ``"S4"``) and short citation.
    config_cls : type
        The study's frozen config dataclass; its defaults are the paper's settings.
    run : callable
        ``run(config, *, quick=False, rng=None, executor=None) -> StudyResult``.
    quick : mapping
        Config overrides for ``--quick``.
    doc : str
        Path of the study's documentation page in the repository.
    resolve : callable or None
        ``resolve(config, seed) -> config``: settings decided before the run from its root seed
        and stored data (onoff-tuning: S4's protocol when every paper-scale GA is stored); the
        runner records and marks the protocol of the config it returns.

    Notes
    -----
    The config keys that only add evidence or steer the execution are declared on
    ``config_cls``'s fields (``metadata=NEUTRAL``) and read by :attr:`neutral_keys`.

    Examples
    --------
    >>> from adcskit.studies import get_study
    >>> s = get_study("wahba-table1")
    >>> s.name, s.config_cls.__name__
    ('wahba-table1', 'Config')
    """

    name: str
    title: str
    paper: str
    config_cls: type
    run: Callable[..., StudyResult]
    quick: Mapping[str, Any] = field(default_factory=dict)
    doc: str = ""
    resolve: Callable[[Any, int], Any] | None = None

    @property
    def neutral_keys(self) -> tuple[str, ...]:
        """The config keys declared neutral on :attr:`config_cls` (see :func:`neutral_keys`)."""
        return neutral_keys(self.config_cls)


def figure_caption(fig: Any, name: str = "") -> str:
    """A caption for a figure: its suptitle, else its axes' titles, else its name in words."""
    sup = getattr(fig, "_suptitle", None)
    if sup is not None and sup.get_text().strip():
        return sup.get_text().strip()
    titles = [ax.get_title().strip() for ax in getattr(fig, "axes", []) if ax.get_title().strip()]
    if titles:
        return "; ".join(dict.fromkeys(titles))
    return name.replace("-", " ").replace("_", " ")


def new_figure(nrows: int = 1, ncols: int = 1, *, figsize: tuple[float, float] = (6.4, 4.0), **kw: Any):
    """A matplotlib Figure and its axes, without pyplot's global state (Agg, thread-safe).

    Returns ``(fig, axes)`` like :func:`matplotlib.pyplot.subplots`.

    Examples
    --------
    >>> fig, ax = new_figure()
    >>> _ = ax.plot([0, 1], [0, 1]); _ = ax.set_xlabel("time (s)")
    >>> type(fig).__name__
    'Figure'
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    axes = fig.subplots(nrows, ncols, **kw)
    return fig, axes
