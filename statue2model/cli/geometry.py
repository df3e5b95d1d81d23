"""Command-line stage of the scan: ``statue2model props``.

    statue2model props [MESH] [--units m|mm|cm|in|auto] [--up x|y|z|-x|-y|-z|auto]
                       [--height H] [--density RHO | --mass M] [--direction DEG]
                       [--base-tol M] [--json OUT]

Loads, repairs and orients a scan, prints its mass properties and rocking
parameters and writes them as JSON (SI units) with the rose table (OUT_rose.csv)
and the footprint-and-rose plot (OUT.png) beside it.
"""
from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from .argtypes import finite_float, positive_float


def add_parsers(sub) -> None:
    p = sub.add_parser(
        "props",
        help="scan -> mass properties and rocking parameters",
        description="Load, repair and orient a scan; print its mass properties and rocking "
        "parameters; write them as JSON with a plot (footprint and vulnerability rose) beside it.",
    )
    p.add_argument("mesh", nargs="?", help="mesh (STL, OBJ, PLY, OFF, GLB) or point cloud (PLY, PCD, XYZ); "
                   "default: the bundled meshes/dancing_girl.ply")
    p.add_argument("--units", default="auto", choices=["auto", "m", "mm", "cm", "in"],
                   help="length unit of the file (default: detected from the size)")
    p.add_argument("--up", default="auto", choices=["auto", "x", "y", "z", "-x", "-y", "-z"],
                   help="file axis pointing up, e.g. --up -y (default: detected from the flat base)")
    p.add_argument("--height", type=positive_float, metavar="H",
                   help="rescale the scan to this real height in metres (for normalised scans)")
    group = p.add_mutually_exclusive_group()
    group.add_argument("--density", type=positive_float, metavar="RHO",
                       help="density in kg/m^3 (default: marble, 2650)")
    group.add_argument("--mass", type=positive_float, metavar="M", help="measured mass in kg (sets the density)")
    p.add_argument("--direction", type=finite_float, metavar="DEG",
                   help="excitation direction in plan, degrees from +x toward +y (default: the weakest)")
    p.add_argument("--base-tol", type=float, metavar="M",
                   help="contact tolerance in metres: vertices this close to the base touch it "
                   "(default: 0.1%% of the height)")
    p.add_argument("--json", metavar="OUT", help="JSON output (default: outputs/<scan name>/props.json); "
                   "the plot (OUT.png) and the rose table (OUT_rose.csv) are written beside it")
    p.set_defaults(func=_cmd_props)


def _cmd_props(args) -> int:
    from ..geometry.body import load_body
    from ..geometry.props import write_props
    from ..io.files import OutputGroup
    from ..io.paths import default_scan
    from ..report.plots import plot_footprint_and_rose
    from ..report.tables import props_table

    mesh = Path(args.mesh) if args.mesh else default_scan()
    out = Path(args.json) if args.json else Path("outputs") / mesh.stem / "props.json"
    if out.exists() and out.is_dir():
        raise InputError(f"--json {out} is a folder; give a file name")
    written = (out, out.with_name(out.stem + "_rose.csv"), out.with_suffix(".png"))
    # a name statue2model did not write is refused before any work (nothing is written or listed);
    # the folder is made only when the files are written: a bad scan leaves no empty folder, and the
    # three files appear (and are listed in the folder's manifest) together or not at all
    group = OutputGroup.files(written, "props")
    body = load_body(
        mesh, units=args.units, up=args.up, height=args.height, density=args.density,
        mass=args.mass, base_tol=args.base_tol,
    )
    params = body.rocking(args.direction)
    rose = body.rose()
    print(props_table(body, params, rose))
    with group as g:
        _, csv = write_props(g / out, body, params, rose)
        png = plot_footprint_and_rose(body, params, rose, (g / out).with_suffix(".png"))
    print(f"\nwrote {out}, {csv.name} and {png.name}")
    return 0
