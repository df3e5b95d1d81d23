"""What a ball carries on a groove surface, and how hard it rolls there (MODEL.md section 9;
thesis ch. 5.2, 6.4, Tables 19 and 25). SI units: N, m, Pa.

Two registries, one row per choice a workshop makes:

* :data:`BALLS_MATERIALS` - the balls: steel (bearing steel, stock sizes) and resin (the
  thesis' 18.3 mm and 20 mm balls);
* :data:`SURFACES` - what the grooves are cut in: beech (the thesis), robinia (a harder
  hardwood), beech lined with the thesis' 3.2 mm rubber layer, an HDPE or a POM plate, and beech
  lined with hardened steel races (shells glued in each groove).

Capacity per ball (:func:`ball_capacity`). Two criteria, stated:

``dent`` (wood, rubber-lined wood, polymers): the ball may leave at most the dent the thesis'
grooves carried undamaged: 30 kg on four 20 mm-radius balls (73.6 N on a ball of diameter
D0 = 40 mm, ch. 6.4; heavier loads pitted the grooves, ch. 5.2). A dent is a pit the ball must
roll out of: a pit of depth delta holds the ball like a fuse seat (eq. 52) until the plate
accelerates g sqrt(2 r delta - delta^2) / (2 (r - delta)), so pits change the device. The
dent follows Meyer's law F = A c^n / D^(n - 2) (c the dent's chord, D the ball's diameter;
n = 2.5 for beech, Koczan et al. 2021, J. Wood Sci. 67:31), with A from the surface's Brinell
hardness HB (EN 1534: a 10 mm ball, 1 kN, HB = F / (pi D h), h the dent depth). For beech
(HB 34 N/mm^2, the lower end of 34-37) the calibration point's dent is DENT_CALIBRATION:
delta0 = 0.046 mm, delta0 / D0 = 1.15e-3 (MODEL.md: "about 0.03 mm"; a pit releasing at
0.034 g on the 20 mm ball). The allowed dent is delta0 both as an absolute depth (smooth
rolling: the same pit on every ball) and relative to the ball (the same roll-out
acceleration); the capacity is the LOWER of the two loads (the conservative reading):

    F(delta, D) = A c^n / D^(n-2),   c = 2 sqrt(delta (D - delta))
    F_short(D)  = min(F(delta0, D), F(delta0 D / D0, D))      ~ D^(2 - n/2) above D0, D^2 below

Below D0 the relative criterion governs (F ~ D^2, the r^2 scaling the thesis used); above it
the absolute one (F ~ D^0.75 on beech): a larger ball helps less than r^2 would say. On beech
F_short(D0) = 73.6 N exactly (the calibration). A museum device carries its statue for decades:
F = F_short x long_term, long_term the surface's creep factor (wood 1 / (1 + k_def), k_def 0.6
for solid timber in service class 1, EN 1995-1-1 Table 3.2; polymers the ratio of their
long-term (10^5 h) to short-term creep modulus).

``race`` (hardened steel race): the static load rating of a ball on a race (Stribeck; ISO 76):
the Hertz contact pressure p0 = 4200 MPa leaves a permanent deformation of about 1e-4 D. For a
ball of radius r in a spherical groove of radius R >> r (R_e = r R / (R - r)),

    C0 = pi^3 p0^3 R_e^2 / (6 E*^2) / s0 = k D^2 / 5 per ball (Stribeck's form, k = 35.9 N/mm^2
    for R_e = r and s0 = 1),  E* = E / (2 (1 - nu^2)) for steel on steel,

with the static safety factor s0 = 2 (ISO 76 / bearing catalogues: s0 >= 2 where quiet running is
required). Steel balls only.

Friction (:func:`rolling_friction`). The thesis measured the rolling friction mu against the
supported mass on its three-groove device (Table 19: steel 9.5 mm, resin 18.3 mm, resin with
the rubber layer) and four-groove device (Table 25: resin 20 mm balls), roughly linear in the
load (Fig. 86). Rolling resistance on a soft surface is the ball climbing out of its own dent,
whose shape is set by the load relative to what the surface carries, so each measured pair is
fitted as mu = a + b u with u = P / F_short(D) the utilisation of the short-term capacity
(P = W / n the load per ball): FRICTION_DATA (resin balls: the table of the nearest ball size).
A pair the thesis measured is read from its fit: with its ball size and inside the measured loads
that is data ("measured"), outside them an extrapolation; another ball size, another hardwood (the
beech fit of the same ball material), polymers and steel races (a constant from the literature) are
assumptions ("assumed"), and :class:`FrictionEstimate` says which.
The design verifies at the bounds mu x (MU_LOW_FACTOR, MU_HIGH_FACTOR)
(statue2model.isolator.friction.friction_bounds: Table 25's spread about its nominal value).

Example
-------
>>> beech = SURFACES["beech"]
>>> round(ball_capacity(0.040, beech, long_term=False).load, 2)        # the calibration point, N
73.57
>>> round(ball_capacity(0.019, beech, long_term=False).load, 2)        # 9.5 mm balls: relative dent, D^2
16.6
>>> cap = ball_capacity(0.100, beech)                                  # 50 mm balls: absolute dent, / 1.6
>>> cap.criterion, round(cap.load, 1)
('absolute dent 0.046 mm', 91.5)
>>> est = rolling_friction(0.040, 24.359 * 9.81 / 4, BALLS_MATERIALS["resin"], beech)
>>> round(est.mu, 4), est.basis                                        # Table 25: 0.0108
(0.0103, 'measured')
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..errors import InputError
from ..quantities import G

D0 = 0.040
"""m: diameter of the balls of the thesis' undamaged four-groove device (r = 20 mm)."""
F0 = 30.0 * G / 4
"""N per ball: 30 kg on its four balls undamaged (ch. 6.4), the calibration point."""
HB_REF = (0.010, 1000.0)
"""EN 1534's Brinell test of wood: a 10 mm ball pressed with 1 kN (D m, F N)."""
K_DEF_WOOD = 0.6
"""EN 1995-1-1 Table 3.2: k_def of solid timber in service class 1 (a heated museum room)."""
P0_RACE = 4.2e9
"""Pa: ISO 76's Hertz pressure for a permanent deformation of about 1e-4 D (hardened steel)."""
S0_RACE = 2.0
"""ISO 76 / bearing catalogues: static safety factor where quiet running is required."""
E_STEEL, NU_STEEL = 210e9, 0.3
from .friction import MU_HIGH_FACTOR, MU_LOW_FACTOR  # noqa: E402  (Table 25's spread: friction.friction_bounds)


