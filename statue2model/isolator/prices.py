"""What a device costs: a small price table (indicative, EUR excl. VAT, Europe, late 2026; every
entry overridable in the project file's ``[isolator.prices]``) and the bill of materials of a design.

The BOM (isolator/bom.csv: item, material, quantity, unit, unit_cost, cost) lists, for the two
plates: the boards or sheets (m^3, whole boards stacked and glued where one is too thin for the
grooves), the glue of each stacked joint (m^2), the balls (each), the groove liners (rubber, m^2;
hardened steel race shells, each, priced by their area), the fuse balls, the fixings and the machine time (h: a
set-up per plate, the pockets' volume at the material's removal rate, the outline at the feed).

>>> p = prices()
>>> round(ball_price(0.040, "steel", p), 2)                  # a 40 mm bearing-steel ball
2.93
>>> prices({"beech_m3": 2500.0})["beech_m3"]
2500.0
>>> prices({"gold_m3": 1.0})
Traceback (most recent call last):
...
statue2model.errors.InputError: [isolator.prices] has no item 'gold_m3' (items: beech_m3, robinia_m3, hdpe_m3, pom_m3, glue_m2, rubber_m2, race_each, race_m2, steel_ball_kg, steel_ball_each, resin_ball_kg, resin_ball_each, fixing_each, machine_h, setup_h)
"""
from __future__ import annotations

import math

from ..errors import InputError

PRICES = {
    "beech_m3": 2200.0,        # glued solid-beech panels, 20-50 mm (about 66 EUR/m^2 at 30 mm)
    "robinia_m3": 3000.0,      # glued robinia panels
    "hdpe_m3": 5700.0,         # PE-HD 500 sheet, about 6 EUR/kg
    "pom_m3": 17000.0,         # POM-C sheet, about 12 EUR/kg
    "glue_m2": 5.0,            # PVAc / PU glue of one stacked joint
    "rubber_m2": 60.0,         # 3.2 mm natural rubber sheet (the thesis' Linatex)
    "race_each": 80.0,         # a hardened steel race shell: pressing or spinning set-up and heat treatment
    "race_m2": 2500.0,         # ... plus its area
    "steel_ball_kg": 10.0,     # bearing-steel balls, G100, by mass
    "steel_ball_each": 0.3,
    "resin_ball_kg": 15.0,     # phenolic resin balls
    "resin_ball_each": 0.5,
    "fixing_each": 0.3,        # screws and plugs: the bottom plate to the floor or pedestal, the statue's clamps
    "machine_h": 70.0,         # CNC router with an operator
    "setup_h": 0.5,            # h of set-up per plate
}
"""Indicative prices (EUR excl. VAT; module docstring); the project file overrides any of them."""
REMOVAL_RATE = {"wood": 1.2e-3, "sheet": 1.0e-3}
"""m^3/h of pocket a CNC router clears in wood and in a polymer sheet (finishing passes included)."""
FEED = 120.0
"""m/h along the plate's outline (2 m/min, several passes)."""
FIXINGS = 16
"""Screws and plugs per device."""
BOM_COLUMNS = ("item", "material", "quantity", "unit", "unit_cost", "cost")


def prices(overrides: dict | None = None) -> dict:
    """PRICES with ``overrides`` ({item: EUR}) applied; an unknown item or a price that is not a finite
    number >= 0 is refused in one line."""
    out = dict(PRICES)
    for k, v in (overrides or {}).items():
        if k not in PRICES:
            raise InputError(f"[isolator.prices] has no item {k!r} (items: {', '.join(PRICES)})")
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
            unit = "h" if k.endswith("_h") and k != "machine_h" else "EUR"
            raise InputError(f"[isolator.prices] {k} must be a number >= 0 ({unit}), got {v!r}")
        out[k] = float(v)
    return out


def ball_price(D: float, material: str, p: dict) -> float:
    """EUR per ball of diameter ``D`` (m) of ``material`` ("steel" or "resin")."""
    from .bearing import BALLS_MATERIALS

    mass = BALLS_MATERIALS[material].density * math.pi * D ** 3 / 6
    return p[f"{material}_ball_each"] + p[f"{material}_ball_kg"] * mass


