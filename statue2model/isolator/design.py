"""Design of a rolling-ball isolator for one statue and one hazard (thesis ch. 5.1, 5.3, 6.4).

Input: the statue's rocking parameters (m, h, b_L, b_R, a_L, a_R; the uplift limits
reduced by alpha when the base is imperfect), a rolling friction coefficient mu and a
design input: an elastic response spectrum (EC8 / NTC 2018, hazard/code_spectra.py) or a
ground motion simulated on every candidate. Optionally a stricter target for the plate's
absolute acceleration, and a fuse (release mechanism, eq. 52). SI units throughout.

Travel capacity of a device (m): the largest relative displacement u_o of the top plate
before a ball leaves its groove or the top plate tips, ``capacity = min(u_groove, u_tip)``:

    u_groove = a R_hat / R                        device.groove_capacity (a: opening radius)
    u_tip    = (L_cr - mu l) R_hat / (R + l)      tipping_capacity

u_tip is eqs. 47-49 written in the top plate's frame at the displacement itself. When the
plate moves u_o, the balls' contact points move back u_o R / R_hat relative to the plate
(groove_capacity's derivation), so the tipping line through the outer balls is
L_cr - u_o R / R_hat from the plate centre (L_cr: half the groove spacing for 4 grooves,
the triangle's inradius for 3). There the grooves push plate and statue with
g (u_o / R_hat + mu), which moves the resultant of the weights out by the safety length
a = (u_o / R_hat + mu) l (eqs. 47, 48; l the lever arm). The plate tips when
a = L_cr - u_o R / R_hat. The thesis' own check, eq. 49 at the design acceleration
(d <= d_max = L_cr - (a_design / g) l, the displacement not reduced by R / R_hat), is kept
as a separate required check.

Demand (spectrum): a_design = Se(T) and d = SDe(T) at T = 2 pi sqrt(R_hat / g) (ch. 6.4);
(motion): the simulated peaks of |a_abs| and |u_o|. The travel the grooves must give is

    need = DISPLACEMENT_MARGIN d + mu R_hat

DISPLACEMENT_MARGIN (1.5) covers what SDe does not, as a stated judgement: EN 1998-1
§10.3(2) designs isolator displacements for gamma_x d with gamma_x = 1.2 (reliability of
the isolation system), and a spherical groove travels along the vector sum of both
horizontal components, whose peak exceeds the one-component spectral value by about
1.25-1.3 at these periods (maximum-direction factors, e.g. 1.3 at T >= 1 s in ASCE 7-16
§21.2): 1.2 x 1.25 = 1.5. mu R_hat is where friction may have left the plate resting off
centre after an earlier shake or a push (static equilibrium k |u| <= mu W); the next
earthquake starts from there.

Checks (each one reads value <= limit, in the stated unit; ratio = value / limit, so a
ratio above 1 fails by that factor):

    acceleration   a_design <= a_lim = min(alpha_L a_L, alpha_R a_R[, target])       m/s^2
    friction       mu g <= a_lim (else the statue rocks before the plate rolls)       m/s^2
    travel         need <= capacity                                                   m
    overturning    d <= d_max = L_cr - (a_design / g) l (eq. 49)                      m
    depth          groove depth <= board - MIN_BOTTOM                                 m
    proud          groove depth <= r - MIN_GAP / 2 (the plates stay apart)            m
    plate size     side <= SIDE_MAX                                                   m
    fuse           release <= a_lim; MIN_WALL <= the least wood around its seats     m/s^2, m
    ball load      W / n <= P_20 (r / BALL_TESTED)^2                                   N
  advisory (reported, not required):
    a_design + mu g <= a_lim (friction transmits up to mu g; the thesis checks Se alone)  m/s^2
    recentring     R_hat <= d / (2 RESTORING) = 20 d (ASCE 7-16 §17.2.4.4)             m

The ball load is required: heavier loads leave pits in the grooves that shorten the period
and trap the balls (ch. 5.2). P_20 (``ball_capacity``, N per ball of BALL_TESTED = 20 mm
radius) is what the grooves' material carries: by default BALL_LOAD_TESTED, the thesis'
beech grooves (30 kg on four 20 mm balls undamaged, ch. 6.4), the only measured point; a
load test of another surface (a hardwood, resin or metal insert, a rubber layer) gives its
own, converted to a 20 mm ball by the same (0.02 / r_test)^2. No material capacity is
assumed without such a test. What raises it: a harder surface, a rubber layer, more balls
(W / n) or larger ones (r^2).

Search: every ball radius in BALLS, groove radius in R_GRID, 3 and 4 grooves and every
board in THICKNESSES (or the ones given). Each candidate is sized, then checked: the
opening radius gives u_groove = need exactly (need: the larger of the spectral need and
``travel_floor[(R, r)]`` when given, the time histories' need of isolator/verify.py); the
groove spacing gives u_tip >= need and d <= d_max, with l taken at its largest (top
plate's mass neglected); the plate is at least the statue's base (2 max(b_L, b_R) + 2 EDGE)
and is capped at SIDE_MAX (the checks then say what is missing); the grooves are spread out
to the plate's edge (EDGE of wood left), which only adds capacity; fuse seats go on the
bisectors between the grooves, at the radius (FUSE_RADII) that leaves the most wood.

Choice (CRITERION, of the spectral search; the pipeline re-ranks the candidates by their
time-history margins, verify.py's CRITERION): among the candidates that pass every required
check, those whose top plate is within PLATE_TOLERANCE (10 %) of the lightest passing one; of these, the least
overload of the balls, then the least shortfall of the restoring force, then the largest
acceleration margin a_lim / a_design, then the smaller side, the thinner board, 3 grooves
before 4, the larger ball. Beyond the spectrum's T_D the spectral displacement no longer
grows with the period, so a longer period lowers the felt acceleration at no cost in
travel: for strong hazards the longest R in range wins; for weak ones the restoring-force
rule keeps R_hat within 20 d. When none passes, the nearest candidate (fewest failing
required checks, then the smallest worst ratio) is shown with passed False, and
``failure`` says which checks fail and by how much, with the ranges searched. Every
evaluated candidate is kept in ``Design.evaluated`` (:class:`Candidate`, not serialised) for
the time-history verification (isolator/verify.py), which re-ranks them.

Example
-------
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard.code_spectra import ec8
>>> statue = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.8})
>>> d = design(statue, spectrum=ec8(0.05 * 9.80665, "A"), mu=0.0073, thickness=0.03)
>>> d.passed, d.R, d.r, d.n_grooves, round(d.T, 2), round(d.side, 3)   # the statue's base sets the plate
(True, 0.2, 0.04, 3, 1.13, 0.439)
>>> round(d.d_design, 4), round(d.travel_need, 4), round(d.capacity, 4), d.capacity_limited_by
(0.0141, 0.0235, 0.024, 'groove rim')
>>> bad = design(statue, spectrum=ec8(0.05 * 9.80665, "A"), mu=0.0073, alpha=(0.02, 0.02))
>>> bad.passed, bad.failure.split(":")[0]
(False, "rolling friction below the statue's uplift limit")
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import InputError
from ..geometry.units import PLAUSIBLE
from .device import (
    G,
    Isolator,
    allowable_displacement,
    check_lengths,
    fuse_release_acceleration,
    fuse_seat_depth,
    groove_capacity,
    lever_arm,
    safety_length,
)

BALLS = (0.0095, 0.0125, 0.0183, 0.020, 0.025, 0.030, 0.040, 0.050)
"""Ball radii tried (m): the thesis' steel 9.5 mm, resin 18.3 mm, ivory 20 mm, and larger ones
for heavier statues (the ball load grows as r^2). A larger ball leaves the groove depth alone
(it is set by R and the opening) and only passes the "proud" check more easily; what it costs
is the gap between the plates, 2 (r - depth), which the top plate rides on and the fuse balls
must fill (about 85 mm at r = 50 mm). 50 mm (100 mm balls, a stock size of steel and ceramic
balls) is the largest: it is 2.5 times the tested 20 mm, so its capacity is already 6.25 times
the only measured load, the furthest this one-point r^2 scaling is taken."""
R_GRID = tuple(float(x) for x in np.round(np.arange(0.20, 2.0001, 0.05), 3))
"""Groove radii tried (m), 0.20 to 2.00: up to R = 2.0 m the period stays within about 4 s
(4.003 s with 9.5 mm balls), the range over which EN 1998-1 §3.2.2.2 defines the elastic
spectrum."""
THICKNESSES = (0.02, 0.03, 0.04, 0.05)
"""Board thicknesses tried (m) when none is given; the thesis' plates were 30 mm beech."""
SIDE_MAX = 1.25
"""Largest plate side, m: a standard panel width and CNC bed (2500 x 1250 mm)."""
PLATE_TOLERANCE = 0.10
"""Top plates within 10 % of the lightest passing one count as equally small (CRITERION)."""
DISPLACEMENT_MARGIN = 1.5
"""Travel need / spectral displacement: EN 1998-1 §10.3(2) gamma_x = 1.2 times about 1.25
for the two horizontal components on a spherical groove (module docstring)."""
BALL_LOAD_TESTED = 30.0 * G / 4
"""N per ball: the thesis' four-groove beech device carried up to 30 kg on its 20 mm balls
undamaged (ch. 6.4); heavier loads on 9.5 and 18.3 mm balls left pits (ch. 5.2). The default
``ball_capacity`` of :func:`design` (the grooves' per-ball capacity on a 20 mm ball)."""
BALL_TESTED = 0.020
"""Radius (m) of the balls of that test. For another radius r the load is scaled by
(r / BALL_TESTED)^2: the same Hertz contact pressure on a ball in a groove much wider
than the ball (p_max ~ (P / r^2)^(1/3)). An assumption from one measured point."""
SIZING_CLEARANCE = 0.01
"""The grooves are cut for the travel need plus 1 %, and the opening radius is rounded up to
OPENING_STEP: a capacity sized to exactly the need would leave the time-history check resting on
the last digit (a margin of 1.0000), where any other run of the same records may tip it over."""
OPENING_STEP = 0.0005
"""Groove opening radii are whole multiples of 0.5 mm (the drawing's precision), rounded up."""
MIN_BOTTOM = 0.005
"""Wood left under the deepest point of a groove, m."""
EDGE = 0.02
"""Wood between a groove opening and the plate edge, m."""
GAP = 0.01
"""Wood between two groove openings, m."""
MIN_GAP = 0.002
"""Least clearance between the plates, m: the balls stand 2 (r - depth) proud."""
MIN_WALL = 0.005
"""Wood between a fuse seat or drop hole and any other cutout or the edge, m (plates.py)."""
RESTORING = 0.025
"""Least restoring force increase, as a fraction of W, from half the design displacement to
all of it (ASCE 7-16 §17.2.4.4, NBC 2015 4.1.8.20(2)): for the pendulum F(d) - F(d/2) =
W d / (2 R_hat), i.e. R_hat <= d / (2 RESTORING) = 20 d. Advisory here (a building code's
rule against ratcheting; the thesis' Venere device, d = 24 mm on R_hat = 0.60 m, misses
it), but preferred by CRITERION."""
WOOD_DENSITY = 700.0
"""Beech, kg/m^3 (the thesis' plates)."""
SHOWN_PASSING = 30
"""design.json lists at most this many passing candidates (best first) ..."""
SHOWN_FAILING = 10
"""... and this many failing ones (nearest to passing first)."""
BALL_CAPACITY_SOURCE = "the thesis' beech grooves, 30 kg on four 20 mm balls undamaged (ch. 6.4)"
"""Where the default per-ball capacity comes from (design.json, the ball-load check)."""
CRITERION = (f"the smallest plate (top plate mass within {PLATE_TOLERANCE:.0%} of the lightest passing one); "
             "among those the least overload of the balls (load per ball / tested load if above 1, to 2 "
             "digits), then the least shortfall of the restoring force (R_hat / 20 d if above 1, to 2 digits), "
             "then the largest acceleration margin a_lim / a_design (to 0.01: the longest period that fits), then the "
             "smaller side (to 1 mm), the thinner board, 3 grooves before 4 (three balls always share the load), "
             "the larger ball")