@dataclass(frozen=True)
class BallMaterial:
    """A ball material: ``key``, a name, the density (kg/m^3) and the surfaces it may roll on."""

    key: str
    name: str
    density: float
    surfaces: tuple
    source: str


@dataclass(frozen=True)
class Surface:
    """A groove surface. ``criterion``: "dent" (Meyer's law from the Brinell hardness ``hb``, Pa,
    and Meyer index ``n``) or "race" (hardened steel, ISO 76). ``long_term``: the creep factor on
    the capacity. ``kind``: "wood" (the plate is cut from boards), "lined" (wooden boards with a liner
    ``layer`` m thick, of density ``liner_density``, glued in each groove: the groove is milled that much
    deeper), "sheet" (the plate is cut from a polymer sheet). ``friction``: the key of FRICTION_DATA or a
    number (an assumed constant mu)."""

    key: str
    name: str
    kind: str
    criterion: str
    hb: float
    n: float
    long_term: float
    density: float
    friction: dict
    source: str
    layer: float = 0.0
    liner_density: float = 0.0


BALLS_MATERIALS = {
    "steel": BallMaterial("steel", "steel balls (bearing steel 100Cr6 / AISI 52100, grade G100)", 7850.0,
                          ("beech", "robinia", "beech_rubber", "hdpe", "pom", "steel_race"),
                          "stock sizes; the thesis' 9.5 mm balls (Table 19)"),
    "resin": BallMaterial("resin", "resin balls (phenolic)", 1300.0, ("beech", "robinia", "beech_rubber"),
                          "the thesis' 18.3 mm (Table 19) and 20 mm (Table 25) balls; on wood only, as tested"),
}
"""Ball materials (registry)."""

