"""Command-line stage of the 3D cross-check: ``statue2model crosscheck``.

    statue2model crosscheck MESH_OR_PARAMS --motion SPEC [--isolator DESIGN.json] --out DIR
                            [--direction DEG] [--dt S] [--statue-dt S] [--iterations N] [--grid MM] [--groove G] [--segments N]
                            [--pulse-freq HZ] [--quick] [--imperfect] [--records N] [--only-motion]

MESH_OR_PARAMS is a scan (its convex hull and mass properties are used) or a
PARAMS.json of rocking parameters (then a prism with those m, h, b_L, b_R, I_G).
A motion file of three columns (time, a_x, a_y in the scan's frame) is resolved along the
excitation direction and across it: the 2D model runs on the first, the 3D scene once on it alone
(like with like) and once on both. --only-motion runs the user's motion alone (no calibration,
free rocking, pulses or boundaries): a shake-table test or a floor record in seconds.
Writes DIR/crosscheck.json (a list ``cases``) and overlay plots (PNG): statue2model.crosscheck.compare
runs the cases, statue2model.report.crosscheck_plots writes the folder.
"""
from __future__ import annotations


from ..errors import InputError
from .argtypes import finite_float, plausible, positive_float, scan_or_params



def add_parsers(sub) -> None:
    p = sub.add_parser("crosscheck", help="3D PyBullet cross-check of the 2D rocking and isolator models",
                       description="Run the statue (and the isolator) in PyBullet and in the 2D models on the "
                       "same motions; write DIR/crosscheck.json (cases with 2D and 3D values, errors, targets) "
                       "and overlaid time histories.")
    p.add_argument("source", metavar="MESH_OR_PARAMS", help="a scan, or the PARAMS.json of `statue2model props`")
    p.add_argument("--motion", required=True, metavar="SPEC", help="ground motion as for `rock` (the recorded-"
                   "motion case and the isolated statue); free:theta0=RAD runs the standard cases only; a file "
                   "of time, a_x, a_y (scan frame) runs in 3D with both components as well")
    p.add_argument("--only-motion", action="store_true", help="the user's motion alone: the statue (and the "
                   "isolated statue, --groove exact) under --motion in 3D and 2D, without the standard cases")
    p.add_argument("--isolator", metavar="DESIGN.json", help="the JSON of `statue2model isolator design`")
    p.add_argument("--out", required=True, metavar="DIR")
    p.add_argument("--direction", type=finite_float, metavar="DEG", help="excitation direction (default: weakest)")
    p.add_argument("--dt", type=positive_float, default=5e-4, metavar="S", help="3D time step of the ball "
                   "isolator scenes (--groove lattice|tiles), the imperfect-base cases and the record ensemble (default "
                   "0.5 ms; the exact isolator scene runs at --statue-dt)")
    p.add_argument("--statue-dt", type=positive_float, default=2e-3, metavar="S", help="3D time step of the "
                   "statue's standard cases (default 2 ms: peak rotation within 1.2 %% of 0.125 ms, "
                   "benchmarks/bench_crosscheck_speed.py)")
    p.add_argument("--iterations", type=int, default=50, metavar="N", help="solver iterations (default 50)")
    p.add_argument("--grid", type=float, default=4.0, metavar="MM", help="grooves as a triangular lattice of MM "
                   "on the sphere (default 4; 0: the CNC mesh with --segments per ring)")
    p.add_argument("--groove", choices=("exact", "lattice", "tiles"), default="exact",
                   help="isolator model: exact (default: the top plate as a translating spherical pendulum, "
                   "rolling resistance mu N, ~40 x real time with the statue), or ball contacts - the detailed "
                   "mode - in grooves as the lattice of --grid or as flat tangent tiles of r (1-5 x real time: "
                   "docs/crosscheck.md, Speed)")
    p.add_argument("--segments", type=int, default=128, metavar="N",
                   help="groove tessellation of the CNC mesh, with --grid 0 (default 128)")
    p.add_argument("--pulse-freq", type=plausible("pulse_frequency", option="--pulse-freq"), default=1.5, metavar="HZ",
                   help="frequency of the one-sine pulses (default 1.5)")
    p.add_argument("--quick", action="store_true", help="shorter runs")
    p.add_argument("--imperfect", action="store_true", help="also the imperfect model in 3D: a convex base, "
                   "alpha and theta identified from 3D pulse tests, classical vs imperfect 2D (crosscheck/imperfect.py)")
    p.add_argument("--records", type=int, default=0, metavar="N", help="also the ensemble of N synthetic records "
                   "(>= 2; 20 or more for the target) at 3 PGA levels: overturning probability and median peak, "
                   "2D vs 3D with intervals (crosscheck/ensemble.py; 2 processes)")
    p.set_defaults(func=_cmd_crosscheck)


