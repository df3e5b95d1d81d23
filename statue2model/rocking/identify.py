"""Coefficients of restitution from a free-rocking record (eq. 43, Tables 4-12, 23).

Between two successive peaks theta_i (on pivot A) and theta_{i+1} (on pivot B)
the body loses energy only at the impact, so

    e = sqrt( d_B I_A [cos(delta_B - |theta_{i+1}|) - cos delta_B]
              / ( I_B d_A [cos(delta_A - |theta_i|) - cos delta_A] ) )

and the impact speed is |theta'-| = sqrt(2 p_A^2 [cos(delta_A - |theta_i|) - cos delta_A]).
Rocking on the right pivot (A = R) lands on the left edge: that e is e_L.
Each side's points are fitted with e = c0 + c1 |theta'| (least squares), or
their mean when fewer than three.

Example
-------
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> from statue2model.rocking import RockingModel, simulate
>>> p = RockingParams(m=19.6, h=0.3523, b_L=0.1995, b_R=0.0805, I_G=1.105)
>>> r = simulate(RockingModel.housner(p, e_L=0.95, e_R=0.90), motions.free(),
...              theta0=0.8 * p.delta_R, t_end=3.0, dt_out=1e-3)
>>> ident = identify_restitution(r.history["t"], r.history["theta"], p)
>>> round(ident.e_L.values[0], 3), round(ident.e_R.values[0], 3)
(0.95, 0.9)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..geometry.rocking_params import RockingParams
from .model import Restitution


@dataclass(frozen=True, eq=False)
class Identification:
    """Per impact: time (s, midway estimate: the zero crossing), impact speed
    |theta'-| (rad/s), e, landing side ("L" or "R"); per side: the fit
    (c0, c1) with e = c0 + c1 |theta'| and the Restitution it gives (a table over
    the measured speed range, or a constant)."""

    t_impact: np.ndarray
    speed: np.ndarray
    e: np.ndarray
    side: np.ndarray
    peak_t: np.ndarray
    peak_theta: np.ndarray
    fit: dict
    e_L: Restitution
    e_R: Restitution

    def to_dict(self) -> dict:
        return {"impacts": [{"i": i, "t": float(t), "speed_rad_s": float(w), "e": float(e), "side": s}
                            for i, (t, w, e, s) in enumerate(zip(self.t_impact, self.speed, self.e, self.side))],
                "fit": self.fit, "e_L": self.e_L.to_dict(), "e_R": self.e_R.to_dict(),
                "peaks": {"t": self.peak_t, "theta": self.peak_theta}}

    def to_csv(self) -> str:
        lines = ["i,t_s,speed_rad_s,e,landing_side"]
        lines += [f"{i},{t:.6g},{w:.6g},{e:.6g},{s}" for i, (t, w, e, s) in
                  enumerate(zip(self.t_impact, self.speed, self.e, self.side))]
        return "\n".join(lines) + "\n"


def find_peaks(t: np.ndarray, theta: np.ndarray, min_fraction: float = 0.02):
    """One peak per half-cycle: between successive sign changes of theta, the
    sample of largest |theta| refined by a parabola through it and its neighbours.
    Half-cycles smaller than ``min_fraction`` of the largest are ignored (noise).
    Returns (peak_t, peak_theta signed, crossing times)."""
    sign = np.sign(theta)
    nz = np.flatnonzero(sign != 0)
    if nz.size < 3:
        raise InputError("the record holds no rocking (theta is zero)")
    cuts = nz[np.flatnonzero(np.diff(sign[nz]) != 0) + 1]
    bounds = np.concatenate([[nz[0]], cuts, [nz[-1] + 1]])
    pk_t, pk_th, cross = [], [], []
    amax = np.max(np.abs(theta))
    for a, b in zip(bounds[:-1], bounds[1:]):
        if b - a < 1:
            continue
        k = a + int(np.argmax(np.abs(theta[a:b])))
        if abs(theta[k]) < min_fraction * amax:
            continue
        tk, yk = t[k], theta[k]
        if 0 < k < len(t) - 1:
            y0, y1, y2 = theta[k - 1], theta[k], theta[k + 1]
            den = y0 - 2 * y1 + y2
            if den != 0:
                x = 0.5 * (y0 - y2) / den
                if abs(x) <= 1:
                    dt = 0.5 * (t[k + 1] - t[k - 1])
                    tk = t[k] + x * dt
                    yk = y1 - 0.25 * (y0 - y2) * x
        pk_t.append(tk)
        pk_th.append(yk)
        if a > 0:
            # linear interpolation of the crossing before this half-cycle
            t0, t1, y0, y1 = t[a - 1], t[a], theta[a - 1], theta[a]
            cross.append(t0 + (t1 - t0) * y0 / (y0 - y1) if y0 != y1 else t1)
        else:
            cross.append(np.nan)
    return np.asarray(pk_t), np.asarray(pk_th), np.asarray(cross)


def identify_restitution(t, theta, params: RockingParams, min_fraction: float = 0.02) -> Identification:
    """e_L and e_R (points and fitted curves) from a free-rocking record theta(t) in rad."""
    t = np.asarray(t, dtype=float).ravel()
    theta = np.asarray(theta, dtype=float).ravel()
    if t.size != theta.size or t.size < 5:
        raise InputError("a free-rocking record needs matching time and rotation columns (at least 5 samples)")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(theta))):
        raise InputError("the free-rocking record holds non-finite values")
    if np.any(np.diff(t) <= 0):
        raise InputError("time must increase in the free-rocking record")
    delta = {1: params.delta_R, -1: params.delta_L}
    if np.any(theta >= delta[1]) or np.any(-theta >= delta[-1]):
        raise InputError("the record exceeds the overturning angle: is theta in radians, and the sign convention "
                         "theta > 0 on the right pivot?")
    pk_t, pk_th, cross = find_peaks(t, theta, min_fraction)
    if pk_t.size < 2:
        raise InputError("the record holds fewer than two rocking peaks: nothing to identify")
    d = {1: params.d_R, -1: params.d_L}
    inertia = {1: params.I_R, -1: params.I_L}
    p2 = {1: params.p_R**2, -1: params.p_L**2}
    rows = []
    for i in range(pk_t.size - 1):
        a, b = int(np.sign(pk_th[i])), int(np.sign(pk_th[i + 1]))
        if a == b:
            continue
        qa, qb = abs(pk_th[i]), abs(pk_th[i + 1])
        # cos(delta - q) - cos(delta), written without cancellation for small q
        ea = 2.0 * math.sin(delta[a] - 0.5 * qa) * math.sin(0.5 * qa)
        eb = 2.0 * math.sin(delta[b] - 0.5 * qb) * math.sin(0.5 * qb)
        if ea <= 0:
            continue
        e = math.sqrt(d[b] * inertia[a] * eb / (inertia[b] * d[a] * ea))
        w = math.sqrt(2 * p2[a] * ea)
        rows.append((cross[i + 1], w, e, "L" if a > 0 else "R"))
    if not rows:
        raise InputError("no pair of successive peaks on opposite pivots in the record")
    tt, ww, ee, ss = (np.array(x) for x in zip(*rows))
    fit, rest = {}, {}
    for side in ("L", "R"):
        sel = ss == side
        if not np.any(sel):
            fit[side] = None
            rest[side] = None
            continue
        w, e = ww[sel], ee[sel]
        if sel.sum() >= 3 and np.ptp(w) > 0:
            c1, c0 = np.polyfit(w, e, 1)
            grid = np.linspace(w.min(), w.max(), 5)
            vals = np.clip(c0 + c1 * grid, 0.0, 1.0)
            rest[side] = Restitution.table(grid, vals, f"e_{side}")
            fit[side] = {"c0": float(c0), "c1": float(c1), "n": int(sel.sum()),
                         "rms_residual": float(np.sqrt(np.mean((c0 + c1 * w - e) ** 2))),
                         "speed_range_rad_s": [float(w.min()), float(w.max())]}
        else:
            rest[side] = Restitution.constant(float(np.clip(e.mean(), 0, 1)), f"e_{side}")
            fit[side] = {"c0": float(e.mean()), "c1": 0.0, "n": int(sel.sum()), "rms_residual": float(e.std()),
                         "speed_range_rad_s": [float(w.min()), float(w.max())]}
    if rest["L"] is None or rest["R"] is None:
        missing = "L" if rest["L"] is None else "R"
        raise InputError(f"the record holds no impact landing on the {'left' if missing == 'L' else 'right'} edge")
    return Identification(tt, ww, ee, ss, pk_t, pk_th, fit, rest["L"], rest["R"])


def read_rotation_record(path, units: str = "rad") -> tuple[np.ndarray, np.ndarray]:
    """CSV of time (s) and rotation in its first two columns (further columns, such as
    those of a ``rock`` history, are ignored), optional header; ``units`` rad or deg."""
    if units not in ("rad", "deg"):
        raise InputError(f"rotation units must be rad or deg, got {units!r}")
    t, theta = read_time_series(path, "rotation")
    return t, (np.radians(theta) if units == "deg" else theta)


def read_time_series(path, quantity: str) -> tuple[np.ndarray, np.ndarray]:
    """Time (s) and one quantity from the first two columns of a CSV (separators
    , ; tab or space; optional header; further columns ignored); ``quantity`` names
    the second column in error messages."""
    from pathlib import Path

    path = Path(path)
    if not path.is_file():
        raise InputError(f"record file not found: {path}")
    rows = []
    ncol = 0
    for j, line in enumerate(path.read_text(encoding="utf-8-sig", errors="replace").splitlines(), start=1):  # BOM
        parts = [x for x in line.replace(";", ",").replace("\t", ",").replace(" ", ",").split(",") if x]
        if not parts or parts[0].startswith("#"):
            continue
        try:
            vals = [float(x) for x in parts]
        except ValueError:
            if rows:
                raise InputError(f"{path}: line {j}: not a number: {line.strip()!r}") from None
            continue
        if len(vals) < 2:
            raise InputError(f"{path}: line {j}: expected at least 2 columns (time, {quantity}), found {len(vals)}")
        if ncol and len(vals) != ncol:
            raise InputError(f"{path}: line {j}: {len(vals)} columns where earlier lines have {ncol}")
        ncol = len(vals)
        rows.append(vals[:2])
    if len(rows) < 5:
        raise InputError(f"{path}: fewer than 5 data rows")
    data = np.asarray(rows)
    if not np.all(np.isfinite(data)):
        raise InputError(f"{path}: a value is not a finite number")
    if np.any(np.diff(data[:, 0]) <= 0):
        raise InputError(f"{path}: the times must increase")
    return data[:, 0], data[:, 1]