SURFACES = {
    "beech": Surface(
        "beech", "beech boards (the thesis)", "wood", "dent", 34e6, 2.5, 1 / (1 + K_DEF_WOOD), 700.0,
        {"steel": "steel_beech", "resin": ("resin_beech", "resin_beech_19")},
        "calibrated on the thesis' grooves (30 kg on four 20 mm balls undamaged, ch. 6.4); Brinell HB 34-37 N/mm^2 "
        "(EN 1534, MODEL.md section 9), Meyer n 2.5 (Koczan et al. 2021); creep k_def 0.6 (EN 1995-1-1 Tab. 3.2)"),
    "robinia": Surface(
        "robinia", "robinia (black locust) boards", "wood", "dent", 48e6, 2.5, 1 / (1 + K_DEF_WOOD), 750.0,
        {"steel": "steel_beech", "resin": ("resin_beech", "resin_beech_19")},
        "Brinell HB about 48 N/mm^2 across the grain (Wagenfuehr, Holzatlas; parquet tables give 43-50); "
        "Meyer n and creep as beech (assumed); friction: the beech fits at the same utilisation (assumed)"),
    "beech_rubber": Surface(
        "beech_rubber", "beech with the thesis' 3.2 mm rubber layer glued in the grooves", "lined", "dent", 34e6,
        2.5, 1 / (1 + K_DEF_WOOD), 700.0, {"steel": "resin_rubber", "resin": "resin_rubber"},
        "the thesis' Linatex layer (ch. 5.2): no higher capacity is claimed (its grooves pitted too, Fig. 85), "
        "the capacity is the beech's; friction Table 19 with rubber (steel balls: assumed the same)", layer=0.0032,
        liner_density=1100.0),
    "hdpe": Surface(
        "hdpe", "HDPE sheet (PE 500)", "sheet", "dent", 50e6, 2.0, 0.3, 955.0, {"steel": 0.008},
        "ball indentation hardness about 50 N/mm^2 (ISO 2039-1, manufacturers' datasheets of PE-HD 500); Meyer "
        "n 2 (assumed); long-term factor 0.3 (ratio of the 10^5 h to the short-term creep modulus, typical of "
        "PE-HD); friction 0.008 (assumed: viscoelastic rolling loss of a polymer liner, no thesis data)"),
    "pom": Surface(
        "pom", "POM-C sheet (acetal copolymer)", "sheet", "dent", 150e6, 2.0, 0.4, 1410.0, {"steel": 0.005},
        "ball indentation hardness about 150 N/mm^2 (ISO 2039-1, manufacturers' datasheets of POM-C); Meyer n 2 "
        "(assumed); long-term factor 0.4 (creep modulus ratio, typical of POM-C); friction 0.005 (assumed, no "
        "thesis data)"),
    "steel_race": Surface(
        "steel_race", "beech lined with hardened steel races (6 mm shells, 58-62 HRC, glued in each groove)",
        "lined", "race", 0.0, 0.0, 1.0, 700.0, {"steel": 0.002},
        "static load rating ISO 76 (Stribeck, p0 4200 MPa, s0 2; the shell spreads the load on the wood under it); "
        "friction 0.002 (assumed: rolling resistance of hardened steel balls on steel, 0.001-0.002; no thesis data)",
        layer=0.006, liner_density=7850.0),
}
"""Groove surfaces (registry)."""

FRICTION_DATA = {
    # key: (description, ball diameter m, n balls of the device, (M kg ...), (mu ...), table)
    "resin_beech": ("Table 25: four-groove device, 20 mm resin balls on beech, no rubber", 0.040, 4,
                    (4.359, 9.359, 14.359, 19.359, 24.359), (0.0039, 0.0055, 0.0070, 0.0081, 0.0108), "25"),
    "steel_beech": ("Table 19: three-groove device, 9.5 mm steel balls on beech, no rubber", 0.019, 3,
                    (11.664, 21.664, 31.664, 41.664, 51.664), (0.0131, 0.0194, 0.0254, 0.0312, 0.0370), "19"),
    "resin_beech_19": ("Table 19: three-groove device, 18.3 mm resin balls on beech, no rubber", 0.0366, 3,
                       (11.664, 21.664, 31.664, 41.664, 51.664), (0.0094, 0.0114, 0.0130, 0.0154, 0.0170), "19"),
    "resin_rubber": ("Table 19: three-groove device, 18.3 mm resin balls on beech with the 3.2 mm rubber layer", 0.0366,
                     3, (11.664, 21.664, 31.664, 41.664, 51.664), (0.0133, 0.0150, 0.0170, 0.0193, 0.0209), "19"),
}
"""The thesis' friction measurements (Tables 19 and 25): mu against the supported mass."""


