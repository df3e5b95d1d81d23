"""Design of a rolling-ball isolator a workshop can build (thesis ch. 5.1, 5.3, 6.4; MODEL.md sections
4, 8, 9): the cheapest device that passes every required check, at the design level for the statue and
at the collapse level (SLC) for the device. SI units throughout.

The design space (one :class:`Device` per combination):

    balls        radius in BALLS (9.5 to 50 mm), material steel or resin (bearing.BALLS_MATERIALS)
    layout       LAYOUTS: 3 to 16 balls on a ring or a grid (layout.py); one groove pair per ball
    grooves      radius R in R_GRID (0.20-2.00 m); R_hat = 2 (R - r), T = 2 pi sqrt(R_hat / g)
    surface      SURFACES (bearing.py): beech, robinia, beech with the 3.2 mm rubber layer, an HDPE or a
                 POM sheet, hardened steel races set into the wooden plate
    boards       wood THICKNESSES (or the one given), stacked and glued up to MAX_LAYERS so that the
                 groove (and its liner) leaves MIN_BOTTOM under it; polymer SHEETS likewise;
                 the thinnest stack that fits is taken (it is the cheapest)

Each candidate is sized, then checked (checks.py holds every formula). Sizing: the grooves' opening
radius a gives the groove capacity a R_hat / R = the travel need (the largest of the design level's,
the collapse level's and ``travel_floor``, the time histories', verify.py) plus SIZING_CLEARANCE,
rounded up to OPENING_STEP; the groove spacing gives the tipping capacity and eq. 49 at the design
acceleration (lever arm at its largest, the plate's mass neglected); the plate is at least the
statue's base (2 max(b_L, b_R) + 2 EDGE) and at most SIDE_MAX (the checks then say what is missing),
and the grooves are spread to the plate's edge. The friction is the pair's law at the load per ball
(bearing.rolling_friction), or the ``mu`` given; its upper bound mu_high enters the offset mu R_hat,
the tipping and the friction check.

Demand (spectrum): a_design = Se(T) and d = SDe(T) at the design level; a_SLC, d_SLC of the collapse
level's spectrum (hazard/levels.py: the design spectrum x gamma_x 1.2 on an EC8 site, the SLC spectrum
on an NTC one) -- ``slc`` None takes the design spectrum x GAMMA_X. (motion): the simulated peaks of
|a_abs| and |u_o| under the motion and under it x GAMMA_X.

Checks (value <= limit; ``level`` design, SLC or static):

    acceleration     Se(T) <= a_lim (the statue's alpha-reduced uplift limit)          design
    friction         mu_high g <= a_lim (else the statue rocks before the plate rolls)
    pit              the roll-out of the pit its ball leaves, g sqrt(delta / 2r), <= a_lim
    travel           1.5 d + mu_high R_hat <= capacity                                  design
    travel_slc       1.25 d_SLC + mu_high R_hat <= capacity                             SLC
    overturning      d <= L_cr - (a_design / g) l (eq. 49)                              design
    overturning_slc  1.25 d_SLC <= L_cr - (a_SLC / g) l                                 SLC
    depth            the groove and its liner leave MIN_BOTTOM in the stack (MAX_LAYERS at most)
    proud            depth <= r - MIN_GAP / 2 (the plates stay apart)
    plate_size       side <= SIDE_MAX
    ball_load        W / n <= the surface's long-term capacity per ball                 static
    ball_load_slc    W / n + M a_SLC l / spread <= the short-term capacity             SLC
    fuse, fuse_layout  (with a fuse) release < a_lim; MIN_WALL of wood around its seats
  advisory:
    acceleration_friction  Se + mu_high g <= a_lim;  recentring  R_hat <= 20 d (ASCE 7-16 17.2.4.4)

A candidate that fails depth, proud, plate_size or fuse_layout cannot be made: it is never shown as
the nearest while one that can be made exists (when none can, the least bad is shown with a note
saying so, and ``nearest_makeable`` false in design.json). Choice (CRITERION): the cheapest passing device by its bill of materials (prices.py);
ties (within COST_TOLERANCE) the larger least margin, then the smaller plate, fewer balls, the larger
ball. When none passes, the nearest makeable candidate (fewest failing required checks, then the
smallest worst ratio) is shown with ``failure`` and ``what_would_pass`` (one sentence: the reason a
conservator understands and what would work instead).

Example
-------
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard.code_spectra import ec8
>>> statue = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.8})
>>> d = design(statue, spectrum=ec8(0.05 * 9.80665, "A"), mu=0.0073, thickness=0.03)
>>> d.passed, d.cost == round(sum(row["cost"] for row in d.bom), 2) or abs(d.cost - sum(r["cost"] for r in d.bom)) < 1e-9
(True, True)
>>> d.what_would_pass is None and all(c.passed for c in d.checks if c.required)
True
>>> bad = design(statue, spectrum=ec8(0.05 * 9.80665, "A"), mu=0.0073, alpha=(0.02, 0.02))
>>> bad.passed, bad.what_would_pass["reason"]
(False, 'friction')
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property, lru_cache

from ..compute.collector import collector_paused
from ..errors import InputError
from ..geometry.units import PLAUSIBLE
from . import checks as C
from .bearing import BALLS_MATERIALS, SURFACES, ball_capacity, dent_depth, pit_release, rolling_friction
from .checks import (
    DISPLACEMENT_MARGIN,
    Lazy as L,
    EDGE,
    GAP,
    GAMMA_X,
    MIN_BOTTOM,
    MIN_GAP,
    MIN_WALL,
    SIDE_MAX,
    SLC_MARGIN,
    Check,
    groove_depth,
    tipping_capacity,
    travel_need,
)
from .device import G, Isolator, check_lengths, fuse_release_acceleration, fuse_seat_depth, groove_capacity, \
    lever_arm, safety_length
from .layout import LAYOUTS
from .prices import bill, bill_total, prices

BALLS = (0.0095, 0.0125, 0.0183, 0.020, 0.025, 0.030, 0.040, 0.050)
"""Ball radii tried (m): the thesis' steel 9.5 mm, resin 18.3 and 20 mm, and stock sizes up to 100 mm
balls (r 50 mm)."""
RESIN_BALLS = (0.0183, 0.020)
"""Resin balls come in the thesis' sizes only (Tables 19, 25)."""
R_GRID = tuple(round(0.20 + 0.05 * k, 3) for k in range(37))
"""Groove radii tried (m), 0.20 to 2.00: up to R = 2.0 m the period stays within about 4 s (the range of
EN 1998-1 3.2.2.2's elastic spectrum)."""
THICKNESSES = (0.02, 0.03, 0.04, 0.05)
"""Wooden board thicknesses (m) when none is given; the thesis' plates were 30 mm beech."""
SHEETS = (0.010, 0.015, 0.020, 0.025, 0.030, 0.040, 0.050)
"""Polymer sheet thicknesses (m)."""
MAX_LAYERS = 3
"""Boards (or sheets) glued into one plate at most."""
SIZING_CLEARANCE = 0.01
"""The grooves are cut for the travel need plus 1 % (a capacity sized exactly would rest on the last digit)."""
OPENING_STEP = 0.0005
"""Groove opening radii are whole multiples of 0.5 mm (the drawing's precision), rounded up."""
COST_TOLERANCE = 0.02
"""Devices within 2 % of the cheapest cost the same (CRITERION's ties)."""
SHOWN_PASSING = 30
SHOWN_FAILING = 10
MAKEABLE = ("depth", "proud", "plate_size", "fuse_layout")
"""Checks a device that cannot be made fails: such a device is never reported as the nearest."""
CRITERION = ("the cheapest device that passes every required check (its bill of materials, prices.py); within "
             f"{COST_TOLERANCE:.0%} of the cheapest: the larger least margin, then the smaller plate, fewer balls, "
             "the larger ball")
