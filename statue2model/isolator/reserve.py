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


def _one(task) -> Reserve:
    model, motion, cap, rtol = task
    ladder = np.geomspace(min(LOWEST, cap), cap, LADDER)
    lo = 0.0
    for s in ladder:
        if _overturns(model, motion, float(s), rtol):
            hi = float(s)
            for _ in range(BISECTIONS):
                mid = 0.5 * (lo + hi)
                if _overturns(model, motion, mid, rtol):
                    hi = mid
                else:
                    lo = mid
            return Reserve(hi, True)
        lo = float(s)
    return Reserve(float(cap), False)


def overturning_scales(model, records, caps, rtol: float = 1e-7, executor=None) -> list[Reserve]:
    """For each record (GroundMotion) the lowest scale (<= its cap) that overturns the fixed-base statue
    (rocking.model.RockingModel ``model``); ``executor`` spreads the records over its workers."""
    tasks = [(model, m, float(c), rtol) for m, c in zip(records, caps)]
    if executor is None or getattr(executor, "workers", 1) < 2:
        return [_one(t) for t in tasks]
    return list(executor.map(_one, tasks, desc="isolator: where the fixed base overturns"))
