"""2D against 3D as a classifier for a statue on a pedestal: yes/no per body and outcome.

Each run (one ground motion) is made in both models:

* 2D - the numbers the assessment uses (statue2model.assessment.support.Support.run): the two-block
  rocking model (statue2model.rocking.stack) for the pedestal; for the statue, the two-block run when
  the pedestal lifts off (exact onset), else the single-body engine on a pedestal at rest
  (statue2model.rocking.engine.simulate, as assessment.limit_states.run_record does); the exact
  rigid-plastic sliding (statue2model.rocking.sliding) of the statue on the pedestal's top (under the
  ground's motion, or the rocking pedestal top's) and of the stack on the floor. No sliding while
  rocking, no rocking while sliding.
* 3D - the same stack in PyBullet (statue2model.crosscheck.stack_scene.simulate_stack_3d): both
  bodies free, Coulomb friction at both interfaces; taken as the reference ("truth").

The six outcomes (:data:`OUTCOMES`), each a yes/no per run:

    statue uplift        the statue's base edge lifts off the pedestal's top
    statue overturning   the statue reaches its delta (or the pedestal overturns with it)
    statue sliding       the statue slides on the pedestal's top more than ``slide_threshold``
    pedestal uplift      the pedestal's base edge lifts off the floor
    pedestal overturning the stack reaches the composite's delta
    pedestal sliding     the pedestal slides on the floor more than ``slide_threshold``

Uplift is read in both models at the 3D lift height (statue_scene.LIFT_HEIGHT, 0.2 mm: what the 3D
contacts resolve): in 2D, peak |theta| >= asin(LIFT_HEIGHT / base width) (statue_cases.lift_angle;
the statue's own base, the pedestal's for the pedestal); an overturned body has lifted. The 2D exact
onset is kept beside it (``uplift_exact``). Sliding: the 2D peak displacement (max of the two
directions) and the 3D peak of the pivot point (stack_scene: rocking without slip reads ~0) against
the same threshold (SLIDE_THRESHOLD, 5 mm by default).

Per outcome the paired runs are counted as in classification.py (3D the reference, 2D the
prediction): both yes (TP), 2D only (FP), 3D only (FN), both no (TN); agreement = (TP + TN) / n with
its 95 % Wilson interval, precision TP / (TP + FP) and recall TP / (TP + FN) where defined. The verdict
(:func:`verdict`):

    "not testable: no positive case in N runs"   neither model says yes in any run (issue [25]: an
    "not testable: no negative case in N runs"   agreement on one class only tests nothing)
    "agrees"     agreement >= ACCURACY_MIN (0.8) and, where defined, precision and recall >= PR_MIN (0.5)
    "disagrees"  otherwise

With few runs the verdict reads the point values; whether the agreement is also SHOWN at 95 % (the
rule of classification.agreement: the lower bounds) is reported beside it (``shown_95``): with every
run agreeing it needs >= 16 runs. A run whose 3D state is not finite is left out on both sides.

Every run that is classified differently says why, where it can be said (:func:`miss_why`): who says
yes, the record's peaks against the body's uplift accelerations or its friction, both peaks; and the
cause when a model's assumption is left (the 3D body slid while the 2D model has it rock without
sliding; the 3D body rocked while the 2D sliding assumes full contact; the 3D pedestal slid, which
caps the acceleration passed up to the statue near mu_floor g; the pedestal lifted in one model only).

Example
-------
>>> verdict(0, 0, 0, 12)
('not testable: no positive case in 12 runs', 'neither model says yes in any run')
>>> verdict(3, 0, 1, 8)[0]
'agrees'
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..assessment import states
from ..errors import InputError
from ..quantities import G
from .classification import ACCURACY_MIN, PR_MIN, REFERENCE, Rate, agreement, confusion, rate
from .ensemble import json_safe
from .statue_cases import lift_angle
from .statue_scene import LIFT_HEIGHT

SLIDE_THRESHOLD = 5e-3
"""m: a body 'slides' when its peak sliding on its support exceeds this (both models). Above the 3D
scene's creep: measured 0.6-1.0 mm of pedestal 'sliding' over 25 s records at PGA 0.1-0.14 g with
mu 0.4 (it cannot slide there), so a 1 mm threshold would read the solver's drift as sliding."""
FREE_TIME_3D = 3.0
"""s of 3D simulation after the motion ends (the run stops earlier once both bodies are at rest)."""
LIFT_RATIO = 1.5
"""The pipeline's second level when the design records' mean PGA is below the stack's (composite's)
smaller uplift acceleration: the records scaled so that their mean PGA is this many times it
(:func:`lift_factor`): the pedestal lifts."""
QUIET_RATIO = 0.6
"""... and when it is above: this many times it: the pedestal stays on the floor (a record's peak below
the static uplift acceleration cannot lift it from rest)."""
BODIES = ("statue", "pedestal")
WHATS = ("uplift", states.OVERTURNING, states.SLIDING)
"""What is classified of each body: its lift-off, and the limit states' overturning and sliding (the
pedestal's rows are pedestal_overturning and pedestal_sliding: assessment/states.py)."""
OUTCOMES = tuple(f"{b}_{w}" for b in BODIES for w in WHATS)
"""The classified outcomes, body_what."""
_KEY = {"uplift": "uplift", states.OVERTURNING: "overturned", states.SLIDING: "slides"}
_VERB = {"uplift": "lifts off", states.OVERTURNING: "overturns"}
_ON = {"statue": "the pedestal's top", "pedestal": "the floor"}


