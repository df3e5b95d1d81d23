"""2D against 3D over an ensemble of records: agreement in distribution, not history by history.

Rocking under a record is sensitive to every impact (a 1 % change of e moves a single peak by
tens of per cent, statue_cases.motion_cases), so single histories cannot be expected to agree; rocking
studies agree statistically. Here the same ``n_records`` synthetic Kanai-Tajimi records
(statue2model.hazard.motions.synthetic_record, seeds 0..n-1, durations cycling over
``durations``) are scaled to each PGA level and run in the 2D model and in the 3D scene; per
level:

* the overturning probability of each, with a 95 % Wilson score interval (:func:`wilson`);
  target: |p_3D - p_2D| <= ``prob_target`` (default 0.15). The runs are paired (same records),
  so the records whose outcome differs are listed too;
* the median peak rotation max |theta| / delta (an overturned run counts as +inf: the median
  stays defined while fewer than half overturn), with a 95 % distribution-free order-statistic
  interval (:func:`median_ci`); target: |median_3D / median_2D - 1| <= ``median_target``
  (default 0.20); both medians "overturned" agree.

Each miss says why: which side overturns more, by how much, whether the intervals overlap, how
many 3D runs the validity screen flags. The screen is the standard cases' own
(:func:`statue2model.crosscheck.screen.screen_values`: the friction the 2D trajectory needs against the
scene's, 3D slip > screen.SLIP_LIMIT, yaw > screen.YAW_LIMIT); a flagged record leaves the level's
statistics on both sides (the runs are paired) and is listed; a level left with fewer than 2 records
is "not applicable".

Levels: multiples of the 2D ensemble's median overturning PGA (:func:`median_overturn_pga`: the
smallest PGA at which at least half the records overturn the 2D model, by boundary.bisect on a
geometric midpoint), so the
levels sit around the 2D overturning level whatever the body. 2D runs are cheap; the 3D runs go
through an executor (statue2model.compute.executors; default two local processes).

:func:`ensemble_cases` returns an :class:`Ensemble`: the Comparison (two cases per level, the
statistics under ``runs['records']`` with non-finite numbers as null, for crosscheck.json) and the
statistics themselves (``results``, an overturned run's peak +inf, for :func:`level_table`).

Example
-------
>>> lo, hi = wilson(8, 20)
>>> round(lo, 4), round(hi, 4)
(0.2188, 0.6134)
>>> median_ci([5, 1, 4, 2, 3, 9, 7, 8, 6, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20])
(10.5, 6.0, 15.0)
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from ..quantities import G
from ..hazard import motions
from ..rocking.engine import simulate as simulate_2d
from ..rocking.model import RockingModel
from ..errors import InputError
from .boundary import bisect
from .case import NOT_APPLICABLE, Case, Comparison
from .contact import ContactSettings
from .restitution import model_2d
from .screen import SLIP_LIMIT, YAW_LIMIT, screen_values, slip_of
from .statue_scene import StatueScene, simulate_statue
from .world import SimSettings

Z95 = 1.959963984540054
LEVELS = (0.5, 0.8, 1.2)
"""Default PGA levels, multiples of the 2D ensemble's median overturning PGA."""
DURATIONS = (6.0, 8.0, 10.0)
"""Default record durations, s (cycled over the seeds)."""


@dataclass(frozen=True, eq=False)
class Ensemble:
    """What :func:`ensemble_cases` returns: ``comparison`` (its cases; runs = {'records':
    json_safe(results)}) and ``results`` ({'levels': [...], 'pga_ref' (m/s^2), 'runs_3d',
    'wall_time_s', ...}, non-finite numbers kept)."""

    comparison: Comparison
    results: dict


