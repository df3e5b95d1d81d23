"""Command-line stage of the isolator: ``statue2model isolator design|plates|simulate|identify``.

    statue2model isolator design PARAMS.json (--spectrum SPEC | --motion SPEC) [--mu MU] [...] --json OUT
    statue2model isolator plates DESIGN.json --out DIR
    statue2model isolator simulate (--R M --r M --mass KG --mu MU | --design DESIGN.json)
                                   [--model coulomb|boucwen --q Q] [--capacity M] [--end-stop stop|impact]
                                   [--statue PARAMS.json] --motion SPEC --json OUT
    statue2model isolator identify RECORD.csv [--units m|mm] [--T S] [--mass KG --table 25] --json OUT
"""
from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from .argtypes import finite_float, length, plausible, positive_float


_SURFACES = ("beech", "robinia", "beech_rubber", "hdpe", "pom", "steel_race")
_LAYOUTS = ("ring3", "ring4", "ring5", "ring6", "ring8", "grid3x3", "grid3x4", "grid4x4")


def add_parsers(sub) -> None:
    p = sub.add_parser("isolator", help="rolling-ball isolator: design, groove plates, simulation",
                       description="Design a rolling-ball isolator for a statue, write its groove plates, "
                       "or simulate it under a ground motion (thesis ch. 2.4.1, 5, 6.4).")
    isub = p.add_subparsers(dest="isolator_command", metavar="ACTION")
    isub.required = True

    d = isub.add_parser("design", help="choose the cheapest rolling-ball isolator a workshop can build for a statue",
                        description="Search balls (radius, steel or resin), layouts (3 to 16 balls on rings or "
                        "grids), groove radii, groove surfaces (beech, robinia, beech with a rubber layer, HDPE, POM, "
                        "steel races) and boards (stacked where a groove needs it) for the cheapest device that passes "
                        "every check on the spectrum: the felt acceleration below the statue's uplift limit, the "
                        "travel at the design level (1.5 SDe + mu R_hat) and at the collapse level (SLC), the top "
                        "plate's tipping, the ball load (long-term, and at SLC), the grooves within the boards. "
                        "Write the design (JSON, with its checks and the candidates), a readable report (OUT.txt) and "
                        "the bill of materials (OUT_bom.csv); exit 2 when nothing in range works. `statue2model run` "
                        "also verifies the device by time histories on several record sets and with a reserve.")
    d.add_argument("params", metavar="PARAMS.json", help="the statue's rocking parameters (`statue2model props`)")
    src = d.add_mutually_exclusive_group(required=True)
    src.add_argument("--spectrum", metavar="SPEC",
                     help="elastic response spectrum: ec8:ag=0.25g,ground=C,type=1[,xi=5] | "
                          "ntc2018:ag=0.2g,F0=2.4,Tc=0.3,soil=B[,topo=T1][,xi=5][,ls=SLV]")
    src.add_argument("--motion", metavar="SPEC", help="a ground motion simulated on every candidate (as for `rock`)")
    d.add_argument("--slc-spectrum", metavar="SPEC",
                   help="the site's spectrum at the collapse level (SLC) for the device's checks; default: the design "
                        "spectrum x 1.2 on EC8 (EN 1998-1 10.3(2)), scaled by the return periods on NTC")
    d.add_argument("--mu", type=plausible("rolling_friction", finite_float, "--mu"),
                   help="rolling friction coefficient for every candidate (default: each ball/surface pair's law, "
                        "Tables 19, 25)")
    d.add_argument("--surface", choices=_SURFACES, help="groove surface (default: the cheapest that passes)")
    d.add_argument("--layout", choices=_LAYOUTS, help="ball layout (default: the cheapest that passes)")
    d.add_argument("--grooves", type=int, metavar="N", help="number of balls: 3, 4, 5, 6, 8, 9, 12 or 16")
    d.add_argument("--ball-material", choices=("steel", "resin"))
    d.add_argument("--target", type=plausible("plate_acceleration", _accel, "--target"), metavar="A",
                   help="stricter limit for the plate acceleration, with a unit: 0.03g or 0.29m/s2")
    d.add_argument("--alpha", type=plausible("alpha", finite_float, "--alpha"), metavar="A", help="alpha_L = alpha_R = A: reduced uplift limits")
    d.add_argument("--alpha-L", type=plausible("alpha", finite_float, "--alpha-L"), metavar="A")
    d.add_argument("--alpha-R", type=plausible("alpha", finite_float, "--alpha-R"), metavar="A")
    d.add_argument("--thickness", type=plausible("plate_thickness", length, "--thickness"), metavar="T",
                   help="wooden board thickness (30mm, 0.03m; a bare number is mm; default: 20, 30, 40 or 50 mm; "
                        "boards are stacked where a groove needs more)")
    d.add_argument("--side-max", type=plausible("plate_side", length, "--side-max"), metavar="S", help="largest plate side (default 1.5 m, the CNC bed)")
    d.add_argument("--fuse-release", type=plausible("fuse_release", _accel, "--fuse-release"), metavar="A",
                   help="add a release mechanism (fuse) that lets go at A, with a unit: 0.075g or 0.736m/s2")
    d.add_argument("--ball-capacity", type=plausible("ball_capacity", positive_float, "--ball-capacity"), metavar="N",
                   help="a load test of the groove surface: N carried on a 40 mm ball with the allowed dent "
                        "(default: the surface's model, isolator/bearing.py)")
    d.add_argument("--json", metavar="OUT", required=True, help="design JSON; OUT.txt gets the report, OUT_bom.csv "
                                                               "the bill of materials")
    d.set_defaults(func=_cmd_design)

    pl = isub.add_parser("plates", help="the two groove plates as STL, 3MF, DXF and a section drawing")
    pl.add_argument("design", metavar="DESIGN.json", help="the JSON written by `isolator design`")
    pl.add_argument("--segments", type=int, default=256, help="tessellation of each groove (default 256)")
    pl.add_argument("--out", metavar="DIR", required=True)
    pl.set_defaults(func=_cmd_plates)

    s = isub.add_parser("simulate", help="top plate (and statue) under a ground motion",
                        description="The top plate (and the statue on it) under a ground motion. The plate's "
                        "displacement is watched against the isolator's capacity (--capacity, or the design's): "
                        "by default the run stops where it is passed, outcome 'isolator capacity exceeded'; "
                        "--end-stop impact lets the plate rebound on a rigid end stop (restitution --e-stop) "
                        "and go on.")
    s.add_argument("--design", metavar="DESIGN.json",
                   help="take R, r, mass, mu and the capacity from a design (`isolator design`); the options "
                        "below override it")
    s.add_argument("--R", type=plausible("groove_radius", option="--R"), metavar="M", help="groove radius of curvature, m")
    s.add_argument("--r", type=plausible("ball_radius", option="--r"), metavar="M", help="ball radius, m")
    s.add_argument("--mass", type=plausible("supported_mass", option="--mass"), metavar="KG",
                   help="supported mass M = top plate + statue, kg")
    s.add_argument("--mu", type=plausible("rolling_friction", finite_float, "--mu"), metavar="MU")
    s.add_argument("--capacity", type=plausible("capacity", length, "--capacity"), metavar="M",
                   help="largest plate displacement before a ball leaves its groove (150mm, 0.15m; a bare "
                        "number is mm; default: the design's with --design, else not checked)")
    s.add_argument("--end-stop", choices=["stop", "impact"], default="stop",
                   help="at the capacity: stop the run (default) or rebound on a rigid end stop")
    s.add_argument("--e-stop", type=plausible("restitution", finite_float, "--e-stop"), default=0.5, metavar="E",
                   help="restitution of the end stop with --end-stop impact (default 0.5, assumed)")
    s.add_argument("--model", choices=["coulomb", "boucwen"], default="coulomb")
    s.add_argument("--q", type=positive_float, default=30.0, help="Bouc-Wen k_i / k (30 without rubber, 5 with)")
    s.add_argument("--n", type=int, choices=[1, 2], default=1, help="Bouc-Wen exponent")
    s.add_argument("--statue", metavar="PARAMS.json", help="the statue on the plate: plate + statue coupled (uplift, rocking, efficiency)")
    s.add_argument("--alpha", type=plausible("alpha", finite_float, "--alpha"), metavar="A", help="the statue's alpha_L = alpha_R (imperfect model)")
    s.add_argument("--motion", required=True, metavar="SPEC", help="as for `rock`, plus free:u0=M[,v0=M/S]")
    s.add_argument("--t-end", type=positive_float, metavar="S")
    s.add_argument("--dt-out", type=positive_float, default=0.005, metavar="S")
    s.add_argument("--rtol", type=positive_float, default=1e-9)
    s.add_argument("--json", metavar="OUT", required=True)
    s.set_defaults(func=_cmd_simulate)

    i = isub.add_parser("identify", help="rolling friction mu from a free-vibration record (eq. 51)",
                        description="Identify the rolling friction mu from a free vibration of the top plate: "
                        "a CSV of time (s) and displacement in its first two columns (a `simulate` history "
                        "or a measured record). Prints mu per cycle, their mean, the envelope fit and the "
                        "measured period; with --mass and --table, compares with the measured tables.")
    i.add_argument("record", metavar="RECORD.csv")
    i.add_argument("--units", choices=["m", "mm"], default="m", help="displacement unit of the record")
    i.add_argument("--T", type=positive_float, metavar="S", help="period for eq. 51 (default: measured)")
    i.add_argument("--mass", type=plausible("supported_mass", option="--mass"), metavar="KG", help="supported mass, for the table value")
    i.add_argument("--table", choices=["19-steel", "19-resin", "19-resin-rubber", "25"],
                   help="measured friction table (Table 19: three grooves; Table 25: four grooves)")
    i.add_argument("--json", metavar="OUT", required=True)
    i.set_defaults(func=_cmd_identify)


