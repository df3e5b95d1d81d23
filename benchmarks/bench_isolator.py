"""Benchmark: run time against error for the isolator's top plate, statue2model vs
scipy solve_ivp, side by side.

Cases (the three-groove prototype, r = 18.3 mm, M = 21.664 kg, mu = 0.0114):
  * Coulomb, free vibration from 50 mm (10 s), and under a 20 s synthetic record
    (0.25 g). Ours is the exact piecewise closed form; the reference for the errors
    is ours. solve_ivp integrates u'' = -omega^2 u - s mu g - u_g'' phase by
    phase, with an event at u' = 0 (RK45, DOP853, LSODA).
  * Bouc-Wen (q = 30, n = 1), the same record. Reference: ours at rtol 1e-13.
    solve_ivp integrates the 3-state (u, u', z) system (Radau, LSODA, RK45).

Errors: max |u - u_ref| over the 5 ms output grid, relative to max |u_ref|.

    python3 benchmarks/bench_isolator.py [--quick]
"""
from __future__ import annotations

import argparse
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

from statue2model.hazard import motions
from statue2model.isolator.device import Isolator
from statue2model.isolator.time_history import simulate

DT = 0.005


def timed(fn, repeat=3):
    best, out = np.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def scipy_coulomb(iso, motion, u0, t_end, method, rtol):
    """Coulomb with solve_ivp, done properly: one integration per sliding phase,
    terminated by an event at u' = 0 (a bare sgn(u') right-hand side chatters
    forever once the plate sticks)."""
    om2, mug = iso.omega**2, iso.mu * iso.g
    acc = motion.acc
    t_eval = np.arange(0, t_end + 1e-12, DT)
    out = np.full(len(t_eval), np.nan)
    t, u, v = 0.0, u0, 0.0
    d = -om2 * u - float(acc(0.0))
    s = np.sign(d) if abs(d) > mug else 0.0
    while t < t_end - 1e-12:
        if s == 0.0:
            # stuck: step to the next output time where the ground can move it
            k = np.searchsorted(t_eval, t, side="right")
            if k >= len(t_eval):
                break
            out[(t_eval >= t) & (t_eval <= t_eval[k])] = u
            t = t_eval[k]
            d = -om2 * u - float(acc(t))
            s = np.sign(d) if abs(d) > mug else 0.0
            continue
        def rhs(tt, y, s=s):
            return [y[1], -om2 * y[0] - s * mug - float(acc(tt))]
        def rev(tt, y, s=s):
            return y[1] if tt > t else s
        rev.terminal, rev.direction = True, -s
        mask = t_eval >= t
        sol = solve_ivp(rhs, (t, t_end), [u, v], method=method, rtol=rtol, atol=rtol * 1e-3, events=rev,
                        dense_output=True)
        te = sol.t[-1]
        sel = mask & (t_eval <= te)
        out[sel] = sol.sol(t_eval[sel])[0]
        t, u, v = te, sol.y[0, -1], 0.0 if sol.status == 1 else sol.y[1, -1]
        d = -om2 * u - float(acc(t))
        s = np.sign(d) if abs(d) > mug else 0.0
    out[np.isnan(out)] = u
    return out


def scipy_boucwen(iso, motion, u0, t_end, method, rtol):
    om2, mug, q = iso.omega**2, iso.mu * iso.g, iso.q
    uy = iso.u_y
    acc = motion.acc
    def rhs(t, y):
        u, v, z = y
        dz = (1 - abs(z) * (0.5 + 0.5 * np.sign(v * z))) * v / uy
        return [v, -om2 * u - (1 - 1 / q) * mug * z - float(acc(t)), dz]
    t_eval = np.arange(0, t_end + 1e-12, DT)
    sol = solve_ivp(rhs, (0, t_end), [u0, 0.0, 0.0], method=method, rtol=rtol, atol=rtol * 1e-3, t_eval=t_eval)
    return sol.y[0]


def error(u, ref):
    n = min(len(u), len(ref))
    return float(np.max(np.abs(u[:n] - ref[:n])) / np.max(np.abs(ref)))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer tolerances")
    args = ap.parse_args()
    record = motions.synthetic_record(duration=20.0, pga=0.25 * 9.81, seed=0)
    rtols = (1e-4, 1e-6, 1e-8) if args.quick else (1e-3, 1e-4, 1e-6, 1e-8, 1e-10)
    cases = [
        ("Coulomb, free from 50 mm, 10 s", "coulomb", motions.free(), 0.05, 10.0),
        ("Coulomb, 20 s record 0.25 g", "coulomb", record, 0.0, 20.0),
        ("Bouc-Wen q 30, 20 s record 0.25 g", "boucwen", record, 0.0, 20.0),
    ]
    simulate(Isolator(R=0.3, r=0.0183, M=21.664, mu=0.0114, model="boucwen"), motions.free(), u0=0.01, t_end=1.0)
    simulate(Isolator(R=0.3, r=0.0183, M=21.664, mu=0.0114), motions.free(), u0=0.01, t_end=1.0)  # compile
    for title, model, motion, u0, t_end in cases:
        iso = Isolator(R=0.30, r=0.0183, M=21.664, mu=0.0114, model=model)
        ref = simulate(iso, motion, u0=u0, t_end=t_end, dt_out=DT, rtol=1e-13).u
        print(f"\n{title}")
        print(f"  {'solver':<28}{'rtol':>8}{'time':>12}{'error':>11}")
        rows = []
        ours_rtols = (1e-6, 1e-9) if model == "coulomb" else rtols
        for rtol in ours_rtols:
            t, res = timed(lambda: simulate(iso, motion, u0=u0, t_end=t_end, dt_out=DT, rtol=rtol))
            label = "statue2model (exact)" if model == "coulomb" else "statue2model DP5 + exact z"
            rows.append((label, rtol, t, error(res.u, ref)))
            if model == "coulomb":
                break
        methods = ("RK45", "DOP853", "LSODA") if model == "coulomb" else ("Radau", "LSODA", "RK45")
        for method in methods:
            for rtol in rtols:
                fn = scipy_coulomb if model == "coulomb" else scipy_boucwen
                t, u = timed(lambda: fn(iso, motion, u0, t_end, method, rtol), repeat=1)
                rows.append((f"solve_ivp {method}", rtol, t, error(u, ref)))
        for label, rtol, t, e in rows:
            print(f"  {label:<28}{rtol:>8.0e}{t * 1000:>10.2f} ms{e:>11.2e}")
        ours = [r for r in rows if r[0].startswith("statue2model")]
        for target in (1e-3, 1e-6):
            o = [r for r in ours if r[3] <= target]
            s = [r for r in rows if r[0].startswith("solve_ivp") and r[3] <= target]
            if o and s:
                bo = min(o, key=lambda r: r[2])
                bs = min(s, key=lambda r: r[2])
                print(f"  error <= {target:.0e}: ours {bo[2] * 1000:.2f} ms, best solve_ivp {bs[0][10:]} "
                      f"{bs[2] * 1000:.1f} ms -> {bs[2] / bo[2]:.0f}x")
            elif o:
                print(f"  error <= {target:.0e}: ours {min(r[2] for r in o) * 1000:.2f} ms; no solve_ivp setting reached it")
    return 0


if __name__ == "__main__":
    sys.exit(main())
