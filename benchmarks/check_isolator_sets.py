"""An independent check of a passing isolator design's travel on record sets it was never designed on.

The isolator stage (pipeline/stages.py isolator_stage -> isolator/verify.py) chooses the device on the design
set (seeds 1..7) and checks it on three further sets (seeds 101.., 201.., 301..). This script takes the
design's design.json and asks whether the groove capacity also holds on three FRESH code-compliant sets the
design never saw: seeds 401.., 501.., 601.. (``--seeds``), matched like the design set (same target, band
and size: assessment.study.match_records with the site's target, T_is = isolator.design.longest_period(),
code = the site's ground code; the site is ``--site``, checked against the spectrum in design.json).

The top plate is integrated by THIS script's own solver (nothing of isolator/time_history.py or kernel.py):
the Coulomb pendulum

    u'' + (g / R_hat) u + mu g sgn(u') = -a_g(t)

with stick-slip: stuck (u' = 0) while |a_g + (g / R_hat) u| <= mu g. A stuck phase ends where the record's
(piecewise linear) |a_g + (g / R_hat) u| first exceeds mu g, found exactly on its segments; the plate then
leaves on the side of -(a_g + (g / R_hat) u). A sliding phase of direction s runs on
scipy.integrate.solve_ivp (DOP853, rtol 1e-10, atol 1e-12): up to the record's next sample in the plate's
own coordinates (u, u'), then in absolute ones (x = u + D_g, y = u' + V_g, the ground's velocity and
displacement integrated exactly from the linear record: a forcing smooth to its second derivative, where
a_g has a kink at every sample that makes adaptive steps crawl), steps at most half the record's dt. It
ends at the event u' = 0, where the plate sticks (|a_g + (g / R_hat) u| <= mu g) or turns back; since
solve_ivp sees a sign change only at the ends of a step, the run also stops at every local minimum of s u'
and looks there for a zero it stepped over (a stop of a few milliseconds). The record is linear between
samples and zero outside; every run goes on 10 s after the record ends (as the package's simulate does).
The peak |u| is the largest |u| at the stops and the ends of the phases. About 1 s a record.

Each record runs at mu_low and mu_high of design.json's verification (the friction bounds the design was
verified at). Per set: u = the larger over the two bounds of the mean over the records of the peak |u|
(the package's rule, verify.Peaks.stat; the mean of each record's larger bound is printed too), the need
1.5 u + mu_high R_hat, the design's capacity, ratio = need / capacity (<= 1 passes), PASS/FAIL.

Sanity rows: (1) the design set (seeds 1..7) by this solver against the travel design.json records for it;
(2) one record (the first of the first fresh set, at mu_low) by this solver against the package's
statue2model.isolator.time_history.simulate (peak travel, relative difference).

Without ``--design`` it first runs ``statue2model run --stages params,isolator --out TMP`` on the default
scan (a minute or two) and reads TMP/isolator/design.json. Exit status 0 always (it is a report).

    python3 benchmarks/check_isolator_sets.py                         # default scan, run the pipeline
    python3 benchmarks/check_isolator_sets.py --design outputs/dancing_girl/isolator/design.json
    python3 benchmarks/check_isolator_sets.py --quick                 # one fresh set (seeds 401..)
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
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

DEFAULT_SITE = "ec8:ag=0.25g,ground=C,type=1"    # the pipeline's default [isolator] spectrum
MAX_STEP = 0.5
"""Steps of a sliding phase at most this many record steps (u' may touch 0 and turn back within a long
step, where the event, seen only at the ends of steps, would miss the stop)."""
FREE_TIME = 10.0                                 # s of free motion after the record
DISPLACEMENT_MARGIN = 1.5                        # the design level's travel rule: 1.5 u + mu_high R_hat


# --- the independent solver -------------------------------------------------------------------------
class Record:
    """The ground: a_g(t) samples every dt from start, linear in between, zero outside; its velocity V_g and
    displacement D_g integrated exactly (piecewise quadratic and cubic) from rest at the start."""

    def __init__(self, samples, dt, start=0.0):
        a = np.asarray(samples, dtype=float)
        h = float(dt)
        self.a, self.dt, self.start = a, h, float(start)
        self.end = self.start + h * (a.size - 1)
        da = np.diff(a)
        self.V = np.concatenate(([0.0], np.cumsum(a[:-1] * h + da * h / 2)))
        self.D = np.concatenate(([0.0], np.cumsum(self.V[:-1] * h + a[:-1] * h * h / 2 + da * h * h / 6)))

    def _seg(self, t):
        k = min(max(int((t - self.start) / self.dt), 0), self.a.size - 2)
        return k, t - (self.start + k * self.dt), (self.a[k + 1] - self.a[k]) / self.dt

    def __call__(self, t: float) -> float:
        """a_g(t), m/s^2."""
        if t < self.start or t > self.end:
            return 0.0
        k, tau, j = self._seg(t)
        return self.a[k] + j * tau

    def right(self, t: float) -> float:
        """a_g just after t (the record's last sample ends at a jump to rest)."""
        return 0.0 if t >= self.end else self(t)

    def vel(self, t: float) -> float:
        if t < self.start:
            return 0.0
        if t > self.end:
            return self.V[-1]
        k, tau, j = self._seg(t)
        return self.V[k] + self.a[k] * tau + j * tau * tau / 2

    def disp(self, t: float) -> float:
        if t < self.start:
            return 0.0
        if t > self.end:
            return self.D[-1] + self.V[-1] * (t - self.end)
        k, tau, j = self._seg(t)
        return self.D[k] + self.V[k] * tau + self.a[k] * tau * tau / 2 + j * tau ** 3 / 6

    def unstick(self, t0: float, offset: float, limit: float) -> float | None:
        """The first t > t0 where |a_g(t) + offset| > limit (a_g piecewise linear), None if never
        (the ground at rest after the record: only where |offset| > limit, at once)."""
        if t0 < self.end:
            k0 = max(int((t0 - self.start) / self.dt), 0) if t0 >= self.start else -1
            times = self.start + self.dt * np.arange(k0 + 1, self.a.size)
            vals = self.a[k0 + 1:] + offset
            tt = np.concatenate(([t0], times))
            ff = np.concatenate(([self(t0) + offset], vals))
            out = np.nonzero(np.abs(ff[1:]) > limit)[0]
            if out.size:
                i = out[0]
                fa, fb, ta, tb = ff[i], ff[i + 1], tt[i], tt[i + 1]
                c = limit if fb > limit else -limit
                return float(ta + (c - fa) / (fb - fa) * (tb - ta)) if fb != fa else float(tb)
            # beyond the last sample the ground jumps to rest
            return self.end if abs(offset) > limit else None
        return t0 if abs(offset) > limit else None


def _slide(rec: Record, w2: float, F: float, s: float, t0: float, u0: float, v0: float, t1: float,
           relative: bool, rtol: float, atol: float, events: bool = True, max_step: float = np.inf):
    """One sliding phase of direction s from (t0, u0, v0) to t1 or to the first u' = 0: (t, u, v, stopped
    at u' = 0). solve_ivp sees an event only where it changes sign between the ends of a step, so u' s
    touching 0 and turning back within one step would be missed: the integration also stops at every
    local minimum of u' s (the event s u'' = 0, upward) and, where u' s is <= 0 there, the first zero is
    found on the step's dense output (brentq)."""
    if relative:        # u'' = -(g / R_hat) u - s mu g - a_g(t): exact signs near u' = 0, forcing kinked
        def rhs(tt, z):
            return (z[1], -w2 * z[0] - s * F - rec(tt))

        def uv(tt, z):
            return z[0], z[1]

        def to_state(u, v, tt):
            return (u, v)
    else:               # x = u + D_g, y = u' + V_g: x'' = -(g / R_hat) (x - D_g(t)) - s mu g, forcing C2
        def rhs(tt, z):
            return (z[1], -w2 * (z[0] - rec.disp(tt)) - s * F)

        def uv(tt, z):
            return z[0] - rec.disp(tt), z[1] - rec.vel(tt)

        def to_state(u, v, tt):
            return (u + rec.disp(tt), v + rec.vel(tt))

    def stop(tt, z):                              # u' s = 0, downward
        return uv(tt, z)[1] * s

    def least(tt, z):                             # s u'' = 0, upward: a local minimum of u' s
        u, _ = uv(tt, z)
        return s * (-w2 * u - s * F - rec(tt))

    stop.terminal, stop.direction = True, -1
    least.terminal, least.direction = True, 1
    t, u, v = t0, u0, v0
    while t < t1:
        sol = solve_ivp(rhs, (t, t1), to_state(u, v, t), method="DOP853", rtol=rtol, atol=atol,
                        events=[stop, least] if events else None, max_step=max_step, dense_output=events)
        if not events or sol.status == 0:
            u, v = uv(sol.t[-1], sol.y[:, -1])
            return float(sol.t[-1]), float(u), float(v), False
        if sol.t_events[0].size:
            te = float(sol.t_events[0][0])
            return te, float(uv(te, sol.y_events[0][0])[0]), 0.0, True
        tm = float(sol.t_events[1][0])
        um, vm = uv(tm, sol.y_events[1][0])
        if vm * s > 0.0 or tm <= t:               # only a minimum (or none yet): go on from there
            if tm <= t:                           # the minimum at the start itself: step past it
                tm = min(t + 1e-3 * rec.dt, t1)
                um, vm = uv(tm, sol.sol(tm))
            t, u, v = tm, float(um), float(vm)
            continue
        left = float(sol.t[-2]) if len(sol.t) > 1 else t

        def f(tt, sol=sol):
            return uv(tt, sol.sol(tt))[1] * s

        if f(left) <= 0.0:
            te = left
        else:
            te = brentq(f, left, tm, xtol=1e-14, rtol=1e-12)
        return te, float(uv(te, sol.sol(te))[0]), 0.0, True
    return t, u, v, False


def plate_peak(rec: Record, R_hat: float, mu: float, g: float, t_final: float | None = None,
               rtol: float = 1e-10, atol: float = 1e-12) -> float:
    """Peak |u| (m) of the Coulomb pendulum (module docstring) from rest under ``rec``.

    A sliding phase starts (u' = 0) in the plate's own coordinates up to the next sample of the record
    (the signs of u' near 0 exact), then goes on in absolute coordinates x = u + D_g, y = u' + V_g, whose
    forcing D_g is smooth to the second derivative (a_g has a kink at every sample, which would make the
    adaptive steps crawl); it ends at the event u' = 0."""
    w2 = g / R_hat
    F = mu * g
    T = 2 * math.pi / math.sqrt(w2)
    t_final = rec.end + FREE_TIME if t_final is None else t_final
    t, u, v = 0.0, 0.0, 0.0
    peak = 0.0
    stuck = True
    s = 0.0
    for _ in range(1_000_000):
        if t >= t_final:
            break
        if stuck:
            tu = rec.unstick(t, w2 * u, F)
            if tu is None or tu >= t_final:
                break
            t = max(tu, t)
            s = -math.copysign(1.0, rec.right(t) + w2 * u)     # the side it leaves on
            stuck, v = False, 0.0
        stop = rec.start if t < rec.start else (rec.end if t < rec.end else t_final)
        if v == 0.0 and t < rec.end:             # the start of a phase: to the next sample, own coordinates
            k = math.floor((t - rec.start) / rec.dt + 1e-9) + 1
            first = min(rec.start + k * rec.dt, stop) if t >= rec.start else stop
            t2, u, v, hit = _slide(rec, w2, F, s, t, u, 0.0, first, True, rtol, atol)
        else:
            t2, u, v, hit = _slide(rec, w2, F, s, t, u, v, stop, False, rtol, atol,
                                   max_step=(MAX_STEP * rec.dt if t < rec.end else T / 40))
        if hit and t2 <= t:
            # a marginal start (|a_g + (g / R_hat) u| = mu g to the last digit): a microsecond without the event
            t2, u, v, _ = _slide(rec, w2, F, s, t, u, 0.0, min(t + 1e-6, stop), True, rtol, atol, events=False)
            t = t2
            if v * s <= 0.0:                     # it cannot move that way: stuck
                stuck, v = True, 0.0
            continue
        t = t2
        peak = max(peak, abs(u))
        if hit:
            f = rec.right(t) + w2 * u
            if abs(f) <= F:
                stuck = True
            else:
                s = -math.copysign(1.0, f)
    return peak


def to_record(m) -> Record:
    if m.kind != "record":
        raise SystemExit(f"motion {m.label!r} is not a sampled record")
    return Record(m.samples, m.dt, m.start)


def set_peaks(records, R_hat, lo, hi, g) -> tuple[np.ndarray, np.ndarray]:
    recs = [to_record(m) for m in records]
    return (np.array([plate_peak(r, R_hat, lo, g) for r in recs]),
            np.array([plate_peak(r, R_hat, hi, g) for r in recs]))


# --- the harness -------------------------------------------------------------------------------------
def run_pipeline(out: Path, workers: int | None) -> Path:
    exe = Path(sys.executable).with_name("statue2model")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "statue2model"]
    cmd += ["run", "--stages", "params,isolator", "--out", str(out)]
    if workers:
        cmd += ["--workers", str(workers)]
    print("running:", " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    hits = sorted(out.rglob("design.json"))
    if not hits:
        raise SystemExit(f"no design.json under {out}")
    return hits[0]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--design", default=None, help="design.json (default: run the default scan's params,isolator)")
    ap.add_argument("--site", default=DEFAULT_SITE, help=f"the site's ground spectrum (default {DEFAULT_SITE!r})")
    ap.add_argument("--seeds", default="401,501,601", help="first seeds of the fresh sets (default 401,501,601)")
    ap.add_argument("--records", type=int, default=7, help="records per set (default 7, the design set's)")
    ap.add_argument("--workers", type=int, default=2, help="workers of the pipeline run (default 2)")
    ap.add_argument("--quick", action="store_true", help="one fresh set only")
    a = ap.parse_args()
    t0 = time.perf_counter()
    from statue2model.assessment.study import match_records
    from statue2model.hazard.site import site_hazard
    from statue2model.isolator.design import longest_period
    from statue2model.quantities import G

    tmp = None
    if a.design is None:
        tmp = tempfile.TemporaryDirectory()
        path = run_pipeline(Path(tmp.name) / "run", a.workers)
        t_pipe = time.perf_counter() - t0
    else:
        path, t_pipe = Path(a.design), 0.0
    d = json.loads(path.read_text())
    v = d.get("verification") or {}
    R_hat, cap = float(d["R_hat"]), float(d["capacity"])
    lo, hi = float(v["mu_low"]), float(v["mu_high"])
    g = G
    hz = site_hazard(a.site)
    same = (d.get("input") or {}).get("spectrum") == json.loads(json.dumps(hz.target.to_dict()))
    print(f"design: {path}" + (f" (pipeline {t_pipe:.0f} s)" if t_pipe else ""))
    print(f"  {'PASSED' if d.get('passed') else 'NOT PASSED'} by the package; {d.get('layout')} {d.get('n_balls')} "
          f"balls r {float(d['r']) * 1000:g} mm on {d.get('surface')}, R {float(d['R']):g} m, R_hat {R_hat:.4f} m, "
          f"T {float(d['T']):.2f} s, capacity {cap:.4f} m, mu_low {lo:g}, mu_high {hi:g}")
    print(f"  site {a.site}: {'the spectrum of design.json' if same else 'NOT the spectrum of design.json (check --site)'}")
    if not d.get("passed"):
        print("  note: the design did not pass; its capacity is checked all the same")

    def match(seed):
        return match_records(hz.target, a.records, None, T1=None, T_is=longest_period(), seed=seed,
                             code=hz.ground.code)

    seeds = [int(s) for s in a.seeds.split(",")][: 1 if a.quick else None]
    rows, t_solve = [], 0.0

    def one(name, records, rules):
        nonlocal t_solve
        t = time.perf_counter()
        ul, uh = set_peaks(records, R_hat, lo, hi, g)
        t_solve += time.perf_counter() - t
        u = max(float(ul.mean()), float(uh.mean()))
        need = DISPLACEMENT_MARGIN * u + hi * R_hat
        rows.append({"name": name, "n": len(records), "rules": rules, "ul": float(ul.mean()),
                     "uh": float(uh.mean()), "u_rec": float(np.maximum(ul, uh).mean()), "u": u, "need": need,
                     "ratio": need / cap})
        return rows[-1]

    ref = one("design 1-7 (reference)", match(1).records, "-")
    pkg = {s.get("name"): s for s in v.get("sets") or []}.get("design") or {}
    fresh = []
    for s0 in seeds:
        rs = match(s0)
        fresh.append(one(f"fresh {s0}-{s0 + len(rs.records) - 1}", rs.records,
                         "met" if rs.check()["met"] else "NOT met"))
        if s0 == seeds[0]:
            first = rs.records[0]

    # sanity: one record against the package's own plate solver
    from statue2model.isolator.device import Isolator
    from statue2model.isolator.time_history import simulate

    mine = plate_peak(to_record(first), R_hat, lo, g)
    theirs = simulate(Isolator(R=R_hat / 2 + 0.01, r=0.01, M=1.0, mu=lo, g=g), first, dt_out=1.0).u_max
    rel = abs(mine - theirs) / theirs if theirs > 0 else float("nan")

    print()
    print(f"{'set':26s} {'n':>2s} {'rules':>7s} {'u(mu_lo)':>9s} {'u(mu_hi)':>9s} {'mean max':>9s} "
          f"{'1.5u+muR':>9s} {'capacity':>9s} {'ratio':>6s}  verdict")
    for r in rows:
        verdict = "PASS" if r["ratio"] <= 1.0 else "FAIL"
        print(f"{r['name']:26s} {r['n']:2d} {r['rules']:>7s} {r['ul']:9.4f} {r['uh']:9.4f} {r['u_rec']:9.4f} "
              f"{r['need']:9.4f} {cap:9.4f} {r['ratio']:6.3f}  {verdict}")
    print("(travels in m; u = the larger bound's mean over the set's records; 'mean max': the mean of each "
          "record's larger bound; ratio = need / capacity)")
    print()
    print("sanity rows")
    if pkg.get("travel") is not None:
        dp = abs(ref["u"] - float(pkg["travel"])) / float(pkg["travel"])
        print(f"  design set, this solver u {ref['u']:.5f} m vs design.json verification {float(pkg['travel']):.5f} m: "
              f"relative difference {dp:.2e}")
    print(f"  record {first.label!r} at mu_low {lo:g}: this solver {mine:.6f} m vs time_history.simulate "
          f"{theirs:.6f} m: relative difference {rel:.2e}")
    worst = max(fresh, key=lambda r: r["ratio"])
    n_ok = sum(r["ratio"] <= 1.0 for r in fresh)
    print()
    print(f"SUMMARY: {'PASS' if n_ok == len(fresh) else 'FAIL'}: the capacity {cap:.4f} m holds on {n_ok} of "
          f"{len(fresh)} fresh sets (worst: {worst['name']}, need {worst['need']:.4f} m, ratio {worst['ratio']:.3f}); "
          f"solver vs package on one record {rel:.1e}; {t_solve:.0f} s of own-solver runs, "
          f"{time.perf_counter() - t0:.0f} s in all")
    if tmp is not None:
        tmp.cleanup()
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except SystemExit:
        raise
    except Exception as exc:  # noqa: BLE001 - a report: say what went wrong, exit 0
        import traceback

        traceback.print_exc()
        print(f"SUMMARY: NOT CHECKED: {type(exc).__name__}: {exc}")
        sys.exit(0)