# --- capacity ---------------------------------------------------------------------------------
def meyer_A(hb: float, n: float) -> float:
    """Meyer's A (N m^(2-n)) of a surface of Brinell hardness ``hb`` (Pa) and Meyer index ``n``,
    from EN 1534's test (HB_REF: the dent depth h = F / (pi D HB), its chord c = 2 sqrt(h (D - h)))."""
    D, F = HB_REF
    h = F / (math.pi * D * hb)
    c = 2 * math.sqrt(h * (D - h))
    return F * D ** (n - 2) / c ** n


def dent_load(delta: float, D: float, hb: float, n: float) -> float:
    """N: the load that dents a surface (Brinell ``hb`` Pa, Meyer ``n``) ``delta`` m deep under a
    ball of diameter ``D`` m (Meyer's law)."""
    c = 2 * math.sqrt(delta * (D - delta))
    return meyer_A(hb, n) * c ** n / D ** (n - 2)


def dent_depth(F: float, D: float, hb: float, n: float) -> float:
    """m: the dent a load ``F`` (N) leaves under a ball of diameter ``D`` (Meyer's law inverted)."""
    if F <= 0:
        return 0.0
    c = (F * D ** (n - 2) / meyer_A(hb, n)) ** (1.0 / n)
    c = min(c, D)
    return D / 2 - math.sqrt(max((D / 2) ** 2 - (c / 2) ** 2, 0.0))


def _calibration() -> float:
    beech = SURFACES["beech"]
    return dent_depth(F0, D0, beech.hb, beech.n)


DENT_CALIBRATION = _calibration()
"""m: the dent of the calibration point on beech (0.046 mm), the allowed dent on every surface."""


def pit_release(r: float, delta: float, g: float = G) -> float:
    """m/s^2: the plate acceleration that rolls a ball of radius r out of a pit delta deep (eq. 52)."""
    if delta <= 0:
        return 0.0
    delta = min(delta, 0.999 * r)
    return g * math.sqrt(2 * r * delta - delta * delta) / (2 * (r - delta))


@dataclass(frozen=True)
class Capacity:
    """The load one ball may carry (N) on a surface: ``load`` (long-term when ``long_term``),
    ``short`` (the short-term load), the ``criterion`` that governs, and its ``source``."""

    load: float
    short: float
    criterion: str
    source: str
    dent: float          # the allowed dent, m (0 for a race)

    def to_dict(self) -> dict:
        return {"load": self.load, "short_term": self.short, "criterion": self.criterion, "allowed_dent": self.dent,
                "source": self.source}


def race_rating(D: float, R: float | None = None, s0: float = S0_RACE) -> float:
    """N: ISO 76 static load rating of one steel ball of diameter ``D`` (m) on a hardened steel race
    of radius of curvature ``R`` (m; None: flat), divided by the static safety factor ``s0``."""
    r = D / 2
    Re = r if R is None or not math.isfinite(R) else r * R / (R - r)
    E_star = E_STEEL / (2 * (1 - NU_STEEL ** 2))
    return math.pi ** 3 * P0_RACE ** 3 * Re ** 2 / (6 * E_star ** 2) / s0


def ball_capacity(D: float, surface: Surface, R: float | None = None, long_term: bool = True,
                  tested: float | None = None) -> Capacity:
    """The load (N) one ball of diameter ``D`` (m) may carry on ``surface`` (module docstring); ``R``
    the groove radius (m; a race's conformity). ``tested``: a load test of the user's surface, N on a
    40 mm ball (the thesis' ball) with the same dent, replaces the surface's hardness (scaled to D by the
    same two criteria)."""
    if not (math.isfinite(D) and D > 0):
        raise InputError(f"ball diameter must be a positive length in m, got {D!r}")
    lt = surface.long_term if long_term else 1.0
    if surface.criterion == "race":
        short = race_rating(D, R)
        if tested is not None:           # a load test of the race on a 40 mm ball, scaled as the rating
            short *= tested / race_rating(D0, R)
            return Capacity(short * lt, short, "a load test, scaled as the ISO 76 rating", "a load test of the race",
                            0.0)
        return Capacity(short * lt, short, f"ISO 76 static rating / s0 {S0_RACE:g}", surface.source, 0.0)
    d_abs, d_rel = DENT_CALIBRATION, DENT_CALIBRATION / D0 * D
    f_abs = dent_load(d_abs, D, surface.hb, surface.n)
    f_rel = dent_load(d_rel, D, surface.hb, surface.n)
    short, crit = (f_abs, f"absolute dent {d_abs * 1000:.3f} mm") if f_abs <= f_rel else \
        (f_rel, f"relative dent {d_rel / D:.2e} D")
    source = surface.source
    if tested is not None:
        scale = tested / min(dent_load(d_abs, D0, surface.hb, surface.n), dent_load(DENT_CALIBRATION, D0, surface.hb,
                                                                                      surface.n))
        short *= scale
        source = f"a load test of the surface: {tested:.1f} N on a {D0 * 1000:g} mm ball, scaled as the surface's law"
    return Capacity(short * lt, short, crit, source, min(d_abs, d_rel))


