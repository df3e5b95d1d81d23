"""The device's checks, in one place: the spectral design (design.py), the time-history
verification (verify.py) and the limit states (assessment/limit_states.py) all compute the
travel, the felt acceleration, the ball load, the groove depth, the top plate's tipping and the
recentring here (MODEL.md sections 4, 8, 9). SI units throughout.

Each check reads ``value <= limit`` in its unit; ``ratio = value / limit`` (above 1 it fails by
that factor). A required check decides; an advisory one is reported.

Travel. The grooves must give the travel

    need = margin x u + mu_high R_hat                                     (travel_need)

u the plate's peak travel relative to the ground (the spectral displacement SDe(T), or the
statistic of the records' peaks), mu_high R_hat where friction may have left the plate resting
off centre after an earlier shake (static equilibrium k |u| <= mu W, at the upper friction bound).
At the design level margin = DISPLACEMENT_MARGIN = GAMMA_X x BIDIRECTIONAL = 1.5: EN 1998-1
10.3(2) designs isolator displacements for gamma_x d (1.2), and a spherical groove travels along
the vector sum of both horizontal components, whose peak exceeds the one-component value by about
1.25 at these periods (maximum-direction factors, e.g. 1.3 at T >= 1 s in ASCE 7-16 21.2). At the
collapse level (SLC, hazard/levels.py) margin = BIDIRECTIONAL alone: the level itself carries the
reliability (on an EC8 site the SLC spectrum is gamma_x x the design one, so the two rules agree).
Reserve (never worse than no device): every design record scaled to the PGA where half of them
overturn the statue on a fixed base, the median travel x RESERVE_MARGIN + mu_high R_hat.

Capacity (m): the lesser of the groove rim and the top plate's tipping,

    u_groove = a R_hat / R                                   device.groove_capacity
    u_tip    = (L_cr - mu_high l) R_hat / (R + l)            tipping_capacity

(a the grooves' opening radius, L_cr the distance from the plate centre to the nearest edge of the
balls' hull, layout.py, l the lever arm of eq. 47).

Ball load (N). Static: W / n on each ball (rigid plates, grooves cut in one set-up) against the
surface's long-term capacity (bearing.ball_capacity). Dynamic, at the collapse level: the felt
acceleration a tips the load onto the outer balls, W / n + M a l / spread (layout.spread: the most
loaded ball of a rigid plate under the overturning moment M a l), against the short-term capacity.

>>> round(travel_need(0.2, 0.0108, 3.0), 4)           # 1.5 x 0.2 + 0.0108 x 3.0
0.3324
>>> round(tipping_capacity(0.2, 0.3, 0.32, 0.02, 0.0), 4)
0.1935
>>> round(dynamic_ball_load(1000.0, 4, 100.0, 1.0, 0.5, 1.414), 2)   # W / n + M a l / spread
285.36
"""
from __future__ import annotations

import math
from typing import NamedTuple

GAMMA_X = 1.2
"""EN 1998-1 10.3(2): reliability factor on the isolators' displacements (hazard/levels.py)."""
BIDIRECTIONAL = 1.25
"""Peak of the two horizontal components' vector sum over one component's, at the isolator's periods."""
DISPLACEMENT_MARGIN = GAMMA_X * BIDIRECTIONAL
"""Travel need / the design level's displacement: 1.5."""
SLC_MARGIN = BIDIRECTIONAL
"""Travel need / the collapse level's displacement: 1.25."""
RESERVE_MARGIN = 1.05
"""Travel need / the median travel where half the design records overturn the fixed base: 5 % for what the
reserve's nominal runs leave out of the fragility study (its parameter samples and its lognormal fit)."""
RESERVE_LEVEL = 3.0
"""The reserve is sought up to this multiple of the design PGA (assessment/study.py AUTO_LEVELS' top):
a record that does not overturn the fixed statue below it is taken there."""
MIN_BOTTOM = 0.005
"""m of wood (or sheet) left under the deepest point of a groove or pocket."""
MIN_GAP = 0.002
"""m: least clearance between the plates; the balls stand 2 (r - depth) proud."""
EDGE = 0.02
"""m of wood between a groove opening and the plate edge."""
GAP = 0.01
"""m of wood between two groove openings."""
MIN_WALL = 0.005
"""m of wood between a fuse seat or drop hole and any other cutout or the edge (plates.py)."""
RESTORING = 0.025
"""Least restoring-force increase, as a fraction of W, from half the design displacement to all of it
(ASCE 7-16 17.2.4.4): R_hat <= d / (2 RESTORING) = 20 d. Advisory."""
SIDE_MAX = 1.5
"""m: the largest plate side: the bed of a common CNC router (1500 x 3000 mm, a "1530" machine) and the width
of standard polymer sheets (1500 x 3000 mm); a wooden plate that wide is glued from two panels. ``[isolator]
side_max`` sets another (1.25 m: a 1250 x 2500 mm bed)."""


