"""Command-line stage of the prototype: ``statue2model slice``.

    statue2model slice [MESH] --scale 1:2 [--board 9mm] [--glue 0.5mm] [--tool 3mm]
                       [--rod 8mm] [--sheet 2500x1250mm] [--out DIR] [...]

Lengths take a unit (mm, cm, m, in); a bare number is millimetres.
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

from ..errors import InputError
from .argtypes import finite_float, length, positive_float, scale_ratio, sheet_size


def add_parsers(sub) -> None:
    p = sub.add_parser(
        "slice",
        help="scan -> stacked-board prototype: layer and sheet DXF, BOM, assembly, as-built properties",
        description="Scale a scan, slice it into glued boards with alignment-rod holes, engraved labels "
        "and tool checks, nest the parts on panels and write CNC-ready DXF (R2010, mm), a bill of "
        "materials, previews, the assembly order and the prototype as built (STL and properties).",
    )
    p.add_argument("mesh", nargs="?", help="scan (as for `props`); default: the bundled meshes/dancing_girl.ply")
    p.add_argument("--units", default="auto", choices=["auto", "m", "mm", "cm", "in"], help="length unit of the file")
    p.add_argument("--up", default="auto", choices=["auto", "x", "y", "z", "-x", "-y", "-z"], help="file axis pointing up")
    p.add_argument("--height", type=positive_float, metavar="H", help="rescale the scan to this real height in m first")
    p.add_argument("--scale", default="1:2", metavar="1:N",
                   help="prototype scale: 1:N, 1/N or the ratio prototype/statue (0.5); default 1:2")
    g = p.add_argument_group("boards and tools (lengths: 9mm, 0.9cm, ...; bare numbers are mm)")
    g.add_argument("--board", type=length, default=0.009, metavar="T", help="board thickness (default 9mm)")
    g.add_argument("--glue", type=length, default=0.0005, metavar="T", help="glue film thickness (default 0.5mm)")
    g.add_argument("--policy", choices=["mid", "envelope", "core"], default="mid",
                   help="board outline: section at mid-board (default), union (envelope) or intersection (core) "
                        "of the sections through the board")
    g.add_argument("--tool", type=length, default=0.003, metavar="D", help="cutter diameter (default 3mm)")
    g.add_argument("--compensate", action="store_true",
                   help="write the cutter-centre path (outline offset by D/2) instead of the true outline")
    g.add_argument("--tolerance", type=length, default=0.00005, metavar="T",
                   help="chordal tolerance of the outlines (default 0.05mm)")
    g.add_argument("--rod", type=length, default=0.008, metavar="D", help="alignment rod diameter (default 8mm)")
    g.add_argument("--clearance", type=length, default=0.0002, metavar="C", help="hole = rod + C (default 0.2mm)")
    g.add_argument("--wall", type=length, default=0.005, metavar="W",
                   help="least wood around a rod hole (default 5mm)")
    n = p.add_argument_group("sheets and machining")
    n.add_argument("--sheet", type=sheet_size, default=(2.5, 1.25), metavar="WxH", help="panel size (default 2500x1250mm)")
    n.add_argument("--margin", type=length, default=0.002, metavar="M",
                   help="gap between parts beyond the cutter diameter (default 2mm)")
    n.add_argument("--edge", type=length, default=0.01, metavar="E", help="unused band along sheet edges (default 10mm)")
    n.add_argument("--feed", type=positive_float, default=2000.0, metavar="MM_PER_MIN",
                   help="cutting feed for the time estimate (default 2000 mm/min)")
    n.add_argument("--pass-depth", type=length, metavar="T", help="depth per pass (default: the cutter diameter)")
    m = p.add_argument_group("prototype")
    m.add_argument("--board-density", type=positive_float, default=620.0, metavar="RHO",
                   help="board density, kg/m^3 (default 620, OSB)")
    m.add_argument("--glue-density", type=finite_float, default=1100.0, metavar="RHO", help="kg/m^3 (default 1100)")
    m.add_argument("--rod-density", type=finite_float, default=7850.0, metavar="RHO",
                   help="kg/m^3 (default 7850, steel; 0 if the rods are pulled out)")
    m.add_argument("--direction", type=finite_float, metavar="DEG",
                   help="excitation direction for the rocking parameters (default: the scan's weakest)")
    m.add_argument("--front", type=finite_float, metavar="DEG",
                   help="plan direction the engraved arrows point to (default: the scan's front)")
    p.add_argument("--no-previews", action="store_true", help="skip the PNG/SVG sheet previews")
    p.add_argument("--out", metavar="DIR", help="output folder (default: outputs/<scan name>/slice): new, empty or "
                   "a previous slice's; a symlink is followed")
    p.add_argument("--reuse", action="store_true", help="write into an --out that holds files statue2model did not "
                   "write (they are never touched; a name that collides with one is refused), or go on with an "
                   "older slice made before output manifests")
    p.set_defaults(func=_cmd_slice)


def _cmd_slice(args) -> int:
    from ..fabrication.output import open_slice_dir, write_slice
    from ..fabrication.slicing import slice_body
    from ..fabrication.spec import SliceSpec
    from ..geometry.body import load_body
    from ..io.paths import default_scan
    from ..report.fabrication_plots import plot_sheet

    try:
        scale = scale_ratio(args.scale)         # a bare 2 is refused with one line (1:2 or 2:1?)
    except argparse.ArgumentTypeError as exc:
        raise InputError(f"--scale {args.scale}: {exc}") from None
    mesh = Path(args.mesh) if args.mesh else default_scan()
    out = Path(args.out) if args.out else Path("outputs") / mesh.stem / "slice"
    spec = SliceSpec(
        scale=scale, board=args.board, glue=args.glue, tool=args.tool, rod=args.rod,
        clearance=args.clearance, wall=args.wall, sheet=args.sheet, margin=args.margin, edge=args.edge,
        policy=args.policy, compensate=args.compensate, tolerance=args.tolerance,
        feed=args.feed / 60000.0, pass_depth=args.pass_depth, osb_density=args.board_density,
        glue_density=args.glue_density, rod_density=args.rod_density,
    )
    with open_slice_dir(out, reuse=args.reuse) as od:     # checked and locked before any work
        t0 = time.perf_counter()
        body = load_body(mesh, units=args.units, up=args.up, height=args.height)
        t_load = time.perf_counter() - t0
        res = slice_body(body, spec, direction_deg=args.direction, front_deg=args.front)
        t1 = time.perf_counter()
        write_slice(res, od, preview=None if args.no_previews else plot_sheet)
        t_write = time.perf_counter() - t1
    print(summary(res, out))
    print(f"\ntime: load {t_load:.2f} s, " + ", ".join(f"{k} {v:.2f} s" for k, v in res.timings.items())
          + f", files {t_write:.2f} s")
    return 0


def summary(res, out: Path) -> str:
    from ..fabrication.output import comparison_rows
    from ..fabrication.prototype import ERROR_LIMIT

    spec = res.spec
    lines = [
        f"{Path(res.source).name} at 1:{spec.scale:g}: {res.n_layers} layers, pitch {spec.pitch * 1000:g} mm "
        f"({spec.board * 1000:g} mm board + {spec.glue * 1000:g} mm glue), height {res.height * 1000:.1f} mm",
        f"parts {len(res.parts)}, rods {len(res.rods.rods)} in {len(res.rods.segments)} segments, "
        f"sheets {res.nesting.n_sheets} of {spec.sheet[0] * 1000:.0f} x {spec.sheet[1] * 1000:.0f} mm, "
        f"material use {res.nesting.material_use * 100:.1f} %, prototype mass {res.proto_mass.mass:.2f} kg",
        "",
        f"{'prototype as built':<30}{'built':>10}{'scaled scan':>13}{'error':>11}  check (+-{ERROR_LIMIT * 100:g} %)",
    ]
    for r in comparison_rows(res):
        check = {"pass": "ok", "fail": "FAIL", "": ""}[r["status"]]
        lines.append(f"{r['quantity']:<30}{r['built']:>10}{r['scan']:>13}{r['error']:>11}  {check}".rstrip())
    if res.warnings:
        lines += ["", f"{len(res.warnings)} warning(s) (all in slice.json):"]
        lines += [f"  {w}" for w in res.warnings[:12]]
        if len(res.warnings) > 12:
            lines.append(f"  ... and {len(res.warnings) - 12} more")
    lines += ["", f"wrote {out}/: layers/ ({res.n_layers} DXF), sheets/ ({res.nesting.n_sheets} DXF + previews), "
              "bom.csv, assembly.txt, prototype.stl, prototype.json, slice.json"]
    return "\n".join(lines)
