"""Command line of the whole pipeline: ``statue2model run`` and ``statue2model config``.

    statue2model run [MESH | FOLDER] [--config project.toml] [--out DIR] [--stages a,b]
                     [--force] [--reuse] [--workers N | --scheduler ADDRESS]

--out is new, empty or a previous run's (its .statue2model.json lists what it wrote);
a folder with other files is refused unless --reuse (they are never touched), and a
folder another statue2model command is writing is refused at once (its lock).
    statue2model config [--out project.toml]       the project file with every default
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

from ..errors import InputError


def add_parsers(sub) -> None:
    p = sub.add_parser(
        "run", help="scan -> parameters, prototype, isolator, 2D analyses, 3D cross-check and an HTML report",
        description="Run every stage on a scan (default: the bundled meshes/dancing_girl.ply), or on every scan "
        "of a folder as one sweep. Stages whose inputs did not change are taken from the output folder "
        "(content hashes); an interrupted run resumes where it stopped.")
    p.add_argument("mesh", nargs="?", metavar="MESH|FOLDER", help="a scan, or a folder of scans (one sweep)")
    p.add_argument("--config", metavar="TOML", help="project file (see `statue2model config`); default: the "
                   "thesis' choices")
    p.add_argument("--out", metavar="DIR", help="output folder (default: outputs/<scan or folder name>)")
    p.add_argument("--stages", metavar="LIST", help="comma list of params, prototype, isolator, dynamics, "
                   "crosscheck, or 'all' (default: [run] stages of the project file, params, prototype, "
                   "isolator, dynamics); the stages they read are run or taken from the cache")
    p.add_argument("--force", action="store_true", help="recompute every stage asked for, cached or not")
    p.add_argument("--reuse", action="store_true", help="write into an --out that holds files statue2model did not "
                   "write (they are never touched; a name that collides with one is refused), or go on with an "
                   "older statue2model run made before output manifests")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--workers", type=int, metavar="N", help="local worker processes for the sweeps "
                   "(default: [run] workers, else one per core)")
    g.add_argument("--scheduler", metavar="ADDRESS", help="run the sweeps on a Dask cluster (tcp://host:8786)")
    p.set_defaults(func=_cmd_run)

    c = sub.add_parser("config", help="write the project file with every key at its default (the thesis' choices)")
    c.add_argument("--out", metavar="TOML", default="project.toml", help="default project.toml; - prints it")
    c.set_defaults(func=_cmd_config)


INLINE_FIRST = 3.0
"""CPU s: one scan's sweeps whose items take less than this in all run in this process until the
local pool has started (compute/executors.ProcessExecutor.inline_first): the sweeps of a default
run take about 2-3 s in all (the first loads of compiled kernels included), less than the start of
the workers (about 1.5-2 s of CPU each)."""


def _executor(args, cfg):
    from ..compute.executors import make_executor

    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    if args.scheduler:                       # the command line wins over [run]
        return make_executor(scheduler=args.scheduler)
    inline = 0.0 if _folder(args) else INLINE_FIRST     # a folder's tasks are whole scans: to the pool
    if args.workers is not None:
        return make_executor(workers=args.workers, cap=True, inline_first=inline)
    from ..compute.executors import config_executor    # [run] scheduler: only on this machine unless --scheduler names it

    return config_executor(cfg.run.scheduler, cfg.run.workers, cfg.source, inline_first=inline)


def _folder(args) -> bool:
    """The run's target is a folder of scans (else one scan, the default one included)."""
    return bool(args.mesh) and Path(args.mesh).is_dir()


def _cmd_run(args) -> int:
    """``statue2model run``; on one scan with Python's automatic cyclic garbage collection paused
    (compute/collector.py: about 2 s of the default run's CPU went to walking its heap). A folder
    keeps it on: its scans run on the workers, and a long folder would pile up the cycles that each
    scan leaves in this process (closed figures)."""
    from contextlib import nullcontext

    from ..compute.collector import collector_paused

    with nullcontext() if _folder(args) else collector_paused():
        return _run(args)


