"""Settings of the rendezvous study (S2): the paper's protocol as defaults.

References
----------
S2 Sec. 6 (20 sub-intervals x 3 LG points) and Table 4 (initial positions).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from adcskit.studies._base import NOT_PRINTED, protocol
from adcskit.studies.rendezvous.paper import PAPER_ROWS, READING_NAMES

__all__ = ["Config"]


@dataclass(frozen=True, kw_only=True)
class Config:
    """Settings of the rendezvous study (defaults: S2 §6 and Table 4).

    The protocol keys declare what S2 prints (``protocol(..., paper=...)``): the five initial
    positions of Table 4, the Gauss method and the 20 × 3 mesh (§6); S2 prints neither a
    multistart (``n_starts``) nor our readings of its dynamics (``readings``). The tolerance of
    a printed ``tf`` is not a setting: it is half a unit of the last printed digit, with the
    solver repeatability measured in the run as the claims' equivalence margin
    (:mod:`.claims`).

    Attributes
    ----------
    rows_m : tuple of (3,) tuples, m
        Initial relative positions in LVLH (m), S2 Table 4.
    readings : tuple of {"paper", "full"}
        Readings of the rotational dynamics, the default first: eq. 2 as printed, or the
        exact relative dynamics (eq. 1 without dropping ``I·D^L[ω_LI]``). The first reading
        runs the multistart; the others continue its branches.
    method : {"gauss", "radau"}
    paper_mesh : (int, int)
        Sub-intervals × LG points of the paper, ``(20, 3)``.
    adaptive_tol : float
        Relative state error every mesh interval must meet
        (:func:`adcskit.optimal_control.estimate_error`: collocation polynomial vs an
        integration of the dynamics under the interpolated control, per state divided by
        ``1 + max |x|``); the tolerance of the error-controlled refinement of every branch.
    adaptive_max_iterations : int
        Most NLP solves of one branch's refinement (the 20×3 re-solve counts). A branch that
        does not reach ``adaptive_tol`` is reported with its achieved error ("not met").
    other_readings_start : {"paper_mesh", "refined_mesh"}
        Where the refinement of a continued branch (readings after the first) starts:
        ``"paper_mesh"`` from its own 20×3 optimum, exactly as the first reading;
        ``"refined_mesh"`` on the first reading's final mesh of the branch, warm-started (primal
        and dual) from the first reading's refined solution: the two dynamics differ by
        O(|ω| n) terms, so that mesh usually already meets the tolerance and one or two solves
        certify it. Either way the certificate is computed with this reading's dynamics and
        the branch-jump test measures ``tf`` from this reading's own 20×3 optimum.
    jump_factor : float
        A refinement whose ``tf`` moves by more than ``jump_factor × adaptive_tol`` (relative)
        from its 20×3 start is a branch jump; two converged values closer than that are the
        same branch.
    n_starts : int
        Starts per row on the paper mesh (start 0 is the straight-line guess, the rest random).
    distinct_rtol : float
        Two 20×3 optima closer than this (relative) are the same.

    """

    # S2 Table 4: the five initial positions
    rows_m: tuple[tuple[float, float, float], ...] = field(
        default=tuple(r[0] for r in PAPER_ROWS), metadata=protocol("claims", paper=tuple(r[0] for r in PAPER_ROWS))
    )
    # S2 prints eq. 2 only; running it beside the full dynamics is our reading of an ambiguity
    readings: tuple[str, ...] = field(default=("paper", "full"), metadata=protocol("claims", paper=NOT_PRINTED))
    # S2 §4-6: the Gauss pseudospectral method on 20 equal sub-intervals x 3 LG points
    method: str = field(default="gauss", metadata=protocol("claims", paper="gauss"))
    paper_mesh: tuple[int, int] = field(default=(20, 3), metadata=protocol("claims", paper=(20, 3)))
    adaptive_tol: float = 1e-3
    adaptive_max_iterations: int = 7
    other_readings_start: str = "refined_mesh"
    jump_factor: float = 1.0
    n_starts: int = field(default=16, metadata=protocol("multistart", paper=NOT_PRINTED))  # S2: one solve per row
    distinct_rtol: float = 1e-4

    def __post_init__(self) -> None:
        if not self.rows_m:
            raise ValueError(f"rows_m must list at least one initial position (m); got {self.rows_m!r}")
        for r in self.rows_m:
            if len(r) != 3 or not all(math.isfinite(float(v)) for v in r):
                raise ValueError(f"each row must be 3 finite numbers (m); got {r!r}")
        if (
            not self.readings
            or any(r not in READING_NAMES for r in self.readings)
            or len(set(self.readings)) != len(self.readings)
        ):
            raise ValueError(
                f"readings must be distinct values of {sorted(READING_NAMES)}; got {self.readings!r}"
            )
        if self.method not in ("gauss", "radau"):
            raise ValueError(f"method must be 'gauss' or 'radau'; got {self.method!r}")
        if self.n_starts < 1:
            raise ValueError(f"n_starts must be >= 1; got {self.n_starts}")
        m = self.paper_mesh
        if len(m) != 2 or min(m) < 1:
            raise ValueError(f"paper_mesh must be (n_intervals >= 1, n_nodes >= 1); got {m!r}")
        if self.other_readings_start not in ("paper_mesh", "refined_mesh"):
            raise ValueError(
                f"other_readings_start must be 'paper_mesh' or 'refined_mesh'; got {self.other_readings_start!r}"
            )
        if self.adaptive_max_iterations < 1:
            raise ValueError(f"adaptive_max_iterations must be >= 1; got {self.adaptive_max_iterations}")
        for name in ("adaptive_tol", "distinct_rtol"):
            if not 0 < getattr(self, name) < 1:
                raise ValueError(f"{name} must be in (0, 1); got {getattr(self, name)}")
        if not self.jump_factor >= 1:
            raise ValueError(f"jump_factor must be >= 1; got {self.jump_factor}")
        if not self.same_rtol < 1:
            raise ValueError(
                f"jump_factor x adaptive_tol must be < 1; got {self.jump_factor} x {self.adaptive_tol}"
            )

    @property
    def same_rtol(self) -> float:
        """``jump_factor × adaptive_tol``: the relative ``tf`` distance of a branch jump, and
        within which two converged values are the same branch."""
        return self.jump_factor * self.adaptive_tol
