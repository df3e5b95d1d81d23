"""The statue riding on the isolator's top plate: does it lift, and how does it rock?

The plate alone (:func:`statue2model.isolator.time_history.simulate`) gives the absolute
acceleration the statue feels; :func:`statue_on_plate` then runs the coupled plate + statue
model (:mod:`statue2model.isolator.coupled`: two degrees of freedom, the rocking statue
pushes the plate back), which decides whether the statue lifts and how it rocks, with the
one-way estimate (the statue driven by the plate-only acceleration) and the fixed-base
response beside it. While the statue stays in full contact the coupled model is exactly
eq. 20 with M = m_o + m, so no 2-DOF integration is needed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..hazard import motions
from ..rocking.engine import simulate as rock
from .coupled import simulate_coupled
from .time_history import IsolatorResult, capacity_dict


@dataclass(frozen=True)
class StatueOnPlate:
    """The statue on the moving plate: uplift check and, where it lifts, its rocking.

    rocking       : CoupledResult of plate + statue (two-way, coupled.py); when the
                    statue never lifts it holds the plate result (no 2-DOF integration)
    one_way       : RockingResult of the statue driven by the plate-only a_abs (the
                    rocking not fed back), for comparison; None without uplift
    fixed_rocking : RockingResult of the statue on a fixed base under the ground motion
    """

    plate: IsolatorResult
    limit_pos: float      # a_abs above this tips the statue (alpha_L a_L), m/s^2
    limit_neg: float      # a_abs below minus this tips it the other way (alpha_R a_R)
    rocking: object
    one_way: object
    fixed_rocking: object

    @property
    def uplift(self) -> bool:
        return bool(self.rocking.uplift)

    @property
    def efficiency(self) -> float:
        """Peak |a_abs| isolated (coupled) / PGA (Table 26)."""
        return self.rocking.efficiency

    def to_dict(self) -> dict:
        r = self.rocking
        out = {
            "uplift": self.uplift, "uplift_limits": [self.limit_pos, self.limit_neg],
            "acc_abs_max": r.acc_abs_max, "pga": r.pga, "efficiency": r.efficiency,
            "margin_plate_only": min(self.limit_pos - float(np.nanmax(self.plate.acc_abs)),
                                     self.limit_neg + float(np.nanmin(self.plate.acc_abs))),
            "model": "coupled plate + statue (two-way)",
            "coupled_integration": bool(r.stats.get("coupled_integration", False)),
            "outcome": r.outcome,
            **capacity_dict(r.capacity, r.capacity_exceeded, r.t_capacity, r.u_at_capacity, r.capacity_hits,
                            r.end_stop, r.end_stop_restitution),
        }
        if self.uplift:
            out["rocking_on_plate"] = {"outcome": r.outcome, "theta_max_over_delta": r.theta_max_over_delta,
                                       "t_uplift": r.t_uplift, "n_impacts": r.n_impacts, "overturned": r.overturned,
                                       "u_max": r.u_max}
        if self.one_way is not None:
            out["rocking_one_way"] = {"outcome": self.one_way.outcome,
                                      "theta_max_over_delta": self.one_way.theta_max_over_delta}
        if self.fixed_rocking is not None:
            out["rocking_fixed_base"] = {"outcome": self.fixed_rocking.outcome,
                                         "theta_max_over_delta": self.fixed_rocking.theta_max_over_delta}
        return out


def statue_on_plate(plate: IsolatorResult, rocking_model, compare_fixed: bool = True,
                    rtol: float = 1e-9) -> StatueOnPlate:
    """The statue (a RockingModel) on the plate of ``plate`` (same isolator, motion,
    start and sampling): the coupled plate + statue model decides whether it lifts
    and how it rocks; the one-way estimate (statue driven by the plate-only a_abs)
    and the fixed-base response are given beside it."""
    up, dn = rocking_model.uplift_limits
    dt = float(plate.t[1] - plate.t[0])
    coupled = simulate_coupled(plate.isolator, rocking_model, plate.motion, u0=float(plate.u[0]),
                               v0=float(plate.v[0]), t_end=float(plate.t[-1]), dt_out=dt, rtol=rtol,
                               end_stop=plate.end_stop, e_stop=plate.end_stop_restitution)
    one_way = None
    acc = plate.acc_abs
    n_ok = int(np.argmin(np.isfinite(acc))) if not np.all(np.isfinite(acc)) else acc.size   # up to a capacity stop
    if coupled.uplift and n_ok >= 2:
        one_way = rock(rocking_model, motions.record(acc[:n_ok], dt, label="isolated plate"),
                       t_end=float(plate.t[n_ok - 1]))
    fixed = rock(rocking_model, plate.motion) if compare_fixed and plate.motion.kind != "none" else None
    return StatueOnPlate(plate=plate, limit_pos=up, limit_neg=dn, rocking=coupled, one_way=one_way,
                         fixed_rocking=fixed)
