"""Command-line stage of the fragility study: ``statue2model fragility``.

    statue2model fragility PARAMS_OR_MESH --records synthetic:N[,duration=S,dt=S,seed=K] | DIR
                           --levels LO:HI:N [--im pga|pgv] [--samples N] [--vary NAME=LO:HI ...]
                           [--sampling lhs|grid] [--isolator DESIGN.json] [--workers N | --scheduler ADDR]
                           [model options] --out DIR

PARAMS_OR_MESH is the PARAMS.json of ``statue2model props`` or a scan (its rocking
parameters in the weakest direction, or --direction). Records: N synthetic records
(seeds K..K+N-1) or the set of a folder: the files its set.json names, each checked
against the length and hash recorded there (hazard/matching.read_record_set; a folder
without set.json, or with a file missing or changed, is refused). Levels: N values from
LO to HI (PGA with a unit, 0.05g or 0.49m/s2; PGV in m/s). --isolator: a design that
`isolator design` passed. Writes DIR/fragility.json, fragility.csv and fragility.png
(assessment/fragility.py) together, into a folder that is new, empty or statue2model's
(files.open_output: a folder with a user's files is refused before any work).
"""
from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from .argtypes import finite_float, plausible, positive_float, scan_or_params



def add_parsers(sub) -> None:
    p = sub.add_parser("fragility", help="fragility curves (probability of overturning vs intensity), fixed base "
                       "and on the isolator",
                       description="Run records x intensity levels x parameter samples, fit lognormal fragility "
                       "curves by maximum likelihood with bootstrap bands, and write DIR/fragility.json, .csv, .png.")
    p.add_argument("source", metavar="PARAMS_OR_MESH", help="the PARAMS.json of `statue2model props`, or a scan")
    p.add_argument("--records", required=True, metavar="SPEC", help="synthetic:N[,duration=S][,dt=S][,seed=K] "
                   "(N synthetic 20 s records by default) or a record set: a folder with the set.json of "
                   "`statue2model records` (only the files it names are used)")
    p.add_argument("--units", choices=["g", "m/s2"], default=None, help="units of the CSV records (default m/s2)")
    p.add_argument("--levels", required=True, metavar="LO:HI:N", help="N intensity levels from LO to HI, e.g. "
                   "0.05g:1g:40 (PGA) or 0.05:1:20 (PGV, m/s)")
    p.add_argument("--im", choices=["pga", "pgv"], default="pga", help="intensity measure (default pga; pgv: "
                   "from the acceleration high-passed at 0.1 Hz for records of 10 s or more)")
    p.add_argument("--samples", type=int, default=1, metavar="N", help="parameter samples per record and level "
                   "(default 1)")
    p.add_argument("--vary", action="append", default=[], metavar="NAME=LO:HI",
                   help="an uncertain parameter and its range (theta_R, theta_L, theta, alpha_L, alpha_R, alpha, "
                   "e_L, e_R, e, im_factor; rad for theta); repeat for several. Default with --samples > 1 and "
                   "the imperfect model: the thesis' theta_R / delta_R in [1.78, 2.26]e-2")
    p.add_argument("--sampling", choices=["lhs", "grid"], default="lhs", help="Latin hypercube (default) or an "
                   "even grid (one --vary only)")
    p.add_argument("--seed", type=int, default=0, metavar="K", help="seed of the samples and the bootstrap")
    p.add_argument("--boot", type=int, default=200, metavar="N", help="bootstrap replicates (default 200; 0: none)")
    p.add_argument("--design-pga", type=_design_pga, metavar="A",
                   help="the design PGA with a unit (0.287g, 2.82m/s2): marked on every panel of fragility.png "
                        "(with --im pga)")
    p.add_argument("--isolator", metavar="DESIGN.json", help="also on this isolator (`statue2model isolator design`)")
    p.add_argument("--direction", type=finite_float, metavar="DEG", help="excitation direction of a scan "
                   "(default: weakest)")
    g = p.add_argument_group("model (default: Housner; imperfect with --alpha-L/--alpha-R)")
    g.add_argument("--alpha-L", type=plausible("alpha", finite_float, "--alpha-L"), metavar="A")
    g.add_argument("--alpha-R", type=plausible("alpha", finite_float, "--alpha-R"), metavar="A")
    g.add_argument("--theta-L", type=positive_float, metavar="RAD", help="default 0.07 delta_L")
    g.add_argument("--theta-R", type=positive_float, metavar="RAD", help="default 0.07 delta_R")
    g.add_argument("--e", type=plausible("restitution", finite_float, "--e"), metavar="E", help="e_L = e_R (default: eq. 15)")
    g.add_argument("--mu-static", type=plausible("static_friction", option="--mu-static"), metavar="MU", help="static friction (default 0.7)")
    g.add_argument("--rtol", type=positive_float, default=1e-7, metavar="TOL", help="solver tolerance (default 1e-7)")
    x = p.add_argument_group("parallel runs (default: the threads of this process)").add_mutually_exclusive_group()
    x.add_argument("--workers", type=int, metavar="N", help="run on N local worker processes, one core each")
    x.add_argument("--scheduler", metavar="ADDRESS", help="run on the workers of a Dask cluster (tcp://host:8786)")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder: new, empty or statue2model's "
                   "(a folder holding other files is refused)")
    p.set_defaults(func=_cmd_fragility)


