"""The isolator design on the default scan: the spectral search alone (design.design) against the search
verified by time histories (verify.verify: the design set of 7 records, two friction bounds), side by side,
with the verification's parts (the plate runs serial and on 2 worker processes, warm).

    python3 benchmarks/bench_isolator_verify.py     # about 20 s
"""
import time

from statue2model.assessment.study import match_records
from statue2model.compute.executors import make_executor
from statue2model.geometry.body import load_body
from statue2model.io.paths import default_scan
from statue2model.isolator.design import design, longest_period
from statue2model.isolator.verify import REPLACED, friction_bounds, plate_demands, verify
from statue2model.pipeline.config import load_config, site


def best_of(fn, n=3):
    out, best = None, float("inf")
    for _ in range(n):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return out, best


if __name__ == "__main__":
    statue = load_body(default_scan()).rocking()
    hz = site(load_config(None))
    rs, t_set = best_of(lambda: match_records(hz.target, 7, None, T_is=longest_period()))
    kw = dict(mu=0.0073, spectrum=hz.target, thickness=0.03, fuse_release=0.075 * 9.81)
    spec, t_spec = best_of(lambda: design(statue, **kw))
    ver, t_ver = best_of(lambda: verify(statue, records=rs.records, **kw))
    pairs = sorted({(c.R, c.r) for c in spec.evaluated if c.passes(ignore=REPLACED)})
    lo, hi = friction_bounds(0.0073)
    _, t_serial = best_of(lambda: plate_demands(pairs, rs.records, lo, hi))
    with make_executor(workers=2) as ex:
        plate_demands(pairs, rs.records, lo, hi, executor=ex)              # warm the workers
        _, t_pool = best_of(lambda: plate_demands(pairs, rs.records, lo, hi, executor=ex))
    v = ver.verification
    print(f"default scan, {statue.m:.0f} kg; {len(rs.records)} records of {rs.records[0].duration:g} s; "
          f"{v['pairs_run']} (R, r) x 2 bounds = {v['runs']} plate runs")
    print(f"{'step':44s} {'time s':>8s} {'ratio':>7s}")
    for name, t in (("design set (match_records, warm)", t_set), ("spectral search (design)", t_spec),
                    ("verified search (verify, serial)", t_ver), ("  of which plate runs, serial", t_serial),
                    ("  plate runs on 2 warm workers", t_pool)):
        print(f"{name:44s} {t:8.2f} {t / t_spec:7.1f}")
    print(f"spectral choice R {spec.R:g} m r {spec.r * 1000:g} mm ({'pass' if spec.passed else 'FAIL'}); verified "
          f"R {ver.R:g} m r {ver.r * 1000:g} mm ({'pass' if ver.passed else 'FAIL'}), margins {ver.th_margins}")
