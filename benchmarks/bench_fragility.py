"""Throughput of a fragility study (assessment/fragility.py) and its scaling on 1 and 2 workers.

The study of issue [12]: the thesis' statue prototype (Table 24: h 0.3523, b_L 0.1995,
b_R 0.0805 m, m 12.074 kg, imperfect model alpha_L 0.159, alpha_R 0.175, theta 4.55e-3 rad)
on a fixed base, 100 synthetic 20 s records x 40 PGA levels (0.05 g..1 g) x 50 Latin-hypercube
samples of theta_R / delta_R in [1.78, 2.26]e-2 and alpha_L, alpha_R within +-10 % = 200 000 runs
(e is left at eq. 15; the default scan's study samples e: a record's runs of every sample go to
the kernel in one batch, each row with its own restitution table).

* The headlines: the whole study (``--records`` 100) for the bundled default scan (Housner's
  model, 50 samples of e, on 2 processes) and for the thesis statue (in this process, numba
  threads on every core), wall time and runs/s; ``--quick`` runs 5 records (10 000 runs, 1/20
  of it) and extrapolates, labelled as such; ``--body scan|thesis`` runs one of them.
* The scaling table: ``--scale-records`` records (default 5) on SerialExecutor (1 worker),
  ProcessExecutor(1), ProcessExecutor(2), a Dask LocalCluster of 1 and 2 workers (skipped
  without distributed), and in-process threads, each checked bit-identical to the first.

    python benchmarks/bench_fragility.py [--quick] [--records N] [--scale-records N] [--no-scaling]

Exit status 1 if any executor's outcomes differ. The machine may be shared: the load
average before and after is printed.
"""
from __future__ import annotations

import argparse
import logging
import os
import time

import numpy as np

from statue2model.compute.executors import DaskExecutor, ProcessExecutor, SerialExecutor
from statue2model.hazard import motions
from statue2model.assessment.fragility import FragilityStudy, run_fragility
from statue2model.rocking.model import RockingModel
from statue2model.rocking.sampling import THESIS_THETA_R, latin_hypercube
from statue2model.geometry.rocking_params import RockingParams

FULL = (100, 40, 50)


def study_inputs(n_records: int, n_levels: int = 40, n_samples: int = 50):
    p = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.8})
    model = RockingModel.imperfect(p, 0.159, 0.175, 4.55e-3, 4.55e-3)
    records = [motions.synthetic_record(20.0, 0.01, 1.0, seed=s) for s in range(n_records)]
    levels = np.linspace(0.05, 1.0, n_levels) * 9.81
    samples = latin_hypercube({"theta_R": tuple(x * p.delta_R for x in THESIS_THETA_R),
                               "alpha_L": (0.143, 0.175), "alpha_R": (0.158, 0.193)}, n_samples, seed=0)
    return model, records, levels, samples


def scan_inputs(n_records: int, n_levels: int = 40, n_samples: int = 50):
    """The bundled default scan (Housner's model, eq. 15's e) with 50 Latin-hypercube samples of e
    over 0.9-1.05 x the smaller of its e_L, e_R (a prototype test's uncertainty), same records and levels."""
    from statue2model.geometry.body import load_body
    from statue2model.io.paths import default_scan

    model = RockingModel.housner(load_body(default_scan()).rocking(None))
    e0 = min(min(model.e_L.values), min(model.e_R.values))
    records = [motions.synthetic_record(20.0, 0.01, 1.0, seed=s) for s in range(n_records)]
    levels = np.linspace(0.05, 1.0, n_levels) * 9.81
    samples = latin_hypercube({"e": (0.9 * e0, min(1.0, 1.05 * e0))}, n_samples, seed=0)
    return model, records, levels, samples


def scan_headline(n_rec: int) -> None:
    """The default scan's study on 2 processes (blocks of rows; in this process's numba threads it
    takes about as long: benchmarks/bench_fragility_speed.py)."""
    inputs = scan_inputs(n_rec)
    runs = n_rec * FULL[1] * FULL[2]
    with ProcessExecutor(2) as ex:
        timed(scan_inputs(4, 2, 2), ex)          # a task for each worker at least: both load the kernels
        res, fixed, _ = timed(inputs, ex)
    c = res.curves["overturning_fixed"]
    print(f"default scan (Housner, e sampled): {runs} runs ({res.stats['integrated_fixed']} integrated) on 2 processes: "
          f"{fixed:.1f} s, {runs / fixed:.0f} runs/s; median {c.median / 9.81:.3f} g, beta {c.beta:.3f}"
          + ("" if runs < 200_000 else f" (target 60 s: {'met' if fixed <= 60 else 'NOT met'})"))