@dataclass(frozen=True)
class Check:
    """One design check: passes when value <= limit (both in ``unit``)."""

    name: str
    passed: bool
    value: float
    limit: float
    why: str
    required: bool = True
    unit: str = "-"
    key: str = ""

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
                "limit": fin(self.limit), "unit": self.unit, "ratio": fin(ratio),
                "required": self.required, "why": self.why}


@dataclass(frozen=True)
class Design:
    R: float
    r: float
    n_grooves: int
    mu: float
    M: float                 # statue + top plate, kg
    m_o: float               # top plate, kg
    T: float
    k: float
    R_hat: float
    a_design: float          # plate absolute acceleration, m/s^2
    a_lim: float
    d_design: float          # design displacement of the top plate, m
    d_max: float             # eq. 49 at the design acceleration, m
    lever_arm: float
    safety_length: float
    L_cr: float
    spacing: float           # groove centre spacing, m
    side: float              # square plate side, m
    thickness: float
    depth: float             # groove depth, m
    opening_radius: float
    groove_centres: tuple
    fuse: dict
    checks: tuple
    input: dict
    candidates_tried: int
    notes: tuple = field(default=())
    capacity: float = 0.0            # min(capacity_groove, capacity_tip), m
    capacity_groove: float = 0.0     # a ball's contact point reaches its groove's rim, m
    capacity_tip: float = 0.0        # the top plate tips, m
    travel_need: float = 0.0         # DISPLACEMENT_MARGIN d_design + mu R_hat, m
    margin: float = DISPLACEMENT_MARGIN
    candidates: dict = field(default_factory=dict)
    failure: str | None = None       # why nothing in range works (None when passed)
    criterion: str = CRITERION
    ball_capacity: float = BALL_LOAD_TESTED   # N per 20 mm ball the grooves carry (the ball-load check)
    ball_capacity_source: str = BALL_CAPACITY_SOURCE
    verification: dict = field(default_factory=dict)    # the time-history verification (verify.py)
    what_would_pass: dict | None = None                 # when nothing passes: what would (verify.py)
    evaluated: tuple = field(default=(), repr=False, compare=False)   # every Candidate (not serialised)

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks if c.required)

    @property
    def capacity_limited_by(self) -> str:
        return "groove rim" if self.capacity_groove <= self.capacity_tip else "top plate tipping"

    @property
    def th_margins(self) -> dict | None:
        """The time-history margins {travel, acceleration, bearing} (limit / demand, > 1 passes) when
        the design was verified (verify.py), else None."""
        return self.verification.get("margins") if self.verification else None

    def isolator(self, model: str = "coulomb", q: float = 30.0) -> Isolator:
        return Isolator(R=self.R, r=self.r, M=self.M, mu=self.mu, model=model, q=q, capacity=self.capacity)

    def to_dict(self) -> dict:
        out = {k: getattr(self, k) for k in (
            "R", "r", "R_hat", "T", "k", "n_grooves", "mu", "M", "m_o", "a_design", "a_lim", "d_design", "d_max",
            "capacity", "capacity_groove", "capacity_tip", "travel_need", "margin", "lever_arm",
            "safety_length", "L_cr", "spacing", "side", "thickness", "depth", "opening_radius",
            "fuse", "input", "candidates_tried", "failure", "criterion")}
        out["capacity_limited_by"] = self.capacity_limited_by
        out["travel_margin"] = self.capacity / self.d_design if self.d_design > 0 else None
        out["acceleration_margin"] = self.a_lim / self.a_design if self.a_design > 0 else None
        out["groove_centres"] = [list(c) for c in self.groove_centres]
        out["passed"] = self.passed
        out["checks"] = [c.to_dict() for c in self.checks]
        out["candidates"] = self.candidates
        out["notes"] = list(self.notes)
        out["ball_capacity"] = {"tested_load": self.ball_capacity, "tested_radius": BALL_TESTED,
                                "per_ball": self.ball_capacity * (self.r / BALL_TESTED) ** 2,
                                "source": self.ball_capacity_source,
                                "scaling": f"per-ball capacity = tested_load x (r / {BALL_TESTED:g} m)^2"}
        out["verification"] = self.verification or None
        out["th_margins"] = self.th_margins
        out["what_would_pass"] = self.what_would_pass
        out["schema"] = "statue2model.isolator_design/3"
        return out

    def report(self) -> str:
        """design.txt: the device, the checks (one unit column) and the choice."""
        lines = [f"Rolling-ball isolator: {'PASS' if self.passed else 'FAIL'}"]
        if self.failure:
            lines.append(f"  no isolator in range works: {self.failure}")
            lines.append("  nearest candidate:")
        lines += [
            f"  grooves R = {self.R:.3f} m, balls r = {self.r:.4f} m, R_hat = {self.R_hat:.3f} m, "
            f"T = {self.T:.2f} s, k = {self.k:.1f} N/m, {self.n_grooves} grooves",
            f"  plates {self.side:.3f} m x {self.side:.3f} m x {self.thickness:.3f} m "
            f"(top plate {self.m_o:.2f} kg), groove spacing {self.spacing:.3f} m, depth {self.depth:.4f} m, "
            f"opening radius {self.opening_radius:.4f} m",
            f"  felt acceleration {self.a_design:.4f} m/s^2 vs uplift limit {self.a_lim:.4f} m/s^2 "
            f"(margin {self.a_lim / self.a_design:.2f})" if self.a_design > 0 else
            f"  felt acceleration 0 vs uplift limit {self.a_lim:.4f} m/s^2",
            f"  travel: demand {self.d_design:.4f} m x {self.margin:g} + mu R_hat {self.mu * self.R_hat:.4f} m = "
            f"{self.travel_need:.4f} m vs capacity {self.capacity:.4f} m ({self.capacity_limited_by}; groove "
            f"{self.capacity_groove:.4f} m, tipping {self.capacity_tip:.4f} m)",
            "",
            "checks (each passes when value <= limit; ratio = value / limit):",
        ]
        rows = [("result", "check", "value", "limit", "unit", "ratio")]
        for c in self.checks:
            mark = "pass" if c.passed else ("FAIL" if c.required else "note")
            ratio = c.ratio
            rows.append((mark, c.name, f"{c.value:.5g}", f"{c.limit:.5g}", c.unit,
                         f"{ratio:.3f}" if math.isfinite(ratio) else "inf"))
        widths = [max(len(r[i]) for r in rows) for i in range(6)]
        for r in rows:
            lines.append("  " + "  ".join(s.ljust(w) if i in (0, 1, 4) else s.rjust(w)
                                          for i, (s, w) in enumerate(zip(r, widths))).rstrip())
        lines += ["", "why:"] + [f"  {c.name}: {c.why}" for c in self.checks]
        cand = self.candidates or {}
        lines += ["", f"choice: {self.criterion}",
                  f"  {cand.get('passing', 0)} of {self.candidates_tried} candidates pass every required check"
                  + (f"; ranges: {cand['ranges']}" if cand.get("ranges") else "")]
        lines += [f"  {n}" for n in self.notes]
        if self.verification:
            lines += [""] + _verification_lines(self)
        return "\n".join(lines)


