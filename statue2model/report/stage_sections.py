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
    """The isolator stage: an IsolatorDesign ``res`` (its plates were written when it passed)."""
    from ..isolator.design import fails_only_on_ball_load

    figs, text, warnings = [], [], []
    if res.passed:
        figs.append(fig("plates/plates_section.png", "Section through the bottom and top plates, a groove and "
                                                     "its ball (dimensions in mm)"))
        text.append("CNC files: plates/bottom_plate.dxf, plates/top_plate.dxf (outline CUT_OUTSIDE, groove "
                    "openings POCKET, centres DRILL), solids as STL and 3MF.")
    elif fails_only_on_ball_load(res.to_dict()):
        warnings.append(f"The nearest device fails on the ball load alone: {res.failure}. Its mechanics pass every "
                        "check, so the analyses on the isolator run on it; its plates are not written until "
                        "[isolator] ball_capacity holds a load-tested capacity of the grooves that carries the load.")
    else:
        warnings.append(f"No isolator in range works: {res.failure}. No plates were written, and the analyses "
                        "on the isolator are skipped.")
    warnings += [f"advisory check not met: {ck.name} ({ck.why})" for ck in res.checks
                 if not ck.required and not ck.passed]
    rows = [[ck.name, fmt(ck.value), fmt(ck.limit), ck.unit, fmt(ck.ratio, 3),
             "pass" if ck.passed else ("fail" if ck.required else "note"), ck.why] for ck in res.checks]
    summary = {"design": "PASS" if res.passed else (
                   "FAIL on the ball load alone (the grooves must carry more; the mechanics pass)"
                   if fails_only_on_ball_load(res.to_dict()) else "FAIL"),
               "grooves / balls": f"R {res.R:.3f} m, r {res.r:.4f} m, {res.n_grooves} grooves",
               "period T": f"{res.T:.2f} s",
               "plate": f"{res.side:.3f} x {res.side:.3f} x {res.thickness:.3f} m",
               "plate acceleration": f"{res.a_design:.4f} m/s^2 (limit {res.a_lim:.4f} m/s^2)",
               "travel": f"{res.d_design:.4f} m x {res.margin:g} + mu R_hat = {res.travel_need:.4f} m "
                         f"(capacity {res.capacity:.4f} m, {res.capacity_limited_by})"}
    text.append(f"Chosen among {res.candidates.get('passing', 0)} passing of {res.candidates_tried} candidates: "
                f"{res.criterion}.")
    tables = [{"title": "Design checks (each passes when value <= limit; ratio = value / limit)",
               "columns": ["check", "value", "limit", "unit", "ratio", "result", "why"],
               "rows": rows, "status_column": 5}]
    v = getattr(res, "verification", None) or {}
    if v:
        mg, rec = v["margins"], v["records"]
        summary["time-history margins"] = (f"travel {fmt(mg['travel'], 3)}, acceleration {fmt(mg['acceleration'], 3)}, "
                                           f"bearing {fmt(mg['bearing'], 3)} (limit / demand, > 1 passes)")
        met = {True: "; the set's rules met", False: "; the set's rules NOT met", None: ""}[rec.get("rules_met")]
        text.append(f"Verified by time histories ({v['model']}) on {rec['count']} records ({rec['source']}{met}): "
                    f"the {v['statistic']} over the records, every record at mu_low {v['mu_low']:.4g} and mu_high "
                    f"{v['mu_high']:.4g}, each demand at the bound that governs it. Margins: "
                    + "; ".join(f"{k}: {d}" for k, d in v["definitions"].items())
                    + f". The capacity covers the larger of the spectral and the time-history travel need (here "
                      f"the {v['demand']['capacity_sized_on']}).")
        if res.what_would_pass:
            warnings.append(f"What would pass: {res.what_would_pass['text']}.")
        cand = []
        for row in res.candidates.get("rows") or []:
            m = row.get("margins")
            if m and len(cand) < 10:
                cand.append([fmt(row["R"]), fmt(row["r"] * 1000), row["n_grooves"], fmt(row["T"], 3),
                             fmt(row["side"], 3), fmt(row["m_o"], 3), fmt(m["travel"], 3), fmt(m["acceleration"], 3),
                             fmt(m["bearing"], 3), fmt(row["balance"], 3), "pass" if row["passed"] else "fail"])
        tables.append({"title": f"Candidates by the criterion with their time-history margins (first {len(cand)} "
                                f"of {res.candidates.get('verified', 0)} verified, "
                                f"{res.candidates.get('passing', 0)} pass)",
                       "columns": ["R (m)", "r (mm)", "grooves", "T (s)", "side (m)", "top plate (kg)", "travel",
                                   "acceleration", "bearing", "balance", "result"],
                       "rows": cand, "status_column": 10})
    return {"summary": summary, "text": text + list(res.notes), "warnings": warnings, "figures": figs,
            "tables": tables}
