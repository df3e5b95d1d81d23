"""Speed and agreement of the pendulum isolator scene (crosscheck.pendulum_scene) against the ball scenes.

    python3 benchmarks/bench_pendulum_scene.py [--design isolator/design.json] [--duration 10]

The default scan's isolator design (made now by ``statue2model run --stages isolator`` unless --design is
given) under a synthetic record (``--duration`` s at 0.1 g, seed 1) + 0.5 s, plate alone and with the
default scan's statue standing free on it (mount 'contact'). Columns: real-time factor (simulated s per
CPU s, one core) of the pendulum scene (dt 2 ms, its default; and dt 0.5 ms), the ball-lattice scene and
the tiles scene (dt 0.5 ms, their default) and the 2D plate model; peak travel and peak plate acceleration
(20 Hz low-pass) with their % difference against the 2D plate model.

Second table (the ratio table, the issue's record agreement): one record (``--ratio-duration`` s at
``--ratio-pga`` g, seed 1, + 0.5 s) on the same design, plate alone (steel balls, and balls of 1/100 the
density: the pendulum and the 2D model leave the balls' mass and rolling inertia out) and with the statue
fixed to the plate (mount 'rigid': the plate response the 2D model gives): the pendulum scene (dt 0.5 ms)
and the ball scene at its default (4 mm lattice, dt 0.5 ms, 50 solver iterations), on tangent tiles (1 r,
dt 0.5 ms, 50 iterations) and at the setting isolator_cases.TRACE found converged on R 2 m, r 25 mm
(25 mm facets, dt 0.25 ms, 200 iterations): peak travel, peak plate acceleration (20 Hz low-pass), their
ratios to the pendulum scene's, and the real-time factor. ``--tables speed,ratios`` picks the tables
(default both; the ratio table first).
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from statue2model.crosscheck.isolator_cases import lowpass
from statue2model.crosscheck.isolator_scene import STEEL, IsolatorScene, simulate_isolator
from statue2model.crosscheck.pendulum_scene import PendulumIsolator, simulate_pendulum
from statue2model.crosscheck.statue_scene import StatueScene
from statue2model.crosscheck.world import SimSettings
from statue2model.geometry.body import load_body
from statue2model.hazard import motions
from statue2model.io.paths import default_scan


def design_json(path: str | None) -> dict:
    """design.json at ``path``, or the default scan's made now (bench_crosscheck_speed.design_json)."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from bench_crosscheck_speed import design_json as made

    return made(path)


def timed(fn):
    c0 = time.process_time()
    r = fn()
    return r, time.process_time() - c0


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--design", help="isolator/design.json of a pipeline run (default: made now)")
    ap.add_argument("--duration", type=float, default=10.0)
    ap.add_argument("--pga", type=float, default=0.1, help="record PGA, g")
    ap.add_argument("--ratio-duration", type=float, default=4.0, help="record of the ratio table, s")
    ap.add_argument("--ratio-pga", type=float, default=0.2, help="record PGA of the ratio table, g")
    ap.add_argument("--tables", default="speed,ratios", help="comma-separated: speed, ratios")
    a = ap.parse_args(argv)
    tables = set(a.tables.split(","))
    design = design_json(a.design)
    sc = StatueScene.from_body(load_body(default_scan()))
    if "ratios" in tables:
        ratio_table(design, sc, a.ratio_duration, a.ratio_pga)
    if "speed" in tables:
        speed_table(design, sc, a)


BALL_SETTINGS = (   # label, groove, grid (m) or None, dt (s), solver iterations
    ("ball default", "lattice", 0.004, 5e-4, 50),
    ("ball tiles", "tiles", None, 5e-4, 50),
    ("ball TRACE conv.", "lattice", 0.025, 2.5e-4, 200),
)
"""The ball-scene settings of the ratio table: the default, tangent tiles and isolator_cases.TRACE's converged one
(measured there on R 2 m, r 25 mm)."""