def read_design(path, option: str = "--isolator", analyse: bool = True) -> dict:
    """The isolator design at ``path`` (the JSON of ``statue2model isolator design``, or one
    written by hand with R, r, M, mu, ...), refused with one line when ``isolator design``
    rejected it: its ``passed`` is not true, or one of its required ``checks`` failed (the ball load
    among them: a device its grooves cannot carry is neither analysed nor cut). A design without
    ``passed`` (written by hand) is taken as it is."""
    from ..io.files import read_json

    d = read_json(path)
    if not isinstance(d, dict):
        raise InputError(f"{option} {path}: not an isolator design (the JSON of `statue2model isolator design`)")
    checks = d.get("checks") if isinstance(d.get("checks"), list) else []
    failed = [str(c.get("name")) for c in checks
              if isinstance(c, dict) and c.get("required") and c.get("passed") is not True]
    if ("passed" in d and d["passed"] is not True) or failed:
        why = d.get("failure") or ("failed checks: " + ", ".join(failed) if failed else "passed: false")
        raise InputError(f"{option} {path}: `statue2model isolator design` rejected this design ({why}); give a "
                         "design that passes every check")
    return d


def _statue(path):
    from ..io.files import read_json
    from ..geometry.rocking_params import RockingParams

    data = read_json(path)
    try:
        return RockingParams.from_dict(data)
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"{path} does not hold rocking parameters ({exc})") from None


