"""A shake-table campaign replayed by ``statue2model validate``: the old code (a git worktree of ``--old-ref``)
in this process, one test after the other, against the working tree on 2 worker processes, in one run.

The campaign is synthetic (:func:`make_campaign`): the bundled default scan (3 distinct contacts in its band,
so 3 PyBullet scenes a test) on a table along x, N tests of ``--seconds`` s (default 40 s, a shake-table test's
length) at dt 5 ms, each a band-limited random motion under a smooth envelope scaled to a PGA between 0.1 g and
0.9 g (log-spaced: the statue lifts at about 0.42 g and some tests topple it). The motion files, tests.csv and
campaign.toml are written as a lab would (the format of tests/test_validate.py's campaign).

Each row runs ``validate`` (pipeline/validate.py: the scan read, the motions read, the predictions, the json and
html written) in a subprocess per code tree (``PYTHONPATH`` = the tree): old = serial, in-process (the
854e6ff code path: one ``simulate`` per 2D run; 3D scenes one after the other); new = ``--workers`` local
processes (ProcessExecutor; the pool's start is in the time) and, for 2D, also in-process (the batch kernel on
one thread). 3D rows run every test in 3D (``--sample N``). The table gives the wall time (s) and the CPU
time (s, the process and its workers), the ratio old / new of each, the tests a minute of the new code and the
time it projects for a 500-test campaign (500 / tests a minute; "500 CPU/w": the new CPU time a test x 500
over the workers' cores, the wall time where each worker has a core of its own: on a shared machine the wall
time is the load's), and whether every test's P(topple) and P(lift) are the same in both trees. Before the
rows, each tree runs a 2-test campaign once, untimed (its compiled-kernel cache filled).

    python benchmarks/bench_campaign.py [--tests 2d:200,3d:20] [--workers 2] [--seconds 40]
                                        [--old /tmp/old_scamp] [--old-ref 854e6ff]

Exit status 1 if any prediction differs. The machine may be shared: the load average is printed with each row.
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
NEW = HERE.parent
G = 9.80665


def make_campaign(folder: Path, n: int, seconds: float = 40.0, dt: float = 0.005, seed: int = 7) -> Path:
    """Write a campaign of ``n`` tests in ``folder`` (module docstring); returns its campaign.toml."""
    folder.mkdir(parents=True, exist_ok=True)
    scan = NEW / "meshes" / "maria_barjatinskaja.ply"
    sys.path.insert(0, str(NEW))
    try:
        from statue2model.io.paths import default_scan

        scan = default_scan()
    finally:
        sys.path.pop(0)
    shutil.copy(scan, folder / ("specimen" + scan.suffix))
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, seconds, dt)
    env = np.clip(t / 3.0, 0, 1) * np.clip((seconds - t) / 6.0, 0, 1)          # 3 s rise, 6 s decay
    pgas = np.geomspace(0.1, 0.9, n) if n > 1 else np.array([0.5])
    rng.shuffle(pgas)
    f = np.fft.rfftfreq(t.size, dt)
    band = (f > 0.5) & (f < 8.0)
    rows = ["name,file,toppled,lifted"]
    for k, pga in enumerate(pgas):
        spec = np.zeros(f.size, complex)
        spec[band] = rng.normal(size=band.sum()) + 1j * rng.normal(size=band.sum())
        a = np.fft.irfft(spec, t.size) * env
        a *= pga / np.abs(a).max()
        name = f"t{k:04d}"
        np.savetxt(folder / f"{name}.txt", np.column_stack([t, a]), fmt=["%.3f", "%.6f"], delimiter="\t",
                   header="time [s]\tacc [g]", comments="")
        rows.append(f"{name},{name}.txt,{int(pga > 0.55)},{int(pga > 0.42)}")
    (folder / "tests.csv").write_text("\n".join(rows) + "\n")
    (folder / "campaign.toml").write_text(
        f'name = "synthetic {n}"\ntests = "tests.csv"\n[specimen]\nscan = "specimen{scan.suffix}"\n'
        'direction = 0\n[motion]\ncolumns = [1, 2]\nunits = "g"\n')
    return folder / "campaign.toml"


# --- the worker: one tree, one row (a subprocess, PYTHONPATH = the tree) ------------------------------------
def worker(args) -> None:
    import statue2model
    from statue2model.pipeline.validate import validate

    ctx = None
    if args.workers >= 2:
        from statue2model.compute.executors import make_executor

        ctx = make_executor(workers=args.workers)
    r0 = resource.getrusage(resource.RUSAGE_SELF)
    t0 = time.perf_counter()
    try:
        res = validate(args.campaign, Path(args.out).with_suffix(".d"), models=(args.model,), sample=args.sample,
                       executor=ctx)
    finally:
        if ctx is not None:
            ctx.close()
    wall = time.perf_counter() - t0
    r1, rc = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime) + rc.ru_utime + rc.ru_stime
    m = args.model
    P = [[row.get(f"p_topple_{m}"), row.get(f"p_lift_{m}")] for row in res["rows"]]
    Path(args.out).write_text(json.dumps({"tree": str(Path(statue2model.__file__).parent.parent), "wall": wall,
                                          "cpu": cpu, "P": P}))


def run(tree: Path, campaign: Path, model: str, workers: int, sample: int, tmp: Path) -> dict:
    out = tmp / f"{model}-{tree.name}-{workers}-{time.monotonic_ns()}.json"
    env = dict(os.environ, PYTHONPATH=str(tree), TQDM_DISABLE="1")
    cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", "--campaign", str(campaign), "--model", model,
           "--workers", str(workers), "--sample", str(sample), "--out", str(out)]
    p = subprocess.run(cmd, env=env, cwd=str(tree), capture_output=True, text=True)
    if p.returncode != 0:
        sys.stderr.write(p.stderr[-4000:])
        raise SystemExit(f"worker failed: {model} in {tree}")
    info = json.loads(out.read_text())
    if Path(info["tree"]).resolve() != tree.resolve():
        raise SystemExit(f"the worker imported {info['tree']}, not {tree}")
    return info


def old_tree(path: Path, ref: str) -> str:
    """The old tree's commit (bench_fragility_speed.old_tree: a worktree of ``ref`` at ``path``)."""
    sys.path.insert(0, str(HERE))
    from bench_fragility_speed import old_tree as make

    return make(path, ref)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--campaign", help=argparse.SUPPRESS)
    ap.add_argument("--model", help=argparse.SUPPRESS)
    ap.add_argument("--out", help=argparse.SUPPRESS)
    ap.add_argument("--sample", type=int, default=10, help=argparse.SUPPRESS)
    ap.add_argument("--tests", default="2d:200,3d:20", help="rows: model:N, comma-separated (default 2d:200,3d:20)")
    ap.add_argument("--workers", type=int, default=2, help="worker processes of the new code (default 2)")
    ap.add_argument("--seconds", type=float, default=40.0, help="length of each test's motion, s (default 40)")
    ap.add_argument("--old", default="/tmp/old_scamp", help="the old tree (a git worktree; made when missing)")
    ap.add_argument("--old-ref", default="854e6ff", help="commit of the old tree when it is made")
    args = ap.parse_args()
    if args.worker:
        worker(args)
        return 0
    old = Path(args.old)
    commit = old_tree(old, args.old_ref)
    print(f"old: {old} (commit {commit}), serial in-process; new: {NEW} (working tree), {args.workers} workers; "
          f"tests of {args.seconds:g} s")
    rows = [(m.strip(), int(n)) for m, n in (x.split(":") for x in args.tests.split(","))]
    table, same_all = [], True
    with tempfile.TemporaryDirectory(prefix="bench_campaign_") as tmp:
        tmp = Path(tmp)
        warm = make_campaign(tmp / "warm", 2, 4.0)
        for tree in (old, NEW):          # untimed: each tree's compiled-kernel cache filled, the files read once
            for model in {m for m, _ in rows}:
                run(tree, warm, model, 1, 2, tmp)
        for model, n in rows:
            camp = make_campaign(tmp / f"c{n}", n, args.seconds) if not (tmp / f"c{n}").is_dir() \
                else tmp / f"c{n}" / "campaign.toml"
            load = os.getloadavg()[0]
            o = run(old, camp, model, 1, n, tmp)
            w = run(NEW, camp, model, args.workers, n, tmp)
            variants = [(f"{args.workers} workers", w)]
            if model == "2d":
                variants.append(("in-process", run(NEW, camp, model, 1, n, tmp)))
            for how, nw in variants:
                same = nw["P"] == o["P"]
                same_all &= same
                per_min = n / (nw["wall"] / 60)
                cores = args.workers if how.endswith("workers") else 1
                cpu500 = nw["cpu"] / n * 500 / cores           # s: the CPU a test x 500, over the workers' cores
                table.append((n, model, how, o["wall"], nw["wall"], o["cpu"], nw["cpu"], per_min, 500 / per_min,
                              cpu500, same, load))
                print(f"  {n} tests {model} new {how}: old {o['wall']:.1f} s ({o['cpu']:.1f} s CPU), new "
                      f"{nw['wall']:.1f} s ({nw['cpu']:.1f} s CPU), same P: {same}  [load {load:.1f}]", flush=True)
    print()
    print(f"{'N':>4} {'model':<5} {'new':<11} {'old s':>7} {'new s':>7} {'ratio':>5} {'CPU old':>7} {'new':>7} "
          f"{'ratio':>5} {'tests/min':>9} {'500 tests':>9} {'500 CPU/w':>9} {'same P':>6} {'load':>5}")
    for n, model, how, ow, nw, oc, nc, pm, proj, cpu500, same, load in table:
        print(f"{n:>4} {model:<5} {how:<11} {ow:>7.1f} {nw:>7.1f} {ow / nw:>5.2f} {oc:>7.1f} {nc:>7.1f} "
              f"{oc / nc:>5.2f} {pm:>9.1f} {proj:>7.1f} m {cpu500 / 60:>7.1f} m {str(same):>6} {load:>5.1f}")
    print(f"load average at the end: {os.getloadavg()[0]:.1f}")
    return 0 if same_all else 1


if __name__ == "__main__":
    sys.exit(main())