def ratio_table(design: dict, sc: StatueScene, duration: float, pga: float, ball_settings=BALL_SETTINGS) -> list:
    """Print and return the ratio table (module docstring): rows (load, scene, u_max m, acc20 m/s^2, u ratio,
    acc ratio, RTF) of the pendulum scene and each ball setting, ratios to the pendulum scene's."""
    m = motions.synthetic_record(duration=duration, pga=pga * 9.81, seed=1)
    t_end = duration + 0.5
    pend = PendulumIsolator.from_design(design)
    n_balls = len(design["groove_centres"])
    m_balls = n_balls * STEEL * 4 / 3 * math.pi * float(design["r"]) ** 3
    print(f"(ratios) design R {design['R']:g} m, r {design['r'] * 1e3:g} mm, mu {pend.mu:g}, m_o {pend.m_o:.2f} kg, "
          f"{n_balls} steel balls {m_balls:.2f} kg; "
          f"statue {sc.mass:.1f} kg fixed to the plate; synthetic record {duration:g} s at {pga:g} g (seed 1) + 0.5 s; "
          f"acc20 = peak |plate acc| low-passed at 20 Hz; RTF = simulated s / CPU s")
    print(f"{'load':>16s} {'scene':>16s} {'groove':>12s} {'dt ms':>6s} {'iter':>5s} {'u max mm':>9s} {'u/pend':>7s} "
          f"{'acc20 m/s2':>10s} {'acc/pend':>8s} {'RTF':>6s} outcome")
    out = []
    for label, statue, density in (("alone", None, STEEL), ("alone, balls/100", None, STEEL / 100),
                                   ("statue", sc, STEEL)):
        dtp = 5e-4
        r, cpu = timed(lambda: simulate_pendulum(pend, m, statue, SimSettings(dt=dtp), t_end=t_end,
                                                 stop_at_capacity=False, mount="rigid"))
        u_p, a_p = r.u_max, float(np.abs(lowpass(r.acc_step, dtp)).max())
        rows = [(label, "pendulum", "-", dtp, SimSettings().solver_iterations, u_p, a_p, r.steps * dtp / cpu,
                 r.outcome)]
        for name, groove, grid, dt, it in ball_settings:
            iso = IsolatorScene.from_design(design, statue=statue, groove=groove,
                                            **({"grid": grid} if grid is not None else {}))
            iso = replace(iso, ball_density=density)
            s = SimSettings(dt=dt, solver_iterations=it)
            r, cpu = timed(lambda: simulate_isolator(iso, m, t_end=t_end, settings=s, stop_at_capacity=False,
                                                     mount="rigid"))
            gl = f"{grid * 1e3:g} mm lat." if groove == "lattice" else f"tiles {iso.tile_size * 1e3:g} mm"
            rows.append((label, name, gl, dt, it, r.u_max, float(np.abs(lowpass(r.acc_step, dt)).max()),
                         r.steps * dt / cpu, r.outcome))
        for row in rows:
            lab, name, gl, dt, it, u, acc, rtf, outc = row
            print(f"{lab:>16s} {name:>16s} {gl:>12s} {dt * 1e3:6.2f} {it:5d} {u * 1e3:9.2f} {u / u_p:7.3f} "
                  f"{acc:10.3f} {acc / a_p:8.3f} {rtf:6.2f} {outc}")
            out.append(row)
    return out


def speed_table(design: dict, sc: StatueScene, a) -> None:
    """The first table (module docstring)."""
    m = motions.synthetic_record(duration=a.duration, pga=a.pga * 9.81, seed=1)
    t_end = a.duration + 0.5
    pend = PendulumIsolator.from_design(design)
    print(f"design R_hat {pend.R_hat:g} m, mu {pend.mu:g}, m_o {pend.m_o:.2f} kg, capacity {pend.travel_capacity:.3f} m; "
          f"statue {sc.mass:.1f} kg; synthetic record {a.duration:g} s at {a.pga:g} g + 0.5 s; RTF = simulated s / CPU s")
    print(f"{'load':>7s} {'scene':>16s} {'dt ms':>6s} {'RTF':>7s} {'u max mm':>9s} {'vs 2D':>7s} {'acc20 m/s2':>10s} "
          f"{'vs 2D':>7s} outcome")
    for label, statue in (("alone", None), ("statue", sc)):
        rows = []
        for name, dt in (("pendulum", 2e-3), ("pendulum", 5e-4), ("ball lattice", 5e-4), ("ball tiles", 5e-4)):
            s = SimSettings(dt=dt)
            if name == "pendulum":
                r, cpu = timed(lambda: simulate_pendulum(pend, m, statue, s, t_end=t_end, stop_at_capacity=False))
            else:
                iso = IsolatorScene.from_design(design, statue=statue, groove=name.split()[1])
                r, cpu = timed(lambda: simulate_isolator(iso, m, t_end=t_end, settings=s, stop_at_capacity=False))
            acc20 = float(np.abs(lowpass(r.acc_step, dt)).max())
            rows.append((name, dt, r.steps * dt / cpu, r.u_max, acc20, r.outcome))
        # the 2D plate model (isolator/time_history: the same translating pendulum with Coulomb
        # friction, exact while the statue stays in full contact): the reference both 3D scenes aim at
        from statue2model.isolator.device import isolator_from_design
        from statue2model.isolator.time_history import simulate as plate_2d

        dt2 = 5e-4
        r2, cpu2 = timed(lambda: plate_2d(isolator_from_design(design), m, t_end=t_end, dt_out=dt2))
        rows.append(("2D plate model", dt2, t_end / cpu2, r2.u_max, float(np.abs(lowpass(r2.acc_abs, dt2)).max()),
                     "ok" if not r2.capacity_exceeded else "capacity"))
        ref = rows[4]
        for name, dt, rtf, u, acc, out in rows:
            du = (u - ref[3]) / ref[3] * 100 if ref[3] else math.nan
            da = (acc - ref[4]) / ref[4] * 100 if ref[4] else math.nan
            print(f"{label:>7s} {name:>16s} {dt * 1e3:6.2f} {rtf:7.1f} {u * 1e3:9.2f} {du:6.1f}% {acc:10.3f} {da:6.1f}% {out}")
        print(f"{'':>7s} speed-up pendulum (2 ms) / ball lattice: {rows[0][2] / rows[2][2]:.0f} x, "
              f"/ tiles: {rows[0][2] / rows[3][2]:.0f} x")


if __name__ == "__main__":
    main()
