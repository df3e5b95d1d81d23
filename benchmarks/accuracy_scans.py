"""Accuracy and time of the scan stage on real and defective scans, in one table.

Rows:
- the bundled scans (meshes/): our numbers, the warnings, and the previous
  release's a_min (commit 43d614b, before the rest plane came from the hull);
- every defect fixture of tests/scan_fixtures.py (twin faces, non-manifold edges
  and vertices, a messy scan, loose and separate pieces, overlapping shells, a
  cavity, an opening too large to close, dished / domed / saddle / rough /
  chamfered / tilted bases): repaired or refused, and the largest relative error
  of volume, h, b_L, b_R, I_G and a_min against the closed form;
- the default scan as a Draco-compressed GLB and as a 30,000-point cloud, against
  the PLY;
- the fixture column stored in cm and in inches (what the unit detection says).

Run:  python3 benchmarks/accuracy_scans.py
"""
from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))

PREVIOUS_A_MIN = {"dancing_girl.ply": 2.7101, "maria_barjatinskaja.ply": 3.4409, "nefertiti_bust.obj": 1.6515}
"""a_min (m/s^2) of release 43d614b, measured with load_body(...).rose().a_min."""

KEYS = ("volume", "h", "b_L", "b_R", "I_G", "a_min")


def numbers(body) -> dict:
    rose = body.rose()
    p = body.rocking(rose.weakest_deg)
    return {"volume": body.mass.volume, "h": p.h, "b_L": p.b_L, "b_R": p.b_R, "I_G": p.I_G, "a_min": rose.a_min}


def timed(fn):
    t = time.perf_counter()
    try:
        out = fn()
    except Exception as exc:  # InputError: the refusal is the result
        return None, f"{type(exc).__name__}: {exc}", time.perf_counter() - t
    return out, None, time.perf_counter() - t


def worst(got: dict, ref: dict) -> tuple[str, float]:
    errs = {k: abs(got[k] / ref[k] - 1) for k in KEYS if k in ref and k in got}
    if not errs:
        return "-", float("nan")
    k = max(errs, key=errs.get)
    return k, errs[k]


def main() -> int:
    from scan_fixtures import defect_cases, expected_a_min

    from statue2model.geometry.body import body_from_mesh, load_body
    from statue2model.io.paths import MESHES_DIR, default_scan

    rows = []
    for path in sorted(MESHES_DIR.glob("*")):
        if path.suffix not in (".ply", ".obj"):
            continue
        body, err, dt = timed(lambda: load_body(path))
        got = numbers(body)
        prev = PREVIOUS_A_MIN.get(path.name)
        rows.append((path.name, "repaired" if body.log else "clean", dt,
                     f"a_min {got['a_min'] / 9.81:.4f} g (before {prev / 9.81:.4f} g, {got['a_min'] / prev - 1:+.2%}); "
                     f"h {got['h']:.4f} m, b_L {got['b_L']:.4f}, b_R {got['b_R']:.4f} m",
                     f"{len(body.warnings)} warning(s)" + (": " + body.warnings[0][:60] + "..." if body.warnings else "")))

    for case in defect_cases():
        body, err, dt = timed(lambda: body_from_mesh(case.vertices, case.faces, **case.options))
        if body is None:
            ok = case.expect == "refused"
            rows.append((case.defect, "refused" + ("" if ok else " (WRONG)"), dt, err.split(": ", 1)[1][:110], ""))
            continue
        got = numbers(body)
        ref = dict(case.reference)
        closed = expected_a_min(case, body)
        if closed is not None:
            ref["a_min"] = closed
        key, e = worst(got, ref)
        warn = [w for w in body.warnings if "uncertain" in w or "unsure" in w]
        rows.append((case.defect, "repaired" + ("" if case.expect == "repaired" else " (WRONG)"), dt,
                     f"worst {key} {e:.2e} of {', '.join(k for k in KEYS if k in ref)}" if ref else "no closed form",
                     ("warns: " + warn[0][:70] + "...") if warn else ""))

    ref_body = load_body(default_scan())
    ref = numbers(ref_body)
    with tempfile.TemporaryDirectory() as tmp:
        import trimesh

        from test_scan_formats import _draco_tree, _glb

        raw = trimesh.load(default_scan(), process=False)
        tree, blob = _draco_tree(raw)
        glb = Path(tmp) / "dancing_girl_draco.glb"
        glb.write_bytes(_glb(tree, blob))
        body, err, dt = timed(lambda: load_body(glb))
        key, e = worst(numbers(body), ref) if body is not None else ("-", float("nan"))
        rows.append(("Draco GLB of the default scan (14-bit)", "read" if body is not None else err, dt,
                     f"worst {key} {e:.2e} against the PLY", ""))
        pts, _ = trimesh.sample.sample_surface(raw, 30000, seed=1)
        xyz = Path(tmp) / "cloud.xyz"
        np.savetxt(xyz, pts)
        body, err, dt = timed(lambda: load_body(xyz))
        if body is not None:
            key, e = worst(numbers(body), ref)
            rows.append(("point cloud: 30,000 points on the default scan", "meshed", dt,
                         f"worst {key} {e:.2e} against the PLY; volume {body.mass.volume / ref['volume'] - 1:+.2%}",
                         next((s for s in body.log if "surface" in s and "points" in s), "")[:80]))
        else:
            rows.append(("point cloud: 30,000 points on the default scan", "refused", dt, err[:110], ""))

    from scan_fixtures import column

    v, f = column()
    for unit, k in (("cm", 100.0), ("in", 1 / 0.0254)):
        body, err, dt = timed(lambda: body_from_mesh(v * k, f, up="z"))
        if body is None:
            rows.append((f"column 1.0 m tall stored in {unit}", "refused", dt, err[:110], ""))
        else:
            note = next((w for w in body.warnings if "unit" in w), "no unit warning")
            rows.append((f"column 1.0 m tall stored in {unit}", f"taken as {body.units}", dt,
                         f"height {body.height:.4g} m, mass {body.mass.mass:.4g} kg", note[:110]))

    width = max(len(r[0]) for r in rows)
    print(f"{'scan / defect':<{width}}  {'outcome':<18} {'time':>7}  result")
    for name, outcome, dt, result, note in rows:
        print(f"{name:<{width}}  {outcome:<18} {dt:6.2f}s  {result}" + (f"\n{'':<{width + 36}}{note}" if note else ""))
    wrong = [r for r in rows if "WRONG" in r[1]]
    return 1 if wrong else 0


if __name__ == "__main__":
    sys.exit(main())
