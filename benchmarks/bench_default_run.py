"""The warm default run, old code (a git worktree) against this checkout, interleaved in one run.

The run: ``statue2model run --stages params,isolator,dynamics`` on the bundled default scan, each
time into a fresh ``--out`` (no stage taken from a cache folder). Each tree first runs once to warm
up (numba's kernel cache, and the new tree's record-set cache, pipeline/record_cache.py), then
``--repeat`` times, old and new in turn. Each run is a child process (``PYTHONPATH`` = its tree); its
CPU time is the process's and its workers' (resource.getrusage(RUSAGE_CHILDREN), user + system),
which other jobs on a shared machine move less than the wall time. The table: per repetition the old
and new CPU and wall seconds and the ratio new / old of the CPU, then the medians. With
``--compare`` the last old and new output folders are compared file by file
(benchmarks/same_outputs.py): the run's outputs must be identical.

    python benchmarks/bench_default_run.py --old /tmp/old_srun [--repeat 3] [--compare]

The old tree: ``git -C <repo> worktree add --detach /tmp/old_srun <commit>``.
"""
from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
NEW = HERE.parent
STAGES = "params,isolator,dynamics"


def one(tree: Path, out: Path) -> tuple[float, float]:
    """(CPU s, wall s) of one default run of ``tree`` into ``out``."""
    shutil.rmtree(out, ignore_errors=True)
    env = dict(os.environ, PYTHONPATH=str(tree))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "statue2model", "run", "--stages", STAGES, "--out", str(out)],
                       cwd=tree, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit(f"{tree}: statue2model run failed ({p.returncode}): {p.stderr.strip().splitlines()[-1:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, wall


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True, help="the old tree (a git worktree of the old commit)")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs of each tree (default 3)")
    ap.add_argument("--work", default=None, help="folder for the runs' outputs (default: a temporary one)")
    ap.add_argument("--compare", action="store_true", help="compare the last old and new outputs byte for byte")
    args = ap.parse_args()
    old = Path(args.old).resolve()
    if not (old / "statue2model").is_dir():
        sys.exit(f"--old {old}: no statue2model package there")
    work = Path(args.work or tempfile.mkdtemp(prefix="bench_default_run_"))
    trees = {"old": old, "new": NEW}
    print(f"old: {old}; new: {NEW}; stages {STAGES}; load average {os.getloadavg()[0]:.2f}", flush=True)
    for name, tree in trees.items():   # warm-up: compiled kernels, cached record sets
        one(tree, work / f"warm_{name}")
    rows = []
    for i in range(args.repeat):
        row = {}
        for name, tree in trees.items():
            row[name] = one(tree, work / name)
        rows.append(row)
        print(f"  repetition {i + 1}: old {row['old'][0]:.2f} s CPU, new {row['new'][0]:.2f} s CPU", flush=True)
    print(f"\nwarm default run ({STAGES}), CPU = process + workers (user + system)")
    print(f"{'rep':>4} {'old CPU s':>10} {'new CPU s':>10} {'new/old':>8} {'old wall s':>11} {'new wall s':>11}")
    for i, r in enumerate(rows, 1):
        print(f"{i:>4} {r['old'][0]:>10.2f} {r['new'][0]:>10.2f} {r['new'][0] / r['old'][0]:>8.3f} "
              f"{r['old'][1]:>11.2f} {r['new'][1]:>11.2f}")
    med = {k: statistics.median(r[k][0] for r in rows) for k in trees}
    medw = {k: statistics.median(r[k][1] for r in rows) for k in trees}
    print(f"{'med':>4} {med['old']:>10.2f} {med['new']:>10.2f} {med['new'] / med['old']:>8.3f} "
          f"{medw['old']:>11.2f} {medw['new']:>11.2f}")
    print(f"load average at the end {os.getloadavg()[0]:.2f}")
    status = 0
    if args.compare:
        p = subprocess.run([sys.executable, str(HERE / "same_outputs.py"), str(work / "old"), str(work / "new")])
        status = p.returncode
    return status


if __name__ == "__main__":
    sys.exit(main())
