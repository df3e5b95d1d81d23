"""2D vs 3D over an ensemble of records, and the imperfect base (crosscheck/ensemble.py, imperfect.py).

    python3 benchmarks/bench_crosscheck_ensemble.py [--quick] [--records N] [--block] [--imperfect]
                                                    [--workers N]

Prints the per-level table (overturning probability with Wilson 95 % intervals, median peak
|theta|/delta with order-statistic intervals, 2D vs 3D, targets met or why not), the same 3D runs
judged against a 2D model with a wrong restitution (e x 0.6: must fail), and the wall time;
``--imperfect`` also prints the imperfect-base cases. Default: the default scan's statue.
"""
from __future__ import annotations

import argparse
import time


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="3-5 s records, 1 s of free motion")
    ap.add_argument("--records", type=int, default=20)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--block", action="store_true", help="a 0.2 x 1.0 m block instead of the statue")
    ap.add_argument("--imperfect", action="store_true", help="also the imperfect-base cases")
    a = ap.parse_args()

    from statue2model.crosscheck import ensemble as ens
    from statue2model.crosscheck.output import table
    from statue2model.crosscheck.restitution import model_2d
    from statue2model.crosscheck.statue_scene import StatueScene

    if a.block:
        sc = StatueScene.block(b=0.1, h=0.5, m=100.0)
    else:
        from statue2model.geometry.body import load_body
        from statue2model.io.paths import default_scan

        sc = StatueScene.from_body(load_body(default_scan()))
    print(f"scene: {sc.name}")
    if a.imperfect:
        from statue2model.crosscheck.imperfect import imperfect_cases

        t = time.perf_counter()
        part = imperfect_cases(sc, quick=a.quick)
        cases, runs = part.cases, part.runs
        print(table(cases))
        ident = runs["imperfect base: identification"]
        for s in ("L", "R"):
            d = ident[s]
            print(f"  {s}: alpha pulses {d['alpha']:.4f}, push-over intercept {d['alpha_ramp']:.4f}, "
                  f"theta {d['theta']:.5f} rad (geometry: alpha {ident['geometry'][f'alpha_{s}']:.3f}, "
                  f"theta {ident['geometry'][f'theta_{s}']:.5f})")
        print(f"  e from 3D free rocking: {runs['imperfect base: restitution']}")
        print(f"imperfect base: wall time {time.perf_counter() - t:.1f} s\n")
    t = time.perf_counter()
    ok = ens.ensemble_cases(sc, n_records=a.records, quick=a.quick, workers=a.workers,
                            progress=lambda m: print(f"  {m}", flush=True))
    cases, res = ok.comparison.cases, ok.results
    print(ens.level_table(res))
    print(f"ensemble: wall time {res['wall_time_s']:.1f} s (2D {res['wall_time_2d_s']:.1f} s, 3D "
          f"{res['wall_time_3d_s']:.1f} s on {res['executor']}; 3D {res['sim_time_3d_s']:.0f} s simulated, "
          f"{res['real_time_factor_3d']:.1f} x real time per worker)")
    wrong = model_2d(sc, scale=0.6)
    wrong_e = ens.ensemble_cases(sc, n_records=a.records, quick=a.quick, model=wrong, pga_ref=res["pga_ref"],
                                 runs_3d=res["runs_3d"])
    bad, res2 = wrong_e.comparison.cases, wrong_e.results
    print("\nthe same 3D runs against a 2D model with e x 0.6 (must fail):")
    print(ens.level_table(res2))
    print(f"{sum(c.met for c in bad)} of {len(bad)} cases met (correct 2D: {sum(c.met for c in cases)} of "
          f"{len(cases)}); total {time.perf_counter() - t:.1f} s")


if __name__ == "__main__":
    main()
