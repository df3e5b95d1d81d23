"""Benchmark: what the capacity check costs the isolated spectrum.

The statue of the isolated-spectrum example (a 1.286 kg block, b = 0.0384, h = 0.2 m)
on a three-groove isolator (R = 0.9 m, r = 9.5 mm, 15 kg top plate, mu = 0.0073),
one-cosine pulses on a 40 x 40 grid (0.25-5 Hz x 0.02-1 g), timed side by side:

  * before the capacity check (the code as it was, from a checkout given with
    ``--before DIR``, run in a subprocess with PYTHONPATH=DIR);
  * with the check and capacity = inf (nothing to find: must cost the same);
  * with a finite capacity (default 0.15 m: many points end early at the capacity).

Each is the best of ``--repeat`` runs after a warm-up (the numba compilation is not
timed). Printed: seconds per spectrum and the ratios to "before" (or to capacity = inf
when no checkout is given).

    python3 benchmarks/bench_capacity.py [--before /tmp/headwt] [--capacity 0.15] [--repeat 3] [--n 40]
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

CODE = r"""
import json, sys, time
import numpy as np
from statue2model.geometry.rocking_params import RockingParams
from statue2model.rocking import RockingModel
from statue2model.isolator.device import Isolator
from statue2model.isolator.sweeps import isolated_spectrum
n, repeat, cap = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
statue = RockingParams.rectangular_block(0.0384, 0.2, 1.286)
model = RockingModel.housner(statue)
kw = {} if cap == float("inf") else {"capacity": cap}
iso = Isolator(R=0.9, r=0.0095, M=statue.m + 15.0, mu=0.0073, **kw)
freqs, amps = np.linspace(0.25, 5.0, n), np.linspace(0.02, 1.0, n) * 9.81
isolated_spectrum(iso, model, freqs[:2], amps[-2:])          # compile
best, sp = float("inf"), None
for _ in range(repeat):
    t = time.perf_counter()
    sp = isolated_spectrum(iso, model, freqs, amps)
    best = min(best, time.perf_counter() - t)
codes = np.asarray(sp.codes)
print(json.dumps({"seconds": best, "counts": {int(c): int((codes == c).sum()) for c in np.unique(codes)}}))
"""


def run(pythonpath: str | None, n: int, repeat: int, cap: float) -> dict:
    env = dict(os.environ, NUMBA_NUM_THREADS="1")
    if pythonpath:
        env["PYTHONPATH"] = pythonpath
    out = subprocess.run([sys.executable, "-c", CODE, str(n), str(repeat), repr(cap)], env=env, check=True,
                         capture_output=True, text=True, cwd=pythonpath or None)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", metavar="DIR", help="a checkout of the code before the capacity check")
    ap.add_argument("--capacity", type=float, default=0.15, help="the finite capacity, m (default 0.15)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--n", type=int, default=40, help="grid size n x n (default 40)")
    args = ap.parse_args()
    here = str(Path(__file__).resolve().parents[1])
    rows = []
    if args.before:
        rows.append(("before the check", run(args.before, args.n, args.repeat, float("inf"))))
    rows.append(("capacity = inf", run(here, args.n, args.repeat, float("inf"))))
    rows.append((f"capacity = {args.capacity:g} m", run(here, args.n, args.repeat, args.capacity)))
    base = rows[0][1]["seconds"]
    print(f"isolated spectrum, {args.n} x {args.n} one-cosine pulses, best of {args.repeat}, one numba thread")
    print(f"  {'':<22}{'seconds':>9}{'ratio':>8}   outcome counts (code: n; -3 capacity exceeded, -1 failed)")
    for name, r in rows:
        print(f"  {name:<22}{r['seconds']:>9.3f}{r['seconds'] / base:>8.3f}   {r['counts']}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
