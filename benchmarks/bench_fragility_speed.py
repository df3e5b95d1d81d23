"""The fixed-base fragility study, today's code (a copy of HEAD) against the working tree, in one run.

The study of benchmarks/bench_fragility.py: 100 synthetic records of 20 s at dt 0.01 x 40 PGA levels
(0.05-1 g) x 50 parameter samples = 200 000 runs on a fixed base, for

* the thesis statue (imperfect model, Latin-hypercube samples of theta_R / delta_R, alpha_L,
  alpha_R), in this process's numba threads;
* the bundled default scan (Housner's model, 50 samples of e), on 2 processes (ProcessExecutor),
  as bench_fragility.py runs it, and in numba threads;
* and each body on records of 30 s that end at rest (the same 20 s records followed by 10 s of
  zeros): what a quiet tail costs.

Each row runs in a subprocess per code tree (``PYTHONPATH`` = the tree): the old tree is a git
worktree of ``--old-ref`` (default HEAD) at ``--old`` (default /tmp/frag_old, made with
``git worktree add`` when missing), the new one this script's checkout. The table gives,
per row, the old and new wall time of the fixed-base runs (FragilityResult.stats["wall_fixed_s"]),
their ratio, the new runs/s, the CPU seconds the study took (the process and its workers: other
jobs on a shared machine move them less than the wall time) and their ratio, whether the outcomes
(overturned or not, every run) are identical, the largest difference of the peak rotations |theta|
on either side (kernel S_QMAX_R, S_QMAX_L) and how many runs differ in any statistic of the kernel
(peaks, counts of steps and impacts, times: each run's whole statistics vector, compared to the
bit; they come from a second, untimed pass over the same runs: the new tree's own fixed-base
path, the old tree's replayed).

    python benchmarks/bench_fragility_speed.py [--quick] [--records N] [--rows thesis,scan,...]

``--quick``: 5 records (10 000 runs a row). Exit status 1 if any outcome differs. The machine may
be shared: the load average is printed before each row and at the end.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
NEW = HERE.parent
LEVELS, SAMPLES = 40, 50
ROWS = {   # name: (body, tail seconds of zeros, mode)
    "thesis": ("thesis", 0.0, "threads"),
    "scan": ("scan", 0.0, "processes"),
    "scan-threads": ("scan", 0.0, "threads"),
    "thesis-30s": ("thesis", 10.0, "threads"),
    "scan-30s": ("scan", 10.0, "processes"),
}
LABELS = {"thesis": "thesis statue", "scan": "default scan"}


# --- the worker: one tree, one row (runs in a subprocess, PYTHONPATH = the tree) -------------------
def inputs(body: str, n_records: int, tail: float, n_levels: int = LEVELS, n_samples: int = SAMPLES):
    """(model, records, levels, samples) of bench_fragility.py's study (public API of both trees)."""
    from statue2model.geometry.rocking_params import RockingParams
    from statue2model.hazard import motions
    from statue2model.rocking.model import RockingModel
    from statue2model.rocking.sampling import THESIS_THETA_R, latin_hypercube

    records = [motions.synthetic_record(20.0, 0.01, 1.0, seed=s) for s in range(n_records)]
    if tail > 0:
        records = [motions.record(np.r_[r.samples, np.zeros(int(round(tail / r.dt)))], r.dt, label=r.label + " + rest")
                   for r in records]
    levels = np.linspace(0.05, 1.0, n_levels) * 9.81
    if body == "thesis":
        p = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.8})
        model = RockingModel.imperfect(p, 0.159, 0.175, 4.55e-3, 4.55e-3)
        samples = latin_hypercube({"theta_R": tuple(x * p.delta_R for x in THESIS_THETA_R),
                                   "alpha_L": (0.143, 0.175), "alpha_R": (0.158, 0.193)}, n_samples, seed=0)
    else:
        from statue2model.geometry.body import load_body
        from statue2model.io.paths import default_scan

        model = RockingModel.housner(load_body(default_scan()).rocking(None))
        e0 = min(min(model.e_L.values), min(model.e_R.values))
        samples = latin_hypercube({"e": (0.9 * e0, min(1.0, 1.05 * e0))}, n_samples, seed=0)
    return model, records, levels, samples


