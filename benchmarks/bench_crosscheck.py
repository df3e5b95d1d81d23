"""Benchmark of the 3D cross-check (PyBullet) against the 2D model.

    python3 benchmarks/bench_crosscheck.py [--quick]

Tables: (1) time step and solver iterations vs error (free rocking of the default
statue: quarter period and first rebound peak against the 2D reference) vs run time;
(2) real-time factor of each scene; (3) the cost of what the scenes skip or choose:
full-mesh collision vs convex hull, plane vs box floor, PyBullet's default 1 mm
collision margin vs 0; (4) groove tessellation vs the isolator's loss at mu = 0 and run
time and time step; (5) overturn / no-overturn agreement on an N x N one-cosine grid around the 2D
boundary (20 x 20 in full mode, 8 x 8 with --quick); (6) the plate's noise floor at rest under the
statue per groove mesh and mount.
"""
from __future__ import annotations

import argparse
import math
import time

import numpy as np

from statue2model.crosscheck.contact import ContactSettings
from statue2model.crosscheck.isolator_scene import IsolatorScene, simulate_isolator
from statue2model.crosscheck.boundary import overturn_amplitude_2d, overturn_grid
from statue2model.crosscheck.restitution import calibrate_restitution, model_2d
from statue2model.crosscheck.statue_scene import StatueScene, simulate_statue
from statue2model.crosscheck.world import SimSettings
from statue2model.hazard import motions
from statue2model.rocking import RockingModel, simulate
from statue2model.geometry.body import load_body
from statue2model.io.paths import default_scan


def free_errors(sc, settings, contact=None, collision="hull", t_end=1.0):
    contact = ContactSettings() if contact is None else contact
    p = sc.params
    th0 = 0.5 * p.delta_R
    r2 = simulate(RockingModel.housner(p), motions.free(), theta0=th0, t_end=2.0)
    r3 = simulate_statue(sc, motions.free(), theta0=th0, t_end=t_end, settings=settings, contact=contact,
                         dt_out=settings.dt, collision=collision)
    q = abs(r3.impact_times[0] - r2.impact_times[0]) / r2.impact_times[0] if r3.impact_times.size else math.nan
    pk = abs(abs(r3.peak_theta[1]) - r2.peak_values[1]) / r2.peak_values[1] if r3.peak_theta.size > 1 else math.nan
    return q, pk, r3


