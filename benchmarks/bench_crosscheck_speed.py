"""Speed against accuracy of the 3D cross-check scenes (PyBullet), side by side in one run.

    python3 benchmarks/bench_crosscheck_speed.py [--quick] [--design isolator/design.json] [--skip-statue]
                                                 [--skip-isolator]

For each engine setting (time step dt, solver iterations, groove lattice spacing) one row: the
real-time factor (simulated s per s; "cpu" uses the process CPU time, robust on a shared machine,
"wall" the wall clock) and the error of each output against the finest setting of the table.

(1) Statue scene on the rigid floor, a slender block (b 0.1 m, h 0.5 m, 100 kg) and the default scan
    (meshes/dancing_girl.ply, weakest direction): a one-sine pulse, 0.8 x the 2D overturning
    amplitude (1.5 Hz for the scan, 3 Hz for the block: 2 x its uplift acceleration), 3 s: peak
    rotation and lift-off time; and the free rocking from 0.5 delta_R, 1 s: first
    rebound peak. The statue scene's own setting (statue_scene.STATUE_SETTINGS) is chosen from it.
(2) Isolator scene, the pipeline's design for the default scan (``statue2model run --stages isolator``,
    made in a temporary directory unless --design is given), statue fixed to the plate (mount
    'rigid', the 2D plate model's assumption), a 4 s synthetic record at 0.2 g (seed 1) + 0.5 s:
    peak plate displacement, peak plate acceleration low-passed at 20 Hz, and the 2D plate's values.

The SimSettings defaults (isolator) and STATUE_SETTINGS are chosen from these tables (docs/crosscheck.md,
"Speed").
"""
from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from statue2model.crosscheck.isolator_cases import lowpass
from statue2model.crosscheck.isolator_scene import IsolatorScene, simulate_isolator
from statue2model.crosscheck.boundary import overturn_amplitude_2d
from statue2model.crosscheck.statue_scene import (
    STATUE_SETTINGS,
    StatueScene,
    simulate_statue,
)
from statue2model.crosscheck.world import SimSettings
from statue2model.hazard import motions
from statue2model.rocking import RockingModel
from statue2model.geometry.body import load_body
from statue2model.io.paths import default_scan


def timed(fn):
    c0, w0 = time.process_time(), time.perf_counter()
    r = fn()
    return r, time.process_time() - c0, time.perf_counter() - w0


def rel(x, ref):
    return abs(x - ref) / abs(ref) if ref else math.nan


def statue_table(sc, settings_list, freq=1.5, repeat=2):
    """One row per engine setting (the last: the reference) for scene ``sc``: CPU and wall real-time
    factors (best of ``repeat``, the process's PyBullet client already connected: World reuses it) of
    the pulse run + the free-rocking run, and the errors against the last row of the peak rotation,
    the lift-off time (geometric, LIFT_HEIGHT) and the first rebound peak."""
    p = sc.params
    a_ot = overturn_amplitude_2d(RockingModel.housner(p), freq)
    pulse = motions.sine_pulse(0.8 * a_ot, freq)
    simulate_statue(sc, motions.free(), theta0=0.5 * p.delta_R, t_end=0.01)     # connect once
    rows = []
    for s in settings_list:
        best = None
        for _ in range(repeat):
            r, cpu, wall = timed(lambda: simulate_statue(sc, pulse, t_end=3.0, settings=s, dt_out=s.dt))
            f, cpu2, wall2 = timed(lambda: simulate_statue(sc, motions.free(), theta0=0.5 * p.delta_R, t_end=1.0,
                                                           settings=s, dt_out=s.dt))
            eng = engine_only(sc, pulse, 3.0, s)
            if best is None or cpu + cpu2 < best[0]:
                best = (cpu + cpu2, wall + wall2, cpu, eng)
        rows.append(dict(s=s, peak=max(r.theta_max_L, r.theta_max_R),
                         lift=r.uplift_time if r.uplift_time is not None else math.nan,
                         rebound=abs(f.peak_theta[1]) if f.peak_theta.size > 1 else math.nan,
                         cpu=(3.0 + 1.0) / best[0], wall=(3.0 + 1.0) / best[1], cpu_pulse=3.0 / best[2],
                         engine=3.0 / best[3]))
    ref = rows[-1]
    print(f"{sc.name}: one-sine {freq:g} Hz at 0.8 x the 2D overturning amplitude ({0.8 * a_ot:.3f} m/s^2), 3 s;"
          f" free rocking from 0.5 delta_R, 1 s. RTF = 4 s / time of both runs (best of {repeat});"
          " errors against the last row (the finest). 'pulse': the pulse run alone; 'engine': its steps alone"
          " (set gravity + step, no reading: the ceiling).")
    print(f"{'dt (ms)':>8s} {'iters':>5s} {'RTF cpu':>8s} {'pulse':>6s} {'engine':>6s} {'RTF wall':>9s} {'peak rot (rad)':>15s} "
          f"{'err':>7s} {'lift-off (s)':>13s} {'err (ms)':>9s} {'rebound (rad)':>14s} {'err':>7s}")
    for w in rows:
        print(f"{w['s'].dt * 1e3:8.3f} {w['s'].solver_iterations:5d} {w['cpu']:8.1f} {w['cpu_pulse']:6.1f} {w['engine']:6.1f} "
              f"{w['wall']:9.1f} {w['peak']:15.5f} {rel(w['peak'], ref['peak']) * 100:6.2f}% {w['lift']:13.4f} "
              f"{(w['lift'] - ref['lift']) * 1e3:9.2f} {w['rebound']:14.5f} {rel(w['rebound'], ref['rebound']) * 100:6.2f}%")
    return rows