def wilson(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson score interval (lo, hi) of a proportion k / n (no continuity correction)."""
    if not (isinstance(n, (int, np.integer)) and n > 0 and 0 <= k <= n):
        raise InputError(f"need 0 <= k <= n and n > 0, got k = {k}, n = {n}")
    p = k / n
    den = 1.0 + z * z / n
    c = (p + z * z / (2 * n)) / den
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return max(0.0, c - h), min(1.0, c + h)


def median_ci(x, conf: float = 0.95) -> tuple[float, float, float]:
    """(median, lo, hi): the sample median and the distribution-free interval between the order
    statistics x_(l) and x_(n - l + 1), l the largest rank with P(Bin(n, 1/2) < l) <= (1 - conf) / 2
    (coverage >= conf; +inf values, e.g. overturned runs, are ordered last)."""
    from scipy.stats import binom

    x = np.sort(np.asarray(x, dtype=float))
    n = x.size
    if n == 0 or np.isnan(x).any():
        raise InputError("median_ci needs a non-empty sample without NaN")
    med = float(np.median(x)) if np.isfinite(x[(n - 1) // 2]) and np.isfinite(x[n // 2]) else math.inf
    lo_rank = int(binom.ppf((1 - conf) / 2, n, 0.5))          # 1-based rank l
    if lo_rank < 1:
        return med, -math.inf, math.inf
    return med, float(x[lo_rank - 1]), float(x[n - lo_rank])


def records(n_records: int, durations=DURATIONS, dt: float = 0.01) -> list:
    """The unscaled ensemble: synthetic_record(seed = i, duration = durations[i % len]), PGA 1 m/s^2."""
    if not (isinstance(n_records, int) and n_records >= 1):
        raise InputError(f"the number of records must be a positive integer, got {n_records!r}")
    return [motions.synthetic_record(duration=float(durations[i % len(durations)]), dt=dt, pga=1.0, seed=i)
            for i in range(n_records)]


def _outcome_2d(model: RockingModel, motion, free_time: float) -> tuple[bool, float]:
    r = simulate_2d(model, motion, t_end=motion.end + free_time)
    return bool(r.overturned), (math.inf if r.overturned else float(r.theta_max_over_delta))


def median_overturn_pga(model: RockingModel, recs, free_time: float = 2.0, tol: float = 0.02) -> float:
    """Smallest PGA (m/s^2) at which at least half of ``recs`` overturn the 2D ``model`` (bisection
    between a_min / 2 and 40 a_min, relative tolerance ``tol``). inf if not even at the top."""
    a0 = min(model.lift_accelerations)
    lo, hi = 0.5 * a0, 40.0 * a0

    def frac(pga):
        return np.mean([_outcome_2d(model, r.scaled_to_pga(pga), free_time)[0] for r in recs])

    if frac(hi) < 0.5:
        return math.inf
    return bisect(lambda pga: frac(pga) >= 0.5, lo, hi, tol, geometric=True)[1]


def run_3d(task: tuple) -> dict:
    """One 3D run (module level, for the executors): task = (scene, motion, settings, contact,
    free_time, dt_out). Returns the numbers the ensemble needs."""
    scene, motion, settings, contact, free_time, dt_out = task
    r = simulate_statue(scene, motion, settings=settings, contact=contact, free_time=free_time, dt_out=dt_out)
    return {"overturned": bool(r.overturned), "peak": math.inf if r.overturned else float(r.theta_max_over_delta),
            "slip": float(slip_of(r)), "yaw": float(np.abs(r.yaw).max(initial=0.0)), "finite": bool(r.finite),
            "wall_time_s": float(r.wall_time), "sim_time_s": float(r.steps * settings.dt)}


def _executor(executor, workers: int):
    from ..compute.executors import ProcessExecutor, SerialExecutor

    if executor is not None:
        return executor, False
    return (ProcessExecutor(workers) if workers > 1 else SerialExecutor()), True


def level_result(pga: float, o2, q2, o3, q3, screened, prob_target: float, median_target: float,
                 seeds=None, reasons=None) -> dict:
    """The statistics of one level (o: overturned flags, q: peak |theta| / delta, inf if overturned) over
    the records the screen kept (``seeds``: their seeds, default 0..n-1); ``screened``: the seeds it took
    out, ``reasons``: {seed: the screen's reasons}."""
    n = len(o2)
    seeds = list(range(n)) if seeds is None else list(seeds)
    k2, k3 = int(sum(o2)), int(sum(o3))
    p2, p3 = k2 / n, k3 / n
    ci2, ci3 = wilson(k2, n), wilson(k3, n)
    m2, m2lo, m2hi = median_ci(q2)
    m3, m3lo, m3hi = median_ci(q3)
    differ = [seeds[i] for i in range(n) if bool(o2[i]) != bool(o3[i])]
    prob_ok = abs(p3 - p2) <= prob_target + 1e-12
    if math.isinf(m2) and math.isinf(m3):
        ratio, med_ok = 1.0, True
    elif math.isinf(m2) or math.isinf(m3) or m2 == 0:
        ratio, med_ok = math.inf, False
    else:
        ratio = m3 / m2
        med_ok = abs(ratio - 1.0) <= median_target + 1e-12
    ci_overlap = ci2[0] <= ci3[1] and ci3[0] <= ci2[1]
    med_overlap = m2lo <= m3hi and m3lo <= m2hi
    why = []
    if not prob_ok:
        more = "3D" if p3 > p2 else "2D"
        why.append(f"{more} overturns more often: 3D {k3}/{n} vs 2D {k2}/{n} (difference {abs(p3 - p2):.2f} > "
                   f"{prob_target:g}; Wilson 95 % intervals {'overlap' if ci_overlap else 'do not overlap'}); "
                   f"records whose outcome differs: seeds {differ}")
    if not med_ok:
        if math.isinf(m2) != math.isinf(m3):
            side = "3D" if math.isinf(m3) else "2D"
            why.append(f"the median record overturns the {side} body only (2D median {m2:.3g}, 3D {m3:.3g})")
        else:
            why.append(f"median peak |theta|/delta 3D {m3:.3f} vs 2D {m2:.3f} (ratio {ratio:.2f}, beyond "
                       f"1 +- {median_target:g}); 95 % intervals [{m2lo:.3f}, {m2hi:.3f}] and [{m3lo:.3f}, {m3hi:.3f}] "
                       f"{'overlap' if med_overlap else 'do not overlap'}")
    if screened:
        first = (reasons or {}).get(screened[0], [])
        why.append(f"{len(screened)} of {n + len(screened)} records left out by the validity screen, both sides "
                   f"(seeds {screened}" + (f"; seed {screened[0]}: {'; '.join(first)}" if first else "") + ")")
    return {"pga": pga, "pga_g": pga / G, "n": n, "p_2d": p2, "p_3d": p3, "ci_2d": list(ci2), "ci_3d": list(ci3),
            "ci_overlap": bool(ci_overlap), "prob_met": bool(prob_ok), "median_2d": m2, "median_3d": m3,
            "median_ci_2d": [m2lo, m2hi], "median_ci_3d": [m3lo, m3hi], "median_ratio": ratio,
            "median_overlap": bool(med_overlap), "median_met": bool(med_ok), "differ": differ,
            "screened": screened, "why": "; ".join(why)}


def ensemble_cases(scene: StatueScene, settings: SimSettings | None = None, contact: ContactSettings | None = None,
                   n_records: int = 20, levels=LEVELS, quick: bool = False, *, model: RockingModel | None = None,
                   durations=None, free_time: float | None = None, prob_target: float = 0.15,
                   median_target: float = 0.20, executor=None, workers: int = 2, progress=None,
                   pga_ref: float | None = None, runs_3d: list | None = None) -> Ensemble:
    """The ensemble comparison of the module docstring. ``levels``: multiples of the 2D median
    overturning PGA; ``model``: the 2D model (default: eq. 15's e, restitution.model_2d - the 2D model
    as the user runs it); ``quick``: shorter records (3-5 s) and 1 s of free motion. Returns its
    :class:`Ensemble` (cases: two per level; results: {'levels': [...], 'pga_ref', 'runs_3d',
    'wall_time_s', ...}).
    ``pga_ref`` (m/s^2) and ``runs_3d`` (an earlier results['runs_3d'], same records, levels and
    pga_ref) reuse an earlier ensemble's 3D runs to judge another 2D model against them."""
    say = progress or (lambda msg: None)
    settings = SimSettings() if settings is None else settings
    contact = ContactSettings() if contact is None else contact
    model = model_2d(scene) if model is None else model
    if n_records < 2:
        raise InputError(f"an ensemble needs at least 2 records, got {n_records}")
    levels = [float(x) for x in levels]
    if not levels or any(not (math.isfinite(x) and x > 0) for x in levels):
        raise InputError(f"PGA levels must be positive multiples of the 2D overturning level, got {levels}")
    durations = ((3.0, 4.0, 5.0) if quick else DURATIONS) if durations is None else durations
    free_time = (1.0 if quick else 2.0) if free_time is None else free_time
    t0 = time.perf_counter()
    recs = records(n_records, durations)
    pga_ref = median_overturn_pga(model, recs, free_time) if pga_ref is None else float(pga_ref)
    if not math.isfinite(pga_ref):
        raise InputError("the 2D model does not overturn under half of the records even at 40 x its uplift "
                         "acceleration: no overturning level to centre the ensemble on")
    say(f"records: 2D median overturning PGA {pga_ref / G:.3f} g")
    t2d = time.perf_counter() - t0
    tasks, two = [], []
    for lev in levels:
        pga = lev * pga_ref
        for r in recs:
            m = r.scaled_to_pga(pga)
            two.append(_outcome_2d(model, m, free_time))
            tasks.append((scene, m, settings, contact, free_time, 0.01))
    t1 = time.perf_counter()
    if runs_3d is not None:
        if len(runs_3d) != len(tasks):
            raise InputError(f"runs_3d holds {len(runs_3d)} runs, this ensemble needs {len(tasks)}")
        three, where = list(runs_3d), "reused"
    else:
        ex, own = _executor(executor, workers)
        where = ex.describe()
        try:
            say(f"records: {len(tasks)} 3D runs on {where}")
            three = ex.map(run_3d, tasks)
        finally:
            if own:
                ex.close()
    t3d = time.perf_counter() - t1
    out, cases = [], []
    n = n_records
    for j, lev in enumerate(levels):
        sl = slice(j * n, (j + 1) * n)
        o2 = [x[0] for x in two[sl]]
        q2 = [x[1] for x in two[sl]]
        r3 = three[sl]
        scr = [screen_values(model, tasks[j * n + i][1], x["slip"], x["yaw"], contact,
                             tasks[j * n + i][1].end + free_time) for i, x in enumerate(r3)]
        screened = [i for i, x in enumerate(scr) if not x["applicable"]]
        keep = [i for i, x in enumerate(scr) if x["applicable"]]
        reasons = {i: scr[i]["reasons"] for i in screened}
        tag = f"records x{lev:g} ({lev * pga_ref / G:.3f} g, {n} records)"
        if len(keep) < 2:
            why = (f"{NOT_APPLICABLE}: {len(screened)} of {n} records fail the validity screen (seed {screened[0]}: "
                   f"{'; '.join(reasons[screened[0]])})")
            out.append({"level": lev, "pga": lev * pga_ref, "pga_g": lev * pga_ref / G, "n": len(keep),
                        "screened": screened, "screen_reasons": reasons, "why": why, "applicable": False})
            for q in ("overturning probability", "median peak rotation"):
                cases.append(Case(f"{tag}: {q}", q, None, None, math.inf, prob_target if "prob" in q else median_target,
                                  False, "absolute" if "prob" in q else "relative", "", status="not applicable",
                                  why=why))
            continue
        o3 = [r3[i]["overturned"] for i in keep]
        q3 = [r3[i]["peak"] for i in keep]
        res = level_result(lev * pga_ref, [o2[i] for i in keep], [q2[i] for i in keep], o3, q3, screened,
                           prob_target, median_target, seeds=keep, reasons=reasons)
        res["level"] = lev
        res["applicable"] = True
        res["screen_reasons"] = reasons
        res["nonfinite_3d"] = [i for i, x in enumerate(r3) if not x["finite"]]
        out.append(res)
        note = (f"Wilson 95 %: 2D [{res['ci_2d'][0]:.2f}, {res['ci_2d'][1]:.2f}], 3D [{res['ci_3d'][0]:.2f}, "
                f"{res['ci_3d'][1]:.2f}]; paired: {len(res['differ'])} records differ")
        c = Case.absolute(f"{tag}: overturning probability", "", res["p_2d"], res["p_3d"], prob_target,
                          quantity="overturning probability", note=note)
        cases.append(_with_why(c, res["why"] if not res["prob_met"] or res["screened"] else ""))
        mnote = (f"max |theta| / delta, overturned = inf; 95 % order-statistic intervals 2D "
                 f"[{res['median_ci_2d'][0]:.3g}, {res['median_ci_2d'][1]:.3g}], 3D [{res['median_ci_3d'][0]:.3g}, "
                 f"{res['median_ci_3d'][1]:.3g}]")
        c = Case(f"{tag}: median peak rotation", "median peak rotation", _num(res["median_2d"]),
                 _num(res["median_3d"]), abs(res["median_ratio"] - 1.0) if math.isfinite(res["median_ratio"])
                 else math.inf, median_target, res["median_met"], "relative", "-", mnote)
        cases.append(_with_why(c, res["why"] if not res["median_met"] else ""))
    sim = sum(x["sim_time_s"] for x in three)
    wall3 = sum(x["wall_time_s"] for x in three)
    results = {"levels": out, "pga_ref": pga_ref, "pga_ref_g": pga_ref / G, "n_records": n,
               "durations": list(durations), "free_time": free_time, "model_2d": model.to_dict(),
               "targets": {"probability_difference": prob_target, "median_ratio": median_target},
               "screen": {"slip_m": SLIP_LIMIT, "yaw_rad": YAW_LIMIT, "friction_scene": contact.friction**2},
               "executor": where, "runs_3d": three,
               "wall_time_s": time.perf_counter() - t0, "wall_time_2d_s": t2d, "wall_time_3d_s": t3d,
               "sim_time_3d_s": sim, "real_time_factor_3d": sim / wall3 if wall3 > 0 else math.inf}
    # an overturned run's peak (inf) -> None in crosscheck.json
    return Ensemble(Comparison(tuple(cases), runs={"records": json_safe(results)}), results)


def _num(x):
    return None if x is None or not math.isfinite(x) else float(x)


def _with_why(case: Case, why: str) -> Case:
    return replace(case, why=why) if why else case


def level_table(results: dict) -> str:
    """The per-level table, 2D vs 3D with intervals (plain text)."""
    lines = [f"2D median overturning PGA {results['pga_ref_g']:.3f} g; {results['n_records']} records; "
             f"targets |dp| <= {results['targets']['probability_difference']:g}, median ratio 1 +- "
             f"{results['targets']['median_ratio']:g}",
             f"{'level':>6s} {'PGA g':>6s} {'p2D [95% CI]':>20s} {'p3D [95% CI]':>20s} {'med2D [CI]':>22s} "
             f"{'med3D [CI]':>22s} {'ratio':>6s} {'P':>2s} {'M':>2s}"]

    def f(x):
        return "ovt" if not math.isfinite(x) else f"{x:.3f}"

    for r in results["levels"]:
        if not r.get("applicable", True):
            lines.append(f"{r['level']:6.2f} {r['pga_g']:6.3f} not applicable: {r['why']}")
            continue
        lines.append(f"{r['level']:6.2f} {r['pga_g']:6.3f} {r['p_2d']:5.2f} [{r['ci_2d'][0]:.2f},{r['ci_2d'][1]:.2f}]"
                     f"     {r['p_3d']:5.2f} [{r['ci_3d'][0]:.2f},{r['ci_3d'][1]:.2f}]     "
                     f"{f(r['median_2d']):>6s} [{f(r['median_ci_2d'][0])},{f(r['median_ci_2d'][1])}] "
                     f"{f(r['median_3d']):>6s} [{f(r['median_ci_3d'][0])},{f(r['median_ci_3d'][1])}] "
                     f"{f(r['median_ratio']):>6s} {'ok' if r['prob_met'] else 'NO':>2s} "
                     f"{'ok' if r['median_met'] else 'NO':>2s}")
        if r["why"]:
            lines.append(f"       why: {r['why']}")
    return "\n".join(lines)


def json_safe(x):
    """``x`` with every non-finite float (an overturned run's inf peak) replaced by None, for JSON."""
    if isinstance(x, dict):
        return {k: json_safe(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [json_safe(v) for v in x]
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    return x