def _params(source: str, direction):
    path, params = scan_or_params(source)
    if params is not None:
        return params
    from ..geometry.body import load_body

    return load_body(path).rocking(direction)


def _model(args, params):
    from ..rocking.model import RockingModel

    if (args.alpha_L is None) != (args.alpha_R is None):
        raise InputError("give both --alpha-L and --alpha-R (the imperfect model), or neither (Housner)")
    if args.alpha_L is None:
        if args.theta_L is not None or args.theta_R is not None:
            raise InputError("--theta-L/--theta-R belong to the imperfect model: give --alpha-L and --alpha-R")
        return RockingModel.housner(params, args.e, args.e, mu_static=args.mu_static)
    return RockingModel.imperfect(params, args.alpha_L, args.alpha_R, args.theta_L, args.theta_R, args.e, args.e,
                                  mu_static=args.mu_static)


def parse_levels(text: str, im: str):
    """'LO:HI:N' -> N levels (m/s^2 for PGA, with a unit; m/s for PGV)."""
    import numpy as np

    from ..quantities import parse_accel

    parts = text.split(":")
    if len(parts) != 3:
        raise InputError(f"--levels {text!r}: expected LO:HI:N, e.g. 0.05g:1g:40")
    try:
        n = int(parts[2])
    except ValueError:
        raise InputError(f"--levels {text!r}: N must be a whole number") from None
    if not 1 <= n <= 10_000:
        raise InputError(f"--levels {text!r}: N must be in 1..10000")
    if im == "pga":
        lo, hi = (parse_accel(v, "--levels") for v in parts[:2])
    else:
        try:
            lo, hi = (float(v.strip().lower().removesuffix("m/s")) for v in parts[:2])
        except ValueError:
            raise InputError(f"--levels {text!r}: PGV levels are numbers in m/s, e.g. 0.05:1:20") from None
    if not (0 < lo and (hi > lo or (n == 1 and hi == lo))) or not np.isfinite(hi):
        raise InputError(f"--levels {text!r}: need 0 < LO < HI")
    return np.linspace(lo, hi, n)


def parse_records(text: str, units: str | None, say=print, check=None):
    """The records of --records: synthetic:N[,duration=S][,dt=S][,seed=K] or a record set's
    folder (the files its set.json names, checked; ``say``: the note on files it leaves out).
    ``check(n_records, samples_per_record)``: the study's budget, called before synthetic
    records are made."""
    from ..hazard import motions

    if text.startswith("synthetic:"):
        head, *opts = text[len("synthetic:"):].split(",")
        kw = {"duration": 20.0, "dt": 0.01, "seed": 0}
        for o in opts:
            if o.partition("=")[0].strip() not in kw:
                raise InputError(f"--records: unknown option {o.partition('=')[0].strip()!r} (duration, dt, seed)")
        try:
            n = int(head)
            for o in opts:
                k, _, v = o.partition("=")
                kw[k.strip()] = int(v) if k.strip() == "seed" else float(v)
        except ValueError:
            raise InputError(f"--records {text!r}: expected synthetic:N[,duration=S][,dt=S][,seed=K]") from None
        if not 1 <= n <= 100_000:
            raise InputError(f"--records {text!r}: N must be in 1..100000")
        if check is not None and kw["dt"] > 0 and kw["duration"] > 0:
            check(n, kw["duration"] / kw["dt"] + 1)
        return [motions.synthetic_record(kw["duration"], kw["dt"], 1.0, seed=kw["seed"] + i) for i in range(n)]
    from ..hazard.matching import read_record_set

    path = Path(text)
    if not path.is_dir():
        raise InputError(f"--records {text!r}: neither synthetic:N nor a folder of records")
    records, info = read_record_set(path, units)
    if info["ignored"]:
        n = len(info["ignored"])
        say(f"note: {n} record file{'s' if n > 1 else ''} in {path} not named by its set.json "
            f"({', '.join(info['ignored'][:4])}{', ...' if n > 4 else ''}): not used")
    scaled = sorted({r.froude_scale for r in records if r.froude_scale != 1.0})
    if scaled:      # never silently: the model of PARAMS.json must be the prototype's
        say(f"note: the records of {path} are Froude-scaled for a 1:{scaled[0]:g} prototype: the model "
            f"(PARAMS.json) must be that prototype's, not the full-size statue's")
    return records