def _verification_lines(d) -> list[str]:
    """design.txt's time-history part (isolator/verify.py): the margins, the records and the
    candidates' margins table."""
    v = d.verification
    m = v["margins"]
    rec = v["records"]
    met = {True: ", the set's rules met", False: ", the set's rules NOT met", None: ""}[rec.get("rules_met")]
    fmt = lambda x: "inf" if x is None else f"{x:.2f}"                # noqa: E731
    lines = [f"time-history verification ({v['model']}): {rec['count']} records ({rec['source']}{met}), the "
             f"{v['statistic']} over the records, mu_low {v['mu_low']:.4g} and mu_high {v['mu_high']:.4g}",
             f"  margins (limit / demand, > 1 passes): travel {fmt(m['travel'])}, acceleration "
             f"{fmt(m['acceleration'])}, bearing {fmt(m['bearing'])}; balance {fmt(v['balance'])}",
             f"  capacity sized on the {v['demand']['capacity_sized_on']}: need {v['demand']['travel_need']:.4f} m "
             f"(time histories) vs {v['demand']['spectral_need']:.4f} m (spectrum); capacity "
             f"{v['demand']['capacity']:.4f} m"]
    lines += [f"  {k}: {text}" for k, text in v["definitions"].items()]
    rows = [("R m", "r mm", "n", "T s", "side m", "plate kg", "travel", "accel", "bearing", "balance", "result")]
    for row in (d.candidates.get("rows") or [])[:10]:
        mg = row.get("margins")
        if not mg:
            continue
        rows.append((f"{row['R']:g}", f"{row['r'] * 1000:g}", str(row["n_grooves"]), f"{row['T']:.2f}",
                     f"{row['side']:.3f}", f"{row['m_o']:.2f}", fmt(mg["travel"]), fmt(mg["acceleration"]),
                     fmt(mg["bearing"]), fmt(row["balance"]), "pass" if row["passed"] else "FAIL"))
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    lines += ["", f"candidates by the criterion (first 10 of {d.candidates.get('verified', 0)} verified; "
                  f"{d.candidates.get('passing', 0)} pass):"]
    lines += ["  " + "  ".join(s.rjust(w) for s, w in zip(r, widths)) for r in rows]
    if d.what_would_pass:
        lines += ["", "what would pass: " + d.what_would_pass["text"]]
    return lines