def timed(inputs, executor=None):
    model, records, levels, samples = inputs
    t0 = time.perf_counter()
    res = run_fragility(model, records, levels, samples, FragilityStudy(n_boot=0), executor=executor)
    wall = time.perf_counter() - t0
    return res, res.stats["wall_fixed_s"], wall


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="5 records for the headline (1/20 of the study)")
    ap.add_argument("--records", type=int, default=None, help="records of the headline study (default 100)")
    ap.add_argument("--scale-records", type=int, default=5, help="records of each scaling run (default 5)")
    ap.add_argument("--no-scaling", action="store_true")
    ap.add_argument("--body", choices=("both", "thesis", "scan"), default="both",
                    help="headline body: the thesis statue (imperfect, the hard case), the default scan, or both")
    args = ap.parse_args()
    load0 = os.getloadavg()[0]
    n_rec = args.records or (5 if args.quick else FULL[0])
    runs = n_rec * FULL[1] * FULL[2]
    ok = True
    # warm-up: compile / load the kernels
    timed(study_inputs(1, 2, 2))

    if args.body in ("both", "scan"):
        scan_headline(n_rec)
    if args.body == "scan":
        return 0
    inputs = study_inputs(n_rec)
    res, fixed, wall = timed(inputs)
    n_int = res.stats["integrated_fixed"]
    c = res.curves["overturning_fixed"]
    print(f"headline: {n_rec} records x {FULL[1]} levels x {FULL[2]} samples = {runs} runs ({n_int} integrated), "
          f"in-process numba threads on {os.cpu_count()} CPUs")
    print(f"  runs {fixed:.1f} s, with the fit {wall:.1f} s: {runs / fixed:.0f} runs/s; "
          f"median {c.median / 9.81:.3f} g, beta {c.beta:.3f}")
    if runs < 200_000:
        print(f"  EXTRAPOLATED to the 200 000-run study at this throughput: {200_000 / (runs / fixed):.0f} s "
              f"(measured on {runs} runs, {runs / 200_000:.0%} of it)")
    else:
        print(f"  200 000-run study: {fixed:.1f} s measured (target 60 s: {'met' if fixed <= 60 else 'NOT met'})")

    if not args.no_scaling:
        sinputs = study_inputs(args.scale_records)
        srun = args.scale_records * FULL[1] * FULL[2]
        rows = []
        ref = None

        def add(name, workers, ex):
            nonlocal ref, ok
            timed(study_inputs(4, 2, 2), ex)                  # start the workers, load the kernels
            r, fx, _ = timed(sinputs, ex)
            same = True
            if ref is None:
                ref = r
            else:
                same = all(np.array_equal(r.fails[k], ref.fails[k]) for k in ref.fails)
                ok &= same
            rows.append((name, workers, fx, srun / fx, same))

        with SerialExecutor() as ex:
            add("SerialExecutor", 1, ex)
        for w in (1, 2):
            with ProcessExecutor(w) as ex:
                add("ProcessExecutor", w, ex)
        try:
            from distributed import LocalCluster
        except ImportError:
            print("distributed not installed: the Dask rows are skipped")
        else:
            for w in (1, 2):
                with LocalCluster(n_workers=w, threads_per_worker=1, processes=True, dashboard_address=None,
                                  host="127.0.0.1", silence_logs=logging.ERROR) as cluster, \
                        DaskExecutor(cluster.scheduler_address) as ex:
                    add("DaskExecutor (LocalCluster)", w, ex)
        add("in-process numba threads", os.cpu_count(), None)
        print(f"\nscaling: {args.scale_records} records x {FULL[1]} levels x {FULL[2]} samples = {srun} runs each")
        print(f"{'executor':<30} {'workers':>7} {'runs s':>8} {'runs/s':>8} {'vs serial':>9}  identical")
        base = rows[0][3]
        for name, w, fx, rate, same in rows:
            print(f"{name:<30} {w:>7} {fx:>8.2f} {rate:>8.0f} {rate / base:>9.2f}  {'yes' if same else 'NO'}")
        print(f"\nidentical outcomes on every executor: {'yes' if ok else 'NO'}")
    print(f"load average before / after: {load0:.2f} / {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs "
          "(a shared machine: other jobs slow the 2-worker rows)")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
