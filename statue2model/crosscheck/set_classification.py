"""The 2D/3D classification over the run's design record set, on the fixed base and on the isolator.

The run's design record set (>= 7 code-compliant records, MODEL.md section 7; the set the dynamics
stage and the isolator's verification use) is scaled to PGA levels around the 2D fragility medians
the dynamics stage found (``factors`` x each median; :func:`levels_around`), and every run is made in
both models (:func:`statue2model.crosscheck.classification.classify_ensemble`):

* fixed base: the 2D rocking model the run uses against the statue scene (contacts on a rigid floor),
  levels around the medians of uplift and overturning;
* on the isolator (when the run has a design): the coupled 2D model against the exact-kinematics
  scene (crosscheck.isolated_runs), levels around the medians of the isolated limit states (uplift
  on the isolator, overturning on the isolator, capacity exceeded).

Where a base has no median in the studied range (nothing fails), its levels go around the fragility
study's top level instead. A time budget (``budget_s``) is planned before anything runs: one timed
3D run per base gives the cost, and the levels shrink to QUICK_FACTORS or the classification is
skipped (saying so) when the estimate does not fit.

Each limit state (uplift, overturning, capacity) is scored as accuracy, precision and recall with
95 % intervals and the 2D and 3D fragility medians are set side by side; the rule can fail
(classification.agreement).

Example
-------
>>> from statue2model.crosscheck.set_classification import levels_around
>>> [round(x, 2) for x in levels_around([2.0, None, float("nan")], (0.5, 1.0))]
[1.0, 2.0]
>>> levels_around([None], (0.5, 1.0)) is None
True
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

from ..errors import InputError
from ..quantities import G
from .classification import FACTORS, Classification, classify_ensemble, default_levels, outcome_3d
from .isolated_runs import Coupled2D, isolator_2d, outcome_3d_isolated

QUICK_FACTORS = (0.5, 1.0, 2.0)
"""The PGA factors of a quick run (3 instead of 5 per median)."""


def levels_around(medians, factors=FACTORS) -> list[float] | None:
    """classification.default_levels of ``medians`` (m/s^2), or None if no median is finite."""
    try:
        return default_levels(*medians, factors=factors)
    except InputError:
        return None


@dataclass(frozen=True, eq=False)
class SetClassification:
    """What :func:`classify_design_set` returns: the fixed-base :class:`Classification`, the isolated
    one (None without an isolator), per base how its levels were chosen (``levels_from``) and the
    time budget's plan (``budget``: budget_s, the estimate per factor set, the factors used). Both
    classifications are None, and ``skipped`` says why, when even the quick levels would not fit the
    budget."""

    fixed: Classification | None
    isolated: Classification | None
    levels_from: dict
    budget: dict = field(default_factory=dict)
    skipped: str | None = None

    @property
    def met(self) -> bool:
        return (self.skipped is None and self.fixed is not None and self.fixed.met
                and (self.isolated is None or self.isolated.met))

    def to_dict(self) -> dict:
        return {"schema": "statue2model.crosscheck.set_classification/1", "met": self.met, "skipped": self.skipped,
                "levels_from": self.levels_from, "budget": self.budget,
                "fixed": None if self.fixed is None else self.fixed.to_dict(),
                "isolated": None if self.isolated is None else self.isolated.to_dict()}


def _levels(medians, fallback, factors, what: str, fallback_what: str):
    lv = levels_around(medians, factors)
    if lv is not None:
        return lv, what
    return levels_around([fallback], factors), fallback_what


def _probe(run_3d, scene, records, level: float, settings, contact, free_time: float) -> float:
    """Wall seconds per simulated second of one 3D run: the longest record at ``level``, in this process."""
    recs = list(getattr(records, "records", records))
    rec = max(recs, key=lambda r: r.end)
    t0 = time.perf_counter()
    out = run_3d((scene, rec.scaled_to_pga(level), settings, contact, free_time))
    wall = time.perf_counter() - t0
    return wall / max(out.get("sim_time_s") or (rec.end + free_time), 1e-3)


def classify_design_set(scene, model, records, medians_fixed, *, iso_scene=None, medians_isolated=(),
                        settings=None, contact=None, executor=None, factors=FACTORS, free_time: float = 2.0,
                        top_level: float | None = None, budget_s: float | None = None,
                        progress=None) -> SetClassification:
    """Both classifications of the module docstring. ``scene``: the StatueScene; ``model``: the 2D
    RockingModel the run uses; ``records``: the design RecordSet (or GroundMotions);
    ``medians_fixed``: (uplift, overturning) 2D fragility medians, m/s^2 (None where not found);
    ``iso_scene``: a PendulumIsolator with ``statue=scene`` (None: fixed base only);
    ``medians_isolated``: the isolated limit states' 2D medians, m/s^2; ``settings``: the 3D engine
    settings (statue scenes'); ``executor``: the run's executor (None: 2 local processes);
    ``top_level``: the highest PGA the fragility study ran (m/s^2): where a base has no finite median
    (nothing fails in the studied range) its levels are put around it instead.

    ``budget_s``: the wall time the 3D runs may take (None: no limit). One 3D run per base (the longest
    record at the highest level, run here) measures the cost per simulated second; the estimate (every
    run to its end: runs that overturn or pass the capacity stop earlier) over the executor's workers
    must fit the budget with ``factors``, else with QUICK_FACTORS; else nothing is run and ``skipped``
    says why."""
    say = progress or (lambda msg: None)
    recs = list(getattr(records, "records", records))
    workers = max(1, int(getattr(executor, "workers", 2) or 1))
    sim_per_level = sum(r.end + free_time for r in recs)
    bases = {"fixed": (scene, medians_fixed, "the fixed base's 2D medians of uplift and overturning",
                       f"no fixed-base 2D median in the studied range: around its top level "
                       f"{(top_level or 0.0) / G:.3f} g", None, None)}
    if iso_scene is not None:
        bases["isolated"] = (iso_scene, medians_isolated, "the isolated limit states' 2D medians",
                             f"no isolated limit state has a 2D median in the studied range: around the top level "
                             f"{(top_level or 0.0) / G:.3f} g", Coupled2D(isolator_2d(iso_scene)), outcome_3d_isolated)
    plan = {}
    for fs in ((tuple(factors), QUICK_FACTORS) if budget_s is not None else (tuple(factors),)):
        plan[fs] = {}
        for name, (sc, meds, what, fb_what, _, _) in bases.items():
            lv, how = _levels(meds, top_level, fs, what, fb_what)
            if lv is None:
                raise InputError(f"no finite 2D fragility median ({name}) and no top level of the fragility study "
                                 "to put the classification's levels around")
            plan[fs][name] = (lv, how)
    budget = {"budget_s": budget_s, "workers": workers}
    chosen = tuple(factors)
    if budget_s is not None:
        cost = {}
        for name, (sc, *_r, run3) in bases.items():
            lv = plan[chosen][name][0]
            say(f"timing one 3D run ({name})")
            cost[name] = _probe(run3 or outcome_3d, sc, recs, max(lv), settings, contact, free_time)
        est = {fs: sum(cost[n] * sim_per_level * len(plan[fs][n][0]) for n in bases) / workers for fs in plan}
        budget |= {"wall_per_simulated_s": cost, "estimate_s": {",".join(f"{f:g}" for f in fs): v
                                                                 for fs, v in est.items()}}
        fits = [fs for fs in plan if est[fs] <= budget_s]
        if not fits:
            why = (f"the 3D runs would take about {min(est.values()):.0f} s on {workers} workers even at the quick "
                   f"levels ({', '.join(f'{f:g}' for f in QUICK_FACTORS)} x the medians), over the budget of "
                   f"{budget_s:g} s ([crosscheck] ensemble_budget)")
            return SetClassification(None, None, {}, budget | {"factors": None}, skipped=why)
        chosen = fits[0]
    budget["factors"] = list(chosen)
    frm, out = {}, {}
    for name, (sc, meds, *_r, run2, run3) in bases.items():
        lv, how = plan[chosen][name]
        frm[name] = {"medians_g": [None if m is None else m / G for m in meds], "factors": list(chosen), "what": how}
        say("fixed base" if name == "fixed" else "on the isolator")
        kw = {} if run2 is None else {"run_2d": run2, "run_3d": run3}
        out[name] = classify_ensemble(sc, model, records, lv, settings, executor, contact=contact,
                                      free_time=free_time, base=name, factors=chosen, **kw)
    return SetClassification(out["fixed"], out.get("isolated"), frm, budget)