def _f(x) -> float | None:
    """A finite float or None."""
    try:
        x = float(x)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


# ------------------------------------------------------------------ the two sides of a run

def support_of_scene(scene, kinetic_ratio: float = 1.0, capacity: float = 0.05):
    """The 2D Support (assessment/support.py) of a 3D StackScene whose pedestal is a box: the statue's
    RockingParams, the pedestal's width, height and mass, the statue's centre of mass ``offset_x`` (m)
    from the pedestal's axis as the 2D x2, frictions mu_top and mu_floor (static; kinetic
    ``kinetic_ratio`` x static: 1 is the 3D engine's single coefficient), sliding capacities
    ``capacity`` (m, not read by the classification)."""
    from ..assessment.support import Support
    from ..rocking.sliding import Friction
    from ..rocking.stack import Pedestal, StackModel

    hull = np.asarray(scene.pedestal.hull, dtype=float)
    w, d, h = (float(x) for x in hull.max(axis=0) - hull.min(axis=0))
    stack = StackModel(scene.statue.params, Pedestal.box(w, d, h, scene.pedestal.mass), x2=scene.offset_x)
    return Support(Friction(scene.mu_top, kinetic_ratio * scene.mu_top), (capacity, capacity), "a test capacity",
                   stack, Friction(scene.mu_floor, kinetic_ratio * scene.mu_floor), (capacity, capacity),
                   "a test capacity")


def outcome_2d(task: tuple) -> dict:
    """One 2D run (module level, for the executors): task = (support, model, motion, slide_threshold);
    ``model`` the statue's single-body RockingModel (None: Housner's of the stack's statue). Returns
    {'statue': {...}, 'pedestal': {...}, 'stack_outcome', 'statue_from'} (module docstring)."""
    from ..rocking.engine import simulate
    from ..rocking.model import RockingModel

    support, model, motion, thr = task
    stack = support.stack
    if stack is None:
        raise InputError("the stack classification needs a Support with a pedestal (its two-block model)")
    model = RockingModel.housner(stack.statue) if model is None else model
    sr, r = support.run_detail(motion)
    ped = r.pedestal
    p_ot = bool(ped.overturned)
    pedestal = {"uplift": p_ot or float(ped.theta_max) >= lift_angle(stack.composite), "uplift_exact": bool(ped.uplift),
                "overturned": p_ot, "peak": None if p_ot else _f(ped.theta_max_over_delta),
                "theta_max": _f(ped.theta_max), "slide": _f(max(sr.ped_slide_pos, sr.ped_slide_neg))}
    if sr.statue is not None:               # the pedestal lifts: the two-block run's statue
        st = r.statue
        ot = bool(sr.statue["overturned"])
        th, exact, peak = float(st.theta_max), bool(st.uplift), st.theta_max_over_delta
        src = "the two-block run (the pedestal lifts)"
    else:                                   # the pedestal in full contact: the statue as on the ground
        s1 = simulate(model, motion)
        ot = bool(s1.overturned)
        th, exact, peak = max(s1.theta_max_L, s1.theta_max_R), s1.uplift_time is not None, s1.theta_max_over_delta
        src = "the single-body model (the pedestal stays in full contact)"
    statue = {"uplift": ot or th >= lift_angle(stack.statue), "uplift_exact": exact, "overturned": ot,
              "peak": None if ot else _f(peak), "theta_max": _f(th),
              "slide": _f(max(sr.slide_pos, sr.slide_neg))}
    for b in (statue, pedestal):
        b["slides"] = b["slide"] is not None and b["slide"] > thr
    return {"statue": statue, "pedestal": pedestal, "stack_outcome": r.outcome, "statue_from": src}


