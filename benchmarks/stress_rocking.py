"""Stress test of the 2D rocking engine: many random cases over wide ranges.

Draws ``--n`` cases (seeded) in four categories and runs each through
``statue2model.rocking.simulate``:

- pulse:  one-cosine / one-sine / sine trains / rectangular pulses, up to 5 g, some
          just above the uplift limit (a grazing uplift);
- record: seeded white-noise, random-walk and Kanai-Tajimi records, 0.2-60 s, up to 5 g;
- free:   release from theta0 (and omega0) with restitution that cannot add energy;
          the mechanical energy must never increase along the sampled history;
- hard:   60 s records at 3-5 g with e = 1 on a side, theta_side down to 1e-12 rad
          and alpha down to 0.05.

Bodies: h in [0.05, 5] m, b = h tan(delta), delta_L, delta_R in [0.01, 0.7]
(asymmetric half of the time); alpha in [0.05, 1]; theta_side from 1e-12 rad to
10 delta; e in [0, 1] (constant or a table); linearised now and then.

Every run is checked for: an exception; a hang (the solver's step budget
``--max-steps`` exceeded, or its stall guard); |theta| <= delta_side unless
overturned (maxima, peaks, history); maxima at least the sampled history (to
10 rtol delta); the same results with and without an output grid (theta_max,
impacts, impact times, overturning, steps); and - free runs - energy that never
grows by more than 1e-7 E(0) (plus 1e-8 E(0) per impact, for drift at e = 1).
Prints a table and every failing case as a Python reproducer; exits 1 on any
failure.

Run:  python3 benchmarks/stress_rocking.py [--n 2000] [--seed 0] [--jobs 2]
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))   # the working tree's package

G = 9.81
CATEGORIES = ("pulse", "record", "free", "hard")
WEIGHTS = (0.35, 0.25, 0.25, 0.15)
DELTA_TOL = 1e-12
SLOW_S = 2.0            # a run slower than this is not repeated without output (time)
ENERGY_RTOL = 1e-7
FREE_RTOL = 1e-10       # for a swing of delta; scaled down with the amplitude (absolute tolerance)


# --- random cases (plain dicts: printable, picklable, rebuilt in the worker) ----------
def _theta_side(rng, delta, hard=False):
    r = rng.random()
    if hard and r < 0.5:
        return float(rng.choice([1e-12, 1e-9]))
    if r < 0.2:
        return 1e-9
    if r < 0.4:
        return float(10.0 ** rng.uniform(-12, -4))
    if r < 0.8:
        return float(rng.uniform(1e-3, 1.0) * delta)
    return float(rng.uniform(1.0, 10.0) * delta)


def _e(rng, e_max=1.0):
    r = rng.random()
    if r < 0.1:
        n = int(rng.integers(2, 5))
        return {"speeds_rad_s": np.cumsum(rng.uniform(0.01, 2.0, n)).tolist(),
                "values": rng.uniform(0.0, e_max, n).tolist()}
    if r < 0.25:
        return float(e_max)
    if r < 0.3:
        return 0.0
    return float(rng.uniform(0.0, e_max))


def draw_case(rng, cat: str, idx: int) -> dict:
    h = float(rng.uniform(0.05, 5.0))
    d_R = float(rng.uniform(0.01, 0.7))
    d_L = d_R if rng.random() < 0.5 else float(rng.uniform(0.01, 0.7))
    b_R, b_L = h * math.tan(d_R), h * math.tan(d_L)
    m = float(10.0 ** rng.uniform(-1, 4))
    I_G = float(rng.uniform(0.3, 3.0) * m * ((0.5 * (b_L + b_R)) ** 2 + h * h) / 3.0)
    I_L, I_R = I_G + m * (b_L**2 + h * h), I_G + m * (b_R**2 + h * h)
    case = {"id": idx, "cat": cat, "body": {"m": m, "h": h, "b_L": b_L, "b_R": b_R, "I_G": I_G}}
    hard = cat == "hard"
    if cat == "free":
        e_max_L, e_max_R = min(1.0, math.sqrt(I_R / I_L)), min(1.0, math.sqrt(I_L / I_R))
    else:
        e_max_L = e_max_R = 1.0
    model = {"linearised": bool(rng.random() < 0.15 and not hard), "e_L": _e(rng, e_max_L), "e_R": _e(rng, e_max_R)}
    if hard:
        side = rng.integers(0, 3)
        if side in (0, 2):
            model["e_L"] = 1.0
        if side in (1, 2):
            model["e_R"] = 1.0
    if rng.random() < 0.15 and not hard:
        model.update(kind="housner")
    else:
        lo = 0.05
        model.update(kind="imperfect",
                     alpha_L=0.05 if hard and rng.random() < 0.5 else float(rng.uniform(lo, 1.0)),
                     alpha_R=0.05 if hard and rng.random() < 0.5 else float(rng.uniform(lo, 1.0)),
                     theta_L=_theta_side(rng, d_L, hard), theta_R=_theta_side(rng, d_R, hard))
    case["model"] = model
    limit = max(G * math.tan(d_L), G * math.tan(d_R))   # a_side, the largest uplift limit
    if cat == "free":
        side = 1 if rng.random() < 0.5 else -1
        delta = d_R if side > 0 else d_L
        case["theta0"] = side * float(rng.uniform(1e-3, 0.99)) * delta
        case["omega0"] = 0.0 if rng.random() < 0.5 else float(rng.uniform(-1, 1)) * delta * 3.0
        case["motion"] = {"kind": "free"}
        case["t_end"] = 8.0
        return case
    case["theta0"] = 0.0
    case["omega0"] = 0.0
    if cat == "pulse":
        r = rng.random()
        sign = float(rng.choice([-1, 1]))
        side_limit = G * math.tan(d_L if sign > 0 else d_R)    # a_side, pushed by this sign
        if model.get("linearised"):
            side_limit = G * (d_L if sign > 0 else d_R)
        alpha = model.get("alpha_L" if sign > 0 else "alpha_R", 1.0)
        if r < 0.4:
            amp = float(rng.uniform(-5, 5) * G)
        elif r < 0.8:
            amp = sign * min(float(rng.uniform(0.5, 4.0)) * limit, 5 * G)
        else:   # just above the uplift limit of the pushed side: a grazing uplift
            amp = sign * min((1.0 + 10.0 ** -float(rng.integers(1, 13))) * alpha * side_limit, 5 * G)
        kind = str(rng.choice(["cosine", "sine", "sines", "rect"]))
        mo = {"kind": kind, "amp": amp}
        if kind == "rect":
            mo["dur"] = float(rng.uniform(0.005, 2.0))
        else:
            mo["freq"] = float(rng.uniform(0.2, 20.0))
            if kind == "sines":
                mo["cycles"] = float(rng.uniform(0.5, 6.0))
        case["motion"] = mo
        return case
    if hard:
        duration, pga = 60.0, float(rng.uniform(3.0, 5.0) * G)
    else:
        duration = float(rng.uniform(0.2, 10.0) if rng.random() < 0.6 else rng.uniform(10.0, 60.0))
        pga = float(rng.uniform(0.01, 5.0) * G) if rng.random() < 0.5 else min(rng.uniform(0.5, 4.0) * limit, 5 * G)
    case["motion"] = {"kind": str(rng.choice(["white", "walk", "synthetic"])), "duration": duration,
                      "dt": float(rng.choice([0.005, 0.01, 0.02])), "pga": pga,
                      "seed": int(rng.integers(0, 2**31 - 1))}
    return case


def build(case):
    from statue2model.hazard import motions
    from statue2model.rocking import RockingModel
    from statue2model.geometry.rocking_params import RockingParams

    p = RockingParams(**case["body"])
    md = case["model"]
    if md["kind"] == "housner":
        model = RockingModel.housner(p, e_L=md["e_L"], e_R=md["e_R"], linearised=md["linearised"])
    else:
        model = RockingModel.imperfect(p, md["alpha_L"], md["alpha_R"], md["theta_L"], md["theta_R"],
                                       e_L=md["e_L"], e_R=md["e_R"], linearised=md["linearised"])
    mo = case["motion"]
    k = mo["kind"]
    if k == "free":
        motion = motions.free()
    elif k == "cosine":
        motion = motions.cosine_pulse(mo["amp"], mo["freq"])
    elif k == "sine":
        motion = motions.sine_pulse(mo["amp"], mo["freq"])
    elif k == "sines":
        motion = motions.sine_train(mo["amp"], mo["freq"], mo["cycles"])
    elif k == "rect":
        motion = motions.rect_pulse(mo["amp"], mo["dur"])
    elif k == "synthetic":
        motion = motions.synthetic_record(mo["duration"], mo["dt"], mo["pga"], seed=mo["seed"])
    else:
        n = round(mo["duration"] / mo["dt"]) + 1
        x = np.random.default_rng(mo["seed"]).standard_normal(n)
        if k == "walk":
            x = np.cumsum(x)
        x -= x.mean()
        x *= mo["pga"] / np.max(np.abs(x))
        motion = motions.record(x, mo["dt"], label=f"{k} seed {mo['seed']}")
    return model, motion


def reproducer(case) -> str:
    """A stand-alone snippet that rebuilds and runs the case."""
    return (f"import sys; sys.path.insert(0, 'benchmarks'); from stress_rocking import build\n"
            f"from statue2model.rocking import simulate\n"
            f"case = {case!r}\n"
            f"model, motion = build(case)\n"
            f"r = simulate(model, motion, theta0=case['theta0'], omega0=case['omega0'], t_end=case.get('t_end'))")


# --- the energy of the model (MODEL.md section 2) -------------------------------------
def _f0(q, d, lin):
    if lin:
        return q * (d - 0.5 * q)
    return 2.0 * math.sin(d - 0.5 * q) * math.sin(0.5 * q)


def _f1(q, d, lin):
    if lin:
        return q * q * (0.5 * d - q / 3.0)
    q2 = q * q
    if q < 1e-2:
        i1 = q2 * (0.5 - q2 / 8.0 + q2 * q2 / 144.0)
        i2 = q * q2 * (1.0 / 3.0 - q2 / 30.0 + q2 * q2 / 840.0)
    else:
        i1 = q * math.sin(q) + math.cos(q) - 1.0
        i2 = math.sin(q) - q * math.cos(q)
    return math.sin(d) * i1 - math.cos(d) * i2


def energy(model, theta, theta_dot):
    """0.5 I_s theta'^2 + m g d_s int_0^|theta| alpha(x) sin(delta_s - x) dx; nan at
    theta = 0 in motion (the pivot is ambiguous at an impact)."""
    if theta == 0.0:
        return 0.0 if theta_dot == 0.0 else math.nan
    p = model.params
    s = 1 if theta > 0 else -1
    q = abs(theta)
    d, a = (p.delta_R, model.alpha_R) if s > 0 else (p.delta_L, model.alpha_L)
    th = ((model.theta_R if s > 0 else model.theta_L) if a < 1.0 else 0.0)
    mgd = p.m * p.g * (p.d_R if s > 0 else p.d_L)
    lin = model.linearised
    if th <= 0.0:
        v = _f0(q, d, lin)
    elif q <= th:
        v = a * _f0(q, d, lin) + (1.0 - a) / th * _f1(q, d, lin)
    else:
        v = a * _f0(th, d, lin) + (1.0 - a) / th * _f1(th, d, lin) + _f0(q, d, lin) - _f0(th, d, lin)
    return 0.5 * (p.I_R if s > 0 else p.I_L) * theta_dot**2 + mgd * v


# --- one case ------------------------------------------------------------------------------
def run_case(args):
    case, max_steps = args
    from statue2model.rocking import simulate

    out = {"id": case["id"], "cat": case["cat"], "failures": [], "times": [], "steps": 0,
           "ratio": math.nan, "overturned": False, "energy_excess": math.nan, "kind": None, "slow": False}
    try:
        model, motion = build(case)
    except Exception as exc:   # noqa: BLE001 - an input the constructors reject is a generator bug
        out["failures"].append(f"build: {exc!r}")
        return out
    p = model.params
    kw = {"theta0": case["theta0"], "omega0": case["omega0"], "t_end": case.get("t_end"), "max_steps": max_steps}
    rtol = 1e-8
    if case["cat"] == "free":
        delta, pp = (p.delta_R, p.p_R) if case["theta0"] > 0 else (p.delta_L, p.p_L)
        rtol = FREE_RTOL * min(1.0, max(abs(case["theta0"]), abs(case["omega0"]) / pp) / delta)
        kw["rtol"] = rtol
    runs = []
    for dt_out in (0.0037, None):
        if runs and out["times"][0] > SLOW_S:
            out["slow"] = True        # not repeated without output: time
            break
        t0 = time.perf_counter()
        try:
            r = simulate(model, motion, dt_out=dt_out, **kw)
        except Exception as exc:   # noqa: BLE001 - every exception of the engine is a finding
            out["times"].append(time.perf_counter() - t0)
            hang = isinstance(exc, RuntimeError) and ("steps" in str(exc) or "no progress" in str(exc))
            out["kind"] = "hang" if hang else "exception"
            out["failures"].append(f"{out['kind']} (dt_out={dt_out}): {type(exc).__name__}: {exc}")
            return out
        out["times"].append(time.perf_counter() - t0)
        runs.append(r)
    b, a = runs if len(runs) == 2 else (runs[0], runs[0])
    out["steps"] = a.stats["n_steps"]
    out["overturned"] = a.overturned
    if not a.overturned:
        out["ratio"] = a.theta_max_over_delta
    # (c) bounds
    if not a.overturned:
        if a.theta_max_R > p.delta_R + DELTA_TOL or a.theta_max_L > p.delta_L + DELTA_TOL:
            out["failures"].append(f"bound: theta_max beyond delta ({a.theta_max_over_delta!r})")
        h = b.history
        if h["theta"].size:
            th = h["theta"]
            if not (np.all(np.isfinite(th)) and np.all(th <= p.delta_R + DELTA_TOL)
                    and np.all(-th <= p.delta_L + DELTA_TOL)):
                out["failures"].append("bound: history beyond delta or not finite")
            gap = max(np.max(th, initial=0.0) - a.theta_max_R - 10 * rtol * p.delta_R,
                      np.max(-th, initial=0.0) - a.theta_max_L - 10 * rtol * p.delta_L)
            if gap > 0:
                out["failures"].append(f"maxima: the history passes theta_max by {gap:.3g} rad")
    # (d) output grid
    same = (a.theta_max_L == b.theta_max_L and a.theta_max_R == b.theta_max_R and a.n_impacts == b.n_impacts
            and np.array_equal(a.impact_times, b.impact_times) and a.overturned == b.overturned
            and a.uplift_time == b.uplift_time and a.stats["n_steps"] == b.stats["n_steps"])
    if not same:
        out["failures"].append(f"sampling: dt_out changes the result (impacts {a.n_impacts} vs {b.n_impacts}, "
                               f"theta_max_R {a.theta_max_R!r} vs {b.theta_max_R!r})")
    # (e) quiet motions
    if case["theta0"] == 0.0 and case["omega0"] == 0.0:
        hi, lo = motion.extremes()
        up, dn = model.uplift_limits
        if hi <= up and lo >= -dn and (a.uplift_time is not None or np.any(b.history["theta"])):
            out["failures"].append("quiet: lifted by a motion below the uplift limits")
    # (b) energy
    if case["cat"] == "free":
        h = b.history
        E0 = energy(model, case["theta0"], case["omega0"])
        E = np.array([energy(model, x, y) for x, y in zip(h["theta"], h["theta_dot"])])
        ok = ~np.isnan(E)
        E, t = E[ok], h["t"][ok]
        n_before = np.searchsorted(b.impact_times, t, side="right")
        excess = (E - np.minimum.accumulate(E)) / E0
        out["energy_excess"] = float(np.max(excess, initial=0.0))
        if np.any(excess > ENERGY_RTOL + 1e-8 * n_before):
            out["failures"].append(f"energy: grows by {out['energy_excess']:.3g} E0")
    return out


def _warm(_):
    from statue2model.hazard import motions
    from statue2model.rocking import RockingModel, simulate
    from statue2model.geometry.rocking_params import RockingParams

    m = RockingModel.imperfect(RockingParams.rectangular_block(0.05, 0.3, 2.0), 0.5, 0.5, 0.01, 0.01)
    for mo in (motions.free(), motions.cosine_pulse(3.0, 2.0), motions.rect_pulse(3.0, 0.2),
               motions.record([0.0, 3.0, -3.0, 0.0], 0.1)):
        simulate(m, mo, theta0=0.01 if mo.kind == "none" else 0.0, t_end=1.0, dt_out=0.1)
    return os.getpid()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=2000, help="number of cases (default 2000)")
    ap.add_argument("--seed", type=int, default=0, help="seed of the case generator (default 0)")
    ap.add_argument("--jobs", type=int, default=min(2, os.cpu_count() or 1), help="worker processes")
    ap.add_argument("--max-steps", type=int, default=10_000_000,
                    help="step budget of one run (~15 s); exceeding it counts as a hang (default 1e7)")
    ap.add_argument("--show", type=int, default=10, help="failing cases printed as reproducers (default 10)")
    args = ap.parse_args(argv)

    rng = np.random.default_rng(args.seed)
    cats = rng.choice(len(CATEGORIES), size=args.n, p=WEIGHTS)
    cases = [draw_case(rng, CATEGORIES[c], i) for i, c in enumerate(cats)]
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        list(pool.map(_warm, range(args.jobs)))
        results = list(pool.map(run_case, [(c, args.max_steps) for c in cases], chunksize=8))
    wall = time.perf_counter() - t0

    rows = []
    for cat in CATEGORIES + ("all",):
        rs = [r for r in results if cat in ("all", r["cat"])]
        times = [t for r in rs for t in r["times"]]
        ratios = [r["ratio"] for r in rs if not math.isnan(r["ratio"])]
        free = [r for r in rs if r["cat"] == "free"]
        def n_fail(prefix, rs=rs):
            return sum(1 for r in rs if any(f.startswith(prefix) for f in r["failures"]))

        rows.append((cat, len(rs), sum(1 for r in rs if r["overturned"]),
                     sum(1 for r in rs if r["kind"] == "exception"), sum(1 for r in rs if r["kind"] == "hang"),
                     n_fail("sampling"), n_fail("bound"), n_fail("maxima"),
                     max(times, default=0.0), float(np.median(times)) if times else 0.0,
                     max((r["steps"] for r in rs), default=0), max(ratios, default=0.0),
                     n_fail("energy") if free else None,
                     max((r["energy_excess"] for r in free if not math.isnan(r["energy_excess"])), default=None)))
    head = ("category", "cases", "overt.", "exceptions", "hangs", "sampling", "bounds", "maxima", "max t/run s",
            "median t/run s", "max steps", "max |th|/delta", "energy viol.", "max dE/E0")
    print(f"stress_rocking: {args.n} cases, seed {args.seed}, {args.jobs} jobs, {wall:.1f} s wall "
          f"(max steps per run {args.max_steps:,})")
    widths = [8, 5, 6, 10, 5, 8, 6, 6, 11, 14, 10, 14, 12, 9]
    print("  ".join(f"{h:>{w}}" for h, w in zip(head, widths)))
    for row in rows:
        cells = list(row[:8]) + [f"{row[8]:.3f}", f"{row[9]:.4f}", f"{row[10]:,}", f"{row[11]:.9f}",
                                 "-" if row[12] is None else row[12], "-" if row[13] is None else f"{row[13]:.2g}"]
        print("  ".join(f"{c!s:>{w}}" for c, w in zip(cells, widths)))
    n_slow = sum(1 for r in results if r["slow"])
    if n_slow:
        print(f"({n_slow} case(s) slower than {SLOW_S:g} s per run: not repeated without output, "
              "so not checked for sampling)")
    failed = [(c, r) for c, r in zip(cases, results) if r["failures"]]
    if failed:
        print(f"\n{len(failed)} failing case(s); the first {min(args.show, len(failed))}:")
        for c, r in failed[:args.show]:
            print(f"\n# case {c['id']} ({c['cat']}): " + "; ".join(r["failures"]))
            print(reproducer(c))
        return 1
    print("\nno failures")
    return 0


if __name__ == "__main__":
    sys.exit(main())
