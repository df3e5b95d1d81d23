"""Executors side by side on a folder of scans: one ``run_collection`` sweep
(each scan one task) serially in this process, on local worker processes and
on a Dask LocalCluster, with 1 and 2 workers each.

    python3 benchmarks/bench_collection.py             # 6 scans, default [dynamics] grids, about 1.5 minutes on 2 cores
    python3 benchmarks/bench_collection.py --quick     # coarse grids, about 50 s
    python3 benchmarks/bench_collection.py --copies 4 --config project.toml
    python3 benchmarks/bench_collection.py --objects 30 --quick   # issue #29: throughput on 30 objects

Folder: the three bundled scans (dancing_girl.ply, maria_barjatinskaja.ply,
nefertiti_bust.obj) each copied ``--copies`` times (default 2) under different
names into a temporary folder, so 2 workers have work to share; or ``--objects N``:
the bundled scans in turn until there are N objects (30: each scan 10 times; the
last ones cut short when N is not a multiple of 3). Configuration:
the defaults with ``[prototype] enabled = false`` and ``[crosscheck] enabled =
false``, i.e. params, isolator design and plates, and the 2D analyses on the
default grids of [dynamics] (40 x 40 pulse spectra fixed and isolated, 24 PGAs);
or ``--config FILE``. ``--quick`` coarsens the [dynamics] grids (12 x 12, 8 PGAs)
and the plate solids (64 groove segments instead of 256).

Timing: wall time of one ``run_collection`` call (tasks, reports, collection.json
and .csv included). Each row writes to a FRESH output folder, so nothing comes
from the stage cache; the last row, "re-run (cached)", repeats the serial run on
the serial row's folder to show the cache. Excluded: numba's JIT compile /
on-disk cache load (one scan run once in this process first, not timed), and,
shown apart in "start s", the start of the process pool / Dask cluster plus one
warm-up scan per worker (each worker imports statue2model and loads the cache).
Every executor runs each scan on one numba thread and one BLAS thread.
"speed-up" is against the 1-worker row of the same kind (the cached row:
against the serial row); "vs serial" is the wall time over the serial row's.
The last column is the largest relative difference of every number of
``data["table"]`` and of the stages' ``data`` of every scan against the serial
row: it must be 0 (bit-identical).

A second table gives the throughput, objects per minute of wall time (the start of
the pool or cluster excluded, as above) and per minute with it, and per worker.
``--no-dask`` leaves the Dask rows out (they are also left out, with a note, when
distributed is not installed).
"""
from __future__ import annotations

import argparse
import logging
import math
import os
import shutil
import tempfile
import time
from pathlib import Path

from speedup_table import print_speedup_table

from statue2model.compute.executors import SerialExecutor, make_executor
from statue2model.io.paths import MESHES_DIR
from statue2model.pipeline.config import load_config, load_config_text
from statue2model.pipeline.run import run_collection, run_project

SCANS = ("dancing_girl.ply", "maria_barjatinskaja.ply", "nefertiti_bust.obj")
CONFIG = "[prototype]\nenabled = false\n[crosscheck]\nenabled = false\n"
QUICK = {"dynamics": {"freq": "0.5:10:12", "amp": "0.02g:1g:12", "pga": "0.05g:1.2g:8"},
         "isolator": {"segments": 64}}


def quiet(message: str) -> None:
    """Drop the progress lines of run_project / run_collection."""


def make_folder(root: Path, names: tuple[str, ...], copies: int, objects: int | None = None) -> Path:
    """``copies`` copies of each bundled scan, as NAME_1.ply, NAME_2.ply, ...; or, with
    ``objects``, the scans of ``names`` in turn until there are ``objects`` files."""
    root.mkdir(parents=True)
    n = objects if objects is not None else copies * len(names)
    for i in range(n):
        src = MESHES_DIR / names[i % len(names)]
        k = i // len(names) + 1
        shutil.copyfile(src, root / f"{src.stem}_{k}{src.suffix}")
    return root