def tipping_capacity(L_cr: float, l: float, R: float, r: float, mu: float) -> float:
    """Largest relative displacement u_o (m) of the top plate before it tips (module
    docstring): (L_cr - mu l) R_hat / (R + l), with L_cr the distance from the plate
    centre to the tipping line through the balls at rest (m), l the lever arm (eq. 47, m),
    R, r the groove and ball radii (m) and mu the rolling friction; <= 0 when even
    friction alone tips it.

    >>> round(tipping_capacity(0.2, 0.3, 0.32, 0.02, 0.0), 4)
    0.1935
    """
    return (L_cr - mu * l) * 2.0 * (R - r) / (R + l)


def _cap_depth(R: float, a: float) -> float:
    """Depth of a spherical cap of radius R opening on a circle of radius a <= R (no cancellation)."""
    return a * a / (R + math.sqrt(max((R - a) * (R + a), 0.0)))


def _layout(n: int, spacing: float) -> tuple[tuple, float]:
    """Groove centres (plate centre at 0) and L_cr, the distance from the centre to
    the nearest tipping line through the balls."""
    if n == 4:
        h = spacing / 2
        return ((-h, -h), (h, -h), (h, h), (-h, h)), h
    if n == 3:
        rad = spacing / math.sqrt(3)                 # circumradius of the triangle
        pts = tuple((rad * math.cos(math.radians(90 + 120 * i)), rad * math.sin(math.radians(90 + 120 * i)))
                    for i in range(3))
        return pts, spacing / (2 * math.sqrt(3))     # inradius
    raise InputError(f"number of grooves must be 3 or 4, got {n}")


def _spacing_for_extent(n: int, ext: float) -> float:
    """Groove spacing whose layout reaches ``ext`` (largest |x| or |y| of a centre)."""
    return 2 * ext if n == 4 else math.sqrt(3) * ext


def _extent_for_L(n: int, L_cr: float) -> float:
    return L_cr if n == 4 else 2 * L_cr


def _extent_min(n: int, a: float) -> float:
    """Smallest extent with GAP of wood between neighbouring openings."""
    return (2 * a + GAP) / 2 if n == 4 else (2 * a + GAP) / math.sqrt(3)


@dataclass(frozen=True)
class _Geometry:
    R: float
    r: float
    n: int
    thickness: float
    a: float                 # opening radius
    depth: float
    spacing: float
    centres: tuple
    L_cr: float
    side: float
    side_needed: float = 0.0   # the side the need asks for before the SIDE_MAX cap, m
    need: float = 0.0          # the travel the opening was sized on, m


@dataclass(frozen=True)
class _Context:
    m: float
    h: float
    mu: float
    g: float
    a_lim: float
    why_lim: str
    margin: float
    side_max: float
    wood_density: float
    fuse_release: float | None
    fuse_ball: float | None
    ball_capacity: float = BALL_LOAD_TESTED
    ball_source: str = BALL_CAPACITY_SOURCE


def _size(R, r, n, t, a_design, d, cx: _Context, min_side: float, floor: float = 0.0) -> _Geometry:
    """Grooves and plate of one candidate for the demand (a_design, d), the opening covering at
    least the travel ``floor`` (m); see the module."""
    R_hat = 2 * (R - r)
    need = max(cx.margin * d + cx.mu * R_hat, floor)
    sized = need * (1.0 + SIZING_CLEARANCE)        # the travel the grooves are cut for (SIZING_CLEARANCE)
    a = min(max(math.ceil(sized * R / R_hat / OPENING_STEP) * OPENING_STEP, 1e-6), R)
    depth = _cap_depth(R, a)
    l0 = cx.h + t                                  # lever arm without the plate's mass: the largest
    L_need = max(sized * (R + l0) / R_hat + cx.mu * l0, d + safety_length(a_design, l0, cx.g))
    ext_min = _extent_min(n, a)
    ext = max(_extent_for_L(n, L_need), ext_min)
    side = side_needed = max(2 * (ext + a + EDGE), min_side)
    if side > cx.side_max:                         # capped: the checks then say what is missing
        side = max(cx.side_max, min_side, 2 * (ext_min + a + EDGE))
    ext = side / 2 - a - EDGE                      # spread the grooves to the plate's edge
    spacing = _spacing_for_extent(n, ext)
    centres, L_cr = _layout(n, spacing)
    return _Geometry(R, r, n, t, a, depth, spacing, centres, L_cr, side, side_needed, need)


def _fuse(geo: _Geometry, cx: _Context) -> dict:
    """The fuse balls carry the plate at rest: diameter = the gap between the plates + two
    seats, 2 r_f = 2 (r - depth) + 2 z with z = c r_f (eq. 52 solved for z)."""
    c = fuse_seat_depth(1.0, cx.fuse_release, cx.g)
    gap = 2 * (geo.r - geo.depth)
    r_f = gap / 2 / (1.0 - c) if cx.fuse_ball is None else cx.fuse_ball
    if not r_f > 0:                                # the plates touch: no room for a fuse ball
        return {"ball_radius": 0.0, "seat_depth": 0.0, "release": None, "release_g": None, "gap": gap}
    z = fuse_seat_depth(r_f, cx.fuse_release, cx.g)
    back = fuse_release_acceleration(r_f, z, cx.g)
    return {"ball_radius": r_f, "seat_depth": z, "release": back, "release_g": back / cx.g, "gap": gap}


FUSE_RADII = (0.2, 0.35, 0.5, 0.65, 0.8)
"""Fuse seats sit on the bisectors between neighbouring grooves, at one of these fractions
of the grooves' distance from the plate centre (the one leaving the most wood)."""


