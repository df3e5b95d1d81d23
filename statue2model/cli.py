"""Command line: argument parsing only; each subcommand calls one stage.

    statue2model props [MESH] [--units m|mm|cm|in|auto] [--up x|y|z|-x|-y|-z|auto]
                       [--height H] [--density RHO | --mass M] [--direction DEG]
                       [--base-tol M] [--json OUT]
    statue2model rock PARAMS.json --motion SPEC [model options] [--t-end S] [--json OUT]
    statue2model spectrum | variability | sweep | identify | motion ...   (see --help of each)
    statue2model slice [MESH] --scale 1:2 [--board 9mm] ... --out DIR
    statue2model isolator design|plates|simulate|identify ...
    statue2model crosscheck MESH_OR_PARAMS --motion SPEC [--isolator DESIGN.json] --out DIR
    statue2model run [MESH|FOLDER] [--config project.toml] [--out DIR] [--stages LIST] [--force]
                     [--workers N | --scheduler ADDRESS]      every stage, cached, with an HTML report
    statue2model config [--out project.toml]                  the project file with every default

Errors in the input are printed as one line (``statue2model: error: ...``) with
exit status 2 (also a refused output folder: one holding the user's files, or in use
by another statue2model command). An output that cannot be written (disk full,
quota, permission, read-only file system, name too long) is one line naming the
file, exit status 3, and leaves no file that looks complete. Ctrl-C: status 130.
Set STATUE2MODEL_DEBUG=1 to see tracebacks of internal errors (status 1).
"""
from __future__ import annotations

import argparse
import errno
import os
import sys
from pathlib import Path

from . import __version__
from .argtypes import finite_float, join_dash_values, positive_float
from .errors import InputError, OutputError
from .files import _REASONS as _OUTPUT_REASONS
from .files import output_error

OUTPUT_ERRNOS = frozenset(_OUTPUT_REASONS)   # ENOSPC, EDQUOT, EACCES, EROFS, ENAMETOOLONG, ...


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="statue2model",
        description="From a 3D scan of a statue to its rocking model, prototype and isolator.",
    )
    parser.add_argument("--version", action="version", version=f"statue2model {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

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

    from . import cli_crosscheck, cli_dynamics, cli_fabrication, cli_isolator, cli_run

    cli_dynamics.add_parsers(sub)
    cli_fabrication.add_parsers(sub)
    cli_isolator.add_parsers(sub)
    cli_crosscheck.add_parsers(sub)
    cli_run.add_parsers(sub)
    return parser


def _cmd_props(args) -> int:
    from .files import claim_files
    from .geometry.body import load_body
    from .paths import default_scan
    from .props import write_props
    from .report.tables import props_table

    mesh = Path(args.mesh) if args.mesh else default_scan()
    out = Path(args.json) if args.json else Path("outputs") / mesh.stem / "props.json"
    if out.exists() and out.is_dir():
        raise InputError(f"--json {out} is a folder; give a file name")
    written = (out, out.with_name(out.stem + "_rose.csv"), out.with_suffix(".png"))
    # refuse a name statue2model did not write before any work; a folder that is not there yet
    # (nothing in it can clash) is made only once the scan loaded: a bad scan leaves no empty folder
    early = out.parent.is_dir()
    if early:
        claim_files(written, "props")
    body = load_body(
        mesh, units=args.units, up=args.up, height=args.height, density=args.density,
        mass=args.mass, base_tol=args.base_tol,
    )
    if not early:
        claim_files(written, "props")
    params = body.rocking(args.direction)
    rose = body.rose()
    print(props_table(body, params, rose))
    _, csv, png = write_props(out, body, params, rose)
    print(f"\nwrote {out}, {csv.name} and {png.name}")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(join_dash_values(sys.argv[1:] if argv is None else list(argv)))
    try:
        return args.func(args)
    except OutputError as exc:
        print(f"statue2model: error: {exc}", file=sys.stderr)
        return 3
    except InputError as exc:
        print(f"statue2model: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("statue2model: interrupted", file=sys.stderr)
        return 130
    except OSError as exc:
        if exc.errno not in OUTPUT_ERRNOS or os.environ.get("STATUE2MODEL_DEBUG"):
            return _internal(exc)
        print(f"statue2model: error: {_os_error_line(exc)}", file=sys.stderr)
        return 3
    except MemoryError:  # a request no budget check caught
        print("statue2model: error: the request does not fit in this machine's memory: use smaller grids, "
              "a coarser --dt-out or a shorter --t-end", file=sys.stderr)
        return 2
    except Exception as exc:  # a bug: still one line unless debugging
        return _internal(exc)


def _os_error_line(exc: OSError) -> str:
    """One line for an OSError no output helper translated (e.g. a library writing directly)."""
    if exc.errno in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG):
        return str(output_error(exc, exc.filename if exc.filename is not None else "an output file"))
    return f"{_OUTPUT_REASONS[exc.errno]}" + (f": {exc.filename}" if exc.filename is not None else "")


def _internal(exc: BaseException) -> int:
    if os.environ.get("STATUE2MODEL_DEBUG"):
        raise exc
    print(f"statue2model: internal error: {type(exc).__name__}: {exc} "
          "(set STATUE2MODEL_DEBUG=1 for the traceback)", file=sys.stderr)
    return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
