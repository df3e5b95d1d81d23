"""Speed of the 3D scenes (PyBullet), old code against new, side by side in one run (issue [23], item 1).

    python3 benchmarks/bench_3d_scenes.py [--design isolator/design.json] [--old-rev 854e6ff]
                                          [--old-tree DIR] [--repeat 3] [--scenes a,b,...]

Two worker processes, one importing statue2model from an old tree (``--old-tree``, else ``git archive``
of ``--old-rev`` into a temporary directory), one from this tree, run the same scenes turn about (old,
new, old, new, ...), each run timed by its worker's process CPU time around the one call (set-up,
engine steps and the histories). Per scene: simulated s, CPU s old / new (the least of ``--repeat``
runs after one untimed warm-up run), the real-time factors (simulated s per CPU s), their ratio, and
the outputs' peaks old against new (the largest relative difference of the scene's peak values).

Scenes: the default scan (meshes/dancing_girl.ply) in its weakest direction, the pipeline's isolator
design for it (``statue2model run --stages isolator``, made in a temporary directory unless --design is
given); the quick cross-check's cases (``statue2model crosscheck ... --quick``: free rocking 2 s, the
one-sine pulses 0.8 / 1.25 x the 2D overturning amplitude at 1.5 Hz + 1.5 s, the record
synthetic:duration=8,pga=0.2g,seed=1 + 1 s, on the floor, and on the exact isolator: the plate alone,
the statue fixed to it, the statue free-standing); the campaign scene of [20] (validate.predict_3d: the
statue on the floor under a 20 s record at 0.3 g + the default 5 s); the statue on a 1 m pedestal
(stack scene, the same record as the quick cross-check's).
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

ROOT = Path(__file__).resolve().parents[1]
SCENES = ("free rocking", "pulse 0.8", "pulse 1.25", "record", "plate alone", "statue rigid on plate",
          "statue free on plate", "campaign test", "stack")


# ---------------------------------------------------------------- worker (runs in either tree) --
def _worker(design_path: str, mesh: str) -> None:
    import math

    from statue2model.crosscheck.boundary import overturn_amplitude_2d
    from statue2model.crosscheck.pendulum_scene import PendulumIsolator, simulate_pendulum
    from statue2model.crosscheck.stack_scene import StackScene, simulate_stack_3d
    from statue2model.crosscheck.statue_scene import StatueScene, simulate_statue
    from statue2model.geometry.body import load_body
    from statue2model.hazard import motions
    from statue2model.rocking import RockingModel

    sc = StatueScene.from_body(load_body(mesh))
    p = sc.params
    iso = PendulumIsolator.from_design(json.loads(Path(design_path).read_text()), statue=sc)
    a_ot = overturn_amplitude_2d(RockingModel.housner(p), 1.5)
    rec = motions.parse_spec("synthetic:duration=8,pga=0.2g,seed=1")[0]
    lab = motions.parse_spec("synthetic:duration=20,pga=0.3g,seed=2")[0]
    stack = StackScene.box(sc, width=0.8, depth=0.8, height=1.0, mass=400.0)

    def statue(r):
        return r.steps * r.settings.dt, {"theta_max_L": r.theta_max_L, "theta_max_R": r.theta_max_R,
                                         "overturned": float(r.overturned), "max_yaw": float(abs(r.yaw).max()),
                                         "uplift_time": r.uplift_time if r.uplift_time is not None else -1.0}

    def plate(r):
        out = {"u_max": r.u_max, "acc_abs_max": r.acc_abs_max}
        if r.theta is not None:
            out["theta_max"] = float(abs(r.theta).max(initial=0.0))
            out["overturned"] = float(r.statue_overturned)
        return r.steps * r.settings.dt, out

    def stacked(r):
        return r.steps * r.settings.dt, {"statue_theta_max": r.statue.theta_max,
                                         "pedestal_theta_max": r.pedestal.theta_max,
                                         "statue_overturned": float(r.statue.overturned)}

    runs = {
        "free rocking": lambda: statue(simulate_statue(sc, motions.free(), theta0=0.5 * p.delta_R, t_end=2.0)),
        "pulse 0.8": lambda: statue(simulate_statue(sc, motions.sine_pulse(0.8 * a_ot, 1.5), free_time=1.5)),
        "pulse 1.25": lambda: statue(simulate_statue(sc, motions.sine_pulse(1.25 * a_ot, 1.5), free_time=1.5)),
        "record": lambda: statue(simulate_statue(sc, rec, free_time=1.0)),
        "plate alone": lambda: plate(simulate_pendulum(iso, motions.free(), u0=0.5 * iso.travel_capacity,
                                                       t_end=3.0)),
        "statue rigid on plate": lambda: plate(simulate_pendulum(iso, rec, sc, mount="rigid", free_time=1.0)),
        "statue free on plate": lambda: plate(simulate_pendulum(iso, rec, sc, free_time=1.0)),
        "campaign test": lambda: statue(simulate_statue(sc, lab)),
        "stack": lambda: stacked(simulate_stack_3d(stack, rec, free_time=1.0)),
    }
    print("ready", flush=True)
    for line in sys.stdin:
        name = line.strip()
        c0 = time.process_time()
        sim, peaks = runs[name]()
        cpu = time.process_time() - c0
        peaks = {k: (v if math.isfinite(v) else None) for k, v in peaks.items()}
        print(json.dumps({"sim": sim, "cpu": cpu, "peaks": peaks}), flush=True)


# ---------------------------------------------------------------- driver --
class Worker:
    def __init__(self, tree: Path, design: str, mesh: str):
        env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
        self.proc = subprocess.Popen([sys.executable, str(Path(__file__).resolve()), "--worker", design, mesh],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, env=env,
                                     cwd=str(tree))
        line = self.proc.stdout.readline()
        while line and line.strip() != "ready":      # (the engine's build banner)
            line = self.proc.stdout.readline()
        if not line:
            raise SystemExit(f"worker in {tree} did not start")

    def run(self, name: str) -> dict:
        self.proc.stdin.write(name + "\n")
        self.proc.stdin.flush()
        while True:
            line = self.proc.stdout.readline()
            if not line:
                raise SystemExit(f"worker died on {name}")
            if line.startswith("{"):
                return json.loads(line)

    def close(self):
        self.proc.stdin.close()
        self.proc.wait()


def old_tree(rev: str) -> Path:
    out = Path(tempfile.mkdtemp(prefix="s2m_old_"))
    arch = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "statue2model", "meshes"], check=True,
                          capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(out)], input=arch, check=True)
    return out


def design_json(path: str | None) -> str:
    if path:
        return str(Path(path).resolve())
    out = Path(tempfile.mkdtemp(prefix="s2m_3d_")) / "run"
    subprocess.run([sys.executable, "-m", "statue2model", "run", str(ROOT / "meshes" / "dancing_girl.ply"),
                    "--stages", "isolator", "--out", str(out)], check=True, stdout=subprocess.DEVNULL,
                   env=dict(os.environ, PYTHONPATH=str(ROOT)))
    return str(out / "isolator" / "design.json")


ANGLE_FLOOR = 1e-3
"""rad: rotations below it are the contact solver's compliance (a statue that does not lift reads
~1e-5 rad), so an angle's difference is taken relative to max(|old|, ANGLE_FLOOR)."""


