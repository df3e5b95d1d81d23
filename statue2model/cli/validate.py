"""Command-line stage of the validation: ``statue2model validate CAMPAIGN.toml --out DIR``.

    statue2model validate CAMPAIGN.toml --out DIR [--models 2d,3d] [--identify OTHER.toml] [--sample N]
                          [--workers N | --scheduler ADDRESS]
"""
from __future__ import annotations

from ..errors import InputError

VALIDATION_FILES = ("validation.json", "validation.html", "validation.png")


def add_parsers(sub) -> None:
    p = sub.add_parser("validate", help="replay a shake-table campaign: how often the models were right",
                       description="Replay a shake-table campaign (a TOML file naming the specimen's scan, the "
                       "table's axis, the motion files' format and a tests.csv of name, file, toppled): predict "
                       "every test with the 2D model (P(topple) over the scan's contact band and the restitution's "
                       "scatter) and a sample of them in 3D, and score the predictions (accuracy, precision, "
                       "recall with 95 %% Wilson intervals, Brier score). --identify identifies the contact's "
                       "alpha and restitution on another campaign first. Writes validation.json, validation.html.")
    p.add_argument("campaign", metavar="CAMPAIGN.toml")
    p.add_argument("--out", metavar="DIR", required=True)
    p.add_argument("--models", default="2d", help="2d, 3d or 2d,3d (default 2d)")
    p.add_argument("--identify", metavar="OTHER.toml", help="identify the contact on this campaign first")
    p.add_argument("--sample", type=int, default=10, metavar="N", help="tests run in 3D (default 10)")
    x = p.add_mutually_exclusive_group()
    x.add_argument("--workers", type=int, metavar="N", help="run the tests (2D and 3D) on N local worker processes, "
                   "one core each (default: this process, the 2D runs of a test in its threads)")
    x.add_argument("--scheduler", metavar="ADDRESS", help="run the tests on the workers of a Dask cluster "
                   "(tcp://host:8786)")
    p.set_defaults(func=_cmd_validate)


def _cmd_validate(args) -> int:
    import contextlib

    from ..io.files import open_output
    from ..pipeline.validate import validate

    models = tuple(m.strip().lower() for m in str(args.models).split(",") if m.strip())
    if args.sample < 1:
        raise InputError(f"--sample must be at least 1, got {args.sample}")
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be at least 1, got {args.workers}")
    if args.scheduler is None and (args.workers is None or args.workers < 2):
        ctx = contextlib.nullcontext(None)
    else:
        from ..compute.executors import make_executor

        ctx = make_executor(scheduler=args.scheduler, workers=args.workers, cap=True)
        print(f"running on {ctx.describe()}")
    with open_output(args.out, "validate", command="validate", can_reuse=False) as od, \
            od.group(VALIDATION_FILES) as g, ctx as ex:
        res = validate(args.campaign, g.tmp, models=models, identify_path=args.identify, sample=args.sample,
                       executor=ex, say=print)
    for model, ms in res["models"].items():
        s = ms["topple"]

        def v(r):
            return "-" if r["value"] is None else f"{r['value']:.2f}"

        print(f"{model.upper()} on {ms['tests']} tests: accuracy {v(s['accuracy'])}, precision {v(s['precision'])}, "
              f"recall {v(s['recall'])}, Brier {s['brier']:.3f}")
    print(f"wrote validation.json, validation.html in {od.path}")
    return 0