def replay_stats(model, records, levels, samples, study, max_steps=20_000_000) -> np.ndarray:
    """(R, S, L, N_S): every fixed-base run's kernel statistics, the runs built as the fixed-base
    path of a tree without ``_fixed(keep_stats=True)`` builds them (one batch per restitution pair),
    through that tree's run_batch."""
    from statue2model.assessment.fragility import intensity
    from statue2model.rocking import kernel as K
    from statue2model.rocking.batch import run_batch

    models = samples.models(model)
    fac = samples.im_factors()
    ims = np.array([intensity(r, study.im) for r in records])
    gains = levels[None, :] / ims[:, None]
    R, L, S_n = len(records), levels.size, samples.n
    out = np.zeros((R, S_n, L, K.N_S))
    groups: dict = {}
    for s, m in enumerate(models):
        groups.setdefault((m.e_L, m.e_R), []).append(s)
    lims = np.array([m.uplift_limits for m in models])
    for r, rec in enumerate(records):
        kind, M0, smp = rec.kernel_args()
        hi, lo = rec.extremes()
        for idx in groups.values():
            ss = np.repeat(np.asarray(idx), L)
            ll = np.tile(np.arange(L), len(idx))
            g = gains[r, ll] * fac[ss]
            M = np.tile(M0, (ss.size, 1))
            M[:, K.MA] *= g
            quiet = (g * hi <= lims[ss, 0]) & (-g * lo <= lims[ss, 1])
            P = np.array([models[s].kernel_vector(early_exit="outcome") for s in ss])
            out[r, ss, ll] = run_batch(models[idx[0]], P, np.full(ss.size, kind), M, smp,
                                       np.full(ss.size, rec.end + study.free_time), rtol=study.rtol, quiet=quiet,
                                       max_steps=max_steps)
    return out


def cpu_seconds() -> float:
    """CPU seconds (user + system) of this process and its live children (the executor's workers):
    what a study costs the machine, less sensitive than wall time to other jobs on a shared one."""
    try:
        import psutil
    except ImportError:                                   # without psutil: this process only
        import resource

        r = resource.getrusage(resource.RUSAGE_SELF)
        return r.ru_utime + r.ru_stime
    me = psutil.Process()
    total = sum(me.cpu_times()[:2])
    for child in me.children(recursive=True):
        try:
            total += sum(child.cpu_times()[:2])
        except psutil.Error:
            pass
    return total


def worker(args) -> None:
    import logging

    logging.disable(logging.WARNING)
    import statue2model
    from statue2model.assessment import fragility as F
    from statue2model.compute.executors import ProcessExecutor

    study = F.FragilityStudy(n_boot=0)
    body, tail, mode = ROWS[args.row]
    inp = inputs(body, args.records, tail)
    warm = inputs(body, 4, tail, 2, 2)      # 4 records: a task for each process at least (kernels loaded)

    def run(ex):
        F.run_fragility(*warm, study, executor=ex)             # load the kernels (and start the workers)
        c0, t0 = cpu_seconds(), time.perf_counter()
        res = F.run_fragility(*inp, study, executor=ex)
        return res, time.perf_counter() - t0, cpu_seconds() - c0

    if mode == "processes":
        with ProcessExecutor(2) as ex:
            res, wall, cpu = run(ex)
    else:
        res, wall, cpu = run(None)
    out = {"tree": str(Path(statue2model.__file__).resolve().parent.parent), "fixed_s": res.stats["wall_fixed_s"],
           "wall_s": wall, "cpu_s": cpu, "runs": res.stats["runs_fixed"], "integrated": res.stats["integrated_fixed"]}
    arrays = {"fails": res.fails["overturning_fixed"], "valid": res.valid["fixed"]}
    if args.stats:
        model, records, levels, samples = inp
        try:                    # the tree's own fixed-base path, when it can return the statistics
            import inspect

            if "keep_stats" not in inspect.signature(F._fixed).parameters:
                raise TypeError
            ims = np.array([F.intensity(r, study.im) for r in records])
            *_, st = F._fixed(model, records, levels[None, :] / ims[:, None], samples, study, None, 20_000_000,
                              keep_stats=True)
            out["stats_from"] = "_fixed(keep_stats=True)"
        except TypeError:
            st = replay_stats(model, records, levels, samples, study)
            out["stats_from"] = "replayed per restitution pair"
        arrays["stats"] = st
    np.savez(args.out, **arrays)
    Path(args.out).with_suffix(".json").write_text(json.dumps(out))


