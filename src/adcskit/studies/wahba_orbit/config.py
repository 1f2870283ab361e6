"""Configuration of the ``wahba-orbit`` study: S0 §4-2's settings and our choices.

``adcskit config wahba-orbit`` prints the fields of :class:`Config` in this order.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from adcskit.studies._base import NEUTRAL, NOT_PRINTED, protocol

__all__ = ["CASES", "Config"]

#: Field-model cases ``truth/reference``: the paper's (dipole everywhere), IGRF-14 everywhere, and
#: the real field measured with the paper's dipole as reference (a model error no interval covers).
CASES = ("dipole/dipole", "igrf/igrf", "igrf/dipole")


@dataclass(frozen=True, kw_only=True)
class Config:
    """S0 §4-2 settings (defaults) and our choices where the paper is silent.

    Attributes
    ----------
    altitude_km : float, km
        Altitude of the circular orbit (S0 Table 3: 800 km).
    inclination_deg : float, deg
        Inclination of the orbit (S0 Table 3: 75°).
    raan_deg : float, deg
        Right ascension of the ascending node (S0 Table 3: 0).
    duration_s : float, s
        Simulated time (S0: 20 min).
    dt_s : float, s
        Sample interval (not printed in S0; ours 10 s: 121 epochs per run, sized so that 5 seeds x 4 runs fit the reproduction budget).
    inertia_kgm2 : tuple of 3 floats, kg m²
        Principal inertia (S0 Table 3).
    euler0_deg : tuple of 3 floats, deg
        Initial 3-2-1 Euler angles (roll, pitch, yaw) of body w.r.t. ECI (S0 Table 2).
    gravity_gradient : bool
        Include the gravity-gradient torque.
    sun_bound_deg : float, deg
        Bound of the sun sensor's angular error (S0: ±0.005°).
    mag_bound_deg : float, deg
        Bound of the magnetometer's angular error (S0: ±0.5°).
    weighting : {"equal", "inverse-variance"}
        Wahba weights: equal (S0: Σa = 1, nothing else printed) or 1/bound².
    cases : tuple of str
        ``truth/reference`` field models, each ``dipole`` or ``igrf``.
    epoch : str
        UTC epoch of t = 0 (not printed; ours).
    n_seeds : int
        Independent sensor-noise realisations (and NSGA-II seeds) per case; the claim is
        decided over them (>= 5 at full settings).
    readings_weighting : tuple of str
        Weightings run on the paper's case (the first of ``cases``) as readings of the claim
        (S0 prints only Σa = 1); ``weighting`` is the default reading.
    nsga2_every : int
        Run NSGA-II on every k-th sample only (it takes ~1 s per epoch).
    pop_size, n_gen : int
        NSGA-II settings.

    Every protocol key declares S0's printed value (``paper=``, Tables 2-3 and §4-2) or
    ``NOT_PRINTED``. ``cases`` is NOT_PRINTED although S0 runs the dipole field: the key lists
    which cases we run, its first one (``dipole/dipole``, the paper's) decides the claim, and the
    others only add findings; S0 prints no sample interval, epoch, weights or NSGA-II settings,
    and does not say whether its "nonlinear simulation" includes the gravity-gradient torque.
    """

    altitude_km: float = field(default=800.0, metadata=protocol("claim", "finding", paper=800.0))
    inclination_deg: float = field(default=75.0, metadata=protocol("claim", "finding", paper=75.0))
    raan_deg: float = field(default=0.0, metadata=protocol("claim", "finding", paper=0.0))
    duration_s: float = field(default=1200.0, metadata=protocol("claim", "finding", paper=1200.0))
    dt_s: float = field(default=10.0, metadata=protocol("finding", paper=NOT_PRINTED))
    inertia_kgm2: tuple[float, float, float] = field(default=(80.0, 80.0, 4.0),
                                                     metadata=protocol("claim", "finding", paper=(80.0, 80.0, 4.0)))
    euler0_deg: tuple[float, float, float] = field(default=(0.0, 0.0, 5.0),
                                                   metadata=protocol("claim", "finding", paper=(0.0, 0.0, 5.0)))
    gravity_gradient: bool = field(default=True, metadata=protocol("claim", "finding", paper=NOT_PRINTED))
    sun_bound_deg: float = field(default=0.005, metadata=protocol("claim", "finding", paper=0.005))
    mag_bound_deg: float = field(default=0.5, metadata=protocol("claim", "finding", paper=0.5))
    weighting: str = field(default="equal", metadata=protocol("claim", "finding", paper=NOT_PRINTED))
    cases: tuple[str, ...] = field(default=CASES, metadata=protocol("claim", paper=NOT_PRINTED))
    epoch: str = field(default="2024-03-20T12:00:00", metadata=protocol("finding", paper=NOT_PRINTED))
    n_seeds: int = field(default=5, metadata=NEUTRAL)
    readings_weighting: tuple[str, ...] = ("equal", "inverse-variance")
    nsga2_every: int = field(default=6, metadata=protocol("nsga2", paper=NOT_PRINTED))
    pop_size: int = field(default=40, metadata=protocol("nsga2", paper=NOT_PRINTED))
    n_gen: int = field(default=40, metadata=protocol("nsga2", paper=NOT_PRINTED))

    def __post_init__(self) -> None:
        from adcskit.errors import ConfigError

        if not self.altitude_km > 100:
            raise ConfigError(f"altitude_km must be > 100 km; got {self.altitude_km}")
        if not 0 <= self.inclination_deg <= 180:
            raise ConfigError(f"inclination_deg must be in [0, 180] deg; got {self.inclination_deg}")
        if not (self.duration_s > 0 and 0 < self.dt_s <= self.duration_s):
            raise ConfigError(f"need duration_s > 0 and 0 < dt_s <= duration_s; got {self.duration_s}, {self.dt_s}")
        if any(not v > 0 for v in self.inertia_kgm2):
            raise ConfigError(f"inertia_kgm2 must be positive (kg m^2); got {self.inertia_kgm2}")
        for name in ("sun_bound_deg", "mag_bound_deg"):
            if not 0 < getattr(self, name) < 90:
                raise ConfigError(f"{name} must be in (0, 90) deg; got {getattr(self, name)}")
        for wt in (self.weighting, *self.readings_weighting):
            if wt not in ("equal", "inverse-variance"):
                raise ConfigError(f"weighting and readings_weighting must be 'equal' or 'inverse-variance'; got {wt!r}")
        if not (isinstance(self.n_seeds, int) and self.n_seeds >= 1):
            raise ConfigError(f"n_seeds must be an integer >= 1; got {self.n_seeds!r}")
        for c in self.cases:
            parts = c.split("/")
            if len(parts) != 2 or any(p not in ("dipole", "igrf") for p in parts):
                raise ConfigError(f"cases must be 'truth/reference' with dipole or igrf; got {c!r}")
        if not self.cases:
            raise ConfigError(f"cases must not be empty; got {self.cases!r}")
        for name in ("nsga2_every", "pop_size", "n_gen"):
            v = getattr(self, name)
            if not (isinstance(v, int) and v >= (1 if name == "nsga2_every" else 4)):
                raise ConfigError(f"{name} must be an integer >= {1 if name == 'nsga2_every' else 4}; got {v!r}")