def engine_only(sc, motion, t_end, s):
    """CPU time, s, of the engine steps of a statue run alone (gravity set and stepped, nothing read)."""
    from statue2model.crosscheck.contact import ContactSettings
    from statue2model.crosscheck.statue_scene import _floor, add_statue
    from statue2model.crosscheck.world import World, step_mean_acc

    n = math.ceil(t_end / s.dt - 1e-9)
    acc = step_mean_acc(motion, 0.0, s.dt, n).tolist()
    with World(s) as w:
        _floor(w, ContactSettings(), "hull")
        add_statue(w, sc, ContactSettings())
        p, cid, g = w.p, w.client, s.g
        c0 = time.process_time()
        for a in acc:
            p.setGravity(-a, 0.0, -g, physicsClientId=cid)
            p.stepSimulation(physicsClientId=cid)
        return time.process_time() - c0


MU_FREE = 0.002
"""Rolling friction of the isolator table's free-vibration decay runs."""


def isolator_table(design, sc, variants, t_rec=4.0):
    """One row per (groove, size m, SimSettings) of ``variants`` (the last: the finest): CPU real-time
    factor of the design under the record (statue fixed), peak displacement and 20 Hz peak plate
    acceleration (errors against the last row and ratio to the 2D plate); then the free vibration of
    the plate alone (from 60 % of the balls' travel, mu = 0 and MU_FREE: the design's mu stops it within a
    cycle): period error (mu = 0) against 2 pi sqrt(R_hat / g), the loss per cycle at mu = 0 (numerical,
    target 0) and the decay per cycle at MU_FREE against 4 mu R_hat."""
    from dataclasses import replace

    from statue2model.crosscheck.isolator_cases import _first_period
    from statue2model.isolator.device import Isolator
    from statue2model.isolator.time_history import simulate as plate_2d

    m = motions.synthetic_record(duration=t_rec, pga=0.2 * 9.81, seed=1)
    t_end = t_rec + 0.5
    rows = []
    for groove, size, s in variants:
        iso = IsolatorScene.from_design(design, statue=sc, grid=size if groove == "lattice" else 0.004,
                                        groove=groove)
        if groove == "tiles":
            iso = replace(iso, tile=size)
        r, cpu, wall = timed(lambda: simulate_isolator(iso, m, t_end=t_end, settings=s, mount="rigid"))
        a3 = float(np.abs(lowpass(r.acc_step, s.dt)).max())
        free = replace(iso, statue=None)
        T = 2 * math.pi * math.sqrt(free.R_hat / s.g)
        u0 = 0.6 * (free.geom.opening_radius - free.r)
        fr = {}
        for mu in (0.0, MU_FREE):
            f, cpu_f, _ = timed(lambda: simulate_isolator(replace(free, mu=mu), motions.free(), u0=u0,
                                                          t_end=1.2 * T, settings=s, dt_out=0.002))
            loss = u0 - abs(f.peaks_u[1]) if f.peaks_u.size > 1 else math.nan
            fr[mu] = (loss, _first_period(f, u0), f.steps * s.dt / cpu_f)
        rows.append(dict(groove=groove, size=size, s=s, u=r.u_max, a=a3, raw=r.acc_abs_max, cpu=t_end / cpu,
                         wall=t_end / wall, out=r.outcome, T_err=rel(fr[0.0][1], T), loss0=fr[0.0][0],
                         decay=fr[MU_FREE][0], decay_target=4 * MU_FREE * free.R_hat, rtf_free=fr[MU_FREE][2]))
    iso = IsolatorScene.from_design(design, statue=sc)
    r2 = plate_2d(Isolator(R=iso.R, r=iso.r, M=iso.M, mu=iso.mu, g=9.81, capacity=iso.travel_capacity), m,
                  t_end=t_end, dt_out=1e-4)
    a2 = float(np.abs(lowpass(r2.acc_abs, 1e-4)).max())
    ref = rows[-1]
    print(f"(2) isolator scene: design R {iso.R:g} m, r {iso.r * 1e3:g} mm, {len(iso.geom.groove_centres)} grooves, "
          f"side {iso.geom.side:.3f} m; statue fixed to the plate; record {t_rec:g} s at 0.2 g + 0.5 s.")
    print(f"    2D plate (Coulomb, mu {iso.mu:g}): peak u {r2.u_max * 1e3:.2f} mm, peak acc. 20 Hz {a2:.3f} m/s^2. "
          "Errors against the last row (the finest) and, for u, against 2D. Free vibration (plate alone):"
          f" period error (mu 0) vs 2 pi sqrt(R_hat/g), loss per cycle at mu 0, decay at mu {MU_FREE:g} vs 4 mu R_hat = "
          f"{rows[0]['decay_target'] * 1e3:.2f} mm. mc: maximal coordinates.")
    print(f"{'groove':>7s} {'size':>5s} {'dt (ms)':>7s} {'it':>3s} {'mc':>2s} {'RTF cpu':>7s} {'free':>6s} "
          f"{'u max':>7s} {'err':>6s} {'vs 2D':>6s} {'acc 20Hz':>8s} {'err':>6s} {'/2D':>5s} {'T err':>6s} "
          f"{'loss0':>6s} {'decay':>6s} {'err':>6s} outcome")
    for w in rows:
        print(f"{w['groove']:>7s} {w['size'] * 1e3:5.1f} {w['s'].dt * 1e3:7.3f} {w['s'].solver_iterations:3d} "
              f"{'y' if w['s'].maximal_coordinates else 'n':>2s} {w['cpu']:7.2f} {w['rtf_free']:6.2f} "
              f"{w['u'] * 1e3:7.2f} {rel(w['u'], ref['u']) * 100:5.1f}% {rel(w['u'], r2.u_max) * 100:5.1f}% "
              f"{w['a']:8.3f} {rel(w['a'], ref['a']) * 100:5.1f}% {w['a'] / a2:5.2f} {w['T_err'] * 100:5.2f}% "
              f"{w['loss0'] * 1e3:6.2f} {w['decay'] * 1e3:6.2f} {rel(w['decay'], w['decay_target']) * 100:5.1f}% "
              f"{w['out']}")
    return rows