def _accel(text: str) -> float:
    """An acceleration with a unit (0.075g, 0.736m/s2)."""
    import argparse

    from ..quantities import parse_accel

    try:
        value = parse_accel(text)
    except InputError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be a positive acceleration, got {text}")
    return value


def _cmd_design(args) -> int:
    from ..hazard.code_spectra import parse_spectrum
    from ..hazard.levels import collapse_spectrum_text
    from ..hazard.motions import parse_spec
    from ..io.files import OutputGroup, atomic_write, write_json
    from ..isolator.design import design
    from ..isolator.prices import write_bom

    statue = _statue(args.params)
    aL = args.alpha_L if args.alpha_L is not None else (args.alpha if args.alpha is not None else 1.0)
    aR = args.alpha_R if args.alpha_R is not None else (args.alpha if args.alpha is not None else 1.0)
    spectrum = parse_spectrum(args.spectrum) if args.spectrum else None
    slc, why = None, None
    if spectrum is not None:
        text, why = collapse_spectrum_text(args.spectrum, args.slc_spectrum)
        slc = parse_spectrum(text)
    elif args.slc_spectrum:
        raise InputError("--slc-spectrum goes with --spectrum, not --motion")
    motion = parse_spec(args.motion)[0] if args.motion else None
    out = Path(args.json)
    bom = out.with_name(out.stem + "_bom.csv")
    group = OutputGroup.files([out, out.with_suffix(".txt"), bom], "isolator design")   # checked before any work
    if args.ball_capacity is not None and args.surface is None:
        raise InputError("--ball-capacity is a load test of one groove surface: name it with --surface")
    res = design(statue, mu=args.mu, spectrum=spectrum, slc=slc, slc_why=why, motion=motion, target=args.target,
                 alpha=(aL, aR), n_grooves=args.grooves, thickness=args.thickness, fuse_release=args.fuse_release,
                 ball_capacity=args.ball_capacity, surfaces=args.surface, layouts=args.layout,
                 materials=args.ball_material, **({"side_max": args.side_max} if args.side_max else {}))
    report = res.report()
    with group as g:
        write_json(g / out, res.to_dict())
        atomic_write(g / out.with_suffix(".txt"), lambda p: p.write_text(report + "\n"))
        write_bom(g / bom, res.bom)
    print(report)
    print(f"\nwrote {out}, {out.with_suffix('.txt').name} and {bom.name}")
    if not res.passed:
        why = ((res.what_would_pass or {}).get("text") or res.failure or "").rstrip(".")
        raise InputError(f"no design meets every check: {why}; see {out.with_suffix('.txt')}")
    return 0