def build_samples(args, model):
    from ..rocking import sampling

    ranges = {}
    for item in args.vary:
        name, _, rng = item.partition("=")
        lo, sep, hi = rng.partition(":")
        if not sep:
            raise InputError(f"--vary {item!r}: expected NAME=LO:HI")
        try:
            ranges[name.strip()] = (float(lo), float(hi))
        except ValueError:
            raise InputError(f"--vary {item!r}: LO and HI must be numbers") from None
    n = args.samples
    if not 1 <= n <= sampling.MAX_SAMPLES:
        raise InputError(f"--samples must be a whole number in 1..{sampling.MAX_SAMPLES}, got {n}")
    if not ranges:
        if n == 1:
            return sampling.nominal(1)
        if model.kind != "imperfect":
            raise InputError("--samples > 1 needs --vary NAME=LO:HI (or the imperfect model, whose default is the "
                             "thesis' theta_R sweep)")
        return sampling.thesis_theta_R(model, n) if args.sampling == "grid" else \
            sampling.latin_hypercube({"theta_R": tuple(x * model.params.delta_R for x in sampling.THESIS_THETA_R)},
                                     n, seed=args.seed)
    if args.sampling == "grid":
        if len(ranges) != 1:
            raise InputError("--sampling grid takes one --vary; use lhs for several")
        (name, (lo, hi)), = ranges.items()
        return sampling.grid(name, lo, hi, n)
    return sampling.latin_hypercube(ranges, n, seed=args.seed)


FRAGILITY_FILES = ("fragility.json", "fragility.csv", "fragility.png")


def _cmd_fragility(args) -> int:
    from ..assessment.fragility import FragilityStudy
    from ..io.files import open_output
    from .isolator import read_design

    params = _params(args.source, args.direction)
    model = _model(args, params)
    levels = parse_levels(args.levels, args.im)
    samples = build_samples(args, model)
    samples.models(model)                       # a bad sample fails here, before any run
    study = FragilityStudy(im=args.im, rtol=args.rtol, n_boot=args.boot, seed=args.seed)
    iso = None
    if args.isolator:
        from ..isolator.device import isolator_from_design

        iso = isolator_from_design(read_design(args.isolator))   # a rejected design is refused
    from ..assessment.fragility import check_study

    # the study's runs and memory are checked before its records are made (compute/budget.py)
    records = parse_records(args.records, args.units, check=lambda n, npts: check_study(
        n, levels.size, samples.n, npts, iso is not None, args.workers is not None or args.scheduler is not None))
    # the folder is checked (a user's files refuse it) and locked before any work; the three
    # files appear together once all are written
    with open_output(args.out, "fragility", command="fragility", can_reuse=False) as od:
        return _study(args, od, model, records, levels, samples, study, iso)


def _design_pga(text: str) -> float:
    """A design PGA with its unit (0.287g, 2.82m/s2), m/s^2."""
    from .isolator import _accel

    return _accel(text)


def _study(args, od, model, records, levels, samples, study, iso) -> int:
    import contextlib

    from ..assessment.fragility import run_fragility
    from ..report.fragility_plots import plot_fragility

    group = od.group(FRAGILITY_FILES)
    out = od.path
    if args.workers is None and args.scheduler is None:
        ctx = contextlib.nullcontext(None)
    else:
        from ..compute.executors import make_executor

        ctx = make_executor(scheduler=args.scheduler, workers=args.workers, cap=True)
        print(f"running on {ctx.describe()}")
    n = len(records) * levels.size * samples.n
    print(f"{len(records)} records x {levels.size} levels x {samples.n} samples = {n} runs"
          f"{' (x 2: fixed and isolated)' if iso is not None else ''}")
    with ctx as ex:
        res = run_fragility(model, records, levels, samples, study, isolator=iso, executor=ex)
    with group as g:
        res.write_json(g / "fragility.json")
        res.write_csv(g / "fragility.csv")
        plot_fragility(res, g / "fragility.png", design_im=args.design_pga if args.im == "pga" else None)
    for line in res.summary_lines():
        print(line)
    s = res.stats
    print(f"{s['runs_fixed']} fixed-base runs in {s['wall_fixed_s']:.1f} s "
          f"({s['runs_fixed'] / max(s['wall_fixed_s'], 1e-9):.0f} runs/s)")
    print(f"wrote fragility.json, fragility.csv, fragility.png in {out}")
    return 0