# re-exported for the modules that read them here
__all__ = ["BALLS", "R_GRID", "THICKNESSES", "DISPLACEMENT_MARGIN", "Check", "Design", "Device", "design", "assess",
           "failure_text", "longest_period", "MIN_BOTTOM", "MIN_GAP", "EDGE", "GAP", "MIN_WALL", "SIDE_MAX"]


@dataclass(frozen=True)
class Device:
    """What the workshop builds (m, kg): grooves R, balls r of ``ball`` material, ``layout`` (``n``
    balls at ``centres``, ``spacing`` apart), the groove ``surface``, the plate (``side``, ``layers``:
    ((board thickness, count), ...) stacked to ``thickness``), the grooves' ``opening_radius`` and
    ``depth`` (the rolling surface's; a liner's groove is milled ``layer`` deeper), the fuse (``fuse_ball``
    radius, ``n_fuse`` seats) and the top plate's mass ``m_o``."""

    R: float
    r: float
    ball: str
    layout: str
    n: int
    surface: str
    layers: tuple
    thickness: float
    side: float
    side_needed: float
    spacing: float
    L_cr: float
    opening_radius: float
    depth: float
    m_o: float
    fuse_ball: float = 0.0
    n_fuse: int = 0

    @property
    def D(self) -> float:
        return 2 * self.r

    @property
    def centres(self) -> tuple:
        """((x, y), ...) of the groove centres, m (plate centre at 0)."""
        return LAYOUTS[self.layout].centres(self.spacing)

    @property
    def R_hat(self) -> float:
        return 2 * (self.R - self.r)

    @property
    def layer(self) -> float:
        """m: the liner's thickness (0 without one)."""
        return SURFACES[self.surface].layer

    @property
    def cut_depth(self) -> float:
        """m: how deep the plate is cut under each groove (the groove and the liner under it)."""
        return self.depth + self.layer

    @property
    def carved_opening(self) -> float:
        """m: the opening radius of the carved groove (a liner's rim included)."""
        c, L = self.cut_depth, self.layer
        return math.sqrt(c * (2 * (self.R + L) - c))

    @property
    def liner_area(self) -> float:
        """m^2: the area of one groove's liner (a spherical cap's, 2 pi R depth)."""
        return 2 * math.pi * self.R * self.depth


@dataclass(frozen=True)
class Demand:
    """The plate's demand at one period: design level (a_design m/s^2, d m) and collapse level."""

    a_design: float
    d: float
    a_slc: float
    d_slc: float


@dataclass(frozen=True)
class Candidate:
    """One evaluated device (:attr:`Design.evaluated`): the device, its demand, friction, capacities,
    checks and bill of materials."""

    device: Device
    demand: Demand
    friction: object          # bearing.FrictionEstimate
    mu: float
    mu_low: float
    mu_high: float
    capacity: float
    capacity_groove: float
    capacity_tip: float
    need: float               # the travel the opening was sized on, m
    lever: float
    d_max: float
    ball_capacity: object     # bearing.Capacity (long-term)
    ball_capacity_short: float
    checks: tuple
    cost: float               # EUR: the total of :attr:`rows`
    cx: object = field(repr=False, compare=False)

    @cached_property
    def rows(self) -> tuple:
        """The rows of the bill of materials (prices.bill), written when first read."""
        return tuple(bill(self.device, self.cx.prices))

    # the old Candidate's names
    @property
    def R(self) -> float:
        return self.device.R

    @property
    def r(self) -> float:
        return self.device.r

    @property
    def n_grooves(self) -> int:
        return self.device.n

    @property
    def side(self) -> float:
        return self.device.side

    @property
    def side_needed(self) -> float:
        return self.device.side_needed

    @property
    def thickness(self) -> float:
        return self.device.thickness

    @property
    def m_o(self) -> float:
        return self.device.m_o

    @property
    def M(self) -> float:
        return self.cx.m + self.device.m_o

    @property
    def W(self) -> float:
        return self.M * self.cx.g

    @property
    def R_hat(self) -> float:
        return self.device.R_hat

    @property
    def T(self) -> float:
        return 2 * math.pi * math.sqrt(self.device.R_hat / self.cx.g)

    def check(self, key: str) -> Check:
        return next(c for c in self.checks if c.key == key)

    def passes(self, ignore=()) -> bool:
        return all(c.passed for c in self.checks if c.required and c.key not in ignore)

    @property
    def makeable(self) -> bool:
        return all(c.passed for c in self.checks if c.key in MAKEABLE)

    @property
    def least_margin(self) -> float:
        """The smallest limit / value of the required checks (> 1 passes)."""
        return min((1 / c.ratio if c.ratio > 0 else math.inf) for c in self.checks if c.required)

    def row(self) -> dict:
        d = self.device
        return {"R": d.R, "r": d.r, "ball": d.ball, "layout": d.layout, "n_grooves": d.n, "surface": d.surface,
                "thickness": d.thickness, "T": _sig(self.T), "side": _sig(d.side), "m_o": _sig(d.m_o),
                "capacity": _sig(self.capacity), "need": _sig(self.need), "mu": _sig(self.mu),
                "cost": round(self.cost, 2), "passed": self.passes(), "makeable": self.makeable,
                "worst_ratio": _sig(_worst(self.checks)),
                "checks": [[_sig(c.value), _sig(c.limit), _sig(c.ratio), c.passed] for c in self.checks]}

    def as_design(self, statue, **kw) -> "Design":
        return _design_from(self, statue, **kw)


