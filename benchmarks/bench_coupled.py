"""Benchmark: run time against error for the coupled plate + statue model,
statue2model (compiled DOP853 with dense-output events) vs scipy solve_ivp, side by side.

Cases: a 10 kg block (b = 0.05, h = 0.25 m; alpha = 0.6, e = 0.85) on the
three-groove prototype (r = 18.3 mm, M = 16 kg, mu = 0.012) under a 0.3 g,
1 Hz one-cosine pulse starting at 0.1 s: the plate unsticks, the statue lifts,
the plate reverses under it, three impacts, overturning (mode 3). Coulomb and
Bouc-Wen (q = 30) plates. solve_ivp: the independent reference of
tests/test_isolator_coupled.py (DOP853, terminal events, phase by phase;
Bouc-Wen z as an ODE state).

Reference for the errors: ours at rtol 1e-13. Error: the largest of
|theta_max_L - ref| / ref, |u_max - ref| / ref and |t_overturn - ref| / ref.

    python3 benchmarks/bench_coupled.py [--quick]
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path


sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from bench_isolator import timed
from test_isolator_coupled import BLOCK, reference

from statue2model.hazard import motions
from statue2model.rocking.model import RockingModel
from statue2model.isolator.coupled import simulate_coupled
from statue2model.isolator.device import Isolator

G = 9.81




def error(vals, ref):
    return max(abs(v - r) / abs(r) for v, r in zip(vals, ref))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer tolerances")
    args = ap.parse_args()
    rtols = (1e-6, 1e-9) if args.quick else (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
    model = RockingModel.imperfect(BLOCK, alpha_L=0.6, alpha_R=0.6, e_L=0.85, e_R=0.85)
    motion = motions.cosine_pulse(0.3 * G, 1.0, start=0.1)
    t_end = 1.5
    for plate in ("coulomb", "boucwen"):
        iso = Isolator(R=0.30, r=0.0183, M=16.0, mu=0.012, model=plate, q=30.0)
        simulate_coupled(iso, model, motion, t_end=t_end)  # compile
        r = simulate_coupled(iso, model, motion, t_end=t_end, rtol=1e-13)
        ref = (r.theta_max_L, r.u_max, r.overturn_time)
        print(f"\n{plate} plate, one-cosine 0.3 g 1 Hz: {r.outcome}, {r.n_impacts} impacts, "
              f"t_overturn = {r.overturn_time:.9f} s")
        print(f"  {'solver':<30}{'rtol':>8}{'time':>12}{'error':>11}")
        rows = []
        for rtol in rtols:
            t, res = timed(lambda iso=iso, rtol=rtol: simulate_coupled(iso, model, motion, t_end=t_end, rtol=rtol))
            rows.append(("statue2model DOP853 + events", rtol, t,
                         error((res.theta_max_L, res.u_max, res.overturn_time), ref)))
        for rtol in rtols:
            t, out = timed(lambda iso=iso, rtol=rtol: reference(iso, model, motion, t_end, rtol=rtol), repeat=1)
            qL, _, umax, _, t_over = out
            rows.append(("solve_ivp DOP853 (phases)", rtol, t, error((qL, umax, t_over), ref)))
        for label, rtol, t, e in rows:
            print(f"  {label:<30}{rtol:>8.0e}{t * 1000:>10.2f} ms{e:>11.2e}")
        for target in (1e-6, 1e-9):
            o = [x for x in rows if x[0].startswith("statue2model") and x[3] <= target]
            s = [x for x in rows if x[0].startswith("solve_ivp") and x[3] <= target]
            if o and s:
                bo = min(o, key=lambda x: x[2])
                bs = min(s, key=lambda x: x[2])
                print(f"  error <= {target:.0e}: ours {bo[2] * 1000:.2f} ms, solve_ivp {bs[2] * 1000:.1f} ms "
                      f"-> {bs[2] / bo[2]:.0f}x")
            elif o:
                print(f"  error <= {target:.0e}: ours {min(x[2] for x in o) * 1000:.2f} ms; "
                      "no solve_ivp setting reached it")
    # a long record: ours only (the scipy reference takes minutes)
    from statue2model.geometry.rocking_params import RockingParams

    statue = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.8})
    weak = RockingModel.imperfect(statue, alpha_L=0.175, alpha_R=0.175, e_L=0.9, e_R=0.9)
    record = motions.synthetic_record(duration=10.0, pga=0.32 * G, seed=4)
    print("\nLandolina-like statue (12.1 kg) on a 16.4 kg plate, 10 s record 0.32 g, 20 s simulated")
    for plate in ("coulomb", "boucwen"):
        iso = Isolator(R=0.30, r=0.02, M=16.433, mu=0.0073, model=plate)
        ref = simulate_coupled(iso, weak, record, rtol=1e-12)
        for rtol in ((1e-9,) if args.quick else (1e-6, 1e-9)):
            t, res = timed(lambda iso=iso, rtol=rtol: simulate_coupled(iso, weak, record, rtol=rtol))
            e = error((res.theta_max_L, res.theta_max_R, res.u_max), (ref.theta_max_L, ref.theta_max_R, ref.u_max))
            print(f"  {plate:<9} rtol {rtol:.0e}: {t * 1000:8.2f} ms, {res.n_impacts} impacts, "
                  f"{res.stats['steps']} steps, error vs rtol 1e-12 {e:.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
