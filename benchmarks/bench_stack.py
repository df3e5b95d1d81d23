"""A statue on a pedestal (rocking/stack.py): the compiled kernel against the scipy reference,
side by side: runs per second, the ratio, and the largest relative difference of the peaks.

    python3 benchmarks/bench_stack.py        # about 1 min on 2 cores (the kernels compiled)

* ours     simulate_stack(..., method="compiled"): rocking/stack_kernel.py (numba DOP853 with the
           events on the dense output, the step carried across record samples);
* scipy    simulate_stack(..., method="scipy"): solve_ivp(DOP853) with events, restarted at every
           event and every record sample (the reference of tests/test_stack_kernel.py);
* batch    simulate_stack_batch: the rows of a fragility study (model, scale) in numba's threads,
           runs per second over 64 scales of the record (0.5 to 1.5).

Records: synthetic, 30 s at 0.01 s (seeds 1-3, PGA 0.3-0.5 g); models: a statue that lifts first
on a squat pedestal (statue a = 0.2 g, stack 0.32 g) and a tall stack whose pedestal lifts first
(stack 0.18 g, statue 0.25 g). "peaks" is the largest relative difference of the two bodies'
theta_max / delta; "same" tells whether the outcome and the impact counts agree (where they do not,
the scipy path missed an impact: it looks for events' sign changes at the ends of its steps only,
and a pedestal rocking by microradians can cross theta1 = 0 and come back inside one of them).
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from statue2model.geometry.rocking_params import RockingParams  # noqa: E402
from statue2model.hazard import motions  # noqa: E402
from statue2model.quantities import G  # noqa: E402
from statue2model.rocking.stack import Pedestal, StackModel, simulate_stack, simulate_stack_batch  # noqa: E402

MODELS = {
    "statue first": StackModel(RockingParams.rectangular_block(b=0.1, h=0.5, m=200.0), Pedestal(0.3, 0.5, 300.0)),
    "pedestal first": StackModel(RockingParams.rectangular_block(b=0.15, h=0.6, m=200.0), Pedestal(0.3, 1.0, 300.0)),
}
RECORDS = [(1, 0.3), (2, 0.4), (3, 0.5)]


def _timed(fn, min_time=0.5, max_runs=200):
    runs, t0 = 0, time.perf_counter()
    while True:
        out = fn()
        runs += 1
        el = time.perf_counter() - t0
        if el >= min_time or runs >= max_runs:
            return out, el / runs


def _rel(a, b):
    return abs(a - b) / max(abs(b), 1e-300) if (a or b) else 0.0


def main() -> int:
    simulate_stack(MODELS["statue first"], motions.sine_pulse(0.25 * G, 2.0))      # load the kernels
    rows = []
    for name, model in MODELS.items():
        for seed, pga in RECORDS:
            rec = motions.synthetic_record(duration=30.0, dt=0.01, pga=pga * G, seed=seed)
            rc, t_c = _timed(lambda: simulate_stack(model, rec))
            rs, t_s = _timed(lambda: simulate_stack(model, rec, method="scipy"), min_time=0.0, max_runs=1)
            peaks = max(_rel(rc.statue.theta_max_over_delta, rs.statue.theta_max_over_delta),
                        _rel(rc.pedestal.theta_max_over_delta, rs.pedestal.theta_max_over_delta))
            same = (rc.outcome == rs.outcome and rc.statue.n_impacts == rs.statue.n_impacts
                    and rc.pedestal.n_impacts == rs.pedestal.n_impacts)
            scales = np.linspace(0.5, 1.5, 64)
            _, t_b = _timed(lambda: simulate_stack_batch([model] * scales.size, rec, scales=scales), min_time=0.5,
                            max_runs=20)
            rows.append((name, seed, pga, rc.outcome, rs.outcome, t_c, t_s, t_b / scales.size, peaks, same))
    print(f"{'model':>14} {'rec':>3} {'PGA':>4} | {'outcome (ours)':>16} {'outcome (scipy)':>16} | "
          f"{'ours run/s':>10} {'scipy run/s':>11} {'ratio':>6} | {'batch run/s':>11} | "
          f"{'peaks rel':>9} {'same':>5}")
    for name, seed, pga, oc, os_, tc, ts, tb, pk, same in rows:
        print(f"{name:>14} {seed:>3} {pga:4.2f} | {oc:>16} {os_:>16} | {1 / tc:10.0f} {1 / ts:11.2f} {ts / tc:6.0f} | "
              f"{1 / tb:11.0f} | {pk:9.1e} {str(same):>5}")
    ratios = [ts / tc for *_, tc, ts, _tb, _pk, _s in rows]
    print(f"single-run speed-up: median {np.median(ratios):.0f}x, min {min(ratios):.0f}x; "
          f"max peak difference where the runs agree: "
          f"{max((r[8] for r in rows if r[9]), default=float('nan')):.1e}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
