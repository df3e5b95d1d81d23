"""Executors side by side: one stability spectrum run in this process (numba
threads, the default), serially, on local worker processes and on a Dask
LocalCluster, with 1 and 2 workers each.

    python3 benchmarks/bench_executor.py            # 800 x 800 grid, about 2 minutes on 2 cores
    python3 benchmarks/bench_executor.py --quick    # 150 x 150 grid, about 10 s
    python3 benchmarks/bench_executor.py --grid 400 --rtol 1e-10

Model: block A1 (Table 1), imperfect (alpha = 0.65, theta = 0.13 delta,
e from eq. 14), one-cosine pulse over 0.5-10 Hz x 0.01-1.5 g, rtol 1e-7.

Timing: wall time of one ``stability_spectrum`` call, best of ``--repeat``
(grid set-up, shipping the rows to the workers and back, assembly included).
The in-process "1" row sets numba to one thread. Excluded and shown apart in
"start s": numba's JIT compile / on-disk cache load (a warm-up spectrum in this
process first), and for processes and Dask the start of the pool / cluster
plus one small warm-up spectrum on it (each worker imports statue2model and
loads the cache). Every executor runs each task on one numba thread;
"speed-up" is against the 1-worker row of the same kind; "vs default" is the
wall time over that of the in-process default (all numba threads). The last
column is max |difference| of codes, theta_max/delta and impact counts
against the in-process result: it must be 0 (bit-identical).
"""
from __future__ import annotations

import argparse
import logging
import math
import os
import time

import numba
import numpy as np
from speedup_table import print_speedup_table

from statue2model.rocking import RockingModel
from statue2model.rocking.spectrum import stability_spectrum
from statue2model.compute.executors import DaskExecutor, ProcessExecutor, SerialExecutor
from statue2model.geometry.rocking_params import RockingParams

G = 9.81
A1 = RockingParams.rectangular_block(0.0384, 0.2000, 1.286)
E_A1 = 1 - 1.5 * math.sin(A1.delta_R) ** 2
MODEL = RockingModel.imperfect(A1, 0.65, 0.65, 0.13 * A1.delta_L, 0.13 * A1.delta_R, e_L=E_A1, e_R=E_A1)
WARM = (np.linspace(0.5, 10.0, 4), np.linspace(0.01, 1.5, 4) * G)


def run(freqs, amps, rtol, executor=None, repeat=1):
    """Best wall time (s) of ``repeat`` calls, and the spectrum."""
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        sp = stability_spectrum(MODEL, freqs, amps, rtol=rtol, executor=executor)
        best = min(best, time.perf_counter() - t0)
    return best, sp


def max_diff(sp, ref) -> float:
    return max(float(np.max(np.abs(getattr(sp, f).astype(float) - getattr(ref, f).astype(float))))
               for f in ("codes", "theta_max_over_delta", "n_impacts"))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="150 x 150 grid")
    ap.add_argument("--grid", type=int, default=None, help="N for an N x N grid (default 800, --quick 150)")
    ap.add_argument("--rtol", type=float, default=1e-7)
    ap.add_argument("--repeat", type=int, default=1, help="best of R calls per row (default 1)")
    args = ap.parse_args()
    n = args.grid or (150 if args.quick else 800)
    freqs = np.linspace(0.5, 10.0, n)
    amps = np.linspace(0.01, 1.5, n) * G
    threads = numba.get_num_threads()
    load0 = os.getloadavg()[0]

    t0 = time.perf_counter()
    stability_spectrum(MODEL, *WARM)
    print(f"{n} x {n} one-cosine spectrum of block A1 ({n * n:,} runs, rtol {args.rtol:g}, best of {args.repeat}); "
          f"JIT compile / cache load {time.perf_counter() - t0:.2f} s (excluded)")
    rows = []  # (executor, kind, workers, start s, wall s, spectrum)

    r = args.repeat
    wall, ref = run(freqs, amps, args.rtol, repeat=r)
    rows.append(("in-process threads (default)", "threads", threads, 0.0, wall, ref))
    print(f"  {ref.n_integrated:,} runs integrated, the rest below the uplift limit; outcomes {ref.counts()}")
    numba.set_num_threads(1)
    try:
        wall, sp = run(freqs, amps, args.rtol, repeat=r)
    finally:
        numba.set_num_threads(threads)
    rows.append(("in-process threads", "threads", 1, 0.0, wall, sp))

    wall, sp = run(freqs, amps, args.rtol, SerialExecutor(), r)
    rows.append(("SerialExecutor", "serial", 1, 0.0, wall, sp))

    for w in (1, 2):
        t0 = time.perf_counter()
        with ProcessExecutor(w) as ex:
            run(*WARM, args.rtol, ex)
            start = time.perf_counter() - t0
            wall, sp = run(freqs, amps, args.rtol, ex, r)
        rows.append(("ProcessExecutor", "processes", w, start, wall, sp))

    from distributed import LocalCluster

    for w in (1, 2):
        t0 = time.perf_counter()
        with LocalCluster(n_workers=w, threads_per_worker=1, processes=True, dashboard_address=None,
                          host="127.0.0.1", silence_logs=logging.ERROR) as cluster, \
                DaskExecutor(cluster.scheduler_address) as ex:
            run(*WARM, args.rtol, ex)
            start = time.perf_counter() - t0
            wall, sp = run(freqs, amps, args.rtol, ex, r)
        rows.append(("DaskExecutor (LocalCluster)", "dask", w, start, wall, sp))

    worst = print_speedup_table(rows, ref, max_diff, base_wall=rows[0][4], vs_label="vs default",
                                diff_label="max |diff|")
    print(f"\nbit-identical to the in-process result: {'yes' if worst == 0 else 'NO'}")
    print(f"load average before / after: {load0:.2f} / {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs "
          "(other jobs on the machine slow the 2-worker rows)")
    return 0 if worst == 0 else 1


if __name__ == "__main__":
    raise SystemExit(main())
