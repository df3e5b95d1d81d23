"""The 2D/3D classification over the run's design record set, on the fixed base and on the isolator.

The run's design record set (>= 7 code-compliant records, MODEL.md section 7; the set the dynamics
stage and the isolator's verification use) is scaled to PGA levels around the 2D fragility medians
the dynamics stage found (``factors`` x each median; :func:`levels_around`), and every run is made in
both models (:func:`statue2model.crosscheck.classification.classify_ensemble`):

* fixed base: the 2D rocking model the run uses against the statue scene (contacts on a rigid floor),
  levels around the medians of uplift and overturning;
* on the isolator (when the run has a design): the coupled 2D model against the exact-kinematics
  scene (crosscheck.isolated_runs), levels around the medians of the isolated limit states (uplift
  on the isolator, overturning on the isolator, capacity exceeded); where none has a median in the
  studied range, the fixed base's levels (the isolator is then shown to stay safe where the fixed
  base does not).

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

from dataclasses import dataclass

from ..errors import InputError
from ..quantities import G
from .classification import FACTORS, Classification, classify_ensemble, default_levels
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
    one (None without an isolator) and, per base, how its levels were chosen (``levels_from``)."""

    fixed: Classification
    isolated: Classification | None
    levels_from: dict

    @property
    def met(self) -> bool:
        return self.fixed.met and (self.isolated is None or self.isolated.met)

    def to_dict(self) -> dict:
        return {"schema": "statue2model.crosscheck.set_classification/1", "met": self.met,
                "levels_from": self.levels_from, "fixed": self.fixed.to_dict(),
                "isolated": None if self.isolated is None else self.isolated.to_dict()}


def classify_design_set(scene, model, records, medians_fixed, *, iso_scene=None, medians_isolated=(),
                        settings=None, contact=None, executor=None, factors=FACTORS, free_time: float = 2.0,
                        top_level: float | None = None, progress=None) -> SetClassification:
    """Both classifications of the module docstring. ``scene``: the StatueScene; ``model``: the 2D
    RockingModel the run uses; ``records``: the design RecordSet (or GroundMotions);
    ``medians_fixed``: (uplift, overturning) 2D fragility medians, m/s^2 (None where not found);
    ``iso_scene``: a PendulumIsolator with ``statue=scene`` (None: fixed base only);
    ``medians_isolated``: the isolated limit states' 2D medians, m/s^2; ``settings``: the 3D engine
    settings (statue scenes'); ``executor``: the run's executor (None: 2 local processes);
    ``top_level``: the highest PGA the fragility study ran (m/s^2): where a base has no finite median
    (nothing fails in the studied range) its levels are put around it instead."""
    say = progress or (lambda msg: None)
    lv_fixed = levels_around(medians_fixed, factors)
    what = "the fixed base's 2D medians of uplift and overturning"
    if lv_fixed is None:
        lv_fixed = levels_around([top_level], factors)
        what = (f"no fixed-base 2D median in the studied range: around its top level "
                f"{(top_level or 0.0) / G:.3f} g")
    if lv_fixed is None:
        raise InputError("no finite 2D fragility median on the fixed base and no top level of the fragility study "
                         "to put the classification's levels around")
    frm = {"fixed": {"medians_g": [None if m is None else m / G for m in medians_fixed],
                     "factors": list(factors), "what": what}}
    say("fixed base")
    fixed = classify_ensemble(scene, model, records, lv_fixed, settings, executor, contact=contact,
                              free_time=free_time, base="fixed", factors=factors)
    iso = None
    if iso_scene is not None:
        lv = levels_around(medians_isolated, factors)
        frm["isolated"] = {"medians_g": [None if m is None else m / G for m in medians_isolated],
                           "factors": list(factors),
                           "what": "the isolated limit states' 2D medians" if lv is not None else
                                   "no isolated limit state has a 2D median in the studied range: the fixed "
                                   "base's levels"}
        say("on the isolator")
        iso = classify_ensemble(iso_scene, model, records, lv if lv is not None else lv_fixed, settings, executor,
                                contact=contact, free_time=free_time, base="isolated", factors=factors,
                                run_2d=Coupled2D(isolator_2d(iso_scene)), run_3d=outcome_3d_isolated)
    return SetClassification(fixed, iso, frm)
