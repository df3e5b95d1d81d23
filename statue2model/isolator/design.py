"""Design of a rolling-ball isolator for one statue (thesis ch. 5.1, 5.3, 6.4).

Input: the statue's rocking parameters (m, h, a_L, a_R; reduced by alpha when the
base is imperfect), a friction coefficient mu, and a design input: an elastic
response spectrum (EC8 / NTC 2018, design_spectrum.py) or a ground motion that
is simulated on every candidate. Optionally a stricter target for the plate's
absolute acceleration.

Procedure, for ball radii ``balls`` and groove radii R on a grid (smallest
first), n grooves (3 or 4; by default both are designed and the smaller plate is
kept):

1. the plate's absolute acceleration: Se(T) from the spectrum (as in ch. 6.4),
   or the simulated peak |a_abs|, must stay below a_lim = min(alpha_L a_L,
   alpha_R a_R, target); friction adds up to mu g, checked separately;
2. design displacement d: SDe(T) or the simulated peak |u_o|;
3. grooves: each ball rolls d/2 on each plate, so the opening radius is
   d/2 + r + margin and the depth follows from the spherical cap; at least
   MIN_BOTTOM of wood must remain under a groove, and the balls must stand
   proud of the grooves (a gap of MIN_GAP between the plates);
4. the plate is at least as large as the statue's base (2 max(b_L, b_R) + edges,
   or ``min_side``); top-plate overturning (eqs. 47-49): lever arm l, safety length
   a = (a_design/g) l, allowable displacement d_max = L_cr - a with L_cr the
   distance from the plate centre to the tipping line of the grooves (half the
   groove spacing for 4 grooves, the inradius of the triangle for 3); the groove
   spacing is chosen so that d <= d_max;
5. optional fuse (eq. 52): seat depth for a release acceleration, which must be
   below a_lim (the statue must not rock before the plate is released).

The first candidate that passes every required check is the design; the report
says pass/fail per check and why, also when nothing passes.

Example
-------
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.isolator.design_spectrum import ec8
>>> statue = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.8})
>>> d = design(statue, spectrum=ec8(0.05 * 9.80665, "A"), mu=0.0073)
>>> d.passed, d.n_grooves, round(d.T, 2) > 1.0
(True, 3, True)
>>> d.notes[-1]                           # both plates are as small as the statue's base
'3 grooves: plate 439 mm vs 4 grooves: 439 mm'
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import InputError
from .device import (
    G,
    Isolator,
    allowable_displacement,
    fuse_release_acceleration,
    fuse_seat_depth,
    lever_arm,
    safety_length,
)

BALLS = (0.0095, 0.0125, 0.0183, 0.020, 0.025)
"""Ball radii tried (m): the thesis' steel 9.5 mm, resin 18.3 mm, ivory 20 mm, and two more."""
R_GRID = tuple(np.round(np.arange(0.20, 3.001, 0.05), 3))
MIN_BOTTOM = 0.005
"""Wood left under the deepest point of a groove, m."""
EDGE = 0.02
"""Wood between a groove opening and the plate edge, m."""
GAP = 0.01
"""Wood between two groove openings, m."""
MIN_GAP = 0.002
"""Least clearance between the plates, m: the balls stand 2 (r - depth) proud."""
WOOD_DENSITY = 700.0
"""Beech, kg/m^3 (the thesis' plates)."""


@dataclass(frozen=True)
class Check:
    name: str
    passed: bool
    value: float
    limit: float
    why: str
    required: bool = True

    def to_dict(self) -> dict:
        return {"name": self.name, "passed": self.passed, "value": self.value, "limit": self.limit,
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
    d_max: float
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

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks if c.required)

    def isolator(self, model: str = "coulomb", q: float = 30.0) -> Isolator:
        return Isolator(R=self.R, r=self.r, M=self.M, mu=self.mu, model=model, q=q)

    def to_dict(self) -> dict:
        out = {k: getattr(self, k) for k in (
            "R", "r", "R_hat", "T", "k", "n_grooves", "mu", "M", "m_o", "a_design", "a_lim", "d_design", "d_max",
            "lever_arm", "safety_length", "L_cr", "spacing", "side", "thickness", "depth", "opening_radius",
            "fuse", "input", "candidates_tried")}
        out["groove_centres"] = [list(c) for c in self.groove_centres]
        out["passed"] = self.passed
        out["checks"] = [c.to_dict() for c in self.checks]
        out["notes"] = list(self.notes)
        out["schema"] = "statue2model.isolator_design/1"
        return out

    def report(self) -> str:
        lines = [
            f"Rolling-ball isolator: {'PASS' if self.passed else 'FAIL'}",
            f"  grooves R = {self.R:.3f} m, balls r = {self.r * 1000:.1f} mm, R_hat = {self.R_hat:.3f} m, "
            f"T = {self.T:.2f} s, k = {self.k:.1f} N/m, {self.n_grooves} grooves",
            f"  plates {self.side * 1000:.0f} x {self.side * 1000:.0f} x {self.thickness * 1000:.0f} mm, "
            f"groove spacing {self.spacing * 1000:.0f} mm, depth {self.depth * 1000:.1f} mm, "
            f"opening radius {self.opening_radius * 1000:.1f} mm",
            f"  plate acceleration {self.a_design:.4f} m/s^2 vs limit {self.a_lim:.4f} m/s^2; "
            f"design displacement {self.d_design * 1000:.1f} mm vs allowable {self.d_max * 1000:.1f} mm",
            "",
            "checks:",
        ]
        for c in self.checks:
            mark = "pass" if c.passed else ("FAIL" if c.required else "note")
            lines.append(f"  [{mark}] {c.name}: {c.why}")
        lines += [f"  {n}" for n in self.notes]
        return "\n".join(lines)


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