def outcome_3d(task: tuple) -> dict:
    """One 3D run (module level, for the executors): task = (scene, motion, settings, free_time,
    slide_threshold). The statue overturns also when the pedestal does (it falls with it)."""
    from .stack_scene import simulate_stack_3d

    scene, motion, settings, free_time, thr = task
    r = simulate_stack_3d(scene, motion, settings=settings, t_end=motion.end + free_time)
    out = {}
    for name, b in (("statue", r.statue), ("pedestal", r.pedestal)):
        ot = bool(b.overturned) or (name == "statue" and bool(r.pedestal.overturned))
        out[name] = {"uplift": ot or b.lifted, "overturned": ot, "peak": None if ot else _f(b.theta_max_over_delta),
                     "theta_max": _f(b.theta_max), "max_lift": _f(b.max_lift), "slide": _f(b.peak_slide),
                     "uplift_time": _f(b.uplift_time)}
        out[name]["slides"] = out[name]["slide"] is not None and out[name]["slide"] > thr
    return out | {"finite": bool(r.finite), "stopped": r.stopped, "wall_time_s": float(r.wall_time),
                  "sim_time_s": float(r.simulated_time)}


def yes(o: dict, key: str) -> bool:
    """The yes/no of outcome ``key`` (body_what) in a run's outcome ``o`` (either model)."""
    body, what = key.split("_", 1)
    return bool(o[body][_KEY[what]])


# ------------------------------------------------------------------ why a run differs

def _mm(x) -> str:
    return "-" if x is None else f"{x * 1000:.1f} mm"


def _pk(o: dict) -> str:
    return "overturned" if o["overturned"] else ("-" if o["peak"] is None else f"{o['peak']:.3f}")


