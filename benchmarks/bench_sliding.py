"""Sliding of one body: the exact stick-slip integration (rocking/sliding.py) against two
independent ones, side by side: run time and the error of the peak sliding displacement.

    python3 benchmarks/bench_sliding.py        # about 1 min on 2 cores

* ours     statue2model.rocking.sliding.simulate_sliding: closed-form onsets and stops on the
           record's own samples (no time step);
* fine     the same stick-slip law in fixed steps of 2e-5 s (trapezoid), pure Python
           (tests/test_sliding.py fine_step_sliding);
* scipy    scipy.integrate.solve_ivp (RK45, rtol 1e-10, atol 1e-12, max_step 1e-3) phase by phase,
           with a stop event (u' = 0) while sliding and an onset event (|a_g| = mu_s g) while stuck.

The reference for the errors is the fine integrator at 5e-6 s (1e-5 s at 0.3 and 0.8 g). Records: synthetic, 10 s at 0.01 s,
PGA 0.3, 0.5 and 0.8 g, under mu_s 0.4, mu_k 0.3 (a statue on a pedestal, the 2020 study's values).
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from statue2model.hazard import motions  # noqa: E402
from statue2model.quantities import G  # noqa: E402
from statue2model.rocking.sliding import Friction, simulate_sliding  # noqa: E402
from test_sliding import fine_step_sliding  # noqa: E402  (the tests' independent integrator)


def fine(friction, motion, dt):
    return fine_step_sliding(friction, motion, dt)[0]


def scipy_phases(friction, motion):
    from scipy.integrate import solve_ivp

    mus, c = friction.mu_s * G, friction.mu_k * G
    t_end = motion.end + 3.0
    t0, u, s, umax = 0.0, 0.0, 0.0, 0.0
    while t0 < t_end:
        if s == 0.0:                                   # stuck: find the onset
            def onset(t, y):
                return abs(float(motion.acc(np.array([t]))[0])) - mus
            onset.terminal, onset.direction = True, 1
            r = solve_ivp(lambda t, y: [0.0], (t0, t_end), [0.0], events=onset, max_step=1e-3, rtol=1e-10,
                          atol=1e-12)
            if not r.t_events[0].size:
                break
            t0 = float(r.t_events[0][0])
            s = -math.copysign(1.0, float(motion.acc(np.array([t0]))[0]))
            continue

        def f(t, y, s=s):
            return [y[1], -float(motion.acc(np.array([t]))[0]) - s * c]

        def stop(t, y):
            return y[1]
        stop.terminal, stop.direction = True, -s          # v returns to 0 from its side
        r = solve_ivp(f, (t0, t_end), [u, 0.0], events=stop, max_step=1e-3, rtol=1e-10, atol=1e-12,
                      first_step=1e-6)
        u = float(r.y[0, -1]) if not r.t_events[0].size else float(r.y_events[0][0][0])
        umax = max(umax, float(np.abs(r.y[0]).max()), abs(u))
        if not r.t_events[0].size:
            break
        t0 = float(r.t_events[0][0]) + 1e-9
        a_now = float(motion.acc(np.array([t0]))[0])
        s = -math.copysign(1.0, a_now) if abs(a_now) > mus else 0.0
    return umax


def main() -> int:
    f = Friction(0.40, 0.30)
    rows = []
    for pga in (0.3, 0.5, 0.8):
        rec = motions.synthetic_record(duration=10.0, dt=0.01, pga=pga * G, seed=7)
        ref = fine(f, rec, 5e-6) if pga == 0.5 else fine(f, rec, 1e-5)
        t = time.perf_counter()
        for _ in range(20):
            ours = simulate_sliding(f, rec).u_max
        t_ours = (time.perf_counter() - t) / 20
        t = time.perf_counter()
        fi = fine(f, rec, 2e-5)
        t_fine = time.perf_counter() - t
        t = time.perf_counter()
        sc = scipy_phases(f, rec)
        t_sc = time.perf_counter() - t
        rows.append((pga, ref, ours, t_ours, fi, t_fine, sc, t_sc))

    def err(x, ref):
        return abs(x - ref) / ref if ref > 0 else abs(x)
    print(f"{'PGA':>5} {'u_max ref mm':>13} | {'ours err':>9} {'ms':>8} | {'fine err':>9} {'ms':>8} | "
          f"{'scipy err':>9} {'ms':>8} | {'fine/ours':>9} {'scipy/ours':>10}")
    for pga, ref, o, to, fi, tf, sc, ts in rows:
        print(f"{pga:5.2f} {ref * 1000:13.3f} | {err(o, ref):9.2e} {to * 1000:8.2f} | {err(fi, ref):9.2e} "
              f"{tf * 1000:8.1f} | {err(sc, ref):9.2e} {ts * 1000:8.1f} | {tf / to:9.0f} {ts / to:10.0f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
