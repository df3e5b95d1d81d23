"""The 2D/3D classification over the run's design record set, on the fixed base and on the isolator.

The run's design record set (>= 7 code-compliant records, MODEL.md section 7; the set the dynamics
stage and the isolator's verification use) is scaled to PGA levels around ANCHORS taken from the
dynamics stage's 2D fragility curves (``factors`` x each anchor; :func:`anchors`, :func:`levels_around`),
and every run is made in both models (:func:`statue2model.crosscheck.classification.classify_ensemble`):

* fixed base: the 2D rocking model the run uses against the statue scene (contacts on a rigid floor),
  levels around the curves of uplift and overturning;
* on the isolator (when the run has a design and the dynamics stage studied it): the coupled 2D model
  against the exact-kinematics scene (crosscheck.isolated_runs), levels around the isolated curves
  (uplift on the isolator, overturning on the isolator, capacity exceeded).

A curve's anchor is its fitted median; where every run of the study failed (the median lies below
the studied range) the LOWEST studied level; where none did (above it) the HIGHEST. So a body that
overturns at every studied level is classified at and below where it starts failing, never only in
a range where every run fails in both models (which would 'agree' without testing anything).

A time budget (``budget_s``) is planned before anything runs: one timed 3D run per base (the longest
record at the middle level) gives the cost, and the levels shrink to QUICK_FACTORS or the
classification is skipped (saying so) when the estimate does not fit.

Each limit state (full contact, overturning, capacity) is scored as accuracy, precision and recall with
95 % intervals and the 2D and 3D fragility medians are set side by side; the rule can fail
(classification.agreement).

Example
-------
>>> from statue2model.crosscheck.set_classification import anchors, levels_around
>>> curves = {"full_contact_fixed": {"median": 2.8, "status": "exact"},
...           "overturning_fixed": {"median": None, "status": "all failed"}}
>>> [(round(a, 2), w) for a, w in anchors(curves, ("full_contact_fixed", "overturning_fixed"), [1.0, 3.0, 8.0])]
[(2.8, 'full_contact_fixed: its median'), (1.0, 'overturning_fixed: every studied level fails, the lowest')]
>>> [round(x, 2) for x in levels_around([2.0, None, float("nan")], (0.5, 1.0))]
[1.0, 2.0]
>>> levels_around([None], (0.5, 1.0)) is None
True
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from ..errors import InputError
from ..quantities import G
from .classification import FACTORS, Classification, classify_ensemble, default_levels, outcome_3d
from .ensemble import json_safe
from .isolated_runs import Coupled2D, isolator_2d, outcome_3d_isolated

QUICK_FACTORS = (0.5, 1.0, 2.0)
"""The PGA factors of a quick run (3 instead of 5 per median)."""


def anchors(curves: dict, names, levels) -> list[tuple[float, str]]:
    """(PGA in m/s^2, what it is) of each curve of ``names`` in ``curves`` (fragility.json's, by name):
    its median where fitted; where every run failed ('all failed') the lowest of ``levels`` (the
    study's PGA levels, m/s^2); where none failed ('no failures') the highest. Curves missing or not
    fitted for another reason give no anchor."""
    lv = sorted(float(x) for x in (levels or ()) if isinstance(x, (int, float)) and math.isfinite(x) and x > 0)
    out = []
    for n in names:
        c = curves.get(n)
        if not isinstance(c, dict):
            continue
        m = c.get("median")
        if isinstance(m, (int, float)) and math.isfinite(m) and m > 0:
            out.append((float(m), f"{n}: its median"))
        elif c.get("status") == "all failed" and lv:
            out.append((lv[0], f"{n}: every studied level fails, the lowest"))
        elif c.get("status") == "no failures" and lv:
            out.append((lv[-1], f"{n}: no studied level fails, the highest"))
    return out


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
        """JSON-ready (non-finite numbers as None)."""
        return json_safe({"schema": "statue2model.crosscheck.set_classification/1", "met": self.met,
                          "skipped": self.skipped, "levels_from": self.levels_from, "budget": self.budget,
                          "fixed": None if self.fixed is None else self.fixed.to_dict(),
                          "isolated": None if self.isolated is None else self.isolated.to_dict()})


def _probe(run_3d, scene, records, level: float, settings, contact, free_time: float) -> float:
    """Wall seconds per simulated second of one 3D run: the longest record at ``level``, in this process."""
    recs = list(getattr(records, "records", records))
    if not recs:
        raise InputError("the classification needs at least one record")
    rec = max(recs, key=lambda r: r.end)
    t0 = time.perf_counter()
    out = run_3d((scene, rec.scaled_to_pga(level), settings, contact, free_time))
    wall = time.perf_counter() - t0
    return wall / max(out.get("sim_time_s") or (rec.end + free_time), 1e-3)


def classify_design_set(scene, model, records, anchors_fixed, *, iso_scene=None, anchors_isolated=(),
                        settings=None, contact=None, executor=None, factors=FACTORS, free_time: float = 2.0,
                        budget_s: float | None = None, progress=None) -> SetClassification:
    """Both classifications of the module docstring. ``scene``: the StatueScene; ``model``: the 2D
    RockingModel the run uses; ``records``: the design RecordSet (or GroundMotions);
    ``anchors_fixed``, ``anchors_isolated``: [(PGA m/s^2, what)] to put each base's levels around
    (:func:`anchors`); ``iso_scene``: a PendulumIsolator with ``statue=scene`` (None: fixed base only);
    ``settings``: the 3D engine settings (statue scenes'); ``executor``: the run's executor (None: 2
    local processes).

    ``budget_s``: the wall time the 3D runs may take (None: no limit). One 3D run per base (the longest
    record at the middle level, run here) measures the cost per simulated second; the estimate (every
    run to its end: runs that overturn or pass the capacity stop earlier; the 2D runs, seconds, are not
    in it) over the executor's workers must fit the budget with ``factors``, else with QUICK_FACTORS;
    else nothing is run and ``skipped`` says why."""
    say = progress or (lambda msg: None)
    recs = list(getattr(records, "records", records))
    workers = max(1, int(getattr(executor, "workers", 2) or 1))
    sim_per_level = sum(r.end + free_time for r in recs)
    bases = {"fixed": (scene, list(anchors_fixed), None, None)}
    if iso_scene is not None:
        bases["isolated"] = (iso_scene, list(anchors_isolated), Coupled2D(isolator_2d(iso_scene)),
                             outcome_3d_isolated)
    plan = {}
    for fs in ((tuple(factors), QUICK_FACTORS) if budget_s is not None else (tuple(factors),)):
        plan[fs] = {}
        for name, (sc, anc, _, _) in bases.items():
            lv = levels_around([a for a, _ in anc], fs)
            if lv is None:
                raise InputError(f"no 2D fragility curve of the {name} base to put the classification's levels "
                                 "around (run the dynamics stage's fragility study)")
            plan[fs][name] = lv
    budget = {"budget_s": budget_s, "workers": workers}
    chosen = tuple(factors)
    if budget_s is not None:
        cost = {}
        for name, (sc, _, _, run3) in bases.items():
            lv = plan[chosen][name]
            say(f"timing one 3D run ({name})")
            cost[name] = _probe(run3 or outcome_3d, sc, recs, lv[len(lv) // 2], settings, contact, free_time)
        est = {fs: sum(cost[n] * sim_per_level * len(plan[fs][n]) for n in bases) / workers for fs in plan}
        budget |= {"wall_per_simulated_s": cost, "estimate_s": {",".join(f"{f:g}" for f in fs): v
                                                                 for fs, v in est.items()}}
        fits = [fs for fs in plan if est[fs] <= budget_s]
        if not fits:
            why = (f"the 3D runs would take about {min(est.values()):.0f} s on {workers} workers even at the quick "
                   f"levels ({', '.join(f'{f:g}' for f in QUICK_FACTORS)} x the anchors), over the budget of "
                   f"{budget_s:g} s ([crosscheck] ensemble_budget)")
            return SetClassification(None, None, {}, budget | {"factors": None}, skipped=why)
        chosen = fits[0]
    budget["factors"] = list(chosen)
    frm, out = {}, {}
    for name, (sc, anc, run2, run3) in bases.items():
        frm[name] = {"anchors_g": [a / G for a, _ in anc], "what": [w for _, w in anc], "factors": list(chosen)}
        say("fixed base" if name == "fixed" else "on the isolator")
        kw = {} if run2 is None else {"run_2d": run2, "run_3d": run3}
        out[name] = classify_ensemble(sc, model, records, plan[chosen][name], settings, executor, contact=contact,
                                      free_time=free_time, base=name, factors=chosen, **kw)
    return SetClassification(out["fixed"], out.get("isolated"), frm, budget)
