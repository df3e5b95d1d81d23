"""What the report shows of the params, prototype and isolator stages: their summary, text,
warnings, tables and figures (the parts of a stage's manifest that are typeset; the stage adds
its ``data``), from the plain results the stage computed.

Example
-------
>>> fmt(0.123456), fmt(float("nan")), fmt(None), fmt(12345.678, 5)
('0.1235', '-', '-', '12346')
>>> fig("a.png", "A figure")
{'path': 'a.png', 'caption': 'A figure'}
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..quantities import G  # m/s^2: the g every report prints


def fig(path: str, caption: str) -> dict:
    """A figure entry of a manifest: ``path`` relative to the stage folder."""
    return {"path": path, "caption": caption}


def fmt(x, nd=4):
    """``x`` with ``nd`` significant digits; '-' for None or a non-finite float."""
    return "-" if x is None or (isinstance(x, float) and not np.isfinite(x)) else f"{x:.{nd}g}"


def params_section(body, p, rose) -> dict:
    """The params stage: a Body ``body``, its RockingParams ``p`` and vulnerability Rose ``rose``."""
    mp = body.mass
    rows = [["h (height of G)", fmt(p.h), "", "m"], ["I_G (about G)", fmt(p.I_G, 5), "", "kg m^2"],
            ["b (G to pivot, in plan)", fmt(p.b_L), fmt(p.b_R), "m"],
            ["delta = atan(b/h)", fmt(p.delta_L), fmt(p.delta_R), "rad"],
            ["p (frequency parameter)", fmt(p.p_L), fmt(p.p_R), "rad/s"],
            ["a = g b/h (uplift)", f"{p.a_L:.4f} ({p.a_L / p.g:.3f} g)", f"{p.a_R:.4f} ({p.a_R / p.g:.3f} g)", "m/s^2"],
            ["e (eq. 15)", fmt(p.e_L), fmt(p.e_R), "-"]]
    summary = {"mass": f"{mp.mass:.4g} kg", "height": f"{body.height:.4f} m", "volume": f"{mp.volume:.5g} m^3",
               "direction": f"{p.direction_deg:.2f} deg", "h": f"{p.h:.4f} m", "b_L / b_R": f"{p.b_L:.4f} / {p.b_R:.4f} m",
               "uplift a_R": f"{p.a_R:.4f} m/s^2 ({p.a_R / p.g:.3f} g)",
               "weakest direction": f"{rose.weakest_deg:.2f} deg ({rose.a_min / p.g:.3f} g)"}
    text = [(f"Scan {Path(body.source).name}: units {body.units}, up {body.up}, scale x{body.scale:g}, "
             f"density {mp.density:.1f} kg/m^3.")]
    return {"summary": summary, "text": text, "warnings": list(body.warnings),
            "tables": [{"title": f"Rocking parameters along {p.direction_deg:.2f} deg",
                        "columns": ["quantity", "left (L)", "right (R)", "unit"], "rows": rows}],
            "figures": [fig("props.png", "Footprint (contact polygons, hull, centre of mass, pivots) and the "
                                         "vulnerability rose: uplift acceleration against the excitation direction")]}


def prototype_progress(spec, res=None) -> str:
    """The progress line of the prototype stage before slicing (``res`` None) or before writing."""
    if res is None:
        return f"slicing at 1:{spec.scale:g} into {spec.board * 1000:g} mm boards, rods, labels, nesting ..."
    return f"writing the CNC files of {len(res.parts)} parts on {res.nesting.n_sheets} sheet(s) ..."


def prototype_section(res, previews: bool) -> dict:
    """The prototype stage: a SliceResult ``res``; ``previews``: the sheets' previews were drawn."""
    from ..fabrication.output import comparison_rows
    from ..fabrication.prototype import ERROR_LIMIT, LABELS

    spec = res.spec
    rows = [[r["quantity"], r["built"], r["scan"], r["error"], r["status"], r["cause"]] for r in comparison_rows(res)]
    figs = [fig("layers.png", "Boards in plan (colour: layer) with the rod holes, and the stack in elevation")]
    if previews:
        for k in range(res.nesting.n_sheets):
            figs.append(fig(f"sheets/sheet_{k + 1:02d}.png", f"Sheet {k + 1} of {res.nesting.n_sheets}: nested "
                                                             "parts, rod holes and engraved labels"))
    worst, err = res.comparison.largest()
    summary = {"scale": f"1:{spec.scale:g}", "layers": f"{res.n_layers} x {spec.board * 1000:g} mm "
               f"(+{spec.glue * 1000:g} mm glue)", "parts / sheets": f"{len(res.parts)} / {res.nesting.n_sheets}",
               "prototype mass": f"{res.proto_mass.mass:.2f} kg",
               "largest parameter error": f"{abs(err) * 100:.2f} % ({LABELS[worst]})"}
    text = [(f"{res.n_layers} boards, {len(res.rods.rods)} alignment rods, material use "
             f"{res.nesting.material_use * 100:.1f} %. CNC files: layers/*.dxf (one per layer), sheets/*.dxf "
             "(nested panels, mm, R2010), bom.csv, assembly.txt.")]
    if res.warnings:
        text.append(f"{len(res.warnings)} warning(s), all in slice.json: " + "; ".join(res.warnings[:3])
                    + ("; ..." if len(res.warnings) > 3 else ""))
    return {"summary": summary, "text": text, "figures": figs, "warnings": list(res.warnings),
            "tables": [{"title": "Prototype as built against the scaled scan",
                        "columns": ["quantity", "as built", "scaled scan", "error",
                                    f"check (+-{ERROR_LIMIT * 100:g} %)", "likely cause"],
                        "rows": rows, "status_column": 4}]}