def _demand(iso: Isolator, spectrum, motion):
    if spectrum is not None:
        return float(spectrum.Se(iso.T)), float(spectrum.SDe(iso.T)), None
    from .dynamics import simulate

    res = simulate(iso, motion, dt_out=0.01)
    return res.acc_abs_max, res.u_max, res


def design(statue, *, mu: float, spectrum=None, motion=None, target: float | None = None,
           alpha: tuple[float, float] = (1.0, 1.0), n_grooves: int | None = None, thickness: float = 0.03,
           balls=BALLS, R_grid=R_GRID, wood_density: float = WOOD_DENSITY, fuse_release: float | None = None,
           fuse_ball: float | None = None, min_side: float | None = None, g: float = G) -> Design:
    """Choose R, r, number of grooves, spacing and plate size for ``statue``
    (RockingParams); see the module. ``n_grooves`` None designs with 3 and with 4
    grooves and keeps the passing design with the smaller (lighter) plate; on a tie,
    3 grooves (three balls always share the load, even on an uneven floor)."""
    if n_grooves is not None:
        return _design(statue, mu=mu, spectrum=spectrum, motion=motion, target=target, alpha=alpha,
                       n_grooves=n_grooves, thickness=thickness, balls=balls, R_grid=R_grid,
                       wood_density=wood_density, fuse_release=fuse_release, fuse_ball=fuse_ball,
                       min_side=min_side, g=g)
    kw = dict(mu=mu, spectrum=spectrum, motion=motion, target=target, alpha=alpha, thickness=thickness,
              balls=balls, R_grid=R_grid, wood_density=wood_density, fuse_release=fuse_release,
              fuse_ball=fuse_ball, min_side=min_side, g=g)
    three, four = (_design(statue, n_grooves=n, **kw) for n in (3, 4))
    best = min((three, four), key=lambda d: (not d.passed, round(d.side, 6), d.n_grooves))
    other = four if best is three else three
    why = (f"{best.n_grooves} grooves: plate {best.side * 1000:.0f} mm"
           f"{'' if best.passed else ' (fails)'} vs {other.n_grooves} grooves: {other.side * 1000:.0f} mm"
           f"{'' if other.passed else ' (fails)'}")
    return replace(best, notes=best.notes + (why,))