def _run(args) -> int:
    from ..io.paths import default_scan
    from ..pipeline.config import load_config
    from ..pipeline.run import run_collection, run_project, warnings_line
    from ..pipeline.config import stage_list

    cfg = load_config(args.config)
    for w in cfg.warnings:          # unusual values of the project file (config.RANGES), as the options' warnings
        print(f"statue2model: warning: {w}", file=sys.stderr)
    target = Path(args.mesh) if args.mesh else default_scan()
    if not target.exists():
        raise InputError(f"scan or folder not found: {target}")
    stages = stage_list(args.stages) if args.stages else None
    out = Path(args.out) if args.out else Path("outputs") / (target.name if target.is_dir() else target.stem)
    t0 = time.perf_counter()
    with _executor(args, cfg) as ex:
        print(f"statue2model run: {target} -> {out}/ (sweeps on {ex.describe()})", flush=True)
        if target.is_dir():
            data = run_collection(target, out, cfg, stages=stages, force=args.force, executor=ex,
                                  reuse=args.reuse)
            print(_collection_table(data))
            print(f"\n{len(data['scans'])} scans in {time.perf_counter() - t0:.1f} s; wrote {out}/collection.html "
                  f"(ranked by risk), collection.csv, collection.json and one folder (with report.html) per scan")
            warned = [(r["scan"], w) for r in data["scans"] for w in r.get("warnings", ())]
            if warned:
                print(f"\n{len(warned)} warning{'s' if len(warned) != 1 else ''} (also in each scan's run.json "
                      "and report.html):")
                for scan, w in warned:
                    print(f"  {scan} {w['stage']}: warning: {w['text']}")
            errors = [r for r in data["scans"] if "error" in r]
            if errors:
                raise InputError(f"{len(errors)} scan(s) failed: " + "; ".join(f"{r['scan']}: {r['error']}"
                                                                              for r in errors))
            return 0
        res = run_project(target, out, cfg, stages=stages, force=args.force, executor=ex,
                          say=lambda m: print(m, flush=True), reuse=args.reuse)
    if res.verdict:
        v = res.verdict
        print(f"\nAssessment [{v.get('code', '-')}]\n  {v.get('headline') or v['recommendation']}")
        for b in v.get("bullets") or ():
            print("  - " + b)
        print("  Reasoning: " + v["recommendation"])
        for line in v["lines"]:
            print("  " + line)
    print("\nSummary")
    w = max(len(n) for n in res.stages)
    for name, status, t in res.summary_rows():
        print(f"  {name:<{w}}  {status:<8} {t}")
    if res.warnings:
        print(f"\n{warnings_line(len(res.warnings))}")
    print(f"\nwrote {out}/config.toml (resolved configuration), run.json and report.html "
          f"in {time.perf_counter() - t0:.1f} s")
    return 0


def _collection_table(data) -> str:
    """The ranked objects (collection.json ``rows``), most urgent first, and the summary line."""
    cols = (("rank", "rank"), ("object", "object"), ("where", "where"), ("status", "status"),
            ("state", "fixed base"), ("device_state", "isolator"), ("sheets", "sheets"))
    rows = data.get("rows") or []

    def cell(r, k):
        v = r.get(k)
        if k == "state" and not r.get("assessed"):
            return "not assessed: " + str(r.get("reason") or "")
        return "-" if v is None or v == "" else str(v)

    width = {k: max(len(h), *(len(cell(r, k)) for r in rows)) for k, h in cols} if rows else {}
    lines = ["  ".join(f"{h:<{width[k]}}" for k, h in cols)] if rows else []
    lines += ["  ".join(f"{cell(r, k):<{width[k]}}" for k, _ in cols) for r in rows]
    s = data.get("summary") or {}
    if s:
        lines.append(f"\n{s.get('objects', 0)} objects: {s.get('needing_protection', 0)} need protection, "
                     f"{s.get('not_assessed', 0)} not assessed; {s.get('devices_passed', 0)} isolators pass, "
                     f"{s.get('devices_conditional', 0)} conditional on the ball load; "
                     f"{s.get('prototype_sheets', 0)} prototype sheets, {s.get('isolator_plates', 0)} isolator plates"
                     + (f" (about {s['devices_cost']:.0f} EUR)" if s.get("devices_cost") else ""))
    return "\n".join(lines)


def _cmd_config(args) -> int:
    from ..io.files import atomic_write
    from ..pipeline.config import default_toml

    text = default_toml()
    if args.out == "-":
        print(text, end="")
        return 0
    out = Path(args.out)
    if out.exists():
        raise InputError(f"{out} exists; give another --out (nothing was overwritten)")
    atomic_write(out, lambda p: p.write_text(text, encoding="utf-8"))
    print(f"wrote {out}: edit it, then run `statue2model run MESH --config {out}`")
    return 0
