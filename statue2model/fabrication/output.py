"""Write a SliceResult to its output folder, so that an interrupted run never
leaves a folder that looks complete.

    DIR/layers/layer_001.dxf ...  one DXF per layer, in the statue's plan frame
                                  (all layers registered: rods at the same x, y)
    DIR/sheets/sheet_01.dxf ...   one DXF per panel, parts nested, plus (with a
           sheet_01.png/.svg      ``preview`` drawer) a preview of it, written after its DXF
    DIR/bom.csv                   bill of materials and machining time
    DIR/assembly.txt              the order of assembly
    DIR/prototype.stl             the stack as built (boards + glue films), m
    DIR/prototype.json            its properties, with the keys of `props` JSON,
                                  and its errors against the scaled scan
    DIR/slice.json                n_layers, pitch, per-layer areas, holes, tool
                                  checks (parts dropped, slivers opened away,
                                  corners, ... counted per layer), how each
                                  section was built and checked, rods, sheets,
                                  the errors against the scaled scan with their
                                  likely causes, warnings (written last)

DIR is new, empty, or a previous slice's (its DIR/.statue2model.json lists what
statue2model wrote there); a folder with other files is refused, unless
``reuse`` (--reuse): then the slice is written beside them and they are never
touched (a name that collides with one is refused). DIR is locked against a
second writer; a symlinked DIR is followed (the link stays). The folders are
built hidden (.layers.partial-PID) and swapped in, files are written atomically,
the previous slice.json is removed first and the new one written last: an
interrupted write never leaves a slice that looks complete.
"""
from __future__ import annotations

import os
import shutil
from pathlib import Path

from ..version import __version__
from ..quantities import G
from ..io.csvsafe import csv_text
from ..io.files import OutputDir, atomic_write, open_output, output_error, swap_in, write_json
from ..geometry.props import props_dict
from . import robust
from .dxf import Drawing, write_dxf
from .prototype import CHECKED, ERROR_LIMIT
from .slicing import SliceResult


SLICE_NAMES = ("layers", "sheets", "bom.csv", "assembly.txt", "prototype.stl", "prototype.json", "slice.json")