def _design(statue, *, mu, spectrum, motion, target, alpha, n_grooves, thickness, balls, R_grid,
            wood_density, fuse_release, fuse_ball, min_side, g) -> Design:
    if (spectrum is None) == (motion is None):
        raise InputError("give exactly one design input: a response spectrum or a ground motion")
    if not (math.isfinite(mu) and 0 <= mu < 0.5):
        raise InputError(f"rolling friction mu must be in [0, 0.5), got {mu}")
    if not all(0 < a <= 1 for a in alpha):
        raise InputError(f"alpha must be in (0, 1], got {alpha}")
    if not (0.01 <= thickness <= 0.2):
        raise InputError(f"plate thickness {thickness * 1000:g} mm is out of range (10 to 200 mm)")
    if target is not None and not (math.isfinite(target) and target > 0):
        raise InputError(f"target acceleration must be positive, got {target}")
    a_lim = min(alpha[0] * statue.a_L, alpha[1] * statue.a_R)
    why_lim = f"min(alpha_L a_L, alpha_R a_R) = {a_lim:.4f} m/s^2"
    if target is not None and target < a_lim:
        a_lim, why_lim = target, f"target {target:.4f} m/s^2 (below the statue's limit)"
    m = statue.m
    if min_side is None:                 # the statue's base must fit on the top plate
        min_side = 2 * max(statue.b_L, statue.b_R) + 2 * EDGE
    tried = 0
    best = None
    for r in sorted(balls):
        for R in sorted(R_grid):
            if R <= 2 * r:
                continue
            tried += 1
            # the top plate's mass depends on its size, which depends on the demand: iterate twice
            m_o = 0.0
            for _ in range(3):
                iso = Isolator(R=R, r=r, M=m + m_o, mu=mu, g=g)
                a_design, d, _ = _demand(iso, spectrum, motion)
                opening = d / 2 + r + 0.005
                if opening >= R:
                    break
                depth = R - math.sqrt(R * R - opening * opening)
                l = lever_arm(m, statue.h, max(m_o, 1e-9), thickness)
                a_s = safety_length(a_design, l, g)
                L_need = d + a_s
                spacing = max(2 * opening + GAP, 2 * L_need if n_grooves == 4 else 2 * math.sqrt(3) * L_need)
                centres, L_cr = _layout(n_grooves, spacing)
                ext = max(max(abs(x), abs(y)) for x, y in centres)
                side = max(2 * (ext + opening + EDGE), min_side)
                m_o = wood_density * side * side * thickness
            else:
                cand = (R, r, iso, a_design, d, opening, depth, l, a_s, spacing, centres, L_cr, side, m_o)
                ok = a_design <= a_lim and depth <= thickness - MIN_BOTTOM and depth <= r - MIN_GAP / 2
                if best is None or (ok and not best[0]):
                    best = (ok, cand)
                if ok:
                    break
        if best is not None and best[0]:
            break
    if best is None:
        raise InputError("no groove radius in the grid is larger than the balls' diameter")
    ok, (R, r, iso, a_design, d, opening, depth, l, a_s, spacing, centres, L_cr, side, m_o) = best
    d_max = allowable_displacement(L_cr, a_s)
    checks = [
        Check("plate acceleration below the statue's uplift limit", a_design <= a_lim, a_design, a_lim,
              f"{a_design:.4f} m/s^2 {'<=' if a_design <= a_lim else '>'} {why_lim}"),
        Check("with the friction force added", a_design + mu * g <= a_lim, a_design + mu * g, a_lim,
              f"a + mu g = {a_design + mu * g:.4f} m/s^2 vs {a_lim:.4f} m/s^2 (friction transmits up to mu g)",
              required=False),
        Check("groove depth leaves wood under the groove", depth <= thickness - MIN_BOTTOM, depth,
              thickness - MIN_BOTTOM, f"depth {depth * 1000:.1f} mm, plate {thickness * 1000:.0f} mm, "
              f"at least {MIN_BOTTOM * 1000:.0f} mm must remain"),
        Check("the plates stay apart (balls stand proud of the grooves)", depth <= r - MIN_GAP / 2,
              2 * (r - depth), MIN_GAP, f"gap 2 (r - depth) = {2 * (r - depth) * 1000:.1f} mm, "
              f"at least {MIN_GAP * 1000:.0f} mm"),
        Check("top plate does not overturn (eq. 49)", d <= d_max + 1e-12, d, d_max,
              f"design displacement {d * 1000:.1f} mm <= d_max = L_cr - a = {L_cr * 1000:.1f} - {a_s * 1000:.1f} mm"),
        Check("ball stays in its groove", d / 2 + r <= opening, d / 2 + r, opening,
              f"ball travel d/2 + r = {(d / 2 + r) * 1000:.1f} mm within the opening radius {opening * 1000:.1f} mm"),
    ]
    fuse = {}
    if fuse_release is not None:
        # the fuse balls carry the plate at rest: diameter = the gap between the plates + two seats,
        # 2 r_f = 2 (r - depth) + 2 z with z = c r_f (eq. 52 solved for z)
        c = fuse_seat_depth(1.0, fuse_release, g)
        r_f = (r - depth) / (1.0 - c) if fuse_ball is None else fuse_ball
        z = fuse_seat_depth(r_f, fuse_release, g)
        back = fuse_release_acceleration(r_f, z, g)
        fuse = {"ball_radius": r_f, "seat_depth": z, "release": back, "release_g": back / g,
                "gap": 2 * (r - depth)}
        checks.append(Check("fuse releases before the statue rocks", back < a_lim, back, a_lim,
                            f"release {back:.4f} m/s^2 ({back / g:.3f} g) vs {a_lim:.4f} m/s^2"))
    notes = []
    if not ok:
        notes.append("no candidate met every check: the one shown comes closest; try more friction-free balls, "
                     "a thicker plate, a larger R grid, or a less demanding design input")
    inp = {"spectrum": spectrum.to_dict() if spectrum is not None else None,
           "motion": motion.to_dict() if motion is not None else None, "target": target,
           "alpha": list(alpha), "statue": {"m": m, "h": statue.h, "a_L": statue.a_L, "a_R": statue.a_R}}
    return Design(
        R=R, r=r, n_grooves=n_grooves, mu=mu, M=iso.M, m_o=m_o, T=iso.T, k=iso.k, R_hat=iso.R_hat,
        a_design=a_design, a_lim=a_lim, d_design=d, d_max=d_max, lever_arm=l, safety_length=a_s, L_cr=L_cr,
        spacing=spacing, side=side, thickness=thickness, depth=depth, opening_radius=opening,
        groove_centres=tuple(centres), fuse=fuse, checks=tuple(checks), input=inp, candidates_tried=tried,
        notes=tuple(notes),
    )