# --- the driver ----------------------------------------------------------------------------------
def old_tree(path: Path, ref: str) -> str:
    """The old tree's commit; a worktree of ``ref`` is added at ``path`` when missing."""
    if not (path / "statue2model").is_dir():
        subprocess.run(["git", "-C", str(NEW), "worktree", "add", "--detach", str(path), ref], check=True,
                       stdout=subprocess.DEVNULL)
    return subprocess.run(["git", "-C", str(path), "rev-parse", "--short", "HEAD"], check=True,
                          capture_output=True, text=True).stdout.strip()


def measure(tree: Path, row: str, records: int, stats: bool, tmp: Path) -> tuple[dict, dict]:
    out = tmp / f"{row}-{tree.name}.npz"
    env = dict(os.environ, PYTHONPATH=str(tree), TQDM_DISABLE="1")
    cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", "--row", row, "--records", str(records),
           "--out", str(out)] + (["--stats"] if stats else [])
    p = subprocess.run(cmd, env=env, cwd=str(tree), capture_output=True, text=True)
    if p.returncode != 0:
        sys.stderr.write(p.stderr[-4000:])
        raise SystemExit(f"worker failed: {row} in {tree}")
    info = json.loads(out.with_suffix(".json").read_text())
    if Path(info["tree"]).resolve() != tree.resolve():
        raise SystemExit(f"the worker imported {info['tree']}, not {tree}")
    with np.load(out) as z:
        return info, {k: z[k] for k in z.files}


