"""Geomagnetic field in ECI: tilted dipole and IGRF-14 (via ``ppigrf``), one interface.

``magnetic_field(r_eci, times, model=...)`` rotates the positions to ECEF (GMST rotation,
:mod:`adcskit.environment.frames`), evaluates the model there, and rotates the field back.

Models (registry :data:`MAGNETIC_MODELS`)
-----------------------------------------
``"dipole"``
    Tilted centred dipole from IGRF-14's degree-1 Gauss coefficients ``g10, g11, h11``
    interpolated at each sample's date: ``B = (a/r)^3 [3 (m . r_hat) r_hat - m]`` with
    ``m = [g11, h11, g10]`` (ECEF, nT) and ``a = 6371.2 km``. This is the ``n = 1`` term of
    the IGRF expansion exactly (tested against ``ppigrf`` with ``max_degree=1``).
``"igrf"``
    IGRF-14 to degree 13, ``ppigrf.igrf_gc`` (geocentric input: radius km, colatitude deg,
    longitude deg; output ``B_r, B_theta, B_phi`` in nT).

Gauss coefficients are evaluated at 00:00 UTC of each sample's day (samples are grouped by
UTC day so that ``ppigrf`` is called once per day, not once per sample). The secular variation
is below ~150 nT/yr, so this costs < 0.5 nT. IGRF-14 covers 1900-2030; other dates raise.

Hand-written part: only the dipole (three coefficients) and the frame glue; the field model
itself is ``ppigrf``.

References
----------
.. [1] P. Alken et al., "International Geomagnetic Reference Field: the fourteenth generation",
   IAGA, 2024 (IGRF-14 coefficients, shipped with ``ppigrf``).
.. [2] K. M. Laundal, ``ppigrf`` — pure Python IGRF, https://github.com/IAGA-VMOD/ppigrf.
.. [3] J. R. Wertz (ed.), *Spacecraft Attitude Determination and Control*, 1978, App. H
   (dipole model from the degree-1 coefficients).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

import numpy as np

from adcskit._validation import as_batch, check_choice
from adcskit.environment.frames import _rot3
from adcskit.environment.time import as_utc, gmst
from adcskit.errors import InputError

__all__ = ["MAGNETIC_MODELS", "IGRF_REFERENCE_RADIUS", "magnetic_field", "dipole_coefficients"]

IGRF_REFERENCE_RADIUS = 6371.2e3  #: IGRF reference (mean) radius a, m
_IGRF_START = np.datetime64("1900-01-01", "ns")
_IGRF_END = np.datetime64("2030-01-01", "ns")


@functools.lru_cache(maxsize=1)
def _degree1_table() -> tuple[np.ndarray, np.ndarray]:
    """IGRF-14 epochs (datetime64[ns]) and the (g10, g11, h11) columns, nT."""
    import ppigrf.ppigrf as pp

    g, h = pp.read_shc(pp.shc_fn_igrf14)
    epochs = np.asarray(g.index.values, dtype="datetime64[ns]")
    coeffs = np.stack([g[(1, 0)].to_numpy(), g[(1, 1)].to_numpy(), h[(1, 1)].to_numpy()], axis=1)
    return epochs, coeffs.astype(float)


def _check_dates(days: np.ndarray) -> np.ndarray:
    lo, hi = days.min(), days.max()
    if lo < _IGRF_START or hi > _IGRF_END:
        raise InputError(
            f"times must lie in IGRF-14's validity [1900-01-01, 2030-01-01]; got {lo} .. {hi}"
        )
    return days


def dipole_coefficients(times: Any) -> np.ndarray:
    """IGRF-14 degree-1 Gauss coefficients ``[g10, g11, h11]`` (nT) at UTC dates.

    Linear interpolation between IGRF's five-yearly epochs, as ``ppigrf`` does; evaluated at
    00:00 UTC of each instant's day. Returns shape (3,) or (N, 3).

    Examples
    --------
    >>> from adcskit.environment import dipole_coefficients
    >>> g10, g11, h11 = dipole_coefficients("2025-01-01")    # nT
    >>> bool(g10 < -29000.0)
    True
    >>> dipole_coefficients(["2020-01-01", "2025-01-01"]).shape
    (2, 3)
    """
    t = as_utc(times)
    days = _check_dates(np.atleast_1d(t).astype("datetime64[D]").astype("datetime64[ns]"))
    epochs, table = _degree1_table()
    x = days.astype(np.int64).astype(float)
    xp = epochs.astype(np.int64).astype(float)
    out = np.stack([np.interp(x, xp, table[:, k]) for k in range(3)], axis=1)
    return out if t.ndim else out[0]


def _dipole_ecef(r_ecef: np.ndarray, days: np.ndarray) -> np.ndarray:
    """Tilted dipole in ECEF, tesla. r_ecef (N, 3) m; days (N,) datetime64 (UTC day)."""
    epochs, table = _degree1_table()
    x = days.astype(np.int64).astype(float)
    xp = epochs.astype(np.int64).astype(float)
    g10, g11, h11 = (np.interp(x, xp, table[:, k]) for k in range(3))
    m = np.stack([g11, h11, g10], axis=1) * 1e-9  # tesla
    rn = np.linalg.norm(r_ecef, axis=1, keepdims=True)
    rhat = r_ecef / rn
    k = (IGRF_REFERENCE_RADIUS / rn) ** 3
    return k * (3.0 * np.sum(m * rhat, axis=1, keepdims=True) * rhat - m)


def _igrf_ecef(r_ecef: np.ndarray, days: np.ndarray) -> np.ndarray:
    """IGRF-14 (ppigrf) in ECEF, tesla, one ppigrf call per distinct UTC day."""
    import ppigrf

    out = np.empty_like(r_ecef)
    rn = np.linalg.norm(r_ecef, axis=1)
    colat = np.arccos(np.clip(r_ecef[:, 2] / rn, -1.0, 1.0))
    # ppigrf divides by sin(colatitude): keep 1e-9 rad off the poles (a 6 mm offset at LEO).
    colat = np.clip(colat, 1e-9, np.pi - 1e-9)
    lon = np.arctan2(r_ecef[:, 1], r_ecef[:, 0])
    for day in np.unique(days):
        sel = days == day
        date = day.astype("datetime64[us]").item()
        Br, Bt, Bp = ppigrf.igrf_gc(rn[sel] / 1e3, np.degrees(colat[sel]), np.degrees(lon[sel]), date)
        Br, Bt, Bp = Br[0], Bt[0], Bp[0]
        th, ph = colat[sel], lon[sel]
        r_hat = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], axis=1)
        t_hat = np.stack([np.cos(th) * np.cos(ph), np.cos(th) * np.sin(ph), -np.sin(th)], axis=1)
        p_hat = np.stack([-np.sin(ph), np.cos(ph), np.zeros_like(ph)], axis=1)
        out[sel] = (Br[:, None] * r_hat + Bt[:, None] * t_hat + Bp[:, None] * p_hat) * 1e-9
    return out


#: Registry of geomagnetic field models: name -> kernel(r_ecef (N,3) m, day (N,)) -> B_ecef (T).
MAGNETIC_MODELS: dict[str, Callable[[np.ndarray, np.ndarray], np.ndarray]] = {
    "dipole": _dipole_ecef,
    "igrf": _igrf_ecef,
}


def magnetic_field(r_eci: Any, times: Any, model: str = "dipole") -> np.ndarray:
    """Geomagnetic field vector in ECI at given positions and UTC instants.

    Parameters
    ----------
    r_eci : array_like, m, shape (3,) or (N, 3)
        Positions in adcskit's ECI (e.g. ``circular_orbit(...).r``); radius must exceed
        1000 km (the models are potential fields outside the Earth).
    times : datetime-like or array_like, shape () or (N,)
        UTC instants, one or one per position (e.g. ``state.times``).
    model : {"dipole", "igrf"}
        Field model, see :data:`MAGNETIC_MODELS` and the module docstring.

    Returns
    -------
    numpy.ndarray, T, shape (3,) or (N, 3)
        Field in ECI, tesla. At 800 km its magnitude is ~16-46 µT.

    Examples
    --------
    >>> import numpy as np
    >>> from adcskit.environment import circular_orbit
    >>> st = circular_orbit(800e3, np.radians(75), 0.0, 0.0, np.arange(0, 1200, 10.0),
    ...                     epoch="2024-01-01")
    >>> B = magnetic_field(st.r, st.times, model="igrf")
    >>> bool(np.all((np.linalg.norm(B, axis=1) > 1.5e-5) & (np.linalg.norm(B, axis=1) < 6e-5)))
    True

    References
    ----------
    Alken et al. (2024), IGRF-14; ppigrf (Laundal); Wertz (1978), App. H (dipole).
    """
    check_choice("model", model, MAGNETIC_MODELS)
    vec, batched = as_batch("r_eci", r_eci, (3,))
    t = as_utc(times)
    if t.ndim > 1:
        raise InputError(f"times must be one instant or a 1-D array; got shape {t.shape}")
    t1 = np.atleast_1d(t)
    n = max(len(t1), len(vec))
    if len(t1) not in (1, n) or len(vec) not in (1, n):
        raise InputError(
            f"times must have one instant or as many as r_eci has rows ({len(vec)}); got {len(t1)}"
        )
    rn = np.linalg.norm(vec, axis=1)
    if np.any(rn < 1.0e6):
        raise InputError(
            f"r_eci must be positions in metres outside the Earth (|r| >= 1e6 m); got |r| = "
            f"{rn.min():g} m (km passed by mistake?)"
        )
    t1 = np.broadcast_to(t1, (n,))
    vec = np.broadcast_to(vec, (n, 3))
    days = _check_dates(t1.astype("datetime64[D]").astype("datetime64[ns]"))
    R = _rot3(gmst(t1))  # ECI -> ECEF
    r_ecef = np.einsum("nij,nj->ni", R, vec)
    B_ecef = MAGNETIC_MODELS[model](r_ecef, days)
    B = np.einsum("nji,nj->ni", R, B_ecef)  # R^T B
    return B if (batched or t.ndim == 1) else B[0]