def print_throughput(rows, n_objects: int) -> None:
    """Objects per minute of each row: of the wall time, of the wall time plus the start
    of the pool or cluster, and per worker."""
    width = max(len("executor"), *(len(r[0]) for r in rows))
    print()
    print(f"| {'executor':<{width}} | {'workers':>7} | {'objects':>7} | {'obj/min':>7} | "
          f"{'obj/min incl. start':>19} | {'obj/min per worker':>18} |")
    print(f"|{'-' * (width + 2)}|{'-' * 9}|{'-' * 9}|{'-' * 9}|{'-' * 21}|{'-' * 20}|")
    for name, _, w, start, wall, _ in rows:
        rate = 60.0 * n_objects / wall if wall > 0 else math.inf
        rate_all = 60.0 * n_objects / (wall + start) if wall + start > 0 else math.inf
        print(f"| {name:<{width}} | {w:>7} | {n_objects:>7} | {rate:>7.1f} | {rate_all:>19.1f} | "
              f"{rate / w:>18.1f} |")


def timed(folder, out, cfg, executor):
    t0 = time.perf_counter()
    data = run_collection(folder, out, cfg, executor=executor, say=quiet)
    return time.perf_counter() - t0, data


def rel_diff(a, b) -> float:
    """Largest relative difference of the numbers of ``a`` and ``b`` (nested dicts /
    lists); strings are skipped (paths differ), a structural mismatch is inf."""
    if isinstance(a, dict) and isinstance(b, dict):
        if a.keys() != b.keys():
            return math.inf
        return max((rel_diff(a[k], b[k]) for k in a), default=0.0)
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        if len(a) != len(b):
            return math.inf
        return max((rel_diff(x, y) for x, y in zip(a, b)), default=0.0)
    if isinstance(a, str) and isinstance(b, str):
        return 0.0
    if a is None or b is None or isinstance(a, bool) or isinstance(b, bool):
        return 0.0 if a == b else math.inf
    try:
        x, y = float(a), float(b)
    except (TypeError, ValueError):
        return 0.0 if a == b else math.inf
    if x == y or (math.isnan(x) and math.isnan(y)):
        return 0.0
    if math.isinf(x) or math.isinf(y) or math.isnan(x) or math.isnan(y):
        return math.inf
    return abs(x - y) / max(abs(x), abs(y))