def compare(a: dict, b: dict) -> tuple[bool, float, int]:
    """(outcomes identical, max |peak difference| in rad, runs whose statistics differ (-1: not compared))."""
    same = np.array_equal(a["fails"], b["fails"]) and np.array_equal(a["valid"], b["valid"])
    if "stats" not in a or "stats" not in b:
        return same, float("nan"), -1
    from statue2model.rocking import kernel as K

    x, y = a["stats"], b["stats"]
    peaks = [K.S_QMAX_R, K.S_QMAX_L]
    dpeak = float(np.max(np.abs(x[..., peaks] - y[..., peaks]))) if x.size else 0.0
    eq = (x == y) | (np.isnan(x) & np.isnan(y))
    return same, dpeak, int((~eq.all(axis=-1)).sum())


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="5 records a row (10 000 runs)")
    ap.add_argument("--records", type=int, default=None, help="records a row (default 100)")
    ap.add_argument("--rows", default=",".join(ROWS), help=f"rows to run, of {', '.join(ROWS)}")
    ap.add_argument("--old", default="/tmp/frag_old", help="the old tree (a git worktree; made when missing)")
    ap.add_argument("--old-ref", default="HEAD", help="commit of the old tree when it is made")
    ap.add_argument("--no-stats", action="store_true", help="skip the untimed pass comparing every run's statistics")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--row", help=argparse.SUPPRESS)
    ap.add_argument("--out", help=argparse.SUPPRESS)
    ap.add_argument("--stats", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    args.records = args.records or (5 if args.quick else 100)
    if args.worker:
        worker(args)
        return 0
    rows = [r.strip() for r in args.rows.split(",") if r.strip()]
    bad = [r for r in rows if r not in ROWS]
    if bad:
        raise SystemExit(f"unknown rows {bad}; choose from {', '.join(ROWS)}")
    old = Path(args.old)
    commit = old_tree(old, args.old_ref)
    runs = args.records * LEVELS * SAMPLES
    print(f"old: {old} (commit {commit}); new: {NEW} (working tree)")
    print(f"{args.records} records x {LEVELS} levels x {SAMPLES} samples = {runs} runs a row; "
          f"{os.cpu_count()} CPUs; load average {os.getloadavg()[0]:.2f}", flush=True)
    ok = True
    table = []
    done_stats: set = set()
    with tempfile.TemporaryDirectory() as tmp:
        for row in rows:
            body, tail, mode = ROWS[row]
            key = (body, tail)
            stats = not args.no_stats and key not in done_stats       # peaks do not depend on the mode
            load = os.getloadavg()[0]
            io, ao = measure(old, row, args.records, stats, Path(tmp))
            inew, an = measure(NEW, row, args.records, stats, Path(tmp))
            same, dpeak, ndiff = compare(ao, an)
            if stats:
                done_stats.add(key)
            ok &= same
            table.append((row, body, tail, mode, io["fixed_s"], inew["fixed_s"], runs / inew["fixed_s"], same, dpeak,
                          ndiff, io["cpu_s"], inew["cpu_s"], load))
            print(f"  {row}: old {io['fixed_s']:.1f} s ({io['cpu_s']:.1f} s CPU), new {inew['fixed_s']:.1f} s "
                  f"({inew['cpu_s']:.1f} s CPU), load {load:.2f}{'' if same else '; OUTCOMES DIFFER'}", flush=True)
    print()
    print(f"{'body':<14} {'records':<20} {'mode':<11} {'old s':>6} {'new s':>6} {'ratio':>5} {'runs/s':>6} "
          f"{'CPU old':>7} {'new':>6} {'ratio':>5}  {'outcomes':<9} {'max peak diff':>13} {'runs differing':>14} "
          f"{'load':>5}")
    for (row, body, tail, mode, to, tn, rate, same, dpeak, ndiff, co, cn, load) in table:
        rec = "20 s" + (f" + {tail:g} s at rest" if tail else "")
        mode_s = "2 processes" if mode == "processes" else "threads"
        peak = "-" if not np.isfinite(dpeak) else f"{dpeak:.3g} rad"
        nd = "-" if ndiff < 0 else str(ndiff)
        print(f"{LABELS[body]:<14} {rec:<20} {mode_s:<11} {to:>6.1f} {tn:>6.1f} {to / tn:>5.2f} {rate:>6.0f} "
              f"{co:>7.1f} {cn:>6.1f} {co / cn:>5.2f}  {'identical' if same else 'DIFFER':<9} {peak:>13} {nd:>14} "
              f"{load:>5.2f}")
    for body in ("thesis", "scan"):
        base = [t for t in table if t[1] == body and t[2] == 0 and t[3] == ROWS[body][2]]
        tail = [t for t in table if t[1] == body and t[2] > 0]
        if base and tail:
            b, t = base[0], tail[0]
            print(f"{LABELS[body]}: records 50 % longer (10 s at rest) cost x{t[5] / b[5]:.2f} the wall time, "
                  f"x{t[11] / b[11]:.2f} the CPU time now (x{t[4] / b[4]:.2f}, x{t[10] / b[10]:.2f} before)")
    print(f"\noutcomes identical in every row: {'yes' if ok else 'NO'}; load average at the end "
          f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs (a shared machine: other jobs slow both trees)")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
