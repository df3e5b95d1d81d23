"""2D against 3D as a classifier: does the 2D model say yes where the 3D scene says yes?

Each run (one record of the design set scaled to one PGA level) gives, in each model, a yes/no per
limit state (MODEL.md section 8): **uplift** (the body lifts off its base), **overturning** and, on
the isolator, **capacity** (the device's capacity reached; on a fixed base "not applicable: no
isolator"). The 3D scene is taken as the reference ("truth"), the 2D model as the prediction - the
way the Virtual Shake Robot scores a simulation against shake-table tests - and the paired outcomes
are counted (:func:`confusion`):

    TP: both yes   FP: 2D yes, 3D no   FN: 2D no, 3D yes   TN: both no
    accuracy = (TP + TN) / n,  precision = TP / (TP + FP),  recall = TP / (TP + FN)

each with its 95 % Wilson score interval (:func:`statue2model.crosscheck.ensemble.wilson`). A rate
with an empty denominator (no 2D positive: precision; no 3D positive: recall) is undefined: value
None with the reason, never NaN (:class:`Rate`).

The verdict per limit state (:func:`agreement`), met only when the runs SHOW agreement:

    the accuracy's 95 % lower bound >= ACCURACY_MIN (0.8: at most one run in five classified
    differently) and, where defined, the precision's and the recall's 95 % lower bounds >= PR_MIN
    (0.5: the 2D model is right more often than wrong about the positives it predicts and about the
    positives there are).

A limit state with no positive case in either model (no run says yes), or no negative one, is
"not testable" with that reason, never met: such runs agree whatever the 2D model does.
Anything else is missed, and the reason says whether disagreement is shown (an upper bound below
its threshold) or agreement is only not shown (too few runs: with all n runs agreeing the accuracy's
lower bound is n / (n + 1.96^2), >= 0.8 only from n = 16; a precision or recall needs >= 4
positives). Rocking near a boundary flips with a 1 % change of e (statue_cases.motion_cases), so a
few disagreeing runs near the fragility medians are expected; a systematic error of e or alpha
flips many and fails (tests/test_classification.py).

What is read per run (:func:`outcome_2d`, :func:`outcome_3d`):

* uplift: 3D - the contacts, geometrically (Statue3DResult.uplift_time: the non-pivot base edge
  above statue_scene.LIFT_HEIGHT = 0.2 mm for LIFT_STEPS steps); 2D - at the same height,
  max |theta| >= asin(LIFT_HEIGHT / (b_L + b_R)) (statue_cases.lift_angle; the exact 2D uplift instant
  is kept beside it). An overturned run has lifted;
* overturning: |theta| reached delta in either model;
* the peak max |theta| / delta. The peaks are compared only where at least one model lifts off
  ("not applicable: neither model lifts off" otherwise) and neither overturns.

Every disagreeing run says why (:func:`disagreement_why`): which model says yes, the record's
peak toward each side against the uplift accelerations alpha_side a_side, both peaks theta / delta,
the 3D lift height. The fragility medians (PGA, lognormal maximum-likelihood fit,
statue2model.assessment.fragility.fit_lognormal) of both models per limit state are set side by side.

The validity screen of the record ensemble (statue2model.crosscheck.screen.screen_values: the 3D
body slides or twists, the 2D trajectory needs more friction than the scene has) is read for every
run and, by default, the run is still COUNTED (the conservative reading: a real statue slides and
twists too, and the 2D model's answer is what the assessment uses; leaving such runs out would drop
most 3D overturns - measured on the default scan's design set: 10 of the 11 runs the screen flags
overturn in 3D, their yaw passing 2 deg at theta / delta < 0.48). The flagged runs are listed per
limit state, and a flagged run that is classified differently says so in its why. With
``use_screen=True`` the flagged runs are left out on both sides (paired). On the isolator only the
3D part applies (the statue's slip and yaw on the plate): the 2D demand is the fixed-base model's.
A run whose 3D state is not finite is always left out.

The isolated base (``base="isolated"``): the runners of statue2model.crosscheck.isolated_runs (the
coupled 2D model against the exact-kinematics 3D isolator with the statue standing on it); the
capacity row then counts.

Plugging in another base: :func:`classify_ensemble` takes ``run_2d`` (model, motion, free_time) ->
outcome dict and ``run_3d`` (task) -> outcome dict (module-level, for the executors); an outcome
with a bool ``capacity`` in both models makes the capacity row count. Keys of an outcome: uplift,
overturned, capacity (bool or None), peak (max |theta| / delta, inf when overturned), and
optionally uplift_time, side, max_lift, slip, yaw (the screen runs when both are there), finite.

Example
-------
>>> truth = [True, True, False, False, True, False]
>>> pred = [True, False, False, True, True, False]
>>> confusion(truth, pred)
{'tp': 2, 'fp': 1, 'fn': 1, 'tn': 2}
>>> a = agreement(truth, pred, "overturning")
>>> round(a.accuracy.value, 4), round(a.accuracy.lo, 4), a.status
(0.6667, 0.3, 'missed')
>>> a = agreement([False] * 20, [False] * 20, "full_contact")
>>> a.status, a.precision.why
('not testable', 'undefined: the 2D model says yes in no run')
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..quantities import G
from ..assessment import states
from ..rocking.engine import simulate as simulate_2d
from ..rocking.model import RockingModel
from .contact import ContactSettings
from .ensemble import json_safe, wilson
from .screen import screen_values, slip_of, validity_screen
from .statue_cases import lift_angle
from .statue_scene import LIFT_HEIGHT, StatueScene, simulate_statue
from .world import SimSettings

STATES = states.CLASSIFIED
"""The yes/no limit states, in the order the damage grows (MODEL.md section 8; assessment/states.py)."""
KEYS = dict(zip(STATES, ("uplift", "overturned", "capacity")))
"""The outcome key of each limit state (full contact lost: the run's ``uplift``)."""
ACCURACY_MIN = 0.8
"""Threshold of the accuracy's 95 % lower bound (at most one run in five classified differently)."""
PR_MIN = 0.5
"""Threshold of the precision's and the recall's 95 % lower bounds (right more often than wrong)."""
FACTORS = (0.5, 0.8, 1.0, 1.25, 2.0)
"""Default PGA levels: these multiples of each 2D fragility median (uplift, overturning)."""
REFERENCE = "3D scene taken as the reference (truth), 2D model as the prediction"
NEITHER_LIFTS = "not applicable: neither model lifts off"


@dataclass(frozen=True)
class Rate:
    """A proportion k / n with its 95 % Wilson interval; value, lo, hi None (and ``why``) when n = 0."""

    name: str
    k: int
    n: int
    value: float | None
    lo: float | None
    hi: float | None
    why: str | None = None

    def to_dict(self) -> dict:
        return {"name": self.name, "k": self.k, "n": self.n, "value": self.value, "lo": self.lo, "hi": self.hi,
                "why": self.why}


def rate(name: str, k: int, n: int, empty_why: str = "undefined: no run to count") -> Rate:
    """:class:`Rate` of k / n (n = 0: undefined with ``empty_why``).

    >>> r = rate("accuracy", 8, 20)
    >>> round(r.value, 2), round(r.lo, 4), round(r.hi, 4)
    (0.4, 0.2188, 0.6134)
    """
    if n == 0:
        return Rate(name, 0, 0, None, None, None, empty_why)
    lo, hi = wilson(int(k), int(n))
    return Rate(name, int(k), int(n), k / n, lo, hi)


def confusion(truth, pred) -> dict:
    """Counts of paired yes/no outcomes (``truth``: 3D, ``pred``: 2D; equal-length sequences of bool):
    {'tp', 'fp', 'fn', 'tn'}."""
    t = np.asarray(truth, dtype=bool)
    p = np.asarray(pred, dtype=bool)
    if t.shape != p.shape or t.ndim != 1:
        raise InputError(f"paired outcomes need two 1-D sequences of the same length, got {t.shape} and {p.shape}")
    return {"tp": int((t & p).sum()), "fp": int((~t & p).sum()), "fn": int((t & ~p).sum()),
            "tn": int((~t & ~p).sum())}


@dataclass(frozen=True)
class Agreement:
    """The 2D-3D classification agreement of one limit state: counts, the three rates, the verdict
    (status 'met' / 'missed' / 'not testable' / 'not applicable', ``why`` says which bound misses and whether
    disagreement is shown or only agreement not shown) and the rule it applied."""

    state: str
    tp: int
    fp: int
    fn: int
    tn: int
    accuracy: Rate
    precision: Rate
    recall: Rate
    status: str
    why: str
    rule: str
    runs_differ: tuple = ()

    @property
    def met(self) -> bool:
        return self.status == "met"

    def to_dict(self) -> dict:
        return {"state": self.state, "reference": REFERENCE, "tp": self.tp, "fp": self.fp, "fn": self.fn,
                "tn": self.tn, "accuracy": self.accuracy.to_dict(), "precision": self.precision.to_dict(),
                "recall": self.recall.to_dict(), "status": self.status, "met": self.met, "why": self.why,
                "rule": self.rule, "runs_differ": list(self.runs_differ)}


NOT_TESTABLE = "not testable"
"""The status of a limit state whose runs hold no positive case (or no negative one) in either model: every
run agrees whatever the model does, so the check could not fail (issue [25])."""


def rule_text(accuracy_min: float = ACCURACY_MIN, pr_min: float = PR_MIN) -> str:
    return (f"met when the accuracy's 95 % Wilson lower bound >= {accuracy_min:g} and, where defined, the "
            f"precision's and the recall's lower bounds >= {pr_min:g} ({REFERENCE})")


def _judge(r: Rate, threshold: float) -> str | None:
    """None if r's lower bound clears ``threshold``, else the reason."""
    if r.value is None or r.lo >= threshold:
        return None
    if r.hi < threshold:
        return (f"{r.name} {r.k}/{r.n} = {r.value:.2f}, 95 % interval [{r.lo:.2f}, {r.hi:.2f}] lies below "
                f"{threshold:g}: disagreement shown")
    best = r.n / (r.n + 1.959963984540054 ** 2)
    more = "" if best >= threshold else f"; even {r.n}/{r.n} would give {best:.2f}: too few runs"
    return (f"{r.name} {r.k}/{r.n} = {r.value:.2f}, 95 % lower bound {r.lo:.2f} < {threshold:g}: agreement not "
            f"shown{more}")


def agreement(truth, pred, state: str, accuracy_min: float = ACCURACY_MIN, pr_min: float = PR_MIN,
              run_ids=None) -> Agreement:
    """The verdict of the module docstring on paired outcomes (``truth``: 3D, ``pred``: 2D);
    ``run_ids`` (default 0..n-1) name the runs that differ."""
    c = confusion(truth, pred)
    n = sum(c.values())
    ids = list(range(n)) if run_ids is None else list(run_ids)
    differ = tuple(ids[i] for i, (a, b) in enumerate(zip(truth, pred)) if bool(a) != bool(b))
    acc = rate("accuracy", c["tp"] + c["tn"], n, "undefined: no run")
    prec = rate("precision", c["tp"], c["tp"] + c["fp"], "undefined: the 2D model says yes in no run")
    rec = rate("recall", c["tp"], c["tp"] + c["fn"], "undefined: the 3D scene says yes in no run")
    rule = rule_text(accuracy_min, pr_min)
    if n == 0:
        return Agreement(state, **c, accuracy=acc, precision=prec, recall=rec, status="not applicable",
                         why="not applicable: no run left to count", rule=rule)
    positives, negatives = c["tp"] + c["fp"] + c["fn"], c["tn"] + c["fp"] + c["fn"]
    if positives == 0 or negatives == 0:
        word, every = ("positive", "no") if positives == 0 else ("negative", "yes")
        return Agreement(state, **c, accuracy=acc, precision=prec, recall=rec, status=NOT_TESTABLE,
                         why=f"not testable: no {word} case in {n} runs (both models say {every} in every run), so "
                             f"agreement there cannot fail and says nothing of the 2D model's "
                             f"{'recall and precision' if positives == 0 else 'specificity'}", rule=rule)
    why = [w for w in (_judge(acc, accuracy_min), _judge(prec, pr_min), _judge(rec, pr_min)) if w]
    status = "missed" if why else "met"
    if prec.value is None and rec.value is None:
        why.append("no run says yes in either model: precision and recall undefined, judged on accuracy alone")
    if differ:
        why.append(f"runs that differ: {list(differ)}")
    return Agreement(state, **c, accuracy=acc, precision=prec, recall=rec, status=status, why="; ".join(why),
                     rule=rule, runs_differ=differ)


def not_applicable(state: str, why: str) -> Agreement:
    """An :class:`Agreement` for a limit state this base does not have (e.g. capacity, fixed base)."""
    na = Rate("-", 0, 0, None, None, None, why)
    return Agreement(state, 0, 0, 0, 0, na, na, na, "not applicable", why, rule_text())


# ------------------------------------------------------------------ the runs

def governing_side(theta_L: float, theta_R: float, params) -> str:
    """'L' or 'R': the pivot whose peak |theta| / delta is the larger (R on a tie).

    >>> from types import SimpleNamespace as P
    >>> governing_side(0.02, 0.02, P(delta_L=0.1, delta_R=0.2))
    'L'
    """
    return "L" if theta_L / params.delta_L > theta_R / params.delta_R else "R"


def outcome_2d(model: RockingModel, motion, free_time: float) -> dict:
    """The fixed-base 2D outcome of one run (module docstring): uplift at the 3D lift height."""
    r = simulate_2d(model, motion, t_end=motion.end + free_time)
    lifted = bool(r.overturned) or max(r.theta_max_L, r.theta_max_R) >= lift_angle(model.params)
    side = governing_side(r.theta_max_L, r.theta_max_R, model.params)
    return {"uplift": lifted, "overturned": bool(r.overturned), "capacity": None,
            "peak": math.inf if r.overturned else float(r.theta_max_over_delta), "side": side,
            "uplift_time": r.uplift_time, "overturn_side": r.overturn_side, "finite": True}


def outcome_3d(task: tuple) -> dict:
    """One fixed-base 3D run (module level, for the executors): task = (scene, motion, settings,
    contact, free_time)."""
    scene, motion, settings, contact, free_time = task
    r = simulate_statue(scene, motion, settings=settings, contact=contact, free_time=free_time)
    side = governing_side(r.theta_max_L, r.theta_max_R, scene.params)
    return {"uplift": bool(r.overturned) or r.uplift_time is not None, "overturned": bool(r.overturned),
            "capacity": None, "peak": math.inf if r.overturned else float(r.theta_max_over_delta), "side": side,
            "uplift_time": r.uplift_time, "overturn_side": r.overturn_side, "max_lift": float(r.max_lift),
            "slip": float(slip_of(r)), "yaw": float(np.abs(r.yaw).max(initial=0.0)), "finite": bool(r.finite),
            "wall_time_s": float(r.wall_time), "sim_time_s": float(r.steps * r.settings.dt)}


def _pk(x) -> str:
    return "overturned" if not math.isfinite(x) else f"{x:.3f}"


def disagreement_why(state: str, o2: dict, o3: dict, motion, model: RockingModel) -> str:
    """Why one run's ``state`` differs: who says yes, the record's peaks toward each side against the
    uplift accelerations, both peaks theta / delta (and the 3D lift height)."""
    key = KEYS[state]
    yes, no = ("2D", "3D") if o2[key] else ("3D", "2D")
    verb = states.get(state).exceeded_words
    hi, lo = motion.extremes()
    aL, aR = model.lift_accelerations
    if "plate_acc" in o2 and "plate_acc" in o3:     # on the isolator the statue feels the plate, not the ground
        felt = (f"the plate's peak absolute acceleration 2D {o2['plate_acc'] / G:.3f} g, 3D {o3['plate_acc'] / G:.3f} g "
                f"against the uplift accelerations alpha_L a_L = {aL / G:.3f} g, alpha_R a_R = {aR / G:.3f} g")
    else:
        felt = (f"the record's peak toward +x {hi / G:.3f} g (lifts the left pivot above alpha_L a_L = "
                f"{aL / G:.3f} g), toward -x {-lo / G:.3f} g (right pivot, alpha_R a_R = {aR / G:.3f} g)")
    txt = (f"{yes} {verb}, {no} does not at PGA {motion.pga / G:.3f} g: {felt}; peak |theta|/delta 2D "
           f"{_pk(o2['peak'])} ({o2.get('side', '?')}), 3D {_pk(o3['peak'])} ({o3.get('side', '?')})")
    if state == states.CAPACITY and "u_max" in o2 and "u_max" in o3:
        txt += f"; peak plate travel 2D {o2['u_max'] * 1000:.1f} mm, 3D {o3['u_max'] * 1000:.1f} mm"
    if state == states.FULL_CONTACT and "max_lift" in o3:
        txt += f"; 3D highest base point {o3['max_lift'] * 1000:.3f} mm (lift-off: {LIFT_HEIGHT * 1000:g} mm)"
    return txt


def peak_comparison(o2: dict, o3: dict) -> dict:
    """The run's peak |theta| / delta, compared only where at least one model lifts off and neither
    overturns: {'status': 'compared' | reason, 'peak_2d', 'peak_3d', 'ratio' (3D / 2D)}."""
    out = {"peak_2d": o2["peak"], "peak_3d": o3["peak"], "ratio": None}
    if not (o2["uplift"] or o3["uplift"]):
        return out | {"status": NEITHER_LIFTS}
    if o2["overturned"] or o3["overturned"]:
        who = " and ".join(s for s, o in (("2D", o2), ("3D", o3)) if o["overturned"])
        return out | {"status": f"not compared: {who} overturns (the overturning row compares it)"}
    if o2["peak"] <= 0.0:
        return out | {"status": "not compared: 2D peak is zero"}
    return out | {"status": "compared", "ratio": o3["peak"] / o2["peak"]}


def default_levels(*medians: float | None, factors=FACTORS) -> list[float]:
    """PGA levels, m/s^2: ``factors`` x each 2D fragility median (finite ones; e.g. uplift,
    overturning), sorted, duplicates (within 1 %) dropped.

    >>> [round(x, 3) for x in default_levels(1.0, 4.0, factors=(0.5, 1.0, 2.0))]
    [0.5, 1.0, 2.0, 4.0, 8.0]
    """
    meds = [m for m in medians if m is not None and math.isfinite(m) and m > 0]
    if not meds:
        raise InputError("no finite positive 2D fragility median to put the PGA levels around")
    out = []
    for x in sorted(f * m for m in meds for f in factors):
        if not out or x > out[-1] * 1.01:
            out.append(float(x))
    return out


# ------------------------------------------------------------------ the result

@dataclass(frozen=True, eq=False)
class Classification:
    """What :func:`classify_ensemble` returns. ``states``: {state: Agreement}; ``runs``: one dict per
    run (record, level, PGA, the 2D and 3D outcomes, per-state agreement and why, the peak
    comparison, the screen); ``fragility``: {state: {'2d': {...}, '3d': {...}}} medians (g) side by
    side; ``info``: the base, levels, cost."""

    base: str
    states: dict
    runs: tuple
    fragility: dict
    info: dict = field(default_factory=dict)

    @property
    def met(self) -> bool:
        """All applicable limit states met."""
        return all(a.status != "missed" for a in self.states.values())

    def to_dict(self) -> dict:
        """JSON-ready (every non-finite number - an overturned run's inf peak - as None)."""
        return json_safe({"schema": "statue2model.crosscheck.classification/1", "base": self.base,
                          "reference": REFERENCE, "met": self.met,
                          "states": {k: a.to_dict() for k, a in self.states.items()},
                          "fragility": self.fragility, "runs": list(self.runs), "info": self.info})

    def table(self) -> str:
        """Plain-text summary: one row per limit state, the medians, the disagreeing runs' reasons."""
        def r(x: Rate) -> str:
            return f"{'n/a':>17s}" if x.value is None else f"{x.value:5.2f} [{x.lo:.2f},{x.hi:.2f}]"

        lines = [f"{self.base} base, {self.info.get('n_runs', len(self.runs))} runs ({REFERENCE})",
                 f"{'state':12s} {'TP':>3s} {'FP':>3s} {'FN':>3s} {'TN':>3s} {'accuracy':>17s} {'precision':>17s} "
                 f"{'recall':>17s} {'med2D g':>8s} {'med3D g':>8s} verdict"]
        for k, a in self.states.items():
            f = self.fragility.get(k, {})
            m2 = f.get("2d", {}).get("median_g")
            m3 = f.get("3d", {}).get("median_g")
            s2, s3 = ("-" if m is None else f"{m:.3f}" for m in (m2, m3))
            lines.append(f"{k:12s} {a.tp:3d} {a.fp:3d} {a.fn:3d} {a.tn:3d} {r(a.accuracy)} {r(a.precision)} "
                         f"{r(a.recall)} {s2:>8s} {s3:>8s} {a.status}")
            if a.why:
                lines.append(f"    why: {a.why}")
        pr = self.info.get("peak_ratio") or {}
        if pr.get("n"):
            lines.append(f"peak |theta|/delta 3D / 2D over {pr['n']} runs where one lifts and neither overturns: "
                         f"median {pr['median']:.2f} (range {pr['min']:.2f}-{pr['max']:.2f})")
        elif pr:
            lines.append(f"peak |theta|/delta: {pr.get('why')}")
        for run in self.runs:
            for k, w in run.get("why", {}).items():
                lines.append(f"  run {run['run']} (record {run['record']}, {run['pga_g']:.3f} g) {k}: {w}")
        return "\n".join(lines)


def _fragility(levels, yes2, yes3, runs_per_level) -> dict:
    from ..assessment.fragility import fit_lognormal

    out = {}
    for side, yes in (("2d", yes2), ("3d", yes3)):
        med, beta, status = fit_lognormal(levels, yes, runs_per_level)
        ok = status in ("ok", "step")
        out[side] = {"median_g": med / G if ok else None, "beta": beta if ok else None, "status": status,
                     "counts": [int(x) for x in yes]}
    out["levels_g"] = [float(x) / G for x in levels]
    out["trials"] = [int(x) for x in runs_per_level]
    out["ratio_3d_2d"] = (out["3d"]["median_g"] / out["2d"]["median_g"]
                          if out["3d"]["median_g"] and out["2d"]["median_g"] else None)
    return out


def classify_ensemble(scene: StatueScene, model: RockingModel, records, levels=None,
                      settings: SimSettings | None = None, executor=None, *,
                      medians: tuple | None = None, factors=FACTORS, contact: ContactSettings | None = None,
                      free_time: float = 2.0, base: str = "fixed", run_2d=None, run_3d=None,
                      use_screen: bool = False, accuracy_min: float = ACCURACY_MIN, pr_min: float = PR_MIN,
                      workers: int = 2, progress=None, reuse_3d: Classification | None = None) -> Classification:
    """Scale every record of ``records`` (GroundMotions or a RecordSet) to every PGA level, run the 2D
    ``model`` and the 3D ``scene``, and score the classification per limit state (module docstring).

    levels   : PGA levels, m/s^2; None: :func:`default_levels` of ``medians`` = (2D fragility median
               PGA of uplift, of overturning), m/s^2, times ``factors``
    settings : the 3D engine settings (None: statue_scene.STATUE_SETTINGS)
    executor : a statue2model.compute.executors executor for the 3D runs (None: ``workers`` local
               processes, or serial for one)
    run_2d, run_3d : the runners (default :func:`outcome_2d`, :func:`outcome_3d` - fixed base); for an
               isolated scene pass its own (their outcome's ``capacity`` bool makes that row count)
               and ``base="isolated"``
    reuse_3d : an earlier Classification on the same scene, records and levels: its 3D outcomes are
               reused (to judge another 2D model against the same 3D runs)
    """
    say = progress or (lambda msg: None)
    recs = list(getattr(records, "records", records))
    if len(recs) < 1:
        raise InputError("the classification needs at least one record")
    if levels is None:
        if medians is None:
            raise InputError("give the PGA levels or the 2D fragility medians (uplift, overturning) to put them around")
        levels = default_levels(*medians, factors=factors)
    levels = [float(x) for x in levels]
    if not levels or any(not (math.isfinite(x) and x > 0) for x in levels):
        raise InputError(f"PGA levels must be positive accelerations (m/s^2), got {levels}")
    contact = ContactSettings() if contact is None else contact
    run_2d = outcome_2d if run_2d is None else run_2d
    run_3d = outcome_3d if run_3d is None else run_3d
    t0 = time.perf_counter()
    motions_, two, tasks, ids = [], [], [], []
    for j, pga in enumerate(levels):
        for i, rec in enumerate(recs):
            m = rec.scaled_to_pga(pga)
            motions_.append(m)
            ids.append((i, j))
            two.append(run_2d(model, m, free_time))
            tasks.append((scene, m, settings, contact, free_time))
    t2d = time.perf_counter() - t0
    if reuse_3d is not None:
        three = [r["out_3d"] for r in reuse_3d.runs]
        if len(three) != len(tasks) or reuse_3d.info.get("levels_m_s2") != levels:
            raise InputError(f"reuse_3d holds {len(three)} runs at other levels or records; this one needs "
                             f"{len(tasks)} at {levels}")
        where = "reused"
    else:
        from ..compute.executors import ProcessExecutor, SerialExecutor

        own = executor is None
        ex = (ProcessExecutor(workers) if workers > 1 else SerialExecutor()) if own else executor
        where = ex.describe()
        try:
            say(f"classification: {len(tasks)} 3D runs on {where}")
            three = list(ex.map(run_3d, tasks))
        finally:
            if own:
                ex.close()
    t3d = time.perf_counter() - t0 - t2d
    runs, keep = [], []
    for k, ((i, j), m, o2, o3) in enumerate(zip(ids, motions_, two, three)):
        row = {"run": k, "record": i, "level": j, "pga": levels[j], "pga_g": levels[j] / G,
               "record_label": getattr(recs[i], "label", str(i)), "out_2d": o2, "out_3d": o3,
               "peak": peak_comparison(o2, o3), "why": {}}
        reasons = []
        if "slip" in o3 and "yaw" in o3:
            if base == "fixed":
                scr = screen_values(model, m, o3["slip"], o3["yaw"], contact, m.end + free_time)
            else:       # on the isolator: the statue's slip and yaw on the plate (no fixed-base 2D demand)
                scr = validity_screen(0.0, 1.0, o3["slip"], o3["yaw"], contact.friction**2, normal_force=False)
            reasons = list(scr["reasons"])
        applicable = not (use_screen and reasons)
        if not o3.get("finite", True):
            applicable, reasons = False, reasons + ["3D state not finite"]
        row["applicable"], row["screen_reasons"] = applicable, reasons
        if applicable:
            keep.append(k)
            for s in STATES:
                key = KEYS[s]
                if o2.get(key) is not None and o3.get(key) is not None and bool(o2[key]) != bool(o3[key]):
                    row["why"][s] = disagreement_why(s, o2, o3, m, model) + (
                        f"; the 3D run leaves the 2D model's rocking assumption ({'; '.join(reasons)})"
                        if reasons else "")
        runs.append(row)
    agreements, frag = {}, {}
    excluded = [r["run"] for r in runs if not r["applicable"]]
    for s in STATES:
        key = KEYS[s]
        have = [k for k in keep if two[k].get(key) is not None and three[k].get(key) is not None]
        if not have:
            why = ("not applicable: a fixed base has no isolator capacity" if s == "capacity" and base == "fixed"
                   else f"not applicable: no run gives a {s} outcome in both models")
            agreements[s] = not_applicable(s, why)
            continue
        a = agreement([bool(three[k][key]) for k in have], [bool(two[k][key]) for k in have], s, accuracy_min,
                      pr_min, run_ids=have)
        if excluded:
            a = _add_why(a, f"{len(excluded)} runs left out, both sides (runs {excluded}: "
                            f"{'; '.join(runs[excluded[0]]['screen_reasons'])})")
        flagged = [k for k in have if runs[k]["screen_reasons"]]
        if flagged:
            bad = [k for k in flagged if s in runs[k]["why"]]
            a = _add_why(a, f"counted: {len(flagged)} runs in which the 3D body slides or twists beyond the "
                            f"validity screen (runs {flagged}; {len(bad)} of them classified differently"
                            + (f": {bad}" if bad else "") + ")")
        agreements[s] = a
        lv = sorted({ids[k][1] for k in have})
        n_l = [sum(1 for k in have if ids[k][1] == j) for j in lv]
        y2 = [sum(1 for k in have if ids[k][1] == j and two[k][key]) for j in lv]
        y3 = [sum(1 for k in have if ids[k][1] == j and three[k][key]) for j in lv]
        frag[s] = _fragility([levels[j] for j in lv], y2, y3, n_l)
    ratios = [r["peak"]["ratio"] for r in runs if r["applicable"] and r["peak"]["ratio"] is not None]
    sim = sum(o.get("sim_time_s", 0.0) for o in three)
    info = {"base": base, "levels_m_s2": levels, "levels_g": [x / G for x in levels], "n_records": len(recs),
            "n_runs": len(runs), "n_counted": len(keep), "excluded_runs": excluded, "free_time_s": free_time,
            "medians_2d_input_g": None if medians is None else [None if m is None else m / G for m in medians],
            "factors": list(factors), "rule": rule_text(accuracy_min, pr_min), "model_2d": model.to_dict(),
            "lift_height_m": LIFT_HEIGHT,
            "peak_ratio": {"n": len(ratios), "median": float(np.median(ratios)) if ratios else None,
                           "min": min(ratios) if ratios else None, "max": max(ratios) if ratios else None,
                           "why": None if ratios else NEITHER_LIFTS + " (or one overturns) in every run"},
            "executor": where, "wall_time_s": time.perf_counter() - t0, "wall_time_2d_s": t2d,
            "wall_time_3d_s": t3d, "sim_time_3d_s": sim}
    return Classification(base, agreements, tuple(runs), frag, info)


def _add_why(a: Agreement, extra: str) -> Agreement:
    from dataclasses import replace

    return replace(a, why=f"{a.why}; {extra}" if a.why else extra)
