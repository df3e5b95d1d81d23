"""Benchmark: a ~1.2 M-face scan to every CNC file of its 1:2 prototype.

1. The slicing step side by side: statue2model.fabrication.layers (vectorised
   triangle-plane crossings, polygons assembled with shapely) against
   trimesh.section_multiplane (the usual way, Path2D per plane, polygons_full),
   on the same mesh and the same heights; their section areas are compared.
2. The whole `statue2model slice` command in a fresh interpreter (imports, load,
   repair, slicing, tool checks, rods, labels, nesting, as-built prototype, all
   DXF files, previews, BOM, JSON); target under 10 s wall.

    python3 benchmarks/bench_slice.py [--levels 3] [--repeat 3]

The scan is the bundled default one subdivided ``levels`` times (cached in
benchmarks/_data/, shared with bench_props.py).
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
sys.path.insert(0, str(HERE))

from bench_props import best, make_scan


def ours(v, f, bottoms, board):
    from statue2model.fabrication.layers import layer_sections

    return [s.area for s in layer_sections(v, f, bottoms, board, "mid", 0.0)]


def baseline(v, f, bottoms, board):
    import trimesh

    mesh = trimesh.Trimesh(v, f, process=False)
    z = bottoms + 0.5 * board
    sections = mesh.section_multiplane(plane_origin=[0, 0, 0], plane_normal=[0, 0, 1], heights=z)
    return [sum(p.area for p in s.polygons_full) if s is not None else 0.0 for s in sections]


def command(path, out):
    t = time.perf_counter()
    subprocess.run([sys.executable, "-m", "statue2model", "slice", str(path), "--scale", "1:2", "--out", str(out)],
                   check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--levels", type=int, default=3, help="subdivisions of the default scan (3 -> 1.23 M faces)")
    ap.add_argument("--repeat", type=int, default=3, help="runs of each timing; the best is shown")
    args = ap.parse_args()

    from statue2model.fabrication.layers import layer_bottoms
    from statue2model.geometry.body import load_body

    path = make_scan(args.levels)
    body = load_body(path)
    v = body.vertices / 2.0
    board, glue = 0.009, 0.0005
    bottoms = layer_bottoms(float(v[:, 2].max()), board, glue)
    print(f"scan: {path.name}, {len(body.faces):,} faces; {len(bottoms)} layers at 1:2")

    t_ours, a_ours = best(lambda: ours(v, body.faces, bottoms, board), args.repeat)
    t_base, a_base = best(lambda: baseline(v, body.faces, bottoms, board), args.repeat)
    a_ours, a_base = np.array(a_ours), np.array(a_base)
    rel = np.abs(a_ours - a_base) / np.maximum(a_base, 1e-12)
    print()
    print(f"{'slicing step':<44}{'statue2model':>14}{'trimesh':>12}{'ratio':>8}")
    print(f"{'sections at the boards mid-planes (best of %d)' % args.repeat:<44}"
          f"{t_ours:>12.3f} s{t_base:>10.3f} s{t_base / t_ours:>7.1f}x")
    print(f"{'largest section-area difference':<44}{rel.max():>14.2e}")

    with tempfile.TemporaryDirectory() as tmp:
        times = [command(path, Path(tmp) / f"run{i}") for i in range(args.repeat)]
        n_files = len(list((Path(tmp) / "run0").rglob("*.dxf")))
    print()
    print(f"{'whole `statue2model slice` command':<44}{min(times):>12.2f} s  (runs: "
          + ", ".join(f"{t:.2f}" for t in times) + f"; {n_files} DXF files)")
    print(f"{'target':<44}{'< 10 s':>14}  {'met' if min(times) < 10 else 'NOT met'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