def _fuse_layout(geo: _Geometry, fuse: dict) -> tuple[tuple, float]:
    """Fuse seat centres (one between each pair of neighbouring grooves) and the least wood
    (m) they leave between the bottom plate's cutouts (grooves, seats, drop holes, laid out
    as plates.py does) and between each and the plate's edge."""
    from .plates import _fuse_geometry

    c = np.asarray(geo.centres, dtype=float)
    ang = np.sort(np.arctan2(c[:, 1], c[:, 0]))
    mid = (ang + np.diff(np.append(ang, ang[0] + 2 * math.pi)) / 2)        # bisectors
    rho_g = float(np.hypot(c[:, 0], c[:, 1]).mean())
    grooves = np.column_stack([c, np.full(len(c), geo.a)])
    best = ((), -math.inf)
    for f in FUSE_RADII:
        seats = tuple((f * rho_g * math.cos(t), f * rho_g * math.sin(t)) for t in mid)
        fg = _fuse_geometry(dict(fuse, centres=seats), {"groove_centres": geo.centres, "thickness": geo.thickness})
        rf, z, off = fg["fuse_ball_radius"], fg["fuse_seat_depth"], fg["fuse_hole_offset"]
        s = np.asarray(seats)
        u = s / np.hypot(s[:, 0], s[:, 1])[:, None]
        circ = np.vstack([grooves,
                          np.column_stack([s, np.full(len(s), math.sqrt(max(2 * rf * z - z * z, 0.0)))]),
                          np.column_stack([s + off * u, np.full(len(s), fg["fuse_hole_diameter"] / 2)])])
        edge = float((geo.side / 2 - np.abs(circ[:, :2]).max(axis=1) - circ[:, 2]).min())
        diff = circ[:, None, :2] - circ[None, :, :2]
        dist = np.hypot(diff[..., 0], diff[..., 1]) - circ[:, None, 2] - circ[None, :, 2]
        wall = min(edge, float(dist[np.triu_indices(len(circ), 1)].min()))
        if wall > best[1]:
            best = (seats, wall)
    return best


def _evaluate(geo: _Geometry, a_design: float, d: float, cx: _Context) -> dict:
    """Every number and check of one device under the demand (a_design, d)."""
    R, r, t, g, mu = geo.R, geo.r, geo.thickness, cx.g, cx.mu
    R_hat = 2 * (R - r)
    n = geo.n
    z = min(geo.depth, t)                          # a groove deeper than the board fails "depth" anyway
    m_o = cx.wood_density * max(geo.side ** 2 * t - n * math.pi * z * z * (3 * R - z) / 3, 0.5 * geo.side ** 2 * t)
    l = lever_arm(cx.m, cx.h, m_o, t)
    a_s = safety_length(a_design, l, g)
    d_max = allowable_displacement(geo.L_cr, a_s)
    cap_g = groove_capacity(R, r, geo.a)
    cap_t = tipping_capacity(geo.L_cr, l, R, r, mu)
    cap = min(cap_g, cap_t)
    need = cx.margin * d + mu * R_hat
    a_lim = cx.a_lim
    limited = "groove rim" if cap_g <= cap_t else "top plate tipping"
    W = (cx.m + m_o) * g
    P_allow = cx.ball_capacity * (r / BALL_TESTED) ** 2
    checks = [
        Check("plate acceleration below the statue's uplift limit", a_design <= a_lim, a_design, a_lim,
              f"felt {a_design:.4f} m/s^2 {'<=' if a_design <= a_lim else '>'} {cx.why_lim}", unit="m/s^2",
              key="acceleration"),
        Check("rolling friction below the statue's uplift limit", mu * g <= a_lim, mu * g, a_lim,
              f"mu g = {mu * g:.4f} m/s^2 vs {a_lim:.4f} m/s^2 (below mu g the plate does not roll and the "
              "statue feels the ground)", unit="m/s^2", key="friction"),
        Check("with the friction force added", a_design + mu * g <= a_lim, a_design + mu * g, a_lim,
              f"a + mu g = {a_design + mu * g:.4f} m/s^2 vs {a_lim:.4f} m/s^2 (friction transmits up to mu g; "
              "the thesis checks the spectral acceleration alone)", required=False, unit="m/s^2",
              key="acceleration_friction"),
        Check("travel capacity covers the demand with the margin", need <= cap, need, cap,
              f"travel demand {d:.4f} m x {cx.margin:g} + mu R_hat {mu * R_hat:.4f} m = {need:.4f} m "
              f"{'<=' if need <= cap else '>'} capacity {cap:.4f} m (limited by the {limited}: groove "
              f"{cap_g:.4f} m, tipping {cap_t:.4f} m)", unit="m", key="travel"),
        Check("top plate does not overturn (eq. 49)", d <= d_max + 1e-12, d, d_max,
              f"design displacement {d:.4f} m {'<=' if d <= d_max + 1e-12 else '>'} d_max = L_cr - a = "
              f"{geo.L_cr:.4f} - {a_s:.4f} m (a = a_design l / g, l = {l:.4f} m)", unit="m", key="overturning"),
        Check("groove depth leaves wood under the groove", geo.depth <= t - MIN_BOTTOM, geo.depth, t - MIN_BOTTOM,
              f"depth {geo.depth:.4f} m in a {t:.3f} m board, at least {MIN_BOTTOM:.3f} m must remain",
              unit="m", key="depth"),
        Check("the plates stay apart (balls stand proud of the grooves)", geo.depth <= r - MIN_GAP / 2,
              geo.depth, r - MIN_GAP / 2, f"depth {geo.depth:.4f} m vs ball radius {r:.4f} m less "
              f"{MIN_GAP / 2:.4f} m: gap 2 (r - depth) = {2 * (r - geo.depth):.4f} m, at least {MIN_GAP:.3f} m",
              unit="m", key="proud"),
        Check("plate within the largest allowed side", geo.side <= cx.side_max + 1e-12, geo.side, cx.side_max,
              f"side {geo.side:.3f} m vs {cx.side_max:.3f} m (panel width and CNC bed)", unit="m", key="plate_size"),
        Check("restoring force recentres the plate", R_hat <= d / (2 * RESTORING) + 1e-12, R_hat,
              d / (2 * RESTORING), f"R_hat {R_hat:.3f} m vs d / (2 x {RESTORING:g}) = {d / (2 * RESTORING):.3f} m: "
              f"F(d) - F(d/2) = W d / (2 R_hat) = {d / (2 * R_hat):.4f} W vs {RESTORING:g} W (ASCE 7-16 "
              "§17.2.4.4); a weaker pendulum may drift and stay off centre", required=False, unit="m",
              key="recentring"),
        Check("load per ball within what the grooves carry", W / n <= P_allow, W / n, P_allow,
              f"{W / n:.0f} N on each of {n} balls of {r * 1000:g} mm vs {P_allow:.0f} N ({cx.ball_capacity:.0f} N "
              f"on a {BALL_TESTED * 1000:g} mm ball: {cx.ball_source}; scaled by (r / {BALL_TESTED:g} m)^2); "
              "heavier loads leave pits that shorten the period and trap the balls (ch. 5.2): a harder groove "
              "surface or insert, a rubber layer, more or larger balls raise it", unit="N", key="ball_load"),
    ]
    fuse = {}
    if cx.fuse_release is not None:
        fuse = _fuse(geo, cx)
        back = math.inf if fuse["release"] is None else fuse["release"]
        no_ball = (f"no room for a fuse ball: the plates touch (gap 2 (r - depth) = {fuse['gap']:.4f} m)"
                   if fuse["release"] is None else "")
        checks.append(Check("fuse releases before the statue rocks", back < a_lim, back, a_lim,
                            no_ball or f"release {back:.4f} m/s^2 ({back / g:.3f} g) vs {a_lim:.4f} m/s^2",
                            unit="m/s^2", key="fuse"))
        seats, wall = _fuse_layout(geo, fuse) if fuse["ball_radius"] > 0 else ((), -math.inf)
        fuse["centres"] = [list(p) for p in seats]
        checks.append(Check("fuse seats and drop holes fit between the grooves", MIN_WALL <= wall + 1e-12,
                            MIN_WALL, wall, no_ball or f"least wood between the cutouts {wall:.4f} m, at least "
                            f"{MIN_WALL:.3f} m needed", unit="m", key="fuse_layout"))
    return {"geo": geo, "T": 2 * math.pi * math.sqrt(R_hat / g), "a_lim": a_lim, "a_design": a_design, "d": d,
            "m_o": m_o, "l": l, "a_s": a_s, "d_max": d_max, "cap": cap, "cap_g": cap_g, "cap_t": cap_t,
            "need": need, "checks": checks, "fuse": fuse}


