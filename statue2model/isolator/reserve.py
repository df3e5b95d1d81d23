"""Where the statue would overturn without the device: the lowest scale of each design record at which
the fixed-base statue overturns (the reserve check of verify.py: the device must keep its travel up
to there, so that its failure curve lies at or right of the fixed base's overturning curve; MODEL.md
section 9).

Rocking is not monotonic in the intensity (a record may overturn the statue at one scale and not at a
larger one), so the scale is found from below: the record is scaled to a geometric ladder of LADDER
steps from LOWEST to ``cap`` times its PGA; the first step that overturns is refined by BISECTIONS
bisections against the step before it. A record that does not overturn the statue up to ``cap``
is taken at ``cap`` (the study's range: checks.RESERVE_LEVEL x the design PGA).

>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> from statue2model.rocking.model import RockingModel
>>> block = RockingModel.housner(RockingParams.rectangular_block(b=0.05, h=0.25, m=10.0))
>>> s = overturning_scales(block, [motions.sine_pulse(1.0, 2.0)], caps=[20.0])
>>> 1.0 < s[0].scale < 20.0, s[0].overturns
(True, True)
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

LADDER = 10
LOWEST = 0.1
BISECTIONS = 6


@dataclass(frozen=True)
class Reserve:
    """One record's reserve: the ``scale`` (x the record as matched) and whether the statue overturns there
    (False: it did not up to the cap, and the scale is the cap)."""

    scale: float
    overturns: bool

    def to_dict(self) -> dict:
        return {"scale": self.scale, "overturns": self.overturns}


def _overturns(model, motion, scale: float, rtol: float) -> bool:
    from ..rocking.engine import simulate

    return bool(simulate(model, motion.scaled(scale), rtol=rtol).overturned)


def lowest(fails, cap: float) -> float | None:
    """The lowest scale in (0, cap] at which ``fails(scale)`` holds, found from below (module docstring: a
    ladder, then bisections against the step before); None when it never does up to ``cap``."""
    lo = 0.0
    for s in np.geomspace(min(LOWEST, cap), cap, LADDER):
        if fails(float(s)):
            hi = float(s)
            for _ in range(BISECTIONS):
                mid = 0.5 * (lo + hi)
                if fails(mid):
                    hi = mid
                else:
                    lo = mid
            return hi
        lo = float(s)
    return None


def _one(task) -> Reserve:
    model, motion, cap, rtol = task
    s = lowest(lambda x: _overturns(model, motion, x, rtol), cap)
    return Reserve(float(cap), False) if s is None else Reserve(s, True)


def overturning_scales(model, records, caps, rtol: float = 1e-7, executor=None) -> list[Reserve]:
    """For each record (GroundMotion) the lowest scale (<= its cap) that overturns the fixed-base statue
    (rocking.model.RockingModel ``model``); ``executor`` spreads the records over its workers."""
    tasks = [(model, m, float(c), rtol) for m, c in zip(records, caps)]
    if executor is None or getattr(executor, "workers", 1) < 2:
        return [_one(t) for t in tasks]
    return list(executor.map(_one, tasks, desc="isolator: where the fixed base overturns"))


def capacity_scales(R_hat: float, mu_low: float, mu_high: float, records, capacity: float, offset: float,
                    caps, g: float) -> list[float]:
    """For each record (GroundMotion) the lowest scale (<= its cap; the cap when none) at which the top plate of
    period 2 pi sqrt(R_hat / g), at either friction bound, travels more than ``capacity - offset`` (m): where
    the device fails under that record. The same ladder and bisections as :func:`overturning_scales`."""
    from .device import Isolator
    from .time_history import simulate

    isos = [Isolator(R=R_hat / 2 + 0.01, r=0.01, M=1.0, mu=mu, g=g) for mu in {mu_low, mu_high}]
    room = capacity - offset

    def fails(m, s):
        return any(simulate(iso, m.scaled(s), dt_out=1.0).u_max > room for iso in isos)

    out = []
    for m, cap in zip(records, caps):
        found = lowest(lambda x, m=m: fails(m, x), cap)
        out.append(float(cap) if found is None else found)
    return out


def tail(fixed_pgas, device_pgas) -> dict:
    """The two empirical failure curves over the same records, compared: ``dominates`` when every k-th lowest
    failure PGA of the device is at least the fixed base's k-th lowest overturning PGA (the device's curve at or
    right of the fixed base's everywhere), else ``worse_from``, the lowest PGA where more records fail on the
    device than overturn without it, and the counts there.

    >>> tail([0.5, 0.6, 0.7], [0.55, 0.65, 0.8])["dominates"]
    True
    >>> t = tail([0.5, 0.6, 0.7], [0.45, 0.7, 0.8]); t["dominates"], t["worse_from"], t["device_fails"], t["fixed_fails"]
    (False, 0.45, 1, 0)
    """
    f, d = np.sort(np.asarray(fixed_pgas, float)), np.sort(np.asarray(device_pgas, float))
    dominates = bool(np.all(d >= f * (1 - 1e-9)))
    out = {"dominates": dominates, "fixed_sorted": f.tolist(), "device_sorted": d.tolist()}
    if not dominates:
        for a in d:
            nd, nf = int((d <= a).sum()), int((f <= a).sum())
            if nd > nf:
                out.update(worse_from=float(a), device_fails=nd, fixed_fails=nf)
                break
    return out
