"""What the statue stands on, for the limit states of sliding and of the pedestal (issue [22]).

A :class:`Support` says how the statue slides on what carries it (its friction, and how far it may
slide toward each side before it leaves its support or passes the allowance) and, when it stands on
a pedestal, the pedestal: the two-block model of the stack (statue2model.rocking.stack) and the
pedestal's own friction on the floor.

Per record (:meth:`Support.run`), the numbers the limit states read (:class:`SupportRecord`):

    statue sliding     the exact rigid-plastic sliding of the statue (statue2model.rocking.sliding)
                       under its support's motion: the ground on the floor; on a pedestal the ground
                       while the pedestal stays in full contact, the acceleration of the pedestal's top
                       under the statue (from the two-block run) when the pedestal rocks
    pedestal sliding   the stack as one rigid-plastic block on the floor (friction mu_pedestal (m1 + m2)
                       g against the inertia (m1 + m2): the equation of one body with mu_pedestal)
    pedestal rocking   the two-block run: the pedestal's lift-off, its peak rotation over its stability
                       angle, its overturning (with the statue), and the statue's rocking on the
                       pedestal's top while the pedestal moves

Sliding and rocking are computed apart: a body that slides is assumed not to rock at the same time
and the reverse (no slide-rock coupling, Shenton 1996). The sliding demand of a body that also lifts
is then that of a body that keeps its full weight on the support: the friction it can mobilise is not
reduced by the uplift, so a slide-rock response can slide farther than computed.

Capacities (m, toward +x and toward -x): the user's ``[sliding] allowance`` when given; else on a
pedestal the distance from the statue's base to the pedestal top's edge on each side (along the
excitation direction, from the rocking parameters: the pivots b_L, b_R about G and the statue's
offset on the top), and on the floor :data:`FLOOR_ALLOWANCE`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InputError
from ..rocking.sliding import Friction, simulate_sliding

FLOOR_ALLOWANCE = 0.05
"""m: how far a body standing on the floor may slide when the user gives no ``[sliding] allowance``: a
convention (a gap a gallery keeps to a wall, a neighbour or a cable), not a measured limit; set the
real gap."""


@dataclass(frozen=True)
class SupportRecord:
    """One record's sliding and pedestal numbers (m; nan where not computed). ``slide_pos`` /
    ``slide_neg``: the statue's peak sliding on its support toward +x / -x; ``ped_slide_pos`` /
    ``ped_slide_neg``: the pedestal's on the floor; ``ped_uplift``, ``ped_overturned``,
    ``ped_theta_max_over_delta``: the pedestal's rocking (with the statue); ``statue``: the statue's
    rocking numbers from the two-block run when the pedestal lifted (a dict of uplift, t_uplift,
    theta_max_over_delta, n_impacts, overturned, outcome), else None (the pedestal stayed in full
    contact: the statue rocks as on the ground)."""

    slide_pos: float
    slide_neg: float
    ped_slide_pos: float = math.nan
    ped_slide_neg: float = math.nan
    ped_uplift: bool = False
    ped_overturned: bool = False
    ped_theta_max_over_delta: float = math.nan
    statue: dict | None = None


@dataclass(frozen=True)
class Support:
    """The statue's support (module docstring). ``friction``: the statue's on its support;
    ``capacity``: (toward +x, toward -x) m; ``capacity_source``: its words ("the allowance", "the
    pedestal top's edge", "the default floor allowance"); ``stack``: the two-block model
    (statue2model.rocking.stack.StackModel) with a pedestal, else None; ``pedestal_friction`` and
    ``pedestal_capacity`` / ``pedestal_capacity_source``: the pedestal's on the floor; ``edge``: the
    statue's capacity is the pedestal top's edge (sliding past it drops the statue off); ``notes``: what the
    limit states should say of the support (one line each: an overhanging base)."""

    friction: Friction
    capacity: tuple[float, float]
    capacity_source: str
    stack: object | None = None
    pedestal_friction: Friction | None = None
    pedestal_capacity: tuple[float, float] | None = None
    pedestal_capacity_source: str = ""
    edge: bool = False
    notes: tuple = ()

    def __post_init__(self):
        for name in ("capacity", "pedestal_capacity"):
            cap = getattr(self, name)
            if cap is None:
                continue
            if len(cap) != 2 or not all(isinstance(c, (int, float)) and math.isfinite(c) and c >= 0 for c in cap):
                raise InputError(f"support: {name} must be two distances >= 0 (m), got {cap!r:.60}")
        if self.stack is not None and self.pedestal_friction is None:
            raise InputError("support: a pedestal needs its friction on the floor")

    @property
    def support_words(self) -> str:
        return "the pedestal's top" if self.stack is not None else "the floor"

    def run(self, motion) -> SupportRecord:
        """The sliding and pedestal numbers of one record ``motion`` (a GroundMotion of the floor)."""
        return self.run_detail(motion)[0]

    def run_detail(self, motion) -> tuple[SupportRecord, object | None]:
        """:meth:`run` and the two-block run behind it (statue2model.rocking.stack.StackResult; None
        without a pedestal): its histories and peak rotations, for whoever reads more than the record's
        numbers (crosscheck/stack_classification.py)."""
        if self.stack is None:
            s = simulate_sliding(self.friction, motion)
            return SupportRecord(s.u_pos, s.u_neg), None
        from ..rocking.bodies import simulate

        r = simulate(self.stack, motion)
        ped = r.pedestal
        statue = None
        top = motion
        if ped.uplift:
            st = r.statue
            statue = {"uplift": bool(st.uplift), "t_uplift": st.uplift_time,
                      "theta_max_over_delta": float(st.theta_max_over_delta), "n_impacts": int(st.n_impacts),
                      "overturned": bool(st.overturned or ped.overturned),   # the pedestal falls with it
                      "outcome": f"on the rocking pedestal: {r.outcome}"}
            top = r.top_motion()
        s = simulate_sliding(self.friction, top)
        p = simulate_sliding(self.pedestal_friction, motion)
        return SupportRecord(s.u_pos, s.u_neg, p.u_pos, p.u_neg, bool(ped.uplift), bool(ped.overturned),
                             float(ped.theta_max_over_delta), statue), r


def edge_distances(b_L: float, b_R: float, x2: float, half_width: float) -> tuple[float, float]:
    """(toward +x, toward -x) m: how far the statue slides before its pivot leaves the pedestal's top:
    its right pivot at x2 + b_R, its left at x2 - b_L, on a top from -half_width to +half_width.

    >>> [round(x, 12) for x in edge_distances(0.1, 0.1, 0.0, 0.3)]
    [0.2, 0.2]
    """
    return (max(half_width - (x2 + b_R), 0.0), max(half_width + (x2 - b_L), 0.0))