def bill(dev, p: dict) -> list[dict]:
    """The rows of the bill of materials of a device ``dev`` (design.Device), prices ``p``."""
    return [{"item": item(), "material": material, "quantity": qty, "unit": unit, "unit_cost": unit_cost,
             "cost": qty * unit_cost} for item, material, qty, unit, unit_cost in _lines(dev, p)]


def bill_total(dev, p: dict) -> float:
    """EUR: ``total(bill(dev, p))``, the same sum in the same order, without writing the items' texts (a
    search prices thousands of devices and lists a few)."""
    return float(sum(qty * unit_cost for _, _, qty, _, unit_cost in _lines(dev, p)))


def _lines(dev, p: dict) -> list[tuple]:
    """(item text maker, material, quantity, unit, unit cost) of each row of :func:`bill`."""
    from .bearing import SURFACES

    s = SURFACES[dev.surface]
    rows = []
    area = dev.side ** 2
    board_material = "beech" if s.kind == "lined" else s.key
    per_m3 = p[f"{board_material}_m3"]
    label = "sheet" if s.kind == "sheet" else "board"
    for t, k in dev.layers:
        rows.append((lambda t=t: f"{label} {dev.side * 1000:.0f} x {dev.side * 1000:.0f} x {t * 1000:g} mm",
                     board_material, 2 * k, "each", per_m3 * area * t))
    joints = sum(k for _, k in dev.layers) - 1
    if joints > 0:
        rows.append((lambda: "glue, one stacked joint of a plate", "glue", 2 * joints * area, "m^2", p["glue_m2"]))
    rows.append((lambda: f"ball, {dev.D * 1000:g} mm", dev.ball, dev.n, "each", ball_price(dev.D, dev.ball, p)))
    groove_area = dev.liner_area                             # a spherical cap's area
    if s.kind == "lined" and s.criterion == "race":
        rows.append((lambda: f"hardened steel race, a {s.layer * 1000:g} mm shell of radius {dev.R * 1000:.0f} mm "
                             f"opening {2 * dev.opening_radius * 1000:.0f} mm", "100Cr6", 2 * dev.n, "each",
                     p["race_each"] + p["race_m2"] * groove_area))
    elif s.kind == "lined":
        rows.append((lambda: f"rubber layer {s.layer * 1000:g} mm, glued in each groove", "rubber",
                     2 * dev.n * groove_area, "m^2", p["rubber_m2"]))
    if dev.fuse_ball > 0:
        rows.append((lambda: f"fuse ball, {2 * dev.fuse_ball * 1000:.1f} mm", "steel", dev.n_fuse, "each",
                     ball_price(2 * dev.fuse_ball, "steel", p)))
    rows.append((lambda: "fixings (screws and plugs)", "steel", FIXINGS, "each", p["fixing_each"]))
    rate = REMOVAL_RATE["sheet" if s.kind == "sheet" else "wood"]
    d, Rc = dev.cut_depth, dev.R + dev.layer
    pockets = 2 * dev.n * (math.pi * d * d * (3 * Rc - d) / 3)
    hours = 2 * p["setup_h"] + pockets / rate + 2 * 4 * dev.side / FEED
    rows.append((lambda: "CNC machine time (set-up, pockets, outlines)", "", hours, "h", p["machine_h"]))
    return rows


def total(rows) -> float:
    """EUR: the sum of a bill's costs."""
    return float(sum(r["cost"] for r in rows))


def write_bom(path, rows) -> None:
    """isolator/bom.csv: BOM_COLUMNS, one row per item, then the total (costs rounded to cents)."""
    from ..io.csvsafe import write_csv

    out = [[r["item"], r["material"], round(r["quantity"], 4), r["unit"], round(r["unit_cost"], 2),
            round(r["cost"], 2)] for r in rows]
    out.append(["total", "", "", "", "", round(total(rows), 2)])
    write_csv(path, list(BOM_COLUMNS), out)