PLATE_FILES = tuple(f"{w}_plate.{ext}" for w in ("bottom", "top") for ext in ("stl", "3mf", "dxf")) + \
    ("plates_section.png", "plates_section.svg", "drawing.svg", "drawing.png")
"""The files `isolator plates` writes into --out (the 3MF ones only when trimesh can write 3MF)."""


def _cmd_plates(args) -> int:
    from ..io.files import open_output
    from ..isolator.plates import PlateGeometry, write_plates
    from ..report.isolator_plots import plot_plates_figures

    dd = read_design(args.design, "DESIGN.json", analyse=False)
    geom = PlateGeometry.from_design(dd, str(args.design))
    if args.segments < 16 or args.segments > 4096:
        raise InputError(f"--segments must be in 16..4096, got {args.segments}")
    with open_output(args.out, "plates", command="isolator plates", can_reuse=False) as od, \
            od.group(PLATE_FILES) as g:
        paths = write_plates(geom, g.tmp, segments=args.segments) | plot_plates_figures(geom, g.tmp, design=dd)
    print("wrote " + ", ".join(str(od.path / p.name) for p in paths.values()))
    return 0


def _cmd_simulate(args) -> int:
    from ..rocking.model import RockingModel
    from ..hazard.motions import parse_spec
    from ..io.files import OutputGroup, write_json
    from ..isolator.statue_on_plate import statue_on_plate
    from ..isolator.time_history import simulate

    spec = args.motion.strip()
    u0 = v0 = 0.0
    if spec.startswith("free:") and "u0" in spec:
        from ..hazard import motions

        opts = dict(kv.split("=", 1) for kv in spec[5:].split(",") if kv)
        try:
            u0 = float(opts.pop("u0"))
            v0 = float(opts.pop("v0", 0.0))
        except ValueError as exc:
            raise InputError(f"bad free-vibration start in --motion {spec!r}: {exc}") from None
        if opts:
            raise InputError(f"unknown key(s) {', '.join(opts)} in --motion {spec!r} (free:u0=M[,v0=M/S])")
        motion = motions.free()
    else:
        motion = parse_spec(spec)[0]
    from ..compute.budget import check_history
    from ..isolator.time_history import FREE_TIME, HISTORY_BYTES_PER_SAMPLE

    # the run and its CSV (about 80 characters a sample), before anything is allocated
    check_history(args.t_end if args.t_end is not None else motion.end + FREE_TIME, args.dt_out,
                  HISTORY_BYTES_PER_SAMPLE + 200, t_name="--t-end", dt_name="--dt-out")
    iso = _isolator(args)
    json_out = Path(args.json)
    group = OutputGroup.files([json_out, json_out.with_suffix(".csv")], "isolator simulate")
    res = simulate(iso, motion, u0=u0, v0=v0, t_end=args.t_end, dt_out=args.dt_out, rtol=args.rtol,
                   end_stop=args.end_stop, e_stop=args.e_stop)
    out = res.to_dict()
    if args.statue:
        params = _statue(args.statue)
        model = RockingModel.housner(params) if args.alpha is None else RockingModel.imperfect(
            params, alpha_L=args.alpha, alpha_R=args.alpha)
        sp = statue_on_plate(res, model, rtol=args.rtol)
        out["statue"] = sp.to_dict()
        out["uplift"] = sp.uplift
        out["efficiency"] = sp.efficiency
    with group as g:
        write_json(g / json_out, out)
        csv = _write_history(g / json_out.with_suffix(".csv"), res)
    print(f"T = {iso.T:.3f} s, k = {iso.k:.2f} N/m; u_max = {res.u_max * 1000:.2f} mm, "
          f"|a_abs| max = {res.acc_abs_max:.4f} m/s^2 (pga {res.pga:.4f}), {len(res.peaks_u)} peaks")
    print("plate: " + _capacity_line(res))
    if args.statue:
        line = f"statue (coupled plate + statue): uplift {'YES' if sp.uplift else 'no'}, efficiency {sp.efficiency:.3f}"
        if sp.uplift:
            line += f"; {sp.rocking.outcome}, theta_max/delta {sp.rocking.theta_max_over_delta:.3f}"
            if sp.one_way is not None:
                line += f" (one-way estimate {sp.one_way.theta_max_over_delta:.3f})"
        print(line)
        print("plate + statue: " + _capacity_line(sp.rocking))
    print(f"wrote {args.json} and {csv.name} (history)")
    return 0