def design_json(path: str | None) -> dict:
    if path:
        return json.loads(Path(path).read_text())
    out = Path(tempfile.mkdtemp(prefix="s2m_speed_")) / "run"
    subprocess.run([sys.executable, "-m", "statue2model", "run", str(default_scan()), "--stages", "isolator",
                    "--out", str(out)], check=True, stdout=subprocess.DEVNULL)
    return json.loads((out / "isolator" / "design.json").read_text())


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--design", help="isolator/design.json of a pipeline run (default: made now)")
    ap.add_argument("--skip-statue", action="store_true")
    ap.add_argument("--skip-isolator", action="store_true")
    a = ap.parse_args(argv)
    sc = StatueScene.from_body(load_body(default_scan()))
    print(f"defaults: {SimSettings()}; statue scene: {STATUE_SETTINGS}")
    if not a.skip_statue:
        its = (10, 50) if a.quick else (5, 10, 20, 50)
        dts = (4e-3, 2e-3, 1e-3, 5e-4) if a.quick else (4e-3, 3e-3, 2e-3, 1.5e-3, 1e-3, 5e-4, 2.5e-4)
        sl = [SimSettings(dt=dt, solver_iterations=it) for dt in dts for it in its]
        sl.append(SimSettings(dt=1.25e-4, solver_iterations=200))
        print("(1) statue scene on the rigid floor")
        for scene in (StatueScene.block(b=0.1, h=0.5, m=100.0), sc):
            statue_table(scene, sl, freq=3.0 if scene is not sc else 1.5)
    if not a.skip_isolator:
        design = design_json(a.design)
        r = float(design["r"])
        runs = ((1e-3, 20), (5e-4, 50)) if a.quick else ((2e-3, 10), (1e-3, 20), (1e-3, 50), (5e-4, 10), (5e-4, 50))
        v = [("lattice", 0.004, SimSettings(dt=dt, solver_iterations=it)) for dt, it in runs]
        v += [("tiles", k * r, SimSettings(dt=dt, solver_iterations=it, maximal_coordinates=True))
              for k in ((0.7, 1.0) if a.quick else (0.5, 0.7, 1.0, 2.0)) for dt, it in runs]
        v.append(("lattice", r, SimSettings(dt=2.5e-4, solver_iterations=200)))
        isolator_table(design, sc, v)


if __name__ == "__main__":
    main()