def miss_why(key: str, o2: dict, o3: dict, motion, support, scene=None, thr: float = SLIDE_THRESHOLD) -> str:
    """Why outcome ``key`` differs in one run: who says yes, what the body felt against what lifts or
    slides it, both peaks, and the cause where a model's assumption is left (module docstring)."""
    body, what = key.split("_", 1)
    a, b = o2[body], o3[body]
    who, other = ("2D", "3D") if yes(o2, key) else ("3D", "2D")
    hi, lo = motion.extremes()
    stack = support.stack
    mu3 = None if scene is None else (scene.mu_top if body == "statue" else scene.mu_floor)
    fr = support.friction if body == "statue" else support.pedestal_friction
    causes = []
    if what == "sliding":
        txt = (f"{who} slides more than {thr * 1000:g} mm on {_ON[body]}, {other} does not: peak slide 2D "
               f"{_mm(a['slide'])}, 3D {_mm(b['slide'])}; the record's peak {max(hi, -lo) / G:.3f} g against mu_s "
               f"{fr.mu_s:g} (2D" + (f", 3D {mu3:g})" if mu3 is not None else ")"))
        if who == "2D" and b["uplift"]:
            causes.append(f"the 3D {body} rocked instead (lifted off): the 2D sliding is that of a body in full "
                          "contact (no slide-rock coupling)")
        if who == "3D" and b["uplift"]:
            causes.append(f"the 3D {body} slid while rocking (slide-rock coupling, which the 2D model leaves out)")
        if body == "statue" and who == "2D" and o3["pedestal"]["slides"]:
            causes.append(f"the 3D pedestal slid {_mm(o3['pedestal']['slide'])} on the floor, which caps the "
                          "acceleration passed up to the statue near mu_floor g (2D: the statue slides under the "
                          "ground's motion, the pedestal's sliding apart)")
        if body == "statue" and o2["pedestal"]["uplift_exact"] != o3["pedestal"]["uplift"]:
            causes.append("the pedestal lifted in " + ("2D" if o2["pedestal"]["uplift_exact"] else "3D")
                          + " only: the statue felt another motion of the pedestal's top")
        if not causes and mu3 is not None and not math.isclose(fr.mu_k, mu3):
            causes.append(f"2D slides at mu_k {fr.mu_k:g} once started, 3D at its single coefficient {mu3:g}")
        if not causes:
            causes.append("near the threshold")
    else:
        p = stack.statue if body == "statue" else stack.composite
        txt = (f"{who} {_VERB[what]}, {other} does not: the record's peak toward +x {hi / G:.3f} g, toward -x "
               f"{-lo / G:.3f} g against the {'statue' if body == 'statue' else 'stack (composite)'}'s uplift "
               f"accelerations a_L {p.a_L / G:.3f} g, a_R {p.a_R / G:.3f} g; peak |theta|/delta 2D {_pk(a)}, 3D "
               f"{_pk(b)}")
        if what == "uplift" and b.get("max_lift") is not None:
            txt += f"; 3D highest base point {b['max_lift'] * 1000:.3f} mm (lift-off: {LIFT_HEIGHT * 1000:g} mm)"
        if b["slides"]:
            causes.append(f"the 3D {body} slid {_mm(b['slide'])} on {_ON[body]} while the 2D model has it rock "
                          "without sliding")
        if body == "statue":
            if o3["pedestal"]["slides"]:
                causes.append(f"the 3D pedestal slid {_mm(o3['pedestal']['slide'])} on the floor (the 2D "
                              "two-block model has no sliding): the statue felt the sliding pedestal's motion, "
                              "capped near mu_floor g")
            if o2["pedestal"]["uplift"] != o3["pedestal"]["uplift"]:
                causes.append("the pedestal lifted in " + ("2D" if o2["pedestal"]["uplift"] else "3D") + " only")
            causes.append(f"2D statue from {o2.get('statue_from', '?')}")
    return txt + ("; " + "; ".join(causes) if causes else "")


# ------------------------------------------------------------------ the verdict

def _runs(n: int) -> str:
    return f"{n} run" if n == 1 else f"{n} runs"


def verdict(tp: int, fp: int, fn: int, tn: int, accuracy_min: float = ACCURACY_MIN,
            pr_min: float = PR_MIN) -> tuple[str, str]:
    """(verdict, why) of the counts (module docstring): 'not testable: ...' when no run says yes in
    either model or every run says yes in both, else 'agrees' / 'disagrees' on the point values."""
    n = tp + fp + fn + tn
    if n == 0:
        return "not testable: no run counted", "no run left to count"
    if tp + fp + fn == 0:
        return f"not testable: no positive case in {_runs(n)}", "neither model says yes in any run"
    if fp + fn + tn == 0:
        return f"not testable: no negative case in {_runs(n)}", "both models say yes in every run"
    why = []
    acc = (tp + tn) / n
    if acc < accuracy_min:
        why.append(f"agreement {acc:.2f} < {accuracy_min:g}")
    if tp + fp and tp / (tp + fp) < pr_min:
        why.append(f"precision {tp / (tp + fp):.2f} < {pr_min:g} (2D says yes in {_runs(tp + fp)}, 3D agrees in {tp})")
    if tp + fn and tp / (tp + fn) < pr_min:
        why.append(f"recall {tp / (tp + fn):.2f} < {pr_min:g} (3D says yes in {_runs(tp + fn)}, 2D in {tp})")
    if tp + fn == 0:
        why.append("3D says yes in no run: only the 2D model's false alarms are tested")
    if tp + fp == 0:
        why.append("2D says yes in no run: only its misses are tested")
    bad = any(w.startswith(("agreement", "precision", "recall")) for w in why)
    return ("disagrees" if bad else "agrees"), "; ".join(why)