def _worst(ev: dict) -> float:
    """Largest ratio of the required checks (<= 1: every required check passes)."""
    return max(c.ratio for c in ev["checks"] if c.required)


def _closeness(ev: dict) -> tuple:
    """Order of the failing candidates, nearest to passing first: fewer failing required
    checks, then the smaller worst ratio, then the smaller plate."""
    return (sum(1 for c in ev["checks"] if c.required and not c.passed), _worst(ev), ev["geo"].side)


def _passes(ev: dict) -> bool:
    return all(c.passed for c in ev["checks"] if c.required)


def failure_text(checks, shown: int | None = 3) -> str:
    """The failing required checks, worst ratio first: what fails and by how much (``shown``: at most
    that many, the rest counted; None: all)."""
    bad = sorted((c for c in checks if c.required and not c.passed), key=lambda c: -c.ratio)
    shown = len(bad) if shown is None else shown
    text = "; ".join(f"{c.name}: {c.why}" + (f" (ratio {c.ratio:.2f})" if math.isfinite(c.ratio) else " (not met)")
                     for c in bad[:shown])
    return text + (f"; and {len(bad) - shown} more" if len(bad) > shown else "")


def _sig(x: float) -> float | None:
    return float(f"{x:.6g}") if math.isfinite(x) else None


def _row(ev: dict) -> dict:
    geo = ev["geo"]
    return {"R": geo.R, "r": geo.r, "n_grooves": geo.n, "thickness": geo.thickness,
            "T": _sig(ev["T"]), "side": _sig(geo.side), "m_o": _sig(ev["m_o"]), "capacity": _sig(ev["cap"]),
            "need": _sig(ev["need"]), "passed": _passes(ev), "worst_ratio": _sig(_worst(ev)),
            "checks": [[_sig(c.value), _sig(c.limit), _sig(c.ratio), c.passed] for c in ev["checks"]]}


def _choose(passing: list[dict]) -> list[dict]:
    """The passing candidates in the order of CRITERION (best first)."""
    lightest = min(ev["m_o"] for ev in passing)
    near = [ev for ev in passing if ev["m_o"] <= lightest * (1 + PLATE_TOLERANCE)]
    rest = [ev for ev in passing if ev["m_o"] > lightest * (1 + PLATE_TOLERANCE)]

    def key(ev):
        geo = ev["geo"]
        over = {c.key: float(f"{max(c.ratio, 1.0):.2g}") for c in ev["checks"] if c.key in ("ball_load", "recentring")}
        margin = ev["a_lim"] / ev["a_design"] if ev["a_design"] > 0 else math.inf
        return (over["ball_load"], over["recentring"], -round(margin, 2), round(geo.side, 3), geo.thickness, geo.n,
                -geo.r)

    return sorted(near, key=key) + sorted(rest, key=lambda ev: (round(ev["m_o"], 3),) + key(ev))


def _demand_fn(spectrum, motion, mu: float, g: float):
    cache: dict = {}

    def demand(R: float, r: float) -> tuple[float, float]:
        if (R, r) not in cache:
            iso = Isolator(R=R, r=r, M=1.0, mu=mu, g=g)      # the plate's motion does not depend on M
            if spectrum is not None:
                cache[R, r] = (float(spectrum.Se(iso.T)), float(spectrum.SDe(iso.T)))
            else:
                from .time_history import simulate

                res = simulate(iso, motion, dt_out=0.01)
                cache[R, r] = (float(res.acc_abs_max), float(res.u_max))
        return cache[R, r]

    return demand


def _context(statue, mu, g, alpha, target, a_lim, a_lim_why, margin, side_max, wood_density, fuse_release,
             fuse_ball, ball_capacity) -> _Context:
    """The search's fixed numbers; the uplift limit min(alpha_L a_L, alpha_R a_R) or the given
    ``a_lim``, lowered to ``target`` when that is stricter."""
    if a_lim is None:
        a_lim = min(alpha[0] * statue.a_L, alpha[1] * statue.a_R)
        why_lim = f"min(alpha_L a_L, alpha_R a_R) = {a_lim:.4f} m/s^2"
    elif not (isinstance(a_lim, (int, float)) and math.isfinite(a_lim) and a_lim > 0):
        raise InputError(f"uplift limit a_lim must be a positive acceleration in m/s^2, got {a_lim!r}")
    else:
        why_lim = f"{a_lim_why or 'the given uplift limit'} = {a_lim:.4f} m/s^2"
    if target is not None and target < a_lim:
        a_lim, why_lim = target, f"target {target:.4f} m/s^2 (below the statue's limit)"
    if ball_capacity is None:
        cap, source = BALL_LOAD_TESTED, BALL_CAPACITY_SOURCE
    elif isinstance(ball_capacity, (int, float)) and math.isfinite(ball_capacity) and ball_capacity > 0:
        cap, source = float(ball_capacity), "the given load test"
    else:
        raise InputError(f"ball capacity must be a positive load in N (per {BALL_TESTED * 1000:g} mm ball), "
                         f"got {ball_capacity!r}")
    return _Context(m=statue.m, h=statue.h, mu=mu, g=g, a_lim=a_lim, why_lim=why_lim, margin=margin,
                    side_max=side_max, wood_density=wood_density, fuse_release=fuse_release, fuse_ball=fuse_ball,
                    ball_capacity=cap, ball_source=source)