class Lazy:
    """A check's explanation built when it is first read (a search evaluates thousands of checks and shows a
    few): ``str()`` of it, or ``+`` a string, gives the text."""

    __slots__ = ("_make", "_text")

    def __init__(self, make):
        self._make, self._text = make, None

    def __str__(self) -> str:
        if self._text is None:
            self._text = self._make()
        return self._text

    def __add__(self, other: str) -> str:
        return str(self) + other

    def __format__(self, spec: str) -> str:
        return format(str(self), spec)

    def __eq__(self, other) -> bool:
        return str(self) == str(other)

    __hash__ = None


class Check(NamedTuple):
    """One check: passes when value <= limit (both in ``unit``). ``level``: "design", "SLC",
    "reserve" or "static"; ``key`` its identifier. (A named tuple: a search builds hundreds of thousands.)"""

    name: str
    passed: bool
    value: float
    limit: float
    why: str
    required: bool = True
    unit: str = "-"
    key: str = ""
    level: str = "design"

    @property
    def ratio(self) -> float:
        """value / limit: above 1 the check fails by that factor (inf: no positive limit)."""
        if self.limit > 0:
            return self.value / self.limit
        return 0.0 if self.value <= self.limit else math.inf

    def to_dict(self) -> dict:
        ratio = self.ratio
        fin = lambda x: x if math.isfinite(x) else None                 # noqa: E731 (JSON has no inf)
        return {"name": self.name, "key": self.key, "passed": self.passed, "value": fin(self.value),
                "limit": fin(self.limit), "unit": self.unit, "ratio": fin(ratio), "required": self.required,
                "level": self.level, "why": str(self.why)}


def travel_need(u: float, mu_high: float, R_hat: float, margin: float = DISPLACEMENT_MARGIN) -> float:
    """m: the travel the grooves must give for a plate travel ``u`` (m) (module docstring)."""
    return margin * u + mu_high * R_hat


def tipping_capacity(L_cr: float, l: float, R: float, r: float, mu: float) -> float:
    """Largest relative displacement u_o (m) of the top plate before it tips: (L_cr - mu l) R_hat /
    (R + l). When the plate moves u_o the balls' contact points move back u_o R / R_hat relative to it,
    so the tipping line is L_cr - u_o R / R_hat from the plate centre; there the grooves push plate
    and statue with g (u_o / R_hat + mu), moving the resultant out by (u_o / R_hat + mu) l (eqs. 47, 48).
    <= 0 when friction alone tips it."""
    return (L_cr - mu * l) * 2.0 * (R - r) / (R + l)


def groove_depth(R: float, a: float) -> float:
    """m: depth of a spherical cap of radius R opening on a circle of radius a <= R (no cancellation)."""
    return a * a / (R + math.sqrt(max((R - a) * (R + a), 0.0)))


def dynamic_ball_load(W: float, n: int, M: float, a: float, l: float, spread: float) -> float:
    """N: the most loaded ball's load, W / n + M a l / spread, under the felt acceleration ``a`` (m/s^2)
    of the supported mass ``M`` (kg) at lever arm ``l`` (m) on ``n`` balls of ``spread`` (m, layout.py)."""
    return W / n + M * a * l / spread


def recentring_limit(d: float) -> float:
    """m: the largest R_hat whose restoring force grows RESTORING W from d / 2 to d (ASCE 7-16 17.2.4.4)."""
    return d / (2 * RESTORING)


def travel_check(need: float, capacity: float, why: str, level: str = "design", key: str = "travel") -> Check:
    names = {"design": "travel capacity covers the design level with its margin",
             "SLC": "travel capacity covers the collapse level (SLC)",
             "reserve": "travel reserve up to where the statue overturns without the device"}
    return Check(names.get(level, "travel capacity"), need <= capacity * (1 + 1e-9), need, capacity, why, unit="m",
                 key=key, level=level)


def acceleration_check(felt: float, a_lim: float, why: str, key: str = "acceleration", required: bool = True,
                       name: str = "plate acceleration below the statue's uplift limit") -> Check:
    return Check(name, felt <= a_lim, felt, a_lim, why, required=required, unit="m/s^2", key=key)


def ball_load_check(P: float, capacity: float, why: str, level: str = "static", key: str = "ball_load") -> Check:
    name = ("load per ball within what the grooves carry" if level == "static"
            else "most loaded ball within what the grooves carry at SLC")
    return Check(name, P <= capacity, P, capacity, why, unit="N", key=key, level=level)