def _isolator(args):
    """The Isolator of `isolator simulate`: --design, overridden by the explicit options."""
    from dataclasses import replace

    from ..isolator.device import Isolator, isolator_from_design

    given = {k: getattr(args, a) for k, a in (("R", "R"), ("r", "r"), ("M", "mass"), ("mu", "mu"))
             if getattr(args, a) is not None}
    opts = dict(model=args.model, q=args.q, n=args.n)
    if args.capacity is not None:
        opts["capacity"] = args.capacity
    if args.design:
        return replace(isolator_from_design(read_design(args.design, "--design")), **given, **opts)
    missing = [f"--{a}" for k, a in (("R", "R"), ("r", "r"), ("M", "mass"), ("mu", "mu")) if k not in given]
    if missing:
        raise InputError(f"isolator simulate needs {', '.join(missing)} (or --design DESIGN.json)")
    return Isolator(**given, **opts)


def _capacity_line(res) -> str:
    """The outcome of a run with respect to the isolator's capacity, one line."""
    import math

    cap = res.isolator.capacity
    if not math.isfinite(cap):
        return f"outcome {res.outcome}; capacity not checked (give --capacity or --design)"
    if not res.capacity_exceeded:
        return f"outcome {res.outcome}; |u| max {res.u_max * 1000:.1f} mm within the capacity {cap * 1000:.1f} mm"
    line = (f"outcome {res.outcome}: |u| reached the capacity {cap * 1000:.1f} mm at t = {res.t_capacity:.4f} s "
            f"(u = {res.u_at_capacity * 1000:.1f} mm)")
    if res.end_stop == "impact":
        line += f"; {res.capacity_hits} end-stop impact(s) (e = {res.end_stop_restitution:g})"
    else:
        line += "; the run stops there"
    return line


def _write_history(path: Path, res) -> Path:
    """t, u, v, a_abs, z every dt_out, SI units: readable by `isolator identify`; a run stopped at the
    capacity ends with its last finite sample and a '# stopped: ...' line (IsolatorResult.history_csv)."""
    from ..io.files import atomic_write

    text = res.history_csv()
    return atomic_write(path, lambda p: p.write_text(text, encoding="utf-8", newline=""))


_TABLES = {"19-steel": "steel_r0.0095", "19-resin": "resin_r0.0183", "19-resin-rubber": "resin_r0.0183_rubber"}


def _cmd_identify(args) -> int:
    from ..rocking.identify import read_time_series
    from ..io.files import OutputGroup, write_json
    from ..isolator.friction import TABLE_19, TABLE_25, friction_from_record, mu_for_load

    if (args.mass is None) != (args.table is None):
        raise InputError("--mass and --table go together (the table value at that load)")
    group = OutputGroup.files([Path(args.json)], "isolator identify")
    t, u = read_time_series(args.record, "displacement")
    if args.units == "mm":
        u = u / 1000.0
    fr = friction_from_record(t, u, T=args.T)
    out = fr.to_dict()
    print(f"{len(fr.peaks_u)} peaks, period {fr.period:.4f} s")
    print("mu per cycle: " + ", ".join(f"{m:.5f}" for m in fr.mu_per_cycle))
    print(f"mu mean {fr.mu_mean:.5f}, envelope fit {fr.mu_fitted:.5f}")
    if args.table:
        if args.table == "25":
            tab = TABLE_25["mu"]
            masses = TABLE_25["M"]
        else:
            tab = TABLE_19[_TABLES[args.table]]
            masses = TABLE_19["M"]
        mu_t = mu_for_load(args.mass, masses, tab)
        out["table"] = {"name": f"Table {args.table}", "mass": args.mass, "mu": mu_t}
        print(f"Table {args.table} at {args.mass:g} kg: mu {mu_t:.5f} (identified / table = {fr.mu_fitted / mu_t:.3f})")
    with group as g:
        write_json(g / Path(args.json), out)
    print(f"wrote {args.json}")
    return 0
