"""2D against 3D over the design records on three bodies: the classification tables and the wall time
of ``statue2model run --stages all`` (issue #28's closing tables).

Bodies: the bundled default scan (dancing girl), a squat urn (benchmarks/verdict_scans.squat_urn: b/h
0.59, never lifts at the default hazard) and a slender tower made here (a 0.16 m x 0.16 m x 0.96 m
marble prism, b/h 1/6, units m). Each runs the whole pipeline but the prototype (``run --stages
all``, the default [crosscheck] settings: the exact isolator scene and the classification over the
design record set around the 2D fragility medians), then prints per body and base the rows of
crosscheck/classification.json - TP/FP/FN/TN, accuracy, precision and recall with 95 % intervals,
the 2D and 3D medians, the result - the 3D cost (runs, simulated s, wall s, simulated s per wall s)
and each stage's wall time.

    python benchmarks/bench_classification_bodies.py [--out DIR] [--workers N]   # ~4 min on 2 cores
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))


def slender_tower(path: Path) -> Path:
    import trimesh

    box = trimesh.creation.box(extents=(0.16, 0.16, 0.96))
    box.apply_translation((0, 0, 0.48))
    box.export(path)
    return path


def bodies(tmp: Path) -> dict:
    from verdict_scans import squat_urn

    return {"default scan (dancing girl)": (ROOT / "meshes" / "dancing_girl.ply", ""),
            "squat urn": (squat_urn(tmp / "squat_urn.stl"), '[scan]\nunits = "m"\ndensity = 2700\n'),
            "slender tower": (slender_tower(tmp / "tower.stl"), '[scan]\nunits = "m"\ndensity = 2650\n')}


def run(mesh: Path, extra: str, out: Path, workers: int | None) -> tuple[dict, float]:
    cfg = out.with_suffix(".toml")
    cfg.write_text(extra + "[prototype]\nenabled = false\n")
    cmd = [sys.executable, "-m", "statue2model", "run", str(mesh), "--config", str(cfg), "--out", str(out),
           "--stages", "params,isolator,dynamics,crosscheck"] + ([] if workers is None else ["--workers", str(workers)])
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise SystemExit(f"{mesh.name}: exit {proc.returncode}\n{proc.stderr[-2000:]}")
    return json.loads((out / "run.json").read_text()), wall


def _r(r: dict) -> str:
    return "n/a" if r.get("value") is None else f"{r['value']:.2f} [{r['lo']:.2f}-{r['hi']:.2f}]"


def table(name: str, out: Path, run_json: dict, wall: float) -> list[str]:
    cls = json.loads((out / "crosscheck" / "classification.json").read_text())
    lines = [f"\n## {name}", "",
             "| base | limit state | TP/FP/FN/TN | accuracy | precision | recall | 2D median g | 3D median g | result |",
             "|---|---|---|---|---|---|---|---|---|"]
    cost = []
    for base in ("fixed", "isolated"):
        c = cls.get(base)
        if c is None:
            continue
        for s, a in c["states"].items():
            f = c["fragility"].get(s, {})
            m2, m3 = (f.get(k, {}).get("median_g") for k in ("2d", "3d"))
            lines.append(f"| {base} | {s} | {a['tp']}/{a['fp']}/{a['fn']}/{a['tn']} | {_r(a['accuracy'])} | "
                         f"{_r(a['precision'])} | {_r(a['recall'])} | {'-' if m2 is None else f'{m2:.3f}'} | "
                         f"{'-' if m3 is None else f'{m3:.3f}'} | {a['status']} |")
        i = c["info"]
        sim, w3 = i.get("sim_time_3d_s") or 0.0, i.get("wall_time_3d_s") or 0.0
        cost.append(f"{base}: {i['n_runs']} runs ({i['n_records']} records x {len(i['levels_g'])} levels "
                    f"{', '.join(f'{x:.3f}' for x in i['levels_g'])} g; levels from "
                    f"{'; '.join(cls['levels_from'][base]['what'])}), {i['n_counted']} counted, 3D {sim:.0f} simulated s "
                    f"in {w3:.1f} s wall ({sim / w3 if w3 else 0:.0f} simulated s per wall s on {i['executor']})")
    whys = [f"{base} {s}: {a['why']}" for base in ("fixed", "isolated") if cls.get(base)
            for s, a in cls[base]["states"].items() if a["status"] == "missed"]
    st = run_json["stages"]
    times = ", ".join(f"{k} {v.get('seconds') or 0:.1f} s" for k, v in st.items()
                      if v.get("status") == "done")
    return lines + [""] + [f"- {c}" for c in cost] + [f"- missed, why: {w}" for w in whys] + \
        [f"- `run --stages params,isolator,dynamics,crosscheck` wall time {wall:.1f} s ({times})"]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=None)
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--only", default=None, help="run only the bodies whose name contains this")
    a = ap.parse_args()
    base = a.out or Path(tempfile.mkdtemp(prefix="cls_bodies_"))
    base.mkdir(parents=True, exist_ok=True)
    for name, (mesh, extra) in bodies(base).items():
        if a.only and a.only not in name:
            continue
        out = base / name.split(" ")[0]
        rj, wall = run(mesh, extra, out, a.workers)
        print("\n".join(table(name, out, rj, wall)), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
