"""The ``wahba-table1`` study's settings: S0 §4-1 defaults and our repetitions and noise sweep.

Examples
--------
>>> from adcskit.studies.wahba_table1.config import Config
>>> Config().n_trials, Config().noise_bound
(100, 0.2)
"""

from __future__ import annotations

from dataclasses import dataclass, field

from adcskit.studies._base import NEUTRAL, NOT_PRINTED, protocol

__all__ = ["Config"]


@dataclass(frozen=True, kw_only=True)
class Config:
    """Settings of S0 §4-1 (defaults) and of our repetitions and noise sweep.

    Attributes
    ----------
    n_seeds : int
        Independent replicas of the whole experiment (noise draws and optimiser seeds); each
        claim is decided over them (>= 5 at full settings).
    n_trials : int
        Perturbed trials per replica (S0: 100).
    n_iterative : int
        Trials per replica on which the iterative rows (SLSQP min-max, NSGA-II) also run.
    noise_bound : float
        Uniform noise bound as a fraction of each component (S0: 0.2).
    search_range : float
        Min-max / NSGA-II search box around TRIAD, fraction of each component (S0: 0.1).
    pop_size, n_gen : int
        NSGA-II population and generations (not printed in S0; ours: 100 x 100 = 1e4
        evaluations per epoch).
    nsga2_big_n_gen : int
        Generations of the big-budget NSGA-II reading of ``speed-600x`` (population
        ``pop_size``; default 1500: 1.5e5 evaluations per epoch, 15x ours: about what S0's
        124.58 s per epoch would buy on our machine). Timed only, on ``n_big_epochs`` epochs.
    timing_epochs : int
        Epochs per replica timed for ``speed-600x`` (the first ones of the iterative trials): each
        compared method solves each of them ``timing_repeats`` times, interleaved, single-threaded.
    n_big_epochs : int
        Of the timed epochs, those (the first ones) on which the big-budget NSGA-II also runs.
    timing_repeats : int
        Repeats of the same solve per method and timed epoch; the epoch's time is their median
        (>= 5 at full settings).

    sweep_bounds : tuple of float
        Noise bounds of the sensitivity sweep (slope reading).
    sweep_trials : int
        Trials per sweep point and replica.

    Every protocol key declares S0's printed value (``paper=``) or ``NOT_PRINTED``: S0 prints 100
    trials, ±20 % noise and a ±10 % search range (§4-1, Table 1), and runs NSGA-II on all 100
    trials; it prints no NSGA-II population or generations and no noise sweep.
    """

    n_seeds: int = field(default=5, metadata=NEUTRAL)
    n_trials: int = field(default=100, metadata=protocol("error-7x", "sensitivity-200x", paper=100))
    n_iterative: int = field(default=20, metadata=protocol("nsga2-error", "nsga2-beats-minmax", "nsga2-variance",
                                                             paper=100))
    noise_bound: float = field(default=0.2, metadata=protocol("error-7x", "nsga2-error", "sensitivity-200x",
                                                              "nsga2-beats-minmax", "nsga2-variance", paper=0.2))
    search_range: float = field(default=0.1, metadata=protocol("error-7x", "nsga2-error", "sensitivity-200x",
                                                               "speed-600x", "nsga2-beats-minmax", "nsga2-variance",
                                                               paper=0.1))
    pop_size: int = field(default=100, metadata=protocol("nsga2-error", "speed-600x", "nsga2-beats-minmax",
                                                         "nsga2-variance", paper=NOT_PRINTED))
    n_gen: int = field(default=100, metadata=protocol("nsga2-error", "speed-600x", "nsga2-beats-minmax",
                                                      "nsga2-variance", paper=NOT_PRINTED))
    nsga2_big_n_gen: int = field(default=1500, metadata=protocol("speed-600x", paper=NOT_PRINTED))
    timing_epochs: int = field(default=3, metadata=protocol("speed-600x", paper=NOT_PRINTED))
    n_big_epochs: int = field(default=1, metadata=protocol("speed-600x", paper=NOT_PRINTED))
    timing_repeats: int = field(default=5, metadata=protocol("speed-600x", paper=NOT_PRINTED))
    sweep_bounds: tuple[float, ...] = field(default=(0.01, 0.02, 0.05, 0.1, 0.2, 0.3),
                                            metadata=protocol("sensitivity-200x", paper=NOT_PRINTED))
    sweep_trials: int = field(default=30, metadata=protocol("sensitivity-200x", paper=NOT_PRINTED))

    def __post_init__(self) -> None:
        from adcskit.errors import ConfigError

        for name, lo in (("n_seeds", 1), ("n_trials", 2), ("sweep_trials", 2), ("n_iterative", 3),
                         ("timing_epochs", 1), ("n_big_epochs", 1), ("timing_repeats", 1), ("nsga2_big_n_gen", 4)):
            v = getattr(self, name)
            if not (isinstance(v, int) and v >= lo):
                raise ConfigError(f"{name} must be an integer >= {lo}; got {v!r}")
        if self.n_iterative > self.n_trials:
            raise ConfigError(f"n_iterative must be <= n_trials ({self.n_trials}); got {self.n_iterative}")
        if self.timing_epochs > self.n_iterative:
            raise ConfigError(f"timing_epochs must be <= n_iterative ({self.n_iterative}); got {self.timing_epochs}")
        if self.n_big_epochs > self.timing_epochs:
            raise ConfigError(f"n_big_epochs must be <= timing_epochs ({self.timing_epochs}); got {self.n_big_epochs}")
        for name in ("pop_size", "n_gen"):
            v = getattr(self, name)
            if not (isinstance(v, int) and v >= 4):
                raise ConfigError(f"{name} must be an integer >= 4; got {v!r}")
        if not 0 < self.noise_bound < 1:
            raise ConfigError(f"noise_bound must be in (0, 1); got {self.noise_bound}")
        if not 0 < self.search_range <= 1:
            raise ConfigError(f"search_range must be in (0, 1]; got {self.search_range}")
        if not self.sweep_bounds or len(self.sweep_bounds) < 2 or any(not 0 < b < 1 for b in self.sweep_bounds):
            raise ConfigError(f"sweep_bounds must hold >= 2 bounds, each in (0, 1); got {self.sweep_bounds}")