def load_scene(source: str, direction: float | None = None):
    """A StatueScene from a scan or a PARAMS.json."""
    from ..crosscheck.statue_scene import StatueScene

    path, params = scan_or_params(source)
    if params is not None:
        return StatueScene.from_params(params)
    from ..geometry.body import load_body

    return StatueScene.from_body(load_body(path), direction)


def _cmd_crosscheck(args) -> int:
    from ..crosscheck.isolator_scene import IsolatorScene
    from ..crosscheck.world import SimSettings, check_user_dt
    from ..hazard.motions import along, parse_spec_components
    from ..io.files import open_output
    from .isolator import read_design

    if not 16 <= args.segments <= 1024:
        raise InputError(f"--segments must be in 16..1024, got {args.segments}")
    if not (args.grid == 0 or 0.5 <= args.grid <= 50):
        raise InputError(f"--grid must be 0 or in 0.5..50 mm, got {args.grid}")
    settings = SimSettings(dt=args.dt, solver_iterations=args.iterations)
    statue_settings = SimSettings(dt=args.statue_dt, solver_iterations=args.iterations)
    for name, dt in (("--dt", args.dt), ("--statue-dt", args.statue_dt)):
        check_user_dt(name, dt)
    comps, _ = parse_spec_components(args.motion)
    if args.only_motion and comps[0].kind == "none":
        raise InputError("--only-motion needs a ground motion (a record or a pulse), not free:theta0")
    if args.only_motion and args.isolator and args.groove != "exact":
        raise InputError("--only-motion runs the isolator with --groove exact (the ball scenes calibrate "
                         "their friction on a free vibration first)")
    if args.only_motion and (args.imperfect or args.records):
        raise InputError("--only-motion runs the user's motion alone: drop --imperfect and --records")
    scene = load_scene(args.source, args.direction)
    motion, motion_y = comps[0], None
    if len(comps) == 2:
        motion, motion_y = along(*comps, scene.params.direction_deg)
    iso = None
    if args.isolator:
        d = read_design(args.isolator)            # a design `isolator design` rejected is refused
        if args.groove == "exact":
            from ..crosscheck.pendulum_scene import PendulumIsolator

            iso = PendulumIsolator.from_design(d, statue=scene)
        else:
            iso = IsolatorScene.from_design(d, statue=scene, segments=args.segments,
                                            grid=args.grid / 1000 if args.grid > 0 else None,
                                            groove="tiles" if args.groove == "tiles" else None)
    if args.records and not 2 <= args.records <= 1000:
        raise InputError(f"--records must be 0 or in 2..1000, got {args.records}")
    # only once the inputs are read (a bad input leaves no folder), before any work: a folder with
    # the user's files (or another command's) is refused, and the outputs appear together
    with open_output(args.out, "crosscheck", command="crosscheck", can_reuse=False) as od:
        return _crosscheck(args, od, scene, motion, iso, settings, statue_settings, motion_y)


def _crosscheck(args, od, scene, motion, iso, settings, statue_settings, motion_y=None) -> int:
    from ..crosscheck.compare import compare
    from ..crosscheck.contact import ContactSettings
    from ..crosscheck.output import summary, table
    from ..crosscheck.output import write_report
    from ..report.crosscheck_plots import plot_histories

    contact = ContactSettings()
    from ..rocking.model import RockingModel

    # a squat body: plastic impacts (eq. 15 < 0) and sliding on the 3D floor (friction contact.friction^2)
    notes = RockingModel.housner(scene.params, mu_static=contact.friction**2).notes
    for note in notes:
        print(f"note (3D floor friction {contact.friction**2:g}): {note}")
    # its plots of an earlier cross-check in this folder go when this one has other cases
    group = od.group(["crosscheck.json", *(n for n in od.entries if n.endswith(".png"))])
    comp = compare(scene, motion, iso_scene=iso, settings=settings, statue_settings=statue_settings,
                   contact=contact,
                   pulse_freq=args.pulse_freq, quick=args.quick, imperfect=args.imperfect,
                   records=args.records, progress=lambda m: print(f"  running: {m}", flush=True),
                   only_motion=args.only_motion, motion_y=motion_y)
    extra = {"scene": {"name": scene.name, "params": scene.params.to_dict(), "hull_vertices": len(scene.hull)},
             "settings": settings.to_dict(), "statue_settings": statue_settings.to_dict(), "contact": contact.to_dict(), "motion": motion.to_dict(),
             "motion_across": None if motion_y is None else motion_y.to_dict(), "only_motion": bool(args.only_motion),
             "notes": notes}
    with group as g:
        paths = plot_histories(comp.histories, g.tmp) | write_report(comp, g.tmp, extra)
    print(table(comp.cases))
    s = summary(comp.cases)
    print(f"\n{s['n_met']} of {s['n_cases']} applicable checks meet their target ({s['n_not_applicable']} not "
          f"applicable, {s['n_diagnostic']} diagnostics not counted); wrote {od.path / paths['json'].name} and "
          f"{len(paths) - 1} plots")
    return 0