def max_diff(data, ref) -> float:
    names = [r["scan"] for r in data["table"]] != [r["scan"] for r in ref["table"]]
    return max(math.inf if names else 0.0, rel_diff(data["table"], ref["table"]),
               rel_diff([s.get("data") for s in data["scans"]], [s.get("data") for s in ref["scans"]]))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="coarse grids: [dynamics] " + ", ".join(f"{k} {v}" for k, v in QUICK["dynamics"].items())
                    + "; [isolator] segments 64")
    ap.add_argument("--copies", type=int, default=2, help="copies of each bundled scan in the folder (default 2)")
    ap.add_argument("--objects", type=int, default=None,
                    help="objects in the folder: the bundled scans in turn until there are N (e.g. 30); "
                         "instead of --copies")
    ap.add_argument("--no-dask", action="store_true", help="leave the Dask LocalCluster rows out")
    ap.add_argument("--config", type=Path, default=None,
                    help="project file (default: prototype and crosscheck disabled, the rest default)")
    args = ap.parse_args()
    if args.copies < 1:
        ap.error("--copies must be >= 1")
    if args.objects is not None and args.objects < 1:
        ap.error("--objects must be >= 1")
    cfg = load_config(args.config) if args.config else load_config_text(CONFIG, "bench_collection")
    if args.quick:
        for section, changes in QUICK.items():
            cfg = cfg.with_section(section, **changes)
    load0 = os.getloadavg()[0]

    with tempfile.TemporaryDirectory(prefix="bench_collection_") as tmp:
        tmp = Path(tmp)
        folder = make_folder(tmp / "scans", SCANS, args.copies, args.objects)
        n_scans = len(list(folder.iterdir()))

        t0 = time.perf_counter()
        warm = run_project(MESHES_DIR / SCANS[1], tmp / "warm", cfg, report=True, say=quiet)
        asked = [k for k, v in warm.stages.items() if v["status"] in ("done", "cached")]
        d = cfg.dynamics
        made = f"{len(SCANS)} bundled x {args.copies}" if args.objects is None else \
            f"{len(SCANS)} bundled in turn"
        print(f"{n_scans} scans ({made}), stages {', '.join(asked)}; "
              f"[dynamics] freq {d.freq}, amp {d.amp}, pga {d.pga}; [isolator] segments {cfg.isolator.segments}"
              + (f"; config {args.config}" if args.config else ""))
        print(f"JIT compile / cache load + one warm-up scan in this process {time.perf_counter() - t0:.2f} s "
              "(excluded)")

        rows = []  # (executor, kind, workers, start s, wall s, data)
        wall, ref = timed(folder, tmp / "out_serial", cfg, SerialExecutor())
        rows.append(("SerialExecutor (this process)", "serial", 1, 0.0, wall, ref))

        for w in (1, 2):
            warm_folder = make_folder(tmp / f"warm_p{w}", SCANS[1:2], w)
            t0 = time.perf_counter()
            with make_executor(workers=w) as ex:
                run_collection(warm_folder, tmp / f"warm_p{w}_out", cfg, executor=ex, say=quiet)
                start = time.perf_counter() - t0
                wall, data = timed(folder, tmp / f"out_p{w}", cfg, ex)
            rows.append(("ProcessExecutor", "processes", w, start, wall, data))

        try:
            from distributed import LocalCluster
        except ImportError:
            LocalCluster = None
            print("  note: distributed is not installed: no Dask rows")
        for w in (1, 2) if LocalCluster is not None and not args.no_dask else ():
            warm_folder = make_folder(tmp / f"warm_d{w}", SCANS[1:2], w)
            t0 = time.perf_counter()
            with LocalCluster(n_workers=w, threads_per_worker=1, processes=True, dashboard_address=None,
                              host="127.0.0.1", silence_logs=logging.ERROR) as cluster, \
                    make_executor(cluster.scheduler_address) as ex:
                if ex.workers != w:
                    print(f"  note: the cluster reported {ex.workers} worker(s) at connection, not {w}")
                run_collection(warm_folder, tmp / f"warm_d{w}_out", cfg, executor=ex, say=quiet)
                start = time.perf_counter() - t0
                wall, data = timed(folder, tmp / f"out_d{w}", cfg, ex)
            rows.append(("DaskExecutor (LocalCluster)", "dask", w, start, wall, data))

        wall, data = timed(folder, tmp / "out_serial", cfg, SerialExecutor())
        rows.append(("re-run (cached)", "serial", 1, 0.0, wall, data))
        cached = sum(s.get("status", {}).get(k) == "cached" for s in data["scans"] for k in asked)

    errors = [(r["scan"], r["error"]) for _, _, _, _, _, dt in rows for r in dt["table"] if "error" in r]
    for scan, err in errors:
        print(f"  error on {scan}: {err}")
    print("  per scan (serial): " + "; ".join(
        f"{r['scan']} m {r['mass [kg]']:.4g} kg, uplift {r['weakest uplift [g]']:.3g} g, "
        f"overturning {r['pulses overturning, fixed']:.3g}" for r in ref["table"]
        if "error" not in r and Path(r["scan"]).stem.endswith("_1")))

    worst = print_speedup_table(rows, ref, max_diff, base_wall=rows[0][4], vs_label="vs serial",
                                diff_label="max rel diff")
    ok = worst == 0 and not errors
    print(f"\nidentical numbers: {'yes' if ok else 'no'}")
    print_throughput(rows, n_scans)
    print(f"re-run: {cached} of {n_scans * len(asked)} scan stages taken from the cache")
    print(f"load average before / after: {load0:.2f} / {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs "
          "(other jobs on the machine slow the 2-worker rows)")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
