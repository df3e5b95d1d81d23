"""Benchmark: ``props`` on a million-face closed scan against pymeshlab, side by side.

Builds a ~1.2 M-face closed scan by subdividing the bundled default scan three
times (written once to benchmarks/_data/), then times, on the same file:

- ours, in process: read + repair + orient + mass properties + footprint +
  rocking parameters + 360-direction rose (statue2model.load_body ...);
- ours, the whole command: ``statue2model props FILE --json OUT`` in a fresh
  interpreter (imports, table, JSON and plot included) - the target is < 3 s;
- pymeshlab: load + get_geometric_measures (volume, centre of mass, inertia).

and checks that both agree on volume, centre of mass and inertia to 1e-6
(ours mapped back to the file's frame; inertia per unit density). Then it shows
that repair stays linear in the number of faces: the default scan subdivided 0-3
times, each with the same share of defects (twin-face fins, flaps on 3-face edges,
missing and flipped faces: one of each per 2,000 faces), repaired, timed per face.

Run:  python3 benchmarks/bench_props.py [--repeat 3]
Needs: pip install -e ".[bench]"   (pymeshlab)
"""
from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DATA = HERE / "_data"


def make_scan(levels: int = 3) -> Path:
    import trimesh

    from statue2model.io.paths import default_scan

    path = DATA / f"dancing_girl_sub{levels}.ply"
    if path.exists():
        return path
    mesh = trimesh.load(default_scan(), process=False)
    v, f = mesh.vertices, mesh.faces
    for _ in range(levels):
        v, f = trimesh.remesh.subdivide(v, f)
    DATA.mkdir(exist_ok=True)
    tmp = path.with_suffix(".part")
    trimesh.Trimesh(v, f, process=False).export(tmp, file_type="ply")
    tmp.replace(path)
    return path


def best(fn, repeat):
    times, out = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def ours(path):
    from statue2model.geometry.body import load_body

    body = load_body(path)
    body.rocking()
    body.rose()
    R, s = body.rotation, body.scale
    com = R.T @ (body.mass.com - body.translation) / s
    inertia = R.T @ body.mass.inertia @ R / (body.mass.density * s**5)
    return body.mass.volume / s**3, com, inertia, len(body.faces), body.height / s


def meshlab(path):
    import pymeshlab

    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    g = ms.get_geometric_measures()
    return g["mesh_volume"], np.asarray(g["center_of_mass"]), np.asarray(g["inertia_tensor"])


def command(path):
    with tempfile.TemporaryDirectory() as tmp:
        t = time.perf_counter()
        subprocess.run([sys.executable, "-m", "statue2model", "props", str(path), "--json", f"{tmp}/p.json"],
                       check=True, stdout=subprocess.DEVNULL)
        return time.perf_counter() - t


def messy(levels: int, seed: int = 0):
    """The default scan subdivided ``levels`` times with one defect of each kind per
    2,000 faces (twin fin, flap, missing face, flipped face)."""
    import trimesh

    from statue2model.io.paths import default_scan

    mesh = trimesh.load(default_scan(), process=False)
    v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    for _ in range(levels):
        v, f = trimesh.remesh.subdivide(v, f)
    rng = np.random.default_rng(seed)
    k = max(1, len(f) // 2000)
    pick = rng.choice(len(f), 4 * k, replace=False)
    fins, flaps, missing, flipped = pick[:k], pick[k:2 * k], pick[2 * k:3 * k], pick[3 * k:]
    tips = v[f[fins, 0]] * 1.001
    flap_tips = v[f[flaps, 1]] * 1.001
    n = len(v)
    a, b = f[fins, 0], f[fins, 1]
    c = n + np.arange(k)
    extra = [np.column_stack([a, b, c]), np.column_stack([b, a, c])]
    a2, b2 = f[flaps, 0], f[flaps, 1]
    extra.append(np.column_stack([a2, b2, n + k + np.arange(k)]))
    f = f.copy()
    f[flipped] = f[flipped][:, ::-1]
    keep = np.ones(len(f), bool)
    keep[missing] = False
    return np.vstack([v, tips, flap_tips]), np.vstack([f[keep]] + extra)


def repair_scaling(repeat: int) -> None:
    from statue2model.geometry.repair import repair_mesh

    print(f"\n{'repair of a messy scan':34s}{'faces':>12s}{'time [s]':>10s}{'us / face':>11s}")
    for levels in range(4):
        v, f = messy(levels)
        t, res = best(lambda: repair_mesh(v, f), repeat)
        print(f"{'  subdivided x' + str(levels):34s}{len(f):12,d}{t:10.3f}{t / len(f) * 1e6:11.2f}")
    print(f"  (last: {'; '.join(res.log)})")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--levels", type=int, default=3, help="subdivisions of the default scan (3 -> 1.23 M faces)")
    args = ap.parse_args()
    path = make_scan(args.levels)
    import pymeshlab  # noqa: F401  (fail early with a clear ImportError)

    t_ours, (vol, com, inertia, n_faces, height) = best(lambda: ours(path), args.repeat)
    t_ml, (vol_ml, com_ml, inertia_ml) = best(lambda: meshlab(path), args.repeat)
    t_cmd = min(command(path) for _ in range(args.repeat))

    err_vol = abs(vol - vol_ml) / abs(vol_ml)
    err_com = float(np.abs(com - com_ml).max()) / height  # relative to the statue's height
    err_in = float(np.abs(inertia - inertia_ml).max() / np.abs(inertia_ml).max())

    print(f"scan: {path.name}, {n_faces:,} faces after repair (best of {args.repeat})\n")
    print(f"{'':34s}{'statue2model':>14s}{'pymeshlab':>12s}{'ratio':>9s}")
    print(f"{'read + mass properties [s]':34s}{t_ours:14.3f}{t_ml:12.3f}{t_ml / t_ours:8.2f}x")
    print("  (ours also repairs, orients, finds the footprint, rocking parameters and rose)")
    print(f"{'whole props command [s]':34s}{t_cmd:14.3f}{'-':>12s}   target < 3 s: {'met' if t_cmd < 3 else 'NOT met'}")
    print()
    print(f"{'agreement':34s}{'rel. error':>14s}{'target':>12s}")
    for name, err in (("volume", err_vol), ("centre of mass", err_com), ("inertia tensor", err_in)):
        print(f"{name:34s}{err:14.2e}{1e-6:12.0e}  {'met' if err < 1e-6 else 'NOT met'}")
    repair_scaling(args.repeat)
    return 0 if max(err_vol, err_com, err_in) < 1e-6 else 1


if __name__ == "__main__":
    sys.exit(main())