@dataclass(frozen=True)
class OutcomeAgreement:
    """One outcome's paired counts (both yes ``tp``, 2D only ``fp``, 3D only ``fn``, both no ``tn``),
    ``agreement`` (Rate: (tp + tn) / n), ``precision``, ``recall`` (Rate, None where undefined), the
    ``verdict`` and its ``why``, ``shown_95`` (the 95 % rule of classification.agreement is met),
    ``rule_95_why``, and ``runs_differ`` (run numbers)."""

    key: str
    tp: int
    fp: int
    fn: int
    tn: int
    agreement: Rate
    precision: Rate
    recall: Rate
    verdict: str
    why: str
    shown_95: bool
    rule_95_why: str
    runs_differ: tuple = ()

    @property
    def n(self) -> int:
        return self.tp + self.fp + self.fn + self.tn

    @property
    def testable(self) -> bool:
        return not self.verdict.startswith("not testable")

    def to_dict(self) -> dict:
        body, what = self.key.split("_", 1)
        return {"key": self.key, "body": body, "outcome": what, "n": self.n, "both_yes": self.tp,
                "only_2d": self.fp, "only_3d": self.fn, "both_no": self.tn, "agreement": self.agreement.to_dict(),
                "precision": self.precision.to_dict(), "recall": self.recall.to_dict(), "verdict": self.verdict,
                "why": self.why, "shown_95": self.shown_95, "rule_95_why": self.rule_95_why,
                "runs_differ": list(self.runs_differ)}


def score(key: str, truth, pred, run_ids=None) -> OutcomeAgreement:
    """The :class:`OutcomeAgreement` of paired yes/no (``truth``: 3D, ``pred``: 2D)."""
    c = confusion(truth, pred) if len(truth) else {"tp": 0, "fp": 0, "fn": 0, "tn": 0}
    n = sum(c.values())
    ids = list(range(n)) if run_ids is None else list(run_ids)
    differ = tuple(int(ids[i]) for i, (t, p) in enumerate(zip(truth, pred)) if bool(t) != bool(p))
    v, why = verdict(**c)
    acc = rate("agreement", c["tp"] + c["tn"], n, "undefined: no run")
    prec = rate("precision", c["tp"], c["tp"] + c["fp"], "undefined: the 2D model says yes in no run")
    rec = rate("recall", c["tp"], c["tp"] + c["fn"], "undefined: the 3D scene says yes in no run")
    if n and not v.startswith("not testable"):
        a = agreement(truth, pred, key, run_ids=ids)
        shown, why95 = a.status == "met", a.why
    else:
        shown, why95 = False, "not testable"
    return OutcomeAgreement(key, c["tp"], c["fp"], c["fn"], c["tn"], acc, prec, rec, v, why, shown, why95, differ)


# ------------------------------------------------------------------ the result

@dataclass(frozen=True, eq=False)
class StackClassification:
    """What :func:`classify_stack` returns: ``outcomes`` {key: OutcomeAgreement} in :data:`OUTCOMES`
    order; ``runs`` one dict per run (record, group, PGA, both outcomes, per-outcome why); ``by_group``
    {group: {key: [tp, fp, fn, tn]}}; ``info`` (the models, threshold, cost)."""

    outcomes: dict
    runs: tuple
    by_group: dict = field(default_factory=dict)
    info: dict = field(default_factory=dict)

    def counts(self) -> dict:
        """{key: (both yes, 2D only, 3D only, both no)}."""
        return {k: (a.tp, a.fp, a.fn, a.tn) for k, a in self.outcomes.items()}

    @property
    def verdicts(self) -> dict:
        return {k: a.verdict for k, a in self.outcomes.items()}

    def to_dict(self) -> dict:
        """JSON-ready: finite numbers only, None where undefined."""
        return json_safe({"schema": "statue2model.crosscheck.stack_classification/1", "reference": REFERENCE,
                          "rule": rule_text(self.info.get("slide_threshold_m", SLIDE_THRESHOLD)),
                          "outcomes": {k: a.to_dict() for k, a in self.outcomes.items()},
                          "by_group": self.by_group, "runs": list(self.runs), "info": self.info})

    def table(self) -> str:
        """Plain text: one row per outcome, then the runs that differ and why."""
        lines = [f"statue on a pedestal, {self.info.get('n_counted', len(self.runs))} runs ({REFERENCE})",
                 f"{'outcome':22s} {'both':>4s} {'2D':>4s} {'3D':>4s} {'none':>4s} {'agreement':>17s} verdict"]
        for k, a in self.outcomes.items():
            r = a.agreement
            ag = f"{'n/a':>17s}" if r.value is None else f"{r.value:5.2f} [{r.lo:.2f},{r.hi:.2f}]"
            lines.append(f"{k:22s} {a.tp:4d} {a.fp:4d} {a.fn:4d} {a.tn:4d} {ag} {a.verdict}"
                         + (f" ({a.why})" if a.why else ""))
        for run in self.runs:
            for k, w in run.get("why", {}).items():
                lines.append(f"  run {run['run']} ({run['record_label']}, {run['group']}, {run['pga_g']:.3f} g) "
                             f"{k}: {w}")
        return "\n".join(lines)