@dataclass(frozen=True)
class Candidate:
    """One evaluated device of a search (:attr:`Design.evaluated`), SI units: grooves R, balls r,
    the plate (``side``; ``side_needed`` before the SIDE_MAX cap), the top plate's mass m_o, the
    supported mass M, the period T, the travel capacity and the travel its opening was sized on
    (``need``), and its checks."""

    R: float
    r: float
    n_grooves: int
    thickness: float
    side: float
    side_needed: float
    m_o: float
    M: float
    T: float
    R_hat: float
    capacity: float
    need: float
    checks: tuple
    ev: dict = field(repr=False, compare=False)
    cx: _Context = field(repr=False, compare=False)

    @property
    def W(self) -> float:
        """Weight on the balls, N."""
        return self.M * self.cx.g

    def check(self, key: str) -> Check:
        return next(c for c in self.checks if c.key == key)

    def passes(self, ignore=()) -> bool:
        """Every required check passes, those keyed in ``ignore`` apart."""
        return all(c.passed for c in self.checks if c.required and c.key not in ignore)

    def row(self) -> dict:
        """The candidate as design.json lists it (checks as [value, limit, ratio, passed])."""
        return _row(self.ev)

    def as_design(self, statue, *, spectrum=None, motion=None, target=None, alpha=(1.0, 1.0), tried: int = 1,
                  candidates: dict | None = None, failure: str | None = None, notes=()) -> Design:
        """The Design of this candidate (the input it was evaluated under)."""
        return _design_from(self.ev, self.cx, statue, spectrum, motion, target, alpha, tried, candidates or {},
                            failure, tuple(notes), self.cx.margin)


def _candidate(ev: dict, cx: _Context) -> Candidate:
    geo = ev["geo"]
    return Candidate(R=geo.R, r=geo.r, n_grooves=geo.n, thickness=geo.thickness, side=geo.side,
                     side_needed=geo.side_needed, m_o=ev["m_o"], M=cx.m + ev["m_o"], T=ev["T"],
                     R_hat=2 * (geo.R - geo.r), capacity=ev["cap"], need=geo.need, checks=tuple(ev["checks"]),
                     ev=ev, cx=cx)


def longest_period(balls=BALLS, R_grid=R_GRID, g: float = G) -> float:
    """The longest period (s) the search can pick: the largest R with the smallest ball.

    >>> round(longest_period(), 3)
    4.003
    """
    return 2 * math.pi * math.sqrt(2 * (max(R_grid) - min(balls)) / g)


def _check_inputs(spectrum, motion, mu, alpha, thicknesses, target, balls, R_grid, side_max, margin):
    if (spectrum is None) == (motion is None):
        raise InputError("give exactly one design input: a response spectrum or a ground motion")
    if not (isinstance(mu, (int, float)) and math.isfinite(mu) and 0 <= mu < 0.5):
        raise InputError(f"rolling friction mu must be in [0, 0.5), got {mu}")
    if not all(0 < a <= 1 for a in alpha):
        raise InputError(f"alpha must be in (0, 1], got {alpha}")
    lo, hi = PLAUSIBLE["plate_thickness"].hard_low, PLAUSIBLE["plate_thickness"].hard_high
    for t in thicknesses:
        if not (math.isfinite(t) and lo <= t <= hi):
            raise InputError(f"plate thickness {t * 1000:g} mm is out of range ({lo * 1000:g} to {hi * 1000:g} mm)")
    if target is not None and not (math.isfinite(target) and target > 0):
        raise InputError(f"target acceleration must be positive, got {target}")
    for name, values in (("ball radius", balls), ("groove radius R", R_grid)):
        if not values or not all(math.isfinite(v) and v > 0 for v in values):
            raise InputError(f"every {name} to try must be a positive length in m, got {values!r}")
    for R in R_grid:
        check_lengths(R, min(balls))
    for r in balls:
        check_lengths(max(R_grid), r)
    if not (math.isfinite(side_max) and side_max > 0):
        raise InputError(f"largest plate side must be positive, got {side_max}")
    if not (math.isfinite(margin) and margin >= 1):
        raise InputError(f"displacement margin must be >= 1, got {margin}")


def fails_only_on_ball_load(design: dict | None) -> bool:
    """True when a design's dict (design.json) fails its required checks on the ball load alone: the
    device's mechanics (travel, felt acceleration, tipping, geometry) pass and only the grooves'
    surface must carry more (``what_would_pass`` says how much). Such a design may be analysed
    (the dynamics stage, the 3D cross-check); its plates are not written.

    >>> fails_only_on_ball_load({"passed": False, "checks": [{"key": "ball_load", "required": True, "passed": False},
    ...                                                      {"key": "travel", "required": True, "passed": True}]})
    True
    """
    if not isinstance(design, dict) or design.get("passed") is True:
        return False
    checks = design.get("checks") if isinstance(design.get("checks"), list) else []
    bad = {c.get("key") for c in checks if isinstance(c, dict) and c.get("required", True) and not c.get("passed")}
    return bad == {"ball_load"}