def older_slice(folder: Path) -> list[str]:
    """The names of a slice written before output manifests: its slice.json has the
    statue2model.slice schema, and layers/ and sheets/ hold only what a slice writes
    there (a user's file inside them would be lost by the swap: then nothing is taken)."""
    import json
    import re

    folder = Path(folder)
    try:
        info = json.loads((folder / "slice.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return []
    if not (isinstance(info, dict) and str(info.get("schema", "")).startswith("statue2model.slice/")):
        return []
    allowed = {"layers": re.compile(r"^layer_\d+\.dxf$"), "sheets": re.compile(r"^sheet_\d+\.(dxf|png|svg)$")}
    for sub, pattern in allowed.items():
        if (folder / sub).is_dir() and not all(pattern.match(p.name) and p.is_file() for p in (folder / sub).iterdir()):
            return []
    return [n for n in SLICE_NAMES if (folder / n).exists()]


def open_slice_dir(out: Path, reuse: bool = False) -> OutputDir:
    """Open (create, check, lock) the output folder of a slice before any work; refuses
    a folder with files statue2model did not write unless ``reuse``."""
    od = open_output(out, "slice", reuse=reuse, command="slice", adopt=older_slice)
    try:
        od.claim(SLICE_NAMES)                 # a name that collides with a user's file: refused now
    except BaseException:
        od.close()
        raise
    return od


def _drawing(part, hole: float, placement=None) -> Drawing:
    """What is machined on ``part`` (its cut contour, rod holes of diameter ``hole``,
    engraving), moved by ``placement`` when it is nested on a sheet."""
    outline = part.cut
    holes = part.holes
    strokes = part.label.strokes if part.label is not None else ()
    if placement is not None:
        outline = placement.apply(outline)
        holes = placement.transform(holes) if len(holes) else holes
        strokes = tuple(placement.transform(s) for s in strokes)
    return Drawing(outline=outline, holes=holes, hole=hole, engrave=strokes)


def cut_lengths(part) -> tuple[float, float, float]:
    """(outside contour, inside contours, engraving) path lengths of a part, m."""
    outside = float(part.cut.exterior.length)
    inside = float(sum(r.length for r in part.cut.interiors))
    engrave = part.label.length() if part.label is not None else 0.0
    return outside, inside, engrave


def machining_minutes(spec, outside: float, inside: float, engrave: float, holes: int) -> float:
    """Cutting (all depth passes) and engraving at the feed, plus drilling; rapids not counted."""
    return ((outside + inside) * spec.passes + engrave) / spec.feed / 60.0 + holes * spec.drill_time / 60.0


def bom_rows(res: SliceResult) -> list[dict]:
    spec = res.spec
    W, H = spec.sheet
    rows = []
    tot = dict(out=0.0, ins=0.0, eng=0.0, holes=0, minutes=0.0)
    for s in range(res.nesting.n_sheets):
        out = ins = eng = 0.0
        holes = 0
        parts = [res.parts[p.part] for p in res.nesting.parts_on(s)]
        for part in parts:
            o, i, e = cut_lengths(part)
            out, ins, eng, holes = out + o, ins + i, eng + e, holes + len(part.holes)
        minutes = machining_minutes(spec, out, ins, eng, holes)
        rows.append({
            "item": f"sheet {s + 1:02d}", "material": "OSB board", "quantity": 1,
            "size_mm": f"{W * 1000:.0f} x {H * 1000:.0f} x {spec.board * 1000:g}",
            "parts": " ".join(p.name for p in parts), "cut_outside_m": round(out, 3), "cut_inside_m": round(ins, 3),
            "engrave_m": round(eng, 3), "drill_holes": holes, "machining_min": round(minutes, 1),
            "note": f"material use {res.nesting.utilisation[s] * 100:.1f} %",
        })
        tot["out"] += out
        tot["ins"] += ins
        tot["eng"] += eng
        tot["holes"] += holes
        tot["minutes"] += minutes
    lengths: dict[float, int] = {}
    for r in res.rods.rods:
        key = round(r.length * 1000, 1)
        lengths[key] = lengths.get(key, 0) + 1
    for length_mm, count in sorted(lengths.items()):
        rows.append({"item": "alignment rod", "material": "steel bar" if spec.rod_density > 2000 else "rod",
                     "quantity": count, "size_mm": f"diameter {spec.rod * 1000:g}, length {length_mm:g}",
                     "parts": "", "cut_outside_m": "", "cut_inside_m": "", "engrave_m": "", "drill_holes": "",
                     "machining_min": "", "note": "cut to length"})
    glue_area = sum(robust.intersection(a, b, what=f"the glue film on layer {k + 1}").area
                    for k, (a, b) in enumerate(zip(res.sections[:-1], res.sections[1:])))
    rows.append({"item": "glue", "material": "PVA wood glue", "quantity": round(glue_area, 3),
                 "size_mm": f"m^2 at {spec.glue * 1000:g} mm", "parts": "", "cut_outside_m": "",
                 "cut_inside_m": "", "engrave_m": "", "drill_holes": "", "machining_min": "",
                 "note": f"about {glue_area * spec.glue * spec.glue_density:.2f} kg cured"})
    rows.append({"item": "total", "material": "", "quantity": res.nesting.n_sheets,
                 "size_mm": "sheets", "parts": f"{len(res.parts)} parts", "cut_outside_m": round(tot["out"], 3),
                 "cut_inside_m": round(tot["ins"], 3), "engrave_m": round(tot["eng"], 3),
                 "drill_holes": tot["holes"], "machining_min": round(tot["minutes"], 1),
                 "note": f"{spec.passes} pass(es) per cut at {spec.feed * 60000:g} mm/min, "
                         f"{spec.drill_time:g} s per hole, rapids not counted; "
                         f"material use {res.nesting.material_use * 100:.1f} %"})
    return rows


def _csv_text(rows: list[dict]) -> str:
    """Quoted by the csv module; text that a spreadsheet would run as a formula is neutralised."""
    fields = list(rows[0])
    return csv_text(fields, ([r.get(k, "") for k in fields] for r in rows))


def assembly_text(res: SliceResult) -> str:
    """Numbered assembly steps, bottom up."""
    spec = res.spec
    where = {}
    for p in res.nesting.placements:
        where[p.part] = p.sheet + 1
    starts: dict[int, list] = {}
    for r in res.rods.rods:
        starts.setdefault(r.first, []).append(r)
    lines = [
        f"Assembly of the 1:{spec.scale:g} prototype of {Path(res.source).name}: {res.n_layers} layers of "
        f"{spec.board * 1000:g} mm board, {spec.glue * 1000:g} mm glue, {len(res.rods.rods)} rods of "
        f"{spec.rod * 1000:g} mm.",
        "Every part is engraved with its layer number and an arrow that points to the statue's front; "
        "lay each part engraving up, arrow to the front.",
        "",
    ]
    step = 1
    by_layer: dict[int, list] = {}
    for i, part in enumerate(res.parts):
        by_layer.setdefault(part.layer, []).append((i, part))
    for k in range(res.n_layers):
        items = by_layer.get(k, [])
        names = ", ".join(f"{p.name} (sheet {where[i]})" for i, p in items) or "nothing"
        text = f"{step}. Layer {k + 1}: place {names}"
        if k > 0:
            text += " on glue"
        lines.append(text + ".")
        step += 1
        for r in sorted(starts.get(k, []), key=lambda r: (r.x, r.y)):
            lines.append(f"   insert a {r.length * 1000:.1f} mm rod at x = {r.x * 1000:.1f} mm, y = {r.y * 1000:.1f} mm "
                         f"(through layers {r.first + 1}-{r.last + 1})")
    lines += ["", "Clamp or weigh down the stack while the glue cures; sand the steps of the edges if wanted."]
    return "\n".join(lines) + "\n"


def comparison_rows(res: SliceResult) -> list[dict]:
    """The prototype as built against the scaled scan, one dict per quantity:
    quantity, built, scan, error (text), status ('pass'/'fail' for the quantities
    held to ERROR_LIMIT, '' otherwise) and cause (the likely cause when it fails)."""
    g = G
    c, pp, sp = res.comparison, res.proto_params, res.scan_params
    failing = set(c.failing())

    def row(key, label, built, scan):
        status = ("fail" if key in failing else "pass") if key in CHECKED else ""
        return {"quantity": label, "built": built, "scan": scan, "error": f"{getattr(c, key) * 100:+.2f} %",
                "status": status, "cause": res.causes.get(key, "") if status == "fail" else ""}

    return [
        row("volume", "volume, dm^3", f"{res.proto_mass.volume * 1e3:.3f}", f"{res.scan_mass.volume * 1e3:.3f}"),
        row("h", "h, m", f"{pp.h:.4f}", f"{sp.h:.4f}"),
        row("b_L", "b_L, m", f"{pp.b_L:.4f}", f"{sp.b_L:.4f}"),
        row("b_R", "b_R, m", f"{pp.b_R:.4f}", f"{sp.b_R:.4f}"),
        row("I_G_per_mass", "I_G / m, m^2", f"{pp.I_G / pp.m:.5f}", f"{sp.I_G / sp.m:.5f}"),
        row("a_R", f"a_R along {res.direction_deg:.1f} deg, g", f"{pp.a_R / g:.4f}", f"{sp.a_R / g:.4f}"),
        row("a_min", "a_min (weakest direction), g", f"{res.a_min[0] / g:.4f}", f"{res.a_min[1] / g:.4f}"),
        {"quantity": "centre of mass offset", "built": "", "scan": "", "error": f"{c.com_offset * 100:.2f} % of h",
         "status": "", "cause": ""},
    ]


def slice_dict(res: SliceResult) -> dict:
    spec = res.spec
    layers = []
    for k, sec in enumerate(res.sections):
        layers.append({
            "layer": k + 1, "z_bottom": float(res.bottoms[k]), "z_top": float(res.bottoms[k] + spec.board),
            "area": float(sec.area), "parts": [p.name for p in res.parts if p.layer == k],
            "holes": res.rods.holes[k].tolist(), "tool": res.tool[k].to_dict(),
            "section": _section_dict(res.section_checks[k]) if res.section_checks else None,
        })
    return {
        "schema": "statue2model.slice/1",
        "version": __version__,
        "source": res.source,
        "spec": spec.to_dict(),
        "n_layers": res.n_layers,
        "pitch": spec.pitch,
        "height": res.height,
        "direction_deg": res.direction_deg,
        "front_deg": res.front_deg,
        "volume_layers": float(sum(s.area for s in res.sections) * spec.board),
        "layers": layers,
        "rods": {**res.rods.to_dict(), "warnings": list(res.rods.warnings)},
        "sheets": {
            "n_sheets": res.nesting.n_sheets,
            "material_use": res.nesting.material_use,
            "utilisation": list(res.nesting.utilisation),
            "placements": [{"part": res.parts[p.part].name, "sheet": p.sheet + 1, "angle_deg": p.angle_deg,
                            "dx": p.dx, "dy": p.dy} for p in res.nesting.placements],
        },
        "prototype": {"mass": res.proto_mass.mass, "comparison": res.comparison.to_dict(),
                      "failing": res.comparison.failing(), "error_limit": ERROR_LIMIT,
                      "likely_causes": dict(res.causes),
                      "a_min": {"prototype": res.a_min[0], "scaled_scan": res.a_min[1]}},
        "timings": res.timings,
        "warnings": list(res.warnings),
    }


def _section_dict(checks) -> dict:
    """How a layer's section was built: one plane ('mid') or the planes through the board."""
    keys = ("segments", "winding_area", "method", "overlap", "inverted", "merged", "note")
    if len(checks) == 1:
        return {k: getattr(checks[0], k) for k in keys}
    return {"planes": [c.to_dict() for c in checks]}


class _ProtoBody:
    """The few Body attributes props_dict reads, for the prototype."""

    def __init__(self, res: SliceResult):
        self.source = f"{res.source} (1:{res.spec.scale:g} prototype, {res.n_layers} layers)"
        self.kind = "prototype"
        self.units = "m"
        self.up = "+z"
        self.scale = 1.0 / res.spec.scale
        self.height = float(res.bottoms[-1] + res.spec.board)
        self.mass = res.proto_mass
        self.footprint = res.proto_footprint
        self.log = (f"stack of {res.n_layers} boards as cut, glue films and rods",)
        self.warnings = ()
        self.base = None          # no contact-tolerance study for the stack: its base is a flat board


def prototype_dict(res: SliceResult) -> dict:
    from ..geometry.rocking_params import vulnerability_rose

    body = _ProtoBody(res)
    out = props_dict(body, res.proto_params, vulnerability_rose(res.proto_mass, res.proto_footprint.hull))
    out["scaled_scan"] = {
        "volume": res.scan_mass.volume, "mass_same_density": res.scan_mass.mass, "com": res.scan_mass.com.tolist(),
        **{k: getattr(res.scan_params, k) for k in ("h", "b_L", "b_R", "I_G", "a_L", "a_R")},
        "a_min": res.a_min[1],
    }
    out["errors_vs_scaled_scan"] = res.comparison.to_dict()
    out["materials"] = {"board_density": res.spec.osb_density, "glue_density": res.spec.glue_density,
                        "rod_density": res.spec.rod_density}
    return out


def write_slice(res: SliceResult, out: Path | OutputDir, preview=None, reuse: bool = False) -> Path:
    """Write every output of the module docstring into ``out`` (a folder, or one
    opened with :func:`open_slice_dir`; see the module docstring). ``preview``: None (no
    previews) or ``preview(res, sheet, drawings, stem)``, called after each sheet's DXF to draw
    STEM.png and STEM.svg of sheet ``sheet`` (0-based), e.g.
    :func:`statue2model.report.fabrication_plots.plot_sheet`."""
    from ..compute.interrupts import checked_import

    trimesh = checked_import("trimesh")   # trimesh drops a Ctrl-C during its import

    od = out if isinstance(out, OutputDir) else open_slice_dir(Path(out), reuse)
    try:
        d = od.path
        od.clean()
        od.claim(SLICE_NAMES)
        od.remove("slice.json")                     # the completeness marker goes first, comes back last
        spec = res.spec
        width = max(3, len(str(res.n_layers)))
        by_layer: dict[int, list] = {}
        for part in res.parts:
            by_layer.setdefault(part.layer, []).append(part)
        tmp = _fresh(d / f".layers.partial-{os.getpid()}")
        for k in range(res.n_layers):
            drawings = [_drawing(p, spec.hole) for p in by_layer.get(k, [])]
            write_dxf(tmp / f"layer_{k + 1:0{width}d}.dxf", drawings, title=f"layer {k + 1}")
        swap_in(tmp, d / "layers")
        tmp = _fresh(d / f".sheets.partial-{os.getpid()}")
        for s in range(res.nesting.n_sheets):
            placed = res.nesting.parts_on(s)
            drawings = [_drawing(res.parts[p.part], spec.hole, p) for p in placed]
            path = write_dxf(tmp / f"sheet_{s + 1:02d}.dxf", drawings, title=f"sheet {s + 1}")
            if preview is not None:
                preview(res, s, drawings, path.with_suffix(""))
        swap_in(tmp, d / "sheets")
        atomic_write(d / "bom.csv", lambda p: p.write_text(_csv_text(bom_rows(res))))
        atomic_write(d / "assembly.txt", lambda p: p.write_text(assembly_text(res)))
        v, f = res.mesh
        mesh = trimesh.Trimesh(v, f, process=False)
        atomic_write(d / "prototype.stl", lambda p: mesh.export(p, file_type="stl"))
        write_json(d / "prototype.json", prototype_dict(res))
        write_json(d / "slice.json", slice_dict(res))
    except BaseException:
        od.clean()                                   # this write's partial folders; slice.json stays absent
        raise
    finally:
        if od is not out:
            od.close()
    return Path(out.path if isinstance(out, OutputDir) else out)


def _fresh(tmp: Path) -> Path:
    shutil.rmtree(tmp, ignore_errors=True)
    try:
        tmp.mkdir()
    except OSError as exc:
        raise output_error(exc, tmp) from None
    return tmp