@lru_cache(maxsize=4096)
def _short(D: float, surface: str, R: float | None) -> float:
    return ball_capacity(D, SURFACES[surface], R, long_term=False).short


# --- friction ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class FrictionEstimate:
    """The rolling friction of one ball/surface pair at a load per ball: ``mu`` (nominal), the bounds
    ``mu_low``, ``mu_high`` the design verifies at, ``basis`` ("measured", "extrapolated" or
    "assumed") and ``note`` (where the thesis' data end and an assumption starts)."""

    mu: float
    mu_low: float
    mu_high: float
    basis: str
    note: str
    utilisation: float

    def to_dict(self) -> dict:
        return {"mu": self.mu, "mu_low": self.mu_low, "mu_high": self.mu_high, "basis": self.basis,
                "note": self.note, "utilisation": self.utilisation}


@lru_cache(maxsize=64)
def friction_fit(key: str, g: float = G) -> tuple[float, float, float, float]:
    """(a, b, u_min, u_max): the least-squares line mu = a + b u of FRICTION_DATA[key] in the
    utilisation u = P / F_short(D) of its balls on beech (P the load per ball), and the range of u
    the table covers."""
    _, D, n, M, mu, _ = FRICTION_DATA[key]
    cap = ball_capacity(D, SURFACES["beech"], long_term=False).short
    u = np.asarray(M, dtype=float) * g / n / cap
    b, a = np.polyfit(u, np.asarray(mu, dtype=float), 1)
    return float(a), float(b), float(u.min()), float(u.max())


def rolling_friction(D: float, P: float, ball: BallMaterial, surface: Surface, R: float | None = None,
                     g: float = G) -> FrictionEstimate:
    """mu of a ball of diameter ``D`` (m) of ``ball`` on ``surface`` carrying ``P`` N (module
    docstring), with its bounds and basis."""
    spec = surface.friction.get(ball.key)
    if spec is None:
        raise InputError(f"{ball.name} are not an option on {surface.name}")
    if isinstance(spec, tuple):                      # several tables of this pair: the one of the nearest ball
        spec = min(spec, key=lambda k: abs(FRICTION_DATA[k][1] - D))
    if not isinstance(spec, str):
        mu = float(spec)
        return FrictionEstimate(mu, mu * MU_LOW_FACTOR, mu * MU_HIGH_FACTOR, "assumed",
                                f"{surface.name}: mu {mu:g} assumed (no thesis data; {surface.source})", math.nan)
    a, b, lo, hi = friction_fit(spec, g)
    u = P / _short(D, surface.key, R if surface.criterion == "race" else None)
    mu = a + b * u
    what = FRICTION_DATA[spec][0]
    if surface.key not in ("beech", "beech_rubber") or (surface.key == "beech_rubber" and ball.key == "steel"):
        basis, note = "assumed", (f"{what}, read at the same utilisation of {surface.name} (u = {u:.2f}): "
                                  "no thesis data for this pair")
    elif abs(D - FRICTION_DATA[spec][1]) > 0.001:
        basis, note = "assumed", (f"{what}, read for {D * 1000:g} mm balls at the same utilisation (u = {u:.2f}): "
                                  f"the table measured {FRICTION_DATA[spec][1] * 1000:g} mm balls only")
    elif lo - 1e-9 <= u <= hi + 1e-9:
        basis, note = "measured", f"{what}, inside its measured loads (u = {u:.2f} in {lo:.2f}-{hi:.2f})"
    else:
        basis, note = "extrapolated", (f"{what}, extrapolated linearly to u = {u:.2f} (measured {lo:.2f}-{hi:.2f}; "
                                       "the thesis' data end there)")
    mu = max(mu, 0.5 * a if a > 0 else 1e-4)
    return FrictionEstimate(mu, mu * MU_LOW_FACTOR, mu * MU_HIGH_FACTOR, basis, note, u)
