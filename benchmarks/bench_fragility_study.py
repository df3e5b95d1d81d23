"""The dynamics stage's fragility study (assessment/study.run_study), today's code (a copy of HEAD)
against the working tree, on the same inputs, in one run.

The inputs come from a finished ``statue2model run`` folder (``--run DIR``): its design record set
(``dynamics/records``, read by hazard.matching.read_record_set), its isolator design
(``isolator/design.json``, when it passed) and its model (``dynamics/fragility.json``'s model: the
rocking parameters, Housner's model or the imperfect one with its alpha and theta). Each tree runs
``run_study(model, iso, target, records, "auto", SAMPLES, 1e-7)`` (the call both trees share: the
new tree then samples theta_R / e / alpha / the friction bounds and adds adaptive levels, the old one
the theta_R grid or nothing) in a subprocess (``PYTHONPATH`` = the tree), once to warm up and
``--repeat`` times timed (the best is kept), in this process's numba threads. The old tree is a git
worktree of ``--old-ref`` (default HEAD) at ``--old`` (made with ``git worktree add`` when missing).

The table: per tree the study's wall time, the runs on each base, the levels each base ran and the
curves; then the ratio new / old (the issue's budget: about 1.5).

    python benchmarks/bench_fragility_study.py --run /tmp/me/run [--repeat 3] [--samples 7]
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

HERE = Path(__file__).resolve().parent
NEW = HERE.parent


def worker(args) -> None:
    import logging

    logging.disable(logging.WARNING)
    import numpy as np

    import statue2model
    from statue2model.assessment import study as S
    from statue2model.geometry.rocking_params import RockingParams
    from statue2model.hazard.matching import read_record_set
    from statue2model.rocking.model import RockingModel

    run = Path(args.run)
    recs, _ = read_record_set(run / "dynamics" / "records")
    fj = json.loads((run / "dynamics" / "fragility.json").read_text())
    md = fj["model"]
    params = RockingParams.from_dict({k: md["params"][k] for k in ("m", "h", "b_L", "b_R", "I_G")})
    if md["model"] == "housner":
        model = RockingModel.housner(params, md["e_L"], md["e_R"])
    else:
        model = RockingModel.imperfect(params, md["alpha_L"], md["alpha_R"], md["theta_L"], md["theta_R"],
                                       md["e_L"], md["e_R"])
    iso = None
    dj = run / "isolator" / "design.json"
    if dj.exists() and json.loads(dj.read_text()).get("passed"):
        from statue2model.isolator.device import isolator_from_design

        iso = isolator_from_design(json.loads(dj.read_text()))
    stage = run / "dynamics" / "stage.json"
    data = json.loads(stage.read_text()).get("data", {}) if stage.exists() else {}
    pga = float(data.get("fragility_design_pga") or args.pga)

    class Target:
        def Se(self, T):
            return np.full(np.shape(T), pga)

    class Records:
        records = recs

        def check(self):
            return {"met": True}

    S.run_study(model, iso, Target(), Records(), "auto", args.samples, 1e-7)          # warm up (compile, import)
    best, res = float("inf"), None
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        r = S.run_study(model, iso, Target(), Records(), "auto", args.samples, 1e-7)
        dt = time.perf_counter() - t0
        if dt < best:
            best, res = dt, r.result
    ran = getattr(res, "ran", None)
    levels = {side: int(ran[side].sum()) if ran else int(res.levels.size) for side in res.valid}
    st = res.stats
    out = {"tree": str(Path(statue2model.__file__).resolve().parent.parent), "wall_s": best,
           "runs_fixed": st.get("runs_fixed"), "runs_isolated": st.get("runs_isolated", 0),
           "fixed_s": st.get("wall_fixed_s"), "isolated_s": st.get("wall_isolated_s", 0.0),
           "levels": levels, "curves": sorted(res.curves), "samples": res.samples.n, "isolator": iso is not None}
    Path(args.out).write_text(json.dumps(out))


def old_tree(path: Path, ref: str) -> str:
    """The old tree's commit (bench_fragility_speed.old_tree: a worktree of ``ref`` at ``path``)."""
    sys.path.insert(0, str(HERE))
    from bench_fragility_speed import old_tree as make

    return make(path, ref)


def measure(tree: Path, args, tmp: Path) -> dict:
    out = tmp / f"{tree.name}.json"
    env = dict(os.environ, PYTHONPATH=str(tree), TQDM_DISABLE="1")
    cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", "--run", args.run, "--out", str(out),
           "--repeat", str(args.repeat), "--samples", str(args.samples), "--pga", str(args.pga)]
    p = subprocess.run(cmd, env=env, cwd=str(tree), capture_output=True, text=True)
    if p.returncode != 0:
        sys.stderr.write(p.stderr[-4000:])
        raise SystemExit(f"worker failed in {tree}")
    info = json.loads(out.read_text())
    if Path(info["tree"]).resolve() != tree.resolve():
        raise SystemExit(f"the worker imported {info['tree']}, not {tree}")
    return info


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--run", required=True, help="a finished `statue2model run` folder (its records, design, model)")
    ap.add_argument("--repeat", type=int, default=3, help="timed repeats (the best is kept)")
    ap.add_argument("--samples", type=int, default=7, help="fragility_samples")
    ap.add_argument("--pga", type=float, default=0.287 * 9.81, help="design PGA m/s^2 when the run does not say")
    ap.add_argument("--old", default="/tmp/frag_study_old", help="the old tree (a git worktree; made when missing)")
    ap.add_argument("--old-ref", default="HEAD", help="commit of the old tree when it is made")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--out", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        worker(args)
        return 0
    commit = old_tree(Path(args.old), args.old_ref)
    print(f"old: {args.old} (commit {commit}); new: {NEW} (working tree); run {args.run}; "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        rows = [("old", measure(Path(args.old), args, Path(tmp))), ("new", measure(NEW, args, Path(tmp)))]
    print(f"\n{'tree':<5} {'study s':>8} {'fixed s':>8} {'iso s':>7} {'runs fixed':>10} {'runs iso':>9} "
          f"{'levels fixed/iso':>16} {'samples':>7}  curves")
    for name, r in rows:
        lv = "/".join(str(r["levels"].get(s, 0)) for s in ("fixed", "isolated"))
        print(f"{name:<5} {r['wall_s']:>8.2f} {r['fixed_s']:>8.2f} {r['isolated_s']:>7.2f} {r['runs_fixed']:>10} "
              f"{r['runs_isolated']:>9} {lv:>16} {r['samples']:>7}  {', '.join(r['curves'])}")
    o, n = rows[0][1], rows[1][1]
    print(f"\nratio new / old: study {n['wall_s'] / o['wall_s']:.2f}, runs fixed "
          f"{n['runs_fixed'] / max(o['runs_fixed'], 1):.1f}, runs isolated "
          f"{(n['runs_isolated'] or 0) / max(o['runs_isolated'] or 0, 1):.1f}; load average at the end "
          f"{os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