@dataclass(frozen=True)
class Design:
    """The chosen (or nearest) device and everything the files and the report say of it."""

    R: float
    r: float
    n_grooves: int
    mu: float
    M: float                 # statue + top plate, kg
    m_o: float               # top plate, kg
    T: float
    k: float
    R_hat: float
    a_design: float          # plate absolute acceleration, m/s^2 (spectral, design level)
    a_lim: float
    d_design: float          # design displacement of the top plate, m
    d_max: float             # eq. 49 at the design acceleration, m
    lever_arm: float
    safety_length: float
    L_cr: float
    spacing: float           # least groove centre spacing, m
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
    capacity: float = 0.0
    capacity_groove: float = 0.0
    capacity_tip: float = 0.0
    travel_need: float = 0.0
    margin: float = DISPLACEMENT_MARGIN
    candidates: dict = field(default_factory=dict)
    failure: str | None = None
    criterion: str = CRITERION
    device: Device | None = None
    friction: dict = field(default_factory=dict)
    ball_capacity: dict = field(default_factory=dict)
    levels: dict = field(default_factory=dict)
    cost: float = 0.0
    bom: tuple = ()
    verification: dict = field(default_factory=dict)
    what_would_pass: dict | None = None
    evaluated: tuple = field(default=(), repr=False, compare=False)

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks if c.required)

    @property
    def capacity_limited_by(self) -> str:
        return "groove rim" if self.capacity_groove <= self.capacity_tip else "top plate tipping"

    @property
    def surface(self) -> str:
        return self.device.surface if self.device else "beech"

    @property
    def layout(self) -> str:
        return self.device.layout if self.device else ""

    @property
    def th_margins(self) -> dict | None:
        return self.verification.get("margins") if self.verification else None

    def _makeable(self) -> bool:
        return all(c.passed for c in self.checks if c.key in MAKEABLE)

    def isolator(self, model: str = "coulomb", q: float = 30.0) -> Isolator:
        return Isolator(R=self.R, r=self.r, M=self.M, mu=self.mu, model=model, q=q, capacity=self.capacity)

    def to_dict(self) -> dict:
        out = {k: getattr(self, k) for k in (
            "R", "r", "R_hat", "T", "k", "n_grooves", "mu", "M", "m_o", "a_design", "a_lim", "d_design", "d_max",
            "capacity", "capacity_groove", "capacity_tip", "travel_need", "margin", "lever_arm",
            "safety_length", "L_cr", "spacing", "side", "thickness", "depth", "opening_radius",
            "fuse", "input", "candidates_tried", "failure", "criterion", "levels", "friction")}
        dev = self.device
        out.update(capacity_limited_by=self.capacity_limited_by,
                   travel_margin=self.capacity / self.travel_need if self.travel_need > 0 else None,
                   acceleration_margin=self.a_lim / self.a_design if self.a_design > 0 else None,
                   groove_centres=[list(c) for c in self.groove_centres], passed=self.passed,
                   checks=[c.to_dict() for c in self.checks], candidates=self.candidates, notes=list(self.notes),
                   ball_capacity=self.ball_capacity, verification=self.verification or None,
                   th_margins=self.th_margins, what_would_pass=self.what_would_pass,
                   layout=dev.layout if dev else None, n_balls=self.n_grooves, surface=dev.surface if dev else None,
                   surface_name=SURFACES[dev.surface].name if dev else None, ball_material=dev.ball if dev else None,
                   layers=[list(x) for x in dev.layers] if dev else None, cut_depth=dev.cut_depth if dev else None,
                   liner=dev.layer if dev else 0.0, cost=round(self.cost, 2),
                   nearest_makeable=bool(dev and self.passed or self._makeable()),
                   bom=[dict(r) for r in self.bom], currency="EUR",
                   schema="statue2model.isolator_design/4")
        return _finite_tree(out)

    def report(self) -> str:
        """design.txt: the device, the checks (one unit column), the cost and the choice."""
        dev = self.device
        lines = [f"Rolling-ball isolator: {'PASS' if self.passed else 'FAIL'}"]
        if self.what_would_pass and not self.passed:
            lines.append(f"  {self.what_would_pass['text']}")
        if self.failure:
            lines += [f"  failing: {self.failure}", "  nearest device that can be made:"]
        if dev is not None:
            lines.append(f"  {LAYOUTS[dev.layout].name}: {dev.ball} balls r = {dev.r * 1000:g} mm on "
                         f"{SURFACES[dev.surface].name}")
            lines.append(f"  plates {self.side:.3f} x {self.side:.3f} m, "
                         + " + ".join(f"{k} x {t * 1000:g} mm" for t, k in dev.layers) + f" ({self.thickness * 1000:g}"
                         f" mm; top plate {self.m_o:.2f} kg)")
        lines += [
            f"  grooves R = {self.R:.4f} m, R_hat = {self.R_hat:.3f} m, T = {self.T:.2f} s, k = {self.k:.1f} N/m, "
            f"opening radius {self.opening_radius:.4f} m, depth {self.depth:.4f} m, spacing {self.spacing:.3f} m",
            f"  rolling friction mu {self.mu:.4g} ({(self.friction or {}).get('basis', 'given')}); travel capacity "
            f"{self.capacity:.4f} m ({self.capacity_limited_by}; groove {self.capacity_groove:.4f} m, tipping "
            f"{self.capacity_tip:.4f} m)",
            f"  cost {self.cost:.0f} EUR (the bill of materials below; prices.py, [isolator.prices])",
            "",
            "checks (each passes when value <= limit; ratio = value / limit):",
        ]
        rows = [("result", "level", "check", "value", "limit", "unit", "ratio")]
        num = lambda x, spec: format(x, spec) if math.isfinite(x) else "-"          # noqa: E731 (no inf in a file)
        for c in self.checks:
            mark = "pass" if c.passed else ("FAIL" if c.required else "note")
            rows.append((mark, c.level, c.name, num(c.value, ".5g"), num(c.limit, ".5g"), c.unit, num(c.ratio, ".3f")))
        widths = [max(len(r[i]) for r in rows) for i in range(7)]
        for r in rows:
            lines.append("  " + "  ".join(s.ljust(w) if i in (0, 1, 2, 5) else s.rjust(w)
                                          for i, (s, w) in enumerate(zip(r, widths))).rstrip())
        lines += ["", "why:"] + [f"  {c.name}: {c.why}" for c in self.checks]
        cand = self.candidates or {}
        lines += ["", f"choice: {self.criterion}",
                  f"  {cand.get('passing', 0)} of {self.candidates_tried} candidates pass every required check"
                  + (f"; ranges: {cand['ranges']}" if cand.get("ranges") else "")]
        lines += [f"  {n}" for n in self.notes]
        if self.verification:
            lines += [""] + _verification_lines(self)
        if self.bom:
            lines += ["", "bill of materials (EUR):"]
            lines += [f"  {r['item']}: {r['quantity']:.4g} {r['unit']} x {r['unit_cost']:.2f} = {r['cost']:.2f}"
                      for r in self.bom]
            lines.append(f"  total {self.cost:.2f}")
        return "\n".join(lines)


def _verification_lines(d) -> list[str]:
    v = d.verification
    m = v.get("margins") or {}
    fmt = lambda x: "inf" if x is None else f"{x:.2f}"                # noqa: E731
    lines = [f"time-history verification ({v.get('model', '')}): {v['records']['count']} records per set, "
             f"{len(v.get('sets', []))} sets ({v['records'].get('source', '')}), the {v.get('statistic', 'mean')} "
             f"over each set, mu_low {v['mu_low']:.4g} and mu_high {v['mu_high']:.4g}"]
    lines.append("  margins (limit / demand, > 1 passes): " + ", ".join(f"{k} {fmt(x)}" for k, x in m.items()))
    for s in v.get("sets", []):
        lines.append(f"  set {s['name']} (seeds {s['seeds']}): travel {s['travel']:.4f} m, felt {s['felt']:.4f} "
                     f"m/s^2, need {s['need']:.4f} m")
    lines += [f"  {k}: {text}" for k, text in (v.get("definitions") or {}).items()]
    return lines


def _sig(x: float) -> float | None:
    return float(f"{x:.6g}") if isinstance(x, (int, float)) and math.isfinite(x) else None