def design(statue, *, mu: float, spectrum=None, motion=None, target: float | None = None,
           alpha: tuple[float, float] = (1.0, 1.0), n_grooves: int | None = None, thickness=None,
           balls=BALLS, R_grid=R_GRID, wood_density: float = WOOD_DENSITY, fuse_release: float | None = None,
           fuse_ball: float | None = None, min_side: float | None = None, side_max: float = SIDE_MAX,
           margin: float = DISPLACEMENT_MARGIN, g: float = G, ball_capacity: float | None = None,
           a_lim: float | None = None, a_lim_why: str | None = None, travel_floor: dict | None = None) -> Design:
    """Choose R, r, number of grooves, board, groove layout and plate size for ``statue``
    (RockingParams) under one design input; see the module for the checks and CRITERION.
    ``n_grooves`` None tries 3 and 4; ``thickness`` None tries THICKNESSES, a number (m)
    or a sequence restricts the boards. ``ball_capacity``: N per 20 mm ball the grooves carry
    (None: BALL_LOAD_TESTED, the thesis' beech). ``a_lim`` (m/s^2, described by ``a_lim_why``):
    the uplift limit instead of min(alpha_L a_L, alpha_R a_R) (e.g. the low end of an uncertain
    base's band). ``travel_floor``: {(R, r): m} a travel each such candidate's opening must
    cover at least (the time histories' need, verify.py)."""
    if thickness is None:
        thicknesses = THICKNESSES
    elif isinstance(thickness, (int, float)):
        thicknesses = (float(thickness),)
    else:
        thicknesses = tuple(float(t) for t in thickness)
    _check_inputs(spectrum, motion, mu, alpha, thicknesses, target, balls, R_grid, side_max, margin)
    if n_grooves not in (None, 3, 4):
        raise InputError(f"number of grooves must be 3 or 4, got {n_grooves}")
    floor = dict(travel_floor or {})
    if not all(math.isfinite(v) and v >= 0 for v in floor.values()):
        raise InputError("every travel the capacity must cover (travel_floor) must be a finite length >= 0 m")
    ns = (3, 4) if n_grooves is None else (n_grooves,)
    if min_side is None:                 # the statue's base must fit on the top plate
        min_side = 2 * max(statue.b_L, statue.b_R) + 2 * EDGE
    cx = _context(statue, mu, g, alpha, target, a_lim, a_lim_why, margin, side_max, wood_density, fuse_release,
                  fuse_ball, ball_capacity)
    demand = _demand_fn(spectrum, motion, mu, g)
    evs = []
    for r in sorted(balls):
        for R in sorted(R_grid):
            if R <= 2 * r:
                continue
            a_design, d = demand(R, r)
            for n in ns:
                for t in thicknesses:
                    geo = _size(R, r, n, t, a_design, d, cx, min_side, floor.get((R, r), 0.0))
                    evs.append(_evaluate(geo, a_design, d, cx))
    if not evs:
        raise InputError("no groove radius in the grid is larger than the balls' diameter")
    passing = [ev for ev in evs if _passes(ev)]
    failing = sorted((ev for ev in evs if not _passes(ev)), key=_closeness)
    ranges = (f"R {min(R_grid):g} to {max(R_grid):g} m, r {min(balls):g} to {max(balls):g} m, "
              f"{' or '.join(map(str, ns))} grooves, boards {', '.join(f'{t:g}' for t in thicknesses)} m, "
              f"plate up to {side_max:g} m")
    notes = []
    if passing:
        ranked = _choose(passing)
        best, failure = ranked[0], None
        for n in ns:
            own = [ev for ev in ranked if ev["geo"].n == n]
            notes.append(f"{n} grooves: " + (f"best plate {own[0]['geo'].side:.3f} m, R {own[0]['geo'].R:g} m"
                                             if own else "none passes"))
        shown = ranked[:SHOWN_PASSING] + failing[:SHOWN_FAILING]
    else:
        best = failing[0]
        failure = failure_text(best["checks"]) + f" [nearest of {len(evs)} candidates; {ranges}]"
        notes.append("no candidate meets every required check: the nearest one (fewest failing required checks, "
                     "then the smallest worst ratio) is shown")
        shown = failing[:SHOWN_PASSING + SHOWN_FAILING]
    head = evs[0]["checks"]
    candidates = {"criterion": CRITERION, "tried": len(evs), "passing": len(passing), "shown": len(shown),
                  "ranges": ranges, "order": "passing by the criterion (chosen first), then failing nearest "
                  "first (fewest failing required checks, then the smallest worst ratio)",
                  "checks": [{"key": c.key, "name": c.name, "unit": c.unit, "required": c.required} for c in head],
                  "check_columns": ["value", "limit", "ratio", "passed"],
                  "rows": [_row(ev) for ev in shown]}
    return replace(_design_from(best, cx, statue, spectrum, motion, target, alpha, len(evs), candidates, failure,
                                tuple(notes), margin), evaluated=tuple(_candidate(ev, cx) for ev in evs))


def _design_from(ev, cx, statue, spectrum, motion, target, alpha, tried, candidates, failure, notes,
                 margin) -> Design:
    geo = ev["geo"]
    iso = Isolator(R=geo.R, r=geo.r, M=cx.m + ev["m_o"], mu=cx.mu, g=cx.g)
    inp = {"spectrum": spectrum.to_dict() if spectrum is not None else None,
           "motion": motion.to_dict() if motion is not None else None, "target": target,
           "alpha": list(alpha), "statue": {"m": statue.m, "h": statue.h, "b_L": statue.b_L, "b_R": statue.b_R,
                                            "a_L": statue.a_L, "a_R": statue.a_R}}
    return Design(
        R=geo.R, r=geo.r, n_grooves=geo.n, mu=cx.mu, M=iso.M, m_o=ev["m_o"], T=iso.T, k=iso.k, R_hat=iso.R_hat,
        a_design=ev["a_design"], a_lim=cx.a_lim, d_design=ev["d"], d_max=ev["d_max"], lever_arm=ev["l"],
        safety_length=ev["a_s"], L_cr=geo.L_cr, spacing=geo.spacing, side=geo.side, thickness=geo.thickness,
        depth=geo.depth, opening_radius=geo.a, groove_centres=tuple(geo.centres), fuse=ev["fuse"],
        checks=tuple(ev["checks"]), input=inp, candidates_tried=tried, notes=notes, capacity=ev["cap"],
        capacity_groove=ev["cap_g"], capacity_tip=ev["cap_t"], travel_need=ev["need"], margin=margin,
        candidates=candidates, failure=failure, ball_capacity=cx.ball_capacity, ball_capacity_source=cx.ball_source)


def assess(statue, *, R: float, r: float, n_grooves: int, opening_radius: float, spacing: float, side: float,
           thickness: float, mu: float, spectrum=None, motion=None, target: float | None = None,
           alpha: tuple[float, float] = (1.0, 1.0), wood_density: float = WOOD_DENSITY,
           fuse_release: float | None = None, fuse_ball: float | None = None, side_max: float = SIDE_MAX,
           margin: float = DISPLACEMENT_MARGIN, g: float = G, ball_capacity: float | None = None) -> Design:
    """Check a given device (no search): grooves R, balls r, ``n_grooves`` grooves of
    opening radius ``opening_radius`` with centres ``spacing`` apart (layout as the
    design's), a square plate ``side`` x ``thickness`` (m), under one design input;
    ``ball_capacity`` as for :func:`design`."""
    _check_inputs(spectrum, motion, mu, alpha, (thickness,), target, (r,), (R,), side_max, margin)
    if not 0 < opening_radius <= R:
        raise InputError(f"opening radius must be in (0, R = {R:g}] m, got {opening_radius!r}")
    cx = _context(statue, mu, g, alpha, target, None, None, margin, side_max, wood_density, fuse_release,
                  fuse_ball, ball_capacity)
    a_design, d = _demand_fn(spectrum, motion, mu, g)(R, r)
    centres, L_cr = _layout(n_grooves, spacing)
    geo = _Geometry(R, r, n_grooves, thickness, opening_radius, _cap_depth(R, opening_radius), spacing,
                    centres, L_cr, side, side, margin * d + mu * 2 * (R - r))
    ev = _evaluate(geo, a_design, d, cx)
    ok = _passes(ev)
    failure = None if ok else failure_text(ev["checks"])
    cands = {"criterion": "given device (no search)", "tried": 1, "passing": int(ok), "shown": 1,
             "checks": [{"key": c.key, "name": c.name, "unit": c.unit, "required": c.required} for c in ev["checks"]],
             "check_columns": ["value", "limit", "ratio", "passed"], "rows": [_row(ev)]}
    return replace(_design_from(ev, cx, statue, spectrum, motion, target, alpha, 1, cands, failure, (), margin),
                   criterion="given device (no search)")