def peak_diff(a: dict, b: dict) -> tuple[float, str]:
    """Largest relative difference of the peaks b against a (and its name); angles (theta, yaw) relative
    to at least ANGLE_FLOOR."""
    worst, name = 0.0, "-"
    for k, va in a.items():
        vb = b.get(k)
        if va is None or vb is None:
            continue
        floor = ANGLE_FLOOR if ("theta" in k or "yaw" in k) else 1e-12
        d = abs(vb - va) / max(abs(va), floor) if va != vb else 0.0
        if d > worst or name == "-":
            worst, name = d, k
    return worst, name


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--design", help="isolator/design.json of a pipeline run (default: made now)")
    ap.add_argument("--old-rev", default="854e6ff", help="the old code's commit (default 854e6ff)")
    ap.add_argument("--old-tree", help="a checkout of the old code (default: git archive of --old-rev)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--scenes", help="comma-separated subset of: " + ", ".join(SCENES))
    a = ap.parse_args(argv)
    scenes = SCENES if not a.scenes else tuple(s.strip() for s in a.scenes.split(","))
    design = design_json(a.design)
    mesh = str(ROOT / "meshes" / "dancing_girl.ply")
    old = Worker(Path(a.old_tree) if a.old_tree else old_tree(a.old_rev), design, mesh)
    new = Worker(ROOT, design, mesh)
    best = {s: {"old": None, "new": None} for s in scenes}
    for s in scenes:                                 # warm-up: kernels, client, caches
        old.run(s)
        new.run(s)
    for _ in range(a.repeat):
        for s in scenes:
            for tag, w in (("old", old), ("new", new)):
                r = w.run(s)
                if best[s][tag] is None or r["cpu"] < best[s][tag]["cpu"]:
                    best[s][tag] = r
    old.close()
    new.close()
    print(f"3D scenes, old ({a.old_rev}) vs new, one run, best of {a.repeat} (process CPU s of the call); "
          f"load {os.getloadavg()[0]:.1f}")
    print("| scene | simulated s old / new | CPU s old | CPU s new | x real time old | x real time new | "
          "ratio | peaks: largest difference new vs old |")
    print("|---|---|---|---|---|---|---|---|")
    for s in scenes:
        o, n = best[s]["old"], best[s]["new"]
        xo, xn = o["sim"] / o["cpu"], n["sim"] / n["cpu"]
        d, k = peak_diff(o["peaks"], n["peaks"])
        print(f"| {s} | {o['sim']:.2f} / {n['sim']:.2f} | {o['cpu']:.3f} | {n['cpu']:.3f} | {xo:.1f} | {xn:.1f} | "
              f"{xn / xo:.2f} | {100 * d:.2f} % ({k}) |")
    print("peaks old -> new:")
    for s in scenes:
        o, n = best[s]["old"]["peaks"], best[s]["new"]["peaks"]
        print(f"  {s}: " + ", ".join(f"{k} {o[k]:.4g} -> {n[k]:.4g}" if o[k] is not None and n[k] is not None
                                     else f"{k} {o[k]} -> {n[k]}" for k in o))


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--worker":
        _worker(sys.argv[2], sys.argv[3])
    else:
        main()