def sections_1_to_4(sc, args):
    print("(1) time step / solver iterations vs error vs run time (default statue, free rocking from 0.5 delta_R,")
    print("    1 s simulated; errors against the 2D model)")
    print(f"{'dt (s)':>9s} {'iters':>6s} {'quarter period err':>19s} {'rebound peak err':>17s} {'wall (s)':>9s} "
          f"{'RTF':>7s} {'max tilt (rad)':>15s}")
    dts = (2e-3, 1e-3, 5e-4, 2.5e-4) if args.quick else (4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4)
    its = (10, 50) if args.quick else (10, 50, 200)
    for dt in dts:
        for it in its:
            q, pk, r = free_errors(sc, SimSettings(dt=dt, solver_iterations=it))
            print(f"{dt:9.2e} {it:6d} {q * 100:18.3f}% {pk * 100:16.3f}% {r.wall_time:9.3f} {r.real_time_factor:7.1f} "
                  f"{np.abs(r.tilt_out).max():15.2e}")

    print("\n(2) real-time factor per scene (dt = 0.5 ms, 50 iterations)")
    s = SimSettings(dt=5e-4)
    _, _, r = free_errors(sc, s, t_end=2.0)
    print(f"  statue on rigid floor (convex hull, {len(sc.hull)} vertices): RTF {r.real_time_factor:.1f}")
    iso = IsolatorScene.simple(R=0.9, r=0.0095, mu=0.0073, m_o=60.0, travel=0.12, spacing=0.6, segments=128)
    ri = simulate_isolator(iso, motions.free(), u0=0.1, t_end=2.0, settings=s)
    print(f"  isolator alone (4 balls, 128-segment grooves): RTF {ri.real_time_factor:.2f}")
    from dataclasses import replace
    ris = simulate_isolator(replace(iso, statue=sc), motions.free(), u0=0.1, t_end=2.0, settings=s)
    print(f"  statue on the isolator: RTF {ris.real_time_factor:.2f} (outcome {ris.outcome})")

    print("\n(3) cost and effect of scene choices (free rocking, 1 s, dt = 0.5 ms)")
    rows = [("convex hull, box floor, margin 0 (default)", s, ContactSettings(), "hull"),
            ("plane floor", replace(s, floor="plane"), ContactSettings(), "hull"),
            ("default 1 mm collision margin", s, ContactSettings(margin=0.001), "hull"),
            (f"full mesh ({len(sc.mesh[1])} faces, concave)", s, ContactSettings(), "mesh")]
    for name, st, ct, col in rows:
        try:
            q, pk, r = free_errors(sc, st, ct, col)
            print(f"  {name:45s} quarter period err {q * 100:7.3f}%  rebound err {pk * 100:7.3f}%  "
                  f"wall {r.wall_time:6.2f} s  RTF {r.real_time_factor:6.1f}  tilt {np.abs(r.tilt_out).max():.1e}")
        except Exception as exc:  # noqa: BLE001 - report, do not stop the benchmark
            print(f"  {name:45s} failed: {type(exc).__name__}: {exc}")

    print("\n(4) groove tessellation (R = 0.3 m, r = 9.5 mm, mu = 0, from u0 = 60 mm, 2 cycles): CNC mesh with N")
    print("    segments per ring, or the lattice of h mm on the sphere (the default, 4 mm)")
    print(f"{'tessellation':>14s} {'dt (ms)':>8s} {'faces/plate':>12s} {'loss/cycle (mm)':>16s} {'= mu':>9s} "
          f"{'RTF':>6s}")
    tess = [("seg", 32), ("seg", 64), ("seg", 128), ("grid", 0.008), ("grid", 0.004), ("grid", 0.002)]
    for kind, val in (tess[1:5] if args.quick else tess):
        base = IsolatorScene.simple(R=0.3, r=0.0095, mu=0.0, m_o=50.0, travel=0.05)
        sci = replace(base, grid=None, segments=val) if kind == "seg" else replace(base, grid=val)
        meshes = {w: sci.plate_mesh(w) for w in ("bottom", "top")}
        for dt in ((5e-4, 2.5e-4) if kind == "seg" and val == 64 or val == 0.004 else (5e-4,)):
            rr = simulate_isolator(sci, motions.free(), u0=0.06, t_end=3.1, settings=SimSettings(dt=dt),
                                   meshes=meshes, dt_out=5e-4)
            pk = np.abs(rr.peaks_u)
            loss = (0.06 - pk[1]) if pk.size > 1 else math.nan
            name = f"{val} seg" if kind == "seg" else f"grid {val * 1000:g} mm"
            print(f"{name:>14s} {dt * 1000:8.3f} {len(meshes['bottom'][1]):12d} {loss * 1000:16.3f} "
                  f"{loss / (4 * sci.R_hat):9.5f} {rr.real_time_factor:6.2f}")

    print("\n(6) plate at rest (no ground motion) carrying the statue: 20 Hz acceleration rms / peak (m/s^2),")
    print("    designed isolator R 0.9 m, 3 s after 0.25 s settling (isolator_cases.plate_at_rest)")
    from statue2model.crosscheck.isolator_cases import plate_at_rest
    from statue2model.isolator.plates import PlateGeometry

    h = 0.30238660547079826
    geom = PlateGeometry(side=0.8880228222042936, thickness=0.03, R=0.9, depth=0.008255974701743884,
                         groove_centres=((-h, -h), (h, -h), (h, h), (-h, h)), ball_radius=0.0095)
    iso_d = IsolatorScene(geom=geom, mu=0.0073, m_o=16.560275187869248, statue=sc)
    rows = [("lattice 4 mm, free-standing", iso_d, "contact", s), ("lattice 4 mm, fixed (JOINT_FIXED)", iso_d, "fixed", s),
            ("lattice 4 mm, one rigid body", iso_d, "rigid", s),
            ("lattice 4 mm, free-standing, 200 it", iso_d, "contact", replace(s, solver_iterations=200)),
            ("lattice 4 mm, no statue", replace(iso_d, statue=None), "contact", s),
            ("128-segment mesh, free-standing", replace(iso_d, grid=None, segments=128), "contact", s),
            ("128-segment mesh, one rigid body", replace(iso_d, grid=None, segments=128), "rigid", s)]
    for name, scn, mount, st in (rows[:3] + rows[5:6] if args.quick else rows):
        r0 = plate_at_rest(scn, st, ContactSettings(), mount=mount)
        print(f"  {name:40s} {r0['rms_filtered']:.3f} / {r0['peak_filtered']:.3f}  (raw {r0['rms_raw']:.3f} / "
              f"{r0['peak_raw']:.2f}; wall {r0['wall_time_s']:.1f} s)")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--grid-only", action="store_true", help="only table (5), the overturn grid")
    ap.add_argument("--dt-check", action="store_true", help="rerun the grid's disagreements at dt = 0.25 ms")
    args = ap.parse_args()
    sc = StatueScene.from_body(load_body(default_scan()))
    t_all = time.perf_counter()

    s = SimSettings(dt=5e-4)
    if not args.grid_only:
        sections_1_to_4(sc, args)

    n = 8 if args.quick else 20
    print(f"\n(5) overturn agreement on a {n} x {n} one-cosine grid around the 2D boundary "
          "(0.85..1.15 x the 2D overturning amplitude, 1..4 Hz; dt = 0.5 ms). The 2D model has the 3D "
          "scene's restitution (calibrated on free rocking, a table e(|theta'|)); a point is 'valid' if "
          "the 2D trajectory's own contact demand (friction |F|/N, normal force N > 0) is within what "
          "the 3D contact (mu = 1) can give")
    t0 = time.perf_counter()
    cal = calibrate_restitution(sc, s, ContactSettings())
    print("  calibrated e_L(|theta'|):", [round(v, 4) for v in cal["e_L_table"]["values"]], "at",
          [round(v, 3) for v in cal["e_L_table"]["speeds"]], "rad/s")
    print("  calibrated e_R(|theta'|):", [round(v, 4) for v in cal["e_R_table"]["values"]], "at",
          [round(v, 3) for v in cal["e_R_table"]["speeds"]], "rad/s")
    model = model_2d(sc, cal)
    grid = overturn_grid(sc, model, np.linspace(1.0, 4.0, n), np.linspace(0.85, 1.15, n), s, ContactSettings(),
                         progress=lambda f: print(f"  {f:.2f} Hz done ({time.perf_counter() - t0:.0f} s)",
                                                  flush=True))
    if grid["skipped"]:
        print(f"  no 2D overturning below 20 x the uplift acceleration (skipped): "
              f"{[round(f, 2) for f in grid['skipped']]} Hz")
    tot, tv = max(grid["total"], 1), max(grid["total_valid"], 1)
    print(f"  agreement, all points: {grid['agree']}/{grid['total']} = {grid['agree'] / tot * 100:.1f}% ; "
          f"points where the 2D rocking-only assumption holds: {grid['agree_valid']}/{grid['total_valid']} = "
          f"{grid['agree_valid'] / tv * 100:.1f}% (target 95%) in {time.perf_counter() - t0:.0f} s")
    for f in sorted({r["freq"] for r in grid["rows"]}):
        rr = [r for r in grid["rows"] if r["freq"] == f]
        print(f"  {f:5.2f} Hz a_ot {rr[0]['amp_g'] / rr[0]['factor']:6.2f} g: agree {sum(r['agree'] for r in rr)}"
              f"/{len(rr)}, valid {sum(r['valid_2d'] for r in rr)}/{len(rr)}, 2D needs mu up to "
              f"{max(r['mu_required'] for r in rr):.2f}, N_min/mg down to {min(r['n_min'] for r in rr):.2f}; "
              f"3D max pivot slip {max(r['max_pivot_slip'] for r in rr) * 1000:.0f} mm, "
              f"max yaw {max(r['max_yaw'] for r in rr):.2f} rad")
    mism = [(round(r["freq"], 2), round(r["factor"], 3), r["overturn_2d"], r["overturn_3d"], r["valid_2d"])
            for r in grid["rows"] if not r["agree"]]
    print(f"  disagreements (freq Hz, amp / a_ot_2D, 2D, 3D, 2D valid): {mism[:40]}")
    if args.dt_check or not args.quick:
        print("  time step check on the disagreements (dt = 0.25 ms):")
        for f, fac, o2, o3, _v in mism[:6]:
            a_ot = overturn_amplitude_2d(model, f, "cosine")
            m = motions.cosine_pulse(fac * a_ot, f)
            r = simulate_statue(sc, m, settings=SimSettings(dt=2.5e-4), free_time=3.0, dt_out=0.01)
            print(f"    {f:.2f} Hz x{fac:.3f}: 3D at 0.5 ms {o3}, at 0.25 ms {r.overturned}")
    print(f"\ntotal {time.perf_counter() - t_all:.0f} s")


if __name__ == "__main__":
    main()