def rule_text(thr: float = SLIDE_THRESHOLD) -> str:
    return (f"'agrees' when (both yes + both no) / n >= {ACCURACY_MIN:g} and, where defined, precision and recall >= "
            f"{PR_MIN:g}; 'not testable' when no run says yes in either model (or every run says yes in both); "
            f"uplift at the 3D lift height {LIFT_HEIGHT * 1000:g} mm, sliding more than {thr * 1000:g} mm")


def lift_factor(stack, motions, ratio: float = LIFT_RATIO) -> float:
    """The factor that brings the mean PGA of ``motions`` to ``ratio`` x the smaller uplift acceleration
    (m/s^2) of the stack's composite (the pedestal with the statue stuck on it: what lifts the pedestal).

    >>> from statue2model.geometry.rocking_params import RockingParams
    >>> from statue2model.rocking.stack import Pedestal, StackModel
    >>> from statue2model.hazard import motions
    >>> st = StackModel(RockingParams(m=100.0, h=0.3, b_L=0.1, b_R=0.1, I_G=4.0), Pedestal(0.2, 0.5, 100.0))
    >>> st.composite.h, round(st.composite.a_R / 9.81, 4)          # a_up = g b / h_c = 0.2 / 0.9 g
    (0.9, 0.2222)
    >>> round(lift_factor(st, [motions.sine_pulse(1.0, 2.0)]) / 9.81, 4)   # PGA 1 m/s^2 -> 1.5 x 0.2222 g
    0.3333
    """
    c = stack.composite
    pga = [float(m.pga) for m in motions]
    if not pga or min(pga) <= 0:
        raise InputError("the lift factor needs motions with a positive PGA")
    return ratio * min(c.a_L, c.a_R) / float(np.mean(pga))