def _finite_tree(x):
    if isinstance(x, float):
        return x if math.isfinite(x) else None
    if isinstance(x, dict):
        return {k: _finite_tree(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_finite_tree(v) for v in x]
    return x


def _worst(checks) -> float:
    return max(c.ratio for c in checks if c.required)


def failure_text(checks, shown: int | None = 3) -> str:
    """The failing required checks, worst ratio first: what fails and by how much."""
    bad = sorted((c for c in checks if c.required and not c.passed), key=lambda c: -c.ratio)
    shown = len(bad) if shown is None else shown
    text = "; ".join(f"{c.name}: {c.why}" + (f" (ratio {c.ratio:.2f})" if math.isfinite(c.ratio) else " (not met)")
                     for c in bad[:shown])
    return text + (f"; and {len(bad) - shown} more" if len(bad) > shown else "")


def longest_period(balls=BALLS, R_grid=R_GRID, g: float = G) -> float:
    """The longest period (s) the search can pick: the largest R with the smallest ball.

    >>> round(longest_period(), 3)
    4.003
    """
    return 2 * math.pi * math.sqrt(2 * (max(R_grid) - min(balls)) / g)


# --- the search's fixed numbers ---------------------------------------------------------------
@dataclass(frozen=True)
class _Context:
    m: float
    h: float
    g: float
    a_lim: float
    why_lim: str
    side_max: float
    min_side: float
    fuse_release: float | None
    fuse_ball: float | None
    mu_given: tuple | None        # (mu, mu_low, mu_high) or None: each pair's law
    prices: dict
    tested: float | None          # a load test of the surface, N on a 40 mm ball
    boards: tuple                 # wooden board thicknesses, m
    slc_why: str


def _context(statue, g, alpha, target, a_lim, a_lim_why, side_max, min_side, fuse_release, fuse_ball, mu,
             mu_low, mu_high, price_table, ball_capacity, boards, slc_why) -> _Context:
    if a_lim is None:
        a_lim = min(alpha[0] * statue.a_L, alpha[1] * statue.a_R)
        why = f"min(alpha_L a_L, alpha_R a_R) = {a_lim:.4f} m/s^2"
    elif not (isinstance(a_lim, (int, float)) and math.isfinite(a_lim) and a_lim > 0):
        raise InputError(f"uplift limit a_lim must be a positive acceleration in m/s^2, got {a_lim!r}")
    else:
        why = f"{a_lim_why or 'the given uplift limit'} = {a_lim:.4f} m/s^2"
    if target is not None and target < a_lim:
        a_lim, why = target, f"target {target:.4f} m/s^2 (below the statue's limit)"
    given = None
    if mu is not None:
        from .friction import friction_bounds

        lo, hi, _ = friction_bounds(mu)
        given = (mu, lo if mu_low is None else mu_low, hi if mu_high is None else mu_high)
    if ball_capacity is not None:
        if not (isinstance(ball_capacity, (int, float)) and math.isfinite(ball_capacity) and 0 < ball_capacity):
            raise InputError(f"ball capacity must be a positive load in N (per 40 mm ball), got {ball_capacity!r}")
        from ..geometry.units import check_plausible

        check_plausible("ball_capacity", ball_capacity, "ball capacity (a load test)")
    return _Context(statue.m, statue.h, g, a_lim, why, side_max, min_side, fuse_release, fuse_ball, given,
                    price_table, ball_capacity, tuple(boards), slc_why)


def _stack(cut: float, options: tuple) -> tuple[tuple, float] | None:
    """The thinnest stack of boards of one thickness in ``options`` (at most MAX_LAYERS) leaving MIN_BOTTOM
    under a cut ``cut`` m deep: (((t, k),), t k), or None when none does."""
    best = None
    for t in options:
        k = max(1, math.ceil((cut + MIN_BOTTOM) / t - 1e-9))
        if k <= MAX_LAYERS:
            key = (t * k, k)
            if best is None or key < best[0]:
                best = (key, (((t, k),), t * k))
    return None if best is None else best[1]


@lru_cache(maxsize=4096)
def _capacity(D: float, surface: str, R: float | None, tested: float | None):
    return ball_capacity(D, SURFACES[surface], R, long_term=True, tested=tested)


def _friction(D, P, ball, surface, R, cx: _Context):
    if cx.mu_given is not None:
        from .bearing import FrictionEstimate

        mu, lo, hi = cx.mu_given
        return FrictionEstimate(mu, lo, hi, "given", "the rolling friction given ([isolator] mu / --mu)", math.nan)
    return rolling_friction(D, P, BALLS_MATERIALS[ball], SURFACES[surface], R, cx.g)


def _size(R, r, ball, layout, surface, dem: Demand, cx: _Context, floor: float = 0.0) -> tuple:
    """(Device, FrictionEstimate, need) of one candidate sized for ``dem`` (module docstring)."""
    lay = LAYOUTS[layout]
    s = SURFACES[surface]
    R_hat = 2 * (R - r)
    m_o = 0.0
    for _ in range(2):                                 # the friction depends on the plate's mass: twice
        P = (cx.m + m_o) * cx.g / lay.n
        fr = _friction(2 * r, P, ball, surface, R, cx)
        need = max(travel_need(dem.d, fr.mu_high, R_hat), travel_need(dem.d_slc, fr.mu_high, R_hat, SLC_MARGIN),
                   floor)
        sized = need * (1.0 + C_CLEAR)
        a = min(max(math.ceil(sized * R / R_hat / OPENING_STEP) * OPENING_STEP, 1e-6), R)
        depth = groove_depth(R, a)
        cut = depth + s.layer
        rim = math.sqrt(cut * (2 * (R + s.layer) - cut))       # the carved opening (a liner's rim included)
        options = SHEETS if s.kind == "sheet" else cx.boards
        stack = _stack(cut, options)
        layers, t = stack if stack is not None else (((max(options), MAX_LAYERS),), max(options) * MAX_LAYERS)
        l0 = cx.h + t
        L_need = max(sized * (R + l0) / R_hat + fr.mu_high * l0, dem.d + safety_length(dem.a_design, l0, cx.g),
                     SLC_MARGIN * dem.d_slc + safety_length(dem.a_slc, l0, cx.g))
        s_min = 2 * rim + GAP
        sp = max(s_min, L_need / lay.unit_L_cr)
        side = side_needed = max(2 * (sp * lay.unit_extent + rim + EDGE), cx.min_side)
        if side > cx.side_max:
            side = max(cx.side_max, cx.min_side, 2 * (s_min * lay.unit_extent + rim + EDGE))
        sp = (side / 2 - rim - EDGE) / lay.unit_extent
        cap_vol = math.pi * cut * cut * (3 * (R + s.layer) - cut) / 3
        m_o = s.density * max(side * side * t - lay.n * cap_vol, 0.5 * side * side * t)
        m_o += lay.n * s.liner_density * s.layer * 2 * math.pi * R * depth
    fuse_r, n_fuse = 0.0, 0
    if cx.fuse_release is not None:
        gap = 2 * (r - depth)
        c = fuse_seat_depth(1.0, cx.fuse_release, cx.g)
        fuse_r = (gap / 2 / (1.0 - c) if cx.fuse_ball is None else cx.fuse_ball) if gap > 0 else 0.0
        n_fuse = lay.n if fuse_r > 0 else 0
    dev = Device(R=R, r=r, ball=ball, layout=layout, n=lay.n, surface=surface, layers=layers, thickness=t,
                 side=side, side_needed=side_needed, spacing=sp, L_cr=lay.L_cr(sp),
                 opening_radius=a, depth=depth, m_o=m_o, fuse_ball=fuse_r, n_fuse=n_fuse)
    return dev, fr, need


C_CLEAR = SIZING_CLEARANCE


def _fuse(dev: Device, cx: _Context) -> dict:
    """The fuse balls carry the plate at rest: diameter = the gap between the plates + two seats."""
    gap = 2 * (dev.r - dev.depth)
    if not dev.fuse_ball > 0:
        return {"ball_radius": 0.0, "seat_depth": 0.0, "release": None, "release_g": None, "gap": gap}
    z = fuse_seat_depth(dev.fuse_ball, cx.fuse_release, cx.g)
    back = fuse_release_acceleration(dev.fuse_ball, z, cx.g)
    return {"ball_radius": dev.fuse_ball, "seat_depth": z, "release": back, "release_g": back / cx.g, "gap": gap}


FUSE_RADII = (0.2, 0.35, 0.5, 0.65, 0.8)
"""Fuse seats sit on the bisectors between neighbouring outer grooves, at one of these fractions of the
grooves' distance from the plate centre (the one leaving the most wood)."""


def _fuse_layout(dev: Device, fuse: dict) -> tuple[tuple, float]:
    """Fuse seat centres and the least wood (m) they leave between the bottom plate's cutouts."""
    import numpy as np

    from .plates import _fuse_geometry

    c = np.asarray(dev.centres, dtype=float)
    rho = np.hypot(c[:, 0], c[:, 1])
    outer = c[rho >= rho.max() - 1e-9]
    ang = np.sort(np.arctan2(outer[:, 1], outer[:, 0]))
    mid = ang + np.diff(np.append(ang, ang[0] + 2 * math.pi)) / 2
    rho_g = float(rho.max())
    rim = dev.carved_opening
    grooves = np.column_stack([c, np.full(len(c), rim)])
    best = ((), -math.inf)
    for f in FUSE_RADII:
        seats = tuple((f * rho_g * math.cos(t), f * rho_g * math.sin(t)) for t in mid)
        fg = _fuse_geometry(dict(fuse, centres=seats), {"groove_centres": dev.centres, "thickness": dev.thickness})
        rf, z, off = fg["fuse_ball_radius"], fg["fuse_seat_depth"], fg["fuse_hole_offset"]
        s = np.asarray(seats)
        u = s / np.hypot(s[:, 0], s[:, 1])[:, None]
        circ = np.vstack([grooves,
                          np.column_stack([s, np.full(len(s), math.sqrt(max(2 * rf * z - z * z, 0.0)))]),
                          np.column_stack([s + off * u, np.full(len(s), fg["fuse_hole_diameter"] / 2)])])
        edge = float((dev.side / 2 - np.abs(circ[:, :2]).max(axis=1) - circ[:, 2]).min())
        diff = circ[:, None, :2] - circ[None, :, :2]
        dist = np.hypot(diff[..., 0], diff[..., 1]) - circ[:, None, 2] - circ[None, :, 2]
        wall = min(edge, float(dist[np.triu_indices(len(circ), 1)].min()))
        if wall > best[1]:
            best = (seats, wall)
    return best


def _evaluate(dev: Device, fr, need: float, dem: Demand, cx: _Context, with_fuse_layout: bool = False) -> Candidate:
    """Every number and check of one device under the demand ``dem``."""
    s = SURFACES[dev.surface]
    g = cx.g
    R, r, n, t = dev.R, dev.r, dev.n, dev.thickness
    R_hat = dev.R_hat
    mu_hi = fr.mu_high
    l = lever_arm(cx.m, cx.h, dev.m_o, t)
    M = cx.m + dev.m_o
    W = M * g
    a_s = safety_length(dem.a_design, l, g)
    d_max = dev.L_cr - a_s
    d_max_slc = dev.L_cr - safety_length(dem.a_slc, l, g)
    cap_g = groove_capacity(R, r, dev.opening_radius)
    cap_t = tipping_capacity(dev.L_cr, l, R, r, mu_hi)
    cap = min(cap_g, cap_t)
    limited = "groove rim" if cap_g <= cap_t else "top plate tipping"
    need_d = travel_need(dem.d, mu_hi, R_hat)
    need_slc = travel_need(dem.d_slc, mu_hi, R_hat, SLC_MARGIN)
    a_lim = cx.a_lim
    capl = _capacity(dev.D, dev.surface, R if s.criterion == "race" else None, cx.tested)
    cap_short = capl.short
    P = W / n
    spread = LAYOUTS[dev.layout].spread(dev.spacing)
    felt_slc = dem.a_slc + mu_hi * g
    P_dyn = C.dynamic_ball_load(W, n, M, felt_slc, l, spread)
    pit = 0.0
    if s.criterion == "dent":
        pit = pit_release(r, dent_depth(P / s.long_term, dev.D, s.hb, s.n), g)
    where = L(lambda: f"(limited by the {limited}: groove {cap_g:.4f} m, tipping {cap_t:.4f} m)")
    stack = L(lambda: " + ".join(f"{k} x {tt * 1000:g} mm" for tt, k in dev.layers))
    a_d = dem.a_design
    checks = [
        C.acceleration_check(a_d, a_lim, L(lambda: f"felt Se(T) {a_d:.4f} m/s^2 {'<=' if a_d <= a_lim else '>'} "
                                           f"{cx.why_lim}")),
        Check("rolling friction below the statue's uplift limit", mu_hi * g <= a_lim, mu_hi * g, a_lim,
              L(lambda: f"mu_high g = {mu_hi * g:.4f} m/s^2 vs {a_lim:.4f} m/s^2 (below mu g the plate does not roll "
                        "and the statue feels the ground)"), unit="m/s^2", key="friction"),
        Check("the balls roll out of their pits before the statue lifts", pit <= a_lim, pit, a_lim,
              L(lambda: f"a pit of the long-term dent under {P:.0f} N releases the ball at {pit:.4f} m/s^2 "
                        f"({pit / g:.4f} g; eq. 52) vs the uplift limit"), unit="m/s^2", key="pit"),
        Check("with the friction force added", a_d + mu_hi * g <= a_lim, a_d + mu_hi * g, a_lim,
              L(lambda: f"Se + mu_high g = {a_d + mu_hi * g:.4f} m/s^2 vs {a_lim:.4f} m/s^2 (the thesis checks Se "
                        "alone)"), required=False, unit="m/s^2", key="acceleration_friction"),
        C.travel_check(need_d, cap, L(lambda: f"{DISPLACEMENT_MARGIN:g} x d {dem.d:.4f} m + mu_high R_hat "
                                              f"{mu_hi * R_hat:.4f} m = {need_d:.4f} m vs capacity {cap:.4f} m {where}")),
        C.travel_check(need_slc, cap, L(lambda: f"{SLC_MARGIN:g} x d_SLC {dem.d_slc:.4f} m + mu_high R_hat = "
                                                f"{need_slc:.4f} m vs capacity {cap:.4f} m ({cx.slc_why})"),
                       level="SLC", key="travel_slc"),
        Check("top plate does not overturn (eq. 49)", dem.d <= d_max + 1e-12, dem.d, d_max,
              L(lambda: f"design displacement {dem.d:.4f} m vs d_max = L_cr - a = {dev.L_cr:.4f} - {a_s:.4f} m "
                        f"(l = {l:.4f} m)"), unit="m", key="overturning"),
        Check("top plate does not overturn at SLC (eq. 49)", SLC_MARGIN * dem.d_slc <= d_max_slc + 1e-12,
              SLC_MARGIN * dem.d_slc, d_max_slc, L(lambda: f"{SLC_MARGIN:g} x d_SLC {dem.d_slc:.4f} m vs L_cr - "
                                                          f"a_SLC l / g = {d_max_slc:.4f} m"),
              unit="m", key="overturning_slc", level="SLC"),
        Check("the grooves fit in the plate's boards", dev.cut_depth <= t - MIN_BOTTOM + 1e-12, dev.cut_depth,
              t - MIN_BOTTOM, L(lambda: f"cut {dev.cut_depth * 1000:.1f} mm deep in {stack} ({t * 1000:g} mm; at "
                                        f"most {MAX_LAYERS} boards), at least {MIN_BOTTOM * 1000:g} mm must remain"),
              unit="m", key="depth", level="static"),
        Check("the plates stay apart (balls stand proud of the grooves)", dev.depth <= r - MIN_GAP / 2,
              dev.depth, r - MIN_GAP / 2, L(lambda: f"depth {dev.depth:.4f} m vs ball radius {r:.4f} m less "
                                                    f"{MIN_GAP / 2:.4f} m: gap 2 (r - depth) = "
                                                    f"{2 * (r - dev.depth):.4f} m"),
              unit="m", key="proud", level="static"),
        Check("plate within the largest allowed side", dev.side <= cx.side_max + 1e-12, dev.side,
              cx.side_max, L(lambda: f"side {dev.side:.3f} m vs {cx.side_max:.3f} m (the CNC bed; the travel and "
                                     f"tipping asked {dev.side_needed:.3f} m at the largest lever arm)"),
              unit="m", key="plate_size", level="static"),
        Check("restoring force recentres the plate", R_hat <= C.recentring_limit(dem.d) + 1e-12, R_hat,
              C.recentring_limit(dem.d), L(lambda: f"R_hat {R_hat:.3f} m vs d / (2 x {C.RESTORING:g}) (ASCE 7-16 "
                                                   "17.2.4.4); a weaker pendulum may drift"),
              required=False, unit="m", key="recentring"),
        C.ball_load_check(P, capl.load, L(lambda: f"{P:.0f} N on each of {n} {dev.ball} balls of {dev.D * 1000:g} mm "
                                                  f"vs {capl.load:.0f} N ({s.name}, {capl.criterion}, long-term)")),
        C.ball_load_check(P_dyn, cap_short, L(lambda: f"W / n + M a l / spread = {P:.0f} + {P_dyn - P:.0f} N (felt "
                                                      f"{felt_slc:.3f} m/s^2 at SLC) vs the short-term "
                                                      f"{cap_short:.0f} N"), level="SLC", key="ball_load_slc"),
    ]
    fuse = {}
    if cx.fuse_release is not None:
        fuse = _fuse(dev, cx)
        back = math.inf if fuse["release"] is None else fuse["release"]
        no_ball = "no room for a fuse ball: the plates touch" if fuse["release"] is None else ""
        checks.append(Check("fuse releases before the statue rocks", back < a_lim, back, a_lim,
                            no_ball or L(lambda: f"release {back:.4f} m/s^2 ({back / g:.3f} g) vs {a_lim:.4f} m/s^2"),
                            unit="m/s^2", key="fuse"))
        if with_fuse_layout:
            seats, wall = _fuse_layout(dev, fuse) if fuse["ball_radius"] > 0 else ((), -math.inf)
            fuse["centres"] = [list(p) for p in seats]
            checks.append(Check("fuse seats and drop holes fit between the grooves", MIN_WALL <= wall + 1e-12,
                                MIN_WALL, wall, no_ball or L(lambda: f"least wood between the cutouts {wall:.4f} m, "
                                                                     f"at least {MIN_WALL:.3f} m"),
                                unit="m", key="fuse_layout", level="static"))
    return Candidate(dev, dem, fr, fr.mu, fr.mu_low, fr.mu_high, cap, cap_g, cap_t, need, l, d_max, capl, cap_short,
                     tuple(checks), bill_total(dev, cx.prices), cx)


def with_fuse_layout(c: Candidate) -> Candidate:
    """The candidate with its fuse layout checked (skipped during the search: it is slow)."""
    if c.cx.fuse_release is None or any(k.key == "fuse_layout" for k in c.checks):
        return c
    return _evaluate(c.device, c.friction, c.need, c.demand, c.cx, with_fuse_layout=True)


def resized(c: Candidate, floor: float) -> Candidate:
    """The candidate re-sized so that its opening covers at least the travel ``floor`` (m)."""
    dev, fr, need = _size(c.device.R, c.device.r, c.device.ball, c.device.layout, c.device.surface, c.demand,
                          c.cx, floor)
    return _evaluate(dev, fr, need, c.demand, c.cx, with_fuse_layout=c.cx.fuse_release is not None)


def _check_inputs(spectrum, motion, mu, alpha, thicknesses, target, balls, R_grid, side_max):
    if (spectrum is None) == (motion is None):
        raise InputError("give exactly one design input: a response spectrum or a ground motion")
    if mu is not None and not (isinstance(mu, (int, float)) and math.isfinite(mu) and 0 <= mu < 0.5):
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


def _choices(name: str, given, registry: dict) -> tuple:
    if given is None or given == "auto":
        return tuple(registry)
    items = (given,) if isinstance(given, str) else tuple(given)
    bad = [x for x in items if x not in registry]
    if bad or not items:
        raise InputError(f"unknown {name} {', '.join(map(repr, bad)) or '(none)'}: choose from {', '.join(registry)}")
    return items


def _demand_fn(spectrum, slc, motion, mu_low: float, g: float):
    """(R, r) -> Demand. The plate's motion does not depend on its mass (a motion: the plate alone at the
    lower friction bound, the travel's)."""
    cache: dict = {}

    def demand(R: float, r: float) -> Demand:
        key = round(2 * (R - r), 12)
        if key not in cache:
            T = 2 * math.pi * math.sqrt(key / g)
            if spectrum is not None:
                hi = slc if slc is not None else None
                a, d = float(spectrum.Se(T)), float(spectrum.SDe(T))
                if hi is None:
                    a2, d2 = GAMMA_X * a, GAMMA_X * d
                else:
                    a2, d2 = float(hi.Se(T)), float(hi.SDe(T))
                cache[key] = Demand(a, d, a2, d2)
            else:
                from .time_history import simulate

                iso = Isolator(R=R, r=r, M=1.0, mu=mu_low, g=g)
                res = simulate(iso, motion, dt_out=0.01)
                res2 = simulate(iso, motion.scaled(GAMMA_X), dt_out=0.01)
                cache[key] = Demand(float(res.acc_abs_max), float(res.u_max), float(res2.acc_abs_max),
                                    float(res2.u_max))
        return cache[key]

    return demand


@dataclass(frozen=True)
class Search:
    """Every candidate of a search (spectral demand), and how they were searched."""

    candidates: tuple
    cx: _Context
    ranges: str
    inputs: dict


def search(statue, *, spectrum=None, motion=None, slc=None, slc_why: str | None = None, mu: float | None = None,
           mu_low: float | None = None, mu_high: float | None = None, target: float | None = None,
           alpha: tuple[float, float] = (1.0, 1.0), n_grooves: int | None = None, thickness=None,
           balls=BALLS, R_grid=R_GRID, surfaces=None, materials=None, layouts=None, fuse_release: float | None = None,
           fuse_ball: float | None = None, min_side: float | None = None, side_max: float = SIDE_MAX,
           g: float = G, ball_capacity: float | None = None, a_lim: float | None = None,
           a_lim_why: str | None = None, price_table: dict | None = None) -> Search:
    """Every candidate device for ``statue`` (RockingParams), sized and checked on the spectral demand
    (module docstring); the keyword arguments restrict the design space or give its inputs."""
    if thickness is None:
        boards = THICKNESSES
    elif isinstance(thickness, (int, float)):
        boards = (float(thickness),)
    else:
        boards = tuple(float(t) for t in thickness)
    _check_inputs(spectrum, motion, mu, alpha, boards, target, balls, R_grid, side_max)
    if n_grooves is not None and not any(lay.n == n_grooves for lay in LAYOUTS.values()):
        raise InputError(f"no ball layout has {n_grooves} balls (layouts: "
                         f"{', '.join(str(v) for v in sorted({lay.n for lay in LAYOUTS.values()}))} balls)")
    lays = tuple(k for k in _choices("layout", layouts, LAYOUTS) if n_grooves is None or LAYOUTS[k].n == n_grooves)
    if not lays:
        raise InputError(f"no layout of {n_grooves} balls among {', '.join(_choices('layout', layouts, LAYOUTS))}")
    surfs = _choices("groove surface", surfaces, SURFACES)
    if ball_capacity is not None and len(surfs) != 1:
        raise InputError("a ball capacity is a load test of one groove surface: name that surface (--surface, "
                         "[isolator] surface)")
    mats = _choices("ball material", materials, BALLS_MATERIALS)
    if min_side is None:
        min_side = 2 * max(statue.b_L, statue.b_R) + 2 * EDGE
    why_slc = slc_why or ("the design motion x gamma_x" if motion is not None else
                          "the design spectrum x gamma_x 1.2 (EN 1998-1 10.3(2))" if slc is None else "the SLC spectrum")
    cx = _context(statue, g, alpha, target, a_lim, a_lim_why, side_max, min_side, fuse_release, fuse_ball, mu,
                  mu_low, mu_high, prices(price_table), ball_capacity, boards, why_slc)
    low = cx.mu_given[1] if cx.mu_given else 0.0039
    demand = _demand_fn(spectrum, slc, motion, low, g)
    out = []
    with collector_paused():        # thousands of small objects that live on: the cyclic collector only slows it
        _fill(out, balls, R_grid, lays, surfs, mats, demand, cx)
    if not out:
        raise InputError("no candidate in range: no groove radius is larger than the balls' diameter, or no ball "
                         "material rolls on the surfaces chosen")
    return _search_result(out, cx, R_grid, balls, lays, surfs, mats, boards, side_max, spectrum, slc, why_slc,
                          motion, target, alpha, statue)


def _fill(out, balls, R_grid, lays, surfs, mats, demand, cx) -> None:
    for r in sorted(balls):
        for R in sorted(R_grid):
            if R <= 2 * r:
                continue
            dem = demand(R, r)
            for layout in lays:
                for surface in surfs:
                    for ball in mats:
                        if surface not in BALLS_MATERIALS[ball].surfaces:
                            continue
                        if ball == "resin" and not any(abs(r - x) < 1e-9 for x in RESIN_BALLS):
                            continue
                        dev, fr, need = _size(R, r, ball, layout, surface, dem, cx)
                        out.append(_evaluate(dev, fr, need, dem, cx))


def _search_result(out, cx, R_grid, balls, lays, surfs, mats, boards, side_max, spectrum, slc, why_slc, motion,
                   target, alpha, statue) -> "Search":
    ranges = (f"R {min(R_grid):g} to {max(R_grid):g} m, r {min(balls):g} to {max(balls):g} m, layouts "
              f"{', '.join(lays)}, surfaces {', '.join(surfs)}, balls {', '.join(mats)}, boards "
              f"{', '.join(f'{t * 1000:g}' for t in boards)} mm (stacked up to {MAX_LAYERS}), plate up to "
              f"{side_max:g} m")
    inputs = {"spectrum": spectrum.to_dict() if spectrum is not None else None,
              "slc_spectrum": slc.to_dict() if slc is not None and hasattr(slc, "to_dict") else None,
              "slc_rule": why_slc, "motion": motion.to_dict() if motion is not None else None, "target": target,
              "alpha": list(alpha), "statue": {"m": statue.m, "h": statue.h, "b_L": statue.b_L, "b_R": statue.b_R,
                                               "a_L": statue.a_L, "a_R": statue.a_R}}
    return Search(tuple(out), cx, ranges, inputs)


def _rank_key(c: Candidate, cheapest: float) -> tuple:
    band = 0 if c.cost <= cheapest * (1 + COST_TOLERANCE) else 1
    return (band, round(c.cost, 2) if band else 0.0, -round(c.least_margin, 3), round(c.device.side, 3),
            c.device.n, -c.device.r)


def rank(passing: list) -> list:
    """Passing candidates in the order of CRITERION (best first)."""
    if not passing:
        return []
    cheapest = min(c.cost for c in passing)
    return sorted(passing, key=lambda c: _rank_key(c, cheapest))


def _closeness(c: Candidate) -> tuple:
    return (sum(1 for k in c.checks if k.required and not k.passed), _worst(c.checks), c.cost)


def nearest(cands) -> Candidate | None:
    """The nearest makeable candidate (fewest failing required checks, then the smallest worst ratio)."""
    ok = [c for c in cands if c.makeable]
    return min(ok, key=_closeness) if ok else None


def design(statue, *, mu: float | None = None, spectrum=None, motion=None, slc=None, slc_why: str | None = None,
           target: float | None = None, alpha: tuple[float, float] = (1.0, 1.0), n_grooves: int | None = None,
           thickness=None, balls=BALLS, R_grid=R_GRID, surfaces=None, materials=None, layouts=None,
           fuse_release: float | None = None, fuse_ball: float | None = None, min_side: float | None = None,
           side_max: float = SIDE_MAX, g: float = G, ball_capacity: float | None = None, a_lim: float | None = None,
           a_lim_why: str | None = None, price_table: dict | None = None, mu_low: float | None = None,
           mu_high: float | None = None) -> Design:
    """The cheapest device for ``statue`` (RockingParams) on the spectral demand (module docstring;
    verify.py checks it by time histories). ``mu`` None: each ball/surface pair's measured law."""
    srch = search(statue, spectrum=spectrum, motion=motion, slc=slc, slc_why=slc_why, mu=mu, mu_low=mu_low,
                  mu_high=mu_high, target=target, alpha=alpha, n_grooves=n_grooves, thickness=thickness, balls=balls,
                  R_grid=R_grid, surfaces=surfaces, materials=materials, layouts=layouts, fuse_release=fuse_release,
                  fuse_ball=fuse_ball, min_side=min_side, side_max=side_max, g=g, ball_capacity=ball_capacity,
                  a_lim=a_lim, a_lim_why=a_lim_why, price_table=price_table)
    return choose(statue, srch)


def choose(statue, srch: Search, ignore=(), verified=None) -> Design:
    """The Design of a search: the best passing candidate (the fuse layout checked lazily), or the
    nearest makeable one with the reason and what would work instead."""
    cands = list(srch.candidates)
    passing = rank([c for c in cands if c.passes(ignore)])
    best = None
    checked = []
    for c in passing:
        c2 = with_fuse_layout(c)
        checked.append(c2)
        if c2.passes(ignore):
            best = c2
            break
    n_pass = sum(1 for c in cands if c.passes(ignore))
    notes = []
    if best is not None:
        shown = [best] + [c for c in passing[:SHOWN_PASSING] if c is not best and c.device != best.device]
        failure, wwp = None, None
    else:
        pool = [c for c in cands if not c.passes(ignore)] + [c for c in checked if not c.passes(ignore)]
        best = nearest(pool)
        if best is None:
            best = min(cands, key=_closeness)
            notes.append("no candidate in range can be made (every one fails a groove, board, plate-size or fuse "
                         "check): the least bad is shown only to say why, not as a device to build")
        best = with_fuse_layout(best)
        failure = failure_text(best.checks) + f" [nearest of {len(cands)} candidates; {srch.ranges}]"
        wwp = what_would_pass(best, cands)
        shown = [best]
    failing = sorted((c for c in cands if not c.passes(ignore) and c.makeable), key=_closeness)[:SHOWN_FAILING]
    table = {"criterion": CRITERION, "tried": len(cands), "passing": n_pass, "ranges": srch.ranges,
             "order": "the chosen device first, then passing candidates by the criterion, then failing ones that can "
                      "be made, nearest first",
             "checks": [{"key": k.key, "name": k.name, "unit": k.unit, "required": k.required, "level": k.level}
                        for k in best.checks],
             "check_columns": ["value", "limit", "ratio", "passed"],
             "rows": [c.row() for c in shown] + [c.row() for c in failing]}
    table["shown"] = len(table["rows"])
    return _design_from(best, statue, inputs=srch.inputs, tried=len(cands), candidates=table, failure=failure,
                        notes=tuple(notes), what_would_pass=wwp, evaluated=tuple(cands))


def _design_from(c: Candidate, statue, *, inputs=None, tried=1, candidates=None, failure=None, notes=(),
                 what_would_pass=None, evaluated=(), checks=None, verification=None, criterion=CRITERION) -> Design:
    dev, cx = c.device, c.cx
    iso = Isolator(R=dev.R, r=dev.r, M=cx.m + dev.m_o, mu=c.mu, g=cx.g)
    fuse = _fuse(dev, cx) if cx.fuse_release is not None else {}
    if fuse and fuse.get("ball_radius", 0) > 0:
        seats, _ = _fuse_layout(dev, fuse)
        fuse["centres"] = [list(p) for p in seats]
    bc = {"per_ball": c.ball_capacity.load, "short_term": c.ball_capacity_short, "criterion": c.ball_capacity.criterion,
          "allowed_dent": c.ball_capacity.dent, "source": c.ball_capacity.source, "surface": dev.surface,
          "load_per_ball": iso.W / dev.n, "diameter": dev.D}
    levels = {"design": {"a": c.demand.a_design, "d": c.demand.d, "margin": DISPLACEMENT_MARGIN},
              "SLC": {"a": c.demand.a_slc, "d": c.demand.d_slc, "margin": SLC_MARGIN, "rule": cx.slc_why}}
    return Design(
        R=dev.R, r=dev.r, n_grooves=dev.n, mu=c.mu, M=iso.M, m_o=dev.m_o, T=iso.T, k=iso.k, R_hat=iso.R_hat,
        a_design=c.demand.a_design, a_lim=cx.a_lim, d_design=c.demand.d, d_max=c.d_max, lever_arm=c.lever,
        safety_length=safety_length(c.demand.a_design, c.lever, cx.g), L_cr=dev.L_cr, spacing=dev.spacing,
        side=dev.side, thickness=dev.thickness, depth=dev.depth, opening_radius=dev.opening_radius,
        groove_centres=dev.centres, fuse=fuse,
        checks=tuple(k._replace(why=str(k.why)) for k in (checks if checks is not None else c.checks)),
        input=inputs or {}, candidates_tried=tried, notes=tuple(notes), capacity=c.capacity,
        capacity_groove=c.capacity_groove, capacity_tip=c.capacity_tip, travel_need=c.need,
        margin=DISPLACEMENT_MARGIN, candidates=candidates or {}, failure=failure, criterion=criterion, device=dev,
        friction=c.friction.to_dict(), ball_capacity=bc, levels=levels, cost=c.cost, bom=c.rows,
        verification=verification or {}, what_would_pass=what_would_pass, evaluated=evaluated)


# --- when nothing passes: one sentence --------------------------------------------------------------
RESTRAIN = ("restrain it instead: a discreet clamp or anchor at its base, designed with a conservator, keeps it "
            "from rocking")


def what_would_pass(best: Candidate, cands=(), reasons=None, felt: float | None = None, checks=None) -> dict:
    """Why no device in range passes, in one sentence a conservator understands, and what would work
    instead: {"reason": the failing kind, "text": the sentence, numbers}. ``reasons``: more failing check keys
    (the time histories'); ``felt``: the least felt acceleration the time histories found (m/s^2). The
    acceleration is named the reason only when no candidate in range keeps the felt acceleration below the
    uplift limit. ``checks``: the candidate's checks with the time histories' (default: its own)."""
    checks = best.checks if checks is None else tuple(checks)
    bad = {k.key for k in checks if k.required and not k.passed}
    g = best.cx.g
    lim = best.cx.a_lim
    if reasons:
        bad |= set(reasons)
    out = {"candidate": {"R": best.R, "r": best.r, "n_grooves": best.n_grooves, "layout": best.device.layout,
                         "surface": best.device.surface, "side": best.side, "T": best.T}}
    if "friction" in bad:
        out.update(reason="friction", restrain=True, text=(
            f"It lifts at so little acceleration ({lim / g:.3f} g) that the balls' own rolling resistance would "
            f"rock it before the plate moves; {RESTRAIN}."))
        return out
    if "pit" in bad:
        out.update(reason="pit", restrain=True, text=(
            f"It lifts at so little acceleration ({lim / g:.3f} g) that the balls would not roll out of the small "
            f"pits their weight presses into the grooves before it rocks; {RESTRAIN}."))
        return out
    low = min(c.demand.a_design for c in cands) if cands else best.demand.a_design
    least = low if felt is None else felt          # the time histories decide where they ran
    if bad & {"acceleration", "th_acceleration"} and least > lim:
        top = max((c for c in cands if c.demand.a_design <= low * 1.001), key=lambda c: c.T) if cands else best
        out.update(reason="acceleration", restrain=True, text=(
            f"No rolling-ball device in range keeps it in full contact: even the softest (period {top.T:.1f} s) "
            f"passes it {least / g:.3f} g, above the {lim / g:.3f} g that lifts it; {RESTRAIN}."))
        return out
    if bad & {"plate_size", "travel", "travel_slc", "th_travel", "th_travel_slc", "reserve", "overturning",
              "overturning_slc", "depth", "proud"}:
        levels = {"travel": "design", "th_travel": "design", "travel_slc": "SLC", "th_travel_slc": "SLC",
                  "reserve": "reserve"}
        needs = [(k.value, levels[k.key]) for k in checks if k.key in levels]
        need, level = max(needs) if needs else (best.need, "design")
        reason = "reserve" if level == "reserve" else "plate_size"
        what = {"reserve": "to keep a reserve up to where it would overturn without the device",
                "design": "for the design earthquake", "SLC": "for the collapse-level earthquake (SLC)"}[level]
        out.update(reason=reason, restrain=True, side_needed=best.side_needed, travel_needed=need, text=(
            f"The device it needs {what} is larger than a {best.cx.side_max:g} m panel (its grooves must travel "
            f"{need:.2f} m, a plate about {best.side_needed:.2f} m wide); a custom larger device, or {RESTRAIN}."))
        return out
    if bad & {"ball_load", "ball_load_slc", "th_ball_load_slc"}:
        P = best.W / best.n_grooves
        out.update(reason="ball_load", restrain=False, text=(
            f"It is too heavy for the groove surfaces in range ({P:.0f} N per ball against at most "
            f"{best.ball_capacity.load:.0f} N); a specialist's steel-race isolator would carry it, or {RESTRAIN}."))
        return out
    out.update(reason="other", restrain=False, text=(
        f"No device in range passes every check ({failure_text(checks, shown=1)}); {RESTRAIN}."))
    return out


def assess(statue, *, R: float, r: float, n_grooves: int, opening_radius: float, spacing: float, side: float,
           thickness: float, mu: float, spectrum=None, motion=None, slc=None, target: float | None = None,
           alpha: tuple[float, float] = (1.0, 1.0), fuse_release: float | None = None, fuse_ball: float | None = None,
           side_max: float = SIDE_MAX, g: float = G, ball_capacity: float | None = None, surface: str = "beech",
           ball: str = "resin", layout: str | None = None) -> Design:
    """Check a given device (no search): grooves R, balls r, ``n_grooves`` grooves of opening radius
    ``opening_radius``, centres ``spacing`` apart (layout ``layout``, default the ring of n), a square plate
    ``side`` x ``thickness`` (m) on ``surface``, under one design input."""
    _check_inputs(spectrum, motion, mu, alpha, (thickness,), target, (r,), (R,), side_max)
    if not 0 < opening_radius <= R:
        raise InputError(f"opening radius must be in (0, R = {R:g}] m, got {opening_radius!r}")
    layout = layout or next((k for k, lay in LAYOUTS.items() if lay.n == n_grooves and k.startswith("ring")), None)
    if layout is None:
        raise InputError(f"no ring layout has {n_grooves} balls")
    if surface not in BALLS_MATERIALS[ball].surfaces:
        ball = "steel"
    cx = _context(statue, g, alpha, target, None, None, side_max, 0.0, fuse_release, fuse_ball, mu, None, None,
                  prices(), ball_capacity, (thickness,), "the design spectrum x gamma_x 1.2")
    low = cx.mu_given[1]
    dem = _demand_fn(spectrum, slc, motion, low, g)(R, r)
    lay = LAYOUTS[layout]
    depth = groove_depth(R, opening_radius)
    s = SURFACES[surface]
    m_o = s.density * max(side * side * thickness - n_grooves * math.pi * depth ** 2 * (3 * R - depth) / 3,
                          0.5 * side * side * thickness) + n_grooves * s.liner_density * s.layer * 2 * math.pi * R * depth
    fuse_r, n_fuse = 0.0, 0
    if fuse_release is not None:
        gap = 2 * (r - depth)
        c = fuse_seat_depth(1.0, fuse_release, g)
        fuse_r = (gap / 2 / (1.0 - c) if fuse_ball is None else fuse_ball) if gap > 0 else 0.0
        n_fuse = lay.n if fuse_r > 0 else 0
    dev = Device(R=R, r=r, ball=ball, layout=layout, n=lay.n, surface=surface, layers=((thickness, 1),),
                 thickness=thickness, side=side, side_needed=side, spacing=spacing, L_cr=lay.L_cr(spacing), opening_radius=opening_radius, depth=depth, m_o=m_o,
                 fuse_ball=fuse_r, n_fuse=n_fuse)
    fr = _friction(dev.D, (cx.m + m_o) * g / lay.n, ball, surface, R, cx)
    need = travel_need(dem.d, fr.mu_high, dev.R_hat)
    c = _evaluate(dev, fr, need, dem, cx, with_fuse_layout=fuse_release is not None)
    ok = c.passes()
    table = {"criterion": "given device (no search)", "tried": 1, "passing": int(ok), "shown": 1,
             "checks": [{"key": k.key, "name": k.name, "unit": k.unit, "required": k.required} for k in c.checks],
             "check_columns": ["value", "limit", "ratio", "passed"], "rows": [c.row()]}
    return _design_from(c, statue, inputs={"spectrum": spectrum.to_dict() if spectrum is not None else None},
                        candidates=table, failure=None if ok else failure_text(c.checks),
                        criterion="given device (no search)")


def replace_checks(d: Design, checks) -> Design:
    return replace(d, checks=tuple(checks))
