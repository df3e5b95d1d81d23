"""The verdict on several bodies and two sweep grids, side by side (issue #27's closing tables).

Runs ``statue2model run`` (prototype stage off) on the bundled default scan, Maria, Nefertiti and a
squat urn made here (a 0.40 m square plinth 0.10 m high under a 0.14 m x 0.70 m cylinder, units m,
density 2700 kg/m^3: b/h 0.59, it never lifts at the default hazard), each with two sweep grids of
the [dynamics] section (A: the default pulse grids, pga 0.05g:1.2g:24; B: freq 0.3:12:50,
amp 0.01g:1.5g:50, pga 0.02g:2.0g:45), and prints per body: the limit states at the design level,
the isolator with its time-history margins, the fragility per limit state, the recommendation; then
whether grids A and B gave the same verdict (they must: the sweeps are illustrations).

    python benchmarks/verdict_scans.py [--out DIR]      # about 80 s on 2 cores
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
G = 9.80665
GRIDS = {"A": '[dynamics]\npga = "0.05g:1.2g:24"\n',
         "B": '[dynamics]\nfreq = "0.3:12:50"\namp = "0.01g:1.5g:50"\npga = "0.02g:2.0g:45"\n'}


def squat_urn(path: Path) -> Path:
    import trimesh

    plinth = trimesh.creation.box(extents=(0.40, 0.40, 0.10))
    plinth.apply_translation((0, 0, 0.05))
    body = trimesh.creation.cylinder(radius=0.14, height=0.70, sections=64)
    body.apply_translation((0, 0, 0.45))
    trimesh.boolean.union([plinth, body], engine="manifold").export(path)
    return path


def bodies(tmp: Path) -> dict:
    return {"default (dancing girl)": (ROOT / "meshes" / "dancing_girl.ply", ""),
            "Maria": (ROOT / "meshes" / "maria_barjatinskaja.ply", ""),
            "Nefertiti": (ROOT / "meshes" / "nefertiti_bust.obj", ""),
            "squat urn": (squat_urn(tmp / "squat_urn.stl"), '[scan]\nunits = "m"\ndensity = 2700\n')}


def run(mesh: Path, extra: str, grid: str, out: Path) -> dict:
    cfg = out.with_suffix(".toml")
    cfg.write_text(extra + GRIDS[grid] + "[prototype]\nenabled = false\n")
    proc = subprocess.run([sys.executable, "-m", "statue2model", "run", str(mesh), "--config", str(cfg),
                           "--out", str(out)], capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        raise SystemExit(f"{mesh.name} ({grid}): exit {proc.returncode}\n{proc.stderr[-2000:]}")
    r = json.loads((out / "run.json").read_text())
    d = json.loads((out / "isolator" / "design.json").read_text())
    return {"verdict": r["verdict"], "design": d, "dyn": r["stages"]["dynamics"]["data"]}


def _q(x, unit):
    if x is None:
        return "-"
    return f"{x / G:.3f} g" if unit == "m/s^2" else f"{x * 1000:.0f} mm" if unit == "m" else \
        f"{x:.0f} N" if unit == "N" else f"{x:.3g}"


def show(name: str, res: dict) -> None:
    v, d, dyn = res["verdict"], res["design"], res["dyn"]
    print(f"\n### {name}\n\n| base | limit state | demand | capacity | ratio | exceeded (records) |\n|---|---|---|---|---|---|")
    for r in v["limit_states"]["rows"]:
        ratio = "-" if r["ratio"] is None else f"{r['ratio']:.3g}"
        print(f"| {r['base']} | {r['name']} | {_q(r['demand'], r['unit'])} | {_q(r['capacity'], r['unit'])} | "
              f"{ratio} | {r['exceeded']} ({r['n_exceeding']}) |")
    m = d.get("th_margins") or {}
    print(f"\nisolator: R {d['R']} m, r {d['r'] * 1000:g} mm, {d['n_grooves']} grooves, T {d['T']:.2f} s, "
          f"side {d['side']:.3f} m, passed {d['passed']}; time-history margins travel {m.get('travel')}, "
          f"acceleration {m.get('acceleration')}, bearing {m.get('bearing')}")
    if d.get("what_would_pass"):
        print(f"what would pass: {d['what_would_pass']['text']}")
    print("\n| limit state | base | median | band | beta | P at the design PGA |\n|---|---|---|---|---|---|")
    for ls, sides in (dyn.get("fragility_limit_states") or {}).items():
        for side, c in sides.items():
            med, ci = c.get("median"), c.get("median_ci") or [None, None]
            band = "-" if None in ci else f"{ci[0] / G:.3f}-{ci[1] / G:.3f} g"
            p = c.get("p_design")
            print(f"| {ls} | {side} | {'-' if med is None else f'{med / G:.3f} g'} | {band} | "
                  f"{'-' if c.get('beta') is None else format(c['beta'], '.3f')} | "
                  f"{format(p, '.3g') if p is not None else c.get('p_design_reason')} |")
    print(f"\nrecommendation ({v['status']}): {v['recommendation']}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", help="keep the run folders here (default: a temporary folder)")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as t:
        tmp = Path(args.out or t)
        tmp.mkdir(parents=True, exist_ok=True)
        same = []
        for name, (mesh, extra) in bodies(tmp).items():
            a, b = (run(mesh, extra, g, tmp / f"{mesh.stem}_{g}") for g in "AB")
            show(name, a)
            keys = lambda r: (r["verdict"]["recommendation"], r["verdict"]["status"],  # noqa: E731
                              r["verdict"]["limit_states"]["rows"], r["design"]["th_margins"],
                              r["dyn"].get("fragility_limit_states"))
            same.append((name, keys(a) == keys(b), a["verdict"]["fixed"].get("first_overturn_pga"),
                         b["verdict"]["fixed"].get("first_overturn_pga")))
        print("\n| body | grid A = grid B (recommendation, limit states, margins, fragility) | sweep's first "
              "overturning PGA A / B |\n|---|---|---|")
        for name, ok, fa, fb in same:
            f = lambda x: "-" if x is None else f"{x / G:.3f} g"     # noqa: E731
            print(f"| {name} | {ok} | {f(fa)} / {f(fb)} |")
    return 0 if all(ok for _, ok, _, _ in same) else 1


if __name__ == "__main__":
    sys.exit(main())