def classify_stack(support, scene_3d, motions, *, model=None, groups=None, slide_threshold: float = SLIDE_THRESHOLD,
                   settings=None, free_time: float = FREE_TIME_3D, executor=None, workers: int = 1,
                   progress=None) -> StackClassification:
    """Run every motion of ``motions`` (GroundMotions, m/s^2) in the 2D ``support`` (an
    assessment.support.Support with a pedestal: its two-block model and frictions) and in the 3D
    ``scene_3d`` (a stack_scene.StackScene of the same stack), and score the six outcomes (module
    docstring).

    model           : the statue's single-body RockingModel, used while the pedestal stays in full
                      contact (None: Housner's of the stack's statue)
    groups          : a name per motion (e.g. 'design', 'scaled x1.9'), counted apart in ``by_group``
    slide_threshold : m, a body slides when its peak sliding exceeds it
    settings        : the 3D engine settings (None: stack_scene.STACK_SETTINGS)
    free_time       : s of 3D simulation after each motion's end (early stop at rest or overturn)
    executor        : a compute.executors executor for both sides' runs (None: ``workers`` local
                      processes, or serial for one)
    """
    say = progress or (lambda msg: None)
    if getattr(support, "stack", None) is None:
        raise InputError("the stack classification needs a Support with a pedestal (its two-block model)")
    ms = list(getattr(motions, "records", motions))
    if not ms:
        raise InputError("the stack classification needs at least one motion")
    groups = ["all"] * len(ms) if groups is None else [str(g) for g in groups]
    if len(groups) != len(ms):
        raise InputError(f"groups names {len(groups)} motions, there are {len(ms)}")
    if not (isinstance(slide_threshold, (int, float)) and math.isfinite(slide_threshold) and slide_threshold > 0):
        raise InputError(f"slide_threshold must be a positive length in m, got {slide_threshold!r}")
    if not (math.isfinite(free_time) and free_time >= 0):
        raise InputError(f"free_time must be >= 0 s, got {free_time!r}")
    from ..compute.executors import ProcessExecutor, SerialExecutor

    own = executor is None
    ex = (ProcessExecutor(workers) if workers > 1 else SerialExecutor()) if own else executor
    t0 = time.perf_counter()
    try:
        say(f"stack classification: {len(ms)} 2D runs on {ex.describe()}")
        two = list(ex.map(outcome_2d, [(support, model, m, slide_threshold) for m in ms],
                          desc="stack classification: 2D runs"))
        t2 = time.perf_counter() - t0
        say(f"stack classification: {len(ms)} 3D runs on {ex.describe()}")
        three = list(ex.map(outcome_3d, [(scene_3d, m, settings, free_time, slide_threshold) for m in ms],
                            desc="stack classification: 3D runs"))
        where = ex.describe()
    finally:
        if own:
            ex.close()
    t3 = time.perf_counter() - t0 - t2
    runs, keep = [], []
    for k, (m, g, o2, o3) in enumerate(zip(ms, groups, two, three)):
        row = {"run": k, "record_label": getattr(m, "label", str(k)), "group": g, "pga": float(m.pga),
               "pga_g": float(m.pga) / G, "out_2d": o2, "out_3d": o3, "counted": bool(o3["finite"]), "why": {}}
        if not o3["finite"]:
            row["left_out"] = "3D state not finite"
        else:
            keep.append(k)
            for key in OUTCOMES:
                if yes(o2, key) != yes(o3, key):
                    row["why"][key] = miss_why(key, o2, o3, m, support, scene_3d, slide_threshold)
        runs.append(row)
    outcomes = {key: score(key, [yes(three[k], key) for k in keep], [yes(two[k], key) for k in keep], keep)
                for key in OUTCOMES}
    by_group = {}
    for g in dict.fromkeys(groups):
        ks = [k for k in keep if groups[k] == g]
        by_group[g] = {"n": len(ks), **{key: [int(v) for v in (
            confusion([yes(three[k], key) for k in ks], [yes(two[k], key) for k in ks]) if ks else
            {"tp": 0, "fp": 0, "fn": 0, "tn": 0}).values()] for key in OUTCOMES}}
    st = support.stack
    info = {"n_runs": len(runs), "n_counted": len(keep), "left_out": [r["run"] for r in runs if not r["counted"]],
            "slide_threshold_m": float(slide_threshold), "lift_height_m": LIFT_HEIGHT, "free_time_3d_s": free_time,
            "groups": list(dict.fromkeys(groups)),
            "model_2d": {"statue": st.statue.to_dict(), "pedestal": {"b": st.pedestal.b, "h": st.pedestal.h,
                                                                     "m": st.pedestal.m},
                         "x2": st.x2, "composite": st.composite.to_dict(),
                         "statue_model": None if model is None else model.to_dict(),
                         "mu_statue": [support.friction.mu_s, support.friction.mu_k],
                         "mu_pedestal": [support.pedestal_friction.mu_s, support.pedestal_friction.mu_k]},
            "scene_3d": scene_3d.to_dict(),
            "uplift_g": {"statue": [st.statue.a_L / G, st.statue.a_R / G],
                         "pedestal": [st.composite.a_L / G, st.composite.a_R / G]},
            "executor": where, "wall_time_s": time.perf_counter() - t0, "wall_time_2d_s": t2, "wall_time_3d_s": t3,
            "sim_time_3d_s": sum(o["sim_time_s"] for o in three),
            "stopped_3d": {s: sum(o["stopped"] == s for o in three) for s in sorted({o["stopped"] for o in three})}}
    return StackClassification(outcomes, tuple(runs), by_group, info)
