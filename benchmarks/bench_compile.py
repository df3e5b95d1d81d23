"""Benchmark: the numba kernels cold (nothing cached) and warm (loaded from the cache), side by side.

Each column is a fresh Python process whose NUMBA_CACHE_DIR is one empty temporary
folder: the first process finds nothing and compiles (cold), the next ones load what
it cached (warm). Each process times

* import:  statue2model's dynamics, isolator and compile modules (numba, scipy, numpy);
* warm_up: statue2model.compute.compile.warm_up, i.e. compile (cold) or load (warm)
  the six kernel entry points; cold, in up to ``--workers`` processes at once;
* rocking: one 5 s pulse history (engine.simulate) and a 6 x 6 stability spectrum;
* plate:   the Coulomb and the Bouc-Wen plate under a 10 s synthetic record;
* coupled: plate + statue (Coulomb, no screening) under the same record;

and the whole process (interpreter start included) from outside, wall and CPU
seconds (CPU counts the compiling processes too). Every kernel must show one
signature and the warm processes no compilation (checked, exit status 1 if not).

    python3 benchmarks/bench_compile.py [--workers N] [--serial] [--warm-runs K]

``--serial`` adds a cold column compiled in one process (``--workers 1``).
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import json, sys, time
t0 = time.perf_counter()
import numpy as np
from statue2model.compute import compile as C
from statue2model.hazard import motions
from statue2model.rocking.engine import simulate as rock
from statue2model.rocking.model import RockingModel
from statue2model.rocking.spectrum import stability_spectrum
from statue2model.geometry.rocking_params import RockingParams
from statue2model.isolator.coupled import simulate_coupled
from statue2model.isolator.device import Isolator
from statue2model.isolator.time_history import simulate as plate
t = {"import": time.perf_counter() - t0}
workers = int(sys.argv[1])
t0 = time.perf_counter()
r = C.warm_up(progress=None, workers=workers)
t["warm_up"] = time.perf_counter() - t0
t["compiled"] = sum(k["compiled"] for k in r["kernels"].values())
G = 9.81
model = RockingModel.imperfect(RockingParams.rectangular_block(b=0.05, h=0.25, m=10.0), alpha_L=0.7,
                               alpha_R=0.8, e_L=0.9, e_R=0.9)
rec = motions.synthetic_record(duration=10.0, dt=0.01, pga=0.3 * G, seed=1)
t0 = time.perf_counter()
rock(model, motions.sine_pulse(0.4 * G, 2.0), t_end=5.0, dt_out=0.01)
stability_spectrum(model, np.linspace(0.5, 3.0, 6), np.linspace(0.1, 1.0, 6) * G)
t["rocking"] = time.perf_counter() - t0
t0 = time.perf_counter()
for kind in ("coulomb", "boucwen"):
    plate(Isolator(R=0.30, r=0.0183, M=15.0, mu=0.01, model=kind), rec, dt_out=0.01)
t["plate"] = time.perf_counter() - t0
t0 = time.perf_counter()
simulate_coupled(Isolator(R=0.30, r=0.0183, M=15.0, mu=0.01), model, rec, dt_out=0.01, screen=False)
t["coupled"] = time.perf_counter() - t0
t["max_signatures"] = max(len(s["signatures"]) for s in C.kernel_stats().values())
print(json.dumps(t))
"""

ROWS = ("import", "warm_up", "rocking", "plate", "coupled")


def run_child(cache_dir: str, workers: int) -> dict:
    path = os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH")) if p)
    env = dict(os.environ, NUMBA_CACHE_DIR=cache_dir, PYTHONPATH=path)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", CHILD, str(workers)], check=False, env=env, capture_output=True,
                         text=True, cwd=tempfile.gettempdir())
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode != 0:
        sys.exit(f"the benchmark process failed:\n{out.stderr}")
    res = json.loads(out.stdout.strip().splitlines()[-1])
    res["process wall"] = wall
    res["process CPU"] = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return res


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=None, help="compiling processes when cold (default: the cores, "
                                                              "at most 3, as warm_up)")
    ap.add_argument("--serial", action="store_true", help="also a cold column compiled in one process")
    ap.add_argument("--warm-runs", type=int, default=2, help="warm processes (the best is shown)")
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT))
    from statue2model.compute.compile import _workers

    workers = _workers(args.workers)
    cols = {}
    if args.serial:
        with tempfile.TemporaryDirectory(prefix="s2m-numba-") as d:
            cols["cold, 1 process"] = run_child(d, 1)
    with tempfile.TemporaryDirectory(prefix="s2m-numba-") as d:
        cold = run_child(d, workers)
        warm = [run_child(d, workers) for _ in range(max(1, args.warm_runs))]
    cols[f"cold, {workers} proc."] = cold
    best = {k: min(w[k] for w in warm) for k in warm[0]}
    best["compiled"] = max(w["compiled"] for w in warm)
    best["max_signatures"] = max(w["max_signatures"] for w in warm)
    cols["warm"] = best

    names = list(cols)
    w0 = 14
    print(f"numba kernels, cold vs warm (python {sys.version.split()[0]}, {os.cpu_count()} CPUs, "
          f"load average {os.getloadavg()[0]:.1f})")
    print(f"{'':<{w0}}" + "".join(f"{n:>17}" for n in names) + f"{'cold / warm':>13}")
    for row in (*ROWS, "process wall", "process CPU"):
        cells = "".join(f"{cols[n][row]:>15.2f} s" for n in names)
        ratio = cold[row] / best[row] if best[row] > 0 else float("inf")
        print(f"{row:<{w0}}{cells}{ratio:>12.1f}x")
    print(f"{'signatures':<{w0}}" + "".join(f"{cols[n]['max_signatures']:>17d}" for n in names)
          + "   (most of one kernel)")
    print(f"{'compiled':<{w0}}" + "".join(f"{cols[n]['compiled']:>17d}" for n in names)
          + "   (kernels compiled by warm_up, of 6)")
    ok = best["compiled"] == 0 and all(c["max_signatures"] == 1 for c in cols.values())
    print("check: one signature per kernel, nothing compiled when warm:", "yes" if ok else "NO")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
