"""Rolling friction of the isolator: identified from free vibration, or read from
the measured tables against the vertical load (thesis ch. 5.2, eq. 51, Tables 19, 25).

A free vibration of the top plate with Coulomb-like rolling resistance keeps its
period T = 2 pi sqrt(R_hat / g) and loses 4 mu R_hat of amplitude per cycle, so

    mu_j = omega^2 (u_j - u_{j+2}) / (4 g)          (eq. 51, u_j the j-th peak, signed magnitudes)

Example: a simulated free vibration, identified back
-------
>>> from statue2model.hazard import motions
>>> from statue2model.isolator.device import Isolator
>>> from statue2model.isolator.time_history import simulate
>>> iso = Isolator(R=0.30, r=0.0183, M=21.664, mu=0.0114)
>>> res = simulate(iso, motions.free(), u0=0.08, t_end=6.0, dt_out=0.002)
>>> fr = friction_from_record(res.t, res.u)
>>> round(fr.mu_fitted, 4), round(fr.period, 3), round(iso.T, 3)
(0.0114, 1.506, 1.506)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

from ..quantities import G  # m/s^2


def identify_mu(peaks_u, T: float, g: float = G) -> dict:
    """Rolling friction from the successive peaks of a free-vibration record (eq. 51):
    mu_j = omega^2 (u_j - u_{j+2}) / (4 g) per cycle, and the least-squares slope of
    the peak envelope (|u_j| against j: each half cycle loses 2 mu g / omega^2)."""
    p = np.abs(np.asarray(peaks_u, dtype=float))
    if p.ndim != 1 or len(p) < 3 or not np.all(np.isfinite(p)):
        raise InputError("identifying mu needs at least three finite successive peaks")
    if not (math.isfinite(T) and T > 0):
        raise InputError(f"period must be positive, got {T}")
    om2 = (2 * math.pi / T) ** 2
    per_cycle = om2 * (p[:-2] - p[2:]) / (4 * g)
    j = np.arange(len(p))
    slope = np.polyfit(j, p, 1)[0]
    return {"per_cycle": per_cycle.tolist(), "mean": float(per_cycle.mean()),
            "fitted": float(-slope * om2 / (2 * g))}


def mu_for_load(M: float, table_M, table_mu) -> float:
    """mu at supported mass M by linear interpolation in a measured table
    (Tables 19, 25); outside the table: an error, not an extrapolation."""
    tm = np.asarray(table_M, dtype=float)
    tv = np.asarray(table_mu, dtype=float)
    if tm.shape != tv.shape or len(tm) < 2 or np.any(np.diff(tm) <= 0):
        raise InputError("the friction table needs two or more increasing masses with one mu each")
    if not (tm[0] <= M <= tm[-1]):
        raise InputError(f"mass {M:g} kg is outside the measured friction table ({tm[0]:g}-{tm[-1]:g} kg)")
    return float(np.interp(M, tm, tv))


TABLE_19 = {  # three-groove device (M kg -> mu)
    "M": (11.664, 21.664, 31.664, 41.664, 51.664),
    "steel_r0.0095": (0.0131, 0.0194, 0.0254, 0.0312, 0.0370),
    "resin_r0.0183": (0.0094, 0.0114, 0.0130, 0.0154, 0.0170),
    "resin_r0.0183_rubber": (0.0133, 0.0150, 0.0170, 0.0193, 0.0209),
}
TABLE_25 = {"M": (4.359, 9.359, 14.359, 19.359, 24.359), "mu": (0.0039, 0.0055, 0.0070, 0.0081, 0.0108)}


@dataclass(frozen=True)
class FrictionIdentification:
    """mu from a free-vibration record of the top plate.

    peaks_t, peaks_u : successive displacement peaks (s, m; signed)
    period           : measured period, twice the mean time between successive peaks (s)
    mu_per_cycle     : eq. 51 for each pair of peaks one cycle apart
    mu_mean, mu_fitted : their mean, and the slope of the peak envelope
    """

    peaks_t: np.ndarray
    peaks_u: np.ndarray
    period: float
    mu_per_cycle: np.ndarray
    mu_mean: float
    mu_fitted: float

    def to_dict(self) -> dict:
        return {"period": self.period, "mu_per_cycle": self.mu_per_cycle.tolist(), "mu_mean": self.mu_mean,
                "mu_fitted": self.mu_fitted, "peaks_t": self.peaks_t.tolist(), "peaks_u": self.peaks_u.tolist()}


def friction_from_record(t, u, T: float | None = None, g: float = G, min_fraction: float = 0.05) -> FrictionIdentification:
    """Identify mu from a sampled free vibration u(t) (s, m; 1-D arrays of one length).

    Peaks: one per half-cycle, the largest |u| between zero crossings refined by a
    parabola (half-cycles below ``min_fraction`` of the largest are noise or the
    final rest and are dropped). ``T`` (s) is the period used in eq. 51; default:
    the measured one (the period does not depend on the friction)."""
    from ..rocking.identify import find_peaks

    t = np.asarray(t, dtype=float)
    u = np.asarray(u, dtype=float)
    if t.ndim != 1 or t.shape != u.shape:
        raise InputError("the record needs one time and one displacement column of equal length")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(u))):
        raise InputError("the record holds a value that is not a finite number")
    if np.any(np.diff(t) <= 0):
        raise InputError("the record's times must increase")
    pk_t, pk_u, _ = find_peaks(t, u, min_fraction=min_fraction)
    if len(pk_u) < 3:
        raise InputError(f"the record holds {len(pk_u)} peak(s); identifying mu needs at least three")
    period = float(2 * np.mean(np.diff(pk_t)))
    res = identify_mu(pk_u, period if T is None else T, g=g)
    return FrictionIdentification(pk_t, pk_u, period, np.asarray(res["per_cycle"]), res["mean"], res["fitted"])


MU_LOW_FACTOR, MU_HIGH_FACTOR = 0.0039 / 0.0073, 0.0108 / 0.0073
"""Where the design gives no friction bounds: mu_low = mu x MU_LOW_FACTOR, mu_high = mu x
MU_HIGH_FACTOR, the spread the thesis measured on its four-groove device (Table 25: 0.0039 to
0.0108 about the nominal 0.0073; the same default as the isolator's time-history verification).
The codes ask for bounds from the device's own tests (EN 15129 upper and lower design values,
ASCE 7-16 17.2.8.4 lambda_min, lambda_max): set [isolator] mu_low and mu_high."""


def friction_bounds(mu: float, mu_low: float | None = None, mu_high: float | None = None) -> tuple[float, float, str]:
    """(mu_low, mu_high, where from) of an isolator of nominal friction ``mu``: the given bounds,
    else mu x MU_LOW_FACTOR and mu x MU_HIGH_FACTOR (Table 25's spread; capped below 1). Refused
    unless 0 <= mu_low <= mu <= mu_high < 1.

    >>> [round(x, 4) for x in friction_bounds(0.0073)[:2]]          # Table 25: 0.0039 and 0.0108
    [0.0039, 0.0108]
    """
    mu = float(mu)
    src = "[isolator] mu_low, mu_high"
    if mu_low is None or mu_high is None:
        src = ("mu x 0.0039 / 0.0073 and mu x 0.0108 / 0.0073 (the spread of Table 25 about its nominal mu: the "
               "design gives no bounds; EN 15129 and ASCE 7-16 17.2.8.4 ask for them from the device's tests)")
        mu_low = mu * MU_LOW_FACTOR if mu_low is None else mu_low
        mu_high = min(mu * MU_HIGH_FACTOR, 0.99) if mu_high is None else mu_high
    lo, hi = float(mu_low), float(mu_high)
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo <= mu <= hi < 1):
        raise InputError(f"friction bounds must satisfy 0 <= mu_low <= mu <= mu_high < 1, got {lo:g}, {mu:g}, {hi:g}")
    return lo, hi, src