def isolator_section(res) -> dict:
    """The isolator stage: an isolator Design ``res`` (its plates, drawing and bill of materials were written
    when it passed)."""
    from ..isolator.bearing import SURFACES
    from ..isolator.layout import LAYOUTS

    figs, text, warnings = [], [], []
    dev = res.device
    what = (f"{LAYOUTS[dev.layout].name}, {dev.ball} balls of {2 * res.r * 1000:g} mm on "
            f"{SURFACES[dev.surface].name}") if dev else f"{res.n_grooves} balls"
    if res.passed:
        figs.append(fig("plates/drawing.png", "The carpenter's drawing: the bottom plate in plan with every groove "
                                              "centre, the opening circles, the fuse seats and the notes (mm; "
                                              "plates/drawing.svg)"))
        figs.append(fig("plates/plates_section.png", "Section through the bottom and top plates, a groove and "
                                                     "its ball (dimensions in mm)"))
        text.append(f"The device: {what}; plates {res.side * 1000:.0f} x {res.side * 1000:.0f} x "
                    f"{res.thickness * 1000:.0f} mm. It costs about {res.cost:.0f} EUR (isolator/bom.csv; prices "
                    "from isolator/prices.py, [isolator.prices] overrides them). CNC files: plates/bottom_plate.dxf, "
                    "plates/top_plate.dxf (outline CUT_OUTSIDE, groove openings POCKET, centres DRILL), solids as "
                    "STL and 3MF, plates/drawing.svg.")
    else:
        wwp = (res.what_would_pass or {}).get("text")
        warnings.append((wwp or "No isolator in range passes every check.") + " No plates were written, and the "
                        "analyses on the isolator are skipped.")
    warnings += [f"advisory check not met: {ck.name} ({ck.why})" for ck in res.checks
                 if not ck.required and not ck.passed]
    tail = ((getattr(res, "verification", None) or {}).get("reserve") or {}).get("tail") or {}
    if res.passed and tail and not tail.get("dominates"):
        n = len(tail.get("fixed_sorted") or [])
        warnings.append(f"The device keeps its failure median at or beyond where half the design records overturn the "
                        f"statue without it, but not its lower tail: from {tail['worse_from'] / G:.3f} g "
                        f"{tail['device_fails']} of {n} records pass the device's travel capacity while "
                        f"{tail['fixed_fails']} overturn the statue on a fixed base (a larger plate or more friction "
                        "would close it).")
    fr = res.friction or {}
    if fr.get("basis") in ("assumed", "extrapolated"):
        warnings.append(f"The rolling friction is {fr['basis']}: {fr.get('note', '')}")
    rows = [[ck.level, ck.name, fmt(ck.value), fmt(ck.limit), ck.unit, fmt(ck.ratio, 3),
             "pass" if ck.passed else ("fail" if ck.required else "note"), ck.why] for ck in res.checks]
    summary = {"design": "PASS" if res.passed else "FAIL",
               "device": what,
               "grooves": f"R {res.R:.3f} m, opening radius {res.opening_radius * 1000:.1f} mm, depth "
                          f"{res.depth * 1000:.1f} mm",
               "period T": f"{res.T:.2f} s",
               "plate": f"{res.side:.3f} x {res.side:.3f} x {res.thickness:.3f} m",
               "rolling friction": f"mu {res.mu:.4g} ({fr.get('basis', 'given')})",
               "travel capacity": f"{res.capacity:.4f} m ({res.capacity_limited_by})",
               "load per ball": f"{res.ball_capacity.get('load_per_ball', 0):.0f} N of "
                                f"{res.ball_capacity.get('per_ball', 0):.0f} N"}
    if res.passed:
        summary["cost"] = f"{res.cost:.0f} EUR"
    text.append(f"Chosen among {res.candidates.get('passing', 0)} passing of {res.candidates_tried} candidates: "
                f"{res.criterion}.")
    tables = [{"title": "Design checks (each passes when value <= limit; ratio = value / limit): the statue at the "
                        "design level, the device at the collapse level (SLC) and with a reserve",
               "columns": ["level", "check", "value", "limit", "unit", "ratio", "result", "why"],
               "rows": rows, "status_column": 6}]
    v = getattr(res, "verification", None) or {}
    if v:
        mg, rec = v["margins"], v["records"]
        summary["margins"] = ", ".join(f"{k} {fmt(x, 3)}" for k, x in mg.items() if x is not None)
        text.append(f"Verified by time histories ({v['model']}) on {len(v.get('sets') or [])} record sets of "
                    f"{rec['count']} records: the {v['statistic']} over each set, every record at mu_low "
                    f"{v['mu_low']:.4g} and mu_high {v['mu_high']:.4g}. Collapse level: {v['slc']['rule']}. "
                    + (f"Reserve: {v['reserve']['rule']} (here {v['reserve']['pga'] / G:.3f} g, "
                       f"{v['reserve']['pga_over_design']:.2f} x the design PGA)." if v.get("reserve") else "")
                    + " Margins: " + "; ".join(f"{k}: {d}" for k, d in v["definitions"].items()) + ".")
        tables.append({"title": "The record sets the device holds on",
                       "columns": ["set", "seeds", "records", "mean travel (m)", "mean felt (m/s^2)",
                                   "travel need (m)", "rules met"],
                       "rows": [[s["name"], s["seeds"], s["records"], fmt(s["travel"], 4), fmt(s["felt"], 4),
                                 fmt(s["need"], 4), {True: "yes", False: "NO", None: "-"}[s.get("rules_met")]]
                                for s in v.get("sets") or []]})
    if res.bom:
        tables.append({"title": f"Bill of materials (EUR; total {res.cost:.2f})",
                       "columns": ["item", "material", "quantity", "unit", "unit cost", "cost"],
                       "rows": [[r["item"], r["material"], fmt(r["quantity"], 4), r["unit"], fmt(r["unit_cost"], 2),
                                 fmt(r["cost"], 2)] for r in res.bom]})
    return {"summary": summary, "text": text + list(res.notes), "warnings": warnings, "figures": figs,
            "tables": tables}
